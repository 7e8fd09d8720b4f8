//! Constant-stress patch tests across a tied (rigid-law) interface.
//!
//! ```text
//!        σ·n on every outer edge (exact tractions of a constant stress state)
//!      +-----------------------+
//!      |   node part (fine)    |  y ∈ [1, 2]
//!      +=======================+  ← tied interface, y = 1
//!      |   host (coarse)       |  y ∈ [0, 1]
//!      +-----------------------+
//!      ▲ (x, y fixed)          ▲ (y fixed)
//! ```
//!
//! The exact solution is the constant stress state everywhere, so every element
//! stress must equal σ. Node-to-element coupling transfers a constant traction
//! exactly when every host vertex on the interface is a coupling node.

mod common;

fn problem(host_cells: usize, node_cells: usize, sigma: [f64; 3], c: f64) -> String {
    let [sxx, syy, sxy] = sigma;
    // Resultants σ·n × length on each outer boundary (width 1, height 1 per part).
    let side = |part: &str, b: &str, f: [f64; 2]| {
        format!(
            "[[load]]\npart = \"{part}\"\nboundary = \"{b}\"\nforce = [{:e}, {:e}]\n",
            f[0], f[1]
        )
    };
    let mut s = format!(
        r#"
[materials.m]
E = 1000.0
nu = 0.3

[[part]]
name = "host"
material = "m"
rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], cells = [{host_cells}, {host_cells}] }}

[[part]]
name = "fine"
material = "m"
rectangle = {{ x = [0.0, 1.0], y = [1.0, 2.0], cells = [{node_cells}, {node_cells}] }}

[[interface]]
host = "host"
nodes = "fine"
boundary = "bottom"
law = "rigid"
c_n = {c:e}

[[support]]
part = "host"
at = [0.0, 0.0]
fix = ["x", "y"]

[[support]]
part = "host"
at = [1.0, 0.0]
fix = ["y"]

[analysis]
increments = 1
"#
    );
    s += &side("host", "bottom", [-sxy, -syy]);
    s += &side("host", "left", [-sxx, -sxy]);
    s += &side("host", "right", [sxx, sxy]);
    s += &side("fine", "left", [-sxx, -sxy]);
    s += &side("fine", "right", [sxx, sxy]);
    s += &side("fine", "top", [sxy, syy]);
    s
}

/// Largest deviation of any element stress from σ, relative /// Largest deviation of any element stress from σ, relative to |σ|.
fn patch_error(host_cells: usize, node_cells: usize, sigma: [f64; 3], c: f64) -> f64 {
    let a = common::analysis(&problem(host_cells, node_cells, sigma, c));
    let inc = common::solve(&a).pop().unwrap();
    let norm = sigma.iter().map(|v| v * v).sum::<f64>().sqrt();
    a.recover(&inc.u)
        .iter()
        .flat_map(|s| s.element.iter())
        .map(|s| (0..3).map(|k| (s[k] - sigma[k]).abs()).fold(0.0, f64::max) / norm)
        .fold(0.0, f64::max)
}

const SIGMA: [f64; 3] = [1.0, 2.0, 0.5];
/// E·t of the test material.
const ET: f64 = 1000.0;

/// Host vertices coincide with coupling nodes (ratios 1:1 and 1:2): the constant
/// stress state (tension and shear together) is reproduced up to the penalty's own
/// error, which falls as 1/c (×100 stiffer penalty → ×100 smaller error) until it
/// meets the round-off floor of the penalised system, about 1e-7 at c = 1e6 E·t.
#[test]
fn coincident_vertices_reproduce_constant_stress() {
    for (h, n) in [(2, 2), (2, 4), (3, 6)] {
        let e5 = patch_error(h, n, SIGMA, 1e2 * ET);
        let e7 = patch_error(h, n, SIGMA, 1e4 * ET);
        let e9 = patch_error(h, n, SIGMA, 1e6 * ET);
        println!("{h}:{n}  c = 1e2 Et: {e5:.3e}   1e4 Et: {e7:.3e}   1e6 Et: {e9:.3e}");
        let ratio = e5 / e7;
        assert!(
            (50.0..200.0).contains(&ratio),
            "error does not scale as 1/c: {ratio}"
        );
        assert!(e9 < 1e-6, "{h}:{n}: error {e9:e} at c = 1e6 E·t");
    }
}

/// Truly non-matching meshes (2:3, 3:7): node-to-element coupling cannot transfer a
/// constant traction exactly; the stress error stays bounded (a few per cent, at the
/// interface) and does not depend on the penalty once it is stiff.
#[test]
fn non_matching_error_is_bounded_and_reported() {
    for (h, n) in [(2, 3), (3, 7)] {
        let e_stiff = patch_error(h, n, SIGMA, 1e6 * ET);
        let e_default = patch_error(h, n, SIGMA, cfe::model::DEFAULT_PENALTY_FACTOR * ET);
        println!(
            "{h}:{n}  stress error {e_stiff:.3e} (c = 1e6 E·t), {e_default:.3e} (default penalty)"
        );
        assert!(e_stiff < 0.1, "{h}:{n}: error {e_stiff:e}");
        assert!((e_stiff - e_default).abs() < 0.01 * e_stiff);
    }
}
