//! Line probes (`[[line]]`, issue 40): a line through the parts sampled for the
//! displacement and the stresses, against closed forms — a uniformly stressed
//! block and a cantilever's linear σxx — their tables at every written
//! increment, and the schema's typed errors.

mod common;

use cfe::Error;
use cfe::analysis::Analysis;
use cfe::model::Model;
use common::Problem;
use std::path::Path;

/// A block x ∈ [0, 1], y ∈ [0, 2] (`elements`, 4 × 8 cells; E = 1000, ν = 0.3,
/// plane stress, t = 1) on rollers at its bottom, pinned in x at the origin,
/// pressed by 3 on its top, and the line `line` (its keys).
fn block(elements: &str, line: &str) -> String {
    Problem::compact()
        .plane("stress")
        .material("steel", 1000.0, 0.3)
        .part("block", "steel")
        .rectangle_of([0.0, 1.0], [0.0, 2.0], [4, 8], elements)
        .rollers("block", [0.0, 0.0])
        .load("block", "top", [0.0, -3.0])
        .raw(&format!("[[line]]\n{line}"))
        .text()
}

fn model(text: &str) -> Result<Model, Error> {
    Model::from_str(text, Path::new("lines.toml"), 1)
}

/// A block under a uniform pressure p = 3 is uniformly stressed, σyy = −p,
/// σxx = σxy = 0 (von Mises p), its displacement u = (ν p x / E, −p y / E):
/// along a diagonal line that crosses elements (T3 and Q4), every sample gives
/// them to round-off; the line's points are evenly spaced from its start.
#[test]
fn a_line_through_a_uniformly_stressed_block_gives_the_constant_stress() {
    for elements in ["t3", "q4"] {
        let text = block(
            elements,
            "name = \"diag\"\nfrom = [0.0, 0.0]\nto = [1.0, 2.0]\npoints = 7",
        );
        let a = Analysis::new(model(&text).unwrap()).unwrap();
        let res = a.solve().unwrap();
        let lines = a.line_samples(&res.last);
        assert_eq!(lines.len(), 1);
        let (name, samples) = &lines[0];
        assert_eq!((*name, samples.len()), ("diag", 7));
        let (p, e, nu) = (3.0, 1000.0, 0.3);
        for (k, s) in samples.iter().enumerate() {
            let t = k as f64 / 6.0;
            assert!((s.x[0] - t).abs() < 1e-12 && (s.x[1] - 2.0 * t).abs() < 1e-12);
            assert!((s.s - t * 5f64.sqrt()).abs() < 1e-12);
            let [sxx, syy, sxy] = s.stress;
            assert!(
                sxx.abs() < 1e-10 && (syy + p).abs() < 1e-10 && sxy.abs() < 1e-10,
                "{elements}: {s:?}"
            );
            assert!((s.von_mises - p).abs() < 1e-10);
            assert!(
                (s.u[0] - nu * p * s.x[0] / e).abs() < 1e-12,
                "{elements}: {s:?}"
            );
            assert!((s.u[1] + p * s.x[1] / e).abs() < 1e-12, "{elements}: {s:?}");
        }
    }
}

/// A cantilever (L = 100, h = 10, t = 1, 80 × 8 Q4, clamped at x = 0, a shear
/// load P = 1 on its free end): across its depth at mid-span, σxx follows beam
/// theory's linear σxx = P (L − x)(y − h/2) / I, I = t h³/12, within 3 % of the
/// largest (the mesh's error: 1.8 % at the faces); the run writes the line as
/// `lines/mid.csv` (the same samples) and `lines/mid.png`, both in the
/// manifest.
#[test]
fn a_line_across_a_cantilever_follows_beam_theory() {
    let text = Problem::compact()
        .plane("stress")
        .material("steel", 1000.0, 0.3)
        .part("beam", "steel")
        .rectangle_of([0.0, 100.0], [0.0, 10.0], [80, 8], "q4")
        .support("beam", "left", ["x", "y"])
        .load("beam", "right", [0.0, -1.0])
        .table("[[line]]")
        .key("name", "mid")
        .key("from", [50.0, 0.0])
        .key("to", [50.0, 10.0])
        .key("points", 21usize)
        .text();
    let mut a = Analysis::new(model(&text).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("cfe-test-lines-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    a.run(&out, &mut |_| {}).unwrap();
    let csv = std::fs::read_to_string(out.join("lines/mid.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(rows.next(), Some("s,x,y,part,ux,uy,sxx,syy,sxy,von_mises"));
    let (p, l, h) = (1.0, 100.0, 10.0);
    let i = h * h * h / 12.0;
    let largest = p * (l - 50.0) * (h / 2.0) / i;
    let mut n = 0;
    for row in rows {
        let f: Vec<&str> = row.split(',').collect();
        let (y, sxx): (f64, f64) = (f[2].parse().unwrap(), f[6].parse().unwrap());
        assert_eq!(f[3], "beam");
        let beam = p * (l - 50.0) * (y - h / 2.0) / i;
        assert!(
            (sxx - beam).abs() <= 0.03 * largest,
            "y = {y}: {sxx} vs {beam}"
        );
        n += 1;
    }
    assert_eq!(n, 21);
    assert!(out.join("lines/mid.png").is_file());
    let manifest = std::fs::read_to_string(out.join(".cfe-manifest")).unwrap();
    assert!(manifest.contains("lines/mid.csv\n") && manifest.contains("lines/mid.png\n"));
    let _ = std::fs::remove_dir_all(&out);
}

/// The key and message of an [`Error::Invalid`].
fn invalid(r: Result<Model, Error>) -> (String, String) {
    match r {
        Err(Error::Invalid { key, message, .. }) => (key, message),
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted"),
    }
}

/// The schema's typed errors: a line outside every part (and outside the part
/// it names), of zero length, with fewer than two points, a name that cannot
/// name a file, twice the same name — each an [`Error::Invalid`] keyed
/// `line.<name>`; an unknown part is a parse error naming it.
#[test]
fn bad_lines_are_typed_errors() {
    let (key, m) = invalid(model(&block(
        "t3",
        "name = \"far\"\nfrom = [5.0, 5.0]\nto = [6.0, 7.0]",
    )));
    assert!(
        key == "line.far" && m.contains("outside every part"),
        "{key}: {m}"
    );
    let (key, m) = invalid(model(&block(
        "q4",
        "name = \"zero\"\nfrom = [0.5, 1.0]\nto = [0.5, 1.0]",
    )));
    assert!(
        key == "line.zero" && m.contains("zero length"),
        "{key}: {m}"
    );
    let (_, m) = invalid(model(&block(
        "t3",
        "name = \"one\"\nfrom = [0.0, 0.0]\nto = [1.0, 1.0]\npoints = 1",
    )));
    assert!(m.contains("2 to 1000000 points"), "{m}");
    let (_, m) = invalid(model(&block(
        "t3",
        "name = \"../x\"\nfrom = [0.0, 0.0]\nto = [1.0, 1.0]",
    )));
    assert!(m.contains("letters, digits"), "{m}");
    let twice = block(
        "t3",
        "name = \"a\"\nfrom = [0.0, 0.0]\nto = [1.0, 1.0]\n[[line]]\nname = \"a\"\nfrom = [0.0, 1.0]\nto = [1.0, 1.0]",
    );
    let (_, m) = invalid(model(&twice));
    assert!(m.contains("unique"), "{m}");
    match model(&block(
        "t3",
        "name = \"p\"\nfrom = [0.0, 0.0]\nto = [1.0, 1.0]\npart = \"nope\"",
    )) {
        Err(Error::Parse { message, .. }) => assert!(message.contains("'nope'"), "{message}"),
        other => panic!("{:?}", other.map(|_| ())),
    }
}

/// The line's table at every increment the run writes files for
/// (`output_every = 2` of 3 increments: the 2nd and the last, as the VTU
/// series): `lines/mid.0002.csv` and `lines/mid.0003.csv`, in the manifest,
/// none for the 1st; the load is proportional, so the 2nd's displacements and
/// stresses are 2/3 of the last's at every sample (to round-off), and the last's
/// table is `lines/mid.csv`'s.
#[test]
fn a_line_is_written_at_every_written_increment() {
    let text = block(
        "q4",
        "name = \"mid\"\nfrom = [0.5, 0.0]\nto = [0.5, 2.0]\npoints = 9",
    ) + "[analysis]\nincrements = 3\noutput_every = 2\n";
    let mut a = Analysis::new(model(&text).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("cfe-test-lines-inc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    a.run(&out, &mut |_| {}).unwrap();
    assert!(!out.join("lines/mid.0001.csv").exists());
    assert!(out.join("vtu/parts_0002.vtu").is_file() && !out.join("vtu/parts_0001.vtu").exists());
    let read = |f: &str| std::fs::read_to_string(out.join("lines").join(f)).unwrap();
    let table = |f: &str| -> Vec<Vec<f64>> {
        read(f)
            .lines()
            .skip(1)
            .map(|row| {
                row.split(',')
                    .enumerate()
                    .filter(|&(k, _)| k != 3)
                    .map(|(_, v)| v.parse().unwrap())
                    .collect()
            })
            .collect()
    };
    let (second, last) = (table("mid.0002.csv"), table("mid.0003.csv"));
    assert_eq!(read("mid.0003.csv"), read("mid.csv"));
    assert_eq!((second.len(), last.len()), (9, 9));
    for (p, q) in second.iter().zip(&last) {
        // s, x, y the same; ux … von Mises scaled by 2/3.
        assert_eq!(p[..3], q[..3]);
        for (u, v) in p[3..].iter().zip(&q[3..]) {
            assert!(
                (u - 2.0 / 3.0 * v).abs() <= 1e-12 * (1.0 + v.abs()),
                "{u} vs {v}"
            );
        }
    }
    let manifest = std::fs::read_to_string(out.join(".cfe-manifest")).unwrap();
    for f in [
        "lines/mid.0002.csv\n",
        "lines/mid.0003.csv\n",
        "lines/mid.csv\n",
    ] {
        assert!(manifest.contains(f), "{f}");
    }
    let _ = std::fs::remove_dir_all(&out);
}
