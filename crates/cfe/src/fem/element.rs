//! The element provider: the routines of one part element, whatever its type
//! ([`t3`] or [`q4`]), behind one interface so that assembly
//! and stress recovery loop over mixed meshes without knowing the types. Element
//! matrices live in fixed 8×8 arrays (the leading `2n × 2n` block is the element's,
//! n its node count): no allocation per element.

use super::{q4, sum_of, t3};
use crate::mesh::{Element, Mesh};

/// Most nodes a part element has (Q4).
pub const MAX_NODES: usize = 4;
/// Most DOFs a part element has.
pub const MAX_DOFS: usize = 2 * MAX_NODES;

/// An element stiffness matrix; the leading `2n × 2n` block is used.
pub type ElementMatrix = [[f64; MAX_DOFS]; MAX_DOFS];

/// The corner coordinates of `element` in `mesh`, padded with zeros past its nodes.
pub fn coordinates(mesh: &Mesh, element: &Element) -> [[f64; 2]; MAX_NODES] {
    let mut x = [[0.0; 2]; MAX_NODES];
    for (xi, &n) in x.iter_mut().zip(element.nodes()) {
        *xi = mesh.nodes[n];
    }
    x
}

/// The element's displacements gathered from the part's nodal vector `u` (2 per
/// node), padded with zeros.
pub fn gather(element: &Element, u: &[f64]) -> [f64; MAX_DOFS] {
    let mut ue = [0.0; MAX_DOFS];
    for (a, &n) in element.nodes().iter().enumerate() {
        ue[2 * a] = u[2 * n];
        ue[2 * a + 1] = u[2 * n + 1];
    }
    ue
}

/// Element stiffness `K_e = ∫ Bᵀ D B t dA` of a T3 (exact, one point) or a Q4
/// (2×2 Gauss), corners `x`, constitutive matrix `d`, thickness `t`.
pub fn stiffness(
    element: &Element,
    x: &[[f64; 2]; MAX_NODES],
    d: &[[f64; 3]; 3],
    thickness: f64,
) -> ElementMatrix {
    match element {
        Element::T3(_) => {
            let k = t3::stiffness(&[x[0], x[1], x[2]], d, thickness);
            let mut out = [[0.0; MAX_DOFS]; MAX_DOFS];
            for (o, r) in out.iter_mut().zip(&k) {
                o[..6].copy_from_slice(r);
            }
            out
        }
        Element::Q4(_) => q4::stiffness(x, d, thickness),
    }
}

/// The element internal force `K_e u_e` of `element` (corners `x`) for its
/// displacements `u`, computed as `∫ Bᵀ D B u t dA` point by point without forming
/// `K_e` (zero past the element's `2n` DOFs).
pub fn internal_force(
    element: &Element,
    x: &[[f64; 2]; MAX_NODES],
    d: &[[f64; 3]; 3],
    thickness: f64,
    u: &[f64; MAX_DOFS],
) -> [f64; MAX_DOFS] {
    match element {
        Element::T3(_) => {
            let ue: [f64; 6] = std::array::from_fn(|i| u[i]);
            let f = t3::internal_force(&[x[0], x[1], x[2]], d, thickness, &ue);
            std::array::from_fn(|i| if i < 6 { f[i] } else { 0.0 })
        }
        Element::Q4(_) => q4::internal_force(x, d, thickness, u),
    }
}

/// `K_e u_e` over the element's `2n` DOFs (zero past them).
pub fn mul(k: &ElementMatrix, u: &[f64; MAX_DOFS], dofs: usize) -> [f64; MAX_DOFS] {
    let mut f = [0.0; MAX_DOFS];
    for (fi, row) in f.iter_mut().zip(k).take(dofs) {
        *fi = sum_of(dofs, |j| row[j] * u[j]);
    }
    f
}

/// The stresses of one element: a representative element value and the values it
/// gives its corner nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementStress {
    /// The element's stress (σxx, σyy, σxy): constant in a T3; the mean of the four
    /// Gauss-point stresses in a Q4.
    pub element: [f64; 3],
    /// The stress at each corner: the constant value in a T3; in a Q4, the bilinear
    /// field through the Gauss-point stresses extrapolated to the corners.
    pub corners: [[f64; 3]; MAX_NODES],
}

/// The stresses of `element` (corners `x`) for its displacements `u`.
pub fn stresses(
    element: &Element,
    x: &[[f64; 2]; MAX_NODES],
    d: &[[f64; 3]; 3],
    u: &[f64; MAX_DOFS],
) -> ElementStress {
    match element {
        Element::T3(_) => {
            let ue: [f64; 6] = std::array::from_fn(|i| u[i]);
            let s = t3::stress(&[x[0], x[1], x[2]], d, &ue);
            ElementStress {
                element: s,
                corners: [s, s, s, [0.0; 3]],
            }
        }
        Element::Q4(_) => {
            let g = q4::gauss_stresses(x, d, u);
            let mean = std::array::from_fn(|c| 0.25 * sum_of(g.len(), |p| g[p][c]));
            ElementStress {
                element: mean,
                corners: q4::extrapolate_to_nodes(&g),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Material, PlaneKind};
    use crate::mesh::ElementKind;

    /// The internal force computed point by point equals `K_e u_e` with the
    /// element stiffness, for a T3 and a distorted Q4 and an arbitrary `u_e`.
    #[test]
    fn internal_force_is_stiffness_times_displacement() {
        let d = Material::new(210000.0, 0.31, PlaneKind::Strain, 1.0, "p")
            .unwrap()
            .d_matrix();
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let mut mesh = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], kind);
            mesh.nodes[3] = [1.2, 1.1];
            for el in &mesh.elements {
                let x = coordinates(&mesh, el);
                let n = 2 * el.nodes().len();
                let u: [f64; MAX_DOFS] =
                    std::array::from_fn(|i| if i < n { (1.0 + i as f64).sin() } else { 0.0 });
                let k = stiffness(el, &x, &d, 2.5);
                let want = mul(&k, &u, n);
                let got = internal_force(el, &x, &d, 2.5, &u);
                let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..MAX_DOFS {
                    assert!((got[i] - want[i]).abs() <= 1e-13 * scale, "{kind:?} {i}");
                }
            }
        }
    }

    /// A unit square as two T3 and as one Q4: both stiffnesses are symmetric, give
    /// zero force for rigid motions, and reproduce the exact constant stress of a
    /// linear displacement field (element value and every corner).
    #[test]
    fn both_kinds_pass_the_patch_test() {
        let d = Material::new(1000.0, 0.3, PlaneKind::Stress, 1.0, "p")
            .unwrap()
            .d_matrix();
        let (a, b, c) = (1e-3, -2e-3, 0.5e-3);
        let exact: [f64; 3] = std::array::from_fn(|i| d[i][0] * a + d[i][1] * b + d[i][2] * c);
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let mut mesh = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], kind);
            mesh.nodes[3] = [1.2, 1.1];
            for el in &mesh.elements {
                let x = coordinates(&mesh, el);
                let n = el.nodes().len();
                let k = stiffness(el, &x, &d, 1.0);
                for i in 0..2 * n {
                    for j in 0..2 * n {
                        assert!((k[i][j] - k[j][i]).abs() < 1e-12 * k[0][0].abs());
                    }
                }
                let rot: [f64; MAX_DOFS] = std::array::from_fn(|i| {
                    if i >= 2 * n {
                        0.0
                    } else if i % 2 == 0 {
                        -x[i / 2][1]
                    } else {
                        x[i / 2][0]
                    }
                });
                assert!(mul(&k, &rot, 2 * n).iter().all(|f| f.abs() < 1e-9));
                let u: Vec<f64> = mesh
                    .nodes
                    .iter()
                    .flat_map(|p| [a * p[0] + c * p[1], b * p[1]])
                    .collect();
                let s = stresses(el, &x, &d, &gather(el, &u));
                for v in std::iter::once(&s.element).chain(&s.corners[..n]) {
                    for i in 0..3 {
                        assert!((v[i] - exact[i]).abs() < 1e-12, "{kind:?}: {v:?}");
                    }
                }
            }
        }
    }
}
