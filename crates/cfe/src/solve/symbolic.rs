//! The elimination tree and the column counts of the Cholesky factor of a
//! symmetric matrix in a given elimination order, in time almost linear in the
//! matrix's nonzeros.
//!
//! For `A = P K Pᵀ` (`n` columns, the pattern only):
//!
//! - the **elimination tree**: the parent of column `j` is the row of the first
//!   off-diagonal nonzero of column `j` of `L`; Liu's algorithm finds it from the
//!   upper triangle, row by row, climbing the partial tree with path compression
//!   (Davis, *Direct Methods for Sparse Linear Systems*, SIAM 2006, §4.1, `cs_etree`);
//! - the **column counts** `|L(:, j)|` (diagonal included): row `i` of `L` is the
//!   *row subtree* of `i`, the union of the tree paths from the columns `j < i`
//!   with `A(i, j) ≠ 0` up to `i`. Counting its nodes one by one costs the number of
//!   nonzeros of `L` (what faer's `prefactorize_symbolic_cholesky` does); the
//!   method of Gilbert, Ng and Peyton (SIAM J. Matrix Anal. Appl. 15, 1994) counts
//!   each row subtree from its leaves only, in postorder: `+1` at each leaf, `−1`
//!   at the least common ancestor of consecutive leaves (found with a disjoint-set
//!   forest), `−1` at the parent of every column; the column counts are then the
//!   sums of these differences over each subtree (Davis §4.5, `cs_counts`).
//!
//! With a nested-dissection order of a 2D mesh `L` holds about 15 times the
//! nonzeros of `A`, and so the row-subtree counting was most of the symbolic
//! analysis: this module does the same in a few passes over `A`.

use std::sync::atomic::AtomicUsize;

/// A step abandoned on the stop flag, and the flag's read (their home is
/// [`crate::error`], below the assembly, which reads the flag too).
pub use crate::error::{Stopped, check_stop as check};

/// Columns of the elimination tree or the column counts done between two reads
/// of the stop flag (a few milliseconds of work at most).
const STOP_CHECK_COLUMNS: usize = 1 << 16;

/// How often the caller reads the stop flag while a step runs on a thread of
/// its own ([`run_until`]).
const STOP_POLL: std::time::Duration = std::time::Duration::from_millis(10);

/// `work` (a step that cannot read the stop flag itself: faer's supernodal
/// analysis) run to its end, or [`Stopped`] within [`STOP_POLL`] of `stop`
/// being read nonzero.
///
/// Without a flag `work` runs here. With one it runs on a thread of its own,
/// which owns everything it reads (hence `'static`), while this thread waits
/// for its answer and reads the flag every [`STOP_POLL`]. On a stop that thread
/// is left to end on its own: a thread cannot be stopped safely from outside,
/// and the step writes no file and holds no lock, so all it does after the
/// stop is finish its computation, drop the answer nobody waits for and free
/// its inputs (a run being stopped exits meanwhile, which ends it). The answer
/// is the same on either thread (the step is sequential). A panic in `work` is
/// resumed here.
pub fn run_until<T, F>(stop: Option<&AtomicUsize>, work: F) -> Result<T, Stopped>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    use std::sync::mpsc::{RecvTimeoutError, sync_channel};
    use std::sync::{Arc, Mutex, PoisonError};
    if stop.is_none() {
        return Ok(work());
    }
    check(stop)?;
    // The work stays reachable from here should no thread be available for it
    // (it then runs here, reading no flag, as without one).
    let slot = Arc::new(Mutex::new(Some(work)));
    let theirs = Arc::clone(&slot);
    let (tx, rx) = sync_channel(1);
    let spawned = std::thread::Builder::new()
        .name("cfe-symbolic".into())
        .spawn(move || {
            let work = theirs.lock().unwrap_or_else(PoisonError::into_inner).take();
            if let Some(work) = work {
                // The receiver is gone after a stop: the answer is dropped.
                let _ = tx.send(work());
            }
        });
    let worker = match spawned {
        Ok(worker) => worker,
        Err(_) => {
            let work = slot.lock().unwrap_or_else(PoisonError::into_inner).take();
            return Ok(work.expect("not taken by a thread that was never started")());
        }
    };
    drop(slot);
    loop {
        match rx.recv_timeout(STOP_POLL) {
            Ok(answer) => {
                let _ = worker.join();
                return Ok(answer);
            }
            Err(RecvTimeoutError::Timeout) => check(stop)?,
            Err(RecvTimeoutError::Disconnected) => match worker.join() {
                Err(panic) => std::panic::resume_unwind(panic),
                Ok(()) => unreachable!("the worker sends its answer before it ends"),
            },
        }
    }
}

/// A row index as a pattern stores it: 4 bytes (the stiffness's) or 8 (faer's).
pub trait Row: Copy + Send + Sync {
    /// The index as a `usize`.
    fn at(self) -> usize;
}

impl Row for u32 {
    #[inline(always)]
    fn at(self) -> usize {
        self as usize
    }
}

impl Row for usize {
    #[inline(always)]
    fn at(self) -> usize {
        self
    }
}

/// The upper and the strict lower triangle of `P K Pᵀ` in compressed columns
/// (rows unsorted within a column), from the lower triangle of `K` (`col_ptr`,
/// `row_idx`; entries above the diagonal are ignored), with `inverse[e]` the
/// position of equation `e` in the elimination order: entry `(i, j)` goes to
/// column `max(i', j')`, row `min(i', j')` of the upper triangle and, off the
/// diagonal, to column `min(i', j')`, row `max(i', j')` of the lower one.
pub fn permuted_triangles<R: Row, P: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    inverse: &[P],
) -> (Pattern, Pattern) {
    let n = col_ptr.len() - 1;
    let (mut up, mut lp) = (vec![0usize; n + 1], vec![0usize; n + 1]);
    each_moved(col_ptr, row_idx, inverse, |r, c| {
        up[c + 1] += 1;
        if r != c {
            lp[r + 1] += 1;
        }
    });
    for c in 0..n {
        up[c + 1] += up[c];
        lp[c + 1] += lp[c];
    }
    let (mut unext, mut lnext) = (up[..n].to_vec(), lp[..n].to_vec());
    let (mut ur, mut lr) = (vec![0usize; up[n]], vec![0usize; lp[n]]);
    each_moved(col_ptr, row_idx, inverse, |r, c| {
        ur[unext[c]] = r;
        unext[c] += 1;
        if r != c {
            lr[lnext[r]] = c;
            lnext[r] += 1;
        }
    });
    (Pattern { col_ptr: up, row_idx: ur }, Pattern { col_ptr: lp, row_idx: lr })
}

/// The upper triangle of `P K Pᵀ` alone (see [`permuted_triangles`]): what the
/// elimination tree and faer's supernodal analysis read, when the lower
/// triangle in the elimination order is built elsewhere (the stiffness's own,
/// [`crate::assembly::Stiffness::in_order_pattern`]). `stop`, if given, is
/// read every `STOP_CHECK_COLUMNS` (2¹⁶) columns of each of its two passes over
/// the entries ([`Stopped`] once nonzero).
pub fn permuted_upper<R: Row, P: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    inverse: &[P],
    stop: Option<&AtomicUsize>,
) -> Result<Pattern, Stopped> {
    let n = col_ptr.len() - 1;
    let mut up = vec![0usize; n + 1];
    each_moved_until(col_ptr, row_idx, inverse, stop, |_, c| up[c + 1] += 1)?;
    for c in 0..n {
        up[c + 1] += up[c];
    }
    let mut next = up[..n].to_vec();
    let mut rows = vec![0usize; up[n]];
    each_moved_until(col_ptr, row_idx, inverse, stop, |r, c| {
        rows[next[c]] = r;
        next[c] += 1;
    })?;
    Ok(Pattern {
        col_ptr: up,
        row_idx: rows,
    })
}

/// Calls `f(r, c)` for every entry `(i, j)`, `i ≥ j`, of the lower triangle
/// `(col_ptr, row_idx)`, moved by the order's `inverse` to row `r` ≤ column `c`.
#[inline]
fn each_moved<R: Row, P: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    inverse: &[P],
    f: impl FnMut(usize, usize),
) {
    each_moved_until(col_ptr, row_idx, inverse, None, f)
        .unwrap_or_else(|_| unreachable!("no stop flag to read"));
}

/// [`each_moved`] reading `stop` (if any) every [`STOP_CHECK_COLUMNS`]
/// columns: [`Stopped`] once it is nonzero (the entries after it are not given).
#[inline]
fn each_moved_until<R: Row, P: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    inverse: &[P],
    stop: Option<&AtomicUsize>,
    mut f: impl FnMut(usize, usize),
) -> Result<(), Stopped> {
    for (j, pj) in inverse.iter().map(|p| p.at()).enumerate().take(col_ptr.len() - 1) {
        if j.is_multiple_of(STOP_CHECK_COLUMNS) {
            check(stop)?;
        }
        for i in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().map(|r| r.at()).filter(|&i| i >= j) {
            let pi = inverse[i].at();
            if pi < pj { f(pi, pj) } else { f(pj, pi) }
        }
    }
    Ok(())
}

/// A sparsity pattern in compressed columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pattern {
    /// Column pointers (length n + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices of each column.
    pub row_idx: Vec<usize>,
}

/// The elimination tree of the matrix whose upper triangle is `(col_ptr,
/// row_idx)`: `parent[j]`, `-1` for a root (faer's convention).
pub fn elimination_tree(col_ptr: &[usize], row_idx: &[usize]) -> Vec<isize> {
    elimination_tree_until(col_ptr, row_idx, None).unwrap_or_else(|_| unreachable!("no stop flag"))
}

/// [`elimination_tree`] reading `stop`, if given, every
/// `STOP_CHECK_COLUMNS` columns: [`Stopped`] once it is nonzero.
pub fn elimination_tree_until(
    col_ptr: &[usize],
    row_idx: &[usize],
    stop: Option<&AtomicUsize>,
) -> Result<Vec<isize>, Stopped> {
    let n = col_ptr.len() - 1;
    let mut parent = vec![-1isize; n];
    // The root of each partial subtree, path-compressed (`usize::MAX`: none yet).
    let mut ancestor = vec![usize::MAX; n];
    for k in 0..n {
        if k % STOP_CHECK_COLUMNS == 0 {
            check(stop)?;
        }
        for &row in &row_idx[col_ptr[k]..col_ptr[k + 1]] {
            let mut i = row;
            while i < k {
                let next = ancestor[i];
                ancestor[i] = k;
                if next == usize::MAX {
                    parent[i] = k as isize;
                    break;
                }
                i = next;
            }
        }
    }
    Ok(parent)
}

/// A postorder of the forest `parent` (`-1` for a root): children before their
/// parent, each subtree contiguous, children in ascending order.
pub fn postorder(parent: &[isize]) -> Vec<usize> {
    let n = parent.len();
    // Children lists, ascending: pushed in descending order onto linked lists.
    let (mut head, mut next) = (vec![usize::MAX; n], vec![usize::MAX; n]);
    for j in (0..n).rev() {
        if parent[j] >= 0 {
            let p = parent[j] as usize;
            next[j] = head[p];
            head[p] = j;
        }
    }
    let mut post = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for root in (0..n).filter(|&j| parent[j] < 0) {
        stack.push(root);
        while let Some(&p) = stack.last() {
            match head[p] {
                usize::MAX => {
                    stack.pop();
                    post.push(p);
                }
                child => {
                    head[p] = next[child];
                    stack.push(child);
                }
            }
        }
    }
    post
}

/// The column counts of `L` (diagonal included) for the matrix whose lower
/// triangle is `(col_ptr, row_idx)` (column `j` holds rows `i ≥ j` with
/// `A(i, j) ≠ 0`; the diagonal may be left out), its elimination tree `parent`
/// and a postorder `post` of it.
pub fn column_counts<R: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    parent: &[isize],
    post: &[usize],
) -> Vec<usize> {
    column_counts_until(col_ptr, row_idx, parent, post, None)
        .unwrap_or_else(|_| unreachable!("no stop flag"))
}

/// [`column_counts`] reading `stop`, if given, every `STOP_CHECK_COLUMNS`
/// columns of the postorder: [`Stopped`] once it is nonzero.
pub fn column_counts_until<R: Row>(
    col_ptr: &[usize],
    row_idx: &[R],
    parent: &[isize],
    post: &[usize],
    stop: Option<&AtomicUsize>,
) -> Result<Vec<usize>, Stopped> {
    const NONE: usize = usize::MAX;
    let n = parent.len();
    // first[j]: the postorder number of the first descendant of j (leaf end of
    // its subtree); delta: the differences summed into the counts at the end.
    let mut first = vec![NONE; n];
    let mut delta = vec![0isize; n];
    for (k, &j) in post.iter().enumerate() {
        delta[j] = if first[j] == NONE { 1 } else { 0 };
        let mut a = j;
        while first[a] == NONE {
            first[a] = k;
            match parent[a] {
                p if p >= 0 => a = p as usize,
                _ => break,
            }
        }
    }
    let mut max_first = vec![NONE; n];
    let mut prev_leaf = vec![NONE; n];
    let mut ancestor: Vec<usize> = (0..n).collect();
    for (k, &j) in post.iter().enumerate() {
        if k % STOP_CHECK_COLUMNS == 0 {
            check(stop)?;
        }
        if parent[j] >= 0 {
            delta[parent[j] as usize] -= 1;
        }
        for i in row_idx[col_ptr[j]..col_ptr[j + 1]].iter().map(|r| r.at()) {
            // Is j a leaf of the row subtree of i?
            if i <= j || (max_first[i] != NONE && first[j] <= max_first[i]) {
                continue;
            }
            max_first[i] = first[j];
            let jprev = prev_leaf[i];
            prev_leaf[i] = j;
            delta[j] += 1;
            if jprev != NONE {
                // A later leaf: the least common ancestor of it and the previous
                // one is the root of jprev's set, whose count is then
                // overcounted by one.
                let mut q = jprev;
                while q != ancestor[q] {
                    q = ancestor[q];
                }
                let mut s = jprev;
                while s != q {
                    let up = ancestor[s];
                    ancestor[s] = q;
                    s = up;
                }
                delta[q] -= 1;
            }
        }
        if parent[j] >= 0 {
            ancestor[j] = parent[j] as usize;
        }
    }
    // Sum each subtree's differences into its root, children first.
    for &j in post {
        if parent[j] >= 0 {
            delta[parent[j] as usize] += delta[j];
        }
    }
    Ok(delta
        .into_iter()
        .map(|d| {
            debug_assert!(d >= 1, "a column count below one");
            d as usize
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::Ordering;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::SymbolicSparseColMatRef;
    use faer::sparse::linalg::cholesky::simplicial::{
        prefactorize_symbolic_cholesky, prefactorize_symbolic_cholesky_scratch,
    };

    /// The lower triangle of the 5-point Laplacian on an `m × m` grid with
    /// `extra` long-range couplings (so the tree is not a path), in a scrambled
    /// order.
    fn grid(m: usize, extra: usize) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
        let n = m * m;
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut add = |a: usize, b: usize| {
            let (i, j) = (a.max(b), a.min(b));
            if !cols[j].contains(&i) {
                cols[j].push(i);
            }
        };
        for y in 0..m {
            for x in 0..m {
                let a = y * m + x;
                add(a, a);
                if x + 1 < m {
                    add(a, a + 1);
                }
                if y + 1 < m {
                    add(a, a + m);
                }
            }
        }
        for k in 0..extra {
            add((k * 37) % n, (k * 101 + 7) % n);
        }
        let (mut ptr, mut rows) = (vec![0], Vec::new());
        for c in &mut cols {
            c.sort_unstable();
            rows.extend_from_slice(c);
            ptr.push(rows.len());
        }
        // A scrambled order (a permutation: 7919 is prime to n for these sizes).
        let order: Vec<usize> = (0..n).map(|k| (k * 7919 + 3) % n).collect();
        (ptr, rows, order)
    }

    /// Tree and counts equal faer's (Liu's tree, row subtrees counted node by
    /// node) on scrambled grids with extra couplings, and a brute-force count of
    /// the rows of `L` by symbolic elimination on the smallest.
    ///
    /// ```text
    ///   o─o─o      the grid, its equations renumbered;
    ///   │ │ │      L(:, j) = rows of A(:, j) below j, and the rows of
    ///   o─o─o      L(:, c) for every child c of j (below j)
    /// ```
    #[test]
    fn tree_and_counts_match_row_subtree_counting() {
        for (m, extra) in [(1, 0), (2, 0), (5, 0), (7, 9), (16, 40), (31, 100)] {
            let (ptr, rows, order) = grid(m, extra);
            let n = m * m;
            let mut inverse = vec![0; n];
            for (k, &e) in order.iter().enumerate() {
                inverse[e] = k;
            }
            let (upper, lower) = permuted_triangles(&ptr, &rows, &inverse);
            let (up, ur) = (&upper.col_ptr, &upper.row_idx);
            let (lp, lr) = (&lower.col_ptr, &lower.row_idx);
            let parent = elimination_tree(up, ur);
            let post = postorder(&parent);
            let counts = column_counts(lp, lr, &parent, &post);
            // faer, on the same upper triangle.
            let a = SymbolicSparseColMatRef::new_unsorted_checked(n, n, up, None, ur);
            let (mut etree, mut cc) = (vec![0isize; n], vec![0usize; n]);
            let mut mem = MemBuffer::new(prefactorize_symbolic_cholesky_scratch::<usize>(n, ur.len()));
            prefactorize_symbolic_cholesky(&mut etree, &mut cc, a, MemStack::new(&mut mem));
            assert_eq!(parent, etree, "tree, m {m}");
            assert_eq!(counts, cc, "counts, m {m}");
            // The postorder: a permutation, each column after its children.
            let mut at = vec![usize::MAX; n];
            for (k, &j) in post.iter().enumerate() {
                at[j] = k;
            }
            assert!(at.iter().all(|&k| k < n));
            assert!((0..n).all(|j| parent[j] < 0 || at[j] < at[parent[j] as usize]));
            if n <= 64 {
                // Symbolic elimination: the rows of L(:, j) are those of A(:, j)
                // and of each earlier column whose first row below it is j.
                let mut struct_l: Vec<Vec<usize>> = (0..n)
                    .map(|j| std::iter::once(j).chain(lr[lp[j]..lp[j + 1]].iter().copied()).collect())
                    .collect();
                for j in 0..n {
                    struct_l[j].sort_unstable();
                    struct_l[j].dedup();
                    if let Some(&p) = struct_l[j].iter().find(|&&i| i > j) {
                        let below: Vec<usize> =
                            struct_l[j].iter().copied().filter(|&i| i > p).collect();
                        struct_l[p].extend(below);
                    }
                }
                for j in 0..n {
                    struct_l[j].sort_unstable();
                    struct_l[j].dedup();
                    assert_eq!(counts[j], struct_l[j].len(), "column {j}, m {m}");
                }
            }
        }
    }

    /// Two parts with nothing between them (a block-diagonal matrix, its
    /// equations interleaved by the order): the tree is a forest of two roots,
    /// and tree and counts still equal faer's.
    #[test]
    fn disconnected_parts_give_a_forest() {
        let (ptr, rows, _) = grid(6, 5);
        let m = ptr.len() - 1;
        // Block diagonal: the grid and a copy of it shifted by m.
        let mut bptr = ptr.clone();
        bptr.extend(ptr[1..].iter().map(|p| p + rows.len()));
        let mut brows = rows.clone();
        brows.extend(rows.iter().map(|r| r + m));
        let n = 2 * m;
        let order: Vec<usize> = (0..n).map(|k| if k % 2 == 0 { k / 2 } else { m + k / 2 }).collect();
        let mut inverse = vec![0; n];
        for (k, &e) in order.iter().enumerate() {
            inverse[e] = k;
        }
        let (upper, lower) = permuted_triangles(&bptr, &brows, &inverse);
        let parent = elimination_tree(&upper.col_ptr, &upper.row_idx);
        let post = postorder(&parent);
        let counts = column_counts(&lower.col_ptr, &lower.row_idx, &parent, &post);
        assert_eq!(parent.iter().filter(|&&p| p < 0).count(), 2);
        let a = SymbolicSparseColMatRef::new_unsorted_checked(n, n, &upper.col_ptr, None, &upper.row_idx);
        let (mut etree, mut cc) = (vec![0isize; n], vec![0usize; n]);
        let mut mem = MemBuffer::new(prefactorize_symbolic_cholesky_scratch::<usize>(n, upper.row_idx.len()));
        prefactorize_symbolic_cholesky(&mut etree, &mut cc, a, MemStack::new(&mut mem));
        assert_eq!(parent, etree);
        assert_eq!(counts, cc);
    }

    /// Every entry of the lower triangle lands once in each triangle of the
    /// permuted matrix (mirrored; the diagonal in the upper one only); entries
    /// above the diagonal are ignored.
    #[test]
    fn permuted_triangles_mirror_the_lower_triangle() {
        // Lower triangle of a 3 × 3 matrix with an entry (0, 2) above the
        // diagonal that must be ignored; order [2, 0, 1].
        let ptr = vec![0, 3, 5, 6];
        let rows = vec![0usize, 1, 2, 1, 0, 2];
        let inverse = vec![1usize, 2, 0];
        let (upper, lower) = permuted_triangles(&ptr, &rows, &inverse);
        let columns = |p: &Pattern| -> Vec<Vec<usize>> {
            (0..3)
                .map(|c| {
                    let mut r = p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]].to_vec();
                    r.sort_unstable();
                    r
                })
                .collect()
        };
        // (0,0)→(1,1), (1,0)→(1,2), (2,0)→(0,1), (1,1)→(2,2), (2,2)→(0,0).
        assert_eq!(columns(&upper), vec![vec![0], vec![0, 1], vec![1, 2]]);
        assert_eq!(columns(&lower), vec![vec![1], vec![2], vec![]]);
    }

    /// With a stop flag that stays zero the permuted triangle, the tree and the
    /// counts are those without one; with the flag set each returns
    /// [`Stopped`] with its value.
    #[test]
    fn stop_flag_abandons_the_symbolic_steps() {
        let (ptr, rows, order) = grid(16, 40);
        let mut inverse = vec![0; order.len()];
        for (k, &e) in order.iter().enumerate() {
            inverse[e] = k;
        }
        let (upper, lower) = permuted_triangles(&ptr, &rows, &inverse);
        let parent = elimination_tree(&upper.col_ptr, &upper.row_idx);
        let post = postorder(&parent);
        let counts = column_counts(&lower.col_ptr, &lower.row_idx, &parent, &post);
        let stop = AtomicUsize::new(0);
        let flag = Some(&stop);
        assert_eq!(permuted_upper(&ptr, &rows, &inverse, flag).as_ref(), Ok(&upper));
        assert_eq!(elimination_tree_until(&upper.col_ptr, &upper.row_idx, flag).as_ref(), Ok(&parent));
        let flagged = column_counts_until(&lower.col_ptr, &lower.row_idx, &parent, &post, flag);
        assert_eq!(flagged.as_ref(), Ok(&counts));
        stop.store(2, Ordering::Relaxed);
        assert_eq!(permuted_upper(&ptr, &rows, &inverse, flag), Err(Stopped(2)));
        assert_eq!(elimination_tree_until(&upper.col_ptr, &upper.row_idx, flag), Err(Stopped(2)));
        let flagged = column_counts_until(&lower.col_ptr, &lower.row_idx, &parent, &post, flag);
        assert_eq!(flagged, Err(Stopped(2)));
    }

    /// A step run with [`run_until`]: without a flag, or with one left zero,
    /// its answer; with the flag set before, `Stopped` and the step never
    /// started; with it set while the step runs (a step that cannot end before
    /// the stop is answered: it waits for a gate opened only afterwards),
    /// `Stopped` with the flag's value, the step then ending on its own.
    #[test]
    fn a_step_on_its_own_thread_is_abandoned_on_a_stop() {
        use std::sync::mpsc::channel;
        assert_eq!(run_until(None, || 6 * 7), Ok(42));
        let clear = AtomicUsize::new(0);
        assert_eq!(run_until(Some(&clear), || 6 * 7), Ok(42));
        let set = AtomicUsize::new(2);
        let (started_tx, started_rx) = channel::<()>();
        assert_eq!(
            run_until(Some(&set), move || {
                let _ = started_tx.send(());
                1
            }),
            Err(Stopped(2))
        );
        assert!(started_rx.recv().is_err(), "the step started");
        let stop = AtomicUsize::new(0);
        let (gate_tx, gate_rx) = channel::<()>();
        let (done_tx, done_rx) = channel::<()>();
        let stopped = std::thread::scope(|s| {
            s.spawn(|| {
                std::thread::sleep(std::time::Duration::from_millis(50));
                stop.store(15, Ordering::Relaxed);
            });
            run_until(Some(&stop), move || {
                let _ = gate_rx.recv();
                let _ = done_tx.send(());
                7
            })
        });
        assert_eq!(stopped, Err(Stopped(15)));
        gate_tx.send(()).unwrap();
        done_rx.recv().unwrap();
    }
}
