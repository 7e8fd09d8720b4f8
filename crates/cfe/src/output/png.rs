//! PNG pictures of a field on the parts, made for reports: a smoothly shaded colour
//! map (or isolines) with part outlines, equal axis scaling, axes in the model's
//! length unit, a title and a colour bar. Drawn with plotters on an in-memory RGB
//! buffer (font bundled, no system libraries) and encoded to PNG.
//!
//! The field is rasterised per pixel (linear interpolation inside each triangle),
//! so the cost is O(triangles + pixels): a picture of a million-element model costs
//! little more than one of a thousand.
//!
//! Every text a picture shows that comes from the problem (the title, units,
//! interface names in a chart's legend) is first bounded by [`label_text`]: at
//! most [`MAX_LABEL_CHARS`] characters, control characters dropped, so drawing
//! it takes time linear in that bound whatever the input. A long drawing asks
//! its caller's `proceed` check between stages and every [`CHUNK`] triangles,
//! edges or markers, so a stop request ends it promptly with no file written.

use super::write_atomic;
use crate::error::{Error, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::borrow::Cow;
use std::path::Path;
use std::sync::Once;

/// The most characters of a title or label drawn in a picture; a longer one is
/// cut there and ends with `…`.
pub const MAX_LABEL_CHARS: usize = 200;

/// Triangles, edges or markers drawn between two `proceed` checks.
pub const CHUNK: usize = 8192;

/// `text` as a picture shows it: control characters (line breaks, tabs, NUL …)
/// dropped and, beyond [`MAX_LABEL_CHARS`] characters, cut with `…`. Linear in
/// the characters kept (and in the control characters skipped before them).
pub fn label_text(text: &str) -> Cow<'_, str> {
    let plain = !text.chars().take(MAX_LABEL_CHARS + 1).any(char::is_control);
    if plain && text.chars().nth(MAX_LABEL_CHARS).is_none() {
        return Cow::Borrowed(text);
    }
    let mut kept = text.chars().filter(|c| !c.is_control());
    let mut out: String = kept.by_ref().take(MAX_LABEL_CHARS).collect();
    if kept.next().is_some() {
        out.pop();
        out.push('…');
    }
    Cow::Owned(out)
}

/// Whether a drawing may go on: `Err` (e.g. [`Error::Interrupted`] once a stop
/// signal came) ends it and is returned by the drawing.
pub type Proceed<'a> = &'a (dyn Fn() -> Result<()> + Sync);

/// What to draw: node coordinates (already deformed if the caller wants a deformed
/// picture) and triangles as node-index triples.
pub struct PlotMesh<'a> {
    /// Node coordinates.
    pub points: &'a [[f64; 2]],
    /// Triangles (indices into `points`).
    pub triangles: &'a [[usize; 3]],
    /// The outline edges ([`outline_edges`] of the triangles), if already known.
    pub outline: Option<&'a [[usize; 2]]>,
}

/// Labels of one picture.
pub struct PlotLabels<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// Colour-bar label, e.g. `σyy [MPa]`.
    pub colorbar: &'a str,
    /// Length unit for the axes, e.g. `mm` (axes read `x [mm]`, `y [mm]`).
    pub axis_unit: &'a str,
}

/// A coupling pair marker: a black circle, filled when bonded, hollow when open;
/// a red square (filled when bonded, hollow when open) when the pair breaks its
/// law (a pair settled against the law to end a cycle, or a lagged `implex` state);
/// a slipping pair (Coulomb) is a filled blue circle.
pub struct PairMarker {
    /// Position.
    pub at: [f64; 2],
    /// Closed (filled: bonded or slipping) or open (hollow).
    pub bonded: bool,
    /// Slipping (Coulomb): drawn blue.
    pub slip: bool,
    /// The pair breaks its law (drawn as a red square).
    pub violates: bool,
}

/// The width of every picture in pixels.
pub(crate) const WIDTH: u32 = 1600;
/// The family name the bundled font is registered under.
pub(crate) const FONT: &str = "sans-serif";
static FONT_ONCE: Once = Once::new();

/// Registers the bundled font with plotters (once).
pub(crate) fn register_font() {
    FONT_ONCE.call_once(|| {
        // The bundled DejaVu Sans (see assets/fonts/DejaVuSans-LICENSE.txt).
        let bytes: &'static [u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, bytes);
    });
}

/// Smoothly shaded colour map of `nodal` (one value per point) with part outlines,
/// pair markers, axes, title and colour bar. `proceed` is asked between stages
/// and every [`CHUNK`] items; its error ends the drawing and nothing is written.
pub fn render_field(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    markers: &[PairMarker],
    labels: &PlotLabels,
    proceed: Proceed<'_>,
) -> Result<()> {
    render(path, mesh, nodal, markers, labels, Style::Field, proceed)
}

/// Isolines of `nodal` at `levels` evenly spaced values strictly inside its range,
/// each coloured by its level against the colour bar, over a light-grey fill of the
/// parts, with part outlines and pair markers. `proceed` as for [`render_field`].
pub fn render_isolines(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    levels: usize,
    markers: &[PairMarker],
    labels: &PlotLabels,
    proceed: Proceed<'_>,
) -> Result<()> {
    render(
        path,
        mesh,
        nodal,
        markers,
        labels,
        Style::Isolines(levels.max(1)),
        proceed,
    )
}

#[derive(Clone, Copy)]
enum Style {
    Field,
    Isolines(usize),
}

/// The "turbo" colour map (Mikhailov, Google 2019; polynomial approximation) at
/// t ∈ [0, 1]: dark blue → cyan → green → yellow → red.
pub fn turbo(t: f64) -> [u8; 3] {
    let x = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let poly = |c: [f64; 6]| c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
    let r = poly([
        0.13572138,
        4.61539260,
        -42.66032258,
        132.13108234,
        -152.94239396,
        59.28637943,
    ]);
    let g = poly([
        0.09140261,
        2.19418839,
        4.84296658,
        -14.18503333,
        4.27729857,
        2.82956604,
    ]);
    let b = poly([
        0.10667330,
        12.64194608,
        -60.58204836,
        110.36276771,
        -89.90310912,
        27.34824973,
    ]);
    [r, g, b].map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// Maps model coordinates to pixels (equal scale in x and y, y up).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Transform {
    x0: f64,
    y1: f64,
    /// Pixels per model unit.
    pub(crate) scale: f64,
    left: f64,
    top: f64,
}

impl Transform {
    /// The pixel position of model point `p`.
    pub(crate) fn px(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.left + (p[0] - self.x0) * self.scale,
            self.top + (self.y1 - p[1]) * self.scale,
        ]
    }
}

/// Calls `f(x, y, [l₀, l₁, l₂])` for every pixel of `clip` = [x0, y0, x1, y1)
/// whose centre (x + ½, y + ½) lies in the triangle `p` (pixel coordinates, to
/// −1e-9 in the barycentric coordinates lᵢ of the centre); nothing for a
/// triangle of (near) zero area. The one pixel-coverage rule of the plane
/// pictures ([`rasterize`]) and the depth-buffered solid views (`view3d`).
pub fn triangle_pixels(
    p: [[f64; 2]; 3],
    clip: [usize; 4],
    mut f: impl FnMut(usize, usize, [f64; 3]),
) {
    let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    if det.abs() <= 1e-12 {
        return;
    }
    let lo = |k: usize| p.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min);
    let hi = |k: usize| p.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max);
    let ix0 = (lo(0).floor().max(clip[0] as f64)) as usize;
    let iy0 = (lo(1).floor().max(clip[1] as f64)) as usize;
    let ix1 = (hi(0).ceil().min(clip[2] as f64)).max(ix0 as f64) as usize;
    let iy1 = (hi(1).ceil().min(clip[3] as f64)).max(iy0 as f64) as usize;
    for y in iy0..iy1 {
        let cy = y as f64 + 0.5;
        for x in ix0..ix1 {
            let cx = x as f64 + 0.5;
            let l1 =
                ((cx - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (cy - p[0][1])) / det;
            let l2 =
                ((p[1][0] - p[0][0]) * (cy - p[0][1]) - (cx - p[0][0]) * (p[1][1] - p[0][1])) / det;
            let l0 = 1.0 - l1 - l2;
            const E: f64 = -1e-9;
            if l0 >= E && l1 >= E && l2 >= E {
                f(x, y, [l0, l1, l2]);
            }
        }
    }
}

/// Fills the triangles into an RGB buffer of `width` × `height` pixels, clipped to
/// `clip` = [x0, y0, x1, y1) in pixels, colouring each covered pixel centre by the
/// linear interpolation of the vertex values mapped through `colour`. A triangle
/// smaller than a pixel still paints the pixel of its centroid.
pub fn rasterize(
    buf: &mut [u8],
    width: usize,
    clip: [usize; 4],
    tris: impl Iterator<Item = ([[f64; 2]; 3], [f64; 3])>,
    colour: impl Fn(f64) -> [u8; 3],
) {
    let mut put = |x: usize, y: usize, c: [u8; 3]| {
        let i = 3 * (y * width + x);
        buf[i..i + 3].copy_from_slice(&c);
    };
    for (p, v) in tris {
        let mut painted = false;
        triangle_pixels(p, clip, |x, y, [l0, l1, l2]| {
            put(x, y, colour(l0 * v[0] + l1 * v[1] + l2 * v[2]));
            painted = true;
        });
        if !painted {
            let c = [
                (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                (p[0][1] + p[1][1] + p[2][1]) / 3.0,
            ];
            if c[0] >= clip[0] as f64
                && c[1] >= clip[1] as f64
                && c[0] < clip[2] as f64
                && c[1] < clip[3] as f64
            {
                put(
                    c[0] as usize,
                    c[1] as usize,
                    colour((v[0] + v[1] + v[2]) / 3.0),
                );
            }
        }
    }
}

/// The segment where the linear field with vertex values `v` over triangle `p`
/// crosses `level`, if it does. A vertex exactly at the level counts as above it,
/// so every crossing gives exactly two points or none.
pub fn isoline_segment(p: &[[f64; 2]; 3], v: &[f64; 3], level: f64) -> Option<[[f64; 2]; 2]> {
    let above = v.map(|x| x >= level);
    let mut pts = [[0.0; 2]; 2];
    let mut n = 0;
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        if above[a] != above[b] {
            let t = (level - v[a]) / (v[b] - v[a]);
            pts[n] = [
                p[a][0] + t * (p[b][0] - p[a][0]),
                p[a][1] + t * (p[b][1] - p[a][1]),
            ];
            n += 1;
        }
    }
    (n == 2).then_some(pts)
}

/// Edges used by exactly one triangle (the outlines of the parts), sorted
/// ([`crate::mesh::edges_used_once`]: O(triangles + nodes)).
pub fn outline_edges(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    crate::mesh::edges_used_once(|| {
        triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| ([t[k], t[(k + 1) % 3]], ())))
    })
    .into_iter()
    .map(|([a, b], ())| [a.min(b), a.max(b)])
    .collect()
}

fn validate(path: &Path, mesh: &PlotMesh, nodal: &[f64]) -> Result<()> {
    let bad = |m: String| Err(Error::output(path, m));
    if mesh.triangles.is_empty() || mesh.points.is_empty() {
        return bad("nothing to draw: the mesh is empty".into());
    }
    if nodal.len() != mesh.points.len() {
        return bad(format!(
            "{} nodal values for {} points",
            nodal.len(),
            mesh.points.len()
        ));
    }
    if let Some(t) = mesh
        .triangles
        .iter()
        .find(|t| t.iter().any(|&n| n >= mesh.points.len()))
    {
        return bad(format!(
            "triangle {t:?} refers to a point beyond the {} given",
            mesh.points.len()
        ));
    }
    if mesh
        .points
        .iter()
        .flatten()
        .chain(nodal)
        .any(|v| !v.is_finite())
    {
        return bad("a coordinate or value is not finite".into());
    }
    Ok(())
}

pub(crate) fn nice_ticks_label(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-2 {
        format!("{v:.2e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The drawing area over the picture's RGB buffer.
pub(crate) type Area<'b> = DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>;

/// Margins around the plot box in pixels (the colour bar lives in the right one).
const LEFT: u32 = 110;
const RIGHT: u32 = 230;
const TOP: u32 = 70;
const BOTTOM: u32 = 80;

/// The picture's geometry: the equal-scale transform from model to pixels, the
/// visible model window and the size of the plot box.
pub(crate) struct Layout {
    /// Model → pixel transform.
    pub(crate) tf: Transform,
    /// Visible model window (after widening the shorter range for equal scaling).
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    /// Plot box width and height in pixels.
    plot_w: u32,
    plot_h: u32,
    /// Picture height in pixels (the width is [`WIDTH`]).
    pub(crate) height: u32,
}

impl Layout {
    /// The layout for the model bounds of `points` with a small pad: plot area,
    /// colour bar strip on the right, equal scaling.
    pub(crate) fn new(points: &[[f64; 2]]) -> Layout {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-300);
        let pad = 0.03 * span;
        let (x0, x1, y0, y1) = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad);
        let plot_w = WIDTH - LEFT - RIGHT;
        let plot_h = ((plot_w as f64) * (y1 - y0) / (x1 - x0))
            .round()
            .clamp(360.0, 1000.0) as u32;
        let height = plot_h + TOP + BOTTOM;
        // Widen the shorter range so that one unit is the same number of pixels both ways.
        let scale = (plot_w as f64 / (x1 - x0)).min(plot_h as f64 / (y1 - y0));
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (hw, hh) = (0.5 * plot_w as f64 / scale, 0.5 * plot_h as f64 / scale);
        let (x0, x1, y0, y1) = (cx - hw, cx + hw, cy - hh, cy + hh);
        let tf = Transform {
            x0,
            y1,
            scale,
            left: LEFT as f64,
            top: TOP as f64,
        };
        Layout {
            tf,
            x0,
            x1,
            y0,
            y1,
            plot_w,
            plot_h,
            height,
        }
    }

    /// The plot box in pixels: (left, top, right, bottom).
    pub(crate) fn plot_box(&self) -> (i32, i32, i32, i32) {
        (
            LEFT as i32,
            TOP as i32,
            (LEFT + self.plot_w) as i32,
            (TOP + self.plot_h) as i32,
        )
    }

    /// The plot box as a clip rectangle [x0, y0, x1, y1) in pixels.
    pub(crate) fn clip(&self) -> [usize; 4] {
        [
            LEFT as usize,
            TOP as usize,
            (LEFT + self.plot_w) as usize,
            (TOP + self.plot_h) as usize,
        ]
    }

    /// Whether pixel position `p` lies in the plot box (edges included).
    pub(crate) fn inside(&self, p: [f64; 2]) -> bool {
        let clip = self.clip();
        p[0] >= clip[0] as f64
            && p[0] <= clip[2] as f64
            && p[1] >= clip[1] as f64
            && p[1] <= clip[3] as f64
    }
}

/// The colour range of a picture and the true extremes of the data.
pub(crate) struct ColourRange {
    /// The value coloured by the map's first colour.
    pub(crate) vmin: f64,
    /// The value coloured by the map's last colour.
    pub(crate) vmax: f64,
    /// The smallest value of the data.
    pub(crate) data_min: f64,
    /// The largest value of the data.
    pub(crate) data_max: f64,
}

impl ColourRange {
    /// For a field, the 0.5–99.5 % quantiles of the nodal values, so that a stress
    /// singularity at a corner does not wash out the rest (the true extremes are
    /// printed beside the colour bar when they fall outside); for isolines, the
    /// full range.
    fn new(nodal: &[f64], style: Style) -> ColourRange {
        let (data_min, data_max) = nodal
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let (vmin, vmax) = match style {
            Style::Field => robust_range(nodal),
            Style::Isolines(_) => (data_min, data_max),
        };
        ColourRange {
            vmin,
            vmax,
            data_min,
            data_max,
        }
    }

    /// The full range of `values`: from their smallest to their largest.
    pub(crate) fn full(values: &[f64]) -> ColourRange {
        ColourRange::new(values, Style::Isolines(1))
    }

    /// `v` as a fraction of the colour range (1 when the range is empty).
    pub(crate) fn norm(&self, v: f64) -> f64 {
        let range = if self.vmax > self.vmin {
            self.vmax - self.vmin
        } else {
            1.0
        };
        (v - self.vmin) / range
    }
}

/// The pixel nearest to `p`.
pub(crate) fn ip(p: [f64; 2]) -> (i32, i32) {
    (p[0].round() as i32, p[1].round() as i32)
}

/// A closure turning a plotters error into the crate's output error for `path`.
pub(crate) fn draw_err(path: &Path) -> impl Fn(&dyn std::fmt::Display) -> Error + '_ {
    move |e: &dyn std::fmt::Display| Error::output(path, e)
}

fn render(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    markers: &[PairMarker],
    labels: &PlotLabels,
    style: Style,
    proceed: Proceed<'_>,
) -> Result<()> {
    validate(path, mesh, nodal)?;
    proceed()?;
    register_font();
    let (title, colorbar, axis_unit) = (
        label_text(labels.title),
        label_text(labels.colorbar),
        label_text(labels.axis_unit),
    );
    let labels = &PlotLabels {
        title: &title,
        colorbar: &colorbar,
        axis_unit: &axis_unit,
    };
    let err = draw_err(path);
    let layout = Layout::new(mesh.points);
    let range = ColourRange::new(nodal, style);

    let mut buf = vec![255u8; (WIDTH * layout.height * 3) as usize];
    // 1. Frame, axes, title, colour bar.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, layout.height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        draw_frame_and_axes(path, &root, &layout, labels, ["x", "y"])?;
        draw_colour_bar(path, &root, layout.plot_box(), &range, labels.colorbar)?;
        root.present().map_err(|e| err(&e))?;
    }

    // 2. The field (or the grey parts under the isolines), CHUNK triangles at a
    // time (each triangle is painted on its own: the same pixels either way).
    let tf = layout.tf;
    let clip = layout.clip();
    for chunk in mesh.triangles.chunks(CHUNK) {
        proceed()?;
        let px_tris = chunk
            .iter()
            .map(|t| (t.map(|n| tf.px(mesh.points[n])), t.map(|n| nodal[n])));
        match style {
            Style::Field => rasterize(&mut buf, WIDTH as usize, clip, px_tris, |v| {
                turbo(range.norm(v))
            }),
            Style::Isolines(_) => {
                rasterize(&mut buf, WIDTH as usize, clip, px_tris, |_| [232, 232, 232])
            }
        }
    }

    // 3. Isolines, outlines, markers.
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, layout.height)).into_drawing_area();
        if let Style::Isolines(levels) = style
            && range.vmax > range.vmin
        {
            draw_isolines(path, &root, &layout, mesh, nodal, &range, levels, proceed)?;
        }
        draw_outline(path, &root, &layout, mesh, proceed)?;
        draw_markers(path, &root, &layout, markers, proceed)?;
        root.present().map_err(|e| err(&e))?;
    }

    // 4. Encode and write atomically.
    proceed()?;
    write_rgb(path, &buf, WIDTH, layout.height)
}

/// `title` and a font size (28 px, or smaller down to 16) at which it fits in
/// `room` pixels; shortened with an ellipsis if it does not fit even at 16 (the
/// longest prefix that fits, found by bisection: O(log n) measurements of at
/// most n characters, n ≤ [`MAX_LABEL_CHARS`] after [`label_text`]).
pub(crate) fn fit_title(root: &Area, title: &str, room: u32) -> (String, f64) {
    let width = |t: &str, size: f64| {
        root.estimate_text_size(t, &TextStyle::from((FONT, size).into_font()))
            .map_or(0, |(w, _)| w)
    };
    let mut size = 28.0;
    while size > 16.0 && width(title, size) > room {
        size -= 2.0;
    }
    if width(title, size) <= room {
        return (title.to_string(), size);
    }
    // Byte offsets of the character boundaries: prefix k is title[..cuts[k]].
    let cuts: Vec<usize> = title
        .char_indices()
        .map(|(i, _)| i)
        .chain([title.len()])
        .collect();
    let shortened = |k: usize| format!("{}…", title[..cuts[k]].trim_end());
    // The longest k in [1, n) whose shortened prefix fits (1 if none does).
    let (mut lo, mut hi) = (1, cuts.len() - 1);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if width(&shortened(mid), size) <= room {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (shortened(lo), size)
}

/// The title, the frame of the plot box, the axis ticks (about 8 along x,
/// matching spacing along y) and the axis labels (`axes`' names, e.g. `x` and
/// `y`, with the unit). Axes are drawn in pixels around the plot box, with the
/// equal-scale transform.
pub(crate) fn draw_frame_and_axes(
    path: &Path,
    root: &Area,
    layout: &Layout,
    labels: &PlotLabels,
    axes: [&str; 2],
) -> Result<()> {
    let err = draw_err(path);
    let text = |size: f64| TextStyle::from((FONT, size).into_font()).color(&BLACK);
    let Layout {
        tf, x0, x1, y0, y1, ..
    } = *layout;
    let (pl, pt, pr, pb) = layout.plot_box();
    // The title ends before the colour bar's label (which starts at pr + 30): a
    // long one is set smaller, down to 16 px, then shortened with an ellipsis.
    let room = (pr + 20 - LEFT as i32).max(50) as u32;
    let (title, size) = fit_title(root, labels.title, room);
    root.draw(&Text::new(title, (LEFT as i32, 22), text(size)))
        .map_err(|e| err(&e))?;
    root.draw(&Rectangle::new(
        [(pl - 1, pt - 1), (pr, pb)],
        BLACK.stroke_width(1),
    ))
    .map_err(|e| err(&e))?;
    let step = nice_step((x1 - x0) / 8.0);
    let tick_font = text(18.0);
    let mut t = (x0 / step).ceil() * step;
    while t <= x1 {
        let px = tf.px([t, y0])[0].round() as i32;
        root.draw(&PathElement::new(vec![(px, pb), (px, pb + 6)], BLACK))
            .map_err(|e| err(&e))?;
        let label = nice_ticks_label(t);
        let w = 5 * label.len() as i32;
        root.draw(&Text::new(label, (px - w, pb + 10), tick_font.clone()))
            .map_err(|e| err(&e))?;
        t += step;
    }
    let mut t = (y0 / step).ceil() * step;
    while t <= y1 {
        let py = tf.px([x0, t])[1].round() as i32;
        root.draw(&PathElement::new(vec![(pl - 6, py), (pl, py)], BLACK))
            .map_err(|e| err(&e))?;
        let label = nice_ticks_label(t);
        let w = 10 * label.len() as i32;
        root.draw(&Text::new(label, (pl - 12 - w, py - 9), tick_font.clone()))
            .map_err(|e| err(&e))?;
        t += step;
    }
    root.draw(&Text::new(
        format!("{} [{}]", axes[0], labels.axis_unit),
        (LEFT as i32 + layout.plot_w as i32 / 2 - 30, pb + 40),
        text(22.0),
    ))
    .map_err(|e| err(&e))?;
    root.draw(&Text::new(
        format!("{} [{}]", axes[1], labels.axis_unit),
        (12, pt + layout.plot_h as i32 / 2 + 30),
        text(22.0).transform(FontTransform::Rotate270),
    ))
    .map_err(|e| err(&e))?;
    Ok(())
}

/// The colour bar right of the plot box `plot_box` (left, top, right, bottom
/// in pixels) with six ticks, its label above it and the true extremes when
/// they fall outside the colour range.
pub(crate) fn draw_colour_bar(
    path: &Path,
    root: &Area,
    plot_box: (i32, i32, i32, i32),
    range: &ColourRange,
    label: &str,
) -> Result<()> {
    let err = draw_err(path);
    let text = |size: f64| TextStyle::from((FONT, size).into_font()).color(&BLACK);
    let tick_font = text(18.0);
    let ColourRange {
        vmin,
        vmax,
        data_min,
        data_max,
    } = *range;
    let (_, pt, pr, pb) = plot_box;
    let (bl, br) = (pr + 40, pr + 70);
    let n = (pb - pt).max(1);
    for k in 0..n {
        let c = turbo(1.0 - k as f64 / (n - 1).max(1) as f64);
        root.draw(&Rectangle::new(
            [(bl, pt + k), (br, pt + k + 1)],
            RGBColor(c[0], c[1], c[2]).filled(),
        ))
        .map_err(|e| err(&e))?;
    }
    root.draw(&Rectangle::new([(bl, pt), (br, pb)], BLACK.stroke_width(1)))
        .map_err(|e| err(&e))?;
    for k in 0..=5 {
        let f = k as f64 / 5.0;
        let v = vmin + f * (vmax - vmin);
        let py = pb - (f * (pb - pt) as f64).round() as i32;
        root.draw(&PathElement::new(vec![(br, py), (br + 6, py)], BLACK))
            .map_err(|e| err(&e))?;
        let label = format_value(if vmax > vmin { v } else { vmin }, vmax - vmin);
        root.draw(&Text::new(label, (br + 10, py - 9), tick_font.clone()))
            .map_err(|e| err(&e))?;
    }
    root.draw(&Text::new(
        label.to_string(),
        (bl - 10, pt - 52),
        text(22.0),
    ))
    .map_err(|e| err(&e))?;
    if data_max > vmax {
        let label = format!("max {}", format_value(data_max, vmax - vmin));
        root.draw(&Text::new(label, (bl - 10, pt - 26), text(16.0)))
            .map_err(|e| err(&e))?;
    }
    if data_min < vmin {
        let label = format!("min {}", format_value(data_min, vmax - vmin));
        root.draw(&Text::new(label, (bl - 10, pb + 10), text(16.0)))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// `levels` isolines evenly spaced strictly inside the colour range, each
/// coloured by its level; segments leaving the plot box are skipped.
#[allow(clippy::too_many_arguments)]
fn draw_isolines(
    path: &Path,
    root: &Area,
    layout: &Layout,
    mesh: &PlotMesh,
    nodal: &[f64],
    range: &ColourRange,
    levels: usize,
    proceed: Proceed<'_>,
) -> Result<()> {
    let err = draw_err(path);
    let (vmin, vmax) = (range.vmin, range.vmax);
    let values: Vec<f64> = (1..=levels)
        .map(|k| vmin + (vmax - vmin) * k as f64 / (levels + 1) as f64)
        .collect();
    // One pass over the triangles finds every level's segments (a level crosses
    // a triangle when its smallest vertex value is below it and its largest is
    // not, as `isoline_segment` counts a vertex at the level as above it); the
    // levels are then drawn one after another, as one pass per level would.
    let mut segments: Vec<Vec<[[f64; 2]; 2]>> = vec![Vec::new(); levels];
    for (i, t) in mesh.triangles.iter().enumerate() {
        if i % CHUNK == 0 {
            proceed()?;
        }
        let v = t.map(|n| nodal[n]);
        let lo = v[0].min(v[1]).min(v[2]);
        let hi = v[0].max(v[1]).max(v[2]);
        let first = values.partition_point(|&l| l <= lo);
        if first == levels || values[first] > hi {
            continue;
        }
        let p = t.map(|n| layout.tf.px(mesh.points[n]));
        for (k, &level) in values.iter().enumerate().skip(first) {
            if level > hi {
                break;
            }
            if let Some([a, b]) = isoline_segment(&p, &v, level)
                && layout.inside(a)
                && layout.inside(b)
            {
                segments[k].push([a, b]);
            }
        }
    }
    for (&level, segments) in values.iter().zip(&segments) {
        let c = turbo(range.norm(level));
        let colour = RGBColor(c[0], c[1], c[2]).stroke_width(2);
        for (i, &[a, b]) in segments.iter().enumerate() {
            if i % CHUNK == 0 {
                proceed()?;
            }
            root.draw(&PathElement::new(vec![ip(a), ip(b)], colour))
                .map_err(|e| err(&e))?;
        }
    }
    Ok(())
}

/// The part outlines (the given ones, or computed from the triangles).
pub(crate) fn draw_outline(
    path: &Path,
    root: &Area,
    layout: &Layout,
    mesh: &PlotMesh,
    proceed: Proceed<'_>,
) -> Result<()> {
    let err = draw_err(path);
    let computed;
    let outline = match mesh.outline {
        Some(o) => o,
        None => {
            computed = outline_edges(mesh.triangles);
            &computed
        }
    };
    for (i, &[a, b]) in outline.iter().enumerate() {
        if i % CHUNK == 0 {
            proceed()?;
        }
        let (pa, pb) = (layout.tf.px(mesh.points[a]), layout.tf.px(mesh.points[b]));
        if layout.inside(pa) && layout.inside(pb) {
            root.draw(&PathElement::new(
                vec![ip(pa), ip(pb)],
                BLACK.stroke_width(1),
            ))
            .map_err(|e| err(&e))?;
        }
    }
    Ok(())
}

/// The pair markers inside the plot box (see [`PairMarker`]).
pub(crate) fn draw_markers(
    path: &Path,
    root: &Area,
    layout: &Layout,
    markers: &[PairMarker],
    proceed: Proceed<'_>,
) -> Result<()> {
    let err = draw_err(path);
    let radius = marker_radius(markers, layout.tf.scale);
    for (i, m) in markers.iter().enumerate() {
        if i % CHUNK == 0 {
            proceed()?;
        }
        let p = layout.tf.px(m.at);
        if !layout.inside(p) {
            continue;
        }
        let colour = if m.violates {
            RED
        } else if m.slip {
            BLUE
        } else {
            BLACK
        };
        let style = if m.bonded {
            colour.filled()
        } else {
            colour.stroke_width(if m.violates { 2 } else { 1 })
        };
        if m.violates {
            let (x, y) = ip(p);
            let r = radius + 1;
            root.draw(&Rectangle::new([(x - r, y - r), (x + r, y + r)], style))
                .map_err(|e| err(&e))?;
        } else {
            root.draw(&Circle::new(ip(p), radius, style))
                .map_err(|e| err(&e))?;
        }
    }
    Ok(())
}

/// Marker radius in pixels from the spacing of consecutive markers (pairs come in
/// order along each interface), so dense interfaces stay readable; `scale` is
/// pixels per model unit.
fn marker_radius(markers: &[PairMarker], scale: f64) -> i32 {
    let mut gaps: Vec<f64> = markers
        .windows(2)
        .map(|w| crate::mesh::dist(w[0].at, w[1].at) * scale)
        .filter(|d| *d > 0.0)
        .collect();
    if gaps.is_empty() {
        4
    } else {
        let mid = gaps.len() / 2;
        let (_, median, _) = gaps.select_nth_unstable_by(mid, f64::total_cmp);
        (0.3 * *median).clamp(2.0, 5.0).round() as i32
    }
}

/// Encodes an RGB buffer of `width` × `height` pixels as PNG and writes it atomically.
pub(crate) fn write_rgb(path: &Path, buf: &[u8], width: u32, height: u32) -> Result<()> {
    use image::ImageEncoder;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(buf, width, height, image::ColorType::Rgb8)
        .map_err(|e| Error::output(path, e))?;
    write_atomic(path, |w| w.write_all(&png))
}

/// The 0.5 % and 99.5 % quantiles of `values` (the full range for small sets).
fn robust_range(values: &[f64]) -> (f64, f64) {
    let mut v = values.to_vec();
    let n = v.len();
    let k = n / 200;
    let (_, lo, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    let lo = *lo;
    let (_, hi, _) = v.select_nth_unstable_by(n - 1 - k, f64::total_cmp);
    (lo, *hi)
}

/// A value printed with about four significant digits relative to `span` (the
/// colour range), in plain notation unless it is very large or very small.
pub(crate) fn format_value(v: f64, span: f64) -> String {
    let mag = v.abs().max(span.abs());
    if mag == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&mag) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - mag.log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

/// The largest 1, 2 or 5 × 10ⁿ not above `x` (a readable magnification factor
/// of a deformed shape).
pub fn nice_floor(x: f64) -> f64 {
    let base = 10f64.powf(x.log10().floor());
    let m = x / base;
    base * if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    }
}

/// A "nice" tick step (1, 2 or 5 × 10ⁿ) close to `raw`.
fn nice_step(raw: f64) -> f64 {
    let e = raw.log10().floor();
    let base = 10f64.powf(e);
    let m = raw / base;
    base * if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drawing that is never asked to stop.
    const GO: Proceed<'static> = &|| Ok(());

    /// Titles and labels are bounded: control characters dropped, at most
    /// MAX_LABEL_CHARS characters with `…` last when cut; a short clean text is
    /// kept as it is (borrowed).
    #[test]
    fn labels_are_bounded() {
        assert!(matches!(
            label_text("plate σyy"),
            Cow::Borrowed("plate σyy")
        ));
        assert_eq!(label_text("a\nb\t\0c\u{7f}"), "abc");
        let exact = "é".repeat(MAX_LABEL_CHARS);
        assert_eq!(label_text(&exact), exact.as_str());
        let long = "é".repeat(MAX_LABEL_CHARS + 1);
        let cut = label_text(&long);
        assert_eq!(cut.chars().count(), MAX_LABEL_CHARS);
        assert!(cut.ends_with("é…"));
        // Control characters do not count towards the bound.
        let mixed = format!("{}{}", "\n".repeat(1000), "x".repeat(MAX_LABEL_CHARS));
        assert_eq!(label_text(&mixed), "x".repeat(MAX_LABEL_CHARS));
    }

    /// A picture whose title, colour-bar label and unit are each a megabyte
    /// (with line breaks and NUL) is drawn, its title cut with `…` to fit the
    /// width; a fitting title is kept whole.
    #[test]
    fn huge_titles_are_cut_to_fit() {
        let dir = std::env::temp_dir().join(format!("cfe_png_title_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let huge = "long title\n\0 ".repeat(80_000);
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mesh = PlotMesh {
            points: &points,
            triangles: &[[0, 1, 2], [0, 2, 3]],
            outline: None,
        };
        let labels = PlotLabels {
            title: &huge,
            colorbar: &huge,
            axis_unit: &huge,
        };
        let path = dir.join("t.png");
        render_field(&path, &mesh, &[0.0, 1.0, 2.0, 3.0], &[], &labels, GO).unwrap();
        assert!(image::open(&path).is_ok());
        // The title as drawn: within the room, cut with the ellipsis.
        let mut buf = vec![255u8; 1600 * 100 * 3];
        let root = BitMapBackend::with_buffer(&mut buf, (1600, 100)).into_drawing_area();
        register_font();
        let (t, size) = fit_title(&root, &label_text(&huge), 800);
        assert!(
            t.ends_with('…') && t.chars().count() < MAX_LABEL_CHARS,
            "{t}"
        );
        assert_eq!(size, 16.0);
        let fits = |t: &str| {
            root.estimate_text_size(t, &TextStyle::from((FONT, size).into_font()))
                .unwrap()
                .0
                <= 800
        };
        assert!(fits(&t));
        assert!(!fits(&format!("{}x…", t.trim_end_matches('…'))));
        assert_eq!(fit_title(&root, "short", 800), ("short".to_string(), 28.0));
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A drawing asked to stop returns the stop's error and leaves no file
    /// (neither the picture nor its temporary), at whichever check it comes.
    #[test]
    fn a_stopped_drawing_writes_nothing() {
        let dir = std::env::temp_dir().join(format!("cfe_png_stop_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (points, triangles) = grid_with_hole(120, 0);
        let nodal: Vec<f64> = points.iter().map(|p| p[0] + p[1]).collect();
        let mesh = PlotMesh {
            points: &points,
            triangles: &triangles,
            outline: None,
        };
        let labels = PlotLabels {
            title: "t",
            colorbar: "c",
            axis_unit: "m",
        };
        let path = dir.join("s.png");
        // Stop at the first, a middle and the last check.
        let checks = std::sync::atomic::AtomicUsize::new(0);
        let count: Proceed = &|| {
            checks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            Ok(())
        };
        render_isolines(&path, &mesh, &nodal, 5, &[], &labels, count).unwrap();
        let total = checks.load(std::sync::atomic::Ordering::Relaxed);
        assert!(total > 4, "{total} checks");
        std::fs::remove_file(&path).unwrap();
        for stop_at in [0, total / 2, total - 1] {
            let seen = std::sync::atomic::AtomicUsize::new(0);
            let stop: Proceed = &|| {
                if seen.fetch_add(1, std::sync::atomic::Ordering::Relaxed) == stop_at {
                    Err(Error::Interrupted {
                        increment: 1,
                        signal: 15,
                    })
                } else {
                    Ok(())
                }
            };
            let r = render_isolines(&path, &mesh, &nodal, 5, &[], &labels, stop);
            assert!(
                matches!(r, Err(Error::Interrupted { signal: 15, .. })),
                "{stop_at}"
            );
            let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
            assert!(left.is_empty(), "{stop_at}: {left:?}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// The turbo map runs from blue through green to red.
    #[test]
    fn turbo_endpoints() {
        let (a, m, b) = (turbo(0.15), turbo(0.5), turbo(0.9));
        assert!(a[2] > a[0] && a[2] > a[1], "{a:?}");
        assert!(m[1] > m[0] && m[1] > m[2], "{m:?}");
        assert!(b[0] > b[1] && b[0] > b[2], "{b:?}");
    }

    /// Marching triangles gives the exact crossing segment of a linear field:
    /// v = x on the unit right triangle crosses 0.25 at x = 0.25.
    #[test]
    fn isoline_of_linear_field() {
        let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let [a, b] = isoline_segment(&p, &[0.0, 1.0, 0.0], 0.25).unwrap();
        for q in [a, b] {
            assert!((q[0] - 0.25).abs() < 1e-15);
        }
        assert!((a[1] - b[1]).abs() > 0.7);
        assert!(isoline_segment(&p, &[0.0, 1.0, 0.0], 2.0).is_none());
    }

    /// The rasteriser fills a square (two triangles) with a linear field whose
    /// colours vary monotonically along x (red channel of a grey ramp), and leaves
    /// pixels outside untouched.
    #[test]
    fn rasterizer_interpolates_linearly() {
        let (w, h) = (20usize, 10usize);
        let mut buf = vec![7u8; w * h * 3];
        let p = [[2.0, 2.0], [12.0, 2.0], [12.0, 8.0], [2.0, 8.0]];
        let v = [0.0, 1.0, 1.0, 0.0];
        let tris = [[0, 1, 2], [0, 2, 3]]
            .into_iter()
            .map(|t: [usize; 3]| (t.map(|n| p[n]), t.map(|n| v[n])));
        rasterize(&mut buf, w, [0, 0, w, h], tris, |x| {
            let g = (x * 250.0).round() as u8;
            [g, g, g]
        });
        let at = |x: usize, y: usize| buf[3 * (y * w + x)];
        let row: Vec<u8> = (2..12).map(|x| at(x, 5)).collect();
        assert!(row.windows(2).all(|r| r[1] > r[0]), "{row:?}");
        assert_eq!(at(15, 5), 7);
        assert_eq!(at(5, 0), 7);
    }

    /// A two-triangle square renders to a valid PNG of the expected width.
    #[test]
    fn writes_a_png() {
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let mesh = PlotMesh {
            points: &points,
            triangles: &triangles,
            outline: None,
        };
        let labels = PlotLabels {
            title: "t",
            colorbar: "v [MPa]",
            axis_unit: "mm",
        };
        let dir = std::env::temp_dir().join(format!("cfe-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.png");
        let markers = [PairMarker {
            at: [0.5, 0.0],
            bonded: true,
            slip: false,
            violates: false,
        }];
        render_field(&path, &mesh, &[0.0, 1.0, 2.0, 3.0], &markers, &labels, GO).unwrap();
        render_isolines(
            &dir.join("b.png"),
            &mesh,
            &[0.0, 1.0, 2.0, 3.0],
            5,
            &markers,
            &labels,
            GO,
        )
        .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        assert_eq!(width, WIDTH);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The outline of a two-triangle square is its four sides, not the diagonal.
    #[test]
    fn outline_of_a_square() {
        let edges = outline_edges(&[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(edges, vec![[0, 1], [0, 3], [1, 2], [2, 3]]);
    }

    /// A unit square of `n` × `n` cells, each split into two triangles, with
    /// the cell at (`hole`, `hole`) left out: (points, triangles).
    fn grid_with_hole(n: usize, hole: usize) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let points = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64 / n as f64, j as f64 / n as f64]))
            .collect();
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if (i, j) != (hole, hole) {
                    let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                    tris.push([a, b, c]);
                    tris.push([a, c, d]);
                }
            }
        }
        (points, tris)
    }

    /// The outline is exactly the edges used by one triangle, sorted: on a grid
    /// with a hole beside a second part (a shifted copy, its own nodes), against
    /// a count of every edge in a map. 4 × 6 outer sides + 4 sides of each hole.
    #[test]
    fn outline_is_the_edges_used_once() {
        let (_, mut tris) = grid_with_hole(6, 2);
        let shift = 49;
        let second: Vec<[usize; 3]> = tris.iter().map(|t| t.map(|n| n + shift)).collect();
        tris.extend(second);
        let mut count = std::collections::BTreeMap::new();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry([a.min(b), a.max(b)]).or_insert(0) += 1;
            }
        }
        let once: Vec<[usize; 2]> = count
            .into_iter()
            .filter(|&(_, c)| c == 1)
            .map(|(e, _)| e)
            .collect();
        assert_eq!(once.len(), 2 * (24 + 4));
        assert_eq!(outline_edges(&tris), once);
        assert!(outline_edges(&[]).is_empty());
    }

    /// Isolines of v = x on a square with a hole lie where x is at each level:
    /// for levels 1/4, 1/2 and 3/4, the pixel of the line's point at mid-height
    /// has the level's colour, and the hole's middle is left unpainted.
    #[test]
    fn isolines_lie_at_their_levels() {
        let (points, triangles) = grid_with_hole(8, 6);
        let nodal: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let mesh = PlotMesh {
            points: &points,
            triangles: &triangles,
            outline: None,
        };
        let labels = PlotLabels {
            title: "v = x",
            colorbar: "v",
            axis_unit: "m",
        };
        let dir = std::env::temp_dir().join(format!("cfe-iso-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("iso.png");
        render_isolines(&path, &mesh, &nodal, 3, &[], &labels, GO).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        let _ = std::fs::remove_dir_all(&dir);
        let layout = Layout::new(&points);
        let range = ColourRange::new(&nodal, Style::Isolines(3));
        let at = |p: [f64; 2]| {
            let (x, y) = ip(layout.tf.px(p));
            img.get_pixel(x as u32, y as u32).0
        };
        for level in [0.25, 0.5, 0.75] {
            assert_eq!(
                at([level, 0.5 + 1.0 / 16.0]),
                turbo(range.norm(level)),
                "{level}"
            );
        }
        // The middle of the hole (cell (6, 6) of 8) is not part of the mesh.
        assert_eq!(at([6.5 / 8.0, 6.5 / 8.0]), [255, 255, 255]);
    }

    /// Bad input is an error, not a panic.
    #[test]
    fn bad_input_is_an_error() {
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let labels = PlotLabels {
            title: "t",
            colorbar: "v",
            axis_unit: "mm",
        };
        let p = Path::new("/nonexistent/x.png");
        let ok = PlotMesh {
            points: &points,
            triangles: &[[0, 1, 2]],
            outline: None,
        };
        assert!(render_field(p, &ok, &[0.0, 1.0], &[], &labels, GO).is_err());
        assert!(render_field(p, &ok, &[0.0, f64::NAN, 1.0], &[], &labels, GO).is_err());
        let bad = PlotMesh {
            points: &points,
            triangles: &[[0, 1, 5]],
            outline: None,
        };
        assert!(render_field(p, &bad, &[0.0, 1.0, 2.0], &[], &labels, GO).is_err());
    }
}
