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
