//! Analysis: one problem from model to results. Finds the coupling pairs, moves the
//! coupling nodes onto their host edges, numbers the DOFs ([`Analysis::new`]), and
//! solves in memory ([`Analysis::solve`], [`Analysis::solve_from`]): the
//! displacements, stresses, pair states and forces, reactions and summary.
//! Writing them to disk as the increments converge is [`Analysis::run`], in
//! the run loop (`crate::run`).
//!
//! This file is the orchestration; the interfaces are built by
//! `coupling::build`, the results read and the summary kept by [`crate::results`]
//! (through `post`), and `describe` writes the `cfe check` text.

use crate::assembly::{self, DofMap};
use crate::coupling::build::{self, InterfaceDim};
use crate::coupling::{Interface, Law, PairStates};
use crate::dim::{D2, D3};
use crate::domain::{LinearBackend, StartPattern};
use crate::error::{Error, Result};
use crate::fem::ElementFamily;
use crate::fem::recovery::PartStress;
use crate::model::{FromProblemFile, Model, Scheme};
use crate::results::memory::peak_memory_bytes;
pub use crate::results::summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, Reaction, RunClock, RunStatus,
    SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};
use crate::results::{PairRow, ResultsDim};
use crate::solve::backend::{LinearSolver, Problem};
use crate::solve::contact::ExternalBackEnd;
use crate::solve::nonlinear::{IncrementResult, IterativeSolves, LoadSteps, Solver};
use crate::solve::warm_start;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;
use std::time::Instant;

mod describe;
mod post;

/// Where the `active-set` iteration of the first increment starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// From the final pattern of the model on 4 × coarser meshes when the model is
    /// refined 4 × or more (as `cfe run` does), else all bonded.
    Coarse,
    /// Every pair bonded.
    AllBonded,
    /// These states (`states[i][k]` for pair k of interface i).
    States(PairStates),
}

/// The dimension of an analysis: what preparing, solving and reading a model
/// needs of it — its interfaces built (`InterfaceDim`), its results read
/// ([`ResultsDim`]), and the few things the analysis decides per dimension
/// (the advice about a model, the warm start from a coarser model).
/// [`D2`] (plane) and [`D3`] (solid).
pub trait AnalysisDim: InterfaceDim + ResultsDim {
    /// Advice about `model` that does not stop it from being solved
    /// (volumetric locking), noted in the summary at increment 0.
    fn notes(model: &Model<Self>) -> Vec<String>;

    /// The final pair states of the same problem on 4× coarser meshes
    /// ([`Analysis::coarse_states_until`]); `None` when there is none.
    fn coarse_states(analysis: &Analysis<Self>, stop: Option<&AtomicUsize>) -> Option<PairStates>;

    /// The back end `kind` of an [`ExternalBackEnd`] for `problem`: its method
    /// of this dimension.
    #[doc(hidden)]
    #[allow(clippy::type_complexity)]
    fn external<'a>(
        back_end: &dyn ExternalBackEnd,
        kind: LinearBackend,
        problem: Problem<'a, Self>,
    ) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)>;
}

/// Plane models: [`Model::warnings`]; a refined problem file's coarser level.
impl AnalysisDim for D2 {
    fn notes(model: &Model) -> Vec<String> {
        model.warnings()
    }

    fn coarse_states(analysis: &Analysis, stop: Option<&AtomicUsize>) -> Option<PairStates> {
        analysis.plane_coarse_states(stop)
    }

    fn external<'a>(
        back_end: &dyn ExternalBackEnd,
        kind: LinearBackend,
        problem: Problem<'a, D2>,
    ) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
        back_end.plane(kind, problem)
    }
}

/// Solid models: no coarser level for the warm start (`None`).
impl AnalysisDim for D3 {
    /// [`Model::<D3>::warnings`](Model::warnings): a part with ν ≥
    /// [`LOCKING_NU`](crate::model::LOCKING_NU), whose TET4 and fully integrated HEX8 elements lock.
    fn notes(model: &Model<D3>) -> Vec<String> {
        model.warnings()
    }

    fn coarse_states(_: &Analysis<D3>, _: Option<&AtomicUsize>) -> Option<PairStates> {
        None
    }

    fn external<'a>(
        back_end: &dyn ExternalBackEnd,
        kind: LinearBackend,
        problem: Problem<'a, D3>,
    ) -> Result<(Box<dyn LinearSolver<'a> + 'a>, Option<IterativeSolves>)> {
        back_end.solid(kind, problem)
    }
}

/// The results of a solved analysis at its last converged increment, in memory,
/// of dimension `D` (plane by default).
#[derive(Debug, Clone)]
pub struct Results<D: ElementFamily = D2> {
    /// The last converged increment: displacements `u` of all DOFs, pair states,
    /// internal and external forces, iterations.
    pub last: IncrementResult<D>,
    /// Stresses of every part (`D::Stress`: (xx, yy, xy) in 2D, the six in 3D).
    pub stresses: Vec<PartStress<D::Stress>>,
    /// One row per coupling pair: state, jumps and forces on the node part.
    pub pairs: Vec<PairRow>,
    /// The summary (as written to `summary.json` by [`Analysis::run`]).
    pub summary: Summary,
}

impl<D: ElementFamily> Results<D> {
    /// Displacements of all DOFs (component c of global node g at `D::N g + c`:
    /// x and y at 2g and 2g + 1 in 2D).
    pub fn displacements(&self) -> &[f64] {
        &self.last.u
    }

    /// The reactions, one per support, as in the summary.
    pub fn reactions(&self) -> &[Reaction] {
        &self.summary.reactions
    }
}

/// A model with its coupling pairs found and its DOFs numbered: ready to solve.
/// Of dimension `D` (plane by default; `Analysis<D3>` for a solid model).
pub struct Analysis<D: AnalysisDim = D2> {
    /// The model.
    pub model: Model<D>,
    /// Interfaces with their coupling elements.
    pub interfaces: Vec<Interface<D>>,
    /// DOF numbering.
    pub dofs: DofMap<D>,
    /// Phase timings so far.
    pub timings: Timings,
    /// The linear back end built outside this library that solves a run whose
    /// `[analysis] solver` names it ([`Analysis::set_back_end`]).
    external: Option<Arc<dyn ExternalBackEnd>>,
}

impl Analysis {
    /// Reads and meshes the problem file, then prepares the analysis.
    pub fn from_file(path: &Path, refine: usize) -> Result<Analysis> {
        let clock = RunClock::start();
        let model = Model::from_file(path, refine)?;
        let (meshing, meshing_cpu) = (clock.wall(), clock.cpu());
        let mut a = Analysis::new(model)?;
        a.timings.meshing = meshing;
        a.timings.setup_cpu = (|| Some(a.timings.setup_cpu? + meshing_cpu?))();
        Ok(a)
    }

    /// [`Analysis::coarse_states_until`] of a plane model: its problem file
    /// solved at a 4× coarser refinement.
    fn plane_coarse_states(&self, stop: Option<&AtomicUsize>) -> Option<PairStates> {
        let m = &self.model;
        let contact = self
            .interfaces
            .iter()
            .any(|i| i.law == crate::coupling::Law::Contact);
        // With loads in steps the first increment is not a fraction of the total
        // load the coarse problem would be solved at: no warm start.
        if m.refine < 4 || m.settings.scheme != Scheme::ActiveSet || !contact || m.steps.len() > 1 {
            return None;
        }
        let mut coarse = Analysis::new(m.with_refine(m.refine / 4).ok()?).ok()?;
        if coarse.interfaces.len() != self.interfaces.len() {
            return None;
        }
        // Same laws as this model (they may have been overridden after reading).
        for (c, i) in coarse.interfaces.iter_mut().zip(&self.interfaces) {
            c.law = i.law;
        }
        let start = coarse.coarse_states_until(stop);
        let problem = warm_start::Problem {
            parts: &coarse.model.parts,
            interfaces: &coarse.interfaces,
            dofs: &coarse.dofs,
            f_ext: assembly::external_force(&coarse.model.loads, &coarse.dofs),
            settings: &m.settings,
        };
        warm_start::states_from_coarse(problem, start, &self.interfaces, stop)
    }
}

/// [`Analysis::from_file`].
impl FromProblemFile for Analysis {
    fn from_file(path: &Path, refine: usize) -> Result<Analysis> {
        Analysis::from_file(path, refine)
    }
}

/// Reads and meshes a solid problem file (`Model::<D3>::from_file`), then
/// prepares the analysis.
impl FromProblemFile for Analysis<D3> {
    fn from_file(path: &Path, refine: usize) -> Result<Analysis<D3>> {
        let clock = RunClock::start();
        let model = Model::<D3>::from_file(path, refine)?;
        let (meshing, meshing_cpu) = (clock.wall(), clock.cpu());
        let mut a = Analysis::new(model)?;
        a.timings.meshing = meshing;
        a.timings.setup_cpu = (|| Some(a.timings.setup_cpu? + meshing_cpu?))();
        Ok(a)
    }
}

impl<D: AnalysisDim> Analysis<D> {
    /// Finds the coupling pairs of every interface, moves each coupling node onto
    /// its host edge (its projection there: a no-op for faces that already
    /// coincide, a small adjustment for a curved face meshed apart), and numbers
    /// the DOFs. Interfaces are taken in file order, each seeing the nodes the
    /// earlier ones moved.
    pub fn new(mut model: Model<D>) -> Result<Analysis<D>> {
        let clock = RunClock::start();
        // A model built or changed in code was not checked as a file is.
        model.check_names()?;
        let interfaces = build::interfaces(&model.interfaces, &mut model.parts, model.refine)?;
        let nodes: Vec<usize> = model.parts.iter().map(|p| p.mesh.nodes.len()).collect();
        let dofs = DofMap::numbered(&nodes, &model.supports);
        let timings = Timings {
            pair_search: clock.wall(),
            setup_cpu: clock.cpu(),
            ..Default::default()
        };
        Ok(Analysis {
            model,
            interfaces,
            dofs,
            timings,
            external: None,
        })
    }

    /// Has every solve whose `[analysis] solver` is a back end outside this
    /// library ([`crate::domain::LinearBackend::is_external`]: `petsc`,
    /// `petsc-mumps`) use `back_end` (e.g. `cfe_petsc::Petsc`). Without one
    /// such a solve is [`Error::LinearBackEnd`] saying how to build it in.
    #[cfg(feature = "internals")]
    pub fn set_back_end(&mut self, back_end: Arc<dyn ExternalBackEnd>) {
        self.external = Some(back_end);
    }

    /// Makes every interface follow `law` (e.g. to compare tied and contact runs of
    /// the same model).
    pub fn override_law(&mut self, law: Law) {
        let m = &mut self.model;
        build::set_law(&mut m.interfaces, &mut self.interfaces, &m.parts, law);
    }

    /// Makes every interface follow the Coulomb law with friction coefficient `mu`
    /// (e.g. a frictional variant of a model written for the seed's law). `mu` must
    /// be finite and ≥ 0 ([`Error::Model`] otherwise).
    pub fn override_friction(&mut self, mu: f64) -> Result<()> {
        let m = &mut self.model;
        build::set_friction(&mut m.interfaces, &mut self.interfaces, &m.parts, mu)
    }

    /// For a refined model solved by `active-set`: the final pair states of the same
    /// problem on meshes 4 × coarser (solved the same way, recursively), mapped to
    /// this model's pairs by position — a start close to the final pattern, so the
    /// iteration needs few, small state changes. `None` when no coarser level exists.
    pub fn coarse_states(&self) -> Option<PairStates> {
        self.coarse_states_until(None)
    }

    /// [`Analysis::coarse_states`] whose coarse solves read `stop` (if given) as
    /// [`Solver::new`] says: a stop ends them, with no start (`None`); the caller's
    /// own solver then sees the same flag.
    pub fn coarse_states_until(&self, stop: Option<&AtomicUsize>) -> Option<PairStates> {
        D::coarse_states(self, stop)
    }

    /// The incremental solver of this analysis: its parts, interfaces, DOFs, loads
    /// and settings (the pattern and the symbolic factorization are built here).
    pub fn solver(&self) -> Result<Solver<'_, D>> {
        self.solver_until(None)
    }

    /// [`Analysis::solver`] reading `stop` (if given) from the start of the
    /// symbolic analysis on ([`Solver::new`]): a nonzero value abandons it with
    /// [`Error::Interrupted`].
    pub fn solver_until<'s>(&'s self, stop: Option<&'s AtomicUsize>) -> Result<Solver<'s, D>> {
        let f = assembly::external_force(&self.model.loads, &self.dofs);
        let settings = &self.model.settings;
        let mut solver = match &self.external {
            // (No equation: `Solver::new` says so.)
            Some(back_end) if settings.solver.is_external() && self.dofs.n_eq > 0 => {
                let t = Instant::now();
                let problem = Problem {
                    parts: &self.model.parts,
                    interfaces: &self.interfaces,
                    dofs: &self.dofs,
                };
                let linear = D::external(back_end.as_ref(), settings.solver, problem)?;
                let seconds = t.elapsed().as_secs_f64();
                Solver::with_back_end(problem, f, settings, stop, linear, seconds)
            }
            _ => Solver::new(
                &self.model.parts,
                &self.interfaces,
                &self.dofs,
                f,
                settings,
                stop,
            )?,
        };
        if let Some(steps) = self.load_steps() {
            solver.set_steps(steps);
        }
        Self::check_memory(&solver, crate::results::memory::available_memory_bytes())?;
        Ok(solver)
    }

    /// Refuses a solve whose estimated peak memory
    /// ([`crate::results::memory::estimated_peak_from_factor`], from the factor's
    /// nonzeros the symbolic factorization counted) exceeds `available` bytes
    /// (the machine's `MemAvailable`; `None`: unknown, no check). Called before
    /// the numeric factorization, so a run that cannot fit stops at once with
    /// [`Error::TooLarge`] instead of being killed midway.
    pub fn check_memory(solver: &Solver<'_, D>, available: Option<u64>) -> Result<()> {
        let Some(available) = available else {
            return Ok(());
        };
        let unknowns = solver.dofs_count() as u64;
        let bytes = crate::results::memory::estimated_peak_from_factor(
            unknowns,
            solver.matrix_nnz() as u64,
            solver.factor_nnz() as u64,
            solver.keeps_factor_between_increments(),
        );
        if bytes <= available {
            return Ok(());
        }
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        Err(Error::TooLarge {
            unknowns,
            bytes,
            available,
            message: format!(
                "{unknowns} unknowns with a Cholesky factor of {} nonzeros need about {:.2} GiB at the peak, but {:.2} GiB of memory are available; use a smaller refinement or fewer cells (the peak grows a little faster than the unknowns), or free memory",
                solver.factor_nnz(),
                gib(bytes),
                gib(available)
            ),
        })
    }

    /// The loads of a model with several `[[step]]`s (or one whose step sets
    /// factors), grouped by amplitude (`None` for one plain step: the solver's
    /// default ramp). Every load and support's prescribed values belong to the
    /// group of the loadings with the same step and the same factors at every
    /// step's end ([`crate::domain::Step::targets`]): without `scale` or factors
    /// one group per step, in step order; each support's DOFs are held in every
    /// step.
    pub fn load_steps(&self) -> Option<LoadSteps> {
        use crate::domain::{Loading, Step};
        let steps = &self.model.steps;
        let amplitudes = steps.iter().any(|s| {
            s.scale.is_some() || !s.load_factors.is_empty() || !s.support_factors.is_empty()
        });
        if steps.len() < 2 && !amplitudes {
            return None;
        }
        // One group per step (its own loadings, unmodified), then any others.
        let mut keys: Vec<(usize, Vec<f64>)> = (0..steps.len())
            .map(|s| (s, Step::targets(steps, s, Loading::Load(usize::MAX))))
            .collect();
        let mut group = |first: usize, which: Loading| {
            let key = (first, Step::targets(steps, first, which));
            match keys.iter().position(|k| *k == key) {
                Some(g) => g,
                None => {
                    keys.push(key);
                    keys.len() - 1
                }
            }
        };
        let last = steps.len() - 1;
        let load_group: Vec<usize> = (self.model.loads.iter().enumerate())
            .map(|(i, l)| group(l.step.min(last), Loading::Load(i)))
            .collect();
        let support_group: Vec<usize> = (self.model.supports.iter().enumerate())
            .map(|(k, s)| group(s.step.min(last), Loading::Support(k)))
            .collect();
        // Groups in step order (a step's unmodified group first).
        let mut order: Vec<usize> = (0..keys.len()).collect();
        order.sort_by_key(|&g| keys[g].0);
        let mut rank = vec![0; keys.len()];
        for (r, &g) in order.iter().enumerate() {
            rank[g] = r;
        }
        let forces = order
            .iter()
            .map(|&g| {
                let loads: Vec<crate::domain::Load<D>> = (self.model.loads.iter().zip(&load_group))
                    .filter(|(_, lg)| **lg == g)
                    .map(|(l, _)| l.clone())
                    .collect();
                assembly::external_force(&loads, &self.dofs)
            })
            .collect();
        let mut prescribed = vec![vec![0.0; self.dofs.prescribed.len()]; keys.len()];
        for &(d, k) in &self.dofs.fixed {
            prescribed[rank[support_group[k]]][d] = self.dofs.prescribed[d];
        }
        let ramps: Vec<Vec<f64>> = order
            .iter()
            .map(|&g| Step::ramp(steps, &keys[g].1))
            .collect();
        let labels = Step::labels(steps);
        let increments = (labels.iter().enumerate())
            .map(|(k, &(s, _))| (s, ramps.iter().map(|r| r[k]).collect()))
            .collect();
        Some(LoadSteps {
            forces,
            prescribed,
            increments,
            progress: labels.iter().map(|&(_, l)| l).collect(),
        })
    }

    /// Why the proportional-load shortcuts are off (`None` when they are on):
    /// an interface whose answer is not proportional to the load or depends on
    /// its path, loads applied in more than one step or with different
    /// factors, or a load reversed (a negative factor).
    pub fn shortcut_off_reason(&self) -> Option<String> {
        let mut why = Vec::new();
        if self
            .interfaces
            .iter()
            .any(crate::coupling::Interface::non_proportional)
        {
            why.push("initial gaps, friction or augmented Lagrangian".to_string());
        }
        let loaded = self.model.loaded_steps();
        let steps = self.load_steps();
        let groups = steps.as_ref().map_or(Vec::new(), LoadSteps::loaded);
        if self.model.steps.len() > 1 && loaded.len() > 1 {
            why.push(format!(
                "loads in {} steps: the loading is not proportional",
                loaded.len()
            ));
        } else if groups.len() > 1 {
            why.push(
                "loads with different factors in the steps: the loading is not proportional".into(),
            );
        }
        if let Some(steps) = &steps
            && groups.iter().any(|&g| steps.reversed(g))
        {
            why.push("a load or prescribed value reversed (a negative factor): contact states do not carry over to the reversed load".into());
        }
        (!why.is_empty()).then(|| why.join("; "))
    }

    /// Solves every increment in memory, as `cfe run` does (the contact iteration
    /// starts as `[analysis] start` says); `on_increment` receives each converged
    /// increment. Returns the last one.
    pub fn solve_with(
        &self,
        on_increment: impl FnMut(&IncrementResult<D>) -> Result<()>,
    ) -> Result<IncrementResult<D>> {
        self.solve_from(self.configured_start(), on_increment)
    }

    /// The start `[analysis] start` names.
    pub fn configured_start(&self) -> Start {
        match self.model.settings.start {
            StartPattern::Bonded => Start::AllBonded,
            StartPattern::Coarse => Start::Coarse,
        }
    }

    /// Solves every increment in memory with the contact iteration starting as
    /// `start` says; `on_increment` receives each converged increment. Returns the
    /// last one.
    pub fn solve_from(
        &self,
        start: Start,
        on_increment: impl FnMut(&IncrementResult<D>) -> Result<()>,
    ) -> Result<IncrementResult<D>> {
        let mut solver = self.solver()?;
        let initial = match start {
            Start::Coarse => self.coarse_states(),
            Start::AllBonded => None,
            Start::States(s) => Some(s),
        };
        if let Some(states) = initial {
            solver.set_initial_states(states);
        }
        solver.run(on_increment)
    }

    /// Solves the problem in memory, writing nothing: the displacements, stresses,
    /// pair states and forces, reactions and summary of the last increment.
    pub fn solve(&self) -> Result<Results<D>> {
        self.solve_observed(|_| Ok(()))
    }

    /// As [`Analysis::solve`], handing each converged increment to `on_increment`
    /// (e.g. to show progress); an error it returns stops the solve and is returned.
    pub fn solve_observed(
        &self,
        on_increment: impl FnMut(&IncrementResult<D>) -> Result<()>,
    ) -> Result<Results<D>> {
        self.solve_observed_until(on_increment, &AtomicUsize::new(0))
    }

    /// [`Analysis::solve_observed`] that the solver abandons with
    /// [`Error::Interrupted`] inside an increment once `stop` is nonzero (e.g.
    /// set by a signal handler; see [`Solver::set_stop`]).
    pub fn solve_observed_until(
        &self,
        mut on_increment: impl FnMut(&IncrementResult<D>) -> Result<()>,
        stop: &AtomicUsize,
    ) -> Result<Results<D>> {
        let clock = RunClock::start();
        let mut summary = self.empty_summary();
        let t = Instant::now();
        let mut solver = self.solver_until(Some(stop))?;
        if self.model.settings.start == StartPattern::Coarse
            && let Some(states) = self.coarse_states_until(Some(stop))
        {
            solver.set_initial_states(states);
        }
        summary.timings.coarse_start = t.elapsed().as_secs_f64();
        summary.matrix_nonzeros = solver.matrix_nnz();
        summary.factor_nonzeros = solver.factor_nnz();
        let last = solver.run(|inc| {
            let rows = self.pair_rows(inc);
            self.fill_summary(&mut summary, inc, &rows);
            on_increment(inc)
        })?;
        summary.timings.solve = solver.timings.clone();
        (summary.factorizations, summary.low_rank_updates) = solver.solve_counts();
        summary.first_factorization_seconds = solver.first_factorization_seconds();
        let t = Instant::now();
        let stresses = self.recover(&last.u);
        summary.timings.stress_recovery = t.elapsed().as_secs_f64();
        summary.status = summary.final_status();
        summary.timings.set_totals(&self.timings, &clock);
        summary.peak_memory_bytes = peak_memory_bytes();
        summary.solve_flops = solver.solve_flops();
        summary.linear_solver = solver.iterative_solves().cloned();
        summary.set_ratios();
        Ok(Results {
            pairs: self.pair_rows(&last),
            stresses,
            summary,
            last,
        })
    }
}
