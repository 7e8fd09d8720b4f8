//! Solid parts through the whole solve: a block of TET4 or HEX8 elements,
//! numbered, assembled, factorized and solved by the same solver as a plane
//! model, against the closed form of a uniform uniaxial stress.

use cfe::assembly::DofMap;
use cfe::dim::D3;
use cfe::domain::{Part, Settings, Support};
use cfe::fem::{ElementFamily, Material, PlaneKind, face3};
use cfe::mesh::{FaceNodes, Mesh, SolidKind};
use cfe::solve::nonlinear::Solver;

const E: f64 = 210e3;
const NU: f64 = 0.3;
const SIZE: [f64; 3] = [1.0, 2.0, 1.5];

/// A block `SIZE` of `kind` cells, its x, y and z held on the left, front and
/// bottom faces (symmetry planes), plus `extra` supports.
fn block(kind: SolidKind, cells: [usize; 3]) -> (Vec<Part<D3>>, Vec<Support>) {
    let mut mesh = Mesh::<D3>::block([0.0, SIZE[0]], [0.0, SIZE[1]], [0.0, SIZE[2]], cells, kind);
    // Distort the interior so the elements are not all alike (a patch test
    // passes on any mesh); the boundary planes stay plane.
    let inside = |x: [f64; 3]| (0..3).all(|c| x[c] > 1e-9 && x[c] < SIZE[c] - 1e-9);
    for x in mesh.nodes.iter_mut() {
        if inside(*x) {
            x[0] += 0.07 * (3.0 * x[1]).sin() * SIZE[0] / cells[0] as f64;
            x[2] += 0.05 * (2.0 * x[0]).cos() * SIZE[2] / cells[2] as f64;
        }
    }
    let material = Material::new(E, NU, PlaneKind::Strain, 1.0, "block").unwrap();
    let hold = |side: &str, c: usize| {
        let mut fix = [false; 3];
        fix[c] = true;
        Support {
            name: format!("block/{side}"),
            part: 0,
            nodes: mesh.boundary_nodes(side).unwrap(),
            fix,
            value: [0.0; 3],
            step: 0,
        }
    };
    let supports = vec![hold("left", 0), hold("front", 1), hold("bottom", 2)];
    let part = Part {
        name: "block".into(),
        mesh,
        material,
    };
    (vec![part], supports)
}

/// Solves the block's single increment for external force `f_ext`.
fn solve(parts: &[Part<D3>], supports: &[Support], f_ext: Vec<f64>) -> Vec<f64> {
    let dofs = DofMap::<D3>::numbered(&[parts[0].mesh.nodes.len()], supports);
    let settings = Settings {
        increments: 1,
        ..Settings::default()
    };
    let mut solver = Solver::new(parts, &[], &dofs, f_ext, &settings, None).unwrap();
    solver.run(|_| Ok(())).unwrap().u
}

/// Every node's displacement is the uniaxial field of σxx = `s`, and every
/// recovered stress (element and nodal) is (s, 0, 0, 0, 0, 0).
fn assert_uniaxial(part: &Part<D3>, u: &[f64], s: f64, what: &str) {
    let strain = s / E;
    for (n, x) in part.mesh.nodes.iter().enumerate() {
        let want = [strain * x[0], -NU * strain * x[1], -NU * strain * x[2]];
        for c in 0..3 {
            assert!(
                (u[3 * n + c] - want[c]).abs() < 1e-10 * strain,
                "{what}: node {n} component {c}: {} against {}",
                u[3 * n + c],
                want[c]
            );
        }
    }
    let stress = D3::recover(&part.mesh, &part.material, u);
    for v in stress.element.iter().chain(&stress.nodal) {
        let want = [s, 0.0, 0.0, 0.0, 0.0, 0.0];
        for c in 0..6 {
            assert!((v[c] - want[c]).abs() < 1e-9 * s, "{what}: stress {v:?}");
        }
    }
}

/// A prescribed displacement δ of the right face gives the uniaxial field
/// σxx = E δ / L exactly (the patch test), in TET4 and distorted HEX8 blocks.
#[test]
fn a_solid_block_stretched_by_a_prescribed_displacement_is_in_uniaxial_stress() {
    for kind in [SolidKind::Tet4, SolidKind::Hex8] {
        let (parts, mut supports) = block(kind, [3, 4, 3]);
        let delta = 1e-3;
        supports.push(Support {
            name: "block/right".into(),
            part: 0,
            nodes: parts[0].mesh.boundary_nodes("right").unwrap(),
            fix: [true, false, false],
            value: [delta, 0.0, 0.0],
            step: 0,
        });
        let f = vec![0.0; 3 * parts[0].mesh.nodes.len()];
        let u = solve(&parts, &supports, f);
        assert_uniaxial(&parts[0], &u, E * delta / SIZE[0], &format!("{kind:?}"));
    }
}

/// A uniform traction q on the right face, turned into consistent nodal forces
/// by the face routines, gives σxx = q exactly (TET4 triangles, HEX8 quads).
#[test]
fn a_solid_block_under_a_face_traction_carries_it_as_uniform_stress() {
    for kind in [SolidKind::Tet4, SolidKind::Hex8] {
        let (parts, supports) = block(kind, [2, 3, 4]);
        let mesh = &parts[0].mesh;
        let q = 50.0;
        let mut f = vec![0.0; 3 * mesh.nodes.len()];
        for face in &mesh.boundaries["right"] {
            let (nodes, forces): (&[usize], Vec<[f64; 3]>) = match &face.nodes {
                FaceNodes::Tri(n) => (
                    n,
                    face3::triangle_traction_forces(&n.map(|k| mesh.nodes[k]), [q, 0.0, 0.0])
                        .to_vec(),
                ),
                FaceNodes::Quad(n) => (
                    n,
                    face3::quad_traction_forces(&n.map(|k| mesh.nodes[k]), [q, 0.0, 0.0]).to_vec(),
                ),
            };
            for (&n, fv) in nodes.iter().zip(&forces) {
                for c in 0..3 {
                    f[3 * n + c] += fv[c];
                }
            }
        }
        let total: f64 = (0..mesh.nodes.len()).map(|n| f[3 * n]).sum();
        assert!((total - q * SIZE[1] * SIZE[2]).abs() < 1e-9 * total);
        let u = solve(&parts, &supports, f);
        assert_uniaxial(&parts[0], &u, q, &format!("{kind:?}"));
    }
}
