//! Incremental solution with contact interfaces. The load (and any prescribed
//! displacement) grows linearly over the increments; every increment solves total
//! equilibrium `K(D̂) u = λ F` (the law is secant, so a lagged state leaves no
//! accumulated error). Two schemes decide the pair states D̂:
//!
//! - `active-set`: solve, let the law update every pair (a bonded pair in tension
//!   opens, an open pair that interpenetrates closes), repeat until the law holds on
//!   every pair. Each whole pattern of states is remembered (hashed); the iteration
//!   *cycles* only when the law sends it back to a pattern it has already solved.
//!   Then it continues cautiously, flipping only the pair with the largest violation
//!   per iteration (with Coulomb friction: the worst whose flip leads to a pattern
//!   not yet solved that holds every part), which finds a consistent pattern the
//!   all-at-once update stepped over. When that leads back to a solved pattern too
//!   (with friction: when no flip is left), or `max_iterations` pass, no consistent
//!   pattern is within reach (the strict stick law has none on some meshes) and the
//!   increment is *settled*: it ends on
//!   the least-violating pattern it solved — no penetration if any such pattern was
//!   visited, then the smallest largest violation, then the earliest — and every
//!   pair that breaks the law there is reported with its amount. Nothing carries
//!   over to the next increment but the pattern it starts from.
//! - `implex` (the seed's): the states of increment n come from `[[u_n]]` of increment
//!   n − 1 (all bonded before the first); one solve per increment. Its pairs are
//!   checked against the law after every increment all the same.
//!
//! After every increment the law is checked on every pair (tension of bonded pairs
//! beyond `force_tolerance` × the load scale, penetration of open pairs beyond
//! `gap_tolerance` × the pair's displacement scale) and the out-of-balance force is
//! checked against the load: above `max_residual` (default 1e-4) the run stops
//! with [`crate::error::Error::Precision`], above [`RESIDUAL_WARN`] the result is flagged.
//!
//! Linear solves go through the linear-solver seam ([`crate::solve::backend`]):
//! the [`Solver`] holds its back end as a `Box<dyn LinearSolver>` and asks it to
//! solve a pattern through one call (`solve_pattern`), using restricted and
//! refined solves and low-rank updates only when the back end offers them. The
//! direct back end ([`crate::solve::direct::Cholesky`]) refactorizes or corrects
//! the current factorization by a low-rank update, whichever costs less. A state set
//! already solved at another load factor is not solved again: with proportional
//! loads its solution scales with λ exactly. For the same reason an increment that
//! starts from the pattern the previous one ended on needs no new solve: the law is
//! homogeneous in the load, so a consistent pattern stays consistent and a settled
//! one breaks the law by the same fraction of the load at every level (and is kept).
//! So with `active-set` the factorization is freed once an increment has converged,
//! before its output is written (a later solve, if any, refactorizes).
//!
//! The scheme reaches the coupling pairs only through [`crate::coupling::PairSet`]
//! (the model's interfaces and DOF map as `InterfacePairs`, `Solver::pairs`):
//! their count, law, DOFs, evaluation at u and labels; its nodal vectors, DOFs
//! per node and tangent components are the dimension `D` of `Solver<'a, D>`
//! (`D2` for the plane models built today), which every layer is generic over.
//!
//! The scheme is a stack of layers, each file using only those below it:
//!
//! ```text
//! driver       Solver::run: the increment loop, implex, the end of an increment
//! active_set   the search: trials, flips, settling, stick point, continuation in μ
//! slip_newton  a pattern's slip forces by Newton steps (columns, small system, exact solve)
//! friction     Coulomb as a semi-smooth Newton: the pair update, the condensed model
//! pattern      one pattern solved (complete or restricted), right-hand sides, finish
//! fixed_point  the pairs' right-hand-side terms (slip forces, multipliers), Anderson
//! pairs        the law sweep and the pair-history rules
//! solver       the Solver's state, configuration, scales of a solution, solve errors
//! scale        load scale, balance scale, drift guard (pure)
//! increment    results (IncrementResult, Iteration, …) and load steps
//! ```

mod active_set;
mod driver;
mod fixed_point;
mod friction;
mod increment;
mod pairs;
mod pattern;
mod scale;
mod slip_newton;
mod solver;

pub use active_set::CONTINUATION;
pub use fixed_point::{ANDERSON_DEPTH, FIXED_POINT_TOLERANCE, MAX_FIXED_POINT};
pub use friction::{
    Active, Condensed, CondensedPair, NewtonRun, Tolerance, newton_condensed, next_active,
    return_map_derivative, solve_pattern_linear,
};
pub use slip_newton::MAX_NEWTON_SLIPPING;
pub use increment::{
    IncrementResult, IterativeSolves, Iteration, LoadSteps, MultipleOf, NewtonCounts,
    PairViolation, SolveTimings,
};
pub use scale::{BALANCE_FLOOR, FORCE_FLOOR, RESIDUAL_WARN};
pub use solver::{ExternalBackEnd, Solver};
