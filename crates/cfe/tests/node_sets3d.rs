//! Named node sets in a solid model: a Gmsh file's physical points and curves
//! (tests/data/gmsh/node_sets_3d.msh, written by make_node_sets_3d.py) become
//! node sets of the part, usable where a support's or a `force` load's
//! `boundary` names a surface, and kept through `--refine`; a name that is
//! neither a boundary nor a node set is a typed error naming the part, the set
//! and the line.

use cfe::analysis::{Analysis, RunStatus};
use cfe::dim::D3;
use cfe::error::Error;
use cfe::model::{FromProblemText, Model};
use std::path::{Path, PathBuf};

const E: f64 = 200e3;
const NU: f64 = 0.3;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/gmsh")
        .join(name)
}

/// The beam (4 × 1 × 1, 8 × 2 × 2 HEX8) with `rest` appended.
fn beam(rest: &str) -> String {
    format!(
        r#"
[materials.steel]
E = {E:e}
nu = {NU}

[[part]]
name = "beam"
material = "steel"
gmsh = {{ file = "node_sets_3d.msh" }}
{rest}
[analysis]
increments = 1
"#
    )
}

fn model(text: &str, refine: usize) -> cfe::Result<Model<D3>> {
    Model::<D3>::from_str(text, &data("node_sets.toml"), refine)
}

/// The physical points and curves are node sets of the part: the corner
/// point one node at the origin, the curves the nodes of their edge lines
/// (3 along y at 2 cells); `--refine 2` puts the new nodes on the curves'
/// lines into the sets (5 along y), every one of them on its line.
#[test]
fn physical_points_and_curves_are_node_sets_kept_by_refine() {
    for k in [1, 2] {
        let m = model(&beam(""), k).unwrap();
        let mesh = &m.parts[0].mesh;
        let corner = &mesh.node_sets["corner"].nodes;
        assert_eq!(corner.len(), 1);
        assert_eq!(mesh.nodes[corner[0]], [0.0, 0.0, 0.0]);
        for (set, x, z) in [("hinge", 0.0, 0.0), ("tip", 4.0, 1.0)] {
            let nodes = &mesh.node_sets[set].nodes;
            assert_eq!(nodes.len(), 2 * k + 1, "{set}, refine {k}");
            let mut ys: Vec<f64> = nodes
                .iter()
                .map(|&n| {
                    let p = mesh.nodes[n];
                    assert!(
                        (p[0] - x).abs() < 1e-12 && (p[2] - z).abs() < 1e-12,
                        "{set}: {p:?}"
                    );
                    p[1]
                })
                .collect();
            ys.sort_by(f64::total_cmp);
            for (i, y) in ys.iter().enumerate() {
                assert!(
                    (y - i as f64 / (2 * k) as f64).abs() < 1e-12,
                    "{set}: {ys:?}"
                );
            }
        }
        // A surface is still a boundary, not a node set.
        assert!(mesh.boundaries.contains_key("root") && !mesh.node_sets.contains_key("root"));
    }
}

/// Uniaxial tension held by node sets: the root face on rollers (x), the
/// hinge line (a physical curve) fixed in z, the corner (a physical point)
/// in y, a traction σ on the end face. The support on node sets removes the
/// rigid modes and nothing more, so the answer is the closed-form state
/// u = (σ x / E, −ν σ y / E, −ν σ z / E) at every node (HEX8 exact) and the
/// hinge and corner react nothing, the root −σ A.
#[test]
fn supports_on_node_sets_hold_a_bar_in_uniaxial_tension() {
    let sigma = 50.0;
    let text = beam(&format!(
        r#"
[[support]]
part = "beam"
boundary = "root"
fix = ["x"]

[[support]]
part = "beam"
boundary = "hinge"
fix = ["z"]

[[support]]
part = "beam"
boundary = "corner"
fix = ["y"]

[[load]]
part = "beam"
boundary = "end"
traction = [{sigma:e}, 0.0, 0.0]
"#
    ));
    let m = model(&text, 1).unwrap();
    assert_eq!(m.supports[1].name, "beam/hinge");
    assert_eq!(m.supports[1].nodes.len(), 3);
    assert_eq!(m.supports[2].nodes.len(), 1);
    let nodes = m.parts[0].mesh.nodes.clone();
    let res = Analysis::new(m).unwrap().solve().unwrap();
    assert_eq!(res.summary.status, RunStatus::Completed);
    let u = res.displacements();
    let scale = sigma * 4.0 / E;
    for (g, p) in nodes.iter().enumerate() {
        let exact = [
            sigma * p[0] / E,
            -NU * sigma * p[1] / E,
            -NU * sigma * p[2] / E,
        ];
        for c in 0..3 {
            assert!(
                (u[3 * g + c] - exact[c]).abs() < 1e-9 * scale,
                "node {g} {p:?}: u{c} = {} against {}",
                u[3 * g + c],
                exact[c]
            );
        }
    }
    let r = res.reactions();
    let f = sigma * 1.0 * 1.0;
    assert!((r[0].fx + f).abs() < 1e-9 * f, "{r:?}");
    assert!(r[1].fz.unwrap().abs() < 1e-9 * f, "{r:?}");
    assert!(r[2].fy.abs() < 1e-9 * f, "{r:?}");
}

/// A `force` on a node set is its resultant spread equally over the set's
/// nodes: the cantilever clamped at its root and pulled down by P on its tip
/// line gets P/3 at each of the line's three nodes, and the clamp reacts P
/// upward and the moment P L about y (statics).
#[test]
fn a_force_on_a_node_set_is_spread_equally_over_its_nodes() {
    let p = 30.0;
    let text = beam(&format!(
        r#"
[[support]]
part = "beam"
boundary = "root"
fix = ["x", "y", "z"]

[[load]]
part = "beam"
boundary = "tip"
force = [0.0, 0.0, {}]
"#,
        -p
    ));
    let m = model(&text, 1).unwrap();
    let load = &m.loads[0];
    assert_eq!(load.name, "beam/tip");
    assert_eq!(load.nodal.len(), 3);
    for (_, f) in &load.nodal {
        assert_eq!(*f, [0.0, 0.0, -p / 3.0]);
    }
    let nodes = m.parts[0].mesh.nodes.clone();
    let support = m.supports[0].nodes.clone();
    let res = Analysis::new(m).unwrap().solve().unwrap();
    assert_eq!(res.summary.status, RunStatus::Completed);
    let r = &res.reactions()[0];
    assert!((r.fz.unwrap() - p).abs() < 1e-9 * p, "{r:?}");
    assert!(r.fx.abs() < 1e-9 * p && r.fy.abs() < 1e-9 * p, "{r:?}");
    // The clamp's moment about the y axis through the root balances P × L:
    // Σ (z f_x − x f_z) over the root's reactions (x = 0) = −(z_tip·0 − 4·(−P)).
    let f_int = &res.last.f_int;
    let my: f64 = support
        .iter()
        .map(|&g| nodes[g][2] * f_int[3 * g] - nodes[g][0] * f_int[3 * g + 2])
        .sum();
    assert!((my - (-4.0 * p)).abs() < 1e-8 * 4.0 * p, "M_y = {my}");
}

/// A `boundary` naming neither a boundary nor a node set of the part is a
/// parse error with its line, naming the part, the name and the sets the
/// part has; a node set given to a pressure is refused as not a surface.
#[test]
fn an_unknown_node_set_is_refused_with_its_line() {
    let text = beam(
        r#"
[[support]]
part = "beam"
boundary = "hing"
fix = ["z"]
"#,
    );
    let line = text.lines().position(|l| l.contains("\"hing\"")).unwrap() + 1;
    match model(&text, 1) {
        Err(Error::Parse {
            line: Some(l),
            message,
            ..
        }) => {
            assert_eq!(l, line, "{message}");
            assert!(
                message.contains("part 'beam' has no boundary or node set named 'hing'")
                    && message.contains("node sets: corner, hinge, tip"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    let text = beam(
        r#"
[[load]]
part = "beam"
boundary = "tip"
pressure = 1.0
"#,
    );
    match model(&text, 1) {
        Err(Error::Parse {
            line: Some(_),
            message,
            ..
        }) => {
            assert!(
                message.contains("'tip' is a node set of part 'beam', not a boundary"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
}
