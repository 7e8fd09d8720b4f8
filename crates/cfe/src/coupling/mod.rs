//! Coupling: the interfaces between independently meshed parts. Finds the coupling
//! pairs (each coupling node of the node part and the host element that contains it),
//! builds one coupling finite element (CFE) per pair, evaluates a pair at a
//! solution ([`Interface::pair_at`]), and is the one home of the interface law: the
//! law of one pair ([`law`]), the law checked on every pair ([`check`]) and the
//! rules of the pairs' histories ([`history`]). The contact scheme calls these; they
//! know no solver.

pub mod check;
pub mod element;
#[cfg(test)]
pub(crate) mod fixture;
pub mod history;
pub mod law;
pub(crate) mod search;
pub mod segment;

pub use check::{CheckTolerance, Verdicts, check_law};
pub use element::{CouplingElement, PairAt, SegmentSide, traction};
pub use law::{
    Enforcement, Law, LawParams, LawTolerance, LawViolation, PairHistories, PairHistory, PairState,
    PairStates, SLIP_STIFFNESS, Transition, ViolationKind, return_map,
};

/// An interface between a host part and a node part, with its coupling elements.
#[derive(Debug, Clone)]
pub struct Interface {
    /// Name used in messages and outputs.
    pub name: String,
    /// Index of the host part (usually the coarser mesh).
    pub host: usize,
    /// Index of the node part (usually the finer mesh), whose boundary nodes couple.
    pub node_part: usize,
    /// `rigid` (always bonded), `contact` (bonded in compression, open in
    /// tension), `frictionless` or `coulomb`.
    pub law: Law,
    /// Normal penalty c_n (force per length).
    pub c_n: f64,
    /// Tangential penalty c_s (force per length).
    pub c_s: f64,
    /// The stabilising tangential stiffness of a slipping pair
    /// (`SLIP_STIFFNESS` × the softer part's E·t; Coulomb law only, else 0).
    pub c_slip: f64,
    /// One coupling element per coupling node.
    pub elements: Vec<CouplingElement>,
    /// Largest distance from a coupling node to its host edge (geometric check).
    pub max_projection_distance: f64,
    /// Friction coefficient μ (`coulomb`; 0 for the other laws).
    pub friction: f64,
    /// Penalty or augmented Lagrangian.
    pub enforcement: Enforcement,
    /// Augmented Lagrangian: the largest penetration (and stick error) accepted
    /// (length).
    pub penetration_tolerance: f64,
    /// Coupling nodes of the boundary left unpaired because no host boundary edge
    /// lies within the search distance (0 without a search distance).
    pub unpaired: usize,
    /// How the coupling elements' jumps are taken: collocated at the coupling
    /// node, or averaged over its face segments.
    pub coupling: Coupling,
}

impl Interface {
    /// The law with its parameters.
    pub fn params(&self) -> LawParams {
        LawParams {
            law: self.law,
            c_n: self.c_n,
            c_s: self.c_s,
            friction: self.friction,
            c_slip: self.c_slip,
        }
    }

    /// Pair `k` evaluated at the displacements `u` (all DOFs, numbered by `dofs`)
    /// in `state` with history `h`: its element displacements gathered, its local
    /// jump, normal gap and force under the interface's law
    /// ([`CouplingElement::at`]). The one evaluation of a pair at u.
    pub fn pair_at(
        &self,
        k: usize,
        dofs: &crate::dofs::DofMap,
        u: &[f64],
        state: PairState,
        h: &PairHistory,
    ) -> PairAt {
        let c = &self.elements[k];
        let g = c.dofs(dofs, self.host, self.node_part);
        c.at(g, g.gather(u), &self.params(), state, h)
    }

    /// Whether the solution depends on the load path or is not proportional to the
    /// load factor: an initial gap on a unilateral interface, the Coulomb law, or
    /// augmented-Lagrangian enforcement.
    pub fn non_proportional(&self) -> bool {
        self.law == Law::Coulomb
            || self.enforcement == Enforcement::Augmented
            || self.elements.iter().any(|c| c.gap0 != 0.0)
    }
}

/// The DOFs of every coupling element of `interfaces`, sorted and without
/// repeats: all the displacements the pairs' jumps, forces and gaps read.
pub fn coupling_dofs(interfaces: &[Interface], dofs: &crate::dofs::DofMap) -> Vec<usize> {
    let mut all: Vec<usize> = interfaces
        .iter()
        .flat_map(|iface| {
            iface.elements.iter().flat_map(move |c| {
                c.dofs(dofs, iface.host, iface.node_part)
                    .as_slice()
                    .to_vec()
            })
        })
        .collect();
    all.sort_unstable();
    all.dedup();
    all
}

/// The coupling formulation of an interface (`coupling` in the problem file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// One CFE per coupling node, collocated at the node (the seed's, default).
    #[default]
    Node,
    /// Segment coupling: one CFE per coupling node whose jump is averaged over its
    /// face segments, integrated exactly on the face cut at the host's vertices
    /// ([`segment`]); passes the patch test on non-matching meshes.
    Segment,
}

impl Coupling {
    /// Lower-case name as in the problem file (`node`, `segment`).
    pub fn as_str(self) -> &'static str {
        match self {
            Coupling::Node => "node",
            Coupling::Segment => "segment",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::fixture;

    /// The coupling element's stiffness is the derivative of its force
    /// (central finite differences of `Interface::pair_at`'s nodal force, pmsim
    /// style): for a bonded pair of every unilateral law (the frictionless one
    /// without tangential stiffness), with an initial gap, a plastic slip and
    /// multipliers (constant terms), and for a slipping pair (its stabilising
    /// spring), on a node CFE and a segment point with weight ω, tilted normal.
    #[test]
    fn stiffness_is_the_derivative_of_the_force() {
        let h: PairHistory = PairHistory {
            slip: 0.05,
            slip_force: 0.7,
            anchor: -0.02,
            multiplier: (-0.3, 0.1),
        };
        let dofs = fixture::dofs(2);
        let u0: Vec<f64> = (0..10).map(|i| 0.01 * ((i * 7) % 5) as f64 - 0.02).collect();
        for (law, state) in [
            (Law::Contact, PairState::Bonded),
            (Law::Frictionless, PairState::Bonded),
            (Law::Coulomb, PairState::Bonded),
            (Law::Coulomb, PairState::Slip),
        ] {
            let mut iface = fixture::interface(law, 2, 0.5);
            let a: f64 = 0.4;
            iface.elements[0].normal = [a.cos(), a.sin()];
            iface.elements[0].gap0 = 0.01;
            iface.elements[1].normal = [a.cos(), a.sin()];
            iface.elements[1].segment = Some(SegmentSide {
                nodes: vec![0, 1],
                shape: vec![0.7, 0.3],
                length: 0.4,
                weight: 0.6,
            });
            for (k, c) in iface.elements.iter().enumerate() {
                let [c_n, c_s] = iface.params().penalties(state);
                let ke = c.stiffness(c_n, c_s, PairState::Bonded);
                let g = c.dofs(&dofs, iface.host, iface.node_part);
                let force = |u: &[f64]| c.nodal_force(iface.pair_at(k, &dofs, u, state, &h).force);
                let step = 1e-4;
                let scale = (0..ke.dofs)
                    .flat_map(|p| (0..ke.dofs).map(move |q| (p, q)))
                    .map(|(p, q)| ke.get(p, q).abs())
                    .fold(0.0, f64::max);
                for (q, &dof) in g.as_slice().iter().enumerate() {
                    let (mut up, mut down) = (u0.clone(), u0.clone());
                    up[dof] += step;
                    down[dof] -= step;
                    let (fp, fm) = (force(&up), force(&down));
                    for p in 0..ke.dofs {
                        let fd = (fp[p] - fm[p]) / (2.0 * step);
                        assert!(
                            (fd - ke.get(p, q)).abs() <= 1e-8 * scale,
                            "{law:?} {state:?} pair {k}: K[{p}][{q}] = {} but dF/du = {fd}",
                            ke.get(p, q)
                        );
                    }
                }
            }
        }
    }
}
