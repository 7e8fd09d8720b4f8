//! Model: reads a problem file (TOML), checks it, meshes its parts and resolves every
//! selection (supports, loads, interface boundaries) into nodes and nodal values.
//! Errors name the file, the line and the key at fault.
//!
//! The problem-file reference is in README.md; `examples/` holds complete files.

use crate::coupling::{Coupling, Enforcement, Law};
pub use crate::domain::{InterfaceDef, Load, Part, Scheme, Settings, Step, Support};
use crate::error::{Error, Result};
use crate::fem::{Material, PlaneKind, loads};
use crate::mesh::gmsh::{GmshMesh, Group};
use crate::mesh::input_file::{self, MESH_FILE_CAP, PROBLEM_FILE_CAP};
use crate::mesh::{ElementKind, Mesh, bounding_diagonal};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use toml::Spanned;

mod check;

/// Default relative geometric tolerance of the pair search: a coupling node may lie
/// up to this fraction of the host edge's length off that edge (it is then moved
/// onto it). 5 % admits a fine circular face against a coarse polygonal one down
/// to about 2.5 host edges per radian (the gap is (edge length)² / (8 radius)),
/// as the tie constraints of established codes admit a few per cent of the
/// element size, while faces meshed visibly apart are still rejected.
pub const DEFAULT_PAIR_TOLERANCE: f64 = 0.05;
/// Default `penetration_tolerance` of the augmented Lagrangian, as a fraction of
/// the diagonal of the bounding box of the interface's two parts.
pub const DEFAULT_PENETRATION_TOLERANCE: f64 = 1e-6;
/// Poisson's ratio from which a part in plane strain gets a volumetric-locking
/// warning ([`Model::warnings`]): the bulk modulus is then 1/(1 − 2ν) ≥ 50 times
/// the shear modulus.
pub const LOCKING_NU: f64 = 0.49;
/// Default coupling penalty as a multiple of the softer part's E·t.
pub const DEFAULT_PENALTY_FACTOR: f64 = 1e5;

// ---------------------------------------------------------------- file schema

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ProblemFile {
    title: Option<String>,
    #[serde(default)]
    units: Units,
    #[serde(default = "default_plane")]
    plane: PlaneKind,
    materials: BTreeMap<String, MaterialSpec>,
    #[serde(rename = "part")]
    parts: Vec<PartSpec>,
    #[serde(rename = "interface", default)]
    interfaces: Vec<InterfaceSpec>,
    #[serde(rename = "support", default)]
    supports: Vec<SupportSpec>,
    #[serde(rename = "load", default)]
    loads: Vec<LoadSpec>,
    #[serde(default)]
    analysis: Settings,
    #[serde(rename = "step", default)]
    steps: Vec<StepSpec>,
}

/// `[[step]]`: a load step.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StepSpec {
    name: Spanned<String>,
    increments: usize,
}

/// The name of the one step of a problem without `[[step]]` tables.
pub const DEFAULT_STEP: &str = "step-1";

fn default_plane() -> PlaneKind {
    PlaneKind::Stress
}

/// Unit names, used only to label outputs (cfe itself is unit-agnostic).
#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Units {
    /// Length unit (default `mm`).
    pub length: String,
    /// Force unit (default `N`).
    pub force: String,
    /// Stress unit (default `MPa`).
    pub stress: String,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            length: "mm".into(),
            force: "N".into(),
            stress: "MPa".into(),
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialSpec {
    #[serde(rename = "E")]
    young: f64,
    nu: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PartSpec {
    name: Spanned<String>,
    material: Spanned<String>,
    #[serde(default = "one")]
    thickness: f64,
    rectangle: Option<RectangleSpec>,
    annulus: Option<AnnulusSpec>,
    gmsh: Option<Spanned<GmshSpec>>,
}

fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct RectangleSpec {
    #[serde(deserialize_with = "pair")]
    x: [f64; 2],
    #[serde(deserialize_with = "pair")]
    y: [f64; 2],
    #[serde(deserialize_with = "pair")]
    cells: [usize; 2],
    /// `t3` (each cell split into two triangles, the default) or `q4`.
    #[serde(default = "default_elements")]
    elements: ElementKind,
    /// T3 only: `rising` (`/`, the default) or `falling` (`\`) cell diagonals.
    #[serde(default)]
    diagonal: crate::mesh::Diagonal,
}

/// A two-entry array (`[x, y]`, `[nx, ny]`, …) with exactly two entries: serde's
/// fixed-size arrays would silently drop extra entries of a TOML array.
fn pair<'de, D, T>(d: D) -> std::result::Result<[T; 2], D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let v: Vec<T> = Vec::deserialize(d)?;
    let n = v.len();
    <[T; 2]>::try_from(v).map_err(|_| {
        serde::de::Error::custom(format!("expected an array of exactly 2 values, got {n}"))
    })
}

/// [`pair`] for an optional key.
fn opt_pair<'de, D, T>(d: D) -> std::result::Result<Option<[T; 2]>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let Some(v) = Option::<Vec<T>>::deserialize(d)? else {
        return Ok(None);
    };
    let n = v.len();
    <[T; 2]>::try_from(v).map(Some).map_err(|_| {
        serde::de::Error::custom(format!("expected an array of exactly 2 values, got {n}"))
    })
}

fn default_elements() -> ElementKind {
    ElementKind::T3
}

/// `annulus = { center, r = [r0, r1], theta = [θ0, θ1], cells = [nr, nt] }`: a
/// structured annular sector (angles in degrees).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct AnnulusSpec {
    #[serde(default, deserialize_with = "pair")]
    center: [f64; 2],
    #[serde(deserialize_with = "pair")]
    r: [f64; 2],
    #[serde(default = "full_turn", deserialize_with = "pair")]
    theta: [f64; 2],
    #[serde(deserialize_with = "pair")]
    cells: [usize; 2],
    #[serde(default = "default_elements")]
    elements: ElementKind,
}

fn full_turn() -> [f64; 2] {
    [0.0, 360.0]
}

/// `gmsh = { file = "plate.msh", surfaces = ["plate"] }`: a part meshed in Gmsh.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct GmshSpec {
    /// The .msh file, relative to the problem file's folder.
    file: String,
    /// Physical surfaces (names or numbers) whose elements make the part; default all.
    surfaces: Option<Vec<GroupSpec>>,
}

/// A physical group given by name (string) or number (integer).
#[derive(Debug, Clone)]
struct GroupSpec(Group);

impl<'de> Deserialize<'de> for GroupSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = GroupSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a physical surface name (string) or number (integer)")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<GroupSpec, E> {
                Ok(GroupSpec(Group::Name(v.to_string())))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<GroupSpec, E> {
                i32::try_from(v)
                    .map(|t| GroupSpec(Group::Tag(t)))
                    .map_err(|_| E::custom(format!("physical tag {v} is out of range")))
            }
        }
        d.deserialize_any(Visitor)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InterfaceSpec {
    name: Option<Spanned<String>>,
    host: Spanned<String>,
    nodes: Spanned<String>,
    boundary: Spanned<String>,
    #[serde(default = "default_law")]
    law: Law,
    c_n: Option<f64>,
    c_s: Option<f64>,
    tolerance: Option<f64>,
    friction: Option<f64>,
    search_distance: Option<f64>,
    #[serde(default)]
    enforcement: Enforcement,
    penetration_tolerance: Option<f64>,
    #[serde(default)]
    coupling: Coupling,
}

fn default_law() -> Law {
    Law::Contact
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
enum Component {
    X,
    Y,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SupportSpec {
    /// Default: `part/boundary` or `part@(x, y)`.
    name: Option<Spanned<String>>,
    part: Spanned<String>,
    boundary: Option<Spanned<String>>,
    #[serde(default, deserialize_with = "opt_pair")]
    at: Option<[f64; 2]>,
    fix: Vec<Component>,
    #[serde(default, deserialize_with = "pair")]
    value: [f64; 2],
    step: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadSpec {
    /// Default: from the part and where the load acts (see [`Builder::load`]).
    name: Option<Spanned<String>>,
    part: Spanned<String>,
    boundary: Option<Spanned<String>>,
    #[serde(default, deserialize_with = "opt_pair")]
    from: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "opt_pair")]
    to: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "opt_pair")]
    at: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "opt_pair")]
    force: Option<[f64; 2]>,
    pressure: Option<f64>,
    step: Option<Spanned<String>>,
}

/// A checked, meshed model ready for analysis.
#[derive(Debug, Clone)]
pub struct Model {
    /// Title (default: the file stem).
    pub title: String,
    /// The problem file it came from.
    pub source: PathBuf,
    /// Unit labels.
    pub units: Units,
    /// Parts in file order.
    pub parts: Vec<Part>,
    /// Interfaces in file order.
    pub interfaces: Vec<InterfaceDef>,
    /// Dirichlet conditions.
    pub supports: Vec<Support>,
    /// External loads.
    pub loads: Vec<Load>,
    /// Analysis settings.
    pub settings: Settings,
    /// The load steps of `[[step]]` tables, in order; empty without them (one
    /// step of `settings.increments`, see [`Model::steps`]).
    pub steps: Vec<Step>,
    /// Refinement factor: the structured meshes' cell counts are multiplied by it,
    /// the Gmsh meshes subdivided uniformly by it.
    pub refine: usize,
    /// The problem text, so the same problem can be rebuilt at another refinement.
    pub text: String,
    /// The curved boundaries of the parts refined from a given mesh (Gmsh, or
    /// in memory) as (part name, boundary): `--refine` kept their polygons.
    pub kept_polygons: Vec<(String, crate::mesh::CurvedBoundary)>,
}

/// A problem given as text (TOML), read as if from a file `problem.toml` in the
/// current folder, at refinement 1.
impl std::str::FromStr for Model {
    type Err = Error;

    fn from_str(text: &str) -> Result<Model> {
        Model::from_str(text, Path::new("problem.toml"), 1)
    }
}

impl Model {
    /// The index of the part named `name`.
    pub fn part_index(&self, name: &str) -> Option<usize> {
        self.parts.iter().position(|p| p.name == name)
    }

    /// Reads, checks and meshes the problem file at `path`; `refine` multiplies every
    /// structured part's cell counts and splits every edge of a Gmsh part into that
    /// many (1 = as written).
    pub fn from_file(path: &Path, refine: usize) -> Result<Model> {
        let read_error = |source| Error::ReadInput {
            path: path.to_path_buf(),
            source,
        };
        let data = input_file::read(path, "problem file", PROBLEM_FILE_CAP, read_error)?;
        let text = String::from_utf8(data)
            .map_err(|e| read_error(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))?;
        Model::from_str(&text, path, refine)
    }

    /// The same problem with the meshes refined `refine` times instead.
    pub fn with_refine(&self, refine: usize) -> Result<Model> {
        Model::from_str(&self.text, &self.source, refine)
    }

    /// A model built in code from its parts: no problem file behind it (so no
    /// coarser level for the warm start: [`Model::with_refine`] fails). Names
    /// given twice within a kind are refused ([`Model::check_names`]).
    #[allow(clippy::too_many_arguments)]
    pub fn from_parts(
        title: impl Into<String>,
        parts: Vec<Part>,
        interfaces: Vec<InterfaceDef>,
        supports: Vec<Support>,
        loads: Vec<Load>,
        settings: Settings,
    ) -> Result<Model> {
        let model = Model {
            title: title.into(),
            source: PathBuf::new(),
            units: Units::default(),
            parts,
            interfaces,
            supports,
            loads,
            settings,
            steps: Vec::new(),
            refine: 1,
            text: String::new(),
            kept_polygons: Vec::new(),
        };
        model.check_names()?;
        Ok(model)
    }

    /// Refuses a name given to two parts, two interfaces, two supports, two
    /// loads or two steps ([`Error::DuplicateName`], the key counting each kind
    /// from 1, e.g. `interface#2.name`): results, reactions and references are
    /// keyed by name. A problem file's names are checked as it is read, with
    /// their lines; this check is for models built or changed in code.
    pub fn check_names(&self) -> Result<()> {
        let kinds: [(&str, Vec<&str>); 5] = [
            ("part", self.parts.iter().map(|p| p.name.as_str()).collect()),
            (
                "interface",
                self.interfaces.iter().map(|i| i.name.as_str()).collect(),
            ),
            (
                "support",
                self.supports.iter().map(|s| s.name.as_str()).collect(),
            ),
            ("load", self.loads.iter().map(|l| l.name.as_str()).collect()),
            ("step", self.steps.iter().map(|s| s.name.as_str()).collect()),
        ];
        for (kind, names) in kinds {
            let mut seen: HashMap<&str, usize> = HashMap::with_capacity(names.len());
            for (i, name) in names.iter().enumerate() {
                if let Some(first) = seen.insert(name, i) {
                    return Err(Error::DuplicateName {
                        path: self.source.clone(),
                        line: None,
                        key: format!("{kind}#{}.name", i + 1),
                        name: name.to_string(),
                        message: format!(
                            "= \"{name}\" is defined twice: {kind} #{} has this name too; {kind} names must be unique (results, reactions and references are keyed by name): rename one",
                            first + 1
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Advice about the model that does not stop it from being solved: parts in
    /// plane strain with ν ≥ [`LOCKING_NU`], whose displacement elements lock
    /// (volumetric locking: too stiff, with oscillating pressure), T3 most.
    pub fn warnings(&self) -> Vec<String> {
        self.parts
            .iter()
            .filter(|p| p.material.plane == PlaneKind::Strain && p.material.poisson >= LOCKING_NU)
            .map(|p| {
                let (t3, _) = p.mesh.counts();
                let nu = p.material.poisson;
                let ratio = 1.0 / (1.0 - 2.0 * nu);
                let advice = if t3 > 0 {
                    "its T3 elements lock (they cannot deform at constant volume, so displacements come out too small and stresses oscillate); use Q4 elements (`elements = \"q4\"`, which lock far less), plane = \"stress\" if the part is thin, or check the results against a finer mesh"
                } else {
                    "its Q4 elements (full integration) stiffen (volumetric locking: displacements come out too small); check the results against a finer mesh, or use plane = \"stress\" if the part is thin"
                };
                format!(
                    "part '{}': ν = {nu} in plane strain is nearly incompressible (bulk modulus {ratio:.1e} × the shear modulus): {advice}",
                    p.name
                )
            })
            .collect()
    }

    /// The load steps: those of the `[[step]]` tables, or without them one step
    /// named [`DEFAULT_STEP`] of `settings.increments`.
    pub fn steps(&self) -> Vec<Step> {
        if self.steps.is_empty() {
            vec![Step {
                name: DEFAULT_STEP.into(),
                increments: self.settings.increments,
            }]
        } else {
            self.steps.clone()
        }
    }

    /// The steps in which some load or prescribed value is applied (sorted).
    pub fn loaded_steps(&self) -> Vec<usize> {
        let mut s: Vec<usize> = self
            .loads
            .iter()
            .filter(|l| l.nodal.iter().any(|(_, f)| f[0] != 0.0 || f[1] != 0.0))
            .map(|l| l.step)
            .chain(
                self.supports
                    .iter()
                    .filter(|s| (0..2).any(|c| s.fix[c] && s.value[c] != 0.0))
                    .map(|s| s.step),
            )
            .collect();
        s.sort_unstable();
        s.dedup();
        s
    }

    /// Reads, checks and meshes a problem given as text; `path` is used in messages
    /// and for the default title.
    pub fn from_str(text: &str, path: &Path, refine: usize) -> Result<Model> {
        Model::from_str_with_meshes(text, path, refine, BTreeMap::new())
    }

    /// As [`Model::from_str`], with the meshes of some parts given (by part name)
    /// instead of by a mesh key in the text (e.g. [`Mesh::from_arrays`]): such a
    /// part has no `rectangle`, `annulus` or `gmsh` key; its boundaries are the
    /// mesh's. Each given mesh must belong to a part of the text. `refine`
    /// subdivides the given meshes as it does Gmsh meshes ([`Mesh::refined`]).
    pub fn from_str_with_meshes(
        text: &str,
        path: &Path,
        refine: usize,
        meshes: BTreeMap<String, Mesh>,
    ) -> Result<Model> {
        let file: ProblemFile = toml::from_str(text).map_err(|e| parse_error(text, path, &e))?;
        if refine == 0 {
            return Err(Error::Model(
                "the refinement factor must be at least 1".into(),
            ));
        }
        if let Some(name) = meshes
            .keys()
            .find(|m| !file.parts.iter().any(|p| p.name.get_ref() == *m))
        {
            return Err(Error::Model(format!(
                "a mesh is given for part '{name}', which the problem does not define"
            )));
        }
        Builder {
            text,
            path,
            meshes: std::cell::RefCell::new(meshes),
            values: check::Values::new(text, path),
        }
        .build(file, refine)
    }
}

struct Builder<'a> {
    text: &'a str,
    path: &'a Path,
    /// Meshes given in memory, by part name, taken by their parts.
    meshes: std::cell::RefCell<BTreeMap<String, Mesh>>,
    /// The text's values with their lines, for the checks.
    values: check::Values<'a>,
}

impl Builder<'_> {
    /// "file:line" for a spanned value.
    fn at<T>(&self, s: &Spanned<T>) -> String {
        let line = self.text[..s.span().start.min(self.text.len())]
            .matches('\n')
            .count()
            + 1;
        format!("{}:{line}", self.path.display())
    }

    fn err<T>(&self, s: &Spanned<T>, msg: impl std::fmt::Display) -> Error {
        Error::Parse {
            path: self.path.to_path_buf(),
            line: Some(line_of(self.text, s.span().start)),
            message: format!(
                "line {}: {msg}",
                self.at(s).rsplit(':').next().unwrap_or("?")
            ),
        }
    }

    fn part_index(&self, parts: &[Part], name: &Spanned<String>, key: &str) -> Result<usize> {
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

    fn boundary<'m>(
        &self,
        part: &'m Part,
        name: &Spanned<String>,
    ) -> Result<&'m Vec<crate::mesh::BoundaryEdge>> {
        part.mesh.boundaries.get(name.get_ref()).ok_or_else(|| {
            let known: Vec<&str> = part.mesh.boundaries.keys().map(|s| s.as_str()).collect();
            self.err(
                name,
                format!(
                    "part '{}' has no boundary named '{}' (it has: {})",
                    part.name,
                    name.get_ref(),
                    known.join(", ")
                ),
            )
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
        let path = self.path.parent().unwrap_or(Path::new("")).join(&g.file);
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        let mesh = match files.get(&key) {
            Some(m) => Rc::clone(m),
            None => {
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
                let m = Rc::new(GmshMesh::parse(&data, &path)?);
                files.insert(key, Rc::clone(&m));
                m
            }
        };
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

    fn build(&self, file: ProblemFile, refine: usize) -> Result<Model> {
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
        } = file;
        if part_specs.is_empty() {
            return Err(Error::Model("the problem defines no [[part]]".into()));
        }
        // Resources are checked before they are spent: the structured parts' sizes
        // (checked arithmetic) against the machine's memory, before any meshing.
        let mut nodes: u64 = 0;
        for spec in &part_specs {
            let n = self.structured_nodes(spec, refine)?;
            nodes = nodes.saturating_add(n);
        }
        // Meshes given in memory (arrays, a Python mesh) are subdivided as well.
        for mesh in self.meshes.borrow().values() {
            nodes = nodes.saturating_add(refined_nodes(mesh.nodes.len(), refine));
        }
        check_size(nodes, refine)?;
        let mut parts: Vec<Part> = Vec::with_capacity(part_specs.len());
        let mut gmsh_files = HashMap::new();
        for spec in &part_specs {
            let part = self.part(spec, &parts, &materials, plane, refine, &mut gmsh_files)?;
            parts.push(part);
        }
        // A refined Gmsh (or in-memory) part keeps its polygons: its curved
        // boundaries are not refined towards the curve (the built-in meshers
        // mesh theirs anew).
        let kept_polygons = if refine > 1 {
            part_specs
                .iter()
                .zip(&parts)
                .filter(|(spec, _)| spec.rectangle.is_none() && spec.annulus.is_none())
                .flat_map(|(_, p)| {
                    p.mesh
                        .curved_boundaries()
                        .into_iter()
                        .map(|b| (p.name.clone(), b))
                })
                .collect()
        } else {
            Vec::new()
        };
        let mut claimed: BTreeMap<(usize, usize), String> = BTreeMap::new();
        // An unnamed interface is named `host/nodes` (made unique).
        let iface_names = unique_defaults(
            iface_specs
                .iter()
                .map(|s| match &s.name {
                    Some(n) => (n.get_ref().clone(), true),
                    None => (format!("{}/{}", s.host.get_ref(), s.nodes.get_ref()), false),
                })
                .collect(),
        );
        let interfaces = iface_specs
            .iter()
            .zip(iface_names)
            .enumerate()
            .map(|(i, (spec, name))| self.interface(i, spec, name, &parts, &mut claimed))
            .collect::<Result<Vec<_>>>()?;
        let steps: Vec<Step> = step_specs
            .iter()
            .map(|s| Step {
                name: s.name.get_ref().clone(),
                increments: s.increments,
            })
            .collect();
        if !steps.is_empty() {
            analysis.increments = steps.iter().map(|s| s.increments).sum();
        }
        let step_of = |s: &Option<Spanned<String>>| -> usize {
            // Checked by `check::steps`: a named step exists.
            s.as_ref()
                .and_then(|s| steps.iter().position(|t| &t.name == s.get_ref()))
                .unwrap_or(0)
        };
        let mut supports = support_specs
            .iter()
            .map(|spec| {
                self.support(spec, &parts).map(|s| Support {
                    step: step_of(&spec.step),
                    ..s
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let mut loads_out = load_specs
            .iter()
            .map(|spec| {
                self.load(spec, &parts).map(|l| Load {
                    step: step_of(&spec.step),
                    ..l
                })
            })
            .collect::<Result<Vec<_>>>()?;
        // Given names replace the default ones, which are made unique (a second
        // support on one boundary gets ` (2)`).
        let named = |s: &Option<Spanned<String>>, default: &str| match s {
            Some(n) => (n.get_ref().clone(), true),
            None => (default.to_string(), false),
        };
        let names = unique_defaults(
            support_specs
                .iter()
                .zip(&supports)
                .map(|(spec, s)| named(&spec.name, &s.name))
                .collect(),
        );
        for (s, name) in supports.iter_mut().zip(names) {
            s.name = name;
        }
        let names = unique_defaults(
            load_specs
                .iter()
                .zip(&loads_out)
                .map(|(spec, l)| named(&spec.name, &l.name))
                .collect(),
        );
        for (l, name) in loads_out.iter_mut().zip(names) {
            l.name = name;
        }
        let title = title.unwrap_or_else(|| {
            self.path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "problem".into())
        });
        Ok(Model {
            title,
            source: self.path.to_path_buf(),
            units,
            parts,
            interfaces,
            supports,
            loads: loads_out,
            settings: analysis,
            steps,
            refine,
            text: self.text.to_string(),
            kept_polygons,
        })
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
        let mesh = self.part_mesh(spec, &name, refine, gmsh_files)?;
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
            (Some(r), _, _) => {
                if !(r.x[1] > r.x[0] && r.y[1] > r.y[0]) || r.cells[0] == 0 || r.cells[1] == 0 {
                    return Err(self.err(
                        &spec.name,
                        format!("part '{name}': rectangle needs x0 < x1, y0 < y1 and at least one cell each way (got x = {:?}, y = {:?}, cells = {:?})", r.x, r.y, r.cells),
                    ));
                }
                Mesh::rectangle_split(
                    r.x,
                    r.y,
                    [r.cells[0] * refine, r.cells[1] * refine],
                    r.elements,
                    r.diagonal,
                )
            }
            (None, Some(a), _) => {
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
                Mesh::annulus(
                    a.center,
                    a.r,
                    a.theta,
                    [a.cells[0] * refine, a.cells[1] * refine],
                    a.elements,
                )
            }
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

    /// An interface: its parts, its coupling nodes (each claimed by one interface
    /// only, recorded in `claimed`), its penalties and tolerance.
    fn interface(
        &self,
        index: usize,
        spec: &InterfaceSpec,
        name: String,
        parts: &[Part],
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
        self.boundary(&parts[node_part], &spec.boundary)?;
        let nodes = parts[node_part]
            .mesh
            .boundary_nodes(spec.boundary.get_ref())
            .unwrap_or_default();
        for &n in &nodes {
            if let Some(other) = claimed.insert((node_part, n), name.clone()) {
                return Err(self.err(
                    &spec.boundary,
                    format!(
                        "node {n} of part '{}' is claimed by interfaces '{other}' and '{name}'",
                        parts[node_part].name
                    ),
                ));
            }
        }
        // The tie's compliance 1/c acts in series with the softer part's local
        // compliance ~ 1/(E·t): its relative error is E·t/c of the softer part.
        // Scaling by the stiffer part would make c needlessly large (round-off)
        // when the materials differ by orders of magnitude.
        let default_c = DEFAULT_PENALTY_FACTOR
            * parts[host]
                .material
                .stiffness_scale()
                .min(parts[node_part].material.stiffness_scale());
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
        let (friction, search_distance, penetration_tolerance) =
            self.contact_keys(spec, &name, parts, host, node_part)?;
        // A penalty beyond 1/ε × E·t of the softer part hides that part's stiffness
        // in round-off: refused here with its name rather than as a failed pivot.
        let softer = if parts[host].material.stiffness_scale()
            <= parts[node_part].material.stiffness_scale()
        {
            host
        } else {
            node_part
        };
        let et = parts[softer].material.stiffness_scale();
        for (key, c) in [("c_n", c_n), ("c_s", c_s)] {
            let at = [
                check::Seg::K("interface"),
                check::Seg::I(index),
                check::Seg::K(key),
            ];
            self.values.penalty(&at, c, et, &parts[softer].name)?;
            // A penalty far below E·t holds nothing: refused by name rather than
            // met as a mechanism. The frictionless law ignores c_s.
            if !(key == "c_s" && frictionless) {
                self.values.weak_penalty(&at, c, et, &parts[softer].name)?;
            }
        }
        Ok(InterfaceDef {
            name,
            host,
            node_part,
            nodes,
            boundary: spec.boundary.get_ref().clone(),
            law: spec.law,
            c_n,
            c_s,
            tolerance,
            friction,
            search_distance,
            enforcement: spec.enforcement,
            penetration_tolerance,
            coupling: spec.coupling,
        })
    }

    /// The keys of the contact laws of interface `name`: `friction` (only with, and
    /// required by, `coulomb`), `search_distance` (a length ≥ 0; not on a rigid tie) and `penetration_tolerance` (augmented
    /// enforcement only; by default 1e-6 × the two parts' bounding diagonal).
    fn contact_keys(
        &self,
        spec: &InterfaceSpec,
        name: &str,
        parts: &[Part],
        host: usize,
        node_part: usize,
    ) -> Result<(f64, f64, f64)> {
        let friction = match (spec.law, spec.friction) {
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
        };
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

    /// A Dirichlet condition on a boundary or at a node.
    fn support(&self, spec: &SupportSpec, parts: &[Part]) -> Result<Support> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        let (name, nodes) = match (&spec.boundary, spec.at) {
            (Some(b), None) => {
                self.boundary(part, b)?;
                (
                    format!("{}/{}", part.name, b.get_ref()),
                    part.mesh.boundary_nodes(b.get_ref()).unwrap_or_default(),
                )
            }
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
        if spec.fix.is_empty() {
            return Err(self.err(
                &spec.part,
                format!("support '{name}': `fix` is empty; list the components to fix, \"x\" and/or \"y\""),
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
            ],
            value: spec.value,
            step: 0,
        })
    }

    /// A load resolved to nodal forces: a pressure over a boundary, or a resultant
    /// at a node, over a boundary or over a segment of the boundary.
    fn load(&self, spec: &LoadSpec, parts: &[Part]) -> Result<Load> {
        let p = self.part_index(parts, &spec.part, "part")?;
        let part = &parts[p];
        let edges_of = |edges: &[crate::mesh::BoundaryEdge]| -> Vec<([usize; 2], [[f64; 2]; 2])> {
            edges
                .iter()
                .map(|e| (e.nodes, e.nodes.map(|n| part.mesh.nodes[n])))
                .collect()
        };
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
            // A normal traction over a whole boundary.
            let b = match (&spec.boundary, spec.force, spec.from, spec.to, spec.at) {
                (Some(b), None, None, None, None) => b,
                _ => {
                    return Err(self.err(
                        &spec.part,
                        "a pressure [[load]] needs `boundary` and `pressure` only (no `force`, `at`, `from` or `to`)",
                    ));
                }
            };
            let edges = edges_of(self.boundary(part, b)?);
            let nodal = loads::pressure_forces(&edges, pressure);
            let mut resultant = [0.0; 2];
            for (_, f) in &nodal {
                resultant[0] += f[0];
                resultant[1] += f[1];
            }
            return Ok(Load {
                name: format!("{}/{} (pressure {pressure})", part.name, b.get_ref()),
                part: p,
                nodal,
                resultant,
                step: 0,
            });
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
            (Some(b), None, None, None) => {
                let edges = edges_of(self.boundary(part, b)?);
                Load {
                    name: format!("{}/{}", part.name, b.get_ref()),
                    part: p,
                    nodal: loads::chain_forces(&edges, force),
                    resultant: force,
                    step: 0,
                }
            }
            (b, Some(from), Some(to), None) => {
                let seg_len = crate::mesh::dist(from, to);
                if seg_len <= 0.0 || seg_len.is_nan() {
                    return Err(self.err(&spec.part, "load segment has `from` equal to `to`"));
                }
                let edges = match b {
                    Some(b) => edges_of(self.boundary(part, b)?),
                    None => edges_of(&part.mesh.boundary_edges()),
                };
                let tol = 1e-6 * part.mesh.max_edge_length();
                let (nodal, covered) = loads::segment_forces(&edges, from, to, force, tol);
                if (covered - seg_len).abs() > 1e-6 * seg_len {
                    return Err(self.err(
                        &spec.part,
                        format!(
                            "load segment ({}, {})–({}, {}) lies on the boundary of part '{}' over {covered:.6} of its length {seg_len:.6}: the whole segment must lie on the part's boundary",
                            from[0], from[1], to[0], to[1], part.name
                        ),
                    ));
                }
                Load {
                    name: format!(
                        "{}[({},{})-({},{})]",
                        part.name, from[0], from[1], to[0], to[1]
                    ),
                    part: p,
                    nodal,
                    resultant: force,
                    step: 0,
                }
            }
            _ => {
                return Err(self.err(
                    &spec.part,
                    "a [[load]] needs `at` (point load), `boundary` (whole boundary), or `from` and `to` (segment, optionally with `boundary`)",
                ));
            }
        })
    }
}

/// The 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

/// About the number of nodes a mesh of `nodes` nodes has once refined `refine`
/// times ([`Mesh::refined`]): `refine`² × `nodes` (an upper bound for a
/// triangulated mesh, whose edges are at most 3 and triangles at most 2 per
/// node), `u64::MAX` when that overflows, so [`check_size`] refuses it before
/// any memory is spent.
fn refined_nodes(nodes: usize, refine: usize) -> u64 {
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

/// An [`Error::Parse`] for a TOML error of `text`, with the line of its span.
/// The reader's "recursion limit" for a dotted key or table header of too many
/// parts has no span: it is told with the line of the deepest key.
fn parse_error(text: &str, path: &Path, e: &toml::de::Error) -> Error {
    let message = e.to_string().trim_end().to_string();
    let mut line = e.span().map(|s| line_of(text, s.start));
    let message = match (line, deepest_key(text)) {
        (None, Some((parts, l))) if message.contains("recursion limit") => {
            line = Some(l);
            format!(
                "line {l}: a key nested too deep ({message} of the TOML reader, about 80 levels): this key has {parts} dotted parts, its table header's included; no problem key has more than 3"
            )
        }
        _ => message,
    };
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// The deepest key of TOML text: its number of dotted parts (its table
/// header's included) and its 1-based line (the first key of 80 parts or more,
/// where the reader stops), for a message only (a rough
/// reading: quoted parts are respected, multi-line values are not).
fn deepest_key(text: &str) -> Option<(usize, usize)> {
    // Dots outside quotes, plus one.
    let parts = |key: &str| {
        let mut quote = None;
        let mut n = 1;
        for c in key.chars() {
            match (quote, c) {
                (None, '"' | '\'') => quote = Some(c),
                (Some(q), c) if c == q => quote = None,
                (None, '.') => n += 1,
                _ => {}
            }
        }
        n
    };
    let mut header = 0;
    let mut best: Option<(usize, usize)> = None;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        let depth = if let Some(h) = t.strip_prefix('[') {
            header = parts(h.trim_start_matches('[').split(']').next().unwrap_or(""));
            header
        } else if let Some((key, _)) = t.split_once('=')
            && !t.starts_with('#')
        {
            header + parts(key)
        } else {
            continue;
        };
        // The first line at the reader's limit (80), else the deepest.
        if best.is_none_or(|(d, _)| depth > d && d < 80) {
            best = Some((depth, i + 1));
        }
    }
    best
}

/// Refuses a model of `nodes` nodes (two unknowns each) whose estimated memory
/// ([`crate::results::memory::estimated_peak_bytes`]) exceeds what the machine has
/// available, before it is meshed.
fn check_size(nodes: u64, refine: usize) -> Result<()> {
    let unknowns = nodes.saturating_mul(2);
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

    /// The deepest key counts its table header's parts and dots outside quotes,
    /// and names the first line at the reader's limit of 80.
    #[test]
    fn deepest_key_counts_dotted_parts() {
        let text = "a = 1\n[t.u]\n\"x.y\".z = 2\n# c.d.e.f = 1\n";
        assert_eq!(deepest_key(text), Some((4, 3)));
        let deep = format!("[h]\nk{} = 1\nk{} = 1\n", ".a".repeat(85), ".a".repeat(90));
        assert_eq!(deepest_key(&deep), Some((87, 2)));
        assert_eq!(deepest_key(""), None);
    }
}
