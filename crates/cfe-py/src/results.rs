//! The results of a solve as a dict of NumPy arrays for the Python layer
//! (`cfe.Results`). The large arrays (displacements, stresses) are the solver's
//! buffers moved into NumPy, not copied: the displacement vector of all DOFs
//! becomes one array, each part's `(n, 2)` (plane) or `(n, 3)` (solid)
//! displacement a view of it (in Python), and each part's stresses an `(n, 3)`
//! (σxx, σyy, σxy) or `(n, 6)` (σxx, σyy, σzz, σxy, σyz, σxz) array whose
//! columns are views. What differs between the dimensions is [`PyDim`]'s.

use cfe::Interface;
use cfe::PartStress;
use cfe::analysis::Analysis;
use cfe::dim::{D2, D3};
use cfe::mesh::{Element, Mesh, MeshCell, MeshDim, MeshFace, SolidElement};
use cfe::output::report::PairRow;
use cfe::{PairState, Part, Results, RunDim};
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::iter::Peekable;

/// `flat` (rows of `cols` values) moved into an `(n, cols)` NumPy array.
fn matrix<T: numpy::Element>(
    py: Python<'_>,
    flat: Vec<T>,
    cols: usize,
) -> PyResult<Bound<'_, PyArrayDyn<T>>> {
    let n = flat.len() / cols;
    PyArray1::from_vec(py, flat).reshape(vec![n, cols])
}

/// A connectivity `(k, corners)` and the element indices of its rows.
pub type Cells<'py> = (Bound<'py, PyArrayDyn<i64>>, Bound<'py, PyArray1<i64>>);

/// What the Python layer reads differently in a plane and a solid model: the
/// names of the element kinds in the part dicts, the stresses' width and von
/// Mises, the line probes (plane only) and the 3D pairs' second tangent.
pub trait PyDim: RunDim {
    /// The two element kinds as (connectivity key, element-index key, corners):
    /// `triangles`/`triangle_ids` (3) and `quads`/`quad_ids` (4) in 2D,
    /// `tetrahedra`/`tetrahedron_ids` (4) and `hexahedra`/`hexahedron_ids` (8) in 3D.
    const CELLS: [(&'static str, &'static str, usize); 2];

    /// Whether `cell` is of kind `k` (0 or 1) of [`PyDim::CELLS`].
    fn is_kind(cell: &Self::Cell, k: usize) -> bool;

    /// The part's stresses (`nodal_stress`, `element_stress`, their von Mises,
    /// and in an axisymmetric part the hoop stress) into `d`.
    fn stresses<'py>(
        py: Python<'py>,
        d: &Bound<'py, PyDict>,
        part: &Part<Self>,
        stress: PartStress<Self::Stress>,
    ) -> PyResult<()>;

    /// The line probes at increment `inc` (`lines`): none in a solid model.
    fn lines<'py>(
        py: Python<'py>,
        analysis: &Analysis<Self>,
        inc: &cfe::IncrementResult<Self>,
    ) -> PyResult<Bound<'py, PyDict>>;
}

impl PyDim for D2 {
    const CELLS: [(&'static str, &'static str, usize); 2] =
        [("triangles", "triangle_ids", 3), ("quads", "quad_ids", 4)];

    fn is_kind(cell: &Element, k: usize) -> bool {
        matches!((cell, k), (Element::T3(_), 0) | (Element::Q4(_), 1))
    }

    fn stresses<'py>(
        py: Python<'py>,
        d: &Bound<'py, PyDict>,
        part: &Part,
        stress: PartStress,
    ) -> PyResult<()> {
        let m = &part.material;
        // An axisymmetric part's von Mises includes its hoop stress σθθ, which
        // comes as its own arrays (`nodal_sigma_theta`, `element_sigma_theta`).
        let von_mises = |s: &[[f64; 3]], hoop: Option<&Vec<f64>>| -> Vec<f64> {
            s.iter()
                .enumerate()
                .map(|(i, v)| m.von_mises_with(*v, hoop.map(|h| h[i])))
                .collect()
        };
        let hoop = stress.hoop.as_ref();
        d.set_item(
            "nodal_von_mises",
            PyArray1::from_vec(py, von_mises(&stress.nodal, hoop.map(|h| &h.nodal))),
        )?;
        d.set_item(
            "element_von_mises",
            PyArray1::from_vec(py, von_mises(&stress.element, hoop.map(|h| &h.element))),
        )?;
        if let Some(h) = hoop {
            d.set_item("nodal_sigma_theta", PyArray1::from_vec(py, h.nodal.clone()))?;
            d.set_item(
                "element_sigma_theta",
                PyArray1::from_vec(py, h.element.clone()),
            )?;
        }
        d.set_item(
            "nodal_stress",
            matrix(py, stress.nodal.into_flattened(), 3)?,
        )?;
        d.set_item(
            "element_stress",
            matrix(py, stress.element.into_flattened(), 3)?,
        )?;
        Ok(())
    }

    fn lines<'py>(
        py: Python<'py>,
        analysis: &Analysis,
        inc: &cfe::IncrementResult,
    ) -> PyResult<Bound<'py, PyDict>> {
        lines(py, analysis, inc)
    }
}

impl PyDim for D3 {
    const CELLS: [(&'static str, &'static str, usize); 2] = [
        ("tetrahedra", "tetrahedron_ids", 4),
        ("hexahedra", "hexahedron_ids", 8),
    ];

    fn is_kind(cell: &SolidElement, k: usize) -> bool {
        matches!(
            (cell, k),
            (SolidElement::Tet4(_), 0) | (SolidElement::Hex8(_), 1)
        )
    }

    /// The six stresses in the Voigt order (xx, yy, zz, xy, yz, xz) and von
    /// Mises ([`cfe::von_mises_3d`]), as the VTU files hold them.
    fn stresses<'py>(
        py: Python<'py>,
        d: &Bound<'py, PyDict>,
        _: &Part<D3>,
        stress: PartStress<[f64; 6]>,
    ) -> PyResult<()> {
        let von_mises = |s: &[[f64; 6]]| -> Vec<f64> { s.iter().map(cfe::von_mises_3d).collect() };
        d.set_item(
            "nodal_von_mises",
            PyArray1::from_vec(py, von_mises(&stress.nodal)),
        )?;
        d.set_item(
            "element_von_mises",
            PyArray1::from_vec(py, von_mises(&stress.element)),
        )?;
        d.set_item(
            "nodal_stress",
            matrix(py, stress.nodal.into_flattened(), 6)?,
        )?;
        d.set_item(
            "element_stress",
            matrix(py, stress.element.into_flattened(), 6)?,
        )?;
        Ok(())
    }

    fn lines<'py>(
        py: Python<'py>,
        _: &Analysis<D3>,
        _: &cfe::IncrementResult<D3>,
    ) -> PyResult<Bound<'py, PyDict>> {
        Ok(PyDict::new(py))
    }
}

/// The node coordinates of `mesh` as an `(n, N)` array.
pub fn points<'py, D: MeshDim>(
    py: Python<'py>,
    mesh: &Mesh<D>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let flat: Vec<f64> = (mesh.nodes.iter())
        .flat_map(|p| p.as_ref().iter().copied())
        .collect();
    matrix(py, flat, D::N)
}

/// The elements of `mesh` of kind `k` of [`PyDim::CELLS`] (triangles or
/// quadrilaterals, tetrahedra or hexahedra): their connectivity `(k, corners)`
/// and their indices among all the mesh's elements (the order of element
/// stresses).
pub fn connectivity<'py, D: PyDim>(
    py: Python<'py>,
    mesh: &Mesh<D>,
    k: usize,
) -> PyResult<Cells<'py>> {
    let mut cells = Vec::new();
    let mut ids = Vec::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        if D::is_kind(el, k) {
            cells.extend(el.nodes().iter().map(|&n| n as i64));
            ids.push(e as i64);
        }
    }
    Ok((
        matrix(py, cells, D::CELLS[k].2)?,
        PyArray1::from_vec(py, ids),
    ))
}

/// Named boundaries: name → edges `(j, 2)` (plane) or faces `(j, 3)` or
/// `(j, 4)` (solid: triangles or quadrangles; a boundary of both is `(j, 4)`
/// with `-1` as the fourth corner of its triangles), outward.
pub fn boundaries<'py, D: MeshDim>(
    py: Python<'py>,
    mesh: &Mesh<D>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, faces) in &mesh.boundaries {
        let width = faces.iter().map(|f| f.nodes().len()).max().unwrap_or(D::N);
        let mut flat: Vec<i64> = Vec::with_capacity(width * faces.len());
        for f in faces {
            flat.extend(f.nodes().iter().map(|&n| n as i64));
            flat.extend(std::iter::repeat_n(-1, width - f.nodes().len()));
        }
        d.set_item(name, matrix(py, flat, width)?)?;
    }
    Ok(d)
}

/// The results as a dict: `u` (all DOFs), `parts` (per part: name, node offset,
/// points, connectivity, boundaries, material, nodal and element stresses and
/// von Mises), `interfaces` (per interface: its pairs' arrays), `summary`
/// (`summary.json`'s content as Python objects), `load_factor`, `step` and `time`
/// of the last increment.
pub fn to_dict<'py, D: PyDim>(
    py: Python<'py>,
    analysis: &Analysis<D>,
    results: Results<D>,
) -> PyResult<Bound<'py, PyDict>> {
    let Results {
        last,
        stresses,
        pairs,
        summary,
    } = results;
    let out = PyDict::new(py);
    let json = serde_json::to_string(&summary)
        .map_err(|e| crate::errors::CfeError::new_err(format!("summary: {e}")))?;
    out.set_item(
        "summary",
        py.import("json")?.call_method1("loads", (json,))?,
    )?;
    out.set_item("load_factor", last.lambda)?;
    out.set_item("step", analysis.step_name(last.step))?;
    out.set_item("time", last.time)?;
    out.set_item("lines", D::lines(py, analysis, &last)?)?;
    out.set_item("dimension", D::N)?;
    out.set_item("u", PyArray1::from_vec(py, last.u))?;
    out.set_item("history", history(py, &summary.history)?)?;

    let parts = PyList::empty(py);
    for (p, (part, stress)) in analysis.model.parts.iter().zip(stresses).enumerate() {
        parts.append(part_dict(py, analysis, p, part, stress)?)?;
    }
    out.set_item("parts", parts)?;

    let interfaces = PyList::empty(py);
    // `pair_rows` lists the pairs interface by interface, in this order.
    let mut rows = pairs.into_iter().peekable();
    for iface in &analysis.interfaces {
        interfaces.append(interface_dict(py, analysis, iface, &mut rows)?)?;
    }
    out.set_item("interfaces", interfaces)?;
    Ok(out)
}

/// The history as a dict of columns (`history.csv`'s names) in order: NumPy
/// arrays of the counts (int64) and numbers (float64), a list of the step
/// names.
fn history<'py>(
    py: Python<'py>,
    rows: &[cfe::results::history::HistoryRow],
) -> PyResult<Bound<'py, PyDict>> {
    use cfe::results::history::{Values, columns};
    let d = PyDict::new(py);
    for (name, values) in columns(rows) {
        match values {
            Values::Count(c) => {
                let c: Vec<i64> = c.into_iter().map(|x| x as i64).collect();
                d.set_item(name, PyArray1::from_vec(py, c))?
            }
            Values::Number(x) => d.set_item(name, PyArray1::from_vec(py, x))?,
            Values::Name(n) => d.set_item(name, n)?,
        }
    }
    Ok(d)
}

/// One increment's row of the history as a dict of `history.csv`'s columns in
/// order to scalars: ints (increment, step_index), the step's name, floats.
pub(crate) fn history_row<'py>(
    py: Python<'py>,
    row: &cfe::results::history::HistoryRow,
) -> PyResult<Bound<'py, PyDict>> {
    use cfe::results::history::{Values, columns};
    let d = PyDict::new(py);
    for (name, values) in columns(std::slice::from_ref(row)) {
        match values {
            Values::Count(c) => d.set_item(name, c[0])?,
            Values::Number(x) => d.set_item(name, x[0])?,
            Values::Name(n) => d.set_item(name, &n[0])?,
        }
    }
    Ok(d)
}

/// The line probes (`[[line]]`) sampled at increment `inc`, by name: per line a
/// dict of `s` `(n,)` (distance from its start), `x` `(n, 2)`, `part` `(n,)`
/// (the part's name per sample), `u` `(n, 2)`, `stress` `(n, 3)` (σxx, σyy,
/// σxy) and `von_mises` `(n,)` — the columns of `lines/<name>.csv`.
fn lines<'py>(
    py: Python<'py>,
    analysis: &Analysis,
    inc: &cfe::IncrementResult,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, samples) in analysis.line_samples(inc) {
        let line = PyDict::new(py);
        line.set_item(
            "s",
            PyArray1::from_vec(py, samples.iter().map(|p| p.s).collect()),
        )?;
        line.set_item(
            "x",
            matrix(py, samples.iter().flat_map(|p| p.x).collect(), 2)?,
        )?;
        let parts: Vec<&str> = samples
            .iter()
            .map(|p| analysis.model.parts[p.part].name.as_str())
            .collect();
        line.set_item("part", parts)?;
        line.set_item(
            "u",
            matrix(py, samples.iter().flat_map(|p| p.u).collect(), 2)?,
        )?;
        line.set_item(
            "stress",
            matrix(py, samples.iter().flat_map(|p| p.stress).collect(), 3)?,
        )?;
        line.set_item(
            "von_mises",
            PyArray1::from_vec(py, samples.iter().map(|p| p.von_mises).collect()),
        )?;
        d.set_item(name, line)?;
    }
    Ok(d)
}

/// Part `p` (`part`) as a dict: name, node offset, points, connectivity, boundaries,
/// material, and its `stress` (nodal and element, with von Mises).
fn part_dict<'py, D: PyDim>(
    py: Python<'py>,
    analysis: &Analysis<D>,
    p: usize,
    part: &Part<D>,
    stress: PartStress<D::Stress>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &part.name)?;
    d.set_item("node_offset", analysis.dofs.node_offset[p])?;
    d.set_item("points", points(py, &part.mesh)?)?;
    for (k, (cells_key, ids_key, _)) in D::CELLS.iter().enumerate() {
        let (cells, ids) = connectivity(py, &part.mesh, k)?;
        d.set_item(cells_key, cells)?;
        d.set_item(ids_key, ids)?;
    }
    d.set_item("boundaries", boundaries(py, &part.mesh)?)?;
    let m = &part.material;
    let material = PyDict::new(py);
    material.set_item("E", m.young)?;
    material.set_item("nu", m.poisson)?;
    if D::N == 2 {
        material.set_item("thickness", m.thickness)?;
    }
    d.set_item("material", material)?;
    D::stresses(py, &d, part, stress)?;
    Ok(d)
}

/// Interface `iface` as a dict: its definition and its pairs' arrays, taken from
/// the front of `rows` (the pair rows of all interfaces, in order).
fn interface_dict<'py, D: PyDim>(
    py: Python<'py>,
    analysis: &Analysis<D>,
    iface: &Interface<D>,
    rows: &mut Peekable<std::vec::IntoIter<PairRow>>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &iface.name)?;
    d.set_item("host", &analysis.model.parts[iface.host].name)?;
    d.set_item("node_part", &analysis.model.parts[iface.node_part].name)?;
    d.set_item("law", iface.law.as_str())?;
    d.set_item("c_n", iface.c_n)?;
    d.set_item("c_s", iface.c_s)?;
    d.set_item("friction", iface.friction)?;
    d.set_item("unpaired", iface.unpaired)?;
    let k = iface.elements.len();
    let mut node = Vec::with_capacity(k);
    let mut host_element = Vec::with_capacity(k);
    let mut position = Vec::with_capacity(D::N * k);
    // The solid pairs' second tangent (t₂) and global force.
    let mut solid: [Vec<f64>; 7] = std::array::from_fn(|_| Vec::with_capacity(k));
    let mut bonded = Vec::with_capacity(k);
    let mut settled = Vec::with_capacity(k);
    let mut violation = Vec::with_capacity(k);
    let mut state = Vec::with_capacity(k);
    let mut columns: [Vec<f64>; 11] = std::array::from_fn(|_| Vec::with_capacity(k));
    while let Some(r) = rows.next_if(|r| r.interface == iface.name) {
        node.push(r.node as i64);
        host_element.push(r.host_element as i64);
        position.extend([r.x, r.y]);
        if let Some(z) = r.z {
            position.push(z);
        }
        for (c, v) in solid.iter_mut().zip([
            r.slip_t2,
            r.force_t2,
            r.slip_t2_plastic,
            r.shear_t2,
            r.force_x,
            r.force_y,
            r.force_z,
        ]) {
            if let Some(v) = v {
                c.push(v);
            }
        }
        bonded.push(r.state == PairState::Bonded);
        state.push(r.state.as_str());
        settled.push(r.settled);
        // 0: the law holds; 1: a bonded pair pulls; 2: an open pair penetrates;
        // 3: a stick pair exceeds μ|f_n|; 4: a slip pair is off μ|f_n|; 5: a
        // stick pair pulls and carries shear (tension and friction).
        violation.push(r.violation_code());
        for (c, v) in columns.iter_mut().zip([
            r.gap_n,
            r.slip_s,
            r.force_n,
            r.force_s,
            r.violation_amount.first().copied().unwrap_or(0.0),
            r.gap0,
            r.gap,
            r.slip,
            r.pressure,
            r.shear,
            r.tributary,
        ]) {
            c.push(v);
        }
    }
    let normal: Vec<f64> = (iface.elements.iter())
        .flat_map(|c| c.normal.as_ref().to_vec())
        .collect();
    d.set_item("node", PyArray1::from_vec(py, node))?;
    d.set_item("host_element", PyArray1::from_vec(py, host_element))?;
    d.set_item("position", matrix(py, position, D::N)?)?;
    d.set_item("normal", matrix(py, normal, D::N)?)?;
    if D::N == 3 {
        let [slip_t2, force_t2, slip_t2_plastic, shear_t2, fx, fy, fz] = solid;
        d.set_item("slip_t2", PyArray1::from_vec(py, slip_t2))?;
        d.set_item("force_t2", PyArray1::from_vec(py, force_t2))?;
        d.set_item("slip_t2_plastic", PyArray1::from_vec(py, slip_t2_plastic))?;
        d.set_item("shear_t2", PyArray1::from_vec(py, shear_t2))?;
        let force: Vec<f64> = (0..fx.len()).flat_map(|i| [fx[i], fy[i], fz[i]]).collect();
        d.set_item("force", matrix(py, force, 3)?)?;
        // The pairs' tangents t₁, t₂ (global unit vectors): the frame of the
        // `_s` (t₁) and `_t2` components.
        for (key, axis) in [("t1", 1), ("t2", 2)] {
            let t: Vec<f64> = (iface.elements.iter())
                .flat_map(|c| D::axis(&c.frame, axis).as_ref().to_vec())
                .collect();
            d.set_item(key, matrix(py, t, 3)?)?;
        }
    }
    d.set_item("bonded", PyArray1::from_vec(py, bonded))?;
    d.set_item("settled", PyArray1::from_vec(py, settled))?;
    let [
        gap_n,
        slip_s,
        force_n,
        force_s,
        violation_amount,
        gap0,
        gap,
        slip,
        pressure,
        shear,
        tributary,
    ] = columns;
    // `bonded`, `open` or `slip` per pair.
    d.set_item("state", state)?;
    d.set_item("gap0", PyArray1::from_vec(py, gap0))?;
    d.set_item("gap", PyArray1::from_vec(py, gap))?;
    d.set_item("slip", PyArray1::from_vec(py, slip))?;
    d.set_item("pressure", PyArray1::from_vec(py, pressure))?;
    d.set_item("shear", PyArray1::from_vec(py, shear))?;
    d.set_item("tributary", PyArray1::from_vec(py, tributary))?;
    d.set_item("violation", PyArray1::from_vec(py, violation))?;
    d.set_item("violation_amount", PyArray1::from_vec(py, violation_amount))?;
    d.set_item("gap_n", PyArray1::from_vec(py, gap_n))?;
    d.set_item("slip_s", PyArray1::from_vec(py, slip_s))?;
    d.set_item("force_n", PyArray1::from_vec(py, force_n))?;
    d.set_item("force_s", PyArray1::from_vec(py, force_s))?;
    // Segment coupling: each pair is an integration point; its share of the face
    // (0 for a node pair) turns its force into a traction.
    d.set_item("coupling", iface.coupling.as_str())?;
    let length: Vec<f64> = iface
        .elements
        .iter()
        .map(|c| c.segment.as_ref().map_or(0.0, |s| s.length))
        .collect();
    d.set_item("segment_length", PyArray1::from_vec(py, length))?;
    Ok(d)
}
