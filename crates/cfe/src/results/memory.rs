//! Memory and machine figures of this process, for the summary and the benchmark
//! report. No maintained portable crate gives the peak resident set size, so this
//! one small module reads Linux's `/proc` files (and gives `None` elsewhere); the
//! parsing is separated from the reading and tested.

/// Peak resident set size of this process in bytes (Linux `VmHWM`), if known.
pub fn peak_memory_bytes() -> Option<u64> {
    kib_field(
        &std::fs::read_to_string("/proc/self/status").ok()?,
        "VmHWM:",
    )
}

/// Processor time this process has used so far, user and system, over all its
/// threads (ended ones too), in seconds (`getrusage(RUSAGE_SELF)` on Unix; `None`
/// elsewhere). Against the wall-clock time it tells how much of the run's work
/// could have been spread over more cores.
pub fn cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
        // SAFETY: getrusage writes one `rusage` through a pointer valid for it;
        // the struct is read only after the call reports success.
        let usage = unsafe {
            if libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) != 0 {
                return None;
            }
            usage.assume_init()
        };
        let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Some(seconds(usage.ru_utime) + seconds(usage.ru_stime))
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// Total memory of the machine in bytes (Linux `MemTotal`), if known.
pub fn total_memory_bytes() -> Option<u64> {
    kib_field(&std::fs::read_to_string("/proc/meminfo").ok()?, "MemTotal:")
}

/// Memory available to a new allocation in bytes (Linux `MemAvailable`), if known.
pub fn available_memory_bytes() -> Option<u64> {
    kib_field(
        &std::fs::read_to_string("/proc/meminfo").ok()?,
        "MemAvailable:",
    )
}

/// The processor's model name (Linux `/proc/cpuinfo`), if known.
pub fn cpu_model() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find(|l| l.starts_with("model name"))
        .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
}

/// Estimated peak memory of a run with `unknowns` unknowns, bytes:
/// `64 MiB + unknowns × 100 B × log₂(unknowns)`. The Cholesky factor of a 2D
/// stiffness with a nested-dissection ordering has about `6.2 n log₂ n` nonzeros
/// (123.5 per unknown at 1.0 M), and the peak resident set was about 1.9× the
/// factor in the runs it was fitted to (1.87 GB measured at 1.0 M unknowns,
/// estimate 2.06 GB; 17.6 GiB at 8.2 M, estimate 17.6 GiB). The peak has since
/// fallen to 1.19–1.29× the factor (1.28 GB at 1.0 M, 5.51 GB at 4.0 M, 11.8 GB at
/// 8.2 M, contact law), so the estimate is now about 1.6× the peak: a first,
/// generous check before meshing.
/// In 24 GiB (about 22.5 GiB available) it admits about 10 million unknowns.
pub fn estimated_peak_bytes(unknowns: u64) -> u64 {
    let n = unknowns as f64;
    let bytes = 64.0 * (1u64 << 20) as f64 + n * 100.0 * n.max(2.0).log2();
    if bytes >= u64::MAX as f64 {
        u64::MAX
    } else {
        bytes as u64
    }
}

/// Estimated peak memory of a run once its symbolic factorization is known, bytes:
/// `64 MiB + 8 nnz(L) + 16 nnz(K) + 350 n` for `n` unknowns, `nnz(K)` nonzeros in
/// the stiffness's lower triangle and `nnz(L)` in the Cholesky factor. The factor's
/// values (8 B each) are held with the stiffness's pattern (row indices of 4 B)
/// and, during a factorization, its values (8 B per nonzero; the stiffness is
/// stored in the elimination order, so the factorization reads it as it is and
/// makes no copy, and its values are freed between factorizations): 12 B per
/// stored nonzero, counted as 16 for a margin (until the factorization was ours
/// it also held the row indices widened to 8 B). The `350 n` covers the meshes,
/// DOF map, elimination order, symbolic structures, the update columns, the
/// per-iteration vectors and the allocator's free but still resident memory.
/// Measured on `examples/plate_on_base.toml` (docs/benchmarks.md): with the
/// contact law the estimate is 2.1× the measured peak at K = 8 (61 MB; the
/// 64 MiB constant dominates), 1.37× at K = 16 and 1.17–1.21× from K = 32 to 100
/// (1.20× at K = 35, 1.19 GiB; 1.17× at K = 100, 11.0 GiB); with the rigid law
/// 1.41× at K = 16 and 1.19–1.23× from K = 32 to 100. It counts the stiffness's
/// pattern held beside the factor, which a run with proportional loads frees
/// after its factorization (`ContactSystem::keep_pattern`): generous there, so
/// that a run which keeps it is not underestimated.
///
/// When the factor is kept from one increment to the next
/// (`factor_beside_writers`: friction, gaps, augmented enforcement, load steps,
/// `implex`), the increments' files are written while it is held: the VTU
/// writers in flight each hold an increment's displacements and stress arrays,
/// and the run its pairs' history, so [`BESIDE_WRITERS`] bytes per unknown are
/// added (the Coulomb plate at K = 33: 1.41 GB measured, 0.96× without the
/// term, 1.09× with it).
pub fn estimated_peak_from_factor(
    unknowns: u64,
    matrix_nnz: u64,
    factor_nnz: u64,
    factor_beside_writers: bool,
) -> u64 {
    let per_unknown = 350
        + if factor_beside_writers {
            BESIDE_WRITERS
        } else {
            0
        };
    (64u64 << 20)
        .saturating_add(factor_nnz.saturating_mul(8))
        .saturating_add(matrix_nnz.saturating_mul(16))
        .saturating_add(unknowns.saturating_mul(per_unknown))
}

/// Bytes per unknown added to [`estimated_peak_from_factor`] when the factor is
/// held while increments are written.
pub const BESIDE_WRITERS: u64 = 200;

/// The value in bytes of a `key: N kB` line of a `/proc` status file.
fn kib_field(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimate is above the peak measured at 1.0 M unknowns (1.28 GB) by at
    /// most 70 %, grows faster than linearly, and saturates instead of overflowing.
    #[test]
    fn peak_estimate_brackets_the_measurement() {
        let at_1m = estimated_peak_bytes(1_002_822) as f64;
        assert!(at_1m > 1.275e9 && at_1m < 1.7 * 1.275e9, "{at_1m:e}");
        let at_8m = estimated_peak_bytes(8_000_000) as f64;
        assert!(at_8m > 8.0 * at_1m);
        assert_eq!(estimated_peak_bytes(u64::MAX), u64::MAX);
    }

    /// The estimate from the factor is within 25 % above the peaks measured at
    /// 1.0 M, 4.0 M and 8.2 M unknowns (plate on a base, contact and rigid laws,
    /// K = 35, 70 and 100; docs/benchmarks.md), and never below them.
    #[test]
    fn factor_estimate_brackets_the_measurements() {
        for (n, k, l, peak) in [
            (1_002_822u64, 7_514_441u64, 123_848_812u64, 1.277e9),
            (4_004_842, 30_022_871, 565_139_372, 5.513e9),
            (8_169_202, 61_249_811, 1_230_503_428, 11.758e9),
            (1_002_822u64, 7_514_441u64, 123_848_812u64, 1.265e9),
            (4_004_842, 30_022_871, 565_139_372, 5.428e9),
            (8_169_202, 61_249_811, 1_230_503_428, 11.564e9),
        ] {
            let e = estimated_peak_from_factor(n, k, l, false) as f64;
            assert!(e >= peak && e < 1.25 * peak, "{n}: {e:e} against {peak:e}");
        }
    }

    /// With the factor held while increments are written (the Coulomb law), the
    /// estimate is above the peak measured on the plate at K = 33 (0.9 M
    /// unknowns, all increments written) by at most 10 %; without the writers'
    /// term it would be below it.
    #[test]
    fn factor_estimate_covers_a_frictional_run() {
        let (n, k, l, peak) = (891_662u64, 6_681_125u64, 108_601_916u64, 1.415e9);
        let e = estimated_peak_from_factor(n, k, l, true) as f64;
        assert!(e >= peak && e < 1.10 * peak, "{e:e} against {peak:e}");
        assert!((estimated_peak_from_factor(n, k, l, false) as f64) < peak);
    }

    #[test]
    fn parses_kib_fields() {
        let status = "Name:\tcfe\nVmPeak:\t  200 kB\nVmHWM:\t    1234 kB\nVmRSS:\t 1000 kB\n";
        assert_eq!(kib_field(status, "VmHWM:"), Some(1234 * 1024));
        assert_eq!(kib_field(status, "VmSwap:"), None);
        assert_eq!(kib_field("VmHWM: lots kB", "VmHWM:"), None);
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn reads_this_process() {
        assert!(peak_memory_bytes().is_some_and(|b| b > 0));
        assert!(total_memory_bytes().is_some_and(|b| b > 0));
    }
}
