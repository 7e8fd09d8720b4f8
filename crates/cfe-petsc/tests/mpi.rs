//! The PETSc back ends on one and two MPI ranks against cfe's direct solver,
//! on the seed example, the roller in a cradle and the 3D plate on a base:
//! `mpirun -n 2` runs the `petsc_solve` binary (every rank solves, rank 0
//! reports) and the test compares its pair states, displacements and pair
//! forces with the direct run in this process; and the partition the ranks
//! share gives every element and node exactly one rank, each rank's rows one
//! contiguous range.

use cfe::analysis::{Analysis, AnalysisDim, RunStatus};
use cfe::dim::D3;
use cfe::model::FromProblemFile;
use cfe_petsc::partition::Partition;
use std::path::{Path, PathBuf};
use std::process::Command;

/// An example problem file of the repository.
fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// What `petsc_solve` reports (rank 0).
struct Report {
    status: String,
    states: Vec<String>,
    u: Vec<f64>,
    forces: Vec<f64>,
}

/// Runs `petsc_solve` on `problem` with `solver`, under `mpirun -n ranks`
/// (`ranks` > 1) or alone, and parses rank 0's report.
fn run(problem: &Path, solver: &str, ranks: usize) -> Report {
    let exe = env!("CARGO_BIN_EXE_petsc_solve");
    let mut command = if ranks > 1 {
        let mut c = Command::new("mpirun");
        // More ranks than free cores here: ranks that wait yield the core.
        c.args(["-n", &ranks.to_string(), "--oversubscribe"]).args([
            "--mca",
            "mpi_yield_when_idle",
            "1",
            exe,
        ]);
        c
    } else {
        Command::new(exe)
    };
    let out = command
        .arg(problem)
        .arg(solver)
        // Open MPI refuses to run as root (as in CI's containers) without both.
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        // One thread a rank (every rank the same: the replicated scheme's
        // sums are split by the thread count).
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("mpirun (Open MPI's openmpi-bin) runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{solver} on {ranks} rank(s) failed: {}{}",
        text,
        String::from_utf8_lossy(&out.stderr)
    );
    let line = |key: &str| -> Vec<String> {
        let lines: Vec<&str> = text
            .lines()
            .filter(|l| l.split(' ').next() == Some(key))
            .collect();
        assert_eq!(lines.len(), 1, "one {key} line (rank 0's only): {text}");
        lines[0]
            .split_whitespace()
            .skip(1)
            .map(String::from)
            .collect()
    };
    let numbers = |key: &str| -> Vec<f64> {
        line(key)
            .iter()
            .map(|v| v.parse().expect("a number"))
            .collect()
    };
    Report {
        status: line("status").join(" "),
        states: line("states"),
        u: numbers("u"),
        forces: numbers("forces"),
    }
}

/// The largest |a − b| relative to the largest |a|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    diff / scale
}

/// `problem` solved by the direct solver here and by `solver` on each of
/// `ranks`: completed, same pair states, displacements and pair forces within
/// `tolerance` of the direct run's largest.
fn assert_agree<D: AnalysisDim>(problem: &str, solver: &str, ranks: &[usize], tolerance: f64)
where
    Analysis<D>: FromProblemFile,
{
    let path = example(problem);
    let direct = Analysis::<D>::from_file(&path, 1).unwrap().solve().unwrap();
    assert_eq!(direct.summary.status, RunStatus::Completed);
    let states: Vec<String> = direct
        .pairs
        .iter()
        .map(|p| format!("{:?}", p.state))
        .collect();
    let forces: Vec<f64> = direct
        .pairs
        .iter()
        .flat_map(|p| [p.force_n, p.force_s])
        .collect();
    for &n in ranks {
        let what = format!("{problem}, {solver}, {n} rank(s)");
        let r = run(&path, solver, n);
        assert_eq!(r.status, "Completed", "{what}");
        assert_eq!(r.states, states, "{what}: pair states");
        let du = relative_difference(&direct.last.u, &r.u);
        assert!(du <= tolerance, "{what}: displacements differ by {du:e}");
        let df = relative_difference(&forces, &r.forces);
        assert!(df <= tolerance, "{what}: pair forces differ by {df:e}");
    }
}

/// MUMPS through PETSc on 1 and 2 ranks gives the direct solver's answer to
/// 1e-8 on the seed example, the roller and the 3D plate on a base.
#[test]
fn mumps_on_two_ranks_matches_direct() {
    assert_agree::<cfe::dim::D2>("plate_on_base.toml", "petsc-mumps", &[1, 2], 1e-8);
    assert_agree::<cfe::dim::D2>(
        "roller_in_cradle/roller_in_cradle.toml",
        "petsc-mumps",
        &[1, 2],
        1e-8,
    );
    assert_agree::<D3>("plate_on_base_3d.toml", "petsc-mumps", &[1, 2], 1e-8);
}

/// CG + GAMG on 1 and 2 ranks ends on the direct solver's pair states with
/// displacements and pair forces within 1e-6 (its tolerance is 1e-8 on the
/// residual) on the seed example and the roller.
#[test]
fn cg_gamg_on_two_ranks_matches_direct() {
    assert_agree::<cfe::dim::D2>("plate_on_base.toml", "petsc", &[1, 2], 1e-6);
    assert_agree::<cfe::dim::D2>(
        "roller_in_cradle/roller_in_cradle.toml",
        "petsc",
        &[1, 2],
        1e-6,
    );
}

/// The partition of the 3D example over 1 to 5 ranks: every node has one
/// rank and one PETSc number, each rank's nodes are one contiguous range in
/// rank order, every part and coupling element has one rank, the part
/// elements are split in proportion to the ranks (to one element per
/// bisection level), and one rank is the
/// identity.
#[test]
fn partition_gives_each_element_and_node_one_rank() {
    let a = Analysis::<D3>::from_file(&example("plate_on_base_3d.toml"), 1).unwrap();
    for ranks in 1..=5 {
        let p = Partition::new(&a.model.parts, &a.interfaces, &a.dofs, ranks);
        let n_nodes = a.dofs.n_nodes();
        assert_eq!(p.node_start[0], 0);
        assert_eq!(p.node_start[ranks], n_nodes);
        let mut seen = vec![false; n_nodes];
        for g in 0..n_nodes {
            let (i, r) = (p.node_index[g], p.node_owner[g] as usize);
            assert!(!seen[i], "node number {i} given twice");
            seen[i] = true;
            assert!((p.node_start[r]..p.node_start[r + 1]).contains(&i));
        }
        for (r, w) in p.node_start.windows(2).enumerate() {
            assert_eq!(p.nodes_of(r).len(), w[1] - w[0]);
        }
        let n_elements = p.part_owner.len();
        // Each bisection level rounds its cut down: at most one element
        // off per level.
        let levels = (usize::BITS - (ranks - 1).leading_zeros()) as f64;
        for r in 0..ranks {
            let mine = Partition::elements_of(&p.part_owner, r).len() as f64;
            let share = n_elements as f64 / ranks as f64;
            assert!(
                (mine - share).abs() <= levels + 1.0,
                "rank {r} of {ranks}: {mine} elements, share {share}"
            );
        }
        assert!(p.part_owner.iter().all(|&r| (r as usize) < ranks));
        assert!(p.coupling_owner.iter().all(|&r| (r as usize) < ranks));
        let total: usize = (0..ranks)
            .map(|r| Partition::elements_of(&p.coupling_owner, r).len())
            .sum();
        assert_eq!(total, p.coupling_owner.len(), "each coupling element once");
        if ranks == 1 {
            assert!(p.node_index.iter().enumerate().all(|(g, &i)| g == i));
        }
    }
}

/// `petsc_solve` on `problem` with `solver` under `mpirun -n 2`, rank `rank`
/// made to fail alone once increment `increment` has converged
/// (`PETSC_SOLVE_FAIL`): its exit status and what the ranks printed on
/// stderr, or `None` when the ranks were still running after `limit`.
fn run_failing(
    problem: &Path,
    solver: &str,
    rank: usize,
    increment: usize,
    limit: std::time::Duration,
) -> Option<(std::process::ExitStatus, String)> {
    let mut child = Command::new("mpirun")
        .args([
            "-n",
            "2",
            "--oversubscribe",
            "--mca",
            "mpi_yield_when_idle",
            "1",
        ])
        .arg(env!("CARGO_BIN_EXE_petsc_solve"))
        .arg(problem)
        .arg(solver)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("RAYON_NUM_THREADS", "1")
        .env("PETSC_SOLVE_FAIL", format!("{rank}:{increment}"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("mpirun (Open MPI's openmpi-bin) runs");
    // stderr is read on a thread, so a full pipe cannot stall the ranks.
    let mut pipe = child.stderr.take().expect("piped");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut pipe, &mut text).map(|_| text)
    });
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("mpirun waits") {
            break Some(status);
        }
        if start.elapsed() > limit {
            // A hang: end mpirun (which ends its ranks) and report it.
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    let text = reader.join().expect("reader").unwrap_or_default();
    status.map(|s| (s, text))
}

/// A failure on one rank alone — rank 1 (which writes nothing) in the middle
/// of the run, rank 0 (which writes) at the first and at the last increment,
/// where the other rank has no further solve to meet it in — ends both ranks
/// promptly with a nonzero exit, each printing the failing rank's message;
/// never a hang (the ranks' agreement, `cfe_petsc::ranks`). Both back ends.
#[test]
fn a_failure_on_one_rank_ends_every_rank() {
    let path = example("plate_on_base.toml");
    // The whole run takes a few seconds; a hang would run until killed.
    let limit = std::time::Duration::from_secs(180);
    for (solver, rank, increment) in [
        ("petsc-mumps", 1, 3),
        ("petsc-mumps", 0, 1),
        ("petsc-mumps", 0, 10),
        ("petsc", 1, 5),
    ] {
        let what = format!("{solver}, rank {rank} failing at increment {increment}");
        let Some((status, stderr)) = run_failing(&path, solver, rank, increment, limit) else {
            panic!("{what}: the ranks hung (still running after {limit:?})");
        };
        assert!(!status.success(), "{what}: exit status {status}: {stderr}");
        // The ranks' lines may interleave on the shared stderr: counted as
        // occurrences.
        let injected = format!("failure injected on rank {rank} at increment {increment}");
        let count = stderr.matches(&injected).count();
        assert_eq!(count, 2, "{what}: every rank prints the failure: {stderr}");
        if rank > 0 {
            let named = format!("MPI rank {rank}: ");
            assert_eq!(
                stderr.matches(&named).count(),
                2,
                "{what}: the failing rank named: {stderr}"
            );
        }
    }
}
