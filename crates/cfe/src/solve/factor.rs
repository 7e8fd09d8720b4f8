//! Numeric supernodal Cholesky factorization `P K Pᵀ = L Lᵀ`, left-looking, with
//! disjoint subtrees of the elimination tree factorized on different threads.
//!
//! The factor has faer's supernodal layout ([`SymbolicSupernodalCholesky`]): the
//! columns `s0..s1` of supernode `s` are one dense column-major block of
//! `(c + p) × c` values, its `c × c` diagonal block on top of the `p` rows of its
//! pattern (ascending, all past `s1`). Supernode `s` is computed from `A = P K Pᵀ`
//! and the supernodes `d` of its subtree whose pattern meets its columns (its
//! *updaters*):
//!
//! ```text
//!   L_s ← A[s0.., s0..s1]                       (rows s0..s1 and the pattern of s)
//!   L_s[r_d, c_d] −= L_d[r_d, :] · L_d[c_d, :]ᵀ  for each updater d, ascending
//!   L_ss ← chol(L_ss),  L_ps ← L_ps · L_ssᵀ⁻¹
//! ```
//!
//! with `c_d` the rows of `d` among the columns of `s` and `r_d` the rows of `d`
//! from `s0` on (each a row of `s`: the pattern of a descendant past `s0` lies in
//! the columns and pattern of its ancestor). The product is formed in a small
//! dense block and subtracted through the row map of `s`.
//!
//! A supernode reads only its descendants, so the subtrees of a
//! [`SubtreeSplit`] (cut by flops) are factorized at the same time, one part per
//! thread with sequential kernels, each zeroing (first touching) its own values;
//! the top supernodes (the large separators) follow in order with faer's
//! parallel dense kernels, their updates split over column ranges on every
//! thread. A supernode's updates are always subtracted in the same order
//! (ascending `d`), so the schedule changes the factor only through the rounding
//! of faer's parallel kernels on the top supernodes.
//!
//! The block operations are faer's dense kernels (matrix product, Cholesky of the
//! diagonal block, triangular solve); this file owns only the schedule and the
//! scatter, which faer's own supernodal factorization runs one supernode after
//! another.

use super::subtree::SubtreeSplit;
use faer::dyn_stack::MemBuffer;
use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;
use faer::linalg::matmul::matmul;
use super::lower::LowerMatrix;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::borrow::Cow;
use std::ops::Range;
use std::sync::atomic::AtomicUsize;

mod dense;
use super::halt::check;
pub use super::halt::Halt;
use dense::{diagonal_cholesky, lower_solve};

/// Entries of the dense update block formed at once (8 MiB): wider updates are
/// formed a group of columns at a time.
const BLOCK_VALUES: usize = 1 << 20;

/// Supernodes with at least this many flops use faer's parallel dense kernels:
/// the top supernodes, or any when the tree is not split (below the top each
/// thread has subtrees of its own and uses sequential kernels).
const PARALLEL_KERNEL_FLOPS: f64 = 4.0e6;

/// What a numeric factorization needs beyond faer's symbolic structure: the
/// updaters of each supernode and the split of the tree into parallel parts.
#[derive(Debug, Clone)]
pub struct NumericPlan {
    /// `updaters[ptr[s]..ptr[s + 1]]`: the supernodes whose pattern meets the
    /// columns of `s`, ascending.
    ptr: Vec<usize>,
    updaters: Vec<u32>,
    /// Flops of each supernode's left-looking work (its diagonal block, the
    /// solve below it and the updates it receives).
    flops: Vec<f64>,
    /// Subtrees factorized in parallel (`None`: one thread).
    split: Option<SubtreeSplit>,
    /// Widest supernode (columns).
    max_cols: usize,
}

/// The scratch of one update loop: the rows of an updater mapped into the
/// supernode and the dense update block.
#[derive(Default)]
struct Scratch {
    rows: Vec<u32>,
    block: Vec<f64>,
}

/// One thread's scratch: the row map of the current supernode (row of the factor
/// → row of its block), the update loops' scratch (one per column range of a
/// large supernode) and the Cholesky kernel's stack.
struct Workspace {
    local: Vec<u32>,
    scratch: Vec<Scratch>,
    stack: MemBuffer,
}

impl Workspace {
    fn new(n: usize, max_cols: usize) -> Self {
        Workspace {
            local: vec![0; n],
            scratch: vec![Scratch::default()],
            stack: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                max_cols,
                Par::rayon(0),
                Default::default(),
            )),
        }
    }
}

impl NumericPlan {
    /// The plan of `sn`, with `supernode_of[j]` the supernode of column `j` and
    /// `parent[s]` the parent of supernode `s` (`usize::MAX` for a root), split
    /// into `parts` parallel parts (1: sequential) when the tree allows it.
    pub fn new(
        sn: &SymbolicSupernodalCholesky<usize>,
        supernode_of: &[u32],
        parent: &[usize],
        parts: usize,
    ) -> Self {
        let ns = sn.n_supernodes();
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        // Each (updater d, supernode s) pair once, with the rows of d from the
        // first column of s on (`m`) and those among its columns (`mid`).
        let each_update = |f: &mut dyn FnMut(usize, usize, usize, usize)| {
            for d in 0..ns {
                let pattern = sn.supernode(d).pattern();
                let mut i = 0;
                while i < pattern.len() {
                    let s = supernode_of[pattern[i]] as usize;
                    let mid = pattern[i..].partition_point(|&r| r < end[s]);
                    f(d, s, pattern.len() - i, mid);
                    i += mid;
                }
            }
        };
        let mut ptr = vec![0usize; ns + 1];
        // Left-looking work of each supernode: the Cholesky of its diagonal block,
        // the triangular solve below it and the updates it receives (the lower
        // trapezoid of an m × mid product of depth dc, multiply–adds counted twice).
        let mut flops: Vec<f64> = (0..ns)
            .map(|s| {
                let c = (end[s] - begin[s]) as f64;
                let p = sn.supernode(s).pattern().len() as f64;
                c * c * c / 3.0 + c * c * p
            })
            .collect();
        each_update(&mut |d, s, m, mid| {
            ptr[s + 1] += 1;
            let dc = (end[d] - begin[d]) as f64;
            flops[s] += dc * mid as f64 * (2 * m - mid) as f64;
        });
        for s in 0..ns {
            ptr[s + 1] += ptr[s];
        }
        let mut fill = ptr.clone();
        let mut updaters = vec![0u32; ptr[ns]];
        each_update(&mut |d, s, _, _| {
            updaters[fill[s]] = d as u32;
            fill[s] += 1;
        });
        let split = SubtreeSplit::with_work(sn, parent, parts, |s| flops[s]);
        let max_cols = (0..ns).map(|s| end[s] - begin[s]).max().unwrap_or(0);
        NumericPlan {
            ptr,
            updaters,
            flops,
            split,
            max_cols,
        }
    }

    /// Number of parts factorized in parallel (1: sequentially).
    pub fn parts(&self) -> usize {
        self.split.as_ref().map_or(1, |s| s.parts())
    }

    /// Factorizes `a`, the lower triangle of `P K Pᵀ` with the pattern `sn` was
    /// analysed from, into `values` (faer's layout, `sn.len_val()` values; every
    /// value is overwritten). A non-positive pivot is returned as its column in
    /// the elimination order (the smallest one if parts fail at the same time).
    /// `stop`, if given, is read before every supernode and inside each, before
    /// every block of an update (at most `BLOCK_VALUES` entries of a product)
    /// and before the Cholesky of its diagonal block and the solve below it, so a
    /// large separator alone does not delay a stop: once nonzero the
    /// factorization is abandoned with [`Halt::Stopped`] (a pivot failure found
    /// meanwhile by another part comes first). Reading it changes no value.
    ///
    /// With the tree split, the top supernodes' blocks are loaded from `a` first;
    /// each subtree then reads only its own columns of `a`, a contiguous range of
    /// its values. When `a` owns its values ([`LowerMatrix::with_values`]) each
    /// thread gives back the pages of the values its subtrees have read as it
    /// goes (`super::heap::discard`), so the matrix's values shrink while the
    /// factor's grow instead of sitting beside the whole factor.
    pub fn factorize(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        a: LowerMatrix<'_>,
        values: &mut [f64],
        stop: Option<&AtomicUsize>,
    ) -> Result<(), Halt> {
        assert_eq!(values.len(), sn.len_val(), "factor storage of another size");
        let (col_ptr, row_idx, mut a_values) = a.into_parts();
        let whole = Input {
            col_ptr,
            row_idx,
            values: &a_values,
            first: 0,
        };
        let Some(split) = &self.split else {
            return self.in_order(sn, Some(whole), 0..sn.n_supernodes(), values, stop);
        };
        load_top(sn, split, whole, values);
        let tasks = subtree_tasks(sn, split, col_ptr, values, &mut a_values);
        let failed = self.factorize_parts(sn, tasks, col_ptr, row_idx, stop);
        // Every column of `a` has been read.
        drop(a_values);
        if let Some(col) = failed {
            return Err(col);
        }
        self.in_order(sn, None, split.top().iter().copied(), values, stop)
    }

    /// The supernodes `nodes` computed one after another on this thread (each
    /// with faer's parallel kernels if it is large, see
    /// [`NumericPlan::kernel_par`]), their blocks loaded from `a` (`None`:
    /// loaded already), into `values` (the whole factor); `stop` is read before
    /// each.
    fn in_order(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        a: Option<Input<'_>>,
        nodes: impl Iterator<Item = usize>,
        values: &mut [f64],
        stop: Option<&AtomicUsize>,
    ) -> Result<(), Halt> {
        let mut ws = Workspace::new(sn.nrows(), self.max_cols);
        for s in nodes {
            check(stop)?;
            self.supernode(sn, a, s, values, 0, &mut ws, self.kernel_par(s), stop)?;
        }
        Ok(())
    }

    /// The subtrees of each part factorized, the parts in parallel (one thread
    /// each, sequential kernels): the first pivot failure or stop of any part
    /// (the smallest column if several parts fail), `None` when all succeed.
    fn factorize_parts(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        tasks: Vec<Vec<Subtree<'_>>>,
        col_ptr: &[usize],
        row_idx: &[u32],
        stop: Option<&AtomicUsize>,
    ) -> Option<Halt> {
        tasks
            .into_par_iter()
            .map(|subtrees| {
                let mut ws = Workspace::new(sn.nrows(), self.max_cols);
                for subtree in subtrees {
                    self.factorize_subtree(sn, subtree, col_ptr, row_idx, &mut ws, stop)?;
                }
                Ok(())
            })
            .filter_map(|r: Result<(), Halt>| r.err())
            .min()
    }

    /// The supernodes of one subtree computed in order with sequential
    /// kernels, each from its columns of `a`, whose pages are given back (when
    /// owned) as they are read, every `DISCARD_VALUES` values and at the end.
    fn factorize_subtree(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        subtree: Subtree<'_>,
        col_ptr: &[usize],
        row_idx: &[u32],
        ws: &mut Workspace,
        stop: Option<&AtomicUsize>,
    ) -> Result<(), Halt> {
        let Subtree {
            supernodes,
            values: vals,
            a: mut piece,
            a_first,
        } = subtree;
        let end = sn.supernode_end();
        let base = sn.col_ptr_for_val()[supernodes.start];
        let mut given_back = 0;
        for s in supernodes {
            check(stop)?;
            let input = Input {
                col_ptr,
                row_idx,
                values: piece.get(),
                first: a_first,
            };
            self.supernode(sn, Some(input), s, vals, base, ws, Par::Seq, stop)?;
            // The columns of `a` up to this supernode's are read.
            let read = col_ptr[end[s]] - a_first;
            if read >= given_back + DISCARD_VALUES {
                given_back = piece.discard(given_back, read);
            }
        }
        let read = piece.get().len();
        piece.discard(given_back, read);
        Ok(())
    }

    /// faer's parallel kernels for a large supernode, sequential ones otherwise.
    fn kernel_par(&self, s: usize) -> Par {
        if self.flops[s] >= PARALLEL_KERNEL_FLOPS && rayon::current_num_threads() > 1 {
            Par::rayon(0)
        } else {
            Par::Seq
        }
    }

    /// Computes supernode `s` into `vals`, which holds the values from offset
    /// `base` of the factor on (`s` and every supernode of its subtree before it),
    /// its block first loaded from `a` (`None`: loaded already, see [`load`]).
    /// `stop` is read between the blocks of its updates and before its dense
    /// kernels; once stopped, `ws`'s row map is left dirty (the factorization
    /// is abandoned with its workspace).
    #[allow(clippy::too_many_arguments)]
    fn supernode(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        a: Option<Input<'_>>,
        s: usize,
        vals: &mut [f64],
        base: usize,
        ws: &mut Workspace,
        par: Par,
        stop: Option<&AtomicUsize>,
    ) -> Result<(), Halt> {
        let val_ptr = sn.col_ptr_for_val();
        let (s0, s1) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        let nc = s1 - s0;
        let pattern = sn.supernode(s).pattern();
        let nr = nc + pattern.len();
        let (done, rest) = vals.split_at_mut(val_ptr[s] - base);
        let done: &[f64] = done;
        let ls = &mut rest[..nr * nc];
        for (i, &r) in pattern.iter().enumerate() {
            ws.local[r] = (nc + i) as u32;
        }
        if let Some(a) = a {
            scatter(a, s0, s1, nr, ls, &ws.local);
        }
        // The updates of its descendants, over column ranges of balanced work
        // in parallel when the supernode is large.
        let updaters = &self.updaters[self.ptr[s]..self.ptr[s + 1]];
        let ranges = match par {
            Par::Rayon(t) if updaters.len() > 1 => column_ranges(nr, nc, t.get()),
            _ => std::iter::once(0..nc).collect(),
        };
        if ws.scratch.len() < ranges.len() {
            ws.scratch.resize_with(ranges.len(), Scratch::default);
        }
        let update = Update {
            sn,
            done,
            base,
            local: &ws.local,
            s0,
            s1,
            nr,
            stop,
        };
        if ranges.len() == 1 {
            update.apply(updaters, 0..nc, ls, &mut ws.scratch[0])?;
        } else {
            let mut pieces = Vec::with_capacity(ranges.len());
            let mut rest: &mut [f64] = ls;
            for r in &ranges {
                let (mine, after) = std::mem::take(&mut rest).split_at_mut(r.len() * nr);
                pieces.push((r.clone(), mine));
                rest = after;
            }
            pieces
                .into_par_iter()
                .zip(ws.scratch.par_iter_mut())
                .try_for_each(|((r, cols), scratch)| update.apply(updaters, r, cols, scratch))?;
        }
        check(stop)?;
        let ls = &mut rest[..nr * nc];
        let l = MatMut::from_column_major_slice_mut(ls, nr, nc);
        let (mut top, bottom) = l.split_at_row_mut(nc);
        let factored = diagonal_cholesky(top.as_mut(), par, &mut ws.stack, stop);
        for &r in pattern {
            ws.local[r] = 0;
        }
        factored.map_err(|h| match h {
            Halt::Pivot(index) => Halt::Pivot(s0 + index),
            stopped => stopped,
        })?;
        lower_solve(top.as_ref(), bottom.transpose_mut(), par, stop)?;
        Ok(())
    }
}

/// Loads the blocks of the top supernodes of `split` from `a` into `values` (the
/// whole factor), before the subtrees take their columns of `a` away.
fn load_top(sn: &SymbolicSupernodalCholesky<usize>, split: &SubtreeSplit, a: Input<'_>, values: &mut [f64]) {
    let val_ptr = sn.col_ptr_for_val();
    let mut local = vec![0u32; sn.nrows()];
    for &s in split.top() {
        let block = &mut values[val_ptr[s]..val_ptr[s + 1]];
        load(sn, a, s, block, &mut local);
    }
}

/// The work of each part of `split`: its subtrees, each handed its values of
/// the factor and its values of `a` (a subtree is a contiguous range of
/// supernodes, so of the factor's values and of the columns of `a`; the
/// subtrees are cut off `values` and `a_values` in ascending order).
fn subtree_tasks<'v>(
    sn: &SymbolicSupernodalCholesky<usize>,
    split: &SubtreeSplit,
    col_ptr: &[usize],
    values: &'v mut [f64],
    a_values: &'v mut Cow<'_, [f64]>,
) -> Vec<Vec<Subtree<'v>>> {
    let val_ptr = sn.col_ptr_for_val();
    let mut pieces: Vec<(usize, Range<usize>)> = split
        .part_subtrees()
        .enumerate()
        .flat_map(|(p, ts)| ts.into_iter().map(move |t| (p, t)))
        .collect();
    pieces.sort_by_key(|(_, t)| t.start);
    let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
    let entries = |t: &Range<usize>| col_ptr[begin[t.start]]..col_ptr[end[t.end - 1]];
    let mut tasks: Vec<Vec<Subtree<'_>>> = (0..split.parts()).map(|_| Vec::new()).collect();
    let mut rest: &mut [f64] = values;
    let mut at = 0;
    let mut a_rest = match a_values {
        Cow::Owned(v) => Piece::Owned(v.as_mut_slice()),
        Cow::Borrowed(v) => Piece::Shared(v),
    };
    let mut a_at = 0;
    for (p, t) in pieces {
        let (from, to) = (val_ptr[t.start], val_ptr[t.end]);
        let tail = std::mem::take(&mut rest).split_at_mut(from - at).1;
        let (mine, after) = tail.split_at_mut(to - from);
        rest = after;
        at = to;
        let r = entries(&t);
        let (a_mine, a_after) = a_rest.split(r.start - a_at, r.end - a_at);
        a_rest = a_after;
        a_at = r.end;
        tasks[p].push(Subtree {
            supernodes: t,
            values: mine,
            a: a_mine,
            a_first: r.start,
        });
    }
    tasks
}

/// Loads the block `ls` of supernode `s` from `a`: zeros, then the columns of
/// `a` in it (`local`, all zero, is the scratch row map).
fn load(sn: &SymbolicSupernodalCholesky<usize>, a: Input<'_>, s: usize, ls: &mut [f64], local: &mut [u32]) {
    let (s0, s1) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
    let pattern = sn.supernode(s).pattern();
    let nc = s1 - s0;
    for (i, &r) in pattern.iter().enumerate() {
        local[r] = (nc + i) as u32;
    }
    scatter(a, s0, s1, nc + pattern.len(), ls, local);
    for &r in pattern {
        local[r] = 0;
    }
}

/// `ls ← A[s0.., s0..s1]`: the `nr × (s1 − s0)` block of a supernode zeroed,
/// then the lower triangle of columns `s0..s1` of `a` added in, rows past `s1`
/// through the row map `local` (row of the factor → row of the block).
fn scatter(a: Input<'_>, s0: usize, s1: usize, nr: usize, ls: &mut [f64], local: &[u32]) {
    ls.fill(0.0);
    for j in s0..s1 {
        let col = &mut ls[(j - s0) * nr..(j - s0 + 1) * nr];
        let (rows, values) = a.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            let i = i as usize;
            if i >= j {
                let at = if i < s1 { i - s0 } else { local[i] as usize };
                col[at] += v;
            }
        }
    }
}

/// Values of `a` read between two give-backs of their pages (2 MiB; in the
/// unit tests a page or so, so their small matrices give pages back between
/// supernodes too).
const DISCARD_VALUES: usize = if cfg!(test) { 1 << 9 } else { 1 << 18 };

/// Columns of the lower triangle of `A` as a factorization reads them: the
/// pattern, and the values from stored entry `first` on (a subtree's own range,
/// or all of them).
#[derive(Clone, Copy)]
struct Input<'a> {
    col_ptr: &'a [usize],
    row_idx: &'a [u32],
    values: &'a [f64],
    first: usize,
}

impl<'a> Input<'a> {
    /// The rows and values stored in column `j`.
    fn column(&self, j: usize) -> (&'a [u32], &'a [f64]) {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.row_idx[r.clone()], &self.values[r.start - self.first..r.end - self.first])
    }
}

/// The values of `a` one thread reads: owned by the factorization (their
/// pages given back once read) or borrowed.
enum Piece<'a> {
    Owned(&'a mut [f64]),
    Shared(&'a [f64]),
}

impl<'a> Piece<'a> {
    fn get(&self) -> &[f64] {
        match self {
            Piece::Owned(v) => v,
            Piece::Shared(v) => v,
        }
    }

    /// The entries `from..to` (relative to the piece's start) and the rest
    /// after `to`, the part before `from` left out.
    fn split(self, from: usize, to: usize) -> (Piece<'a>, Piece<'a>) {
        match self {
            Piece::Owned(v) => {
                let (mine, after) = v.split_at_mut(to);
                (Piece::Owned(&mut mine[from..]), Piece::Owned(after))
            }
            Piece::Shared(v) => {
                let (mine, after) = v.split_at(to);
                (Piece::Shared(&mine[from..]), Piece::Shared(after))
            }
        }
    }

    /// Gives back the pages of the entries `from..to`, read and not needed again
    /// (owned values only); returns where the next give-back starts (see
    /// [`super::heap::discard`]).
    fn discard(&mut self, from: usize, to: usize) -> usize {
        match self {
            Piece::Owned(v) => super::heap::discard(v, from, to),
            Piece::Shared(_) => from,
        }
    }
}

/// One subtree of a part: its supernodes, its values of the factor and its
/// values of `a` (from stored entry `a_first` on).
struct Subtree<'a> {
    supernodes: Range<usize>,
    values: &'a mut [f64],
    a: Piece<'a>,
    a_first: usize,
}

/// The updates of one supernode `s` by its descendants, read from the finished
/// part of the factor.
struct Update<'a> {
    sn: &'a SymbolicSupernodalCholesky<usize>,
    /// The factor's values from offset `base` on (up to `s`).
    done: &'a [f64],
    base: usize,
    /// Row of the factor → row of the block of `s`.
    local: &'a [u32],
    s0: usize,
    s1: usize,
    /// Rows of the block of `s`.
    nr: usize,
    /// The caller's stop flag, read before every block product.
    stop: Option<&'a AtomicUsize>,
}

impl Update<'_> {
    /// `L_s[:, cols] −= L_d[r_d, :] · L_d[c_d ∩ cols, :]ᵀ` for each updater `d`,
    /// ascending, with `ls` the columns `cols` of the block of `s`; abandoned
    /// ([`Halt::Stopped`]) once the stop flag, read before every block product,
    /// is nonzero.
    fn apply(
        &self,
        updaters: &[u32],
        cols: Range<usize>,
        ls: &mut [f64],
        scratch: &mut Scratch,
    ) -> Result<(), Halt> {
        let (sn, nr) = (self.sn, self.nr);
        let val_ptr = sn.col_ptr_for_val();
        for &d in updaters {
            let d = d as usize;
            let d_pattern = sn.supernode(d).pattern();
            let dc = sn.supernode_end()[d] - sn.supernode_begin()[d];
            let ld = MatRef::from_column_major_slice(
                &self.done[val_ptr[d] - self.base..val_ptr[d + 1] - self.base],
                dc + d_pattern.len(),
                dc,
            );
            // The rows of d from s0 on; the first `mid` are columns of s, of which
            // `lo..hi` fall in `cols`.
            let first = d_pattern.partition_point(|&r| r < self.s0);
            let below = &d_pattern[first..];
            let mid = below.partition_point(|&r| r < self.s1);
            let lo = below[..mid].partition_point(|&r| r < self.s0 + cols.start);
            let hi = below[..mid].partition_point(|&r| r < self.s0 + cols.end);
            if lo == hi {
                continue;
            }
            scratch.rows.clear();
            scratch.rows.extend(below.iter().enumerate().map(|(i, &r)| {
                if i < mid {
                    (r - self.s0) as u32
                } else {
                    self.local[r]
                }
            }));
            let m = below.len();
            let lb = ld.subrows(dc + first, m);
            let group = (BLOCK_VALUES / m).max(1);
            let mut c0 = lo;
            while c0 < hi {
                // One relaxed load per block product (of up to `BLOCK_VALUES`
                // entries, `dc` multiply–adds each).
                check(self.stop)?;
                let c1 = (c0 + group).min(hi);
                // Rows c0.. of the product (the lower part of its columns c0..c1).
                let h = m - c0;
                scratch.block.resize(h * (c1 - c0), 0.0);
                let w = MatMut::from_column_major_slice_mut(&mut scratch.block, h, c1 - c0);
                matmul(
                    w,
                    Accum::Replace,
                    lb.subrows(c0, h),
                    lb.subrows(c0, c1 - c0).transpose(),
                    1.0,
                    Par::Seq,
                );
                for jj in c0..c1 {
                    let target = (scratch.rows[jj] as usize - cols.start) * nr;
                    let wcol = &scratch.block[(jj - c0) * h..(jj - c0 + 1) * h];
                    for (&r, &x) in scratch.rows[jj..].iter().zip(&wcol[jj - c0..]) {
                        ls[target + r as usize] -= x;
                    }
                }
                c0 = c1;
            }
        }
        Ok(())
    }
}

/// The columns `0..nc` of a supernode block with `nr` rows cut into at most
/// `parts` ranges of about equal lower-triangle area (column `j` holds `nr − j`
/// values on and below the diagonal).
fn column_ranges(nr: usize, nc: usize, parts: usize) -> Vec<Range<usize>> {
    let area = |j: usize| (nr - j) as f64;
    let total: f64 = (0..nc).map(area).sum();
    let mut out = Vec::with_capacity(parts);
    let (mut start, mut acc) = (0, 0.0);
    for j in 0..nc {
        acc += area(j);
        if acc >= total * (out.len() + 1) as f64 / parts as f64 && out.len() + 1 < parts {
            out.push(start..j + 1);
            start = j + 1;
        }
    }
    if start < nc || out.is_empty() {
        out.push(start..nc);
    }
    out
}
