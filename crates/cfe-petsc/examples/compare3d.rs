//! Times cfe's direct solver, MUMPS through PETSc and CG + GAMG on a 3D punch
//! on a base (HEX8, contact, symmetry supports, two increments) of `cells`
//! cells along each side of the base: `cargo run --release -p cfe-petsc
//! --example compare3d -- 8 12 16`. Prints one row per solver and size.

use cfe::analysis::Analysis;
use cfe::dim::D3;
use cfe::domain::{
    Coupling, Enforcement, FaceLoad, InterfaceDef, Law, LinearBackend, Load, Part, Settings,
    Support,
};
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::{Mesh, SolidKind};
use cfe::model::Model;
use cfe_petsc::Petsc;
use std::sync::Arc;
use std::time::Instant;

fn model(n: usize) -> Analysis<D3> {
    let block = |name: &str, z: [f64; 2], cells: [usize; 3]| Part {
        name: name.into(),
        mesh: Mesh::<D3>::block([0.0, 1.0], [0.0, 1.0], z, cells, SolidKind::Hex8),
        material: Material::new(70e3, 0.3, PlaneKind::Strain, 1.0, name).unwrap(),
    };
    let base = block("base", [0.0, 1.0], [n, n, n]);
    let m = (n * 3 / 4).max(2);
    let punch = block("punch", [1.0, 1.25], [m, m, (m / 4).max(1)]);
    let hold = |index: usize, part: &Part<D3>, side: &str, c: usize| {
        let mut fix = [false; 3];
        fix[c] = true;
        Support::on_boundary(index, part, side, fix, [0.0; 3]).unwrap()
    };
    let supports = vec![
        hold(0, &base, "left", 0),
        hold(0, &base, "front", 1),
        hold(0, &base, "bottom", 2),
        hold(1, &punch, "left", 0),
        hold(1, &punch, "front", 1),
    ];
    let load = Load::on_faces("punch/top", 1, &punch, "top", FaceLoad::Pressure(10.0), 0).unwrap();
    let interface = InterfaceDef {
        name: "base/punch".into(),
        host: 0,
        node_part: 1,
        nodes: punch.mesh.boundary_nodes("bottom").unwrap(),
        boundary: "bottom".into(),
        law: Law::Contact,
        c_n: 1e4 * 70e3,
        c_s: 1e4 * 70e3,
        tolerance: 1e-3,
        friction: 0.0,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        coupling: Coupling::Node,
        form: cfe::domain::CouplingForm::Face,
    };
    let settings = Settings {
        increments: 2,
        ..Settings::default()
    };
    let model = Model::from_parts(
        "punch on base",
        vec![base, punch],
        vec![interface],
        supports,
        vec![load],
        settings,
    )
    .unwrap();
    Analysis::new(model).unwrap()
}

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("a number of cells"))
        .collect();
    println!(
        "| cells | unknowns | solver | status | wall s | preparations | iterations per solve | max |u_z| |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for n in sizes {
        for solver in [
            LinearBackend::Direct,
            LinearBackend::PetscMumps,
            LinearBackend::Petsc,
        ] {
            let mut a = model(n);
            a.model.settings.solver = solver;
            a.set_back_end(Arc::new(Petsc::default()));
            let t = Instant::now();
            let r = a.solve();
            let wall = t.elapsed().as_secs_f64();
            match r {
                Ok(r) => {
                    let its = r
                        .summary
                        .linear_solver
                        .as_ref()
                        .map(|l| l.iterations.clone())
                        .unwrap_or_default();
                    let uz = r
                        .last
                        .u
                        .iter()
                        .skip(2)
                        .step_by(3)
                        .fold(0.0f64, |m, v| m.max(v.abs()));
                    println!(
                        "| {n} | {} | {} | {:?} | {wall:.2} | {} | {its:?} | {uz:.9e} |",
                        a.dofs.n_eq,
                        solver.name(),
                        r.summary.status,
                        r.summary.factorizations,
                    );
                }
                Err(e) => println!(
                    "| {n} | {} | {} | error: {e} | {wall:.2} | | | |",
                    a.dofs.n_eq,
                    solver.name()
                ),
            }
        }
    }
    cfe_petsc::finalize().unwrap();
}
