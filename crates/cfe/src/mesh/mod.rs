//! Mesh: the nodes, elements (linear triangles T3 and bilinear quadrilaterals Q4,
//! possibly mixed) and named boundaries of one part, the built-in structured
//! rectangle mesher, and the geometric checks (inverted, degenerate or non-convex
//! elements) every mesh passes before it is used. [`gmsh`] reads Gmsh meshes;
//! [`Mesh::refined`] (in `refine`) subdivides any mesh uniformly.
//!
//! A mesh is of one dimension: [`Mesh<D>`](Mesh), whose nodes are `D::Vector`, whose
//! cells are [`MeshDim::Cell`] and whose named boundaries are lists of
//! [`MeshDim::Face`]. The plane mesh `Mesh<D2>` (the default, plain `Mesh`) has
//! [`Element`]s (T3, Q4) and [`BoundaryEdge`]s; the solid mesh `Mesh<D3>` has
//! [`SolidElement`]s (TET4, HEX8) and [`BoundaryFace`]s (module `solid`).

mod arrays;
pub mod gmsh;
pub mod input_file;
mod refine;
mod refine_solid;
mod solid;

pub use arrays::BoundarySelection;
pub use refine::{CURVED_TURN, CurvedBoundary};
pub use solid::{
    BoundaryFace, FaceNodes, HEX8_EDGES, HEX8_FACES, SolidElement, SolidKind, TET4_EDGES,
    TET4_FACES, distance3, tetrahedron_volume,
};

use crate::dim::{D2, Dim};
use crate::error::{Error, Result};
use std::collections::BTreeMap;
use std::fmt::Debug;

/// A cell of a mesh (an element, by its corner nodes): what the dimension-free
/// parts of [`Mesh`] read of it.
pub trait MeshCell: Copy + Debug + PartialEq + Send + Sync + 'static {
    /// Its nodes (local numbering of the part), in the kind's order.
    fn nodes(&self) -> &[usize];
    /// The name of its kind as in messages (`T3`, `Q4`, `TET4`, `HEX8`).
    fn kind_name(&self) -> &'static str;
    /// Whether it is the dimension's simplex (T3, TET4) rather than its
    /// tensor-product cell (Q4, HEX8).
    fn is_simplex(&self) -> bool;
    /// Its edges as (start, end) node pairs.
    fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_;
}

/// A boundary facet of a mesh (an edge in 2D, a face in 3D), oriented outward,
/// with the element that owns it.
pub trait MeshFace: Copy + Debug + PartialEq + Send + Sync + 'static {
    /// Its corner nodes, ordered so the outward normal follows (in 2D the part on
    /// the left; in 3D the right-hand rule).
    fn nodes(&self) -> &[usize];
    /// The element it belongs to.
    fn element(&self) -> usize;
}

/// A dimension a part can be meshed in: the [`Dim`] and the kinds of its cells
/// and boundary facets. Declared here rather than in `dim` because the cell
/// enums are the mesh's (`dim` imports nothing of the crate).
pub trait MeshDim: Dim {
    /// The element enum of the dimension ([`Element`] in 2D, [`SolidElement`]
    /// in 3D).
    type Cell: MeshCell;
    /// A boundary facet ([`BoundaryEdge`] in 2D, [`BoundaryFace`] in 3D).
    type Face: MeshFace;
    /// The names of its two cell kinds as in messages: the simplex's, then the
    /// tensor-product cell's (`T3`, `Q4` in 2D; `TET4`, `HEX8` in 3D).
    const KIND_NAMES: [&'static str; 2];
}

/// Plane meshes: T3/Q4 elements, boundaries of edges.
impl MeshDim for D2 {
    type Cell = Element;
    type Face = BoundaryEdge;
    const KIND_NAMES: [&'static str; 2] = ["T3", "Q4"];
}

/// The element types a part may be meshed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// 3-node linear triangle (constant strain).
    T3,
    /// 4-node bilinear quadrilateral (2×2 Gauss integration).
    Q4,
}

/// Which diagonal splits each cell of a structured T3 mesh.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Diagonal {
    /// From the cell's lower-left to its upper-right corner (`/`, the default).
    #[default]
    Rising,
    /// From the cell's upper-left to its lower-right corner (`\`).
    Falling,
}

impl ElementKind {
    /// Name as in the problem file and in messages (`T3`, `Q4`).
    pub fn as_str(self) -> &'static str {
        match self {
            ElementKind::T3 => "T3",
            ElementKind::Q4 => "Q4",
        }
    }
}

/// One element of a part: its corner nodes (local numbering of the part),
/// counter-clockwise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    /// A linear triangle.
    T3([usize; 3]),
    /// A bilinear quadrilateral, corners in order around it.
    Q4([usize; 4]),
}

impl Element {
    /// The element's nodes, counter-clockwise.
    pub fn nodes(&self) -> &[usize] {
        match self {
            Element::T3(n) => n,
            Element::Q4(n) => n,
        }
    }

    /// Its type.
    pub fn kind(&self) -> ElementKind {
        match self {
            Element::T3(_) => ElementKind::T3,
            Element::Q4(_) => ElementKind::Q4,
        }
    }

    /// Its edges as (start, end) node pairs, counter-clockwise: the part lies on the
    /// left of each.
    pub fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        let n = self.nodes();
        (0..n.len()).map(move |k| [n[k], n[(k + 1) % n.len()]])
    }
}

impl MeshCell for Element {
    fn nodes(&self) -> &[usize] {
        Element::nodes(self)
    }

    fn kind_name(&self) -> &'static str {
        self.kind().as_str()
    }

    fn is_simplex(&self) -> bool {
        self.kind() == ElementKind::T3
    }

    fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        Element::edges(self)
    }
}

/// A boundary edge of a part: its two nodes, ordered so that the part lies on the
/// left (counter-clockwise traversal; the outward normal is the edge direction turned
/// −90°), and the element that owns it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryEdge {
    /// Start and end node (local numbering of the part).
    pub nodes: [usize; 2],
    /// The element the edge belongs to.
    pub element: usize,
}

impl MeshFace for BoundaryEdge {
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    fn element(&self) -> usize {
        self.element
    }
}

/// The edges that occur exactly once among `edges()` (each a pair of nodes as
/// given, with a tag), as given and with their tags, ordered by their lower then
/// upper node: each edge is filed under its lower node by a counting sort and
/// each node's few edges are sorted (O(edges + nodes), no sort of all edges).
/// `edges` is called twice (to count, then to file). The boundary of a mesh
/// ([`Mesh::boundary_edges`]) and the outline of a triangulation are these.
pub fn edges_used_once<T, I>(edges: impl Fn() -> I) -> Vec<([usize; 2], T)>
where
    T: Copy + Ord + Default,
    I: Iterator<Item = ([usize; 2], T)>,
{
    let size = edges().map(|([a, b], _)| a.max(b) + 1).max().unwrap_or(0);
    // The edges filed under node `lo` are bucket[start[lo]..start[lo + 1]]:
    // (upper node, whether given lower → upper, tag).
    let mut start = vec![0usize; size + 1];
    for ([a, b], _) in edges() {
        start[a.min(b) + 1] += 1;
    }
    for i in 0..size {
        start[i + 1] += start[i];
    }
    let mut bucket = vec![(0usize, false, T::default()); start[size]];
    let mut next = start[..size].to_vec();
    for ([a, b], tag) in edges() {
        let lo = a.min(b);
        bucket[next[lo]] = (a.max(b), a < b, tag);
        next[lo] += 1;
    }
    drop(next);
    let mut once = Vec::new();
    for lo in 0..size {
        let filed = &mut bucket[start[lo]..start[lo + 1]];
        filed.sort_unstable();
        for (i, &(hi, forward, tag)) in filed.iter().enumerate() {
            let repeated =
                (i > 0 && filed[i - 1].0 == hi) || filed.get(i + 1).is_some_and(|f| f.0 == hi);
            if !repeated {
                once.push((if forward { [lo, hi] } else { [hi, lo] }, tag));
            }
        }
    }
    once
}

/// The mesh of one part in dimension `D` (plane by default): node coordinates,
/// elements, and named boundaries as lists of boundary facets. In 2D the elements
/// are T3/Q4 counter-clockwise and the facets edges; in 3D TET4/HEX8 of positive
/// volume and the facets faces.
#[derive(Debug, Clone)]
pub struct Mesh<D: MeshDim = D2> {
    /// Node coordinates ((x, y) in 2D, (x, y, z) in 3D).
    pub nodes: Vec<D::Vector>,
    /// Elements (T3 and Q4, or TET4 and HEX8, may be mixed), nodes in their kind's
    /// order (counter-clockwise in 2D).
    pub elements: Vec<D::Cell>,
    /// Named boundaries (e.g. `left`, `right`, `bottom`, `top`).
    pub boundaries: BTreeMap<String, Vec<D::Face>>,
    /// Named node sets (e.g. a Gmsh file's physical points and, in 3D, its
    /// physical curves): nodes a support or a point force may name where a
    /// boundary is named. Empty for the built-in meshers.
    pub node_sets: BTreeMap<String, NodeSet>,
}

/// A named set of nodes of a part: its nodes and the mesh edges (segments of a
/// Gmsh curve) along which refinement adds the new nodes to the set.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NodeSet {
    /// The nodes, ascending, each once.
    pub nodes: Vec<usize>,
    /// Element edges between nodes of the set (each a node pair); `--refine`
    /// puts the nodes it makes on them into the set.
    pub edges: Vec<[usize; 2]>,
}

impl NodeSet {
    /// The set of `nodes` (sorted, each once) with `edges`.
    pub fn new(mut nodes: Vec<usize>, edges: Vec<[usize; 2]>) -> NodeSet {
        nodes.sort_unstable();
        nodes.dedup();
        NodeSet { nodes, edges }
    }
}

/// The empty mesh: no node, no element, no boundary.
impl<D: MeshDim> Default for Mesh<D> {
    fn default() -> Self {
        Mesh {
            nodes: Vec::new(),
            elements: Vec::new(),
            boundaries: BTreeMap::new(),
            node_sets: BTreeMap::new(),
        }
    }
}

/// What reads the same in every dimension.
impl<D: MeshDim> Mesh<D> {
    /// The nodes of a named boundary, each once, in traversal order.
    pub fn boundary_nodes(&self, name: &str) -> Option<Vec<usize>> {
        let faces = self.boundaries.get(name)?;
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        for f in faces {
            for &n in f.nodes() {
                if seen.insert(n) {
                    out.push(n);
                }
            }
        }
        Some(out)
    }

    /// The corner coordinates of element `e`, in its kind's node order
    /// (counter-clockwise in 2D).
    pub fn coordinates(&self, e: usize) -> Vec<D::Vector> {
        self.elements[e]
            .nodes()
            .iter()
            .map(|&n| self.nodes[n])
            .collect()
    }

    /// The nodes no element uses, in increasing order.
    pub fn unused_nodes(&self) -> Vec<usize> {
        let mut used = vec![false; self.nodes.len()];
        for el in &self.elements {
            for &n in el.nodes() {
                if let Some(u) = used.get_mut(n) {
                    *u = true;
                }
            }
        }
        (0..used.len()).filter(|&n| !used[n]).collect()
    }

    /// How many elements of each kind the mesh has: (simplices, tensor-product
    /// cells), i.e. (T3, Q4) in 2D and (TET4, HEX8) in 3D.
    pub fn counts(&self) -> (usize, usize) {
        let simplices = self.elements.iter().filter(|e| e.is_simplex()).count();
        (simplices, self.elements.len() - simplices)
    }

    /// The element kinds as text, e.g. `480 T3`, `120 T3 + 36 Q4` or `48 HEX8`.
    pub fn describe_elements(&self) -> String {
        let [simplex, cell] = D::KIND_NAMES;
        match self.counts() {
            (s, 0) => format!("{s} {simplex}"),
            (0, c) => format!("{c} {cell}"),
            (s, c) => format!("{s} {simplex} + {c} {cell}"),
        }
    }

    /// The length of the longest element edge: the mesh's largest element size.
    pub fn max_edge_length(&self) -> f64 {
        self.elements
            .iter()
            .flat_map(|el| el.edges())
            .map(|[a, b]| distance::<D>(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max)
    }
}

/// The Euclidean distance `|b − a|` between two points of dimension `D`
/// ([`Dim::length`] of the difference: [`dist`] in 2D, [`distance3`] in 3D, to
/// the bit).
fn distance<D: Dim>(a: D::Vector, b: D::Vector) -> f64 {
    let mut d = b;
    for (d, a) in d.as_mut().iter_mut().zip(a.as_ref()) {
        *d -= a;
    }
    D::length(d.as_ref())
}

impl Mesh {
    /// A structured mesh of the rectangle `[x0, x1] × [y0, y1]` with `nx × ny` cells:
    /// each cell one Q4, or two T3 split along its rising diagonal. Boundaries
    /// `left`, `right`, `bottom` and `top` are named.
    ///
    /// Node (i, j) has index `j (nx + 1) + i`. With T3, cell (i, j) gives elements
    /// `2 (j nx + i)` (below the diagonal) and `2 (j nx + i) + 1` (above it); with Q4,
    /// element `j nx + i`.
    pub fn rectangle(x: [f64; 2], y: [f64; 2], cells: [usize; 2], kind: ElementKind) -> Mesh {
        Mesh::rectangle_split(x, y, cells, kind, Diagonal::Rising)
    }

    /// [`Mesh::rectangle`] with T3 cells split along the chosen diagonal. With the
    /// falling diagonal, cell (i, j) gives elements `2 (j nx + i)` (below it, owning
    /// the cell's lower and left edges) and `2 (j nx + i) + 1` (above it, owning the
    /// upper and right edges). Q4 meshes ignore the diagonal.
    pub fn rectangle_split(
        x: [f64; 2],
        y: [f64; 2],
        cells: [usize; 2],
        kind: ElementKind,
        diagonal: Diagonal,
    ) -> Mesh {
        let [nx, ny] = cells;
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            let yj = lerp(y, j, ny);
            for i in 0..=nx {
                nodes.push([lerp(x, i, nx), yj]);
            }
        }
        let per_cell = match kind {
            ElementKind::T3 => 2,
            ElementKind::Q4 => 1,
        };
        let mut elements = Vec::with_capacity(per_cell * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (n00, n10, n11, n01) = (
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                );
                match (kind, diagonal) {
                    (ElementKind::T3, Diagonal::Rising) => {
                        elements.push(Element::T3([n00, n10, n11]));
                        elements.push(Element::T3([n00, n11, n01]));
                    }
                    (ElementKind::T3, Diagonal::Falling) => {
                        elements.push(Element::T3([n00, n10, n01]));
                        elements.push(Element::T3([n10, n11, n01]));
                    }
                    (ElementKind::Q4, _) => elements.push(Element::Q4([n00, n10, n11, n01])),
                }
            }
        }
        // The element of cell (i, j) that owns its lower and right edges, and the one
        // that owns its upper and left edges.
        let lower = |i: usize, j: usize| per_cell * (j * nx + i);
        let upper = |i: usize, j: usize| per_cell * (j * nx + i) + per_cell - 1;
        // The owners of the right and left edges swap with a falling diagonal.
        let falling = kind == ElementKind::T3 && diagonal == Diagonal::Falling;
        let right_owner = |i: usize, j: usize| if falling { upper(i, j) } else { lower(i, j) };
        let left_owner = |i: usize, j: usize| if falling { lower(i, j) } else { upper(i, j) };
        let mut boundaries = BTreeMap::new();
        let edge = |a, b, element| BoundaryEdge {
            nodes: [a, b],
            element,
        };
        boundaries.insert(
            "bottom".to_string(),
            (0..nx)
                .map(|i| edge(node(i, 0), node(i + 1, 0), lower(i, 0)))
                .collect(),
        );
        boundaries.insert(
            "right".to_string(),
            (0..ny)
                .map(|j| edge(node(nx, j), node(nx, j + 1), right_owner(nx - 1, j)))
                .collect(),
        );
        boundaries.insert(
            "top".to_string(),
            (0..nx)
                .rev()
                .map(|i| edge(node(i + 1, ny), node(i, ny), upper(i, ny - 1)))
                .collect(),
        );
        boundaries.insert(
            "left".to_string(),
            (0..ny)
                .rev()
                .map(|j| edge(node(0, j + 1), node(0, j), left_owner(0, j)))
                .collect(),
        );
        Mesh {
            nodes,
            elements,
            boundaries,
            node_sets: BTreeMap::new(),
        }
    }

    /// A structured mesh of the annular sector around `center` with radii
    /// `r = [r0, r1]` (0 < r0 < r1) and polar angles `theta = [θ0, θ1]` in degrees
    /// (θ0 < θ1 ≤ θ0 + 360), `nr × nt` cells (radial × circumferential): each cell
    /// one Q4, or two T3. Nodes lie exactly on the circles, so the boundary arcs
    /// are polygons inscribed in them. Boundaries `inner` (r = r0), `outer`
    /// (r = r1), and, unless the sector is a full ring (θ1 = θ0 + 360, whose seam
    /// nodes are shared), `start` (θ = θ0) and `end` (θ = θ1).
    ///
    /// Node (i, j) (i along r, j along θ) has index `j (nr + 1) + i`.
    pub fn annulus(
        center: [f64; 2],
        r: [f64; 2],
        theta: [f64; 2],
        cells: [usize; 2],
        kind: ElementKind,
    ) -> Mesh {
        let [nr, nt] = cells;
        // The rectangle mesher in (r, θ), mapped: its bottom, right, top and left
        // sides become start, outer, end and inner, with the same orientation
        // (r then θ is counter-clockwise).
        let mut m = Mesh::rectangle(r, theta, cells, kind);
        for p in &mut m.nodes {
            let t = p[1].to_radians();
            *p = [center[0] + p[0] * t.cos(), center[1] + p[0] * t.sin()];
        }
        let mut rename = |from: &str, to: &str| {
            let edges = m.boundaries.remove(from).unwrap_or_default();
            m.boundaries.insert(to.to_string(), edges);
        };
        rename("bottom", "start");
        rename("right", "outer");
        rename("top", "end");
        rename("left", "inner");
        let full = (theta[1] - theta[0] - 360.0).abs() <= 1e-12 * 360.0;
        if full {
            // The last ring of nodes (j = nt) repeats the first (j = 0).
            let seam = nt * (nr + 1);
            let wrap = |n: usize| if n >= seam { n - seam } else { n };
            for el in &mut m.elements {
                match el {
                    Element::T3(n) => *n = n.map(wrap),
                    Element::Q4(n) => *n = n.map(wrap),
                }
            }
            for edges in m.boundaries.values_mut() {
                for e in edges.iter_mut() {
                    e.nodes = e.nodes.map(wrap);
                }
            }
            m.nodes.truncate(seam);
            m.boundaries.remove("start");
            m.boundaries.remove("end");
        }
        m
    }

    /// Every boundary edge of the mesh (edges used by exactly one element), oriented
    /// counter-clockwise with respect to the part, in a deterministic order.
    pub fn boundary_edges(&self) -> Vec<BoundaryEdge> {
        let mut edges: Vec<BoundaryEdge> = edges_used_once(|| {
            self.elements
                .iter()
                .enumerate()
                .flat_map(|(e, el)| el.edges().map(move |ab| (ab, e)))
        })
        .into_iter()
        .map(|(nodes, element)| BoundaryEdge { nodes, element })
        .collect();
        edges.sort_by_key(|e| (e.element, e.nodes));
        edges
    }

    /// Signed area of element `e` (positive when counter-clockwise; for a Q4, the
    /// area of the quadrilateral through its corners, which the bilinear map fills
    /// exactly).
    pub fn element_area(&self, e: usize) -> f64 {
        let p = |n: usize| self.nodes[n];
        match self.elements[e] {
            Element::T3([a, b, c]) => {
                let (a, b, c) = (p(a), p(b), p(c));
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
            }
            // Half the cross product of the diagonals.
            Element::Q4([a, b, c, d]) => {
                let (a, b, c, d) = (p(a), p(b), p(c), p(d));
                0.5 * ((c[0] - a[0]) * (d[1] - b[1]) - (d[0] - b[0]) * (c[1] - a[1]))
            }
        }
    }

    /// Checks that node indices are in range, coordinates are finite and every
    /// element is counter-clockwise and not degenerate: a triangle's area, and each
    /// corner's cross product of a quadrilateral's two edges there (4 det J at that
    /// corner: a quadrilateral must be convex), must not be negligible against the
    /// square of the element's longest edge. Errors name the part, the element, its
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
            .find(|(_, p)| !p[0].is_finite() || !p[1].is_finite())
        {
            return Err(err(format!("node {i} has a non-finite coordinate {p:?}")));
        }
        for e in 0..self.elements.len() {
            self.check_element(e).map_err(err)?;
        }
        Ok(())
    }

    /// Checks that the elements tile the part — no overlap, no fold — for a mesh
    /// whose elements are each valid and counter-clockwise: every edge is used by at
    /// most two elements, which run along it in opposite directions (one on each
    /// side), the elements' areas add up to the area their boundary encloses, and no
    /// two elements' interiors intersect.
    /// A mesh read from a file can break this (a node swapped between elements)
    /// while every element on its own looks fine.
    pub fn check_tiling(&self) -> std::result::Result<(), Tiling> {
        // Each edge by its sorted node pair: its uses (element, direction).
        let mut edges: Vec<(usize, usize, usize, bool)> = self
            .elements
            .iter()
            .enumerate()
            .flat_map(|(e, el)| el.edges().map(move |[a, b]| (a.min(b), a.max(b), e, a < b)))
            .collect();
        edges.sort_unstable();
        let mut enclosed = 0.0;
        for run in edges.chunk_by(|p, q| (p.0, p.1) == (q.0, q.1)) {
            let (a, b) = (run[0].0, run[0].1);
            match run {
                [(_, _, _, forward)] => {
                    let (p, q) = if *forward { (a, b) } else { (b, a) };
                    let (p, q) = (self.nodes[p], self.nodes[q]);
                    enclosed += 0.5 * (p[0] * q[1] - q[0] * p[1]);
                }
                [(_, _, e, f), (_, _, g, h)] if f == h => {
                    return Err(Tiling::SameSide {
                        edge: [a, b],
                        elements: [*e, *g],
                    });
                }
                [_, _] => {}
                _ => {
                    return Err(Tiling::Shared {
                        edge: [a, b],
                        elements: run.iter().map(|u| u.2).collect(),
                    });
                }
            }
        }
        // Elements that share nodes and still overlap show as more area than the
        // boundary encloses; an element lying loose on others has a boundary of its
        // own, so the elements' bounding boxes are searched as well.
        let total: f64 = (0..self.elements.len()).map(|e| self.element_area(e)).sum();
        let pairs = self.overlapping_pairs(10);
        if pairs.is_empty() && (total - enclosed).abs() <= 1e-9 * total.abs().max(enclosed.abs()) {
            return Ok(());
        }
        Err(Tiling::Overlap {
            area: total,
            enclosed,
            pairs,
        })
    }

    /// Up to `limit` pairs of elements whose interiors overlap (bounding boxes in an
    /// R-tree, then a separating-axis test of the two convex polygons).
    fn overlapping_pairs(&self, limit: usize) -> Vec<[usize; 2]> {
        use rstar::{AABB, RTree, primitives::GeomWithData, primitives::Rectangle};
        let corners = |e: usize| -> Vec<[f64; 2]> {
            self.elements[e]
                .nodes()
                .iter()
                .map(|&n| self.nodes[n])
                .collect()
        };
        let boxes: Vec<GeomWithData<Rectangle<[f64; 2]>, usize>> = (0..self.elements.len())
            .map(|e| {
                let x = corners(e);
                let lo = x
                    .iter()
                    .fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
                let hi = x.iter().fold([f64::NEG_INFINITY; 2], |m, p| {
                    [m[0].max(p[0]), m[1].max(p[1])]
                });
                GeomWithData::new(Rectangle::from_corners(lo, hi), e)
            })
            .collect();
        let tree = RTree::bulk_load(boxes.clone());
        let mut out = Vec::new();
        for b in &boxes {
            let e = b.data;
            let env = AABB::from_corners(b.geom().lower(), b.geom().upper());
            for other in tree.locate_in_envelope_intersecting(env) {
                let f = other.data;
                if f > e && interiors_overlap(&corners(e), &corners(f)) {
                    out.push([e, f]);
                    if out.len() == limit {
                        return out;
                    }
                }
            }
        }
        out
    }

    /// Checks only the elements that contain one of `nodes` (after those nodes
    /// moved), as [`Mesh::validate`] does for all.
    pub fn validate_around(&self, part: &str, nodes: &[usize]) -> Result<()> {
        let mut moved = vec![false; self.nodes.len()];
        for &n in nodes {
            if let Some(m) = moved.get_mut(n) {
                *m = true;
            }
        }
        for (e, el) in self.elements.iter().enumerate() {
            if el
                .nodes()
                .iter()
                .any(|&n| moved.get(n).copied().unwrap_or(false))
            {
                self.check_element(e).map_err(|message| Error::Mesh {
                    part: part.to_string(),
                    message,
                })?;
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
        let mut corners = [[0.0; 2]; 4];
        for (c, &n) in corners.iter_mut().zip(nodes) {
            *c = self.nodes[n];
        }
        let x = &corners[..nodes.len()];
        let h = el
            .edges()
            .map(|[a, b]| dist(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max);
        let kind = el.kind().as_str();
        let area = self.element_area(e);
        if area.abs() <= 1e-10 * h * h {
            return Err(format!(
                "{kind} element {e} (nodes {nodes:?} at {x:?}) is degenerate: area {area:e}"
            ));
        }
        if area < 0.0 {
            return Err(format!(
                "{kind} element {e} (nodes {nodes:?} at {x:?}) is inverted (clockwise), area {area:e}"
            ));
        }
        // A triangle's corner products all equal twice its area; a
        // quadrilateral's tell whether it is convex.
        if let Element::Q4(_) = el
            && let Some((k, _)) = corner_crosses(x)
                .enumerate()
                .find(|(_, c)| *c <= 1e-10 * h * h)
        {
            return Err(format!(
                "{kind} element {e} (nodes {nodes:?} at {x:?}) is not convex or is degenerate at its corner {k} (node {}): the bilinear map folds there",
                nodes[k]
            ));
        }
        Ok(())
    }
}

fn lerp(range: [f64; 2], i: usize, n: usize) -> f64 {
    if i == n {
        range[1]
    } else {
        range[0] + (range[1] - range[0]) * (i as f64) / (n as f64)
    }
}

/// The diagonal of the bounding box of the nodes of `meshes` (0 when they have
/// no node), in any dimension.
pub fn bounding_diagonal<D: MeshDim>(meshes: &[&Mesh<D>]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in meshes.iter().flat_map(|m| &m.nodes) {
        for (c, &x) in p.as_ref().iter().enumerate() {
            lo[c] = lo[c].min(x);
            hi[c] = hi[c].max(x);
        }
    }
    if lo[0] <= hi[0] {
        let mut size = D::Vector::default();
        for (c, s) in size.as_mut().iter_mut().enumerate() {
            *s = hi[c] - lo[c];
        }
        D::length(size.as_ref())
    } else {
        0.0
    }
}

/// Euclidean distance between two points.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// How a mesh fails to tile its part (see [`Mesh::check_tiling`]); element and
/// node numbers are the mesh's.
#[derive(Debug, Clone, PartialEq)]
pub enum Tiling {
    /// More than two elements use one edge.
    Shared {
        /// The edge's nodes.
        edge: [usize; 2],
        /// The elements that use it.
        elements: Vec<usize>,
    },
    /// Two elements lie on the same side of their common edge (one folds over the other).
    SameSide {
        /// The edge's nodes.
        edge: [usize; 2],
        /// The two elements.
        elements: [usize; 2],
    },
    /// Elements overlap: they cover more area than their boundary encloses, or
    /// the interiors of two of them intersect.
    Overlap {
        /// Sum of the element areas.
        area: f64,
        /// Area enclosed by the boundary edges.
        enclosed: f64,
        /// Pairs of elements found to overlap (at most ten).
        pairs: Vec<[usize; 2]>,
    },
}

/// Whether two convex polygons (counter-clockwise corners) share interior area: no
/// edge normal of either separates them by more than round-off.
fn interiors_overlap(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    let scale = a
        .iter()
        .chain(b)
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max);
    let eps = 1e-12 * scale * scale;
    for poly in [a, b] {
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let n = [q[1] - p[1], p[0] - q[0]];
            let proj = |x: &[f64; 2]| n[0] * (x[0] - p[0]) + n[1] * (x[1] - p[1]);
            let (a0, a1) = a
                .iter()
                .map(proj)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, v| {
                    (m.0.min(v), m.1.max(v))
                });
            let (b0, b1) = b
                .iter()
                .map(proj)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, v| {
                    (m.0.min(v), m.1.max(v))
                });
            if a1 <= b0 + eps || b1 <= a0 + eps {
                return false;
            }
        }
    }
    true
}

/// Signed area of the polygon through `points` (shoelace; positive when
/// counter-clockwise).
pub fn polygon_area(points: impl Iterator<Item = [f64; 2]> + Clone) -> f64 {
    let first = points.clone().next();
    let mut area = 0.0;
    let mut prev: Option<[f64; 2]> = None;
    for p in points.chain(first) {
        if let Some(q) = prev {
            area += q[0] * p[1] - p[0] * q[1];
        }
        prev = Some(p);
    }
    0.5 * area
}

/// At each corner k of a polygon, the cross product of the edges leaving it:
/// (x_{k+1} − x_k) × (x_{k−1} − x_k). All positive: convex and counter-clockwise.
fn corner_crosses(x: &[[f64; 2]]) -> impl Iterator<Item = f64> + '_ {
    let n = x.len();
    (0..n).map(move |k| {
        let (p, a, b) = (x[k], x[(k + 1) % n], x[(k + n - 1) % n]);
        (a[0] - p[0]) * (b[1] - p[1]) - (a[1] - p[1]) * (b[0] - p[0])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The boundary edges are exactly the edges one element has, counted by an
    /// independent map over undirected edges, each oriented as its element runs
    /// it, on a T3 and a Q4 mesh with a hole (some elements removed).
    #[test]
    fn boundary_edges_match_a_counting_map() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let mut m = Mesh::rectangle([0.0, 3.0], [0.0, 2.0], [6, 4], kind);
            let n = m.elements.len();
            m.elements.remove(n / 2);
            m.elements.remove(n / 2 - 1);
            let mut count: BTreeMap<(usize, usize), Vec<BoundaryEdge>> = BTreeMap::new();
            for (e, el) in m.elements.iter().enumerate() {
                for [a, b] in el.edges() {
                    count
                        .entry((a.min(b), a.max(b)))
                        .or_default()
                        .push(BoundaryEdge {
                            nodes: [a, b],
                            element: e,
                        });
                }
            }
            let mut expected: Vec<BoundaryEdge> = count
                .into_values()
                .filter(|v| v.len() == 1)
                .map(|v| v[0])
                .collect();
            expected.sort_by_key(|e| (e.element, e.nodes));
            let got = m.boundary_edges();
            assert!(got.len() > 2 * (6 + 4), "{kind:?}: the hole adds edges");
            assert_eq!(got, expected, "{kind:?}");
        }
    }

    /// The structured mesher gives the expected counts, positive areas that sum to the
    /// rectangle's area, and boundaries that are exactly the mesh's free edges, with
    /// triangles and with quadrilaterals.
    #[test]
    fn rectangle_counts_areas_and_boundaries() {
        for (kind, diagonal, elements) in [
            (ElementKind::T3, Diagonal::Rising, 336),
            (ElementKind::T3, Diagonal::Falling, 336),
            (ElementKind::Q4, Diagonal::Rising, 168),
        ] {
            let m = Mesh::rectangle_split([30.0, 170.0], [120.0, 135.0], [28, 6], kind, diagonal);
            assert_eq!(m.nodes.len(), 29 * 7);
            assert_eq!(m.elements.len(), elements);
            m.validate("plate").unwrap();
            let area: f64 = (0..m.elements.len()).map(|e| m.element_area(e)).sum();
            assert!((area - 140.0 * 15.0).abs() < 1e-9);
            assert_eq!(m.boundary_nodes("bottom").unwrap().len(), 29);
            let mut named: Vec<_> = m.boundaries.values().flatten().copied().collect();
            let mut free = m.boundary_edges();
            named.sort_by_key(|e| (e.element, e.nodes));
            free.sort_by_key(|e| (e.element, e.nodes));
            assert_eq!(named, free, "{kind:?} {diagonal:?}");
        }
    }

    /// Every named boundary edge runs counter-clockwise: its outward normal points
    /// away from its element's centroid.
    #[test]
    fn boundary_edges_are_counter_clockwise() {
        for (kind, diagonal) in [
            (ElementKind::T3, Diagonal::Rising),
            (ElementKind::T3, Diagonal::Falling),
            (ElementKind::Q4, Diagonal::Rising),
        ] {
            let m = Mesh::rectangle_split([0.0, 2.0], [0.0, 1.0], [2, 1], kind, diagonal);
            for e in m.boundary_edges() {
                let [a, b] = e.nodes.map(|n| m.nodes[n]);
                let normal = [b[1] - a[1], -(b[0] - a[0])];
                let x = m.coordinates(e.element);
                let c = [0, 1].map(|k| x.iter().map(|p| p[k]).sum::<f64>() / x.len() as f64);
                let to_centroid = [c[0] - a[0], c[1] - a[1]];
                assert!(normal[0] * to_centroid[0] + normal[1] * to_centroid[1] < 0.0);
            }
        }
    }

    /// The tiling check: structured meshes of both kinds tile their rectangle;
    /// a triangle folded over its neighbour (one node moved across their common
    /// edge, each triangle still counter-clockwise), a third element on an edge,
    /// and a triangle lying on top of others are each caught, naming the elements.
    ///
    /// ```text
    ///   2               2
    ///   │ ╲             │ ╲  ╲
    ///   │   ╲     +     │    ╲   ╲      [0, 1, 2] and [0, 4, 2]: both lie
    ///   0─────1         0─────────4     right of their common edge 0–2
    /// ```
    #[test]
    fn tiling_detects_folds_and_overlaps() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let m = Mesh::rectangle([0.0, 3.0], [0.0, 2.0], [3, 2], kind);
            assert_eq!(m.check_tiling(), Ok(()));
        }
        // A fold: two triangles on the same side of their common edge.
        let mut fold = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], ElementKind::T3);
        fold.nodes.push([2.0, 0.5]);
        // Nodes 0 (0, 0), 1 (1, 0), 2 (0, 1) and 4 (2, 0.5): node 4 lies right of
        // edge 0–2, like node 1.
        fold.elements = vec![Element::T3([0, 1, 2]), Element::T3([0, 4, 2])];
        assert!(fold.element_area(1) > 0.0);
        assert!(matches!(
            fold.check_tiling(),
            Err(Tiling::SameSide {
                edge: [0, 2],
                elements: [0, 1]
            })
        ));
        // A third element on one edge.
        let mut three = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], ElementKind::T3);
        three.nodes.push([0.2, 2.0]);
        three.elements.push(Element::T3([0, 3, 4]));
        let t = three.check_tiling();
        assert!(
            matches!(t, Err(Tiling::Shared { .. })),
            "{t:?} {:?}",
            three.elements
        );
        // An element lying on top of others, sharing no edge with them.
        let mut on_top = Mesh::rectangle([0.0, 2.0], [0.0, 2.0], [2, 2], ElementKind::T3);
        let n = on_top.nodes.len();
        on_top.nodes.extend([[0.6, 0.6], [1.4, 0.6], [1.0, 1.4]]);
        on_top.elements.push(Element::T3([n, n + 1, n + 2]));
        match on_top.check_tiling() {
            Err(Tiling::Overlap {
                area,
                enclosed,
                pairs,
            }) => {
                assert!((area - enclosed).abs() < 1e-12, "{area} {enclosed}");
                assert!(pairs.iter().all(|p| p[1] == 8 || p[0] == 8), "{pairs:?}");
                assert!(!pairs.is_empty());
            }
            other => panic!("overlap not found: {other:?}"),
        }
    }

    /// Inverted and degenerate triangles, and clockwise or non-convex quadrilaterals,
    /// are rejected with the element named.
    #[test]
    fn validate_rejects_bad_elements() {
        let mut m = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], ElementKind::T3);
        // Nodes: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1); triangles [0,1,3], [0,3,2].
        m.elements[1] = Element::T3([0, 2, 3]);
        let msg = m.validate("p").unwrap_err().to_string();
        assert!(
            msg.contains("element 1") && msg.contains("inverted"),
            "{msg}"
        );
        m.elements[1] = Element::T3([0, 3, 2]);
        m.nodes[2] = [0.5, 0.5];
        let msg = m.validate("p").unwrap_err().to_string();
        assert!(msg.contains("degenerate"), "{msg}");

        let mut q = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], ElementKind::Q4);
        q.elements[0] = Element::Q4([0, 2, 3, 1]);
        let msg = q.validate("q").unwrap_err().to_string();
        assert!(
            msg.contains("Q4 element 0") && msg.contains("inverted"),
            "{msg}"
        );
        // An arrow head: node 3 (1, 1) pulled inside to (0.3, 0.3).
        q.elements[0] = Element::Q4([0, 1, 3, 2]);
        q.nodes[3] = [0.3, 0.3];
        let msg = q.validate("q").unwrap_err().to_string();
        assert!(
            msg.contains("not convex") && msg.contains("node 3"),
            "{msg}"
        );
    }

    /// The annular mesher: every node on its circle, the area of the inscribed
    /// polygons (nt/2 · r² sin(2π/nt) per ring for a full ring), boundaries that
    /// are exactly the free edges, and a full ring without seam or start/end.
    #[test]
    fn annulus_geometry_and_boundaries() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let (r0, r1, nt) = (10.0f64, 20.0f64, 24usize);
            let m = Mesh::annulus([1.0, 2.0], [r0, r1], [0.0, 360.0], [3, nt], kind);
            m.validate("ring").unwrap();
            assert_eq!(m.nodes.len(), 4 * nt);
            let polygon =
                |r: f64| 0.5 * nt as f64 * r * r * (std::f64::consts::TAU / nt as f64).sin();
            let area: f64 = (0..m.elements.len()).map(|e| m.element_area(e)).sum();
            assert!((area - (polygon(r1) - polygon(r0))).abs() < 1e-9, "{area}");
            let names: Vec<&String> = m.boundaries.keys().collect();
            assert_eq!(names, ["inner", "outer"]);
            for (name, r) in [("inner", r0), ("outer", r1)] {
                for n in m.boundary_nodes(name).unwrap() {
                    let p = m.nodes[n];
                    assert!(((p[0] - 1.0).hypot(p[1] - 2.0) - r).abs() < 1e-12);
                }
            }
            let mut named: Vec<_> = m.boundaries.values().flatten().copied().collect();
            let mut free = m.boundary_edges();
            named.sort_by_key(|e| (e.element, e.nodes));
            free.sort_by_key(|e| (e.element, e.nodes));
            assert_eq!(named, free, "{kind:?}");

            let q = Mesh::annulus([0.0, 0.0], [r0, r1], [0.0, 90.0], [2, 6], kind);
            q.validate("quarter").unwrap();
            let names: Vec<&String> = q.boundaries.keys().collect();
            assert_eq!(names, ["end", "inner", "outer", "start"]);
            assert!(
                q.boundary_nodes("end")
                    .unwrap()
                    .iter()
                    .all(|&n| q.nodes[n][0].abs() < 1e-12)
            );
        }
    }

    /// The shoelace area of a unit square and of a triangle, both orientations.
    #[test]
    fn polygon_areas() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(polygon_area(sq.iter().copied()), 1.0);
        assert_eq!(polygon_area(sq.iter().rev().copied()), -1.0);
        assert_eq!(
            polygon_area([[0.0, 0.0], [2.0, 0.0], [0.0, 3.0]].into_iter()),
            3.0
        );
    }
}
