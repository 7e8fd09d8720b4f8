//! Coupling: the interfaces between independently meshed parts. Finds the coupling
//! pairs (each coupling node of the node part and the host element that contains it),
//! builds one coupling finite element (CFE) per pair, evaluates a pair at a
//! solution ([`Interface::pair_at`]), and is the one home of the interface law: the
//! law of one pair ([`law`]), the law checked on every pair ([`check`]) and the
//! rules of the pairs' histories ([`history`]). The contact scheme calls these; they
//! know no solver.

pub mod build;
pub mod check;
pub mod element;
#[cfg(test)]
mod element3d_check;
pub mod face;
#[cfg(test)]
pub(crate) mod fixture;
#[cfg(test)]
mod stiffness_check;
#[cfg(test)]
mod tangent_plane_check;
pub mod history;
pub mod law;
pub mod pair_set;
pub(crate) mod search;
pub mod search3d;
pub mod segment;
pub mod volume;

pub use crate::domain::{Coupling, CouplingForm};
use crate::dim::{D2, Dim};
pub use check::{CheckTolerance, Verdicts, check_law};
pub use element::{CouplingElement, PairAt, SegmentSide, traction};
pub use pair_set::{InterfacePairs, PairSet};
pub use law::{
    Enforcement, Law, LawParams, LawTolerance, LawViolation, PairHistories, PairHistory, PairState,
    PairStates, SLIP_STIFFNESS, Transition, ViolationKind, return_map,
};

/// An interface between a host part and a node part, with its coupling elements
/// (of the dimension `D`, [`D2`] by default).
#[derive(Debug, Clone)]
pub struct Interface<D: Dim = D2> {
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
    pub elements: Vec<CouplingElement<D>>,
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
    /// lies within the search distance (0 without a search distance); in the
    /// volume form, the nodes that lie in no host element (not coupled).
    pub unpaired: usize,
    /// How the coupling elements' jumps are taken: collocated at the coupling
    /// node, or averaged over its face segments.
    pub coupling: Coupling,
    /// Where the coupling nodes meet the host: on its boundary (`face`) or
    /// inside its elements (`volume`, [`CouplingForm::Volume`]).
    pub form: CouplingForm,
}

impl<D: Dim> Interface<D> {
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
        dofs: &crate::dofs::DofMap<D>,
        u: &[f64],
        state: PairState,
        h: &PairHistory<D>,
    ) -> PairAt<D> {
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
pub fn coupling_dofs<D: Dim>(interfaces: &[Interface<D>], dofs: &crate::dofs::DofMap<D>) -> Vec<usize> {
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
