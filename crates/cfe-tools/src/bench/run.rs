//! Running the benchmark: every case in its own `cfe run` process (so peak memory
//! is that run's), in passes over all the cases with each case's fastest run
//! kept, the machine's speed measured before and after; the results go to
//! `benchmarks.json` and the report.

use super::plan::{
    FRICTION, Planned, Probe, gmsh_problem, petsc_plan, plan, solid_plan, solid_problem,
};
use super::{Benchmarks, Case, Group, Only, Outcome, Speeds, report};
use crate::speed::MachineSpeed;
use cfe::error::{Error, Result};
use cfe::{Law, Summary};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs the benchmark with the `cfe` executable `exe` and writes the report into
/// `out` (`benchmarks.json`, `benchmarks.md`, `benchmarks.png`). Every case is run
/// in each of `repeat` passes (at least one) over all the cases and its fastest
/// run end to end is kept, all its phases from that run. `progress` receives one
/// line per run. `only` runs some rows alone ([`Only`]), of `problem` when it
/// is a solid model, else of the 3D problem beside it
/// (`plate_on_base_3d_bench.toml`); [`Only::Petsc`] needs `exe` built with
/// the `petsc` feature and, for its 2-rank rows, Open MPI's `mpirun` on the
/// `PATH` (the caller checks the first).
/// `merge`: the results already in `out/benchmarks.json` (read before anything
/// runs) keep their other row groups, the groups this run measures replaced
/// ([`Benchmarks::merge`]), and the report is written from the merged file.
#[allow(clippy::too_many_arguments)]
pub fn run(
    exe: &Path,
    problem: &Path,
    max_unknowns: usize,
    repeat: usize,
    out: &Path,
    only: Option<Only>,
    merge: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<Case>> {
    let repeat = repeat.max(1);
    let earlier = if merge {
        Some(read_benchmarks(&out.join("benchmarks.json"))?)
    } else {
        None
    };
    std::fs::create_dir_all(out).map_err(|e| Error::output(out, e))?;
    let runner = Runner {
        exe,
        scratch: std::env::temp_dir().join(format!("cfe-bench-{}", std::process::id())),
    };
    let (problem, planned) = if let Some(only) = only {
        let solid = match cfe::model::problem_dimension(problem)? {
            cfe::model::ProblemDimension::Solid => problem.to_path_buf(),
            _ => solid_problem(problem).ok_or_else(|| {
                Error::Model(format!(
                    "no 3D benchmark problem: {} is not a solid model and plate_on_base_3d_bench.toml is not beside it; give one with --problem FILE",
                    problem.display()
                ))
            })?,
        };
        let n = runner.solid_sizes(&solid)?;
        let planned = match only {
            Only::Solid => solid_plan(&solid, n),
            Only::Petsc => petsc_plan(&solid, n, max_unknowns),
        };
        (solid.clone(), planned)
    } else {
        (
            problem.to_path_buf(),
            plan(problem, max_unknowns, &runner.probe(problem)?),
        )
    };
    let problem = problem.as_path();
    // The machine's speed, once the problem is known to run.
    let before = MachineSpeed::measure();
    progress(&format!("machine speed before: {}", before.describe()));
    let best = fastest_in_passes(
        &planned,
        repeat,
        |case, pass| runner.outcome(case, pass, repeat, progress),
        Outcome::total_seconds,
    )?;
    let _ = std::fs::remove_dir_all(&runner.scratch);
    let cases: Vec<Case> = planned
        .iter()
        .zip(best)
        .map(|(case, summary)| Case {
            problem: case.group,
            law: case.law,
            refine: case.refine,
            ranks: case.ranks,
            summary,
        })
        .collect();
    let after = MachineSpeed::measure();
    progress(&format!("machine speed after:  {}", after.describe()));
    let raw = Benchmarks {
        problem: problem.to_path_buf(),
        machine: machine(),
        speed: Some(Speeds { before, after }),
        repeat,
        commit: commit(),
        date: Some(super::utc_date(std::time::SystemTime::now())),
        cases,
        merged: Vec::new(),
    };
    let raw = match earlier {
        Some(earlier) => earlier.merge(&raw),
        None => raw,
    };
    raw.write(&out.join("benchmarks.json"))?;
    report::write_report(out, &raw)?;
    Ok(raw.cases)
}

/// Reads the results of a benchmark (`benchmarks.json`).
pub fn read_benchmarks(path: &Path) -> Result<Benchmarks> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Parse {
        line: None,
        message: format!("cannot read the benchmark's results to merge into: {e}"),
        path: path.to_path_buf(),
    })?;
    serde_json::from_str(&text).map_err(|e| Error::Parse {
        line: Some(e.line()),
        message: format!("not a benchmark's results (benchmarks.json): {e}"),
        path: path.to_path_buf(),
    })
}

/// Runs `cfe run` as a child process, each run in its own folder under `scratch`.
struct Runner<'a> {
    exe: &'a Path,
    scratch: PathBuf,
}

impl Runner<'_> {
    /// The sizes the plan is made from: `problem` at K = 1 and 2, the Gmsh
    /// problem (when there) at K = 1, one `contact` run each, and the 3D
    /// problem (when there) as [`Runner::solid_sizes`].
    fn probe(&self, problem: &Path) -> Result<Probe> {
        let unknowns = |path: &Path, k| Ok(self.summary(path, Law::Contact, k, None)?.unknowns);
        let (n1, n2) = (unknowns(problem, 1)?, unknowns(problem, 2)?);
        let gmsh = match gmsh_problem(problem) {
            Some(roller) => Some((roller.clone(), unknowns(&roller, 1)?)),
            None => None,
        };
        let solid = match solid_problem(problem) {
            Some(solid) => Some((solid.clone(), self.solid_sizes(&solid)?)),
            None => None,
        };
        Ok(Probe {
            n1,
            n2,
            gmsh,
            solid,
        })
    }

    /// The unknowns of the 3D problem `solid` at K = 1, 2 and 3, one
    /// `frictionless` run each.
    fn solid_sizes(&self, solid: &Path) -> Result<[usize; 3]> {
        let mut n = [0; 3];
        for (k, v) in n.iter_mut().enumerate() {
            *v = self
                .summary(solid, Law::Frictionless, k + 1, None)?
                .unknowns;
        }
        Ok(n)
    }

    /// Runs `problem` with `law` refined `refine` times (on `--solver petsc`
    /// on `ranks` MPI ranks when given) and reads its summary (rank 0's).
    fn summary(
        &self,
        problem: &Path,
        law: Law,
        refine: usize,
        ranks: Option<usize>,
    ) -> Result<Summary> {
        let dir = self
            .scratch
            .join(format!("{}-{refine}-{}", law.as_str(), ranks.unwrap_or(0)));
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut command = run_command(self.exe, problem, (law, refine, ranks), &dir, cores);
        let child = command
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .output()
            .map_err(|e| {
                let what = match ranks {
                    Some(r) if r > 1 => "mpirun (Open MPI's openmpi-bin, on the PATH)",
                    _ => "the benchmark run",
                };
                Error::output(self.exe, format!("cannot start {what}: {e}"))
            })?;
        if !child.status.success() {
            let _ = std::fs::remove_dir_all(&dir);
            return Err(Error::Subprocess {
                command: format!(
                    "{} {}",
                    command.get_program().to_string_lossy(),
                    command
                        .get_args()
                        .map(|a| a.to_string_lossy())
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
                status: child.status.code(),
                stderr: error_lines(&String::from_utf8_lossy(&child.stderr)),
            });
        }
        let path = dir.join("summary.json");
        let text = std::fs::read_to_string(&path).map_err(|e| Error::output(&path, e))?;
        let summary: Summary = serde_json::from_str(&text).map_err(|e| Error::Parse {
            line: Some(e.line()),
            message: format!("not a summary of this version of cfe: {e}"),
            path: path.clone(),
        })?;
        let _ = std::fs::remove_dir_all(&dir);
        Ok(summary)
    }

    /// Runs a planned case in pass `pass` of `repeat` and reports it in one line:
    /// its size, time and peak memory, or (a `coulomb` or `frictionless` run,
    /// which is reported, not fatal: the rows before it stand) why it failed.
    fn outcome(
        &self,
        case: &Planned,
        pass: usize,
        repeat: usize,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Outcome> {
        let k = case.refine;
        let of = if repeat > 1 {
            format!(" (run {pass} of {repeat})")
        } else {
            String::new()
        };
        match self.summary(&case.path, case.law, k, case.ranks) {
            Ok(s) => {
                // The Gmsh problem is named by its row group, the others by law.
                let name = match (case.group, case.ranks) {
                    (Group::Gmsh, _) => "gmsh".to_string(),
                    (Group::Solid, _) => "3d".to_string(),
                    (Group::Petsc, Some(r)) => format!("petsc×{r}"),
                    _ => case.law.as_str().to_string(),
                };
                progress(&format!(
                    "{name:>7} K = {k:>3}: {:>9} unknowns, {:>8.2} s, {:>7.0} MiB{of}",
                    s.unknowns,
                    s.timings.total,
                    s.peak_memory_bytes.unwrap_or(0) as f64 / 1048576.0
                ));
                Ok(Outcome::Ran(Box::new(s)))
            }
            Err(e) if matches!(case.law, Law::Coulomb | Law::Frictionless) => {
                // A 3D row that fails (e.g. beyond the memory) is reported
                // as failed: the rows before it stand.
                progress(&format!(
                    "{:>7} K = {k:>3}: failed: {e}{of}",
                    case.law.as_str()
                ));
                Ok(Outcome::Failed(e.to_string()))
            }
            Err(e) => Err(e),
        }
    }
}

/// The command of one run: `exe run PROBLEM` with [`run_args`] and `--out
/// dir`; on `--solver petsc` when `ranks` is given, and for more than one
/// rank under `mpirun -n RANKS` with each rank `cores / RANKS` threads
/// (`RAYON_NUM_THREADS`, at least 1, exported to the ranks with `-x`: every
/// rank the same, as the replicated contact scheme needs). One rank runs
/// without `mpirun`, with the default threads (all cores).
fn run_command(
    exe: &Path,
    problem: &Path,
    (law, refine, ranks): (Law, usize, Option<usize>),
    dir: &Path,
    cores: usize,
) -> Command {
    let mut command = match ranks {
        Some(r) if r > 1 => {
            let mut c = Command::new("mpirun");
            c.env("RAYON_NUM_THREADS", (cores / r).max(1).to_string())
                .args(["-n", &r.to_string(), "-x", "RAYON_NUM_THREADS"])
                .arg(exe);
            c
        }
        _ => Command::new(exe),
    };
    command
        .arg("run")
        .arg(problem)
        .args(run_args(law, refine))
        .arg("--out")
        .arg(dir);
    if ranks.is_some() {
        command.args(["--solver", "petsc"]);
    }
    command
}

/// The arguments of `cfe run` after the problem: refinement, law and (Coulomb)
/// the benchmark's friction coefficient.
fn run_args(law: Law, refine: usize) -> Vec<String> {
    let mut args = vec![
        "--refine".to_string(),
        refine.to_string(),
        "--law".to_string(),
        law.as_str().to_string(),
    ];
    if law == Law::Coulomb {
        args.extend(["--friction".to_string(), FRICTION.to_string()]);
    }
    args
}

/// What a failed child said went wrong: its error and warning lines (its
/// progress output left out), or its last 20 lines when it has none.
fn error_lines(stderr: &str) -> String {
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error") || l.starts_with("warning"))
        .collect();
    let text = if errors.is_empty() {
        stderr.lines().rev().take(20).collect::<Vec<_>>().join("\n")
    } else {
        errors.join("\n")
    };
    text.trim().to_string()
}

/// Runs every case once in each of `repeat` passes (at least one) over all the
/// cases (`run(case, pass)`, passes counted from 1) and keeps each case's fastest
/// result by `seconds` end to end: a case's runs lie a whole pass apart, so a slow
/// spell of the machine touches one of them, not all. A failed run (infinite
/// seconds) is kept only when no run of its case succeeded; an error ends the
/// benchmark.
fn fastest_in_passes<C, T>(
    cases: &[C],
    repeat: usize,
    mut run: impl FnMut(&C, usize) -> Result<T>,
    seconds: impl Fn(&T) -> f64,
) -> Result<Vec<T>> {
    let mut best: Vec<Option<T>> = cases.iter().map(|_| None).collect();
    for pass in 1..=repeat.max(1) {
        for (case, kept) in cases.iter().zip(best.iter_mut()) {
            let result = run(case, pass)?;
            if kept.as_ref().is_none_or(|b| seconds(&result) < seconds(b)) {
                *kept = Some(result);
            }
        }
    }
    // At least one pass: every case has a result.
    Ok(best.into_iter().flatten().collect())
}

/// The processor, its cores and the memory of this machine.
fn machine() -> String {
    let cpu = cfe::output::memory::cpu_model().unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let mem = cfe::output::memory::total_memory_bytes()
        .map(|b| format!("{:.0} GiB", b as f64 / 1073741824.0))
        .unwrap_or_else(|| "unknown memory".into());
    format!("{cpu}, {cores} cores, {mem}")
}

/// The commit checked out in the current folder (`unknown` outside a repository).
fn commit() -> String {
    Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    /// Three passes over two cases run them in turn (a b a b a b, not a a a b b b)
    /// and keep each case's fastest run end to end; a failed run (infinite
    /// seconds) gives way to any run of its case that succeeded, and an error ends
    /// it all.
    #[test]
    fn each_pass_runs_every_case_and_the_fastest_is_kept() {
        let totals = [[2.0, 1.5, 3.0], [f64::INFINITY, 4.0, 5.0]];
        let mut order = Vec::new();
        // Each run gives (seconds, pass).
        let best = super::fastest_in_passes(
            &[0usize, 1],
            3,
            |&case, pass| {
                order.push((case, pass));
                Ok((totals[case][pass - 1], pass))
            },
            |r| r.0,
        )
        .unwrap();
        assert_eq!(order, [(0, 1), (1, 1), (0, 2), (1, 2), (0, 3), (1, 3)]);
        assert_eq!(best[0].1, 2, "case 0's fastest is its second run");
        assert_eq!(best[1].1, 2, "case 1's failed first run gives way");
        let failing = super::fastest_in_passes(
            &[0usize],
            2,
            |_, pass| {
                if pass == 2 {
                    Err(cfe::error::Error::output("x", "stopped"))
                } else {
                    Ok(1.0)
                }
            },
            |t| *t,
        );
        assert!(matches!(failing, Err(cfe::error::Error::Output { .. })));
    }

    /// A failed child's message is its error and warning lines, or without any
    /// its last lines (progress output left out when there are errors).
    #[test]
    fn a_failed_run_passes_its_error_lines_through() {
        let stderr = "[1/10] solving\nwarning: slow\nerror: no pairs found\n[2/10]\n";
        assert_eq!(
            super::error_lines(stderr),
            "warning: slow\nerror: no pairs found"
        );
        assert_eq!(super::error_lines("killed\n"), "killed");
    }

    /// A direct row is `cfe run` alone; a PETSc row on one rank adds `--solver
    /// petsc`; on two ranks it runs under `mpirun -n 2`, each rank with half
    /// the cores' threads exported to it (one on one core, never zero).
    #[test]
    fn a_petsc_row_runs_on_petsc_under_mpirun() {
        use cfe::Law;
        use std::ffi::OsStr;
        use std::path::Path;
        let line = |c: &std::process::Command| {
            std::iter::once(c.get_program())
                .chain(c.get_args())
                .map(|a| a.to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join(" ")
        };
        let threads = |c: &std::process::Command| {
            c.get_envs()
                .find(|(k, _)| *k == OsStr::new("RAYON_NUM_THREADS"))
                .and_then(|(_, v)| v.map(|v| v.to_string_lossy().into_owned()))
        };
        let (exe, p, dir) = (Path::new("/b/cfe"), Path::new("p.toml"), Path::new("o"));
        let direct = super::run_command(exe, p, (Law::Frictionless, 4, None), dir, 2);
        assert_eq!(
            line(&direct),
            "/b/cfe run p.toml --refine 4 --law frictionless --out o"
        );
        let one = super::run_command(exe, p, (Law::Frictionless, 4, Some(1)), dir, 2);
        assert_eq!(
            line(&one),
            "/b/cfe run p.toml --refine 4 --law frictionless --out o --solver petsc"
        );
        assert_eq!(threads(&one), None);
        let two = super::run_command(exe, p, (Law::Frictionless, 4, Some(2)), dir, 2);
        assert_eq!(
            line(&two),
            "mpirun -n 2 -x RAYON_NUM_THREADS /b/cfe run p.toml --refine 4 --law frictionless --out o --solver petsc"
        );
        assert_eq!(threads(&two).as_deref(), Some("1"));
        let alone = super::run_command(exe, p, (Law::Frictionless, 4, Some(2)), dir, 1);
        assert_eq!(threads(&alone).as_deref(), Some("1"));
        let wide = super::run_command(exe, p, (Law::Frictionless, 4, Some(2)), dir, 8);
        assert_eq!(threads(&wide).as_deref(), Some("4"));
    }

    /// The frictional run gets the benchmark's friction coefficient; the others
    /// only refinement and law.
    #[test]
    fn run_arguments() {
        use cfe::Law;
        assert_eq!(
            super::run_args(Law::Coulomb, 3).join(" "),
            "--refine 3 --law coulomb --friction 0.2"
        );
        assert_eq!(
            super::run_args(Law::Rigid, 1).join(" "),
            "--refine 1 --law rigid"
        );
    }
}
