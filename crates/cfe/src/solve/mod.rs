//! Solve: the sparse Cholesky solver (symbolic analysis once, numeric factorization
//! per state), the support check that turns a singular system into a clear error,
//! the incremental contact schemes (`active-set`, `implex`) and their warm start
//! from a coarser model.

pub mod linear;
pub mod nonlinear;
pub mod ordering;
pub mod support;
pub mod system;
pub mod warm_start;
