//! Load amplitudes (issue 40): a `[[step]]` may set the loads and prescribed
//! values of earlier steps to any factor of their full value (`scale`, or per
//! load or support in `factors`), ramped from where the previous step left them —
//! down to zero, or reversed. Checked against independent truth: a linear (tied)
//! model returns exactly to zero and reverses exactly; a Coulomb block cycled
//! sideways draws a hysteresis loop that closes, unloads with the stick
//! stiffness, is point-symmetric, slides at μN and whose area is the work the
//! pairs dissipate; the input checks by error variant.

mod common;

use cfe::Error;
use cfe::analysis::Analysis;
use cfe::solve::nonlinear::IncrementResult;

/// A unit block (x ∈ [0, 1], y ∈ [0, 1], 4 × 4 Q4) on a base (x ∈ [−0.5, 1.5],
/// y ∈ [−1, 0], 5 × 3 Q4, its bottom clamped), both E = 1000, ν = 0.3, plane
/// stress: both meshes mirror-symmetric about x = 0.5. `iface` holds the
/// interface's keys, `tail` the steps, supports and loads.
fn block(iface: &str, tail: &str) -> String {
    format!(
        r#"[materials.steel]
E = 1000.0
nu = 0.3
[[part]]
name = "base"
material = "steel"
rectangle = {{ x = [-0.5, 1.5], y = [-1.0, 0.0], cells = [5, 3], elements = "q4" }}
[[part]]
name = "block"
material = "steel"
rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], cells = [4, 4], elements = "q4" }}
[[interface]]
name = "contact"
host = "base"
nodes = "block"
boundary = "bottom"
{iface}
[[support]]
name = "ground"
part = "base"
boundary = "bottom"
fix = ["x", "y"]
{tail}"#
    )
}

fn solve(text: &str) -> (Analysis, Vec<IncrementResult>) {
    let a = common::analysis(text);
    let incs = common::solve(&a);
    (a, incs)
}

fn largest(u: &[f64]) -> f64 {
    u.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// A tied (linear) block loaded by a force and a prescribed displacement,
/// unloaded with `scale = 0.0`, returns to exactly zero displacement and zero
/// reaction; `scale = -1.0` then gives exactly the negated loaded solution (to
/// round-off); every increment is labelled with its step and the step's own
/// factor k / n.
#[test]
fn a_linear_model_unloads_to_zero_and_reverses() {
    let tail = r#"[[support]]
name = "corner"
part = "block"
at = [1.0, 1.0]
fix = ["x"]
value = [0.002, 0.0]
[[load]]
name = "down"
part = "block"
boundary = "top"
force = [0.0, -1.0]
[[step]]
name = "load"
increments = 2
[[step]]
name = "unload"
increments = 3
scale = 0.0
[[step]]
name = "reverse"
increments = 2
scale = -1.0
"#;
    let (a, incs) = solve(&block("law = \"rigid\"", tail));
    assert_eq!(incs.len(), 7);
    let loaded = &incs[1];
    let zero = &incs[4];
    let reversed = &incs[6];
    let scale = largest(&loaded.u);
    assert!(scale > 1e-4);
    // Back at zero: every displacement and reaction exactly 0.
    assert!(zero.u.iter().all(|&x| x == 0.0), "{}", largest(&zero.u));
    for r in a.reactions(zero) {
        assert_eq!(r, [0.0, 0.0]);
    }
    // Reversed: the negated solution; halfway down, half of it.
    for (x, y) in loaded.u.iter().zip(&reversed.u) {
        assert!((x + y).abs() <= 1e-12 * scale, "{x} vs {y}");
    }
    for (x, y) in loaded.u.iter().zip(&incs[2].u) {
        assert!((2.0 / 3.0 * x - y).abs() <= 1e-12 * scale);
    }
    let labels: Vec<(usize, f64)> = incs.iter().map(|i| (i.step, i.lambda)).collect();
    let third = 1.0 / 3.0;
    let expect = [
        (0, 0.5),
        (0, 1.0),
        (1, third),
        (1, 2.0 * third),
        (1, 1.0),
        (2, 0.5),
        (2, 1.0),
    ];
    for (l, e) in labels.iter().zip(&expect) {
        assert!(l.0 == e.0 && (l.1 - e.1).abs() < 1e-15, "{l:?} vs {e:?}");
    }
    // A per-load factor: the force unloaded, the prescribed value held, equals
    // the prescribed value alone.
    let held = tail.replace("scale = 0.0", "factors = { down = 0.0 }");
    let (_, incs) = solve(&block("law = \"rigid\"", &held));
    let alone = tail
        .replace("force = [0.0, -1.0]", "force = [0.0, 0.0]")
        .replace("scale = 0.0", "");
    let (_, only) = solve(&block("law = \"rigid\"", &alone));
    let d = incs[4].u.iter().zip(&only[4].u).map(|(x, y)| (x - y).abs());
    assert!(d.fold(0.0, f64::max) <= 1e-12 * scale);
}

/// A Coulomb block (μ = 0.1) pressed by 1 N on its top, its top then pushed
/// sideways to δ = +D, back to −D and forward to +D again (D = 0.005, far
/// beyond the stick range) by a prescribed displacement whose `factors` the
/// steps set. Checked, each by a reasoning independent of the solver:
/// - at ±D every pair slips (μ is low enough that the tipping moment μP·h
///   lifts no edge: 6μh/w < 1), and the support's force is μ × the pairs'
///   normal force (the block's balance in x with Coulomb's law);
/// - the loop closes: at the second +D the state is the first's (with every pair
///   slipping the state is fixed by the prescribed displacements, whatever the
///   path);
/// - the unloading branch starts with the stick stiffness: a small step back
///   from +D (every pair sticks again) has the slope of the same model tied
///   (every pair bonded: the same linear system), not the sliding slope just
///   before it (pressing alone already makes the outer pairs slip outwards, so
///   the loading branch has no all-stick start);
/// - point symmetry (the model is mirror-symmetric about x = 0.5): back at
///   δ = 0 from +D the force and the residual plastic slips are the negatives of
///   those back at δ = 0 from −D, mirrored, and not zero;
/// - energy: around the closed cycle the support's work ∮ F dδ equals the work
///   the pairs dissipate, Σ ∫ f_s ds_p with f_s = c_s([[u_s]] − s_p) (the
///   elastic energy is a quadratic state function, so with the trapezoidal rule
///   in both sums the identity is exact over each increment).
#[test]
fn coulomb_hysteresis_loop() {
    let (mu, d) = (0.1, 0.005);
    let n = 8;
    let tail = format!(
        r#"[[support]]
name = "push"
part = "block"
boundary = "top"
fix = ["x"]
value = [{d}, 0.0]
step = "out"
[[load]]
name = "press"
part = "block"
boundary = "top"
force = [0.0, -1.0]
[[step]]
name = "press"
increments = 1
[[step]]
name = "out"
increments = {n}
[[step]]
name = "turn"
increments = 1
factors = {{ push = 0.999 }}
[[step]]
name = "back"
increments = {n}
factors = {{ push = 0.0 }}
[[step]]
name = "back-on"
increments = {n}
factors = {{ push = -1.0 }}
[[step]]
name = "again"
increments = {n}
factors = {{ push = 0.0 }}
[[step]]
name = "again-on"
increments = {n}
factors = {{ push = 1.0 }}
"#
    );
    let (a, incs) = solve(&block(
        &format!("law = \"coulomb\"\nfriction = {mu}"),
        &tail,
    ));
    let step = |name: &str| a.model.steps.iter().position(|s| s.name == name).unwrap();
    let end = |name: &str| {
        incs.iter()
            .rposition(|i| i.step == step(name))
            .expect("the step's increments")
    };
    let push = 1; // the support's index
    let force = |k: usize| a.reactions(&incs[k])[push][0];
    let delta = |k: usize| common::displacement_at(&a, &incs[k], "block", [0.5, 1.0])[0];
    let rows = |k: usize| a.pair_rows(&incs[k]);
    let normal = |k: usize| rows(k).iter().map(|r| r.force_n).sum::<f64>();
    for inc in &incs {
        assert!(inc.violations.is_empty(), "increment {}", inc.index);
    }
    // At ±D: every pair slips; |F| = μ N.
    let (out, back_on, again_on) = (end("out"), end("back-on"), end("again-on"));
    for (k, sign) in [(out, 1.0), (back_on, -1.0), (again_on, 1.0)] {
        assert!((delta(k) - sign * d).abs() < 1e-12);
        assert!(
            rows(k)
                .iter()
                .all(|r| r.state == cfe::coupling::PairState::Slip)
        );
        let (f, nf) = (force(k), normal(k));
        assert!(
            (f.abs() - mu * nf).abs() < 1e-6 * nf,
            "{f} vs μN = {}",
            mu * nf
        );
        assert_eq!(f.signum(), sign, "the support pushes the block along δ");
    }
    // The loop closes.
    let scale = largest(&incs[out].u);
    let gap = incs[out]
        .u
        .iter()
        .zip(&incs[again_on].u)
        .map(|(x, y)| (x - y).abs());
    assert!(gap.fold(0.0, f64::max) < 1e-8 * scale);
    for (r, s) in rows(out).iter().zip(&rows(again_on)) {
        assert!(
            (r.slip - s.slip).abs() < 1e-8 * d,
            "{} vs {}",
            r.slip,
            s.slip
        );
    }
    // Unloading starts with the stick stiffness.
    let slope = |k: usize| (force(k) - force(k - 1)) / (delta(k) - delta(k - 1));
    let turn = end("turn");
    assert!(
        rows(turn)
            .iter()
            .all(|r| r.state == cfe::coupling::PairState::Bonded)
    );
    // The stick stiffness: the same model tied (every pair bonded: the same
    // stiffness matrix), pressed, then pushed by D.
    let tied_text = block(
        "law = \"rigid\"",
        &tail.replace(&format!("increments = {n}"), "increments = 1"),
    );
    let tied_text = tied_text
        .split("[[step]]\nname = \"turn\"")
        .next()
        .unwrap()
        .to_string();
    let (t, tied) = solve(&tied_text);
    let stick = (t.reactions(&tied[1])[push][0] - t.reactions(&tied[0])[push][0]) / d;
    assert!(
        (slope(turn) - stick).abs() < 1e-6 * stick,
        "{} vs {stick}",
        slope(turn)
    );
    assert!(
        slope(out).abs() < 0.05 * stick,
        "sliding slope {}",
        slope(out)
    );
    // Point symmetry at δ = 0, with a residual slip.
    let (back, again) = (end("back"), end("again"));
    assert!(delta(back).abs() < 1e-12 && delta(again).abs() < 1e-12);
    assert!(
        force(back).abs() > 0.1 * mu,
        "residual force {}",
        force(back)
    );
    assert!((force(back) + force(again)).abs() < 1e-6 * force(back).abs());
    let (rb, ra) = (rows(back), rows(again));
    for r in &rb {
        assert!(r.slip.abs() > 1e-5 * d, "residual slip at x = {}", r.x);
        let m = ra
            .iter()
            .find(|s| (s.x - (1.0 - r.x)).abs() < 1e-12)
            .expect("mirror pair");
        assert!(
            (r.slip + m.slip).abs() < 1e-6 * d,
            "{} vs {}",
            r.slip,
            m.slip
        );
    }
    // Energy: ∮ F dδ = Σ ∫ f_s ds_p over the cycle out → again-on.
    let c_s = a.interfaces[0].c_s;
    let (mut work, mut dissipated) = (0.0, 0.0);
    for k in out + 1..=again_on {
        work += 0.5 * (force(k) + force(k - 1)) * (delta(k) - delta(k - 1));
        for (r0, r1) in rows(k - 1).iter().zip(&rows(k)) {
            let f = |r: &cfe::results::PairRow| c_s * (r.slip_s - r.slip);
            dissipated += 0.5 * (f(r0) + f(r1)) * (r1.slip - r0.slip);
        }
    }
    assert!(work > 0.5 * mu * d, "loop area {work}");
    assert!(
        (work - dissipated).abs() < 1e-5 * work,
        "∮F dδ = {work}, dissipated {dissipated}"
    );
}

/// The step keys are checked where they are read: a `factors` key naming no
/// load or support, one naming a load of a later step, a non-finite factor and
/// `scale` on the first step are `Invalid` errors naming the key and its line.
#[test]
fn step_factors_are_checked() {
    let base = |steps: &str| {
        block(
            "law = \"rigid\"",
            &format!(
                "[[load]]\nname = \"down\"\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\nstep = \"two\"\n{steps}"
            ),
        )
    };
    let invalid = |text: String, key: &str| match cfe::model::Model::from_str(
        &text,
        std::path::Path::new("t.toml"),
        1,
    ) {
        Err(Error::Invalid { key: k, line, .. }) => {
            assert_eq!(k, key);
            assert!(line.is_some(), "{key}: a line");
        }
        other => panic!("{key}: {other:?}"),
    };
    let one = "[[step]]\nname = \"one\"\nincrements = 1\n";
    let two = "[[step]]\nname = \"two\"\nincrements = 1\n";
    invalid(
        base(&format!("{one}{two}factors = {{ up = 0.0 }}\n")),
        "step.two.factors.up",
    );
    invalid(
        base(&format!("{one}factors = {{ down = 0.5 }}\n{two}")),
        "step.one.factors.down",
    );
    invalid(
        base(&format!("{one}{two}factors = {{ down = nan }}\n")),
        "step.two.factors.down",
    );
    invalid(base(&format!("{one}scale = 0.0\n{two}")), "step.one.scale");
}
