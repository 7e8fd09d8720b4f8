//! A problem given as Python dicts and lists mirroring the TOML schema, turned
//! into TOML text for the library's reader, so the same checks apply and errors
//! name the same keys. `None` leaves a key out; NumPy arrays and scalars are
//! taken as lists and numbers.
//!
//! The walk is bounded: a value nested deeper than [`MAX_DEPTH`] levels, or a
//! container that contains itself (directly, through other containers, or
//! through `tolist()` / `__fspath__()` returning an object already on the
//! path), raises `ValueError` naming the entry, instead of exhausting the stack.

use crate::errors::ParseError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// The deepest nesting of dicts, lists and conversions (`tolist()`,
/// `__fspath__()`) a problem dict may have; a problem file needs about 5.
pub const MAX_DEPTH: usize = 64;

/// The TOML text of the problem `problem` (a dict).
#[pyfunction]
pub fn dict_to_toml(problem: &Bound<'_, PyAny>) -> PyResult<String> {
    let mut walk = Walk { path: Vec::new() };
    match walk.value(problem, "problem")? {
        Some(toml::Value::Table(table)) => {
            toml::to_string(&table).map_err(|e| ParseError::new_err(format!("problem dict: {e}")))
        }
        _ => Err(ParseError::new_err(
            "problem dict: the problem must be a dict (mapping keys to values)",
        )),
    }
}

/// The containers (and converted objects) on the path from the problem to the
/// value being converted, by identity.
struct Walk {
    path: Vec<usize>,
}

impl Walk {
    /// `v` as a TOML value; `at` is its key path for messages. `None` for a
    /// Python `None` (the key is left out).
    fn value(&mut self, v: &Bound<'_, PyAny>, at: &str) -> PyResult<Option<toml::Value>> {
        if v.is_none() {
            return Ok(None);
        }
        if let Ok(b) = v.cast::<PyBool>() {
            return Ok(Some(toml::Value::Boolean(b.is_true())));
        }
        if v.is_instance_of::<PyInt>() {
            return Ok(Some(toml::Value::Integer(v.extract::<i64>().map_err(
                |_| ParseError::new_err(format!("problem dict, `{at}`: integer out of range")),
            )?)));
        }
        if v.is_instance_of::<PyFloat>() {
            return Ok(Some(toml::Value::Float(v.extract::<f64>()?)));
        }
        if let Ok(s) = v.cast::<PyString>() {
            return Ok(Some(toml::Value::String(s.extract::<String>()?)));
        }
        // Everything below holds or yields other values: entered on the path.
        self.enter(v, at)?;
        let converted = self.container(v, at);
        self.path.pop();
        converted
    }

    /// Puts `v` on the path, refusing one already on it or a path too deep.
    fn enter(&mut self, v: &Bound<'_, PyAny>, at: &str) -> PyResult<()> {
        let id = v.as_ptr() as usize;
        if self.path.contains(&id) {
            return Err(PyValueError::new_err(format!(
                "problem dict, `{at}`: contains itself (a dict or list that holds itself, or a `tolist()` / `__fspath__()` that returns itself)"
            )));
        }
        if self.path.len() >= MAX_DEPTH {
            return Err(PyValueError::new_err(format!(
                "problem dict, `{}`: nested deeper than {MAX_DEPTH} levels",
                shortened(at)
            )));
        }
        self.path.push(id);
        Ok(())
    }

    /// A dict, list, tuple, path or array-like `v` (already on the path).
    fn container(&mut self, v: &Bound<'_, PyAny>, at: &str) -> PyResult<Option<toml::Value>> {
        if let Ok(d) = v.cast::<PyDict>() {
            let mut table = toml::Table::new();
            // A snapshot of the items: a value's `tolist()` cannot change what is walked.
            for item in d.items().iter() {
                let (k, item): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
                let key: String = k.extract().map_err(|_| {
                    ParseError::new_err(format!(
                        "problem dict, `{at}`: keys must be strings (got {})",
                        k.repr()
                            .map(|r| shortened(&r.to_string_lossy()))
                            .unwrap_or_default()
                    ))
                })?;
                let path = if at == "problem" {
                    key.clone()
                } else {
                    format!("{at}.{key}")
                };
                if let Some(x) = self.value(&item, &path)? {
                    table.insert(key, x);
                }
            }
            return Ok(Some(toml::Value::Table(table)));
        }
        // The list's or tuple's own items (an overridden `__iter__` is not called).
        let items: Option<Vec<Bound<'_, PyAny>>> = if let Ok(l) = v.cast::<PyList>() {
            Some(l.iter().collect())
        } else if let Ok(t) = v.cast::<PyTuple>() {
            Some(t.iter().collect())
        } else {
            None
        };
        if let Some(items) = items {
            let mut out = Vec::with_capacity(items.len());
            for (i, item) in items.iter().enumerate() {
                match self.value(item, &format!("{at}[{i}]"))? {
                    Some(x) => out.push(x),
                    None => {
                        return Err(ParseError::new_err(format!(
                            "problem dict, `{at}[{i}]`: None is not allowed in a list"
                        )));
                    }
                }
            }
            return Ok(Some(toml::Value::Array(out)));
        }
        // Paths (a Gmsh file) as their text.
        if v.hasattr("__fspath__")? {
            return self.value(&v.call_method0("__fspath__")?, at);
        }
        // NumPy arrays and scalars (and anything else with `tolist`, e.g. array-likes).
        if v.hasattr("tolist")? {
            return self.value(&v.call_method0("tolist")?, at);
        }
        Err(ParseError::new_err(format!(
            "problem dict, `{at}`: a value of type {} cannot be written to the problem (use numbers, strings, booleans, lists and dicts)",
            v.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        )))
    }
}

/// A key path for a message: its first 200 characters, then `…`.
fn shortened(at: &str) -> String {
    const KEEP: usize = 200;
    match at.char_indices().nth(KEEP) {
        Some((cut, _)) => format!("{}…", &at[..cut]),
        None => at.to_string(),
    }
}
