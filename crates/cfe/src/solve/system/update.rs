//! The low-rank (Woodbury) update of the kept factor: which pairs flipped from
//! the base states and how their penalties changed, the choice by flops between
//! an update and a refactorization, the correction columns forward-solved and
//! cached, and the capacitance system `(Δ⁻¹ + VᵀV) t = Vᵀ z` applied to the
//! forward half of a solve (`z ← z − V t`).

use super::{ContactSystem, Half, Method, Read, UPDATE_FLOP_WEIGHT, UpdatePolicy};
use crate::assembly::{DofMap, FIXED};
use crate::coupling::{Interface, PairState};
use crate::dim::Tangent;
use crate::fem::ElementFamily;
use crate::solve::capacitance::{Capacitance, Entry};
use crate::solve::columns::{Columns, SparseColumn};
use crate::solve::factor::Halt;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use std::time::Instant;

impl<D: ElementFamily> ContactSystem<'_, D> {
    /// The forward half of a solve with the kept factor: `y = z − V t` (in the
    /// elimination order) for the backward solve, on the rows `read` (the others
    /// meaningless), or, when a new factorization is needed or cheaper, the
    /// complete solution in `rhs`.
    pub(super) fn forward_half(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        rhs_on_interface: bool,
        read: Read,
    ) -> Result<Half, Halt> {
        let Some(base) = &self.base else {
            return self
                .refactor_and_solve(interfaces, dofs, states, rhs)
                .map(Half::Solved);
        };
        let (flips, changes) = flipped_pairs(interfaces, states, base);
        let per_pair = columns_per_pair::<D>();
        if flips.is_empty() {
            let t = Instant::now();
            let z = self.forward_solve(rhs, rhs_on_interface, read);
            self.solve_seconds += t.elapsed().as_secs_f64();
            return Ok(Half::Forward(z, Method::Reuse));
        }
        let new: Vec<(usize, usize)> = flips
            .iter()
            .copied()
            .filter(|p| !self.cached.contains_key(p))
            .collect();
        if new.is_empty() {
            let entries = self.correction(&flips, &changes, per_pair);
            if let Some(cap) = self.capacitance.take_if(|c| c.entries() == entries.as_slice()) {
                return Ok(self.same_correction(cap, rhs, rhs_on_interface, read));
            }
        }
        let cols = self.new_columns(interfaces, dofs, &new);
        let paths: Vec<Vec<u32>> = cols.iter().map(|c| Columns::path(&self.chol, c)).collect();
        let r = (per_pair * flips.len()) as f64;
        // The dense system costed as one LU of it (an upper bound: a change of a
        // few entries is bordered, see `super::capacitance`).
        let dense = 2.0 / 3.0 * r * r * r;
        let cost_update = self.columns.add_flops(&self.chol, &paths) + self.chol.solve_flops() + dense;
        let cost_factor = self.chol.factor_flops() + self.chol.solve_flops();
        let memory = self.columns.bytes()
            + 8 * paths.iter().map(|p| self.path_width(p)).sum::<usize>()
            + self.columns.gram_bytes_with(per_pair * self.cached.len() + cols.len());
        let cheaper = match self.policy {
            UpdatePolicy::Auto => UPDATE_FLOP_WEIGHT * cost_update < cost_factor,
            UpdatePolicy::Always => true,
            UpdatePolicy::Never => false,
        };
        if !cheaper || memory > self.budget {
            return self
                .refactor_and_solve(interfaces, dofs, states, rhs)
                .map(Half::Solved);
        }
        let t = Instant::now();
        // The solve's halves are counted where they are done (the forward one only
        // when it is not kept, the backward one full or on the interface).
        self.flops += cost_update - self.chol.solve_flops() - dense;
        if !cols.is_empty() {
            self.cache_columns(&new, &cols, paths, per_pair);
        }
        let mut z = self.forward_solve(rhs, rhs_on_interface, read);
        let entries = self.correction(&flips, &changes, per_pair);
        let r = entries.len();
        let columns = &self.columns;
        let gram = |a: usize, b: usize| columns.gram(a, b);
        let cap = match self.capacitance.take() {
            Some(cap) => cap.update(entries, gram),
            None => Capacitance::new(entries, gram),
        };
        self.flops += cap.flops();
        self.apply_correction(&cap, &mut z);
        self.solve_seconds += t.elapsed().as_secs_f64();
        self.updates += 1;
        self.capacitance = Some(cap);
        Ok(Half::Forward(z, Method::LowRank { rank: r }))
    }

    /// The forward half of a solve with the same correction as the last update
    /// (only the right-hand side changed): the forward solve, r products with the
    /// kept columns and the capacitance's triangular solves.
    fn same_correction(
        &mut self,
        cap: Capacitance,
        rhs: &[f64],
        rhs_on_interface: bool,
        read: Read,
    ) -> Half {
        let t = Instant::now();
        let mut z = self.forward_solve(rhs, rhs_on_interface, read);
        let r = cap.entries().len();
        self.correct_again(cap, &mut z);
        self.solve_seconds += t.elapsed().as_secs_f64();
        Half::Forward(z, Method::LowRank { rank: r })
    }

    /// `z ← z − V_S t` with the last update's correction `cap` (its r products
    /// with the kept columns and the capacitance's triangular solves), which is
    /// kept for the next solve.
    pub(super) fn correct_again(&mut self, cap: Capacitance, z: &mut [f64]) {
        let r = cap.entries().len();
        self.apply_correction(&cap, z);
        self.flops += 2.0 * (r * r) as f64;
        self.capacitance = Some(cap);
    }

    /// `z ← z − V_S t` with `M_S t = V_Sᵀ z` (the correction's entries S).
    fn apply_correction(&self, cap: &Capacitance, z: &mut [f64]) {
        let columns: Vec<usize> = cap.entries().iter().map(|e| e.column).collect();
        let mut t = self.columns.dots(&self.chol, &columns, z);
        cap.solve_in_place(&mut t);
        let terms: Vec<(usize, f64)> = columns.into_iter().zip(t).collect();
        self.columns.subtract_all(&self.chol, &terms, z);
    }

    /// The Woodbury correction of the flipped pairs: the cached columns whose
    /// penalty changed and the change (±c_k: a pair bonding or opening changes
    /// both, a stick pair slipping or a frictionless pair closing only the normal
    /// one; a segment element's penalties include its weight). A pair has
    /// `per_pair` columns: the normal one (c_n), then one per tangent (c_s).
    fn correction(
        &self,
        flips: &[(usize, usize)],
        changes: &[[f64; 2]],
        per_pair: usize,
    ) -> Vec<Entry> {
        let mut entries = Vec::with_capacity(per_pair * flips.len());
        for (p, change) in flips.iter().zip(changes) {
            let c = self.cached[p];
            for t in 0..per_pair {
                let dc = change[t.min(1)];
                if dc != 0.0 {
                    entries.push(Entry {
                        column: c + t,
                        weight: dc,
                    });
                }
            }
        }
        entries
    }

    /// The flexibility of the pairs `pairs` under `K(states)`, from the kept
    /// factorization and its cached correction columns: `F = W_Pᵀ K⁻¹ W_T`,
    /// `W_P` every correction column of the pairs (normal, then each tangent:
    /// `per_pair` a pair, pair-major), `W_T` their tangential ones only, so
    /// entry `(r, s)` is the jump along axis r of the pairs a unit local force
    /// along tangential axis s causes; row-major, `per_pair m × (per_pair − 1) m`.
    /// With `K = K₀ + W_S Δ W_Sᵀ` (the update the last solve of `states` built)
    /// and `V = L⁻¹ P W`, Woodbury gives `F = G_PT − G_PS M_S⁻¹ G_ST` from the
    /// Gram matrix `G = VᵀV` of the cached columns and the factorized
    /// capacitance `M_S` (no solve with the factor: the pairs' columns not yet
    /// cached are forward-solved on their elimination-tree paths and cached,
    /// as an update of their flips would). `None` when nothing is factorized,
    /// the states are neither the factorized ones nor those of the kept
    /// capacitance, or the columns would not fit the cache's memory.
    pub fn pair_flexibility(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        pairs: &[(usize, usize)],
    ) -> Option<Vec<f64>> {
        let base = self.base.as_ref()?;
        let (flips, changes) = flipped_pairs(interfaces, states, base);
        let per_pair = columns_per_pair::<D>();
        if !flips.is_empty() {
            if flips.iter().any(|p| !self.cached.contains_key(p)) {
                return None;
            }
            let entries = self.correction(&flips, &changes, per_pair);
            if self.capacitance.as_ref()?.entries() != entries.as_slice() {
                return None;
            }
        }
        // The same pairs under the same correction: the same flexibility.
        let key = FlexibilityKey {
            pairs: pairs.to_vec(),
            correction: if flips.is_empty() {
                Vec::new()
            } else {
                self.capacitance.as_ref().map_or(Vec::new(), |c| c.entries().to_vec())
            },
        };
        if let Some((kept, f)) = &self.flexibility
            && *kept == key
        {
            return Some(f.clone());
        }
        let t = Instant::now();
        self.cache_pair_columns(interfaces, dofs, pairs, per_pair)?;
        let all: Vec<usize> = pairs
            .iter()
            .flat_map(|p| {
                let c = self.cached[p];
                c..c + per_pair
            })
            .collect();
        let tangential: Vec<usize> = all
            .iter()
            .enumerate()
            .filter(|(r, _)| r % per_pair != 0)
            .map(|(_, &c)| c)
            .collect();
        let columns = &self.columns;
        let (np, nt) = (all.len(), tangential.len());
        let mut f = Mat::<f64>::from_fn(np, nt, |r, j| columns.gram(all[r], tangential[j]));
        if !flips.is_empty() {
            self.subtract_correction(&mut f, &all, &tangential);
        }
        let f: Vec<f64> = (0..np).flat_map(|r| (0..nt).map(move |j| (r, j))).map(|(r, j)| f[(r, j)]).collect();
        self.flexibility = Some((key, f.clone()));
        self.solve_seconds += t.elapsed().as_secs_f64();
        Some(f)
    }

    /// Caches the correction columns of those of `pairs` not cached yet
    /// (forward-solved on their elimination-tree paths, as an update of their
    /// flips would); `None` when they would not fit the cache's memory.
    fn cache_pair_columns(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        pairs: &[(usize, usize)],
        per_pair: usize,
    ) -> Option<()> {
        let mut new: Vec<(usize, usize)> = pairs
        .iter()
        .copied()
        .filter(|p| !self.cached.contains_key(p))
        .collect();
    new.sort_unstable();
    new.dedup();
    if !new.is_empty() {
        let cols = self.new_columns(interfaces, dofs, &new);
        let paths: Vec<Vec<u32>> = cols.iter().map(|c| Columns::path(&self.chol, c)).collect();
        let memory = self.columns.bytes()
            + 8 * paths.iter().map(|p| self.path_width(p)).sum::<usize>()
            + self.columns.gram_bytes_with(per_pair * self.cached.len() + cols.len());
        if memory > self.budget {
            return None;
        }
        self.flops += self.columns.add_flops(&self.chol, &paths);
        self.cache_columns(&new, &cols, paths, per_pair);
    }
        Some(())
    }

    /// `F −= G_PS (M_S⁻¹ G_ST)` for the kept capacitance `M_S` of the last
    /// update (the r × nt solves, then one product), `all` and `tangential` the
    /// cached columns of F's rows and columns.
    fn subtract_correction(&mut self, f: &mut Mat<f64>, all: &[usize], tangential: &[usize]) {
        let Some(cap) = self.capacitance.as_ref() else {
            return;
        };
        let columns = &self.columns;
        let (np, nt) = (all.len(), tangential.len());
        // F −= G_PS (M_S⁻¹ G_ST): the r × nt solves, then one product.
        let s: Vec<usize> = cap.entries().iter().map(|e| e.column).collect();
        let r = s.len();
        let g_ps = Mat::<f64>::from_fn(np, r, |a, e| columns.gram(all[a], s[e]));
        let mut x = Mat::<f64>::zeros(r, nt);
        let mut col = vec![0.0; r];
        for (j, &b) in tangential.iter().enumerate() {
            for (e, v) in col.iter_mut().enumerate() {
                *v = columns.gram(s[e], b);
            }
            cap.solve_in_place(&mut col);
            for (e, v) in col.iter().enumerate() {
                x[(e, j)] = *v;
            }
        }
        matmul(f.as_mut(), Accum::Add, g_ps.as_ref(), x.as_ref(), -1.0, Par::Seq);
        let (r, p) = (r as f64, np as f64);
        self.flops += nt as f64 * (2.0 * r * r + 2.0 * r * p);
    }

    /// Rows of the factor on the supernodes of `path`.
    fn path_width(&self, path: &[u32]) -> usize {
        let sn = self.chol.supernodal();
        path.iter()
            .map(|&s| sn.supernode_end()[s as usize] - sn.supernode_begin()[s as usize])
            .sum()
    }

    /// The correction columns of the pairs `new` (not cached yet), their rows
    /// in the elimination order.
    fn new_columns(
        &self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        new: &[(usize, usize)],
    ) -> Vec<SparseColumn> {
        let mut cols = Vec::with_capacity(columns_per_pair::<D>() * new.len());
        for &(i, k) in new {
            for col in pair_columns(&interfaces[i], k, dofs) {
                cols.push(SparseColumn {
                    entries: col
                        .eq
                        .iter()
                        .zip(&col.w)
                        .map(|(&e, &w)| (self.chol.permuted(e), w))
                        .collect(),
                });
            }
        }
        cols
    }

    /// Forward-solves the columns `cols` of the pairs `new` along their `paths`
    /// and caches them (`per_pair` consecutive columns a pair).
    fn cache_columns(
        &mut self,
        new: &[(usize, usize)],
        cols: &[SparseColumn],
        paths: Vec<Vec<u32>>,
        per_pair: usize,
    ) {
        let first = self.columns.add(&self.chol, cols, paths);
        for (j, &(i, k)) in new.iter().enumerate() {
            self.cached.insert((i, k), first + per_pair * j);
        }
        // The columns' blocks grow by reallocation (each supernode's), and
        // their sparse solves' scratch is freed: pages that would stay
        // resident beside the factor through the next trials. Given back
        // once the columns have grown by a sixty-fourth of the factor.
        if self.columns.bytes() >= self.trimmed_at + self.chol.factor_nnz() / 8 {
            crate::solve::heap::return_free_memory();
            self.trimmed_at = self.columns.bytes();
        }
    }
}

/// What a pair flexibility was computed for: its pairs and the correction
/// (entries of the capacitance; empty for the factorized states themselves).
/// The factorization it was read from is the kept one: a new factorization
/// forgets it ([`ContactSystem::invalidate`]).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct FlexibilityKey {
    pairs: Vec<(usize, usize)>,
    correction: Vec<Entry>,
}

/// The pairs whose state differs from the base states (interface, pair), and
/// the change of each one's penalties (c_n, c_s) from its base state.
#[allow(clippy::type_complexity)]
fn flipped_pairs<D: ElementFamily>(
    interfaces: &[Interface<D>],
    states: &[Vec<PairState>],
    base: &[Vec<PairState>],
) -> (Vec<(usize, usize)>, Vec<[f64; 2]>) {
    let flips: Vec<(usize, usize)> = states
        .iter()
        .zip(base)
        .enumerate()
        .flat_map(|(i, (s, b))| {
            s.iter()
                .zip(b)
                .enumerate()
                .filter(|(_, (x, y))| x != y)
                .map(move |(k, _)| (i, k))
        })
        .collect();
    let changes: Vec<[f64; 2]> = flips
        .iter()
        .map(|&(i, k)| {
            let law = interfaces[i].elements[k].params(&interfaces[i].params());
            let (now, was) = (law.penalties(states[i][k]), law.penalties(base[i][k]));
            [now[0] - was[0], now[1] - was[1]]
        })
        .collect();
    (flips, changes)
}

/// One correction column: the free equations and values of `w_k`.
struct Column {
    eq: Vec<usize>,
    w: Vec<f64>,
}

/// The correction columns of a pair of dimension `D`: one per local axis
/// (the normal, then each tangent).
fn columns_per_pair<D: ElementFamily>() -> usize {
    1 + <D::Tangent as Tangent>::COMPONENTS
}

/// The correction columns (normal, then each tangent) of pair `k` of `iface`:
/// the element's rank-one terms `w_k` restricted to the free equations (their
/// weights, the change of the penalty c_k between the base state and the
/// current one, are taken at each solve).
fn pair_columns<D: ElementFamily>(iface: &Interface<D>, k: usize, dofs: &DofMap<D>) -> Vec<Column> {
    let c = &iface.elements[k];
    let g = c.dofs(dofs, iface.host, iface.node_part);
    let g = g.as_slice();
    let mut cols = Vec::with_capacity(columns_per_pair::<D>());
    c.for_each_stiffness_term(iface.c_n, iface.c_s, |_, _, w| {
        let mut col = Column {
            eq: Vec::with_capacity(g.len()),
            w: Vec::with_capacity(g.len()),
        };
        for (p, &gp) in g.iter().enumerate() {
            let e = dofs.eq[gp];
            if e != FIXED {
                col.eq.push(e);
                col.w.push(w[p]);
            }
        }
        cols.push(col);
    });
    cols
}
