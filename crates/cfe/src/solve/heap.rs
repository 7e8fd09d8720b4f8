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
/// temporaries, and before and after each complete solve while the factor is
/// held (the trials' vectors, then the solve's own temporaries).
pub(crate) fn return_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases memory the allocator holds as free; it
    // touches no live allocation and may be called at any time from any thread.
    unsafe {
        libc::malloc_trim(0);
    }
}
