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

mod common;

fn tied(host: [usize; 2], fine: [usize; 2]) -> String {
    format!(
        r#"
[materials.steel]
E = 210000.0
nu = 0.31
[[part]]
name = "coarse"
material = "steel"
rectangle = {{ x = [0.0, 50.0], y = [-5.0, 5.0], cells = [{}, {}] }}
[[part]]
name = "fine"
material = "steel"
rectangle = {{ x = [50.0, 100.0], y = [-5.0, 5.0], cells = [{}, {}] }}
[[interface]]
host = "coarse"
nodes = "fine"
boundary = "left"
law = "rigid"
[[support]]
part = "coarse"
boundary = "left"
fix = ["x", "y"]
[[load]]
part = "fine"
boundary = "right"
force = [0.0, -1.0]
[analysis]
increments = 1
"#,
        host[0], host[1], fine[0], fine[1]
    )
}

fn conforming(cells: [usize; 2]) -> String {
    format!(
        r#"
[materials.steel]
E = 210000.0
nu = 0.31
[[part]]
name = "beam"
material = "steel"
rectangle = {{ x = [0.0, 100.0], y = [-5.0, 5.0], cells = [{}, {}] }}
[[support]]
part = "beam"
boundary = "left"
fix = ["x", "y"]
[[load]]
part = "beam"
boundary = "right"
force = [0.0, -1.0]
[analysis]
increments = 1
"#,
        cells[0], cells[1]
    )
}

fn tip(text: &str, part: &str) -> f64 {
    let a = common::analysis(text);
    let inc = common::solve(&a).pop().unwrap();
    -common::displacement_at(&a, &inc, part, [100.0, 0.0])[1]
}

fn timoshenko_goodier() -> f64 {
    let (e, nu, p, l, d) = (210000.0f64, 0.31f64, 1.0f64, 100.0f64, 10.0f64);
    let i = d.powi(3) / 12.0;
    p * l.powi(3) / (3.0 * e * i) + (4.0 + 5.0 * nu) * p * d * d * l / (24.0 * e * i)
}

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
        let tied = tip(&tied([20 * k, 4 * k], [30 * k, 6 * k]), "fine");
        let coarse = tip(&conforming([40 * k, 4 * k]), "beam");
        let fine = tip(&conforming([60 * k, 6 * k]), "beam");
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
