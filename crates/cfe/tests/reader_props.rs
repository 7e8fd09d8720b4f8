//! Property tests of the readers: the problem-file (TOML) reader and the Gmsh
//! reader return a value or a typed error for any input — never a panic — and a
//! refused number is named by its key and the line that holds it.

use cfe::Error;
use cfe::mesh::gmsh::GmshMesh;
use cfe::model::Model;
use proptest::prelude::*;
use std::path::Path;

/// A float as TOML writes it (`nan`, `inf`, `-inf`, `1e300`, `0.5`).
fn toml_float(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{v:e}")
    }
}

/// Any f64, with the hostile ones (non-finite, huge, tiny, zero, negative) often.
fn hostile_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(1e300),
        Just(-1e308),
        Just(1e-300),
        -1e6..1e6f64,
        any::<f64>(),
    ]
}

/// A small problem with its numbers given.
fn problem(e: f64, nu: f64, t: f64, x1: f64, c_n: f64, fy: f64, gap: f64) -> String {
    let f = toml_float;
    format!(
        r#"[materials.m]
E = {}
nu = {}

[[part]]
name = "a"
material = "m"
thickness = {}
rectangle = {{ x = [0.0, {}], y = [0.0, 1.0], cells = [2, 1] }}

[[part]]
name = "b"
material = "m"
rectangle = {{ x = [0.0, 1.0], y = [1.0, 2.0], cells = [2, 1] }}

[[interface]]
host = "a"
nodes = "b"
boundary = "bottom"
c_n = {}

[[support]]
part = "a"
boundary = "bottom"
fix = ["x", "y"]

[[load]]
part = "b"
boundary = "top"
force = [0.0, {}]

[analysis]
gap_tolerance = {}
"#,
        f(e),
        f(nu),
        f(t),
        f(x1),
        f(c_n),
        f(fy),
        f(gap)
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Any numbers in a problem file: a model, or an error; a value refused as
    /// invalid or overflowing names its key, and its line holds that key.
    #[test]
    fn problem_numbers_never_panic(
        e in hostile_f64(), nu in hostile_f64(), t in hostile_f64(), x1 in hostile_f64(),
        c_n in hostile_f64(), fy in hostile_f64(), gap in hostile_f64(),
    ) {
        let text = problem(e, nu, t, x1, c_n, fy, gap);
        match Model::from_str(&text, Path::new("p.toml"), 1) {
            Ok(m) => {
                // Accepted values are finite and in range.
                prop_assert!(e.is_finite() && e > 0.0 && nu > -1.0 && nu < 0.5);
                prop_assert!(t.is_finite() && t > 0.0 && fy.is_finite() && gap >= 0.0);
                prop_assert!(m.parts.len() == 2);
            }
            Err(Error::Invalid { key, line, .. } | Error::Overflow { key, line: line @ Some(_), .. }) => {
                let last = key.rsplit('.').next().unwrap().trim_start_matches(|c: char| c == '#' || c.is_ascii_digit()).to_string();
                let l = text.lines().nth(line.unwrap() - 1).unwrap();
                prop_assert!(l.contains(&last), "line '{}' lacks key {}", l, key);
            }
            Err(_) => {}
        }
    }

    /// Any text as a problem file: a model or an error, never a panic.
    #[test]
    fn problem_text_never_panics(text in "\\PC{0,200}") {
        let _ = Model::from_str(&text, Path::new("p.toml"), 1);
    }

    /// A valid problem with one line replaced by arbitrary text: never a panic.
    #[test]
    fn problem_line_edits_never_panic(line in 0usize..40, with in "[ -~]{0,40}") {
        let base = problem(210000.0, 0.3, 1.0, 1.0, 1e9, -1.0, 1e-9);
        let text: Vec<String> = base
            .lines()
            .enumerate()
            .map(|(i, l)| if i == line { with.clone() } else { l.to_string() })
            .collect();
        let _ = Model::from_str(&text.join("\n"), Path::new("p.toml"), 1);
    }

    /// Any bytes as a Gmsh file, bare or after a valid header: a mesh or an
    /// error, never a panic.
    #[test]
    fn gmsh_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..400), header in any::<bool>()) {
        let data = if header {
            [b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n".as_slice(), &data].concat()
        } else {
            data
        };
        if let Ok(m) = GmshMesh::parse(&data, Path::new("x.msh")) {
            let _ = m.part_mesh("x", None).and_then(|mesh| mesh.validate("x"));
        }
    }

    /// A valid Gmsh file with one token replaced by a hostile number or word:
    /// never a panic.
    #[test]
    fn gmsh_token_edits_never_panic(which in any::<prop::sample::Index>(), with in prop_oneof![
        Just("nan".to_string()), Just("1e308".to_string()), Just("-1".to_string()),
        Just("18446744073709551615".to_string()), Just("$EndNodes".to_string()),
        any::<i64>().prop_map(|v| v.to_string()), "[ -~]{0,8}",
    ]) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/gmsh/square_41.msh");
        let text = std::fs::read_to_string(&path).unwrap();
        let tokens: Vec<&str> = text.split_whitespace().collect();
        let i = which.index(tokens.len());
        let edited: Vec<&str> = tokens.iter().enumerate().map(|(j, t)| if j == i { with.as_str() } else { t }).collect();
        if let Ok(m) = GmshMesh::parse(edited.join("\n").as_bytes(), &path) {
            let _ = m.part_mesh("x", None).and_then(|mesh| mesh.validate("x"));
        }
    }
}
