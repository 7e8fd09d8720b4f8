//! Pair search: for each coupling node of the node part, the host element whose
//! boundary edge contains it, through an R-tree over the host's boundary edges
//! (O(n log n), no all-pairs loop). Also gives the host's outward normal there.

use super::element::CouplingElement;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryEdge, Mesh, dist};
use rstar::{RTree, primitives::GeomWithData, primitives::Line};
use std::collections::HashMap;

/// Finds one coupling element per node in `nodes` (indices into `node_mesh`).
///
/// A node couples to the host boundary edge nearest to it, provided its distance is
/// at most `tolerance × (length of that edge)`. Among edges at the same distance (a
/// node at a host vertex, or on an edge shared by two elements) the one of the
/// lowest host element index is taken, so the assignment is deterministic. The
/// node's natural coordinates come from its projection on that edge, and the normal
/// is the edge's outward normal, or at a host vertex the normalised average of the
/// normals of the boundary edges that meet there. Nodes that lie in no host element
/// are an error listing them with their coordinates.
pub fn find_pairs(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    nodes: &[usize],
    tolerance: f64,
) -> Result<Vec<CouplingElement>> {
    let edges = host.boundary_edges();
    let segment = |e: &BoundaryEdge| e.nodes.map(|n| host.nodes[n]);
    let tree = RTree::bulk_load(
        edges
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let [a, b] = segment(e);
                GeomWithData::new(Line::new(a, b), i)
            })
            .collect(),
    );
    let max_len = edges
        .iter()
        .map(|e| {
            let [a, b] = segment(e);
            dist(a, b)
        })
        .fold(0.0, f64::max);
    let radius = tolerance * max_len;
    // Outward normals of the boundary edges that meet at each host vertex.
    let mut vertex_normals: HashMap<usize, Vec<[f64; 2]>> = HashMap::new();
    for e in &edges {
        let n = edge_normal(segment(e));
        for v in e.nodes {
            vertex_normals.entry(v).or_default().push(n);
        }
    }

    let mut pairs = Vec::with_capacity(nodes.len());
    let mut orphans = Vec::new();
    for &node in nodes {
        let p = node_mesh.nodes[node];
        // (distance, element, edge index, ξ)
        let mut best: Option<(f64, usize, usize, f64)> = None;
        for cand in tree.locate_within_distance(p, radius * radius) {
            let edge = &edges[cand.data];
            let [a, b] = segment(edge);
            let len = dist(a, b);
            let (xi, d) = project(p, a, b);
            if d > tolerance * len {
                continue;
            }
            let key = (d, edge.element, cand.data, xi);
            best = match best {
                None => Some(key),
                Some(cur) => {
                    let same =
                        (d - cur.0).abs() <= 1e-12 * len.max(1e-300) + 1e-3 * tolerance * len;
                    if (same && (edge.element, cand.data) < (cur.1, cur.2)) || (!same && d < cur.0)
                    {
                        Some(key)
                    } else {
                        Some(cur)
                    }
                }
            };
        }
        let Some((d, element, edge_index, xi)) = best else {
            orphans.push((node, p));
            continue;
        };
        let edge = &edges[edge_index];
        let tri = host.triangles[element];
        let mut shape = [0.0; 3];
        for (k, &v) in tri.iter().enumerate() {
            if v == edge.nodes[0] {
                shape[k] = 1.0 - xi;
            } else if v == edge.nodes[1] {
                shape[k] = xi;
            }
        }
        let len = dist(host.nodes[edge.nodes[0]], host.nodes[edge.nodes[1]]);
        let at_vertex = if xi * len <= tolerance * len {
            Some(edge.nodes[0])
        } else if (1.0 - xi) * len <= tolerance * len {
            Some(edge.nodes[1])
        } else {
            None
        };
        let normal = match at_vertex {
            Some(v) => normalised_average(&vertex_normals[&v]),
            None => edge_normal(segment(edge)),
        };
        pairs.push(CouplingElement {
            node,
            host_element: element,
            host_nodes: tri,
            shape,
            normal,
            position: p,
            distance: d,
        });
    }
    if !orphans.is_empty() {
        let list: Vec<String> = orphans
            .iter()
            .take(20)
            .map(|(n, p)| format!("node {n} at ({}, {})", p[0], p[1]))
            .collect();
        return Err(Error::Coupling {
            interface: interface.to_string(),
            message: format!(
                "{} coupling node(s) lie in no host element (none within tolerance {} × edge length of the host boundary): {}{}",
                orphans.len(),
                tolerance,
                list.join(", "),
                if orphans.len() > 20 { ", ..." } else { "" }
            ),
        });
    }
    Ok(pairs)
}

/// Projection of `p` on segment `a`–`b`: the clamped parameter ξ ∈ [0, 1] and the distance.
pub fn project(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let xi = ((ap[0] * ab[0] + ap[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
    let q = [a[0] + xi * ab[0], a[1] + xi * ab[1]];
    (xi, dist(p, q))
}

/// Unit outward normal of a counter-clockwise boundary edge (its direction turned −90°).
pub fn edge_normal([a, b]: [[f64; 2]; 2]) -> [f64; 2] {
    let l = dist(a, b);
    [(b[1] - a[1]) / l, -(b[0] - a[0]) / l]
}

fn normalised_average(normals: &[[f64; 2]]) -> [f64; 2] {
    let s = normals
        .iter()
        .fold([0.0, 0.0], |acc, n| [acc[0] + n[0], acc[1] + n[1]]);
    let l = s[0].hypot(s[1]);
    if l > 1e-12 {
        [s[0] / l, s[1] / l]
    } else {
        normals[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seed's plate on its base: the plate's 29 bottom nodes each find a base
    /// element whose top edge contains them, with shape functions that reproduce
    /// the node's position, the normal +y, and nodes at base vertices assigned to
    /// the lower-numbered element.
    #[test]
    fn plate_on_base_pairs() {
        let base = Mesh::rectangle([0.0, 200.0], [0.0, 120.0], [20, 12]);
        let plate = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6]);
        let nodes = plate.boundary_nodes("bottom").unwrap();
        let pairs = find_pairs("i", &base, &plate, &nodes, 1e-4).unwrap();
        assert_eq!(pairs.len(), 29);
        for p in &pairs {
            let x: [f64; 2] = std::array::from_fn(|c| {
                (0..3)
                    .map(|i| p.shape[i] * base.nodes[p.host_nodes[i]][c])
                    .sum::<f64>()
            });
            assert!(dist(x, p.position) < 1e-12);
            assert!((p.normal[1] - 1.0).abs() < 1e-12);
            assert!((p.shape.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        // x = 30 is a base vertex shared by the top edges of cells 2 and 3 of the top row.
        let at30 = pairs
            .iter()
            .find(|p| (p.position[0] - 30.0).abs() < 1e-9)
            .unwrap();
        assert_eq!(at30.host_element, 2 * (11 * 20 + 2) + 1);
    }

    /// A node that is off the host boundary is an error that lists it with its
    /// coordinates.
    #[test]
    fn orphan_nodes_are_listed() {
        let base = Mesh::rectangle([0.0, 10.0], [0.0, 10.0], [2, 2]);
        let other = Mesh::rectangle([20.0, 30.0], [10.0, 12.0], [1, 1]);
        let nodes = other.boundary_nodes("bottom").unwrap();
        let e = find_pairs("gap", &base, &other, &nodes, 1e-4)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("gap") && e.contains("(20, 10)") && e.contains("(30, 10)"),
            "{e}"
        );
    }

    /// At a host corner the normal is the normalised average of the two edges' normals.
    #[test]
    fn corner_normal_is_averaged() {
        let host = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1]);
        let probe = Mesh {
            nodes: vec![[1.0, 1.0]],
            ..Default::default()
        };
        let p = &find_pairs("c", &host, &probe, &[0], 1e-6).unwrap()[0];
        let h = 0.5f64.sqrt();
        assert!((p.normal[0] - h).abs() < 1e-12 && (p.normal[1] - h).abs() < 1e-12);
    }
}
