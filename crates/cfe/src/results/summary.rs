//! The summary of a run (`summary.json`): what was solved, how, and the main
//! results of the last converged increment. Plain data; [`crate::analysis`] fills
//! it, [`Analysis::run`](crate::analysis::Analysis::run) writes it.

use super::memory::cpu_seconds;
use crate::coupling::{Enforcement, Law, PairState, ViolationKind};
use crate::domain::Scheme;
use crate::solve::nonlinear::{Iteration, IterativeSolves, SolveTimings};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::Instant;

/// Where a run stands (serialized as `running`, `completed`,
/// `completed_with_violations`, `completed_imprecise`, `failed`, `interrupted`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// Increments are being solved.
    Running,
    /// Every increment converged on a pattern where the contact law holds on every
    /// pair, in equilibrium to 1e-8 of the balance scale.
    Completed,
    /// Every increment converged, but some pairs break the law (each listed in
    /// `violations`, never empty with this status).
    CompletedWithViolations,
    /// Every increment converged and the law holds on every pair, but at some
    /// increment the out-of-balance force exceeds 1e-8 of the balance scale (see
    /// `warnings`): the solution has lost accuracy.
    CompletedImprecise,
    /// The run stopped with an error (converged increments are kept).
    Failed,
    /// The run was stopped on request (a signal) after an increment; the
    /// converged increments are kept.
    Interrupted,
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RunStatus::Running => "running",
            RunStatus::Completed => "completed",
            RunStatus::CompletedWithViolations => "completed_with_violations",
            RunStatus::CompletedImprecise => "completed_imprecise",
            RunStatus::Failed => "failed",
            RunStatus::Interrupted => "interrupted",
        })
    }
}

/// A warning about one converged increment, or (increment 0) about the model
/// as meshed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Warning {
    /// Increment (1-based); 0 for a warning about the model before any
    /// increment (a refined curved Gmsh face keeps its polygon).
    pub increment: usize,
    /// What is wrong, in one sentence.
    pub message: String,
}

/// A pair that breaks its law at a converged increment.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ViolationRecord {
    /// Increment (1-based).
    pub increment: usize,
    /// Interface name.
    pub interface: String,
    /// Coupling node (index in the node part).
    pub node: usize,
    /// Its position.
    pub x: f64,
    /// Its position.
    pub y: f64,
    /// Its z (a solid model only; absent in a plane one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// `tension` (a bonded pair pulls) or `penetration` (an open pair interpenetrates).
    pub kind: ViolationKind,
    /// The tensile force, or the penetration depth.
    pub amount: f64,
    /// The amount as a force (`c_n` × depth for a penetration).
    pub force: f64,
    /// The force relative to the increment's load scale.
    pub relative: f64,
    /// Kept against the law to settle a cycle (active-set), rather than a lagged
    /// state (`implex`).
    pub settled: bool,
}

/// What "the law holds" and "in equilibrium" mean for a run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Tolerances {
    /// A bonded pair pulling with more than this fraction of the load scale breaks the law.
    pub tension: f64,
    /// An open pair penetrating by more than this fraction of its nodes' largest
    /// displacement breaks the law.
    pub penetration: f64,
    /// The run fails when a violation exceeds this fraction of the load scale.
    pub max_violation: f64,
    /// Out-of-balance force (relative to the balance scale) above which a warning is given.
    pub residual_warn: f64,
    /// Out-of-balance force (relative to the balance scale) above which the run fails.
    pub residual_fail: f64,
}

/// Seconds spent in each phase of a run.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Timings {
    /// Reading the problem and meshing the parts.
    pub meshing: f64,
    /// Pair search and DOF numbering.
    pub pair_search: f64,
    /// Solving the problem on 4× coarser meshes for the active-set's starting pattern.
    pub coarse_start: f64,
    /// Linear-algebra phases of the solution.
    #[serde(flatten)]
    pub solve: SolveTimings,
    /// Stress recovery.
    pub stress_recovery: f64,
    /// Writing the per-increment files (VTU, PVD, CSV, JSON) on the main
    /// thread, including its waits for the background parts-VTU writers (their
    /// own time overlaps the solve and the pictures and is not counted).
    pub output: f64,
    /// Rendering the PNG pictures (wall time; the last parts VTU files are
    /// written meanwhile).
    pub pictures: f64,
    /// Wall time of the whole run.
    pub total: f64,
    /// Processor time of the whole run (user and system, every thread of the
    /// process over the same span as `total`, so a program doing other work
    /// meanwhile counts it too; Unix only): against `total` × the cores, how much
    /// of the run's work could have been spread over them.
    pub cpu: Option<f64>,
    /// Processor time of the meshing and the pair search, done before a run
    /// starts (part of `cpu`).
    #[serde(skip)]
    pub setup_cpu: Option<f64>,
}

/// When a run (or a phase) started: the wall clock and the process's processor
/// time.
#[derive(Debug, Clone, Copy)]
pub struct RunClock {
    wall: Instant,
    cpu: Option<f64>,
}

impl RunClock {
    /// Now.
    pub fn start() -> RunClock {
        RunClock {
            wall: Instant::now(),
            cpu: cpu_seconds(),
        }
    }

    /// Wall seconds since the start.
    pub fn wall(&self) -> f64 {
        self.wall.elapsed().as_secs_f64()
    }

    /// Processor seconds since the start (every thread), if known.
    pub fn cpu(&self) -> Option<f64> {
        Some(cpu_seconds()? - self.cpu?)
    }
}

impl Timings {
    /// Sets `total` and `cpu` at the end of a run started at `clock`, adding the
    /// meshing and the pair search of `setup` (done before it).
    pub fn set_totals(&mut self, setup: &Timings, clock: &RunClock) {
        self.total = clock.wall() + setup.meshing + setup.pair_search;
        self.setup_cpu = setup.setup_cpu;
        self.cpu = (|| Some(clock.cpu()? + setup.setup_cpu?))();
    }
}

/// Summary of one part.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PartSummary {
    /// Part name.
    pub name: String,
    /// Number of nodes.
    pub nodes: usize,
    /// Number of elements.
    pub elements: usize,
    /// Of which linear triangles.
    pub t3: usize,
    /// Of which bilinear quadrilaterals.
    pub q4: usize,
    /// Its TET4 elements (a solid part; absent when 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tet4: usize,
    /// Its HEX8 elements (a solid part; absent when 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub hex8: usize,
}

/// A pair whose state was fixed against the law to settle an active-set cycle.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SettledPair {
    /// Coupling node.
    pub node: usize,
    /// Its position.
    pub x: f64,
    /// Its position.
    pub y: f64,
    /// Its z (a solid model only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// `bonded` or `open`.
    pub state: PairState,
    /// Normal force on the node part (negative: tension).
    pub force_n: f64,
}

/// Summary of one interface at the last converged increment.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InterfaceSummary {
    /// Interface name.
    pub name: String,
    /// Host part.
    pub host: String,
    /// Node part.
    pub node_part: String,
    /// `rigid` or `contact`.
    pub law: Law,
    /// `node` or `segment`.
    pub coupling: crate::coupling::Coupling,
    /// Normal penalty.
    pub c_n: f64,
    /// Tangential penalty.
    pub c_s: f64,
    /// Number of coupling pairs.
    pub pairs: usize,
    /// Bonded pairs.
    pub bonded: usize,
    /// Open pairs.
    pub open: usize,
    /// Pairs whose state was fixed against the law to settle a cycle, with their forces.
    pub settled: Vec<SettledPair>,
    /// Pairs that break the law at the last converged increment.
    pub violations: usize,
    /// Largest penetration (−`[[u_n]]`) among all pairs, bonded or open.
    pub max_penetration: f64,
    /// Total normal force on the node part.
    pub total_force_n: f64,
    /// Largest distance of a coupling node from its host edge.
    pub max_projection_distance: f64,
    /// Positions of the bonded pairs with the smallest and the largest x (then y):
    /// the ends of the contact zone; `null` when no pair is bonded.
    pub bonded_extent: Option<[Vec<f64>; 2]>,
    /// Friction coefficient μ (`coulomb`; 0 otherwise).
    pub friction: f64,
    /// `penalty` or `augmented`.
    pub enforcement: Enforcement,
    /// Pairs slipping (Coulomb).
    pub slip: usize,
    /// Coupling nodes left unpaired: no host boundary edge within the search distance.
    pub unpaired: usize,
    /// Largest contact pressure, a stress: normal force on the node part /
    /// (tributary length × the node part's thickness).
    pub max_pressure: f64,
    /// Largest shear traction magnitude (a stress, as `max_pressure`).
    pub max_shear: f64,
    /// Positions of the closed (bonded or slipping) pairs with the smallest and the
    /// largest x (then y): the contact extent; `null` when no pair is closed.
    pub contact_extent: Option<[Vec<f64>; 2]>,
    /// Distance between the two ends of `contact_extent` (0 when none).
    pub contact_length: f64,
    /// Largest tangential jump of a pair relative to its host edge's length (the
    /// geometrically linear formulation assumes it small; a warning is given above
    /// 0.5).
    pub max_slip_ratio: f64,
    /// The resultant (x, y, z) of its pairs' forces on the node part, in
    /// global components (a solid model only: a plane model states its normal
    /// and tangential sums, `total_force_n` and the history's `force_s`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resultant: Option<Vec<f64>>,
    /// The contact area (a solid model only): the sum of the tributary areas
    /// (∫ N_i dA over the node part's interface faces) of its closed (bonded
    /// or slipping) pairs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_area: Option<f64>,
}

/// The maximum displacement magnitude and where it occurs.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct MaxDisplacement {
    /// |u|.
    pub value: f64,
    /// Reference position x.
    pub x: f64,
    /// Reference position y.
    pub y: f64,
    /// Its node's z (a solid model only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// Part name.
    pub part: String,
    /// Node of the part.
    pub node: usize,
}

/// The total reaction of one support.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Reaction {
    /// Support label.
    pub support: String,
    /// Reaction force x.
    pub fx: f64,
    /// Reaction force y.
    pub fy: f64,
    /// Reaction z (a solid model only; absent in a plane one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fz: Option<f64>,
}

impl Summary {
    /// Sets [`Summary::total_over_factorization`] and [`Summary::peak_over_factor`]
    /// from the timings, the peak memory and the factor's size.
    pub fn set_ratios(&mut self) {
        let fact = self.timings.solve.factorization;
        self.total_over_factorization = (fact > 0.0).then(|| self.timings.total / fact);
        self.peak_over_factor = self
            .peak_memory_bytes
            .filter(|_| self.factor_nonzeros > 0)
            .map(|b| b as f64 / (8.0 * self.factor_nonzeros as f64));
    }

    /// The status of a run whose increments all converged:
    /// `completed_with_violations` when a pair broke its law (listed in
    /// `violations`), else `completed_imprecise` when an increment has a warning
    /// (with no violation, its out-of-balance force above 1e-8 of the balance
    /// scale), else `completed`. Warnings about the model as meshed (increment 0,
    /// e.g. a refined curved Gmsh face) do not change it.
    pub fn final_status(&self) -> RunStatus {
        if !self.violations.is_empty() {
            RunStatus::CompletedWithViolations
        } else if self.warnings.iter().any(|w| w.increment > 0) {
            RunStatus::CompletedImprecise
        } else {
            RunStatus::Completed
        }
    }
}

/// A load step in the summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StepSummary {
    /// Name.
    pub name: String,
    /// Its increments.
    pub increments: usize,
}

/// A probe point in the summary: the node it records.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ProbeSummary {
    /// Name.
    pub name: String,
    /// Its part's name.
    pub part: String,
    /// The part's node nearest to `at` (index in the part's mesh).
    pub node: usize,
    /// The element containing `at` (index in the part's mesh), in which the
    /// displacement is interpolated; `None`: `at` is a node or outside the
    /// part, and the displacement is `node`'s.
    #[serde(default)]
    pub element: Option<usize>,
    /// The point asked for.
    pub at: Vec<f64>,
    /// The nearest node's position.
    pub x: f64,
    /// See `x`.
    pub y: f64,
    /// Its node's z (a solid model only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
}

/// The step of one converged increment in the summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct IncrementStep {
    /// 1-based increment number over all steps.
    pub increment: usize,
    /// The step's name.
    pub step: String,
    /// The step's load factor (0 to 1 over the step).
    pub load_factor: f64,
    /// Total time: step index − 1 + load factor (monotonic over the steps).
    pub time: f64,
}

/// The JSON summary of a run (`summary.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Summary {
    /// `running`; `completed` (the law holds on every pair at every increment and
    /// equilibrium to the stated tolerance); `completed_with_violations` (some pairs
    /// break the law, each listed in `violations`); `completed_imprecise` (the law
    /// holds, but the out-of-balance force exceeds its tolerance, see
    /// `warnings`); `failed` or `interrupted`.
    pub status: RunStatus,
    /// Error message when failed.
    pub error: Option<String>,
    /// Warnings: law violations and loss of precision, per increment; at
    /// increment 0, about the model as meshed (a refined curved Gmsh face).
    pub warnings: Vec<Warning>,
    /// Every pair that broke its law, per converged increment.
    pub violations: Vec<ViolationRecord>,
    /// The largest violation as a fraction of its increment's load scale (0 when none).
    pub max_violation: f64,
    /// The tolerances the law and equilibrium were checked to.
    pub tolerances: Tolerances,
    /// Title.
    pub title: String,
    /// Problem file.
    pub problem: PathBuf,
    /// Refinement factor of the structured meshes.
    pub refine: usize,
    /// `active-set` or `implex`.
    pub scheme: Scheme,
    /// Number of unknowns (free DOFs).
    pub unknowns: usize,
    /// Nonzeros of the lower triangle of K.
    pub matrix_nonzeros: usize,
    /// Nonzeros of the Cholesky factor.
    pub factor_nonzeros: usize,
    /// Parts.
    pub parts: Vec<PartSummary>,
    /// Interfaces at the last converged increment.
    pub interfaces: Vec<InterfaceSummary>,
    /// Increments requested.
    pub increments: usize,
    /// Increments converged.
    pub converged_increments: usize,
    /// Active-set iterations (state checks) per converged increment.
    pub iterations: Vec<usize>,
    /// How each iteration was solved, per increment: a factorization, a reuse of the
    /// current one, a low-rank update, or (method null) the scaled solution of the
    /// same states at another load factor; and how many pairs changed state.
    pub iteration_history: Vec<Vec<Iteration>>,
    /// Numeric factorizations performed.
    pub factorizations: usize,
    /// Low-rank updates performed instead of factorizations.
    pub low_rank_updates: usize,
    /// Seconds of the first numeric factorization.
    pub first_factorization_seconds: Option<f64>,
    /// Largest displacement at the last converged increment.
    pub max_displacement: MaxDisplacement,
    /// Reactions per support at the last converged increment.
    pub reactions: Vec<Reaction>,
    /// Applied load (sum of nodal forces) at the last converged increment.
    pub applied: Vec<f64>,
    /// |Σ reactions + Σ loads| / |Σ loads| (0 when no load).
    pub equilibrium_error: f64,
    /// Largest out-of-balance force at a free DOF relative to the balance scale:
    /// the largest of Σ‖f‖ over the loaded nodes, the largest support reaction,
    /// the largest pair force and 1e-4 × the largest E·t × the largest nodal |u|
    /// (the last two matter only where nothing is loaded).
    pub residual: f64,
    /// Whether the proportional-load shortcuts were on (a solved pattern scaled to
    /// another load factor, a settled pattern kept): off when an interface has an
    /// initial gap, follows the Coulomb law or uses the augmented Lagrangian —
    /// then every increment is solved.
    pub proportional_shortcut: bool,
    /// Why the proportional-load shortcuts were off (null when on): initial gaps,
    /// friction or augmented Lagrangian, or loads in more than one step.
    pub proportional_shortcut_off: Option<String>,
    /// The load steps (one, named `step-1`, without `[[step]]` tables).
    pub steps: Vec<StepSummary>,
    /// Per converged increment: its step and that step's load factor, and the
    /// total time (step index − 1 + load factor).
    pub increment_steps: Vec<IncrementStep>,
    /// The probe points (`[[probe]]`): the node each records.
    #[serde(default)]
    pub probes: Vec<ProbeSummary>,
    /// Per converged increment: step, load factor, time, reactions, contact
    /// resultants, contact length, largest pressure, probe displacements (the
    /// rows of `history.csv`).
    #[serde(default)]
    pub history: Vec<super::history::HistoryRow>,
    /// Fixed-point solves (slip forces, Uzawa steps) per converged increment, each
    /// a triangular solve with the pattern's factorization.
    pub fixed_point_iterations: Vec<usize>,
    /// Augmented Lagrangian: the largest penetration of a closed pair (or stick
    /// error) at the last converged increment (0 without augmented interfaces).
    pub augmented_penetration: f64,
    /// Notes that do not make the result break its law: pairs whose slip exceeds
    /// half their host edge (beyond the geometrically linear formulation), and
    /// increments whose Coulomb states were found by a continuation in μ.
    pub notes: Vec<Warning>,
    /// Peak resident memory of the process (bytes; Linux).
    pub peak_memory_bytes: Option<u64>,
    /// Peak memory relative to the Cholesky factor's values (8 bytes per nonzero).
    pub peak_over_factor: Option<f64>,
    /// Floating-point operations of the factorizations, solves and low-rank update
    /// columns, counted from the factor's supernodes: the solver's work, the same
    /// on every run of the same problem.
    pub solve_flops: f64,
    /// The iterative linear solver (`[analysis] solver = "cg"`): its name,
    /// preconditioner, tolerance and the iterations of every linear solve.
    /// Absent for the direct solver (the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_solver: Option<IterativeSolves>,
    /// End-to-end time relative to the time in numeric factorizations (the floor of
    /// a run: one factorization).
    pub total_over_factorization: Option<f64>,
    /// Threads the run's parallel parts could use (rayon's pool: the machine's
    /// cores unless `RAYON_NUM_THREADS` says otherwise); with `timings.cpu` and
    /// `timings.total` it tells how much of the run kept them busy.
    pub threads: usize,
    /// Seconds per phase.
    pub timings: Timings,
}

/// Whether a count is 0 (then summary.json leaves it out).
fn is_zero(n: &usize) -> bool {
    *n == 0
}
