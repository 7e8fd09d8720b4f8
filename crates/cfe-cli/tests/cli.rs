//! The `cfe` command line on hostile input: exit status 1 and a message naming
//! the file, line and key (or the real numerical trouble); `bench` passes its
//! children's errors through; `check` prints one number format.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Output};
use std::time::{Duration, Instant};

fn cfe(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cfe"))
        .args(args)
        .output()
        .expect("cfe runs")
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The seed's plate problem with `from` replaced by `to`, written to a temporary
/// file named `name`.
fn problem(name: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/plate_on_base.toml")).unwrap();
    assert!(text.contains(from));
    let dir = std::env::temp_dir().join(format!("cfe-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Bad values exit with status 1 and name the file, the line and the key.
#[test]
fn bad_values_name_file_line_and_key() {
    let cases = [
        ("E = 210000.0", "E = -1.0", "materials.steel.E", ":14:"),
        ("nu = 0.31", "nu = 0.5", "materials.steel.nu", ":15:"),
        (
            "increments = 10",
            "increments = 0",
            "analysis.increments",
            ":51:",
        ),
        (
            "x = [0.0, 200.0]",
            "x = [0.0, inf]",
            "part.base.rectangle.x",
            ":21:",
        ),
    ];
    for (i, (from, to, key, line)) in cases.iter().enumerate() {
        let p = problem(&format!("bad{i}.toml"), from, to);
        for cmd in ["check", "run"] {
            let o = cfe(&[
                cmd,
                p.to_str().unwrap(),
                "--out",
                "/nonexistent-never-written",
            ][..if cmd == "check" { 2 } else { 4 }]);
            assert_eq!(o.status.code(), Some(1), "{cmd} {to}");
            let e = stderr(&o);
            assert!(e.contains(key) && e.contains(line), "{cmd} {to}: {e}");
        }
    }
}

/// Numbers double precision cannot carry are named as overflow or loss of
/// precision, never as a mechanism or a singular system.
#[test]
fn numerical_trouble_has_its_real_name() {
    let cases = [
        ("E = 210000.0", "E = 1e300", "overflow"),
        ("E = 210000.0", "E = 1e-300", "overflow"),
        ("c_n = 1e9 ", "c_n = 1e25 ", "loss of precision"),
        (
            "force = [0.0, -1500.0]",
            "force = [0.0, -1e308]",
            "overflow",
        ),
    ];
    for (i, (from, to, words)) in cases.iter().enumerate() {
        let p = problem(&format!("num{i}.toml"), from, to);
        let out = p.with_extension("out");
        let o = cfe(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{to}");
        let e = stderr(&o);
        assert!(e.contains(words), "{to}: {e}");
        assert!(
            !e.contains("mechanism") && !e.contains("singular"),
            "{to}: {e}"
        );
    }
}

/// `bench` refuses a missing problem file clearly, and shows a failing child's
/// own error message.
#[test]
fn bench_passes_errors_through() {
    let o = cfe(&["bench", "--problem", "nope.toml"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("nope.toml does not exist"),
        "{}",
        stderr(&o)
    );
    let p = problem("benchbad.toml", "E = 210000.0", "E = -5.0");
    let out = p.with_extension("bench");
    let o = cfe(&[
        "bench",
        "--problem",
        p.to_str().unwrap(),
        "--max-unknowns",
        "1000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.contains("cfe run") && e.contains("materials.steel.E") && e.contains("positive"),
        "{e}"
    );
}

/// `bench --speed` measures and prints the machine's three speed figures and
/// runs nothing else; `--repeat` takes 1 to 100 runs per case and refuses 0.
#[test]
fn bench_measures_the_machine_speed_alone() {
    let o = cfe(&["bench", "--speed"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = String::from_utf8_lossy(&o.stdout);
    let figures: Vec<f64> = s
        .trim()
        .trim_start_matches("machine speed: ")
        .split(", ")
        .map(|part| {
            let words: Vec<&str> = part.split(' ').collect();
            words[words.len() - 2].parse().unwrap_or(f64::NAN)
        })
        .collect();
    assert!(
        s.starts_with("machine speed: dense product ")
            && figures.len() == 3
            && figures.iter().all(|v| v.is_finite() && *v > 0.0),
        "{s}"
    );
    let o = cfe(&["bench", "--repeat", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--repeat"), "{}", stderr(&o));
}

/// `check` prints four significant digits and round-off as zero: the roller's
/// projection distance as 7.457e-2, the plate's as 0.
#[test]
fn check_uses_one_number_format() {
    let o = cfe(&[
        "check",
        repo()
            .join("examples/roller_in_cradle/roller_in_cradle.toml")
            .to_str()
            .unwrap(),
    ]);
    assert!(o.status.success());
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("max projection distance 7.457e-2"), "{s}");
    assert!(s.contains("E = 2.1e5"), "{s}");
    let o = cfe(&[
        "check",
        repo().join("examples/plate_on_base.toml").to_str().unwrap(),
    ]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("max projection distance 0\n"), "{s}");
    assert!(!s.contains("0e0"), "{s}");
}

/// `--refine`'s help mentions Gmsh parts.
#[test]
fn refine_help_mentions_gmsh() {
    let o = cfe(&["run", "--help"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("Gmsh"));
}

/// A friction coefficient below zero or not a number, given on the command
/// line, is refused by the model's own check (exit 1, naming the coefficient
/// and its value) before anything is solved: `--friction -0.1` is a value, not
/// an unknown flag.
#[test]
fn a_bad_friction_flag_is_refused_by_the_model_check() {
    let plate = repo().join("examples/plate_on_base.toml");
    for (bad, shown) in [("-0.1", "-0.1"), ("-3", "-3"), ("NaN", "NaN")] {
        let o = cfe(&[
            "run",
            plate.to_str().unwrap(),
            "--out",
            "/nonexistent-never-written",
            "--law",
            "coulomb",
            "--friction",
            bad,
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{bad}: {e}");
        assert!(
            e.contains("friction coefficient must be finite and ≥ 0") && e.contains(shown),
            "{bad}: {e}"
        );
    }
}

/// `--write-every last` writes only the last increment's VTU files (pairs.csv and
/// the summary stay complete); 0, negative and other words are refused before
/// anything is solved, naming the flag.
#[test]
fn write_every_flag() {
    let out = std::env::temp_dir().join(format!("cfe-cli-write-every-{}", std::process::id()));
    let plate = repo().join("examples/plate_on_base.toml");
    let o = cfe(&[
        "run",
        plate.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--write-every",
        "last",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut vtu: Vec<String> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    vtu.sort();
    assert_eq!(vtu, ["pairs_0010.vtu", "parts_0010.vtu"]);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"converged_increments\": 10"),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&out);
    for bad in ["0", "-1", "first", "2.5"] {
        let o = cfe(&[
            "run",
            plate.to_str().unwrap(),
            "--out",
            "/nonexistent-never-written",
            "--write-every",
            bad,
        ]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            stderr(&o).contains("--write-every"),
            "{bad}: {}",
            stderr(&o)
        );
    }
}

/// Runs `cfe run <problem> --out <out> [extra]` in the background (its output
/// discarded, so that no unread pipe can block it).
fn spawn_run(problem: &Path, out: &Path, extra: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_cfe"))
        .arg("run")
        .arg(problem)
        .arg("--out")
        .arg(out)
        .args(extra)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("cfe runs")
}

/// Waits for `child` at most `bound`; kills it (and fails) if it is still
/// running then. A liveness bound, not a speed assertion: what it guards would
/// otherwise take minutes or never end.
fn wait_at_most(child: &mut std::process::Child, bound: Duration, what: &str) -> ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait for cfe") {
            return status;
        }
        if start.elapsed() > bound {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: cfe was still running {bound:?} later");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// SIGTERM is honoured while the pictures are drawn: sent as soon as the only
/// increment's pairs table is on disk (the pictures come next), the run ends
/// within 10 s (a liveness bound: the pictures take about a second here), with
/// exit status 128 + 15, a summary saying `interrupted` and no picture or
/// temporary file; a run the signal reaches only after its pictures has them
/// all. Of three tries at least one must land in the picture phase (before
/// stopping was checked there, none did: every run completed).
#[test]
fn sigterm_during_the_pictures_interrupts_the_run() {
    let problem = problem("pictures_sigterm.toml", "increments = 10", "increments = 1");
    let mut interrupted = 0;
    for attempt in 0..3 {
        let out =
            std::env::temp_dir().join(format!("cfe-cli-sigterm-{}-{attempt}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let mut child = spawn_run(&problem, &out, &["--refine", "8"]);
        let start = Instant::now();
        while !out.join("pairs.csv").exists() {
            if let Some(s) = child.try_wait().unwrap() {
                panic!("cfe ended ({s}) before writing pairs.csv");
            }
            assert!(start.elapsed() < Duration::from_secs(600), "no pairs.csv");
            std::thread::sleep(Duration::from_millis(1));
        }
        let killed = Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(killed.success());
        let status = wait_at_most(&mut child, Duration::from_secs(10), "after SIGTERM");
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        let pictures =
            ["sigma_yy.png", "displacement.png", "pressure.png"].map(|p| out.join(p).exists());
        let temporary: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".tmp"))
            .collect();
        assert!(temporary.is_empty(), "{temporary:?}");
        if status.code() == Some(0) {
            assert!(summary.contains("\"status\": \"completed\""), "{summary}");
            assert_eq!(pictures, [true; 3]);
        } else {
            assert_eq!(status.code(), Some(128 + 15), "{status}");
            assert!(summary.contains("\"status\": \"interrupted\""), "{summary}");
            assert_eq!(pictures, [false; 3]);
            interrupted += 1;
        }
        let _ = std::fs::remove_dir_all(&out);
    }
    assert!(interrupted >= 1, "SIGTERM never stopped the pictures");
}

/// SIGTERM inside a long increment (the first of a Coulomb run, about a hundred
/// fixed-point steps of solves, sent a second after the run has started writing
/// into its folder) ends the run within a liveness bound of 30 s, with exit status
/// 128 + 15 and a consistent folder: a summary saying `interrupted`, no temporary
/// file, no lock left, `results.pvd` naming exactly the VTU files on disk,
/// each converged increment either in it or noted as left without VTU files by
/// the stop, and every file the run left listed in the folder's manifest (so the next run
/// removes them). The time from the signal to the exit is printed (not asserted:
/// the machine is shared).
#[test]
fn sigterm_inside_an_increment_stops_promptly() {
    let out = std::env::temp_dir().join(format!("cfe-cli-sigterm-inc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let plate = repo().join("examples/plate_on_base.toml");
    let args = ["--refine", "12", "--law", "coulomb", "--friction", "0.3"];
    let mut child = spawn_run(&plate, &out, &args);
    let start = Instant::now();
    while !out.join(".cfe-manifest").exists() {
        if let Some(s) = child.try_wait().unwrap() {
            panic!("cfe ended ({s}) before starting its run");
        }
        assert!(start.elapsed() < Duration::from_secs(600), "no manifest");
        std::thread::sleep(Duration::from_millis(1));
    }
    std::thread::sleep(Duration::from_secs(1));
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let sent = Instant::now();
    let status = wait_at_most(&mut child, Duration::from_secs(30), "after SIGTERM");
    eprintln!(
        "SIGTERM {:.2} s after the run started: exit {:.3} s later",
        sent.duration_since(start).as_secs_f64(),
        sent.elapsed().as_secs_f64()
    );
    assert_eq!(status.code(), Some(128 + 15), "{status}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted", "{summary}");
    let on_disk = |dir: &Path, prefix: &str| -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| format!("{prefix}{}", e.unwrap().file_name().to_string_lossy()))
            .collect()
    };
    let files: Vec<String> = on_disk(&out, "")
        .into_iter()
        .filter(|f| f != "vtu")
        .chain(on_disk(&out.join("vtu"), "vtu/"))
        .collect();
    let temporary: Vec<&String> = files.iter().filter(|f| f.ends_with(".tmp")).collect();
    assert!(temporary.is_empty(), "{temporary:?}");
    assert!(!files.contains(&".cfe-lock".to_string()), "{files:?}");
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    let mut named: Vec<String> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap().to_string())
        .collect();
    let mut series: Vec<String> = files
        .iter()
        .filter(|f| f.starts_with("vtu/"))
        .cloned()
        .collect();
    named.sort();
    series.sort();
    assert_eq!(named, series);
    // Every converged increment (all have files: output_every is 1) is either
    // in results.pvd or named by a note saying its VTU files were not written
    // because of the stop, never both, never neither.
    let converged = summary["converged_increments"].as_u64().unwrap() as usize;
    let notes = summary["notes"].as_array().unwrap();
    for k in 1..=converged {
        let in_pvd = named.contains(&format!("vtu/parts_{k:04}.vtu"));
        let noted = notes.iter().any(|n| {
            n["increment"] == k && n["message"].as_str().unwrap().contains("were not written")
        });
        assert!(
            in_pvd != noted,
            "increment {k}: in results.pvd {in_pvd}, noted {noted}: {summary}"
        );
    }
    let manifest = std::fs::read_to_string(out.join(".cfe-manifest")).unwrap();
    let listed: Vec<&str> = manifest.lines().skip(1).collect();
    for f in files.iter().filter(|f| !f.starts_with(".cfe-")) {
        assert!(
            listed.contains(&f.as_str()),
            "{f} not in the manifest: {manifest}"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// A problem whose title is a megabyte (with line breaks) runs and draws its
/// three pictures within a generous liveness bound (drawn whole, a 30 000-
/// character title took 204 s and a megabyte never ended); the summary keeps
/// the whole title.
#[test]
fn a_megabyte_title_is_drawn_promptly() {
    let title = "A very long title\\n".repeat(60_000);
    assert!(title.len() > 1_000_000);
    let problem = problem(
        "huge_title.toml",
        "title = \"Plate on a base\"",
        &format!("title = \"{title}\""),
    );
    let out = std::env::temp_dir().join(format!("cfe-cli-huge-title-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut child = spawn_run(&problem, &out, &[]);
    let status = wait_at_most(&mut child, Duration::from_secs(300), "a 1 MB title");
    assert!(status.success(), "{status}");
    for p in ["sigma_yy.png", "displacement.png", "pressure.png"] {
        assert!(out.join(p).is_file(), "{p}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["title"].as_str().unwrap().len(),
        title.len() - 60_000
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A fresh scratch folder for test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cfe-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `cfe run --out .` in a folder of the user's (`notes.tmp`, `thesis.docx.tmp`,
/// a `summary.json`) is refused with exit status 1, naming the colliding file and
/// `--force`, and leaves every file as it was; with `--force` it writes its
/// results there, replacing only `summary.json`; the next run needs no
/// `--force`, as the folder now holds a cfe run.
#[test]
fn out_dot_in_a_users_folder() {
    let dir = scratch("dot");
    let plate = repo().join("examples/plate_on_base.toml");
    let user = [
        ("notes.tmp", "notes"),
        ("thesis.docx.tmp", "thesis"),
        ("summary.json", "my summary"),
    ];
    for (f, text) in user {
        std::fs::write(dir.join(f), text).unwrap();
    }
    let run = |force: bool| {
        Command::new(env!("CARGO_BIN_EXE_cfe"))
            .args(["run", plate.to_str().unwrap(), "--out", "."])
            .args(if force { &["--force"][..] } else { &[][..] })
            .current_dir(&dir)
            .output()
            .expect("cfe runs")
    };
    let o = run(false);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("summary.json") && e.contains("--force") && e.contains("untouched"),
        "{e}"
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["notes.tmp", "summary.json", "thesis.docx.tmp"]);
    for (f, text) in user {
        assert_eq!(std::fs::read_to_string(dir.join(f)).unwrap(), text);
    }
    let o = run(true);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(dir.join("summary.json"))
            .unwrap()
            .contains("\"status\": \"completed\"")
    );
    assert!(dir.join("vtu/parts_0010.vtu").is_file());
    let o = run(false);
    assert!(o.status.success(), "{}", stderr(&o));
    for (f, text) in &user[..2] {
        assert_eq!(std::fs::read_to_string(dir.join(f)).unwrap(), *text);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run into a folder another process holds (here this test, through the
/// library's lock) is refused with exit status 1, naming that process's id, and
/// writes nothing; a non-empty folder without a cfe run is refused naming what it
/// holds; `--help` documents `--force`.
#[test]
fn a_folder_in_use_or_not_ours_is_refused() {
    let dir = scratch("lock");
    let plate = repo().join("examples/plate_on_base.toml");
    let run_plate = || {
        cfe(&[
            "run",
            plate.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ])
    };
    let held = cfe::output::folder::OutputFolder::open(&dir, false).unwrap();
    let o = run_plate();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("in use by another cfe run")
            && e.contains(&format!("process {}", std::process::id())),
        "{e}"
    );
    assert!(!dir.join("vtu").exists() && !dir.join("summary.json").exists());
    drop(held);

    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    let o = run_plate();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("holds no cfe run") && e.contains("notes.txt"),
        "{e}"
    );
    assert!(!dir.join("vtu").exists());

    let help = String::from_utf8_lossy(&cfe(&["run", "--help"]).stdout).into_owned();
    assert!(help.contains("--force"), "{help}");
    let _ = std::fs::remove_dir_all(&dir);
}
