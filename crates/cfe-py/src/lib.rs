//! The native module `cfe._cfe` of the Python package `cfe`: a thin layer over the
//! library. [`PyMesh`] builds a part's mesh from arrays, [`PyModel`] holds a
//! checked, meshed [`cfe::Model`] (from a file, TOML text, or text plus meshes) and
//! solves it with the GIL released, handing the results over as NumPy arrays made
//! from the solver's buffers. The friendly API (`cfe.Model`, `cfe.Results`, meshio
//! conversion) is the pure-Python package around it (`python/cfe`).

mod dict;
mod errors;
mod results;

use cfe::IncrementResult;
use cfe::mesh::{BoundarySelection, Element, Mesh};
use cfe::results::history::HistoryRow;
use cfe::{Analysis, Law, Results};
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;

use errors::{mesh_error, to_py};

/// A part's mesh given as arrays: node coordinates, triangles and/or
/// quadrilaterals (node indices, 0-based, either way round) and named boundaries.
#[pyclass(name = "Mesh", module = "cfe._cfe", frozen)]
pub struct PyMesh {
    mesh: Mesh,
}

#[pymethods]
impl PyMesh {
    /// Builds and checks a mesh: `points` (n, 2) float64, `triangles` (m, 3) and
    /// `quads` (k, 4) int64, `boundaries` a dict name → edges (j, 2) or nodes (j,)
    /// int64; `part` names the part in messages.
    #[new]
    #[pyo3(signature = (points, triangles=None, quads=None, boundaries=None, *, part="mesh"))]
    fn new(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        triangles: Option<&Bound<'_, PyAny>>,
        quads: Option<&Bound<'_, PyAny>>,
        boundaries: Option<&Bound<'_, PyDict>>,
        part: &str,
    ) -> PyResult<Self> {
        let nodes: Vec<[f64; 2]> = rows(part, "points", points, 2)?
            .into_iter()
            .map(|r: Vec<f64>| [r[0], r[1]])
            .collect();
        let mut elements = Vec::new();
        if let Some(t) = triangles {
            for r in rows(part, "triangles", t, 3)? {
                elements.push(Element::T3([
                    index(part, "triangles", r[0])?,
                    index(part, "triangles", r[1])?,
                    index(part, "triangles", r[2])?,
                ]));
            }
        }
        if let Some(q) = quads {
            for r in rows(part, "quads", q, 4)? {
                elements.push(Element::Q4([
                    index(part, "quads", r[0])?,
                    index(part, "quads", r[1])?,
                    index(part, "quads", r[2])?,
                    index(part, "quads", r[3])?,
                ]));
            }
        }
        if elements.is_empty() {
            return Err(mesh_error(
                part,
                "no elements: give `triangles` (m, 3) and/or `quads` (m, 4)",
            ));
        }
        let mut named = Vec::new();
        if let Some(b) = boundaries {
            for (k, v) in b.iter() {
                let name: String = k
                    .extract()
                    .map_err(|_| mesh_error(part, "boundary names must be strings"))?;
                let what = format!("boundaries['{name}']");
                let array = int_array(part, &what, &v)?;
                let selection = match array.shape() {
                    [_] => BoundarySelection::Nodes(
                        array
                            .as_array()
                            .iter()
                            .map(|&i| index(part, &what, i))
                            .collect::<PyResult<_>>()?,
                    ),
                    [_, 2] => {
                        let a = array.as_array();
                        let mut edges = Vec::with_capacity(a.shape()[0]);
                        for r in a.outer_iter() {
                            edges.push([index(part, &what, r[0])?, index(part, &what, r[1])?]);
                        }
                        BoundarySelection::Edges(edges)
                    }
                    s => {
                        return Err(mesh_error(
                            part,
                            format!("`{what}` must be edges (j, 2) or nodes (j,), got shape {s:?}"),
                        ));
                    }
                };
                named.push((name, selection));
            }
        }
        let mesh = Mesh::from_arrays(part, nodes, elements, named).map_err(|e| to_py(py, e))?;
        Ok(PyMesh { mesh })
    }

    /// Node coordinates (n, 2).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let flat: Vec<f64> = self.mesh.nodes.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape(vec![self.mesh.nodes.len(), 2])
    }

    /// The triangles (m, 3), counter-clockwise.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        results::connectivity(py, &self.mesh, 3).map(|(c, _)| c)
    }

    /// The quadrilaterals (k, 4), counter-clockwise.
    #[getter]
    fn quads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        results::connectivity(py, &self.mesh, 4).map(|(c, _)| c)
    }

    /// Named boundaries: name → edges (j, 2), each with the part on its left,
    /// in order along the boundary.
    #[getter]
    fn boundaries<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        results::boundaries(py, &self.mesh)
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh({} nodes, {}, boundaries: {})",
            self.mesh.nodes.len(),
            self.mesh.describe_elements(),
            self.mesh
                .boundaries
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// A checked, meshed model, ready to solve.
#[pyclass(name = "Model", module = "cfe._cfe", frozen)]
pub struct PyModel {
    model: cfe::Model,
}

#[pymethods]
impl PyModel {
    /// Reads, checks and meshes the problem file at `path`; `refine` multiplies
    /// the structured cell counts and subdivides Gmsh meshes (as `cfe run --refine`).
    #[staticmethod]
    #[pyo3(signature = (path, refine=1))]
    fn from_file(py: Python<'_>, path: PathBuf, refine: usize) -> PyResult<Self> {
        let model = py
            .detach(|| cfe::Model::from_file(&path, refine))
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel { model })
    }

    /// Reads a CalculiX/Abaqus input deck (`.inp`): its common subset mapped onto
    /// cfe's parts, interfaces, supports, loads and steps (README, "Running a
    /// CalculiX/Abaqus deck"); anything outside it raises `ParseError` with the
    /// line, the keyword and the fault.
    #[staticmethod]
    fn from_inp(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let model = py
            .detach(|| cfe::Model::from_inp(&path))
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel { model })
    }

    /// What reading the input noted (a deck's ignored keywords and mapping).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.model.notes.clone()
    }

    /// Reads, checks and meshes a problem given as TOML text; `path` is used in
    /// messages and to find Gmsh files (relative to its folder); `meshes` gives
    /// the meshes of parts that have no mesh key, by part name.
    #[staticmethod]
    #[pyo3(signature = (text, refine=1, path=None, meshes=None))]
    fn from_toml(
        py: Python<'_>,
        text: String,
        refine: usize,
        path: Option<PathBuf>,
        meshes: Option<BTreeMap<String, PyRef<'_, PyMesh>>>,
    ) -> PyResult<Self> {
        let path = path.unwrap_or_else(|| PathBuf::from("problem.toml"));
        let meshes: BTreeMap<String, Mesh> = meshes
            .unwrap_or_default()
            .into_iter()
            .map(|(k, m)| (k, m.mesh.clone()))
            .collect();
        let model = py
            .detach(|| cfe::Model::from_str_with_meshes(&text, &path, refine, meshes))
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel { model })
    }

    /// The title.
    #[getter]
    fn title(&self) -> &str {
        &self.model.title
    }

    /// The refinement factor the model was meshed with.
    #[getter]
    fn refine(&self) -> usize {
        self.model.refine
    }

    /// The problem text (TOML).
    #[getter]
    fn text(&self) -> &str {
        &self.model.text
    }

    /// The part names, in order.
    #[getter]
    fn parts(&self) -> Vec<String> {
        self.model.parts.iter().map(|p| p.name.clone()).collect()
    }

    /// The interface names, in order.
    #[getter]
    fn interfaces(&self) -> Vec<String> {
        self.model
            .interfaces
            .iter()
            .map(|i| i.name.clone())
            .collect()
    }

    /// The analysis settings: increments, scheme, max_iterations, gap_tolerance,
    /// solver (`direct` or `cg`).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let s = &self.model.settings;
        let d = PyDict::new(py);
        d.set_item("increments", s.increments)?;
        d.set_item(
            "scheme",
            match s.scheme {
                cfe::Scheme::ActiveSet => "active-set",
                cfe::Scheme::Implex => "implex",
            },
        )?;
        d.set_item("max_iterations", s.max_iterations)?;
        d.set_item("gap_tolerance", s.gap_tolerance)?;
        d.set_item("solver", s.solver.name())?;
        Ok(d.into_any())
    }

    /// The load steps, in order: dicts of name and increments (one step,
    /// `step-1`, without `[[step]]` tables).
    #[getter]
    fn steps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for s in self.model.steps() {
            let d = PyDict::new(py);
            d.set_item("name", s.name)?;
            d.set_item("increments", s.increments)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// The mesh of part `name` (as meshed, before coupling nodes are moved).
    fn mesh(&self, name: &str) -> PyResult<PyMesh> {
        let p = self.model.part_index(name).ok_or_else(|| {
            errors::ModelError::new_err(format!(
                "no part named '{name}' (parts: {})",
                self.parts().join(", ")
            ))
        })?;
        Ok(PyMesh {
            mesh: self.model.parts[p].mesh.clone(),
        })
    }

    /// Finds the coupling pairs and numbers the DOFs without solving; returns the
    /// description `cfe check` prints.
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        let model = self.model.clone();
        py.detach(|| Analysis::new(model).map(|a| a.describe()))
            .map_err(|e| to_py(py, e))
    }

    /// Solves the model with the GIL released. `progress(info)` is called after
    /// each converged increment with a dict (increment, increments, load_factor,
    /// iterations, step, time: the step's name, and step index − 1 + load factor;
    /// history: the increment's row of the run's history, a dict of
    /// `history.csv`'s columns to scalars); an exception it raises stops the solve; Ctrl-C (SIGINT, registered
    /// on the solver's stop flag for the solve's duration) stops it inside an
    /// increment with `KeyboardInterrupt`. With `out`,
    /// every converged increment is also written there as `cfe run` does (the
    /// callback then cannot stop the run: its exception is raised at the end).
    /// `law` ("rigid", "contact", "frictionless" or "coulomb", the last with
    /// `friction` = μ) overrides every interface's law. `write_every` (N ≥ 1 or
    /// "last", with `out`) writes the VTU files of every N-th increment only (the
    /// last of each step always), overriding the file's `output_every`. `force`
    /// (with `out`) writes into a folder that is not empty and holds no cfe run,
    /// or holds files at the names cfe writes that no cfe run wrote (those are
    /// replaced, nothing else is touched); without it such a folder is refused
    /// with an `OutputError`, as `cfe run` without `--force`. Returns a dict of
    /// the raw results (see `cfe.Results`).
    #[pyo3(signature = (progress=None, out=None, law=None, friction=None, write_every=None, force=false))]
    #[allow(clippy::too_many_arguments)]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        progress: Option<Py<PyAny>>,
        out: Option<PathBuf>,
        law: Option<&str>,
        friction: Option<f64>,
        write_every: Option<Bound<'py, PyAny>>,
        force: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let write_every = match write_every {
            None => None,
            Some(v) => {
                let bad = || {
                    errors::ModelError::new_err(format!(
                        "write_every = {v}: expected a positive integer N (write every N-th increment) or 'last'"
                    ))
                };
                if let Ok(text) = v.extract::<String>() {
                    if text != "last" {
                        return Err(bad());
                    }
                    Some(cfe::OUTPUT_LAST)
                } else {
                    match v.extract::<i64>() {
                        Ok(n) if n >= 1 && !v.is_instance_of::<pyo3::types::PyBool>() => {
                            Some(n as usize)
                        }
                        _ => return Err(bad()),
                    }
                }
            }
        };
        let law = match law {
            None => None,
            Some("rigid") => Some(Law::Rigid),
            Some("contact") => Some(Law::Contact),
            Some("frictionless") => Some(Law::Frictionless),
            Some("coulomb") => Some(Law::Coulomb),
            Some(other) => {
                return Err(errors::ModelError::new_err(format!(
                    "law '{other}' is not known: use 'rigid', 'contact', 'frictionless' or 'coulomb'"
                )));
            }
        };
        match (law, friction) {
            (Some(Law::Coulomb), None) => {
                return Err(errors::ModelError::new_err(
                    "law 'coulomb' needs friction = μ (the friction coefficient)",
                ));
            }
            (l, Some(_)) if l != Some(Law::Coulomb) => {
                return Err(errors::ModelError::new_err(
                    "friction applies to law = 'coulomb' only",
                ));
            }
            _ => {}
        }
        let mut model = self.model.clone();
        if let Some(n) = write_every {
            model.settings.output_every = n;
        }
        let increments = model.settings.increments;
        let step_names: Vec<String> = model.steps().into_iter().map(|s| s.name).collect();
        let mut stopped: Option<PyErr> = None;
        // Ctrl-C while the solve runs: SIGINT sets the run's stop flag
        // (signal-hook chains to Python's own handler, so the KeyboardInterrupt
        // is pending too), which the solver reads inside the increments; with
        // `out` the run ends `interrupted` with the converged increments on disk.
        let stop = Arc::new(AtomicUsize::new(0));
        let sigint = signal_hook::flag::register_usize(
            signal_hook::consts::SIGINT,
            Arc::clone(&stop),
            signal_hook::consts::SIGINT as usize,
        )
        .ok();
        let outcome = py.detach(|| -> cfe::Result<(Analysis, Results)> {
            let mut analysis = Analysis::new(model)?;
            match (law, friction) {
                (Some(Law::Coulomb), Some(mu)) => analysis.override_friction(mu)?,
                (Some(law), _) => analysis.override_law(law),
                (None, _) => {}
            }
            let mut on_increment =
                |inc: &IncrementResult, row: Option<&HistoryRow>| -> cfe::Result<()> {
                    Python::attach(|py| {
                        let called = py.check_signals().and_then(|_| match &progress {
                            Some(callback) => {
                                let info = PyDict::new(py);
                                info.set_item("increment", inc.index)?;
                                info.set_item("increments", increments)?;
                                info.set_item("load_factor", inc.lambda)?;
                                info.set_item("iterations", inc.iterations)?;
                                info.set_item(
                                    "step",
                                    step_names.get(inc.step).map_or("", String::as_str),
                                )?;
                                info.set_item("time", inc.time)?;
                                if let Some(row) = row {
                                    info.set_item("history", results::history_row(py, row)?)?;
                                }
                                callback.call1(py, (info,)).map(|_| ())
                            }
                            None => Ok(()),
                        });
                        called.map_err(|e| {
                            stopped = Some(e);
                            cfe::Error::Model("stopped from Python".into())
                        })
                    })
                };
            match &out {
                None => {
                    // The history row only for a callback to receive it.
                    let rows = progress.is_some();
                    let a = &analysis;
                    let results = analysis.solve_observed_until(
                        |inc| on_increment(inc, rows.then(|| a.history_row(inc)).as_ref()),
                        &stop,
                    )?;
                    Ok((analysis, results))
                }
                Some(dir) => {
                    let mut last: Option<IncrementResult> = None;
                    let mut failed = false;
                    let folder = cfe::output::folder::OutputFolder::open(dir, force)?;
                    let summary = analysis.run_recorded_in(
                        folder,
                        &mut |inc, row| {
                            if !failed {
                                failed = on_increment(inc, Some(row)).is_err();
                            }
                            last = Some(inc.clone());
                        },
                        &stop,
                    )?;
                    let last = last.ok_or_else(|| {
                        cfe::Error::Model("the run converged no increment".into())
                    })?;
                    let results = Results {
                        stresses: analysis.recover(&last.u),
                        pairs: analysis.pair_rows(&last),
                        summary,
                        last,
                    };
                    Ok((analysis, results))
                }
            }
        });
        if let Some(id) = sigint {
            signal_hook::low_level::unregister(id);
        }
        // An interrupted run raises its `KeyboardInterrupt` (with the increment
        // and signal), unless the callback raised another exception first;
        // Python's pending one (or the one the callback's signal check raised)
        // is consumed by it rather than raised again later.
        let by_ctrl_c = stopped
            .as_ref()
            .is_none_or(|e| e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py));
        let outcome = match outcome {
            Err(e @ cfe::Error::Interrupted { .. }) if by_ctrl_c => {
                let _ = py.check_signals();
                return Err(to_py(py, e));
            }
            other => other,
        };
        if let Some(e) = stopped {
            return Err(e);
        }
        let (analysis, results) = outcome.map_err(|e| to_py(py, e))?;
        results::to_dict(py, &analysis, results)
    }

    fn __repr__(&self) -> String {
        format!(
            "Model('{}', parts: {}, interfaces: {})",
            self.model.title,
            self.parts().join(", "),
            self.interfaces().join(", ")
        )
    }
}

/// The rows of a 2D array with `cols` columns, or a `MeshError` naming `what`.
fn rows<T: numpy::Element + Copy>(
    part: &str,
    what: &str,
    a: &Bound<'_, PyAny>,
    cols: usize,
) -> PyResult<Vec<Vec<T>>> {
    let array: PyReadonlyArrayDyn<'_, T> = a.extract().map_err(|_| {
        mesh_error(
            part,
            format!(
                "`{what}` must be a NumPy array of {} with shape (n, {cols})",
                std::any::type_name::<T>()
            ),
        )
    })?;
    match array.shape() {
        [_, c] if *c == cols => Ok(array
            .as_array()
            .outer_iter()
            .map(|r| r.iter().copied().collect())
            .collect()),
        s => Err(mesh_error(
            part,
            format!("`{what}` must have shape (n, {cols}), got {s:?}"),
        )),
    }
}

/// An int64 array of any shape, or a `MeshError` naming `what`.
fn int_array<'py>(
    part: &str,
    what: &str,
    a: &Bound<'py, PyAny>,
) -> PyResult<PyReadonlyArrayDyn<'py, i64>> {
    a.extract()
        .map_err(|_| mesh_error(part, format!("`{what}` must be a NumPy array of int64")))
}

/// A node index from an int64, or a `MeshError` for a negative one.
fn index(part: &str, what: &str, i: i64) -> PyResult<usize> {
    usize::try_from(i)
        .map_err(|_| mesh_error(part, format!("`{what}` has a negative node index {i}")))
}

/// The native module.
#[pymodule]
fn _cfe(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<PyMesh>()?;
    m.add_class::<PyModel>()?;
    m.add_function(wrap_pyfunction!(dict::dict_to_toml, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
