//! The volume form of the coupling element (`form = "volume"`): a finely meshed
//! insert embedded inside a coarse host (overlapping meshes), every insert node
//! inside a host element tied to all of that element's nodes. The truth is the
//! closed-form linear field and its constant stress, the invariance under a
//! rigid rotation, the element's algebra (symmetry, rigid modes, K d = F), and
//! the typed refusals of what the volume form cannot mean.

mod common;

use cfe::assembly::DofMap;
use cfe::coupling::{Coupling, CouplingForm, Interface, Law, PairState, build, volume};
use cfe::dim::{D2, D3};
use cfe::domain::{Enforcement, InterfaceDef, Part, Settings, Support};
use cfe::error::Error;
use cfe::fem::material::d_solid;
use cfe::fem::{ElementFamily, Material, PlaneKind, face3};
use cfe::mesh::{ElementKind, FaceNodes, Mesh, SolidKind};
use cfe::solve::nonlinear::{IncrementResult, Solver};

const E: f64 = 210e3;
const NU: f64 = 0.3;

fn material(name: &str) -> Material {
    Material::new(E, NU, PlaneKind::Strain, 1.0, name).unwrap()
}

/// The volume-form tie of every node of part 1 (the insert) in part 0 (the
/// host), rigid, penalty `c`.
fn embed(parts_nodes: usize, law: Law, c_n: f64, c_s: f64) -> InterfaceDef {
    InterfaceDef {
        name: "host/insert".into(),
        host: 0,
        node_part: 1,
        nodes: (0..parts_nodes).collect(),
        boundary: String::new(),
        law,
        c_n,
        c_s,
        tolerance: 0.05,
        friction: 0.0,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        coupling: Coupling::Node,
        form: CouplingForm::Volume,
    }
}

/// Node `k` of part `p` held at `value` in every component.
fn held(p: usize, k: usize, value: [f64; 3]) -> Support {
    Support {
        name: format!("{p}/{k}"),
        part: p,
        nodes: vec![k],
        fix: [true; 3],
        value,
        step: 0,
    }
}

/// The linear field u(X) = A X + b of the patch tests (3D; its top-left 2 × 2
/// block and first two entries of b in 2D).
const A: [[f64; 3]; 3] = [
    [1e-3, 4e-4, -2e-4],
    [-3e-4, -5e-4, 6e-4],
    [2e-4, 7e-4, 8e-4],
];
const B: [f64; 3] = [0.01, -0.02, 0.005];

fn field(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| B[i] + (0..n).map(|j| A[i][j] * x[j]).sum::<f64>())
        .collect()
}

/// Solves `parts` with `interfaces` under the supports and no load, in one
/// increment.
fn solve<D: ElementFamily>(
    parts: &[Part<D>],
    interfaces: &[Interface<D>],
    supports: &[Support],
    f_ext: Vec<f64>,
) -> (DofMap<D>, IncrementResult<D>) {
    let counts: Vec<usize> = parts.iter().map(|p| p.mesh.nodes.len()).collect();
    let dofs = DofMap::<D>::numbered(&counts, supports);
    let settings = Settings::default();
    let mut last = None;
    {
        let mut solver = Solver::new(parts, interfaces, &dofs, f_ext, &settings, None).unwrap();
        solver
            .run(|inc| {
                last = Some(inc.clone());
                Ok(())
            })
            .unwrap();
    }
    (dofs, last.unwrap())
}

/// The relative errors (displacement of the insert's nodes against the field,
/// relative to |b_y|; stress of both parts against D ε(A), relative to its
/// largest component) of the 3D patch test with hosts of `host_kind`, inserts
/// of `insert_kind` and penalty `c`.
fn patch_3d(host_kind: SolidKind, insert_kind: SolidKind, c: f64) -> (f64, f64) {
    let eps = [
        A[0][0],
        A[1][1],
        A[2][2],
        A[0][1] + A[1][0],
        A[1][2] + A[2][1],
        A[2][0] + A[0][2],
    ];
    let d = d_solid(E, NU);
    let sigma: Vec<f64> = (0..6)
        .map(|i| (0..6).map(|j| d[i][j] * eps[j]).sum())
        .collect();
    let scale = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let host = Mesh::<D3>::block([0.0, 2.0], [0.0, 2.0], [0.0, 2.0], [2, 2, 2], host_kind);
    // Nodes at z = 0.2, 0.6, 1.0 (on the host's shared face z = 1).
    let insert = Mesh::<D3>::block([0.5, 1.3], [0.4, 1.6], [0.2, 1.0], [4, 3, 2], insert_kind);
    let n_insert = insert.nodes.len();
    let mut parts = vec![
        Part {
            name: "host".into(),
            material: material("host"),
            mesh: host,
        },
        Part {
            name: "insert".into(),
            material: material("insert"),
            mesh: insert,
        },
    ];
    let supports: Vec<Support> = (parts[0].mesh.nodes.iter().enumerate())
        .map(|(k, x)| {
            let u = field(x);
            held(0, k, [u[0], u[1], u[2]])
        })
        .collect();
    let defs = vec![embed(n_insert, Law::Rigid, c, c)];
    let interfaces = build::interfaces(&defs, &mut parts, 1).unwrap();
    assert_eq!(
        (interfaces[0].elements.len(), interfaces[0].unpaired),
        (n_insert, 0)
    );
    let n_host = if host_kind == SolidKind::Hex8 { 8 } else { 4 };
    assert!(
        interfaces[0]
            .elements
            .iter()
            .all(|e| e.host_nodes.len() == n_host)
    );
    let dofs_total = 3 * (parts[0].mesh.nodes.len() + n_insert);
    let (_, r) = solve(&parts, &interfaces, &supports, vec![0.0; dofs_total]);
    assert!(r.violations.is_empty());
    let off = parts[0].mesh.nodes.len();
    let mut u_err = 0.0f64;
    for (k, x) in parts[1].mesh.nodes.iter().enumerate() {
        let want = field(x);
        for (c, w) in want.iter().enumerate() {
            u_err = u_err.max((r.u[3 * (off + k) + c] - w).abs() / B[1].abs());
        }
    }
    let mut s_err = 0.0f64;
    for (p, part) in parts.iter().enumerate() {
        let lo = if p == 0 { 0 } else { off };
        let up = &r.u[3 * lo..3 * (lo + part.mesh.nodes.len())];
        let s = D3::recover(&part.mesh, &part.material, up);
        for v in s.element.iter().chain(&s.nodal) {
            for c in 0..6 {
                s_err = s_err.max((v[c] - sigma[c]).abs() / scale);
            }
        }
    }
    (u_err, s_err)
}

/// Patch test in 3D, TET4 and HEX8 hosts and inserts: a block [0, 2]³ of
/// 2 × 2 × 2 cells with every node held at the linear field u = A X + b, a
/// finer block inside it (some of its nodes on the host's shared faces) tied
/// in volume form and otherwise free: every insert node moves with the field
/// and the insert's stress equals the host's constant stress D ε(A) to the
/// penalty's accuracy — the ties carry the tractions σ·n of the insert's free
/// boundary, so the error is O(E h / c), falling tenfold when c grows
/// tenfold, and at c = 1e6 E h below 1e-6 (displacement) and 1e-4 (stress).
#[test]
fn an_embedded_block_follows_a_linear_host_field_in_3d() {
    let h = 0.2;
    for host_kind in [SolidKind::Tet4, SolidKind::Hex8] {
        for insert_kind in [SolidKind::Tet4, SolidKind::Hex8] {
            let (u1, s1) = patch_3d(host_kind, insert_kind, 1e3 * E * h);
            let (u2, s2) = patch_3d(host_kind, insert_kind, 1e4 * E * h);
            let (u3, s3) = patch_3d(host_kind, insert_kind, 1e6 * E * h);
            eprintln!(
                "{host_kind:?}/{insert_kind:?}: u {u1:e} {u2:e} {u3:e}, σ {s1:e} {s2:e} {s3:e}"
            );
            assert!(
                (u1 / u2 - 10.0).abs() < 1.0 && (s1 / s2 - 10.0).abs() < 1.0,
                "{u1} {u2} {s1} {s2}"
            );
            assert!(u3 < 1e-6 && s3 < 1e-4, "{u3} {s3}");
        }
    }
}

/// The relative errors of the 2D patch test (as [`patch_3d`]), plane strain.
fn patch_2d(host_kind: ElementKind, insert_kind: ElementKind, c: f64) -> (f64, f64) {
    let eps = [A[0][0], A[1][1], A[0][1] + A[1][0]];
    let d = material("m").d_matrix();
    let sigma: Vec<f64> = (0..3)
        .map(|i| (0..3).map(|j| d[i][j] * eps[j]).sum())
        .collect();
    let scale = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let host = Mesh::rectangle([0.0, 2.0], [0.0, 2.0], [2, 2], host_kind);
    // Nodes at y = 0.2, 0.6, 1.0 (on the host's shared edge y = 1).
    let insert = Mesh::rectangle([0.5, 1.3], [0.2, 1.0], [4, 2], insert_kind);
    let n_insert = insert.nodes.len();
    let mut parts = vec![
        Part {
            name: "host".into(),
            material: material("host"),
            mesh: host,
        },
        Part {
            name: "insert".into(),
            material: material("insert"),
            mesh: insert,
        },
    ];
    let supports: Vec<Support> = (parts[0].mesh.nodes.iter().enumerate())
        .map(|(k, x)| {
            let u = field(x);
            held(0, k, [u[0], u[1], 0.0])
        })
        .collect();
    let defs = vec![embed(n_insert, Law::Rigid, c, c)];
    let interfaces = build::interfaces(&defs, &mut parts, 1).unwrap();
    assert_eq!(
        (interfaces[0].elements.len(), interfaces[0].unpaired),
        (n_insert, 0)
    );
    let dofs_total = 2 * (parts[0].mesh.nodes.len() + n_insert);
    let (_, r) = solve(&parts, &interfaces, &supports, vec![0.0; dofs_total]);
    let off = parts[0].mesh.nodes.len();
    let mut u_err = 0.0f64;
    for (k, x) in parts[1].mesh.nodes.iter().enumerate() {
        let want = field(x);
        for (c, w) in want.iter().enumerate() {
            u_err = u_err.max((r.u[2 * (off + k) + c] - w).abs() / B[1].abs());
        }
    }
    let mut s_err = 0.0f64;
    for (p, part) in parts.iter().enumerate() {
        let lo = if p == 0 { 0 } else { off };
        let up = &r.u[2 * lo..2 * (lo + part.mesh.nodes.len())];
        let s = D2::recover(&part.mesh, &part.material, up);
        for v in s.element.iter().chain(&s.nodal) {
            for c in 0..3 {
                s_err = s_err.max((v[c] - sigma[c]).abs() / scale);
            }
        }
    }
    (u_err, s_err)
}

/// The same patch test in 2D (plane strain; T3 and Q4 hosts and inserts): the
/// volume form is generic over the dimension; the same penalty accuracy.
#[test]
fn an_embedded_block_follows_a_linear_host_field_in_2d() {
    let h = 0.2;
    for host_kind in [ElementKind::T3, ElementKind::Q4] {
        for insert_kind in [ElementKind::T3, ElementKind::Q4] {
            let (u1, s1) = patch_2d(host_kind, insert_kind, 1e3 * E * h);
            let (u2, s2) = patch_2d(host_kind, insert_kind, 1e4 * E * h);
            let (u3, s3) = patch_2d(host_kind, insert_kind, 1e6 * E * h);
            eprintln!(
                "{host_kind:?}/{insert_kind:?}: u {u1:e} {u2:e} {u3:e}, σ {s1:e} {s2:e} {s3:e}"
            );
            assert!(
                (u1 / u2 - 10.0).abs() < 1.0 && (s1 / s2 - 10.0).abs() < 1.0,
                "{u1} {u2} {s1} {s2}"
            );
            assert!(u3 < 1e-6 && s3 < 1e-4, "{u3} {s3}");
        }
    }
}

/// The rotation by `angle` about the unit `axis` (Rodrigues), applied to `v`.
fn rotate(axis: [f64; 3], angle: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let k = axis;
    let kxv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    std::array::from_fn(|i| v[i] * c + kxv[i] * s + k[i] * kv * (1.0 - c))
}

/// The embedded model of the rotation test: a HEX8 host [0, 2] × [0, 1] ×
/// [0, 3] clamped at its bottom, a TET4 insert inside it tied in volume form
/// (a stiffer insert, E × 5: the tie carries force), the host's top under the
/// traction `t`; its nodes rotated by `turn` first. The displacements and the
/// pairs' global forces.
fn embedded_run(t: [f64; 3], turn: impl Fn([f64; 3]) -> [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>) {
    let mut host = Mesh::<D3>::block(
        [0.0, 2.0],
        [0.0, 1.0],
        [0.0, 3.0],
        [2, 2, 3],
        SolidKind::Hex8,
    );
    let mut insert = Mesh::<D3>::block(
        [0.3, 1.7],
        [0.2, 0.8],
        [0.5, 2.5],
        [3, 2, 4],
        SolidKind::Tet4,
    );
    for x in host.nodes.iter_mut().chain(insert.nodes.iter_mut()) {
        *x = turn(*x);
    }
    let n_insert = insert.nodes.len();
    let stiff = Material::new(5.0 * E, NU, PlaneKind::Strain, 1.0, "insert").unwrap();
    let mut parts = vec![
        Part {
            name: "host".into(),
            material: material("host"),
            mesh: host,
        },
        Part {
            name: "insert".into(),
            material: stiff,
            mesh: insert,
        },
    ];
    let supports = vec![Support {
        name: "host/bottom".into(),
        part: 0,
        nodes: parts[0].mesh.boundary_nodes("bottom").unwrap(),
        fix: [true; 3],
        value: [0.0; 3],
        step: 0,
    }];
    let c = 1e3 * E;
    let defs = vec![embed(n_insert, Law::Rigid, c, c)];
    let interfaces = build::interfaces(&defs, &mut parts, 1).unwrap();
    assert_eq!(interfaces[0].elements.len(), n_insert);
    let mut f = vec![0.0; 3 * (parts[0].mesh.nodes.len() + n_insert)];
    let mesh = &parts[0].mesh;
    let load = turn(t);
    for face in &mesh.boundaries["top"] {
        let FaceNodes::Quad(n) = face.nodes else {
            unreachable!("a HEX8 block")
        };
        let forces = face3::quad_traction_forces(&n.map(|k| mesh.nodes[k]), load);
        for (&k, fv) in n.iter().zip(&forces) {
            for c in 0..3 {
                f[3 * k + c] += fv[c];
            }
        }
    }
    let (dofs, r) = solve(&parts, &interfaces, &supports, f);
    assert!(r.violations.is_empty());
    let iface = &interfaces[0];
    let forces = (0..iface.elements.len())
        .map(|k| {
            let at = iface.pair_at(k, &dofs, &r.u, r.states[0][k], &r.pair_history[0][k]);
            let c = &iface.elements[k];
            <D3 as cfe::dim::Dim>::to_global(&c.frame, at.force.0, at.force.1)
        })
        .collect();
    (r.u, forces)
}

/// A rigid rotation of a tied embedded model (nodes and load, an arbitrary
/// axis and angle) rotates its displacements and its pairs' forces to
/// round-off: the volume form reads no frame of its own (c·I).
#[test]
fn a_rigid_rotation_of_an_embedded_model_rotates_the_results() {
    let l = (1.0f64 + 4.0 + 9.0).sqrt();
    let axis = [1.0 / l, -2.0 / l, 3.0 / l];
    let angle = 0.83;
    let t = [3.0, -1.0, -5.0];
    let (ua, fa) = embedded_run(t, |x| x);
    let (ub, fb) = embedded_run(t, |x| rotate(axis, angle, x));
    let umax = ua.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, b) in ua.chunks(3).zip(ub.chunks(3)) {
        let r = rotate(axis, angle, [a[0], a[1], a[2]]);
        assert!(
            (0..3).all(|c| (r[c] - b[c]).abs() < 1e-9 * umax),
            "{r:?} against {b:?}"
        );
    }
    let fmax = fa.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(fmax > 1e-3, "the tie carries force: {fmax}");
    for (a, b) in fa.iter().zip(&fb) {
        let r = rotate(axis, angle, *a);
        assert!(
            (0..3).all(|c| (r[c] - b[c]).abs() < 1e-8 * fmax),
            "{r:?} against {b:?}"
        );
    }
}

/// The volume element's stiffness (TET4 and HEX8 hosts, 5 and 9 nodes; T3
/// and Q4, 4 and 5) is exactly symmetric, positive semidefinite of rank N (the
/// jump's N components), has the rigid modes of node and host together in its
/// null space, and its internal force is K d and self-equilibrated — the
/// tie's force is linear in d, so its central difference is K.
#[test]
fn the_volume_element_is_symmetric_psd_with_the_rigid_modes_in_its_null_space() {
    let tet = Mesh::<D3>::block(
        [0.0, 1.0],
        [0.0, 1.5],
        [0.0, 0.8],
        [1, 1, 1],
        SolidKind::Tet4,
    );
    let hex = Mesh::<D3>::block(
        [0.0, 1.0],
        [0.0, 1.5],
        [0.0, 0.8],
        [1, 1, 1],
        SolidKind::Hex8,
    );
    let probe = [[0.3, 0.8, 0.2]];
    let c = 1e6;
    for host in [tet, hex] {
        let (pairs, _) = volume::embedded_elements(&host, &probe, &[0]);
        let e = &pairs[0];
        let x: Vec<[f64; 3]> = e
            .host_nodes
            .iter()
            .map(|&i| host.nodes[i])
            .chain([probe[0]])
            .collect();
        let n = 3 * x.len();
        assert_eq!(e.n_dofs(), n);
        let k = e.stiffness(c, c, PairState::Bonded);
        let dense: Vec<Vec<f64>> = (0..n)
            .map(|p| (0..n).map(|q| k.get(p, q)).collect())
            .collect();
        for (p, row) in dense.iter().enumerate() {
            for (q, v) in row.iter().enumerate() {
                assert_eq!(*v, dense[q][p]);
            }
        }
        // Rigid modes: translations and infinitesimal rotations θ × X.
        for m in 0..6 {
            let d: Vec<f64> = (0..n)
                .map(|p| {
                    let (a, comp) = (p / 3, p % 3);
                    let y = x[a];
                    match m {
                        0..=2 => f64::from(u8::from(comp == m)),
                        3 => [0.0, -y[2], y[1]][comp],
                        4 => [y[2], 0.0, -y[0]][comp],
                        _ => [-y[1], y[0], 0.0][comp],
                    }
                })
                .collect();
            let kd = k.mul(&d);
            assert!(
                kd[..n].iter().all(|v| v.abs() < 1e-9 * c),
                "mode {m}: {kd:?}"
            );
        }
        // K = c b bᵀ ⊗ I: its nonzero eigenvalue is c |b|² (3 times), PSD.
        let b2: f64 = 1.0 + e.shape.iter().map(|s| s * s).sum::<f64>();
        let trace: f64 = (0..n).map(|p| dense[p][p]).sum();
        assert!((trace - 3.0 * c * b2).abs() < 1e-9 * trace);
        let d: Vec<f64> = (0..n).map(|p| ((p * 7) % 5) as f64 * 0.1 - 0.2).collect();
        let energy: f64 = (0..n)
            .map(|p| d[p] * (0..n).map(|q| dense[p][q] * d[q]).sum::<f64>())
            .sum();
        assert!(energy >= 0.0);
        let (f, _) = e.internal_force(c, c, PairState::Bonded, &d);
        let kd = k.mul(&d);
        for p in 0..n {
            assert!((f[p] - kd[p]).abs() < 1e-9 * c);
        }
        for comp in 0..3 {
            assert!((0..x.len()).map(|a| f[3 * a + comp]).sum::<f64>().abs() < 1e-9 * c);
        }
    }
}

/// An insert sticking out of the host: its nodes inside are coupled, those
/// outside are not, and the interface counts them (`unpaired`), the counts
/// those of the geometry (x ≤ 1 of the host [0, 1]³; insert nodes at x =
/// 0.6, 0.8, 1.0, 1.2, 1.4: three planes in, two out).
#[test]
fn nodes_outside_the_host_are_not_coupled_and_are_counted() {
    let host = Mesh::<D3>::block(
        [0.0, 1.0],
        [0.0, 1.0],
        [0.0, 1.0],
        [2, 2, 2],
        SolidKind::Hex8,
    );
    let insert = Mesh::<D3>::block(
        [0.6, 1.4],
        [0.2, 0.8],
        [0.2, 0.8],
        [4, 2, 2],
        SolidKind::Hex8,
    );
    let n_insert = insert.nodes.len();
    let inside = insert.nodes.iter().filter(|x| x[0] <= 1.0).count();
    let mut parts = vec![
        Part {
            name: "host".into(),
            material: material("host"),
            mesh: host,
        },
        Part {
            name: "insert".into(),
            material: material("insert"),
            mesh: insert,
        },
    ];
    let defs = vec![embed(n_insert, Law::Rigid, 1e9, 1e9)];
    let interfaces = build::interfaces(&defs, &mut parts, 1).unwrap();
    assert_eq!(inside, 27);
    assert_eq!(interfaces[0].elements.len(), inside);
    assert_eq!(interfaces[0].unpaired, n_insert - inside);
    assert!(
        interfaces[0]
            .elements
            .iter()
            .all(|c| parts[1].mesh.nodes[c.node][0] <= 1.0)
    );
    // An insert wholly outside couples nothing: a typed error.
    let far = Mesh::<D3>::block(
        [2.0, 3.0],
        [0.0, 1.0],
        [0.0, 1.0],
        [1, 1, 1],
        SolidKind::Hex8,
    );
    parts[1].mesh = far;
    let e = build::interfaces(&[embed(8, Law::Rigid, 1e9, 1e9)], &mut parts, 1).unwrap_err();
    assert!(
        matches!(&e, Error::Coupling { interface, .. } if interface == "host/insert"),
        "{e}"
    );
}

/// What the volume form cannot mean is refused with a typed error naming the
/// interface: a contact law (no face, so no normal to measure a gap or a
/// slip along), c_n ≠ c_s (a tie without a frame must be c·I), a search
/// distance.
#[test]
fn a_contact_law_or_unequal_penalties_in_volume_form_are_refused() {
    let host = Mesh::<D3>::block(
        [0.0, 1.0],
        [0.0, 1.0],
        [0.0, 1.0],
        [1, 1, 1],
        SolidKind::Tet4,
    );
    let insert = Mesh::<D3>::block(
        [0.2, 0.8],
        [0.2, 0.8],
        [0.2, 0.8],
        [1, 1, 1],
        SolidKind::Tet4,
    );
    let mut parts = vec![
        Part {
            name: "host".into(),
            material: material("host"),
            mesh: host,
        },
        Part {
            name: "insert".into(),
            material: material("insert"),
            mesh: insert,
        },
    ];
    let mut gapped = embed(8, Law::Rigid, 1e9, 1e9);
    gapped.search_distance = 0.1;
    for (def, says) in [
        (embed(8, Law::Contact, 1e9, 1e9), "no normal"),
        (embed(8, Law::Coulomb, 1e9, 1e9), "no normal"),
        (embed(8, Law::Frictionless, 1e9, 0.0), "no normal"),
        (embed(8, Law::Rigid, 1e9, 5e8), "c·I"),
        (gapped, "search_distance"),
    ] {
        let e = build::interfaces(&[def], &mut parts, 1).unwrap_err();
        assert!(
            matches!(&e, Error::Coupling { interface, .. } if interface == "host/insert"),
            "{e}"
        );
        assert!(e.to_string().contains(says), "{e}");
    }
}

/// Through a problem file (`[[interface]] form = "volume"`): a strip's
/// boundary nodes tied inside a larger base, the nodes beyond the base not
/// coupled and counted in the summary (`unpaired`), the run completed; without
/// `boundary` every node of the strip couples (those inside the base); a
/// contact law there is the typed error, and so is a face-form interface
/// without `boundary`.
#[test]
fn a_problem_file_asks_for_the_volume_form() {
    let text = |law: &str, boundary: &str, form: &str| {
        format!(
            r#"
title = "embedded"
plane = "strain"
[materials.steel]
E = 210000.0
nu = 0.3
[[part]]
name = "base"
material = "steel"
rectangle = {{ x = [0.0, 10.0], y = [0.0, 4.0], cells = [5, 2], elements = "q4" }}
[[part]]
name = "strip"
material = "steel"
rectangle = {{ x = [2.0, 12.0], y = [1.0, 2.0], cells = [10, 2] }}
[[interface]]
host = "base"
nodes = "strip"
{boundary}
{form}
law = "{law}"
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
[[load]]
part = "base"
boundary = "top"
force = [100.0, -300.0]
"#
        )
    };
    let text_of = |law: &str| text(law, "boundary = \"bottom\"", "form = \"volume\"");
    let a = common::analysis(&text_of("rigid"));
    let iface = &a.interfaces[0];
    // The strip's bottom nodes at x = 2, 3, …, 12: x ≤ 10 inside (9), 2 beyond.
    assert_eq!(
        (iface.elements.len(), iface.unpaired, iface.form),
        (9, 2, CouplingForm::Volume)
    );
    let res = common::solve_completed(&a);
    let s = &res.summary.interfaces[0];
    assert_eq!((s.pairs, s.unpaired), (9, 2));
    assert!(a.describe().contains("volume form"), "{}", a.describe());
    let path = std::path::Path::new("t.toml");
    let model = cfe::model::Model::from_str(&text_of("contact"), path, 1).unwrap();
    let e = cfe::analysis::Analysis::new(model).err().expect("refused");
    assert!(matches!(e, Error::Coupling { .. }), "{e}");
    // No boundary: all 33 strip nodes are candidates, the 27 with x ≤ 10 inside.
    let a = common::analysis(&text("rigid", "", "form = \"volume\""));
    assert_eq!(
        (a.interfaces[0].elements.len(), a.interfaces[0].unpaired),
        (27, 6)
    );
    common::solve_completed(&a);
    let Err(e) = cfe::model::Model::from_str(&text("rigid", "", ""), path, 1) else {
        panic!("a face-form interface without `boundary` is refused");
    };
    assert!(
        matches!(&e, Error::Parse { .. }) && e.to_string().contains("needs `boundary`"),
        "{e}"
    );
}
