//! Gmsh 3D input: the two cubes of tests/data/gmsh/cubes_*.msh (written by Gmsh from
//! make_cubes_3d.py: a HEX8 cube and a TET4 cube side by side, each meshed on its
//! own) read the same from every encoding into solid parts of the cubes' volumes,
//! with named boundaries of the right areas and outward normals; small meshes
//! written here check the errors.

use cfe::dim::D3;
use cfe::mesh::gmsh::{Element, GmshFile, GmshMesh, GmshMesh3d, Group, MshVersion, read_gmsh_3d};
use cfe::mesh::{BoundaryFace, Mesh, SolidElement};
use cfe::{Error, Result};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("tests/data/gmsh")
        .join(name)
}

const CUBES: [&str; 4] = [
    "cubes_41.msh",
    "cubes_41_bin.msh",
    "cubes_22.msh",
    "cubes_22_bin.msh",
];

fn parts(name: &str) -> Vec<(String, Mesh<D3>)> {
    read_gmsh_3d(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn part<'a>(parts: &'a [(String, Mesh<D3>)], name: &str) -> &'a Mesh<D3> {
    &parts.iter().find(|(n, _)| n == name).unwrap().1
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn centroid(points: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    let (mut c, mut n) = ([0.0; 3], 0.0);
    for p in points {
        for k in 0..3 {
            c[k] += p[k];
        }
        n += 1.0;
    }
    c.map(|v| v / n)
}

/// The volume of an element: a tetrahedron's by its triple product, a
/// hexahedron's by 2×2×2 Gauss integration of its trilinear map's Jacobian (exact:
/// the Jacobian is of degree 2 in each natural coordinate).
fn volume(m: &Mesh<D3>, e: &SolidElement) -> f64 {
    let x = |k: usize| m.nodes[e.nodes()[k]];
    match e {
        SolidElement::Tet4(_) => {
            dot(sub(x(1), x(0)), cross(sub(x(2), x(0)), sub(x(3), x(0)))) / 6.0
        }
        SolidElement::Hex8(_) => {
            // Natural corners in Gmsh order.
            let s: [[f64; 3]; 8] = [
                [-1., -1., -1.],
                [1., -1., -1.],
                [1., 1., -1.],
                [-1., 1., -1.],
                [-1., -1., 1.],
                [1., -1., 1.],
                [1., 1., 1.],
                [-1., 1., 1.],
            ];
            let g = 1.0 / 3f64.sqrt();
            let mut v = 0.0;
            for p in [
                [-g, -g, -g],
                [g, -g, -g],
                [g, g, -g],
                [-g, g, -g],
                [-g, -g, g],
                [g, -g, g],
                [g, g, g],
                [-g, g, g],
            ] {
                // J's columns, the derivatives ∂x/∂ξ_d (Gauss weights 1).
                let mut cols = [[0.0; 3]; 3];
                for (a, sa) in s.iter().enumerate() {
                    for (d, col) in cols.iter_mut().enumerate() {
                        let mut dn = sa[d] / 8.0;
                        for o in 0..3 {
                            if o != d {
                                dn *= 1.0 + sa[o] * p[o];
                            }
                        }
                        for (v, xa) in col.iter_mut().zip(x(a)) {
                            *v += dn * xa;
                        }
                    }
                }
                v += dot(cols[0], cross(cols[1], cols[2]));
            }
            v
        }
    }
}

/// A face's area and unit normal by the right-hand rule (a quadrangle as two
/// triangles; the cubes' faces are plane).
fn area_normal(m: &Mesh<D3>, f: &BoundaryFace) -> (f64, [f64; 3]) {
    let x: Vec<[f64; 3]> = f.nodes.as_slice().iter().map(|&n| m.nodes[n]).collect();
    let mut a = [0.0; 3];
    for k in 1..x.len() - 1 {
        let c = cross(sub(x[k], x[0]), sub(x[k + 1], x[0]));
        for d in 0..3 {
            a[d] += 0.5 * c[d];
        }
    }
    let area = dot(a, a).sqrt();
    (area, a.map(|v| v / area))
}

/// A file's elements as (nodes, physical groups, entity), sorted: MSH 2.2 lists
/// and numbers the elements by physical group, 4.1 by entity.
fn by_nodes<const N: usize>(elements: &[Element<N>]) -> Vec<([usize; N], &[i32], i32)> {
    let mut out: Vec<_> = elements
        .iter()
        .map(|e| (e.nodes, &e.physical[..], e.entity))
        .collect();
    out.sort();
    out
}

/// MSH 4.1 and 2.2, ASCII and binary, read to identical solid parts (nodes,
/// elements, named boundaries) and identical file contents.
#[test]
fn encodings_give_identical_meshes() {
    let reference = parts(CUBES[0]);
    let file0 = GmshMesh3d::read(&data(CUBES[0])).unwrap();
    assert_eq!(file0.version, MshVersion::V41);
    assert_eq!(
        reference
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>(),
        ["hexa", "tetra"]
    );
    for name in &CUBES[1..] {
        let other = parts(name);
        assert_eq!(other.len(), reference.len(), "{name}");
        for ((na, a), (nb, b)) in reference.iter().zip(&other) {
            assert_eq!(na, nb, "{name}");
            assert_eq!(a.nodes, b.nodes, "{name}: {na}: nodes");
            assert_eq!(a.elements, b.elements, "{name}: {na}: elements");
            assert_eq!(a.boundaries, b.boundaries, "{name}: {na}: boundaries");
        }
        let f = GmshMesh3d::read(&data(name)).unwrap();
        assert_eq!(f.binary, name.contains("bin"), "{name}");
        assert_eq!(
            (&f.node_tags, &f.nodes, &f.physical_names),
            (&file0.node_tags, &file0.nodes, &file0.physical_names),
            "{name}"
        );
        assert_eq!(
            by_nodes(&f.tetrahedra),
            by_nodes(&file0.tetrahedra),
            "{name}"
        );
        assert_eq!(by_nodes(&f.hexahedra), by_nodes(&file0.hexahedra), "{name}");
        assert_eq!(by_nodes(&f.triangles), by_nodes(&file0.triangles), "{name}");
        assert_eq!(by_nodes(&f.quads), by_nodes(&file0.quads), "{name}");
    }
}

/// Each part is the unit cube it meshes: every element of positive volume, the
/// volumes summing to 1, the nodes in its box, HEX8 in "hexa" and TET4 in "tetra".
#[test]
fn parts_fill_the_cubes() {
    let parts = parts("cubes_41.msh");
    for (name, x0, hex) in [("hexa", 0.0, true), ("tetra", 1.0, false)] {
        let m = part(&parts, name);
        assert!(!m.elements.is_empty());
        assert!(
            m.elements
                .iter()
                .all(|e| matches!(e, SolidElement::Hex8(_)) == hex),
            "{name}"
        );
        let mut total = 0.0;
        for e in &m.elements {
            let v = volume(m, e);
            assert!(v > 0.0, "{name}: {e:?} has volume {v}");
            total += v;
        }
        assert!((total - 1.0).abs() < 1e-12, "{name}: volume {total}");
        for p in &m.nodes {
            assert!(
                p[0] >= x0 - 1e-12 && p[0] <= x0 + 1.0 + 1e-12,
                "{name}: {p:?}"
            );
            assert!(
                (0.0..=1.0).contains(&p[1]) && (0.0..=1.0).contains(&p[2]),
                "{name}: {p:?}"
            );
        }
        assert!(m.unused_nodes().is_empty(), "{name}");
    }
    assert_eq!(part(&parts, "hexa").elements.len(), 8);
    assert_eq!(part(&parts, "hexa").nodes.len(), 27);
}

/// Each physical surface is a named boundary of the part it bounds, with the area
/// of its cube face and the face's outward normal on every face (the normal also
/// points from the owning element's centroid to the face's); a surface without a
/// name is named by its number, and a part lacks the surfaces of the other.
#[test]
fn named_boundaries_have_their_areas_and_outward_normals() {
    let parts = parts("cubes_22_bin.msh");
    // Per part: its boundaries and their outward normals.
    type Boundaries<'a> = &'a [(&'a str, [f64; 3])];
    let expected: [(&str, Boundaries); 2] = [
        (
            "hexa",
            &[
                ("15", [0.0, 1.0, 0.0]),
                ("bottom", [0.0, 0.0, -1.0]),
                ("fixed", [-1.0, 0.0, 0.0]),
                ("interface", [1.0, 0.0, 0.0]),
            ],
        ),
        (
            "tetra",
            &[
                ("bottom", [0.0, 0.0, -1.0]),
                ("interface", [-1.0, 0.0, 0.0]),
                ("load", [1.0, 0.0, 0.0]),
            ],
        ),
    ];
    for (name, boundaries) in expected {
        let m = part(&parts, name);
        assert_eq!(
            m.boundaries.keys().map(String::as_str).collect::<Vec<_>>(),
            boundaries.iter().map(|b| b.0).collect::<Vec<_>>(),
            "{name}"
        );
        for (b, n) in boundaries {
            let mut area = 0.0;
            for f in &m.boundaries[*b] {
                let (a, normal) = area_normal(m, f);
                area += a;
                assert!(
                    dot(normal, *n) > 1.0 - 1e-12,
                    "{name}.{b}: {f:?} normal {normal:?}"
                );
                let el = m.elements[f.element];
                assert_eq!(el.face(f.face), f.nodes, "{name}.{b}");
                let c_face = centroid(f.nodes.as_slice().iter().map(|&k| m.nodes[k]));
                let c_el = centroid(el.nodes().iter().map(|&k| m.nodes[k]));
                assert!(dot(normal, sub(c_face, c_el)) > 0.0, "{name}.{b}: {f:?}");
            }
            assert!((area - 1.0).abs() < 1e-12, "{name}.{b}: area {area}");
        }
    }
}

/// The interface, one physical surface over the touching faces of both cubes, is
/// found on both parts: every element of it in the file is a face of exactly one
/// part (matched by its corners' coordinates), the two sides facing each other.
#[test]
fn interface_faces_are_found_on_both_parts() {
    let file = GmshMesh3d::read(&data("cubes_41_bin.msh")).unwrap();
    let parts = file.parts().unwrap();
    let key = |mut pts: Vec<[f64; 3]>| {
        pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        format!("{pts:?}")
    };
    let mut in_file: Vec<String> = file
        .triangles
        .iter()
        .filter(|e| e.physical.contains(&12))
        .map(|e| key(e.nodes.iter().map(|&n| file.nodes[n]).collect()))
        .chain(
            file.quads
                .iter()
                .filter(|e| e.physical.contains(&12))
                .map(|e| key(e.nodes.iter().map(|&n| file.nodes[n]).collect())),
        )
        .collect();
    let mut on_parts = Vec::new();
    for (name, normal) in [("hexa", 1.0), ("tetra", -1.0)] {
        let m = part(&parts, name);
        let faces = &m.boundaries["interface"];
        assert!(!faces.is_empty(), "{name}");
        for f in faces {
            assert!((area_normal(m, f).1[0] - normal).abs() < 1e-12, "{name}");
            on_parts.push(key(f
                .nodes
                .as_slice()
                .iter()
                .map(|&n| m.nodes[n])
                .collect()));
        }
    }
    in_file.sort();
    on_parts.sort();
    assert_eq!(on_parts, in_file);
}

/// Two tetrahedra sharing the face 1-2-3, each its own physical volume ("up" and
/// "down", the second written with a negative volume), the shared face a physical
/// surface "mid", and an outer face of "up" in "cut" with it (MSH 2.2 writes the shared
/// face twice, once per physical surface: read as one element, 10, in both).
const TWO_TETS: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
4
2 7 \"mid\"
2 8 \"cut\"
3 1 \"up\"
3 2 \"down\"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 0 0 -1
$EndNodes
$Elements
5
10 2 2 7 5 1 2 3
11 2 2 8 5 1 2 3
12 2 2 8 7 1 2 4
20 4 2 1 1 1 2 3 4
21 4 2 2 2 1 2 3 5
$EndElements
";

fn parse3(text: &str) -> Result<GmshMesh3d> {
    GmshMesh3d::parse(text.as_bytes(), Path::new("tets.msh"))
}

/// A face shared by two physical volumes that share their nodes (a conformal
/// mesh) is a boundary of both parts, outward from each (−z from "up", +z from
/// "down"); an element written with a negative volume is mirrored to a positive
/// one.
#[test]
fn shared_face_of_two_volumes_bounds_both() {
    let file = parse3(TWO_TETS).unwrap();
    let parts = file.parts().unwrap();
    assert_eq!(parts.len(), 2);
    for (name, nz) in [("up", -1.0), ("down", 1.0)] {
        let m = part(&parts, name);
        assert_eq!(m.nodes.len(), 4, "{name}");
        assert!(
            (volume(m, &m.elements[0]) - 1.0 / 6.0).abs() < 1e-15,
            "{name}"
        );
        let mid = &m.boundaries["mid"];
        assert_eq!(mid.len(), 1, "{name}");
        let (area, n) = area_normal(m, &mid[0]);
        assert!(
            (area - 0.5).abs() < 1e-15 && (n[2] - nz).abs() < 1e-15,
            "{name}: {n:?}"
        );
    }
    // "cut" lies on the boundary of "up" alone: its two faces there.
    assert_eq!(part(&parts, "up").boundaries["cut"].len(), 2);
    assert_eq!(part(&parts, "down").boundaries["cut"].len(), 1);
}

/// A physical surface with one element on the part's boundary and one inside it
/// (the face between its two tetrahedra) is a typed mesh error naming the part,
/// the surface and the inner element; a surface wholly inside ("mid") is no
/// boundary of the part.
#[test]
fn surface_partly_inside_the_part_is_an_error() {
    let file = parse3(TWO_TETS).unwrap();
    match file.part_mesh("both", None) {
        Err(Error::Mesh { part, message }) => {
            assert_eq!(part, "both");
            assert!(
                message.contains("physical surface 'cut' (8)")
                    && message.contains("partly inside the part")
                    && message.contains("element 10 (3-node triangle)"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    let up_down = [Group::Name("up".into()), Group::Name("down".into())];
    let without_cut = TWO_TETS
        .replace("12 2 2 8 7 1 2 4\n", "")
        .replace("5\n10 2", "4\n10 2");
    let m = parse3(&without_cut)
        .unwrap()
        .part_mesh("both", Some(&up_down))
        .unwrap();
    assert_eq!(m.elements.len(), 2);
    assert!(!m.boundaries.contains_key("mid"));
    assert!(!m.boundaries.contains_key("cut"));
}

/// A physical-surface element that is no face of any volume element is refused
/// when the file is read, naming the element, its line and its surface.
#[test]
fn surface_on_no_element_face_is_refused() {
    let text = TWO_TETS.replace("12 2 2 8 7 1 2 4", "12 2 2 8 7 2 4 5");
    match parse3(&text) {
        Err(Error::Parse { line, message, .. }) => {
            assert_eq!(line, Some(23));
            assert!(
                message.contains("element 12 (3-node triangle")
                    && message.contains("physical surface 'cut' (8)")
                    && message.contains("not a face of any tetrahedron or hexahedron"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
}

/// Second-order volume elements (10-node tetrahedra, 27- and 20-node hexahedra)
/// are refused as the file is read, with the reason: their faces' nodal weights
/// break the sign test of the bonded-in-compression law.
#[test]
fn quadratic_elements_are_refused_with_the_reason() {
    for (t, n, what) in [
        (11, 10, "10-node tetrahedron"),
        (12, 27, "27-node hexahedron"),
        (17, 20, "20-node hexahedron"),
    ] {
        let nodes: String = (1..=n).map(|k| format!("{k} {} 0 0\n", k as f64)).collect();
        let ids: Vec<String> = (1..=n).map(|k| k.to_string()).collect();
        let text = format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{n}\n{nodes}$EndNodes\n$Elements\n1\n1 {t} 2 1 1 {}\n$EndElements\n",
            ids.join(" ")
        );
        for e in [
            parse3(&text).unwrap_err(),
            GmshMesh::parse(text.as_bytes(), Path::new("tets.msh")).unwrap_err(),
        ] {
            match e {
                Error::Parse { line, message, .. } => {
                    assert_eq!(line, Some(n + 9), "{message}");
                    assert!(
                        message.contains(&format!("element type {t} ({what})"))
                            && message.contains("second-order")
                            && message.contains("sign test of the bonded-in-compression law")
                            && message.contains("Mesh.ElementOrder = 1"),
                        "{message}"
                    );
                }
                other => panic!("{other:?}"),
            }
        }
    }
}

/// A hexahedron whose corner Jacobians differ in sign (two top nodes swapped: the
/// element is twisted) is refused as the file is read, naming its tag, its line and
/// the signs at its corners; the same hexahedron
/// mirrored as a whole (negative at every corner) is read with positive volume.
#[test]
fn inverted_hexahedron_is_reported() {
    let cube = |order: &str| {
        format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n$Elements\n1\n9 5 2 1 1 {order}\n$EndElements\n"
        )
    };
    match parse3(&cube("1 2 3 4 6 5 7 8")) {
        Err(Error::Parse { line, message, .. }) => {
            assert_eq!(line, Some(17));
            assert!(
                message.contains("element 9 (8-node hexahedron)")
                    && message.contains("inverted")
                    && message.contains("+ + + + − − + +"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    let mirrored = parse3(&cube("1 4 3 2 5 8 7 6")).unwrap();
    let m = mirrored.part_mesh("block", None).unwrap();
    assert!((volume(&m, &m.elements[0]) - 1.0).abs() < 1e-14);
}

/// The 2D reader refuses a 3D file (naming its first volume element), and
/// `GmshFile` tells the dimension of a file: a plane one reads exactly as
/// `GmshMesh` reads it.
#[test]
fn the_dimension_of_a_file_is_detected() {
    match GmshMesh::read(&data("cubes_41.msh")) {
        Err(Error::Parse { message, .. }) => {
            assert!(
                message.contains("is a 3D mesh") && message.contains("volume element"),
                "{message}"
            )
        }
        other => panic!("{other:?}"),
    }
    let solid = GmshFile::read(&data("cubes_22.msh")).unwrap();
    assert_eq!(solid.dimension(), 3);
    assert_eq!(
        solid,
        GmshFile::Solid(GmshMesh3d::read(&data("cubes_22.msh")).unwrap())
    );
    let plane = GmshFile::read(&data("square_41.msh")).unwrap();
    assert_eq!(plane.dimension(), 2);
    assert_eq!(
        plane,
        GmshFile::Plane(GmshMesh::read(&data("square_41.msh")).unwrap())
    );
    match GmshMesh3d::read(&data("square_41.msh")) {
        Err(Error::Parse { message, .. }) => {
            assert!(message.contains("no volume elements"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

/// Unknown volumes are named with the file's physical volumes; a volume element
/// type cfe has no element for (a 6-node prism) is refused as the file is read.
#[test]
fn unknown_volume_and_prisms_are_errors() {
    let file = parse3(TWO_TETS).unwrap();
    match file.part_mesh("p", Some(&[Group::Name("side".into())])) {
        Err(Error::Mesh { message, .. }) => assert!(
            message.contains("no physical volume 'side'")
                && message.contains("'up' (1), 'down' (2)"),
            "{message}"
        ),
        other => panic!("{other:?}"),
    }
    let prism = TWO_TETS.replace("21 4 2 2 2 1 2 3 5", "21 6 2 2 2 1 2 3 4 5 1");
    match parse3(&prism) {
        Err(Error::Parse { message, .. }) => assert!(
            message.contains("element type 6 (6-node prism)") && message.contains("not supported"),
            "{message}"
        ),
        other => panic!("{other:?}"),
    }
}

/// A problem file's `gmsh` part given a 3D file is refused (3D parts are not yet
/// runnable from a problem file), naming the file's first volume element.
#[test]
fn a_problem_file_refuses_a_3d_file() {
    let text = r#"
[materials.steel]
E = 210000.0
nu = 0.3

[[part]]
name = "block"
material = "steel"
gmsh = { file = "cubes_41.msh" }
"#;
    match cfe::Model::from_str(text, &data("inline.toml"), 1) {
        Err(Error::Parse { message, .. }) => assert!(
            message.contains("is a volume element")
                && message.contains("is a 3D mesh")
                && message.contains("not yet from a problem file"),
            "{message}"
        ),
        other => panic!("{:?}", other.err()),
    }
}

/// The dimension peeked from an ASCII file's element types
/// (`peek_dimension`, nodes not read) is the parsed file's, on every Gmsh
/// file of the tests and examples (2D and 3D, MSH 2.2 and 4.1); a binary file
/// is not peeked (`None`: it is parsed).
#[test]
fn the_peeked_dimension_is_the_parsed_one() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("tests/data/gmsh"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "msh"))
        .collect();
    for f in [
        "examples/hertz/hertz.msh",
        "examples/roller_in_cradle/cradle.msh",
    ] {
        files.push(root.join(f));
    }
    let (mut peeked, mut solid) = (0, 0);
    for path in &files {
        let data = std::fs::read(path).unwrap();
        let Ok(parsed) = GmshFile::parse(&data, path) else {
            continue;
        };
        let binary = path.to_string_lossy().contains("_bin");
        match cfe::mesh::gmsh::peek_dimension(&data) {
            Some(d) => {
                assert!(!binary, "{}", path.display());
                assert_eq!(d, parsed.dimension(), "{}", path.display());
                peeked += 1;
                solid += usize::from(d == 3);
            }
            None => assert!(binary, "{} not peeked", path.display()),
        }
    }
    assert!(peeked >= 8 && solid >= 2, "{peeked} peeked, {solid} solid");
}
