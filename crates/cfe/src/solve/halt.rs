//! Why a numeric factorization (or a solve that reads the stop flag) did not
//! finish, and the stop flag's one check: below the factorization and its
//! dense kernels, which both report it.

use std::sync::atomic::{AtomicUsize, Ordering};

/// Why a numeric factorization did not finish.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Halt {
    /// A non-positive pivot at this column (of the elimination order from
    /// [`super::factor::NumericPlan::factorize`], of the equations' order from
    /// [`super::linear::CholeskySolver::factorize`]).
    Pivot(usize),
    /// The caller's stop flag was nonzero (its value, e.g. a signal's number)
    /// before a supernode, between two blocks of its updates or before its
    /// dense kernels: the factor is incomplete.
    Stopped(usize),
}

/// `Err(Halt::Stopped)` once `stop` (if any) is nonzero: one relaxed load.
pub(crate) fn check(stop: Option<&AtomicUsize>) -> Result<(), Halt> {
    match stop.map_or(0, |s| s.load(Ordering::Relaxed)) {
        0 => Ok(()),
        signal => Err(Halt::Stopped(signal)),
    }
}
