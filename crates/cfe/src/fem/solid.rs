//! What the 3D solid elements ([`super::tet4`], [`super::hex8`]) share: the Voigt
//! order of 3D stresses and strains, the strain–displacement rows of a node from
//! its gradient, the 3×3 Jacobian's determinant and the node gradients through
//! it, the products `Bᵀ D B` and `Bᵀ σ` summed point by point, and the report of a
//! non-positive Jacobian.
//!
//! **Voigt order** (every 3D routine, and ParaView's order of a symmetric tensor's
//! six components): `[xx, yy, zz, xy, yz, zx]`, strains with the engineering shears
//!
//! ```text
//!   ε = [∂u/∂x, ∂v/∂y, ∂w/∂z, ∂u/∂y + ∂v/∂x, ∂v/∂z + ∂w/∂y, ∂w/∂x + ∂u/∂z]
//! ```
//!
//! CalculiX and Abaqus print S11, S22, S33, S12, S13, S23: their last two are this
//! order's last two swapped (S13 = σzx is our 6th component, S23 = σyz our 5th).
//!
//! **B** (6 × 3n) of an element of n nodes, node a's columns `3a, 3a+1, 3a+2`
//! from its gradient `∇N_a = (g_x, g_y, g_z)`:
//!
//! ```text
//!   B_a = [[g_x, 0,   0  ],
//!          [0,   g_y, 0  ],
//!          [0,   0,   g_z],
//!          [g_y, g_x, 0  ],
//!          [0,   g_z, g_y],
//!          [g_z, 0,   g_x]]
//! ```
//!
//! **Jacobian** of the map from natural coordinates ξ = (ξ, η, ζ):
//! `J_ab = ∂x_b/∂ξ_a = Σ_i ∂N_i/∂ξ_a x_ib` (rows natural, columns physical, as
//! [`super::q4::jacobian`]), so `∇N_i = J⁻¹ ∂N_i/∂ξ` and `dV = det J dξ dη dζ`.

use std::fmt;

/// Relative size below which a Jacobian determinant counts as zero: an element of
/// size ℓ with det J ≤ `FLAT` × ℓ³ is flat to round-off.
pub const FLAT: f64 = 1e-12;

/// Whether the Jacobian determinant `det` of an element of size ℓ = `size` is
/// positive beyond round-off: finite and > [`FLAT`] × ℓ³.
pub fn is_positive(det: f64, size: f64) -> bool {
    det.is_finite() && det > FLAT * size * size * size
}

/// Names of the six Voigt components, in the order of every 3D stress and strain.
pub const VOIGT: [&str; 6] = ["xx", "yy", "zz", "xy", "yz", "zx"];

/// An element whose Jacobian determinant is not positive at a natural point
/// (inverted, degenerate or non-finite): the value the mesh validation reports,
/// naming the element, instead of a stiffness computed from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NonPositiveJacobian {
    /// The natural coordinates (ξ, η, ζ) of the point checked.
    pub at: [f64; 3],
    /// det J there (≤ 0 or NaN).
    pub det: f64,
}

impl fmt::Display for NonPositiveJacobian {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the Jacobian determinant is {:e} (not positive) at natural point ({}, {}, {}): \
             the element is inverted (node order) or degenerate",
            self.det, self.at[0], self.at[1], self.at[2]
        )
    }
}

/// The stresses of one 3D element: a representative element value and the values
/// it gives its `N` corner nodes (the 3D counterpart of
/// [`super::element::ElementStress`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidStress<const N: usize> {
    /// The element's stress (Voigt order [`VOIGT`]): constant in a TET4, the mean of
    /// the Gauss-point stresses in a HEX8.
    pub element: [f64; 6],
    /// The stress at each corner: the constant in a TET4, the Gauss-point field
    /// extrapolated to the corners in a HEX8.
    pub corners: [[f64; 6]; N],
}

/// `det A` of a 3×3 matrix by the rule of Sarrus (cofactors of the first row).
pub fn det3(a: &[[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// The physical gradients `∇N_i = J⁻¹ ∂N_i/∂ξ` of `N` shape functions with natural
/// derivatives `dn` (`dn[a][i] = ∂N_i/∂ξ_a`) through the Jacobian `j`, and det J.
/// `J⁻¹ = adj(J) / det J`; non-finite gradients when det J = 0 (the caller checks
/// det J first, e.g. with the element's `check`).
pub fn gradients<const N: usize>(j: &[[f64; 3]; 3], dn: &[[f64; N]; 3]) -> ([[f64; 3]; N], f64) {
    let det = det3(j);
    let s = 1.0 / det;
    // inv[r][c] = cofactor(c, r) / det.
    let cof = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        j[r1][c1] * j[r2][c2] - j[r1][c2] * j[r2][c1]
    };
    let inv: [[f64; 3]; 3] = std::array::from_fn(|r| std::array::from_fn(|c| s * cof(c, r)));
    let g = std::array::from_fn(|i| {
        std::array::from_fn(|r| (0..3).map(|a| inv[r][a] * dn[a][i]).sum())
    });
    (g, det)
}

/// The Jacobian `J_ab = Σ_i dn[a][i] x[i][b]` of `N` nodes at `x` with natural
/// derivatives `dn`.
pub fn jacobian<const N: usize>(x: &[[f64; 3]; N], dn: &[[f64; N]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|a| std::array::from_fn(|b| (0..N).map(|i| dn[a][i] * x[i][b]).sum()))
}

/// B (6 × DOFS, DOFS = 3N) from the node gradients `g` (module doc's `B_a` per node).
pub fn b_matrix<const N: usize, const DOFS: usize>(g: &[[f64; 3]; N]) -> [[f64; DOFS]; 6] {
    const { assert!(DOFS == 3 * N) };
    let mut b = [[0.0; DOFS]; 6];
    for (a, &[gx, gy, gz]) in g.iter().enumerate() {
        let c = 3 * a;
        b[0][c] = gx;
        b[1][c + 1] = gy;
        b[2][c + 2] = gz;
        b[3][c] = gy;
        b[3][c + 1] = gx;
        b[4][c + 1] = gz;
        b[4][c + 2] = gy;
        b[5][c] = gz;
        b[5][c + 2] = gx;
    }
    b
}

/// The strain `ε = B u` (Voigt order, engineering shears).
pub fn strain<const DOFS: usize>(b: &[[f64; DOFS]; 6], u: &[f64; DOFS]) -> [f64; 6] {
    std::array::from_fn(|i| (0..DOFS).map(|j| b[i][j] * u[j]).sum())
}

/// `D v` for the 6×6 `d`.
pub fn mul6(d: &[[f64; 6]; 6], v: &[f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| (0..6).map(|j| d[i][j] * v[j]).sum())
}

/// Adds `w Bᵀ D B` to the upper triangle (j ≥ i) of `k`.
pub fn add_btdb<const DOFS: usize>(
    k: &mut [[f64; DOFS]; DOFS],
    b: &[[f64; DOFS]; 6],
    d: &[[f64; 6]; 6],
    w: f64,
) {
    let db: [[f64; DOFS]; 6] =
        std::array::from_fn(|i| std::array::from_fn(|j| (0..6).map(|m| d[i][m] * b[m][j]).sum()));
    for (i, row) in k.iter_mut().enumerate() {
        for (j, kij) in row.iter_mut().enumerate().skip(i) {
            *kij += w * (0..6).map(|m| b[m][i] * db[m][j]).sum::<f64>();
        }
    }
}

/// The symmetric matrix whose upper triangle is `k`'s (so K is exactly symmetric).
pub fn mirror<const DOFS: usize>(k: &[[f64; DOFS]; DOFS]) -> [[f64; DOFS]; DOFS] {
    std::array::from_fn(|i| std::array::from_fn(|j| k[i.min(j)][i.max(j)]))
}

/// Adds `Bᵀ s` to `f` (s a stress already multiplied by the point's weight).
pub fn add_bt_sigma<const DOFS: usize>(f: &mut [f64; DOFS], b: &[[f64; DOFS]; 6], s: &[f64; 6]) {
    for (j, fj) in f.iter_mut().enumerate() {
        *fj += (0..6).map(|i| b[i][j] * s[i]).sum::<f64>();
    }
}

/// `K u` of a square element matrix.
pub fn mul<const DOFS: usize>(k: &[[f64; DOFS]; DOFS], u: &[f64; DOFS]) -> [f64; DOFS] {
    std::array::from_fn(|i| (0..DOFS).map(|j| k[i][j] * u[j]).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradients through J are J⁻¹ ∂N/∂ξ: for a J of known inverse (a scaled,
    /// sheared map) J · ∇N gives back ∂N/∂ξ, and det J is the triple product.
    #[test]
    fn gradients_invert_the_jacobian() {
        let j = [[2.0, 0.3, -0.1], [0.4, 1.5, 0.2], [-0.3, 0.1, 0.8]];
        let dn = [[1.0, -0.5, 0.25], [0.0, 2.0, -1.0], [3.0, 0.5, 0.75]];
        let (g, det) = gradients(&j, &dn);
        let triple = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
            - j[1][0] * (j[0][1] * j[2][2] - j[0][2] * j[2][1])
            + j[2][0] * (j[0][1] * j[1][2] - j[0][2] * j[1][1]);
        assert!((det - triple).abs() < 1e-14);
        for i in 0..3 {
            for a in 0..3 {
                let back: f64 = (0..3).map(|r| j[a][r] * g[i][r]).sum();
                assert!((back - dn[a][i]).abs() < 1e-14, "{i} {a}");
            }
        }
    }

    /// B u of a node moved by u = (1, 2, 3) · (x-gradient of N) gives the Voigt
    /// strains of the displacement gradient, engineering shears in [xy, yz, zx].
    #[test]
    fn b_rows_follow_the_voigt_order() {
        // One "node" with gradient g: ε_ij from u_i g_j.
        let g = [[0.5, -1.0, 2.0]];
        let b: [[f64; 3]; 6] = b_matrix(&g);
        let u = [1.0, 2.0, 3.0];
        let e = strain(&b, &u);
        let grad = |i: usize, j: usize| u[i] * g[0][j];
        let want = [
            grad(0, 0),
            grad(1, 1),
            grad(2, 2),
            grad(0, 1) + grad(1, 0),
            grad(1, 2) + grad(2, 1),
            grad(2, 0) + grad(0, 2),
        ];
        assert_eq!(e, want);
        assert_eq!(VOIGT[4], "yz");
    }
}

/// Shared tools of the 3D element tests: fields, rigid modes, eigenvalues, a small
/// dense solver, rotations.
#[cfg(test)]
pub(crate) mod testing {
    /// Nodal displacements of the linear field `u(p) = c + G p` at the nodes `x`.
    pub fn linear_field<const N: usize, const DOFS: usize>(
        x: &[[f64; 3]; N],
        c: [f64; 3],
        g: [[f64; 3]; 3],
    ) -> [f64; DOFS] {
        std::array::from_fn(|k| {
            let (a, i) = (k / 3, k % 3);
            c[i] + (0..3).map(|j| g[i][j] * x[a][j]).sum::<f64>()
        })
    }

    /// The Voigt strain of the displacement gradient `g` (engineering shears).
    pub fn strain_of_gradient(g: [[f64; 3]; 3]) -> [f64; 6] {
        [
            g[0][0],
            g[1][1],
            g[2][2],
            g[0][1] + g[1][0],
            g[1][2] + g[2][1],
            g[2][0] + g[0][2],
        ]
    }

    /// The six rigid-body modes at nodes `x`: three translations and the three
    /// infinitesimal rotations `ω × p`.
    pub fn rigid_modes<const N: usize, const DOFS: usize>(x: &[[f64; 3]; N]) -> [[f64; DOFS]; 6] {
        std::array::from_fn(|m| {
            if m < 3 {
                let mut c = [0.0; 3];
                c[m] = 1.0;
                linear_field(x, c, [[0.0; 3]; 3])
            } else {
                // ω = e_k: u = ω × p, gradient W with W_ij = −ε_ijk.
                let k = m - 3;
                let mut w = [[0.0; 3]; 3];
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                w[i][j] = -1.0;
                w[j][i] = 1.0;
                linear_field(x, [0.0; 3], w)
            }
        })
    }

    /// Whether `k` equals its transpose bit for bit.
    pub fn is_exactly_symmetric<const D: usize>(k: &[[f64; D]; D]) -> bool {
        k.iter().enumerate().all(|(i, row)| {
            row.iter()
                .enumerate()
                .all(|(j, v)| v.to_bits() == k[j][i].to_bits())
        })
    }

    /// The eigenvalues of the symmetric `k`, ascending (faer's self-adjoint solver).
    pub fn eigenvalues<const DOFS: usize>(k: &[[f64; DOFS]; DOFS]) -> Vec<f64> {
        let m = faer::Mat::<f64>::from_fn(DOFS, DOFS, |i, j| k[i][j]);
        m.self_adjoint_eigenvalues(faer::Side::Lower).unwrap()
    }

    /// Solves the small dense system `a x = b` by Gaussian elimination with partial
    /// pivoting.
    pub fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for c in 0..n {
            let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
            a.swap(c, p);
            b.swap(c, p);
            for r in c + 1..n {
                let f = a[r][c] / a[c][c];
                let pivot = a[c].clone();
                for (ark, ack) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                    *ark -= f * ack;
                }
                b[r] -= f * b[c];
            }
        }
        let mut x = vec![0.0; n];
        for r in (0..n).rev() {
            x[r] = (b[r] - (r + 1..n).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
        }
        x
    }

    /// The rotation by `angle` about the unit `axis` (Rodrigues).
    pub fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
        let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let k = axis.map(|v| v / n);
        let (s, c) = angle.sin_cos();
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let cross = match (i, j) {
                    (0, 1) => -k[2],
                    (0, 2) => k[1],
                    (1, 0) => k[2],
                    (1, 2) => -k[0],
                    (2, 0) => -k[1],
                    (2, 1) => k[0],
                    _ => 0.0,
                };
                let id = if i == j { 1.0 } else { 0.0 };
                c * id + s * cross + (1.0 - c) * k[i] * k[j]
            })
        })
    }

    /// `R p`.
    pub fn rotate(r: &[[f64; 3]; 3], p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| r[i][j] * p[j]).sum())
    }

    /// The largest absolute entry.
    pub fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
        v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
    }
}
