//! CalculiX/Abaqus deck import (issue 40): decks written as a CalculiX user
//! writes them give the same model and results as the TOML problem they
//! describe, and everything outside the subset, or malformed, is a typed
//! [`Error::Deck`] naming the line and the keyword.

mod common;

use cfe::analysis::Analysis;
use cfe::model::Model;
use cfe::{DeckFault, Error};
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A fresh folder under the target directory for deck files.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("inp-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The deck text read from `problem.inp` in the current folder.
fn deck(text: &str) -> cfe::Result<Model> {
    Model::from_inp_str(text, Path::new("problem.inp"))
}

/// The seed's plate on a base as a CalculiX deck (examples/plate_on_base.inp:
/// the same meshes, a *CONTACT PAIR with a LINEAR pressure-overclosure of the
/// seed's penalty and ROUGH friction, the segment load's nodal forces as
/// *CLOADs) gives the TOML model's parts, penalties, supports and loads, and
/// the same displacements and pair states at every increment.
#[test]
fn plate_on_base_deck_matches_the_toml_model() {
    let toml = Analysis::new(Model::from_file(&example("plate_on_base.toml"), 1).unwrap()).unwrap();
    let inp = Analysis::new(Model::from_file(&example("plate_on_base.inp"), 1).unwrap()).unwrap();
    assert_eq!(inp.model.title, "Plate on a base (CalculiX deck)");
    for (a, b) in toml.model.parts.iter().zip(&inp.model.parts) {
        assert_eq!(a.mesh.nodes, b.mesh.nodes, "{}", b.name);
        assert_eq!(a.mesh.elements, b.mesh.elements, "{}", b.name);
        assert_eq!(a.material.young, b.material.young);
        assert_eq!(a.material.thickness, b.material.thickness);
    }
    let (ia, ib) = (&toml.interfaces[0], &inp.interfaces[0]);
    assert_eq!(ia.law, ib.law);
    assert!((ia.c_n - ib.c_n).abs() <= 1e-12 * ia.c_n && (ia.c_s - ib.c_s).abs() <= 1e-12 * ia.c_s);
    assert_eq!(ia.elements.len(), ib.elements.len());
    assert_eq!(toml.model.supports[0].nodes, inp.model.supports[0].nodes);
    let ra = toml.model.loads[0].resultant;
    let rb: f64 = inp.model.loads.iter().map(|l| l.resultant[1]).sum();
    assert!((ra[1] - rb).abs() < 1e-9 * ra[1].abs());
    let (ua, ub) = (common::solve(&toml), common::solve(&inp));
    assert_eq!(ua.len(), 10);
    assert_eq!(ua.len(), ub.len());
    for (a, b) in ua.iter().zip(&ub) {
        let scale = a.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let diff =
            a.u.iter()
                .zip(&b.u)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-10 * scale, "increment {}: {diff:e}", a.index);
        assert_eq!(a.states, b.states, "increment {}", a.index);
    }
}

/// A cantilever (x ∈ [0, 10], y ∈ [0, 1], CPS4) as a CalculiX user writes it:
/// nodes in an *INCLUDEd file, lower-case keywords, GENERATE sets, a tip load
/// spread over the end's nodes. `two` splits it at x = 4 into two bodies with
/// their own nodes, joined by a *TIE.
fn cantilever(dir: &Path, two: bool) -> PathBuf {
    let (nx, ny) = (20, 4);
    let id = |i: usize, j: usize, right: bool| {
        // The right body's nodes from 1001 when split at column 8.
        let base = if right { 1001 } else { 1 };
        base + j * (nx + 1) + i
    };
    let mut mesh = String::from("** cantilever nodes\n*node, nset=nall\n");
    let split = 8;
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.25);
            if !two || i <= split {
                mesh += &format!("{}, {x}, {y}, 0.\n", id(i, j, false));
            }
            if two && i >= split {
                mesh += &format!("{}, {x}, {y}\n", id(i, j, true));
            }
        }
    }
    std::fs::write(dir.join("cantilever_nodes.inp"), mesh).unwrap();
    let mut d = String::from(
        "*Heading\nCantilever, tip load\n** units: mm, N, MPa\n*Include, input=cantilever_nodes.inp\n",
    );
    let mut elements = |name: &str, i0: usize, i1: usize, right: bool, first: usize| {
        d += &format!("*Element, type=CPS4, elset={name}\n");
        let mut k = first;
        for j in 0..ny {
            for i in i0..i1 {
                d += &format!(
                    "{k}, {}, {}, {}, {}\n",
                    id(i, j, right),
                    id(i + 1, j, right),
                    id(i + 1, j + 1, right),
                    id(i, j + 1, right)
                );
                k += 1;
            }
        }
    };
    if two {
        elements("ROOT", 0, split, false, 1);
        elements("ARM", split, nx, true, 1001);
    } else {
        elements("BEAM", 0, nx, false, 1);
    }
    d += "*Material, name=Alu\n*Elastic\n70000., 0.33\n*Density\n2.7e-9\n";
    for name in if two {
        &["ROOT", "ARM"][..]
    } else {
        &["BEAM"][..]
    } {
        d += &format!("*Solid Section, elset={name}, material=Alu\n2.\n");
    }
    d += "*Nset, nset=clamp, generate\n";
    d += &format!("1, {}, {}\n", id(0, ny, false), nx + 1);
    let tip_right = two;
    d += "*Nset, nset=tip, generate\n";
    d += &format!(
        "{}, {}, {}\n",
        id(nx, 0, tip_right),
        id(nx, ny, tip_right),
        nx + 1
    );
    if two {
        // The ROOT's right end (faces S2 of its last column) is the master.
        d += "*Elset, elset=root_end, generate\n";
        d += &format!("{split}, {}, {split}\n", split * ny);
        d += "*Surface, name=root_end, type=element\nroot_end, S2\n";
        d += "*Nset, nset=arm_start, generate\n";
        d += &format!(
            "{}, {}, {}\n",
            id(split, 0, true),
            id(split, ny, true),
            nx + 1
        );
        d += "*Surface, name=arm_start, type=node\narm_start\n";
        d += "*Tie, name=glue, adjust=yes\narm_start, root_end\n";
    }
    d += "*Boundary\nclamp, 1, 2\n";
    d += "*Step\n*Static\n1., 1.\n*Cload\ntip, 2, -20.\n*Node print, nset=tip\nU\n*End step\n";
    let path = dir.join(if two { "tied.inp" } else { "one.inp" });
    std::fs::write(&path, d).unwrap();
    path
}

/// A cantilever in two bodies joined by *TIE (rigid law, cfe's default
/// penalty) deflects as the same cantilever in one body (relative difference
/// of the tip deflection below 1e-4, the penalty's compliance being 1e-5 of
/// the parts'), and the clamp of the one-body deck carries the whole load
/// (equilibrium).
#[test]
fn tied_cantilever_deck_deflects_as_one_body() {
    let dir = scratch("cantilever");
    let one = Analysis::new(Model::from_file(&cantilever(&dir, false), 1).unwrap()).unwrap();
    let two = Analysis::new(Model::from_file(&cantilever(&dir, true), 1).unwrap()).unwrap();
    assert_eq!(two.model.parts.len(), 2);
    assert_eq!(two.interfaces[0].law, cfe::Law::Rigid);
    assert_eq!(two.interfaces[0].elements.len(), 5);
    assert!(two.model.notes.iter().any(|n| n.contains("*DENSITY")));
    assert!(two.model.notes.iter().any(|n| n.contains("*NODE PRINT")));
    let tip = |a: &Analysis, part: &str| {
        let incs = common::solve(a);
        common::displacement_at(a, incs.last().unwrap(), part, [10.0, 0.5])[1]
    };
    let (d1, d2) = (tip(&one, "BEAM"), tip(&two, "ARM"));
    assert!(d1 < 0.0);
    assert!((d1 - d2).abs() < 1e-4 * d1.abs(), "{d1} vs {d2}");
    let res = common::solve_completed(&one);
    let reaction: f64 = res.summary.reactions.iter().map(|r| r.fy).sum();
    assert!((reaction.abs() - 100.0).abs() < 1e-6 * 100.0, "{reaction}");
}

/// A block with its bottom clamped, loaded in two *STEPs — a downward *CLOAD
/// and a *DLOAD pressure on its top in step 1; in step 2 the *CLOAD changed
/// (OP=MOD: the new value replaces the old) and a sideways one added — ends
/// each step on the one-step solution of the loads then in force (a linear
/// model superposes, to round-off); the pressure's resultant is P × t × the
/// face's length.
#[test]
fn steps_deck_superposes() {
    let head = "*NODE\n1, 0., 0.\n2, 1., 0.\n3, 2., 0.\n4, 0., 1.\n5, 1., 1.\n6, 2., 1.\n\
        *ELEMENT, TYPE=CPE4, ELSET=BLOCK\n1, 1, 2, 5, 4\n2, 2, 3, 6, 5\n\
        *MATERIAL, NAME=M\n*ELASTIC\n1000., 0.25\n*SOLID SECTION, ELSET=BLOCK, MATERIAL=M\n0.5\n\
        *BOUNDARY\n1, 1, 2\n2, 1, 2\n3, 1, 2\n";
    let two_steps = format!(
        "{head}*STEP, NAME=press\n*STATIC\n0.5, 1.\n*CLOAD\n6, 2, -3.\n*DLOAD\nBLOCK, P3, 4.\n*END STEP\n\
         *STEP, NAME=shear\n*STATIC\n1., 3.\n*CLOAD\n6, 2, -5.\n5, 1, 2.\n*END STEP\n"
    );
    let one_step = |loads: &str| {
        format!("{head}*STEP\n*STATIC\n*CLOAD\n{loads}*DLOAD\nBLOCK, P3, 4.\n*END STEP\n")
    };
    let a = Analysis::new(deck(&two_steps).unwrap()).unwrap();
    assert_eq!(a.model.steps.len(), 2);
    assert_eq!(a.model.steps[0].increments, 2);
    assert_eq!(a.model.steps[1].increments, 3);
    // The pressure: 4 × t (0.5) × length 2, downward on the top face.
    let p: Vec<_> = a
        .model
        .loads
        .iter()
        .filter(|l| l.name.starts_with("*DLOAD"))
        .collect();
    assert_eq!(p.len(), 1);
    assert!(p[0].resultant[0].abs() < 1e-12 && (p[0].resultant[1] + 4.0).abs() < 1e-12);
    let incs = common::solve(&a);
    assert_eq!(incs.len(), 5);
    let end = |text: String| {
        let b = Analysis::new(deck(&text).unwrap()).unwrap();
        common::solve(&b).pop().unwrap().u
    };
    let first = end(one_step("6, 2, -3.\n"));
    let last = end(one_step("6, 2, -5.\n5, 1, 2.\n"));
    for (u, v) in [(&incs[1].u, &first), (&incs[4].u, &last)] {
        let scale = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let diff = u
            .iter()
            .zip(v.iter())
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-10 * scale, "{diff:e}");
    }
}

/// The base deck of the error cases: a block (one CPS4) tied on a base (one
/// CPS4), the base's bottom clamped, the block's corner loaded. Line numbers
/// as commented.
const BASE: &str = "*HEADING
block on a base
*NODE, NSET=NBASE
1, 0., 0.
2, 2., 0.
3, 2., 1.
4, 0., 1.
*NODE, NSET=NBLOCK
11, 0.5, 1.
12, 1.5, 1.
13, 1.5, 2.
14, 0.5, 2.
*ELEMENT, TYPE=CPS4, ELSET=BASE
1, 1, 2, 3, 4
*ELEMENT, TYPE=CPS4, ELSET=BLOCK
11, 11, 12, 13, 14
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=BASE, MATERIAL=STEEL
1.
*SOLID SECTION, ELSET=BLOCK, MATERIAL=STEEL
1.
*SURFACE, NAME=BASE_TOP
BASE, S3
*SURFACE, NAME=BLOCK_BOTTOM
BLOCK, S1
*TIE, NAME=GLUE
BLOCK_BOTTOM, BASE_TOP
*BOUNDARY
1, 1, 2
2, 1, 2
*STEP
*STATIC
*CLOAD
13, 2, -10.
*END STEP
";

/// BASE with line `line` (1-based) replaced by `with` (which may span lines).
fn with_line(line: usize, with: &str) -> String {
    BASE.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == line { with } else { l })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// The base deck is valid: two parts tied, one support, one load.
#[test]
fn base_deck_is_valid() {
    let m = deck(BASE).unwrap();
    assert_eq!(m.parts.len(), 2);
    assert_eq!(m.interfaces[0].law, cfe::Law::Rigid);
    // One support per *BOUNDARY line (nodes 1 and 2), one load per *CLOAD card.
    assert_eq!(m.supports.len(), 2);
    assert_eq!(m.loads.len(), 1);
    let a = Analysis::new(m).unwrap();
    let res = common::solve_completed(&a);
    let reaction: f64 = res.summary.reactions.iter().map(|r| r.fy).sum();
    assert!((reaction.abs() - 10.0).abs() < 1e-9, "{reaction}");
}

/// Every construct outside the subset and every malformed line is an
/// [`Error::Deck`] of the right kind, naming its line and keyword.
#[test]
fn unsupported_and_malformed_lines_are_typed_errors_with_their_line() {
    use DeckFault::*;
    let cases: Vec<(String, DeckFault, usize, &str, &str)> = vec![
        (
            with_line(19, "210000., 0.3\n*PLASTIC\n250., 0."),
            Unsupported,
            20,
            "*PLASTIC",
            "linear elastic",
        ),
        (
            with_line(13, "*ELEMENT, TYPE=C3D8, ELSET=BASE"),
            Unsupported,
            13,
            "*ELEMENT",
            "C3D8",
        ),
        (
            with_line(13, "*ELEMENT, TYPE=CAX4, ELSET=BASE"),
            Conflict,
            16,
            "*ELEMENT",
            "axisymmetric (CAX)",
        ),
        (
            with_line(28, "*TIE, NAME=GLUE, ADJUST=NO"),
            Unsupported,
            28,
            "*TIE",
            "ADJUST=NO",
        ),
        (
            with_line(28, "*TIE, NAME=GLUE, POSITION TOLERANCE=0.1"),
            Unsupported,
            28,
            "*TIE",
            "POSITION TOLERANCE",
        ),
        (
            with_line(1, "*ASSEMBLY, NAME=A1"),
            Unsupported,
            1,
            "*ASSEMBLY",
            "flattened",
        ),
        (
            with_line(1, "*INSTANCE, NAME=I1, PART=P1\n1., 0., 0."),
            Unsupported,
            1,
            "*INSTANCE",
            "flattened",
        ),
        (
            with_line(13, "*ELEMENT, TYPE=CPS4R, ELSET=BASE"),
            Unsupported,
            13,
            "*ELEMENT",
            "reduced integration",
        ),
        (
            with_line(14, "1, 1, 2, 3"),
            Malformed,
            14,
            "*ELEMENT",
            "4 nodes",
        ),
        (with_line(4, "1, 0., abc"), Malformed, 4, "*NODE", "`abc`"),
        (
            with_line(4, "1, 0., 0., 5."),
            Unsupported,
            4,
            "*NODE",
            "two-dimensional",
        ),
        (
            with_line(5, "1, 2., 0."),
            Conflict,
            5,
            "*NODE",
            "second time",
        ),
        (
            with_line(20, "*SOLID SECTION, ELSET=BASE, MATERIAL=IRON"),
            Undefined,
            20,
            "*SOLID SECTION",
            "IRON",
        ),
        (
            with_line(20, "*SOLID SECTION, ELSET=BASEX, MATERIAL=STEEL"),
            Undefined,
            20,
            "*SOLID SECTION",
            "BASEX",
        ),
        (
            with_line(
                20,
                "*SOLID SECTION, ELSET=BASE, MATERIAL=STEEL, ORIENTATION=OR1",
            ),
            Unsupported,
            20,
            "*SOLID SECTION",
            "ORIENTATION",
        ),
        (with_line(25, "BASE, S7"), Unsupported, 25, "*SURFACE", "S7"),
        (
            with_line(29, "BLOCK_BOTTOM, NOPE"),
            Undefined,
            29,
            "*TIE",
            "NOPE",
        ),
        (
            with_line(29, "BLOCK_BOTTOM, BLOCK_BOTTOM"),
            Conflict,
            29,
            "*TIE",
            "same body",
        ),
        (
            with_line(31, "1, 1, 6"),
            Unsupported,
            31,
            "*BOUNDARY",
            "DOFs 1 to 6",
        ),
        (
            with_line(31, "NOSUCH, 1, 2"),
            Undefined,
            31,
            "*BOUNDARY",
            "NOSUCH",
        ),
        (
            with_line(36, "13, 2, -10., 4"),
            Malformed,
            36,
            "*CLOAD",
            "4 fields",
        ),
        (
            with_line(36, "13, 5, -10."),
            Unsupported,
            36,
            "*CLOAD",
            "DOF 5",
        ),
        (
            with_line(36, "13, 2, -10.\n13, 2, -20."),
            Conflict,
            37,
            "*CLOAD",
            "second time",
        ),
        (
            with_line(33, "*STEP, NLGEOM"),
            Unsupported,
            33,
            "*STEP",
            "geometrically linear",
        ),
        (
            with_line(34, "*DYNAMIC"),
            Unsupported,
            34,
            "*DYNAMIC",
            "static",
        ),
        (
            with_line(34, "*STATIC\n0., 1."),
            Malformed,
            35,
            "*STATIC",
            "positive",
        ),
        (
            with_line(35, "*CLOAD, AMPLITUDE=A1"),
            Unsupported,
            35,
            "*CLOAD",
            "AMPLITUDE",
        ),
        (
            with_line(36, "13, 2, -10.\n*DLOAD\n11, BX, 5."),
            Unsupported,
            38,
            "*DLOAD",
            "body forces",
        ),
        (
            with_line(12, "14, 0.5, 2.\n*INCLUDE, INPUT=missing.inp"),
            Include,
            13,
            "*INCLUDE",
            "missing.inp",
        ),
        (
            with_line(16, "11, 1, 12, 13, 14"),
            Conflict,
            22,
            "*SOLID SECTION",
            "node 1",
        ),
        (
            with_line(37, "** no end"),
            Malformed,
            33,
            "*STEP",
            "*END STEP",
        ),
        (
            with_line(13, "*ELEMENT, TYPE=CPE4, ELSET=BASE"),
            Conflict,
            16,
            "*ELEMENT",
            "one plane kind",
        ),
        (
            with_line(30, "*EQUATION"),
            Unsupported,
            30,
            "*EQUATION",
            "constraint",
        ),
        (
            with_line(1, "*PART, NAME=P1"),
            Unsupported,
            1,
            "*PART",
            "flattened",
        ),
        (
            with_line(24, "*SURFACE, NAME=BASE_TOP, TYPE=CUTTING SURFACE"),
            Unsupported,
            24,
            "*SURFACE",
            "TYPE",
        ),
        (
            with_line(1, "1, 2, 3"),
            Malformed,
            1,
            "data line",
            "before any keyword",
        ),
        (
            with_line(17, "** no material"),
            Malformed,
            18,
            "*ELASTIC",
            "*MATERIAL",
        ),
        (
            with_line(28, "*CONTACT PAIR, INTERACTION=SI"),
            Undefined,
            29,
            "*CONTACT PAIR",
            "SI",
        ),
        (
            with_line(28, "*CONTACT PAIR"),
            Malformed,
            28,
            "*CONTACT PAIR",
            "INTERACTION",
        ),
        (
            with_line(33, "*STEP\n*STATIC\n*END STEP\n*STEP"),
            Unsupported,
            39,
            "*BOUNDARY",
            "every step",
        ),
    ];
    assert!(cases.len() >= 20);
    for (text, fault, line, keyword, words) in &cases {
        let text = if *words == "every step" {
            // A support first given in the second step.
            text.replace(
                "*CLOAD\n13, 2, -10.\n",
                "*BOUNDARY\n13, 1\n*CLOAD\n13, 2, -10.\n",
            )
        } else {
            text.clone()
        };
        match deck(&text) {
            Err(Error::Deck {
                fault: f,
                line: l,
                keyword: k,
                message,
                ..
            }) => {
                assert!(
                    f == *fault && l == *line && k == *keyword && message.contains(words),
                    "expected {fault:?} at line {line} ({keyword}, `{words}`), got {f:?} at line {l} ({k}): {message}"
                );
                assert!(message.contains(&format!("line {line}")), "{message}");
            }
            other => panic!("expected {fault:?} at line {line} ({keyword}), got {other:?}"),
        }
    }
}

/// A value the shared checks refuse (a negative E) is told at the deck line
/// it came from (the *ELASTIC data line), with the converted model's key.
#[test]
fn builder_errors_name_the_deck_line() {
    match deck(&with_line(19, "-210000., 0.3")) {
        Err(Error::Invalid {
            line, key, path, ..
        }) => {
            assert_eq!(line, Some(19));
            assert_eq!(key, "materials.STEEL.E");
            assert_eq!(path, Path::new("problem.inp"));
        }
        other => panic!("expected an invalid E, got {other:?}"),
    }
}

/// *INCLUDE nesting is depth-limited (a file including itself), only regular
/// files are read, and a deck refuses the refinement factor 0.
#[test]
fn includes_are_bounded_and_refinement_zero_refused() {
    let dir = scratch("include");
    let me = dir.join("self.inp");
    std::fs::write(&me, "*INCLUDE, INPUT=self.inp\n").unwrap();
    match Model::from_inp(&me) {
        Err(Error::Deck { fault, .. }) => assert_eq!(fault, DeckFault::Include),
        other => panic!("{other:?}"),
    }
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    let text = "*INCLUDE, INPUT=sub\n";
    match Model::from_inp_str(text, &dir.join("d.inp")) {
        Err(Error::Deck { fault, message, .. }) => {
            assert_eq!(fault, DeckFault::Include);
            assert!(message.contains("not a regular file"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let path = dir.join("base.inp");
    std::fs::write(&path, BASE).unwrap();
    assert!(matches!(Model::from_file(&path, 0), Err(Error::Model(_))));
    assert!(Model::from_file(&path, 1).unwrap().with_refine(1).is_ok());
}

/// The axisymmetric twin of [`AXI_DECK`] as a problem file: the same meshes
/// (built-in rectangles numbered as the deck numbers them), penalty, supports
/// and loads.
const AXI_TOML: &str = r#"
plane = "axisymmetric"
[materials.STEEL]
E = 210000.0
nu = 0.3
[materials.SOFT]
E = 70000.0
nu = 0.33
[[part]]
name = "BASE"
material = "SOFT"
rectangle = { x = [0.0, 4.0], y = [-2.0, 0.0], cells = [4, 2], elements = "q4" }
[[part]]
name = "PUNCH"
material = "STEEL"
rectangle = { x = [0.0, 1.0], y = [0.0, 1.0], cells = [2, 2], elements = "t3" }
[[interface]]
host = "BASE"
nodes = "PUNCH"
boundary = "bottom"
law = "frictionless"
c_n = 1000000.0
[[support]]
part = "BASE"
boundary = "bottom"
fix = ["x", "y"]
[[load]]
part = "PUNCH"
at = [0.0, 1.0]
force = [0.0, -90.0]
[[load]]
part = "PUNCH"
boundary = "top"
pressure = 30.0
[analysis]
increments = 1
"#;

/// An axisymmetric deck as a CalculiX user writes it: a CAX3 punch (r ≤ 1) on
/// a CAX4 base, node-to-surface contact with a LINEAR pressure-overclosure,
/// a point force on the axis (a total over the ring, as CalculiX reads it) and a
/// pressure on the punch's top.
const AXI_DECK: &str = "*HEADING
axisymmetric punch on a base
*NODE, NSET=NBASE
1, 0., -2.
2, 1., -2.
3, 2., -2.
4, 3., -2.
5, 4., -2.
6, 0., -1.
7, 1., -1.
8, 2., -1.
9, 3., -1.
10, 4., -1.
11, 0., 0.
12, 1., 0.
13, 2., 0.
14, 3., 0.
15, 4., 0.
*NODE
101, 0., 0.
102, 0.5, 0.
103, 1., 0.
104, 0., 0.5
105, 0.5, 0.5
106, 1., 0.5
107, 0., 1.
108, 0.5, 1.
109, 1., 1.
*ELEMENT, TYPE=CAX4, ELSET=BASE
1, 1, 2, 7, 6
2, 2, 3, 8, 7
3, 3, 4, 9, 8
4, 4, 5, 10, 9
5, 6, 7, 12, 11
6, 7, 8, 13, 12
7, 8, 9, 14, 13
8, 9, 10, 15, 14
*ELEMENT, TYPE=CAX3, ELSET=PUNCH
101, 101, 102, 105
102, 101, 105, 104
103, 102, 103, 106
104, 102, 106, 105
105, 104, 105, 108
106, 104, 108, 107
107, 105, 106, 109
108, 105, 109, 108
*ELSET, ELSET=PTOP
106, 108
*ELSET, ELSET=PBOTTOM
101, 103
*ELSET, ELSET=BTOP
5, 6, 7, 8
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*MATERIAL, NAME=SOFT
*ELASTIC
70000., 0.33
*SOLID SECTION, ELSET=BASE, MATERIAL=SOFT
*SOLID SECTION, ELSET=PUNCH, MATERIAL=STEEL
1.
*SURFACE, NAME=BASE_TOP
BTOP, S3
*SURFACE, NAME=PUNCH_BOTTOM
PBOTTOM, S1
*SURFACE INTERACTION, NAME=HARDISH
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR
2.E6
*CONTACT PAIR, INTERACTION=HARDISH
PUNCH_BOTTOM, BASE_TOP
*BOUNDARY
1, 1, 2
2, 1, 2
3, 1, 2
4, 1, 2
5, 1, 2
*STEP
*STATIC
*CLOAD
107, 2, -90.
*DLOAD
PTOP, P2, 30.
*END STEP
";

/// CAX3/CAX4 decks (issue 40): the axisymmetric deck gives its TOML twin's
/// model — the same meshes, plane, penalty (the LINEAR slope × the mean slave
/// edge, per unit circumference: 2e6 × 0.5 = 1e6), loads (the *CLOAD the ring's
/// total, 90, as CalculiX reads it; the *DLOAD pressure integrated with 2πr),
/// the note saying so — and the same displacements to round-off (1e-12 of the largest);
/// the base's reaction balances the loads' z resultant (90 + 30 π 1²).
#[test]
fn axisymmetric_deck_matches_its_toml_twin() {
    let toml = Analysis::new(Model::from_str(AXI_TOML, Path::new("axi.toml"), 1).unwrap()).unwrap();
    let inp = Analysis::new(deck(AXI_DECK).unwrap()).unwrap();
    assert_eq!(inp.model.parts.len(), 2);
    for (a, b) in toml.model.parts.iter().zip(&inp.model.parts) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.mesh.nodes, b.mesh.nodes, "{}", b.name);
        assert_eq!(a.mesh.elements, b.mesh.elements, "{}", b.name);
        assert_eq!(a.material.plane, cfe::fem::PlaneKind::Axisymmetric);
        assert_eq!(a.material.plane, b.material.plane);
        assert_eq!(a.material.thickness, b.material.thickness);
    }
    assert_eq!(toml.interfaces[0].c_n, inp.interfaces[0].c_n);
    assert_eq!(inp.interfaces[0].law, cfe::Law::Frictionless);
    assert!(
        inp.model
            .notes
            .iter()
            .any(|n| n.contains("*CLOAD") && n.contains("total over the ring's circumference"))
    );
    let total = |a: &Analysis| -> f64 { a.model.loads.iter().map(|l| l.resultant[1]).sum() };
    let want = -(90.0 + 30.0 * std::f64::consts::PI);
    assert!((total(&toml) - want).abs() < 1e-12 * want.abs());
    assert!((total(&inp) - want).abs() < 1e-12 * want.abs());
    let (ra, rb) = (
        common::solve_completed(&toml),
        common::solve_completed(&inp),
    );
    let scale = ra.last.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(scale > 0.0);
    let diff = ra
        .last
        .u
        .iter()
        .zip(&rb.last.u)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!("axisymmetric deck against TOML: largest difference {diff:e} of {scale:e}");
    assert!(diff <= 1e-12 * scale, "{diff:e}");
    let reaction: f64 = rb.summary.reactions.iter().map(|r| r.fy).sum();
    assert!((reaction + want).abs() < 1e-9 * want.abs(), "{reaction}");
}

/// `--refine K` on a deck (issue 40): a plane-strain block (2 × 1, two CPE4,
/// t = 0.5) clamped along its bottom by a node set, a *CLOAD at a corner and a
/// *DLOAD on its top, refined 1, 2 and 3 times, gives at every node the
/// displacement of the same block meshed by the built-in rectangle with K× the
/// cells (its twin, the node matched by position) to round-off (1e-10 of the
/// largest): the refined clamp holds the new nodes of its face, the pressure
/// acts on the refined top, the point force stays on its node — also when the
/// clamp is written node by node, one *BOUNDARY line each; and `with_refine`
/// gives the same model as reading at that factor.
#[test]
fn deck_refined_matches_the_refined_rectangle() {
    let text = "*NODE, NSET=ALL\n1, 0., 0.\n2, 1., 0.\n3, 2., 0.\n4, 0., 1.\n5, 1., 1.\n6, 2., 1.\n\
        *NSET, NSET=CLAMP\n1, 2, 3\n\
        *ELEMENT, TYPE=CPE4, ELSET=BLOCK\n1, 1, 2, 5, 4\n2, 2, 3, 6, 5\n\
        *MATERIAL, NAME=M\n*ELASTIC\n1000., 0.25\n*SOLID SECTION, ELSET=BLOCK, MATERIAL=M\n0.5\n\
        *BOUNDARY\nCLAMP, 1, 2\n\
        *STEP\n*STATIC\n*CLOAD\n6, 2, -3.\n6, 1, 1.\n*DLOAD\nBLOCK, P3, 4.\n*END STEP\n";
    let dir = scratch("refine");
    for (file, text) in [
        ("block.inp", text.to_string()),
        (
            "by_node.inp",
            text.replace("CLAMP, 1, 2\n", "1, 1, 2\n2, 1, 2\n3, 1, 2\n"),
        ),
    ] {
        let path = dir.join(file);
        std::fs::write(&path, &text).unwrap();
        for k in 1..=3usize {
            let twin = format!(
                "plane = \"strain\"\n[materials.M]\nE = 1000.0\nnu = 0.25\n[[part]]\nname = \"BLOCK\"\nmaterial = \"M\"\nthickness = 0.5\nrectangle = {{ x = [0.0, 2.0], y = [0.0, 1.0], cells = [{}, {}], elements = \"q4\" }}\n[[support]]\npart = \"BLOCK\"\nboundary = \"bottom\"\nfix = [\"x\", \"y\"]\n[[load]]\npart = \"BLOCK\"\nat = [2.0, 1.0]\nforce = [1.0, -3.0]\n[[load]]\npart = \"BLOCK\"\nboundary = \"top\"\npressure = 2.0\n[analysis]\nincrements = 1\n",
                2 * k,
                k
            );
            let a =
                Analysis::new(Model::from_str(&twin, Path::new("twin.toml"), 1).unwrap()).unwrap();
            let model = Model::from_file(&path, k).unwrap();
            assert_eq!(model.refine, k);
            let again = Model::from_file(&path, 1).unwrap().with_refine(k).unwrap();
            assert_eq!(again.parts[0].mesh.nodes, model.parts[0].mesh.nodes);
            assert!(
                again
                    .supports
                    .iter()
                    .map(|s| &s.nodes)
                    .eq(model.supports.iter().map(|s| &s.nodes))
            );
            let b = Analysis::new(model).unwrap();
            assert_eq!(b.model.parts[0].mesh.elements.len(), 2 * k * k);
            let held: usize = b.model.supports.iter().map(|s| s.nodes.len()).sum();
            assert_eq!(held, 2 * k + 1);
            let (ua, ub) = (common::solve(&a), common::solve(&b));
            let (ua, ub) = (&ua.last().unwrap().u, &ub.last().unwrap().u);
            let scale = ua.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let (ma, mb) = (&a.model.parts[0].mesh, &b.model.parts[0].mesh);
            assert_eq!(ma.nodes.len(), mb.nodes.len());
            let mut worst: f64 = 0.0;
            for (n, x) in mb.nodes.iter().enumerate() {
                let m = ma
                    .nodes
                    .iter()
                    .position(|y| (y[0] - x[0]).abs() < 1e-12 && (y[1] - x[1]).abs() < 1e-12)
                    .expect("the twin has a node here");
                let (ga, gb) = (a.dofs.node(0, m), b.dofs.node(0, n));
                for c in 0..2 {
                    worst = worst.max((ua[2 * ga + c] - ub[2 * gb + c]).abs());
                }
            }
            assert!(
                worst <= 1e-10 * scale,
                "{file}, refine {k}: {worst:e} of {scale:e}"
            );
        }
    }
}

/// A CAX4 ring (1 ≤ r ≤ 2, 0 ≤ z ≤ 1, 4 × 2 elements, E = 210000, ν = 0.3) on
/// rollers at z = 0, pressed on its top by p = 100 given two ways: a *DLOAD
/// pressure, and *CLOADs of the ring totals of that pressure's consistent
/// nodal forces (f_a = p L 2π (2r_a + r_b)/6 per edge, summing to p π (2² − 1²)).
/// The state is uniaxial, so both decks give the closed form at every node:
/// u_z = −p z / E, u_r = ν p r / E (to 1e-9 of the largest). The rule this
/// checks: CalculiX reads an axisymmetric *CLOAD as the total over the ring's
/// circumference (not per 2° segment) and a *DLOAD as a pressure. CalculiX 2.20
/// on these two decks (run by hand, `ccx`) gives u_z(top) = −4.761905e-4 with
/// the *DLOAD and −4.762872e-4 with the *CLOADs, and with the *CLOADs divided
/// by 180 a displacement 180 × smaller (−2.646e-6); the closed form is
/// −4.761905e-4.
#[test]
fn axisymmetric_cload_is_the_ring_total_as_calculix_reads_it() {
    use std::fmt::Write;
    let (nr, nz, p, e, nu) = (4usize, 2usize, 100.0, 210_000.0, 0.3);
    let id = |i: usize, j: usize| 1 + j * (nr + 1) + i;
    let x = |i: usize, j: usize| [1.0 + i as f64 / nr as f64, j as f64 / nz as f64];
    let mut head = String::from("*NODE, NSET=NALL\n");
    for j in 0..=nz {
        for i in 0..=nr {
            let [r, z] = x(i, j);
            writeln!(head, "{}, {r}, {z}", id(i, j)).unwrap();
        }
    }
    head += "*ELEMENT, TYPE=CAX4, ELSET=EALL\n";
    for j in 0..nz {
        for i in 0..nr {
            let n = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            writeln!(
                head,
                "{}, {}, {}, {}, {}",
                j * nr + i + 1,
                n[0],
                n[1],
                n[2],
                n[3]
            )
            .unwrap();
        }
    }
    let bottom: Vec<String> = (0..=nr).map(|i| id(i, 0).to_string()).collect();
    write!(
        head,
        "*NSET, NSET=BOT\n{}\n*MATERIAL, NAME=STEEL\n*ELASTIC\n{e}, {nu}\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nBOT, 2, 2\n*STEP\n*STATIC\n",
        bottom.join(", ")
    )
    .unwrap();
    let mut dload = head.clone() + "*DLOAD\n";
    for i in 0..nr {
        // S3 of a CAX4 is its face from corner 3 to corner 4: the top.
        writeln!(dload, "{}, P3, {p}", (nz - 1) * nr + i + 1).unwrap();
    }
    let mut forces = vec![0.0; nr + 1];
    for i in 0..nr {
        let (ra, rb) = (x(i, nz)[0], x(i + 1, nz)[0]);
        let l = rb - ra;
        forces[i] += p * l * std::f64::consts::TAU * (2.0 * ra + rb) / 6.0;
        forces[i + 1] += p * l * std::f64::consts::TAU * (ra + 2.0 * rb) / 6.0;
    }
    let total: f64 = forces.iter().sum();
    assert!((total - p * std::f64::consts::PI * 3.0).abs() < 1e-12 * total);
    let mut cload = head + "*CLOAD\n";
    for (i, f) in forces.iter().enumerate() {
        writeln!(cload, "{}, 2, {}", id(i, nz), -f).unwrap();
    }
    for text in [dload, cload] {
        let a = Analysis::new(deck(&(text + "*END STEP\n")).unwrap()).unwrap();
        let res = common::solve_completed(&a);
        let mesh = &a.model.parts[0].mesh;
        let largest = p / e * 2.0;
        for (n, &[r, z]) in mesh.nodes.iter().enumerate() {
            let g = a.dofs.node(0, n);
            let (ur, uz) = (res.last.u[2 * g], res.last.u[2 * g + 1]);
            assert!(
                (uz + p * z / e).abs() < 1e-9 * largest,
                "node at ({r}, {z}): u_z {uz}"
            );
            assert!(
                (ur - nu * p * r / e).abs() < 1e-9 * largest,
                "node at ({r}, {z}): u_r {ur}"
            );
        }
    }
}

/// CalculiX's face numbers on axisymmetric elements (S1–S4 of a CAX4: corners
/// 1–2, 2–3, 3–4, 4–1; S1–S3 of a CAX3: 1–2, 2–3, 3–1): a ring 1 ≤ r ≤ 2,
/// 0 ≤ z ≤ 1 of 2 × 2 CAX4 (or each square split into two CAX3, (a, b, c) and
/// (a, c, d)), held in z at one node, with p = 1 by *DLOAD on every outer face
/// through each face number, is under hydrostatic pressure: u = −p (1 − 2ν)/E x
/// at every node, to 1e-12 of the largest (the linear field both elements hold
/// exactly). A face read as another would load an edge inside or leave one
/// bare. CalculiX 2.20 on these decks (run by hand) loads the same faces: 1.5e-4
/// of the closed form with CAX4, 6.9e-2 with CAX3 (its expansion into a 2°
/// wedge of C3D6).
#[test]
fn axisymmetric_face_numbers_are_calculix_s() {
    use std::fmt::Write;
    let (n, e, nu) = (2usize, 1000.0, 0.3f64);
    let id = |i: usize, j: usize| 1 + j * (n + 1) + i;
    for kind in ["CAX4", "CAX3"] {
        let mut text = String::from("*NODE, NSET=NALL\n");
        for j in 0..=n {
            for i in 0..=n {
                let (r, z) = (1.0 + i as f64 / n as f64, j as f64 / n as f64);
                writeln!(text, "{}, {r}, {z}", id(i, j)).unwrap();
            }
        }
        let (mut elements, mut faces) = (String::new(), String::new());
        let mut count = 0;
        for j in 0..n {
            for i in 0..n {
                let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                // (element, its corners, [bottom, right, top, left] face numbers).
                let cells: Vec<(Vec<usize>, [Option<u8>; 4])> = if kind == "CAX4" {
                    vec![(vec![a, b, c, d], [Some(1), Some(2), Some(3), Some(4)])]
                } else {
                    vec![
                        (vec![a, b, c], [Some(1), Some(2), None, None]),
                        (vec![a, c, d], [None, None, Some(2), Some(3)]),
                    ]
                };
                for (corners, s) in cells {
                    count += 1;
                    let list: Vec<String> = corners.iter().map(|c| c.to_string()).collect();
                    writeln!(elements, "{count}, {}", list.join(", ")).unwrap();
                    let outer = [j == 0, i == n - 1, j == n - 1, i == 0];
                    for (side, face) in outer.iter().zip(s) {
                        if let (true, Some(f)) = (side, face) {
                            writeln!(faces, "{count}, P{f}, 1.").unwrap();
                        }
                    }
                }
            }
        }
        write!(
            text,
            "*ELEMENT, TYPE={kind}, ELSET=EALL\n{elements}*MATERIAL, NAME=M\n*ELASTIC\n{e}, {nu}\n*SOLID SECTION, ELSET=EALL, MATERIAL=M\n*BOUNDARY\n1, 2, 2\n*STEP\n*STATIC\n*DLOAD\n{faces}*END STEP\n"
        )
        .unwrap();
        let a = Analysis::new(deck(&text).unwrap()).unwrap();
        let res = common::solve_completed(&a);
        let k = -(1.0 - 2.0 * nu) / e;
        let largest = 2.0 * k.abs();
        for (node, x) in a.model.parts[0].mesh.nodes.iter().enumerate() {
            let g = a.dofs.node(0, node);
            for c in 0..2 {
                let u = res.last.u[2 * g + c];
                assert!(
                    (u - k * x[c]).abs() < 1e-12 * largest,
                    "{kind} node at {x:?}: u[{c}] {u}"
                );
            }
        }
    }
}
