//! The seam between the contact scheme and the linear algebra: what the scheme
//! asks of a linear solver, so that any back end — today's supernodal Cholesky
//! ([`super::direct::Cholesky`]), preconditioned conjugate gradients
//! ([`super::iterative::ConjugateGradients`]), PETSc (the `cfe-petsc` crate,
//! through [`super::contact::ExternalBackEnd`]) — can answer it.
//!
//! Every matrix the scheme solves with is `K(states)`: the parts' stiffness plus
//! the coupling elements' in the given pair states, over the free equations of a
//! fixed pattern (the node graph: every coupling element is in it whatever its
//! state). A back end is built for that pattern once ([`Analyse::analyse`]:
//! ordering and symbolic factorization, or the sparse layout of an iterative
//! solver), then for each set of states it makes the values ready
//! ([`LinearSolver::prepare`]: a numeric factorization, or a preconditioner)
//! and solves ([`LinearSolver::solve_in_place`], from an optional initial
//! guess, reporting what it did in an [`Outcome`]).
//!
//! That small core is all a back end must do. What only some can do is offered
//! as optional capabilities, each a method returning `Option`:
//!
//! - [`RestrictedSolve`] ([`LinearSolver::restricted`]): solves whose answer is
//!   wanted at the coupling equations only, or whose right-hand side is zero off
//!   them (a direct solver walks the elimination-tree paths of those equations);
//! - [`RefinedSolve`] ([`LinearSolver::refinement`]): a solve completed by one
//!   step of iterative refinement at the coupling equations, with the residual
//!   given by the caller (after a low-rank update);
//! - [`LowRankUpdate`] ([`LinearSolver::low_rank`]): a kept factorization
//!   corrected for the few pairs whose state changed, under a policy;
//! - [`PairFlexibility`] ([`LinearSolver::flexibility`]): the pairs'
//!   flexibility (the condensed interface) from a kept factorization and its
//!   cached correction columns, without a solve.
//!
//! The scheme asks through one call, [`Solve::solve_pattern`] (implemented for
//! every back end), with a [`Request`] saying what it needs; a back end without
//! the capability a request could use answers it by a complete solve, which is
//! always a valid answer.
//!
//! ```
//! use cfe::solve::backend::{Request, Solve};
//! use cfe::coupling::PairState;
//! // What the active-set search asks for a trial: the coupling equations'
//! // entries of the solution, warm-started from the last trial (a back end
//! // that cannot restrict its solve or use a guess ignores what it cannot).
//! let states = vec![vec![PairState::Bonded; 3]];
//! let last = vec![0.0; 12];
//! let request = Request::new(&states).interface_only().guess(&last);
//! assert!(request.wants_interface_only());
//! ```

use super::factor::Halt;
use super::system::{Method, UpdatePolicy};
use crate::assembly::DofMap;
use crate::coupling::{Interface, PairState};
use crate::dim::D2;
use crate::domain::Part;
use crate::fem::ElementFamily;
use std::sync::atomic::AtomicUsize;

/// The problem a back end solves: `K(states)` of these parts (whose stiffness is
/// constant) and interfaces (whose coupling elements' stiffness follows the pair
/// states) over the free equations of `dofs`.
pub struct Problem<'a, D: ElementFamily = D2> {
    /// The parts.
    pub parts: &'a [Part<D>],
    /// The interfaces (their coupling elements, of dimension `D`).
    pub interfaces: &'a [Interface<D>],
    /// The DOF map: the free equations (`D::N` DOFs a node).
    pub dofs: &'a DofMap<D>,
}

impl<D: ElementFamily> Clone for Problem<'_, D> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<D: ElementFamily> Copy for Problem<'_, D> {}

/// A linear solve that did not give a solution.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum LinearFailure {
    /// The caller's stop flag was nonzero (its value, e.g. a signal's number).
    #[error("stopped (flag {0})")]
    Stopped(usize),
    /// The matrix is not positive definite: a non-positive pivot at this
    /// equation (a direct solver), or a direction of non-positive curvature or
    /// a non-positive diagonal entry (an iterative one; the equation when
    /// known). A mechanism or a part without support.
    #[error("the stiffness matrix is not positive definite{}", .equation.map(|e| format!(" (at equation {e})")).unwrap_or_default())]
    NotPositiveDefinite {
        /// The equation where it was found, when known.
        equation: Option<usize>,
    },
    /// A back end outside this library failed in one of its calls (e.g. a PETSc
    /// function returning an error code).
    #[error("{function} failed with error code {code}")]
    BackEnd {
        /// The call that failed.
        function: &'static str,
        /// Its error code.
        code: i32,
    },
    /// An iterative solve reached its iteration cap before its tolerance.
    #[error("the iterative solve did not converge: relative residual {relative_residual:e} after {iterations} iterations (tolerance {tolerance:e})")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// `‖b − K x‖ / ‖b‖` of the last iterate.
        relative_residual: f64,
        /// The tolerance it was to reach.
        tolerance: f64,
    },
}

impl From<Halt> for LinearFailure {
    fn from(halt: Halt) -> Self {
        match halt {
            Halt::Pivot(eq) => LinearFailure::NotPositiveDefinite { equation: Some(eq) },
            Halt::Stopped(signal) => LinearFailure::Stopped(signal),
        }
    }
}

/// What an iterative solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iterations {
    /// Iterations done (0: the initial guess met the tolerance).
    pub count: usize,
    /// `‖b − K x‖ / ‖b‖` of the solution returned.
    pub relative_residual: f64,
}

/// What one solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// [`Method::Factorization`]: the values were prepared anew for this solve
    /// (a numeric factorization, or a preconditioner built);
    /// [`Method::Reuse`]: the kept preparation served; [`Method::LowRank`]: a
    /// kept factorization corrected for the pairs that changed.
    pub method: Method,
    /// The iterations and the residual of an iterative solve (`None`: direct).
    pub iterations: Option<Iterations>,
    /// Whether every entry of the solution was written (`false` only for a
    /// [`RestrictedSolve::solve_interface`] that solved for the coupling
    /// equations only: the other entries are meaningless).
    pub complete: bool,
}

impl Outcome {
    /// A direct solve's complete outcome.
    pub fn direct(method: Method) -> Self {
        Outcome {
            method,
            iterations: None,
            complete: true,
        }
    }
}

/// Counts and times of a back end's work so far.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Statistics {
    /// Entries stored in the lower triangle of the stiffness.
    pub matrix_nnz: usize,
    /// Nonzeros of the Cholesky factor (0 for a back end without one).
    pub factor_nnz: usize,
    /// Flops of one numeric factorization (0 for a back end without one).
    pub factor_flops: f64,
    /// Preparations of values (numeric factorizations, preconditioners built).
    pub preparations: usize,
    /// Low-rank updates (0 without that capability).
    pub updates: usize,
    /// Iterations of every iterative solve (0 for a direct back end).
    pub iterations: usize,
    /// Flops counted by the back end's cost model for its work so far.
    pub flops: f64,
    /// Seconds preparing values.
    pub prepare_seconds: f64,
    /// Seconds of the first preparation (`None` before it).
    pub first_prepare_seconds: Option<f64>,
    /// Seconds solving.
    pub solve_seconds: f64,
}

/// Building a back end for the fixed pattern of a problem: the analysis of the
/// pattern (an elimination order and a symbolic factorization, or the layout of
/// an iterative solver's matrix), done once. Apart from [`LinearSolver`] so
/// that the latter can be used as a trait object.
pub trait Analyse<'a, D: ElementFamily = D2>: Sized {
    /// The back end for `problem`'s pattern (an error when it cannot hold it).
    fn analyse(problem: Problem<'a, D>) -> crate::error::Result<Self>;
}

/// The core of a linear back end: prepare the values of `K(states)`, solve with
/// them. The contact scheme reaches the linear algebra through this trait (and
/// its conveniences, [`Solve`]); everything else is an optional capability.
pub trait LinearSolver<'a> {
    /// Makes the back end ready to solve `K(states)`: a numeric factorization,
    /// or a preconditioner. [`Method::Reuse`] when what is kept is of these
    /// states already. A solve prepares its states itself when needed: calling
    /// this first is optional (to time it apart, or to fail before solving).
    fn prepare(&mut self, states: &[Vec<PairState>]) -> Result<Method, LinearFailure>;

    /// Solves `K(states) x = rhs` in place (`rhs` is over the free equations),
    /// from the initial guess `guess` when given (an iterative back end starts
    /// from it; a direct one ignores it). Every entry of the solution is written.
    fn solve_in_place(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        guess: Option<&[f64]>,
    ) -> Result<Outcome, LinearFailure>;

    /// Has the back end read `stop` (one relaxed load) before and within long
    /// work: once nonzero it returns [`LinearFailure::Stopped`] with its value.
    fn set_stop(&mut self, stop: &'a AtomicUsize);

    /// Forgets the prepared values: the next solve prepares anew.
    fn forget(&mut self);

    /// Forgets anything kept of the right-hand sides solved so far (an
    /// increment was accepted, its right-hand side is not solved again).
    fn forget_right_hand_side(&mut self) {}

    /// Forgets the prepared values and frees their memory.
    fn release(&mut self);

    /// Whether prepared values are kept (a solve may reuse or update them).
    fn is_prepared(&self) -> bool;

    /// Whether a solve starts from the initial guess it is given (an iterative
    /// back end): only then is a guess worth keeping for it.
    fn starts_from_guess(&self) -> bool {
        false
    }

    /// A hint: `false` when another preparation is unlikely (proportional
    /// loads), so what only a later one would need may be freed after each.
    fn keep_pattern(&mut self, _keep: bool) {}

    /// Counts and times so far.
    fn statistics(&self) -> Statistics;

    /// Seconds spent building the pattern again since the last call (setup
    /// work that happens during the solve), reset to zero.
    fn take_pattern_seconds(&mut self) -> f64 {
        0.0
    }

    /// The restricted solves, if the back end has them.
    fn restricted(&mut self) -> Option<&mut dyn RestrictedSolve> {
        None
    }

    /// The refined solve, if the back end has it.
    fn refinement(&mut self) -> Option<&mut dyn RefinedSolve> {
        None
    }

    /// The low-rank updates, if the back end has them.
    fn low_rank(&mut self) -> Option<&mut dyn LowRankUpdate> {
        None
    }

    /// The pairs' flexibility from what is kept, if the back end has it.
    fn flexibility(&mut self) -> Option<&mut dyn PairFlexibility> {
        None
    }
}

/// Solves restricted to the coupling equations (optional capability).
pub trait RestrictedSolve {
    /// Solves `K(states) x = rhs` for the entries of `x` at the coupling
    /// equations only, written into `rhs` there; the others are meaningless
    /// unless [`Outcome::complete`] (a new preparation may solve in full).
    /// `rhs_on_interface`: `rhs` is zero off the coupling equations.
    fn solve_interface(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        rhs_on_interface: bool,
    ) -> Result<Outcome, LinearFailure>;

    /// Solves `K(states) x = rhs` in full for a `rhs` that is zero off the
    /// coupling equations (a change of the pairs' forces).
    fn solve_pair_forces(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Outcome, LinearFailure>;
}

/// The residual of an approximate solution at the coupling equations, for a
/// refinement: called with the approximate solution in the vector (valid at
/// least at the equations the [`RefinedSolve`] was given to read), it must
/// overwrite the vector with `b − K x̃` at the coupling equations and zeros at
/// every other equation.
pub type Residual<'r> = &'r mut dyn FnMut(&mut [f64]);

/// A solve completed by one step of iterative refinement at the coupling
/// equations (optional capability): after a low-rank update, whose round-off
/// lies there.
pub trait RefinedSolve {
    /// Solves `K(states) x = rhs` in place. If the solve is approximate (a
    /// low-rank update), `residual` is called once with the approximate
    /// solution (valid at the equations `read`, which must hold every equation
    /// the residual at the coupling equations depends on) and the correction it
    /// returns is solved and added; otherwise it is not called.
    fn solve_refined(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        read: &[usize],
        residual: Residual<'_>,
    ) -> Result<Outcome, LinearFailure>;
}

/// Low-rank updates of a kept factorization (optional capability): a solve of
/// states a few pairs away from the factorized ones corrects it instead of
/// factorizing anew, when [`UpdatePolicy`] says so.
pub trait LowRankUpdate {
    /// Chooses when to update rather than refactorize.
    fn set_policy(&mut self, policy: UpdatePolicy);
}

/// The pairs' flexibility under `K(states)` from a kept factorization and its
/// cached low-rank columns, without a solve with the factor (optional
/// capability): the interface's condensed operator, read by the Newton solve
/// of Coulomb friction (docs/method.md §2.1).
pub trait PairFlexibility {
    /// `F = W_Pᵀ K(states)⁻¹ W_T` for the pairs `pairs` (interface, pair):
    /// rows every local axis of each pair (normal, then each tangent; pair
    /// after pair), columns each pair's tangential axes; entry `(r, s)` the
    /// jump along axis r under a unit local force along axis s. Row-major.
    /// `None` when it cannot be had cheaply (nothing kept for these states,
    /// or no room for the columns): the caller solves instead.
    fn pair_flexibility(&mut self, states: &[Vec<PairState>], pairs: &[(usize, usize)]) -> Option<Vec<f64>>;
}

/// What the scheme asks of one solve of a pattern: the states, and what it
/// needs and knows. Built by [`Request::new`] and its setters.
pub struct Request<'r> {
    states: &'r [Vec<PairState>],
    guess: Option<&'r [f64]>,
    interface_only: bool,
    rhs_on_interface: bool,
    refine: Option<(&'r [usize], Residual<'r>)>,
}

impl<'r> Request<'r> {
    /// A complete solve of `K(states) x = b`.
    pub fn new(states: &'r [Vec<PairState>]) -> Self {
        Request {
            states,
            guess: None,
            interface_only: false,
            rhs_on_interface: false,
            refine: None,
        }
    }

    /// Only the coupling equations' entries are needed.
    pub fn interface_only(mut self) -> Self {
        self.interface_only = true;
        self
    }

    /// The right-hand side is zero off the coupling equations.
    pub fn rhs_on_interface(mut self) -> Self {
        self.rhs_on_interface = true;
        self
    }

    /// Start from `guess` (an iterative back end's warm start).
    pub fn guess(mut self, guess: &'r [f64]) -> Self {
        self.guess = Some(guess);
        self
    }

    /// Refine an approximate solve at the coupling equations with `residual`,
    /// reading the approximate solution at `read` ([`RefinedSolve`]).
    pub fn refined(mut self, read: &'r [usize], residual: Residual<'r>) -> Self {
        self.refine = Some((read, residual));
        self
    }

    /// Whether only the coupling equations' entries are asked for.
    pub fn wants_interface_only(&self) -> bool {
        self.interface_only
    }
}

/// The conveniences on top of [`LinearSolver`], for every back end.
pub trait Solve<'a>: LinearSolver<'a> {
    /// Solves the pattern of `request` with `rhs` in place, by the cheapest
    /// means the back end has: a restricted solve when only the coupling
    /// equations are wanted or the right-hand side lives there, a refined solve
    /// when a refinement is offered, else a complete solve (from the guess).
    fn solve_pattern(
        &mut self,
        request: Request<'_>,
        rhs: &mut [f64],
    ) -> Result<Outcome, LinearFailure> {
        let Request {
            states,
            guess,
            interface_only,
            rhs_on_interface,
            refine,
        } = request;
        if interface_only && let Some(r) = self.restricted() {
            return r.solve_interface(states, rhs, rhs_on_interface);
        }
        if let Some((read, residual)) = refine
            && let Some(r) = self.refinement()
        {
            return r.solve_refined(states, rhs, read, residual);
        }
        if rhs_on_interface
            && !interface_only
            && let Some(r) = self.restricted()
        {
            return r.solve_pair_forces(states, rhs);
        }
        self.solve_in_place(states, rhs, guess)
    }
}

impl<'a, S: LinearSolver<'a> + ?Sized> Solve<'a> for S {}
