//! Domain: the resolved problem below the numerics — parts (mesh + material),
//! supports, loads, interface parameters (with the vocabulary of an interface:
//! its [`Law`], [`Enforcement`] and [`Coupling`]) and analysis settings. The problem-file
//! schema ([`crate::model`]) translates into these types; the element routines, the
//! coupling, the assembly and the solver take only these, never the input types.

use crate::dim::{D2, D3, Dim};
use crate::error::{Error, Result};
use crate::fem::Material;
use crate::fem::loads;
pub use crate::fem::loads::FaceLoad;
use crate::mesh::{Mesh, MeshDim};
use serde::Deserialize;

/// The nonlinear scheme for contact interfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// Iterate within each increment until no pair changes state (default).
    ActiveSet,
    /// The seed's scheme: states lagged by one increment, one solve per increment.
    Implex,
}

/// The linear solver every pattern of pair states is solved by (`[analysis]
/// solver`, `--solver`): a back end behind the linear-solver seam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LinearBackend {
    /// The supernodal Cholesky factorization with low-rank updates and
    /// restricted solves (default): exact to round-off.
    #[default]
    Direct,
    /// Jacobi-preconditioned conjugate gradients on the assembled matrix,
    /// warm-started from the last solution, to a relative residual of
    /// [`crate::domain::CG_TOLERANCE`]: slow, and only for a well-conditioned
    /// coupling (a moderate penalty, or augmented-Lagrangian enforcement).
    Cg,
    /// PETSc's conjugate gradients preconditioned by smoothed-aggregation
    /// algebraic multigrid (GAMG) with the rigid-body modes as its near-null
    /// space: the `cfe-petsc` crate (the command line built with
    /// `--features petsc`); without it, a typed error saying how to build it.
    Petsc,
    /// MUMPS's sparse Cholesky through PETSc (the `cfe-petsc` crate, as
    /// [`LinearBackend::Petsc`]).
    PetscMumps,
}

impl LinearBackend {
    /// Whether this is the default back end (then summary.json does not name it).
    pub fn is_direct(&self) -> bool {
        *self == LinearBackend::Direct
    }

    /// Whether the back end lives outside this library (PETSc): a run needs one
    /// handed to it (`solve::contact::ExternalBackEnd`, with the `internals` feature).
    pub fn is_external(&self) -> bool {
        matches!(self, LinearBackend::Petsc | LinearBackend::PetscMumps)
    }

    /// The name in the problem file (`[analysis] solver`).
    pub fn name(&self) -> &'static str {
        match self {
            LinearBackend::Direct => "direct",
            LinearBackend::Cg => "cg",
            LinearBackend::Petsc => "petsc",
            LinearBackend::PetscMumps => "petsc-mumps",
        }
    }
}

/// The relative residual `‖b − K x‖ / ‖b‖` every linear solve of the `cg`
/// back end must reach; a solve that does not ends the run with an error.
pub const CG_TOLERANCE: f64 = 1e-10;

/// How a pattern's slip forces of slipping Coulomb pairs are solved and the
/// patterns searched (`[analysis] friction_solve`; docs/method.md §2.1, "The
/// search as the semi-smooth Newton").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionSolve {
    /// The default: [`FrictionSolve::Newton`] in a plane model,
    /// [`FrictionSolve::FixedPoint`] in a solid one (the 3D direction loop of
    /// the Newton step is not yet fast enough to be the default there).
    #[default]
    Auto,
    /// The Anderson-accelerated fixed point on the slip forces within each
    /// pattern, with the search's rescues (friction first, the stick-point
    /// move, the continuation in μ).
    FixedPoint,
    /// The semi-smooth Newton: every pattern — each pair open,
    /// sticking, or slipping along a direction — solved exactly (its slip
    /// forces from the slipping pairs' Schur-complement columns and one small
    /// dense solve), the next pattern the law's update of every pair at once
    /// (a slip the solve reversed sticks, a pair in tension opens); where the
    /// small system is singular or its solution drifts (no state of rest in
    /// the pattern), the pattern is not accepted; an increment it settles or
    /// finds no state in is searched again with the fixed point.
    Newton,
}

impl FrictionSolve {
    /// Whether this is the default (then summary.json does not name it).
    pub fn is_default(&self) -> bool {
        *self == FrictionSolve::Auto
    }

    /// The solve a model of `solid` (3D) parts uses: [`FrictionSolve::Auto`]
    /// resolved, the others as they are.
    pub fn resolved(self, solid: bool) -> FrictionSolve {
        match self {
            FrictionSolve::Auto if solid => FrictionSolve::FixedPoint,
            FrictionSolve::Auto => FrictionSolve::Newton,
            other => other,
        }
    }
}

/// Where the `active-set` iteration of the first increment starts (`[analysis] start`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartPattern {
    /// Every pair bonded (default): the answer the method defines.
    #[default]
    Bonded,
    /// For a model refined with `--refine K` (K ≥ 4), the final pattern of the same
    /// problem on 4× coarser meshes: far fewer iterations on large models, and the
    /// same answer wherever the law has one consistent state; where it has several
    /// (they exist for the stick law at the edge of a contact zone), it may end on
    /// another of them.
    Coarse,
}

/// Analysis settings (`[analysis]`).
#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Number of load increments (the load grows linearly to its full value). With
    /// `[[step]]` tables, the total of the steps' increments (set by the model; the
    /// file may not give it).
    pub increments: usize,
    /// `active-set` or `implex`.
    pub scheme: Scheme,
    /// Iteration limit per increment (active-set).
    pub max_iterations: usize,
    /// Where the active-set iteration starts: all pairs bonded, or the coarser
    /// model's pattern.
    pub start: StartPattern,
    /// An open pair closes (and, once converged, counts as penetrating) when
    /// `−[[u_n]]` exceeds this fraction of the largest displacement magnitude among
    /// its nodes.
    pub gap_tolerance: f64,
    /// A bonded pair opens (and, once converged, counts as pulling) when its tensile
    /// force exceeds this fraction of the load scale (the larger of the total
    /// applied force Σ‖f‖ and the largest support reaction).
    pub force_tolerance: f64,
    /// The largest law violation a run may finish with, as a fraction of the load
    /// scale: a pair settled against the law (in tension, or penetrating, as a
    /// force `c_n` × depth) beyond it stops the run with an error naming it.
    pub max_violation: f64,
    /// The largest out-of-balance force (relative to the load scale) a run accepts:
    /// above it the solve has lost accuracy (typically a penalty far above E·t) and
    /// the run stops. Results above 1e-8 are flagged in any case.
    pub max_residual: f64,
    /// Write the VTU files of every N-th increment (default 1: all); the last
    /// increment (with load steps, the last of every step) is always written.
    /// Bounds the output of runs with many increments. [`OUTPUT_LAST`] (the file's
    /// `output_every = "last"`) writes only those.
    #[serde(with = "output_every")]
    pub output_every: usize,
    /// The linear solver: `direct` (default), `cg`, `petsc` or `petsc-mumps`.
    #[serde(skip_serializing_if = "LinearBackend::is_direct")]
    pub solver: LinearBackend,
    /// PETSc options for the `petsc` and `petsc-mumps` solvers, as on a PETSc
    /// program's command line (`-ksp_rtol 1e-12 -pc_gamg_threshold 0.02`,
    /// `-options_file tuning.opts`); ignored by the other solvers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub petsc_options: Option<String>,
    /// How the slip forces of a pattern's slipping Coulomb pairs are solved:
    /// `fixed-point` (default) or `newton`.
    #[serde(skip_serializing_if = "FrictionSolve::is_default")]
    pub friction_solve: FrictionSolve,
}

/// [`Settings::output_every`] for "write only the last increment (of each step)":
/// no increment index is a multiple of it.
pub const OUTPUT_LAST: usize = usize::MAX;

/// `output_every` in the problem file: a positive integer or `"last"`
/// ([`OUTPUT_LAST`]); 0 is read here and refused by the model's checks with its
/// line.
mod output_every {
    use super::OUTPUT_LAST;
    use serde::de::{self, Visitor};
    use serde::{Deserializer, Serializer};

    pub fn serialize<S: Serializer>(n: &usize, s: S) -> Result<S::Ok, S::Error> {
        if *n == OUTPUT_LAST {
            s.serialize_str("last")
        } else {
            s.serialize_u64(*n as u64)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
        struct Every;
        impl Visitor<'_> for Every {
            type Value = usize;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a positive integer N (write every N-th increment) or \"last\"")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<usize, E> {
                usize::try_from(v).map_err(|_| {
                    E::custom(format!(
                        "output_every = {v}: expected a positive integer N (write every N-th increment) or \"last\""
                    ))
                })
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<usize, E> {
                usize::try_from(v)
                    .map_err(|_| E::custom(format!("output_every = {v} is too large")))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<usize, E> {
                match v {
                    "last" => Ok(OUTPUT_LAST),
                    other => Err(E::custom(format!(
                        "output_every = \"{other}\": expected a positive integer N (write every N-th increment) or \"last\""
                    ))),
                }
            }
        }
        d.deserialize_any(Every)
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            increments: 10,
            scheme: Scheme::ActiveSet,
            max_iterations: 200,
            start: StartPattern::Bonded,
            gap_tolerance: 1e-9,
            force_tolerance: 1e-6,
            max_violation: 0.05,
            max_residual: 1e-4,
            output_every: 1,
            solver: LinearBackend::Direct,
            petsc_options: None,
            friction_solve: FrictionSolve::Auto,
        }
    }
}

/// A part of dimension `D` (plane by default): its mesh and material.
#[derive(Debug, Clone)]
pub struct Part<D: MeshDim = D2> {
    /// Name from the problem file.
    pub name: String,
    /// The part's mesh.
    pub mesh: Mesh<D>,
    /// Material: E and ν, with the 2D idealisation and thickness of a plane part
    /// (a solid part reads E and ν only).
    pub material: Material,
}

// The interface vocabulary: what the user chose for an interface. The law's
// behaviour (transitions, forces, checks) lives in `coupling::law`.

/// Which law an interface follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
    /// Tied: D̂ = 0 always (plain non-matching mesh tying).
    Rigid,
    /// Unilateral: bonded (stick in both directions) where `g_n` ≤ tolerance, open
    /// where it separates.
    Contact,
    /// Unilateral and frictionless: a closed pair resists penetration only; its
    /// tangential force is zero (`c_s` is ignored).
    Frictionless,
    /// Unilateral with Coulomb friction (coefficient μ): stick, slip or open.
    Coulomb,
}

impl Law {
    /// Lower-case name as in the problem file (`rigid`, `contact`, `frictionless`,
    /// `coulomb`).
    pub fn as_str(self) -> &'static str {
        match self {
            Law::Rigid => "rigid",
            Law::Contact => "contact",
            Law::Frictionless => "frictionless",
            Law::Coulomb => "coulomb",
        }
    }

    /// Whether pairs of this law open in tension (every law but `rigid`).
    pub fn is_unilateral(self) -> bool {
        self != Law::Rigid
    }
}

/// How an interface enforces its law (`enforcement = …`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Enforcement {
    /// The penalties alone (default): a closed pair penetrates by about f_n / c_n.
    #[default]
    Penalty,
    /// Augmented Lagrangian: Uzawa iterations on multipliers on top of the
    /// penalties until the penetration (and the stick error) is below
    /// `penetration_tolerance`.
    Augmented,
}

impl Enforcement {
    /// Lower-case name as in the problem file (`penalty`, `augmented`).
    pub fn as_str(self) -> &'static str {
        match self {
            Enforcement::Penalty => "penalty",
            Enforcement::Augmented => "augmented",
        }
    }
}

/// The coupling formulation of an interface (`coupling` in the problem file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// One CFE per coupling node, collocated at the node (the seed's, default).
    #[default]
    Node,
    /// Segment coupling: one CFE per coupling node whose jump is averaged over its
    /// face segments, integrated exactly on the face cut at the host's vertices
    /// (`coupling::segment`); passes the patch test on non-matching meshes.
    Segment,
}

impl Coupling {
    /// Lower-case name as in the problem file (`node`, `segment`).
    pub fn as_str(self) -> &'static str {
        match self {
            Coupling::Node => "node",
            Coupling::Segment => "segment",
        }
    }
}

/// Where an interface's coupling nodes meet their host (`form` in the problem
/// file): on the host's boundary (the face form) or inside its elements (the
/// volume form, for overlapping meshes: `coupling::volume`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingForm {
    /// Each coupling node on a boundary edge (2D) or face (3D) of the host,
    /// found within the tolerance or the search distance; its element is the
    /// face's nodes (the off-face shape values vanish there). The default.
    #[default]
    Face,
    /// Each coupling node inside a host element (overlapping meshes): its
    /// element is the node and all the host element's nodes, N̄ᵢ at the node's
    /// natural coordinates in it; only the `rigid` law (a bonded tie, c·I: no
    /// face, so no normal), nodes outside the host not coupled (counted).
    Volume,
}

impl CouplingForm {
    /// Lower-case name as in the problem file (`face`, `volume`).
    pub fn as_str(self) -> &'static str {
        match self {
            CouplingForm::Face => "face",
            CouplingForm::Volume => "volume",
        }
    }
}

/// An interface as defined in the problem file, with its parts resolved.
#[derive(Debug, Clone)]
pub struct InterfaceDef {
    /// Name (default `host/nodes`).
    pub name: String,
    /// Index of the host part.
    pub host: usize,
    /// Index of the node part.
    pub node_part: usize,
    /// Coupling nodes: the nodes of the node part's named boundary.
    pub nodes: Vec<usize>,
    /// Name of that boundary.
    pub boundary: String,
    /// `rigid`, `contact`, `frictionless` or `coulomb`.
    pub law: Law,
    /// Normal penalty.
    pub c_n: f64,
    /// Tangential penalty (0 allowed, and ignored, for `frictionless`).
    pub c_s: f64,
    /// Relative geometric tolerance of the pair search.
    pub tolerance: f64,
    /// Friction coefficient μ (`coulomb` only; 0 otherwise).
    pub friction: f64,
    /// Search distance (a length): 0 pairs only nodes on the host's faces (moved
    /// onto them); d > 0 pairs each node with the nearest host boundary edge within
    /// d and keeps its initial gap.
    pub search_distance: f64,
    /// Penalty or augmented Lagrangian.
    pub enforcement: Enforcement,
    /// Augmented Lagrangian: largest penetration accepted (length).
    pub penetration_tolerance: f64,
    /// `node` (the gap collocated at each coupling node) or `segment` (the gap
    /// averaged over each coupling node's face segments).
    pub coupling: Coupling,
    /// `face` (the coupling nodes on the host's boundary) or `volume` (inside
    /// its elements: overlapping meshes).
    pub form: CouplingForm,
}

/// A Dirichlet condition on a set of nodes of one part.
#[derive(Debug, Clone)]
pub struct Support {
    /// Label, e.g. `base/bottom`.
    pub name: String,
    /// Part index.
    pub part: usize,
    /// Nodes of the part.
    pub nodes: Vec<usize>,
    /// Which components are fixed (x, y, z): a model of dimension `D` reads the
    /// first `D::N` (a plane model x and y; z is then never fixed).
    pub fix: [bool; 3],
    /// Prescribed values of the fixed components at full load (x, y, z).
    pub value: [f64; 3],
    /// The load step (index into the model's steps, 0: the first) in which the
    /// prescribed values ramp from 0 to `value`; the DOFs are held in every step.
    pub step: usize,
}

impl Support {
    /// The support `part name/boundary` holding the components `fix` (x, y, z;
    /// a model of dimension `D` reads the first `D::N`) of every node of the
    /// named boundary `boundary` of `part` (index `index` in the model) at the
    /// prescribed values `value`, applied in the first step. An unknown boundary
    /// is an [`Error::Model`] naming the part and its boundaries.
    pub fn on_boundary<D: MeshDim>(
        index: usize,
        part: &Part<D>,
        boundary: &str,
        fix: [bool; 3],
        value: [f64; 3],
    ) -> Result<Support> {
        boundary_of(part, boundary)?;
        Ok(Support {
            name: format!("{}/{boundary}", part.name),
            part: index,
            nodes: part.mesh.boundary_nodes(boundary).unwrap_or_default(),
            fix,
            value,
            step: 0,
        })
    }
}

/// An external load resolved to nodal forces at full load, in a model of
/// dimension `D` (plane by default: forces (x, y); a solid model's (x, y, z)).
#[derive(Debug, Clone)]
pub struct Load<D: Dim = D2> {
    /// Label, e.g. `plate/top`.
    pub name: String,
    /// Part index.
    pub part: usize,
    /// Nodal forces (node of the part, force).
    pub nodal: Vec<(usize, D::Vector)>,
    /// The resultant the user asked for.
    pub resultant: D::Vector,
    /// The load step (index into the model's steps, 0: the first) in which the
    /// load ramps from 0 to full; it stays at full value in the later steps.
    pub step: usize,
}

impl Load<D3> {
    /// The load `name` of a uniform traction or pressure (`load`) on the named
    /// boundary `boundary` of the solid `part` (index `index` in the model),
    /// applied in step `step`: its consistent nodal forces, integrated face by
    /// face (`loads::face_forces`); the resultant is their sum. An unknown
    /// boundary is an [`Error::Model`] naming the part and its boundaries.
    pub fn on_faces(
        name: impl Into<String>,
        index: usize,
        part: &Part<D3>,
        boundary: &str,
        load: FaceLoad,
        step: usize,
    ) -> Result<Load<D3>> {
        let faces = boundary_of(part, boundary)?;
        let (nodal, resultant) = loads::face_forces(&part.mesh.nodes, faces, load);
        Ok(Load {
            name: name.into(),
            part: index,
            nodal,
            resultant,
            step,
        })
    }
}

/// The faces (or edges) of the named boundary `name` of `part`, or an
/// [`Error::Model`] listing the boundaries it has.
fn boundary_of<'a, D: MeshDim>(part: &'a Part<D>, name: &str) -> Result<&'a [D::Face]> {
    part.mesh
        .boundaries
        .get(name)
        .map(Vec::as_slice)
        .ok_or_else(|| {
            let known: Vec<&str> = part.mesh.boundaries.keys().map(String::as_str).collect();
            Error::Model(format!(
                "part '{}' has no boundary '{name}' (its boundaries: {})",
                part.name,
                known.join(", ")
            ))
        })
}

/// A probe point (`[[probe]]`, as CalculiX's `*NODE PRINT`): a point of a part
/// whose displacement the history records at every increment, interpolated
/// inside the element that contains it. Of dimension `D` (plane by default).
#[derive(Debug, Clone, PartialEq)]
pub struct Probe<D: Dim = D2> {
    /// Name, as the history's columns (`probe:NAME.ux`) refer to it.
    pub name: String,
    /// Part index.
    pub part: usize,
    /// The part's node nearest to the point asked for.
    pub node: usize,
    /// The point asked for.
    pub at: D::Vector,
    /// The interpolation at the point: the nodes (of the part) of the element
    /// containing it with their shape functions there; the node alone (weight
    /// 1) when the point is a node or lies in no element.
    pub weights: Vec<(usize, f64)>,
    /// The element containing the point, if any (`None`: at its nearest node).
    pub element: Option<usize>,
}

impl<D: Dim> Probe<D> {
    /// The probe's displacement in `u` (`D::N` per global node), its part's
    /// nodes numbered from `offset`: Σ N_a u_a over [`Probe::weights`].
    pub fn displacement(&self, u: &[f64], offset: usize) -> D::Vector {
        let mut d = D::Vector::default();
        if let [(n, w)] = self.weights[..]
            && w == 1.0
        {
            // The node's own values, bit for bit (a -0.0 stays -0.0).
            let g = offset + n;
            for (c, v) in d.as_mut().iter_mut().enumerate() {
                *v = u[D::dof(g, c)];
            }
            return d;
        }
        for &(n, w) in &self.weights {
            let g = offset + n;
            for (c, v) in d.as_mut().iter_mut().enumerate() {
                *v += w * u[D::dof(g, c)];
            }
        }
        d
    }
}

/// A load step (`[[step]]`, as Abaqus's or CalculiX's *STEP). The loads and
/// prescribed values of the step ramp linearly from 0 to their full value over
/// its increments (or to the factor `load_factors`/`support_factors` give them);
/// those of earlier steps ramp from where the previous step left them to
/// `scale` × their full value, or to their own factor, or are held; those of
/// later steps are 0. Without `scale` and factors this is the Abaqus
/// convention: a step's loads go 0 → full and stay.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Name, as the loads and supports refer to it.
    pub name: String,
    /// Number of increments of the step (≥ 1).
    pub increments: usize,
    /// The factor (of its full value) every load and prescribed value of the
    /// earlier steps reaches at the end of this step, ramped linearly from
    /// where the previous step left it (0: unloaded, negative: reversed);
    /// `None`: held.
    pub scale: Option<f64>,
    /// Loads (index into the model's loads) with their own factor at the end of
    /// this step, instead of `scale` (for a load of this step, instead of 1).
    pub load_factors: Vec<(usize, f64)>,
    /// Supports (index into the model's supports) whose prescribed values reach
    /// this factor of `value` at the end of this step (as `load_factors`).
    pub support_factors: Vec<(usize, f64)>,
}

/// One loading of a model a step's factors refer to: a load, or a support's
/// prescribed values (indices into the model's loads and supports).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loading {
    /// A `[[load]]`.
    Load(usize),
    /// The prescribed values of a `[[support]]`.
    Support(usize),
}

impl Step {
    /// A step named `name` of `increments` increments that holds the loads of the
    /// earlier steps (no `scale`, no factors).
    pub fn new(name: impl Into<String>, increments: usize) -> Step {
        Step {
            name: name.into(),
            increments,
            scale: None,
            load_factors: Vec::new(),
            support_factors: Vec::new(),
        }
    }

    /// The factor a step gives `which` at its end, when it names it.
    fn own_factor(&self, which: Loading) -> Option<f64> {
        let (list, i) = match which {
            Loading::Load(i) => (&self.load_factors, i),
            Loading::Support(i) => (&self.support_factors, i),
        };
        list.iter().find(|(j, _)| *j == i).map(|(_, f)| *f)
    }

    /// The factor of loading `which`, applied in step `first`, at the end of each
    /// of `steps`: 0 before `first`; in `first` its own factor or 1; after it
    /// its own factor, else the step's `scale`, else the previous step's.
    pub fn targets(steps: &[Step], first: usize, which: Loading) -> Vec<f64> {
        let mut a = 0.0;
        steps
            .iter()
            .enumerate()
            .map(|(s, step)| {
                let own = step.own_factor(which);
                a = match s.cmp(&first) {
                    std::cmp::Ordering::Less => 0.0,
                    std::cmp::Ordering::Equal => own.unwrap_or(1.0),
                    std::cmp::Ordering::Greater => own.or(step.scale).unwrap_or(a),
                };
                a
            })
            .collect()
    }

    /// Every increment of `steps` in turn: its step and the step's own load
    /// factor k / n over its n increments (its progress, 1 at its end).
    pub fn labels(steps: &[Step]) -> Vec<(usize, f64)> {
        let mut out = Vec::with_capacity(steps.iter().map(|s| s.increments).sum());
        for (s, step) in steps.iter().enumerate() {
            let n = step.increments;
            out.extend((1..=n).map(|k| (s, k as f64 / n as f64)));
        }
        out
    }

    /// The factor at every increment of an amplitude whose value at the end of
    /// each of `steps` is `ends` ([`Step::targets`]): linear within each step
    /// from the previous step's end value (0 before the first), so a loading a
    /// step does not change is held exactly, and one it applies goes k / n.
    pub fn ramp(steps: &[Step], ends: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(steps.iter().map(|s| s.increments).sum());
        let mut a0 = 0.0;
        for (step, &a1) in steps.iter().zip(ends) {
            let n = step.increments;
            out.extend((1..=n).map(|k| {
                if k == n {
                    a1
                } else {
                    a0 + (k as f64 / n as f64) * (a1 - a0)
                }
            }));
            a0 = a1;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::{Loading, Step};

    /// Step-end factors and their ramps, worked by hand: a load of step 1 goes
    /// 0 → 1, is held by a plain step, set to 0 by `scale`, reversed by its own
    /// factor; a load of step 2 goes 0 → 1 there whatever `scale` says; every
    /// increment ends its step exactly on the step's factor.
    #[test]
    fn step_factors_ramp_from_the_previous_step() {
        let steps = vec![
            Step::new("a", 2),
            Step::new("b", 1),
            Step {
                scale: Some(0.0),
                ..Step::new("c", 2)
            },
            Step {
                load_factors: vec![(0, -0.3)],
                ..Step::new("d", 3)
            },
        ];
        let first = Step::targets(&steps, 0, Loading::Load(0));
        assert_eq!(first, vec![1.0, 1.0, 0.0, -0.3]);
        let ramp = Step::ramp(&steps, &first);
        let expect = [0.5, 1.0, 1.0, 0.5, 0.0, -0.1, -0.2, -0.3];
        for (r, e) in ramp.iter().zip(expect) {
            assert!((r - e).abs() < 1e-15, "{ramp:?}");
        }
        // Step ends exact: held values and every step's last increment.
        assert_eq!([ramp[1], ramp[2], ramp[4], ramp[7]], [1.0, 1.0, 0.0, -0.3]);
        let second = Step::targets(&steps, 1, Loading::Support(0));
        assert_eq!(second, vec![0.0, 1.0, 0.0, 0.0]);
        let labels = Step::labels(&steps);
        assert_eq!(labels.len(), 8);
        assert_eq!(labels[3], (2, 0.5));
        assert_eq!(labels[7], (3, 1.0));
    }
}
