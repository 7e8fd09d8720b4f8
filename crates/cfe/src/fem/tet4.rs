//! The linear tetrahedron TET4 (constant strain) for 3D elasticity: shape
//! functions, Jacobian and volume, strain–displacement matrix, stiffness (exact,
//! one point), internal force, stress, and the natural coordinates of a point.
//!
//! Local numbering as Gmsh's 4-node tetrahedron and VTK_TETRA; the natural
//! coordinates (ξ, η, ζ) of the corners are 0 (0,0,0), 1 (1,0,0), 2 (0,1,0),
//! 3 (0,0,1):
//!
//! ```text
//!              3  ζ
//!              │╲
//!              │ ╲
//!              │  ╲
//!              │   ╲
//!              0────2  η         positive volume when
//!             ╱   ╱             (x₁ − x₀) × (x₂ − x₀) · (x₃ − x₀) > 0
//!            ╱ ╱                (3 on the side of face 0-1-2 that
//!           1   ξ                0 → 1 → 2 turns counter-clockwise about)
//! ```
//!
//! Outward faces (right-hand rule): 0-2-1, 0-1-3, 1-2-3, 0-3-2.
//!
//! - Shape functions (barycentric): `N₀ = 1 − ξ − η − ζ`, `N₁ = ξ`, `N₂ = η`, `N₃ = ζ`.
//! - Jacobian `J = [x₁ − x₀; x₂ − x₀; x₃ − x₀]` (rows), constant; `det J = 6 V`.
//! - `∇N_i = J⁻¹ ∂N_i/∂ξ`, B (6×12) from them in the Voigt order
//!   `[xx, yy, zz, xy, yz, zx]` with engineering shears ([`super::solid`]).
//! - Stiffness `K_e = V Bᵀ D B` (B constant: the one-point rule is exact); stress
//!   `σ = D B u_e`, constant over the element.
//! - Natural coordinates of a point p in closed form: `Jᵀ ξ = p − x₀` (Cramer's rule).
//!
//! Element DOFs are ordered `[u₀, v₀, w₀, u₁, v₁, w₁, …]`.
//!
//! ```
//! use cfe::fem::{material::d_solid, tet4};
//! // The unit corner tetrahedron: ∇N₀ = (−1, −1, −1), V = 1/6, so
//! // K(u₀, u₀) = V (λ + 2G + G + G) = (λ + 4G)/6 and K(u₀, v₀) = V (λ + G).
//! let (e, nu) = (210000.0, 0.3);
//! let k = tet4::stiffness(&tet4::CORNERS, &d_solid(e, nu));
//! let (lambda, g) = (e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)));
//! assert!((k[0][0] - (lambda + 4.0 * g) / 6.0).abs() < 1e-9);
//! assert!((k[0][1] - (lambda + g) / 6.0).abs() < 1e-9);
//! assert_eq!(tet4::check(&tet4::CORNERS), Ok(1.0 / 6.0));
//! // The centroid's natural coordinates, from its physical position.
//! let xi = tet4::natural_coordinates(&tet4::CORNERS, [0.25; 3]).unwrap();
//! assert!(xi.iter().all(|v| (v - 0.25).abs() < 1e-15));
//! ```

use super::solid::{self, NonPositiveJacobian, SolidStress};

/// The natural coordinates of the four corners.
pub const CORNERS: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// The centroid in natural coordinates, the one integration point.
pub const CENTROID: [f64; 3] = [0.25, 0.25, 0.25];

/// Shape functions `[1 − ξ − η − ζ, ξ, η, ζ]` at `xi = (ξ, η, ζ)` (the barycentric
/// coordinates of the point).
pub fn shape(xi: [f64; 3]) -> [f64; 4] {
    [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]]
}

/// Natural derivatives `dn[a][i] = ∂N_i/∂ξ_a` (constant).
pub fn shape_derivatives() -> [[f64; 4]; 3] {
    [
        [-1.0, 1.0, 0.0, 0.0],
        [-1.0, 0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0, 1.0],
    ]
}

/// Jacobian `J = [x₁ − x₀; x₂ − x₀; x₃ − x₀]` (rows ∂x/∂ξ, ∂x/∂η, ∂x/∂ζ).
pub fn jacobian(x: &[[f64; 3]; 4]) -> [[f64; 3]; 3] {
    solid::jacobian(x, &shape_derivatives())
}

/// Signed volume `det J / 6 = (x₁ − x₀) × (x₂ − x₀) · (x₃ − x₀) / 6`: positive in the
/// Gmsh/VTK orientation.
pub fn volume(x: &[[f64; 3]; 4]) -> f64 {
    solid::det3(&jacobian(x)) / 6.0
}

/// The volume if det J is positive beyond round-off (det J > [`solid::FLAT`] × ℓ³,
/// ℓ the longest edge); otherwise the value reporting it (at the centroid: J is
/// constant), for the mesh validation to name the element.
pub fn check(x: &[[f64; 3]; 4]) -> Result<f64, NonPositiveJacobian> {
    let det = solid::det3(&jacobian(x));
    if solid::is_positive(det, longest_edge(x)) {
        Ok(det / 6.0)
    } else {
        Err(NonPositiveJacobian { at: CENTROID, det })
    }
}

/// The longest of the six edges.
fn longest_edge(x: &[[f64; 3]; 4]) -> f64 {
    let mut l = 0.0_f64;
    for a in 0..4 {
        for b in a + 1..4 {
            l = l.max((x[b][0] - x[a][0]).hypot(x[b][1] - x[a][1]).hypot(x[b][2] - x[a][2]));
        }
    }
    l
}

/// Strain–displacement matrix B (6×12) and the signed volume V. Non-finite entries
/// when V = 0 ([`check`] first).
pub fn b_matrix(x: &[[f64; 3]; 4]) -> ([[f64; 12]; 6], f64) {
    let (g, det) = solid::gradients(&jacobian(x), &shape_derivatives());
    (solid::b_matrix(&g), det / 6.0)
}

/// Element stiffness `K_e = V Bᵀ D B` (12×12, exactly symmetric).
pub fn stiffness(x: &[[f64; 3]; 4], d: &[[f64; 6]; 6]) -> [[f64; 12]; 12] {
    let (b, v) = b_matrix(x);
    let mut k = [[0.0; 12]; 12];
    solid::add_btdb(&mut k, &b, d, v);
    solid::mirror(&k)
}

/// Element internal force `K_e u_e = V Bᵀ (D (B u_e))`, without forming `K_e`.
pub fn internal_force(x: &[[f64; 3]; 4], d: &[[f64; 6]; 6], u: &[f64; 12]) -> [f64; 12] {
    let (b, v) = b_matrix(x);
    let s = solid::mul6(d, &solid::strain(&b, u)).map(|c| v * c);
    let mut f = [0.0; 12];
    solid::add_bt_sigma(&mut f, &b, &s);
    f
}

/// Stress `σ = D B u_e` (Voigt order `[xx, yy, zz, xy, yz, zx]`), constant over the
/// element.
pub fn stress(x: &[[f64; 3]; 4], d: &[[f64; 6]; 6], u: &[f64; 12]) -> [f64; 6] {
    let (b, _) = b_matrix(x);
    solid::mul6(d, &solid::strain(&b, u))
}

/// The element's stresses for recovery: the constant stress as the element value and
/// at each corner.
pub fn stresses(x: &[[f64; 3]; 4], d: &[[f64; 6]; 6], u: &[f64; 12]) -> SolidStress<4> {
    let s = stress(x, d, u);
    SolidStress {
        element: s,
        corners: [s; 4],
    }
}

/// Natural coordinates (ξ, η, ζ) of the point `p`: the solution of
/// `Jᵀ ξ = p − x₀` by Cramer's rule, `ξ_a = det(J with row a replaced by p − x₀) /
/// det J`; `shape` of them are p's barycentric coordinates. Exact for any p (outside
/// the element some are negative, see [`is_inside`]). `None` when the element is
/// degenerate: `|det J| ≤` [`solid::FLAT`] `× ℓ³`, ℓ its longest edge, or not finite.
pub fn natural_coordinates(x: &[[f64; 3]; 4], p: [f64; 3]) -> Option<[f64; 3]> {
    let j = jacobian(x);
    let det = solid::det3(&j);
    if !solid::is_positive(det.abs(), longest_edge(x)) {
        return None;
    }
    let r = [p[0] - x[0][0], p[1] - x[0][1], p[2] - x[0][2]];
    let xi: [f64; 3] = std::array::from_fn(|a| {
        let mut m = j;
        m[a] = r;
        solid::det3(&m) / det
    });
    xi.iter().all(|v| v.is_finite()).then_some(xi)
}

/// Whether natural coordinates `xi` lie in the element within `tol`: every
/// barycentric coordinate ≥ −tol.
pub fn is_inside(xi: [f64; 3], tol: f64) -> bool {
    shape(xi).iter().all(|&n| n >= -tol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::face3;
    use crate::fem::material::d_solid;
    use crate::fem::solid::testing::*;

    /// A distorted tetrahedron in the Gmsh/VTK orientation.
    const TET: [[f64; 3]; 4] = [
        [0.2, -0.1, 0.3],
        [2.1, 0.4, -0.2],
        [0.5, 1.8, 0.1],
        [0.7, 0.6, 1.9],
    ];

    /// Outward faces of the local numbering.
    const FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];

    fn steel() -> [[f64; 6]; 6] {
        d_solid(210000.0, 0.3)
    }

    /// The shape functions sum to one everywhere, are 1 at their own corner and 0 at
    /// the others, and their derivatives are the finite differences of them.
    #[test]
    fn partition_of_unity_kronecker_and_derivatives() {
        for (i, &c) in CORNERS.iter().enumerate() {
            let n = shape(c);
            for (k, v) in n.iter().enumerate() {
                assert_eq!(*v, if k == i { 1.0 } else { 0.0 });
            }
        }
        let dn = shape_derivatives();
        let h = 1e-6;
        for xi in [[0.1, 0.2, 0.3], [0.6, -0.2, 0.9], CENTROID] {
            assert!((shape(xi).iter().sum::<f64>() - 1.0).abs() < 1e-15);
            for a in 0..3 {
                let (mut p, mut m) = (xi, xi);
                p[a] += h;
                m[a] -= h;
                let (np, nm) = (shape(p), shape(m));
                for i in 0..4 {
                    assert!((dn[a][i] - (np[i] - nm[i]) / (2.0 * h)).abs() < 1e-9);
                }
            }
        }
    }

    /// The volume is the triple product over 6 (1/6 for the unit corner tetrahedron);
    /// swapping two corners inverts it and `check` reports the negative det J as a
    /// value, a flat one reports zero.
    #[test]
    fn volume_orientation_and_check() {
        assert!((volume(&CORNERS) - 1.0 / 6.0).abs() < 1e-16);
        let v = check(&TET).unwrap();
        let e = |k: usize| [TET[k][0] - TET[0][0], TET[k][1] - TET[0][1], TET[k][2] - TET[0][2]];
        let (a, b, c) = (e(1), e(2), e(3));
        let triple = (a[1] * b[2] - a[2] * b[1]) * c[0]
            + (a[2] * b[0] - a[0] * b[2]) * c[1]
            + (a[0] * b[1] - a[1] * b[0]) * c[2];
        assert!((v - triple / 6.0).abs() < 1e-15);
        let inverted = [TET[0], TET[2], TET[1], TET[3]];
        let err = check(&inverted).unwrap_err();
        assert!((err.det + triple).abs() < 1e-14 && err.to_string().contains("not positive"));
        // Corner 3 at the mean of the first three: in their plane.
        let mean = std::array::from_fn(|k| (TET[0][k] + TET[1][k] + TET[2][k]) / 3.0);
        let flat = [TET[0], TET[1], TET[2], mean];
        assert!(check(&flat).unwrap_err().det.abs() < 1e-14);
    }

    /// K is exactly symmetric, the six rigid-body modes give zero force, and K has
    /// exactly six zero eigenvalues, the other six positive (faer's eigensolver).
    #[test]
    fn stiffness_symmetric_psd_with_six_rigid_modes() {
        let k = stiffness(&TET, &steel());
        let kmax = max_abs(k.iter().flatten().copied());
        assert!(is_exactly_symmetric(&k));
        for m in rigid_modes::<4, 12>(&TET) {
            let f = solid::mul(&k, &m);
            assert!(max_abs(f) < 1e-12 * kmax * max_abs(m), "{f:?}");
        }
        let ev = eigenvalues(&k);
        assert!(ev[..6].iter().all(|l| l.abs() < 1e-12 * kmax), "{ev:?}");
        assert!(ev[6..].iter().all(|&l| l > 1e-3 * kmax), "{ev:?}");
    }

    /// Patch test: a linear displacement field gives the exact constant stress D ε,
    /// and K u equals the consistent nodal forces of the tractions σ n on the four
    /// faces (face3's triangle pressure forces carry ∫ N_i n dA).
    #[test]
    fn linear_field_gives_exact_stress_and_boundary_forces() {
        let d = steel();
        let g = [[1e-3, 2e-3, -5e-4], [-1e-3, 3e-4, 7e-4], [2e-4, -6e-4, -8e-4]];
        let u: [f64; 12] = linear_field(&TET, [0.1, -0.2, 0.05], g);
        let exact = solid::mul6(&d, &strain_of_gradient(g));
        let s = stress(&TET, &d, &u);
        let scale = max_abs(exact);
        assert!((0..6).all(|c| (s[c] - exact[c]).abs() < 1e-12 * scale), "{s:?}");
        assert_eq!(stresses(&TET, &d, &u).corners, [s; 4]);
        let t = [
            [exact[0], exact[3], exact[5]],
            [exact[3], exact[1], exact[4]],
            [exact[5], exact[4], exact[2]],
        ];
        let mut boundary = [0.0; 12];
        for face in FACES {
            // −(pressure forces of p = 1) = ∫ N_i n dA; traction σ n.
            let w = face3::triangle_pressure_forces(&face.map(|i| TET[i]), -1.0);
            for (k, &node) in face.iter().enumerate() {
                for r in 0..3 {
                    boundary[3 * node + r] += (0..3).map(|c| t[r][c] * w[k][c]).sum::<f64>();
                }
            }
        }
        let f = internal_force(&TET, &d, &u);
        let fk = solid::mul(&stiffness(&TET, &d), &u);
        let fmax = max_abs(boundary);
        for i in 0..12 {
            assert!((f[i] - boundary[i]).abs() < 1e-12 * fmax, "{i}: {f:?} vs {boundary:?}");
            assert!((fk[i] - boundary[i]).abs() < 1e-12 * fmax, "{i}");
        }
    }

    /// Uniaxial stress: the corner tetrahedron (a, b, c) held by symmetry on its three
    /// coordinate faces and pulled by σ on its slanted face stretches by σ a / E and
    /// contracts by ν σ b / E and ν σ c / E (Poisson), exactly.
    #[test]
    fn uniaxial_stress_gives_poisson_contraction() {
        let (a, b, c, e, nu, sigma) = (2.0, 1.5, 0.8, 1000.0, 0.3, 5.0);
        let x = [[0.0; 3], [a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
        let k = stiffness(&x, &d_solid(e, nu));
        let slanted = [x[1], x[2], x[3]];
        let n = face3::triangle_normal(&slanted).unwrap();
        let f = face3::triangle_traction_forces(&slanted, [sigma * n[0], 0.0, 0.0]);
        // Free: u of node 1, v of node 2, w of node 3.
        let free = [3, 7, 11];
        let kk = free.iter().map(|&i| free.iter().map(|&j| k[i][j]).collect()).collect();
        let rhs = vec![f[0][0], f[1][1], f[2][2]];
        let sol = solve(kk, rhs);
        let want = [sigma * a / e, -nu * sigma * b / e, -nu * sigma * c / e];
        for i in 0..3 {
            assert!((sol[i] - want[i]).abs() < 1e-14, "{sol:?} vs {want:?}");
        }
    }

    /// The internal force is the gradient of the strain energy ½ V εᵀ D ε: central
    /// differences of the energy match K u (the energy is quadratic, so to round-off).
    #[test]
    fn internal_force_is_the_energy_gradient() {
        let d = steel();
        let energy = |u: &[f64; 12]| {
            let (b, v) = b_matrix(&TET);
            let eps = solid::strain(&b, u);
            let s = solid::mul6(&d, &eps);
            0.5 * v * (0..6).map(|i| eps[i] * s[i]).sum::<f64>()
        };
        let u: [f64; 12] = std::array::from_fn(|i| 1e-3 * (1.3 + i as f64).sin());
        let f = internal_force(&TET, &d, &u);
        let h = 1e-7;
        for i in 0..12 {
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
        let k = stiffness(&TET, &d);
        let kr = stiffness(&TET.map(|p| rotate(&r, p)), &d);
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

    /// The closed-form natural coordinates invert x(ξ) = Σ N_i(ξ) x_i inside, on a
    /// face and outside; `is_inside` tells them apart; a flat element gives None.
    #[test]
    fn natural_coordinates_round_trip() {
        for xi in [[0.2, 0.3, 0.1], [0.0, 0.5, 0.5], [0.7, 0.4, 0.3], [-0.1, 0.2, 0.2]] {
            let n = shape(xi);
            let p: [f64; 3] = std::array::from_fn(|c| (0..4).map(|i| n[i] * TET[i][c]).sum());
            let back = natural_coordinates(&TET, p).unwrap();
            assert!((0..3).all(|a| (back[a] - xi[a]).abs() < 1e-14), "{back:?} vs {xi:?}");
            assert_eq!(is_inside(back, 1e-12), n.iter().all(|&v| v >= 0.0));
        }
        // Corner 3 on the line through corners 0 and 1.
        let beyond = std::array::from_fn(|k| 2.0 * TET[1][k] - TET[0][k]);
        let flat = [TET[0], TET[1], TET[2], beyond];
        assert_eq!(natural_coordinates(&flat, [0.0; 3]), None);
    }
}
