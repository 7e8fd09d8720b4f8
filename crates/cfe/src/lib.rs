//! # cfe: contact between independently meshed parts by coupling finite elements
//!
//! Each part of an assembly is meshed on its own; the parts interact across their
//! shared faces through *coupling finite elements* (CFEs), one per coupling node,
//! bonded where the faces press together and free where they pull apart. No degree of
//! freedom is added. The method follows Bitencourt Jr. et al. (CMAME 290, 2015) and
//! Tosati et al. (CILAMCE 2016).
//!
//! Data flows one way through the modules:
//! [`model`] (problem file, validation) → [`mesh`] (nodes, elements, boundaries) →
//! [`fem`] (materials, element routines) → [`coupling`] (pair search, CFEs, laws) →
//! [`assembly`] (DOF map, sparse pattern, global K and F) → [`solve`] (sparse
//! Cholesky, contact schemes) → [`output`] (VTU, CSV, JSON, PNG).
//! [`analysis`] strings them together for one problem. The verification report and
//! the benchmark live in the `cfe-tools` crate, the command line in `cfe-cli`.

pub mod analysis;
pub mod assembly;
pub mod coupling;
pub mod dofs;
pub mod domain;
pub mod error;
pub mod fem;
pub mod mesh;
pub mod model;
pub mod output;
pub mod solve;

pub use error::{Error, Result};
