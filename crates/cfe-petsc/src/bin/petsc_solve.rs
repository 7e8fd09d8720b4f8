//! Solves a problem file (plane or solid) in memory with a PETSc back end and
//! prints, on rank 0 only, the run's status, pair states, displacements and
//! pair forces, one line each (`tests/mpi.rs` runs it under `mpirun -n 2` and
//! compares with cfe's direct solver):
//!
//! `petsc_solve PROBLEM petsc|petsc-mumps [PETSC OPTIONS]`
//!
//! Every rank solves (the contact scheme is replicated, the linear solves are
//! distributed); nothing is written to disk.

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
    let mut a = Analysis::<D>::from_file(path, 1)?;
    a.model.settings.solver = solver;
    a.set_back_end(Arc::new(Petsc::new(options, None)));
    let (rank, _) = cfe_petsc::world()?;
    let results = a.solve()?;
    Ok(if rank == 0 {
        report(&results)
    } else {
        String::new()
    })
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
        ProblemDimension::Plane => solve::<cfe::dim::D2>(path, solver, &options)?,
        ProblemDimension::Solid => solve::<cfe::dim::D3>(path, solver, &options)?,
    };
    print!("{text}");
    cfe_petsc::finalize()?;
    Ok(())
}
