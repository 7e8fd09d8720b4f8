//! Gmsh input: the small meshes in tests/data/gmsh (written by make_msh.py, by hand,
//! and make_reference.py, by Gmsh) read the same from every format, become part
//! meshes with oriented named boundaries, and solve like the built-in meshes.

mod common;

use cfe::analysis::Analysis;
use cfe::coupling::PairState;
use cfe::mesh::gmsh::{GmshMesh, Group, MshVersion};
use cfe::mesh::{ElementKind, Mesh};
use cfe::model::Model;
use cfe::solve::nonlinear::IncrementResult;
use common::{Problem, Raw, Text};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("tests/data/gmsh")
        .join(name)
}

fn read(name: &str) -> GmshMesh {
    GmshMesh::read(&data(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A problem given as text, as if it were a file in tests/data/gmsh.
fn model(text: &str) -> cfe::Result<Model> {
    Model::from_str(text, &data("inline.toml"), 1)
}

fn name(g: &str) -> Group {
    Group::Name(g.into())
}

/// Compares two meshes exactly: nodes, elements and boundaries.
fn assert_same_mesh(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.nodes, b.nodes, "{what}: nodes");
    assert_eq!(a.elements, b.elements, "{what}: elements");
    assert_eq!(a.boundaries, b.boundaries, "{what}: boundaries");
}

/// A boundary as a list of (start, end) points.
fn segments(m: &Mesh, boundary: &str) -> Vec<[[f64; 2]; 2]> {
    m.boundaries[boundary]
        .iter()
        .map(|e| e.nodes.map(|n| m.nodes[n]))
        .collect()
}

const SQUARES: [&str; 5] = [
    "square_41.msh",
    "square_41_bin.msh",
    "square_41_bin_be.msh",
    "square_22.msh",
    "square_22_bin.msh",
];

/// The same geometry in MSH 4.1 and 2.2, ASCII and binary (little- and big-endian,
/// 8- and 4-byte size_t) reads to identical nodes, elements, physical groups and
/// part meshes.
#[test]
fn all_formats_give_identical_meshes() {
    let reference = read(SQUARES[0]);
    assert_eq!(reference.version, MshVersion::V41);
    assert!(!reference.binary);
    for file in &SQUARES[1..] {
        let m = read(file);
        assert_eq!(m.binary, file.contains("bin"), "{file}");
        assert_eq!(m.node_tags, reference.node_tags, "{file}");
        assert_eq!(m.nodes, reference.nodes, "{file}");
        assert_eq!(m.lines, reference.lines, "{file}");
        assert_eq!(m.triangles, reference.triangles, "{file}");
        assert_eq!(m.quads, reference.quads, "{file}");
        assert_eq!(m.physical_names, reference.physical_names, "{file}");
        for surfaces in [None, Some(vec![name("left")]), Some(vec![Group::Tag(2)])] {
            let s = surfaces.as_deref();
            assert_same_mesh(
                &m.part_mesh("p", s).unwrap(),
                &reference.part_mesh("p", s).unwrap(),
                &format!("{file} {surfaces:?}"),
            );
        }
    }
    // And the reference itself is what make_msh.py describes.
    assert_eq!(reference.node_tags, vec![1, 2, 3, 40, 5, 60, 100]);
    assert_eq!(reference.nodes[3], [2.0, 1.0]);
    assert_eq!(reference.triangles.len(), 6);
    assert_eq!(reference.lines.len(), 7);
    assert_eq!(reference.lines[2].physical, vec![13, 15]);
}

/// Two parts from one shared file: each keeps only its own nodes, gets the
/// physical curves that lie on its boundary, oriented counter-clockwise with respect
/// to itself (so the shared "interface" curve runs up for the left square and down
/// for the right one); a curve inside the selection is no boundary.
#[test]
fn shared_file_parts_and_oriented_boundaries() {
    let m = read("square_41.msh");
    let left = m.part_mesh("left", Some(&[name("left")])).unwrap();
    let right = m.part_mesh("right", Some(&[name("right")])).unwrap();
    left.validate("left").unwrap();
    right.validate("right").unwrap();
    assert_eq!((left.nodes.len(), left.elements.len()), (5, 4));
    assert_eq!((right.nodes.len(), right.elements.len()), (4, 2));
    // Nodes keep the file's order: tags 1, 2, 5, 60, 100 for the left square.
    assert_eq!(
        left.nodes,
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]]
    );
    let names = |m: &Mesh| m.boundaries.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&left), ["bottom", "interface", "sides", "top"]);
    assert_eq!(names(&right), ["13", "bottom", "interface", "sides", "top"]);
    assert_eq!(segments(&left, "interface"), [[[1.0, 0.0], [1.0, 1.0]]]);
    assert_eq!(segments(&right, "interface"), [[[1.0, 1.0], [1.0, 0.0]]]);
    // Line 204 is written from (1,1) to (2,1); on the part it runs right to left.
    assert_eq!(segments(&right, "top"), [[[2.0, 1.0], [1.0, 1.0]]]);
    assert_eq!(segments(&left, "sides"), [[[0.0, 1.0], [0.0, 0.0]]]);
    assert_eq!(segments(&right, "13"), segments(&right, "sides"));
    // The whole file: "interface" is interior; "bottom" is a chain of two edges.
    let all = m.part_mesh("all", None).unwrap();
    assert_eq!(names(&all), ["13", "bottom", "sides", "top"]);
    assert_eq!(
        segments(&all, "bottom"),
        [[[0.0, 0.0], [1.0, 0.0]], [[1.0, 0.0], [2.0, 0.0]]]
    );
    assert_eq!(
        segments(&all, "top"),
        [[[2.0, 1.0], [1.0, 1.0]], [[1.0, 1.0], [0.0, 1.0]]]
    );
    // Every boundary edge is one of the mesh's free edges, with its owner.
    for mesh in [&left, &right, &all] {
        let free = mesh.boundary_edges();
        for e in mesh.boundaries.values().flatten() {
            assert!(free.contains(e), "{e:?} is not a free edge");
        }
    }
}

/// A physical curve with lines both on a part's boundary and inside it ("cut" =
/// the top of the left square and the line between the squares, in
/// partial_curve_41.msh) is an error for the part made of both squares, naming
/// the part, the curve, the file, the counts and an inner edge, and saying what to
/// do; for each square alone the curve lies on its boundary (or on the other
/// square) and names a boundary as usual.
#[test]
fn curve_partly_inside_a_part_is_an_error() {
    let m = read("partial_curve_41.msh");
    let e = m.part_mesh("all", None).unwrap_err().to_string();
    for want in [
        "part 'all'",
        "physical curve 'cut' (16)",
        "partial_curve_41.msh",
        "1 edge on the part's boundary and 1 edge inside it",
        "from node 2 (1, 0) to node 5 (1, 1)",
        "split the curve",
        "only boundary curves",
    ] {
        assert!(e.contains(want), "'{want}' not in: {e}");
    }
    // The same through a problem file.
    let text = SQUARES_PROBLEM.replace(
        "square_41_bin.msh\", surfaces = [\"left\"]",
        "partial_curve_41.msh\"",
    );
    let e = model(&text).unwrap_err().to_string();
    assert!(e.contains("part 'left'") && e.contains("'cut' (16)"), "{e}");
    // Each square alone: "cut" is a boundary, counter-clockwise w.r.t. the part.
    let left = m.part_mesh("left", Some(&[name("left")])).unwrap();
    assert_eq!(
        segments(&left, "cut"),
        [[[1.0, 0.0], [1.0, 1.0]], [[1.0, 1.0], [0.0, 1.0]]]
    );
    let right = m.part_mesh("right", Some(&[name("right")])).unwrap();
    assert_eq!(segments(&right, "cut"), [[[1.0, 1.0], [1.0, 0.0]]]);
    // Apart from "cut", the file is square_41.msh.
    let square = read("square_41.msh");
    for part in ["left", "right"] {
        let mut a = m.part_mesh(part, Some(&[name(part)])).unwrap();
        a.boundaries.remove("cut");
        let b = square.part_mesh(part, Some(&[name(part)])).unwrap();
        assert_same_mesh(&a, &b, part);
    }
}

/// Quadrilaterals are read (binary 4.1 and ASCII 2.2) into their own list and
/// become Q4 elements, counter-clockwise, alone or mixed with the file's
/// triangles in one part.
#[test]
fn quadrilaterals_are_read_as_q4() {
    for file in ["quads_41_bin.msh", "quads_22.msh"] {
        let m = read(file);
        assert_eq!(m.quads.len(), 1, "{file}");
        assert_eq!(
            m.quads[0].nodes.map(|n| m.nodes[n]),
            [[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]
        );
        assert_eq!(m.quads[0].physical, vec![2]);
        assert_eq!(m.triangles.len(), 4);
        let right = m.part_mesh("right", Some(&[name("right")])).unwrap();
        right.validate("right").unwrap();
        assert_eq!(right.counts(), (0, 1), "{file}");
        assert!(right.element_area(0) > 0.0);
        let both = m.part_mesh("plate", None).unwrap();
        both.validate("plate").unwrap();
        assert_eq!(both.counts(), (4, 1), "{file}");
        let area: f64 = (0..both.elements.len()).map(|e| both.element_area(e)).sum();
        assert!((area - 2.0).abs() < 1e-14, "{file}: {area}");
        let left = m.part_mesh("left", Some(&[name("left")])).unwrap();
        assert_eq!(left.counts(), (4, 0));
    }
}

/// Every truncation of a binary file before the end of its $Elements section is an
/// error naming the file, never a panic; later cuts (in the skipped section after
/// it) either fail or read the same mesh.
#[test]
fn truncated_binary_files_are_errors() {
    for file in [
        "square_41_bin.msh",
        "square_22_bin.msh",
        "square_41_bin_be.msh",
    ] {
        let bytes = std::fs::read(data(file)).unwrap();
        let full = GmshMesh::parse(&bytes, Path::new(file)).unwrap();
        let end = bytes
            .windows(12)
            .position(|w| w == b"$EndElements")
            .unwrap()
            + 12;
        for len in 0..bytes.len() {
            match GmshMesh::parse(&bytes[..len], Path::new(file)) {
                Err(e) => assert!(e.to_string().contains(file), "{e}"),
                Ok(m) => assert!(len >= end && m == full, "{file} cut at {len} parsed"),
            }
        }
    }
}

/// The seed's plate on a base from one Gmsh file (transfinite meshes, cells split
/// along the rising diagonal) gives exactly the built-in structured meshes: the same
/// triangles and the same named boundaries, up to node numbering and round-off.
#[test]
fn gmsh_plate_on_base_matches_the_structured_meshes() {
    let m = read("plate_on_base_41.msh");
    let cases = [
        (
            "base",
            Mesh::rectangle([0.0, 200.0], [0.0, 120.0], [20, 12], ElementKind::T3),
        ),
        (
            "plate",
            Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6], ElementKind::T3),
        ),
    ];
    let key = |p: [f64; 2]| ((p[0] * 1e6).round() as i64, (p[1] * 1e6).round() as i64);
    for (part, structured) in cases {
        let g = m.part_mesh(part, Some(&[name(part)])).unwrap();
        g.validate(part).unwrap();
        assert_eq!(g.nodes.len(), structured.nodes.len());
        let triangles = |mesh: &Mesh| {
            let mut t: Vec<_> = mesh
                .elements
                .iter()
                .map(|el| {
                    let mut k: Vec<_> = el.nodes().iter().map(|&n| key(mesh.nodes[n])).collect();
                    k.sort();
                    k
                })
                .collect();
            t.sort();
            t
        };
        assert_eq!(triangles(&g), triangles(&structured), "{part}");
        for side in ["bottom", "right", "top", "left"] {
            let edges = |mesh: &Mesh| {
                let mut e: Vec<_> = mesh.boundaries[side]
                    .iter()
                    .map(|e| e.nodes.map(|n| key(mesh.nodes[n])))
                    .collect();
                e.sort();
                e
            };
            assert_eq!(edges(&g), edges(&structured), "{part} {side}");
        }
    }
}

/// Gmsh's own binary and MSH 2.2 output of the plate on a base reads to the same
/// meshes as its MSH 4.1 ASCII output (nodes to the 16 digits Gmsh prints in ASCII).
#[test]
fn gmsh_written_formats_agree() {
    let reference = read("plate_on_base_41.msh");
    for file in [
        "plate_on_base_41_bin.msh",
        "plate_on_base_22.msh",
        "plate_on_base_22_bin.msh",
    ] {
        let m = read(file);
        for part in ["base", "plate"] {
            let a = m.part_mesh(part, Some(&[name(part)])).unwrap();
            let b = reference.part_mesh(part, Some(&[name(part)])).unwrap();
            assert_eq!(a.nodes.len(), b.nodes.len(), "{file} {part}");
            for (p, q) in a.nodes.iter().zip(&b.nodes) {
                assert!(
                    cfe::mesh::dist(*p, *q) < 1e-12 * 200.0,
                    "{file} {part}: {p:?} {q:?}"
                );
            }
            assert_eq!(a.elements, b.elements, "{file} {part}: elements");
            assert_eq!(a.boundaries, b.boundaries, "{file} {part}: boundaries");
        }
    }
}

/// Σ (F_int − F_ext) over the nodes of support `s`: its reaction.
fn reaction(a: &Analysis, inc: &IncrementResult, s: usize) -> [f64; 2] {
    let support = &a.model.supports[s];
    let mut r = [0.0; 2];
    for &n in &support.nodes {
        let g = a.dofs.node(support.part, n);
        for (k, rk) in r.iter_mut().enumerate() {
            *rk += inc.f_int[2 * g + k] - inc.f_ext[2 * g + k];
        }
    }
    r
}

/// (x, bonded, force_n) per pair, sorted by x.
fn pairs_by_x(a: &Analysis, inc: &IncrementResult) -> Vec<(f64, bool, f64)> {
    let mut rows: Vec<_> = a
        .pair_rows(inc)
        .into_iter()
        .map(|r| (r.x, r.state == PairState::Bonded, r.force_n))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    rows
}

/// Solves the plate on a base with both parts from the shared Gmsh file
/// (tests/data/gmsh/plate_on_base.toml) and as examples/plate_on_base.toml, both at
/// refinement `refine`, and checks that they agree: the same pairs with the same
/// states and forces (to 1e-6 of the largest), the same reactions, and the
/// load-point displacement to `rel` (relative). Returns (pairs, open pairs).
fn gmsh_and_structured_plate_on_base_agree(refine: usize, rel: f64) -> (usize, usize) {
    let gmsh =
        Analysis::new(Model::from_file(&data("plate_on_base.toml"), refine).unwrap()).unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("examples/plate_on_base.toml");
    let structured = Analysis::new(Model::from_file(&example, refine).unwrap()).unwrap();
    for (g, s) in gmsh.model.parts.iter().zip(&structured.model.parts) {
        assert_eq!(
            g.mesh.nodes.len(),
            s.mesh.nodes.len(),
            "{} K = {refine}",
            g.name
        );
        assert_eq!(
            g.mesh.elements.len(),
            s.mesh.elements.len(),
            "{} K = {refine}",
            g.name
        );
    }
    let (g, s) = (common::solve(&gmsh), common::solve(&structured));
    let (g, s) = (g.last().unwrap(), s.last().unwrap());
    let (rg, rs) = (reaction(&gmsh, g, 0), reaction(&structured, s, 0));
    assert!((rg[1] - 1500.0).abs() < 1e-8 * 1500.0, "{rg:?}");
    assert!((rg[0] - rs[0]).abs() < 1e-8 * 1500.0 && (rg[1] - rs[1]).abs() < 1e-8 * 1500.0);
    let (pg, ps) = (pairs_by_x(&gmsh, g), pairs_by_x(&structured, s));
    assert_eq!(pg.len(), ps.len(), "K = {refine}");
    let fmax = ps.iter().map(|p| p.2.abs()).fold(0.0, f64::max);
    for (a, b) in pg.iter().zip(&ps) {
        assert!((a.0 - b.0).abs() < 1e-9, "{a:?} {b:?}");
        assert_eq!(a.1, b.1, "K = {refine}: state at x = {}", a.0);
        assert!(
            (a.2 - b.2).abs() < 1e-6 * fmax,
            "K = {refine}: force at x = {}: {a:?} {b:?}",
            a.0
        );
    }
    let top = [100.0, 135.0];
    let (ug, us) = (
        common::displacement_at(&gmsh, g, "plate", top),
        common::displacement_at(&structured, s, "plate", top),
    );
    assert!(
        (ug[1] - us[1]).abs() < rel * us[1].abs(),
        "K = {refine}: {ug:?} {us:?}"
    );
    (pg.len(), pg.iter().filter(|p| !p.1).count())
}

/// The plate on a base with both parts from the shared Gmsh file (physical
/// surfaces select the parts, physical curves name the interface, support and load
/// boundaries) solves like examples/plate_on_base.toml: 29 pairs with the same
/// states and forces, the same reactions and displacements.
#[test]
fn gmsh_plate_on_base_solves_like_the_structured_one() {
    assert_eq!(gmsh_and_structured_plate_on_base_agree(1, 1e-7), (29, 11));
}

/// With --refine 2 the Gmsh plate on a base, subdivided uniformly, solves like the
/// structured example with its cells doubled: 57 pairs, 20 of them open, each in
/// the same state with the same force, the same reactions, and the load-point
/// displacement to 1e-9 (relative).
#[test]
fn refined_gmsh_plate_on_base_solves_like_the_refined_structured_one() {
    assert_eq!(gmsh_and_structured_plate_on_base_agree(2, 1e-9), (57, 20));
}

/// An unstructured (Delaunay) Gmsh mesh of the plate on a base: one pair per node of
/// the plate's bottom, the reactions balance the load, bonded pairs form one run
/// that covers the loaded zone and the ends lift off.
#[test]
fn unstructured_gmsh_plate_on_base_solves() {
    let text = std::fs::read_to_string(data("plate_on_base.toml"))
        .unwrap()
        .replace("plate_on_base_41.msh", "plate_on_base_free.msh");
    let a = Analysis::new(model(&text).unwrap()).unwrap();
    let plate = &a.model.parts[1].mesh;
    let bottom = plate.boundary_nodes("bottom").unwrap();
    assert!(bottom.len() > 29, "{} bottom nodes", bottom.len());
    assert_eq!(a.interfaces[0].elements.len(), bottom.len());
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    let r = reaction(&a, last, 0);
    assert!(
        r[0].abs() < 1e-8 * 1500.0 && (r[1] - 1500.0).abs() < 1e-8 * 1500.0,
        "{r:?}"
    );
    let pairs = pairs_by_x(&a, last);
    let bonded: Vec<bool> = pairs.iter().map(|p| p.1).collect();
    let first = bonded.iter().position(|&b| b).unwrap();
    let end = bonded.iter().rposition(|&b| b).unwrap();
    assert!(bonded[first..=end].iter().all(|&b| b), "{bonded:?}");
    assert!(pairs[first].0 < 86.0 && pairs[end].0 > 114.0);
    assert!(!bonded[0] && !bonded[bonded.len() - 1]);
    assert!(last.states[0].contains(&PairState::Open));
}

/// Two squares from Gmsh files (the left chosen by its surface's name, the
/// right by number) tied across the physical curve "interface", the left held
/// on "sides" and at the origin, the right pulled on curve 13.
static SQUARES_PROBLEM: Text = Text::new(|| {
    Problem::spaced()
        .material("m", 1000.0, 0.25)
        .part("left", "m")
        .key(
            "gmsh",
            Raw("{ file = \"square_41_bin.msh\", surfaces = [\"left\"] }"),
        )
        .part("right", "m")
        .key("gmsh", Raw("{ file = \"square_22.msh\", surfaces = [2] }"))
        .interface("left", "right", "interface")
        .law("rigid")
        .support("left", "sides", ["x"])
        .support_at("left", [0.0, 0.0], ["y"])
        .load("right", "13", [1.0, 0.0])
        .text()
});

/// Physical curve names (and an unnamed curve's number) work as the boundaries of
/// interfaces, supports and loads, and surfaces are chosen by name or number: the
/// two squares tied across "interface" and pulled on curve 13 are in uniform
/// tension σxx = 1 (u = (2e-3, -2.5e-4) at (2, 1) with E = 1000, ν = 0.25).
#[test]
fn physical_curves_name_problem_boundaries() {
    let a = Analysis::new(model(&SQUARES_PROBLEM).unwrap()).unwrap();
    assert_eq!(a.interfaces[0].elements.len(), 2);
    let last = common::solve(&a).pop().unwrap();
    let u = common::displacement_at(&a, &last, "right", [2.0, 1.0]);
    assert!(
        (u[0] - 2e-3).abs() < 1e-8 && (u[1] + 2.5e-4).abs() < 1e-8,
        "{u:?}"
    );
    let r = reaction(&a, &last, 0);
    assert!((r[0] + 1.0).abs() < 1e-9, "{r:?}");
}

/// --refine K subdivides Gmsh parts: the two squares at K = 3 have 9× the
/// triangles and n + 2 per edge + 1 per triangle nodes, the right square's
/// interface edge gives K + 1 = 4 pairs, and they are still in uniform tension
/// (the same displacement at (2, 1) and reaction as at K = 1).
#[test]
fn refine_subdivides_gmsh_parts() {
    let m = Model::from_str(&SQUARES_PROBLEM, &data("inline.toml"), 3).unwrap();
    let counts: Vec<_> = m
        .parts
        .iter()
        .map(|p| (p.mesh.nodes.len(), p.mesh.elements.len()))
        .collect();
    assert_eq!(counts, [(5 + 8 * 2 + 4, 36), (4 + 5 * 2 + 2, 18)]);
    for p in &m.parts {
        p.mesh.validate(&p.name).unwrap();
    }
    let a = Analysis::new(m).unwrap();
    assert_eq!(a.interfaces[0].elements.len(), 4);
    let last = common::solve(&a).pop().unwrap();
    let u = common::displacement_at(&a, &last, "right", [2.0, 1.0]);
    assert!(
        (u[0] - 2e-3).abs() < 1e-8 && (u[1] + 2.5e-4).abs() < 1e-8,
        "{u:?}"
    );
    let r = reaction(&a, &last, 0);
    assert!((r[0] + 1.0).abs() < 1e-9, "{r:?}");
}

/// Problem-file errors for Gmsh parts: both or neither of `rectangle` and `gmsh`,
/// a missing file, an unknown surface (listing the file's
/// surfaces), an unknown boundary (listing the part's physical curves), a bad
/// `surfaces` entry, and an unknown key in `gmsh`.
#[test]
fn problem_file_errors_for_gmsh_parts() {
    let err = |text: &str| model(text).unwrap_err().to_string();
    let both = SQUARES_PROBLEM.replacen(
        "gmsh = { file",
        "rectangle = { x = [0.0, 1.0], y = [0.0, 1.0], cells = [1, 1] }\ngmsh = { file",
        1,
    );
    let e = err(&both);
    assert!(
        e.contains("more than one of `rectangle`, `annulus` and `gmsh`") && e.contains("line 7"),
        "{e}"
    );
    let neither = SQUARES_PROBLEM.replacen(
        "gmsh = { file = \"square_41_bin.msh\", surfaces = [\"left\"] }\n",
        "",
        1,
    );
    let e = err(&neither);
    assert!(
        e.contains("part 'left' has no mesh") && e.contains("gmsh = {"),
        "{e}"
    );
    let e = err(&SQUARES_PROBLEM.replace("square_22.msh", "nowhere.msh"));
    assert!(
        e.contains("part 'right': cannot read Gmsh file") && e.contains("nowhere.msh"),
        "{e}"
    );
    let e = err(&SQUARES_PROBLEM.replace("[\"left\"]", "[\"lft\"]"));
    assert!(
        e.contains("part 'left'")
            && e.contains("no physical surface 'lft'")
            && e.contains("'left' (1), 'right' (2)"),
        "{e}"
    );
    let e = err(&SQUARES_PROBLEM.replace("boundary = \"13\"", "boundary = \"14\""));
    assert!(
        e.contains("no boundary named '14'") && e.contains("13, bottom, interface, sides, top"),
        "{e}"
    );
    let e = err(&SQUARES_PROBLEM.replace("surfaces = [2]", "surfaces = [2.5]"));
    assert!(
        e.contains("physical surface name (string) or number (integer)"),
        "{e}"
    );
    let e = err(&SQUARES_PROBLEM.replace("surfaces = [2]", "surface = [2]"));
    assert!(e.contains("surface"), "{e}");
}

/// The Gmsh-made mixed mesh (make_mixed.py: 2 × 1 rectangle, 4 Q4 on the left
/// half, 8 T3 on the right, conforming along x = 1) is one part of 12 elements of
/// both kinds, counter-clockwise, filling the rectangle, with its four sides named
/// and exactly its free edges.
#[test]
fn mixed_triangles_and_quadrilaterals_make_one_part() {
    let m = read("mixed.msh");
    let body = m.part_mesh("body", Some(&[name("body")])).unwrap();
    body.validate("body").unwrap();
    assert_eq!(body.counts(), (8, 4));
    assert_eq!(body.nodes.len(), 15);
    let area: f64 = (0..body.elements.len()).map(|e| body.element_area(e)).sum();
    assert!((area - 2.0).abs() < 1e-14);
    let names: Vec<&String> = body.boundaries.keys().collect();
    assert_eq!(names, ["bottom", "left", "right", "top"]);
    let mut named: Vec<_> = body.boundaries.values().flatten().copied().collect();
    let mut free = body.boundary_edges();
    named.sort_by_key(|e| (e.element, e.nodes));
    free.sort_by_key(|e| (e.element, e.nodes));
    assert_eq!(named, free);
    // The left side belongs to quadrilaterals, the right side to triangles.
    let kind = |side: &str| {
        body.boundaries[side]
            .iter()
            .map(|e| body.elements[e.element].kind())
            .collect::<Vec<_>>()
    };
    assert!(kind("left").iter().all(|k| *k == ElementKind::Q4));
    assert!(kind("right").iter().all(|k| *k == ElementKind::T3));
}

/// A tangled mesh — one node of a triangle swapped (302: 2 5 100 → 2 5 1), so that
/// it overlaps its neighbours while every element on its own is valid — is an
/// error naming the file's elements, not a run with a wrong answer.
#[test]
fn tangled_mesh_is_an_error() {
    let text = std::fs::read_to_string(data("square_41.msh")).unwrap();
    assert!(text.contains("\n302 2 5 100\n"));
    let tangled = text.replace("\n302 2 5 100\n", "\n302 2 5 1\n");
    let dir = std::env::temp_dir().join(format!("cfe-tangled-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("tangled.msh");
    std::fs::write(&path, tangled).unwrap();
    let m = GmshMesh::read(&path).unwrap();
    let e = m.part_mesh("all", None).unwrap_err();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(matches!(e, cfe::Error::Mesh { .. }), "{e:?}");
    let e = e.to_string();
    assert!(e.contains("part 'all'") && e.contains("tangled.msh"), "{e}");
    assert!(e.contains("302"), "the swapped element is not named: {e}");
    assert!(e.contains("folds over"), "{e}");

    // The untangled file reads as before.
    read("square_41.msh").part_mesh("all", None).unwrap();
}

// ------------------------------------------------------------ strict reading

/// The text of a test mesh.
fn text_of(name: &str) -> String {
    std::fs::read_to_string(data(name)).unwrap()
}

/// The error of reading `bytes` as a Gmsh file: it must be `Error::Parse` naming
/// the file; returns its line and message.
fn refused(bytes: &[u8], case: &str) -> (Option<usize>, String) {
    match GmshMesh::parse(bytes, Path::new("bad.msh")) {
        Ok(_) => panic!("{case}: accepted"),
        Err(cfe::Error::Parse {
            path,
            line,
            message,
        }) => {
            assert_eq!(path, Path::new("bad.msh"), "{case}");
            (line, message)
        }
        Err(e) => panic!("{case}: not a parse error: {e:?}"),
    }
}

/// `text` with `from` (which must occur once) replaced by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from}");
    text.replacen(from, to, 1)
}

/// The 1-based line of `text` that starts with `start` (once).
fn line_of(text: &str, start: &str) -> usize {
    let found: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with(start))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(found.len(), 1, "{start}: {found:?}");
    found[0]
}

/// MSH 4.1 element blocks must fit `$Entities` (the auditor's silent wrong
/// answers): a block whose entity is not listed, whose dimension does not fit
/// its element type, or out of range, and a listed entity dropped, are errors
/// naming the block's line and the entity (an element outside its entity's
/// bounding box, its own line) — not elements without a physical
/// group, left out of their part.
#[test]
fn element_blocks_must_fit_their_entities() {
    let sq = text_of("square_41.msh");
    let cases = [
        (
            edit(&sq, "2 2 2 2\n401", "2 9 2 2\n401"),
            "2 9 2 2",
            "in entity 9 of dimension 2, which $Entities does not list",
        ),
        (
            edit(&sq, "2 1 2 4\n301", "1 1 2 4\n301"),
            "1 1 2 4",
            "has dimension 1, but its elements (3-node triangles, type 2) have dimension 2",
        ),
        (
            edit(&sq, "1 7 1 1\n207", "5 7 1 1\n207"),
            "5 7 1 1",
            "has dimension 5, but its elements (2-node lines, type 1) have dimension 1",
        ),
        (
            edit(&sq, "0 1 15 1\n501", "1 1 15 1\n501"),
            "1 1 15 1",
            "has dimension 1, but its elements (1-node points, type 15) have dimension 0",
        ),
        // A line moved to another curve entity (bottom → the right side): its
        // nodes lie outside that curve's bounding box.
        (
            edit(&sq, "1 2 1 1\n202", "1 3 1 1\n202"),
            "202 2 3",
            "element 202 (2-node line, line 63) of entity 3 (dimension 1) has node 2 at (1, 0, 0.25), outside the entity's bounding box (2, 0, 0.25) to (2, 1, 0.25)",
        ),
        // The right square's entity dropped from $Entities: its two triangles
        // would have been read with no physical group (a hole in "right").
        (
            edit(
                &edit(&sq, "6 7 2 0\n", "6 7 1 0\n"),
                "2 1.0 0.0 0.25 2.0 1.0 0.25 1 2 4 2 3 -4 -7\n",
                "",
            ),
            "2 2 2 2",
            "2 3-node triangles is in entity 2 of dimension 2, which $Entities does not list",
        ),
        // A curve entity dropped: its line would have left the support "bottom".
        (
            edit(
                &edit(&sq, "6 7 2 0\n", "6 6 2 0\n"),
                "2 1.0 0.0 0.25 2.0 0.0 0.25 1 11 2 2 -3\n",
                "",
            ),
            "1 2 1 1",
            "in entity 2 of dimension 1, which $Entities does not list",
        ),
    ];
    for (text, block, words) in cases {
        let (line, message) = refused(text.as_bytes(), block);
        let l = text[..text.find(block).unwrap()].matches('\n').count() + 1;
        assert_eq!(line, Some(l), "{block}: {message}");
        assert!(message.contains(words), "{block}: {message}");
    }
}

/// A binary MSH 4.1 file whose element block names an entity $Entities lacks
/// (one flipped byte, as in the auditor's fuzz seed 292) is refused at the
/// block's byte; the file read whole is unchanged.
#[test]
fn binary_element_block_with_unknown_entity_is_refused() {
    let data = std::fs::read(data("square_41_bin.msh")).unwrap();
    // The block header of the right square's 2 triangles: dim 2, entity 2, type 2
    // (int), 2 elements (size_t).
    let mut header: Vec<u8> = [2i32, 2, 2].iter().flat_map(|v| v.to_le_bytes()).collect();
    header.extend(2u64.to_le_bytes());
    let at = data
        .windows(header.len())
        .position(|w| w == header.as_slice())
        .unwrap();
    let mut bad = data.clone();
    bad[at + 4] ^= 0x08; // entity 2 → 10
    let (line, message) = refused(&bad, "binary block");
    assert_eq!(line, None);
    assert!(
        message.contains(&format!("byte {at}"))
            && message.contains("entity 10 of dimension 2, which $Entities does not list"),
        "{message}"
    );
}

/// Counts and tag ranges of the section headers must be those of the data; tags
/// must be unique; an element may not repeat another's nodes (4.1); an element
/// line may not hold a value too many; physical names need $Entities (4.1).
#[test]
fn headers_tags_and_repeats_must_be_consistent() {
    let sq = text_of("square_41.msh");
    let cases = [
        (
            edit(&sq, "10 14 201 501", "10 13 201 501"),
            Some("10 13 201 501"),
            "the $Elements header announces 13 elements, but its blocks hold 14",
        ),
        (
            edit(&sq, "10 14 201 501", "10 14 201 502"),
            Some("10 14 201 502"),
            "gives element tags 201 to 502, but the elements' tags run from 201 to 501",
        ),
        (
            edit(&sq, "7 7 1 100", "7 8 1 100"),
            Some("7 8 1 100"),
            "the $Nodes header announces 8 nodes, but its blocks hold 7",
        ),
        (
            edit(&sq, "7 7 1 100", "7 7 1 99"),
            Some("7 7 1 99"),
            "gives node tags 1 to 99, but the nodes' tags run from 1 to 100",
        ),
        (
            edit(&sq, "402 2 5 40", "401 2 5 40"),
            Some("401 2 5 40"),
            "element 401 (3-node triangle, line 81) has the tag of element 401 (3-node triangle, line 80)",
        ),
        (
            edit(&sq, "402 2 5 40", "402 40 3 2"),
            Some("402 40 3 2"),
            "has the same nodes as element 401 (3-node triangle, line 80): MSH 4.1 lists each element once",
        ),
        (
            edit(&sq, "301 1 2 100", "301 1 2 100 5"),
            Some("301 1 2 100 5"),
            "unexpected '5' at the end of an element's line",
        ),
        (
            {
                let a = sq.find("$Entities").unwrap();
                let b = sq.find("$EndEntities\n").unwrap() + 13;
                format!("{}{}", &sq[..a], &sq[b..])
            },
            None,
            "names physical groups ('corner', ...) but has no $Entities section",
        ),
    ];
    for (text, at, words) in cases {
        let (line, message) = refused(text.as_bytes(), words);
        assert_eq!(line, at.map(|a| line_of(&text, a)), "{words}: {message}");
        assert!(message.contains(words), "{message}");
    }
}

/// MSH 2.2 gives physical groups per element: a triangle whose group differs
/// from its entity's other elements (it would leave a hole in "left"), and a
/// repeat that is no copy for another group, are refused, naming both elements.
#[test]
fn msh22_elements_of_an_entity_share_its_groups() {
    let sq = text_of("square_22.msh");
    let hole = edit(&sq, "302 2 2 1 1 2 5 100", "302 2 2 7 1 2 5 100");
    let (line, message) = refused(hole.as_bytes(), "hole");
    assert_eq!(line, Some(line_of(&hole, "302 ")), "{message}");
    assert!(
        message.contains("element 302 (3-node triangle, line 36) of entity 1 (dimension 2) is in physical group(s) [7], but element 301 (3-node triangle, line 35) of the same entity is in [1]"),
        "{message}"
    );
    let repeat = edit(&sq, "304 2 2 1 1 60 100 1", "304 2 2 1 1 100 5 60");
    let (line, message) = refused(repeat.as_bytes(), "repeat");
    assert_eq!(line, Some(line_of(&repeat, "304 ")), "{message}");
    assert!(
        message.contains("element 304 (3-node triangle, line 38) has the same nodes as element 303 (3-node triangle, line 37): MSH 2.2 repeats an element only as a copy for another physical group of the same elementary entity"),
        "{message}"
    );
    // A copy for another group of the same entity is merged (square_22.msh's
    // line 203/600 on curve 3, in groups 13 and 15).
    let m = read("square_22.msh");
    let l = m.lines.iter().find(|l| l.tag == 203).unwrap();
    assert_eq!((l.physical.clone(), l.entity), (vec![13, 15], 3));
    assert!(m.lines.iter().all(|l| l.tag != 600));
}

/// A physical-curve line that is no element edge (a damaged node tag: "interface"
/// from node 2 to node 5 becomes 1 to 5, a diagonal of no triangle) is refused in
/// either format, naming the line element, its curve and its nodes — it was
/// silently dropped, leaving the boundary short.
#[test]
fn physical_curve_lines_must_be_element_edges() {
    // (4.1: curve 7's bounding box widened to hold node 1, else the line is
    // refused as outside its entity.)
    let sq41 = edit(
        &text_of("square_41.msh"),
        "7 1.0 0.0 0.25 1.0 1.0 0.25",
        "7 0.0 0.0 0.25 1.0 1.0 0.25",
    );
    for (file, original, from, to, start) in [
        ("square_41.msh", sq41, "207 2 5", "207 1 5", "207 "),
        (
            "square_22.msh",
            text_of("square_22.msh"),
            "207 1 2 14 7 2 5",
            "207 1 2 14 7 1 5",
            "207 ",
        ),
    ] {
        let text = edit(&original, from, to);
        let (line, message) = refused(text.as_bytes(), file);
        let l = line_of(&text, start);
        assert_eq!(line, Some(l), "{message}");
        assert!(
            message.contains(&format!(
                "element 207 (2-node line, line {l}) of physical curve 'interface' (14), from node 1 to node 5, is not an edge of any triangle or quadrilateral of the file"
            )),
            "{file}: {message}"
        );
    }
}

/// Line endings and byte-order marks are named as such: a CR-only file (it was
/// "section $NodeData has no $EndNodeData"), and a UTF-8 BOM; CR LF reads the
/// same mesh as LF.
#[test]
fn line_endings_and_byte_order_marks_are_named() {
    let sq = text_of("square_41.msh");
    let (line, message) = refused(sq.replace('\n', "\r").as_bytes(), "CR");
    assert_eq!(line, Some(1));
    assert!(
        message.contains("end in a carriage return alone (CR, classic Mac OS line endings)"),
        "{message}"
    );
    let (line, message) = refused(format!("\u{FEFF}{sq}").as_bytes(), "BOM");
    assert_eq!(line, Some(1));
    assert!(
        message.contains("starts with a UTF-8 byte-order mark (bytes EF BB BF)"),
        "{message}"
    );
    let crlf =
        GmshMesh::parse(sq.replace('\n', "\r\n").as_bytes(), &data("square_41.msh")).unwrap();
    assert_eq!(crlf, read("square_41.msh"));
}

/// A binary header that does not match its data is named as such: the
/// endianness marker written big-endian before little-endian data (it read as
/// 16777216 little-endian), a data size 4 before 8-byte sizes, a data size 4 in
/// MSH 2.2, and a damaged marker.
#[test]
fn binary_headers_that_do_not_match_their_data_are_named() {
    let le = std::fs::read(data("square_41_bin.msh")).unwrap();
    let marker = le.windows(8).position(|w| w == b"4.1 1 8\n").unwrap() + 8;
    assert_eq!(&le[marker..marker + 4], &1i32.to_le_bytes());
    let mut big = le.clone();
    big[marker..marker + 4].copy_from_slice(&1i32.to_be_bytes());
    let (_, message) = refused(&big, "big-endian marker");
    assert!(
        message.contains("the binary header says big-endian, data size 8 (8-byte size_t) but the data reads as little-endian, data size 8 (8-byte size_t)"),
        "{message}"
    );
    let four = edit_bytes(&le, b"4.1 1 8\n", b"4.1 1 4\n");
    let (_, message) = refused(&four, "data size 4");
    assert!(
        message.contains("the binary header says little-endian, data size 4 (4-byte size_t) but the data reads as little-endian, data size 8 (8-byte size_t)"),
        "{message}"
    );
    let v22 = std::fs::read(data("square_22_bin.msh")).unwrap();
    let (_, message) = refused(&edit_bytes(&v22, b"2.2 1 8\n", b"2.2 1 4\n"), "2.2 size 4");
    assert!(
        message.contains("the header gives data size 4 (the size of size_t); a binary MSH 2.2 file has data size 8"),
        "{message}"
    );
    let mut two = le.clone();
    two[marker] = 2;
    let (_, message) = refused(&two, "marker 2");
    assert!(
        message.contains("reads as 2 little-endian and 33554432 big-endian"),
        "{message}"
    );
    // The big-endian file with 4-byte sizes is read as its header says.
    assert_eq!(
        read("square_41_bin_be.msh").nodes,
        read("square_41.msh").nodes
    );
}

/// `data` with `from` (once) replaced by `to` of the same length.
fn edit_bytes(data: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    let at = data.windows(from.len()).position(|w| w == from).unwrap();
    let mut d = data.to_vec();
    d[at..at + to.len()].copy_from_slice(to);
    d
}
