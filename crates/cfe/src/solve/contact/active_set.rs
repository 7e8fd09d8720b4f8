//! The active-set search of one increment: from a starting pattern, solve,
//! let the law update every pair, repeat until the law holds; on a cycle go on
//! cautiously one pair at a time ([`flip_worst`]); a face that lost its last
//! stick pair moves its stick point ([`move_stick_point`]); with nothing left,
//! settle on the least-violating pattern solved ([`least_violating`]). With
//! Coulomb interfaces an increment the search does not answer is searched
//! again from the pattern a continuation in μ leads to. The search's record
//! of what it solved is a [`Search`].

use super::fixed_point::FixedPointScale;
use super::increment::{IncrementResult, Iteration, PairViolation, count_changes};
use super::pairs::LawCheck;
use super::solver::Solver;
use crate::coupling::{PairState, PairStates, ViolationKind};
use crate::domain::FrictionSolve;
use crate::error::{Error, Result};
use crate::fem::ElementFamily;
use crate::solve::system::Method;
use std::collections::HashSet;
use std::time::Instant;

/// The factors on the friction coefficients of a continuation in μ
/// (`Solver::friction_continuation`), largest first: at 16 μ the closed
/// pairs of an ordinary model all stick, and each step after halves the excess
/// or less, down to 1.1 μ before μ itself.
pub const CONTINUATION: [f64; 7] = [16.0, 8.0, 4.0, 2.0, 1.5, 1.25, 1.1];

/// A pattern solved during an increment's iteration, and how well it satisfies the law.
struct Visit {
    pub(super) states: PairStates,
    pub(super) score: (bool, f64),
    /// Whether its pairs' terms (slip forces, multipliers) reached their fixed
    /// point: a pattern whose terms did not is no solution, whatever its check
    /// says (its displacements drift with the last step), and is never settled on.
    pub(super) converged: bool,
}

/// The record of one active-set search: the patterns it solved and how it
/// goes on from them.
#[derive(Default)]
struct Search {
    /// Every pattern solved.
    seen: HashSet<PairStates>,
    /// Every pattern solved, in order, with its score.
    visits: Vec<Visit>,
    /// Whether the search goes on one pair at a time (after a cycle).
    cautious: bool,
    /// The last pattern whose slip forces found their fixed point, and its
    /// slipping pairs nearest their cones.
    last_fixed: Option<(PairStates, Vec<Option<usize>>)>,
    /// The load scale of the increment's last complete solution: the law checks
    /// of trial solutions (seed laws) use it.
    scale: Option<f64>,
}

impl Search {
    /// Records the pattern `states` solved, its `check` and whether its
    /// terms reached their fixed point.
    fn record(&mut self, states: &PairStates, check: &LawCheck, converged: bool) {
        self.seen.insert(states.clone());
        self.visits.push(Visit {
            states: states.clone(),
            score: check.score(),
            converged,
        });
    }
}

/// A pattern's solution as the search checks it: displacements, internal force
/// (`None` for a trial, restricted to the coupling DOFs), how it was solved and
/// the law's verdict.
type Checked = (Vec<f64>, Option<Vec<f64>>, Option<Method>, LawCheck);

impl<D: ElementFamily> Solver<'_, D> {
    /// One active-set increment from the pattern `start`. With Coulomb
    /// interfaces (path-dependent, so every increment is searched), an increment
    /// whose search from `start` finds no state, only settles, or reaches a
    /// pattern that leaves a part free (`Unsupported`: a pattern the search
    /// flips to, not the model's answer) is searched again from the pattern a
    /// continuation in the friction coefficient leads to
    /// ([`Solver::friction_continuation`]); its answer is taken if it obeys the
    /// law (or, when the first search found nothing, if there is one). Otherwise
    /// the first search's answer or error stands.
    pub(super) fn active_set_or_continuation(
        &mut self,
        inc: usize,
        lambda: f64,
        start: &PairStates,
    ) -> Result<IncrementResult<D>> {
        let coulomb = !self.proportional && self.coulomb.contains(&true);
        if !coulomb || self.friction_solve != FrictionSolve::Newton {
            return self.search_or_continuation(inc, lambda, start);
        }
        // The semi-smooth Newton's answer; an increment it does not answer
        // (it settles, or finds no state) is searched again with the fixed
        // point on the slip forces and its rescues, whose answer is taken if
        // it obeys the law.
        let newton = self.search_or_continuation(inc, lambda, start);
        let first = match newton {
            Ok(r) if r.settled.is_empty() => return Ok(r),
            Ok(r) => Ok((r, self.history.clone(), self.augmented_error)),
            Err(e @ (Error::NoConvergence(_) | Error::Unsupported { .. })) => {
                Err((e, std::mem::take(&mut self.failed_search)))
            }
            Err(e) => return Err(e),
        };
        self.friction_solve = FrictionSolve::FixedPoint;
        let again = self.search_or_continuation(inc, lambda, start);
        self.friction_solve = FrictionSolve::Newton;
        let solves = match &first {
            Ok((r, ..)) => r.history.clone(),
            Err((_, solves)) => solves.clone(),
        };
        match (again, first) {
            (Ok(mut r), _) if r.settled.is_empty() => {
                r.history.splice(0..0, solves);
                r.iterations = r.history.len();
                Ok(r)
            }
            (Err(e @ Error::Interrupted { .. }), _) => Err(e),
            (_, Ok((r, history, error))) => {
                (self.history, self.augmented_error) = (history, error);
                Ok(r)
            }
            (_, Err((e, _))) => Err(e),
        }
    }

    /// [`Solver::active_set_or_continuation`] with the current friction solve.
    fn search_or_continuation(
        &mut self,
        inc: usize,
        lambda: f64,
        start: &PairStates,
    ) -> Result<IncrementResult<D>> {
        let direct = self.active_set_increment(inc, lambda, start.clone());
        let coulomb = !self.proportional && self.coulomb.contains(&true);
        if !coulomb {
            return direct;
        }
        // What the first search leaves: a settled answer (with the histories
        // its pairs end on), or its error.
        let first = match direct {
            Ok(r) if r.settled.is_empty() => return Ok(r),
            Ok(r) => Ok((r, self.history.clone(), self.augmented_error)),
            Err(e @ (Error::NoConvergence(_) | Error::Unsupported { .. })) => {
                Err((e, std::mem::take(&mut self.failed_search)))
            }
            Err(e) => return Err(e),
        };
        let Some(mut r) = self.friction_continuation(inc, lambda, start)? else {
            return match first {
                Ok((r, history, error)) => {
                    (self.history, self.augmented_error) = (history, error);
                    Ok(r)
                }
                Err((e, _)) => Err(e),
            };
        };
        match first {
            Ok((settled, history, error)) if !r.settled.is_empty() => {
                (self.history, self.augmented_error) = (history, error);
                Ok(settled)
            }
            first => {
                // The solves of the first search count too, whether it settled
                // or ended in an error.
                let solves = match first {
                    Ok((settled, ..)) => settled.history,
                    Err((_, solves)) => solves,
                };
                r.history.splice(0..0, solves);
                r.iterations = r.history.len();
                r.friction_continuation = true;
                Ok(r)
            }
        }
    }

    /// A continuation in the friction coefficient for increment `inc` at load
    /// factor `lambda`: the increment searched with every μ scaled by each of
    /// [`CONTINUATION`] in turn, each search from the pattern the previous one
    /// ended on (a search that finds nothing passes its start on), and at last
    /// with μ itself. Every search starts from the increment's committed pair
    /// histories: only the starting pattern passes from one to the next, so the
    /// answer is the increment's own, checked against its own law. With μ large
    /// every closed pair sticks (the search is the contact law's); each smaller
    /// μ then frees the pairs a little beyond their cones, a few flips from the
    /// last pattern. Returns the last search's answer with every search's solves
    /// in its history, or `None` when it found no state. A search that fails
    /// otherwise (a pattern it reaches leaves a part free, say) ends the
    /// continuation with `None` too: its error belongs to a scaled μ or to a
    /// start of the continuation's, not to the model, whose own first search
    /// gives the answer then. Only a stop request ([`Error::Interrupted`]) is
    /// an error of the continuation.
    pub(super) fn friction_continuation(
        &mut self,
        inc: usize,
        lambda: f64,
        start: &PairStates,
    ) -> Result<Option<IncrementResult<D>>> {
        // `Ok(Err(()))`: the stage failed otherwise than by finding nothing.
        let stage = |this: &mut Self, factor: f64, start: &PairStates| {
            this.check_stop(inc)?;
            this.friction_factor = factor;
            let r = this.active_set_increment(inc, lambda, start.clone());
            this.friction_factor = 1.0;
            match r {
                Ok(r) => Ok(Ok(Some(r))),
                Err(Error::NoConvergence(_)) => Ok(Ok(None)),
                Err(e @ Error::Interrupted { .. }) => Err(e),
                Err(_) => Ok(Err(())),
            }
        };
        let mut start = start.clone();
        let mut history = Vec::new();
        for &factor in &CONTINUATION {
            let Ok(found) = stage(self, factor, &start)? else {
                return Ok(None);
            };
            match found {
                Some(r) => {
                    history.extend(r.history);
                    start = r.states;
                }
                // A search that found nothing: its solves count too.
                None => history.append(&mut self.failed_search),
            }
        }
        let Ok(Some(mut r)) = stage(self, 1.0, &start)? else {
            return Ok(None);
        };
        history.append(&mut r.history);
        r.history = history;
        r.iterations = r.history.len();
        Ok(Some(r))
    }

    /// One increment of the active-set scheme from the pattern `start`. A
    /// search that ends in an error leaves its iterations in
    /// [`Solver::failed_search`].
    pub(super) fn active_set_increment(
        &mut self,
        inc: usize,
        lambda: f64,
        start: PairStates,
    ) -> Result<IncrementResult<D>> {
        let mut history = Vec::new();
        let result = self.active_set_search(inc, lambda, start, &mut history);
        self.failed_search = if result.is_err() { history } else { Vec::new() };
        result
    }

    /// [`Solver::active_set_increment`], its iterations recorded in `history`
    /// as they are made (an error leaves them there).
    pub(super) fn active_set_search(
        &mut self,
        inc: usize,
        lambda: f64,
        start: PairStates,
        history: &mut Vec<Iteration>,
    ) -> Result<IncrementResult<D>> {
        // An iteration that started this increment before (a warm start that
        // settled) left its touch-downs and fixed-point iterates in the history.
        if !self.proportional {
            self.history.clone_from(&self.committed);
        }
        // Proportional loads: the law is homogeneous in the load (forces, jumps and
        // both tolerances scale with λ), so a pattern the previous increment settled
        // on breaks the law by the same fraction at this load, and the iteration from
        // it would find the same cycle: keep it (its solution is the previous one
        // scaled, no solve). A consistent pattern needs no such rule: its first,
        // scaled solution already satisfies the law.
        if self.proportional && self.settled_pattern.as_ref() == Some(&start) {
            return self.keep_settled(inc, lambda, start, history);
        }
        let mut search = Search::default();
        let mut states = start;
        for _ in 0..self.settings.max_iterations {
            self.check_stop(inc)?;
            let t = Instant::now();
            let (u, f_int, method, check) = self.solve_and_check(inc, lambda, &states, &mut search)?;
            let was_trial = f_int.is_none();
            // Without a fixed point the pattern has no consistent pair terms: its
            // displacements are the last step's, and may have drifted without
            // bound (a part pushed along its faces harder than friction holds it
            // slides on under the slipping pairs' springs), inflating the load
            // scale its check is relative to. It is neither accepted nor settled on.
            let converged = self.proportional || self.fixed_point_converged;
            search.record(&states, &check, converged);
            if let (true, true, Some(f_int)) = (check.violations.is_empty(), converged, f_int) {
                history.push(Iteration {
                    method,
                    changed: 0,
                    seconds: t.elapsed().as_secs_f64(),
                });
                if self.restore_closed_slips(&states) {
                    // A pair closed where the increment started, opened by the
                    // iteration and closed again, touched down on a plastic slip
                    // of the iteration's: with its own back, the pattern is solved
                    // and checked again.
                    continue;
                }
                self.settled_pattern = None;
                let history = std::mem::take(history);
                return Ok(self.finish(inc, lambda, history, u, f_int, states, check, false));
            }
            let next = self.next_pattern(&states, check, converged, &mut search);
            history.push(Iteration {
                method,
                changed: count_changes(&next, &states),
                seconds: t.elapsed().as_secs_f64(),
            });
            if search.seen.contains(&next) {
                return self.settle(inc, lambda, &search.visits, history);
            }
            self.touch_down(&states, &next, &u);
            if was_trial {
                self.return_trial(u);
            }
            states = next;
        }
        if search.cautious {
            return self.settle(inc, lambda, &search.visits, history);
        }
        Err(self.unsettled(inc, lambda, &states))
    }

    /// Keeps the pattern `start` the previous increment settled on, with
    /// proportional loads (its solution is the previous one scaled, no solve).
    fn keep_settled(
        &mut self,
        inc: usize,
        lambda: f64,
        start: PairStates,
        history: &mut Vec<Iteration>,
    ) -> Result<IncrementResult<D>> {
        let t = Instant::now();
        let (u, f_int, method) = self.solve_states(lambda, &start, inc)?;
        let check = self.check_law(&start, &u, &f_int, lambda);
        history.push(Iteration {
            method,
            changed: 0,
            seconds: t.elapsed().as_secs_f64(),
        });
        let history = std::mem::take(history);
        Ok(self.finish(inc, lambda, history, u, f_int, start, check, true))
    }

    /// Solves the pattern `states` of a search and checks the law on it: a
    /// trial restricted to the coupling DOFs once the search has a load scale,
    /// and a complete solve when there is none yet or the trial finds a
    /// violation-free pattern (a pattern is accepted only on a complete
    /// solution, with its internal force, refinement and residual check).
    fn solve_and_check(
        &mut self,
        inc: usize,
        lambda: f64,
        states: &PairStates,
        search: &mut Search,
    ) -> Result<Checked> {
        let trial = match search.scale {
            Some(sc) => {
                let (mut u, method) = self.solve_interface(lambda, states, inc)?;
                if !self.proportional {
                    self.fixed_point(states, inc, &mut u, FixedPointScale::Given(sc))?;
                }
                let check = self.check_law_scaled(states, &u, sc);
                (!check.violations.is_empty()).then_some((u, method, check))
            }
            _ => None,
        };
        Ok(match trial {
            Some((u, method, check)) => (u, None, method, check),
            None => {
                let (u, f_int, method) = self.solve_states(lambda, states, inc)?;
                let check = self.check_law(states, &u, &f_int, lambda);
                search.scale = Some(check.load_scale);
                (u, Some(f_int), method, check)
            }
        })
    }

    /// The pattern the search goes to from `states`, given the law's verdict
    /// `check` on it and whether its terms reached their fixed point
    /// (`converged`): the law's next states, with a face's stick point moved
    /// or the unsettled slipping pairs stuck; once the law leads back to a
    /// pattern solved (a cycle), one pair flipped at a time.
    fn next_pattern(
        &self,
        states: &PairStates,
        mut check: LawCheck,
        converged: bool,
        search: &mut Search,
    ) -> PairStates {
        // A face that lost its last stick pair in a pattern without a fixed
        // point moves its stick point (rather than sticking every slipping
        // pair), if that pattern is new and holds every part.
        let moved = match (&search.last_fixed, converged) {
            (Some((held, nearest)), false) => {
                move_stick_point(&self.coulomb, states, held, nearest, &check.pressed)
                    .filter(|p| {
                        !search.seen.contains(p)
                            && self.supports.check(self.parts, self.interfaces, p).is_ok()
                    })
            }
            _ => None,
        };
        if converged {
            search.last_fixed = Some((states.clone(), check.nearest_slip.clone()));
        }
        if let Some(moved) = moved {
            check.next = moved;
        } else if !converged {
            stick_unsettled(&mut check, states);
        }
        // A pattern the cautious step may go to: not solved yet, and one that
        // holds every part (a flip that frees a part is no way forward).
        let wide = self.coulomb.contains(&true);
        let seen = &search.seen;
        let open = |p: &PairStates| {
            !seen.contains(p) && self.supports.check(self.parts, self.interfaces, p).is_ok()
        };
        let mut next = if search.cautious {
            flip_worst(states, &check, wide, open)
        } else {
            check.next.clone()
        };
        if !search.cautious && seen.contains(&next) {
            // The law leads back to a pattern already solved: a cycle. Go on one
            // pair at a time, from here.
            search.cautious = true;
            next = flip_worst(states, &check, wide, open);
        }
        next
    }

    /// Ends a cycling increment on the least-violating pattern it solved: one
    /// without penetration if any, then the smallest largest violation, then the
    /// earliest (the rule is deterministic). Its violating pairs are the settled ones.
    fn settle(
        &mut self,
        inc: usize,
        lambda: f64,
        visits: &[Visit],
        history: &mut Vec<Iteration>,
    ) -> Result<IncrementResult<D>> {
        let best = least_violating(visits);
        let Some(best) = best else {
            return Err(self.no_fixed_point(inc, lambda, visits));
        };
        let t = Instant::now();
        let states = best.states.clone();
        // Solved again from the terms the iteration left, or, should its fixed
        // point not be found from there (after patterns without one the terms
        // may have drifted far), once more from the increment's start.
        let mut solved = None;
        for from_start in [false, true] {
            if from_start {
                self.history.clone_from(&self.committed);
            }
            self.restore_closed_slips(&states);
            let solution = self.solve_states(lambda, &states, inc)?;
            if self.proportional || self.fixed_point_converged {
                solved = Some(solution);
                break;
            }
        }
        let Some((u, f_int, method)) = solved else {
            return Err(self.no_fixed_point(inc, lambda, visits));
        };
        let check = self.check_law(&states, &u, &f_int, lambda);
        history.push(Iteration {
            method,
            changed: 0,
            seconds: t.elapsed().as_secs_f64(),
        });
        self.settled_pattern = Some(states.clone());
        let history = std::mem::take(history);
        Ok(self.finish(inc, lambda, history, u, f_int, states, check, true))
    }

    /// The error of an increment whose pair terms found no fixed point in any of
    /// the patterns it `tried` (or not again in the one it settled on).
    fn no_fixed_point(&self, inc: usize, lambda: f64, tried: &[Visit]) -> Error {
        let fixed = tried.iter().filter(|v| v.converged).count();
        let found = if fixed == 0 {
            format!("found no fixed point in any of the {} contact-state pattern(s) tried", tried.len())
        } else {
            format!(
                "found a fixed point in only {fixed} of the {} contact-state patterns tried, none satisfying the law, and none when the least-violating of those was solved again",
                tried.len()
            )
        };
        let why = if self.friction_hold.judges_all() {
            // The inclined-plane check passed on every body friction holds.
            "the search found no state, though the loads are within what friction holds along the faces (every part friction holds passed the inclined-plane check before the increment): likely a state the active-set search does not reach on this model. Try another mesh (--refine) or other penalties (c_n, c_s)"
        } else {
            "no state holds: a part is pushed along its faces harder than friction holds it (a tangential load beyond μ × the normal load, nothing else holding the part along the face), or the search missed the state. Hold the part, raise the friction coefficient, or reduce the tangential load"
        };
        Error::NoConvergence(format!(
            "increment {inc} ({}): the slip forces {found}, so {why}",
            self.where_in_path(inc, lambda),
        ))
    }

    /// The error of an increment whose search ended at `states` after
    /// `max_iterations` without a pattern repeating.
    fn unsettled(&self, inc: usize, lambda: f64, states: &PairStates) -> Error {
    let open: usize = states
        .iter()
        .flatten()
        .filter(|&&s| s == PairState::Open)
        .count();
        Error::NoConvergence(format!(
        "increment {inc} ({}): the contact states did not settle within {} iterations ({open} pairs open at the last one, no pattern repeated). Raise [analysis] max_iterations or use more increments",
        self.where_in_path(inc, lambda),
        self.settings.max_iterations,
        ))
    }
}

/// The pattern a cycling increment settles on among the `visits` it solved
/// (only those whose terms reached their fixed point): one without
/// penetration if any, then the smallest largest violation, then the earliest
/// (the rule is deterministic). `None` when none converged.
fn least_violating(visits: &[Visit]) -> Option<&Visit> {
    visits
        .iter()
        .enumerate()
        .filter(|(_, v)| v.converged)
        .min_by(|(i, a), (j, b)| {
            a.score
                .0
                .cmp(&b.score.0)
                .then(a.score.1.total_cmp(&b.score.1))
                .then(i.cmp(j))
        })
        .map(|(_, v)| v)
}

/// Slipping pairs whose slip forces found no fixed point in the pattern
/// `states` (they pull the solution along without settling) stick in
/// `check.next`: those the check finds off the law, or, when it finds none
/// (its load scale grown with the drift), every slipping pair.
fn stick_unsettled(check: &mut LawCheck, states: &[Vec<PairState>]) {
    let off_law: Vec<(usize, usize)> = check
        .violations
        .iter()
        .filter(|v| v.kind == ViolationKind::Slip)
        .map(|v| (v.interface, v.pair))
        .collect();
    if check.violations.is_empty() {
        for (next, now) in check.next.iter_mut().zip(states) {
            for (n, &s) in next.iter_mut().zip(now) {
                if s == PairState::Slip {
                    *n = PairState::Bonded;
                }
            }
        }
    }
    for (i, k) in off_law {
        check.next[i][k] = PairState::Bonded;
    }
}

/// The pattern `states` (whose slip forces found no fixed point) with the
/// stick point moved: on each Coulomb interface (`coulomb[i]`) that has no
/// stick pair in `states` but had one in `held` (the last pattern with a fixed
/// point) and whose pairs press together (`pressed[i]`), `held`'s slipping pair
/// nearest its cone (`nearest[i]`) sticks. A part whose last stick pair went
/// beyond its cone slides off on the rest — their slip forces balance at any
/// position — so its stick zone moves to the pair next to reaching its own
/// cone, rather than every slipping pair sticking. An interface whose pairs
/// pull together is coming apart, not sliding (the law opens them). `None`
/// when no interface's stick point moves.
fn move_stick_point(
    coulomb: &[bool],
    states: &[Vec<PairState>],
    held: &[Vec<PairState>],
    nearest: &[Option<usize>],
    pressed: &[bool],
) -> Option<PairStates> {
    let sticks = |s: &[PairState]| s.contains(&PairState::Bonded);
    let mut moved = states.to_vec();
    let mut any = false;
    for i in 0..states.len() {
        if !coulomb[i] || sticks(&states[i]) || !sticks(&held[i]) || !pressed[i] {
            continue;
        }
        if let Some(k) = nearest[i].filter(|&k| states[i][k] == PairState::Slip) {
            moved[i][k] = PairState::Bonded;
            any = true;
        }
    }
    any.then_some(moved)
}

/// The cautious step: `states` with one pair flipped the way its violation asks
/// (a pulling pair opens, a penetrating one closes, a stick pair beyond its cone
/// slips, a slip pair inside it sticks; the first of equals).
///
/// With `wide` (friction: the all-at-once update's friction-first rule holds
/// pulling pairs closed while a stick pair exceeds its cone, so normal and
/// tangential flips interleave), the worst violating pair whose flip leads to a
/// pattern that is `open` to the iteration — not yet solved, and holding every
/// part — and `states` itself when no flip does. Without, the worst violating
/// pair's flip whatever it leads to (the seed's laws: where it leads back to a
/// solved pattern, the contact-states study found no consistent pattern near the
/// pairs that then settle; searching on costs iterations without changing that).
fn flip_worst(
    states: &[Vec<PairState>],
    check: &LawCheck,
    wide: bool,
    open: impl Fn(&PairStates) -> bool,
) -> PairStates {
    let mut order: Vec<&PairViolation> = check.violations.iter().collect();
    // Stable: equal violations keep their order.
    order.sort_by(|a, b| b.force.total_cmp(&a.force));
    let mut next = states.to_vec();
    for v in order {
        let (i, k) = (v.interface, v.pair);
        let now = next[i][k];
        let to = match v.kind {
            ViolationKind::Tension => PairState::Open,
            ViolationKind::Penetration | ViolationKind::Slip => PairState::Bonded,
            ViolationKind::Friction => PairState::Slip,
        };
        if to == now {
            continue;
        }
        next[i][k] = to;
        if !wide || open(&next) {
            return next;
        }
        next[i][k] = now;
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;
    use PairState::{Bonded, Open, Slip};

    fn violation(pair: usize, kind: ViolationKind, force: f64) -> PairViolation {
        PairViolation {
            interface: 0,
            pair,
            kind,
            amount: force,
            force,
        }
    }

    /// The cautious step flips the worst violating pair the way its violation
    /// asks, passing over flips that lead back to a solved pattern, and returns
    /// the pattern itself (the increment settles) when no flip is left; the
    /// all-at-once update's verdict (`next`, here holding a pulling pair closed as
    /// the friction-first rule does) does not restrict it.
    #[test]
    fn cautious_step_takes_the_worst_unsolved_flip() {
        let states = vec![vec![Bonded, Bonded, Slip, Open]];
        let check = LawCheck {
            next: states.clone(),
            violations: vec![
                violation(0, ViolationKind::Tension, 3.0),
                violation(1, ViolationKind::Friction, 5.0),
                violation(2, ViolationKind::Slip, 5.0),
                violation(3, ViolationKind::Penetration, 1.0),
            ],
            load_scale: 1.0,
            pair_force: 0.0,
            nearest_slip: vec![None],
            pressed: vec![true],
        };
        let mut seen = HashSet::new();
        seen.insert(states.clone());
        let flip = |i: usize, to: PairState| {
            let mut s = states.clone();
            s[0][i] = to;
            s
        };
        // In order: the first of the two worst (5.0), the stick pair beyond its
        // cone, slips; the slip pair inside its cone sticks; the pulling pair
        // opens, although `next` kept it bonded; the penetrating pair closes.
        for (pair, to) in [(1, Slip), (2, Bonded), (0, Open), (3, Bonded)] {
            let next = flip_worst(&states, &check, true, |p| !seen.contains(p));
            assert_eq!(next, flip(pair, to), "pair {pair}");
            seen.insert(next);
        }
        // Nothing unsolved is left: the pattern itself.
        assert_eq!(flip_worst(&states, &check, true, |p| !seen.contains(p)), states);
        // Without friction: the worst pair's flip, solved before or not.
        let next = flip_worst(&states, &check, false, |p| !seen.contains(p));
        assert_eq!(next, flip(1, Slip));
    }

    /// A face whose one stick pair slipped, every pair now slipping: the stick
    /// point moves to the slipping pair the held pattern had nearest its cone,
    /// the others keep their states. Not on a face that pulls, a face that
    /// still sticks somewhere, a face that had no stick pair to lose, or a
    /// face that is not Coulomb's.
    ///
    /// ```text
    ///   held:    slip  stick  slip  slip  open     nearest: pair 2
    ///   states:  slip  slip   slip  slip  open
    ///   moved:   slip  slip   stick slip  open
    /// ```
    #[test]
    fn the_stick_point_moves_to_the_slipping_pair_nearest_its_cone() {
        let held = vec![vec![Slip, Bonded, Slip, Slip, Open]];
        let states = vec![vec![Slip, Slip, Slip, Slip, Open]];
        let nearest = [Some(2)];
        let moved = move_stick_point(&[true], &states, &held, &nearest, &[true]);
        assert_eq!(moved, Some(vec![vec![Slip, Slip, Bonded, Slip, Open]]));
        // A face pulling together, a face still sticking, a face that had
        // no stick pair, a face not Coulomb's: nothing moves.
        assert_eq!(move_stick_point(&[true], &states, &held, &nearest, &[false]), None);
        let sticking = vec![vec![Slip, Slip, Slip, Bonded, Open]];
        assert_eq!(move_stick_point(&[true], &sticking, &held, &nearest, &[true]), None);
        assert_eq!(move_stick_point(&[true], &states, &states, &nearest, &[true]), None);
        assert_eq!(move_stick_point(&[false], &states, &held, &nearest, &[true]), None);
        // The pair nearest its cone in the held pattern opened since: none.
        let opened = vec![vec![Slip, Slip, Open, Slip, Open]];
        assert_eq!(move_stick_point(&[true], &opened, &held, &nearest, &[true]), None);
    }

    fn visit(state: PairState, penetrates: bool, worst: f64, converged: bool) -> Visit {
        Visit {
            states: vec![vec![state]],
            score: (penetrates, worst),
            converged,
        }
    }

    /// The settle rule: among the patterns whose terms reached their fixed
    /// point, one without penetration beats any with (whatever its size), then
    /// the smaller largest violation, then the earlier of equals (so the choice
    /// does not depend on anything but the order solved); a pattern without a
    /// fixed point is never chosen, and without any there is none.
    #[test]
    fn settling_takes_the_least_violating_converged_pattern() {
        let mut visits = vec![
            visit(Open, true, 0.1, true),
            visit(Bonded, false, 5.0, true),
            visit(Slip, false, 1.0, false),
            visit(Open, false, 5.0, true),
            visit(Slip, false, 7.0, true),
        ];
        let best = |v: &[Visit]| least_violating(v).map(|b| b.states[0][0]);
        assert_eq!(best(&visits), Some(Bonded));
        // The two equals swapped: again the earlier.
        visits.swap(1, 3);
        assert_eq!(best(&visits), Some(Open));
        // Only the penetrating one and the unconverged one: the penetrating.
        assert_eq!(best(&visits[..3]), Some(Open));
        assert_eq!(best(&visits[2..3]), None);
    }

    /// In a pattern whose slip forces found no fixed point, the slipping pairs
    /// the check finds off the law stick, the rest keep the law's next state;
    /// when the check finds no violation, every slipping pair sticks.
    #[test]
    fn unsettled_slipping_pairs_stick() {
        let states = vec![vec![Slip, Slip, Bonded, Open]];
        let mut check = LawCheck {
            next: vec![vec![Slip, Slip, Slip, Open]],
            violations: vec![
                violation(1, ViolationKind::Slip, 2.0),
                violation(2, ViolationKind::Friction, 1.0),
            ],
            load_scale: 1.0,
            pair_force: 0.0,
            nearest_slip: vec![None],
            pressed: vec![true],
        };
        stick_unsettled(&mut check, &states);
        assert_eq!(check.next, vec![vec![Slip, Bonded, Slip, Open]]);
        check.violations.clear();
        check.next = states.clone();
        stick_unsettled(&mut check, &states);
        assert_eq!(check.next, vec![vec![Bonded, Bonded, Bonded, Open]]);
    }
}
