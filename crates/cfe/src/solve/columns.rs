//! Sparse forward solves of the low-rank correction columns, and their Gram matrix.
//!
//! With `K₀ = Pᵀ L Lᵀ P`, the Woodbury capacitance of a correction `W Δ Wᵀ` is
//! `Wᵀ K₀⁻¹ W = Vᵀ V` with `V = L⁻¹ P W`. A column `w` of a coupling element has at
//! most ten nonzeros, and `L⁻¹ w` is nonzero only on the supernodes on the paths of
//! the elimination tree from those rows to the root: each column is forward-solved
//! through those supernodes only, all new columns together supernode by supernode
//! (a small dense triangular solve and product per supernode), and stored on them
//! only. The Gram matrix `G = VᵀV` of every stored column is accumulated on the way
//! (columns meet only on the supernodes they share). A solve then needs one full
//! forward and backward solve of the right-hand side, `Vᵀ z` and `z − V t` on the
//! stored supernodes, and a small dense solve: see [`super::system`].
//!
//! Every cost is counted in flops from the supernode sizes, so the choice between
//! an update and a refactorization is the same on every run and every machine.

use super::linear::CholeskySolver;
use crate::assembly::cut_at;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::ops::Range;

/// The columns stored on one supernode: their indices and values (supernode
/// width × number of columns, column-major).
#[derive(Default)]
struct Block {
    cols: Vec<u32>,
    vals: Vec<f64>,
}

/// Forward-solved correction columns `V = L⁻¹ P W` on their supernodes, and `VᵀV`.
#[derive(Default)]
pub struct Columns {
    blocks: Vec<Block>,
    /// Supernodes holding some column (to clear them).
    touched: Vec<usize>,
    /// Per column: (supernode, position in its block), sorted by supernode.
    paths: Vec<Vec<(u32, u32)>>,
    /// `G = VᵀV` of the stored columns (row-major, `len() × len()` in rows of
    /// `stride` entries: room for more columns, so adding a few copies nothing).
    gram: Vec<f64>,
    /// Entries per row of `gram` (at least `len()`).
    stride: usize,
    /// Values stored on all supernodes.
    stored: usize,
}

/// A new column: its nonzero rows in the elimination order and their values.
pub struct SparseColumn {
    /// (permuted row, value) pairs.
    pub entries: Vec<(usize, f64)>,
}

impl Columns {
    /// Number of stored columns.
    #[allow(dead_code)]
    pub fn len(&self) -> usize {
        self.paths.len()
    }

    /// True when no column is stored.
    #[allow(dead_code)]
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }

    /// Bytes of the stored values.
    pub fn bytes(&self) -> usize {
        8 * (self.stored + self.gram.len())
    }

    /// Bytes of a Gram matrix newly allocated for `m` columns (0 if the present
    /// one has room for them; it is freed once the new one is filled).
    pub fn gram_bytes_with(&self, m: usize) -> usize {
        if m > self.stride {
            let stride = m.max(2 * self.stride);
            8 * stride * stride
        } else {
            0
        }
    }

    /// Forgets every column.
    pub fn clear(&mut self) {
        for &s in &self.touched {
            self.blocks[s] = Block::default();
        }
        self.touched.clear();
        self.paths.clear();
        self.gram = Vec::new();
        self.stride = 0;
        self.stored = 0;
    }

    /// The supernodes on the tree paths from the rows of `col` to the root, sorted.
    pub fn path(chol: &CholeskySolver, col: &SparseColumn) -> Vec<u32> {
        let mut path: Vec<u32> = Vec::new();
        for &(r, _) in &col.entries {
            let mut s = Some(chol.supernode_of(r));
            while let Some(t) = s {
                path.push(t as u32);
                s = chol.parent(t);
            }
        }
        path.sort_unstable();
        path.dedup();
        path
    }

    /// Flops to add columns with these paths: per column and supernode of width
    /// `c` with `p` rows below, `c²` (triangular solve) + `2 c p` (update of the
    /// ancestors); per supernode `2 c m_new m_all` for the Gram matrix.
    pub fn add_flops(&self, chol: &CholeskySolver, paths: &[Vec<u32>]) -> f64 {
        let mut new_at: std::collections::HashMap<u32, usize> = Default::default();
        let mut flops = 0.0;
        for path in paths {
            for &s in path {
                let (c, p) = width(chol, s as usize);
                flops += c * c + 2.0 * c * p;
                *new_at.entry(s).or_default() += 1;
            }
        }
        for (s, m_new) in new_at {
            let (c, _) = width(chol, s as usize);
            let m_all = self.blocks.get(s as usize).map_or(0, |b| b.cols.len()) + m_new;
            flops += 2.0 * c * (m_new * m_all) as f64;
        }
        flops
    }

    /// Forward-solves the new columns (with their `paths` from [`Columns::path`])
    /// through the factor of `chol`, stores them and extends the Gram matrix.
    /// Returns the index of the first new column.
    pub fn add(
        &mut self,
        chol: &CholeskySolver,
        cols: &[SparseColumn],
        paths: Vec<Vec<u32>>,
    ) -> usize {
        let sn = chol.supernodal();
        if self.blocks.len() != sn.n_supernodes() {
            self.blocks = (0..sn.n_supernodes()).map(|_| Block::default()).collect();
            self.touched.clear();
        }
        let first = self.paths.len();
        let union = self.place(chol, paths);
        self.scatter(chol, cols, first);
        self.make_room(first);
        let bounds = self.solve_new(chol, &union, first);
        self.fill_gram(chol, &union, &bounds, first);
        first
    }

    /// Gives each new column (numbered on from `len()`, with its `paths`) a
    /// zeroed place in the block of every supernode on its path; returns the
    /// supernodes receiving new columns, ascending.
    fn place(&mut self, chol: &CholeskySolver, paths: Vec<Vec<u32>>) -> Vec<usize> {
        let first = self.paths.len();
        let mut union: Vec<usize> = Vec::new();
        for path in paths {
            let j = self.paths.len() as u32;
            let mut placed = Vec::with_capacity(path.len());
            for s in path {
                let su = s as usize;
                let blk = &mut self.blocks[su];
                if blk.cols.is_empty() {
                    self.touched.push(su);
                }
                if blk.cols.last().is_none_or(|&c| (c as usize) < first) {
                    union.push(su);
                }
                let (c, _) = width(chol, su);
                placed.push((s, blk.cols.len() as u32));
                blk.cols.push(j);
                blk.vals.resize(blk.vals.len() + c as usize, 0.0);
                self.stored += c as usize;
            }
            self.paths.push(placed);
        }
        union.sort_unstable();
        union
    }

    /// Adds the entries of the new columns `cols` (numbered from `first`) into
    /// their places: the right-hand sides the forward solve starts from.
    fn scatter(&mut self, chol: &CholeskySolver, cols: &[SparseColumn], first: usize) {
        let sn = chol.supernodal();
        for (k, col) in cols.iter().enumerate() {
            let j = first + k;
            for &(r, w) in &col.entries {
                let s = chol.supernode_of(r);
                let pos = self.position(j, s);
                let begin = sn.supernode_begin()[s];
                let c = sn.supernode_end()[s] - begin;
                self.blocks[s].vals[pos * c + r - begin] += w;
            }
        }
    }

    /// Makes room in the Gram matrix for every column stored, keeping the
    /// entries of the `first` columns there before: twice the room, so n columns
    /// added a few at a time are copied O(log n) times (`gram_bytes_with` counts
    /// the same).
    fn make_room(&mut self, first: usize) {
        let m = self.paths.len();
        if m <= self.stride {
            return;
        }
        let stride = m.max(2 * self.stride);
        let mut gram = vec![0.0; stride * stride];
        for a in 0..first {
            gram[a * stride..a * stride + first]
                .copy_from_slice(&self.gram[a * self.stride..a * self.stride + first]);
        }
        self.gram = gram;
        self.stride = stride;
    }

    /// Fills the rows and columns of the new columns `first..` in the Gram
    /// matrix: each group of new columns (between consecutive `bounds`) computes
    /// its rows on the supernodes `union` ([`gram_rows`]; the groups in
    /// parallel), then the rows are copied in and mirrored into the old columns.
    fn fill_gram(&mut self, chol: &CholeskySolver, union: &[usize], bounds: &[usize], first: usize) {
        let m = self.paths.len();
        let stride = self.stride;
        let blocks = &self.blocks;
        let group_rows = |w: &[usize]| gram_rows(blocks, chol, union, w[0]..w[1], m);
        let windows: Vec<&[usize]> = bounds.windows(2).collect();
        let rows: Vec<Vec<f64>> = if windows.len() > 1 {
            windows.par_iter().map(|w| group_rows(w)).collect()
        } else {
            windows.iter().map(|w| group_rows(w)).collect()
        };
        for (w, g) in windows.iter().zip(&rows) {
            for ja in w[0]..w[1] {
                let row = &g[(ja - w[0]) * m..][..m];
                self.gram[ja * stride..ja * stride + m].copy_from_slice(row);
                for (jk, &v) in row.iter().enumerate().take(first) {
                    self.gram[jk * stride + ja] = v;
                }
            }
        }
    }

    /// Forward-solves the new columns `first..` (scattered into their blocks) on
    /// the supernodes `union` of their paths (ascending): per supernode a dense
    /// triangular solve and product for all of a group's columns there, and the
    /// product subtracted from the ancestors' rows. The columns are cut into
    /// contiguous groups of balanced work, as many as the full solves use parallel
    /// parts ([`CholeskySolver::solve_parts`]: one per rayon thread on a factor
    /// big enough), solved in parallel:
    /// a group's columns are contiguous in every block (columns are stored in
    /// index order), so each group owns a slice of each block, and a column's
    /// values do not depend on the grouping.
    /// Returns the groups' bounds (`first`, …, `m`).
    fn solve_new(&mut self, chol: &CholeskySolver, union: &[usize], first: usize) -> Vec<usize> {
        let m = self.paths.len();
        if m == first {
            return vec![first, m];
        }
        // Work of each new column (c² + 2 c p per supernode on its path).
        let work: Vec<f64> = self.paths[first..]
            .iter()
            .map(|path| {
                path.iter()
                    .map(|&(s, _)| {
                        let (c, p) = width(chol, s as usize);
                        c * c + 2.0 * c * p
                    })
                    .sum()
            })
            .collect();
        let bounds = balanced_groups(&work, first, chol.solve_parts().clamp(1, m - first));
        let groups = bounds.len() - 1;
        let mut index = vec![u32::MAX; self.blocks.len()];
        for (u, &s) in union.iter().enumerate() {
            index[s] = u as u32;
        }
        let mut slices = group_slices(&mut self.blocks, chol, &index, union.len(), &bounds);
        let paths = &self.paths;
        let solve = |slices: &mut Vec<GroupSlice>| forward_group(chol, union, &index, paths, slices);
        if groups > 1 {
            slices.par_iter_mut().for_each(solve);
        } else {
            slices.iter_mut().for_each(solve);
        }
        bounds
    }

    /// `G[a, b] = v_aᵀ v_b`.
    pub fn gram(&self, a: usize, b: usize) -> f64 {
        self.gram[a * self.stride + b]
    }

    /// `v_jᵀ z` for a vector `z` in the elimination order.
    pub fn dot(&self, chol: &CholeskySolver, j: usize, z: &[f64]) -> f64 {
        let begin = chol.supernodal().supernode_begin();
        self.paths[j]
            .iter()
            .map(|&(s, pos)| {
                let (s, pos) = (s as usize, pos as usize);
                let b = begin[s];
                let c = chol.supernodal().supernode_end()[s] - b;
                let v = &self.blocks[s].vals[pos * c..(pos + 1) * c];
                v.iter().zip(&z[b..b + c]).map(|(x, y)| x * y).sum::<f64>()
            })
            .sum()
    }

    /// `v_jᵀ z` for each column `j` of `columns`, in parallel (each product is
    /// summed as [`Columns::dot`] sums it).
    pub fn dots(&self, chol: &CholeskySolver, columns: &[usize], z: &[f64]) -> Vec<f64> {
        if chol.solve_parts() > 1 {
            columns.par_iter().map(|&j| self.dot(chol, j, z)).collect()
        } else {
            columns.iter().map(|&j| self.dot(chol, j, z)).collect()
        }
    }

    /// `z ← z − Σ_k a_k v_{j_k}` for the `(j_k, a_k)` of `terms`, in their order:
    /// every entry of `z` receives the same subtractions in the same order as
    /// from `z ← z − a_k v_{j_k}` done for one term after another, so the result
    /// does not depend on how the rows are cut. With parallel solve parts the
    /// rows are cut at supernode boundaries into as many ranges of about equal
    /// stored values, and the ranges are done in parallel.
    pub fn subtract_all(&self, chol: &CholeskySolver, terms: &[(usize, f64)], z: &mut [f64]) {
        let sn = chol.supernodal();
        let n_sn = sn.n_supernodes();
        // Supernodes where the ranges start (the first at 0), then the end.
        let mut cuts = vec![0];
        let parts = chol.solve_parts();
        if parts > 1 {
            let mut sizes: Vec<(usize, usize)> = self
                .touched
                .iter()
                .map(|&s| (s, self.blocks[s].vals.len()))
                .collect();
            sizes.sort_unstable();
            let mut acc = 0;
            for &(s, size) in &sizes {
                if acc >= self.stored * cuts.len() / parts && cuts.len() < parts && s > 0 {
                    cuts.push(s);
                }
                acc += size;
            }
        }
        cuts.push(n_sn);
        let n = z.len();
        let first_row = |s: usize| if s < n_sn { sn.supernode_begin()[s] } else { n };
        let mut ranges = cut_at(z, &cuts, first_row);
        let run = |(supernodes, z): &mut (std::ops::Range<usize>, &mut [f64])| {
            for &(j, a) in terms {
                self.subtract_on(chol, j, a, supernodes.clone(), z);
            }
        };
        if ranges.len() > 1 {
            ranges.par_iter_mut().for_each(run);
        } else {
            ranges.iter_mut().for_each(run);
        }
    }

    /// `z ← z − a v_j` on the `supernodes` of column `j`'s path, `z` holding
    /// the rows of those supernodes only.
    fn subtract_on(
        &self,
        chol: &CholeskySolver,
        j: usize,
        a: f64,
        supernodes: std::ops::Range<usize>,
        z: &mut [f64],
    ) {
        let sn = chol.supernodal();
        let offset = sn.supernode_begin().get(supernodes.start).copied().unwrap_or(0);
        let path = &self.paths[j];
        let first = path.partition_point(|&(s, _)| (s as usize) < supernodes.start);
        for &(s, pos) in path[first..].iter().take_while(|&&(s, _)| (s as usize) < supernodes.end) {
            let (s, pos) = (s as usize, pos as usize);
            let b = sn.supernode_begin()[s] - offset;
            let c = sn.supernode_end()[s] - sn.supernode_begin()[s];
            let v = &self.blocks[s].vals[pos * c..(pos + 1) * c];
            for (x, y) in z[b..b + c].iter_mut().zip(v) {
                *x -= a * y;
            }
        }
    }

    /// Position of column `j` in the block of supernode `s` (on its path).
    fn position(&self, j: usize, s: usize) -> usize {
        position(&self.paths, j, s)
    }
}

/// A column group's share of one block: the position of its first column in the
/// block, the block's columns and the group's values.
type GroupSlice<'a> = (usize, &'a [u32], &'a mut [f64]);

/// Position of column `j` in the block of supernode `s` (on its path).
fn position(paths: &[Vec<(u32, u32)>], j: usize, s: usize) -> usize {
    let path = &paths[j];
    let i = path
        .binary_search_by_key(&(s as u32), |&(t, _)| t)
        .expect("an ancestor of a column's supernode is on its path");
    path[i].1 as usize
}


/// The columns `first..first + work.len()` cut into at most `groups`
/// contiguous groups of about equal `work` (a group closes once the work up to
/// it reaches its share of the total): the groups' bounds, `first` to the end,
/// without an empty group.
fn balanced_groups(work: &[f64], first: usize, groups: usize) -> Vec<usize> {
    let total: f64 = work.iter().sum();
    let mut bounds = vec![first];
    let mut acc = 0.0;
    for (k, w) in work.iter().enumerate() {
        acc += w;
        if bounds.len() < groups && acc >= total * bounds.len() as f64 / groups as f64 {
            bounds.push(first + k + 1);
        }
    }
    bounds.push(first + work.len());
    bounds.dedup();
    bounds
}

/// Each group's share (between consecutive `bounds`) of the blocks of the
/// supernodes with an `index` in the union (`union_len` of them), in the
/// union's order: the position of its first column in the block, the block's
/// columns and its values, split off the blocks so the groups can be solved in
/// parallel.
fn group_slices<'a>(
    blocks: &'a mut [Block],
    chol: &CholeskySolver,
    index: &[u32],
    union_len: usize,
    bounds: &[usize],
) -> Vec<Vec<GroupSlice<'a>>> {
    let sn = chol.supernodal();
    let groups = bounds.len() - 1;
    let mut slices: Vec<Vec<GroupSlice>> =
        (0..groups).map(|_| Vec::with_capacity(union_len)).collect();
    for (s, blk) in blocks.iter_mut().enumerate() {
        if index[s] == u32::MAX {
            continue;
        }
        let c = sn.supernode_end()[s] - sn.supernode_begin()[s];
        let Block { cols, vals } = blk;
        let cols: &[u32] = cols;
        let mut rest: &mut [f64] = vals;
        let mut at = 0;
        for (g, w) in bounds.windows(2).enumerate() {
            let lo = cols.partition_point(|&j| (j as usize) < w[0]);
            let hi = cols.partition_point(|&j| (j as usize) < w[1]);
            let tail = std::mem::take(&mut rest).split_at_mut((lo - at) * c).1;
            let (mine, after) = tail.split_at_mut((hi - lo) * c);
            slices[g].push((lo, cols, mine));
            rest = after;
            at = hi;
        }
    }
    slices
}

/// Forward-solves one group's columns on the supernodes `union` (ascending,
/// `slices` the group's share of each, `index` a supernode's place in the
/// union): per supernode `x ← L_ss⁻¹ x` and the product `L_ps x` subtracted
/// from the ancestors' rows ([`subtract_from_ancestors`]).
fn forward_group(
    chol: &CholeskySolver,
    union: &[usize],
    index: &[u32],
    paths: &[Vec<(u32, u32)>],
    slices: &mut [GroupSlice],
) {
    let l = chol.factor();
    let mut tmp: Vec<f64> = Vec::new();
    for (u, &s) in union.iter().enumerate() {
        let node = l.supernode(s);
        let lv = node.val();
        let c = lv.ncols();
        let (head, after) = slices.split_at_mut(u + 1);
        let (lo, cols, x) = &mut head[u];
        let k = x.len() / c;
        if k == 0 {
            continue;
        }
        let (top, bottom) = lv.split_at_row(c);
        let mut xm = MatMut::from_column_major_slice_mut(x, c, k);
        solve_lower_triangular_in_place(top, xm.as_mut(), Par::Seq);
        let pattern = node.pattern();
        if pattern.is_empty() {
            continue;
        }
        tmp.clear();
        tmp.resize(pattern.len() * k, 0.0);
        let tm = MatMut::from_column_major_slice_mut(&mut tmp, pattern.len(), k);
        matmul(tm, Accum::Replace, bottom, xm.as_ref(), 1.0, Par::Seq);
        let group = &cols[*lo..*lo + k];
        subtract_from_ancestors(chol, pattern, &tmp, group, paths, after, |t| {
            index[t] as usize - u - 1
        });
    }
}

/// `x_t[rows] −= product[rows]` for each column `j` of `group` on the
/// ancestors `t` its supernode's `pattern` reaches: `product` holds one
/// column of `pattern.len()` values per column of the group, the pattern runs
/// through the ancestors in ascending runs, and `after[slot(t)]` is the
/// group's share of the block of `t`.
fn subtract_from_ancestors(
    chol: &CholeskySolver,
    pattern: &[usize],
    product: &[f64],
    group: &[u32],
    paths: &[Vec<(u32, u32)>],
    after: &mut [GroupSlice],
    slot: impl Fn(usize) -> usize,
) {
    let sn = chol.supernodal();
    let rows = pattern.len();
    let mut i = 0;
    while i < rows {
        let t = chol.supernode_of(pattern[i]);
        let begin = sn.supernode_begin()[t];
        let end = sn.supernode_end()[t];
        let run = pattern[i..].partition_point(|&r| r < end);
        let ct = end - begin;
        let (lo_t, _, dst_all) = &mut after[slot(t)];
        for (q, &j) in group.iter().enumerate() {
            let pos = position(paths, j as usize, t) - *lo_t;
            let dst = &mut dst_all[pos * ct..(pos + 1) * ct];
            let src = &product[q * rows + i..q * rows + i + run];
            for (&r, &v) in pattern[i..i + run].iter().zip(src) {
                dst[r - begin] -= v;
            }
        }
        i += run;
    }
}

/// The rows `a` of the Gram matrix `G = VᵀV` of `m` columns (row-major,
/// `a.len() × m`), summed supernode by supernode over `union` (ascending) as
/// `x_aᵀ x_all` of the columns stored there: the same sums in the same order
/// for any cut of the rows into groups.
fn gram_rows(blocks: &[Block], chol: &CholeskySolver, union: &[usize], a: Range<usize>, m: usize) -> Vec<f64> {
    let sn = chol.supernodal();
    let (a0, a1) = (a.start, a.end);
    let mut g = vec![0.0; (a1 - a0) * m];
    for &s in union {
        let blk = &blocks[s];
        let c = sn.supernode_end()[s] - sn.supernode_begin()[s];
        let lo = blk.cols.partition_point(|&j| (j as usize) < a0);
        let hi = blk.cols.partition_point(|&j| (j as usize) < a1);
        if lo == hi {
            continue;
        }
        let x_group = MatRef::from_column_major_slice(&blk.vals[lo * c..hi * c], c, hi - lo);
        let x_all = MatRef::from_column_major_slice(&blk.vals, c, blk.cols.len());
        let mut h = Mat::<f64>::zeros(hi - lo, blk.cols.len());
        matmul(
            h.as_mut(),
            Accum::Replace,
            x_group.transpose(),
            x_all,
            1.0,
            Par::Seq,
        );
        for a in 0..hi - lo {
            let row = &mut g[(blk.cols[lo + a] as usize - a0) * m..][..m];
            for (k, &jk) in blk.cols.iter().enumerate() {
                row[jk as usize] += h[(a, k)];
            }
        }
    }
    g
}

/// Width `c` and rows below `p` of supernode `s`.
fn width(chol: &CholeskySolver, s: usize) -> (f64, f64) {
    let sn = chol.supernodal();
    let c = sn.supernode_end()[s] - sn.supernode_begin()[s];
    (c as f64, sn.supernode(s).pattern().len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::linear::tests::factored_laplacian;

    /// Correction columns solved on their tree paths are the full forward solves
    /// `L⁻¹ P w` of their sparse right-hand sides (their products with a vector and
    /// the Gram matrix agree to 1e-13, columns added in four batches), and
    /// `z − Σ a_k v_k` from `dots` and `subtract_all` is the same to the last bit
    /// with the rows cut into 1, 2 or 3 ranges, and the dense sum to 1e-13: a
    /// 5-point Laplacian of a 90 × 90 grid, AMD order (a branching tree).
    #[test]
    fn columns_are_forward_solves_and_cut_subtraction_is_exact() {
        let m = 90;
        let n = m * m;
        let (mut s, _) = factored_laplacian(m, 4.01);
        // Seven columns like a coupling element's: a few rows of one neighbourhood.
        let rows: Vec<Vec<(usize, f64)>> = [17usize, 2345, 4050, 4051, 6000, 8099, 3]
            .iter()
            .enumerate()
            .map(|(c, &e)| {
                (0..4)
                    .map(|i| ((e + i * m) % n, (1.0 + c as f64) * (0.5 - 0.3 * i as f64)))
                    .collect()
            })
            .collect();
        let cols: Vec<SparseColumn> = rows
            .iter()
            .map(|r| SparseColumn {
                entries: r.iter().map(|&(e, w)| (s.permuted(e), w)).collect(),
            })
            .collect();
        let full: Vec<Vec<f64>> = rows
            .iter()
            .map(|r| {
                let mut b = vec![0.0; n];
                for &(e, w) in r {
                    b[e] += w;
                }
                let mut z = vec![0.0; n];
                s.forward(&b, &mut z);
                z
            })
            .collect();
        let mut columns = Columns::default();
        // In four batches: the Gram matrix grows (2, 4, 8 entries a row) and is
        // also extended in place (the third).
        for (range, stride) in [(0..2, 2), (2..3, 4), (3..4, 4), (4..7, 8)] {
            let paths = cols[range.clone()].iter().map(|c| Columns::path(&s, c)).collect();
            let allocated = columns.gram_bytes_with(range.end);
            assert_eq!(columns.add(&s, &cols[range.clone()], paths), range.start);
            assert_eq!(columns.stride, stride);
            assert_eq!(allocated, if range == (3..4) { 0 } else { 8 * stride * stride });
        }
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let y: Vec<f64> = (0..n).map(|i| (0.11 * i as f64).cos()).collect();
        for (a, va) in full.iter().enumerate() {
            let exact = dot(va, &y);
            assert!((columns.dot(&s, a, &y) - exact).abs() < 1e-13 * dot(va, va).sqrt() * 90.0);
            for (b, vb) in full.iter().enumerate() {
                let g = dot(va, vb);
                assert!((columns.gram(a, b) - g).abs() < 1e-13 * columns.gram(a, a).max(1.0));
            }
        }
        let picked = [6usize, 0, 3, 2, 5];
        let mut results = Vec::new();
        for parts in [1, 2, 3] {
            assert_eq!(s.set_solve_parts(parts), parts);
            let mut z = y.clone();
            let t = columns.dots(&s, &picked, &z);
            let terms: Vec<(usize, f64)> =
                picked.iter().zip(&t).map(|(&j, &tj)| (j, 0.25 * tj - 1.0)).collect();
            columns.subtract_all(&s, &terms, &mut z);
            results.push((t, z));
        }
        for r in &results[1..] {
            assert_eq!(r.0, results[0].0);
            assert_eq!(r.1, results[0].1);
        }
        let (t, z) = &results[0];
        let mut expected = y.clone();
        for (&j, &tj) in picked.iter().zip(t) {
            for (e, v) in expected.iter_mut().zip(&full[j]) {
                *e -= (0.25 * tj - 1.0) * v;
            }
        }
        for (p, q) in z.iter().zip(&expected) {
            assert!((p - q).abs() < 1e-13 * q.abs().max(1.0));
        }
    }

    /// Columns of unequal work cut into groups: each group closes once the
    /// running work reaches its share of the total (10 of 20 for two groups;
    /// equal work into three: 2 + 2 + 2), never more groups than asked, no
    /// empty group, the bounds starting at `first` and ending past the last.
    #[test]
    fn groups_balance_the_work_of_contiguous_columns() {
        assert_eq!(balanced_groups(&[4.0, 6.0, 5.0, 5.0], 7, 2), vec![7, 9, 11]);
        assert_eq!(balanced_groups(&[1.0; 6], 0, 3), vec![0, 2, 4, 6]);
        assert_eq!(balanced_groups(&[1.0, 9.0], 3, 1), vec![3, 5]);
        assert_eq!(balanced_groups(&[9.0, 1.0], 0, 2), vec![0, 1, 2]);
        // A heavy column closes the first group; each later one then reaches
        // the next share at once.
        assert_eq!(balanced_groups(&[0.0, 30.0, 1.0, 1.0], 0, 3), vec![0, 2, 3, 4]);
        // Three groups asked of two columns: two groups (the last bound once).
        assert_eq!(balanced_groups(&[1.0, 1.0], 0, 3), vec![0, 1, 2]);
    }

}
