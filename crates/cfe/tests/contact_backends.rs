//! The contact scheme through the linear-solver seam: tied and contact problems
//! solved with the direct back end (supernodal Cholesky, low-rank updates,
//! restricted solves) and with conjugate gradients (`[analysis] solver = "cg"`:
//! complete solves only, warm-started) end every increment on the same pair
//! states, with displacements and internal forces that agree to what the CG
//! tolerance allows, every CG solve having met its tolerance.

mod common;

use cfe::LinearBackend;
use cfe::analysis::Analysis;
use cfe::domain::CG_TOLERANCE;
use cfe::solve::nonlinear::IncrementResult;
use common::{Problem, Raw};

/// Agreement asked of the two back ends, relative to the direct run's largest
/// displacement or internal force: the CG solves stop at a relative residual of
/// 1e-10, which on these models' conditioning leaves errors far below it.
const AGREE: f64 = 1e-6;

/// Every increment of `text` solved with the direct back end and with CG, and
/// the iterations of each CG solve.
fn both(text: &str) -> (Vec<IncrementResult>, Vec<IncrementResult>, Vec<usize>) {
    let direct = common::analysis(text);
    assert_eq!(
        direct.model.settings.solver,
        LinearBackend::Direct,
        "the default"
    );
    let mut cg: Analysis = common::analysis(text);
    cg.model.settings.solver = LinearBackend::Cg;
    let d = common::solve(&direct);
    let mut solver = cg.solver().expect("the CG back end analyses the pattern");
    let mut c = Vec::new();
    solver
        .run(|inc| {
            c.push(inc.clone());
            Ok(())
        })
        .expect("every CG solve reaches its tolerance");
    let solves = solver
        .iterative_solves()
        .expect("a CG run records its solves");
    assert_eq!(solves.back_end, "cg");
    assert_eq!(solves.tolerance, CG_TOLERANCE);
    assert!(!solves.iterations.is_empty(), "CG solved something");
    assert!(
        solves.largest_relative_residual <= CG_TOLERANCE,
        "a CG solve returned above its tolerance: {:e}",
        solves.largest_relative_residual
    );
    (d, c, solves.iterations.clone())
}

/// The largest |a − b| over the entries, relative to the largest |a|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    if scale > 0.0 { diff / scale } else { diff }
}

/// Asserts the two runs converged on the same increments with the same pair
/// states, displacements and internal forces (to [`AGREE`]), and that the law
/// holds on every pair of both.
fn assert_same(d: &[IncrementResult], c: &[IncrementResult]) {
    assert_eq!(d.len(), c.len(), "same number of increments");
    for (a, b) in d.iter().zip(c) {
        assert_eq!(a.index, b.index);
        assert_eq!(a.states, b.states, "increment {}: pair states", a.index);
        assert!(
            a.violations.is_empty() && b.violations.is_empty(),
            "increment {}",
            a.index
        );
        let du = relative_difference(&a.u, &b.u);
        assert!(
            du <= AGREE,
            "increment {}: displacements differ by {du:e}",
            a.index
        );
        let df = relative_difference(&a.f_int, &b.f_int);
        assert!(
            df <= AGREE,
            "increment {}: internal forces differ by {df:e}",
            a.index
        );
    }
}

/// A tied patch (law `rigid`, non-matching meshes, uniform pressure on the
/// block): CG through the seam gives the direct solution.
#[test]
fn tied_patch_agrees() {
    let text = Problem::block_on_base()
        .law("rigid")
        .pressure("block", "top", 1.0)
        .support_at("block", [0.0, 1.0], ["x"])
        .increments(1)
        .text();
    let (d, c, _) = both(&text);
    assert_same(&d, &c);
    assert!(
        d[0].states
            .iter()
            .flatten()
            .all(|s| *s == cfe::coupling::PairState::Bonded)
    );
}

/// The seed's plate on a base with its law (`contact`, c_n = c_s = 1e9): the
/// active-set search, whose trials the direct back end restricts to the
/// coupling equations and updates by low rank, ends on the same open and
/// bonded pairs with CG's complete, warm-started solves.
#[test]
fn plate_on_base_seed_law_agrees() {
    let text = Problem::plate_on_base()
        .law("contact")
        .iface_key("c_n", Raw("1e9"))
        .iface_key("c_s", Raw("1e9"))
        .plate_load_down()
        .increments(2)
        .text();
    let (d, c, _) = both(&text);
    assert_same(&d, &c);
    let last = d.last().unwrap();
    let open = last
        .states
        .iter()
        .flatten()
        .filter(|s| **s == cfe::coupling::PairState::Open);
    assert!(
        open.count() > 0,
        "the plate lifts off somewhere: the search did work"
    );
}

/// Frictionless contact with an eccentric load (the block pressed on its top
/// and pulled up at its right end, which lifts off): the same closed and open
/// pairs, and the same solution, with either back end.
#[test]
fn frictionless_eccentric_agrees() {
    let text = Problem::block_on_base()
        .law("frictionless")
        .support_at("block", [0.0, 1.0], ["x"])
        .load_from_to("block", [0.0, 1.0], [1.0, 1.0], [0.0, -1.0])
        .load_from_to("block", [0.75, 1.0], [1.0, 1.0], [0.0, 0.5])
        .increments(2)
        .text();
    let (d, c, _) = both(&text);
    assert_same(&d, &c);
    let last = &d.last().unwrap().states;
    let open = last
        .iter()
        .flatten()
        .filter(|s| **s == cfe::coupling::PairState::Open);
    assert!(
        open.count() > 0,
        "the right end lifts off: the search did work"
    );
}

/// A small Coulomb case (μ = 0.3, pressed and pushed sideways far beyond
/// sticking): the slip forces' fixed point, whose corrections the direct back
/// end solves on the coupling equations, converges to the same stick/slip
/// pattern and solution on CG's complete solves (corrections from zero).
#[test]
fn coulomb_small_case_agrees() {
    let text = Problem::coulomb_block_pushed_far(0.3, 2).text();
    let (d, c, iterations) = both(&text);
    assert_same(&d, &c);
    // The fixed point solved corrections too: more solves than increments.
    assert!(iterations.len() > d.len(), "{} solves", iterations.len());
}

/// A load-stepped contact case (press, then push sideways and lift one end
/// while pressed): the pair states of every increment of both steps, and the
/// solution, are those of the direct back end.
#[test]
fn load_steps_agree() {
    let steps =
        "[[step]]\nname = \"press\"\nincrements = 2\n[[step]]\nname = \"shear\"\nincrements = 2\n";
    let press = "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.0, -1.0]\n";
    let shear =
        "[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [0.05, 0.3]\nstep = \"shear\"\n";
    let text = Problem::block_on_base()
        .law("contact")
        .raw(steps)
        .raw(press)
        .raw(shear)
        .text();
    let (d, c, _) = both(&text);
    assert_eq!(d.len(), 4);
    assert_same(&d, &c);
}

/// `solver = "petsc"` (and `petsc-mumps`) read from the problem file, in a
/// build whose analysis has no PETSc back end handed to it (`cfe` alone), is a
/// typed error naming the solver and saying how to build it in, not a panic.
#[test]
fn petsc_without_its_back_end_is_a_typed_error() {
    for (name, kind) in [
        ("petsc", LinearBackend::Petsc),
        ("petsc-mumps", LinearBackend::PetscMumps),
    ] {
        let text = Problem::block_on_base()
            .law("rigid")
            .pressure("block", "top", 1.0)
            .support_at("block", [0.0, 1.0], ["x"])
            .increments(1)
            .text()
            .replace("[analysis]", &format!("[analysis]\nsolver = \"{name}\""));
        let a: Analysis = common::analysis(&text);
        assert_eq!(a.model.settings.solver, kind, "{text}");
        match a.solve() {
            Err(cfe::Error::LinearBackEnd { back_end, message }) => {
                assert_eq!(back_end, name);
                assert!(message.contains("--features petsc"), "{message}");
            }
            other => panic!(
                "{name}: expected a typed error, got {:?}",
                other.map(|r| r.summary.status)
            ),
        }
    }
}
