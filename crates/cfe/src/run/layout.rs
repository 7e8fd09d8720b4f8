//! The layout of a run's VTU files: which grid (points and cells) and which
//! named field arrays each file holds, taken from the analysis and an increment
//! and handed to the writer ([`crate::output::vtu`]) as plain data. The parts VTU
//! of an increment holds the parts' mesh with the displacement, the stresses,
//! von Mises and the part of each point and cell; the pairs VTU one vertex per
//! coupling pair with its state, law check, gap, slip, forces and contact fields.
//! Written once for both dimensions: what differs (cell kinds, stress
//! components, tangential fields) is asked of [`Layout`]. The plane fields are
//! laid out here (for `super::plane`); the solid ones in `super::solid`.

use super::dim::{Layout, StressField};
use super::stresses::Stresses;
use crate::analysis::Analysis;
use crate::coupling::PairState;
use crate::dim::{D2, Dim, Tangent};
use crate::domain::Part;
use crate::error::Result;
use crate::fem::ElementFamily;
use crate::mesh::{Element, MeshCell};
use crate::output::vtu;
use crate::results::PairRow;
use crate::solve::nonlinear::IncrementResult;
use std::path::Path;
use std::sync::atomic::AtomicUsize;

/// The parts' points and cells as written to every VTU of a run (checked and
/// encoded once), and the part of each point and cell.
pub struct PartsGrid {
    /// The points and cells, checked and encoded.
    pub(super) geometry: vtu::Geometry,
    /// The part of each point.
    pub(super) part_point: Vec<i32>,
    /// The part of each cell.
    pub(super) part_cell: Vec<i32>,
}

/// The field data of an increment's VTU files: the total time (step index − 1 +
/// load factor), the step's 1-based index and its load factor.
pub(super) fn time_fields<D: ElementFamily>(inc: &IncrementResult<D>) -> [(&'static str, f64); 3] {
    [
        ("TIME", inc.time),
        ("STEP", (inc.step + 1) as f64),
        ("LOAD_FACTOR", inc.lambda),
    ]
}

/// The names of the stress fields of the parts VTU, point and cell data alike.
const STRESS_FIELDS: [&str; 4] = ["sigma_xx", "sigma_yy", "sigma_xy", "von_mises"];

/// The stress fields of plane parts: σxx, σyy, σxy and von Mises, at the points
/// (nodal, recovered) and in the cells, each in the parts' order; then σθθ when
/// every part is axisymmetric ([`hoop_fields`]).
pub(super) fn plane_stress_fields(
    parts: &[Part],
    stresses: &Stresses,
    n_points: usize,
    n_cells: usize,
) -> Vec<StressField> {
    let mut nodal: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(n_points));
    let mut cell: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(n_cells));
    for (part, s) in parts.iter().zip(stresses.base.iter()) {
        let hoop = |h: Option<&Vec<f64>>, i: usize| h.map(|h| stresses.hoop_value(h[i]));
        for (i, v) in s.nodal.iter().enumerate() {
            let v = stresses.value(*v);
            for c in 0..3 {
                nodal[c].push(v[c]);
            }
            let h = hoop(s.hoop.as_ref().map(|h| &h.nodal), i);
            nodal[3].push(part.material.von_mises_with(v, h));
        }
        for (i, v) in s.element.iter().enumerate() {
            let v = stresses.value(*v);
            for c in 0..3 {
                cell[c].push(v[c]);
            }
            let h = hoop(s.hoop.as_ref().map(|h| &h.element), i);
            cell[3].push(part.material.von_mises_with(v, h));
        }
    }
    let mut fields: Vec<StressField> = (STRESS_FIELDS.into_iter().zip(nodal).zip(cell))
        .map(|((name, nodal), cell)| StressField { name, nodal, cell })
        .collect();
    if let Some((nodal, cell)) = hoop_fields(stresses) {
        fields.push(StressField {
            name: "sigma_theta",
            nodal,
            cell,
        });
    }
    fields
}

/// The hoop stress σθθ at the points and in the cells when every part is
/// axisymmetric (the model's `plane`), `None` otherwise (no such field).
fn hoop_fields(stresses: &Stresses) -> Option<(Vec<f64>, Vec<f64>)> {
    let (mut nodal, mut cell) = (Vec::new(), Vec::new());
    for s in stresses.base.iter() {
        let h = s.hoop.as_ref()?;
        nodal.extend(h.nodal.iter().map(|&v| stresses.hoop_value(v)));
        cell.extend(h.element.iter().map(|&v| stresses.hoop_value(v)));
    }
    (!stresses.base.is_empty()).then_some((nodal, cell))
}

/// The integer codes of the pairs VTU, one per pair: `bonded` (0/1), `settled`
/// (0/1), `violation` and `state`.
fn pair_codes(rows: &[PairRow]) -> [Vec<i32>; 4] {
    let bonded: Vec<i32> = rows
        .iter()
        .map(|r| (r.state == PairState::Bonded) as i32)
        .collect();
    let settled: Vec<i32> = rows.iter().map(|r| r.settled as i32).collect();
    // `PairRow::violation_code`: 0 the law holds, 1–4 one violation, 5 two.
    let violation: Vec<i32> = rows.iter().map(PairRow::violation_code).collect();
    // 0: open, 1: bonded (stick), 2: slip.
    let state: Vec<i32> = rows
        .iter()
        .map(|r| match r.state {
            PairState::Open => 0,
            PairState::Bonded => 1,
            PairState::Slip => 2,
        })
        .collect();
    [bonded, settled, violation, state]
}

/// The VTK kind of a plane element.
pub(super) fn plane_cell_kind(el: &Element) -> vtu::CellKind {
    match el {
        Element::T3(_) => vtu::CellKind::Triangle,
        Element::Q4(_) => vtu::CellKind::Quad,
    }
}

/// The plane layout of a tangential quantity `t` in the pairs VTU: its one
/// component along s, as the pairs table states it.
pub(super) fn plane_tangent(_: &<D2 as Dim>::Frame, t: f64, out: &mut Vec<f64>) {
    out.push(t);
}

/// A tangential quantity of a pair given by its components along the frame's
/// tangents (`first`, then `second` where the dimension has one).
fn tangent_of<T: Tangent>(first: f64, second: Option<f64>) -> T {
    let mut t = T::default();
    t.set_component(0, first);
    if T::COMPONENTS > 1 {
        t.set_component(1, second.unwrap_or(0.0));
    }
    t
}

impl<D: Layout> Analysis<D> {
    /// Every node of every part, in the global node numbering.
    pub(super) fn global_points(&self) -> Vec<D::Vector> {
        self.model
            .parts
            .iter()
            .flat_map(|p| p.mesh.nodes.iter().copied())
            .collect()
    }

    /// The cells of every part in global node numbers, as the VTU grid holds
    /// them: connectivity, end offsets and kinds.
    pub(super) fn global_cells(&self) -> (Vec<usize>, Vec<usize>, Vec<vtu::CellKind>) {
        let n_cells: usize = self.model.parts.iter().map(|p| p.mesh.elements.len()).sum();
        let mut connectivity = Vec::with_capacity(4 * n_cells);
        let mut offsets = Vec::with_capacity(n_cells);
        let mut kinds = Vec::with_capacity(n_cells);
        for (p, part) in self.model.parts.iter().enumerate() {
            let o = self.dofs.node_offset[p];
            for el in &part.mesh.elements {
                connectivity.extend(el.nodes().iter().map(|n| n + o));
                offsets.push(connectivity.len());
                kinds.push(D::cell_kind(el));
            }
        }
        (connectivity, offsets, kinds)
    }

    /// The parts' geometry for the VTU files, built once per run (at its first
    /// written increment).
    pub(super) fn parts_grid(&self) -> PartsGrid {
        let n_cells: usize = self.model.parts.iter().map(|p| p.mesh.elements.len()).sum();
        let mut part_point = Vec::with_capacity(self.dofs.n_nodes());
        let mut part_cell = Vec::with_capacity(n_cells);
        for (p, part) in self.model.parts.iter().enumerate() {
            part_point.extend(std::iter::repeat_n(p as i32, part.mesh.nodes.len()));
            part_cell.extend(std::iter::repeat_n(p as i32, part.mesh.elements.len()));
        }
        let (connectivity, offsets, kinds) = self.global_cells();
        PartsGrid {
            geometry: vtu::Geometry::new(&self.global_points(), &connectivity, &offsets, &kinds),
            part_point,
            part_cell,
        }
    }

    /// Writes the parts VTU of an increment at `path`: on `grid`, the
    /// displacement `u` (`D::N` components), the `stresses`
    /// ([`Layout::stress_fields`]) and the part of each point and cell, with the
    /// increment's time `fields`.
    pub(super) fn write_parts_vtu(
        &self,
        path: &Path,
        grid: &PartsGrid,
        fields: &[(&str, f64)],
        u: &[f64],
        stresses: &Stresses<D::Stress>,
        stop: &AtomicUsize,
    ) -> Result<()> {
        let (part_point, part_cell) = (&grid.part_point, &grid.part_cell);
        let stress = D::stress_fields(
            &self.model.parts,
            stresses,
            part_point.len(),
            part_cell.len(),
        );
        let mut point_data = vec![vtu::DataArray {
            name: "displacement",
            components: D::N,
            values: vtu::Values::F64(u),
        }];
        for f in &stress {
            point_data.push(vtu::DataArray {
                name: f.name,
                components: 1,
                values: vtu::Values::F64(&f.nodal),
            });
        }
        point_data.push(vtu::DataArray {
            name: "part_id",
            components: 1,
            values: vtu::Values::I32(part_point),
        });
        let mut cell_data: Vec<vtu::DataArray> = stress
            .iter()
            .map(|f| vtu::DataArray {
                name: f.name,
                components: 1,
                values: vtu::Values::F64(&f.cell),
            })
            .collect();
        cell_data.push(vtu::DataArray {
            name: "part_id",
            components: 1,
            values: vtu::Values::I32(part_cell),
        });
        vtu::write_on_until(
            path,
            &grid.geometry,
            &vtu::Fields {
                point_data: &point_data,
                cell_data: &cell_data,
                field_data: fields,
            },
            stop,
        )
    }

    /// The unit normal (`D::N` components), the interface number and the
    /// displacement of the coupling node of every pair, in the order of the
    /// pairs table.
    fn pair_geometry(&self, inc: &IncrementResult<D>, n: usize) -> (Vec<f64>, Vec<i32>, Vec<f64>) {
        let mut normal = Vec::with_capacity(D::N * n);
        let mut iface_id = Vec::with_capacity(n);
        let mut disp = Vec::with_capacity(D::N * n);
        for (i, iface) in self.interfaces.iter().enumerate() {
            for c in &iface.elements {
                normal.extend_from_slice(c.normal.as_ref());
                iface_id.push(i as i32);
                let g = self.dofs.node(iface.node_part, c.node);
                disp.extend_from_slice(&inc.u[D::dof(g, 0)..D::dof(g + 1, 0)]);
            }
        }
        (normal, iface_id, disp)
    }

    /// The tangential quantities of the pairs VTU, laid out by
    /// [`Layout::tangent_field`] (one component along s in 2D; vectors in
    /// global components in 3D): the tangential jump (`slip_s`), the
    /// tangential force (`force_s`), the slip not carried elastically
    /// (`slip`) and the shear traction (`shear`), in this order.
    fn pair_tangents(&self, rows: &[PairRow]) -> [Vec<f64>; 4] {
        let n = D::TANGENT_FIELD * rows.len();
        let mut out: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(n));
        let frames = (self.interfaces.iter()).flat_map(|i| i.elements.iter().map(|c| &c.frame));
        for (frame, r) in frames.zip(rows) {
            let quantities = [
                (r.slip_s, r.slip_t2),
                (r.force_s, r.force_t2),
                (r.slip, r.slip_t2_plastic),
                (r.shear, r.shear_t2),
            ];
            for (o, (first, second)) in out.iter_mut().zip(quantities) {
                D::tangent_field(frame, tangent_of(first, second), o);
            }
        }
        out
    }

    /// Writes the pairs VTU of increment `inc` at `path`: one vertex per pair
    /// (the rows of the pairs table) with its fields.
    pub(super) fn write_pairs_vtu(
        &self,
        path: &Path,
        inc: &IncrementResult<D>,
        rows: &[PairRow],
    ) -> Result<()> {
        let points: Vec<D::Vector> = (self.interfaces.iter())
            .flat_map(|i| i.elements.iter().map(|c| c.position))
            .collect();
        let connectivity: Vec<usize> = (0..rows.len()).collect();
        let offsets: Vec<usize> = (1..=rows.len()).collect();
        let kinds: Vec<vtu::CellKind> = rows.iter().map(|_| vtu::CellKind::Vertex).collect();
        let [bonded, settled, violation, state] = pair_codes(rows);
        // A pair's first violation's amount (the normal one, for code 5: the
        // friction one is its |force_s|).
        let violation_amount: Vec<f64> = rows
            .iter()
            .map(|r| r.violation_amount.first().copied().unwrap_or(0.0))
            .collect();
        let col = |f: fn(&PairRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
        let [slip_s, force_s, slip, shear] = self.pair_tangents(rows);
        let (gap, fn_) = (col(|r| r.gap_n), col(|r| r.force_n));
        let contact = [
            ("gap0", col(|r| r.gap0), 1),
            ("gap", col(|r| r.gap), 1),
            ("slip", slip, D::TANGENT_FIELD),
            ("pressure", col(|r| r.pressure), 1),
            ("shear", shear, D::TANGENT_FIELD),
            ("tributary", col(|r| r.tributary), 1),
        ];
        let (normal, iface_id, disp) = self.pair_geometry(inc, rows.len());
        let mut point_data = vec![
            vtu::DataArray::f64("displacement", D::N, &disp),
            vtu::DataArray::i32("bonded", &bonded),
            vtu::DataArray::i32("settled", &settled),
            vtu::DataArray::i32("violation", &violation),
            vtu::DataArray::f64("violation_amount", 1, &violation_amount),
            vtu::DataArray::f64("gap_n", 1, &gap),
            vtu::DataArray::f64("slip_s", D::TANGENT_FIELD, &slip_s),
            vtu::DataArray::f64("force_n", 1, &fn_),
            vtu::DataArray::f64("force_s", D::TANGENT_FIELD, &force_s),
            vtu::DataArray::f64("normal", D::N, &normal),
            vtu::DataArray::i32("interface_id", &iface_id),
            vtu::DataArray::i32("state", &state),
        ];
        for (name, values, components) in &contact {
            point_data.push(vtu::DataArray::f64(name, *components, values));
        }
        let force = D::pair_force_field(rows);
        if let Some(force) = &force {
            point_data.push(vtu::DataArray::f64("force", D::N, force));
        }
        vtu::write_vtu(
            path,
            &vtu::Grid {
                points: &points,
                connectivity: &connectivity,
                offsets: &offsets,
                kinds: &kinds,
                point_data: &point_data,
                cell_data: &[],
                field_data: &time_fields(inc),
            },
        )
    }
}
