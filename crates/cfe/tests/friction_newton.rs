//! Coulomb friction solved pattern by pattern (solve/contact/friction.rs): a
//! pattern's slip forces solved in one shot against the fixed point's limit,
//! and the quarter shrink fit with friction (node and segment coupling, T3 and
//! Q4, two refinements) completing with Coulomb's law on every pair, checked
//! from the pairs' own forces.

mod common;

use cfe::coupling::PairState;
use cfe::{Analysis, FrictionSolve, IncrementResult, Model};
use common::Problem;

/// The seed's plate on its base with the Coulomb law (μ = 0.2): the plate is
/// held along the base by friction alone.
fn plate_coulomb() -> String {
    std::fs::read_to_string(common::example_path("plate_on_base.toml"))
        .expect("the example")
        .replace("law = \"contact\"", "law = \"coulomb\"\nfriction = 0.2")
}

/// Per-pattern exactness: the pattern the run's first increment ends on (with
/// slipping pairs), solved in one shot — slip directions fixed, the slip forces
/// from one dense system on the slipping pairs — gives the displacements the
/// fixed point on its slip forces converges to (to 1e-7 of the largest, the
/// fixed point stopping at 1e-10 of the load), and obeys the law on every pair.
#[test]
fn a_pattern_solved_in_one_shot_is_the_fixed_points_answer() {
    let a = common::analysis(&plate_coulomb());
    let incs = common::solve(&a);
    let first = &incs[0];
    let slipping = first.states[0]
        .iter()
        .filter(|s| **s == PairState::Slip)
        .count();
    assert!(slipping > 0, "{:?}", first.states);
    let mut s = a.solver().unwrap();
    let fixed = s.solve_pattern(first.lambda, &first.states).unwrap();
    let mut s = a.solver().unwrap();
    let exact = s
        .solve_pattern_exact(first.lambda, &first.states)
        .unwrap()
        .expect("a pattern with a state of rest");
    let scale = fixed.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = fixed
        .u
        .iter()
        .zip(&exact.u)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff <= 1e-7 * scale, "{diff} of {scale}");
    assert!(exact.violations.is_empty(), "{:?}", exact.violations);
}

/// A quarter shrink fit (shaft δ = 0.01 mm over a ring, symmetry supports, 3:5
/// faces) with `elements` and `coupling`, Coulomb μ = 0.3, `refine`.
fn quarter_fit(elements: &str, coupling: &str, refine: usize) -> String {
    let (ring, shaft) = (12 * refine, 20 * refine);
    Problem::compact()
        .plane("strain")
        .material("steel", 210000.0, 0.3)
        .material("alu", 70000.0, 0.33)
        .part("ring", "alu")
        .annulus([0.0, 0.0], [10.0, 20.0], [0.0, 90.0], [4, ring], elements)
        .part("shaft", "steel")
        .annulus([0.0, 0.0], [5.0, 10.01], [0.0, 90.0], [4, shaft], elements)
        .quarter_symmetry("ring")
        .quarter_symmetry("shaft")
        .interface("ring", "shaft", "outer")
        .law("coulomb")
        .friction(0.3)
        .iface_key("coupling", coupling)
        .iface_key("search_distance", 0.05)
        .increments(1)
        .text()
}

/// The quarter shrink fit with friction completes with node and segment
/// coupling, T3 and Q4, at two refinements, and every pair obeys Coulomb's law
/// as its own forces show (no tension, |f_s| ≤ μ f_n, slipping pairs at the
/// cone, open pairs without force or penetration), and the loads (none: the
/// interference alone) balance.
#[test]
fn the_quarter_shrink_fit_with_friction_holds_the_law_on_every_pair() {
    for elements in ["t3", "q4"] {
        for coupling in ["node", "segment"] {
            for refine in [1, 2] {
                let what = format!("{elements}, {coupling}, ×{refine}");
                let a = common::analysis(&quarter_fit(elements, coupling, refine));
                let incs = common::solve(&a);
                let last = incs.last().expect("an increment");
                assert!(last.violations.is_empty(), "{what}: {:?}", last.violations);
                assert!(last.settled.is_empty(), "{what}");
                let iface = &a.interfaces[0];
                let law = iface.params();
                let mut fmax = 0.0f64;
                let mut forces = Vec::new();
                for k in 0..iface.elements.len() {
                    let state = last.states[0][k];
                    let h = &last.pair_history[0][k];
                    let p = iface.pair_at(k, &a.dofs, &last.u, state, h);
                    fmax = fmax.max(p.force.0.abs());
                    forces.push((state, p.gap, p.force));
                }
                assert!(fmax > 0.0, "{what}: the fit presses");
                let tol = 1e-6 * fmax;
                for (k, (state, gap, f)) in forces.into_iter().enumerate() {
                    let cone = law.friction * (-f.0).max(0.0);
                    match state {
                        PairState::Open => {
                            assert_eq!(f, (0.0, 0.0), "{what}: pair {k}");
                            assert!(gap >= -1e-6, "{what}: pair {k} penetrates {gap}");
                        }
                        PairState::Bonded => {
                            assert!(f.0 <= tol, "{what}: pair {k} pulls {f:?}");
                            assert!(f.1.abs() <= cone + tol, "{what}: pair {k} {f:?}");
                        }
                        PairState::Slip => {
                            assert!(f.0 <= tol, "{what}: pair {k} pulls {f:?}");
                            assert!((f.1.abs() - cone).abs() <= tol, "{what}: pair {k} {f:?}");
                        }
                    }
                }
                assert!(last.residual <= 1e-8, "{what}: residual {}", last.residual);
            }
        }
    }
}

/// Every increment of `a` solved to its end with `how` solving the patterns'
/// slip forces, and what the Newton steps did: patterns solved, left to the
/// fixed point, with their columns from the cached condensed operator.
fn run_with(a: &Analysis, how: FrictionSolve) -> (Vec<IncrementResult>, (usize, usize, usize)) {
    let mut model = a.model.clone();
    model.settings.friction_solve = how;
    let b = Analysis::new(model).expect("pairs found");
    let mut s = b.solver().expect("a solver");
    let mut incs = Vec::new();
    s.run(|inc| {
        incs.push(inc.clone());
        Ok(())
    })
    .expect("converges");
    let c = s.newton_counts();
    (incs, (c.solved, c.fallbacks, c.cached))
}

/// The law on every pair of `inc` from its own forces (compression, |f_s| ≤ μ
/// |f_n| sticking, = μ |f_n| slipping, open pairs force-free and not
/// penetrating), to 1e-6 of the largest normal force.
fn assert_coulomb(a: &Analysis, inc: &IncrementResult, what: &str) {
    assert!(inc.violations.is_empty(), "{what}: {:?}", inc.violations);
    assert!(inc.settled.is_empty(), "{what}");
    for (i, iface) in a.interfaces.iter().enumerate() {
        let law = iface.params();
        let forces: Vec<_> = (0..iface.elements.len())
            .map(|k| {
                let (state, h) = (inc.states[i][k], &inc.pair_history[i][k]);
                let p = iface.pair_at(k, &a.dofs, &inc.u, state, h);
                (state, p.gap, p.force)
            })
            .collect();
        let tol = 1e-6 * forces.iter().fold(0.0f64, |m, f| m.max(f.2.0.abs()));
        for (k, (state, gap, f)) in forces.into_iter().enumerate() {
            let cone = law.friction * (-f.0).max(0.0);
            match state {
                PairState::Open => {
                    assert_eq!(f, (0.0, 0.0), "{what}: pair {k}");
                    assert!(gap >= -1e-6, "{what}: pair {k} penetrates {gap}");
                }
                PairState::Bonded => {
                    assert!(
                        f.0 <= tol && f.1.abs() <= cone + tol,
                        "{what}: pair {k} {f:?}"
                    );
                }
                PairState::Slip => {
                    assert!(f.0 <= tol, "{what}: pair {k} pulls {f:?}");
                    assert!((f.1.abs() - cone).abs() <= tol, "{what}: pair {k} {f:?}");
                }
            }
        }
    }
}

/// `friction_solve = "newton"` on the seed's plate (μ = 0.2), on
/// Cattaneo–Mindlin (μ = 0.3: a normal increment, then shear ones) and on the
/// roller in its cradle (μ = 0.3): the patterns' slip forces are solved by
/// Newton steps whose columns come from the interface's condensed operator
/// (the cached low-rank columns, no solve), and every increment ends on the
/// default fixed point's pattern, with its displacements to 1e-7 of the
/// largest and Coulomb's law on every pair. The Newton step is the fixed
/// point's limit: on the plate the fixed point confirms it at its first check
/// (one solve moving the solution per pattern, none of its own steps).
#[test]
fn the_newton_solve_of_the_slip_forces_gives_the_fixed_points_answer() {
    let cattaneo = Model::from_file(&common::example_path("hertz/cattaneo.toml"), 1).unwrap();
    let roller = Model::from_file(
        &common::example_path("roller_in_cradle/roller_in_cradle.toml"),
        1,
    )
    .unwrap();
    let mut roller_coulomb = roller.clone();
    for iface in &mut roller_coulomb.interfaces {
        iface.law = cfe::coupling::Law::Coulomb;
        iface.friction = 0.3;
    }
    let cases = [
        ("plate", common::analysis(&plate_coulomb())),
        ("cattaneo", Analysis::new(cattaneo).unwrap()),
        ("roller", Analysis::new(roller_coulomb).unwrap()),
    ];
    for (what, a) in &cases {
        let (fixed, none) = run_with(a, FrictionSolve::FixedPoint);
        assert_eq!(none, (0, 0, 0), "{what}: off by default");
        let (newton, counts) = run_with(a, FrictionSolve::Newton);
        assert!(counts.0 > 0, "{what}: {counts:?}");
        assert_eq!(counts.2, counts.0 + counts.1, "{what}: {counts:?}");
        assert_eq!(fixed.len(), newton.len(), "{what}");
        for (f, n) in fixed.iter().zip(&newton) {
            let what = format!("{what}, increment {}", n.index);
            assert_eq!(f.states, n.states, "{what}");
            let scale = f.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff =
                f.u.iter()
                    .zip(&n.u)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff <= 1e-7 * scale, "{what}: {diff} of {scale}");
            assert_coulomb(a, n, &what);
            if what.starts_with("plate") {
                assert!(
                    n.fixed_point_iterations <= n.iterations,
                    "{what}: {} solves for {} patterns",
                    n.fixed_point_iterations,
                    n.iterations
                );
            }
        }
    }
}

/// Coulomb's law on every pair of `res`'s last increment, read from its
/// `pairs.csv` rows alone (not from the solver's check): stick pairs pressed
/// and inside the cone, slipping pairs pressed and on it,
/// open pairs force-free and not penetrating, no pair flagged, to
/// 1e-7 of the largest pair force; and the loads balanced by the reactions to
/// 1e-8 of the load. Returns the numbers of stick and slip pairs.
fn assert_law_from_rows(
    a: &Analysis,
    res: &cfe::analysis::Results,
    mu: f64,
    what: &str,
) -> (usize, usize) {
    assert_eq!(
        res.summary.status,
        cfe::analysis::RunStatus::Completed,
        "{what}: {:?}",
        res.summary.warnings
    );
    let rows = a.pair_rows(&res.last);
    let fmax = rows
        .iter()
        .fold(0.0f64, |m, r| m.max(r.force_n.abs()).max(r.force_s.abs()));
    assert!(fmax > 0.0, "{what}: the parts press");
    let tol = 1e-7 * fmax;
    let gmax = rows.iter().fold(0.0f64, |m, r| m.max(r.gap.abs()));
    let (mut stick, mut slip) = (0, 0);
    for r in &rows {
        let at = format!(
            "{what}: {} node {} at ({}, {})",
            r.interface, r.node, r.x, r.y
        );
        assert!(r.violation.is_empty(), "{at}: flagged {:?}", r.violation);
        match r.state {
            PairState::Open => {
                assert!(
                    r.force_n == 0.0 && r.force_s == 0.0,
                    "{at}: open carries force"
                );
                assert!(r.gap >= -1e-9 * gmax, "{at}: open penetrates {}", r.gap);
            }
            PairState::Bonded => {
                stick += 1;
                assert!(r.force_n >= -tol, "{at}: pulls {}", r.force_n);
                assert!(
                    r.force_s.abs() <= mu * r.force_n + tol,
                    "{at}: |f_s| {} > μ f_n {}",
                    r.force_s,
                    mu * r.force_n
                );
            }
            PairState::Slip => {
                slip += 1;
                assert!(r.force_n >= -tol, "{at}: pulls {}", r.force_n);
                assert!(
                    (r.force_s.abs() - mu * r.force_n).abs() <= tol,
                    "{at}: |f_s| {} ≠ μ f_n {}",
                    r.force_s,
                    mu * r.force_n
                );
            }
        }
    }
    let load = res
        .summary
        .applied
        .iter()
        .map(|f| f.abs())
        .fold(0.0, f64::max);
    let fx: f64 = res.summary.reactions.iter().map(|r| r.fx).sum();
    let fy: f64 = res.summary.reactions.iter().map(|r| r.fy).sum();
    assert!(
        (fx + res.summary.applied[0]).abs() <= 1e-8 * load,
        "{what}: Σ reaction x {fx}, load {:?}",
        res.summary.applied
    );
    assert!(
        (fy + res.summary.applied[1]).abs() <= 1e-8 * load,
        "{what}: Σ reaction y {fy}, load {:?}",
        res.summary.applied
    );
    (stick, slip)
}

/// The semi-smooth Newton search is the default Coulomb solve of a plane
/// model: the seed's
/// plate held along its base by friction alone (examples/plate_on_base.toml,
/// Coulomb at μ = 0.05, 0.2, 0.5, 1), the roller in its cradle
/// (examples/roller_in_cradle, μ = 0.3) and Cattaneo–Mindlin
/// (examples/hertz/cattaneo.toml: pressed, then sheared at 0.5 μP) complete
/// with the settings left at their defaults, Coulomb's law on every pair read
/// from the pairs' rows (stick and slip zones both present) and the loads
/// balanced. A block pushed beyond friction with nothing else to hold it
/// still ends with the typed error naming it.
#[test]
fn the_default_newton_search_completes_on_the_law_and_refuses_no_state_of_rest() {
    assert_eq!(cfe::Settings::default().friction_solve, FrictionSolve::Auto);
    assert_eq!(FrictionSolve::Auto.resolved(false), FrictionSolve::Newton);
    for mu in [0.05, 0.2, 0.5, 1.0] {
        let a = common::analysis(
            &plate_coulomb().replace("friction = 0.2", &format!("friction = {mu}")),
        );
        let res = a.solve().expect("the plate rests on its base");
        let (stick, slip) = assert_law_from_rows(&a, &res, mu, &format!("plate, μ = {mu}"));
        assert!(
            stick > 0 && slip > 0,
            "plate, μ = {mu}: {stick} stick, {slip} slip"
        );
    }
    let mut roller = Analysis::from_file(
        &common::example_path("roller_in_cradle/roller_in_cradle.toml"),
        1,
    )
    .unwrap();
    roller.override_friction(0.3).unwrap();
    let res = roller.solve().expect("the roller rests in its cradle");
    assert_law_from_rows(&roller, &res, 0.3, "roller");
    let cattaneo = Analysis::from_file(&common::example_path("hertz/cattaneo.toml"), 1).unwrap();
    let res = cattaneo.solve().expect("the cylinder is held at 0.5 μP");
    let (stick, slip) = assert_law_from_rows(&cattaneo, &res, 0.3, "cattaneo");
    assert!(
        stick > 0 && slip > 0,
        "cattaneo: {stick} stick, {slip} slip (a stick zone inside slip zones)"
    );
    // Q = 0.45 P against μ P = 0.3 P, nothing else holding the block.
    let beyond = Problem::block_on_base()
        .law("coulomb")
        .friction(0.3)
        .raw("[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.45, -1.0]\n[analysis]\nincrements = 2")
        .text();
    match common::analysis(&beyond).solve() {
        Err(cfe::Error::Unsupported { parts, .. }) => assert_eq!(parts, ["block"]),
        Err(e) => panic!("beyond friction: unexpected error {e}"),
        Ok(r) => panic!("beyond friction: {:?}", r.summary.status),
    }
}
