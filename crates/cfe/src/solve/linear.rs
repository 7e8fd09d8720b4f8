//! Sparse Cholesky (LLᵀ) of the symmetric positive definite stiffness: the symbolic
//! analysis is computed once for the fixed pattern (the given elimination order or
//! faer's AMD; the elimination tree and column counts in [`super::symbolic`]; the
//! supernodes by faer's low-level API); each new set of values is refactorized
//! into the same factor storage ([`super::factor`]), and solves reuse it.
//!
//! The factor is always supernodal (dense column blocks along the elimination
//! tree), so a right-hand side with a few nonzeros can be forward-solved through
//! the supernodes on the tree paths from its rows to the root only (see
//! `super::columns`), and the cost of a factorization is known in flops before it
//! is done ([`CholeskySolver::factor_flops`]). On a factor big enough the full and
//! restricted solves run disjoint subtrees of the elimination tree on different
//! threads ([`super::subtree`]). The solves restricted to elimination-tree
//! paths are in [`super::paths`].

use super::factor::{Halt, NumericPlan};
use super::lower::LowerMatrix;
use super::symbolic;
use super::subtree::{PARALLEL_MIN_VALUES, SubtreeSplit};
use crate::assembly::MAX_EQUATIONS;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::SymbolicSupernodalParams;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::simplicial::EliminationTreeRef;
use faer::sparse::linalg::cholesky::supernodal::{
    SupernodalLltRef, SymbolicSupernodalCholesky, factorize_supernodal_symbolic_cholesky,
    factorize_supernodal_symbolic_cholesky_scratch,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};
use std::sync::atomic::AtomicUsize;

/// A sparse Cholesky solver bound to one sparsity pattern.
pub struct CholeskySolver {
    /// The supernodal structure of the factor.
    sn: SymbolicSupernodalCholesky<usize>,
    /// The elimination order (`order[k]` = equation eliminated k-th) and its
    /// inverse (the position of each equation), 4 bytes each (held beside the
    /// factor for the whole solve).
    order: Vec<u32>,
    inverse: Vec<u32>,
    factor: Vec<f64>,
    scratch: MemBuffer,
    scratch_req: StackReq,
    scratch_bytes: usize,
    pub(super) factorized: bool,
    /// Supernode of each (permuted) column.
    pub(super) supernode_of: Vec<u32>,
    /// Parent of each supernode in the supernodal elimination tree (`usize::MAX`
    /// for a root).
    pub(super) parent: Vec<usize>,
    /// Flops of one numeric factorization.
    factor_flops: f64,
    /// The elimination tree cut into subtrees solved in parallel by the full
    /// forward and backward solves (`None`: sequential).
    pub(super) split: Option<SubtreeSplit>,
    /// The numeric factorization's schedule (updaters, parallel subtrees).
    plan: NumericPlan,
    /// Number of numeric factorizations performed.
    pub factorizations: usize,
}

impl CholeskySolver {
    /// Symbolic analysis of the lower-triangular pattern of `k`, with the
    /// elimination order `order` (`order[k]` = equation eliminated k-th), or AMD.
    pub fn new(k: SparseColMatRef<'_, usize, f64>, order: Option<&[usize]>) -> Result<Self> {
        let n = k.nrows();
        if n > MAX_EQUATIONS {
            return Err(Error::TooLarge {
                unknowns: n as u64,
                bytes: 0,
                available: 0,
                message: format!(
                    "{n} equations, more than the {MAX_EQUATIONS} an elimination order can index"
                ),
            });
        }
        let (order, inverse): (Vec<u32>, Vec<u32>) = match order {
            Some(o) => {
                let mut inv = vec![usize::MAX; o.len()];
                for (new, &old) in o.iter().enumerate() {
                    if old < inv.len() {
                        inv[old] = new;
                    }
                }
                if o.len() != n || inv.contains(&usize::MAX) {
                    return Err(Error::Singular(
                        "the elimination order is not a permutation".into(),
                    ));
                }
                (o.iter().map(|&e| narrow(e)).collect(), inv.into_iter().map(narrow).collect())
            }
            None => {
                let (o, inv) = amd_order(k)?;
                (o.into_iter().map(narrow).collect(), inv.into_iter().map(narrow).collect())
            }
        };
        // Elimination tree and column counts (ours: Gilbert–Ng–Peyton, see
        // `super::symbolic`), then faer's supernodal structure from them.
        let sym = k.symbolic();
        let (upper, lower) =
            symbolic::permuted_triangles(sym.col_ptr(), sym.row_idx(), &inverse);
        let etree = symbolic::elimination_tree(&upper.col_ptr, &upper.row_idx);
        let post = symbolic::postorder(&etree);
        let counts = symbolic::column_counts(&lower.col_ptr, &lower.row_idx, &etree, &post);
        drop(lower);
        Self::from_symbolic(order, inverse, upper, etree, counts, None)
    }

    /// The solver for the elimination order `order` (and its `inverse`) from the
    /// symbolic analysis done: `upper` the upper triangle of `P K Pᵀ`, `etree` its
    /// elimination tree ([`symbolic::elimination_tree`]) and `counts` the column
    /// counts of its factor ([`symbolic::column_counts`]). faer finds the
    /// supernodes (and frees these three); the numeric plan and the solves'
    /// parallel split follow. With a stop flag faer's analysis, which cannot
    /// read it, runs on a thread of its own that a stop abandons
    /// ([`symbolic::run_until`]): [`Error::Interrupted`] after increment 0.
    pub fn from_symbolic(
        order: Vec<u32>,
        inverse: Vec<u32>,
        upper: symbolic::Pattern,
        etree: Vec<isize>,
        counts: Vec<usize>,
        stop: Option<&AtomicUsize>,
    ) -> Result<Self> {
        let n = order.len();
        assert!(
            inverse.len() == n
                && etree.len() == n
                && counts.len() == n
                && upper.col_ptr.len() == n + 1
                && etree.iter().enumerate().all(|(j, &p)| p == -1 || (p > j as isize && (p as usize) < n)),
            "a symbolic analysis of another matrix, or not an elimination tree"
        );
        // faer's analysis owns its inputs: it may run on a thread of its own
        // (with a stop flag), which a stop leaves to finish and free them.
        let sn = symbolic::run_until(stop, move || {
            let upper_ref = SymbolicSparseColMatRef::new_unsorted_checked(
                n,
                n,
                &upper.col_ptr,
                None,
                &upper.row_idx,
            );
            let mut mem =
                MemBuffer::new(factorize_supernodal_symbolic_cholesky_scratch::<usize>(n));
            // SAFETY: faer asks for the array `prefactorize_symbolic_cholesky` fills: the
            // elimination tree of `upper`, each entry −1 (a root) or the parent column,
            // which is greater than the column (faer indexes with it unchecked; checked
            // above). `elimination_tree` is Liu's algorithm, and `symbolic::tests`
            // checks it and `column_counts` equal faer's.
            let tree_ref = unsafe { EliminationTreeRef::<usize>::from_inner(&etree) };
            factorize_supernodal_symbolic_cholesky(
                upper_ref,
                tree_ref,
                &counts,
                MemStack::new(&mut mem),
                SymbolicSupernodalParams::default(),
            )
            .map_err(|e| format!("{e:?}"))
        })
        .map_err(|symbolic::Stopped(signal)| Error::Interrupted {
            increment: 0,
            signal,
        })?
        .map_err(|e| Error::Singular(format!("symbolic analysis failed: {e}")))?;
        // The solves' scratch (the numeric factorization has its own, per thread).
        let req = sn.solve_in_place_scratch::<f64>(1, Par::Seq);
        let (supernode_of, parent, factor_flops) = tree(&sn);
        let big = sn.len_val() >= PARALLEL_MIN_VALUES;
        let threads = if big { rayon::current_num_threads() } else { 1 };
        let split = big
            .then(|| SubtreeSplit::new(&sn, &parent, threads))
            .flatten();
        let plan = NumericPlan::new(&sn, &supernode_of, &parent, threads);
        Ok(CholeskySolver {
            factor: Vec::new(),
            sn,
            order,
            inverse,
            scratch: MemBuffer::new(req),
            scratch_req: req,
            scratch_bytes: req.size_bytes(),
            factorized: false,
            supernode_of,
            parent,
            factor_flops,
            split,
            plan,
            factorizations: 0,
        })
    }

    /// Frees the factor's values and the scratch buffer (the symbolic analysis
    /// stays): the next [`CholeskySolver::factorize`] allocates them again.
    pub fn release(&mut self) {
        self.factor = Vec::new();
        self.scratch = MemBuffer::new(StackReq::EMPTY);
        self.scratch_bytes = 0;
        self.factorized = false;
    }

    /// Solves the full forward and backward solves in `parts` parallel parts of the
    /// elimination tree (1: sequentially), whatever the size of the factor (by
    /// default: as many parts as rayon has threads when the factor has at least
    /// [`PARALLEL_MIN_VALUES`] values). Returns the number of parts used (1 when
    /// the tree cannot be split usefully).
    pub fn set_solve_parts(&mut self, parts: usize) -> usize {
        let split = SubtreeSplit::new(self.supernodal(), &self.parent, parts);
        self.split = split;
        self.split.as_ref().map_or(1, |s| s.parts())
    }

    /// Number of parts the full and restricted solves run in parallel (1:
    /// sequential).
    pub fn solve_parts(&self) -> usize {
        self.split.as_ref().map_or(1, |s| s.parts())
    }

    /// The supernodal structure of the factor.
    pub fn supernodal(&self) -> &SymbolicSupernodalCholesky<usize> {
        &self.sn
    }

    /// The numeric factor (after a successful [`CholeskySolver::factorize`]).
    pub fn factor(&self) -> SupernodalLltRef<'_, usize, f64> {
        assert!(
            self.factorized,
            "factor used before a successful factorization"
        );
        SupernodalLltRef::new(&self.sn, &self.factor)
    }

    /// Supernode holding (permuted) column `j` of the factor.
    pub fn supernode_of(&self, j: usize) -> usize {
        self.supernode_of[j] as usize
    }

    /// Parent of supernode `s` in the supernodal elimination tree, if any.
    pub fn parent(&self, s: usize) -> Option<usize> {
        let p = self.parent[s];
        (p != usize::MAX).then_some(p)
    }

    /// Position of original equation `e` in the elimination order.
    pub fn permuted(&self, e: usize) -> usize {
        self.inverse[e] as usize
    }

    /// Flops of one numeric factorization (multiply–adds counted as two), from the
    /// supernode sizes: a deterministic measure of its cost.
    pub fn factor_flops(&self) -> f64 {
        self.factor_flops
    }

    /// Flops of one solve with one right-hand side (forward and backward).
    pub fn solve_flops(&self) -> f64 {
        4.0 * self.factor_nnz() as f64
    }

    /// `z ← L⁻¹ P b`: permutes the original-order `b` into `z` and forward-solves.
    pub fn forward(&mut self, b: &[f64], z: &mut [f64]) {
        assert!(self.factorized, "solve before a successful factorization");
        for (zj, &o) in z.iter_mut().zip(&self.order) {
            *zj = b[o as usize];
        }
        let l = SupernodalLltRef::new(&self.sn, &self.factor);
        if let Some(split) = &self.split {
            split.forward(l, &self.supernode_of, None, z);
            return;
        }
        let stack = MemStack::new(&mut self.scratch);
        let n = z.len();
        let z = MatMut::from_column_major_slice_mut(z, n, 1);
        l.l_solve_with_conj(Conj::No, z, Par::Seq, stack);
    }

    /// `x ← Pᵀ L⁻ᵀ z`: backward-solves `z` in place and un-permutes it into `x`.
    pub fn backward(&mut self, z: &mut [f64], x: &mut [f64]) {
        assert!(self.factorized, "solve before a successful factorization");
        let l = SupernodalLltRef::new(&self.sn, &self.factor);
        if let Some(split) = &self.split {
            split.backward(l, &self.supernode_of, None, z);
        } else {
            let stack = MemStack::new(&mut self.scratch);
            let n = z.len();
            let zm = MatMut::from_column_major_slice_mut(z, n, 1);
            l.l_transpose_solve_with_conj(Conj::No, zm, Par::Seq, stack);
        }
        for (&zj, &o) in z.iter().zip(&self.order) {
            x[o as usize] = zj;
        }
    }

    /// Number of values stored for the factor L (its supernodes' dense blocks).
    pub fn factor_nnz(&self) -> usize {
        self.sn.len_val()
    }

    /// The elimination order (`order[k]` = equation eliminated k-th) and its
    /// inverse (the position of each equation).
    pub fn order(&self) -> (&[u32], &[u32]) {
        (&self.order, &self.inverse)
    }

    /// Numeric factorization of `k_ordered`, the lower triangle of `P K Pᵀ`: the
    /// matrix of the pattern given at construction stored in the elimination
    /// order ([`CholeskySolver::order`]; see [`crate::assembly::Stiffness::in_order`]),
    /// which the numeric factorization ([`super::factor`]) reads as it is, its
    /// 4-byte rows too ([`LowerMatrix`]). A non-positive pivot
    /// is returned as the original equation number where it occurred
    /// ([`Halt::Pivot`]); `stop`, if given, is read before every supernode and
    /// once nonzero abandons the factorization ([`Halt::Stopped`]).
    pub fn factorize(
        &mut self,
        k_ordered: LowerMatrix<'_>,
        stop: Option<&AtomicUsize>,
    ) -> std::result::Result<(), Halt> {
        assert_eq!(k_ordered.n(), self.sn.nrows(), "a matrix of another size");
        self.factorized = false;
        if self.factor.len() != self.sn.len_val() {
            self.factor = factor_storage(self.sn.len_val());
        }
        if self.scratch_bytes < self.scratch_req.size_bytes() {
            self.scratch = MemBuffer::new(self.scratch_req);
            self.scratch_bytes = self.scratch_req.size_bytes();
        }
        let res = self.plan.factorize(&self.sn, k_ordered, &mut self.factor, stop);
        self.factorizations += 1;
        match res {
            Ok(_) => {
                self.factorized = true;
                Ok(())
            }
            Err(Halt::Pivot(idx)) => {
                // Map the permuted pivot back to the original equation.
                let original = self.order.get(idx).map_or(idx, |&o| o as usize);
                Err(Halt::Pivot(original))
            }
            Err(stopped) => Err(stopped),
        }
    }

    /// Solves K x = b in place (after a successful [`CholeskySolver::factorize`]).
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = b.len();
        self.solve_columns(b, n, 1);
    }

    /// Solves K X = B in place for `ncols` right-hand sides stored column-major in
    /// `b` (each of length `n`).
    pub fn solve_columns(&mut self, b: &mut [f64], n: usize, ncols: usize) {
        assert!(self.factorized, "solve before a successful factorization");
        if ncols == 0 {
            return;
        }
        // Few right-hand sides: the solve is bound by reading the factor, and the
        // second thread would mostly wait (spinning) between small supernodes.
        let par = if ncols >= 8 { Par::rayon(0) } else { Par::Seq };
        let req = self.sn.solve_in_place_scratch::<f64>(ncols, par);
        if req.size_bytes() > self.scratch_bytes {
            self.scratch = MemBuffer::new(req.or(self.scratch_req));
            self.scratch_bytes = req.size_bytes().max(self.scratch_bytes);
        }
        // P b, solved in the elimination order, then un-permuted.
        let mut permuted = vec![0.0; n * ncols];
        for (pc, bc) in permuted.chunks_exact_mut(n).zip(b.chunks_exact(n)) {
            for (x, &o) in pc.iter_mut().zip(&self.order) {
                *x = bc[o as usize];
            }
        }
        let stack = MemStack::new(&mut self.scratch);
        let rhs = MatMut::from_column_major_slice_mut(&mut permuted, n, ncols);
        SupernodalLltRef::new(&self.sn, &self.factor).solve_in_place_with_conj(
            Conj::No,
            rhs,
            par,
            stack,
        );
        for (pc, bc) in permuted.chunks_exact(n).zip(b.chunks_exact_mut(n)) {
            for (&x, &o) in pc.iter().zip(&self.order) {
                bc[o as usize] = x;
            }
        }
    }
}

/// An equation's index in 4 bytes (the order and its inverse are held for the
/// whole solve); `n ≤ MAX_EQUATIONS` is checked before any is narrowed.
fn narrow(i: usize) -> u32 {
    u32::try_from(i).expect("at most MAX_EQUATIONS equations")
}

/// An approximate minimum degree order of the lower-triangular pattern of `k` and
/// its inverse (faer's AMD).
fn amd_order(k: SparseColMatRef<'_, usize, f64>) -> Result<(Vec<usize>, Vec<usize>)> {
    let n = k.nrows();
    let failed = |e| Error::Singular(format!("the AMD ordering failed: {e:?}"));
    // AMD reads the whole symmetric pattern: the lower triangle and its mirror.
    let sym = k.symbolic();
    let (mut ptr, mut rows) = (vec![0usize; n + 1], Vec::new());
    let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in 0..n {
        for &i in sym.row_idx_of_col_raw(j) {
            if i >= j {
                cols[j].push(i);
                if i != j {
                    cols[i].push(j);
                }
            }
        }
    }
    for (j, c) in cols.iter_mut().enumerate() {
        c.sort_unstable();
        rows.extend_from_slice(c);
        ptr[j + 1] = rows.len();
    }
    let full = SymbolicSparseColMatRef::new_checked(n, n, &ptr, None, &rows);
    let (mut fwd, mut inv) = (vec![0usize; n], vec![0usize; n]);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, rows.len()));
    amd::order(&mut fwd, &mut inv, full, amd::Control::default(), MemStack::new(&mut mem))
        .map_err(failed)?;
    Ok((fwd, inv))
}

/// Zeroed storage for `len` factor values, on transparent huge pages where the
/// system offers them on request (Linux with THP in `madvise` mode): the factor is
/// the largest array of a run, first written by the factorization, and 2 MiB pages
/// take 512 times fewer page faults to touch than 4 KiB ones.
fn factor_storage(len: usize) -> Vec<f64> {
    // Zeroed by the allocator from fresh pages (nothing touched yet).
    let v = vec![0.0f64; len];
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let start = v.as_ptr() as usize;
        let end = start + std::mem::size_of_val(v.as_slice());
        let (first, last) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
        if last > first {
            // SAFETY: MADV_HUGEPAGE only advises the kernel how to back the pages of
            // `first..last`, which lies inside the allocation of `v`; it changes
            // neither their contents nor their protection, and a refusal is harmless
            // (the pages stay ordinary).
            unsafe {
                libc::madvise(first as *mut libc::c_void, last - first, libc::MADV_HUGEPAGE);
            }
        }
    }
    v
}

/// The supernode of every column, the parent of every supernode and the flops of
/// a numeric factorization: per supernode of `c` columns and `p` rows below them,
/// `c³/3` for its diagonal block, `c² p` for the panel and `c p²` for the update of
/// its ancestors.
fn tree(sn: &SymbolicSupernodalCholesky<usize>) -> (Vec<u32>, Vec<usize>, f64) {
    let ns = sn.n_supernodes();
    let mut supernode_of = vec![0u32; sn.nrows()];
    for s in 0..ns {
        supernode_of[sn.supernode_begin()[s]..sn.supernode_end()[s]].fill(s as u32);
    }
    let mut flops = 0.0;
    let parent = (0..ns)
        .map(|s| {
            let pattern = sn.supernode(s).pattern();
            let c = (sn.supernode_end()[s] - sn.supernode_begin()[s]) as f64;
            let p = pattern.len() as f64;
            flops += c * c * c / 3.0 + c * c * p + c * p * p;
            pattern
                .first()
                .map_or(usize::MAX, |&r| supernode_of[r] as usize)
        })
        .collect();
    (supernode_of, parent, flops)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use faer::Side;

    /// A lower triangle in CSC form: column pointers, rows, values.
    pub(crate) type Csc = (Vec<usize>, Vec<usize>, Vec<f64>);

    /// The lower triangle of `P K Pᵀ` in the elimination order of `s`, for
    /// [`CholeskySolver::factorize`].
    fn ordered(k: SparseColMatRef<'_, usize, f64>, s: &CholeskySolver) -> Csc {
        let n = k.nrows();
        let (fwd, inv) = s.order();
        let fwd: Vec<usize> = fwd.iter().map(|&o| o as usize).collect();
        let inv: Vec<usize> = inv.iter().map(|&o| o as usize).collect();
        let nnz = k.compute_nnz();
        let (mut col_ptr, mut row, mut val) = (vec![0; n + 1], vec![0; nnz], vec![0.0; nnz]);
        let mut mem = MemBuffer::new(faer::sparse::utils::permute_self_adjoint_scratch::<usize>(n));
        faer::sparse::utils::permute_self_adjoint(
            &mut val,
            &mut col_ptr,
            &mut row,
            k,
            faer::perm::PermRef::new_checked(&fwd, &inv, n),
            Side::Lower,
            Side::Lower,
            MemStack::new(&mut mem),
        );
        (col_ptr, row, val)
    }

    /// Factorizes `k` (in the equations' order) with `s`.
    fn factorize(s: &mut CholeskySolver, k: SparseColMatRef<'_, usize, f64>) -> std::result::Result<(), Halt> {
        let (col_ptr, row, val) = ordered(k, s);
        let row: Vec<u32> = row.iter().map(|&i| i as u32).collect();
        s.factorize(LowerMatrix::new(&col_ptr, &row, &val), None)
    }

    /// A tridiagonal SPD system (−1, 2, −1 plus identity) is solved to round-off,
    /// twice with different values on the same symbolic analysis.
    #[test]
    fn solves_and_refactorizes() {
        let n = 50;
        let mut col_ptr = vec![0];
        let mut row = vec![];
        for j in 0..n {
            row.push(j);
            if j + 1 < n {
                row.push(j + 1);
            }
            col_ptr.push(row.len());
        }
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row);
        for scale in [1.0, 7.0] {
            let vals: Vec<f64> = (0..n)
                .flat_map(|j| {
                    let mut v = vec![3.0 * scale];
                    if j + 1 < n {
                        v.push(-scale);
                    }
                    v
                })
                .collect();
            let k = SparseColMatRef::new(sym, &vals);
            let mut s = CholeskySolver::new(k, None).unwrap();
            factorize(&mut s, k).unwrap();
            let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|i| {
                    3.0 * scale * x[i]
                        - scale * (if i > 0 { x[i - 1] } else { 0.0 })
                        - scale * (if i + 1 < n { x[i + 1] } else { 0.0 })
                })
                .collect();
            s.solve_in_place(&mut b);
            for i in 0..n {
                assert!((b[i] - x[i]).abs() < 1e-13);
            }
        }
    }

    /// The lower triangle (CSC: column pointers, rows, values) of the 5-point
    /// Laplacian of an `m` × `m` grid with `diagonal` on the diagonal.
    fn laplacian(m: usize, diagonal: f64) -> Csc {
        let mut col_ptr = vec![0];
        let mut row = vec![];
        let mut vals = vec![];
        for j in 0..m * m {
            let (x, y) = (j % m, j / m);
            row.push(j);
            vals.push(diagonal);
            if x + 1 < m {
                row.push(j + 1);
                vals.push(-1.0);
            }
            if y + 1 < m {
                row.push(j + m);
                vals.push(-1.0);
            }
            col_ptr.push(row.len());
        }
        (col_ptr, row, vals)
    }

    /// [`laplacian`]`(m, diagonal)` with its Cholesky solver (AMD order),
    /// factorized.
    pub(crate) fn factored_laplacian(m: usize, diagonal: f64) -> (CholeskySolver, Csc) {
        let n = m * m;
        let (col_ptr, row, vals) = laplacian(m, diagonal);
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row);
        let k = SparseColMatRef::new(sym, &vals);
        let mut s = CholeskySolver::new(k, None).unwrap();
        factorize(&mut s, k).unwrap();
        (s, (col_ptr, row, vals))
    }

    /// The subtree-parallel forward and backward solves (2 and 3 parts) give the
    /// sequential solves' values to 1e-12 relative (only the summation order of the
    /// top rows' updates differs) and solve K x = b, on a 5-point Laplacian of a
    /// 90 × 90 grid whose AMD ordering has a branching tree.
    #[test]
    fn subtree_parallel_solves_match_sequential() {
        let m = 90;
        let n = m * m;
        let (mut s, (col_ptr, row, vals)) = factored_laplacian(m, 4.01);
        let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect();
        assert_eq!(s.set_solve_parts(1), 1);
        let (mut z_seq, mut x_seq) = (vec![0.0; n], vec![0.0; n]);
        s.forward(&b, &mut z_seq);
        let fwd_seq = z_seq.clone();
        s.backward(&mut z_seq, &mut x_seq);
        let rel = |a: &[f64], b: &[f64]| {
            let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            a.iter().zip(b).fold(0.0f64, |m, (p, q)| m.max((p - q).abs())) / scale
        };
        // K x = b for the sequential solve (Kx from the lower triangle).
        let mut kx = vec![0.0; n];
        for j in 0..n {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let i = row[p];
                kx[i] += vals[p] * x_seq[j];
                if i != j {
                    kx[j] += vals[p] * x_seq[i];
                }
            }
        }
        assert!(rel(&kx, &b) < 1e-12);
        for parts in [2, 3] {
            assert_eq!(s.set_solve_parts(parts), parts);
            let split = s.split.as_ref().unwrap();
            assert!(split.critical_fraction() < 0.7, "{}", split.critical_fraction());
            let (mut z, mut x) = (vec![0.0; n], vec![0.0; n]);
            s.forward(&b, &mut z);
            assert!(rel(&z, &fwd_seq) < 1e-12);
            s.backward(&mut z, &mut x);
            assert!(rel(&x, &x_seq) < 1e-12, "{}", rel(&x, &x_seq));
        }
        // The restricted solves on the tree paths of a few rows, split and not.
        let rows = [5usize, 4000, 8099];
        let set = s.ancestors(rows.iter().map(|&e| s.permuted(e)));
        let mut on = Vec::new();
        for parts in [1, 2] {
            s.set_solve_parts(parts);
            let mut z = vec![0.0; n];
            for (i, &e) in rows.iter().enumerate() {
                z[s.permuted(e)] = 1.0 + i as f64;
            }
            s.forward_on(&set, &mut z);
            let f = z.clone();
            s.backward_on(&set, &mut z);
            on.push((f, z));
        }
        assert!(rel(&on[1].0, &on[0].0) < 1e-12);
        let sn = s.supernodal();
        let on_set = |z: &[f64]| -> Vec<f64> {
            set.iter()
                .flat_map(|&t| z[sn.supernode_begin()[t]..sn.supernode_end()[t]].to_vec())
                .collect()
        };
        assert!(rel(&on_set(&on[1].1), &on_set(&on[0].1)) < 1e-12);
    }

    /// The subtree-parallel left-looking factorization (1, 2 and 3 parts) gives
    /// faer's own supernodal factor to 1e-13 relative, value by value, on a
    /// 5-point Laplacian of a 90 × 90 grid with varied coefficients (AMD order, a
    /// branching tree): the same supernodal arithmetic, scheduled differently;
    /// and the same bits whether the matrix's values are lent or given (and
    /// their pages given back as they are read).
    #[test]
    fn parallel_factorization_matches_faer() {
        use faer::linalg::cholesky::llt::factor::LltRegularization;
        use faer::sparse::linalg::cholesky::supernodal::{
            factorize_supernodal_numeric_llt, factorize_supernodal_numeric_llt_scratch,
        };
        let m = 90;
        let n = m * m;
        let (col_ptr, row, mut vals) = laplacian(m, 4.0);
        // Off-diagonals shrunk (≤ 1 in size) and diagonals grown, unevenly: still
        // diagonally dominant, so positive definite.
        for (p, v) in vals.iter_mut().enumerate() {
            let f = (0.7 * p as f64).sin().abs();
            *v *= if *v > 0.0 { 1.0 + 0.3 * f } else { 0.5 + 0.5 * f };
        }
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row);
        let k = SparseColMatRef::new(sym, &vals);
        let mut s = CholeskySolver::new(k, None).unwrap();
        let (cp, rw, vl) = ordered(k, &s);
        let a = SparseColMatRef::new(SymbolicSparseColMatRef::new_checked(n, n, &cp, None, &rw), &vl);
        let rw32: Vec<u32> = rw.iter().map(|&i| i as u32).collect();
        let sn = s.supernodal();
        let mut reference = vec![0.0; sn.len_val()];
        let mut mem = MemBuffer::new(factorize_supernodal_numeric_llt_scratch::<usize, f64>(
            sn,
            Par::Seq,
            Default::default(),
        ));
        factorize_supernodal_numeric_llt(
            &mut reference,
            a,
            LltRegularization::default(),
            sn,
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .unwrap();
        let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for parts in [1, 2, 3] {
            s.plan = NumericPlan::new(s.supernodal(), &s.supernode_of, &s.parent, parts);
            assert_eq!(s.plan.parts(), parts);
            s.factorize(LowerMatrix::new(&cp, &rw32, &vl), None).unwrap();
            let worst = s.factor.iter().zip(&reference).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(worst < 1e-13 * scale, "{parts} parts: {worst:e}");
            // Given its values, the factorization gives their pages back as it
            // reads them: the same factor, bit for bit.
            let borrowed = s.factor.clone();
            s.factorize(LowerMatrix::with_values(&cp, &rw32, vl.clone()), None).unwrap();
            assert!(s.factor.iter().zip(&borrowed).all(|(p, q)| p.to_bits() == q.to_bits()), "{parts} parts");
        }
    }

    /// A non-positive pivot is reported at its equation, whichever part of the tree
    /// (or the top) meets it: a grid Laplacian with one diagonal made negative.
    #[test]
    fn non_positive_pivot_is_located() {
        let m = 60;
        let n = m * m;
        for bad in [0, 1234, n / 2 + m / 2, n - 1] {
            let (col_ptr, row, mut vals) = laplacian(m, 4.5);
            vals[col_ptr[bad]] = -1.0;
            let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row);
            let k = SparseColMatRef::new(sym, &vals);
            let mut s = CholeskySolver::new(k, None).unwrap();
            s.plan = NumericPlan::new(s.supernodal(), &s.supernode_of, &s.parent, 2);
            assert_eq!(s.plan.parts(), 2);
            // The pivot fails at `bad` itself or, when the negative diagonal is
            // absorbed by later eliminations, at the first column after it that
            // turns non-positive; with a diagonal of −1 among 4.5s it is `bad`.
            assert_eq!(factorize(&mut s, k), Err(Halt::Pivot(bad)));
        }
    }

    /// A stop flag already set abandons the factorization before its first
    /// supernode, sequential or split into parts (`Halt::Stopped` with the
    /// flag's value); cleared, the next factorization of the same solver gives
    /// the factor of one never stopped, bit for bit.
    #[test]
    fn a_stop_flag_abandons_the_factorization() {
        let m = 40;
        let n = m * m;
        let (col_ptr, row, vals) = laplacian(m, 4.5);
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row);
        let k = SparseColMatRef::new(sym, &vals);
        for parts in [1, 2] {
            let mut s = CholeskySolver::new(k, None).unwrap();
            s.plan = NumericPlan::new(s.supernodal(), &s.supernode_of, &s.parent, parts);
            let (cp, rw, vl) = ordered(k, &s);
            let rw32: Vec<u32> = rw.iter().map(|&i| i as u32).collect();
            s.factorize(LowerMatrix::new(&cp, &rw32, &vl), None).unwrap();
            let plain = s.factor.clone();
            let stop = AtomicUsize::new(15);
            assert_eq!(
                s.factorize(LowerMatrix::new(&cp, &rw32, &vl), Some(&stop)),
                Err(Halt::Stopped(15)),
                "{parts} parts"
            );
            assert!(!s.factorized);
            stop.store(0, std::sync::atomic::Ordering::Relaxed);
            s.factorize(LowerMatrix::new(&cp, &rw32, &vl), Some(&stop)).unwrap();
            assert!(s.factor.iter().zip(&plain).all(|(p, q)| p.to_bits() == q.to_bits()), "{parts} parts");
        }
    }

    /// An indefinite matrix is reported as a failed factorization, not a panic.
    #[test]
    fn indefinite_is_an_error() {
        let col_ptr = [0usize, 1, 2];
        let row = [0usize, 1];
        let sym = SymbolicSparseColMatRef::new_checked(2, 2, &col_ptr, None, &row);
        let vals = [1.0, -1.0];
        let k = SparseColMatRef::new(sym, &vals);
        let mut s = CholeskySolver::new(k, None).unwrap();
        assert!(factorize(&mut s, k).is_err());
    }
}
