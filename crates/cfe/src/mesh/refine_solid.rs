//! Uniform refinement of a solid mesh (`Mesh<D3>`) by a factor k, what `--refine K`
//! does to a 3D part: every edge split into k equal segments, every HEX8 into k³
//! HEX8 (the image of a k × k × k grid under its trilinear map) and every TET4
//! into k³ TET4 (its regular k-subdivision: the barycentric lattice of spacing
//! 1/k cut into upright and inverted tetrahedra and octahedra, each octahedron
//! split into four tetrahedra around its shortest diagonal — for k = 2 the
//! classical 8-tetrahedron split). It is one k-subdivision, not repeated
//! halving: any k ≥ 1 is done in one pass.
//!
//! Conformity: every new point is known by its weights on the corners of the
//! element it was made in, with zero weights dropped. A point on an edge or a face
//! has weights only on that edge's or face's corners, the same ones from both
//! elements that share it, so it is created once (a hash of those weights) and
//! shared; points inside an element are its own. A triangle's k-lattice is unique
//! (the lines parallel to its sides), so the octahedra's diagonals, which are
//! interior, never disagree across a face.

use super::solid::{BoundaryFace, HEX8_CORNERS, SolidElement, SolidKind};
use super::{Mesh, NodeSet};
use crate::dim::{D3, Dim};
use std::collections::{BTreeMap, HashMap};

/// The subdivision of one reference element at factor k: its lattice points as
/// integer weights on the element's corners (over the common denominator k³), its
/// children as lattice points, and which child faces lie on each of its faces.
struct Template {
    /// Each lattice point's weights on the element's 4 or 8 corners, summing to k³.
    points: Vec<Vec<u64>>,
    /// The children, each as the indices of its corners in `points`, in the VTK
    /// order of its kind (TET4 or HEX8, the parent's kind), positive.
    children: Vec<Vec<usize>>,
    /// `on_face[f]`: (child, child's local face) of the child faces lying on the
    /// element's local face f.
    on_face: Vec<Vec<(usize, usize)>>,
}

impl Template {
    /// The children's faces lying on each local face of a parent of `kind`: those
    /// whose lattice points all have zero weight on the corners off that face.
    fn find_faces(&mut self, kind: SolidKind) {
        let parent = match kind {
            SolidKind::Tet4 => SolidElement::Tet4([0, 1, 2, 3]),
            SolidKind::Hex8 => SolidElement::Hex8([0, 1, 2, 3, 4, 5, 6, 7]),
        };
        self.on_face = (0..parent.face_count())
            .map(|f| {
                let on = parent.face(f);
                let off: Vec<usize> = (0..kind.node_count())
                    .filter(|c| !on.as_slice().contains(c))
                    .collect();
                let mut found = Vec::new();
                for (c, child) in self.children.iter().enumerate() {
                    let el = as_element(kind, child);
                    for cf in 0..el.face_count() {
                        if el
                            .face(cf)
                            .as_slice()
                            .iter()
                            .all(|&p| off.iter().all(|&o| self.points[p][o] == 0))
                        {
                            found.push((c, cf));
                        }
                    }
                }
                found
            })
            .collect();
    }

    /// A HEX8 cut into k³: point (i, j, l) of the grid has weight
    /// Π (i or k − i)… on each corner; child (i, j, l) is the grid cell there,
    /// row by row, layer by layer.
    fn hexahedron(k: usize) -> Template {
        let kk = k as u64;
        let at = |i: usize, j: usize, l: usize| (l * (k + 1) + j) * (k + 1) + i;
        let mut points = Vec::with_capacity((k + 1).pow(3));
        for l in 0..=k {
            for j in 0..=k {
                for i in 0..=k {
                    let g = [i as u64, j as u64, l as u64];
                    points.push(
                        HEX8_CORNERS
                            .iter()
                            .map(|o| {
                                (0..3)
                                    .map(|a| if o[a] == 1 { g[a] } else { kk - g[a] })
                                    .product()
                            })
                            .collect(),
                    );
                }
            }
        }
        let mut children = Vec::with_capacity(k * k * k);
        for l in 0..k {
            for j in 0..k {
                for i in 0..k {
                    children.push(
                        HEX8_CORNERS
                            .iter()
                            .map(|o| at(i + o[0], j + o[1], l + o[2]))
                            .collect(),
                    );
                }
            }
        }
        let mut t = Template {
            points,
            children,
            on_face: Vec::new(),
        };
        t.find_faces(SolidKind::Hex8);
        t
    }

    /// A TET4 cut into k³: lattice point (a, b, c) (a + b + c ≤ k) is
    /// x₀ + (a E₁ + b E₂ + c E₃)/k, Eᵢ = xᵢ − x₀ (weights k − a − b − c, a, b, c
    /// over k, times k² for the common denominator). Each unit cube of the lattice
    /// at (a, b, c) with s = a + b + c gives an upright tetrahedron (s + 1 ≤ k), the
    /// octahedron between the planes s + 1 and s + 2 (s + 2 ≤ k), cut into four
    /// around the diagonal `diagonal` (0, 1, 2: the one from corner + e_d to
    /// + e₁ + e₂ + e₃ − e_d), and an inverted tetrahedron (s + 3 ≤ k).
    fn tetrahedron(k: usize, diagonal: usize) -> Template {
        let kk = k as u64;
        let mut index = HashMap::new();
        let mut points = Vec::new();
        for c in 0..=k {
            for b in 0..=k - c {
                for a in 0..=k - b - c {
                    index.insert([a, b, c], points.len());
                    let w = [(k - a - b - c) as u64, a as u64, b as u64, c as u64];
                    points.push(w.iter().map(|v| v * kk * kk).collect());
                }
            }
        }
        let mut children: Vec<Vec<usize>> = Vec::with_capacity(k * k * k);
        // A tetrahedron of lattice points, turned positive if needed.
        let mut push = |mut t: [[usize; 3]; 4]| {
            let v = |p: [usize; 3]| p.map(|x| x as i64);
            let (p0, p1, p2, p3) = (v(t[0]), v(t[1]), v(t[2]), v(t[3]));
            let d = |p: [i64; 3]| [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]];
            let (u, w, z) = (d(p1), d(p2), d(p3));
            let det = u[0] * (w[1] * z[2] - w[2] * z[1]) - u[1] * (w[0] * z[2] - w[2] * z[0])
                + u[2] * (w[0] * z[1] - w[1] * z[0]);
            if det < 0 {
                t.swap(1, 2);
            }
            children.push(t.iter().map(|p| index[p]).collect());
        };
        let e = |o: [usize; 3], add: &[usize]| {
            let mut p = o;
            for &a in add {
                p[a] += 1;
            }
            p
        };
        for c in 0..k {
            for b in 0..k - c {
                for a in 0..k - b - c {
                    let o = [a, b, c];
                    let s = a + b + c;
                    push([o, e(o, &[0]), e(o, &[1]), e(o, &[2])]);
                    if s + 2 <= k {
                        // The octahedron's opposite pairs: +e_d and +(all but d).
                        let pair = |d: usize| {
                            let rest: Vec<usize> = (0..3).filter(|&x| x != d).collect();
                            (e(o, &[d]), e(o, &rest))
                        };
                        let (p, q) = pair(diagonal);
                        let (r0, r2) = pair((diagonal + 1) % 3);
                        let (r3, r1) = pair((diagonal + 2) % 3);
                        for (x, y) in [(r0, r1), (r1, r2), (r2, r3), (r3, r0)] {
                            push([p, q, x, y]);
                        }
                    }
                    if s + 3 <= k {
                        push([
                            e(o, &[0, 1]),
                            e(o, &[0, 2]),
                            e(o, &[1, 2]),
                            e(o, &[0, 1, 2]),
                        ]);
                    }
                }
            }
        }
        let mut t = Template {
            points,
            children,
            on_face: Vec::new(),
        };
        t.find_faces(SolidKind::Tet4);
        t
    }
}

/// A child given as lattice points, as an element of `kind`.
fn as_element(kind: SolidKind, nodes: &[usize]) -> SolidElement {
    match kind {
        SolidKind::Tet4 => SolidElement::Tet4(std::array::from_fn(|i| nodes[i])),
        SolidKind::Hex8 => SolidElement::Hex8(std::array::from_fn(|i| nodes[i])),
    }
}

/// Which octahedron diagonal of a TET4's subdivision is shortest: d = 0, 1, 2
/// runs along E_d − Σ_{i≠d} Eᵢ (Eᵢ = x_{i+1} − x₀); ties go to the lowest d.
fn shortest_diagonal(x: [[f64; 3]; 4]) -> usize {
    let edge = |i: usize| [0, 1, 2].map(|c| x[i + 1][c] - x[0][c]);
    let length = |d: usize| {
        let v: [f64; 3] = std::array::from_fn(|c| {
            (0..3)
                .map(|i| if i == d { edge(i)[c] } else { -edge(i)[c] })
                .sum()
        });
        D3::length(&v)
    };
    let mut best = 0;
    for d in 1..3 {
        if length(d) < length(best) {
            best = d;
        }
    }
    best
}

impl Mesh<D3> {
    /// The mesh refined uniformly by the factor `k`: every edge split into k equal
    /// segments, each HEX8 into k³ HEX8 (the image of a k³ grid under its trilinear
    /// map: the children fill it exactly) and each TET4 into k³ TET4 (its regular
    /// k-subdivision, the octahedra of the lattice split around their shortest
    /// diagonal; for k = 2 the 8-tetrahedron split), every child positive. Named
    /// boundaries are refined with it: each boundary face becomes its k² sub-faces,
    /// owned by the children that have them, outward. Nodes on shared edges and
    /// faces are made once, so a conforming mesh stays conforming.
    ///
    /// Numbering: the input nodes keep their indices `0..n`; new nodes follow in
    /// the order the elements first make them (element by element, each element's
    /// lattice in its order). Element e's children are elements `e k³ .. (e + 1) k³`.
    /// `k = 1` returns an identical mesh.
    ///
    /// New nodes lie on the input's straight edges and flat (or bilinear) faces: a
    /// curved surface stays the polyhedron the input mesh gives it.
    ///
    /// Panics if `k` is 0, if k³ overflows, or if a named boundary face's local
    /// face index is not a face of its element (meshes from the built-in mesher
    /// and the readers always are; [`Mesh::validate`] checks it).
    pub fn refined(&self, k: usize) -> Mesh<D3> {
        assert!(k >= 1, "the refinement factor must be at least 1");
        let k3 = k
            .checked_pow(3)
            .expect("the refinement factor's cube overflows");
        let denominator = k3 as f64;
        let hexahedron = Template::hexahedron(k);
        let tetrahedra = [0, 1, 2].map(|d| Template::tetrahedron(k, d));
        let template = |el: &SolidElement| -> &Template {
            match el {
                SolidElement::Hex8(_) => &hexahedron,
                SolidElement::Tet4(n) => &tetrahedra[shortest_diagonal(n.map(|a| self.nodes[a]))],
            }
        };

        let mut nodes = self.nodes.clone();
        // The shared points: (corner node, weight) pairs sorted by node → node.
        let mut shared: HashMap<Vec<(usize, u64)>, usize> = HashMap::new();
        let mut elements = Vec::with_capacity(self.elements.len().saturating_mul(k3));
        let mut lattice = Vec::new();
        for el in &self.elements {
            let t = template(el);
            let corners = el.nodes();
            lattice.clear();
            for w in &t.points {
                let mut key: Vec<(usize, u64)> = corners
                    .iter()
                    .zip(w)
                    .filter(|(_, w)| **w > 0)
                    .map(|(&n, &w)| (n, w))
                    .collect();
                let node = if key.len() == 1 {
                    key[0].0
                } else {
                    key.sort_unstable();
                    let on_boundary = key.len() < corners.len();
                    let make = |nodes: &mut Vec<[f64; 3]>| {
                        nodes.push(std::array::from_fn(|c| {
                            key.iter()
                                .map(|&(n, w)| w as f64 * self.nodes[n][c])
                                .sum::<f64>()
                                / denominator
                        }));
                        nodes.len() - 1
                    };
                    if on_boundary {
                        match shared.get(&key) {
                            Some(&n) => n,
                            None => {
                                let n = make(&mut nodes);
                                shared.insert(key, n);
                                n
                            }
                        }
                    } else {
                        make(&mut nodes)
                    }
                };
                lattice.push(node);
            }
            for child in &t.children {
                let c: Vec<usize> = child.iter().map(|&p| lattice[p]).collect();
                elements.push(as_element(el.kind(), &c));
            }
        }

        let boundaries: BTreeMap<String, Vec<BoundaryFace>> = self
            .boundaries
            .iter()
            .map(|(name, faces)| {
                let sub = faces
                    .iter()
                    .flat_map(|b| {
                        let el = &self.elements[b.element];
                        assert!(
                            b.face < el.face_count(),
                            "face {:?} of boundary '{name}' is not a face of element {}",
                            b.nodes,
                            b.element
                        );
                        let first = b.element * k3;
                        let elements = &elements;
                        template(el).on_face[b.face].iter().map(move |&(c, cf)| {
                            let child: &SolidElement = &elements[first + c];
                            BoundaryFace {
                                nodes: child.face(cf),
                                element: first + c,
                                face: cf,
                            }
                        })
                    })
                    .collect();
                (name.clone(), sub)
            })
            .collect();
        let node_sets = self.refined_node_sets(&shared);
        Mesh {
            nodes,
            elements,
            boundaries,
            node_sets,
        }
    }

    /// The named node sets of the refined mesh whose points on shared edges and
    /// faces are `shared` (corner weights → node): each keeps its nodes (their
    /// indices are kept) and gains the new nodes on its element edges, in order
    /// along each edge, each edge becoming its sub-edges.
    fn refined_node_sets(
        &self,
        shared: &HashMap<Vec<(usize, u64)>, usize>,
    ) -> BTreeMap<String, NodeSet> {
        // The new nodes of each element edge (lower node, higher node), each
        // with its weight at the higher node (its distance from the lower one).
        let mut on_edge: HashMap<(usize, usize), Vec<(u64, usize)>> = HashMap::new();
        if self.node_sets.values().any(|s| !s.edges.is_empty()) {
            for (key, &n) in shared {
                if let [(a, _), (b, wb)] = key[..] {
                    on_edge.entry((a, b)).or_default().push((wb, n));
                }
            }
            for list in on_edge.values_mut() {
                list.sort_unstable();
            }
        }
        (self.node_sets.iter())
            .map(|(name, set)| {
                let mut nodes = set.nodes.clone();
                let mut sub = Vec::new();
                for &[a, b] in &set.edges {
                    let inner = on_edge.get(&(a.min(b), a.max(b)));
                    let mut chain = vec![a.min(b)];
                    chain.extend(inner.into_iter().flatten().map(|&(_, n)| n));
                    chain.push(a.max(b));
                    nodes.extend(&chain[1..chain.len() - 1]);
                    sub.extend(chain.windows(2).map(|w| [w[0], w[1]]));
                }
                (name.clone(), NodeSet::new(nodes, sub))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::solid::tetrahedron_volume;

    fn total_volume(m: &Mesh<D3>) -> f64 {
        (0..m.elements.len()).map(|e| m.element_volume(e)).sum()
    }

    fn side_areas(m: &Mesh<D3>) -> BTreeMap<String, f64> {
        m.boundaries
            .iter()
            .map(|(name, faces)| {
                let area = faces
                    .iter()
                    .map(|f| D3::length(&f.nodes.vector_area(&m.nodes)))
                    .sum();
                (name.clone(), area)
            })
            .collect()
    }

    /// Pairs of nodes closer than `tol`, found through a grid of cells of size
    /// `cell` (each node against the 27 cells around it).
    fn near_pairs(nodes: &[[f64; 3]], cell: f64, tol: f64) -> Vec<[usize; 2]> {
        let at = |p: [f64; 3]| p.map(|x| (x / cell).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (n, p) in nodes.iter().enumerate() {
            grid.entry(at(*p)).or_default().push(n);
        }
        let mut out = Vec::new();
        for (n, p) in nodes.iter().enumerate() {
            let c = at(*p);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for &m in grid
                            .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                            .into_iter()
                            .flatten()
                        {
                            let q = nodes[m];
                            let d = D3::length(&[q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
                            if m > n && d < tol {
                                out.push([n, m]);
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The box [0, 2] × [0, 1.5] × [0, 1] in 3 × 3 × 2 cells with its interior
    /// nodes moved off the grid (up to 0.06).
    fn distorted(kind: SolidKind) -> Mesh<D3> {
        let mut m = Mesh::<D3>::block([0.0, 2.0], [0.0, 1.5], [0.0, 1.0], [3, 3, 2], kind);
        let hi = [2.0, 1.5, 1.0];
        for (n, p) in m.nodes.iter_mut().enumerate() {
            if (0..3).all(|c| p[c] > 1e-9 && p[c] < hi[c] - 1e-9) {
                for (c, x) in p.iter_mut().enumerate() {
                    *x += 0.06 * ((n * 7 + c * 3) as f64).sin();
                }
            }
        }
        m
    }

    /// Refining by k = 1, 2, 3 conserves the volume and each named side's area,
    /// gives k³ valid children per element, a conforming mesh (no two nodes at one
    /// point; the faces used once are exactly the refined named sides, so no
    /// interior face is left unmatched), and on the structured box the node count
    /// of the box meshed with k times the cells.
    #[test]
    fn refinement_conserves_volume_and_areas_and_conforms() {
        for kind in [SolidKind::Tet4, SolidKind::Hex8] {
            let m = distorted(kind);
            let straight = Mesh::<D3>::block([0.0, 2.0], [0.0, 1.5], [0.0, 1.0], [3, 3, 2], kind);
            for k in 1..=3 {
                let r = m.refined(k);
                r.validate("refined").unwrap();
                assert_eq!(r.elements.len(), k * k * k * m.elements.len());
                assert!((total_volume(&r) - 3.0).abs() < 1e-12, "{kind:?} k = {k}");
                for (name, area) in side_areas(&r) {
                    assert!((area - side_areas(&m)[&name]).abs() < 1e-12, "{name}");
                    assert_eq!(r.boundaries[&name].len(), k * k * m.boundaries[&name].len());
                }
                let h = r.max_edge_length();
                assert!(
                    near_pairs(&r.nodes, h, 1e-6 * h).is_empty(),
                    "{kind:?} k = {k}"
                );
                let mut named: Vec<BoundaryFace> =
                    r.boundaries.values().flatten().copied().collect();
                let mut free = r.boundary_faces();
                named.sort_unstable();
                free.sort_unstable();
                assert_eq!(named, free, "{kind:?} k = {k}");
                let s = straight.refined(k);
                assert_eq!(s.nodes.len(), (3 * k + 1) * (3 * k + 1) * (2 * k + 1));
            }
            assert_eq!(m.refined(1).nodes, m.nodes);
            assert_eq!(m.refined(1).elements, m.elements);
        }
    }

    /// The regular k-subdivision of one irregular tetrahedron gives k³ children of
    /// equal volume V/k³ (for k = 2 to 4), and for k = 2 the one interior edge
    /// joins the midpoints of the pair of opposite edges closest to each other —
    /// the shortest of the three diagonals of the octahedron.
    #[test]
    fn tetrahedron_subdivision_is_regular_and_takes_the_shortest_diagonal() {
        // The shortest pair of opposite-edge midpoints: (02, 13) in the first,
        // (01, 23) in the second, (03, 12) in the last two.
        let shapes = [
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.8, 1.0, 1.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.1, -0.1, 1.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [2.0, 0.1, 0.0],
                [0.3, 1.0, 0.2],
                [0.4, 0.3, 1.5],
            ],
            [
                [0.0, 0.0, 0.0],
                [0.5, 0.0, 0.0],
                [0.0, 0.6, 0.0],
                [1.0, 1.0, 2.0],
            ],
        ];
        let mut chosen = std::collections::BTreeSet::new();
        for x in shapes {
            let m = Mesh::<D3> {
                nodes: x.to_vec(),
                elements: vec![SolidElement::Tet4([0, 1, 2, 3])],
                boundaries: BTreeMap::new(),
                node_sets: BTreeMap::new(),
            };
            let v = tetrahedron_volume(x[0], x[1], x[2], x[3]);
            assert!(v > 0.0);
            for k in 2..=4 {
                let r = m.refined(k);
                assert_eq!(r.elements.len(), k * k * k);
                let kf = (k * k * k) as f64;
                for e in 0..r.elements.len() {
                    assert!((r.element_volume(e) - v / kf).abs() < 1e-14 * v, "k = {k}");
                }
            }
            // The midpoints of the opposite edges (01, 23), (02, 13), (03, 12).
            let mid = |a: usize, b: usize| -> [f64; 3] {
                std::array::from_fn(|c| 0.5 * (x[a][c] + x[b][c]))
            };
            let pairs = [
                (mid(0, 1), mid(2, 3)),
                (mid(0, 2), mid(1, 3)),
                (mid(0, 3), mid(1, 2)),
            ];
            let length =
                |(p, q): ([f64; 3], [f64; 3])| D3::length(&[q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
            let shortest = (0..3)
                .min_by(|&a, &b| length(pairs[a]).total_cmp(&length(pairs[b])))
                .unwrap();
            let r = m.refined(2);
            let find = |p: [f64; 3]| {
                r.nodes
                    .iter()
                    .position(|q| D3::length(&[q[0] - p[0], q[1] - p[1], q[2] - p[2]]) < 1e-12)
                    .unwrap()
            };
            let joined: Vec<bool> = pairs
                .iter()
                .map(|&(p, q)| {
                    let (a, b) = (find(p), find(q));
                    r.elements.iter().any(|el| {
                        el.edges()
                            .any(|[c, d]| (c, d) == (a, b) || (c, d) == (b, a))
                    })
                })
                .collect();
            let want: Vec<bool> = (0..3).map(|i| i == shortest).collect();
            assert_eq!(joined, want, "{x:?}");
            chosen.insert(shortest);
        }
        assert_eq!(chosen.len(), 3, "the shapes exercise every diagonal");
    }

    /// Two HEX8 sharing a face and refined by 3 share the face's 16 points: the
    /// node count is that of a 2 × 1 × 1 block refined, (6 + 1)(3 + 1)(3 + 1).
    #[test]
    fn shared_face_points_are_made_once() {
        let m = Mesh::<D3>::block(
            [0.0, 2.0],
            [0.0, 1.0],
            [0.0, 1.0],
            [2, 1, 1],
            SolidKind::Hex8,
        );
        let r = m.refined(3);
        assert_eq!(r.nodes.len(), 7 * 4 * 4);
        assert!(r.unused_nodes().is_empty());
    }
}
