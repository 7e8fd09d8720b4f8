//! A solid part's mesh from arrays (points (n, 3), tetrahedra (m, 4) and/or
//! hexahedra (k, 8), boundaries as faces or node sets), as the plane
//! [`cfe::Mesh::from_arrays`] makes a plane one: node indices checked, elements
//! of negative volume mirrored (as the Gmsh reader mirrors them), boundary
//! faces matched against the part's own boundary faces and oriented outward,
//! then [`Mesh::<D3>::validate`](cfe::Mesh::validate).

use cfe::dim::D3;
use cfe::mesh::{BoundaryFace, SolidElement};
use cfe::{Error, Mesh, Result};
use std::collections::{BTreeMap, HashMap, HashSet};

/// A named boundary of a solid mesh given as arrays.
pub enum FaceSelection {
    /// Faces, each the corners of a triangle (3) or a quadrangle (4), in
    /// either orientation: each must be a face of an element on the part's
    /// boundary.
    Faces(Vec<Vec<usize>>),
    /// A node set: the boundary is every boundary face whose corners are all in it.
    Nodes(Vec<usize>),
}

/// The corners of a face as a sorted key (a triangle's padded with `usize::MAX`).
fn key(nodes: &[usize]) -> [usize; 4] {
    let mut k = [usize::MAX; 4];
    k[..nodes.len()].copy_from_slice(nodes);
    k.sort_unstable();
    k
}

/// The solid mesh of part `part` from its node coordinates, its elements and its
/// named boundaries; errors ([`Error::Mesh`]) name the part, the element or
/// boundary and the nodes at fault.
pub fn from_arrays(
    part: &str,
    nodes: Vec<[f64; 3]>,
    elements: Vec<SolidElement>,
    boundaries: Vec<(String, FaceSelection)>,
) -> Result<Mesh<D3>> {
    let err = |message: String| Error::Mesh {
        part: part.to_string(),
        message,
    };
    let n = nodes.len();
    for (e, el) in elements.iter().enumerate() {
        if let Some(&bad) = el.nodes().iter().find(|&&k| k >= n) {
            return Err(err(format!(
                "element {e} ({:?}) uses node {bad}, but the part has {n} nodes (0 to {})",
                el.nodes(),
                n.saturating_sub(1)
            )));
        }
    }
    let mut mesh = Mesh::<D3> {
        nodes,
        elements,
        boundaries: BTreeMap::new(),
        node_sets: Default::default(),
    };
    // Mirrored as the Gmsh reader mirrors an element of negative volume; an
    // element inverted at some corners only stays so and `validate` names it.
    for e in 0..mesh.elements.len() {
        if mesh.element_volume(e) < 0.0 {
            mesh.elements[e] = match mesh.elements[e] {
                SolidElement::Tet4([a, b, c, d]) => SolidElement::Tet4([a, c, b, d]),
                SolidElement::Hex8([a, b, c, d, e, f, g, h]) => {
                    SolidElement::Hex8([a, d, c, b, e, h, g, f])
                }
            };
        }
    }
    mesh.validate(part)?;
    let free: HashMap<[usize; 4], BoundaryFace> = (mesh.boundary_faces().into_iter())
        .map(|f| (key(f.nodes.as_slice()), f))
        .collect();
    for (name, selection) in boundaries {
        if mesh.boundaries.contains_key(&name) {
            return Err(err(format!("boundary '{name}' is given twice")));
        }
        let faces: Vec<BoundaryFace> = match &selection {
            FaceSelection::Faces(list) => {
                if list.is_empty() {
                    return Err(err(format!("boundary '{name}' has no faces")));
                }
                let mut faces = Vec::with_capacity(list.len());
                for (i, f) in list.iter().enumerate() {
                    if let Some(&bad) = f.iter().find(|&&k| k >= n) {
                        return Err(err(format!(
                            "face {i} of boundary '{name}' ({f:?}) uses node {bad}, but the part has {n} nodes"
                        )));
                    }
                    match free.get(&key(f)) {
                        Some(face) => faces.push(*face),
                        None => {
                            return Err(err(format!(
                                "face {i} of boundary '{name}' (nodes {f:?}) is not a face of an element on the part's boundary (a face inside the part, or nodes that make no element face)"
                            )));
                        }
                    }
                }
                faces
            }
            FaceSelection::Nodes(list) => {
                if let Some(&bad) = list.iter().find(|&&k| k >= n) {
                    return Err(err(format!(
                        "boundary '{name}' names node {bad}, but the part has {n} nodes"
                    )));
                }
                let set: HashSet<usize> = list.iter().copied().collect();
                let mut faces: Vec<BoundaryFace> = (free.values())
                    .filter(|f| f.nodes.as_slice().iter().all(|k| set.contains(k)))
                    .copied()
                    .collect();
                faces.sort_unstable_by_key(|f| (f.element, f.face));
                if faces.is_empty() {
                    return Err(err(format!(
                        "boundary '{name}': no boundary face has all its corners among its {} nodes",
                        set.len()
                    )));
                }
                faces
            }
        };
        mesh.boundaries.insert(name, faces);
    }
    Ok(mesh)
}
