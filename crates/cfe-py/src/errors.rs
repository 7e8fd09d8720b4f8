//! The library's errors as Python exceptions: one class per kind of failure, all
//! subclasses of `cfe.CfeError`, carrying the library's message and, as
//! attributes, the values it names (path, line, part, key, interface, nodes ...).

use pyo3::IntoPyObjectExt;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _cfe,
    CfeError,
    PyException,
    "Any error of cfe; the message names the file, line, key, part or node at fault."
);
create_exception!(
    _cfe,
    ParseError,
    CfeError,
    "The problem cannot be read: unreadable file, invalid TOML, a key the schema does not know or a name that does not exist or is given twice. Attributes: `path`, `line` (1-based or None); for a name given twice also `key` (e.g. `interface#2.name`) and `name`; for a CalculiX/Abaqus deck also `keyword` (e.g. `*PLASTIC`) and `fault` (`unsupported`, `malformed`, `undefined`, `conflict` or `include`)."
);
create_exception!(
    _cfe,
    ModelError,
    CfeError,
    "The problem is well formed but describes an invalid model (settings, materials). Attributes: `path`, `line`, `key` (dotted, e.g. `materials.steel.nu`) for a value out of range; `part`, `key` for the constants of a material given in memory; `ratio` for a penalty far below E·t."
);
create_exception!(
    _cfe,
    MeshError,
    CfeError,
    "A mesh is unusable: bad array shapes or indices, inverted or degenerate elements, bad boundaries. Attribute: `part`."
);
create_exception!(
    _cfe,
    CouplingError,
    CfeError,
    "An interface cannot be built, e.g. coupling nodes on no host edge, or no pair within `search_distance`. Attributes: `interface`, `nodes` (list of (node, (x, y))) for orphan nodes, `search_distance` and `nearest` for an interface without pairs."
);
create_exception!(
    _cfe,
    SingularError,
    CfeError,
    "The system is singular: a part without support, a mechanism. Attributes: `parts`, or `increment`, `part`, `node`, `component`."
);
create_exception!(
    _cfe,
    ConvergenceError,
    CfeError,
    "The contact iteration did not converge."
);
create_exception!(
    _cfe,
    LawViolationError,
    CfeError,
    "The contact law has no consistent state and the least-violating one breaks it by more than `[analysis] max_violation`. Attributes: `increment`, `pairs` (list of (interface, node))."
);
create_exception!(
    _cfe,
    PrecisionError,
    CfeError,
    "Numbers beyond double precision: the solution lost accuracy (out-of-balance force above `[analysis] max_residual`; attributes `increment`, `residual`), or an input refused before solving as overflow or as a penalty far above E·t (attributes `path`, `line`, `key`, and `ratio` for a penalty)."
);
create_exception!(
    _cfe,
    TooLargeError,
    CfeError,
    "The model would need more memory than the machine has; refused before meshing. Attributes: `unknowns`, `bytes`, `available`."
);
create_exception!(
    _cfe,
    OutputError,
    CfeError,
    "A result file cannot be written, or the output folder is refused (attributes `files`, the files at fault relative to the folder, for a folder that holds files cfe did not write where it would write, or something it cannot write through; `pid`, the other run's process id, for a folder in use). Attribute: `path` (the file or the folder)."
);

/// The Python exception for a library error: its class by kind, its message the
/// library's, the values the error names as attributes.
pub fn to_py(py: Python<'_>, e: cfe::Error) -> PyErr {
    use cfe::Error as E;
    let message = e.to_string();
    let (err, attrs): (PyErr, Vec<(&str, Py<PyAny>)>) = match e {
        E::ReadInput { path, .. } => (
            ParseError::new_err(message),
            vec![("path", obj(py, path)), ("line", py.None())],
        ),
        E::Parse { path, line, .. } => (
            ParseError::new_err(message),
            vec![("path", obj(py, path)), ("line", obj(py, line))],
        ),
        E::Model(_) => (ModelError::new_err(message), vec![]),
        // A key of the other dimension (a plane key in a solid problem, …).
        E::Dimension {
            path, line, key, ..
        } => (
            ModelError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
            ],
        ),
        E::Invalid {
            path, line, key, ..
        } => (
            ModelError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
            ],
        ),
        E::Overflow {
            path, line, key, ..
        } => (
            PrecisionError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
            ],
        ),
        E::PenaltyPrecision {
            path,
            line,
            key,
            ratio,
            ..
        } => (
            PrecisionError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
                ("ratio", obj(py, ratio)),
            ],
        ),
        E::Subprocess {
            command, status, ..
        } => (
            CfeError::new_err(message),
            vec![("command", obj(py, command)), ("status", obj(py, status))],
        ),
        E::Material { part, key, .. } => (
            ModelError::new_err(message),
            vec![("part", obj(py, part)), ("key", obj(py, key))],
        ),
        E::Mesh { part, .. } => (MeshError::new_err(message), vec![("part", obj(py, part))]),
        E::NegativeRadius { part, node, r } => (
            MeshError::new_err(message),
            vec![
                ("part", obj(py, part)),
                ("node", obj(py, node)),
                ("r", obj(py, r)),
            ],
        ),
        E::Coupling { interface, .. } => (
            CouplingError::new_err(message),
            vec![("interface", obj(py, interface))],
        ),
        E::OrphanNodes {
            interface, nodes, ..
        } => (
            CouplingError::new_err(message),
            vec![("interface", obj(py, interface)), ("nodes", obj(py, nodes))],
        ),
        E::Unsupported { parts, .. } => (
            SingularError::new_err(message),
            vec![("parts", obj(py, parts))],
        ),
        E::NotPositiveDefinite {
            increment,
            part,
            node,
            component,
            ..
        } => (
            SingularError::new_err(message),
            vec![
                ("increment", obj(py, increment)),
                ("part", obj(py, part)),
                ("node", obj(py, node)),
                ("component", obj(py, component)),
            ],
        ),
        E::Singular(_) => (SingularError::new_err(message), vec![]),
        E::NoConvergence(_) => (ConvergenceError::new_err(message), vec![]),
        E::LinearBackEnd { back_end, .. } => (
            ModelError::new_err(message),
            vec![("back_end", obj(py, back_end))],
        ),
        E::LawViolation {
            increment, pairs, ..
        } => (
            LawViolationError::new_err(message),
            vec![("increment", obj(py, increment)), ("pairs", obj(py, pairs))],
        ),
        E::Precision {
            increment,
            residual,
            ..
        } => (
            PrecisionError::new_err(message),
            vec![
                ("increment", obj(py, increment)),
                ("residual", obj(py, residual)),
            ],
        ),
        E::TooLarge {
            unknowns,
            bytes,
            available,
            ..
        } => (
            TooLargeError::new_err(message),
            vec![
                ("unknowns", obj(py, unknowns)),
                ("bytes", obj(py, bytes)),
                ("available", obj(py, available)),
            ],
        ),
        E::Interrupted { increment, signal } => (
            pyo3::exceptions::PyKeyboardInterrupt::new_err(message),
            vec![
                ("increment", obj(py, increment)),
                ("signal", obj(py, signal)),
            ],
        ),
        E::Output { path, .. } => (OutputError::new_err(message), vec![("path", obj(py, path))]),
        E::DuplicateName {
            path,
            line,
            key,
            name,
            ..
        } => (
            ParseError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
                ("name", obj(py, name)),
            ],
        ),
        E::WeakPenalty {
            path,
            line,
            key,
            ratio,
            ..
        } => (
            ModelError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("key", obj(py, key)),
                ("ratio", obj(py, ratio)),
            ],
        ),
        E::NoPairs {
            interface,
            search_distance,
            nearest,
            ..
        } => (
            CouplingError::new_err(message),
            vec![
                ("interface", obj(py, interface)),
                ("search_distance", obj(py, search_distance)),
                ("nearest", obj(py, nearest)),
            ],
        ),
        E::InputFile { path, .. } => (
            ParseError::new_err(message),
            vec![("path", obj(py, path)), ("line", py.None())],
        ),
        E::Deck {
            path,
            line,
            keyword,
            fault,
            ..
        } => (
            ParseError::new_err(message),
            vec![
                ("path", obj(py, path)),
                ("line", obj(py, line)),
                ("keyword", obj(py, keyword)),
                ("fault", obj(py, format!("{fault:?}").to_lowercase())),
            ],
        ),
        E::OutputFolderNotOurs { folder, files, .. } => (
            OutputError::new_err(message),
            vec![("path", obj(py, folder)), ("files", obj(py, files))],
        ),
        E::OutputFolderInUse { folder, pid } => (
            OutputError::new_err(message),
            vec![("path", obj(py, folder)), ("pid", obj(py, pid))],
        ),
        E::OutputPathBlocked { folder, path, .. } => (
            OutputError::new_err(message),
            vec![("path", obj(py, folder)), ("files", obj(py, vec![path]))],
        ),
    };
    let value = err.value(py);
    for (name, v) in attrs {
        // Setting an attribute on a fresh exception instance cannot fail.
        let _ = value.setattr(name, v);
    }
    err
}

/// A Rust value as a Python object (None when it cannot be converted).
fn obj<'py, T: IntoPyObject<'py>>(py: Python<'py>, v: T) -> Py<PyAny> {
    v.into_py_any(py).unwrap_or_else(|_| py.None())
}

/// A `MeshError` for arrays handed over with a bad shape or content.
pub fn mesh_error(part: &str, message: impl std::fmt::Display) -> PyErr {
    MeshError::new_err(format!("mesh of part '{part}': {message}"))
}

/// Registers the exception classes in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("CfeError", py.get_type::<CfeError>())?;
    m.add("ParseError", py.get_type::<ParseError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("MeshError", py.get_type::<MeshError>())?;
    m.add("CouplingError", py.get_type::<CouplingError>())?;
    m.add("SingularError", py.get_type::<SingularError>())?;
    m.add("ConvergenceError", py.get_type::<ConvergenceError>())?;
    m.add("LawViolationError", py.get_type::<LawViolationError>())?;
    m.add("PrecisionError", py.get_type::<PrecisionError>())?;
    m.add("TooLargeError", py.get_type::<TooLargeError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    Ok(())
}
