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

    /// The state the law assigns to a normal jump `gap_n` = `[[u_n]]`: open only when
    /// the pair separates by more than `tolerance` (≥ 0). A rigid law is always bonded.
    pub fn state(self, gap_n: f64, tolerance: f64) -> PairState {
        match self {
            Law::Contact if gap_n > tolerance => PairState::Open,
            _ => PairState::Bonded,
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

    /// The contact law opens only beyond the tolerance; the rigid law never opens;
    /// an open pair carries no force and a bonded one carries c·[[u]].
    #[test]
    fn states_and_forces() {
        assert_eq!(Law::Contact.state(-1.0, 1e-9), PairState::Bonded);
        assert_eq!(Law::Contact.state(0.5e-9, 1e-9), PairState::Bonded);
        assert_eq!(Law::Contact.state(2e-9, 1e-9), PairState::Open);
        assert_eq!(Law::Rigid.state(1.0, 1e-9), PairState::Bonded);
        assert_eq!(
            local_force(PairState::Open, 1e9, 1e9, [1.0, 2.0]),
            [0.0, 0.0]
        );
        assert_eq!(
            local_force(PairState::Bonded, 2.0, 3.0, [1.0, 2.0]),
            [2.0, 6.0]
        );
    }
}
