//! What a plane (2D) run writes of its own, the [`Layout`] of [`D2`]: T3/Q4
//! cells, σxx σyy σxy von Mises (and σθθ when axisymmetric), tangential
//! quantities along s, `sigma_yy.png`, `displacement.png`, `pressure.png` (with
//! a contact law) and `history.png`, and the line probes.

use super::dim::{Layout, StressField};
use super::layout;
use super::stresses::Stresses;
use crate::analysis::Analysis;
use crate::coupling::Law;
use crate::dim::D2;
use crate::domain::Part;
use crate::error::Result;
use crate::output::folder::{OutputFolder, PICTURES};
use crate::output::png::Proceed;
use crate::output::vtu::CellKind;
use crate::results::{PAIR_COLUMNS, PairRow};
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;

/// Plane models: T3/Q4 cells, σxx σyy σxy von Mises (and σθθ when
/// axisymmetric), tangential quantities along s, `sigma_yy.png`,
/// `displacement.png` and `pressure.png` (with a contact law), line probes.
impl Layout for D2 {
    const TANGENT_FIELD: usize = 1;
    const PAIR_COLUMNS: &'static [&'static str] = &PAIR_COLUMNS;

    fn cell_kind(cell: &crate::mesh::Element) -> CellKind {
        layout::plane_cell_kind(cell)
    }

    fn stress_fields(
        parts: &[Part],
        stresses: &Stresses,
        n_points: usize,
        n_cells: usize,
    ) -> Vec<StressField> {
        layout::plane_stress_fields(parts, stresses, n_points, n_cells)
    }

    fn tangent_field(frame: &[[f64; 2]; 2], t: f64, out: &mut Vec<f64>) {
        layout::plane_tangent(frame, t, out);
    }

    fn pair_force_field(_: &[PairRow]) -> Option<Vec<f64>> {
        None
    }

    /// `pressure.png` only with a contact law (see `write_pressure_chart`).
    fn pictures(analysis: &Analysis) -> Vec<String> {
        let pressure = analysis.interfaces.iter().any(|i| i.law != Law::Rigid);
        (PICTURES.into_iter())
            .filter(|&f| f != PICTURES[2] || pressure)
            .map(String::from)
            .collect()
    }

    fn write_pictures(
        analysis: &Analysis,
        out: &Path,
        inc: &IncrementResult,
        stresses: &Stresses,
        proceed: Proceed<'_>,
    ) -> Result<()> {
        analysis.write_pictures(out, inc, stresses, proceed)
    }

    fn write_lines(
        analysis: &Analysis,
        out: &Path,
        inc: &IncrementResult,
        folder: &mut OutputFolder,
    ) -> Result<()> {
        analysis.write_lines(out, inc, folder)
    }

    fn write_line_increment(
        analysis: &Analysis,
        out: &Path,
        inc: &IncrementResult,
        folder: &mut OutputFolder,
    ) -> Result<()> {
        analysis.write_line_increment(out, inc, folder)
    }
}
