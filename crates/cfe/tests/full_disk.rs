//! A full disk in the middle of a run (simulated by injected write failures, so it
//! runs unprivileged): the run fails with the write error, `summary.json` says
//! `failed` with the reason, and `results.pvd` names only files that exist; when
//! not even the summary can be written, no stale summary saying `running` stays
//! behind and the error says so; a disk that fills up while the last increment is
//! written and the pictures drawn leaves no picture. Also: `output_every` writes
//! every N-th increment and the last, and a run of many increments ends with
//! complete files. One test, as the fault injection is process-wide.

mod common;

use common::{Problem, Text};

use cfe::Error;
use std::path::Path;

/// The seed's plate on a base, coarsened (10 × 6 and 14 × 3 cells), its load in
/// 10 increments.
static PROBLEM: Text = Text::new(|| {
    Problem::plate_on_base()
        .cells("base", [10, 6])
        .cells("plate", [14, 3])
        .plate_load_down()
        .increments(10)
        .text()
});

/// The files `results.pvd` in `out` names; each must exist.
fn pvd_files_exist(out: &Path) -> usize {
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap_or_default();
    common::pvd_files_exist(out, &pvd)
}

fn no_tmp_left(out: &Path) {
    for dir in [out.to_path_buf(), out.join("vtu")] {
        for e in std::fs::read_dir(dir).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.ends_with(".tmp"), "{name} left behind");
        }
    }
}

#[test]
fn full_disk_and_output_every() {
    let base = std::env::temp_dir().join(format!("cfe-test-disk-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);

    // A disk that fills up after 9 files (a few increments in), with room left
    // for the small summary.
    let out = base.join("full");
    let mut a = common::analysis(&PROBLEM);
    cfe::output::inject_write_faults(Some(9), true);
    let e = a.run(&out, &mut |_| {}).unwrap_err();
    cfe::output::inject_write_faults(None, false);
    assert!(
        matches!(&e, Error::Output { message, .. } if message.contains("No space left")),
        "{e:?}"
    );
    let s = common::summary_json(&out);
    assert_eq!(s["status"], "failed");
    assert!(
        s["error"].as_str().unwrap().contains("No space left"),
        "{s}"
    );
    let named = pvd_files_exist(&out);
    assert!(named < 20, "{named} files named after a failure");
    no_tmp_left(&out);

    // A disk with no room at all: nothing, not even the summary, can be written;
    // the error says the failure could not be recorded and no summary says
    // `running`.
    let out = base.join("nothing");
    cfe::output::inject_write_faults(Some(0), false);
    let e = a.run(&out, &mut |_| {}).unwrap_err();
    cfe::output::inject_write_faults(None, false);
    let m = e.to_string();
    assert!(
        m.contains("could not be recorded") && m.contains("No space left"),
        "{m}"
    );
    if out.join("summary.json").is_file() {
        assert_ne!(common::summary_json(&out)["status"], "running");
    }
    assert_eq!(pvd_files_exist(&out), 0);
    no_tmp_left(&out);

    // A disk that fills up at the very end, while the last parts VTU streams
    // and the pictures are drawn beside it: whichever of the last writes fails
    // (the order between the writer and the pictures varies), the run fails with
    // the write error, no picture stays behind and `results.pvd` names only
    // files that exist. `writes` is the number of writes of a whole run (the
    // smallest budget that succeeds).
    let out = base.join("end");
    let writes = (0..200)
        .find(|&n| {
            cfe::output::inject_write_faults(Some(n), true);
            let ok = a.run(&out, &mut |_| {}).is_ok();
            cfe::output::inject_write_faults(None, false);
            ok
        })
        .expect("a run writes fewer than 200 files");
    assert!(out.join("sigma_yy.png").is_file());
    for n in writes.saturating_sub(4)..writes {
        cfe::output::inject_write_faults(Some(n), true);
        let e = a.run(&out, &mut |_| {}).unwrap_err();
        cfe::output::inject_write_faults(None, false);
        assert!(e.to_string().contains("No space left"), "{n}: {e}");
        assert_eq!(common::summary_json(&out)["status"], "failed", "{n}");
        for f in ["sigma_yy.png", "displacement.png", "pressure.png"] {
            assert!(!out.join(f).exists(), "{n}: {f} after a failure");
        }
        pvd_files_exist(&out);
        no_tmp_left(&out);
    }

    // `output_every = 4` of 10 increments: files of 4, 8 and the last, 10.
    let out = base.join("every");
    let mut a =
        common::analysis(&PROBLEM.replace("increments = 10", "increments = 10\noutput_every = 4"));
    let s = a.run(&out, &mut |_| {}).unwrap();
    assert_eq!(s.converged_increments, 10);
    let vtu = common::vtu_files(&out);
    assert_eq!(
        vtu,
        [
            "pairs_0004.vtu",
            "pairs_0008.vtu",
            "pairs_0010.vtu",
            "parts_0004.vtu",
            "parts_0008.vtu",
            "parts_0010.vtu"
        ]
    );
    assert_eq!(pvd_files_exist(&out), 6);
    assert_eq!(common::summary_json(&out)["status"], "completed");
    assert_eq!(common::summary_json(&out)["converged_increments"], 10);

    // 300 increments (beyond the 100 below which the growing files are rewritten
    // freely), every 100th written: the final pvd and summary are complete.
    let out = base.join("many");
    let mut a = common::analysis(
        &PROBLEM.replace("increments = 10", "increments = 300\noutput_every = 100"),
    );
    a.run(&out, &mut |_| {}).unwrap();
    assert_eq!(pvd_files_exist(&out), 6);
    assert!(out.join("vtu/parts_0300.vtu").is_file());
    let s = common::summary_json(&out);
    assert_eq!(s["status"], "completed");
    assert_eq!(s["converged_increments"], 300);
    assert_eq!(s["iterations"].as_array().unwrap().len(), 300);

    // `output_every = "last"`: only the last increment's files; pairs.csv and
    // the summary still cover all 10.
    let out = base.join("last");
    let mut a = common::analysis(&PROBLEM.replace(
        "increments = 10",
        "increments = 10\noutput_every = \"last\"",
    ));
    assert_eq!(a.model.settings.output_every, cfe::OUTPUT_LAST);
    a.run(&out, &mut |_| {}).unwrap();
    assert_eq!(pvd_files_exist(&out), 2);
    assert!(out.join("vtu/parts_0010.vtu").is_file());
    assert!(!out.join("vtu/parts_0009.vtu").exists());
    let s = common::summary_json(&out);
    assert_eq!(s["converged_increments"], 10);
    assert_eq!(s["iterations"].as_array().unwrap().len(), 10);
    let _ = std::fs::remove_dir_all(&base);
}
