//! The law checked on every pair of a model at one solution (the sweep the
//! contact scheme runs after every solve): each pair is evaluated at the
//! displacements ([`PairSet::at`]) and judged by its law
//! ([`LawParams::next_state`]); the sweep adds the rule that binds pairs
//! together — friction first: while some stick pair exceeds its cone, no pair is
//! opened for tension (the tension may come from the shear friction cannot carry,
//! a block tipped by a trial force; those pairs open once the stick pairs have
//! slipped) — and what the scheme reads of the whole (the largest pair force, each
//! interface's slipping pair nearest its cone, whether its pairs press).
//!
//! It receives the displacements, the states, the histories, the laws and the
//! tolerances, and knows no solver.

use super::law::{
    Law, LawParams, LawTolerance, LawViolation, PairHistory, PairState, PairStates,
    ViolationKind,
};
use super::pair_set::PairSet;
use crate::dim::{Dim, Tangent};

/// The tolerances of a law check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckTolerance {
    /// The largest tensile force a closed pair may carry, and the slack of the
    /// friction checks (a force: the force tolerance × the load scale).
    pub force: f64,
    /// The largest interpenetration an open pair may show, as a fraction of the
    /// largest displacement magnitude among the pair's nodes.
    pub gap: f64,
}

impl CheckTolerance {
    /// The tolerances of a pair with element displacements `d`: the force
    /// tolerance, and the gap tolerance × the largest displacement magnitude
    /// among its nodes.
    pub fn of_pair<D: Dim>(&self, d: &[f64]) -> LawTolerance {
        let scale = d.chunks_exact(D::N).map(D::length).fold(0.0, f64::max);
        LawTolerance {
            tension: self.force,
            penetration: self.gap * scale,
        }
    }
}

/// The law's verdicts on every pair of a model at one solution ([`check_law`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Verdicts {
    /// The state the law gives each pair next: `next[i][k]` for pair k of
    /// interface i.
    pub next: PairStates,
    /// Every violation as (interface, pair, violation), sorted by interface and
    /// pair (a pair's normal violation before its friction one).
    pub violations: Vec<(usize, usize, LawViolation)>,
    /// The largest force ‖(f_n, f_s)‖ of a closed pair of a law other than
    /// `rigid`.
    pub pair_force: f64,
    /// Per interface, its slipping Coulomb pair nearest its cone (the least
    /// trial force over μ |f_n|), if it has one.
    pub nearest_slip: Vec<Option<usize>>,
    /// Per interface, whether its closed pairs press together (Σ f_n < 0).
    pub pressed: Vec<bool>,
}

/// Checks the law on every pair of `interfaces` at the displacements `u` (read
/// at the coupling elements' DOFs only) in `states`, with the pairs' histories
/// (`None`: all zero, the seed's laws) and the laws `laws` (per interface; the
/// interface's own, or its friction coefficient scaled by a continuation in μ):
/// the state the law gives each pair next and every violation with its amount.
/// Pairs of a `rigid` interface stay bonded and are not evaluated.
pub fn check_law<P: PairSet>(
    pairs: &P,
    laws: &[LawParams],
    states: &[Vec<PairState>],
    history: Option<&[Vec<PairHistory<P::Dim>>]>,
    u: &[f64],
    tol: CheckTolerance,
) -> Verdicts {
    let count = pairs.interface_count();
    debug_assert_eq!(laws.len(), count);
    let mut violations = Vec::new();
    let mut nearest: Vec<Option<(usize, f64)>> = vec![None; count];
    let mut normal = vec![0.0; count];
    let mut pair_force = 0.0f64;
    let mut next: PairStates = Vec::with_capacity(count);
    for (i, (base, st)) in laws.iter().zip(states).enumerate() {
        if base.law == Law::Rigid {
            next.push(vec![PairState::Bonded; st.len()]);
            continue;
        }
        let mut next_i = Vec::with_capacity(st.len());
        for (k, &state) in st.iter().enumerate().take(pairs.pair_count(i)) {
            let h = history.map_or(PairHistory::default(), |h| h[i][k]);
            let p = pairs.at(i, k, u, state, &h);
            // A segment point's penalties are its weight × the interface's.
            let law = pairs.pair_law(i, k, base);
            let f = p.force;
            if state.is_closed() {
                normal[i] += f.0;
                pair_force = pair_force.max(f.0.hypot(f.1.norm()));
            }
            let t = law.next_state(state, p.gap, f, p.jump.1, &h, tol.of_pair::<P::Dim>(p.d()));
            violations.extend(t.violations().map(|v| (i, k, v)));
            if t.normal.is_none() && state == PairState::Slip && law.law == Law::Coulomb {
                let limit = law.cone(f.0);
                let ratio = law.trial_shear(p.jump.1, &h).norm() / limit;
                if limit > 0.0 && nearest[i].is_none_or(|(_, r)| ratio < r) {
                    nearest[i] = Some((k, ratio));
                }
            }
            next_i.push(t.next);
        }
        next.push(next_i);
    }
    // Friction first.
    if violations
        .iter()
        .any(|(_, _, v)| v.kind == ViolationKind::Friction)
    {
        for &(i, k, v) in &violations {
            if v.kind == ViolationKind::Tension && next[i][k] == PairState::Open {
                next[i][k] = states[i][k];
            }
        }
    }
    Verdicts {
        next,
        violations,
        pair_force,
        nearest_slip: nearest.into_iter().map(|n| n.map(|(k, _)| k)).collect(),
        pressed: normal.into_iter().map(|f| f < 0.0).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::fixture::{displaced, dofs, interface};
    use crate::coupling::pair_set::InterfacePairs;

    const TOL: CheckTolerance = CheckTolerance {
        force: 1e-3,
        gap: 1e-3,
    };

    /// The law check on a contact interface: a bonded pair pulling beyond the
    /// force tolerance is reported as tension (its normal force) and opened, one
    /// within it kept; an open pair penetrating is reported as penetration (its
    /// depth; c_n × depth as a force) and closed, one penetrating less than the
    /// gap tolerance × its displacement kept open; a rigid interface in tension
    /// stays bonded, breaks nothing and is left out of the largest pair force.
    #[test]
    fn contact_violations_kind_and_amount() {
        // The rigid interface's pairs read nodes 2 and 3, whose forces (−10 × 0.1,
        // 4 × 1) exceed every contact pair's.
        let mut rigid = interface(Law::Rigid, 2, 0.0);
        for (j, c) in rigid.elements.iter_mut().enumerate() {
            c.node = j + 2;
        }
        let ifaces = [interface(Law::Contact, 4, 0.0), rigid];
        let laws: Vec<LawParams> = ifaces.iter().map(|i| i.params()).collect();
        let u = displaced(&[[2e-4, 0.0], [0.5e-4, 0.0], [-0.1, 0.0], [-0.5e-3, 1.0]]);
        let states = vec![
            vec![PairState::Bonded, PairState::Bonded, PairState::Open, PairState::Open],
            vec![PairState::Bonded, PairState::Open],
        ];
        let v = check_law(&InterfacePairs::new(&ifaces, &dofs(4)), &laws, &states, None, &u, TOL);
        assert_eq!(
            v.next,
            vec![
                vec![PairState::Open, PairState::Bonded, PairState::Bonded, PairState::Open],
                vec![PairState::Bonded; 2],
            ]
        );
        assert_eq!(v.violations.len(), 2);
        let (i, k, t) = v.violations[0];
        assert_eq!((i, k, t.kind), (0, 0, ViolationKind::Tension));
        assert!((t.amount - 2e-3).abs() < 1e-15 && t.force == t.amount);
        let (i, k, p) = v.violations[1];
        assert_eq!((i, k, p.kind), (0, 2, ViolationKind::Penetration));
        assert!((p.amount - 0.1).abs() < 1e-15 && (p.force - 1.0).abs() < 1e-14);
        // The largest closed pair's force, the rigid pairs' left out.
        assert!((v.pair_force - 2e-3).abs() < 1e-15);
        assert_eq!(v.pressed, [false, false]);
        assert_eq!(v.nearest_slip, [None, None]);
    }

    /// The law check on a Coulomb interface: a stick pair beyond its cone is
    /// reported (friction, by its excess) and slips; while it does, a pulling
    /// stick pair is reported (tension) but not opened (friction first), and it
    /// opens once no pair exceeds its cone; of the slipping pairs on their cones
    /// the one with the smallest trial force over μ|f_n| is the nearest; the
    /// interface presses. The laws passed decide: at 16 μ no pair exceeds its
    /// cone.
    #[test]
    fn coulomb_violations_friction_first_and_nearest_slip() {
        let iface = interface(Law::Coulomb, 4, 0.5);
        let ifaces = [iface];
        let laws = [ifaces[0].params()];
        // f_n = −2 on pairs 0, 2, 3 (the cone is 1); pair 1 pulls with 0.1.
        let jumps = [[-0.2, 0.3], [0.01, 0.0], [-0.2, 0.3], [-0.2, 0.28]];
        let u = displaced(&jumps);
        let states = vec![vec![
            PairState::Bonded,
            PairState::Bonded,
            PairState::Slip,
            PairState::Slip,
        ]];
        // The slip pairs carry μ|f_n| = 1, their springs at rest.
        let mut history = vec![vec![PairHistory::default(); 4]];
        for k in [2, 3] {
            history[0][k].slip_force = 1.0;
            history[0][k].anchor = jumps[k][1];
        }
        let v = check_law(&InterfacePairs::new(&ifaces, &dofs(4)), &laws, &states, Some(&history), &u, TOL);
        assert_eq!(
            v.next,
            vec![vec![
                PairState::Slip,
                PairState::Bonded,
                PairState::Slip,
                PairState::Slip
            ]]
        );
        let kinds: Vec<_> = v.violations.iter().map(|&(i, k, v)| (i, k, v.kind)).collect();
        assert_eq!(
            kinds,
            [(0, 0, ViolationKind::Friction), (0, 1, ViolationKind::Tension)]
        );
        assert!((v.violations[0].2.amount - 0.2).abs() < 1e-12);
        assert!((v.violations[1].2.amount - 0.1).abs() < 1e-12);
        assert_eq!(v.nearest_slip, [Some(3)]);
        assert_eq!(v.pressed, [true]);
        assert!((v.pair_force - 2.0f64.hypot(1.2)).abs() < 1e-12);
        // Pair 0 inside its cone: pair 1 opens.
        let u = displaced(&[[-0.2, 0.2], jumps[1], jumps[2], jumps[3]]);
        let v = check_law(&InterfacePairs::new(&ifaces, &dofs(4)), &laws, &states, Some(&history), &u, TOL);
        assert_eq!(v.next[0][..2], [PairState::Bonded, PairState::Open]);
        // A continuation's laws at 16 μ: pair 0 sticks, so pair 1 opens.
        let wide = [LawParams {
            friction: 16.0 * 0.5,
            ..laws[0]
        }];
        let u = displaced(&jumps);
        let v = check_law(&InterfacePairs::new(&ifaces, &dofs(4)), &wide, &states, Some(&history), &u, TOL);
        assert_eq!(v.next[0][..2], [PairState::Bonded, PairState::Open]);
    }

    /// A pair's penetration tolerance is the gap tolerance × the largest
    /// displacement magnitude among its nodes; its tension tolerance is the force
    /// tolerance.
    #[test]
    fn tolerances_of_a_pair() {
        let t = TOL.of_pair::<crate::dim::D2>(&[0.0, 0.0, 3.0, 4.0, -1.0, 0.0]);
        assert_eq!(t.tension, 1e-3);
        assert!((t.penetration - 5e-3).abs() < 1e-18);
    }
}
