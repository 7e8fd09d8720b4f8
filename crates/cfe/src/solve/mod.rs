//! Solve: the sparse Cholesky solver (symbolic analysis once, numeric factorization
//! per state), the support check that turns a singular system into a clear error,
//! the incremental contact schemes (`active-set`, `implex`) and their warm start
//! from a coarser model. The linear-solver seam ([`backend`]) puts the linear
//! algebra behind a trait, implemented by the supernodal Cholesky ([`direct`])
//! and by preconditioned conjugate gradients ([`iterative`]); the scheme
//! ([`contact`], re-exported under its former path [`nonlinear`]) reaches the
//! linear algebra only through that seam, the back end chosen per run.

pub(crate) mod anderson;
pub mod backend;
pub(crate) mod capacitance;
pub(crate) mod columns;
pub mod contact;
pub mod direct;
pub mod factor;
#[cfg(test)]
mod fixture;
pub(crate) mod halt;
pub(crate) mod heap;
pub mod iterative;
pub mod linear;
pub mod lower;
pub mod paths;
pub mod nonlinear;
pub(crate) mod ordering;
pub(crate) mod setup;
pub mod subtree;
pub(crate) mod friction_hold;
pub(crate) mod support;
pub mod symbolic;
pub mod system;
pub(crate) mod warm_start;
