//! # cfe-tools: the verification report and the benchmark of cfe
//!
//! Tools built on the `cfe` library's public API, used by the `cfe verify` and
//! `cfe bench` subcommands: [`verification`] runs the cases against closed-form and
//! conforming references and writes `docs/verification.md`; [`bench`](mod@bench)
//! runs the `cfe` executable at growing refinement and writes `docs/benchmarks.md`,
//! stating the machine's [`speed`] before and after its runs.

pub mod bench;
pub mod speed;
pub mod verification;
