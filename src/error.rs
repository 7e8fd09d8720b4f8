//! Error values: every failure a user can cause or meet, with a message that says
//! which part, node, key or file is at fault and what to do about it.

use std::path::PathBuf;

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything that can go wrong between reading a problem file and writing results.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The problem file could not be read.
    #[error("cannot read problem file {path}: {source}")]
    ReadInput {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The problem file is not valid TOML or does not match the schema
    /// (unknown key, missing key, wrong type). The message names the key and line.
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// The problem is well-formed TOML but describes an invalid model
    /// (bad material constants, unknown part names, empty selections, ...).
    #[error("invalid model: {0}")]
    Model(String),
    /// A mesh is unusable (inverted or degenerate elements, bad connectivity).
    #[error("mesh of part '{part}': {message}")]
    Mesh { part: String, message: String },
    /// Coupling nodes that lie in no host element.
    #[error("interface '{interface}': {message}")]
    Coupling { interface: String, message: String },
    /// The system is singular: a part is left without support, or the mesh has a mechanism.
    #[error("singular system: {0}")]
    Singular(String),
    /// The nonlinear iteration did not converge.
    #[error("no convergence: {0}")]
    NoConvergence(String),
    /// The contact law is broken beyond `[analysis] max_violation` at some pairs
    /// (no consistent state exists and the least-violating one is still too far off).
    #[error("contact law violated: {0}")]
    LawViolation(String),
    /// The solution lost accuracy: the out-of-balance force is too large a fraction
    /// of the load (a penalty too large for double precision, or an ill-conditioned model).
    #[error("loss of precision: {0}")]
    Precision(String),
    /// Writing a result file failed.
    #[error("cannot write {path}: {message}")]
    Output { path: PathBuf, message: String },
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
