//! The PETSc back ends against cfe's own direct solver, on the seed example
//! (examples/plate_on_base.toml) and a 3D contact model built in code: MUMPS
//! through PETSc agrees to 1e-8 in displacements and pair forces, CG + GAMG to
//! what its tolerance allows, both on the same pair states; PETSc's errors
//! are typed; GAMG's near-null space is the rigid-body motions of the model.

use cfe::analysis::{Analysis, AnalysisDim, Results, RunStatus};
use cfe::coupling::PairState;
use cfe::dim::D3;
use cfe::domain::{
    Coupling, Enforcement, FaceLoad, InterfaceDef, Law, LinearBackend, Load, Part, Settings,
    Support,
};
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::{Mesh, SolidKind};
use cfe::model::Model;
use cfe::solve::backend::Problem;
use cfe_petsc::{Kind, Petsc, PetscSolver};
use std::path::Path;
use std::sync::Arc;

/// The seed example, refined `refine` times (1: as written).
fn plate(refine: usize) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    Analysis::from_file(&path, refine).expect("the seed example reads")
}

/// A punch (2 × 2 × 2 HEX8) pressed by a pressure onto a base (3 × 3 × 2 TET4,
/// the host) through a contact interface with the seed's penalty ratio,
/// symmetry supports, two increments.
fn punch_on_base() -> Analysis<D3> {
    let block = |name: &str, z: [f64; 2], cells: [usize; 3], kind| Part {
        name: name.into(),
        mesh: Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], z, cells, kind),
        material: Material::new(70e3, 0.3, PlaneKind::Strain, 1.0, name).unwrap(),
    };
    let base = block("base", [0.0, 1.0], [3, 3, 2], SolidKind::Tet4);
    let punch = block("punch", [1.0, 1.5], [2, 2, 2], SolidKind::Hex8);
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

/// `analysis` solved with `solver` through the PETSc back end `petsc`.
fn solve_with<D: AnalysisDim>(
    mut analysis: Analysis<D>,
    solver: LinearBackend,
    petsc: Petsc,
) -> cfe::Result<Results<D>> {
    analysis.model.settings.solver = solver;
    analysis.set_back_end(Arc::new(petsc));
    analysis.solve()
}

/// The largest |a − b| relative to the largest |a|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    diff / scale
}

/// Both runs completed, on the same pair states, with displacements and pair
/// forces (normal and tangential, every pair) within `tolerance` of the
/// direct run's largest.
fn assert_agree<D: AnalysisDim>(
    direct: &Results<D>,
    other: &Results<D>,
    tolerance: f64,
    what: &str,
) {
    assert_eq!(
        direct.summary.status,
        RunStatus::Completed,
        "{what}: direct"
    );
    assert_eq!(
        other.summary.status,
        RunStatus::Completed,
        "{what}: {:?}",
        other.summary.warnings
    );
    let states = |r: &Results<D>| r.pairs.iter().map(|p| p.state).collect::<Vec<_>>();
    assert_eq!(states(direct), states(other), "{what}: pair states");
    assert!(
        states(direct).contains(&PairState::Bonded),
        "{what}: the model is in contact"
    );
    let du = relative_difference(&direct.last.u, &other.last.u);
    assert!(du <= tolerance, "{what}: displacements differ by {du:e}");
    let forces = |r: &Results<D>| {
        r.pairs
            .iter()
            .flat_map(|p| [p.force_n, p.force_s])
            .collect::<Vec<_>>()
    };
    let df = relative_difference(&forces(direct), &forces(other));
    assert!(df <= tolerance, "{what}: pair forces differ by {df:e}");
    assert!(
        other.summary.equilibrium_error < 1e-8,
        "{what}: equilibrium error {:e}",
        other.summary.equilibrium_error
    );
}

/// MUMPS through PETSc solves the seed example to the direct solver's answer
/// (1e-8 relative in displacements and pair forces, the same pair states).
#[test]
fn mumps_matches_direct_on_the_seed_example() {
    let direct = plate(1).solve().unwrap();
    let mumps = solve_with(plate(1), LinearBackend::PetscMumps, Petsc::default()).unwrap();
    assert_agree(&direct, &mumps, 1e-8, "plate, mumps");
    let record = mumps.summary.linear_solver.as_ref().expect("recorded");
    assert_eq!(record.back_end, "petsc-mumps");
}

/// CG + GAMG (rigid-body near-null space) solves the seed example, penalty
/// 1e9 against E = 2.1e5, on the direct solver's pair states with displacements
/// and pair forces within 1e-6, every solve at its tolerance (1e-8 on the
/// true residual), warm-started and reusing its preconditioner.
#[test]
fn cg_gamg_matches_direct_on_the_seed_example() {
    let direct = plate(1).solve().unwrap();
    let cg = solve_with(plate(1), LinearBackend::Petsc, Petsc::default()).unwrap();
    assert_agree(&direct, &cg, 1e-6, "plate, cg+gamg");
    let record = cg.summary.linear_solver.as_ref().expect("recorded");
    assert_eq!(
        (record.back_end.as_str(), record.preconditioner.as_str()),
        ("petsc-cg", "gamg")
    );
    assert!(!record.iterations.is_empty());
    assert!(
        record.largest_relative_residual <= record.tolerance && record.tolerance == 1e-8,
        "{record:?}"
    );
    // Fewer preconditioners built than solves: it was kept across patterns.
    assert!(
        cg.summary.factorizations < record.iterations.len(),
        "{record:?}"
    );
}

/// The same on a 3D contact model (TET4 base, HEX8 punch, block size 3, six
/// rigid-body modes): MUMPS to 1e-8, CG + GAMG to 1e-6, same pair states.
#[test]
fn petsc_matches_direct_in_3d() {
    let direct = punch_on_base().solve().unwrap();
    let mumps = solve_with(punch_on_base(), LinearBackend::PetscMumps, Petsc::default()).unwrap();
    assert_agree(&direct, &mumps, 1e-8, "punch, mumps");
    let cg = solve_with(punch_on_base(), LinearBackend::Petsc, Petsc::default()).unwrap();
    assert_agree(&direct, &cg, 1e-6, "punch, cg+gamg");
}

/// `-ksp_rtol` passed through as a PETSc option overrides the default
/// tolerance: every solve meets the looser 1e-6, the first in fewer
/// iterations than at the default 1e-8.
#[test]
fn options_pass_through() {
    let run = |options: &str| {
        let r = solve_with(plate(1), LinearBackend::Petsc, Petsc::new(options, None)).unwrap();
        r.summary.linear_solver.unwrap()
    };
    let (loose, default) = (run("-ksp_rtol 1e-6"), run(""));
    assert_eq!((loose.tolerance, default.tolerance), (1e-6, 1e-8));
    assert!(loose.largest_relative_residual <= 1e-6, "{loose:?}");
    assert!(
        loose.iterations[0] < default.iterations[0],
        "{loose:?} {default:?}"
    );
}

/// A bad option value is a typed error naming the PETSc function that read it,
/// through the analysis too (not a crash, not a printout).
#[test]
fn a_petsc_error_is_typed() {
    let a = plate(1);
    let problem = Problem {
        parts: &a.model.parts,
        interfaces: &a.interfaces,
        dofs: &a.dofs,
    };
    let bad = Petsc::new("-ksp_rtol not-a-number", None);
    match PetscSolver::new(problem, Kind::CgGamg, &bad) {
        Err(cfe_petsc::Error::Call {
            function,
            code,
            message,
        }) => {
            assert_eq!(function, "KSPSetFromOptions");
            assert_ne!(code, 0);
            assert!(message.contains("not-a-number"), "{message}");
        }
        other => panic!("expected a PETSc error, got {:?}", other.err()),
    }
    match solve_with(plate(1), LinearBackend::Petsc, bad) {
        Err(cfe::Error::LinearBackEnd { back_end, message }) => {
            assert_eq!(back_end, "petsc");
            assert!(message.contains("KSPSetFromOptions"), "{message}");
        }
        other => panic!(
            "expected a typed error, got {:?}",
            other.map(|r| r.summary.status)
        ),
    }
    let missing = Petsc::new("", Some("/nonexistent/cfe-petsc.opts".into()));
    assert!(matches!(
        solve_with(plate(1), LinearBackend::Petsc, missing),
        Err(cfe::Error::LinearBackEnd { .. })
    ));
}

/// The near-null space GAMG is given holds the rigid-body motions: with no
/// support, `K r ≈ 0` for each of them (3 in 2D, 6 in 3D), K with every pair
/// bonded.
#[test]
fn rigid_body_modes_are_in_the_null_space() {
    fn residuals<D: AnalysisDim>(mut analysis: Analysis<D>) -> Vec<f64> {
        analysis.model.supports.clear();
        let a = Analysis::new(analysis.model).unwrap();
        assert_eq!(a.dofs.n_eq, a.dofs.eq.len(), "no DOF prescribed");
        let states: Vec<Vec<PairState>> = (a.interfaces.iter())
            .map(|i| vec![PairState::Bonded; i.elements.len()])
            .collect();
        let problem = Problem {
            parts: &a.model.parts,
            interfaces: &a.interfaces,
            dofs: &a.dofs,
        };
        let mut solver = PetscSolver::new(problem, Kind::CgGamg, &Petsc::default()).unwrap();
        solver.rigid_mode_residuals(&states).unwrap()
    }
    let plane = residuals(plate(1));
    assert_eq!(plane.len(), 3);
    assert!(plane.iter().all(|&r| r < 1e-12), "{plane:?}");
    let solid = residuals(punch_on_base());
    assert_eq!(solid.len(), 6);
    assert!(solid.iter().all(|&r| r < 1e-12), "{solid:?}");
}

/// A user's GAMG options reach the solver: four Chebyshev smoothing steps a
/// level over a wider band (`-mg_levels_ksp_max_it 4
/// -mg_levels_ksp_chebyshev_esteig 0,0.05,0,1.1`) take fewer CG iterations in
/// all on the seed example than PETSc's own settings, both runs on the direct
/// solver's pair states within 1e-6.
#[test]
fn more_smoothing_from_the_users_options_takes_fewer_cg_iterations() {
    let direct = plate(1).solve().unwrap();
    let total = |options: &str| {
        let r = solve_with(plate(1), LinearBackend::Petsc, Petsc::new(options, None)).unwrap();
        assert_agree(&direct, &r, 1e-6, options);
        let record = r.summary.linear_solver.unwrap();
        record.iterations.iter().sum::<usize>()
    };
    let (smoothed, petsc_own) = (
        total("-mg_levels_ksp_max_it 4 -mg_levels_ksp_chebyshev_esteig 0,0.05,0,1.1"),
        total(""),
    );
    assert!(smoothed < petsc_own, "{smoothed} against {petsc_own}");
}
