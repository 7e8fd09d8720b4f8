//! Stress recovery: constant element stresses of the T3 elements and nodal stresses
//! averaged (area-weighted) over the elements around each node, within one part
//! only — never across parts, whose meshes are independent.

use super::t3;
use crate::model::Part;

/// Stresses of one part: per element and averaged per node, (σxx, σyy, σxy).
#[derive(Debug, Clone)]
pub struct PartStress {
    /// Element stresses.
    pub element: Vec<[f64; 3]>,
    /// Area-weighted nodal averages.
    pub nodal: Vec<[f64; 3]>,
}

/// Recovers the stresses of `part` from its nodal displacements `u` (2 per node,
/// the part's own numbering).
pub fn recover(part: &Part, u: &[f64]) -> PartStress {
    let d = part.material.d_matrix();
    let mesh = &part.mesh;
    let mut nodal = vec![[0.0; 3]; mesh.nodes.len()];
    let mut weight = vec![0.0; mesh.nodes.len()];
    use rayon::prelude::*;
    let element: Vec<[f64; 3]> = mesh
        .triangles
        .par_iter()
        .map(|tri| {
            let x = tri.map(|n| mesh.nodes[n]);
            let ue: [f64; 6] = std::array::from_fn(|i| u[2 * tri[i / 2] + i % 2]);
            t3::stress(&x, &d, &ue)
        })
        .collect();
    for (e, tri) in mesh.triangles.iter().enumerate() {
        let a = mesh.triangle_area(e);
        for &n in tri {
            for c in 0..3 {
                nodal[n][c] += a * element[e][c];
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
