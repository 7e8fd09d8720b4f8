//! Solve: the sparse Cholesky solver (symbolic analysis once, numeric factorization
//! per state), the support check that turns a singular system into a clear error,
//! the incremental contact schemes (`active-set`, `implex`) and their warm start
//! from a coarser model.

pub(crate) mod anderson;
pub(crate) mod capacitance;
pub(crate) mod columns;
pub mod contact;
pub mod factor;
pub(crate) mod heap;
pub mod linear;
pub mod nonlinear;
pub(crate) mod ordering;
pub(crate) mod setup;
pub mod subtree;
pub(crate) mod support;
pub mod symbolic;
pub mod system;
pub(crate) mod warm_start;
