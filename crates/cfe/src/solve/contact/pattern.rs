//! One pattern of pair states solved: completely (the displacements of every
//! DOF, the internal force, a low-rank update refined on the coupling ring, a
//! lost update solved again by factorization; or, with proportional loads, a
//! solved pattern scaled), or restricted to the coupling DOFs (a trial of the
//! active-set search); each with the pairs' terms at their fixed point. Its
//! right-hand sides, the internal forces, the result of an increment built
//! from a solution ([`Solver::finish`]) and the solution kept for scaling.

use super::fixed_point::FixedPointScale;
use super::increment::{IncrementResult, Iteration, MultipleOf, count_changes};
use super::pairs::LawCheck;
use super::solver::{CouplingRing, Solved, Solver, Spare, TrialRhs};
use crate::assembly::{self, DofMap, ElementSource, FIXED};
use crate::coupling::{Interface, PairHistory, PairState, PairStates};
use crate::dim::Dim;
use crate::domain::Part;
use crate::error::{Error, Result};
use crate::solve::backend::{Request, Solve};
use crate::solve::system::Method;
use std::time::Instant;

/// Out-of-balance tolerance above which a low-rank solution is redone by factorization.
const UPDATE_RESIDUAL_LIMIT: f64 = 1e-8;

/// A solution: displacements and internal force of all DOFs, and how the
/// system was solved (`None`: a solved pattern scaled).
type Solution = (Vec<f64>, Vec<f64>, Option<Method>);

impl<D: Dim> Solver<'_, D> {
    /// Solves the pattern `states` once at load factor `lambda` and checks the law on
    /// every pair, without iterating: the increment a run would end on if this
    /// pattern were its answer (`settled` empty, `violations` whatever the law says).
    /// For studies of the pattern space, e.g. whether any pattern near a settled one
    /// satisfies the law.
    pub fn solve_pattern(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
    ) -> Result<IncrementResult<D>> {
        let t = Instant::now();
        let (u, f_int, method) = self.solve_states(lambda, states, 1)?;
        let check = self.check_law(states, &u, &f_int, lambda);
        let history = vec![Iteration {
            method,
            changed: count_changes(&check.next, states),
            seconds: t.elapsed().as_secs_f64(),
        }];
        Ok(self.finish(1, lambda, history, u, f_int, states.to_vec(), check, false))
    }

    /// Displacements (all DOFs), internal force and solve method for the given
    /// states at load factor `lambda`, with the pairs' right-hand-side terms at
    /// their fixed point: the slip forces of slipping Coulomb pairs
    /// (`μ |f_n|` along the trial force, from the solution) and, with augmented
    /// Lagrangian enforcement, the multipliers (Uzawa: `m ← f`, until the largest
    /// penetration of a closed pair and stick error is below the interface's
    /// `penetration_tolerance`). Each further solve reuses the factorization of the
    /// pattern (the values of K do not change). One solve for the seed's laws.
    pub(super) fn solve_states(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<Solution> {
        let first = self.solve_once(lambda, states, inc)?;
        if self.proportional {
            return Ok(first);
        }
        let (mut u, f_first, method) = first;
        let u_first = u.clone();
        let Some(mut total) =
            self.fixed_point(states, inc, &mut u, FixedPointScale::Forces(lambda, &f_first))?
        else {
            return Ok((u, f_first, method));
        };
        // The summed change is on the coupling equations only.
        self.check_stop(inc)?;
        let outcome = self
            .linear
            .solve_pattern(Request::new(states).rhs_on_interface(), &mut total)
            .map_err(|f| self.linear_error(f, inc))?;
        self.record(&outcome);
        let mut u = u_first;
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                u[d] += total[e];
            }
        }
        let t = Instant::now();
        let f_int = self.internal_force(states, &u);
        self.timings.contact_update += t.elapsed().as_secs_f64();
        let residual = self.residual(lambda, &f_int, self.load_scale(lambda, &f_int, &u));
        if residual > UPDATE_RESIDUAL_LIMIT {
            // The corrections lost accuracy: solve the converged terms afresh.
            let (u, f_int, _) = self.solve_once(lambda, states, inc)?;
            return Ok((u, f_int, method));
        }
        Ok((u, f_int, method))
    }

    /// One linear solve of `states` at load factor `lambda` with the current pair
    /// histories.
    pub(super) fn solve_once(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<Solution> {
        if let Some(scaled) = self.scaled_solution(lambda, states) {
            return Ok(scaled);
        }
        let t = Instant::now();
        self.supports.check(self.parts, self.interfaces, states)?;
        self.timings.contact_update += t.elapsed().as_secs_f64();
        // This solve replaces the kept solution, whose vectors are freed now
        // rather than held beside this solve's; the trials' two vectors become
        // this solve's displacements and right-hand side (their pages already
        // touched: a fresh pair would be first-touched again, 61 MiB at 4 M
        // unknowns).
        let number = self.kept.last.take().map_or(0, |s| s.number + 1);
        let Spare { mut u, mut x, .. } = std::mem::take(&mut self.kept.spare);
        // The freed vectors and the columns' scratch stay resident in the heap
        // unless given back.
        crate::solve::heap::return_free_memory();
        // The right-hand side is solved in place (`x`); the rare second solve of
        // a lost update builds it again rather than keeping a copy.
        let _ = self.right_hand_side_into(lambda, states, &mut u, &mut x);
        let mut refactored = false;
        loop {
            let method = self.solve_in_place(lambda, states, inc, &mut u, &mut x)?;
            for (d, &e) in self.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    u[d] = x[e];
                }
            }
            if u.iter().any(|v| !v.is_finite()) {
                return Err(self.not_finite(inc));
            }
            // The solve's vector is spent: its memory serves the internal force
            // and the kept copies.
            drop(std::mem::take(&mut x));
            let t = Instant::now();
            let f_int = self.internal_force(states, &u);
            self.timings.contact_update += t.elapsed().as_secs_f64();
            let residual = self.residual(lambda, &f_int, self.load_scale(lambda, &f_int, &u));
            if residual > UPDATE_RESIDUAL_LIMIT
                && matches!(method, Method::LowRank { .. })
                && !refactored
            {
                // The update lost accuracy: solve again with a fresh factorization.
                self.linear.forget();
                refactored = true;
                let _ = self.right_hand_side_into(lambda, states, &mut u, &mut x);
                continue;
            }
            // Its values, to be scaled by later increments, are copied from the
            // increment's result once it is accepted (`keep_for_scaling`), after
            // the factor is freed, rather than here beside it.
            self.kept.last = Some(Solved {
                number,
                states: states.to_vec(),
                lambda,
                values: None,
            });
            crate::solve::heap::return_free_memory();
            return Ok((u, f_int, Some(method)));
        }
    }

    /// With proportional loads, the kept solution of `states` scaled to load
    /// factor `lambda`, if there is one.
    fn scaled_solution(&self, lambda: f64, states: &[Vec<PairState>]) -> Option<Solution> {
        if self.proportional
            && let Some(s) = &self.kept.last
            && let Some((su, sf)) = &s.values
            && s.states == states
            && s.lambda != 0.0
        {
            // Loads and prescribed values are proportional: same states, scaled solution.
            let f = lambda / s.lambda;
            let u = su.iter().map(|v| f * v).collect();
            let f_int = sf.iter().map(|v| f * v).collect();
            return Some((u, f_int, None));
        }
        None
    }

    /// Solves the right-hand side `x` (free equations) in place for `states`,
    /// through the seam: by the back end's complete solve (from the last
    /// solution, when it starts from a guess), or, when it offers refined
    /// solves, by a low-rank update refined on the coupling equations (the
    /// unrefined solution read into `u` around the coupling nodes).
    fn solve_in_place(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
        u: &mut [f64],
        x: &mut [f64],
    ) -> Result<Method> {
        // With a factor kept, the solve may be an update, whose refinement
        // reads the unrefined solution around the coupling nodes (the ring
        // is usually found by the first trial already).
        if self.kept.coupling_ring.is_none() && self.linear.is_prepared() {
            self.kept.coupling_ring = Some(self.coupling_ring());
        }
        self.check_stop(inc)?;
        let Solver {
            parts,
            interfaces,
            dofs,
            f_ext,
            linear,
            kept,
            history,
            proportional,
            coupling_dofs,
            timings,
            guess,
            ..
        } = self;
        let ring = kept.coupling_ring.as_ref();
        let read = ring.map_or(&[][..], |r| &r.eqs[..]);
        let history = (!*proportional).then_some(history.as_slice());
        // One step of iterative refinement after a low-rank update: the
        // Woodbury correction of a stiff pair opening cancels large terms, and
        // on soft models loses digits a factorization keeps. They are lost in
        // the capacitance's solution, so the residual they leave is on the
        // coupling DOFs (`ContactSystem::solve_unrefined`): its correction
        // there restores them, and keeps elsewhere the round-off of the
        // factorization the update shares. The residual is read from the
        // unrefined solution around the coupling nodes, and takes the memory
        // of `x`.
        let mut residual = |x: &mut [f64]| {
            let t = Instant::now();
            let ring = ring.expect("built for a kept factor");
            for &d in &ring.dofs {
                let e = dofs.eq[d];
                if e != FIXED {
                    u[d] = x[e];
                }
            }
            let f_c = ring_force(ring, parts, interfaces, dofs, history, states, u);
            x.fill(0.0);
            for &d in coupling_dofs.iter() {
                let e = dofs.eq[d];
                if e != FIXED {
                    x[e] = lambda * f_ext[d] - f_c[d];
                }
            }
            drop(f_c);
            timings.contact_update += t.elapsed().as_secs_f64();
        };
        let mut request = Request::new(states).refined(read, &mut residual);
        if guess.len() == x.len() {
            request = request.guess(guess);
        }
        let outcome = linear.solve_pattern(request, x);
        let outcome = outcome.map_err(|f| self.linear_error(f, inc))?;
        self.record(&outcome);
        self.keep_guess(x);
        Ok(outcome.method)
    }

    /// Keeps the solution `x` (free equations) as the next solve's initial
    /// guess, for a back end that starts from one.
    fn keep_guess(&mut self, x: &[f64]) {
        if self.linear.starts_from_guess() {
            self.guess.clear();
            self.guess.extend_from_slice(x);
        }
    }

    /// The prescribed displacements at load factor `lambda` (all DOFs, zero at the
    /// free ones) into `u` and the right-hand side of the free equations into
    /// `rhs` (both overwritten, their memory reused): the loads less the internal
    /// force of the prescribed values, which carries the pairs' constant terms
    /// (initial gaps, slip history, slip forces, multipliers). Returns whether
    /// the right-hand side depends on `states` (through that force): not with
    /// proportional loads and nothing prescribed moving, where it is λ f.
    pub(super) fn right_hand_side_into(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        u: &mut Vec<f64>,
        rhs: &mut Vec<f64>,
    ) -> bool {
        let t = Instant::now();
        let prescribed = self.path.prescribed.as_deref().unwrap_or(&self.dofs.prescribed);
        u.clear();
        u.extend(prescribed.iter().map(|v| lambda * v));
        let u = &*u;
        let moved = u.iter().any(|&v| v != 0.0);
        let has_prescribed = moved || !self.proportional;
        let f_p = if moved {
            self.internal_force(states, u)
        } else if has_prescribed {
            // No prescribed motion: the parts' forces vanish, only the pairs'
            // constant terms remain.
            let history = (!self.proportional).then_some(self.history.as_slice());
            let pairs = assembly::CouplingElements::new(self.interfaces, Some(states), self.dofs)
                .with_history(history);
            assembly::internal_force_of(&[&pairs], u)
        } else {
            Vec::new()
        };
        rhs.clear();
        rhs.resize(self.dofs.n_eq, 0.0);
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                rhs[e] = lambda * self.f_ext[d] - if has_prescribed { f_p[d] } else { 0.0 };
            }
        }
        self.timings.assembly += t.elapsed().as_secs_f64();
        has_prescribed
    }

    /// A trial solution of `states` for the law check of an active-set iteration
    /// (seed laws only): the displacements at the coupling elements' DOFs, from a
    /// solve on the elimination-tree paths of their equations
    /// (a back end's restricted solve; a complete one where it has none, then
    /// every DOF is given); every other free DOF is NaN. No
    /// internal force, residual or refinement: a pattern the trial finds
    /// consistent is solved in full before it is accepted.
    pub fn solve_interface(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Option<Method>)> {
        self.prepare_trial(states, inc)?;
        let Spare { mut u, mut x, trial } = std::mem::take(&mut self.kept.spare);
        // The last trial's vectors serve as they are when that trial was of this
        // increment and load factor, its right-hand side independent of the
        // states, and its displacements given back: the solve changed the
        // right-hand side at the coupling equations only (restored here), and
        // the displacements are NaN at every free DOF but the coupling ones.
        // Otherwise both are built anew (O(unknowns) each).
        let again = trial
            .filter(|t| t.inc == inc && t.lambda == lambda && u.len() == self.dofs.eq.len());
        let reused = again.is_some();
        // The right-hand side at the coupling equations, when it does not
        // depend on the states (kept for the next trial).
        let rhs: Option<Vec<f64>> = match again {
            Some(t) => {
                for (e, &v) in self.coupling_equations().zip(&t.rhs) {
                    x[e] = v;
                }
                Some(t.rhs)
            }
            None => (!self.right_hand_side_into(lambda, states, &mut u, &mut x))
                .then(|| self.coupling_equations().map(|e| x[e]).collect()),
        };
        let mut request = Request::new(states).interface_only();
        if self.guess.len() == x.len() {
            request = request.guess(&self.guess);
        }
        let outcome = self.linear.solve_pattern(request, &mut x);
        let outcome = outcome.map_err(|f| self.linear_error(f, inc))?;
        self.record(&outcome);
        let (method, complete) = (outcome.method, outcome.complete);
        if complete {
            self.keep_guess(&x);
        }
        self.trial_displacements(&x, &mut u, complete, reused);
        self.kept.spare.x = x;
        self.kept.spare.trial = rhs
            .filter(|_| !complete)
            .map(|rhs| TrialRhs { inc, lambda, rhs });
        // Only the values solved for can be infinite (the prescribed ones are
        // finite multiples of finite input).
        let infinite = if complete {
            u.iter().any(|v| v.is_infinite())
        } else {
            self.coupling_dofs.iter().any(|&d| u[d].is_infinite())
        };
        if infinite {
            return Err(self.not_finite(inc));
        }
        Ok((u, Some(method)))
    }

    /// Before a trial of `states`: the stop flag, the support check, the
    /// coupling ring found, the kept solution's values dropped.
    fn prepare_trial(&mut self, states: &[Vec<PairState>], inc: usize) -> Result<()> {
        self.check_stop(inc)?;
        let t = Instant::now();
        self.supports.check(self.parts, self.interfaces, states)?;
        if self.kept.coupling_ring.is_none() {
            // What the complete solve accepting a trial's pattern (an update,
            // to be refined) reads: found with the first trial rather than
            // inside that solve.
            self.kept.coupling_ring = Some(self.coupling_ring());
        }
        self.timings.contact_update += t.elapsed().as_secs_f64();
        if let Some(s) = &mut self.kept.last {
            // A trial moves on from the kept solution's pattern.
            s.values = None;
        }
        Ok(())
    }

    /// A trial's displacements `u` from its solution `x` (free equations): all
    /// of them from a `complete` solve, otherwise those at the coupling DOFs,
    /// NaN at the other free DOFs (already, when the vectors are `reused`).
    fn trial_displacements(&self, x: &[f64], u: &mut [f64], complete: bool, reused: bool) {
    if complete {
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                u[d] = x[e];
            }
        }
    } else {
        if !reused {
            for (d, &e) in self.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    u[d] = f64::NAN;
                }
            }
        }
        for &d in &self.coupling_dofs {
            let e = self.dofs.eq[d];
            if e != FIXED {
                u[d] = x[e];
            }
        }
    }
    }

    /// Gives the displacements `u` of a trial ([`Solver::solve_interface`]) back
    /// once read: their memory, and with the same right-hand side their
    /// contents (NaN off the coupling DOFs), serve the next trial.
    pub fn return_trial(&mut self, u: Vec<f64>) {
        self.kept.spare.u = u;
    }

    /// The free equations of the coupling DOFs (in their order).
    fn coupling_equations(&self) -> impl Iterator<Item = usize> + '_ {
        self.coupling_dofs
            .iter()
            .map(|&d| self.dofs.eq[d])
            .filter(|&e| e != FIXED)
    }

    pub(super) fn not_finite(&self, inc: usize) -> Error {
        Error::Overflow {
            path: None,
            line: None,
            key: String::new(),
            message: format!(
                "increment {inc}: the solution is not finite (a load, a prescribed value or a stiffness is too large or too small for double precision; rescale the units)"
            ),
        }
    }

    /// The part elements around the coupling nodes and the DOFs and equations
    /// of their nodes.
    fn coupling_ring(&self) -> CouplingRing {
        let part_elements = assembly::PartElements::new(self.parts, self.dofs);
        let mut at_coupling = vec![false; self.dofs.n_nodes()];
        for &d in &self.coupling_dofs {
            at_coupling[d / D::N] = true;
        }
        let elements = part_elements.touching(|n| at_coupling[n]);
        let mut dofs = self.coupling_dofs.clone();
        for &e in &elements {
            part_elements.nodes(e, &mut |nodes| {
                for &n in nodes {
                    dofs.extend((0..D::N).map(|c| D::dof(n, c)));
                }
            });
        }
        dofs.sort_unstable();
        dofs.dedup();
        let mut eqs: Vec<usize> =
            dofs.iter().map(|&d| self.dofs.eq[d]).filter(|&e| e != FIXED).collect();
        eqs.sort_unstable();
        CouplingRing {
            elements,
            dofs,
            eqs,
        }
    }

    /// The internal force of all DOFs for `u` with the pairs in `states` and their
    /// current histories (none for the seed's laws).
    fn internal_force(&self, states: &[Vec<PairState>], u: &[f64]) -> Vec<f64> {
        let history = (!self.proportional).then_some(self.history.as_slice());
        assembly::internal_force_with(self.parts, self.interfaces, states, history, self.dofs, u)
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn finish(
        &mut self,
        index: usize,
        lambda: f64,
        history: Vec<Iteration>,
        u: Vec<f64>,
        f_int: Vec<f64>,
        states: PairStates,
        check: LawCheck,
        settled: bool,
    ) -> IncrementResult<D> {
        // The increment is accepted: its right-hand side is not solved again.
        self.linear.forget_right_hand_side();
        let f_ext: Vec<f64> = self.f_ext.iter().map(|f| lambda * f).collect();
        let balance_scale = self.balance_scale(check.load_scale, check.pair_force, &u);
        let residual = self.residual(lambda, &f_int, balance_scale);
        // Σ reactions + Σ loads = Σ over fixed DOFs of (F_int − F_ext) + Σ F_ext.
        let mut total = <D as Dim>::Vector::default();
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            total.as_mut()[d % D::N] += if e == FIXED { f_int[d] } else { f_ext[d] };
        }
        // Axisymmetric forces are totals over the ring: their radial sums
        // balance through the hoop stresses, so statics checks z alone.
        if self.parts.iter().any(|p| p.material.is_axisymmetric()) {
            total.as_mut()[0] = 0.0;
        }
        let balance = D::length(total.as_ref()) / balance_scale.max(f64::MIN_POSITIVE);
        // With the proportional shortcuts the final solve either is the last
        // solution (a method) or scales it (no method); see `solve_once`.
        let multiple_of = match (&self.kept.last, history.last()) {
            (Some(s), Some(it)) if self.proportional => Some(MultipleOf {
                solution: s.number,
                factor: if it.method.is_some() { 1.0 } else { lambda / s.lambda },
            }),
            _ => None,
        };
        let settled = if settled {
            check
                .violations
                .iter()
                .map(|v| (v.interface, v.pair))
                .collect()
        } else {
            Vec::new()
        };
        IncrementResult {
            index,
            lambda,
            step: 0,
            time: lambda,
            iterations: history.len(),
            history,
            u,
            states,
            settled,
            violations: check.violations,
            load_scale: check.load_scale,
            balance_scale,
            f_int,
            f_ext,
            residual,
            balance,
            pair_history: Vec::new(),
            fixed_point_iterations: 0,
            augmented_error: 0.0,
            multiple_of,
            friction_continuation: false,
        }
    }

    /// With proportional loads, keeps the values of the last complete solve for
    /// later increments to scale ([`Solved::values`]) when `result`, accepted at
    /// load factor `lambda`, is that solve's answer itself (its states, its load
    /// factor, a multiple 1 of it): copied once the increment is accepted, so
    /// the copies are not made beside the factor and the solve's vectors.
    pub(super) fn keep_for_scaling(&mut self, result: &IncrementResult<D>, lambda: f64) {
        let Some(s) = &mut self.kept.last else {
            return;
        };
        let its_answer = result
            .multiple_of
            .as_ref()
            .is_some_and(|m| m.solution == s.number && m.factor == 1.0);
        if self.proportional
            && s.values.is_none()
            && its_answer
            && s.lambda == lambda
            && s.states == result.states
        {
            s.values = Some((result.u.clone(), result.f_int.clone()));
        }
    }
}

/// The internal force at the coupling elements' DOFs for `u` (read at the
/// [`CouplingRing`]'s DOFs only) with the pairs in `states` and their
/// `history` (none for the seed's laws), from the coupling elements and the
/// part elements around their nodes (the other DOFs hold partial sums): what a
/// refinement on the coupling equations reads, for a few elements' work.
fn ring_force<D: Dim>(
    ring: &CouplingRing,
    parts: &[Part],
    interfaces: &[Interface<D>],
    dofs: &DofMap<D>,
    history: Option<&[Vec<PairHistory<D>>]>,
    states: &[Vec<PairState>],
    u: &[f64],
) -> Vec<f64> {
    let part_elements = assembly::PartElements::new(parts, dofs);
    let around = assembly::SomeElements::new(&part_elements, &ring.elements);
    let pairs =
        assembly::CouplingElements::new(interfaces, Some(states), dofs).with_history(history);
    assembly::internal_force_of(&[&around, &pairs], u)
}
