//! The seed's two examples (Tosati et al. 2016, §3.1–3.2, reconstructed in SPEC §4),
//! run end to end: counts, equilibrium, the contact conditions at every pair, the
//! state pattern SPEC §4 describes, and the two schemes.

mod common;

use cfe::analysis::Analysis;
use cfe::coupling::PairState;
use cfe::model::{Model, Scheme};
use std::path::Path;

fn example(name: &str) -> Model {
    Model::from_file(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join("examples")
            .join(name),
        1,
    )
    .unwrap()
}

/// Bonded (true) / open (false) per pair of interface `i`.
fn pattern(states: &[Vec<PairState>], i: usize) -> Vec<bool> {
    states[i].iter().map(|&s| s == PairState::Bonded).collect()
}

/// Bonded pairs form one contiguous run.
fn contiguous(p: &[bool]) -> bool {
    let first = p.iter().position(|&b| b);
    let last = p.iter().rposition(|&b| b);
    match (first, last) {
        (Some(f), Some(l)) => p[f..=l].iter().all(|&b| b),
        _ => true,
    }
}

/// Plate on a base: 480 + 336 elements and 29 pairs; reactions balance the 1500 N
/// load to 1e-8; contact conditions hold; the plate is bonded over a central zone
/// that contains the whole loaded segment and open over several nodes at each end;
/// all outputs are written.
#[test]
fn plate_on_base() {
    let mut a = Analysis::new(example("plate_on_base.toml")).unwrap();
    assert_eq!(a.model.parts[0].mesh.elements.len(), 480);
    assert_eq!(a.model.parts[1].mesh.elements.len(), 336);
    assert_eq!(a.interfaces[0].elements.len(), 29);
    let out = std::env::temp_dir().join(format!("cfe-test-plate-{}", std::process::id()));
    let summary = a.run(&out, &mut |_| {}).unwrap();
    assert!(
        summary.equilibrium_error < 1e-8,
        "equilibrium error {:e}",
        summary.equilibrium_error
    );
    assert!((summary.reactions[0].fy - 1500.0).abs() < 1e-8 * 1500.0);
    for f in [
        "summary.json",
        "pairs.csv",
        "results.pvd",
        "sigma_yy.png",
        "displacement.png",
        "vtu/parts_0010.vtu",
        "vtu/pairs_0010.vtu",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("pairs.csv")).unwrap();
    assert_eq!(
        csv.lines().next().unwrap(),
        "interface,node,x,y,host_element,state,gap_n,slip_s,force_n,force_s,settled,violation,violation_amount,gap0,gap,slip,pressure,shear,tributary,segment,increment,step,load_factor"
    );
    assert_eq!(csv.lines().count(), 30);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "parts",
        "interfaces",
        "increments",
        "iterations",
        "max_displacement",
        "reactions",
        "timings",
    ] {
        assert!(json.get(key).is_some(), "summary.json lacks {key}");
    }
    let _ = std::fs::remove_dir_all(&out);

    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    common::check_contact_conditions(&a, last);
    let p = pattern(&last.states, 0);
    let xs: Vec<f64> = a.interfaces[0]
        .elements
        .iter()
        .map(|c| c.position[0])
        .collect();
    assert!(contiguous(&p), "bonded zone not contiguous: {p:?}");
    for (x, &b) in xs.iter().zip(&p) {
        if (86.0..=114.0).contains(x) {
            assert!(b, "pair under the load at x = {x} is open");
        }
    }
    assert!(
        p[..3].iter().all(|&b| !b) && p[p.len() - 3..].iter().all(|&b| !b),
        "ends not open: {p:?}"
    );
}

/// Bar in a bearing: 1920 + 540 elements and 16 + 16 pairs; reactions balance the
/// 100 N load to 1e-8; contact conditions hold; the bar presses on the upper block
/// at its right corner and on the lower block at its left corner, each bonded zone
/// contiguous, with the opposite ends open.
#[test]
fn bar_in_bearing() {
    let a = Analysis::new(example("bar_in_bearing.toml")).unwrap();
    let elements: usize = a.model.parts.iter().map(|p| p.mesh.elements.len()).sum();
    assert_eq!(
        (a.model.parts[0].mesh.elements.len(), elements - 1920),
        (1920, 540)
    );
    assert_eq!(
        (
            a.interfaces[0].elements.len(),
            a.interfaces[1].elements.len()
        ),
        (16, 16)
    );
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    common::check_contact_conditions(&a, last);
    let [fx, reaction_y] = common::total_reaction(&a, last);
    let fy = reaction_y + 100.0;
    assert!(
        fx.hypot(fy) < 1e-8 * 100.0,
        "reactions do not balance the load: ({fx:e}, {fy:e})"
    );
    for (i, corner_bonded_at) in [(0usize, 255.0), (1, 225.0)] {
        let p = pattern(&last.states, i);
        let xs: Vec<f64> = a.interfaces[i]
            .elements
            .iter()
            .map(|c| c.position[0])
            .collect();
        assert!(contiguous(&p), "interface {i}: {p:?}");
        let at = |x: f64| p[xs.iter().position(|&v| (v - x).abs() < 1e-9).unwrap()];
        let other = if corner_bonded_at == 255.0 {
            225.0
        } else {
            255.0
        };
        assert!(at(corner_bonded_at) && !at(other), "interface {i}: {p:?}");
    }
}

/// Under proportional load the contact pattern does not depend on the load level:
/// `active-set` finds the final pattern in the first increment (and needs one solve
/// per later increment), and `implex`, lagging states by one increment, reaches the
/// same pattern after a few increments and keeps it.
#[test]
fn schemes_reach_the_same_pattern() {
    for name in ["plate_on_base.toml", "bar_in_bearing.toml"] {
        let a = Analysis::new(example(name)).unwrap();
        let active = common::solve(&a);
        let last = active.last().unwrap();
        assert_eq!(
            active[0].states, last.states,
            "{name}: active-set pattern changed after increment 1"
        );
        assert!(active[1..].iter().all(|inc| inc.iterations == 1));

        let mut model = example(name);
        model.settings.scheme = Scheme::Implex;
        model.settings.increments = 20;
        let b = Analysis::new(model).unwrap();
        let implex = common::solve(&b);
        let reached = implex.iter().position(|inc| inc.states == last.states);
        println!("{name}: implex reaches the active-set pattern at increment {reached:?}");
        let k = reached.expect("implex never reaches the active-set pattern");
        assert!(k < 10, "{name}: implex needs {} increments", k + 1);
        assert!(
            implex[k..].iter().all(|inc| inc.states == last.states),
            "{name}: implex leaves the pattern"
        );
        // Same pattern, same secant system: the same displacements.
        let (ua, ub) = (&last.u, &implex.last().unwrap().u);
        let umax = ua.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(ua.iter().zip(ub).all(|(x, y)| (x - y).abs() < 1e-9 * umax));
    }
}

/// Every increment the solver reports as a multiple of a linear solution is that
/// multiple of it (to round-off), and so are its stresses: the scaled stresses the
/// run writes equal stresses recovered from the increment's own displacements.
/// With friction the shortcut is off and no increment claims to be a multiple.
#[test]
fn multiples_of_a_solution_scale_their_stresses() {
    let a = Analysis::new(example("plate_on_base.toml")).unwrap();
    let incs = common::solve(&a);
    let scale = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut scaled = 0;
    for inc in &incs {
        let m = inc
            .multiple_of
            .expect("contact law: proportional shortcuts on");
        // The increment solved for the solution (factor 1) it is a multiple of.
        let source = incs
            .iter()
            .find(|s| {
                s.multiple_of
                    .is_some_and(|n| n.solution == m.solution && n.factor == 1.0)
            })
            .expect("the solution's own increment");
        let (u, us) = (&inc.u, &source.u);
        assert!(
            u.iter()
                .zip(us)
                .all(|(x, y)| (x - m.factor * y).abs() <= 1e-14 * scale(u)),
            "increment {}: not {} × increment {}",
            inc.index,
            m.factor,
            source.index
        );
        if m.factor != 1.0 {
            scaled += 1;
            let direct = a.recover(u);
            for (d, s) in direct.iter().zip(a.recover(us)) {
                let s = s.scaled(m.factor);
                let big = d
                    .element
                    .iter()
                    .flatten()
                    .fold(0.0f64, |m, x| m.max(x.abs()));
                for (x, y) in d
                    .element
                    .iter()
                    .zip(&s.element)
                    .chain(d.nodal.iter().zip(&s.nodal))
                {
                    assert!(x.iter().zip(y).all(|(p, q)| (p - q).abs() <= 1e-13 * big));
                }
            }
        }
    }
    assert!(scaled >= 8, "only {scaled} increments scaled");

    let mut model = example("plate_on_base.toml");
    for i in &mut model.interfaces {
        i.law = cfe::coupling::Law::Coulomb;
        i.friction = 0.2;
    }
    let b = Analysis::new(model).unwrap();
    assert!(
        common::solve(&b)
            .iter()
            .all(|inc| inc.multiple_of.is_none())
    );
}
