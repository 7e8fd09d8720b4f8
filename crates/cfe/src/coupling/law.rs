//! The interface law of a coupling pair (SPEC §2): in the local frame (n, s),
//! `f_n = (1 − D̂) c_n g_n`, `f_s = (1 − D̂) c_s [[u_s]]`, with the normal gap
//! `g_n = g₀ + [[u_n]]` (g₀ the initial gap, 0 for touching faces), D̂ = 0 (bonded)
//! when the pair is closed or in compression and D̂ = 1 (open) when it separates.
//!
//! Four laws (per interface):
//! - `rigid`: always bonded (mesh tying);
//! - `contact` (the seed's): bonded (stick in both directions) or open; secant,
//!   so a pair that closes again after sliding while open snaps back tangentially;
//! - `frictionless`: closed (state `bonded`: normal penalty only, tangential
//!   force zero) or open;
//! - `coulomb` with friction coefficient μ: stick (state `bonded`:
//!   `f_s = c_s ([[u_s]] − s_p)`, s_p the plastic slip carried from increment to
//!   increment), slip (`f_s = μ |f_n|` along the trial force
//!   `c_s ([[u_s]] − s_p)`, a constant of the pair's [`PairHistory`] iterated to a
//!   fixed point, so the stiffness stays symmetric) or open.
//!
//! While the fixed point runs, a slipping pair also keeps a small tangential
//! stiffness `c_slip` (see [`SLIP_STIFFNESS`]) anchored at its previous iterate's
//! jump: `f_s = μ |f_n| + c_slip ([[u_s]] − u_anchor)`. The spring's force vanishes
//! at the fixed point (the anchor is the jump), so the converged answer is the
//! law's; on the way it keeps the stiffness nonsingular when every pair holding a
//! part slips (friction then holds it, as it does physically).
//!
//! State diagram (a transition is taken after a solve when the law is broken;
//! `tol` are the law tolerances, so a pair at the boundary does not flip back and
//! forth on round-off):
//! ```text
//! open ──(penetrates: g_n < −tol)──▶ bonded (stick)
//! bonded ──(pulls: f_n > tol)──▶ open
//! bonded ──(coulomb: |c_s([[u_s]] − s_p)| > μ|f_n| + tol)──▶ slip
//! slip ──(coulomb: |c_s([[u_s]] − s_p)| < μ|f_n| − tol: inside the cone)──▶ bonded
//! slip ──(pulls: f_n > tol)──▶ open
//! ```
//!
//! The law reaches the dimension through [`Dim`]: the tangential jump, force,
//! slip and multiplier are its tangent ([`Tangent`], one component in 2D, two in
//! 3D), the cone is round and the return map radial, so one text serves both.

use crate::dim::{D2, Dim, Tangent};

pub use crate::domain::{Enforcement, Law};

impl std::fmt::Display for PairState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The states of every pair of a model: `states[i][k]` for pair k of interface i.
pub type PairStates = Vec<Vec<PairState>>;

/// The state of one coupling pair (serialized as `bonded`, `open` or `slip`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PairState {
    /// D̂ = 0: closed; no penetration, and (except for the frictionless law) no
    /// elastic slip beyond the tangential penalty (stick).
    Bonded,
    /// D̂ = 1: no force.
    Open,
    /// Coulomb law only: closed and slipping; the normal penalty acts, the
    /// tangential force is μ |f_n| along the trial force.
    Slip,
}

impl PairState {
    /// The damage-like variable D̂ of the normal law: 0 closed (bonded or slip),
    /// 1 open.
    pub fn d_hat(self) -> f64 {
        match self {
            PairState::Bonded | PairState::Slip => 0.0,
            PairState::Open => 1.0,
        }
    }

    /// Whether the pair is closed (bonded or slipping): it carries a normal force.
    pub fn is_closed(self) -> bool {
        self != PairState::Open
    }

    /// Lower-case name used in tables (`bonded`, `open`, `slip`).
    pub fn as_str(self) -> &'static str {
        match self {
            PairState::Bonded => "bonded",
            PairState::Open => "open",
            PairState::Slip => "slip",
        }
    }
}

/// The law of one interface with its parameters: what a pair's force and stiffness
/// follow from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawParams {
    /// The law.
    pub law: Law,
    /// Normal penalty c_n.
    pub c_n: f64,
    /// Tangential penalty c_s (ignored by the frictionless law).
    pub c_s: f64,
    /// Friction coefficient μ (Coulomb law; 0 otherwise).
    pub friction: f64,
    /// Tangential stiffness a slipping pair keeps while its slip force is iterated
    /// (Coulomb law; 0 otherwise): see [`SLIP_STIFFNESS`].
    pub c_slip: f64,
}

/// The stabilising tangential stiffness of a slipping Coulomb pair, as a fraction
/// of the softer part's E·t (the stiffness of the body behind a coupling node is of
/// the order of E·t). A part held only by slipping pairs keeps a nonsingular
/// stiffness (its sliding mode is held by the springs of all its pairs); the
/// springs are anchored at the previous fixed-point iterate, so they carry no
/// force once it converges. Small, so they barely slow the fixed point of the
/// modes the body holds (a plate's stretching along a face of a thousand pairs is
/// still far stiffer than their springs together); the sliding drift they let
/// through is what the Anderson acceleration of the fixed point removes.
pub const SLIP_STIFFNESS: f64 = 1e-3;

/// What a pair's force depends on besides its jump: the plastic slip carried
/// between increments (Coulomb), the tangential force of a slipping pair (iterated
/// to a fixed point within an increment) and the augmented-Lagrangian multipliers.
/// All zero for the penalty laws of the seed. Its tangential quantities are the
/// dimension's tangent ([`Dim::Tangent`]: one component along s in 2D, two in the
/// face plane in 3D).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(bound = "")]
pub struct PairHistory<D: Dim = D2> {
    /// Plastic slip s_p (tangential, length): the stick force is `c_s ([[u_s]] − s_p)`.
    pub slip: D::Tangent,
    /// Tangential force of a slipping pair, `μ |f_n|` along the trial force.
    pub slip_force: D::Tangent,
    /// The tangential jump a slipping pair's stabilising spring (`c_slip`) is
    /// anchored at: the jump of the previous fixed-point iterate.
    pub anchor: D::Tangent,
    /// Multipliers (normal, tangential) added to the penalty forces of a closed pair
    /// (augmented Lagrangian).
    pub multiplier: (f64, D::Tangent),
}

/// The histories of every pair of a model: `h[i][k]` for pair k of interface i.
pub type PairHistories<D = D2> = Vec<Vec<PairHistory<D>>>;

/// `a + b`, but exactly `a` when `b` is zero (so the seed's laws keep their bits,
/// the sign of a zero included).
fn plus(a: f64, b: f64) -> f64 {
    if b == 0.0 { a } else { a + b }
}

/// [`plus`] on each component of two tangents.
fn plus_t<T: Tangent>(a: T, b: T) -> T {
    a.zip_each(b, plus)
}

impl LawParams {
    /// The penalties (normal, tangential) that act in the stiffness of a pair in
    /// `state`: both when bonded (the tangential one zero for the frictionless law),
    /// the normal one and the stabilising `c_slip` when slipping, none when open.
    pub fn penalties(&self, state: PairState) -> [f64; 2] {
        match state {
            PairState::Open => [0.0, 0.0],
            PairState::Bonded if self.law == Law::Frictionless => [self.c_n, 0.0],
            PairState::Bonded => [self.c_n, self.c_s],
            PairState::Slip => [self.c_n, self.c_slip],
        }
    }

    /// The local force `f = (f_n, f_s)` (the force the host side exerts on the pair)
    /// for the normal gap `g_n` (`g₀ + [[u_n]]`) and the tangential jump `u_s`:
    /// bonded `(c_n g_n, c_s (u_s − s_p))` (tangential 0 when frictionless), slip
    /// `(c_n g_n, slip_force + c_slip (u_s − anchor))`, open 0; plus the
    /// multipliers when closed. In any dimension (`f_s`, `u_s` tangents).
    pub fn local_force<D: Dim>(
        &self,
        state: PairState,
        g_n: f64,
        u_s: D::Tangent,
        h: &PairHistory<D>,
    ) -> (f64, D::Tangent) {
        let m_n = h.multiplier.0;
        let zero = D::Tangent::default();
        match state {
            PairState::Open => (0.0, zero),
            PairState::Bonded if self.law == Law::Frictionless => {
                (plus(self.c_n * g_n, m_n), zero)
            }
            PairState::Bonded => (plus(self.c_n * g_n, m_n), self.trial_shear(u_s, h)),
            PairState::Slip => (
                plus(self.c_n * g_n, m_n),
                plus_t(h.slip_force, u_s.sub(h.anchor).scale(self.c_slip)),
            ),
        }
    }

    /// The radius of the Coulomb cone at normal force `f_n` (negative in
    /// compression): `μ max(−f_n, 0)`, the largest tangential force a closed pair
    /// carries while it sticks (0 for a pair in tension). The one home of the cone.
    pub fn cone(&self, f_n: f64) -> f64 {
        self.friction * (-f_n).max(0.0)
    }

    /// The trial tangential force of a closed pair, `c_s (u_s − s_p) + m_s`: what it
    /// would carry if it stuck.
    pub fn trial_shear<D: Dim>(&self, u_s: D::Tangent, h: &PairHistory<D>) -> D::Tangent {
        let elastic = u_s.zip_each(h.slip, |u, s| plus(u, -s)).scale(self.c_s);
        plus_t(elastic, h.multiplier.1)
    }

    /// The Coulomb check of a closed pair (after the normal check): its state
    /// next, and how it breaks the friction law if it does. `f_n` is the normal force
    /// (negative in compression), `u_s` the tangential jump, `f_s` the tangential
    /// force it carries, `tol` the force tolerance. A stick pair whose trial force
    /// exceeds μ|f_n| slips; a slip pair whose trial force falls inside the cone
    /// sticks; a slip pair whose force differs from μ|f_n| along the trial force
    /// breaks the law but keeps its state (an unconverged fixed point, or a slip
    /// that reverses: a trial force turned against the slip force beyond the cone
    /// slips the other way — the return map). A violation's amount is the distance
    /// of the pair's force from the law's: the trial force inside the cone, μ|f_n|
    /// along the trial force beyond it (at most 2 μ|f_n| for a reversing pair).
    /// In any dimension: the cone is round (the tangent's length), the map radial.
    pub fn friction_check<D: Dim>(
        &self,
        state: PairState,
        f_n: f64,
        u_s: D::Tangent,
        f_s: D::Tangent,
        h: &PairHistory<D>,
        tol: f64,
    ) -> (PairState, Option<LawViolation>) {
        if self.law != Law::Coulomb || !state.is_closed() {
            return (state, None);
        }
        let limit = self.cone(f_n);
        let trial = self.trial_shear(u_s, h);
        match state {
            PairState::Bonded if trial.norm() > limit + tol => {
                let excess = trial.norm() - limit;
                (
                    PairState::Slip,
                    Some(LawViolation {
                        kind: ViolationKind::Friction,
                        amount: excess,
                        force: excess,
                    }),
                )
            }
            PairState::Slip if trial.norm() < limit - tol => {
                // The law's force is the trial force itself.
                let excess = if trial.dot(f_s) < 0.0 {
                    trial.sub(f_s).norm()
                } else {
                    limit - trial.norm()
                };
                (
                    PairState::Bonded,
                    Some(LawViolation {
                        kind: ViolationKind::Slip,
                        amount: excess,
                        force: excess,
                    }),
                )
            }
            PairState::Slip => {
                let error = f_s.sub(return_map(trial, limit)).norm();
                let v = (error > tol).then_some(LawViolation {
                    kind: ViolationKind::Slip,
                    amount: error,
                    force: error,
                });
                (state, v)
            }
            _ => (state, None),
        }
    }
}

/// How a pair breaks its law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ViolationKind {
    /// A bonded pair pulls: the law says it should be open.
    Tension,
    /// An open pair interpenetrates: the law says it should be bonded.
    Penetration,
    /// A stick pair carries more than μ |f_n| (Coulomb): it should slip.
    Friction,
    /// A slip pair whose force is not μ |f_n| opposing its slip (Coulomb): its
    /// trial force is inside the cone (it should stick) or its slip force has not
    /// converged.
    Slip,
}

impl ViolationKind {
    /// Lower-case name used in tables (`tension`, `penetration`, `friction`, `slip`).
    pub fn as_str(self) -> &'static str {
        match self {
            ViolationKind::Tension => "tension",
            ViolationKind::Penetration => "penetration",
            ViolationKind::Friction => "friction",
            ViolationKind::Slip => "slip",
        }
    }
}

/// The thresholds below which a pair is taken to satisfy its law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawTolerance {
    /// Largest tensile normal force a bonded pair may carry (force).
    pub tension: f64,
    /// Largest interpenetration `−g_n` an open pair may show (length).
    pub penetration: f64,
}

/// A pair's departure from its law: the kind, the amount (a force for
/// [`ViolationKind::Tension`] and the friction kinds, a length for
/// [`ViolationKind::Penetration`]) and the amount as a force (`c_n` × the
/// penetration for an open pair), which ranks violations of all kinds on one scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawViolation {
    /// Tension, penetration, friction or slip.
    pub kind: ViolationKind,
    /// Tensile force, penetration depth, or friction force error.
    pub amount: f64,
    /// The amount as a force.
    pub force: f64,
}

impl LawParams {
    /// Checks a pair in `state` against the normal law, with normal gap `gap_n`
    /// (g₀ + \[\[u_n\]\]) and normal force `f_n` (`c_n gap_n`, plus the
    /// augmented-Lagrangian multiplier): a closed pair (bonded or slip) may not pull
    /// (`f_n` above `tol.tension`), an open pair may not interpenetrate (`−gap_n`
    /// above `tol.penetration`; as a force, `c_n` × the depth). A rigid interface
    /// has no unilateral law and is never in violation.
    pub fn normal_violation(
        &self,
        state: PairState,
        gap_n: f64,
        f_n: f64,
        tol: LawTolerance,
    ) -> Option<LawViolation> {
        if self.law == Law::Rigid {
            return None;
        }
        match state {
            PairState::Bonded | PairState::Slip if f_n > tol.tension => Some(LawViolation {
                kind: ViolationKind::Tension,
                amount: f_n,
                force: f_n,
            }),
            PairState::Open if -gap_n > tol.penetration => Some(LawViolation {
                kind: ViolationKind::Penetration,
                amount: -gap_n,
                force: -self.c_n * gap_n,
            }),
            _ => None,
        }
    }

    /// The transition of one pair (the active-set update; see the state diagram
    /// above): the state the law gives a pair now in `state` with normal gap
    /// `gap_n`, local force `f = (f_n, f_s)` (as [`LawParams::local_force`] gives
    /// it), tangential jump `u_s` and history `h`, and how the pair breaks the law.
    /// A closed pair in tension opens, an open pair that interpenetrates closes
    /// (bonded: stick) — but a stick pair that pulls and exceeds its cone slips
    /// first (its tension may come from the shear it cannot carry); then the
    /// Coulomb check ([`LawParams::friction_check`]). Every other pair keeps its
    /// state, so a pair within the tolerances of a boundary between two states does
    /// not flip back and forth on round-off. A rigid pair is always bonded.
    /// In any dimension (`f = (f_n, f_s)`, `f_s` and `u_s` tangents).
    pub fn next_state<D: Dim>(
        &self,
        state: PairState,
        gap_n: f64,
        f: (f64, D::Tangent),
        u_s: D::Tangent,
        h: &PairHistory<D>,
        tol: LawTolerance,
    ) -> Transition {
        if self.law == Law::Rigid {
            return Transition {
                next: PairState::Bonded,
                normal: None,
                friction: None,
            };
        }
        if let Some(v) = self.normal_violation(state, gap_n, f.0, tol) {
            if state == PairState::Bonded
                && let (PairState::Slip, Some(fv)) =
                    self.friction_check(state, f.0, u_s, f.1, h, tol.tension)
            {
                return Transition {
                    next: PairState::Slip,
                    normal: Some(v),
                    friction: Some(fv),
                };
            }
            let next = match state {
                PairState::Open => PairState::Bonded,
                _ => PairState::Open,
            };
            return Transition {
                next,
                normal: Some(v),
                friction: None,
            };
        }
        let (next, friction) = self.friction_check(state, f.0, u_s, f.1, h, tol.tension);
        Transition {
            next,
            normal: None,
            friction,
        }
    }
}

/// What the law makes of one pair after a solve ([`LawParams::next_state`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transition {
    /// The state the pair takes next.
    pub next: PairState,
    /// How it breaks the normal law (tension or penetration), if it does.
    pub normal: Option<LawViolation>,
    /// How it breaks the friction law (friction or slip), if it does.
    pub friction: Option<LawViolation>,
}

impl Transition {
    /// The violations, the normal one first.
    pub fn violations(&self) -> impl Iterator<Item = LawViolation> {
        self.normal.into_iter().chain(self.friction)
    }
}

/// The Coulomb return map of a pair beyond its cone: the slip force the trial
/// force `trial` returns to on a cone of radius `limit` — radially, `limit` along
/// the trial force, `limit · trial / |trial|` ([`Tangent::direction`]; in 2D the
/// trial force's sign, exactly, so `limit · sign(trial)` to the bit). A trial force
/// turned against a pair's slip force beyond the cone so slips the other way. One
/// formula for every dimension; it commutes with a rotation of the tangent plane,
/// so no result depends on the choice of the tangents in 3D.
pub fn return_map<T: Tangent>(trial: T, limit: f64) -> T {
    trial.direction().scale(limit)
}

/// Local interface force `f = (1 − D̂) c [[u]]` for the local jump `[[u_n]], [[u_s]]`
/// (the seed's laws without history: bonded or open).
pub fn local_force(state: PairState, c_n: f64, c_s: f64, jump: [f64; 2]) -> [f64; 2] {
    let k = 1.0 - state.d_hat();
    [k * c_n * jump[0], k * c_s * jump[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An open pair carries no force and a bonded one carries c·[[u]].
    #[test]
    fn forces() {
        assert_eq!(
            local_force(PairState::Open, 1e9, 1e9, [1.0, 2.0]),
            [0.0, 0.0]
        );
        assert_eq!(
            local_force(PairState::Bonded, 2.0, 3.0, [1.0, 2.0]),
            [2.0, 6.0]
        );
    }

    /// The law check: a bonded pair pulling beyond the force tolerance and an open
    /// pair penetrating beyond the length tolerance violate the contact law, and
    /// the active-set update flips exactly those; pairs inside the tolerances keep
    /// their state; a rigid interface never violates.
    #[test]
    fn violations_and_next_state() {
        let tol = LawTolerance {
            tension: 1e-3,
            penetration: 1e-9,
        };
        let c = 1e6;
        let params = |law| LawParams {
            law,
            c_n: c,
            c_s: 0.0,
            friction: 0.0,
            c_slip: 0.0,
        };
        let zero: PairHistory = PairHistory::default();
        // The normal law and the transition of a pair with normal force c_n g_n.
        let violation = |law, state, gap: f64| params(law).normal_violation(state, gap, c * gap, tol);
        let next_state = |law, state, gap: f64| {
            params(law)
                .next_state(state, gap, (c * gap, 0.0), 0.0, &zero, tol)
                .next
        };
        // Bonded, gap 2e-9: tension 2e-3 > 1e-3.
        let v = violation(Law::Contact, PairState::Bonded, 2e-9)
            .unwrap();
        assert_eq!(v.kind, ViolationKind::Tension);
        assert!((v.amount - 2e-3).abs() < 1e-15 && v.force == v.amount);
        assert_eq!(
            next_state(Law::Contact, PairState::Bonded, 2e-9),
            PairState::Open
        );
        // Bonded, gap 0.5e-9: tension 0.5e-3, within tolerance; compression is fine.
        assert!(
            violation(Law::Contact, PairState::Bonded, 0.5e-9)
                .is_none()
        );
        assert!(
            violation(Law::Contact, PairState::Bonded, -1.0)
                .is_none()
        );
        assert_eq!(
            next_state(Law::Contact, PairState::Bonded, 0.5e-9),
            PairState::Bonded
        );
        // Open, penetrating 3e-9 > 1e-9: closes; force measure c × 3e-9.
        let v = violation(Law::Contact, PairState::Open, -3e-9)
            .unwrap();
        assert_eq!(v.kind, ViolationKind::Penetration);
        assert!((v.amount - 3e-9).abs() < 1e-20 && (v.force - 3e-3).abs() < 1e-15);
        assert_eq!(
            next_state(Law::Contact, PairState::Open, -3e-9),
            PairState::Bonded
        );
        // Open and touching within the tolerance, or apart: stays open.
        assert_eq!(
            next_state(Law::Contact, PairState::Open, -0.5e-9),
            PairState::Open
        );
        assert_eq!(
            next_state(Law::Contact, PairState::Open, 1.0),
            PairState::Open
        );
        // Rigid: never in violation, always bonded.
        assert!(
            violation(Law::Rigid, PairState::Bonded, 1.0)
                .is_none()
        );
        assert_eq!(
            next_state(Law::Rigid, PairState::Bonded, 1.0),
            PairState::Bonded
        );
    }

    /// The laws' penalties and forces: frictionless pairs have no tangential
    /// stiffness, slip pairs only the stabilising one, a stick pair's shear is measured from its plastic slip,
    /// a slip pair carries its slip force, multipliers add to closed pairs' forces;
    /// the seed's laws with a zero history give exactly the seed's forces.
    #[test]
    fn law_params_forces() {
        let p = |law, friction| LawParams {
            law,
            c_n: 10.0,
            c_s: 4.0,
            friction,
            c_slip: if law == Law::Coulomb { 0.5 } else { 0.0 },
        };
        let h: PairHistory = PairHistory {
            slip: 0.5,
            slip_force: -1.5,
            anchor: 1.0,
            multiplier: (0.0, 0.0),
        };
        let zero: PairHistory = PairHistory::default();
        assert_eq!(
            p(Law::Frictionless, 0.0).penalties(PairState::Bonded),
            [10.0, 0.0]
        );
        assert_eq!(p(Law::Coulomb, 0.3).penalties(PairState::Slip), [10.0, 0.5]);
        assert_eq!(
            p(Law::Coulomb, 0.3).penalties(PairState::Bonded),
            [10.0, 4.0]
        );
        assert_eq!(p(Law::Contact, 0.0).penalties(PairState::Open), [0.0, 0.0]);
        let c = p(Law::Contact, 0.0);
        for (g, u) in [(-0.3, 0.7), (0.2, -1.1), (-0.0, 0.0)] {
            let seed = local_force(PairState::Bonded, 10.0, 4.0, [g, u]);
            let now = c.local_force(PairState::Bonded, g, u, &zero);
            assert_eq!(seed.map(f64::to_bits), [now.0, now.1].map(f64::to_bits));
        }
        assert_eq!(
            p(Law::Frictionless, 0.0).local_force(PairState::Bonded, -0.1, 3.0, &h),
            (-1.0, 0.0)
        );
        let coulomb = p(Law::Coulomb, 0.3);
        assert_eq!(
            coulomb.local_force(PairState::Bonded, -0.1, 1.0, &h),
            (-1.0, 2.0)
        );
        // At its anchor a slip pair carries its slip force; away from it, the
        // stabilising spring's force adds.
        assert_eq!(
            coulomb.local_force(PairState::Slip, -0.1, 1.0, &h),
            (-1.0, -1.5)
        );
        assert_eq!(
            coulomb.local_force(PairState::Slip, -0.1, 3.0, &h),
            (-1.0, -0.5)
        );
        let m: PairHistory = PairHistory {
            multiplier: (-2.0, 0.25),
            ..h
        };
        assert_eq!(
            coulomb.local_force(PairState::Bonded, -0.1, 1.0, &m),
            (-3.0, 2.25)
        );
        assert_eq!(
            coulomb.local_force(PairState::Open, -0.1, 1.0, &m),
            (0.0, 0.0)
        );
    }

    /// The Coulomb return mapping: a stick pair whose trial force exceeds μ|f_n|
    /// slips, one inside stays; a slip pair whose trial force falls inside the cone
    /// sticks; a slip pair on the cone along its trial force satisfies the law, off
    /// it by more than the tolerance it breaks it — a trial force reversed beyond
    /// the cone included, which keeps slipping the other way (Simo & Hughes,
    /// *Computational Inelasticity*, 1998, §2.2: the return map of one-dimensional
    /// rate-independent plasticity).
    #[test]
    fn friction_return_mapping() {
        let law = LawParams {
            law: Law::Coulomb,
            c_n: 10.0,
            c_s: 4.0,
            friction: 0.5,
            c_slip: 0.4,
        };
        let h: PairHistory = PairHistory::default();
        let tol = 1e-9;
        // f_n = −2 (compression): the cone is 1.
        let (next, v) = law.friction_check(PairState::Bonded, -2.0, 0.3, 1.2, &h, tol);
        assert_eq!(next, PairState::Slip);
        assert_eq!(v.unwrap().kind, ViolationKind::Friction);
        let (next, v) = law.friction_check(PairState::Bonded, -2.0, 0.2, 0.8, &h, tol);
        assert_eq!((next, v), (PairState::Bonded, None));
        // Slip along +s with trial 1.2 > 1 and force 1: consistent.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, 0.3, 1.0, &h, tol);
        assert_eq!((next, v), (PairState::Slip, None));
        // Slip force off the cone: a violation, state kept.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, 0.3, 0.9, &h, tol);
        assert_eq!(next, PairState::Slip);
        assert_eq!(v.unwrap().kind, ViolationKind::Slip);
        // Trial inside the cone: sticks, off by the room left in the cone.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, 0.2, 1.0, &h, tol);
        assert_eq!(next, PairState::Bonded);
        assert!((v.unwrap().amount - 0.2).abs() < 1e-12);
        // Trial reversed beyond the cone (−1.2): slips the other way; its force
        // (+1, the old direction) is off by 2 μ|f_n| from −1, state kept.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, -0.3, 1.0, &h, tol);
        assert_eq!(next, PairState::Slip);
        let v = v.unwrap();
        assert_eq!(v.kind, ViolationKind::Slip);
        assert!((v.amount - 2.0).abs() < 1e-12);
        // Reversed and converged (force −1 along the new trial): consistent.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, -0.3, -1.0, &h, tol);
        assert_eq!((next, v), (PairState::Slip, None));
        // Reversed inside the cone (trial −0.4): sticks, carrying the trial force.
        let (next, v) = law.friction_check(PairState::Slip, -2.0, -0.1, 1.0, &h, tol);
        assert_eq!(next, PairState::Bonded);
        assert!((v.unwrap().amount - 1.4).abs() < 1e-12);
        // Reversed at a pair without normal force (cone 0, a lifted end): a pair
        // carrying 1e-3 is off by 1e-3 whatever the trial force's size.
        let (next, v) = law.friction_check(PairState::Slip, 0.0, -300.0, 1e-3, &h, tol);
        assert_eq!(next, PairState::Slip);
        assert!((v.unwrap().amount - 1e-3).abs() < 1e-15);
        // Other laws have no friction check.
        let contact = LawParams {
            law: Law::Contact,
            ..law
        };
        let (next, v) = contact.friction_check(PairState::Bonded, -2.0, 9.0, 36.0, &h, tol);
        assert_eq!((next, v), (PairState::Bonded, None));
    }

    fn coulomb(friction: f64) -> LawParams {
        LawParams {
            law: Law::Coulomb,
            c_n: 10.0,
            c_s: 4.0,
            friction,
            c_slip: 0.4,
        }
    }

    const TOL: LawTolerance = LawTolerance {
        tension: 1e-3,
        penetration: 1e-6,
    };

    /// The cone is μ max(−f_n, 0): μ × the compression, and zero for a pair without
    /// compression (in tension or just touching) whatever μ.
    #[test]
    fn cone_is_mu_times_the_compression() {
        assert_eq!(coulomb(0.5).cone(-3.0), 1.5);
        assert_eq!(coulomb(0.5).cone(2.0), 0.0);
        assert_eq!(coulomb(0.5).cone(0.0), 0.0);
        assert_eq!(coulomb(0.0).cone(-3.0), 0.0);
    }

    /// The return map sends a trial force beyond the cone back onto it along
    /// itself: magnitude the cone's radius, direction the trial force's (either
    /// way), zero on a cone of radius zero.
    #[test]
    fn return_map_direction_and_magnitude() {
        assert_eq!(return_map(7.0, 2.0), 2.0);
        assert_eq!(return_map(-7.0, 2.0), -2.0);
        assert_eq!(return_map(-7.0, 0.0), 0.0);
    }

    /// In 2D (one tangent component) the radial return map `limit · t / |t|` is
    /// the sign rule `limit · sign(t)` bit for bit — for trial forces of every
    /// magnitude, subnormal and huge ones included, and for the two signed zeros
    /// (whose sign bit sets the direction) — so the dimension-generic law changed
    /// no 2D result.
    #[test]
    fn return_map_in_2d_is_the_sign_rule_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut trials = vec![0.0, -0.0, 1e-310, -1e-310, 49.0, -3.0, 1e300, -7.0e-5];
        let mut limits = vec![0.0, 1.0, 0.3, 2.5e7, 1e-12];
        for _ in 0..2000 {
            // Random finite doubles of every exponent, then positive limits.
            let t = f64::from_bits(next() & !(0x7ff << 52) | ((next() % 0x7fe) << 52));
            trials.push(t);
            limits.push(t.abs());
        }
        for &t in &trials {
            for &l in &limits {
                let sign_rule = l * t.signum();
                assert_eq!(return_map(t, l).to_bits(), sign_rule.to_bits(), "{t} {l}");
            }
        }
    }

    /// The radial return map and the Coulomb check on a two-component tangent
    /// (the 3D shape, through the generic law with a test dimension): the map
    /// sends a trial force beyond the cone to radius μ|f_n| along itself, and
    /// rotating the tangent pair (trial, jump, slip, force and multiplier turned
    /// together) rotates the slip force and leaves the states and the violation
    /// amounts unchanged (to round-off): no result depends on the choice of the
    /// tangents.
    #[test]
    fn return_map_and_friction_check_invariant_under_rotating_the_tangents() {
        use crate::dim::PlaneTangent;
        let law = coulomb(0.5);
        let rot = |a: f64, v: [f64; 2]| {
            let (c, s) = (a.cos(), a.sin());
            [c * v[0] - s * v[1], s * v[0] + c * v[1]]
        };
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-13;
        let trial = [0.9, -1.2];
        let mapped = return_map(trial, 1.0);
        assert!((mapped.norm() - 1.0).abs() < 1e-15);
        assert!(close(mapped, [0.6, -0.8]));
        let h: PairHistory<PlaneTangent> = PairHistory {
            slip: [0.01, 0.02],
            slip_force: [0.6, -0.8],
            anchor: [0.3, -0.1],
            multiplier: (-0.1, [0.05, -0.02]),
        };
        // f_n = −2: the cone is 1. Jumps inside and beyond it, slip forces on and
        // off it.
        let cases = [
            (PairState::Bonded, [0.3, -0.25], [1.2, -1.0]),
            (PairState::Bonded, [0.1, -0.05], [0.4, -0.2]),
            (PairState::Slip, [0.3, -0.25], [0.6, -0.8]),
            (PairState::Slip, [0.3, -0.25], [0.1, 0.3]),
            (PairState::Slip, [0.05, 0.0], [0.6, -0.8]),
            (PairState::Slip, [-0.3, 0.25], [0.6, -0.8]),
        ];
        for a in [0.0, 0.7, 2.0, -2.9] {
            let turned: PairHistory<PlaneTangent> = PairHistory {
                slip: rot(a, h.slip),
                slip_force: rot(a, h.slip_force),
                anchor: rot(a, h.anchor),
                multiplier: (h.multiplier.0, rot(a, h.multiplier.1)),
            };
            assert!(close(return_map(rot(a, trial), 1.0), rot(a, mapped)));
            for (state, u_s, f_s) in cases {
                let (next0, v0) = law.friction_check(state, -2.0, u_s, f_s, &h, 1e-9);
                let (next, v) =
                    law.friction_check(state, -2.0, rot(a, u_s), rot(a, f_s), &turned, 1e-9);
                assert_eq!(next, next0, "{state:?} {u_s:?} at {a}");
                assert_eq!(v.map(|v| v.kind), v0.map(|v| v.kind));
                if let (Some(v), Some(v0)) = (v, v0) {
                    assert!((v.amount - v0.amount).abs() < 1e-13, "{v:?} {v0:?}");
                }
                let f0 = law.local_force(state, -0.2, u_s, &h);
                let f = law.local_force(state, -0.2, rot(a, u_s), &turned);
                assert!((f.0 - f0.0).abs() < 1e-15 && close(f.1, rot(a, f0.1)));
            }
        }
    }

    /// Stick ↔ slip: a stick pair slips when its trial force leaves the cone by more
    /// than the tolerance, a slip pair sticks when its trial force is inside the
    /// cone by more than it; within the tolerance of the cone either keeps its
    /// state (the dead band), and a slip pair exactly on the cone breaks nothing.
    #[test]
    fn stick_slip_transitions_and_dead_band() {
        let law = coulomb(0.5);
        let h: PairHistory = PairHistory::default();
        // f_n = −2: the cone is 1; the trial force is c_s u_s = 4 u_s.
        let at = |state, u_s: f64, f_s: f64| law.next_state(state, -0.2, (-2.0, f_s), u_s, &h, TOL);
        let t = at(PairState::Bonded, 0.3, 1.2);
        assert_eq!(t.next, PairState::Slip);
        assert_eq!(t.normal, None);
        let v = t.friction.unwrap();
        assert_eq!(v.kind, ViolationKind::Friction);
        assert!((v.amount - 0.2).abs() < 1e-12 && v.force == v.amount);
        // Beyond the cone by half the tolerance: still sticks, no violation.
        let u = (1.0 + 0.5e-3) / 4.0;
        assert_eq!(at(PairState::Bonded, u, 4.0 * u), Transition {
            next: PairState::Bonded,
            normal: None,
            friction: None,
        });
        // A slip pair on the cone, its force μ|f_n| along the trial force: consistent.
        assert_eq!(at(PairState::Slip, 0.3, 1.0).violations().count(), 0);
        assert_eq!(at(PairState::Slip, 0.3, 1.0).next, PairState::Slip);
        // Inside the cone by half the tolerance: stays slipping (its force is μ|f_n|).
        let u = (1.0 - 0.5e-3) / 4.0;
        assert_eq!(at(PairState::Slip, u, 1.0).next, PairState::Slip);
        // Inside by more: sticks, off the law by the room left in the cone.
        let t = at(PairState::Slip, 0.2, 1.0);
        assert_eq!(t.next, PairState::Bonded);
        let v = t.friction.unwrap();
        assert_eq!(v.kind, ViolationKind::Slip);
        assert!((v.amount - 0.2).abs() < 1e-12);
    }

    /// Bonded ↔ open with friction: a closed pair (stick or slip) that pulls opens
    /// with a tension violation of its normal force; an open pair that penetrates
    /// beyond the tolerance closes as stick (bonded) with a penetration violation of
    /// its depth (c_n × depth as a force); within the tolerances nothing flips.
    #[test]
    fn bonded_open_transitions() {
        let law = coulomb(0.5);
        let h: PairHistory = PairHistory::default();
        let t = law.next_state(PairState::Slip, 0.2, (2.0, 0.0), 0.0, &h, TOL);
        assert_eq!(t.next, PairState::Open);
        assert_eq!(t.normal.unwrap().kind, ViolationKind::Tension);
        assert_eq!(t.normal.unwrap().amount, 2.0);
        assert_eq!(t.friction, None);
        let t = law.next_state(PairState::Bonded, 0.2, (2.0, 0.0), 0.0, &h, TOL);
        assert_eq!(t.next, PairState::Open);
        let t = law.next_state(PairState::Open, -1e-5, (0.0, 0.0), 3.0, &h, TOL);
        assert_eq!(t.next, PairState::Bonded);
        let v = t.normal.unwrap();
        assert_eq!(v.kind, ViolationKind::Penetration);
        assert_eq!(v.amount, 1e-5);
        assert!((v.force - 1e-4).abs() < 1e-18);
        // Within the tolerances: a touching open pair, a closed one barely pulling.
        let t = law.next_state(PairState::Open, -0.5e-6, (0.0, 0.0), 3.0, &h, TOL);
        assert_eq!((t.next, t.violations().count()), (PairState::Open, 0));
        let t = law.next_state(PairState::Bonded, 0.5e-4, (0.5e-3, 0.0), 0.0, &h, TOL);
        assert_eq!((t.next, t.violations().count()), (PairState::Bonded, 0));
    }

    /// A stick pair that both pulls and carries a tangential force beyond its
    /// (zero) cone slips rather than opens, reporting both violations, the tension
    /// first: its tension may come from the shear it cannot carry.
    #[test]
    fn a_pulling_stick_pair_beyond_its_cone_slips_first() {
        let law = coulomb(0.5);
        let h: PairHistory = PairHistory::default();
        let t = law.next_state(PairState::Bonded, 0.2, (2.0, 1.2), 0.3, &h, TOL);
        assert_eq!(t.next, PairState::Slip);
        let kinds: Vec<_> = t.violations().map(|v| v.kind).collect();
        assert_eq!(kinds, [ViolationKind::Tension, ViolationKind::Friction]);
        // Without tangential force it opens.
        let t = law.next_state(PairState::Bonded, 0.2, (2.0, 0.0), 0.0, &h, TOL);
        assert_eq!(t.next, PairState::Open);
    }

    /// Frictionless pairs never slip, whatever their tangential jump; the contact
    /// law's pairs neither (they stick); a rigid pair stays bonded even pulling or
    /// reported open, and breaks nothing.
    #[test]
    fn frictionless_contact_and_rigid_never_slip_and_rigid_never_opens() {
        let h: PairHistory = PairHistory::default();
        for law in [Law::Frictionless, Law::Contact] {
            let p = LawParams {
                law,
                ..coulomb(0.0)
            };
            let t = p.next_state(PairState::Bonded, -0.2, (-2.0, 40.0), 10.0, &h, TOL);
            assert_eq!((t.next, t.violations().count()), (PairState::Bonded, 0));
        }
        let rigid = LawParams {
            law: Law::Rigid,
            ..coulomb(0.0)
        };
        for state in [PairState::Bonded, PairState::Open] {
            let t = rigid.next_state(state, 5.0, (50.0, 40.0), 10.0, &h, TOL);
            assert_eq!((t.next, t.violations().count()), (PairState::Bonded, 0));
        }
        assert_eq!(rigid.normal_violation(PairState::Open, -5.0, 0.0, TOL), None);
    }
}
