//! The contact scheme's public items under the path analysis, output, the
//! tools and the tests import them by; the scheme itself, in layers, is
//! [`super::contact`].

pub use super::contact::{
    ANDERSON_DEPTH, BALANCE_FLOOR, CONTINUATION, FIXED_POINT_TOLERANCE, FORCE_FLOOR,
    IncrementResult, IterativeSolves, Iteration, LoadSteps, MAX_FIXED_POINT, MultipleOf,
    PairViolation,
    RESIDUAL_WARN, SolveTimings, Solver,
};
