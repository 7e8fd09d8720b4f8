//! The linear triangle T3 (constant strain): strain–displacement matrix, stiffness
//! `K_e = ∫ Bᵀ D B t dA = t A Bᵀ D B`, internal force and stress.
//!
//! Element DOFs are ordered `[u1, v1, u2, v2, u3, v3]`.

use super::sum_of;

/// Strain–displacement matrix B (3×6) and area A of the triangle with corners `x`
/// (counter-clockwise):
///
/// `B = 1/(2A) [[y23, 0, y31, 0, y12, 0], [0, x32, 0, x13, 0, x21], [x32, y23, x13, y31, x21, y12]]`
/// with `xij = xi − xj`, `yij = yi − yj`.
pub fn b_matrix(x: &[[f64; 2]; 3]) -> ([[f64; 6]; 3], f64) {
    let [[x1, y1], [x2, y2], [x3, y3]] = *x;
    let two_a = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
    let s = 1.0 / two_a;
    let (y23, y31, y12) = ((y2 - y3) * s, (y3 - y1) * s, (y1 - y2) * s);
    let (x32, x13, x21) = ((x3 - x2) * s, (x1 - x3) * s, (x2 - x1) * s);
    (
        [
            [y23, 0.0, y31, 0.0, y12, 0.0],
            [0.0, x32, 0.0, x13, 0.0, x21],
            [x32, y23, x13, y31, x21, y12],
        ],
        0.5 * two_a,
    )
}

/// Element stiffness `K_e = t A Bᵀ D B` (6×6, symmetric).
pub fn stiffness(x: &[[f64; 2]; 3], d: &[[f64; 3]; 3], thickness: f64) -> [[f64; 6]; 6] {
    let (b, area) = b_matrix(x);
    let w = thickness * area;
    // DB (3×6)
    let mut db = [[0.0; 6]; 3];
    for i in 0..3 {
        for j in 0..6 {
            db[i][j] = sum_of(3, |k| d[i][k] * b[k][j]);
        }
    }
    let mut k = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in i..6 {
            let v = w * sum_of(3, |m| b[m][i] * db[m][j]);
            k[i][j] = v;
            k[j][i] = v;
        }
    }
    k
}

/// Stress `σ = D B u_e` (σxx, σyy, σxy), constant over the element.
pub fn stress(x: &[[f64; 2]; 3], d: &[[f64; 3]; 3], u: &[f64; 6]) -> [f64; 3] {
    let (b, _) = b_matrix(x);
    let eps: [f64; 3] = std::array::from_fn(|i| sum_of(6, |j| b[i][j] * u[j]));
    std::array::from_fn(|i| sum_of(3, |j| d[i][j] * eps[j]))
}

/// Element internal force `K_e u_e = t A Bᵀ (D (B u_e))`, without forming `K_e`
/// (a third of the multiplications).
pub fn internal_force(x: &[[f64; 2]; 3], d: &[[f64; 3]; 3], thickness: f64, u: &[f64; 6]) -> [f64; 6] {
    let (b, area) = b_matrix(x);
    let w = thickness * area;
    let eps: [f64; 3] = std::array::from_fn(|i| sum_of(6, |j| b[i][j] * u[j]));
    let sigma: [f64; 3] = std::array::from_fn(|i| w * sum_of(3, |j| d[i][j] * eps[j]));
    std::array::from_fn(|j| sum_of(3, |i| b[i][j] * sigma[i]))
}

/// Product of a 6×6 element matrix with a 6-vector: the element internal force `K_e u_e`.
pub fn mul(k: &[[f64; 6]; 6], u: &[f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| sum_of(6, |j| k[i][j] * u[j]))
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

    /// The stiffness of the unit right triangle (E = 1, ν = 0, t = 1, plane stress,
    /// D = diag(1, 1, ½)) equals the hand computation K = A Bᵀ D B, A = ½.
    #[test]
    fn stiffness_matches_hand_computation() {
        let d = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.5]];
        let k = stiffness(&UNIT, &d, 1.0);
        // Columns of B: (−1,0,−1), (0,−1,−1), (1,0,0), (0,0,1), (0,0,1), (0,1,0);
        // K_ij = ½ Σ_k D_kk B_ki B_kj.
        let hand = [
            [0.75, 0.25, -0.5, -0.25, -0.25, 0.0],
            [0.25, 0.75, 0.0, -0.25, -0.25, -0.5],
            [-0.5, 0.0, 0.5, 0.0, 0.0, 0.0],
            [-0.25, -0.25, 0.0, 0.25, 0.25, 0.0],
            [-0.25, -0.25, 0.0, 0.25, 0.25, 0.0],
            [0.0, -0.5, 0.0, 0.0, 0.0, 0.5],
        ];
        for i in 0..6 {
            for j in 0..6 {
                assert!((k[i][j] - hand[i][j]).abs() < 1e-15, "K[{i}][{j}]");
            }
        }
    }

    /// Rigid translations and an infinitesimal rotation store no energy: K u = 0.
    #[test]
    fn rigid_body_modes_have_zero_force() {
        let x = [[1.0, 2.0], [4.0, 2.5], [2.0, 5.0]];
        let d = crate::fem::Material::new(210000.0, 0.31, crate::fem::PlaneKind::Stress, 1.0, "p")
            .unwrap()
            .d_matrix();
        let k = stiffness(&x, &d, 2.0);
        let modes = [
            [1.0, 0.0, 1.0, 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 1.0, 0.0, 1.0],
            std::array::from_fn(|i| {
                if i % 2 == 0 {
                    -x[i / 2][1]
                } else {
                    x[i / 2][0]
                }
            }),
        ];
        for m in modes {
            assert!(mul(&k, &m).iter().all(|f| f.abs() < 1e-9 * 210000.0));
        }
    }

    /// A linear displacement field gives its exact constant strain: u = (a x, b y)
    /// gives σ = D (a, b, 0).
    #[test]
    fn linear_field_gives_exact_stress() {
        let x = [[1.0, 2.0], [4.0, 2.5], [2.0, 5.0]];
        let d = [[2.0, 0.5, 0.0], [0.5, 2.0, 0.0], [0.0, 0.0, 0.75]];
        let u: [f64; 6] = std::array::from_fn(|i| {
            let p = x[i / 2];
            if i % 2 == 0 {
                1e-3 * p[0]
            } else {
                -2e-3 * p[1]
            }
        });
        let s = stress(&x, &d, &u);
        assert!((s[0] - (2.0e-3 - 1.0e-3)).abs() < 1e-15);
        assert!((s[1] - (0.5e-3 - 4.0e-3)).abs() < 1e-15);
        assert!(s[2].abs() < 1e-15);
    }
}
