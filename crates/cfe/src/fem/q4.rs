//! The 4-node bilinear quadrilateral Q4 (isoparametric, full 2×2 Gauss integration)
//! for plane elasticity: shape functions, Jacobian, strain–displacement matrix,
//! stiffness, stress recovery and the inverse map.
//!
//! Corners are numbered counter-clockwise; corner i sits at the natural corner
//! `(ξ_i, η_i)` = (−1, −1), (1, −1), (1, 1), (−1, 1). Element DOFs are ordered
//! `[u1, v1, u2, v2, u3, v3, u4, v4]`; stresses are (σxx, σyy, σxy) with engineering
//! shear strain γxy = ∂u/∂y + ∂v/∂x.
//!
//! - Shape functions `N_i(ξ, η) = ¼ (1 + ξ ξ_i)(1 + η η_i)`; geometry and displacement
//!   are interpolated alike: `x = Σ N_i x_i`, `u = Σ N_i u_i`.
//! - Jacobian `J = [[∂x/∂ξ, ∂y/∂ξ], [∂x/∂η, ∂y/∂η]] = Σ_i [∂N_i/∂ξ; ∂N_i/∂η] [x_i, y_i]`
//!   and `[∂N_i/∂x; ∂N_i/∂y] = J⁻¹ [∂N_i/∂ξ; ∂N_i/∂η]`. For the bilinear map det J is
//!   linear in (ξ, η) (the ξη terms cancel), so `∫ det J dξ dη = Σ_g det J_g` exactly
//!   and its minimum over the element is at a corner.
//! - B (3×8), columns `2i, 2i+1` (node i = 0..3): `[[N_i,x, 0], [0, N_i,y], [N_i,y, N_i,x]]`.
//! - Stiffness `K_e = Σ_g B_gᵀ D B_g t det J_g w_g` over the 2×2 Gauss points
//!   `(±1/√3, ±1/√3)`, `w_g = 1` (full integration: no spurious zero-energy modes).
//! - Stress `σ = D B u_e`, best sampled at the Gauss points. Nodal values come from the
//!   bilinear field through the four Gauss values: in `r = √3 ξ, s = √3 η` the Gauss
//!   points are the corners (±1, ±1), so `σ_i = Σ_g N_g(√3 ξ_i, √3 η_i) σ_g`, i.e. weights
//!   1 + √3/2 (own point), −½ (the two adjacent points), 1 − √3/2 (opposite point).

use super::sum_of;

/// 1/√3, the 2-point Gauss–Legendre abscissa.
const G: f64 = 0.577_350_269_189_625_8;

/// √3, the factor from Gauss-point coordinates back to natural coordinates.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// Natural coordinates (ξ_i, η_i) of the corners, counter-clockwise.
const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// 2×2 Gauss points (ξ, η) and weights, in the order corner 1..4 (point k nearest
/// natural corner k): `(ξ, η) = (±1/√3, ±1/√3)`, weights all 1.
pub const GAUSS: [[f64; 2]; 4] = [[-G, -G], [G, -G], [G, G], [-G, G]];

/// Shape functions `N_i = ¼ (1 + ξ ξ_i)(1 + η η_i)` at `xi = (ξ, η)`.
pub fn shape(xi: [f64; 2]) -> [f64; 4] {
    std::array::from_fn(|i| {
        let [a, b] = CORNERS[i];
        0.25 * (1.0 + xi[0] * a) * (1.0 + xi[1] * b)
    })
}

/// Shape-function derivatives `[dN/dξ, dN/dη]` at `xi = (ξ, η)`:
/// `∂N_i/∂ξ = ¼ ξ_i (1 + η η_i)`, `∂N_i/∂η = ¼ η_i (1 + ξ ξ_i)`.
pub fn shape_derivatives(xi: [f64; 2]) -> [[f64; 4]; 2] {
    [
        std::array::from_fn(|i| 0.25 * CORNERS[i][0] * (1.0 + xi[1] * CORNERS[i][1])),
        std::array::from_fn(|i| 0.25 * CORNERS[i][1] * (1.0 + xi[0] * CORNERS[i][0])),
    ]
}

/// Jacobian `J = [[∂x/∂ξ, ∂y/∂ξ], [∂x/∂η, ∂y/∂η]]`, `J_ab = Σ_i ∂N_i/∂ξ_a x_ib`, of the
/// map from natural coordinates to the element with corners `x`.
pub fn jacobian(x: &[[f64; 2]; 4], xi: [f64; 2]) -> [[f64; 2]; 2] {
    let dn = shape_derivatives(xi);
    std::array::from_fn(|a| std::array::from_fn(|b| sum_of(4, |i| dn[a][i] * x[i][b])))
}

/// Strain–displacement matrix B (3×8) at `xi = (ξ, η)` and det J:
///
/// `[∂N_i/∂x; ∂N_i/∂y] = 1/det J [[J22, −J12], [−J21, J11]] [∂N_i/∂ξ; ∂N_i/∂η]`,
/// B columns `2i, 2i+1` (i = 0..3) = `[[N_i,x, 0], [0, N_i,y], [N_i,y, N_i,x]]`.
/// Non-finite entries if det J = 0.
pub fn b_matrix(x: &[[f64; 2]; 4], xi: [f64; 2]) -> ([[f64; 8]; 3], f64) {
    let dn = shape_derivatives(xi);
    let j = jacobian(x, xi);
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let s = 1.0 / det;
    let mut b = [[0.0; 8]; 3];
    for i in 0..4 {
        let nx = s * (j[1][1] * dn[0][i] - j[0][1] * dn[1][i]);
        let ny = s * (j[0][0] * dn[1][i] - j[1][0] * dn[0][i]);
        b[0][2 * i] = nx;
        b[1][2 * i + 1] = ny;
        b[2][2 * i] = ny;
        b[2][2 * i + 1] = nx;
    }
    (b, det)
}

/// Signed area by the shoelace formula `A = ½ Σ_i (x_i y_{i+1} − x_{i+1} y_i)`;
/// positive for counter-clockwise corners.
pub fn area(x: &[[f64; 2]; 4]) -> f64 {
    0.5 * (0..4)
        .map(|i| {
            let (p, q) = (x[i], x[(i + 1) % 4]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
}

/// Element stiffness `K_e = ∫ Bᵀ D B t dA = Σ_g B_gᵀ D B_g t det J_g` (2×2 Gauss,
/// weights 1). The upper triangle is accumulated and mirrored, so K_e is exactly
/// symmetric (D is taken symmetric).
pub fn stiffness(x: &[[f64; 2]; 4], d: &[[f64; 3]; 3], thickness: f64) -> [[f64; 8]; 8] {
    let mut k = [[0.0; 8]; 8];
    for xi in GAUSS {
        let (b, det) = b_matrix(x, xi);
        let w = thickness * det;
        // DB (3×8)
        let db: [[f64; 8]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| sum_of(3, |m| d[i][m] * b[m][j]))
        });
        for (i, row) in k.iter_mut().enumerate() {
            for (j, kij) in row.iter_mut().enumerate().skip(i) {
                *kij += w * sum_of(3, |m| b[m][i] * db[m][j]);
            }
        }
    }
    std::array::from_fn(|i| std::array::from_fn(|j| k[i.min(j)][i.max(j)]))
}

/// Element internal force `K_e u_e = Σ_g t det J_g B_gᵀ (D (B_g u_e))` over the
/// 2×2 Gauss points, without forming `K_e`.
pub fn internal_force(x: &[[f64; 2]; 4], d: &[[f64; 3]; 3], thickness: f64, u: &[f64; 8]) -> [f64; 8] {
    let mut f = [0.0; 8];
    for xi in GAUSS {
        let (b, det) = b_matrix(x, xi);
        let w = thickness * det;
        let eps: [f64; 3] = std::array::from_fn(|i| sum_of(8, |j| b[i][j] * u[j]));
        let sigma: [f64; 3] =
            std::array::from_fn(|i| w * sum_of(3, |j| d[i][j] * eps[j]));
        for (j, fj) in f.iter_mut().enumerate() {
            *fj += sum_of(3, |i| b[i][j] * sigma[i]);
        }
    }
    f
}

/// Stress `σ = D B(ξ, η) u_e` (σxx, σyy, σxy) at natural coordinates `xi`.
pub fn stress_at(x: &[[f64; 2]; 4], d: &[[f64; 3]; 3], u: &[f64; 8], xi: [f64; 2]) -> [f64; 3] {
    let (b, _) = b_matrix(x, xi);
    let eps: [f64; 3] = std::array::from_fn(|i| sum_of(8, |j| b[i][j] * u[j]));
    std::array::from_fn(|i| sum_of(3, |j| d[i][j] * eps[j]))
}

/// Stresses `σ_g = D B_g u_e` at the Gauss points, in the order of [`GAUSS`].
pub fn gauss_stresses(x: &[[f64; 2]; 4], d: &[[f64; 3]; 3], u: &[f64; 8]) -> [[f64; 3]; 4] {
    GAUSS.map(|xi| stress_at(x, d, u, xi))
}

/// Nodal values from the 4 Gauss-point values by the bilinear field through them
/// (exact for bilinear fields): `σ_i = Σ_g N_g(√3 ξ_i, √3 η_i) σ_g`.
pub fn extrapolate_to_nodes(gauss: &[[f64; 3]; 4]) -> [[f64; 3]; 4] {
    std::array::from_fn(|i| {
        let w = shape([SQRT_3 * CORNERS[i][0], SQRT_3 * CORNERS[i][1]]);
        std::array::from_fn(|c| sum_of(4, |g| w[g] * gauss[g][c]))
    })
}

/// Product of an 8×8 element matrix with an 8-vector: the element internal force `K_e u_e`.
pub fn mul(k: &[[f64; 8]; 8], u: &[f64; 8]) -> [f64; 8] {
    std::array::from_fn(|i| sum_of(8, |j| k[i][j] * u[j]))
}

/// Natural coordinates of point p by Newton's method on x(ξ) = p (inverse bilinear
/// map), started at the centre: `Jᵀ δ = −(x(ξ) − p)`, `ξ ← ξ + δ`. Converged when the
/// step is below 1e-14 (relative to 1) or the residual below 1e-13 × element size (the
/// longer diagonal); at most 50 iterations. None if it does not converge or J becomes
/// singular (|det J| ≤ ε size²). Works for points on the boundary and outside the
/// element (returns coordinates outside [−1, 1] then).
pub fn natural_coordinates(x: &[[f64; 2]; 4], p: [f64; 2]) -> Option<[f64; 2]> {
    let diag = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]).hypot(b[1] - a[1]);
    let size = diag(x[0], x[2]).max(diag(x[1], x[3]));
    if !(size.is_finite() && size > 0.0) {
        return None;
    }
    let mut xi = [0.0; 2];
    for _ in 0..50 {
        let n = shape(xi);
        let r: [f64; 2] =
            std::array::from_fn(|c| sum_of(4, |i| n[i] * x[i][c]) - p[c]);
        if r[0].hypot(r[1]) <= 1e-13 * size {
            return Some(xi);
        }
        let j = jacobian(x, xi);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det.is_nan() || det.abs() <= f64::EPSILON * size * size {
            return None;
        }
        // Jᵀ = [[∂x/∂ξ, ∂x/∂η], [∂y/∂ξ, ∂y/∂η]]
        let step = [
            -(j[1][1] * r[0] - j[1][0] * r[1]) / det,
            -(j[0][0] * r[1] - j[0][1] * r[0]) / det,
        ];
        xi = [xi[0] + step[0], xi[1] + step[1]];
        if step[0].hypot(step[1]) < 1e-14 {
            return Some(xi);
        }
    }
    None
}

/// Shape quality: `min_i det J(ξ_i, η_i) / (|A| / 4)` over the 4 corners. Since det J is
/// linear in (ξ, η), a positive value means det J > 0 everywhere in the element (Gauss
/// points included): not inverted, not degenerate. 1 for a parallelogram; ≤ 0 when
/// non-convex, clockwise (det J < 0) or degenerate (0 when the area vanishes).
pub fn min_corner_jacobian_ratio(x: &[[f64; 2]; 4]) -> f64 {
    let quarter = 0.25 * area(x).abs();
    if !(quarter.is_finite() && quarter > 0.0) {
        return 0.0;
    }
    CORNERS
        .iter()
        .map(|&c| {
            let j = jacobian(x, c);
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / quarter
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Material, PlaneKind};

    /// A distorted convex quad (no two sides parallel), counter-clockwise, off the origin.
    const QUAD: [[f64; 2]; 4] = [[1.0, 2.0], [4.0, 2.4], [3.5, 4.2], [1.3, 3.4]];

    fn d_steel() -> [[f64; 3]; 3] {
        Material::new(210000.0, 0.3, PlaneKind::Stress, 1.0, "p")
            .unwrap()
            .d_matrix()
    }

    /// Point x(ξ) = Σ N_i(ξ) x_i of the element.
    fn map(x: &[[f64; 2]; 4], xi: [f64; 2]) -> [f64; 2] {
        let n = shape(xi);
        std::array::from_fn(|c| (0..4).map(|i| n[i] * x[i][c]).sum())
    }

    /// Nodal DOFs of the linear field u = (a0 + a1 x + a2 y, b0 + b1 x + b2 y).
    fn linear_field(x: &[[f64; 2]; 4], a: [f64; 3], b: [f64; 3]) -> [f64; 8] {
        std::array::from_fn(|k| {
            let [px, py] = x[k / 2];
            let c = if k % 2 == 0 { a } else { b };
            c[0] + c[1] * px + c[2] * py
        })
    }

    fn energy(k: &[[f64; 8]; 8], u: &[f64; 8]) -> f64 {
        mul(k, u).iter().zip(u).map(|(f, v)| f * v).sum()
    }

    /// The Gauss abscissa is 1/√3 and √3 is its inverse, to the last bit but one.
    #[test]
    fn constants_are_exact() {
        assert!((G - 1.0 / 3f64.sqrt()).abs() <= f64::EPSILON * G);
        assert!((SQRT_3 - 3f64.sqrt()).abs() <= f64::EPSILON * SQRT_3);
        for (k, g) in GAUSS.iter().enumerate() {
            assert_eq!(
                g.map(f64::signum),
                CORNERS[k],
                "Gauss point {k} nearest corner {k}"
            );
        }
    }

    /// Shape functions sum to 1, are δ_ij at the corners, and their ξ and η
    /// derivatives sum to 0.
    #[test]
    fn partition_of_unity_and_kronecker_delta() {
        for (i, &c) in CORNERS.iter().enumerate() {
            let n = shape(c);
            for (j, nj) in n.iter().enumerate() {
                assert_eq!(*nj, if i == j { 1.0 } else { 0.0 }, "N_{j} at corner {i}");
            }
        }
        for xi in [
            [0.0, 0.0],
            [0.3, -0.7],
            [-0.9, 0.15],
            [1.0, 0.4],
            [1.3, -1.2],
            GAUSS[2],
        ] {
            assert!((shape(xi).iter().sum::<f64>() - 1.0).abs() < 1e-15);
            for row in shape_derivatives(xi) {
                assert!(row.iter().sum::<f64>().abs() < 1e-15);
            }
        }
    }

    /// The shape-function derivatives agree with central differences of the shape functions.
    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for xi in [[0.0, 0.0], [0.3, -0.7], [-0.9, 0.15]] {
            let dn = shape_derivatives(xi);
            let (xp, xm) = (shape([xi[0] + h, xi[1]]), shape([xi[0] - h, xi[1]]));
            let (yp, ym) = (shape([xi[0], xi[1] + h]), shape([xi[0], xi[1] - h]));
            for i in 0..4 {
                assert!((dn[0][i] - (xp[i] - xm[i]) / (2.0 * h)).abs() < 1e-9);
                assert!((dn[1][i] - (yp[i] - ym[i]) / (2.0 * h)).abs() < 1e-9);
            }
        }
    }

    /// The a × b rectangle in plane stress equals the textbook closed form of the bilinear
    /// rectangle (Cook, Malkus, Plesha & Witt, "Concepts and Applications of Finite
    /// Element Analysis", 4th ed., Wiley 2002, ch. 3; for a = b it is the square-element
    /// matrix k1..k8 of Sigmund, "A 99 line topology optimization code written in
    /// Matlab", Struct. Multidisc. Optim. 21 (2001) 120–127).
    #[test]
    fn rectangle_matches_closed_form() {
        // Derivation (exact integration of the bilinear field; 2×2 Gauss is exact here):
        // with node i at (0 or a, 0 or b), sx_i = ±1 the sign of ∂N_i/∂x, sy_i that of
        // ∂N_i/∂y, N_i = f_i(x) g_i(y):
        //   Ixx_ij = ∫ N_i,x N_j,x dA = sx_i sx_j / a · (b/3 if same y side, b/6 otherwise),
        //   Iyy_ij = ∫ N_i,y N_j,y dA = sy_i sy_j / b · (a/3 if same x side, a/6 otherwise),
        //   Ixy_ij = ∫ N_i,x N_j,y dA = sx_i sy_j / 4,
        // and with D = c [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]], c = E/(1−ν²):
        //   K(ui, uj) = t c (Ixx_ij + (1−ν)/2 Iyy_ij),
        //   K(vi, vj) = t c (Iyy_ij + (1−ν)/2 Ixx_ij),
        //   K(ui, vj) = t c (ν Ixy_ij + (1−ν)/2 Ixy_ji).
        // Signs (sx, sy): node 1 (−,−), 2 (+,−), 3 (+,+), 4 (−,+).
        let (a, b, e, nu, t) = (3.0, 2.0, 200.0, 0.3, 0.5);
        let (x0, y0) = (1.5, -2.0);
        let x = [[x0, y0], [x0 + a, y0], [x0 + a, y0 + b], [x0, y0 + b]];
        let d = Material::new(e, nu, PlaneKind::Stress, t, "p")
            .unwrap()
            .d_matrix();
        let k = stiffness(&x, &d, t);
        let tc = t * e / (1.0 - nu * nu);
        let (u1, v1, u2, v2, u3, v3, u4, v4) = (0, 1, 2, 3, 4, 5, 6, 7);
        let hand = [
            // k11 = E t/(1−ν²) [b/(3a) + (1−ν) a/(6b)]
            (u1, u1, tc * (b / (3.0 * a) + (1.0 - nu) * a / (6.0 * b))),
            // k12 = E t/(8(1−ν)) = t c (1+ν)/8
            (u1, v1, e * t / (8.0 * (1.0 - nu))),
            (v1, v1, tc * (a / (3.0 * b) + (1.0 - nu) * b / (6.0 * a))),
            (u1, u2, tc * (-b / (3.0 * a) + (1.0 - nu) * a / (12.0 * b))),
            (u1, u3, tc * (-b / (6.0 * a) - (1.0 - nu) * a / (12.0 * b))),
            (u1, u4, tc * (b / (6.0 * a) - (1.0 - nu) * a / (6.0 * b))),
            (u1, v2, tc * (3.0 * nu - 1.0) / 8.0),
            (u1, v3, -tc * (1.0 + nu) / 8.0),
            (u1, v4, tc * (1.0 - 3.0 * nu) / 8.0),
            (v1, v2, tc * (a / (6.0 * b) - (1.0 - nu) * b / (6.0 * a))),
            (v1, v4, tc * (-a / (3.0 * b) + (1.0 - nu) * b / (12.0 * a))),
            (u3, u3, tc * (b / (3.0 * a) + (1.0 - nu) * a / (6.0 * b))),
            (v3, v4, tc * (a / (6.0 * b) - (1.0 - nu) * b / (6.0 * a))),
            (u3, v4, tc * (3.0 * nu - 1.0) / 8.0),
            (u2, v4, tc * (1.0 + nu) / 8.0),
        ];
        for (i, j, want) in hand {
            assert!(
                (k[i][j] - want).abs() < 1e-13 * tc,
                "K[{i}][{j}] = {} vs {want}",
                k[i][j]
            );
        }
    }

    /// For the unit square (E = 1, t = 1) the first row of K is Sigmund's
    /// `E/(1−ν²) [k1 … k8]`, k = [1/2−ν/6, 1/8+ν/8, −1/4−ν/12, −1/8+3ν/8, −1/4+ν/12,
    /// −1/8−ν/8, ν/6, 1/8−3ν/8] (same DOF order).
    #[test]
    fn unit_square_matches_sigmund_row() {
        let nu = 0.3;
        let x = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let d = Material::new(1.0, nu, PlaneKind::Stress, 1.0, "p")
            .unwrap()
            .d_matrix();
        let k = stiffness(&x, &d, 1.0);
        let c = 1.0 / (1.0 - nu * nu);
        let row = [
            0.5 - nu / 6.0,
            0.125 + nu / 8.0,
            -0.25 - nu / 12.0,
            -0.125 + 3.0 * nu / 8.0,
            -0.25 + nu / 12.0,
            -0.125 - nu / 8.0,
            nu / 6.0,
            0.125 - 3.0 * nu / 8.0,
        ];
        for j in 0..8 {
            assert!((k[0][j] - c * row[j]).abs() < 1e-15, "K[0][{j}]");
        }
    }

    /// On a distorted quad K is exactly symmetric, rigid translations and the
    /// infinitesimal rotation give zero force, and K is positive semidefinite with
    /// exactly these 3 zero-energy modes (strain and hourglass modes store energy).
    #[test]
    fn stiffness_symmetric_with_exactly_three_rigid_modes() {
        let d = d_steel();
        let k = stiffness(&QUAD, &d, 2.0);
        let kmax = k.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (i, row) in k.iter().enumerate() {
            for (j, kij) in row.iter().enumerate() {
                assert_eq!(kij.to_bits(), k[j][i].to_bits(), "K[{i}][{j}]");
            }
        }
        let rigid = [
            linear_field(&QUAD, [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
            linear_field(&QUAD, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            linear_field(&QUAD, [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ];
        for m in rigid {
            let f = mul(&k, &m);
            let scale = kmax * m.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            assert!(f.iter().all(|f| f.abs() < 1e-13 * scale), "{f:?}");
        }
        // Non-rigid modes: stretches, shear, the two hourglass modes and a random one.
        let hourglass_u = [1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0, 0.0];
        let hourglass_v = [0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0];
        let modes = [
            linear_field(&QUAD, [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]),
            linear_field(&QUAD, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            linear_field(&QUAD, [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            hourglass_u,
            hourglass_v,
            [0.3, -0.2, 0.9, 0.1, -0.4, 0.7, 0.05, -0.6],
        ];
        for m in modes {
            assert!(energy(&k, &m) > 1e-3 * kmax, "{m:?}");
        }
        // Exactly 3 zero eigenvalues: with u1, v1, v2 fixed (which stops all rigid
        // motion, x2 ≠ x1) the remaining 5×5 block is positive definite (Cholesky).
        // Any u = r + s with r rigid and s in that subspace has uᵀKu = sᵀKs.
        let free = [2, 4, 5, 6, 7];
        let mut a: Vec<Vec<f64>> = free
            .iter()
            .map(|&i| free.iter().map(|&j| k[i][j]).collect())
            .collect();
        for c in 0..5 {
            let pivot = a[c][c] - (0..c).map(|m| a[c][m] * a[c][m]).sum::<f64>();
            assert!(pivot > 1e-3 * kmax, "pivot {c} = {pivot}");
            a[c][c] = pivot.sqrt();
            for r in c + 1..5 {
                a[r][c] = (a[r][c] - (0..c).map(|m| a[r][m] * a[c][m]).sum::<f64>()) / a[c][c];
            }
        }
    }

    /// Patch test on one element: a linear displacement field gives the exact constant
    /// stress D ε at all Gauss points, at the centre and at an off-centre point.
    #[test]
    fn linear_field_gives_exact_constant_stress() {
        let d = d_steel();
        let (a, b) = ([0.01, 2e-3, -1e-3], [-0.02, 3e-3, -4e-3]);
        let u = linear_field(&QUAD, a, b);
        let eps = [a[1], b[2], a[2] + b[1]];
        let exact: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| d[i][j] * eps[j]).sum());
        let tol = 1e-12 * exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut samples = gauss_stresses(&QUAD, &d, &u).to_vec();
        samples.push(stress_at(&QUAD, &d, &u, [0.0, 0.0]));
        samples.push(stress_at(&QUAD, &d, &u, [0.7, -0.35]));
        for s in samples {
            for c in 0..3 {
                assert!((s[c] - exact[c]).abs() < tol, "{s:?} vs {exact:?}");
            }
        }
    }

    /// Assembled patch test: four distorted quads around one interior node; with the 8
    /// boundary nodes moved by a linear field, equilibrium of the interior node puts it
    /// on that field and every Gauss-point stress is the exact constant stress.
    #[test]
    fn assembled_patch_reproduces_linear_field() {
        let nodes = [
            [0.0, 0.0],
            [1.1, 0.0],
            [2.0, 0.0],
            [2.0, 0.8],
            [2.0, 2.0],
            [0.9, 2.0],
            [0.0, 2.0],
            [0.0, 1.2],
            [1.2, 0.9], // interior
        ];
        let elements = [[0, 1, 8, 7], [1, 2, 3, 8], [8, 3, 4, 5], [7, 8, 5, 6]];
        let d = d_steel();
        let (a, b) = ([0.01, 2e-3, -1e-3], [-0.02, 3e-3, -4e-3]);
        let exact_u = |p: [f64; 2]| {
            [
                a[0] + a[1] * p[0] + a[2] * p[1],
                b[0] + b[1] * p[0] + b[2] * p[1],
            ]
        };
        let mut kg = vec![vec![0.0; 18]; 18];
        for e in elements {
            let x = e.map(|n| nodes[n]);
            assert!(min_corner_jacobian_ratio(&x) > 0.0);
            let k = stiffness(&x, &d, 1.0);
            for i in 0..8 {
                for j in 0..8 {
                    kg[2 * e[i / 2] + i % 2][2 * e[j / 2] + j % 2] += k[i][j];
                }
            }
        }
        // Interior DOFs 16, 17: K_ii u_i = −K_ib u_b.
        let mut ug: Vec<f64> = nodes.iter().flat_map(|&p| exact_u(p)).collect();
        ug[16] = 0.0;
        ug[17] = 0.0;
        let rhs: [f64; 2] =
            std::array::from_fn(|r| -(0..16).map(|j| kg[16 + r][j] * ug[j]).sum::<f64>());
        let (k00, k01, k10, k11) = (kg[16][16], kg[16][17], kg[17][16], kg[17][17]);
        let det = k00 * k11 - k01 * k10;
        ug[16] = (k11 * rhs[0] - k01 * rhs[1]) / det;
        ug[17] = (k00 * rhs[1] - k10 * rhs[0]) / det;
        let want = exact_u(nodes[8]);
        assert!((ug[16] - want[0]).abs() < 1e-14 && (ug[17] - want[1]).abs() < 1e-14);
        let eps = [a[1], b[2], a[2] + b[1]];
        let exact: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| d[i][j] * eps[j]).sum());
        for e in elements {
            let x = e.map(|n| nodes[n]);
            let u: [f64; 8] = std::array::from_fn(|i| ug[2 * e[i / 2] + i % 2]);
            for s in gauss_stresses(&x, &d, &u) {
                for c in 0..3 {
                    assert!((s[c] - exact[c]).abs() < 1e-9, "{s:?} vs {exact:?}");
                }
            }
        }
    }

    /// The shoelace area of a distorted quad equals half the cross product of its
    /// diagonals and Σ_g det J_g w_g; it changes sign for clockwise corners.
    #[test]
    fn area_equals_integral_of_det_j() {
        // ½ (x3 − x1) × (x4 − x2) = ½ (2.5 · 1.0 − 2.2 · (−2.7)) = 4.22
        assert!((area(&QUAD) - 4.22).abs() < 1e-14);
        let integral: f64 = GAUSS.iter().map(|&g| b_matrix(&QUAD, g).1).sum();
        assert!((integral - 4.22).abs() < 1e-14);
        let cw = [QUAD[0], QUAD[3], QUAD[2], QUAD[1]];
        assert!((area(&cw) + 4.22).abs() < 1e-14);
    }

    /// natural_coordinates inverts x(ξ) to 1e-12 inside, on the edges, at the corners
    /// and slightly outside a distorted quad; edge points come back with |ξ| or |η| = 1;
    /// a collapsed element gives None.
    #[test]
    fn natural_coordinates_round_trip() {
        let ticks = [-1.2, -1.0, -0.999, -0.6, -0.1, 0.0, 0.35, 0.8, 1.0, 1.15];
        for &s in &ticks {
            for &t in &ticks {
                let p = map(&QUAD, [s, t]);
                let xi = natural_coordinates(&QUAD, p).expect("converges");
                assert!(
                    (xi[0] - s).abs() < 1e-12 && (xi[1] - t).abs() < 1e-12,
                    "{xi:?} vs {s}, {t}"
                );
            }
        }
        // Points on side 2–3 (ξ = 1) and side 4–1 (ξ = −1), given by x alone.
        let p = [
            0.3 * QUAD[1][0] + 0.7 * QUAD[2][0],
            0.3 * QUAD[1][1] + 0.7 * QUAD[2][1],
        ];
        let xi = natural_coordinates(&QUAD, p).unwrap();
        assert!((xi[0] - 1.0).abs() < 1e-12 && xi[1].abs() < 1.0);
        let p = [
            0.6 * QUAD[3][0] + 0.4 * QUAD[0][0],
            0.6 * QUAD[3][1] + 0.4 * QUAD[0][1],
        ];
        let xi = natural_coordinates(&QUAD, p).unwrap();
        assert!((xi[0] + 1.0).abs() < 1e-12 && xi[1].abs() < 1.0);
        // A point well outside maps outside [−1, 1].
        let xi = natural_coordinates(&QUAD, [5.0, 3.0]).unwrap();
        assert!(xi[0] > 1.0);
        let flat = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
        assert_eq!(natural_coordinates(&flat, [1.0, 0.0]), None);
    }

    /// extrapolate_to_nodes reproduces a bilinear field a + bξ + cη + dξη exactly at the
    /// corners from its values at the Gauss points.
    #[test]
    fn extrapolation_exact_for_bilinear_fields() {
        let coef = [
            [1.5, -2.0, 0.7, 3.1],
            [-40.0, 12.0, 5.0, -8.0],
            [0.0, 0.25, -0.5, 1.0],
        ];
        let f = |c: usize, xi: [f64; 2]| {
            let [a, b, cc, d] = coef[c];
            a + b * xi[0] + cc * xi[1] + d * xi[0] * xi[1]
        };
        let gauss: [[f64; 3]; 4] = GAUSS.map(|g| std::array::from_fn(|c| f(c, g)));
        let nodal = extrapolate_to_nodes(&gauss);
        for (i, node) in nodal.iter().enumerate() {
            for (c, v) in node.iter().enumerate() {
                assert!((v - f(c, CORNERS[i])).abs() < 1e-13, "node {i} comp {c}");
            }
        }
    }

    /// The corner Jacobian ratio is 1 for a parallelogram, in (0, 1) for a convex
    /// distorted quad, −1 for a clockwise square, ≤ 0 for a non-convex arrow head and 0
    /// for three collinear corners.
    #[test]
    fn corner_jacobian_ratio_flags_bad_shapes() {
        let parallelogram = [[0.0, 0.0], [2.0, 0.0], [3.0, 1.0], [1.0, 1.0]];
        assert!((min_corner_jacobian_ratio(&parallelogram) - 1.0).abs() < 1e-14);
        let r = min_corner_jacobian_ratio(&QUAD);
        assert!(r > 0.0 && r < 1.0);
        // Corner 4 lies inside the triangle of the other three (reflex angle there).
        let arrow = [[0.0, 0.0], [2.0, 1.0], [0.0, 2.0], [1.0, 1.0]];
        assert!(area(&arrow) > 0.0 && min_corner_jacobian_ratio(&arrow) <= 0.0);
        let clockwise = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        assert!((min_corner_jacobian_ratio(&clockwise) + 1.0).abs() < 1e-14);
        let collinear = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        assert!(min_corner_jacobian_ratio(&collinear).abs() < 1e-15);
    }
}
