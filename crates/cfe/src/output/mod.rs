//! Output: the summary types of a run, and the writers of what an analysis produced
//! (VTU series, pairs CSV, JSON summary, PNG pictures) into a results folder. Every file is written atomically: to a
//! temporary name first, then renamed, so a crash never leaves a half-written file.

pub mod chart;
pub mod memory;
pub(crate) mod png;
pub mod report;
pub(crate) mod run;
pub mod summary;
pub mod vtu;

use crate::error::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::Path;

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
    let tmp = path.with_file_name(format!(".{file_name}.tmp"));
    let result = (|| -> std::io::Result<()> {
        let file = std::fs::File::create(&tmp)?;
        let mut w = BufWriter::with_capacity(1 << 20, file);
        fill(&mut w)?;
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
