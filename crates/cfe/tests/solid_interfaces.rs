//! Solid parts meshed independently and joined through 3D coupling elements,
//! solved by the solver: tied patch tests (nested, non-nested, TET4, HEX8 and
//! mixed faces), the contact patch test, Coulomb friction with the load along a
//! diagonal of the face, the invariance under a turn of every pair's tangents
//! and under a rigid rotation of the whole model, and a curved interface whose
//! nodes are moved onto the host's faces. The interfaces are built by
//! `coupling::build::interfaces` from hand-made definitions; the truth is the
//! closed-form uniform state, statics and the invariances.

use cfe::assembly::DofMap;
use cfe::coupling::{Coupling, Interface, Law, PairState, build};
use cfe::dim::{D3, Dim};
use cfe::domain::{Enforcement, FrictionSolve, InterfaceDef, Part, Settings, Support};
use cfe::error::Error;
use cfe::fem::{ElementFamily, Material, PlaneKind, face3};
use cfe::mesh::{FaceNodes, Mesh, SolidKind};
use cfe::solve::nonlinear::{IncrementResult, LoadSteps, Solver};
use std::collections::BTreeMap;

const E: f64 = 210e3;
const NU: f64 = 0.3;

/// The host's mesh kind: TET4, HEX8, or mixed (TET4 cells for x below the
/// middle, HEX8 above: the face carries triangles and quadrangles).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Tet,
    Hex,
    Mixed,
}

/// A block [x] × [y] × [z] of `cells` cells of `kind`, with its six sides named.
fn block(x: [f64; 2], y: [f64; 2], z: [f64; 2], cells: [usize; 3], kind: Kind) -> Mesh<D3> {
    match kind {
        Kind::Tet => Mesh::<D3>::block(x, y, z, cells, SolidKind::Tet4),
        Kind::Hex => Mesh::<D3>::block(x, y, z, cells, SolidKind::Hex8),
        Kind::Mixed => {
            // Same node numbering in both: the cell (i, j, k) is HEX8 element c
            // or TET4 elements 6c..6c+6 (c = (k ny + j) nx + i).
            let tet = Mesh::<D3>::block(x, y, z, cells, SolidKind::Tet4);
            let hex = Mesh::<D3>::block(x, y, z, cells, SolidKind::Hex8);
            let nx = cells[0];
            let mut elements = Vec::new();
            for c in 0..hex.elements.len() {
                if c % nx < nx / 2 {
                    elements.extend_from_slice(&tet.elements[6 * c..6 * c + 6]);
                } else {
                    elements.push(hex.elements[c]);
                }
            }
            let mut mesh = Mesh::<D3> {
                nodes: hex.nodes,
                elements,
                boundaries: BTreeMap::new(),
                node_sets: Default::default(),
            };
            let sides = [
                ("left", 0, x[0]),
                ("right", 0, x[1]),
                ("front", 1, y[0]),
                ("back", 1, y[1]),
                ("bottom", 2, z[0]),
                ("top", 2, z[1]),
            ];
            let faces = mesh.boundary_faces();
            for (name, axis, at) in sides {
                let on: Vec<_> = faces
                    .iter()
                    .filter(|f| {
                        f.nodes
                            .as_slice()
                            .iter()
                            .all(|&n| mesh.nodes[n][axis] == at)
                    })
                    .copied()
                    .collect();
                mesh.boundaries.insert(name.to_string(), on);
            }
            mesh.validate("mixed").unwrap();
            mesh
        }
    }
}

/// A two-part model: the host (part 0) below, the node part (part 1) above, the
/// interface of the node part's bottom on the host, the supports.
struct Model {
    parts: Vec<Part<D3>>,
    defs: Vec<InterfaceDef>,
    supports: Vec<Support>,
}

fn part(name: &str, mesh: Mesh<D3>) -> Part<D3> {
    Part {
        name: name.into(),
        material: Material::new(E, NU, PlaneKind::Strain, 1.0, name).unwrap(),
        mesh,
    }
}

/// The interface of part 1's `bottom` on part 0 under `law`, penalties `c`.
fn interface_def(parts: &[Part<D3>], law: Law, c: f64, friction: f64) -> InterfaceDef {
    InterfaceDef {
        name: "base/block".into(),
        host: 0,
        node_part: 1,
        nodes: parts[1].mesh.boundary_nodes("bottom").unwrap(),
        boundary: "bottom".into(),
        law,
        c_n: c,
        c_s: c,
        tolerance: 0.05,
        friction,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        coupling: Coupling::Node,
        form: cfe::coupling::CouplingForm::Face,
    }
}

/// Part `p`'s nodes of side `side` held in the components `fix` at `value`.
fn hold(parts: &[Part<D3>], p: usize, side: &str, fix: [bool; 3], value: [f64; 3]) -> Support {
    Support {
        name: format!("{}/{side}", parts[p].name),
        part: p,
        nodes: parts[p].mesh.boundary_nodes(side).unwrap(),
        fix,
        value,
        step: 0,
    }
}

/// The global node offsets of the parts.
fn offsets(parts: &[Part<D3>]) -> Vec<usize> {
    let mut o = vec![0];
    for p in parts {
        o.push(o.last().unwrap() + p.mesh.nodes.len());
    }
    o
}

/// Adds to `f` (all DOFs) the consistent nodal forces of the uniform traction
/// `t` on side `side` of part `p`.
fn traction(parts: &[Part<D3>], p: usize, side: &str, t: [f64; 3], f: &mut [f64]) {
    let off = offsets(parts)[p];
    let mesh = &parts[p].mesh;
    for face in &mesh.boundaries[side] {
        let (nodes, forces): (&[usize], Vec<[f64; 3]>) = match &face.nodes {
            FaceNodes::Tri(n) => (
                n,
                face3::triangle_traction_forces(&n.map(|k| mesh.nodes[k]), t).to_vec(),
            ),
            FaceNodes::Quad(n) => (
                n,
                face3::quad_traction_forces(&n.map(|k| mesh.nodes[k]), t).to_vec(),
            ),
        };
        for (&n, fv) in nodes.iter().zip(&forces) {
            for c in 0..3 {
                f[3 * (off + n) + c] += fv[c];
            }
        }
    }
}

/// A solved model: its interfaces (as built), DOF map and last increment.
struct Solved {
    interfaces: Vec<Interface<D3>>,
    dofs: DofMap<D3>,
    result: IncrementResult<D3>,
}

/// Builds the interfaces of `m` (nodes moved onto their host faces), lets
/// `edit` change them, and solves `m` under `f_ext` in `increments`
/// (or the load `steps`).
fn solve_with(
    m: &mut Model,
    f_ext: Vec<f64>,
    increments: usize,
    steps: impl FnOnce(&DofMap<D3>) -> Option<LoadSteps>,
    edit: impl FnOnce(&mut Vec<Interface<D3>>),
) -> Result<Solved, Error> {
    solve_friction(m, f_ext, increments, steps, edit, FrictionSolve::default())
}

/// [`solve_with`] with the slip forces solved by `friction_solve`.
fn solve_friction(
    m: &mut Model,
    f_ext: Vec<f64>,
    increments: usize,
    steps: impl FnOnce(&DofMap<D3>) -> Option<LoadSteps>,
    edit: impl FnOnce(&mut Vec<Interface<D3>>),
    friction_solve: FrictionSolve,
) -> Result<Solved, Error> {
    let mut interfaces = build::interfaces(&m.defs, &mut m.parts, 1)?;
    edit(&mut interfaces);
    let counts: Vec<usize> = m.parts.iter().map(|p| p.mesh.nodes.len()).collect();
    let dofs = DofMap::<D3>::numbered(&counts, &m.supports);
    let settings = Settings {
        increments,
        friction_solve,
        ..Settings::default()
    };
    let result = {
        let mut solver = Solver::new(&m.parts, &interfaces, &dofs, f_ext, &settings, None)?;
        if let Some(s) = steps(&dofs) {
            solver.set_steps(s);
        }
        solver.run(|_| Ok(()))?
    };
    Ok(Solved {
        interfaces,
        dofs,
        result,
    })
}

fn solve(m: &mut Model, f_ext: Vec<f64>) -> Solved {
    solve_with(m, f_ext, 1, |_| None, |_| {}).unwrap()
}

/// The force the host exerts on the node part at pair k of interface 0 (−f,
/// f the pair's local force on its coupling node's spring): global, then local
/// (normal: > 0 pressing; tangential), and the pair's tributary area.
fn pair_force(s: &Solved, k: usize) -> ([f64; 3], (f64, [f64; 2]), f64) {
    let iface = &s.interfaces[0];
    let r = &s.result;
    let at = iface.pair_at(k, &s.dofs, &r.u, r.states[0][k], &r.pair_history[0][k]);
    let c = &iface.elements[k];
    let on_node = (-at.force.0, [-at.force.1[0], -at.force.1[1]]);
    (
        D3::to_global(&c.frame, on_node.0, on_node.1),
        on_node,
        c.tributary,
    )
}

/// The largest misallocation of a uniform unit traction's force by the
/// interface's pairs: host node i receives Σ_c N̄ᵢ(X_c) A_c (A_c the coupling
/// node's tributary area) where the consistent share of the host's face is
/// ∫ N̄ᵢ dA; the largest difference relative to the largest share.
fn transfer_error(parts: &[Part<D3>], iface: &Interface<D3>) -> f64 {
    let host = &parts[iface.host];
    let n = host.mesh.nodes.len();
    let mut got = vec![0.0; 3 * n];
    for c in &iface.elements {
        for (&i, &w) in c.host_nodes.iter().zip(&c.shape) {
            got[3 * i + 2] += w * c.tributary;
        }
    }
    let mut want = vec![0.0; 3 * offsets(parts)[2]];
    traction(parts, iface.host, "top", [0.0, 0.0, 1.0], &mut want);
    let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    (0..n)
        .map(|i| (got[3 * i + 2] - want[3 * i + 2]).abs() / scale)
        .fold(0.0, f64::max)
}

/// The largest deviation of any element or nodal stress of both parts from
/// `want`, relative to the largest component of `want`.
fn stress_error(m: &Model, u: &[f64], want: [f64; 6]) -> f64 {
    let off = offsets(&m.parts);
    let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut worst = 0.0f64;
    for (p, part) in m.parts.iter().enumerate() {
        let up = &u[3 * off[p]..3 * off[p + 1]];
        let s = D3::recover(&part.mesh, &part.material, up);
        for v in s.element.iter().chain(&s.nodal) {
            for c in 0..6 {
                worst = worst.max((v[c] - want[c]).abs() / scale);
            }
        }
    }
    worst
}

/// The tied stack: a host block [0, 1]² × [0, 1] of `host` (n × n × 2 cells)
/// under a block [0, 1]² × [1, 2] of `top` (m × m × 2 cells), tied with
/// penalty `c`, held on the symmetry planes x = 0, y = 0 and the host's bottom
/// z = 0 (each in its normal component).
fn tied_stack(host: Kind, n: usize, top: Kind, m: usize, c: f64) -> Model {
    let parts = vec![
        part(
            "base",
            block([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [n, n, 2], host),
        ),
        part(
            "block",
            block([0.0, 1.0], [0.0, 1.0], [1.0, 2.0], [m, m, 2], top),
        ),
    ];
    let defs = vec![interface_def(&parts, Law::Rigid, c, 0.0)];
    let mut supports = Vec::new();
    for p in 0..2 {
        supports.push(hold(&parts, p, "left", [true, false, false], [0.0; 3]));
        supports.push(hold(&parts, p, "front", [false, true, false], [0.0; 3]));
    }
    supports.push(hold(&parts, 0, "bottom", [false, false, true], [0.0; 3]));
    Model {
        parts,
        defs,
        supports,
    }
}

/// The tied stack under a uniform tension q on its top: σzz = q everywhere,
/// solved; the largest stress error relative to q.
fn tension_error(host: Kind, n: usize, top: Kind, m: usize, c: f64) -> f64 {
    tension(host, n, top, m, c).0
}

/// [`tension_error`] and the interface's [`transfer_error`].
fn tension(host: Kind, n: usize, top: Kind, m: usize, c: f64) -> (f64, f64) {
    let mut model = tied_stack(host, n, top, m, c);
    let q = 10.0;
    let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
    traction(&model.parts, 1, "top", [0.0, 0.0, q], &mut f);
    let s = solve(&mut model, f);
    assert!(s.result.violations.is_empty());
    (
        stress_error(&model, &s.result.u, [0.0, 0.0, q, 0.0, 0.0, 0.0]),
        transfer_error(&model.parts, &s.interfaces[0]),
    )
}

/// Tied patch test, nested faces (every host vertex on the interface is a
/// coupling node: 2:4 HEX8 on HEX8 and TET4 on TET4, whose face diagonals
/// nest): σzz = q through the interface to the penalty's accuracy — the error
/// is O(E h / c), falling tenfold when c grows tenfold (the penalty's own
/// error, not the coupling's), and below 1e-6 at c = 1e6 E h.
#[test]
fn a_tied_nested_interface_carries_a_uniform_tension_to_the_penalty_accuracy() {
    let h = 0.25;
    for (host, top) in [(Kind::Hex, Kind::Hex), (Kind::Tet, Kind::Tet)] {
        let coarse = tension_error(host, 2, top, 4, 1e3 * E * h);
        let stiff = tension_error(host, 2, top, 4, 1e4 * E * h);
        let tight = tension_error(host, 2, top, 4, 1e6 * E * h);
        eprintln!("{host:?}/{top:?} nested: {coarse:e} {stiff:e} {tight:e}");
        let ratio = coarse / stiff;
        assert!(
            (ratio - 10.0).abs() < 1.0,
            "{host:?}: error ratio {ratio} for 10 × c"
        );
        assert!(tight < 1e-6, "{host:?}: {tight}");
    }
}

/// Tied patch test, faces that do not nest: HEX8 over TET4 at 2:4 (the host's
/// triangles cut the node part's quadrangles), HEX8 over HEX8 at 3:5, HEX8 over
/// TET4 at 3:5, HEX8 at 2:3 and 3:7, and a mixed host (TET4 and HEX8 cells)
/// under TET4 at 3:5 and 4:5. The uniform tension is not reproduced exactly:
/// node-to-face coupling hands the traction to the host by the node part's
/// tributary areas, Σ_c N̄ᵢ(X_c) A_c at host node i where the consistent share
/// is ∫ N̄ᵢ dA — a one-point rule per tributary on the host's shape functions,
/// exact only when they are in the node part's face space (nested faces).
/// That misallocation ([`transfer_error`], computed from the pairs alone) is
/// the error's origin: the stress error does not fall with the penalty, and
/// it is bounded by 3 × the transfer error (measured, printed: 0.7–2.1 ×; the
/// stress errors 3.9–18 %, as the 2D non-nested cases' 2.3–4.5 %).
#[test]
fn a_tied_non_nested_interface_carries_a_uniform_tension_within_a_measured_error() {
    let c = 1e5 * E * 0.25;
    for (host, n, top, m) in [
        (Kind::Tet, 2, Kind::Hex, 4),
        (Kind::Hex, 3, Kind::Hex, 5),
        (Kind::Tet, 3, Kind::Hex, 5),
        (Kind::Mixed, 3, Kind::Tet, 5),
        (Kind::Mixed, 4, Kind::Tet, 5),
        (Kind::Hex, 2, Kind::Hex, 3),
        (Kind::Hex, 3, Kind::Hex, 7),
    ] {
        let (err, transfer) = tension(host, n, top, m, c);
        let stiffer = tension_error(host, n, top, m, 10.0 * c);
        eprintln!(
            "{host:?} {n} / {top:?} {m}: stress error {err:e} (10 × c: {stiffer:e}), transfer error {transfer:e}, ratio {}",
            err / transfer
        );
        assert!(
            transfer > 1e-3 && err <= 3.0 * transfer,
            "{host:?} {n} / {top:?} {m}: {err} against {transfer}"
        );
        // Not the penalty's error: it stays when c grows tenfold.
        assert!((stiffer - err).abs() < 0.2 * err + 1e-6, "{err} {stiffer}");
    }
}

/// Tied patch test in shear: the stack clamped at its bottom, a shear traction
/// τ on its top along x and ±τ along z on its faces x = 0, 1 (the pure shear
/// σxz = τ, whose displacement with the bottom clamped is u = (τ/G) z e_x),
/// nested HEX8 2:4 and TET4 2:4: σxz = τ everywhere to the penalty's
/// accuracy, the pairs' tangential forces summing to τ × area. (The mixed
/// mesh of these tests joins TET4 and HEX8 cells across a plane x = const
/// without conforming faces, which carries no traction under σzz but does
/// under σxz: it serves the tension tests only.)
#[test]
fn a_tied_nested_interface_carries_a_uniform_shear() {
    let c = 1e6 * E * 0.25;
    let tau = 7.0;
    for (host, n, top, m) in [(Kind::Hex, 2, Kind::Hex, 4), (Kind::Tet, 2, Kind::Tet, 4)] {
        let mut model = tied_stack(host, n, top, m, c);
        model.supports = vec![hold(&model.parts, 0, "bottom", [true; 3], [0.0; 3])];
        let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
        traction(&model.parts, 1, "top", [tau, 0.0, 0.0], &mut f);
        for p in 0..2 {
            traction(&model.parts, p, "right", [0.0, 0.0, tau], &mut f);
            traction(&model.parts, p, "left", [0.0, 0.0, -tau], &mut f);
        }
        let s = solve(&mut model, f);
        let err = stress_error(&model, &s.result.u, [0.0, 0.0, 0.0, 0.0, 0.0, tau]);
        eprintln!("{host:?} shear: {err:e}");
        assert!(err < 1e-5, "{host:?}: {err}");
        let g = E / (2.0 * (1.0 + NU));
        let off = offsets(&model.parts);
        for (p, part) in model.parts.iter().enumerate() {
            for (k, x) in part.mesh.nodes.iter().enumerate() {
                let ux = s.result.u[3 * (off[p] + k)];
                assert!((ux - tau / g * x[2]).abs() < 1e-5 * tau / g, "{ux}");
            }
        }
        let total: [f64; 3] = (0..s.interfaces[0].elements.len()).fold([0.0; 3], |acc, k| {
            let (f, _, _) = pair_force(&s, k);
            [acc[0] + f[0], acc[1] + f[1], acc[2] + f[2]]
        });
        // The host holds the block back against τ on its top.
        assert!(
            (total[0] + tau).abs() < 1e-8 * tau && total[1].abs() < 1e-8 * tau,
            "{total:?}"
        );
        assert!(total[2].abs() < 1e-8 * tau, "{total:?}");
    }
}

/// A base [0, 1]² × [0, 1] of `host` under a block [0, 1]² × [1, 1.5] of `top`
/// (non-matching), interface `law` with friction μ, penalties 1e5 E h; the base
/// held at its bottom in z and both on the symmetry planes x = 0, y = 0.
fn contact_stack(host: Kind, n: usize, top: Kind, m: usize, law: Law, mu: f64) -> Model {
    let parts = vec![
        part(
            "base",
            block([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [n, n, 2], host),
        ),
        part(
            "block",
            block([0.0, 1.0], [0.0, 1.0], [1.0, 1.5], [m, m, 2], top),
        ),
    ];
    let defs = vec![interface_def(&parts, law, 1e5 * E * 0.25, mu)];
    let mut supports = Vec::new();
    for p in 0..2 {
        supports.push(hold(&parts, p, "left", [true, false, false], [0.0; 3]));
        supports.push(hold(&parts, p, "front", [false, true, false], [0.0; 3]));
    }
    supports.push(hold(&parts, 0, "bottom", [false, false, true], [0.0; 3]));
    Model {
        parts,
        defs,
        supports,
    }
}

/// The 3D contact patch test: two blocks meshed apart pressed together by a
/// uniform pressure p on the top, `contact` and `frictionless`: every pair
/// closed, its normal the top face's (the rim's too: the host's sides do not
/// face the block), the normal forces summing to p A, σzz = −p. With nested
/// faces (HEX8 2:4, TET4 2:4) every pair's pressure force_n / tributary area is
/// p and no pair carries shear, to the penalty's accuracy (10 E h / c: equal
/// springs on unequal tributaries, docs/method.md §5); with faces that do
/// not nest (HEX8 3 under TET4 4) the pressures scatter about p by the
/// traction-transfer error (bounded by 3 × it, as the tied test measures) and
/// the stick law carries the small shear that scatter makes. Pulled apart by
/// the same traction the block is free and the run refuses it; held at its top
/// and lifted, every pair is open and carries nothing.
#[test]
fn the_contact_patch_test_in_3d() {
    let p = 5.0;
    for (host, n, top, m, nested) in [
        (Kind::Hex, 2, Kind::Hex, 4, true),
        (Kind::Tet, 2, Kind::Tet, 4, true),
        (Kind::Hex, 3, Kind::Tet, 4, false),
    ] {
        for law in [Law::Contact, Law::Frictionless] {
            let mut model = contact_stack(host, n, top, m, law, 0.0);
            let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
            traction(&model.parts, 1, "top", [0.0, 0.0, -p], &mut f);
            let s = solve(&mut model, f.clone());
            let what = format!("{host:?} {n} / {top:?} {m}, {law:?}");
            assert!(s.result.violations.is_empty(), "{what}");
            let transfer = transfer_error(&model.parts, &s.interfaces[0]);
            let mut total = [0.0; 3];
            let mut worst = 0.0f64;
            for k in 0..s.interfaces[0].elements.len() {
                assert_eq!(s.result.states[0][k], PairState::Bonded, "{what}: pair {k}");
                let normal = s.interfaces[0].elements[k].normal;
                assert!(
                    (normal[2] - 1.0).abs() < 1e-14,
                    "{what}: pair {k}: {normal:?}"
                );
                let (g, (f_n, f_t), area) = pair_force(&s, k);
                worst = worst.max((f_n / area - p).abs() / p);
                if law == Law::Frictionless {
                    assert_eq!(f_t, [0.0; 2], "{what}");
                } else if nested {
                    assert!(f_t[0].hypot(f_t[1]) < 1e-4 * p * area, "{what}: {f_t:?}");
                }
                for c in 0..3 {
                    total[c] += g[c];
                }
            }
            eprintln!("{what}: largest pair pressure error {worst:e}, transfer error {transfer:e}");
            if nested {
                // The penalty's accuracy: 10 E h / c with c = 1e5 E h.
                assert!(worst < 1e-4, "{what}: {worst}");
            } else {
                assert!(worst < 3.0 * transfer, "{what}: {worst} against {transfer}");
            }
            assert!((total[2] - p).abs() < 1e-9 * p, "{what}: Σ f_n = {total:?}");
            if nested || law == Law::Frictionless {
                assert!(
                    total[0].abs() + total[1].abs() < 1e-6 * p,
                    "{what}: {total:?}"
                );
            }
            let err = stress_error(&model, &s.result.u, [0.0, 0.0, -p, 0.0, 0.0, 0.0]);
            assert!(
                err < if nested { 1e-5 } else { 3.0 * transfer },
                "{what}: stress error {err}"
            );
            // Pulled apart: nothing holds the block, which the run refuses.
            let pulled: Vec<f64> = f.iter().map(|v| -v).collect();
            let mut model = contact_stack(host, n, top, m, law, 0.0);
            match solve_with(&mut model, pulled.clone(), 1, |_| None, |_| {}) {
                Err(Error::Unsupported { parts, .. }) => assert_eq!(parts, ["block"], "{what}"),
                Err(Error::NotPositiveDefinite { part, .. }) => assert_eq!(part, "block", "{what}"),
                other => panic!("{what}: pulled apart: {:?}", other.map(|s| s.result.states)),
            }
            // Held at its top, lifted by δ: every pair opens, with no force.
            let mut model = contact_stack(host, n, top, m, law, 0.0);
            let lift = hold(
                &model.parts,
                1,
                "top",
                [false, false, true],
                [0.0, 0.0, 1e-3],
            );
            model.supports.push(lift);
            let s = solve(&mut model, vec![0.0; pulled.len()]);
            for k in 0..s.interfaces[0].elements.len() {
                assert_eq!(s.result.states[0][k], PairState::Open, "{what}: pair {k}");
                let (g, _, _) = pair_force(&s, k);
                assert_eq!(g, [0.0; 3]);
            }
        }
    }
}

/// A block [0, 1]² × [1, 1.5] (HEX8 4 × 4) on a base [0, 1]² × [0, 1] (HEX8
/// 2 × 2, nested) under the Coulomb law with μ; the base held at its bottom in
/// z and on x = 0, y = 0 (symmetric about the plane x = y), the block by its
/// faces alone.
fn coulomb_stack(mu: f64) -> Model {
    let mut m = contact_stack(Kind::Hex, 2, Kind::Hex, 4, Law::Coulomb, mu);
    m.supports.retain(|s| s.part == 0);
    m
}

/// The diagonal unit vector of the face plane, (1, 1, 0)/√2.
const DIAGONAL: [f64; 3] = [
    std::f64::consts::FRAC_1_SQRT_2,
    std::f64::consts::FRAC_1_SQRT_2,
    0.0,
];

/// Two load steps: `first` (all DOFs) in one increment, then `second` added in
/// `n` increments; prescribed values (of `dofs`) in the second.
fn two_steps(first: Vec<f64>, second: Vec<f64>, n: usize, dofs: &DofMap<D3>) -> LoadSteps {
    let zero = vec![0.0; first.len()];
    LoadSteps {
        forces: vec![first, second],
        prescribed: vec![zero, dofs.prescribed.clone()],
        increments: std::iter::once((0, vec![1.0, 0.0]))
            .chain((1..=n).map(|k| (1, vec![1.0, k as f64 / n as f64])))
            .collect(),
        progress: std::iter::once(1.0)
            .chain((1..=n).map(|k| k as f64 / n as f64))
            .collect(),
    }
}

/// Coulomb in 3D below the limit: the block pressed by P (step 1), then pushed
/// along the diagonal of x and y by T = 0.03 P with μ = 0.5 (step 2): every pair
/// sticks (no slip anywhere), each inside its cone |f_t| ≤ μ f_n, and the
/// interface carries the loads: Σ f = (−T/√2, −T/√2, P) on the block. (The
/// ratio |f_t| / f_n of bonded faces peaks at the trailing corner, where the
/// push's moment unloads the face and the bonded edges concentrate the shear:
/// 12.3 T/P there, so that corner pair slips at T = 0.1 P even with μ = 1 —
/// the partial-slip case of the tangent-pair test.)
#[test]
fn coulomb_below_the_limit_sticks_everywhere_in_3d() {
    let (mu, p, t) = (0.5, 1.0, 0.03);
    let mut model = coulomb_stack(mu);
    let n = 3 * offsets(&model.parts)[2];
    let mut press = vec![0.0; n];
    traction(&model.parts, 1, "top", [0.0, 0.0, -p], &mut press);
    let mut push = vec![0.0; n];
    traction(&model.parts, 1, "top", DIAGONAL.map(|d| t * d), &mut push);
    let s = solve_with(
        &mut model,
        press.clone(),
        3,
        |d| Some(two_steps(press, push, 2, d)),
        |_| {},
    )
    .unwrap();
    assert!(s.result.violations.is_empty());
    let mut total = [0.0; 3];
    for k in 0..s.interfaces[0].elements.len() {
        assert_eq!(s.result.states[0][k], PairState::Bonded, "pair {k}");
        let (g, (f_n, f_t), _) = pair_force(&s, k);
        assert!(f_t[0].hypot(f_t[1]) <= mu * f_n, "pair {k}: {f_t:?} {f_n}");
        for c in 0..3 {
            total[c] += g[c];
        }
    }
    let want = [-t * DIAGONAL[0], -t * DIAGONAL[1], p];
    assert!(
        (0..3).all(|c| (total[c] - want[c]).abs() < 1e-8),
        "{total:?}"
    );
}

/// Coulomb in 3D beyond the limit, the block held so that a state of rest
/// exists: pressed by P, then its top pushed along the diagonal by a
/// displacement 100 × the elastic scale: every closed pair slips with
/// |f_t| = μ f_n (the trailing corner, lifted by the push's moment, opens and
/// carries nothing), its friction force along −(1, 1, 0)/√2 (the slip follows the load's
/// direction in the plane, not the frame's tangents), Σ f_t = μ P. Pushed by a
/// force T = 0.8 P > μ P with nothing else holding it, the block has no state
/// of rest: the typed error names it.
#[test]
fn coulomb_beyond_the_limit_slips_along_the_load_in_3d() {
    let (mu, p) = (0.3, 1.0);
    let mut model = coulomb_stack(mu);
    let delta = 100.0 * p / E;
    let push = hold(
        &model.parts,
        1,
        "top",
        [true, true, false],
        DIAGONAL.map(|d| delta * d),
    );
    model.supports.push(Support { step: 1, ..push });
    let n = 3 * offsets(&model.parts)[2];
    let mut press = vec![0.0; n];
    traction(&model.parts, 1, "top", [0.0, 0.0, -p], &mut press);
    let s = solve_with(
        &mut model,
        press.clone(),
        3,
        |d| Some(two_steps(press, vec![0.0; n], 2, d)),
        |_| {},
    )
    .unwrap();
    assert!(s.result.violations.is_empty());
    let scale = s.result.load_scale;
    let mut total = [0.0; 3];
    let mut slipping = 0;
    for k in 0..s.interfaces[0].elements.len() {
        let (g, (f_n, f_t), _) = pair_force(&s, k);
        if s.result.states[0][k] == PairState::Open {
            assert_eq!(g, [0.0; 3]);
            continue;
        }
        assert_eq!(s.result.states[0][k], PairState::Slip, "pair {k}");
        slipping += 1;
        let ft = f_t[0].hypot(f_t[1]);
        assert!(
            (ft - mu * f_n).abs() < 1e-8 * scale,
            "pair {k}: {ft} against {}",
            mu * f_n
        );
        let along = -(g[0] * DIAGONAL[0] + g[1] * DIAGONAL[1]) / ft;
        assert!(
            along > 1.0 - 1e-6,
            "pair {k}: friction {g:?} off the diagonal ({along})"
        );
        for c in 0..3 {
            total[c] += g[c];
        }
    }
    assert!(
        slipping > s.interfaces[0].elements.len() / 2,
        "{slipping} slip"
    );
    let want = [-mu * p * DIAGONAL[0], -mu * p * DIAGONAL[1], p];
    assert!(
        (0..3).all(|c| (total[c] - want[c]).abs() < 1e-8),
        "{total:?}"
    );
    // A force beyond friction on the free block: no state of rest.
    let mut model = coulomb_stack(mu);
    let mut f = vec![0.0; n];
    traction(
        &model.parts,
        1,
        "top",
        [0.8 * p * DIAGONAL[0], 0.8 * p * DIAGONAL[1], -p],
        &mut f,
    );
    match solve_with(&mut model, f, 2, |_| None, |_| {}) {
        Err(Error::Unsupported { parts, message }) => {
            assert_eq!(parts, ["block"]);
            assert!(
                message.contains("harder than friction holds them"),
                "{message}"
            );
        }
        other => panic!("beyond friction: {:?}", other.map(|s| s.result.states)),
    }
}

/// Every pair's frame with its tangents turned about n by an angle of its own
/// (0.3 + 1.7 k rad for pair k): another right-handed orthonormal frame of
/// the same face.
fn turn_tangents(interfaces: &mut [Interface<D3>]) {
    for iface in interfaces {
        for (k, c) in iface.elements.iter_mut().enumerate() {
            let [n, t1, t2] = c.frame;
            let (sn, cs) = (0.3 + 1.7 * k as f64).sin_cos();
            c.frame = [
                n,
                std::array::from_fn(|i| cs * t1[i] + sn * t2[i]),
                std::array::from_fn(|i| -sn * t1[i] + cs * t2[i]),
            ];
        }
    }
}

/// Compares two solutions of one model: the displacements to `tol` × the
/// largest, the pair states equal, the global pair forces to `tol` × the largest.
fn assert_same(a: &Solved, b: &Solved, tol: f64, what: &str) {
    let umax = a.result.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (x, y) in a.result.u.iter().zip(&b.result.u) {
        assert!((x - y).abs() <= tol * umax, "{what}: u {x} against {y}");
    }
    assert_eq!(a.result.states, b.result.states, "{what}");
    let forces = |s: &Solved| {
        (0..s.interfaces[0].elements.len())
            .map(|k| pair_force(s, k).0)
            .collect::<Vec<_>>()
    };
    let (fa, fb) = (forces(a), forces(b));
    let fmax = fa.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for (x, y) in fa.iter().zip(&fb) {
        for c in 0..3 {
            assert!(
                (x[c] - y[c]).abs() <= tol * fmax,
                "{what}: force {x:?} against {y:?}"
            );
        }
    }
}

/// No result depends on the choice of the tangents t₁, t₂: every coupling
/// element's tangent pair turned about n by an angle of its own gives the same
/// displacements, pair states and pair forces (global) to round-off — the
/// stick law (`contact`) and `frictionless` on non-nested faces under a
/// pressure (the stick pairs carrying the mismatch's shear), and Coulomb in
/// partial slip under a push off the diagonal and slipping under a diagonal
/// displacement, with the slip forces by the fixed point and by the
/// semi-smooth Newton (`friction_solve = "newton"`, whose radial return turns
/// each slipping pair's direction within its pattern).
#[test]
fn no_result_depends_on_the_tangent_pair() {
    for law in [Law::Contact, Law::Frictionless] {
        let run = |turn: bool| {
            let mut model = contact_stack(Kind::Hex, 3, Kind::Tet, 4, law, 0.0);
            let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
            traction(&model.parts, 1, "top", [0.0, 0.0, -5.0], &mut f);
            solve_with(
                &mut model,
                f,
                1,
                |_| None,
                |i| {
                    if turn {
                        turn_tangents(i)
                    }
                },
            )
            .unwrap()
        };
        assert_same(&run(false), &run(true), 1e-9, &format!("{law:?}"));
    }
    for (slip, how) in [false, true]
        .into_iter()
        .flat_map(|s| [(s, FrictionSolve::FixedPoint), (s, FrictionSolve::Newton)])
    {
        let run = |turn: bool| {
            let mu = 0.3;
            let mut model = coulomb_stack(mu);
            let n = 3 * offsets(&model.parts)[2];
            let mut press = vec![0.0; n];
            traction(&model.parts, 1, "top", [0.0, 0.0, -1.0], &mut press);
            let mut push = vec![0.0; n];
            if slip {
                let d = DIAGONAL.map(|d| 100.0 / E * d);
                let s = hold(&model.parts, 1, "top", [true, true, false], d);
                model.supports.push(Support { step: 1, ..s });
            } else {
                traction(&model.parts, 1, "top", [0.1, 0.05, 0.0], &mut push);
            }
            let steps = |d: &DofMap<D3>| Some(two_steps(press.clone(), push, 2, d));
            let turned = |i: &mut Vec<Interface<D3>>| {
                if turn {
                    turn_tangents(i)
                }
            };
            solve_friction(&mut model, press.clone(), 3, steps, turned, how).unwrap()
        };
        let (a, b) = (run(false), run(true));
        let slipping = a.result.states[0]
            .iter()
            .filter(|s| **s == PairState::Slip)
            .count();
        let sticking = a.result.states[0]
            .iter()
            .filter(|s| **s == PairState::Bonded)
            .count();
        assert!(
            slipping > 0 && (slip || sticking > 0),
            "{slipping} pairs slip, {sticking} stick"
        );
        assert_same(&a, &b, 1e-8, &format!("Coulomb, slip {slip}, {how:?}"));
    }
}

/// The rotation by `angle` about the unit `axis` (Rodrigues), applied to `v`.
fn rotate(axis: [f64; 3], angle: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let k = axis;
    let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    let x = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    std::array::from_fn(|i| v[i] * c + x[i] * s + k[i] * kv * (1.0 - c))
}

/// A rigid rotation of the whole model (nodes and loads, an arbitrary axis and
/// angle) gives the rotated displacements and pair forces to round-off and
/// the same pair states: the tied stack on non-nested faces (HEX8 3 under
/// TET4 4) and the stick law under a load that tips the block, opening part
/// of its face. The base is clamped at its bottom (a support any rotation
/// keeps), the top loaded by a uniform traction.
#[test]
fn a_rigid_rotation_of_the_model_rotates_the_results() {
    let l = (1.0f64 + 4.0 + 9.0).sqrt();
    let axis = [1.0 / l, -2.0 / l, 3.0 / l];
    let angle = 0.83;
    for (law, t) in [
        (Law::Rigid, [1.0, 2.0, -5.0]),
        (Law::Contact, [1.5, 0.5, -3.0]),
    ] {
        let run = |rotated: bool| {
            let mut model = contact_stack(Kind::Hex, 3, Kind::Tet, 4, law, 0.0);
            model.supports = vec![hold(&model.parts, 0, "bottom", [true; 3], [0.0; 3])];
            if rotated {
                for part in &mut model.parts {
                    for x in &mut part.mesh.nodes {
                        *x = rotate(axis, angle, *x);
                    }
                }
            }
            let load = if rotated { rotate(axis, angle, t) } else { t };
            let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
            traction(&model.parts, 1, "top", load, &mut f);
            solve_with(&mut model, f, 1, |_| None, |_| {}).unwrap()
        };
        let (a, b) = (run(false), run(true));
        assert_eq!(a.result.states, b.result.states, "{law:?}");
        if law == Law::Contact {
            let open = a.result.states[0]
                .iter()
                .filter(|s| **s == PairState::Open)
                .count();
            assert!(open > 0 && open < a.result.states[0].len(), "{open} open");
        }
        let umax = a.result.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (ua, ub) in a.result.u.chunks(3).zip(b.result.u.chunks(3)) {
            let r = rotate(axis, angle, [ua[0], ua[1], ua[2]]);
            assert!(
                (0..3).all(|c| (r[c] - ub[c]).abs() < 1e-9 * umax),
                "{law:?}: {r:?} against {ub:?}"
            );
        }
        for k in 0..a.interfaces[0].elements.len() {
            let (fa, _, _) = pair_force(&a, k);
            let (fb, _, _) = pair_force(&b, k);
            let r = rotate(axis, angle, fa);
            assert!(
                (0..3).all(|c| (r[c] - fb[c]).abs() < 1e-8 * 5.0),
                "{law:?}: {r:?} against {fb:?}"
            );
        }
    }
}

/// A curved interface meshed apart: a base [−1, 1]² × [0, 1] (HEX8 3 × 3)
/// whose top is bent onto the paraboloid z = 1 + a (2 − x² − y²), a = 0.05 (a
/// sphere-ish cap of curvature 2a), and a TET4 block (4 × 4) whose bottom is
/// on the same surface: its nodes lie on the surface, off the host's bilinear
/// facets. Building the tied interface moves each coupling node onto its host
/// face — the moved node is Σ N̄ᵢ Xᵢ of its face, the shape values a partition
/// of unity ≥ 0 — by at most the facets' sagitta κ h²/8 (κ = 2a, h the facet's
/// diagonal), and the reported `max_projection_distance` is the largest move;
/// the tied model then carries a load to its support, the pairs' forces
/// balancing it.
#[test]
fn a_curved_interface_moves_its_nodes_onto_the_host_faces() {
    let a = 0.05;
    let cap = |x: [f64; 3]| a * (2.0 - x[0] * x[0] - x[1] * x[1]);
    let mut base = block([-1.0, 1.0], [-1.0, 1.0], [0.0, 1.0], [3, 3, 2], Kind::Hex);
    for x in &mut base.nodes {
        x[2] *= 1.0 + cap(*x);
    }
    let mut top = block([-1.0, 1.0], [-1.0, 1.0], [1.0, 1.5], [4, 4, 2], Kind::Tet);
    for x in &mut top.nodes {
        x[2] += cap(*x);
    }
    let parts = vec![part("base", base), part("block", top)];
    let defs = vec![interface_def(&parts, Law::Rigid, 1e5 * E * 0.5, 0.0)];
    let supports = vec![hold(&parts, 0, "bottom", [true; 3], [0.0; 3])];
    let mut model = Model {
        parts,
        defs,
        supports,
    };
    let before = model.parts[1].mesh.nodes.clone();
    let mut f = vec![0.0; 3 * offsets(&model.parts)[2]];
    traction(&model.parts, 1, "top", [0.5, -0.3, -2.0], &mut f);
    let applied: [f64; 3] = std::array::from_fn(|c| f.iter().skip(c).step_by(3).sum());
    let s = solve(&mut model, f);
    let iface = &s.interfaces[0];
    let host = &model.parts[0].mesh.nodes;
    let h = (2.0f64 / 3.0) * 2.0f64.sqrt();
    let sagitta = 2.0 * a * h * h / 8.0;
    let mut largest = 0.0f64;
    for c in &iface.elements {
        let moved = model.parts[1].mesh.nodes[c.node];
        assert_eq!(moved, c.position);
        let on_face: [f64; 3] = std::array::from_fn(|k| {
            (0..c.shape.len())
                .map(|i| c.shape[i] * host[c.host_nodes[i]][k])
                .sum()
        });
        assert!(
            (0..3).all(|k| (on_face[k] - moved[k]).abs() < 1e-12),
            "{on_face:?} {moved:?}"
        );
        assert!(
            c.shape.iter().all(|&v| v >= -1e-12)
                && (c.shape.iter().sum::<f64>() - 1.0).abs() < 1e-12
        );
        let d = (0..3)
            .map(|k| (moved[k] - before[c.node][k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((d - c.distance).abs() < 1e-14, "{d} {}", c.distance);
        assert!(d <= sagitta * (1.0 + 1e-12), "{d} > {sagitta}");
        largest = largest.max(d);
    }
    eprintln!("curved: largest move {largest:e}, sagitta bound {sagitta:e}");
    assert!(
        largest > 1e-4,
        "{largest}: the faces were meant to be apart"
    );
    assert_eq!(iface.max_projection_distance, largest);
    let total: [f64; 3] = (0..iface.elements.len()).fold([0.0; 3], |acc, k| {
        let (g, _, _) = pair_force(&s, k);
        [acc[0] + g[0], acc[1] + g[1], acc[2] + g[2]]
    });
    assert!(
        (0..3).all(|c| (total[c] + applied[c]).abs() < 1e-8),
        "{total:?} against {applied:?}"
    );
}
