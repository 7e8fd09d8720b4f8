//! Output: the writers of what an analysis produced (VTU series, pairs CSV, JSON
//! summary, PNG pictures) into a results folder; the summary types they write are
//! [`crate::results`]. The writers take plain data (points, cells, named field
//! arrays); the run loop (`crate::run`) lays them out from the analysis. Every file is written atomically: to a
//! temporary name first, then renamed, so a crash never leaves a half-written file.

pub mod chart;
pub mod folder;
pub(crate) mod png;
pub mod report;
pub mod view3d;
pub mod vtu;

// Results vocabulary, at its former paths (`output::summary::Summary`,
// `output::fmt::num`, `output::memory::peak_memory_bytes`).
pub use crate::results::{fmt, memory, summary};

use crate::error::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Writes still allowed before injected faults start (`usize::MAX`: no faults).
static WRITES_BEFORE_FAULT: AtomicUsize = AtomicUsize::new(usize::MAX);
/// Whether injected faults spare `summary.json`.
static SPARE_SUMMARY: AtomicBool = AtomicBool::new(false);

/// Test hook: simulates a full disk. After `after` more successful file writes,
/// every write fails with "No space left on device" (`None` turns the faults
/// off); with `spare_summary`, writes of `summary.json` neither fail nor count
/// (a disk with just enough room left for the small summary). Process-wide: use
/// it from a test binary of its own.
#[doc(hidden)]
pub fn inject_write_faults(after: Option<usize>, spare_summary: bool) {
    SPARE_SUMMARY.store(spare_summary, Ordering::SeqCst);
    WRITES_BEFORE_FAULT.store(after.unwrap_or(usize::MAX), Ordering::SeqCst);
}

/// Takes one write from the injected budget: an error once it is spent.
fn injected_fault() -> std::io::Result<()> {
    let spent = WRITES_BEFORE_FAULT
        .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| match n {
            usize::MAX => Some(usize::MAX),
            0 => None,
            n => Some(n - 1),
        })
        .is_err();
    if spent {
        Err(std::io::Error::new(
            std::io::ErrorKind::StorageFull,
            "No space left on device (injected)",
        ))
    } else {
        Ok(())
    }
}

/// The temporary name a file named `file_name` is written under, beside it, before
/// it is renamed into place: `.NAME.tmp` (see [`write_atomic`]).
pub fn temporary_name(file_name: &str) -> String {
    format!(".{file_name}.tmp")
}

/// Writes a file atomically: `fill` writes the content into a buffered temporary file
/// beside `path`, which is then renamed over `path`.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let file_name = path
        .file_name()
        .ok_or_else(|| Error::output(path, "not a file path"))?
        .to_string_lossy()
        .into_owned();
    let tmp = path.with_file_name(temporary_name(&file_name));
    let result = (|| -> std::io::Result<()> {
        let file = std::fs::File::create(&tmp)?;
        let mut w = BufWriter::with_capacity(1 << 20, file);
        fill(&mut w)?;
        if !(file_name == "summary.json" && SPARE_SUMMARY.load(Ordering::SeqCst)) {
            injected_fault()?;
        }
        w.flush()?;
        // No fsync: the rename makes the file appear whole or not at all if cfe
        // stops; durability against power loss is left to the operating system.
        drop(w.into_inner().map_err(|e| e.into_error())?);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::output(path, e)
    })
}
