//! The 8-node trilinear hexahedron HEX8 (isoparametric, full 2×2×2 Gauss
//! integration) for 3D elasticity: shape functions, Jacobian and volume,
//! strain–displacement matrix, stiffness, internal force, stresses at any point and
//! at the Gauss points with their extrapolation to the corners, and the inverse map.
//!
//! Local numbering as Gmsh's 8-node hexahedron and VTK_HEXAHEDRON: the bottom face
//! 0-1-2-3 counter-clockwise seen from above (from +ζ), the top 4-5-6-7 above it
//! (4 above 0, …, 7 above 3). Natural corners (ξ_i, η_i, ζ_i):
//! 0 (−1,−1,−1), 1 (1,−1,−1), 2 (1,1,−1), 3 (−1,1,−1), 4 (−1,−1,1), 5 (1,−1,1),
//! 6 (1,1,1), 7 (−1,1,1).
//!
//! ```text
//!            7 ─────────── 6
//!           ╱│            ╱│
//!          ╱ │           ╱ │            ζ
//!         4 ─────────── 5  │            │  η
//!         │  │          │  │            │ ╱
//!         │  3 ─────────│─ 2            │╱
//!         │ ╱           │ ╱             ○──── ξ
//!         │╱            │╱
//!         0 ─────────── 1
//! ```
//!
//! Outward faces (right-hand rule): 0-3-2-1 (ζ = −1), 4-5-6-7 (ζ = 1), 0-1-5-4
//! (η = −1), 1-2-6-5 (ξ = 1), 2-3-7-6 (η = 1), 3-0-4-7 (ξ = −1).
//!
//! - Shape functions `N_i = ⅛ (1 + ξ ξ_i)(1 + η η_i)(1 + ζ ζ_i)`; `x = Σ N_i x_i`,
//!   `u = Σ N_i u_i`.
//! - Jacobian `J_ab = Σ_i ∂N_i/∂ξ_a x_ib`, `∇N_i = J⁻¹ ∂N_i/∂ξ`; B (6×24) from the
//!   gradients in the Voigt order `[xx, yy, zz, xy, yz, zx]` ([`super::solid`]).
//!   det J is of degree ≤ 2 in each natural coordinate, so `V = Σ_g det J_g` over the
//!   2×2×2 Gauss points is exact.
//! - Stiffness `K_e = Σ_g B_gᵀ D B_g det J_g` over the 2×2×2 Gauss points
//!   `(±1/√3, ±1/√3, ±1/√3)`, weights 1 (full integration: the six rigid modes are
//!   the only zero-energy modes).
//! - Stress `σ = D B u_e` at any natural point; at the Gauss points; their mean is the
//!   element value, and the trilinear field through the eight Gauss values gives the
//!   corners: in `r = √3 ξ` the Gauss points are the corners (±1, ±1, ±1), so
//!   `σ_i = Σ_g N_g(√3 ξ_i) σ_g`.
//! - Inverse map: Newton's method on `x(ξ) = p` from the centre, `Jᵀ δ = −(x(ξ) − p)`.
//!
//! Element DOFs are ordered `[u₀, v₀, w₀, u₁, v₁, w₁, …]`.
//!
//! ```
//! use cfe::fem::{hex8, material::d_solid};
//! // The unit cube: K(u₀, u₀) = ∫ (λ + 2G) N₀,x² + G (N₀,y² + N₀,z²) dV = (λ + 4G)/9
//! // and K(u₀, v₀) = (λ + G) ∫ N₀,x N₀,y dV = (λ + G)/12.
//! let x = hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
//! let (e, nu) = (210000.0, 0.3);
//! let k = hex8::stiffness(&x, &d_solid(e, nu));
//! let (lambda, g) = (e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)));
//! assert!((k[0][0] - (lambda + 4.0 * g) / 9.0).abs() < 1e-9);
//! assert!((k[0][1] - (lambda + g) / 12.0).abs() < 1e-9);
//! assert!((hex8::check(&x).unwrap() - 1.0).abs() < 1e-15);
//! ```

use super::solid::{self, NonPositiveJacobian, SolidStress};

/// 1/√3, the 2-point Gauss–Legendre abscissa.
const G: f64 = 0.577_350_269_189_625_8;

/// √3, the factor from Gauss-point coordinates back to natural coordinates.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// Natural coordinates (ξ_i, η_i, ζ_i) of the corners, in the Gmsh/VTK order.
pub const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// 2×2×2 Gauss points `(±1/√3, ±1/√3, ±1/√3)`, point k nearest corner k; weights all 1.
pub const GAUSS: [[f64; 3]; 8] = {
    let mut g = [[0.0; 3]; 8];
    let mut k = 0;
    while k < 8 {
        g[k] = [G * CORNERS[k][0], G * CORNERS[k][1], G * CORNERS[k][2]];
        k += 1;
    }
    g
};

/// Newton iterations of [`natural_coordinates`] at most.
pub const INVERSE_MAP_ITERATIONS: usize = 50;

/// Residual tolerance of [`natural_coordinates`], relative to the element's longest
/// body diagonal.
pub const INVERSE_MAP_TOLERANCE: f64 = 1e-13;

/// Shape functions `N_i = ⅛ (1 + ξ ξ_i)(1 + η η_i)(1 + ζ ζ_i)` at `xi`.
pub fn shape(xi: [f64; 3]) -> [f64; 8] {
    std::array::from_fn(|i| {
        let c = CORNERS[i];
        0.125 * (1.0 + xi[0] * c[0]) * (1.0 + xi[1] * c[1]) * (1.0 + xi[2] * c[2])
    })
}

/// Natural derivatives `dn[a][i] = ∂N_i/∂ξ_a` at `xi`, e.g.
/// `∂N_i/∂ξ = ⅛ ξ_i (1 + η η_i)(1 + ζ ζ_i)`.
pub fn shape_derivatives(xi: [f64; 3]) -> [[f64; 8]; 3] {
    std::array::from_fn(|a| {
        std::array::from_fn(|i| {
            let c = CORNERS[i];
            let f = |b: usize| if b == a { c[b] } else { 1.0 + xi[b] * c[b] };
            0.125 * f(0) * f(1) * f(2)
        })
    })
}

/// Jacobian `J_ab = ∂x_b/∂ξ_a = Σ_i ∂N_i/∂ξ_a x_ib` at `xi`.
pub fn jacobian(x: &[[f64; 3]; 8], xi: [f64; 3]) -> [[f64; 3]; 3] {
    solid::jacobian(x, &shape_derivatives(xi))
}

/// The physical point `x(ξ) = Σ N_i(ξ) x_i`.
pub fn point(x: &[[f64; 3]; 8], xi: [f64; 3]) -> [f64; 3] {
    let n = shape(xi);
    std::array::from_fn(|c| (0..8).map(|i| n[i] * x[i][c]).sum())
}

/// Strain–displacement matrix B (6×24) at `xi` and det J there. Non-finite entries
/// if det J = 0 ([`check`] first).
pub fn b_matrix(x: &[[f64; 3]; 8], xi: [f64; 3]) -> ([[f64; 24]; 6], f64) {
    let (g, det) = solid::gradients(&jacobian(x, xi), &shape_derivatives(xi));
    (solid::b_matrix(&g), det)
}

/// Signed volume `∫ det J dξ dη dζ = Σ_g det J_g` (2×2×2 Gauss, exact).
pub fn volume(x: &[[f64; 3]; 8]) -> f64 {
    GAUSS.iter().map(|&g| solid::det3(&jacobian(x, g))).sum()
}

/// The volume if det J is positive beyond round-off (> [`solid::FLAT`] × d³, d the
/// longest body diagonal) at the 8 corners, the 8 Gauss points and the centre;
/// otherwise the first point where it is not (corners first), as a value for the
/// mesh validation to name the element. Positive corner values are what the
/// stiffness needs in practice (it samples the Gauss points, checked too); a
/// trilinear det J can still dip below zero between points of a badly warped
/// element, which no finite set of samples excludes.
pub fn check(x: &[[f64; 3]; 8]) -> Result<f64, NonPositiveJacobian> {
    let size = diagonal(x);
    for at in CORNERS.iter().chain(&GAUSS).chain(&[[0.0; 3]]) {
        let det = solid::det3(&jacobian(x, *at));
        if !solid::is_positive(det, size) {
            return Err(NonPositiveJacobian { at: *at, det });
        }
    }
    Ok(volume(x))
}

/// Shape quality: `min_i det J(corner i) / (V / 8)`: 1 for a parallelepiped, in
/// (0, 1) for a distorted element, ≤ 0 for an inverted or degenerate corner (0 when
/// the volume vanishes or is not finite).
pub fn min_corner_jacobian_ratio(x: &[[f64; 3]; 8]) -> f64 {
    let eighth = volume(x).abs() / 8.0;
    if !(eighth.is_finite() && eighth > 0.0) {
        return 0.0;
    }
    CORNERS
        .iter()
        .map(|&c| solid::det3(&jacobian(x, c)) / eighth)
        .fold(f64::INFINITY, f64::min)
}

/// Element stiffness `K_e = Σ_g B_gᵀ D B_g det J_g` (2×2×2 Gauss, weights 1); the
/// upper triangle is accumulated and mirrored, so K_e is exactly symmetric.
pub fn stiffness(x: &[[f64; 3]; 8], d: &[[f64; 6]; 6]) -> [[f64; 24]; 24] {
    let mut k = [[0.0; 24]; 24];
    for xi in GAUSS {
        let (b, det) = b_matrix(x, xi);
        solid::add_btdb(&mut k, &b, d, det);
    }
    solid::mirror(&k)
}

/// Element internal force `K_e u_e = Σ_g det J_g B_gᵀ (D (B_g u_e))`, without forming
/// `K_e`.
pub fn internal_force(x: &[[f64; 3]; 8], d: &[[f64; 6]; 6], u: &[f64; 24]) -> [f64; 24] {
    let mut f = [0.0; 24];
    for xi in GAUSS {
        let (b, det) = b_matrix(x, xi);
        let s = solid::mul6(d, &solid::strain(&b, u)).map(|c| det * c);
        solid::add_bt_sigma(&mut f, &b, &s);
    }
    f
}

/// Stress `σ = D B(ξ) u_e` (Voigt order `[xx, yy, zz, xy, yz, zx]`) at natural
/// coordinates `xi` (the centroid is `[0.0; 3]`).
pub fn stress_at(x: &[[f64; 3]; 8], d: &[[f64; 6]; 6], u: &[f64; 24], xi: [f64; 3]) -> [f64; 6] {
    let (b, _) = b_matrix(x, xi);
    solid::mul6(d, &solid::strain(&b, u))
}

/// Stresses at the Gauss points, in the order of [`GAUSS`].
pub fn gauss_stresses(x: &[[f64; 3]; 8], d: &[[f64; 6]; 6], u: &[f64; 24]) -> [[f64; 6]; 8] {
    GAUSS.map(|xi| stress_at(x, d, u, xi))
}

/// Corner values from the 8 Gauss-point values by the trilinear field through them
/// (exact for trilinear fields): `σ_i = Σ_g N_g(√3 ξ_i) σ_g`.
pub fn extrapolate_to_nodes(gauss: &[[f64; 6]; 8]) -> [[f64; 6]; 8] {
    std::array::from_fn(|i| {
        let w = shape(CORNERS[i].map(|c| SQRT_3 * c));
        std::array::from_fn(|c| (0..8).map(|g| w[g] * gauss[g][c]).sum())
    })
}

/// The element's stresses for recovery: the mean of the Gauss-point stresses as the
/// element value (as the Q4's), and their trilinear extrapolation at the corners.
pub fn stresses(x: &[[f64; 3]; 8], d: &[[f64; 6]; 6], u: &[f64; 24]) -> SolidStress<8> {
    let g = gauss_stresses(x, d, u);
    SolidStress {
        element: std::array::from_fn(|c| 0.125 * g.iter().map(|s| s[c]).sum::<f64>()),
        corners: extrapolate_to_nodes(&g),
    }
}

/// Natural coordinates of the point `p` by Newton's method on `x(ξ) = p`, started at
/// the centre: `Jᵀ δ = −(x(ξ) − p)` (Cramer's rule), `ξ ← ξ + δ`. Converged when the
/// residual |x(ξ) − p| ≤ [`INVERSE_MAP_TOLERANCE`] × the longest body diagonal, or
/// the step is below 1e-14; at most [`INVERSE_MAP_ITERATIONS`] iterations. `None` if
/// it does not converge, if J becomes singular on the way (|det J| ≤ [`solid::FLAT`] ×
/// diagonal³) or anything is not finite. Points on the boundary and outside the element are
/// mapped too (coordinates outside [−1, 1] then: [`is_inside`] tells).
pub fn natural_coordinates(x: &[[f64; 3]; 8], p: [f64; 3]) -> Option<[f64; 3]> {
    let size = diagonal(x);
    if !(size.is_finite() && size > 0.0 && p.iter().all(|v| v.is_finite())) {
        return None;
    }
    let mut xi = [0.0; 3];
    for _ in 0..INVERSE_MAP_ITERATIONS {
        let at = point(x, xi);
        let r: [f64; 3] = std::array::from_fn(|c| at[c] - p[c]);
        if r[0].hypot(r[1]).hypot(r[2]) <= INVERSE_MAP_TOLERANCE * size {
            return Some(xi);
        }
        let j = jacobian(x, xi);
        let det = solid::det3(&j);
        if !solid::is_positive(det.abs(), size) {
            return None;
        }
        // Jᵀ δ = −r: δ_a = −det(J with row a replaced by r) / det J.
        let step: [f64; 3] = std::array::from_fn(|a| {
            let mut m = j;
            m[a] = r;
            -solid::det3(&m) / det
        });
        xi = std::array::from_fn(|a| xi[a] + step[a]);
        if !xi.iter().all(|v| v.is_finite()) {
            return None;
        }
        if step[0].hypot(step[1]).hypot(step[2]) < 1e-14 {
            return Some(xi);
        }
    }
    None
}

/// The longest of the four body diagonals 0-6, 1-7, 2-4, 3-5 (the element's size).
fn diagonal(x: &[[f64; 3]; 8]) -> f64 {
    let dist = |a: [f64; 3], b: [f64; 3]| (b[0] - a[0]).hypot(b[1] - a[1]).hypot(b[2] - a[2]);
    [(0, 6), (1, 7), (2, 4), (3, 5)]
        .iter()
        .map(|&(a, b)| dist(x[a], x[b]))
        .fold(0.0, f64::max)
}

/// Whether natural coordinates `xi` lie in the element within `tol`: |ξ|, |η|, |ζ| ≤ 1 + tol.
pub fn is_inside(xi: [f64; 3], tol: f64) -> bool {
    xi.iter().all(|v| v.abs() <= 1.0 + tol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::face3;
    use crate::fem::material::d_solid;
    use crate::fem::solid::testing::*;
    use crate::fem::tet4;

    /// A distorted hexahedron with warped (non-planar) faces, positively oriented.
    const HEX: [[f64; 3]; 8] = [
        [0.0, 0.0, 0.0],
        [2.0, 0.1, -0.2],
        [2.3, 1.8, 0.1],
        [-0.2, 2.1, 0.0],
        [0.1, -0.1, 1.9],
        [1.8, 0.2, 2.4],
        [2.1, 2.2, 1.7],
        [0.2, 1.9, 2.2],
    ];

    /// Outward faces of the local numbering.
    const FACES: [[usize; 4]; 6] = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];

    fn steel() -> [[f64; 6]; 6] {
        d_solid(210000.0, 0.3)
    }

    /// The shape functions sum to one, are 1 at their own corner and 0 at the others,
    /// and their derivatives are the finite differences of them (and sum to zero).
    #[test]
    fn partition_of_unity_kronecker_and_derivatives() {
        for (i, &c) in CORNERS.iter().enumerate() {
            for (k, v) in shape(c).iter().enumerate() {
                assert_eq!(*v, if k == i { 1.0 } else { 0.0 });
            }
        }
        let h = 1e-6;
        for xi in [[0.0; 3], [0.3, -0.7, 0.2], [-0.9, 0.15, 1.0], GAUSS[5], [1.3, -1.1, 0.4]] {
            assert!((shape(xi).iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let dn = shape_derivatives(xi);
            for a in 0..3 {
                assert!(dn[a].iter().sum::<f64>().abs() < 1e-15);
                let (mut p, mut m) = (xi, xi);
                p[a] += h;
                m[a] -= h;
                let (np, nm) = (shape(p), shape(m));
                for i in 0..8 {
                    assert!((dn[a][i] - (np[i] - nm[i]) / (2.0 * h)).abs() < 1e-9);
                }
            }
        }
    }

    /// The volume of a hexahedron with warped faces equals its split into 24
    /// tetrahedra (each face fanned from the mean of its corners to the mean of all
    /// eight, exact for bilinear faces); a parallelepiped's is the triple product.
    #[test]
    fn volume_equals_tetrahedral_split() {
        let mean = |ids: &[usize]| -> [f64; 3] {
            std::array::from_fn(|c| ids.iter().map(|&i| HEX[i][c]).sum::<f64>() / ids.len() as f64)
        };
        let centre = mean(&[0, 1, 2, 3, 4, 5, 6, 7]);
        let mut split = 0.0;
        for f in FACES {
            let fc = mean(&f);
            for k in 0..4 {
                // The outward triangle (fc, f[k], f[k+1]) reversed, apex the centre.
                split += tet4::volume(&[fc, HEX[f[(k + 1) % 4]], HEX[f[k]], centre]);
            }
        }
        let v = volume(&HEX);
        assert!(v > 0.0 && (v - split).abs() < 1e-13 * v, "{v} vs {split}");
        assert!((check(&HEX).unwrap() - v).abs() < 1e-15 * v);
        let (a, b, c) = ([2.0, 0.3, 0.1], [0.4, 1.5, -0.2], [0.2, 0.3, 1.2]);
        let box_x = CORNERS.map(|n| {
            let s = n.map(|v| 0.5 * (v + 1.0));
            std::array::from_fn(|k| s[0] * a[k] + s[1] * b[k] + s[2] * c[k])
        });
        let triple = (a[1] * b[2] - a[2] * b[1]) * c[0]
            + (a[2] * b[0] - a[0] * b[2]) * c[1]
            + (a[0] * b[1] - a[1] * b[0]) * c[2];
        assert!((volume(&box_x) - triple).abs() < 1e-14);
        assert!((min_corner_jacobian_ratio(&box_x) - 1.0).abs() < 1e-13);
        let r = min_corner_jacobian_ratio(&HEX);
        assert!(r > 0.0 && r < 1.0);
    }

    /// `check` reports a non-positive Jacobian as a value: a mirrored element (top
    /// and bottom swapped) at its first corner, a corner pushed deep inside (the
    /// element folds), a collapsed element as zero.
    #[test]
    fn check_reports_non_positive_jacobians() {
        let mirrored = [HEX[4], HEX[5], HEX[6], HEX[7], HEX[0], HEX[1], HEX[2], HEX[3]];
        let e = check(&mirrored).unwrap_err();
        assert!(e.det < 0.0 && e.at == CORNERS[0]);
        let mut pushed = HEX;
        pushed[6] = [0.5, 0.5, 0.3]; // below the top face, near corner 0
        let e = check(&pushed).unwrap_err();
        assert!(e.det <= 0.0, "{e:?}");
        assert!(min_corner_jacobian_ratio(&pushed) <= 0.0);
        let mut collapsed = HEX;
        collapsed.copy_within(0..4, 4);
        assert!(check(&collapsed).unwrap_err().det.abs() < 1e-15);
        assert_eq!(min_corner_jacobian_ratio(&collapsed), 0.0);
    }

    /// K is exactly symmetric, the six rigid-body modes give zero force, and K has
    /// exactly six zero eigenvalues, the other eighteen positive (full integration:
    /// no hourglass mode).
    #[test]
    fn stiffness_symmetric_psd_with_six_rigid_modes() {
        let k = stiffness(&HEX, &steel());
        let kmax = max_abs(k.iter().flatten().copied());
        assert!(is_exactly_symmetric(&k));
        for m in rigid_modes::<8, 24>(&HEX) {
            let f = solid::mul(&k, &m);
            assert!(max_abs(f) < 1e-12 * kmax * max_abs(m), "{f:?}");
        }
        let ev = eigenvalues(&k);
        assert!(ev[..6].iter().all(|l| l.abs() < 1e-12 * kmax), "{ev:?}");
        assert!(ev[6..].iter().all(|&l| l > 1e-4 * kmax), "{ev:?}");
    }

    /// Patch test on the distorted element: a linear field gives the exact constant
    /// stress at the Gauss points, the centroid, an off-centre point and the
    /// extrapolated corners; K u equals the consistent nodal forces of σ n on the six
    /// warped faces (face3's exact quad pressure forces carry ∫ N_i n dA).
    #[test]
    fn linear_field_gives_exact_stress_and_boundary_forces() {
        let d = steel();
        let g = [[1e-3, 2e-3, -5e-4], [-1e-3, 3e-4, 7e-4], [2e-4, -6e-4, -8e-4]];
        let u: [f64; 24] = linear_field(&HEX, [0.1, -0.2, 0.05], g);
        let exact = solid::mul6(&d, &strain_of_gradient(g));
        let tol = 1e-11 * max_abs(exact);
        let s = stresses(&HEX, &d, &u);
        let mut samples = gauss_stresses(&HEX, &d, &u).to_vec();
        samples.extend(s.corners);
        samples.push(s.element);
        samples.push(stress_at(&HEX, &d, &u, [0.0; 3]));
        samples.push(stress_at(&HEX, &d, &u, [0.7, -0.35, 0.9]));
        for v in samples {
            assert!((0..6).all(|c| (v[c] - exact[c]).abs() < tol), "{v:?} vs {exact:?}");
        }
        let t = [
            [exact[0], exact[3], exact[5]],
            [exact[3], exact[1], exact[4]],
            [exact[5], exact[4], exact[2]],
        ];
        let mut boundary = [0.0; 24];
        for face in FACES {
            let w = face3::quad_pressure_forces(&face.map(|i| HEX[i]), -1.0);
            for (k, &node) in face.iter().enumerate() {
                for r in 0..3 {
                    boundary[3 * node + r] += (0..3).map(|c| t[r][c] * w[k][c]).sum::<f64>();
                }
            }
        }
        let f = internal_force(&HEX, &d, &u);
        let fk = solid::mul(&stiffness(&HEX, &d), &u);
        let fmax = max_abs(boundary);
        for i in 0..24 {
            assert!((f[i] - boundary[i]).abs() < 1e-12 * fmax, "{i}: {} vs {}", f[i], boundary[i]);
            assert!((fk[i] - boundary[i]).abs() < 1e-12 * fmax, "{i}");
        }
    }

    /// Assembled patch test: eight distorted hexahedra around one interior node; with
    /// the 26 boundary nodes moved by a linear field, equilibrium of the interior node
    /// puts it on that field and every Gauss-point stress is the exact constant one.
    #[test]
    fn assembled_patch_reproduces_linear_field() {
        // A 3×3×3 lattice of nodes on [0, 2]³, the interior node moved off-centre and
        // the boundary nodes perturbed within their faces' planes where it keeps them
        // on the boundary (a perturbation inside is free: the patch is any mesh).
        let id = |i: usize, j: usize, k: usize| i + 3 * j + 9 * k;
        let mut nodes = vec![[0.0; 3]; 27];
        for k in 0..3 {
            for j in 0..3 {
                for i in 0..3 {
                    let wobble = |a: usize, s: f64| if a == 1 { s } else { 0.0 };
                    nodes[id(i, j, k)] = [
                        i as f64 + wobble(i, 0.13 * (j as f64 - 1.0) + 0.07 * k as f64),
                        j as f64 + wobble(j, -0.11 * (k as f64 - 1.0) + 0.05 * i as f64),
                        k as f64 + wobble(k, 0.09 * (i as f64 - 1.0) - 0.06 * j as f64),
                    ];
                }
            }
        }
        nodes[id(1, 1, 1)] = [1.17, 0.88, 1.09];
        let cells: Vec<[usize; 8]> = (0..8)
            .map(|c| {
                let (i, j, k) = (c % 2, (c / 2) % 2, c / 4);
                [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]
            })
            .collect();
        let d = steel();
        let g = [[1e-3, 2e-3, -5e-4], [-1e-3, 3e-4, 7e-4], [2e-4, -6e-4, -8e-4]];
        let field = |p: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|r| 0.01 * r as f64 + (0..3).map(|c| g[r][c] * p[c]).sum::<f64>())
        };
        let centre = id(1, 1, 1);
        let mut kg = [[0.0; 3]; 3];
        let mut rhs = [0.0; 3];
        for cell in &cells {
            let x = cell.map(|n| nodes[n]);
            assert!(check(&x).is_ok());
            let k = stiffness(&x, &d);
            if let Some(a) = cell.iter().position(|&n| n == centre) {
                for (b, &nb) in cell.iter().enumerate() {
                    for r in 0..3 {
                        for c in 0..3 {
                            if nb == centre {
                                kg[r][c] += k[3 * a + r][3 * b + c];
                            } else {
                                rhs[r] -= k[3 * a + r][3 * b + c] * field(nodes[nb])[c];
                            }
                        }
                    }
                }
            }
        }
        let sol = solve(kg.iter().map(|r| r.to_vec()).collect(), rhs.to_vec());
        let want = field(nodes[centre]);
        for r in 0..3 {
            assert!((sol[r] - want[r]).abs() < 1e-13, "{sol:?} vs {want:?}");
        }
        let exact = solid::mul6(&d, &strain_of_gradient(g));
        for cell in &cells {
            let x = cell.map(|n| nodes[n]);
            let u: [f64; 24] = std::array::from_fn(|i| {
                let n = cell[i / 3];
                if n == centre { sol[i % 3] } else { field(nodes[n])[i % 3] }
            });
            for s in gauss_stresses(&x, &d, &u) {
                assert!((0..6).all(|c| (s[c] - exact[c]).abs() < 1e-8), "{s:?} vs {exact:?}");
            }
        }
    }

    /// Uniaxial stress: an a × b × c box held by symmetry on its three coordinate
    /// faces and pulled by σ on the face x = a moves every node by (σ x/E, −ν σ y/E,
    /// −ν σ z/E) exactly.
    #[test]
    fn uniaxial_stress_gives_poisson_contraction() {
        let (a, b, c, e, nu, sigma) = (2.0, 1.5, 0.8, 1000.0, 0.3, 5.0);
        let x = CORNERS.map(|n| {
            let s = n.map(|v| 0.5 * (v + 1.0));
            [a * s[0], b * s[1], c * s[2]]
        });
        let k = stiffness(&x, &d_solid(e, nu));
        let mut f = [0.0; 24];
        let right = [1, 2, 6, 5];
        for (q, fq) in right.iter().zip(face3::quad_traction_forces(&right.map(|i| x[i]), [sigma, 0.0, 0.0])) {
            for r in 0..3 {
                f[3 * q + r] += fq[r];
            }
        }
        let free: Vec<usize> = (0..24).filter(|&i| x[i / 3][i % 3] != 0.0).collect();
        let kk = free.iter().map(|&i| free.iter().map(|&j| k[i][j]).collect()).collect();
        let sol = solve(kk, free.iter().map(|&i| f[i]).collect());
        for (&i, v) in free.iter().zip(&sol) {
            let p = x[i / 3];
            let want = match i % 3 {
                0 => sigma * p[0] / e,
                1 => -nu * sigma * p[1] / e,
                _ => -nu * sigma * p[2] / e,
            };
            assert!((v - want).abs() < 1e-14, "dof {i}: {v} vs {want}");
        }
    }

    /// The internal force is the gradient of the strain energy ½ Σ_g εᵀ D ε det J_g:
    /// central differences of the energy match it (the energy is quadratic).
    #[test]
    fn internal_force_is_the_energy_gradient() {
        let d = steel();
        let energy = |u: &[f64; 24]| {
            GAUSS
                .iter()
                .map(|&xi| {
                    let (b, det) = b_matrix(&HEX, xi);
                    let eps = solid::strain(&b, u);
                    let s = solid::mul6(&d, &eps);
                    0.5 * det * (0..6).map(|i| eps[i] * s[i]).sum::<f64>()
                })
                .sum::<f64>()
        };
        let u: [f64; 24] = std::array::from_fn(|i| 1e-3 * (1.3 + i as f64).sin());
        let f = internal_force(&HEX, &d, &u);
        let h = 1e-7;
        for i in 0..24 {
            let (mut p, mut m) = (u, u);
            p[i] += h;
            m[i] -= h;
            let fd = (energy(&p) - energy(&m)) / (2.0 * h);
            assert!((fd - f[i]).abs() < 1e-6 * max_abs(f), "{i}: {fd} vs {}", f[i]);
        }
    }

    /// Rotating the element by R rotates its stiffness: K(R x) = R̂ K(x) R̂ᵀ with R̂
    /// the block diagonal of R (isotropic D).
    #[test]
    fn stiffness_is_rotation_invariant() {
        let d = steel();
        let r = rotation([0.3, -0.5, 0.8], 0.9);
        let k = stiffness(&HEX, &d);
        let kr = stiffness(&HEX.map(|p| rotate(&r, p)), &d);
        let kmax = max_abs(k.iter().flatten().copied());
        for (i, row) in kr.iter().enumerate() {
            for (j, kij) in row.iter().enumerate() {
                let (a, p, b, q) = (i / 3, i % 3, j / 3, j % 3);
                let want: f64 = (0..3)
                    .flat_map(|s| (0..3).map(move |t| (s, t)))
                    .map(|(s, t)| r[p][s] * k[3 * a + s][3 * b + t] * r[q][t])
                    .sum();
                assert!((kij - want).abs() < 1e-12 * kmax, "{i} {j}");
            }
        }
    }

    /// The inverse map returns ξ to 1e-12 inside, on faces, edges and corners and
    /// outside the distorted element (`is_inside` false there); a point given by x
    /// alone on a face comes back with that face's coordinate ±1; a collapsed element
    /// or a non-finite point gives None.
    #[test]
    fn natural_coordinates_round_trip() {
        let ticks = [-1.15, -1.0, -0.6, 0.0, 0.35, 1.0, 1.1];
        for &s in &ticks {
            for &t in &ticks {
                for &w in &ticks {
                    let xi = [s, t, w];
                    let back = natural_coordinates(&HEX, point(&HEX, xi)).expect("converges");
                    assert!((0..3).all(|a| (back[a] - xi[a]).abs() < 1e-12), "{back:?} vs {xi:?}");
                    assert_eq!(is_inside(back, 1e-9), is_inside(xi, 0.0));
                }
            }
        }
        // The mean of the corners of the warped face 1-2-6-5 is x(1, 0, 0).
        let p: [f64; 3] = std::array::from_fn(|c| [1, 2, 6, 5].iter().map(|&i| HEX[i][c]).sum::<f64>() / 4.0);
        let xi = natural_coordinates(&HEX, p).unwrap();
        assert!((xi[0] - 1.0).abs() < 1e-12 && xi[1].abs() < 1e-12 && xi[2].abs() < 1e-12);
        let mut collapsed = HEX;
        collapsed.copy_within(0..4, 4);
        assert_eq!(natural_coordinates(&collapsed, [1.0, 1.0, 0.0]), None);
        assert_eq!(natural_coordinates(&HEX, [f64::NAN, 0.0, 0.0]), None);
    }

    /// The corner extrapolation reproduces a trilinear field exactly from its values
    /// at the Gauss points.
    #[test]
    fn extrapolation_exact_for_trilinear_fields() {
        let f = |c: usize, x: [f64; 3]| {
            let k = 1.0 + c as f64;
            k + 2.0 * x[0] - 0.5 * k * x[1] + 0.3 * x[2] + 0.7 * x[0] * x[1] - k * x[1] * x[2]
                + 0.2 * x[2] * x[0]
                + 1.1 * k * x[0] * x[1] * x[2]
        };
        let gauss = GAUSS.map(|g| std::array::from_fn(|c| f(c, g)));
        let nodal = extrapolate_to_nodes(&gauss);
        for (i, node) in nodal.iter().enumerate() {
            for (c, v) in node.iter().enumerate() {
                assert!((v - f(c, CORNERS[i])).abs() < 1e-13, "node {i} comp {c}");
            }
        }
    }
}
