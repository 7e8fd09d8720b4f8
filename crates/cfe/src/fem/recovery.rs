//! Stress recovery: element stresses (constant in a T3 or TET4, the Gauss-point
//! mean in a Q4 or HEX8) and nodal stresses averaged (area- or volume-weighted)
//! over the elements around each node from each element's corner values (a Q4's
//! and a HEX8's extrapolated from their Gauss points), within one part only —
//! never across parts, whose meshes are independent.

use super::Material;
use super::element;
use super::{hex8, tet4};
use crate::dim::D3;
use crate::mesh::{Mesh, SolidElement};

/// Elements per block of [`recover`]: large enough for the threads, small enough
/// that the block's corner stresses stay in cache.
const BLOCK: usize = 1 << 13;

/// Stresses of one part: per element and averaged per node, each a stress `S` in
/// its dimension's Voigt order ((σxx, σyy, σxy) in 2D; (xx, yy, zz, xy, yz, zx)
/// in 3D).
#[derive(Debug, Clone)]
pub struct PartStress<S = [f64; 3]> {
    /// Element stresses.
    pub element: Vec<S>,
    /// Area- (2D) or volume-weighted (3D) nodal averages.
    pub nodal: Vec<S>,
    /// The hoop stress σθθ of an axisymmetric part (`None` for a plane part).
    pub hoop: Option<Hoop>,
}

/// The hoop stress σθθ of an axisymmetric part, per element (the mean of its
/// points' values) and per node (area-weighted average of the corner values, as
/// the other components).
#[derive(Debug, Clone)]
pub struct Hoop {
    /// Element values.
    pub element: Vec<f64>,
    /// Nodal averages.
    pub nodal: Vec<f64>,
}

/// A scalar `v` scaled by each of `factors` in turn, as [`scaled_in_turn`].
pub fn scalar_scaled_in_turn(v: f64, factors: &[f64]) -> f64 {
    factors.iter().fold(v, |x, &f| f * x)
}

/// `v` scaled by each of `factors` in turn: bit for bit the value after as many
/// successive [`PartStress::scaled`] calls with those factors (so a writer can
/// scale shared stresses while it reads them instead of holding scaled copies).
pub fn scaled_in_turn<const N: usize>(v: [f64; N], factors: &[f64]) -> [f64; N] {
    v.map(|x| factors.iter().fold(x, |x, &f| f * x))
}

impl<const N: usize> PartStress<[f64; N]> {
    /// The stresses of `factor` × the displacements these were recovered from:
    /// recovery is linear in the displacements (no initial strain), so scaling the
    /// values equals recovering from the scaled displacements to round-off.
    pub fn scaled(&self, factor: f64) -> Self {
        self.scaled_in_turn(&[factor])
    }

    /// These stresses scaled by each of `factors` in turn (`scaled_in_turn`
    /// on every value): bit for bit as many successive [`PartStress::scaled`]
    /// calls.
    pub fn scaled_in_turn(&self, factors: &[f64]) -> Self {
        let scale = |v: &[[f64; N]]| -> Vec<[f64; N]> {
            v.iter().map(|&s| scaled_in_turn(s, factors)).collect()
        };
        let hoop = |v: &[f64]| -> Vec<f64> {
            v.iter().map(|&h| scalar_scaled_in_turn(h, factors)).collect()
        };
        PartStress {
            element: scale(&self.element),
            nodal: scale(&self.nodal),
            hoop: self.hoop.as_ref().map(|h| Hoop {
                element: hoop(&h.element),
                nodal: hoop(&h.nodal),
            }),
        }
    }
}

/// Recovers the stresses of a part (its `mesh` and `material`) from its nodal
/// displacements `u` (2 per node, the part's own numbering).
pub fn recover(mesh: &Mesh, material: &Material, u: &[f64]) -> PartStress {
    if material.is_axisymmetric() {
        return recover_axisymmetric(mesh, material, u);
    }
    use rayon::prelude::*;
    let d = material.d_matrix();
    let mut nodal = vec![[0.0; 3]; mesh.nodes.len()];
    let mut weight = vec![0.0; mesh.nodes.len()];
    let mut element = Vec::with_capacity(mesh.elements.len());
    // Blocks of elements: each element's stresses (its value and its corner
    // values) and area computed once, in parallel, into a small buffer, then
    // added to the nodes in element order (so the sums do not depend on the
    // threads). Only the element values are kept for every element: a
    // million-element part does not hold four corner stresses per element.
    let mut block: Vec<(element::ElementStress, f64)> = Vec::with_capacity(BLOCK);
    for (b, els) in mesh.elements.chunks(BLOCK).enumerate() {
        els.par_iter()
            .enumerate()
            .map(|(i, el)| {
                let x = element::coordinates(mesh, el);
                let s = element::stresses(el, &x, &d, &element::gather(el, u));
                (s, mesh.element_area(b * BLOCK + i))
            })
            .collect_into_vec(&mut block);
        for (el, (s, a)) in els.iter().zip(&block) {
            element.push(s.element);
            let corners = &s.corners;
            for (&n, c) in el.nodes().iter().zip(corners) {
                for (v, s) in nodal[n].iter_mut().zip(c) {
                    *v += a * s;
                }
                weight[n] += a;
            }
        }
    }
    for (s, w) in nodal.iter_mut().zip(&weight) {
        if *w > 0.0 {
            for v in s.iter_mut() {
                *v /= w;
            }
        }
    }
    PartStress {
        element,
        nodal,
        hoop: None,
    }
}

/// Recovers the stresses of a solid part (`mesh`, the 6×6 `d` of its material)
/// from its nodal displacements `u` (3 per node, the part's own numbering):
/// the element values (constant in a TET4, the Gauss-point mean in a HEX8) and
/// the volume-weighted average of the corner values at each node.
pub fn recover_solid(mesh: &Mesh<D3>, d: &[[f64; 6]; 6], u: &[f64]) -> PartStress<[f64; 6]> {
    use rayon::prelude::*;
    let gather = |nodes: &[usize], out: &mut [f64]| {
        for (a, &n) in nodes.iter().enumerate() {
            out[3 * a..3 * a + 3].copy_from_slice(&u[3 * n..3 * n + 3]);
        }
    };
    let all: Vec<([f64; 6], [[f64; 6]; 8], f64)> = mesh
        .elements
        .par_iter()
        .enumerate()
        .map(|(e, el)| {
            let volume = mesh.element_volume(e);
            match el {
                SolidElement::Tet4(n) => {
                    let mut ue = [0.0; 12];
                    gather(n, &mut ue);
                    let s = tet4::stresses(&n.map(|k| mesh.nodes[k]), d, &ue);
                    let mut corners = [[0.0; 6]; 8];
                    corners[..4].copy_from_slice(&s.corners);
                    (s.element, corners, volume)
                }
                SolidElement::Hex8(n) => {
                    let mut ue = [0.0; 24];
                    gather(n, &mut ue);
                    let s = hex8::stresses(&n.map(|k| mesh.nodes[k]), d, &ue);
                    (s.element, s.corners, volume)
                }
            }
        })
        .collect();
    let n = mesh.nodes.len();
    let (mut nodal, mut weight) = (vec![[0.0; 6]; n], vec![0.0; n]);
    for (el, (_, corners, v)) in mesh.elements.iter().zip(&all) {
        for (&node, c) in el.nodes().iter().zip(corners) {
            for (s, c) in nodal[node].iter_mut().zip(c) {
                *s += v * c;
            }
            weight[node] += v;
        }
    }
    for (s, w) in nodal.iter_mut().zip(&weight) {
        if *w > 0.0 {
            for v in s.iter_mut() {
                *v /= w;
            }
        }
    }
    PartStress {
        element: all.iter().map(|(s, _, _)| *s).collect(),
        nodal,
        hoop: None,
    }
}

/// [`recover`] for an axisymmetric part: the same averages, with σθθ.
fn recover_axisymmetric(mesh: &Mesh, material: &Material, u: &[f64]) -> PartStress {
    use rayon::prelude::*;
    let d = material.d_axisymmetric();
    let all: Vec<(super::axisymmetric::AxiStress, f64)> = mesh
        .elements
        .par_iter()
        .enumerate()
        .map(|(e, el)| {
            let x = element::coordinates(mesh, el);
            let s = super::axisymmetric::stresses(el, &x, &d, &element::gather(el, u));
            (s, mesh.element_area(e))
        })
        .collect();
    let n = mesh.nodes.len();
    let (mut nodal, mut nodal_hoop, mut weight) = (vec![[0.0; 3]; n], vec![0.0; n], vec![0.0; n]);
    for (el, (s, a)) in mesh.elements.iter().zip(&all) {
        for (k, &node) in el.nodes().iter().enumerate() {
            for (v, c) in nodal[node].iter_mut().zip(&s.plane.corners[k]) {
                *v += a * c;
            }
            nodal_hoop[node] += a * s.hoop_corners[k];
            weight[node] += a;
        }
    }
    for ((s, h), w) in nodal.iter_mut().zip(&mut nodal_hoop).zip(&weight) {
        if *w > 0.0 {
            for v in s.iter_mut() {
                *v /= w;
            }
            *h /= w;
        }
    }
    PartStress {
        element: all.iter().map(|(s, _)| s.plane.element).collect(),
        nodal,
        hoop: Some(Hoop {
            element: all.iter().map(|(s, _)| s.hoop).collect(),
            nodal: nodal_hoop,
        }),
    }
}
