//! Axisymmetric elements (`plane = "axisymmetric"`): the T3 and Q4 of a part
//! meshed in the r–z half-plane (x = r ≥ 0, y = z), each standing for the solid
//! of revolution it sweeps about the z axis, with torsionless axisymmetric
//! displacements (u_r, u_z).
//!
//! Strains (εrr, εzz, γrz, εθθ) = B u_e with the hoop row u_r / r:
//!
//! `B_a = [[N_a,r, 0], [0, N_a,z], [N_a,z, N_a,r], [N_a / r, 0]]` (node a's columns),
//!
//! the isotropic D (4×4, [`super::Material::d_axisymmetric`]) and every integral over the ring,
//! `K_e = ∫ Bᵀ D B 2πr dA`. The element integrals are sampled at points inside
//! the element, never on the axis: the Q4's 2×2 Gauss points, the T3's three
//! interior points (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) (a rule exact for
//! quadratics; the centroid alone would leave the hoop strain's modes of a T3
//! under-integrated). So a node on the axis (r = 0) gives a finite stiffness; the
//! hoop term N_a u_r,a / r at the points next to it makes u_r there stiff, which
//! drives u_r → 0 on the axis as symmetry requires (it is not imposed: a support
//! u_r = 0 on the axis imposes it exactly).
//!
//! Element stresses are (σrr, σzz, σrz) as in the plane elements plus σθθ
//! (returned apart, [`AxiStress`], so the plane elements' outputs are unchanged):
//! the Q4's Gauss values are extrapolated to its corners as in [`q4`], the T3's
//! three point values through the linear field they define.

use super::element::{ElementMatrix, ElementStress, MAX_DOFS, MAX_NODES};
use super::{q4, sum_of};
use crate::error::{Error, Result};
use crate::mesh::Element;
use std::f64::consts::PI;

/// One integration point of an axisymmetric element: B (4 × 2n, padded), the
/// radius r there and the weight `w det J` of the point over the element's area
/// (so `Σ weight = area`).
#[derive(Debug, Clone, Copy)]
pub struct Point {
    /// Strain–displacement rows (εrr, εzz, γrz, εθθ).
    pub b: [[f64; MAX_DOFS]; 4],
    /// The radius of the point.
    pub r: f64,
    /// The point's share of the element's area.
    pub weight: f64,
}

/// The T3's interior points in area coordinates (L₂, L₃), weights 1/3 of the area
/// each: exact for quadratics, none on an edge.
const T3_POINTS: [[f64; 2]; 3] = [[1.0 / 6.0, 1.0 / 6.0], [2.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 2.0 / 3.0]];

/// B at a point of shape values `n` and derivatives `dn` (∂/∂r, ∂/∂z per node).
fn b_rows(n: &[f64], dn: &[[f64; 2]], r: f64) -> [[f64; MAX_DOFS]; 4] {
    let mut b = [[0.0; MAX_DOFS]; 4];
    for a in 0..n.len() {
        let [dr, dz] = dn[a];
        b[0][2 * a] = dr;
        b[1][2 * a + 1] = dz;
        b[2][2 * a] = dz;
        b[2][2 * a + 1] = dr;
        b[3][2 * a] = n[a] / r;
    }
    b
}

/// The integration points of `element` with corners `x` (T3: three interior
/// points; Q4: 2×2 Gauss, in [`q4::GAUSS`]'s order).
pub fn points(element: &Element, x: &[[f64; 2]; MAX_NODES]) -> Vec<Point> {
    match element {
        Element::T3(_) => {
            let (bt, area) = super::t3::b_matrix(&[x[0], x[1], x[2]]);
            // Shape derivatives from the plane B: row 0 holds N_a,r, row 1 N_a,z.
            let dn: [[f64; 2]; 3] = std::array::from_fn(|a| [bt[0][2 * a], bt[1][2 * a + 1]]);
            T3_POINTS
                .iter()
                .map(|&[l2, l3]| {
                    let n = [1.0 - l2 - l3, l2, l3];
                    let r = sum_of(3, |a| n[a] * x[a][0]);
                    Point {
                        b: b_rows(&n, &dn, r),
                        r,
                        weight: area / 3.0,
                    }
                })
                .collect()
        }
        Element::Q4(_) => {
            let x4 = [x[0], x[1], x[2], x[3]];
            q4::GAUSS
                .iter()
                .map(|&g| {
                    let n = q4::shape(g);
                    let (bp, det) = q4::b_matrix(&x4, g);
                    let dn: [[f64; 2]; 4] = std::array::from_fn(|a| [bp[0][2 * a], bp[1][2 * a + 1]]);
                    let r = sum_of(4, |a| n[a] * x[a][0]);
                    Point {
                        b: b_rows(&n, &dn, r),
                        r,
                        weight: det,
                    }
                })
                .collect()
        }
    }
}

/// Element stiffness `K_e = Σ_p B_pᵀ D B_p 2π r_p w_p` (symmetric; the leading
/// 2n × 2n block).
pub fn stiffness(element: &Element, x: &[[f64; 2]; MAX_NODES], d: &[[f64; 4]; 4]) -> ElementMatrix {
    let m = 2 * element.nodes().len();
    let mut k = [[0.0; MAX_DOFS]; MAX_DOFS];
    for p in points(element, x) {
        let w = 2.0 * PI * p.r * p.weight;
        let db: [[f64; MAX_DOFS]; 4] =
            std::array::from_fn(|i| std::array::from_fn(|j| sum_of(4, |l| d[i][l] * p.b[l][j])));
        for (i, row) in k.iter_mut().enumerate().take(m) {
            for (j, kij) in row.iter_mut().enumerate().take(m).skip(i) {
                *kij += w * sum_of(4, |l| p.b[l][i] * db[l][j]);
            }
        }
    }
    std::array::from_fn(|i| std::array::from_fn(|j| if i < m && j < i { k[j][i] } else { k[i][j] }))
}

/// The stresses (rr, zz, rz, θθ) at one point of `element` (corners `x`, its
/// displacements `u`): the T3's at area coordinates given by its shape values
/// `shape` (the first three), the Q4's at natural coordinates `xi`. σ = D B u
/// with the hoop strain Σ N_a u_r,a / r; on the axis (r within 1e-12 of the
/// element's largest radius of 0), where u_r / r → ∂u_r/∂r, εθθ = εrr.
pub fn stress_at(
    element: &Element,
    x: &[[f64; 2]; MAX_NODES],
    d: &[[f64; 4]; 4],
    u: &[f64; MAX_DOFS],
    shape: &[f64],
    xi: [f64; 2],
) -> [f64; 4] {
    let (n, dn): (Vec<f64>, Vec<[f64; 2]>) = match element {
        Element::T3(_) => {
            let (bt, _) = super::t3::b_matrix(&[x[0], x[1], x[2]]);
            (shape[..3].to_vec(), (0..3).map(|a| [bt[0][2 * a], bt[1][2 * a + 1]]).collect())
        }
        Element::Q4(_) => {
            let (bp, _) = q4::b_matrix(&[x[0], x[1], x[2], x[3]], xi);
            (q4::shape(xi).to_vec(), (0..4).map(|a| [bp[0][2 * a], bp[1][2 * a + 1]]).collect())
        }
    };
    let r: f64 = n.iter().zip(x).map(|(na, xa)| na * xa[0]).sum();
    let size = x[..n.len()].iter().map(|xa| xa[0]).fold(0.0, f64::max);
    let m = 2 * n.len();
    let b = b_rows(&n, &dn, r.max(f64::MIN_POSITIVE));
    let mut eps: [f64; 4] = std::array::from_fn(|i| (0..m).map(|j| b[i][j] * u[j]).sum());
    if r <= 1e-12 * size {
        eps[3] = eps[0];
    }
    std::array::from_fn(|i| (0..4).map(|j| d[i][j] * eps[j]).sum())
}

/// The strains and stresses (rr, zz, rz, θθ) at each point.
fn point_stresses(element: &Element, x: &[[f64; 2]; MAX_NODES], d: &[[f64; 4]; 4], u: &[f64; MAX_DOFS]) -> Vec<(Point, [f64; 4])> {
    let m = 2 * element.nodes().len();
    points(element, x)
        .into_iter()
        .map(|p| {
            let eps: [f64; 4] = std::array::from_fn(|i| sum_of(m, |j| p.b[i][j] * u[j]));
            let s = std::array::from_fn(|i| sum_of(4, |j| d[i][j] * eps[j]));
            (p, s)
        })
        .collect()
}

/// The element internal force `Σ_p B_pᵀ σ_p 2π r_p w_p` (= `K_e u_e`; zero past
/// the element's DOFs).
pub fn internal_force(element: &Element, x: &[[f64; 2]; MAX_NODES], d: &[[f64; 4]; 4], u: &[f64; MAX_DOFS]) -> [f64; MAX_DOFS] {
    let m = 2 * element.nodes().len();
    let mut f = [0.0; MAX_DOFS];
    for (p, s) in point_stresses(element, x, d, u) {
        let w = 2.0 * PI * p.r * p.weight;
        for (j, fj) in f.iter_mut().enumerate().take(m) {
            *fj += w * sum_of(4, |i| p.b[i][j] * s[i]);
        }
    }
    f
}

/// The stresses of one axisymmetric element: (σrr, σzz, σrz) as the plane
/// elements give them, and σθθ alongside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxiStress {
    /// (σrr, σzz, σrz): the mean of the point values, and the corner values.
    pub plane: ElementStress,
    /// σθθ: the mean of the point values.
    pub hoop: f64,
    /// σθθ at the corners.
    pub hoop_corners: [f64; MAX_NODES],
}

/// The stresses of `element` for its displacements `u`: the point values'
/// mean, and corner values extrapolated from the points (Q4: the bilinear field
/// through the Gauss values; T3: the linear field through its three points,
/// `σ_a = Σ_p c_ap σ_p` with `c = 5/3` for the point nearest corner a, −1/3 for
/// the others).
pub fn stresses(element: &Element, x: &[[f64; 2]; MAX_NODES], d: &[[f64; 4]; 4], u: &[f64; MAX_DOFS]) -> AxiStress {
    let ps = point_stresses(element, x, d, u);
    let np = ps.len() as f64;
    let mean: [f64; 4] = std::array::from_fn(|c| sum_of(ps.len(), |p| ps[p].1[c]) / np);
    let mut corners = [[0.0; 3]; MAX_NODES];
    let mut hoop_corners = [0.0; MAX_NODES];
    match element {
        Element::T3(_) => {
            // Point p sits at area coordinates with 2/3 on corner p (p = 0: corner 0
            // has L₁ = 2/3). A linear field through the three point values:
            // σ(corner a) = 5/3 σ_a − 1/3 (σ_b + σ_c).
            let at = |a: usize, c: usize| {
                sum_of(3, |p| if p == a { 5.0 / 3.0 } else { -1.0 / 3.0 } * ps[p].1[c])
            };
            for a in 0..3 {
                corners[a] = std::array::from_fn(|c| at(a, c));
                hoop_corners[a] = at(a, 3);
            }
        }
        Element::Q4(_) => {
            let g: [[f64; 3]; 4] = std::array::from_fn(|p| [ps[p].1[0], ps[p].1[1], ps[p].1[2]]);
            corners = q4::extrapolate_to_nodes(&g);
            let h: [[f64; 3]; 4] = std::array::from_fn(|p| [ps[p].1[3], 0.0, 0.0]);
            let hc = q4::extrapolate_to_nodes(&h);
            hoop_corners = std::array::from_fn(|a| hc[a][0]);
        }
    }
    AxiStress {
        plane: ElementStress {
            element: [mean[0], mean[1], mean[2]],
            corners,
        },
        hoop: mean[3],
        hoop_corners,
    }
}

/// The ring area `2π ∫ N_a r ds` of each end of the straight edge a–b (the
/// weights with which a traction per unit area, constant along the edge, loads
/// its two nodes): `2π L (2 r_a + r_b) / 6` and `2π L (r_a + 2 r_b) / 6`.
pub fn edge_ring_weights(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
    let k = 2.0 * PI * l / 6.0;
    [k * (2.0 * a[0] + b[0]), k * (a[0] + 2.0 * b[0])]
}

/// Checks that the nodes of axisymmetric part `part` lie at r = x ≥ 0: a node at
/// r < 0 is an [`Error::NegativeRadius`] naming it, unless it lies within round-off
/// of the axis (r ≥ −1e-12 × the part's largest |x|), when it is put on it (r = 0).
pub fn check_radii(nodes: &mut [[f64; 2]], part: &str) -> Result<()> {
    let scale = nodes.iter().fold(0.0f64, |m, x| m.max(x[0].abs()));
    for (node, x) in nodes.iter_mut().enumerate() {
        if x[0] < 0.0 || x[0].is_nan() {
            if x[0] >= -1e-12 * scale {
                x[0] = 0.0;
            } else {
                return Err(Error::NegativeRadius {
                    part: part.to_string(),
                    node,
                    r: x[0],
                });
            }
        }
    }
    Ok(())
}

/// The ring 2π r̄ of each of `nodes` (a face of `mesh`, an interface's coupling
/// nodes), r̄ the mean radius of the node's share of the face:
/// `r̄_a = ∫ N_a r ds / ∫ N_a ds` over the boundary edges at a whose both ends are
/// among `nodes` (an edge a–b adds `L (2 r_a + r_b) / 6` and `L / 2`); a node with
/// no such edge takes its own radius. On the axis r̄ > 0 (a third of the edge's
/// length), so a pair there still couples.
pub fn face_rings(mesh: &crate::mesh::Mesh, nodes: &[usize]) -> std::collections::HashMap<usize, f64> {
    let set: std::collections::HashSet<usize> = nodes.iter().copied().collect();
    let mut sums: std::collections::HashMap<usize, [f64; 2]> = nodes.iter().map(|&n| (n, [0.0; 2])).collect();
    for e in mesh.boundary_edges() {
        let [a, b] = e.nodes;
        if set.contains(&a) && set.contains(&b) {
            let w = edge_ring_weights(mesh.nodes[a], mesh.nodes[b]);
            let half = 0.5 * crate::mesh::dist(mesh.nodes[a], mesh.nodes[b]);
            for (n, wn) in [(a, w[0]), (b, w[1])] {
                let s = sums.entry(n).or_default();
                s[0] += wn;
                s[1] += half;
            }
        }
    }
    sums.into_iter()
        .map(|(n, [w, l])| (n, if l > 0.0 { w / l } else { 2.0 * PI * mesh.nodes[n][0] }))
        .collect()
}

/// Nodal forces (totals over the ring) of a uniform pressure `p` (per unit area,
/// positive pushing into the part) over `edges`, counter-clockwise with respect
/// to the part: the traction −p n integrated with 2πr exactly over each straight
/// edge, `f_a = −p n L · 2π (2 r_a + r_b) / 6` ([`edge_ring_weights`]).
pub fn pressure_forces(edges: &[([usize; 2], [[f64; 2]; 2])], p: f64) -> Vec<(usize, [f64; 2])> {
    edges
        .iter()
        .flat_map(|&(nodes, [a, b])| {
            let l = (b[0] - a[0]).hypot(b[1] - a[1]);
            let w = edge_ring_weights(a, b);
            // −p n with n L = (y_b − y_a, −(x_b − x_a)).
            let t = [-p * (b[1] - a[1]) / l, p * (b[0] - a[0]) / l];
            [(nodes[0], t.map(|v| v * w[0])), (nodes[1], t.map(|v| v * w[1]))]
        })
        .collect()
}

/// Nodal forces of a resultant `force` (a total over the ring) spread as a
/// uniform traction per unit area over the whole chain of `edges`: each node takes
/// the share of the chain's lateral area its [`edge_ring_weights`] give it. A
/// chain on the axis alone (no area) spreads the force by length instead.
pub fn chain_forces(edges: &[([usize; 2], [[f64; 2]; 2])], force: [f64; 2]) -> Vec<(usize, [f64; 2])> {
    let total: f64 = edges.iter().map(|e| edge_ring_weights(e.1[0], e.1[1]).iter().sum::<f64>()).sum();
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return super::loads::chain_forces(edges, force);
    }
    edges
        .iter()
        .flat_map(|&(nodes, [a, b])| {
            let w = edge_ring_weights(a, b).map(|w| w / total);
            [(nodes[0], force.map(|f| f * w[0])), (nodes[1], force.map(|f| f * w[1]))]
        })
        .collect()
}

/// Nodal forces of a resultant `force` (a total over the ring) spread as a
/// uniform traction per unit area over the part of `edges` on the straight
/// segment `from`–`to` (an edge counts when both ends lie on the segment's line
/// within `tol`): `q = force / A`, A = π (r_from + r_to) |to − from| the
/// segment's lateral area, `f_a = q 2π ∫ N_a r dt` over each edge's overlap with
/// the segment (2-point Gauss, exact for the quadratic integrand). Returns the
/// nodal forces and the length of the segment covered by edges; a segment with no
/// lateral area (on the axis) gives no forces and covers nothing.
pub fn segment_forces(
    edges: &[([usize; 2], [[f64; 2]; 2])],
    from: [f64; 2],
    to: [f64; 2],
    force: [f64; 2],
    tol: f64,
) -> (Vec<(usize, [f64; 2])>, f64) {
    let length = (to[0] - from[0]).hypot(to[1] - from[1]);
    let area = PI * (from[0] + to[0]) * length;
    if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return (Vec::new(), 0.0);
    }
    let dir = [(to[0] - from[0]) / length, (to[1] - from[1]) / length];
    let q = force.map(|f| f / area);
    let along = |p: [f64; 2]| (p[0] - from[0]) * dir[0] + (p[1] - from[1]) * dir[1];
    let off = |p: [f64; 2]| ((p[0] - from[0]) * dir[1] - (p[1] - from[1]) * dir[0]).abs();
    let r_at = |t: f64| from[0] + t * dir[0];
    let mut out = Vec::new();
    let mut covered = 0.0;
    for &(nodes, [a, b]) in edges {
        if off(a) > tol || off(b) > tol {
            continue;
        }
        let (ta, tb) = (along(a), along(b));
        if (tb - ta).abs() <= tol {
            continue;
        }
        let (t0, t1) = (ta.min(tb).max(0.0), ta.max(tb).min(length));
        if t1 - t0 <= 0.0 {
            continue;
        }
        covered += t1 - t0;
        let (mut ia, mut ib) = (0.0, 0.0);
        for g in [-1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()] {
            let t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * g;
            let xi = (t - ta) / (tb - ta);
            let w = 0.5 * (t1 - t0) * 2.0 * PI * r_at(t);
            ia += w * (1.0 - xi);
            ib += w * xi;
        }
        out.push((nodes[0], q.map(|v| v * ia)));
        out.push((nodes[1], q.map(|v| v * ib)));
    }
    (out, covered)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Material, PlaneKind};
    use crate::mesh::{ElementKind, Mesh};

    fn axi(e: f64, nu: f64) -> [[f64; 4]; 4] {
        Material::new(e, nu, PlaneKind::Axisymmetric, 1.0, "p")
            .unwrap()
            .d_axisymmetric()
    }

    /// A ring of unit square cross-section at 1 ≤ r ≤ 2 as Q4 and as T3 (with a
    /// node moved): a rigid translation along z stores no energy; the uniform
    /// expansion u = (a r, b z) gives exactly εrr = εθθ = a, εzz = b at every point
    /// and corner; and the sum of the nodal forces in z of any displacement is 0
    /// (the ring's z equilibrium), while a uniform radial translation (not a
    /// rigid motion of a ring) is resisted.
    #[test]
    fn ring_patch_test() {
        let d = axi(1000.0, 0.3);
        let (a, b) = (1e-3, -4e-4);
        let exact: [f64; 4] = std::array::from_fn(|i| d[i][0] * a + d[i][1] * b + d[i][3] * a);
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let mut mesh = Mesh::rectangle([1.0, 2.0], [0.0, 1.0], [2, 2], kind);
            mesh.nodes[4] = [1.6, 0.45];
            for el in &mesh.elements {
                let x = super::super::element::coordinates(&mesh, el);
                let m = 2 * el.nodes().len();
                let k = stiffness(el, &x, &d);
                for i in 0..m {
                    for j in 0..m {
                        assert!((k[i][j] - k[j][i]).abs() <= 1e-12 * k[0][0].abs());
                    }
                }
                let tz: [f64; MAX_DOFS] = std::array::from_fn(|i| if i < m && i % 2 == 1 { 1.0 } else { 0.0 });
                let f = super::super::element::mul(&k, &tz, m);
                assert!(f.iter().all(|v| v.abs() < 1e-9 * k[0][0]), "{kind:?}: {f:?}");
                let tr: [f64; MAX_DOFS] = std::array::from_fn(|i| if i < m && i % 2 == 0 { 1.0 } else { 0.0 });
                let f = super::super::element::mul(&k, &tr, m);
                assert!(f.iter().step_by(2).take(m / 2).any(|v| v.abs() > 1e-3 * k[0][0]));
                let u: Vec<f64> = mesh.nodes.iter().flat_map(|p| [a * p[0], b * p[1]]).collect();
                let ue = super::super::element::gather(el, &u);
                let s = stresses(el, &x, &d, &ue);
                let n = el.nodes().len();
                for (v, h) in std::iter::once((&s.plane.element, s.hoop)).chain(s.plane.corners[..n].iter().zip(s.hoop_corners)) {
                    for i in 0..3 {
                        assert!((v[i] - exact[i]).abs() < 1e-12, "{kind:?}: {v:?}");
                    }
                    assert!((h - exact[3]).abs() < 1e-12, "{kind:?}: {h}");
                }
                let fz: f64 = internal_force(el, &x, &d, &ue).iter().skip(1).step_by(2).sum();
                assert!(fz.abs() < 1e-12, "{kind:?}: {fz}");
            }
        }
    }

    /// The internal force point by point equals `K_e u_e`, and an element with a
    /// corner on the axis has a finite stiffness (its points lie off the axis).
    #[test]
    fn internal_force_is_stiffness_times_displacement_even_on_the_axis() {
        let d = axi(210000.0, 0.3);
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let mesh = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [1, 1], kind);
            for el in &mesh.elements {
                let x = super::super::element::coordinates(&mesh, el);
                let m = 2 * el.nodes().len();
                let u: [f64; MAX_DOFS] = std::array::from_fn(|i| if i < m { (1.0 + i as f64).sin() } else { 0.0 });
                let k = stiffness(el, &x, &d);
                assert!(k.iter().flatten().all(|v| v.is_finite()));
                let want = super::super::element::mul(&k, &u, m);
                let got = internal_force(el, &x, &d, &u);
                let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..MAX_DOFS {
                    assert!((got[i] - want[i]).abs() <= 1e-12 * scale, "{kind:?} {i}");
                }
            }
        }
    }

    /// A pressure p on the outer face r = R, 0 ≤ z ≤ H of a ring meshed in
    /// three edges gives the total radial force p 2πR H, and on its top face
    /// r ∈ [1, 2] the total axial force p π (2² − 1²); the same axial total spread
    /// as a segment load and as a chain load gives the same nodal forces.
    #[test]
    fn ring_loads_integrate_2_pi_r() {
        let side: Vec<_> = (0..3)
            .map(|i| ([i, i + 1], [[2.0, i as f64], [2.0, i as f64 + 1.0]]))
            .collect();
        let f = pressure_forces(&side, 5.0);
        let fr: f64 = f.iter().map(|v| v.1[0]).sum();
        assert!((fr + 5.0 * 2.0 * PI * 2.0 * 3.0).abs() < 1e-12, "{fr}");
        let top: Vec<_> = (0..4)
            .map(|i| {
                let (a, b) = (2.0 - 0.25 * i as f64, 1.75 - 0.25 * i as f64);
                ([i, i + 1], [[a, 1.0], [b, 1.0]])
            })
            .collect();
        let f = pressure_forces(&top, 5.0);
        let fz: f64 = f.iter().map(|v| v.1[1]).sum();
        assert!((fz + 5.0 * PI * 3.0).abs() < 1e-12, "{fz}");
        let total = [0.0, -5.0 * PI * 3.0];
        let (s, covered) = segment_forces(&top, [1.0, 1.0], [2.0, 1.0], total, 1e-9);
        assert!((covered - 1.0).abs() < 1e-14);
        let c = chain_forces(&top, total);
        let mut by_node = [[0.0; 3]; 5];
        for (n, v) in &f {
            by_node[*n][0] += v[1];
        }
        for (n, v) in &s {
            by_node[*n][1] += v[1];
        }
        for (n, v) in &c {
            by_node[*n][2] += v[1];
        }
        for v in by_node {
            assert!((v[0] - v[1]).abs() < 1e-12 && (v[0] - v[2]).abs() < 1e-12, "{v:?}");
        }
    }

    /// The ring weights of an edge sum to its lateral area 2π r̄ L, and on an
    /// edge from the axis the outer node takes twice the inner node's share.
    #[test]
    fn edge_ring_weights_sum_to_the_lateral_area() {
        let w = edge_ring_weights([1.0, 0.0], [3.0, 0.0]);
        assert!((w[0] + w[1] - 2.0 * PI * 2.0 * 2.0).abs() < 1e-12);
        let w = edge_ring_weights([0.0, 0.0], [1.0, 0.0]);
        assert!((w[1] - 2.0 * w[0]).abs() < 1e-15 && (w[0] + w[1] - PI).abs() < 1e-15);
    }
}
