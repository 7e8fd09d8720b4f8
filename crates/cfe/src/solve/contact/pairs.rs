//! The law on every pair, as the contact scheme reads it: the sweep that
//! checks a solution and gives each pair its next state ([`LawCheck`]), the
//! law's parameters and tolerances as the search reads them, and the
//! pair-history rules (a pair touching down, the plastic slip of the
//! increment's start restored, the history committed at an increment's end).

use super::increment::{IncrementResult, PairViolation};
use super::solver::Solver;
use crate::coupling::{
    self, CheckTolerance, LawParams, PairSet, PairState, PairStates, ViolationKind, history,
};
use crate::domain::FrictionSolve;
use crate::fem::ElementFamily;

/// The law checked on one solution: the state the law gives each pair next and
/// every pair that breaks it.
pub(super) struct LawCheck {
    pub(super) next: PairStates,
    pub(super) violations: Vec<PairViolation>,
    pub(super) load_scale: f64,
    /// The largest force ‖(f_n, f_s)‖ of a pair of a law other than `rigid`
    /// (for the balance scale).
    pub(super) pair_force: f64,
    /// Per interface, its slipping Coulomb pair nearest its cone (the least
    /// trial force over μ |f_n|), if it has one: where a stick zone moves to
    /// ([`move_stick_point`]).
    pub(super) nearest_slip: Vec<Option<usize>>,
    /// Per interface, whether its closed pairs press together (Σ f_n < 0).
    pub(super) pressed: Vec<bool>,
}

impl LawCheck {
    /// How bad the solution is, for choosing among the patterns of a cycle: any
    /// penetration first, then the largest violation as a force.
    pub(super) fn score(&self) -> (bool, f64) {
        let penetrates = self
            .violations
            .iter()
            .any(|v| v.kind == ViolationKind::Penetration);
        let worst = self.violations.iter().map(|v| v.force).fold(0.0, f64::max);
        (penetrates, worst)
    }
}

impl<D: ElementFamily> Solver<'_, D> {
    /// The law parameters of interface `i` as the search reads them: its
    /// friction coefficient times [`Solver::friction_factor`].
    pub(super) fn law_params(&self, i: usize) -> LawParams {
        let mut p = self.pairs().law(i);
        p.friction *= self.friction_factor;
        p
    }

    /// The law parameters of every interface as the search reads them
    /// ([`Solver::law_params`]).
    pub(super) fn laws(&self) -> Vec<LawParams> {
        (0..self.pairs().interface_count())
            .map(|i| self.law_params(i))
            .collect()
    }

    /// Checks the law on every pair of the solution `u` of `states`: the state the
    /// law gives each pair next, and every violation with its amount.
    pub(super) fn check_law(
        &self,
        states: &[Vec<PairState>],
        u: &[f64],
        f_int: &[f64],
        lambda: f64,
    ) -> LawCheck {
        self.check_law_scaled(states, u, self.load_scale(lambda, f_int, u))
    }

    /// [`Solver::check_law`] with a given load scale (reads `u` at the coupling
    /// elements' DOFs only).
    pub(super) fn check_law_scaled(&self, states: &[Vec<PairState>], u: &[f64], load_scale: f64) -> LawCheck {
        let laws = self.laws();
        let history = (!self.proportional).then_some(self.history.as_slice());
        let tol = CheckTolerance {
            force: self.settings.force_tolerance * load_scale,
            gap: self.settings.gap_tolerance,
        };
        let mut v = coupling::check_law(&self.pairs(), &laws, states, history, u, tol);
        if self.friction_solve == FrictionSolve::Newton {
            // The semi-smooth Newton updates the normal and the tangential
            // law together: every closed pair in tension opens (no friction
            // first; each pattern is solved exactly, so a tension is the
            // pattern's, not a slip force's lag).
            // A slipping pair off the cone whose state the law keeps (its
            // slip reversed by the exact solve: the trial force turned against
            // the slip force beyond the cone) sticks next: the reversal passes
            // through the cone, and a pair that truly slides the other way
            // leaves it again along its new trial force. Two opposite slips,
            // each reversing the other, are the stick between them.
            for &(i, k, ref lv) in &v.violations {
                if lv.kind == ViolationKind::Tension && states[i][k].is_closed() {
                    v.next[i][k] = PairState::Open;
                } else if lv.kind == ViolationKind::Slip
                    && states[i][k] == PairState::Slip
                    && v.next[i][k] == PairState::Slip
                {
                    v.next[i][k] = PairState::Bonded;
                }
            }
        }
        LawCheck {
            next: v.next,
            violations: v
                .violations
                .into_iter()
                .map(|(interface, pair, v)| PairViolation {
                    interface,
                    pair,
                    kind: v.kind,
                    amount: v.amount,
                    force: v.force,
                })
                .collect(),
            load_scale,
            pair_force: v.pair_force,
            nearest_slip: v.nearest_slip,
            pressed: v.pressed,
        }
    }

    /// Pairs of a Coulomb interface that close (open in `states`, bonded in `next`)
    /// touch down where they are: their plastic slip becomes their tangential jump
    /// in the solution `u`, so they close without tangential force. For a pair
    /// that was closed where the increment started this is a step of the search
    /// only: a pattern is accepted on its plastic slip of the increment's start
    /// ([`Solver::restore_closed_slips`]).
    pub(super) fn touch_down(&mut self, states: &[Vec<PairState>], next: &[Vec<PairState>], u: &[f64]) {
        if self.proportional {
            return;
        }
        history::touch_down(&self.pairs(), states, next, u, &mut self.history);
    }

    /// Gives every pair closed both where the increment started and in `states`
    /// its plastic slip of the increment's start back (a touch-down of the
    /// search, [`Solver::touch_down`], moved it: the pair was opened by a pattern
    /// tried, not by the path). Its stick force and its trial force are then
    /// measured from where it stuck. Returns whether any changed.
    pub(super) fn restore_closed_slips(&mut self, states: &[Vec<PairState>]) -> bool {
        if self.proportional {
            return false;
        }
        history::restore_closed_slips(
            &self.pairs(),
            &self.closed_at_start,
            &self.committed,
            states,
            &mut self.history,
        )
    }

    /// Ends an increment's history: a slipping Coulomb pair keeps its plastic slip
    /// `s_p = [[u_s]] − f_s / c_s`, an open pair's slip follows its jump (it closes
    /// again unstressed tangentially) and loses its multipliers. Copies the history
    /// into `result`.
    pub(super) fn commit_history(&mut self, result: &mut IncrementResult<D>) {
        result.fixed_point_iterations = self.fixed_point;
        result.augmented_error = self.augmented_error;
        if self.proportional {
            result.pair_history = self.history.clone();
            return;
        }
        history::commit(
            &self.pairs(),
            &result.states,
            &result.u,
            &mut self.history,
        );
        result.pair_history = self.history.clone();
        self.committed.clone_from(&self.history);
        for (c, st) in self.closed_at_start.iter_mut().zip(&result.states) {
            for (c, s) in c.iter_mut().zip(st) {
                *c = s.is_closed();
            }
        }
    }
}
