//! The builder of a solid model (`Model<D3>`): a problem file whose parts are
//! `box`es or 3D Gmsh meshes, its supports fixing any of x, y, z (on a named
//! surface, at a node, or on the surface nodes inside a box; prescribed
//! values), its loads (point forces, resultants, pressures and tractions on
//! named surfaces, over the whole surface or its part inside a box, a face the
//! box cuts clipped to it and integrated exactly), its probes (interpolated in
//! their element) and the `[output]` choice of `deformed.png`'s view and
//! colouring. Interfaces,
//! steps, names and the `[output]` keys are resolved as in a plane model
//! ([`super::build`]): the schema is the plane one with a third component.

use super::build::{Builder, check_size_of, names, spread_equally, step_of, steps};
use super::schema::{
    BoxSpec, Component, GmshSpec, GroupSpec, LoadSpec, MaterialSpec, OutputSpec, PartSpec,
    ProbeSpec, ProblemFile, SupportSpec,
};
use super::{Load, Model, Part, Picture, PictureField, Probe, Step, Support, ViewPoint, check};
use crate::coupling::volume;
use crate::dim::D3;
use crate::domain::FaceLoad;
use crate::error::{Error, Result};
use crate::fem::{Material, PlaneKind, loads};
use crate::mesh::gmsh::{GmshMesh3d, Group};
use crate::mesh::{BoundaryFace, Mesh, distance3};
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use std::rc::Rc;
use toml::Spanned;

/// The mean edge length of the faces of boundary `boundary` of `mesh` (of all
/// its boundary faces when it has no such boundary, of its longest edge when it
/// has no face): the size h of the stiffness scale E·h of an interface.
pub(super) fn mean_face_edge(mesh: &Mesh<D3>, boundary: &str) -> f64 {
    let all;
    let faces = match mesh.boundaries.get(boundary) {
        Some(f) if !f.is_empty() => f.as_slice(),
        _ => {
            all = mesh.boundary_faces();
            all.as_slice()
        }
    };
    let (mut sum, mut count) = (0.0, 0usize);
    for f in faces {
        let n = f.nodes.as_slice();
        for (k, &a) in n.iter().enumerate() {
            sum += distance3(mesh.nodes[a], mesh.nodes[n[(k + 1) % n.len()]]);
            count += 1;
        }
    }
    if count == 0 {
        mesh.max_edge_length()
    } else {
        sum / count as f64
    }
}

/// `(x, y, z)`, with components below 1e-10 of the largest shown as 0 (as a
/// plane point is in names).
fn point3(p: [f64; 3]) -> String {
    let size = p.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let c = |v: f64| if v.abs() <= 1e-10 * size { 0.0 } else { v };
    format!("({}, {}, {})", c(p[0]), c(p[1]), c(p[2]))
}

/// Where a boundary face lies against a selection box.
#[derive(Debug, PartialEq)]
enum Inside {
    /// Wholly inside (to the tolerance).
    Whole,
    /// Outside, or touching it along an edge or at a corner only.
    Out,
    /// Cut by a side of the box: partly in, partly out.
    Cut,
}

/// Where the face of corners `corners` lies against the box `[lo, hi]`, to
/// the tolerance `tol`. A box may be flat along an axis (a patch of a plane
/// face): a face in that plane is inside when its extent is.
fn inside(corners: &[[f64; 3]], lo: [f64; 3], hi: [f64; 3], tol: f64) -> Inside {
    let mut whole = true;
    let mut overlaps = true;
    for a in 0..3 {
        let fmin = corners.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
        let fmax = corners
            .iter()
            .map(|p| p[a])
            .fold(f64::NEG_INFINITY, f64::max);
        let contained = fmin >= lo[a] - tol && fmax <= hi[a] + tol;
        whole &= contained;
        let flat_face = fmax - fmin <= tol;
        let flat_box = hi[a] - lo[a] <= tol;
        let overlap = if flat_face {
            contained
        } else if flat_box {
            // The box's plane crosses the face.
            fmin < lo[a] - tol && fmax > hi[a] + tol
        } else {
            fmin < hi[a] - tol && fmax > lo[a] + tol
        };
        overlaps &= overlap;
    }
    match (whole, overlaps) {
        (true, _) => Inside::Whole,
        (false, true) => Inside::Cut,
        (false, false) => Inside::Out,
    }
}

/// The faces a surface load acts on: those wholly inside its box (or the
/// whole surface without a box), and those its box cuts, each with the axes
/// along which it is cut to the box `[lo, hi]` ([`clip_axes`]).
struct Selection {
    whole: Vec<BoundaryFace>,
    cut: Vec<(BoundaryFace, [bool; 3])>,
    lo: [f64; 3],
    hi: [f64; 3],
}

/// The axes along which a face of corners `corners` that the box `[lo, hi]`
/// cuts ([`Inside::Cut`]) is clipped to it: every axis but those the face is
/// flat along (it lies in the box's extent there, to `tol`: clipping it
/// would only move its corners by round-off). `None` when the box is flat
/// along an axis the face is not: the box's plane meets the face along a
/// line, which has no area to load.
fn clip_axes(corners: &[[f64; 3]], lo: [f64; 3], hi: [f64; 3], tol: f64) -> Option<[bool; 3]> {
    let mut clip = [true; 3];
    for a in 0..3 {
        let fmin = corners.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
        let fmax = (corners.iter().map(|p| p[a])).fold(f64::NEG_INFINITY, f64::max);
        let flat_face = fmax - fmin <= tol;
        let flat_box = hi[a] - lo[a] <= tol;
        if flat_face {
            clip[a] = false;
        } else if flat_box {
            return None;
        }
    }
    Some(clip)
}

impl Builder<'_> {
    /// The solid model of the parsed `file` at refinement `refine`: its values
    /// checked, its size checked against the machine's memory, then its parts
    /// meshed and its interfaces, steps, supports, loads and probes resolved.
    pub(super) fn build_solid(&self, file: ProblemFile<3>, refine: usize) -> Result<Model<D3>> {
        if !file.parts.is_empty() {
            check::problem(&self.values, &file)?;
        }
        let ProblemFile {
            title,
            units,
            plane: _,
            materials,
            parts: part_specs,
            interfaces: iface_specs,
            supports: support_specs,
            loads: load_specs,
            mut analysis,
            steps: step_specs,
            lines: _,
            probes: probe_specs,
            output,
        } = file;
        if part_specs.is_empty() {
            return Err(Error::Model("the problem defines no [[part]]".into()));
        }
        self.check_solid_resources(&part_specs, refine)?;
        let mut parts: Vec<Part<D3>> = Vec::with_capacity(part_specs.len());
        let mut files = HashMap::new();
        for spec in &part_specs {
            let part = self.solid_part(spec, &parts, &materials, refine, &mut files)?;
            parts.push(part);
        }
        let interfaces = self.interfaces(&iface_specs, &parts)?;
        let steps = steps(&step_specs);
        if !steps.is_empty() {
            analysis.increments = steps.iter().map(|s| s.increments).sum();
        }
        let supports = self.solid_supports(&support_specs, &parts, &steps)?;
        let loads = self.solid_loads(&load_specs, &parts, &steps)?;
        let steps = self.step_factors(&step_specs, steps, &loads, &supports)?;
        let probes = self.solid_probes(&probe_specs, &parts)?;
        let picture = self.picture(&output)?;
        let history_plot = self.history_plot(output, &supports, &interfaces, &probes)?;
        Ok(Model {
            title: self.title(title),
            source: self.path.to_path_buf(),
            units,
            parts,
            interfaces,
            supports,
            loads,
            settings: analysis,
            steps,
            refine,
            text: self.text.to_string(),
            kept_polygons: Vec::new(),
            notes: Vec::new(),
            lines: Vec::new(),
            probes,
            history_plot,
            picture,
        })
    }

    /// `[output] view` and `component`: what `deformed.png` shows (the
    /// default without them); an unknown name is an [`Error::Invalid`]
    /// naming the key, its line and the names it takes.
    fn picture(&self, output: &OutputSpec) -> Result<Picture> {
        let mut picture = Picture::default();
        if let Some(v) = &output.view {
            picture.view = ViewPoint::from_name(v).ok_or_else(|| {
                self.values.invalid(
                    &[check::Seg::K("output"), check::Seg::K("view")],
                    format!(
                        "= \"{v}\" is no viewpoint of deformed.png (one of: {})",
                        ViewPoint::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if let Some(c) = &output.component {
            picture.field = PictureField::from_name(c).ok_or_else(|| {
                self.values.invalid(
                    &[check::Seg::K("output"), check::Seg::K("component")],
                    format!(
                        "= \"{c}\" is no field deformed.png can be coloured by (one of: {})",
                        PictureField::NAMES.join(", ")
                    ),
                )
            })?;
        }
        Ok(picture)
    }

    /// The boxes' node counts at refinement `refine` (checked arithmetic)
    /// against the machine's memory, before any meshing.
    fn check_solid_resources(&self, specs: &[PartSpec], refine: usize) -> Result<()> {
        let mut nodes: u64 = 0;
        let k = refine as u64;
        for spec in specs {
            let Some(b) = &spec.block else { continue };
            let count = b.cells.iter().try_fold(1u64, |n, &c| {
                (c as u64).checked_mul(k)?.checked_add(1)?.checked_mul(n)
            });
            let count = count
                .filter(|_| b.cells.iter().all(|&c| c.checked_mul(refine).is_some()))
                .ok_or_else(|| {
                    self.err(
                        &spec.name,
                        format!(
                            "part '{}': {:?} cells refined {refine} times is too many to count",
                            spec.name.get_ref(),
                            b.cells
                        ),
                    )
                })?;
            nodes = nodes.saturating_add(count);
        }
        // Meshes given in memory are subdivided as a Gmsh mesh is (k³ × the nodes).
        let k3 = k.saturating_mul(k).saturating_mul(k);
        for mesh in self.solid_meshes.borrow().values() {
            nodes = nodes.saturating_add((mesh.nodes.len() as u64).saturating_mul(k3));
        }
        check_size_of(nodes, 3, refine)
    }

    /// A solid part: its material (E and ν), its mesh (`box` or `gmsh`),
    /// checked; `parts` are the parts defined before it.
    fn solid_part(
        &self,
        spec: &PartSpec,
        parts: &[Part<D3>],
        materials: &BTreeMap<String, MaterialSpec>,
        refine: usize,
        files: &mut HashMap<PathBuf, Rc<GmshMesh3d>>,
    ) -> Result<Part<D3>> {
        let name = spec.name.get_ref().clone();
        if parts.iter().any(|p| p.name == name) {
            return Err(self.err(&spec.name, format!("part '{name}' is defined twice")));
        }
        let m = materials.get(spec.material.get_ref()).ok_or_else(|| {
            self.err(
                &spec.material,
                format!(
                    "part '{name}' uses material '{}', which is not in [materials] (defined: {})",
                    spec.material.get_ref(),
                    materials.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            )
        })?;
        // A solid reads E and ν (the plane idealisation and thickness are unused).
        let material = Material::new(m.young, m.nu, PlaneKind::Strain, 1.0, &name)?;
        let in_memory = self.solid_meshes.borrow().contains_key(&name);
        if in_memory && (spec.block.is_some() || spec.gmsh.is_some()) {
            return Err(self.err(
                &spec.name,
                format!("part '{name}' has a mesh given in memory and a `box` or `gmsh` key: give one of them"),
            ));
        }
        let mesh = match (&spec.block, &spec.gmsh) {
            (None, None) if in_memory => {
                let mesh = (self.solid_meshes.borrow_mut().remove(&name)).unwrap_or_default();
                if refine > 1 {
                    mesh.refined(refine)
                } else {
                    mesh
                }
            }
            (Some(b), None) => self.box_mesh(spec, b, &name, refine)?,
            (None, Some(g)) => self.gmsh_solid(&name, g, refine, files)?,
            (Some(_), Some(_)) => {
                return Err(self.err(
                    &spec.name,
                    format!("part '{name}' has both `box` and `gmsh`: give exactly one"),
                ));
            }
            (None, None) => {
                return Err(self.err(
                    &spec.name,
                    format!("part '{name}' has no mesh: give `box = {{ x = [x0, x1], y = [y0, y1], z = [z0, z1], cells = [nx, ny, nz] }}` or `gmsh = {{ file = \"part.msh\" }}`"),
                ));
            }
        };
        mesh.validate(&name)?;
        Ok(Part {
            name,
            mesh,
            material,
        })
    }

    /// A `box` part's mesh, its cell counts multiplied by `refine`.
    fn box_mesh(
        &self,
        spec: &PartSpec,
        b: &BoxSpec,
        name: &str,
        refine: usize,
    ) -> Result<Mesh<D3>> {
        let ok = b.x[1] > b.x[0] && b.y[1] > b.y[0] && b.z[1] > b.z[0];
        if !ok || b.cells.contains(&0) {
            return Err(self.err(
                &spec.name,
                format!("part '{name}': box needs x0 < x1, y0 < y1, z0 < z1 and at least one cell each way (got x = {:?}, y = {:?}, z = {:?}, cells = {:?})", b.x, b.y, b.z, b.cells),
            ));
        }
        // Counted with checked arithmetic by `check_solid_resources`.
        let cells = b.cells.map(|c| c * refine);
        Ok(Mesh::<D3>::block(b.x, b.y, b.z, cells, b.elements))
    }

    /// The solid mesh of part `name` from a 3D Gmsh file (its `volumes`, all
    /// volume elements by default; physical surfaces as boundaries), refined
    /// `refine` times ([`Mesh::<D3>::refined`](Mesh::refined)); `files` caches
    /// the files already read.
    fn gmsh_solid(
        &self,
        name: &str,
        spec: &Spanned<GmshSpec>,
        refine: usize,
        files: &mut HashMap<PathBuf, Rc<GmshMesh3d>>,
    ) -> Result<Mesh<D3>> {
        let g = spec.get_ref();
        let mesh = self.gmsh_file(name, spec, files, GmshMesh3d::parse)?;
        let volumes: Option<Vec<Group>> = g
            .volumes
            .as_ref()
            .map(|s| s.iter().map(|GroupSpec(g)| g.clone()).collect());
        let part = mesh.part_mesh(name, volumes.as_deref())?;
        Ok(if refine > 1 {
            let k = refine as u64;
            let nodes =
                (part.nodes.len() as u64).saturating_mul(k.saturating_mul(k).saturating_mul(k));
            check_size_of(nodes, 3, refine)?;
            part.refined(refine)
        } else {
            part
        })
    }

    /// The node of solid `part` at `at` (within 1e-6 of its longest edge), for
    /// the message `what`.
    fn node_at3(
        &self,
        part: &Part<D3>,
        at: [f64; 3],
        span: &Spanned<String>,
        what: &str,
    ) -> Result<usize> {
        let h = part.mesh.max_edge_length();
        let (best, d) = (part.mesh.nodes.iter().enumerate())
            .map(|(i, p)| (i, distance3(*p, at)))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if d > 1e-6 * h {
            return Err(self.err(
                span,
                format!(
                    "{what} at {} matches no node of part '{}' (nearest node {best} is {d:.3e} away)",
                    point3(at),
                    part.name
                ),
            ));
        }
        Ok(best)
    }

    /// The supports in file order, each in its step, named (`part/boundary`
    /// or `part@(x, y, z)` by default).
    fn solid_supports(
        &self,
        specs: &[SupportSpec<3>],
        parts: &[Part<D3>],
        steps: &[Step],
    ) -> Result<Vec<Support>> {
        let mut supports = specs
            .iter()
            .map(|spec| {
                self.solid_support(spec, parts).map(|s| Support {
                    step: step_of(steps, &spec.step),
                    ..s
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let given = specs.iter().map(|spec| &spec.name);
        let names = names(given, supports.iter().map(|s| s.name.as_str()));
        for (s, name) in supports.iter_mut().zip(names) {
            s.name = name;
        }
        Ok(supports)
    }

    /// A Dirichlet condition on a boundary surface or at a node of a solid
    /// part: any of x, y, z fixed, at `value` (default 0).
    fn solid_support(&self, spec: &SupportSpec<3>, parts: &[Part<D3>]) -> Result<Support> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        let (name, nodes) = match (&spec.boundary, spec.at, spec.from, spec.to) {
            (Some(b), None, None, None) => (
                format!("{}/{}", part.name, b.get_ref()),
                self.support_nodes(part, b)?,
            ),
            (None, Some(at), None, None) => (
                format!("{}@{}", part.name, point3(at)),
                vec![self.node_at3(part, at, &spec.part, "support")?],
            ),
            (b, None, Some(from), Some(to)) => {
                self.support_box(spec, part, b.as_ref(), from, to)?
            }
            (_, None, Some(_), None) | (_, None, None, Some(_)) => {
                return Err(self.err(
                    &spec.part,
                    "a support box needs both `from` and `to` (opposite corners)",
                ));
            }
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a [[support]] needs one of `boundary`, `at` or a box `from`/`to` (optionally with `boundary`)",
                ));
            }
        };
        let give = "give any of \"x\", \"y\" and \"z\", each once, e.g. [\"x\", \"y\", \"z\"]";
        if spec.fix.is_empty() {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `fix` is empty; {give}"),
            ));
        }
        let fixed = [Component::X, Component::Y, Component::Z].map(|c| spec.fix.contains(&c));
        if fixed.iter().filter(|&&f| f).count() != spec.fix.len() {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `fix` names the same component twice; {give}"),
            ));
        }
        Ok(Support {
            name,
            part: p,
            nodes,
            fix: fixed,
            value: spec.value,
            step: 0,
        })
    }

    /// The nodes of a support's box `from`–`to` (opposite corners, within
    /// 1e-6 of the part's longest edge): those of boundary `b` (of the part's
    /// whole boundary without one) inside it, in the boundary's order, and
    /// the support's default name `part/boundary[(lo)-(hi)]`; a box holding
    /// no such node is refused.
    fn support_box(
        &self,
        spec: &SupportSpec<3>,
        part: &Part<D3>,
        b: Option<&Spanned<String>>,
        from: [f64; 3],
        to: [f64; 3],
    ) -> Result<(String, Vec<usize>)> {
        let (lo, hi) = (
            [0, 1, 2].map(|c| from[c].min(to[c])),
            [0, 1, 2].map(|c| from[c].max(to[c])),
        );
        let (candidates, mut name) = match b {
            Some(b) => (
                self.support_nodes(part, b)?,
                format!("{}/{}", part.name, b.get_ref()),
            ),
            None => {
                let mut seen = std::collections::HashSet::new();
                let nodes = (part.mesh.boundary_faces().iter())
                    .flat_map(|f| f.nodes.as_slice().to_vec())
                    .filter(|n| seen.insert(*n))
                    .collect();
                (nodes, part.name.clone())
            }
        };
        let tol = 1e-6 * part.mesh.max_edge_length();
        let nodes: Vec<usize> = (candidates.into_iter())
            .filter(|&n| {
                let x = part.mesh.nodes[n];
                (0..3).all(|c| x[c] >= lo[c] - tol && x[c] <= hi[c] + tol)
            })
            .collect();
        if nodes.is_empty() {
            return Err(self.err(
                &spec.part,
                format!(
                    "the support box {}–{} holds no node of {}",
                    point3(lo),
                    point3(hi),
                    b.map_or(format!("part '{}''s boundary", part.name), |b| format!(
                        "boundary '{}' of part '{}'",
                        b.get_ref(),
                        part.name
                    ))
                ),
            ));
        }
        name += &format!("[{}-{}]", point3(lo), point3(hi));
        Ok((name, nodes))
    }

    /// The loads in file order, each in its step, named (see [`names`]).
    fn solid_loads(
        &self,
        specs: &[LoadSpec<3>],
        parts: &[Part<D3>],
        steps: &[Step],
    ) -> Result<Vec<Load<D3>>> {
        let mut loads = specs
            .iter()
            .map(|spec| {
                self.solid_load(spec, parts).map(|l| Load {
                    step: step_of(steps, &spec.step),
                    ..l
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let given = specs.iter().map(|spec| &spec.name);
        let names = names(given, loads.iter().map(|l| l.name.as_str()));
        for (l, name) in loads.iter_mut().zip(names) {
            l.name = name;
        }
        Ok(loads)
    }

    /// A load on a solid part resolved to nodal forces: a `force` at a node
    /// (`at`) or as a resultant spread uniformly (a traction force / area) over
    /// a surface, a `pressure` or a `traction` on a surface; the surface is a
    /// named `boundary`, or its part (of the part's whole boundary without
    /// one) inside the box `from`–`to`: the faces inside it whole, those it
    /// cuts over their polygons clipped to it ([`loads::clipped_face_forces`]:
    /// the resultant and moment of a uniform load are exact).
    fn solid_load(&self, spec: &LoadSpec<3>, parts: &[Part<D3>]) -> Result<Load<D3>> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        let kinds = [
            spec.force.is_some(),
            spec.pressure.is_some(),
            spec.traction.is_some(),
        ];
        if kinds.iter().filter(|&&k| k).count() != 1 {
            return Err(self.err(
                &spec.part,
                "a [[load]] of a solid part needs exactly one of `force` (a resultant [fx, fy, fz], with `at`, `boundary` or `from`/`to`), `pressure` or `traction` (per area, with `boundary` or `from`/`to`)",
            ));
        }
        if let (Some(force), Some(at)) = (spec.force, spec.at) {
            if spec.boundary.is_some() || spec.from.is_some() || spec.to.is_some() {
                return Err(self.err(
                    &spec.part,
                    "a point [[load]] (`at`) takes no `boundary`, `from` or `to`",
                ));
            }
            let n = self.node_at3(part, at, &spec.part, "point load")?;
            return Ok(Load {
                name: format!("{}@{}", part.name, point3(at)),
                part: p,
                nodal: vec![(n, force)],
                resultant: force,
                step: 0,
            });
        }
        if spec.at.is_some() {
            return Err(self.err(
                &spec.part,
                "`at` places a point force: it takes `force`, not `pressure` or `traction`",
            ));
        }
        if let (Some(force), Some(b), None, None) = (spec.force, &spec.boundary, spec.from, spec.to)
            && !part.mesh.boundaries.contains_key(b.get_ref())
            && let Some(set) = part.mesh.node_sets.get(b.get_ref())
        {
            return Ok(Load {
                name: format!("{}/{}", part.name, b.get_ref()),
                part: p,
                nodal: spread_equally(&set.nodes, force),
                resultant: force,
                step: 0,
            });
        }
        let (faces, mut name) = self.load_faces(spec, part)?;
        let (load, what) = match (spec.force, spec.pressure, spec.traction) {
            (Some(force), _, _) => {
                let area: f64 = (faces.whole.iter())
                    .map(|f| norm(f.nodes.vector_area(&part.mesh.nodes)))
                    .sum();
                let area = area
                    + self
                        .cut_forces(spec, part, &faces, FaceLoad::Pressure(0.0))?
                        .2;
                (FaceLoad::Traction(force.map(|c| c / area)), String::new())
            }
            (_, Some(pressure), _) => (
                FaceLoad::Pressure(pressure),
                format!(" (pressure {pressure})"),
            ),
            (_, _, Some(t)) => (FaceLoad::Traction(t), format!(" (traction {})", point3(t))),
            _ => unreachable!("one kind of load, checked above"),
        };
        name += &what;
        let (mut nodal, mut sum) = loads::face_forces(&part.mesh.nodes, &faces.whole, load);
        if !faces.cut.is_empty() {
            // The cut faces' share, added to the whole faces' (a node of both
            // keeps one entry).
            let (cut, cut_sum, _) = self.cut_forces(spec, part, &faces, load)?;
            let mut at: HashMap<usize, usize> = nodal
                .iter()
                .enumerate()
                .map(|(k, (n, _))| (*n, k))
                .collect();
            for (n, f) in cut {
                let k = *at.entry(n).or_insert_with(|| {
                    nodal.push((n, [0.0; 3]));
                    nodal.len() - 1
                });
                for (o, f) in nodal[k].1.iter_mut().zip(f) {
                    *o += f;
                }
            }
            for c in 0..3 {
                sum[c] += cut_sum[c];
            }
        }
        Ok(Load {
            name,
            part: p,
            nodal,
            // A resultant is the one asked for; a pressure's or traction's the
            // integrated one.
            resultant: spec.force.unwrap_or(sum),
            step: 0,
        })
    }

    /// The nodal forces, resultant and loaded area of `load` over the parts of
    /// the cut faces of `faces` inside its box
    /// ([`loads::clipped_face_forces`], each face cut along its axes).
    fn cut_forces(
        &self,
        spec: &LoadSpec<3>,
        part: &Part<D3>,
        faces: &Selection,
        load: FaceLoad,
    ) -> Result<loads::ClippedForces> {
        let mut nodal: Vec<(usize, [f64; 3])> = Vec::new();
        let mut at: HashMap<usize, usize> = HashMap::new();
        let (mut sum, mut area) = ([0.0; 3], 0.0);
        for (f, clip) in &faces.cut {
            let one = std::slice::from_ref(f);
            let (forces, s, a) =
                loads::clipped_face_forces(&part.mesh.nodes, one, faces.lo, faces.hi, *clip, load)
                    .map_err(|_| {
                        self.err(
                            &spec.part,
                            format!(
                                "the load box cuts a degenerate face of part '{}' (element {}, nodes {:?}): its part inside the box cannot be integrated",
                                part.name,
                                f.element,
                                f.nodes.as_slice()
                            ),
                        )
                    })?;
            for (n, v) in forces {
                let k = *at.entry(n).or_insert_with(|| {
                    nodal.push((n, [0.0; 3]));
                    nodal.len() - 1
                });
                for (o, v) in nodal[k].1.iter_mut().zip(v) {
                    *o += v;
                }
            }
            for c in 0..3 {
                sum[c] += s[c];
            }
            area += a;
        }
        Ok((nodal, sum, area))
    }

    /// The faces a surface load acts on, and its default name: the named
    /// `boundary` (the part's whole boundary without one), restricted to the
    /// box `from`–`to` when it is given: the faces wholly inside it, and the
    /// faces it cuts (partly in, partly out) with the axes they are cut along,
    /// loaded over their part inside the box only ([`Selection`]).
    fn load_faces(&self, spec: &LoadSpec<3>, part: &Part<D3>) -> Result<(Selection, String)> {
        let (faces, mut name) = match &spec.boundary {
            Some(b) => (
                self.boundary(part, b)?.clone(),
                format!("{}/{}", part.name, b.get_ref()),
            ),
            None => (part.mesh.boundary_faces(), part.name.clone()),
        };
        let (lo, hi) = match (spec.from, spec.to) {
            (None, None) if spec.boundary.is_some() => {
                return Ok((
                    Selection {
                        whole: faces,
                        cut: Vec::new(),
                        lo: [0.0; 3],
                        hi: [0.0; 3],
                    },
                    name,
                ));
            }
            (Some(a), Some(b)) => (
                [0, 1, 2].map(|c| a[c].min(b[c])),
                [0, 1, 2].map(|c| a[c].max(b[c])),
            ),
            (None, None) => {
                return Err(self.err(
                    &spec.part,
                    "a surface [[load]] needs `boundary` (a named surface), a box `from`/`to` (opposite corners), or both",
                ));
            }
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a load box needs both `from` and `to` (opposite corners)",
                ));
            }
        };
        let tol = 1e-6 * part.mesh.max_edge_length();
        let mut whole = Vec::new();
        let mut cut = Vec::new();
        for f in &faces {
            let corners: Vec<[f64; 3]> = (f.nodes.as_slice().iter())
                .map(|&n| part.mesh.nodes[n])
                .collect();
            match inside(&corners, lo, hi, tol) {
                Inside::Whole => whole.push(*f),
                Inside::Out => {}
                Inside::Cut => {
                    if let Some(clip) = clip_axes(&corners, lo, hi, tol) {
                        cut.push((*f, clip));
                    }
                }
            }
        }
        if whole.is_empty() && cut.is_empty() {
            return Err(self.err(
                &spec.part,
                format!(
                    "the load box {}–{} holds no face of {}",
                    point3(lo),
                    point3(hi),
                    spec.boundary.as_ref().map_or(
                        format!("part '{}''s boundary", part.name),
                        |b| format!("boundary '{}' of part '{}'", b.get_ref(), part.name)
                    )
                ),
            ));
        }
        name += &format!("[{}-{}]", point3(lo), point3(hi));
        Ok((Selection { whole, cut, lo, hi }, name))
    }

    /// The probes in file order, each interpolated in the element of its part
    /// that contains its point (TET4: barycentric; HEX8: Newton's inverse
    /// map; the host found through an R-tree of the elements' boxes, the
    /// lowest element index of those containing it: [`volume::locate`]), or
    /// at the node nearest to it (the first of equally near ones) when the
    /// point is a node or lies in no element — as a plane model's.
    fn solid_probes(&self, specs: &[ProbeSpec<3>], parts: &[Part<D3>]) -> Result<Vec<Probe<D3>>> {
        let mut trees = HashMap::new();
        specs
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                let Some(part) = parts.iter().position(|p| &p.name == spec.part.get_ref()) else {
                    let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
                    return Err(self.values.invalid(
                        &[
                            check::Seg::K("probe"),
                            check::Seg::I(i),
                            check::Seg::K("part"),
                        ],
                        format!(
                            "= \"{}\" names no part (parts: {})",
                            spec.part.get_ref(),
                            names.join(", ")
                        ),
                    ));
                };
                let mesh = &parts[part].mesh;
                let node = (mesh.nodes.iter().enumerate())
                    .min_by(|a, b| distance3(*a.1, spec.at).total_cmp(&distance3(*b.1, spec.at)))
                    .map_or(0, |(n, _)| n);
                // At a node (to 1e-12 of the part's size) the node itself, so a
                // probe put on a node records that node's displacement exactly.
                let at_node = (mesh.nodes.get(node))
                    .is_some_and(|x| distance3(*x, spec.at) <= 1e-12 * mesh.max_edge_length());
                let located = if at_node {
                    None
                } else {
                    let tree = trees
                        .entry(part)
                        .or_insert_with(|| volume::element_tree(mesh));
                    volume::locate(mesh, tree, spec.at)
                };
                let weights = match &located {
                    Some((e, shape)) => {
                        let nodes = mesh.elements[*e].nodes();
                        nodes.iter().zip(shape).map(|(&n, &w)| (n, w)).collect()
                    }
                    None => vec![(node, 1.0)],
                };
                Ok(Probe {
                    name: spec.name.get_ref().clone(),
                    part,
                    node,
                    at: spec.at,
                    weights,
                    element: located.map(|(e, _)| e),
                })
            })
            .collect()
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face is wholly inside a box, outside it (touching it along an edge
    /// counts as outside), or cut by it; a flat box selects the faces in its
    /// plane.
    #[test]
    fn faces_against_a_box() {
        let square = |x0: f64, y0: f64| {
            [
                [x0, y0, 1.0],
                [x0 + 1.0, y0, 1.0],
                [x0 + 1.0, y0 + 1.0, 1.0],
                [x0, y0 + 1.0, 1.0],
            ]
        };
        let (lo, hi) = ([0.0, 0.0, 1.0], [2.0, 2.0, 1.0]);
        assert_eq!(inside(&square(0.0, 0.0), lo, hi, 1e-9), Inside::Whole);
        assert_eq!(inside(&square(1.0, 1.0), lo, hi, 1e-9), Inside::Whole);
        assert_eq!(inside(&square(2.0, 0.0), lo, hi, 1e-9), Inside::Out);
        assert_eq!(inside(&square(1.5, 0.0), lo, hi, 1e-9), Inside::Cut);
        // A side face (x = 2, spanning z 0..1) touching the flat box at an edge.
        let side = [
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [2.0, 1.0, 1.0],
            [2.0, 0.0, 1.0],
        ];
        assert_eq!(inside(&side, lo, hi, 1e-9), Inside::Out);
        // Crossed by a flat box's plane.
        let through = [
            [1.0, 0.0, 0.5],
            [1.0, 1.0, 0.5],
            [1.0, 1.0, 1.5],
            [1.0, 0.0, 1.5],
        ];
        assert_eq!(inside(&through, lo, hi, 1e-9), Inside::Cut);
    }
}
