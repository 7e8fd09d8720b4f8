//! Solid models described in a problem file (`Model::<D3>::from_str` /
//! `from_file`, `Analysis::<D3>::from_file`): a two-block contact model in TOML
//! solved against the uniform closed-form state and statics, the same model
//! built in code giving the same answer, a Gmsh 3D mesh through a problem file,
//! `--refine` in 3D, the 3D example, the dimension probe, and every refusal
//! (keys of the other dimension, wrong component counts, a load box cutting a
//! face) as its typed error.

use cfe::analysis::{Analysis, Results, RunStatus};
use cfe::coupling::PairState;
use cfe::dim::D3;
use cfe::domain::{
    Coupling, Enforcement, FaceLoad, InterfaceDef, Law, Load, Part, Settings, Support,
};
use cfe::error::Error;
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::{Mesh, SolidKind};
use cfe::model::{FromProblemFile, FromProblemText, Model, ProblemDimension, problem_dimension};
use std::path::{Path, PathBuf};

const E: f64 = 70e3;
const NU: f64 = 0.3;
const P: f64 = 40.0;

/// A punch pressed by a uniform pressure `P` onto a base (the host), both
/// meshed in `kind` with nested faces (4 × 4 on 2 × 2), held by symmetry
/// supports (x on the left sides, y on the front sides, z under the base);
/// `c` the penalties (`None`: the default).
fn punch_toml(kind: &str, c: Option<f64>) -> String {
    let penalties = c.map_or(String::new(), |c| format!("c_n = {c:e}\nc_s = {c:e}\n"));
    format!(
        r#"title = "punch on base"
[materials.al]
E = {E:e}
nu = {NU}

[[part]]
name = "base"
material = "al"
box = {{ x = [0.0, 1.0], y = [0.0, 2.0], z = [0.0, 1.0], cells = [2, 2, 2], elements = "{kind}" }}

[[part]]
name = "punch"
material = "al"
box = {{ x = [0.0, 1.0], y = [0.0, 2.0], z = [1.0, 1.5], cells = [4, 4, 2], elements = "{kind}" }}

[[interface]]
name = "base/punch"
host = "base"
nodes = "punch"
boundary = "bottom"
law = "contact"
tolerance = 1e-3
{penalties}
[[support]]
part = "base"
boundary = "left"
fix = ["x"]

[[support]]
part = "base"
boundary = "front"
fix = ["y"]

[[support]]
part = "base"
boundary = "bottom"
fix = ["z"]

[[support]]
part = "punch"
boundary = "left"
fix = ["x"]

[[support]]
part = "punch"
boundary = "front"
fix = ["y"]

[[load]]
part = "punch"
boundary = "top"
pressure = {P}

[analysis]
increments = 1
"#
    )
}

fn solid(text: &str) -> cfe::Result<Model<D3>> {
    Model::<D3>::from_str(text, Path::new("punch.toml"), 1)
}

/// The applied load, the reactions and the pairs' forces balance; every pair
/// keeps its law; the run completes.
fn assert_balanced(res: &Results<D3>, load: f64, what: &str) {
    let s = &res.summary;
    assert_eq!(s.status, RunStatus::Completed, "{what}: {:?}", s.warnings);
    let fz: f64 = s.reactions.iter().map(|r| r.fz.unwrap()).sum();
    let fx: f64 = s.reactions.iter().map(|r| r.fx).sum();
    let fy: f64 = s.reactions.iter().map(|r| r.fy).sum();
    assert!(
        (s.applied[2] + load).abs() < 1e-12 * load,
        "{what}: {:?}",
        s.applied
    );
    assert!((fz - load).abs() < 1e-8 * load, "{what}: Σ fz = {fz}");
    assert!(fx.abs() < 1e-8 * load && fy.abs() < 1e-8 * load, "{what}");
    assert!(
        s.equilibrium_error < 1e-8,
        "{what}: {}",
        s.equilibrium_error
    );
    for r in &res.pairs {
        assert!(!r.breaks_law(), "{what}: {r:?}");
    }
    for i in &s.interfaces {
        assert_eq!(i.violations, 0, "{what}");
    }
}

/// A two-block contact model written as TOML (HEX8 on HEX8, TET4 on TET4),
/// solved: the punch's pressure p reaches the supports (Σ reactions = p A),
/// every pair is bonded and lawful, and every element of both blocks carries
/// the uniaxial closed-form state σzz = −p, the rest 0 (to the penalty's
/// accuracy).
#[test]
fn a_two_block_contact_model_in_toml_transmits_a_uniform_pressure() {
    for kind in ["hex8", "tet4"] {
        let model = solid(&punch_toml(kind, Some(1e5 * E))).unwrap();
        assert_eq!(model.parts.len(), 2);
        let a = Analysis::new(model).unwrap();
        let res = a.solve().unwrap();
        assert_balanced(&res, P * 2.0, kind);
        assert_eq!(res.pairs.len(), 25, "{kind}");
        assert!(res.pairs.iter().all(|r| r.state == PairState::Bonded));
        for part in &res.stresses {
            for sigma in &part.element {
                let want = [0.0, 0.0, -P, 0.0, 0.0, 0.0];
                for (s, w) in sigma.iter().zip(want) {
                    assert!((s - w).abs() < 1e-5 * P, "{kind}: {sigma:?}");
                }
            }
        }
    }
}

/// The default penalty of a solid interface is 1e5 × E × h (h the mean edge of
/// the node part's coupling faces: 0.375 here), and the model it gives passes
/// the same contact patch test to the accuracy that penalty allows.
#[test]
fn the_default_solid_penalty_is_e_times_the_face_size() {
    let model = solid(&punch_toml("hex8", None)).unwrap();
    let h = (0.25 + 0.5) / 2.0;
    let c = model.interfaces[0].c_n;
    assert!((c - 1e5 * E * h).abs() < 1e-9 * c, "{c}");
    assert_eq!(model.interfaces[0].c_s, c);
    let res = Analysis::new(model).unwrap().solve().unwrap();
    assert_balanced(&res, P * 2.0, "default penalty");
    for sigma in res.stresses.iter().flat_map(|p| &p.element) {
        assert!((sigma[2] + P).abs() < 1e-4 * P, "{sigma:?}");
    }
}

/// The TOML model equals the same model built in code (`Mesh::<D3>::block`,
/// `Support::on_boundary`, `Load::on_faces`, an `InterfaceDef`): the same node
/// count, supports, loads and pairs, and the same displacements to 1e-12 of
/// the largest.
#[test]
fn a_toml_model_equals_the_model_built_in_code() {
    let c = 1e5 * E;
    let from_file = solid(&punch_toml("tet4", Some(c))).unwrap();
    let block = |name: &str, z: [f64; 2], cells: [usize; 3]| Part {
        name: name.into(),
        mesh: Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], z, cells, SolidKind::Tet4),
        material: Material::new(E, NU, PlaneKind::Strain, 1.0, name).unwrap(),
    };
    let base = block("base", [0.0, 1.0], [2, 2, 2]);
    let punch = block("punch", [1.0, 1.5], [4, 4, 2]);
    let hold = |i: usize, part: &Part<D3>, side: &str, c: usize| {
        let mut fix = [false; 3];
        fix[c] = true;
        Support::on_boundary(i, part, side, fix, [0.0; 3]).unwrap()
    };
    let supports = vec![
        hold(0, &base, "left", 0),
        hold(0, &base, "front", 1),
        hold(0, &base, "bottom", 2),
        hold(1, &punch, "left", 0),
        hold(1, &punch, "front", 1),
    ];
    let load = Load::on_faces("punch/top", 1, &punch, "top", FaceLoad::Pressure(P), 0).unwrap();
    let interface = InterfaceDef {
        name: "base/punch".into(),
        host: 0,
        node_part: 1,
        nodes: punch.mesh.boundary_nodes("bottom").unwrap(),
        boundary: "bottom".into(),
        law: Law::Contact,
        c_n: c,
        c_s: c,
        tolerance: 1e-3,
        friction: 0.0,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: from_file.interfaces[0].penetration_tolerance,
        coupling: Coupling::Node,
        form: cfe::domain::CouplingForm::Face,
    };
    let settings = Settings {
        increments: 1,
        ..Settings::default()
    };
    let in_code = Model::from_parts(
        "punch on base",
        vec![base, punch],
        vec![interface],
        supports,
        vec![load],
        settings,
    )
    .unwrap();
    let nodes = |m: &Model<D3>| m.parts.iter().map(|p| p.mesh.nodes.len()).sum::<usize>();
    assert_eq!(nodes(&from_file), nodes(&in_code));
    for (a, b) in from_file.supports.iter().zip(&in_code.supports) {
        assert_eq!((&a.name, &a.nodes, a.fix), (&b.name, &b.nodes, b.fix));
    }
    assert_eq!(from_file.loads[0].nodal, in_code.loads[0].nodal);
    assert_eq!(from_file.interfaces[0].nodes, in_code.interfaces[0].nodes);
    let u1 = Analysis::new(from_file).unwrap().solve().unwrap();
    let u2 = Analysis::new(in_code).unwrap().solve().unwrap();
    let (u1, u2) = (u1.displacements(), u2.displacements());
    assert_eq!(u1.len(), u2.len());
    let scale = u2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    for (a, b) in u1.iter().zip(u2) {
        assert!((a - b).abs() <= 1e-12 * scale, "{a} {b}");
    }
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/gmsh")
        .join(name)
}

/// Two cubes from one Gmsh file (a HEX8 cube and a TET4 cube meshed apart,
/// tests/data/gmsh/cubes_41.msh) as parts of a problem file (physical volumes
/// chosen by `volumes`, physical surfaces as boundaries), tied and pulled by a
/// traction q on the far face: the run completes with every pair bonded, the
/// applied force is q × the unit face, and the reactions balance it.
#[test]
fn a_gmsh_3d_mesh_through_a_problem_file() {
    let text = r#"
[materials.steel]
E = 210000.0
nu = 0.3

[[part]]
name = "hexa"
material = "steel"
gmsh = { file = "cubes_41.msh", volumes = ["hexa"] }

[[part]]
name = "tetra"
material = "steel"
gmsh = { file = "cubes_41.msh", volumes = [2] }

[[interface]]
host = "hexa"
nodes = "tetra"
boundary = "interface"
law = "rigid"

[[support]]
part = "hexa"
boundary = "fixed"
fix = ["x"]

[[support]]
part = "hexa"
boundary = "bottom"
fix = ["z"]

[[support]]
part = "hexa"
boundary = "15"
fix = ["y"]

[[load]]
part = "tetra"
boundary = "load"
traction = [5.0, 0.0, 0.0]

[analysis]
increments = 1
"#;
    let path = data("cubes.toml");
    let model = Model::<D3>::from_str(text, &path, 1).unwrap();
    assert_eq!(model.parts[0].mesh.describe_elements(), "8 HEX8");
    assert!(model.parts[1].mesh.counts().0 > 0 && model.parts[1].mesh.counts().1 == 0);
    assert!(model.parts[1].mesh.boundaries.contains_key("load"));
    let resultant = model.loads[0].resultant;
    assert!((resultant[0] - 5.0).abs() < 1e-12 && resultant[1].abs() < 1e-12);
    let res = Analysis::new(model).unwrap().solve().unwrap();
    let s = &res.summary;
    assert_eq!(s.status, RunStatus::Completed, "{:?}", s.warnings);
    let fx: f64 = s.reactions.iter().map(|r| r.fx).sum();
    assert!((fx + 5.0).abs() < 1e-8 * 5.0, "Σ fx = {fx}");
    assert!(res.pairs.iter().all(|r| r.state == PairState::Bonded));
    // Refined: each element into 8, each boundary face into 4.
    let m1 = Model::<D3>::from_str(text, &path, 1).unwrap();
    let m2 = m1.with_refine(2).unwrap();
    for (a, b) in m1.parts.iter().zip(&m2.parts) {
        assert_eq!(b.mesh.elements.len(), 8 * a.mesh.elements.len());
        assert_eq!(
            b.mesh.boundaries["bottom"].len(),
            4 * a.mesh.boundaries["bottom"].len()
        );
    }
}

/// `--refine K` multiplies a box's cell counts by K: (K nx + 1)(K ny + 1)
/// (K nz + 1) nodes, K³ × the elements, and a refined model still solves the
/// patch test to its closed form.
#[test]
fn refine_multiplies_the_cells_of_a_box() {
    let text = punch_toml("hex8", Some(1e5 * E));
    let m1 = solid(&text).unwrap();
    let m2 = m1.with_refine(2).unwrap();
    assert_eq!(m2.refine, 2);
    assert_eq!(m2.parts[0].mesh.nodes.len(), 5 * 5 * 5);
    assert_eq!(m2.parts[1].mesh.nodes.len(), 9 * 9 * 5);
    for (a, b) in m1.parts.iter().zip(&m2.parts) {
        assert_eq!(b.mesh.elements.len(), 8 * a.mesh.elements.len());
    }
    let res = Analysis::new(m2).unwrap().solve().unwrap();
    assert_balanced(&res, P * 2.0, "refined");
    for sigma in res.stresses.iter().flat_map(|p| &p.element) {
        assert!((sigma[2] + P).abs() < 1e-5 * P, "{sigma:?}");
    }
}

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base_3d.toml")
}

/// The 3D plate on a base (examples/plate_on_base_3d.toml: a TET4 plate on a
/// HEX8 base, a load patch, frictionless contact) solves to `completed`: the applied force is the
/// patch's 60 kN, the reactions balance it, every pair keeps its law, the
/// pairs' forces carry the load, and the contact recedes (some pairs open
/// towards the plate's ends, those under the patch stay closed).
#[test]
fn the_3d_plate_on_a_base_example_solves() {
    let path = example();
    assert_eq!(problem_dimension(&path).unwrap(), ProblemDimension::Solid);
    let a = Analysis::<D3>::from_file(&path, 1).unwrap();
    assert_eq!(a.model.parts[0].mesh.describe_elements(), "120 HEX8");
    assert_eq!(a.model.parts[1].mesh.describe_elements(), "4032 TET4");
    let res = a.solve().unwrap();
    let load = 60e3;
    assert_balanced(&res, load, "plate on base");
    let i = &res.summary.interfaces[0];
    assert_eq!(i.pairs, 29 * 9);
    assert!(i.open > 0 && i.bonded > 0, "{i:?}");
    let fz: f64 = res.pairs.iter().map(|r| r.force_z.unwrap()).sum();
    // On the node part (the plate): the base pushes it up with the whole load.
    assert!((fz - load).abs() < 1e-6 * load, "pairs carry {fz}");
    for r in res.pairs.iter().filter(|r| (r.x - 100.0).abs() < 10.0) {
        assert_ne!(r.state, PairState::Open, "{r:?}");
    }
}

/// A solid problem file read by the plane reader (`Model::from_file`, as the
/// Python package does) is an `Error::Dimension` at its first `box` that says
/// the model is solid and how to run it — not that a plane model has a stray
/// key.
#[test]
fn a_solid_file_read_as_a_plane_model_says_it_is_solid() {
    match Model::from_file(&example(), 1) {
        Err(Error::Dimension {
            key, line, message, ..
        }) => {
            assert_eq!(key, "part.base.box");
            assert_eq!(line, Some(29));
            assert!(message.contains("solid (3D) model"), "{message}");
            assert!(message.contains("cfe run"), "{message}");
        }
        other => panic!("expected Error::Dimension, got {other:?}"),
    }
}

/// The dimension probe: a file of boxes is solid, one of rectangles (the seed's
/// plate on a base) plane, a deck plane, a 3D Gmsh part solid, and plane and
/// solid parts together an `Error::Dimension` naming both.
#[test]
fn the_dimension_of_a_problem_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dim = |p: &str| problem_dimension(&root.join(p));
    assert_eq!(
        dim("examples/plate_on_base.toml").unwrap(),
        ProblemDimension::Plane
    );
    assert_eq!(
        dim("examples/plate_on_base.inp").unwrap(),
        ProblemDimension::Plane
    );
    assert_eq!(
        dim("examples/plate_on_base_3d.toml").unwrap(),
        ProblemDimension::Solid
    );
    assert_eq!(
        dim("tests/data/gmsh/plate_on_base.toml").unwrap(),
        ProblemDimension::Plane
    );
    let dir = std::env::temp_dir().join(format!("cfe-problem3d-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("cubes_22.msh"), dir.join("cubes.msh")).unwrap();
    let gmsh = "[materials.m]\nE = 1.0\nnu = 0.3\n[[part]]\nname = \"c\"\nmaterial = \"m\"\ngmsh = { file = \"cubes.msh\" }\n";
    std::fs::write(dir.join("g.toml"), gmsh).unwrap();
    assert_eq!(
        problem_dimension(&dir.join("g.toml")).unwrap(),
        ProblemDimension::Solid
    );
    let mixed = format!(
        "{gmsh}[[part]]\nname = \"flat\"\nmaterial = \"m\"\nrectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], cells = [1, 1] }}\n"
    );
    std::fs::write(dir.join("mixed.toml"), mixed).unwrap();
    match problem_dimension(&dir.join("mixed.toml")) {
        Err(Error::Dimension {
            key, line, message, ..
        }) => {
            assert_eq!((key.as_str(), line), ("part.c", Some(4)));
            assert!(
                message.contains("'flat'") && message.contains("'c'"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The line of `needle` in `text` (1-based).
fn line_of(text: &str, needle: &str) -> usize {
    1 + text[..text.find(needle).unwrap()].matches('\n').count()
}

/// Keys of a plane model in a solid one are `Error::Dimension` naming the key
/// and its line: `plane`, a part's `thickness`, `rectangle`, `annulus`, a
/// `[[line]]`, a Gmsh part's `surfaces`, and `coupling = "segment"` (segment
/// coupling is plane-only).
#[test]
fn plane_keys_in_a_solid_model_are_refused() {
    let base = punch_toml("hex8", None);
    let cases = [
        ("title", "plane = \"strain\"\ntitle", "plane"),
        (
            "material = \"al\"\nbox",
            "material = \"al\"\nthickness = 2.0\nbox",
            "part.base.thickness",
        ),
        (
            "material = \"al\"\nbox",
            "material = \"al\"\nrectangle = { x = [0.0, 1.0], y = [0.0, 1.0], cells = [1, 1] }\nbox",
            "part.base.rectangle",
        ),
        (
            "material = \"al\"\nbox",
            "material = \"al\"\nannulus = { r = [1.0, 2.0], cells = [1, 3] }\nbox",
            "part.base.annulus",
        ),
        (
            "[analysis]",
            "[[line]]\nname = \"l\"\nfrom = [0.0, 0.0]\nto = [1.0, 0.0]\n[analysis]",
            "line",
        ),
        (
            "law = \"contact\"",
            "law = \"contact\"\ncoupling = \"segment\"",
            "interface.base/punch.coupling",
        ),
        (
            "material = \"al\"\nbox",
            "material = \"al\"\ngmsh = { file = \"x.msh\", surfaces = [1] }\nbox",
            "part.base.gmsh.surfaces",
        ),
    ];
    for (from, to, want) in cases {
        let text = base.replacen(from, to, 1);
        assert_ne!(text, base, "{want}");
        let needle = to.lines().find(|l| !from.contains(l)).unwrap();
        match solid(&text) {
            Err(Error::Dimension { key, line, .. }) => {
                assert_eq!(key, want);
                assert_eq!(line, Some(line_of(&text, needle)), "{want}");
            }
            other => panic!("{want}: {other:?}"),
        }
    }
}

/// Keys of a solid model in a plane one are refused too: a part's `box`
/// (`Error::Dimension`), a load's `traction` (`Error::Dimension`), `fix = ["z"]`
/// (`Error::Parse` naming the support, as the plane reader's other `fix`
/// errors).
#[test]
fn solid_keys_in_a_plane_model_are_refused() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let base = std::fs::read_to_string(&root).unwrap();
    let plane = |t: &str| Model::from_str(t, &root, 1);
    assert!(plane(&base).is_ok());
    let with_box = base.replacen(
        "thickness = 1.0\nrectangle = { x = [30.0",
        "thickness = 1.0\nbox = { x = [0.0, 1.0], y = [0.0, 1.0], z = [0.0, 1.0], cells = [1, 1, 1] }\nrectangle = { x = [30.0",
        1,
    );
    match plane(&with_box) {
        Err(Error::Dimension { key, line, .. }) => {
            assert_eq!(
                (key.as_str(), line),
                ("part.plate.box", Some(line_of(&with_box, "box = ")))
            );
        }
        other => panic!("{other:?}"),
    }
    let traction = base.replacen("force = [0.0, -1500.0]", "traction = [0.0, -1.0]", 1);
    assert!(matches!(
        plane(&traction),
        Err(Error::Dimension { ref key, .. }) if key == "load.#1.traction"
    ));
    let z = base.replacen("fix = [\"x\", \"y\"]", "fix = [\"x\", \"z\"]", 1);
    match plane(&z) {
        Err(Error::Parse {
            line: Some(_),
            message,
            ..
        }) => {
            assert!(
                message.contains("\"z\"") && message.contains("base/bottom"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
}

/// A vector with the other dimension's number of components is an
/// `Error::Parse` naming the line and the count: a force of two values in a
/// solid model, of three in a plane one; and a box cell count of two.
#[test]
fn wrong_component_counts_are_refused_with_their_line() {
    let base = punch_toml("hex8", None);
    let two = base.replacen("pressure = 40", "force = [0.0, -1.0]", 1);
    match solid(&two) {
        Err(Error::Parse { line, message, .. }) => {
            assert_eq!(line, Some(line_of(&two, "force = ")));
            assert!(message.contains("exactly 3 values, got 2"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let cells = base.replacen("cells = [2, 2, 2]", "cells = [2, 2]", 1);
    assert!(matches!(
        solid(&cells),
        Err(Error::Parse { line: Some(_), .. })
    ));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let plane = std::fs::read_to_string(&root).unwrap();
    let three = plane.replacen("force = [0.0, -1500.0]", "force = [0.0, -1500.0, 0.0]", 1);
    match Model::from_str(&three, &root, 1) {
        Err(Error::Parse { line, message, .. }) => {
            assert_eq!(line, Some(line_of(&three, "force = [")));
            assert!(message.contains("exactly 2 values, got 3"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

/// Loads on a solid surface: a resultant `force` on a named surface is spread
/// as a uniform traction (its nodal forces sum to it), a box holding whole
/// faces selects them, and a point force away from every node is refused
/// (`Error::Parse` naming it).
#[test]
fn surface_loads_and_load_boxes() {
    let base = punch_toml("hex8", None);
    let force = base.replacen("pressure = 40", "force = [1.0, -2.0, -30.0]", 1);
    let m = solid(&force).unwrap();
    let mut sum = [0.0; 3];
    for (_, f) in &m.loads[0].nodal {
        for c in 0..3 {
            sum[c] += f[c];
        }
    }
    for (s, w) in sum.iter().zip([1.0, -2.0, -30.0]) {
        assert!((s - w).abs() < 1e-12 * 30.0, "{sum:?}");
    }
    // Half of the top (y from 0 to 1: 4 × 2 faces of 0.25 × 0.5) by a box.
    let half = base.replacen(
        "pressure = 40",
        "pressure = 40\nfrom = [0.0, 0.0, 1.5]\nto = [1.0, 1.0, 1.5]",
        1,
    );
    let m = solid(&half).unwrap();
    assert!((m.loads[0].resultant[2] + P * 1.0).abs() < 1e-12 * P);
    let point = base.replacen(
        "boundary = \"top\"\npressure = 40",
        "at = [0.1, 0.0, 1.5]\nforce = [0.0, 0.0, -1.0]",
        1,
    );
    match solid(&point) {
        Err(Error::Parse { message, .. }) => {
            assert!(message.contains("matches no node"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

/// `cfe check`'s description of a solid model names it solid, counts its
/// parts' elements by kind and their boundaries' faces, the interface's pairs,
/// the components each support fixes, and each load's resultant as a
/// 3-vector (the patch's 60 kN down).
#[test]
fn a_solid_model_is_described() {
    let a = Analysis::<D3>::from_file(&example(), 1).unwrap();
    let d = a.describe();
    for want in [
        "solid model",
        "part 'base': 231 nodes, 120 HEX8 elements",
        "'top' 20",
        "part 'plate': 1044 nodes, 4032 TET4 elements",
        "interface 'plate-base': host 'base', nodes 'plate', law frictionless, 261 pairs",
        "support 'base/bottom': 33 nodes, fix x, y, z",
        "load 'patch': resultant (0, 0, -6e4)",
    ] {
        assert!(d.contains(want), "{want}\n{d}");
    }
}

/// Σ f and Σ x × f (about the origin) of a load's nodal forces on `part`.
fn resultant_and_moment(m: &Model<D3>, load: usize) -> ([f64; 3], [f64; 3]) {
    let l = &m.loads[load];
    let nodes = &m.parts[l.part].mesh.nodes;
    let (mut r, mut mo) = ([0.0; 3], [0.0; 3]);
    for (n, f) in &l.nodal {
        let x = nodes[*n];
        let c = [
            x[1] * f[2] - x[2] * f[1],
            x[2] * f[0] - x[0] * f[2],
            x[0] * f[1] - x[1] * f[0],
        ];
        for k in 0..3 {
            r[k] += f[k];
            mo[k] += c[k];
        }
    }
    (r, mo)
}

/// A load box that cuts faces (HEX8 and TET4 tops, boxes off the mesh lines)
/// loads exactly the part inside it: a pressure p gives the resultant
/// −p × (clipped area) e_z and the moment −p A (c × e_z) about the origin
/// (c the clipped rectangle's centroid), to round-off; a traction and a
/// spread resultant `force` likewise; and the loaded nodes include the cut
/// faces' nodes outside the box.
#[test]
fn a_load_box_cutting_faces_loads_exactly_its_part() {
    for kind in ["hex8", "tet4"] {
        let base = punch_toml(kind, None);
        // The top is z = 1.5, x in [0, 1], y in [0, 2]; the box cuts it to
        // [0.1, 0.83] × [0.3, 1.37] (faces of 0.25 × 0.5).
        let (x0, x1, y0, y1) = (0.1, 0.83, 0.3, 1.37);
        let area = (x1 - x0) * (y1 - y0);
        let c = [(x0 + x1) / 2.0, (y0 + y1) / 2.0, 1.5];
        let boxed = |load: &str| {
            base.replacen(
                "pressure = 40",
                &format!("{load}\nfrom = [{x0}, {y0}, 1.5]\nto = [{x1}, {y1}, 1.5]"),
                1,
            )
        };
        let m = solid(&boxed("pressure = 40")).unwrap();
        let (r, mo) = resultant_and_moment(&m, 0);
        let f = P * area;
        let tol = 1e-13 * f;
        assert!(
            (r[2] + f).abs() < tol && r[0].abs() < tol && r[1].abs() < tol,
            "{kind}: {r:?}"
        );
        assert!((m.loads[0].resultant[2] + f).abs() < tol, "{kind}");
        // M = c × (−f e_z) = (−f c_y, f c_x, 0).
        let want = [-f * c[1], f * c[0], 0.0];
        for k in 0..3 {
            assert!(
                (mo[k] - want[k]).abs() < 1e-13 * f * 2.0,
                "{kind}: {mo:?} vs {want:?}"
            );
        }
        // A node outside the box (y = 0 row) carries part of a cut face's load.
        let nodes = &m.parts[1].mesh.nodes;
        assert!(
            m.loads[0]
                .nodal
                .iter()
                .any(|(n, _)| nodes[*n][1] < y0 - 1e-9),
            "{kind}"
        );
        // A traction [1, 2, 3] per area: resultant area × t, moment c × (area t).
        let t = [1.0, 2.0, 3.0];
        let m = solid(&boxed("traction = [1.0, 2.0, 3.0]")).unwrap();
        let (r, mo) = resultant_and_moment(&m, 0);
        let ft = t.map(|v| v * area);
        let want = [
            c[1] * ft[2] - c[2] * ft[1],
            c[2] * ft[0] - c[0] * ft[2],
            c[0] * ft[1] - c[1] * ft[0],
        ];
        for k in 0..3 {
            assert!((r[k] - ft[k]).abs() < 1e-13 * 3.0, "{kind}: {r:?}");
            assert!(
                (mo[k] - want[k]).abs() < 1e-13 * 6.0,
                "{kind}: {mo:?} vs {want:?}"
            );
        }
        // A resultant spread over the box: its nodal forces sum to it, centred
        // at c.
        let m = solid(&boxed("force = [0.0, 0.0, -12.0]")).unwrap();
        let (r, mo) = resultant_and_moment(&m, 0);
        assert!((r[2] + 12.0).abs() < 1e-13 * 12.0, "{kind}: {r:?}");
        assert!((mo[0] + 12.0 * c[1]).abs() < 1e-12 && (mo[1] - 12.0 * c[0]).abs() < 1e-12);
    }
}

/// A punch lifted off the base (its bottom at z = 1.2, tolerance 1e-3): the
/// coupling nodes are the typed `Error::OrphanNodes`, each listed with its
/// three coordinates (z = 1.2, on the punch's bottom) as the message prints
/// them.
#[test]
fn orphan_coupling_nodes_of_a_solid_model_carry_x_y_z() {
    let text = punch_toml("hex8", None).replace("z = [1.0, 1.5]", "z = [1.2, 1.5]");
    let e = Analysis::new(solid(&text).unwrap()).err().expect("orphans");
    let Error::OrphanNodes {
        interface, nodes, ..
    } = &e
    else {
        panic!("unexpected error {e:?}");
    };
    assert_eq!(interface, "base/punch");
    // The punch's bottom: 5 × 5 nodes of the 4 × 4 faces.
    assert_eq!(nodes.len(), 25);
    for (_, x) in nodes {
        assert_eq!(x.len(), 3);
        assert!((x[2] - 1.2).abs() < 1e-15, "{x:?}");
    }
    let message = e.to_string();
    assert!(message.contains(", 1.2) (nearest host face"), "{message}");
}

/// With a search distance too short for the gap (0.1 < 0.2), a solid
/// interface's `Error::NoPairs` gives the nearest node–face distance: the
/// gap 0.2.
#[test]
fn no_pairs_in_a_solid_model_measure_the_nearest_distance() {
    let text = punch_toml("tet4", None)
        .replace("z = [1.0, 1.5]", "z = [1.2, 1.5]")
        .replace("tolerance = 1e-3", "search_distance = 0.1");
    match Analysis::new(solid(&text).unwrap()).err() {
        Some(Error::NoPairs {
            nearest: Some(d), ..
        }) => assert!((d - 0.2).abs() < 1e-12, "{d}"),
        other => panic!("{other:?}"),
    }
}

/// A probe inside a solid part is interpolated in the element containing it
/// (HEX8: Newton's inverse map; TET4: barycentric): its weights are that
/// element's nodes, non-negative, summing to 1 and reproducing the point; a
/// probe on a node is that node alone.
#[test]
fn solid_probes_interpolate_in_their_element() {
    for kind in ["hex8", "tet4"] {
        let text = punch_toml(kind, None)
            + "\n[[probe]]\nname = \"inside\"\npart = \"base\"\nat = [0.31, 1.27, 0.58]\n\
               \n[[probe]]\nname = \"corner\"\npart = \"punch\"\nat = [1.0, 2.0, 1.5]\n";
        let m = solid(&text).unwrap();
        let p = &m.probes[0];
        let e = p.element.expect("in an element");
        let nodes = m.parts[0].mesh.elements[e].nodes();
        assert_eq!(p.weights.len(), nodes.len(), "{kind}");
        let sum: f64 = p.weights.iter().map(|(_, w)| w).sum();
        assert!((sum - 1.0).abs() < 1e-13, "{kind}: {sum}");
        for k in 0..3 {
            let x: f64 = (p.weights.iter())
                .map(|(n, w)| w * m.parts[0].mesh.nodes[*n][k])
                .sum();
            assert!((x - p.at[k]).abs() < 1e-12, "{kind}: {x} vs {:?}", p.at);
        }
        assert!(
            p.weights
                .iter()
                .all(|(n, w)| *w >= -1e-12 && nodes.contains(n))
        );
        let c = &m.probes[1];
        assert_eq!(c.element, None);
        assert_eq!(c.weights, vec![(c.node, 1.0)]);
        assert_eq!(m.parts[1].mesh.nodes[c.node], [1.0, 2.0, 1.5]);
    }
}

/// `[output] view` and `component` choose deformed.png's viewpoint and
/// colouring in a solid model (the default without them: isometric, von
/// Mises); an unknown name is `Error::Invalid` naming the key and its line;
/// in a plane model both keys are `Error::Dimension`.
#[test]
fn the_solid_picture_is_chosen_in_output() {
    use cfe::model::{Picture, PictureField, ViewPoint};
    let base = punch_toml("hex8", None);
    assert_eq!(solid(&base).unwrap().picture, Picture::default());
    let chosen = base.clone() + "\n[output]\nview = \"-y\"\ncomponent = \"uz\"\n";
    let m = solid(&chosen).unwrap();
    assert_eq!(m.picture.view, ViewPoint::Axis(1, false));
    assert_eq!(m.picture.field, PictureField::Displacement(2));
    let m = solid(&(base.clone() + "\n[output]\ncomponent = \"sxz\"\n")).unwrap();
    assert_eq!(m.picture.field, PictureField::Stress(5));
    for (key, text) in [
        ("output.view", "view = \"top\"\n"),
        ("output.component", "component = \"tresca\"\n"),
    ] {
        let bad = base.clone() + "\n[output]\n" + text;
        match solid(&bad) {
            Err(Error::Invalid {
                key: k,
                line,
                message,
                ..
            }) => {
                assert_eq!(k, key);
                assert_eq!(line, Some(line_of(&bad, text.trim_end())));
                assert!(message.contains("one of:"), "{message}");
            }
            other => panic!("{key}: {other:?}"),
        }
    }
    let plane = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml"),
    )
    .unwrap()
        + "\n[output]\nview = \"x\"\n";
    match Model::from_str(&plane, Path::new("examples/plate_on_base.toml"), 1) {
        Err(Error::Dimension { key, .. }) => assert_eq!(key, "output.view"),
        other => panic!("{other:?}"),
    }
}

/// One block (1 × 1 × 2, `kind` cells) held by symmetry supports and pulled
/// by a prescribed u_z = 0.01 on its top, selected by a support box; with
/// `steps`, in steps.
fn pulled_block(kind: &str, steps: &str) -> String {
    format!(
        r#"[materials.al]
E = {E:e}
nu = {NU}

[[part]]
name = "block"
material = "al"
box = {{ x = [0.0, 1.0], y = [0.0, 1.0], z = [0.0, 2.0], cells = [2, 2, 4], elements = "{kind}" }}

[[support]]
part = "block"
boundary = "bottom"
fix = ["z"]

[[support]]
part = "block"
boundary = "left"
fix = ["x"]

[[support]]
part = "block"
boundary = "front"
fix = ["y"]

[[support]]
name = "pull"
part = "block"
from = [-1.0, -1.0, 2.0]
to = [2.0, 2.0, 2.0]
fix = ["z"]
value = [0.0, 0.0, 0.01]
{steps}"#
    )
}

/// A support box selects the boundary nodes inside it (the top's 3 × 3 nodes,
/// whatever boundary they are on) and a prescribed displacement on it pulls
/// the block into the closed-form uniaxial state: σzz = E ε, ε = 0.01 / 2,
/// the bottom's reaction −E ε A and the box's +E ε A (HEX8 and TET4, exact
/// to round-off); a box holding no node is refused (`Error::Parse`).
#[test]
fn support_boxes_and_prescribed_displacements_in_3d() {
    for kind in ["hex8", "tet4"] {
        let m = solid(&pulled_block(kind, "")).unwrap();
        let pull = &m.supports[3];
        assert_eq!(pull.name, "pull");
        assert_eq!(pull.nodes.len(), 9, "{kind}");
        assert_eq!(pull.fix, [false, false, true]);
        let res = Analysis::new(m).unwrap().solve().unwrap();
        assert_eq!(res.summary.status, RunStatus::Completed, "{kind}");
        let f = E * 0.01 / 2.0;
        let r = &res.summary.reactions;
        assert!((r[0].fz.unwrap() + f).abs() < 1e-9 * f, "{kind}: {r:?}");
        assert!((r[3].fz.unwrap() - f).abs() < 1e-9 * f, "{kind}: {r:?}");
        for s in &res.stresses {
            for v in &s.element {
                assert!((v[2] - f).abs() < 1e-9 * f, "{kind}: {v:?}");
            }
        }
    }
    let empty = pulled_block("hex8", "").replace("z = [0.0, 2.0]", "z = [0.0, 1.5]");
    match solid(&empty) {
        Err(Error::Parse { message, .. }) => {
            assert!(message.contains("holds no node"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

/// Load steps in 3D: the prescribed pull in a first step of 2 increments,
/// then doubled by a second step's factor: the reaction follows the steps
/// (E ε A, then 2 E ε A), the run has 3 increments and completes.
#[test]
fn load_steps_in_a_solid_model() {
    let steps = "\n[[step]]\nname = \"first\"\nincrements = 2\n\
                 \n[[step]]\nname = \"double\"\nincrements = 1\nfactors = { pull = 2.0 }\n";
    let m = solid(&pulled_block("hex8", steps)).unwrap();
    assert_eq!(m.steps.len(), 2);
    let res = Analysis::new(m).unwrap().solve().unwrap();
    let s = &res.summary;
    assert_eq!(s.status, RunStatus::Completed);
    assert_eq!(s.converged_increments, 3);
    let f = E * 0.01 / 2.0;
    let fz = s.reactions[3].fz.unwrap();
    assert!((fz - 2.0 * f).abs() < 1e-9 * f, "{fz}");
}

/// A penalty beyond 1e16 × the softer part's stiffness scale in a solid model
/// is `Error::PenaltyPrecision` whose message names that scale E·h (h the
/// face size), not a plane model's E·t.
#[test]
fn solid_penalty_messages_name_e_times_h() {
    match solid(&punch_toml("hex8", Some(1e30))) {
        Err(Error::PenaltyPrecision { message, .. }) => {
            assert!(
                message.contains("× E·h of part") && !message.contains("E·t"),
                "{message}"
            )
        }
        other => panic!("{other:?}"),
    }
}
