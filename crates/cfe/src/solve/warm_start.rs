//! Warm start of the `active-set` iteration from a coarser model: the final pair
//! states of the same problem on coarser meshes, mapped to the fine pairs by
//! position (each fine pair takes the state of the nearest coarse pair of its
//! interface). A start close to the final pattern needs few, small state changes;
//! the converged result does not depend on it.
//!
//! Building the coarser model is the caller's business (the solver reads no input):
//! it hands over the coarse problem, already prepared.

use super::contact::Solver;
use crate::coupling::{Interface, PairState, PairStates};
use crate::dim::D2;
use crate::dofs::DofMap;
use crate::domain::{Part, Settings};
use crate::fem::ElementFamily;
use std::sync::atomic::AtomicUsize;

/// A prepared problem to solve for its final states: parts, interfaces with their
/// coupling elements, DOF numbering, external force at full load, settings.
pub struct Problem<'a, D: ElementFamily = D2> {
    /// The parts.
    pub parts: &'a [Part<D>],
    /// The interfaces with their coupling elements.
    pub interfaces: &'a [Interface<D>],
    /// The DOF numbering.
    pub dofs: &'a DofMap<D>,
    /// External force of all DOFs at full load.
    pub f_ext: Vec<f64>,
    /// Analysis settings (the increments are ignored: one increment is solved).
    pub settings: &'a Settings,
}

/// The final pair states of `coarse` solved in one increment (its own iteration
/// starting from `coarse_start` when given), mapped onto the pairs of `fine`.
/// `None` when the coarse problem does not solve, its interfaces do not match,
/// or `stop` (read as [`Solver::new`] says) is set.
pub fn states_from_coarse<'a, D: ElementFamily>(
    coarse: Problem<'a, D>,
    coarse_start: Option<PairStates>,
    fine: &[Interface<D>],
    stop: Option<&'a AtomicUsize>,
) -> Option<PairStates>
where
    D::Vector: rstar::Point<Scalar = f64>,
{
    if coarse.interfaces.len() != fine.len() {
        return None;
    }
    // The coarse model is small: a back end outside the library (PETSc) is
    // not needed for it, and the direct one is there in every build.
    let solver = match coarse.settings.solver {
        s if s.is_external() => crate::domain::LinearBackend::Direct,
        s => s,
    };
    let settings = Settings {
        increments: 1,
        solver,
        ..coarse.settings.clone()
    };
    let mut solver = Solver::new(
        coarse.parts,
        coarse.interfaces,
        coarse.dofs,
        coarse.f_ext,
        &settings,
        stop,
    )
    .ok()?;
    if let Some(s) = coarse_start {
        solver.set_initial_states(s);
    }
    let last = solver.run(|_| Ok(())).ok()?;
    Some(map_states(coarse.interfaces, &last.states, fine))
}

/// Each pair of `fine` takes the state of the nearest pair (by reference position)
/// of the same interface of `coarse`, whose states are `coarse_states`.
pub fn map_states<D: ElementFamily>(
    coarse: &[Interface<D>],
    coarse_states: &[Vec<PairState>],
    fine: &[Interface<D>],
) -> PairStates
where
    D::Vector: rstar::Point<Scalar = f64>,
{
    fine.iter()
        .zip(coarse)
        .zip(coarse_states)
        .map(|((fine, coarse), cs)| {
            let tree = rstar::RTree::bulk_load(
                coarse
                    .elements
                    .iter()
                    .enumerate()
                    .map(|(k, c)| rstar::primitives::GeomWithData::new(c.position, k))
                    .collect(),
            );
            fine.elements
                .iter()
                .map(|c| {
                    tree.nearest_neighbor(c.position)
                        .map_or(PairState::Bonded, |n| cs[n.data])
                })
                .collect()
        })
        .collect()
}
