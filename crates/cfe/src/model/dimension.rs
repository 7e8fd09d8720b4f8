//! The dimension of a problem file: plane or solid, decided from its parts
//! ([`problem_dimension`]), and the keys of the other dimension refused with
//! their line before the file is read as one or the other
//! ([`refuse_other_keys`]). The schema is one for both: the 2D keys carry over
//! to 3D (`fix`, `force`, `pressure`, `gmsh`, …) with a third component, and
//! only the mesh keys and a few idealisations belong to one dimension.

use super::schema::line_of;
use crate::error::{Error, Result};
use crate::mesh::gmsh::{GmshFile, peek_dimension};
use crate::mesh::input_file::{self, MESH_FILE_CAP};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// The dimension of a problem ([`problem_dimension`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProblemDimension {
    /// A plane model (`Model<D2>`): `rectangle`, `annulus` or 2D Gmsh parts,
    /// or a CalculiX/Abaqus deck.
    Plane,
    /// A solid model (`Model<D3>`): `box` parts or Gmsh parts of volume
    /// elements.
    Solid,
}

/// The dimension of the problem file at `path`, from its parts: a part with
/// `box`, or with a Gmsh mesh holding volume elements, is solid; one with
/// `rectangle`, `annulus` or a plane Gmsh mesh is plane. Plane and solid parts
/// together are an [`Error::Dimension`] naming both kinds of part. A deck
/// (`.inp`) is plane; a file that does not parse as TOML, or whose parts say
/// nothing (a Gmsh file that cannot be read), is plane, so the plane reader
/// reports what is wrong as it always has.
pub fn problem_dimension(path: &Path) -> Result<ProblemDimension> {
    if super::is_deck(path) {
        return Ok(ProblemDimension::Plane);
    }
    let text = super::read_text(path, input_file::PROBLEM_FILE_CAP, "problem file")?;
    problem_text_dimension(&text, path)
}

/// [`problem_dimension`] of problem text read from `path` (the folder of its
/// Gmsh files, and messages): plane or solid from its parts, as a file's.
pub fn problem_text_dimension(text: &str, path: &Path) -> Result<ProblemDimension> {
    let Ok(root) = DeTable::parse(text) else {
        return Ok(ProblemDimension::Plane);
    };
    let root = root.get_ref();
    let Some(DeValue::Array(parts)) = root.get("part").map(|p| p.get_ref()) else {
        return Ok(ProblemDimension::Plane);
    };
    let mut files: HashMap<PathBuf, Option<ProblemDimension>> = HashMap::new();
    let mut plane: Vec<(String, usize)> = Vec::new();
    let mut solid: Vec<(String, usize)> = Vec::new();
    for (i, part) in parts.iter().enumerate() {
        let DeValue::Table(t) = part.get_ref() else {
            continue;
        };
        let name = item_name(t).unwrap_or_else(|| format!("#{}", i + 1));
        let line = line_of(text, part.span().start);
        let kind = if t.get("box").is_some() {
            Some(ProblemDimension::Solid)
        } else if t.get("rectangle").is_some() || t.get("annulus").is_some() {
            Some(ProblemDimension::Plane)
        } else if let Some(DeValue::Table(g)) = t.get("gmsh").map(|g| g.get_ref())
            && let Some(DeValue::String(file)) = g.get("file").map(|f| f.get_ref())
        {
            let file = path.parent().unwrap_or(Path::new("")).join(file.as_ref());
            *files
                .entry(file.clone())
                .or_insert_with(|| gmsh_dimension(&file))
        } else {
            None
        };
        match kind {
            Some(ProblemDimension::Plane) => plane.push((name, line)),
            Some(ProblemDimension::Solid) => solid.push((name, line)),
            None => {}
        }
    }
    if !plane.is_empty() && !solid.is_empty() {
        let list = |v: &[(String, usize)]| {
            v.iter()
                .map(|(n, l)| format!("'{n}' (line {l})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        // The part of the minority kind (the later one on a tie) is at fault.
        let at = if solid.len() <= plane.len() {
            &solid[0]
        } else {
            &plane[0]
        };
        return Err(Error::Dimension {
            path: path.to_path_buf(),
            line: Some(at.1),
            key: format!("part.{}", at.0),
            message: format!(
                "mixes plane and solid parts: plane parts {} (`rectangle`, `annulus` or a 2D Gmsh mesh) and solid parts {} (`box` or a Gmsh mesh of volume elements); a model is plane or solid: mesh every part in the same dimension",
                list(&plane),
                list(&solid)
            ),
        });
    }
    Ok(if solid.is_empty() {
        ProblemDimension::Plane
    } else {
        ProblemDimension::Solid
    })
}

/// The dimension of the Gmsh file at `path` (`None` when it cannot be read or
/// parsed: the reader of the model reports why). An ASCII file's is peeked
/// from its element types ([`peek_dimension`]: its nodes are not read, so
/// the model's reader parses the file once); a binary file, or one the peek
/// does not follow, is parsed.
fn gmsh_dimension(path: &Path) -> Option<ProblemDimension> {
    let data = input_file::read(path, "Gmsh file", MESH_FILE_CAP, |e| Error::ReadInput {
        path: path.to_path_buf(),
        source: e,
    })
    .ok()?;
    let dimension = match peek_dimension(&data) {
        Some(d) => d,
        None => GmshFile::parse(&data, path).ok()?.dimension(),
    };
    Some(match dimension {
        3 => ProblemDimension::Solid,
        _ => ProblemDimension::Plane,
    })
}

/// The `name` string of an array-of-tables item, if it has one.
fn item_name(t: &DeTable) -> Option<String> {
    match t.get("name").map(|n| n.get_ref()) {
        Some(DeValue::String(s)) => Some(s.to_string()),
        _ => None,
    }
}

/// Refuses, with an [`Error::Dimension`] naming the key and its line, the keys
/// that belong to the other dimension: in a solid model (`solid`) `plane`,
/// `[[line]]`, a part's `thickness`, `rectangle` and `annulus`, a Gmsh part's
/// `surfaces` (its physical volumes are `volumes`) and `coupling = "segment"`;
/// in a plane model a part's `box`, a Gmsh part's `volumes`, a load's
/// `traction` and `[output] view` and `component`. Text that does not parse is left to the schema's reader.
pub(super) fn refuse_other_keys(text: &str, path: &Path, solid: bool) -> Result<()> {
    let Ok(root) = DeTable::parse(text) else {
        return Ok(());
    };
    let root = root.get_ref();
    let refuse = |key: String, span: std::ops::Range<usize>, message: &str| Error::Dimension {
        path: path.to_path_buf(),
        line: Some(line_of(text, span.start)),
        key,
        message: message.to_string(),
    };
    let items = |table: &str| -> Vec<(String, &DeTable)> {
        match root.get(table).map(|v| v.get_ref()) {
            Some(DeValue::Array(a)) => (a.iter().enumerate())
                .filter_map(|(i, v)| match v.get_ref() {
                    DeValue::Table(t) => Some((
                        format!(
                            "{table}.{}",
                            item_name(t).unwrap_or_else(|| format!("#{}", i + 1))
                        ),
                        t,
                    )),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        }
    };
    if solid {
        if let Some(v) = root.get("plane") {
            return Err(refuse(
                "plane".into(),
                v.span(),
                "is a plane model's idealisation (stress, strain, axisymmetric): a solid model (`box` or 3D Gmsh parts) is three-dimensional; remove it",
            ));
        }
        if let Some(v) = root.get("line") {
            return Err(refuse(
                "line".into(),
                v.span(),
                "([[line]] probes) samples a plane model along a segment and is not available for a solid model yet; remove it (a [[probe]] records a point's displacement)",
            ));
        }
        for (key, t) in items("part") {
            for (k, why) in [
                (
                    "thickness",
                    "is a plane part's thickness: a solid part has its own extent; remove it",
                ),
                (
                    "rectangle",
                    "meshes a plane part: a solid part's structured mesh is `box = { x = [..], y = [..], z = [..], cells = [nx, ny, nz] }`",
                ),
                (
                    "annulus",
                    "meshes a plane part and has no solid counterpart: mesh the solid in Gmsh (`gmsh = { file = … }`)",
                ),
            ] {
                if let Some(v) = t.get(k) {
                    return Err(refuse(format!("{key}.{k}"), v.span(), why));
                }
            }
            if let Some(DeValue::Table(g)) = t.get("gmsh").map(|g| g.get_ref())
                && let Some(v) = g.get("surfaces")
            {
                return Err(refuse(
                    format!("{key}.gmsh.surfaces"),
                    v.span(),
                    "selects a plane part's physical surfaces: a solid part is made of physical volumes, `volumes = [..]` (its physical surfaces are its boundaries)",
                ));
            }
        }
        for (key, t) in items("interface") {
            if let Some(v) = t.get("coupling")
                && matches!(v.get_ref(), DeValue::String(s) if s.as_ref() == "segment")
            {
                return Err(refuse(
                    format!("{key}.coupling"),
                    v.span(),
                    "= \"segment\" is for plane models only: in 3D the segment coupling needs the clipping of one face mesh's polygons by the other's, which cfe does not do; solid parts couple node to face: leave `coupling` out",
                ));
            }
        }
    } else {
        for (key, t) in items("part") {
            if let Some(v) = t.get("box") {
                // A solid model read as a plane one: say how to read it (parts
                // of both dimensions: this part is the stray one).
                if matches!(
                    problem_text_dimension(text, path),
                    Ok(ProblemDimension::Solid)
                ) {
                    return Err(refuse(
                        format!("{key}.box"),
                        v.span(),
                        "makes this a solid (3D) model, read here as a plane one: run it with `cfe run` or read it with `Model::<D3>::from_file` (`use cfe::model::FromProblemFile`; Python's `cfe.Model.from_file` reads either dimension)",
                    ));
                }
                return Err(refuse(
                    format!("{key}.box"),
                    v.span(),
                    "meshes a solid part, and this model is plane (it has `rectangle`, `annulus` or 2D Gmsh parts): mesh every part in the same dimension",
                ));
            }
            if let Some(DeValue::Table(g)) = t.get("gmsh").map(|g| g.get_ref())
                && let Some(v) = g.get("volumes")
            {
                return Err(refuse(
                    format!("{key}.gmsh.volumes"),
                    v.span(),
                    "selects a solid part's physical volumes, and this model is plane: a plane part is made of physical surfaces, `surfaces = [..]`",
                ));
            }
        }
        if let Some(DeValue::Table(o)) = root.get("output").map(|o| o.get_ref()) {
            for k in ["view", "component"] {
                if let Some(v) = o.get(k) {
                    return Err(refuse(
                        format!("output.{k}"),
                        v.span(),
                        "sets what a solid model's deformed.png shows; a plane model's pictures are fixed (deformed.png coloured by von Mises in the x–y plane): remove it",
                    ));
                }
            }
        }
        for (key, t) in items("load") {
            if let Some(v) = t.get("traction") {
                return Err(refuse(
                    format!("{key}.traction"),
                    v.span(),
                    "is a solid model's load (a traction on a surface); a plane model's boundary loads are `force` (a resultant) and `pressure`",
                ));
            }
        }
    }
    Ok(())
}
