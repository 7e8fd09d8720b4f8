//! Mesh: the nodes, linear triangles (T3) and named boundaries of one part, the
//! built-in structured rectangle mesher, and the geometric checks (inverted or
//! degenerate elements) every mesh passes before it is used. [`gmsh`] reads Gmsh
//! meshes.

pub mod gmsh;

use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap};

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

/// The mesh of one part: node coordinates, T3 connectivity (counter-clockwise), and
/// named boundaries as lists of edges.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates (x, y).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles as counter-clockwise node triples.
    pub triangles: Vec<[usize; 3]>,
    /// Named boundaries (e.g. `left`, `right`, `bottom`, `top`).
    pub boundaries: BTreeMap<String, Vec<BoundaryEdge>>,
}

impl Mesh {
    /// A structured mesh of the rectangle `[x0, x1] × [y0, y1]` with `nx × ny` cells,
    /// each split into two T3 along its rising diagonal. Boundaries `left`, `right`,
    /// `bottom` and `top` are named.
    ///
    /// Node (i, j) has index `j (nx + 1) + i`; cell (i, j) gives triangles
    /// `2 (j nx + i)` (below the diagonal) and `2 (j nx + i) + 1` (above it).
    pub fn rectangle(x: [f64; 2], y: [f64; 2], cells: [usize; 2]) -> Mesh {
        let [nx, ny] = cells;
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            let yj = lerp(y, j, ny);
            for i in 0..=nx {
                nodes.push([lerp(x, i, nx), yj]);
            }
        }
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (n00, n10, n11, n01) = (
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                );
                triangles.push([n00, n10, n11]);
                triangles.push([n00, n11, n01]);
            }
        }
        let lower = |i: usize, j: usize| 2 * (j * nx + i);
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
                .map(|i| edge(node(i + 1, ny), node(i, ny), lower(i, ny - 1) + 1))
                .collect(),
        );
        boundaries.insert(
            "left".to_string(),
            (0..ny)
                .rev()
                .map(|j| edge(node(0, j + 1), node(0, j), lower(0, j) + 1))
                .collect(),
        );
        Mesh {
            nodes,
            triangles,
            boundaries,
        }
    }

    /// Every boundary edge of the mesh (edges used by exactly one triangle), oriented
    /// counter-clockwise with respect to the part, in a deterministic order.
    pub fn boundary_edges(&self) -> Vec<BoundaryEdge> {
        let mut count: HashMap<(usize, usize), (usize, BoundaryEdge)> =
            HashMap::with_capacity(3 * self.triangles.len() / 2);
        for (e, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
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

    /// Signed area of triangle `e` (positive when counter-clockwise).
    pub fn triangle_area(&self, e: usize) -> f64 {
        let [a, b, c] = self.triangles[e].map(|n| self.nodes[n]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
    }

    /// The length of the longest element edge: the mesh's largest element size.
    pub fn max_edge_length(&self) -> f64 {
        self.triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .map(|(a, b)| dist(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max)
    }

    /// Checks that node indices are in range, coordinates are finite and every
    /// triangle is counter-clockwise with an area that is not negligible against the
    /// square of its longest edge. Errors name the part, the element and its nodes.
    pub fn validate(&self, part: &str) -> Result<()> {
        let err = |message: String| Error::Mesh {
            part: part.to_string(),
            message,
        };
        if self.triangles.is_empty() {
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
        for (e, tri) in self.triangles.iter().enumerate() {
            if let Some(n) = tri.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(err(format!(
                    "element {e} refers to node {n}, but the mesh has {} nodes",
                    self.nodes.len()
                )));
            }
            let area = self.triangle_area(e);
            let h = (0..3)
                .map(|k| dist(self.nodes[tri[k]], self.nodes[tri[(k + 1) % 3]]))
                .fold(0.0, f64::max);
            let corners = tri.map(|n| self.nodes[n]);
            if area.abs() <= 1e-10 * h * h {
                return Err(err(format!(
                    "element {e} (nodes {tri:?} at {corners:?}) is degenerate: area {area:e}"
                )));
            }
            if area < 0.0 {
                return Err(err(format!(
                    "element {e} (nodes {tri:?} at {corners:?}) is inverted (clockwise), area {area:e}"
                )));
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The structured mesher gives the expected counts, positive areas that sum to the
    /// rectangle's area, and boundaries that are exactly the mesh's free edges.
    #[test]
    fn rectangle_counts_areas_and_boundaries() {
        let m = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6]);
        assert_eq!(m.nodes.len(), 29 * 7);
        assert_eq!(m.triangles.len(), 336);
        m.validate("plate").unwrap();
        let area: f64 = (0..m.triangles.len()).map(|e| m.triangle_area(e)).sum();
        assert!((area - 140.0 * 15.0).abs() < 1e-9);
        assert_eq!(m.boundary_nodes("bottom").unwrap().len(), 29);
        let mut named: Vec<_> = m.boundaries.values().flatten().copied().collect();
        let mut free = m.boundary_edges();
        named.sort_by_key(|e| (e.element, e.nodes));
        free.sort_by_key(|e| (e.element, e.nodes));
        assert_eq!(named, free);
    }

    /// Every named boundary edge runs counter-clockwise: its outward normal points
    /// away from its element's centroid.
    #[test]
    fn boundary_edges_are_counter_clockwise() {
        let m = Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1]);
        for e in m.boundary_edges() {
            let [a, b] = e.nodes.map(|n| m.nodes[n]);
            let normal = [b[1] - a[1], -(b[0] - a[0])];
            let tri = m.triangles[e.element];
            let c = [
                tri.iter().map(|&n| m.nodes[n][0]).sum::<f64>() / 3.0,
                tri.iter().map(|&n| m.nodes[n][1]).sum::<f64>() / 3.0,
            ];
            let to_centroid = [c[0] - a[0], c[1] - a[1]];
            assert!(normal[0] * to_centroid[0] + normal[1] * to_centroid[1] < 0.0);
        }
    }

    /// Inverted and degenerate triangles are rejected with the element named.
    #[test]
    fn validate_rejects_bad_elements() {
        let mut m = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1]);
        // Nodes: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1); triangles [0,1,3], [0,3,2].
        m.triangles[1] = [0, 2, 3];
        let msg = m.validate("p").unwrap_err().to_string();
        assert!(
            msg.contains("element 1") && msg.contains("inverted"),
            "{msg}"
        );
        m.triangles[1] = [0, 3, 2];
        m.nodes[2] = [0.5, 0.5];
        let msg = m.validate("p").unwrap_err().to_string();
        assert!(msg.contains("degenerate"), "{msg}");
    }
}
