//! The machine's speed, measured in about two seconds: what the benchmark report
//! states beside its times, before and after its runs, so that reports from
//! different days or machines can be compared, and a slower report can be told
//! apart from a slower machine.
//!
//! Three figures, one for each kind of work a run does:
//!
//! - **dense product** (Gflop/s): `C = A B` with n = 1024 by faer on all threads,
//!   `2 n³` flops — the kernel of the supernodal factorization;
//! - **memory copy** (GB/s): a 256 MiB array copied into another already in memory,
//!   bytes read plus bytes written — what the triangular solves, the low-rank
//!   columns and the output are bound by;
//! - **fresh memory** (GB/s): a new 256 MiB array written once — the page faults
//!   and the kernel's zeroing of new pages, which every new factor pays on first
//!   touch (on a virtual machine the part of a run that varies most from day to
//!   day).
//!
//! Each figure is the best of a few repetitions (the least disturbed), and each
//! measurement checks its own result, so a kernel the compiler could skip is not
//! timed as a fast one. A figure whose memory cannot be allocated is `None`.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use std::time::Instant;

/// Size of the dense product: n × n times n × n.
const DENSE_N: usize = 1024;

/// Values (f64) of the arrays of the two memory figures: 256 MiB.
const MEMORY_VALUES: usize = 32 << 20;

/// Repetitions of each figure (the best is kept).
const REPEATS: usize = 5;

/// The machine's speed (see the [module](self) documentation), as stored in
/// `benchmarks.json`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MachineSpeed {
    /// Dense product, Gflop/s.
    pub dense_gflops: Option<f64>,
    /// Memory copy (read + write), GB/s.
    pub copy_gb_per_s: Option<f64>,
    /// Fresh memory written once, GB/s.
    pub fresh_gb_per_s: Option<f64>,
}

impl MachineSpeed {
    /// Measures the three figures (about two seconds on two cores).
    pub fn measure() -> MachineSpeed {
        MachineSpeed {
            dense_gflops: dense_product_rate(DENSE_N, REPEATS),
            copy_gb_per_s: copy_rate(MEMORY_VALUES, REPEATS),
            fresh_gb_per_s: fresh_rate(MEMORY_VALUES, REPEATS),
        }
    }

    /// The figures in one line, e.g. `dense product 24.1 Gflop/s, memory copy
    /// 9.8 GB/s, fresh memory 3.1 GB/s` (`–` for a figure not measured).
    pub fn describe(&self) -> String {
        format!(
            "dense product {} Gflop/s, memory copy {} GB/s, fresh memory {} GB/s",
            figure(self.dense_gflops),
            figure(self.copy_gb_per_s),
            figure(self.fresh_gb_per_s)
        )
    }
}

/// A figure with one decimal, or `–` when it was not measured.
pub fn figure(v: Option<f64>) -> String {
    v.map_or_else(|| "–".to_string(), |v| format!("{v:.1}"))
}

/// Gflop/s of the best of `repeats` dense products of two n × n matrices of
/// ones (every entry of the product is n: checked at two corners), on all of
/// rayon's threads as the factorization runs it. `None` if a product is wrong.
pub fn dense_product_rate(n: usize, repeats: usize) -> Option<f64> {
    let a = Mat::<f64>::from_fn(n, n, |_, _| 1.0);
    let b = Mat::<f64>::from_fn(n, n, |_, _| 1.0);
    let mut c = Mat::<f64>::zeros(n, n);
    let par = Par::rayon(0);
    // A first product, untimed: the threads and the packing buffers warm up.
    matmul(c.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), 1.0, par);
    let best = best_seconds(repeats, || {
        matmul(c.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), 1.0, par);
        let nf = n as f64;
        (c[(0, 0)] == nf && c[(n - 1, n - 1)] == nf).then_some(())
    })?;
    Some(2.0 * (n as f64).powi(3) / best / 1e9)
}

/// GB/s (bytes read plus bytes written) of the best of `repeats` copies of
/// `values` f64 into an array already in memory; `None` if the arrays cannot be
/// allocated or a copy is wrong.
pub fn copy_rate(values: usize, repeats: usize) -> Option<f64> {
    let mut src = allocate(values)?;
    src.iter_mut().enumerate().for_each(|(i, v)| *v = i as f64);
    let mut dst = allocate(values)?;
    dst.fill(-1.0);
    let mut pass = 0.0;
    let best = best_seconds(repeats, || {
        pass += 1.0;
        src[0] = pass;
        dst.copy_from_slice(&src);
        (dst[0] == pass && dst[values - 1] == (values - 1) as f64).then_some(())
    })?;
    Some(2.0 * 8.0 * values as f64 / best / 1e9)
}

/// GB/s of the best of `repeats` first writes of a newly allocated array of
/// `values` f64 (its pages faulted in and zeroed by the kernel on the way: an
/// allocation of this size is a fresh mapping, untouched until written); `None`
/// if it cannot be allocated.
pub fn fresh_rate(values: usize, repeats: usize) -> Option<f64> {
    let best = best_seconds(repeats, || {
        let mut fresh: Vec<f64> = Vec::new();
        fresh.try_reserve_exact(values).ok()?;
        fresh.resize(values, 1.0);
        (fresh[0] == 1.0 && fresh[values - 1] == 1.0).then_some(())
    })?;
    Some(8.0 * values as f64 / best / 1e9)
}

/// `values` zeros, written (in memory), or `None` if they cannot be allocated.
fn allocate(values: usize) -> Option<Vec<f64>> {
    let mut v: Vec<f64> = Vec::new();
    v.try_reserve_exact(values).ok()?;
    v.resize(values, 0.0);
    Some(v)
}

/// The shortest of `repeats` timings of `f` (which returns `None` when its
/// result is wrong: then `None`).
fn best_seconds(repeats: usize, mut f: impl FnMut() -> Option<()>) -> Option<f64> {
    let mut best = f64::INFINITY;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        f()?;
        best = best.min(t.elapsed().as_secs_f64());
    }
    (best > 0.0 && best.is_finite()).then_some(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each figure is measured on a small size, checks its own result and is a
    /// positive rate; the JSON form reads back to the same figures.
    #[test]
    fn figures_are_measured_and_read_back() {
        let speed = MachineSpeed {
            dense_gflops: dense_product_rate(64, 2),
            copy_gb_per_s: copy_rate(1 << 16, 2),
            fresh_gb_per_s: fresh_rate(1 << 16, 2),
        };
        for figure in [
            speed.dense_gflops,
            speed.copy_gb_per_s,
            speed.fresh_gb_per_s,
        ] {
            let v = figure.expect("measured");
            assert!(v.is_finite() && v > 0.0, "{v}");
        }
        let json = serde_json::to_string(&speed).unwrap();
        assert_eq!(serde_json::from_str::<MachineSpeed>(&json).unwrap(), speed);
    }

    /// A measurement whose result is wrong gives no figure.
    #[test]
    fn a_wrong_result_gives_no_figure() {
        assert_eq!(best_seconds(3, || None), None);
        let mut calls = 0;
        assert_eq!(
            best_seconds(3, || {
                calls += 1;
                (calls < 2).then_some(())
            }),
            None
        );
    }
}
