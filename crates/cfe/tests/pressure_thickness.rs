//! The pairs' `pressure` and `shear` are stresses: force / (tributary length ×
//! the node part's thickness t), in plane stress and in plane strain, everywhere
//! they are reported (pairs, summary).

mod common;

use common::Problem;

use cfe::analysis::{Analysis, Results};

/// Load P on the upper block's top (N).
const P: f64 = 1000.0;
/// The blocks' width L (mm).
const L: f64 = 30.0;

/// A block (node part, `t_block` thick, x ∈ [0, L], y ∈ [20, 30], 6 × 3 Q4)
/// pressed with P on its top onto a base of the same width (host, `t_base`
/// thick, y ∈ [0, 20], 6 × 4 Q4) resting on rollers, both steel, in plane
/// `plane`, with Poisson's ratio `nu`, through a contact interface (its pairs
/// bonded): a uniform
/// σyy = −P / (L t_block) in the block, up to the penalty's error. (The faces'
/// nodes match, so the node coupling passes this patch test: on non-matching
/// faces it is off by about 1 %, El-Abbasi & Bathe.)
fn pressed_blocks(plane: &str, nu: f64, t_base: f64, t_block: f64) -> String {
    Problem::compact()
        .plane(plane)
        .material("steel", 210000.0, nu)
        .part("base", "steel")
        .key("thickness", t_base)
        .rectangle_of([0.0, L], [0.0, 20.0], [6, 4], "q4")
        .part("block", "steel")
        .key("thickness", t_block)
        .rectangle_of([0.0, L], [20.0, 30.0], [6, 3], "q4")
        .named_interface("face", "base", "block", "bottom")
        .law("contact")
        .rollers("base", [0.0, 0.0])
        .support_at("block", [0.0, 30.0], ["x"])
        .load("block", "top", [0.0, -P])
        .text()
}

/// With the block t = 10 (plane stress) and t = 2.5 (plane strain) thick (and
/// t = 1), the pressure of every pair inside the face (the two corner pairs'
/// normals are tilted by the host's corners) and their mean are P / (L t) to
/// 1e-4 (the penalty's error), the shear ~0, the summary's `max_pressure` that
/// of the rows, and σyy in the block at the face (nodal, from the stress
/// recovery) is −P / (L t): the pressure is a stress, the one the part carries.
#[test]
fn pressure_is_force_over_tributary_length_times_thickness() {
    for (plane, t) in [("stress", 10.0), ("strain", 2.5), ("stress", 1.0)] {
        let a = common::analysis(&pressed_blocks(plane, 0.3, t, t));
        check_face(&a, &a.solve().unwrap(), &format!("{plane} t = {t}"), t);
    }
}

/// The face's pairs and the block's stress at it in `r` (solved from `a`)
/// against the uniform pressure P / (L t) of a block of thickness `t` (see
/// [`pressure_is_force_over_tributary_length_times_thickness`]).
fn check_face(a: &Analysis, r: &Results, case: &str, t: f64) {
    let p = P / (L * t);
    let rows = &r.pairs;
    assert_eq!(rows.len(), 7);
    let inner: Vec<_> = rows
        .iter()
        .filter(|r| r.x > 1e-9 && r.x < L - 1e-9)
        .collect();
    assert_eq!(inner.len(), 5);
    let length: f64 = inner.iter().map(|r| r.tributary).sum();
    let mean = inner.iter().map(|r| r.pressure * r.tributary).sum::<f64>() / length;
    assert!(
        (mean / p - 1.0).abs() < 1e-4,
        "{case}: mean {mean} against {p}"
    );
    for r in &inner {
        assert!((r.pressure / p - 1.0).abs() < 1e-4, "{case}: {r:?}");
        assert!(r.shear.abs() < 1e-4 * p, "{case}: {r:?}");
        // The row's pressure is its force over its share of the face's area.
        assert_eq!(r.pressure, r.force_n / (r.tributary * t));
    }
    let max = rows.iter().map(|r| r.pressure).fold(0.0, f64::max);
    assert_eq!(r.summary.interfaces[0].max_pressure, max);
    assert!((max / p - 1.0).abs() < 1e-4, "{case}: max {max}");
    let block = a.model.part_index("block").unwrap();
    let mesh = &a.model.parts[block].mesh;
    let mut at_face = 0;
    for (n, x) in mesh.nodes.iter().enumerate() {
        if (x[1] - 20.0).abs() < 1e-9 {
            let syy = r.stresses[block].nodal[n][1];
            assert!((syy / -p - 1.0).abs() < 1e-4, "{case}: σyy {syy} at {x:?}");
            at_face += 1;
        }
    }
    assert_eq!(at_face, 7);
}

/// A base twice as thick as the block (20 against 10): the pressure is over the
/// node part's (the block's) thickness, the area the force crosses on its side
/// of the face, and it is the block's σyy there. (ν = 0: the two blocks, under
/// different stresses, then strain alike sideways, and both stay uniform.)
#[test]
fn pressure_uses_the_node_parts_thickness() {
    let a = common::analysis(&pressed_blocks("stress", 0.0, 20.0, 10.0));
    check_face(&a, &a.solve().unwrap(), "base 20, block 10", 10.0);
}

/// What `cfe run` writes: `pairs.csv`'s `pressure` column and `summary.json`'s
/// `max_pressure` are the stresses P / (L t) too (t = 10).
#[test]
fn written_pressures_are_stresses() {
    let t = 10.0;
    let p = P / (L * t);
    let out = std::env::temp_dir().join(format!("cfe-test-pressure-t-{}", std::process::id()));
    let mut a = common::analysis(&pressed_blocks("stress", 0.3, t, t));
    a.run(&out, &mut |_| {}).unwrap();
    let csv = std::fs::read_to_string(out.join("pairs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (x, pressure) = (col("x"), col("pressure"));
    let mut inner = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let xv: f64 = f[x].parse().unwrap();
        if xv > 1e-9 && xv < L - 1e-9 {
            let pv: f64 = f[pressure].parse().unwrap();
            assert!((pv / p - 1.0).abs() < 1e-4, "{line}");
            inner += 1;
        }
    }
    assert_eq!(inner, 5);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let max = s["interfaces"][0]["max_pressure"].as_f64().unwrap();
    assert!((max / p - 1.0).abs() < 1e-4, "{max}");
    std::fs::remove_dir_all(&out).ok();
}
