//! Assembly: numbers the degrees of freedom of all parts (Dirichlet DOFs eliminated),
//! builds the sparsity pattern of the global stiffness once — including every coupling
//! element's couplings, so a pair changing state changes values, never the pattern —
//! and fills the lower triangle of K, the internal force vector and the external loads.

mod source;

use crate::coupling::{Interface, PairHistory, PairState};
use crate::dim::Dim;
pub use crate::dofs::{DofMap, FIXED};
use crate::domain::{Load, Part};
use crate::error::{Stopped, check_stop};
use crate::fem::ElementFamily;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
pub use source::{
    CouplingElements, ElementSource, MatrixSink, PartElements, SomeElements, VectorSink,
};
use std::sync::atomic::AtomicUsize;

/// Elements listed, or nodes or columns gone through, between two reads of a
/// caller's stop flag while the node graph or the pattern is built (well under
/// a millisecond of work each: the read is one relaxed load).
const STOP_CHECK_ROWS: usize = 1 << 14;

/// The node adjacency graph of the whole model (CSR, each row sorted, self
/// included): two nodes are adjacent when an element — a part element or a coupling
/// element — contains both. It gives the sparsity pattern and the fill-reducing
/// ordering.
#[derive(Debug, Clone)]
pub struct NodeGraph {
    /// Row pointers (length nodes + 1).
    pub ptr: Vec<usize>,
    /// Neighbours of each node, sorted.
    pub adj: Vec<usize>,
}

impl NodeGraph {
    /// The graph of all part elements and all coupling elements (whatever their state).
    pub fn new<D: ElementFamily>(parts: &[Part<D>], interfaces: &[Interface<D>], dofs: &DofMap<D>) -> NodeGraph {
        NodeGraph::new_until(parts, interfaces, dofs, None)
            .unwrap_or_else(|_| unreachable!("no stop flag to read"))
    }

    /// [`NodeGraph::new`] reading the caller's stop flag `stop` (if any) every
    /// few thousand elements or rows: [`Stopped`] once it is nonzero. The graph
    /// is that of [`NodeGraph::new`] otherwise.
    pub fn new_until<D: ElementFamily>(
        parts: &[Part<D>],
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        stop: Option<&AtomicUsize>,
    ) -> Result<NodeGraph, Stopped> {
        let part_elements = PartElements::new(parts, dofs);
        let coupling_elements = CouplingElements::new(interfaces, None, dofs);
        NodeGraph::from_sources_until(&[&part_elements, &coupling_elements], dofs.n_nodes(), stop)
    }

    /// The graph of the elements of `sources` over `n_nodes` global nodes.
    pub fn from_sources(sources: &[&dyn ElementSource], n_nodes: usize) -> NodeGraph {
        NodeGraph::from_sources_until(sources, n_nodes, None)
            .unwrap_or_else(|_| unreachable!("no stop flag to read"))
    }

    /// [`NodeGraph::from_sources`] reading `stop` (if any) every
    /// [`STOP_CHECK_ROWS`] elements of each pass and every block of rows sorted:
    /// [`Stopped`] once it is nonzero.
    pub fn from_sources_until(
        sources: &[&dyn ElementSource],
        n_nodes: usize,
        stop: Option<&AtomicUsize>,
    ) -> Result<NodeGraph, Stopped> {
        // Two passes (count, fill), then sort and dedup each row. The nodes are
        // cut into one range per thread; every thread goes through all the
        // elements and counts and fills the rows of its range only (an element's
        // nodes are cheap to list; the rows are the memory traffic).
        use rayon::prelude::*;
        // Every element's nodes to `f`, in order, the flag read every
        // `STOP_CHECK_ROWS` elements (once read nonzero the rest is skipped).
        let each_element = |f: &mut dyn FnMut(&[usize])| -> Result<(), Stopped> {
            let mut seen = 0usize;
            let mut halted = Ok(());
            for source in sources {
                source.for_each_nodes(&mut |nodes| {
                    if halted.is_ok() && seen.is_multiple_of(STOP_CHECK_ROWS) {
                        halted = check_stop(stop);
                    }
                    if halted.is_ok() {
                        seen += 1;
                        f(nodes);
                    }
                });
                halted?;
            }
            Ok(())
        };
        let threads = rayon::current_num_threads().clamp(1, 8);
        let bounds: Vec<usize> = (0..=threads).map(|t| t * n_nodes / threads).collect();
        let mut count = vec![0usize; n_nodes + 1];
        cut_at(&mut count[1..], &bounds, |b| b)
            .into_par_iter()
            .try_for_each(|(range, count)| {
                each_element(&mut |nodes| {
                    for &a in nodes {
                        if range.contains(&a) {
                            count[a - range.start] += nodes.len();
                        }
                    }
                })
            })?;
        for i in 0..n_nodes {
            count[i + 1] += count[i];
        }
        let mut adj = vec![0usize; count[n_nodes]];
        cut_at(&mut adj, &bounds, |b| count[b])
            .into_par_iter()
            .try_for_each(|(range, adj)| {
                let base = count[range.start];
                let mut fill: Vec<usize> =
                    count[range.clone()].iter().map(|&c| c - base).collect();
                each_element(&mut |nodes| {
                    for &a in nodes {
                        if range.contains(&a) {
                            let at = &mut fill[a - range.start];
                            for &b in nodes {
                                adj[*at] = b;
                                *at += 1;
                            }
                        }
                    }
                })
            })?;
        // Each row sorted and deduplicated in place, blocks of rows in parallel,
        // then the rows' unique prefixes gathered.
        const BLOCK: usize = 4096;
        let blocks = cut_at(&mut adj, &blocks_of(n_nodes, BLOCK), |b| count[b]);
        let mut unique = vec![0usize; n_nodes];
        blocks
            .into_par_iter()
            .zip(unique.par_chunks_mut(BLOCK))
            .try_for_each(|((nodes, block), unique)| {
                check_stop(stop)?;
                let base = count[nodes.start];
                for (a, u) in nodes.zip(unique) {
                    let row = &mut block[count[a] - base..count[a + 1] - base];
                    row.sort_unstable();
                    let mut k = 0;
                    for i in 0..row.len() {
                        if k == 0 || row[i] != row[k - 1] {
                            row[k] = row[i];
                            k += 1;
                        }
                    }
                    *u = k;
                }
                Ok(())
            })?;
        let mut ptr = vec![0usize; n_nodes + 1];
        for a in 0..n_nodes {
            ptr[a + 1] = ptr[a] + unique[a];
        }
        let mut out = Vec::with_capacity(ptr[n_nodes]);
        for a in 0..n_nodes {
            out.extend_from_slice(&adj[count[a]..count[a] + unique[a]]);
        }
        Ok(NodeGraph { ptr, adj: out })
    }

    /// The neighbours of node `a` (including itself).
    pub fn neighbours(&self, a: usize) -> &[usize] {
        &self.adj[self.ptr[a]..self.ptr[a + 1]]
    }
}

/// The global stiffness matrix K (lower triangle, compressed sparse columns over the
/// free DOFs) with a fixed pattern, stored either in the equations' order or — for
/// the solver, see [`Stiffness::in_order`] — in the elimination order of its
/// Cholesky factorization, `P K Pᵀ`, so the factorization reads it as it is (no
/// permuted copy beside the factor).
///
/// Only the pattern is kept for the whole solve. The values are those of the
/// parts plus the coupling elements in some pair states
/// ([`Stiffness::assemble`]): they are needed by a numeric factorization only
/// (residuals are summed element by element), so the solver gives them to each
/// one ([`Stiffness::take_values`]), which frees them once read, and assembles
/// them anew, parts included, for the next.
#[derive(Debug, Clone)]
pub struct Stiffness {
    /// Column pointers (length n_eq + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column, all ≥ the column; 4 bytes each
    /// (the matrix is held for the whole solve, beside the factor). The symbolic
    /// analysis and the numeric factorization read them as they are.
    pub row_idx: Vec<u32>,
    /// Current values (empty when freed).
    pub values: Vec<f64>,
    /// Row and column of each equation in the stored matrix (empty: the
    /// equation itself).
    position: Vec<u32>,
    /// Whether `values` hold the parts' contribution only (from
    /// [`Stiffness::assemble_parts`]): the next [`Stiffness::assemble`] then
    /// adds the coupling elements to them.
    parts_only: bool,
}

impl Stiffness {
    /// Builds the pattern from the node graph of every part element and every
    /// coupling element, and assembles the parts' stiffness.
    pub fn new<D: ElementFamily>(parts: &[Part<D>], dofs: &DofMap<D>, graph: &NodeGraph) -> Stiffness {
        Stiffness::from_sources(&[&PartElements::new(parts, dofs)], dofs, graph)
    }

    /// Builds the pattern from `graph` and assembles the constant part of the values
    /// from the elements of `sources`.
    pub fn from_sources<D: Dim>(
        sources: &[&dyn ElementSource],
        dofs: &DofMap<D>,
        graph: &NodeGraph,
    ) -> Stiffness {
        let mut k = Stiffness::pattern(dofs, graph);
        k.assemble_parts(sources, dofs);
        k
    }

    /// The pattern of `graph` over the equations of `dofs` (in the equations'
    /// order), every value zero: the symbolic analysis needs no more.
    pub fn pattern<D: Dim>(dofs: &DofMap<D>, graph: &NodeGraph) -> Stiffness {
        Stiffness::pattern_until(dofs, graph, None)
            .unwrap_or_else(|_| unreachable!("no stop flag to read"))
    }

    /// [`Stiffness::pattern`] reading the caller's stop flag `stop` (if any)
    /// every [`STOP_CHECK_ROWS`] nodes of each of its two passes: [`Stopped`]
    /// once it is nonzero.
    pub fn pattern_until<D: Dim>(
        dofs: &DofMap<D>,
        graph: &NodeGraph,
        stop: Option<&AtomicUsize>,
    ) -> Result<Stiffness, Stopped> {
        use rayon::prelude::*;
        let n_nodes = dofs.n_nodes();
        // DOF-level lower-triangular CSC over equations. Equation numbers increase
        // with DOF index, so rows come out sorted, and the columns of node a follow
        // those of node a − 1: the nodes are done in parallel blocks, each into its
        // own slice of the row indices (counted first).
        let rows_of = |a: usize, ca: usize, out: &mut dyn FnMut(usize)| {
            let j = dofs.eq[dofs.dof(a, ca)];
            for &b in graph.neighbours(a) {
                for cb in 0..dofs.per_node() {
                    let i = dofs.eq[dofs.dof(b, cb)];
                    if i != FIXED && i >= j {
                        out(i);
                    }
                }
            }
        };
        let free = |a: usize, ca: usize| dofs.eq[dofs.dof(a, ca)] != FIXED;
        // Row count of each node's columns (up to `D::N` columns a node: column
        // c of node a at `counts[D::N a + c]`, 0 when its DOF is fixed).
        let mut counts = vec![0usize; dofs.dof(n_nodes, 0)];
        counts
            .par_chunks_mut(D::N)
            .with_min_len(4096)
            .enumerate()
            .try_for_each(|(a, counts)| {
                if a.is_multiple_of(STOP_CHECK_ROWS) {
                    check_stop(stop)?;
                }
                for (ca, count) in counts.iter_mut().enumerate() {
                    if free(a, ca) {
                        rows_of(a, ca, &mut |_| *count += 1);
                    }
                }
                Ok::<(), Stopped>(())
            })?;
        let mut col_ptr = Vec::with_capacity(dofs.n_eq + 1);
        col_ptr.push(0);
        let mut node_start = Vec::with_capacity(n_nodes + 1);
        let mut nnz = 0;
        for (a, c) in counts.chunks(D::N).enumerate() {
            node_start.push(nnz);
            for (ca, &count) in c.iter().enumerate() {
                if free(a, ca) {
                    nnz += count;
                    col_ptr.push(nnz);
                }
            }
        }
        node_start.push(nnz);
        drop(counts);
        let mut row_idx = vec![0u32; nnz];
        // Blocks of nodes, each with its slice of the row indices.
        const BLOCK: usize = 8192;
        let slices = cut_at(&mut row_idx, &blocks_of(n_nodes, BLOCK), |b| node_start[b]);
        slices.into_par_iter().try_for_each(|(nodes, slice)| {
            check_stop(stop)?;
            let mut k = 0;
            for a in nodes {
                for ca in 0..D::N {
                    if free(a, ca) {
                        rows_of(a, ca, &mut |i| {
                            slice[k] = narrow(i);
                            k += 1;
                        });
                    }
                }
            }
            Ok(())
        })?;
        Ok(Stiffness {
            col_ptr,
            row_idx,
            values: vec![0.0; nnz],
            position: Vec::new(),
            parts_only: false,
        })
    }

    /// This matrix stored in the elimination order `order` (`order[k]` = equation
    /// eliminated k-th, `inverse` its inverse): `P K Pᵀ`, lower triangle, rows
    /// sorted, with the current values permuted along (the values are zero when
    /// there are none). Later assemblies place each equation's entries at its
    /// position in the order.
    pub fn in_order(&self, order: &[u32], inverse: &[u32]) -> Stiffness {
        let zeros;
        let values = if self.values.len() == self.row_idx.len() {
            &self.values
        } else {
            zeros = vec![0.0; self.row_idx.len()];
            &zeros
        };
        self.permuted(Some(values), self.parts_only, order, inverse, None)
            .unwrap_or_else(|_| unreachable!("no stop flag to read"))
    }

    /// The pattern of this matrix in the elimination order, as [`Stiffness::in_order`]
    /// stores it, without values (set them with [`Stiffness::set_parts_values`] or
    /// [`Stiffness::assemble`]). `stop`, if given, is read every
    /// [`STOP_CHECK_ROWS`] columns of each pass: [`Stopped`] once it is nonzero.
    pub fn in_order_pattern(
        &self,
        order: &[u32],
        inverse: &[u32],
        stop: Option<&AtomicUsize>,
    ) -> Result<Stiffness, Stopped> {
        self.permuted(None, false, order, inverse, stop)
    }

    /// The values of the elements of `sources` in this matrix's storage (those
    /// [`Stiffness::assemble_parts`] would set), leaving the matrix as it is: one
    /// thread assembles them while another reads the pattern.
    pub fn values_of<D: Dim>(&self, sources: &[&dyn ElementSource], dofs: &DofMap<D>) -> Vec<f64> {
        let mut values = vec![0.0; self.row_idx.len()];
        self.add_sources(&mut values, sources, dofs);
        values
    }

    /// Sets the values to `values`, the constant part (the parts' elements, from
    /// [`Stiffness::values_of`]), to which the next [`Stiffness::assemble`] adds
    /// the coupling elements.
    pub fn set_parts_values(&mut self, values: Vec<f64>) {
        assert_eq!(values.len(), self.row_idx.len(), "values of another pattern");
        self.values = values;
        self.parts_only = true;
    }

    /// This matrix with `values` (`None`: the pattern only, no values) in the
    /// elimination order (see [`Stiffness::in_order`]), `stop` (if any) read
    /// every [`STOP_CHECK_ROWS`] columns of each pass.
    fn permuted(
        &self,
        values: Option<&[f64]>,
        parts_only: bool,
        order: &[u32],
        inverse: &[u32],
        stop: Option<&AtomicUsize>,
    ) -> Result<Stiffness, Stopped> {
        let n = self.n();
        let nnz = self.row_idx.len();
        // A wrong order would misplace entries silently: checked here (O(n), next
        // to the O(nnz) copy), as faer's permute did.
        assert!(
            order.len() == n
                && inverse.len() == n
                && order
                    .iter()
                    .enumerate()
                    .all(|(k, &e)| inverse.get(e as usize).is_some_and(|&i| i as usize == k)),
            "the elimination order and its inverse are not inverse permutations"
        );
        // The stored matrix's rows are its equations' positions: compose with
        // its own order.
        let composed;
        let inverse = if self.position.is_empty() {
            inverse
        } else {
            let mut inv = vec![0; n];
            for (k, &e) in order.iter().enumerate() {
                inv[self.position[e as usize] as usize] = narrow(k);
            }
            composed = inv;
            &composed[..]
        };
        // Entry (i, j) of the stored lower triangle goes to column min(i', j'),
        // row max(i', j') (i' = inverse[i]): counted, placed column by column,
        // then each (short) column sorted by row; the values move along.
        let mut col_ptr = vec![0usize; n + 1];
        for j in 0..n {
            if j.is_multiple_of(STOP_CHECK_ROWS) {
                check_stop(stop)?;
            }
            let pj = inverse[j] as usize;
            for &i in &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]] {
                col_ptr[(inverse[i as usize] as usize).min(pj) + 1] += 1;
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0u32; nnz];
        let mut new_values = vec![0.0; if values.is_some() { nnz } else { 0 }];
        for j in 0..n {
            if j.is_multiple_of(STOP_CHECK_ROWS) {
                check_stop(stop)?;
            }
            let pj = inverse[j] as usize;
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let pi = inverse[self.row_idx[p] as usize] as usize;
                let (r, c) = (pi.max(pj), pi.min(pj));
                let at = next[c];
                next[c] += 1;
                row_idx[at] = narrow(r);
                if let Some(values) = values {
                    new_values[at] = values[p];
                }
            }
        }
        drop(next);
        for c in 0..n {
            if c.is_multiple_of(STOP_CHECK_ROWS) {
                check_stop(stop)?;
            }
            let (s, e) = (col_ptr[c], col_ptr[c + 1]);
            let rows = &mut row_idx[s..e];
            if values.is_none() {
                rows.sort_unstable();
                continue;
            }
            // Insertion sort of the (short) column, its values along.
            let vals = &mut new_values[s..e];
            for k in 1..rows.len() {
                let (r, v) = (rows[k], vals[k]);
                let mut at = k;
                while at > 0 && rows[at - 1] > r {
                    rows[at] = rows[at - 1];
                    vals[at] = vals[at - 1];
                    at -= 1;
                }
                rows[at] = r;
                vals[at] = v;
            }
        }
        let mut position = vec![0u32; n];
        for (e, p) in position.iter_mut().enumerate() {
            *p = inverse[self.stored(e)];
        }
        Ok(Stiffness {
            col_ptr,
            row_idx,
            values: new_values,
            position,
            parts_only,
        })
    }

    /// Sets the values to those of the elements of `sources` (the constant part,
    /// usually the parts), to which the next [`Stiffness::assemble`] adds the
    /// coupling elements.
    pub fn assemble_parts<D: Dim>(&mut self, sources: &[&dyn ElementSource], dofs: &DofMap<D>) {
        let mut values = std::mem::take(&mut self.values);
        values.clear();
        values.resize(self.row_idx.len(), 0.0);
        self.add_sources(&mut values, sources, dofs);
        self.values = values;
        self.parts_only = true;
    }

    /// Frees the values (the pattern stays); the next [`Stiffness::assemble`]
    /// assembles them anew.
    pub fn free_values(&mut self) {
        drop(self.take_values());
    }

    /// Takes the values out (for a factorization that frees them once read),
    /// leaving the pattern; the next [`Stiffness::assemble`] assembles them anew.
    pub fn take_values(&mut self) -> Vec<f64> {
        self.parts_only = false;
        std::mem::take(&mut self.values)
    }

    /// Row (and column) of equation `e` in the stored matrix.
    pub fn stored(&self, e: usize) -> usize {
        if self.position.is_empty() {
            e
        } else {
            self.position[e] as usize
        }
    }

    /// The row (and column) in the stored matrix of every equation, when it is
    /// stored in an elimination order (`None`: the equations' order).
    pub fn positions(&self) -> Option<&[u32]> {
        (!self.position.is_empty()).then_some(&self.position[..])
    }

    /// Number of equations.
    pub fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Position of entry (row i, column j), i ≥ j, in the value array.
    fn position(&self, i: usize, j: usize) -> usize {
        let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
        s + self.row_idx[s..e]
            .binary_search(&narrow(i))
            .expect("entry is in the sparsity pattern")
    }

    /// Adds an element matrix (entry `(a, b)` over local DOFs `g` at
    /// `k[a * stride + b]`) into `values`, free DOFs only: the entries of its
    /// lower triangle in the equations' order (so the values do not depend on the
    /// order the matrix is stored in, to the last bit, whatever the rounding of
    /// the element matrix's symmetry), each at its place in the lower triangle of
    /// the stored matrix.
    ///
    /// The element's DOFs are sorted by their stored row; each stored column is
    /// then walked once for all the element's rows at or below it (sorted too),
    /// instead of a binary search per entry. Each entry of `values` still gets
    /// one term per element, so the sums are those of any other visiting order.
    fn scatter<D: Dim>(&self, values: &mut [f64], dofs: &DofMap<D>, g: &[usize], k: &[f64], stride: usize) {
        /// DOFs of the largest element walked column by column (larger ones are
        /// searched entry by entry).
        const MERGE_MAX: usize = 32;
        if g.len() > MERGE_MAX {
            return self.scatter_searched(values, dofs, g, k, stride);
        }
        // (stored row, equation, local DOF) of each free DOF, sorted by row.
        let mut free = [(0u32, 0usize, 0usize); MERGE_MAX];
        let mut m = 0;
        for (a, &ga) in g.iter().enumerate() {
            let e = dofs.eq[ga];
            if e == FIXED {
                continue;
            }
            let entry = (narrow(self.stored(e)), e, a);
            let mut at = m;
            while at > 0 && free[at - 1].0 > entry.0 {
                free[at] = free[at - 1];
                at -= 1;
            }
            free[at] = entry;
            m += 1;
        }
        let free = &free[..m];
        if free.windows(2).any(|w| w[0].0 == w[1].0) {
            // A DOF twice in one element: the entry-by-entry order.
            return self.scatter_searched(values, dofs, g, k, stride);
        }
        for (c, &(j, ej, b)) in free.iter().enumerate() {
            let start = self.col_ptr[j as usize];
            let rows = &self.row_idx[start..self.col_ptr[j as usize + 1]];
            let mut p = 0;
            for &(i, ei, a) in &free[c..] {
                p += rows[p..]
                    .iter()
                    .position(|&r| r == i)
                    .expect("entry is in the sparsity pattern");
                // The lower triangle in the equations' order: entry (a, b) with
                // equation a ≥ equation b.
                values[start + p] += if ei >= ej {
                    k[a * stride + b]
                } else {
                    k[b * stride + a]
                };
            }
        }
    }

    /// [`Stiffness::scatter`] entry by entry, each found by a binary search in
    /// its column.
    fn scatter_searched<D: Dim>(
        &self,
        values: &mut [f64],
        dofs: &DofMap<D>,
        g: &[usize],
        k: &[f64],
        stride: usize,
    ) {
        for (b, &gb) in g.iter().enumerate() {
            let eb = dofs.eq[gb];
            if eb == FIXED {
                continue;
            }
            let j = self.stored(eb);
            for (a, &ga) in g.iter().enumerate() {
                let ea = dofs.eq[ga];
                if ea == FIXED || ea < eb {
                    continue;
                }
                let i = self.stored(ea);
                let pos = self.position(i.max(j), i.min(j));
                values[pos] += k[a * stride + b];
            }
        }
    }

    /// Adds the stiffness of every element of `sources` into `values`.
    fn add_sources<D: Dim>(&self, values: &mut [f64], sources: &[&dyn ElementSource], dofs: &DofMap<D>) {
        for source in sources {
            source.for_each_stiffness(&mut |g, k, stride| self.scatter(values, dofs, g, k, stride));
        }
    }

    /// Sets the values to parts + the coupling elements in their `states`
    /// (`states[i][k]` for pair k of interface i).
    pub fn assemble<D: ElementFamily>(
        &mut self,
        parts: &[Part<D>],
        interfaces: &[Interface<D>],
        states: &[Vec<PairState>],
        dofs: &DofMap<D>,
    ) {
        self.assemble_sources(
            &[&PartElements::new(parts, dofs)],
            &[&CouplingElements::new(interfaces, Some(states), dofs)],
            dofs,
        );
    }

    /// Sets the values to the elements of `constant` (unless they are there
    /// already, from [`Stiffness::assemble_parts`]) plus those of `varying` (the
    /// elements whose stiffness changes between solves).
    pub fn assemble_sources<D: Dim>(
        &mut self,
        constant: &[&dyn ElementSource],
        varying: &[&dyn ElementSource],
        dofs: &DofMap<D>,
    ) {
        if !self.parts_only || self.values.len() != self.row_idx.len() {
            self.assemble_parts(constant, dofs);
        }
        let mut values = std::mem::take(&mut self.values);
        self.add_sources(&mut values, varying, dofs);
        self.values = values;
        self.parts_only = false;
    }

    /// The current matrix as a faer sparse view (lower triangle of the stored
    /// matrix). The values must be there (assembled, not freed). The row indices
    /// are widened to `usize` for the call (a copy of 8 bytes per stored entry,
    /// freed after it): for faer's own routines (tests, AMD); the solver reads
    /// the 4-byte rows as they are.
    pub fn with_matrix<R>(&self, f: impl FnOnce(SparseColMatRef<'_, usize, f64>) -> R) -> R {
        let n = self.n();
        let rows: Vec<usize> = self.row_idx.iter().map(|&i| i as usize).collect();
        let symbolic = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &rows);
        f(SparseColMatRef::new(symbolic, &self.values))
    }
}

/// The internal force vector over all DOFs, `F_int = Σ_parts K_e u_e + Σ_CFE B_eᵀ Rᵀ f`
/// (seed eq. 1), for the full displacement vector `u` (free and prescribed DOFs).
pub fn internal_force<D: ElementFamily>(
    parts: &[Part<D>],
    interfaces: &[Interface<D>],
    states: &[Vec<PairState>],
    dofs: &DofMap<D>,
    u: &[f64],
) -> Vec<f64> {
    internal_force_with(parts, interfaces, states, None, dofs, u)
}

/// As [`internal_force`], with the pairs' histories (slip, slip force,
/// multipliers; `None`: all zero) in the coupling elements' forces.
pub fn internal_force_with<D: ElementFamily>(
    parts: &[Part<D>],
    interfaces: &[Interface<D>],
    states: &[Vec<PairState>],
    history: Option<&[Vec<PairHistory<D>>]>,
    dofs: &DofMap<D>,
    u: &[f64],
) -> Vec<f64> {
    let part_elements = PartElements::new(parts, dofs);
    let coupling_elements =
        CouplingElements::new(interfaces, Some(states), dofs).with_history(history);
    internal_force_of(&[&part_elements, &coupling_elements], u)
}

/// The internal force `Σ_e F_e(u)` of the elements of `source` at the DOFs `at`
/// only (sorted, each once; every DOF an element touches must be among them),
/// summed in element order: the bits of [`internal_force_of`] there for a source
/// it sums in element order (not [parallel](ElementSource::parallel)), without
/// a vector of all DOFs. For the few DOFs of the coupling elements, say.
pub fn internal_force_at(source: &dyn ElementSource, u: &[f64], at: &[usize]) -> Vec<f64> {
    let mut f = vec![0.0; at.len()];
    for e in 0..source.len() {
        source.internal_force(e, u, &mut |g, fe| {
            for (&d, v) in g.iter().zip(fe) {
                let k = at
                    .binary_search(&d)
                    .unwrap_or_else(|_| panic!("DOF {d} of element {e} is not among `at`"));
                f[k] += v;
            }
        });
    }
    f
}

/// The internal force vector over all DOFs, `Σ_e F_e(u)` over the elements of
/// `sources`, summed source after source: for a [parallel](ElementSource::parallel)
/// source in one chunk of elements per thread, the first into a vector of all
/// DOFs and each other into a vector of the DOFs its elements touch
/// ([`ElementSource::dof_span`]), added to the first in chunk order (the same
/// sum whatever thread finishes first); in element order otherwise.
pub fn internal_force_of(sources: &[&dyn ElementSource], u: &[f64]) -> Vec<f64> {
    use rayon::prelude::*;
    // Allocated by the first contribution (a parallel source's sum is taken as it is).
    let mut f: Option<Vec<f64>> = None;
    for source in sources {
        if !source.parallel() {
            let f = f.get_or_insert_with(|| vec![0.0; u.len()]);
            source.add_internal_forces(0..source.len(), u, f, 0);
            continue;
        }
        let threads = rayon::current_num_threads().max(1);
        let chunk = source.len().div_ceil(threads).max(1);
        let chunks: Vec<std::ops::Range<usize>> = (0..source.len())
            .step_by(chunk)
            .map(|s| s..(s + chunk).min(source.len()))
            .collect();
        let mut sums: Vec<(usize, Vec<f64>)> = chunks
            .into_par_iter()
            .enumerate()
            .map(|(i, range)| {
                let span = match i {
                    0 => 0..u.len(),
                    _ => source.dof_span(range.clone()).unwrap_or(0..u.len()),
                };
                let mut w = vec![0.0; span.len()];
                source.add_internal_forces(range, u, &mut w, span.start);
                (span.start, w)
            })
            .collect();
        if sums.is_empty() {
            continue;
        }
        let (_, mut sum) = sums.remove(0);
        for (first, w) in sums {
            for (x, y) in sum[first..first + w.len()].iter_mut().zip(&w) {
                *x += y;
            }
        }
        match &mut f {
            None => f = Some(sum),
            Some(f) => {
                for (x, y) in f.iter_mut().zip(&sum) {
                    *x += y;
                }
            }
        }
    }
    f.unwrap_or_else(|| vec![0.0; u.len()])
}

/// The external force vector over all DOFs at full load.
pub fn external_force<D: Dim>(loads: &[Load<D>], dofs: &DofMap<D>) -> Vec<f64> {
    let mut f = vec![0.0; dofs.dof(dofs.n_nodes(), 0)];
    for load in loads {
        for &(n, v) in &load.nodal {
            let g = dofs.node(load.part, n);
            for (c, v) in v.as_ref().iter().enumerate() {
                f[dofs.dof(g, c)] += v;
            }
        }
    }
    f
}

/// Most equations a [`Stiffness`] can hold: its row indices take 4 bytes.
/// `solve::setup` refuses larger systems with [`crate::Error::TooLarge`] before
/// the pattern is built (they would need terabytes of memory anyway).
pub const MAX_EQUATIONS: usize = u32::MAX as usize;

/// `data` cut into the pieces of the consecutive ranges `bounds[i]..bounds[i + 1]`:
/// the piece of a range holds `data[offset(start) − offset(bounds[0]) ..
/// offset(end) − offset(bounds[0])]` (`offset` non-decreasing, the last piece
/// ending at most at the end of `data`). Each piece goes to its own thread.
pub(crate) fn cut_at<'a, T>(
    data: &'a mut [T],
    bounds: &[usize],
    offset: impl Fn(usize) -> usize,
) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let mut pieces = Vec::with_capacity(bounds.len().saturating_sub(1));
    let mut rest = data;
    for w in bounds.windows(2) {
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(offset(w[1]) - offset(w[0]));
        pieces.push((w[0]..w[1], head));
        rest = tail;
    }
    pieces
}

/// `0, block, 2 block, …, n`: the bounds of `n` items in blocks of `block`.
fn blocks_of(n: usize, block: usize) -> Vec<usize> {
    (0..n).step_by(block).chain(std::iter::once(n)).collect()
}

/// A row index stored in 4 bytes (at most [`MAX_EQUATIONS`] equations).
fn narrow(i: usize) -> u32 {
    u32::try_from(i).expect("at most MAX_EQUATIONS equations (checked by solve::setup)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Material, PlaneKind};
    use crate::mesh::{ElementKind, Mesh};

    /// Two parts, 3 × 1 each, one above the other: T3 cells `a` below, Q4 cells
    /// `b` above (not coupled: the tests read each part's elements).
    fn t3_under_q4(a: [usize; 2], b: [usize; 2]) -> Vec<Part> {
        let material = Material::new(200.0, 0.3, PlaneKind::Stress, 1.0, "m").unwrap();
        vec![
            Part {
                name: "a".into(),
                mesh: Mesh::rectangle([0.0, 3.0], [0.0, 1.0], a, ElementKind::T3),
                material,
            },
            Part {
                name: "b".into(),
                mesh: Mesh::rectangle([0.0, 3.0], [1.0, 2.0], b, ElementKind::Q4),
                material,
            },
        ]
    }

    /// Displacements of every DOF with no pattern an error could hide in.
    fn some_displacements(dofs: &DofMap) -> Vec<f64> {
        (0..2 * dofs.n_nodes()).map(|i| (0.37 * i as f64).sin() * 1e-3).collect()
    }

    /// The parallel internal force sums its chunks in chunk order, each past the
    /// first over the DOFs it touches only: on 1 to 5 threads, two parts (T3
    /// and Q4) give the same bits as the chunks' full vectors added in order,
    /// the same bits on every repetition, and the element-by-element sum to
    /// round-off.
    #[test]
    fn chunked_internal_force_is_the_ordered_sum_of_its_chunks() {
        let parts = t3_under_q4([30, 8], [20, 6]);
        let dofs = DofMap::new(&parts, &[]);
        let u = some_displacements(&dofs);
        let elements = PartElements::new(&parts, &dofs);
        let mut one_by_one = vec![0.0; u.len()];
        elements.add_internal_forces(0..elements.len(), &u, &mut one_by_one, 0);
        let scale = one_by_one.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for threads in 1..=5 {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let got = pool.install(|| internal_force_of(&[&elements], &u));
            let again = pool.install(|| internal_force_of(&[&elements], &u));
            // The chunks' full vectors, added in order.
            let chunk = elements.len().div_ceil(threads);
            let mut ordered = vec![0.0; u.len()];
            for (i, start) in (0..elements.len()).step_by(chunk).enumerate() {
                let mut c = vec![0.0; u.len()];
                elements.add_internal_forces(start..(start + chunk).min(elements.len()), &u, &mut c, 0);
                if i == 0 {
                    ordered = c;
                } else {
                    ordered.iter_mut().zip(&c).for_each(|(x, y)| *x += y);
                }
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&ordered), "{threads} threads");
            assert_eq!(bits(&got), bits(&again), "{threads} threads, repeated");
            let worst = got.iter().zip(&one_by_one).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(worst <= 1e-14 * scale, "{threads} threads: {worst:e}");
        }
    }

    /// The elements touching some nodes give the complete internal force at
    /// those nodes' DOFs: on a T3 and a Q4 part, the elements `touching` a
    /// band of nodes across both parts (and no others) sum, as a
    /// [`SomeElements`] source, to the force of all elements at the band's
    /// DOFs, bit for bit in element order, and [`internal_force_at`] the DOFs
    /// they touch gives those bits without a vector of all DOFs.
    #[test]
    fn the_elements_touching_nodes_give_their_whole_force() {
        let parts = t3_under_q4([12, 4], [6, 3]);
        let dofs = DofMap::new(&parts, &[]);
        let u = some_displacements(&dofs);
        let all = PartElements::new(&parts, &dofs);
        // The nodes at x = 1.5 of either part (global numbering).
        let band: Vec<bool> = parts
            .iter()
            .flat_map(|p| p.mesh.nodes.iter().map(|x| (x[0] - 1.5).abs() < 1e-12))
            .collect();
        let touching = all.touching(|n| band[n]);
        // Every element with a node in the band, and only those.
        let mut expected = Vec::new();
        for e in 0..all.len() {
            let mut hit = false;
            all.nodes(e, &mut |g| hit = g.iter().any(|&n| band[n]));
            if hit {
                expected.push(e);
            }
        }
        assert_eq!(touching, expected);
        assert!(!touching.is_empty() && touching.len() < all.len());
        let some = SomeElements::new(&all, &touching);
        let (part, whole) = (internal_force_of(&[&some], &u), {
            let mut f = vec![0.0; u.len()];
            all.add_internal_forces(0..all.len(), &u, &mut f, 0);
            f
        });
        for (n, _) in band.iter().enumerate().filter(|(_, b)| **b) {
            for d in [2 * n, 2 * n + 1] {
                assert_eq!(part[d].to_bits(), whole[d].to_bits(), "DOF {d}");
            }
        }
        // Summed at every DOF those elements touch only, the same bits.
        let mut at = Vec::new();
        some.for_each_nodes(&mut |g| at.extend(g.iter().flat_map(|&n| [2 * n, 2 * n + 1])));
        at.sort_unstable();
        at.dedup();
        assert!(at.len() < u.len());
        for (&d, v) in at.iter().zip(&internal_force_at(&some, &u, &at)) {
            assert_eq!(v.to_bits(), part[d].to_bits(), "DOF {d} alone");
        }
    }

    /// The column-walking scatter puts every term of an element matrix (here
    /// unsymmetric, so a wrong triangle shows) where the entry-by-entry binary
    /// search does, bit for bit, with fixed DOFs, in the equations' order and
    /// in a reversed elimination order, for T3 and Q4 elements.
    #[test]
    fn walked_scatter_matches_searched_scatter() {
        for kind in [ElementKind::T3, ElementKind::Q4] {
            let parts = vec![Part {
                name: "p".into(),
                mesh: Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [5, 4], kind),
                material: Material::new(1.0, 0.3, PlaneKind::Stress, 1.0, "p").unwrap(),
            }];
            let supports = vec![crate::domain::Support {
                name: "s".into(),
                part: 0,
                nodes: parts[0].mesh.boundary_nodes("bottom").unwrap(),
                fix: [true, false, false],
                value: [0.0; 3],
                step: 0,
            }];
            let dofs = DofMap::new(&parts, &supports);
            let graph = NodeGraph::new(&parts, &[], &dofs);
            let k = Stiffness::pattern(&dofs, &graph);
            let order: Vec<u32> = (0..dofs.n_eq as u32).rev().collect();
            let reversed = k.in_order(&order, &order);
            for k in [&k, &reversed] {
                let (mut walked, mut searched) =
                    (vec![0.0; k.row_idx.len()], vec![0.0; k.row_idx.len()]);
                let elements = PartElements::new(&parts, &dofs);
                let mut e = 0.0;
                elements.for_each_nodes(&mut |nodes| {
                    let g: Vec<usize> = nodes.iter().flat_map(|&a| [2 * a, 2 * a + 1]).collect();
                    let n = g.len();
                    let m: Vec<f64> = (0..n * n)
                        .map(|i| (i as f64 * 0.37 + e).sin() / 3.0)
                        .collect();
                    k.scatter(&mut walked, &dofs, &g, &m, n);
                    k.scatter_searched(&mut searched, &dofs, &g, &m, n);
                    e += 1.0;
                });
                assert!(walked.iter().any(|&v| v != 0.0));
                for (w, s) in walked.iter().zip(&searched) {
                    assert_eq!(w.to_bits(), s.to_bits());
                }
            }
        }
    }

    /// The node graph built one range of rows per thread (here three threads on
    /// a Q4 and a T3 part) is, row by row, the sorted set of the nodes sharing an
    /// element with the node, listed element by element.
    #[test]
    fn node_graph_rows_are_the_nodes_sharing_an_element() {
        let parts: Vec<Part> = [ElementKind::Q4, ElementKind::T3]
            .into_iter()
            .map(|kind| Part {
                name: "p".into(),
                mesh: Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [7, 5], kind),
                material: Material::new(1.0, 0.3, PlaneKind::Stress, 1.0, "p").unwrap(),
            })
            .collect();
        let dofs = DofMap::new(&parts, &[]);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let graph = pool.install(|| NodeGraph::new(&parts, &[], &dofs));
        let mut expected = vec![std::collections::BTreeSet::new(); dofs.n_nodes()];
        PartElements::new(&parts, &dofs).for_each_nodes(&mut |nodes| {
            for &a in nodes {
                expected[a].extend(nodes.iter().copied());
            }
        });
        for (a, row) in expected.iter().enumerate() {
            assert_eq!(graph.neighbours(a), row.iter().copied().collect::<Vec<_>>());
        }
    }

    /// Storing a matrix in an elimination order and that copy back in the
    /// equations' order gives the matrix again, pattern and values bit for bit
    /// (the copy composes the order it is stored in with the one asked for).
    #[test]
    fn reordering_a_reordered_matrix_composes_the_orders() {
        let parts = vec![Part {
            name: "p".into(),
            mesh: Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [6, 3], ElementKind::Q4),
            material: Material::new(1.0, 0.3, PlaneKind::Strain, 1.0, "p").unwrap(),
        }];
        let dofs = DofMap::new(&parts, &[]);
        let graph = NodeGraph::new(&parts, &[], &dofs);
        let k = Stiffness::new(&parts, &dofs, &graph);
        let n = dofs.n_eq;
        // A scrambled order (5 is prime to the 56 equations) and its inverse.
        assert_eq!(n, 56);
        let order: Vec<u32> = (0..n).map(|i| ((i * 5 + 3) % n) as u32).collect();
        let mut inverse = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old as usize] = new as u32;
        }
        let scrambled = k.in_order(&order, &inverse);
        assert_ne!(scrambled.row_idx, k.row_idx);
        let identity: Vec<u32> = (0..n as u32).collect();
        let back = scrambled.in_order(&identity, &identity);
        assert_eq!(back.col_ptr, k.col_ptr);
        assert_eq!(back.row_idx, k.row_idx);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.values), bits(&k.values));
        assert!((0..n).all(|e| back.stored(e) == e && scrambled.stored(e) == inverse[e] as usize));
    }

    /// The node graph, the pattern and its copy in an elimination order read
    /// the caller's stop flag: set, each returns `Stopped` with its value; left
    /// zero, each gives what the call without a flag gives (the same graph,
    /// pattern and copy).
    #[test]
    fn a_set_stop_flag_ends_the_graph_and_the_patterns() {
        use std::sync::atomic::Ordering;
        let parts = vec![Part {
            name: "p".into(),
            mesh: Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [40, 20], ElementKind::T3),
            material: Material::new(1.0, 0.3, PlaneKind::Strain, 1.0, "p").unwrap(),
        }];
        let dofs = DofMap::new(&parts, &[]);
        let graph = NodeGraph::new(&parts, &[], &dofs);
        let k = Stiffness::pattern(&dofs, &graph);
        let n = dofs.n_eq;
        // A scrambled order (5 is prime to the 1722 equations) and its inverse.
        assert_eq!(n, 1722);
        let order: Vec<u32> = (0..n).map(|i| ((i * 5 + 3) % n) as u32).collect();
        let mut inverse = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old as usize] = new as u32;
        }
        let ordered = k.in_order_pattern(&order, &inverse, None).unwrap();
        let stop = AtomicUsize::new(0);
        let flagged = NodeGraph::new_until(&parts, &[], &dofs, Some(&stop)).unwrap();
        assert_eq!((&flagged.ptr, &flagged.adj), (&graph.ptr, &graph.adj));
        let flagged = Stiffness::pattern_until(&dofs, &graph, Some(&stop)).unwrap();
        assert_eq!((&flagged.col_ptr, &flagged.row_idx), (&k.col_ptr, &k.row_idx));
        let flagged = k.in_order_pattern(&order, &inverse, Some(&stop)).unwrap();
        assert_eq!((&flagged.col_ptr, &flagged.row_idx), (&ordered.col_ptr, &ordered.row_idx));
        assert_ne!(ordered.row_idx, k.row_idx);
        stop.store(15, Ordering::Relaxed);
        assert_eq!(
            NodeGraph::new_until(&parts, &[], &dofs, Some(&stop)).map(|_| ()),
            Err(Stopped(15))
        );
        assert_eq!(
            Stiffness::pattern_until(&dofs, &graph, Some(&stop)).map(|_| ()),
            Err(Stopped(15))
        );
        assert_eq!(
            k.in_order_pattern(&order, &inverse, Some(&stop)).map(|_| ()),
            Err(Stopped(15))
        );
    }
}
