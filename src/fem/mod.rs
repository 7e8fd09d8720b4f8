//! Finite elements of the parts: the linear elastic material law and the element
//! routines (stiffness, internal force, stress) as small pure functions.

pub mod loads;
pub mod material;
pub mod recovery;
pub mod t3;

pub use material::{Material, PlaneKind};
