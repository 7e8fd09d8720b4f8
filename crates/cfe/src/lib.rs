//! # cfe: contact between independently meshed parts by coupling finite elements
//!
//! Each part of an assembly is meshed on its own; the parts interact across their
//! shared faces through *coupling finite elements* (CFEs), one per coupling node,
//! bonded where the faces press together and free where they pull apart. No degree of
//! freedom is added. The method follows Bitencourt Jr. et al. (CMAME 290, 2015) and
//! Tosati et al. (CILAMCE 2016).
//!
//! ## Solving a model in memory
//!
//! A [`Model`] comes from a problem file ([`Model::from_file`]), from text
//! (`text.parse::<Model>()` or [`Model::from_str`]), or is built in code
//! ([`Model::from_parts`]). [`Analysis::new`] finds the coupling pairs and numbers
//! the DOFs; [`Analysis::solve`] solves every increment without writing a file and
//! returns the [`Results`] of the last one; [`Analysis::run`] also writes them.
//!
//! ```
//! let text = r#"
//! [materials.steel]
//! E = 210000.0
//! nu = 0.3
//!
//! [[part]]
//! name = "base"
//! material = "steel"
//! rectangle = { x = [0.0, 40.0], y = [0.0, 20.0], cells = [4, 2] }
//!
//! [[part]]
//! name = "block"
//! material = "steel"
//! rectangle = { x = [10.0, 30.0], y = [20.0, 30.0], cells = [6, 3] }
//!
//! [[interface]]
//! host = "base"
//! nodes = "block"
//! boundary = "bottom"
//!
//! [[support]]
//! part = "base"
//! boundary = "bottom"
//! fix = ["x", "y"]
//!
//! [[load]]
//! part = "block"
//! boundary = "top"
//! force = [0.0, -100.0]
//! "#;
//! let model: cfe::Model = text.parse()?;
//! let analysis = cfe::Analysis::new(model)?;
//! let results = analysis.solve()?;
//! // Pressed down, every pair is bonded and the base carries the load.
//! assert!(results.last.states[0].iter().all(|&s| s == cfe::PairState::Bonded));
//! let reaction = &results.reactions()[0];
//! assert!((reaction.fy - 100.0).abs() < 1e-6);
//! let u = results.displacements();
//! assert!(u.iter().all(|v| v.is_finite()));
//! # Ok::<(), cfe::Error>(())
//! ```
//!
//! ## Layers
//!
//! Each module imports only the modules below it, in the order
//! `error < dim < mesh < fem < domain < dofs < coupling < assembly < solve < results <
//! model < analysis < output < run` (checked by `tests/architecture.rs`, with no import
//! circle): `dim` (the dimension: DOFs per node, the tangent and local frame of
//! the interface law) → `mesh` (nodes, elements, boundaries) → `fem` (materials, element
//! routines) → `domain` (the resolved problem) → `dofs` → `coupling` (interface
//! building, pair search, CFEs, laws) → `assembly` (sparse pattern, global K and
//! F) → `solve` (sparse Cholesky, contact schemes) → [`results`] (the summary and
//! its bookkeeping, the pair rows) → [`model`] (problem file, validation) →
//! [`analysis`] (one problem from model to results) → [`output`] (VTU, CSV, JSON,
//! PNG) → `run` (the run loop: [`Analysis::run`] hands each converged increment
//! to the writers). The verification report and the benchmark live in the `cfe-tools`
//! crate, the command line in `cfe-cli`.
//!
//! ## Public API
//!
//! The crate root re-exports what a program needs to build, solve and read a model
//! ([`Model`], [`Analysis`], [`Results`], [`Summary`], [`Error`], the domain types and
//! the result types), and [`analysis`], [`model`], [`domain`], [`mesh`], [`dim`], [`results`],
//! [`output`] and [`error`] are public. The numerical layers (`fem`, `coupling`, `dofs`, `assembly`,
//! `solve`) are crate-private; the `internals` feature makes them public for the
//! verification crate and the integration tests, with no stability promise.

#![warn(missing_docs)]

/// Declares a layer module: public with the `internals` feature (for the verification
/// crate and the integration tests, no stability promise), crate-private otherwise.
macro_rules! layer {
    ($(#[$attr:meta])* $name:ident) => {
        $(#[$attr])*
        #[cfg(feature = "internals")]
        pub mod $name;
        $(#[$attr])*
        #[cfg(not(feature = "internals"))]
        #[allow(dead_code, unused_imports)]
        pub(crate) mod $name;
    };
}

pub mod analysis;
layer!(assembly);
layer!(coupling);
pub mod dim;
layer!(dofs);
pub mod domain;
pub mod error;
layer!(fem);
pub mod mesh;
pub mod model;
pub mod output;
pub mod results;
mod run;
layer!(solve);

pub use analysis::{Analysis, Results, RunStatus, Start, Summary};
pub use coupling::{
    CouplingElement, Enforcement, Interface, Law, PairState, PairStates, ViolationKind,
};
pub use dofs::DofMap;
pub use domain::{
    FrictionSolve, InterfaceDef, LinearBackend, Load, OUTPUT_LAST, Part, Scheme, Settings, Support,
};
pub use error::{DeckFault, Error, Result};
pub use fem::material::{Material, PlaneKind, von_mises_3d};
pub use fem::recovery::PartStress;
pub use mesh::{BoundarySelection, Element, ElementKind, Mesh};
pub use model::{FromProblemFile, FromProblemText, Model};
pub use output::report::PairRow;
pub use run::RunDim;
pub use solve::nonlinear::{IncrementResult, Iteration, MultipleOf, PairViolation, Solver};
pub use solve::system::{Method, UpdatePolicy};
