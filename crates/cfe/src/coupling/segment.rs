//! Segment coupling (`coupling = "segment"`): the gap of each coupling node is
//! integrated over its face segments instead of collocated at the node, so a
//! constant traction passes a tied interface exactly whatever the two meshes (the
//! patch test), still with one coupling element per coupling node and no added
//! unknown.
//!
//! For coupling node a with face shape function N_a (the hat function on the node
//! part's face) the element's jump is the weighted mean jump
//! `[[U]]_a = ∫ N_a (u_node − u_host) ds / m_a`, `m_a = ∫ N_a ds`, which is linear
//! in the displacements of a, its face neighbours and the host nodes under its
//! segments: `[[U]]_a = Σ_b M̂_ab D_b − Σ_i N̂_ai D_i` with `M̂_ab = ∫ N_a N_b / m_a`
//! and `N̂_ai = ∫ N_a N̄_i / m_a` (both rows sum to 1). Its penalty is
//! `ω_a c`, `ω_a = m_a / h̄` (h̄ the mean face-segment length): the traction penalty
//! is κ = c / h̄, so `c_n`, `c_s` keep their meaning (the stiffness of a coupling
//! node of a uniformly meshed face), and the element carries the force
//! `f_a = m_a κ [[u]]_a`. The normal is the N_a-weighted mean of the host edges'
//! normals. docs/method.md §2b derives it and when it reduces to the node CFE.
//!
//! The integrals are exact: the face segments are cut at the projections of the
//! host's vertices, so on each piece both sides are linear (the node side on its
//! segment, the host on one boundary edge) and 2 Gauss points per piece integrate
//! `N_a N_b` and `N_a N̄_i` exactly. The host's shape functions are taken at the
//! Gauss point itself — extrapolated where a face segment cuts a corner of a
//! curved host face — so no linear displacement field has a jump.
//!
//! With initial gaps (a search distance) each point's gap is measured between
//! the two faces' curves (the cubic through each edge's ends with the face's
//! vertex normals, [`curve_offset`]), not between their polygons: on curved faces
//! meshed apart the polygons' overlap alternates from node to node by a chord's
//! sagitta, which alone opens every other pair of a shrink fit.

use super::element::{CouplingElement, MAX_NODES, SegmentSide};
use super::search::{edge_normal, edge_tree, face_normals, facing, project, shape_at};
use crate::dim::{D2, Dim};
use crate::error::{Error, Result};
use crate::mesh::{BoundaryEdge, Mesh, dist};
use rstar::AABB;
use std::collections::{HashMap, HashSet};

/// Projections of host vertices closer than this fraction of a face segment to one
/// of its ends, or to each other, are merged (no sliver sub-segments).
const MERGE: f64 = 1e-9;

/// A host boundary vertex where two boundary edges meet with their normals less
/// than this angle apart is a point of a smooth curve that the host's polygon
/// approximates (an arc meshed by chords); a sharper one is a corner of the host.
/// Only with initial gaps (see [`curve_offset`]).
pub const SMOOTH_TURN: f64 = std::f64::consts::PI / 6.0;

/// From a face's oriented edges (nodes, outward normal): the bisector at each
/// vertex (the normalised sum of the normals of the edges meeting there), and the
/// vertices where the face is taken as a smooth curve — exactly two edges whose
/// normals are less than [`SMOOTH_TURN`] apart — with that curve's normal there,
/// the bisector.
fn vertex_normals(
    edges: impl Iterator<Item = ([usize; 2], [f64; 2])>,
) -> (HashMap<usize, [f64; 2]>, HashMap<usize, [f64; 2]>) {
    let mut at: HashMap<usize, Vec<[f64; 2]>> = HashMap::new();
    for (nodes, n) in edges {
        for v in nodes {
            at.entry(v).or_default().push(n);
        }
    }
    let mut bisectors = HashMap::with_capacity(at.len());
    let mut smooth = HashMap::with_capacity(at.len());
    for (v, normals) in at {
        let s = normals
            .iter()
            .fold([0.0, 0.0], |s, n| [s[0] + n[0], s[1] + n[1]]);
        let l = s[0].hypot(s[1]);
        if l <= 1e-12 {
            continue;
        }
        let bisector = [s[0] / l, s[1] / l];
        if let [n1, n2] = normals[..]
            && n1[0] * n2[0] + n1[1] * n2[1] >= SMOOTH_TURN.cos()
        {
            smooth.insert(v, bisector);
        }
        bisectors.insert(v, bisector);
    }
    (bisectors, smooth)
}

/// The 2-point Gauss rule on [0, 1]: (abscissa, weight).
const GAUSS2: [(f64, f64); 2] = [
    (0.5 - 0.5 / SQRT3, 0.5),
    (0.5 + 0.5 / SQRT3, 0.5),
];
/// The 3-point Gauss rule on [0, 1]: (abscissa, weight), exact to degree 5.
const GAUSS3: [(f64, f64); 3] = [
    (0.5 - 0.5 * SQRT_3_5, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.5 + 0.5 * SQRT_3_5, 5.0 / 18.0),
];
const SQRT3: f64 = 1.732_050_807_568_877_2;
/// √(3/5).
const SQRT_3_5: f64 = 0.774_596_669_241_483_4;

/// The offset, along the edge's outward normal, of the host face's curve from
/// its chord `[p, q]` at the edge's parameter `xi` ∈ [0, 1]: the cubic (Hermite)
/// curve through p and q whose normals there are `n_p`, `n_q`,
/// `c(ξ) = L (σ_p ξ(1 − ξ)² − σ_q ξ²(1 − ξ))` with the end slopes
/// `σ = −(n · t_e) / (n · n_e)` (t_e the edge's direction, n_e its normal, L its
/// length). 0 where both ends' normals are the edge's (a flat face, a corner). On
/// a circle of radius R meshed by chords with their vertices' radial normals it is
/// the arc's offset to O(L⁴/R³): its middle is off the chord by the sagitta
/// L²/(8R). Initial gaps are measured to this curve, not to the chord, so that a
/// curved host face meshed coarser than the node part's does not give
/// alternating gaps (the chord's sagitta) to the coupling nodes.
pub fn curve_offset([p, q]: [[f64; 2]; 2], [n_p, n_q]: [[f64; 2]; 2], xi: f64) -> f64 {
    let l = dist(p, q);
    let t = [(q[0] - p[0]) / l, (q[1] - p[1]) / l];
    let n = edge_normal([p, q]);
    let slope = |v: [f64; 2]| -(v[0] * t[0] + v[1] * t[1]) / (v[0] * n[0] + v[1] * n[1]);
    let (sp, sq) = (slope(n_p), slope(n_q));
    l * xi * (1.0 - xi) * (sp * (1.0 - xi) - sq * xi)
}

/// The normals at an edge's two ends that its curve ([`curve_offset`]) takes,
/// from the edge's own normal `n_e` and the curve's normal at each end where the
/// face is smooth there (`None` at a corner or the face's end). Where one end is
/// smooth and the other is not, the curve keeps its curvature up to the corner:
/// the corner's normal is the smooth end's reflected about the edge's normal,
/// 2 (n_e · n) n_e − n (on a circle meshed by chords, the radial direction at the
/// corner; on a flat face n = n_e, so nothing changes). With neither end smooth
/// the edge is straight (both normals n_e).
fn end_normals(n_e: [f64; 2], ends: [Option<[f64; 2]>; 2]) -> [[f64; 2]; 2] {
    let reflect = |n: [f64; 2]| {
        let d = 2.0 * (n_e[0] * n[0] + n_e[1] * n[1]);
        [d * n_e[0] - n[0], d * n_e[1] - n[1]]
    };
    match ends {
        [Some(p), Some(q)] => [p, q],
        [Some(p), None] => [p, reflect(p)],
        [None, Some(q)] => [reflect(q), q],
        [None, None] => [n_e, n_e],
    }
}

/// The face segments of the node part on an interface: the edges of the named
/// `boundary` of `node_mesh` (whose nodes are the interface's coupling nodes), as
/// node pairs in ascending order (none when there is no such boundary).
pub fn face_segments(node_mesh: &Mesh, boundary: &str) -> Vec<[usize; 2]> {
    let mut segments: Vec<[usize; 2]> = node_mesh
        .boundaries
        .get(boundary)
        .map(|edges| edges.iter().map(|e| e.nodes).collect())
        .unwrap_or_default();
    segments.sort_unstable();
    segments.dedup();
    segments
}

/// A Gauss point of the face: where it lies on which face segment, its weight,
/// and the host element under it with its shape functions and normal there.
struct Point {
    /// The face segment's nodes a, b and their shape functions at the point.
    segment: [usize; 2],
    n: [f64; 2],
    /// Gauss weight × sub-segment length.
    w: f64,
    /// The point's x, its radius r in an axisymmetric model.
    r: f64,
    element: usize,
    host_nodes: Vec<usize>,
    host_shape: Vec<f64>,
    normal: [f64; 2],
    /// Distance from the point to the host edge.
    distance: f64,
    /// Initial normal gap (X − P) · n to its projection P on the host edge (0
    /// for touching faces).
    gap0: f64,
}

/// The segment coupling elements of an interface, one per coupling node a with a
/// face segment over the host (in the order of `nodes`, the nodes of the node
/// part's `boundary`): the gap integrated over
/// a's face segments with weight N_a (see the module doc and
/// [`super::element::SegmentSide`]). The integrals are evaluated at two Gauss
/// points on every piece of the node part's face segments (the edges of
/// `boundary`) cut at the host's vertices, over the
/// host boundary edge within `tolerance` × its length. Call it once the coupling
/// nodes lie on the host boundary (after the node search has moved them there).
/// Errors: coupling nodes that form no face segment; a node whose segments lie
/// over more host elements than a coupling element holds (the node part's face is
/// much coarser than the host's: swap host and node part).
pub fn segment_elements(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    boundary: &str,
    nodes: &[usize],
    tolerance: f64,
) -> Result<Vec<CouplingElement>> {
    segment_elements_within(
        interface,
        host,
        node_mesh,
        boundary,
        nodes,
        tolerance,
        0.0,
        FaceMeasure::Length,
    )
    .map(|(elements, _)| elements)
}

/// The measure of the interface face the segment coupling integrates over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaceMeasure {
    /// A plane model: length along the face, ds (the thickness applies apart).
    Length,
    /// An axisymmetric model (x = r): the ring's area, 2πr ds. Each element's
    /// averages are then r-weighted, `M̂_ab = ∫ N_a N_b r ds / ∫ N_a r ds` (and
    /// so N̂_ai, the normal, g₀), and its ring is `2π ∫ N_a r ds / ∫ N_a ds`, so
    /// that Σ_a ω_a M̂_ab is the ring integral ∫ N_b 2πr ds for every node b:
    /// a node on the axis (r = 0) takes its consistent share of the face's
    /// force, as away from it. A share of the face lying on the axis has no area
    /// and gets no element.
    Ring,
}

/// As [`segment_elements`] when `search_distance` is 0 (faces that touch, nodes
/// already moved onto the host). With a search distance d > 0 (a length) the
/// faces may be apart or overlap and nothing is moved: every piece of a face
/// segment takes the host boundary edge nearest to its midpoint, the segments
/// being cut where that choice or the projection's clamping can change (the lines
/// through the host's vertices along their edges' normals and along the vertices'
/// bisectors); each Gauss point X is tied to its projection P on that edge (the
/// host's shape functions are taken at P) and carries the pointwise initial gap
/// `g₀(X) = (X − P) · n_e` (n_e the edge's outward normal; > 0 apart, < 0
/// overlapping), measured between the two faces' curves rather than their
/// polygons (plus the node face's and minus the host face's [`curve_offset`]).
/// The element's initial gap is the N_a-weighted mean
/// `g₀_a = ∫ N_a g₀ ds / m_a`, with the weight of its averaged jump. A coupling node
/// with a Gauss point on its face segments farther than d from every host edge is
/// left unpaired, as the node coupling leaves a node beyond d; their number is
/// returned second (0 when d = 0, where the node search has placed every node).
/// `measure` is the face's ([`FaceMeasure`]): its ring in an axisymmetric model.
#[allow(clippy::too_many_arguments)]
pub fn segment_elements_within(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    boundary: &str,
    nodes: &[usize],
    tolerance: f64,
    search_distance: f64,
    measure: FaceMeasure,
) -> Result<(Vec<CouplingElement>, usize)> {
    let segments = face_segments(node_mesh, boundary);
    if segments.is_empty() {
        return Err(Error::Coupling {
            interface: interface.to_string(),
            message: format!(
                "`coupling = \"segment\"` integrates over the node part's face, but its boundary '{boundary}' has no edge for its {} coupling node(s); name a boundary made of edges, or use `coupling = \"node\"`",
                nodes.len()
            ),
        });
    }
    let x = |n: usize| node_mesh.nodes[n];
    let mean_length =
        segments.iter().map(|&[a, b]| dist(x(a), x(b))).sum::<f64>() / segments.len() as f64;
    let gaps = search_distance > 0.0;
    let reach = if gaps {
        Reach::Distance(search_distance)
    } else {
        Reach::Tolerance(tolerance)
    };
    let (points, unreached) = gauss_points(interface, host, node_mesh, boundary, &segments, reach)?;

    // Accumulate, per coupling node a: m_a, ∫ N_a N_b, ∫ N_a N̄_i, ∫ N_a n, each
    // r-weighted in an axisymmetric model (then also ∫ N_a r ds, `mr`; in a plane
    // model every weight ρ is 1 and `mr` is m_a).
    #[derive(Default)]
    struct Acc {
        m: f64,
        mr: f64,
        side: Vec<(usize, f64)>,
        host: Vec<(usize, f64)>,
        normal: [f64; 2],
        element: (f64, usize),
        distance: f64,
        gap0: f64,
    }
    fn add(list: &mut Vec<(usize, f64)>, id: usize, v: f64) {
        match list.iter_mut().find(|(i, _)| *i == id) {
            Some(e) => e.1 += v,
            None => list.push((id, v)),
        }
    }
    let mut acc: HashMap<usize, Acc> = HashMap::with_capacity(nodes.len());
    let ring = measure == FaceMeasure::Ring;
    for p in &points {
        let rho = if ring { p.r } else { 1.0 };
        for (k, &a) in p.segment.iter().enumerate() {
            let wa = p.w * p.n[k];
            // The weight of the averages: N_a ds, or N_a r ds on a ring.
            let wr = wa * rho;
            let e = acc.entry(a).or_default();
            e.m += wa;
            e.mr += wr;
            for (&b, &nb) in p.segment.iter().zip(&p.n) {
                add(&mut e.side, b, wr * nb);
            }
            for (&i, &ni) in p.host_nodes.iter().zip(&p.host_shape) {
                add(&mut e.host, i, wr * ni);
            }
            e.normal = [
                e.normal[0] + wr * p.normal[0],
                e.normal[1] + wr * p.normal[1],
            ];
            if wr > e.element.0 {
                e.element = (wr, p.element);
            }
            e.distance = e.distance.max(p.distance);
            e.gap0 += wr * p.gap0;
        }
    }
    let mut elements = Vec::with_capacity(nodes.len());
    for &a in nodes {
        if unreached.contains(&a) {
            continue;
        }
        let Some(e) = acc.remove(&a) else { continue };
        if e.m <= 1e-12 * mean_length {
            continue;
        }
        // A share of the face on the axis (r = 0 all along) sweeps no area.
        if ring && e.mr <= 1e-12 * e.m * mean_length {
            continue;
        }
        let mut side = e.side;
        side.sort_unstable_by_key(|&(b, _)| b);
        let mut host_coef = e.host;
        host_coef.retain(|&(_, v)| v.abs() > 1e-13 * e.mr);
        host_coef.sort_unstable_by_key(|&(i, _)| i);
        if side.len() + host_coef.len() > MAX_NODES {
            return Err(Error::Coupling {
                interface: interface.to_string(),
                message: format!(
                    "with `coupling = \"segment\"`, coupling node {a} at ({}, {}) ties {} host nodes under its face segments, more than a coupling element holds ({}); the node part's face is much coarser than the host's there — make the finer part the node part, or use `coupling = \"node\"`",
                    x(a)[0],
                    x(a)[1],
                    host_coef.len(),
                    MAX_NODES - side.len()
                ),
            });
        }
        let l = e.normal[0].hypot(e.normal[1]);
        elements.push(CouplingElement {
            node: a,
            host_element: e.element.1,
            host_nodes: host_coef.iter().map(|&(i, _)| i).collect(),
            shape: host_coef.iter().map(|&(_, v)| v / e.mr).collect(),
            normal: [e.normal[0] / l, e.normal[1] / l],
            frame: D2::frame([e.normal[0] / l, e.normal[1] / l]),
            position: x(a),
            distance: e.distance,
            // The N_a-weighted mean of the pointwise initial gap (0 without a
            // search distance: the faces touch).
            gap0: if gaps { e.gap0 / e.mr } else { 0.0 },
            tributary: e.m,
            // The geometrically linear limit's scale: the face's mean segment.
            edge_length: mean_length,
            // 2π r̄ with r̄ = ∫ N_a r ds / m_a: ring × m_a is a's ring area.
            ring: if ring {
                std::f64::consts::TAU * e.mr / e.m
            } else {
                1.0
            },
            segment: Some(SegmentSide {
                nodes: side.iter().map(|&(b, _)| b).collect(),
                shape: side.iter().map(|&(_, v)| v / e.mr).collect(),
                length: e.m,
                weight: e.m / mean_length,
            }),
        });
    }
    let unpaired = if gaps {
        nodes.len() - elements.len()
    } else {
        0
    };
    Ok((elements, unpaired))
}

/// How far a face point may lie from its host edge.
#[derive(Debug, Clone, Copy)]
enum Reach {
    /// Faces that touch: within this fraction of the edge's length (the nodes
    /// were moved onto the host).
    Tolerance(f64),
    /// Faces apart or overlapping: within this length (`search_distance`).
    Distance(f64),
}

impl Reach {
    /// Whether a point `d` from an edge of length `len` is within reach.
    fn within(self, d: f64, len: f64) -> bool {
        match self {
            Reach::Tolerance(t) => d <= t * len,
            Reach::Distance(r) => d <= r,
        }
    }
}

/// Two Gauss points on every piece of the face `segments` cut at the projections
/// of the host's boundary vertices, each over the host boundary edge nearest to its
/// piece's midpoint within `reach`. Touching faces (`Reach::Tolerance`): the
/// host's shape functions at the point itself, no initial gap; pieces over no host
/// edge (beyond the host's end) get none. Faces within a search distance
/// (`Reach::Distance`): the pieces are also cut where the nearest edge or the
/// clamping of the projection can change, each point is tied to its projection on
/// the edge with its initial gap, and the nodes of a segment with a point beyond
/// the distance are returned (second) to be left unpaired.
fn gauss_points(
    interface: &str,
    host: &Mesh,
    node_mesh: &Mesh,
    boundary: &str,
    segments: &[[usize; 2]],
    reach: Reach,
) -> Result<(Vec<Point>, HashSet<usize>)> {
    let x = |n: usize| node_mesh.nodes[n];
    let (edges, tree, max_len) = edge_tree(host);
    let segment = |e: &BoundaryEdge| e.nodes.map(|n| host.nodes[n]);
    let (radius, gaps) = match reach {
        Reach::Tolerance(t) => (t * max_len, false),
        Reach::Distance(d) => (d, true),
    };
    // With gaps: the bisector direction at each host boundary vertex (the
    // normalised sum of the normals of the edges meeting there), where the nearest
    // of two edges changes.
    // With gaps: the bisector direction at each host boundary vertex (the
    // normalised sum of the normals of the edges meeting there), where the nearest
    // of two edges changes; and the vertices of either face where it is taken as a
    // smooth curve, with that curve's normal (see `curve_offset`).
    let (bisectors, smooth) = if gaps {
        vertex_normals(edges.iter().map(|e| (e.nodes, edge_normal(segment(e)))))
    } else {
        (HashMap::new(), HashMap::new())
    };
    // The node part's face segments as oriented on its boundary (outward normal
    // to their right), and its smooth vertices.
    let oriented: HashSet<[usize; 2]> = if gaps {
        node_mesh
            .boundaries
            .get(boundary)
            .into_iter()
            .flatten()
            .map(|e| e.nodes)
            .collect()
    } else {
        HashSet::new()
    };
    // With gaps: each face segment's outward normal, which the host edges under
    // it must face (`search::facing`: never a host boundary that merely meets the
    // interface, such as a symmetry edge).
    let face = if gaps {
        let nodes: Vec<usize> = segments.iter().flatten().copied().collect();
        face_normals(node_mesh, &nodes)
    } else {
        HashMap::new()
    };
    let (_, node_smooth) = if gaps {
        vertex_normals(
            node_mesh
                .boundaries
                .get(boundary)
                .into_iter()
                .flatten()
                .map(|e| (e.nodes, edge_normal(e.nodes.map(x)))),
        )
    } else {
        (HashMap::new(), HashMap::new())
    };
    // Touching faces: 2 Gauss points per piece integrate the (linear × linear)
    // coefficients exactly. Faces apart: 3, as the initial gap then has the host
    // curve's cubic offset (N_a × cubic, degree 4).
    let gauss: &[(f64, f64)] = if gaps { &GAUSS3 } else { &GAUSS2 };

    let mut points = Vec::with_capacity(4 * segments.len());
    let mut unreached = HashSet::new();
    let mut candidates = Vec::new();
    let mut cuts = Vec::new();
    for &[na, nb] in segments {
        let (a, b) = (x(na), x(nb));
        let len = dist(a, b);
        let ab = [b[0] - a[0], b[1] - a[1]];
        // With gaps: the node face's curve over this segment, oriented as on the
        // boundary (reversed: its parameter runs from b to a), with its outward
        // normal.
        let node_curve = [[na, nb], [nb, na]]
            .into_iter()
            .find(|e| oriented.contains(e))
            .map(|[p, q]| {
            let ends = [x(p), x(q)];
            let n = edge_normal(ends);
            let normals = end_normals(n, [p, q].map(|v| node_smooth.get(&v).copied()));
            (ends, normals, n, p != na)
        });
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
        if let Some(&n) = face.get(&[na.min(nb), na.max(nb)]) {
            candidates.retain(|&e| facing(edge_normal(segment(&edges[e])), n));
        }
        if gaps && candidates.is_empty() {
            unreached.extend([na, nb]);
            continue;
        }
        // Cut the segment at the projections of the host vertices near it.
        cuts.clear();
        cuts.extend([0.0, 1.0]);
        for &e in &candidates {
            let [p, q] = segment(&edges[e]);
            match reach {
                Reach::Distance(_) => {
                    // Where the line through a vertex along `dir` (its edge's
                    // normal, and the vertex's bisector) crosses the segment:
                    // (a + t ab − v) · dir⊥ = 0.
                    let n = edge_normal([p, q]);
                    for (v, id) in [(p, edges[e].nodes[0]), (q, edges[e].nodes[1])] {
                        for dir in [Some(n), bisectors.get(&id).copied()]
                            .into_iter()
                            .flatten()
                        {
                            let perp = [-dir[1], dir[0]];
                            let den = ab[0] * perp[0] + ab[1] * perp[1];
                            if den.abs() > 1e-12 * len {
                                let t = ((v[0] - a[0]) * perp[0] + (v[1] - a[1]) * perp[1])
                                    / den;
                                if t > MERGE && t < 1.0 - MERGE {
                                    cuts.push(t);
                                }
                            }
                        }
                    }
                }
                Reach::Tolerance(tolerance) => {
                    let tol = tolerance * dist(p, q);
                    for v in [p, q] {
                        let t =
                            ((v[0] - a[0]) * ab[0] + (v[1] - a[1]) * ab[1]) / (len * len);
                        let off =
                            ((v[0] - a[0]) * ab[1] - (v[1] - a[1]) * ab[0]).abs() / len;
                        if t > MERGE && t < 1.0 - MERGE && off <= tol {
                            cuts.push(t);
                        }
                    }
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
            // The host edge under the piece: the nearest to its midpoint (ties to
            // the lowest host element, then edge), within reach.
            let tm = 0.5 * (t0 + t1);
            let mid = [a[0] + tm * ab[0], a[1] + tm * ab[1]];
            let Some((element, e)) = edge_under(host, &edges, &candidates, mid, reach) else {
                if gaps {
                    unreached.extend([na, nb]);
                }
                continue;
            };
            let [p, q] = segment(&edges[e]);
            let corners = host.coordinates(element);
            let normal = edge_normal([p, q]);
            // The host face's curve over this edge (faces apart only): its ends'
            // normals where the boundary is smooth there, extrapolated at a corner
            // ([`end_normals`]).
            let curve = gaps.then(|| end_normals(normal, edges[e].nodes.map(|v| smooth.get(&v).copied())));
            for &(g, wg) in gauss {
                let t = t0 + g * (t1 - t0);
                let at = [a[0] + t * ab[0], a[1] + t * ab[1]];
                let (xi, distance) = project(at, p, q);
                // Touching faces: the host's shape functions at the point itself,
                // not at its projection: where the face segment cuts a corner of
                // the host's polygon (a curved face) the point lies off the host
                // edge, and extrapolating the host element there keeps every
                // linear field free of jump (as the node CFE does by moving its
                // nodes). Faces apart: at the projection P, the host point the
                // face point meets when the gap closes, as the node coupling does
                // within a search distance; the point carries its initial gap
                // (X − P) · n.
                let (on_host, gap0) = if gaps {
                    if !reach.within(distance, dist(p, q)) {
                        unreached.extend([na, nb]);
                    }
                    let proj = [p[0] + xi * (q[0] - p[0]), p[1] + xi * (q[1] - p[1])];
                    let [n_p, n_q] = curve.expect("faces apart");
                    // The gap between the two faces' curves: the node face's
                    // point X + c_s n_s, the host's P + c_h n_e.
                    let node_offset = node_curve.map_or(0.0, |(ends, normals, n, reversed)| {
                        let s = if reversed { 1.0 - t } else { t };
                        curve_offset(ends, normals, s) * (n[0] * normal[0] + n[1] * normal[1])
                    });
                    let g0 = (at[0] - proj[0]) * normal[0] + (at[1] - proj[1]) * normal[1]
                        + node_offset
                        - curve_offset([p, q], [n_p, n_q], xi);
                    (proj, g0)
                } else {
                    (at, 0.0)
                };
                let host_shape = shape_at(&host.elements[element], &corners, on_host)
                    .ok_or_else(|| Error::Coupling {
                        interface: interface.to_string(),
                        message: format!(
                            "the inverse map of host element {element} (corners {corners:?}) does not converge at the face point ({}, {})",
                            on_host[0], on_host[1]
                        ),
                    })?;
                points.push(Point {
                    segment: [na, nb],
                    n: [1.0 - t, t],
                    w: wg * (t1 - t0) * len,
                    r: at[0],
                    element,
                    host_nodes: host.elements[element].nodes().to_vec(),
                    host_shape,
                    normal,
                    distance,
                    gap0,
                });
            }
        }
    }
    Ok((points, unreached))
}

/// The host boundary edge (among `candidates`, indices into `edges`) under the
/// point `mid` of a face piece: the nearest within `reach`, ties to the lowest
/// host element, then edge. Returns (host element, edge). Within a search
/// distance a tie is first broken by how far the point's projection on the edge's
/// line falls beyond the edge: off a host corner, where the clamped projections on
/// both edges are the corner and the distances equal, the piece takes the edge on
/// its side of the corner's bisector, so that g₀ is continuous along the face.
fn edge_under(
    host: &Mesh,
    edges: &[BoundaryEdge],
    candidates: &[usize],
    mid: [f64; 2],
    reach: Reach,
) -> Option<(usize, usize)> {
    // (distance, overshoot beyond the edge's ends, element, edge)
    let mut best: Option<(f64, f64, usize, usize)> = None;
    for &e in candidates {
        let [p, q] = edges[e].nodes.map(|n| host.nodes[n]);
        let elen = dist(p, q);
        let (_, d) = project(mid, p, q);
        if !reach.within(d, elen) {
            continue;
        }
        let over = match reach {
            Reach::Tolerance(_) => 0.0,
            Reach::Distance(_) => {
                let xi = ((mid[0] - p[0]) * (q[0] - p[0]) + (mid[1] - p[1]) * (q[1] - p[1]))
                    / (elen * elen);
                (-xi).max(xi - 1.0).max(0.0) * elen
            }
        };
        let key = (d, over, edges[e].element, e);
        let better = match best {
            None => true,
            Some(cur) => {
                let tie = |a: f64, b: f64| (a - b).abs() <= 1e-12 * elen;
                if !tie(d, cur.0) {
                    d < cur.0
                } else if !tie(over, cur.1) {
                    over < cur.1
                } else {
                    (key.2, key.3) < (cur.2, cur.3)
                }
            }
        };
        if better {
            best = Some(key);
        }
    }
    best.map(|(_, _, element, e)| (element, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ElementKind;

    /// The shift Σ M̂_b X_b − Σ N̂_i X_i between an element's averaged face point
    /// (node side, in `top`) and its averaged host point (in `host`): zero for
    /// touching faces, g₀ n across a uniform gap.
    fn face_shift(c: &CouplingElement, top: &Mesh, host: &Mesh) -> [f64; 2] {
        let s = c.segment.as_ref().expect("a segment element");
        std::array::from_fn(|k| {
            let side: f64 = s.nodes.iter().zip(&s.shape).map(|(&b, m)| m * top.nodes[b][k]).sum();
            let hosted: f64 = c.host_nodes.iter().zip(&c.shape).map(|(&i, n)| n * host.nodes[i][k]).sum();
            side - hosted
        })
    }

    /// A 3-cell node face over a 7-cell host face (3:7), T3 and Q4: one element per
    /// face node, both coefficient rows sum to 1 and give the same point
    /// (Σ M̂_b X_b = Σ N̂_i X_i: no jump for a linear field), the normal is +y, the
    /// shares m_a add up to the face's length with interior nodes weighing ω = 1
    /// (like a node CFE) and the two ends ½, and the host nodes are those of the
    /// host's top row only.
    #[test]
    fn elements_on_a_3_to_7_face() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let host = Mesh::rectangle([0.0, 7.0], [0.0, 2.0], [7, 2], kind);
            let top = Mesh::rectangle([0.0, 7.0], [2.0, 3.0], [3, 1], kind);
            let nodes = top.boundary_nodes("bottom").unwrap();
            let els = segment_elements("i", &host, &top, "bottom", &nodes, 1e-6).unwrap();
            assert_eq!(els.len(), 4, "{kind:?}");
            let total: f64 = els.iter().map(|c| c.segment.as_ref().unwrap().length).sum();
            assert!((total - 7.0).abs() < 1e-12);
            for c in &els {
                let s = c.segment.as_ref().unwrap();
                assert!((s.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                assert!((c.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                let shift = face_shift(c, &top, &host);
                assert!(shift.iter().all(|d| d.abs() < 1e-12), "{kind:?} {shift:?}");
                assert!((c.normal[1] - 1.0).abs() < 1e-12 && c.distance < 1e-12);
                assert!(c.host_nodes.iter().all(|&i| host.nodes[i][1] > 1.5));
                let end = top.nodes[c.node][0] < 1e-9 || top.nodes[c.node][0] > 7.0 - 1e-9;
                let expected = if end { 0.5 } else { 1.0 };
                assert!((s.weight - expected).abs() < 1e-12, "{}", s.weight);
                assert_eq!(s.nodes.len(), if end { 2 } else { 3 });
            }
        }
    }

    /// On a ring (`FaceMeasure::Ring`, x = r) the elements' forces are the ring
    /// integrals of the Galerkin form: for every node b of either face, Σ_a of
    /// ring_a m_a M̂_ab (and N̂_ai) is ∫ N_b 2πr ds — 2π r_b h inside, 2π h²/6 on
    /// the axis, 2π h (R/2 − h/6) at the outer end R — on 3:7 non-matching faces
    /// from the axis, T3 and Q4; so the node on the axis (r = 0) has its element
    /// with ring 2π h/3 and coefficients (½, ½) on its segment (the r-weighted
    /// means), and no linear field has a jump.
    #[test]
    fn ring_weights_integrate_2_pi_r() {
        use std::f64::consts::TAU;
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let host = Mesh::rectangle([0.0, 7.0], [0.0, 2.0], [7, 2], kind);
            let top = Mesh::rectangle([0.0, 7.0], [2.0, 3.0], [3, 1], kind);
            let nodes = top.boundary_nodes("bottom").unwrap();
            let (els, _) = segment_elements_within(
                "i", &host, &top, "bottom", &nodes, 1e-6, 0.0, FaceMeasure::Ring,
            )
            .unwrap();
            assert_eq!(els.len(), 4, "{kind:?}");
            let ring_integral = |r: f64, h: f64| {
                if r < 1e-9 {
                    TAU * h * h / 6.0
                } else if r > 7.0 - 1e-9 {
                    TAU * h * (r / 2.0 - h / 6.0)
                } else {
                    TAU * r * h
                }
            };
            let mut side: HashMap<usize, f64> = HashMap::new();
            let mut hosted: HashMap<usize, f64> = HashMap::new();
            for c in &els {
                let s = c.segment.as_ref().unwrap();
                let area = c.ring * s.length;
                for (&b, m) in s.nodes.iter().zip(&s.shape) {
                    *side.entry(b).or_default() += area * m;
                }
                for (&i, n) in c.host_nodes.iter().zip(&c.shape) {
                    *hosted.entry(i).or_default() += area * n;
                }
                let shift = face_shift(c, &top, &host);
                assert!(shift.iter().all(|d| d.abs() < 1e-12), "{kind:?} {shift:?}");
                if top.nodes[c.node][0] == 0.0 {
                    let h = 7.0 / 3.0;
                    assert!((c.ring - TAU * h / 3.0).abs() < 1e-12, "{}", c.ring);
                    assert!(s.shape.iter().all(|m| (m - 0.5).abs() < 1e-12), "{:?}", s.shape);
                }
            }
            for (b, v) in side {
                let want = ring_integral(top.nodes[b][0], 7.0 / 3.0);
                assert!((v - want).abs() < 1e-12 * want.max(1.0), "{kind:?} node {b}: {v} vs {want}");
            }
            hosted.retain(|_, v| v.abs() > 1e-13);
            assert_eq!(hosted.len(), 8, "{kind:?}: the host's top row");
            for (i, v) in hosted {
                let want = ring_integral(host.nodes[i][0], 1.0);
                assert!((v - want).abs() < 1e-12 * want.max(1.0), "{kind:?} host node {i}: {v} vs {want}");
            }
        }
    }

    /// Flat faces apart by a uniform gap g₀ (and overlapping by it) on 3:9
    /// non-matching meshes, T3 and Q4 hosts: within a search distance every
    /// coupling node gets an element whose initial gap is g₀ to round-off, with
    /// the normal +y, coefficient rows summing to 1, host nodes on the host's face
    /// only (tied to the projections), and the face shift of its points equal to
    /// g₀ n (Σ M̂_b X_b − Σ N̂_i X_i = g₀ n: no jump but the gap for a linear field).
    #[test]
    fn uniform_gap_on_non_matching_faces() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            for g0 in [0.01, -0.01] {
                // The host wider than the face: an overlapping face point near a
                // host corner would otherwise be nearer to the host's side.
                let host = Mesh::rectangle([-1.0, 8.0], [0.0, 2.0], [9, 2], kind);
                let top = Mesh::rectangle([0.0, 7.0], [2.0 + g0, 3.0], [3, 1], kind);
                let nodes = top.boundary_nodes("bottom").unwrap();
                let (els, unpaired) =
                    segment_elements_within("i", &host, &top, "bottom", &nodes, 1e-6, 0.05, FaceMeasure::Length)
                        .unwrap();
                assert_eq!((els.len(), unpaired), (4, 0), "{kind:?}");
                for c in &els {
                    assert!((c.gap0 - g0).abs() < 1e-14, "{kind:?}: {} vs {g0}", c.gap0);
                    assert!((c.normal[1] - 1.0).abs() < 1e-14);
                    assert!((c.distance - g0.abs()).abs() < 1e-14);
                    let s = c.segment.as_ref().unwrap();
                    assert!((s.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                    assert!((c.shape.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                    assert!(c.host_nodes.iter().zip(&c.shape).all(|(&i, v)| {
                        host.nodes[i][1] > 1.5 || v.abs() < 1e-14
                    }));
                    let shift = face_shift(c, &top, &host);
                    assert!(shift[0].abs() < 1e-13, "{kind:?} {shift:?}");
                    assert!((shift[1] - g0).abs() < 1e-13, "{kind:?} {shift:?}");
                }
                // Beyond the search distance nothing pairs.
                let (none, unpaired) =
                    segment_elements_within("i", &host, &top, "bottom", &nodes, 1e-6, 0.005, FaceMeasure::Length)
                        .unwrap();
                assert_eq!((none.len(), unpaired), (0, 4));
            }
        }
    }

    /// A circle's polygon (radius R, its lowest vertex at height c) over a flat
    /// host face y = 0 meshed non-matching: each coupling node's initial gap is the
    /// N_a-weighted mean of the height of the circle, not of its chords (the gap is
    /// measured to the face's curve): ∫ N_a y(X + λ n) ds / ∫ N_a ds with X + λ n
    /// the circle's point along the chord's normal from its point X, computed here
    /// independently with 400 points a chord, to 2e-6 against the chords' sagitta
    /// L²/(8R) = 1.9e-3; the nodes whose chords reach beyond the search distance
    /// are unpaired, the others paired.
    #[test]
    fn curved_face_mean_gap() {
        let (r, c, d) = (10.0f64, 0.02, 0.5);
        let host = Mesh::rectangle([-6.0, 6.0], [-3.0, 0.0], [13, 3], ElementKind::Q4);
        // 80 vertices on the lower half of the circle, a boundary `arc` of 79 edges.
        let m = 80usize;
        let at = |k: usize| {
            let t = -std::f64::consts::PI * (k as f64 + 0.5) / m as f64;
            [r * t.cos(), r + c + r * t.sin()]
        };
        let mut arc = Mesh {
            nodes: (0..m).map(at).collect(),
            ..Default::default()
        };
        arc.boundaries.insert(
            "arc".into(),
            (0..m - 1)
                .map(|k| BoundaryEdge {
                    nodes: [k + 1, k],
                    element: 0,
                })
                .collect(),
        );
        let nodes: Vec<usize> = (0..m).collect();
        let (els, unpaired) =
            segment_elements_within("arc", &host, &arc, "arc", &nodes, 1e-6, d, FaceMeasure::Length).unwrap();
        assert_eq!(els.len() + unpaired, m);
        let y = |k: usize| arc.nodes[k][1];
        let len = |i: usize, j: usize| dist(arc.nodes[i], arc.nodes[j]);
        for k in 0..m {
            let mut chords = Vec::new();
            if k > 0 {
                chords.push(k - 1);
            }
            if k + 1 < m {
                chords.push(k + 1);
            }
            // Paired exactly when every point of its chords is within d.
            let reached = chords.iter().all(|&j| y(j).max(y(k)) <= d);
            let el = els.iter().find(|e| e.node == k);
            assert_eq!(el.is_some(), reached, "node {k} at {:?}", arc.nodes[k]);
            let Some(el) = el else { continue };
            let centre = [0.0, r + c];
            let mut num = 0.0;
            for &j in &chords {
                let (p, q) = (arc.nodes[k], arc.nodes[j]);
                let l = len(k, j);
                let n = [(q[1] - p[1]) / l, -(q[0] - p[0]) / l];
                let n = if n[1] < 0.0 { n } else { [-n[0], -n[1]] };
                let steps = 400;
                for m in 0..steps {
                    let s = (m as f64 + 0.5) / steps as f64;
                    let x = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
                    // |x + λ n − centre| = R, the root λ ≥ 0 (the arc beyond the chord).
                    let d = [x[0] - centre[0], x[1] - centre[1]];
                    let b = d[0] * n[0] + d[1] * n[1];
                    let lambda = -b + (b * b - (d[0] * d[0] + d[1] * d[1] - r * r)).sqrt();
                    num += (1.0 - s) * (x[1] + lambda * n[1]) * l / steps as f64;
                }
            }
            let den: f64 = chords.iter().map(|&j| len(k, j) / 2.0).sum();
            assert!(
                (el.gap0 - num / den).abs() < 2e-6,
                "node {k}: {} vs {}",
                el.gap0,
                num / den
            );
            assert!((el.tributary - den).abs() < 1e-13);
            assert!((el.normal[1] - 1.0).abs() < 1e-14);
        }
        assert!(els.len() >= 10 && unpaired >= 20, "{} {unpaired}", els.len());
    }

    /// Overclosure on a curved host: a shaft (node part, 2N segments around, radius
    /// b + δ) inside a ring's bore (host, N chords, radius b), as in a shrink fit.
    /// The polygons' overlap alternates: δ + b(1 − cos(θ/2)) (θ = 2π/N) at a ring
    /// chord's middle, δ cos(θ/2) at its vertices, so their N_a-weighted means
    /// differ by more than half δ between neighbouring shaft nodes. Measured
    /// between the two faces' curves every node's initial gap is −δ, to 5 % of δ
    /// (the cubic curves' and the normals' O(θ²) errors at θ = 15°), and the
    /// normal is the inward radial direction.
    #[test]
    fn overclosure_on_a_curved_host() {
        let (b, delta, n) = (10.0f64, 0.05, 24usize);
        let ring = Mesh::annulus([0.0, 0.0], [b, 12.0], [0.0, 360.0], [1, n], ElementKind::Q4);
        let shaft = Mesh::annulus(
            [0.0, 0.0],
            [8.0, b + delta],
            [0.0, 360.0],
            [1, 2 * n],
            ElementKind::T3,
        );
        let nodes = shaft.boundary_nodes("outer").unwrap();
        let (els, unpaired) =
            segment_elements_within("fit", &ring, &shaft, "outer", &nodes, 1e-6, 5.0 * delta, FaceMeasure::Length)
                .unwrap();
        assert_eq!((els.len(), unpaired), (2 * n, 0));
        for c in &els {
            let x = shaft.nodes[c.node];
            let angle = x[1].atan2(x[0]).rem_euclid(std::f64::consts::TAU);
            let expected = -delta;
            assert!(
                (c.gap0 - expected).abs() < 0.05 * delta,
                "node at {:.2}°: {} vs {expected}",
                angle.to_degrees(),
                c.gap0
            );
            assert!((c.normal[0] + angle.cos()).abs() < 1e-12);
            assert!((c.normal[1] + angle.sin()).abs() < 1e-12);
        }
    }

    /// The host curve's offset from its chord: on a chord of a circle (radius R,
    /// angle θ) with the radial normals at its ends it is the arc's, the sagitta
    /// R(1 − cos(θ/2)) at the middle and the arc's offset all along the chord to
    /// θ²/8 of the sagitta (the cubic's error), towards the centre's far side for an
    /// outward normal pointing away from the centre; 0 at the ends, and 0
    /// everywhere when the ends' normals are the chord's (a flat face, a corner).
    #[test]
    fn curve_offset_follows_the_arc() {
        let (r, theta) = (10.0f64, 0.2f64);
        // Counter-clockwise on a disc: outward normal away from the centre.
        let p = [r * (-theta / 2.0).cos(), r * (-theta / 2.0).sin()];
        let q = [r * (theta / 2.0).cos(), r * (theta / 2.0).sin()];
        let ends = [[p[0] / r, p[1] / r], [q[0] / r, q[1] / r]];
        let sagitta = r * (1.0 - (theta / 2.0).cos());
        for k in 0..=10 {
            let xi = k as f64 / 10.0;
            // The arc's distance beyond the chord x = R cos(θ/2) at height y.
            let y = p[1] + xi * (q[1] - p[1]);
            let arc = (r * r - y * y).sqrt() - r * (theta / 2.0).cos();
            let c = curve_offset([p, q], ends, xi);
            assert!((c - arc).abs() < theta * theta / 8.0 * sagitta, "ξ = {xi}: {c} vs {arc}");
        }
        assert!(curve_offset([p, q], ends, 0.0).abs() < 1e-15);
        assert!(curve_offset([p, q], ends, 1.0).abs() < 1e-15);
        let n = edge_normal([p, q]);
        assert_eq!(curve_offset([p, q], [n, n], 0.3), 0.0);
    }

    /// At a corner next to a smooth vertex the curve keeps its curvature: on a
    /// circle meshed by chords, the corner's normal from the smooth neighbour's
    /// radial normal is the radial direction at the corner (to round-off), so the
    /// last chord's curve is the arc's as in the middle of the face; on a flat
    /// face (the neighbour's normal the edge's) nothing changes, and an edge with
    /// no smooth end stays straight.
    #[test]
    fn a_corner_extrapolates_the_arc() {
        let (r, theta) = (7.0f64, 0.3f64);
        let radial = |a: f64| [a.cos(), a.sin()];
        let (p, q) = (radial(0.0).map(|c| r * c), radial(theta).map(|c| r * c));
        let n = edge_normal([p, q]);
        let [at_p, at_q] = end_normals(n, [None, Some(radial(theta))]);
        for (got, want) in [(at_p, radial(0.0)), (at_q, radial(theta))] {
            assert!((got[0] - want[0]).abs() < 1e-14 && (got[1] - want[1]).abs() < 1e-14);
        }
        let [a, b] = end_normals(n, [Some(n), None]);
        assert_eq!(a, n);
        assert!((b[0] - n[0]).abs() < 1e-15 && (b[1] - n[1]).abs() < 1e-15);
        assert_eq!(end_normals(n, [None, None]), [n, n]);
    }

    /// Coupling nodes on no boundary edge cannot be integrated over: an error
    /// naming the interface and the remedy.
    #[test]
    fn isolated_nodes_are_an_error() {
        let host = Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1], ElementKind::T3);
        let top = Mesh::rectangle([0.0, 2.0], [1.0, 2.0], [2, 1], ElementKind::T3);
        let nodes = top.boundary_nodes("bottom").unwrap();
        let e = segment_elements("lone", &host, &top, "nowhere", &nodes[..1], 1e-6)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("lone") && e.contains("coupling = \"node\""),
            "{e}"
        );
    }
}
