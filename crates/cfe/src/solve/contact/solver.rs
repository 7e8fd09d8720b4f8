//! The contact scheme's state: the [`Solver`], which the layers above extend
//! (an `impl` block each: the law sweep, the fixed point, the pattern's solve,
//! the active-set search, the driver), with what it keeps between solves, its
//! configuration (load path, initial states, update policy, stop flag) and
//! the plumbing every layer reads: the stop flag, the scales of a solution
//! ([`Scales`]) and the errors of a linear solve.

use super::increment::{IterativeSolves, Iteration, LoadPath, LoadSteps, SolveTimings};
use super::scale::{Scales, largest_off, total_force};
use crate::assembly::{DofMap, FIXED};
use crate::coupling::{
    Interface, InterfacePairs, Law, PairHistories, PairHistory, PairSet, PairState, PairStates,
};
use crate::dim::{D2, D3};
use crate::domain::{CG_TOLERANCE, LinearBackend, Part, Scheme, Settings};
use crate::error::{Error, Result};
use crate::fem::ElementFamily;
use crate::solve::backend::{Analyse, LinearFailure, LinearSolver, Outcome, Problem, Statistics};
use crate::solve::direct::Cholesky;
use crate::solve::iterative::ConjugateGradients;
use crate::solve::friction_hold::FrictionHold;
use crate::solve::support;
use crate::solve::system::{ContactSystem, UpdatePolicy};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The pair set the scheme reaches the pairs through ([`PairSet`]): the
/// model's interfaces of dimension `D` with its DOF numbering.
pub(super) type Pairs<'a, D> = InterfacePairs<'a, D>;

/// The solution of one state set, kept to answer the same states at another λ.
pub(super) struct Solved {
    /// The solution's number over the run.
    pub(super) number: usize,
    pub(super) states: PairStates,
    pub(super) lambda: f64,
    /// Its displacements and internal force, to be scaled by later increments:
    /// kept with proportional loads only, copied from the increment's result
    /// once it is accepted ([`Solver::keep_for_scaling`]; an increment never
    /// scales its own solve), and dropped when a trial moves on from its pattern
    /// (only a return to it could use them; a complete solve answers that), so
    /// the trials' vectors do not sit beside two more.
    pub(super) values: Option<(Vec<f64>, Vec<f64>)>,
}

/// The part elements around the coupling nodes (those with a node among the
/// coupling elements'): with the coupling elements, every element whose
/// internal force reaches a coupling DOF.
pub(super) struct CouplingRing {
    /// The elements, in [`assembly::PartElements`]' numbering.
    pub(super) elements: Vec<usize>,
    /// The DOFs of their nodes and of the coupling elements, sorted.
    pub(super) dofs: Vec<usize>,
    /// The free equations of those DOFs, sorted.
    pub(super) eqs: Vec<usize>,
}

/// What the solves of patterns keep from one to the next: the last complete
/// solution, the coupling ring, and the last trial's vectors.
#[derive(Default)]
pub(super) struct Kept {
    /// The last complete solve's pattern and load factor (and, with
    /// proportional loads once accepted, its values to scale).
    pub(super) last: Option<Solved>,
    /// The part elements around the coupling nodes (what a low-rank update's
    /// refinement reads), found with the first trial or, failing one, the first
    /// complete solve with a factor kept.
    pub(super) coupling_ring: Option<CouplingRing>,
    /// The displacement and right-hand-side vectors of the last trial solve,
    /// kept so the next trial reuses their memory (at 8 M unknowns they are 195 MB
    /// an iteration that would otherwise be allocated and first touched anew),
    /// and, when their contents serve it too, which trial they were.
    pub(super) spare: Spare,
}

/// The incremental solver for one model of dimension `D` (its nodal vectors,
/// DOFs per node, tangent and rigid modes: [`D2`] for the plane models built
/// today). The scheme reads the dimension only through `D`.
pub struct Solver<'a, D: ElementFamily = D2> {
    pub(super) parts: &'a [Part<D>],
    pub(super) interfaces: &'a [Interface<D>],
    pub(super) dofs: &'a DofMap<D>,
    pub(super) settings: &'a Settings,
    pub(super) f_ext: Vec<f64>,
    /// The linear back end every pattern is solved by, behind the seam
    /// ([`crate::solve::backend`]); its optional capabilities (restricted and
    /// refined solves, low-rank updates) are used when it offers them.
    pub(super) linear: Box<dyn LinearSolver<'a> + 'a>,
    /// The last solution of a complete or trial solve (free equations): the
    /// initial guess of the next, kept only for a back end that starts from
    /// one ([`LinearSolver::starts_from_guess`]; empty otherwise).
    pub(super) guess: Vec<f64>,
    /// The iterations of every solve of an iterative back end (`None`: direct).
    pub(super) iterative: Option<IterativeSolves>,
    /// The support check's constant part (frames and fixed DOFs).
    pub(super) supports: support::SupportCheck<D>,
    /// The parts friction alone holds along their faces, checked against each
    /// increment's load before it is solved.
    pub(super) friction_hold: FrictionHold<D>,
    /// What the solves of patterns keep from one to the next.
    pub(super) kept: Kept,
    pub(super) initial: Option<PairStates>,
    /// The pattern the previous active-set increment settled on, if it settled.
    pub(super) settled_pattern: Option<PairStates>,
    /// The model's sizes the load and balance scales and the drift guard read.
    pub(super) scales: Scales,
    /// Whether the solution scales with the load factor (no initial gap, no
    /// friction, no augmented Lagrangian): then a solved pattern is scaled, not
    /// solved again.
    pub(super) proportional: bool,
    /// Each pair's history (plastic slip, slip force, multipliers).
    pub(super) history: PairHistories<D>,
    /// The history the increment starts from (the last one committed): every
    /// iteration of an increment starts from it, and a pair that was closed there
    /// closes again on its plastic slip.
    pub(super) committed: PairHistories<D>,
    /// The pairs closed where the increment starts: at the end of the last
    /// increment, or, before the first, the pairs touching (g₀ ≤ 0).
    pub(super) closed_at_start: Vec<Vec<bool>>,
    /// Fixed-point solves in the current increment.
    pub(super) fixed_point: usize,
    /// The load path, when not the default ramp (load factors, load steps).
    pub(super) path: LoadPath,
    /// Largest augmented-Lagrangian error of the last fixed point.
    pub(super) augmented_error: f64,
    /// Whether the last pattern's fixed point converged.
    pub(super) fixed_point_converged: bool,
    /// Whether the last pattern's slip directions settled: false when its
    /// Newton step left pairs whose slip reverses (the pattern's exact
    /// solution at the directions last solved for; the active-set search
    /// reads the reversals from the law check, the implex scheme, which
    /// corrects nothing, has no consistent slip forces in its states).
    pub(super) slip_directions_settled: bool,
    /// What the Newton steps of the patterns' slip forces did
    /// (`friction_solve = "newton"`).
    pub(super) newton: super::increment::NewtonCounts,
    /// The friction solve the search uses now: the settings', but the fixed
    /// point while an increment the Newton search did not answer is searched
    /// again with it.
    pub(super) friction_solve: crate::domain::FrictionSolve,
    /// Per interface, whether it follows the Coulomb law.
    pub(super) coulomb: Vec<bool>,
    /// The factor on every interface's friction coefficient: 1 but while a
    /// continuation in μ looks for an increment's starting pattern.
    pub(super) friction_factor: f64,
    /// The iterations of the last active-set search that ended in an error
    /// (the caller that searches again counts them with its own).
    pub(super) failed_search: Vec<Iteration>,
    /// Every coupling element's DOFs (sorted): the DOFs a solve restricted to the
    /// interface gives.
    pub(super) coupling_dofs: Vec<usize>,
    /// The caller's request to stop (nonzero: e.g. a signal's number), read at
    /// every increment, active-set iteration, fixed-point step, continuation
    /// stage and before every linear solve ([`Solver::set_stop`]).
    pub(super) stop: Option<&'a AtomicUsize>,
    /// Phase timings.
    pub timings: SolveTimings,
}

/// The two vectors of a trial solve, kept for the next trial ([`Kept`]'s
/// `spare`; taken, it is left empty).
#[derive(Default)]
pub(super) struct Spare {
    /// Displacements: NaN at the free DOFs but the coupling ones after a trial.
    pub(super) u: Vec<f64>,
    /// The right-hand side, solved in place at the coupling equations.
    pub(super) x: Vec<f64>,
    /// The trial whose right-hand side `x` holds off the coupling equations,
    /// when it does not depend on the states (the next trial of the same
    /// increment and load factor reuses it).
    pub(super) trial: Option<TrialRhs>,
}

/// A trial's right-hand side, independent of the states: its increment, load
/// factor and values at the coupling equations (where the solve overwrote it).
pub(super) struct TrialRhs {
    pub(super) inc: usize,
    pub(super) lambda: f64,
    pub(super) rhs: Vec<f64>,
}

impl<'a, D: ElementFamily> Solver<'a, D> {
    /// The pairs the scheme solves with, through the [`PairSet`] it reads them by.
    pub(super) fn pairs(&self) -> Pairs<'a, D> {
        InterfacePairs::new(self.interfaces, self.dofs)
    }

    /// Builds the node graph, the nested-dissection ordering, the fixed sparsity
    /// pattern and the symbolic factorization. `stop`, if given, is read during
    /// that analysis too (a nonzero value abandons it with
    /// [`Error::Interrupted`]) and then as [`Solver::set_stop`] says.
    pub fn new(
        parts: &'a [Part<D>],
        interfaces: &'a [Interface<D>],
        dofs: &'a DofMap<D>,
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
        let problem = Problem {
            parts,
            interfaces,
            dofs,
        };
        let (linear, iterative) = linear_back_end(settings.solver, problem, stop)?;
        Ok(Self::with_back_end(
            problem,
            f_ext,
            settings,
            stop,
            (linear, iterative),
            t.elapsed().as_secs_f64(),
        ))
    }

    /// The solver of `problem` on a linear back end already analysed for its
    /// pattern (`back_end`: the solver and, for an iterative one, the record of
    /// its solves; `analysis_seconds`: the time that analysis took), e.g. one
    /// built outside this library (`solve::contact::ExternalBackEnd`, with the `internals` feature).
    /// `stop` as [`Solver::new`] says.
    #[allow(clippy::type_complexity)]
    pub fn with_back_end(
        problem: Problem<'a, D>,
        f_ext: Vec<f64>,
        settings: &'a Settings,
        stop: Option<&'a AtomicUsize>,
        back_end: (Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>),
        analysis_seconds: f64,
    ) -> Self {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = problem;
        let (linear, iterative) = back_end;
        let timings = SolveTimings {
            pattern_and_symbolic: analysis_seconds,
            ..Default::default()
        };
        let total_load = total_force::<D>(&f_ext);
        let proportional = !interfaces.iter().any(Interface::non_proportional);
        let pairs = InterfacePairs::new(interfaces, dofs);
        let each_pair = |i: usize| (0..pairs.pair_count(i)).map(move |k| (i, k));
        let history: PairHistories<D> = (0..pairs.interface_count())
            .map(|i| vec![PairHistory::default(); pairs.pair_count(i)])
            .collect();
        let mut solver = Solver {
            parts,
            interfaces,
            dofs,
            settings,
            f_ext,
            linear,
            guess: Vec::new(),
            iterative,
            supports: support::SupportCheck::new(parts, dofs),
            friction_hold: FrictionHold::new(parts, interfaces, dofs),
            initial: None,
            settled_pattern: None,
            scales: model_scales(parts, &pairs, dofs, total_load),
            proportional,
            committed: history.clone(),
            history,
            // At u = 0 a pair's gap is its initial gap (`CouplingElement::gap`).
            closed_at_start: (0..pairs.interface_count())
                .map(|i| each_pair(i).map(|(i, k)| pairs.initial_gap(i, k) <= 0.0).collect())
                .collect(),
            fixed_point: 0,
            path: LoadPath::default(),
            augmented_error: 0.0,
            fixed_point_converged: true,
            slip_directions_settled: true,
            newton: Default::default(),
            friction_solve: settings
                .friction_solve
                .resolved(<D::Tangent as crate::dim::Tangent>::COMPONENTS > 1),
            coulomb: (0..pairs.interface_count())
                .map(|i| pairs.law(i).law == Law::Coulomb)
                .collect(),
            friction_factor: 1.0,
            failed_search: Vec::new(),
            coupling_dofs: crate::coupling::coupling_dofs(interfaces, dofs),
            kept: Kept::default(),
            stop: None,
            timings,
        };
        if let Some(stop) = stop {
            solver.set_stop(stop);
        }
        solver
    }

    /// Has the solver read `stop` at every increment, active-set iteration,
    /// fixed-point step and continuation stage, before every factorization or
    /// low-rank update, and before every supernode of a numeric factorization
    /// (`LinearSolver::set_stop`): once it is nonzero (the caller sets it, e.g. to a
    /// signal's number) the run ends there with [`Error::Interrupted`], the
    /// increment being solved abandoned. Reading it changes nothing else.
    pub fn set_stop(&mut self, stop: &'a AtomicUsize) {
        self.stop = Some(stop);
        self.linear.set_stop(stop);
    }

    /// `Err(Error::Interrupted)` once the stop flag is set, while increment
    /// `inc` is being solved (the last one written is the one before).
    pub(super) fn check_stop(&self, inc: usize) -> Result<()> {
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
        self.linear.statistics().matrix_nnz
    }

    /// Number of nonzeros of the Cholesky factor (0 for a back end without one).
    pub fn factor_nnz(&self) -> usize {
        self.linear.statistics().factor_nnz
    }

    /// What the iterative back end did (iterations per solve), when the run
    /// uses one.
    pub fn iterative_solves(&self) -> Option<&IterativeSolves> {
        self.iterative.as_ref()
    }

    /// Counts a linear solve's iterations, for an iterative back end.
    pub(super) fn record(&mut self, outcome: &Outcome) {
        if let (Some(solves), Some(it)) = (&mut self.iterative, outcome.iterations) {
            solves.iterations.push(it.count);
            solves.largest_relative_residual =
                solves.largest_relative_residual.max(it.relative_residual);
        }
    }

    /// The linear back end's counts and times so far.
    pub fn linear_statistics(&self) -> Statistics {
        self.linear.statistics()
    }

    /// Whether the factor is kept from one increment to the next, so the files
    /// of an increment are written beside it: every increment is solved (friction,
    /// gaps, augmented enforcement, load steps, or the `implex` scheme). With the
    /// active set under proportional loads it is freed after the first increment.
    pub fn keeps_factor_between_increments(&self) -> bool {
        !(self.settings.scheme == Scheme::ActiveSet && self.proportional)
    }

    /// Seconds of the first numeric factorization or preconditioner (None before it).
    pub fn first_factorization_seconds(&self) -> Option<f64> {
        self.linear.statistics().first_prepare_seconds
    }

    /// Whether the proportional-load shortcuts are on: a pattern solved at one load
    /// factor is scaled to another, and a settled pattern carries to the next
    /// increment without iterating. Off when an interface has an initial gap,
    /// follows the Coulomb law or is enforced by augmented Lagrangian (the solution
    /// is then not proportional to the load, or depends on the path).
    pub fn proportional(&self) -> bool {
        self.proportional
    }

    /// Applies the loads in steps: increment k carries the load Σ_g λ_g(k) f_g and
    /// the prescribed values Σ_g λ_g(k) p_g, and reports its step and that step's
    /// own factor. When at most one group carries load and its factor never goes
    /// negative the loading stays proportional (that group's vectors scaled by
    /// its factor, the shortcuts kept); otherwise
    /// the proportional shortcuts are off and the combined vectors are formed
    /// once per increment. Ignored when the vectors' lengths do not match the DOFs
    /// or an increment's factors do not match the groups.
    pub fn set_steps(&mut self, mut steps: LoadSteps) {
        let n = self.f_ext.len();
        let m = steps.forces.len();
        if m == 0
            || steps.prescribed.len() != m
            || steps.increments.is_empty()
            || steps.progress.len() != steps.increments.len()
            || steps.forces.iter().chain(&steps.prescribed).any(|v| v.len() != n)
            || steps
                .increments
                .iter()
                .any(|(_, f)| f.len() != m || f.iter().any(|x| !x.is_finite()))
        {
            return;
        }
        self.path.labels = Some(
            (steps.increments.iter().zip(&steps.progress))
                .map(|((s, _), l)| (*s, *l))
                .collect(),
        );
        self.scales.largest_prescribed = steps
            .prescribed
            .iter()
            .map(|p| largest_off::<D>(p, &[]))
            .fold(self.scales.largest_prescribed, f64::max);
        let loaded = steps.loaded();
        // A reversed load breaks the contact states' homogeneity (a bonded
        // pair in compression would pull): not proportional.
        if loaded.len() <= 1 && !loaded.first().is_some_and(|&g| steps.reversed(g)) {
            // Proportional: one group's load, scaled by its factor.
            let s = loaded.first().copied().unwrap_or(0);
            self.path.factors = Some(steps.increments.iter().map(|(_, f)| f[s]).collect());
            self.f_ext = std::mem::take(&mut steps.forces[s]);
            self.path.prescribed = Some(std::mem::take(&mut steps.prescribed[s]));
            self.scales.total_load = total_force::<D>(&self.f_ext);
        } else {
            self.proportional = false;
            self.path.factors = Some(vec![1.0; steps.increments.len()]);
            self.path.prescribed = Some(vec![0.0; n]);
            self.path.steps = Some(steps);
        }
    }

    /// With loads in several steps, sets `f_ext`, `prescribed` and the total load
    /// to those of increment `k` (0-based).
    pub(super) fn combine_steps(&mut self, k: usize) {
        let path = &mut self.path;
        let Some(steps) = &path.steps else {
            return;
        };
        let prescribed = path.prescribed.get_or_insert_with(Vec::new);
        prescribed.resize(self.f_ext.len(), 0.0);
        steps.combine(k, &mut self.f_ext, prescribed);
        self.scales.total_load = total_force::<D>(&self.f_ext);
    }

    /// Where increment `inc` (1-based, solved at factor `lambda`) is on the load
    /// path, for messages: its load factor, and with load steps its step.
    pub(super) fn where_in_path(&self, inc: usize, lambda: f64) -> String {
        self.path.describe(inc, lambda)
    }

    /// Replaces the load path: the increments go through these load factors in
    /// turn (the default is `k / increments`, k = 1, …, increments). A path that
    /// goes back (unloading) matters for a path-dependent law (Coulomb friction);
    /// the problem file has no such key — this is for studies and tests.
    pub fn set_load_factors(&mut self, factors: Vec<f64>) {
        if !factors.is_empty() && factors.iter().all(|f| f.is_finite()) {
            self.path.factors = Some(factors);
        }
    }

    /// Flops of the factorizations, solves and update columns so far (counted from
    /// the factor's supernodes, not measured).
    pub fn solve_flops(&self) -> f64 {
        self.linear.statistics().flops
    }

    /// Numeric factorizations (preconditioners built) and low-rank updates
    /// performed so far.
    pub fn solve_counts(&self) -> (usize, usize) {
        let s = self.linear.statistics();
        (s.preparations, s.updates)
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
    /// does not depend on it beyond round-off. Ignored by a back end without
    /// low-rank updates.
    pub fn set_update_policy(&mut self, policy: UpdatePolicy) {
        if let Some(l) = self.linear.low_rank() {
            l.set_policy(policy);
        }
    }

    /// Every pair of every interface bonded.
    pub(super) fn all_bonded(&self) -> PairStates {
        self.interfaces
            .iter()
            .map(|i| vec![PairState::Bonded; i.elements.len()])
            .collect()
    }

    /// The load scale at load factor `lambda`: the larger of Σ‖λ f‖ over the loaded
    /// nodes and the largest support reaction of the solution with internal force
    /// `f_int` (so a problem driven by prescribed displacements has a scale too).
    ///
    /// Without the proportional shortcuts (initial gaps, friction, augmented), the
    /// scale is at least [`FORCE_FLOOR`] × the largest E·t × the largest
    /// displacement `u`: a part that moves without load (a gap closing under a
    /// prescribed displacement) has no force to measure round-off against.
    pub(super) fn load_scale(&self, lambda: f64, f_int: &[f64], u: &[f64]) -> f64 {
        if self.proportional {
            return self.load_scale_of_forces(lambda, f_int);
        }
        self.load_scale_with(lambda, f_int, largest_off::<D>(u, &[]))
    }

    /// [`Solver::load_scale`] without the proportional shortcuts, given the
    /// largest nodal displacement `umax` ([`Scales::with_floor`]).
    pub(super) fn load_scale_with(&self, lambda: f64, f_int: &[f64], umax: f64) -> f64 {
        self.scales
            .with_floor(self.load_scale_of_forces(lambda, f_int), umax)
    }

    /// λ × the total load, or the largest support reaction of the solution
    /// with internal force `f_int` where larger ([`Scales::of_forces`]).
    pub(super) fn load_scale_of_forces(&self, lambda: f64, f_int: &[f64]) -> f64 {
        let largest = self
            .dofs
            .reactions(self.dofs.support_count(), f_int, &self.f_ext, lambda)
            .iter()
            .map(|r| D::length(r.as_ref()))
            .fold(0.0, f64::max);
        self.scales.of_forces(lambda, largest)
    }

    /// The scale the out-of-balance force of the solution `u` is measured
    /// against ([`Scales::balance`]), from its load scale and largest pair force.
    pub(super) fn balance_scale(&self, load_scale: f64, pair_force: f64, u: &[f64]) -> f64 {
        self.scales
            .balance(load_scale, pair_force, largest_off::<D>(u, &[]))
    }

    /// Largest out-of-balance force at a free DOF relative to `scale`.
    pub(super) fn residual(&self, lambda: f64, f_int: &[f64], scale: f64) -> f64 {
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

    /// The error of a linear solve of increment `inc` that did not finish: a
    /// stop request ([`Error::Interrupted`]), a matrix not positive definite
    /// (at an equation, named by part and node, when known), or an iterative
    /// solve short of its tolerance ([`Error::NoConvergence`]).
    pub(super) fn linear_error(&self, failure: LinearFailure, inc: usize) -> Error {
        let eq = match failure {
            LinearFailure::Stopped(signal) => {
                return Error::Interrupted {
                    increment: inc.saturating_sub(1),
                    signal,
                };
            }
            LinearFailure::NotPositiveDefinite { equation: Some(eq) } => eq,
            LinearFailure::NotPositiveDefinite { equation: None } => {
                return Error::Singular(format!(
                    "increment {inc}: {failure}; check for a mechanism or an unsupported part"
                ));
            }
            LinearFailure::BackEnd { .. } => {
                return Error::LinearBackEnd {
                    back_end: self.settings.solver.name().into(),
                    message: format!("increment {inc}: {failure}"),
                };
            }
            LinearFailure::NotConverged { .. } => {
                return Error::NoConvergence(format!(
                    "increment {inc}: {failure}; the penalty's conditioning is too poor for the iterative solver (lower the interface's penalty, use enforcement = \"augmented\", or solver = \"direct\")"
                ));
            }
        };
        let d = self.dofs.eq.iter().position(|&e| e == eq).unwrap_or(0);
        let (p, n) = self.dofs.locate(d / D::N);
        let c = d % D::N;
        Error::NotPositiveDefinite {
            increment: inc,
            part: self.parts[p].name.clone(),
            node: n,
            component: c,
            message: format!(
                "increment {inc}: the stiffness matrix is not positive definite (pivot at part '{}', node {n}, {} displacement); check for a mechanism or an unsupported part",
                self.parts[p].name,
                ["x", "y", "z"][c]
            ),
        }
    }
}

/// A back end built outside this library (the `cfe-petsc` crate): it depends
/// on `cfe`, `cfe` does not know it. Handed to an analysis
/// (`Analysis::set_back_end`), it is asked for the solver of each pattern of a
/// run whose `[analysis] solver` it offers ([`LinearBackend::is_external`]).
/// The dimension picks the method (a trait object cannot be generic over it).
pub trait ExternalBackEnd: Send + Sync {
    /// The back end `kind` analysed for a plane problem's pattern, and the
    /// record of its solves for summary.json (`None`: a direct solve, or not
    /// recorded).
    #[allow(clippy::type_complexity)]
    fn plane<'a>(
        &self,
        kind: LinearBackend,
        problem: Problem<'a, D2>,
    ) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)>;

    /// [`ExternalBackEnd::plane`] for a solid problem.
    #[allow(clippy::type_complexity)]
    fn solid<'a>(
        &self,
        kind: LinearBackend,
        problem: Problem<'a, D3>,
    ) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)>;
}

/// The linear back end `kind` analysed for `problem`'s pattern (the direct one
/// reading `stop` during that analysis), and, for an iterative one, the record
/// of its solves.
#[allow(clippy::type_complexity)]
fn linear_back_end<'a, D: ElementFamily>(
    kind: LinearBackend,
    problem: Problem<'a, D>,
    stop: Option<&'a AtomicUsize>,
) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
    let Problem {
        parts,
        interfaces,
        dofs,
    } = problem;
    Ok(match kind {
        LinearBackend::Direct => {
            let (k, chol) =
                crate::solve::setup::pattern_and_symbolic(parts, interfaces, dofs, stop)?;
            let system = ContactSystem::new(parts, k, chol);
            (Box::new(Cholesky::with_system(problem, system)), None)
        }
        kind @ (LinearBackend::Petsc | LinearBackend::PetscMumps) => {
            return Err(Error::LinearBackEnd {
                back_end: kind.name().into(),
                message: "this build of cfe has no PETSc back end: install PETSc (Debian: `apt-get install libpetsc-real-dev openmpi-bin libopenmpi-dev pkg-config`) and build the command line with `cargo build --release -p cfe-cli --features petsc`, or choose solver = \"direct\"".into(),
            });
        }
        LinearBackend::Cg => {
            let mut cg = ConjugateGradients::analyse(problem)?;
            cg.tolerance = CG_TOLERANCE;
            let solves = IterativeSolves {
                back_end: "cg".into(),
                preconditioner: "jacobi".into(),
                tolerance: CG_TOLERANCE,
                ..IterativeSolves::default()
            };
            (Box::new(cg), Some(solves))
        }
    })
}

/// The model's sizes the load and balance scales and the drift guard read.
fn model_scales<D: ElementFamily>(
    parts: &[Part<D>],
    pairs: &impl PairSet<Dim = D>,
    dofs: &DofMap<D>,
    total_load: f64,
) -> Scales {
    Scales {
        total_load,
        extent: parts
            .iter()
            .map(|p| crate::mesh::bounding_diagonal(&[&p.mesh]))
            .fold(0.0, f64::max),
        largest_prescribed: (0..pairs.interface_count())
            .flat_map(|i| (0..pairs.pair_count(i)).map(move |k| pairs.initial_gap(i, k).abs()))
            .fold(largest_off::<D>(&dofs.prescribed, &[]), f64::max),
        stiffest: parts
            .iter()
            .map(|p| p.material.young * p.material.thickness)
            .fold(0.0, f64::max),
        softest: parts
            .iter()
            .map(|p| p.material.young * p.material.thickness)
            .fold(f64::INFINITY, f64::min),
    }
}
