//! Tables and summaries: the interface pairs CSV and the JSON summary of a run.

use super::write_atomic;
use crate::coupling::{PairState, ViolationKind};
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
    /// Reference position x of the pair: with the node coupling, the coupling
    /// node's projection on its host edge (where the node is placed; with a search
    /// distance the node stays where it is meshed, |g₀| away); with the segment
    /// coupling, the coupling node's own position.
    #[serde(serialize_with = "plain")]
    pub x: f64,
    /// Reference position y of the pair (as `x`).
    #[serde(serialize_with = "plain")]
    pub y: f64,
    /// Host element (index in the host part).
    pub host_element: usize,
    /// `bonded` or `open`.
    pub state: PairState,
    /// Normal jump `[[u_n]]` (> 0: the faces separate).
    #[serde(serialize_with = "sci")]
    pub gap_n: f64,
    /// Tangential jump `[[u_s]]`.
    #[serde(serialize_with = "sci")]
    pub slip_s: f64,
    /// Normal force on the node part (> 0: the faces press together).
    #[serde(serialize_with = "sci")]
    pub force_n: f64,
    /// Tangential force on the node part along s.
    #[serde(serialize_with = "sci")]
    pub force_s: f64,
    /// State fixed against the law by the active-set scheme to settle a cycle.
    pub settled: bool,
    /// How the pair breaks its law (`tension`, `penetration`), or `None` (empty).
    pub violation: Option<ViolationKind>,
    /// The violation's amount: the tensile force, or the penetration depth (0 when none).
    #[serde(serialize_with = "sci")]
    pub violation_amount: f64,
    /// Initial normal gap g₀ (0 unless paired within a search distance).
    #[serde(serialize_with = "sci")]
    pub gap0: f64,
    /// Current normal gap g₀ + `[[u_n]]` (< 0: penetration).
    #[serde(serialize_with = "sci")]
    pub gap: f64,
    /// Slip not carried elastically: the plastic slip s_p of a closed pair with
    /// friction (0 for the seed's stick law), the tangential jump of an open or
    /// frictionless pair.
    #[serde(serialize_with = "sci")]
    pub slip: f64,
    /// Contact pressure, a stress: `force_n` / (tributary length × the node part's
    /// thickness t) (> 0 in compression; [`crate::coupling::traction`]).
    #[serde(serialize_with = "sci")]
    pub pressure: f64,
    /// Shear traction, a stress: `force_s` / (tributary length × t).
    #[serde(serialize_with = "sci")]
    pub shear: f64,
    /// Tributary length of the coupling node on the node part's face (with segment
    /// coupling, its share of the face m_a = ∫ N_a ds).
    #[serde(serialize_with = "sci")]
    pub tributary: f64,
    /// With segment coupling, the node-part nodes of the pair's averaged jump (the
    /// coupling node and its face neighbours), as `a-b-c`; empty for the node CFE.
    pub segment: Option<String>,
    /// The increment (1-based, over all steps).
    pub increment: usize,
    /// The increment's load step (its name).
    pub step: String,
    /// The step's load factor at this increment.
    #[serde(serialize_with = "plain")]
    pub load_factor: f64,
}

/// The columns of `pairs.csv` (the serialized fields of [`PairRow`]).
pub const PAIR_COLUMNS: [&str; 23] = [
    "interface",
    "node",
    "x",
    "y",
    "host_element",
    "state",
    "gap_n",
    "slip_s",
    "force_n",
    "force_s",
    "settled",
    "violation",
    "violation_amount",
    "gap0",
    "gap",
    "slip",
    "pressure",
    "shear",
    "tributary",
    "segment",
    "increment",
    "step",
    "load_factor",
];

/// Writes the pairs table (one row per coupling pair; the header is the field
/// names of [`PairRow`]).
pub fn write_pairs_csv(path: &Path, rows: &[PairRow]) -> Result<()> {
    write_atomic(path, |w| {
        let mut csv = csv::Writer::from_writer(w);
        if rows.is_empty() {
            csv.write_record(PAIR_COLUMNS)?;
        }
        for r in rows {
            csv.serialize(r).map_err(std::io::Error::other)?;
        }
        csv.flush()
    })
}

/// A number as Rust's `Display` writes it (`100`, `0.5`): the positions' format.
fn plain<S: serde::Serializer>(v: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(v)
}

/// A number in scientific notation (`-1.25e-3`): the jumps' and forces' format.
fn sci<S: serde::Serializer>(v: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:e}"))
}

/// Writes any serializable value as pretty JSON.
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<()> {
    write_atomic(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value).map_err(std::io::Error::other)?;
        writeln!(w)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSV: header from the field names, positions as written, jumps and forces
    /// in scientific notation, a name with a comma quoted, the violation empty when
    /// there is none; an empty table keeps its header.
    #[test]
    fn pairs_csv_format() {
        let dir = std::env::temp_dir().join(format!("cfe-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pairs.csv");
        let row = PairRow {
            interface: "a,b".into(),
            node: 3,
            x: 100.0,
            y: -6.5,
            host_element: 7,
            state: PairState::Open,
            gap_n: 1.25e-3,
            slip_s: 0.0,
            force_n: -0.5,
            force_s: 2.0,
            settled: false,
            violation: None,
            violation_amount: 0.0,
            gap0: -1.0,
            gap: 0.5,
            slip: 0.0,
            pressure: 0.25,
            shear: 0.0,
            tributary: 2.0,
            segment: None,
            increment: 2,
            step: "shear".into(),
            load_factor: 0.5,
        };
        let pulling = PairRow {
            state: PairState::Bonded,
            settled: true,
            violation: Some(ViolationKind::Tension),
            violation_amount: 0.5,
            segment: Some("3-4".into()),
            ..row.clone()
        };
        write_pairs_csv(&path, &[row, pulling]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            format!(
                "{}\n\"a,b\",3,100,-6.5,7,open,1.25e-3,0e0,-5e-1,2e0,false,,0e0,-1e0,5e-1,0e0,2.5e-1,0e0,2e0,,2,shear,0.5\n\"a,b\",3,100,-6.5,7,bonded,1.25e-3,0e0,-5e-1,2e0,true,tension,5e-1,-1e0,5e-1,0e0,2.5e-1,0e0,2e0,3-4,2,shear,0.5\n",
                PAIR_COLUMNS.join(",")
            )
        );
        write_pairs_csv(&path, &[]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, format!("{}\n", PAIR_COLUMNS.join(",")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
