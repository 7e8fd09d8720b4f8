//! What the 3D verification cases share: solid parts, supports and interfaces
//! built in code through the library API (`Model::<D3>::from_parts`), solved
//! in memory by `Analysis::<D3>`, and read back (node displacements, pair
//! forces).

use cfe::analysis::{Analysis, Results, RunStatus};
use cfe::dim::D3;
use cfe::domain::{
    Coupling, CouplingForm, Enforcement, FaceLoad, InterfaceDef, Law, Load, Part, Settings, Step,
    Support,
};
use cfe::error::Result;
use cfe::fem::{Material, PlaneKind};
use cfe::mesh::Mesh;
use cfe::model::Model;

/// A solid part `name` of `mesh`, E and ν.
pub fn part(name: &str, mesh: Mesh<D3>, e: f64, nu: f64) -> Result<Part<D3>> {
    Ok(Part {
        name: name.into(),
        material: Material::new(e, nu, PlaneKind::Strain, 1.0, name)?,
        mesh,
    })
}

/// Part `p`'s nodes of side `side` held in the components `fix` at `value`.
pub fn hold(
    parts: &[Part<D3>],
    p: usize,
    side: &str,
    fix: [bool; 3],
    value: [f64; 3],
) -> Result<Support> {
    Support::on_boundary(p, &parts[p], side, fix, value)
}

/// Part `p`'s side `side` held in component `c` only (a symmetry plane).
pub fn roller(parts: &[Part<D3>], p: usize, side: &str, c: usize) -> Result<Support> {
    let mut fix = [false; 3];
    fix[c] = true;
    let mut s = hold(parts, p, side, fix, [0.0; 3])?;
    s.name = format!("{}/{side}/{}", parts[p].name, ["x", "y", "z"][c]);
    Ok(s)
}

/// The interface of side `boundary` of part `node_part` on part `host` under
/// `law`, penalties `c` (normal and tangential), pair-search tolerance 0.05,
/// no friction and no search distance (the faces coincide; set `friction` and
/// `search_distance` on the result for others).
pub fn interface(
    parts: &[Part<D3>],
    host: usize,
    node_part: usize,
    boundary: &str,
    law: Law,
    c: f64,
) -> Result<InterfaceDef> {
    let nodes = parts[node_part]
        .mesh
        .boundary_nodes(boundary)
        .ok_or_else(|| cfe::Error::Model(format!("no boundary '{boundary}'")))?;
    Ok(InterfaceDef {
        name: format!("{}/{}", parts[host].name, parts[node_part].name),
        host,
        node_part,
        nodes,
        boundary: boundary.into(),
        law,
        c_n: c,
        c_s: c,
        tolerance: 0.05,
        friction: 0.0,
        search_distance: 0.0,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        coupling: Coupling::Node,
        form: CouplingForm::Face,
    })
}

/// A uniform load (traction or pressure) on side `side` of part `p`, applied
/// in step `step`.
pub fn face_load(
    parts: &[Part<D3>],
    p: usize,
    side: &str,
    load: FaceLoad,
    step: usize,
) -> Result<Load<D3>> {
    Load::on_faces(
        format!("{}/{side}#{step}", parts[p].name),
        p,
        &parts[p],
        side,
        load,
        step,
    )
}

/// A model's parts, interfaces and supports.
pub type Setup = (Vec<Part<D3>>, Vec<InterfaceDef>, Vec<Support>);

/// A solid model and its results.
pub struct Solved {
    /// The prepared analysis (interfaces built, nodes moved onto their faces).
    pub analysis: Analysis<D3>,
    /// The results of its last increment.
    pub results: Results<D3>,
}

impl Solved {
    /// The displacement of node `n` of part `p`.
    pub fn u(&self, p: usize, n: usize) -> [f64; 3] {
        let g = self.analysis.dofs.node(p, n);
        let u = self.results.displacements();
        [u[3 * g], u[3 * g + 1], u[3 * g + 2]]
    }

    /// Whether the run completed (law on every pair, loads balanced).
    pub fn completed(&self) -> bool {
        self.results.summary.status == RunStatus::Completed
    }

    /// The sum over the pairs of the force on the node part (x, y, z).
    pub fn pair_resultant(&self) -> [f64; 3] {
        self.results.pairs.iter().fold([0.0; 3], |a, r| {
            [
                a[0] + r.force_x.unwrap_or(0.0),
                a[1] + r.force_y.unwrap_or(0.0),
                a[2] + r.force_z.unwrap_or(0.0),
            ]
        })
    }

    /// The largest relative deviation of any element or nodal stress of every
    /// part from `want` (relative to its largest component).
    pub fn stress_error(&self, want: [f64; 6]) -> f64 {
        let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut worst = 0.0f64;
        for s in &self.results.stresses {
            for v in s.element.iter().chain(&s.nodal) {
                for c in 0..6 {
                    worst = worst.max((v[c] - want[c]).abs() / scale);
                }
            }
        }
        worst
    }
}

/// Builds the model of `parts`, `interfaces`, `supports` and `loads` in the
/// load `steps` (their increments; one step: `[n]`) and solves it.
pub fn solve(
    title: &str,
    parts: Vec<Part<D3>>,
    interfaces: Vec<InterfaceDef>,
    supports: Vec<Support>,
    loads: Vec<Load<D3>>,
    steps: &[usize],
) -> Result<Solved> {
    let settings = Settings {
        increments: steps.iter().sum(),
        ..Settings::default()
    };
    let mut model = Model::from_parts(title, parts, interfaces, supports, loads, settings)?;
    if steps.len() > 1 {
        model.steps = (steps.iter().enumerate())
            .map(|(i, &n)| Step::new(format!("step-{}", i + 1), n))
            .collect();
    }
    let analysis = Analysis::new(model)?;
    let results = analysis.solve()?;
    Ok(Solved { analysis, results })
}
