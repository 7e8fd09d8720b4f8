//! Prescribed displacements and point loads.
//!
//! ```text
//!        uy = −δ on the top (prescribed)
//!      +-------------------+   y = 2
//!      |  upper (fine)     |
//!      +===================+   y = 1, tied, 3:6 (host vertices are coupling nodes)
//!      |  lower (coarse)   |
//!      +-------------------+   y = 0, uy = 0; (0,0) also ux = 0
//! ```
//!
//! Plane stress, free sides: uniaxial compression, σyy = −E δ / H everywhere
//! (H = 2), σxx = σxy = 0, up to the tie's penalty error O(E·t/c) = 1e-6 here; the
//! reaction on the bottom balances the one on the top.

mod common;

const E: f64 = 1000.0;
const DELTA: f64 = 0.01;

fn problem(extra: &str) -> String {
    format!(
        r#"
[materials.m]
E = {E}
nu = 0.25

[[part]]
name = "lower"
material = "m"
rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], cells = [3, 3] }}

[[part]]
name = "upper"
material = "m"
rectangle = {{ x = [0.0, 1.0], y = [1.0, 2.0], cells = [6, 6] }}

[[interface]]
host = "lower"
nodes = "upper"
boundary = "bottom"
law = "rigid"
c_n = 1e9

[[support]]
part = "lower"
boundary = "bottom"
fix = ["y"]

[[support]]
part = "lower"
at = [0.0, 0.0]
fix = ["x"]

{extra}

[analysis]
increments = 2
"#
    )
}

/// A prescribed top displacement compresses the tied pair of blocks uniformly:
/// every element has σyy = −E δ / H to 1e-5 (the penalty's error), and the reactions of the two supports
/// that carry it are equal and opposite, each E δ / H × width.
#[test]
fn prescribed_displacement_gives_uniaxial_stress() {
    let text = problem(&format!(
        "[[support]]\npart = \"upper\"\nboundary = \"top\"\nfix = [\"y\"]\nvalue = [0.0, {}]\n",
        -DELTA
    ));
    let a = common::analysis(&text);
    let inc = common::solve(&a).pop().unwrap();
    let sigma = -E * DELTA / 2.0;
    for s in a.recover(&inc.u).iter().flat_map(|p| p.element.iter()) {
        assert!(
            (s[1] - sigma).abs() < 1e-5 * sigma.abs(),
            "σyy = {} (expected {sigma})",
            s[1]
        );
        assert!(
            s[0].abs() < 1e-5 * sigma.abs() && s[2].abs() < 1e-5 * sigma.abs(),
            "{s:?}"
        );
    }
    // Reactions per support (forces of the supports on the blocks): the bottom
    // pushes up and the top pushes down, by |σ| × width.
    let r = a.reactions(&inc);
    assert!(
        (r[0][1] + sigma).abs() < 1e-5 * sigma.abs(),
        "bottom reaction {:?}",
        r[0]
    );
    assert!(
        (r[2][1] - sigma).abs() < 1e-5 * sigma.abs(),
        "top reaction {:?}",
        r[2]
    );
    assert!(
        (r[0][1] + r[2][1]).abs() < 1e-9 * sigma.abs(),
        "reactions do not balance"
    );
    // The top moved by exactly −δ at full load.
    let top = common::displacement_at(&a, &inc, "upper", [0.5, 2.0]);
    assert!((top[1] + DELTA).abs() < 1e-15);
}

/// A point load at a node is carried to the supports: the reactions balance it to
/// 1e-7 (the round-off of a tie 1e6 times stiffer than the blocks).
#[test]
fn point_load_is_balanced() {
    let text = problem("[[load]]\npart = \"upper\"\nat = [0.5, 2.0]\nforce = [0.3, -2.0]\n");
    let a = common::analysis(&text);
    let inc = common::solve(&a).pop().unwrap();
    let total = common::total_reaction(&a, &inc);
    // Round-off of the stiff tie (c = 1e6 E·t) limits the balance to about 1e-9.
    assert!(
        (total[0] + 0.3).abs() < 1e-7 * 2.0 && (total[1] - 2.0).abs() < 1e-7 * 2.0,
        "{total:?}"
    );
}
