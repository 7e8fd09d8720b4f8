//! The line probes' files of a run: `lines/<name>.csv` (s, x, y, part, ux, uy,
//! σxx, σyy, σxy, von Mises at each sample point inside a part) and
//! `lines/<name>.png` (displacement and stresses against s), at the last
//! converged increment; and the same table at every increment the run writes
//! its VTU series for, `lines/<name>.<NNNN>.csv`. Each file is claimed in the
//! folder's manifest before it is written.

use crate::analysis::Analysis;
use crate::error::{Error, Result};
use crate::output::chart::{Axes, Series, side_by_side};
use crate::output::folder::{LINES, OutputFolder, line_increment_file};
use crate::output::write_atomic;
use crate::results::lines::LineSample;
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;

/// The columns of `lines/<name>.csv`.
pub const LINE_COLUMNS: [&str; 10] = [
    "s",
    "x",
    "y",
    "part",
    "ux",
    "uy",
    "sxx",
    "syy",
    "sxy",
    "von_mises",
];

impl Analysis {
    /// Writes every line probe's table and chart of increment `inc` into
    /// `out/lines/` (created when there is a line), each claimed in `folder`'s
    /// manifest first.
    pub(super) fn write_lines(
        &self,
        out: &Path,
        inc: &IncrementResult,
        folder: &mut OutputFolder,
    ) -> Result<()> {
        let lines = self.line_samples(inc);
        if lines.is_empty() {
            return Ok(());
        }
        lines_folder(out)?;
        for (name, samples) in &lines {
            let csv = format!("{LINES}/{name}.csv");
            folder.claim(&csv)?;
            write_line_csv(&out.join(&csv), samples, |p| {
                self.model.parts[p].name.as_str()
            })?;
            let png = format!("{LINES}/{name}.png");
            folder.claim(&png)?;
            self.write_line_chart(&out.join(&png), name, samples)?;
        }
        Ok(())
    }

    /// Writes every line probe's table of increment `inc` into
    /// `out/lines/<name>.<NNNN>.csv` (NNNN the increment's number,
    /// [`line_increment_file`]), each claimed in `folder`'s manifest first: the
    /// lines' history, written at the increments whose VTU files are written.
    pub(super) fn write_line_increment(
        &self,
        out: &Path,
        inc: &IncrementResult,
        folder: &mut OutputFolder,
    ) -> Result<()> {
        let lines = self.line_samples(inc);
        if lines.is_empty() {
            return Ok(());
        }
        lines_folder(out)?;
        for (name, samples) in &lines {
            let csv = format!("{LINES}/{}", line_increment_file(name, inc.index));
            folder.claim(&csv)?;
            write_line_csv(&out.join(&csv), samples, |p| {
                self.model.parts[p].name.as_str()
            })?;
        }
        Ok(())
    }

    /// The chart of line `name`: the displacement components (left) and the
    /// stresses (right) against the distance s along it.
    fn write_line_chart(&self, path: &Path, name: &str, samples: &[LineSample]) -> Result<()> {
        let units = &self.model.units;
        let series = |label: &str, f: &dyn Fn(&LineSample) -> f64| Series {
            name: label.to_string(),
            points: samples.iter().map(|s| (s.s, f(s))).collect(),
            reference: false,
        };
        let disp = [series("ux", &|s| s.u[0]), series("uy", &|s| s.u[1])];
        let stress = [
            series("σxx", &|s| s.stress[0]),
            series("σyy", &|s| s.stress[1]),
            series("σxy", &|s| s.stress[2]),
            series("von Mises", &|s| s.von_mises),
        ];
        let x = format!("s [{}]", units.length);
        let (t1, t2) = (
            format!("{}: displacement along line '{name}'", self.model.title),
            format!("stresses along line '{name}'"),
        );
        let (y1, y2) = (
            format!("displacement [{}]", units.length),
            format!("stress [{}]", units.stress),
        );
        let axes = |title, y| Axes {
            title,
            x: &x,
            y,
            log_x: false,
            log_y: false,
        };
        side_by_side(
            path,
            [(&axes(&t1, &y1), &disp[..]), (&axes(&t2, &y2), &stress[..])],
        )
    }
}

/// Creates `out/lines/` unless it exists (the folder check has refused a file or
/// a link there).
fn lines_folder(out: &Path) -> Result<()> {
    let dir = out.join(LINES);
    match std::fs::create_dir(&dir) {
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => Err(Error::output(&dir, e)),
        _ => Ok(()),
    }
}

/// Writes the table of a line's `samples` (`part_name` names a part by index).
fn write_line_csv<'a>(
    path: &Path,
    samples: &[LineSample],
    part_name: impl Fn(usize) -> &'a str,
) -> Result<()> {
    write_atomic(path, |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(LINE_COLUMNS)?;
        for s in samples {
            let sci = |v: f64| format!("{v:e}");
            csv.write_record([
                s.s.to_string(),
                s.x[0].to_string(),
                s.x[1].to_string(),
                part_name(s.part).to_string(),
                sci(s.u[0]),
                sci(s.u[1]),
                sci(s.stress[0]),
                sci(s.stress[1]),
                sci(s.stress[2]),
                sci(s.von_mises),
            ])?;
        }
        csv.flush()
    })
}
