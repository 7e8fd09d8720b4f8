//! output::png — report-quality PNG pictures of a field on a 2D triangle mesh: a
//! smoothly shaded colour map ([`render_field`]) or coloured isolines over the grey
//! parts ([`render_isolines`]), with part outlines, coupling-pair markers, equal axis
//! scaling, axes in the model's length unit, a title and a colour bar.
//!
//! Text is drawn with plotters through ab_glyph and the bundled DejaVu Sans (no system
//! font library is needed). Everything else is drawn directly into the RGB buffer:
//! the field is rasterised per pixel (linear interpolation inside each triangle), so
//! the cost is O(triangles + pixels) whatever the mesh size; lines and markers are
//! anti-aliased. The buffer is encoded to PNG and written atomically.

use super::write_atomic;
use crate::error::{Error, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::Path;
use std::sync::Once;

/// What to draw: node coordinates (already deformed if the caller wants a deformed
/// picture) and triangles as node-index triples. Nodal values are given per node.
pub struct PlotMesh<'a> {
    /// Node coordinates in the model's length unit.
    pub points: &'a [[f64; 2]],
    /// Triangles as indices into `points`; the parts' outlines are the edges used by
    /// exactly one triangle.
    pub triangles: &'a [[usize; 3]],
}

/// Labels of one picture.
pub struct PlotLabels<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// Colour-bar label, e.g. `σyy [MPa]`.
    pub colorbar: &'a str,
    /// Length unit of the axes, e.g. `mm` (the axes then read `x [mm]` and `y [mm]`).
    pub axis_unit: &'a str,
}

/// A coupling pair marker: position and whether the pair is bonded (filled) or open
/// (hollow).
pub struct PairMarker {
    /// Position in model coordinates (deformed, if the picture is).
    pub at: [f64; 2],
    /// Bonded pairs are drawn as filled dots, open pairs as hollow circles.
    pub bonded: bool,
}

/// Smoothly shaded (per-pixel linear interpolation inside each triangle) colour map of
/// `nodal` (one value per point), with part outlines, colour bar, axes, title, and
/// pair markers. The colour range is the data's min..max (a constant field is drawn
/// in one colour).
pub fn render_field(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    markers: &[PairMarker],
    labels: &PlotLabels,
) -> Result<()> {
    render(path, mesh, nodal, markers, labels, Style::Field)
}

/// Isolines of `nodal` (e.g. total displacement magnitude) at `levels` evenly spaced
/// values strictly inside its (min, max) range, each line coloured by its level
/// against the colour bar, drawn over a light-grey fill of the mesh with part
/// outlines; same frame as [`render_field`]. The levels are also marked on the colour
/// bar. At most 200 levels are drawn (more would merge into a fill at this
/// resolution); a constant field has no isolines.
pub fn render_isolines(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    levels: usize,
    markers: &[PairMarker],
    labels: &PlotLabels,
) -> Result<()> {
    let levels = levels.min(MAX_LEVELS);
    render(path, mesh, nodal, markers, labels, Style::Isolines(levels))
}

/// The largest number of isoline levels [`render_isolines`] draws.
const MAX_LEVELS: usize = 200;

/// Picture width in pixels.
const WIDTH: u32 = 1600;
/// Left margin (y tick labels and axis label).
const LEFT: usize = 120;
/// Right column (colour bar, its ticks and label, marker legend).
const RIGHT: usize = 250;
/// Top margin (title and colour-bar label).
const TOP: usize = 106;
/// Bottom margin (x tick labels, axis label, marker legend).
const BOTTOM: usize = 88;
/// Plot-area width in pixels.
const PLOT_W: usize = WIDTH as usize - LEFT - RIGHT;
/// Smallest plot-area height: a flat model gets this much and a taller y range.
const MIN_PLOT_H: usize = 340;
/// Largest plot-area height: a tall model gets this much and a wider x range.
const MAX_PLOT_H: usize = 1300;
/// Free space around the model, as a fraction of its larger extent, on each side.
const PAD: f64 = 0.04;
/// Font family name under which the bundled font is registered.
const FONT: &str = "sans-serif";
/// Colour of text, frame and outlines.
const INK: [u8; 3] = [20, 20, 20];
/// Fill of the parts under isolines.
const PART_GREY: [u8; 3] = [226, 226, 226];

static FONT_ONCE: Once = Once::new();

/// Registers the bundled DejaVu Sans with plotters under the name "sans-serif" (once
/// per process; see assets/fonts/DejaVuSans-LICENSE.txt).
pub(crate) fn register_font() {
    FONT_ONCE.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        // A failure here shows up as an error from the first text drawn.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, bytes);
    });
}

/// Encodes an RGB buffer of `width` × `height` pixels as PNG and writes it to `path`
/// atomically.
pub(crate) fn write_rgb(path: &Path, buf: &[u8], width: u32, height: u32) -> Result<()> {
    use image::ImageEncoder;
    if buf.len() != 3 * width as usize * height as usize {
        return Err(Error::output(path, "image buffer does not match its size"));
    }
    write_atomic(path, |w| {
        use image::codecs::png::{CompressionType, FilterType, PngEncoder};
        // Fast deflate with the Sub filter: ~20 ms for a picture, at some 1.5–2 times
        // the size of the slowest setting (which takes ~15 times longer).
        PngEncoder::new_with_quality(w, CompressionType::Fast, FilterType::Sub)
            .write_image(buf, width, height, image::ColorType::Rgb8)
            .map_err(std::io::Error::other)
    })
}

/// The "turbo" colour map (Mikhailov, Google 2019) at `t` ∈ [0, 1]: dark blue → blue →
/// cyan → green → yellow → red → dark red. Linear interpolation in every fifth entry of
/// the published 256-entry table (within 1/255 of it). `t` is clamped; NaN gives 0.
pub(crate) fn turbo(t: f64) -> [u8; 3] {
    #[rustfmt::skip]
    const TABLE: [[u8; 3]; 52] = [
        [48, 18, 59], [54, 33, 95], [59, 47, 128], [63, 62, 156], [66, 75, 181],
        [69, 89, 203], [70, 102, 221], [71, 115, 235], [70, 128, 246], [69, 140, 253],
        [64, 153, 255], [56, 165, 251], [47, 178, 244], [39, 190, 233], [31, 201, 221],
        [26, 212, 208], [24, 221, 194], [26, 228, 182], [34, 235, 170], [47, 241, 155],
        [63, 246, 138], [82, 250, 122], [101, 253, 105], [121, 254, 89], [139, 255, 75],
        [156, 254, 64], [169, 251, 57], [183, 247, 53], [195, 241, 52], [208, 234, 52],
        [219, 226, 54], [229, 217, 56], [238, 207, 58], [245, 197, 58], [250, 186, 57],
        [253, 174, 53], [254, 161, 48], [254, 147, 42], [252, 132, 35], [249, 117, 29],
        [244, 102, 23], [239, 88, 17], [232, 75, 12], [225, 65, 9], [216, 55, 6],
        [206, 45, 4], [195, 37, 3], [183, 29, 2], [169, 22, 1], [155, 15, 1],
        [139, 9, 2], [122, 4, 3],
    ];
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (TABLE.len() - 1) as f64;
    let k = (x as usize).min(TABLE.len() - 2);
    let f = x - k as f64;
    let (a, b) = (TABLE[k], TABLE[k + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + f * (b[c] as f64 - a[c] as f64)).round() as u8)
}

#[derive(Clone, Copy)]
enum Style {
    Field,
    Isolines(usize),
}

/// Where the model goes on the picture: plot area in pixels and the model-coordinate
/// window shown in it, with one scale for x and y.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// Picture height in pixels (the width is [`WIDTH`]).
    height: u32,
    /// Plot-area height in pixels (its width is [`PLOT_W`], its top-left corner
    /// ([`LEFT`], [`TOP`])).
    plot_h: usize,
    /// Shown window: x0, x1, y0, y1 in model units.
    view: [f64; 4],
    /// Pixels per model unit, the same along x and y.
    scale: f64,
}

impl Frame {
    /// The frame for a model with these points: the picture height follows the model's
    /// aspect ratio (clamped), and the shorter window side is widened so that the scale
    /// is equal both ways. None if the points have no finite extent.
    fn new(points: &[[f64; 2]]) -> Option<Frame> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let (dx, dy) = (hi[0] - lo[0], hi[1] - lo[1]);
        let mut span = dx.max(dy);
        if !span.is_finite() || !lo[0].is_finite() || !lo[1].is_finite() {
            return None;
        }
        if span <= 0.0 {
            span = if lo[0].abs().max(lo[1].abs()) > 0.0 {
                lo[0].abs().max(lo[1].abs())
            } else {
                1.0
            };
        }
        let pad = PAD * span;
        let (wx, wy) = ((dx + 2.0 * pad).max(pad), (dy + 2.0 * pad).max(pad));
        let plot_h = (PLOT_W as f64 * wy / wx)
            .round()
            .clamp(MIN_PLOT_H as f64, MAX_PLOT_H as f64) as usize;
        let scale = (PLOT_W as f64 / wx).min(plot_h as f64 / wy);
        let (cx, cy) = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]));
        let (hx, hy) = (0.5 * PLOT_W as f64 / scale, 0.5 * plot_h as f64 / scale);
        if !(scale.is_finite() && scale > 0.0 && hx.is_finite() && hy.is_finite()) {
            return None;
        }
        Some(Frame {
            height: (TOP + plot_h + BOTTOM) as u32,
            plot_h,
            view: [cx - hx, cx + hx, cy - hy, cy + hy],
            scale,
        })
    }

    /// Model point → continuous pixel coordinates (pixel (i, j) covers [i, i+1) ×
    /// [j, j+1); y grows downwards).
    fn px(&self, p: [f64; 2]) -> [f64; 2] {
        [
            LEFT as f64 + (p[0] - self.view[0]) * self.scale,
            TOP as f64 + (self.view[3] - p[1]) * self.scale,
        ]
    }

    /// The plot area as a clip rectangle [x0, y0, x1, y1) in pixels.
    fn clip(&self) -> [usize; 4] {
        [LEFT, TOP, LEFT + PLOT_W, TOP + self.plot_h]
    }
}

/// Fills triangles into an RGB buffer (`width` pixels per row, 3 bytes per pixel),
/// clipped to `clip` = [x0, y0, x1, y1) in pixels: every pixel whose centre lies in a
/// triangle gets `colour` of the linear (barycentric) interpolation of the vertex
/// values there. A triangle that covers no pixel centre (smaller than a pixel, or a
/// sliver) still paints the pixel of its centroid. Vertices are in continuous pixel
/// coordinates. Cost: O(triangles + covered pixels).
fn rasterize(
    buf: &mut [u8],
    width: usize,
    clip: [usize; 4],
    tris: impl IntoIterator<Item = ([[f64; 2]; 3], [f64; 3])>,
    colour: impl Fn(f64) -> [u8; 3],
) {
    let rows = if width == 0 {
        0
    } else {
        buf.len() / (3 * width)
    };
    let clip = [
        clip[0].min(width),
        clip[1].min(rows),
        clip[2].min(width),
        clip[3].min(rows),
    ];
    let mut put = |x: usize, y: usize, c: [u8; 3]| {
        let i = 3 * (y * width + x);
        buf[i..i + 3].copy_from_slice(&c);
    };
    for (p, v) in tris {
        let xmin = p[0][0].min(p[1][0]).min(p[2][0]);
        let xmax = p[0][0].max(p[1][0]).max(p[2][0]);
        let ymin = p[0][1].min(p[1][1]).min(p[2][1]);
        let ymax = p[0][1].max(p[1][1]).max(p[2][1]);
        if !(xmin.is_finite() && xmax.is_finite() && ymin.is_finite() && ymax.is_finite()) {
            continue;
        }
        // Pixel centres x + 0.5 in [xmin, xmax].
        let range = |lo: f64, hi: f64, c0: usize, c1: usize| {
            let a = (lo - 0.5).ceil().max(c0 as f64);
            let b = ((hi - 0.5).floor() + 1.0).min(c1 as f64);
            (a as usize, (b.max(a)) as usize)
        };
        let (ix0, ix1) = range(xmin, xmax, clip[0], clip[2]);
        let (iy0, iy1) = range(ymin, ymax, clip[1], clip[3]);
        let (e1, e2) = (
            [p[1][0] - p[0][0], p[1][1] - p[0][1]],
            [p[2][0] - p[0][0], p[2][1] - p[0][1]],
        );
        let det = e1[0] * e2[1] - e2[0] * e1[1];
        let mut painted = false;
        if det.abs() > 1e-12 {
            const TOL: f64 = -1e-9;
            for y in iy0..iy1 {
                let dy = y as f64 + 0.5 - p[0][1];
                for x in ix0..ix1 {
                    let dx = x as f64 + 0.5 - p[0][0];
                    let l1 = (dx * e2[1] - e2[0] * dy) / det;
                    let l2 = (e1[0] * dy - dx * e1[1]) / det;
                    let l0 = 1.0 - l1 - l2;
                    if l0 >= TOL && l1 >= TOL && l2 >= TOL {
                        put(x, y, colour(l0 * v[0] + l1 * v[1] + l2 * v[2]));
                        painted = true;
                    }
                }
            }
        }
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

/// Marching triangles: the segment where the linear field with vertex values `v` over
/// the triangle `p` equals `level`, by linear interpolation along the crossed edges.
/// A vertex exactly at the level counts as above it, so an edge lying on the level is
/// drawn by one of its two triangles only; a crossing that shrinks to a point gives
/// None.
fn isoline_segment(p: &[[f64; 2]; 3], v: &[f64; 3], level: f64) -> Option<[[f64; 2]; 2]> {
    let above = v.map(|x| x >= level);
    let mut pts = [[0.0; 2]; 2];
    let mut n = 0;
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        if above[a] != above[b] {
            // v[a] != v[b] here: one is >= level, the other below.
            let t = (level - v[a]) / (v[b] - v[a]);
            pts[n] = [
                p[a][0] + t * (p[b][0] - p[a][0]),
                p[a][1] + t * (p[b][1] - p[a][1]),
            ];
            n += 1;
        }
    }
    (n == 2 && pts[0] != pts[1]).then_some(pts)
}

/// The parts' outlines: edges (as sorted node pairs) used by exactly one triangle;
/// returned sorted. O(triangles) with a hash map over sorted edge pairs: a first pass
/// toggles each edge in and out of the map, which leaves the edges used an odd number
/// of times and stays small (about the size of the front between visited and unvisited
/// triangles) on meshes numbered with any locality; a second pass counts the uses of
/// just those edges, so that an edge shared by three triangles (a broken mesh) is not
/// taken for an outline.
pub(crate) fn outline_edges(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    type EdgeMap<V> = HashMap<(usize, usize), V, BuildHasherDefault<EdgeHasher>>;
    let edges = |t: &[usize; 3]| {
        let t = *t;
        (0..3).filter_map(move |k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            (a != b).then_some((a.min(b), a.max(b)))
        })
    };
    let mut odd: EdgeMap<()> = EdgeMap::default();
    for e in triangles.iter().flat_map(edges) {
        if odd.remove(&e).is_none() {
            odd.insert(e, ());
        }
    }
    let mut uses: EdgeMap<u32> = odd.into_keys().map(|e| (e, 0)).collect();
    for e in triangles.iter().flat_map(edges) {
        if let Some(n) = uses.get_mut(&e) {
            *n += 1;
        }
    }
    let mut out: Vec<[usize; 2]> = uses
        .into_iter()
        .filter_map(|((a, b), n)| (n == 1).then_some([a, b]))
        .collect();
    out.sort_unstable();
    out
}

/// A fast multiplicative hasher for node-index pairs (the keys are not chosen by an
/// adversary, so the default DoS-resistant hasher would only cost time).
#[derive(Default)]
struct EdgeHasher(u64);

impl Hasher for EdgeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// An anti-aliased drawing layer over a pixel rectangle: shapes set per-pixel coverage
/// (the largest wins, so touching or overlapping pieces of one line do not darken
/// each other) and colour; [`Layer::composite`] then blends it over the picture once.
struct Layer {
    /// Rectangle [x0, y0, x1, y1) in pixels.
    rect: [usize; 4],
    cov: Vec<f32>,
    col: Vec<[u8; 3]>,
}

impl Layer {
    fn new(rect: [usize; 4]) -> Layer {
        let n = (rect[2] - rect[0]) * (rect[3] - rect[1]);
        Layer {
            rect,
            cov: vec![0.0; n],
            col: vec![[0; 3]; n],
        }
    }

    /// Applies `coverage(pixel centre)` to the pixels of the box [lo, hi] (clipped).
    fn shade(
        &mut self,
        lo: [f64; 2],
        hi: [f64; 2],
        colour: [u8; 3],
        coverage: impl Fn([f64; 2]) -> f64,
    ) {
        let r = self.rect;
        let x0 = lo[0].floor().max(r[0] as f64);
        let y0 = lo[1].floor().max(r[1] as f64);
        let x1 = (hi[0].ceil() + 1.0).min(r[2] as f64);
        let y1 = (hi[1].ceil() + 1.0).min(r[3] as f64);
        if !(x0 < x1 && y0 < y1) {
            return;
        }
        let w = r[2] - r[0];
        for y in y0 as usize..y1 as usize {
            for x in x0 as usize..x1 as usize {
                let c = coverage([x as f64 + 0.5, y as f64 + 0.5]).clamp(0.0, 1.0) as f32;
                let i = (y - r[1]) * w + (x - r[0]);
                if c > self.cov[i] {
                    self.cov[i] = c;
                    self.col[i] = colour;
                }
            }
        }
    }

    /// A line of width 2 `half` from `a` to `b` (cut into short pieces so that the work
    /// follows the line's length, not its bounding box).
    fn segment(&mut self, a: [f64; 2], b: [f64; 2], half: f64, colour: [u8; 3]) {
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        if !len.is_finite() {
            return;
        }
        let pieces = (len / 8.0).ceil().clamp(1.0, 1e5) as usize;
        let reach = half + 1.0;
        for k in 0..pieces {
            let (s, t) = (k as f64 / pieces as f64, (k + 1) as f64 / pieces as f64);
            let p = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let lo = [p[0].min(q[0]) - reach, p[1].min(q[1]) - reach];
            let hi = [p[0].max(q[0]) + reach, p[1].max(q[1]) + reach];
            let d = [q[0] - p[0], q[1] - p[1]];
            let dd = d[0] * d[0] + d[1] * d[1];
            self.shade(lo, hi, colour, |c| {
                let u = if dd > 0.0 {
                    (((c[0] - p[0]) * d[0] + (c[1] - p[1]) * d[1]) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let dist = (c[0] - p[0] - u * d[0]).hypot(c[1] - p[1] - u * d[1]);
                half + 0.5 - dist
            });
        }
    }

    /// A filled disc of radius `r` around `c`.
    fn disc(&mut self, c: [f64; 2], r: f64, colour: [u8; 3]) {
        let reach = r + 1.0;
        self.shade(
            [c[0] - reach, c[1] - reach],
            [c[0] + reach, c[1] + reach],
            colour,
            |p| r + 0.5 - (p[0] - c[0]).hypot(p[1] - c[1]),
        );
    }

    /// A circle of radius `r` and line width 2 `half` around `c`.
    fn ring(&mut self, c: [f64; 2], r: f64, half: f64, colour: [u8; 3]) {
        let reach = r + half + 1.0;
        self.shade(
            [c[0] - reach, c[1] - reach],
            [c[0] + reach, c[1] + reach],
            colour,
            |p| half + 0.5 - ((p[0] - c[0]).hypot(p[1] - c[1]) - r).abs(),
        );
    }

    /// Blends the layer over the RGB buffer (`width` pixels per row).
    fn composite(&self, buf: &mut [u8], width: usize) {
        let w = self.rect[2] - self.rect[0];
        for (i, (&c, col)) in self.cov.iter().zip(&self.col).enumerate() {
            if c <= 0.0 {
                continue;
            }
            let (x, y) = (self.rect[0] + i % w, self.rect[1] + i / w);
            let j = 3 * (y * width + x);
            if let Some(px) = buf.get_mut(j..j + 3) {
                for k in 0..3 {
                    px[k] = (px[k] as f32 * (1.0 - c) + col[k] as f32 * c).round() as u8;
                }
            }
        }
    }
}

/// Fills the pixel rectangle [x0, y0, x1, y1) with `colour`.
fn fill_rect(buf: &mut [u8], width: usize, r: [usize; 4], colour: [u8; 3]) {
    let rows = buf.len() / (3 * width);
    for y in r[1]..r[3].min(rows) {
        for x in r[0]..r[2].min(width) {
            let i = 3 * (y * width + x);
            buf[i..i + 3].copy_from_slice(&colour);
        }
    }
}

/// A 1-pixel frame just outside the pixel rectangle [x0, y0, x1, y1).
fn frame_rect(buf: &mut [u8], width: usize, r: [usize; 4], colour: [u8; 3]) {
    let [x0, y0, x1, y1] = [r[0] - 1, r[1] - 1, r[2] + 1, r[3] + 1];
    fill_rect(buf, width, [x0, y0, x1, y0 + 1], colour);
    fill_rect(buf, width, [x0, y1 - 1, x1, y1], colour);
    fill_rect(buf, width, [x0, y0, x0 + 1, y1], colour);
    fill_rect(buf, width, [x1 - 1, y0, x1, y1], colour);
}

/// The smallest 1, 2 or 5 × 10ⁿ that is at least `raw` (> 0).
fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let base = 10f64.powf(raw.log10().floor());
    let m = raw / base;
    base * if m <= 1.0 + 1e-9 {
        1.0
    } else if m <= 2.0 + 1e-9 {
        2.0
    } else if m <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    }
}

/// The next 1, 2 or 5 × 10ⁿ below `step` (itself such a number).
fn finer_step(step: f64) -> f64 {
    let base = 10f64.powf(step.log10().floor());
    let m = (step / base).round();
    step * if m == 5.0 { 0.4 } else { 0.5 }
}

/// Multiples of `step` in [lo, hi] (at most 100).
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step - 1e-9).ceil();
    (0..100)
        .map(|k| (first + k as f64) * step)
        .take_while(|&v| v <= hi + 1e-9 * step)
        .collect()
}

/// Decimals that print multiples of `step` exactly.
fn decimals(step: f64) -> usize {
    if step >= 1.0 {
        0
    } else {
        (-step.log10() - 1e-9).ceil().clamp(0.0, 12.0) as usize
    }
}

/// `v` with `decimals` decimals; scientific (4 significant digits at most, e.g.
/// `-1.25e8`) for very large or very fine numbers; no "-0".
fn fmt_num(v: f64, decimals: usize) -> String {
    let s = if v != 0.0 && (v.abs() >= 1e6 || decimals > 6) {
        let s = format!("{v:.3e}");
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    } else {
        format!("{v:.decimals$}")
    };
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// Like [`fmt_num`] but without trailing zeros after the decimal point.
fn fmt_trim(v: f64, decimals: usize) -> String {
    let s = fmt_num(v, decimals);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Checks the input: a non-empty mesh, one finite value per point, triangle indices in
/// range, finite coordinates and marker positions.
fn validate(path: &Path, mesh: &PlotMesh, nodal: &[f64], markers: &[PairMarker]) -> Result<()> {
    let bad = |m: String| Err(Error::output(path, m));
    if mesh.points.is_empty() || mesh.triangles.is_empty() {
        return bad(format!(
            "nothing to draw: the mesh has {} points and {} triangles",
            mesh.points.len(),
            mesh.triangles.len()
        ));
    }
    if nodal.len() != mesh.points.len() {
        return bad(format!(
            "{} nodal values given for {} points",
            nodal.len(),
            mesh.points.len()
        ));
    }
    let n = mesh.points.len();
    if let Some((i, t)) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&k| k >= n))
    {
        return bad(format!(
            "triangle {i} {t:?} refers to a point beyond the {n} given"
        ));
    }
    if let Some(i) = mesh
        .points
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return bad(format!("point {i} has a non-finite coordinate"));
    }
    if let Some(i) = nodal.iter().position(|v| !v.is_finite()) {
        return bad(format!("the value at point {i} is not finite"));
    }
    if let Some(i) = markers
        .iter()
        .position(|m| !m.at.iter().all(|c| c.is_finite()))
    {
        return bad(format!("pair marker {i} has a non-finite position"));
    }
    Ok(())
}

/// A text to draw: content, anchor point, size, anchoring, and whether it runs
/// upwards (rotated by 270°).
struct Label {
    text: String,
    at: (i32, i32),
    size: f64,
    pos: Pos,
    upright: bool,
}

fn label(text: impl Into<String>, at: (i32, i32), size: f64, h: HPos, v: VPos) -> Label {
    Label {
        text: text.into(),
        at: (at.0, at.1),
        size,
        pos: Pos::new(h, v),
        upright: false,
    }
}

/// Draws the labels into the buffer with plotters (the bundled font, anti-aliased).
fn draw_labels(buf: &mut [u8], height: u32, labels: &[Label]) -> std::result::Result<(), String> {
    let root = BitMapBackend::with_buffer(buf, (WIDTH, height)).into_drawing_area();
    let ink = RGBColor(INK[0], INK[1], INK[2]);
    for l in labels {
        if l.text.is_empty() {
            continue;
        }
        let mut style = TextStyle::from((FONT, l.size).into_font())
            .color(&ink)
            .pos(l.pos);
        if l.upright {
            style = style.transform(FontTransform::Rotate270);
        }
        root.draw_text(&l.text, &style, l.at)
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Font size at most `size` at which `text` fits in `max_width` pixels (down to 60 %).
fn fitting_size(text: &str, size: f64, max_width: f64) -> f64 {
    // Measured on a scratch 1 × 1 backend; a failure keeps the size.
    let mut scratch = [0u8; 3];
    let area = BitMapBackend::with_buffer(&mut scratch, (1, 1)).into_drawing_area();
    let mut s = size;
    while s > 0.6 * size {
        let style = TextStyle::from((FONT, s).into_font());
        match area.estimate_text_size(text, &style) {
            Ok((w, _)) if w as f64 > max_width => s -= 1.0,
            _ => break,
        }
    }
    s
}

fn render(
    path: &Path,
    mesh: &PlotMesh,
    nodal: &[f64],
    markers: &[PairMarker],
    labels: &PlotLabels,
    style: Style,
) -> Result<()> {
    validate(path, mesh, nodal, markers)?;
    let frame = Frame::new(mesh.points)
        .ok_or_else(|| Error::output(path, "the coordinates are too large to draw"))?;
    register_font();

    let (width, height) = (WIDTH as usize, frame.height as usize);
    let plot = frame.clip();
    let (pl, pt, pr, pb) = (plot[0], plot[1], plot[2], plot[3]);
    let mut buf = vec![255u8; width * height * 3];

    // Colour range: the data's min..max; a constant field maps to the middle colour.
    let (vmin, vmax) = nodal
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = vmax - vmin;
    let flat = !(span > 0.0 && span.is_finite());
    let norm = |v: f64| if flat { 0.5 } else { (v - vmin) / span };
    let level_values: Vec<f64> = match style {
        Style::Isolines(n) if !flat => (1..=n)
            .map(|k| vmin + span * k as f64 / (n + 1) as f64)
            .collect(),
        _ => Vec::new(),
    };

    let mut texts: Vec<Label> = Vec::new();
    let (xc, yc) = ((pl + pr) as i32 / 2, (pt + pb) as i32 / 2);

    // Title, centred over the plot area, shrunk if long.
    let title_room = 2.0 * (xc as f64).min((width as i32 - xc) as f64) - 20.0;
    let title_size = fitting_size(labels.title, 30.0, title_room);
    texts.push(label(
        labels.title,
        (xc, 22),
        title_size,
        HPos::Center,
        VPos::Top,
    ));

    // Axes: ticks at one common step (at least 100 px apart), labels, unit.
    let tick = nice_step(100.0 / frame.scale);
    let [vx0, vx1, vy0, vy1] = frame.view;
    // (The minimum plot height leaves room for three; finer steps just in case.)
    let mut ystep = tick;
    for _ in 0..6 {
        if ticks(vy0, vy1, ystep).len() >= 3 || ystep * frame.scale < 90.0 {
            break;
        }
        ystep = finer_step(ystep);
    }
    let ink = INK;
    for t in ticks(vx0, vx1, tick) {
        let x = frame.px([t, 0.0])[0].floor() as usize;
        if (pl..pr).contains(&x) {
            fill_rect(&mut buf, width, [x, pb + 1, x + 1, pb + 8], ink);
            texts.push(label(
                fmt_num(t, decimals(tick)),
                (x as i32, pb as i32 + 12),
                19.0,
                HPos::Center,
                VPos::Top,
            ));
        }
    }
    for t in ticks(vy0, vy1, ystep) {
        let y = frame.px([0.0, t])[1].floor() as usize;
        if (pt..pb).contains(&y) {
            fill_rect(&mut buf, width, [pl - 8, y, pl - 1, y + 1], ink);
            texts.push(label(
                fmt_num(t, decimals(ystep)),
                (pl as i32 - 12, y as i32),
                19.0,
                HPos::Right,
                VPos::Center,
            ));
        }
    }
    texts.push(label(
        format!("x [{}]", labels.axis_unit),
        (xc, pb as i32 + 44),
        22.0,
        HPos::Center,
        VPos::Top,
    ));
    texts.push(Label {
        upright: true,
        ..label(
            format!("y [{}]", labels.axis_unit),
            (26, yc),
            22.0,
            HPos::Center,
            VPos::Center,
        )
    });

    // Colour bar: continuous turbo strip beside the plot, value max at the top.
    let (bl, br) = (pr + 40, pr + 68);
    let bar_h = pb - pt;
    for y in pt..pb {
        let f = 1.0 - (y - pt) as f64 / (bar_h - 1).max(1) as f64;
        let c = if flat { turbo(0.5) } else { turbo(f) };
        fill_rect(&mut buf, width, [bl, y, br, y + 1], c);
    }
    for &level in &level_values {
        let y = pt + ((1.0 - norm(level)) * (bar_h - 1) as f64).round() as usize;
        fill_rect(&mut buf, width, [bl, y, br, y + 1], ink);
    }
    frame_rect(&mut buf, width, [bl, pt, br, pb], ink);
    let bar_y = |v: f64| pt as f64 + (1.0 - norm(v)) * (bar_h - 1) as f64;
    let mut bar_ticks: Vec<(f64, String)> = Vec::new();
    if flat {
        bar_ticks.push((vmin, fmt_trim(vmin, decimals(vmin.abs() / 1e3))));
    } else {
        let step = nice_step(span * 45.0 / bar_h as f64);
        let d = decimals(step);
        bar_ticks.push((vmin, fmt_trim(vmin, d + 1)));
        bar_ticks.push((vmax, fmt_trim(vmax, d + 1)));
        for t in ticks(vmin, vmax, step) {
            let y = bar_y(t);
            if (y - bar_y(vmin)).abs() > 26.0 && (y - bar_y(vmax)).abs() > 26.0 {
                bar_ticks.push((t, fmt_num(t, d)));
            }
        }
    }
    for (v, text) in bar_ticks {
        let y = bar_y(v).round() as usize;
        fill_rect(&mut buf, width, [br + 1, y, br + 7, y + 1], ink);
        texts.push(label(
            text,
            (br as i32 + 11, y as i32),
            19.0,
            HPos::Left,
            VPos::Center,
        ));
    }
    let cb_size = fitting_size(labels.colorbar, 22.0, (width - bl + 6) as f64);
    texts.push(label(
        labels.colorbar,
        (bl as i32 - 6, pt as i32 - 20),
        cb_size,
        HPos::Left,
        VPos::Bottom,
    ));

    // Legend of the pair markers, under the colour bar.
    let bonded = markers.iter().filter(|m| m.bonded).count();
    let open = markers.len() - bonded;
    let mut legend = Layer::new([pr + 2, pb + 2, width, height]);
    let mut row = 0;
    for (n, text, filled) in [(bonded, "bonded", true), (open, "open", false)] {
        if n == 0 {
            continue;
        }
        let y = (pb + 34 + 26 * row) as f64 + 0.5;
        let c = [bl as f64 + 7.0, y];
        if filled {
            legend.disc(c, 4.5, ink);
        } else {
            legend.ring(c, 4.5, 0.8, ink);
        }
        texts.push(label(
            format!("{text} pairs ({n})"),
            (bl as i32 + 20, y as i32),
            18.0,
            HPos::Left,
            VPos::Center,
        ));
        row += 1;
    }
    legend.composite(&mut buf, width);

    draw_labels(&mut buf, frame.height, &texts).map_err(|e| Error::output(path, e))?;

    // The field, or the grey parts under the isolines.
    let px_tris = mesh
        .triangles
        .iter()
        .map(|t| (t.map(|n| frame.px(mesh.points[n])), t.map(|n| nodal[n])));
    match style {
        Style::Field => rasterize(&mut buf, width, plot, px_tris, |v| turbo(norm(v))),
        Style::Isolines(_) => rasterize(&mut buf, width, plot, px_tris, |_| PART_GREY),
    }

    // Isolines: each triangle visits only the levels inside its value range, so the
    // cost is O(triangles + segments). A dark casing keeps light colours legible.
    if !level_values.is_empty() {
        let dl = span / (level_values.len() + 1) as f64;
        let mut casing = Layer::new(plot);
        let mut lines = Layer::new(plot);
        for t in mesh.triangles {
            let v = t.map(|n| nodal[n]);
            let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
            if hi <= lo {
                continue;
            }
            let k0 = (((lo - vmin) / dl).floor() as i64).max(1) as usize;
            let k1 = (((hi - vmin) / dl).ceil() as i64).min(level_values.len() as i64) as usize;
            if k0 > k1 {
                continue;
            }
            let p = t.map(|n| frame.px(mesh.points[n]));
            for &level in &level_values[k0 - 1..k1] {
                if let Some([a, b]) = isoline_segment(&p, &v, level) {
                    casing.segment(a, b, 2.1, [60, 60, 60]);
                    lines.segment(a, b, 1.25, turbo(norm(level)));
                }
            }
        }
        casing.composite(&mut buf, width);
        lines.composite(&mut buf, width);
    }

    // Part outlines.
    let mut outline = Layer::new(plot);
    for [a, b] in outline_edges(mesh.triangles) {
        outline.segment(
            frame.px(mesh.points[a]),
            frame.px(mesh.points[b]),
            0.55,
            [0, 0, 0],
        );
    }
    outline.composite(&mut buf, width);

    // Pair markers, sized from the median spacing of consecutive markers (pairs come
    // in order along an interface) so that dense interfaces stay readable; a white
    // halo keeps them visible on dark colours (and is the inside of an open one).
    if !markers.is_empty() {
        let mut gaps: Vec<f64> = markers
            .windows(2)
            .map(|w| (w[1].at[0] - w[0].at[0]).hypot(w[1].at[1] - w[0].at[1]) * frame.scale)
            .filter(|d| *d > 0.0)
            .collect();
        let r = if gaps.is_empty() {
            4.5
        } else {
            let mid = gaps.len() / 2;
            let (_, m, _) = gaps.select_nth_unstable_by(mid, f64::total_cmp);
            (0.35 * *m).clamp(2.0, 4.5)
        };
        let mut halo = Layer::new(plot);
        let mut dots = Layer::new(plot);
        for m in markers {
            let c = frame.px(m.at);
            halo.disc(c, r + 1.2, [255, 255, 255]);
            if m.bonded {
                dots.disc(c, r, ink);
            } else {
                dots.ring(c, r, 0.75, ink);
            }
        }
        halo.composite(&mut buf, width);
        dots.composite(&mut buf, width);
    }

    frame_rect(&mut buf, width, plot, ink);
    write_rgb(path, &buf, WIDTH, frame.height)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels() -> PlotLabels<'static> {
        PlotLabels {
            title: "test",
            colorbar: "σyy [MPa]",
            axis_unit: "mm",
        }
    }

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("cfe-png-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]];
    const SQUARE_TRIS: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

    /// A two-triangle square renders to a PNG with the PNG signature, 1600 px wide and
    /// as high as its equal-scale plot area (a square) plus margins.
    #[test]
    fn square_writes_png_of_expected_size() {
        let dir = temp_dir("size");
        let mesh = PlotMesh {
            points: &SQUARE,
            triangles: &SQUARE_TRIS,
        };
        let markers = [
            PairMarker {
                at: [50.0, 0.0],
                bonded: true,
            },
            PairMarker {
                at: [60.0, 0.0],
                bonded: false,
            },
        ];
        let values = [0.0, 1.0, 2.0, 3.0];
        let path = dir.join("field.png");
        render_field(&path, &mesh, &values, &markers, &labels()).unwrap();
        let iso = dir.join("iso.png");
        render_isolines(&iso, &mesh, &values, 5, &markers, &labels()).unwrap();
        let expected_h = (TOP + PLOT_W + BOTTOM) as u32;
        for p in [&path, &iso] {
            let bytes = std::fs::read(p).unwrap();
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
            let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
            let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
            assert_eq!((w, h), (WIDTH, expected_h));
            let img = image::load_from_memory(&bytes).unwrap().to_rgb8();
            assert_eq!(img.dimensions(), (WIDTH, expected_h));
        }
        // No temporary file is left behind.
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 2);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The rasteriser fills a square (two triangles) with a linear field whose colours
    /// increase strictly along x at mid-height, and leaves pixels outside untouched.
    #[test]
    fn rasterizer_interpolates_linearly() {
        let (w, h) = (20usize, 10usize);
        let mut buf = vec![7u8; w * h * 3];
        let p = [[2.0, 2.0], [12.0, 2.0], [12.0, 8.0], [2.0, 8.0]];
        let v = [0.0, 1.0, 1.0, 0.0];
        let tris = [[0, 1, 2], [0, 2, 3]].map(|t: [usize; 3]| (t.map(|n| p[n]), t.map(|n| v[n])));
        rasterize(&mut buf, w, [0, 0, w, h], tris, |x| {
            let g = (x * 250.0).round() as u8;
            [g, g, 255 - g]
        });
        let at = |x: usize, y: usize| buf[3 * (y * w + x)];
        let row: Vec<u8> = (2..12).map(|x| at(x, 5)).collect();
        assert!(row.windows(2).all(|r| r[1] > r[0]), "{row:?}");
        assert_eq!(at(1, 5), 7);
        assert_eq!(at(12, 5), 7);
        assert_eq!(at(5, 1), 7);
        assert_eq!(at(5, 8), 7);
    }

    /// A triangle smaller than a pixel still paints the pixel of its centroid.
    #[test]
    fn tiny_triangle_paints_a_pixel() {
        let (w, h) = (4usize, 4usize);
        let mut buf = vec![0u8; w * h * 3];
        let tri = ([[1.1, 2.1], [1.3, 2.1], [1.1, 2.3]], [1.0; 3]);
        rasterize(&mut buf, w, [0, 0, w, h], [tri], |_| [9, 9, 9]);
        assert_eq!(buf[3 * (2 * w + 1)], 9);
        assert_eq!(buf.iter().filter(|&&b| b == 9).count(), 3);
    }

    /// A linear field v = x rendered through the whole pipeline gives, along the middle
    /// row of the square, turbo colours whose position on the map increases with x.
    #[test]
    fn linear_field_colours_increase_along_x() {
        let dir = temp_dir("linear");
        let mesh = PlotMesh {
            points: &SQUARE,
            triangles: &SQUARE_TRIS,
        };
        let values: Vec<f64> = SQUARE.iter().map(|p| p[0]).collect();
        let path = dir.join("linear.png");
        render_field(&path, &mesh, &values, &[], &labels()).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        let frame = Frame::new(&SQUARE).unwrap();
        let table: Vec<[u8; 3]> = (0..=1000).map(|k| turbo(k as f64 / 1000.0)).collect();
        let inverse = |c: &image::Rgb<u8>| {
            (0..table.len())
                .min_by_key(|&k| {
                    (0..3)
                        .map(|i| (table[k][i] as i32 - c[i] as i32).pow(2))
                        .sum::<i32>()
                })
                .unwrap()
        };
        let y = frame.px([0.0, 50.0])[1] as u32;
        let (x0, x1) = (
            frame.px([2.0, 0.0])[0] as u32,
            frame.px([98.0, 0.0])[0] as u32,
        );
        let ts: Vec<usize> = (x0..x1).map(|x| inverse(img.get_pixel(x, y))).collect();
        assert!(ts.windows(2).all(|w| w[1] + 3 >= w[0]), "{ts:?}");
        assert!(ts[0] < 60 && *ts.last().unwrap() > 940, "{ts:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The turbo map runs from its dark-blue start through a green-yellow middle to its
    /// dark-red end, matching the published table.
    #[test]
    fn turbo_endpoints_and_midpoint() {
        assert_eq!(turbo(0.0), [48, 18, 59]);
        assert_eq!(turbo(1.0), [122, 4, 3]);
        let m = turbo(0.5);
        // Published table entries 127 and 128: (161, 253, 61) and (164, 252, 60).
        assert!((m[0] as i32 - 163).abs() <= 2, "{m:?}");
        assert!((m[1] as i32 - 252).abs() <= 2, "{m:?}");
        assert!((m[2] as i32 - 60).abs() <= 2, "{m:?}");
        assert_eq!(turbo(-1.0), turbo(0.0));
        assert_eq!(turbo(2.0), turbo(1.0));
        assert_eq!(turbo(f64::NAN), turbo(0.0));
    }

    /// Marching triangles gives the exact crossing segment: v = 4x on the unit right
    /// triangle crosses 1 along x = 0.25, from (0.25, 0) to (0.25, 0.75); degenerate
    /// crossings (level outside, or touching only a vertex) give none.
    #[test]
    fn isoline_on_one_triangle() {
        let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let v = [0.0, 4.0, 0.0];
        let [a, b] = isoline_segment(&p, &v, 1.0).unwrap();
        let mut s = [a, b];
        s.sort_by(|a, b| a[1].total_cmp(&b[1]));
        assert_eq!(s, [[0.25, 0.0], [0.25, 0.75]]);
        assert!(isoline_segment(&p, &v, 5.0).is_none());
        assert!(isoline_segment(&p, &v, -1.0).is_none());
        // Touches only vertex 1.
        assert!(isoline_segment(&p, &v, 4.0).is_none());
        // Constant field.
        assert!(isoline_segment(&p, &[2.0; 3], 2.0).is_none());
    }

    /// Tick labels print exactly the step's digits, switch to compact scientific
    /// notation for very large or fine values, and never read "-0".
    #[test]
    fn number_formats() {
        assert_eq!(fmt_num(20.0, decimals(5.0)), "20");
        assert_eq!(fmt_num(0.3, decimals(0.1)), "0.3");
        assert_eq!(fmt_num(0.25, decimals(0.05)), "0.25");
        assert_eq!(fmt_num(3e7, 0), "3e7");
        assert_eq!(fmt_num(-1.5343e8, 0), "-1.534e8");
        assert_eq!(fmt_num(5e-9, decimals(5e-9)), "5e-9");
        assert_eq!(fmt_num(-1e-9, 2), "0.00");
        assert_eq!(fmt_trim(0.0263, 4), "0.0263");
        assert_eq!(fmt_trim(12.0, 2), "12");
        assert_eq!(nice_step(0.13), 0.2);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(
            [finer_step(10.0), finer_step(5.0), finer_step(0.2)],
            [5.0, 2.0, 0.1]
        );
        assert_eq!(ticks(-7.0, 12.0, 5.0), vec![-5.0, 0.0, 5.0, 10.0]);
    }

    /// The outline of a two-triangle square is its four sides, not the diagonal.
    #[test]
    fn outline_of_a_square() {
        assert_eq!(
            outline_edges(&SQUARE_TRIS),
            vec![[0, 1], [0, 3], [1, 2], [2, 3]]
        );
    }

    /// A flat model (480 × 32 mm) keeps equal scaling: the plot gets the minimum height
    /// and a widened y window, and the whole model stays inside it.
    #[test]
    fn flat_model_keeps_equal_scaling() {
        let f = Frame::new(&[[0.0, 0.0], [480.0, 32.0]]).unwrap();
        assert_eq!(f.plot_h, MIN_PLOT_H);
        let [x0, x1, y0, y1] = f.view;
        let sx = PLOT_W as f64 / (x1 - x0);
        let sy = f.plot_h as f64 / (y1 - y0);
        assert!((sx / sy - 1.0).abs() < 1e-12 && (sx / f.scale - 1.0).abs() < 1e-12);
        assert!(x0 < 0.0 && x1 > 480.0 && y0 < 0.0 && y1 > 32.0);
    }

    /// A constant field still renders (one colour, one colour-bar label).
    #[test]
    fn constant_field_renders() {
        let dir = temp_dir("flat");
        let mesh = PlotMesh {
            points: &SQUARE,
            triangles: &SQUARE_TRIS,
        };
        render_field(&dir.join("a.png"), &mesh, &[3.0; 4], &[], &labels()).unwrap();
        render_isolines(&dir.join("b.png"), &mesh, &[3.0; 4], 8, &[], &labels()).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Bad input (mismatched lengths, an index out of range, NaN or infinite numbers,
    /// an empty mesh, an unwritable path) is an error, not a panic.
    #[test]
    fn bad_input_is_an_error() {
        let dir = temp_dir("bad");
        let p = dir.join("x.png");
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let ok = PlotMesh {
            points: &points,
            triangles: &[[0, 1, 2]],
        };
        let l = labels();
        assert!(render_field(&p, &ok, &[0.0, 1.0], &[], &l).is_err());
        assert!(render_isolines(&p, &ok, &[0.0, 1.0, 2.0, 3.0], 4, &[], &l).is_err());
        assert!(render_field(&p, &ok, &[0.0, f64::NAN, 1.0], &[], &l).is_err());
        assert!(render_isolines(&p, &ok, &[0.0, 1.0, f64::INFINITY], 4, &[], &l).is_err());
        let bad_index = PlotMesh {
            points: &points,
            triangles: &[[0, 1, 3]],
        };
        assert!(render_field(&p, &bad_index, &[0.0, 1.0, 2.0], &[], &l).is_err());
        let nan_point = PlotMesh {
            points: &[[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0]],
            triangles: &[[0, 1, 2]],
        };
        assert!(render_field(&p, &nan_point, &[0.0, 1.0, 2.0], &[], &l).is_err());
        let empty = PlotMesh {
            points: &[],
            triangles: &[],
        };
        assert!(render_field(&p, &empty, &[], &[], &l).is_err());
        let nan_marker = [PairMarker {
            at: [f64::NAN, 0.0],
            bonded: true,
        }];
        assert!(render_field(&p, &ok, &[0.0, 1.0, 2.0], &nan_marker, &l).is_err());
        let huge = PlotMesh {
            points: &[[-1e308, 0.0], [1e308, 0.0], [0.0, 1e308]],
            triangles: &[[0, 1, 2]],
        };
        assert!(render_field(&p, &huge, &[0.0, 1.0, 2.0], &[], &l).is_err());
        let nowhere = dir.join("missing").join("x.png");
        assert!(render_field(&nowhere, &ok, &[0.0, 1.0, 2.0], &[], &l).is_err());
        assert!(!p.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
