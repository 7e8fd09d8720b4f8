//! Load steps (`[[step]]`, issue 12): each step's loads and prescribed values ramp
//! over its increments and stay at full value after it. Checked against
//! independent truth: superposition for a linear model, Coulomb's closed form for
//! a block pressed and then pushed, and the input checks by error variant.

mod common;

use common::Problem;

use cfe::Error;
use cfe::analysis::{Analysis, RunStatus};
use cfe::coupling::PairState;
use cfe::model::Model;
use cfe::solve::nonlinear::IncrementResult;
use std::path::Path;

/// A block (x ∈ [0, 1], y ∈ [0, 1]) on a base (x ∈ [−0.5, 1.5], y ∈ [−1, 0],
/// bottom clamped), non-matching meshes, the interface's keys `iface`; `tail`
/// holds the steps, the block's supports and its loads.
fn block(iface: &str, tail: &str) -> String {
    Problem::block_on_base().iface(iface).raw(tail).text()
}

fn solve(text: &str) -> (Analysis, Vec<IncrementResult>) {
    let a = common::analysis(text);
    let incs = common::solve(&a);
    (a, incs)
}

/// The largest difference of two displacement vectors relative to the largest
/// displacement of the first.
fn rel_diff(u: &[f64], v: &[f64]) -> f64 {
    let scale = u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    u.iter()
        .zip(v)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// Superposition: a tied (linear) model loaded in two steps — a downward force
/// in step 1, a sideways force and a prescribed displacement of the block's
/// corner in step 2 — ends each step on the one-step solution of the loads
/// applied so far (to round-off), and labels every increment with its step, the
/// step's load factor and the monotonic time.
#[test]
fn two_steps_of_a_linear_model_superpose() {
    let down = "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\n";
    let side = "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.3, 0.0]\n";
    let corner =
        "[[support]]\npart = \"block\"\nat = [1.0, 1.0]\nfix = [\"y\"]\nvalue = [0.0, 0.002]\n";
    let steps =
        "[[step]]\nname = \"press\"\nincrements = 2\n[[step]]\nname = \"shear\"\nincrements = 3\n";
    let in_step2 = |s: &str| s.replacen('\n', "\nstep = \"shear\"\n", 1);
    let text = block(
        "law = \"rigid\"",
        &format!("{steps}{down}{}{}", in_step2(side), in_step2(corner)),
    );
    let (a, incs) = solve(&text);
    assert_eq!(incs.len(), 5);
    let labels: Vec<(usize, usize, f64, f64)> = incs
        .iter()
        .map(|i| (i.index, i.step, i.lambda, i.time))
        .collect();
    let expect = [
        (1, 0, 0.5, 0.5),
        (2, 0, 1.0, 1.0),
        (3, 1, 1.0 / 3.0, 1.0 + 1.0 / 3.0),
        (4, 1, 2.0 / 3.0, 1.0 + 2.0 / 3.0),
        (5, 1, 1.0, 2.0),
    ];
    for (l, e) in labels.iter().zip(&expect) {
        assert!(
            l.0 == e.0 && l.1 == e.1 && (l.2 - e.2).abs() < 1e-15 && (l.3 - e.3).abs() < 1e-15,
            "{l:?} vs {e:?}"
        );
    }
    // One step of everything, and one step of step 1's loads (the corner held at 0).
    let all = block(
        "law = \"rigid\"\n",
        &format!("[analysis]\nincrements = 1\n{down}{side}{corner}"),
    );
    let (_, one) = solve(&all);
    let first = block(
        "law = \"rigid\"",
        &format!(
            "[analysis]\nincrements = 1\n{down}{}",
            corner.replace("0.002", "0.0")
        ),
    );
    let (_, part1) = solve(&first);
    let d_end = rel_diff(&one[0].u, &incs[4].u);
    let d_mid = rel_diff(&part1[0].u, &incs[1].u);
    assert!(d_end < 1e-10 && d_mid < 1e-10, "{d_end:e} {d_mid:e}");
    // Halfway through step 2: step 1 in full plus half of step 2 (linearity).
    let half: Vec<f64> = part1[0]
        .u
        .iter()
        .zip(&one[0].u)
        .map(|(p, o)| p + (o - p) * 2.0 / 3.0)
        .collect();
    assert!(rel_diff(&half, &incs[3].u) < 1e-10);
    let res = a.solve().unwrap();
    assert!(!res.summary.proportional_shortcut);
    assert!(
        res.summary
            .proportional_shortcut_off
            .as_deref()
            .is_some_and(|w| w.contains("2 steps")),
        "{:?}",
        res.summary.proportional_shortcut_off
    );
    let names: Vec<&str> = res
        .summary
        .increment_steps
        .iter()
        .map(|s| s.step.as_str())
        .collect();
    assert_eq!(names, ["press", "press", "shear", "shear", "shear"]);
    assert!(
        res.pairs
            .iter()
            .all(|r| r.step == "shear" && r.increment == 5)
    );
}

/// A step without loads holds the earlier steps' loads: with one loaded step
/// the loading stays proportional (the shortcuts stay on) and the unloaded
/// step's increments repeat the loaded step's final solution exactly.
#[test]
fn a_step_without_load_holds_the_load() {
    let text = block(
        "law = \"contact\"",
        "[[step]]\nname = \"load\"\nincrements = 2\n[[step]]\nname = \"hold\"\nincrements = 2\n[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.2, -1.0]\n",
    );
    let (a, incs) = solve(&text);
    assert_eq!(incs.len(), 4);
    assert_eq!(incs[3].u, incs[1].u);
    assert_eq!((incs[3].step, incs[3].lambda, incs[3].time), (1, 1.0, 2.0));
    assert!(a.solve().unwrap().summary.proportional_shortcut);
}

/// Coulomb's closed form along a load history: a block pressed by N (step 1) and
/// then pushed sideways (step 2). Pushed by a force T = 0.2 N < μN (μ = 0.5) it
/// sticks: the interface carries −T, no pair leaves the cone, most pairs stick
/// and the faces' tangential jumps stay below 1 % of the displacements (no
/// sliding). Pushed by a displacement
/// of its top far beyond the elastic range, every closed pair slips with
/// |f_s| = μ f_n and the sideways reaction is μN — to round-off.
#[test]
fn friction_block_pressed_then_pushed() {
    let steps =
        "[[step]]\nname = \"press\"\nincrements = 1\n[[step]]\nname = \"push\"\nincrements = 3\n";
    let press =
        "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\nstep = \"press\"\n";
    // Below the limit: a sideways force in step 2.
    let mu = 0.5;
    let text = block(
        &format!("law = \"coulomb\"\nfriction = {mu}"),
        &format!(
            "{steps}{press}[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.2, 0.0]\nstep = \"push\"\n"
        ),
    );
    let a = common::analysis(&text);
    let res = common::solve_completed(&a);
    let fs: f64 = res.pairs.iter().map(|r| r.force_s).sum();
    let fnn: f64 = res.pairs.iter().map(|r| r.force_n).sum();
    assert!(
        (fs.abs() - 0.2).abs() < 1e-9 && (fnn - 1.0).abs() < 1e-9,
        "{fs} {fnn}"
    );
    let mut stick = 0;
    for r in &res.pairs {
        match r.state {
            PairState::Bonded => {
                stick += 1;
                assert!(r.force_s.abs() <= mu * r.force_n + 1e-9);
            }
            PairState::Slip => assert!((r.force_s.abs() - mu * r.force_n).abs() < 1e-9),
            PairState::Open => {}
        }
    }
    assert!(
        stick > res.pairs.len() / 2,
        "{stick} of {} stick",
        res.pairs.len()
    );
    // No sliding: the tangential jumps are a small fraction of the displacements.
    let jump = res.pairs.iter().map(|r| r.slip_s.abs()).fold(0.0, f64::max);
    let umax = res.last.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(jump < 0.01 * umax, "{jump:e} vs {umax:e}");

    // Beyond the limit: the top pushed 0.005 sideways in step 2 (held in x at 0
    // during step 1).
    let mu = 0.3;
    let text = block(
        &format!("law = \"coulomb\"\nfriction = {mu}"),
        &format!(
            "{steps}{press}[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"x\"]\nvalue = [0.005, 0.0]\nstep = \"push\"\n"
        ),
    );
    let (a, incs) = solve(&text);
    // Step 1 holds the top at x = 0: its prescribed value only moves in step 2.
    let top = common::displacement_at(&a, &incs[0], "block", [1.0, 1.0]);
    assert_eq!(top[0], 0.0);
    let mid = common::displacement_at(&a, &incs[2], "block", [1.0, 1.0]);
    assert!((mid[0] - 0.005 * 2.0 / 3.0).abs() < 1e-15, "{mid:?}");
    let last = incs.last().unwrap();
    let side = a.reactions(last)[1][0];
    assert!((side.abs() - mu).abs() < 1e-8, "{side}");
    let rows = a.pair_rows(last);
    let closed = rows.iter().filter(|r| r.state.is_closed()).count();
    for r in rows.iter().filter(|r| r.state.is_closed()) {
        assert_eq!(r.state, PairState::Slip, "pair at x = {}", r.x);
        assert!((r.force_s.abs() - mu * r.force_n).abs() < 1e-8);
    }
    assert!(
        closed >= rows.len() - 1,
        "{closed} of {} closed",
        rows.len()
    );
}

fn parse(text: &str) -> Result<Model, Error> {
    Model::from_str(text, Path::new("steps.toml"), 1)
}

/// The key and line of an [`Error::Invalid`] (panics on any other result).
fn invalid(text: &str) -> (String, Option<usize>, String) {
    match parse(text) {
        Err(Error::Invalid {
            key, line, message, ..
        }) => (key, line, message),
        other => panic!("expected Error::Invalid, got {other:?}"),
    }
}

/// Every misuse of steps is an `Error::Invalid` naming the key and its line: an
/// unknown step name (with and without `[[step]]` tables), a step of 0
/// increments, `[analysis] increments` beside `[[step]]`; a duplicate name is an
/// `Error::DuplicateName` with its key and line.
#[test]
fn step_input_errors_name_key_and_line() {
    let load = |step: &str| {
        format!(
            "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\nstep = \"{step}\"\n"
        )
    };
    let two = "[[step]]\nname = \"a\"\nincrements = 1\n[[step]]\nname = \"b\"\nincrements = 2\n";
    let line_of = |text: &str, pat: &str| text[..text.find(pat).unwrap()].matches('\n').count() + 1;

    let text = block("law = \"rigid\"", &format!("{two}{}", load("c")));
    let (key, line, msg) = invalid(&text);
    assert_eq!(key, "load#1.step");
    assert_eq!(line, Some(line_of(&text, "step = \"c\"")));
    assert!(msg.contains("a, b"), "{msg}");

    let text = block("law = \"rigid\"", &load("a"));
    let (key, _, msg) = invalid(&text);
    assert_eq!(key, "load#1.step");
    assert!(msg.contains("no [[step]]"), "{msg}");

    let text = block(
        "law = \"rigid\"",
        &format!(
            "{two}[[support]]\npart = \"block\"\nat = [0.0, 1.0]\nfix = [\"x\"]\nstep = \"x\"\n"
        ),
    );
    assert_eq!(invalid(&text).0, "support#2.step");

    // A name given twice: `Error::DuplicateName`, keyed by the step's number
    // (both steps are `step.a`).
    let text = block("law = \"rigid\"", &two.replace("\"b\"", "\"a\""));
    match parse(&text) {
        Err(Error::DuplicateName { key, line, .. }) => {
            assert_eq!(key, "step#2.name");
            assert_eq!(line, Some(line_of(&text, "name = \"a\"\nincrements = 2")));
        }
        other => panic!("expected Error::DuplicateName, got {other:?}"),
    }

    let text = block(
        "law = \"rigid\"",
        &two.replace("increments = 2", "increments = 0"),
    );
    assert_eq!(invalid(&text).0, "step.b.increments");

    let text = block(
        "law = \"rigid\"",
        &format!("[analysis]\nincrements = 3\n{two}"),
    );
    let (key, line, msg) = invalid(&text);
    assert_eq!(key, "analysis.increments");
    assert_eq!(line, Some(line_of(&text, "increments = 3")));
    assert!(msg.contains("[[step]]"), "{msg}");

    // Without `[analysis] increments`, the run has the steps' total.
    let m = parse(&block("law = \"rigid\"", &format!("{two}{}", load("b")))).unwrap();
    assert_eq!(m.settings.increments, 3);
    assert_eq!(m.loads[0].step, 1);
    assert_eq!(m.steps().len(), 2);
}

/// The files of a run in steps: `results.pvd` times are step index − 1 + the
/// step's factor (monotonic), the last increment of each step is written even
/// between `output_every`, `pairs.csv` names the step, `summary.json` lists the
/// steps and each increment's step.
#[test]
fn outputs_name_the_steps() {
    let text = block(
        "law = \"contact\"",
        "[analysis]\noutput_every = 2\n[[step]]\nname = \"press\"\nincrements = 1\n[[step]]\nname = \"shear\"\nincrements = 2\n[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\n[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.1, 0.0]\nstep = \"shear\"\n",
    );
    let mut a = common::analysis(&text);
    let out = std::env::temp_dir().join(format!("cfe-test-steps-{}", std::process::id()));
    let summary = a.run(&out, &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    let times: Vec<&str> = pvd
        .split("timestep=\"")
        .skip(1)
        .map(|t| &t[..t.find('"').unwrap()])
        .collect();
    // Increments 1 (end of "press"), 2 (every 2nd) and 3 (the last), two blocks each.
    assert_eq!(times, ["1.0", "1.0", "1.5", "1.5", "2.0", "2.0"], "{pvd}");
    // The VTU is binary-appended: look for the field data's names in its header.
    let vtu = String::from_utf8_lossy(&std::fs::read(out.join("vtu/pairs_0002.vtu")).unwrap())
        .into_owned();
    assert!(vtu.contains("Name=\"STEP\"") && vtu.contains("Name=\"LOAD_FACTOR\""));
    let csv = std::fs::read_to_string(out.join("pairs.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .ends_with(",increment,step,load_factor")
    );
    assert!(lines.all(|l| l.ends_with(",3,shear,1")), "{csv}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["steps"][1]["name"], "shear");
    assert_eq!(json["increment_steps"][1]["step"], "shear");
    assert_eq!(json["increment_steps"][1]["load_factor"], 0.5);
    assert_eq!(json["increment_steps"][2]["time"], 2.0);
    assert_eq!(json["increments"], 3);
    let _ = std::fs::remove_dir_all(&out);
}
