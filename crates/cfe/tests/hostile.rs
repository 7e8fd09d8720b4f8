//! Hostile input: every bad value of a problem file is refused where it is read
//! with a typed error naming the file, the line and the key (and the reason), and
//! numbers double precision cannot carry are named as overflow or loss of
//! precision — never a panic, a silent acceptance or a vague "mechanism". Each
//! case asserts the error's variant, its key and line, and the message's key words.

mod common;

use cfe::Error;
use cfe::model::Model;
use common::{Problem, Raw, Text};
use std::path::Path;

/// A valid problem (the seed's plate on a base, coarsened) that every case spoils
/// in one place.
static BASE: Text = Text::new(|| {
    Problem::spaced()
        .no_leading_newline()
        .head("title", "hostile")
        .material("steel", 210000.0, 0.31)
        .material("soft", 1000.0, 0.2)
        .part("base", "steel")
        .key("thickness", 1.0)
        .rectangle([0.0, 200.0], [0.0, 120.0], [10, 6])
        .part("plate", "steel")
        .key("thickness", 1.0)
        .rectangle([30.0, 170.0], [120.0, 135.0], [14, 3])
        .part("ring", "soft")
        .key(
            "annulus",
            Raw("{ center = [500.0, 0.0], r = [10.0, 20.0], theta = [0.0, 90.0], cells = [2, 4] }"),
        )
        .named_interface("plate-base", "base", "plate", "bottom")
        .key("c_n", Raw("1e9"))
        .key("c_s", Raw("1e9"))
        .key("tolerance", 0.05)
        .support("base", "bottom", ["x", "y"])
        .key("value", [0.0, 0.0])
        .support("ring", "inner", ["x", "y"])
        .plate_load_down()
        .table("[[load]]")
        .key("part", "ring")
        .key("at", [520.0, 0.0])
        .key("force", [1.0, 0.0])
        .increments(10)
        .key("max_iterations", 200)
        .key("gap_tolerance", Raw("1e-9"))
        .key("force_tolerance", Raw("1e-6"))
        .key("max_violation", 0.05)
        .key("max_residual", Raw("1e-4"))
        .key("output_every", 1)
        .text()
});

/// The error of `text` at refinement `refine`.
fn error(text: &str, refine: usize) -> Error {
    match Model::from_str(text, Path::new("hostile.toml"), refine) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// The kinds of error a case expects.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// `Error::Invalid` with this key.
    Invalid(&'static str),
    /// `Error::Overflow` with this key.
    Overflow(&'static str),
    /// `Error::PenaltyPrecision` with this key.
    Precision(&'static str),
    /// `Error::Parse` (schema, names, selections) with a line.
    Parse,
    /// `Error::TooLarge`.
    TooLarge,
    /// `Error::DuplicateName` with this key.
    Duplicate(&'static str),
    /// `Error::WeakPenalty` with this key.
    Weak(&'static str),
}

/// Checks `e` against `kind`: the variant, the key, and that the line it names
/// holds that key in `text`; then that the message holds every word of `words`.
fn assert_error(case: &str, text: &str, e: &Error, kind: Kind, words: &[&str]) {
    let line_of = |line: &Option<usize>| -> &str {
        let l = line.unwrap_or_else(|| panic!("{case}: no line in {e:?}"));
        text.lines().nth(l - 1).unwrap_or("")
    };
    // The last plain segment of a dotted key (`part.base.rectangle.x` → `x`).
    let last = |key: &str| key.rsplit('.').next().unwrap_or("").to_string();
    match (kind, e) {
        (Kind::Invalid(k), Error::Invalid { key, line, .. })
        | (Kind::Overflow(k), Error::Overflow { key, line, .. })
        | (Kind::Precision(k), Error::PenaltyPrecision { key, line, .. })
        | (Kind::Duplicate(k), Error::DuplicateName { key, line, .. })
        | (Kind::Weak(k), Error::WeakPenalty { key, line, .. }) => {
            assert_eq!(key, k, "{case}: {e}");
            let l = line_of(line);
            assert!(l.contains(&last(k)), "{case}: line '{l}' lacks {k}: {e}");
        }
        (Kind::Parse, Error::Parse { line, .. }) => {
            line_of(line);
        }
        (Kind::TooLarge, Error::TooLarge { .. }) => {}
        _ => panic!("{case}: expected {kind:?}, got {e:?}"),
    }
    let msg = e.to_string();
    for w in words {
        assert!(msg.contains(w), "{case}: message lacks '{w}': {msg}");
    }
}

/// `BASE` with the first `from` replaced by `to` (which must occur).
fn with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "{from}");
    BASE.replacen(from, to, 1)
}

/// The base problem is valid: the cases below fail because of their one change.
#[test]
fn the_base_problem_is_valid() {
    Model::from_str(&BASE, Path::new("hostile.toml"), 1).unwrap();
}

/// Every value class: non-finite, out of physical range, beyond what double
/// precision carries, wrong shape, dangling name, oversized. 70 cases.
#[test]
fn hostile_values_are_refused_with_file_line_and_key() {
    use Kind::*;
    let e_line = "E = 210000.0";
    let t_line = "thickness = 1.0\nrectangle = { x = [0.0, 200.0]";
    let t_rest = "\nrectangle = { x = [0.0, 200.0]";
    let rect = "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [10, 6] }";
    let ann = "annulus = { center = [500.0, 0.0], r = [10.0, 20.0], theta = [0.0, 90.0], cells = [2, 4] }";
    let cases: Vec<(&str, String, Kind, &[&str])> = vec![
        // ---- materials
        (
            "E zero",
            with(e_line, "E = 0.0"),
            Invalid("materials.steel.E"),
            &["must be positive", "hostile.toml:3"],
        ),
        (
            "E negative",
            with(e_line, "E = -210000.0"),
            Invalid("materials.steel.E"),
            &["positive"],
        ),
        (
            "E nan",
            with(e_line, "E = nan"),
            Invalid("materials.steel.E"),
            &["not a finite number"],
        ),
        (
            "E inf",
            with(e_line, "E = inf"),
            Invalid("materials.steel.E"),
            &["not a finite number"],
        ),
        (
            "E -inf",
            with(e_line, "E = -inf"),
            Invalid("materials.steel.E"),
            &["not a finite number"],
        ),
        (
            "E 1e300",
            with(e_line, "E = 1e300"),
            Overflow("materials.steel.E"),
            &["overflow", "too large"],
        ),
        (
            "E 1e-300",
            with(e_line, "E = 1e-300"),
            Overflow("materials.steel.E"),
            &["overflow", "too small"],
        ),
        (
            "E of an unused-first material",
            with("E = 1000.0", "E = -1.0"),
            Invalid("materials.soft.E"),
            &["materials.soft.E", "hostile.toml:7"],
        ),
        (
            "nu 0.5",
            with("nu = 0.31", "nu = 0.5"),
            Invalid("materials.steel.nu"),
            &["(-1, 0.5)", "incompressible"],
        ),
        (
            "nu 0.7",
            with("nu = 0.31", "nu = 0.7"),
            Invalid("materials.steel.nu"),
            &["(-1, 0.5)"],
        ),
        (
            "nu -1",
            with("nu = 0.31", "nu = -1.0"),
            Invalid("materials.steel.nu"),
            &["(-1, 0.5)"],
        ),
        (
            "nu nan",
            with("nu = 0.31", "nu = nan"),
            Invalid("materials.steel.nu"),
            &["finite"],
        ),
        (
            "nu of soft",
            with("nu = 0.2", "nu = 2.0"),
            Invalid("materials.soft.nu"),
            &["hostile.toml:8"],
        ),
        ("E as text", with(e_line, "E = \"steel\""), Parse, &["E"]),
        (
            "unknown material key",
            with("nu = 0.31", "nu = 0.31\nrho = 7.8e-9"),
            Parse,
            &["rho"],
        ),
        ("missing nu", with("nu = 0.31\n", ""), Parse, &["nu"]),
        // ---- parts
        (
            "thickness zero",
            with(t_line, &format!("thickness = 0.0{t_rest}")),
            Invalid("part.base.thickness"),
            &["positive", "thickness"],
        ),
        (
            "thickness negative",
            with(t_line, &format!("thickness = -1.0{t_rest}")),
            Invalid("part.base.thickness"),
            &["positive"],
        ),
        (
            "thickness nan",
            with(t_line, &format!("thickness = nan{t_rest}")),
            Invalid("part.base.thickness"),
            &["finite"],
        ),
        (
            "thickness inf",
            with(t_line, &format!("thickness = inf{t_rest}")),
            Invalid("part.base.thickness"),
            &["finite"],
        ),
        (
            "thickness huge",
            with(t_line, &format!("thickness = 1e200{t_rest}")),
            Overflow("part.base.thickness"),
            &["overflow"],
        ),
        (
            "E·t underflows",
            with(t_line, &format!("thickness = 1e-106{t_rest}")),
            Overflow("part.base.thickness"),
            &["E·t", "overflow"],
        ),
        (
            "E·t overflows",
            with(e_line, "E = 1e60").replacen(t_line, &format!("thickness = 1e60{t_rest}"), 1),
            Overflow("part.base.thickness"),
            &["E·t"],
        ),
        (
            "rectangle x inf",
            with(
                rect,
                "rectangle = { x = [0.0, inf], y = [0.0, 120.0], cells = [10, 6] }",
            ),
            Invalid("part.base.rectangle.x"),
            &["inf", "not a finite number"],
        ),
        (
            "rectangle y nan",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0], y = [nan, 120.0], cells = [10, 6] }",
            ),
            Invalid("part.base.rectangle.y"),
            &["NaN"],
        ),
        (
            "rectangle x huge",
            with(
                rect,
                "rectangle = { x = [0.0, 1e200], y = [0.0, 120.0], cells = [10, 6] }",
            ),
            Overflow("part.base.rectangle.x"),
            &["too large"],
        ),
        (
            "rectangle reversed",
            with(
                rect,
                "rectangle = { x = [200.0, 0.0], y = [0.0, 120.0], cells = [10, 6] }",
            ),
            Parse,
            &["x0 < x1"],
        ),
        (
            "rectangle no cells",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [0, 6] }",
            ),
            Parse,
            &["at least one cell"],
        ),
        (
            "rectangle three cells",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [10, 6, 3] }",
            ),
            Parse,
            &["exactly 2"],
        ),
        (
            "rectangle three x",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0, 900.0], y = [0.0, 120.0], cells = [10, 6] }",
            ),
            Parse,
            &["exactly 2"],
        ),
        (
            "rectangle negative cells",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [-1, 6] }",
            ),
            Parse,
            &["cells"],
        ),
        (
            "rectangle elements outside",
            with(rect, &format!("{rect}\nelements = \"q4\"")),
            Parse,
            &["elements"],
        ),
        (
            "cells too many",
            with(
                rect,
                "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [100000, 100000] }",
            ),
            TooLarge,
            &["unknowns", "GiB"],
        ),
        (
            "annulus r inf",
            with(
                ann,
                "annulus = { center = [500.0, 0.0], r = [10.0, inf], theta = [0.0, 90.0], cells = [2, 4] }",
            ),
            Invalid("part.ring.annulus.r"),
            &["finite"],
        ),
        (
            "annulus center nan",
            with(
                ann,
                "annulus = { center = [nan, 0.0], r = [10.0, 20.0], theta = [0.0, 90.0], cells = [2, 4] }",
            ),
            Invalid("part.ring.annulus.center"),
            &["finite"],
        ),
        (
            "annulus theta nan",
            with(
                ann,
                "annulus = { center = [500.0, 0.0], r = [10.0, 20.0], theta = [0.0, nan], cells = [2, 4] }",
            ),
            Invalid("part.ring.annulus.theta"),
            &["finite"],
        ),
        (
            "annulus r reversed",
            with(
                ann,
                "annulus = { center = [500.0, 0.0], r = [20.0, 10.0], theta = [0.0, 90.0], cells = [2, 4] }",
            ),
            Parse,
            &["0 < r0 < r1"],
        ),
        (
            "annulus center huge",
            with(
                ann,
                "annulus = { center = [1e300, 0.0], r = [10.0, 20.0], theta = [0.0, 90.0], cells = [2, 4] }",
            ),
            Overflow("part.ring.annulus.center"),
            &["too large"],
        ),
        (
            "unknown material",
            with("material = \"soft\"", "material = \"gold\""),
            Parse,
            &["gold", "[materials]"],
        ),
        (
            "duplicate part",
            with("name = \"ring\"", "name = \"plate\""),
            Duplicate("part#3.name"),
            &["defined twice", "[[part]] #2 on line 17"],
        ),
        (
            "two meshes",
            with(ann, &format!("{ann}\n{rect}")),
            Parse,
            &["exactly one"],
        ),
        // ---- interfaces
        (
            "c_n zero",
            with("c_n = 1e9", "c_n = 0.0"),
            Invalid("interface.plate-base.c_n"),
            &["positive", "penalty"],
        ),
        (
            "c_n negative",
            with("c_n = 1e9", "c_n = -1e9"),
            Invalid("interface.plate-base.c_n"),
            &["positive"],
        ),
        (
            "c_n nan",
            with("c_n = 1e9", "c_n = nan"),
            Invalid("interface.plate-base.c_n"),
            &["finite"],
        ),
        (
            "c_s inf",
            with("c_s = 1e9", "c_s = inf"),
            Invalid("interface.plate-base.c_s"),
            &["finite"],
        ),
        (
            "c_n 1e25",
            with("c_n = 1e9", "c_n = 1e25"),
            Precision("interface.plate-base.c_n"),
            &["loss of precision", "E·t", "round-off"],
        ),
        (
            "c_s 1e30",
            with("c_s = 1e9", "c_s = 1e30"),
            Precision("interface.plate-base.c_s"),
            &["loss of precision"],
        ),
        (
            "c_n 1e200",
            with("c_n = 1e9", "c_n = 1e200"),
            Overflow("interface.plate-base.c_n"),
            &["overflow"],
        ),
        (
            "c_n 1e-200",
            with("c_n = 1e9", "c_n = 1e-200"),
            Overflow("interface.plate-base.c_n"),
            &["too small"],
        ),
        (
            "tolerance zero",
            with("tolerance = 0.05", "tolerance = 0.0"),
            Invalid("interface.plate-base.tolerance"),
            &["positive"],
        ),
        (
            "tolerance nan",
            with("tolerance = 0.05", "tolerance = nan"),
            Invalid("interface.plate-base.tolerance"),
            &["finite"],
        ),
        (
            "unknown host",
            with("host = \"base\"", "host = \"nope\""),
            Parse,
            &["nope", "not defined"],
        ),
        (
            "unknown boundary",
            with("boundary = \"bottom\"\nc_n", "boundary = \"floor\"\nc_n"),
            Parse,
            &["floor", "no boundary"],
        ),
        (
            "host is node part",
            with("host = \"base\"", "host = \"plate\""),
            Parse,
            &["same part"],
        ),
        (
            "unknown law",
            with("c_n = 1e9", "law = \"glue\"\nc_n = 1e9"),
            Parse,
            &["glue"],
        ),
        // ---- supports
        (
            "support value nan",
            with("value = [0.0, 0.0]", "value = [0.0, nan]"),
            Invalid("support#1.value"),
            &["[1]", "finite"],
        ),
        (
            "support value huge",
            with("value = [0.0, 0.0]", "value = [0.0, 1e200]"),
            Overflow("support#1.value"),
            &["too large"],
        ),
        (
            "support value three",
            with("value = [0.0, 0.0]", "value = [0.0, 0.0, 5.0]"),
            Parse,
            &["exactly 2"],
        ),
        (
            "support fix twice",
            with("fix = [\"x\", \"y\"]", "fix = [\"x\", \"x\"]"),
            Parse,
            &["same component twice"],
        ),
        (
            "support fix empty",
            with("fix = [\"x\", \"y\"]", "fix = []"),
            Parse,
            &["empty"],
        ),
        (
            "support fix z",
            with("fix = [\"x\", \"y\"]", "fix = [\"z\"]"),
            Parse,
            &["z"],
        ),
        (
            "support at nan",
            with("boundary = \"inner\"", "at = [nan, 0.0]"),
            Invalid("support#2.at"),
            &["finite"],
        ),
        (
            "support at and boundary",
            with(
                "boundary = \"inner\"",
                "boundary = \"inner\"\nat = [510.0, 0.0]",
            ),
            Parse,
            &["exactly one"],
        ),
        // ---- loads
        (
            "force nan",
            with("force = [0.0, -1500.0]", "force = [0.0, nan]"),
            Invalid("load#1.force"),
            &["finite"],
        ),
        (
            "force 1e308",
            with("force = [0.0, -1500.0]", "force = [0.0, -1e308]"),
            Overflow("load#1.force"),
            &["overflow", "too large"],
        ),
        (
            "force three",
            with("force = [0.0, -1500.0]", "force = [0.0, -1500.0, -99999.0]"),
            Parse,
            &["exactly 2"],
        ),
        (
            "from inf",
            with("from = [86.0, 135.0]", "from = [inf, 135.0]"),
            Invalid("load#1.from"),
            &["finite"],
        ),
        (
            "from equals to",
            with("from = [86.0, 135.0]", "from = [114.0, 135.0]"),
            Parse,
            &["equal"],
        ),
        (
            "segment off the boundary",
            with("to = [114.0, 135.0]", "to = [114.0, 130.0]"),
            Parse,
            &["must lie on the part's boundary"],
        ),
        (
            "point load nowhere",
            with("at = [520.0, 0.0]", "at = [525.0, 3.0]"),
            Parse,
            &["matches no node"],
        ),
        (
            "point load at nan",
            with("at = [520.0, 0.0]", "at = [nan, 0.0]"),
            Invalid("load#2.at"),
            &["finite"],
        ),
        (
            "pressure nan",
            with(
                "at = [520.0, 0.0]\nforce = [1.0, 0.0]",
                "boundary = \"outer\"\npressure = nan",
            ),
            Invalid("load#2.pressure"),
            &["finite"],
        ),
        (
            "pressure huge",
            with(
                "at = [520.0, 0.0]\nforce = [1.0, 0.0]",
                "boundary = \"outer\"\npressure = 1e300",
            ),
            Overflow("load#2.pressure"),
            &["too large"],
        ),
        (
            "pressure and force",
            with(
                "at = [520.0, 0.0]\nforce = [1.0, 0.0]",
                "boundary = \"outer\"\npressure = 1.0\nforce = [1.0, 0.0]",
            ),
            Parse,
            &["pressure"],
        ),
        // ---- analysis
        (
            "increments zero",
            with("increments = 10", "increments = 0"),
            Invalid("analysis.increments"),
            &["at least 1"],
        ),
        (
            "increments 2^64-1",
            with("increments = 10", "increments = 18446744073709551615"),
            Invalid("analysis.increments"),
            &["more than 10000000"],
        ),
        (
            "increments negative",
            with("increments = 10", "increments = -1"),
            Parse,
            &["increments"],
        ),
        (
            "max_iterations zero",
            with("max_iterations = 200", "max_iterations = 0"),
            Invalid("analysis.max_iterations"),
            &["at least 1"],
        ),
        (
            "output_every zero",
            with("output_every = 1", "output_every = 0"),
            Invalid("analysis.output_every"),
            &["at least 1"],
        ),
        (
            "output_every negative",
            with("output_every = 1", "output_every = -2"),
            Parse,
            &["output_every = -2", "positive integer", "\"last\""],
        ),
        (
            "output_every unknown word",
            with("output_every = 1", "output_every = \"first\""),
            Parse,
            &["output_every = \"first\"", "\"last\""],
        ),
        (
            "output_every fraction",
            with("output_every = 1", "output_every = 2.5"),
            Parse,
            &["positive integer"],
        ),
        (
            "gap_tolerance negative",
            with("gap_tolerance = 1e-9", "gap_tolerance = -1.0"),
            Invalid("analysis.gap_tolerance"),
            &["non-negative"],
        ),
        (
            "gap_tolerance nan",
            with("gap_tolerance = 1e-9", "gap_tolerance = nan"),
            Invalid("analysis.gap_tolerance"),
            &["finite"],
        ),
        (
            "force_tolerance one",
            with("force_tolerance = 1e-6", "force_tolerance = 1.0"),
            Invalid("analysis.force_tolerance"),
            &["[0, 1)"],
        ),
        (
            "force_tolerance negative",
            with("force_tolerance = 1e-6", "force_tolerance = -0.1"),
            Invalid("analysis.force_tolerance"),
            &["[0, 1)"],
        ),
        (
            "max_violation inf",
            with("max_violation = 0.05", "max_violation = inf"),
            Invalid("analysis.max_violation"),
            &["finite"],
        ),
        (
            "max_residual zero",
            with("max_residual = 1e-4", "max_residual = 0.0"),
            Invalid("analysis.max_residual"),
            &["positive"],
        ),
        (
            "max_residual nan",
            with("max_residual = 1e-4", "max_residual = nan"),
            Invalid("analysis.max_residual"),
            &["finite"],
        ),
        (
            "unknown analysis key",
            with("output_every = 1", "output_every = 1\nincrement = 5"),
            Parse,
            &["increment"],
        ),
        (
            "unknown scheme",
            with("output_every = 1", "output_every = 1\nscheme = \"newton\""),
            Parse,
            &["newton"],
        ),
        // ---- the file as a whole
        ("not toml", "E = = 3".to_string(), Parse, &["hostile.toml"]),
        (
            "no parts",
            "[materials.steel]\nE = 1.0\nnu = 0.3\n".to_string(),
            Parse,
            &["part"],
        ),
    ];
    assert!(cases.len() >= 60, "{} cases", cases.len());
    for (case, text, kind, words) in &cases {
        let e = error(text, 1);
        assert_error(case, text, &e, *kind, words);
    }
}

/// Sizes computed from `--refine` use checked arithmetic and are weighed against
/// the machine's memory before meshing: a refinement too large to count or to
/// hold is refused with the estimate, never an allocation abort.
#[test]
fn oversized_refinements_are_refused() {
    for refine in [
        100_000,
        4_294_967_296,
        4_611_686_018_427_387_905,
        usize::MAX,
    ] {
        let e = error(&BASE, refine);
        assert!(
            matches!(e, Error::TooLarge { .. } | Error::Parse { .. }),
            "refine {refine}: {e:?}"
        );
        let m = e.to_string();
        assert!(
            m.contains("too large") || m.contains("too many"),
            "refine {refine}: {m}"
        );
    }
    assert!(matches!(error(&BASE, 0), Error::Model(_)));
}

/// A Gmsh node with a non-finite coordinate is named by the file, its line and
/// the node's tag.
#[test]
fn gmsh_non_finite_coordinate_names_file_and_node() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/gmsh");
    let text = std::fs::read_to_string(dir.join("square_22.msh")).unwrap();
    // The second node line of the $Nodes section: "2 x y z".
    let lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| *l == "$Nodes").unwrap() + 3;
    let tag = lines[at].split_whitespace().next().unwrap().to_string();
    let bad: Vec<String> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i == at {
                format!("{tag} nan 0 0")
            } else {
                l.to_string()
            }
        })
        .collect();
    let e = cfe::mesh::gmsh::GmshMesh::parse(bad.join("\n").as_bytes(), Path::new("sq.msh"))
        .unwrap_err();
    match &e {
        Error::Parse { line, path, .. } => {
            assert_eq!(*line, Some(at + 1), "{e}");
            assert_eq!(path, Path::new("sq.msh"));
        }
        other => panic!("{other:?}"),
    }
    let m = e.to_string();
    assert!(
        m.contains(&format!("node {tag}")) && m.contains("non-finite x"),
        "{m}"
    );
}

/// The second `[[interface]]` table of the cases below: the plate's left side on
/// the base (its coupling nodes lie on no base edge, but names are checked
/// before anything is meshed or paired).
const SECOND_INTERFACE: &str = "\n[[interface]]\nname = \"plate-base\"\nhost = \"base\"\nnodes = \"plate\"\nboundary = \"left\"\n";

/// `BASE` with `extra` appended to its `[[interface]]` block (before its first
/// `[[support]]`).
fn with_before_support(extra: &str) -> String {
    with("\n[[support]]", &format!("{extra}\n[[support]]"))
}

/// `BASE` in plane strain with the steel's ν set to `nu`.
fn plane_strain_nu(nu: &str) -> String {
    with(
        "title = \"hostile\"",
        "title = \"hostile\"\nplane = \"strain\"",
    )
    .replacen("nu = 0.31", &format!("nu = {nu}"), 1)
}

/// Names given twice, penalties far below E·t, ν at its bounds and keys nested
/// beyond the TOML reader's limit: each refused with its typed error, key and
/// line, and a message naming the real cause (not a mechanism, not a bare
/// "recursion limit"). 21 cases.
#[test]
fn names_penalties_and_nesting_are_refused_with_their_cause() {
    use Kind::*;
    let deep_key = format!("deep{} = 1", ".a".repeat(100));
    let deep_header = format!("[deep{}]\nb = 1", ".a".repeat(90));
    let deep_array = format!("deep = {}{}", "[".repeat(300), "]".repeat(300));
    let deep_table = format!("deep = {}1{}", "{a=".repeat(300), "}".repeat(300));
    let cases: Vec<(&str, String, Kind, &[&str])> = vec![
        // ---- names
        (
            "interface name twice",
            with_before_support(SECOND_INTERFACE),
            Duplicate("interface#2.name"),
            &[
                "\"plate-base\"",
                "defined twice",
                "[[interface]] #1 on line 28",
            ],
        ),
        (
            "third interface repeats the first",
            with_before_support(&format!(
                "{}{SECOND_INTERFACE}",
                SECOND_INTERFACE.replace("plate-base", "other")
            )),
            Duplicate("interface#3.name"),
            &["[[interface]] #1", "rename one"],
        ),
        (
            "support name twice",
            with(
                "[[support]]\npart = \"base\"",
                "[[support]]\nname = \"ground\"\npart = \"base\"",
            )
            .replacen(
                "[[support]]\npart = \"ring\"",
                "[[support]]\nname = \"ground\"\npart = \"ring\"",
                1,
            ),
            Duplicate("support#2.name"),
            &["\"ground\"", "[[support]] #1 on line"],
        ),
        (
            "load name twice",
            with(
                "[[load]]\npart = \"plate\"",
                "[[load]]\nname = \"push\"\npart = \"plate\"",
            )
            .replacen(
                "[[load]]\npart = \"ring\"",
                "[[load]]\nname = \"push\"\npart = \"ring\"",
                1,
            ),
            Duplicate("load#2.name"),
            &["\"push\"", "load names must be unique"],
        ),
        (
            "step name twice",
            with("increments = 10\n", "")
                + "\n[[step]]\nname = \"s\"\nincrements = 1\n\n[[step]]\nname = \"s\"\nincrements = 2\n",
            Duplicate("step#2.name"),
            &["\"s\"", "[[step]] #1"],
        ),
        (
            "part name twice, first and last",
            with("name = \"ring\"", "name = \"base\""),
            Duplicate("part#3.name"),
            &["\"base\"", "[[part]] #1 on line 11"],
        ),
        // ---- penalties far below E·t
        (
            "c_n far below E·t",
            with("c_n = 1e9", "c_n = 1e-3"),
            Weak("interface.plate-base.c_n"),
            &["far below E·t", "part 'base'", "mechanism"],
        ),
        (
            "c_s far below E·t",
            with("c_s = 1e9", "c_s = 0.01"),
            Weak("interface.plate-base.c_s"),
            &["far below E·t", "1e3 to 1e8 × E·t"],
        ),
        (
            "E = 1e100 under a penalty of 1e9",
            with("E = 210000.0", "E = 1e100"),
            Weak("interface.plate-base.c_n"),
            &["E·t = 1e100", "1.0e-91 × E·t"],
        ),
        (
            "c_n below E·t of the softer part",
            with("c_n = 1e9", "c_n = 1e-4").replacen(
                "name = \"plate\"\nmaterial = \"steel\"",
                "name = \"plate\"\nmaterial = \"soft\"",
                1,
            ),
            Weak("interface.plate-base.c_n"),
            &["E·t = 1e3 of part 'plate'"],
        ),
        // ---- ν at its bounds
        (
            "nu one ulp below 0.5 in plane strain",
            plane_strain_nu("0.49999999999999994"),
            Invalid("materials.steel.nu"),
            &[
                "of 0.5 in plane strain",
                "ill-conditioned",
                "plane = \"stress\"",
            ],
        ),
        (
            "nu 1e-12 below 0.5 in plane strain",
            plane_strain_nu("0.499999999999"),
            Invalid("materials.steel.nu"),
            &["bulk modulus", "5.0e11 × the shear modulus"],
        ),
        (
            "nu one ulp above -1",
            with("nu = 0.31", "nu = -0.9999999999999999"),
            Invalid("materials.steel.nu"),
            &["of -1", "shear modulus", "ill-conditioned"],
        ),
        (
            "nu 1e-12 above -1 in plane strain",
            plane_strain_nu("-0.999999999999"),
            Invalid("materials.steel.nu"),
            &["of -1"],
        ),
        (
            "nu of the soft material near 0.5 in plane strain",
            plane_strain_nu("0.31").replacen("nu = 0.2", "nu = 0.49999999999", 1),
            Invalid("materials.soft.nu"),
            &["hostile.toml:9"],
        ),
        // ---- nesting beyond the TOML reader's limit
        (
            "dotted key of 101 parts under [analysis]",
            format!("{BASE}{deep_key}\n"),
            Parse,
            &["nested too deep", "102 dotted parts", "recursion limit"],
        ),
        (
            "table header of 91 parts",
            format!("{BASE}{deep_header}\n"),
            Parse,
            &["nested too deep", "91 dotted parts"],
        ),
        (
            "dotted key at the top",
            format!("{deep_key}\n{BASE}"),
            Parse,
            &["hostile.toml: line 1:", "101 dotted parts"],
        ),
        (
            "arrays 300 deep",
            format!("{BASE}{deep_array}\n"),
            Parse,
            &["recurse"],
        ),
        (
            "inline tables 300 deep",
            format!("{BASE}{deep_table}\n"),
            Parse,
            &["recurse"],
        ),
        (
            "nested arrays as a value",
            with(
                "fix = [\"x\", \"y\"]",
                &format!("fix = {}{}", "[".repeat(200), "]".repeat(200)),
            ),
            Parse,
            &["recurse"],
        ),
    ];
    assert!(cases.len() >= 21, "{} cases", cases.len());
    for (case, text, kind, words) in &cases {
        let e = error(text, 1);
        assert_error(case, text, &e, *kind, words);
    }
    // The nesting errors name the deep line itself.
    let text = format!("{BASE}{deep_header}\n");
    match error(&text, 1) {
        Error::Parse { line: Some(l), .. } => {
            assert!(text.lines().nth(l - 1).unwrap().starts_with("[deep"))
        }
        e => panic!("{e:?}"),
    }
}

/// What stays accepted next to the refusals above: a penalty of 1e-5 × E·t,
/// a tiny `c_s` the frictionless law ignores, ν one ulp below 0.5 in plane
/// stress (where nothing diverges) and 1e-9 from its bounds in plane strain.
#[test]
fn values_near_the_new_limits_are_accepted() {
    for text in [
        with("c_n = 1e9", "c_n = 2.1"),
        with("c_s = 1e9", "c_s = 1e-9\nlaw = \"frictionless\""),
        with("nu = 0.31", "nu = 0.49999999999999994"),
        plane_strain_nu("0.499999999"),
        plane_strain_nu("-0.999999999"),
    ] {
        Model::from_str(&text, Path::new("hostile.toml"), 1)
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
    }
}

// ------------------------------------------------------------ input files

use cfe::error::InputRefusal;
use cfe::mesh::gmsh::GmshMesh;
use cfe::mesh::input_file::{MESH_FILE_CAP, PROBLEM_FILE_CAP};
use std::path::PathBuf;

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cfe-hostile-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A FIFO at `path`. Should a reader block on it anyway, a writer opens it after
/// a few seconds so that the test fails instead of hanging.
fn fifo(path: &Path) {
    let c = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0, "mkfifo");
    let p = path.to_path_buf();
    std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_secs(5));
        let _ = std::fs::OpenOptions::new().write(true).open(p);
    });
}

/// A problem of one Gmsh part (the left square of square_41.msh, copied into
/// `dir`) whose mesh file is `mesh`.
fn gmsh_problem(dir: &Path, mesh: &str) -> PathBuf {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/gmsh/square_41.msh");
    std::fs::copy(data, dir.join("square_41.msh")).unwrap();
    let problem = dir.join("p.toml");
    std::fs::write(
        &problem,
        format!(
            "[materials.m]\nE = 1000.0\nnu = 0.25\n\n[[part]]\nname = \"sq\"\nmaterial = \"m\"\ngmsh = {{ file = \"{mesh}\", surfaces = [\"left\"] }}\n\n[[support]]\npart = \"sq\"\nboundary = \"sides\"\nfix = [\"x\", \"y\"]\n\n[[load]]\npart = \"sq\"\nboundary = \"top\"\nforce = [0.0, 1.0]\n"
        ),
    )
    .unwrap();
    problem
}

/// Checks that `e` refuses `path` as not a regular file, being `found`.
fn assert_not_regular(e: &Error, path: &Path, found: &str) {
    match e {
        Error::InputFile {
            path: p,
            refusal: InputRefusal::NotRegular { found: f },
            ..
        } => {
            assert_eq!(p, path, "{e}");
            assert_eq!(*f, found, "{e}");
        }
        other => panic!("not a refusal of {}: {other:?}", path.display()),
    }
    assert!(e.to_string().contains("not a regular file"), "{e}");
}

/// Only regular files are read as problem and mesh files: a FIFO (which blocked
/// forever), a character device (/dev/zero was read until the allocator
/// refused), and a directory are refused at once with `Error::InputFile` naming
/// the path and what it is; the same problem with a regular mesh file reads.
#[test]
fn only_regular_files_are_read() {
    let dir = scratch("regular");
    let problem = gmsh_problem(&dir, "square_41.msh");
    Model::from_file(&problem, 1).unwrap();
    // A FIFO as the problem file, and as the mesh file.
    let pipe = dir.join("pipe.toml");
    fifo(&pipe);
    let e = Model::from_file(&pipe, 1).unwrap_err();
    assert_not_regular(&e, &pipe, "a FIFO (named pipe)");
    assert!(e.to_string().contains("problem file"), "{e}");
    let mesh_pipe = dir.join("pipe.msh");
    fifo(&mesh_pipe);
    let e = Model::from_file(&gmsh_problem(&dir, "pipe.msh"), 1).unwrap_err();
    assert_not_regular(&e, &mesh_pipe, "a FIFO (named pipe)");
    assert!(e.to_string().contains("Gmsh file of part 'sq'"), "{e}");
    let e = GmshMesh::read(&mesh_pipe).unwrap_err();
    assert_not_regular(&e, &mesh_pipe, "a FIFO (named pipe)");
    // Devices.
    let e = Model::from_file(&gmsh_problem(&dir, "/dev/zero"), 1).unwrap_err();
    assert_not_regular(&e, Path::new("/dev/zero"), "a character device");
    let e = Model::from_file(Path::new("/dev/null"), 1).unwrap_err();
    assert_not_regular(&e, Path::new("/dev/null"), "a character device");
    // Directories.
    let e = Model::from_file(&gmsh_problem(&dir, "."), 1).unwrap_err();
    assert_not_regular(&e, &dir.join("."), "a directory");
    let e = Model::from_file(&dir, 1).unwrap_err();
    assert_not_regular(&e, &dir, "a directory");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Input files are read up to a cap stated in the error: a problem file of
/// 64 MiB + 1 byte and a mesh file of 4 GiB + 1 byte (both sparse: nothing is
/// written or read) are refused with `Error::InputFile`, size and cap; a missing
/// file is still `ReadInput`.
#[test]
fn input_files_are_read_up_to_a_cap() {
    let dir = scratch("cap");
    let big = dir.join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(PROBLEM_FILE_CAP + 1)
        .unwrap();
    let e = Model::from_file(&big, 1).unwrap_err();
    match &e {
        Error::InputFile {
            refusal: InputRefusal::TooLarge { size, cap },
            ..
        } => assert_eq!((*size, *cap), (PROBLEM_FILE_CAP + 1, 64 << 20)),
        other => panic!("{other:?}"),
    }
    assert!(
        e.to_string()
            .contains("it holds 67108865 bytes, more than the 64 MiB cap on a problem file"),
        "{e}"
    );
    let mesh = dir.join("big.msh");
    std::fs::File::create(&mesh)
        .unwrap()
        .set_len(MESH_FILE_CAP + 1)
        .unwrap();
    let e = Model::from_file(&gmsh_problem(&dir, "big.msh"), 1).unwrap_err();
    match &e {
        Error::InputFile {
            refusal: InputRefusal::TooLarge { size, cap },
            path,
            ..
        } => {
            assert_eq!((*size, *cap), (MESH_FILE_CAP + 1, 4 << 30));
            assert_eq!(path, &mesh);
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("more than the 4 GiB cap"), "{e}");
    let _ = std::fs::remove_file(&mesh);
    let e = Model::from_file(&dir.join("missing.toml"), 1).unwrap_err();
    assert!(matches!(e, Error::ReadInput { .. }), "{e:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
