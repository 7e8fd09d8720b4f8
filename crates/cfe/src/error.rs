//! Error values: every failure a user can cause or meet, with a message that says
//! which part, node, key or file is at fault and what to do about it.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

/// A step abandoned because the caller's stop flag was nonzero (its value,
/// e.g. a signal's number): what the node graph and the matrix pattern
/// (`assembly`), the ordering and the steps of the symbolic analysis (`solve`)
/// return once they read it nonzero. The callers turn it into
/// [`Error::Interrupted`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stopped(pub usize);

/// `Err(Stopped)` once `stop` (if any) is nonzero: one relaxed load.
pub fn check_stop(stop: Option<&AtomicUsize>) -> std::result::Result<(), Stopped> {
    match stop.map_or(0, |s| s.load(Ordering::Relaxed)) {
        0 => Ok(()),
        signal => Err(Stopped(signal)),
    }
}

/// Everything that can go wrong between reading a problem file and writing results.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The problem file could not be read.
    #[error("cannot read problem file {path}: {source}")]
    ReadInput {
        /// The file.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// The problem file is not valid TOML, does not match the schema (unknown key,
    /// missing key, wrong type) or names something that does not exist (a part, a
    /// boundary, a node). The message names the key and the line.
    #[error("{path}: {message}")]
    Parse {
        /// The problem file.
        path: PathBuf,
        /// The line at fault (1-based), when known.
        line: Option<usize>,
        /// What is wrong, with the line and the key.
        message: String,
    },
    /// The problem is well-formed TOML but describes an invalid model (no part,
    /// invalid analysis settings, nothing to solve, ...).
    #[error("invalid model: {0}")]
    Model(String),
    /// A value of the problem file is unusable: not a finite number, or outside its
    /// physical range (the message gives the range and the reason). `key` is the
    /// value's dotted path in the file, e.g. `materials.steel.E`,
    /// `part.base.thickness`, `analysis.increments`.
    #[error("{}: `{key}` {message}", place(path, *line))]
    Invalid {
        /// The problem file.
        path: PathBuf,
        /// The line of the value (1-based), when known.
        line: Option<usize>,
        /// The value's dotted path in the file.
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// Numbers too large or too small for double precision to carry through the
    /// solve: a value whose stiffness products or load sums would overflow (or
    /// underflow to zero), or a solution that came out non-finite. `key` and `line`
    /// name the input at fault when it is known.
    #[error("overflow: {}{message}", match (path, line) { (Some(p), l) => format!("{}: ", place(p, *l)), _ => String::new() })]
    Overflow {
        /// The problem file, when an input value is at fault.
        path: Option<PathBuf>,
        /// The line of that value (1-based).
        line: Option<usize>,
        /// The value's dotted path (empty when no single input is at fault).
        key: String,
        /// What overflows and what to change.
        message: String,
    },
    /// A coupling penalty so far above the softer part's E·t that the part's
    /// stiffness is lost in the round-off of the penalty entries (double precision
    /// keeps about 16 digits): refused before solving.
    #[error("loss of precision: {}: `{key}` {message}", place(path, *line))]
    PenaltyPrecision {
        /// The problem file.
        path: PathBuf,
        /// The line of the penalty (1-based), when known.
        line: Option<usize>,
        /// The penalty's dotted path, e.g. `interface.plate-base.c_n`.
        key: String,
        /// The penalty relative to the softer part's E·t.
        ratio: f64,
        /// What is wrong and the working range.
        message: String,
    },
    /// Invalid material constants of a part.
    #[error("invalid model: part '{part}': {message}")]
    Material {
        /// The part.
        part: String,
        /// The constant at fault: `E`, `nu` or `thickness`.
        key: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A mesh is unusable (inverted or degenerate elements, bad connectivity).
    #[error("mesh of part '{part}': {message}")]
    Mesh {
        /// The part whose mesh is at fault.
        part: String,
        /// What is wrong, with the element or node numbers.
        message: String,
    },
    /// A node of an axisymmetric part lies at r = x < 0: the r–z half-plane is
    /// x ≥ 0 (the axis is x = 0).
    #[error(
        "part '{part}': node {node} lies at r = x = {r} < 0; an axisymmetric part is meshed in the half-plane r ≥ 0 about the axis r = 0 (x = radius, y = axial coordinate): mirror or move the mesh"
    )]
    NegativeRadius {
        /// The part.
        part: String,
        /// The node (in the part's numbering).
        node: usize,
        /// Its radius.
        r: f64,
    },
    /// An interface cannot be built (a host element's inverse map fails, moving
    /// the coupling nodes spoils the node part's mesh).
    #[error("interface '{interface}': {message}")]
    Coupling {
        /// The interface's name.
        interface: String,
        /// What is wrong.
        message: String,
    },
    /// Coupling nodes that lie on no host boundary edge (plane) or face (solid)
    /// within the tolerance.
    #[error("interface '{interface}': {message}")]
    OrphanNodes {
        /// The interface.
        interface: String,
        /// The coupling nodes (index in the node part) and their positions:
        /// (x, y) in a plane model, (x, y, z) in a solid one.
        nodes: Vec<(usize, Vec<f64>)>,
        /// The message listing them with their nearest host edges.
        message: String,
    },
    /// Parts left without support: they can move as rigid bodies.
    #[error("singular system: {message}")]
    Unsupported {
        /// The parts that can move.
        parts: Vec<String>,
        /// The message naming them with their open pairs.
        message: String,
    },
    /// A pivot of the factorization is not positive: a mechanism or an unsupported part.
    #[error("singular system: {message}")]
    NotPositiveDefinite {
        /// The increment (1-based).
        increment: usize,
        /// The part of the DOF at the pivot.
        part: String,
        /// The node of that part.
        node: usize,
        /// The DOF's component: 0 (x) or 1 (y).
        component: usize,
        /// The message naming them.
        message: String,
    },
    /// The system is singular in another way (a non-finite solution, a failed check).
    #[error("singular system: {0}")]
    Singular(String),
    /// The nonlinear iteration did not converge.
    #[error("no convergence: {0}")]
    NoConvergence(String),
    /// A linear back end outside this library (`[analysis] solver = "petsc"`)
    /// is not built in, or failed: which back end, and what to do.
    #[error("linear solver '{back_end}': {message}")]
    LinearBackEnd {
        /// The back end (`petsc`, `petsc-mumps`).
        back_end: String,
        /// What went wrong (the failing call and its error code, or how to build it in).
        message: String,
    },
    /// The contact law is broken beyond `[analysis] max_violation` at some pairs:
    /// no consistent state exists and the least-violating one is still too far off.
    #[error("contact law violated: {message}")]
    LawViolation {
        /// The increment (1-based).
        increment: usize,
        /// The pairs beyond the limit: (interface, coupling node).
        pairs: Vec<(String, usize)>,
        /// The message naming them with their amounts.
        message: String,
    },
    /// The solution lost accuracy: the out-of-balance force exceeds
    /// `[analysis] max_residual` of the load (a penalty too large for double
    /// precision, or an ill-conditioned model).
    #[error("loss of precision: {message}")]
    Precision {
        /// The increment (1-based).
        increment: usize,
        /// The out-of-balance force relative to the load scale.
        residual: f64,
        /// The message, with the interface whose penalty is too large if any.
        message: String,
    },
    /// The model is too large for this machine: refused before meshing it, or
    /// before its numeric factorization once the factor's size is known.
    #[error("model too large: {message}")]
    TooLarge {
        /// Estimated unknowns.
        unknowns: u64,
        /// Estimated memory (bytes).
        bytes: u64,
        /// Memory available (bytes).
        available: u64,
        /// The message with the estimate and what to change.
        message: String,
    },
    /// The run was stopped on request (e.g. SIGINT) after a converged increment.
    #[error(
        "interrupted (signal {signal}) after increment {increment}; the converged increments are on disk (summary.json's notes name any whose VTU files the stop left unwritten)"
    )]
    Interrupted {
        /// The last increment written.
        increment: usize,
        /// What asked to stop: the signal's number.
        signal: usize,
    },
    /// A child process (e.g. a benchmark run) failed: its command, exit status and
    /// its own error message.
    #[error("`{command}` failed (exit status {}): {stderr}", status.map_or("none (killed by a signal)".to_string(), |c| c.to_string()))]
    Subprocess {
        /// The command, as a user would type it.
        command: String,
        /// Its exit status (`None` when killed by a signal).
        status: Option<i32>,
        /// Its error lines (stderr).
        stderr: String,
    },
    /// The output folder holds files cfe did not write where it would write: it is
    /// not empty and holds no cfe run, or holds files at the names a run writes
    /// that the last run's manifest does not list. Nothing in it was touched.
    /// `force` (`cfe run --force`, Python `force=True`) accepts it.
    #[error("output folder {}: {message}", folder.display())]
    OutputFolderNotOurs {
        /// The output folder.
        folder: PathBuf,
        /// The files at fault, relative to the folder: those at the names a run
        /// writes, or (a folder with no cfe run) its entries.
        files: Vec<PathBuf>,
        /// What is wrong and how to proceed.
        message: String,
    },
    /// Another run holds the output folder's lock (`.cfe-lock`): two runs must
    /// not write into one folder.
    #[error(
        "output folder {} is in use by another cfe run ({}); wait for it to end or choose another output folder",
        folder.display(),
        pid.map_or("its process id is not known yet".to_string(), |p| format!("process {p}"))
    )]
    OutputFolderInUse {
        /// The output folder.
        folder: PathBuf,
        /// The process id of the run holding it, as written in its lock file.
        pid: Option<u32>,
    },
    /// Something in the output folder cfe can neither write through nor remove,
    /// even with `force`: `vtu` is a symbolic link or a file, or a folder sits
    /// at a name a run writes. Nothing in the folder was touched.
    #[error("output folder {}: `{}` {message}", folder.display(), path.display())]
    OutputPathBlocked {
        /// The output folder.
        folder: PathBuf,
        /// The entry at fault, relative to the folder.
        path: PathBuf,
        /// What it is and what to do.
        message: String,
    },
    /// Writing a result file failed.
    #[error("cannot write {path}: {message}")]
    Output {
        /// The file or folder that could not be written.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A key of the other dimension: a plane model's key (`plane`, `thickness`,
    /// `rectangle`, `annulus`, `[[line]]`, a Gmsh part's `surfaces`) in a solid
    /// model, a solid model's (`box`, a Gmsh part's `volumes`, `traction`) in a
    /// plane one, a solid-only choice (`coupling = "segment"` in 3D), or plane
    /// and solid parts in one problem. `key` is its dotted path, e.g.
    /// `part.base.thickness`, `line` its line.
    #[error("{}: `{key}` {message}", place(path, *line))]
    Dimension {
        /// The problem file.
        path: PathBuf,
        /// The line of the key (1-based), when known.
        line: Option<usize>,
        /// The key's dotted path.
        key: String,
        /// Why it does not belong to this model, and what to do.
        message: String,
    },
    /// Two parts, interfaces, supports, loads or steps share a name: results,
    /// reactions and references are keyed by name, so names are unique within
    /// each kind. `key` is the duplicate's name key (e.g. `interface#2.name`,
    /// counting the tables of its kind from 1) and `line` its line; a model
    /// built in code has no file (`path` empty, no line).
    #[error("{}: `{key}` {message}", if path.as_os_str().is_empty() { "model".to_string() } else { place(path, *line) })]
    DuplicateName {
        /// The problem file (empty for a model built in code).
        path: PathBuf,
        /// The line of the duplicate (1-based), when known.
        line: Option<usize>,
        /// The duplicate's key, e.g. `interface#2.name`.
        key: String,
        /// The name given twice.
        name: String,
        /// What is wrong (with the line of the first use) and what to do.
        message: String,
    },
    /// A coupling penalty so far below the E·t of the parts it joins that the
    /// interface holds nothing (the joined faces are free to drift apart): refused
    /// before solving, rather than met as a mechanism in the factorization.
    #[error("{}: `{key}` {message}", place(path, *line))]
    WeakPenalty {
        /// The problem file.
        path: PathBuf,
        /// The line of the penalty (1-based), when known.
        line: Option<usize>,
        /// The penalty's dotted path, e.g. `interface.plate-base.c_n`.
        key: String,
        /// The penalty relative to the stiffer part's E·t.
        ratio: f64,
        /// What is wrong and the working range.
        message: String,
    },
    /// A contact interface with a `search_distance` found no pair: none of its
    /// coupling nodes lies within that distance of a host edge, so it would
    /// couple nothing.
    #[error("interface '{interface}': {message}")]
    NoPairs {
        /// The interface.
        interface: String,
        /// Its `search_distance`.
        search_distance: f64,
        /// The distance from the nearest coupling node to the nearest host
        /// boundary edge, when it was measured.
        nearest: Option<f64>,
        /// The message with both distances and what to change.
        message: String,
    },
    /// An input file (a problem file or a mesh file) refused before it is read: not
    /// a regular file (a directory, a FIFO, a device: reading one could block
    /// forever or never end), or larger than the cap on its kind (64 MiB for a
    /// problem file, 4 GiB for a mesh file).
    #[error("cannot read {what} {path}: {message}")]
    InputFile {
        /// The file.
        path: PathBuf,
        /// What the file is to cfe: "problem file", "Gmsh file of part 'base'".
        what: String,
        /// Why it is refused.
        refusal: InputRefusal,
        /// The message, with the file's type or its size and the cap.
        message: String,
    },
    /// A CalculiX/Abaqus input deck (`.inp`) that cfe cannot read: a keyword,
    /// parameter or element type outside the subset it reads, a malformed line,
    /// a name that is not defined, or a construct cfe cannot represent. `line`
    /// is the line at fault (1-based) in `path` (the deck or a file it includes).
    #[error("{}: {message}", path.display())]
    Deck {
        /// The deck file holding the line.
        path: PathBuf,
        /// The line at fault (1-based).
        line: usize,
        /// The keyword of that line or of its card (`*PLASTIC`, `*BOUNDARY`).
        keyword: String,
        /// What kind of fault.
        fault: DeckFault,
        /// `KEYWORD at line N` and what is wrong and what to do.
        message: String,
    },
}

/// The kind of an [`Error::Deck`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeckFault {
    /// A keyword, parameter, element type or option outside what cfe reads or
    /// computes (`*PLASTIC`: cfe is linear elastic).
    Unsupported,
    /// A line that does not say what its keyword needs (a missing or extra
    /// field, a number that is not one, a missing parameter).
    Malformed,
    /// A name or number that is not defined (a set, a node, a material).
    Undefined,
    /// Statements that contradict each other or that cfe's model cannot hold
    /// together (a node shared by two sections' bodies, a value changed twice).
    Conflict,
    /// An `*INCLUDE` that cannot be read (missing file, nesting too deep).
    Include,
}

/// Why an input file is refused ([`Error::InputFile`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputRefusal {
    /// It is not a regular file: `found` says what it is ("a FIFO (named pipe)",
    /// "a character device", "a directory", ...).
    NotRegular {
        /// What the path is.
        found: &'static str,
    },
    /// It is larger than the cap: `size` bytes (as reported, or as read when the
    /// read passed the cap) against `cap`.
    TooLarge {
        /// Its size in bytes (at least `cap + 1`).
        size: u64,
        /// The cap in bytes.
        cap: u64,
    },
}

/// `file:line` (or just `file`) for messages.
fn place(path: &std::path::Path, line: Option<usize>) -> String {
    match line {
        Some(l) => format!("{}:{l}", path.display()),
        None => path.display().to_string(),
    }
}

impl Error {
    /// An output error for `path` from anything printable.
    pub fn output(path: impl Into<PathBuf>, message: impl std::fmt::Display) -> Self {
        Error::Output {
            path: path.into(),
            message: message.to_string(),
        }
    }
}

/// How many entries of a list (nodes, pairs) an error message shows before
/// "… and N more": a message stays a few lines long however many there are.
pub const LIST_SHOWN: usize = 5;

/// The first [`LIST_SHOWN`] of `items` joined by ", ", then "… and N more" when
/// there are more: the one way error messages list nodes or pairs.
pub fn short_list<T: std::fmt::Display>(items: impl IntoIterator<Item = T>) -> String {
    let mut items = items.into_iter();
    let shown: Vec<String> = items
        .by_ref()
        .take(LIST_SHOWN)
        .map(|x| x.to_string())
        .collect();
    let more = items.count();
    let mut s = shown.join(", ");
    if more > 0 {
        s += &format!(" … and {more} more");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Up to five entries are listed whole; beyond, the first five and the count
    /// of the rest.
    #[test]
    fn short_list_shows_five_then_counts_the_rest() {
        assert_eq!(short_list(1..=3), "1, 2, 3");
        assert_eq!(short_list(1..=5), "1, 2, 3, 4, 5");
        assert_eq!(short_list(1..=21), "1, 2, 3, 4, 5 … and 16 more");
        assert_eq!(short_list(Vec::<usize>::new()), "");
    }
}
