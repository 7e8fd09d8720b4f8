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
pub use pairs::{PAIR_COLUMNS, PairRow};
pub(crate) use record::{Heading, kept_polygon_warnings};
pub use summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, Reaction, RunClock, RunStatus,
    SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};

use crate::coupling::Interface;
use crate::dofs::DofMap;
use crate::domain::{Part, Probe, Settings, Support};
use crate::fem::recovery::{self, PartStress};
use crate::solve::nonlinear::IncrementResult;

/// The solved problem results are read against: its parts, supports, interfaces
/// with their coupling elements, DOF numbering and settings.
pub(crate) struct Problem<'a> {
    /// The parts.
    pub parts: &'a [Part],
    /// The supports.
    pub supports: &'a [Support],
    /// The interfaces with their coupling elements.
    pub interfaces: &'a [Interface],
    /// The DOF numbering.
    pub dofs: &'a DofMap,
    /// The analysis settings (scheme, increments, tolerances).
    pub settings: &'a Settings,
    /// The probe points the history records.
    pub probes: &'a [Probe],
}

impl Problem<'_> {
    /// The reaction (x, y) of each support, in the order of `supports`: the
    /// out-of-balance force F_int − F_ext summed over the DOFs it fixes.
    pub fn reactions(&self, inc: &IncrementResult) -> Vec<[f64; 2]> {
        // `inc.f_ext` is already at the increment's load factor.
        self.dofs
            .reactions(self.supports.len(), &inc.f_int, &inc.f_ext, 1.0)
    }

    /// Stresses of every part for displacements `u` (all DOFs).
    pub fn recover(&self, u: &[f64]) -> Vec<PartStress> {
        self.parts
            .iter()
            .enumerate()
            .map(|(p, part)| {
                let s = 2 * self.dofs.node_offset[p];
                recovery::recover(
                    &part.mesh,
                    &part.material,
                    &u[s..s + 2 * part.mesh.nodes.len()],
                )
            })
            .collect()
    }
}
