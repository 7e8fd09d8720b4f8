//! A stop request (the flag a signal handler sets) is honoured inside an
//! increment: the solver reads it at every increment, active-set iteration,
//! fixed-point step, continuation stage and linear solve, and the run ends
//! `interrupted` with only converged increments on disk.

mod common;

use common::Problem;

use cfe::error::Error;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// A block pressed on a base with Coulomb friction and its top pushed sideways
/// far beyond the elastic range over `increments` increments: every increment
/// is searched with slip-force fixed points (several solves each).
fn coulomb_push(increments: usize) -> String {
    Problem::coulomb_block_pushed_far(0.3, increments).text()
}

fn fresh_folder(name: &str) -> PathBuf {
    let out = std::env::temp_dir().join(format!("cfe-test-stop-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    out
}

/// The files `results.pvd` names: each exists.
fn pvd_names_existing(out: &Path) -> usize {
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    common::pvd_files_exist(out, &pvd)
}

/// A run stopped by `signal` before any increment: `e` is
/// `Error::Interrupted` at increment 0, the summary in `out` says `interrupted`
/// with none converged, and no increment (series entry, VTU file, pairs.csv) is
/// written.
fn assert_nothing_written(e: &Error, signal: usize, out: &Path) {
    assert!(
        matches!(e, Error::Interrupted { increment: 0, signal: s } if *s == signal),
        "{e:?}"
    );
    let s = common::summary_json(out);
    assert_eq!(s["status"], "interrupted");
    assert_eq!(s["converged_increments"], 0);
    assert_eq!(pvd_names_existing(out), 0);
    assert!(
        common::vtu_files(out).is_empty(),
        "{:?}",
        common::vtu_files(out)
    );
    assert!(!out.join("pairs.csv").exists());
}

/// A stop already requested before the run: the first check ends it before
/// any increment is written; the summary says `interrupted` with none converged.
#[test]
fn a_stop_before_the_run_writes_no_increment() {
    let out = fresh_folder("before");
    let mut a = common::analysis(&coulomb_push(4));
    let stop = AtomicUsize::new(2);
    let e = a.run_until(&out, &mut |_| {}, &stop).unwrap_err();
    assert_nothing_written(&e, 2, &out);
    std::fs::remove_dir_all(&out).unwrap();
}

/// The solver itself honours the flag: set while increment 1 is handed over
/// (its callback does not refuse), the run ends before increment 2 is solved,
/// with increment 1 the last one delivered.
#[test]
fn the_solver_stops_before_the_next_increment_is_solved() {
    let a = common::analysis(&coulomb_push(4));
    let stop = AtomicUsize::new(0);
    let mut solver = a.solver().unwrap();
    solver.set_stop(&stop);
    let mut delivered = Vec::new();
    let e = solver
        .run(|inc| {
            delivered.push(inc.index);
            stop.store(15, Ordering::Relaxed);
            Ok(())
        })
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Interrupted {
                increment: 1,
                signal: 15
            }
        ),
        "{e:?}"
    );
    assert_eq!(delivered, [1]);
}

/// Without a stop the flag changes nothing: the same increments, bit for bit,
/// as a solver that has none.
#[test]
fn an_unset_flag_changes_no_result() {
    let a = common::analysis(&coulomb_push(3));
    let plain = common::run_all(a.solver().unwrap());
    let stop = AtomicUsize::new(0);
    let mut solver = a.solver().unwrap();
    solver.set_stop(&stop);
    let flagged = common::run_all(solver);
    assert_eq!(plain.len(), flagged.len());
    for (p, f) in plain.iter().zip(&flagged) {
        assert_eq!(p.u, f.u);
        assert_eq!(p.f_int, f.f_int);
        assert_eq!(p.states, f.states);
        assert_eq!(p.iterations, f.iterations);
    }
}

/// The symbolic analysis reads the flag too: a solver built with a stop
/// already requested is refused before any factorization with
/// `Error::Interrupted` after increment 0; one built with an unset flag gives
/// the increments of a solver without one, bit for bit.
#[test]
fn the_analysis_reads_the_flag_given_to_the_solver() {
    let a = common::analysis(&coulomb_push(2));
    let stop = AtomicUsize::new(15);
    match a.solver_until(Some(&stop)) {
        Err(Error::Interrupted {
            increment: 0,
            signal: 15,
        }) => {}
        other => panic!("expected Interrupted, got {:?}", other.map(|_| ())),
    }
    let plain = common::run_all(a.solver().unwrap());
    let unset = AtomicUsize::new(0);
    let flagged = common::run_all(a.solver_until(Some(&unset)).unwrap());
    assert_eq!(plain.len(), flagged.len());
    for (p, f) in plain.iter().zip(&flagged) {
        assert_eq!(p.u, f.u);
        assert_eq!(p.states, f.states);
        assert_eq!(p.iterations, f.iterations);
    }
}

/// A stop set from another thread while the run goes on (after the first
/// increment is written): the run ends `interrupted` at whatever point of the
/// search it reached, the converged increments stay on disk, every pair and
/// parts file `results.pvd` names exists, and no increment after the last
/// converged one left a file.
#[test]
fn a_stop_from_another_thread_leaves_the_converged_increments() {
    let out = fresh_folder("during");
    let n = 6;
    let mut a = common::analysis(&coulomb_push(n));
    let stop = AtomicUsize::new(0);
    let (tx, rx) = mpsc::channel::<()>();
    let e = std::thread::scope(|s| {
        let stop = &stop;
        s.spawn(move || {
            if rx.recv().is_ok() {
                stop.store(15, Ordering::Relaxed);
            }
        });
        let r = a.run_until(
            &out,
            &mut |_| {
                // Wait until the other thread has set the flag: on a loaded
                // machine it could otherwise come only after the last increment.
                if tx.send(()).is_ok() {
                    while stop.load(Ordering::Relaxed) == 0 {
                        std::thread::yield_now();
                    }
                }
            },
            stop,
        );
        drop(tx);
        r
    })
    .unwrap_err();
    let Error::Interrupted {
        increment,
        signal: 15,
    } = e
    else {
        panic!("{e:?}");
    };
    assert!((1..n).contains(&increment), "{increment}");
    let s = common::summary_json(&out);
    assert_eq!(s["status"], "interrupted");
    assert_eq!(s["converged_increments"], increment);
    assert_eq!(pvd_names_existing(&out), 2 * increment);
    let expected: Vec<String> = (1..=increment)
        .flat_map(|k| [format!("pairs_{k:04}.vtu"), format!("parts_{k:04}.vtu")])
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    assert_eq!(common::vtu_files(&out), expected);
    std::fs::remove_dir_all(&out).unwrap();
}

/// The coarse warm start reads the stop flag: on the seed's plate refined 4
/// times (a coarser level exists), the start from the coarse solve is found with
/// the flag clear and abandoned (no start, nothing solved to the end) with it set.
#[test]
fn the_coarse_start_reads_the_flag() {
    let text = Problem::plate_on_base().plate_load_down().text();
    let model: cfe::Model = text.parse().unwrap();
    let a = cfe::Analysis::new(model.with_refine(4).unwrap()).unwrap();
    let clear = AtomicUsize::new(0);
    assert!(a.coarse_states_until(Some(&clear)).is_some());
    let set = AtomicUsize::new(15);
    assert!(a.coarse_states_until(Some(&set)).is_none());
}

/// A frictional solve ends on the flag (issue 41): the shrink fit of
/// `examples/shrink_fit.toml` with Coulomb friction μ = 0.3 on both interfaces
/// (its one increment runs slip-force fixed points for minutes), the flag set
/// from another thread once the run is well into that increment, ends
/// `Interrupted` after increment 0 with an `interrupted` summary, no increment
/// converged, and a consistent folder: `results.pvd` names no file, `vtu/` is
/// empty, no `pairs.csv`, no temporary file and no lock left.
#[test]
fn a_coulomb_solve_ends_on_the_flag_with_an_interrupted_summary() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/shrink_fit.toml");
    let text = std::fs::read_to_string(example).unwrap().replace(
        "law = \"frictionless\"",
        "law = \"coulomb\"\nfriction = 0.3",
    );
    assert_eq!(text.matches("friction = 0.3").count(), 2);
    let out = fresh_folder("coulomb");
    let mut a = common::analysis(&text);
    let stop = AtomicUsize::new(0);
    let e = std::thread::scope(|s| {
        let stop = &stop;
        s.spawn(move || {
            // The set-up of these 34 000 unknowns takes a fraction of this.
            std::thread::sleep(std::time::Duration::from_secs(2));
            stop.store(15, Ordering::Relaxed);
        });
        a.run_until(&out, &mut |_| {}, stop)
    })
    .unwrap_err();
    assert_nothing_written(&e, 15, &out);
    assert!(!out.join(".cfe-lock").exists());
    for dir in [out.clone(), out.join("vtu")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.ends_with(".tmp"), "{name} left in {}", dir.display());
        }
    }
    std::fs::remove_dir_all(&out).unwrap();
}
