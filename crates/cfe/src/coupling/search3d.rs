//! Pair search in 3D: for each coupling node of the node part, the host boundary
//! face nearest to it, through an R-tree over the host's boundary faces
//! (O(n log n), no all-pairs loop), and the 3D coupling element
//! (`CouplingElement<D3>`) of the node and that face.
//!
//! It takes the meshes as light slices ([`Surface`]: node coordinates and
//! boundary faces with their corners, owning element and local face index), so it
//! knows no mesh type. The rules, as in 2D ([`super::search`]):
//!
//! - **Tolerance.** Without a search distance a node pairs with a face within
//!   `tolerance × h` of it (h the face's longest edge, [`face_size`]); it is then
//!   moved onto its closest point X_C ([`move_onto_faces`]), and the move is
//!   reported (`distance`, the interface's largest). Nodes beyond every face are
//!   an error listing them. With a search distance d > 0 a node pairs with the
//!   nearest face within d, stays where it is and keeps its initial normal gap
//!   g₀ = (X − X_C) · n; a node with none is left unpaired (counted).
//! - **Facing.** With or without a search distance, only the host faces that
//!   *face* the node part's face at the node (`search::FACING_COSINE`) are its
//!   candidates, and only they enter its normal: a side of the host meeting
//!   the interface at its rim is about 90° off and is not the interface's face
//!   (without this, a node on the rim of two blocks of one footprint took the
//!   mean of the top's and the side's normals, 45° off, and a frictionless
//!   pair there pushed sideways). A node with no face of the node part (a
//!   point set) is not filtered. The plane search does the same within a
//!   search distance only; without one it keeps averaging every edge at a host
//!   vertex (unchanged, its results bit-identical).
//! - **Ties.** All candidate faces are measured first; the faces within 1e-12 × h
//!   of the smallest distance are tied (a node on an edge or a vertex shared by
//!   several faces), and the one of the lowest (host element, local face index)
//!   is taken — whatever order the tree returns them in.
//! - **Normal.** n is the chosen face's outward unit normal at X_C; when X_C is on
//!   an edge or at a vertex of it ([`super::face::FEATURE_TOLERANCE`]), the normalised mean of
//!   the outward unit normals, at X_C, of every host boundary face sharing that
//!   edge or vertex that faces the node, each face counted once — the 2D rule
//!   at a host vertex, one dimension up. The element's frame
//!   (`CouplingElement::frame`) is [`D3::frame`] of n.
//! - **Shape values.** The chosen face's, at X_C: barycentric on a triangle, the
//!   bilinear values at the natural coordinates of the projection on a
//!   quadrangle ([`closest_point`]). The element is the coupling node and the
//!   face's 3 or 4 corners (the off-face shape values of the host element vanish
//!   on its face).

use super::element::CouplingElement;
use super::face::{
    BoundaryFace, FaceObject, FacePoint, Feature, closest_point,
    corner_areas, face_size, unit,
};
use super::search::FACING_COSINE;
use crate::dim::{D3, Dim};
use crate::error::{Error, Result};
use rstar::RTree;
use std::collections::{HashMap, HashSet};

/// One side of an interface as the 3D search reads it: a part's node coordinates
/// and boundary faces (corners counter-clockwise seen from outside).
#[derive(Debug, Clone, Copy)]
pub struct Surface<'a> {
    /// The part's node coordinates.
    pub nodes: &'a [[f64; 3]],
    /// Its boundary faces (the host's: all of them, or those that may host; the
    /// node part's: those of the interface, or all — only faces whose corners
    /// all couple are read).
    pub faces: &'a [BoundaryFace],
}

impl Surface<'_> {
    /// The corner coordinates of face `f`.
    fn corners(&self, f: usize) -> Vec<[f64; 3]> {
        self.faces[f]
            .nodes
            .as_slice()
            .iter()
            .map(|&n| self.nodes[n])
            .collect()
    }
}

/// Two candidate faces are tied when their distances differ by at most this
/// fraction of the face's size.
pub const TIE_TOLERANCE: f64 = 1e-12;

/// The R-tree of a surface's faces ([`FaceObject`]: exact point–face distances)
/// and the largest face size.
fn face_tree(host: &Surface) -> (RTree<FaceObject>, f64) {
    let objects: Vec<FaceObject> = (0..host.faces.len())
        .map(|f| FaceObject::new(&host.corners(f), f))
        .collect();
    let max_size = objects
        .iter()
        .map(|o| face_size(o.corners()))
        .fold(0.0, f64::max);
    (RTree::bulk_load(objects), max_size)
}

/// A candidate host face of a node: its closest point, the face's index and size.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    at: FacePoint,
    face: usize,
    size: f64,
}

/// The deterministic choice among `candidates`: the smallest distance, and among
/// those within [`TIE_TOLERANCE`] × the face size of it, the lowest (element,
/// local face index).
fn choose(candidates: &[Candidate], faces: &[BoundaryFace]) -> Option<Candidate> {
    let least = candidates
        .iter()
        .map(|c| c.at.distance)
        .fold(f64::INFINITY, f64::min);
    candidates
        .iter()
        .filter(|c| c.at.distance <= least + TIE_TOLERANCE * c.size)
        .min_by_key(|c| (faces[c.face].element, faces[c.face].face, c.face))
        .copied()
}

/// Whether a host face of outward normal `host` faces a node-part face of outward
/// normal `face` ([`FACING_COSINE`]).
fn facing(host: [f64; 3], face: [f64; 3]) -> bool {
    host[0] * face[0] + host[1] * face[1] + host[2] * face[2] < -FACING_COSINE
}

/// The normalised mean of `normals`; `fallback` when they cancel.
fn mean_normal(normals: &[[f64; 3]], fallback: [f64; 3]) -> [f64; 3] {
    let s = normals.iter().fold([0.0; 3], |acc, n| {
        [acc[0] + n[0], acc[1] + n[1], acc[2] + n[2]]
    });
    let l = s[0].hypot(s[1]).hypot(s[2]);
    if l > 1e-12 {
        s.map(|v| v / l)
    } else {
        fallback
    }
}

/// The faces of `surface` whose corners are all in `nodes`, with, per node, the
/// outward normal there (the normalised mean of those faces' normals at the
/// node) and its share of their area (`∫ Nᵢ dA`, the tributary area).
fn node_side(surface: &Surface, nodes: &[usize]) -> (HashMap<usize, [f64; 3]>, HashMap<usize, f64>) {
    let set: HashSet<usize> = nodes.iter().copied().collect();
    let mut normals: HashMap<usize, Vec<[f64; 3]>> = HashMap::new();
    let mut areas: HashMap<usize, f64> = nodes.iter().map(|&n| (n, 0.0)).collect();
    for (f, face) in surface.faces.iter().enumerate() {
        let corners = face.nodes.as_slice();
        if !corners.iter().all(|n| set.contains(n)) {
            continue;
        }
        let x = surface.corners(f);
        let shares = corner_areas(&x);
        for (i, &n) in corners.iter().enumerate() {
            normals
                .entry(n)
                .or_default()
                .push(closest_point(&x, x[i]).normal);
            *areas.entry(n).or_default() += shares[i];
        }
    }
    let normals = normals
        .into_iter()
        .map(|(n, v)| (n, mean_normal(&v, v[0])))
        .collect();
    (normals, areas)
}

/// Finds one 3D coupling element per node in `nodes` (indices into
/// `node_part.nodes`), on the boundary faces of `host` (see the module's rules):
/// within `tolerance × face size` of a facing face, the node is paired to be moved onto
/// it (`search_distance` 0); within `search_distance` > 0 of a facing face, it is
/// paired where it is with its initial gap, and the nodes with none are counted
/// (second). Each element gets its tributary area on the node part's face (the
/// share of the faces of `node_part` whose corners all couple) and its host
/// face's size (`edge_length`).
///
/// Errors ([`Error::OrphanNodes`]): without a search distance, the nodes farther
/// than the tolerance from every host face, listed with their (x, y, z) and
/// nearest face.
///
/// ```
/// use cfe::coupling::face::{BoundaryFace, FaceNodes};
/// use cfe::coupling::search3d::{Surface, find_pairs_3d};
/// // A host's top face (a HEX8's face 5, z = 0) and a node 0.001 above it.
/// let host_nodes = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let faces = [BoundaryFace { nodes: FaceNodes::Quad([0, 1, 2, 3]), element: 0, face: 5 }];
/// let host = Surface { nodes: &host_nodes, faces: &faces };
/// let probe = [[0.25, 0.5, 0.001]];
/// let node_part = Surface { nodes: &probe, faces: &[] };
/// let (pairs, unpaired) = find_pairs_3d("top", host, node_part, &[0], 0.01, 0.0).unwrap();
/// assert_eq!(unpaired, 0);
/// let c = &pairs[0];
/// assert_eq!(c.host_nodes, [0, 1, 2, 3]);
/// // Bilinear values at (ξ, η) = (−0.5, 0): 3/8 at the corners x = 0, 1/8 at x = 1.
/// let want = [0.375, 0.125, 0.125, 0.375];
/// assert!((0..4).all(|i| (c.shape[i] - want[i]).abs() < 1e-12));
/// assert_eq!(c.normal, [0.0, 0.0, 1.0]);
/// assert!((c.distance - 0.001).abs() < 1e-15 && c.position[2].abs() < 1e-15);
/// ```
pub fn find_pairs_3d(
    interface: &str,
    host: Surface,
    node_part: Surface,
    nodes: &[usize],
    tolerance: f64,
    search_distance: f64,
) -> Result<(Vec<CouplingElement<D3>>, usize)> {
    let gaps = search_distance > 0.0;
    let (tree, max_size) = face_tree(&host);
    let sizes: Vec<f64> = (0..host.faces.len())
        .map(|f| face_size(&host.corners(f)))
        .collect();
    let radius = if gaps {
        search_distance
    } else {
        tolerance * max_size
    };
    let (face_normal, tributary) = node_side(&node_part, nodes);
    // The host faces at each host node.
    let mut at_node: HashMap<usize, Vec<usize>> = HashMap::new();
    for (f, face) in host.faces.iter().enumerate() {
        for &n in face.nodes.as_slice() {
            at_node.entry(n).or_default().push(f);
        }
    }
    let mut pairs = Vec::with_capacity(nodes.len());
    let mut orphans: Vec<Orphan> = Vec::new();
    let mut unpaired = 0;
    for &node in nodes {
        let p = node_part.nodes[node];
        // Only the host faces that face the node part's face at the node are
        // its face (a side of the host meeting the interface at its rim is not),
        // with or without a search distance.
        let faces_node = |n: [f64; 3]| face_normal.get(&node).is_none_or(|&f| facing(n, f));
        let candidates: Vec<Candidate> = tree
            .locate_within_distance(p, radius * radius)
            .filter_map(|o| {
                let at = closest_point(o.corners(), p);
                let size = sizes[o.index];
                let within = if gaps {
                    at.distance <= search_distance
                } else {
                    at.distance <= tolerance * size
                };
                (within && faces_node(at.normal)).then_some(Candidate {
                    at,
                    face: o.index,
                    size,
                })
            })
            .collect();
        let Some(best) = choose(&candidates, host.faces) else {
            if gaps {
                unpaired += 1;
            } else {
                let nearest = tree
                    .nearest_neighbor(p)
                    .map(|o| (closest_point(o.corners(), p).distance, sizes[o.index]));
                orphans.push((node, p, nearest));
            }
            continue;
        };
        let face = &host.faces[best.face];
        let corners = face.nodes.as_slice();
        let normal = feature_normal(&host, &at_node, &best, &faces_node);
        let position = best.at.point;
        let gap0 = if gaps {
            (0..3).map(|c| (p[c] - position[c]) * normal[c]).sum()
        } else {
            0.0
        };
        pairs.push(CouplingElement {
            node,
            host_element: face.element,
            host_nodes: corners.to_vec(),
            shape: best.at.shape[..corners.len()].to_vec(),
            normal,
            frame: D3::frame(normal),
            position,
            distance: best.at.distance,
            gap0,
            tributary: tributary.get(&node).copied().unwrap_or(0.0),
            edge_length: best.size,
            ring: 1.0,
            segment: None,
        });
    }
    if !orphans.is_empty() {
        return Err(orphan_error(interface, &orphans, tolerance));
    }
    Ok((pairs, unpaired))
}

/// The distance from the nearest of the coupling nodes `nodes` of `node_part`
/// to the nearest boundary face of `host` (an R-tree nearest-neighbour query
/// per node: O(n log m)), for the message of an interface that found no pair;
/// `None` without nodes or faces.
pub fn nearest_face_distance(host: Surface, node_part: Surface, nodes: &[usize]) -> Option<f64> {
    if host.faces.is_empty() {
        return None;
    }
    let (tree, _) = face_tree(&host);
    nodes
        .iter()
        .filter_map(|&n| {
            let p = node_part.nodes[n];
            tree.nearest_neighbor(p)
                .map(|o| closest_point(o.corners(), p).distance)
        })
        .reduce(f64::min)
}

/// The normal of a pair on face `best.face` at its closest point: the face's own
/// inside it; on an edge or at a vertex, the normalised mean over the host faces
/// sharing that edge or vertex (those that `faces_node` accepts) of their normals
/// at the point — each face's normal at its own closest point to X_C, which is
/// X_C itself.
fn feature_normal(
    host: &Surface,
    at_node: &HashMap<usize, Vec<usize>>,
    best: &Candidate,
    faces_node: &dyn Fn([f64; 3]) -> bool,
) -> [f64; 3] {
    let corners = host.faces[best.face].nodes.as_slice();
    let shared: Vec<usize> = match best.at.feature {
        Feature::Inside => return best.at.normal,
        Feature::Vertex(a) => at_node[&corners[a]].clone(),
        Feature::Edge(a, b) => {
            let other = &at_node[&corners[b]];
            at_node[&corners[a]]
                .iter()
                .copied()
                .filter(|f| other.contains(f))
                .collect()
        }
    };
    let normals: Vec<[f64; 3]> = shared
        .iter()
        .map(|&f| closest_point(&host.corners(f), best.at.point).normal)
        .filter(|&n| faces_node(n))
        .collect();
    unit(mean_normal(&normals, best.at.normal))
}

/// Moves each coupling node of `elements` onto its host face (its closest point
/// X_C there) in the node part's coordinates `nodes`, and gives the largest move
/// (what the run reports). A node already on its face does not move (to
/// round-off).
pub fn move_onto_faces(nodes: &mut [[f64; 3]], elements: &[CouplingElement<D3>]) -> f64 {
    let mut largest = 0.0f64;
    for c in elements {
        nodes[c.node] = c.position;
        largest = largest.max(c.distance);
    }
    largest
}

/// A coupling node on no host face: its index, its position and, when there is
/// one, the distance to the nearest host face and that face's size.
type Orphan = (usize, [f64; 3], Option<(f64, f64)>);

/// The error listing the coupling nodes on no host face within the tolerance:
/// (node, position, nearest (distance, face size)).
fn orphan_error(interface: &str, orphans: &[Orphan], tolerance: f64) -> Error {
    let list = crate::error::short_list(orphans.iter().map(|(n, p, near)| match near {
        Some((d, h)) => format!(
            "node {n} at ({}, {}, {}) (nearest host face {d:.4e} away, {:.3} × its size {h:.4e})",
            p[0],
            p[1],
            p[2],
            d / h
        ),
        None => format!("node {n} at ({}, {}, {})", p[0], p[1], p[2]),
    }));
    Error::OrphanNodes {
        interface: interface.to_string(),
        nodes: orphans.iter().map(|(n, p, _)| (*n, p.to_vec())).collect(),
        message: format!(
            "{} coupling node(s) lie on no host boundary face within the tolerance {} × face size: {} — check that the interface's boundary faces the host, or raise `tolerance` if the faces are meshed apart (curved faces: about (face size)² / (8 × radius))",
            orphans.len(),
            tolerance,
            list
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::super::face::FaceNodes;
    use super::*;

    /// The brute-force search (every face measured, the same tie rule): the
    /// truth the R-tree search is compared with.
    fn brute_force(host: &Surface, p: [f64; 3], tolerance: f64) -> Option<Candidate> {
        let candidates: Vec<Candidate> = (0..host.faces.len())
            .map(|f| {
                let x = host.corners(f);
                Candidate {
                    at: closest_point(&x, p),
                    face: f,
                    size: face_size(&x),
                }
            })
            .filter(|c| c.at.distance <= tolerance * c.size)
            .collect();
        choose(&candidates, host.faces)
    }

    /// A cylinder of radius r, axis z, from z = 0 to `height`, meshed with `m`
    /// sectors and `k` rows of quadrangles each split into two triangles (faces
    /// counter-clockwise seen from outside: outward normals radial); element = the
    /// quadrangle's index, face = 0 or 1.
    fn cylinder(r: f64, height: f64, m: usize, k: usize) -> (Vec<[f64; 3]>, Vec<BoundaryFace>) {
        let step = std::f64::consts::TAU / m as f64;
        let mut nodes = Vec::new();
        for j in 0..=k {
            for i in 0..m {
                let t = i as f64 * step;
                nodes.push([r * t.cos(), r * t.sin(), height * j as f64 / k as f64]);
            }
        }
        let id = |i: usize, j: usize| j * m + i % m;
        let mut faces = Vec::new();
        for j in 0..k {
            for i in 0..m {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                let element = j * m + i;
                faces.push(BoundaryFace {
                    nodes: FaceNodes::Tri([a, b, c]),
                    element,
                    face: 0,
                });
                faces.push(BoundaryFace {
                    nodes: FaceNodes::Tri([a, c, d]),
                    element,
                    face: 1,
                });
            }
        }
        (nodes, faces)
    }

    /// A small deterministic generator of numbers in [0, 1).
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A curved host: points on a cylinder of radius 20 meshed with 24 sectors of
    /// triangles pair with the closest face (the brute force's), within the
    /// chords' sagitta h²/(8r) (h the sector's chord) and so within a tolerance of
    /// 0.05 × the face size, land on that face (their position reproduced by the
    /// shape values, inside the cylinder), and take a normal within the sector's
    /// half-angle of the radial direction.
    #[test]
    fn a_curved_host_pairs_with_the_closest_face() {
        let (r, m) = (20.0f64, 24);
        let (nodes, faces) = cylinder(r, 10.0, m, 4);
        let host = Surface {
            nodes: &nodes,
            faces: &faces,
        };
        let mut seed = 7;
        let probe: Vec<[f64; 3]> = (0..300)
            .map(|_| {
                let t = std::f64::consts::TAU * uniform(&mut seed);
                [r * t.cos(), r * t.sin(), 10.0 * uniform(&mut seed)]
            })
            .collect();
        let all: Vec<usize> = (0..probe.len()).collect();
        let node_part = Surface {
            nodes: &probe,
            faces: &[],
        };
        let (pairs, _) = find_pairs_3d("cyl", host, node_part, &all, 0.05, 0.0).unwrap();
        let half = std::f64::consts::PI / m as f64;
        let sagitta = r * (1.0 - half.cos());
        for c in &pairs {
            let p = probe[c.node];
            let truth = brute_force(&host, p, 0.05).unwrap();
            assert_eq!(faces[truth.face].element, c.host_element);
            assert!((truth.at.distance - c.distance).abs() < 1e-13 * r);
            assert!(c.distance <= sagitta * (1.0 + 1e-12), "{} > {sagitta}", c.distance);
            let x: [f64; 3] = std::array::from_fn(|k| {
                (0..c.shape.len())
                    .map(|i| c.shape[i] * nodes[c.host_nodes[i]][k])
                    .sum()
            });
            assert!((0..3).all(|k| (x[k] - c.position[k]).abs() < 1e-12 * r));
            assert!(c.position[0].hypot(c.position[1]) <= r * (1.0 + 1e-14));
            let radial = unit([p[0], p[1], 0.0]);
            let cos: f64 = (0..3).map(|k| radial[k] * c.normal[k]).sum();
            assert!(cos >= (2.0 * half).cos() - 1e-12, "{cos}");
        }
        // A tolerance below the sagitta's share of the face loses the nodes
        // farthest from the chords: the typed error lists them.
        let e = find_pairs_3d("cyl", host, node_part, &all, 0.001, 0.0).unwrap_err();
        let Error::OrphanNodes {
            interface,
            nodes: orphans,
            ..
        } = &e
        else {
            panic!("unexpected error {e:?}");
        };
        assert_eq!(interface, "cyl");
        // Each orphan is named with its three coordinates, as given.
        assert!(!orphans.is_empty());
        for (n, x) in orphans {
            assert_eq!(x.as_slice(), &node_part.nodes[*n][..]);
        }
        assert!(e.to_string().contains("nearest host face"), "{e}");
    }

    /// The R-tree search gives the brute force's host, face and distance for every
    /// point of a random cloud around the cylinder (inside, outside, beyond its
    /// ends), with a generous tolerance so that many faces are candidates.
    #[test]
    fn the_tree_finds_the_brute_forces_hosts() {
        let (nodes, faces) = cylinder(5.0, 8.0, 10, 3);
        let host = Surface {
            nodes: &nodes,
            faces: &faces,
        };
        let mut seed = 11;
        let cloud: Vec<[f64; 3]> = (0..500)
            .map(|_| {
                let t = std::f64::consts::TAU * uniform(&mut seed);
                let rho = 5.0 * (0.7 + 0.6 * uniform(&mut seed));
                [rho * t.cos(), rho * t.sin(), -1.0 + 10.0 * uniform(&mut seed)]
            })
            .collect();
        let all: Vec<usize> = (0..cloud.len()).collect();
        let tolerance = 0.6;
        let node_part = Surface {
            nodes: &cloud,
            faces: &[],
        };
        let mut found = 0;
        for &n in &all {
            let truth = brute_force(&host, cloud[n], tolerance);
            let got = find_pairs_3d("cloud", host, node_part, &[n], tolerance, 0.0);
            match (truth, got) {
                (Some(t), Ok((pairs, _))) => {
                    let c = &pairs[0];
                    assert_eq!(faces[t.face].element, c.host_element);
                    assert_eq!(faces[t.face].nodes.as_slice(), &c.host_nodes[..]);
                    assert_eq!(t.at.distance, c.distance);
                    found += 1;
                }
                (None, Err(Error::OrphanNodes { .. })) => {}
                (t, g) => panic!("node {n}: brute force {t:?}, tree {g:?}"),
            }
        }
        assert!(found > 300, "{found}");
    }

    /// Ties are broken by (element, local face index), whatever the order of the
    /// face list: a node on the diagonal shared by the two triangles of a square
    /// goes to local face 0; a node at the square's centre vertex shared by four
    /// elements' faces goes to the lowest element; its normal is the faces'
    /// common one.
    #[test]
    fn a_node_on_a_shared_edge_or_vertex_gets_the_deterministic_host() {
        // A 2 × 2 grid of unit squares on z = 0, each split along its diagonal.
        let nodes: Vec<[f64; 3]> = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64, 0.0]).collect();
        let mut faces = Vec::new();
        for (e, (i, j)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
            let id = |a: usize, b: usize| 3 * (j + b) + i + a;
            let element = 10 + e;
            faces.push(BoundaryFace {
                nodes: FaceNodes::Tri([id(0, 0), id(1, 0), id(1, 1)]),
                element,
                face: 0,
            });
            faces.push(BoundaryFace {
                nodes: FaceNodes::Tri([id(0, 0), id(1, 1), id(0, 1)]),
                element,
                face: 1,
            });
        }
        let probe = [[0.3, 0.3, 0.0], [1.0, 1.0, 1e-9], [1.5, 1.0, 0.0]];
        let node_part = Surface {
            nodes: &probe,
            faces: &[],
        };
        let mut orders = vec![faces.clone(), faces.iter().rev().copied().collect()];
        let mut shuffled = faces.clone();
        shuffled.swap(0, 5);
        shuffled.swap(2, 7);
        orders.push(shuffled);
        for list in &orders {
            let host = Surface {
                nodes: &nodes,
                faces: list,
            };
            let (pairs, _) = find_pairs_3d("tie", host, node_part, &[0, 1, 2], 1e-6, 0.0).unwrap();
            // The diagonal of element 10 (nodes 0–4): local face 0, [0, 1, 4].
            assert_eq!((pairs[0].host_element, &pairs[0].host_nodes[..]), (10, &[0, 1, 4][..]));
            // The centre node 4: element 10's local face 0; shape 1 there.
            assert_eq!((pairs[1].host_element, &pairs[1].host_nodes[..]), (10, &[0, 1, 4][..]));
            assert!((pairs[1].shape[2] - 1.0).abs() < 1e-12);
            // The edge between elements 11 and 13 (nodes 4–5): element 11.
            assert_eq!(pairs[2].host_element, 11);
            for c in &pairs {
                assert_eq!(c.normal, [0.0, 0.0, 1.0]);
            }
        }
    }

    /// The corner of a cube's face (three faces meet): the normal is the mean of
    /// the three faces' normals, (1, 1, 1)/√3; on an edge of two faces, the mean
    /// of two, (1, 0, 1)/√2.
    #[test]
    fn the_normal_at_a_host_edge_or_vertex_is_averaged() {
        let nodes: Vec<[f64; 3]> = (0..8)
            .map(|k| [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64])
            .collect();
        // The faces x = 1, y = 1, z = 1 of the unit cube (element 0), outward.
        let faces = [
            BoundaryFace {
                nodes: FaceNodes::Quad([1, 3, 7, 5]),
                element: 0,
                face: 2,
            },
            BoundaryFace {
                nodes: FaceNodes::Quad([2, 6, 7, 3]),
                element: 0,
                face: 3,
            },
            BoundaryFace {
                nodes: FaceNodes::Quad([4, 5, 7, 6]),
                element: 0,
                face: 5,
            },
        ];
        let host = Surface {
            nodes: &nodes,
            faces: &faces,
        };
        let probe = [[1.0, 1.0, 1.0], [1.0, 0.5, 1.0]];
        let node_part = Surface {
            nodes: &probe,
            faces: &[],
        };
        let (pairs, _) = find_pairs_3d("cube", host, node_part, &[0, 1], 1e-6, 0.0).unwrap();
        let s3 = 1.0 / 3.0f64.sqrt();
        let s2 = 0.5f64.sqrt();
        assert!((0..3).all(|k| (pairs[0].normal[k] - s3).abs() < 1e-15), "{:?}", pairs[0].normal);
        let want = [s2, 0.0, s2];
        assert!((0..3).all(|k| (pairs[1].normal[k] - want[k]).abs() < 1e-15), "{:?}", pairs[1].normal);
        assert_eq!(pairs[1].host_element, 0);
        assert_eq!(pairs[1].host_nodes, [1, 3, 7, 5]);
    }

    /// A structured block [0, 1]² × [z0, z1] of `n × n × 1` HEX8 cells: its node
    /// coordinates and all its boundary faces, outward (local faces 0: z = z0,
    /// 5: z = z1, 1–4 the sides), or with `tri` its top and bottom faces split
    /// into triangles.
    fn block(n: usize, z: [f64; 2], tri: bool) -> (Vec<[f64; 3]>, Vec<BoundaryFace>) {
        let h = 1.0 / n as f64;
        let id = |i: usize, j: usize, k: usize| k * (n + 1) * (n + 1) + j * (n + 1) + i;
        let mut nodes = Vec::new();
        for zk in z {
            for j in 0..=n {
                for i in 0..=n {
                    nodes.push([i as f64 * h, j as f64 * h, zk]);
                }
            }
        }
        let mut faces = Vec::new();
        let mut push = |nodes4: [usize; 4], element: usize, local: usize, split: bool| {
            if split {
                let [a, b, c, d] = nodes4;
                faces.push(BoundaryFace { nodes: FaceNodes::Tri([a, b, c]), element, face: local });
                faces.push(BoundaryFace { nodes: FaceNodes::Tri([a, c, d]), element, face: local + 10 });
            } else {
                faces.push(BoundaryFace { nodes: FaceNodes::Quad(nodes4), element, face: local });
            }
        };
        for j in 0..n {
            for i in 0..n {
                let e = j * n + i;
                push([id(i, j, 0), id(i, j + 1, 0), id(i + 1, j + 1, 0), id(i + 1, j, 0)], e, 0, tri);
                push([id(i, j, 1), id(i + 1, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1)], e, 5, tri);
                if j == 0 {
                    push([id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 0, 1), id(i, 0, 1)], e, 1, false);
                }
                if i == n - 1 {
                    push([id(n, j, 0), id(n, j + 1, 0), id(n, j + 1, 1), id(n, j, 1)], e, 2, false);
                }
                if j == n - 1 {
                    push([id(i + 1, n, 0), id(i, n, 0), id(i, n, 1), id(i + 1, n, 1)], e, 3, false);
                }
                if i == 0 {
                    push([id(0, j + 1, 0), id(0, j, 0), id(0, j, 1), id(0, j + 1, 1)], e, 4, false);
                }
            }
        }
        (nodes, faces)
    }

    /// A flat 3D contact patch: a block of 3 × 3 HEX8 cells (top z = 0) hosts the
    /// bottom face of a block above it meshed with 5 × 5 cells split into
    /// triangles (non-matching). Within a search distance every bottom node finds
    /// a host face — the top's, never a side face (they do not face it) — with
    /// g₀ = 0, normal +z and its tributary areas summing to the patch's area 1;
    /// without one, every node pairs at distance 0 (to round-off).
    #[test]
    fn a_flat_contact_patch_of_non_matching_faces_pairs_with_zero_gap() {
        let (host_nodes, host_faces) = block(3, [-1.0, 0.0], false);
        let (top_nodes, top_faces) = block(5, [0.0, 0.5], true);
        let bottom: Vec<usize> = (0..top_nodes.len()).filter(|&k| top_nodes[k][2] == 0.0).collect();
        assert_eq!(bottom.len(), 36);
        let host = Surface {
            nodes: &host_nodes,
            faces: &host_faces,
        };
        let node_part = Surface {
            nodes: &top_nodes,
            faces: &top_faces,
        };
        let (pairs, unpaired) = find_pairs_3d("patch", host, node_part, &bottom, 0.05, 0.1).unwrap();
        assert_eq!((pairs.len(), unpaired), (36, 0));
        let mut area = 0.0;
        for c in &pairs {
            assert_eq!(c.gap0, 0.0);
            assert_eq!(c.normal, [0.0, 0.0, 1.0]);
            assert_eq!(c.host_nodes.len(), 4);
            assert!(c.host_nodes.iter().all(|&n| host_nodes[n][2] == 0.0));
            assert!((c.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            area += c.tributary;
        }
        assert!((area - 1.0).abs() < 1e-14, "{area}");
        let (tied, _) = find_pairs_3d("patch", host, node_part, &bottom, 1e-6, 0.0).unwrap();
        assert!(tied.iter().all(|c| c.distance < 1e-15) && tied.len() == 36);
        // Lifted by 0.01: the same hosts, g₀ = 0.01.
        let lifted: Vec<[f64; 3]> = top_nodes.iter().map(|p| [p[0], p[1], p[2] + 0.01]).collect();
        let node_part = Surface {
            nodes: &lifted,
            faces: &top_faces,
        };
        let (gapped, _) = find_pairs_3d("patch", host, node_part, &bottom, 0.05, 0.1).unwrap();
        for (a, b) in gapped.iter().zip(&pairs) {
            assert_eq!(a.host_element, b.host_element);
            assert!((a.gap0 - 0.01).abs() < 1e-15);
        }
        let mut moved = lifted.clone();
        let largest = move_onto_faces(&mut moved, &gapped);
        assert!((largest - 0.01).abs() < 1e-15);
        assert!(bottom.iter().all(|&n| moved[n][2].abs() < 1e-15));
    }
}
