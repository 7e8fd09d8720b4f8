//! Returning the heap's free memory to the system.
//!
//! glibc's allocator serves requests below its mmap threshold from its heap, and
//! the threshold rises to the largest block freed (up to 32 MiB): once the
//! setup's large temporaries are freed, the vectors of the unknowns' size at 1 M
//! (8 MiB) and 4 M (30.5 MiB) unknowns live in the heap too. Freed, their pages
//! stay resident as free chunks between live ones, and a solve's peak counts them
//! beside the factor: at 4 M unknowns 364 MiB of the heap was free at the start
//! of the accepted pattern's complete solve (docs/method.md §3). `malloc_trim`
//! gives the pages of free chunks back (`MADV_DONTNEED`); a later allocation
//! there takes fresh pages, which the solve touches anyway.

/// Gives the heap's free pages back to the system where the allocator can
/// (glibc's `malloc_trim`); elsewhere nothing. Called where a solve has just freed
/// much and is about to allocate less than it freed: after the setup's
/// temporaries, after each low-rank update's new correction columns (their
/// blocks reallocated as they grow, their solves' scratch), and before and after
/// each complete solve while the factor is held (the trials' vectors, then the
/// solve's own temporaries).
pub(crate) fn return_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases memory the allocator holds as free; it
    // touches no live allocation and may be called at any time from any thread.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Gives back the whole memory pages of the entries `from..to` of `values`,
/// whose contents are not needed again (they read as zeros afterwards: `values`
/// is part of an allocation, a `Vec`'s, whose memory is private), and
/// returns the index up to which they were given back: the entries of a page
/// only partly in `from..to` stay, for a later call from the returned index to
/// give back once the rest of that page is done with. The allocation itself
/// stays (it is freed as usual). Linux only (`madvise(MADV_DONTNEED)`); elsewhere
/// nothing is given back and `from` is returned.
pub(crate) fn discard(values: &mut [f64], from: usize, to: usize) -> usize {
    assert!(from <= to && to <= values.len(), "entries out of range");
    #[cfg(target_os = "linux")]
    {
        use std::sync::OnceLock;
        static PAGE: OnceLock<usize> = OnceLock::new();
        // SAFETY: sysconf only reads a system setting.
        let page = *PAGE.get_or_init(|| match unsafe { libc::sysconf(libc::_SC_PAGESIZE) } {
            p if p > 0 => p as usize,
            _ => 4096,
        });
        let base = values.as_mut_ptr() as usize;
        let start = (base + 8 * from).next_multiple_of(page);
        let stop = (base + 8 * to) / page * page;
        if stop > start {
            // SAFETY: `start..stop` lies inside `values`, which is borrowed mutably
            // here, so nothing else reads or writes it. The memory of a Rust
            // allocation is private and anonymous (the heap's, or a mapping of
            // its own), for which MADV_DONTNEED only replaces the pages' contents
            // with zeros: as if the entries were overwritten.
            let given = unsafe {
                libc::madvise(start as *mut libc::c_void, stop - start, libc::MADV_DONTNEED)
            };
            if given == 0 {
                return (stop - base) / 8;
            }
        }
    }
    from
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries whose pages are given back read as zeros, all of them from the
    /// first whole page on up to the returned index; the others keep their
    /// values; a second call from that index goes on to the end.
    #[test]
    fn given_back_pages_read_as_zeros() {
        let n = 1 << 17;
        let mut v: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        let (from, to) = (10, n / 2 + 3);
        let next = discard(&mut v, from, to);
        assert!(next <= to);
        if cfg!(target_os = "linux") {
            // 512 KiB hold whole pages of any size Linux uses for this.
            assert!(next > from, "no page given back");
        }
        let zero = (from..next).find(|&i| v[i] == 0.0).unwrap_or(next);
        for (i, &x) in v.iter().enumerate() {
            if (zero..next).contains(&i) {
                assert_eq!(x, 0.0, "entry {i} of a page given back");
            } else {
                assert_eq!(x, i as f64 + 1.0, "entry {i} not given back changed");
            }
        }
        let last = discard(&mut v, next, n);
        assert!(last >= next && v[next..last].iter().all(|&x| x == 0.0));
    }
}
