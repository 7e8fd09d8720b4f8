//! A part's mesh from plain arrays (points, element connectivity, named boundaries
//! as edges or node sets), as a program or the Python package hands it over:
//! checked, with clockwise elements reversed and the boundaries oriented and
//! ordered as the built-in meshers and the Gmsh reader make them.

use super::gmsh::chain_order;
use super::{BoundaryEdge, Element, Mesh};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap, HashSet};

/// A named boundary given as arrays.
#[derive(Debug, Clone, PartialEq)]
pub enum BoundarySelection {
    /// Node pairs, each an element edge on the part's boundary (in either order).
    Edges(Vec<[usize; 2]>),
    /// A node set: the boundary is every boundary edge whose two ends are in it.
    Nodes(Vec<usize>),
}

impl Mesh {
    /// The mesh of part `part` from its node coordinates, its elements (T3 and Q4
    /// may be mixed; their nodes in order around the element, either way round)
    /// and its named boundaries. Node indices are checked against the nodes,
    /// clockwise elements are reversed, and the mesh passes [`Mesh::validate`]. A
    /// boundary's edges are oriented counter-clockwise with respect to the part and
    /// ordered along their chains, as [`Mesh::rectangle`] and the Gmsh reader make
    /// them. Errors name the part, the element or boundary, and the nodes at fault.
    pub fn from_arrays(
        part: &str,
        nodes: Vec<[f64; 2]>,
        elements: Vec<Element>,
        boundaries: Vec<(String, BoundarySelection)>,
    ) -> Result<Mesh> {
        let err = |message: String| Error::Mesh {
            part: part.to_string(),
            message,
        };
        let n = nodes.len();
        let mut oriented = Vec::with_capacity(elements.len());
        for (e, el) in elements.into_iter().enumerate() {
            if let Some(&bad) = el.nodes().iter().find(|&&k| k >= n) {
                return Err(err(format!(
                    "element {e} ({:?}) uses node {bad}, but the part has {n} nodes (0 to {})",
                    el.nodes(),
                    n.saturating_sub(1)
                )));
            }
            let area = super::polygon_area(el.nodes().iter().map(|&k| nodes[k]));
            // Reversed as the Gmsh reader reverses a clockwise element.
            oriented.push(match el {
                Element::T3([a, b, c]) if area < 0.0 => Element::T3([c, b, a]),
                Element::Q4([a, b, c, d]) if area < 0.0 => Element::Q4([d, c, b, a]),
                el => el,
            });
        }
        let mut mesh: Mesh = Mesh {
            nodes,
            elements: oriented,
            boundaries: BTreeMap::new(),
            node_sets: BTreeMap::new(),
        };
        mesh.validate(part)?;
        let free: HashMap<(usize, usize), BoundaryEdge> = mesh
            .boundary_edges()
            .into_iter()
            .map(|e| ((e.nodes[0].min(e.nodes[1]), e.nodes[0].max(e.nodes[1])), e))
            .collect();
        let key = |[a, b]: [usize; 2]| (a.min(b), a.max(b));
        for (name, selection) in boundaries {
            if mesh.boundaries.contains_key(&name) {
                return Err(err(format!("boundary '{name}' is given twice")));
            }
            let edges: Vec<BoundaryEdge> = match &selection {
                BoundarySelection::Edges(pairs) => {
                    if pairs.is_empty() {
                        return Err(err(format!("boundary '{name}' has no edges")));
                    }
                    let mut edges = Vec::with_capacity(pairs.len());
                    for (i, &pair) in pairs.iter().enumerate() {
                        match free.get(&key(pair)) {
                            Some(edge) => edges.push(*edge),
                            None => {
                                let what = if pair.iter().any(|&k| k >= n) {
                                    format!("uses a node out of range (the part has {n} nodes)")
                                } else if mesh
                                    .elements
                                    .iter()
                                    .any(|el| el.edges().any(|e| key(e) == key(pair)))
                                {
                                    "is an edge inside the part (shared by two elements), not on its boundary".to_string()
                                } else {
                                    "is not an edge of any element".to_string()
                                };
                                return Err(err(format!(
                                    "boundary '{name}': edge {i} ({}, {}) {what}",
                                    pair[0], pair[1]
                                )));
                            }
                        }
                    }
                    edges
                }
                BoundarySelection::Nodes(list) => {
                    if let Some(&bad) = list.iter().find(|&&k| k >= n) {
                        return Err(err(format!(
                            "boundary '{name}' names node {bad}, but the part has {n} nodes"
                        )));
                    }
                    let set: HashSet<usize> = list.iter().copied().collect();
                    let mut edges: Vec<BoundaryEdge> = free
                        .values()
                        .filter(|e| set.contains(&e.nodes[0]) && set.contains(&e.nodes[1]))
                        .copied()
                        .collect();
                    edges.sort_by_key(|e| (e.element, e.nodes));
                    if edges.is_empty() {
                        return Err(err(format!(
                            "boundary '{name}': no boundary edge of the part joins two of its {} nodes",
                            set.len()
                        )));
                    }
                    edges
                }
            };
            mesh.boundaries.insert(name, chain_order(edges));
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ElementKind;

    /// The rectangle mesher's mesh given back as arrays (one triangle clockwise,
    /// boundaries as reversed edges and as node sets) is the same mesh.
    #[test]
    fn arrays_give_the_rectangle_mesh() {
        let m = Mesh::rectangle([0.0, 3.0], [0.0, 2.0], [3, 2], ElementKind::T3);
        let mut elements = m.elements.clone();
        if let Element::T3([a, b, c]) = elements[1] {
            elements[1] = Element::T3([c, b, a]);
        }
        let bottom: Vec<[usize; 2]> = m.boundaries["bottom"]
            .iter()
            .rev()
            .map(|e| [e.nodes[1], e.nodes[0]])
            .collect();
        let top = m.boundary_nodes("top").unwrap();
        let a = Mesh::from_arrays(
            "p",
            m.nodes.clone(),
            elements,
            vec![
                ("bottom".into(), BoundarySelection::Edges(bottom)),
                ("top".into(), BoundarySelection::Nodes(top)),
            ],
        )
        .unwrap();
        assert_eq!(a.elements, m.elements);
        assert_eq!(a.boundaries["bottom"], m.boundaries["bottom"]);
        assert_eq!(a.boundaries["top"], m.boundaries["top"]);
    }

    /// Bad indices, inner edges and empty selections are errors naming them.
    #[test]
    fn bad_arrays_are_named() {
        let m = Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1], ElementKind::Q4);
        let msg = |elements: Vec<Element>, b: BoundarySelection| {
            Mesh::from_arrays("p", m.nodes.clone(), elements, vec![("b".into(), b)])
                .unwrap_err()
                .to_string()
        };
        let e = msg(
            vec![Element::Q4([0, 1, 4, 9])],
            BoundarySelection::Nodes(vec![0]),
        );
        assert!(e.contains("element 0") && e.contains("node 9"), "{e}");
        let e = msg(m.elements.clone(), BoundarySelection::Edges(vec![[1, 4]]));
        assert!(e.contains("inside the part"), "{e}");
        let e = msg(m.elements.clone(), BoundarySelection::Edges(vec![[0, 4]]));
        assert!(e.contains("not an edge"), "{e}");
        let e = msg(m.elements.clone(), BoundarySelection::Nodes(vec![0, 4]));
        assert!(e.contains("no boundary edge"), "{e}");
    }
}
