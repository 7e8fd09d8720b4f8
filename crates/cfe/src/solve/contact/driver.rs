//! The driver of the contact scheme, its top: [`Solver::run`] takes the
//! increments along the load path, each found by the active-set search (or,
//! with `implex`, one solve in the states the previous increment left), commits
//! the pairs' histories, labels the increment with its step, checks its
//! precision and its violations, and hands it to the caller.

use super::increment::{IncrementResult, Iteration, PairViolation, count_changes};
use super::solver::Solver;
use crate::coupling::{Interface, PairSet, PairStates, ViolationKind};
use crate::domain::{Part, Scheme};
use crate::error::{Error, Result};
use crate::fem::ElementFamily;
use std::time::Instant;

impl<D: ElementFamily> Solver<'_, D> {
    /// Runs all increments; `on_increment` receives each converged increment (to
    /// write it out) before the next starts. Returns the last increment. Stops with
    /// [`Error::LawViolation`] after handing over an increment whose largest
    /// violation exceeds `max_violation` × the load scale.
    pub fn run(
        &mut self,
        mut on_increment: impl FnMut(&IncrementResult<D>) -> Result<()>,
    ) -> Result<IncrementResult<D>> {
        let factors = self.path.factors.clone().unwrap_or_else(|| {
            let n = self.settings.increments;
            (1..=n).map(|k| k as f64 / n as f64).collect()
        });
        let n_inc = factors.len();
        // With proportional loads the active set's first factorization answers
        // every increment (the factor is freed after the first): the stiffness's
        // pattern is not held beside the factor for another one.
        let keep = !(self.settings.scheme == Scheme::ActiveSet && self.proportional);
        self.linear.keep_pattern(keep);
        let all_bonded = self.all_bonded();
        let warm = match self.settings.scheme {
            Scheme::ActiveSet => self.initial.take(),
            Scheme::Implex => None,
        };
        let mut states = warm.clone().unwrap_or_else(|| all_bonded.clone());
        let mut last = None;
        for inc in 1..=n_inc {
            let lambda = factors[inc - 1];
            self.start_increment(inc, lambda)?;
            let mut result = match self.settings.scheme {
                Scheme::ActiveSet => {
                    let r = self.active_set_step(inc, lambda, &states, warm.is_some(), &all_bonded)?;
                    states = r.states.clone();
                    r
                }
                Scheme::Implex => self.implex_increment(inc, lambda, &mut states)?,
            };
            self.end_increment(inc, n_inc, lambda, &mut result)?;
            on_increment(&result)?;
            if !result.violations.is_empty() {
                self.check_no_rest(inc, lambda, &result)?;
            }
            // implex lags its states by design: only its final answer must obey the law.
            if self.settings.scheme == Scheme::ActiveSet || inc == n_inc {
                self.check_violation_limit(&result)?;
            }
            last = Some(result);
        }
        let stats = self.linear.statistics();
        let t = &mut self.timings;
        t.factorization = stats.prepare_seconds;
        t.solve = stats.solve_seconds;
        // A pattern built again for a later factorization is setup work too.
        t.pattern_and_symbolic += self.linear.take_pattern_seconds();
        Ok(last.expect("at least one increment"))
    }

    /// Starts increment `inc` at load factor `lambda`: the stop flag read, the
    /// fixed-point count reset, the load steps combined, and a part friction
    /// cannot hold reported before the patterns are searched for its state of
    /// rest.
    fn start_increment(&mut self, inc: usize, lambda: f64) -> Result<()> {
        self.check_stop(inc)?;
        self.fixed_point = 0;
        self.combine_steps(inc - 1);
        // A part friction cannot hold has no state of rest: say so before
        // searching the patterns for one.
        self.friction_hold.check(
            &self.f_ext,
            lambda,
            self.settings.force_tolerance * lambda * self.scales.total_load,
            || format!("increment {inc} ({})", self.where_in_path(inc, lambda)),
        )?;
        Ok(())
    }

    /// Active-set increment `inc` from the pattern `states`. With a warm
    /// start, a first increment that settles is searched again from all bonded
    /// (`all_bonded`): a settlement depends on where the iteration started.
    fn active_set_step(
        &mut self,
        inc: usize,
        lambda: f64,
        states: &PairStates,
        warm: bool,
        all_bonded: &PairStates,
    ) -> Result<IncrementResult<D>> {
        let mut r = self.active_set_or_continuation(inc, lambda, states)?;
        if warm && inc == 1 && !r.settled.is_empty() {
            // A settlement depends on where the iteration started: take the
            // one a start from all bonded gives, as without the warm start.
            let history = r.history;
            self.settled_pattern = None;
            r = self.active_set_increment(inc, lambda, all_bonded.clone())?;
            r.history.splice(0..0, history);
            r.iterations = r.history.len();
        }
        Ok(r)
    }

    /// Implex increment `inc`: one solve in the carried `states`, which become
    /// those the law gives from this increment's jumps.
    fn implex_increment(
        &mut self,
        inc: usize,
        lambda: f64,
        states: &mut PairStates,
    ) -> Result<IncrementResult<D>> {
        let t = Instant::now();
        let (u, f_int, method) = self.solve_states(lambda, states, inc)?;
        let consistent = self.fixed_point_converged && self.slip_directions_settled;
        if !self.proportional && !consistent {
            // No consistent slip forces in the carried states: the
            // solution is the last fixed-point step's, possibly drifted
            // far (see the active set's rule), and no answer.
            return Err(Error::NoConvergence(format!(
                "increment {inc} ({}): the slip forces found no fixed point in the contact states the implex scheme carried from the previous increment (its slipping pairs do not hold their part, or a part is pushed along its faces harder than friction holds it). The scheme does not correct the states within an increment: use scheme = \"active-set\", or more increments",
                self.where_in_path(inc, lambda),
            )));
        }
        let check = self.check_law(states, &u, &f_int, lambda);
        // States for the next increment from this increment's jumps.
        let changed = count_changes(&check.next, states);
        let history = vec![Iteration {
            method,
            changed,
            seconds: t.elapsed().as_secs_f64(),
        }];
        let next = check.next.clone();
        let states = std::mem::replace(states, next);
        Ok(self.finish(inc, lambda, history, u, f_int, states, check, false))
    }

    /// Ends increment `inc` of `n_inc`, solved at load factor `lambda`: the
    /// pairs' histories committed into `result`, its step label, the precision
    /// check, the factor freed when no later increment needs it, and the
    /// solution kept for scaling.
    fn end_increment(
        &mut self,
        inc: usize,
        n_inc: usize,
        lambda: f64,
        result: &mut IncrementResult<D>,
    ) -> Result<()> {
        self.commit_history(result);
        if let Some((step, l)) = self.path.label(inc) {
            result.step = step;
            result.lambda = l;
            result.time = step as f64 + l;
        }
        self.check_precision(result)?;
        if (self.settings.scheme == Scheme::ActiveSet && self.proportional) || inc == n_inc {
            // Loads are proportional, so the next increment starts from a pattern
            // that holds at every load factor and is answered by scaling this
            // solution: the factor is not needed again (were it needed, the next
            // solve refactorizes). Free it before the increment is written. With
            // initial gaps, friction or augmented enforcement every increment is
            // solved, so the factor is kept until the last one (with either
            // scheme), and freed before the last increment's stresses and files.
            self.linear.release();
        }
        self.keep_for_scaling(result, lambda);
        Ok(())
    }

    /// Stops the run when the out-of-balance force has grown beyond what round-off
    /// explains: the solve lost its accuracy.
    fn check_precision(&self, r: &IncrementResult<D>) -> Result<()> {
        let worst = r.residual.max(r.balance);
        if worst <= self.settings.max_residual {
            return Ok(());
        }
        Err(Error::Precision {
            increment: r.index,
            residual: worst,
            message: format!(
                "increment {}: the out-of-balance force is {:.1e} of the balance scale {:.4e} (the largest at a free DOF, or the reactions against the applied load; the scale is the largest of the load (or the support reactions), the pair forces and 1e-4 × the softest part's {} × the largest displacement; limit [analysis] max_residual = {:.0e}), so the solution cannot be trusted. {}",
                r.index,
                worst,
                r.balance_scale,
                if D::N == 3 { "E × 1 (unit length)" } else { "E·t" },
                self.settings.max_residual,
                penalty_advice(self.parts, self.interfaces)
            ),
        })
    }

    /// Stops the run when the increment, which found no state satisfying the
    /// law, leaves a part held by its supports only across its faces pushed
    /// along them beyond μ × the normal force they carry
    /// ([`crate::solve::friction_hold::FrictionHold::check_settled`]).
    fn check_no_rest(&self, inc: usize, lambda: f64, r: &IncrementResult<D>) -> Result<()> {
        self.friction_hold.check_settled(
            self.interfaces,
            self.dofs,
            &self.f_ext,
            lambda,
            self.settings.force_tolerance * lambda * self.scales.total_load,
            &r.u,
            &r.states,
            &r.pair_history,
            || format!("increment {inc} ({})", self.where_in_path(inc, lambda)),
        )
    }

    /// Stops the run when a violation exceeds `max_violation` × the load scale.
    fn check_violation_limit(&self, r: &IncrementResult<D>) -> Result<()> {
        let limit = self.settings.max_violation * r.load_scale;
        let over: Vec<&PairViolation> = r.violations.iter().filter(|v| v.force > limit).collect();
        if over.is_empty() {
            return Ok(());
        }
        let pairs = self.pairs();
        let list: Vec<String> = over
            .iter()
            .take(10)
            .map(|v| {
                let (name, node, position) = pairs.label(v.interface, v.pair);
                let what = match v.kind {
                    ViolationKind::Tension => format!("bonded in tension {:.4e}", v.amount),
                    ViolationKind::Penetration => {
                        format!(
                            "open, penetrating {:.4e} (as a force {:.4e})",
                            v.amount, v.force
                        )
                    }
                    ViolationKind::Friction => {
                        format!("sticking beyond μ|f_n| by {:.4e}", v.amount)
                    }
                    ViolationKind::Slip => {
                        format!("slipping off μ|f_n| by {:.4e}", v.amount)
                    }
                };
                let at: Vec<String> = position.as_ref().iter().map(f64::to_string).collect();
                format!(
                    "interface '{name}' node {node} at ({}): {what}",
                    at.join(", ")
                )
            })
            .collect();
        let pairs = over
            .iter()
            .map(|v| {
                let (name, node, _) = pairs.label(v.interface, v.pair);
                (name.to_string(), node)
            })
            .collect();
        Err(Error::LawViolation {
            increment: r.index,
            pairs,
            message: format!(
                "increment {} (load factor {:.4}): no state satisfies the contact law, and {} pair(s) break it by more than [analysis] max_violation = {} of the load scale {:.4e}: {}{}. Refine the node part's face, or raise max_violation to accept",
                r.index,
                r.lambda,
                over.len(),
                self.settings.max_violation,
                r.load_scale,
                list.join("; "),
                if over.len() > 10 { "; …" } else { "" }
            ),
        })
    }
}

/// What to say about the penalties when the solve lost accuracy: the
/// interface of the largest penalty against the stiffness scale of its softer
/// part, E·t in a plane model, E·h in a solid one (h the mean size of its
/// pairs' host faces).
fn penalty_advice<D: ElementFamily>(parts: &[Part<D>], interfaces: &[Interface<D>]) -> String {
    let solid = D::N == 3;
    let worst = interfaces
        .iter()
        .map(|i| {
            let length = if solid && !i.elements.is_empty() {
                i.elements.iter().map(|c| c.edge_length).sum::<f64>() / i.elements.len() as f64
            } else {
                1.0
            };
            let et = |p: usize| parts[p].material.young * parts[p].material.thickness * length;
            let softer = et(i.host).min(et(i.node_part));
            (i.c_n.max(i.c_s) / softer, i)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let et = if solid { "E·h" } else { "E·t" };
    match worst {
        Some((ratio, i)) if ratio > 1e7 => format!(
            "Interface '{}' has a penalty {:.3e}, {:.1e} × {et} of its softer part: too large for double precision. Penalties between about 1e3 and 1e7 × {et} work (the default is 1e5 × {et}); lower c_n and c_s.",
            i.name,
            i.c_n.max(i.c_s),
            ratio
        ),
        _ if solid => "The model is ill-conditioned: check for very different stiffnesses (E) between parts, or elements of very different sizes.".into(),
        _ => "The model is ill-conditioned: check for very different stiffnesses (E, thickness) between parts, or elements of very different sizes.".into(),
    }
}
