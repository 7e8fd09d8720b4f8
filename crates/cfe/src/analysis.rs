//! Analysis: one problem from model to results. Finds the coupling pairs, moves the
//! coupling nodes onto their host edges, numbers the DOFs ([`Analysis::new`]), and
//! solves in memory ([`Analysis::solve`], [`Analysis::solve_from`]): the
//! displacements, stresses, pair states and forces, reactions and summary.
//! Writing them to disk as the increments converge is [`Analysis::run`], in
//! `output::run`.

use crate::assembly::{self, DofMap};
use crate::coupling::{
    Coupling, Interface, Law, PairState, PairStates, ViolationKind, search, segment,
};
use crate::domain::{InterfaceDef, Part, StartPattern};
use crate::error::{Error, Result};
use crate::fem::recovery::{self, PartStress};
use crate::model::{Model, Scheme};
use crate::output::memory::peak_memory_bytes;
use crate::output::report::PairRow;
pub use crate::output::summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, Reaction, RunClock, RunStatus,
    SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};
use crate::solve::nonlinear::{IncrementResult, LoadSteps, RESIDUAL_WARN, Solver};
use crate::solve::warm_start;
use std::path::Path;
use std::sync::atomic::AtomicUsize;
use std::time::Instant;

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

/// The results of a solved analysis at its last converged increment, in memory.
#[derive(Debug, Clone)]
pub struct Results {
    /// The last converged increment: displacements `u` of all DOFs, pair states,
    /// internal and external forces, iterations.
    pub last: IncrementResult,
    /// Stresses of every part.
    pub stresses: Vec<PartStress>,
    /// One row per coupling pair: state, jumps and forces on the node part.
    pub pairs: Vec<PairRow>,
    /// The summary (as written to `summary.json` by [`Analysis::run`]).
    pub summary: Summary,
}

impl Results {
    /// Displacements of all DOFs (x and y of global node g at 2g and 2g + 1).
    pub fn displacements(&self) -> &[f64] {
        &self.last.u
    }

    /// The reactions, one per support, as in the summary.
    pub fn reactions(&self) -> &[Reaction] {
        &self.summary.reactions
    }
}

/// A model with its coupling pairs found and its DOFs numbered: ready to solve.
pub struct Analysis {
    /// The model.
    pub model: Model,
    /// Interfaces with their coupling elements.
    pub interfaces: Vec<Interface>,
    /// DOF numbering.
    pub dofs: DofMap,
    /// Phase timings so far.
    pub timings: Timings,
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

    /// Finds the coupling pairs of every interface, moves each coupling node onto
    /// its host edge (its projection there: a no-op for faces that already
    /// coincide, a small adjustment for a curved face meshed apart), and numbers
    /// the DOFs. Interfaces are taken in file order, each seeing the nodes the
    /// earlier ones moved.
    pub fn new(mut model: Model) -> Result<Analysis> {
        let clock = RunClock::start();
        // A model built or changed in code was not checked as a file is.
        model.check_names()?;
        let mut interfaces = Vec::with_capacity(model.interfaces.len());
        for def in &model.interfaces {
            let host = &model.parts[def.host];
            let node_part = &model.parts[def.node_part];
            // The tolerance is a fraction of the host's edges as meshed in the
            // problem file: `--refine K` subdivides edges K times but leaves the gap
            // between two faces meshed apart (a Gmsh part keeps its polygons) as it is.
            // The segment coupling within a search distance moves no node and
            // finds its own host edges, point by point along the face.
            let segment_gaps = def.coupling == Coupling::Segment && def.search_distance > 0.0;
            let (mut elements, mut unpaired) = if segment_gaps {
                (Vec::new(), 0)
            } else {
                search::find_pairs_within(
                    &def.name,
                    &host.mesh,
                    &node_part.mesh,
                    &def.nodes,
                    def.tolerance * model.refine as f64,
                    def.search_distance,
                )?
            };
            // Within a search distance the nodes stay where they are (their gaps
            // are kept): nothing is moved.
            let max_projection_distance = if def.search_distance > 0.0 {
                0.0
            } else {
                elements.iter().map(|c| c.distance).fold(0.0, f64::max)
            };
            if max_projection_distance > 0.0 {
                let part = &mut model.parts[def.node_part];
                for c in &elements {
                    part.mesh.nodes[c.node] = c.position;
                }
                let moved: Vec<usize> = elements.iter().map(|c| c.node).collect();
                part.mesh
                    .validate_around(&part.name, &moved)
                    .map_err(|e| Error::Coupling {
                    interface: def.name.clone(),
                    message: format!(
                        "moving the coupling nodes onto the host edges (by up to {max_projection_distance:e}) spoils the node part's mesh: {e}; lower `tolerance` or mesh the faces closer together"
                    ),
                })?;
            }
            if def.coupling == Coupling::Segment {
                // The nodes now lie on the host boundary (or, within a search
                // distance, stay where they are): integrate over their face
                // segments.
                let (segment_elements, segment_unpaired) = segment::segment_elements_within(
                    &def.name,
                    &model.parts[def.host].mesh,
                    &model.parts[def.node_part].mesh,
                    &def.boundary,
                    &def.nodes,
                    def.tolerance * model.refine as f64,
                    def.search_distance,
                )?;
                elements = segment_elements;
                if segment_gaps {
                    unpaired = segment_unpaired;
                }
            }
            if elements.is_empty() && !def.nodes.is_empty() && def.search_distance > 0.0 {
                return Err(no_pairs(
                    def,
                    &model.parts[def.host],
                    &model.parts[def.node_part],
                ));
            }
            let c_slip =
                slip_stiffness(def.law, &model.parts[def.host], &model.parts[def.node_part]);
            interfaces.push(Interface {
                name: def.name.clone(),
                host: def.host,
                node_part: def.node_part,
                law: def.law,
                c_n: def.c_n,
                c_s: def.c_s,
                c_slip,
                elements,
                max_projection_distance,
                friction: def.friction,
                enforcement: def.enforcement,
                penetration_tolerance: def.penetration_tolerance,
                unpaired,
                coupling: def.coupling,
            });
        }
        let dofs = DofMap::new(&model.parts, &model.supports);
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
        })
    }

    /// Makes every interface follow `law` (e.g. to compare tied and contact runs of
    /// the same model).
    pub fn override_law(&mut self, law: crate::coupling::Law) {
        for def in &mut self.model.interfaces {
            def.law = law;
        }
        for iface in &mut self.interfaces {
            iface.law = law;
            let parts = &self.model.parts;
            iface.c_slip = slip_stiffness(law, &parts[iface.host], &parts[iface.node_part]);
        }
    }

    /// Makes every interface follow the Coulomb law with friction coefficient `mu`
    /// (e.g. a frictional variant of a model written for the seed's law). `mu` must
    /// be finite and ≥ 0 ([`Error::Model`] otherwise).
    pub fn override_friction(&mut self, mu: f64) -> Result<()> {
        if !(mu.is_finite() && mu >= 0.0) {
            return Err(Error::Model(format!(
                "the friction coefficient must be finite and ≥ 0, not {mu}"
            )));
        }
        self.override_law(Law::Coulomb);
        for def in &mut self.model.interfaces {
            def.friction = mu;
        }
        for iface in &mut self.interfaces {
            iface.friction = mu;
        }
        Ok(())
    }

    /// A human-readable description of the prepared model (for `cfe check`).
    pub fn describe(&self) -> String {
        use crate::output::fmt::{num, num_rel};
        // The model's size: lengths below 1e-10 of it are round-off, shown as 0.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in self.model.parts.iter().flat_map(|p| &p.mesh.nodes) {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0);
        let load: f64 = self
            .model
            .loads
            .iter()
            .map(|l| l.resultant[0].hypot(l.resultant[1]))
            .fold(0.0, f64::max);
        let mut s = format!(
            "{} ({})\n  unknowns: {}\n",
            self.model.title,
            self.model.source.display(),
            self.dofs.n_eq
        );
        for p in &self.model.parts {
            s += &format!(
                "  part '{}': {} nodes, {} elements, E = {}, nu = {}, t = {}\n",
                p.name,
                p.mesh.nodes.len(),
                p.mesh.describe_elements(),
                num(p.material.young),
                num(p.material.poisson),
                num(p.material.thickness)
            );
        }
        for i in &self.interfaces {
            s += &format!(
                "  interface '{}': host '{}', nodes '{}', law {}, {} pairs, c_n = {}, c_s = {}, max projection distance {}\n",
                i.name,
                self.model.parts[i.host].name,
                self.model.parts[i.node_part].name,
                i.law.as_str(),
                i.elements.len(),
                num(i.c_n),
                num(i.c_s),
                num_rel(i.max_projection_distance, size)
            );
            if i.coupling == Coupling::Segment {
                s += "    segment coupling: each pair's gap is averaged over its node's face segments\n";
            }
            // The contact extensions, only when used (the seed's lines unchanged).
            let gaps = i.elements.iter().any(|c| c.gap0 != 0.0);
            if i.law == Law::Coulomb
                || i.enforcement == crate::coupling::Enforcement::Augmented
                || gaps
                || i.unpaired > 0
            {
                let (lo, hi) = i
                    .elements
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                        (a.min(c.gap0), b.max(c.gap0))
                    });
                s += &format!(
                    "    friction {}, enforcement {}, initial gaps from {} to {}, {} node(s) unpaired (beyond the search distance)\n",
                    num(i.friction),
                    i.enforcement.as_str(),
                    num_rel(if lo.is_finite() { lo } else { 0.0 }, size),
                    num_rel(if hi.is_finite() { hi } else { 0.0 }, size),
                    i.unpaired
                );
            }
        }
        for sup in &self.model.supports {
            s += &format!(
                "  support '{}': {} nodes, fix x: {}, fix y: {}\n",
                sup.name,
                sup.nodes.len(),
                sup.fix[0],
                sup.fix[1]
            );
        }
        let steps = self.model.steps.len() > 1;
        for l in &self.model.loads {
            s += &format!(
                "  load '{}': resultant ({}, {}) on {} nodal forces{}\n",
                l.name,
                num_rel(l.resultant[0], load),
                num_rel(l.resultant[1], load),
                l.nodal.len(),
                if steps {
                    format!(", step '{}'", self.step_name(l.step))
                } else {
                    String::new()
                }
            );
        }
        if steps {
            for (k, st) in self.model.steps.iter().enumerate() {
                s += &format!(
                    "  step {} '{}': {} increments\n",
                    k + 1,
                    st.name,
                    st.increments
                );
            }
        }
        for w in self.model.warnings() {
            s += &format!("  warning: {w}\n");
        }
        s
    }

    /// For a refined model solved by `active-set`: the final pair states of the same
    /// problem on meshes 4 × coarser (solved the same way, recursively), mapped to
    /// this model's pairs by position — a start close to the final pattern, so the
    /// iteration needs few, small state changes. `None` when no coarser level exists.
    pub fn coarse_states(&self) -> Option<PairStates> {
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
        let start = coarse.coarse_states();
        let problem = warm_start::Problem {
            parts: &coarse.model.parts,
            interfaces: &coarse.interfaces,
            dofs: &coarse.dofs,
            f_ext: assembly::external_force(&coarse.model.loads, &coarse.dofs),
            settings: &m.settings,
        };
        warm_start::states_from_coarse(problem, start, &self.interfaces)
    }

    /// The incremental solver of this analysis: its parts, interfaces, DOFs, loads
    /// and settings (the pattern and the symbolic factorization are built here).
    pub fn solver(&self) -> Result<Solver<'_>> {
        self.solver_until(None)
    }

    /// [`Analysis::solver`] reading `stop` (if given) from the start of the
    /// symbolic analysis on ([`Solver::new`]): a nonzero value abandons it with
    /// [`Error::Interrupted`].
    pub fn solver_until<'s>(&'s self, stop: Option<&'s AtomicUsize>) -> Result<Solver<'s>> {
        let f = assembly::external_force(&self.model.loads, &self.dofs);
        let mut solver = Solver::new(
            &self.model.parts,
            &self.interfaces,
            &self.dofs,
            f,
            &self.model.settings,
            stop,
        )?;
        if let Some(steps) = self.load_steps() {
            solver.set_steps(steps);
        }
        Self::check_memory(&solver, crate::output::memory::available_memory_bytes())?;
        Ok(solver)
    }

    /// Refuses a solve whose estimated peak memory
    /// ([`crate::output::memory::estimated_peak_from_factor`], from the factor's
    /// nonzeros the symbolic factorization counted) exceeds `available` bytes
    /// (the machine's `MemAvailable`; `None`: unknown, no check). Called before
    /// the numeric factorization, so a run that cannot fit stops at once with
    /// [`Error::TooLarge`] instead of being killed midway.
    pub fn check_memory(solver: &Solver<'_>, available: Option<u64>) -> Result<()> {
        let Some(available) = available else {
            return Ok(());
        };
        let unknowns = solver.dofs_count() as u64;
        let bytes = crate::output::memory::estimated_peak_from_factor(
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

    /// The loads of a model with several `[[step]]`s, step by step (`None` for one
    /// step: the solver's default ramp). Each support's prescribed values belong to
    /// its step; its DOFs are held in every step.
    pub fn load_steps(&self) -> Option<LoadSteps> {
        let steps = &self.model.steps;
        if steps.len() < 2 {
            return None;
        }
        let forces = (0..steps.len())
            .map(|s| {
                let loads: Vec<crate::domain::Load> = self
                    .model
                    .loads
                    .iter()
                    .filter(|l| l.step == s)
                    .cloned()
                    .collect();
                assembly::external_force(&loads, &self.dofs)
            })
            .collect();
        let mut prescribed = vec![vec![0.0; self.dofs.prescribed.len()]; steps.len()];
        for &(d, k) in &self.dofs.fixed {
            let s = self.model.supports[k].step.min(steps.len() - 1);
            prescribed[s][d] = self.dofs.prescribed[d];
        }
        Some(LoadSteps {
            forces,
            prescribed,
            increments: crate::domain::Step::factors(steps),
        })
    }

    /// Why the proportional-load shortcuts are off (`None` when they are on):
    /// an interface whose answer is not proportional to the load or depends on
    /// its path, or loads applied in more than one step.
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
        if self.model.steps.len() > 1 && loaded.len() > 1 {
            why.push(format!(
                "loads in {} steps: the loading is not proportional",
                loaded.len()
            ));
        }
        (!why.is_empty()).then(|| why.join("; "))
    }

    /// Solves every increment in memory, as `cfe run` does (the contact iteration
    /// starts as `[analysis] start` says); `on_increment` receives each converged
    /// increment. Returns the last one.
    pub fn solve_with(
        &self,
        on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<IncrementResult> {
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
        on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<IncrementResult> {
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
    pub fn solve(&self) -> Result<Results> {
        self.solve_observed(|_| Ok(()))
    }

    /// As [`Analysis::solve`], handing each converged increment to `on_increment`
    /// (e.g. to show progress); an error it returns stops the solve and is returned.
    pub fn solve_observed(
        &self,
        on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<Results> {
        self.solve_observed_until(on_increment, &AtomicUsize::new(0))
    }

    /// [`Analysis::solve_observed`] that the solver abandons with
    /// [`Error::Interrupted`] inside an increment once `stop` is nonzero (e.g.
    /// set by a signal handler; see [`Solver::set_stop`]).
    pub fn solve_observed_until(
        &self,
        mut on_increment: impl FnMut(&IncrementResult) -> Result<()>,
        stop: &AtomicUsize,
    ) -> Result<Results> {
        let clock = RunClock::start();
        let mut summary = self.empty_summary();
        let t = Instant::now();
        let mut solver = self.solver_until(Some(stop))?;
        if self.model.settings.start == StartPattern::Coarse
            && let Some(states) = self.coarse_states()
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
        summary.set_ratios();
        Ok(Results {
            pairs: self.pair_rows(&last),
            stresses,
            summary,
            last,
        })
    }

    /// The warnings about the model as meshed (increment 0): each curved
    /// boundary of a part refined from a given mesh, whose polygon `--refine`
    /// kept.
    fn kept_polygon_warnings(&self) -> Vec<Warning> {
        self.model
            .kept_polygons
            .iter()
            .map(|(part, b)| Warning {
                increment: 0,
                message: format!(
                    "part '{part}', boundary '{}': a curved boundary (its consecutive edges turn by up to {:.3}°) refined by --refine {}: the new nodes lie on the given mesh's straight edges, so the geometry stays its polygon, not the curve (a contact pressure there alternates between the new mid-edge nodes and the given ones); mesh the curve finer in the mesh generator instead",
                    b.name,
                    b.largest_turn.to_degrees(),
                    self.model.refine
                ),
            })
            .collect()
    }

    pub(crate) fn empty_summary(&self) -> Summary {
        Summary {
            status: RunStatus::Running,
            error: None,
            warnings: self.kept_polygon_warnings(),
            violations: Vec::new(),
            max_violation: 0.0,
            tolerances: Tolerances {
                tension: self.model.settings.force_tolerance,
                penetration: self.model.settings.gap_tolerance,
                max_violation: self.model.settings.max_violation,
                residual_warn: RESIDUAL_WARN,
                residual_fail: self.model.settings.max_residual,
            },
            title: self.model.title.clone(),
            problem: self.model.source.clone(),
            refine: self.model.refine,
            scheme: self.model.settings.scheme,
            unknowns: self.dofs.n_eq,
            matrix_nonzeros: 0,
            factor_nonzeros: 0,
            parts: self
                .model
                .parts
                .iter()
                .map(|p| {
                    let (t3, q4) = p.mesh.counts();
                    PartSummary {
                        name: p.name.clone(),
                        nodes: p.mesh.nodes.len(),
                        elements: t3 + q4,
                        t3,
                        q4,
                    }
                })
                .collect(),
            interfaces: Vec::new(),
            increments: self.model.settings.increments,
            converged_increments: 0,
            iterations: Vec::new(),
            iteration_history: Vec::new(),
            factorizations: 0,
            low_rank_updates: 0,
            first_factorization_seconds: None,
            max_displacement: MaxDisplacement::default(),
            reactions: Vec::new(),
            applied: [0.0; 2],
            equilibrium_error: 0.0,
            residual: 0.0,
            proportional_shortcut: self.shortcut_off_reason().is_none(),
            proportional_shortcut_off: self.shortcut_off_reason(),
            steps: self
                .model
                .steps()
                .into_iter()
                .map(|s| StepSummary {
                    name: s.name,
                    increments: s.increments,
                })
                .collect(),
            increment_steps: Vec::new(),
            fixed_point_iterations: Vec::new(),
            augmented_penetration: 0.0,
            // Advice about the model as a whole (volumetric locking) is noted
            // at increment 0, before any increment.
            notes: self
                .model
                .warnings()
                .into_iter()
                .map(|message| Warning {
                    increment: 0,
                    message,
                })
                .collect(),
            peak_memory_bytes: None,
            peak_over_factor: None,
            solve_flops: 0.0,
            total_over_factorization: None,
            threads: rayon::current_num_threads(),
            timings: Timings {
                meshing: self.timings.meshing,
                pair_search: self.timings.pair_search,
                setup_cpu: self.timings.setup_cpu,
                ..Default::default()
            },
        }
    }

    /// The reaction (x, y) of each support, in the order of `model.supports`: the
    /// out-of-balance force F_int − F_ext summed over the DOFs it fixes.
    pub fn reactions(&self, inc: &IncrementResult) -> Vec<[f64; 2]> {
        // `inc.f_ext` is already at the increment's load factor.
        self.dofs
            .reactions(self.model.supports.len(), &inc.f_int, &inc.f_ext, 1.0)
    }

    /// The name of step `step` (0-based) of the model.
    pub fn step_name(&self, step: usize) -> String {
        match self.model.steps.get(step) {
            Some(s) => s.name.clone(),
            None => crate::model::DEFAULT_STEP.into(),
        }
    }

    /// Stresses of every part for displacements `u` (all DOFs).
    pub fn recover(&self, u: &[f64]) -> Vec<PartStress> {
        self.model
            .parts
            .iter()
            .enumerate()
            .map(|(p, part)| {
                let s = 2 * self.dofs.node_offset[p];
                recovery::recover(
                    &part.mesh,
                    &part.material,
                    &u[s..s + 2 * part.mesh.nodes.len()],
                )
            })
            .collect()
    }

    /// One row per coupling pair: state, jumps and forces on the node part.
    pub fn pair_rows(&self, inc: &IncrementResult) -> Vec<PairRow> {
        let mut rows = Vec::new();
        let step = self.step_name(inc.step);
        let mut violations = inc.violations.iter().peekable();
        for (i, iface) in self.interfaces.iter().enumerate() {
            for (k, c) in iface.elements.iter().enumerate() {
                let state = inc.states[i][k];
                // Violations are sorted by interface and pair, like the rows.
                let violation = violations.next_if(|v| (v.interface, v.pair) == (i, k));
                let h = inc
                    .pair_history
                    .get(i)
                    .and_then(|h| h.get(k))
                    .copied()
                    .unwrap_or_default();
                let p = iface.pair_at(k, &self.dofs, &inc.u, state, &h);
                let (f, jump) = (p.force, p.jump);
                // The slip not carried by the tangential spring: the plastic slip of
                // a closed pair with friction, the whole tangential jump when
                // nothing holds it (open, or frictionless).
                let slip = if state.is_closed() && iface.law != Law::Frictionless {
                    h.slip
                } else {
                    jump[1]
                };
                let thickness = self.model.parts[iface.node_part].material.thickness;
                rows.push(PairRow {
                    interface: iface.name.clone(),
                    node: c.node,
                    x: c.position[0],
                    y: c.position[1],
                    host_element: c.host_element,
                    state,
                    gap_n: jump[0],
                    slip_s: jump[1],
                    // Force on the node part is −f; `+ 0.0` turns −0 into 0 for open pairs.
                    force_n: -f[0] + 0.0,
                    force_s: -f[1] + 0.0,
                    settled: inc.settled.binary_search(&(i, k)).is_ok(),
                    violation: violation.map(|v| v.kind),
                    violation_amount: violation.map_or(0.0, |v| v.amount),
                    gap0: c.gap0,
                    gap: p.gap,
                    slip,
                    pressure: c.traction(-f[0] + 0.0, thickness),
                    shear: c.traction(-f[1] + 0.0, thickness),
                    tributary: c.tributary,
                    segment: c.segment.as_ref().map(|s| {
                        s.nodes
                            .iter()
                            .map(|n| n.to_string())
                            .collect::<Vec<_>>()
                            .join("-")
                    }),
                    increment: inc.index,
                    step: step.clone(),
                    load_factor: inc.lambda,
                });
            }
        }
        rows
    }

    pub(crate) fn fill_summary(&self, s: &mut Summary, inc: &IncrementResult, rows: &[PairRow]) {
        s.converged_increments = inc.index;
        s.increment_steps.push(IncrementStep {
            increment: inc.index,
            step: self.step_name(inc.step),
            load_factor: inc.lambda,
            time: inc.time,
        });
        self.record_violations(s, inc);
        s.iterations.push(inc.iterations);
        s.iteration_history.push(inc.history.clone());
        s.residual = inc.residual;
        s.interfaces = self
            .interfaces
            .iter()
            .map(|iface| {
                let mine: Vec<&PairRow> =
                    rows.iter().filter(|r| r.interface == iface.name).collect();
                let bonded = mine.iter().filter(|r| r.state == PairState::Bonded).count();
                InterfaceSummary {
                    name: iface.name.clone(),
                    host: self.model.parts[iface.host].name.clone(),
                    node_part: self.model.parts[iface.node_part].name.clone(),
                    law: iface.law,
                    coupling: iface.coupling,
                    c_n: iface.c_n,
                    c_s: iface.c_s,
                    pairs: mine.len(),
                    bonded,
                    open: mine.iter().filter(|r| r.state == PairState::Open).count(),
                    settled: mine
                        .iter()
                        .filter(|r| r.settled)
                        .map(|r| SettledPair {
                            node: r.node,
                            x: r.x,
                            y: r.y,
                            state: r.state,
                            force_n: r.force_n,
                        })
                        .collect(),
                    violations: mine.iter().filter(|r| r.violation.is_some()).count(),
                    max_penetration: mine.iter().map(|r| -r.gap).fold(0.0, f64::max),
                    total_force_n: mine.iter().map(|r| r.force_n).sum(),
                    max_projection_distance: iface.max_projection_distance,
                    bonded_extent: bonded_extent(&mine),
                    friction: iface.friction,
                    enforcement: iface.enforcement,
                    slip: mine.iter().filter(|r| r.state == PairState::Slip).count(),
                    unpaired: iface.unpaired,
                    max_pressure: mine.iter().map(|r| r.pressure).fold(0.0, f64::max),
                    max_shear: mine.iter().map(|r| r.shear.abs()).fold(0.0, f64::max),
                    contact_extent: contact_extent(&mine),
                    contact_length: contact_extent(&mine)
                        .map_or(0.0, |[a, b]| (b[0] - a[0]).hypot(b[1] - a[1])),
                    max_slip_ratio: iface
                        .elements
                        .iter()
                        .zip(rows.iter().filter(|r| r.interface == iface.name))
                        .map(|(c, r)| r.slip_s.abs() / c.edge_length.max(f64::MIN_POSITIVE))
                        .fold(0.0, f64::max),
                }
            })
            .collect();
        s.fixed_point_iterations.push(inc.fixed_point_iterations);
        s.augmented_penetration = inc.augmented_error;
        for i in &s.interfaces {
            let noted = s
                .notes
                .iter()
                .any(|n| n.message.contains(&format!("'{}'", i.name)));
            if i.max_slip_ratio > 0.5 && i.law != Law::Rigid && !noted {
                s.notes.push(Warning {
                    increment: inc.index,
                    message: format!(
                        "interface '{}': a pair's tangential jump reaches {:.2} × its host edge's length; the pairs and normals are fixed in the reference configuration (geometrically linear), which assumes sliding small against a host edge",
                        i.name, i.max_slip_ratio
                    ),
                });
            }
        }
        if inc.friction_continuation {
            s.notes.push(Warning {
                increment: inc.index,
                message: format!(
                    "the search from the contact states it started with found no state satisfying the law; its states were found from the same start with every friction coefficient scaled by {} and then 1 (a continuation in μ, {} solves in all)",
                    crate::solve::nonlinear::CONTINUATION.map(|f| f.to_string()).join(", "),
                    inc.iterations,
                ),
            });
        }
        // Maximum displacement.
        let best = largest_magnitude(&inc.u);
        let (p, n) = self.dofs.locate(best.1);
        let x = self.model.parts[p].mesh.nodes[n];
        s.max_displacement = MaxDisplacement {
            value: best.0,
            x: x[0],
            y: x[1],
            part: self.model.parts[p].name.clone(),
            node: n,
        };
        let r = self.reactions(inc);
        s.reactions = self
            .model
            .supports
            .iter()
            .zip(&r)
            .map(|(sup, r)| Reaction {
                support: sup.name.clone(),
                fx: r[0],
                fy: r[1],
            })
            .collect();
        let mut applied = [0.0; 2];
        for (d, f) in inc.f_ext.iter().enumerate() {
            applied[d % 2] += f;
        }
        s.applied = applied;
        let total: [f64; 2] =
            std::array::from_fn(|c| applied[c] + r.iter().map(|r| r[c]).sum::<f64>());
        let scale = applied[0].hypot(applied[1]);
        s.equilibrium_error = if scale > 0.0 {
            total[0].hypot(total[1]) / scale
        } else {
            0.0
        };
    }

    /// Adds the increment's law violations and precision warning to the summary
    /// (with `implex`, those of the final increment only: its early increments lag
    /// by design).
    fn record_violations(&self, s: &mut Summary, inc: &IncrementResult) {
        let settings = &self.model.settings;
        if settings.scheme == Scheme::Implex && inc.index < settings.increments {
            return;
        }
        for v in &inc.violations {
            let iface = &self.interfaces[v.interface];
            let c = &iface.elements[v.pair];
            let relative = if inc.load_scale > 0.0 {
                v.force / inc.load_scale
            } else {
                0.0
            };
            s.max_violation = s.max_violation.max(relative);
            s.violations.push(ViolationRecord {
                increment: inc.index,
                interface: iface.name.clone(),
                node: c.node,
                x: c.position[0],
                y: c.position[1],
                kind: v.kind,
                amount: v.amount,
                force: v.force,
                relative,
                settled: inc.settled.binary_search(&(v.interface, v.pair)).is_ok(),
            });
        }
        if let Some(worst) = inc
            .violations
            .iter()
            .max_by(|a, b| a.force.total_cmp(&b.force))
        {
            let iface = &self.interfaces[worst.interface];
            let c = &iface.elements[worst.pair];
            let why = if inc.settled.is_empty() {
                "lagged states of the implex scheme"
            } else {
                "no state satisfies the law; settled on the least-violating pattern"
            };
            s.warnings.push(Warning {
                increment: inc.index,
                message: format!(
                    "{} pair(s) break the contact law ({why}); the worst, node {} at ({}, {}) of interface '{}', {} {:.4e} ({:.2e} of the load scale)",
                    inc.violations.len(),
                    c.node,
                    c.position[0],
                    c.position[1],
                    iface.name,
                    match worst.kind {
                        ViolationKind::Tension => "pulls with",
                        ViolationKind::Penetration => "penetrates by",
                        ViolationKind::Friction => "sticks beyond μ|f_n| by",
                        ViolationKind::Slip => "slips off μ|f_n| by",
                    },
                    worst.amount,
                    worst.force / inc.load_scale.max(f64::MIN_POSITIVE)
                ),
            });
        }
        let imbalance = inc.residual.max(inc.balance);
        if imbalance > RESIDUAL_WARN {
            s.warnings.push(Warning {
                increment: inc.index,
                message: format!(
                    "the out-of-balance force is {imbalance:.1e} of the balance scale {:.4e} (above {RESIDUAL_WARN:.0e}; the largest at a free DOF, or the reactions against the applied load; the scale is the largest of the load (or the support reactions), the pair forces and 1e-4 × the softest part's E·t × the largest displacement): the solution has lost accuracy; a penalty far above E·t (more than about 1e7 × E·t) is the usual cause",
                    inc.balance_scale
                ),
            });
        }
    }
}

/// The error of interface `def`, whose search distance found no pair, with the
/// distance from its nearest coupling node to the nearest host boundary edge
/// (measured over every node and boundary edge: only on this failure, and both
/// are boundaries, so about as many products as the model has nodes).
fn no_pairs(def: &InterfaceDef, host: &Part, node_part: &Part) -> Error {
    let edges = host.mesh.boundary_edges();
    let nearest = def
        .nodes
        .iter()
        .flat_map(|&n| {
            let p = node_part.mesh.nodes[n];
            edges.iter().map(move |e| {
                let [a, b] = e.nodes.map(|k| host.mesh.nodes[k]);
                crate::coupling::search::project(p, a, b).1
            })
        })
        .fold(f64::INFINITY, f64::min);
    let nearest = nearest.is_finite().then_some(nearest);
    Error::NoPairs {
        interface: def.name.clone(),
        search_distance: def.search_distance,
        nearest,
        message: format!(
            "no pair within search_distance = {}: none of the {} coupling nodes of part '{}' (boundary '{}') lies within it of a boundary edge of part '{}'{}; the pairs are fixed in the initial configuration, so the interface would couple nothing: raise `search_distance` or place the faces closer",
            def.search_distance,
            def.nodes.len(),
            node_part.name,
            def.boundary,
            host.name,
            nearest.map_or(String::new(), |d| format!(" (the nearest is {d:e} away)")),
        ),
    }
}

/// The positions of the closed (bonded or slipping) pairs with the smallest and
/// the largest x (then y); `None` when no pair is closed.
/// The stabilising tangential stiffness of a slipping pair between `host` and
/// `node` under `law`: [`crate::coupling::SLIP_STIFFNESS`] × the softer side's E·t
/// for the Coulomb law, 0 for the others (they have no slip state).
fn slip_stiffness(law: Law, host: &crate::domain::Part, node: &crate::domain::Part) -> f64 {
    let et = |p: &crate::domain::Part| p.material.young * p.material.thickness;
    if law == Law::Coulomb {
        crate::coupling::SLIP_STIFFNESS * et(host).min(et(node))
    } else {
        0.0
    }
}

fn contact_extent(rows: &[&PairRow]) -> Option<[[f64; 2]; 2]> {
    let by_x = |a: &&&PairRow, b: &&&PairRow| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y));
    let closed = || rows.iter().filter(|r| r.state.is_closed());
    match (closed().min_by(by_x), closed().max_by(by_x)) {
        (Some(a), Some(b)) => Some([[a.x, a.y], [b.x, b.y]]),
        _ => None,
    }
}

/// The positions of the bonded pairs with the smallest and the largest x (then y):
/// the ends of the contact zone; `None` when no pair is bonded.
fn bonded_extent(rows: &[&PairRow]) -> Option<[[f64; 2]; 2]> {
    let by_x = |a: &&&PairRow, b: &&&PairRow| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y));
    let bonded = || rows.iter().filter(|r| r.state == PairState::Bonded);
    match (bonded().min_by(by_x), bonded().max_by(by_x)) {
        (Some(a), Some(b)) => Some([[a.x, a.y], [b.x, b.y]]),
        _ => None,
    }
}

/// The largest magnitude `|(u[2g], u[2g+1])|` over the nodes g of `u` and the
/// first node reaching it: found by the squared magnitudes (a product per node,
/// no `hypot`: 0.03 s per increment at 4 M unknowns), then measured with `hypot`.
/// Where the squares leave the normal range (magnitudes beyond 1e154 or below
/// 1e-154, or no displacement at all) `hypot` is taken at every node.
fn largest_magnitude(u: &[f64]) -> (f64, usize) {
    fn first_largest(u: &[f64], magnitude: impl Fn(&[f64]) -> f64) -> (f64, usize) {
        let mut best = (0.0, 0usize);
        for (g, v) in u.chunks_exact(2).enumerate() {
            let m = magnitude(v);
            if m > best.0 {
                best = (m, g);
            }
        }
        best
    }
    let (square, g) = first_largest(u, |v| v[0] * v[0] + v[1] * v[1]);
    if square.is_finite() && square >= f64::MIN_POSITIVE {
        (u[2 * g].hypot(u[2 * g + 1]), g)
    } else {
        first_largest(u, |v| v[0].hypot(v[1]))
    }
}

#[cfg(test)]
mod tests {
    use super::largest_magnitude;

    /// The largest nodal displacement and its node: the first of equal ones,
    /// (0, 0) for no displacement or none at all, and magnitudes whose squares
    /// overflow (5e200) or underflow (5e-200) still compared exactly.
    #[test]
    fn largest_magnitude_finds_the_first_largest_node() {
        assert_eq!(
            largest_magnitude(&[3.0, 4.0, 0.0, -5.0, 1.0, 1.0]),
            (5.0, 0)
        );
        assert_eq!(largest_magnitude(&[0.0, 0.0, -0.0, 0.0]), (0.0, 0));
        assert_eq!(largest_magnitude(&[]), (0.0, 0));
        let big = [3e200, 0.0, 3e200, 4e200, 1.0, 0.0];
        assert_eq!(largest_magnitude(&big), (3e200f64.hypot(4e200), 1));
        let tiny = [1e-200, 0.0, 3e-200, 4e-200, 0.0, 2e-200];
        assert_eq!(largest_magnitude(&tiny), (3e-200f64.hypot(4e-200), 1));
    }
}
