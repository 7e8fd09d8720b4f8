//! Anderson acceleration of a fixed-point iteration `x ← G(x)` (Anderson 1965;
//! the form of Walker & Ni, "Anderson acceleration for fixed-point iterations",
//! SIAM J. Numer. Anal. 49 (2011), Algorithm AA with depth m).
//!
//! With the residual `f_k = G(x_k) − x_k` and the differences of the last m
//! residuals and images, `ΔF = [f_k − f_{k−1}, …]`, `ΔG = [G(x_k) − G(x_{k−1}), …]`,
//! the next iterate is
//!
//! ```text
//! γ = argmin ‖f_k − ΔF γ‖₂,     x_{k+1} = G(x_k) − ΔG γ.
//! ```
//!
//! On an affine map `G(x) = A x + b` this is a Krylov method (equivalent to GMRES
//! on `(I − A) x = b` while the depth covers the iterations), so slow modes of the
//! plain iteration (contraction close to 1) are removed in a few steps. The least
//! squares is solved by modified Gram–Schmidt on the columns of ΔF, dropping a
//! column that is nearly dependent on the others (its norm after orthogonalisation
//! below [`DROP`] × its norm before), so γ stays bounded.
//!
//! The solver uses it on the right-hand-side terms of the contact pairs (slip
//! forces, the slipping pairs' spring anchors and augmented-Lagrangian multipliers)
//! within one pattern of states.

/// A column of ΔF whose norm falls below this fraction of its original norm when
/// orthogonalised against the others is dropped from the least squares.
const DROP: f64 = 1e-8;

/// The history of an Anderson-accelerated fixed-point iteration (one per map: the
/// solver starts a new one for each pattern of states).
#[derive(Debug, Clone)]
pub struct Anderson {
    depth: usize,
    /// The last residual and image, `f_{k−1}` and `G(x_{k−1})`.
    last: Option<(Vec<f64>, Vec<f64>)>,
    /// Columns `f_j − f_{j−1}` and `G(x_j) − G(x_{j−1})`, oldest first.
    d_f: Vec<Vec<f64>>,
    d_g: Vec<Vec<f64>>,
}

impl Anderson {
    /// A new history of depth `depth` (0: the plain iteration `x ← G(x)`).
    pub fn new(depth: usize) -> Self {
        Anderson {
            depth,
            last: None,
            d_f: Vec::new(),
            d_g: Vec::new(),
        }
    }

    /// The next iterate from the current iterate `x` and its image `g = G(x)`.
    /// The first step (or any with depth 0, or after the vector's length changed)
    /// is `g`.
    pub fn step(&mut self, x: &[f64], g: &[f64]) -> Vec<f64> {
        assert_eq!(x.len(), g.len(), "iterate and image of different lengths");
        let f: Vec<f64> = g.iter().zip(x).map(|(g, x)| g - x).collect();
        if let Some((f_last, g_last)) = self.last.take() {
            if f_last.len() == f.len() && self.depth > 0 {
                self.d_f.push(f.iter().zip(&f_last).map(|(a, b)| a - b).collect());
                self.d_g.push(g.iter().zip(&g_last).map(|(a, b)| a - b).collect());
                if self.d_f.len() > self.depth {
                    self.d_f.remove(0);
                    self.d_g.remove(0);
                }
            } else {
                self.d_f.clear();
                self.d_g.clear();
            }
        }
        let mut next = g.to_vec();
        let gamma = least_squares(&self.d_f, &f);
        for (j, &c) in gamma.iter().enumerate() {
            if c != 0.0 {
                for (n, d) in next.iter_mut().zip(&self.d_g[j]) {
                    *n -= c * d;
                }
            }
        }
        self.last = Some((f, g.to_vec()));
        next
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// `γ = argmin ‖b − Σ_j γ_j a_j‖₂` over the columns `a`, by modified Gram–Schmidt;
/// a nearly dependent column gets γ_j = 0.
fn least_squares(a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
    let m = a.len();
    // Q's columns (orthonormal), R (upper triangular, by rows), and which of a's
    // columns each Q column came from.
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(m);
    let mut r = vec![vec![0.0; m]; m];
    let mut kept: Vec<usize> = Vec::with_capacity(m);
    for (j, col) in a.iter().enumerate() {
        let norm0 = dot(col, col).sqrt();
        if norm0 == 0.0 {
            continue;
        }
        let mut v = col.clone();
        let mut coeffs = Vec::with_capacity(q.len());
        for qi in &q {
            let c = dot(qi, &v);
            for (v, q) in v.iter_mut().zip(qi) {
                *v -= c * q;
            }
            coeffs.push(c);
        }
        let norm = dot(&v, &v).sqrt();
        if norm <= DROP * norm0 {
            continue;
        }
        let row = q.len();
        for (i, c) in coeffs.into_iter().enumerate() {
            r[i][row] = c;
        }
        r[row][row] = norm;
        v.iter_mut().for_each(|x| *x /= norm);
        q.push(v);
        kept.push(j);
    }
    // R y = Qᵀ b, back substitution.
    let k = q.len();
    let qtb: Vec<f64> = q.iter().map(|qi| dot(qi, b)).collect();
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let s: f64 = (i + 1..k).map(|l| r[i][l] * y[l]).sum();
        y[i] = (qtb[i] - s) / r[i][i];
    }
    let mut gamma = vec![0.0; m];
    for (i, &j) in kept.iter().enumerate() {
        gamma[j] = y[i];
    }
    gamma
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map G(x) = A x + b with A = diag(0.999, 0.5, −0.9) (one mode that the
    /// plain iteration would need ~30 000 steps to reduce by 1e-13): Anderson with
    /// depth 3 reaches the fixed point (I − A)⁻¹ b to 1e-12 within 6 steps, as a
    /// Krylov method does on a 3-dimensional space.
    #[test]
    fn affine_map_converges_in_dimension_steps() {
        let a = [0.999, 0.5, -0.9];
        let b = [1.0, -2.0, 0.5];
        let exact: Vec<f64> = (0..3).map(|i| b[i] / (1.0 - a[i])).collect();
        let g = |x: &[f64]| -> Vec<f64> { (0..3).map(|i| a[i] * x[i] + b[i]).collect() };
        let mut acc = Anderson::new(3);
        let mut x = vec![0.0; 3];
        let mut steps = 0;
        while (0..3).any(|i| (x[i] - exact[i]).abs() > 1e-12 * exact[i].abs()) {
            x = acc.step(&x.clone(), &g(&x));
            steps += 1;
            assert!(steps <= 6, "not converged after {steps} steps: {x:?}");
        }
    }

    /// Depth 0 is the plain iteration, and so is the first step after the
    /// vector's length changed (the history no longer applies).
    #[test]
    fn depth_zero_and_new_layouts_are_plain_steps() {
        let mut acc = Anderson::new(0);
        assert_eq!(acc.step(&[1.0, 2.0], &[3.0, 5.0]), vec![3.0, 5.0]);
        assert_eq!(acc.step(&[3.0, 5.0], &[4.0, 4.0]), vec![4.0, 4.0]);
        let mut acc = Anderson::new(4);
        acc.step(&[1.0], &[2.0]);
        acc.step(&[2.0], &[2.5]);
        assert_eq!(acc.step(&[7.0, 1.0], &[9.0, 2.0]), vec![9.0, 2.0]);
    }

    /// The least squares matches the normal equations on a well-conditioned
    /// system, and gives a repeated column zero weight instead of blowing up.
    #[test]
    fn least_squares_drops_dependent_columns() {
        let a = vec![vec![1.0, 0.0, 1.0], vec![0.0, 2.0, 1.0]];
        let b = [1.0, 1.0, 1.0];
        let g = least_squares(&a, &b);
        // Normal equations: [[2, 1], [1, 5]] γ = [2, 3] → γ = (7/9, 4/9).
        assert!((g[0] - 7.0 / 9.0).abs() < 1e-14 && (g[1] - 4.0 / 9.0).abs() < 1e-14);
        let dup = vec![a[0].clone(), a[0].clone()];
        let g = least_squares(&dup, &b);
        assert!((g[0] - 1.0).abs() < 1e-14 && g[1] == 0.0, "{g:?}");
    }
}
