//! Analysis: one problem from model to results. Finds the coupling pairs, moves the
//! coupling nodes onto their host edges, numbers the DOFs ([`Analysis::new`]), and
//! solves in memory ([`Analysis::solve`], [`Analysis::solve_from`]): the
//! displacements, stresses, pair states and forces, reactions and summary.
//! Writing them to disk as the increments converge is [`Analysis::run`], in
//! `output::run`.

use crate::assembly::{self, DofMap};
use crate::coupling::{Coupling, Interface, Law, PairStates, search, segment};
use crate::domain::{InterfaceDef, Part, StartPattern};
use crate::error::{Error, Result};
use crate::fem::recovery::{self, PartStress};
use crate::model::{Model, Scheme};
use crate::results::memory::peak_memory_bytes;
pub use crate::results::summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, Reaction, RunClock, RunStatus,
    SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};
use crate::results::{self, PairRow};
use crate::solve::nonlinear::{IncrementResult, LoadSteps, Solver};
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
        use crate::results::fmt::{num, num_rel};
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
        let f = assembly::external_force(&self.model.loads, &self.dofs);
        let mut solver = Solver::new(
            &self.model.parts,
            &self.interfaces,
            &self.dofs,
            f,
            &self.model.settings,
        )?;
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
    pub fn check_memory(solver: &Solver<'_>, available: Option<u64>) -> Result<()> {
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
        let mut solver = self.solver()?;
        solver.set_stop(stop);
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

    /// The summary before the first increment.
    pub(crate) fn empty_summary(&self) -> Summary {
        let m = &self.model;
        Summary::new(
            &self.problem(),
            results::Heading {
                title: m.title.clone(),
                problem: m.source.clone(),
                refine: m.refine,
                steps: m.steps(),
                warnings: results::kept_polygon_warnings(&m.kept_polygons, m.refine),
                notes: m.warnings(),
                shortcut_off: self.shortcut_off_reason(),
                setup: &self.timings,
            },
        )
    }

    /// The reaction (x, y) of each support, in the order of `model.supports`: the
    /// out-of-balance force F_int − F_ext summed over the DOFs it fixes.
    pub fn reactions(&self, inc: &IncrementResult) -> Vec<[f64; 2]> {
        self.problem().reactions(inc)
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
        results::pair_rows(&self.problem(), inc, &self.step_name(inc.step))
    }

    /// Records converged increment `inc` (with its pair rows `rows`) in the
    /// summary `s`.
    pub(crate) fn fill_summary(&self, s: &mut Summary, inc: &IncrementResult, rows: &[PairRow]) {
        s.record_increment(&self.problem(), inc, rows, self.step_name(inc.step));
    }

    /// The problem the results are read against.
    fn problem(&self) -> results::Problem<'_> {
        results::Problem {
            parts: &self.model.parts,
            supports: &self.model.supports,
            interfaces: &self.interfaces,
            dofs: &self.dofs,
            settings: &self.model.settings,
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
