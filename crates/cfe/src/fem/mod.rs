//! Finite elements of the parts: the linear elastic material law, the element
//! routines (stiffness, internal force, stress) of the linear triangle [`t3`] and
//! the bilinear quadrilateral [`q4`] as small pure functions, and the
//! [`element`] provider that dispatches between them for mixed meshes.

pub mod axisymmetric;
pub mod element;
pub(crate) mod loads;
pub mod material;
pub mod q4;
pub mod recovery;
pub mod t3;

pub use material::{Material, PlaneKind};
