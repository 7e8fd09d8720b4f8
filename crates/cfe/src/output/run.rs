//! Running an analysis to disk: solves the increments and writes each converged
//! one (VTU + PVD series, pairs CSV, JSON summary) as soon as it converges, so
//! results survive a later failure; the pictures of the last increment are drawn
//! while its parts VTU is still being written.

use super::folder::{OutputFolder, PICTURES, VTU};
use super::memory::peak_memory_bytes;
use super::report::{self, PairRow};
use super::summary::{RunClock, RunStatus, Summary, Warning};
use super::{chart, png, vtu};
use crate::analysis::Analysis;
use crate::coupling::{Law, PairState, ViolationKind};
use crate::error::{Error, Result};
use crate::fem::recovery::{PartStress, scaled_in_turn};
use crate::mesh::Element;
use crate::solve::nonlinear::Solver;
use crate::solve::nonlinear::{IncrementResult, MultipleOf};
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::Instant;

/// Removes the pictures of a run that failed after drawing them, those it
/// listed in the folder's manifest (best effort: the run's error is what gets
/// reported).
fn remove_pictures(out: &Path, folder: &OutputFolder) {
    for f in PICTURES.into_iter().filter(|f| folder.lists(f)) {
        let _ = std::fs::remove_file(out.join(f));
    }
}

/// Files that grow with the number of increments (`results.pvd`, `summary.json`)
/// are rewritten at every chance while they are small, and at most once per
/// [`REWRITE_INTERVAL`] once they hold [`REWRITE_FREELY`] increments or more, so a
/// run of 100 000 increments does not spend its time rewriting them; the final
/// versions are always written at the end.
const REWRITE_FREELY: usize = 100;
/// See [`REWRITE_FREELY`].
const REWRITE_INTERVAL: std::time::Duration = std::time::Duration::from_secs(1);

/// Whether a growing file holding `count` increments, last written at `last`, is
/// due for a rewrite (see [`REWRITE_FREELY`]); marks it written if so.
fn rewrite_due(last: &mut Option<Instant>, count: usize) -> bool {
    let due = count < REWRITE_FREELY || last.is_none_or(|t| t.elapsed() >= REWRITE_INTERVAL);
    if due {
        *last = Some(Instant::now());
    }
    due
}

/// What a run accumulates while its increments are solved and written.
struct RunLog {
    /// The locked output folder, whose manifest lists each file before it is
    /// written.
    folder: OutputFolder,
    /// When `summary.json` was last written.
    summary_written: Option<Instant>,
    /// The summary, rewritten after each converged increment.
    summary: Summary,
    /// Time spent recovering stresses [s].
    recovery_time: f64,
    /// Time spent writing the per-increment files [s].
    output_time: f64,
    /// The stresses of the last written increment, kept for the pictures.
    last_stresses: Option<Stresses>,
    /// The linear solution `last_stresses` were recovered from a multiple of
    /// (proportional shortcuts): an increment that is another multiple of it
    /// scales them instead of recovering again.
    last_multiple: Option<MultipleOf>,
}

/// A parts-VTU writer thread with the series entries of its increment and the
/// increment's index.
type Writer<'scope> = (
    ScopedJoinHandle<'scope, Result<()>>,
    [vtu::PvdEntry; 2],
    usize,
);

/// Parts-VTU writers a run keeps in flight: two, so the writers of consecutive
/// increments that follow each other quickly (multiples of one linear solution
/// take no solve) encode and copy on both cores, and the last two stream while
/// the pictures are drawn. At most two written increments' displacements and
/// stresses are held besides those of the increment being solved, a bounded
/// amount whatever the number of increments (at 1 M unknowns the peak memory
/// rose by < 1 % over one writer, while the run's wait for its writers halved).
const WRITERS_IN_FLIGHT: usize = 2;

/// The VTU series of a run. The large parts VTU of each increment is written by a
/// background thread (at most [`WRITERS_IN_FLIGHT`] at a time) while the next
/// increments are solved, their stresses recovered and the small files written;
/// an increment's entries are added to `results.pvd` once its writer has
/// finished, in increment order. The writers read the run's stop flag as they
/// write ([`vtu::write_on_until`]): once it is set they abandon their files, and
/// an increment whose parts VTU was not written leaves no file in `vtu/`.
struct Series<'scope> {
    /// The run's stop flag.
    stop: &'scope AtomicUsize,
    /// The `vtu/` folder.
    vtu_dir: PathBuf,
    /// `results.pvd`.
    pvd_path: PathBuf,
    /// The entries of the increments whose files are complete.
    pvd: Vec<vtu::PvdEntry>,
    /// The writers in flight, oldest first.
    writers: VecDeque<Writer<'scope>>,
    /// When `results.pvd` was last written.
    written: Option<Instant>,
    /// The increments whose writer was abandoned at a stop: converged, but
    /// with no file in `vtu/`.
    abandoned: Vec<usize>,
}

impl<'scope> Series<'scope> {
    fn new(out: &Path, stop: &'scope AtomicUsize) -> Self {
        Series {
            stop,
            vtu_dir: out.join(VTU),
            pvd_path: out.join("results.pvd"),
            pvd: Vec::new(),
            writers: VecDeque::new(),
            written: None,
            abandoned: Vec::new(),
        }
    }

    /// Waits for one writer; if it failed (or was stopped), removes its
    /// increment's pairs VTU too (best effort: the writer's error is what gets
    /// reported), so `vtu/` holds only increments `results.pvd` can name. An
    /// increment abandoned at a stop is listed in `abandoned`.
    fn join(&mut self, (h, entries, index): Writer<'scope>) -> Result<[vtu::PvdEntry; 2]> {
        let written = h
            .join()
            .unwrap_or_else(|_| Err(Error::output(&self.vtu_dir, "a VTU writer thread panicked")));
        if written.is_err()
            && let Some(out) = self.pvd_path.parent()
        {
            for e in &entries {
                let _ = std::fs::remove_file(out.join(&e.file));
            }
        }
        if let Err(Error::Interrupted { .. }) = written {
            self.abandoned.push(index);
        }
        written.map(|_| entries)
    }

    /// With [`WRITERS_IN_FLIGHT`] writers in flight, waits for the oldest and
    /// adds its increment to `results.pvd`.
    fn make_room(&mut self) -> Result<()> {
        while self.writers.len() >= WRITERS_IN_FLIGHT {
            let writer = self.writers.pop_front().expect("a writer in flight");
            let entries = self.join(writer)?;
            self.pvd.extend(entries);
            if rewrite_due(&mut self.written, self.pvd.len() / 2) {
                vtu::write_pvd(&self.pvd_path, &self.pvd)?;
            }
        }
        Ok(())
    }

    /// Registers the writer of increment `index` at time `lambda` (step index −
    /// 1 + the step's load factor) whose files (in `vtu/`)
    /// are `parts_file` and `pairs_file`.
    fn push(
        &mut self,
        handle: ScopedJoinHandle<'scope, Result<()>>,
        index: usize,
        lambda: f64,
        parts_file: String,
        pairs_file: String,
    ) {
        let entries = [parts_file, pairs_file].map(|file| format!("vtu/{file}"));
        let [a, b] = entries;
        self.writers.push_back((
            handle,
            [
                vtu::PvdEntry {
                    time: lambda,
                    part: 0,
                    file: a,
                },
                vtu::PvdEntry {
                    time: lambda,
                    part: 1,
                    file: b,
                },
            ],
            index,
        ));
    }

    /// Joins all writers, adds the increments of those that succeeded and writes
    /// `results.pvd`; the first error, if any.
    fn finish(&mut self) -> Result<()> {
        let mut written = Ok(());
        for writer in std::mem::take(&mut self.writers) {
            let w = self.join(writer).map(|entries| self.pvd.extend(entries));
            written = written.and(w);
        }
        written.and(vtu::write_pvd(&self.pvd_path, &self.pvd))
    }
}

/// Notes in `summary` each converged increment in `abandoned` whose VTU files
/// the stop left unwritten: the summary then tells what `vtu/` lacks, and that
/// `summary.json` and `pairs.csv` are whole.
fn note_abandoned(summary: &mut Summary, abandoned: &[usize]) {
    for &index in abandoned {
        summary.notes.push(Warning {
            increment: index,
            message: format!(
                "converged, but its VTU files (vtu/parts_{index:04}.vtu, vtu/pairs_{index:04}.vtu) were not written: the run was interrupted while they were being written, and results.pvd does not name it; summary.json holds every converged increment and pairs.csv the last increment written, both complete"
            ),
        });
    }
}

impl Analysis {
    /// Solves all increments and writes the results into `out`. `progress` is called
    /// after each converged increment. On failure the converged increments stay on
    /// disk and `summary.json` records the error.
    ///
    /// ```
    /// let text = r#"
    /// [materials.steel]
    /// E = 210000.0
    /// nu = 0.3
    ///
    /// [[part]]
    /// name = "base"
    /// material = "steel"
    /// rectangle = { x = [0.0, 40.0], y = [0.0, 20.0], cells = [4, 2] }
    ///
    /// [[part]]
    /// name = "block"
    /// material = "steel"
    /// rectangle = { x = [10.0, 30.0], y = [20.0, 30.0], cells = [6, 3] }
    ///
    /// [[interface]]
    /// host = "base"
    /// nodes = "block"
    /// boundary = "bottom"
    ///
    /// [[support]]
    /// part = "base"
    /// boundary = "bottom"
    /// fix = ["x", "y"]
    ///
    /// [[load]]
    /// part = "block"
    /// boundary = "top"
    /// force = [0.0, -100.0]
    /// "#;
    /// let out = std::env::temp_dir().join(format!("cfe-doc-run-{}", std::process::id()));
    /// let mut analysis = cfe::Analysis::new(text.parse()?)?;
    /// let mut increments = 0;
    /// let summary = analysis.run(&out, &mut |_increment| increments += 1)?;
    /// assert_eq!(summary.status, cfe::RunStatus::Completed);
    /// assert_eq!(increments, summary.increments);
    /// // The snapshot on disk: the summary, the pairs table and the ParaView files.
    /// for file in ["summary.json", "pairs.csv", "results.pvd"] {
    ///     assert!(out.join(file).is_file(), "{file}");
    /// }
    /// # std::fs::remove_dir_all(&out).ok();
    /// # Ok::<(), cfe::Error>(())
    /// ```
    pub fn run(
        &mut self,
        out: &Path,
        progress: &mut dyn FnMut(&IncrementResult),
    ) -> Result<Summary> {
        self.run_until(out, progress, &AtomicUsize::new(0))
    }

    /// [`Analysis::run`] that stops at the next safe point once `stop` is
    /// nonzero (e.g. set by a signal handler to the signal's number): inside the
    /// increment being solved at its next active-set iteration, fixed-point
    /// step, continuation stage or linear solve ([`Solver::set_stop`]; that
    /// increment is abandoned), after an increment is written, in the
    /// pictures at their next check (no picture is kept), or in the parts VTU
    /// writers still in flight, within their next [`vtu::STOP_CHECK_BYTES`]
    /// (an increment whose parts VTU is abandoned leaves no file in `vtu/` and
    /// is not named in `results.pvd`). The converged increments whose files are
    /// complete stay on disk,
    /// `summary.json` says `interrupted`, and the error is [`Error::Interrupted`].
    ///
    /// `out` is opened with [`OutputFolder::open`] without `force`: a folder that
    /// holds no cfe run and is not empty, or holds files at the names a run writes
    /// that no cfe run wrote, is refused ([`Error::OutputFolderNotOurs`]), one
    /// another run writes into too as well ([`Error::OutputFolderInUse`]). See
    /// [`Analysis::run_in`].
    pub fn run_until(
        &mut self,
        out: &Path,
        progress: &mut dyn FnMut(&IncrementResult),
        stop: &AtomicUsize,
    ) -> Result<Summary> {
        self.run_in(OutputFolder::open(out, false)?, progress, stop)
    }

    /// [`Analysis::run_until`] into a folder already locked and checked by
    /// [`OutputFolder::open`] (e.g. with `force`). The files the last run into
    /// the folder listed in its manifest are removed first (and, with `force`,
    /// the other files at the names a run writes), so the folder never mixes two
    /// runs; every other file is left alone. `results.pvd` names an increment's
    /// files only once both are completely written. The folder's lock is held
    /// until the run has ended.
    pub fn run_in(
        &mut self,
        mut folder: OutputFolder,
        progress: &mut dyn FnMut(&IncrementResult),
        stop: &AtomicUsize,
    ) -> Result<Summary> {
        let clock = RunClock::start();
        folder.start()?;
        // Written whatever happens next (a failure is recorded in the summary).
        for f in ["summary.json", "results.pvd"] {
            folder.claim(f)?;
        }
        let out = &folder.path().to_path_buf();
        let mut log = RunLog {
            folder,
            summary_written: None,
            summary: self.empty_summary(),
            recovery_time: 0.0,
            output_time: 0.0,
            last_stresses: None,
            last_multiple: None,
        };
        // The parts' geometry, built when the first increment is written: after
        // the solver has freed the factor if it is not needed again (proportional
        // loads), so the grid is not held beside it (45 MB at 1 M unknowns).
        let grid = OnceLock::new();
        // All VTU writer threads are joined before the scope ends.
        let this = &*self;
        let result = std::thread::scope(|scope| {
            this.solve_and_write(scope, &grid, out, &mut log, progress, stop)
        });
        let result = result.and_then(|_| self.finish_run(out, &mut log, &clock));
        match result {
            Ok(summary) => Ok(summary),
            Err(e) => match self.record_stop(out, &mut log.summary, &clock, &e) {
                Ok(()) => Err(e),
                Err(w) => {
                    // Not even the summary could be written: a stale one saying
                    // `running` must not stay behind.
                    let summary = out.join("summary.json");
                    let removed = match std::fs::remove_file(&summary) {
                        Ok(()) => "the stale summary.json was removed",
                        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                            "no summary.json was written"
                        }
                        Err(_) => "summary.json is stale",
                    };
                    Err(Error::output(
                        &summary,
                        format!("{e}; the failure could not be recorded ({w}); {removed}"),
                    ))
                }
            },
        }
    }

    /// Solves the increments, writing each converged one (see
    /// [`Analysis::write_increment`]) and stopping once `stop` is nonzero, then
    /// draws the pictures of the last increment while the last writers finish.
    /// Solver statistics go into the summary either way. An error of the solver
    /// comes first, then one of a writer, then one of the pictures; after an
    /// error no picture stays on disk.
    fn solve_and_write<'scope, 'env: 'scope>(
        &'env self,
        scope: &'scope Scope<'scope, 'env>,
        grid: &'env OnceLock<PartsGrid>,
        out: &Path,
        log: &mut RunLog,
        progress: &mut dyn FnMut(&IncrementResult),
        stop: &'env AtomicUsize,
    ) -> Result<()> {
        let mut series = Series::new(out, stop);
        // Read from the symbolic analysis on, and inside the increments: a long
        // search stops within its next iteration, fixed-point step or solve.
        let mut solver = match self.solver_until(Some(stop)) {
            Ok(solver) => solver,
            Err(e) => {
                // `results.pvd` is written whatever happens (naming no increment).
                let _ = series.finish();
                return Err(e);
            }
        };
        self.prepare_solver(&mut solver, &mut log.summary);
        let r = solver.run(|inc| {
            self.write_increment(scope, grid, inc, &mut series, log, out)?;
            progress(inc);
            match stop.load(Ordering::Relaxed) {
                0 => Ok(()),
                signal => Err(Error::Interrupted {
                    increment: inc.index,
                    signal,
                }),
            }
        });
        let summary = &mut log.summary;
        summary.timings.solve = solver.timings.clone();
        (summary.factorizations, summary.low_rank_updates) = solver.solve_counts();
        summary.first_factorization_seconds = solver.first_factorization_seconds();
        summary.solve_flops = solver.solve_flops();
        // The factor is not needed for the pictures or the writers still in flight.
        drop(solver);
        // The pictures of the last increment are drawn while its parts VTU (and
        // any other writer in flight) still streams in the background.
        let pictures = r.as_ref().ok().map(|inc| {
            let t = Instant::now();
            let drawn = self.draw_pictures(out, inc, log, stop);
            log.summary.timings.pictures = t.elapsed().as_secs_f64();
            drawn
        });
        let t = Instant::now();
        let written = series.finish();
        log.output_time += t.elapsed().as_secs_f64();
        note_abandoned(&mut log.summary, &series.abandoned);
        r?;
        let drawn = pictures.unwrap_or(Ok(()));
        if written.is_err() || drawn.is_err() {
            // Pictures belong to a successful run only (after a writer's failure
            // they would show an increment whose parts VTU is missing).
            remove_pictures(out, &log.folder);
        }
        written.and(drawn)
    }

    /// The pictures of the last converged increment `inc`, from the stresses the
    /// run kept for it (recovered anew only if it kept none). A nonzero `stop`
    /// ends the drawing at its next check ([`png::Proceed`]) with
    /// [`Error::Interrupted`]; the caller then removes the pictures.
    fn draw_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult,
        log: &mut RunLog,
        stop: &AtomicUsize,
    ) -> Result<()> {
        let proceed = || match stop.load(Ordering::Relaxed) {
            0 => Ok(()),
            signal => Err(Error::Interrupted {
                increment: inc.index,
                signal,
            }),
        };
        proceed()?;
        // `pressure.png` is drawn only with a contact law (see
        // `write_pressure_chart`).
        let pressure = self.interfaces.iter().any(|i| i.law != Law::Rigid);
        for f in PICTURES {
            if f != PICTURES[2] || pressure {
                log.folder.claim(f)?;
            }
        }
        let stresses = match log.last_stresses.take() {
            Some(s) => s,
            None => Stresses {
                base: Arc::new(self.recover(&inc.u)),
                factors: Vec::new(),
            },
        };
        self.write_pictures(out, inc, &stresses, &proceed)
    }

    /// The coarse start (if the settings ask for it) and the matrix sizes.
    fn prepare_solver(&self, solver: &mut Solver<'_>, summary: &mut Summary) {
        let t = Instant::now();
        if self.model.settings.start == crate::domain::StartPattern::Coarse
            && let Some(states) = self.coarse_states()
        {
            solver.set_initial_states(states);
        }
        summary.timings.coarse_start = t.elapsed().as_secs_f64();
        summary.matrix_nonzeros = solver.matrix_nnz();
        summary.factor_nonzeros = solver.factor_nnz();
    }

    /// Writes one converged increment: recovers its stresses, starts its parts VTU
    /// in the background, writes its pairs VTU and the pairs table, and updates
    /// the summary on disk. Only every `output_every`-th increment, the last and
    /// (with load steps) the last of each step have their files written; the
    /// summary is rewritten at a bounded rate (see [`REWRITE_FREELY`]).
    fn write_increment<'scope, 'env: 'scope>(
        &'env self,
        scope: &'scope Scope<'scope, 'env>,
        grid: &'env OnceLock<PartsGrid>,
        inc: &IncrementResult,
        series: &mut Series<'scope>,
        log: &mut RunLog,
        out: &Path,
    ) -> Result<()> {
        let settings = &self.model.settings;
        // The last increment of the run, and with load steps of every step, is
        // always written.
        let step_end = self.model.steps.len() > 1 && inc.lambda >= 1.0;
        let files = inc.index.is_multiple_of(settings.output_every.max(1))
            || inc.index >= settings.increments
            || step_end;
        let t = Instant::now();
        if !files {
            self.fill_summary(&mut log.summary, inc, &self.pair_rows(inc));
            if rewrite_due(&mut log.summary_written, inc.index) {
                report::write_json(&out.join("summary.json"), &log.summary)?;
            }
            log.output_time += t.elapsed().as_secs_f64();
            return Ok(());
        }
        let stresses = match (&log.last_stresses, log.last_multiple, inc.multiple_of) {
            (Some(s), Some(a), Some(b)) if a.solution == b.solution && a.factor != 0.0 => {
                s.times(b.factor / a.factor)
            }
            _ => Stresses {
                base: Arc::new(self.recover(&inc.u)),
                factors: Vec::new(),
            },
        };
        log.last_multiple = inc.multiple_of;
        log.recovery_time += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let rows = self.pair_rows(inc);
        let parts_file = format!("parts_{:04}.vtu", inc.index);
        let pairs_file = format!("pairs_{:04}.vtu", inc.index);
        for file in [&parts_file, &pairs_file] {
            log.folder.claim(&format!("{VTU}/{file}"))?;
        }
        series.make_room()?;
        let (path, fields, u) = (
            series.vtu_dir.join(&parts_file),
            time_fields(inc),
            inc.u.clone(),
        );
        log.last_stresses = Some(stresses.clone());
        let grid = grid.get_or_init(|| self.parts_grid());
        let (stop, index) = (series.stop, inc.index);
        // A named thread ("cfe-vtu"), so profiles and debuggers tell it apart.
        let handle = std::thread::Builder::new()
            .name("cfe-vtu".into())
            .spawn_scoped(scope, move || {
                let written = self.write_parts_vtu(&path, grid, &fields, &u, &stresses, stop);
                // Abandoned at a stop: the run's increments before this one
                // are the last complete on disk.
                match stop.load(Ordering::Relaxed) {
                    0 => written,
                    signal => written.map_err(|_| Error::Interrupted {
                        increment: index.saturating_sub(1),
                        signal,
                    }),
                }
            })
            .map_err(|e| {
                Error::output(&series.vtu_dir, format!("cannot start a VTU writer: {e}"))
            })?;
        self.write_pairs_vtu(&series.vtu_dir.join(&pairs_file), inc, &rows)?;
        series.push(handle, inc.index, inc.time, parts_file, pairs_file);
        log.folder.claim("pairs.csv")?;
        report::write_pairs_csv(&out.join("pairs.csv"), &rows)?;
        self.fill_summary(&mut log.summary, inc, &rows);
        if rewrite_due(&mut log.summary_written, inc.index) {
            report::write_json(&out.join("summary.json"), &log.summary)?;
        }
        log.output_time += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Records a run that stopped with `e` (failed or interrupted) in
    /// `summary.json`.
    fn record_stop(
        &self,
        out: &Path,
        summary: &mut Summary,
        clock: &RunClock,
        e: &Error,
    ) -> Result<()> {
        summary.status = if matches!(e, Error::Interrupted { .. }) {
            RunStatus::Interrupted
        } else {
            RunStatus::Failed
        };
        summary.error = Some(e.to_string());
        summary.timings.set_totals(&self.timings, clock);
        summary.peak_memory_bytes = peak_memory_bytes();
        report::write_json(&out.join("summary.json"), summary)
    }

    /// Finishes a run whose increments all converged and whose files (pictures
    /// included) are all written: the final status and timings in `summary.json`.
    fn finish_run(&mut self, out: &Path, log: &mut RunLog, clock: &RunClock) -> Result<Summary> {
        let summary = &mut log.summary;
        summary.status = summary.final_status();
        summary.timings.meshing = self.timings.meshing;
        summary.timings.pair_search = self.timings.pair_search;
        summary.timings.stress_recovery = log.recovery_time;
        summary.timings.output = log.output_time;
        summary.timings.set_totals(&self.timings, clock);
        summary.peak_memory_bytes = peak_memory_bytes();
        summary.set_ratios();
        report::write_json(&out.join("summary.json"), summary)?;
        self.timings = summary.timings.clone();
        Ok(summary.clone())
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

    /// The parts' geometry for the VTU files, built once per run (at its first
    /// written increment).
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
            geometry: vtu::Geometry::new(&self.global_points(), &connectivity, &offsets, &kinds),
            part_point,
            part_cell,
        }
    }

    fn write_parts_vtu(
        &self,
        path: &Path,
        grid: &PartsGrid,
        fields: &[(&str, f64)],
        u: &[f64],
        stresses: &Stresses,
        stop: &AtomicUsize,
    ) -> Result<()> {
        let (part_point, part_cell) = (&grid.part_point, &grid.part_cell);
        let mut nodal: [Vec<f64>; 4] =
            std::array::from_fn(|_| Vec::with_capacity(part_point.len()));
        let mut cell: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(part_cell.len()));
        for (part, s) in self.model.parts.iter().zip(stresses.base.iter()) {
            for v in &s.nodal {
                let v = stresses.value(*v);
                for c in 0..3 {
                    nodal[c].push(v[c]);
                }
                nodal[3].push(part.material.von_mises(v));
            }
            for v in &s.element {
                let v = stresses.value(*v);
                for c in 0..3 {
                    cell[c].push(v[c]);
                }
                cell[3].push(part.material.von_mises(v));
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
        vtu::write_on_until(
            path,
            &grid.geometry,
            &vtu::Fields {
                point_data: &point_data,
                cell_data: &cell_data,
                field_data: fields,
            },
            stop,
        )
    }

    fn write_pairs_vtu(&self, path: &Path, inc: &IncrementResult, rows: &[PairRow]) -> Result<()> {
        let points: Vec<[f64; 2]> = rows.iter().map(|r| [r.x, r.y]).collect();
        let connectivity: Vec<usize> = (0..rows.len()).collect();
        let offsets: Vec<usize> = (1..=rows.len()).collect();
        let kinds: Vec<vtu::CellKind> = rows.iter().map(|_| vtu::CellKind::Vertex).collect();
        let bonded: Vec<i32> = rows
            .iter()
            .map(|r| (r.state == PairState::Bonded) as i32)
            .collect();
        let settled: Vec<i32> = rows.iter().map(|r| r.settled as i32).collect();
        // 0: the law holds; 1: a bonded pair pulls; 2: an open pair penetrates;
        // 3: a stick pair exceeds μ|f_n|; 4: a slip pair is off μ|f_n|.
        let violation: Vec<i32> = rows
            .iter()
            .map(|r| match r.violation {
                None => 0,
                Some(ViolationKind::Tension) => 1,
                Some(ViolationKind::Penetration) => 2,
                Some(ViolationKind::Friction) => 3,
                Some(ViolationKind::Slip) => 4,
            })
            .collect();
        // 0: open, 1: bonded (stick), 2: slip.
        let state: Vec<i32> = rows
            .iter()
            .map(|r| match r.state {
                PairState::Open => 0,
                PairState::Bonded => 1,
                PairState::Slip => 2,
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
        let contact = [
            ("gap0", col(|r| r.gap0)),
            ("gap", col(|r| r.gap)),
            ("slip", col(|r| r.slip)),
            ("pressure", col(|r| r.pressure)),
            ("shear", col(|r| r.shear)),
            ("tributary", col(|r| r.tributary)),
        ];
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
        let mut point_data = vec![
            vtu::DataArray::f64("displacement", 2, &disp),
            vtu::DataArray::i32("bonded", &bonded),
            vtu::DataArray::i32("settled", &settled),
            vtu::DataArray::i32("violation", &violation),
            vtu::DataArray::f64("violation_amount", 1, &violation_amount),
            vtu::DataArray::f64("gap_n", 1, &gap),
            vtu::DataArray::f64("slip_s", 1, &slip),
            vtu::DataArray::f64("force_n", 1, &fn_),
            vtu::DataArray::f64("force_s", 1, &fs),
            vtu::DataArray::f64("normal", 2, &normal),
            vtu::DataArray::i32("interface_id", &iface_id),
            vtu::DataArray::i32("state", &state),
        ];
        for (name, values) in &contact {
            point_data.push(vtu::DataArray::f64(name, 1, values));
        }
        vtu::write_vtu(
            path,
            &vtu::Grid {
                points: &points,
                connectivity: &connectivity,
                offsets: &offsets,
                kinds: &kinds,
                point_data: &point_data,
                cell_data: &[],
                field_data: &time_fields(inc),
            },
        )
    }

    fn write_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult,
        stresses: &Stresses,
        proceed: png::Proceed<'_>,
    ) -> Result<()> {
        let points = self.global_points();
        let tris = self.plot_triangles();
        let outline = png::outline_edges(&tris);
        let syy: Vec<f64> = stresses
            .base
            .iter()
            .flat_map(|s| s.nodal.iter().map(|v| stresses.value(*v)[1]))
            .collect();
        let rows = self.pair_rows(inc);
        let markers: Vec<png::PairMarker> = rows
            .iter()
            .map(|r| png::PairMarker {
                at: [r.x, r.y],
                bonded: r.state.is_closed(),
                slip: r.state == PairState::Slip,
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
                proceed,
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
                    bonded: r.state.is_closed(),
                    slip: r.state == PairState::Slip,
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
                proceed,
            )
        };
        let (a, b) = rayon::join(field, isolines);
        a.and(b)?;
        proceed()?;
        self.write_pressure_chart(out, &rows).map(|_| ())
    }

    /// `pressure.png`: the contact pressure of every pair along each interface
    /// with a contact law (one curve per interface, against x, or y where the
    /// interface spans more in y); `false` when no interface has a contact law
    /// with pairs.
    fn write_pressure_chart(&self, out: &Path, rows: &[PairRow]) -> Result<bool> {
        let mut series = Vec::new();
        let mut along_y = 0;
        for iface in self.interfaces.iter().filter(|i| i.law != Law::Rigid) {
            let mine: Vec<&PairRow> = rows.iter().filter(|r| r.interface == iface.name).collect();
            // An interface without pairs has no curve (a chart of no curve is
            // not drawn): never a failed picture.
            if mine.is_empty() {
                continue;
            }
            let span = |f: fn(&PairRow) -> f64| {
                let (lo, hi) = mine
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                        (lo.min(f(r)), hi.max(f(r)))
                    });
                hi - lo
            };
            let use_y = span(|r| r.y) > span(|r| r.x);
            along_y += usize::from(use_y);
            let mut points: Vec<(f64, f64)> = mine
                .iter()
                .map(|r| (if use_y { r.y } else { r.x }, r.pressure))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            series.push(chart::Series {
                name: iface.name.clone(),
                points,
                reference: false,
            });
        }
        if series.is_empty() {
            return Ok(false);
        }
        let units = &self.model.units;
        let axis = if along_y == series.len() { "y" } else { "x" };
        chart::line_chart(
            &out.join("pressure.png"),
            &chart::Axes {
                title: &format!("{}: contact pressure along the interface", self.model.title),
                x: &format!("{axis} [{}]", units.length),
                y: &format!("pressure [{}]", units.stress),
                log_x: false,
                log_y: false,
            },
            &series,
        )?;
        Ok(true)
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

/// Scaling factors a [`Stresses`] applies in turn before it materializes the
/// scaled values (so a long run of multiples costs a bounded number of
/// multiplications per value).
const MAX_FACTORS: usize = 8;

/// The stresses of a written increment: `base` (recovered from a solution)
/// scaled by each of `factors` in turn. An increment that is a multiple of the
/// same linear solution shares `base` with the increments before it (the
/// writers scale while they read) instead of holding a scaled copy; the values
/// are bit for bit those of successive [`PartStress::scaled`] calls.
#[derive(Clone)]
struct Stresses {
    base: Arc<Vec<PartStress>>,
    factors: Vec<f64>,
}

impl Stresses {
    /// The stress `v` of `base` as this increment's.
    fn value(&self, v: [f64; 3]) -> [f64; 3] {
        scaled_in_turn(v, &self.factors)
    }

    /// These stresses times `factor`: shares `base`, or, once [`MAX_FACTORS`]
    /// factors are pending, a new base holding the scaled values.
    fn times(&self, factor: f64) -> Stresses {
        if self.factors.len() < MAX_FACTORS {
            let mut factors = self.factors.clone();
            factors.push(factor);
            return Stresses {
                base: Arc::clone(&self.base),
                factors,
            };
        }
        let base = self
            .base
            .iter()
            .map(|p| p.scaled_in_turn(&self.factors))
            .collect();
        Stresses {
            base: Arc::new(base),
            factors: Vec::new(),
        }
        .times(factor)
    }
}

/// The parts' points and cells as written to every VTU of a run (checked and
/// encoded once), and the part of each point and cell.
struct PartsGrid {
    geometry: vtu::Geometry,
    part_point: Vec<i32>,
    part_cell: Vec<i32>,
}

/// The field data of an increment's VTU files: the total time (step index − 1 +
/// load factor), the step's 1-based index and its load factor.
fn time_fields(inc: &IncrementResult) -> [(&'static str, f64); 3] {
    [
        ("TIME", inc.time),
        ("STEP", (inc.step + 1) as f64),
        ("LOAD_FACTOR", inc.lambda),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward stresses (round-off in every scaling) of two small parts.
    fn sample() -> Vec<PartStress> {
        let v = |k: f64| [1.0 / 3.0 * k, -7.1e5 / k, 0.1 + k];
        vec![
            PartStress {
                element: (1..4).map(|k| v(k as f64)).collect(),
                nodal: (1..6).map(|k| v(k as f64 * 0.7)).collect(),
            },
            PartStress {
                element: vec![v(11.0)],
                nodal: vec![v(0.3), v(1e-9)],
            },
        ]
    }

    /// A run of multiples scaled in turn through shared stresses (past the
    /// materialization after `MAX_FACTORS`) gives, bit for bit, the values of
    /// scaling a copy at every increment, as the run did before sharing.
    #[test]
    fn shared_stresses_scale_like_copies() {
        let factors: Vec<f64> = (0..3 * MAX_FACTORS + 2)
            .map(|i| 1.0 + 0.1 * (i as f64 + 1.0) / 3.0)
            .collect();
        let mut copies = sample();
        let first = Arc::new(sample());
        let mut shared = Stresses {
            base: Arc::clone(&first),
            factors: Vec::new(),
        };
        for (i, &f) in factors.iter().enumerate() {
            copies = copies.iter().map(|p| p.scaled(f)).collect();
            shared = shared.times(f);
            // Shared until MAX_FACTORS are pending, then materialized.
            assert_eq!(Arc::ptr_eq(&shared.base, &first), i < MAX_FACTORS, "{i}");
            assert!(shared.factors.len() <= MAX_FACTORS);
            for (c, s) in copies.iter().zip(shared.base.iter()) {
                for (a, b) in [(&c.element, &s.element), (&c.nodal, &s.nodal)] {
                    let b: Vec<[f64; 3]> = b.iter().map(|&v| shared.value(v)).collect();
                    let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                        v.iter().map(|s| s.map(f64::to_bits)).collect()
                    };
                    assert_eq!(bits(a), bits(&b));
                }
            }
        }
    }
}
