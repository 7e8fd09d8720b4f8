//! Stress recovery: element stresses (constant in a T3, the Gauss-point mean in a
//! Q4) and nodal stresses averaged (area-weighted) over the elements around each
//! node from each element's corner values (a Q4's extrapolated from its Gauss
//! points), within one part only — never across parts, whose meshes are
//! independent.

use super::Material;
use super::element;
use crate::mesh::{Element, Mesh};

/// Stresses of one part: per element and averaged per node, (σxx, σyy, σxy).
#[derive(Debug, Clone)]
pub struct PartStress {
    /// Element stresses.
    pub element: Vec<[f64; 3]>,
    /// Area-weighted nodal averages.
    pub nodal: Vec<[f64; 3]>,
}

/// Recovers the stresses of a part (its `mesh` and `material`) from its nodal
/// displacements `u` (2 per node, the part's own numbering).
pub fn recover(mesh: &Mesh, material: &Material, u: &[f64]) -> PartStress {
    let d = material.d_matrix();
    let mut nodal = vec![[0.0; 3]; mesh.nodes.len()];
    let mut weight = vec![0.0; mesh.nodes.len()];
    use rayon::prelude::*;
    // Element values in parallel; only these are kept for every element (a T3's
    // corner values equal its element value, a Q4's are recomputed below), so a
    // million-element part does not hold four corner stresses per element.
    let element: Vec<[f64; 3]> = mesh
        .elements
        .par_iter()
        .map(|el| {
            let x = element::coordinates(mesh, el);
            element::stresses(el, &x, &d, &element::gather(el, u)).element
        })
        .collect();
    for (e, el) in mesh.elements.iter().enumerate() {
        let a = mesh.element_area(e);
        let corners = match el {
            Element::T3(_) => [element[e]; element::MAX_NODES],
            Element::Q4(_) => {
                let x = element::coordinates(mesh, el);
                element::stresses(el, &x, &d, &element::gather(el, u)).corners
            }
        };
        for (&n, c) in el.nodes().iter().zip(&corners) {
            for (v, s) in nodal[n].iter_mut().zip(c) {
                *v += a * s;
            }
            weight[n] += a;
        }
    }
    for (s, w) in nodal.iter_mut().zip(&weight) {
        if *w > 0.0 {
            for v in s.iter_mut() {
                *v /= w;
            }
        }
    }
    PartStress { element, nodal }
}
