//! The linear system `K(D̂) x = b` for a set of pair states, solved with the least
//! work: the Cholesky factor of the stiffness for some *base* states is kept, and a
//! new state set that differs from the base in a few pairs is solved by a low-rank
//! (Sherman–Morrison–Woodbury) correction of that factor instead of a new
//! factorization. A cost model in flops chooses (deterministic: the same choice on
//! every run): refactorization costs one numeric factorization and a solve; an
//! update costs the sparse forward solves of the correction columns not yet cached
//! (two per changed pair, see `super::columns`), one solve of the right-hand side
//! and a dense solve of the capacitance. Each call reports what it did.
//!
//! A CFE's stiffness is `K_e = Σ_k c_k w_k w_kᵀ` with `w_k = (R_k B_e)ᵀ` (k = n, s), so
//! flipping a pair adds or removes a rank-2 term, and with `K₀ = Pᵀ L Lᵀ P`,
//! `K = K₀ + W Δ Wᵀ`, `V = L⁻¹ P W`, `z = L⁻¹ P b`:
//! `K⁻¹ b = Pᵀ L⁻ᵀ (z − V t)`, `(Δ⁻¹ + VᵀV) t = Vᵀ z`.

use super::capacitance::Capacitance;
use super::columns::Columns;
use super::factor::Halt;
use super::linear::CholeskySolver;
use super::lower::LowerMatrix;
use crate::assembly::{DofMap, FIXED, Stiffness};
use crate::coupling::{Interface, PairState, PairStates};
use crate::dim::D2;
use crate::domain::Part;
use crate::fem::ElementFamily;
use std::collections::HashMap;
use std::sync::atomic::AtomicUsize;
use std::time::Instant;

mod update;

/// How one solve was done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// A numeric factorization for these states, then a solve.
    Factorization,
    /// A solve with the factorization of the same states.
    Reuse,
    /// A low-rank correction of the factorization of other states.
    LowRank {
        /// Rank of the correction (2 per changed pair).
        rank: usize,
    },
}

/// When to use a low-rank update instead of a new factorization.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpdatePolicy {
    /// Whichever the cost model says is cheaper (default).
    Auto,
    /// Always update when the cached columns fit in memory (for tests and studies).
    Always,
    /// Always refactorize.
    Never,
}

/// A flop of a sparse forward solve of correction columns (small dense blocks,
/// one thread) costs about this many flops of the numeric factorization (large
/// blocks, all threads): measured on the plate on a base at 1 M unknowns.
pub const UPDATE_FLOP_WEIGHT: f64 = 4.0;

/// The stiffness, its factorization for the base states, and the cached
/// low-rank correction columns.
pub struct ContactSystem<'a, D: ElementFamily = D2> {
    /// The parts, whose stiffness is assembled anew for each factorization.
    parts: &'a [Part<D>],
    /// The caller's stop flag, read before every supernode of a numeric
    /// factorization ([`ContactSystem::set_stop`]).
    stop: Option<&'a AtomicUsize>,
    /// The stiffness with its fixed pattern, in the factorization's elimination
    /// order; its values are there only while a factorization needs them, its
    /// pattern (`None`: freed) while another factorization may
    /// ([`ContactSystem::keep_pattern`]).
    k: Option<Stiffness>,
    /// Entries stored in the stiffness's lower triangle.
    k_entries: usize,
    /// Whether the stiffness's pattern is kept between factorizations (the
    /// default). When another factorization is unlikely (proportional loads:
    /// one factorization answers every increment) the solver sets it `false`:
    /// the pattern, a 4-byte row index per stored entry and a pointer per column
    /// (37 MiB at 1 M unknowns), is freed after each factorization instead of
    /// held beside the factor, and built again (node graph, pattern, elimination
    /// order: `super::setup::pattern_in_order`) should one be needed.
    pub keep_pattern: bool,
    chol: CholeskySolver,
    base: Option<PairStates>,
    /// First of the two correction columns of each changed pair (relative to `base`).
    cached: HashMap<(usize, usize), usize>,
    /// `V = L⁻¹ P W` of the cached columns.
    columns: Columns,
    /// The first right-hand side `b` solved with the current factorization (kept
    /// to be recognised, see [`KeptVector`]) and its `z = L⁻¹ P b` (the
    /// iterations of an increment share their right-hand side).
    forward: Option<(KeptVector, Vec<f64>)>,
    /// A vector of the equations' length kept between solves for the forward
    /// half's result (`z − V t`), so an iteration reuses its memory instead of
    /// allocating and first-touching a new one (65 MB at 8 M unknowns).
    spare: Vec<f64>,
    /// The factorized capacitance `Δ⁻¹ + VᵀV` of the last update, with the
    /// columns and weights it was built for: a solve with the same states and
    /// another right-hand side (a slip-force or Uzawa step) reuses it.
    capacitance: Option<Capacitance>,
    /// The last pair flexibility given ([`ContactSystem::pair_flexibility`]),
    /// with what it was computed for: asked again for the same pairs under
    /// the same correction (the next increment's patterns), it is returned
    /// as it is.
    flexibility: Option<(update::FlexibilityKey, Vec<f64>)>,
    /// The coupling elements' free equations and the supernodes of their
    /// elimination-tree paths (for [`ContactSystem::solve_interface`]; the
    /// pattern, hence the tree, is fixed).
    interface_set: Option<(Vec<usize>, Vec<usize>)>,
    /// The equations a refinement's residual reads and the supernodes of their
    /// and the coupling equations' elimination-tree paths (for
    /// [`ContactSystem::solve_unrefined`]).
    read_set: Option<(Vec<usize>, Vec<usize>)>,
    /// Largest memory for cached columns (bytes).
    budget: usize,
    /// The columns' bytes when the heap's free pages were last given back.
    trimmed_at: usize,
    /// When to update instead of refactorizing.
    pub policy: UpdatePolicy,
    /// Numeric factorizations so far.
    pub factorizations: usize,
    /// Low-rank updates so far (capacitance matrices built; further solves with
    /// the same correction and another right-hand side are not counted).
    pub updates: usize,
    /// Seconds in numeric factorizations.
    pub factor_seconds: f64,
    /// Seconds of the first numeric factorization.
    pub first_factor_seconds: Option<f64>,
    /// Seconds building the stiffness's pattern again after it was freed
    /// ([`ContactSystem::keep_pattern`]).
    pub pattern_seconds: f64,
    /// Seconds in solves (including update columns).
    pub solve_seconds: f64,
    /// Flops counted by the cost model for everything done so far (factorizations,
    /// solves, update columns): the deterministic measure of the work.
    pub flops: f64,
}

impl<'a, D: ElementFamily> ContactSystem<'a, D> {
    /// Wraps the stiffness of `parts` (and of coupling elements) and its symbolic
    /// factorization; the stiffness is put in the factorization's elimination
    /// order if it is not already (its values permuted along).
    pub fn new(parts: &'a [Part<D>], k: Stiffness, chol: CholeskySolver) -> Self {
        let budget = (256usize << 20).max(8 * chol.factor_nnz() / 4);
        let (order, inverse) = chol.order();
        let k = if k.positions() != Some(inverse) {
            k.in_order(order, inverse)
        } else {
            k
        };
        ContactSystem {
            parts,
            stop: None,
            k_entries: k.row_idx.len(),
            k: Some(k),
            keep_pattern: true,
            chol,
            base: None,
            cached: HashMap::new(),
            columns: Columns::default(),
            forward: None,
            spare: Vec::new(),
            capacitance: None,
            flexibility: None,
            interface_set: None,
            read_set: None,
            budget,
            trimmed_at: 0,
            policy: UpdatePolicy::Auto,
            factorizations: 0,
            updates: 0,
            factor_seconds: 0.0,
            first_factor_seconds: None,
            pattern_seconds: 0.0,
            solve_seconds: 0.0,
            flops: 0.0,
        }
    }

    /// Entries stored in the lower triangle of the stiffness.
    pub fn matrix_nnz(&self) -> usize {
        self.k_entries
    }

    /// Nonzeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.chol.factor_nnz()
    }

    /// Flops of one numeric factorization.
    pub fn factor_flops(&self) -> f64 {
        self.chol.factor_flops()
    }

    /// Has every numeric factorization read `stop` before each supernode (and
    /// the pattern built again for one, every few thousand rows): once
    /// it is nonzero the factorization is abandoned and the solve returns
    /// [`Halt::Stopped`] (the factor is then incomplete: the next solve
    /// refactorizes).
    pub fn set_stop(&mut self, stop: &'a AtomicUsize) {
        self.stop = Some(stop);
    }

    /// Forgets the factorization, so the next solve refactorizes.
    pub fn invalidate(&mut self) {
        self.base = None;
        self.cached.clear();
        self.columns.clear();
        self.trimmed_at = 0;
        self.forward = None;
        self.capacitance = None;
        self.flexibility = None;
    }

    /// Forgets the kept forward solve of the right-hand side and frees the spare
    /// vector: called when an increment is accepted, whose right-hand side is
    /// not solved again. The next increment's first full solve keeps its own
    /// (its iterations share it), and the memory of both (three vectors of the
    /// equations' size) is not held while the increment's results are built.
    pub fn forget_right_hand_side(&mut self) {
        self.forward = None;
        self.spare = Vec::new();
    }

    /// Whether a factorization is kept (the next solve may update it).
    pub fn has_factor(&self) -> bool {
        self.base.is_some()
    }

    /// Forgets the factorization and frees its memory (factor values, scratch,
    /// correction columns); the next solve refactorizes.
    pub fn release(&mut self) {
        self.invalidate();
        self.forget_right_hand_side();
        self.chol.release();
    }

    /// Solves `K(states) x = rhs` in place. A non-positive pivot returns the
    /// equation where it occurred.
    pub fn solve(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Method, Halt> {
        let half = self.forward_half(interfaces, dofs, states, rhs, false, Read::All)?;
        self.backward_half(half, rhs)
    }

    /// Solves `K(states) x = rhs` in place, like [`solve`](Self::solve), for a
    /// `rhs` that is zero off the coupling equations (a change of the pairs'
    /// forces): its forward solve runs on the interface's tree paths only
    /// ([`CholeskySolver::forward_on`]), the backward solve in full.
    pub fn solve_pair_forces(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Method, Halt> {
        self.interface_set(interfaces, dofs);
        let half = self.forward_half(interfaces, dofs, states, rhs, true, Read::All)?;
        self.backward_half(half, rhs)
    }

    /// Solves `K(states) x = rhs` in place like [`solve`](Self::solve), except
    /// that a low-rank update's solution is left for [`refine`](Self::refine)
    /// to complete: then only its entries at the equations `read` are written
    /// into `rhs` (the values of the unrefined solution there; the other entries
    /// are meaningless), from a backward solve on the supernodes of their
    /// elimination-tree paths, and the forward half is returned to be refined.
    /// `read` must hold every equation the caller's residual at the coupling
    /// equations depends on.
    ///
    /// A refinement is needed after an update, and only on the coupling
    /// equations: the update's round-off is in the capacitance's solution `t`
    /// (the cancellation of `1/Δc` against `Vᵀ V` when a stiff pair opens), so
    /// its solution is `K₀⁻¹ W δt` off and its residual is `−W (I + D Vᵀ V) δt`,
    /// on the rows of `W`: the coupling elements' DOFs. Elsewhere the residual
    /// is the round-off of the direct solve with the factor the update shares.
    /// The two solves then cost one backward solve in full and the tree paths
    /// of the interface (forward) and of `read` (backward), instead of three
    /// full passes over the factor.
    pub fn solve_unrefined(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        read: &[usize],
    ) -> Result<Solve, Halt> {
        match self.forward_half(interfaces, dofs, states, rhs, false, Read::All)? {
            Half::Forward(mut y, method @ Method::LowRank { .. }) => {
                let t = Instant::now();
                self.interface_set(interfaces, dofs);
                if self.read_set.as_ref().is_none_or(|(eqs, _)| eqs != read) {
                    let (coupling, _) = self.interface_set.as_ref().expect("computed above");
                    let rows = read.iter().chain(coupling).map(|&e| self.chol.permuted(e));
                    self.read_set = Some((read.to_vec(), self.chol.ancestors(rows)));
                }
                let (_, set) = self.read_set.as_ref().expect("computed above");
                // The backward solve on the paths, on a copy of their rows
                // (`y` is kept for the complete solve).
                let kept: Vec<f64> = self.chol.rows_on(set).flat_map(|r| y[r].to_vec()).collect();
                self.chol.backward_on(set, &mut y);
                for &e in read {
                    rhs[e] = y[self.chol.permuted(e)];
                }
                let mut kept = kept.into_iter();
                for r in self.chol.rows_on(set) {
                    y[r].iter_mut().zip(&mut kept).for_each(|(v, k)| *v = k);
                }
                self.flops += 2.0 * self.chol.values_on(set) as f64;
                self.solve_seconds += t.elapsed().as_secs_f64();
                Ok(Solve::Unrefined(Unrefined { y, method }))
            }
            half => self.backward_half(half, rhs).map(Solve::Complete),
        }
    }

    /// Completes the solve `unrefined` of [`solve_unrefined`](Self::solve_unrefined)
    /// with one step of iterative refinement: `r`, the residual of its values at
    /// the coupling equations (zero at every other equation), is solved by the
    /// same update (a forward solve on the interface's tree paths,
    /// [`CholeskySolver::forward_on`]) and added to its forward half, and one
    /// backward solve in full gives the refined solution, in `r`. It must follow
    /// its `solve_unrefined` with no other solve between them (the update's
    /// capacitance is the one kept from it).
    pub fn refine(&mut self, unrefined: Unrefined, r: &mut [f64]) -> Method {
        let Unrefined { mut y, method } = unrefined;
        let cap = self
            .capacitance
            .take()
            .expect("an unrefined solve is a low-rank update's, which keeps its capacitance");
        let t = Instant::now();
        // The correction `w = L⁻¹ P r − V t` in `r`'s own memory (no vector
        // of the unknowns' size beside `y` and `r`).
        let values: Vec<f64> = self.interface_equations().iter().map(|&e| r[e]).collect();
        r.fill(0.0);
        self.forward_on_interface(&values, r);
        self.correct_again(cap, r);
        // `w` lives on the interface's paths (the forward solve and the
        // columns both do).
        let (_, set) = self.interface_set.as_ref().expect("computed by solve_unrefined");
        for rows in self.chol.rows_on(set) {
            y[rows.clone()].iter_mut().zip(&r[rows]).for_each(|(a, b)| *a += b);
        }
        self.chol.backward(&mut y, r);
        self.spare = y;
        self.flops += self.chol.solve_flops() / 2.0;
        self.solve_seconds += t.elapsed().as_secs_f64();
        method
    }

    /// The coupling elements' free equations (computed by [`Self::interface_set`]).
    fn interface_equations(&self) -> &[usize] {
        &self.interface_set.as_ref().expect("interface set computed").0
    }

    /// `z ← L⁻¹ P b` for a `b` that is zero off the coupling equations, given as
    /// its `values` there (in [`Self::interface_equations`]' order), into a `z`
    /// of zeros: the forward solve on the interface's tree paths.
    fn forward_on_interface(&mut self, values: &[f64], z: &mut [f64]) {
        let (eqs, set) = self.interface_set.as_ref().expect("interface set computed");
        for (&e, &v) in eqs.iter().zip(values) {
            z[self.chol.permuted(e)] = v;
        }
        self.chol.forward_on(set, z);
        self.flops += 2.0 * self.chol.values_on(set) as f64;
    }

    /// The solution into `rhs` from the forward half `half` (a backward solve in
    /// full, unless the forward half refactorized and solved already).
    fn backward_half(&mut self, half: Half, rhs: &mut [f64]) -> Result<Method, Halt> {
        match half {
            Half::Solved(method) => Ok(method),
            Half::Forward(mut y, method) => {
                let t = Instant::now();
                self.chol.backward(&mut y, rhs);
                self.spare = y;
                self.solve_seconds += t.elapsed().as_secs_f64();
                self.flops += self.chol.solve_flops() / 2.0;
                Ok(method)
            }
        }
    }

    /// Solves `K(states) x = rhs` for the entries of `x` at the coupling elements'
    /// free equations only, written into `rhs` there; the other entries of `rhs`
    /// are left meaningless unless the returned flag says the solve was complete
    /// (a refactorization solves for every entry). `rhs_on_interface` says that
    /// `rhs` is zero off the coupling equations (a change of the pairs' constant
    /// forces), so the forward solve is restricted too.
    ///
    /// With the factor kept, the solves run on the supernodes of the
    /// elimination-tree paths from those equations to the root only
    /// ([`CholeskySolver::backward_on`], [`CholeskySolver::forward_on`]): the same
    /// values as the full solve there, for a fraction of its work (18–30 % of the
    /// factor on the plate on a base). This is what an active-set iteration needs
    /// to check the law on every pair, and a fixed-point step on the pairs' forces
    /// to update them.
    pub fn solve_interface(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        rhs_on_interface: bool,
    ) -> Result<(Method, bool), Halt> {
        self.interface_set(interfaces, dofs);
        let read = Read::InterfaceSet;
        match self.forward_half(interfaces, dofs, states, rhs, rhs_on_interface, read)? {
            Half::Solved(method) => Ok((method, true)),
            Half::Forward(mut y, method) => {
                let t = Instant::now();
                let (eqs, set) = self.interface_set.as_ref().expect("computed above");
                self.chol.backward_on(set, &mut y);
                for &e in eqs {
                    rhs[e] = y[self.chol.permuted(e)];
                }
                self.spare = y;
                self.flops += 2.0 * self.chol.values_on(set) as f64;
                self.solve_seconds += t.elapsed().as_secs_f64();
                Ok((method, false))
            }
        }
    }

    /// Computes, once, the coupling elements' free equations and the supernodes
    /// of their elimination-tree paths.
    fn interface_set(&mut self, interfaces: &[Interface<D>], dofs: &DofMap<D>) {
        if self.interface_set.is_none() {
            let eqs = interface_equations(interfaces, dofs);
            let set = self
                .chol
                .ancestors(eqs.iter().map(|&e| self.chol.permuted(e)));
            self.interface_set = Some((eqs, set));
        }
    }

    /// `z = L⁻¹ P b`, on the rows `read` (with the interface set computed, the
    /// others may be left meaningless: O(unknowns) less to zero or copy for a
    /// trial). The first right-hand side solved in full with a factorization,
    /// or since an increment was accepted
    /// ([`ContactSystem::forget_right_hand_side`]), is kept with its `z` (the
    /// iterations of an increment share it; the residuals of their refinement
    /// steps do not replace it).
    fn forward_solve(&mut self, b: &[f64], on_interface: bool, read: Read) -> Vec<f64> {
        let n = b.len();
        let on_set = read == Read::InterfaceSet && self.interface_set.is_some();
        if on_interface && self.interface_set.is_some() {
            let mut z = std::mem::take(&mut self.spare);
            if on_set {
                // Only the set's rows are solved and read: only they are zeroed.
                z.resize(n, 0.0);
                let (_, set) = self.interface_set.as_ref().expect("checked above");
                for rows in self.chol.rows_on(set) {
                    z[rows].fill(0.0);
                }
            } else {
                z.clear();
                z.resize(n, 0.0);
            }
            let values: Vec<f64> = self.interface_equations().iter().map(|&e| b[e]).collect();
            self.forward_on_interface(&values, &mut z);
            return z;
        }
        if let Some((kept, z)) = &self.forward
            && kept.equals(b)
        {
            let mut copy = std::mem::take(&mut self.spare);
            if on_set {
                copy.resize(n, 0.0);
                let (_, set) = self.interface_set.as_ref().expect("checked above");
                for rows in self.chol.rows_on(set) {
                    copy[rows.clone()].copy_from_slice(&z[rows]);
                }
            } else {
                copy.clear();
                copy.extend_from_slice(z);
            }
            return copy;
        }
        // The spare vector's memory, every entry written by the forward solve.
        let mut z = std::mem::take(&mut self.spare);
        z.resize(n, 0.0);
        self.chol.forward(b, &mut z);
        self.flops += self.chol.solve_flops() / 2.0;
        if self.forward.is_none() {
            self.forward = Some((KeptVector::of(b), z.clone()));
        }
        z
    }

    fn refactor_and_solve(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Method, Halt> {
        self.refactorize(interfaces, dofs, states)?;
        // The forward half of the solve is counted by `forward_solve`.
        self.flops += self.chol.factor_flops() + self.chol.solve_flops() / 2.0;
        let t = Instant::now();
        let mut z = self.forward_solve(rhs, false, Read::All);
        self.chol.backward(&mut z, rhs);
        self.solve_seconds += t.elapsed().as_secs_f64();
        Ok(Method::Factorization)
    }

    /// Factorizes `K(states)` (unless the kept factorization is of these
    /// states already) without solving: the next solve of these states reuses
    /// it, and one of states a few pairs away may update it. Returns what it
    /// did ([`Method::Factorization`] or [`Method::Reuse`]).
    pub fn factorize(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
    ) -> Result<Method, Halt> {
        if self.base.as_deref() == Some(states) {
            return Ok(Method::Reuse);
        }
        self.refactorize(interfaces, dofs, states)?;
        self.flops += self.chol.factor_flops();
        Ok(Method::Factorization)
    }

    /// A new numeric factorization of `K(states)`, kept as the base of later
    /// updates (its flops are counted by the caller).
    fn refactorize(
        &mut self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        states: &[Vec<PairState>],
    ) -> Result<(), Halt> {
        self.invalidate();
        let (order, inverse) = self.chol.order();
        if self.k.is_none() {
            let t = Instant::now();
            let k = super::setup::pattern_in_order(
                self.parts, interfaces, dofs, order, inverse, self.stop,
            )
            .map_err(|super::symbolic::Stopped(signal)| Halt::Stopped(signal))?;
            self.pattern_seconds += t.elapsed().as_secs_f64();
            self.k = Some(k);
        }
        let k = self.k.as_mut().expect("the pattern is built above");
        k.assemble(self.parts, interfaces, states, dofs);
        let t = Instant::now();
        // The values are needed by a factorization only: given to it, which frees
        // them once read (they are assembled anew for the next).
        let values = k.take_values();
        let factorized = self
            .chol
            .factorize(LowerMatrix::with_values(&k.col_ptr, &k.row_idx, values), self.stop);
        if !self.keep_pattern {
            self.k = None;
        }
        factorized?;
        let dt = t.elapsed().as_secs_f64();
        self.factor_seconds += dt;
        self.first_factor_seconds.get_or_insert(dt);
        self.factorizations += 1;
        self.base = Some(states.to_vec());
        Ok(())
    }
}

/// A vector kept only to recognise it later: its nonzero entries (a right-hand
/// side is mostly zeros: nodal loads on a boundary, the terms of a few
/// prescribed DOFs and pairs), or a copy of all of them when that is smaller
/// (body forces). Held beside the factor for an increment, so the few entries
/// matter: a copy would be a vector of the equations' size.
#[derive(Debug, Clone, PartialEq)]
enum KeptVector {
    /// Length, and the entries that are not zero (ascending) with their values.
    Sparse {
        len: usize,
        index: Vec<u32>,
        value: Vec<f64>,
    },
    Dense(Vec<f64>),
}

impl KeptVector {
    /// `b`, kept in the smaller of the two forms (12 bytes a nonzero entry, 8 an
    /// entry).
    fn of(b: &[f64]) -> Self {
        let nonzero = b.iter().filter(|&&x| x != 0.0).count();
        if 3 * nonzero >= 2 * b.len() || b.len() > u32::MAX as usize {
            return KeptVector::Dense(b.to_vec());
        }
        let (mut index, mut value) = (Vec::with_capacity(nonzero), Vec::with_capacity(nonzero));
        for (i, &x) in b.iter().enumerate().filter(|(_, x)| **x != 0.0) {
            index.push(i as u32);
            value.push(x);
        }
        KeptVector::Sparse {
            len: b.len(),
            index,
            value,
        }
    }

    /// Whether `b` equals the kept vector entry by entry (`==` on `f64`, as a
    /// comparison of the two slices: a NaN equals nothing, −0 equals 0).
    fn equals(&self, b: &[f64]) -> bool {
        match self {
            KeptVector::Dense(kept) => kept.as_slice() == b,
            KeptVector::Sparse { len, index, value } => {
                if *len != b.len() {
                    return false;
                }
                let mut from = 0;
                for (&i, &v) in index.iter().zip(value) {
                    let i = i as usize;
                    if b[i] != v || b[from..i].iter().any(|&x| x != 0.0) {
                        return false;
                    }
                    from = i + 1;
                }
                b[from..].iter().all(|&x| x == 0.0)
            }
        }
    }
}

/// A solve of [`ContactSystem::solve_unrefined`].
#[must_use]
pub enum Solve {
    /// The solution is complete, in the right-hand side's vector.
    Complete(Method),
    /// A low-rank update's solution, for [`ContactSystem::refine`] to complete.
    Unrefined(Unrefined),
}

/// The forward half `y = z − V t` of a low-rank update's solve, in the
/// elimination order, waiting for its refinement.
pub struct Unrefined {
    y: Vec<f64>,
    method: Method,
}

/// The rows of a forward half its caller reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Read {
    /// Every row (a complete solve follows).
    All,
    /// The rows of the interface set only ([`ContactSystem::solve_interface`]'s
    /// backward solve on its paths): the others are left meaningless.
    InterfaceSet,
}

/// The forward half of a solve.
enum Half {
    /// The solve is complete (after a new factorization).
    Solved(Method),
    /// `y = z − V t` in the elimination order, for the backward solve.
    Forward(Vec<f64>, Method),
}

/// The free equations of every coupling element's DOFs, sorted.
fn interface_equations<D: ElementFamily>(interfaces: &[Interface<D>], dofs: &DofMap<D>) -> Vec<usize> {
    let mut eqs: Vec<usize> = crate::coupling::coupling_dofs(interfaces, dofs)
        .into_iter()
        .map(|d| dofs.eq[d])
        .filter(|&e| e != FIXED)
        .collect();
    eqs.sort_unstable();
    eqs
}

#[cfg(test)]
mod tests {
    use super::KeptVector;

    /// A kept vector recognises exactly the vectors a slice comparison finds
    /// equal (`==` on `f64`), in both forms: mostly zeros (a load vector) and
    /// mostly nonzero (body forces), with zeros of either sign, a NaN, a
    /// changed, added or removed entry and another length.
    #[test]
    fn a_kept_vector_equals_what_a_copy_would() {
        let mut sparse = vec![0.0; 50];
        sparse[3] = -1.5;
        sparse[17] = 2.0;
        sparse[49] = 1e-300;
        let dense: Vec<f64> = (0..50).map(|i| 1.0 + i as f64).collect();
        assert!(matches!(KeptVector::of(&sparse), KeptVector::Sparse { .. }));
        assert!(matches!(KeptVector::of(&dense), KeptVector::Dense(_)));
        for base in [sparse, dense] {
            let kept = KeptVector::of(&base);
            let mut others = vec![base.clone(), base[..49].to_vec(), [&base[..], &[0.0]].concat()];
            for i in [0, 3, 4, 17, 48, 49] {
                for v in [0.0, -0.0, 7.0, f64::NAN, base[i] * (1.0 + f64::EPSILON)] {
                    let mut b = base.clone();
                    b[i] = v;
                    others.push(b);
                }
            }
            for b in &others {
                assert_eq!(kept.equals(b), base.as_slice() == b.as_slice(), "{b:?}");
            }
        }
        // A kept NaN is never recognised, as with a copy.
        let mut nan = vec![0.0; 10];
        nan[2] = f64::NAN;
        assert!(!KeptVector::of(&nan).equals(&nan));
    }
}
