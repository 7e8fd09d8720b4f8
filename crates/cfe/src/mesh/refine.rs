//! Uniform refinement of any mesh: every edge split into k equal segments, every
//! T3 into k² T3 and every Q4 into k² Q4, named boundaries carried over. This is
//! what `--refine K` does to parts that are not meshed by a built-in mesher (Gmsh
//! parts), and it gives the same meshes as the built-in meshers with K× the cells.

use super::{BoundaryEdge, Element, Mesh, NodeSet};
use std::collections::{BTreeMap, HashMap};

/// The subdivision of one reference element at factor k: the lattice points of its
/// children and which child owns each sub-edge of each of its edges.
///
/// Lattice point (i, j) is `x(i/k, j/k)` for the element's map `x`: for a T3
/// `A + (B − A) i/k + (C − A) j/k` (i + j ≤ k), for a Q4 the bilinear map of the
/// unit square (0 ≤ i, j ≤ k).
struct Template {
    /// Each child's corners as lattice points (i, j), counter-clockwise.
    children: Vec<Vec<[usize; 2]>>,
    /// `owner[m][s]`: the child that owns sub-edge s (counted from the edge's start)
    /// of the element's edge m (from node m to node m + 1).
    owner: Vec<Vec<usize>>,
}

impl Template {
    /// The barycentric lattice of a triangle: for every (i, j) with i + j < k the
    /// child `(i, j), (i + 1, j), (i, j + 1)` (shaped like the parent), and with
    /// i + j < k − 1 also `(i + 1, j), (i + 1, j + 1), (i, j + 1)` (turned over).
    fn triangle(k: usize) -> Template {
        let mut children = Vec::with_capacity(k * k);
        let mut upright = HashMap::new();
        for j in 0..k {
            for i in 0..k - j {
                upright.insert([i, j], children.len());
                children.push(vec![[i, j], [i + 1, j], [i, j + 1]]);
                if i + j + 1 < k {
                    children.push(vec![[i + 1, j], [i + 1, j + 1], [i, j + 1]]);
                }
            }
        }
        // Edge 0 (A → B) is j = 0, edge 1 (B → C) is i + j = k, edge 2 (C → A) is
        // i = 0; each sub-edge belongs to an upright child.
        let owner = vec![
            (0..k).map(|s| upright[&[s, 0]]).collect(),
            (0..k).map(|s| upright[&[k - 1 - s, s]]).collect(),
            (0..k).map(|s| upright[&[0, k - 1 - s]]).collect(),
        ];
        Template { children, owner }
    }

    /// The bilinear lattice of a quadrilateral: child `(i, j), (i + 1, j),
    /// (i + 1, j + 1), (i, j + 1)` for 0 ≤ i, j < k, row by row.
    fn quadrilateral(k: usize) -> Template {
        let child = |i: usize, j: usize| j * k + i;
        let children = (0..k)
            .flat_map(|j| (0..k).map(move |i| vec![[i, j], [i + 1, j], [i + 1, j + 1], [i, j + 1]]))
            .collect();
        // Edges 0..3: j = 0 (rightwards), i = k (up), j = k (leftwards), i = 0 (down).
        let owner = vec![
            (0..k).map(|s| child(s, 0)).collect(),
            (0..k).map(|s| child(k - 1, s)).collect(),
            (0..k).map(|s| child(k - 1 - s, k - 1)).collect(),
            (0..k).map(|s| child(0, k - 1 - s)).collect(),
        ];
        Template { children, owner }
    }
}

/// The new nodes on the mesh's edges: for each edge (sorted node pair), the index of
/// the first of its k − 1 inner nodes, which run from the lower-numbered end to the
/// other.
struct EdgeNodes {
    k: usize,
    first: HashMap<(usize, usize), usize>,
}

impl EdgeNodes {
    /// Node s (0 ≤ s ≤ k) of the edge from `a` to `b`, counted from `a`.
    fn node(&self, a: usize, b: usize, s: usize) -> usize {
        if s == 0 {
            return a;
        }
        if s == self.k {
            return b;
        }
        let first = self.first[&(a.min(b), a.max(b))];
        let from_low = if a < b { s } else { self.k - s };
        first + from_low - 1
    }
}

impl Mesh {
    /// The mesh refined uniformly by the factor `k`: every edge split into k equal
    /// segments, each T3 into k² T3 (its barycentric lattice) and each Q4 into k² Q4
    /// (the image of a k × k grid under its bilinear map), all counter-clockwise.
    ///
    /// New nodes lie on the straight edges of the input mesh (and, inside a Q4, on
    /// its bilinear map): a curved boundary stays the polygon the input mesh gives
    /// it, it does not get closer to the curve. The result is the same as meshing
    /// the same geometry with k times the cells when the input is a structured mesh
    /// of the built-in meshers (up to node numbering), e.g. [`Mesh::rectangle`].
    ///
    /// Numbering: the input nodes keep their indices `0..n`; then come the new edge
    /// nodes (edges in the order elements first use them, each edge's nodes from
    /// its lower-numbered end), then the new interior nodes, element by element.
    /// Element e's children are elements `e k² .. (e + 1) k²`. Each edge of a named
    /// boundary becomes its k sub-edges, in order along the boundary, each owned by
    /// the child element it belongs to. `k = 1` returns an identical mesh.
    ///
    /// Panics if `k` is 0 or a boundary edge is not an edge of its element.
    pub fn refined(&self, k: usize) -> Mesh {
        assert!(k >= 1, "the refinement factor must be at least 1");
        let triangle = Template::triangle(k);
        let quadrilateral = Template::quadrilateral(k);
        let template = |el: &Element| match el {
            Element::T3(_) => &triangle,
            Element::Q4(_) => &quadrilateral,
        };
        let mut nodes = self.nodes.clone();

        // New nodes on the edges, each edge once.
        let mut edges = EdgeNodes {
            k,
            first: HashMap::with_capacity(2 * self.elements.len()),
        };
        if k > 1 {
            for el in &self.elements {
                for [a, b] in el.edges() {
                    let (lo, hi) = (a.min(b), a.max(b));
                    edges.first.entry((lo, hi)).or_insert_with(|| {
                        let first = nodes.len();
                        let (p, q) = (self.nodes[lo], self.nodes[hi]);
                        nodes.extend((1..k).map(|s| {
                            let t = s as f64 / k as f64;
                            [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]
                        }));
                        first
                    });
                }
            }
        }

        // Interior nodes and children, element by element.
        let mut elements = Vec::with_capacity(k * k * self.elements.len());
        let mut lattice = vec![usize::MAX; (k + 1) * (k + 1)];
        let at = |i: usize, j: usize| j * (k + 1) + i;
        for el in &self.elements {
            let n = el.nodes();
            let x: Vec<[f64; 2]> = n.iter().map(|&a| self.nodes[a]).collect();
            let kf = k as f64;
            match el {
                Element::T3(_) => {
                    for j in 0..=k {
                        for i in 0..=k - j {
                            lattice[at(i, j)] = if j == 0 {
                                edges.node(n[0], n[1], i)
                            } else if i + j == k {
                                edges.node(n[1], n[2], j)
                            } else if i == 0 {
                                edges.node(n[2], n[0], k - j)
                            } else {
                                let (a, b, c) = ((k - i - j) as f64, i as f64, j as f64);
                                nodes.push(std::array::from_fn(|d| {
                                    (a * x[0][d] + b * x[1][d] + c * x[2][d]) / kf
                                }));
                                nodes.len() - 1
                            };
                        }
                    }
                }
                Element::Q4(_) => {
                    for j in 0..=k {
                        for i in 0..=k {
                            lattice[at(i, j)] = if j == 0 {
                                edges.node(n[0], n[1], i)
                            } else if i == k {
                                edges.node(n[1], n[2], j)
                            } else if j == k {
                                edges.node(n[2], n[3], k - i)
                            } else if i == 0 {
                                edges.node(n[3], n[0], k - j)
                            } else {
                                let (s, t) = (i as f64 / kf, j as f64 / kf);
                                let w =
                                    [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
                                nodes.push(std::array::from_fn(|d| {
                                    (0..4).map(|c| w[c] * x[c][d]).sum()
                                }));
                                nodes.len() - 1
                            };
                        }
                    }
                }
            }
            for child in &template(el).children {
                let c: Vec<usize> = child.iter().map(|&[i, j]| lattice[at(i, j)]).collect();
                elements.push(match c[..] {
                    [a, b, c] => Element::T3([a, b, c]),
                    [a, b, c, d] => Element::Q4([a, b, c, d]),
                    _ => unreachable!("children have 3 or 4 corners"),
                });
            }
        }

        let boundaries = self.refined_boundaries(k, &edges, &template);
        let node_sets = self.refined_node_sets(&edges);
        Mesh {
            nodes,
            elements,
            boundaries,
            node_sets,
        }
    }

    /// The named node sets of the mesh refined with `edges`: each keeps its nodes
    /// (their indices are kept) and gains the new nodes on its element edges,
    /// each edge becoming its k sub-edges.
    fn refined_node_sets(&self, edges: &EdgeNodes) -> BTreeMap<String, NodeSet> {
        let k = edges.k;
        (self.node_sets.iter())
            .map(|(name, set)| {
                let mut nodes = set.nodes.clone();
                let mut sub = Vec::with_capacity(set.edges.len() * k);
                for &[a, b] in &set.edges {
                    if k > 1 && !edges.first.contains_key(&(a.min(b), a.max(b))) {
                        sub.push([a, b]);
                        continue;
                    }
                    for s in 0..k {
                        let n = edges.node(a, b, s + 1);
                        if s + 1 < k {
                            nodes.push(n);
                        }
                        sub.push([edges.node(a, b, s), n]);
                    }
                }
                (name.clone(), NodeSet::new(nodes, sub))
            })
            .collect()
    }

    /// The named boundaries of the mesh refined `k` times: each boundary edge
    /// becomes its k sub-edges (nodes from `edges`), in order along the boundary,
    /// each owned by the child element (of the element's `template`) that has it.
    fn refined_boundaries<'t>(
        &self,
        k: usize,
        edges: &EdgeNodes,
        template: &dyn Fn(&Element) -> &'t Template,
    ) -> BTreeMap<String, Vec<BoundaryEdge>> {
        // Each boundary edge becomes its k sub-edges, owned by the child that has it.
        self.boundaries
            .iter()
            .map(|(name, list)| {
                let sub = list
                    .iter()
                    .flat_map(|e| {
                        let [a, b] = e.nodes;
                        let el = &self.elements[e.element];
                        let m = el
                            .edges()
                            .position(|[p, q]| (p, q) == (a, b) || (p, q) == (b, a))
                            .unwrap_or_else(|| {
                                panic!(
                                    "edge {:?} of boundary '{name}' is not an edge of element {}",
                                    e.nodes, e.element
                                )
                            });
                        let owner = &template(el).owner[m];
                        let forward = el.nodes()[m] == a;
                        let edges = &edges;
                        (0..k).map(move |s| BoundaryEdge {
                            nodes: [edges.node(a, b, s), edges.node(a, b, s + 1)],
                            element: e.element * k * k + owner[if forward { s } else { k - 1 - s }],
                        })
                    })
                    .collect();
                (name.clone(), sub)
            })
            .collect()
    }
}

/// A named boundary of a mesh that is a curved polygon
/// ([`Mesh::curved_boundaries`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CurvedBoundary {
    /// The boundary's name.
    pub name: String,
    /// The largest turn between two consecutive edges that counts as curved,
    /// in radians.
    pub largest_turn: f64,
}

/// Two consecutive edges of a named boundary turning by more than the first and
/// less than the second of these angles (radians) make it curved: more than
/// round-off (an arc of radius R meshed with edges h turns by h/R at each
/// vertex; below 1e-6 its sagitta h²/(8R) is below 1e-7 h) and less than a
/// corner (45°: a circle meshed with fewer than eight edges is not told from an
/// octagon's corners).
pub const CURVED_TURN: [f64; 2] = [1e-6, std::f64::consts::FRAC_PI_4];

impl Mesh {
    /// The named boundaries that are curved polygons: those with two consecutive
    /// edges (sharing a node, each of the boundary) that are not collinear, turning
    /// by an angle within [`CURVED_TURN`] — an arc meshed by its chords, not a
    /// straight side and not a corner. [`Mesh::refined`] keeps such a polygon:
    /// its new nodes lie on the chords, not on the curve. Sorted by name.
    pub fn curved_boundaries(&self) -> Vec<CurvedBoundary> {
        self.boundaries
            .iter()
            .filter_map(|(name, list)| {
                // Each node's neighbours along the boundary.
                let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
                for e in list {
                    let [a, b] = e.nodes;
                    next.entry(a).or_default().push(b);
                    next.entry(b).or_default().push(a);
                }
                let largest = next
                    .iter()
                    .filter(|(_, around)| around.len() == 2)
                    .map(|(&n, around)| {
                        let x = self.nodes[n];
                        let [p, q] = [self.nodes[around[0]], self.nodes[around[1]]];
                        let u = [p[0] - x[0], p[1] - x[1]];
                        let v = [q[0] - x[0], q[1] - x[1]];
                        // The edges run on from p through x to q: the turn is π
                        // minus the angle between the two edges at x.
                        let angle = (u[0] * v[1] - u[1] * v[0])
                            .abs()
                            .atan2(u[0] * v[0] + u[1] * v[1]);
                        std::f64::consts::PI - angle
                    })
                    .filter(|&t| t > CURVED_TURN[0] && t < CURVED_TURN[1])
                    .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))))?;
                Some(CurvedBoundary {
                    name: name.clone(),
                    largest_turn: largest,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ElementKind;

    /// A mixed mesh of [0, 3] × [0, 2]: 3 × 2 cells with the inner nodes moved off the
    /// grid, so that no quadrilateral is a parallelogram; cells (0, 0), (2, 0) and
    /// (1, 1) split into two T3, the others Q4. Boundaries as the rectangle's.
    fn mixed() -> Mesh {
        let mut m = Mesh::rectangle([0.0, 3.0], [0.0, 2.0], [3, 2], ElementKind::Q4);
        // Nodes (1, 1) and (2, 1) of the 4 × 3 grid, and the top middle ones.
        m.nodes[5] = [1.2, 0.9];
        m.nodes[6] = [1.85, 1.15];
        m.nodes[9] = [0.9, 2.0];
        for cell in [0, 2, 4] {
            let Element::Q4([a, b, c, d]) = m.elements[cell] else {
                unreachable!()
            };
            m.elements[cell] = Element::T3([a, b, c]);
            m.elements.push(Element::T3([a, c, d]));
        }
        // Owners: the element that has each boundary edge.
        for edges in m.boundaries.values_mut() {
            for e in edges.iter_mut() {
                e.element = m
                    .elements
                    .iter()
                    .position(|el| el.edges().any(|x| x == e.nodes))
                    .unwrap();
            }
        }
        m.validate("mixed").unwrap();
        m
    }

    /// The test meshes: T3 and Q4 rectangles, T3 and Q4 full rings (a seam, curved
    /// quadrilaterals), the mixed mesh.
    fn meshes() -> Vec<(&'static str, Mesh)> {
        let ring = |kind| Mesh::annulus([1.0, -2.0], [1.0, 2.0], [0.0, 360.0], [2, 8], kind);
        vec![
            (
                "T3 rectangle",
                Mesh::rectangle([1.0, 4.0], [-1.0, 1.0], [3, 2], ElementKind::T3),
            ),
            (
                "Q4 rectangle",
                Mesh::rectangle([1.0, 4.0], [-1.0, 1.0], [3, 2], ElementKind::Q4),
            ),
            ("T3 ring", ring(ElementKind::T3)),
            ("Q4 ring", ring(ElementKind::Q4)),
            ("mixed", mixed()),
        ]
    }

    /// The number of distinct edges of a mesh.
    fn edge_count(m: &Mesh) -> usize {
        let mut e: Vec<(usize, usize)> = m
            .elements
            .iter()
            .flat_map(|el| el.edges())
            .map(|[a, b]| (a.min(b), a.max(b)))
            .collect();
        e.sort_unstable();
        e.dedup();
        e.len()
    }

    /// Refined T3, Q4 and mixed meshes have the node and element counts of the formulas.
    #[test]
    fn counts_follow_the_formulas() {
        for (what, m) in meshes() {
            let (t3, q4) = m.counts();
            assert!(t3 + q4 > 0);
            for k in 1..=4 {
                let r = m.refined(k);
                // n + (k − 1) per edge + (k − 1)(k − 2)/2 per T3 + (k − 1)² per Q4;
                // k² children per element, of its kind; the input nodes first.
                let nodes = m.nodes.len()
                    + (k - 1) * edge_count(&m)
                    + t3 * (k - 1) * (k.max(2) - 2) / 2
                    + q4 * (k - 1) * (k - 1);
                assert_eq!(r.nodes.len(), nodes, "{what} k = {k}");
                assert_eq!(r.counts(), (k * k * t3, k * k * q4), "{what} k = {k}");
                assert_eq!(r.nodes[..m.nodes.len()], m.nodes[..], "{what} k = {k}");
                for (e, el) in m.elements.iter().enumerate() {
                    assert!(
                        r.elements[e * k * k..(e + 1) * k * k]
                            .iter()
                            .all(|c| c.kind() == el.kind())
                    );
                }
            }
        }
        // A structured rectangle: (k nx + 1)(k ny + 1) nodes.
        let r = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [3, 2], ElementKind::T3).refined(5);
        assert_eq!(r.nodes.len(), 16 * 11);
    }

    /// Children are counter-clockwise, tile their parent's area, and refined meshes validate.
    #[test]
    fn areas_are_preserved_and_meshes_valid() {
        for (what, m) in meshes() {
            for k in [1, 2, 3, 5] {
                let r = m.refined(k);
                r.validate(what).unwrap();
                for e in 0..m.elements.len() {
                    let parent = m.element_area(e);
                    let children: Vec<f64> = (e * k * k..(e + 1) * k * k)
                        .map(|c| r.element_area(c))
                        .collect();
                    assert!(children.iter().all(|&a| a > 0.0), "{what} k = {k}");
                    let sum: f64 = children.iter().sum();
                    assert!(
                        (sum - parent).abs() < 1e-13 * parent,
                        "{what} k = {k} element {e}: {sum} vs {parent}"
                    );
                }
            }
        }
    }

    /// Refined boundaries are exactly the free edges, with owners, in order along each one.
    #[test]
    fn boundaries_are_the_free_edges() {
        for (what, m) in meshes() {
            for k in [2, 3, 4] {
                let r = m.refined(k);
                let mut named: Vec<_> = r.boundaries.values().flatten().copied().collect();
                let mut free = r.boundary_edges();
                named.sort_by_key(|e| (e.element, e.nodes));
                free.sort_by_key(|e| (e.element, e.nodes));
                assert_eq!(named, free, "{what} k = {k}");
                for (name, edges) in &r.boundaries {
                    assert_eq!(edges.len(), k * m.boundaries[name].len(), "{what} {name}");
                    for w in edges.windows(2) {
                        assert_eq!(w[0].nodes[1], w[1].nodes[0], "{what} k = {k} {name}");
                    }
                    for e in edges {
                        assert!(
                            r.elements[e.element].edges().any(|x| x == e.nodes),
                            "{what} {name} {e:?}"
                        );
                    }
                }
            }
        }
    }

    /// Refining by k = 1 returns an identical mesh.
    #[test]
    fn factor_one_is_the_identity() {
        for (what, m) in meshes() {
            let r = m.refined(1);
            assert_eq!(r.nodes, m.nodes, "{what}");
            assert_eq!(r.elements, m.elements, "{what}");
            assert_eq!(r.boundaries, m.boundaries, "{what}");
        }
    }

    /// A refined rectangle is `Mesh::rectangle` with k× the cells, up to node numbering.
    #[test]
    fn refined_rectangle_is_the_finer_rectangle() {
        let key = |p: [f64; 2]| ((p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64);
        // An element as its corners' keys, rotated to start at the smallest.
        let corners = |m: &Mesh, e: usize| {
            let mut c: Vec<_> = m.elements[e]
                .nodes()
                .iter()
                .map(|&n| key(m.nodes[n]))
                .collect();
            let first = (0..c.len()).min_by_key(|&i| c[i]).unwrap();
            c.rotate_left(first);
            c
        };
        for kind in [ElementKind::T3, ElementKind::Q4] {
            for k in [2, 3, 4] {
                let coarse = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [7, 3], kind);
                let r = coarse.refined(k);
                let fine = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [7 * k, 3 * k], kind);
                assert_eq!(r.nodes.len(), fine.nodes.len());
                let mut a: Vec<_> = r.nodes.iter().map(|&p| key(p)).collect();
                let mut b: Vec<_> = fine.nodes.iter().map(|&p| key(p)).collect();
                a.sort_unstable();
                b.sort_unstable();
                assert_eq!(a, b, "{kind:?} k = {k}: nodes");
                let elements = |m: &Mesh| {
                    let mut v: Vec<_> = (0..m.elements.len()).map(|e| corners(m, e)).collect();
                    v.sort_unstable();
                    v
                };
                assert_eq!(elements(&r), elements(&fine), "{kind:?} k = {k}: elements");
                let sides = |m: &Mesh| -> Vec<(String, Vec<_>)> {
                    m.boundaries
                        .iter()
                        .map(|(name, edges)| {
                            let list = edges
                                .iter()
                                .map(|e| (e.nodes.map(|n| key(m.nodes[n])), corners(m, e.element)))
                                .collect();
                            (name.clone(), list)
                        })
                        .collect()
                };
                assert_eq!(sides(&r), sides(&fine), "{kind:?} k = {k}: boundaries");
            }
        }
    }

    /// New nodes sit at the parent's lattice points, where a linear field equals its interpolant.
    #[test]
    fn linear_field_is_interpolated_at_the_new_nodes() {
        let f = |p: [f64; 2]| 3.0 + 2.0 * p[0] - 5.0 * p[1];
        for (what, m) in meshes() {
            for k in [2, 3, 4] {
                let r = m.refined(k);
                for (e, el) in m.elements.iter().enumerate() {
                    let x = m.coordinates(e);
                    let values: Vec<f64> = x.iter().map(|&p| f(p)).collect();
                    // Lattice weights of the parent's corners at each (i, j).
                    let kf = k as f64;
                    let weights: Vec<Vec<f64>> = match el {
                        Element::T3(_) => (0..=k)
                            .flat_map(|j| (0..=k - j).map(move |i| (i, j)))
                            .map(|(i, j)| {
                                vec![(k - i - j) as f64 / kf, i as f64 / kf, j as f64 / kf]
                            })
                            .collect(),
                        Element::Q4(_) => (0..=k)
                            .flat_map(|j| (0..=k).map(move |i| (i as f64 / kf, j as f64 / kf)))
                            .map(|(s, t)| {
                                vec![(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t]
                            })
                            .collect(),
                    };
                    let mut own: Vec<usize> = r.elements[e * k * k..(e + 1) * k * k]
                        .iter()
                        .flat_map(|c| c.nodes().to_vec())
                        .collect();
                    own.sort_unstable();
                    own.dedup();
                    assert_eq!(own.len(), weights.len(), "{what} k = {k} element {e}");
                    let size = m.max_edge_length();
                    for w in &weights {
                        let p: [f64; 2] =
                            std::array::from_fn(|d| (0..x.len()).map(|c| w[c] * x[c][d]).sum());
                        let interpolated: f64 = (0..x.len()).map(|c| w[c] * values[c]).sum();
                        let n = own
                            .iter()
                            .copied()
                            .min_by(|&a, &b| {
                                crate::mesh::dist(r.nodes[a], p)
                                    .total_cmp(&crate::mesh::dist(r.nodes[b], p))
                            })
                            .unwrap();
                        assert!(
                            crate::mesh::dist(r.nodes[n], p) < 1e-13 * size,
                            "{what} k = {k} element {e}: {p:?}"
                        );
                        assert!(
                            (f(r.nodes[n]) - interpolated).abs()
                                < 1e-12 * (1.0 + interpolated.abs()),
                            "{what} k = {k}"
                        );
                    }
                }
            }
        }
    }

    /// A curved boundary is one whose consecutive edges turn by a small angle: an
    /// annulus's circles (turning by 2π/n at each vertex of n chords around) are
    /// curved and its radial sides are not; a rectangle's sides are straight, and
    /// its whole outline as one boundary turns only at 90° corners (not curved).
    /// Refined, the circles stay the same polygons: the largest turn is the
    /// same, at the input's vertices (the new nodes on the chords turn by 0).
    #[test]
    fn curved_boundaries_are_told_from_straight_sides_and_corners() {
        let ring = Mesh::annulus(
            [1.0, -2.0],
            [10.0, 20.0],
            [0.0, 90.0],
            [2, 9],
            ElementKind::T3,
        );
        let turn = (90.0f64 / 9.0).to_radians();
        for mesh in [ring.clone(), ring.refined(3)] {
            let curved = mesh.curved_boundaries();
            let names: Vec<&str> = curved.iter().map(|c| c.name.as_str()).collect();
            assert_eq!(names, ["inner", "outer"]);
            for c in &curved {
                assert!((c.largest_turn - turn).abs() < 1e-9, "{c:?}");
            }
        }
        let mut rect = Mesh::rectangle([0.0, 3.0], [0.0, 2.0], [3, 2], ElementKind::Q4);
        assert!(rect.curved_boundaries().is_empty());
        let outline: Vec<BoundaryEdge> = rect.boundary_edges();
        rect.boundaries.insert("outline".into(), outline);
        assert!(rect.refined(2).curved_boundaries().is_empty());
    }
}
