//! Model: reads a problem file (TOML), checks it, meshes its parts and resolves every
//! selection (supports, loads, interface boundaries) into nodes and nodal values.
//! Errors name the file, the line and the key at fault.
//!
//! Rooms: `schema` (private: the serde types of the problem file and
//! the messages of a file that does not parse), `check` (every value checked where
//! it is read, with its line and key), `build` (the builder: schema → domain
//! parts, interfaces, supports and loads, meshing each part), `solid` (the
//! builder's solid parts, supports and loads: `Model<D3>`) and `dimension`
//! (plane or solid, [`problem_dimension`], and the keys of the other dimension
//! refused); this module is the [`Model`] API on top of them.
//!
//! The problem-file reference is in README.md; `examples/` holds complete files.

use crate::dim::{D2, D3};
pub use crate::domain::{InterfaceDef, Load, Part, Probe, Scheme, Settings, Step, Support};
use crate::error::{Error, Result};
use crate::fem::PlaneKind;
use crate::mesh::input_file::{self, MESH_FILE_CAP, PROBLEM_FILE_CAP};
use crate::mesh::{Mesh, MeshDim};
pub use schema::Units;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

mod build;
mod check;
mod dimension;
mod inp;
mod schema;
mod solid;

pub use dimension::{ProblemDimension, problem_dimension, problem_text_dimension};

/// What reading a problem file needs of its dimension beyond the mesh: the
/// stiffness scale of a part an interface's default penalty is a multiple of
/// ([`DEFAULT_PENALTY_FACTOR`]) and its penalties are checked against.
trait ProblemDim: MeshDim {
    /// The stiffness scales (host, node part) of the interface of the node
    /// part's boundary `boundary` on `host`.
    fn stiffness_scales(host: &Part<Self>, nodes: &Part<Self>, boundary: &str) -> [f64; 2];
}

/// A plane part's E·t (a force per length, the stiffness of a unit square).
impl ProblemDim for D2 {
    fn stiffness_scales(host: &Part, nodes: &Part, _: &str) -> [f64; 2] {
        [
            host.material.stiffness_scale(),
            nodes.material.stiffness_scale(),
        ]
    }
}

/// A solid part's E·h, h the mean edge length of the interface's faces on
/// the node part (the stiffness of a node of a cube of side h, a force per
/// length as E·t is in 2D): the default penalty is 1e5 × E·h of the softer
/// part, so it follows the mesh under `--refine`.
impl ProblemDim for D3 {
    fn stiffness_scales(host: &Part<D3>, nodes: &Part<D3>, boundary: &str) -> [f64; 2] {
        let h = solid::mean_face_edge(&nodes.mesh, boundary);
        [host.material.young * h, nodes.material.young * h]
    }
}

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

/// The name of the one step of a problem without `[[step]]` tables.
pub const DEFAULT_STEP: &str = "step-1";

/// A checked, meshed model ready for analysis, of dimension `D` (plane by
/// default; a solid model is a `Model<D3>`, read from a problem file of `box`
/// or 3D Gmsh parts by [`Model::<D3>::from_file`](Model::from_file), or built
/// in code with [`Model::from_parts`]).
#[derive(Debug, Clone)]
pub struct Model<D: MeshDim = D2> {
    /// Title (default: the file stem).
    pub title: String,
    /// The problem file it came from.
    pub source: PathBuf,
    /// Unit labels.
    pub units: Units,
    /// Parts in file order.
    pub parts: Vec<Part<D>>,
    /// Interfaces in file order.
    pub interfaces: Vec<InterfaceDef>,
    /// Dirichlet conditions.
    pub supports: Vec<Support>,
    /// External loads.
    pub loads: Vec<Load<D>>,
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
    /// What reading the input noted that a user should know: for a CalculiX/
    /// Abaqus deck, the keywords accepted and ignored (with their lines) and
    /// how its contact behaviour was mapped ([`Model::from_inp`]).
    pub notes: Vec<String>,
    /// The line probes of `[[line]]` tables, located in the parts (plane
    /// models; empty in a solid one).
    pub lines: Vec<crate::results::lines::LineProbe>,
    /// Probe points (`[[probe]]`): nodes whose displacement the history records.
    pub probes: Vec<Probe<D>>,
    /// `history.png`'s axes as two history columns (x, y) (`[output]
    /// history_plot`); `None`: the default (see README, Outputs).
    pub history_plot: Option<[String; 2]>,
    /// What a solid model's `deformed.png` shows (`[output] view` and
    /// `component`); the default (isometric, von Mises) in a plane model.
    pub picture: Picture,
}

/// What a solid model's `deformed.png` shows: where from and coloured by what
/// (`[output] view` and `component`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Picture {
    /// The viewpoint.
    pub view: ViewPoint,
    /// The colouring.
    pub field: PictureField,
}

/// Where `deformed.png` is seen from, z up (`[output] view`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ViewPoint {
    /// `iso`: isometric, the eye along (1, −1, 1) (the default).
    #[default]
    Isometric,
    /// From the positive (`true`) or negative side of axis 0 (x), 1 (y) or 2
    /// (z), looking back along it: `x`, `-x`, `y`, `-y`, `z`, `-z`.
    Axis(usize, bool),
}

/// The nodal value `deformed.png` is coloured by (`[output] component`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PictureField {
    /// `von_mises`: the von Mises stress (the default).
    #[default]
    VonMises,
    /// A stress component in Voigt order (xx, yy, zz, xy, yz, xz): `sxx`,
    /// `syy`, `szz`, `sxy`, `syz`, `sxz`.
    Stress(usize),
    /// A displacement component 0 (x), 1 (y), 2 (z): `ux`, `uy`, `uz`.
    Displacement(usize),
    /// `u`: the displacement's magnitude.
    DisplacementMagnitude,
}

impl ViewPoint {
    /// The names `[output] view` takes, in order.
    pub const NAMES: [&'static str; 7] = ["iso", "x", "-x", "y", "-y", "z", "-z"];

    /// The viewpoint named `name` ([`ViewPoint::NAMES`]).
    pub fn from_name(name: &str) -> Option<ViewPoint> {
        Some(match name {
            "iso" => ViewPoint::Isometric,
            "x" => ViewPoint::Axis(0, true),
            "-x" => ViewPoint::Axis(0, false),
            "y" => ViewPoint::Axis(1, true),
            "-y" => ViewPoint::Axis(1, false),
            "z" => ViewPoint::Axis(2, true),
            "-z" => ViewPoint::Axis(2, false),
            _ => return None,
        })
    }
}

impl PictureField {
    /// The names `[output] component` takes, in order.
    pub const NAMES: [&'static str; 11] = [
        "von_mises",
        "sxx",
        "syy",
        "szz",
        "sxy",
        "syz",
        "sxz",
        "ux",
        "uy",
        "uz",
        "u",
    ];

    /// The field named `name` ([`PictureField::NAMES`]).
    pub fn from_name(name: &str) -> Option<PictureField> {
        let k = Self::NAMES.iter().position(|n| *n == name)?;
        Some(match k {
            0 => PictureField::VonMises,
            1..=6 => PictureField::Stress(k - 1),
            7..=9 => PictureField::Displacement(k - 7),
            _ => PictureField::DisplacementMagnitude,
        })
    }
}

/// Whether `path` names a CalculiX/Abaqus deck (extension `.inp`, any case).
fn is_deck(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("inp"))
}

/// The UTF-8 text of the input file at `path` (`what` names it in messages), of
/// at most `cap` bytes, from a regular file only ([`input_file::read`]).
fn read_text(path: &Path, cap: u64, what: &str) -> Result<String> {
    let read_error = |source| Error::ReadInput {
        path: path.to_path_buf(),
        source,
    };
    let data = input_file::read(path, what, cap, read_error)?;
    String::from_utf8(data)
        .map_err(|e| read_error(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// A problem given as text (TOML), read as if from a file `problem.toml` in the
/// current folder, at refinement 1.
impl std::str::FromStr for Model {
    type Err = Error;

    fn from_str(text: &str) -> Result<Model> {
        Model::from_str(text, Path::new("problem.toml"), 1)
    }
}

impl<D: MeshDim> Model<D> {
    /// The index of the part named `name`.
    pub fn part_index(&self, name: &str) -> Option<usize> {
        self.parts.iter().position(|p| p.name == name)
    }

    /// A model built in code from its parts: no problem file behind it (so no
    /// coarser level for the warm start: [`Model::with_refine`] fails). Names
    /// given twice within a kind are refused ([`Model::check_names`]). Plane
    /// or solid (`Part<D3>`, `Load<D3>`): the dimension is the parts'.
    #[allow(clippy::too_many_arguments)]
    pub fn from_parts(
        title: impl Into<String>,
        parts: Vec<Part<D>>,
        interfaces: Vec<InterfaceDef>,
        supports: Vec<Support>,
        loads: Vec<Load<D>>,
        settings: Settings,
    ) -> Result<Model<D>> {
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
            notes: Vec::new(),
            lines: Vec::new(),
            probes: Vec::new(),
            history_plot: None,
            picture: Picture::default(),
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
        let kinds: [(&str, Vec<&str>); 6] = [
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
            (
                "probe",
                self.probes.iter().map(|p| p.name.as_str()).collect(),
            ),
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

    /// The load steps: those of the `[[step]]` tables, or without them one step
    /// named [`DEFAULT_STEP`] of `settings.increments`.
    pub fn steps(&self) -> Vec<Step> {
        if self.steps.is_empty() {
            vec![Step::new(DEFAULT_STEP, self.settings.increments)]
        } else {
            self.steps.clone()
        }
    }

    /// The steps in which some load or prescribed value is applied (sorted).
    pub fn loaded_steps(&self) -> Vec<usize> {
        let mut s: Vec<usize> = self
            .loads
            .iter()
            .filter(|l| (l.nodal.iter()).any(|(_, f)| f.as_ref().iter().any(|&c| c != 0.0)))
            .map(|l| l.step)
            .chain(
                self.supports
                    .iter()
                    .filter(|s| (0..D::N).any(|c| s.fix[c] && s.value[c] != 0.0))
                    .map(|s| s.step),
            )
            .collect();
        s.sort_unstable();
        s.dedup();
        s
    }
}

impl Model {
    /// Reads, checks and meshes the problem file at `path`; `refine` multiplies every
    /// structured part's cell counts and splits every edge of a Gmsh part into that
    /// many (1 = as written). A file named `*.inp` is read as a CalculiX/Abaqus
    /// deck ([`Model::from_inp`]; its mesh as written, `refine` must be 1).
    pub fn from_file(path: &Path, refine: usize) -> Result<Model> {
        if is_deck(path) {
            let text = read_text(path, MESH_FILE_CAP, "CalculiX/Abaqus deck")?;
            return inp::model(&text, path, refine);
        }
        let text = read_text(path, PROBLEM_FILE_CAP, "problem file")?;
        Model::from_str(&text, path, refine)
    }

    /// Reads a CalculiX/Abaqus input deck: the common subset (nodes, CPS3/CPE3/
    /// CPS4/CPE4 elements, sets, surfaces, elastic materials, solid sections,
    /// boundary conditions, concentrated and pressure loads, static steps, ties
    /// and contact pairs) mapped onto cfe's parts, interfaces, supports, loads
    /// and steps as README.md, "Running a CalculiX/Abaqus deck", states; anything
    /// outside it is an [`Error::Deck`] naming the line and the keyword.
    pub fn from_inp(path: &Path) -> Result<Model> {
        let text = read_text(path, MESH_FILE_CAP, "CalculiX/Abaqus deck")?;
        inp::model(&text, path, 1)
    }

    /// [`Model::from_inp`] of deck text; `path` is used in messages and to find
    /// its `*INCLUDE`d files (relative to its folder).
    pub fn from_inp_str(text: &str, path: &Path) -> Result<Model> {
        inp::model(text, path, 1)
    }

    /// The same problem with the meshes refined `refine` times instead.
    pub fn with_refine(&self, refine: usize) -> Result<Model> {
        if is_deck(&self.source) {
            return inp::model(&self.text, &self.source, refine);
        }
        Model::from_str(&self.text, &self.source, refine)
    }

    /// Advice about the model that does not stop it from being solved: parts in
    /// plane strain (or axisymmetric: as constrained out of plane) with ν ≥ [`LOCKING_NU`], whose displacement elements lock
    /// (volumetric locking: too stiff, with oscillating pressure), T3 most.
    pub fn warnings(&self) -> Vec<String> {
        self.parts
            .iter()
            .filter(|p| {
                matches!(p.material.plane, PlaneKind::Strain | PlaneKind::Axisymmetric)
                    && p.material.poisson >= LOCKING_NU
            })
            .map(|p| {
                let (t3, _) = p.mesh.counts();
                let nu = p.material.poisson;
                let ratio = 1.0 / (1.0 - 2.0 * nu);
                let advice = if t3 > 0 {
                    "its T3 elements lock (they cannot deform at constant volume, so displacements come out too small and stresses oscillate); use Q4 elements (`elements = \"q4\"`, which lock far less), plane = \"stress\" if the part is thin, or check the results against a finer mesh"
                } else {
                    "its Q4 elements (full integration) stiffen (volumetric locking: displacements come out too small); check the results against a finer mesh, or use plane = \"stress\" if the part is thin"
                };
                let plane = if p.material.is_axisymmetric() {
                    "an axisymmetric model"
                } else {
                    "plane strain"
                };
                format!(
                    "part '{}': ν = {nu} in {plane} is nearly incompressible (bulk modulus {ratio:.1e} × the shear modulus): {advice}",
                    p.name
                )
            })
            .collect()
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
        dimension::refuse_other_keys(text, path, false)?;
        let file = schema::parse(text, path)?;
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
        build::Builder::new(text, path, meshes).build(file, refine)
    }
}

/// A model read from a problem file, of either dimension: `Model::<D3>::from_file`
/// reads a solid problem as `Model::from_file` reads a plane one (the plane
/// model's inherent methods are these; the trait lets a solid model, and code
/// generic over the dimension, name them the same). Bring it into scope with
/// `use cfe::model::FromProblemFile`.
pub trait FromProblemFile: Sized {
    /// Reads, checks and meshes the problem file at `path`; `refine` multiplies
    /// the structured meshes' cell counts and splits every edge of a Gmsh mesh
    /// into that many.
    fn from_file(path: &Path, refine: usize) -> Result<Self>;
}

/// A model read from problem text, of either dimension (see
/// [`FromProblemFile`]; `use cfe::model::FromProblemText`).
pub trait FromProblemText: Sized {
    /// Reads, checks and meshes a problem given as text; `path` is used in
    /// messages, for the default title and to find the mesh files.
    fn from_str(text: &str, path: &Path, refine: usize) -> Result<Self>;

    /// The same problem with the meshes refined `refine` times instead.
    fn with_refine(&self, refine: usize) -> Result<Self>;
}

/// [`Model::from_file`].
impl FromProblemFile for Model {
    fn from_file(path: &Path, refine: usize) -> Result<Model> {
        Model::from_file(path, refine)
    }
}

/// [`Model::from_str`] and [`Model::with_refine`].
impl FromProblemText for Model {
    fn from_str(text: &str, path: &Path, refine: usize) -> Result<Model> {
        Model::from_str(text, path, refine)
    }

    fn with_refine(&self, refine: usize) -> Result<Model> {
        Model::with_refine(self, refine)
    }
}

/// A solid problem file: parts of `box` or of 3D Gmsh meshes
/// ([`problem_dimension`] tells a file's dimension). `refine` multiplies
/// every box's cell counts and splits every edge of a Gmsh part into that
/// many ([`Mesh::<D3>::refined`](Mesh::refined)). A deck (`.inp`) is plane:
/// refused.
impl FromProblemFile for Model<D3> {
    fn from_file(path: &Path, refine: usize) -> Result<Model<D3>> {
        if is_deck(path) {
            return Err(Error::Model(format!(
                "{} is a CalculiX/Abaqus deck, which cfe reads as a plane model (CPS/CPE elements): read it with Model::from_file (plane)",
                path.display()
            )));
        }
        let text = read_text(path, PROBLEM_FILE_CAP, "problem file")?;
        <Model<D3> as FromProblemText>::from_str(&text, path, refine)
    }
}

/// Solid problem text. The keys of a plane model (`plane`, `thickness`,
/// `rectangle`, `annulus`, `[[line]]`, a Gmsh part's `surfaces`) and
/// `coupling = "segment"` are refused with [`Error::Dimension`] naming the
/// key and its line; points and vectors (`at`, `from`, `to`, `force`,
/// `traction`, `value`) have three components.
impl FromProblemText for Model<D3> {
    fn from_str(text: &str, path: &Path, refine: usize) -> Result<Model<D3>> {
        Model::<D3>::from_str_with_solid_meshes(text, path, refine, BTreeMap::new())
    }

    fn with_refine(&self, refine: usize) -> Result<Model<D3>> {
        <Model<D3> as FromProblemText>::from_str(&self.text, &self.source, refine)
    }
}

impl Model<D3> {
    /// As [`FromProblemText::from_str`] of a solid problem, with the meshes of
    /// some parts given (by part name) instead of by a `box` or `gmsh` key in
    /// the text (e.g. a mesh built from arrays by the Python package): such a
    /// part has neither key; its boundaries are the mesh's. Each given mesh
    /// must belong to a part of the text, and is checked
    /// ([`Mesh::<D3>::validate`](Mesh::validate)). `refine` subdivides the
    /// given meshes as it does Gmsh meshes ([`Mesh::<D3>::refined`](Mesh::refined)).
    pub fn from_str_with_solid_meshes(
        text: &str,
        path: &Path,
        refine: usize,
        meshes: BTreeMap<String, Mesh<D3>>,
    ) -> Result<Model<D3>> {
        dimension::refuse_other_keys(text, path, true)?;
        let file = schema::parse::<3>(text, path)?;
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
        let mut builder =
            build::Builder::new(text, path, BTreeMap::new()).with_solid_meshes(meshes);
        builder.values.solid = true;
        builder.build_solid(file, refine)
    }

    /// Advice about the model that does not stop it from being solved: parts
    /// with ν ≥ [`LOCKING_NU`], whose TET4 and fully integrated HEX8 elements
    /// lock (too stiff at nearly constant volume).
    pub fn warnings(&self) -> Vec<String> {
        (self.parts.iter())
            .filter(|p| p.material.poisson >= LOCKING_NU)
            .map(|p| {
                let nu = p.material.poisson;
                format!(
                    "part '{}': ν = {nu} is nearly incompressible (bulk modulus {:.1e} × the shear modulus): its TET4 and HEX8 elements (full integration) lock (displacements come out too small, stresses oscillate); check the results against a finer mesh",
                    p.name,
                    1.0 / (1.0 - 2.0 * nu)
                )
            })
            .collect()
    }
}
