//! The contact laws beyond the seed's (issue 12): frictionless, initial gaps
//! (`search_distance`), Coulomb friction with slip history, augmented Lagrangian —
//! each against a closed form or equilibrium, on small models.

mod common;

use common::Problem;

use cfe::Error;
use cfe::analysis::{Analysis, RunStatus};
use cfe::coupling::PairState;
use cfe::model::Model;
use cfe::solve::nonlinear::IncrementResult;
use std::path::Path;

/// A block (node part, x ∈ [0, 1], height `h`, bottom at `bottom`) over a thin,
/// stiff, fully supported base layer (host, x ∈ [−0.5, 1.5], y ∈ [−0.1, 0]); `iface`
/// is the interface's extra keys, `tail` the supports, loads and analysis.
fn block_on_layer(bottom: f64, h: f64, iface: &str, tail: &str) -> String {
    Problem::block_on_layer(bottom, h)
        .iface(iface)
        .raw(tail)
        .text()
}

fn analysis(text: &str) -> Analysis {
    common::analysis(text)
}

fn reaction(a: &Analysis, inc: &IncrementResult, k: usize) -> [f64; 2] {
    a.reactions(inc)[k]
}

/// An interference δ between a block of height L, its top held (y = 0), and a
/// rigidly supported stiff layer (a negative initial gap g₀ = −δ found within the
/// search distance): the block is compressed uniformly, p = E δ / L (uniaxial
/// plane stress, the frictionless face free to expand), on every pair's pressure
/// and in the top reaction, to the penalty's and the layer's compliance (1e-3).
#[test]
fn interference_gives_the_closed_form_pressure() {
    let (delta, l) = (0.01, 10.0);
    let text = block_on_layer(
        -delta,
        l,
        "law = \"frictionless\"\nsearch_distance = 0.05",
        &format!(
            "[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"y\"]\n[[support]]\npart = \"block\"\nat = [0.0, {}]\nfix = [\"x\"]\n[analysis]\nincrements = 1",
            l - delta
        ),
    );
    let a = analysis(&text);
    assert!(
        a.interfaces[0]
            .elements
            .iter()
            .all(|c| (c.gap0 + delta).abs() < 1e-12)
    );
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    let p = 1000.0 * delta / l;
    let rows = a.pair_rows(last);
    assert_eq!(rows.len(), 5);
    for r in &rows {
        assert_eq!(r.state, PairState::Bonded);
        assert!(
            (r.pressure - p).abs() < 1e-3 * p,
            "pressure {} vs {p}",
            r.pressure
        );
        assert!(r.force_s == 0.0 && r.shear == 0.0);
        assert!((r.gap0 + delta).abs() < 1e-12);
    }
    let top = reaction(&a, last, 1);
    assert!((top[1].abs() - p * 1.0).abs() < 1e-3 * p, "{top:?}");
}

/// An initial gap g₀ closes only once the top of the block is pushed down by more
/// than g₀: before, no reaction and the gap shrinks by the push; after, the column
/// carries R = (E w t / L)(δ − g₀) (a spring of the block's axial stiffness).
#[test]
fn initial_gap_closes_after_the_load_exceeds_it() {
    let (g0, l, push) = (0.02, 10.0, 0.05);
    let text = block_on_layer(
        g0,
        l,
        "law = \"frictionless\"\nsearch_distance = 0.05",
        &format!(
            "[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"y\"]\nvalue = [0.0, {}]\n[[support]]\npart = \"block\"\nat = [0.0, {}]\nfix = [\"x\"]\n[analysis]\nincrements = 5",
            -push,
            l + g0
        ),
    );
    let a = analysis(&text);
    let incs = common::solve(&a);
    let k = 1000.0 * 1.0 / l;
    for inc in &incs {
        let delta = push * inc.lambda;
        let r = reaction(&a, inc, 1)[1].abs();
        let rows = a.pair_rows(inc);
        if delta < g0 - 1e-9 {
            assert!(r < 1e-9, "increment {}: reaction {r}", inc.index);
            for row in &rows {
                assert_eq!(row.state, PairState::Open);
                assert!((row.gap - (g0 - delta)).abs() < 1e-9, "{}", row.gap);
            }
        } else if delta > g0 + 1e-9 {
            let expected = k * (delta - g0);
            assert!(
                (r - expected).abs() < 1e-3 * expected,
                "increment {}: reaction {r} vs {expected}",
                inc.index
            );
            assert!(rows.iter().all(|r| r.state == PairState::Bonded));
        }
    }
    // The law holds everywhere, and the summary says the shortcut was off.
    let summary = a.solve().unwrap().summary;
    assert_eq!(
        summary.status,
        RunStatus::Completed,
        "{:?}",
        summary.warnings
    );
    assert!(!summary.proportional_shortcut);
    assert_eq!(summary.interfaces[0].unpaired, 0);
}

/// A search distance shorter than some nodes' gaps leaves those nodes unpaired
/// (counted), instead of failing: a block tilted over a layer pairs only its
/// nodes within the distance.
#[test]
fn nodes_beyond_the_search_distance_are_unpaired() {
    let text = block_on_layer(
        0.0,
        1.0,
        "law = \"frictionless\"\nsearch_distance = 0.05",
        "[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"x\", \"y\"]",
    );
    let mut model = Model::from_str(&text, Path::new("t.toml"), 1).unwrap();
    // Lift the block's right half: its bottom rises linearly to 0.1 at x = 1.
    let p = model.part_index("block").unwrap();
    for x in &mut model.parts[p].mesh.nodes {
        x[1] += 0.1 * x[0];
    }
    let a = Analysis::new(model).unwrap();
    let iface = &a.interfaces[0];
    // Bottom nodes at x = 0, 0.25, 0.5 (gaps 0, 0.025, 0.05) pair; 0.75, 1 do not.
    assert_eq!(iface.elements.len(), 3);
    assert_eq!(iface.unpaired, 2);
    for c in &iface.elements {
        let x = c.position[0];
        assert!((c.gap0 - 0.1 * x).abs() < 1e-12, "{x}: {}", c.gap0);
        let edge = 0.25 * 1.01f64.sqrt();
        let expected = if x == 0.0 { 0.5 * edge } else { edge };
        assert!((c.tributary - expected).abs() < 1e-12, "{}", c.tributary);
    }
}

/// A block pressed on a base by a tilted load with the frictionless law: the
/// interface carries no tangential force, so the block's x support takes the whole
/// tangential load and the base none (with the seed's stick law the base takes a
/// share); the normal forces carry the normal load.
#[test]
fn frictionless_carries_no_shear() {
    let make = |law: &str| {
        Problem::block_on_base()
            .law(law)
            .support("block", "left", ["x"])
            .load("block", "top", [0.3, -1.0])
            .increments(2)
            .text()
    };
    let a = analysis(&make("frictionless"));
    let last = common::solve(&a).pop().unwrap();
    let base = reaction(&a, &last, 0);
    let side = reaction(&a, &last, 1);
    assert!(base[0].abs() < 1e-9, "base takes {base:?}");
    assert!((side[0] + 0.3).abs() < 1e-9, "side takes {side:?}");
    assert!((base[1] - 1.0).abs() < 1e-9);
    let rows = a.pair_rows(&last);
    assert!(rows.iter().all(|r| r.force_s == 0.0));
    let fy: f64 = rows.iter().map(|r| r.force_n).sum();
    assert!((fy - 1.0).abs() < 1e-9, "{fy}");
    let stick = analysis(&make("contact"));
    let last = common::solve(&stick).pop().unwrap();
    assert!(reaction(&stick, &last, 0)[0].abs() > 1e-3);
}

fn parse(text: &str) -> Result<Model, Error> {
    Model::from_str(text, Path::new("laws.toml"), 1)
}

/// The keys of the laws are checked: `friction` only with (and required by)
/// `coulomb`, finite and ≥ 0; `c_s = 0` only for `frictionless`;
/// `search_distance` a finite length ≥ 0 and not on a rigid tie;
/// `penetration_tolerance` only with augmented enforcement; unknown values of
/// `law` and `enforcement` rejected — a parse error naming the key, or, for a
/// value out of its range, an `Invalid` error with the key's path and line.
#[test]
fn bad_law_keys_are_typed_errors() {
    let tail = "[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"y\"]";
    // (keys, the key an `Invalid` error names, or the words of a parse error)
    enum Expect {
        Parse(&'static str),
        Invalid(&'static str),
    }
    use Expect::{Invalid, Parse};
    for (keys, expect) in [
        (
            "law = \"frictionless\"\nfriction = 0.3",
            Parse("`friction` applies"),
        ),
        ("law = \"coulomb\"", Parse("needs `friction`")),
        ("law = \"coulomb\"\nfriction = -0.1", Invalid("friction")),
        ("law = \"coulomb\"\nfriction = nan", Invalid("friction")),
        ("law = \"contact\"\nc_s = 0.0", Invalid("c_s")),
        (
            "law = \"contact\"\nsearch_distance = -1.0",
            Invalid("search_distance"),
        ),
        (
            "law = \"contact\"\nsearch_distance = inf",
            Invalid("search_distance"),
        ),
        (
            "law = \"rigid\"\nsearch_distance = 0.1",
            Parse("needs a contact law"),
        ),
        (
            "law = \"frictionless\"\npenetration_tolerance = 1e-6",
            Parse("`penetration_tolerance` applies"),
        ),
        (
            "law = \"frictionless\"\nenforcement = \"augmented\"\npenetration_tolerance = 0.0",
            Invalid("penetration_tolerance"),
        ),
        ("law = \"sticky\"", Parse("unknown variant")),
        ("enforcement = \"lagrange\"", Parse("unknown variant")),
    ] {
        let text = block_on_layer(0.0, 1.0, keys, tail);
        match (parse(&text), expect) {
            (Err(e @ Error::Parse { .. }), Parse(needle)) => {
                let m = e.to_string();
                assert!(m.contains(needle), "{keys}: {m}");
            }
            (Err(Error::Invalid { key, line, .. }), Invalid(name)) => {
                assert!(key.ends_with(&format!(".{name}")), "{keys}: {key}");
                let line = line.expect("the line of the value");
                let at = text.lines().nth(line - 1).unwrap_or("");
                assert!(
                    at.trim_start().starts_with(name),
                    "{keys}: line {line} is {at}"
                );
            }
            (other, _) => panic!("{keys}: not the expected error: {other:?}"),
        }
    }
    // c_s = 0 (or absent) is fine for the frictionless law.
    let text = block_on_layer(0.0, 1.0, "law = \"frictionless\"\nc_s = 0.0", tail);
    assert_eq!(parse(&text).unwrap().interfaces[0].c_s, 0.0);
}

/// A block on a base (same material, touching faces), the Coulomb law with μ:
/// `tail` holds the block's supports and loads.
fn coulomb_block(mu: f64, tail: &str) -> String {
    Problem::block_on_base()
        .law("coulomb")
        .friction(mu)
        .raw(tail)
        .text()
}

/// Checks Coulomb's law on every closed pair of an increment: stick pairs within
/// the cone, slip pairs on it (|f_s| = μ f_n) with the force opposing their slip
/// increment (same sign as the trial force c_s([[u_s]] − s_p)); returns the number
/// of slipping pairs.
fn check_coulomb(a: &Analysis, inc: &IncrementResult, mu: f64, tol: f64) -> usize {
    let mut slipping = 0;
    for r in a.pair_rows(inc) {
        match r.state {
            PairState::Bonded => assert!(
                r.force_s.abs() <= mu * r.force_n + tol,
                "stick pair at x = {} carries {} > μ {}",
                r.x,
                r.force_s,
                r.force_n
            ),
            PairState::Slip => {
                slipping += 1;
                assert!(
                    (r.force_s.abs() - mu * r.force_n).abs() <= tol,
                    "slip pair at x = {}: |f_s| {} vs μ f_n {}",
                    r.x,
                    r.force_s,
                    mu * r.force_n
                );
            }
            PairState::Open => assert!(r.force_n == 0.0 && r.force_s == 0.0),
        }
    }
    slipping
}

/// The message of `result`, which must be an [`Error::Unsupported`] naming
/// exactly `parts` (`what` names the case in a failure's message).
fn unsupported_message(
    result: Result<cfe::analysis::Results, Error>,
    parts: &[&str],
    what: &str,
) -> String {
    match result {
        Err(e @ Error::Unsupported { .. }) => {
            let Error::Unsupported { parts: named, .. } = &e else {
                unreachable!()
            };
            assert_eq!(named, parts, "{what}");
            e.to_string()
        }
        Err(e) => panic!("{what}: unexpected error {e}"),
        Ok(res) => panic!(
            "{what}: {:?}, largest displacement {:?}",
            res.summary.status, res.summary.max_displacement
        ),
    }
}

/// The Coulomb block's tail: P = 1 down and Q = 0.2 sideways on its top.
const PUSH_BELOW: &str = "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.2, -1.0]\n[analysis]\nincrements = 2";

/// The Coulomb block pressed by P = 1 on its top, which is pushed sideways by a
/// displacement far beyond the elastic range (4 increments).
fn coulomb_block_pushed_far(mu: f64) -> String {
    Problem::coulomb_block_pushed_far(mu, 4).text()
}

/// A block pushed far sideways (`coulomb_block_pushed_far`): every closed pair slips with
/// |f_s| = μ f_n (all but at most one closed), and the sideways reaction is μ P.
fn assert_slides_at_mu(a: &Analysis, res: &cfe::analysis::Results, mu: f64) {
    let n = check_coulomb(a, &res.last, mu, 1e-8);
    let closed = res.pairs.iter().filter(|r| r.state.is_closed()).count();
    assert!(
        n == closed && n >= res.pairs.len() - 1,
        "{n} of {closed} closed pairs slip"
    );
    let side = res.summary.reactions[1].fx;
    assert!((side.abs() - mu).abs() < 1e-8, "{side}");
}

/// Coulomb, Q < μP: a block pressed by P and pushed sideways by Q = 0.2 P with
/// μ = 0.5 stays put: the interface carries the whole of Q (Σ f_s = Q), every
/// pair is inside the cone, the law holds (status `completed`).
#[test]
fn coulomb_below_the_limit_sticks() {
    let mu = 0.5;
    let text = coulomb_block(mu, PUSH_BELOW);
    let a = analysis(&text);
    let res = common::solve_completed(&a);
    assert!(!res.summary.proportional_shortcut);
    let rows = &res.pairs;
    let fs: f64 = rows.iter().map(|r| r.force_s).sum();
    let fnn: f64 = rows.iter().map(|r| r.force_n).sum();
    // Force on the node part: −Q along s = (−n_y, n_x) = (−1, 0) is +Q... the
    // interface pushes the block back by −Q in x.
    assert!(
        (fs.abs() - 0.2).abs() < 1e-9 && (fnn - 1.0).abs() < 1e-9,
        "{fs} {fnn}"
    );
    let slipping = check_coulomb(&a, &res.last, mu, 1e-9);
    assert!(
        slipping < rows.len() / 2,
        "{slipping} of {} slip",
        rows.len()
    );
}

/// Coulomb, sliding: the block's top is pushed sideways by a displacement far
/// beyond the elastic range while P presses it down: every pair slips with
/// |f_s| = μ f_n, and the sideways reaction is μ P.
#[test]
fn coulomb_beyond_the_limit_slips_on_every_pair() {
    let mu = 0.3;
    let text = coulomb_block_pushed_far(mu);
    let a = analysis(&text);
    let res = common::solve_completed(&a);
    assert_slides_at_mu(&a, &res, mu);
    // The slip history: the plastic slip is the jump less the elastic part.
    for r in &res.pairs {
        assert!(r.slip.abs() > 0.0 && r.slip.signum() == r.slip_s.signum());
    }
}

/// A part held tangentially by friction alone: the plate of the seed's second
/// example (no x support on the plate) pressed on its base with μ = 0.2, meshes
/// refined twice. Its face stretches outwards from the middle, so the active-set
/// iteration passes through a pattern where every pair slips (a stiffness with no
/// tangential support, until slipping pairs kept a stabilising spring). The run
/// completes with Coulomb's law on every pair, and the friction forces balance:
/// Σ f_s = 0, as the plate carries no tangential load.
#[test]
fn a_part_held_only_by_friction_finds_its_stick_zone() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let mut a = Analysis::new(Model::from_file(&path, 2).unwrap()).unwrap();
    let mu = 0.2;
    a.override_friction(mu).unwrap();
    let res = common::solve_completed(&a);
    let slipping = check_coulomb(&a, &res.last, mu, 1e-6 * 1500.0);
    let closed = res.pairs.iter().filter(|r| r.state.is_closed()).count();
    let sticking = closed - slipping;
    assert!(
        slipping > 0 && sticking > 0,
        "{slipping} slip, {sticking} stick"
    );
    let fs: f64 = res.pairs.iter().map(|r| r.force_s).sum();
    let fnn: f64 = res.pairs.iter().map(|r| r.force_n).sum();
    assert!(fs.abs() < 1e-9 * 1500.0, "Σ f_s = {fs}");
    assert!((fnn - 1500.0).abs() < 1e-8 * 1500.0, "Σ f_n = {fnn}");
}

/// A block pushed sideways beyond friction with nothing else to hold it
/// (Q = 0.45 P > μ P, μ = 0.3, too little to tip it): no state of rest exists,
/// and the run says so before any solve, with a typed error naming the block
/// and the inclined plane's numbers: at the first increment (λ = 1/2) it is
/// pressed with P/2 = 0.5 and pushed along with Q/2 = 0.225 against
/// μ P/2 = 0.15 (Beer & Johnston, *Statics*, §8.2).
#[test]
fn a_block_pushed_beyond_friction_is_not_reported_as_held() {
    let text = coulomb_block(
        0.3,
        "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.45, -1.0]\n[analysis]\nincrements = 2",
    );
    let e = unsupported_message(analysis(&text).solve(), &["block"], "block");
    assert!(
        e.contains("harder than friction holds them")
            && e.contains("at increment 1 (load factor 0.5000)")
            && e.contains("onto its faces with 5.0000e-1")
            && e.contains("along its faces with 2.2500e-1")
            && e.contains("holds at most 1.5000e-1"),
        "{e}"
    );
}

/// The seed's plate on a base (examples/plate_on_base.toml) pushed sideways as
/// well as down on x ∈ [100, 130] (Q = 400 N, P = 1500 N), the Coulomb law, T3
/// and Q4 meshes. With μ = 0.2 friction holds at most μP = 300 N < Q and nothing
/// else holds the plate along the face: no state of rest exists, and the run
/// ends at its first increment, before any solve, with a typed error saying so
/// (once it "completed" with the plate moved by 1e9 mm: the slipping pairs'
/// springs let it drift, and the checks were relative to a load scale grown with
/// the drift; later it searched 200 patterns before failing). With μ = 0.3
/// (μP = 450 N > Q) it is held, every pair on its law, the sideways reaction
/// equal to Q. The seed's implex scheme cannot hold it even then — it does not
/// correct the states it carries, whose slipping pairs find no fixed point —
/// and says so instead of writing the drift as a result.
#[test]
fn the_plate_pushed_sideways_beyond_friction_is_not_reported_as_held() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let seed = std::fs::read_to_string(&example).unwrap();
    let edited = |mu: f64, elements: &str| {
        let text = seed
            .replace("from = [86.0, 135.0]", "from = [100.0, 135.0]")
            .replace("to = [114.0, 135.0]", "to = [130.0, 135.0]")
            .replace("force = [0.0, -1500.0]", "force = [400.0, -1500.0]")
            .replace(
                "cells = [20, 12] }",
                &format!("cells = [20, 12]{elements} }}"),
            )
            .replace(
                "cells = [28, 6] }",
                &format!("cells = [28, 6]{elements} }}"),
            )
            .replace(
                "law = \"contact\"",
                &format!("law = \"coulomb\"\nfriction = {mu}"),
            );
        for edit in [
            "from = [100.0",
            "to = [130.0",
            "[400.0,",
            "cells = [28, 6]",
            "friction",
        ] {
            assert!(
                text.contains(edit),
                "the example no longer has the line for {edit}"
            );
        }
        text
    };
    for elements in ["", ", elements = \"q4\""] {
        let e = unsupported_message(
            analysis(&edited(0.2, elements)).solve(),
            &["plate"],
            elements,
        );
        // At λ = 0.1: P = 150 N, Q = 40 N, μP = 30 N.
        assert!(
            e.contains("at increment 1 (load factor 0.1000)")
                && e.contains("onto its faces with 1.5000e2")
                && e.contains("along its faces with 4.0000e1")
                && e.contains("holds at most 3.0000e1"),
            "{elements}: {e}"
        );
        let a = analysis(&edited(0.3, elements));
        let res = a.solve().unwrap();
        assert_eq!(res.summary.status, RunStatus::Completed, "{elements}");
        check_coulomb(&a, &res.last, 0.3, 1e-8 * 1500.0);
        let fx: f64 = res.summary.reactions.iter().map(|r| r.fx).sum();
        assert!(
            (fx + 400.0).abs() < 1e-8 * 1500.0,
            "{elements}: Σ reaction x = {fx}"
        );
    }
    // The seed's implex scheme carries each increment's states to the next
    // without correcting them: the slipping pairs it carries cannot hold the
    // plate, though friction could, and it says so instead of writing the drift
    // as a result.
    let implex = edited(0.3, "").replace("scheme = \"active-set\"", "scheme = \"implex\"");
    assert!(implex.contains("scheme = \"implex\""));
    match analysis(&implex).solve() {
        Err(e @ Error::NoConvergence(_)) => {
            let e = e.to_string();
            assert!(e.contains("found no fixed point"), "{e}");
        }
        Err(e) => panic!("implex: unexpected error {e}"),
        Ok(res) => panic!(
            "implex: {:?}, largest displacement {:?}",
            res.summary.status, res.summary.max_displacement
        ),
    }
}

/// Cattaneo–Mindlin pushed beyond friction: examples/hertz/cattaneo.toml (a
/// cylinder pressed by P = 4000 N on a block, then pushed sideways, μ = 0.3)
/// with its tangential load raised from 600 N to Q = 1300 N > μP = 1200 N. The
/// cylinder, held along the block's face by friction alone, has no state of rest
/// once Q > μP: the shear step's first four increments (Q up to 1040 N) are
/// solved and written, and the fifth stops before its solve with the error
/// naming the cylinder. (Once that increment ended `completed_with_violations`
/// with one pair settled sticking beyond μ f_n by the 100 N excess: the cylinder
/// reported held, its reaction −1300 N.)
#[test]
fn the_cylinder_pushed_beyond_friction_stops_where_the_load_passes_mu_p() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/hertz/cattaneo.toml");
    let text = std::fs::read_to_string(&example)
        .unwrap()
        .replace("force = [600.0, 0.0]", "force = [1300.0, 0.0]");
    assert!(text.contains("[1300.0, 0.0]") && text.contains("friction = 0.3"));
    let mut a = Analysis::new(Model::from_str(&text, &example, 1).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("cfe-test-cattaneo-beyond-{}", std::process::id()));
    let e = a
        .run(&out, &mut |_| {})
        .expect_err("no state of rest at Q > μP");
    let Error::Unsupported { parts, .. } = &e else {
        panic!("unexpected error {e}");
    };
    assert_eq!(parts, &["cylinder"]);
    let e = e.to_string();
    assert!(
        e.contains("at increment 6 (step 2, load factor 1.0000)")
            && e.contains("onto its faces with 4.0000e3")
            && e.contains("along its faces with 1.3000e3")
            && e.contains("holds at most 1.2000e3"),
        "{e}"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"failed\"") && summary.contains("\"converged_increments\": 5"),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The seed's plate on its base (examples/plate_on_base.toml) with a block on
/// the plate, the plate on a `coulomb` face (μ = 0.2), the block on the plate
/// by `block_law` (its default penalty), and the block pushed down and sideways
/// on the left half of its top (P = 1500 N, Q = `q`), meshes refined `refine`
/// times.
///
/// ```text
///            ↙ P, Q
///        ┌──────┐ block
///   ┌────┴──────┴─────┐ plate
///   ╞═════════════════╡ μ = 0.2
///   │      base       │
///   └─────────────────┘ fixed
/// ```
fn block_on_plate(block_law: &str, q: f64, refine: usize) -> Analysis {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let seed = std::fs::read_to_string(&example).unwrap();
    let block = format!(
        "[[part]]\nname = \"block\"\nmaterial = \"steel\"\nrectangle = {{ x = [85.0, 115.0], y = [135.0, 150.0], cells = [12, 6] }}\n\n[[interface]]\nname = \"block-plate\"\nhost = \"plate\"\nnodes = \"block\"\nboundary = \"bottom\"\n{block_law}\n\n[[support]]"
    );
    let text = seed
        .replace("law = \"contact\"", "law = \"coulomb\"\nfriction = 0.2")
        .replacen("[[support]]", &block, 1)
        .replace(
            "part = \"plate\"\nboundary = \"top\"",
            "part = \"block\"\nboundary = \"top\"",
        )
        .replace("from = [86.0, 135.0]", "from = [85.0, 150.0]")
        .replace("to = [114.0, 135.0]", "to = [100.0, 150.0]")
        .replace(
            "force = [0.0, -1500.0]",
            &format!("force = [{q:.1}, -1500.0]"),
        );
    for edit in [
        "friction = 0.2",
        "name = \"block\"",
        "part = \"block\"",
        "[85.0, 150.0]",
        "[100.0, 150.0]",
    ] {
        assert!(
            text.contains(edit),
            "the example no longer has the line for {edit}"
        );
    }
    Analysis::new(Model::from_str(&text, &example, refine).unwrap()).unwrap()
}

/// Asserts Coulomb's law (coefficient `mu`) on every pair of `interface` at the
/// last increment of `res`; returns its numbers of stick and slip pairs.
fn assert_coulomb_on(
    a: &Analysis,
    res: &cfe::analysis::Results,
    interface: &str,
    mu: f64,
) -> (usize, usize) {
    let (mut stick, mut slip) = (0, 0);
    for r in a.pair_rows(&res.last) {
        if r.interface != interface {
            continue;
        }
        match r.state {
            PairState::Bonded => {
                stick += 1;
                assert!(
                    r.force_s.abs() <= mu * r.force_n + 1e-6,
                    "{interface}: stick x = {}",
                    r.x
                );
            }
            PairState::Slip => {
                slip += 1;
                assert!(
                    (r.force_s.abs() - mu * r.force_n).abs() <= 1e-6,
                    "{interface}: slip x = {}",
                    r.x
                );
            }
            PairState::Open => assert!(r.force_n == 0.0 && r.force_s == 0.0),
        }
    }
    (stick, slip)
}

/// Asserts Coulomb's law (μ = 0.2) on every plate–base pair of the block on the
/// plate (`block_on_plate`), at least one of them sticking and some slipping,
/// and the sideways reaction equal to the push `q`.
fn assert_plate_held_by_a_stick_zone(a: &Analysis, res: &cfe::analysis::Results, q: f64) {
    let fx: f64 = res.summary.reactions.iter().map(|r| r.fx).sum();
    assert!((fx + q).abs() < 1e-8 * 1500.0, "Σ reaction x = {fx}");
    assert!(res.summary.max_displacement.value < 0.1);
    let (stick, slip) = assert_coulomb_on(a, res, "plate-base", 0.2);
    assert!(stick >= 1 && slip > 0, "{stick} stick, {slip} slip");
}

/// The block on the plate (`block_on_plate`) pushed with Q = 400 N. Neither
/// part alone can be judged — the block is bonded to the plate, or held by
/// μ = 0.5, and the plate is pressed from above and below — but the two taken
/// together rest on the plate's face alone, so Q > μP = 300 N has no state of
/// rest, and the run stops at its first increment with the error naming both
/// (the search once ran 200 patterns and advised raising `max_iterations`, or
/// named the parts free after 8 s). With Q = 100 N < μP it completes, the
/// sideways reaction equal to Q.
#[test]
fn a_stack_on_a_frictional_face_is_judged_as_one_body() {
    for block_law in ["law = \"contact\"", "law = \"coulomb\"\nfriction = 0.5"] {
        let e = unsupported_message(
            block_on_plate(block_law, 400.0, 1).solve(),
            &["plate", "block"],
            block_law,
        );
        // At λ = 0.1: P = 150 N, Q = 40 N, μP = 30 N.
        assert!(
            e.contains("'plate', 'block' taken together at increment 1")
                && e.contains("onto their faces with 1.5000e2")
                && e.contains("along their faces with 4.0000e1")
                && e.contains("holds at most 3.0000e1")
                && e.contains("on 'plate-base'"),
            "{block_law}: {e}"
        );
    }
    let res = block_on_plate("law = \"contact\"", 100.0, 1)
        .solve()
        .unwrap();
    assert_eq!(res.summary.status, RunStatus::Completed);
    let fx: f64 = res.summary.reactions.iter().map(|r| r.fx).sum();
    assert!((fx + 100.0).abs() < 1e-8 * 1500.0, "Σ reaction x = {fx}");
}

/// The block bonded on the plate (`block_on_plate`) pushed with Q = 250 N,
/// 0.83 μP: held, but by a plate face where all closed pairs but one slip. A
/// pattern with every closed pair slipping balances at any position along the
/// face; its fixed point once carried the plate and block off by 290 m under the
/// slipping pairs' springs, was taken as converged, and the run stopped with a
/// loss of precision (the drift through the block's stiff penalty). Such a
/// fixed point is no longer taken as converged: the run completes with one
/// stick pair holding the plate, Coulomb's law on every plate–base pair, the
/// sideways reaction equal to Q, and the plate moved by hundredths of a mm.
#[test]
fn a_part_held_by_slipping_pairs_does_not_drift_off() {
    let a = block_on_plate("law = \"contact\"", 250.0, 1);
    let res = common::solve_completed(&a);
    assert_plate_held_by_a_stick_zone(&a, &res, 250.0);
}

/// The block bonded on the plate (`block_on_plate`) pushed with Q = 200 N,
/// meshes refined twice: within friction (Q < μP = 300 N), but the Coulomb
/// active-set search from all pairs bonded reaches no state satisfying the law
/// (it once failed after 81 patterns). The increment is searched again from the
/// pattern a continuation in μ leads to (16 μ, where every closed pair sticks,
/// down to μ): the run completes with Coulomb's law on every plate–base pair, a
/// stick zone holding the plate, the sideways reaction equal to Q, and a note
/// naming the first increment and counting its solves in all (the first
/// search's and the continuation's). This case still needs the continuation
/// with the semi-smooth Newton search: from all pairs bonded it finds no state
/// at the first increment. (Which later increments need it too is the
/// search's path, not the model's: the fixed-point search needed it at the
/// first only, the Newton search at the first and the fourth to the tenth.)
#[test]
fn a_state_the_search_misses_is_found_by_a_continuation_in_mu() {
    let a = block_on_plate("law = \"contact\"", 200.0, 2);
    let res = common::solve_completed(&a);
    assert_plate_held_by_a_stick_zone(&a, &res, 200.0);
    let noted: Vec<(usize, &str)> = res
        .summary
        .notes
        .iter()
        .filter(|n| n.message.contains("continuation in μ"))
        .map(|n| (n.increment, n.message.as_str()))
        .collect();
    assert_eq!(
        noted.first().map(|n| n.0),
        Some(1),
        "{:?}",
        res.summary.notes
    );
    let solves = res.summary.iterations[0];
    assert!(
        noted[0]
            .1
            .contains(&format!("continuation in μ, {solves} solves in all")),
        "{}",
        noted[0].1
    );
}

/// The block bonded on the plate (`block_on_plate`) pushed with Q = 150 N,
/// meshes refined twice, where the plate's one stick pair goes beyond its cone:
/// with it slipping every closed plate–base pair slips, their slip forces
/// balance at any position, and the plate slides off — no fixed point. The
/// search used to stick every slipping pair at once, cycled, and settled with
/// 22 pairs off the law (and the continuation in μ ended the same way). The
/// stick point now moves to the slipping pair nearest its cone in the last
/// pattern that had a fixed point: the search itself completes (no
/// continuation), with Coulomb's law on every plate–base pair and the sideways
/// reaction equal to Q.
#[test]
fn a_stick_zone_moves_when_its_last_pair_slips() {
    let a = block_on_plate("law = \"contact\"", 150.0, 2);
    let res = common::solve_completed(&a);
    assert_plate_held_by_a_stick_zone(&a, &res, 150.0);
    assert!(
        !res.summary
            .notes
            .iter()
            .any(|n| n.message.contains("continuation")),
        "{:?}",
        res.summary.notes
    );
}

/// Both faces Coulomb: the block on μ = 0.5 on the plate on μ = 0.2
/// (`block_on_plate`), pushed with Q = 250 N (0.83 μP): the run completes with
/// each face on its own law and the sideways reaction equal to Q.
#[test]
fn a_stack_on_two_frictional_faces_completes_on_both_laws() {
    let a = block_on_plate("law = \"coulomb\"\nfriction = 0.5", 250.0, 1);
    let res = common::solve_completed(&a);
    assert_plate_held_by_a_stick_zone(&a, &res, 250.0);
    assert_coulomb_on(&a, &res, "block-plate", 0.5);
}

/// The seed's plate pressed on its last cell (1500 N over x = 165–170 mm, at
/// the end of the plate), the Coulomb law with μ = 0.2: the fixed-point search
/// reached a pattern with one closed pair, which leaves the plate free to turn
/// about it, and the run once stopped there with an `Unsupported` error, as if
/// the plate could not rest on its base (a pattern the search reaches is not
/// the model's answer; the fixed-point search needs the continuation in μ
/// here). The run completes with the plate resting on its end: Coulomb's law
/// on every pair, the load balanced. (The semi-smooth Newton search, the
/// default, finds the state without the continuation; the continuation's
/// count of solves is checked in
/// `a_state_the_search_misses_is_found_by_a_continuation_in_mu`.) The plate
/// pulled off its base still ends with the `Unsupported` error
/// (`a_plate_pulled_off_its_base_is_reported_free_not_sliding`).
#[test]
fn a_pattern_leaving_a_part_free_does_not_end_a_frictional_search() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let text = std::fs::read_to_string(&example)
        .unwrap()
        .replace("from = [86.0, 135.0]", "from = [165.0, 135.0]")
        .replace("to = [114.0, 135.0]", "to = [170.0, 135.0]")
        .replace("law = \"contact\"", "law = \"coulomb\"\nfriction = 0.2");
    assert!(text.contains("[165.0, 135.0]") && text.contains("friction = 0.2"));
    let a = analysis(&text);
    let res = common::solve_completed(&a);
    check_coulomb(&a, &res.last, 0.2, 1e-8 * res.last.load_scale);
    let fy: f64 = res.summary.reactions.iter().map(|r| r.fy).sum();
    assert!((fy - 1500.0).abs() < 1e-8 * 1500.0, "Σ reaction y = {fy}");
}

/// The roller in its cradle (examples/roller_in_cradle, meshes refined twice)
/// with Coulomb friction μ = 0.2: the fixed-point search from the ninth
/// increment's pattern cycled at the tenth and settled on a pattern with one
/// stick pair beyond its cone (`completed_with_violations`); the continuation
/// in μ found the state. The run completes with every pair on Coulomb's law and
/// the load carried (the semi-smooth Newton search, the default, finds the
/// state itself: no continuation).
#[test]
fn the_roller_refined_twice_at_mu_0_2_completes_on_the_law() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/roller_in_cradle/roller_in_cradle.toml");
    let mut a = Analysis::from_file(&example, 2).unwrap();
    a.override_friction(0.2).unwrap();
    let res = common::solve_completed(&a);
    check_coulomb(&a, &res.last, 0.2, 1e-8 * res.last.load_scale);
    let fy: f64 = res.summary.reactions.iter().map(|r| r.fy).sum();
    let applied = res.summary.applied[1];
    assert!(
        (fy + applied).abs() < 1e-8 * applied.abs(),
        "Σ reaction y = {fy}, load {applied}"
    );
}

/// The seed's plate pulled up off its base (the load reversed), the Coulomb law:
/// every pair opens and the plate is free, an `Unsupported` error naming it that
/// says the loads should press the parts together — not that friction fails to
/// hold it, which no pair slipping would explain.
#[test]
fn a_plate_pulled_off_its_base_is_reported_free_not_sliding() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let text = std::fs::read_to_string(&example)
        .unwrap()
        .replace("force = [0.0, -1500.0]", "force = [0.0, 1500.0]")
        .replace("law = \"contact\"", "law = \"coulomb\"\nfriction = 0.2");
    assert!(text.contains("[0.0, 1500.0]") && text.contains("friction = 0.2"));
    let e = unsupported_message(analysis(&text).solve(), &["plate"], "pulled off");
    assert!(
        e.contains("29 of its 29 coupling pairs open")
            && e.contains("press the parts together")
            && !e.contains("friction"),
        "{e}"
    );
}

/// Coulomb with augmented-Lagrangian enforcement: below the limit (Q = 0.2 P,
/// μ = 0.5) the interface carries Q with every stick pair inside the cone; pushed
/// far sideways (μ = 0.3) every closed pair slips with |f_s| = μ f_n and the
/// sideways reaction is μ P — and in both, no closed pair penetrates by more than
/// the penetration tolerance (1e-9), whatever the penalty.
#[test]
fn coulomb_with_augmented_enforcement() {
    let augmented = |text: String, mu: f64| {
        text.replace(
            &format!("friction = {mu}"),
            &format!("friction = {mu}\nenforcement = \"augmented\"\npenetration_tolerance = 1e-9"),
        )
    };
    let no_penetration = |res: &cfe::analysis::Results| {
        for r in res.pairs.iter().filter(|r| r.state.is_closed()) {
            assert!(
                r.gap.abs() <= 1e-9,
                "pair at x = {} penetrates {}",
                r.x,
                r.gap
            );
        }
    };
    let below = augmented(coulomb_block(0.5, PUSH_BELOW), 0.5);
    let a = analysis(&below);
    let res = common::solve_completed(&a);
    let fs: f64 = res.pairs.iter().map(|r| r.force_s).sum();
    assert!((fs.abs() - 0.2).abs() < 1e-9, "Σ f_s = {fs}");
    check_coulomb(&a, &res.last, 0.5, 1e-9);
    no_penetration(&res);

    let mu = 0.3;
    let slide = augmented(coulomb_block_pushed_far(mu), mu);
    let a = analysis(&slide);
    let res = common::solve_completed(&a);
    assert_slides_at_mu(&a, &res, mu);
    no_penetration(&res);
}

/// Friction is path-dependent: a block pressed by an interference (constant
/// pressure) is pushed sideways to δ and back to 0. Going out it slips with
/// |F| = μ P; coming back, the first step unloads elastically (sticks), then it
/// slips the other way (F = −μ P at δ = 0) and keeps a plastic slip — where a run
/// straight to δ = 0 has no force at all. A pair that sticks through an increment
/// keeps its plastic slip, whatever patterns the active set tried (a pair it opened
/// and closed again on the way does not touch down afresh).
#[test]
fn friction_history_load_then_unload() {
    let mu = 0.4;
    let (delta_n, l) = (0.01, 1.0);
    let text = block_on_layer(
        -delta_n,
        l,
        &format!("law = \"coulomb\"\nfriction = {mu}\nsearch_distance = 0.05"),
        "[[support]]\npart = \"block\"\nboundary = \"top\"\nfix = [\"x\", \"y\"]\nvalue = [0.05, 0.0]\n[analysis]\nincrements = 1",
    );
    let a = analysis(&text);
    let mut solver = a.solver().unwrap();
    solver.set_load_factors(vec![0.5, 1.0, 0.9, 0.5, 0.0]);
    let incs = common::run_all(solver);
    let fx = |inc: &IncrementResult| a.reactions(inc)[1][0];
    let p = a.reactions(&incs[1])[1][1].abs();
    assert!(p > 0.0);
    for inc in &incs {
        check_coulomb(&a, inc, mu, 1e-8);
        assert!(inc.violations.is_empty());
    }
    // A pair closed on both sides of an increment that sticks at its end stuck
    // through it: its plastic slip has not moved (whatever patterns the active set
    // tried on the way).
    for w in incs.windows(2) {
        let (h0, h1) = (&w[0].pair_history[0], &w[1].pair_history[0]);
        for (p, s) in w[1].states[0].iter().enumerate() {
            if w[0].states[0][p].is_closed() && *s == PairState::Bonded {
                assert_eq!(h1[p].slip, h0[p].slip, "pair {p} at λ = {}", w[1].lambda);
            }
        }
    }
    let slips = |inc: &IncrementResult| {
        a.pair_rows(inc)
            .iter()
            .filter(|r| r.state == PairState::Slip)
            .count()
    };
    // Out: slipping at μP (the top's support pushes the block along +x against
    // the friction).
    assert!(
        (fx(&incs[1]) - mu * p).abs() < 1e-6 * p,
        "{} vs {}",
        fx(&incs[1]),
        mu * p
    );
    assert_eq!(slips(&incs[1]), 5);
    // First step back: sticks, the force drops below μP.
    assert_eq!(slips(&incs[2]), 0);
    assert!(fx(&incs[2]).abs() < mu * p * (1.0 - 1e-3));
    // Back at δ = 0: slipping the other way, F = −μP, plastic slip left behind.
    let last = incs.last().unwrap();
    assert_eq!(slips(last), 5);
    let pl = a.reactions(last)[1][1].abs();
    assert!(
        (fx(last) + mu * pl).abs() < 1e-6 * pl,
        "{} vs {}",
        fx(last),
        mu * pl
    );
    assert!(a.pair_rows(last).iter().all(|r| r.slip.abs() > 1e-6));
    // Straight to δ = 0 (λ = 0 only): no tangential force.
    let mut fresh = a.solver().unwrap();
    fresh.set_load_factors(vec![0.0]);
    let direct = fresh.run(|_| Ok(())).unwrap();
    assert!(fx(&direct).abs() < 1e-9 * p);
}

/// Augmented Lagrangian: a block pressed on a base (frictionless, a load off the
/// centre so the pressure varies) gives the same contact forces for c_n from 1e3
/// to 1e6 × E (to 1e-6 of the load) once the Uzawa iterations have brought the
/// penetration under the tolerance, while the penalty alone differs by far more;
/// the summary reports the iterations and the final penetration.
#[test]
fn augmented_is_independent_of_the_penalty() {
    let make = |factor: f64, augmented: bool| {
        let keys = if augmented {
            "enforcement = \"augmented\"\npenetration_tolerance = 1e-11"
        } else {
            ""
        };
        Problem::block_on_base()
            .cells("block", [6, 4])
            .law("frictionless")
            .iface_key("c_n", factor * 1000.0)
            .iface(keys)
            .support("block", "left", ["x"])
            .load_from_to("block", [0.8, 1.0], [1.0, 1.0], [0.0, -1.5])
            .load_from_to("block", [0.0, 1.0], [0.2, 1.0], [0.0, 0.5])
            .increments(1)
            .text()
    };
    let forces = |factor: f64, augmented: bool| {
        let a = analysis(&make(factor, augmented));
        let res = common::solve_completed(&a);
        if augmented {
            assert!(res.summary.augmented_penetration <= 1e-11);
            assert!(res.summary.fixed_point_iterations[0] > 0);
            for r in res.pairs.iter().filter(|r| r.state.is_closed()) {
                assert!(r.gap.abs() <= 1e-11, "{}", r.gap);
            }
        }
        res.pairs.iter().map(|r| r.force_n).collect::<Vec<f64>>()
    };
    let reference = forces(1e6, true);
    assert!(reference.contains(&0.0), "part of the face lifts off");
    for factor in [1e3, 1e4, 1e5] {
        let f = forces(factor, true);
        for (a, b) in f.iter().zip(&reference) {
            assert!((a - b).abs() < 1e-6, "c_n = {factor} E: {a} vs {b}");
        }
    }
    // The penalty alone depends on c_n visibly at 1e3 × E.
    let soft = forces(1e3, false);
    let worst = soft
        .iter()
        .zip(&reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst > 1e-4, "{worst}");
}

/// The contact-states issue's thin plate loaded off-centre, with Coulomb friction:
///
/// ```text
///                         1500 N on x ∈ [120, 148]
///                               ↓↓↓↓↓↓
///    ┌──────────────────────────────────────────────┐ plate 6 mm, x ∈ [30, 170]
///    └──────────────────────────────────────────────┘ ← coulomb, μ = 0.2
///  ┌──────────────────────────────────────────────────────┐
///  │                  base (host)                         │
///  └──────────────────────────────────────────────────────┘
///  //////////////////////// clamped ////////////////////////
/// ```
///
/// The plate's far end lifts, so pairs there slip with a normal force near zero
/// and their slip turns back by a hair from one increment to the next: a slip
/// that reverses beyond the cone keeps slipping the other way, with nothing left to
/// settle. At K = 4 and 8 every increment ends on Coulomb's law on every pair
/// (checked here from the pair rows: stick inside the cone, slip on it, open
/// pairs free and not penetrating, closed pairs not pulling) and in equilibrium.
/// Before, K = 8 stopped at λ = 0.2 on a pair "reversing" by 63 N against a cone
/// of 8e-4 N (and K = 16 did not converge).
#[test]
fn coulomb_on_the_thin_plate_loaded_off_centre() {
    let mu = 0.2;
    // The seed's plate on a base (examples/plate_on_base.toml), 6 mm thin, the
    // load moved to x ∈ [120, 148], the Coulomb law.
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let seed = std::fs::read_to_string(&example).unwrap();
    let text = seed
        .replace(
            "y = [120.0, 135.0], cells = [28, 6]",
            "y = [120.0, 126.0], cells = [28, 3]",
        )
        .replace("from = [86.0, 135.0]", "from = [120.0, 126.0]")
        .replace("to = [114.0, 135.0]", "to = [148.0, 126.0]")
        .replace(
            "law = \"contact\"",
            &format!("law = \"coulomb\"\nfriction = {mu}"),
        );
    for edit in [
        "cells = [28, 3]",
        "from = [120.0, 126.0]",
        "to = [148.0, 126.0]",
        "friction",
    ] {
        assert!(
            text.contains(edit),
            "the example no longer has the line for {edit}"
        );
    }
    for k in [4, 8] {
        let model = Model::from_str(&text, Path::new("thin.toml"), k).unwrap();
        let a = Analysis::new(model).unwrap();
        let mut increments = 0;
        // Each pair's state and plastic slip at the last increment's end (before
        // the first: touching, s_p = 0).
        let pairs = a.interfaces[0].elements.len();
        let mut before = (vec![PairState::Bonded; pairs], vec![0.0; pairs]);
        let res = a
            .solve_observed(|inc| {
                increments += 1;
                // A pair closed on both sides of an increment that sticks at its
                // end stuck through it: its plastic slip has not moved.
                let slip: Vec<f64> = inc.pair_history[0].iter().map(|h| h.slip).collect();
                for (p, s) in inc.states[0].iter().enumerate() {
                    if before.0[p].is_closed() && *s == PairState::Bonded {
                        assert_eq!(slip[p], before.1[p], "K = {k}: pair {p}");
                    }
                }
                before = (inc.states[0].clone(), slip);
                assert!(
                    inc.violations.is_empty(),
                    "K = {k}: {} violations, first {:?}",
                    inc.violations.len(),
                    inc.violations.first()
                );
                // Forces to 1e-8 of the load, penetration to 1e-9 of the largest
                // displacement.
                let tol = 1e-8 * 1500.0;
                let umax = inc.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                check_coulomb(&a, inc, mu, tol);
                for r in a.pair_rows(inc) {
                    if r.state.is_closed() {
                        assert!(r.force_n >= -tol, "K = {k}: x = {} pulls", r.x);
                    } else {
                        assert!(r.gap_n >= -1e-9 * umax, "K = {k}: x = {}", r.x);
                    }
                }
                Ok(())
            })
            .unwrap_or_else(|e| panic!("K = {k}: {e}"));
        assert_eq!(increments, 10);
        assert_eq!(res.summary.status, RunStatus::Completed, "K = {k}");
        assert!(res.summary.equilibrium_error < 1e-9, "K = {k}");
        // The plate lifts at its far end and some pairs slip.
        let open = res.pairs.iter().filter(|r| r.state == PairState::Open);
        assert!(open.count() > 0, "K = {k}");
        assert!(res.pairs.iter().any(|r| r.state == PairState::Slip));
    }
}
