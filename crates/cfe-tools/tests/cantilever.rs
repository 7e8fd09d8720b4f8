//! Tied non-matching cantilever (plane stress, L = 100, D = 10, t = 1, E = 210000,
//! ν = 0.31, 1 N end shear, clamped end), split at mid-span into a coarse host and a
//! finer node part (element ratio 2:3), against conforming meshes and against the
//! Timoshenko–Goodier closed form.
//!
//! ```text
//!   |▒ coarse (host) ▒▒▒▒▒▒▒|░ fine (nodes) ░░░░░░░░|  ↓ P = 1 N (uniform on x = 100)
//!   |▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒|░░░░░░░░░░░░░░░░░░░░░░|
//!   x = 0 (clamped)        x = 50 (tied)          x = 100
//! ```
//!
//! Reference: S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed., §21:
//! v(L) = P L³ / (3 E I) + (4 + 5ν) P D² L / (24 E I).
//! (Its end conditions differ slightly from a fully clamped end; the difference
//! vanishes as L/D grows and is below 1 % here.)

use cfe_tools::verification::cantilever::{conforming, tied, timoshenko_goodier, tip};

/// The tied model's tip deflection lies between the conforming meshes of its two
/// element sizes (the interface adds no stiffness or flexibility beyond the bulk
/// discretization), is within 1 % of the conforming mesh at the host's size once the
/// beam has 8 elements through its depth, and converges to Timoshenko–Goodier at
/// about second order.
#[test]
fn tied_cantilever_matches_conforming_and_closed_form() {
    let exact = timoshenko_goodier();
    let mut errors = Vec::new();
    for k in [1usize, 2, 4] {
        let tied = tip(&tied([20 * k, 4 * k], [30 * k, 6 * k], None), "fine").unwrap();
        let coarse = tip(&conforming([40 * k, 4 * k]), "beam").unwrap();
        let fine = tip(&conforming([60 * k, 6 * k]), "beam").unwrap();
        println!(
            "K={k}: tied {tied:.6e}, conforming h {coarse:.6e}, conforming 2h/3 {fine:.6e}, closed form {exact:.6e}"
        );
        assert!(
            coarse < tied && tied < fine,
            "tied result not bracketed by conforming meshes"
        );
        if k >= 2 {
            assert!(
                (tied - coarse).abs() / coarse < 0.01,
                "tied vs conforming differ by more than 1 %"
            );
        }
        errors.push((exact - tied) / exact);
    }
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            order > 1.7,
            "convergence order {order:.2} against the closed form (errors {errors:?})"
        );
    }
    assert!(
        errors[2] < 0.015,
        "error {:.3e} against the closed form at K = 4",
        errors[2]
    );
}
