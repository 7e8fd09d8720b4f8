//! The linear-solver seam (`cfe::solve::backend`) carries two back ends: the
//! supernodal Cholesky and Jacobi-preconditioned conjugate gradients. On systems
//! the library assembles (a tied two-part problem, contact patterns of the plate
//! on a base) the iterative solution agrees with the direct one to what its
//! tolerance allows, a warm start from the solution converges at once, and a
//! singular system is a typed error, not a hang.

mod common;

use common::{Raw, Text};

use cfe::analysis::Analysis;
use cfe::assembly::{NodeGraph, Stiffness};
use cfe::coupling::PairState;
use cfe::solve::backend::{Analyse, LinearFailure, LinearSolver, Problem, Request, Solve};
use cfe::solve::direct::Cholesky;
use cfe::solve::iterative::ConjugateGradients;
use cfe::solve::system::Method;

/// Two unit-square-ish blocks of different meshes and stiffnesses tied along a
/// face (law `rigid`, a moderate penalty), the lower one supported at its
/// bottom, the upper one pushed down and sideways on its top.
static TIED: Text = Text::new(|| {
    common::Problem::compact()
        .head("title", "tied")
        .plane("strain")
        .material("soft", 1000.0, 0.3)
        .material("stiff", 5000.0, 0.25)
        .part("A", "stiff")
        .rectangle([0.0, 2.0], [0.0, 1.0], [8, 4])
        .part("B", "soft")
        .rectangle_of([0.0, 2.0], [1.0, 2.0], [11, 5], "q4")
        .named_interface("A-B", "A", "B", "bottom")
        .law("rigid")
        .iface_key("c_n", Raw("1e5"))
        .iface_key("c_s", Raw("1e5"))
        .support("A", "bottom", ["x", "y"])
        .load("B", "top", [30.0, -100.0])
        .text()
});

fn problem(a: &Analysis) -> Problem<'_> {
    Problem {
        parts: &a.model.parts,
        interfaces: &a.interfaces,
        dofs: &a.dofs,
    }
}

/// `b − K x` with `K(states)` assembled here, apart from both back ends (its
/// lower triangle, applied symmetrically).
fn residual_vector(a: &Analysis, states: &[Vec<PairState>], b: &[f64], x: &[f64]) -> Vec<f64> {
    let graph = NodeGraph::new(&a.model.parts, &a.interfaces, &a.dofs);
    let mut k = Stiffness::new(&a.model.parts, &a.dofs, &graph);
    k.assemble(&a.model.parts, &a.interfaces, states, &a.dofs);
    let mut r = b.to_vec();
    for j in 0..k.n() {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            let (i, v) = (k.row_idx[p] as usize, k.values[p]);
            r[i] -= v * x[j];
            if i != j {
                r[j] -= v * x[i];
            }
        }
    }
    r
}

/// `‖b − K x‖ / ‖b‖` ([`residual_vector`]).
fn relative_residual(a: &Analysis, states: &[Vec<PairState>], b: &[f64], x: &[f64]) -> f64 {
    norm(&residual_vector(a, states, b, x)) / norm(b)
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// `‖x − y‖ / ‖y‖`.
fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
    let d: Vec<f64> = x.iter().zip(y).map(|(p, q)| p - q).collect();
    norm(&d) / norm(y)
}

/// Solves `states` with the load by both back ends through the seam: the
/// Cholesky's solution, the CG's, and its iterations.
fn both(a: &Analysis, states: &[Vec<PairState>], tolerance: f64) -> (Vec<f64>, Vec<f64>, usize) {
    let b = common::free_load(a);
    let mut direct = Cholesky::analyse(problem(a)).unwrap();
    let mut x = b.clone();
    let done = direct.solve_pattern(Request::new(states), &mut x).unwrap();
    assert_eq!(done.method, Method::Factorization);
    assert!(done.iterations.is_none() && done.complete);
    let mut cg = ConjugateGradients::analyse(problem(a)).unwrap();
    cg.tolerance = tolerance;
    let mut y = b.clone();
    let done = cg.solve_pattern(Request::new(states), &mut y).unwrap();
    let it = done
        .iterations
        .expect("an iterative solve reports its iterations");
    assert!(it.relative_residual <= tolerance);
    // The reported residual is the true one.
    let r = relative_residual(a, states, &b, &y);
    assert!(
        r <= tolerance,
        "residual {r:e} above the tolerance {tolerance:e}"
    );
    (x, y, it.count)
}

/// On the tied two-part problem, conjugate gradients to a relative residual of
/// 1e-12 give the Cholesky's displacements to 1e-9 (the relative error is at
/// most the condition number times the relative residual).
#[test]
fn conjugate_gradients_agree_with_cholesky_on_a_tied_problem() {
    let a = common::analysis(&TIED);
    let states = vec![vec![PairState::Bonded; a.interfaces[0].elements.len()]];
    let (x, y, _) = both(&a, &states, 1e-12);
    let d = relative_difference(&y, &x);
    assert!(d < 1e-9, "CG differs from Cholesky by {d:e}");
}

/// On the plate on a base (its penalty 1e9, ~5000 × E·t), with the pairs all
/// bonded, the ends open and every third pair open, conjugate gradients to
/// 1e-9 (about the accuracy CG can reach there in double precision: to 1e-12
/// its true residual stalls near 1e-10) give the Cholesky's displacements to
/// 1e-7.
#[test]
fn conjugate_gradients_agree_with_cholesky_on_contact_patterns() {
    let a = common::example("plate_on_base.toml", 1);
    for states in common::contact_patterns(a.interfaces[0].elements.len()) {
        let (x, y, _) = both(&a, &states, 1e-9);
        let d = relative_difference(&y, &x);
        assert!(d < 1e-7, "CG differs from Cholesky by {d:e}");
    }
}

/// A warm start from the solution converges at once: from the Cholesky's
/// solution and from a converged CG solution, 0 iterations (their residuals are
/// within the tolerance); the preparation of the same states is reused, and
/// other states prepare anew.
#[test]
fn a_warm_start_from_the_solution_converges_at_once() {
    let a = common::example("plate_on_base.toml", 1);
    let [bonded, ends, _] = common::contact_patterns(a.interfaces[0].elements.len());
    let b = common::free_load(&a);
    let mut direct = Cholesky::analyse(problem(&a)).unwrap();
    let mut exact = b.clone();
    direct
        .solve_pattern(Request::new(&bonded), &mut exact)
        .unwrap();
    let mut cg = ConjugateGradients::analyse(problem(&a)).unwrap();
    cg.tolerance = 1e-9;
    let mut x = b.clone();
    let cold = cg
        .solve_pattern(Request::new(&bonded).guess(&exact), &mut x)
        .unwrap();
    assert_eq!(cold.method, Method::Factorization);
    assert!(cold.iterations.unwrap().count <= 1, "{cold:?}");
    let mut y = b.clone();
    let first = cg.solve_pattern(Request::new(&bonded), &mut y).unwrap();
    assert_eq!(first.method, Method::Reuse);
    assert!(first.iterations.unwrap().count > 100);
    let mut z = b.clone();
    let warm = cg
        .solve_pattern(Request::new(&bonded).guess(&y), &mut z)
        .unwrap();
    assert_eq!(warm.method, Method::Reuse);
    assert!(warm.iterations.unwrap().count <= 1, "{warm:?}");
    // Another pattern prepares anew; warm-started from its neighbour's
    // solution it needs fewer iterations than from zero.
    let mut from_zero = b.clone();
    let cold = cg
        .solve_pattern(Request::new(&ends), &mut from_zero)
        .unwrap();
    assert_eq!(cold.method, Method::Factorization);
    let mut from_bonded = b.clone();
    let warm = cg
        .solve_pattern(Request::new(&ends).guess(&y), &mut from_bonded)
        .unwrap();
    assert_eq!(warm.method, Method::Reuse);
    assert!(
        warm.iterations.unwrap().count < cold.iterations.unwrap().count,
        "warm {warm:?}, cold {cold:?}"
    );
    assert_eq!(cg.statistics().preparations, 2);
}

/// A back end without the restricted solves answers an interface-only request
/// by a complete solve, whose coupling equations carry what the Cholesky's
/// restricted solve (the elimination-tree paths only) gives there.
#[test]
fn a_restricted_request_falls_back_to_a_complete_solve() {
    let a = common::example("plate_on_base.toml", 1);
    let [bonded, ..] = common::contact_patterns(a.interfaces[0].elements.len());
    let b = common::free_load(&a);
    let coupling: Vec<usize> = common::coupling_equations(&a, 0);
    let mut direct = Cholesky::analyse(problem(&a)).unwrap();
    let mut cg = ConjugateGradients::analyse(problem(&a)).unwrap();
    cg.tolerance = 1e-9;
    assert!(cg.restricted().is_none() && direct.restricted().is_some());
    // The Cholesky's first solve factorizes (complete), its second is restricted.
    let mut x = b.clone();
    direct.solve_pattern(Request::new(&bonded), &mut x).unwrap();
    let mut x = b.clone();
    let restricted = direct
        .solve_pattern(Request::new(&bonded).interface_only(), &mut x)
        .unwrap();
    assert!(!restricted.complete);
    let mut y = b.clone();
    let full = cg
        .solve_pattern(Request::new(&bonded).interface_only(), &mut y)
        .unwrap();
    assert!(full.complete);
    let scale = coupling.iter().map(|&e| x[e].abs()).fold(0.0, f64::max);
    for &e in &coupling {
        assert!(
            (x[e] - y[e]).abs() <= 1e-7 * scale,
            "equation {e}: {} against {}",
            x[e],
            y[e]
        );
    }
}

/// The tied problem held in y only (free to slide in x) under a load with an
/// x component: K is singular and the system has no solution. Conjugate
/// gradients end with a typed error within their cap, not a hang: a direction
/// of non-positive curvature (the rigid slide's, zero but for round-off), or
/// `NotConverged` with the residual far above the tolerance.
#[test]
fn a_singular_system_is_a_typed_error() {
    let a = common::analysis(&TIED.replace(r#"fix = ["x", "y"]"#, r#"fix = ["y"]"#));
    let states = vec![vec![PairState::Bonded; a.interfaces[0].elements.len()]];
    let mut cg = ConjugateGradients::analyse(problem(&a)).unwrap();
    cg.max_iterations = Some(2000);
    let mut x = common::free_load(&a);
    match cg.solve_pattern(Request::new(&states), &mut x) {
        Err(LinearFailure::NotPositiveDefinite { equation: None }) => {}
        Err(LinearFailure::NotConverged {
            iterations,
            relative_residual,
            tolerance,
        }) => {
            assert!(iterations <= 2000);
            assert!(relative_residual > 1e3 * tolerance, "{relative_residual:e}");
        }
        other => panic!("expected a typed failure, got {other:?}"),
    }
    assert!(cg.statistics().iterations <= 2000);
}

/// A negative penalty (not accepted from a problem file; set here on the built
/// interface) makes the tied problem's matrix indefinite: conjugate gradients
/// report `NotPositiveDefinite` (a non-positive diagonal entry or a direction
/// of non-positive curvature), as the Cholesky does (a non-positive pivot).
#[test]
fn an_indefinite_system_is_a_typed_error() {
    let mut a = common::analysis(&TIED);
    a.interfaces[0].c_n = -1e5;
    a.interfaces[0].c_s = -1e5;
    let states = vec![vec![PairState::Bonded; a.interfaces[0].elements.len()]];
    let mut cg = ConjugateGradients::analyse(problem(&a)).unwrap();
    let mut x = common::free_load(&a);
    let failed = cg.solve_pattern(Request::new(&states), &mut x);
    assert!(
        matches!(failed, Err(LinearFailure::NotPositiveDefinite { .. })),
        "{failed:?}"
    );
    let mut direct = Cholesky::analyse(problem(&a)).unwrap();
    let mut x = common::free_load(&a);
    let failed = direct.solve_pattern(Request::new(&states), &mut x);
    assert!(
        matches!(
            failed,
            Err(LinearFailure::NotPositiveDefinite { equation: Some(_) })
        ),
        "{failed:?}"
    );
}

/// The Cholesky's refined solve through the seam: after the all-bonded
/// factorization, the ends-open pattern is a low-rank update whose residual at
/// the coupling equations (computed here from an independent assembly) is
/// solved and added (the residual is asked for exactly once); the refined
/// solution is a fresh factorization's to 1e-10 relative, with a residual
/// within twice the fresh one's.
#[test]
fn the_refined_solve_corrects_an_update_at_the_coupling_equations() {
    use cfe::solve::system::UpdatePolicy;
    let a = common::example("plate_on_base.toml", 1);
    let [bonded, ends, _] = common::contact_patterns(a.interfaces[0].elements.len());
    let b = common::free_load(&a);
    let mut coupling: Vec<usize> = common::coupling_equations(&a, 0);
    coupling.sort_unstable();
    coupling.dedup();
    let every: Vec<usize> = (0..b.len()).collect();
    let mut direct = Cholesky::analyse(problem(&a)).unwrap();
    direct
        .low_rank()
        .expect("the Cholesky updates")
        .set_policy(UpdatePolicy::Always);
    let mut x = b.clone();
    direct.solve_pattern(Request::new(&bonded), &mut x).unwrap();
    let (mut unrefined, mut calls) = (f64::NAN, 0);
    let mut residual = |v: &mut [f64]| {
        calls += 1;
        unrefined = relative_residual(&a, &ends, &b, v);
        let mut r = vec![0.0; v.len()];
        // b − K x at the coupling equations, zero elsewhere.
        let full = residual_vector(&a, &ends, &b, v);
        for &e in &coupling {
            r[e] = full[e];
        }
        v.copy_from_slice(&r);
    };
    let mut x = b.clone();
    let done = direct
        .solve_pattern(Request::new(&ends).refined(&every, &mut residual), &mut x)
        .unwrap();
    assert!(matches!(done.method, Method::LowRank { .. }), "{done:?}");
    assert_eq!(calls, 1, "an update's residual is asked for once");
    let mut fresh = Cholesky::analyse(problem(&a)).unwrap();
    let mut y = b.clone();
    fresh.solve_pattern(Request::new(&ends), &mut y).unwrap();
    assert!(relative_difference(&x, &y) < 1e-10);
    // As accurate as the factorization: within twice its residual.
    let (refined, fresh) = (
        relative_residual(&a, &ends, &b, &x),
        relative_residual(&a, &ends, &b, &y),
    );
    assert!(
        refined <= 2.0 * fresh,
        "refined {refined:e}, fresh {fresh:e}"
    );
    assert!(unrefined.is_finite());
}
