//! Tables and summaries: the interface pairs CSV (its rows, [`PairRow`], are
//! results vocabulary: `crate::results::pairs`) and the JSON summary of a run.

use super::write_atomic;
use crate::error::Result;
pub use crate::results::history::HistoryRow;
pub use crate::results::pairs::{PAIR_COLUMNS, PairRow};
use serde::Serialize;
use std::path::Path;

/// Writes the pairs table of a plane model (one row per coupling pair; the
/// header is the field names of [`PairRow`], [`PAIR_COLUMNS`]).
pub fn write_pairs_csv(path: &Path, rows: &[PairRow]) -> Result<()> {
    write_pairs_table(path, rows, &PAIR_COLUMNS)
}

/// Writes the pairs table (one row per coupling pair; the header is the field
/// names each row serializes: [`PAIR_COLUMNS`] in a plane model,
/// [`crate::results::SOLID_PAIR_COLUMNS`] in a solid one), or `empty_header`
/// alone when there is no row.
pub fn write_pairs_table(path: &Path, rows: &[PairRow], empty_header: &[&str]) -> Result<()> {
    write_atomic(path, |w| {
        let mut csv = csv::Writer::from_writer(w);
        if rows.is_empty() {
            csv.write_record(empty_header)?;
        }
        for r in rows {
            csv.serialize(r).map_err(std::io::Error::other)?;
        }
        csv.flush()
    })
}

/// Writes the history table (`history.csv`): one row per converged increment,
/// the columns of [`crate::results::history::columns`] (counts and names as
/// they are, the load factor and time in Rust's shortest form, the other
/// numbers in scientific notation); an empty history writes the header of its
/// first five columns.
pub fn write_history_csv(path: &Path, rows: &[HistoryRow]) -> Result<()> {
    use crate::results::history::{Values, column_names, columns};
    let cols = columns(rows);
    write_atomic(path, |w| {
        let mut csv = csv::Writer::from_writer(w);
        if cols.is_empty() {
            let names = column_names([].into_iter(), [].into_iter(), [].into_iter());
            csv.write_record(&names)?;
            return csv.flush();
        }
        csv.write_record(cols.iter().map(|(n, _)| n))?;
        for k in 0..rows.len() {
            let record = cols.iter().map(|(name, v)| match v {
                Values::Count(c) => c[k].to_string(),
                Values::Name(n) => n[k].clone(),
                Values::Number(x) if name == "load_factor" || name == "time" => x[k].to_string(),
                Values::Number(x) => format!("{:e}", x[k]),
            });
            csv.write_record(record)?;
        }
        csv.flush()
    })
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
    use crate::coupling::{PairState, ViolationKind};

    /// The CSV: header from the field names, positions as written, jumps and forces
    /// in scientific notation, a name with a comma quoted, the violation empty when
    /// there is none, both of a pair breaking the law twice (`;`-separated, the
    /// amounts in the same order); an empty table keeps its header.
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
            z: None,
            host_element: 7,
            state: PairState::Open,
            gap_n: 1.25e-3,
            slip_s: 0.0,
            slip_t2: None,
            force_n: -0.5,
            force_s: 2.0,
            force_t2: None,
            force_x: None,
            force_y: None,
            force_z: None,
            settled: false,
            violation: Vec::new(),
            violation_amount: Vec::new(),
            gap0: -1.0,
            gap: 0.5,
            slip: 0.0,
            slip_t2_plastic: None,
            pressure: 0.25,
            shear: 0.0,
            shear_t2: None,
            tributary: 2.0,
            segment: None,
            increment: 2,
            step: "shear".into(),
            load_factor: 0.5,
        };
        let pulling = PairRow {
            state: PairState::Bonded,
            settled: true,
            violation: vec![ViolationKind::Tension],
            violation_amount: vec![0.5],
            segment: Some("3-4".into()),
            ..row.clone()
        };
        // A stick pair pulling while it carries shear: both violations, the
        // normal one first, with their amounts.
        let twice = PairRow {
            violation: vec![ViolationKind::Tension, ViolationKind::Friction],
            violation_amount: vec![0.5, 2.0],
            ..pulling.clone()
        };
        assert_eq!(
            [&row, &pulling, &twice].map(|r| r.violation_code()),
            [0, 1, 5]
        );
        write_pairs_csv(&path, &[row, pulling, twice]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            format!(
                "{}\n\"a,b\",3,100,-6.5,7,open,1.25e-3,0e0,-5e-1,2e0,false,,0e0,-1e0,5e-1,0e0,2.5e-1,0e0,2e0,,2,shear,0.5\n\"a,b\",3,100,-6.5,7,bonded,1.25e-3,0e0,-5e-1,2e0,true,tension,5e-1,-1e0,5e-1,0e0,2.5e-1,0e0,2e0,3-4,2,shear,0.5\n\"a,b\",3,100,-6.5,7,bonded,1.25e-3,0e0,-5e-1,2e0,true,tension;friction,5e-1;2e0,-1e0,5e-1,0e0,2.5e-1,0e0,2e0,3-4,2,shear,0.5\n",
                PAIR_COLUMNS.join(",")
            )
        );
        write_pairs_csv(&path, &[]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, format!("{}\n", PAIR_COLUMNS.join(",")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
