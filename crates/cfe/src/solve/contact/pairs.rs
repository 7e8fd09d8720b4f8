//! The law on every pair, as the contact scheme reads it: the sweep that
//! checks a solution and gives each pair its next state ([`LawCheck`]), the
//! law's parameters and tolerances as the search reads them, and the
//! pair-history rules (a pair touching down, the plastic slip of the
//! increment's start restored, the history committed at an increment's end).

use super::increment::{IncrementResult, PairViolation};
use super::solver::Solver;
use crate::coupling::{Interface, Law, LawTolerance, PairState, PairStates, ViolationKind};

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

impl Solver<'_> {
    /// The law parameters of `iface` as the search reads them: its friction
    /// coefficient times [`Solver::friction_factor`].
    pub(super) fn law_params(&self, iface: &Interface) -> crate::coupling::LawParams {
        let mut p = iface.params();
        p.friction *= self.friction_factor;
        p
    }

    /// The open/closed tolerance of a pair: `gap_tolerance` × the largest
    /// displacement magnitude among its nodes (element displacements `d`).
    pub(super) fn gap_tolerance(&self, d: &[f64]) -> f64 {
        let scale = d
            .chunks_exact(2)
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        self.settings.gap_tolerance * scale
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
        let mut violations = Vec::new();
        let mut nearest: Vec<Option<(usize, f64)>> = vec![None; self.interfaces.len()];
        let mut normal = vec![0.0; self.interfaces.len()];
        let mut pair_force = 0.0f64;
        let next = self
            .interfaces
            .iter()
            .zip(states)
            .enumerate()
            .map(|(i, (iface, st))| {
                iface
                    .elements
                    .iter()
                    .zip(st)
                    .enumerate()
                    .map(|(k, (c, &state))| {
                        if iface.law == Law::Rigid {
                            return PairState::Bonded;
                        }
                        let d = c.dofs(self.dofs, iface.host, iface.node_part).gather(u);
                        let d = &d[..c.n_dofs()];
                        let jump = c.local_jump(d);
                        let gap = c.gap(jump);
                        let tol = LawTolerance {
                            tension: self.settings.force_tolerance * load_scale,
                            penetration: self.gap_tolerance(d),
                        };
                        // A segment point's penalties are its weight × the interface's.
                        let base = self.law_params(iface);
                        let law = c.params(&base);
                        let h = &self.history[i][k];
                        let f = if self.proportional {
                            [law.c_n * gap, 0.0]
                        } else {
                            c.law_force(&base, state, h, d).1
                        };
                        if state.is_closed() {
                            normal[i] += f[0];
                            // (With the proportional shortcuts `f` holds the
                            // normal force only.)
                            let shear = if iface.law == Law::Frictionless {
                                0.0
                            } else if self.proportional {
                                law.c_s * jump[1]
                            } else {
                                f[1]
                            };
                            pair_force = pair_force.max(f[0].hypot(shear));
                        }
                        let mut push = |v: crate::coupling::LawViolation| {
                            violations.push(PairViolation {
                                interface: i,
                                pair: k,
                                kind: v.kind,
                                amount: v.amount,
                                force: v.force,
                            })
                        };
                        if let Some(v) =
                            iface.law.normal_violation(state, gap, f[0], law.c_n, tol)
                        {
                            push(v);
                            // A stick pair pulling beyond its (zero) cone slips first:
                            // its tension may come from the shear it cannot carry.
                            if state == PairState::Bonded
                                && let (PairState::Slip, Some(fv)) =
                                    law.friction_check(state, f[0], jump[1], f[1], h, tol.tension)
                            {
                                push(fv);
                                return PairState::Slip;
                            }
                            return match state {
                                PairState::Open => PairState::Bonded,
                                _ => PairState::Open,
                            };
                        }
                        let (next, v) =
                            law.friction_check(state, f[0], jump[1], f[1], h, tol.tension);
                        if let Some(v) = v {
                            push(v);
                        }
                        if state == PairState::Slip && iface.law == Law::Coulomb {
                            let limit = law.friction * (-f[0]).max(0.0);
                            let ratio = law.trial_shear(jump[1], h).abs() / limit;
                            if limit > 0.0 && nearest[i].is_none_or(|(_, r)| ratio < r) {
                                nearest[i] = Some((k, ratio));
                            }
                        }
                        next
                    })
                    .collect()
            })
            .collect();
        let mut next: PairStates = next;
        // Friction first: while some stick pair exceeds its cone, the tension of
        // other pairs may come from that excess shear (a block tipped by a trial
        // force friction cannot carry), so they are opened only once the stick
        // pairs have slipped.
        if violations.iter().any(|v| v.kind == ViolationKind::Friction) {
            for v in &violations {
                if v.kind == ViolationKind::Tension && next[v.interface][v.pair] == PairState::Open
                {
                    next[v.interface][v.pair] = states[v.interface][v.pair];
                }
            }
        }
        LawCheck {
            next,
            violations,
            load_scale,
            pair_force,
            nearest_slip: nearest.into_iter().map(|n| n.map(|(k, _)| k)).collect(),
            pressed: normal.into_iter().map(|f| f < 0.0).collect(),
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
        for (i, iface) in self.interfaces.iter().enumerate() {
            if iface.law != Law::Coulomb {
                continue;
            }
            for (k, c) in iface.elements.iter().enumerate() {
                if states[i][k] == PairState::Open && next[i][k].is_closed() {
                    let d = c.dofs(self.dofs, iface.host, iface.node_part).gather(u);
                    let u_s = c.local_jump(&d)[1];
                    self.history[i][k].slip = u_s;
                    self.history[i][k].anchor = u_s;
                }
            }
        }
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
        let mut changed = false;
        for (i, iface) in self.interfaces.iter().enumerate() {
            if iface.law != Law::Coulomb {
                continue;
            }
            let closed = self.closed_at_start[i].iter().zip(&states[i]);
            let history = self.history[i].iter_mut().zip(&self.committed[i]);
            for ((h, start), (&was, now)) in history.zip(closed) {
                if was && now.is_closed() && h.slip != start.slip {
                    h.slip = start.slip;
                    changed = true;
                }
            }
        }
        changed
    }

    /// Ends an increment's history: a slipping Coulomb pair keeps its plastic slip
    /// `s_p = [[u_s]] − f_s / c_s`, an open pair's slip follows its jump (it closes
    /// again unstressed tangentially) and loses its multipliers. Copies the history
    /// into `result`.
    pub(super) fn commit_history(&mut self, result: &mut IncrementResult) {
        result.fixed_point_iterations = self.fixed_point;
        result.augmented_error = self.augmented_error;
        if self.proportional {
            result.pair_history = self.history.clone();
            return;
        }
        for (i, iface) in self.interfaces.iter().enumerate() {
            for (k, c) in iface.elements.iter().enumerate() {
                let h = &mut self.history[i][k];
                let d = c
                    .dofs(self.dofs, iface.host, iface.node_part)
                    .gather(&result.u);
                let u_s = c.local_jump(&d)[1];
                match result.states[i][k] {
                    PairState::Slip if iface.c_s > 0.0 => {
                        h.slip = u_s - h.slip_force / (c.weight() * iface.c_s)
                    }
                    PairState::Open => {
                        h.slip = if iface.law == Law::Coulomb { u_s } else { 0.0 };
                        h.multiplier = [0.0; 2];
                    }
                    _ => {}
                }
            }
        }
        result.pair_history = self.history.clone();
        self.committed.clone_from(&self.history);
        for (c, st) in self.closed_at_start.iter_mut().zip(&result.states) {
            for (c, s) in c.iter_mut().zip(st) {
                *c = s.is_closed();
            }
        }
    }
}
