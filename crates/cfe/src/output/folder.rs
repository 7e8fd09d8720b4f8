//! The output folder of a run: cfe deletes and overwrites there only what it
//! wrote.
//!
//! * **Lock.** A run holds the folder's lock file, [`LOCK`] (`.cfe-lock`), for as
//!   long as it writes: an advisory lock of the operating system (`flock`) on that
//!   file, which holds the run's process id. A second run into the same folder is
//!   refused with [`Error::OutputFolderInUse`], naming that process. The system
//!   releases the lock when its process ends, however it ends, so a lock file left
//!   by a killed run never blocks a later one. The run removes the file when it
//!   ends.
//! * **Manifest.** Before a run creates a file, it lists it, and the temporary
//!   name it is written under (`.NAME.tmp`, see [`super::write_atomic`]), in the
//!   folder's manifest, [`MANIFEST`] (`.cfe-manifest`: a first line
//!   [`MANIFEST_HEADER`], then one path relative to the folder per line). The next
//!   run removes exactly the files its manifest lists, and nothing else.
//! * **Checks first.** Before it removes anything, a run checks the whole folder
//!   and refuses it, touching nothing, when
//!   - it is not empty and holds no cfe run (no manifest), or holds files at the
//!     names a run writes that its manifest does not list
//!     ([`Error::OutputFolderNotOurs`], naming them). With `force` both are
//!     accepted: the files at the names a run writes are replaced, every other
//!     file is left alone;
//!   - `vtu` or `lines` is not a folder of its own (a symbolic link, a file), or a name a run
//!     writes is taken by a folder ([`Error::OutputPathBlocked`]; `force` does
//!     not override: cfe never writes or deletes through a link inside its output
//!     folder, and never removes a folder).
//!
//! The names a run writes are [`RUN_FILES`] and `pressure_N.png` (a solid run's
//! contact pressure maps, N digits) in the folder and
//! `vtu/parts_N.vtu`, `vtu/pairs_N.vtu` (N: digits), `lines/NAME.csv` and
//! `lines/NAME.png` (a line probe's; NAME of letters, digits, `-` and `_`), each
//! with its temporary name — the files inside `vtu/` and `lines/` are checked as
//! those of the folder itself; [`MANIFEST`], its temporary `.cfe-manifest.tmp` and [`LOCK`] are cfe's
//! own.

use crate::error::{Error, Result};
use std::collections::HashSet;
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// The manifest: the files the last run into the folder wrote.
pub const MANIFEST: &str = ".cfe-manifest";
/// The first line of a manifest (its format and version).
pub const MANIFEST_HEADER: &str = "cfe output manifest 1";
/// The manifest while it is written, before it is renamed into place.
const MANIFEST_TMP: &str = ".cfe-manifest.tmp";
/// The lock file a run holds while it writes.
pub const LOCK: &str = ".cfe-lock";
/// The folder of the VTU series.
pub const VTU: &str = "vtu";
/// The folder of the line probes' tables and charts (`lines/<name>.csv`,
/// `lines/<name>.png`).
pub const LINES: &str = "lines";
/// The pictures a successful plane run draws into its output folder.
pub const PICTURES: [&str; 4] = [
    "sigma_yy.png",
    "displacement.png",
    "pressure.png",
    "history.png",
];
/// The pictures of the parts a successful solid run draws into its output
/// folder (besides `history.png` and a contact pressure map per contact
/// interface, [`pressure_map_file`]).
pub const SOLID_PICTURES: [&str; 1] = ["deformed.png"];
/// The files a run writes into its output folder (besides `vtu/`, `lines/` and
/// a solid run's pressure maps, [`pressure_map_file`]).
pub const RUN_FILES: [&str; 9] = [
    "summary.json",
    "pairs.csv",
    "results.pvd",
    "history.csv",
    PICTURES[0],
    PICTURES[1],
    PICTURES[2],
    PICTURES[3],
    SOLID_PICTURES[0],
];
/// The largest manifest read (a run of a million written increments lists about
/// 60 MB).
const MANIFEST_MAX_BYTES: u64 = 1 << 30;
/// How many names an error message lists (the error's `files` holds them all).
const LISTED: usize = 12;

/// `rel`'s temporary name (`vtu/parts_0001.vtu` → `vtu/.parts_0001.vtu.tmp`).
fn temporary(rel: &str) -> String {
    match rel.rsplit_once('/') {
        Some((dir, name)) => format!("{dir}/{}", super::temporary_name(name)),
        None => super::temporary_name(rel),
    }
}

/// The contact pressure map of a solid run's interface `k` (1-based, in the
/// model's order of interfaces): `pressure_<k>.png`.
pub fn pressure_map_file(k: usize) -> String {
    format!("pressure_{k}.png")
}

/// Whether `name` is a pressure map: `pressure_N.png`, N digits.
fn is_pressure_map(name: &str) -> bool {
    name.strip_prefix("pressure_")
        .and_then(|r| r.strip_suffix(".png"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// Whether `name` is a series file: `parts_N.vtu` or `pairs_N.vtu`, N digits.
fn is_series(name: &str) -> bool {
    ["parts_", "pairs_"].iter().any(|p| {
        name.strip_prefix(p)
            .and_then(|r| r.strip_suffix(".vtu"))
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// Whether `rel` (relative to the output folder, `/`-separated) is a name a run
/// writes: one of [`RUN_FILES`], a solid run's pressure map
/// ([`pressure_map_file`]), a series file in `vtu/`, a line probe's
/// `lines/<name>.csv` or `.png` or its table at an increment
/// `lines/<name>.<NNNN>.csv` ([`line_increment_file`]), or the temporary name
/// of one of them.
pub fn is_run_name(rel: &str) -> bool {
    let (dir, name) = match rel.split_once('/') {
        Some((dir, name)) => (Some(dir), name),
        None => (None, rel),
    };
    let file = name
        .strip_prefix('.')
        .and_then(|n| n.strip_suffix(".tmp"))
        .unwrap_or(name);
    match dir {
        None => RUN_FILES.contains(&file) || is_pressure_map(file),
        Some(VTU) => !file.contains('/') && is_series(file),
        Some(LINES) => {
            let line_name = |n: &str| {
                !n.is_empty()
                    && n.chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
            };
            let at_increment = |n: &str| {
                n.rsplit_once('.').is_some_and(|(line, k)| {
                    line_name(line) && !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit())
                })
            };
            [".csv", ".png"]
                .iter()
                .any(|ext| file.strip_suffix(ext).is_some_and(line_name))
                || file.strip_suffix(".csv").is_some_and(at_increment)
        }
        Some(_) => false,
    }
}

/// The table of line probe `line` at increment `increment` in the folder
/// [`LINES`]: `<line>.<NNNN>.csv` (the increment's number, at least 4 digits, as
/// the VTU series'; a line's name has no `.`, so it never meets another line's).
pub fn line_increment_file(line: &str, increment: usize) -> String {
    format!("{line}.{increment:04}.csv")
}

/// What a folder's manifest says about it.
enum Previous {
    /// No manifest: no cfe run wrote here.
    None,
    /// The files the last run listed.
    Run(HashSet<String>),
    /// A manifest cfe did not write (or one damaged), and why.
    Foreign(String),
}

/// Reads the manifest of `folder`. Only its complete lines count: a run killed
/// while it appended a name had not created that file yet.
fn read_manifest(folder: &Path) -> Result<Previous> {
    let path = folder.join(MANIFEST);
    let meta = match std::fs::symlink_metadata(&path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Previous::None),
        Err(e) => return Err(Error::output(&path, e)),
    };
    if !meta.file_type().is_file() {
        return Ok(Previous::Foreign("it is not a regular file".into()));
    }
    if meta.len() > MANIFEST_MAX_BYTES {
        return Ok(Previous::Foreign(format!(
            "it is larger than the {} MiB a manifest can be",
            MANIFEST_MAX_BYTES >> 20
        )));
    }
    let mut bytes = Vec::new();
    open_no_follow(&path, false)
        .and_then(|f| f.take(MANIFEST_MAX_BYTES).read_to_end(&mut bytes))
        .map_err(|e| Error::output(&path, format!("cannot read it: {e}")))?;
    let Ok(text) = String::from_utf8(bytes) else {
        return Ok(Previous::Foreign("it is not UTF-8 text".into()));
    };
    let mut lines = text.split_inclusive('\n');
    if lines.next() != Some(&format!("{MANIFEST_HEADER}\n")) {
        return Ok(Previous::Foreign(format!(
            "its first line is not `{MANIFEST_HEADER}`"
        )));
    }
    let mut files = HashSet::new();
    for (i, line) in lines.enumerate() {
        let Some(rel) = line.strip_suffix('\n') else {
            break;
        };
        if !is_run_name(rel) {
            return Ok(Previous::Foreign(format!(
                "its line {} `{rel}` is not a name cfe writes",
                i + 2
            )));
        }
        files.insert(rel.to_string());
    }
    Ok(Previous::Run(files))
}

/// Opens `path` for reading (or, with `write`, for reading and writing, created if
/// missing) without following a symbolic link at `path` itself.
fn open_no_follow(path: &Path, write: bool) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    if write {
        options.write(true).create(true).truncate(false);
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC);
    }
    #[cfg(not(unix))]
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(std::io::Error::other("a symbolic link"));
    }
    options.open(path)
}

/// The lock of an output folder, held while the value lives: its file is
/// removed (while still locked) when it is dropped.
struct Lock {
    path: PathBuf,
    /// The locked file; closing it releases the lock.
    _file: File,
}

impl Lock {
    /// Locks `folder` for this process, or refuses it when another holds it.
    fn acquire(folder: &Path) -> Result<Lock> {
        let path = folder.join(LOCK);
        // A run that finishes removes its lock file: a file locked after that
        // is no longer the folder's lock, so the lock is taken again on the file
        // now at the path.
        for _ in 0..100 {
            let mut file = open_no_follow(&path, true).map_err(|e| {
                Error::output(&path, format!("cannot open the output folder's lock: {e}"))
            })?;
            if !try_lock(&file)
                .map_err(|e| Error::output(&path, format!("cannot lock the output folder: {e}")))?
            {
                let mut text = String::new();
                let _ = file.take(64).read_to_string(&mut text);
                return Err(Error::OutputFolderInUse {
                    folder: folder.to_path_buf(),
                    pid: text.trim().parse().ok(),
                });
            }
            if is_at(&file, &path) {
                file.set_len(0)
                    .and_then(|_| writeln!(file, "{}", std::process::id()))
                    .map_err(|e| Error::output(&path, e))?;
                return Ok(Lock { path, _file: file });
            }
        }
        Err(Error::output(
            &path,
            "the output folder's lock file keeps being replaced",
        ))
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Takes the advisory lock of `file` without waiting: `false` when another
/// open file holds it (another process, or another run of this one).
fn try_lock(file: &File) -> std::io::Result<bool> {
    #[cfg(unix)]
    {
        use std::os::fd::AsRawFd;
        // SAFETY: flock takes a file descriptor, valid as long as `file` lives.
        let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
        if r == 0 {
            return Ok(true);
        }
        let e = std::io::Error::last_os_error();
        if e.kind() == std::io::ErrorKind::WouldBlock {
            Ok(false)
        } else {
            Err(e)
        }
    }
    #[cfg(not(unix))]
    {
        // No advisory lock elsewhere: the folder is not guarded against a
        // concurrent run.
        let _ = file;
        Ok(true)
    }
}

/// Whether `file` is the file at `path` now.
fn is_at(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::symlink_metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

/// `names` for a message: the first [`LISTED`], then how many more.
fn list(names: &[String]) -> String {
    let mut s = names
        .iter()
        .take(LISTED)
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > LISTED {
        s.push_str(&format!(" and {} more", names.len() - LISTED));
    }
    s
}

/// An output folder locked for a run, checked, with the files the run removes
/// before it writes (see the [module](self)). Made by [`OutputFolder::open`] and
/// handed to [`crate::Analysis::run_in`]; the lock is released when it is dropped.
pub struct OutputFolder {
    path: PathBuf,
    _lock: Lock,
    /// The files (relative) the run removes before it writes: those the last run
    /// listed and, with `force`, the other files at the names a run writes.
    stale: Vec<String>,
    /// The manifest being written, once the run has started.
    manifest: Option<File>,
    /// The names the manifest lists.
    listed: HashSet<String>,
}

impl std::fmt::Debug for OutputFolder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OutputFolder")
            .field("path", &self.path)
            .field("stale", &self.stale)
            .finish_non_exhaustive()
    }
}

impl OutputFolder {
    /// Creates `path` if it does not exist, locks it and checks it (see the
    /// [module](self)); nothing in it is removed or written yet, except the lock
    /// file. `force` accepts a folder that holds no cfe run or holds files at the
    /// names a run writes that no cfe run wrote: those are then replaced, every
    /// other file is left alone.
    pub fn open(path: &Path, force: bool) -> Result<OutputFolder> {
        std::fs::create_dir_all(path).map_err(|e| Error::output(path, e))?;
        let lock = Lock::acquire(path)?;
        let stale = inspect(path, force)?;
        Ok(OutputFolder {
            path: path.to_path_buf(),
            _lock: lock,
            stale,
            manifest: None,
            listed: HashSet::new(),
        })
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The files (relative to the folder) the run removes before it writes.
    pub fn stale(&self) -> &[String] {
        &self.stale
    }

    /// Starts the run: removes the files of the last run (and a manifest left
    /// half-written), creates `vtu/` and writes a new manifest, empty: the run
    /// then [claims](Self::claim) each file before it writes it, so the manifest
    /// never lists a name the run did not write (a `pressure.png` a rigid run
    /// does not draw stays the user's to make).
    pub(crate) fn start(&mut self) -> Result<()> {
        let remove = |p: &Path| match std::fs::remove_file(p) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::output(p, e)),
            _ => Ok(()),
        };
        remove(&self.path.join(MANIFEST_TMP))?;
        for rel in &self.stale {
            remove(&self.path.join(rel))?;
        }
        let vtu = self.path.join(VTU);
        match std::fs::create_dir(&vtu) {
            Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => {
                return Err(Error::output(&vtu, e));
            }
            _ => {}
        }
        let text = format!("{MANIFEST_HEADER}\n");
        let (tmp, path) = (self.path.join(MANIFEST_TMP), self.path.join(MANIFEST));
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        let file = options
            .open(&tmp)
            .and_then(|mut f| f.write_all(text.as_bytes()).map(|_| f))
            .and_then(|f| std::fs::rename(&tmp, &path).map(|_| f))
            .map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                Error::output(&path, e)
            })?;
        self.manifest = Some(file);
        self.listed = HashSet::new();
        Ok(())
    }

    /// Whether the manifest lists `rel`: the run has written it, or was about
    /// to.
    pub(crate) fn lists(&self, rel: &str) -> bool {
        self.listed.contains(rel)
    }

    /// Lists `rel` (relative to the folder) and its temporary name in the
    /// manifest, before the run creates them.
    pub(crate) fn claim(&mut self, rel: &str) -> Result<()> {
        debug_assert!(is_run_name(rel), "{rel}");
        if self.listed.contains(rel) {
            return Ok(());
        }
        let path = self.path.join(MANIFEST);
        let Some(manifest) = self.manifest.as_mut() else {
            return Err(Error::output(&path, "the run has not started"));
        };
        let tmp = temporary(rel);
        manifest
            .write_all(format!("{rel}\n{tmp}\n").as_bytes())
            .map_err(|e| Error::output(&path, e))?;
        self.listed.insert(rel.to_string());
        self.listed.insert(tmp);
        Ok(())
    }
}

/// What is in the folder at `rel`, not following a link.
enum Entry {
    File,
    Link,
    Folder,
}

/// The entries of `dir` (names, `prefix` before each) with their kinds.
fn entries(dir: &Path, prefix: &str) -> Result<Vec<(String, Entry)>> {
    let mut found = Vec::new();
    for e in std::fs::read_dir(dir).map_err(|e| Error::output(dir, e))? {
        let e = e.map_err(|e| Error::output(dir, e))?;
        let kind = e.file_type().map_err(|err| Error::output(e.path(), err))?;
        let kind = if kind.is_symlink() {
            Entry::Link
        } else if kind.is_dir() {
            Entry::Folder
        } else {
            Entry::File
        };
        found.push((format!("{prefix}{}", e.file_name().to_string_lossy()), kind));
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(found)
}

/// Checks `folder` (locked) and returns the files a run removes before it
/// writes; refuses the folder (see the [module](self)).
fn inspect(folder: &Path, force: bool) -> Result<Vec<String>> {
    let previous = read_manifest(folder)?;
    let listed = match &previous {
        Previous::Run(files) => Some(files),
        _ => None,
    };
    let top = entries(folder, "")?;
    let blocked = |path: &str, message: String| Error::OutputPathBlocked {
        folder: folder.to_path_buf(),
        path: PathBuf::from(path),
        message,
    };
    let mut all = Vec::new();
    for (name, kind) in top {
        match (name.as_str(), &kind) {
            (LOCK, _) => continue,
            (MANIFEST_TMP | MANIFEST, Entry::Folder) => {
                return Err(blocked(
                    &name,
                    "is a folder where cfe keeps its own file; cfe never removes a folder: rename it or choose another output folder".into(),
                ));
            }
            (MANIFEST_TMP, _) => continue,
            (MANIFEST, _) if listed.is_some() => continue,
            // The folders cfe writes into (the VTU series, the line probes):
            // their files are checked as the top level's are.
            (VTU | LINES, Entry::Folder) => {
                let inside = entries(&folder.join(&name), &format!("{name}/"))?;
                all.push((name, kind));
                all.extend(inside);
            }
            (VTU | LINES, Entry::Link) => {
                return Err(blocked(
                    &name,
                    "is a symbolic link; cfe never writes or deletes through a link in its output folder, even with force: remove the link (what it points to is left alone) or choose another output folder".into(),
                ));
            }
            (VTU | LINES, Entry::File) => {
                let what = if name == VTU {
                    "its VTU series"
                } else {
                    "its line probes"
                };
                return Err(blocked(
                    &name,
                    format!(
                        "is a file where cfe writes {what} into a folder; cfe does not remove it, even with force: rename it or choose another output folder"
                    ),
                ));
            }
            _ => all.push((name, kind)),
        }
    }
    let mut stale = Vec::new();
    let mut colliding = Vec::new();
    for (name, kind) in &all {
        if !is_run_name(name) {
            continue;
        }
        if let Entry::Folder = kind {
            return Err(blocked(
                name,
                "is a folder where cfe writes a file; cfe never removes a folder, even with force: rename it or choose another output folder".into(),
            ));
        }
        if listed.is_some_and(|l| l.contains(name)) {
            stale.push(name.clone());
        } else {
            colliding.push(name.clone());
        }
    }
    if force {
        stale.extend(colliding);
        return Ok(stale);
    }
    let refuse = |files: Vec<String>, message: String| Error::OutputFolderNotOurs {
        folder: folder.to_path_buf(),
        files: files.into_iter().map(PathBuf::from).collect(),
        message,
    };
    const OVERRIDE: &str = "pass force (`cfe run --force`, Python `force=True`)";
    if !colliding.is_empty() {
        let whose = match &previous {
            Previous::Run(_) => "the last cfe run here did not write (its manifest .cfe-manifest does not list them)".to_string(),
            Previous::None => "no cfe run wrote (the folder has no manifest .cfe-manifest)".to_string(),
            Previous::Foreign(why) => format!("no cfe run is known to have written (the manifest .cfe-manifest is not cfe's: {why})"),
        };
        return Err(refuse(
            colliding.clone(),
            format!(
                "holds files at names cfe writes that {whose}: {}; they are left untouched. Move them, choose another output folder, or {OVERRIDE} to replace them (other files are never touched)",
                list(&colliding)
            ),
        ));
    }
    if listed.is_none() && !all.is_empty() {
        // Only the top-level entries name what the folder holds.
        let names: Vec<String> = all
            .iter()
            .map(|(n, _)| n)
            .filter(|n| !n.starts_with("vtu/") && !n.starts_with("lines/"))
            .cloned()
            .collect();
        let why = match &previous {
            Previous::Foreign(why) => format!(" (its .cfe-manifest is not cfe's: {why})"),
            _ => " (no manifest .cfe-manifest)".to_string(),
        };
        return Err(refuse(
            names.clone(),
            format!(
                "is not empty and holds no cfe run{why}: {}; cfe writes only into an empty or new folder, or one holding its own earlier run. Choose another output folder, or {OVERRIDE} to write into it anyway: your files stay untouched (only files at the names cfe writes would be replaced)",
                list(&names)
            ),
        ));
    }
    Ok(stale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names a run writes are recognized, with their temporary names, and
    /// nothing else is.
    #[test]
    fn run_names() {
        for n in RUN_FILES
            .into_iter()
            .chain(["vtu/parts_0001.vtu", "vtu/pairs_12345.vtu"])
            .chain(["lines/mid.csv", "lines/a-b_1.png"])
            .chain(["lines/mid.0001.csv", "lines/a-b_1.12345.csv"])
            .chain(["pressure_1.png", "pressure_12.png"])
        {
            assert!(is_run_name(n), "{n}");
            assert!(is_run_name(&temporary(n)), "{}", temporary(n));
        }
        for n in [
            "notes.tmp",
            "thesis.docx.tmp",
            "summary.json.tmp",
            "vtu/parts_experiment.vtu",
            "vtu/parts_.vtu",
            "vtu/parts_0001.vtu.tmp",
            "parts_0001.vtu",
            "vtu/sub/parts_0001.vtu",
            "../summary.json",
            "x/summary.json",
            "vtu",
            ".cfe-manifest",
            "build.tmp",
            "lines/.csv",
            "lines/mid.txt",
            "lines/../summary.csv",
            "lines/a b.png",
            "lines/sub/mid.csv",
            "lines/mid.0001.png",
            "lines/mid..csv",
            "lines/.0001.csv",
            "lines/mid.x1.csv",
            "lines/a.b.0001.csv",
            "pressure_.png",
            "pressure_a.png",
            "pressure_1.png.png",
            "vtu/pressure_1.png",
        ] {
            assert!(!is_run_name(n), "{n}");
        }
        assert_eq!(temporary("vtu/parts_0001.vtu"), "vtu/.parts_0001.vtu.tmp");
        assert_eq!(temporary("summary.json"), ".summary.json.tmp");
    }
}
