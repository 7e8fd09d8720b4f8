//! The law sweep and the history rules the contact scheme runs, driven through a
//! pair set of this test's own whose tangent has two components (test-only; a
//! file of its own, above `pair_set`, `check` and `history`, which it uses).

use super::check::{CheckTolerance, check_law};
use super::element::{CfeDofs, PairAt};
use super::history;
use super::law::{Law, LawParams, PairHistory, PairState, ViolationKind};
use super::pair_set::PairSet;
use crate::dim::{PlaneTangent, Tangent};

/// A pair set of the test's own in a dimension with a two-component
/// tangent ([`PlaneTangent`]: n along z, the tangent plane x–y): one node per
/// pair on a fixed ground, so the jump is the node's displacement. Its frame
/// is the identity rotated about n by `turn` — the choice of t₁, t₂ no result
/// may depend on.
struct GroundPairs {
    law: LawParams,
    pairs: usize,
    turn: f64,
}

impl GroundPairs {
    /// The tangential components along the set's (t₁, t₂) of global (x, y).
    fn local(&self, x: f64, y: f64) -> [f64; 2] {
        let (s, c) = self.turn.sin_cos();
        [c * x + s * y, -s * x + c * y]
    }
}

impl PairSet for GroundPairs {
    type Dim = PlaneTangent;

    fn interface_count(&self) -> usize {
        1
    }

    fn pair_count(&self, _: usize) -> usize {
        self.pairs
    }

    fn law(&self, _: usize) -> LawParams {
        self.law
    }

    fn augmented(&self, _: usize) -> Option<f64> {
        None
    }

    fn pair_law(&self, _: usize, _: usize, base: &LawParams) -> LawParams {
        *base
    }

    fn pair_dofs(&self, _: usize, k: usize) -> CfeDofs {
        CfeDofs::new(&[3 * k, 3 * k + 1, 3 * k + 2])
    }

    fn initial_gap(&self, _: usize, _: usize) -> f64 {
        0.0
    }

    fn label(&self, _: usize, k: usize) -> (&str, usize, [f64; 3]) {
        ("ground", k, [k as f64, 0.0, 0.0])
    }

    fn at(
        &self,
        i: usize,
        k: usize,
        u: &[f64],
        state: PairState,
        h: &PairHistory<PlaneTangent>,
    ) -> PairAt<PlaneTangent> {
        let dofs = self.pair_dofs(i, k);
        let d = dofs.gather(u);
        let jump = (d[2], self.local(d[0], d[1]));
        let gap = jump.0;
        let force = self.law.local_force(state, gap, jump.1, h);
        PairAt {
            dofs,
            d,
            jump,
            gap,
            force,
        }
    }

    fn stiffness_terms(&self, _: usize, _: usize, f: &mut dyn FnMut(usize, f64, &[f64])) {
        let (s, c) = self.turn.sin_cos();
        f(0, self.law.c_n, &[0.0, 0.0, 1.0]);
        f(1, self.law.c_s, &[c, s, 0.0]);
        f(2, self.law.c_s, &[-s, c, 0.0]);
    }
}

fn coulomb() -> LawParams {
    LawParams {
        law: Law::Coulomb,
        c_n: 10.0,
        c_s: 4.0,
        friction: 0.5,
        c_slip: 0.4,
    }
}

/// The law sweep and the history rules the contact scheme runs are
/// dimension-agnostic: driven through a pair set with a two-component
/// tangent, a stick pair pressed (f_n = −2, cone 1) and sheared beyond its
/// cone is reported and slips whichever tangent pair (t₁, t₂) the set chose;
/// a sheared pair within its cone sticks; the fixed-point step puts the slip
/// force on the cone along the trial force (radial return), and the commit
/// keeps the plastic slip whose stick force is that slip force — the same
/// global vectors for every choice of the tangents.
#[test]
fn the_sweep_and_the_history_rules_in_a_tangent_plane() {
    // Pair 0: (x, y) shear (0.3, 0.4) → trial 4 × 0.5 = 2 > 1; pair 1: 0.1 → 0.4.
    let u = [0.3, 0.4, -0.2, 0.06, -0.08, -0.2];
    let tol = CheckTolerance {
        force: 1e-9,
        gap: 1e-9,
    };
    let mut slips = Vec::new();
    for turn in [0.0, 0.7, -2.3] {
        let set = GroundPairs {
            law: coulomb(),
            pairs: 2,
            turn,
        };
        let states = vec![vec![PairState::Bonded; 2]];
        let v = check_law(&set, &[set.law], &states, None, &u, tol);
        assert_eq!(v.next, vec![vec![PairState::Slip, PairState::Bonded]]);
        let kinds: Vec<_> = v.violations.iter().map(|&(i, k, v)| (i, k, v.kind)).collect();
        assert_eq!(kinds, [(0, 0, ViolationKind::Friction)]);
        assert!((v.violations[0].2.amount - 1.0).abs() < 1e-12);
        assert_eq!(v.pressed, [true]);
        // The fixed point's step on the slipping pair: slip force μ|f_n| = 1
        // along the trial force, anchor at the jump.
        let slipping = vec![vec![PairState::Slip, PairState::Bonded]];
        let mut h = vec![vec![PairHistory::<PlaneTangent>::default(); 2]];
        let (settled, _) =
            history::step_terms(&set, &[set.law], &slipping, &u, &mut h, 1e-12);
        assert!(!settled);
        let f = h[0][0].slip_force;
        assert!((f.norm() - 1.0).abs() < 1e-14);
        let along = set.local(0.6, 0.8);
        assert!((f[0] - along[0]).abs() < 1e-14 && (f[1] - along[1]).abs() < 1e-14);
        // Commit: the plastic slip s_p = u_s − f_s / c_s, so the stick force
        // at the slip is the slip force.
        history::commit(&set, &slipping, &u, &mut h);
        let s = h[0][0].slip;
        let stick = set.law.trial_shear(set.local(0.3, 0.4), &h[0][0]);
        assert!(stick.sub(f).norm() < 1e-14, "{stick:?} {f:?}");
        // Back in global (x, y): the same for every choice of (t₁, t₂).
        let (sn, cs) = turn.sin_cos();
        slips.push([cs * s[0] - sn * s[1], sn * s[0] + cs * s[1]]);
    }
    for s in &slips[1..] {
        assert!((s[0] - slips[0][0]).abs() < 1e-14 && (s[1] - slips[0][1]).abs() < 1e-14);
    }
    // s_p = (0.3, 0.4) − (0.6, 0.8) / 4 = (0.15, 0.2).
    assert!((slips[0][0] - 0.15).abs() < 1e-14 && (slips[0][1] - 0.2).abs() < 1e-14);
}

/// A pair set's stiffness terms cover its components: the normal and each
/// tangent component, 1 + `Tangent::COMPONENTS` of them.
#[test]
fn one_stiffness_term_per_local_component() {
    let set = GroundPairs {
        law: coulomb(),
        pairs: 1,
        turn: 0.3,
    };
    let mut seen = Vec::new();
    set.stiffness_terms(0, 0, &mut |j, _, w| seen.push((j, w.len())));
    assert_eq!(seen.len(), 1 + <[f64; 2] as Tangent>::COMPONENTS);
    assert!(seen.iter().enumerate().all(|(j, &(s, n))| s == j && n == 3));
}
