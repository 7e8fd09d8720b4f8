//! Subtree-parallel forward and backward solves with the supernodal Cholesky factor.
//!
//! Each supernode's forward step `x_s = L_ss⁻¹ z_s`, `z_p ← z_p − L_ps x_s` writes only
//! rows of its elimination-tree ancestors, and each backward step
//! `x_s = L_ssᵀ⁻¹ (z_s − L_psᵀ x_p)` reads only them. So disjoint subtrees of the
//! supernodal tree can be solved at the same time. [`SubtreeSplit`] cuts the tree
//! below its top supernodes (the separators of a nested-dissection ordering) into
//! subtrees of balanced work (factor values), packed into as many parts as rayon has
//! threads, each part solved on its own thread:
//!
//! - forward: the parts in parallel, each writing its updates of the top rows into a
//!   private buffer; the buffers are then subtracted from the top rows in part order,
//!   and the top supernodes are solved in sequence;
//! - backward: the top supernodes in sequence first, then the parts in parallel, which
//!   read the top rows (from a copy) and write only their own rows.
//!
//! faer numbers the supernodes children before parents, but not always in
//! postorder (a subtree's range of numbers can hold a supernode of another
//! subtree), so the split is built only when each subtree it hands out is a
//! contiguous range; such a subtree owns a contiguous range of `z` (and of the
//! factor's values), split off safely with `split_at_mut`.
//!
//! The result equals the sequential solve's up to the order in which the updates of
//! a top row are summed (per part, then the parts), and both are backward-stable
//! triangular solves with the same bound: the computed `x` solves `(L + ΔL) x = z`
//! with `|ΔL| ≤ γ_m |L|`, `γ_m = m u / (1 − m u)`, `m` the most terms summed into one
//! row (Higham, *Accuracy and Stability*, Thm. 8.5 holds for any summation order).
//! The kernels are generic over faer's index type.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::{Accum, Index, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::ops::Range;

/// Below this many factor values a solve stays sequential (the threads would
/// cost more than they save).
pub const PARALLEL_MIN_VALUES: usize = 1 << 18;

/// Most top supernodes tried when splitting (each split moves one subtree root to
/// the top).
const MAX_SPLITS: usize = 4096;

/// Splits tried past the best one before the search stops.
const MAX_STALE: usize = 64;

/// A subtree of the supernodal tree: its supernodes and columns (both contiguous).
#[derive(Debug, Clone)]
struct Subtree {
    supernodes: Range<usize>,
    columns: Range<usize>,
}

/// The supernodal elimination tree cut into top supernodes and disjoint subtrees
/// below them, the subtrees packed into parts of balanced work.
#[derive(Debug, Clone)]
pub struct SubtreeSplit {
    /// The subtrees of each part.
    parts: Vec<Vec<Subtree>>,
    /// The top supernodes (closed under the parent), ascending.
    top: Vec<usize>,
    /// Per supernode: the position of its first column in the compact vector of
    /// the top rows (`usize::MAX` below the top).
    top_offset: Vec<usize>,
    /// Number of top rows.
    top_len: usize,
    /// Factor values on the top supernodes and in the heaviest part, over all.
    critical: f64,
}

impl SubtreeSplit {
    /// Splits the tree of `sn` (with `parent[s]` the parent of supernode `s`,
    /// `usize::MAX` for a root) into `parts` parts. `None` when the tree cannot be
    /// split usefully (one part, a chain, non-contiguous subtrees, or a critical
    /// path above 90 % of the sequential work).
    pub fn new<I: Index>(
        sn: &SymbolicSupernodalCholesky<I>,
        parent: &[usize],
        parts: usize,
    ) -> Option<Self> {
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        Self::with_work(sn, parent, parts, |s| {
            let c = end[s].zx() - begin[s].zx();
            (c * (c + sn.supernode(s).pattern().len())) as f64
        })
    }

    /// [`SubtreeSplit::new`] with the work of supernode `s` given by `own_work(s)`
    /// (factor values for a solve, flops for a factorization).
    pub fn with_work<I: Index>(
        sn: &SymbolicSupernodalCholesky<I>,
        parent: &[usize],
        parts: usize,
        own_work: impl Fn(usize) -> f64,
    ) -> Option<Self> {
        let ns = sn.n_supernodes();
        if parts < 2 || ns < 2 || parent.len() != ns {
            return None;
        }
        let tree = Tree::new(parent, own_work)?;
        let total = tree.total();
        let (critical, frontier) = tree.best_frontier(parts, total)?;
        if critical > 0.9 * total {
            return None;
        }
        if frontier.iter().any(|&s| !tree.is_contiguous(s)) {
            return None;
        }
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        Some(Self::below(begin, end, &tree, &frontier, parts, critical / total))
    }

    /// The split with the subtrees of the roots `frontier` packed into `parts`
    /// parts and every other supernode on top (`begin`, `end`: the supernodes'
    /// column ranges; `critical`: the critical path's fraction of the work).
    fn below<I: Index>(
        begin: &[I],
        end: &[I],
        tree: &Tree,
        frontier: &[usize],
        parts: usize,
        critical: f64,
    ) -> Self {
        let ns = tree.work.len();
        let (bins, _) = pack(frontier, &tree.work, parts);
        let mut below = vec![false; ns];
        let parts: Vec<Vec<Subtree>> = bins
            .into_iter()
            .map(|bin| {
                bin.into_iter()
                    .map(|s| {
                        let first = tree.first[s];
                        below[first..=s].fill(true);
                        Subtree {
                            supernodes: first..s + 1,
                            columns: begin[first].zx()..end[s].zx(),
                        }
                    })
                    .collect()
            })
            .collect();
        let top: Vec<usize> = (0..ns).filter(|&s| !below[s]).collect();
        let mut top_offset = vec![usize::MAX; ns];
        let mut top_len = 0;
        for &s in &top {
            top_offset[s] = top_len;
            top_len += end[s].zx() - begin[s].zx();
        }
        SubtreeSplit {
            parts,
            top,
            top_offset,
            top_len,
            critical,
        }
    }

    /// Number of parts solved in parallel.
    pub fn parts(&self) -> usize {
        self.parts.len()
    }

    /// The subtrees of each part: their supernodes (each a contiguous range).
    pub fn part_subtrees(&self) -> impl Iterator<Item = Vec<Range<usize>>> + '_ {
        self.parts
            .iter()
            .map(|ts| ts.iter().map(|t| t.supernodes.clone()).collect())
    }

    /// The top supernodes (closed under the parent), ascending.
    pub fn top(&self) -> &[usize] {
        &self.top
    }

    /// The critical path (top supernodes and heaviest part) over the whole work,
    /// in factor values: the best speed-up is its inverse.
    pub fn critical_fraction(&self) -> f64 {
        self.critical
    }

    /// `z ← L⁻¹ z` (in the elimination order), the parts in parallel.
    /// `supernode_of[j]` is the supernode of column `j`. With `set` (supernodes
    /// closed under the parent, descending, as from
    /// [`super::linear::CholeskySolver::ancestors`]), `z` is zero outside `set` and
    /// only its supernodes are visited (as [`super::linear::CholeskySolver::forward_on`]).
    pub fn forward<I: Index>(
        &self,
        l: SupernodalLltRef<'_, I, f64>,
        supernode_of: &[u32],
        set: Option<&[usize]>,
        z: &mut [f64],
    ) {
        let begin = l.symbolic().supernode_begin();
        let mut tasks: Vec<(Vec<Piece>, Vec<f64>)> = self
            .split(z)
            .into_iter()
            .map(|t| (t, vec![0.0; self.top_len]))
            .collect();
        let top = self.spill(supernode_of, begin);
        tasks.par_iter_mut().for_each(|(subtrees, spill)| {
            let mut below = Vec::new();
            for (t, zt) in subtrees.iter_mut() {
                forward_nodes(l, nodes_in(set, &t.supernodes).rev(), zt, t.columns.clone(), |r, v| {
                    spill[top.position(r)] += v
                }, &mut below);
            }
        });
        let spills: Vec<Vec<f64>> = tasks.into_iter().map(|(_, spill)| spill).collect();
        for spill in &spills {
            for (rows, at) in self.top_blocks(l) {
                for (x, v) in z[rows].iter_mut().zip(&spill[at]) {
                    *x -= v;
                }
            }
        }
        let n = z.len();
        forward_nodes(l, self.top_nodes(set).rev(), z, 0..n, |_, _| {
            unreachable!("the top is closed under the parent")
        }, &mut Vec::new());
    }

    /// `z ← L⁻ᵀ z` (in the elimination order): the top in sequence, then the parts
    /// in parallel. With `set` (as for [`SubtreeSplit::forward`]), only its
    /// supernodes are solved (as [`super::linear::CholeskySolver::backward_on`]).
    pub fn backward<I: Index>(
        &self,
        l: SupernodalLltRef<'_, I, f64>,
        supernode_of: &[u32],
        set: Option<&[usize]>,
        z: &mut [f64],
    ) {
        let begin = l.symbolic().supernode_begin();
        let n = z.len();
        let mut below = Vec::new();
        backward_nodes(l, self.top_nodes(set), z, 0..n, |_| {
            unreachable!("the top is closed under the parent")
        }, &mut below);
        let mut top_z = vec![0.0; self.top_len];
        for (rows, at) in self.top_blocks(l) {
            top_z[at].copy_from_slice(&z[rows]);
        }
        let top = self.spill(supernode_of, begin);
        let mut tasks = self.split(z);
        tasks.par_iter_mut().for_each(|subtrees| {
            let mut below = Vec::new();
            for (t, zt) in subtrees.iter_mut() {
                backward_nodes(l, nodes_in(set, &t.supernodes), zt, t.columns.clone(), |r| {
                    top_z[top.position(r)]
                }, &mut below);
            }
        });
    }

    /// Per top supernode: its rows in `z` and where they sit in the compact
    /// vector of the top rows.
    fn top_blocks<'a, I: Index>(
        &'a self,
        l: SupernodalLltRef<'a, I, f64>,
    ) -> impl Iterator<Item = (Range<usize>, Range<usize>)> + 'a {
        let (begin, end) = (l.symbolic().supernode_begin(), l.symbolic().supernode_end());
        self.top.iter().map(move |&s| {
            let (b, e, o) = (begin[s].zx(), end[s].zx(), self.top_offset[s]);
            (b..e, o..o + e - b)
        })
    }

    /// The map from a top row to its position in the compact vector of the top
    /// rows.
    fn spill<'a, I: Index>(&'a self, supernode_of: &'a [u32], begin: &'a [I]) -> Spill<'a, I> {
        Spill {
            supernode_of,
            top_offset: &self.top_offset,
            begin,
        }
    }

    /// The top supernodes (of `set` if given), descending.
    fn top_nodes<'a>(&'a self, set: Option<&'a [usize]>) -> Box<dyn DoubleEndedIterator<Item = usize> + 'a> {
        match set {
            Some(set) => Box::new(set.iter().copied().filter(|&s| self.top_offset[s] != usize::MAX)),
            None => Box::new(self.top.iter().rev().copied()),
        }
    }

    /// `z` cut into the columns of each part's subtrees.
    fn split<'z>(&'z self, z: &'z mut [f64]) -> Vec<Vec<Piece<'z>>> {
        let mut all: Vec<(usize, &Subtree)> = self
            .parts
            .iter()
            .enumerate()
            .flat_map(|(p, ts)| ts.iter().map(move |t| (p, t)))
            .collect();
        all.sort_by_key(|(_, t)| t.columns.start);
        let mut out: Vec<Vec<Piece>> =
            (0..self.parts.len()).map(|_| Vec::new()).collect();
        let mut rest = z;
        let mut at = 0;
        for (p, t) in all {
            let tail = std::mem::take(&mut rest).split_at_mut(t.columns.start - at).1;
            let (mine, after) = tail.split_at_mut(t.columns.len());
            out[p].push((t, mine));
            rest = after;
            at = t.columns.end;
        }
        out
    }
}

/// The supernodes of `range` (of `set` if given: descending), descending.
fn nodes_in<'a>(
    set: Option<&'a [usize]>,
    range: &Range<usize>,
) -> Box<dyn DoubleEndedIterator<Item = usize> + 'a> {
    match set {
        Some(set) => {
            let from = set.partition_point(|&s| s >= range.end);
            let to = set.partition_point(|&s| s >= range.start);
            Box::new(set[from..to].iter().copied())
        }
        None => Box::new(range.clone().rev()),
    }
}

/// A subtree and its columns of the solution vector.
type Piece<'z> = (&'z Subtree, &'z mut [f64]);

/// The position of a top row in the compact vector of the top rows.
struct Spill<'a, I> {
    supernode_of: &'a [u32],
    top_offset: &'a [usize],
    begin: &'a [I],
}

impl<I: Index> Spill<'_, I> {
    fn position(&self, r: usize) -> usize {
        let s = self.supernode_of[r] as usize;
        self.top_offset[s] + r - self.begin[s].zx()
    }
}

/// The supernodal tree with its subtree sums (children are numbered before
/// their parents).
#[derive(Debug)]
struct Tree {
    /// Work of the subtree rooted at each supernode.
    work: Vec<f64>,
    /// First supernode (smallest number) of each subtree.
    first: Vec<usize>,
    /// Supernodes in each subtree.
    size: Vec<usize>,
    /// The children of each supernode, ascending.
    children: Vec<Vec<usize>>,
    /// The roots, ascending.
    roots: Vec<usize>,
}

impl Tree {
    /// The tree of `parent` (`usize::MAX` for a root) with the work of supernode
    /// `s` given by `own_work(s)`, its subtree sums accumulated children first;
    /// `None` when a parent is not numbered after its child.
    fn new(parent: &[usize], own_work: impl Fn(usize) -> f64) -> Option<Self> {
        let ns = parent.len();
        let mut work: Vec<f64> = (0..ns).map(own_work).collect();
        let mut first: Vec<usize> = (0..ns).collect();
        let mut size = vec![1usize; ns];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); ns];
        let mut roots = Vec::new();
        for s in 0..ns {
            let p = parent[s];
            if p == usize::MAX {
                roots.push(s);
                continue;
            }
            if p <= s || p >= ns {
                return None;
            }
            work[p] += work[s];
            first[p] = first[p].min(first[s]);
            size[p] += size[s];
            children[p].push(s);
        }
        Some(Tree {
            work,
            first,
            size,
            children,
            roots,
        })
    }

    /// The work of the whole tree (its roots' subtrees).
    fn total(&self) -> f64 {
        self.roots.iter().map(|&r| self.work[r]).sum()
    }

    /// The work of supernode `s` alone.
    fn own(&self, s: usize) -> f64 {
        self.work[s] - self.children[s].iter().map(|&c| self.work[c]).sum::<f64>()
    }

    /// True when the subtree of `s` is the contiguous range of supernodes
    /// `first[s]..=s`.
    fn is_contiguous(&self, s: usize) -> bool {
        self.size[s] == s + 1 - self.first[s]
    }

    /// The cut of the tree with the shortest critical path (the work above the
    /// cut plus the heaviest of `parts` parts packed from the subtrees below
    /// it), found greedily: the root of the heaviest subtree is moved to the top
    /// while that may shorten the path (at most `MAX_SPLITS` moves, stopping
    /// `MAX_STALE` moves past the best or once the top holds half of `total`).
    /// Returns the critical path and the roots of the subtrees below the cut.
    fn best_frontier(&self, parts: usize, total: f64) -> Option<(f64, Vec<usize>)> {
        let mut frontier = self.roots.clone();
        let mut top_work = 0.0;
        let mut best: Option<(f64, Vec<usize>)> = None;
        let mut stale = 0;
        for _ in 0..MAX_SPLITS.min(self.work.len()) {
            let loads = pack(&frontier, &self.work, parts).1;
            let cost = top_work + loads.iter().cloned().fold(0.0, f64::max);
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((cost, frontier.clone()));
                stale = 0;
            }
            stale += 1;
            if top_work > 0.5 * total || stale > MAX_STALE {
                break;
            }
            let Some((i, _)) = frontier
                .iter()
                .enumerate()
                .filter(|(_, s)| !self.children[**s].is_empty())
                .max_by(|a, b| self.work[*a.1].total_cmp(&self.work[*b.1]))
            else {
                break;
            };
            let s = frontier.swap_remove(i);
            top_work += self.own(s);
            frontier.extend_from_slice(&self.children[s]);
        }
        best
    }
}

/// The subtrees packed into `parts` bins, heaviest first into the lightest bin
/// (LPT), and the bins' loads.
fn pack(subtrees: &[usize], work: &[f64], parts: usize) -> (Vec<Vec<usize>>, Vec<f64>) {
    let mut order = subtrees.to_vec();
    order.sort_by(|a, b| work[*b].total_cmp(&work[*a]).then(a.cmp(b)));
    let mut bins = vec![Vec::new(); parts];
    let mut loads = vec![0.0f64; parts];
    for s in order {
        let i = (0..parts)
            .min_by(|a, b| loads[*a].total_cmp(&loads[*b]))
            .expect("parts ≥ 1");
        loads[i] += work[s];
        bins[i].push(s);
    }
    (bins, loads)
}

/// Forward steps on the supernodes `nodes` (ascending) with `z` holding the
/// columns `cols`: updates of rows past `cols` go to `spill(row, value)` (to be
/// subtracted).
fn forward_nodes<I: Index>(
    l: SupernodalLltRef<'_, I, f64>,
    nodes: impl Iterator<Item = usize>,
    z: &mut [f64],
    cols: Range<usize>,
    mut spill: impl FnMut(usize, f64),
    below: &mut Vec<f64>,
) {
    for s in nodes {
        let node = l.supernode(s);
        let b = node.start() - cols.start;
        let val = node.val();
        let c = val.ncols();
        let (top, bottom) = val.split_at_row(c);
        let mut x = MatMut::from_column_major_slice_mut(&mut z[b..b + c], c, 1);
        solve_lower_triangular_in_place(top, x.as_mut(), Par::Seq);
        let pattern = node.pattern();
        if pattern.is_empty() {
            continue;
        }
        below.clear();
        below.resize(pattern.len(), 0.0);
        let t = MatMut::from_column_major_slice_mut(below, pattern.len(), 1);
        matmul(t, Accum::Replace, bottom, x.as_ref(), 1.0, Par::Seq);
        for (&r, &v) in pattern.iter().zip(below.iter()) {
            let r = r.zx();
            if r < cols.end {
                z[r - cols.start] -= v;
            } else {
                spill(r, v);
            }
        }
    }
}

/// Backward steps on the supernodes `nodes` (descending) with `z` holding the
/// columns `cols`: rows past `cols` are read with `outside(row)`.
fn backward_nodes<I: Index>(
    l: SupernodalLltRef<'_, I, f64>,
    nodes: impl Iterator<Item = usize>,
    z: &mut [f64],
    cols: Range<usize>,
    outside: impl Fn(usize) -> f64,
    below: &mut Vec<f64>,
) {
    for s in nodes {
        let node = l.supernode(s);
        let b = node.start() - cols.start;
        let val = node.val();
        let c = val.ncols();
        let (top, bottom) = val.split_at_row(c);
        let pattern = node.pattern();
        below.clear();
        below.extend(pattern.iter().map(|r| {
            let r = r.zx();
            if r < cols.end {
                z[r - cols.start]
            } else {
                outside(r)
            }
        }));
        let mut x = MatMut::from_column_major_slice_mut(&mut z[b..b + c], c, 1);
        if !pattern.is_empty() {
            let xp = MatRef::from_column_major_slice(below, pattern.len(), 1);
            matmul(x.as_mut(), Accum::Add, bottom.transpose(), xp, -1.0, Par::Seq);
        }
        solve_upper_triangular_in_place(top.transpose(), x, Par::Seq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Subtree sums of a small tree, children numbered first: 0, 1 → 2 and
    /// 2, 3 → 4, the work of each subtree the sum of its own (1, 2, 4, 8, 16),
    /// its first supernode and size; a parent numbered before its child is refused.
    #[test]
    fn tree_sums_its_subtrees_and_refuses_a_parent_before_its_child() {
        let parent = [2, 2, 4, 4, usize::MAX];
        let tree = Tree::new(&parent, |s| (1u32 << s) as f64).unwrap();
        assert_eq!(tree.work, vec![1.0, 2.0, 7.0, 8.0, 31.0]);
        assert_eq!(tree.first, vec![0, 1, 0, 3, 0]);
        assert_eq!(tree.size, vec![1, 1, 3, 1, 5]);
        assert_eq!(tree.roots, vec![4]);
        assert_eq!(tree.total(), 31.0);
        assert_eq!(tree.own(2), 4.0);
        assert!((0..5).all(|s| tree.is_contiguous(s)));
        assert!(Tree::new(&[usize::MAX, 0], |_| 1.0).is_none());
    }

    /// A root over two equal leaves: cutting below the root gives a critical
    /// path of the root's own work plus one leaf (1 + 10, against 21 uncut),
    /// and the split puts one leaf in each part and the root on top.
    #[test]
    fn the_best_cut_of_a_root_over_two_leaves_is_below_the_root() {
        let parent = [2, 2, usize::MAX];
        let tree = Tree::new(&parent, |s| if s < 2 { 10.0 } else { 1.0 }).unwrap();
        let (critical, frontier) = tree.best_frontier(2, tree.total()).unwrap();
        assert_eq!(critical, 11.0);
        assert_eq!(frontier, vec![0, 1]);
        let (begin, end) = ([0usize, 2, 4], [2usize, 4, 5]);
        let split = SubtreeSplit::below(&begin, &end, &tree, &frontier, 2, critical / tree.total());
        assert_eq!(split.parts(), 2);
        let subtrees: Vec<Vec<Range<usize>>> = split.part_subtrees().collect();
        assert_eq!(subtrees, vec![vec![0..1], vec![1..2]]);
        assert_eq!(split.parts[1][0].columns, 2..4);
        assert_eq!(split.top(), &[2]);
        assert_eq!((split.top_offset[2], split.top_len), (0, 1));
    }
}
