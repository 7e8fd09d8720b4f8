//! Solid models through the analysis API a plane model uses: a `Model<D3>`
//! built in code (parts, supports on named sides, a pressure resolved from
//! faces, a contact interface) prepared and solved by `Analysis`, its results
//! (reactions, pairs, stresses, summary) checked against statics and closed
//! forms.

use cfe::analysis::{Analysis, RunStatus};
use cfe::coupling::PairState;
use cfe::dim::D3;
use cfe::domain::{
    Coupling, Enforcement, FaceLoad, InterfaceDef, Law, Load, Part, Probe, Settings, Support,
};
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::{Mesh, SolidKind};
use cfe::model::Model;

const E: f64 = 70e3;
const NU: f64 = 0.3;

/// A solid part `name`: the box `x × y × z` of `cells` cells of `kind`.
fn block(name: &str, z: [f64; 2], cells: [usize; 3], kind: SolidKind) -> Part<D3> {
    Part {
        name: name.into(),
        mesh: Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], z, cells, kind),
        material: Material::new(E, NU, PlaneKind::Strain, 1.0, name).unwrap(),
    }
}

/// The symmetry supports of part `index`: x held on its left side, y on its
/// front side; and z on its bottom when `bottom`.
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

fn one_increment() -> Settings {
    Settings {
        increments: 1,
        ..Settings::default()
    }
}

/// A punch (`punch` cells of `punch_kind`, 0.5 high) pressed by a uniform
/// pressure `p` onto a base (2 × 2 × 2 cells of `base_kind`, the host) through
/// a contact interface, symmetry supports, one increment: its analysis and
/// results.
fn punch_on_base(
    base_kind: SolidKind,
    punch_kind: SolidKind,
    punch: usize,
    p: f64,
) -> (Analysis<D3>, cfe::analysis::Results<D3>) {
    let base = block("base", [0.0, 1.0], [2, 2, 2], base_kind);
    let punch = block("punch", [1.0, 1.5], [punch, punch, 2], punch_kind);
    let mut supports = symmetry(0, &base, true);
    supports.extend(symmetry(1, &punch, false));
    let load = Load::on_faces("punch/top", 1, &punch, "top", FaceLoad::Pressure(p), 0).unwrap();
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
        form: cfe::coupling::CouplingForm::Face,
    };
    let model = Model::from_parts(
        "punch on base",
        vec![base, punch],
        vec![interface],
        supports,
        vec![load],
        one_increment(),
    )
    .unwrap();
    let a = Analysis::new(model).unwrap();
    let res = a.solve().unwrap();
    (a, res)
}

/// What holds for any punch on a base: the run completes; the applied load is
/// (0, 0, −p A) and the reactions balance it; every pair is closed and keeps
/// its law; the pairs' forces on the punch add up to the load along z (their
/// resultant in the summary too).
fn assert_balanced_and_lawful(res: &cfe::analysis::Results<D3>, p: f64, pairs: usize, what: &str) {
    let area = 2.0;
    let s = &res.summary;
    assert_eq!(s.status, RunStatus::Completed, "{what}: {:?}", s.warnings);
    assert_eq!(s.applied.len(), 3);
    assert!((s.applied[2] + p * area).abs() < 1e-12 * p * area, "{what}");
    let sum = |f: &dyn Fn(&cfe::analysis::Reaction) -> f64| s.reactions.iter().map(f).sum::<f64>();
    let (fx, fy, fz) = (sum(&|r| r.fx), sum(&|r| r.fy), sum(&|r| r.fz.unwrap()));
    assert!(
        (fz - p * area).abs() < 1e-8 * p * area,
        "{what}: Σ fz = {fz}"
    );
    assert!(
        fx.abs() < 1e-8 * p * area && fy.abs() < 1e-8 * p * area,
        "{what}: {fx} {fy}"
    );
    assert!(
        s.equilibrium_error < 1e-8,
        "{what}: {}",
        s.equilibrium_error
    );
    assert_eq!(res.pairs.len(), pairs, "{what}");
    let mut total = [0.0; 3];
    for r in &res.pairs {
        assert_eq!(r.state, PairState::Bonded, "{what}: {r:?}");
        assert!(!r.breaks_law(), "{what}: {r:?}");
        assert!(r.z == Some(1.0) && r.force_t2.is_some(), "{what}: {r:?}");
        total[0] += r.force_x.unwrap();
        total[1] += r.force_y.unwrap();
        total[2] += r.force_z.unwrap();
    }
    assert!(
        (total[2] - p * area).abs() < 1e-8 * p * area,
        "{what}: {total:?}"
    );
    let i = &s.interfaces[0];
    assert_eq!(
        (i.pairs, i.bonded, i.open, i.violations),
        (pairs, pairs, 0, 0),
        "{what}"
    );
    let resultant = i.resultant.as_ref().unwrap();
    assert!(
        (resultant[2] - p * area).abs() < 1e-8 * p * area,
        "{what}: {resultant:?}"
    );
}

/// The contact patch test in 3D: a punch pressed by a uniform pressure p onto
/// a base, the punch's face mesh nested in the base's (4 × 4 cells on 2 × 2,
/// HEX8 on HEX8 and TET4 on TET4: the node part's nodal weights then integrate
/// the host's face shape functions exactly): balanced, lawful, every pair
/// carries the traction (0, 0, p) on its tributary area, and every element of
/// both parts is in the uniaxial stress σzz = −p (to the penalty's accuracy).
#[test]
fn a_punch_pressed_on_a_base_transmits_a_uniform_contact_pressure() {
    let p = 40.0;
    for kind in [SolidKind::Hex8, SolidKind::Tet4] {
        let what = format!("{kind:?}");
        let (_, res) = punch_on_base(kind, kind, 4, p);
        assert_balanced_and_lawful(&res, p, 25, &what);
        for r in &res.pairs {
            let t = [r.force_x.unwrap(), r.force_y.unwrap(), r.force_z.unwrap()]
                .map(|f| f / r.tributary);
            assert!(
                (t[2] - p).abs() < 1e-5 * p,
                "{what}: traction {t:?} at {:?}",
                r.position()
            );
            assert!(
                t[0].hypot(t[1]) < 1e-5 * p,
                "{what}: traction {t:?} at {:?}",
                r.position()
            );
            // Off the rim the host's normal is the top face's: pressure = p.
            if r.x > 0.0 && r.x < 1.0 && r.y > 0.0 && r.y < 2.0 {
                assert!((r.pressure - p).abs() < 1e-5 * p, "{what}: {r:?}");
                assert!(r.shear_magnitude() < 1e-5 * p, "{what}: {r:?}");
            }
        }
        for part in &res.stresses {
            for sigma in &part.element {
                let want = [0.0, 0.0, -p, 0.0, 0.0, 0.0];
                for (s, w) in sigma.iter().zip(want) {
                    assert!((s - w).abs() < 1e-5 * p, "{what}: {sigma:?}");
                }
            }
        }
    }
}

/// A TET4 punch on a HEX8 base (nested faces, 4 × 4 on 2 × 2): balanced and
/// lawful on every pair, the element counts in the summary. The node CFE's
/// vertex weights of triangles do not integrate the bilinear host faces'
/// shape functions exactly, so the contact pressure is not exactly uniform:
/// measured here, within 1 % of p off the interface's rim (the error
/// concentrates at its corners).
#[test]
fn a_tet4_punch_on_a_hex8_base_balances_and_keeps_the_law() {
    let p = 40.0;
    let (a, res) = punch_on_base(SolidKind::Hex8, SolidKind::Tet4, 4, p);
    assert_balanced_and_lawful(&res, p, 25, "TET4 on HEX8");
    let inner = (res.pairs.iter())
        .filter(|r| r.x > 0.0 && r.x < 1.0 && r.y > 0.0 && r.y < 2.0)
        .map(|r| (r.pressure - p).abs() / p)
        .fold(0.0, f64::max);
    assert!(inner < 1e-2, "{inner}");
    let s = &res.summary;
    assert_eq!((s.parts[0].hex8, s.parts[0].tet4), (8, 0));
    assert_eq!((s.parts[1].tet4, s.parts[1].hex8), (6 * 32, 0));
    assert_eq!(a.dofs.per_node(), 3);
}

/// A single HEX8 or TET4 block, its symmetry sides held and a pressure p on
/// its right side: the closed form u = (−p x, ν p y, ν p z) / E at every node,
/// the summary's largest displacement at the far corner, a probe there and the
/// left side's reaction −(−p A) along x.
#[test]
fn a_solid_block_under_a_side_pressure_matches_the_closed_form() {
    let p = 25.0;
    let height = 1.5;
    for kind in [SolidKind::Hex8, SolidKind::Tet4] {
        let part = block("block", [0.0, height], [2, 3, 2], kind);
        let supports = symmetry(0, &part, true);
        let load =
            Load::on_faces("block/right", 0, &part, "right", FaceLoad::Pressure(p), 0).unwrap();
        let corner = (part.mesh.nodes.iter())
            .position(|x| *x == [1.0, 2.0, height])
            .unwrap();
        let mut model = Model::from_parts(
            "block",
            vec![part],
            Vec::new(),
            supports,
            vec![load],
            one_increment(),
        )
        .unwrap();
        model.probes.push(Probe {
            name: "corner".into(),
            part: 0,
            node: corner,
            at: [1.0, 2.0, height],
            weights: vec![(corner, 1.0)],
            element: None,
        });
        let a = Analysis::new(model).unwrap();
        let res = a.solve().unwrap();
        let s = &res.summary;
        assert_eq!(s.status, RunStatus::Completed, "{kind:?}: {:?}", s.warnings);
        let strain = p / E;
        let want = |x: [f64; 3]| [-strain * x[0], NU * strain * x[1], NU * strain * x[2]];
        for (n, x) in a.model.parts[0].mesh.nodes.iter().enumerate() {
            let w = want(*x);
            for (c, w) in w.iter().enumerate() {
                let u = res.displacements()[3 * n + c];
                assert!(
                    (u - w).abs() < 1e-10 * strain,
                    "{kind:?} node {n}: {u} against {w}"
                );
            }
        }
        let far = want([1.0, 2.0, height]);
        let magnitude = far.iter().map(|v| v * v).sum::<f64>().sqrt();
        let m = &s.max_displacement;
        assert!(
            (m.value - magnitude).abs() < 1e-9 * magnitude,
            "{kind:?}: {m:?}"
        );
        assert_eq!((m.x, m.y, m.z), (1.0, 2.0, Some(height)));
        let probe = &s.history.last().unwrap().probes[0];
        assert!((probe.uz.unwrap() - far[2]).abs() < 1e-10 * strain);
        assert_eq!(s.probes[0].at, vec![1.0, 2.0, height]);
        // The left side holds the pressure's resultant: p × (2 × height) along +x.
        let left = &s.reactions[0];
        assert!((left.fx - p * 2.0 * height).abs() < 1e-9 * p, "{left:?}");
        assert!(left.fz.unwrap().abs() < 1e-9 * p);
    }
}

/// A support or load on a side the part does not have is refused, naming it.
#[test]
fn a_missing_side_is_an_error_naming_the_part() {
    let part = block("block", [0.0, 1.0], [1, 1, 1], SolidKind::Hex8);
    let e = Load::on_faces("x", 0, &part, "lid", FaceLoad::Pressure(1.0), 0).unwrap_err();
    assert!(
        matches!(&e, cfe::Error::Model(m) if m.contains("'block'") && m.contains("'lid'")),
        "{e}"
    );
    let e = Support::on_boundary(0, &part, "lid", [true; 3], [0.0; 3]).unwrap_err();
    assert!(matches!(e, cfe::Error::Model(_)));
}
