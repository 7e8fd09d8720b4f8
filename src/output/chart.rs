//! Line charts (linear or logarithmic axes) for reports: convergence plots and
//! benchmark curves, drawn with plotters on the bundled font and written as PNG.

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

/// Draws `series` into a `width` × `height` area of `root`.
fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    axes: &Axes,
    series: &[Series],
) -> std::result::Result<(), String> {
    // Finite points, positive on logarithmic axes.
    let drawable = |p: &(f64, f64)| {
        p.0.is_finite()
            && p.1.is_finite()
            && (!axes.log_x || p.0 > 0.0)
            && (!axes.log_y || p.1 > 0.0)
    };
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(drawable)
        .collect();
    if pts.is_empty() {
        return Err("no finite points to draw".into());
    }
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
            *lo *= 0.7;
            *hi *= 1.4;
        } else {
            let pad = 0.05 * (*hi - *lo).abs().max(1e-12 * hi.abs().max(1.0));
            *lo -= pad;
            *hi += pad;
        }
    };
    widen(&mut x0, &mut x1, axes.log_x);
    widen(&mut y0, &mut y1, axes.log_y);
    let e = |e: &dyn std::fmt::Display| e.to_string();
    macro_rules! plot_with {
        ($xr:expr, $yr:expr) => {{
            let mut chart = ChartBuilder::on(area)
                .caption(axes.title, ("sans-serif", 24))
                .margin(20)
                .x_label_area_size(50)
                .y_label_area_size(80)
                .build_cartesian_2d($xr, $yr)
                .map_err(|x| e(&x))?;
            chart
                .configure_mesh()
                .x_desc(axes.x)
                .y_desc(axes.y)
                .label_style(("sans-serif", 15))
                .draw()
                .map_err(|x| e(&x))?;
            for (i, s) in series.iter().enumerate() {
                let colour = if s.reference {
                    BLACK
                } else {
                    PALETTE[i % PALETTE.len()]
                };
                let data: Vec<(f64, f64)> = s.points.iter().copied().filter(drawable).collect();
                let style = if s.reference {
                    colour.stroke_width(1)
                } else {
                    colour.stroke_width(2)
                };
                chart
                    .draw_series(LineSeries::new(data.clone(), style))
                    .map_err(|x| e(&x))?
                    .label(s.name.clone())
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
                .background_style(WHITE)
                .label_font(("sans-serif", 15))
                .position(SeriesLabelPosition::LowerRight)
                .draw()
                .map_err(|x| e(&x))?;
        }};
    }
    match (axes.log_x, axes.log_y) {
        (true, true) => plot_with!((x0..x1).log_scale(), (y0..y1).log_scale()),
        (true, false) => plot_with!((x0..x1).log_scale(), y0..y1),
        (false, true) => plot_with!(x0..x1, (y0..y1).log_scale()),
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
        let _ = std::fs::remove_dir_all(&dir);
    }
}
