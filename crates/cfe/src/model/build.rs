//! The builder: a parsed problem file ([`super::schema`]) → the domain values
//! of a [`Model`]: each part meshed (rectangle, annulus, Gmsh file or a mesh given
//! in memory) with its material, each interface's coupling nodes and penalties,
//! each support and load resolved to nodes and nodal values, with the names,
//! steps and default values filled in. Every error names the line and key at
//! fault.

use super::schema::{
    AnnulusSpec, Component, GmshSpec, GroupSpec, InterfaceSpec, LineSpec, LoadSpec, MaterialSpec,
    PartSpec, ProbeSpec, ProblemFile, RectangleSpec, StepSpec, SupportSpec, line_of,
};
use super::{
    DEFAULT_PAIR_TOLERANCE, DEFAULT_PENALTY_FACTOR, DEFAULT_PENETRATION_TOLERANCE, InterfaceDef,
    Load, Model, Part, Probe, ProblemDim, Step, Support, check,
};
use crate::coupling::{Enforcement, Law};
use crate::domain::Loading;
use crate::error::{Error, Result};
use crate::fem::{Material, PlaneKind, axisymmetric, loads};
use crate::mesh::gmsh::{GmshMesh, Group};
use crate::mesh::input_file::{self, MESH_FILE_CAP};
use crate::mesh::{Mesh, MeshDim, NodeSet, bounding_diagonal};
use crate::results::lines::{LineProbe, locate, locate_point};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use toml::Spanned;

/// A problem text's builder: resolves its parsed tables against each other
/// (names, boundaries, nodes) into a [`Model`].
pub(super) struct Builder<'a> {
    pub(super) text: &'a str,
    pub(super) path: &'a Path,
    /// Meshes given in memory, by part name, taken by their parts.
    meshes: std::cell::RefCell<BTreeMap<String, Mesh>>,
    /// Solid meshes given in memory, by part name, taken by their parts
    /// ([`Builder::with_solid_meshes`]).
    pub(super) solid_meshes: std::cell::RefCell<BTreeMap<String, Mesh<crate::dim::D3>>>,
    /// The text's values with their lines, for the checks.
    pub(super) values: check::Values<'a>,
}

impl<'a> Builder<'a> {
    /// "file:line" for a spanned value.
    fn at<T>(&self, s: &Spanned<T>) -> String {
        let line = self.text[..s.span().start.min(self.text.len())]
            .matches('\n')
            .count()
            + 1;
        format!("{}:{line}", self.path.display())
    }

    pub(super) fn err<T>(&self, s: &Spanned<T>, msg: impl std::fmt::Display) -> Error {
        Error::Parse {
            path: self.path.to_path_buf(),
            line: Some(line_of(self.text, s.span().start)),
            message: format!(
                "line {}: {msg}",
                self.at(s).rsplit(':').next().unwrap_or("?")
            ),
        }
    }

    pub(super) fn part_index<D: MeshDim>(
        &self,
        parts: &[Part<D>],
        name: &Spanned<String>,
        key: &str,
    ) -> Result<usize> {
        parts
            .iter()
            .position(|p| &p.name == name.get_ref())
            .ok_or_else(|| {
                let known: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
                self.err(
                    name,
                    format!(
                        "`{key}` names part '{}', which is not defined (parts: {})",
                        name.get_ref(),
                        known.join(", ")
                    ),
                )
            })
    }

    pub(super) fn boundary<'m, D: MeshDim>(
        &self,
        part: &'m Part<D>,
        name: &Spanned<String>,
    ) -> Result<&'m Vec<D::Face>> {
        part.mesh.boundaries.get(name.get_ref()).ok_or_else(|| {
            if part.mesh.node_sets.contains_key(name.get_ref()) {
                return self.err(
                    name,
                    format!(
                        "'{}' is a node set of part '{}', not a boundary: only a [[support]] or a `force` [[load]] (spread equally over its nodes) takes a node set; this key needs a boundary (it has: {})",
                        name.get_ref(),
                        part.name,
                        keys(part.mesh.boundaries.keys())
                    ),
                );
            }
            self.err(
                name,
                format!(
                    "part '{}' has no boundary named '{}' (it has: {})",
                    part.name,
                    name.get_ref(),
                    keys(part.mesh.boundaries.keys())
                ),
            )
        })
    }

    /// What a support's or a `force` load's `boundary` names on `part`: its
    /// boundary of that name, or else its node set of that name (a Gmsh
    /// physical point, or in 3D curve). Neither is an error naming the part,
    /// the name, the line and what the part has.
    pub(super) fn boundary_or_set<'m, D: MeshDim>(
        &self,
        part: &'m Part<D>,
        name: &Spanned<String>,
    ) -> Result<Named<'m, D::Face>> {
        if let Some(faces) = part.mesh.boundaries.get(name.get_ref()) {
            return Ok(Named::Boundary(faces));
        }
        if let Some(set) = part.mesh.node_sets.get(name.get_ref()) {
            return Ok(Named::NodeSet(set));
        }
        if part.mesh.node_sets.is_empty() {
            return self.boundary(part, name).map(|f| Named::Boundary(f));
        }
        Err(self.err(
            name,
            format!(
                "part '{}' has no boundary or node set named '{}' (boundaries: {}; node sets: {})",
                part.name,
                name.get_ref(),
                keys(part.mesh.boundaries.keys()),
                keys(part.mesh.node_sets.keys())
            ),
        ))
    }

    /// The nodes a support's `boundary` names (a boundary's, each once in its
    /// order, or a node set's, ascending).
    pub(super) fn support_nodes<D: MeshDim>(
        &self,
        part: &Part<D>,
        name: &Spanned<String>,
    ) -> Result<Vec<usize>> {
        Ok(match self.boundary_or_set(part, name)? {
            Named::Boundary(_) => (part.mesh.boundary_nodes(name.get_ref())).unwrap_or_default(),
            Named::NodeSet(set) => set.nodes.clone(),
        })
    }

    fn node_at(
        &self,
        part: &Part,
        at: [f64; 2],
        span: &Spanned<String>,
        what: &str,
    ) -> Result<usize> {
        let h = part.mesh.max_edge_length();
        let (best, d) = part
            .mesh
            .nodes
            .iter()
            .enumerate()
            .map(|(i, p)| (i, crate::mesh::dist(*p, at)))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if d > 1e-6 * h {
            return Err(self.err(
                span,
                format!(
                    "{what} at ({}, {}) matches no node of part '{}' (nearest node {best} is {d:.3e} away)",
                    at[0], at[1], part.name
                ),
            ));
        }
        Ok(best)
    }

    /// The Gmsh file of part `name` (`spec.file`, relative to the problem
    /// file's folder) parsed by `parse`, read once per file however many parts
    /// take their elements from it (`files`, keyed by the canonical path).
    pub(super) fn gmsh_file<M>(
        &self,
        name: &str,
        spec: &Spanned<GmshSpec>,
        files: &mut HashMap<PathBuf, Rc<M>>,
        parse: fn(&[u8], &Path) -> Result<M>,
    ) -> Result<Rc<M>> {
        let path = self
            .path
            .parent()
            .unwrap_or(Path::new(""))
            .join(&spec.get_ref().file);
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if let Some(m) = files.get(&key) {
            return Ok(Rc::clone(m));
        }
        let what = format!("Gmsh file of part '{name}'");
        let data = input_file::read(&path, &what, MESH_FILE_CAP, |e| {
            self.err(
                spec,
                format!(
                    "part '{name}': cannot read Gmsh file {}: {e}",
                    path.display()
                ),
            )
        })?;
        let m = Rc::new(parse(&data, &path)?);
        files.insert(key, Rc::clone(&m));
        Ok(m)
    }

    /// The mesh of part `name` from a Gmsh file, subdivided uniformly by `refine`
    /// ([`Mesh::refined`]: every edge split into `refine` equal segments, so curved
    /// boundaries stay the file's polygons); `files` caches the files already read,
    /// so a file shared by several parts is read once.
    fn gmsh_mesh(
        &self,
        name: &str,
        spec: &Spanned<GmshSpec>,
        refine: usize,
        files: &mut HashMap<PathBuf, Rc<GmshMesh>>,
    ) -> Result<Mesh> {
        let g = spec.get_ref();
        let mesh = self.gmsh_file(name, spec, files, GmshMesh::parse)?;
        let surfaces: Option<Vec<Group>> = g
            .surfaces
            .as_ref()
            .map(|s| s.iter().map(|GroupSpec(g)| g.clone()).collect());
        let part = mesh.part_mesh(name, surfaces.as_deref())?;
        Ok(if refine > 1 {
            check_size(refined_nodes(part.nodes.len(), refine), refine)?;
            part.refined(refine)
        } else {
            part
        })
    }

    /// A builder of the problem `text` read from `path` (for messages and the
    /// default title), with the meshes of some parts given in memory by name.
    pub(super) fn new(text: &'a str, path: &'a Path, meshes: BTreeMap<String, Mesh>) -> Self {
        Builder {
            text,
            path,
            meshes: std::cell::RefCell::new(meshes),
            solid_meshes: std::cell::RefCell::new(BTreeMap::new()),
            values: check::Values::new(text, path),
        }
    }

    /// The same builder with the solid meshes of some parts given in memory
    /// by name (a solid model's parts without `box` or `gmsh`).
    pub(super) fn with_solid_meshes(self, meshes: BTreeMap<String, Mesh<crate::dim::D3>>) -> Self {
        self.solid_meshes.replace(meshes);
        self
    }

    /// The model of the parsed `file` at refinement `refine`: its values checked,
    /// its size checked against the machine's memory, then its parts meshed and its
    /// interfaces, steps, supports and loads resolved, in that order.
    pub(super) fn build(&self, file: ProblemFile, refine: usize) -> Result<Model> {
        // Every number is checked (finite, in range) before anything is meshed.
        if !file.parts.is_empty() {
            check::problem(&self.values, &file)?;
        }
        let ProblemFile {
            title,
            units,
            plane,
            materials,
            parts: part_specs,
            interfaces: iface_specs,
            supports: support_specs,
            loads: load_specs,
            mut analysis,
            steps: step_specs,
            lines: line_specs,
            probes: probe_specs,
            output,
        } = file;
        if part_specs.is_empty() {
            return Err(Error::Model("the problem defines no [[part]]".into()));
        }
        self.check_resources(&part_specs, refine)?;
        let parts = self.parts(&part_specs, &materials, plane, refine)?;
        let kept_polygons = kept_polygons(&part_specs, &parts, refine);
        let interfaces = self.interfaces(&iface_specs, &parts)?;
        let steps = steps(&step_specs);
        if !steps.is_empty() {
            analysis.increments = steps.iter().map(|s| s.increments).sum();
        }
        let supports = self.supports(&support_specs, &parts, &steps)?;
        let loads = self.loads(&load_specs, &parts, &steps)?;
        let lines = self.lines(&line_specs, &parts)?;
        let steps = self.step_factors(&step_specs, steps, &loads, &supports)?;
        let probes = self.probes(&probe_specs, &parts)?;
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
            kept_polygons,
            notes: Vec::new(),
            lines,
            probes,
            history_plot,
            picture: super::Picture::default(),
        })
    }

    /// `[output] history_plot`'s two columns, each a column of history.csv.
    pub(super) fn history_plot<D: crate::dim::Dim>(
        &self,
        output: super::schema::OutputSpec,
        supports: &[Support],
        interfaces: &[InterfaceDef],
        probes: &[Probe<D>],
    ) -> Result<Option<[String; 2]>> {
        let history_plot = output.history_plot.map(|p| [p.x, p.y]);
        if let Some(plot) = &history_plot {
            let columns = crate::results::history::column_names(
                supports.iter().map(|s| s.name.as_str()),
                interfaces.iter().map(|i| i.name.as_str()),
                probes.iter().map(|p| p.name.as_str()),
            );
            for (axis, name) in ["x", "y"].iter().zip(plot) {
                if !columns.contains(name) {
                    return Err(self.values.invalid(
                        &[
                            check::Seg::K("output"),
                            check::Seg::K("history_plot"),
                            check::Seg::K(axis),
                        ],
                        format!(
                            "= \"{name}\" is no column of history.csv (columns: {})",
                            columns.join(", ")
                        ),
                    ));
                }
            }
        }
        Ok(history_plot)
    }

    /// The title: as given, else the problem file's stem.
    pub(super) fn title(&self, title: Option<String>) -> String {
        title.unwrap_or_else(|| {
            self.path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "problem".into())
        })
    }

    /// The line probes: each named uniquely (letters, digits, `-`, `_`: its file
    /// names), of nonzero length, with at least two points, its part known, and
    /// some point inside a part (else a typed [`Error::Invalid`] naming it).
    fn lines(&self, specs: &[LineSpec], parts: &[Part]) -> Result<Vec<LineProbe>> {
        let mut lines: Vec<LineProbe> = Vec::with_capacity(specs.len());
        for spec in specs {
            let name = spec.name.get_ref();
            let invalid = |message: String| Error::Invalid {
                path: self.path.to_path_buf(),
                line: Some(line_of(self.text, spec.name.span().start)),
                key: format!("line.{name}"),
                message,
            };
            if name.is_empty()
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
            {
                return Err(invalid(
                    "name must be letters, digits, '-' or '_' (it names the files lines/<name>.csv and .png)".into(),
                ));
            }
            if lines.iter().any(|l| &l.name == name) {
                return Err(invalid(
                    "names a second [[line]]: line names must be unique".into(),
                ));
            }
            let (from, to) = (spec.from, spec.to);
            let length = (to[0] - from[0]).hypot(to[1] - from[1]);
            if !(length.is_finite() && length > 0.0) {
                return Err(invalid(format!(
                    "has zero length (from = to = [{}, {}]): a line needs two distinct finite ends",
                    from[0], from[1]
                )));
            }
            let points = spec.points.unwrap_or(101);
            if !(2..=1_000_000).contains(&points) {
                return Err(invalid(format!(
                    "points = {points}: a line is sampled at 2 to 1000000 points, ends included"
                )));
            }
            let only = match &spec.part {
                Some(part) => Some(self.part_index(parts, part, "part")?),
                None => None,
            };
            let line = locate(parts, only, name, from, to, points);
            if line.points.iter().all(|p| p.2.is_none()) {
                let within = only.map_or("every part".to_string(), |p| {
                    format!("part '{}'", parts[p].name)
                });
                return Err(invalid(format!(
                    "from [{}, {}] to [{}, {}] lies outside {within}: none of its {points} points is in an element",
                    from[0], from[1], to[0], to[1]
                )));
            }
            lines.push(line);
        }
        Ok(lines)
    }

    /// Resources are checked before they are spent: the structured parts' sizes
    /// (checked arithmetic) and the meshes given in memory, refined, against the
    /// machine's memory, before any meshing.
    fn check_resources(&self, part_specs: &[PartSpec], refine: usize) -> Result<()> {
        let mut nodes: u64 = 0;
        for spec in part_specs {
            let n = self.structured_nodes(spec, refine)?;
            nodes = nodes.saturating_add(n);
        }
        // Meshes given in memory (arrays, a Python mesh) are subdivided as well.
        for mesh in self.meshes.borrow().values() {
            nodes = nodes.saturating_add(refined_nodes(mesh.nodes.len(), refine));
        }
        check_size(nodes, refine)
    }

    /// The parts in file order, each meshed (a Gmsh file shared by several parts
    /// is read once).
    fn parts(
        &self,
        part_specs: &[PartSpec],
        materials: &BTreeMap<String, MaterialSpec>,
        plane: PlaneKind,
        refine: usize,
    ) -> Result<Vec<Part>> {
        let mut parts: Vec<Part> = Vec::with_capacity(part_specs.len());
        let mut gmsh_files = HashMap::new();
        for spec in part_specs {
            let part = self.part(spec, &parts, materials, plane, refine, &mut gmsh_files)?;
            parts.push(part);
        }
        Ok(parts)
    }

    /// The interfaces in file order; an unnamed interface is named `host/nodes`
    /// (made unique). A coupling node is claimed by one interface only.
    pub(super) fn interfaces<D: ProblemDim>(
        &self,
        iface_specs: &[InterfaceSpec],
        parts: &[Part<D>],
    ) -> Result<Vec<InterfaceDef>> {
        let mut claimed: BTreeMap<(usize, usize), String> = BTreeMap::new();
        let iface_names = unique_defaults(
            iface_specs
                .iter()
                .map(|s| match &s.name {
                    Some(n) => (n.get_ref().clone(), true),
                    None => (format!("{}/{}", s.host.get_ref(), s.nodes.get_ref()), false),
                })
                .collect(),
        );
        iface_specs
            .iter()
            .zip(iface_names)
            .enumerate()
            .map(|(i, (spec, name))| self.interface(i, spec, name, parts, &mut claimed))
            .collect()
    }

    /// The probes in file order, each interpolated in the element of its part
    /// that contains its point (the first in element order), or at the node
    /// nearest to it (the first of equally near ones) when the point is a node
    /// or lies in no element.
    fn probes(&self, specs: &[ProbeSpec<2>], parts: &[Part]) -> Result<Vec<Probe>> {
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
                let d = |x: &[f64; 2]| (x[0] - spec.at[0]).hypot(x[1] - spec.at[1]);
                let node = (mesh.nodes.iter().enumerate())
                    .min_by(|a, b| d(a.1).total_cmp(&d(b.1)))
                    .map_or(0, |(n, _)| n);
                // At a node (to 1e-12 of the part's size) the node itself, so a
                // probe put on a node records that node's displacement exactly.
                let at_node = mesh
                    .nodes
                    .get(node)
                    .is_some_and(|x| d(x) <= 1e-12 * mesh.max_edge_length());
                let located = if at_node {
                    None
                } else {
                    locate_point(&parts[part], part, spec.at)
                };
                let weights = match located {
                    Some(l) => {
                        let nodes = mesh.elements[l.element].nodes();
                        nodes.iter().zip(l.shape).map(|(&n, w)| (n, w)).collect()
                    }
                    None => vec![(node, 1.0)],
                };
                Ok(Probe {
                    name: spec.name.get_ref().clone(),
                    part,
                    node,
                    at: spec.at,
                    weights,
                    element: located.map(|l| l.element),
                })
            })
            .collect()
    }

    /// The steps with their `factors` resolved: each key names a load or a
    /// support (not both) applied in this step or an earlier one.
    pub(super) fn step_factors<D: MeshDim>(
        &self,
        specs: &[StepSpec],
        mut steps: Vec<Step>,
        loads: &[Load<D>],
        supports: &[Support],
    ) -> Result<Vec<Step>> {
        for (i, (spec, step)) in specs.iter().zip(&mut steps).enumerate() {
            for (name, &f) in &spec.factors {
                let at = [
                    check::Seg::K("step"),
                    check::Seg::I(i),
                    check::Seg::K("factors"),
                    check::Seg::K(name),
                ];
                let load = loads.iter().position(|l| &l.name == name);
                let support = supports.iter().position(|s| &s.name == name);
                let (which, first) = match (load, support) {
                    (Some(l), None) => (Loading::Load(l), loads[l].step),
                    (None, Some(k)) => (Loading::Support(k), supports[k].step),
                    (Some(_), Some(_)) => {
                        return Err(self.values.invalid(
                            &at,
                            format!("names both a load and a support '{name}': rename one (`name` of its [[load]] or [[support]])"),
                        ));
                    }
                    (None, None) => {
                        let known: Vec<&str> = (loads.iter().map(|l| l.name.as_str()))
                            .chain(supports.iter().map(|s| s.name.as_str()))
                            .collect();
                        return Err(self.values.invalid(
                            &at,
                            format!(
                                "names no load or support (loads and supports: {})",
                                known.join(", ")
                            ),
                        ));
                    }
                };
                if first > i {
                    return Err(self.values.invalid(
                        &at,
                        format!(
                            "sets '{name}', which is applied in a later step ('{}'): a step can set only the loads and supports of itself and earlier steps",
                            specs[first].name.get_ref()
                        ),
                    ));
                }
                match which {
                    Loading::Load(l) => step.load_factors.push((l, f)),
                    Loading::Support(k) => step.support_factors.push((k, f)),
                }
            }
        }
        Ok(steps)
    }

    /// The supports in file order, each in its step, named (see [`names`]).
    fn supports(
        &self,
        specs: &[SupportSpec<2>],
        parts: &[Part],
        steps: &[Step],
    ) -> Result<Vec<Support>> {
        let mut supports = specs
            .iter()
            .map(|spec| {
                self.support(spec, parts).map(|s| Support {
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

    /// The loads in file order, each in its step, named (see [`names`]).
    fn loads(&self, specs: &[LoadSpec<2>], parts: &[Part], steps: &[Step]) -> Result<Vec<Load>> {
        let mut loads = specs
            .iter()
            .map(|spec| {
                self.load(spec, parts).map(|l| Load {
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

    /// The number of nodes a structured part (rectangle or annulus) will have at
    /// refinement `refine`, without meshing it (0 for a Gmsh part); an error when
    /// a count overflows.
    fn structured_nodes(&self, spec: &PartSpec, refine: usize) -> Result<u64> {
        let cells = match (&spec.rectangle, &spec.annulus) {
            (Some(r), _) => r.cells,
            (None, Some(a)) => a.cells,
            _ => return Ok(0),
        };
        let k = refine as u64;
        let count = cells.iter().try_fold(1u64, |n, &c| {
            (c as u64).checked_mul(k)?.checked_add(1)?.checked_mul(n)
        });
        count.ok_or_else(|| {
            self.err(
                &spec.name,
                format!(
                    "part '{}': {:?} cells refined {refine} times is too many to count",
                    spec.name.get_ref(),
                    cells
                ),
            )
        })
    }

    /// A part: its material from `[materials]`, its mesh, checked; `parts` are
    /// the parts defined before it.
    fn part(
        &self,
        spec: &PartSpec,
        parts: &[Part],
        materials: &BTreeMap<String, MaterialSpec>,
        plane: PlaneKind,
        refine: usize,
        gmsh_files: &mut HashMap<PathBuf, Rc<GmshMesh>>,
    ) -> Result<Part> {
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
        let material = Material::new(m.young, m.nu, plane, spec.thickness, &name)?;
        let given = [
            spec.rectangle.is_some(),
            spec.annulus.is_some(),
            spec.gmsh.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() > 1 {
            return Err(self.err(
                &spec.name,
                format!("part '{name}' has more than one of `rectangle`, `annulus` and `gmsh`: give exactly one"),
            ));
        }
        if given.contains(&true) && self.meshes.borrow().contains_key(&name) {
            return Err(self.err(
                &spec.name,
                format!("part '{name}' has a mesh given in memory and a `rectangle`, `annulus` or `gmsh` key: give one of them"),
            ));
        }
        let mut mesh = self.part_mesh(spec, &name, refine, gmsh_files)?;
        if material.is_axisymmetric() {
            axisymmetric::check_radii(&mut mesh.nodes, &name)?;
        }
        mesh.validate(&name)?;
        Ok(Part {
            name,
            mesh,
            material,
        })
    }

    /// The mesh of a part from its one mesh key (`rectangle`, `annulus` or `gmsh`),
    /// refined `refine` times.
    fn part_mesh(
        &self,
        spec: &PartSpec,
        name: &str,
        refine: usize,
        gmsh_files: &mut HashMap<PathBuf, Rc<GmshMesh>>,
    ) -> Result<Mesh> {
        Ok(match (&spec.rectangle, &spec.annulus, &spec.gmsh) {
            (Some(r), _, _) => self.rectangle_mesh(spec, r, name, refine)?,
            (None, Some(a), _) => self.annulus_mesh(spec, a, name, refine)?,
            (None, None, Some(g)) => self.gmsh_mesh(name, g, refine, gmsh_files)?,
            (None, None, None) if self.meshes.borrow().contains_key(name) => {
                let mesh = self.meshes.borrow_mut().remove(name).unwrap_or_default();
                if refine > 1 {
                    mesh.refined(refine)
                } else {
                    mesh
                }
            }
            (None, None, None) => {
                return Err(self.err(
                    &spec.name,
                    format!("part '{name}' has no mesh: give `rectangle = {{ x = [x0, x1], y = [y0, y1], cells = [nx, ny] }}`, `annulus = {{ r = [r0, r1], theta = [t0, t1], cells = [nr, nt] }}` or `gmsh = {{ file = \"part.msh\" }}`"),
                ));
            }
        })
    }

    /// A `rectangle` part's mesh, its cell counts multiplied by `refine`.
    fn rectangle_mesh(
        &self,
        spec: &PartSpec,
        r: &RectangleSpec,
        name: &str,
        refine: usize,
    ) -> Result<Mesh> {
        if !(r.x[1] > r.x[0] && r.y[1] > r.y[0]) || r.cells[0] == 0 || r.cells[1] == 0 {
            return Err(self.err(
                &spec.name,
                format!("part '{name}': rectangle needs x0 < x1, y0 < y1 and at least one cell each way (got x = {:?}, y = {:?}, cells = {:?})", r.x, r.y, r.cells),
            ));
        }
        Ok(Mesh::rectangle_split(
            r.x,
            r.y,
            [r.cells[0] * refine, r.cells[1] * refine],
            r.elements,
            r.diagonal,
        ))
    }

    /// An `annulus` part's mesh, its cell counts multiplied by `refine`.
    fn annulus_mesh(
        &self,
        spec: &PartSpec,
        a: &AnnulusSpec,
        name: &str,
        refine: usize,
    ) -> Result<Mesh> {
        let span = a.theta[1] - a.theta[0];
        let ok = a.r[0] > 0.0
            && a.r[1] > a.r[0]
            && span > 0.0
            && span <= 360.0 * (1.0 + 1e-12)
            && a.cells[0] > 0
            && a.cells[1] > 0
            && a.center
                .iter()
                .chain(&a.r)
                .chain(&a.theta)
                .all(|v| v.is_finite());
        let full = (span - 360.0).abs() <= 1e-12 * 360.0;
        if !ok || (full && a.cells[1] < 3) {
            return Err(self.err(
                &spec.name,
                format!("part '{name}': annulus needs 0 < r0 < r1, θ0 < θ1 ≤ θ0 + 360 (degrees) and at least one cell each way, three around a full ring (got r = {:?}, theta = {:?}, cells = {:?})", a.r, a.theta, a.cells),
            ));
        }
        Ok(Mesh::annulus(
            a.center,
            a.r,
            a.theta,
            [a.cells[0] * refine, a.cells[1] * refine],
            a.elements,
        ))
    }

    /// An interface: its parts, its coupling nodes (each claimed by one interface
    /// only, recorded in `claimed`), its penalties and tolerance.
    fn interface<D: ProblemDim>(
        &self,
        index: usize,
        spec: &InterfaceSpec,
        name: String,
        parts: &[Part<D>],
        claimed: &mut BTreeMap<(usize, usize), String>,
    ) -> Result<InterfaceDef> {
        let host = self.part_index(parts, &spec.host, "host")?;
        let node_part = self.part_index(parts, &spec.nodes, "nodes")?;
        if host == node_part {
            return Err(self.err(
                &spec.host,
                format!("interface '{name}': host and node part are the same part"),
            ));
        }
        let nodes = self.coupling_nodes(spec, &name, &parts[node_part], node_part, claimed)?;
        // In volume form the boundary may be left out: h over the whole part.
        let boundary = spec.boundary.as_ref().map_or("", |b| b.get_ref().as_str());
        let scales = D::stiffness_scales(&parts[host], &parts[node_part], boundary);
        let (c_n, c_s, tolerance) = self.penalties(spec, &name, scales)?;
        let (friction, search_distance, penetration_tolerance) =
            self.contact_keys(spec, &name, parts, host, node_part)?;
        let softer = if scales[0] <= scales[1] {
            (&parts[host].name, scales[0])
        } else {
            (&parts[node_part].name, scales[1])
        };
        self.check_penalty_ratios(index, spec, c_n, c_s, softer)?;
        Ok(InterfaceDef {
            name,
            host,
            node_part,
            nodes,
            boundary: spec
                .boundary
                .as_ref()
                .map_or_else(String::new, |b| b.get_ref().clone()),
            law: spec.law,
            c_n,
            c_s,
            tolerance,
            friction,
            search_distance,
            enforcement: spec.enforcement,
            penetration_tolerance,
            coupling: spec.coupling,
            form: spec.form,
        })
    }

    /// The coupling nodes of interface `name`: those of its boundary on the node
    /// part (number `node_part`; in volume form without a boundary, all its
    /// nodes), each claimed in `claimed` (a node claimed by two
    /// interfaces is refused).
    fn coupling_nodes<D: MeshDim>(
        &self,
        spec: &InterfaceSpec,
        name: &str,
        part: &Part<D>,
        node_part: usize,
        claimed: &mut BTreeMap<(usize, usize), String>,
    ) -> Result<Vec<usize>> {
        let nodes = match &spec.boundary {
            Some(b) => {
                self.boundary(part, b)?;
                part.mesh.boundary_nodes(b.get_ref()).unwrap_or_default()
            }
            None if spec.form == crate::domain::CouplingForm::Volume => {
                (0..part.mesh.nodes.len()).collect()
            }
            None => {
                let msg = format!(
                    "interface '{name}' needs `boundary`: the boundary of part '{}' whose nodes couple (only form = \"volume\" may leave it out: every node of the part then couples)",
                    part.name
                );
                return Err(self.err(&spec.nodes, msg));
            }
        };
        for &n in &nodes {
            if let Some(other) = claimed.insert((node_part, n), name.to_string()) {
                return Err(self.err(
                    spec.boundary.as_ref().unwrap_or(&spec.nodes),
                    format!(
                        "node {n} of part '{}' is claimed by interfaces '{other}' and '{name}'",
                        part.name
                    ),
                ));
            }
        }
        Ok(nodes)
    }

    /// The penalties `c_n`, `c_s` and the pair tolerance of interface `name`
    /// between parts `host` and `nodes`, given or by default, each positive and
    /// finite (`c_s` may be 0 with the frictionless law).
    fn penalties(
        &self,
        spec: &InterfaceSpec,
        name: &str,
        [host, nodes]: [f64; 2],
    ) -> Result<(f64, f64, f64)> {
        // The tie's compliance 1/c acts in series with the softer part's local
        // compliance ~ 1/(E·t): its relative error is E·t/c of the softer part.
        // Scaling by the stiffer part would make c needlessly large (round-off)
        // when the materials differ by orders of magnitude.
        let default_c = DEFAULT_PENALTY_FACTOR * host.min(nodes);
        let c_n = spec.c_n.unwrap_or(default_c);
        let frictionless = spec.law == Law::Frictionless;
        // The frictionless law ignores c_s: absent, it is 0.
        let c_s = spec.c_s.unwrap_or(if frictionless { 0.0 } else { c_n });
        let tolerance = spec.tolerance.unwrap_or(DEFAULT_PAIR_TOLERANCE);
        for (key, v) in [("c_n", c_n), ("c_s", c_s), ("tolerance", tolerance)] {
            let zero_ok = key == "c_s" && frictionless;
            if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
                let hint = if key == "c_s" {
                    " (c_s = 0 is allowed only with law = \"frictionless\")"
                } else {
                    ""
                };
                return Err(self.err(
                    &spec.host,
                    format!("interface '{name}': `{key}` = {v} must be positive and finite{hint}"),
                ));
            }
        }
        Ok((c_n, c_s, tolerance))
    }

    /// Refuses a penalty `c_n` or `c_s` of interface number `index` beyond 1/ε ×
    /// the stiffness scale `et` of the softer part (named), or far below it.
    fn check_penalty_ratios(
        &self,
        index: usize,
        spec: &InterfaceSpec,
        c_n: f64,
        c_s: f64,
        (softer, et): (&String, f64),
    ) -> Result<()> {
        let frictionless = spec.law == Law::Frictionless;
        // A penalty beyond 1/ε × E·t of the softer part hides that part's stiffness
        // in round-off: refused here with its name rather than as a failed pivot.
        for (key, c) in [("c_n", c_n), ("c_s", c_s)] {
            let at = [
                check::Seg::K("interface"),
                check::Seg::I(index),
                check::Seg::K(key),
            ];
            self.values.penalty(&at, c, et, softer)?;
            // A penalty far below E·t holds nothing: refused by name rather than
            // met as a mechanism. The frictionless law ignores c_s.
            if !(key == "c_s" && frictionless) {
                self.values.weak_penalty(&at, c, et, softer)?;
            }
        }
        Ok(())
    }

    /// The keys of the contact laws of interface `name`: `friction` (only with, and
    /// required by, `coulomb`), `search_distance` (a length ≥ 0; not on a rigid tie) and `penetration_tolerance` (augmented
    /// enforcement only; by default 1e-6 × the two parts' bounding diagonal).
    fn contact_keys<D: MeshDim>(
        &self,
        spec: &InterfaceSpec,
        name: &str,
        parts: &[Part<D>],
        host: usize,
        node_part: usize,
    ) -> Result<(f64, f64, f64)> {
        let friction = self.friction(spec, name)?;
        let search_distance = spec.search_distance.unwrap_or(0.0);
        if !(search_distance.is_finite() && search_distance >= 0.0) {
            return Err(self.err(
                &spec.host,
                format!(
                    "interface '{name}': `search_distance` = {search_distance} must be a finite length ≥ 0"
                ),
            ));
        }
        if search_distance > 0.0 && spec.law == Law::Rigid {
            return Err(self.err(
                &spec.host,
                format!(
                    "interface '{name}': `search_distance` needs a contact law (contact, frictionless, coulomb); a rigid tie joins faces that touch (use `tolerance`)"
                ),
            ));
        }
        let penetration_tolerance = match spec.penetration_tolerance {
            Some(t) if t.is_finite() && t > 0.0 => t,
            Some(t) => {
                return Err(self.err(
                    &spec.host,
                    format!(
                        "interface '{name}': `penetration_tolerance` = {t} must be a positive, finite length"
                    ),
                ));
            }
            // 1e-6 × the size of the two parts (their bounding box's diagonal).
            None => {
                DEFAULT_PENETRATION_TOLERANCE
                    * bounding_diagonal(&[&parts[host].mesh, &parts[node_part].mesh])
            }
        };
        if spec.penetration_tolerance.is_some() && spec.enforcement != Enforcement::Augmented {
            return Err(self.err(
                &spec.host,
                format!(
                    "interface '{name}': `penetration_tolerance` applies to enforcement = \"augmented\" only"
                ),
            ));
        }
        Ok((friction, search_distance, penetration_tolerance))
    }

    /// The friction coefficient μ of interface `name`: required by, and only
    /// allowed with, the Coulomb law (0 for the other laws).
    fn friction(&self, spec: &InterfaceSpec, name: &str) -> Result<f64> {
        Ok(match (spec.law, spec.friction) {
            (Law::Coulomb, Some(mu)) if mu.is_finite() && mu >= 0.0 => mu,
            (Law::Coulomb, Some(mu)) => {
                return Err(self.err(
                    &spec.host,
                    format!(
                        "interface '{name}': `friction` = {mu} must be finite and non-negative"
                    ),
                ));
            }
            (Law::Coulomb, None) => {
                return Err(self.err(
                    &spec.host,
                    format!(
                        "interface '{name}': law = \"coulomb\" needs `friction` = μ (the friction coefficient)"
                    ),
                ));
            }
            (law, Some(_)) => {
                return Err(self.err(
                    &spec.host,
                    format!(
                        "interface '{name}': `friction` applies to law = \"coulomb\" only, not \"{}\"",
                        law.as_str()
                    ),
                ));
            }
            (_, None) => 0.0,
        })
    }

    /// A Dirichlet condition on a boundary or at a node.
    fn support(&self, spec: &SupportSpec<2>, parts: &[Part]) -> Result<Support> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        if spec.from.is_some() || spec.to.is_some() {
            return Err(self.err(
                &spec.part,
                "a support's box (`from`/`to`) selects nodes of a solid model only; a plane model's support takes `boundary` or `at`",
            ));
        }
        let (name, nodes) = match (&spec.boundary, spec.at) {
            (Some(b), None) => (
                format!("{}/{}", part.name, b.get_ref()),
                self.support_nodes(part, b)?,
            ),
            (None, Some(at)) => (
                format!("{}@{}", part.name, crate::results::fmt::point(at)),
                vec![self.node_at(part, at, &spec.part, "support")?],
            ),
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a [[support]] needs exactly one of `boundary` or `at`",
                ));
            }
        };
        if spec.fix.is_empty() {
            return Err(self.err(
                &spec.part,
                format!(
                    "support '{name}': `fix` is empty; give [\"x\"], [\"y\"] or [\"x\", \"y\"]"
                ),
            ));
        }
        if spec.fix.contains(&Component::Z) {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `fix` names \"z\", which a plane model does not have: give [\"x\"], [\"y\"] or [\"x\", \"y\"] (z belongs to a solid model, of `box` or 3D Gmsh parts)"),
            ));
        }
        if spec.fix.len() == 2 && spec.fix[0] == spec.fix[1] {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `fix` names the same component twice; give [\"x\"], [\"y\"] or [\"x\", \"y\"]"),
            ));
        }
        if spec.fix.len() > 2 {
            return Err(self.err(
                &spec.part,
                format!(
                    "support '{name}': `fix` has {} entries; give at most \"x\" and \"y\"",
                    spec.fix.len()
                ),
            ));
        }
        if !spec.value.iter().all(|v| v.is_finite()) {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `value` must be finite"),
            ));
        }
        Ok(Support {
            name,
            part: p,
            nodes,
            fix: [
                spec.fix.contains(&Component::X),
                spec.fix.contains(&Component::Y),
                false,
            ],
            value: [spec.value[0], spec.value[1], 0.0],
            step: 0,
        })
    }

    /// A load resolved to nodal forces: a pressure over a boundary, or a resultant
    /// at a node, over a boundary or over a segment of the boundary.
    fn load(&self, spec: &LoadSpec<2>, parts: &[Part]) -> Result<Load> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        if !spec
            .force
            .iter()
            .flatten()
            .chain(&spec.pressure)
            .all(|v| v.is_finite())
        {
            return Err(self.err(&spec.part, "load `force` and `pressure` must be finite"));
        }
        if let Some(pressure) = spec.pressure {
            return self.pressure_load(spec, p, part, pressure);
        }
        let Some(force) = spec.force else {
            return Err(self.err(
                &spec.part,
                "a [[load]] needs `force` (a resultant, with `at`, `boundary` or `from`/`to`) or `pressure` (with `boundary`)",
            ));
        };
        Ok(match (&spec.boundary, spec.from, spec.to, spec.at) {
            (None, None, None, Some(at)) => {
                let n = self.node_at(part, at, &spec.part, "point load")?;
                Load {
                    name: format!("{}@{}", part.name, crate::results::fmt::point(at)),
                    part: p,
                    nodal: vec![(n, force)],
                    resultant: force,
                    step: 0,
                }
            }
            (Some(b), None, None, None)
                if !part.mesh.boundaries.contains_key(b.get_ref())
                    && part.mesh.node_sets.contains_key(b.get_ref()) =>
            {
                let set = &part.mesh.node_sets[b.get_ref()];
                Load {
                    name: format!("{}/{}", part.name, b.get_ref()),
                    part: p,
                    nodal: spread_equally(&set.nodes, force),
                    resultant: force,
                    step: 0,
                }
            }
            (Some(b), None, None, None) => {
                let edges = edges_of(part, self.boundary(part, b)?);
                Load {
                    name: format!("{}/{}", part.name, b.get_ref()),
                    part: p,
                    nodal: if part.material.is_axisymmetric() {
                        axisymmetric::chain_forces(&edges, force)
                    } else {
                        loads::chain_forces(&edges, force)
                    },
                    resultant: force,
                    step: 0,
                }
            }
            (b, Some(from), Some(to), None) => {
                self.segment_load(spec, p, part, b.as_ref(), [from, to], force)?
            }
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a [[load]] needs `at` (point load), `boundary` (whole boundary), or `from` and `to` (segment, optionally with `boundary`)",
                ));
            }
        })
    }

    /// A normal traction `pressure` over a whole boundary of part `part` (number
    /// `p`), resolved to nodal forces.
    fn pressure_load(
        &self,
        spec: &LoadSpec<2>,
        p: usize,
        part: &Part,
        pressure: f64,
    ) -> Result<Load> {
        let b = match (&spec.boundary, spec.force, spec.from, spec.to, spec.at) {
            (Some(b), None, None, None, None) => b,
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a pressure [[load]] needs `boundary` and `pressure` only (no `force`, `at`, `from` or `to`)",
                ));
            }
        };
        let edges = edges_of(part, self.boundary(part, b)?);
        let nodal = if part.material.is_axisymmetric() {
            axisymmetric::pressure_forces(&edges, pressure)
        } else {
            loads::pressure_forces(&edges, pressure)
        };
        let mut resultant = [0.0; 2];
        for (_, f) in &nodal {
            resultant[0] += f[0];
            resultant[1] += f[1];
        }
        Ok(Load {
            name: format!("{}/{} (pressure {pressure})", part.name, b.get_ref()),
            part: p,
            nodal,
            resultant,
            step: 0,
        })
    }

    /// A resultant `force` spread over the segment `from`–`to` of the boundary
    /// of part `part` (number `p`; of its boundary `b` if named), which must lie
    /// on that boundary over its whole length.
    fn segment_load(
        &self,
        spec: &LoadSpec<2>,
        p: usize,
        part: &Part,
        b: Option<&Spanned<String>>,
        [from, to]: [[f64; 2]; 2],
        force: [f64; 2],
    ) -> Result<Load> {
        let seg_len = crate::mesh::dist(from, to);
        if seg_len <= 0.0 || seg_len.is_nan() {
            return Err(self.err(&spec.part, "load segment has `from` equal to `to`"));
        }
        let edges = match b {
            Some(b) => edges_of(part, self.boundary(part, b)?),
            None => edges_of(part, &part.mesh.boundary_edges()),
        };
        let tol = 1e-6 * part.mesh.max_edge_length();
        let (nodal, covered) = if part.material.is_axisymmetric() {
            axisymmetric::segment_forces(&edges, from, to, force, tol)
        } else {
            loads::segment_forces(&edges, from, to, force, tol)
        };
        if (covered - seg_len).abs() > 1e-6 * seg_len {
            return Err(self.err(
                &spec.part,
                format!(
                    "load segment ({}, {})–({}, {}) lies on the boundary of part '{}' over {covered:.6} of its length {seg_len:.6}: the whole segment must lie on the part's boundary",
                    from[0], from[1], to[0], to[1], part.name
                ),
            ));
        }
        Ok(Load {
            name: format!(
                "{}[({},{})-({},{})]",
                part.name, from[0], from[1], to[0], to[1]
            ),
            part: p,
            nodal,
            resultant: force,
            step: 0,
        })
    }
}

/// The edges `edges` of part `part` with their end points, as the load
/// routines take them.
fn edges_of(part: &Part, edges: &[crate::mesh::BoundaryEdge]) -> Vec<([usize; 2], [[f64; 2]; 2])> {
    edges
        .iter()
        .map(|e| (e.nodes, e.nodes.map(|n| part.mesh.nodes[n])))
        .collect()
}

/// A refined Gmsh (or in-memory) part keeps its polygons: its curved
/// boundaries are not refined towards the curve (the built-in meshers mesh
/// theirs anew). Empty at refinement 1.
fn kept_polygons(
    part_specs: &[PartSpec],
    parts: &[Part],
    refine: usize,
) -> Vec<(String, crate::mesh::CurvedBoundary)> {
    if refine <= 1 {
        return Vec::new();
    }
    part_specs
        .iter()
        .zip(parts)
        .filter(|(spec, _)| spec.rectangle.is_none() && spec.annulus.is_none())
        .flat_map(|(_, p)| {
            p.mesh
                .curved_boundaries()
                .into_iter()
                .map(|b| (p.name.clone(), b))
        })
        .collect()
}

/// The load steps of the `[[step]]` tables, in order (their factors resolved
/// once the loads and supports are named: [`Builder::step_factors`]).
pub(super) fn steps(step_specs: &[StepSpec]) -> Vec<Step> {
    step_specs
        .iter()
        .map(|s| Step {
            scale: s.scale,
            ..Step::new(s.name.get_ref().clone(), s.increments)
        })
        .collect()
}

/// The index of the step a support or load names (the first without one).
pub(super) fn step_of(steps: &[Step], s: &Option<Spanned<String>>) -> usize {
    // Checked by `check::steps`: a named step exists.
    s.as_ref()
        .and_then(|s| steps.iter().position(|t| &t.name == s.get_ref()))
        .unwrap_or(0)
}

/// The names of one kind of table: the `given` names replace the `defaults`,
/// which are made unique (a second support on one boundary gets ` (2)`, see
/// [`unique_defaults`]).
pub(super) fn names<'s>(
    given: impl Iterator<Item = &'s Option<Spanned<String>>>,
    defaults: impl Iterator<Item = &'s str>,
) -> Vec<String> {
    unique_defaults(
        given
            .zip(defaults)
            .map(|(name, default)| match name {
                Some(n) => (n.get_ref().clone(), true),
                None => (default.to_string(), false),
            })
            .collect(),
    )
}

/// About the number of nodes a mesh of `nodes` nodes has once refined `refine`
/// times ([`Mesh::refined`]): `refine`² × `nodes` (an upper bound for a
/// triangulated mesh, whose edges are at most 3 and triangles at most 2 per
/// node), `u64::MAX` when that overflows, so [`check_size`] refuses it before
/// any memory is spent.
pub(super) fn refined_nodes(nodes: usize, refine: usize) -> u64 {
    let k = refine as u64;
    (nodes as u64)
        .checked_mul(k)
        .and_then(|n| n.checked_mul(k))
        .unwrap_or(u64::MAX)
}

/// The names of one kind of table, `(name, given)` each, with the default
/// names (`given` false) made unique: a default name already taken (by a given
/// name or an earlier table) gets ` (2)`, ` (3)`, … Given names are checked
/// unique before (`check::names`) and are kept as they are.
fn unique_defaults(names: Vec<(String, bool)>) -> Vec<String> {
    let mut taken: std::collections::HashSet<String> = names
        .iter()
        .filter(|(_, given)| *given)
        .map(|(n, _)| n.clone())
        .collect();
    names
        .into_iter()
        .map(|(name, given)| {
            if given {
                return name;
            }
            let mut unique = name.clone();
            let mut k = 2usize;
            while taken.contains(&unique) {
                unique = format!("{name} ({k})");
                k += 1;
            }
            taken.insert(unique.clone());
            unique
        })
        .collect()
}

/// ([`crate::results::memory::estimated_peak_bytes`]) exceeds what the machine has
/// available, before it is meshed.
pub(super) fn check_size(nodes: u64, refine: usize) -> Result<()> {
    check_size_of(nodes, 2, refine)
}

/// [`check_size`] of a model of `per_node` unknowns per node.
pub(super) fn check_size_of(nodes: u64, per_node: u64, refine: usize) -> Result<()> {
    let unknowns = nodes.saturating_mul(per_node);
    let bytes = crate::results::memory::estimated_peak_bytes(unknowns);
    let Some(available) = crate::results::memory::available_memory_bytes() else {
        return Ok(());
    };
    if bytes <= available {
        return Ok(());
    }
    Err(Error::TooLarge {
        unknowns,
        bytes,
        available,
        message: format!(
            "the model would have about {unknowns} unknowns{} and need about {:.1} GiB, but {:.1} GiB of memory are available; use a smaller refinement or fewer cells",
            if refine > 1 {
                format!(" at refinement {refine}")
            } else {
                String::new()
            },
            bytes as f64 / (1u64 << 30) as f64,
            available as f64 / (1u64 << 30) as f64
        ),
    })
}

/// What a `boundary` key names on a part ([`Builder::boundary_or_set`]).
pub(super) enum Named<'m, F> {
    /// A named boundary (its facets: [`Mesh::boundary_nodes`] gives its nodes).
    Boundary(#[allow(dead_code)] &'m [F]),
    /// A named node set.
    NodeSet(&'m NodeSet),
}

/// A resultant `force` spread equally over `nodes` (each node `force / n`):
/// a `force` [[load]] on a node set.
pub(super) fn spread_equally<const N: usize>(
    nodes: &[usize],
    force: [f64; N],
) -> Vec<(usize, [f64; N])> {
    let n = nodes.len() as f64;
    nodes.iter().map(|&a| (a, force.map(|c| c / n))).collect()
}

/// The names of `names`, comma separated.
fn keys<'a>(names: impl Iterator<Item = &'a String>) -> String {
    names.map(String::as_str).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Default names that repeat, or equal a given name, get the first free
    /// ` (k)`; given names are kept as they are.
    #[test]
    fn default_names_are_made_unique() {
        let names = unique_defaults(vec![
            ("a".into(), false),
            ("a".into(), false),
            ("a (2)".into(), true),
            ("a".into(), false),
            ("b".into(), true),
            ("b".into(), false),
        ]);
        assert_eq!(names, ["a", "a (3)", "a (2)", "a (4)", "b", "b (2)"]);
    }
}
