//! Mesh: the nodes, elements (linear triangles T3 and bilinear quadrilaterals Q4,
//! possibly mixed) and named boundaries of one part, the built-in structured
//! rectangle mesher, and the geometric checks (inverted, degenerate or non-convex
//! elements) every mesh passes before it is used. [`gmsh`] reads Gmsh meshes;
//! [`Mesh::refined`] (in `refine`) subdivides any mesh uniformly.

mod arrays;
pub mod gmsh;
mod refine;

pub use arrays::BoundarySelection;

use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap};

/// The element types a part may be meshed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// 3-node linear triangle (constant strain).
    T3,
    /// 4-node bilinear quadrilateral (2×2 Gauss integration).
    Q4,
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

/// The mesh of one part: node coordinates, elements (counter-clockwise), and named
/// boundaries as lists of edges.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates (x, y).
    pub nodes: Vec<[f64; 2]>,
    /// Elements (T3 and Q4 may be mixed), nodes counter-clockwise.
    pub elements: Vec<Element>,
    /// Named boundaries (e.g. `left`, `right`, `bottom`, `top`).
    pub boundaries: BTreeMap<String, Vec<BoundaryEdge>>,
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
                match kind {
                    ElementKind::T3 => {
                        elements.push(Element::T3([n00, n10, n11]));
                        elements.push(Element::T3([n00, n11, n01]));
                    }
                    ElementKind::Q4 => elements.push(Element::Q4([n00, n10, n11, n01])),
                }
            }
        }
        // The element of cell (i, j) that owns its lower and right edges, and the one
        // that owns its upper and left edges.
        let lower = |i: usize, j: usize| per_cell * (j * nx + i);
        let upper = |i: usize, j: usize| per_cell * (j * nx + i) + per_cell - 1;
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
                .map(|j| edge(node(nx, j), node(nx, j + 1), lower(nx - 1, j)))
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
                .map(|j| edge(node(0, j + 1), node(0, j), upper(0, j)))
                .collect(),
        );
        Mesh {
            nodes,
            elements,
            boundaries,
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
        let mut count: HashMap<(usize, usize), (usize, BoundaryEdge)> =
            HashMap::with_capacity(2 * self.elements.len());
        for (e, el) in self.elements.iter().enumerate() {
            for [a, b] in el.edges() {
                let key = (a.min(b), a.max(b));
                count.entry(key).and_modify(|c| c.0 += 1).or_insert((
                    1,
                    BoundaryEdge {
                        nodes: [a, b],
                        element: e,
                    },
                ));
            }
        }
        let mut edges: Vec<BoundaryEdge> = count
            .into_values()
            .filter(|(n, _)| *n == 1)
            .map(|(_, edge)| edge)
            .collect();
        edges.sort_by_key(|e| (e.element, e.nodes));
        edges
    }

    /// The nodes of a named boundary, each once, in traversal order.
    pub fn boundary_nodes(&self, name: &str) -> Option<Vec<usize>> {
        let edges = self.boundaries.get(name)?;
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        for e in edges {
            for n in e.nodes {
                if seen.insert(n) {
                    out.push(n);
                }
            }
        }
        Some(out)
    }

    /// The corner coordinates of element `e`, counter-clockwise.
    pub fn coordinates(&self, e: usize) -> Vec<[f64; 2]> {
        self.elements[e]
            .nodes()
            .iter()
            .map(|&n| self.nodes[n])
            .collect()
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

    /// How many elements of each kind the mesh has: (T3, Q4).
    pub fn counts(&self) -> (usize, usize) {
        let q4 = self
            .elements
            .iter()
            .filter(|e| e.kind() == ElementKind::Q4)
            .count();
        (self.elements.len() - q4, q4)
    }

    /// The element types as text, e.g. `480 T3` or `120 T3 + 36 Q4`.
    pub fn describe_elements(&self) -> String {
        match self.counts() {
            (t, 0) => format!("{t} T3"),
            (0, q) => format!("{q} Q4"),
            (t, q) => format!("{t} T3 + {q} Q4"),
        }
    }

    /// The length of the longest element edge: the mesh's largest element size.
    pub fn max_edge_length(&self) -> f64 {
        self.elements
            .iter()
            .flat_map(|el| el.edges())
            .map(|[a, b]| dist(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max)
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

    /// Checks only the elements that contain one of `nodes` (after those nodes
    /// moved), as [`Mesh::validate`] does for all.
    pub fn validate_around(&self, part: &str, nodes: &[usize]) -> Result<()> {
        let moved: std::collections::HashSet<usize> = nodes.iter().copied().collect();
        for (e, el) in self.elements.iter().enumerate() {
            if el.nodes().iter().any(|n| moved.contains(n)) {
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

/// Euclidean distance between two points.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
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

    /// The structured mesher gives the expected counts, positive areas that sum to the
    /// rectangle's area, and boundaries that are exactly the mesh's free edges, with
    /// triangles and with quadrilaterals.
    #[test]
    fn rectangle_counts_areas_and_boundaries() {
        for (kind, elements) in [(ElementKind::T3, 336), (ElementKind::Q4, 168)] {
            let m = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6], kind);
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
            assert_eq!(named, free, "{kind:?}");
        }
    }

    /// Every named boundary edge runs counter-clockwise: its outward normal points
    /// away from its element's centroid.
    #[test]
    fn boundary_edges_are_counter_clockwise() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let m = Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1], kind);
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
