//! The volume form of the coupling element (`form = "volume"`): a coupling node
//! lying *inside* a host element rather than on its boundary — overlapping
//! meshes, a finely meshed insert or patch embedded in a coarse body (the
//! kinematics of OpenSees's `ASDEmbeddedNodeElement`, here for T3/Q4 hosts in
//! 2D and TET4/HEX8 hosts in 3D).
//!
//! - **Element.** For a coupling node at X inside host element e: its natural
//!   coordinates ξ in e (computed once, in the reference configuration: exact
//!   barycentric coordinates on a T3 or TET4, Newton's inverse map on a Q4 or
//!   HEX8 — the element routines' own, [`crate::fem::q4::natural_coordinates`],
//!   [`crate::fem::hex8::natural_coordinates`]), the shape values N̄ᵢ(ξ) of
//!   *all* e's nodes, and `[[U]] = D_node − Σᵢ N̄ᵢ Dᵢ`: the node and 3, 4 (2D)
//!   or 4, 8 (3D) host nodes, the same [`CouplingElement`] as the face form's
//!   with a longer host-node list. On e's boundary the off-face N̄ᵢ vanish (to
//!   round-off), and it is still a volume coupling.
//! - **Which host.** The host elements whose bounding boxes (padded by
//!   [`INSIDE_TOLERANCE`] × the element's size) contain X, from an R-tree over
//!   the host's elements (no all-pairs loop); of those that contain X — every
//!   N̄ᵢ ≥ −[`INSIDE_TOLERANCE`] — the one of the lowest element index. A node on
//!   a face, edge or vertex shared by several host elements so goes to the
//!   lowest of them, whatever order the tree returns them in (the face form's
//!   rule: the lowest (element, face)).
//! - **Outside.** A node in no host element is not coupled; the interface
//!   counts it (`Interface::unpaired`, reported with the run).
//! - **Frame and law.** A node inside a body has no face and so no normal: the
//!   only law of the volume form is the bonded tie `rigid` with c_n = c_s = c,
//!   whose stiffness `C = Rᵀ c R = c I` is the same in every frame (the pair's
//!   frame is the global axes, its "normal" the x axis; its pressure is 0, it
//!   has no face to spread its force on). A unilateral or frictional law needs
//!   the face's normal and is refused (`coupling::build`).

use super::element::CouplingElement;
use super::search;
use crate::dim::{D2, D3};
use crate::fem::{hex8, tet4};
use crate::mesh::{Mesh, MeshCell, MeshDim, SolidElement};
use rstar::{AABB, RTree, primitives::GeomWithData, primitives::Rectangle};

/// A node is inside a host element when each of the element's shape values at
/// it is at least −`INSIDE_TOLERANCE` (a point of a face, edge or vertex is in
/// every element sharing it, to round-off); the elements' bounding boxes are
/// padded by this fraction of their size.
pub const INSIDE_TOLERANCE: f64 = 1e-10;

/// The host elements of a dimension as the volume form reads them: the shape
/// values of an element at a point.
pub trait VolumeDim: MeshDim {
    /// The shape values N̄ᵢ of element `cell` of `mesh` at `p`, one per node of
    /// the element in its order, at `p`'s natural coordinates (exact on a
    /// simplex, Newton's inverse map on a Q4 or HEX8): they sum to 1 and
    /// reproduce p, `Σ N̄ᵢ Xᵢ = p`, for any p; all ≥ 0 exactly when p is in the
    /// element. `None` when the inverse map fails (a degenerate element, or a
    /// p far outside a distorted one).
    fn shape_in(mesh: &Mesh<Self>, cell: &Self::Cell, p: Self::Vector) -> Option<Vec<f64>>;
}

/// T3: barycentric coordinates; Q4: the bilinear values at Newton's inverse map
/// ([`search::shape_at`], the face form's own).
impl VolumeDim for D2 {
    fn shape_in(mesh: &Mesh, cell: &Self::Cell, p: [f64; 2]) -> Option<Vec<f64>> {
        let x: Vec<[f64; 2]> = cell.nodes().iter().map(|&n| mesh.nodes[n]).collect();
        search::shape_at(cell, &x, p)
    }
}

/// TET4: barycentric coordinates (exact, Cramer's rule); HEX8: the trilinear
/// values at Newton's inverse map ([`tet4::natural_coordinates`],
/// [`hex8::natural_coordinates`]).
impl VolumeDim for D3 {
    fn shape_in(mesh: &Mesh<D3>, cell: &SolidElement, p: [f64; 3]) -> Option<Vec<f64>> {
        match cell {
            SolidElement::Tet4(n) => {
                let x = n.map(|k| mesh.nodes[k]);
                tet4::natural_coordinates(&x, p).map(|xi| tet4::shape(xi).to_vec())
            }
            SolidElement::Hex8(n) => {
                let x = n.map(|k| mesh.nodes[k]);
                hex8::natural_coordinates(&x, p).map(|xi| hex8::shape(xi).to_vec())
            }
        }
    }
}

/// A point of any dimension as a 3D point (z = 0 in 2D), for the R-tree.
fn point3(p: &[f64]) -> [f64; 3] {
    std::array::from_fn(|c| p.get(c).copied().unwrap_or(0.0))
}

/// The longest edge of element `cell` of `mesh`: its size.
fn size<D: MeshDim>(mesh: &Mesh<D>, cell: &D::Cell) -> f64 {
    cell.edges()
        .map(|[a, b]| {
            let (a, b) = (mesh.nodes[a], mesh.nodes[b]);
            let d = a.as_ref().iter().zip(b.as_ref()).map(|(x, y)| (x - y) * (x - y));
            d.sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max)
}

/// The R-tree of the host's elements: each one's bounding box, padded by
/// [`INSIDE_TOLERANCE`] × its size, carrying its index ([`locate`]'s tree).
pub fn element_tree<D: MeshDim>(host: &Mesh<D>) -> RTree<GeomWithData<Rectangle<[f64; 3]>, usize>> {
    let boxes = host.elements.iter().enumerate().map(|(e, cell)| {
        let pad = INSIDE_TOLERANCE * size(host, cell);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &n in cell.nodes() {
            let x = point3(host.nodes[n].as_ref());
            for c in 0..3 {
                lo[c] = lo[c].min(x[c] - pad);
                hi[c] = hi[c].max(x[c] + pad);
            }
        }
        GeomWithData::new(Rectangle::from_aabb(AABB::from_corners(lo, hi)), e)
    });
    RTree::bulk_load(boxes.collect())
}

/// The host element containing `p` (the lowest index among those that do,
/// see the module's rule) and its shape values there; `None` when `p` is in no
/// element of `host`.
pub fn locate<D: VolumeDim>(
    host: &Mesh<D>,
    tree: &RTree<GeomWithData<Rectangle<[f64; 3]>, usize>>,
    p: D::Vector,
) -> Option<(usize, Vec<f64>)> {
    let mut candidates: Vec<usize> = tree
        .locate_all_at_point(point3(p.as_ref()))
        .map(|g| g.data)
        .collect();
    candidates.sort_unstable();
    candidates.into_iter().find_map(|e| {
        let shape = D::shape_in(host, &host.elements[e], p)?;
        shape
            .iter()
            .all(|&n| n >= -INSIDE_TOLERANCE)
            .then_some((e, shape))
    })
}

/// The volume-form coupling elements of the nodes `nodes` (indices into
/// `node_coords`, the node part's coordinates) inside the elements of `host`
/// (see the module's rules), in the order of `nodes`, and the number of those
/// that lie in no host element (not coupled). Each element's frame is the global
/// axes ([`crate::dim::Dim::frame`] of the x axis: the tie c·I reads no frame), its
/// position the node as meshed (nothing moves), its size (`edge_length`) the
/// host element's longest edge, its tributary 0 (no face).
///
/// ```
/// use cfe::coupling::volume::embedded_elements;
/// use cfe::dim::D3;
/// use cfe::mesh::{Mesh, SolidKind};
/// // A unit cube of one HEX8, a node at (0.25, 0.5, 0.75) inside it and one outside.
/// let host = Mesh::<D3>::block([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [1, 1, 1], SolidKind::Hex8);
/// let probe = [[0.25, 0.5, 0.75], [2.0, 0.5, 0.5]];
/// let (pairs, outside) = embedded_elements(&host, &probe, &[0, 1]);
/// assert_eq!((pairs.len(), outside), (1, 1));
/// let c = &pairs[0];
/// assert_eq!(c.host_nodes.len(), 8);
/// // The shape values reproduce the node: Σ N̄ᵢ Xᵢ = X.
/// for k in 0..3 {
///     let x: f64 = c.host_nodes.iter().zip(&c.shape).map(|(&i, w)| w * host.nodes[i][k]).sum();
///     assert!((x - probe[0][k]).abs() < 1e-12);
/// }
/// ```
pub fn embedded_elements<D: VolumeDim>(
    host: &Mesh<D>,
    node_coords: &[D::Vector],
    nodes: &[usize],
) -> (Vec<CouplingElement<D>>, usize) {
    let tree = element_tree(host);
    let mut x_axis = D::Vector::default();
    x_axis.as_mut()[0] = 1.0;
    let mut pairs = Vec::with_capacity(nodes.len());
    let mut outside = 0;
    for &node in nodes {
        let p = node_coords[node];
        let Some((e, shape)) = locate(host, &tree, p) else {
            outside += 1;
            continue;
        };
        let cell = &host.elements[e];
        pairs.push(CouplingElement {
            node,
            host_element: e,
            host_nodes: cell.nodes().to_vec(),
            shape,
            normal: x_axis,
            frame: D::frame(x_axis),
            position: p,
            distance: 0.0,
            gap0: 0.0,
            tributary: 0.0,
            edge_length: size(host, cell),
            ring: 1.0,
            segment: None,
        });
    }
    (pairs, outside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ElementKind, SolidKind};

    /// `Σ N̄ᵢ Xᵢ` of pair `c` on `host`.
    fn reproduced<D: VolumeDim>(host: &Mesh<D>, c: &CouplingElement<D>) -> Vec<f64> {
        (0..D::N)
            .map(|k| {
                c.host_nodes
                    .iter()
                    .zip(&c.shape)
                    .map(|(&i, w)| w * host.nodes[i].as_ref()[k])
                    .sum()
            })
            .collect()
    }

    /// Partition of unity and reproduction of the node: Σ N̄ᵢ = 1 and
    /// Σ N̄ᵢ Xᵢ = X to 1e-12, every N̄ᵢ ≥ −tolerance.
    fn assert_exact<D: VolumeDim>(host: &Mesh<D>, c: &CouplingElement<D>, x: &[f64]) {
        assert_eq!(c.shape.len(), c.host_nodes.len());
        assert!((c.shape.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{:?}", c.shape);
        assert!(c.shape.iter().all(|&n| n >= -INSIDE_TOLERANCE), "{:?}", c.shape);
        let r = reproduced(host, c);
        assert!((0..D::N).all(|k| (r[k] - x[k]).abs() < 1e-12), "{r:?} vs {x:?}");
    }

    /// The brute force: the lowest element (by index, over all of them) whose
    /// shape values at p are all ≥ −tolerance.
    fn brute_force<D: VolumeDim>(host: &Mesh<D>, p: D::Vector) -> Option<usize> {
        (0..host.elements.len()).find(|&e| {
            D::shape_in(host, &host.elements[e], p)
                .is_some_and(|s| s.iter().all(|&n| n >= -INSIDE_TOLERANCE))
        })
    }

    /// A node at a host vertex shared by 8 HEX8 (and by the 6 × 8 TET4 of the
    /// same grid), on an edge shared by 4, on a face shared by 2 gets the lowest
    /// element containing it — the brute force's — with exact shape values
    /// (shape 1 at the vertex's own node, 0 elsewhere); an interior point gets
    /// the one element containing it.
    #[test]
    fn a_node_on_shared_features_gets_the_lowest_element_and_exact_shapes() {
        for kind in [SolidKind::Hex8, SolidKind::Tet4] {
            let host = Mesh::<D3>::block([0.0, 2.0], [0.0, 2.0], [0.0, 2.0], [2, 2, 2], kind);
            let probe = [
                [1.0, 1.0, 1.0],
                [1.0, 1.0, 0.3],
                [1.0, 0.4, 0.7],
                [0.3, 1.4, 1.7],
            ];
            let all: Vec<usize> = (0..probe.len()).collect();
            let (pairs, outside) = embedded_elements(&host, &probe, &all);
            assert_eq!((pairs.len(), outside), (4, 0), "{kind:?}");
            for c in &pairs {
                let p = probe[c.node];
                assert_eq!(Some(c.host_element), brute_force(&host, p), "{kind:?} {p:?}");
                assert_exact(&host, c, &p);
            }
            // The centre vertex: shape 1 at the host node there.
            let centre = host.nodes.iter().position(|x| *x == [1.0, 1.0, 1.0]).unwrap();
            let c = &pairs[0];
            for (&i, &w) in c.host_nodes.iter().zip(&c.shape) {
                let want = if i == centre { 1.0 } else { 0.0 };
                assert!((w - want).abs() < 1e-12, "{kind:?}: N̄ at node {i} = {w}");
            }
        }
    }

    /// The same rule in 2D (T3 and Q4 hosts): a vertex shared by 4 or 6
    /// elements, a shared edge, an interior point.
    #[test]
    fn plane_hosts_follow_the_same_rule() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let host = Mesh::rectangle([0.0, 2.0], [0.0, 2.0], [2, 2], kind);
            let probe = [[1.0, 1.0], [1.0, 0.3], [0.3, 1.6], [3.0, 1.0]];
            let (pairs, outside) = embedded_elements(&host, &probe, &[0, 1, 2, 3]);
            assert_eq!((pairs.len(), outside), (3, 1), "{kind:?}");
            for c in &pairs {
                let p = probe[c.node];
                assert_eq!(Some(c.host_element), brute_force(&host, p));
                assert_exact(&host, c, &p);
            }
        }
    }

    /// A distorted HEX8 host (corners moved by up to a quarter of the cell,
    /// still convex): for 200 random points of its reference cube mapped into it,
    /// Newton's inverse map converges, the host found is the element, the shape
    /// values are a partition of unity reproducing the point to 1e-12 and equal
    /// the trilinear values at the natural coordinates used to make the point.
    #[test]
    fn a_distorted_hex8_host_is_inverted_exactly() {
        let x: [[f64; 3]; 8] = [
            [0.0, 0.0, 0.0],
            [1.2, 0.1, -0.1],
            [1.0, 1.1, 0.2],
            [-0.2, 0.9, 0.0],
            [0.1, -0.1, 1.0],
            [1.1, 0.0, 1.3],
            [1.25, 1.2, 0.9],
            [0.0, 1.0, 1.1],
        ];
        let host = Mesh::<D3> {
            nodes: x.to_vec(),
            elements: vec![SolidElement::Hex8(std::array::from_fn(|k| k))],
            boundaries: Default::default(),
            node_sets: Default::default(),
        };
        host.validate("distorted").unwrap();
        let mut seed = 3u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        let xis: Vec<[f64; 3]> = (0..200).map(|_| [uniform(), uniform(), uniform()]).collect();
        let probe: Vec<[f64; 3]> = xis.iter().map(|&xi| hex8::point(&x, xi)).collect();
        let all: Vec<usize> = (0..probe.len()).collect();
        let (pairs, outside) = embedded_elements(&host, &probe, &all);
        assert_eq!((pairs.len(), outside), (200, 0));
        for c in &pairs {
            assert_exact(&host, c, &probe[c.node]);
            let want = hex8::shape(xis[c.node]);
            assert!((0..8).all(|i| (c.shape[i] - want[i]).abs() < 1e-10), "{:?}", c.shape);
        }
    }

    /// The R-tree search gives the brute force's element for a random cloud of
    /// points in and around a TET4 block (inside: the lowest containing element;
    /// outside: none, counted).
    #[test]
    fn the_tree_finds_the_brute_forces_host() {
        let host = Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], [0.0, 1.0], [3, 4, 2], SolidKind::Tet4);
        let mut seed = 19u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let cloud: Vec<[f64; 3]> = (0..400)
            .map(|_| [1.4 * uniform() - 0.2, 2.4 * uniform() - 0.2, 1.4 * uniform() - 0.2])
            .collect();
        let all: Vec<usize> = (0..cloud.len()).collect();
        let (pairs, outside) = embedded_elements(&host, &cloud, &all);
        let mut k = 0;
        let mut missing = 0;
        for (n, &p) in cloud.iter().enumerate() {
            match brute_force(&host, p) {
                Some(e) => {
                    assert_eq!((pairs[k].node, pairs[k].host_element), (n, e));
                    k += 1;
                }
                None => missing += 1,
            }
        }
        assert_eq!((k, missing), (pairs.len(), outside));
        assert!(outside > 50 && pairs.len() > 150, "{outside} {}", pairs.len());
    }
}
