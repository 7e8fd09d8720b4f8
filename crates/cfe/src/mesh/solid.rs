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

use super::{Mesh, MeshCell, MeshDim, MeshFace};
use crate::dim::{D3, Dim};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

/// Solid meshes: TET4/HEX8 elements, boundaries of faces.
impl MeshDim for D3 {
    type Cell = SolidElement;
    type Face = BoundaryFace;
    const KIND_NAMES: [&'static str; 2] = ["TET4", "HEX8"];
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

    fn is_simplex(&self) -> bool {
        self.kind() == SolidKind::Tet4
    }

    fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        SolidElement::edges(self)
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

impl FaceNodes {
    /// The face's vector area: its area times its unit normal, the normal given by
    /// the right-hand rule (outward for an element's face). A triangle's is
    /// ½ (b − a) × (c − a); a quadrangle's ½ (c − a) × (d − b), the vector area of
    /// its boundary polygon, which is that of the bilinear surface through its
    /// corners even when they are not coplanar. `nodes` are the mesh's nodes.
    pub fn vector_area(&self, nodes: &[[f64; 3]]) -> [f64; 3] {
        let p = |n: usize| nodes[n];
        let c = match *self {
            FaceNodes::Tri([a, b, c]) => cross(sub(p(b), p(a)), sub(p(c), p(a))),
            FaceNodes::Quad([a, b, c, d]) => cross(sub(p(c), p(a)), sub(p(d), p(b))),
        };
        c.map(|v| 0.5 * v)
    }

    /// The corners as a sorted key (a triangle's padded with `usize::MAX`): the
    /// same for the two elements that share the face.
    fn key(&self) -> [usize; 4] {
        let mut k = [usize::MAX; 4];
        k[..self.as_slice().len()].copy_from_slice(self.as_slice());
        k.sort_unstable();
        k
    }
}

/// `a − b`.
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a × b`.
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a · b`.
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The Euclidean distance between two points in space.
pub fn distance3(a: [f64; 3], b: [f64; 3]) -> f64 {
    D3::length(&sub(b, a))
}

/// The signed volume of the tetrahedron (a, b, c, d): (b − a) × (c − a) · (d − a) / 6,
/// positive in the VTK_TETRA orientation.
pub fn tetrahedron_volume(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a)) / 6.0
}

/// The corner of a HEX8 at each local node, as 0/1 offsets along ξ, η, ζ.
pub(super) const HEX8_CORNERS: [[usize; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [1, 1, 1],
    [0, 1, 1],
];

/// At each local node of a HEX8, its three neighbours along the element's edges,
/// ordered so that the corner tetrahedron (node, a, b, c) is positive in a positive
/// element: its volume is det J at that corner / 6 (in units of the natural cell).
const HEX8_CORNER_TETRAHEDRA: [[usize; 3]; 8] = [
    [1, 3, 4],
    [2, 0, 5],
    [3, 1, 6],
    [0, 2, 7],
    [7, 5, 0],
    [4, 6, 1],
    [5, 7, 2],
    [6, 4, 3],
];

/// The volume of the trilinear hexahedron through corners `x` (VTK order): the
/// integral of det J by the 2 × 2 × 2 Gauss rule, exact since det J is at most
/// quadratic in each natural coordinate.
fn hexahedron_volume(x: &[[f64; 3]; 8]) -> f64 {
    let g = 1.0 / 3f64.sqrt();
    let sign = |o: usize| if o == 1 { 1.0 } else { -1.0 };
    let mut volume = 0.0;
    for point in HEX8_CORNERS {
        let xi = point.map(|o| sign(o) * g);
        // j[r][c] = ∂x_r / ∂ξ_c.
        let mut j = [[0.0; 3]; 3];
        for (corner, p) in HEX8_CORNERS.iter().zip(x) {
            let s = corner.map(sign);
            let f = [0, 1, 2].map(|c| 1.0 + s[c] * xi[c]);
            let d = [
                s[0] * f[1] * f[2] / 8.0,
                s[1] * f[0] * f[2] / 8.0,
                s[2] * f[0] * f[1] / 8.0,
            ];
            for r in 0..3 {
                for c in 0..3 {
                    j[r][c] += p[r] * d[c];
                }
            }
        }
        volume += dot(j[0], cross(j[1], j[2]));
    }
    volume
}

impl Mesh<D3> {
    /// A structured mesh of the box `[x0, x1] × [y0, y1] × [z0, z1]` with
    /// `nx × ny × nz` cells: each cell one HEX8, or six TET4 (the Kuhn–Freudenthal
    /// split along the cell's diagonal from its lowest to its highest corner, the
    /// same in every cell, so neighbouring cells share their face diagonals and the
    /// mesh is conforming).
    ///
    /// Named boundaries, by side of the box: `left` (x = x0), `right` (x = x1),
    /// `front` (y = y0), `back` (y = y1), `bottom` (z = z0) and `top` (z = z1),
    /// each a list of [`BoundaryFace`]s oriented outward, ordered by element.
    ///
    /// Node (i, j, k) has index `(k (ny + 1) + j) (nx + 1) + i`. Cell (i, j, k) is
    /// number `c = (k ny + j) nx + i`: with HEX8, element `c`; with TET4, elements
    /// `6 c .. 6 c + 6`. A zero cell count gives a mesh without elements (which
    /// [`Mesh::validate`] rejects).
    ///
    /// ```
    /// use cfe::dim::D3;
    /// use cfe::mesh::{Mesh, SolidKind};
    ///
    /// let m = Mesh::<D3>::block([0.0, 2.0], [0.0, 1.0], [0.0, 3.0], [4, 2, 6], SolidKind::Hex8);
    /// m.validate("block").unwrap();
    /// assert_eq!(m.nodes.len(), 5 * 3 * 7);
    /// assert_eq!(m.describe_elements(), "48 HEX8");
    /// let volume: f64 = (0..m.elements.len()).map(|e| m.element_volume(e)).sum();
    /// assert!((volume - 6.0).abs() < 1e-12);
    /// assert_eq!(m.boundaries["top"].len(), 4 * 2);
    ///
    /// let t = Mesh::<D3>::block([0.0, 2.0], [0.0, 1.0], [0.0, 3.0], [4, 2, 6], SolidKind::Tet4);
    /// assert_eq!(t.counts(), (6 * 48, 0));
    /// assert_eq!(t.boundaries["top"].len(), 2 * 4 * 2);
    /// ```
    ///
    /// Panics if the node count overflows `usize`.
    pub fn block(
        x: [f64; 2],
        y: [f64; 2],
        z: [f64; 2],
        cells: [usize; 3],
        kind: SolidKind,
    ) -> Mesh<D3> {
        let [nx, ny, nz] = cells;
        let count = (nx + 1)
            .checked_mul(ny + 1)
            .and_then(|c| c.checked_mul(nz + 1))
            .expect("the block's node count overflows usize");
        let node = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
        let mut nodes = Vec::with_capacity(count);
        for k in 0..=nz {
            let zk = super::lerp(z, k, nz);
            for j in 0..=ny {
                let yj = super::lerp(y, j, ny);
                for i in 0..=nx {
                    nodes.push([super::lerp(x, i, nx), yj, zk]);
                }
            }
        }
        // The paths from corner (0, 0, 0) to (1, 1, 1) of the cell, one axis at a
        // time: each is a tetrahedron of the split, with the sign of its permutation.
        const PATHS: [([usize; 3], bool); 6] = [
            ([0, 1, 2], true),
            ([0, 2, 1], false),
            ([1, 0, 2], false),
            ([1, 2, 0], true),
            ([2, 0, 1], true),
            ([2, 1, 0], false),
        ];
        let mut elements = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let corner = |o: [usize; 3]| node(i + o[0], j + o[1], k + o[2]);
                    match kind {
                        SolidKind::Hex8 => {
                            elements.push(SolidElement::Hex8(HEX8_CORNERS.map(corner)));
                        }
                        SolidKind::Tet4 => {
                            for (axes, even) in PATHS {
                                let mut o = [0; 3];
                                let mut path = [corner(o); 4];
                                for (step, &a) in axes.iter().enumerate() {
                                    o[a] = 1;
                                    path[step + 1] = corner(o);
                                }
                                if !even {
                                    path.swap(1, 2);
                                }
                                elements.push(SolidElement::Tet4(path));
                            }
                        }
                    }
                }
            }
        }
        let mut mesh = Mesh {
            nodes,
            elements,
            boundaries: BTreeMap::new(),
            node_sets: BTreeMap::new(),
        };
        // Each boundary face lies on one side: the one all its nodes are on.
        let index = |n: usize| {
            [
                n % (nx + 1),
                (n / (nx + 1)) % (ny + 1),
                n / ((nx + 1) * (ny + 1)),
            ]
        };
        let sides = [
            ("left", 0, 0),
            ("right", 0, nx),
            ("front", 1, 0),
            ("back", 1, ny),
            ("bottom", 2, 0),
            ("top", 2, nz),
        ];
        let mut named: Vec<Vec<BoundaryFace>> = vec![Vec::new(); sides.len()];
        for face in mesh.boundary_faces() {
            if let Some(s) = sides.iter().position(|&(_, axis, at)| {
                face.nodes.as_slice().iter().all(|&n| index(n)[axis] == at)
            }) {
                named[s].push(face);
            }
        }
        for ((name, _, _), faces) in sides.iter().zip(named) {
            mesh.boundaries.insert(name.to_string(), faces);
        }
        mesh
    }

    /// Every boundary face of the mesh (faces used by exactly one element), as the
    /// element that owns it gives it — outward by the right-hand rule — with its
    /// local face index, ordered by element then local face. Faces are matched by
    /// their sorted corners after one sort of all faces (O(n log n), no search).
    pub fn boundary_faces(&self) -> Vec<BoundaryFace> {
        let mut all: Vec<([usize; 4], usize, usize)> = Vec::new();
        for (e, el) in self.elements.iter().enumerate() {
            for f in 0..el.face_count() {
                all.push((el.face(f).key(), e, f));
            }
        }
        all.sort_unstable();
        let mut out: Vec<BoundaryFace> = all
            .chunk_by(|a, b| a.0 == b.0)
            .filter(|run| run.len() == 1)
            .map(|run| {
                let (_, element, face) = run[0];
                BoundaryFace {
                    nodes: self.elements[element].face(face),
                    element,
                    face,
                }
            })
            .collect();
        out.sort_unstable_by_key(|f| (f.element, f.face));
        out
    }

    /// Signed volume of element `e`: positive in the VTK orientation. A TET4's is
    /// that of its tetrahedron, a HEX8's that of the trilinear map of its corners
    /// (the integral of det J, exact).
    pub fn element_volume(&self, e: usize) -> f64 {
        let p = |n: usize| self.nodes[n];
        match self.elements[e] {
            SolidElement::Tet4([a, b, c, d]) => tetrahedron_volume(p(a), p(b), p(c), p(d)),
            SolidElement::Hex8(n) => hexahedron_volume(&n.map(p)),
        }
    }

    /// Checks the solid mesh: it has elements, node indices are in range,
    /// coordinates are finite, every element has a positive volume that is not
    /// negligible (against the cube of its longest edge h), every face of every
    /// element has a non-negligible area (against h²) and, for a quadrangle, turns
    /// the same way at each corner (it is convex), a HEX8's eight corner
    /// tetrahedra (det J at each corner) are all positive, every node is used by an
    /// element, and every named boundary face is the face of its element it says
    /// it is. Errors ([`Error::Mesh`]) name the part, the element or node, its
    /// nodes and their coordinates.
    pub fn validate(&self, part: &str) -> Result<()> {
        let err = |message: String| Error::Mesh {
            part: part.to_string(),
            message,
        };
        if self.elements.is_empty() {
            return Err(err("the mesh has no elements".into()));
        }
        if let Some((i, p)) = self
            .nodes
            .iter()
            .enumerate()
            .find(|(_, p)| p.iter().any(|c| !c.is_finite()))
        {
            return Err(err(format!("node {i} has a non-finite coordinate {p:?}")));
        }
        for e in 0..self.elements.len() {
            self.check_element(e).map_err(err)?;
        }
        if let Some(&n) = self.unused_nodes().first() {
            return Err(err(format!(
                "node {n} (at {:?}) is used by no element: a node of a solid part must belong to an element (remove it, or mesh the volume around it)",
                self.nodes[n]
            )));
        }
        for (name, faces) in &self.boundaries {
            for (i, b) in faces.iter().enumerate() {
                let matches = self.elements.get(b.element).is_some_and(|el| {
                    b.face < el.face_count() && el.face(b.face).key() == b.nodes.key()
                });
                if !matches {
                    return Err(err(format!(
                        "face {i} of boundary '{name}' (nodes {:?}) is not face {} of element {}",
                        b.nodes.as_slice(),
                        b.face,
                        b.element
                    )));
                }
            }
        }
        Ok(())
    }

    /// The geometric check of element `e` (see [`Mesh::validate`]), with the
    /// message of its failure.
    fn check_element(&self, e: usize) -> std::result::Result<(), String> {
        let el = &self.elements[e];
        let nodes = el.nodes();
        if let Some(n) = nodes.iter().find(|&&n| n >= self.nodes.len()) {
            return Err(format!(
                "element {e} refers to node {n}, but the mesh has {} nodes",
                self.nodes.len()
            ));
        }
        let x: Vec<[f64; 3]> = nodes.iter().map(|&n| self.nodes[n]).collect();
        let kind = el.kind().as_str();
        let h = el
            .edges()
            .map(|[a, b]| distance3(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max);
        let volume = self.element_volume(e);
        if volume.abs() <= 1e-10 * h * h * h {
            return Err(format!(
                "{kind} element {e} (nodes {nodes:?} at {x:?}) is degenerate: volume {volume:e}"
            ));
        }
        if volume < 0.0 {
            return Err(format!(
                "{kind} element {e} (nodes {nodes:?} at {x:?}) is inverted (its nodes are not in the Gmsh/VTK order), volume {volume:e}"
            ));
        }
        for (f, face) in el.faces().enumerate() {
            let a = face.vector_area(&self.nodes);
            let area = D3::length(&a);
            if area <= 1e-10 * h * h {
                return Err(format!(
                    "{kind} element {e} (nodes {nodes:?} at {x:?}) has a degenerate face {f} (nodes {:?}): area {area:e}",
                    face.as_slice()
                ));
            }
            let c = face.as_slice();
            for k in 0..c.len() {
                let p = self.nodes[c[k]];
                let next = sub(self.nodes[c[(k + 1) % c.len()]], p);
                let prev = sub(self.nodes[c[(k + c.len() - 1) % c.len()]], p);
                if dot(cross(next, prev), a) / area <= 1e-10 * h * h {
                    return Err(format!(
                        "{kind} element {e} (nodes {nodes:?} at {x:?}): its face {f} (nodes {c:?}) is not convex or is degenerate at node {}",
                        c[k]
                    ));
                }
            }
        }
        if let SolidElement::Hex8(n) = el {
            for (k, [a, b, c]) in HEX8_CORNER_TETRAHEDRA.iter().copied().enumerate() {
                let v = tetrahedron_volume(
                    self.nodes[n[k]],
                    self.nodes[n[a]],
                    self.nodes[n[b]],
                    self.nodes[n[c]],
                );
                if v <= 1e-10 * h * h * h {
                    return Err(format!(
                        "HEX8 element {e} (nodes {nodes:?} at {x:?}) is not convex or is degenerate at its corner {k} (node {}): the corner tetrahedron's volume is {v:e}, the trilinear map folds there",
                        n[k]
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    const KINDS: [SolidKind; 2] = [SolidKind::Tet4, SolidKind::Hex8];
    /// The test box [0, 2] × [0, 1.5] × [0, 1].
    const BOX: [[f64; 2]; 3] = [[0.0, 2.0], [0.0, 1.5], [0.0, 1.0]];
    const BOX_VOLUME: f64 = 3.0;
    /// Each side's name, axis, the coordinate it lies at and its area.
    const SIDES: [(&str, usize, f64, f64); 6] = [
        ("left", 0, 0.0, 1.5),
        ("right", 0, 2.0, 1.5),
        ("front", 1, 0.0, 2.0),
        ("back", 1, 1.5, 2.0),
        ("bottom", 2, 0.0, 3.0),
        ("top", 2, 1.0, 3.0),
    ];

    fn block(kind: SolidKind, cells: [usize; 3]) -> Mesh<D3> {
        Mesh::<D3>::block(BOX[0], BOX[1], BOX[2], cells, kind)
    }

    /// The test box with its interior nodes moved off the grid by a deterministic
    /// pattern (up to 0.06 against cells of about 0.5): no HEX8 is a
    /// parallelepiped and the inner faces are not planar; the boundary is the box's.
    fn distorted(kind: SolidKind) -> Mesh<D3> {
        let mut m = block(kind, [3, 3, 2]);
        for (n, p) in m.nodes.iter_mut().enumerate() {
            let inside = (0..3).all(|c| p[c] > BOX[c][0] + 1e-9 && p[c] < BOX[c][1] - 1e-9);
            if inside {
                for (c, x) in p.iter_mut().enumerate() {
                    *x += 0.06 * ((n * 7 + c * 3) as f64).sin();
                }
            }
        }
        m.validate("distorted").unwrap();
        m
    }

    fn total_volume(m: &Mesh<D3>) -> f64 {
        (0..m.elements.len()).map(|e| m.element_volume(e)).sum()
    }

    fn sorted(mut faces: Vec<BoundaryFace>) -> Vec<BoundaryFace> {
        faces.sort_unstable();
        faces
    }

    /// The box mesher: the expected node and element counts, every element
    /// positive, and the element volumes add up to the box's volume for TET4 and
    /// HEX8, on the structured and on the distorted mesh.
    #[test]
    fn block_volume_is_the_sum_of_element_volumes() {
        for kind in KINDS {
            let m = block(kind, [4, 3, 2]);
            m.validate("box").unwrap();
            assert_eq!(m.nodes.len(), 5 * 4 * 3);
            let per_cell = if kind == SolidKind::Tet4 { 6 } else { 1 };
            assert_eq!(m.elements.len(), per_cell * 24);
            assert!((0..m.elements.len()).all(|e| m.element_volume(e) > 0.0));
            assert!((total_volume(&m) - BOX_VOLUME).abs() < 1e-12, "{kind:?}");
            let d = distorted(kind);
            assert!((total_volume(&d) - BOX_VOLUME).abs() < 1e-12, "{kind:?}");
        }
    }

    /// Each named side is made of boundary faces lying on it whose areas add up to
    /// the side's area and whose unit normals are the outward axis; the sides
    /// together are exactly the mesh's boundary faces, each the face of its element
    /// it says it is.
    #[test]
    fn block_sides_have_their_area_and_outward_normals() {
        for kind in KINDS {
            let m = distorted(kind);
            let names: Vec<&String> = m.boundaries.keys().collect();
            assert_eq!(names, ["back", "bottom", "front", "left", "right", "top"]);
            for (name, axis, at, area) in SIDES {
                let faces = &m.boundaries[name];
                let mut sum = 0.0;
                for f in faces {
                    assert_eq!(m.elements[f.element].face(f.face), f.nodes);
                    assert!(f.nodes.as_slice().iter().all(|&n| m.nodes[n][axis] == at));
                    let a = f.nodes.vector_area(&m.nodes);
                    let l = D3::length(&a);
                    let outward = if at > 0.0 { 1.0 } else { -1.0 };
                    for c in 0..3 {
                        let want = if c == axis { outward } else { 0.0 };
                        assert!((a[c] / l - want).abs() < 1e-14, "{kind:?} {name}: {a:?}");
                    }
                    sum += l;
                }
                assert!((sum - area).abs() < 1e-13, "{kind:?} {name}: {sum}");
            }
            let named = sorted(m.boundaries.values().flatten().copied().collect());
            assert_eq!(named, sorted(m.boundary_faces()), "{kind:?}");
        }
    }

    /// The boundary is a closed oriented surface: every directed edge of a
    /// boundary face is run once, and its reverse once by another face (two faces
    /// per edge, opposite ways), the Euler characteristic V − E + F is 2 (a
    /// sphere's), the vector areas cancel, and the divergence theorem over the
    /// faces, V = ⅓ Σ x̄·A, gives the box's volume.
    #[test]
    fn block_boundary_is_watertight() {
        for kind in KINDS {
            let m = distorted(kind);
            let faces = m.boundary_faces();
            let mut directed: HashMap<[usize; 2], usize> = HashMap::new();
            let mut vertices = std::collections::HashSet::new();
            let mut total = [0.0; 3];
            let mut flux = 0.0;
            for f in &faces {
                let c = f.nodes.as_slice();
                for k in 0..c.len() {
                    *directed.entry([c[k], c[(k + 1) % c.len()]]).or_default() += 1;
                    vertices.insert(c[k]);
                }
                let a = f.nodes.vector_area(&m.nodes);
                let mean: [f64; 3] = std::array::from_fn(|d| {
                    c.iter().map(|&n| m.nodes[n][d]).sum::<f64>() / c.len() as f64
                });
                flux += dot(mean, a) / 3.0;
                for d in 0..3 {
                    total[d] += a[d];
                }
            }
            for (&[a, b], &count) in &directed {
                assert_eq!(count, 1, "{kind:?}: edge {a}→{b}");
                assert_eq!(directed.get(&[b, a]), Some(&1), "{kind:?}: edge {a}→{b}");
            }
            let edges = directed.len() / 2;
            let euler = vertices.len() as i64 - edges as i64 + faces.len() as i64;
            assert_eq!(euler, 2, "{kind:?}");
            assert!(total.iter().all(|t| t.abs() < 1e-13), "{total:?}");
            assert!((flux - BOX_VOLUME).abs() < 1e-12, "{kind:?}: {flux}");
        }
    }

    /// The boundary faces are exactly the faces one element has, counted by an
    /// independent map over sorted corner sets, as the element gives them, on meshes
    /// with a hole (some elements removed).
    #[test]
    fn boundary_faces_match_a_counting_map() {
        for kind in KINDS {
            let mut m = block(kind, [3, 2, 2]);
            let n = m.elements.len();
            m.elements.remove(n / 2);
            m.elements.remove(n / 3);
            let mut count: BTreeMap<Vec<usize>, Vec<BoundaryFace>> = BTreeMap::new();
            for (e, el) in m.elements.iter().enumerate() {
                for f in 0..el.face_count() {
                    let nodes = el.face(f);
                    let mut key = nodes.as_slice().to_vec();
                    key.sort_unstable();
                    count.entry(key).or_default().push(BoundaryFace {
                        nodes,
                        element: e,
                        face: f,
                    });
                }
            }
            let expected: Vec<BoundaryFace> = count
                .into_values()
                .filter(|v| v.len() == 1)
                .map(|v| v[0])
                .collect();
            let got = m.boundary_faces();
            let outer: usize = m.boundaries.values().map(Vec::len).sum();
            assert!(got.len() > outer, "{kind:?}: the hole adds faces");
            assert_eq!(sorted(got), sorted(expected), "{kind:?}");
        }
    }

    /// Counts, text and the longest edge: a HEX8 cell's longest edge is its
    /// longest side, a Kuhn split's the cell's main diagonal.
    #[test]
    fn counts_description_and_longest_edge() {
        let h = block(SolidKind::Hex8, [4, 3, 2]);
        assert_eq!(h.counts(), (0, 24));
        assert_eq!(h.describe_elements(), "24 HEX8");
        assert!((h.max_edge_length() - 0.5).abs() < 1e-15);
        let t = block(SolidKind::Tet4, [4, 3, 2]);
        assert_eq!(t.describe_elements(), "144 TET4");
        assert!((t.max_edge_length() - 0.75f64.sqrt()).abs() < 1e-15);
        let mut mixed = h.clone();
        mixed.elements.push(t.elements[0]);
        assert_eq!(mixed.describe_elements(), "1 TET4 + 24 HEX8");
    }

    fn mesh_error(m: &Mesh<D3>) -> String {
        match m.validate("solid") {
            Err(Error::Mesh { part, message }) => {
                assert_eq!(part, "solid");
                message
            }
            other => panic!("expected a mesh error, got {other:?}"),
        }
    }

    /// Validation rejects, each with a typed mesh error naming the element or
    /// node: an inverted TET4 and HEX8, a degenerate TET4, a HEX8 folded at one
    /// corner (positive volume, negative det J there), a node no element uses,
    /// and a named face that is not the face of its element it says.
    #[test]
    fn validate_rejects_bad_solid_meshes() {
        let mut t = block(SolidKind::Tet4, [1, 1, 1]);
        let SolidElement::Tet4([a, b, c, d]) = t.elements[3] else {
            unreachable!()
        };
        t.elements[3] = SolidElement::Tet4([a, c, b, d]);
        let msg = mesh_error(&t);
        assert!(
            msg.contains("TET4 element 3") && msg.contains("inverted"),
            "{msg}"
        );
        t.elements[3] = SolidElement::Tet4([a, b, c, a]);
        let msg = mesh_error(&t);
        assert!(
            msg.contains("TET4 element 3") && msg.contains("degenerate"),
            "{msg}"
        );

        let mut h = block(SolidKind::Hex8, [1, 1, 1]);
        let SolidElement::Hex8(n) = h.elements[0] else {
            unreachable!()
        };
        // Top and bottom swapped: a mirror image.
        h.elements[0] = SolidElement::Hex8([n[4], n[5], n[6], n[7], n[0], n[1], n[2], n[3]]);
        let msg = mesh_error(&h);
        assert!(
            msg.contains("HEX8 element 0") && msg.contains("inverted"),
            "{msg}"
        );
        // Node 6 at (1, 1, 1) pulled through to (0.2, 0.2, 0.2): the corner folds.
        h.elements[0] = SolidElement::Hex8(n);
        h.nodes[n[6]] = [0.2, 0.2, 0.2];
        assert!(h.element_volume(0) > 0.0);
        let msg = mesh_error(&h);
        assert!(
            msg.contains("HEX8 element 0") && msg.contains("not convex"),
            "{msg}"
        );

        let mut u = block(SolidKind::Hex8, [2, 1, 1]);
        u.nodes.push([5.0, 5.0, 5.0]);
        let msg = mesh_error(&u);
        assert!(
            msg.contains("node 12") && msg.contains("used by no element"),
            "{msg}"
        );

        let mut w = block(SolidKind::Hex8, [2, 1, 1]);
        w.boundaries.get_mut("top").unwrap()[1].face = 4;
        let msg = mesh_error(&w);
        assert!(
            msg.contains("boundary 'top'") && msg.contains("is not face 4"),
            "{msg}"
        );
    }

    /// The local faces are outward: on the unit TET4 and HEX8 each face's vector
    /// area points away from the element's centroid, and the faces' areas are
    /// the unit shapes' (½, ½, ½, √3/2 and six of 1).
    #[test]
    fn local_faces_point_outward() {
        let tet = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let hex: Vec<[f64; 3]> = HEX8_CORNERS.iter().map(|o| o.map(|v| v as f64)).collect();
        for (x, el) in [
            (tet.to_vec(), SolidElement::Tet4([0, 1, 2, 3])),
            (hex, SolidElement::Hex8([0, 1, 2, 3, 4, 5, 6, 7])),
        ] {
            let centroid: [f64; 3] =
                std::array::from_fn(|c| x.iter().map(|p| p[c]).sum::<f64>() / x.len() as f64);
            let mut areas = Vec::new();
            for face in el.faces() {
                let a = face.vector_area(&x);
                let p = x[face.as_slice()[0]];
                assert!(dot(a, sub(p, centroid)) > 0.0, "{face:?}");
                areas.push(D3::length(&a));
            }
            let want: &[f64] = match el.kind() {
                SolidKind::Tet4 => &[0.5, 0.5, 0.5, 0.75f64.sqrt()],
                SolidKind::Hex8 => &[1.0; 6],
            };
            for (a, w) in areas.iter().zip(want) {
                assert!((a - w).abs() < 1e-15, "{areas:?}");
            }
        }
    }
}
