//! A solid (3D) model run into a folder through the run loop a plane model
//! uses (`Analysis::run`, `run_until`): a punch pressed by a uniform pressure
//! onto a base through a contact interface, built in code, and its files read
//! back independently of the writers — the parts and pairs VTU (points,
//! displacements, stresses, forces), `pairs.csv` (3D columns, the contact
//! pressure), `history.csv` (z columns), `summary.json` and the pictures; a
//! stopped run and the folder's safety.

use cfe::analysis::{Analysis, Results, RunStatus};
use cfe::dim::D3;
use cfe::domain::{
    Coupling, Enforcement, FaceLoad, InterfaceDef, Law, Load, Part, Probe, Settings, Support,
};
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::{Mesh, SolidKind};
use cfe::model::Model;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicUsize;

const E: f64 = 70e3;
const NU: f64 = 0.3;
/// The pressure on the punch's top.
const P: f64 = 40.0;
/// The pictures' width in pixels (`output::png::WIDTH`).
const PICTURE_WIDTH: u32 = 1600;

/// A fresh folder for test `name` (removed first).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cfe-run3d-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A solid part `name`: the box [0, 1] × [0, 2] × `z` of `cells` HEX8 cells.
fn block(name: &str, z: [f64; 2], cells: [usize; 3]) -> Part<D3> {
    Part {
        name: name.into(),
        mesh: Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], z, cells, SolidKind::Hex8),
        material: Material::new(E, NU, PlaneKind::Strain, 1.0, name).unwrap(),
    }
}

/// The symmetry supports of part `index`: x held on its left side, y on its
/// front side, and z on its bottom when `bottom`.
fn symmetry(index: usize, part: &Part<D3>, bottom: bool) -> Vec<Support> {
    let hold = |side: &str, c: usize| {
        let mut fix = [false; 3];
        fix[c] = true;
        Support::on_boundary(index, part, side, fix, [0.0; 3]).unwrap()
    };
    let mut s = vec![hold("left", 0), hold("front", 1)];
    if bottom {
        s.push(hold("bottom", 2));
    }
    s
}

/// A HEX8 punch (4 × 4 × 2 cells, 0.5 high) pressed by the uniform pressure
/// [`P`] onto a HEX8 base (2 × 2 × 2 cells, the host) through a contact
/// interface (the punch's face mesh nested in the base's), symmetry supports,
/// `increments` increments, a probe at the punch's top corner.
fn punch_on_base(increments: usize) -> Analysis<D3> {
    let base = block("base", [0.0, 1.0], [2, 2, 2]);
    let punch = block("punch", [1.0, 1.5], [4, 4, 2]);
    let mut supports = symmetry(0, &base, true);
    supports.extend(symmetry(1, &punch, false));
    let load = Load::on_faces("punch/top", 1, &punch, "top", FaceLoad::Pressure(P), 0).unwrap();
    let corner = (punch.mesh.nodes.iter())
        .position(|x| *x == [1.0, 2.0, 1.5])
        .unwrap();
    let interface = InterfaceDef {
        name: "base/punch".into(),
        host: 0,
        node_part: 1,
        nodes: punch.mesh.boundary_nodes("bottom").unwrap(),
        boundary: "bottom".into(),
        law: Law::Contact,
        c_n: 1e5 * E,
        c_s: 1e5 * E,
        tolerance: 1e-3,
        friction: 0.0,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        coupling: Coupling::Node,
        form: cfe::domain::CouplingForm::Face,
    };
    let mut model = Model::from_parts(
        "punch on base",
        vec![base, punch],
        vec![interface],
        supports,
        vec![load],
        Settings {
            increments,
            ..Settings::default()
        },
    )
    .unwrap();
    model.probes.push(Probe {
        name: "corner".into(),
        part: 1,
        node: corner,
        at: [1.0, 2.0, 1.5],
        weights: vec![(corner, 1.0)],
        element: None,
    });
    Analysis::new(model).unwrap()
}

/// A VTU file a run wrote, read back from its text header and raw appended
/// data (UInt64 block sizes, little-endian values), independently of the writer.
struct Vtu {
    points: usize,
    cells: usize,
    /// (section, name) → (type, components, offset).
    arrays: HashMap<(String, String), (String, usize, usize)>,
    data: Vec<u8>,
}

impl Vtu {
    fn read(path: &Path) -> Vtu {
        let bytes = std::fs::read(path).unwrap();
        let marker = b"<AppendedData encoding=\"raw\">";
        let start = (bytes.windows(marker.len()))
            .position(|w| w == marker)
            .expect("raw appended data");
        let header = std::str::from_utf8(&bytes[..start]).unwrap();
        assert!(header.contains("header_type=\"UInt64\""), "{header}");
        let underscore = start
            + marker.len()
            + (bytes[start + marker.len()..].iter())
                .position(|&b| b == b'_')
                .unwrap();
        let attr = |body: &str, key: &str| -> Option<String> {
            let k = format!(" {key}=\"");
            let i = body.find(&k)? + k.len();
            Some(body[i..i + body[i..].find('"')?].to_string())
        };
        let (mut points, mut cells) = (0, 0);
        let mut arrays = HashMap::new();
        let mut section = String::new();
        for element in header.split('<').skip(1) {
            let body = element.split('>').next().unwrap();
            let tag = body.split_whitespace().next().unwrap_or("");
            match tag {
                "Piece" => {
                    points = attr(body, "NumberOfPoints").unwrap().parse().unwrap();
                    cells = attr(body, "NumberOfCells").unwrap().parse().unwrap();
                }
                "PointData" | "CellData" | "FieldData" | "Points" | "Cells" => {
                    section = tag.to_string();
                }
                "DataArray" => {
                    let name = attr(body, "Name").unwrap_or_default();
                    let kind = attr(body, "type").unwrap();
                    let components =
                        attr(body, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
                    let offset = attr(body, "offset").unwrap().parse().unwrap();
                    arrays.insert((section.clone(), name), (kind, components, offset));
                }
                _ => {}
            }
        }
        Vtu {
            points,
            cells,
            arrays,
            data: bytes[underscore + 1..].to_vec(),
        }
    }

    /// The Float64 array `name` of `section` and its components.
    fn f64s(&self, section: &str, name: &str) -> (usize, Vec<f64>) {
        let (kind, components, offset) = &self.arrays[&(section.to_string(), name.to_string())];
        assert_eq!(kind, "Float64", "{name}");
        let size = u64::from_le_bytes(self.data[*offset..offset + 8].try_into().unwrap()) as usize;
        let values = self.data[offset + 8..offset + 8 + size]
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        (*components, values)
    }

    /// The cell types (UInt8).
    fn types(&self) -> Vec<u8> {
        let (kind, _, offset) = &self.arrays[&("Cells".to_string(), "types".to_string())];
        assert_eq!(kind, "UInt8");
        let size = u64::from_le_bytes(self.data[*offset..offset + 8].try_into().unwrap()) as usize;
        self.data[offset + 8..offset + 8 + size].to_vec()
    }
}

/// A CSV file as its header and rows of named fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<HashMap<String, String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            let fields: Vec<&str> = l.split(',').collect();
            assert_eq!(fields.len(), header.len(), "{l}");
            (header.iter().cloned())
                .zip(fields.into_iter().map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The number in field `key` of a CSV row.
fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {}", row[key]))
}

/// The width and height of the PNG at `path`.
fn png_size(path: &Path) -> (u32, u32) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (img.width(), img.height())
}

/// The in-memory results of the same model, for comparison with the files.
fn solved(increments: usize) -> Results<D3> {
    punch_on_base(increments).solve().unwrap()
}

/// A solid run writes what its results are: the parts VTU holds every node
/// (HEX8 cells) with the displacement of the in-memory solve, σzz = −p and von
/// Mises = p in every cell (uniaxial stress); the pairs VTU one vertex per pair
/// whose forces on the punch add up to p × area along z; `pairs.csv` one row
/// per pair with z and the t₂ and global-force columns, the contact pressure
/// the normal force over the tributary area (to round-off) and p at every
/// interior pair (to the penalty's accuracy); `history.csv` a row per increment with the fz/uz
/// columns and the interface's resultant; `summary.json` `completed`; and the
/// pictures (the deformed parts, the interface's pressure map, the history)
/// are PNGs of the expected size.
#[test]
fn a_solid_run_writes_its_results_files_and_pictures() {
    let out = scratch("files");
    let mut a = punch_on_base(2);
    let mut seen = Vec::new();
    let summary = a.run(&out, &mut |inc| seen.push(inc.index)).unwrap();
    assert_eq!(
        summary.status,
        RunStatus::Completed,
        "{:?}",
        summary.warnings
    );
    assert_eq!(seen, [1, 2]);
    let res = solved(2);
    let area = 2.0;

    // Parts VTU of the last increment.
    let parts = Vtu::read(&out.join("vtu/parts_0002.vtu"));
    let nodes = a
        .model
        .parts
        .iter()
        .map(|p| p.mesh.nodes.len())
        .sum::<usize>();
    assert_eq!((parts.points, parts.cells), (nodes, 8 + 32));
    assert!(parts.types().iter().all(|&t| t == 12), "VTK_HEXAHEDRON");
    let (nc, u) = parts.f64s("PointData", "displacement");
    assert_eq!((nc, u.len()), (3, 3 * nodes));
    let umax = res
        .displacements()
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for (k, (a, b)) in u.iter().zip(res.displacements()).enumerate() {
        assert!((a - b).abs() <= 1e-12 * umax, "dof {k}: {a} against {b}");
    }
    for name in ["sigma_xx", "sigma_yy", "sigma_xy", "sigma_yz", "sigma_xz"] {
        let (_, s) = parts.f64s("CellData", name);
        assert!(s.iter().all(|v| v.abs() < 1e-5 * P), "{name}: {s:?}");
        assert_eq!(parts.f64s("PointData", name).1.len(), nodes);
    }
    let (_, szz) = parts.f64s("CellData", "sigma_zz");
    let (_, vm) = parts.f64s("CellData", "von_mises");
    assert_eq!(szz.len(), 40);
    for (s, v) in szz.iter().zip(&vm) {
        assert!(
            (s + P).abs() < 1e-5 * P && (v - P).abs() < 1e-5 * P,
            "{s} {v}"
        );
    }

    // Pairs VTU: a vertex per pair, the forces on the punch balancing the load.
    let pairs = Vtu::read(&out.join("vtu/pairs_0002.vtu"));
    assert_eq!((pairs.points, pairs.cells), (25, 25));
    let (nc, force) = pairs.f64s("PointData", "force");
    assert_eq!((nc, force.len()), (3, 75));
    let fz: f64 = force.chunks_exact(3).map(|f| f[2]).sum();
    assert!((fz - P * area).abs() < 1e-8 * P * area, "{fz}");
    for name in [
        "normal",
        "slip_s",
        "force_s",
        "slip",
        "shear",
        "displacement",
    ] {
        let (nc, v) = pairs.f64s("PointData", name);
        assert_eq!((nc, v.len()), (3, 75), "{name}");
    }
    let (_, normal) = pairs.f64s("PointData", "normal");
    assert!(
        normal.chunks_exact(3).all(|n| n[2] > 0.99),
        "the base's top faces z"
    );
    let (_, shear) = pairs.f64s("PointData", "force_s");
    assert!(shear.iter().all(|v| v.abs() < 1e-5 * P), "{shear:?}");
    let series = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    for f in ["vtu/parts_0002.vtu", "vtu/pairs_0002.vtu"] {
        assert!(series.contains(f), "{series}");
    }

    // pairs.csv: one row per pair, the solid columns, pressure p inside.
    let (header, rows) = read_csv(&out.join("pairs.csv"));
    assert_eq!(header, cfe::results::SOLID_PAIR_COLUMNS);
    assert_eq!(rows.len(), res.pairs.len());
    let mut interior = 0;
    for r in &rows {
        assert_eq!((num(r, "z"), r["state"].as_str()), (1.0, "bonded"));
        // The pressure is the normal force over the tributary area (no
        // thickness in 3D), to round-off at every pair.
        let (p, f, area) = (num(r, "pressure"), num(r, "force_n"), num(r, "tributary"));
        assert!(
            (p - f / area).abs() <= 1e-14 * P,
            "{p} against {f} / {area}"
        );
        let (x, y) = (num(r, "x"), num(r, "y"));
        if x > 0.0 && x < 1.0 && y > 0.0 && y < 2.0 {
            interior += 1;
            // p to the penalty's accuracy (the pairs' jumps f/c_n differ with
            // their tributary areas: measured 7e-7 p at c_n = 1e5 E).
            assert!((p - P).abs() < 1e-5 * P, "pressure {p} at ({x}, {y})");
            let t = num(r, "force_z") / area;
            assert!((t - P).abs() < 1e-5 * P, "{t}");
        }
    }
    assert_eq!(interior, 9);

    // history.csv: the z columns, a row per increment, the load's resultants.
    let (header, rows) = read_csv(&out.join("history.csv"));
    for c in [
        "reaction:base/bottom.fz",
        "interface:base/punch.fz",
        "interface:base/punch.force_n",
        "probe:corner.uz",
    ] {
        assert!(header.iter().any(|h| h == c), "{c} in {header:?}");
    }
    assert_eq!(rows.len(), 2);
    for (k, r) in rows.iter().enumerate() {
        let lambda = (k + 1) as f64 / 2.0;
        let want = lambda * P * area;
        assert!((num(r, "reaction:base/bottom.fz") - want).abs() < 1e-8 * want);
        assert!((num(r, "interface:base/punch.fz") - want).abs() < 1e-8 * want);
        assert!((num(r, "interface:base/punch.force_n") - want).abs() < 1e-8 * want);
        assert!(num(r, "interface:base/punch.force_s").abs() < 1e-8 * want);
        let uz = res.summary.history[k].probes[0].uz.unwrap();
        assert!((num(r, "probe:corner.uz") - uz).abs() <= 1e-12 * uz.abs());
        assert!(uz < 0.0);
    }

    // summary.json.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "completed");
    assert_eq!(json["converged_increments"], 2);
    assert_eq!(json["interfaces"][0]["pairs"], 25);

    // Pictures: the solid pictures at the pictures' width (the height follows
    // the drawing's aspect), the history chart at the charts' 900 × 600.
    for picture in ["deformed.png", "pressure_1.png"] {
        let (w, h) = png_size(&out.join(picture));
        assert_eq!(w, PICTURE_WIDTH, "{picture}");
        assert!((300..=1500).contains(&h), "{picture}: {h}");
    }
    assert_eq!(png_size(&out.join("history.png")), (900, 600));
    for plane in ["sigma_yy.png", "displacement.png", "pressure.png", "lines"] {
        assert!(!out.join(plane).exists(), "{plane}");
    }
    std::fs::remove_dir_all(&out).unwrap();
}

/// A solid run stopped before it starts (the stop flag set, as by a signal)
/// ends with `Error::Interrupted`, `summary.json` says `interrupted`, and no
/// picture is drawn.
#[test]
fn a_stopped_solid_run_is_recorded_as_interrupted() {
    let out = scratch("stop");
    let mut a = punch_on_base(2);
    let e = a
        .run_until(&out, &mut |_| {}, &AtomicUsize::new(2))
        .unwrap_err();
    assert!(matches!(e, cfe::Error::Interrupted { .. }), "{e}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    for picture in ["deformed.png", "pressure_1.png", "history.png"] {
        assert!(!out.join(picture).exists(), "{picture}");
    }
    std::fs::remove_dir_all(&out).unwrap();
}

/// A solid run stopped after its first increment keeps that increment's files
/// complete, says `interrupted`, and draws no picture.
#[test]
fn a_solid_run_stopped_after_an_increment_keeps_it() {
    let out = scratch("stop-later");
    let mut a = punch_on_base(3);
    let stop = AtomicUsize::new(0);
    let e = a
        .run_until(
            &out,
            &mut |_| stop.store(15, std::sync::atomic::Ordering::Relaxed),
            &stop,
        )
        .unwrap_err();
    assert!(
        matches!(e, cfe::Error::Interrupted { signal: 15, .. }),
        "{e}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    assert_eq!(json["converged_increments"], 1);
    let (_, rows) = read_csv(&out.join("pairs.csv"));
    assert!(rows.iter().all(|r| r["increment"] == "1"));
    assert!(!out.join("deformed.png").exists());
    std::fs::remove_dir_all(&out).unwrap();
}

/// A second solid run into the folder of a first replaces the first's files
/// and leaves a user's file there untouched; a folder holding a user's file at
/// a name a solid run writes (`pressure_1.png`) and no cfe run is refused,
/// touching nothing.
#[test]
fn a_solid_run_leaves_the_users_files_alone() {
    let out = scratch("safety");
    punch_on_base(1).run(&out, &mut |_| {}).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let summary = punch_on_base(1).run(&out, &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(out.join("deformed.png").is_file());
    std::fs::remove_dir_all(&out).unwrap();

    let theirs = scratch("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(theirs.join("pressure_1.png"), "not a picture").unwrap();
    let e = punch_on_base(1).run(&theirs, &mut |_| {}).unwrap_err();
    assert!(matches!(e, cfe::Error::OutputFolderNotOurs { .. }), "{e}");
    assert_eq!(
        std::fs::read_to_string(theirs.join("pressure_1.png")).unwrap(),
        "not a picture"
    );
    assert!(!theirs.join("summary.json").exists());
    std::fs::remove_dir_all(&theirs).unwrap();
}

/// A solid run's summary gives each interface's contact area, the sum of its
/// closed pairs' tributary areas: with every pair of the punch's bottom
/// closed it is that face's area, 1 × 2, to round-off (summary.json too).
#[test]
fn a_solid_run_reports_its_contact_area() {
    let out = scratch("area");
    let summary = punch_on_base(1).run(&out, &mut |_| {}).unwrap();
    let i = &summary.interfaces[0];
    assert_eq!(i.open, 0);
    let area = i.contact_area.expect("a solid interface's contact area");
    assert!((area - 2.0).abs() < 1e-13, "{area}");
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(json.contains("\"contact_area\""), "{json}");
}

/// `deformed.png` follows the model's picture (`[output] view` and
/// `component`): seen from +z and coloured by u_z it is a picture of the
/// usual size whose pixels differ from the default's (isometric, von Mises).
#[test]
fn a_solid_run_draws_the_chosen_view_and_component() {
    use cfe::model::{Picture, PictureField, ViewPoint};
    let default = scratch("view_default");
    punch_on_base(1).run(&default, &mut |_| {}).unwrap();
    let chosen = scratch("view_chosen");
    let mut a = punch_on_base(1);
    a.model.picture = Picture {
        view: ViewPoint::Axis(2, true),
        field: PictureField::Displacement(2),
    };
    a.run(&chosen, &mut |_| {}).unwrap();
    let (d, c) = (default.join("deformed.png"), chosen.join("deformed.png"));
    assert_eq!(png_size(&c).0, PICTURE_WIDTH);
    assert_ne!(std::fs::read(&d).unwrap(), std::fs::read(&c).unwrap());
}
