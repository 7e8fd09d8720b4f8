//! Pair search: for each coupling node of the node part, the host element whose
//! boundary edge it lies on, through an R-tree over the host's boundary edges
//! (O(n log n), no all-pairs loop). A node near but off the host boundary — a fine
//! curved face against a coarse polygonal one — is projected on its nearest host
//! edge when within the tolerance; the host's outward normal there and the host
//! shape functions at the projection make the coupling element.

use super::element::CouplingElement;
use crate::dim::{D2, Dim};
use crate::error::{Error, Result};
use crate::fem::q4;
use crate::mesh::{BoundaryEdge, Element, Mesh, dist};
use rstar::{RTree, primitives::GeomWithData, primitives::Line};
use std::collections::HashMap;

/// An R-tree of boundary edges: each a segment carrying its index in the list.
pub(super) type EdgeTree = RTree<GeomWithData<Line<[f64; 2]>, usize>>;

/// The host's boundary edges, their R-tree (for the searches of the pair search
/// and of the segment coupling) and the longest edge's length.
pub(super) fn edge_tree(host: &Mesh) -> (Vec<BoundaryEdge>, EdgeTree, f64) {
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
    (edges, tree, max_len)
}

/// A coupling node closer than this fraction of the host edge's length to one of
/// the edge's ends is *at* that host vertex: it takes the vertex's averaged normal.
pub const VERTEX_TOLERANCE: f64 = 1e-6;

/// Within a search distance, a host boundary edge *faces* a point of the node
/// part's face when the angle between the edge's outward normal and the reversed
/// outward normal of the node part's face there is below 60°: n_host · n_face <
/// −cos 60° = −1/2. Two faces in contact have opposite normals; within a search
/// distance d the curvature of faces of radius R turns them by at most
/// acos(1 − d/R) (18° for the Hertz example's d/R = 0.05, 60° only at d = R/2),
/// while a host boundary that merely meets the interface — a symmetry edge at the
/// end of a quarter model, a side at a corner — is about 90° off and is never the
/// interface's face.
pub const FACING_COSINE: f64 = 0.5;

/// Whether a host boundary edge with outward normal `host` faces a node-part face
/// with outward normal `face` (see [`FACING_COSINE`]).
pub(super) fn facing(host: [f64; 2], face: [f64; 2]) -> bool {
    host[0] * face[0] + host[1] * face[1] < -FACING_COSINE
}

/// The outward normal of each edge of the node part's face (the boundary edges of
/// `mesh` whose both ends are among `nodes`), keyed by its node pair, lower first.
/// Taken from the elements' counter-clockwise boundary edges, whatever the order
/// a named boundary lists its nodes in.
pub(super) fn face_normals(mesh: &Mesh, nodes: &[usize]) -> HashMap<[usize; 2], [f64; 2]> {
    let set: std::collections::HashSet<usize> = nodes.iter().copied().collect();
    mesh.boundary_edges()
        .into_iter()
        .filter(|e| e.nodes.iter().all(|n| set.contains(n)))
        .map(|e| {
            let [a, b] = e.nodes;
            (
                [a.min(b), a.max(b)],
                edge_normal([mesh.nodes[a], mesh.nodes[b]]),
            )
        })
        .collect()
}

/// The outward normal of the node part's face at each of its nodes: the
/// normalised average of the normals of the face edges (`face_normals`) that
/// meet there. A node on no face edge has none.
fn node_normals(face: &HashMap<[usize; 2], [f64; 2]>) -> HashMap<usize, [f64; 2]> {
    let mut sums: HashMap<usize, Vec<[f64; 2]>> = HashMap::new();
    let mut keys: Vec<&[usize; 2]> = face.keys().collect();
    keys.sort_unstable();
    for k in keys {
        for n in k {
            sums.entry(*n).or_default().push(face[k]);
        }
    }
    sums.into_iter()
        .map(|(n, normals)| (n, normalised_average(&normals)))
        .collect()
}

/// Finds one coupling element per node in `nodes` (indices into `node_mesh`).
///
/// A node couples to the host boundary edge nearest to it, provided its distance
/// is at most `tolerance × (length of that edge)`; it is then projected on that
/// edge, and the projection is the coupling position X_C (the caller moves the
/// node there, as established codes adjust tied nodes onto the master surface).
/// Among edges at the same distance (a node at a host vertex, or on an edge shared
/// by two elements) the one of the lowest host element index is taken, so the
/// assignment is deterministic. The host shape functions at X_C come from the host
/// element's natural coordinates there: barycentric for a T3, Newton's inverse
/// bilinear map for a Q4. The normal is the edge's outward normal, or at a host
/// vertex the normalised average of the normals of the boundary edges that meet
/// there. Nodes farther than the tolerance from every host edge are an error
/// listing them with their coordinates and distances.
#[cfg(test)]
pub fn find_pairs(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    nodes: &[usize],
    tolerance: f64,
) -> Result<Vec<CouplingElement>> {
    find_pairs_within(interface, host, node_mesh, nodes, tolerance, 0.0).map(|(p, _)| p)
}

/// As [`find_pairs`] when `search_distance` is 0. With a search distance d > 0
/// (a length) each node couples to the host boundary edge nearest to it within d
/// among those that face the node part's face at the node ([`facing`]: a host
/// boundary that merely meets the interface, such as a symmetry edge the node
/// touches, is not its face), whatever the tolerance; at a host vertex its normal
/// is the average of the facing edges' meeting there. It is *not* moved: its initial normal gap
/// g₀ = (X − X_C) · n (positive apart, negative overlapping) is stored in the
/// coupling element, and a node with no host edge within d is left unpaired
/// (returned as the count, second). Every element gets its tributary length on
/// the node part's face and its host edge's length.
pub fn find_pairs_within(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    nodes: &[usize],
    tolerance: f64,
    search_distance: f64,
) -> Result<(Vec<CouplingElement>, usize)> {
    let gaps = search_distance > 0.0;
    let (edges, tree, max_len) = edge_tree(host);
    let segment = |e: &BoundaryEdge| e.nodes.map(|n| host.nodes[n]);
    let radius = if gaps {
        search_distance
    } else {
        tolerance * max_len
    };
    let tributary = tributary_lengths(node_mesh, nodes);
    // Within a search distance: the node part's outward normal at each node, which
    // the host edges it pairs with must face.
    let face = if gaps {
        node_normals(&face_normals(node_mesh, nodes))
    } else {
        HashMap::new()
    };
    let mut unpaired = 0;
    // Outward normals of the boundary edges that meet at each host vertex.
    let mut vertex_normals: HashMap<usize, Vec<[f64; 2]>> = HashMap::new();
    for e in &edges {
        let n = edge_normal(segment(e));
        for v in e.nodes {
            vertex_normals.entry(v).or_default().push(n);
        }
    }

    let mut pairs = Vec::with_capacity(nodes.len());
    let mut orphans: Vec<Orphan> = Vec::new();
    for &node in nodes {
        let p = node_mesh.nodes[node];
        let faces = |n: [f64; 2]| face.get(&node).is_none_or(|&f| facing(n, f));
        // (distance, element, edge index, ξ along the edge)
        let mut best: Option<(f64, usize, usize, f64)> = None;
        for cand in tree.locate_within_distance(p, radius * radius) {
            let edge = &edges[cand.data];
            let [a, b] = segment(edge);
            if !faces(edge_normal([a, b])) {
                continue;
            }
            let len = dist(a, b);
            let (xi, d) = project(p, a, b);
            if (!gaps && d > tolerance * len) || (gaps && d > search_distance) {
                continue;
            }
            let key = (d, edge.element, cand.data, xi);
            best = match best {
                None => Some(key),
                Some(cur) => {
                    let same = (d - cur.0).abs() <= 1e-12 * len.max(1e-300);
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
            if gaps {
                unpaired += 1;
                continue;
            }
            let nearest = tree.nearest_neighbor(p).map(|c| {
                let [a, b] = segment(&edges[c.data]);
                let (_, d) = project(p, a, b);
                (d, dist(a, b))
            });
            orphans.push((node, p, nearest));
            continue;
        };
        let edge = &edges[edge_index];
        let [a, b] = segment(edge);
        let position = [a[0] + xi * (b[0] - a[0]), a[1] + xi * (b[1] - a[1])];
        let host_element = &host.elements[element];
        let corners = host.coordinates(element);
        let shape = shape_at(host_element, &corners, position).ok_or_else(|| Error::Coupling {
            interface: interface.to_string(),
            message: format!(
                "the inverse map of host element {element} (corners {corners:?}) does not converge at coupling node {node} ({}, {})",
                p[0], p[1]
            ),
        })?;
        let at_vertex = if xi <= VERTEX_TOLERANCE {
            Some(edge.nodes[0])
        } else if 1.0 - xi <= VERTEX_TOLERANCE {
            Some(edge.nodes[1])
        } else {
            None
        };
        let normal = match at_vertex {
            Some(v) => {
                let meeting: Vec<[f64; 2]> = vertex_normals[&v]
                    .iter()
                    .copied()
                    .filter(|&n| faces(n))
                    .collect();
                normalised_average(&meeting)
            }
            None => edge_normal([a, b]),
        };
        let gap0 = if gaps {
            (p[0] - position[0]) * normal[0] + (p[1] - position[1]) * normal[1]
        } else {
            0.0
        };
        pairs.push(CouplingElement {
            node,
            host_element: element,
            host_nodes: host_element.nodes().to_vec(),
            shape,
            normal,
            frame: D2::frame(normal),
            position,
            distance: d,
            gap0,
            tributary: tributary.get(&node).copied().unwrap_or(0.0),
            edge_length: dist(a, b),
            ring: 1.0,
            segment: None,
        });
    }
    if !orphans.is_empty() {
        return Err(orphan_error(interface, &orphans, tolerance));
    }
    Ok((pairs, unpaired))
}

/// The tributary length of each of `nodes` on the node part's face: half the sum
/// of the lengths of the boundary edges of `mesh` at the node whose both ends are
/// among `nodes`.
fn tributary_lengths(mesh: &Mesh, nodes: &[usize]) -> HashMap<usize, f64> {
    let set: std::collections::HashSet<usize> = nodes.iter().copied().collect();
    let mut out: HashMap<usize, f64> = nodes.iter().map(|&n| (n, 0.0)).collect();
    for e in mesh.boundary_edges() {
        let [a, b] = e.nodes;
        if set.contains(&a) && set.contains(&b) {
            let half = 0.5 * dist(mesh.nodes[a], mesh.nodes[b]);
            *out.entry(a).or_default() += half;
            *out.entry(b).or_default() += half;
        }
    }
    out
}

/// A coupling node on no host edge: its index, its position and, when there is
/// one, the distance to the nearest host edge and that edge's length.
type Orphan = (usize, [f64; 2], Option<(f64, f64)>);

/// The error listing the coupling nodes that lie on no host edge within the
/// tolerance (the first few, with their nearest host edge, then how many more:
/// [`crate::error::short_list`]), `orphans` as (node, position, nearest
/// (distance, edge length)).
fn orphan_error(interface: &str, orphans: &[Orphan], tolerance: f64) -> Error {
    let list = crate::error::short_list(orphans.iter().map(|(n, p, near)| match near {
            Some((d, len)) => format!(
                "node {n} at ({}, {}) (nearest host edge {d:.4e} away, {:.3} × its length {len:.4e})",
                p[0],
                p[1],
                d / len
            ),
            None => format!("node {n} at ({}, {})", p[0], p[1]),
        }));
    Error::OrphanNodes {
        interface: interface.to_string(),
        nodes: orphans.iter().map(|(n, p, _)| (*n, p.to_vec())).collect(),
        message: format!(
            "{} coupling node(s) lie on no host boundary edge within the tolerance {} × edge length: {} — check that the interface's boundary faces the host, or raise `tolerance` if the faces are meshed apart (curved faces: about (edge length)² / (8 × radius))",
            orphans.len(),
            tolerance, list,
        ),
    }
}

/// The shape functions of host element `element` (corner coordinates `x`) at the
/// point `p` of its boundary: barycentric coordinates for a T3; for a Q4 the
/// bilinear shape functions at the natural coordinates found by Newton's inverse
/// map. `None` when the inverse map does not converge.
pub fn shape_at(element: &Element, x: &[[f64; 2]], p: [f64; 2]) -> Option<Vec<f64>> {
    match element {
        Element::T3(_) => {
            let [a, b, c] = [x[0], x[1], x[2]];
            let two_a = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let l1 = ((b[0] - p[0]) * (c[1] - p[1]) - (c[0] - p[0]) * (b[1] - p[1])) / two_a;
            let l2 = ((c[0] - p[0]) * (a[1] - p[1]) - (a[0] - p[0]) * (c[1] - p[1])) / two_a;
            Some(vec![l1, l2, 1.0 - l1 - l2])
        }
        Element::Q4(_) => {
            let x4 = [x[0], x[1], x[2], x[3]];
            q4::natural_coordinates(&x4, p).map(|xi| q4::shape(xi).to_vec())
        }
    }
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
    use crate::mesh::ElementKind;

    /// The seed's plate on its base, with a T3 base and with a Q4 base: the plate's
    /// 29 bottom nodes each find a base element whose top edge contains them, with
    /// shape functions that reproduce the node's position (for the Q4 through
    /// Newton's inverse map: the two nodes off the edge get 0), the normal +y, and
    /// nodes at base vertices assigned to the lower-numbered element.
    #[test]
    fn plate_on_base_pairs() {
        let plate = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6], ElementKind::T3);
        for (kind, at30_element) in [
            (ElementKind::T3, 2 * (11 * 20 + 2) + 1),
            (ElementKind::Q4, 11 * 20 + 2),
        ] {
            let base = Mesh::rectangle([0.0, 200.0], [0.0, 120.0], [20, 12], kind);
            let nodes = plate.boundary_nodes("bottom").unwrap();
            let pairs = find_pairs("i", &base, &plate, &nodes, 1e-4).unwrap();
            assert_eq!(pairs.len(), 29);
            for p in &pairs {
                assert_eq!(p.shape.len(), p.host_nodes.len());
                let x: [f64; 2] = std::array::from_fn(|c| {
                    (0..p.shape.len())
                        .map(|i| p.shape[i] * base.nodes[p.host_nodes[i]][c])
                        .sum::<f64>()
                });
                assert!(dist(x, p.position) < 1e-12);
                assert!((p.normal[1] - 1.0).abs() < 1e-12);
                assert!((p.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                for (i, &n) in p.host_nodes.iter().enumerate() {
                    if base.nodes[n][1] < 119.0 {
                        assert!(p.shape[i].abs() < 1e-13, "{kind:?}: {:?}", p.shape);
                    }
                }
            }
            // x = 30 is a base vertex shared by the top edges of cells 2 and 3 of
            // the top row.
            let at30 = pairs
                .iter()
                .find(|p| (p.position[0] - 30.0).abs() < 1e-9)
                .unwrap();
            assert_eq!(at30.host_element, at30_element, "{kind:?}");
        }
    }

    /// A node that is off the host boundary is an error that lists it with its
    /// coordinates and its distance to the nearest host edge.
    #[test]
    fn orphan_nodes_are_listed() {
        let base = Mesh::rectangle([0.0, 10.0], [0.0, 10.0], [2, 2], ElementKind::T3);
        let other = Mesh::rectangle([20.0, 30.0], [10.0, 12.0], [1, 1], ElementKind::T3);
        let nodes = other.boundary_nodes("bottom").unwrap();
        let e = find_pairs("gap", &base, &other, &nodes, 1e-4)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("gap")
                && e.contains("(20, 10)")
                && e.contains("(30, 10)")
                && e.contains("nearest host edge 1.0000e1 away"),
            "{e}"
        );
    }

    /// At a host corner the normal is the normalised average of the two edges' normals.
    #[test]
    fn corner_normal_is_averaged() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let host = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], kind);
            let probe = Mesh {
                nodes: vec![[1.0, 1.0]],
                ..Default::default()
            };
            let p = &find_pairs("c", &host, &probe, &[0], 1e-6).unwrap()[0];
            let h = 0.5f64.sqrt();
            assert!((p.normal[0] - h).abs() < 1e-12 && (p.normal[1] - h).abs() < 1e-12);
        }
    }

    /// A fine circular face against a coarse polygonal host (a disk of radius R cut
    /// into n triangles): every node on the circle is projected on its nearest
    /// chord, at most the sagitta h²/(8R) (h the chord) away — exactly that at a
    /// chord's midpoint — lands on the chord, and takes the chord's normal; with a
    /// tolerance below the sagitta's share of the chord the midpoint nodes are
    /// rejected and listed.
    #[test]
    fn curved_face_projects_on_chords() {
        let (r, n) = (20.0f64, 12usize);
        let at = |t: f64| [r * t.cos(), r * t.sin()];
        let step = std::f64::consts::TAU / n as f64;
        let mut host: Mesh = Mesh {
            nodes: (0..n).map(|k| at(k as f64 * step)).collect(),
            ..Default::default()
        };
        host.nodes.push([0.0, 0.0]);
        host.elements = (0..n).map(|k| Element::T3([n, k, (k + 1) % n])).collect();
        host.validate("disk").unwrap();
        // Four fine nodes per chord.
        let probe = Mesh {
            nodes: (0..4 * n).map(|k| at(k as f64 * step / 4.0)).collect(),
            ..Default::default()
        };
        let all: Vec<usize> = (0..4 * n).collect();
        let chord = 2.0 * r * (step / 2.0).sin();
        let sagitta = r * (1.0 - (step / 2.0).cos());
        assert!((sagitta - chord * chord / (8.0 * r)).abs() < 0.02 * sagitta);
        let pairs = find_pairs("arc", &host, &probe, &all, 0.1).unwrap();
        let largest = pairs.iter().map(|p| p.distance).fold(0.0, f64::max);
        assert!(
            (largest - sagitta).abs() < 1e-12 * r,
            "{largest} vs {sagitta}"
        );
        for p in &pairs {
            // On the chord: at distance R cos(step/2) from the centre along the
            // chord's normal, which points outwards at the chord's mid-angle.
            let k = p.host_element as f64;
            let mid = (k + 0.5) * step;
            let vertex = (p.node % 4) == 0;
            if !vertex {
                assert!((p.normal[0] - mid.cos()).abs() < 1e-12);
                assert!((p.normal[1] - mid.sin()).abs() < 1e-12);
                let along_normal = p.position[0] * mid.cos() + p.position[1] * mid.sin();
                assert!((along_normal - r * (step / 2.0).cos()).abs() < 1e-12 * r);
            } else {
                // At a vertex: the average of the two chords' normals, radial.
                let t = p.node as f64 * step / 4.0;
                assert!((p.normal[0] - t.cos()).abs() < 1e-12);
                assert!(p.distance < 1e-12 * r);
            }
        }
        let e = find_pairs("arc", &host, &probe, &all, 0.85 * sagitta / chord)
            .unwrap_err()
            .to_string();
        assert!(e.contains(&format!("{} coupling node(s)", n)), "{e}");
    }
}
