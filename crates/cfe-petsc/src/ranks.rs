//! Failures under MPI: every rank ends together, with the same message, and
//! none waits in a collective call for a rank that has given up.
//!
//! The ranks run the same replicated contact scheme, so most failures happen
//! on every rank at the same point (a non-converged KSP or an indefinite
//! preconditioner: PETSc reduces the reason over the ranks; a law or
//! equilibrium failure: the same decision on the same data). A failure can
//! still happen on one rank alone: rank 0's output (a folder refused, a
//! write that fails), a stop signal seen by one rank before the others, or an
//! error of one rank's local work (its elements into PETSc's matrix). Such a
//! rank must not simply leave: the others would wait for it in their next
//! collective call.
//!
//! **The agreement** ([`agree`]): at fixed points every rank reaches in the
//! same order — the start of each back-end operation (a solver built, a
//! preparation, a solve), after a rank's local assembly and before the
//! collective assembly that follows it, and once at the end of the run (the
//! caller's) — each rank gives its own outcome (its stop flag, and a failure
//! message or none). One `MPI_Allreduce` (2 ints, max) tells every rank the
//! largest stop flag and the lowest failing rank, whose message is then
//! broadcast (`MPI_Bcast`). The first agreement that is not clean is final:
//! every later one returns it at once, without communicating, so a rank that
//! failed (and agreed once, on its way out) and the ranks that learn of it at
//! their next agreement point all end, with the same message, and can all
//! finalize MPI.
//!
//! **The abort** ([`abort`]): an error returned by a collective PETSc call
//! (assembly, preconditioner set-up, solve, scatter) on one rank may leave the
//! others inside that call, where no agreement reaches them: under `mpirun -n
//! N > 1` the failing rank prints its message and calls `MPI_Abort`, which
//! ends every rank (nonzero exit).
//!
//! On one rank both are local: [`agree`] returns the rank's own outcome.

use crate::{Result, ffi, session};
use std::ffi::{c_int, c_void};
use std::sync::Mutex;

/// What the ranks agreed on: the largest stop flag and the first failure.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Agreement {
    /// The largest stop flag of the ranks (a signal's number; 0: none).
    pub stop: usize,
    /// The failure of the lowest rank that failed, if any.
    pub failure: Option<RankFailure>,
}

impl Agreement {
    /// No stop and no failure.
    pub fn is_clean(&self) -> bool {
        self.stop == 0 && self.failure.is_none()
    }
}

/// A failure one rank reported to the others.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.message_with_rank())]
pub struct RankFailure {
    /// The rank that failed (the lowest, when several did).
    pub rank: usize,
    /// Its message.
    pub message: String,
}

impl RankFailure {
    /// The message, named by its rank when that is not rank 0 (rank 0's is
    /// the run's own message, which it writes to the console).
    fn message_with_rank(&self) -> String {
        if self.rank == 0 {
            self.message.clone()
        } else {
            format!("MPI rank {}: {}", self.rank, self.message)
        }
    }

    /// The message as a `'static` string (for the seam's
    /// [`cfe::solve::backend::LinearFailure::BackEnd`], whose function name is
    /// one): made once a process, as the agreement is final.
    pub fn as_static(&self) -> &'static str {
        static TEXT: Mutex<Option<&'static str>> = Mutex::new(None);
        let mut text = TEXT.lock().unwrap_or_else(|e| e.into_inner());
        text.get_or_insert_with(|| Box::leak(self.to_string().into_boxed_str()))
    }
}

/// The first agreement that was not clean (final).
static FINAL: Mutex<Option<Agreement>> = Mutex::new(None);

/// Agrees with every other rank on `stop` (this rank's stop flag) and `local`
/// (this rank's failure message, if any): see the module. Collective: every
/// rank calls it at the same point, until the ranks have agreed on a stop or a
/// failure (then it is local). Initializes PETSc (and MPI) if not done yet.
pub fn agree(stop: usize, local: Option<&str>) -> Result<Agreement> {
    let _s = session()?;
    Ok(agree_in_session(stop, local))
}

/// [`agree`] for a caller that holds the session's lock.
pub(crate) fn agree_in_session(stop: usize, local: Option<&str>) -> Agreement {
    let mut last = FINAL.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(agreed) = &*last {
        return agreed.clone();
    }
    // SAFETY: globals PETSc sets at initialization (the caller holds the lock).
    let (rank, size, comm) = unsafe {
        (
            ffi::PetscGlobalRank.max(0),
            ffi::PetscGlobalSize.max(1),
            ffi::PETSC_COMM_WORLD,
        )
    };
    let agreed = if size == 1 {
        Agreement {
            stop,
            failure: local.map(|m| RankFailure {
                rank: 0,
                message: m.to_string(),
            }),
        }
    } else {
        // [stop flag, size − rank of a failing rank (0: none)]: the maximum
        // gives the largest flag and the lowest failing rank.
        let mine: [c_int; 2] = [
            c_int::try_from(stop).unwrap_or(c_int::MAX),
            if local.is_some() { size - rank } else { 0 },
        ];
        let mut all: [c_int; 2] = [0, 0];
        // SAFETY: two ints each way; Open MPI's predefined objects by address;
        // MPI's default handler aborts on an MPI error.
        unsafe {
            ffi::MPI_Allreduce(
                mine.as_ptr().cast::<c_void>(),
                all.as_mut_ptr().cast::<c_void>(),
                2,
                &raw const ffi::ompi_mpi_int,
                &raw const ffi::ompi_mpi_op_max,
                comm,
            );
        }
        let failure = (all[1] > 0).then(|| {
            let first = size - all[1];
            let mut bytes = if first == rank {
                local.unwrap_or_default().as_bytes().to_vec()
            } else {
                Vec::new()
            };
            let mut len = c_int::try_from(bytes.len()).unwrap_or(c_int::MAX);
            bytes.truncate(len as usize);
            // SAFETY: one int, then `len` bytes, from the failing rank.
            unsafe {
                ffi::MPI_Bcast(
                    (&raw mut len).cast::<c_void>(),
                    1,
                    &raw const ffi::ompi_mpi_int,
                    first,
                    comm,
                );
                bytes.resize(len.max(0) as usize, 0);
                ffi::MPI_Bcast(
                    bytes.as_mut_ptr().cast::<c_void>(),
                    len,
                    &raw const ffi::ompi_mpi_char,
                    first,
                    comm,
                );
            }
            RankFailure {
                rank: first as usize,
                message: String::from_utf8_lossy(&bytes).into_owned(),
            }
        });
        Agreement {
            stop: all[0].max(0) as usize,
            failure,
        }
    };
    if !agreed.is_clean() {
        *last = Some(agreed.clone());
    }
    agreed
}

/// The final agreement, once the ranks agreed on a stop or a failure.
pub fn agreed() -> Option<Agreement> {
    FINAL.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Prints `message` naming `rank` and ends every rank (`MPI_Abort`, exit code
/// 1): for a failure no agreement can reach (see the module).
pub fn abort(rank: usize, message: &str) -> ! {
    eprintln!(
        "error: MPI rank {rank}: {message}; a failure inside a collective call: ending every rank (MPI_Abort)"
    );
    // SAFETY: PETSc's world communicator; MPI_Abort does not return.
    unsafe { ffi::MPI_Abort(ffi::PETSC_COMM_WORLD, 1) };
    std::process::exit(1)
}
