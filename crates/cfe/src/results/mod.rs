//! Results: the vocabulary of what a solve produced, below the model and the
//! writers. The summary of a run ([`Summary`], `summary.json`) and its bookkeeping
//! (started from the problem, brought up to date with each converged increment),
//! the rows of the pairs table ([`PairRow`]), the memory figures of the process
//! ([`memory`]) and the one number format of everything printed ([`fmt`]). The
//! analysis fills them; the writers in [`crate::output`] write them.

pub mod fmt;
pub mod history;
pub mod lines;
pub mod memory;
pub mod pairs;
mod record;
pub mod summary;

pub(crate) use pairs::pair_rows;
pub use pairs::{PAIR_COLUMNS, PairRow, SOLID_PAIR_COLUMNS};
pub(crate) use record::{Heading, kept_polygon_warnings};
pub use summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, Reaction, RunClock, RunStatus,
    SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};

use crate::coupling::Interface;
use crate::dim::{D2, D3};
use crate::dofs::DofMap;
use crate::domain::{Part, Probe, Settings, Support};
use crate::fem::recovery::PartStress;
use crate::fem::{ElementFamily, Material};
use crate::solve::nonlinear::IncrementResult;

/// What reading results needs of a dimension beyond its elements: the
/// thickness a pair's force is spread over with its tributary share.
pub trait ResultsDim: ElementFamily {
    /// The out-of-plane thickness of a pair's traction on a node part of
    /// `material`: its thickness in 2D (the tributary is a length); 1 in 3D
    /// (the tributary is an area).
    fn traction_thickness(material: &Material) -> f64;
}

/// Plane parts: tractions over tributary length × thickness.
impl ResultsDim for D2 {
    fn traction_thickness(material: &Material) -> f64 {
        material.thickness
    }
}

/// Solid parts: tractions over the tributary area.
impl ResultsDim for D3 {
    fn traction_thickness(_: &Material) -> f64 {
        1.0
    }
}

/// The solved problem results are read against: its parts, supports, interfaces
/// with their coupling elements, DOF numbering and settings, in dimension `D`.
pub(crate) struct Problem<'a, D: ResultsDim = D2> {
    /// The parts.
    pub parts: &'a [Part<D>],
    /// The supports.
    pub supports: &'a [Support],
    /// The interfaces with their coupling elements.
    pub interfaces: &'a [Interface<D>],
    /// The DOF numbering.
    pub dofs: &'a DofMap<D>,
    /// The analysis settings (scheme, increments, tolerances).
    pub settings: &'a Settings,
    /// The probe points the history records.
    pub probes: &'a [Probe<D>],
}

impl<D: ResultsDim> Problem<'_, D> {
    /// The reaction (`D::N` components) of each support, in the order of
    /// `supports`: the out-of-balance force F_int − F_ext summed over the DOFs
    /// it fixes.
    pub fn reactions(&self, inc: &IncrementResult<D>) -> Vec<D::Vector> {
        // `inc.f_ext` is already at the increment's load factor.
        self.dofs
            .reactions(self.supports.len(), &inc.f_int, &inc.f_ext, 1.0)
    }

    /// Stresses of every part for displacements `u` (all DOFs).
    pub fn recover(&self, u: &[f64]) -> Vec<PartStress<D::Stress>> {
        self.parts
            .iter()
            .enumerate()
            .map(|(p, part)| {
                let s = D::dof(self.dofs.node_offset[p], 0);
                let e = D::dof(self.dofs.node_offset[p] + part.mesh.nodes.len(), 0);
                D::recover(&part.mesh, &part.material, &u[s..e])
            })
            .collect()
    }
}
