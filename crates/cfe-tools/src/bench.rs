//! Benchmark: runs a problem (by default the seed's plate on a base) with the
//! `rigid` and the `contact` law at refinements K = 1, 2, 4, … up to a number of
//! unknowns, each run in its own process (so peak memory is that run's), and
//! writes `benchmarks.md` with the phase timings and a log–log picture of time and
//! memory against unknowns.

use crate::speed::{MachineSpeed, figure};
use cfe::error::{Error, Result};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One benchmark run: its law, refinement and the summary it wrote.
pub struct Case {
    /// `plate` (the refined problem) or `gmsh` (the Gmsh problem refined).
    pub problem: &'static str,
    /// `rigid` or `contact`.
    pub law: &'static str,
    /// Refinement factor.
    pub refine: usize,
    /// The run's `summary.json`.
    pub summary: Value,
}

/// The refinement factors to run: 1, 2, 4, … doubling while within
/// `max_unknowns` and a million unknowns, then the first factors that reach the
/// reference sizes of 1 M and 4 M unknowns and `max_unknowns` itself (the last
/// replacing the last doubling when within 25 % of it). `unknowns(K)` predicts the
/// unknowns at refinement K.
pub fn refinements(unknowns: impl Fn(usize) -> f64, max_unknowns: usize) -> Vec<usize> {
    let max = max_unknowns as f64;
    let mut ks = vec![1usize];
    while unknowns(2 * ks.last().unwrap()) <= max.min(1e6) {
        ks.push(ks.last().unwrap() * 2);
    }
    let reaching = |size: f64| {
        let mut k = 1;
        while unknowns(k) < size {
            k += 1;
        }
        k
    };
    for size in [1e6, 4e6] {
        if size <= max {
            ks.push(reaching(size));
        }
    }
    let last = *ks.last().unwrap();
    let reach = reaching(max);
    if reach > last {
        if reach as f64 <= 1.25 * last as f64 && ks.len() > 1 {
            *ks.last_mut().unwrap() = reach;
        } else {
            ks.push(reach);
        }
    }
    ks.sort_unstable();
    ks.dedup();
    ks
}

/// The unknowns of a 2D structured model at refinement K, `a K² + b K`, fitted to
/// the counts at K = 1 and K = 2.
pub fn unknowns_model(n1: usize, n2: usize) -> impl Fn(usize) -> f64 {
    let (n1, n2) = (n1 as f64, n2 as f64);
    let a = (n2 - 2.0 * n1) / 2.0;
    let b = n1 - a;
    move |k: usize| a * (k * k) as f64 + b * k as f64
}

/// Runs the benchmark with the `cfe` executable `exe` and writes the report into
/// `out` (`benchmarks.md`, `benchmarks.png`). Every case is run in each of
/// `repeat` passes (at least one) over all the cases and its fastest run end to
/// end is kept, all its phases from that run. `progress` receives one line per
/// run.
pub fn run(
    exe: &Path,
    problem: &Path,
    max_unknowns: usize,
    repeat: usize,
    out: &Path,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<Case>> {
    let repeat = repeat.max(1);
    std::fs::create_dir_all(out).map_err(|e| Error::output(out, e))?;
    let scratch = std::env::temp_dir().join(format!("cfe-bench-{}", std::process::id()));
    let run_in = |problem: &Path, law: &'static str, refine: usize| -> Result<Value> {
        let dir = scratch.join(format!("{law}-{refine}"));
        let child = Command::new(exe)
            .arg("run")
            .arg(problem)
            .args(["--refine", &refine.to_string(), "--law", law])
            .args(if law == "coulomb" {
                vec!["--friction".to_string(), FRICTION.to_string()]
            } else {
                vec![]
            })
            .arg("--out")
            .arg(&dir)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .output()
            .map_err(|e| Error::output(exe, format!("cannot start the benchmark run: {e}")))?;
        if !child.status.success() {
            // The child's own message says what went wrong: pass it through
            // (its error lines; its progress output is left out).
            let stderr = String::from_utf8_lossy(&child.stderr);
            let errors: Vec<&str> = stderr
                .lines()
                .filter(|l| l.starts_with("error") || l.starts_with("warning"))
                .collect();
            let text = if errors.is_empty() {
                stderr.lines().rev().take(20).collect::<Vec<_>>().join("\n")
            } else {
                errors.join("\n")
            };
            let _ = std::fs::remove_dir_all(&dir);
            return Err(Error::Subprocess {
                command: format!(
                    "cfe run {} --refine {refine} --law {law}{}",
                    problem.display(),
                    if law == "coulomb" {
                        format!(" --friction {FRICTION}")
                    } else {
                        String::new()
                    }
                ),
                status: child.status.code(),
                stderr: text.trim().to_string(),
            });
        }
        let summary_path = dir.join("summary.json");
        let text =
            std::fs::read_to_string(&summary_path).map_err(|e| Error::output(&summary_path, e))?;
        let summary: Value =
            serde_json::from_str(&text).map_err(|e| Error::output(&summary_path, e))?;
        let _ = std::fs::remove_dir_all(&dir);
        Ok(summary)
    };
    // The unknowns at K = 1 and 2 (one run each) fit the model that picks the
    // refinements.
    let count = |s: Value| s["unknowns"].as_u64().unwrap_or(1) as usize;
    let (n1, n2) = (
        count(run_in(problem, "contact", 1)?),
        count(run_in(problem, "contact", 2)?),
    );
    let ks = refinements(unknowns_model(n1, n2), max_unknowns);
    let mut plan: Vec<Planned> = Vec::new();
    for law in ["rigid", "contact"] {
        plan.extend(ks.iter().map(|&refine| Planned {
            path: problem.to_path_buf(),
            problem: "plate",
            law,
            refine,
        }));
    }
    plan.extend(extra_cases(problem, max_unknowns, n1, &run_in)?);
    // The machine's speed, once the problem is known to run.
    let speed_before = MachineSpeed::measure();
    progress(&format!(
        "machine speed before: {}",
        speed_before.describe()
    ));
    let best = fastest_in_passes(&plan, repeat, |case, pass| {
        let k = case.refine;
        let of = if repeat > 1 {
            format!(" (run {pass} of {repeat})")
        } else {
            String::new()
        };
        match run_in(&case.path, case.law, k) {
            Ok(summary) => {
                // The Gmsh problem is named by its row group, the others by law.
                let name = if case.problem == "gmsh" {
                    "gmsh"
                } else {
                    case.law
                };
                progress(&format!(
                    "{name:>7} K = {k:>3}: {:>9} unknowns, {:>8.2} s, {:>7.0} MiB{of}",
                    summary["unknowns"],
                    total_seconds(&summary),
                    summary["peak_memory_bytes"].as_f64().unwrap_or(0.0) / 1048576.0
                ));
                Ok(summary)
            }
            // A failed frictional run is reported, not fatal: the rows before it
            // stand.
            Err(e) if case.law == "coulomb" => {
                progress(&format!("coulomb K = {k:>3}: failed: {e}{of}"));
                Ok(serde_json::json!({"status": "failed", "error": e.to_string()}))
            }
            Err(e) => Err(e),
        }
    })?;
    let cases: Vec<Case> = plan
        .iter()
        .zip(best)
        .map(|(case, summary)| Case {
            problem: case.problem,
            law: case.law,
            refine: case.refine,
            summary,
        })
        .collect();
    let _ = std::fs::remove_dir_all(&scratch);
    let raw: Vec<Value> = cases
        .iter()
        .map(|c| serde_json::json!({"problem": c.problem, "law": c.law, "refine": c.refine, "summary": c.summary}))
        .collect();
    let speed_after = MachineSpeed::measure();
    progress(&format!("machine speed after:  {}", speed_after.describe()));
    let speed =
        serde_json::json!({"before": speed_before.to_json(), "after": speed_after.to_json()});
    let header = serde_json::json!({"problem": problem, "machine": machine(), "speed": speed, "repeat": repeat, "commit": commit(), "cases": raw});
    cfe::output::report::write_json(&out.join("benchmarks.json"), &header)?;
    write_report(out, &header)?;
    Ok(cases)
}

/// A run's end-to-end seconds (infinite for a failed run, which has none).
fn total_seconds(summary: &Value) -> f64 {
    summary["timings"]["total"]
        .as_f64()
        .unwrap_or(f64::INFINITY)
}

/// Runs every case once in each of `repeat` passes (at least one) over all the
/// cases (`run(case, pass)`, passes counted from 1) and keeps each case's fastest
/// summary end to end: a case's runs lie a whole pass apart, so a slow spell of
/// the machine touches one of them, not all. A failed run (no total) is kept only
/// when no run of its case succeeded; an error ends the benchmark.
fn fastest_in_passes<C>(
    cases: &[C],
    repeat: usize,
    mut run: impl FnMut(&C, usize) -> Result<Value>,
) -> Result<Vec<Value>> {
    let mut best: Vec<Option<Value>> = vec![None; cases.len()];
    for pass in 1..=repeat.max(1) {
        for (case, kept) in cases.iter().zip(best.iter_mut()) {
            let summary = run(case, pass)?;
            if kept
                .as_ref()
                .is_none_or(|b| total_seconds(&summary) < total_seconds(b))
            {
                *kept = Some(summary);
            }
        }
    }
    Ok(best.into_iter().map(|b| b.unwrap_or(Value::Null)).collect())
}

/// A case the benchmark runs: the problem file, its row group and law, and the
/// refinement.
struct Planned {
    path: PathBuf,
    /// `plate`, `gmsh` or `friction` (the report's row groups).
    problem: &'static str,
    law: &'static str,
    refine: usize,
}

/// The cases beside the refined problem: one Gmsh problem (the roller in its
/// cradle, next to the problem file's folder as in the repository's examples,
/// when it is there) and one frictional run of the problem, each at about a
/// quarter of the largest size (at most a million unknowns). The roller's
/// refinement comes from its unknowns at K = 1 (one run); `n1` is the problem's.
fn extra_cases(
    problem: &Path,
    max_unknowns: usize,
    n1: usize,
    run_in: &dyn Fn(&Path, &'static str, usize) -> Result<Value>,
) -> Result<Vec<Planned>> {
    let target = (max_unknowns as f64 / 4.0).min(1e6);
    let refine_for = |n1: f64| ((target / n1.max(1.0)).sqrt().floor() as usize).max(1);
    let mut cases = Vec::new();
    let roller = problem
        .parent()
        .unwrap_or(Path::new("."))
        .join("roller_in_cradle/roller_in_cradle.toml");
    if roller.exists() {
        let first = run_in(&roller, "contact", 1)?;
        cases.push(Planned {
            refine: refine_for(first["unknowns"].as_f64().unwrap_or(1.0)),
            path: roller,
            problem: "gmsh",
            law: "contact",
        });
    }
    // Every increment of a frictional run is solved (no proportional shortcut).
    cases.push(Planned {
        path: problem.to_path_buf(),
        problem: "friction",
        law: "coulomb",
        refine: refine_for(n1 as f64),
    });
    Ok(cases)
}

/// Friction coefficient of the benchmark's frictional run.
pub const FRICTION: f64 = 0.2;

/// The cost of one coupling formulation on a benchmark problem (see
/// [`coupling_cost`]).
#[derive(Debug, Clone)]
pub struct CouplingCost {
    /// `node` or `segment`.
    pub coupling: &'static str,
    /// Unknowns of the model.
    pub unknowns: usize,
    /// Coupling elements over all interfaces.
    pub pairs: usize,
    /// Nonzeros of the Cholesky factor.
    pub factor_nonzeros: usize,
    /// Pair search (and, for `segment`, the face integration) with DOF numbering, s.
    pub pair_search: f64,
    /// Node graph, ordering, pattern and symbolic factorization, s.
    pub pattern: f64,
    /// Assembly of K, s.
    pub assembly: f64,
    /// Numeric factorization, s.
    pub factorization: f64,
}

/// Solves `problem` refined `refine` times, tied (every interface `rigid`, one
/// increment: one assembly and one factorization), once with `coupling = "node"`
/// and once with `coupling = "segment"` on every interface, in this process, and
/// returns the cost of each. The two runs differ only in the coupling elements, so
/// the ratio of their assembly + factorization times is the segment coupling's
/// cost.
pub fn coupling_cost(problem: &Path, refine: usize) -> Result<Vec<CouplingCost>> {
    use cfe::coupling::{Coupling, Law};
    let mut rows = Vec::new();
    for (name, coupling) in [("node", Coupling::Node), ("segment", Coupling::Segment)] {
        let mut model = cfe::model::Model::from_file(problem, refine)?;
        for def in &mut model.interfaces {
            def.coupling = coupling;
        }
        model.settings.increments = 1;
        let mut a = cfe::analysis::Analysis::new(model)?;
        a.override_law(Law::Rigid);
        let pair_search = a.timings.pair_search;
        let r = a.solve()?;
        let t = &r.summary.timings.solve;
        rows.push(CouplingCost {
            coupling: name,
            unknowns: r.summary.unknowns,
            pairs: a.interfaces.iter().map(|i| i.elements.len()).sum(),
            factor_nonzeros: r.summary.factor_nonzeros,
            pair_search,
            pattern: t.pattern_and_symbolic,
            assembly: t.assembly,
            factorization: t.factorization,
        });
    }
    Ok(rows)
}

/// The rows of [`coupling_cost`] as a Markdown table, with the segment / node
/// ratio of assembly + factorization.
pub fn coupling_cost_table(rows: &[CouplingCost]) -> String {
    let mut s = String::from(
        "| coupling | unknowns | pairs | factor nonzeros | pair search (s) | pattern + symbolic (s) | assembly (s) | factorization (s) | assembly + factorization (s) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
            r.coupling,
            r.unknowns,
            r.pairs,
            r.factor_nonzeros,
            r.pair_search,
            r.pattern,
            r.assembly,
            r.factorization,
            r.assembly + r.factorization
        );
    }
    if let [node, segment] = rows {
        let _ = writeln!(
            s,
            "\nsegment / node, assembly + factorization: {:.3}",
            (segment.assembly + segment.factorization) / (node.assembly + node.factorization)
        );
    }
    s
}

/// Writes `benchmarks.md` and `benchmarks.png` in `out` from the raw results
/// (`benchmarks.json`, as written by [`run`]), so the report can be regenerated
/// without running the benchmark again.
pub fn write_report(out: &Path, raw: &Value) -> Result<()> {
    let cases: Vec<Case> = raw["cases"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|c| Case {
                    problem: if c["problem"] == "gmsh" {
                        "gmsh"
                    } else if c["problem"] == "friction" {
                        "friction"
                    } else {
                        "plate"
                    },
                    law: if c["law"] == "rigid" {
                        "rigid"
                    } else if c["law"] == "coulomb" {
                        "coulomb"
                    } else {
                        "contact"
                    },
                    refine: c["refine"].as_u64().unwrap_or(0) as usize,
                    summary: c["summary"].clone(),
                })
                .collect()
        })
        .unwrap_or_default();
    let plate: Vec<Case> = cases
        .iter()
        .filter(|c| c.problem == "plate")
        .map(Case::clone_ref)
        .collect();
    plot(&out.join("benchmarks.png"), &plate)?;
    let problem = PathBuf::from(raw["problem"].as_str().unwrap_or("?"));
    let md = report(
        &problem,
        raw["machine"].as_str().unwrap_or("?"),
        &raw["speed"],
        raw["commit"].as_str().unwrap_or("?"),
        raw["repeat"].as_u64().unwrap_or(1) as usize,
        &cases,
    );
    cfe::output::write_atomic(&out.join("benchmarks.md"), |w| w.write_all(md.as_bytes()))
}

impl Case {
    fn clone_ref(c: &Case) -> Case {
        Case {
            problem: c.problem,
            law: c.law,
            refine: c.refine,
            summary: c.summary.clone(),
        }
    }
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(0.0)
}

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

fn commit() -> String {
    Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

/// The report's line on the machine's speed before and after the runs (`None`
/// for a report written before the speed was measured).
fn speed_line(speed: &Value) -> Option<String> {
    let before = MachineSpeed::from_json(&speed["before"])?;
    let after = MachineSpeed::from_json(&speed["after"])?;
    let pair = |a: Option<f64>, b: Option<f64>| format!("{} / {}", figure(a), figure(b));
    Some(format!(
        "Machine speed before / after the runs (`cfe bench --speed` measures it alone): dense product {} Gflop/s (n = 1024, faer, all threads), memory copy {} GB/s (256 MiB, read + write), fresh memory {} GB/s (256 MiB written once: page faults and the kernel's zeroing of new pages). Times from another report compare through these: the factorization follows the dense product, the solves and the output the memory copy, a new factor's first touch the fresh memory.\n",
        pair(before.dense_gflops, after.dense_gflops),
        pair(before.copy_gb_per_s, after.copy_gb_per_s),
        pair(before.fresh_gb_per_s, after.fresh_gb_per_s),
    ))
}

fn report(
    problem: &Path,
    machine: &str,
    speed: &Value,
    commit: &str,
    repeat: usize,
    cases: &[Case],
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Benchmark: {} refined\n", problem.display());
    let _ = writeln!(
        s,
        "Generated by `cargo run --release -- bench --out docs{}` (see README). Machine: {}. Commit `{}`. Each row is {} `cfe run --refine K --law LAW` in its own process, 10 load increments, all outputs written (a VTU per increment, CSV, JSON, two PNGs). Times in seconds.\n",
        if repeat > 1 {
            format!(" --repeat {repeat}")
        } else {
            String::new()
        },
        machine,
        commit,
        if repeat > 1 {
            format!(
                "the fastest end to end of {repeat} runs (one in each of {repeat} passes over all the cases, so a slow spell of the machine touches one of them; all its phases from that run) of"
            )
        } else {
            "one".to_string()
        }
    );
    if let Some(line) = speed_line(speed) {
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(
        s,
        "*status* is the run's (`completed`: the law holds on every pair and the loads balance; otherwise how many pairs the last increment left off the law, settled to end a cycle, and the largest violation as a fraction of the load scale). Phases: *mesh* meshing, *pairs* pair search and DOF numbering, *coarse* solving the 4× coarser model for the active-set's starting pattern, *symbolic* node graph + nested-dissection ordering + sparsity pattern + symbolic factorization, *asm* assembly of values and right-hand sides, *# fact* and *# upd* the numbers of numeric factorizations and of low-rank updates, *fact* the seconds in numeric factorizations, *1st fact* the first of them, *solve* triangular solves including low-rank update columns, *later it.* the slowest active-set iteration after the first (and its ratio to the first factorization), *update* state updates, support checks and internal forces, *stress* stress recovery, *output* VTU/CSV/JSON of all increments, *png* the two pictures, *Gflop* the solver's work counted from the factor's supernodes (factorizations, solves, update columns; the same on every machine), *total / fact* end-to-end time over the time in numeric factorizations, *peak / factor* peak resident memory over the factor's values (8 bytes per nonzero).\n"
    );
    let (gmsh, rest): (Vec<&Case>, Vec<&Case>) = cases.iter().partition(|c| c.problem == "gmsh");
    let (friction, plate): (Vec<&Case>, Vec<&Case>) =
        rest.into_iter().partition(|c| c.problem == "friction");
    let plate: Vec<Case> = plate.into_iter().map(Case::clone_ref).collect();
    for law in ["rigid", "contact"] {
        let rows: Vec<&Case> = plate.iter().filter(|c| c.law == law).collect();
        timing_table(&mut s, &format!("`{law}` law"), &rows);
    }
    if !gmsh.is_empty() {
        timing_table(
            &mut s,
            "A Gmsh problem: the roller in its cradle (examples/roller_in_cradle), `contact` law, meshes subdivided K times",
            &gmsh,
        );
    }
    let (failed, friction): (Vec<&Case>, Vec<&Case>) = friction
        .into_iter()
        .partition(|c| c.summary["status"] == "failed");
    for c in failed {
        let _ = writeln!(
            s,
            "## A frictional run: the plate with the `coulomb` law (μ = {FRICTION})\n\nThe run at K = {} failed: {}\n",
            c.refine,
            c.summary["error"].as_str().unwrap_or("?")
        );
    }
    if !friction.is_empty() {
        timing_table(
            &mut s,
            &format!(
                "A frictional run: the plate with the `coulomb` law (μ = {FRICTION}, `--law coulomb --friction {FRICTION}`); path-dependent, so every increment is solved"
            ),
            &friction,
        );
    }
    targets(&mut s, &plate);
    convergence_table(&mut s, &plate);
    let _ = writeln!(s, "\n![time and memory against unknowns](benchmarks.png)\n");
    s
}

/// One table of timings, a row per run.
fn timing_table(s: &mut String, title: &str, cases: &[&Case]) {
    {
        let _ = writeln!(s, "## {title}\n");
        let _ = writeln!(
            s,
            "| K | unknowns | pairs | open | status | iterations | # fact | # upd | Gflop | mesh | pairs | coarse | symbolic | asm | 1st fact | fact | solve | later it. | update | stress | output | png | **total** | total / fact | peak MiB | peak / factor |"
        );
        let _ = writeln!(s, "|{}", "---|".repeat(26));
        for c in cases {
            let m = &c.summary;
            let t = &m["timings"];
            let pairs: u64 = m["interfaces"]
                .as_array()
                .map(|a| a.iter().map(|i| i["pairs"].as_u64().unwrap_or(0)).sum())
                .unwrap_or(0);
            let open: u64 = m["interfaces"]
                .as_array()
                .map(|a| a.iter().map(|i| i["open"].as_u64().unwrap_or(0)).sum())
                .unwrap_or(0);
            let history = m["iteration_history"]
                .as_array()
                .cloned()
                .unwrap_or_default();
            let its: Vec<String> = history
                .iter()
                .map(|h| h.as_array().map_or(0, |a| a.len()).to_string())
                .collect();
            let first_fact = f(&m["first_factorization_seconds"]);
            let later = later_iterations(m)
                .iter()
                .map(|(it, _)| f(&it["seconds"]))
                .fold(0.0, f64::max);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} ({:.2}×) | {:.2} | {:.2} | {:.2} | {:.2} | **{:.2}** | {:.2} | {:.0} | {:.2} |",
                c.refine,
                m["unknowns"],
                pairs,
                open,
                status(m),
                its.join(" "),
                m["factorizations"],
                m["low_rank_updates"],
                f(&m["solve_flops"]) / 1e9,
                f(&t["meshing"]),
                f(&t["pair_search"]),
                f(&t["coarse_start"]),
                f(&t["pattern_and_symbolic"]),
                f(&t["assembly"]),
                first_fact,
                f(&t["factorization"]),
                f(&t["solve"]),
                later,
                if first_fact > 0.0 {
                    later / first_fact
                } else {
                    0.0
                },
                f(&t["contact_update"]),
                f(&t["stress_recovery"]),
                f(&t["output"]),
                f(&t["pictures"]),
                f(&t["total"]),
                f(&m["total_over_factorization"]),
                f(&m["peak_memory_bytes"]) / 1048576.0,
                f(&m["peak_over_factor"])
            );
        }
        let _ = writeln!(s);
    }
}

/// A run's status for its row: `completed`, or for a run that completed with
/// pairs off the law how many its last increment left (and whether the
/// search settled on them to end a cycle) and the largest violation, as a
/// fraction of the load scale (a run must not look clean in the benchmark
/// when it is not).
fn status(m: &Value) -> String {
    let status = m["status"].as_str().unwrap_or("?");
    if status != "completed_with_violations" {
        return status.to_string();
    }
    let violations = m["violations"].as_array().cloned().unwrap_or_default();
    let last = violations
        .iter()
        .filter_map(|v| v["increment"].as_u64())
        .max();
    let off: Vec<&Value> = violations
        .iter()
        .filter(|v| last.is_some() && v["increment"].as_u64() == last)
        .collect();
    if off.is_empty() {
        return "completed_with_violations (out of balance: see its warnings)".into();
    }
    let worst = off.iter().map(|v| f(&v["relative"])).fold(0.0, f64::max);
    let settled = off.iter().all(|v| v["settled"].as_bool() == Some(true));
    format!(
        "{} pair{} off the law{}, worst {worst:.1e} of the load",
        off.len(),
        if off.len() == 1 { "" } else { "s" },
        if settled { " (settled)" } else { "" }
    )
}

/// Convergence of the scaled contact runs: load-point displacement and contact-zone ends.
fn convergence_table(s: &mut String, cases: &[Case]) {
    // Convergence of the scaled runs: load-point displacement and contact-zone ends.
    let _ = writeln!(s, "## Convergence of the contact runs\n");
    let _ = writeln!(
        s,
        "The load-point displacement (the largest displacement, at the middle of the loaded segment) and the ends of the contact zone (the first and last bonded pair along each interface) as the meshes are refined. Differences between successive rows give the observed convergence.\n"
    );
    let _ = writeln!(
        s,
        "| K | unknowns | max displacement | change from K/2 | observed order in h | at x | bonded pairs | open pairs | contact zone (x from – to) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    let value = |c: &Case| f(&c.summary["max_displacement"]["value"]);
    let contact: Vec<&Case> = cases.iter().filter(|c| c.law == "contact").collect();
    let by_k = |k: usize| contact.iter().find(|c| c.refine == k).copied();
    for c in cases.iter().filter(|c| c.law == "contact") {
        let m = &c.summary;
        let bonded: u64 = m["interfaces"]
            .as_array()
            .map(|a| a.iter().map(|i| i["bonded"].as_u64().unwrap_or(0)).sum())
            .unwrap_or(0);
        let open: u64 = m["interfaces"]
            .as_array()
            .map(|a| a.iter().map(|i| i["open"].as_u64().unwrap_or(0)).sum())
            .unwrap_or(0);
        let zones: Vec<String> = m["interfaces"]
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|i| {
                        let e = &i["bonded_extent"];
                        format!("{:.3} – {:.3}", f(&e[0][0]), f(&e[1][0]))
                    })
                    .collect()
            })
            .unwrap_or_default();
        // Change from K/2, and the order log2(change(K/2) / change(K)) when K/4 exists.
        let (change, order) = match (c.refine % 2, by_k(c.refine / 2), by_k(c.refine / 4)) {
            (0, Some(h), q) => {
                let d = value(c) - value(h);
                let p = q
                    .filter(|_| c.refine % 4 == 0)
                    .map(|q| ((value(h) - value(q)) / d).abs().log2());
                (
                    format!("{d:.3e}"),
                    p.map_or(String::new(), |p| format!("{p:.2}")),
                )
            }
            _ => (String::new(), String::new()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.6e} | {change} | {order} | {} | {} | {} | {} |",
            c.refine,
            m["unknowns"],
            f(&m["max_displacement"]["value"]),
            m["max_displacement"]["x"],
            bonded,
            open,
            zones.join("; ")
        );
    }
}

/// The performance targets of the project, evaluated on the measured runs.
fn targets(s: &mut String, cases: &[Case]) {
    let contact: Vec<&Case> = cases.iter().filter(|c| c.law == "contact").collect();
    let n = |c: &Case| f(&c.summary["unknowns"]);
    let total = |c: &Case| f(&c.summary["timings"]["total"]);
    let gib = |c: &Case| f(&c.summary["peak_memory_bytes"]) / 1073741824.0;
    let verdict = |ok: bool| if ok { "met" } else { "**not met**" };
    let _ = writeln!(s, "## Targets\n");
    // The run closest to a size (in ratio), if one is within 25 % of it.
    let near = |target: f64| {
        contact
            .iter()
            .copied()
            .min_by(|a, b| {
                (n(a) / target)
                    .ln()
                    .abs()
                    .total_cmp(&(n(b) / target).ln().abs())
            })
            .filter(|c| (n(c) / target - 1.0).abs() <= 0.25)
    };
    for (size, label, t_max, m_max) in [
        (1e6, "about 1 million", 5.0, None),
        (4e6, "about 4 million", 30.0, None),
        (8e6, "about 8 million", 80.0, Some(20.0)),
    ] {
        if let Some(c) = near(size) {
            let memory = match m_max {
                Some(m) => format!(
                    ", peak {:.2} GiB (target ≤ {m} GiB: {})",
                    gib(c),
                    verdict(gib(c) <= m)
                ),
                None => format!(", peak {:.2} GiB", gib(c)),
            };
            let why = if total(c) <= t_max {
                String::new()
            } else {
                format!("; {}", why_slow(c, Limit::Seconds(t_max)))
            };
            let _ = writeln!(
                s,
                "- Contact, {label} unknowns (K = {}, {} unknowns): {:.1} s (target ≤ {t_max} s: {}){memory}{why}.",
                c.refine,
                c.summary["unknowns"],
                total(c),
                verdict(total(c) <= t_max),
            );
        }
    }
    // End to end against the numeric factorization, and peak memory against the
    // factor, at a million unknowns and above.
    for (law, limit) in [("rigid", 1.25), ("contact", 1.5)] {
        let large: Vec<&Case> = cases
            .iter()
            .filter(|c| c.law == law && n(c) >= 0.95e6)
            .collect();
        if let Some(worst) = large.iter().max_by(|a, b| {
            f(&a.summary["total_over_factorization"])
                .total_cmp(&f(&b.summary["total_over_factorization"]))
        }) {
            let r = f(&worst.summary["total_over_factorization"]);
            let why = if r <= limit {
                String::new()
            } else {
                format!("; {}", why_slow(worst, Limit::OfFactorization(limit)))
            };
            let _ = writeln!(
                s,
                "- `{law}` end to end relative to the numeric factorization (runs ≥ 1 M unknowns): at most {r:.2}× at K = {} (target ≤ {limit}×: {}){why}.",
                worst.refine,
                verdict(r <= limit)
            );
        }
    }
    if let Some(worst) = cases.iter().filter(|c| n(c) >= 0.95e6).max_by(|a, b| {
        f(&a.summary["peak_over_factor"]).total_cmp(&f(&b.summary["peak_over_factor"]))
    }) {
        let r = f(&worst.summary["peak_over_factor"]);
        let mib = |b: f64| b / 1048576.0;
        let peak = f(&worst.summary["peak_memory_bytes"]);
        let factor = 8.0 * f(&worst.summary["factor_nonzeros"]);
        let why = if r <= 1.3 {
            String::new()
        } else {
            format!(
                "; why: {:.0} MiB beside the factor's {:.0} MiB, held while it is: the symbolic structures and elimination order, the meshes and DOF map, and either the factorization's scratch with the stiffness's values not yet read or the correction columns with the iterations' vectors (docs/method.md §3)",
                mib(peak - factor),
                mib(factor),
            )
        };
        let _ = writeln!(
            s,
            "- Peak memory relative to the factor's values (runs ≥ 1 M unknowns): at most {r:.2}× ({} K = {}; target ≤ 1.3×: {}){why}.",
            worst.law,
            worst.refine,
            verdict(r <= 1.3)
        );
    }
    let big: Vec<&&Case> = contact.iter().filter(|c| n(c) >= 5e4).collect();
    if let [.., a, b] = big.as_slice() {
        let slope = |y: &dyn Fn(&Case) -> f64| (y(b) / y(a)).ln() / (n(b) / n(a)).ln();
        let p_total = slope(&total);
        let p_fact = slope(&|c: &Case| f(&c.summary["first_factorization_seconds"]));
        let _ = writeln!(
            s,
            "- Growth between the two largest contact runs: total time ∝ n^{p_total:.2}, first factorization ∝ n^{p_fact:.2} (target: no faster than the factorization: {}).",
            verdict(p_total <= p_fact + 0.05)
        );
    }
    slowest_iteration(s, &big);
    if let Some(c) = contact.last() {
        time_split(s, c);
    }
    let _ = writeln!(s);
}

/// The slowest contact iteration after the first, relative to the first
/// factorization, among the runs `big` (the issue's ≤ 0.1 target), and among
/// those of them with a million unknowns or more.
fn slowest_iteration(s: &mut String, big: &[&&Case]) {
    let verdict = |ok: bool| if ok { "met" } else { "**not met**" };
    // Over the runs of at least `min_unknowns`: the slowest iteration after the
    // first, relative to its run's first factorization (ratio, run, the
    // iteration's record), and the slowest trial and complete solve.
    let slowest = |min_unknowns: f64| {
        let mut worst: Option<(f64, &Case, Value)> = None;
        let (mut trial, mut complete) = (0.0f64, 0.0f64);
        for (ratio, c, it, last) in later_ratios(big, min_unknowns) {
            if last {
                complete = complete.max(ratio);
            } else {
                trial = trial.max(ratio);
            }
            if worst.as_ref().is_none_or(|w| ratio > w.0) {
                worst = Some((ratio, c, it));
            }
        }
        worst.map(|(ratio, c, it)| (ratio, c, it, trial, complete))
    };
    if let Some((ratio, c, it, trial, complete)) = slowest(0.0) {
        let how = match it["method"]["low-rank"]["rank"].as_u64() {
            Some(r) => format!(
                "a low-rank update of rank {r} (sparse forward solves of its new columns and a solve on the interface's tree paths, or, for the pattern accepted, a complete solve: a backward solve on the paths around the coupling nodes, the refinement forward-solved on the interface's paths, one full backward solve and one internal force; a factor of {:.1} million nonzeros)",
                f(&c.summary["factor_nonzeros"]) / 1e6
            ),
            None => format!("solved by {}", it["method"]),
        };
        let why = if ratio <= 0.1 {
            String::new()
        } else {
            "; a complete solution reads the whole factor once and sums every element's force, which on a small model cost more relative to its factorization (fewer flops per factor value)".to_string()
        };
        let _ = writeln!(
            s,
            "- Each contact iteration after the first, relative to the first factorization (runs ≥ 50 000 unknowns): at most {ratio:.2} (target ≤ 0.1: {}); the slowest, at K = {}, was {how}{why}. Of these, the iterations that tried a pattern (every one of an increment but its last) took at most {trial:.2}, and an increment's last, which solves its accepted pattern completely, at most {complete:.2}.",
            verdict(ratio <= 0.1),
            c.refine
        );
    }
    if let Some((ratio, c, _, trial, complete)) = slowest(1e6) {
        let _ = writeln!(
            s,
            "- The same from 1 M unknowns up: at most {ratio:.2} (K = {}; target ≤ 0.1: {}); the trials at most {trial:.2}, the increments' last (complete) solves at most {complete:.2}.",
            c.refine,
            verdict(ratio <= 0.1)
        );
    }
}

/// Every iteration after its run's first, over the runs of `big` with at least
/// `min_unknowns` unknowns: its time relative to its run's first factorization,
/// the run, the iteration's record, and whether it is its increment's last (the
/// accepted pattern's complete solve, or a reuse) rather than a trial.
fn later_ratios<'c>(
    big: &[&&'c Case],
    min_unknowns: f64,
) -> impl Iterator<Item = (f64, &'c Case, Value, bool)> {
    big.iter()
        .map(|&&c| c)
        .filter(move |c| f(&c.summary["unknowns"]) >= min_unknowns)
        .flat_map(|c| {
            let first = f(&c.summary["first_factorization_seconds"]).max(1e-12);
            later_iterations(&c.summary)
                .into_iter()
                .map(move |(it, last)| (f(&it["seconds"]) / first, c, it, last))
        })
}

/// Every iteration record of the run summarized in `m` after its first, in
/// order, each with whether it is its increment's last (the accepted pattern's
/// complete solve, or a reuse).
fn later_iterations(m: &Value) -> Vec<(Value, bool)> {
    let increments = m["iteration_history"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    increments
        .iter()
        .flat_map(|inc| {
            let its = inc.as_array().cloned().unwrap_or_default();
            let n = its.len();
            its.into_iter()
                .enumerate()
                .map(move |(i, it)| (it, i + 1 == n))
        })
        .skip(1)
        .collect()
}

/// The phases of run `c` with their seconds, largest first.
fn phases(c: &Case) -> Vec<(&'static str, f64)> {
    let t = &c.summary["timings"];
    let mut phases: Vec<(&str, f64)> = [
        ("numeric factorization", "factorization"),
        ("solves and update columns", "solve"),
        ("output files", "output"),
        ("pictures", "pictures"),
        ("ordering and symbolic analysis", "pattern_and_symbolic"),
        ("state updates and internal forces", "contact_update"),
        ("stress recovery", "stress_recovery"),
        ("coarse start", "coarse_start"),
        ("pair search", "pair_search"),
        ("meshing", "meshing"),
        ("assembly", "assembly"),
    ]
    .iter()
    .map(|(name, key)| (*name, f(&t[*key])))
    .collect();
    phases.sort_by(|a, b| b.1.total_cmp(&a.1));
    phases
}

/// A target on a run's end-to-end time.
#[derive(Debug, Clone, Copy)]
enum Limit {
    /// At most this many seconds.
    Seconds(f64),
    /// At most this multiple of the run's numeric factorization time.
    OfFactorization(f64),
}

/// Why run `c` misses its time `limit`: the numeric factorization's share, and
/// the largest phases beyond it; for a ratio target, what the target leaves
/// beyond the factorization, and whether the ordering and symbolic analysis,
/// which the factorization cannot start without, take more than that alone.
fn why_slow(c: &Case, limit: Limit) -> String {
    let t = &c.summary["timings"];
    let fact = f(&t["factorization"]);
    // The three largest phases beyond the factorization and any `named` already.
    let largest = |named: &str| {
        phases(c)
            .into_iter()
            .filter(|(name, _)| *name != "numeric factorization" && *name != named)
            .take(3)
            .map(|(name, v)| format!("{name} {v:.1} s"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let beyond = f(&t["total"]) - fact;
    match limit {
        Limit::Seconds(t) if fact >= t => format!(
            "why: the numeric factorization alone takes {fact:.1} s, at or above the target, so it needs a faster factorization, not less overhead; beyond it {beyond:.1} s, largest {}",
            largest("")
        ),
        Limit::Seconds(_) => format!(
            "why: {beyond:.1} s beyond the numeric factorization ({fact:.1} s), largest {}",
            largest("")
        ),
        Limit::OfFactorization(r) => {
            let allowed = (r - 1.0) * fact;
            let symbolic = f(&t["pattern_and_symbolic"]);
            // The processor time outside the factorization (which can have
            // used at most every thread for its wall time), spread perfectly
            // over the threads: a floor for the run's time beyond it.
            let floor = match (t["cpu"].as_f64(), c.summary["threads"].as_u64()) {
                (Some(cpu), Some(threads)) if threads > 0 && fact > 0.0 => {
                    let p = threads as f64;
                    let outside = (cpu - p * fact).max(0.0);
                    format!(
                        "; the run used {cpu:.1} processor-seconds, of which the factorization can have used at most {threads} × {fact:.1}: the other {outside:.1}, even spread perfectly over the {threads} threads, take {:.2} s, so with this work the run cannot go below {:.2}× its factorization",
                        outside / p,
                        1.0 + outside / p / fact
                    )
                }
                _ => String::new(),
            };
            const SYMBOLIC: &str = "ordering and symbolic analysis";
            if symbolic > allowed {
                format!(
                    "why: the target leaves {allowed:.2} s beyond the numeric factorization ({fact:.1} s), the run takes {beyond:.1} s{floor}; the {SYMBOLIC} alone take {symbolic:.1} s, on both cores, and the factorization cannot start before them; the other largest phases {}",
                    largest(SYMBOLIC)
                )
            } else {
                format!(
                    "why: the target leaves {allowed:.2} s beyond the numeric factorization ({fact:.1} s), the run takes {beyond:.1} s{floor}; largest beyond it {}",
                    largest("")
                )
            }
        }
    }
}

/// Where the time of run `c` goes: its four largest phases.
fn time_split(s: &mut String, c: &Case) {
    let total = f(&c.summary["timings"]["total"]).max(1e-12);
    let list: Vec<String> = phases(c)
        .iter()
        .take(4)
        .map(|(name, v)| format!("{name} {v:.1} s ({:.0} %)", 100.0 * v / total))
        .collect();
    let _ = writeln!(
        s,
        "- Where the time goes in the largest contact run: {}.",
        list.join(", ")
    );
}

fn plot(path: &Path, cases: &[Case]) -> Result<()> {
    use cfe::output::chart::{Axes, Series};
    let curve = |law: &str, key: fn(&Value) -> f64| Series {
        name: law.to_string(),
        points: cases
            .iter()
            .filter(|c| c.law == law)
            .map(|c| (f(&c.summary["unknowns"]), key(&c.summary)))
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect(),
        reference: false,
    };
    // A reference slope (n^p) through the largest contact run.
    let reference = |key: fn(&Value) -> f64, p: f64, name: &str| {
        let pts = curve("contact", key).points;
        let x0 = pts.first().map_or(1.0, |q| q.0);
        let (xa, ya) = pts.last().copied().unwrap_or((1.0, 1.0));
        Series {
            name: name.to_string(),
            points: [x0, xa]
                .iter()
                .map(|&x| (x, ya * (x / xa).powf(p)))
                .collect(),
            reference: true,
        }
    };
    fn total(m: &Value) -> f64 {
        f(&m["timings"]["total"])
    }
    fn memory(m: &Value) -> f64 {
        f(&m["peak_memory_bytes"]) / 1048576.0
    }
    let time = [
        curve("rigid", total),
        curve("contact", total),
        reference(total, 1.5, "n^1.5"),
    ];
    let mem = [
        curve("rigid", memory),
        curve("contact", memory),
        reference(memory, 1.0, "n"),
    ];
    let log = |title, y| Axes {
        title,
        x: "unknowns",
        y,
        log_x: true,
        log_y: true,
    };
    cfe::output::chart::side_by_side(
        path,
        [
            (&log("run time", "seconds"), &time[..]),
            (&log("peak memory", "MiB"), &mem[..]),
        ],
    )
}

#[cfg(test)]
mod tests {
    /// Refinements double up to the target (or a million unknowns), then reach
    /// 1 M, 4 M and the target;
    /// the unknowns model reproduces the plate-on-base counts it is fitted to.
    #[test]
    fn refinement_sequence() {
        let n = super::unknowns_model(910, 3450);
        assert_eq!((n(1), n(2)), (910.0, 3450.0));
        assert_eq!(
            super::refinements(&n, 4_000_000),
            vec![1, 2, 4, 8, 16, 32, 35, 70]
        );
        assert_eq!(
            super::refinements(&n, 8_100_000),
            vec![1, 2, 4, 8, 16, 32, 35, 70, 100]
        );
        assert_eq!(super::refinements(&n, 100_000), vec![1, 2, 4, 8, 12]);
        assert_eq!(super::refinements(&n, 910), vec![1]);
    }

    /// A row's status is the run's; a run that completed with pairs off the law
    /// says how many its last increment left and the worst, never `completed`.
    #[test]
    fn a_settled_run_is_not_reported_as_completed() {
        let v = |inc: u64, rel: f64| serde_json::json!({"increment": inc, "relative": rel, "settled": true});
        let settled = serde_json::json!({
            "status": "completed_with_violations",
            "violations": [v(1, 2e-4), v(1, 1e-4), v(2, 3e-4), v(2, 1.5e-4), v(2, 1e-5)],
        });
        assert_eq!(
            super::status(&settled),
            "3 pairs off the law (settled), worst 3.0e-4 of the load"
        );
        // implex lags its states: its last increment's pairs off the law are
        // not settled ones.
        let lagged = serde_json::json!({
            "status": "completed_with_violations",
            "violations": [{"increment": 10, "relative": 2e-3, "settled": false}],
        });
        assert_eq!(
            super::status(&lagged),
            "1 pair off the law, worst 2.0e-3 of the load"
        );
        let clean = serde_json::json!({"status": "completed", "violations": []});
        assert_eq!(super::status(&clean), "completed");
        let unbalanced =
            serde_json::json!({"status": "completed_with_violations", "violations": []});
        assert!(super::status(&unbalanced).contains("out of balance"));
    }

    /// Three passes over two cases run them in turn (a b a b a b, not a a a b b b)
    /// and keep each case's fastest run end to end; a failed run (no total) gives
    /// way to any run of its case that succeeded, and an error ends it all.
    #[test]
    fn each_pass_runs_every_case_and_the_fastest_is_kept() {
        let totals = [[2.0, 1.5, 3.0], [f64::NAN, 4.0, 5.0]];
        let mut order = Vec::new();
        let best = super::fastest_in_passes(&[0usize, 1], 3, |&case, pass| {
            order.push((case, pass));
            let t = totals[case][pass - 1];
            Ok(if t.is_nan() {
                serde_json::json!({"status": "failed"})
            } else {
                serde_json::json!({"timings": {"total": t}, "pass": pass})
            })
        })
        .unwrap();
        assert_eq!(order, [(0, 1), (1, 1), (0, 2), (1, 2), (0, 3), (1, 3)]);
        assert_eq!(best[0]["pass"], 2, "case 0's fastest is its second run");
        assert_eq!(best[1]["pass"], 2, "case 1's failed first run gives way");
        let failing = super::fastest_in_passes(&[0usize], 2, |_, pass| {
            if pass == 2 {
                Err(cfe::error::Error::output("x", "stopped"))
            } else {
                Ok(serde_json::json!({"timings": {"total": 1.0}}))
            }
        });
        assert!(matches!(failing, Err(cfe::error::Error::Output { .. })));
    }

    /// The report states the machine's speed before and after the runs, each
    /// figure as measured (`–` for one that was not), and how many runs each row
    /// is the fastest of; a report from a JSON written before the speed was
    /// measured has no such line.
    #[test]
    fn the_report_states_the_machine_speed() {
        let speed = serde_json::json!({
            "before": {"dense_gflops": 61.25, "copy_gb_per_s": 19.04, "fresh_gb_per_s": 1.46},
            "after": {"dense_gflops": 58.0, "copy_gb_per_s": null, "fresh_gb_per_s": 1.5},
        });
        let problem = std::path::Path::new("plate.toml");
        let with = super::report(problem, "some CPU", &speed, "abc1234", 3, &[]);
        assert!(
            with.contains("dense product 61.2 / 58.0 Gflop/s")
                && with.contains("memory copy 19.0 / – GB/s")
                && with.contains("fresh memory 1.5 / 1.5 GB/s"),
            "{with}"
        );
        assert!(
            with.contains("bench --out docs --repeat 3`")
                && with.contains("Each row is the fastest end to end of 3 runs"),
            "{with}"
        );
        let without = super::report(
            problem,
            "some CPU",
            &serde_json::Value::Null,
            "abc1234",
            1,
            &[],
        );
        assert!(!without.contains("Machine speed"), "{without}");
        assert!(without.contains("Each row is one `cfe run"), "{without}");
    }

    /// A missed target names its cause from the run's own phases: the
    /// factorization when it alone exceeds the target, else the time beyond it
    /// with the largest other phases, largest first; a ratio target states the
    /// time it leaves beyond the factorization and whether the symbolic analysis
    /// alone exceeds it.
    #[test]
    fn why_a_target_is_missed() {
        let case = |fact: f64, total: f64| super::Case {
            problem: "plate",
            law: "contact",
            refine: 100,
            summary: serde_json::json!({"timings": {
                "factorization": fact, "total": total, "solve": 20.0, "output": 11.0,
                "stress_recovery": 1.0, "pattern_and_symbolic": 9.0, "pictures": 2.0,
            }}),
        };
        let slow = super::why_slow(&case(90.0, 150.0), super::Limit::Seconds(80.0));
        assert!(slow.contains("factorization alone takes 90.0 s"), "{slow}");
        assert!(slow.contains("beyond it 60.0 s, largest solves and update columns 20.0 s, output files 11.0 s, ordering and symbolic analysis 9.0 s"), "{slow}");
        let over = super::why_slow(&case(3.0, 8.0), super::Limit::Seconds(5.0));
        assert!(
            over.starts_with("why: 5.0 s beyond the numeric factorization (3.0 s)"),
            "{over}"
        );
        // A ratio of 1.5 leaves 0.5 × 20 s = 10 s beyond the factorization: the
        // 9 s of symbolic analysis fit in it, but not in the 2 s that 1.1 leaves.
        let fits = super::why_slow(&case(20.0, 45.0), super::Limit::OfFactorization(1.5));
        assert!(
            fits.starts_with("why: the target leaves 10.00 s beyond the numeric factorization (20.0 s), the run takes 25.0 s; largest beyond it solves"),
            "{fits}"
        );
        // 70 processor-seconds on 2 threads, at most 40 of them in the 20 s
        // factorization: the other 30 take at least 15 s, 1.75× the factorization.
        let mut busy = case(20.0, 45.0);
        busy.summary["timings"]["cpu"] = serde_json::json!(70.0);
        busy.summary["threads"] = serde_json::json!(2);
        let floor = super::why_slow(&busy, super::Limit::OfFactorization(1.5));
        assert!(
            floor.contains("the run used 70.0 processor-seconds, of which the factorization can have used at most 2 × 20.0: the other 30.0, even spread perfectly over the 2 threads, take 15.00 s, so with this work the run cannot go below 1.75× its factorization"),
            "{floor}"
        );
        let not = super::why_slow(&case(20.0, 45.0), super::Limit::OfFactorization(1.1));
        assert!(
            not.contains("leaves 2.00 s")
                && not.contains("symbolic analysis alone take 9.0 s")
                && not.ends_with("the other largest phases solves and update columns 20.0 s, output files 11.0 s, pictures 2.0 s"),
            "{not}"
        );
    }

    /// The slowest later iteration is taken over every run from 50 000
    /// unknowns and again from 1 M up, each against its own run's first
    /// factorization, every iteration after the run's first (a later
    /// increment's too): here 0.3 s after a 1 s factorization at 0.1 M (not
    /// met), 0.5 s after a 10 s one at 4 M (met); the 9 s first iterations
    /// never count. Each line splits trials from complete solves.
    #[test]
    fn the_slowest_later_iteration_is_reported_overall_and_from_a_million() {
        let case = |refine: usize, unknowns: f64, first: f64, later: &[f64]| super::Case {
            problem: "plate",
            law: "contact",
            refine,
            summary: serde_json::json!({
                "unknowns": unknowns,
                "first_factorization_seconds": first,
                "factor_nonzeros": 5e6,
                "iteration_history": [
                    std::iter::once(serde_json::json!({"method": "factorization", "seconds": 9.0}))
                        .chain(later.iter().map(|t| serde_json::json!({"method": {"low-rank": {"rank": 40}}, "seconds": t})))
                        .collect::<Vec<_>>(),
                    [serde_json::json!({"method": "reuse", "seconds": 0.01})],
                ],
            }),
        };
        let (small, large) = (
            case(16, 1e5, 1.0, &[0.1, 0.3]),
            case(70, 4e6, 10.0, &[0.5, 0.2]),
        );
        let mut s = String::new();
        super::slowest_iteration(&mut s, &[&&small, &&large]);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 2, "{s}");
        // Trials: 0.1 / 1 at K = 16 and 0.5 / 10 at K = 70; the increments'
        // last: 0.3 / 1 and 0.2 / 10 (and the reuses, 0.01 / 1 and 0.01 / 10).
        assert!(
            lines[0].contains("tried a pattern (every one of an increment but its last) took at most 0.10, and an increment's last, which solves its accepted pattern completely, at most 0.30"),
            "{s}"
        );
        assert!(lines[0].contains("at most 0.30 (target ≤ 0.1: **not met**); the slowest, at K = 16, was a low-rank update of rank 40"), "{s}");
        assert!(
            lines[0].contains("why")
                || lines[0].contains("a complete solution reads the whole factor once"),
            "{s}"
        );
        assert!(
            lines[1].contains("from 1 M unknowns up: at most 0.05 (K = 70; target ≤ 0.1: met); the trials at most 0.05, the increments' last (complete) solves at most 0.02."),
            "{s}"
        );
    }
}
