//! A run deletes and overwrites only what it wrote: the files its manifest lists
//! (`.cfe-manifest`), never a user's file (`notes.tmp`, `vtu/parts_experiment.vtu`,
//! a folder `build.tmp/`), never through a symbolic link; a folder holding files
//! cfe did not write at its names, or no cfe run at all, is refused untouched
//! unless forced; a folder in use by another run is refused naming its process.

mod common;

use common::Problem;

use cfe::Error;
use cfe::output::folder::{LOCK, MANIFEST, MANIFEST_HEADER, OutputFolder};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A steel block (x ∈ [10, 30], y ∈ [20, 30]) tied on a steel base (x ∈ [0, 40],
/// y ∈ [0, 20], its bottom clamped), 100 down on the block's top, in `n`
/// increments.
fn problem(n: usize) -> String {
    Problem::spaced()
        .material("steel", 210000.0, 0.3)
        .part("base", "steel")
        .rectangle([0.0, 40.0], [0.0, 20.0], [4, 2])
        .part("block", "steel")
        .rectangle([10.0, 30.0], [20.0, 30.0], [4, 2])
        .interface("base", "block", "bottom")
        .law("rigid")
        .support("base", "bottom", ["x", "y"])
        .load("block", "top", [0.0, -100.0])
        .increments(n)
        .text()
}

/// A fresh, empty scratch folder for test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cfe-test-safety-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every file under `dir` (relative, `/`-separated), links not followed.
fn tree(dir: &Path) -> BTreeSet<String> {
    let mut all = BTreeSet::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    while let Some((d, prefix)) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let name = format!("{prefix}{}", e.file_name().to_string_lossy());
            if e.file_type().unwrap().is_dir() {
                stack.push((e.path(), format!("{name}/")));
            } else {
                all.insert(name);
            }
        }
    }
    all
}

/// The names the manifest in `out` lists.
fn manifest(out: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(out.join(MANIFEST)).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(MANIFEST_HEADER));
    lines.map(str::to_string).collect()
}

/// Runs the problem with `n` increments into `out` (not forced).
fn run(n: usize, out: &Path) -> cfe::Result<cfe::Summary> {
    common::analysis(&problem(n)).run(out, &mut |_| {})
}

/// Runs the problem with `n` increments into `out` with `force`.
fn run_forced(n: usize, out: &Path) -> cfe::Result<cfe::Summary> {
    let folder = OutputFolder::open(out, true)?;
    common::analysis(&problem(n)).run_in(
        folder,
        &mut |_| {},
        &std::sync::atomic::AtomicUsize::new(0),
    )
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// A run lists every file it leaves in the folder in its manifest (each with
/// its temporary name) and leaves no lock file; a re-run with fewer increments
/// removes exactly the earlier run's files (its series beyond the new run's
/// increments and a temporary file of its own left by a kill), while the user's
/// files — `notes.tmp`, `thesis.docx.tmp`, `vtu/parts_experiment.vtu`, a folder
/// `build.tmp/` with a file inside, a link `link.tmp` and what it points to —
/// stay as they were.
#[test]
fn rerun_removes_only_the_last_runs_files() {
    let out = scratch("rerun");
    let elsewhere = scratch("rerun-elsewhere");
    run(10, &out).unwrap();
    let first = tree(&out);
    assert!(first.contains("vtu/parts_0010.vtu"), "{first:?}");
    assert!(!first.contains(LOCK));
    let listed = manifest(&out);
    for f in first.iter().filter(|f| *f != MANIFEST) {
        assert!(listed.contains(f), "{f} is not in the manifest");
    }
    assert!(listed.contains("vtu/.parts_0010.vtu.tmp"));
    assert!(listed.contains(".summary.json.tmp"));

    // The user's files, and a temporary file of the run as a kill leaves it.
    let user = [
        "notes.tmp",
        "thesis.docx.tmp",
        "vtu/parts_experiment.vtu",
        "vtu/notes.txt",
        "build.tmp/inside.txt",
        "notes.txt",
    ];
    for f in user {
        write(&out.join(f), f);
    }
    write(&elsewhere.join("target.txt"), "kept");
    std::os::unix::fs::symlink(elsewhere.join("target.txt"), out.join("link.tmp")).unwrap();
    write(&out.join("vtu/.parts_0007.vtu.tmp"), "half");

    let s = run(2, &out).unwrap();
    assert_eq!(s.status, cfe::RunStatus::Completed);
    let second = tree(&out);
    for f in user {
        assert_eq!(read(&out.join(f)), f, "{f}");
    }
    assert_eq!(read(&out.join("link.tmp")), "kept");
    assert!(
        std::fs::symlink_metadata(out.join("link.tmp"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let run_files: BTreeSet<String> = second
        .iter()
        .filter(|f| !user.contains(&f.as_str()) && *f != "link.tmp")
        .cloned()
        .collect();
    let expected: BTreeSet<String> = [
        MANIFEST,
        "summary.json",
        "pairs.csv",
        "results.pvd",
        "history.csv",
        "sigma_yy.png",
        "displacement.png",
        "history.png",
        "vtu/parts_0001.vtu",
        "vtu/pairs_0001.vtu",
        "vtu/parts_0002.vtu",
        "vtu/pairs_0002.vtu",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    assert_eq!(run_files, expected);
    // The new manifest lists the new run's files only.
    let listed = manifest(&out);
    assert!(listed.contains("vtu/parts_0002.vtu"));
    assert!(!listed.contains("vtu/parts_0003.vtu"));
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&elsewhere);
}

/// A user's `summary.json` in a folder without a cfe run is refused, named, and
/// left untouched, with nothing added to the folder; `force` replaces it (and
/// only it: the user's other file stays).
#[test]
fn foreign_summary_is_refused_untouched() {
    let out = scratch("summary");
    write(&out.join("summary.json"), "my summary");
    let e = run(2, &out).unwrap_err();
    match &e {
        Error::OutputFolderNotOurs { folder, files, .. } => {
            assert_eq!(folder, &out);
            assert_eq!(files, &[PathBuf::from("summary.json")]);
        }
        _ => panic!("{e:?}"),
    }
    assert!(e.to_string().contains("summary.json"), "{e}");
    assert!(e.to_string().contains("force"), "{e}");
    assert_eq!(read(&out.join("summary.json")), "my summary");
    assert_eq!(tree(&out), BTreeSet::from(["summary.json".to_string()]));

    write(&out.join("notes.txt"), "mine");
    run_forced(2, &out).unwrap();
    assert!(read(&out.join("summary.json")).contains("\"status\": \"completed\""));
    assert_eq!(read(&out.join("notes.txt")), "mine");
    let _ = std::fs::remove_dir_all(&out);
}

/// A non-empty folder holding no cfe run (only `notes.txt`) is refused, naming
/// what it holds; with `force` the run writes into it and `notes.txt` stays;
/// the folder then holds a cfe run, so the next run needs no `force`.
#[test]
fn folder_without_a_run_is_refused_unless_forced() {
    let out = scratch("foreign");
    write(&out.join("notes.txt"), "mine");
    let e = run(2, &out).unwrap_err();
    assert!(
        matches!(&e, Error::OutputFolderNotOurs { files, .. } if files == &[PathBuf::from("notes.txt")]),
        "{e:?}"
    );
    assert_eq!(tree(&out), BTreeSet::from(["notes.txt".to_string()]));
    run_forced(2, &out).unwrap();
    run(3, &out).unwrap();
    assert_eq!(read(&out.join("notes.txt")), "mine");
    assert!(out.join("vtu/parts_0003.vtu").is_file());
    // A new folder and an empty one are fine.
    let fresh = scratch("fresh");
    std::fs::remove_dir(&fresh).unwrap();
    run(2, &fresh.join("a/b")).unwrap();
    let empty = scratch("empty");
    run(2, &empty).unwrap();
    for d in [out, fresh, empty] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// Into a folder holding an earlier cfe run, user files at the names a run
/// writes (a series file beyond the manifest, a picture) are refused by name
/// and nothing is removed; with `force` exactly those are replaced, the user's
/// other files (`vtu/parts_experiment.vtu`, `notes.tmp`) stay.
#[test]
fn force_replaces_only_the_colliding_names() {
    let out = scratch("force");
    run(2, &out).unwrap();
    write(&out.join("vtu/parts_0042.vtu"), "mine");
    write(&out.join("pressure.png"), "mine");
    write(&out.join("vtu/parts_experiment.vtu"), "experiment");
    write(&out.join("notes.tmp"), "notes");
    let before = tree(&out);
    let e = run(2, &out).unwrap_err();
    match &e {
        Error::OutputFolderNotOurs { files, .. } => assert_eq!(
            files,
            &[
                PathBuf::from("pressure.png"),
                PathBuf::from("vtu/parts_0042.vtu")
            ]
        ),
        _ => panic!("{e:?}"),
    }
    assert_eq!(tree(&out), before, "a refused run touched the folder");
    run_forced(2, &out).unwrap();
    assert!(!out.join("vtu/parts_0042.vtu").exists());
    // A rigid interface draws no pressure chart: the replaced user file is gone.
    assert!(!out.join("pressure.png").exists());
    assert_eq!(read(&out.join("vtu/parts_experiment.vtu")), "experiment");
    assert_eq!(read(&out.join("notes.tmp")), "notes");
    let _ = std::fs::remove_dir_all(&out);
}

/// A folder at a name a run writes (`summary.json/`, `vtu/.parts_0001.vtu.tmp/`)
/// is refused even with `force`, before anything is removed: the earlier run's
/// files all stay. A folder merely named like a temporary file (`build.tmp/`)
/// is not cfe's and is left alone.
#[test]
fn folder_at_a_run_name_is_refused_before_removing_anything() {
    for blocker in ["summary.json", "vtu/.parts_0001.vtu.tmp"] {
        let out = scratch("blocked");
        run(3, &out).unwrap();
        if blocker == "summary.json" {
            std::fs::remove_file(out.join(blocker)).unwrap();
        }
        std::fs::create_dir_all(out.join(blocker).join("inside")).unwrap();
        std::fs::create_dir_all(out.join("build.tmp")).unwrap();
        let before = tree(&out);
        for force in [false, true] {
            let e = if force {
                run_forced(2, &out)
            } else {
                run(2, &out)
            }
            .unwrap_err();
            assert!(
                matches!(&e, Error::OutputPathBlocked { path, .. } if path == Path::new(blocker)),
                "{e:?}"
            );
            assert_eq!(tree(&out), before, "{blocker}");
        }
        std::fs::remove_dir_all(out.join(blocker)).unwrap();
        run(2, &out).unwrap();
        assert!(out.join("build.tmp").is_dir());
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// A `vtu` that is a symbolic link to another folder is refused, even with
/// `force`; the files there (named like a run's series) and the earlier run's
/// files stay.
#[test]
fn vtu_symlink_is_never_followed() {
    let out = scratch("link");
    let other = scratch("link-other");
    run(2, &out).unwrap();
    std::fs::rename(out.join("vtu"), other.join("vtu")).unwrap();
    std::os::unix::fs::symlink(other.join("vtu"), out.join("vtu")).unwrap();
    let (before, there) = (tree(&out), tree(&other));
    for force in [false, true] {
        let e = if force {
            run_forced(2, &out)
        } else {
            run(2, &out)
        }
        .unwrap_err();
        assert!(
            matches!(&e, Error::OutputPathBlocked { path, .. } if path == Path::new("vtu")),
            "{e:?}"
        );
        assert!(e.to_string().contains("symbolic link"), "{e}");
        assert_eq!(tree(&out), before);
        assert_eq!(tree(&other), there);
    }
    assert!(other.join("vtu/parts_0002.vtu").is_file());
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&other);
}

/// A manifest cfe did not write (one listing `../victim.txt`) is not trusted:
/// the folder is refused; with `force` the run goes ahead and the file outside
/// stays.
#[test]
fn a_foreign_manifest_is_not_trusted() {
    let out = scratch("manifest");
    let victim = out.with_file_name(format!(
        "{}-victim.txt",
        out.file_name().unwrap().to_string_lossy()
    ));
    write(&victim, "precious");
    write(
        &out.join(MANIFEST),
        &format!(
            "{MANIFEST_HEADER}\nsummary.json\n../{}\n",
            victim.file_name().unwrap().to_string_lossy()
        ),
    );
    let e = run(2, &out).unwrap_err();
    assert!(
        matches!(&e, Error::OutputFolderNotOurs { files, .. } if files == &[PathBuf::from(MANIFEST)]),
        "{e:?}"
    );
    assert!(e.to_string().contains("not a name cfe writes"), "{e}");
    run_forced(2, &out).unwrap();
    assert_eq!(read(&victim), "precious");
    assert!(!manifest(&out).iter().any(|f| f.contains("..")));
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_file(&victim);
}

/// While a run holds the folder, a second is refused naming the first's process
/// (here this one) and touches nothing; once the first ends the lock file is
/// gone and the folder is free. A lock file left by a dead process (no lock
/// held) does not block.
#[test]
fn a_folder_in_use_is_refused_naming_its_process() {
    let out = scratch("lock");
    run(2, &out).unwrap();
    let held = OutputFolder::open(&out, false).unwrap();
    assert!(out.join(LOCK).is_file());
    let before = tree(&out);
    let e = run(2, &out).unwrap_err();
    assert!(
        matches!(&e, Error::OutputFolderInUse { folder, pid } if folder == &out && *pid == Some(std::process::id())),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains(&format!("process {}", std::process::id())),
        "{e}"
    );
    assert_eq!(tree(&out), before);
    drop(held);
    assert!(!out.join(LOCK).exists());
    run(2, &out).unwrap();

    // A stale lock file: its process is gone, so nobody holds the lock.
    write(&out.join(LOCK), "999999999\n");
    run(2, &out).unwrap();
    assert!(!out.join(LOCK).exists());
    let _ = std::fs::remove_dir_all(&out);
}

/// The line probes' folder is checked as `vtu/` is: a user's `lines/mid.csv`
/// (a name a `[[line]]` run writes) in a folder holding an earlier run is
/// refused untouched, and replaced only when forced while the user's
/// `lines/notes.txt` stays; so is a user's `lines/mid.0001.csv` (a line's table
/// at an increment); a `lines` link is never followed, even with force.
#[test]
fn lines_folder_is_checked_like_the_vtu_folder() {
    let out = scratch("lines");
    run(1, &out).unwrap();
    write(&out.join("lines/mid.csv"), "mine");
    write(&out.join("lines/notes.txt"), "mine");
    let before = tree(&out);
    let e = run(1, &out).unwrap_err();
    assert!(
        matches!(&e, Error::OutputFolderNotOurs { files, .. } if files == &[PathBuf::from("lines/mid.csv")]),
        "{e:?}"
    );
    assert_eq!(tree(&out), before);
    assert_eq!(read(&out.join("lines/mid.csv")), "mine");
    run_forced(1, &out).unwrap();
    assert!(
        !out.join("lines/mid.csv").exists(),
        "forced: the colliding name is replaced"
    );
    assert_eq!(read(&out.join("lines/notes.txt")), "mine");
    // A line's table at an increment (`lines/mid.0001.csv`) is a name a run
    // writes too: a user's file there is refused untouched.
    write(&out.join("lines/mid.0001.csv"), "mine");
    let before = tree(&out);
    let e = run(1, &out).unwrap_err();
    assert!(
        matches!(&e, Error::OutputFolderNotOurs { files, .. } if files == &[PathBuf::from("lines/mid.0001.csv")]),
        "{e:?}"
    );
    assert_eq!(tree(&out), before);
    assert_eq!(read(&out.join("lines/mid.0001.csv")), "mine");

    let other = scratch("lines-other");
    std::fs::remove_dir_all(out.join("lines")).unwrap();
    write(&other.join("lines/mid.csv"), "theirs");
    std::os::unix::fs::symlink(other.join("lines"), out.join("lines")).unwrap();
    let (before, there) = (tree(&out), tree(&other));
    for force in [false, true] {
        let e = if force {
            run_forced(1, &out)
        } else {
            run(1, &out)
        }
        .unwrap_err();
        assert!(
            matches!(&e, Error::OutputPathBlocked { path, .. } if path == Path::new("lines")),
            "{e:?}"
        );
        assert_eq!(tree(&out), before);
        assert_eq!(tree(&other), there);
    }
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&other);
}
