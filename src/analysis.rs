//! Analysis: one problem from model to results on disk. Finds the coupling pairs,
//! numbers the DOFs, runs the incremental solver, recovers stresses, and writes each
//! converged increment (VTU + PVD series, pairs CSV, JSON summary) as soon as it
//! converges, so results survive a later failure; pictures at the end.

use crate::assembly::{self, DofMap};
use crate::coupling::{Interface, PairState, element as cfe, search};
use crate::error::{Error, Result};
use crate::fem::recovery::{self, PartStress};
use crate::mesh::Element;
use crate::model::{Model, Scheme};
use crate::output::report::{self, PairRow};
use crate::output::{png, vtu};
use crate::solve::nonlinear::{IncrementResult, RESIDUAL_WARN, SolveTimings, Solver};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Seconds spent in each phase of a run.
#[derive(Debug, Clone, Default, Serialize)]
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
    /// Writing the per-increment files (VTU, PVD, CSV, JSON).
    pub output: f64,
    /// Rendering the PNG pictures.
    pub pictures: f64,
    /// Wall time of the whole run.
    pub total: f64,
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

/// Summary of one part.
#[derive(Debug, Clone, Serialize)]
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
}

/// A pair whose state was fixed against the law to settle an active-set cycle.
#[derive(Debug, Clone, Serialize)]
pub struct SettledPair {
    /// Coupling node.
    pub node: usize,
    /// Its position.
    pub x: f64,
    /// Its position.
    pub y: f64,
    /// `bonded` or `open`.
    pub state: &'static str,
    /// Normal force on the node part (negative: tension).
    pub force_n: f64,
}

/// A pair that breaks its law at a converged increment.
#[derive(Debug, Clone, Serialize)]
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
    /// `tension` (a bonded pair pulls) or `penetration` (an open pair interpenetrates).
    pub kind: crate::coupling::ViolationKind,
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

/// Summary of one interface at the last converged increment.
#[derive(Debug, Clone, Serialize)]
pub struct InterfaceSummary {
    /// Interface name.
    pub name: String,
    /// Host part.
    pub host: String,
    /// Node part.
    pub node_part: String,
    /// `rigid` or `contact`.
    pub law: crate::coupling::Law,
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
    pub bonded_extent: Option<[[f64; 2]; 2]>,
}

/// A warning about one converged increment.
#[derive(Debug, Clone, Serialize)]
pub struct Warning {
    /// Increment (1-based).
    pub increment: usize,
    /// What is wrong, in one sentence.
    pub message: String,
}

/// What "the law holds" and "in equilibrium" mean for a run.
#[derive(Debug, Clone, Serialize)]
pub struct Tolerances {
    /// A bonded pair pulling with more than this fraction of the load scale breaks the law.
    pub tension: f64,
    /// An open pair penetrating by more than this fraction of its nodes' largest
    /// displacement breaks the law.
    pub penetration: f64,
    /// The run fails when a violation exceeds this fraction of the load scale.
    pub max_violation: f64,
    /// Out-of-balance force (relative to the load scale) above which a warning is given.
    pub residual_warn: f64,
    /// Out-of-balance force (relative to the load scale) above which the run fails.
    pub residual_fail: f64,
}

/// The maximum displacement magnitude and where it occurs.
#[derive(Debug, Clone, Default, Serialize)]
pub struct MaxDisplacement {
    /// |u|.
    pub value: f64,
    /// Reference position x.
    pub x: f64,
    /// Reference position y.
    pub y: f64,
    /// Part name.
    pub part: String,
    /// Node of the part.
    pub node: usize,
}

/// The total reaction of one support.
#[derive(Debug, Clone, Serialize)]
pub struct Reaction {
    /// Support label.
    pub support: String,
    /// Reaction force x.
    pub fx: f64,
    /// Reaction force y.
    pub fy: f64,
}

/// The JSON summary of a run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// `running`; `completed` (the law holds on every pair at every increment and
    /// equilibrium to the stated tolerance); `completed_with_violations` (some pairs
    /// break the law, each listed in `violations`, or the result is imprecise, see
    /// `warnings`); or `failed`.
    pub status: String,
    /// Error message when failed.
    pub error: Option<String>,
    /// Warnings: law violations and loss of precision, per increment.
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
    pub iteration_history: Vec<Vec<crate::solve::nonlinear::Iteration>>,
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
    pub applied: [f64; 2],
    /// |Σ reactions + Σ loads| / |Σ loads| (0 when no load).
    pub equilibrium_error: f64,
    /// Largest out-of-balance force at a free DOF relative to the load scale (the
    /// larger of Σ‖f‖ over the loaded nodes and the largest support reaction).
    pub residual: f64,
    /// Peak resident memory of the process (bytes; Linux).
    pub peak_memory_bytes: Option<u64>,
    /// Seconds per phase.
    pub timings: Timings,
}

impl Analysis {
    /// Reads and meshes the problem file, then prepares the analysis.
    pub fn from_file(path: &Path, refine: usize) -> Result<Analysis> {
        let t = Instant::now();
        let model = Model::from_file(path, refine)?;
        let meshing = t.elapsed().as_secs_f64();
        let mut a = Analysis::new(model)?;
        a.timings.meshing = meshing;
        Ok(a)
    }

    /// Finds the coupling pairs of every interface, moves each coupling node onto
    /// its host edge (its projection there: a no-op for faces that already
    /// coincide, a small adjustment for a curved face meshed apart), and numbers
    /// the DOFs. Interfaces are taken in file order, each seeing the nodes the
    /// earlier ones moved.
    pub fn new(mut model: Model) -> Result<Analysis> {
        let t = Instant::now();
        let mut interfaces = Vec::with_capacity(model.interfaces.len());
        for def in &model.interfaces {
            let host = &model.parts[def.host];
            let node_part = &model.parts[def.node_part];
            // The tolerance is a fraction of the host's edges as meshed in the
            // problem file: `--refine K` subdivides edges K times but leaves the gap
            // between two faces meshed apart (a Gmsh part keeps its polygons) as it is.
            let elements = search::find_pairs(
                &def.name,
                &host.mesh,
                &node_part.mesh,
                &def.nodes,
                def.tolerance * model.refine as f64,
            )?;
            let max_projection_distance = elements.iter().map(|c| c.distance).fold(0.0, f64::max);
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
            interfaces.push(Interface {
                name: def.name.clone(),
                host: def.host,
                node_part: def.node_part,
                law: def.law,
                c_n: def.c_n,
                c_s: def.c_s,
                elements,
                max_projection_distance,
            });
        }
        let dofs = DofMap::new(&model.parts, &model.supports);
        let timings = Timings {
            pair_search: t.elapsed().as_secs_f64(),
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
        }
    }

    /// A human-readable description of the prepared model (for `cfe check`).
    pub fn describe(&self) -> String {
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
                p.material.young,
                p.material.poisson,
                p.material.thickness
            );
        }
        for i in &self.interfaces {
            s += &format!(
                "  interface '{}': host '{}', nodes '{}', law {}, {} pairs, c_n = {:e}, c_s = {:e}, max projection distance {:e}\n",
                i.name,
                self.model.parts[i.host].name,
                self.model.parts[i.node_part].name,
                i.law.as_str(),
                i.elements.len(),
                i.c_n,
                i.c_s,
                i.max_projection_distance
            );
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
        for l in &self.model.loads {
            s += &format!(
                "  load '{}': resultant ({}, {}) on {} nodal forces\n",
                l.name,
                l.resultant[0],
                l.resultant[1],
                l.nodal.len()
            );
        }
        s
    }

    /// Solves all increments and writes the results into `out`. `progress` is called
    /// after each converged increment. On failure the converged increments stay on
    /// disk and `summary.json` records the error.
    pub fn run(
        &mut self,
        out: &Path,
        progress: &mut dyn FnMut(&IncrementResult),
    ) -> Result<Summary> {
        let start = Instant::now();
        let vtu_dir = out.join("vtu");
        std::fs::create_dir_all(&vtu_dir).map_err(|e| Error::output(&vtu_dir, e))?;
        let f_ext = assembly::external_force(&self.model.loads, &self.dofs);
        let mut summary = self.empty_summary();
        let mut pvd: Vec<vtu::PvdEntry> = Vec::new();
        let mut output_time = 0.0;
        let mut recovery_time = 0.0;

        let grid = self.parts_grid();
        // The stresses of the last converged increment, kept for the pictures.
        let mut last_stresses: Option<std::sync::Arc<Vec<PartStress>>> = None;
        // The large parts VTU of each increment is written by a background thread
        // (at most two in flight) while the next increment is solved and the small
        // files are written; all writers are joined before returning.
        let result = std::thread::scope(|scope| -> Result<IncrementResult> {
            let this = &*self;
            let grid = &grid;
            let mut solver = match Solver::new(
                &this.model.parts,
                &this.interfaces,
                &this.dofs,
                f_ext,
                &this.model.settings,
            ) {
                Ok(s) => s,
                Err(e) => {
                    summary.status = "failed".into();
                    summary.error = Some(e.to_string());
                    report::write_json(&out.join("summary.json"), &summary)?;
                    return Err(e);
                }
            };
            let t = Instant::now();
            if this.model.settings.start == crate::model::Start::Coarse
                && let Some(states) = this.coarse_states()
            {
                solver.set_initial_states(states);
            }
            summary.timings.coarse_start = t.elapsed().as_secs_f64();
            summary.matrix_nonzeros = solver.matrix_nnz();
            summary.factor_nonzeros = solver.factor_nnz();
            let mut writers: std::collections::VecDeque<
                std::thread::ScopedJoinHandle<'_, Result<()>>,
            > = std::collections::VecDeque::new();
            let join = |h: std::thread::ScopedJoinHandle<'_, Result<()>>| -> Result<()> {
                h.join().unwrap_or_else(|_| {
                    Err(Error::output(&vtu_dir, "a VTU writer thread panicked"))
                })
            };
            let r = solver.run(|inc| {
                let t = Instant::now();
                let stresses = this.recover(&inc.u);
                recovery_time += t.elapsed().as_secs_f64();
                let t = Instant::now();
                let rows = this.pair_rows(inc);
                let parts_file = format!("parts_{:04}.vtu", inc.index);
                let pairs_file = format!("pairs_{:04}.vtu", inc.index);
                if writers.len() >= 2 {
                    join(writers.pop_front().expect("two writers"))?;
                }
                let (path, lambda, u) = (vtu_dir.join(&parts_file), inc.lambda, inc.u.clone());
                let stresses = std::sync::Arc::new(stresses);
                last_stresses = Some(std::sync::Arc::clone(&stresses));
                writers.push_back(
                    scope.spawn(move || this.write_parts_vtu(&path, grid, lambda, &u, &stresses)),
                );
                this.write_pairs_vtu(&vtu_dir.join(&pairs_file), inc, &rows)?;
                pvd.push(vtu::PvdEntry {
                    time: inc.lambda,
                    part: 0,
                    file: format!("vtu/{parts_file}"),
                });
                pvd.push(vtu::PvdEntry {
                    time: inc.lambda,
                    part: 1,
                    file: format!("vtu/{pairs_file}"),
                });
                vtu::write_pvd(&out.join("results.pvd"), &pvd)?;
                report::write_pairs_csv(&out.join("pairs.csv"), &rows)?;
                this.fill_summary(&mut summary, inc, &rows);
                report::write_json(&out.join("summary.json"), &summary)?;
                output_time += t.elapsed().as_secs_f64();
                progress(inc);
                Ok(())
            });
            let t = Instant::now();
            let mut written = Ok(());
            for h in writers {
                written = written.and(join(h));
            }
            output_time += t.elapsed().as_secs_f64();
            summary.timings.solve = solver.timings.clone();
            (summary.factorizations, summary.low_rank_updates) = solver.solve_counts();
            summary.first_factorization_seconds = solver.first_factorization_seconds();
            let r = r?;
            written.map(|_| r)
        });
        let inc = match result {
            Ok(inc) => inc,
            Err(e) => {
                summary.status = "failed".into();
                summary.error = Some(e.to_string());
                summary.timings.total =
                    start.elapsed().as_secs_f64() + self.timings.meshing + self.timings.pair_search;
                summary.peak_memory_bytes = peak_memory_bytes();
                report::write_json(&out.join("summary.json"), &summary)?;
                return Err(e);
            }
        };
        let t = Instant::now();
        let stresses = match last_stresses.take() {
            Some(s) => s,
            None => std::sync::Arc::new(self.recover(&inc.u)),
        };
        self.write_pictures(out, &inc, &stresses)?;
        summary.timings.pictures = t.elapsed().as_secs_f64();
        summary.status = if summary.warnings.is_empty() {
            "completed".into()
        } else {
            "completed_with_violations".into()
        };
        summary.timings.meshing = self.timings.meshing;
        summary.timings.pair_search = self.timings.pair_search;
        summary.timings.stress_recovery = recovery_time;
        summary.timings.output = output_time;
        summary.timings.total =
            start.elapsed().as_secs_f64() + self.timings.meshing + self.timings.pair_search;
        summary.peak_memory_bytes = peak_memory_bytes();
        report::write_json(&out.join("summary.json"), &summary)?;
        self.timings = summary.timings.clone();
        Ok(summary)
    }

    /// For a refined model solved by `active-set`: the final pair states of the same
    /// problem on meshes 4 × coarser (solved the same way, recursively), mapped to
    /// this model's pairs by position — a start close to the final pattern, so the
    /// iteration needs few, small state changes. `None` when no coarser level exists.
    pub fn coarse_states(&self) -> Option<Vec<Vec<PairState>>> {
        let m = &self.model;
        let contact = self
            .interfaces
            .iter()
            .any(|i| i.law == crate::coupling::Law::Contact);
        if m.refine < 4 || m.settings.scheme != Scheme::ActiveSet || !contact {
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
        let f = assembly::external_force(&coarse.model.loads, &coarse.dofs);
        let settings = crate::model::Settings {
            increments: 1,
            ..m.settings.clone()
        };
        let mut solver = Solver::new(
            &coarse.model.parts,
            &coarse.interfaces,
            &coarse.dofs,
            f,
            &settings,
        )
        .ok()?;
        if let Some(s) = coarse.coarse_states() {
            solver.set_initial_states(s);
        }
        let last = solver.run(|_| Ok(())).ok()?;
        // Each fine pair takes the state of the nearest coarse pair of its interface.
        let states = self
            .interfaces
            .iter()
            .zip(&coarse.interfaces)
            .zip(&last.states)
            .map(|((fine, coarse), cs)| {
                let tree = rstar::RTree::bulk_load(
                    coarse
                        .elements
                        .iter()
                        .enumerate()
                        .map(|(k, c)| rstar::primitives::GeomWithData::new(c.position, k))
                        .collect(),
                );
                fine.elements
                    .iter()
                    .map(|c| {
                        tree.nearest_neighbor(c.position)
                            .map_or(PairState::Bonded, |n| cs[n.data])
                    })
                    .collect()
            })
            .collect();
        Some(states)
    }

    fn empty_summary(&self) -> Summary {
        Summary {
            status: "running".into(),
            error: None,
            warnings: Vec::new(),
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
            peak_memory_bytes: None,
            timings: Timings {
                meshing: self.timings.meshing,
                pair_search: self.timings.pair_search,
                ..Default::default()
            },
        }
    }

    /// The reaction (x, y) of each support, in the order of `model.supports`: the
    /// out-of-balance force F_int − F_ext summed over the DOFs it fixes.
    pub fn reactions(&self, inc: &IncrementResult) -> Vec<[f64; 2]> {
        let mut r = vec![[0.0; 2]; self.model.supports.len()];
        for (d, sup) in self.dofs.support_of.iter().enumerate() {
            if let Some(k) = sup {
                r[*k][d % 2] += inc.f_int[d] - inc.f_ext[d];
            }
        }
        r
    }

    /// Stresses of every part for displacements `u` (all DOFs).
    pub fn recover(&self, u: &[f64]) -> Vec<PartStress> {
        self.model
            .parts
            .iter()
            .enumerate()
            .map(|(p, part)| {
                let s = 2 * self.dofs.node_offset[p];
                recovery::recover(part, &u[s..s + 2 * part.mesh.nodes.len()])
            })
            .collect()
    }

    /// One row per coupling pair: state, jumps and forces on the node part.
    pub fn pair_rows(&self, inc: &IncrementResult) -> Vec<PairRow> {
        let mut rows = Vec::new();
        let mut violations = inc.violations.iter().peekable();
        for (i, iface) in self.interfaces.iter().enumerate() {
            for (k, c) in iface.elements.iter().enumerate() {
                let state = inc.states[i][k];
                // Violations are sorted by interface and pair, like the rows.
                let violation = violations.next_if(|v| (v.interface, v.pair) == (i, k));
                let d: Vec<f64> = self
                    .dofs
                    .cfe_dofs(iface, c)
                    .iter()
                    .map(|&j| inc.u[j])
                    .collect();
                let (_, f) =
                    cfe::internal_force(&c.shape, c.normal, iface.c_n, iface.c_s, state, &d);
                let jump = cfe::local_jump(c.normal, cfe::jump(&c.shape, &d));
                rows.push(PairRow {
                    interface: iface.name.clone(),
                    node: c.node,
                    x: c.position[0],
                    y: c.position[1],
                    host_element: c.host_element,
                    state: state.as_str(),
                    gap_n: jump[0],
                    slip_s: jump[1],
                    // Force on the node part is −f; `+ 0.0` turns −0 into 0 for open pairs.
                    force_n: -f[0] + 0.0,
                    force_s: -f[1] + 0.0,
                    settled: inc.settled.binary_search(&(i, k)).is_ok(),
                    violation: violation.map(|v| v.kind),
                    violation_amount: violation.map_or(0.0, |v| v.amount),
                });
            }
        }
        rows
    }

    fn fill_summary(&self, s: &mut Summary, inc: &IncrementResult, rows: &[PairRow]) {
        s.converged_increments = inc.index;
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
                let bonded = mine
                    .iter()
                    .filter(|r| r.state == PairState::Bonded.as_str())
                    .count();
                InterfaceSummary {
                    name: iface.name.clone(),
                    host: self.model.parts[iface.host].name.clone(),
                    node_part: self.model.parts[iface.node_part].name.clone(),
                    law: iface.law,
                    c_n: iface.c_n,
                    c_s: iface.c_s,
                    pairs: mine.len(),
                    bonded,
                    open: mine.len() - bonded,
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
                    max_penetration: mine.iter().map(|r| -r.gap_n).fold(0.0, f64::max),
                    total_force_n: mine.iter().map(|r| r.force_n).sum(),
                    max_projection_distance: iface.max_projection_distance,
                    bonded_extent: {
                        let by_x = |a: &&&PairRow, b: &&&PairRow| {
                            a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
                        };
                        let bonded = || mine.iter().filter(|r| r.state == "bonded");
                        match (bonded().min_by(by_x), bonded().max_by(by_x)) {
                            (Some(a), Some(b)) => Some([[a.x, a.y], [b.x, b.y]]),
                            _ => None,
                        }
                    },
                }
            })
            .collect();
        // Maximum displacement.
        let mut best = (0.0, 0usize);
        for g in 0..self.dofs.n_nodes() {
            let m = inc.u[2 * g].hypot(inc.u[2 * g + 1]);
            if m > best.0 {
                best = (m, g);
            }
        }
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
    /// (with `implex`, those of the final increment only).
    fn record_violations(&self, s: &mut Summary, inc: &IncrementResult) {
        // implex lags its states by design: only its final increment is judged.
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
        if !inc.violations.is_empty() {
            let worst = inc
                .violations
                .iter()
                .max_by(|a, b| a.force.total_cmp(&b.force))
                .expect("non-empty");
            let c = &self.interfaces[worst.interface].elements[worst.pair];
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
                self.interfaces[worst.interface].name,
                match worst.kind {
                    crate::coupling::ViolationKind::Tension => "pulls with",
                    crate::coupling::ViolationKind::Penetration => "penetrates by",
                },
                worst.amount,
                worst.force / inc.load_scale.max(f64::MIN_POSITIVE)
            ),
            });
        }
        if inc.residual.max(inc.balance) > RESIDUAL_WARN {
            s.warnings.push(Warning {
                increment: inc.index,
                message: format!(
                "the out-of-balance force is {:.1e} of the load scale (above {:.0e}; the largest at a free DOF, or the reactions against the applied load): the solution has lost accuracy; a penalty far above E·t (more than about 1e7 × E·t) is the usual cause",
                inc.residual.max(inc.balance), RESIDUAL_WARN
            ),
            });
        }
    }

    fn global_points(&self) -> Vec<[f64; 2]> {
        self.model
            .parts
            .iter()
            .flat_map(|p| p.mesh.nodes.iter().copied())
            .collect()
    }

    /// Every element as triangles in global node numbers, for the pictures: a Q4
    /// is split along its diagonal 1–3 (the picture interpolates linearly).
    fn plot_triangles(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for (p, part) in self.model.parts.iter().enumerate() {
            let o = self.dofs.node_offset[p];
            for el in &part.mesh.elements {
                match *el {
                    Element::T3(t) => out.push(t.map(|n| n + o)),
                    Element::Q4([a, b, c, d]) => {
                        out.push([a + o, b + o, c + o]);
                        out.push([a + o, c + o, d + o]);
                    }
                }
            }
        }
        out
    }

    /// The parts' geometry for the VTU files, built once per run.
    fn parts_grid(&self) -> PartsGrid {
        let n_cells: usize = self.model.parts.iter().map(|p| p.mesh.elements.len()).sum();
        let mut part_point = Vec::with_capacity(self.dofs.n_nodes());
        let mut part_cell = Vec::with_capacity(n_cells);
        let mut connectivity = Vec::with_capacity(4 * n_cells);
        let mut offsets = Vec::with_capacity(n_cells);
        let mut kinds = Vec::with_capacity(n_cells);
        for (p, part) in self.model.parts.iter().enumerate() {
            let o = self.dofs.node_offset[p];
            part_point.extend(std::iter::repeat_n(p as i32, part.mesh.nodes.len()));
            part_cell.extend(std::iter::repeat_n(p as i32, part.mesh.elements.len()));
            for el in &part.mesh.elements {
                connectivity.extend(el.nodes().iter().map(|n| n + o));
                offsets.push(connectivity.len());
                kinds.push(match el {
                    Element::T3(_) => vtu::CellKind::Triangle,
                    Element::Q4(_) => vtu::CellKind::Quad,
                });
            }
        }
        PartsGrid {
            points: self.global_points(),
            connectivity,
            offsets,
            kinds,
            part_point,
            part_cell,
        }
    }

    fn write_parts_vtu(
        &self,
        path: &Path,
        grid: &PartsGrid,
        lambda: f64,
        u: &[f64],
        stresses: &[PartStress],
    ) -> Result<()> {
        let (points, connectivity, offsets, kinds) =
            (&grid.points, &grid.connectivity, &grid.offsets, &grid.kinds);
        let (part_point, part_cell) = (&grid.part_point, &grid.part_cell);
        let mut nodal: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(points.len()));
        let mut cell: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(part_cell.len()));
        for (part, s) in self.model.parts.iter().zip(stresses) {
            for v in &s.nodal {
                for c in 0..3 {
                    nodal[c].push(v[c]);
                }
                nodal[3].push(part.material.von_mises(*v));
            }
            for v in &s.element {
                for c in 0..3 {
                    cell[c].push(v[c]);
                }
                cell[3].push(part.material.von_mises(*v));
            }
        }
        let names = ["sigma_xx", "sigma_yy", "sigma_xy", "von_mises"];
        let mut point_data = vec![vtu::DataArray {
            name: "displacement",
            components: 2,
            values: vtu::Values::F64(u),
        }];
        for (name, v) in names.iter().zip(&nodal) {
            point_data.push(vtu::DataArray {
                name,
                components: 1,
                values: vtu::Values::F64(v),
            });
        }
        point_data.push(vtu::DataArray {
            name: "part_id",
            components: 1,
            values: vtu::Values::I32(part_point),
        });
        let mut cell_data: Vec<vtu::DataArray> = names
            .iter()
            .zip(&cell)
            .map(|(name, v)| vtu::DataArray {
                name,
                components: 1,
                values: vtu::Values::F64(v),
            })
            .collect();
        cell_data.push(vtu::DataArray {
            name: "part_id",
            components: 1,
            values: vtu::Values::I32(part_cell),
        });
        vtu::write_vtu(
            path,
            &vtu::Grid {
                points,
                connectivity,
                offsets,
                kinds,
                point_data: &point_data,
                cell_data: &cell_data,
                field_data: &[("TIME", lambda)],
            },
        )
    }

    fn write_pairs_vtu(&self, path: &Path, inc: &IncrementResult, rows: &[PairRow]) -> Result<()> {
        let points: Vec<[f64; 2]> = rows.iter().map(|r| [r.x, r.y]).collect();
        let connectivity: Vec<usize> = (0..rows.len()).collect();
        let offsets: Vec<usize> = (1..=rows.len()).collect();
        let kinds: Vec<vtu::CellKind> = rows.iter().map(|_| vtu::CellKind::Vertex).collect();
        let bonded: Vec<i32> = rows.iter().map(|r| (r.state == "bonded") as i32).collect();
        let settled: Vec<i32> = rows.iter().map(|r| r.settled as i32).collect();
        // 0: the law holds; 1: a bonded pair pulls; 2: an open pair penetrates.
        let violation: Vec<i32> = rows
            .iter()
            .map(|r| match r.violation {
                None => 0,
                Some(crate::coupling::ViolationKind::Tension) => 1,
                Some(crate::coupling::ViolationKind::Penetration) => 2,
            })
            .collect();
        let violation_amount: Vec<f64> = rows.iter().map(|r| r.violation_amount).collect();
        let col = |f: fn(&PairRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
        let (gap, slip, fn_, fs) = (
            col(|r| r.gap_n),
            col(|r| r.slip_s),
            col(|r| r.force_n),
            col(|r| r.force_s),
        );
        let mut normal = Vec::with_capacity(2 * rows.len());
        let mut iface_id = Vec::with_capacity(rows.len());
        let mut disp = Vec::with_capacity(2 * rows.len());
        for (i, iface) in self.interfaces.iter().enumerate() {
            for c in &iface.elements {
                normal.extend_from_slice(&c.normal);
                iface_id.push(i as i32);
                let g = self.dofs.node(iface.node_part, c.node);
                disp.extend_from_slice(&inc.u[2 * g..2 * g + 2]);
            }
        }
        let point_data = [
            vtu::DataArray {
                name: "displacement",
                components: 2,
                values: vtu::Values::F64(&disp),
            },
            vtu::DataArray {
                name: "bonded",
                components: 1,
                values: vtu::Values::I32(&bonded),
            },
            vtu::DataArray {
                name: "settled",
                components: 1,
                values: vtu::Values::I32(&settled),
            },
            vtu::DataArray {
                name: "violation",
                components: 1,
                values: vtu::Values::I32(&violation),
            },
            vtu::DataArray {
                name: "violation_amount",
                components: 1,
                values: vtu::Values::F64(&violation_amount),
            },
            vtu::DataArray {
                name: "gap_n",
                components: 1,
                values: vtu::Values::F64(&gap),
            },
            vtu::DataArray {
                name: "slip_s",
                components: 1,
                values: vtu::Values::F64(&slip),
            },
            vtu::DataArray {
                name: "force_n",
                components: 1,
                values: vtu::Values::F64(&fn_),
            },
            vtu::DataArray {
                name: "force_s",
                components: 1,
                values: vtu::Values::F64(&fs),
            },
            vtu::DataArray {
                name: "normal",
                components: 2,
                values: vtu::Values::F64(&normal),
            },
            vtu::DataArray {
                name: "interface_id",
                components: 1,
                values: vtu::Values::I32(&iface_id),
            },
        ];
        vtu::write_vtu(
            path,
            &vtu::Grid {
                points: &points,
                connectivity: &connectivity,
                offsets: &offsets,
                kinds: &kinds,
                point_data: &point_data,
                cell_data: &[],
                field_data: &[("TIME", inc.lambda)],
            },
        )
    }

    fn write_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult,
        stresses: &[PartStress],
    ) -> Result<()> {
        let points = self.global_points();
        let tris = self.plot_triangles();
        let outline = png::outline_edges(&tris);
        let syy: Vec<f64> = stresses
            .iter()
            .flat_map(|s| s.nodal.iter().map(|v| v[1]))
            .collect();
        let rows = self.pair_rows(inc);
        let markers: Vec<png::PairMarker> = rows
            .iter()
            .map(|r| png::PairMarker {
                at: [r.x, r.y],
                bonded: r.state == "bonded",
                violates: r.violation.is_some(),
            })
            .collect();
        let units = &self.model.units;
        let broken = rows.iter().filter(|r| r.violation.is_some()).count();
        let note = if broken > 0 {
            format!(" ({broken} pair(s) break the contact law: red squares)")
        } else {
            String::new()
        };
        let title = format!("{}: σyy{note}", self.model.title);
        // The two pictures are drawn in parallel.
        let field = || {
            png::render_field(
                &out.join("sigma_yy.png"),
                &png::PlotMesh {
                    points: &points,
                    triangles: &tris,
                    outline: Some(&outline),
                },
                &syy,
                &markers,
                &png::PlotLabels {
                    title: &title,
                    colorbar: &format!("σyy [{}]", units.stress),
                    axis_unit: &units.length,
                },
            )
        };
        let isolines = || {
            // Deformed shape, magnified so the largest displacement is 5 % of the model size.
            let magnitude: Vec<f64> = (0..points.len())
                .map(|g| inc.u[2 * g].hypot(inc.u[2 * g + 1]))
                .collect();
            let umax = magnitude.iter().copied().fold(0.0, f64::max);
            let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for p in &points {
                for c in 0..2 {
                    lo[c] = lo[c].min(p[c]);
                    hi[c] = hi[c].max(p[c]);
                }
            }
            let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
            let scale = if umax > 0.0 {
                nice_floor(0.05 * size / umax)
            } else {
                0.0
            };
            let deformed: Vec<[f64; 2]> = points
                .iter()
                .enumerate()
                .map(|(g, p)| [p[0] + scale * inc.u[2 * g], p[1] + scale * inc.u[2 * g + 1]])
                .collect();
            let deformed_markers: Vec<png::PairMarker> = self
                .interfaces
                .iter()
                .flat_map(|iface| {
                    iface
                        .elements
                        .iter()
                        .map(move |c| self.dofs.node(iface.node_part, c.node))
                })
                .zip(&rows)
                .map(|(g, r)| png::PairMarker {
                    at: deformed[g],
                    bonded: r.state == "bonded",
                    violates: r.violation.is_some(),
                })
                .collect();
            let title = format!(
                "{}: total displacement, deformed ×{scale}{note}",
                self.model.title
            );
            png::render_isolines(
                &out.join("displacement.png"),
                &png::PlotMesh {
                    points: &deformed,
                    triangles: &tris,
                    outline: Some(&outline),
                },
                &magnitude,
                12,
                &deformed_markers,
                &png::PlotLabels {
                    title: &title,
                    colorbar: &format!("|u| [{}]", units.length),
                    axis_unit: &units.length,
                },
            )
        };
        let (a, b) = rayon::join(field, isolines);
        a.and(b)
    }
}

/// The largest 1, 2 or 5 × 10ⁿ not above `x` (a readable magnification factor).
fn nice_floor(x: f64) -> f64 {
    let base = 10f64.powf(x.log10().floor());
    let m = x / base;
    base * if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    }
}

/// The parts' points and cells as written to every VTU of a run.
struct PartsGrid {
    points: Vec<[f64; 2]>,
    connectivity: Vec<usize>,
    offsets: Vec<usize>,
    kinds: Vec<vtu::CellKind>,
    part_point: Vec<i32>,
    part_cell: Vec<i32>,
}

/// Peak resident set size of this process in bytes (Linux `VmHWM`), if known.
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
