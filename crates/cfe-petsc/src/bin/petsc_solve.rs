//! Solves a problem file (plane or solid) in memory with a PETSc back end and
//! prints, on rank 0 only, the run's status, pair states, displacements and
//! pair forces, one line each (`tests/mpi.rs` runs it under `mpirun -n 2` and
//! compares with cfe's direct solver):
//!
//! `petsc_solve PROBLEM petsc|petsc-mumps [PETSC OPTIONS]`
//!
//! Every rank solves (the contact scheme is replicated, the linear solves are
//! distributed); nothing is written to disk. At the end the ranks agree on
//! their outcome (`cfe_petsc::ranks::agree`), as `cfe run` does: a failure of
//! any rank is printed by every rank (`error: ...`, exit code 1).
//!
//! `PETSC_SOLVE_REFINE=K` refines the model K times (the measurements of the
//! README's cluster section); each rank prints on stderr the gathers after its
//! solves (`cfe_petsc::backend::exchanged`).
//!
//! For the tests of that agreement only, `PETSC_SOLVE_FAIL=RANK:INCREMENT`
//! makes rank RANK fail alone once increment INCREMENT has converged (as rank
//! 0 of `cfe run` fails when it cannot write an increment): this binary's
//! own hook, not the library's nor `cfe`'s.

use cfe::analysis::{Analysis, AnalysisDim, Results};
use cfe::domain::LinearBackend;
use cfe::model::{FromProblemFile, ProblemDimension, problem_dimension};
use cfe_petsc::Petsc;
use std::path::Path;
use std::sync::Arc;

/// The lines rank 0 prints for `results`.
fn report<D: AnalysisDim>(results: &Results<D>) -> String {
    let join = |v: &mut dyn Iterator<Item = String>| v.collect::<Vec<_>>().join(" ");
    format!(
        "status {:?}\nstates {}\nu {}\nforces {}\n",
        results.summary.status,
        join(&mut results.pairs.iter().map(|p| format!("{:?}", p.state))),
        join(&mut results.last.u.iter().map(|v| format!("{v:e}"))),
        join(
            &mut results
                .pairs
                .iter()
                .flat_map(|p| [p.force_n, p.force_s])
                .map(|v| format!("{v:e}"))
        ),
    )
}

/// Reads `path` as an analysis of dimension `D`, solves it with `solver` and
/// returns rank 0's report (empty on the other ranks).
fn solve<D: AnalysisDim>(
    path: &Path,
    solver: LinearBackend,
    options: &str,
) -> Result<String, Box<dyn std::error::Error>>
where
    Analysis<D>: FromProblemFile,
{
    let refine = match std::env::var("PETSC_SOLVE_REFINE") {
        Ok(k) => k.parse()?,
        Err(_) => 1,
    };
    let mut a = Analysis::<D>::from_file(path, refine)?;
    a.model.settings.solver = solver;
    a.set_back_end(Arc::new(Petsc::new(options, None)));
    let (rank, _) = cfe_petsc::world()?;
    let fail = injected_failure()?;
    let results = a.solve_observed(|inc| match fail {
        Some((r, k)) if r == rank && inc.index == k => Err(cfe::Error::output(
            path,
            format!("failure injected on rank {r} at increment {k} (PETSC_SOLVE_FAIL)"),
        )),
        _ => Ok(()),
    });
    // Every rank ends with the first failure of any rank.
    let local = results.as_ref().err().map(ToString::to_string);
    if let Some(failure) = cfe_petsc::ranks::agree(0, local.as_deref())?.failure {
        return Err(failure.into());
    }
    let results = results?;
    let r = cfe_petsc::backend::exchanged();
    eprintln!(
        "exchange rank {rank}: unknowns {} gathers whole {} coupling {} received {} bytes ({} in the coupling gathers) in {:.3} s; solve {:.3} s",
        a.dofs.n_eq,
        r.all,
        r.coupling,
        8 * r.doubles,
        8 * r.coupling_doubles,
        r.seconds,
        results.summary.timings.solve.solve
    );
    Ok(if rank == 0 {
        report(&results)
    } else {
        String::new()
    })
}

/// `PETSC_SOLVE_FAIL=RANK:INCREMENT`, when set (tests only).
fn injected_failure() -> Result<Option<(usize, usize)>, Box<dyn std::error::Error>> {
    let Ok(text) = std::env::var("PETSC_SOLVE_FAIL") else {
        return Ok(None);
    };
    let parsed = text
        .split_once(':')
        .and_then(|(r, k)| Some((r.parse().ok()?, k.parse().ok()?)));
    match parsed {
        Some(p) => Ok(Some(p)),
        None => Err(format!("PETSC_SOLVE_FAIL={text:?} is not RANK:INCREMENT").into()),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, solver, options @ ..] = args.as_slice() else {
        return Err("usage: petsc_solve PROBLEM petsc|petsc-mumps [PETSC OPTIONS]".into());
    };
    let solver = match solver.as_str() {
        "petsc" => LinearBackend::Petsc,
        "petsc-mumps" => LinearBackend::PetscMumps,
        other => return Err(format!("unknown solver {other:?}").into()),
    };
    let path = Path::new(path);
    let options = options.join(" ");
    let text = match problem_dimension(path)? {
        ProblemDimension::Plane => solve::<cfe::dim::D2>(path, solver, &options),
        ProblemDimension::Solid => solve::<cfe::dim::D3>(path, solver, &options),
    };
    // Every rank finalizes MPI, after a failure too (the ranks agreed on it).
    let finalized = cfe_petsc::finalize();
    match text {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
    finalized?;
    Ok(())
}
