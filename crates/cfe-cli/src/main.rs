//! `cfe` command line: a thin layer over the library.

use anyhow::Context;
use cfe::analysis::Analysis;
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use signal_hook::consts::{SIGINT, SIGTERM};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;

/// Contact between independently meshed parts, by coupling finite elements.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// An interface law on the command line.
#[derive(Clone, Copy, ValueEnum)]
enum LawArg {
    /// Tied: always bonded.
    Rigid,
    /// Bonded in compression, open in tension.
    Contact,
    /// Closed pairs resist penetration only; no tangential force.
    Frictionless,
    /// Stick, slip (|f_s| = μ f_n) or open; needs --friction.
    Coulomb,
}

/// A linear solver on the command line.
#[derive(Clone, Copy, ValueEnum)]
enum SolverArg {
    /// Supernodal Cholesky with low-rank updates (default).
    Direct,
    /// Jacobi-preconditioned conjugate gradients (slow; a moderate penalty or
    /// augmented enforcement).
    Cg,
    /// PETSc: conjugate gradients with algebraic multigrid (GAMG); needs cfe
    /// built with `--features petsc`.
    Petsc,
    /// MUMPS through PETSc; needs cfe built with `--features petsc`.
    PetscMumps,
}

impl From<SolverArg> for cfe::LinearBackend {
    fn from(s: SolverArg) -> cfe::LinearBackend {
        match s {
            SolverArg::Direct => cfe::LinearBackend::Direct,
            SolverArg::Cg => cfe::LinearBackend::Cg,
            SolverArg::Petsc => cfe::LinearBackend::Petsc,
            SolverArg::PetscMumps => cfe::LinearBackend::PetscMumps,
        }
    }
}

impl From<LawArg> for cfe::Law {
    fn from(l: LawArg) -> cfe::Law {
        match l {
            LawArg::Rigid => cfe::Law::Rigid,
            LawArg::Contact => cfe::Law::Contact,
            LawArg::Frictionless => cfe::Law::Frictionless,
            LawArg::Coulomb => cfe::Law::Coulomb,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Solve a problem and write the results (VTU series, pairs.csv, summary.json, PNGs).
    Run {
        /// The problem file (TOML).
        problem: PathBuf,
        /// Output folder (default: results/<problem stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Refine every part K times: structured parts' cell counts are multiplied
        /// by K, Gmsh, given and .inp deck meshes are subdivided uniformly (each edge into K).
        #[arg(long, default_value_t = 1, value_name = "K")]
        refine: usize,
        /// Make every interface follow this law instead of the file's.
        #[arg(long, value_enum)]
        law: Option<LawArg>,
        /// The friction coefficient μ with --law coulomb.
        #[arg(
            long,
            value_name = "MU",
            required_if_eq("law", "coulomb"),
            allow_negative_numbers = true
        )]
        friction: Option<f64>,
        /// Write the VTU files of every N-th increment only, or with `last` of the
        /// last increment (of each load step) only; overrides the file's
        /// `[analysis] output_every`. pairs.csv and summary.json stay complete.
        #[arg(long, value_name = "N|last", value_parser = parse_write_every, allow_negative_numbers = true)]
        write_every: Option<usize>,
        /// The linear solver; overrides the file's `[analysis] solver`.
        #[arg(long, value_enum)]
        solver: Option<SolverArg>,
        /// PETSc options for `--solver petsc` or `petsc-mumps`, as on a PETSc
        /// program's command line (e.g. "-ksp_rtol 1e-8 -pc_gamg_threshold
        /// 0.02"); read after the file's `[analysis] petsc_options`.
        #[arg(long, value_name = "OPTIONS", allow_hyphen_values = true)]
        petsc_options: Option<String>,
        /// A PETSc options file for `--solver petsc` or `petsc-mumps`, read
        /// after the options.
        #[arg(long, value_name = "FILE")]
        petsc_options_file: Option<PathBuf>,
        /// Write into the output folder even if it is not empty and holds no cfe
        /// run, or holds files at the names cfe writes (summary.json, pairs.csv,
        /// results.pvd, the PNGs, vtu/parts_N.vtu, vtu/pairs_N.vtu) that no cfe run
        /// wrote: those files are replaced; every other file is left alone.
        /// Without it such a folder is refused, untouched.
        #[arg(long)]
        force: bool,
    },
    /// Benchmark: run a problem with the rigid and the contact law at growing
    /// refinement and write benchmarks.md and benchmarks.png.
    Bench {
        /// The problem file (default: the repository's examples/plate_on_base.toml,
        /// found from the current folder or from the cfe executable's location).
        #[arg(long)]
        problem: Option<PathBuf>,
        /// Refine until about this many unknowns (default 8 100 000; with
        /// `--only petsc` 1 000 000, and a PETSc row at this size when beyond
        /// a million, e.g. the largest model the memory holds).
        #[arg(long)]
        max_unknowns: Option<usize>,
        /// Where to write the report (regenerate the committed one with `--out docs`).
        #[arg(long, default_value = "results/bench")]
        out: PathBuf,
        /// Run every case once in each of N passes over all the cases and keep
        /// each case's fastest end to end (all its phases from that run): steadier
        /// figures on a machine whose speed varies.
        #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
        repeat: u32,
        /// Only regenerate benchmarks.md and benchmarks.png from OUT/benchmarks.json.
        #[arg(long)]
        report_only: bool,
        /// Only measure and print the machine's speed (dense product, memory copy,
        /// fresh memory; about two seconds), as the report states it before and
        /// after its runs.
        #[arg(long)]
        speed: bool,
        /// Instead, compare the cost of `coupling = "node"` and `"segment"` on the
        /// problem refined K times (tied, one assembly and factorization each) and
        /// print the table.
        #[arg(long, value_name = "K")]
        coupling_cost: Option<usize>,
        /// Run only these rows: `3d`, the 3D plate on a base at about 50k, 100k,
        /// 200k and 400k unknowns (examples/plate_on_base_3d_bench.toml, or the
        /// solid problem given with --problem); the report has those rows and
        /// the 3D targets alone. `petsc` (a cfe built with `--features
        /// petsc`): those rows, then the same problem on `--solver petsc` at
        /// about 50k, 100k, 200k, 400k, 700k and 1M unknowns (up to
        /// --max-unknowns) on 1 and 2 MPI ranks (`mpirun -n 2`), and the
        /// report's PETSc section.
        #[arg(long, value_name = "ROWS", value_parser = ["3d", "petsc"])]
        only: Option<String>,
        /// Keep the rows already in OUT/benchmarks.json: replace only the row
        /// groups this run measures (e.g. with --only 3d, the 3D rows), keep
        /// the others, and state in the report each group's own commit, day
        /// and machine speed.
        #[arg(long, conflicts_with_all = ["report_only", "speed", "coupling_cost"])]
        merge: bool,
        /// Run nothing: merge the rows of FILE (a benchmarks.json measured
        /// elsewhere) into OUT/benchmarks.json, replacing the row groups FILE
        /// has, and write the report again. A FILE that does not record its day
        /// is dated by its modification time.
        #[arg(long, value_name = "FILE", conflicts_with_all = ["merge", "speed", "coupling_cost"])]
        merge_from: Option<PathBuf>,
    },
    /// Verification: run the cases against closed-form and conforming references and
    /// write verification.md with its pictures.
    Verify {
        /// Where to write the report (regenerate the committed one with `--out docs`).
        #[arg(long, default_value = "results/verify")]
        out: PathBuf,
        /// The reduced versions of the cases (as run by the tests).
        #[arg(long)]
        quick: bool,
    },
    /// Read the problem, mesh it and find the coupling pairs, without solving.
    Check {
        /// The problem file (TOML).
        problem: PathBuf,
        /// Refine every part K times: structured parts' cell counts are multiplied
        /// by K, Gmsh, given and .inp deck meshes are subdivided uniformly (each edge into K).
        #[arg(long, default_value_t = 1, value_name = "K")]
        refine: usize,
    },
}

fn main() {
    let result = run(Cli::parse());
    // PETSc (and MPI) end once, after every solver is dropped; under MPI also
    // after a failure, which every rank has agreed on (`settle_ranks`).
    #[cfg(feature = "petsc")]
    let result = {
        let finalized = cfe_petsc::finalize();
        result.and_then(|()| Ok(finalized?))
    };
    if let Err(e) = result {
        eprintln!("error: {}", chain_message(&e));
        std::process::exit(exit_code(&e));
    }
}

/// The chain of causes of `e`, each once: a library error's message already
/// holds its I/O cause.
fn chain_message(e: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if !message.contains(&text) {
            if !message.is_empty() {
                message.push_str(": ");
            }
            message.push_str(&text);
        }
    }
    message
}

/// The exit status of a command that failed with `e`: a run stopped by a signal
/// exits as the shell reports a signal (128 + its number), every other failure
/// (a verification case not met included) with 1.
fn exit_code(e: &anyhow::Error) -> i32 {
    match e.downcast_ref::<cfe::Error>() {
        Some(cfe::Error::Interrupted { signal, .. }) => 128 + *signal as i32,
        _ => 1,
    }
}

/// `cfe verify`'s outcome from its report: an error naming the cases that did
/// not meet their reference, if any (the command then exits with 1).
fn verify_outcome(cases: &[cfe_tools::verification::Case]) -> anyhow::Result<()> {
    let failed = cfe_tools::verification::failures(cases);
    if failed.is_empty() {
        return Ok(());
    }
    let titles: Vec<&str> = failed.iter().map(|c| c.title.as_str()).collect();
    anyhow::bail!(
        "{} of {} verification cases did not meet their reference: {}",
        failed.len(),
        cases.len(),
        titles.join("; ")
    )
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Check { problem, refine } => {
            // A solid problem (box or 3D Gmsh parts) is described as one.
            match cfe::model::problem_dimension(&problem)? {
                cfe::model::ProblemDimension::Plane => {
                    let a = Analysis::from_file(&problem, refine)?;
                    print!("{}", a.describe());
                }
                cfe::model::ProblemDimension::Solid => {
                    use cfe::model::FromProblemFile;
                    let a = Analysis::<cfe::dim::D3>::from_file(&problem, refine)?;
                    print!("{}", a.describe());
                }
            }
            Ok(())
        }
        Command::Verify { out, quick } => {
            let cases =
                cfe_tools::verification::run_all(quick, &mut |name| eprintln!("running {name}"))?;
            cfe_tools::verification::write_report(&out, &cases, quick)?;
            for c in &cases {
                println!("{} {}", if c.passed { "pass" } else { "FAIL" }, c.title);
            }
            println!("wrote {}", out.join("verification.md").display());
            verify_outcome(&cases)
        }
        Command::Bench {
            problem,
            max_unknowns,
            out,
            repeat,
            report_only,
            speed,
            coupling_cost,
            only,
            merge,
            merge_from,
        } => {
            if let Some(file) = merge_from {
                let target = out.join("benchmarks.json");
                let earlier = cfe_tools::bench::read_benchmarks(&target)?;
                let mut new = cfe_tools::bench::read_benchmarks(&file)?;
                if new.date.is_none() {
                    let modified = std::fs::metadata(&file)
                        .and_then(|m| m.modified())
                        .with_context(|| format!("cannot read the date of {}", file.display()))?;
                    new.date = Some(format!(
                        "{} (the modification day of its benchmarks.json)",
                        cfe_tools::bench::utc_date(modified)
                    ));
                }
                let merged = earlier.merge(&new);
                merged.write(&target)?;
                cfe_tools::bench::write_report(&out, &merged)?;
                println!(
                    "merged {} into {}; wrote {}",
                    file.display(),
                    target.display(),
                    out.join("benchmarks.md").display()
                );
                return Ok(());
            }
            if speed {
                let speed = cfe_tools::speed::MachineSpeed::measure();
                println!("machine speed: {}", speed.describe());
                return Ok(());
            }
            if report_only {
                let path = out.join("benchmarks.json");
                let text = std::fs::read_to_string(&path)
                    .with_context(|| format!("cannot read {}", path.display()))?;
                let raw: cfe_tools::bench::Benchmarks = serde_json::from_str(&text)
                    .with_context(|| format!("{} is not a benchmark's results", path.display()))?;
                cfe_tools::bench::write_report(&out, &raw)?;
                println!("wrote {}", out.join("benchmarks.md").display());
                return Ok(());
            }
            let exe = std::env::current_exe().context("cannot locate the cfe executable")?;
            let problem = match problem {
                Some(p) if p.is_file() => p,
                Some(p) => anyhow::bail!("the problem file {} does not exist", p.display()),
                None => default_bench_problem(&exe)?,
            };
            if let Some(k) = coupling_cost {
                let rows = cfe_tools::bench::coupling_cost(&problem, k)?;
                print!("{}", cfe_tools::bench::coupling_cost_table(&rows));
                return Ok(());
            }
            let only = match only.as_deref() {
                None => None,
                Some("petsc") => Some(cfe_tools::bench::Only::Petsc),
                Some(_) => Some(cfe_tools::bench::Only::Solid),
            };
            if only == Some(cfe_tools::bench::Only::Petsc) && !cfg!(feature = "petsc") {
                anyhow::bail!(
                    "`cfe bench --only petsc` runs `cfe run --solver petsc`, and this cfe was built without PETSc: build it with `cargo build --release -p cfe-cli --features petsc` (PETSc and Open MPI installed: see the README's \"PETSc back end\") and run that target/release/cfe"
                );
            }
            let max_unknowns = max_unknowns.unwrap_or(match only {
                Some(cfe_tools::bench::Only::Petsc) => 1_000_000,
                _ => 8_100_000,
            });
            cfe_tools::bench::run(
                &exe,
                &problem,
                max_unknowns,
                repeat as usize,
                &out,
                only,
                merge,
                &mut |line| println!("{line}"),
            )?;
            println!("wrote {}", out.join("benchmarks.md").display());
            Ok(())
        }
        Command::Run {
            problem,
            out,
            refine,
            law,
            friction,
            write_every,
            solver,
            petsc_options,
            petsc_options_file,
            force,
        } => run_problem(
            &problem,
            out,
            refine,
            (law, friction),
            write_every,
            (solver, petsc_options, petsc_options_file),
            force,
        ),
    }
}

/// `--write-every`: a positive integer N, or `last` ([`cfe::OUTPUT_LAST`]).
fn parse_write_every(text: &str) -> Result<usize, String> {
    match text.trim() {
        "last" => Ok(cfe::OUTPUT_LAST),
        t => match t.parse::<usize>() {
            Ok(0) => Err("0 writes nothing: use N ≥ 1 (every N-th increment) or `last`".into()),
            Ok(n) => Ok(n),
            Err(_) => Err(format!(
                "'{t}' is not a positive integer N (every N-th increment) or `last`"
            )),
        },
    }
}

/// The benchmark's default problem, `examples/plate_on_base.toml` of the
/// repository: looked for under the current folder, then above the executable
/// (`target/release/cfe` lies two levels below the repository's root).
fn default_bench_problem(exe: &Path) -> anyhow::Result<PathBuf> {
    let rel = Path::new("examples").join("plate_on_base.toml");
    let candidates: Vec<PathBuf> = std::iter::once(rel.clone())
        .chain(exe.ancestors().skip(1).map(|d| d.join(&rel)))
        .collect();
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| {
            anyhow::anyhow!(
                "the default benchmark problem examples/plate_on_base.toml is neither under the current folder nor above the cfe executable ({}); give one with --problem FILE",
                exe.display()
            )
        })
}

/// `cfe run`'s options beyond the problem file and its refinement.
struct RunOptions {
    /// The output folder (default `results/<problem stem>`).
    out: PathBuf,
    /// `--law`, `--friction`.
    law: (Option<LawArg>, Option<f64>),
    /// `--write-every`.
    write_every: Option<usize>,
    /// `--solver`, `--petsc-options`, `--petsc-options-file`.
    solver: (Option<SolverArg>, Option<String>, Option<PathBuf>),
    /// `--force`.
    force: bool,
}

/// `cfe run`: reads the problem as a plane or a solid model (whichever its
/// parts are, [`cfe::model::problem_dimension`]), solves it with a progress
/// bar, writes the results into `out` (default `results/<problem stem>`) and
/// prints the main figures. The folder is locked and checked (`force`: see
/// `--force`) once the problem is read, before anything in it is removed.
fn run_problem(
    problem: &Path,
    out: Option<PathBuf>,
    refine: usize,
    law: (Option<LawArg>, Option<f64>),
    write_every: Option<usize>,
    solver: (Option<SolverArg>, Option<String>, Option<PathBuf>),
    force: bool,
) -> anyhow::Result<()> {
    let out = out.unwrap_or_else(|| {
        let stem = problem
            .file_stem()
            .map(|s| s.to_os_string())
            .unwrap_or_else(|| "problem".into());
        PathBuf::from("results").join(stem)
    });
    let options = RunOptions {
        out,
        law,
        write_every,
        solver,
        force,
    };
    match cfe::model::problem_dimension(problem)? {
        cfe::model::ProblemDimension::Plane => {
            let a = Analysis::from_file(problem, refine)?;
            let description = a.describe();
            run_analysis(a, &description, options)
        }
        cfe::model::ProblemDimension::Solid => {
            use cfe::model::FromProblemFile;
            let a = Analysis::<cfe::dim::D3>::from_file(problem, refine)?;
            let description = a.describe();
            run_analysis(a, &description, options)
        }
    }
}

/// Runs a read analysis of either dimension as [`run_problem`] says;
/// `description` is its `cfe check` text, printed before the run.
fn run_analysis<D: cfe::RunDim>(
    mut a: Analysis<D>,
    description: &str,
    options: RunOptions,
) -> anyhow::Result<()> {
    let RunOptions {
        out,
        law: (law, friction),
        write_every,
        solver: (solver, petsc_options, petsc_options_file),
        force,
    } = options;
    match (law, friction) {
        (Some(LawArg::Coulomb), Some(mu)) => a.override_friction(mu)?,
        (_, Some(_)) => anyhow::bail!("--friction applies to --law coulomb only"),
        (Some(law), None) => a.override_law(law.into()),
        (None, None) => {}
    }
    if let Some(n) = write_every {
        a.model.settings.output_every = n;
    }
    if let Some(s) = solver {
        a.model.settings.solver = s.into();
    }
    if let Some(o) = petsc_options {
        let settings = &mut a.model.settings;
        settings.petsc_options = Some(match settings.petsc_options.take() {
            Some(file) => format!("{file} {o}"),
            None => o,
        });
    }
    use_petsc(&mut a, petsc_options_file);
    let rank = mpi_rank(&a)?;
    // SIGINT and SIGTERM ask the run to stop after the increment being solved,
    // leaving a consistent output folder whose summary says `interrupted`.
    let stop = Arc::new(AtomicUsize::new(0));
    for signal in [SIGINT, SIGTERM] {
        signal_hook::flag::register_usize(signal, Arc::clone(&stop), signal as usize)?;
    }
    let result = if rank > 0 {
        // A rank after the first of `mpirun -n N cfe run … --solver petsc`:
        // it takes part in every distributed solve (the same contact scheme
        // on the replicated model) and writes nothing; rank 0 writes the
        // output folder and the console.
        a.solve_observed_until(|_| Ok(()), &stop)
            .map(|_| ())
            .map_err(anyhow::Error::new)
    } else {
        write_run(&mut a, description, &stop, out, force)
    };
    let result = settle_ranks(&a, rank, &stop, result);
    if let Err(e) = &result
        && let Some(cfe::Error::Interrupted { .. }) = e.downcast_ref::<cfe::Error>()
    {
        // The folder is complete (summary, results.pvd, lock released) and
        // the process ends at once (`main`): the model is left to the
        // system rather than freed piece by piece, which took seconds at
        // millions of unknowns on a loaded machine.
        std::mem::forget(a);
    }
    result
}

/// Rank 0's part of [`run_analysis`] (the whole run without MPI): the output
/// folder opened, the run solved and written with its progress bar, the
/// summary printed.
fn write_run<D: cfe::RunDim>(
    a: &mut Analysis<D>,
    description: &str,
    stop: &Arc<AtomicUsize>,
    out: PathBuf,
    force: bool,
) -> anyhow::Result<()> {
    let folder = cfe::output::folder::OutputFolder::open(&out, force)?;
    eprint!("{description}");
    let bar = ProgressBar::new(a.model.settings.increments as u64);
    let steps = a.model.steps();
    bar.set_style(
        ProgressStyle::with_template("{spinner} increment {pos}/{len} [{bar:30}] {elapsed} {msg}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let summary = a.run_in(
        folder,
        &mut |inc| {
            // The step is named when the problem has several.
            let step = match steps.get(inc.step) {
                Some(s) if steps.len() > 1 => {
                    format!("step '{}' ({}/{}), ", s.name, inc.step + 1, steps.len())
                }
                _ => String::new(),
            };
            bar.set_message(format!(
                "{step}λ = {:.3}, {} iteration(s)",
                inc.lambda, inc.iterations
            ));
            bar.inc(1);
        },
        stop,
    );
    bar.finish_and_clear();
    let summary = match summary {
        Ok(s) => s,
        Err(e @ cfe::Error::Interrupted { .. }) => return Err(e.into()),
        Err(e) => {
            // The summary on disk records the failure unless even it could not be
            // written (then the library removed a stale one).
            let written = std::fs::read_to_string(out.join("summary.json"))
                .is_ok_and(|t| t.contains("\"status\": \"failed\""));
            return Err(anyhow::Error::new(e).context(if written {
                format!(
                    "run failed; the converged increments and the summary are in {}",
                    out.display()
                )
            } else {
                format!("run failed; nothing could be written to {}", out.display())
            }));
        }
    };
    print_summary(&out, &summary);
    Ok(())
}

/// Hands the analysis the PETSc back ends when its solver is one of them
/// (`petsc`, `petsc-mumps`), with its options and `options_file`.
#[cfg(feature = "petsc")]
fn use_petsc<D: cfe::RunDim>(a: &mut Analysis<D>, options_file: Option<PathBuf>) {
    let settings = &a.model.settings;
    if settings.solver.is_external() {
        let options = settings.petsc_options.clone().unwrap_or_default();
        a.set_back_end(Arc::new(cfe_petsc::Petsc::new(options, options_file)));
    }
}

/// Without the `petsc` feature there is no PETSc back end: a run that asks for
/// one fails with the library's typed error saying how to build it in.
#[cfg(not(feature = "petsc"))]
fn use_petsc<D: cfe::RunDim>(_: &mut Analysis<D>, _: Option<PathBuf>) {}

/// This process's rank among those `mpirun` started, for a run on a PETSc
/// back end (initializing PETSc and MPI); 0 for every other run.
#[cfg(feature = "petsc")]
fn mpi_rank<D: cfe::RunDim>(a: &Analysis<D>) -> anyhow::Result<usize> {
    if a.model.settings.solver.is_external() {
        Ok(cfe_petsc::world()?.0)
    } else {
        Ok(0)
    }
}

/// Under MPI (a run on a PETSc back end), every rank's outcome of the run
/// made one: the ranks agree (`cfe_petsc::ranks::agree`, collective) on the
/// first failure of any rank and on a stop signal, so that every rank ends
/// (and can finalize MPI) rather than wait for one that has left. Rank 0
/// keeps its own error (its summary records it); the other ranks report the
/// first failing rank's message. Any other run's outcome is `result`.
#[cfg(feature = "petsc")]
fn settle_ranks<D: cfe::RunDim>(
    a: &Analysis<D>,
    rank: usize,
    stop: &AtomicUsize,
    result: anyhow::Result<()>,
) -> anyhow::Result<()> {
    if !a.model.settings.solver.is_external() {
        return result;
    }
    let local = result.as_ref().err().map(chain_message);
    let signal = stop.load(std::sync::atomic::Ordering::Relaxed);
    let agreed = cfe_petsc::ranks::agree(signal, local.as_deref())?;
    match (result, agreed.failure) {
        (Err(e), _) if rank == 0 => Err(e),
        (_, Some(failure)) => Err(anyhow::Error::new(failure)),
        (result, None) => result,
    }
}

/// Without the `petsc` feature every run is one process: its outcome as it is.
#[cfg(not(feature = "petsc"))]
fn settle_ranks<D: cfe::RunDim>(
    _: &Analysis<D>,
    _: usize,
    _: &AtomicUsize,
    result: anyhow::Result<()>,
) -> anyhow::Result<()> {
    result
}

/// Without the `petsc` feature every run is one process: rank 0.
#[cfg(not(feature = "petsc"))]
fn mpi_rank<D: cfe::RunDim>(_: &Analysis<D>) -> anyhow::Result<usize> {
    Ok(0)
}

/// Prints the main figures of a finished run.
fn print_summary(out: &Path, summary: &cfe::analysis::Summary) {
    use cfe::output::fmt::{num, num_rel};
    println!("results in {}", out.display());
    println!(
        "  {} unknowns, {} increments, iterations per increment {:?}",
        summary.unknowns, summary.converged_increments, summary.iterations
    );
    for i in &summary.interfaces {
        println!(
            "  interface '{}': {} pairs, {} bonded, {} open{}{}",
            i.name,
            i.pairs,
            i.bonded,
            i.open,
            if i.violations == 0 {
                String::new()
            } else {
                format!(
                    ", {} breaking the law ({} settled to end a cycle)",
                    i.violations,
                    i.settled.len()
                )
            },
            if i.max_projection_distance > 0.0 {
                format!(
                    "; coupling nodes moved onto the host edges by up to {}",
                    num(i.max_projection_distance)
                )
            } else {
                String::new()
            }
        );
    }
    let solid = summary.max_displacement.z.is_some();
    for i in &summary.interfaces {
        if i.law == cfe::Law::Frictionless || i.law == cfe::Law::Coulomb || i.unpaired > 0 {
            println!(
                "  interface '{}' ({}{}): {} slipping, {} unpaired, max pressure {}, {} {}",
                i.name,
                i.law.as_str(),
                if i.law == cfe::Law::Coulomb {
                    format!(", μ = {}", i.friction)
                } else {
                    String::new()
                },
                i.slip,
                i.unpaired,
                num(i.max_pressure),
                // In a solid model the length is between the two extreme
                // closed pairs (by x, then y), not a contact zone's size.
                if solid {
                    "span of the closed pairs"
                } else {
                    "contact length"
                },
                num(i.contact_length)
            );
        }
        // A solid model's contact area: the closed pairs' tributary areas.
        if let Some(area) = i.contact_area
            && i.law != cfe::Law::Rigid
        {
            println!(
                "  interface '{}': contact area {} ({} of {} pairs closed)",
                i.name,
                num(area),
                i.pairs - i.open,
                i.pairs
            );
        }
        if i.enforcement == cfe::Enforcement::Augmented {
            println!(
                "  interface '{}': augmented Lagrangian, {} Uzawa/fixed-point solves, final penetration {}",
                i.name,
                summary.fixed_point_iterations.iter().sum::<usize>(),
                num(summary.augmented_penetration)
            );
        }
    }
    if !summary.proportional_shortcut {
        println!(
            "  proportional-load shortcut off ({}): every increment solved",
            summary
                .proportional_shortcut_off
                .as_deref()
                .unwrap_or("initial gaps, friction or augmented Lagrangian")
        );
    }
    if summary.steps.len() > 1 {
        let list: Vec<String> = summary
            .steps
            .iter()
            .map(|s| format!("'{}' ({} increments)", s.name, s.increments))
            .collect();
        println!("  load steps: {}", list.join(", "));
    }
    for n in &summary.notes {
        // Increment 0: advice about the model as a whole.
        if n.increment == 0 {
            eprintln!("warning: {}", n.message);
        } else {
            eprintln!("note: increment {}: {}", n.increment, n.message);
        }
    }
    let m = &summary.max_displacement;
    // A solid model's positions and reactions carry z.
    let z = |v: Option<f64>, show: &dyn Fn(f64) -> String| {
        v.map_or(String::new(), |v| format!(", {}", show(v)))
    };
    println!(
        "  max |u| = {} at ({}, {}{}) in part '{}'",
        num(m.value),
        short(m.x),
        short(m.y),
        z(m.z, &|v| short(v).to_string()),
        m.part
    );
    for r in &summary.reactions {
        // A component below 1e-10 of the reaction is round-off: shown as 0.
        let size = r.fx.hypot(r.fy).hypot(r.fz.unwrap_or(0.0));
        println!(
            "  reaction '{}': ({}, {}{})",
            r.support,
            num_rel(r.fx, size),
            num_rel(r.fy, size),
            z(r.fz, &|v| num_rel(v, size).to_string())
        );
    }
    println!(
        "  equilibrium error {:.2e}, total {:.3} s{}",
        summary.equilibrium_error,
        summary.timings.total,
        summary
            .total_over_factorization
            .map_or(String::new(), |r| format!(
                " ({r:.2}× the numeric factorization)"
            ))
    );
    println!("  status: {}", summary.status);
    for line in warning_lines(&summary.warnings, summary.converged_increments) {
        eprintln!("{line}");
    }
}

/// The console's warning lines: every warning about the model as meshed
/// (increment 0), every warning of the last increment `last`, and, when earlier
/// increments have warnings too, the first of them in full before their count
/// (the rest are in summary.json).
fn warning_lines(warnings: &[cfe::analysis::Warning], last: usize) -> Vec<String> {
    let mut lines: Vec<String> = warnings
        .iter()
        .filter(|w| w.increment == 0)
        .map(|w| format!("warning: {}", w.message))
        .collect();
    lines.extend(
        warnings
            .iter()
            .filter(|w| w.increment == last && last > 0)
            .map(|w| format!("warning: increment {}: {}", w.increment, w.message)),
    );
    let earlier: Vec<&cfe::analysis::Warning> = warnings
        .iter()
        .filter(|w| w.increment != 0 && w.increment != last)
        .collect();
    if let Some(first) = earlier.iter().min_by_key(|w| w.increment) {
        let increments: std::collections::BTreeSet<usize> =
            earlier.iter().map(|w| w.increment).collect();
        lines.push(format!(
            "warning: increment {}: {}",
            first.increment, first.message
        ));
        let others = earlier.len() - 1;
        if others > 0 {
            lines.push(format!(
                "warning: {others} more warning(s) at {} earlier increment(s) in all (see summary.json)",
                increments.len()
            ));
        }
    }
    lines
}

/// A coordinate rounded to 7 significant digits, printed without trailing zeros
/// (`100`, `-6.840403`).
fn short(v: f64) -> f64 {
    format!("{v:.6e}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use cfe::analysis::Warning;
    use cfe_tools::verification::Case;

    fn warning(increment: usize, message: &str) -> Warning {
        Warning {
            increment,
            message: message.into(),
        }
    }

    /// Warnings at earlier increments only: the console prints the first of
    /// them in full (the one the count refers to), then how many more there
    /// are; a model warning (increment 0) is printed whatever the increments.
    #[test]
    fn the_first_earlier_warning_is_printed() {
        let w = [
            warning(0, "part 'p': boundary 'arc' is curved"),
            warning(2, "second"),
            warning(1, "first"),
            warning(3, "third"),
        ];
        let lines = warning_lines(&w, 5);
        assert_eq!(
            lines,
            [
                "warning: part 'p': boundary 'arc' is curved",
                "warning: increment 1: first",
                "warning: 2 more warning(s) at 3 earlier increment(s) in all (see summary.json)",
            ]
        );
        // The last increment's warnings are all printed; a single earlier one
        // needs no count.
        let w = [
            warning(1, "early"),
            warning(4, "late a"),
            warning(4, "late b"),
        ];
        assert_eq!(
            warning_lines(&w, 4),
            [
                "warning: increment 4: late a",
                "warning: increment 4: late b",
                "warning: increment 1: early",
            ]
        );
        assert!(warning_lines(&[], 3).is_empty());
    }

    fn case(title: &str, passed: bool) -> Case {
        Case {
            title: title.into(),
            setup: String::new(),
            reference: String::new(),
            tables: Vec::new(),
            plots: Vec::new(),
            verdict: String::new(),
            passed,
        }
    }

    /// `cfe verify` exits 0 only when every case met its reference: one FAIL
    /// among passing cases gives exit status 1 and an error naming that case.
    #[test]
    fn a_failing_verification_case_exits_non_zero() {
        let all_pass = [case("patch", true), case("Hertz", true)];
        assert!(verify_outcome(&all_pass).is_ok());
        let one_fails = [case("patch", true), case("Hertz", false), case("fit", true)];
        let e = verify_outcome(&one_fails).expect_err("a FAIL must fail the command");
        assert_eq!(exit_code(&e), 1);
        let message = e.to_string();
        assert!(message.starts_with("1 of 3 "), "{message}");
        assert!(
            message.contains("Hertz") && !message.contains("patch"),
            "{message}"
        );
    }
}
