//! Benchmark: runs a problem (by default the seed's plate on a base) with the
//! `rigid` and the `contact` law at refinements K = 1, 2, 4, … up to a number of
//! unknowns, each run in its own process (so peak memory is that run's), and
//! writes `benchmarks.md` with the phase timings and a log–log picture of time and
//! memory against unknowns.
//!
//! One concept per file: `plan` picks the cases and their refinements, `run` runs
//! them (each in its own process, the fastest of several passes kept) and writes
//! `benchmarks.json`, `report` writes `benchmarks.md` and the picture from it,
//! `targets` judges the runs against the project's performance targets, and
//! `coupling_cost` compares the node and segment couplings. Every run is read as
//! the [`Summary`] it wrote (`summary.json`), and `benchmarks.json` as
//! [`Benchmarks`].

mod coupling_cost;
mod petsc;
mod plan;
mod report;
mod run;
mod targets;

pub use coupling_cost::{CouplingCost, coupling_cost, coupling_cost_table};
pub use plan::{
    FRICTION, PETSC_RANKS, PETSC_SIZES, SOLID_SIZES, refinements, sizes_within, solid_refinements,
    solid_unknowns_model, unknowns_model,
};
pub use report::write_report;
pub use run::{read_benchmarks, run};

use crate::speed::MachineSpeed;
use cfe::error::{Error, Result};
use cfe::{Iteration, Law, Summary};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::{Path, PathBuf};

/// The report's row group of a case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Group {
    /// The refined problem (its `rigid` and `contact` tables, the targets).
    Plate,
    /// The Gmsh problem refined (the roller in its cradle).
    Gmsh,
    /// The frictional run of the problem.
    Friction,
    /// The problem with the `frictionless` and the `coulomb` law at the
    /// headline sizes (beside the plate's `contact` rows of the same K).
    Laws,
    /// The 3D plate on a base (`plate_on_base_3d_bench.toml`) refined to about
    /// 50k, 100k, 200k and 400k unknowns.
    Solid,
    /// The same 3D problem on `--solver petsc` (CG + GAMG), on 1 and 2 MPI
    /// ranks (`cfe bench --only petsc`).
    Petsc,
}

/// Rows `cfe bench --only` runs alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Only {
    /// `3d`: the 3D plate on a base on the direct solver ([`Group::Solid`]).
    Solid,
    /// `petsc`: those rows, then the same problem on `--solver petsc` from
    /// 50k to a million unknowns (and `--max-unknowns` when beyond), on 1 and
    /// 2 MPI ranks ([`Group::Petsc`]); needs a `cfe` built with the `petsc`
    /// feature.
    Petsc,
}

/// One benchmark run (a record of `benchmarks.json`): its row group, law,
/// refinement and what it gave.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Case {
    /// The row group (`plate`, `gmsh` or `friction`).
    pub problem: Group,
    /// The law it ran with (`--law`).
    pub law: Law,
    /// Refinement factor.
    pub refine: usize,
    /// The MPI ranks of a run on `--solver petsc` (absent: the direct solver).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranks: Option<usize>,
    /// The run's summary, or why it gave none.
    pub summary: Outcome,
}

impl Case {
    /// The run's summary, if it ran.
    pub fn ran(&self) -> Option<&Summary> {
        match &self.summary {
            Outcome::Ran(s) => Some(s),
            Outcome::Failed(_) => None,
        }
    }
}

/// A case that ran, with its summary.
#[derive(Clone, Copy)]
struct Run<'a> {
    /// The case (row group, law, refinement).
    pub case: &'a Case,
    /// Its summary.
    pub summary: &'a Summary,
}

/// The cases of `cases` that ran, in order.
fn runs(cases: &[Case]) -> impl Iterator<Item = Run<'_>> {
    cases
        .iter()
        .filter_map(|case| case.ran().map(|summary| Run { case, summary }))
}

/// What a case's run gave: its summary, or (a frictional run only, which may
/// fail without ending the benchmark) the error that stopped it. A failure is
/// stored as `{"status": "failed", "error": …}`.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// The run's `summary.json`.
    Ran(Box<Summary>),
    /// The error of a run that failed.
    Failed(String),
}

impl Outcome {
    /// The run's end-to-end seconds (infinite for a failed run, which has none).
    pub fn total_seconds(&self) -> f64 {
        match self {
            Outcome::Ran(s) => s.timings.total,
            Outcome::Failed(_) => f64::INFINITY,
        }
    }
}

/// A failed run as stored: its status and error.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FailedRecord {
    status: FailedStatus,
    error: String,
}

/// The status of a failed run's record (`failed` only).
#[derive(Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
enum FailedStatus {
    Failed,
}

impl Serialize for Outcome {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Outcome::Ran(summary) => summary.serialize(s),
            Outcome::Failed(error) => FailedRecord {
                status: FailedStatus::Failed,
                error: error.clone(),
            }
            .serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Outcome {
    /// A failure record, else a summary (whose own error names the field that
    /// does not fit).
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        if let Ok(failed) = FailedRecord::deserialize(&value) {
            return Ok(Outcome::Failed(failed.error));
        }
        Summary::deserialize(value)
            .map(|s| Outcome::Ran(Box::new(s)))
            .map_err(serde::de::Error::custom)
    }
}

/// The machine's speed before and after the runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Speeds {
    /// Measured before the first run of the plan.
    pub before: MachineSpeed,
    /// Measured after the last.
    pub after: MachineSpeed,
}

/// `benchmarks.json`: the runs and where they were made, from which
/// [`write_report`] writes the report again without running anything.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Benchmarks {
    /// The problem file refined.
    pub problem: PathBuf,
    /// Processor, cores and memory.
    pub machine: String,
    /// The machine's speed (absent from a file written before it was measured).
    #[serde(default)]
    pub speed: Option<Speeds>,
    /// Passes over the cases; each row is the fastest of its runs.
    #[serde(default = "one")]
    pub repeat: usize,
    /// The commit the binary was built from (`git rev-parse --short HEAD`).
    pub commit: String,
    /// The day the runs were made (UTC, `YYYY-MM-DD`; absent from a file
    /// written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub date: Option<String>,
    /// Every case, in the plan's order.
    pub cases: Vec<Case>,
    /// The row groups measured apart and merged in (`cfe bench --merge`),
    /// each with where it was measured; the fields above describe the other
    /// groups' runs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged: Vec<Origin>,
}

/// Where a set of row groups was measured: the fields of [`Benchmarks`] that
/// describe a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Origin {
    /// The row groups measured in that run.
    pub groups: Vec<Group>,
    /// The problem file refined.
    pub problem: PathBuf,
    /// Processor, cores and memory.
    pub machine: String,
    /// The machine's speed before and after the runs.
    #[serde(default)]
    pub speed: Option<Speeds>,
    /// Passes over the cases.
    pub repeat: usize,
    /// The commit the binary was built from.
    pub commit: String,
    /// The day the runs were made.
    #[serde(default)]
    pub date: Option<String>,
}

impl Group {
    /// The group's name in `benchmarks.json` and the report.
    pub fn as_str(self) -> &'static str {
        match self {
            Group::Plate => "plate",
            Group::Gmsh => "gmsh",
            Group::Friction => "friction",
            Group::Laws => "laws",
            Group::Solid => "solid",
            Group::Petsc => "petsc",
        }
    }
}

fn one() -> usize {
    1
}

impl Benchmarks {
    /// Writes it at `path`, every object's keys in alphabetical order (as the
    /// files written before it was typed).
    pub fn write(&self, path: &Path) -> Result<()> {
        let value = serde_json::to_value(self).map_err(|e| Error::output(path, e))?;
        cfe::output::report::write_json(path, &value)
    }

    /// The row groups of its cases, in order of first appearance.
    pub fn groups(&self) -> Vec<Group> {
        let mut groups = Vec::new();
        for case in &self.cases {
            if !groups.contains(&case.problem) {
                groups.push(case.problem);
            }
        }
        groups
    }

    /// Where the rows of `group` were measured: the merged run that holds
    /// it, else this file's own run.
    pub fn origin(&self, group: Group) -> Origin {
        match self.merged.iter().find(|o| o.groups.contains(&group)) {
            Some(o) => Origin {
                groups: vec![group],
                ..o.clone()
            },
            None => Origin {
                groups: vec![group],
                problem: self.problem.clone(),
                machine: self.machine.clone(),
                speed: self.speed,
                repeat: self.repeat,
                commit: self.commit.clone(),
                date: self.date.clone(),
            },
        }
    }

    /// These results with the rows of every group that `new` has replaced by
    /// `new`'s and the other groups' rows kept, each group keeping where it
    /// was measured: this file's own fields still describe its groups that
    /// `new` does not replace, and each replaced group's run (from `new`) is
    /// listed in [`Benchmarks::merged`]. When `new` replaces every group, the
    /// result is `new`.
    pub fn merge(&self, new: &Benchmarks) -> Benchmarks {
        let replaced = new.groups();
        let own_kept = self.cases.iter().any(|c| {
            !replaced.contains(&c.problem)
                && !self.merged.iter().any(|o| o.groups.contains(&c.problem))
        });
        let kept_merged = self
            .merged
            .iter()
            .any(|o| o.groups.iter().any(|g| !replaced.contains(g)));
        if !own_kept && !kept_merged {
            return new.clone();
        }
        let mut merged: Vec<Origin> = self
            .merged
            .iter()
            .filter_map(|o| {
                let groups: Vec<Group> = o
                    .groups
                    .iter()
                    .copied()
                    .filter(|g| !replaced.contains(g))
                    .collect();
                (!groups.is_empty()).then(|| Origin {
                    groups,
                    ..o.clone()
                })
            })
            .collect();
        for group in replaced {
            let origin = new.origin(group);
            match merged.iter_mut().find(|o| {
                Origin {
                    groups: vec![group],
                    ..(*o).clone()
                } == origin
            }) {
                Some(o) => o.groups.push(group),
                None => merged.push(origin),
            }
        }
        let mut cases: Vec<Case> = self
            .cases
            .iter()
            .filter(|c| !new.cases.iter().any(|n| n.problem == c.problem))
            .cloned()
            .collect();
        cases.extend(new.cases.iter().cloned());
        Benchmarks {
            cases,
            merged,
            ..self.clone()
        }
    }
}

/// The UTC day of `time` as `YYYY-MM-DD` (the proleptic Gregorian calendar;
/// a time before 1970 gives 1970-01-01).
pub fn utc_date(time: std::time::SystemTime) -> String {
    let seconds = time
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    // Days since 1970-01-01 to a civil date (H. Hinnant's algorithm).
    let z = (seconds / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// Every iteration record of the run summarized in `s` after its first, in
/// order, each with whether it is its increment's last (the accepted pattern's
/// complete solve, or a reuse) rather than a trial.
fn later_iterations(s: &Summary) -> Vec<(&Iteration, bool)> {
    s.iteration_history
        .iter()
        .flat_map(|its| {
            let n = its.len();
            its.iter().enumerate().map(move |(i, it)| (it, i + 1 == n))
        })
        .skip(1)
        .collect()
}

/// A number as JSON writes it (`100.0`, `1e-7`): how the report showed the
/// values it read untyped.
fn json_number(x: f64) -> String {
    serde_json::Value::from(x).to_string()
}

/// Hand-made summaries for the tests.
#[cfg(test)]
pub(crate) mod fixture {
    use cfe::Summary;
    use serde_json::Value;

    /// Every key of a summary, zero or empty.
    const ZEROS: &str = r#"{
        "status": "completed", "error": null, "warnings": [], "violations": [],
        "max_violation": 0.0,
        "tolerances": {"tension": 1e-6, "penetration": 1e-4, "max_violation": 1e-2,
            "residual_warn": 1e-8, "residual_fail": 1e-4},
        "title": "test", "problem": "test.toml", "refine": 1, "scheme": "active-set",
        "unknowns": 0, "matrix_nonzeros": 0, "factor_nonzeros": 0, "parts": [],
        "interfaces": [], "increments": 1, "converged_increments": 1, "iterations": [],
        "iteration_history": [], "factorizations": 0, "low_rank_updates": 0,
        "first_factorization_seconds": null,
        "max_displacement": {"value": 0.0, "x": 0.0, "y": 0.0, "part": "p", "node": 0},
        "reactions": [], "applied": [0.0, 0.0], "equilibrium_error": 0.0, "residual": 0.0,
        "proportional_shortcut": true, "proportional_shortcut_off": null, "steps": [],
        "increment_steps": [], "fixed_point_iterations": [], "augmented_penetration": 0.0,
        "notes": [], "peak_memory_bytes": null, "peak_over_factor": null, "solve_flops": 0.0,
        "total_over_factorization": null, "threads": 1,
        "timings": {"meshing": 0.0, "pair_search": 0.0, "coarse_start": 0.0,
            "pattern_and_symbolic": 0.0, "assembly": 0.0, "factorization": 0.0, "solve": 0.0,
            "contact_update": 0.0, "stress_recovery": 0.0, "output": 0.0, "pictures": 0.0,
            "total": 0.0, "cpu": null}
    }"#;

    /// A summary of zeros (no interface, no iteration) with the keys of `patch`
    /// set (objects merged key by key).
    pub fn summary(patch: Value) -> Summary {
        let mut base: Value = serde_json::from_str(ZEROS).expect("valid JSON");
        merge(&mut base, patch);
        serde_json::from_value(base).expect("a complete summary")
    }

    fn merge(base: &mut Value, patch: Value) {
        match (base, patch) {
            (Value::Object(b), Value::Object(p)) => {
                for (k, v) in p {
                    merge(b.entry(k).or_insert(Value::Null), v);
                }
            }
            (b, p) => *b = p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `benchmarks.json` reads back as written: a run's summary as a summary, a
    /// failed frictional run as its error; a file from before the machine's
    /// speed was measured has none, and one run per case.
    #[test]
    fn the_raw_results_read_back() {
        let ran = fixture::summary(serde_json::json!({"unknowns": 910, "timings": {"total": 1.5}}));
        let cases = vec![
            Case {
                problem: Group::Plate,
                law: Law::Contact,
                refine: 1,
                ranks: None,
                summary: Outcome::Ran(Box::new(ran)),
            },
            Case {
                problem: Group::Friction,
                law: Law::Coulomb,
                refine: 2,
                ranks: Some(2),
                summary: Outcome::Failed("no convergence".into()),
            },
        ];
        let b = Benchmarks {
            problem: "plate.toml".into(),
            machine: "m".into(),
            speed: None,
            repeat: 3,
            commit: "abc".into(),
            date: None,
            cases,
            merged: vec![],
        };
        let value = serde_json::to_value(&b).unwrap();
        assert_eq!(
            value["cases"][1]["summary"],
            serde_json::json!({"status": "failed", "error": "no convergence"})
        );
        let read: Benchmarks = serde_json::from_value(value).unwrap();
        assert_eq!(read.cases[0].ran().map(|s| s.unknowns), Some(910));
        assert_eq!(read.cases[0].summary.total_seconds(), 1.5);
        assert!(matches!(&read.cases[1].summary, Outcome::Failed(e) if e == "no convergence"));
        assert_eq!(read.cases[1].summary.total_seconds(), f64::INFINITY);
        let old: Benchmarks = serde_json::from_value(serde_json::json!({
            "problem": "p.toml", "machine": "m", "commit": "c", "cases": []
        }))
        .unwrap();
        assert_eq!((old.speed, old.repeat), (None, 1));
    }

    /// A summary missing a field is refused with the field's name, not taken
    /// for a failed run.
    #[test]
    fn an_incomplete_summary_names_its_missing_field() {
        let e = serde_json::from_value::<Outcome>(serde_json::json!({"status": "completed"}))
            .unwrap_err();
        assert!(e.to_string().contains("missing field"), "{e}");
    }

    /// A case of `group` at refinement `refine` whose run took `total` seconds.
    fn case(group: Group, refine: usize, total: f64) -> Case {
        let summary = fixture::summary(serde_json::json!({"timings": {"total": total}}));
        Case {
            problem: group,
            law: Law::Frictionless,
            refine,
            ranks: None,
            summary: Outcome::Ran(Box::new(summary)),
        }
    }

    /// Results of one run at `commit` on `day` with `cases`.
    fn results(commit: &str, day: &str, cases: Vec<Case>) -> Benchmarks {
        Benchmarks {
            problem: format!("{commit}.toml").into(),
            machine: format!("machine of {commit}"),
            speed: None,
            repeat: 1,
            commit: commit.into(),
            date: Some(day.into()),
            cases,
            merged: vec![],
        }
    }

    /// Merging a run of the 3D rows into results of 2D and 3D rows replaces
    /// exactly the 3D rows, keeps the 2D ones with their own commit and day,
    /// records where the 3D rows were measured (and only once when merged
    /// again), survives the JSON round trip, is stated in the report group
    /// by group, and gives the new run itself when it replaces every group.
    #[test]
    fn merging_replaces_only_the_measured_groups() {
        let old = results(
            "aaa",
            "2026-11-01",
            vec![
                case(Group::Plate, 1, 1.0),
                case(Group::Plate, 2, 2.0),
                case(Group::Solid, 1, 9.0),
            ],
        );
        let new = results(
            "bbb",
            "2026-11-28",
            vec![case(Group::Solid, 1, 3.0), case(Group::Solid, 2, 4.0)],
        );
        let merged = old.merge(&new);
        let rows: Vec<(Group, usize, f64)> = merged
            .cases
            .iter()
            .map(|c| (c.problem, c.refine, c.summary.total_seconds()))
            .collect();
        assert_eq!(
            rows,
            [
                (Group::Plate, 1, 1.0),
                (Group::Plate, 2, 2.0),
                (Group::Solid, 1, 3.0),
                (Group::Solid, 2, 4.0)
            ]
        );
        assert_eq!(
            (merged.commit.as_str(), merged.date.as_deref()),
            ("aaa", Some("2026-11-01"))
        );
        assert_eq!(merged.origin(Group::Plate).commit, "aaa");
        let solid = merged.origin(Group::Solid);
        assert_eq!(
            (solid.commit.as_str(), solid.date.as_deref()),
            ("bbb", Some("2026-11-28"))
        );
        assert_eq!(solid.machine, "machine of bbb");
        // Merged again with a later 3D run: one record of where the 3D rows are from.
        let later = results("ccc", "2026-11-29", vec![case(Group::Solid, 1, 2.5)]);
        let again = merged.merge(&later);
        assert_eq!(again.merged.len(), 1);
        assert_eq!(again.origin(Group::Solid).commit, "ccc");
        assert_eq!(again.cases.len(), 3);
        // The JSON keeps where each group is from.
        let read: Benchmarks =
            serde_json::from_value(serde_json::to_value(&again).unwrap()).unwrap();
        assert_eq!(read.merged, again.merged);
        assert_eq!(read.origin(Group::Plate).commit, "aaa");
        // The report says it group by group.
        let text = report::report(&merged);
        assert!(
            text.contains(
                "The rows of `plate` are from the run described above (commit `aaa`, 2026-11-01)"
            ) && text.contains("The rows of `solid`: commit `bbb`, 2026-11-28, machine of bbb"),
            "{text}"
        );
        assert!(!report::report(&old).contains("merges runs made apart"));
        // A run of every group replaces the whole file.
        let all = results(
            "ddd",
            "2026-12-01",
            vec![case(Group::Plate, 1, 0.5), case(Group::Solid, 1, 0.7)],
        );
        let replaced = merged.merge(&all);
        assert_eq!(
            (
                replaced.commit.as_str(),
                replaced.merged.len(),
                replaced.cases.len()
            ),
            ("ddd", 0, 2)
        );
    }

    /// The UTC day of a time, against dates whose Unix times are known
    /// (a leap day, the turn of a century, the epoch).
    #[test]
    fn utc_dates() {
        let at = |s: u64| utc_date(std::time::UNIX_EPOCH + std::time::Duration::from_secs(s));
        assert_eq!(at(0), "1970-01-01");
        assert_eq!(at(951_782_400), "2000-02-29");
        assert_eq!(at(951_782_400 - 1), "2000-02-28");
        assert_eq!(at(946_598_400 + 86_399), "1999-12-31");
        assert_eq!(at(1_795_824_000 + 45_000), "2026-11-28");
    }
}
