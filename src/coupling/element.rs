//! The coupling finite element (CFE) "T4": the host element's 3 nodes plus the
//! coupling node (SPEC §2, seed eqs. 3–16).
//!
//! Kinematics: `[[U]] = D₄ − Σᵢ N̄ᵢ(X_C) Dᵢ = B_e D_e`, `B_e = [−N̄₁I −N̄₂I −N̄₃I I]` (2×8).
//! Local frame: `R = [[n₁ n₂], [s₁ s₂]]`, s = n turned +90°, `[[u]] = R [[U]]`.
//! Law: `c = diag(c_n, c_s)`, `C = Rᵀ c R`; internal force `F_e = B_eᵀ Rᵀ f` and
//! stiffness `K_e = B_eᵀ (1 − D̂) C B_e` (8×8, symmetric).
//!
//! Element DOFs are ordered `[u₁ v₁ u₂ v₂ u₃ v₃ u₄ v₄]`: host nodes, then the
//! coupling node.

use super::law::{PairState, local_force};

/// One coupling pair: a coupling node of the node part and the host element that
/// contains it, with everything the CFE needs, computed once in the reference
/// configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingElement {
    /// The coupling node (index in the node part's mesh).
    pub node: usize,
    /// The host element (index in the host part's mesh).
    pub host_element: usize,
    /// The host element's nodes (indices in the host part's mesh).
    pub host_nodes: [usize; 3],
    /// Host shape functions at the coupling node, N̄ᵢ(X_C) (they sum to 1).
    pub shape: [f64; 3],
    /// Unit outward normal n of the host boundary at the coupling node.
    pub normal: [f64; 2],
    /// Reference position X_C of the coupling node.
    pub position: [f64; 2],
    /// Distance from the coupling node to the host edge it was projected on.
    pub distance: f64,
}

/// The rotation `R = [[n₁, n₂], [s₁, s₂]]` with `s = n` turned +90° (s = (−n₂, n₁)).
pub fn rotation(n: [f64; 2]) -> [[f64; 2]; 2] {
    [[n[0], n[1]], [-n[1], n[0]]]
}

/// The global jump `[[U]] = D₄ − Σ N̄ᵢ Dᵢ` for element displacements `d` (8 values).
pub fn jump(shape: &[f64; 3], d: &[f64; 8]) -> [f64; 2] {
    std::array::from_fn(|c| d[6 + c] - (0..3).map(|i| shape[i] * d[2 * i + c]).sum::<f64>())
}

/// The local jump `[[u]] = R [[U]] = ([[u_n]], [[u_s]])`.
pub fn local_jump(normal: [f64; 2], jump: [f64; 2]) -> [f64; 2] {
    let r = rotation(normal);
    [
        r[0][0] * jump[0] + r[0][1] * jump[1],
        r[1][0] * jump[0] + r[1][1] * jump[1],
    ]
}

/// The coefficients `b` of `B_e` per node: `B_e = [b₁I b₂I b₃I b₄I]` with
/// `b = (−N̄₁, −N̄₂, −N̄₃, 1)`.
fn b_coefficients(shape: &[f64; 3]) -> [f64; 4] {
    [-shape[0], -shape[1], -shape[2], 1.0]
}

/// CFE stiffness `K_e = B_eᵀ (1 − D̂) C B_e`, `C = Rᵀ c R` (8×8, symmetric, positive
/// semidefinite). Since `B_e = b ⊗ I`, `K_e[2a+i][2b+j] = (1 − D̂) b_a b_b C_ij`.
pub fn stiffness(
    shape: &[f64; 3],
    normal: [f64; 2],
    c_n: f64,
    c_s: f64,
    state: PairState,
) -> [[f64; 8]; 8] {
    let r = rotation(normal);
    let k = 1.0 - state.d_hat();
    let c: [[f64; 2]; 2] = std::array::from_fn(|i| {
        std::array::from_fn(|j| k * (c_n * r[0][i] * r[0][j] + c_s * r[1][i] * r[1][j]))
    });
    let b = b_coefficients(shape);
    std::array::from_fn(|p| std::array::from_fn(|q| b[p / 2] * b[q / 2] * c[p % 2][q % 2]))
}

/// CFE internal force `F_e = B_eᵀ Rᵀ f` with `f = (1 − D̂) c [[u]]`, for element
/// displacements `d`. Also returns the local force `f` (the force the host side
/// exerts on the pair, in (n, s)).
pub fn internal_force(
    shape: &[f64; 3],
    normal: [f64; 2],
    c_n: f64,
    c_s: f64,
    state: PairState,
    d: &[f64; 8],
) -> ([f64; 8], [f64; 2]) {
    let u = local_jump(normal, jump(shape, d));
    let f = local_force(state, c_n, c_s, u);
    let r = rotation(normal);
    let g = [
        r[0][0] * f[0] + r[1][0] * f[1],
        r[0][1] * f[0] + r[1][1] * f[1],
    ];
    let b = b_coefficients(shape);
    (std::array::from_fn(|p| b[p / 2] * g[p % 2]), f)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHAPE: [f64; 3] = [0.3, 0.7, 0.0];
    fn normal() -> [f64; 2] {
        let a: f64 = 0.4;
        [a.cos(), a.sin()]
    }

    /// K_e is symmetric and positive semidefinite (xᵀKx ≥ 0 for many x), and an
    /// open pair has zero stiffness.
    #[test]
    fn stiffness_symmetric_psd() {
        let k = stiffness(&SHAPE, normal(), 1e9, 5e8, PairState::Bonded);
        for (i, row) in k.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                assert_eq!(*v, k[j][i], "K[{i}][{j}] != K[{j}][{i}]");
            }
        }
        let mut seed = 12345u64;
        for _ in 0..200 {
            let x: [f64; 8] = std::array::from_fn(|_| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            });
            let e: f64 = (0..8)
                .map(|i| (0..8).map(|j| x[i] * k[i][j] * x[j]).sum::<f64>())
                .sum();
            assert!(e >= -1e-6);
        }
        let open = stiffness(&SHAPE, normal(), 1e9, 5e8, PairState::Open);
        assert!(open.iter().flatten().all(|&v| v == 0.0));
    }

    /// A rigid translation and an infinitesimal rigid rotation of host and coupling
    /// node together produce no jump and no energy: K_e d = 0 (coupling node on the
    /// host edge, X_C = Σ N̄ᵢ Xᵢ).
    #[test]
    fn rigid_body_motion_has_zero_energy() {
        let x = [[0.0, 0.0], [10.0, 1.0], [3.0, 8.0]];
        let xc = [
            SHAPE.iter().zip(&x).map(|(n, p)| n * p[0]).sum::<f64>(),
            SHAPE.iter().zip(&x).map(|(n, p)| n * p[1]).sum::<f64>(),
        ];
        let pts = [x[0], x[1], x[2], xc];
        let k = stiffness(&SHAPE, normal(), 1e9, 1e9, PairState::Bonded);
        let modes: [[f64; 8]; 3] = [
            std::array::from_fn(|i| if i % 2 == 0 { 1.0 } else { 0.0 }),
            std::array::from_fn(|i| if i % 2 == 1 { 1.0 } else { 0.0 }),
            std::array::from_fn(|i| {
                if i % 2 == 0 {
                    -pts[i / 2][1]
                } else {
                    pts[i / 2][0]
                }
            }),
        ];
        for d in modes {
            assert!(jump(&SHAPE, &d).iter().all(|v| v.abs() < 1e-12));
            let kd: Vec<f64> = (0..8)
                .map(|i| (0..8).map(|j| k[i][j] * d[j]).sum())
                .collect();
            assert!(kd.iter().all(|v| v.abs() < 1e-9 * 1e9), "{kd:?}");
        }
    }

    /// The internal force equals K_e d for a bonded pair (the law is linear there),
    /// and its node-by-node sum vanishes (the CFE is self-equilibrated).
    #[test]
    fn internal_force_is_k_times_d_and_balanced() {
        let d = [0.1, -0.2, 0.05, 0.3, -0.1, 0.0, 0.7, -0.4];
        let k = stiffness(&SHAPE, normal(), 2.0, 3.0, PairState::Bonded);
        let (f, _) = internal_force(&SHAPE, normal(), 2.0, 3.0, PairState::Bonded, &d);
        for i in 0..8 {
            let kd: f64 = (0..8).map(|j| k[i][j] * d[j]).sum();
            assert!((kd - f[i]).abs() < 1e-12);
        }
        assert!((f[0] + f[2] + f[4] + f[6]).abs() < 1e-12);
        assert!((f[1] + f[3] + f[5] + f[7]).abs() < 1e-12);
    }

    /// The local frame: a coupling node pushed along −n has [[u_n]] < 0 and
    /// [[u_s]] = 0; pushed along s, [[u_s]] equals the push.
    #[test]
    fn local_jump_components() {
        let n = normal();
        let s = [-n[1], n[0]];
        let u = local_jump(n, [-2.0 * n[0], -2.0 * n[1]]);
        assert!((u[0] + 2.0).abs() < 1e-15 && u[1].abs() < 1e-15);
        let u = local_jump(n, [0.5 * s[0], 0.5 * s[1]]);
        assert!(u[0].abs() < 1e-15 && (u[1] - 0.5).abs() < 1e-15);
    }
}
