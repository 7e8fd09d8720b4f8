//! The dense kernels of a supernode that read the stop flag within their work:
//! the Cholesky of a large diagonal block a panel at a time, and the triangular
//! solve of a large panel split in pieces — each bit for bit faer's own kernel
//! (the unit tests hold them to it), so a stop can end a factorization inside
//! one large separator without changing its values.

use crate::solve::halt::{Halt, check};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltError, LltRegularization, cholesky_in_place,
};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, MatMut, MatRef, Par};
use std::sync::atomic::AtomicUsize;

/// Diagonal blocks of at least this many columns are factorized a panel at a
/// time here ([`diagonal_cholesky`]), the stop flag read between panels (in the
/// unit tests smaller, so their blocks take this path too).
const CHECKED_CHOLESKY_COLS: usize = if cfg!(test) { 200 } else { 1024 };

/// The panel width of faer's dense `L Lᵀ` (its `LltParams`' block size).
const FAER_LLT_BLOCK: usize = 128;

/// Triangular solves of at least this many multiply–adds (`n² k` for `n`
/// rows and `k` right-hand sides) are split here ([`lower_solve`]), the stop
/// flag read between the pieces (about 0.1 s of work on one core; in the unit
/// tests a few thousand, so their solves are split too).
const CHECKED_SOLVE_FLOPS: f64 = if cfg!(test) { 4.0e3 } else { 2.7e8 };

/// `a ← L` with `a = L Lᵀ` (lower triangle of the `n × n` block `a`), bit for bit
/// faer's `cholesky_in_place` (no regularization), reading `stop` before every
/// panel of a large block: faer 0.24 factorizes a block of more than 64 columns
/// right-looking in panels of `min(n.next_power_of_two() / 2, 128)` columns
/// (the panel's Cholesky, the solve below it, the lower triangle of the trailing
/// block updated), the steps done here with the same kernels and arguments
/// (the unit test `panel_cholesky_is_faers` holds this to faer's own). A
/// non-positive pivot is [`Halt::Pivot`] at its column of the block.
pub(super) fn diagonal_cholesky(
    mut a: MatMut<'_, f64>,
    par: Par,
    stack: &mut MemBuffer,
    stop: Option<&AtomicUsize>,
) -> Result<(), Halt> {
    let n = a.nrows();
    let chol = |a: MatMut<'_, f64>, stack: &mut MemBuffer| {
        cholesky_in_place(
            a,
            LltRegularization::default(),
            par,
            MemStack::new(stack),
            Default::default(),
        )
        .map(|_| ())
        .map_err(|LltError::NonPositivePivot { index }| Halt::Pivot(index))
    };
    if n < CHECKED_CHOLESKY_COLS || stop.is_none() {
        return chol(a, stack);
    }
    let block = (n.next_power_of_two() / 2).min(FAER_LLT_BLOCK);
    let mut j = 0;
    while j < n {
        check(stop)?;
        let b = block.min(n - j);
        let (mut a00, _, mut a10, a11) = a.as_mut().get_mut(j.., j..).split_at_mut(b, b);
        chol(a00.as_mut(), stack).map_err(|h| match h {
            Halt::Pivot(index) => Halt::Pivot(j + index),
            stopped => stopped,
        })?;
        solve_lower_triangular_in_place(a00.as_ref(), a10.as_mut().transpose_mut(), par);
        triangular::matmul(
            a11,
            BlockStructure::TriangularLower,
            Accum::Add,
            a10.as_ref(),
            BlockStructure::Rectangular,
            a10.as_ref().adjoint(),
            BlockStructure::Rectangular,
            -1.0,
            par,
        );
        j += b;
    }
    Ok(())
}

/// `x ← L⁻¹ x` (`l` lower triangular, `x` its right-hand sides), bit for bit
/// faer's `solve_lower_triangular_in_place`, reading `stop` between pieces of
/// at most about [`CHECKED_SOLVE_FLOPS`]: faer 0.24 splits a triangle of more
/// than 128 rows into a head of `n − ⌈n/2⌉₁₆` rows (for `n ≥ 32`: `n/2` rounded
/// up to a multiple of 16) and the rest, solves the head, subtracts its product
/// from the rest's right-hand sides and solves the rest; the large levels of that
/// recursion are done here with the same kernels and arguments (the unit test
/// `split_solve_is_faers` holds this to faer's own).
pub(super) fn lower_solve(
    l: MatRef<'_, f64>,
    x: MatMut<'_, f64>,
    par: Par,
    stop: Option<&AtomicUsize>,
) -> Result<(), Halt> {
    let n = l.nrows();
    let work = (n as f64) * (n as f64) * (x.ncols() as f64);
    if n <= 128 || work < CHECKED_SOLVE_FLOPS || stop.is_none() {
        check(stop)?;
        solve_lower_triangular_in_place(l, x, par);
        return Ok(());
    }
    let head = n - (n / 2).div_ceil(16) * 16;
    let (l00, _, l10, l11) = l.split_at(head, head);
    let (mut top, mut bottom) = x.split_at_row_mut(head);
    lower_solve(l00, top.as_mut(), par, stop)?;
    check(stop)?;
    matmul(bottom.as_mut(), Accum::Add, l10, top.as_ref(), -1.0, par);
    lower_solve(l11, bottom, par, stop)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;
    use std::sync::atomic::Ordering;
    use faer::Mat;

    /// A dense matrix of awkward values (a fixed linear congruential sequence).
    fn awkward(rows: usize, cols: usize, seed: u64) -> Mat<f64> {
        let mut x = seed;
        Mat::from_fn(rows, cols, |_, _| {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    /// `B Bᵀ + n I`: symmetric positive definite, with round-off in every entry.
    fn spd(n: usize) -> Mat<f64> {
        let b = awkward(n, n, 7);
        let mut a = &b * b.transpose();
        for i in 0..n {
            a[(i, i)] += n as f64;
        }
        a
    }

    fn bits(m: &Mat<f64>) -> Vec<u64> {
        let mut v = Vec::with_capacity(m.nrows() * m.ncols());
        for j in 0..m.ncols() {
            for i in j.min(m.nrows())..m.nrows() {
                v.push(m[(i, j)].to_bits());
            }
        }
        v
    }

    /// The diagonal Cholesky done a panel at a time with a stop flag gives faer's
    /// `cholesky_in_place`'s lower triangle bit for bit (sequential and parallel
    /// kernels, sizes with a partial last panel and a power of two), and a set
    /// flag abandons it.
    #[test]
    fn panel_cholesky_is_faers() {
        for n in [CHECKED_CHOLESKY_COLS, 333, 512] {
            for par in [Par::Seq, Par::rayon(2)] {
                let a = spd(n);
                let mut stack = MemBuffer::new(cholesky_in_place_scratch::<f64>(
                    n,
                    par,
                    Default::default(),
                ));
                let mut faers = a.clone();
                cholesky_in_place(
                    faers.as_mut(),
                    LltRegularization::default(),
                    par,
                    MemStack::new(&mut stack),
                    Default::default(),
                )
                .unwrap();
                let stop = AtomicUsize::new(0);
                let mut ours = a.clone();
                diagonal_cholesky(ours.as_mut(), par, &mut stack, Some(&stop)).unwrap();
                assert_eq!(bits(&faers), bits(&ours), "n = {n}");
                stop.store(2, Ordering::Relaxed);
                let mut stopped = a.clone();
                assert_eq!(
                    diagonal_cholesky(stopped.as_mut(), par, &mut stack, Some(&stop)),
                    Err(Halt::Stopped(2))
                );
            }
        }
    }

    /// A non-positive pivot in a later panel is reported at its column of the
    /// block, as faer reports it.
    #[test]
    fn panel_cholesky_reports_faers_pivot() {
        let n = 300;
        let mut a = spd(n);
        // Row and column 250 made a copy of 10's: singular from column 250 on.
        for k in 0..n {
            let v = a[(10, k)];
            a[(250, k)] = v;
            a[(k, 250)] = v;
        }
        a[(250, 250)] = a[(10, 10)];
        let mut stack =
            MemBuffer::new(cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default()));
        let faers = cholesky_in_place(
            a.clone().as_mut(),
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut stack),
            Default::default(),
        );
        let Err(LltError::NonPositivePivot { index }) = faers else {
            panic!("faer factorized a singular matrix");
        };
        let stop = AtomicUsize::new(0);
        assert_eq!(
            diagonal_cholesky(a.as_mut(), Par::Seq, &mut stack, Some(&stop)),
            Err(Halt::Pivot(index))
        );
    }

    /// The triangular solve split with a stop flag gives faer's
    /// `solve_lower_triangular_in_place` bit for bit (a transposed right-hand
    /// side as a supernode's rows below its diagonal block; sequential and
    /// parallel), and a set flag abandons it.
    #[test]
    fn split_solve_is_faers() {
        for (n, k) in [(300, 70), (129, 400), (517, 33)] {
            for par in [Par::Seq, Par::rayon(2)] {
                let mut l = spd(n);
                let mut stack =
                    MemBuffer::new(cholesky_in_place_scratch::<f64>(n, par, Default::default()));
                cholesky_in_place(
                    l.as_mut(),
                    LltRegularization::default(),
                    par,
                    MemStack::new(&mut stack),
                    Default::default(),
                )
                .unwrap();
                let rhs = awkward(k, n, 11);
                let mut faers = rhs.clone();
                solve_lower_triangular_in_place(l.as_ref(), faers.as_mut().transpose_mut(), par);
                let stop = AtomicUsize::new(0);
                let mut ours = rhs.clone();
                lower_solve(l.as_ref(), ours.as_mut().transpose_mut(), par, Some(&stop)).unwrap();
                let all = |m: &Mat<f64>| -> Vec<u64> {
                    (0..m.ncols())
                        .flat_map(|j| (0..m.nrows()).map(move |i| (i, j)))
                        .map(|(i, j)| m[(i, j)].to_bits())
                        .collect()
                };
                assert_eq!(all(&faers), all(&ours), "n = {n}, k = {k}");
                stop.store(15, Ordering::Relaxed);
                assert_eq!(
                    lower_solve(l.as_ref(), rhs.clone().as_mut().transpose_mut(), par, Some(&stop)),
                    Err(Halt::Stopped(15))
                );
            }
        }
    }
}
