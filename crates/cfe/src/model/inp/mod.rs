//! The CalculiX/Abaqus input deck (`.inp`) reader: the common subset of a deck
//! read into the same model description a TOML problem file gives — the
//! problem-file schema (parts, materials, interfaces, steps) with the parts'
//! meshes as arrays, built by the same builder, so every later check and error
//! is shared — plus the supports and loads resolved to nodes per step.
//!
//! Four rooms: `lexer` (lines → cards, `**` comments, continuation lines,
//! `*INCLUDE`), `keywords` (what is read, ignored or refused, and why), `read`
//! (the cards interpreted in the deck's own terms, every keyword, parameter and
//! option outside the subset refused with its line) and `convert` (the deck's
//! bodies, surfaces and loads as cfe's parts, interfaces, supports and loads).
//! The mapping is stated in README.md, "Running a CalculiX/Abaqus deck".

use super::{Model, check};
use crate::domain::{Load, Support};
pub use crate::error::DeckFault;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use std::collections::BTreeMap;
use std::path::Path;

mod convert;
mod keywords;
mod lexer;
mod read;

/// The largest magnitude of a number read from a deck (as the problem file's
/// [`check::MAX_MAGNITUDE`]).
const MAX_ABS: f64 = check::MAX_MAGNITUDE;

/// A deck converted: the schema as TOML text with the deck line of each of its
/// lines, the parts' meshes, and the supports and loads resolved to nodes.
struct InpModel {
    toml: String,
    lines: Vec<Option<lexer::Loc>>,
    meshes: BTreeMap<String, Mesh>,
    supports: Vec<Support>,
    loads: Vec<Load>,
    notes: Vec<String>,
}

/// An [`Error::Deck`] at `line` of `path`: the message reads
/// "`keyword` at line `line` `message`".
fn deck_error(path: &Path, line: usize, keyword: &str, fault: DeckFault, message: String) -> Error {
    Error::Deck {
        path: path.to_path_buf(),
        line,
        keyword: keyword.to_string(),
        fault,
        message: format!("{keyword} at line {line} {message}"),
    }
}

/// The model of the deck `text` read from `path` (its `*INCLUDE`s relative to
/// its folder), its meshes refined `refine` times ([`Mesh::refined`], as a
/// Gmsh part's are): supports hold the new nodes of the edges joining two of
/// their nodes, pressures and contact penalties are taken on the refined faces,
/// and point forces stay on their nodes.
pub(super) fn model(text: &str, path: &Path, refine: usize) -> Result<Model> {
    if refine == 0 {
        return Err(Error::Model(
            "the refinement factor must be at least 1".into(),
        ));
    }
    let deck = lexer::Deck::lex(text, path)?;
    let read = read::Read::new(&deck)?;
    let converted = convert::convert(&read, refine)?;
    let mut model = Model::from_str_with_meshes(&converted.toml, path, 1, converted.meshes)
        .map_err(|e| remap(e, &deck, &converted.lines))?;
    model.text = text.to_string();
    model.refine = refine;
    model.supports = converted.supports;
    model.loads = converted.loads;
    model.notes = read
        .ignored
        .iter()
        .chain(&read.notes)
        .chain(&converted.notes)
        .cloned()
        .collect();
    model.check_names()?;
    Ok(model)
}

/// An error of the builder on the converted TOML text, told at the deck line
/// the value came from.
fn remap(e: Error, deck: &lexer::Deck, lines: &[Option<lexer::Loc>]) -> Error {
    let to_deck =
        |line: Option<usize>| line.and_then(|l| lines.get(l.wrapping_sub(1)).copied().flatten());
    let file = |loc: lexer::Loc| deck.files[loc.file].clone();
    let note = "(in the model converted from the deck)";
    match e {
        Error::Parse {
            line,
            message,
            path,
        } => match to_deck(line) {
            Some(loc) => {
                let prefix = format!("line {}: ", line.unwrap_or(0));
                let rest = message.strip_prefix(&prefix).unwrap_or(&message);
                Error::Parse {
                    path: file(loc),
                    line: Some(loc.line),
                    message: format!("line {}: {rest} {note}", loc.line),
                }
            }
            None => Error::Parse {
                path,
                line,
                message: format!("{message} {note}"),
            },
        },
        Error::Invalid {
            path,
            line,
            key,
            message,
        } => match to_deck(line) {
            Some(loc) => Error::Invalid {
                path: file(loc),
                line: Some(loc.line),
                key,
                message: format!("{message} {note}"),
            },
            None => Error::Invalid {
                path,
                line,
                key,
                message,
            },
        },
        Error::PenaltyPrecision {
            path,
            line,
            key,
            ratio,
            message,
        } => {
            let loc = to_deck(line);
            Error::PenaltyPrecision {
                path: loc.map(file).unwrap_or(path),
                line: loc.map(|l| l.line).or(line),
                key,
                ratio,
                message,
            }
        }
        Error::WeakPenalty {
            path,
            line,
            key,
            ratio,
            message,
        } => {
            let loc = to_deck(line);
            Error::WeakPenalty {
                path: loc.map(file).unwrap_or(path),
                line: loc.map(|l| l.line).or(line),
                key,
                ratio,
                message,
            }
        }
        Error::DuplicateName {
            path,
            line,
            key,
            name,
            message,
        } => {
            let loc = to_deck(line);
            Error::DuplicateName {
                path: loc.map(file).unwrap_or(path),
                line: loc.map(|l| l.line).or(line),
                key,
                name,
                message,
            }
        }
        e => e,
    }
}
