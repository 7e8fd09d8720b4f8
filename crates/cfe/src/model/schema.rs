//! The problem file's schema: the serde types of its tables and keys (what a
//! problem file may say, with the lines of its names kept as spans), and the
//! messages of a file that does not parse. The values are checked by
//! [`super::check`]; the builder turns them into domain values.

use crate::coupling::{Coupling, Enforcement, Law};
use crate::domain::Settings;
use crate::error::{Error, Result};
use crate::fem::PlaneKind;
use crate::mesh::ElementKind;
use crate::mesh::gmsh::Group;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;

/// A whole problem file of a model whose points and vectors have `N`
/// components (2: a plane model, the default; 3: a solid model). The keys of
/// the other dimension (`plane`, `thickness`, `rectangle`, … in a solid model;
/// `box`, `volumes`, `traction` in a plane one) are refused before this is
/// read ([`super::dimension`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProblemFile<const N: usize = 2> {
    pub(super) title: Option<String>,
    #[serde(default)]
    pub(super) units: Units,
    #[serde(default = "default_plane")]
    pub(super) plane: PlaneKind,
    pub(super) materials: BTreeMap<String, MaterialSpec>,
    #[serde(rename = "part")]
    pub(super) parts: Vec<PartSpec>,
    #[serde(rename = "interface", default)]
    pub(super) interfaces: Vec<InterfaceSpec>,
    #[serde(rename = "support", default)]
    pub(super) supports: Vec<SupportSpec<N>>,
    #[serde(rename = "load", default)]
    pub(super) loads: Vec<LoadSpec<N>>,
    #[serde(default)]
    pub(super) analysis: Settings,
    #[serde(rename = "step", default)]
    pub(super) steps: Vec<StepSpec>,
    #[serde(rename = "line", default)]
    pub(super) lines: Vec<LineSpec>,
    #[serde(rename = "probe", default)]
    pub(super) probes: Vec<ProbeSpec<N>>,
    #[serde(default)]
    pub(super) output: OutputSpec,
}

/// `[[line]]`: a line probe, sampled for displacement and stresses.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LineSpec {
    pub(super) name: Spanned<String>,
    #[serde(deserialize_with = "pair")]
    pub(super) from: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) to: [f64; 2],
    /// Sample points, ends included (default 101).
    pub(super) points: Option<usize>,
    /// Only this part (default: every part).
    pub(super) part: Option<Spanned<String>>,
}

/// `[[probe]]`: a point whose displacement the history records (the part's
/// node nearest to `at`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProbeSpec<const N: usize> {
    pub(super) name: Spanned<String>,
    pub(super) part: Spanned<String>,
    #[serde(deserialize_with = "array")]
    pub(super) at: [f64; N],
}

/// `[output]`: what the run draws besides its fixed pictures.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OutputSpec {
    /// `history.png`'s axes: two columns of `history.csv`.
    pub(super) history_plot: Option<PlotSpec>,
    /// A solid model's `deformed.png` viewpoint: `iso` (the default), or
    /// from an axis, `x`, `-x`, `y`, `-y`, `z`, `-z` ([`super::ViewPoint`]).
    pub(super) view: Option<String>,
    /// A solid model's `deformed.png` colouring: `von_mises` (the default), a
    /// stress component `sxx` … `sxz`, or a displacement `ux`, `uy`, `uz`,
    /// `u` ([`super::PictureField`]).
    pub(super) component: Option<String>,
}

/// `history_plot = { x = "probe:tip.uy", y = "reaction:base.fy" }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlotSpec {
    pub(super) x: String,
    pub(super) y: String,
}

/// `[[step]]`: a load step.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StepSpec {
    pub(super) name: Spanned<String>,
    pub(super) increments: usize,
    /// The factor every load and prescribed value of the earlier steps reaches
    /// at the end of this step (default: held).
    pub(super) scale: Option<f64>,
    /// Loads and supports by name, each with its own factor at the end of this
    /// step.
    #[serde(default)]
    pub(super) factors: BTreeMap<String, f64>,
}

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
pub(super) struct MaterialSpec {
    #[serde(rename = "E")]
    pub(super) young: f64,
    pub(super) nu: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PartSpec {
    pub(super) name: Spanned<String>,
    pub(super) material: Spanned<String>,
    #[serde(default = "one")]
    pub(super) thickness: f64,
    pub(super) rectangle: Option<RectangleSpec>,
    pub(super) annulus: Option<AnnulusSpec>,
    pub(super) gmsh: Option<Spanned<GmshSpec>>,
    /// A solid part's structured box mesh.
    #[serde(rename = "box")]
    pub(super) block: Option<BoxSpec>,
}

/// `box = { x = [x0, x1], y = [y0, y1], z = [z0, z1], cells = [nx, ny, nz],
/// elements = "hex8" }`: a structured box of a solid part
/// ([`Mesh::<D3>::block`](crate::mesh::Mesh::block)), its sides named `left`,
/// `right`, `front`, `back`, `bottom` and `top`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoxSpec {
    #[serde(deserialize_with = "pair")]
    pub(super) x: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) y: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) z: [f64; 2],
    #[serde(deserialize_with = "array")]
    pub(super) cells: [usize; 3],
    /// `hex8` (one hexahedron per cell, the default) or `tet4` (six tetrahedra
    /// per cell); `element` is read as well.
    #[serde(default = "default_solid", alias = "element")]
    pub(super) elements: crate::mesh::SolidKind,
}

fn default_solid() -> crate::mesh::SolidKind {
    crate::mesh::SolidKind::Hex8
}

fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RectangleSpec {
    #[serde(deserialize_with = "pair")]
    pub(super) x: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) y: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) cells: [usize; 2],
    /// `t3` (each cell split into two triangles, the default) or `q4`.
    #[serde(default = "default_elements")]
    pub(super) elements: ElementKind,
    /// T3 only: `rising` (`/`, the default) or `falling` (`\`) cell diagonals.
    #[serde(default)]
    pub(super) diagonal: crate::mesh::Diagonal,
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

/// An `N`-entry array (a point or a vector of a model of `N` dimensions, a
/// box's three cell counts) with exactly `N` entries, as [`pair`].
fn array<'de, D, T, const N: usize>(d: D) -> std::result::Result<[T; N], D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let v: Vec<T> = Vec::deserialize(d)?;
    let n = v.len();
    <[T; N]>::try_from(v).map_err(|_| {
        serde::de::Error::custom(format!("expected an array of exactly {N} values, got {n}"))
    })
}

/// [`array`] for an optional key.
fn opt_array<'de, D, T, const N: usize>(d: D) -> std::result::Result<Option<[T; N]>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let Some(v) = Option::<Vec<T>>::deserialize(d)? else {
        return Ok(None);
    };
    let n = v.len();
    <[T; N]>::try_from(v).map(Some).map_err(|_| {
        serde::de::Error::custom(format!("expected an array of exactly {N} values, got {n}"))
    })
}

/// `N` zeros: the default prescribed values of a support.
fn zeros<const N: usize>() -> [f64; N] {
    [0.0; N]
}

fn default_elements() -> ElementKind {
    ElementKind::T3
}

/// `annulus = { center, r = [r0, r1], theta = [θ0, θ1], cells = [nr, nt] }`: a
/// structured annular sector (angles in degrees).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AnnulusSpec {
    #[serde(default, deserialize_with = "pair")]
    pub(super) center: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) r: [f64; 2],
    #[serde(default = "full_turn", deserialize_with = "pair")]
    pub(super) theta: [f64; 2],
    #[serde(deserialize_with = "pair")]
    pub(super) cells: [usize; 2],
    #[serde(default = "default_elements")]
    pub(super) elements: ElementKind,
}

fn full_turn() -> [f64; 2] {
    [0.0, 360.0]
}

/// `gmsh = { file = "plate.msh", surfaces = ["plate"] }`: a part meshed in Gmsh.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GmshSpec {
    /// The .msh file, relative to the problem file's folder.
    pub(super) file: String,
    /// Physical surfaces (names or numbers) whose elements make the part; default all.
    pub(super) surfaces: Option<Vec<GroupSpec>>,
    /// A solid part's physical volumes (names or numbers); default all.
    pub(super) volumes: Option<Vec<GroupSpec>>,
}

/// A physical group given by name (string) or number (integer).
#[derive(Debug, Clone)]
pub(super) struct GroupSpec(pub(super) Group);

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
pub(super) struct InterfaceSpec {
    pub(super) name: Option<Spanned<String>>,
    pub(super) host: Spanned<String>,
    pub(super) nodes: Spanned<String>,
    /// Required but with `form = "volume"` (then every node of the node part).
    pub(super) boundary: Option<Spanned<String>>,
    #[serde(default = "default_law")]
    pub(super) law: Law,
    pub(super) c_n: Option<f64>,
    pub(super) c_s: Option<f64>,
    pub(super) tolerance: Option<f64>,
    pub(super) friction: Option<f64>,
    pub(super) search_distance: Option<f64>,
    #[serde(default)]
    pub(super) enforcement: Enforcement,
    pub(super) penetration_tolerance: Option<f64>,
    #[serde(default)]
    pub(super) coupling: Coupling,
    #[serde(default)]
    pub(super) form: crate::domain::CouplingForm,
}

fn default_law() -> Law {
    Law::Contact
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum Component {
    X,
    Y,
    /// A solid model's third component (refused in a plane model).
    Z,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SupportSpec<const N: usize> {
    /// Default: `part/boundary` or `part@(x, y)`.
    pub(super) name: Option<Spanned<String>>,
    pub(super) part: Spanned<String>,
    pub(super) boundary: Option<Spanned<String>>,
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) at: Option<[f64; N]>,
    /// A solid model's selection box (opposite corners `from`, `to`): the
    /// nodes of `boundary` (of the part's whole boundary without one) inside
    /// it.
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) from: Option<[f64; N]>,
    /// See `from`.
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) to: Option<[f64; N]>,
    pub(super) fix: Vec<Component>,
    #[serde(default = "zeros", deserialize_with = "array")]
    pub(super) value: [f64; N],
    pub(super) step: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LoadSpec<const N: usize> {
    /// Default: from the part and where the load acts (see [`Builder::load`]).
    pub(super) name: Option<Spanned<String>>,
    pub(super) part: Spanned<String>,
    pub(super) boundary: Option<Spanned<String>>,
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) from: Option<[f64; N]>,
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) to: Option<[f64; N]>,
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) at: Option<[f64; N]>,
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) force: Option<[f64; N]>,
    pub(super) pressure: Option<f64>,
    /// A solid model's uniform traction (force per area) on a boundary.
    #[serde(default, deserialize_with = "opt_array")]
    pub(super) traction: Option<[f64; N]>,
    pub(super) step: Option<Spanned<String>>,
}

/// Parses problem text into its schema; a TOML error or a key the schema does
/// not know is an [`Error::Parse`] with its line ([`parse_error`]).
pub(super) fn parse<const N: usize>(text: &str, path: &Path) -> Result<ProblemFile<N>> {
    toml::from_str(text).map_err(|e| parse_error(text, path, &e))
}

/// The 1-based line of byte offset `at` in `text`.
pub(super) fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

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

#[cfg(test)]
mod tests {
    use super::*;

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
