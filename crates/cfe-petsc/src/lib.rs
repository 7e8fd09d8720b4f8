//! PETSc as a linear-solver back end of cfe (issue 42), on one rank or
//! distributed over the ranks of `mpirun`.
//!
//! The library `cfe` solves every pattern of pair states through its seam
//! (`cfe::solve::backend`: [`Analyse`](cfe::solve::backend::Analyse) and
//! [`LinearSolver`]); this crate answers it
//! with the system PETSc, found by pkg-config at build time and called through
//! declarations of its own ([`ffi`]):
//!
//! - `petsc`: conjugate gradients preconditioned by smoothed-aggregation
//!   algebraic multigrid (KSPCG + PCGAMG), with the matrix's block size `D::N`
//!   and the rigid-body modes of the node coordinates as GAMG's near-null space
//!   (`MatNullSpaceCreateRigidBody`, 3 modes in 2D, 6 in 3D);
//! - `petsc-mumps`: MUMPS's sparse Cholesky through PETSc (KSPPREONLY +
//!   PCCHOLESKY).
//!
//! Under `mpirun -n N` every rank builds the same analysis and runs the same
//! contact scheme (the model, its mesh and the pair states are replicated);
//! the matrix, the preconditioner and the solve are distributed (see
//! [`backend`] and [`partition`]). The caller writes output on rank 0 only
//! ([`world`]).
//!
//! `cfe` does not know this crate: [`Petsc`] is handed to an analysis
//! (`Analysis::set_back_end`) by the command line built with `--features
//! petsc`. Any PETSc option passes through ([`Petsc::new`]: a string as on a
//! PETSc program's command line, and an options file), each back end with its
//! own options database.
//!
//! PETSc is one library state per process and is not thread-safe: every call
//! goes through a process-wide lock ([`session`]), which also initializes PETSc
//! on first use. Each PETSc error code is checked and becomes an [`Error`]
//! naming the function.

/// Calls a PETSc function and checks its error code: `call!(KSPSolve(ksp, b, x))`.
/// Every use is a call of a declaration of [`ffi`] (the arguments are its
/// handles and pointers): the macro is the crate's one `unsafe` call site.
macro_rules! call {
    ($f:ident($($arg:expr),* $(,)?)) => {
        // SAFETY: each call site passes live PETSc objects and pointers to
        // memory of the types ffi.rs declares, under the session's lock.
        $crate::check(unsafe { $crate::ffi::$f($($arg),*) }, stringify!($f))
    };
}

pub mod backend;
pub mod ffi;
pub mod partition;
pub mod ranks;

pub use backend::{DEFAULT_TOLERANCE, Kind, PetscSolver};

use cfe::dim::{D2, D3};
use cfe::domain::LinearBackend;
use cfe::solve::backend::{LinearSolver, Problem};
use cfe::solve::contact::ExternalBackEnd;
use cfe::solve::nonlinear::IterativeSolves;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};

/// A failure of this back end.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A PETSc function returned a nonzero error code.
    #[error("{function} failed with PETSc error {code}: {message}")]
    Call {
        /// The function.
        function: &'static str,
        /// Its error code (`PetscErrorCode`).
        code: i32,
        /// PETSc's message for it.
        message: String,
    },
    /// The model has more DOFs or matrix entries than a 32-bit `PetscInt` can
    /// number (the Debian PETSc's indices).
    #[error("{0}")]
    TooLarge(String),
    /// An option string holding a NUL byte, or an options file path that is
    /// not valid UTF-8.
    #[error("{0}")]
    Options(String),
    /// Another MPI rank failed (or this one, on its local work), as the ranks
    /// agreed ([`ranks::agree`]).
    #[error(transparent)]
    Rank(#[from] ranks::RankFailure),
}

impl From<Error> for cfe::Error {
    fn from(e: Error) -> cfe::Error {
        cfe::Error::LinearBackEnd {
            back_end: "petsc".into(),
            message: e.to_string(),
        }
    }
}

/// The result of this crate's calls.
pub type Result<T> = std::result::Result<T, Error>;

/// Whether PETSc is initialized (guarded by the lock).
static PETSC: Mutex<bool> = Mutex::new(false);

/// The message of the last error PETSc raised (its first report, where it was
/// raised), filled by [`record_error`].
static LAST_ERROR: Mutex<String> = Mutex::new(String::new());

/// PETSc's error handler while this crate calls it: keeps the message of an
/// error where it was raised (PETSc then returns the code up the stack, printing
/// nothing) for the [`Error`] made of the code.
unsafe extern "C" fn record_error(
    _comm: ffi::MPI_Comm,
    line: c_int,
    fun: *const c_char,
    _file: *const c_char,
    n: ffi::PetscErrorCode,
    p: c_int,
    mess: *const c_char,
    _ctx: *mut c_void,
) -> ffi::PetscErrorCode {
    // PETSC_ERROR_INITIAL (0): where the error was raised (repeats follow it up).
    if p == 0 {
        let text = |s: *const c_char| {
            if s.is_null() {
                String::new()
            } else {
                // SAFETY: PETSc passes NUL-terminated strings or null.
                unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned()
            }
        };
        let mut last = LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner());
        *last = format!("{} (in {}, line {line})", text(mess).trim(), text(fun));
    }
    n
}

/// `Ok` for error code 0, else an [`Error::Call`] of `function` with the
/// message PETSc raised.
pub fn check(code: ffi::PetscErrorCode, function: &'static str) -> Result<()> {
    if code == 0 {
        return Ok(());
    }
    let mut last = LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner());
    let mut message = std::mem::take(&mut *last);
    if message.is_empty() {
        let mut text: *const c_char = std::ptr::null();
        // SAFETY: PETSc writes a pointer to a static string.
        if unsafe { ffi::PetscErrorMessage(code, &mut text, std::ptr::null_mut()) } == 0
            && !text.is_null()
        {
            // SAFETY: a static NUL-terminated string.
            message = unsafe { CStr::from_ptr(text) }
                .to_string_lossy()
                .into_owned();
        }
    }
    Err(Error::Call {
        function,
        code,
        message,
    })
}

/// Exclusive use of PETSc: the process-wide lock, PETSc initialized (once,
/// without its signal handlers, so a run's SIGINT/SIGTERM stay the caller's),
/// and, while it lives, an options database of a back end made the one PETSc
/// reads (`PetscOptionsPush`).
pub struct Session {
    _guard: MutexGuard<'static, bool>,
    pushed: bool,
}

/// Takes the lock, initializing PETSc on first use.
pub fn session() -> Result<Session> {
    let mut guard = PETSC.lock().unwrap_or_else(|e| e.into_inner());
    if !*guard {
        // PETSc keeps argv: leaked on purpose (once a process).
        // argv[argc] is null, as C's.
        let mut args: Vec<*mut c_char> = ["cfe", "-no_signal_handler"]
            .iter()
            .map(|a| CString::new(*a).expect("no NUL").into_raw())
            .collect();
        let argc: &'static mut c_int = Box::leak(Box::new(args.len() as c_int));
        args.push(std::ptr::null_mut());
        let argv: &'static mut Vec<*mut c_char> = Box::leak(Box::new(args));
        let argv_ptr: &'static mut *mut *mut c_char = Box::leak(Box::new(argv.as_mut_ptr()));
        call!(PetscInitialize(
            argc,
            argv_ptr,
            std::ptr::null(),
            std::ptr::null()
        ))?;
        call!(PetscPushErrorHandler(record_error, std::ptr::null_mut()))?;
        *guard = true;
    }
    Ok(Session {
        _guard: guard,
        pushed: false,
    })
}

impl Session {
    /// Makes `options` the database PETSc reads until the session ends.
    fn push(&mut self, options: ffi::PetscOptions) -> Result<()> {
        call!(PetscOptionsPush(options))?;
        self.pushed = true;
        Ok(())
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        if self.pushed {
            // SAFETY: pops the database pushed above.
            unsafe { ffi::PetscOptionsPop() };
        }
    }
}

/// Finalizes PETSc (and MPI, if PETSc started it) if it was initialized: to be
/// called once, at the end of the program, after every back end is dropped.
/// PETSc cannot be initialized again afterwards in the same process.
pub fn finalize() -> Result<()> {
    let mut guard = PETSC.lock().unwrap_or_else(|e| e.into_inner());
    if *guard {
        call!(PetscFinalize())?;
        *guard = false;
    }
    Ok(())
}

/// This process's rank and the number of ranks (`MPI_COMM_WORLD`: 1 without
/// `mpirun`), initializing PETSc (and MPI) if not done yet.
pub fn world() -> Result<(usize, usize)> {
    let _s = session()?;
    // SAFETY: globals PETSc sets at initialization, read under the lock.
    let (rank, size) = unsafe { (ffi::PetscGlobalRank, ffi::PetscGlobalSize) };
    Ok((rank.max(0) as usize, size.max(1) as usize))
}

/// The communicator PETSc's objects are made on (`PETSC_COMM_WORLD`: every
/// rank `mpirun` started, one without it).
fn comm() -> ffi::MPI_Comm {
    // SAFETY: a global PETSc sets at initialization, read under the lock.
    unsafe { ffi::PETSC_COMM_WORLD }
}

/// A back end's own PETSc options database holding `string` (options as on a
/// PETSc program's command line) and the options of `file` (when given; it
/// must exist). A bad option value is found later, when an object reads it.
/// Destroyed by its owner (`PetscOptionsDestroy`, under the lock).
fn options_database(
    _s: &Session,
    string: &str,
    file: Option<&PathBuf>,
) -> Result<ffi::PetscOptions> {
    let text = CString::new(string)
        .map_err(|_| Error::Options(format!("PETSc options hold a NUL byte: {string:?}")))?;
    let path =
        match file {
            Some(file) => {
                let path = file.to_str().ok_or_else(|| {
                    Error::Options(format!(
                        "options file {} is not a UTF-8 path",
                        file.display()
                    ))
                })?;
                Some(CString::new(path).map_err(|_| {
                    Error::Options(format!("options file {path:?} holds a NUL byte"))
                })?)
            }
            None => None,
        };
    let mut handle = std::ptr::null_mut();
    call!(PetscOptionsCreate(&mut handle))?;
    let filled =
        call!(PetscOptionsInsertString(handle, text.as_ptr())).and_then(|()| match &path {
            Some(p) => call!(PetscOptionsInsertFile(
                comm(),
                handle,
                p.as_ptr(),
                ffi::PETSC_TRUE
            )),
            None => Ok(()),
        });
    if let Err(e) = filled {
        // SAFETY: the database just made, under the lock.
        unsafe { ffi::PetscOptionsDestroy(&mut handle) };
        return Err(e);
    }
    Ok(handle)
}

/// The PETSc back ends for [`cfe::Analysis::set_back_end`]: `petsc` (CG +
/// GAMG) and `petsc-mumps`, for plane and solid models, with the PETSc options
/// of the run.
#[derive(Debug, Clone)]
pub struct Petsc {
    /// PETSc options as on a PETSc program's command line (`-ksp_rtol 1e-12`).
    pub options: String,
    /// A PETSc options file, read after `options`.
    pub options_file: Option<PathBuf>,
    /// The relative residual `‖b − K x‖ / ‖b‖` CG stops at (`-ksp_rtol`
    /// overrides it).
    pub tolerance: f64,
}

impl Default for Petsc {
    /// No options, [`DEFAULT_TOLERANCE`].
    fn default() -> Petsc {
        Petsc::new("", None)
    }
}

impl Petsc {
    /// The back ends with these options ([`DEFAULT_TOLERANCE`]).
    pub fn new(options: impl Into<String>, options_file: Option<PathBuf>) -> Petsc {
        Petsc {
            options: options.into(),
            options_file,
            tolerance: DEFAULT_TOLERANCE,
        }
    }

    /// The solver of `kind` for `problem`, with its record for summary.json.
    #[allow(clippy::type_complexity)]
    fn build<'a, D: cfe::fem::ElementFamily>(
        &self,
        kind: LinearBackend,
        problem: Problem<'a, D>,
    ) -> cfe::Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
        let kind = match kind {
            LinearBackend::PetscMumps => Kind::Mumps,
            _ => Kind::CgGamg,
        };
        let solver = PetscSolver::new(problem, kind, self)?;
        let record = IterativeSolves {
            back_end: match kind {
                Kind::CgGamg => "petsc-cg".into(),
                Kind::Mumps => "petsc-mumps".into(),
            },
            preconditioner: solver.preconditioner_name(),
            tolerance: match kind {
                Kind::CgGamg => solver.tolerance(),
                Kind::Mumps => 0.0,
            },
            ..IterativeSolves::default()
        };
        Ok((Box::new(solver), Some(record)))
    }
}

impl ExternalBackEnd for Petsc {
    fn plane<'a>(
        &self,
        kind: LinearBackend,
        problem: Problem<'a, D2>,
    ) -> cfe::Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
        self.build(kind, problem)
    }

    fn solid<'a>(
        &self,
        kind: LinearBackend,
        problem: Problem<'a, D3>,
    ) -> cfe::Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
        self.build(kind, problem)
    }
}
