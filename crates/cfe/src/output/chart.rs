//! Line charts (linear or logarithmic axes) for reports: convergence plots and
//! benchmark curves, drawn with plotters on the bundled font and written as PNG.
//! The title, axis labels and legend names are bounded by `png::label_text`.

use super::png::label_text;
use crate::error::{Error, Result};
use plotters::prelude::*;
use std::path::Path;

/// One curve: a name for the legend and its points (x, y).
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// Points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Dashed reference line (no markers) instead of a measured curve.
    pub reference: bool,
}

/// Axis labels and scales of a chart.
pub struct Axes<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// x-axis label.
    pub x: &'a str,
    /// y-axis label.
    pub y: &'a str,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// A tick label: at most four significant decimals without trailing zeros, and
/// `1e-7`-style outside [1e-3, 1e5).
fn tick_label(v: f64) -> String {
    tick_label_step(v, 0.0)
}

/// A tick label on an axis whose ticks are `step` apart (0: unknown): enough
/// decimals to tell neighbouring ticks apart, trailing zeros removed.
fn tick_label_step(v: f64, step: f64) -> String {
    let a = v.abs();
    if a < 1e-12 * step.max(f64::MIN_POSITIVE) || a == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&a) && (step == 0.0 || step >= 1e-3 * a) {
        let s = format!("{v:.1e}");
        return s.replace(".0e", "e");
    }
    let mut decimals = (3 - a.log10().floor() as i32).clamp(0, 6);
    if step > 0.0 {
        decimals = decimals.max(1 - step.log10().floor() as i32).clamp(0, 12);
    }
    let decimals = decimals as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Labelled (bold) and unlabelled (light) grid values of a logarithmic axis over
/// [lo, hi]: mantissas 1…9 × 10^k, fewer labelled as the axis spans more decades.
fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let decades = (hi / lo).log10();
    let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let within = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let at = |mantissas: &[i32], every: i32| -> Vec<f64> {
        (e0..=e1)
            .filter(|e| (e - e0) % every == 0)
            .flat_map(|e| mantissas.iter().map(move |&m| m as f64 * 10f64.powi(e)))
            .filter(within)
            .collect()
    };
    let mut bold = if decades <= 1.2 {
        at(&[1, 2, 3, 4, 5, 6, 8], 1)
    } else if decades <= 3.5 {
        at(&[1, 2, 5], 1)
    } else {
        at(&[1], if decades > 9.0 { 2 } else { 1 })
    };
    if bold.len() < 2 {
        bold = at(&[1, 2, 3, 4, 5, 6, 7, 8, 9], 1);
    }
    let light = if decades <= 6.0 {
        at(&[1, 2, 3, 4, 5, 6, 7, 8, 9], 1)
    } else {
        at(&[1], 1)
    };
    (bold, light)
}

/// The corner of the plotting area (in drawing fractions, y up) with the fewest
/// The axis ranges of the points `pts`: their extent, widened by 5 % (a factor on
/// a logarithmic axis).
fn ranges(axes: &Axes, pts: &[(f64, f64)]) -> ([f64; 2], [f64; 2]) {
    let (mut x0, mut x1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    let (mut y0, mut y1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let widen = |lo: &mut f64, hi: &mut f64, log: bool| {
        if log {
            let f = (*hi / *lo).powf(0.05).max(1.15);
            *lo /= f;
            *hi *= f;
        } else {
            let pad = 0.05 * (*hi - *lo).abs().max(1e-12 * hi.abs().max(1.0));
            *lo -= pad;
            *hi += pad;
        }
    };
    widen(&mut x0, &mut x1, axes.log_x);
    widen(&mut y0, &mut y1, axes.log_y);
    ([x0, x1], [y0, y1])
}

/// Whether a point can be drawn: finite, and positive on a logarithmic axis.
fn drawable(axes: &Axes, p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && (!axes.log_x || p.0 > 0.0) && (!axes.log_y || p.1 > 0.0)
}

/// Where the points `pts` and the lines of `series` fall in the plotting area
/// `[x0, x1] × [y0, y1]` (fractions of it), for choosing the legend's corner: the
/// points, and ten samples along each segment between drawable points.
fn plotted_points(
    axes: &Axes,
    series: &[Series],
    pts: &[(f64, f64)],
    [x0, x1]: [f64; 2],
    [y0, y1]: [f64; 2],
) -> Vec<(f64, f64)> {
    let frac = |v: f64, lo: f64, hi: f64, log: bool| {
        if log {
            (v / lo).ln() / (hi / lo).ln()
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let mut placed: Vec<(f64, f64)> = pts
        .iter()
        .map(|p| (frac(p.0, x0, x1, axes.log_x), frac(p.1, y0, y1, axes.log_y)))
        .collect();
    // Lines between points also hide a legend: sample the segments.
    for s in series {
        let d: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| drawable(axes, p))
            .collect();
        for w in d.windows(2) {
            let a = (
                frac(w[0].0, x0, x1, axes.log_x),
                frac(w[0].1, y0, y1, axes.log_y),
            );
            let b = (
                frac(w[1].0, x0, x1, axes.log_x),
                frac(w[1].1, y0, y1, axes.log_y),
            );
            for i in 1..10 {
                let t = i as f64 / 10.0;
                placed.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
    }
    placed
}

/// points near it, for the legend.
fn legend_corner(points: &[(f64, f64)]) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::LowerRight, (0.6, 1.0), (0.0, 0.35)),
        (SeriesLabelPosition::UpperRight, (0.6, 1.0), (0.65, 1.0)),
        (SeriesLabelPosition::LowerLeft, (0.0, 0.4), (0.0, 0.35)),
        (SeriesLabelPosition::UpperLeft, (0.0, 0.4), (0.65, 1.0)),
        (SeriesLabelPosition::UpperMiddle, (0.3, 0.7), (0.65, 1.0)),
        (SeriesLabelPosition::LowerMiddle, (0.3, 0.7), (0.0, 0.35)),
    ];
    let mut best = (usize::MAX, SeriesLabelPosition::LowerRight);
    for (pos, (x0, x1), (y0, y1)) in corners {
        let n = points
            .iter()
            .filter(|p| (x0..=x1).contains(&p.0) && (y0..=y1).contains(&p.1))
            .count();
        if n < best.0 {
            best = (n, pos);
        }
    }
    best.1
}

/// Draws `series` into the drawing area `area`.
fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    axes: &Axes,
    series: &[Series],
) -> std::result::Result<(), String> {
    // Finite points, positive on logarithmic axes.
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|p| drawable(axes, p))
        .collect();
    if pts.is_empty() {
        return Err("no finite points to draw".into());
    }
    // Texts from the problem (title, units, interface names) bounded and cleaned.
    let (title, x_desc, y_desc) = (
        label_text(axes.title),
        label_text(axes.x),
        label_text(axes.y),
    );
    let ([x0, x1], [y0, y1]) = ranges(axes, &pts);
    let corner = legend_corner(&plotted_points(axes, series, &pts, [x0, x1], [y0, y1]));
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let x_step = (x1 - x0) / 10.0;
    let y_step = (y1 - y0) / 10.0;
    let x_fmt = |v: &f64| {
        if axes.log_x {
            tick_label(*v)
        } else {
            tick_label_step(*v, x_step)
        }
    };
    let y_fmt = |v: &f64| {
        if axes.log_y {
            tick_label(*v)
        } else {
            tick_label_step(*v, y_step)
        }
    };
    let (xb, xl) = log_ticks(x0, x1);
    let (yb, yl) = log_ticks(y0, y1);
    let n_x = if axes.log_x { xb.len() + 1 } else { 10 };
    let n_y = if axes.log_y { yb.len() + 1 } else { 10 };
    let log_x = || {
        (x0..x1)
            .log_scale()
            .with_key_points(xb.clone())
            .with_light_points(xl.clone())
    };
    let log_y = || {
        (y0..y1)
            .log_scale()
            .with_key_points(yb.clone())
            .with_light_points(yl.clone())
    };
    macro_rules! plot_with {
        ($xr:expr, $yr:expr) => {{
            let mut chart = ChartBuilder::on(area)
                .caption(&*title, ("sans-serif", 24))
                .margin(20)
                .x_label_area_size(50)
                .y_label_area_size(80)
                .build_cartesian_2d($xr, $yr)
                .map_err(|x| e(&x))?;
            chart
                .configure_mesh()
                .x_desc(&*x_desc)
                .y_desc(&*y_desc)
                .x_labels(n_x)
                .y_labels(n_y)
                .x_label_formatter(&x_fmt)
                .y_label_formatter(&y_fmt)
                .label_style(("sans-serif", 15))
                .draw()
                .map_err(|x| e(&x))?;
            for (i, s) in series.iter().enumerate() {
                let colour = if s.reference {
                    BLACK
                } else {
                    PALETTE[i % PALETTE.len()]
                };
                let data: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| drawable(axes, p))
                    .collect();
                let style = if s.reference {
                    colour.stroke_width(1)
                } else {
                    colour.stroke_width(2)
                };
                chart
                    .draw_series(LineSeries::new(data.clone(), style))
                    .map_err(|x| e(&x))?
                    .label(label_text(&s.name))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
                if !s.reference {
                    chart
                        .draw_series(data.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                        .map_err(|x| e(&x))?;
                }
            }
            chart
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.9))
                .label_font(("sans-serif", 15))
                .position(corner)
                .draw()
                .map_err(|x| e(&x))?;
        }};
    }
    match (axes.log_x, axes.log_y) {
        (true, true) => plot_with!(log_x(), log_y()),
        (true, false) => plot_with!(log_x(), y0..y1),
        (false, true) => plot_with!(x0..x1, log_y()),
        (false, false) => plot_with!(x0..x1, y0..y1),
    }
    Ok(())
}

/// Writes a line chart of `series` to `path` (PNG, 900 × 600).
pub fn line_chart(path: &Path, axes: &Axes, series: &[Series]) -> Result<()> {
    super::png::register_font();
    let (w, h) = (900u32, 600u32);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| Error::output(path, e))?;
        draw(&root, axes, series).map_err(|m| Error::output(path, m))?;
        root.present().map_err(|e| Error::output(path, e))?;
    }
    super::png::write_rgb(path, &buf, w, h)
}

/// Writes two charts side by side to `path` (PNG, 1400 × 600).
pub fn side_by_side(path: &Path, charts: [(&Axes, &[Series]); 2]) -> Result<()> {
    super::png::register_font();
    let (w, h) = (1400u32, 600u32);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| Error::output(path, e))?;
        let (left, right) = root.split_horizontally(w / 2);
        for (area, (axes, series)) in [left, right].iter().zip(charts) {
            draw(area, axes, series).map_err(|m| Error::output(path, m))?;
        }
        root.present().map_err(|e| Error::output(path, e))?;
    }
    super::png::write_rgb(path, &buf, w, h)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Titles, axis labels and legend names of any length are drawn.
    #[test]
    fn huge_texts_are_drawn_bounded() {
        // A chart whose title, axis labels and legend name are each a megabyte
        // with control characters is drawn (they are cut to MAX_LABEL_CHARS;
        // drawn whole the layout would not end).
        let dir = std::env::temp_dir().join(format!("cfe-chart-huge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let huge = "name\r\n".repeat(200_000);
        let axes = Axes {
            title: &huge,
            x: &huge,
            y: &huge,
            log_x: false,
            log_y: false,
        };
        let s = vec![Series {
            name: huge.clone(),
            points: vec![(0.0, 1.0), (1.0, 2.0)],
            reference: false,
        }];
        line_chart(&dir.join("h.png"), &axes, &s).unwrap();
        assert_eq!(&std::fs::read(dir.join("h.png")).unwrap()[..4], b"\x89PNG");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A log–log chart of two curves is written as a PNG; a chart with nothing
    /// drawable is an error.
    #[test]
    fn writes_and_rejects() {
        let dir = std::env::temp_dir().join(format!("cfe-chart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let axes = Axes {
            title: "t",
            x: "h",
            y: "error",
            log_x: true,
            log_y: true,
        };
        let s = vec![
            Series {
                name: "a".into(),
                points: vec![(1.0, 1.0), (0.5, 0.25)],
                reference: false,
            },
            Series {
                name: "h²".into(),
                points: vec![(1.0, 2.0), (0.5, 0.5)],
                reference: true,
            },
        ];
        line_chart(&dir.join("c.png"), &axes, &s).unwrap();
        assert_eq!(&std::fs::read(dir.join("c.png")).unwrap()[..4], b"\x89PNG");
        let empty = vec![Series {
            name: "z".into(),
            points: vec![(0.0, -1.0)],
            reference: false,
        }];
        assert!(line_chart(&dir.join("d.png"), &axes, &empty).is_err());
        assert_eq!(tick_label(0.7000000000001), "0.7");
        assert_eq!(tick_label(1e-7), "1e-7");
        assert_eq!(tick_label(250.0), "250");
        assert_eq!(tick_label_step(5.0000002, 1e-7), "5.0000002");
        assert_eq!(log_ticks(1.5, 9.0).0, vec![2.0, 3.0, 4.0, 5.0, 6.0, 8.0]);
        assert_eq!(
            log_ticks(1.0, 100.0).0,
            vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
