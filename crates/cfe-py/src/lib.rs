//! The native module `cfe._cfe` of the Python package `cfe`: a thin layer over the
//! library. [`PyMesh`] builds a part's mesh from arrays (plane: triangles and
//! quadrilaterals; solid: tetrahedra and hexahedra), [`PyModel`] holds a
//! checked, meshed [`cfe::Model`] of either dimension (plane `Model<D2>` or
//! solid `Model<D3>`, told from the problem: one class for both) from a file,
//! TOML text, or text plus meshes, and solves it with the GIL released, handing
//! the results over as NumPy arrays made from the solver's buffers. The friendly API (`cfe.Model`, `cfe.Results`, meshio
//! conversion) is the pure-Python package around it (`python/cfe`).

mod dict;
mod errors;
mod results;
mod solid;

use cfe::IncrementResult;
use cfe::dim::D3;
use cfe::mesh::{BoundarySelection, Element, Mesh, SolidElement};
use cfe::model::{FromProblemFile, ProblemDimension};
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
use results::PyDim;
use solid::FaceSelection;

/// A part's mesh of either dimension.
#[derive(Clone)]
enum AnyMesh {
    /// A plane mesh (T3, Q4).
    Plane(Mesh),
    /// A solid mesh (TET4, HEX8).
    Solid(Mesh<D3>),
}

/// A part's mesh given as arrays: node coordinates, triangles and/or
/// quadrilaterals (plane) or tetrahedra and/or hexahedra (solid) (node indices,
/// 0-based, either way round) and named boundaries.
#[pyclass(name = "Mesh", module = "cfe._cfe", frozen)]
pub struct PyMesh {
    mesh: AnyMesh,
}

/// The hint added to a connectivity of the wrong width: which argument takes
/// a connectivity of `cols` corners.
fn cells_hint(what: &str, cols: usize) -> &'static str {
    match (what, cols) {
        ("triangles", 4) | ("hexahedra", 4) => {
            " (four corners per cell: `quads=` in a plane mesh, `tetrahedra=` in a solid one)"
        }
        ("quads", 3) | ("tetrahedra", 3) => " (three corners per cell: `triangles=`, a plane mesh)",
        (_, 8) => " (eight corners per cell: `hexahedra=`, a solid mesh)",
        (_, 2) => " (two nodes per row are edges: a plane mesh's `boundaries`)",
        _ => "",
    }
}

/// The rows of the connectivity `a` of `cols` corners (`what`: its argument's
/// name), as node indices.
fn cells(part: &str, what: &str, a: &Bound<'_, PyAny>, cols: usize) -> PyResult<Vec<Vec<usize>>> {
    let array = int_array(part, what, a)?;
    match array.shape() {
        [_, c] if *c == cols => array
            .as_array()
            .outer_iter()
            .map(|r| r.iter().map(|&i| index(part, what, i)).collect())
            .collect(),
        s => {
            let hint = match s {
                [_, c] => cells_hint(what, *c),
                _ => "",
            };
            Err(mesh_error(
                part,
                format!("`{what}` must have shape (n, {cols}), got {s:?}{hint}"),
            ))
        }
    }
}

/// The boundary selections of a solid mesh: name → faces `(j, 3)` or `(j, 4)`
/// (a `-1` fourth corner makes a row a triangle), nodes `(j,)`, or a list of
/// such face arrays.
fn solid_boundaries(part: &str, b: &Bound<'_, PyDict>) -> PyResult<Vec<(String, FaceSelection)>> {
    let mut named = Vec::new();
    for (k, v) in b.iter() {
        let name: String = k
            .extract()
            .map_err(|_| mesh_error(part, "boundary names must be strings"))?;
        let what = format!("boundaries['{name}']");
        let arrays: Vec<Bound<'_, PyAny>> = match v.cast::<PyList>() {
            Ok(list) => list.iter().collect(),
            Err(_) => vec![v],
        };
        let mut faces: Vec<Vec<usize>> = Vec::new();
        let mut nodes: Option<Vec<usize>> = None;
        for a in &arrays {
            let array = int_array(part, &what, a)?;
            match array.shape() {
                [_] if arrays.len() == 1 => {
                    nodes = Some(
                        (array.as_array().iter())
                            .map(|&i| index(part, &what, i))
                            .collect::<PyResult<_>>()?,
                    )
                }
                [_, w @ (3 | 4)] => {
                    for r in array.as_array().outer_iter() {
                        let corners = if *w == 4 && r[3] == -1 { 3 } else { *w };
                        faces.push(
                            (0..corners)
                                .map(|c| index(part, &what, r[c]))
                                .collect::<PyResult<_>>()?,
                        );
                    }
                }
                s => {
                    return Err(mesh_error(
                        part,
                        format!(
                            "`{what}` must be faces (j, 3) or (j, 4), nodes (j,), or a list of face arrays, got shape {s:?}{}",
                            if matches!(s, [_, 2]) {
                                " (edges (j, 2) bound a plane mesh; a solid mesh's boundaries are faces)"
                            } else {
                                ""
                            }
                        ),
                    ));
                }
            }
        }
        named.push((
            name,
            match nodes {
                Some(n) => FaceSelection::Nodes(n),
                None => FaceSelection::Faces(faces),
            },
        ));
    }
    Ok(named)
}

#[pymethods]
impl PyMesh {
    /// Builds and checks a mesh. Plane: `points` (n, 2) float64, `triangles`
    /// (m, 3) and `quads` (k, 4) int64, `boundaries` a dict name → edges (j, 2)
    /// or nodes (j,). Solid: `points` (n, 3), `tetrahedra` (m, 4) and
    /// `hexahedra` (k, 8) (Gmsh/VTK node order), `boundaries` a dict name →
    /// faces (j, 3) or (j, 4) (or a list of both), or nodes (j,). `part` names
    /// the part in messages.
    #[new]
    #[pyo3(signature = (points, triangles=None, quads=None, boundaries=None, *, tetrahedra=None, hexahedra=None, part="mesh"))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        triangles: Option<&Bound<'_, PyAny>>,
        quads: Option<&Bound<'_, PyAny>>,
        boundaries: Option<&Bound<'_, PyDict>>,
        tetrahedra: Option<&Bound<'_, PyAny>>,
        hexahedra: Option<&Bound<'_, PyAny>>,
        part: &str,
    ) -> PyResult<Self> {
        let plane = triangles.is_some() || quads.is_some();
        let solid = tetrahedra.is_some() || hexahedra.is_some();
        if plane && solid {
            return Err(mesh_error(
                part,
                "a mesh is plane (`triangles`, `quads`) or solid (`tetrahedra`, `hexahedra`), not both: give the part's elements of one dimension",
            ));
        }
        if solid {
            if let Ok(a) = points.extract::<PyReadonlyArrayDyn<'_, f64>>()
                && !matches!(a.shape(), [_, 3])
            {
                return Err(mesh_error(
                    part,
                    format!(
                        "tetrahedra and hexahedra need points (n, 3) (x, y, z), got shape {:?}",
                        a.shape()
                    ),
                ));
            }
            let nodes: Vec<[f64; 3]> = rows(part, "points", points, 3)?
                .into_iter()
                .map(|r: Vec<f64>| [r[0], r[1], r[2]])
                .collect();
            let mut elements = Vec::new();
            if let Some(t) = tetrahedra {
                for r in cells(part, "tetrahedra", t, 4)? {
                    elements.push(SolidElement::Tet4([r[0], r[1], r[2], r[3]]));
                }
            }
            if let Some(h) = hexahedra {
                for r in cells(part, "hexahedra", h, 8)? {
                    elements.push(SolidElement::Hex8(std::array::from_fn(|i| r[i])));
                }
            }
            if elements.is_empty() {
                return Err(mesh_error(
                    part,
                    "no elements: give `tetrahedra` (m, 4) and/or `hexahedra` (m, 8)",
                ));
            }
            let named = match boundaries {
                Some(b) => solid_boundaries(part, b)?,
                None => Vec::new(),
            };
            let mesh =
                solid::from_arrays(part, nodes, elements, named).map_err(|e| to_py(py, e))?;
            return Ok(PyMesh {
                mesh: AnyMesh::Solid(mesh),
            });
        }
        let nodes: Vec<[f64; 2]> = rows(part, "points", points, 2)?
            .into_iter()
            .map(|r: Vec<f64>| [r[0], r[1]])
            .collect();
        let mut elements = Vec::new();
        if let Some(t) = triangles {
            for r in cells(part, "triangles", t, 3)? {
                elements.push(Element::T3([r[0], r[1], r[2]]));
            }
        }
        if let Some(q) = quads {
            for r in cells(part, "quads", q, 4)? {
                elements.push(Element::Q4([r[0], r[1], r[2], r[3]]));
            }
        }
        if elements.is_empty() {
            return Err(mesh_error(
                part,
                "no elements: give `triangles` (m, 3) and/or `quads` (m, 4) (or `tetrahedra`, `hexahedra` for a solid mesh)",
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
        Ok(PyMesh {
            mesh: AnyMesh::Plane(mesh),
        })
    }

    /// 2 for a plane mesh, 3 for a solid one.
    #[getter]
    fn dimension(&self) -> usize {
        match &self.mesh {
            AnyMesh::Plane(_) => 2,
            AnyMesh::Solid(_) => 3,
        }
    }

    /// Node coordinates (n, 2) or (n, 3).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        match &self.mesh {
            AnyMesh::Plane(m) => results::points(py, m),
            AnyMesh::Solid(m) => results::points(py, m),
        }
    }

    /// The triangles (m, 3), counter-clockwise (none in a solid mesh).
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        self.cells(py, 2, 0)
    }

    /// The quadrilaterals (k, 4), counter-clockwise (none in a solid mesh).
    #[getter]
    fn quads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        self.cells(py, 2, 1)
    }

    /// The tetrahedra (m, 4), of positive volume (none in a plane mesh).
    #[getter]
    fn tetrahedra<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        self.cells(py, 3, 0)
    }

    /// The hexahedra (k, 8), of positive volume (none in a plane mesh).
    #[getter]
    fn hexahedra<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        self.cells(py, 3, 1)
    }

    /// Named boundaries: name → edges (j, 2), each with the part on its left,
    /// in order along the boundary (plane); name → faces (j, 3) or (j, 4),
    /// outward by the right-hand rule (solid; a boundary of triangles and
    /// quadrangles is (j, 4) with -1 as its triangles' fourth corner).
    #[getter]
    fn boundaries<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match &self.mesh {
            AnyMesh::Plane(m) => results::boundaries(py, m),
            AnyMesh::Solid(m) => results::boundaries(py, m),
        }
    }

    fn __repr__(&self) -> String {
        let (nodes, elements, names): (usize, String, Vec<String>) = match &self.mesh {
            AnyMesh::Plane(m) => (
                m.nodes.len(),
                m.describe_elements(),
                m.boundaries.keys().cloned().collect(),
            ),
            AnyMesh::Solid(m) => (
                m.nodes.len(),
                m.describe_elements(),
                m.boundaries.keys().cloned().collect(),
            ),
        };
        format!(
            "Mesh({nodes} nodes, {elements}, boundaries: {})",
            names.join(", ")
        )
    }
}

impl PyMesh {
    /// The cells of kind `k` (0: simplex, 1: the other) of a mesh of dimension
    /// `dim`; an empty `(0, corners)` array for a mesh of the other dimension.
    fn cells<'py>(
        &self,
        py: Python<'py>,
        dim: usize,
        k: usize,
    ) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        match &self.mesh {
            AnyMesh::Plane(m) if dim == 2 => results::connectivity(py, m, k).map(|(c, _)| c),
            AnyMesh::Solid(m) if dim == 3 => results::connectivity(py, m, k).map(|(c, _)| c),
            _ => {
                let corners = if dim == 2 {
                    <cfe::dim::D2 as PyDim>::CELLS[k].2
                } else {
                    <D3 as PyDim>::CELLS[k].2
                };
                PyArray1::<i64>::from_vec(py, Vec::new()).reshape(vec![0, corners])
            }
        }
    }
}

/// A model of either dimension.
#[derive(Clone)]
enum AnyModel {
    /// A plane model.
    Plane(cfe::Model),
    /// A solid model.
    Solid(cfe::Model<D3>),
}

/// What reads the same in a model of either dimension.
struct Common<'a> {
    title: &'a str,
    refine: usize,
    text: &'a str,
    notes: &'a [String],
    settings: &'a cfe::Settings,
    parts: Vec<String>,
    interfaces: Vec<String>,
    steps: Vec<cfe::model::Step>,
}

impl<'a> Common<'a> {
    /// The common items of `m`.
    fn of<D: cfe::mesh::MeshDim>(m: &'a cfe::Model<D>) -> Self {
        Common {
            title: &m.title,
            refine: m.refine,
            text: &m.text,
            notes: &m.notes,
            settings: &m.settings,
            parts: m.parts.iter().map(|p| p.name.clone()).collect(),
            interfaces: m.interfaces.iter().map(|i| i.name.clone()).collect(),
            steps: m.steps(),
        }
    }
}

impl AnyModel {
    /// Its common items.
    fn common(&self) -> Common<'_> {
        match self {
            AnyModel::Plane(m) => Common::of(m),
            AnyModel::Solid(m) => Common::of(m),
        }
    }
}

/// A checked, meshed model, ready to solve: plane or solid, told from the
/// problem (its parts' mesh keys, Gmsh files or given meshes).
#[pyclass(name = "Model", module = "cfe._cfe", frozen)]
pub struct PyModel {
    model: AnyModel,
}

#[pymethods]
impl PyModel {
    /// Reads, checks and meshes the problem file at `path`, plane or solid
    /// ([`cfe::model::problem_dimension`]); `refine` multiplies the structured
    /// cell counts and subdivides Gmsh meshes (as `cfe run --refine`).
    #[staticmethod]
    #[pyo3(signature = (path, refine=1))]
    fn from_file(py: Python<'_>, path: PathBuf, refine: usize) -> PyResult<Self> {
        let model = py
            .detach(|| match cfe::model::problem_dimension(&path)? {
                ProblemDimension::Plane => {
                    cfe::Model::from_file(&path, refine).map(AnyModel::Plane)
                }
                ProblemDimension::Solid => {
                    <cfe::Model<D3> as FromProblemFile>::from_file(&path, refine)
                        .map(AnyModel::Solid)
                }
            })
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel { model })
    }

    /// Reads a CalculiX/Abaqus input deck (`.inp`): its common subset mapped onto
    /// cfe's parts, interfaces, supports, loads and steps (README, "Running a
    /// CalculiX/Abaqus deck"); anything outside it raises `ParseError` with the
    /// line, the keyword and the fault. A deck is a plane model.
    #[staticmethod]
    fn from_inp(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let model = py
            .detach(|| cfe::Model::from_inp(&path))
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel {
            model: AnyModel::Plane(model),
        })
    }

    /// 2 for a plane model, 3 for a solid one.
    #[getter]
    fn dimension(&self) -> usize {
        match &self.model {
            AnyModel::Plane(_) => 2,
            AnyModel::Solid(_) => 3,
        }
    }

    /// What reading the input noted (a deck's ignored keywords and mapping).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.model.common().notes.to_vec()
    }

    /// Reads, checks and meshes a problem given as TOML text, plane or solid
    /// (from its parts, or from the meshes given); `path` is used in messages
    /// and to find Gmsh files (relative to its folder); `meshes` gives the meshes
    /// of parts that have no mesh key, by part name (all plane or all solid).
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
        let mut plane: BTreeMap<String, Mesh> = BTreeMap::new();
        let mut solid: BTreeMap<String, Mesh<D3>> = BTreeMap::new();
        for (k, m) in meshes.unwrap_or_default() {
            match &m.mesh {
                AnyMesh::Plane(mesh) => {
                    plane.insert(k, mesh.clone());
                }
                AnyMesh::Solid(mesh) => {
                    solid.insert(k, mesh.clone());
                }
            }
        }
        if let (Some(p), Some(s)) = (plane.keys().next(), solid.keys().next()) {
            return Err(errors::ModelError::new_err(format!(
                "the meshes given mix plane and solid ones: part '{p}' has a plane mesh (triangles, quads) and part '{s}' a solid one (tetrahedra, hexahedra); a model is plane or solid: give every part a mesh of the same dimension"
            )));
        }
        let model = py
            .detach(|| -> cfe::Result<AnyModel> {
                let dimension = cfe::model::problem_text_dimension(&text, &path)?;
                if !solid.is_empty() || (dimension == ProblemDimension::Solid && plane.is_empty()) {
                    return cfe::Model::<D3>::from_str_with_solid_meshes(&text, &path, refine, solid)
                        .map(AnyModel::Solid);
                }
                if dimension == ProblemDimension::Solid {
                    let name = plane.keys().next().cloned().unwrap_or_default();
                    return Err(cfe::Error::Model(format!(
                        "part '{name}' has a plane mesh (triangles, quads), and the problem is solid (it has `box` or 3D Gmsh parts): give it a solid mesh (tetrahedra, hexahedra, points (n, 3)), or mesh every part in the plane"
                    )));
                }
                cfe::Model::from_str_with_meshes(&text, &path, refine, plane).map(AnyModel::Plane)
            })
            .map_err(|e| to_py(py, e))?;
        Ok(PyModel { model })
    }

    /// The title.
    #[getter]
    fn title(&self) -> &str {
        self.model.common().title
    }

    /// The refinement factor the model was meshed with.
    #[getter]
    fn refine(&self) -> usize {
        self.model.common().refine
    }

    /// The problem text (TOML).
    #[getter]
    fn text(&self) -> &str {
        self.model.common().text
    }

    /// The part names, in order.
    #[getter]
    fn parts(&self) -> Vec<String> {
        self.model.common().parts
    }

    /// The interface names, in order.
    #[getter]
    fn interfaces(&self) -> Vec<String> {
        self.model.common().interfaces
    }

    /// The analysis settings: increments, scheme, max_iterations, gap_tolerance,
    /// solver (`direct` or `cg`).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let common = self.model.common();
        let s = common.settings;
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
        for s in self.model.common().steps {
            let d = PyDict::new(py);
            d.set_item("name", s.name)?;
            d.set_item("increments", s.increments)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// The mesh of part `name` (as meshed, before coupling nodes are moved).
    fn mesh(&self, name: &str) -> PyResult<PyMesh> {
        let missing = || {
            errors::ModelError::new_err(format!(
                "no part named '{name}' (parts: {})",
                self.parts().join(", ")
            ))
        };
        let mesh = match &self.model {
            AnyModel::Plane(m) => AnyMesh::Plane(
                m.parts[m.part_index(name).ok_or_else(missing)?]
                    .mesh
                    .clone(),
            ),
            AnyModel::Solid(m) => AnyMesh::Solid(
                m.parts[m.part_index(name).ok_or_else(missing)?]
                    .mesh
                    .clone(),
            ),
        };
        Ok(PyMesh { mesh })
    }

    /// Finds the coupling pairs and numbers the DOFs without solving; returns the
    /// description `cfe check` prints.
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        let model = self.model.clone();
        py.detach(|| match model {
            AnyModel::Plane(m) => Analysis::new(m).map(|a| a.describe()),
            AnyModel::Solid(m) => Analysis::<D3>::new(m).map(|a| a.describe()),
        })
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
        let options = SolveOptions {
            progress,
            out,
            law,
            friction,
            write_every,
            force,
        };
        match &self.model {
            AnyModel::Plane(m) => solve_model(py, m.clone(), options),
            AnyModel::Solid(m) => solve_model(py, m.clone(), options),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "Model('{}', {}, parts: {}, interfaces: {})",
            self.title(),
            if self.dimension() == 3 {
                "solid"
            } else {
                "plane"
            },
            self.parts().join(", "),
            self.interfaces().join(", ")
        )
    }
}

/// The checked arguments of [`PyModel::solve`].
struct SolveOptions {
    progress: Option<Py<PyAny>>,
    out: Option<PathBuf>,
    law: Option<Law>,
    friction: Option<f64>,
    write_every: Option<usize>,
    force: bool,
}

/// Solves `model` (of either dimension) as [`PyModel::solve`] states, with
/// the GIL released; the raw results dict.
fn solve_model<D: PyDim>(
    py: Python<'_>,
    model: cfe::Model<D>,
    options: SolveOptions,
) -> PyResult<Bound<'_, PyDict>> {
    let SolveOptions {
        progress,
        out,
        law,
        friction,
        write_every,
        force,
    } = options;
    let mut model = model;
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
    let outcome = py.detach(|| -> cfe::Result<(Analysis<D>, Results<D>)> {
        let mut analysis = Analysis::new(model)?;
        match (law, friction) {
            (Some(Law::Coulomb), Some(mu)) => analysis.override_friction(mu)?,
            (Some(law), _) => analysis.override_law(law),
            (None, _) => {}
        }
        let mut on_increment = |inc: &IncrementResult<D>,
                                row: Option<&HistoryRow>|
         -> cfe::Result<()> {
            Python::attach(|py| {
                let called = py.check_signals().and_then(|_| match &progress {
                    Some(callback) => {
                        let info = PyDict::new(py);
                        info.set_item("increment", inc.index)?;
                        info.set_item("increments", increments)?;
                        info.set_item("load_factor", inc.lambda)?;
                        info.set_item("iterations", inc.iterations)?;
                        info.set_item("step", step_names.get(inc.step).map_or("", String::as_str))?;
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
                let mut last: Option<IncrementResult<D>> = None;
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
                let last =
                    last.ok_or_else(|| cfe::Error::Model("the run converged no increment".into()))?;
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
