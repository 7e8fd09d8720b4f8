//! The cells and boundary faces of a solid (3D) mesh, `Mesh<D3>`: linear
//! tetrahedra TET4 and trilinear hexahedra HEX8 (possibly mixed), numbered as Gmsh
//! and VTK number them, and their local faces and edges as node lists.
//!
//! ```text
//!   TET4 (VTK_TETRA)                HEX8 (VTK_HEXAHEDRON)
//!          3                          7 ─────── 6
//!         /|╲                        /|        /|
//!        / | ╲                      4 ─────── 5 |
//!       /  |  ╲                     | 3 ──────|─ 2        z
//!      0 ──|── 2                    |/        |/         │  y
//!       ╲  | ╱                      0 ─────── 1          │ ╱
//!        ╲ |╱                                            └──── x
//!          1
//!   positive volume:               bottom 0-1-2-3 counter-clockwise
//!   (x1 − x0) × (x2 − x0) · (x3 − x0) > 0   seen from above, 4-7 above 0-3
//! ```
//!
//! Each local face lists its corners so that the right-hand rule gives the
//! outward normal of a positive element; [`TET4_FACES`] and [`HEX8_FACES`] are the
//! one home of those lists (the element routines of `fem` read them).

use super::{MeshCell, MeshDim, MeshFace};
use crate::dim::D3;

/// Solid meshes: TET4/HEX8 elements, boundaries of faces.
impl MeshDim for D3 {
    type Cell = SolidElement;
    type Face = BoundaryFace;
}

/// The element types of a solid part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SolidKind {
    /// 4-node linear tetrahedron (constant strain).
    Tet4,
    /// 8-node trilinear hexahedron.
    Hex8,
}

impl SolidKind {
    /// Name as in messages and counts (`TET4`, `HEX8`).
    pub fn as_str(self) -> &'static str {
        match self {
            SolidKind::Tet4 => "TET4",
            SolidKind::Hex8 => "HEX8",
        }
    }

    /// Number of nodes of an element of this kind (4 or 8).
    pub fn node_count(self) -> usize {
        match self {
            SolidKind::Tet4 => 4,
            SolidKind::Hex8 => 8,
        }
    }
}

/// The faces of a TET4 as local node lists, each ordered so the right-hand rule
/// gives the outward normal of a positive tetrahedron; face `f` is the one
/// opposite local node `[3, 2, 1, 0][f]`.
pub const TET4_FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [3, 1, 2]];

/// The faces of a HEX8 as local node lists, outward by the right-hand rule:
/// bottom (ζ = −1), front (η = −1), left (ξ = −1), right (ξ = +1), back
/// (η = +1), top (ζ = +1) in the element's natural coordinates.
pub const HEX8_FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [0, 1, 5, 4],
    [0, 4, 7, 3],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [4, 5, 6, 7],
];

/// The six edges of a TET4 as local node pairs.
pub const TET4_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The twelve edges of a HEX8 as local node pairs: the bottom ring, the top ring,
/// the four verticals.
pub const HEX8_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// One element of a solid part: its corner nodes (local numbering of the part),
/// in the Gmsh/VTK order (see the module's figure).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolidElement {
    /// A linear tetrahedron.
    Tet4([usize; 4]),
    /// A trilinear hexahedron.
    Hex8([usize; 8]),
}

impl SolidElement {
    /// The element's nodes in the Gmsh/VTK order.
    pub fn nodes(&self) -> &[usize] {
        match self {
            SolidElement::Tet4(n) => n,
            SolidElement::Hex8(n) => n,
        }
    }

    /// Its type.
    pub fn kind(&self) -> SolidKind {
        match self {
            SolidElement::Tet4(_) => SolidKind::Tet4,
            SolidElement::Hex8(_) => SolidKind::Hex8,
        }
    }

    /// Number of local faces (4 or 6).
    pub fn face_count(&self) -> usize {
        match self {
            SolidElement::Tet4(_) => TET4_FACES.len(),
            SolidElement::Hex8(_) => HEX8_FACES.len(),
        }
    }

    /// Local face `f` as mesh nodes, ordered so the right-hand rule gives the
    /// outward normal ([`TET4_FACES`], [`HEX8_FACES`]).
    pub fn face(&self, f: usize) -> FaceNodes {
        match self {
            SolidElement::Tet4(n) => FaceNodes::Tri(TET4_FACES[f].map(|k| n[k])),
            SolidElement::Hex8(n) => FaceNodes::Quad(HEX8_FACES[f].map(|k| n[k])),
        }
    }

    /// Its faces as mesh nodes, outward, in local face order.
    pub fn faces(&self) -> impl Iterator<Item = FaceNodes> + '_ {
        (0..self.face_count()).map(move |f| self.face(f))
    }

    /// Its edges as mesh node pairs ([`TET4_EDGES`], [`HEX8_EDGES`]).
    pub fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        let (n, local): (&[usize], &[[usize; 2]]) = match self {
            SolidElement::Tet4(n) => (n, &TET4_EDGES),
            SolidElement::Hex8(n) => (n, &HEX8_EDGES),
        };
        local.iter().map(move |&[a, b]| [n[a], n[b]])
    }
}

impl MeshCell for SolidElement {
    fn nodes(&self) -> &[usize] {
        SolidElement::nodes(self)
    }

    fn kind_name(&self) -> &'static str {
        self.kind().as_str()
    }
}

/// The corners of a face of a solid element: a triangle (of a TET4) or a
/// quadrangle (of a HEX8), ordered so that the right-hand rule gives the normal
/// pointing out of the element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FaceNodes {
    /// A triangular face.
    Tri([usize; 3]),
    /// A quadrangular face, corners in order around it.
    Quad([usize; 4]),
}

impl FaceNodes {
    /// The corners, in order around the face.
    pub fn as_slice(&self) -> &[usize] {
        match self {
            FaceNodes::Tri(n) => n,
            FaceNodes::Quad(n) => n,
        }
    }
}

/// A boundary face of a solid part: its corners, ordered so that the right-hand
/// rule gives the outward normal, the element that owns it and which of that
/// element's local faces it is ([`SolidElement::face`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BoundaryFace {
    /// The corners (local numbering of the part), outward by the right-hand rule.
    pub nodes: FaceNodes,
    /// The element the face belongs to.
    pub element: usize,
    /// Its local face index in that element ([`TET4_FACES`], [`HEX8_FACES`]).
    pub face: usize,
}

impl MeshFace for BoundaryFace {
    fn nodes(&self) -> &[usize] {
        self.nodes.as_slice()
    }

    fn element(&self) -> usize {
        self.element
    }
}
