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
            Unsupported,
            13,
            "*ELEMENT",
            "axisymmetric",
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
/// files are read, and a deck refuses refinement.
#[test]
fn includes_are_bounded_and_refinement_refused() {
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
    assert!(matches!(Model::from_file(&path, 2), Err(Error::Model(_))));
    assert!(Model::from_file(&path, 1).unwrap().with_refine(1).is_ok());
}
