//! The quick versions of the verification cases (`cfe verify --quick`): each must
//! meet its independent reference. `cfe verify` runs the full versions and writes
//! docs/verification.md.

use cfe_tools::verification::{cantilever, contact, curved, patch, punch, quads, seed};

fn check(case: cfe::error::Result<cfe_tools::verification::Case>) {
    let c = case.expect("case runs");
    assert!(c.passed, "{}: {}", c.title, c.verdict);
}

/// Constant stress through a tied interface: error O(E·t/c) with coincident
/// vertices; bounded at the interface, RMS falling as √h, with non-matching meshes.
#[test]
fn constant_stress_patch() {
    check(patch::constant_stress(true));
}

/// Two blocks pressed together: all bonded, pair forces = pressure × tributary length.
#[test]
fn contact_patch() {
    check(patch::contact_patch(true));
}

/// The coarse part must host: reversing the roles worsens the patch test and the cantilever.
#[test]
fn host_choice() {
    check(patch::host_choice(true));
}

/// Tied cantilever: Timoshenko–Goodier tip (order 2) and energy norm (order 1), no
/// error beyond the conforming halves', bracketed by conforming meshes when clamped.
#[test]
fn tied_cantilever() {
    check(cantilever::convergence(true));
}

/// The tie's error falls as 1/c and the default penalty is accurate, also for
/// parts of very different stiffness.
#[test]
fn penalty() {
    check(cantilever::penalty_study(true));
}

/// Bonded rigid punch: pressure converging to the closed form, the load balanced,
/// the same forces as a conforming model of the punch.
#[test]
fn bonded_punch() {
    check(punch::bonded_punch(true));
}

/// implex reaches the active-set result; the seed examples settle under refinement.
#[test]
fn seed_examples() {
    check(seed::schemes_and_refinement(true));
}

/// Lamé's cylinder tied along a curved face: u_r at order 2, the tie adds no error beyond the bulk's.
#[test]
fn curved_interface() {
    check(curved::lame_cylinder(true));
}

/// Q4 and mixed meshes: patch tests for every T3/Q4 pairing, Q4 cantilever at order 2, beating T3.
#[test]
fn q4_and_mixed() {
    check(quads::q4_and_mixed(true));
}

/// The contact iteration: every variant ends on a pattern satisfying the law or has
/// none nearby; warm start and updates change nothing; implex ends where active-set does.
#[test]
fn contact_iteration() {
    check(contact::contact_iteration(true));
}
