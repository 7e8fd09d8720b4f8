//! The pictures of a plane run's last increment, laid out from the analysis and
//! handed to the drawing routines ([`crate::output::png`], [`crate::output::chart`])
//! as plain data: `sigma_yy.png` (σyy over the parts, pairs marked),
//! `displacement.png` (|u| isolines on the deformed shape) and, with a contact
//! law, `pressure.png` (the contact pressure along each interface); and
//! `history.png`, drawn alike in both dimensions (a solid run's other pictures
//! are `super::solid`'s).

use super::stresses::Stresses;
use crate::analysis::{Analysis, AnalysisDim};
use crate::coupling::{Law, PairState};
use crate::error::Result;
use crate::mesh::Element;
use crate::output::{chart, png};
use crate::results::PairRow;
use crate::results::history::{self, HistoryRow};
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;

/// The marker of the pair of `row`, drawn at `at`.
fn marker(row: &PairRow, at: [f64; 2]) -> png::PairMarker {
    png::PairMarker {
        at,
        bonded: row.state.is_closed(),
        slip: row.state == PairState::Slip,
        violates: row.breaks_law(),
    }
}

/// The deformed shape of `points` under the displacements `u` (two per point),
/// magnified so the largest displacement is 5 % of the model size: the
/// displacement magnitude at each point, the magnification and the deformed
/// points.
fn deformed_shape(points: &[[f64; 2]], u: &[f64]) -> (Vec<f64>, f64, Vec<[f64; 2]>) {
    let magnitude: Vec<f64> = (0..points.len())
        .map(|g| u[2 * g].hypot(u[2 * g + 1]))
        .collect();
    let umax = magnitude.iter().copied().fold(0.0, f64::max);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let scale = if umax > 0.0 {
        png::nice_floor(0.05 * size / umax)
    } else {
        0.0
    };
    let deformed: Vec<[f64; 2]> = points
        .iter()
        .enumerate()
        .map(|(g, p)| [p[0] + scale * u[2 * g], p[1] + scale * u[2 * g + 1]])
        .collect();
    (magnitude, scale, deformed)
}

impl Analysis {
    /// Every element as triangles in global node numbers, for the pictures: a Q4
    /// is split along its diagonal 1–3 (the picture interpolates linearly).
    fn plot_triangles(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for (p, part) in self.model.parts.iter().enumerate() {
            let o = self.dofs.node_offset[p];
            for el in &part.mesh.elements {
                match *el {
                    Element::T3(t) => out.push(t.map(|n| n + o)),
                    Element::Q4([a, b, c, d]) => {
                        out.push([a + o, b + o, c + o]);
                        out.push([a + o, c + o, d + o]);
                    }
                }
            }
        }
        out
    }

    /// Draws the pictures of increment `inc` into `out`: `sigma_yy.png` and
    /// `displacement.png` in parallel, then `pressure.png`. `proceed` is asked
    /// between the drawing's stages.
    pub(super) fn write_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult,
        stresses: &Stresses,
        proceed: png::Proceed<'_>,
    ) -> Result<()> {
        let points = self.global_points();
        let tris = self.plot_triangles();
        let outline = png::outline_edges(&tris);
        let syy: Vec<f64> = stresses
            .base
            .iter()
            .flat_map(|s| s.nodal.iter().map(|v| stresses.value(*v)[1]))
            .collect();
        let rows = self.pair_rows(inc);
        let markers: Vec<png::PairMarker> = rows.iter().map(|r| marker(r, [r.x, r.y])).collect();
        let units = &self.model.units;
        let broken = rows.iter().filter(|r| r.breaks_law()).count();
        let note = if broken > 0 {
            format!(" ({broken} pair(s) break the contact law: red squares)")
        } else {
            String::new()
        };
        let title = format!("{}: σyy{note}", self.model.title);
        let mesh = png::PlotMesh {
            points: &points,
            triangles: &tris,
            outline: Some(&outline),
        };
        // The two pictures are drawn in parallel.
        let field = || {
            png::render_field(
                &out.join("sigma_yy.png"),
                &mesh,
                &syy,
                &markers,
                &png::PlotLabels {
                    title: &title,
                    colorbar: &format!("σyy [{}]", units.stress),
                    axis_unit: &units.length,
                },
                proceed,
            )
        };
        let isolines = || self.write_displacement_picture(out, inc, &mesh, &rows, &note, proceed);
        let (a, b) = rayon::join(field, isolines);
        a.and(b)?;
        proceed()?;
        self.write_pressure_chart(out, &rows).map(|_| ())
    }

    /// `displacement.png`: isolines of |u| of increment `inc` on the deformed
    /// shape of `mesh` ([`deformed_shape`]), the pairs of `rows` marked where
    /// their coupling nodes moved; `note` ends the title.
    fn write_displacement_picture(
        &self,
        out: &Path,
        inc: &IncrementResult,
        mesh: &png::PlotMesh,
        rows: &[PairRow],
        note: &str,
        proceed: png::Proceed<'_>,
    ) -> Result<()> {
        let (magnitude, scale, deformed) = deformed_shape(mesh.points, &inc.u);
        let deformed_markers: Vec<png::PairMarker> = self
            .interfaces
            .iter()
            .flat_map(|iface| {
                iface
                    .elements
                    .iter()
                    .map(move |c| self.dofs.node(iface.node_part, c.node))
            })
            .zip(rows)
            .map(|(g, r)| marker(r, deformed[g]))
            .collect();
        let title = format!(
            "{}: total displacement, deformed ×{scale}{note}",
            self.model.title
        );
        let units = &self.model.units;
        png::render_isolines(
            &out.join("displacement.png"),
            &png::PlotMesh {
                points: &deformed,
                triangles: mesh.triangles,
                outline: mesh.outline,
            },
            &magnitude,
            12,
            &deformed_markers,
            &png::PlotLabels {
                title: &title,
                colorbar: &format!("|u| [{}]", units.length),
                axis_unit: &units.length,
            },
            proceed,
        )
    }

    /// `pressure.png`: the contact pressure of every pair along each interface
    /// with a contact law (one curve per interface, against x, or y where the
    /// interface spans more in y), and its shear traction (dashed) where the law
    /// carries shear; `false` when no interface has a contact law
    /// with pairs.
    fn write_pressure_chart(&self, out: &Path, rows: &[PairRow]) -> Result<bool> {
        let mut series = Vec::new();
        let mut along_y = 0;
        for iface in self.interfaces.iter().filter(|i| i.law != Law::Rigid) {
            let mine: Vec<&PairRow> = rows.iter().filter(|r| r.interface == iface.name).collect();
            // An interface without pairs has no curve (a chart of no curve is
            // not drawn): never a failed picture.
            if mine.is_empty() {
                continue;
            }
            let span = |f: fn(&PairRow) -> f64| {
                let (lo, hi) = mine
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                        (lo.min(f(r)), hi.max(f(r)))
                    });
                hi - lo
            };
            let use_y = span(|r| r.y) > span(|r| r.x);
            along_y += usize::from(use_y);
            let mut points: Vec<(f64, f64)> = mine
                .iter()
                .map(|r| (if use_y { r.y } else { r.x }, r.pressure))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            series.push(chart::Series {
                name: iface.name.clone(),
                points,
                reference: false,
            });
            // The shear traction beside it (dashed) where the law carries
            // shear (the seed's stick law, Coulomb).
            if matches!(iface.law, Law::Contact | Law::Coulomb) {
                let mut shear: Vec<(f64, f64)> = mine
                    .iter()
                    .map(|r| (if use_y { r.y } else { r.x }, r.shear))
                    .collect();
                shear.sort_by(|a, b| a.0.total_cmp(&b.0));
                series.push(chart::Series {
                    name: format!("{} (shear)", iface.name),
                    points: shear,
                    reference: true,
                });
            }
        }
        if series.is_empty() {
            return Ok(false);
        }
        let units = &self.model.units;
        let curves = series.iter().filter(|s| !s.reference).count();
        let axis = if along_y == curves { "y" } else { "x" };
        chart::line_chart(
            &out.join("pressure.png"),
            &chart::Axes {
                title: &format!(
                    "{}: contact pressure and shear traction along the interface",
                    self.model.title
                ),
                x: &format!("{axis} [{}]", units.length),
                y: &format!("traction [{}]", units.stress),
                log_x: false,
                log_y: false,
            },
            &series,
        )?;
        Ok(true)
    }
}

/// `history.png`, drawn the same way for both dimensions.
impl<D: AnalysisDim> Analysis<D> {
    /// Draws `history.png`: the two history columns `[output] history_plot`
    /// names (x, y), or [`history::default_plot`]'s (the largest reaction
    /// against the first probe's displacement in its direction, or the time),
    /// one curve per step, each from where the previous step ended.
    pub(super) fn write_history_chart(&self, out: &Path, rows: &[HistoryRow]) -> Result<()> {
        let [x, y] = self
            .model
            .history_plot
            .clone()
            .or_else(|| history::default_plot(rows))
            .unwrap_or_else(|| ["time".to_string(), "load_factor".to_string()]);
        let cols = history::columns(rows);
        let (Some(xs), Some(ys)) = (history::numbers(&cols, &x), history::numbers(&cols, &y))
        else {
            return Ok(());
        };
        let mut series: Vec<chart::Series> = Vec::new();
        let mut last: Option<(f64, f64)> = None;
        for (k, r) in rows.iter().enumerate() {
            let p = (xs[k], ys[k]);
            match series.last_mut() {
                Some(s) if s.name == r.step => s.points.push(p),
                _ => series.push(chart::Series {
                    name: r.step.clone(),
                    points: last.into_iter().chain([p]).collect(),
                    reference: false,
                }),
            }
            last = Some(p);
        }
        let units = &self.model.units;
        let label = |c: &str| {
            let unit = match c.rsplit('.').next().unwrap_or("") {
                "fx" | "fy" | "fz" | "force_n" | "force_s" => Some(&units.force),
                "ux" | "uy" | "uz" | "contact_length" => Some(&units.length),
                "max_pressure" => Some(&units.stress),
                _ => None,
            };
            match unit {
                Some(u) if c.contains(':') => format!("{c} [{u}]"),
                _ => c.to_string(),
            }
        };
        chart::line_chart(
            &out.join("history.png"),
            &chart::Axes {
                title: &format!("{}: history", self.model.title),
                x: &label(&x),
                y: &label(&y),
                log_x: false,
                log_y: false,
            },
            &series,
        )
    }
}
