//! Incremental solution with contact interfaces. The load (and any prescribed
//! displacement) grows linearly over the increments; every increment solves total
//! equilibrium `K(D̂) u = λ F` (the law is secant, so a lagged state leaves no
//! accumulated error). Two schemes decide the pair states D̂:
//!
//! - `active-set`: solve, let the law update every pair (a bonded pair in tension
//!   opens, an open pair that interpenetrates closes), repeat until the law holds on
//!   every pair. Each whole pattern of states is remembered (hashed); the iteration
//!   *cycles* only when the law sends it back to a pattern it has already solved.
//!   Then it continues cautiously, flipping only the pair with the largest violation
//!   per iteration (with Coulomb friction: the worst whose flip leads to a pattern
//!   not yet solved that holds every part), which finds a consistent pattern the
//!   all-at-once update stepped over. When that leads back to a solved pattern too
//!   (with friction: when no flip is left), or `max_iterations` pass, no consistent
//!   pattern is within reach (the strict stick law has none on some meshes) and the
//!   increment is *settled*: it ends on
//!   the least-violating pattern it solved — no penetration if any such pattern was
//!   visited, then the smallest largest violation, then the earliest — and every
//!   pair that breaks the law there is reported with its amount. Nothing carries
//!   over to the next increment but the pattern it starts from.
//! - `implex` (the seed's): the states of increment n come from `[[u_n]]` of increment
//!   n − 1 (all bonded before the first); one solve per increment. Its pairs are
//!   checked against the law after every increment all the same.
//!
//! After every increment the law is checked on every pair (tension of bonded pairs
//! beyond `force_tolerance` × the load scale, penetration of open pairs beyond
//! `gap_tolerance` × the pair's displacement scale) and the out-of-balance force is
//! checked against the load: above `max_residual` (default 1e-4) the run stops
//! with [`Error::Precision`], above [`RESIDUAL_WARN`] the result is flagged.
//!
//! Linear solves go through [`ContactSystem`], which refactorizes or corrects the
//! current factorization by a low-rank update, whichever costs less. A state set
//! already solved at another load factor is not solved again: with proportional
//! loads its solution scales with λ exactly. For the same reason an increment that
//! starts from the pattern the previous one ended on needs no new solve: the law is
//! homogeneous in the load, so a consistent pattern stays consistent and a settled
//! one breaks the law by the same fraction of the load at every level (and is kept).
//! So with `active-set` the factorization is freed once an increment has converged,
//! before its output is written (a later solve, if any, refactorizes).

use super::anderson::Anderson;
use super::factor::Halt;
use super::support;
use super::system::{ContactSystem, Method, Solve, UpdatePolicy};
use crate::assembly::{self, DofMap, ElementSource, FIXED};
use crate::coupling::{
    self, CheckTolerance, Enforcement, Interface, Law, LawParams, PairHistories, PairHistory, PairState,
    PairStates, ViolationKind, history,
};
use crate::domain::{Part, Scheme, Settings};
use crate::error::{Error, Result};
use std::collections::HashSet;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Seconds spent in each phase of the solution.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct SolveTimings {
    /// Node graph, ordering, sparsity pattern and symbolic factorization (once),
    /// and the pattern built again when a freed one is needed
    /// ([`ContactSystem::keep_pattern`]).
    pub pattern_and_symbolic: f64,
    /// Assembly of K values and right-hand sides.
    pub assembly: f64,
    /// Numeric factorizations.
    pub factorization: f64,
    /// Triangular solves, including low-rank update columns.
    pub solve: f64,
    /// State updates, support checks, internal forces.
    pub contact_update: f64,
}

/// One linear solve of an increment.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Iteration {
    /// How the system was solved (or `None` when the solution of the same states
    /// at another load factor was scaled: no solve). In `summary.json` both a
    /// solve with the same factorization and a scaled solution read `"reuse"`.
    #[serde(serialize_with = "method_or_reuse")]
    pub method: Option<Method>,
    /// Pairs whose state the law changed after this solve.
    pub changed: usize,
    /// Seconds spent on this iteration (solve, internal forces, state update).
    pub seconds: f64,
}

/// Serializes a scaled solution (`None`) as `"reuse"`, like a solve that
/// reused its factorization.
fn method_or_reuse<S: serde::Serializer>(
    m: &Option<Method>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&m.unwrap_or(Method::Reuse), s)
}

/// The converged result of one increment.
#[derive(Debug, Clone)]
pub struct IncrementResult {
    /// 1-based increment number (counted over all steps).
    pub index: usize,
    /// Load factor λ of the increment's step (1 at its last increment).
    pub lambda: f64,
    /// The increment's load step (0-based index; 0 without steps).
    pub step: usize,
    /// The total time: step index + λ (0-based step, so λ without steps; grows
    /// monotonically over the steps).
    pub time: f64,
    /// Linear solves in this increment.
    pub iterations: usize,
    /// What each solve did.
    pub history: Vec<Iteration>,
    /// Displacements of all DOFs.
    pub u: Vec<f64>,
    /// Pair states used in the final solve, per interface.
    pub states: PairStates,
    /// Pairs whose state was fixed against the law to settle a cycle:
    /// (interface, pair), sorted. Empty when the law holds everywhere.
    pub settled: Vec<(usize, usize)>,
    /// Every pair that breaks its law at this increment (settled pairs, and with
    /// `implex` pairs whose lagged state is wrong), sorted by interface and pair.
    pub violations: Vec<PairViolation>,
    /// The load scale of this increment: the larger of Σ‖λ f‖ over the loaded
    /// nodes and the largest support reaction (force); the law's tolerances are
    /// relative to it.
    pub load_scale: f64,
    /// The scale the out-of-balance force is measured against
    /// ([`Solver::balance_scale`]): the load scale, or, where larger, the largest
    /// pair force (an interference fit) or [`BALANCE_FLOOR`] × the smallest E·t
    /// × the largest nodal |u| (a rigid approach under a prescribed displacement).
    pub balance_scale: f64,
    /// Internal force of all DOFs (reactions are F_int − F_ext at fixed DOFs).
    pub f_int: Vec<f64>,
    /// External force of all DOFs at this λ.
    pub f_ext: Vec<f64>,
    /// Largest out-of-balance force at a free DOF relative to the balance scale.
    pub residual: f64,
    /// The global balance: ‖Σ reactions + Σ loads‖ relative to the balance scale.
    pub balance: f64,
    /// Each pair's history after this increment (plastic slip, slip force,
    /// multipliers), per interface; all zero for the seed's laws.
    pub pair_history: PairHistories,
    /// Fixed-point solves of this increment beyond the first per pattern: slip
    /// forces (Coulomb) and Uzawa steps (augmented Lagrangian), each one triangular
    /// solve with the factorization of the pattern.
    pub fixed_point_iterations: usize,
    /// Augmented Lagrangian: the largest penetration of a closed pair (and stick
    /// error) at the end of the increment (0 without augmented interfaces).
    pub augmented_error: f64,
    /// With the proportional-load shortcuts, the linear solution these
    /// displacements are a multiple of (`None` otherwise): everything linear in
    /// `u` (strains, stresses) is that multiple of the solution's.
    pub multiple_of: Option<MultipleOf>,
    /// Whether the increment's state was found from the pattern a continuation
    /// in the friction coefficients led to: the search from the previous
    /// increment's pattern found none, only settled, or reached a pattern that
    /// leaves a part free.
    pub friction_continuation: bool,
}

/// `u = factor × u_s`, where `u_s` is the displacement vector of the run's linear
/// solution number `solution` (one per pattern solved with the proportional
/// shortcuts on).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultipleOf {
    /// The solution's number (counted over the run).
    pub solution: usize,
    /// The multiple.
    pub factor: f64,
}

impl IncrementResult {
    /// The largest violation as a force (0 when the law holds everywhere).
    pub fn max_violation_force(&self) -> f64 {
        self.violations.iter().map(|v| v.force).fold(0.0, f64::max)
    }
}

/// A pair that breaks its law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairViolation {
    /// Interface index.
    pub interface: usize,
    /// Pair index within the interface.
    pub pair: usize,
    /// Tension (a bonded pair pulls) or penetration (an open pair interpenetrates).
    pub kind: ViolationKind,
    /// The tensile force, or the penetration depth.
    pub amount: f64,
    /// The amount as a force (`c_n` × depth for a penetration).
    pub force: f64,
}

/// Out-of-balance force (relative to the balance scale) above which a result is
/// flagged as imprecise.
pub const RESIDUAL_WARN: f64 = 1e-8;

/// The balance scale's floor, as a fraction of (smallest E·t) × (largest nodal
/// |u|): the size of the terms K_ij u_j whose sums the out-of-balance force is
/// (E·t is a 2D element's stiffness scale, a force per length), so a part moved
/// without load — its internal force zero but for round-off of those terms — is
/// imprecise only when its out-of-balance force exceeds
/// [`RESIDUAL_WARN`] × 1e-4 = 1e-12 of them (about 5000 units of round-off; the
/// rigid approach of a punch gives 3e-14). Loaded models have load scales far
/// above it (the plate on a base: 1500 N against 0.27 N).
pub const BALANCE_FLOOR: f64 = 1e-4;

/// The law checked on one solution: the state the law gives each pair next and
/// every pair that breaks it.
struct LawCheck {
    next: PairStates,
    violations: Vec<PairViolation>,
    load_scale: f64,
    /// The largest force ‖(f_n, f_s)‖ of a pair of a law other than `rigid`
    /// (for the balance scale).
    pair_force: f64,
    /// Per interface, its slipping Coulomb pair nearest its cone (the least
    /// trial force over μ |f_n|), if it has one: where a stick zone moves to
    /// ([`move_stick_point`]).
    nearest_slip: Vec<Option<usize>>,
    /// Per interface, whether its closed pairs press together (Σ f_n < 0).
    pressed: Vec<bool>,
}

impl LawCheck {
    /// How bad the solution is, for choosing among the patterns of a cycle: any
    /// penetration first, then the largest violation as a force.
    fn score(&self) -> (bool, f64) {
        let penetrates = self
            .violations
            .iter()
            .any(|v| v.kind == ViolationKind::Penetration);
        let worst = self.violations.iter().map(|v| v.force).fold(0.0, f64::max);
        (penetrates, worst)
    }
}

/// A pattern solved during an increment's iteration, and how well it satisfies the law.
struct Visit {
    states: PairStates,
    score: (bool, f64),
    /// Whether its pairs' terms (slip forces, multipliers) reached their fixed
    /// point: a pattern whose terms did not is no solution, whatever its check
    /// says (its displacements drift with the last step), and is never settled on.
    converged: bool,
}

/// The solution of one state set, kept to answer the same states at another λ.
struct Solved {
    /// The solution's number over the run.
    number: usize,
    states: PairStates,
    lambda: f64,
    /// Its displacements and internal force, to be scaled by later increments:
    /// kept with proportional loads only, copied from the increment's result
    /// once it is accepted ([`Solver::keep_for_scaling`]; an increment never
    /// scales its own solve), and dropped when a trial moves on from its pattern
    /// (only a return to it could use them; a complete solve answers that), so
    /// the trials' vectors do not sit beside two more.
    values: Option<(Vec<f64>, Vec<f64>)>,
}

/// The part elements around the coupling nodes (those with a node among the
/// coupling elements'): with the coupling elements, every element whose
/// internal force reaches a coupling DOF.
struct CouplingRing {
    /// The elements, in [`assembly::PartElements`]' numbering.
    elements: Vec<usize>,
    /// The DOFs of their nodes and of the coupling elements, sorted.
    dofs: Vec<usize>,
    /// The free equations of those DOFs, sorted.
    eqs: Vec<usize>,
}

/// The incremental solver for one model.
pub struct Solver<'a> {
    parts: &'a [Part],
    interfaces: &'a [Interface],
    dofs: &'a DofMap,
    settings: &'a Settings,
    f_ext: Vec<f64>,
    system: ContactSystem<'a>,
    /// The support check's constant part (frames and fixed DOFs).
    supports: support::SupportCheck,
    /// The parts friction alone holds along their faces, checked against each
    /// increment's load before it is solved.
    friction_hold: support::FrictionHold,
    last: Option<Solved>,
    initial: Option<PairStates>,
    /// The pattern the previous active-set increment settled on, if it settled.
    settled_pattern: Option<PairStates>,
    /// Σ‖f‖ over the loaded nodes at full load.
    total_load: f64,
    /// The largest part's size (the diagonal of its bounding box): the largest
    /// displacement the load scale's floor reads (see [`FORCE_FLOOR`]).
    extent: f64,
    /// The largest prescribed displacement (any support, any step, at full
    /// value) and the largest initial gap: with `extent`, how far a state of
    /// rest may move a coupling node (see [`Solver::drifted`]).
    largest_prescribed: f64,
    /// Whether the solution scales with the load factor (no initial gap, no
    /// friction, no augmented Lagrangian): then a solved pattern is scaled, not
    /// solved again.
    proportional: bool,
    /// Each pair's history (plastic slip, slip force, multipliers).
    history: PairHistories,
    /// The history the increment starts from (the last one committed): every
    /// iteration of an increment starts from it, and a pair that was closed there
    /// closes again on its plastic slip.
    committed: PairHistories,
    /// The pairs closed where the increment starts: at the end of the last
    /// increment, or, before the first, the pairs touching (g₀ ≤ 0).
    closed_at_start: Vec<Vec<bool>>,
    /// Fixed-point solves in the current increment.
    fixed_point: usize,
    /// The load path, when not the default ramp.
    load_factors: Option<Vec<f64>>,
    /// Prescribed values of all DOFs at load factor 1, when not those of the DOF
    /// map (load steps).
    prescribed: Option<Vec<f64>>,
    /// Loads in several steps: the per-step vectors, combined into `f_ext` and
    /// `prescribed` at every increment (then the load factor is 1).
    steps: Option<LoadSteps>,
    /// Per increment, its step and that step's load factor (load steps).
    step_labels: Option<Vec<(usize, f64)>>,
    /// Largest augmented-Lagrangian error of the last fixed point.
    augmented_error: f64,
    /// Whether the last pattern's fixed point converged.
    fixed_point_converged: bool,
    /// Per interface, whether it follows the Coulomb law.
    coulomb: Vec<bool>,
    /// The factor on every interface's friction coefficient: 1 but while a
    /// continuation in μ looks for an increment's starting pattern.
    friction_factor: f64,
    /// The iterations of the last active-set search that ended in an error
    /// (the caller that searches again counts them with its own).
    failed_search: Vec<Iteration>,
    /// Every coupling element's DOFs (sorted): the DOFs a solve restricted to the
    /// interface gives.
    coupling_dofs: Vec<usize>,
    /// The part elements around the coupling nodes (what a low-rank update's
    /// refinement reads), found with the first trial or, failing one, the first
    /// complete solve with a factor kept.
    coupling_ring: Option<CouplingRing>,
    /// The displacement and right-hand-side vectors of the last trial solve,
    /// kept so the next trial reuses their memory (at 8 M unknowns they are 195 MB
    /// an iteration that would otherwise be allocated and first touched anew),
    /// and, when their contents serve it too, which trial they were.
    spare: Spare,
    /// The caller's request to stop (nonzero: e.g. a signal's number), read at
    /// every increment, active-set iteration, fixed-point step, continuation
    /// stage and before every linear solve ([`Solver::set_stop`]).
    stop: Option<&'a AtomicUsize>,
    /// Phase timings.
    pub timings: SolveTimings,
}

/// The two vectors of a trial solve, kept for the next trial ([`Solver`]'s
/// `spare`; taken, it is left empty).
#[derive(Default)]
struct Spare {
    /// Displacements: NaN at the free DOFs but the coupling ones after a trial.
    u: Vec<f64>,
    /// The right-hand side, solved in place at the coupling equations.
    x: Vec<f64>,
    /// The trial whose right-hand side `x` holds off the coupling equations,
    /// when it does not depend on the states (the next trial of the same
    /// increment and load factor reuses it).
    trial: Option<TrialRhs>,
}

/// A trial's right-hand side, independent of the states: its increment, load
/// factor and values at the coupling equations (where the solve overwrote it).
struct TrialRhs {
    inc: usize,
    lambda: f64,
    rhs: Vec<f64>,
}

/// The loads of a run in load steps (the problem file's `[[step]]`): every step's
/// external forces and prescribed values at full value, and every increment's
/// factors. The load of increment k is Σ_s λ_s(k) f_s, its prescribed values
/// Σ_s λ_s(k) p_s.
#[derive(Debug, Clone)]
pub struct LoadSteps {
    /// Per step: the external force of every DOF at full value.
    pub forces: Vec<Vec<f64>>,
    /// Per step: the prescribed value of every DOF at full value (0 at the DOFs
    /// another step prescribes, and at free DOFs).
    pub prescribed: Vec<Vec<f64>>,
    /// Per increment: its step and every step's load factor λ_s.
    pub increments: Vec<(usize, Vec<f64>)>,
}

impl LoadSteps {
    /// The steps that apply some force or prescribed value.
    pub fn loaded(&self) -> Vec<usize> {
        let nonzero = |v: &Vec<f64>| v.iter().any(|&x| x != 0.0);
        (0..self.forces.len())
            .filter(|&s| nonzero(&self.forces[s]) || nonzero(&self.prescribed[s]))
            .collect()
    }
}

/// The smallest load scale of a model without the proportional shortcuts, as a
/// fraction of (largest E·t) × (largest displacement, at most the largest part's
/// size). The cap keeps the floor a floor: a pattern whose slipping pairs cannot
/// hold a part lets it drift, under their springs, by more than any part's size,
/// and a scale grown with that drift would make the drift itself pass every
/// check relative to it (the fixed point's tolerance, the law's).
pub const FORCE_FLOOR: f64 = 1e-6;

/// The fixed point on the slip forces stops when none changes by more than this
/// fraction of the load scale (far below the law's force tolerance, so a converged
/// slip force is μ |f_n| to round-off as the law check sees it).
pub const FIXED_POINT_TOLERANCE: f64 = 1e-10;

/// Most fixed-point solves (slip forces, Uzawa steps) per pattern. With the
/// Anderson acceleration a pattern that has a fixed point reaches it in far fewer
/// (typically 5–10); one that does not is left: its unsettled slipping pairs stick.
pub const MAX_FIXED_POINT: usize = 60;

/// How many previous fixed-point steps the Anderson acceleration of the pairs'
/// right-hand-side terms mixes (`Anderson`, in `solve::anderson`).
pub const ANDERSON_DEPTH: usize = 8;

/// The factors on the friction coefficients of a continuation in μ
/// (`Solver::friction_continuation`), largest first: at 16 μ the closed
/// pairs of an ordinary model all stick, and each step after halves the excess
/// or less, down to 1.1 μ before μ itself.
pub const CONTINUATION: [f64; 7] = [16.0, 8.0, 4.0, 2.0, 1.5, 1.25, 1.1];

/// A right-hand-side term of a pair that the fixed point iterates.
#[derive(Debug, Clone, Copy)]
enum Term {
    SlipForce,
    Anchor,
    Multiplier(usize),
}

/// The load scale a fixed point's tolerance is taken from.
#[derive(Clone, Copy)]
enum FixedPointScale<'f> {
    /// From the internal force of the pattern's first solution and the current
    /// displacements, at this load factor ([`Solver::load_scale`]).
    Forces(f64, &'f [f64]),
    /// A given scale (a trial solution, which has no internal force).
    Given(f64),
}

/// Out-of-balance tolerance above which a low-rank solution is redone by factorization.
const UPDATE_RESIDUAL_LIMIT: f64 = 1e-8;

impl<'a> Solver<'a> {
    /// Builds the node graph, the nested-dissection ordering, the fixed sparsity
    /// pattern and the symbolic factorization. `stop`, if given, is read during
    /// that analysis too (a nonzero value abandons it with
    /// [`Error::Interrupted`]) and then as [`Solver::set_stop`] says.
    pub fn new(
        parts: &'a [Part],
        interfaces: &'a [Interface],
        dofs: &'a DofMap,
        f_ext: Vec<f64>,
        settings: &'a Settings,
        stop: Option<&'a AtomicUsize>,
    ) -> Result<Self> {
        if dofs.n_eq == 0 {
            return Err(Error::Model(
                "every degree of freedom is prescribed: nothing to solve".into(),
            ));
        }
        let t = Instant::now();
        let (k, chol) = super::setup::pattern_and_symbolic(parts, interfaces, dofs, stop)?;
        let timings = SolveTimings {
            pattern_and_symbolic: t.elapsed().as_secs_f64(),
            ..Default::default()
        };
        let total_load = total_force(&f_ext);
        let proportional = !interfaces.iter().any(Interface::non_proportional);
        let history: PairHistories = interfaces
            .iter()
            .map(|i| vec![PairHistory::default(); i.elements.len()])
            .collect();
        let mut solver = Solver {
            parts,
            interfaces,
            dofs,
            settings,
            f_ext,
            system: ContactSystem::new(parts, k, chol),
            supports: support::SupportCheck::new(parts, dofs),
            friction_hold: support::FrictionHold::new(parts, interfaces, dofs),
            last: None,
            initial: None,
            settled_pattern: None,
            total_load,
            extent: parts
                .iter()
                .map(|p| crate::mesh::bounding_diagonal(&[&p.mesh]))
                .fold(0.0, f64::max),
            largest_prescribed: interfaces
                .iter()
                .flat_map(|i| i.elements.iter().map(|c| c.gap0.abs()))
                .fold(largest_off(&dofs.prescribed, &[]), f64::max),
            proportional,
            committed: history.clone(),
            history,
            closed_at_start: interfaces
                .iter()
                .map(|i| i.elements.iter().map(|c| c.gap([0.0; 2]) <= 0.0).collect())
                .collect(),
            fixed_point: 0,
            load_factors: None,
            prescribed: None,
            steps: None,
            step_labels: None,
            augmented_error: 0.0,
            fixed_point_converged: true,
            coulomb: interfaces.iter().map(|i| i.law == Law::Coulomb).collect(),
            friction_factor: 1.0,
            failed_search: Vec::new(),
            coupling_dofs: crate::coupling::coupling_dofs(interfaces, dofs),
            coupling_ring: None,
            spare: Spare::default(),
            stop: None,
            timings,
        };
        if let Some(stop) = stop {
            solver.set_stop(stop);
        }
        Ok(solver)
    }

    /// Has the solver read `stop` at every increment, active-set iteration,
    /// fixed-point step and continuation stage, before every factorization or
    /// low-rank update, and before every supernode of a numeric factorization
    /// ([`ContactSystem::set_stop`]): once it is nonzero (the caller sets it, e.g. to a
    /// signal's number) the run ends there with [`Error::Interrupted`], the
    /// increment being solved abandoned. Reading it changes nothing else.
    pub fn set_stop(&mut self, stop: &'a AtomicUsize) {
        self.stop = Some(stop);
        self.system.set_stop(stop);
    }

    /// `Err(Error::Interrupted)` once the stop flag is set, while increment
    /// `inc` is being solved (the last one written is the one before).
    fn check_stop(&self, inc: usize) -> Result<()> {
        match self.stop.map_or(0, |s| s.load(Ordering::Relaxed)) {
            0 => Ok(()),
            signal => Err(Error::Interrupted {
                increment: inc.saturating_sub(1),
                signal,
            }),
        }
    }

    /// Number of unknowns (free equations).
    pub fn dofs_count(&self) -> usize {
        self.dofs.n_eq
    }

    /// Number of nonzeros in the lower triangle of K.
    pub fn matrix_nnz(&self) -> usize {
        self.system.matrix_nnz()
    }

    /// Number of nonzeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.system.factor_nnz()
    }

    /// Whether the factor is kept from one increment to the next, so the files
    /// of an increment are written beside it: every increment is solved (friction,
    /// gaps, augmented enforcement, load steps, or the `implex` scheme). With the
    /// active set under proportional loads it is freed after the first increment.
    pub fn keeps_factor_between_increments(&self) -> bool {
        !(self.settings.scheme == Scheme::ActiveSet && self.proportional)
    }

    /// Seconds of the first numeric factorization (None before it).
    pub fn first_factorization_seconds(&self) -> Option<f64> {
        self.system.first_factor_seconds
    }

    /// Whether the proportional-load shortcuts are on: a pattern solved at one load
    /// factor is scaled to another, and a settled pattern carries to the next
    /// increment without iterating. Off when an interface has an initial gap,
    /// follows the Coulomb law or is enforced by augmented Lagrangian (the solution
    /// is then not proportional to the load, or depends on the path).
    pub fn proportional(&self) -> bool {
        self.proportional
    }

    /// Applies the loads in steps: increment k carries the load Σ_s λ_s(k) f_s and
    /// the prescribed values Σ_s λ_s(k) p_s, and reports its step and that step's
    /// factor. When at most one step carries load the loading stays proportional
    /// (that step's vectors scaled by its factor, the shortcuts kept); otherwise
    /// the proportional shortcuts are off and the combined vectors are formed
    /// once per increment. Ignored when the vectors' lengths do not match the DOFs
    /// or an increment's factors do not match the steps.
    pub fn set_steps(&mut self, mut steps: LoadSteps) {
        let n = self.f_ext.len();
        let m = steps.forces.len();
        if m == 0
            || steps.prescribed.len() != m
            || steps.increments.is_empty()
            || steps.forces.iter().chain(&steps.prescribed).any(|v| v.len() != n)
            || steps
                .increments
                .iter()
                .any(|(s, f)| *s >= m || f.len() != m || f.iter().any(|x| !x.is_finite()))
        {
            return;
        }
        self.step_labels = Some(steps.increments.iter().map(|(s, f)| (*s, f[*s])).collect());
        self.largest_prescribed = steps
            .prescribed
            .iter()
            .map(|p| largest_off(p, &[]))
            .fold(self.largest_prescribed, f64::max);
        let loaded = steps.loaded();
        if loaded.len() <= 1 {
            // Proportional: one step's load, scaled by its factor.
            let s = loaded.first().copied().unwrap_or(0);
            self.load_factors = Some(steps.increments.iter().map(|(_, f)| f[s]).collect());
            self.f_ext = std::mem::take(&mut steps.forces[s]);
            self.prescribed = Some(std::mem::take(&mut steps.prescribed[s]));
            self.total_load = total_force(&self.f_ext);
        } else {
            self.proportional = false;
            self.load_factors = Some(vec![1.0; steps.increments.len()]);
            self.prescribed = Some(vec![0.0; n]);
            self.steps = Some(steps);
        }
    }

    /// With loads in several steps, sets `f_ext`, `prescribed` and the total load
    /// to those of increment `k` (0-based).
    fn combine_steps(&mut self, k: usize) {
        let Some(steps) = &self.steps else {
            return;
        };
        let factors = &steps.increments[k].1;
        let prescribed = self.prescribed.get_or_insert_with(Vec::new);
        prescribed.resize(self.f_ext.len(), 0.0);
        self.f_ext.iter_mut().for_each(|f| *f = 0.0);
        prescribed.iter_mut().for_each(|p| *p = 0.0);
        for (s, &l) in factors.iter().enumerate() {
            if l == 0.0 {
                continue;
            }
            for (f, g) in self.f_ext.iter_mut().zip(&steps.forces[s]) {
                *f += l * g;
            }
            for (p, q) in prescribed.iter_mut().zip(&steps.prescribed[s]) {
                *p += l * q;
            }
        }
        self.total_load = total_force(&self.f_ext);
    }

    /// Where increment `inc` (1-based, solved at factor `lambda`) is on the load
    /// path, for messages: its load factor, and with load steps its step.
    fn where_in_path(&self, inc: usize, lambda: f64) -> String {
        match self.step_labels.as_ref().and_then(|s| s.get(inc - 1)) {
            Some(&(step, l)) => format!("step {}, load factor {l:.4}", step + 1),
            None => format!("load factor {lambda:.4}"),
        }
    }

    /// Replaces the load path: the increments go through these load factors in
    /// turn (the default is `k / increments`, k = 1, …, increments). A path that
    /// goes back (unloading) matters for a path-dependent law (Coulomb friction);
    /// the problem file has no such key — this is for studies and tests.
    pub fn set_load_factors(&mut self, factors: Vec<f64>) {
        if !factors.is_empty() && factors.iter().all(|f| f.is_finite()) {
            self.load_factors = Some(factors);
        }
    }

    /// Flops of the factorizations, solves and update columns so far (counted from
    /// the factor's supernodes, not measured).
    pub fn solve_flops(&self) -> f64 {
        self.system.flops
    }

    /// Numeric factorizations and low-rank updates performed so far.
    pub fn solve_counts(&self) -> (usize, usize) {
        (self.system.factorizations, self.system.updates)
    }

    /// Starts the `active-set` iteration of the first increment from these states
    /// instead of all bonded (e.g. the pattern found on a coarser mesh). The converged
    /// result does not depend on it; the number of iterations does.
    pub fn set_initial_states(&mut self, states: PairStates) {
        if states.len() == self.interfaces.len()
            && states
                .iter()
                .zip(self.interfaces)
                .all(|(s, i)| s.len() == i.elements.len())
        {
            self.initial = Some(states);
        }
    }

    /// Chooses when a changed pattern is solved by a low-rank update of the current
    /// factorization rather than a new one (default: by a cost model). The answer
    /// does not depend on it beyond round-off.
    pub fn set_update_policy(&mut self, policy: UpdatePolicy) {
        self.system.policy = policy;
    }

    /// Solves the pattern `states` once at load factor `lambda` and checks the law on
    /// every pair, without iterating: the increment a run would end on if this
    /// pattern were its answer (`settled` empty, `violations` whatever the law says).
    /// For studies of the pattern space, e.g. whether any pattern near a settled one
    /// satisfies the law.
    pub fn solve_pattern(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
    ) -> Result<IncrementResult> {
        let t = Instant::now();
        let (u, f_int, method) = self.solve_states(lambda, states, 1)?;
        let check = self.check_law(states, &u, &f_int, lambda);
        let history = vec![Iteration {
            method,
            changed: count_changes(&check.next, states),
            seconds: t.elapsed().as_secs_f64(),
        }];
        Ok(self.finish(1, lambda, history, u, f_int, states.to_vec(), check, false))
    }

    /// Runs all increments; `on_increment` receives each converged increment (to
    /// write it out) before the next starts. Returns the last increment. Stops with
    /// [`Error::LawViolation`] after handing over an increment whose largest
    /// violation exceeds `max_violation` × the load scale.
    pub fn run(
        &mut self,
        mut on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<IncrementResult> {
        let factors = self.load_factors.clone().unwrap_or_else(|| {
            let n = self.settings.increments;
            (1..=n).map(|k| k as f64 / n as f64).collect()
        });
        let n_inc = factors.len();
        // With proportional loads the active set's first factorization answers
        // every increment (the factor is freed after the first): the stiffness's
        // pattern is not held beside the factor for another one.
        self.system.keep_pattern = !(self.settings.scheme == Scheme::ActiveSet && self.proportional);
        let all_bonded = self.all_bonded();
        let warm = match self.settings.scheme {
            Scheme::ActiveSet => self.initial.take(),
            Scheme::Implex => None,
        };
        let mut states = warm.clone().unwrap_or_else(|| all_bonded.clone());
        let mut last = None;
        for inc in 1..=n_inc {
            self.check_stop(inc)?;
            let lambda = factors[inc - 1];
            self.fixed_point = 0;
            self.combine_steps(inc - 1);
            // A part friction cannot hold has no state of rest: say so before
            // searching the patterns for one.
            self.friction_hold.check(
                &self.f_ext,
                lambda,
                self.settings.force_tolerance * lambda * self.total_load,
                || format!("increment {inc} ({})", self.where_in_path(inc, lambda)),
            )?;
            let mut result = match self.settings.scheme {
                Scheme::ActiveSet => {
                    let mut r = self.active_set_or_continuation(inc, lambda, &states)?;
                    if warm.is_some() && inc == 1 && !r.settled.is_empty() {
                        // A settlement depends on where the iteration started: take the
                        // one a start from all bonded gives, as without the warm start.
                        let history = r.history;
                        self.settled_pattern = None;
                        r = self.active_set_increment(inc, lambda, all_bonded.clone())?;
                        r.history.splice(0..0, history);
                        r.iterations = r.history.len();
                    }
                    states = r.states.clone();
                    r
                }
                Scheme::Implex => {
                    let t = Instant::now();
                    let (u, f_int, method) = self.solve_states(lambda, &states, inc)?;
                    if !self.proportional && !self.fixed_point_converged {
                        // No consistent slip forces in the carried states: the
                        // solution is the last fixed-point step's, possibly drifted
                        // far (see the active set's rule), and no answer.
                        return Err(Error::NoConvergence(format!(
                            "increment {inc} ({}): the slip forces found no fixed point in the contact states the implex scheme carried from the previous increment (its slipping pairs do not hold their part, or a part is pushed along its faces harder than friction holds it). The scheme does not correct the states within an increment: use scheme = \"active-set\", or more increments",
                            self.where_in_path(inc, lambda),
                        )));
                    }
                    let check = self.check_law(&states, &u, &f_int, lambda);
                    // States for the next increment from this increment's jumps.
                    let changed = count_changes(&check.next, &states);
                    let history = vec![Iteration {
                        method,
                        changed,
                        seconds: t.elapsed().as_secs_f64(),
                    }];
                    let next = check.next.clone();
                    let r = self.finish(inc, lambda, history, u, f_int, states, check, false);
                    states = next;
                    r
                }
            };
            self.commit_history(&mut result);
            if let Some(&(step, l)) = self.step_labels.as_ref().and_then(|s| s.get(inc - 1)) {
                result.step = step;
                result.lambda = l;
                result.time = step as f64 + l;
            }
            self.check_precision(&result)?;
            if (self.settings.scheme == Scheme::ActiveSet && self.proportional) || inc == n_inc {
                // Loads are proportional, so the next increment starts from a pattern
                // that holds at every load factor and is answered by scaling this
                // solution: the factor is not needed again (were it needed, the next
                // solve refactorizes). Free it before the increment is written. With
                // initial gaps, friction or augmented enforcement every increment is
                // solved, so the factor is kept until the last one (with either
                // scheme), and freed before the last increment's stresses and files.
                self.system.release();
            }
            self.keep_for_scaling(&result, lambda);
            on_increment(&result)?;
            // implex lags its states by design: only its final answer must obey the law.
            if self.settings.scheme == Scheme::ActiveSet || inc == n_inc {
                self.check_violation_limit(&result)?;
            }
            last = Some(result);
        }
        let t = &mut self.timings;
        t.factorization = self.system.factor_seconds;
        t.solve = self.system.solve_seconds;
        // A pattern built again for a later factorization is setup work too.
        t.pattern_and_symbolic += std::mem::take(&mut self.system.pattern_seconds);
        Ok(last.expect("at least one increment"))
    }

    /// One active-set increment from the pattern `start`. With Coulomb
    /// interfaces (path-dependent, so every increment is searched), an increment
    /// whose search from `start` finds no state, only settles, or reaches a
    /// pattern that leaves a part free (`Unsupported`: a pattern the search
    /// flips to, not the model's answer) is searched again from the pattern a
    /// continuation in the friction coefficient leads to
    /// ([`Solver::friction_continuation`]); its answer is taken if it obeys the
    /// law (or, when the first search found nothing, if there is one). Otherwise
    /// the first search's answer or error stands.
    fn active_set_or_continuation(
        &mut self,
        inc: usize,
        lambda: f64,
        start: &PairStates,
    ) -> Result<IncrementResult> {
        let direct = self.active_set_increment(inc, lambda, start.clone());
        let coulomb = !self.proportional && self.coulomb.contains(&true);
        if !coulomb {
            return direct;
        }
        // What the first search leaves: a settled answer (with the histories
        // its pairs end on), or its error.
        let first = match direct {
            Ok(r) if r.settled.is_empty() => return Ok(r),
            Ok(r) => Ok((r, self.history.clone(), self.augmented_error)),
            Err(e @ (Error::NoConvergence(_) | Error::Unsupported { .. })) => {
                Err((e, std::mem::take(&mut self.failed_search)))
            }
            Err(e) => return Err(e),
        };
        let Some(mut r) = self.friction_continuation(inc, lambda, start)? else {
            return match first {
                Ok((r, history, error)) => {
                    (self.history, self.augmented_error) = (history, error);
                    Ok(r)
                }
                Err((e, _)) => Err(e),
            };
        };
        match first {
            Ok((settled, history, error)) if !r.settled.is_empty() => {
                (self.history, self.augmented_error) = (history, error);
                Ok(settled)
            }
            first => {
                // The solves of the first search count too, whether it settled
                // or ended in an error.
                let solves = match first {
                    Ok((settled, ..)) => settled.history,
                    Err((_, solves)) => solves,
                };
                r.history.splice(0..0, solves);
                r.iterations = r.history.len();
                r.friction_continuation = true;
                Ok(r)
            }
        }
    }

    /// A continuation in the friction coefficient for increment `inc` at load
    /// factor `lambda`: the increment searched with every μ scaled by each of
    /// [`CONTINUATION`] in turn, each search from the pattern the previous one
    /// ended on (a search that finds nothing passes its start on), and at last
    /// with μ itself. Every search starts from the increment's committed pair
    /// histories: only the starting pattern passes from one to the next, so the
    /// answer is the increment's own, checked against its own law. With μ large
    /// every closed pair sticks (the search is the contact law's); each smaller
    /// μ then frees the pairs a little beyond their cones, a few flips from the
    /// last pattern. Returns the last search's answer with every search's solves
    /// in its history, or `None` when it found no state. A search that fails
    /// otherwise (a pattern it reaches leaves a part free, say) ends the
    /// continuation with `None` too: its error belongs to a scaled μ or to a
    /// start of the continuation's, not to the model, whose own first search
    /// gives the answer then. Only a stop request ([`Error::Interrupted`]) is
    /// an error of the continuation.
    fn friction_continuation(
        &mut self,
        inc: usize,
        lambda: f64,
        start: &PairStates,
    ) -> Result<Option<IncrementResult>> {
        // `Ok(Err(()))`: the stage failed otherwise than by finding nothing.
        let stage = |this: &mut Self, factor: f64, start: &PairStates| {
            this.check_stop(inc)?;
            this.friction_factor = factor;
            let r = this.active_set_increment(inc, lambda, start.clone());
            this.friction_factor = 1.0;
            match r {
                Ok(r) => Ok(Ok(Some(r))),
                Err(Error::NoConvergence(_)) => Ok(Ok(None)),
                Err(e @ Error::Interrupted { .. }) => Err(e),
                Err(_) => Ok(Err(())),
            }
        };
        let mut start = start.clone();
        let mut history = Vec::new();
        for &factor in &CONTINUATION {
            let Ok(found) = stage(self, factor, &start)? else {
                return Ok(None);
            };
            match found {
                Some(r) => {
                    history.extend(r.history);
                    start = r.states;
                }
                // A search that found nothing: its solves count too.
                None => history.append(&mut self.failed_search),
            }
        }
        let Ok(Some(mut r)) = stage(self, 1.0, &start)? else {
            return Ok(None);
        };
        history.append(&mut r.history);
        r.history = history;
        r.iterations = r.history.len();
        Ok(Some(r))
    }

    /// With proportional loads, keeps the values of the last complete solve for
    /// later increments to scale ([`Solved::values`]) when `result`, accepted at
    /// load factor `lambda`, is that solve's answer itself (its states, its load
    /// factor, a multiple 1 of it): copied once the increment is accepted, so
    /// the copies are not made beside the factor and the solve's vectors.
    fn keep_for_scaling(&mut self, result: &IncrementResult, lambda: f64) {
        let Some(s) = &mut self.last else {
            return;
        };
        let its_answer = result
            .multiple_of
            .as_ref()
            .is_some_and(|m| m.solution == s.number && m.factor == 1.0);
        if self.proportional
            && s.values.is_none()
            && its_answer
            && s.lambda == lambda
            && s.states == result.states
        {
            s.values = Some((result.u.clone(), result.f_int.clone()));
        }
    }

    /// The law parameters of `iface` as the search reads them: its friction
    /// coefficient times [`Solver::friction_factor`].
    fn law_params(&self, iface: &Interface) -> crate::coupling::LawParams {
        let mut p = iface.params();
        p.friction *= self.friction_factor;
        p
    }

    fn all_bonded(&self) -> PairStates {
        self.interfaces
            .iter()
            .map(|i| vec![PairState::Bonded; i.elements.len()])
            .collect()
    }

    /// One increment of the active-set scheme from the pattern `start`. A
    /// search that ends in an error leaves its iterations in
    /// [`Solver::failed_search`].
    fn active_set_increment(
        &mut self,
        inc: usize,
        lambda: f64,
        start: PairStates,
    ) -> Result<IncrementResult> {
        let mut history = Vec::new();
        let result = self.active_set_search(inc, lambda, start, &mut history);
        self.failed_search = if result.is_err() { history } else { Vec::new() };
        result
    }

    /// [`Solver::active_set_increment`], its iterations recorded in `history`
    /// as they are made (an error leaves them there).
    fn active_set_search(
        &mut self,
        inc: usize,
        lambda: f64,
        start: PairStates,
        history: &mut Vec<Iteration>,
    ) -> Result<IncrementResult> {
        // An iteration that started this increment before (a warm start that
        // settled) left its touch-downs and fixed-point iterates in the history.
        if !self.proportional {
            self.history.clone_from(&self.committed);
        }
        // Proportional loads: the law is homogeneous in the load (forces, jumps and
        // both tolerances scale with λ), so a pattern the previous increment settled
        // on breaks the law by the same fraction at this load, and the iteration from
        // it would find the same cycle: keep it (its solution is the previous one
        // scaled, no solve). A consistent pattern needs no such rule: its first,
        // scaled solution already satisfies the law.
        if self.proportional && self.settled_pattern.as_ref() == Some(&start) {
            let t = Instant::now();
            let (u, f_int, method) = self.solve_states(lambda, &start, inc)?;
            let check = self.check_law(&start, &u, &f_int, lambda);
            history.push(Iteration {
                method,
                changed: 0,
                seconds: t.elapsed().as_secs_f64(),
            });
            let history = std::mem::take(history);
            return Ok(self.finish(inc, lambda, history, u, f_int, start, check, true));
        }
        let mut seen: HashSet<PairStates> = HashSet::new();
        let mut visits: Vec<Visit> = Vec::new();
        let mut states = start;
        let mut cautious = false;
        // The last pattern whose slip forces found their fixed point, and its
        // slipping pairs nearest their cones.
        let mut last_fixed: Option<(PairStates, Vec<Option<usize>>)> = None;
        // The load scale of the increment's last complete solution: the law checks
        // of trial solutions (seed laws) use it.
        let mut scale: Option<f64> = None;
        for _ in 0..self.settings.max_iterations {
            self.check_stop(inc)?;
            let t = Instant::now();
            let trial = match scale {
                Some(sc) => {
                    let (mut u, method) = self.solve_interface(lambda, &states, inc)?;
                    if !self.proportional {
                        self.fixed_point(&states, inc, &mut u, FixedPointScale::Given(sc))?;
                    }
                    let check = self.check_law_scaled(&states, &u, sc);
                    (!check.violations.is_empty()).then_some((u, method, check))
                }
                _ => None,
            };
            // A pattern is accepted only on a complete solution (with its internal
            // force, refinement and residual check): either no trial was made, or
            // the trial found no violation.
            let (u, f_int, method, check) = match trial {
                Some((u, method, check)) => (u, None, method, check),
                None => {
                    let (u, f_int, method) = self.solve_states(lambda, &states, inc)?;
                    let check = self.check_law(&states, &u, &f_int, lambda);
                    scale = Some(check.load_scale);
                    (u, Some(f_int), method, check)
                }
            };
            let was_trial = f_int.is_none();
            // Without a fixed point the pattern has no consistent pair terms: its
            // displacements are the last step's, and may have drifted without
            // bound (a part pushed along its faces harder than friction holds it
            // slides on under the slipping pairs' springs), inflating the load
            // scale its check is relative to. It is neither accepted nor settled on.
            let converged = self.proportional || self.fixed_point_converged;
            seen.insert(states.clone());
            visits.push(Visit {
                states: states.clone(),
                score: check.score(),
                converged,
            });
            if let (true, true, Some(f_int)) = (check.violations.is_empty(), converged, f_int) {
                history.push(Iteration {
                    method,
                    changed: 0,
                    seconds: t.elapsed().as_secs_f64(),
                });
                if self.restore_closed_slips(&states) {
                    // A pair closed where the increment started, opened by the
                    // iteration and closed again, touched down on a plastic slip
                    // of the iteration's: with its own back, the pattern is solved
                    // and checked again.
                    continue;
                }
                self.settled_pattern = None;
                let history = std::mem::take(history);
                return Ok(self.finish(inc, lambda, history, u, f_int, states, check, false));
            }
            let mut check = check;
            // A face that lost its last stick pair in a pattern without a fixed
            // point moves its stick point (rather than sticking every slipping
            // pair), if that pattern is new and holds every part.
            let moved = match (&last_fixed, converged) {
                (Some((held, nearest)), false) => {
                    move_stick_point(&self.coulomb, &states, held, nearest, &check.pressed)
                        .filter(|p| {
                            !seen.contains(p)
                                && self.supports.check(self.parts, self.interfaces, p).is_ok()
                        })
                }
                _ => None,
            };
            if converged {
                last_fixed = Some((states.clone(), check.nearest_slip.clone()));
            }
            if let Some(moved) = moved {
                check.next = moved;
            } else if !converged {
                // Slipping pairs whose slip forces found no fixed point in this
                // pattern (they pull the solution along without settling) stick:
                // those the check finds off the law, or, when it finds none (its
                // load scale grown with the drift), every slipping pair.
                let off_law: Vec<(usize, usize)> = check
                    .violations
                    .iter()
                    .filter(|v| v.kind == ViolationKind::Slip)
                    .map(|v| (v.interface, v.pair))
                    .collect();
                if check.violations.is_empty() {
                    for (next, now) in check.next.iter_mut().zip(&states) {
                        for (n, &s) in next.iter_mut().zip(now) {
                            if s == PairState::Slip {
                                *n = PairState::Bonded;
                            }
                        }
                    }
                }
                for (i, k) in off_law {
                    check.next[i][k] = PairState::Bonded;
                }
            }
            // A pattern the cautious step may go to: not solved yet, and one that
            // holds every part (a flip that frees a part is no way forward).
            let wide = self.coulomb.contains(&true);
            let open = |p: &PairStates| {
                !seen.contains(p) && self.supports.check(self.parts, self.interfaces, p).is_ok()
            };
            let mut next = if cautious {
                flip_worst(&states, &check, wide, open)
            } else {
                check.next.clone()
            };
            if !cautious && seen.contains(&next) {
                // The law leads back to a pattern already solved: a cycle. Go on one
                // pair at a time, from here.
                cautious = true;
                next = flip_worst(&states, &check, wide, open);
            }
            history.push(Iteration {
                method,
                changed: count_changes(&next, &states),
                seconds: t.elapsed().as_secs_f64(),
            });
            if seen.contains(&next) {
                return self.settle(inc, lambda, &visits, history);
            }
            self.touch_down(&states, &next, &u);
            if was_trial {
                self.return_trial(u);
            }
            states = next;
        }
        if cautious {
            return self.settle(inc, lambda, &visits, history);
        }
        let open: usize = states
            .iter()
            .flatten()
            .filter(|&&s| s == PairState::Open)
            .count();
        Err(Error::NoConvergence(format!(
            "increment {inc} ({}): the contact states did not settle within {} iterations ({open} pairs open at the last one, no pattern repeated). Raise [analysis] max_iterations or use more increments",
            self.where_in_path(inc, lambda),
            self.settings.max_iterations,
        )))
    }

    /// Ends a cycling increment on the least-violating pattern it solved: one
    /// without penetration if any, then the smallest largest violation, then the
    /// earliest (the rule is deterministic). Its violating pairs are the settled ones.
    fn settle(
        &mut self,
        inc: usize,
        lambda: f64,
        visits: &[Visit],
        history: &mut Vec<Iteration>,
    ) -> Result<IncrementResult> {
        let best = visits
            .iter()
            .enumerate()
            .filter(|(_, v)| v.converged)
            .min_by(|(i, a), (j, b)| {
                a.score
                    .0
                    .cmp(&b.score.0)
                    .then(a.score.1.total_cmp(&b.score.1))
                    .then(i.cmp(j))
            })
            .map(|(_, v)| v);
        let Some(best) = best else {
            return Err(self.no_fixed_point(inc, lambda, visits));
        };
        let t = Instant::now();
        let states = best.states.clone();
        // Solved again from the terms the iteration left, or, should its fixed
        // point not be found from there (after patterns without one the terms
        // may have drifted far), once more from the increment's start.
        let mut solved = None;
        for from_start in [false, true] {
            if from_start {
                self.history.clone_from(&self.committed);
            }
            self.restore_closed_slips(&states);
            let solution = self.solve_states(lambda, &states, inc)?;
            if self.proportional || self.fixed_point_converged {
                solved = Some(solution);
                break;
            }
        }
        let Some((u, f_int, method)) = solved else {
            return Err(self.no_fixed_point(inc, lambda, visits));
        };
        let check = self.check_law(&states, &u, &f_int, lambda);
        history.push(Iteration {
            method,
            changed: 0,
            seconds: t.elapsed().as_secs_f64(),
        });
        self.settled_pattern = Some(states.clone());
        let history = std::mem::take(history);
        Ok(self.finish(inc, lambda, history, u, f_int, states, check, true))
    }

    /// The error of an increment whose pair terms found no fixed point in any of
    /// the patterns it `tried` (or not again in the one it settled on).
    fn no_fixed_point(&self, inc: usize, lambda: f64, tried: &[Visit]) -> Error {
        let fixed = tried.iter().filter(|v| v.converged).count();
        let found = if fixed == 0 {
            format!("found no fixed point in any of the {} contact-state pattern(s) tried", tried.len())
        } else {
            format!(
                "found a fixed point in only {fixed} of the {} contact-state patterns tried, none satisfying the law, and none when the least-violating of those was solved again",
                tried.len()
            )
        };
        let why = if self.friction_hold.judges_all() {
            // The inclined-plane check passed on every body friction holds.
            "the search found no state, though the loads are within what friction holds along the faces (every part friction holds passed the inclined-plane check before the increment): likely a state the active-set search does not reach on this model. Try another mesh (--refine) or other penalties (c_n, c_s)"
        } else {
            "no state holds: a part is pushed along its faces harder than friction holds it (a tangential load beyond μ × the normal load, nothing else holding the part along the face), or the search missed the state. Hold the part, raise the friction coefficient, or reduce the tangential load"
        };
        Error::NoConvergence(format!(
            "increment {inc} ({}): the slip forces {found}, so {why}",
            self.where_in_path(inc, lambda),
        ))
    }

    /// Checks the law on every pair of the solution `u` of `states`: the state the
    /// law gives each pair next, and every violation with its amount.
    fn check_law(
        &self,
        states: &[Vec<PairState>],
        u: &[f64],
        f_int: &[f64],
        lambda: f64,
    ) -> LawCheck {
        self.check_law_scaled(states, u, self.load_scale(lambda, f_int, u))
    }

    /// [`Solver::check_law`] with a given load scale (reads `u` at the coupling
    /// elements' DOFs only).
    fn check_law_scaled(&self, states: &[Vec<PairState>], u: &[f64], load_scale: f64) -> LawCheck {
        let laws: Vec<LawParams> = self.interfaces.iter().map(|i| self.law_params(i)).collect();
        let history = (!self.proportional).then_some(self.history.as_slice());
        let tol = CheckTolerance {
            force: self.settings.force_tolerance * load_scale,
            gap: self.settings.gap_tolerance,
        };
        let v = coupling::check_law(self.interfaces, &laws, self.dofs, states, history, u, tol);
        LawCheck {
            next: v.next,
            violations: v
                .violations
                .into_iter()
                .map(|(interface, pair, v)| PairViolation {
                    interface,
                    pair,
                    kind: v.kind,
                    amount: v.amount,
                    force: v.force,
                })
                .collect(),
            load_scale,
            pair_force: v.pair_force,
            nearest_slip: v.nearest_slip,
            pressed: v.pressed,
        }
    }

    /// The load scale at load factor `lambda`: the larger of Σ‖λ f‖ over the loaded
    /// nodes and the largest support reaction of the solution with internal force
    /// `f_int` (so a problem driven by prescribed displacements has a scale too).
    ///
    /// Without the proportional shortcuts (initial gaps, friction, augmented), the
    /// scale is at least [`FORCE_FLOOR`] × the largest E·t × the largest
    /// displacement `u`: a part that moves without load (a gap closing under a
    /// prescribed displacement) has no force to measure round-off against.
    fn load_scale(&self, lambda: f64, f_int: &[f64], u: &[f64]) -> f64 {
        if self.proportional {
            return self.load_scale_of_forces(lambda, f_int);
        }
        self.load_scale_with(lambda, f_int, largest_off(u, &[]))
    }

    /// [`Solver::load_scale`] without the proportional shortcuts, given the
    /// largest nodal displacement `umax`.
    fn load_scale_with(&self, lambda: f64, f_int: &[f64], umax: f64) -> f64 {
        let et = self
            .parts
            .iter()
            .map(|p| p.material.young * p.material.thickness)
            .fold(0.0, f64::max);
        self.load_scale_of_forces(lambda, f_int)
            .max(FORCE_FLOOR * et * umax.min(self.extent))
    }

    fn load_scale_of_forces(&self, lambda: f64, f_int: &[f64]) -> f64 {
        let largest = self
            .dofs
            .reactions(self.dofs.support_count(), f_int, &self.f_ext, lambda)
            .iter()
            .map(|r| r[0].hypot(r[1]))
            .fold(0.0, f64::max);
        (lambda * self.total_load).max(largest)
    }

    /// The scale the out-of-balance force of a solution is measured against: the
    /// largest of the load scale `load_scale`, the largest pair force
    /// `pair_force` (an interference fit with no load carries its pairs' forces
    /// and nothing else) and [`BALANCE_FLOOR`] × the **smallest** E·t × the
    /// largest nodal displacement of `u` (a part moved by a prescribed
    /// displacement, or into contact, with no force anywhere). The softest part's
    /// E·t keeps the floor below the loads of a loaded model even where another
    /// part is far stiffer (a cantilever whose node part is 1e4 times stiffer than
    /// its host is judged against its load, as before the floor existed).
    fn balance_scale(&self, load_scale: f64, pair_force: f64, u: &[f64]) -> f64 {
        let et = self
            .parts
            .iter()
            .map(|p| p.material.young * p.material.thickness)
            .fold(f64::INFINITY, f64::min);
        let floor = if et.is_finite() {
            BALANCE_FLOOR * et * largest_off(u, &[])
        } else {
            0.0
        };
        load_scale.max(pair_force).max(floor)
    }

    /// Stops the run when the out-of-balance force has grown beyond what round-off
    /// explains: the solve lost its accuracy.
    fn check_precision(&self, r: &IncrementResult) -> Result<()> {
        let worst = r.residual.max(r.balance);
        if worst <= self.settings.max_residual {
            return Ok(());
        }
        Err(Error::Precision {
            increment: r.index,
            residual: worst,
            message: format!(
                "increment {}: the out-of-balance force is {:.1e} of the balance scale {:.4e} (the largest at a free DOF, or the reactions against the applied load; the scale is the largest of the load (or the support reactions), the pair forces and 1e-4 × the softest part's E·t × the largest displacement; limit [analysis] max_residual = {:.0e}), so the solution cannot be trusted. {}",
                r.index,
                worst,
                r.balance_scale,
                self.settings.max_residual,
                penalty_advice(self.parts, self.interfaces)
            ),
        })
    }

    /// Stops the run when a violation exceeds `max_violation` × the load scale.
    fn check_violation_limit(&self, r: &IncrementResult) -> Result<()> {
        let limit = self.settings.max_violation * r.load_scale;
        let over: Vec<&PairViolation> = r.violations.iter().filter(|v| v.force > limit).collect();
        if over.is_empty() {
            return Ok(());
        }
        let list: Vec<String> = over
            .iter()
            .take(10)
            .map(|v| {
                let iface = &self.interfaces[v.interface];
                let c = &iface.elements[v.pair];
                let what = match v.kind {
                    ViolationKind::Tension => format!("bonded in tension {:.4e}", v.amount),
                    ViolationKind::Penetration => {
                        format!(
                            "open, penetrating {:.4e} (as a force {:.4e})",
                            v.amount, v.force
                        )
                    }
                    ViolationKind::Friction => {
                        format!("sticking beyond μ|f_n| by {:.4e}", v.amount)
                    }
                    ViolationKind::Slip => {
                        format!("slipping off μ|f_n| by {:.4e}", v.amount)
                    }
                };
                format!(
                    "interface '{}' node {} at ({}, {}): {what}",
                    iface.name, c.node, c.position[0], c.position[1]
                )
            })
            .collect();
        let pairs = over
            .iter()
            .map(|v| {
                let iface = &self.interfaces[v.interface];
                (iface.name.clone(), iface.elements[v.pair].node)
            })
            .collect();
        Err(Error::LawViolation {
            increment: r.index,
            pairs,
            message: format!(
                "increment {} (load factor {:.4}): no state satisfies the contact law, and {} pair(s) break it by more than [analysis] max_violation = {} of the load scale {:.4e}: {}{}. Refine the node part's face, or raise max_violation to accept",
                r.index,
                r.lambda,
                over.len(),
                self.settings.max_violation,
                r.load_scale,
                list.join("; "),
                if over.len() > 10 { "; …" } else { "" }
            ),
        })
    }

    /// Displacements (all DOFs), internal force and solve method for the given
    /// states at load factor `lambda`, with the pairs' right-hand-side terms at
    /// their fixed point: the slip forces of slipping Coulomb pairs
    /// (`μ |f_n|` along the trial force, from the solution) and, with augmented
    /// Lagrangian enforcement, the multipliers (Uzawa: `m ← f`, until the largest
    /// penetration of a closed pair and stick error is below the interface's
    /// `penetration_tolerance`). Each further solve reuses the factorization of the
    /// pattern (the values of K do not change). One solve for the seed's laws.
    fn solve_states(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Vec<f64>, Option<Method>)> {
        let first = self.solve_once(lambda, states, inc)?;
        if self.proportional {
            return Ok(first);
        }
        let (mut u, f_first, method) = first;
        let u_first = u.clone();
        let Some(mut total) =
            self.fixed_point(states, inc, &mut u, FixedPointScale::Forces(lambda, &f_first))?
        else {
            return Ok((u, f_first, method));
        };
        // The summed change is on the coupling equations only.
        self.check_stop(inc)?;
        self.system
            .solve_pair_forces(self.interfaces, self.dofs, states, &mut total)
            .map_err(|h| self.halt_error(h, inc))?;
        let mut u = u_first;
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                u[d] += total[e];
            }
        }
        let t = Instant::now();
        let f_int = self.internal_force(states, &u);
        self.timings.contact_update += t.elapsed().as_secs_f64();
        let residual = self.residual(lambda, &f_int, self.load_scale(lambda, &f_int, &u));
        if residual > UPDATE_RESIDUAL_LIMIT {
            // The corrections lost accuracy: solve the converged terms afresh.
            let (u, f_int, _) = self.solve_once(lambda, states, inc)?;
            return Ok((u, f_int, method));
        }
        Ok((u, f_int, method))
    }

    /// Iterates the pairs' right-hand-side terms of `states` to their fixed point
    /// from the solution `u` (valid at the coupling elements' DOFs at least),
    /// Anderson-accelerated. K is the pattern's: only the pairs' constant terms
    /// change, so each step moves `u` by K⁻¹ of their change, a right-hand side on
    /// the pairs' DOFs solved on the interface's tree paths (`u` moves at the
    /// coupling DOFs only, all the pairs' forces read). A step's work is the
    /// pairs' and that solve's: the change, its sum and the load scale's largest
    /// displacement are kept on the coupling DOFs (the rest of `u` does not move
    /// unless a refactorization solves in full). Returns the summed force change
    /// (free equations) for one complete solve, or `None` when the terms were
    /// already at their fixed point.
    fn fixed_point(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        u: &mut [f64],
        scale: FixedPointScale<'_>,
    ) -> Result<Option<Vec<f64>>> {
        let mut anderson = Anderson::new(ANDERSON_DEPTH);
        self.fixed_point_converged = false;
        // The summed change at the coupling DOFs (in their order).
        let mut total: Option<Vec<f64>> = None;
        // A step's right-hand side: zero off the coupling equations.
        let mut du: Vec<f64> = Vec::new();
        // The displacements at zero, at which the pairs' constant terms are read.
        let zero = vec![0.0; u.len()];
        // The largest nodal displacement off the coupling nodes (the load scale's
        // floor reads the largest of all): fixed until a step solves in full.
        let coupling_nodes: Vec<usize> = {
            let mut nodes: Vec<usize> = self.coupling_dofs.iter().map(|&d| d / 2).collect();
            nodes.dedup();
            nodes
        };
        let rest_max = |u: &[f64]| largest_off(u, &coupling_nodes);
        let mut u_rest = match scale {
            FixedPointScale::Forces(..) => rest_max(u),
            FixedPointScale::Given(_) => 0.0,
        };
        for _ in 0..MAX_FIXED_POINT {
            self.check_stop(inc)?;
            // The largest displacement of a coupling node.
            let moved = coupling_nodes
                .iter()
                .map(|&n| u[2 * n].hypot(u[2 * n + 1]))
                .fold(0.0, f64::max);
            let load = match scale {
                FixedPointScale::Forces(lambda, f) => {
                    self.load_scale_with(lambda, f, moved.max(u_rest))
                }
                FixedPointScale::Given(s) => s,
            };
            let before = self.history.clone();
            if self.update_right_hand_side(states, u, FIXED_POINT_TOLERANCE * load, &mut anderson) {
                self.fixed_point_converged = !self.drifted(moved);
                break;
            }
            self.fixed_point += 1;
            let t = Instant::now();
            let change = self.pair_term_change(states, &before, &zero);
            let total = total.get_or_insert_with(|| vec![0.0; self.coupling_dofs.len()]);
            if du.is_empty() {
                du = vec![0.0; self.dofs.n_eq];
            }
            for ((&d, c), sum) in self.coupling_dofs.iter().zip(&change).zip(total.iter_mut()) {
                let e = self.dofs.eq[d];
                if e != FIXED {
                    du[e] = -c;
                    *sum -= c;
                }
            }
            self.timings.contact_update += t.elapsed().as_secs_f64();
            let (_, complete) = self
                .system
                .solve_interface(self.interfaces, self.dofs, states, &mut du, true)
                .map_err(|h| self.halt_error(h, inc))?;
            if complete {
                for (d, &e) in self.dofs.eq.iter().enumerate() {
                    if e != FIXED {
                        u[d] += du[e];
                    }
                }
                // Solved in full: zero off the coupling equations again.
                du.fill(0.0);
                if let FixedPointScale::Forces(..) = scale {
                    u_rest = rest_max(u);
                }
            } else {
                for &d in &self.coupling_dofs {
                    let e = self.dofs.eq[d];
                    if e != FIXED {
                        u[d] += du[e];
                    }
                }
            }
        }
        Ok(total.map(|sum| {
            let mut full = vec![0.0; self.dofs.n_eq];
            for (&d, &v) in self.coupling_dofs.iter().zip(&sum) {
                let e = self.dofs.eq[d];
                if e != FIXED {
                    full[e] = v;
                }
            }
            full
        }))
    }

    /// Whether a fixed point whose coupling nodes moved by at most `moved` has
    /// one moved further than a state of rest can move it: the largest part's
    /// size beyond the largest prescribed displacement (or initial gap, should
    /// one be larger). Within a geometrically linear model only a rigid drift
    /// goes that far — a part held along its faces by slipping pairs alone,
    /// whose slip forces balance at any position along them, carried off by the
    /// fixed point's steps under their springs (the seed's plate with a block
    /// bonded on it, pushed at Q = 0.83 μP, drifted 290 m in a pattern with
    /// every closed pair slipping, and the run stopped with a loss of
    /// precision). Such a fixed point is not taken as converged: its pattern is
    /// neither accepted nor settled on, and its slipping pairs stick in the next
    /// (where one stick pair holds the part, 0.02 mm from where it started).
    fn drifted(&self, moved: f64) -> bool {
        moved > self.extent + self.largest_prescribed
    }

    /// The change of the pairs' internal force at zero displacement `zero` (their
    /// constant terms: slip forces, spring anchors, multipliers) from the
    /// histories `before` to the current ones, at the coupling DOFs (in their
    /// order; the pairs act nowhere else). Each side is summed element by element
    /// as the assembled force would be.
    fn pair_term_change(
        &self,
        states: &[Vec<PairState>],
        before: &PairHistories,
        zero: &[f64],
    ) -> Vec<f64> {
        let force = |h: &[Vec<PairHistory>]| {
            let pairs = assembly::CouplingElements::new(self.interfaces, Some(states), self.dofs)
                .with_history(Some(h));
            assembly::internal_force_at(&pairs, zero, &self.coupling_dofs)
        };
        let (now, was) = (force(&self.history), force(before));
        now.iter().zip(&was).map(|(a, b)| a - b).collect()
    }

    /// One fixed-point step on the pairs' right-hand-side terms for the solution
    /// `u` of `states`: sets every closed Coulomb pair's slip force to
    /// `μ |f_n|` along its trial force and its spring anchor to its tangential
    /// jump, the multipliers of augmented interfaces to the pairs' forces (zero
    /// when open), and returns whether nothing changed by more than the tolerances
    /// (force `tol`; each interface's `penetration_tolerance`) — then the history
    /// is left as it was, consistent with `u`. Otherwise the terms that act on the
    /// solution go through `anderson` (the plain step mixed with the previous ones).
    fn update_right_hand_side(
        &mut self,
        states: &[Vec<PairState>],
        u: &[f64],
        tol: f64,
        anderson: &mut Anderson,
    ) -> bool {
        let mut next = self.history.clone();
        let laws: Vec<LawParams> = self.interfaces.iter().map(|i| self.law_params(i)).collect();
        let (converged, augmented_error) =
            history::step_terms(self.interfaces, &laws, self.dofs, states, u, &mut next, tol);
        self.augmented_error = augmented_error;
        if converged {
            // Keep the history the solution was computed with; a stick pair's slip
            // force and anchor (unused while it sticks) are its start should it slip.
            for ((h, n), st) in self.history.iter_mut().zip(&next).zip(states) {
                for ((h, n), s) in h.iter_mut().zip(n).zip(st) {
                    if *s == PairState::Bonded {
                        h.slip_force = n.slip_force;
                        h.anchor = n.anchor;
                    }
                }
            }
        } else {
            let x = self.active_terms(states, &self.history);
            let g = self.active_terms(states, &next);
            let mixed = anderson.step(&x, &g);
            self.set_active_terms(states, &mut next, &mixed);
            self.history = next;
        }
        converged
    }

    /// The right-hand-side terms of `history` that act on the solution of
    /// `states`, each as a force: a slipping Coulomb pair's slip force and
    /// `c_slip` × its anchor; an augmented closed pair's normal multiplier, and
    /// its tangential one when it sticks.
    fn active_terms(&self, states: &[Vec<PairState>], history: &PairHistories) -> Vec<f64> {
        let mut x = Vec::new();
        self.visit_active_terms(states, |i, k, field, c_slip| {
            let h = &history[i][k];
            x.push(match field {
                Term::SlipForce => h.slip_force,
                Term::Anchor => c_slip * h.anchor,
                Term::Multiplier(j) => h.multiplier[j],
            });
        });
        x
    }

    /// Writes `x` (as [`Self::active_terms`] orders it) into `history`.
    fn set_active_terms(&self, states: &[Vec<PairState>], history: &mut PairHistories, x: &[f64]) {
        let mut it = x.iter();
        self.visit_active_terms(states, |i, k, field, c_slip| {
            let v = *it.next().expect("as many terms as active_terms gives");
            let h = &mut history[i][k];
            match field {
                Term::SlipForce => h.slip_force = v,
                Term::Anchor => h.anchor = v / c_slip,
                Term::Multiplier(j) => h.multiplier[j] = v,
            }
        });
    }

    /// Calls `f(interface, pair, term, c_slip)` for each right-hand-side term that
    /// acts on the solution of `states`, in a fixed order.
    fn visit_active_terms(
        &self,
        states: &[Vec<PairState>],
        mut f: impl FnMut(usize, usize, Term, f64),
    ) {
        for (i, iface) in self.interfaces.iter().enumerate() {
            let base = iface.params();
            let augmented = iface.enforcement == Enforcement::Augmented;
            for (k, c) in iface.elements.iter().enumerate() {
                let state = states[i][k];
                let law = c.params(&base);
                if state == PairState::Slip && law.c_slip > 0.0 {
                    f(i, k, Term::SlipForce, law.c_slip);
                    f(i, k, Term::Anchor, law.c_slip);
                }
                if augmented && state.is_closed() {
                    f(i, k, Term::Multiplier(0), law.c_slip);
                    if state == PairState::Bonded && law.penalties(state)[1] > 0.0 {
                        f(i, k, Term::Multiplier(1), law.c_slip);
                    }
                }
            }
        }
    }

    /// Pairs of a Coulomb interface that close (open in `states`, bonded in `next`)
    /// touch down where they are: their plastic slip becomes their tangential jump
    /// in the solution `u`, so they close without tangential force. For a pair
    /// that was closed where the increment started this is a step of the search
    /// only: a pattern is accepted on its plastic slip of the increment's start
    /// ([`Solver::restore_closed_slips`]).
    fn touch_down(&mut self, states: &[Vec<PairState>], next: &[Vec<PairState>], u: &[f64]) {
        if self.proportional {
            return;
        }
        history::touch_down(self.interfaces, self.dofs, states, next, u, &mut self.history);
    }

    /// Gives every pair closed both where the increment started and in `states`
    /// its plastic slip of the increment's start back (a touch-down of the
    /// search, [`Solver::touch_down`], moved it: the pair was opened by a pattern
    /// tried, not by the path). Its stick force and its trial force are then
    /// measured from where it stuck. Returns whether any changed.
    fn restore_closed_slips(&mut self, states: &[Vec<PairState>]) -> bool {
        if self.proportional {
            return false;
        }
        history::restore_closed_slips(
            self.interfaces,
            &self.closed_at_start,
            &self.committed,
            states,
            &mut self.history,
        )
    }

    /// Ends an increment's history: a slipping Coulomb pair keeps its plastic slip
    /// `s_p = [[u_s]] − f_s / c_s`, an open pair's slip follows its jump (it closes
    /// again unstressed tangentially) and loses its multipliers. Copies the history
    /// into `result`.
    fn commit_history(&mut self, result: &mut IncrementResult) {
        result.fixed_point_iterations = self.fixed_point;
        result.augmented_error = self.augmented_error;
        if self.proportional {
            result.pair_history = self.history.clone();
            return;
        }
        history::commit(
            self.interfaces,
            self.dofs,
            &result.states,
            &result.u,
            &mut self.history,
        );
        result.pair_history = self.history.clone();
        self.committed.clone_from(&self.history);
        for (c, st) in self.closed_at_start.iter_mut().zip(&result.states) {
            for (c, s) in c.iter_mut().zip(st) {
                *c = s.is_closed();
            }
        }
    }

    /// One linear solve of `states` at load factor `lambda` with the current pair
    /// histories.
    fn solve_once(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Vec<f64>, Option<Method>)> {
        if self.proportional
            && let Some(s) = &self.last
            && let Some((su, sf)) = &s.values
            && s.states == states
            && s.lambda != 0.0
        {
            // Loads and prescribed values are proportional: same states, scaled solution.
            let f = lambda / s.lambda;
            let u = su.iter().map(|v| f * v).collect();
            let f_int = sf.iter().map(|v| f * v).collect();
            return Ok((u, f_int, None));
        }
        let t = Instant::now();
        self.supports.check(self.parts, self.interfaces, states)?;
        self.timings.contact_update += t.elapsed().as_secs_f64();
        // This solve replaces the kept solution, whose vectors are freed now
        // rather than held beside this solve's; the trials' two vectors become
        // this solve's displacements and right-hand side (their pages already
        // touched: a fresh pair would be first-touched again, 61 MiB at 4 M
        // unknowns).
        let number = self.last.take().map_or(0, |s| s.number + 1);
        let Spare { mut u, mut x, .. } = std::mem::take(&mut self.spare);
        // The freed vectors and the columns' scratch stay resident in the heap
        // unless given back.
        super::heap::return_free_memory();
        // The right-hand side is solved in place (`x`); the rare second solve of
        // a lost update builds it again rather than keeping a copy.
        let _ = self.right_hand_side_into(lambda, states, &mut u, &mut x);
        let mut refactored = false;
        loop {
            // With a factor kept, the solve may be an update, whose refinement
            // reads the unrefined solution around the coupling nodes (the ring
            // is usually found by the first trial already).
            if self.coupling_ring.is_none() && self.system.has_factor() {
                self.coupling_ring = Some(self.coupling_ring());
            }
            self.check_stop(inc)?;
            let read = self.coupling_ring.as_ref().map_or(&[][..], |r| &r.eqs[..]);
            let solved = self
                .system
                .solve_unrefined(self.interfaces, self.dofs, states, &mut x, read)
                .map_err(|h| self.halt_error(h, inc))?;
            let method = match solved {
                Solve::Complete(method) => method,
                Solve::Unrefined(unrefined) => {
                    // One step of iterative refinement: the Woodbury correction
                    // of a stiff pair opening cancels large terms, and on soft
                    // models loses digits a factorization keeps. They are lost
                    // in the capacitance's solution, so the residual they leave
                    // is on the coupling DOFs (`ContactSystem::solve_unrefined`):
                    // its correction there restores them, and keeps elsewhere
                    // the round-off of the factorization the update shares. The
                    // residual is read from the unrefined solution around the
                    // coupling nodes, and takes the memory of `x`.
                    let t = Instant::now();
                    let ring = self.coupling_ring.as_ref().expect("built for a kept factor");
                    for &d in &ring.dofs {
                        let e = self.dofs.eq[d];
                        if e != FIXED {
                            u[d] = x[e];
                        }
                    }
                    let f_c = self.coupling_force(states, &u);
                    x.fill(0.0);
                    for &d in &self.coupling_dofs {
                        let e = self.dofs.eq[d];
                        if e != FIXED {
                            x[e] = lambda * self.f_ext[d] - f_c[d];
                        }
                    }
                    drop(f_c);
                    self.timings.contact_update += t.elapsed().as_secs_f64();
                    self.system.refine(unrefined, &mut x)
                }
            };
            for (d, &e) in self.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    u[d] = x[e];
                }
            }
            if u.iter().any(|v| !v.is_finite()) {
                return Err(self.not_finite(inc));
            }
            // The solve's vector is spent: its memory serves the internal force
            // and the kept copies.
            drop(std::mem::take(&mut x));
            let t = Instant::now();
            let f_int = self.internal_force(states, &u);
            self.timings.contact_update += t.elapsed().as_secs_f64();
            let residual = self.residual(lambda, &f_int, self.load_scale(lambda, &f_int, &u));
            if residual > UPDATE_RESIDUAL_LIMIT
                && matches!(method, Method::LowRank { .. })
                && !refactored
            {
                // The update lost accuracy: solve again with a fresh factorization.
                self.system.invalidate();
                refactored = true;
                let _ = self.right_hand_side_into(lambda, states, &mut u, &mut x);
                continue;
            }
            // Its values, to be scaled by later increments, are copied from the
            // increment's result once it is accepted (`keep_for_scaling`), after
            // the factor is freed, rather than here beside it.
            self.last = Some(Solved {
                number,
                states: states.to_vec(),
                lambda,
                values: None,
            });
            super::heap::return_free_memory();
            return Ok((u, f_int, Some(method)));
        }
    }

    /// The prescribed displacements at load factor `lambda` (all DOFs, zero at the
    /// free ones) into `u` and the right-hand side of the free equations into
    /// `rhs` (both overwritten, their memory reused): the loads less the internal
    /// force of the prescribed values, which carries the pairs' constant terms
    /// (initial gaps, slip history, slip forces, multipliers). Returns whether
    /// the right-hand side depends on `states` (through that force): not with
    /// proportional loads and nothing prescribed moving, where it is λ f.
    fn right_hand_side_into(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        u: &mut Vec<f64>,
        rhs: &mut Vec<f64>,
    ) -> bool {
        let t = Instant::now();
        let prescribed = self.prescribed.as_deref().unwrap_or(&self.dofs.prescribed);
        u.clear();
        u.extend(prescribed.iter().map(|v| lambda * v));
        let u = &*u;
        let moved = u.iter().any(|&v| v != 0.0);
        let has_prescribed = moved || !self.proportional;
        let f_p = if moved {
            self.internal_force(states, u)
        } else if has_prescribed {
            // No prescribed motion: the parts' forces vanish, only the pairs'
            // constant terms remain.
            let history = (!self.proportional).then_some(self.history.as_slice());
            let pairs = assembly::CouplingElements::new(self.interfaces, Some(states), self.dofs)
                .with_history(history);
            assembly::internal_force_of(&[&pairs], u)
        } else {
            Vec::new()
        };
        rhs.clear();
        rhs.resize(self.dofs.n_eq, 0.0);
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                rhs[e] = lambda * self.f_ext[d] - if has_prescribed { f_p[d] } else { 0.0 };
            }
        }
        self.timings.assembly += t.elapsed().as_secs_f64();
        has_prescribed
    }

    /// A trial solution of `states` for the law check of an active-set iteration
    /// (seed laws only): the displacements at the coupling elements' DOFs, from a
    /// solve on the elimination-tree paths of their equations
    /// (`ContactSystem::solve_interface`); every other free DOF is NaN. No
    /// internal force, residual or refinement: a pattern the trial finds
    /// consistent is solved in full before it is accepted.
    pub fn solve_interface(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Option<Method>)> {
        self.check_stop(inc)?;
        let t = Instant::now();
        self.supports.check(self.parts, self.interfaces, states)?;
        if self.coupling_ring.is_none() {
            // What the complete solve accepting a trial's pattern (an update,
            // to be refined) reads: found with the first trial rather than
            // inside that solve.
            self.coupling_ring = Some(self.coupling_ring());
        }
        self.timings.contact_update += t.elapsed().as_secs_f64();
        if let Some(s) = &mut self.last {
            // A trial moves on from the kept solution's pattern.
            s.values = None;
        }
        let Spare { mut u, mut x, trial } = std::mem::take(&mut self.spare);
        // The last trial's vectors serve as they are when that trial was of this
        // increment and load factor, its right-hand side independent of the
        // states, and its displacements given back: the solve changed the
        // right-hand side at the coupling equations only (restored here), and
        // the displacements are NaN at every free DOF but the coupling ones.
        // Otherwise both are built anew (O(unknowns) each).
        let again = trial
            .filter(|t| t.inc == inc && t.lambda == lambda && u.len() == self.dofs.eq.len());
        let reused = again.is_some();
        // The right-hand side at the coupling equations, when it does not
        // depend on the states (kept for the next trial).
        let rhs: Option<Vec<f64>> = match again {
            Some(t) => {
                for (e, &v) in self.coupling_equations().zip(&t.rhs) {
                    x[e] = v;
                }
                Some(t.rhs)
            }
            None => (!self.right_hand_side_into(lambda, states, &mut u, &mut x))
                .then(|| self.coupling_equations().map(|e| x[e]).collect()),
        };
        let (method, complete) = self
            .system
            .solve_interface(self.interfaces, self.dofs, states, &mut x, false)
            .map_err(|h| self.halt_error(h, inc))?;
        if complete {
            for (d, &e) in self.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    u[d] = x[e];
                }
            }
        } else {
            if !reused {
                for (d, &e) in self.dofs.eq.iter().enumerate() {
                    if e != FIXED {
                        u[d] = f64::NAN;
                    }
                }
            }
            for &d in &self.coupling_dofs {
                let e = self.dofs.eq[d];
                if e != FIXED {
                    u[d] = x[e];
                }
            }
        }
        self.spare.x = x;
        self.spare.trial = rhs
            .filter(|_| !complete)
            .map(|rhs| TrialRhs { inc, lambda, rhs });
        // Only the values solved for can be infinite (the prescribed ones are
        // finite multiples of finite input).
        let infinite = if complete {
            u.iter().any(|v| v.is_infinite())
        } else {
            self.coupling_dofs.iter().any(|&d| u[d].is_infinite())
        };
        if infinite {
            return Err(self.not_finite(inc));
        }
        Ok((u, Some(method)))
    }

    /// Gives the displacements `u` of a trial ([`Solver::solve_interface`]) back
    /// once read: their memory, and with the same right-hand side their
    /// contents (NaN off the coupling DOFs), serve the next trial.
    pub fn return_trial(&mut self, u: Vec<f64>) {
        self.spare.u = u;
    }

    /// The free equations of the coupling DOFs (in their order).
    fn coupling_equations(&self) -> impl Iterator<Item = usize> + '_ {
        self.coupling_dofs
            .iter()
            .map(|&d| self.dofs.eq[d])
            .filter(|&e| e != FIXED)
    }

    fn not_finite(&self, inc: usize) -> Error {
        Error::Overflow {
            path: None,
            line: None,
            key: String::new(),
            message: format!(
                "increment {inc}: the solution is not finite (a load, a prescribed value or a stiffness is too large or too small for double precision; rescale the units)"
            ),
        }
    }

    /// The part elements around the coupling nodes and the DOFs and equations
    /// of their nodes.
    fn coupling_ring(&self) -> CouplingRing {
        let part_elements = assembly::PartElements::new(self.parts, self.dofs);
        let mut at_coupling = vec![false; self.dofs.n_nodes()];
        for &d in &self.coupling_dofs {
            at_coupling[d / 2] = true;
        }
        let elements = part_elements.touching(|n| at_coupling[n]);
        let mut dofs = self.coupling_dofs.clone();
        for &e in &elements {
            part_elements.nodes(e, &mut |nodes| {
                for &n in nodes {
                    dofs.extend([2 * n, 2 * n + 1]);
                }
            });
        }
        dofs.sort_unstable();
        dofs.dedup();
        let mut eqs: Vec<usize> =
            dofs.iter().map(|&d| self.dofs.eq[d]).filter(|&e| e != FIXED).collect();
        eqs.sort_unstable();
        CouplingRing {
            elements,
            dofs,
            eqs,
        }
    }

    /// The internal force at the coupling elements' DOFs for `u` (read at the
    /// [`CouplingRing`]'s DOFs only) with the pairs in `states` and their
    /// current histories, from the coupling elements and the part elements
    /// around their nodes (the other DOFs hold partial sums): what a refinement
    /// on the coupling equations reads, for a few elements' work.
    fn coupling_force(&self, states: &[Vec<PairState>], u: &[f64]) -> Vec<f64> {
        let ring = self.coupling_ring.as_ref().expect("built before a refinement");
        let part_elements = assembly::PartElements::new(self.parts, self.dofs);
        let around = assembly::SomeElements::new(&part_elements, &ring.elements);
        let history = (!self.proportional).then_some(self.history.as_slice());
        let pairs = assembly::CouplingElements::new(self.interfaces, Some(states), self.dofs)
            .with_history(history);
        assembly::internal_force_of(&[&around, &pairs], u)
    }

    /// The internal force of all DOFs for `u` with the pairs in `states` and their
    /// current histories (none for the seed's laws).
    fn internal_force(&self, states: &[Vec<PairState>], u: &[f64]) -> Vec<f64> {
        let history = (!self.proportional).then_some(self.history.as_slice());
        assembly::internal_force_with(self.parts, self.interfaces, states, history, self.dofs, u)
    }

    /// The error of a linear solve of increment `inc` that did not finish: a
    /// stop request ([`Error::Interrupted`]) or a non-positive pivot at an
    /// equation (where, named by part and node).
    fn halt_error(&self, halt: Halt, inc: usize) -> Error {
        let eq = match halt {
            Halt::Stopped(signal) => {
                return Error::Interrupted {
                    increment: inc.saturating_sub(1),
                    signal,
                };
            }
            Halt::Pivot(eq) => eq,
        };
        let d = self.dofs.eq.iter().position(|&e| e == eq).unwrap_or(0);
        let (p, n) = self.dofs.locate(d / 2);
        Error::NotPositiveDefinite {
            increment: inc,
            part: self.parts[p].name.clone(),
            node: n,
            component: d % 2,
            message: format!(
                "increment {inc}: the stiffness matrix is not positive definite (pivot at part '{}', node {n}, {} displacement); check for a mechanism or an unsupported part",
                self.parts[p].name,
                if d % 2 == 0 { "x" } else { "y" }
            ),
        }
    }

    /// Largest out-of-balance force at a free DOF relative to `scale`.
    fn residual(&self, lambda: f64, f_int: &[f64], scale: f64) -> f64 {
        let res = self
            .dofs
            .eq
            .iter()
            .enumerate()
            .filter(|(_, e)| **e != FIXED)
            .map(|(d, _)| (f_int[d] - lambda * self.f_ext[d]).abs())
            .fold(0.0, f64::max);
        if scale > 0.0 { res / scale } else { res }
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &mut self,
        index: usize,
        lambda: f64,
        history: Vec<Iteration>,
        u: Vec<f64>,
        f_int: Vec<f64>,
        states: PairStates,
        check: LawCheck,
        settled: bool,
    ) -> IncrementResult {
        // The increment is accepted: its right-hand side is not solved again.
        self.system.forget_right_hand_side();
        let f_ext: Vec<f64> = self.f_ext.iter().map(|f| lambda * f).collect();
        let balance_scale = self.balance_scale(check.load_scale, check.pair_force, &u);
        let residual = self.residual(lambda, &f_int, balance_scale);
        // Σ reactions + Σ loads = Σ over fixed DOFs of (F_int − F_ext) + Σ F_ext.
        let mut total = [0.0; 2];
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            total[d % 2] += if e == FIXED { f_int[d] } else { f_ext[d] };
        }
        let balance = total[0].hypot(total[1]) / balance_scale.max(f64::MIN_POSITIVE);
        // With the proportional shortcuts the final solve either is the last
        // solution (a method) or scales it (no method); see `solve_once`.
        let multiple_of = match (&self.last, history.last()) {
            (Some(s), Some(it)) if self.proportional => Some(MultipleOf {
                solution: s.number,
                factor: if it.method.is_some() { 1.0 } else { lambda / s.lambda },
            }),
            _ => None,
        };
        let settled = if settled {
            check
                .violations
                .iter()
                .map(|v| (v.interface, v.pair))
                .collect()
        } else {
            Vec::new()
        };
        IncrementResult {
            index,
            lambda,
            step: 0,
            time: lambda,
            iterations: history.len(),
            history,
            u,
            states,
            settled,
            violations: check.violations,
            load_scale: check.load_scale,
            balance_scale,
            f_int,
            f_ext,
            residual,
            balance,
            pair_history: Vec::new(),
            fixed_point_iterations: 0,
            augmented_error: 0.0,
            multiple_of,
            friction_continuation: false,
        }
    }
}

/// The pattern `states` (whose slip forces found no fixed point) with the
/// stick point moved: on each Coulomb interface (`coulomb[i]`) that has no
/// stick pair in `states` but had one in `held` (the last pattern with a fixed
/// point) and whose pairs press together (`pressed[i]`), `held`'s slipping pair
/// nearest its cone (`nearest[i]`) sticks. A part whose last stick pair went
/// beyond its cone slides off on the rest — their slip forces balance at any
/// position — so its stick zone moves to the pair next to reaching its own
/// cone, rather than every slipping pair sticking. An interface whose pairs
/// pull together is coming apart, not sliding (the law opens them). `None`
/// when no interface's stick point moves.
fn move_stick_point(
    coulomb: &[bool],
    states: &[Vec<PairState>],
    held: &[Vec<PairState>],
    nearest: &[Option<usize>],
    pressed: &[bool],
) -> Option<PairStates> {
    let sticks = |s: &[PairState]| s.contains(&PairState::Bonded);
    let mut moved = states.to_vec();
    let mut any = false;
    for i in 0..states.len() {
        if !coulomb[i] || sticks(&states[i]) || !sticks(&held[i]) || !pressed[i] {
            continue;
        }
        if let Some(k) = nearest[i].filter(|&k| states[i][k] == PairState::Slip) {
            moved[i][k] = PairState::Bonded;
            any = true;
        }
    }
    any.then_some(moved)
}

/// The cautious step: `states` with one pair flipped the way its violation asks
/// (a pulling pair opens, a penetrating one closes, a stick pair beyond its cone
/// slips, a slip pair inside it sticks; the first of equals).
///
/// With `wide` (friction: the all-at-once update's friction-first rule holds
/// pulling pairs closed while a stick pair exceeds its cone, so normal and
/// tangential flips interleave), the worst violating pair whose flip leads to a
/// pattern that is `open` to the iteration — not yet solved, and holding every
/// part — and `states` itself when no flip does. Without, the worst violating
/// pair's flip whatever it leads to (the seed's laws: where it leads back to a
/// solved pattern, the contact-states study found no consistent pattern near the
/// pairs that then settle; searching on costs iterations without changing that).
fn flip_worst(
    states: &[Vec<PairState>],
    check: &LawCheck,
    wide: bool,
    open: impl Fn(&PairStates) -> bool,
) -> PairStates {
    let mut order: Vec<&PairViolation> = check.violations.iter().collect();
    // Stable: equal violations keep their order.
    order.sort_by(|a, b| b.force.total_cmp(&a.force));
    let mut next = states.to_vec();
    for v in order {
        let (i, k) = (v.interface, v.pair);
        let now = next[i][k];
        let to = match v.kind {
            ViolationKind::Tension => PairState::Open,
            ViolationKind::Penetration | ViolationKind::Slip => PairState::Bonded,
            ViolationKind::Friction => PairState::Slip,
        };
        if to == now {
            continue;
        }
        next[i][k] = to;
        if !wide || open(&next) {
            return next;
        }
        next[i][k] = now;
    }
    next
}

/// What to say about the penalties when the solve lost accuracy.
fn penalty_advice(parts: &[Part], interfaces: &[Interface]) -> String {
    let worst = interfaces
        .iter()
        .map(|i| {
            let et = |p: usize| parts[p].material.young * parts[p].material.thickness;
            let softer = et(i.host).min(et(i.node_part));
            (i.c_n.max(i.c_s) / softer, i)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    match worst {
        Some((ratio, i)) if ratio > 1e7 => format!(
            "Interface '{}' has a penalty {:.3e}, {:.1e} × E·t of its softer part: too large for double precision. Penalties between about 1e3 and 1e7 × E·t work (the default is 1e5 × E·t); lower c_n and c_s.",
            i.name,
            i.c_n.max(i.c_s),
            ratio
        ),
        _ => "The model is ill-conditioned: check for very different stiffnesses (E, thickness) between parts, or elements of very different sizes.".into(),
    }
}

/// Σ ‖f‖ over the nodes of the force vector `f`.
fn total_force(f: &[f64]) -> f64 {
    f.chunks_exact(2).map(|f| f[0].hypot(f[1])).sum()
}

fn count_changes(a: &[Vec<PairState>], b: &[Vec<PairState>]) -> usize {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.iter().zip(y).filter(|(p, q)| p != q).count())
        .sum()
}

/// The largest nodal displacement |u_n| of `u` (two DOFs a node) over the nodes
/// not in `skip` (sorted).
fn largest_off(u: &[f64], skip: &[usize]) -> f64 {
    u.chunks_exact(2)
        .enumerate()
        .filter(|(n, _)| skip.binary_search(n).is_err())
        .map(|(_, v)| v[0].hypot(v[1]))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use PairState::{Bonded, Open, Slip};

    fn violation(pair: usize, kind: ViolationKind, force: f64) -> PairViolation {
        PairViolation {
            interface: 0,
            pair,
            kind,
            amount: force,
            force,
        }
    }

    /// The cautious step flips the worst violating pair the way its violation
    /// asks, passing over flips that lead back to a solved pattern, and returns
    /// the pattern itself (the increment settles) when no flip is left; the
    /// all-at-once update's verdict (`next`, here holding a pulling pair closed as
    /// the friction-first rule does) does not restrict it.
    #[test]
    fn cautious_step_takes_the_worst_unsolved_flip() {
        let states = vec![vec![Bonded, Bonded, Slip, Open]];
        let check = LawCheck {
            next: states.clone(),
            violations: vec![
                violation(0, ViolationKind::Tension, 3.0),
                violation(1, ViolationKind::Friction, 5.0),
                violation(2, ViolationKind::Slip, 5.0),
                violation(3, ViolationKind::Penetration, 1.0),
            ],
            load_scale: 1.0,
            pair_force: 0.0,
            nearest_slip: vec![None],
            pressed: vec![true],
        };
        let mut seen = HashSet::new();
        seen.insert(states.clone());
        let flip = |i: usize, to: PairState| {
            let mut s = states.clone();
            s[0][i] = to;
            s
        };
        // In order: the first of the two worst (5.0), the stick pair beyond its
        // cone, slips; the slip pair inside its cone sticks; the pulling pair
        // opens, although `next` kept it bonded; the penetrating pair closes.
        for (pair, to) in [(1, Slip), (2, Bonded), (0, Open), (3, Bonded)] {
            let next = flip_worst(&states, &check, true, |p| !seen.contains(p));
            assert_eq!(next, flip(pair, to), "pair {pair}");
            seen.insert(next);
        }
        // Nothing unsolved is left: the pattern itself.
        assert_eq!(flip_worst(&states, &check, true, |p| !seen.contains(p)), states);
        // Without friction: the worst pair's flip, solved before or not.
        let next = flip_worst(&states, &check, false, |p| !seen.contains(p));
        assert_eq!(next, flip(1, Slip));
    }

    /// A face whose one stick pair slipped, every pair now slipping: the stick
    /// point moves to the slipping pair the held pattern had nearest its cone,
    /// the others keep their states. Not on a face that pulls, a face that
    /// still sticks somewhere, a face that had no stick pair to lose, or a
    /// face that is not Coulomb's.
    ///
    /// ```text
    ///   held:    slip  stick  slip  slip  open     nearest: pair 2
    ///   states:  slip  slip   slip  slip  open
    ///   moved:   slip  slip   stick slip  open
    /// ```
    #[test]
    fn the_stick_point_moves_to_the_slipping_pair_nearest_its_cone() {
        let held = vec![vec![Slip, Bonded, Slip, Slip, Open]];
        let states = vec![vec![Slip, Slip, Slip, Slip, Open]];
        let nearest = [Some(2)];
        let moved = move_stick_point(&[true], &states, &held, &nearest, &[true]);
        assert_eq!(moved, Some(vec![vec![Slip, Slip, Bonded, Slip, Open]]));
        // A face pulling together, a face still sticking, a face that had
        // no stick pair, a face not Coulomb's: nothing moves.
        assert_eq!(move_stick_point(&[true], &states, &held, &nearest, &[false]), None);
        let sticking = vec![vec![Slip, Slip, Slip, Bonded, Open]];
        assert_eq!(move_stick_point(&[true], &sticking, &held, &nearest, &[true]), None);
        assert_eq!(move_stick_point(&[true], &states, &states, &nearest, &[true]), None);
        assert_eq!(move_stick_point(&[false], &states, &held, &nearest, &[true]), None);
        // The pair nearest its cone in the held pattern opened since: none.
        let opened = vec![vec![Slip, Slip, Open, Slip, Open]];
        assert_eq!(move_stick_point(&[true], &opened, &held, &nearest, &[true]), None);
    }
}
