//! output::vtu — writes VTK XML UnstructuredGrid files (.vtu) for ParaView and the
//! .pvd collection that makes a time series of them.
//!
//! A .vtu is a short XML header followed by one `<AppendedData encoding="raw">`
//! block holding every array as raw little-endian binary, each preceded by its byte
//! count as a UInt64 (`header_type="UInt64"`). The header gives each array's
//! `offset` into that block, so the sizes are computed first and the data is then
//! streamed to the file: Float64 and Int32 arrays are handed to the (buffered)
//! writer as their memory on a little-endian machine, padded vectors are encoded a
//! fixed-size chunk at a time. The mesh is checked and encoded once into its
//! written form ([`Geometry`]), which every file of a series on it reuses
//! ([`write_on`]); no text per value, so it scales to millions of points.
//! Everything is validated before a byte is written, and the file is written
//! atomically (see [`super::write_atomic`]).
//!
//! Plane grids (points `[f64; 2]`, written with z = 0) and solid grids (points
//! `[f64; 3]`, with tetrahedra, hexahedra and wedges) are written by the same
//! functions: [`Grid`] and [`Geometry::new`] take any [`GridPoint`].
//!
//! Types written: point coordinates Float64 (3 components, z = 0 for plane points), connectivity and
//! offsets Int32 when every index and offset fits (see `index_type`; half the bytes
//! of Int64), Int64 otherwise, cell types UInt8, data arrays Float64 or Int32, field
//! data Float64.

use super::write_atomic;
use crate::error::{Error, Result};
use std::collections::HashSet;
use std::io::{self, Write};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// VTK cell types used by cfe. The discriminant is the VTK cell type number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum CellKind {
    /// A single point (VTK_VERTEX = 1), 1 node.
    Vertex = 1,
    /// A straight segment (VTK_LINE = 3), 2 nodes.
    Line = 3,
    /// A linear triangle (VTK_TRIANGLE = 5), 3 nodes counter-clockwise.
    Triangle = 5,
    /// A bilinear quadrilateral (VTK_QUAD = 9), 4 nodes in order around it.
    Quad = 9,
    /// A linear tetrahedron (VTK_TETRA = 10), 4 nodes: a base triangle 0-1-2
    /// whose normal by the right-hand rule points towards the apex 3.
    Tetra = 10,
    /// A trilinear hexahedron (VTK_HEXAHEDRON = 12), 8 nodes: the bottom face
    /// 0-1-2-3 (its right-hand normal pointing into the cell), then the top face
    /// 4-5-6-7 with node 4 above 0, 5 above 1 …
    Hexahedron = 12,
    /// A linear wedge (VTK_WEDGE = 13), 6 nodes: the triangle 0-1-2, then the
    /// triangle 3-4-5 with node 3 opposite 0, 4 opposite 1, 5 opposite 2. VTK
    /// orders the first triangle so that its right-hand normal points away from
    /// the second (the reverse of a Gmsh prism's, whose first triangle 0-1-2 is
    /// read as VTK's 0-2-1, and 3-4-5 as 3-5-4).
    Wedge = 13,
}

impl CellKind {
    /// The VTK cell type number written to the `types` array.
    pub fn vtk_type(self) -> u8 {
        self as u8
    }

    /// How many nodes a cell of this kind has in the connectivity.
    pub fn node_count(self) -> usize {
        match self {
            CellKind::Vertex => 1,
            CellKind::Line => 2,
            CellKind::Triangle => 3,
            CellKind::Quad => 4,
            CellKind::Tetra => 4,
            CellKind::Hexahedron => 8,
            CellKind::Wedge => 6,
        }
    }
}

/// A point of a grid as the writer takes it: plane points `[f64; 2]` (written
/// with z = 0) or points in space `[f64; 3]`.
pub trait GridPoint: Copy {
    /// The coordinates (x, y, z) written to the file.
    fn xyz(self) -> [f64; 3];
}

impl GridPoint for [f64; 2] {
    fn xyz(self) -> [f64; 3] {
        [self[0], self[1], 0.0]
    }
}

impl GridPoint for [f64; 3] {
    fn xyz(self) -> [f64; 3] {
        self
    }
}

/// Values of one data array, tuple after tuple (all components of the first point
/// or cell, then all of the second, ...).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Values<'a> {
    /// Written as Float64.
    F64(&'a [f64]),
    /// Written as Int32.
    I32(&'a [i32]),
}

impl Values<'_> {
    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I32(v) => v.len(),
        }
    }
}

/// One named data array with `components` values per point or cell (1, 2, 3, 6 ...).
/// A 2-component array is written padded to 3 components (z = 0) so ParaView treats
/// it as a vector (Warp By Vector works); a 3-component array is a vector in space
/// as it is. A 6-component array is what ParaView reads as a symmetric tensor,
/// its components in the order XX, YY, ZZ, XY, YZ, XZ (the six stresses of a
/// solid: σxx, σyy, σzz, τxy, τyz, τxz), written as given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DataArray<'a> {
    /// Name shown in ParaView; must be non-empty, unique within its point or cell
    /// data, and free of control characters. It is XML-escaped when written.
    pub name: &'a str,
    /// Values per point or cell, at least 1.
    pub components: usize,
    /// The values: `components` × (number of points or cells) of them.
    pub values: Values<'a>,
}

impl<'a> DataArray<'a> {
    /// A Float64 array of `components` values per point or cell.
    pub fn f64(name: &'a str, components: usize, values: &'a [f64]) -> Self {
        DataArray {
            name,
            components,
            values: Values::F64(values),
        }
    }

    /// An Int32 array of one value per point or cell.
    pub fn i32(name: &'a str, values: &'a [i32]) -> Self {
        DataArray {
            name,
            components: 1,
            values: Values::I32(values),
        }
    }
}

/// A mesh of mixed cells: in the plane with points `[f64; 2]` (the default; z = 0
/// is written), or in space with points `[f64; 3]` (tetrahedra, hexahedra and
/// wedges, with vertices for pairs, beside the plane kinds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid<'a, P: GridPoint = [f64; 2]> {
    /// Point coordinates: (x, y) or (x, y, z).
    pub points: &'a [P],
    /// Point indices of all cells, one cell after the other.
    pub connectivity: &'a [usize],
    /// End offset of each cell in `connectivity`, VTK style: cell `i` is
    /// `connectivity[offsets[i - 1]..offsets[i]]` (from 0 for the first cell).
    pub offsets: &'a [usize],
    /// Kind of each cell; as many as `offsets`.
    pub kinds: &'a [CellKind],
    /// Arrays with one tuple per point.
    pub point_data: &'a [DataArray<'a>],
    /// Arrays with one tuple per cell.
    pub cell_data: &'a [DataArray<'a>],
    /// Single numbers for the whole dataset, e.g. `("TIME", λ)`.
    pub field_data: &'a [(&'a str, f64)],
}

/// Writes `grid` as a binary VTK XML UnstructuredGrid file at `path`, atomically.
///
/// Returns [`Error::Output`] without touching `path` if the grid is inconsistent:
/// offsets not increasing or not ending at `connectivity.len()`, a cell whose node
/// count does not fit its kind, `kinds` and `offsets` of different lengths, a
/// connectivity index that is not a point, an array whose length is not
/// points × components (or cells × components), or a bad or repeated array name.
///
/// ```
/// use cfe::output::vtu::{write_vtu, CellKind, DataArray, Grid};
/// // One tetrahedron with its displacement and a von Mises value.
/// let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let u = [0.0; 12];
/// let point_data = [DataArray::f64("displacement", 3, &u)];
/// let cell_data = [DataArray::f64("von_mises", 1, &[2.5])];
/// let grid = Grid {
///     points: &points,
///     connectivity: &[0, 1, 2, 3],
///     offsets: &[4],
///     kinds: &[CellKind::Tetra],
///     point_data: &point_data,
///     cell_data: &cell_data,
///     field_data: &[("TIME", 1.0)],
/// };
/// let path = std::env::temp_dir().join(format!("cfe_doc_tet_{}.vtu", std::process::id()));
/// write_vtu(&path, &grid).unwrap();
/// std::fs::remove_file(&path).unwrap();
/// ```
pub fn write_vtu<P: GridPoint>(path: &Path, grid: &Grid<P>) -> Result<()> {
    let geometry = Geometry::new(grid.points, grid.connectivity, grid.offsets, grid.kinds);
    write_on(
        path,
        &geometry,
        &Fields {
            point_data: grid.point_data,
            cell_data: grid.cell_data,
            field_data: grid.field_data,
        },
    )
}

/// The points and cells of a grid, checked and encoded once as they are written
/// (coordinates (x, y, z) as Float64, z = 0 for plane points, connectivity and offsets as Int32 when
/// every value fits, else Int64, cell types as UInt8): the files of a series on
/// one mesh, one per increment, are written from it ([`write_on`]) without
/// checking or converting the mesh again. The encoded mesh is also smaller than
/// the given one (4-byte indices instead of 8).
pub struct Geometry {
    n_points: usize,
    n_cells: usize,
    index: IndexType,
    points: Vec<u8>,
    connectivity: Vec<u8>,
    offsets: Vec<u8>,
    types: Vec<u8>,
    /// Why the cells are inconsistent, if they are: reported by every
    /// [`write_on`] with the file it could not write (nothing is encoded).
    invalid: Option<String>,
}

impl Geometry {
    /// Checks and encodes `points` and the cells given by `connectivity`,
    /// `offsets` and `kinds` (as in [`Grid`]). Inconsistent cells are not an
    /// error here but at each [`write_on`], which names the file.
    pub fn new<P: GridPoint>(
        points: &[P],
        connectivity: &[usize],
        offsets: &[usize],
        kinds: &[CellKind],
    ) -> Geometry {
        let mut g = Geometry {
            n_points: points.len(),
            n_cells: offsets.len(),
            index: IndexType::Int32,
            points: Vec::new(),
            connectivity: Vec::new(),
            offsets: Vec::new(),
            types: Vec::new(),
            invalid: validate_cells(points.len(), connectivity, offsets, kinds).err(),
        };
        if g.invalid.is_some() {
            return g;
        }
        // The largest value of either array: the last offset is the connectivity's
        // length, and every connectivity entry is below the number of points.
        let largest = connectivity.iter().copied().max().unwrap_or(0);
        g.index = index_type(largest.max(connectivity.len()));
        g.points = encode(points, |p| {
            let mut b = [0u8; 24];
            for (to, x) in b.chunks_exact_mut(8).zip(p.xyz()) {
                to.copy_from_slice(&x.to_le_bytes());
            }
            b
        });
        g.connectivity = encode_indices(connectivity, g.index);
        g.offsets = encode_indices(offsets, g.index);
        g.types = kinds.iter().map(|k| k.vtk_type()).collect();
        g
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.n_cells
    }
}

/// Indices as the little-endian integers of `t` (which every value must fit:
/// [`index_type`] of the largest).
fn encode_indices(values: &[usize], t: IndexType) -> Vec<u8> {
    match t {
        IndexType::Int32 => encode(values, |i| (i as i32).to_le_bytes()),
        IndexType::Int64 => encode(values, |i| (i as i64).to_le_bytes()),
    }
}

/// Every value of `values` as its `bytes`, one after the other.
fn encode<T: Copy, const N: usize>(values: &[T], bytes: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    let mut out = vec![0u8; values.len() * N];
    for (to, &v) in out.chunks_exact_mut(N).zip(values) {
        to.copy_from_slice(&bytes(v));
    }
    out
}

/// The data of one file on a [`Geometry`]: arrays per point and per cell, and
/// single numbers for the whole dataset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fields<'a> {
    /// Arrays with one tuple per point.
    pub point_data: &'a [DataArray<'a>],
    /// Arrays with one tuple per cell.
    pub cell_data: &'a [DataArray<'a>],
    /// Single numbers for the whole dataset, e.g. `("TIME", λ)`.
    pub field_data: &'a [(&'a str, f64)],
}

/// Writes `fields` on `geometry` as a binary VTK XML UnstructuredGrid file at
/// `path`, atomically: [`write_vtu`] for a mesh already checked and encoded.
///
/// Returns [`Error::Output`] without touching `path` if the geometry's cells are
/// inconsistent (see [`write_vtu`]), or an array's length is not points ×
/// components (or cells × components), or a name is bad or repeated.
pub fn write_on(path: &Path, geometry: &Geometry, fields: &Fields) -> Result<()> {
    write_on_until(path, geometry, fields, &AtomicUsize::new(0))
}

/// [`write_on`] that abandons the file once `stop` is nonzero (e.g. a signal's
/// number), read before every [`STOP_CHECK_BYTES`] written: the temporary file
/// is removed, `path` is left as it was and the error (an [`Error::Output`])
/// says the writing was stopped. A file smaller than that is written whole.
pub fn write_on_until(
    path: &Path,
    geometry: &Geometry,
    fields: &Fields,
    stop: &AtomicUsize,
) -> Result<()> {
    let bad = |message: String| Error::output(path, message);
    if let Some(message) = &geometry.invalid {
        return Err(bad(message.clone()));
    }
    validate_fields(geometry, fields).map_err(bad)?;
    let arrays = layout(geometry, fields);
    write_atomic(path, |w| {
        write_file(
            &mut Stoppable {
                w,
                stop,
                unchecked: 0,
            },
            geometry,
            &arrays,
        )
    })
}

/// One dataset of a .pvd series.
#[derive(Debug, Clone, PartialEq)]
pub struct PvdEntry {
    /// Time (or load factor) of the dataset; must be finite.
    pub time: f64,
    /// Part number, for several datasets at one time.
    pub part: usize,
    /// Path of the .vtu file relative to the .pvd; XML-escaped when written.
    pub file: String,
}

/// Writes a ParaView collection (.pvd) listing `entries` at `path`, atomically, so
/// ParaView opens them as one time series.
///
/// Returns [`Error::Output`] without touching `path` if a time is not finite or a
/// file name is empty or contains control characters.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> Result<()> {
    for (i, e) in entries.iter().enumerate() {
        if !e.time.is_finite() {
            return Err(Error::output(
                path,
                format!("pvd entry {i} ({}): time {} is not finite", e.file, e.time),
            ));
        }
        check_name(&e.file).map_err(|m| Error::output(path, format!("pvd entry {i}: file {m}")))?;
    }
    write_atomic(path, |w| {
        w.write_all(
            b"<?xml version=\"1.0\"?>\n\
              <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  \
              <Collection>\n",
        )?;
        for e in entries {
            writeln!(
                w,
                "    <DataSet timestep=\"{:?}\" group=\"\" part=\"{}\" file=\"{}\"/>",
                e.time,
                e.part,
                escape(&e.file)
            )?;
        }
        w.write_all(b"  </Collection>\n</VTKFile>\n")
    })
}

// ---------------------------------------------------------------------------------
// Validation

/// Checks the cells: kinds and offsets of one length, offsets increasing and
/// ending at the connectivity's length, each cell's node count its kind's, and
/// every connectivity entry a point (of `n_points`). The message says what is
/// wrong where.
pub(super) fn validate_cells(
    n_points: usize,
    connectivity: &[usize],
    offsets: &[usize],
    kinds: &[CellKind],
) -> std::result::Result<(), String> {
    let n_cells = offsets.len();
    if kinds.len() != n_cells {
        return Err(format!(
            "{} cell kinds for {} cell offsets: need one kind per cell",
            kinds.len(),
            n_cells
        ));
    }
    let mut start = 0;
    for (i, (&end, &kind)) in offsets.iter().zip(kinds).enumerate() {
        if end <= start {
            return Err(format!(
                "offsets are not increasing: offsets[{i}] = {end} after {start}"
            ));
        }
        if end > connectivity.len() {
            return Err(format!(
                "offsets[{i}] = {end} is past the end of the connectivity ({} entries)",
                connectivity.len()
            ));
        }
        if end - start != kind.node_count() {
            return Err(format!(
                "cell {i} is a {kind:?} with {} nodes, expected {}",
                end - start,
                kind.node_count()
            ));
        }
        start = end;
    }
    if start != connectivity.len() {
        return Err(format!(
            "offsets end at {start} but the connectivity has {} entries",
            connectivity.len()
        ));
    }
    if let Some((i, &p)) = connectivity
        .iter()
        .enumerate()
        .find(|&(_, &p)| p >= n_points)
    {
        return Err(format!(
            "connectivity[{i}] = {p} is not a point (there are {n_points} points)"
        ));
    }
    Ok(())
}

/// Checks the data arrays against the geometry's points and cells, and the
/// field data's names.
fn validate_fields(geometry: &Geometry, fields: &Fields) -> std::result::Result<(), String> {
    check_arrays("point", fields.point_data, geometry.n_points)?;
    check_arrays("cell", fields.cell_data, geometry.n_cells)?;
    let mut seen = HashSet::new();
    for (name, _) in fields.field_data {
        check_name(name).map_err(|m| format!("field data name {m}"))?;
        if !seen.insert(*name) {
            return Err(format!("field data '{name}' is given twice"));
        }
    }
    Ok(())
}

/// Checks names, component counts and lengths of point or cell data arrays.
fn check_arrays(
    what: &str,
    arrays: &[DataArray],
    tuples: usize,
) -> std::result::Result<(), String> {
    let mut seen = HashSet::new();
    for a in arrays {
        check_name(a.name).map_err(|m| format!("{what} data name {m}"))?;
        if !seen.insert(a.name) {
            return Err(format!("{what} data '{}' is given twice", a.name));
        }
        if a.components == 0 {
            return Err(format!("{what} data '{}' has 0 components", a.name));
        }
        if tuples.checked_mul(a.components) != Some(a.values.len()) {
            return Err(format!(
                "{what} data '{}' has {} values, expected {tuples} {what}s × {} components",
                a.name,
                a.values.len(),
                a.components
            ));
        }
    }
    Ok(())
}

/// A name must be non-empty and have no control characters (XML 1.0 cannot hold most
/// of them, and an attribute would turn the rest into spaces).
fn check_name(name: &str) -> std::result::Result<(), String> {
    if name.is_empty() {
        return Err("is empty".into());
    }
    if name.chars().any(char::is_control) {
        return Err(format!("{name:?} contains a control character"));
    }
    Ok(())
}

/// Escapes the characters that cannot stand literally in an XML attribute value.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Layout: what goes into the appended block, in which order, at which offset.

/// Where an array's `<DataArray>` element goes in the XML header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Section {
    Field,
    Point,
    Cell,
    Points,
    Cells,
}

/// The data of one appended block.
enum Payload<'a> {
    /// Bytes already encoded (the geometry's).
    Bytes(&'a [u8]),
    /// A data array; 2 components are padded to 3.
    Data {
        values: Values<'a>,
        components: usize,
    },
}

impl Payload<'_> {
    /// Number of payload bytes (not counting the UInt64 size before them).
    fn byte_len(&self) -> u64 {
        let n = match self {
            Payload::Bytes(b) => b.len(),
            Payload::Data { values, components } => {
                let scalar = match values {
                    Values::F64(_) => 8,
                    Values::I32(_) => 4,
                };
                values.len() / components * written_components(*components) * scalar
            }
        };
        n as u64
    }

    /// Streams the payload bytes.
    fn write(&self, out: &mut Chunked) -> io::Result<()> {
        match self {
            Payload::Bytes(b) => out.put_le(b, |x| [x]),
            Payload::Data { values, components } => match values {
                Values::F64(v) if *components == 2 => {
                    out.put_each(bytemuck::cast_slice::<f64, [f64; 2]>(v), |[x, y]| {
                        let mut b = [0u8; 24];
                        b[..8].copy_from_slice(&x.to_le_bytes());
                        b[8..16].copy_from_slice(&y.to_le_bytes());
                        b
                    })
                }
                Values::F64(v) => out.put_le(v, f64::to_le_bytes),
                Values::I32(v) if *components == 2 => put_padded(out, v, i32::to_le_bytes),
                Values::I32(v) => out.put_le(v, i32::to_le_bytes),
            },
        }
    }
}

/// Writes 2-component tuples as little-endian bytes, padded with a zero.
fn put_padded<T: Copy + Default, const N: usize>(
    out: &mut Chunked,
    values: &[T],
    bytes: fn(T) -> [u8; N],
) -> io::Result<()> {
    let zero = bytes(T::default());
    for pair in values.chunks_exact(2) {
        out.put(&bytes(pair[0]))?;
        out.put(&bytes(pair[1]))?;
        out.put(&zero)?;
    }
    Ok(())
}

/// Components as written: 2 becomes 3 (a vector with z = 0).
fn written_components(components: usize) -> usize {
    if components == 2 { 3 } else { components }
}

/// One `<DataArray>` of the header and its appended block.
struct Array<'a> {
    section: Section,
    /// Already XML-escaped.
    name: String,
    vtk_type: &'static str,
    /// Written as NumberOfComponents when not 1.
    components: usize,
    /// Written as NumberOfTuples (field data needs it).
    tuples: Option<usize>,
    /// RangeMin / RangeMax as text, when there is a finite value.
    range: Option<(String, String)>,
    payload: Payload<'a>,
}

/// Lists every array in the order of the header's `<DataArray>`s (the blocks
/// are appended in the reverse order: see [`write_file`]).
fn layout<'a>(geometry: &'a Geometry, fields: &Fields<'a>) -> Vec<Array<'a>> {
    let mut arrays = Vec::new();
    for (name, value) in fields.field_data {
        arrays.push(Array {
            section: Section::Field,
            name: escape(name),
            vtk_type: "Float64",
            components: 1,
            tuples: Some(1),
            range: None,
            payload: Payload::Data {
                values: Values::F64(std::slice::from_ref(value)),
                components: 1,
            },
        });
    }
    for (section, data) in [
        (Section::Point, fields.point_data),
        (Section::Cell, fields.cell_data),
    ] {
        for a in data {
            arrays.push(Array {
                section,
                name: escape(a.name),
                vtk_type: match a.values {
                    Values::F64(_) => "Float64",
                    Values::I32(_) => "Int32",
                },
                components: written_components(a.components),
                tuples: None,
                range: range(a.values, a.components),
                payload: Payload::Data {
                    values: a.values,
                    components: a.components,
                },
            });
        }
    }
    let index = geometry.index.vtk_name();
    for (section, name, vtk_type, components, bytes) in [
        (Section::Points, "Points", "Float64", 3, &geometry.points),
        (
            Section::Cells,
            "connectivity",
            index,
            1,
            &geometry.connectivity,
        ),
        (Section::Cells, "offsets", index, 1, &geometry.offsets),
        (Section::Cells, "types", "UInt8", 1, &geometry.types),
    ] {
        arrays.push(Array {
            section,
            name: name.into(),
            vtk_type,
            components,
            tuples: None,
            range: None,
            payload: Payload::Bytes(bytes),
        });
    }
    arrays
}

/// The integer type of a grid's connectivity and offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum IndexType {
    /// 4 bytes per value.
    Int32,
    /// 8 bytes per value.
    Int64,
}

impl IndexType {
    /// The VTK type name of the `<DataArray>`.
    fn vtk_name(self) -> &'static str {
        match self {
            IndexType::Int32 => "Int32",
            IndexType::Int64 => "Int64",
        }
    }
}

/// The type the connectivity and offsets of a grid are written in, given the
/// largest value either holds: Int32 when it fits (every mesh below ~2·10⁹ point
/// references), Int64 otherwise. Both arrays share it.
fn index_type(largest: usize) -> IndexType {
    if i32::try_from(largest).is_ok() {
        IndexType::Int32
    } else {
        IndexType::Int64
    }
}

/// The range ParaView expects in RangeMin / RangeMax: of the values for one
/// component, of the tuple magnitudes for several. Non-finite values are skipped;
/// `None` if nothing finite is left.
fn range(values: Values, components: usize) -> Option<(String, String)> {
    if let (Values::I32(v), 1) = (values, components) {
        let min = v.iter().min()?;
        let max = v.iter().max()?;
        return Some((min.to_string(), max.to_string()));
    }
    let mut min = f64::INFINITY;
    let mut max = f64::NEG_INFINITY;
    let mut add = |x: f64| {
        if x.is_finite() {
            min = min.min(x);
            max = max.max(x);
        }
    };
    match (values, components) {
        (Values::F64(v), 1) => v.iter().for_each(|&x| add(x)),
        (Values::F64(v), c) => v
            .chunks_exact(c)
            .for_each(|t| add(t.iter().map(|x| x * x).sum::<f64>().sqrt())),
        (Values::I32(v), c) => v.chunks_exact(c).for_each(|t| {
            add(t
                .iter()
                .map(|&x| f64::from(x) * f64::from(x))
                .sum::<f64>()
                .sqrt())
        }),
    }
    (min <= max).then(|| (format!("{min:?}"), format!("{max:?}")))
}

// ---------------------------------------------------------------------------------
// Writing

/// Size of the chunks handed to the writer.
const CHUNK: usize = 1 << 16;

/// Bytes a [`write_on_until`] writes between two reads of its stop flag (8 MiB:
/// some milliseconds of writing; a write of a large array is handed on in
/// pieces of this size).
pub const STOP_CHECK_BYTES: usize = 8 << 20;

/// A writer that fails once `stop` is nonzero, read before every
/// [`STOP_CHECK_BYTES`] handed on to `w`.
struct Stoppable<'w> {
    w: &'w mut dyn Write,
    stop: &'w AtomicUsize,
    /// Bytes handed on since the flag was last read.
    unchecked: usize,
}

impl Write for Stoppable<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.unchecked >= STOP_CHECK_BYTES {
            self.unchecked = 0;
            // Not `ErrorKind::Interrupted`: `write_all` would retry.
            match self.stop.load(Ordering::Relaxed) {
                0 => {}
                signal => {
                    return Err(io::Error::other(format!(
                        "stopped (signal {signal}) before it was complete"
                    )));
                }
            }
        }
        let n = self
            .w
            .write(&buf[..buf.len().min(STOP_CHECK_BYTES - self.unchecked)])?;
        self.unchecked += n;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.w.flush()
    }
}

/// Collects small pieces of binary data into chunks before handing them to the
/// (dynamically dispatched) writer.
struct Chunked<'w> {
    w: &'w mut dyn Write,
    buf: Vec<u8>,
}

impl Chunked<'_> {
    #[inline]
    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.buf.extend_from_slice(bytes);
        if self.buf.len() >= CHUNK {
            self.flush_chunk()?;
        }
        Ok(())
    }

    /// Puts every value of `values` as its `bytes`, a chunk's worth at a time
    /// (the bulk path of the large arrays: no size check per value).
    fn put_each<T: Copy, const N: usize>(
        &mut self,
        values: &[T],
        bytes: impl Fn(T) -> [u8; N],
    ) -> io::Result<()> {
        for block in values.chunks(CHUNK / N) {
            let start = self.buf.len();
            self.buf.resize(start + block.len() * N, 0);
            for (to, &v) in self.buf[start..].chunks_exact_mut(N).zip(block) {
                to.copy_from_slice(&bytes(v));
            }
            if self.buf.len() >= CHUNK {
                self.flush_chunk()?;
            }
        }
        Ok(())
    }

    /// Puts `values` as their little-endian `bytes`: on a little-endian machine
    /// their memory is handed to the writer as it is (no copy, no encoding).
    fn put_le<T: bytemuck::Pod, const N: usize>(
        &mut self,
        values: &[T],
        bytes: impl Fn(T) -> [u8; N],
    ) -> io::Result<()> {
        if cfg!(target_endian = "little") {
            self.flush_chunk()?;
            self.w.write_all(bytemuck::cast_slice(values))
        } else {
            self.put_each(values, bytes)
        }
    }

    fn flush_chunk(&mut self) -> io::Result<()> {
        self.w.write_all(&self.buf)?;
        self.buf.clear();
        Ok(())
    }
}

/// The offset of each array's block in the appended data, for blocks written in
/// the reverse of the header's order (the last `<DataArray>` first): see
/// [`write_file`]. Every block starts with its 8-byte size, so the offsets are
/// distinct.
fn appended_offsets(arrays: &[Array]) -> Vec<u64> {
    let mut offsets = vec![0u64; arrays.len()];
    let mut offset = 0u64;
    for (a, at) in arrays.iter().zip(offsets.iter_mut()).rev() {
        *at = offset;
        offset += 8 + a.payload.byte_len();
    }
    offsets
}

/// Writes the XML header, the appended block and the closing tags.
///
/// The blocks are appended in the reverse of the order their `<DataArray>`s
/// appear in the header. VTK and ParaView find a block by its offset, so the
/// order is theirs to ignore; meshio 5.x's raw reader is not: it walks the
/// blocks from the start and, for the block at byte i, takes the first
/// `<DataArray>` in document order whose offset reads i, then rewrites that
/// offset to a position in its own base64 copy of the data. In the header's
/// order a rewritten offset of an earlier array can equal the raw offset of a
/// later one (the FieldData written first made `displacement` land in
/// `LOAD_FACTOR`); in the reverse order every array still to be found comes
/// before every rewritten one in the document, so the first match is always
/// the array whose block starts at i.
fn write_file(w: &mut dyn Write, geometry: &Geometry, arrays: &[Array]) -> io::Result<()> {
    let offsets = appended_offsets(arrays);

    w.write_all(
        b"<?xml version=\"1.0\"?>\n\
          <VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
          header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
    )?;
    let section = |w: &mut dyn Write, s: Section, tag: &str, indent: &str| -> io::Result<()> {
        if !arrays.iter().any(|a| a.section == s) {
            return Ok(());
        }
        writeln!(w, "{indent}<{tag}>")?;
        for (a, off) in arrays.iter().zip(&offsets).filter(|(a, _)| a.section == s) {
            write!(
                w,
                "{indent}  <DataArray type=\"{}\" Name=\"{}\"",
                a.vtk_type, a.name
            )?;
            if a.components != 1 {
                write!(w, " NumberOfComponents=\"{}\"", a.components)?;
            }
            if let Some(n) = a.tuples {
                write!(w, " NumberOfTuples=\"{n}\"")?;
            }
            write!(w, " format=\"appended\"")?;
            if let Some((min, max)) = &a.range {
                write!(w, " RangeMin=\"{min}\" RangeMax=\"{max}\"")?;
            }
            writeln!(w, " offset=\"{off}\"/>")?;
        }
        writeln!(w, "{indent}</{tag}>")
    };
    section(w, Section::Field, "FieldData", "    ")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        geometry.n_points, geometry.n_cells
    )?;
    section(w, Section::Point, "PointData", "      ")?;
    section(w, Section::Cell, "CellData", "      ")?;
    section(w, Section::Points, "Points", "      ")?;
    section(w, Section::Cells, "Cells", "      ")?;
    w.write_all(b"    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_")?;

    let mut out = Chunked {
        w,
        buf: Vec::with_capacity(CHUNK + 64),
    };
    for a in arrays.iter().rev() {
        out.put(&a.payload.byte_len().to_le_bytes())?;
        a.payload.write(&mut out)?;
    }
    out.flush_chunk()?;
    out.w.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::path::PathBuf;

    /// A fresh scratch directory for one test.
    fn scratch(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("cfe_vtu_{}_{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Undoes `escape`.
    fn unescape(s: &str) -> String {
        s.replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&")
    }

    /// Attributes of every `<tag ...>` element in `xml`, values unescaped.
    fn elements(xml: &str, tag: &str) -> Vec<HashMap<String, String>> {
        let open = format!("<{tag} ");
        let mut found = Vec::new();
        let mut rest = xml;
        while let Some(start) = rest.find(&open) {
            let after = &rest[start + open.len()..];
            let end = after.find('>').expect("unclosed element");
            let mut attrs = HashMap::new();
            let mut body = after[..end].trim_end_matches('/').trim();
            while !body.is_empty() {
                let eq = body.find("=\"").expect("attribute without value");
                let key = body[..eq].trim().to_string();
                let value_end = body[eq + 2..].find('"').expect("unterminated value");
                let value = unescape(&body[eq + 2..eq + 2 + value_end]);
                assert!(attrs.insert(key, value).is_none(), "repeated attribute");
                body = body[eq + 2 + value_end + 1..].trim_start();
            }
            found.push(attrs);
            rest = &after[end..];
        }
        found
    }

    /// The part of `xml` between `<tag>` and `</tag>`, or "" if there is none.
    fn section<'x>(xml: &'x str, tag: &str) -> &'x str {
        let Some(start) = xml.find(&format!("<{tag}>")) else {
            return "";
        };
        let end = xml.find(&format!("</{tag}>")).expect("unclosed section");
        &xml[start..end]
    }

    /// A .vtu read back: XML header and appended bytes (after the `_`).
    struct Vtu {
        header: String,
        appended: Vec<u8>,
    }

    impl Vtu {
        fn read(path: &Path) -> Vtu {
            let bytes = std::fs::read(path).unwrap();
            let marker = b"<AppendedData encoding=\"raw\">";
            let at = bytes
                .windows(marker.len())
                .position(|w| w == marker)
                .expect("no appended data");
            let header = String::from_utf8(bytes[..at].to_vec()).unwrap();
            let underscore = at + bytes[at..].iter().position(|&b| b == b'_').unwrap();
            let tail = b"\n  </AppendedData>\n</VTKFile>\n";
            assert!(bytes.ends_with(tail), "bad file end");
            let appended = bytes[underscore + 1..bytes.len() - tail.len()].to_vec();
            Vtu { header, appended }
        }

        /// The `<DataArray>` elements of one section.
        fn arrays(&self, tag: &str) -> Vec<HashMap<String, String>> {
            elements(section(&self.header, tag), "DataArray")
        }

        /// The single array called `name` in section `tag`.
        fn array(&self, tag: &str, name: &str) -> HashMap<String, String> {
            let mut found: Vec<_> = self
                .arrays(tag)
                .into_iter()
                .filter(|a| a["Name"] == name)
                .collect();
            assert_eq!(found.len(), 1, "array {name} in {tag}");
            found.pop().unwrap()
        }

        /// The payload of an array: UInt64 size at `offset`, then the bytes.
        fn payload(&self, array: &HashMap<String, String>) -> &[u8] {
            assert_eq!(array["format"], "appended");
            let offset: usize = array["offset"].parse().unwrap();
            let size = u64::from_le_bytes(self.appended[offset..offset + 8].try_into().unwrap());
            &self.appended[offset + 8..offset + 8 + size as usize]
        }

        fn f64s(&self, tag: &str, name: &str) -> Vec<f64> {
            let a = self.array(tag, name);
            assert_eq!(a["type"], "Float64");
            let p = self.payload(&a);
            p.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect()
        }

        fn i32s(&self, tag: &str, name: &str) -> Vec<i32> {
            let a = self.array(tag, name);
            assert_eq!(a["type"], "Int32");
            let p = self.payload(&a);
            p.chunks_exact(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        }

        fn u8s(&self, tag: &str, name: &str) -> Vec<u8> {
            let a = self.array(tag, name);
            assert_eq!(a["type"], "UInt8");
            self.payload(&a).to_vec()
        }

        /// Checks that the blocks of all arrays tile the appended data exactly.
        fn check_tiling(&self) {
            let all = elements(&self.header, "DataArray");
            let mut blocks: Vec<(usize, usize)> = all
                .iter()
                .map(|a| {
                    let off: usize = a["offset"].parse().unwrap();
                    (off, 8 + self.payload(a).len())
                })
                .collect();
            blocks.sort();
            let mut at = 0;
            for (off, len) in blocks {
                assert_eq!(off, at, "gap or overlap in appended data");
                at += len;
            }
            assert_eq!(at, self.appended.len(), "junk after the last block");
        }
    }

    const VECTOR: [f64; 8] = [
        0.1,
        -1e-300,
        f64::MAX,
        1.0 / 3.0,
        -0.0,
        2.5,
        f64::MIN_POSITIVE,
        -7.0,
    ];
    const SCALAR: [f64; 4] = [1.0, -2.0, 0.3, 4e10];
    const CELL_IDS: [i32; 2] = [i32::MIN, 7];

    /// Writes the 2-triangle sample grid with a point vector, a point scalar with an
    /// awkward name, a cell i32 array and a TIME field.
    fn write_sample(path: &Path) -> Result<()> {
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0 / 3.0]];
        let point_data = [
            DataArray {
                name: "displacement",
                components: 2,
                values: Values::F64(&VECTOR),
            },
            DataArray {
                name: "p<&>\"'",
                components: 1,
                values: Values::F64(&SCALAR),
            },
        ];
        let cell_data = [DataArray {
            name: "part",
            components: 1,
            values: Values::I32(&CELL_IDS),
        }];
        write_vtu(
            path,
            &Grid {
                points: &points,
                connectivity: &[0, 1, 2, 0, 2, 3],
                offsets: &[3, 6],
                kinds: &[CellKind::Triangle, CellKind::Triangle],
                point_data: &point_data,
                cell_data: &cell_data,
                field_data: &[("TIME", 0.25)],
            },
        )
    }

    /// Every value of the sample grid round-trips bit for bit, and the 2-component
    /// vector is written as 3 components with z = 0.
    #[test]
    fn two_triangles_round_trip() {
        let dir = scratch("round_trip");
        let path = dir.join("sample.vtu");
        write_sample(&path).unwrap();
        let vtu = Vtu::read(&path);
        vtu.check_tiling();

        let file = elements(&vtu.header, "VTKFile").pop().unwrap();
        assert_eq!(file["type"], "UnstructuredGrid");
        assert_eq!(file["header_type"], "UInt64");
        assert_eq!(file["byte_order"], "LittleEndian");
        let piece = elements(&vtu.header, "Piece").pop().unwrap();
        assert_eq!(piece["NumberOfPoints"], "4");
        assert_eq!(piece["NumberOfCells"], "2");

        let points = vtu.f64s("Points", "Points");
        assert_eq!(vtu.array("Points", "Points")["NumberOfComponents"], "3");
        let expected = [
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            1.0,
            1.0,
            0.0,
            0.0,
            1.0 / 3.0,
            0.0,
        ];
        assert_eq!(bits(&points), bits(&expected));
        assert_eq!(vtu.i32s("Cells", "connectivity"), [0, 1, 2, 0, 2, 3]);
        assert_eq!(vtu.i32s("Cells", "offsets"), [3, 6]);
        assert_eq!(vtu.u8s("Cells", "types"), [5, 5]);

        let vector = vtu.f64s("PointData", "displacement");
        assert_eq!(
            vtu.array("PointData", "displacement")["NumberOfComponents"],
            "3"
        );
        let padded: Vec<f64> = VECTOR.chunks(2).flat_map(|p| [p[0], p[1], 0.0]).collect();
        assert_eq!(bits(&vector), bits(&padded));

        let scalar = vtu.array("PointData", "p<&>\"'");
        assert!(!scalar.contains_key("NumberOfComponents"));
        assert_eq!(scalar["RangeMin"].parse::<f64>().unwrap(), -2.0);
        assert_eq!(scalar["RangeMax"].parse::<f64>().unwrap(), 4e10);
        assert_eq!(bits(&vtu.f64s("PointData", "p<&>\"'")), bits(&SCALAR));
        assert!(vtu.header.contains("Name=\"p&lt;&amp;&gt;&quot;&apos;\""));

        assert_eq!(vtu.i32s("CellData", "part"), CELL_IDS);
        let part = vtu.array("CellData", "part");
        assert_eq!(part["RangeMin"], i32::MIN.to_string());
        assert_eq!(part["RangeMax"], "7");

        let time = vtu.array("FieldData", "TIME");
        assert_eq!(time["NumberOfTuples"], "1");
        assert_eq!(vtu.f64s("FieldData", "TIME"), [0.25]);
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Connectivity and offsets are Int32 up to i32::MAX and Int64 beyond it, and an
    /// Int64 index block holds every value as 8 little-endian bytes (what a grid of
    /// more than 2³¹ point references is written with, without building one).
    #[test]
    fn indices_beyond_i32_are_int64() {
        let max = i32::MAX as usize;
        assert_eq!(index_type(0), IndexType::Int32);
        assert_eq!(index_type(max), IndexType::Int32);
        assert_eq!(index_type(max + 1), IndexType::Int64);
        assert_eq!(index_type(usize::MAX), IndexType::Int64);
        let values = [0, 3, max, max + 1, 5 * max];
        for (t, width) in [(IndexType::Int32, 4), (IndexType::Int64, 8)] {
            let values = if t == IndexType::Int32 {
                &values[..3]
            } else {
                &values[..]
            };
            let bytes = encode_indices(values, t);
            assert_eq!(bytes.len(), width * values.len());
            let back: Vec<usize> = bytes
                .chunks_exact(width)
                .map(|c| match t {
                    IndexType::Int32 => i32::from_le_bytes(c.try_into().unwrap()) as usize,
                    IndexType::Int64 => i64::from_le_bytes(c.try_into().unwrap()) as usize,
                })
                .collect();
            assert_eq!(back, values, "{t:?}");
        }
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// Vertex, line, triangle and quad cells are written with VTK types 1, 3, 5, 9,
    /// and a grid without data arrays has no empty data sections.
    #[test]
    fn mixed_cells_and_no_data() {
        let dir = scratch("mixed");
        let path = dir.join("mixed.vtu");
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0]];
        let grid = Grid {
            points: &points,
            connectivity: &[4, 1, 4, 0, 1, 2, 0, 1, 2, 3],
            offsets: &[1, 3, 6, 10],
            kinds: &[
                CellKind::Vertex,
                CellKind::Line,
                CellKind::Triangle,
                CellKind::Quad,
            ],
            point_data: &[],
            cell_data: &[],
            field_data: &[],
        };
        write_vtu(&path, &grid).unwrap();
        let vtu = Vtu::read(&path);
        vtu.check_tiling();
        assert_eq!(vtu.u8s("Cells", "types"), [1, 3, 5, 9]);
        assert_eq!(vtu.i32s("Cells", "offsets"), [1, 3, 6, 10]);
        assert_eq!(
            vtu.i32s("Cells", "connectivity"),
            [4, 1, 4, 0, 1, 2, 0, 1, 2, 3]
        );
        for tag in ["PointData", "CellData", "FieldData"] {
            assert!(!vtu.header.contains(tag), "{tag} written without arrays");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A solid grid of a hexahedron, a tetrahedron on its top face, a wedge
    /// beside it and a vertex (a pair) reads back with VTK types 12, 10, 13, 1,
    /// offsets 8, 12, 18, 19, its (x, y, z) points bit for bit, and its fields:
    /// a 3-component displacement as given, the six stresses as one
    /// 6-component array in ParaView's tensor order, von Mises and the part id
    /// per cell; 2D points of the same cells write z = 0.
    #[test]
    fn a_solid_grid_reads_back() {
        let dir = scratch("solid");
        let path = dir.join("solid.vtu");
        let points: [[f64; 3]; 11] = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
            [0.5, 0.5, 1.0 + 1.0 / 3.0],
            [2.0, 0.0, 0.0],
            [2.0, 0.0, 1.0],
        ];
        let connectivity = [
            0, 1, 2, 3, 4, 5, 6, 7, // hexahedron
            4, 5, 6, 8, // tetrahedron on the top face
            1, 2, 9, 5, 6, 10, // wedge beside the hexahedron
            8,  // a pair at the apex
        ];
        let offsets = [8, 12, 18, 19];
        let kinds = [
            CellKind::Hexahedron,
            CellKind::Tetra,
            CellKind::Wedge,
            CellKind::Vertex,
        ];
        let u: Vec<f64> = (0..3 * points.len()).map(|i| i as f64 * -1e-3).collect();
        // σxx, σyy, σzz, τxy, τyz, τxz per cell.
        let stress: Vec<f64> = (0..6 * kinds.len()).map(|i| 10.0 + i as f64).collect();
        let von_mises = [1.5, 2.5, 3.5, 0.0];
        let part = [0, 1, 0, -1];
        let point_data = [DataArray::f64("displacement", 3, &u)];
        let cell_data = [
            DataArray::f64("stress", 6, &stress),
            DataArray::f64("von_mises", 1, &von_mises),
            DataArray::i32("part", &part),
        ];
        write_vtu(
            &path,
            &Grid {
                points: &points,
                connectivity: &connectivity,
                offsets: &offsets,
                kinds: &kinds,
                point_data: &point_data,
                cell_data: &cell_data,
                field_data: &[("TIME", 1.0)],
            },
        )
        .unwrap();
        let vtu = Vtu::read(&path);
        vtu.check_tiling();
        let piece = elements(&vtu.header, "Piece").pop().unwrap();
        assert_eq!(piece["NumberOfPoints"], "11");
        assert_eq!(piece["NumberOfCells"], "4");
        assert_eq!(vtu.u8s("Cells", "types"), [12, 10, 13, 1]);
        assert_eq!(vtu.i32s("Cells", "offsets"), [8, 12, 18, 19]);
        let written: Vec<i32> = connectivity.iter().map(|&n| n as i32).collect();
        assert_eq!(vtu.i32s("Cells", "connectivity"), written);
        let xyz: Vec<f64> = points.iter().flatten().copied().collect();
        assert_eq!(bits(&vtu.f64s("Points", "Points")), bits(&xyz));
        assert_eq!(
            vtu.array("PointData", "displacement")["NumberOfComponents"],
            "3"
        );
        assert_eq!(bits(&vtu.f64s("PointData", "displacement")), bits(&u));
        assert_eq!(vtu.array("CellData", "stress")["NumberOfComponents"], "6");
        let back = vtu.f64s("CellData", "stress");
        assert_eq!(bits(&back), bits(&stress));
        // The second cell's τyz is its fifth component.
        assert_eq!(back[6 + 4], 10.0 + 10.0);
        assert_eq!(bits(&vtu.f64s("CellData", "von_mises")), bits(&von_mises));
        assert_eq!(vtu.i32s("CellData", "part"), part);
        // The same cells on plane points: z = 0 written.
        let flat: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1]]).collect();
        let plane = dir.join("plane.vtu");
        let geometry = Geometry::new(&flat, &connectivity, &offsets, &kinds);
        let none = Fields {
            point_data: &[],
            cell_data: &[],
            field_data: &[],
        };
        write_on(&plane, &geometry, &none).unwrap();
        let expected: Vec<f64> = points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        assert_eq!(
            bits(&Vtu::read(&plane).f64s("Points", "Points")),
            bits(&expected)
        );
        // A wedge given 5 nodes is refused, naming the cell.
        let bad = Geometry::new(&points, &connectivity[..17], &[8, 12, 17], &kinds[..3]);
        match write_on(&dir.join("bad.vtu"), &bad, &none) {
            Err(Error::Output { message, .. }) => {
                assert!(
                    message.contains("cell 2 is a Wedge with 5 nodes"),
                    "{message}"
                )
            }
            other => panic!("expected an output error, got {other:?}"),
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Each file of a series written from one [`Geometry`] reads back as that
    /// mesh (mixed cells) with its own data; a geometry whose cells are
    /// inconsistent fails every write, naming the file, and writes nothing.
    #[test]
    fn a_series_on_one_geometry_reads_back() {
        let dir = scratch("series");
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]];
        let (connectivity, offsets) = ([0, 1, 2, 3, 1, 4, 2], [4, 7]);
        let kinds = [CellKind::Quad, CellKind::Triangle];
        let geometry = Geometry::new(&points, &connectivity, &offsets, &kinds);
        assert_eq!((geometry.n_points(), geometry.n_cells()), (5, 2));
        let xyz: Vec<f64> = points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        for k in 0..3 {
            let s = [k as f64 / 3.0, -1.5 * k as f64];
            let cell_data = [DataArray::f64("s", 1, &s)];
            let path = dir.join(format!("on_{k}.vtu"));
            let fields = Fields {
                point_data: &[],
                cell_data: &cell_data,
                field_data: &[("TIME", k as f64)],
            };
            write_on(&path, &geometry, &fields).unwrap();
            let vtu = Vtu::read(&path);
            vtu.check_tiling();
            assert_eq!(bits(&vtu.f64s("Points", "Points")), bits(&xyz));
            assert_eq!(vtu.i32s("Cells", "connectivity"), [0, 1, 2, 3, 1, 4, 2]);
            assert_eq!(vtu.i32s("Cells", "offsets"), [4, 7]);
            assert_eq!(vtu.u8s("Cells", "types"), [9, 5]);
            assert_eq!(bits(&vtu.f64s("CellData", "s")), bits(&s));
            assert_eq!(vtu.f64s("FieldData", "TIME"), [k as f64]);
        }
        let broken = Geometry::new(&points, &connectivity, &[4, 6], &kinds);
        let path = dir.join("broken.vtu");
        let fields = Fields {
            point_data: &[],
            cell_data: &[],
            field_data: &[],
        };
        for _ in 0..2 {
            match write_on(&path, &broken, &fields) {
                Err(Error::Output { path: p, message }) => {
                    assert_eq!(p, path);
                    assert!(
                        message.contains("cell 1 is a Triangle with 2 nodes"),
                        "{message}"
                    );
                }
                other => panic!("expected an output error, got {other:?}"),
            }
        }
        assert!(!path.exists());
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A writer given a stop flag: unset, it writes the bytes `write_on` writes
    /// (a file larger than [`STOP_CHECK_BYTES`], so the flag is read and its
    /// arrays handed on in pieces); set, a file that large is abandoned (an
    /// output error saying it was stopped, no file, no temporary left) while a
    /// small one, which never reaches a check, is written whole.
    #[test]
    fn a_stop_abandons_a_large_file() {
        let dir = scratch("stop");
        let n = STOP_CHECK_BYTES / 16;
        let points: Vec<[f64; 2]> = (0..n)
            .map(|i| [i as f64 / 7.0, 1.0 / (1.0 + i as f64)])
            .collect();
        let connectivity: Vec<usize> = (0..n).collect();
        let offsets: Vec<usize> = (1..=n).collect();
        let kinds = vec![CellKind::Vertex; n];
        let big = Geometry::new(&points, &connectivity, &offsets, &kinds);
        let small = Geometry::new(
            &points[..10],
            &connectivity[..10],
            &offsets[..10],
            &kinds[..10],
        );
        let fields = Fields {
            point_data: &[],
            cell_data: &[],
            field_data: &[("TIME", 1.0)],
        };
        let (plain, flagged) = (dir.join("plain.vtu"), dir.join("flagged.vtu"));
        write_on(&plain, &big, &fields).unwrap();
        let stop = AtomicUsize::new(0);
        write_on_until(&flagged, &big, &fields, &stop).unwrap();
        let bytes = std::fs::read(&plain).unwrap();
        assert!(bytes.len() > 2 * STOP_CHECK_BYTES, "{}", bytes.len());
        assert!(bytes == std::fs::read(&flagged).unwrap());
        stop.store(15, Ordering::Relaxed);
        let stopped = dir.join("stopped.vtu");
        match write_on_until(&stopped, &big, &fields, &stop) {
            Err(Error::Output { path, message }) => {
                assert_eq!(path, stopped);
                assert!(message.contains("stopped (signal 15)"), "{message}");
            }
            other => panic!("expected a stopped write, got {other:?}"),
        }
        assert!(!stopped.exists());
        assert!(
            !dir.join(crate::output::temporary_name("stopped.vtu"))
                .exists()
        );
        write_on_until(&dir.join("small.vtu"), &small, &fields, &stop).unwrap();
        Vtu::read(&dir.join("small.vtu")).check_tiling();
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Inconsistent grids give an output error naming the file, and no file is written.
    #[test]
    fn bad_grids_are_errors() {
        let dir = scratch("bad");
        let path = dir.join("bad.vtu");
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let ok = Grid {
            points: &points,
            connectivity: &[0, 1, 2],
            offsets: &[3],
            kinds: &[CellKind::Triangle],
            point_data: &[],
            cell_data: &[],
            field_data: &[],
        };
        let short = [DataArray {
            name: "u",
            components: 2,
            values: Values::F64(&[0.0; 5]),
        }];
        let cells_long = [DataArray {
            name: "id",
            components: 1,
            values: Values::I32(&[1, 2]),
        }];
        let zero_comps = [DataArray {
            name: "z",
            components: 0,
            values: Values::F64(&[]),
        }];
        let twice = [
            DataArray {
                name: "a",
                components: 1,
                values: Values::I32(&[1]),
            },
            DataArray {
                name: "a",
                components: 1,
                values: Values::I32(&[1]),
            },
        ];
        let cases: Vec<(&str, Grid)> = vec![
            (
                "point data length",
                Grid {
                    point_data: &short,
                    ..ok
                },
            ),
            (
                "cell data length",
                Grid {
                    cell_data: &cells_long,
                    ..ok
                },
            ),
            (
                "zero components",
                Grid {
                    point_data: &zero_comps,
                    ..ok
                },
            ),
            (
                "repeated name",
                Grid {
                    cell_data: &twice,
                    ..ok
                },
            ),
            ("kinds/offsets", Grid { kinds: &[], ..ok }),
            (
                "offsets short",
                Grid {
                    offsets: &[2],
                    kinds: &[CellKind::Line],
                    ..ok
                },
            ),
            (
                "offsets past end",
                Grid {
                    offsets: &[4],
                    ..ok
                },
            ),
            (
                "offsets not increasing",
                Grid {
                    connectivity: &[0, 1, 2, 0, 1, 2],
                    offsets: &[3, 3, 6],
                    kinds: &[CellKind::Triangle; 3],
                    ..ok
                },
            ),
            (
                "first offset 0",
                Grid {
                    offsets: &[0, 3],
                    kinds: &[CellKind::Triangle; 2],
                    ..ok
                },
            ),
            (
                "kind size",
                Grid {
                    kinds: &[CellKind::Quad],
                    ..ok
                },
            ),
            (
                "connectivity range",
                Grid {
                    connectivity: &[0, 1, 3],
                    ..ok
                },
            ),
            (
                "field name",
                Grid {
                    field_data: &[("a\nb", 1.0)],
                    ..ok
                },
            ),
            (
                "empty name",
                Grid {
                    field_data: &[("", 1.0)],
                    ..ok
                },
            ),
        ];
        for (what, grid) in cases {
            match write_vtu(&path, &grid) {
                Err(Error::Output { path: p, message }) => {
                    assert_eq!(p, path, "{what}");
                    assert!(!message.is_empty(), "{what}");
                }
                other => panic!("{what}: expected an output error, got {other:?}"),
            }
            assert!(!path.exists(), "{what}: file written");
        }
        write_vtu(&path, &ok).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// The .pvd lists every entry with its time, part and XML-escaped file, and a
    /// non-finite time is an error.
    #[test]
    fn pvd_lists_entries() {
        let dir = scratch("pvd");
        let path = dir.join("series.pvd");
        let entries = vec![
            PvdEntry {
                time: 0.0,
                part: 0,
                file: "step_0000/plate.vtu".into(),
            },
            PvdEntry {
                time: 1.0 / 3.0,
                part: 1,
                file: "a&b <\"x'>.vtu".into(),
            },
            PvdEntry {
                time: 1e-12,
                part: 0,
                file: "tiny.vtu".into(),
            },
        ];
        write_pvd(&path, &entries).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let file = elements(&text, "VTKFile").pop().unwrap();
        assert_eq!(file["type"], "Collection");
        assert!(text.contains("<Collection>") && text.contains("</Collection>"));
        let sets = elements(&text, "DataSet");
        assert_eq!(sets.len(), entries.len());
        for (set, e) in sets.iter().zip(&entries) {
            assert_eq!(set["timestep"].parse::<f64>().unwrap(), e.time);
            assert_eq!(set["part"].parse::<usize>().unwrap(), e.part);
            assert_eq!(set["file"], e.file);
        }
        assert!(text.contains("file=\"a&amp;b &lt;&quot;x&apos;&gt;.vtu\""));

        let bad = [PvdEntry {
            time: f64::NAN,
            part: 0,
            file: "x.vtu".into(),
        }];
        let other = dir.join("bad.pvd");
        assert!(matches!(write_pvd(&other, &bad), Err(Error::Output { .. })));
        assert!(!other.exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
