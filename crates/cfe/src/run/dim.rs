//! What a run writes differently per dimension, behind one trait: the run loop
//! (`super`) and the VTU layout (`super::layout`) are written once over
//! [`RunDim`], and each dimension states only its own parts — the VTK kind of
//! its cells, its stress components, how a tangential quantity is laid out in
//! the pairs VTU, the header of an empty pairs table, its pictures and its line
//! probes. Plane models implement it in `super::plane` (with `super::layout`,
//! `super::pictures` and `super::lines`), solid models in `super::solid`.

use super::stresses::Stresses;
use crate::analysis::{Analysis, AnalysisDim};
use crate::dim::D2;
use crate::domain::Part;
use crate::error::Result;
use crate::output::folder::OutputFolder;
use crate::output::png::Proceed;
use crate::output::vtu::{CellKind, GridPoint};
use crate::results::PairRow;
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;

/// A stress field of the parts VTU: its name, its values at the points
/// (nodal, recovered) and in the cells, each in the parts' order.
pub struct StressField {
    /// The array's name (`sigma_xx`, `von_mises` …), point and cell data alike.
    pub name: &'static str,
    /// One value per point.
    pub nodal: Vec<f64>,
    /// One value per cell.
    pub cell: Vec<f64>,
}

/// The dimensions an [`Analysis`] can run in, writing its results into a
/// folder ([`Analysis::run`]): [`D2`] (plane) and [`crate::dim::D3`] (solid).
/// Sealed: its methods are the run's own.
pub trait RunDim: Layout {}

impl RunDim for D2 {}
impl RunDim for crate::dim::D3 {}

/// The parts of a run that differ between the dimensions (see the
/// [module](self)). Not nameable outside the crate, so [`RunDim`] is sealed.
pub trait Layout: AnalysisDim<Vector: GridPoint> {
    /// Components of a tangential quantity in the pairs VTU (`slip_s`,
    /// `force_s`, `slip`, `shear`): 1 in 2D (along s), 3 in 3D (a vector in
    /// global components).
    const TANGENT_FIELD: usize;

    /// The header of the pairs table when it has no row.
    const PAIR_COLUMNS: &'static [&'static str];

    /// The VTK kind of a cell.
    fn cell_kind(cell: &Self::Cell) -> CellKind;

    /// The stress fields of the parts VTU, in the order written.
    fn stress_fields(
        parts: &[Part<Self>],
        stresses: &Stresses<Self::Stress>,
        n_points: usize,
        n_cells: usize,
    ) -> Vec<StressField>;

    /// Appends the tangential quantity `t` of a pair with local frame `frame`
    /// to `out`, as the pairs VTU holds it ([`Layout::TANGENT_FIELD`] values).
    fn tangent_field(frame: &Self::Frame, t: Self::Tangent, out: &mut Vec<f64>);

    /// The force on the node part of every pair in global components, the
    /// pairs VTU's `force` (`None`: no such field, a plane model's rows state
    /// it by its normal and tangential parts).
    fn pair_force_field(rows: &[PairRow]) -> Option<Vec<f64>>;

    /// The pictures `analysis` draws after its last increment, `history.png`
    /// (drawn by the loop) included: each is claimed in the folder's manifest
    /// before the drawing starts, and removed again if the run then fails.
    fn pictures(analysis: &Analysis<Self>) -> Vec<String>;

    /// Draws [`Layout::pictures`] but `history.png` of increment `inc` into
    /// `out` from its `stresses`; `proceed` is asked between the drawing's
    /// stages.
    fn write_pictures(
        analysis: &Analysis<Self>,
        out: &Path,
        inc: &IncrementResult<Self>,
        stresses: &Stresses<Self::Stress>,
        proceed: Proceed<'_>,
    ) -> Result<()>;

    /// Writes the line probes' tables and charts of the last increment `inc`
    /// (`lines/`), each claimed in `folder` first. A solid model has none.
    fn write_lines(
        _analysis: &Analysis<Self>,
        _out: &Path,
        _inc: &IncrementResult<Self>,
        _folder: &mut OutputFolder,
    ) -> Result<()> {
        Ok(())
    }

    /// Writes the line probes' tables of a written increment `inc`
    /// (`lines/<name>.<NNNN>.csv`), each claimed in `folder` first. A solid
    /// model has none.
    fn write_line_increment(
        _analysis: &Analysis<Self>,
        _out: &Path,
        _inc: &IncrementResult<Self>,
        _folder: &mut OutputFolder,
    ) -> Result<()> {
        Ok(())
    }
}
