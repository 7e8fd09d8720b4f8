//! The run loop, above the analysis and the writers: drives an [`Analysis`]
//! (plane or solid: one loop over [`RunDim`], whose instances state what each
//! dimension writes differently) through its increments and hands each converged one to the writers as it
//! converges (VTU + PVD series, pairs CSV, JSON summary), so results survive a
//! later failure; the pictures of the last increment are drawn while its parts
//! VTU is still being written. The large parts VTU of each increment is written
//! by a background thread ([`Series`]). The output folder's safety (manifest,
//! lock, atomic writes) is [`crate::output::folder`]'s; what the files hold is
//! laid out in `layout` (VTU grids and fields) and `pictures` (plane) or
//! `solid` (solid pictures and fields), from the analysis, and written by
//! [`crate::output`] from plain data.

mod dim;
mod layout;
mod lines;
mod pictures;
mod plane;
mod solid;
mod stresses;

pub use dim::RunDim;

use crate::analysis::Analysis;
use crate::error::{Error, Result};
use crate::output::folder::{OutputFolder, VTU};
use crate::output::report;
use crate::output::vtu;
use crate::results::history::HistoryRow;
use crate::results::memory::peak_memory_bytes;
use crate::results::summary::{RunClock, RunStatus, Summary, Warning};
use crate::solve::nonlinear::Solver;
use crate::solve::nonlinear::{IncrementResult, MultipleOf};
use layout::{PartsGrid, time_fields};
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::Instant;
use stresses::Stresses;

/// Removes the pictures of a run that failed after drawing them, those it
/// listed in the folder's manifest (best effort: the run's error is what gets
/// reported).
fn remove_pictures(out: &Path, folder: &OutputFolder, pictures: &[String]) {
    for f in pictures.iter().filter(|f| folder.lists(f)) {
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

/// What a run accumulates while its increments are solved and written (`S`:
/// the dimension's stress).
struct RunLog<S> {
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
    last_stresses: Option<Stresses<S>>,
    /// The linear solution `last_stresses` were recovered from a multiple of
    /// (proportional shortcuts): an increment that is another multiple of it
    /// scales them instead of recovering again.
    last_multiple: Option<MultipleOf>,
    /// The pictures claimed in the folder's manifest (removed again if the run
    /// fails after drawing them).
    pictures: Vec<String>,
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

/// Writes `summary.json`, then the history it holds as `history.csv` (the run
/// claimed both before its first increment).
fn write_summary(out: &Path, summary: &Summary) -> Result<()> {
    report::write_json(&out.join("summary.json"), summary)?;
    report::write_history_csv(&out.join("history.csv"), &summary.history)
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

impl<D: RunDim> Analysis<D> {
    /// Solves all increments and writes the results into `out`. `progress` is called
    /// after each converged increment. On failure the converged increments stay on
    /// disk and `summary.json` records the error. A plane analysis and a solid one
    /// (`Analysis<D3>`) write the same files, the solid one with 3D cells and
    /// columns, and `deformed.png` and a `pressure_<k>.png` per contact
    /// interface instead of the plane pictures (README, *Outputs of a solid
    /// model*); line probes are plane only.
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
        progress: &mut dyn FnMut(&IncrementResult<D>),
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
        progress: &mut dyn FnMut(&IncrementResult<D>),
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
        folder: OutputFolder,
        progress: &mut dyn FnMut(&IncrementResult<D>),
        stop: &AtomicUsize,
    ) -> Result<Summary> {
        self.run_recorded_in(folder, &mut |inc, _| progress(inc), stop)
    }

    /// [`Analysis::run_in`] handing `progress` each converged increment with its
    /// row of the run's history (the row `history.csv` and the summary's
    /// `history` get for it: reactions, contact resultants, probe
    /// displacements), once the increment is written.
    pub fn run_recorded_in(
        &mut self,
        mut folder: OutputFolder,
        progress: &mut dyn FnMut(&IncrementResult<D>, &HistoryRow),
        stop: &AtomicUsize,
    ) -> Result<Summary> {
        let clock = RunClock::start();
        folder.start()?;
        // Written whatever happens next (a failure is recorded in the summary).
        for f in ["summary.json", "results.pvd", "history.csv"] {
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
            pictures: Vec::new(),
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
        log: &mut RunLog<D::Stress>,
        progress: &mut dyn FnMut(&IncrementResult<D>, &HistoryRow),
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
        self.prepare_solver(&mut solver, &mut log.summary, stop);
        let r = solver.run(|inc| {
            self.write_increment(scope, grid, inc, &mut series, log, out)?;
            if let Some(row) = log.summary.history.last() {
                progress(inc, row);
            }
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
        summary.linear_solver = solver.iterative_solves().cloned();
        // The factor is not needed for the pictures or the writers still in flight.
        drop(solver);
        // The pictures of the last increment are drawn while its parts VTU (and
        // any other writer in flight) still streams in the background.
        // The whole history, before the pictures (a failure here leaves none).
        let history = r
            .as_ref()
            .ok()
            .map(|_| report::write_history_csv(&out.join("history.csv"), &log.summary.history));
        let history = history.unwrap_or(Ok(()));
        let pictures = r.as_ref().ok().filter(|_| history.is_ok()).map(|inc| {
            let t = Instant::now();
            let drawn = self
                .draw_pictures(out, inc, log, stop)
                .and_then(|_| D::write_lines(self, out, inc, &mut log.folder));
            log.summary.timings.pictures = t.elapsed().as_secs_f64();
            drawn
        });
        let t = Instant::now();
        let written = series.finish();
        log.output_time += t.elapsed().as_secs_f64();
        note_abandoned(&mut log.summary, &series.abandoned);
        r?;
        history?;
        let drawn = pictures.unwrap_or(Ok(()));
        if written.is_err() || drawn.is_err() {
            // Pictures belong to a successful run only (after a writer's failure
            // they would show an increment whose parts VTU is missing).
            remove_pictures(out, &log.folder, &log.pictures);
        }
        written.and(drawn)
    }

    /// The pictures of the last converged increment `inc`, from the stresses the
    /// run kept for it (recovered anew only if it kept none). A nonzero `stop`
    /// ends the drawing at its next check ([`crate::output::png::Proceed`]) with
    /// [`Error::Interrupted`]; the caller then removes the pictures.
    fn draw_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult<D>,
        log: &mut RunLog<D::Stress>,
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
        for f in D::pictures(self) {
            log.folder.claim(&f)?;
            log.pictures.push(f);
        }
        self.write_history_chart(out, &log.summary.history)?;
        proceed()?;
        let stresses = match log.last_stresses.take() {
            Some(s) => s,
            None => Stresses::recovered(self.recover(&inc.u)),
        };
        D::write_pictures(self, out, inc, &stresses, &proceed)
    }

    /// The coarse start (if the settings ask for it; its coarse solves read
    /// `stop`) and the matrix sizes.
    fn prepare_solver(
        &self,
        solver: &mut Solver<'_, D>,
        summary: &mut Summary,
        stop: &AtomicUsize,
    ) {
        let t = Instant::now();
        if self.model.settings.start == crate::domain::StartPattern::Coarse
            && let Some(states) = self.coarse_states_until(Some(stop))
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
        inc: &IncrementResult<D>,
        series: &mut Series<'scope>,
        log: &mut RunLog<D::Stress>,
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
                write_summary(out, &log.summary)?;
            }
            log.output_time += t.elapsed().as_secs_f64();
            return Ok(());
        }
        let stresses = match (&log.last_stresses, log.last_multiple, inc.multiple_of) {
            (Some(s), Some(a), Some(b)) if a.solution == b.solution && a.factor != 0.0 => {
                s.times(b.factor / a.factor)
            }
            _ => Stresses::recovered(self.recover(&inc.u)),
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
        report::write_pairs_table(&out.join("pairs.csv"), &rows, D::PAIR_COLUMNS)?;
        D::write_line_increment(self, out, inc, &mut log.folder)?;
        self.fill_summary(&mut log.summary, inc, &rows);
        if rewrite_due(&mut log.summary_written, inc.index) {
            write_summary(out, &log.summary)?;
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
        report::write_json(&out.join("summary.json"), summary)?;
        // Best effort: the summary that records the failure comes first.
        let _ = report::write_history_csv(&out.join("history.csv"), &summary.history);
        Ok(())
    }

    /// Finishes a run whose increments all converged and whose files (pictures
    /// included) are all written: the final status and timings in `summary.json`.
    fn finish_run(
        &mut self,
        out: &Path,
        log: &mut RunLog<D::Stress>,
        clock: &RunClock,
    ) -> Result<Summary> {
        let summary = &mut log.summary;
        summary.status = summary.final_status();
        summary.timings.meshing = self.timings.meshing;
        summary.timings.pair_search = self.timings.pair_search;
        summary.timings.stress_recovery = log.recovery_time;
        summary.timings.output = log.output_time;
        summary.timings.set_totals(&self.timings, clock);
        summary.peak_memory_bytes = peak_memory_bytes();
        summary.set_ratios();
        // `history.csv` is whole already (written before the pictures).
        report::write_json(&out.join("summary.json"), summary)?;
        self.timings = summary.timings.clone();
        Ok(summary.clone())
    }
}
