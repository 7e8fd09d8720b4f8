//! Segment-to-segment coupling (`coupling = "segment"`): the gap is integrated over
//! the node part's face instead of collocated at its nodes, so a constant traction
//! passes a tied interface exactly whatever the two meshes (the patch test), still
//! with no added unknown.
//!
//! The node part's face is cut into **sub-segments** at the projections of the host
//! boundary's vertices; on each sub-segment both sides are linear (the node side on
//! its face segment a–b, the host on one boundary edge), so the 2-point Gauss rule
//! integrates the penalty energy `½ ∫ κ [[u]]·[[u]] ds` exactly. Every Gauss point is
//! one [`CouplingElement`]: its node side is the point on a–b (`N₁ D_a + N₂ D_b`),
//! its host side the host element at the point's projection on the host edge, its
//! normal the host edge's outward normal, and its penalty weight
//! `ω = w / h̄` (w = Gauss weight × sub-segment length, h̄ = mean face-segment length
//! of the interface): the traction penalty is `κ = c / h̄`, so `c_n`, `c_s` keep
//! their meaning, the stiffness per coupling node of a uniformly meshed face
//! (docs/method.md §2b). The points are the interface's pairs: each has its own gap,
//! state and force, and the assembly, the low-rank updates and the law check treat
//! them like node pairs.

use super::element::{CouplingElement, SegmentPoint};
use super::search::{edge_normal, project, shape_at};
use crate::error::{Error, Result};
use crate::mesh::{BoundaryEdge, Mesh, dist};
use rstar::{AABB, RTree, primitives::GeomWithData, primitives::Line};

/// Projections of host vertices closer than this fraction of a face segment to one
/// of its ends, or to each other, are merged (no sliver sub-segments).
const MERGE: f64 = 1e-9;

/// The face segments of the node part on an interface: the boundary edges of
/// `node_mesh` whose two nodes are both coupling nodes (`nodes`), counter-clockwise
/// (the part on their left).
pub fn face_segments(node_mesh: &Mesh, nodes: &[usize]) -> Vec<[usize; 2]> {
    let mut is_coupling = vec![false; node_mesh.nodes.len()];
    for &n in nodes {
        is_coupling[n] = true;
    }
    let mut segments: Vec<[usize; 2]> = node_mesh
        .boundary_edges()
        .into_iter()
        .map(|e| e.nodes)
        .filter(|[a, b]| is_coupling[*a] && is_coupling[*b])
        .collect();
    segments.sort_unstable();
    segments
}

/// The segment-to-segment coupling elements of an interface: two Gauss points per
/// sub-segment of every face segment of `node_mesh` (boundary edges joining two of
/// the coupling `nodes`) that lies over a host boundary edge within `tolerance` ×
/// that edge's length. Call it once the coupling nodes lie on the host boundary
/// (after the node search has moved them there). Points are ordered by face
/// segment, then along it. An interface whose coupling nodes form no face segment
/// is an error.
pub fn segment_points(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    nodes: &[usize],
    tolerance: f64,
) -> Result<Vec<CouplingElement>> {
    let segments = face_segments(node_mesh, nodes);
    if segments.is_empty() {
        return Err(Error::Coupling {
            interface: interface.to_string(),
            message: format!(
                "`coupling = \"segment\"` integrates over the node part's face, but its {} coupling node(s) share no boundary edge; name a boundary of connected edges, or use `coupling = \"node\"`",
                nodes.len()
            ),
        });
    }
    let x = |n: usize| node_mesh.nodes[n];
    let mean_length =
        segments.iter().map(|&[a, b]| dist(x(a), x(b))).sum::<f64>() / segments.len() as f64;
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
    let gauss = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];

    let mut points = Vec::with_capacity(4 * segments.len());
    let mut candidates = Vec::new();
    let mut cuts = Vec::new();
    for &[na, nb] in &segments {
        let (a, b) = (x(na), x(nb));
        let len = dist(a, b);
        let ab = [b[0] - a[0], b[1] - a[1]];
        // Host edges near the segment.
        let envelope = AABB::from_corners(
            [a[0].min(b[0]) - radius, a[1].min(b[1]) - radius],
            [a[0].max(b[0]) + radius, a[1].max(b[1]) + radius],
        );
        candidates.clear();
        candidates.extend(
            tree.locate_in_envelope_intersecting(envelope)
                .map(|c| c.data),
        );
        candidates.sort_unstable();
        // Cut the segment at the projections of the host vertices near it.
        cuts.clear();
        cuts.extend([0.0, 1.0]);
        for &e in &candidates {
            let [p, q] = segment(&edges[e]);
            let tol = tolerance * dist(p, q);
            for v in [p, q] {
                let t = ((v[0] - a[0]) * ab[0] + (v[1] - a[1]) * ab[1]) / (len * len);
                let off = ((v[0] - a[0]) * ab[1] - (v[1] - a[1]) * ab[0]).abs() / len;
                if t > MERGE && t < 1.0 - MERGE && off <= tol {
                    cuts.push(t);
                }
            }
        }
        cuts.sort_unstable_by(f64::total_cmp);
        cuts.dedup_by(|later, earlier| *later - *earlier <= MERGE);
        for sub in cuts.windows(2) {
            let (t0, t1) = (sub[0], sub[1]);
            if t1 - t0 <= MERGE {
                continue;
            }
            // The host edge under the sub-segment: the nearest to its midpoint
            // (ties to the lowest host element, then edge), within the tolerance.
            let tm = 0.5 * (t0 + t1);
            let mid = [a[0] + tm * ab[0], a[1] + tm * ab[1]];
            let mut best: Option<(f64, usize, usize)> = None;
            for &e in &candidates {
                let [p, q] = segment(&edges[e]);
                let elen = dist(p, q);
                let (_, d) = project(mid, p, q);
                if d > tolerance * elen {
                    continue;
                }
                let key = (d, edges[e].element, e);
                let same = best.is_some_and(|cur| (d - cur.0).abs() <= 1e-12 * elen);
                best = match best {
                    None => Some(key),
                    Some(cur) if same && (key.1, key.2) < (cur.1, cur.2) => Some(key),
                    Some(cur) if !same && d < cur.0 => Some(key),
                    cur => cur,
                };
            }
            // A part of the face beyond the host's end carries no points.
            let Some((_, element, e)) = best else {
                continue;
            };
            let [p, q] = segment(&edges[e]);
            let corners = host.coordinates(element);
            let normal = edge_normal([p, q]);
            for g in gauss {
                let t = t0 + g * (t1 - t0);
                let at = [a[0] + t * ab[0], a[1] + t * ab[1]];
                let (xi, distance) = project(at, p, q);
                let on_host = [p[0] + xi * (q[0] - p[0]), p[1] + xi * (q[1] - p[1])];
                let shape = shape_at(&host.elements[element], &corners, on_host).ok_or_else(
                    || Error::Coupling {
                        interface: interface.to_string(),
                        message: format!(
                            "the inverse map of host element {element} (corners {corners:?}) does not converge at the segment point ({}, {})",
                            at[0], at[1]
                        ),
                    },
                )?;
                let length = 0.5 * (t1 - t0) * len;
                points.push(CouplingElement {
                    node: if t < 0.5 { na } else { nb },
                    host_element: element,
                    host_nodes: host.elements[element].nodes().to_vec(),
                    shape,
                    normal,
                    position: at,
                    distance,
                    segment: Some(SegmentPoint {
                        nodes: [na, nb],
                        shape: [1.0 - t, t],
                        length,
                        weight: length / mean_length,
                    }),
                });
            }
        }
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ElementKind;

    /// A 3-cell node face over a 7-cell host face (3:7): the points' lengths add up
    /// to the face's length, each sub-segment lies over one host edge (the points
    /// are cut at every host vertex that falls inside a segment: 3 + 6 = 9
    /// sub-segments, 18 points), the node-side shape functions reproduce the
    /// point's position, the host's reproduce its projection (on the face, so
    /// distance 0), the normal is +y, the weights ω = w / h̄ sum to the number of
    /// segments, and Σ ω N_a gives each interior node the weight 1 of a node CFE.
    #[test]
    fn points_on_a_3_to_7_face() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let host = Mesh::rectangle([0.0, 7.0], [0.0, 2.0], [7, 2], kind);
            let top = Mesh::rectangle([0.0, 7.0], [2.0, 3.0], [3, 1], kind);
            let nodes = top.boundary_nodes("bottom").unwrap();
            let pts = segment_points("i", &host, &top, &nodes, 1e-6).unwrap();
            assert_eq!(pts.len(), 18, "{kind:?}");
            let total: f64 = pts.iter().map(|p| p.segment.unwrap().length).sum();
            assert!((total - 7.0).abs() < 1e-12);
            let weights: f64 = pts.iter().map(|p| p.weight()).sum();
            assert!((weights - 3.0).abs() < 1e-12);
            let mut per_node = vec![0.0; top.nodes.len()];
            for p in &pts {
                let s = p.segment.unwrap();
                let xa = top.nodes[s.nodes[0]];
                let xb = top.nodes[s.nodes[1]];
                for c in 0..2 {
                    let at = s.shape[0] * xa[c] + s.shape[1] * xb[c];
                    assert!((at - p.position[c]).abs() < 1e-12);
                    let on_host: f64 = (0..p.shape.len())
                        .map(|i| p.shape[i] * host.nodes[p.host_nodes[i]][c])
                        .sum();
                    assert!((on_host - p.position[c]).abs() < 1e-12);
                }
                assert!(p.distance < 1e-12 && (p.normal[1] - 1.0).abs() < 1e-12);
                for (&n, &w) in s.nodes.iter().zip(&s.shape) {
                    per_node[n] += p.weight() * w;
                }
            }
            let mut interior: Vec<f64> = nodes
                .iter()
                .filter(|&&n| top.nodes[n][0] > 0.0 && top.nodes[n][0] < 7.0)
                .map(|&n| per_node[n])
                .collect();
            assert_eq!(interior.len(), 2);
            interior.retain(|w| (w - 1.0).abs() > 1e-12);
            assert!(interior.is_empty(), "{interior:?}");
        }
    }

    /// Coupling nodes that share no boundary edge cannot be integrated over: an
    /// error naming the interface and the remedy.
    #[test]
    fn isolated_nodes_are_an_error() {
        let host = Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1], ElementKind::T3);
        let top = Mesh::rectangle([0.0, 2.0], [1.0, 2.0], [2, 1], ElementKind::T3);
        let nodes = top.boundary_nodes("bottom").unwrap();
        let e = segment_points("lone", &host, &top, &nodes[..1], 1e-6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("lone") && e.contains("coupling = \"node\""), "{e}");
    }
}
