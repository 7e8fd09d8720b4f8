//! The interface law of a coupling pair (SPEC §2): in the local frame (n, s),
//! `f_n = (1 − D̂) c_n [[u_n]]`, `f_s = (1 − D̂) c_s [[u_s]]`, with D̂ = 0 (bonded)
//! when the pair is closed or in compression and D̂ = 1 (open) when it separates.
//! The law is secant: the force follows from the total jump, so a pair that closes
//! again after sliding while open snaps back tangentially (no slip memory).

impl std::fmt::Display for PairState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The states of every pair of a model: `states[i][k]` for pair k of interface i.
pub type PairStates = Vec<Vec<PairState>>;

/// Which law an interface follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
    /// Tied: D̂ = 0 always (plain non-matching mesh tying).
    Rigid,
    /// Unilateral: bonded where `[[u_n]]` ≤ tolerance, open where it separates.
    Contact,
}

/// The state of one coupling pair (serialized as `bonded` or `open`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PairState {
    /// D̂ = 0: no penetration and no slip.
    Bonded,
    /// D̂ = 1: no force.
    Open,
}

impl PairState {
    /// The damage-like variable D̂ of the law: 0 bonded, 1 open.
    pub fn d_hat(self) -> f64 {
        match self {
            PairState::Bonded => 0.0,
            PairState::Open => 1.0,
        }
    }

    /// Lower-case name used in tables (`bonded`, `open`).
    pub fn as_str(self) -> &'static str {
        match self {
            PairState::Bonded => "bonded",
            PairState::Open => "open",
        }
    }
}

impl Law {
    /// Lower-case name as in the problem file (`rigid`, `contact`).
    pub fn as_str(self) -> &'static str {
        match self {
            Law::Rigid => "rigid",
            Law::Contact => "contact",
        }
    }
}

/// How a pair breaks its law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ViolationKind {
    /// A bonded pair pulls: the law says it should be open.
    Tension,
    /// An open pair interpenetrates: the law says it should be bonded.
    Penetration,
}

impl ViolationKind {
    /// Lower-case name used in tables (`tension`, `penetration`).
    pub fn as_str(self) -> &'static str {
        match self {
            ViolationKind::Tension => "tension",
            ViolationKind::Penetration => "penetration",
        }
    }
}

/// The thresholds below which a pair is taken to satisfy its law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawTolerance {
    /// Largest tensile normal force a bonded pair may carry (force).
    pub tension: f64,
    /// Largest interpenetration `−[[u_n]]` an open pair may show (length).
    pub penetration: f64,
}

/// A pair's departure from its law: the kind, the amount (a force for
/// [`ViolationKind::Tension`], a length for [`ViolationKind::Penetration`]) and the
/// amount as a force (`c_n` × the penetration for an open pair), which ranks
/// violations of both kinds on one scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawViolation {
    /// Tension or penetration.
    pub kind: ViolationKind,
    /// Tensile force, or penetration depth.
    pub amount: f64,
    /// The amount as a force.
    pub force: f64,
}

impl Law {
    /// Checks a pair in `state` with normal jump `gap_n` and normal penalty `c_n`
    /// against the law: a bonded pair may not pull (`c_n [[u_n]]` above
    /// `tol.tension`), an open pair may not interpenetrate (`−[[u_n]]` above
    /// `tol.penetration`). A rigid interface has no unilateral law and is never in
    /// violation.
    pub fn violation(
        self,
        state: PairState,
        gap_n: f64,
        c_n: f64,
        tol: LawTolerance,
    ) -> Option<LawViolation> {
        if self == Law::Rigid {
            return None;
        }
        match state {
            PairState::Bonded if c_n * gap_n > tol.tension => Some(LawViolation {
                kind: ViolationKind::Tension,
                amount: c_n * gap_n,
                force: c_n * gap_n,
            }),
            PairState::Open if -gap_n > tol.penetration => Some(LawViolation {
                kind: ViolationKind::Penetration,
                amount: -gap_n,
                force: -c_n * gap_n,
            }),
            _ => None,
        }
    }

    /// The state the law gives a pair now in `state` (the active-set update): a
    /// bonded pair in tension opens, an open pair that interpenetrates closes, and
    /// every other pair keeps its state — so a pair within the tolerances of the
    /// boundary between the two does not flip back and forth on round-off.
    pub fn next_state(
        self,
        state: PairState,
        gap_n: f64,
        c_n: f64,
        tol: LawTolerance,
    ) -> PairState {
        match (self.violation(state, gap_n, c_n, tol), state) {
            (Some(_), PairState::Bonded) => PairState::Open,
            (Some(_), PairState::Open) => PairState::Bonded,
            (None, s) => s,
        }
    }
}

/// Local interface force `f = (1 − D̂) c [[u]]` for the local jump `[[u_n]], [[u_s]]`.
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
        // Bonded, gap 2e-9: tension 2e-3 > 1e-3.
        let v = Law::Contact
            .violation(PairState::Bonded, 2e-9, c, tol)
            .unwrap();
        assert_eq!(v.kind, ViolationKind::Tension);
        assert!((v.amount - 2e-3).abs() < 1e-15 && v.force == v.amount);
        assert_eq!(
            Law::Contact.next_state(PairState::Bonded, 2e-9, c, tol),
            PairState::Open
        );
        // Bonded, gap 0.5e-9: tension 0.5e-3, within tolerance; compression is fine.
        assert!(
            Law::Contact
                .violation(PairState::Bonded, 0.5e-9, c, tol)
                .is_none()
        );
        assert!(
            Law::Contact
                .violation(PairState::Bonded, -1.0, c, tol)
                .is_none()
        );
        assert_eq!(
            Law::Contact.next_state(PairState::Bonded, 0.5e-9, c, tol),
            PairState::Bonded
        );
        // Open, penetrating 3e-9 > 1e-9: closes; force measure c × 3e-9.
        let v = Law::Contact
            .violation(PairState::Open, -3e-9, c, tol)
            .unwrap();
        assert_eq!(v.kind, ViolationKind::Penetration);
        assert!((v.amount - 3e-9).abs() < 1e-20 && (v.force - 3e-3).abs() < 1e-15);
        assert_eq!(
            Law::Contact.next_state(PairState::Open, -3e-9, c, tol),
            PairState::Bonded
        );
        // Open and touching within the tolerance, or apart: stays open.
        assert_eq!(
            Law::Contact.next_state(PairState::Open, -0.5e-9, c, tol),
            PairState::Open
        );
        assert_eq!(
            Law::Contact.next_state(PairState::Open, 1.0, c, tol),
            PairState::Open
        );
        // Rigid: never in violation, always bonded.
        assert!(
            Law::Rigid
                .violation(PairState::Bonded, 1.0, c, tol)
                .is_none()
        );
        assert_eq!(
            Law::Rigid.next_state(PairState::Bonded, 1.0, c, tol),
            PairState::Bonded
        );
    }
}
