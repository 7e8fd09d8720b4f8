//! The quick versions of the verification cases (`cfe verify --quick`): each must
//! meet its independent reference.

use cfe::verification::{cantilever, patch, seed};

fn check(case: cfe::error::Result<cfe::verification::Case>) {
    let c = case.expect("case runs");
    assert!(c.passed, "{}: {}", c.title, c.verdict);
}

/// Constant stress through a tied interface: 1/c penalty error with coincident
/// vertices, bounded error with non-matching meshes.
#[test]
fn constant_stress_patch() {
    check(patch::constant_stress(true));
}

/// Two blocks pressed together: all bonded, pair forces = pressure × tributary length.
#[test]
fn contact_patch() {
    check(patch::contact_patch(true));
}

/// The coarse part must host: reversing the roles worsens the patch test.
#[test]
fn host_choice() {
    check(patch::host_choice(true));
}

/// Tied cantilever: bracketed by conforming meshes, converging to Timoshenko–Goodier.
#[test]
fn tied_cantilever() {
    check(cantilever::convergence(true));
}

/// The tie's error falls as 1/c and the default penalty is accurate.
#[test]
fn penalty() {
    check(cantilever::penalty_study(true));
}

/// implex reaches the active-set result; the seed examples settle under refinement.
#[test]
fn seed_examples() {
    check(seed::schemes_and_refinement(true));
}

/// A rigid flat punch bonded to a block: pair pressures follow the closed-form
/// bonded-punch distribution over the central part of the punch.
#[test]
fn bonded_punch() {
    check(cfe::verification::punch::bonded_punch(true));
}
