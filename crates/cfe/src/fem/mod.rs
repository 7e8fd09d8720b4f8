//! Finite elements of the parts: the linear elastic material law, the element
//! routines (stiffness, internal force, stress) of the linear triangle [`t3`] and
//! the bilinear quadrilateral [`q4`] as small pure functions, and the
//! [`element`] provider that dispatches between them for mixed meshes; and the
//! 3D solid elements' routines on corner coordinates — the linear tetrahedron
//! [`tet4`], the trilinear hexahedron [`hex8`], what they share ([`solid`]: the
//! Voigt order, B, the report of a non-positive Jacobian) and their faces' loads
//! ([`face3`]) — which no mesh type reaches yet.

pub mod axisymmetric;
pub mod element;
pub mod face3;
pub mod hex8;
pub(crate) mod loads;
pub mod material;
pub mod q4;
pub mod recovery;
pub mod solid;
pub mod t3;
pub mod tet4;

pub use material::{Material, PlaneKind};
