//! Post-processing of a solved analysis: its results read through
//! [`results::Problem`] — stresses, reactions, pair rows — and its summary started
//! and brought up to date increment by increment.

use super::{Analysis, AnalysisDim};
use crate::fem::recovery::PartStress;
use crate::results::history::HistoryRow;
use crate::results::lines::LineSample;
use crate::results::{self, PairRow, Summary};
use crate::solve::nonlinear::IncrementResult;

impl<D: AnalysisDim> Analysis<D> {
    /// The summary before the first increment.
    pub(crate) fn empty_summary(&self) -> Summary {
        let m = &self.model;
        Summary::new(
            &self.problem(),
            results::Heading {
                title: m.title.clone(),
                problem: m.source.clone(),
                refine: m.refine,
                steps: m.steps(),
                warnings: results::kept_polygon_warnings(&m.kept_polygons, m.refine),
                notes: D::notes(m),
                shortcut_off: self.shortcut_off_reason(),
                setup: &self.timings,
            },
        )
    }

    /// The reaction (`D::N` components: x, y and in 3D z) of each support, in
    /// the order of `model.supports`: the out-of-balance force F_int − F_ext
    /// summed over the DOFs it fixes.
    pub fn reactions(&self, inc: &IncrementResult<D>) -> Vec<D::Vector> {
        self.problem().reactions(inc)
    }

    /// The name of step `step` (0-based) of the model.
    pub fn step_name(&self, step: usize) -> String {
        match self.model.steps.get(step) {
            Some(s) => s.name.clone(),
            None => crate::model::DEFAULT_STEP.into(),
        }
    }

    /// Stresses of every part for displacements `u` (all DOFs).
    pub fn recover(&self, u: &[f64]) -> Vec<PartStress<D::Stress>> {
        self.problem().recover(u)
    }

    /// One row per coupling pair: state, jumps and forces on the node part.
    pub fn pair_rows(&self, inc: &IncrementResult<D>) -> Vec<PairRow> {
        results::pair_rows(&self.problem(), inc, &self.step_name(inc.step))
    }

    /// The history row of converged increment `inc` — its step, load factor,
    /// time, every support's reaction, every interface's contact resultants,
    /// contact length and largest pressure, every probe's displacement — as the
    /// summary's `history` records it (`history.csv`'s row).
    pub fn history_row(&self, inc: &IncrementResult<D>) -> HistoryRow {
        let mut s = self.empty_summary();
        self.fill_summary(&mut s, inc, &self.pair_rows(inc));
        s.history
            .pop()
            .expect("fill_summary records the increment's history row")
    }

    /// Records converged increment `inc` (with its pair rows `rows`) in the
    /// summary `s`.
    pub(crate) fn fill_summary(&self, s: &mut Summary, inc: &IncrementResult<D>, rows: &[PairRow]) {
        s.record_increment(&self.problem(), inc, rows, self.step_name(inc.step));
    }

    /// The problem the results are read against.
    pub(crate) fn problem(&self) -> results::Problem<'_, D> {
        results::Problem {
            parts: &self.model.parts,
            supports: &self.model.supports,
            interfaces: &self.interfaces,
            dofs: &self.dofs,
            settings: &self.model.settings,
            probes: &self.model.probes,
        }
    }
}

/// What only a plane model has.
impl Analysis {
    /// The samples of every line probe (`[[line]]`) at increment `inc`, by
    /// name, in file order: the points of each line that lie in a part.
    pub fn line_samples(&self, inc: &IncrementResult) -> Vec<(&str, Vec<LineSample>)> {
        let m = &self.model;
        m.lines
            .iter()
            .map(|l| {
                let samples = results::lines::sample(l, &m.parts, &self.dofs.node_offset, &inc.u);
                (l.name.as_str(), samples)
            })
            .collect()
    }
}
