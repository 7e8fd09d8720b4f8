//! Tables and summaries: the interface pairs CSV and the JSON summary of a run.

use super::write_atomic;
use crate::error::Result;
use serde::Serialize;
use std::path::Path;

/// One coupling pair at one increment, as written to `pairs.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct PairRow {
    /// Interface name.
    pub interface: String,
    /// Coupling node (index in the node part).
    pub node: usize,
    /// Reference position x of the coupling node.
    pub x: f64,
    /// Reference position y of the coupling node.
    pub y: f64,
    /// Host element (index in the host part).
    pub host_element: usize,
    /// `bonded` or `open`.
    pub state: &'static str,
    /// Normal jump `[[u_n]]` (> 0: the faces separate).
    pub gap_n: f64,
    /// Tangential jump `[[u_s]]`.
    pub slip_s: f64,
    /// Normal force on the node part (> 0: the faces press together).
    pub force_n: f64,
    /// Tangential force on the node part along s.
    pub force_s: f64,
    /// State fixed against the law by the active-set scheme to settle a cycle.
    pub settled: bool,
    /// How the pair breaks its law (`tension`, `penetration`), or `None`.
    pub violation: Option<crate::coupling::ViolationKind>,
    /// The violation's amount: the tensile force, or the penetration depth (0 when none).
    pub violation_amount: f64,
}

/// The header of `pairs.csv`.
pub const PAIRS_HEADER: &str = "interface,node,x,y,host_element,state,gap_n,slip_s,force_n,force_s,settled,violation,violation_amount";

/// Writes the pairs table (one row per coupling pair).
pub fn write_pairs_csv(path: &Path, rows: &[PairRow]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{PAIRS_HEADER}")?;
        for r in rows {
            writeln!(
                w,
                "{},{},{},{},{},{},{:e},{:e},{:e},{:e},{},{},{:e}",
                csv_field(&r.interface),
                r.node,
                r.x,
                r.y,
                r.host_element,
                r.state,
                r.gap_n,
                r.slip_s,
                r.force_n,
                r.force_s,
                r.settled,
                r.violation.map_or("", |v| v.as_str()),
                r.violation_amount
            )?;
        }
        Ok(())
    })
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Writes any serializable value as pretty JSON.
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<()> {
    write_atomic(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value).map_err(std::io::Error::other)?;
        writeln!(w)
    })
}
