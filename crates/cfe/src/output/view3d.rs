//! output::view3d — pictures of solid (3D) parts a user can look at straight
//! away, from plain data (points, faces, nodal values), drawn with the same
//! colour map, font, colour bar and PNG writer as the plane pictures
//! (`super::png`):
//!
//! - [`render_view`]: the (deformed) boundary faces of the parts seen from a
//!   stated viewpoint ([`View`]: orthographic, azimuth and elevation about an up
//!   axis; isometric by default), each face filled with a colour map of a nodal
//!   value interpolated across it, hidden faces removed by a per-pixel depth
//!   buffer (right for any assembly, convex or not), element edges drawn
//!   lightly, the magnification of the displacements in the title, a colour
//!   bar over the values' full range and a small triad of the x, y, z axes;
//! - [`render_pressure_map`]: the contact pressure over one interface: the
//!   pairs' positions projected onto the interface's mean plane
//!   ([`InterfacePlane`]), triangulated (Delaunay, by the `delaunator` crate)
//!   and coloured by the pressure interpolated linearly, with axes in that plane,
//!   the convex hull of the pairs outlined, the contact zone's outline (where the
//!   interpolated pressure falls to zero) drawn thick, each pair marked (filled
//!   where it carries pressure, hollow where open) and a colour bar;
//! - [`boundary_faces`]: the faces used by one solid cell only, from the cells
//!   of a VTU grid, oriented outwards.
//!
//! Everything is computed sequentially in a fixed order: the same input gives
//! the same bytes. A drawing asks its `proceed` check between stages and every
//! `CHUNK` faces, edges or markers; its error ends the drawing and nothing is
//! written.

use super::png::{
    self, CHUNK, ColourRange, FONT, Layout, PairMarker, PlotLabels, PlotMesh, Proceed, WIDTH,
};
use super::vtu::CellKind;
use crate::error::{Error, Result};
use plotters::prelude::*;
use std::path::Path;

/// A coordinate axis of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

impl Axis {
    /// The unit vector along the axis.
    pub fn unit(self) -> [f64; 3] {
        match self {
            Axis::X => [1.0, 0.0, 0.0],
            Axis::Y => [0.0, 1.0, 0.0],
            Axis::Z => [0.0, 0.0, 1.0],
        }
    }

    /// The axis pointing right in the front view of a model with `self` up:
    /// x for y or z up, y for x up.
    fn right(self) -> Axis {
        match self {
            Axis::X => Axis::Y,
            Axis::Y | Axis::Z => Axis::X,
        }
    }

    /// Its name in a picture.
    fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// Where a 3D picture is seen from: an orthographic view along the direction
/// given by an azimuth and an elevation about the model's `up` axis.
///
/// With `up` and the axis `right` (x, or y when x is up), the front view (azimuth
/// 0, elevation 0) looks along −(right × up), right to the right and up up (for y
/// up: from +z, x right, y up, as the plane pictures; for z up: from −y, x right,
/// z up). The azimuth turns the eye about `up` towards `right`, the elevation
/// raises it towards `up`: the eye lies along
/// cos e (cos a (right × up) + sin a right) + sin e up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Azimuth a in degrees (any finite value).
    pub azimuth_deg: f64,
    /// Elevation e in degrees, from −90 (from below) to 90 (from above).
    pub elevation_deg: f64,
    /// The model's up axis: up in the picture.
    pub up: Axis,
}

impl View {
    /// The elevation of an isometric view, atan(1/√2) ≈ 35.26°: the eye along a
    /// diagonal of a cube, which shows the three faces it sees equally.
    pub const ISOMETRIC_ELEVATION_DEG: f64 = 35.264_389_682_754_654;

    /// The isometric view with `up` up: azimuth 45°, elevation
    /// [`ISOMETRIC_ELEVATION_DEG`](Self::ISOMETRIC_ELEVATION_DEG); for y up the
    /// eye is along (1, 1, 1), for z up along (1, −1, 1).
    pub fn isometric(up: Axis) -> View {
        View {
            azimuth_deg: 45.0,
            elevation_deg: Self::ISOMETRIC_ELEVATION_DEG,
            up,
        }
    }

    /// The unit vector from the model towards the eye.
    pub fn toward_eye(&self) -> [f64; 3] {
        let (a, e) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        let up = self.up.unit();
        let right = self.up.right().unit();
        let front = cross(right, up);
        let mut d = [0.0; 3];
        for k in 0..3 {
            d[k] = e.cos() * (a.cos() * front[k] + a.sin() * right[k]) + e.sin() * up[k];
        }
        normalized(d)
    }

    /// The picture's right and up directions in the model and the direction
    /// towards the eye, or why the view is not one.
    fn camera(&self) -> std::result::Result<Camera, String> {
        if !self.azimuth_deg.is_finite()
            || !self.elevation_deg.is_finite()
            || self.elevation_deg.abs() > 90.0
        {
            return Err(format!(
                "the view's azimuth ({}°) must be finite and its elevation ({}°) within −90° to 90°",
                self.azimuth_deg, self.elevation_deg
            ));
        }
        let d = self.toward_eye();
        let side = cross(self.up.unit(), d);
        // Straight from above or below: the picture's right is the model's.
        let right = if norm(side) > 1e-9 {
            normalized(side)
        } else {
            self.up.right().unit()
        };
        Ok(Camera {
            right,
            up: cross(d, right),
            toward_eye: d,
        })
    }
}

impl Default for View {
    /// The isometric view with y up ([`View::isometric`]), the up axis of the
    /// plane pictures.
    fn default() -> View {
        View::isometric(Axis::Y)
    }
}

/// The orthonormal frame of a view: a model point p is drawn at (p · right,
/// p · up) at the depth p · toward_eye (larger is nearer).
#[derive(Debug, Clone, Copy)]
struct Camera {
    right: [f64; 3],
    up: [f64; 3],
    toward_eye: [f64; 3],
}

impl Camera {
    /// (screen x, screen y, depth) of `p` in model units.
    fn project(&self, p: [f64; 3]) -> [f64; 3] {
        [dot(p, self.right), dot(p, self.up), dot(p, self.toward_eye)]
    }
}

/// A face of a part's boundary: a triangle or a quadrangle given by its nodes
/// in order around it (indices into the points).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Face {
    /// Three nodes.
    Triangle([usize; 3]),
    /// Four nodes in order around it (drawn as the triangles 0-1-2 and 0-2-3).
    Quad([usize; 4]),
}

impl Face {
    /// The nodes in order around the face.
    pub fn nodes(&self) -> &[usize] {
        match self {
            Face::Triangle(n) => n,
            Face::Quad(n) => n,
        }
    }

    /// The triangles the face is drawn as.
    fn triangles(&self) -> impl Iterator<Item = [usize; 3]> {
        let (first, second) = match *self {
            Face::Triangle(t) => (t, None),
            Face::Quad([a, b, c, d]) => ([a, b, c], Some([a, c, d])),
        };
        std::iter::once(first).chain(second)
    }
}

/// The faces of each solid cell kind, as positions in the cell's node list,
/// oriented outwards (right-hand normal pointing out of the cell, VTK's node
/// order; see [`CellKind`]). Other kinds have none.
fn cell_faces(kind: CellKind) -> &'static [&'static [usize]] {
    match kind {
        CellKind::Tetra => &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]],
        CellKind::Hexahedron => &[
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ],
        CellKind::Wedge => &[
            &[0, 1, 2],
            &[3, 5, 4],
            &[0, 3, 4, 1],
            &[1, 4, 5, 2],
            &[2, 5, 3, 0],
        ],
        CellKind::Vertex | CellKind::Line | CellKind::Triangle | CellKind::Quad => &[],
    }
}

/// The boundary of solid cells: every face of a tetrahedron, hexahedron or wedge
/// (cells as in [`super::vtu::Grid`]: `connectivity`, `offsets`, `kinds`) that
/// no other cell has (whatever its nodes' order), with its nodes in the order
/// that makes it face out of its cell, sorted by their node numbers (the same
/// cells give the same list). Vertices, lines, triangles and quadrangles give
/// no faces. Parts meshed independently do not share nodes, so each part's
/// boundary is whole, the faces at an interface included. O(faces log faces).
///
/// Returns [`Error::Output`] (naming `what`, e.g. the picture's path) when the
/// cells are inconsistent (as [`super::vtu::write_vtu`] checks them).
pub fn boundary_faces(
    what: &Path,
    n_points: usize,
    connectivity: &[usize],
    offsets: &[usize],
    kinds: &[CellKind],
) -> Result<Vec<Face>> {
    super::vtu::validate_cells(n_points, connectivity, offsets, kinds)
        .map_err(|m| Error::output(what, m))?;
    let mut keyed: Vec<([usize; 4], Face)> = Vec::new();
    let mut start = 0;
    for (&end, &kind) in offsets.iter().zip(kinds) {
        let cell = &connectivity[start..end];
        start = end;
        for local in cell_faces(kind) {
            let face = match local.len() {
                3 => Face::Triangle([cell[local[0]], cell[local[1]], cell[local[2]]]),
                _ => Face::Quad([
                    cell[local[0]],
                    cell[local[1]],
                    cell[local[2]],
                    cell[local[3]],
                ]),
            };
            let mut key = [usize::MAX; 4];
            key[..local.len()].copy_from_slice(face.nodes());
            key.sort_unstable();
            keyed.push((key, face));
        }
    }
    keyed.sort_unstable();
    let mut faces = Vec::new();
    let mut i = 0;
    while i < keyed.len() {
        let mut j = i + 1;
        while j < keyed.len() && keyed[j].0 == keyed[i].0 {
            j += 1;
        }
        if j == i + 1 {
            faces.push(keyed[i].1);
        }
        i = j;
    }
    Ok(faces)
}

/// What [`render_view`] draws: the parts' boundary faces, a nodal value on them
/// and, for a deformed picture, the displacements.
#[derive(Debug, Clone, Copy)]
pub struct Surface<'a> {
    /// Node coordinates (undeformed).
    pub points: &'a [[f64; 3]],
    /// The faces to draw (e.g. [`boundary_faces`]), node indices into `points`.
    pub faces: &'a [Face],
    /// The value coloured, one per point (von Mises, a stress component …);
    /// only the values of the faces' nodes are read.
    pub values: &'a [f64],
    /// Displacements of the points, one per point, for the deformed shape;
    /// `None` draws the undeformed shape.
    pub displacement: Option<&'a [[f64; 3]]>,
}

/// How much the displacements are magnified in a deformed picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Magnification {
    /// The largest 1, 2 or 5 × 10ⁿ that makes the largest displacement at most
    /// 5 % of the model's size (the largest side of its bounding box), as the
    /// plane pictures do; 0 when nothing moves.
    Auto,
    /// This factor (finite, not negative; 1 is the true shape).
    Factor(f64),
}

/// The texts of a [`render_view`] picture (each bounded by
/// `png::label_text`).
#[derive(Debug, Clone, Copy)]
pub struct ViewLabels<'a> {
    /// What is shown, e.g. `plate on a base: von Mises`; the magnification
    /// (`deformed ×200`, or `undeformed`) is added after it.
    pub title: &'a str,
    /// The colour bar's label, e.g. `σ_vM [MPa]`.
    pub colorbar: &'a str,
}

/// What a [`render_view`] picture shows, for a caller to report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewPicture {
    /// The magnification of the displacements drawn (0 when undeformed).
    pub magnification: f64,
    /// The value coloured by the colour bar's bottom: the smallest value at
    /// the faces' nodes.
    pub colour_min: f64,
    /// The value coloured by the colour bar's top: the largest value at the
    /// faces' nodes.
    pub colour_max: f64,
}

/// Margins of a [`render_view`] picture around its plot box, in pixels (the
/// colour bar is in the right one, the axes' triad in the bottom one).
const VIEW_LEFT: u32 = 40;
const VIEW_RIGHT: u32 = 230;
const VIEW_TOP: u32 = 90;
const VIEW_BOTTOM: u32 = 110;

/// The brightness of a face facing the eye squarely is 1, of one seen edge-on
/// `FLAT_LIGHT`: a face's colour is its value's times
/// `FLAT_LIGHT + (1 − FLAT_LIGHT) |cos θ|` (θ between its normal and the
/// direction to the eye), a gentle shading that shows the shape and keeps
/// the colours readable against the colour bar.
const FLAT_LIGHT: f64 = 0.7;

/// How much an element edge darkens the colour under it (0.6 of it is kept).
const EDGE_KEEP: f64 = 0.6;

/// Draws `surface` seen from `view` as a PNG at `path`: the faces, deformed by
/// the displacements times the magnification (stated in the title), coloured
/// by the values interpolated linearly across each triangle (a quadrangle is
/// two, split at its 0-2 diagonal), hidden faces removed per pixel, element
/// edges drawn lightly (a visible edge darkens the pixels it crosses; so does
/// the outline of the parts on the background), gently shaded by the angle to
/// the eye; a colour bar over the values' full range at the faces' nodes, a
/// line under the title stating the view, and a triad of the axes. Returns the
/// magnification and the colour range drawn. `proceed` is asked between the
/// stages and every `CHUNK` faces or edges; its error ends the drawing and
/// nothing is written.
///
/// Returns [`Error::Output`] without writing when there is no face, a face
/// names a point that is not given, the values or the displacements are not
/// one per point, a coordinate, value or displacement is not finite, the
/// magnification is negative or not finite, or the view is not one.
///
/// ```
/// use cfe::output::view3d::{render_view, Face, Magnification, Surface, View, ViewLabels};
/// // A unit cube of one hexahedron's faces, the value rising with z, squeezed in z.
/// let points = [
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let faces = [
///     Face::Quad([0, 3, 2, 1]), Face::Quad([4, 5, 6, 7]), Face::Quad([0, 1, 5, 4]),
///     Face::Quad([1, 2, 6, 5]), Face::Quad([2, 3, 7, 6]), Face::Quad([3, 0, 4, 7]),
/// ];
/// let values: Vec<f64> = points.iter().map(|p| p[2]).collect();
/// let u: Vec<[f64; 3]> = points.iter().map(|p| [0.0, 0.0, -1e-3 * p[2]]).collect();
/// let surface = Surface { points: &points, faces: &faces, values: &values, displacement: Some(&u) };
/// let path = std::env::temp_dir().join(format!("cfe_doc_view_{}.png", std::process::id()));
/// let labels = ViewLabels { title: "cube: z", colorbar: "z [m]" };
/// let drawn = render_view(&path, &surface, &View::default(), Magnification::Auto, &labels, &|| Ok(()))
///     .unwrap();
/// assert_eq!(drawn.magnification, 50.0); // 5 % of the size 1 over the largest displacement 1e-3
/// assert_eq!((drawn.colour_min, drawn.colour_max), (0.0, 1.0));
/// std::fs::remove_file(&path).unwrap();
/// ```
pub fn render_view(
    path: &Path,
    surface: &Surface,
    view: &View,
    magnification: Magnification,
    labels: &ViewLabels,
    proceed: Proceed<'_>,
) -> Result<ViewPicture> {
    let bad = |m: String| Error::output(path, m);
    let camera = view.camera().map_err(bad)?;
    validate_surface(surface, magnification).map_err(bad)?;
    proceed()?;
    png::register_font();
    let scale = match magnification {
        Magnification::Factor(f) => f,
        Magnification::Auto => auto_magnification(surface.points, surface.displacement),
    };
    let deformed: Vec<[f64; 3]> = match surface.displacement {
        Some(u) if scale > 0.0 => surface
            .points
            .iter()
            .zip(u)
            .map(|(p, d)| [0, 1, 2].map(|k| p[k] + scale * d[k]))
            .collect(),
        _ => surface.points.to_vec(),
    };
    let moved = surface.displacement.is_some() && scale > 0.0;
    // The drawn nodes, once each in increasing order.
    let mut used: Vec<usize> = surface
        .faces
        .iter()
        .flat_map(|f| f.nodes().iter().copied())
        .collect();
    used.sort_unstable();
    used.dedup();
    let drawn_values: Vec<f64> = used.iter().map(|&n| surface.values[n]).collect();
    let range = ColourRange::full(&drawn_values);
    let projected: Vec<[f64; 3]> = deformed.iter().map(|&p| camera.project(p)).collect();
    let fit = ViewFit::new(used.iter().map(|&n| projected[n]));
    let px = |n: usize| fit.px(projected[n]);

    let title = format!(
        "{}, {}",
        png::label_text(labels.title),
        if moved {
            format!("deformed ×{}", magnification_text(scale))
        } else {
            "undeformed".to_string()
        }
    );
    let colorbar = png::label_text(labels.colorbar);
    let err = png::draw_err(path);
    let (width, height) = (WIDTH, fit.height);
    let mut buf = vec![255u8; (width * height * 3) as usize];
    // 1. Title, the view's line, colour bar.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        let (_, _, pr, _) = fit.plot_box();
        let room = (pr + 20 - VIEW_LEFT as i32).max(50) as u32;
        let (title, size) = png::fit_title(&root, &title, room);
        let text = |size: f64| TextStyle::from((FONT, size).into_font()).color(&BLACK);
        root.draw(&Text::new(title, (VIEW_LEFT as i32, 18), text(size)))
            .map_err(|e| err(&e))?;
        let line = format!(
            "seen from azimuth {}°, elevation {}° ({} up), orthographic",
            angle_text(view.azimuth_deg),
            angle_text(view.elevation_deg),
            view.up.name()
        );
        root.draw(&Text::new(line, (VIEW_LEFT as i32, 54), text(18.0)))
            .map_err(|e| err(&e))?;
        png::draw_colour_bar(path, &root, fit.plot_box(), &range, &colorbar)?;
        root.present().map_err(|e| err(&e))?;
    }

    // 2. The faces, a depth buffer over the plot box.
    let clip = fit.clip();
    let mut depth = DepthBuffer::new(width as usize, clip);
    for chunk in surface.faces.chunks(CHUNK) {
        proceed()?;
        for face in chunk {
            let light = face_light(face, &deformed, camera.toward_eye);
            for t in face.triangles() {
                depth.fill(&mut buf, t.map(px), t.map(|n| surface.values[n]), |v| {
                    shade(png::turbo(range.norm(v)), light)
                });
            }
        }
    }

    // 3. Element edges: darken the pixels of the visible ones (each pixel once).
    let mut edges: Vec<[usize; 2]> = surface
        .faces
        .iter()
        .flat_map(|f| {
            let n = f.nodes();
            (0..n.len()).map(move |k| {
                let (a, b) = (n[k], n[(k + 1) % n.len()]);
                [a.min(b), a.max(b)]
            })
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    // An edge lies on its faces: it is visible where it is no more than two
    // pixels' depth behind what was drawn.
    let tolerance = 2.0 / fit.scale;
    let mut mask = vec![false; depth.z.len()];
    for chunk in edges.chunks(CHUNK) {
        proceed()?;
        for &[a, b] in chunk {
            depth.mark_edge(&mut mask, px(a), px(b), tolerance);
        }
    }
    depth.darken(&mut buf, &mask);

    // 4. The axes' triad.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        draw_triad(path, &root, &camera, fit.plot_box())?;
        root.present().map_err(|e| err(&e))?;
    }
    proceed()?;
    png::write_rgb(path, &buf, width, height)?;
    Ok(ViewPicture {
        magnification: if moved { scale } else { 0.0 },
        colour_min: range.vmin,
        colour_max: range.vmax,
    })
}

/// Why `surface` cannot be drawn with `magnification`, if it cannot.
fn validate_surface(
    surface: &Surface,
    magnification: Magnification,
) -> std::result::Result<(), String> {
    let n = surface.points.len();
    if surface.faces.is_empty() {
        return Err("nothing to draw: no face is given".into());
    }
    if let Some(f) = surface
        .faces
        .iter()
        .find(|f| f.nodes().iter().any(|&k| k >= n))
    {
        return Err(format!("face {f:?} names a point beyond the {n} given"));
    }
    if surface.values.len() != n {
        return Err(format!("{} values for {n} points", surface.values.len()));
    }
    if let Some(u) = surface.displacement
        && u.len() != n
    {
        return Err(format!("{} displacements for {n} points", u.len()));
    }
    let finite = surface.points.iter().flatten().all(|x| x.is_finite())
        && surface.values.iter().all(|x| x.is_finite())
        && surface
            .displacement
            .is_none_or(|u| u.iter().flatten().all(|x| x.is_finite()));
    if !finite {
        return Err("a coordinate, value or displacement is not finite".into());
    }
    if let Magnification::Factor(f) = magnification
        && !(f.is_finite() && f >= 0.0)
    {
        return Err(format!(
            "the magnification {f} must be finite and not negative"
        ));
    }
    Ok(())
}

/// [`Magnification::Auto`]'s factor for `points` moved by `displacement`.
fn auto_magnification(points: &[[f64; 3]], displacement: Option<&[[f64; 3]]>) -> f64 {
    let Some(u) = displacement else {
        return 0.0;
    };
    let umax = u.iter().map(|d| norm(*d)).fold(0.0, f64::max);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if umax > 0.0 && size > 0.0 {
        png::nice_floor(0.05 * size / umax)
    } else {
        0.0
    }
}

/// A magnification as the title states it: plain below 10⁵, else `2e6`.
fn magnification_text(m: f64) -> String {
    if (1e-3..1e5).contains(&m) {
        format!("{m}")
    } else {
        format!("{m:e}")
    }
}

/// An angle in degrees with at most two decimals (`45`, `35.26`).
fn angle_text(deg: f64) -> String {
    let s = format!("{deg:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The brightness factor of `face` (of the deformed points `p`) seen along
/// `toward_eye`: see [`FLAT_LIGHT`]. Its normal is Newell's (the sum of its
/// edges' cross terms), right for a warped quadrangle too.
fn face_light(face: &Face, p: &[[f64; 3]], toward_eye: [f64; 3]) -> f64 {
    let n = face.nodes();
    let mut normal = [0.0; 3];
    for k in 0..n.len() {
        let (a, b) = (p[n[k]], p[n[(k + 1) % n.len()]]);
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let length = norm(normal);
    let cos = if length > 0.0 {
        (dot(normal, toward_eye) / length).abs()
    } else {
        1.0
    };
    FLAT_LIGHT + (1.0 - FLAT_LIGHT) * cos
}

/// `c` times `factor` (≤ 1), rounded.
fn shade(c: [u8; 3], factor: f64) -> [u8; 3] {
    c.map(|v| (f64::from(v) * factor).round() as u8)
}

/// The fit of the projected model into a [`render_view`] picture: equal scale
/// both ways, screen up drawn up, a small pad.
struct ViewFit {
    /// Projected window: smallest screen x and largest screen y shown.
    x0: f64,
    y1: f64,
    /// Pixels per model unit.
    scale: f64,
    plot_w: u32,
    plot_h: u32,
    height: u32,
}

impl ViewFit {
    /// The fit of the projected points `projected` ((screen x, screen y,
    /// depth)).
    fn new(projected: impl Iterator<Item = [f64; 3]>) -> ViewFit {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in projected {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-300);
        let pad = 0.04 * span;
        let (x0, x1, y0, y1) = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad);
        let plot_w = WIDTH - VIEW_LEFT - VIEW_RIGHT;
        let plot_h = ((plot_w as f64) * (y1 - y0) / (x1 - x0).max(1e-300))
            .round()
            .clamp(400.0, 1000.0) as u32;
        let scale = (plot_w as f64 / (x1 - x0)).min(plot_h as f64 / (y1 - y0));
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (hw, hh) = (0.5 * plot_w as f64 / scale, 0.5 * plot_h as f64 / scale);
        ViewFit {
            x0: cx - hw,
            y1: cy + hh,
            scale,
            plot_w,
            plot_h,
            height: plot_h + VIEW_TOP + VIEW_BOTTOM,
        }
    }

    /// (pixel x, pixel y, depth in model units) of a projected point.
    fn px(&self, p: [f64; 3]) -> [f64; 3] {
        [
            VIEW_LEFT as f64 + (p[0] - self.x0) * self.scale,
            VIEW_TOP as f64 + (self.y1 - p[1]) * self.scale,
            p[2],
        ]
    }

    /// The plot box: (left, top, right, bottom) in pixels.
    fn plot_box(&self) -> (i32, i32, i32, i32) {
        (
            VIEW_LEFT as i32,
            VIEW_TOP as i32,
            (VIEW_LEFT + self.plot_w) as i32,
            (VIEW_TOP + self.plot_h) as i32,
        )
    }

    /// The plot box as a clip rectangle [x0, y0, x1, y1) in pixels.
    fn clip(&self) -> [usize; 4] {
        let (l, t, r, b) = self.plot_box();
        [l as usize, t as usize, r as usize, b as usize]
    }
}

/// The depth of what was drawn at each pixel of a clip rectangle (−∞ where
/// nothing is), for hidden-surface removal.
struct DepthBuffer {
    /// The picture's width in pixels.
    width: usize,
    /// [x0, y0, x1, y1) in pixels.
    clip: [usize; 4],
    /// Row by row over the clip rectangle.
    z: Vec<f64>,
}

impl DepthBuffer {
    fn new(width: usize, clip: [usize; 4]) -> DepthBuffer {
        let n = (clip[2] - clip[0]) * (clip[3] - clip[1]);
        DepthBuffer {
            width,
            clip,
            z: vec![f64::NEG_INFINITY; n],
        }
    }

    /// The index in `z` of pixel (x, y), if it is in the clip rectangle.
    fn at(&self, x: f64, y: f64) -> Option<usize> {
        let [x0, y0, x1, y1] = self.clip.map(|v| v as f64);
        (x >= x0 && x < x1 && y >= y0 && y < y1).then(|| {
            let (ix, iy) = (x as usize - self.clip[0], y as usize - self.clip[1]);
            iy * (self.clip[2] - self.clip[0]) + ix
        })
    }

    /// The RGB buffer's index of the pixel of depth index `i`.
    fn rgb(&self, i: usize) -> usize {
        let w = self.clip[2] - self.clip[0];
        3 * ((self.clip[1] + i / w) * self.width + self.clip[0] + i % w)
    }

    /// Fills the triangle `p` ((pixel x, pixel y, depth) of its corners) into
    /// `buf`: every pixel whose centre it covers, where it is nearer than what
    /// was drawn there, gets `colour` of the linear interpolation of `v` (a
    /// triangle covering no pixel centre still paints its centroid's pixel, if
    /// nearer). Nearer means a larger depth; a tie keeps the first drawn.
    fn fill(
        &mut self,
        buf: &mut [u8],
        p: [[f64; 3]; 3],
        v: [f64; 3],
        colour: impl Fn(f64) -> [u8; 3],
    ) {
        let mut put = |this: &mut Self, x: f64, y: f64, z: f64, value: f64| -> bool {
            match this.at(x, y) {
                Some(i) if z > this.z[i] => {
                    this.z[i] = z;
                    let k = this.rgb(i);
                    buf[k..k + 3].copy_from_slice(&colour(value));
                    true
                }
                Some(_) => true,
                None => false,
            }
        };
        let mut covered = false;
        let clip = self.clip;
        png::triangle_pixels(
            [0, 1, 2].map(|k| [p[k][0], p[k][1]]),
            clip,
            |x, y, [l0, l1, l2]| {
                let z = l0 * p[0][2] + l1 * p[1][2] + l2 * p[2][2];
                let value = l0 * v[0] + l1 * v[1] + l2 * v[2];
                covered |= put(self, x as f64 + 0.5, y as f64 + 0.5, z, value);
            },
        );
        if !covered {
            let c = [0, 1, 2].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
            put(self, c[0], c[1], c[2], (v[0] + v[1] + v[2]) / 3.0);
        }
    }

    /// Marks in `mask` the pixels of the segment from `a` to `b` ((pixel x,
    /// pixel y, depth)) where it is no more than `tolerance` behind what was
    /// drawn (or where nothing was): one sample per pixel step along it.
    fn mark_edge(&self, mask: &mut [bool], a: [f64; 3], b: [f64; 3], tolerance: f64) {
        let steps = (b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil().max(1.0) as usize;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let q = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
            if let Some(i) = self.at(q[0], q[1])
                && q[2] + tolerance >= self.z[i]
            {
                mask[i] = true;
            }
        }
    }

    /// Darkens the pixels of `buf` marked in `mask` (see [`EDGE_KEEP`]).
    fn darken(&self, buf: &mut [u8], mask: &[bool]) {
        for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
            let k = self.rgb(i);
            let c = [buf[k], buf[k + 1], buf[k + 2]];
            buf[k..k + 3].copy_from_slice(&shade(c, EDGE_KEEP));
        }
    }
}

/// The x, y, z axes as seen in the view, drawn below the plot box's left
/// corner: red, green and blue arrows with their names.
fn draw_triad(
    path: &Path,
    root: &png::Area,
    camera: &Camera,
    plot_box: (i32, i32, i32, i32),
) -> Result<()> {
    let err = png::draw_err(path);
    let (pl, _, _, pb) = plot_box;
    let origin = (pl + 60, pb + 55);
    let length = 40.0;
    let font = TextStyle::from((FONT, 18.0).into_font()).color(&BLACK);
    for (axis, colour) in [
        (Axis::X, RGBColor(200, 30, 30)),
        (Axis::Y, RGBColor(30, 150, 30)),
        (Axis::Z, RGBColor(30, 60, 200)),
    ] {
        let e = axis.unit();
        let (dx, dy) = (dot(e, camera.right), -dot(e, camera.up));
        let tip = (
            origin.0 + (length * dx).round() as i32,
            origin.1 + (length * dy).round() as i32,
        );
        root.draw(&PathElement::new(vec![origin, tip], colour.stroke_width(3)))
            .map_err(|e| err(&e))?;
        let label = (
            origin.0 + ((length + 12.0) * dx).round() as i32 - 5,
            origin.1 + ((length + 12.0) * dy).round() as i32 - 9,
        );
        root.draw(&Text::new(axis.name(), label, font.clone()))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// The plane a contact pressure map is drawn in: through the centroid of the
/// pairs' positions, its normal the direction in which they spread least (the
/// eigenvector of the smallest eigenvalue of their scatter matrix), with two
/// axes in it. A point p is drawn at (p · axes\[0\], p · axes\[1\]): where an
/// axis is a model axis, the picture's coordinate is the model's.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfacePlane {
    /// The centroid of the positions.
    pub origin: [f64; 3],
    /// The unit normal, on the side the map is seen from.
    pub normal: [f64; 3],
    /// The picture's horizontal and vertical axes: the model axis most nearly
    /// in the plane (the first such of x, y, z) projected onto it, and
    /// normal × that axis, so (axes\[0\], axes\[1\], normal) is right-handed and
    /// the map is seen from the normal's side; of the two sides, the one whose
    /// vertical axis' largest component is positive (a plane normal to z is
    /// seen with x across and y up, one normal to y with x across and z up,
    /// one normal to x with y across and z up).
    pub axes: [[f64; 3]; 2],
}

impl InterfacePlane {
    /// The mean plane of `points` (at least one); `None` when a coordinate
    /// is not finite.
    pub fn through(points: &[[f64; 3]]) -> Option<InterfacePlane> {
        if points.is_empty() || points.iter().flatten().any(|x| !x.is_finite()) {
            return None;
        }
        let n = points.len() as f64;
        let origin = [0, 1, 2].map(|k| points.iter().map(|p| p[k]).sum::<f64>() / n);
        let mut scatter = [[0.0; 3]; 3];
        for p in points {
            let d = [0, 1, 2].map(|k| p[k] - origin[k]);
            for i in 0..3 {
                for j in 0..3 {
                    scatter[i][j] += d[i] * d[j];
                }
            }
        }
        let m = faer::Mat::<f64>::from_fn(3, 3, |i, j| scatter[i][j]);
        let eigen = m.self_adjoint_eigen(faer::Side::Lower).ok()?;
        // Eigenvalues in nondecreasing order: the first vector is the normal.
        let u = eigen.U();
        let mut normal = normalized([u[(0, 0)], u[(1, 0)], u[(2, 0)]]);
        if !normal.iter().all(|x| x.is_finite()) {
            return None;
        }
        // The model axis most nearly in the plane (the first of equals).
        let k = (0..3)
            .min_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()).then(a.cmp(&b)))
            .unwrap_or(0);
        let e = Axis::unit([Axis::X, Axis::Y, Axis::Z][k]);
        let along = dot(e, normal);
        let first = normalized([0, 1, 2].map(|i| e[i] - along * normal[i]));
        let mut second = cross(normal, first);
        // The side the map is seen from: the one whose vertical axis' largest
        // component is positive (for an interface normal to y: x across, z up).
        let largest = (0..3)
            .max_by(|&a, &b| second[a].abs().total_cmp(&second[b].abs()).then(b.cmp(&a)))
            .unwrap_or(2);
        if second[largest] < 0.0 {
            normal = normal.map(|x| -x);
            second = second.map(|x| -x);
        }
        Some(InterfacePlane {
            origin,
            normal,
            axes: [first, second],
        })
    }

    /// The picture's coordinates of `p`: (p · axes\[0\], p · axes\[1\]).
    pub fn project(&self, p: [f64; 3]) -> [f64; 2] {
        [dot(p, self.axes[0]), dot(p, self.axes[1])]
    }

    /// The name of axis `k` in the picture: `x`, `−z` … where it is a model
    /// axis, else `s₁`, `s₂`.
    fn axis_name(&self, k: usize) -> String {
        let a = self.axes[k];
        for (i, name) in ["x", "y", "z"].iter().enumerate() {
            if a[i].abs() > 1.0 - 1e-9 {
                return if a[i] > 0.0 {
                    name.to_string()
                } else {
                    format!("−{name}")
                };
            }
        }
        ["s₁", "s₂"][k].to_string()
    }
}

/// What [`render_pressure_map`] draws: the pairs of one interface.
#[derive(Debug, Clone, Copy)]
pub struct PressureMap<'a> {
    /// Each pair's position (its coupling node).
    pub points: &'a [[f64; 3]],
    /// Each pair's contact pressure (0 where open).
    pub pressure: &'a [f64],
}

/// The texts of a [`render_pressure_map`] picture (each bounded by
/// `png::label_text`).
#[derive(Debug, Clone, Copy)]
pub struct MapLabels<'a> {
    /// The title, e.g. `plate on a base: contact pressure on base/plate`.
    pub title: &'a str,
    /// The colour bar's label, e.g. `p [MPa]`.
    pub colorbar: &'a str,
    /// The length unit of the axes, e.g. `mm`.
    pub axis_unit: &'a str,
}

/// The level of the contact zone's outline, as a fraction of the largest
/// pressure: where the linearly interpolated pressure falls to (nearly) zero.
const ZONE_LEVEL: f64 = 1e-6;

/// The mean plane of the pair positions `points`, their projections on it and
/// their Delaunay triangulation; why not when a position is not finite or they
/// do not span a plane (fewer than three, or all on one line once projected).
fn triangulate(
    points: &[[f64; 3]],
) -> std::result::Result<(InterfacePlane, Vec<[f64; 2]>, delaunator::Triangulation), String> {
    let n = points.len();
    let collinear = || {
        format!(
            "the {n} pair positions do not span a plane (fewer than 3, or all on one line): no map to draw"
        )
    };
    if n < 3 {
        return Err(collinear());
    }
    let plane = InterfacePlane::through(points)
        .ok_or_else(|| "a pair position is not finite".to_string())?;
    let projected: Vec<[f64; 2]> = points.iter().map(|&p| plane.project(p)).collect();
    // Triangulated about the centroid's projection (the better conditioned).
    let c = plane.project(plane.origin);
    let relative: Vec<delaunator::Point> = projected
        .iter()
        .map(|p| delaunator::Point {
            x: p[0] - c[0],
            y: p[1] - c[1],
        })
        .collect();
    let delaunay = delaunator::triangulate(&relative);
    // Positions on one line up to round-off may still give slivers: the
    // triangles must cover some of the positions' extent.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &relative {
        lo = [lo[0].min(p.x), lo[1].min(p.y)];
        hi = [hi[0].max(p.x), hi[1].max(p.y)];
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let area: f64 = delaunay
        .triangles
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|k| &relative[k]);
            0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)).abs()
        })
        .sum();
    if delaunay.triangles.is_empty() || area <= 1e-9 * extent * extent {
        return Err(collinear());
    }
    Ok((plane, projected, delaunay))
}

/// Whether [`render_pressure_map`] can draw the pair positions `points`: they
/// are finite and span a plane (at least three, not all on one line once
/// projected on their mean plane).
pub fn spans_plane(points: &[[f64; 3]]) -> bool {
    triangulate(points).is_ok()
}

/// Draws the contact pressure over one interface as a PNG at `path`: the
/// pairs' positions projected onto the interface's mean plane
/// ([`InterfacePlane::through`]), their Delaunay triangulation filled with the
/// pressure interpolated linearly (the colour bar over its full range), the
/// convex hull of the pairs outlined thin, the contact zone's outline (the
/// pressure's isoline at `ZONE_LEVEL` of its largest value) thick, every pair
/// marked (filled where its pressure is positive, hollow where it is not), axes
/// in the plane in the model's length unit, and a line under the title giving
/// the plane's normal and centroid. Returns the plane. `proceed` is asked
/// between the stages and every `CHUNK` triangles or markers.
///
/// Returns [`Error::Output`] without writing when the pressures are not one per
/// position, a value is not finite, or the positions do not span a plane
/// (fewer than three, or all on one line once projected).
///
/// ```
/// use cfe::output::view3d::{render_pressure_map, MapLabels, PressureMap};
/// // Pairs on a 5 × 5 grid in the plane y = 1, pressed most at the centre.
/// let points: Vec<[f64; 3]> = (0..25)
///     .map(|k| [(k % 5) as f64, 1.0, (k / 5) as f64])
///     .collect();
/// let pressure: Vec<f64> = points
///     .iter()
///     .map(|p| (4.0 - (p[0] - 2.0).powi(2) - (p[2] - 2.0).powi(2)).max(0.0))
///     .collect();
/// let path = std::env::temp_dir().join(format!("cfe_doc_map_{}.png", std::process::id()));
/// let labels = MapLabels { title: "punch: contact pressure", colorbar: "p [MPa]", axis_unit: "mm" };
/// let plane = render_pressure_map(&path, &PressureMap { points: &points, pressure: &pressure }, &labels, &|| Ok(()))
///     .unwrap();
/// assert!((plane.normal[1].abs() - 1.0).abs() < 1e-12); // the plane y = 1
/// assert!((plane.axes[0][0] - 1.0).abs() < 1e-12 && (plane.axes[1][2] - 1.0).abs() < 1e-12); // x across, z up
/// std::fs::remove_file(&path).unwrap();
/// ```
pub fn render_pressure_map(
    path: &Path,
    map: &PressureMap,
    labels: &MapLabels,
    proceed: Proceed<'_>,
) -> Result<InterfacePlane> {
    let bad = |m: String| Error::output(path, m);
    let n = map.points.len();
    if map.pressure.len() != n {
        return Err(bad(format!(
            "{} pressures for {n} pair positions",
            map.pressure.len()
        )));
    }
    if map.pressure.iter().any(|p| !p.is_finite()) {
        return Err(bad("a pressure is not finite".into()));
    }
    let (plane, projected, delaunay) = triangulate(map.points).map_err(bad)?;
    proceed()?;
    png::register_font();
    let triangles: Vec<[usize; 3]> = delaunay
        .triangles
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let hull: Vec<[usize; 2]> = (0..delaunay.hull.len())
        .map(|k| {
            [
                delaunay.hull[k],
                delaunay.hull[(k + 1) % delaunay.hull.len()],
            ]
        })
        .collect();
    let axes = [plane.axis_name(0), plane.axis_name(1)];
    let (title, colorbar, axis_unit) = (
        png::label_text(labels.title),
        png::label_text(labels.colorbar),
        png::label_text(labels.axis_unit),
    );
    let plot_labels = PlotLabels {
        title: &title,
        colorbar: &colorbar,
        axis_unit: &axis_unit,
    };
    let err = png::draw_err(path);
    let layout = Layout::new(&projected);
    let range = ColourRange::full(map.pressure);
    let mut buf = vec![255u8; (WIDTH * layout.height * 3) as usize];
    // 1. Frame, axes, title, the plane's line, colour bar.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, layout.height)).into_drawing_area();
        png::draw_frame_and_axes(path, &root, &layout, &plot_labels, [&axes[0], &axes[1]])?;
        let (pl, pt, _, _) = layout.plot_box();
        let line = format!(
            "pairs projected on the plane through ({}) with normal ({})",
            vector_text(plane.origin),
            vector_text(plane.normal)
        );
        let font = TextStyle::from((FONT, 16.0).into_font()).color(&BLACK);
        root.draw(&Text::new(line, (pl, pt - 22), font))
            .map_err(|e| err(&e))?;
        png::draw_colour_bar(path, &root, layout.plot_box(), &range, &colorbar)?;
        root.present().map_err(|e| err(&e))?;
    }
    // 2. The pressure over the triangulation.
    let tf = layout.tf;
    for chunk in triangles.chunks(CHUNK) {
        proceed()?;
        let tris = chunk
            .iter()
            .map(|t| (t.map(|k| tf.px(projected[k])), t.map(|k| map.pressure[k])));
        png::rasterize(&mut buf, WIDTH as usize, layout.clip(), tris, |v| {
            png::turbo(range.norm(v))
        });
    }
    // 3. Hull, contact zone, pairs.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, layout.height)).into_drawing_area();
        let mesh = PlotMesh {
            points: &projected,
            triangles: &triangles,
            outline: Some(&hull),
        };
        png::draw_outline(path, &root, &layout, &mesh, proceed)?;
        let pmax = range.data_max;
        if pmax > 0.0 && range.data_min < ZONE_LEVEL * pmax {
            let level = ZONE_LEVEL * pmax;
            for (i, t) in triangles.iter().enumerate() {
                if i % CHUNK == 0 {
                    proceed()?;
                }
                let p = t.map(|k| tf.px(projected[k]));
                if let Some([a, b]) = png::isoline_segment(&p, &t.map(|k| map.pressure[k]), level)
                    && layout.inside(a)
                    && layout.inside(b)
                {
                    root.draw(&PathElement::new(
                        vec![png::ip(a), png::ip(b)],
                        BLACK.stroke_width(3),
                    ))
                    .map_err(|e| err(&e))?;
                }
            }
        }
        let markers: Vec<PairMarker> = projected
            .iter()
            .zip(map.pressure)
            .map(|(&at, &p)| PairMarker {
                at,
                bonded: p > 0.0,
                slip: false,
                violates: false,
            })
            .collect();
        png::draw_markers(path, &root, &layout, &markers, proceed)?;
        root.present().map_err(|e| err(&e))?;
    }
    proceed()?;
    png::write_rgb(path, &buf, WIDTH, layout.height)?;
    Ok(plane)
}

/// A vector with three significant decimals per component: `0, 1, 0`.
fn vector_text(v: [f64; 3]) -> String {
    let scale = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    v.map(|x| {
        let x = if x.abs() <= 1e-12 * scale { 0.0 } else { x };
        png::format_value(x, scale)
    })
    .join(", ")
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn normalized(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    a.map(|x| x / n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::path::PathBuf;

    /// A drawing that is never asked to stop.
    const GO: Proceed<'static> = &|| Ok(());

    /// A fresh scratch directory for one test.
    fn scratch(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("cfe_view3d_{}_{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The six faces of the box [lo, hi], each with four nodes of its own
    /// (appended to `points`), with `values[k]` at the nodes of face k in the
    /// order x = lo, x = hi, y = lo, y = hi, z = lo, z = hi.
    fn box_faces(
        points: &mut Vec<[f64; 3]>,
        nodal: &mut Vec<f64>,
        lo: [f64; 3],
        hi: [f64; 3],
        values: [f64; 6],
    ) -> Vec<Face> {
        let corner = |i: usize, j: usize, k: usize| {
            [
                if i == 0 { lo[0] } else { hi[0] },
                if j == 0 { lo[1] } else { hi[1] },
                if k == 0 { lo[2] } else { hi[2] },
            ]
        };
        let sides: [[[usize; 3]; 4]; 6] = [
            [[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]],
            [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]],
            [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]],
            [[0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
            [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
            [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
        ];
        sides
            .iter()
            .zip(values)
            .map(|(side, v)| {
                let first = points.len();
                for c in side {
                    points.push(corner(c[0], c[1], c[2]));
                    nodal.push(v);
                }
                Face::Quad([first, first + 1, first + 2, first + 3])
            })
            .collect()
    }

    /// The pixel (x, y) of model point `p` in a [`render_view`] picture of
    /// `surface` (undeformed) from `view`, as the drawing fits it.
    fn pixel_of(surface: &Surface, view: &View, p: [f64; 3]) -> (u32, u32) {
        let camera = view.camera().unwrap();
        let fit = ViewFit::new(
            surface
                .faces
                .iter()
                .flat_map(|f| f.nodes().iter())
                .map(|&n| camera.project(surface.points[n])),
        );
        let q = fit.px(camera.project(p));
        (q[0] as u32, q[1] as u32)
    }

    /// How many pixels of the plot box of a [`render_view`] picture `img` of
    /// `surface` from `view` are within 1 of `c` in every channel.
    fn count(img: &image::RgbImage, surface: &Surface, view: &View, c: [u8; 3]) -> usize {
        let camera = view.camera().unwrap();
        let fit = ViewFit::new(surface.points.iter().map(|&p| camera.project(p)));
        let [x0, y0, x1, y1] = fit.clip();
        let mut n = 0;
        for y in y0..y1 {
            for x in x0..x1 {
                let px = img.get_pixel(x as u32, y as u32).0;
                n += usize::from((0..3).all(|k| px[k].abs_diff(c[k]) <= 1));
            }
        }
        n
    }

    /// A cube seen from the corner (1, 1, 1) shows the colours of its three
    /// near faces and never a pixel of its three far faces' colours, though
    /// the far faces are drawn last (hidden faces are removed, not overdrawn).
    #[test]
    fn a_cube_from_a_corner_shows_its_three_near_faces() {
        let dir = scratch("cube");
        let (mut points, mut nodal) = (Vec::new(), Vec::new());
        // Far faces x = 0, y = 0, z = 0: 0, 4, 5; near faces x = 1, y = 1, z = 1: 1, 2, 3.
        let faces = box_faces(
            &mut points,
            &mut nodal,
            [0.0; 3],
            [1.0; 3],
            [0.0, 1.0, 4.0, 2.0, 5.0, 3.0],
        );
        let order = [1, 3, 5, 0, 2, 4].map(|k| faces[k]);
        let surface = Surface {
            points: &points,
            faces: &order,
            values: &nodal,
            displacement: None,
        };
        let view = View::default();
        let toward = view.toward_eye();
        for k in 0..3 {
            assert!((toward[k] - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{toward:?}");
        }
        let path = dir.join("cube.png");
        let labels = ViewLabels {
            title: "cube",
            colorbar: "v",
        };
        let drawn = render_view(&path, &surface, &view, Magnification::Auto, &labels, GO).unwrap();
        assert_eq!(drawn.magnification, 0.0);
        let img = image::open(&path).unwrap().to_rgb8();
        // Every face is seen at the same angle: cos θ = 1/√3.
        let light = FLAT_LIGHT + (1.0 - FLAT_LIGHT) / 3f64.sqrt();
        let colour = |v: f64| shade(png::turbo(v / 5.0), light);
        for v in [1.0, 2.0, 3.0] {
            let n = count(&img, &surface, &view, colour(v));
            assert!(n > 20_000, "near face {v}: {n} pixels");
        }
        for v in [0.0, 4.0, 5.0] {
            assert_eq!(count(&img, &surface, &view, colour(v)), 0, "far face {v}");
        }
        // The middle of the top face (y = 1) is drawn in its colour.
        let (x, y) = pixel_of(&surface, &view, [0.5, 1.0, 0.5]);
        assert_eq!(img.get_pixel(x, y).0, colour(2.0));
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A small block in front of a larger sloping one is drawn over it where
    /// it covers it, though the sloping face's centroid is nearer the eye than
    /// the small block's (a painter's sort by centroid depth would paint the
    /// large face over it, and both face the eye: culling does not help).
    #[test]
    fn a_near_block_is_drawn_over_a_far_one() {
        let dir = scratch("blocks");
        let (mut points, mut nodal) = (Vec::new(), Vec::new());
        let mut faces = box_faces(
            &mut points,
            &mut nodal,
            [1.0, 1.0, 2.5],
            [2.0, 2.0, 3.5],
            [1.0; 6],
        );
        // A ramp: z rises from 0 at x = 0 to 10 at x = 10, for y in [0, 4].
        let ramp = points.len();
        for p in [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 10.0],
            [10.0, 4.0, 10.0],
            [0.0, 4.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 4.0, 0.0],
        ] {
            points.push(p);
            nodal.push(0.0);
        }
        let r = |k: usize| ramp + k;
        faces.extend([
            Face::Quad([r(0), r(1), r(2), r(3)]),
            Face::Quad([r(0), r(3), r(5), r(4)]),
            Face::Quad([r(4), r(5), r(2), r(1)]),
            Face::Triangle([r(0), r(4), r(1)]),
            Face::Triangle([r(3), r(2), r(5)]),
        ]);
        let surface = Surface {
            points: &points,
            faces: &faces,
            values: &nodal,
            displacement: None,
        };
        // Seen from +z: depth is z.
        let view = View {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            up: Axis::Y,
        };
        assert_eq!(view.toward_eye(), [0.0, 0.0, 1.0]);
        let slope_centroid_depth = 5.0;
        let block_front_depth = 3.5;
        assert!(slope_centroid_depth > block_front_depth);
        let path = dir.join("blocks.png");
        let labels = ViewLabels {
            title: "blocks",
            colorbar: "v",
        };
        render_view(&path, &surface, &view, Magnification::Auto, &labels, GO).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        let near = png::turbo(1.0);
        let slope = shade(
            png::turbo(0.0),
            FLAT_LIGHT + (1.0 - FLAT_LIGHT) / 2f64.sqrt(),
        );
        for p in [[1.5, 1.5], [1.2, 1.8], [1.8, 1.2]] {
            let (x, y) = pixel_of(&surface, &view, [p[0], p[1], 3.5]);
            assert_eq!(img.get_pixel(x, y).0, near, "{p:?}");
        }
        for p in [[0.5, 1.5], [6.0, 3.0], [1.5, 3.0]] {
            let (x, y) = pixel_of(&surface, &view, [p[0], p[1], p[0]]);
            assert_eq!(img.get_pixel(x, y).0, slope, "{p:?}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// The colour bar spans the smallest to the largest value at the faces'
    /// nodes (a point on no face does not stretch it): its top is the map's
    /// last colour, its bottom the first, and the face at the largest value is
    /// drawn in the last colour.
    #[test]
    fn the_colour_bar_spans_the_values_on_the_faces() {
        let dir = scratch("bar");
        let (mut points, mut nodal) = (Vec::new(), Vec::new());
        let faces = box_faces(
            &mut points,
            &mut nodal,
            [0.0; 3],
            [2.0, 1.0, 1.0],
            [-3.0, 7.5, 0.0, 1.0, 2.0, 0.5],
        );
        points.push([50.0, 50.0, 50.0]);
        nodal.push(100.0);
        let surface = Surface {
            points: &points,
            faces: &faces,
            values: &nodal,
            displacement: None,
        };
        let view = View {
            azimuth_deg: 90.0,
            elevation_deg: 0.0,
            up: Axis::Y,
        };
        // From +x: the face x = 2 (value 7.5) squarely.
        let toward = view.toward_eye();
        assert!((toward[0] - 1.0).abs() < 1e-15 && toward[2].abs() < 1e-15);
        let path = dir.join("bar.png");
        let labels = ViewLabels {
            title: "bar",
            colorbar: "v",
        };
        let drawn = render_view(&path, &surface, &view, Magnification::Auto, &labels, GO).unwrap();
        assert_eq!((drawn.colour_min, drawn.colour_max), (-3.0, 7.5));
        let img = image::open(&path).unwrap().to_rgb8();
        let camera = view.camera().unwrap();
        let fit = ViewFit::new(points[..24].iter().map(|&p| camera.project(p)));
        let (_, pt, pr, pb) = fit.plot_box();
        let bar = (pr + 55) as u32;
        // The first row under the bar's frame: the second colour of its ramp.
        let rows = f64::from(pb - pt - 1);
        assert_eq!(
            img.get_pixel(bar, pt as u32 + 1).0,
            png::turbo(1.0 - 1.0 / rows)
        );
        assert_eq!(img.get_pixel(bar, (pb - 1) as u32).0, png::turbo(0.0));
        let (x, y) = pixel_of(&surface, &view, [2.0, 0.5, 0.5]);
        assert_eq!(img.get_pixel(x, y).0, png::turbo(1.0));
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Pairs on rings in a tilted plane with a pressure decreasing from the
    /// centre (zero on the outer rings): the plane found is theirs, the
    /// highest colour drawn lies at the centre, and no pixel outside the
    /// projected convex hull (inside the outer ring's circle) is coloured.
    #[test]
    fn a_pressure_map_peaks_at_the_centre_inside_the_hull() {
        let dir = scratch("map");
        let normal = normalized([1.0, 1.0, 1.0]);
        let e1 = normalized([1.0, -1.0, 0.0]);
        let e2 = cross(normal, e1);
        let centre = [3.0, -1.0, 2.0];
        let radius = 2.0;
        let (mut points, mut pressure) = (vec![centre], vec![10.0]);
        for ring in 1..=8 {
            let r = radius * ring as f64 / 8.0;
            for k in 0..6 * ring {
                let a = std::f64::consts::TAU * k as f64 / (6 * ring) as f64;
                let (c, s) = (r * a.cos(), r * a.sin());
                points.push([0, 1, 2].map(|i| centre[i] + c * e1[i] + s * e2[i]));
                pressure.push((10.0 * (1.0 - (r / (0.75 * radius)).powi(2))).max(0.0));
            }
        }
        let path = dir.join("map.png");
        let labels = MapLabels {
            title: "map",
            colorbar: "p",
            axis_unit: "mm",
        };
        let map = PressureMap {
            points: &points,
            pressure: &pressure,
        };
        let plane = render_pressure_map(&path, &map, &labels, GO).unwrap();
        assert!(
            (dot(plane.normal, normal).abs() - 1.0).abs() < 1e-12,
            "{plane:?}"
        );
        for (o, c) in plane.origin.iter().zip(centre) {
            assert!((o - c).abs() < 1e-12, "{o} ≠ {c}");
        }
        assert!(dot(cross(plane.axes[0], plane.axes[1]), plane.normal) > 1.0 - 1e-12);
        let img = image::open(&path).unwrap().to_rgb8();
        let projected: Vec<[f64; 2]> = points.iter().map(|&p| plane.project(p)).collect();
        let layout = Layout::new(&projected);
        let c = layout.tf.px(plane.project(centre));
        let radius_px = radius * layout.tf.scale;
        // Every colour of the map, with the fraction it stands for.
        let mut lut = HashMap::new();
        for k in (0..=1 << 16).rev() {
            let t = k as f64 / f64::from(1 << 16);
            lut.insert(png::turbo(t), t);
        }
        let [x0, y0, x1, y1] = layout.clip();
        let (mut best, mut coloured) = ((0.0, [0.0; 2]), 0);
        for y in y0..y1 {
            for x in x0..x1 {
                let Some(&t) = lut.get(&img.get_pixel(x as u32, y as u32).0) else {
                    continue;
                };
                coloured += 1;
                let at = [x as f64 + 0.5, y as f64 + 0.5];
                let d = (at[0] - c[0]).hypot(at[1] - c[1]);
                assert!(
                    d <= radius_px + 2.0,
                    "coloured pixel {at:?} outside the hull"
                );
                if t > best.0 {
                    best = (t, at);
                }
            }
        }
        assert!(coloured > 100_000, "{coloured}");
        let (t, at) = best;
        assert!(t > 0.99, "{t}");
        let d = (at[0] - c[0]).hypot(at[1] - c[1]);
        assert!(d < radius_px / 8.0, "highest colour {d} px from the centre");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// The plane of points on a plane normal to a model axis has that axis as
    /// its normal and the other two as its axes, both positive: x and y for a
    /// plane normal to z, x and z for y, y and z for x.
    #[test]
    fn an_axis_plane_is_drawn_on_positive_axes() {
        let grid = |k: usize| -> Vec<[f64; 3]> {
            (0..9)
                .map(|i| {
                    let mut p = [2.0; 3];
                    let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                    p[a] = (i % 3) as f64;
                    p[b] = (i / 3) as f64 + 0.1 * (i % 3) as f64;
                    p
                })
                .collect()
        };
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        let z = [0.0, 0.0, 1.0];
        for (k, axes, names) in [
            (2, [x, y], ["x", "y"]),
            (1, [x, z], ["x", "z"]),
            (0, [y, z], ["y", "z"]),
        ] {
            let plane = InterfacePlane::through(&grid(k)).unwrap();
            assert!((plane.normal[k].abs() - 1.0).abs() < 1e-12, "{plane:?}");
            for (a, e) in plane.axes.iter().zip(axes) {
                assert!((dot(*a, e) - 1.0).abs() < 1e-12, "{plane:?}");
            }
            assert_eq!([plane.axis_name(0), plane.axis_name(1)], names);
        }
    }

    /// The same input gives the same bytes, for both pictures.
    #[test]
    fn identical_inputs_give_identical_bytes() {
        let dir = scratch("same");
        let (mut points, mut nodal) = (Vec::new(), Vec::new());
        let faces = box_faces(
            &mut points,
            &mut nodal,
            [0.0; 3],
            [3.0, 1.0, 2.0],
            [0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
        );
        let u: Vec<[f64; 3]> = points.iter().map(|p| [1e-3 * p[1], 0.0, 0.0]).collect();
        let surface = Surface {
            points: &points,
            faces: &faces,
            values: &nodal,
            displacement: Some(&u),
        };
        let labels = ViewLabels {
            title: "same",
            colorbar: "v",
        };
        let pressure: Vec<f64> = points.iter().map(|p| p[0] * p[2]).collect();
        let map_labels = MapLabels {
            title: "same",
            colorbar: "p",
            axis_unit: "m",
        };
        let mut bytes = Vec::new();
        for k in 0..2 {
            let view = dir.join(format!("view{k}.png"));
            let drawn = render_view(
                &view,
                &surface,
                &View::isometric(Axis::Z),
                Magnification::Auto,
                &labels,
                GO,
            )
            .unwrap();
            assert_eq!(drawn.magnification, 100.0);
            let map = dir.join(format!("map{k}.png"));
            let flat: Vec<[f64; 3]> = points.iter().map(|p| [p[0], 0.0, p[2]]).collect();
            let pm = PressureMap {
                points: &flat,
                pressure: &pressure,
            };
            render_pressure_map(&map, &pm, &map_labels, GO).unwrap();
            bytes.push((std::fs::read(view).unwrap(), std::fs::read(map).unwrap()));
        }
        assert!(bytes[0] == bytes[1]);
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Boundary faces: two hexahedra sharing a face have the ten others, a
    /// tetrahedron its four, a wedge its five, each facing out of its cell
    /// (Newell normal · (face centre − cell centre) > 0); vertices add none.
    #[test]
    fn boundary_faces_face_outwards() {
        let mut points: Vec<[f64; 3]> = Vec::new();
        for z in [0.0, 1.0] {
            for [x, y] in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
                points.push([x, y, z]);
            }
        }
        for z in [0.0, 1.0] {
            points.push([2.0, 0.0, z]);
            points.push([2.0, 1.0, z]);
        }
        // Hexahedra [0,1]³ and [1,2]×[0,1]²; a tetrahedron and a wedge apart.
        let hexes = vec![0, 1, 2, 3, 4, 5, 6, 7, 1, 8, 9, 2, 5, 10, 11, 6];
        let tet_at = points.len();
        points.extend([
            [5.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [5.0, 1.0, 0.0],
            [5.0, 0.0, 1.0],
        ]);
        let wedge_at = points.len();
        points.extend([
            [8.0, 0.0, 0.0],
            [8.0, 1.0, 0.0],
            [9.0, 0.0, 0.0],
            [8.0, 0.0, 1.0],
            [8.0, 1.0, 1.0],
            [9.0, 0.0, 1.0],
        ]);
        let mut connectivity = hexes;
        connectivity.extend((0..4).map(|k| tet_at + k));
        connectivity.extend((0..6).map(|k| wedge_at + k));
        connectivity.push(0);
        let offsets = [8, 16, 20, 26, 27];
        let kinds = [
            CellKind::Hexahedron,
            CellKind::Hexahedron,
            CellKind::Tetra,
            CellKind::Wedge,
            CellKind::Vertex,
        ];
        let what = Path::new("cells");
        let faces = boundary_faces(what, points.len(), &connectivity, &offsets, &kinds).unwrap();
        assert_eq!(faces.len(), 10 + 4 + 5);
        let centre = |nodes: &[usize]| {
            [0, 1, 2].map(|k| nodes.iter().map(|&n| points[n][k]).sum::<f64>() / nodes.len() as f64)
        };
        // The cell a face belongs to: by its smallest node.
        let cell_centre = |face: &Face| {
            let n = face.nodes()[0];
            if n >= wedge_at {
                centre(&connectivity[20..26])
            } else if n >= tet_at {
                centre(&connectivity[16..20])
            } else {
                let x = face.nodes().iter().map(|&k| points[k][0]).sum::<f64>();
                if x / (face.nodes().len() as f64) < 1.0 {
                    centre(&connectivity[0..8])
                } else {
                    centre(&connectivity[8..16])
                }
            }
        };
        for f in &faces {
            let n = f.nodes();
            let mut normal = [0.0; 3];
            for k in 0..n.len() {
                let (a, b) = (points[n[k]], points[n[(k + 1) % n.len()]]);
                normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
                normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
                normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
            }
            let (fc, cc) = (centre(n), cell_centre(f));
            let out = [0, 1, 2].map(|k| fc[k] - cc[k]);
            assert!(dot(normal, out) > 0.0, "{f:?} faces inwards");
        }
        // The shared face x = 1 is not a boundary face.
        assert!(
            !faces
                .iter()
                .any(|f| f.nodes().iter().all(|&n| points[n][0] == 1.0))
        );
        let bad = boundary_faces(what, points.len(), &connectivity, &[8, 16, 20, 26], &kinds);
        assert!(matches!(bad, Err(Error::Output { .. })));
    }

    /// Bad input is an output error naming the file, and nothing is written.
    #[test]
    fn bad_input_is_an_error() {
        let dir = scratch("bad");
        let path = dir.join("bad.png");
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let ok = Surface {
            points: &points,
            faces: &[Face::Triangle([0, 1, 2])],
            values: &[0.0, 1.0, 2.0],
            displacement: None,
        };
        let labels = ViewLabels {
            title: "t",
            colorbar: "v",
        };
        let view = View::default();
        let u = [[0.0; 3]; 2];
        let cases: Vec<(Surface, View, Magnification)> = vec![
            (Surface { faces: &[], ..ok }, view, Magnification::Auto),
            (
                Surface {
                    faces: &[Face::Triangle([0, 1, 3])],
                    ..ok
                },
                view,
                Magnification::Auto,
            ),
            (
                Surface {
                    values: &[0.0, 1.0],
                    ..ok
                },
                view,
                Magnification::Auto,
            ),
            (
                Surface {
                    values: &[0.0, f64::NAN, 1.0],
                    ..ok
                },
                view,
                Magnification::Auto,
            ),
            (
                Surface {
                    displacement: Some(&u),
                    ..ok
                },
                view,
                Magnification::Auto,
            ),
            (ok, view, Magnification::Factor(-1.0)),
            (
                ok,
                View {
                    elevation_deg: 91.0,
                    ..view
                },
                Magnification::Auto,
            ),
        ];
        for (k, (surface, view, m)) in cases.into_iter().enumerate() {
            match render_view(&path, &surface, &view, m, &labels, GO) {
                Err(Error::Output { path: p, .. }) => assert_eq!(p, path, "{k}"),
                other => panic!("case {k}: expected an output error, got {other:?}"),
            }
        }
        let map_labels = MapLabels {
            title: "t",
            colorbar: "p",
            axis_unit: "m",
        };
        let line = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]];
        for (pts, p) in [
            (&line[..], &[1.0, 2.0, 3.0][..]),
            (&points[..2], &[1.0, 2.0][..]),
            (&points[..], &[1.0, 2.0][..]),
        ] {
            let map = PressureMap {
                points: pts,
                pressure: p,
            };
            assert!(matches!(
                render_pressure_map(&path, &map, &map_labels, GO),
                Err(Error::Output { .. })
            ));
        }
        assert!(std::fs::read_dir(&dir).unwrap().next().is_none());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
