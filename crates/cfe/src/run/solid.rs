//! What a solid (3D) run writes of its own, the [`Layout`] of [`D3`]:
//!
//! - the parts VTU's cells are VTK tetrahedra and hexahedra, its stress fields
//!   the six components `sigma_xx`, `sigma_yy`, `sigma_zz`, `sigma_xy`,
//!   `sigma_yz`, `sigma_xz` and `von_mises` (points and cells);
//! - the pairs VTU's tangential quantities (`slip_s`, `force_s`, `slip`,
//!   `shear`) are 3-vectors in global components (in the pair's tangent plane,
//!   the same whatever its tangents t₁, t₂), and `force` is the force on the
//!   node part;
//! - the pictures: `deformed.png`, the deformed parts seen from the isometric
//!   view with z up ([`VIEW`]: the eye along (1, −1, 1)) or from the axis
//!   `[output] view` names, coloured by the nodal von Mises stress or the
//!   stress or displacement `[output] component` names, hidden faces removed; `pressure_<k>.png`, the contact
//!   pressure over interface k (1-based, in the model's order) for each
//!   interface with a contact law whose pairs span a plane; and `history.png`
//!   as a plane run's.
//!
//! Line probes are plane only: a solid model has none.

use super::dim::{Layout, StressField};
use super::stresses::Stresses;
use crate::analysis::Analysis;
use crate::coupling::Law;
use crate::dim::{D3, Dim};
use crate::domain::Part;
use crate::error::Result;
use crate::fem::material::von_mises_3d;
use crate::mesh::SolidElement;
use crate::model::{PictureField, ViewPoint};
use crate::output::folder::{PICTURES, SOLID_PICTURES, pressure_map_file};
use crate::output::png::Proceed;
use crate::output::view3d::{self, Axis, Magnification, View};
use crate::output::vtu::CellKind;
use crate::results::{PairRow, SOLID_PAIR_COLUMNS};
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;

/// The names of a solid part's stress fields, in the Voigt order of its
/// stresses (xx, yy, zz, xy, yz, zx), then von Mises.
const SOLID_STRESS_FIELDS: [&str; 7] = [
    "sigma_xx",
    "sigma_yy",
    "sigma_zz",
    "sigma_xy",
    "sigma_yz",
    "sigma_xz",
    "von_mises",
];

/// The viewpoint of `deformed.png`: isometric, z up (the eye along
/// (1, −1, 1): x to the right and towards the eye, y away, z up).
pub const VIEW: View = View {
    azimuth_deg: 45.0,
    elevation_deg: View::ISOMETRIC_ELEVATION_DEG,
    up: Axis::Z,
};

/// The view of `deformed.png` from `view`: [`VIEW`] (isometric), or from an
/// axis, z up: from ±x or ±y at elevation 0 (azimuth 90° for +x, −90° for
/// −x, 180° for +y, 0 for −y: the front view), from ±z at elevation ±90°.
fn view_of(view: ViewPoint) -> View {
    let (azimuth_deg, elevation_deg) = match view {
        ViewPoint::Isometric => return VIEW,
        ViewPoint::Axis(0, true) => (90.0, 0.0),
        ViewPoint::Axis(0, false) => (-90.0, 0.0),
        ViewPoint::Axis(1, true) => (180.0, 0.0),
        ViewPoint::Axis(1, false) => (0.0, 0.0),
        ViewPoint::Axis(_, true) => (0.0, 90.0),
        ViewPoint::Axis(_, false) => (0.0, -90.0),
    };
    View {
        azimuth_deg,
        elevation_deg,
        up: Axis::Z,
    }
}

/// The title words of the field `deformed.png` is coloured by.
fn field_title(field: PictureField) -> String {
    let xyz = ["x", "y", "z"];
    match field {
        PictureField::VonMises => "von Mises stress".into(),
        PictureField::Stress(k) => format!("stress σ_{}", STRESS_INDICES[k]),
        PictureField::Displacement(c) => format!("displacement u_{}", xyz[c]),
        PictureField::DisplacementMagnitude => "displacement magnitude |u|".into(),
    }
}

/// The colour bar's label of the field `deformed.png` is coloured by.
fn field_label(field: PictureField, units: &crate::model::Units) -> String {
    let xyz = ["x", "y", "z"];
    match field {
        PictureField::VonMises => format!("σ_vM [{}]", units.stress),
        PictureField::Stress(k) => format!("σ_{} [{}]", STRESS_INDICES[k], units.stress),
        PictureField::Displacement(c) => format!("u_{} [{}]", xyz[c], units.length),
        PictureField::DisplacementMagnitude => format!("|u| [{}]", units.length),
    }
}

/// The indices of the six stress components in Voigt order.
const STRESS_INDICES: [&str; 6] = ["xx", "yy", "zz", "xy", "yz", "xz"];

/// The six stress components and von Mises of `stresses` at the points and in
/// the cells, in the parts' order.
fn solid_stress_fields(
    stresses: &Stresses<[f64; 6]>,
    n_points: usize,
    n_cells: usize,
) -> Vec<StressField> {
    let mut nodal: [Vec<f64>; 7] = std::array::from_fn(|_| Vec::with_capacity(n_points));
    let mut cell: [Vec<f64>; 7] = std::array::from_fn(|_| Vec::with_capacity(n_cells));
    for s in stresses.base.iter() {
        for (out, values) in [(&mut nodal, &s.nodal), (&mut cell, &s.element)] {
            for v in values {
                let v = stresses.value(*v);
                for c in 0..6 {
                    out[c].push(v[c]);
                }
                out[6].push(von_mises_3d(&v));
            }
        }
    }
    (SOLID_STRESS_FIELDS.into_iter().zip(nodal).zip(cell))
        .map(|((name, nodal), cell)| StressField { name, nodal, cell })
        .collect()
}

/// Solid models: TET4/HEX8 cells, the six stresses and von Mises, tangential
/// quantities as global vectors, `deformed.png` and a pressure map per contact
/// interface; no line probes.
impl Layout for D3 {
    const TANGENT_FIELD: usize = 3;
    const PAIR_COLUMNS: &'static [&'static str] = &SOLID_PAIR_COLUMNS;

    fn cell_kind(cell: &SolidElement) -> CellKind {
        match cell {
            SolidElement::Tet4(_) => CellKind::Tetra,
            SolidElement::Hex8(_) => CellKind::Hexahedron,
        }
    }

    fn stress_fields(
        _: &[Part<D3>],
        stresses: &Stresses<[f64; 6]>,
        n_points: usize,
        n_cells: usize,
    ) -> Vec<StressField> {
        solid_stress_fields(stresses, n_points, n_cells)
    }

    /// `t₁ t_1 + t₂ t_2` of `frame`: the vector in global components.
    fn tangent_field(frame: &[[f64; 3]; 3], t: [f64; 2], out: &mut Vec<f64>) {
        out.extend(D3::to_global(frame, 0.0, t));
    }

    fn pair_force_field(rows: &[PairRow]) -> Option<Vec<f64>> {
        let mut force = Vec::with_capacity(3 * rows.len());
        for r in rows {
            force.extend([r.force_x?, r.force_y?, r.force_z?]);
        }
        Some(force)
    }

    fn pictures(analysis: &Analysis<D3>) -> Vec<String> {
        let mut names: Vec<String> = SOLID_PICTURES.map(String::from).to_vec();
        names.extend((analysis.pressure_maps().into_iter()).map(|k| pressure_map_file(k + 1)));
        names.push(PICTURES[3].to_string());
        names
    }

    fn write_pictures(
        analysis: &Analysis<D3>,
        out: &Path,
        inc: &IncrementResult<D3>,
        stresses: &Stresses<[f64; 6]>,
        proceed: Proceed<'_>,
    ) -> Result<()> {
        analysis.write_solid_pictures(out, inc, stresses, proceed)
    }
}

impl Analysis<D3> {
    /// The interfaces (indices in the model's order) whose contact pressure is
    /// mapped: those with a contact law whose pairs' positions span a plane
    /// ([`view3d::spans_plane`]).
    fn pressure_maps(&self) -> Vec<usize> {
        (self.interfaces.iter().enumerate())
            .filter(|(_, i)| i.law != Law::Rigid)
            .filter(|(_, i)| {
                let points: Vec<[f64; 3]> = i.elements.iter().map(|c| c.position).collect();
                view3d::spans_plane(&points)
            })
            .map(|(k, _)| k)
            .collect()
    }

    /// Draws `deformed.png` and the pressure maps of increment `inc` into
    /// `out` (see the [module](self)); `proceed` is asked between the
    /// drawing's stages.
    fn write_solid_pictures(
        &self,
        out: &Path,
        inc: &IncrementResult<D3>,
        stresses: &Stresses<[f64; 6]>,
        proceed: Proceed<'_>,
    ) -> Result<()> {
        let path = out.join(SOLID_PICTURES[0]);
        let points = self.global_points();
        let (connectivity, offsets, kinds) = self.global_cells();
        let faces = view3d::boundary_faces(&path, points.len(), &connectivity, &offsets, &kinds)?;
        drop((connectivity, offsets, kinds));
        let u: Vec<[f64; 3]> = (0..points.len())
            .map(|g| std::array::from_fn(|c| inc.u[D3::dof(g, c)]))
            .collect();
        let picture = self.model.picture;
        let stress = |f: &dyn Fn(&[f64; 6]) -> f64| -> Vec<f64> {
            (stresses.base.iter())
                .flat_map(|s| s.nodal.iter().map(|v| f(&stresses.value(*v))))
                .collect()
        };
        let values: Vec<f64> = match picture.field {
            PictureField::VonMises => stress(&von_mises_3d),
            PictureField::Stress(k) => stress(&|s| s[k]),
            PictureField::Displacement(c) => u.iter().map(|v| v[c]).collect(),
            PictureField::DisplacementMagnitude => {
                u.iter().map(|v| v[0].hypot(v[1]).hypot(v[2])).collect()
            }
        };
        let rows = self.pair_rows(inc);
        let broken = rows.iter().filter(|r| r.breaks_law()).count();
        let note = if broken > 0 {
            format!(" ({broken} pair(s) break the contact law: see pairs.csv)")
        } else {
            String::new()
        };
        let units = &self.model.units;
        view3d::render_view(
            &path,
            &view3d::Surface {
                points: &points,
                faces: &faces,
                values: &values,
                displacement: Some(&u),
            },
            &view_of(picture.view),
            Magnification::Auto,
            &view3d::ViewLabels {
                title: &format!("{}: {}{note}", self.model.title, field_title(picture.field)),
                colorbar: &field_label(picture.field, units),
            },
            proceed,
        )?;
        for k in self.pressure_maps() {
            proceed()?;
            let iface = &self.interfaces[k];
            let mine: Vec<&PairRow> = rows.iter().filter(|r| r.interface == iface.name).collect();
            let positions: Vec<[f64; 3]> = iface.elements.iter().map(|c| c.position).collect();
            let pressure: Vec<f64> = mine.iter().map(|r| r.pressure).collect();
            view3d::render_pressure_map(
                &out.join(pressure_map_file(k + 1)),
                &view3d::PressureMap {
                    points: &positions,
                    pressure: &pressure,
                },
                &view3d::MapLabels {
                    title: &format!(
                        "{}: contact pressure on interface '{}'",
                        self.model.title, iface.name
                    ),
                    colorbar: &format!("p [{}]", units.stress),
                    axis_unit: &units.length,
                },
                proceed,
            )?;
        }
        Ok(())
    }
}
