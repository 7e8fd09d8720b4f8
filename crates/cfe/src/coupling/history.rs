//! The rules of the pairs' histories ([`PairHistory`]: plastic slip, slip force,
//! spring anchor, multipliers): how a pair's history follows its solution within
//! an increment and from one increment to the next. Each rule is a method of one
//! pair's history; the sweeps apply it to every pair of a model at the
//! displacements `u` ([`PairSet::at`]). They know no solver: the contact
//! scheme decides when each applies.
//!
//! - touch-down ([`touch_down`]): a Coulomb pair that closes does so where it is,
//!   unstressed tangentially;
//! - restore ([`restore_closed_slips`]): a Coulomb pair closed where the increment
//!   started and closed now is measured from its plastic slip of the increment's
//!   start, whatever the patterns tried in between did to it;
//! - the fixed-point step ([`step_terms`]): a slipping pair's slip force goes to
//!   its return map, its spring's anchor to its jump, an augmented pair's
//!   multipliers to its force (Uzawa);
//! - commit ([`commit`]): at the end of an increment a slipping pair keeps its
//!   plastic slip, an open one follows its jump and loses its multipliers.

use super::element::PairAt;
use super::law::{Law, LawParams, PairHistories, PairHistory, PairState, return_map};
use super::pair_set::PairSet;
use crate::dim::{Dim, Tangent};

/// What one fixed-point step did to a pair's terms ([`PairHistory::step_terms`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TermStep {
    /// Whether no term moved by more than the tolerances: the pair is at its
    /// fixed point.
    pub settled: bool,
    /// Augmented Lagrangian, closed pair: its penetration, or stick error where
    /// larger (length); `None` otherwise.
    pub augmented_error: Option<f64>,
}

impl<D: Dim> PairHistory<D> {
    /// Touch-down: a pair that closes at tangential jump `u_s` takes it as its
    /// plastic slip (so it closes without tangential force) and as its spring's
    /// anchor.
    pub fn touch_down(&mut self, u_s: D::Tangent) {
        self.slip = u_s;
        self.anchor = u_s;
    }

    /// Gives the pair the plastic slip of `start` (its history where the increment
    /// started) back; returns whether it changed.
    pub fn restore_slip(&mut self, start: &PairHistory<D>) -> bool {
        if self.slip != start.slip {
            self.slip = start.slip;
            true
        } else {
            false
        }
    }

    /// Ends an increment for a pair in `state` at tangential jump `u_s` under the
    /// law `law` (the element's: its penalties include the weight ω): a slipping
    /// pair keeps its plastic slip `s_p = [[u_s]] − f_s / c_s` (its slip force
    /// is the stick force of that slip), an open pair's slip follows its jump
    /// (Coulomb: it closes again unstressed tangentially; 0 for the other laws) and
    /// its multipliers are dropped; a bonded pair keeps its history.
    pub fn commit(&mut self, law: &LawParams, state: PairState, u_s: D::Tangent) {
        match state {
            PairState::Slip if law.c_s > 0.0 => {
                self.slip = u_s.sub(self.slip_force.map_each(|f| f / law.c_s));
            }
            PairState::Open => {
                self.slip = if law.law == Law::Coulomb {
                    u_s
                } else {
                    D::Tangent::default()
                };
                self.multiplier = Default::default();
            }
            _ => {}
        }
    }

    /// One fixed-point step on the right-hand-side terms of a pair in `state`
    /// evaluated at `p` (with this history) under the law `law` (the element's),
    /// with `augmented` the interface's penetration tolerance when it enforces its
    /// law by augmented Lagrangian, and `tol` the force tolerance:
    /// - an open pair drops its multipliers;
    /// - a closed Coulomb pair's slip force goes to its return map
    ///   ([`return_map`]: μ|f_n| along the trial force) and its spring's anchor to
    ///   its tangential jump — except a slip pair whose trial force is inside the
    ///   cone (it has no slip force to converge to in this pattern: the law check
    ///   makes it stick); a slip pair is settled when its slip force moved and its
    ///   spring carries no more than `tol`;
    /// - an augmented closed pair's multipliers go to its force (the tangential
    ///   one only when it sticks with a tangential penalty); it is settled when
    ///   its penetration and stick error are within `augmented`.
    pub fn step_terms(
        &mut self,
        law: &LawParams,
        state: PairState,
        p: &PairAt<D>,
        augmented: Option<f64>,
        tol: f64,
    ) -> TermStep {
        let local = LocalPair {
            gap: p.gap,
            u_s: p.jump.1,
            force: p.force,
        };
        self.step_local(law, state, &local, augmented, tol)
    }

    /// [`Self::step_terms`] for a pair given by its local quantities, in any
    /// dimension.
    pub fn step_local(
        &mut self,
        law: &LawParams,
        state: PairState,
        p: &LocalPair<D>,
        augmented: Option<f64>,
        tol: f64,
    ) -> TermStep {
        let mut settled = true;
        let zero = D::Tangent::default();
        if !state.is_closed() {
            if self.multiplier != (0.0, zero) {
                self.multiplier = (0.0, zero);
                settled = false;
            }
            return TermStep {
                settled,
                augmented_error: None,
            };
        }
        let (u_s, f) = (p.u_s, p.force);
        if law.law == Law::Coulomb {
            let limit = law.cone(f.0);
            let trial = law.trial_shear(u_s, self);
            let target = return_map(trial, limit);
            let inside = state == PairState::Slip && trial.norm() < limit;
            // The stabilising spring's force, which the fixed point removes.
            let spring = u_s.sub(self.anchor).scale(law.c_slip);
            if state == PairState::Slip
                && !inside
                && (target.sub(self.slip_force).norm() > tol || spring.norm() > tol)
            {
                settled = false;
            }
            if !inside {
                self.slip_force = target;
                self.anchor = u_s;
            }
        }
        let mut augmented_error = None;
        if let Some(penetration_tolerance) = augmented {
            let stick = state == PairState::Bonded && law.penalties(state)[1] > 0.0;
            let stick_error = if stick {
                u_s.sub(self.slip).norm()
            } else {
                0.0
            };
            let error = p.gap.abs().max(stick_error);
            augmented_error = Some(error);
            if error > penetration_tolerance {
                settled = false;
            }
            self.multiplier.0 = f.0;
            if stick {
                self.multiplier.1 = f.1;
            }
        }
        TermStep {
            settled,
            augmented_error,
        }
    }
}

/// A pair's local quantities at a solution, in any dimension: what the
/// fixed-point step reads of it ([`PairHistory::step_local`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalPair<D: Dim> {
    /// The normal gap `g₀ + [[u_n]]`.
    pub gap: f64,
    /// The tangential jump.
    pub u_s: D::Tangent,
    /// The local force `(f_n, f_s)` the host side exerts on the pair.
    pub force: (f64, D::Tangent),
}

/// The pairs of a Coulomb interface that close (open in `states`, closed in
/// `next`) touch down at their tangential jump in the solution `u`
/// ([`PairHistory::touch_down`]).
pub fn touch_down<P: PairSet>(
    pairs: &P,
    states: &[Vec<PairState>],
    next: &[Vec<PairState>],
    u: &[f64],
    history: &mut PairHistories<P::Dim>,
) {
    for i in 0..pairs.interface_count() {
        if pairs.law(i).law != Law::Coulomb {
            continue;
        }
        for k in 0..pairs.pair_count(i) {
            if states[i][k] == PairState::Open && next[i][k].is_closed() {
                let u_s = pairs.at(i, k, u, states[i][k], &history[i][k]).jump.1;
                history[i][k].touch_down(u_s);
            }
        }
    }
}

/// Gives every pair of a Coulomb interface closed both where the increment
/// started (`closed_at_start`) and in `states` its plastic slip of the
/// increment's start (`committed`) back ([`PairHistory::restore_slip`]): a
/// touch-down of a pattern tried, not of the path, moved it. Returns whether any
/// changed.
pub fn restore_closed_slips<P: PairSet>(
    pairs: &P,
    closed_at_start: &[Vec<bool>],
    committed: &PairHistories<P::Dim>,
    states: &[Vec<PairState>],
    history: &mut PairHistories<P::Dim>,
) -> bool {
    let mut changed = false;
    for i in 0..pairs.interface_count() {
        if pairs.law(i).law != Law::Coulomb {
            continue;
        }
        let closed = closed_at_start[i].iter().zip(&states[i]);
        let pairs = history[i].iter_mut().zip(&committed[i]);
        for ((h, start), (&was, now)) in pairs.zip(closed) {
            if was && now.is_closed() && h.restore_slip(start) {
                changed = true;
            }
        }
    }
    changed
}

/// One fixed-point step on the right-hand-side terms of every pair
/// ([`PairHistory::step_terms`]) at the solution `u` of `states`, under the laws
/// `laws` (per interface), on `history` (the histories `u` was computed with,
/// stepped in place). Returns whether every pair is settled, and the largest
/// augmented-Lagrangian error (0 without augmented interfaces).
pub fn step_terms<P: PairSet>(
    pairs: &P,
    laws: &[LawParams],
    states: &[Vec<PairState>],
    u: &[f64],
    history: &mut PairHistories<P::Dim>,
    tol: f64,
) -> (bool, f64) {
    let mut settled = true;
    let mut augmented_error: f64 = 0.0;
    for (i, base) in laws.iter().enumerate().take(pairs.interface_count()) {
        let augmented = pairs.augmented(i);
        for k in 0..pairs.pair_count(i) {
            let state = states[i][k];
            let h = &mut history[i][k];
            let p = pairs.at(i, k, u, state, h);
            // A segment point's penalties are its weight × the interface's.
            let step = h.step_terms(&pairs.pair_law(i, k, base), state, &p, augmented, tol);
            settled &= step.settled;
            if let Some(e) = step.augmented_error {
                augmented_error = augmented_error.max(e);
            }
        }
    }
    (settled, augmented_error)
}

/// Ends an increment on every pair ([`PairHistory::commit`]) at its solution `u`
/// and final `states`.
pub fn commit<P: PairSet>(
    pairs: &P,
    states: &[Vec<PairState>],
    u: &[f64],
    history: &mut PairHistories<P::Dim>,
) {
    for i in 0..pairs.interface_count() {
        let base = pairs.law(i);
        for k in 0..pairs.pair_count(i) {
            let state = states[i][k];
            let u_s = pairs.at(i, k, u, state, &history[i][k]).jump.1;
            history[i][k].commit(&pairs.pair_law(i, k, &base), state, u_s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::fixture::{displaced, dofs, interface};
    use crate::coupling::pair_set::InterfacePairs;

    /// Touch-down: the Coulomb pairs that close take their tangential jump as
    /// their plastic slip and anchor (so they close without tangential force);
    /// pairs that stay open or were closed, and pairs of other laws, keep theirs.
    #[test]
    fn touch_down_closes_pairs_where_they_are() {
        let ifaces = [interface(Law::Coulomb, 3, 0.5), interface(Law::Contact, 3, 0.0)];
        let u = displaced(&[[0.0, 0.7], [0.0, -0.2], [0.0, 0.4]]);
        let open = vec![PairState::Open, PairState::Open, PairState::Bonded];
        let states = vec![open.clone(), open];
        let next = vec![vec![PairState::Bonded, PairState::Open, PairState::Bonded]; 2];
        let start: PairHistory = PairHistory {
            slip: 0.1,
            anchor: 0.1,
            ..PairHistory::default()
        };
        let mut history = vec![vec![start; 3]; 2];
        touch_down(&InterfacePairs::new(&ifaces, &dofs(3)), &states, &next, &u, &mut history);
        assert_eq!((history[0][0].slip, history[0][0].anchor), (0.7, 0.7));
        assert_eq!(history[0][1], start);
        assert_eq!(history[0][2], start);
        assert!(history[1].iter().all(|h| *h == start));
        // At touch-down the pair's stick force is zero.
        let p = ifaces[0].pair_at(0, &dofs(3), &u, PairState::Bonded, &history[0][0]);
        assert_eq!(p.force.1, 0.0);
    }

    /// Restore: a Coulomb pair closed where the increment started and closed now
    /// gets its plastic slip of the start back (and only its slip); a pair open at
    /// the start, or open now, keeps what it has; the answer says whether any
    /// changed.
    #[test]
    fn restore_gives_closed_pairs_their_slip_back() {
        let ifaces = [interface(Law::Coulomb, 3, 0.5)];
        let committed = vec![vec![PairHistory::default(); 3]];
        let moved: PairHistory = PairHistory {
            slip: 0.3,
            slip_force: 0.2,
            ..PairHistory::default()
        };
        let mut history = vec![vec![moved; 3]];
        let closed_at_start = vec![vec![true, false, true]];
        let states = vec![vec![PairState::Bonded, PairState::Bonded, PairState::Open]];
        assert!(restore_closed_slips(
            &InterfacePairs::new(&ifaces, &dofs(3)),
            &closed_at_start,
            &committed,
            &states,
            &mut history
        ));
        assert_eq!(history[0][0].slip, 0.0);
        assert_eq!(history[0][0].slip_force, 0.2);
        assert_eq!(history[0][1], moved);
        assert_eq!(history[0][2], moved);
        assert!(!restore_closed_slips(
            &InterfacePairs::new(&ifaces, &dofs(3)),
            &closed_at_start,
            &committed,
            &states,
            &mut history
        ));
    }

    /// Commit: a slipping pair keeps the plastic slip whose stick force is its slip
    /// force (so it sticks on at the force it slipped with); an open Coulomb pair's
    /// slip follows its jump, an open contact pair's returns to 0, and both lose
    /// their multipliers; a bonded pair keeps its history.
    #[test]
    fn commit_keeps_the_plastic_slip() {
        let ifaces = [interface(Law::Coulomb, 3, 0.5), interface(Law::Contact, 3, 0.0)];
        let u = displaced(&[[-0.2, 0.6], [0.1, 0.9], [-0.2, 0.5]]);
        let h: PairHistory = PairHistory {
            slip: 0.05,
            slip_force: 1.0,
            anchor: 0.6,
            multiplier: (-0.5, 0.25),
        };
        let states = vec![vec![PairState::Slip, PairState::Open, PairState::Bonded]; 2];
        let mut history = vec![vec![h; 3]; 2];
        commit(&InterfacePairs::new(&ifaces, &dofs(3)), &states, &u, &mut history);
        let slipped = history[0][0];
        assert!((slipped.slip - (0.6 - 1.0 / 4.0)).abs() < 1e-15);
        let law = ifaces[0].params();
        let stick = law.local_force(PairState::Bonded, -0.2, 0.6, &slipped);
        assert!((stick.1 - (1.0 + 0.25)).abs() < 1e-14, "{stick:?}");
        assert_eq!(history[0][1].slip, 0.9);
        assert_eq!(history[0][1].multiplier, (0.0, 0.0));
        assert_eq!(history[1][1].slip, 0.0);
        assert_eq!(history[1][1].multiplier, (0.0, 0.0));
        assert_eq!(history[0][2], h);
        assert_eq!(history[1][2], h);
    }

    /// The fixed-point step of a slipping pair: its slip force goes to μ|f_n|
    /// along its trial force (the return map, either way) and its anchor to its
    /// jump, unsettled while they move; at the fixed point a step changes
    /// nothing and is settled. A slip pair inside its cone is left alone; an open
    /// pair drops its multipliers (unsettled once).
    #[test]
    fn slip_force_steps_to_the_return_map() {
        let law = interface(Law::Coulomb, 1, 0.5).params();
        let ifaces = [interface(Law::Coulomb, 3, 0.5)];
        // f_n = −2: the cone is 1; trial forces 4 × (0.3, −0.3, 0.1).
        let u = displaced(&[[-0.2, 0.3], [-0.2, -0.3], [-0.2, 0.1]]);
        let states = vec![vec![PairState::Slip; 3]];
        let mut history = vec![vec![PairHistory::default(); 3]];
        let laws = [law];
        let (settled, error) =
            step_terms(&InterfacePairs::new(&ifaces, &dofs(3)), &laws, &states, &u, &mut history, 1e-9);
        assert!(!settled);
        assert_eq!(error, 0.0);
        assert_eq!((history[0][0].slip_force, history[0][0].anchor), (1.0, 0.3));
        assert_eq!((history[0][1].slip_force, history[0][1].anchor), (-1.0, -0.3));
        assert_eq!(history[0][2], PairHistory::default());
        let (settled, _) = step_terms(&InterfacePairs::new(&ifaces, &dofs(3)), &laws, &states, &u, &mut history, 1e-9);
        assert!(settled);
        assert_eq!(history[0][0].slip_force, 1.0);
        // Open with multipliers: dropped.
        let mut h: PairHistory = PairHistory {
            multiplier: (1.0, 0.0),
            ..PairHistory::default()
        };
        let p = ifaces[0].pair_at(0, &dofs(3), &u, PairState::Open, &h);
        let step = h.step_terms(&law, PairState::Open, &p, Some(1e-3), 1e-9);
        assert_eq!((step.settled, h.multiplier), (false, (0.0, 0.0)));
    }

    /// The Uzawa step of an augmented stick pair: its multipliers become its force
    /// (so the next solve's penetration shrinks); its error is the larger of its
    /// penetration and its stick error, settled only within the tolerance.
    #[test]
    fn augmented_multipliers_step_to_the_force() {
        let law = interface(Law::Contact, 1, 0.0).params();
        let ifaces = [interface(Law::Contact, 1, 0.0)];
        let u = displaced(&[[-0.02, 0.03]]);
        let mut h: PairHistory = PairHistory {
            multiplier: (-1.0, 0.0),
            ..PairHistory::default()
        };
        let p = ifaces[0].pair_at(0, &dofs(1), &u, PairState::Bonded, &h);
        let step = h.step_terms(&law, PairState::Bonded, &p, Some(1e-3), 1e-9);
        assert!(!step.settled);
        assert_eq!(step.augmented_error, Some(0.03));
        assert!((h.multiplier.0 - (-0.2 - 1.0)).abs() < 1e-15);
        assert!((h.multiplier.1 - 0.12).abs() < 1e-15);
        let step = h.step_terms(&law, PairState::Bonded, &p, Some(0.05), 1e-9);
        assert!(step.settled);
    }
}
