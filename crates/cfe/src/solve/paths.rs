//! Solves restricted to the elimination-tree paths of a few equations: with the
//! supernodal factor of a [`CholeskySolver`], a right-hand side that is zero off
//! a few rows is forward-solved through the supernodes on their paths to the
//! root only, and the backward solve restricted to an ancestor-closed set of
//! supernodes gives the full solve's values there — at the cost of the factor's
//! values on that set. The trial solves of the active-set search and the
//! fixed-point steps use them (through `super::system::ContactSystem`).

use super::linear::CholeskySolver;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Accum, MatMut, MatRef, Par};

impl CholeskySolver {
    /// The supernodes on the elimination-tree paths from the (permuted) rows
    /// `rows` to the root, in descending order (every supernode after its
    /// ancestors): the set a [`CholeskySolver::backward_on`] solve visits.
    pub fn ancestors(&self, rows: impl IntoIterator<Item = usize>) -> Vec<usize> {
        let mut on = vec![false; self.parent.len()];
        for r in rows {
            let mut s = Some(self.supernode_of(r));
            while let Some(t) = s {
                if on[t] {
                    break;
                }
                on[t] = true;
                s = self.parent(t);
            }
        }
        (0..on.len()).rev().filter(|&s| on[s]).collect()
    }

    /// The rows (in the elimination order) of each supernode of `set`, in the
    /// order of `set`.
    pub fn rows_on<'a>(&'a self, set: &'a [usize]) -> impl Iterator<Item = std::ops::Range<usize>> + 'a {
        let sn = self.supernodal();
        set.iter()
            .map(move |&s| sn.supernode_begin()[s]..sn.supernode_end()[s])
    }

    /// Values of the factor on the supernodes `set`: the work of a
    /// [`CholeskySolver::backward_on`] solve is twice this in flops.
    pub fn values_on(&self, set: &[usize]) -> usize {
        let sn = self.supernodal();
        set.iter()
            .map(|&s| {
                let c = sn.supernode_end()[s] - sn.supernode_begin()[s];
                c * (c + sn.supernode(s).pattern().len())
            })
            .sum()
    }

    /// Supernode `s` of the factor: its first column, its width `c`, its diagonal
    /// block (c × c, lower triangular), the block below it and that block's rows.
    #[allow(clippy::type_complexity)]
    fn supernode_blocks(
        &self,
        s: usize,
    ) -> (usize, usize, MatRef<'_, f64>, MatRef<'_, f64>, &[usize]) {
        let sn = self.supernodal();
        let begin = sn.supernode_begin()[s];
        let c = sn.supernode_end()[s] - begin;
        let node = self.factor().supernode(s);
        let (top, bottom) = node.val().split_at_row(c);
        (begin, c, top, bottom, node.pattern())
    }

    /// `z ← L⁻¹ z` for a `z` (in the elimination order) that is zero outside the
    /// supernodes of `set` (from [`CholeskySolver::ancestors`]): the forward solve
    /// carries a row's value only up its elimination-tree path, so `L⁻¹ z` is zero
    /// outside `set` too, and the solve visits `set` only, leaves first:
    /// `x_s = L_ss⁻¹ z_s`, then `z_p ← z_p − L_ps x_s` on the rows `p` below.
    pub fn forward_on(&self, set: &[usize], z: &mut [f64]) {
        assert!(self.factorized, "solve before a successful factorization");
        if let Some(split) = &self.split {
            split.forward(self.factor(), &self.supernode_of, Some(set), z);
            return;
        }
        let mut below: Vec<f64> = Vec::new();
        for &s in set.iter().rev() {
            let (begin, c, top, bottom, pattern) = self.supernode_blocks(s);
            let mut x = MatMut::from_column_major_slice_mut(&mut z[begin..begin + c], c, 1);
            solve_lower_triangular_in_place(top, x.as_mut(), Par::Seq);
            if !pattern.is_empty() {
                below.clear();
                below.resize(pattern.len(), 0.0);
                let mut t = MatMut::from_column_major_slice_mut(&mut below, pattern.len(), 1);
                matmul(t.as_mut(), Accum::Replace, bottom, x.as_ref(), 1.0, Par::Seq);
                for (&r, &v) in pattern.iter().zip(&below) {
                    z[r] -= v;
                }
            }
        }
    }

    /// `z ← L⁻ᵀ z` on the supernodes of `set` only (from [`CholeskySolver::ancestors`]:
    /// closed under the parent and ordered root first), in the elimination order.
    ///
    /// The entries of `L⁻ᵀ z` on a supernode depend only on `z` there and on the
    /// entries on its ancestors, so the solve restricted to an ancestor-closed set
    /// gives exactly the full backward solve's values on that set, at the cost of
    /// the factor's values there: `x_s = L_ssᵀ⁻¹ (z_s − L_psᵀ x_p)` for each supernode
    /// `s` with the rows `p` below its diagonal block. Entries outside `set` are
    /// left as they were.
    pub fn backward_on(&self, set: &[usize], z: &mut [f64]) {
        assert!(self.factorized, "solve before a successful factorization");
        if let Some(split) = &self.split {
            split.backward(self.factor(), &self.supernode_of, Some(set), z);
            return;
        }
        let mut below: Vec<f64> = Vec::new();
        for &s in set {
            let (begin, c, top, bottom, pattern) = self.supernode_blocks(s);
            below.clear();
            below.extend(pattern.iter().map(|&r| z[r]));
            let mut x = MatMut::from_column_major_slice_mut(&mut z[begin..begin + c], c, 1);
            if !pattern.is_empty() {
                let xp = MatRef::from_column_major_slice(&below, pattern.len(), 1);
                matmul(
                    x.as_mut(),
                    Accum::Add,
                    bottom.transpose(),
                    xp,
                    -1.0,
                    Par::Seq,
                );
            }
            solve_upper_triangular_in_place(top.transpose(), x, Par::Seq);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::solve::linear::tests::factored_laplacian;

    /// The backward solve restricted to the tree paths of a few rows gives the full
    /// solve's values on those rows (to round-off) and touches no other supernode,
    /// and the forward solve of a right-hand side on those rows, restricted to the
    /// same paths, equals the full forward solve,
    /// on a 5-point Laplacian of a 30 × 30 grid (plus identity) whose AMD ordering
    /// has a branching elimination tree.
    #[test]
    fn backward_on_paths_matches_full_solve() {
        let m = 30;
        let n = m * m;
        let (mut s, _) = factored_laplacian(m, 5.0);
        let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let mut z = vec![0.0; n];
        s.forward(&b, &mut z);
        let forward = z.clone();
        let mut x = vec![0.0; n];
        s.backward(&mut z.clone(), &mut x);
        let rows = [3usize, 451, 899];
        let set = s.ancestors(rows.iter().map(|&e| s.permuted(e)));
        assert!(set.len() < s.supernodal().n_supernodes() / 2);
        assert!(set.windows(2).all(|w| w[0] > w[1]));
        s.backward_on(&set, &mut z);
        for e in rows {
            assert!((z[s.permuted(e)] - x[e]).abs() < 1e-14 * x[e].abs().max(1.0));
        }
        let sn = s.supernodal();
        for t in (0..sn.n_supernodes()).filter(|t| !set.contains(t)) {
            let r = sn.supernode_begin()[t]..sn.supernode_end()[t];
            assert_eq!(z[r.clone()], forward[r]);
        }
        // A right-hand side on those rows only: the forward solve on their paths
        // equals the full one everywhere (zero off the paths).
        let mut b = vec![0.0; n];
        for (i, e) in rows.into_iter().enumerate() {
            b[e] = 1.0 + i as f64;
        }
        let mut full = vec![0.0; n];
        s.forward(&b, &mut full);
        let mut z = vec![0.0; n];
        for e in rows {
            z[s.permuted(e)] = b[e];
        }
        s.forward_on(&set, &mut z);
        for (p, q) in z.iter().zip(&full) {
            assert!((p - q).abs() < 1e-14);
        }
        assert!(full.iter().filter(|v| **v != 0.0).count() < n / 2);
    }
}
