//! A problem given as Python dicts and lists mirroring the TOML schema, turned
//! into TOML text for the library's reader, so the same checks apply and errors
//! name the same keys. `None` leaves a key out; NumPy arrays and scalars are
//! taken as lists and numbers.

use crate::errors::ParseError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// The TOML text of the problem `problem` (a dict).
#[pyfunction]
pub fn dict_to_toml(problem: &Bound<'_, PyAny>) -> PyResult<String> {
    match value(problem, "problem")? {
        Some(toml::Value::Table(table)) => {
            toml::to_string(&table).map_err(|e| ParseError::new_err(format!("problem dict: {e}")))
        }
        _ => Err(ParseError::new_err(
            "problem dict: the problem must be a dict (mapping keys to values)",
        )),
    }
}

/// `v` as a TOML value; `at` is its key path for messages. `None` for a Python
/// `None` (the key is left out).
fn value(v: &Bound<'_, PyAny>, at: &str) -> PyResult<Option<toml::Value>> {
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
    if let Ok(d) = v.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, item) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                ParseError::new_err(format!(
                    "problem dict, `{at}`: keys must be strings (got {})",
                    k.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
            let path = if at == "problem" {
                key.clone()
            } else {
                format!("{at}.{key}")
            };
            if let Some(x) = value(&item, &path)? {
                table.insert(key, x);
            }
        }
        return Ok(Some(toml::Value::Table(table)));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, item) in v.try_iter()?.enumerate() {
            let item = item?;
            match value(&item, &format!("{at}[{i}]"))? {
                Some(x) => items.push(x),
                None => {
                    return Err(ParseError::new_err(format!(
                        "problem dict, `{at}[{i}]`: None is not allowed in a list"
                    )));
                }
            }
        }
        return Ok(Some(toml::Value::Array(items)));
    }
    // Paths (a Gmsh file) as their text.
    if v.hasattr("__fspath__")? {
        return value(&v.call_method0("__fspath__")?, at);
    }
    // NumPy arrays and scalars (and anything else with `tolist`, e.g. array-likes).
    if v.hasattr("tolist")? {
        return value(&v.call_method0("tolist")?, at);
    }
    Err(ParseError::new_err(format!(
        "problem dict, `{at}`: a value of type {} cannot be written to the problem (use numbers, strings, booleans, lists and dicts)",
        v.get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default()
    )))
}
