//! The deck's lexer: the text of a CalculiX/Abaqus input deck (and of the files
//! it includes) as a list of cards — a keyword line with its parameters and the
//! data lines that follow it — each line kept with its file and number.
//!
//! Rules (those of CalculiX and Abaqus): a line starting with `**` is a comment;
//! a line starting with `*` is a keyword line, continued on the next line when
//! it ends with a comma; every other non-blank line is a data line of the last
//! keyword, its fields separated by commas. Keywords and parameter names are
//! case-insensitive (kept upper-case, inner blanks collapsed: `*Solid  section`
//! is `SOLID SECTION`). `*INCLUDE, INPUT=file` reads `file` (relative to the
//! including file's folder) in place, to a depth of [`MAX_INCLUDE_DEPTH`]; its
//! data lines continue the keyword before it, as in CalculiX.

use super::{DeckFault, deck_error};
use crate::error::{Error, Result};
use crate::mesh::input_file::{self, MESH_FILE_CAP};
use std::path::{Path, PathBuf};

/// How deep `*INCLUDE` may nest (a file including itself is caught by it).
pub const MAX_INCLUDE_DEPTH: usize = 8;

/// Where a line is: the index of its file in [`Deck::files`] and its 1-based
/// number in that file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Loc {
    /// Index into [`Deck::files`].
    pub file: usize,
    /// 1-based line number.
    pub line: usize,
}

/// A keyword parameter: `NAME` or `NAME=VALUE` (name upper-case, value as written).
#[derive(Debug, Clone)]
pub struct Param {
    /// Upper-case name, inner blanks collapsed.
    pub name: String,
    /// The value as written (trimmed), if any.
    pub value: Option<String>,
}

/// A data line: its comma-separated fields (trimmed; a trailing empty field
/// dropped) and whether it ended with a comma (an `*ELEMENT` line continues).
#[derive(Debug, Clone)]
pub struct Data {
    /// The fields.
    pub fields: Vec<String>,
    /// The line ended with a comma.
    pub continued: bool,
    /// Where it is.
    pub loc: Loc,
}

/// A keyword with its parameters and data lines.
#[derive(Debug, Clone)]
pub struct Card {
    /// Upper-case keyword without the `*` (`SOLID SECTION`).
    pub keyword: String,
    /// Its parameters in order.
    pub params: Vec<Param>,
    /// The keyword line.
    pub loc: Loc,
    /// Its data lines.
    pub data: Vec<Data>,
}

/// A lexed deck: its files (the main one first) and its cards in order.
#[derive(Debug, Default)]
pub struct Deck {
    /// The files read, the main one first.
    pub files: Vec<PathBuf>,
    /// The cards of all files, in reading order.
    pub cards: Vec<Card>,
}

/// Upper-case, blanks trimmed and runs of blanks collapsed to one space.
pub fn normalize(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase()
}

impl Deck {
    /// The deck whose main file `path` holds `text`.
    pub fn lex(text: &str, path: &Path) -> Result<Deck> {
        let mut deck = Deck::default();
        deck.lex_file(text, path, 0)?;
        Ok(deck)
    }

    fn lex_file(&mut self, text: &str, path: &Path, depth: usize) -> Result<()> {
        let file = self.files.len();
        self.files.push(path.to_path_buf());
        // A byte-order mark (as some Windows editors write) is not part of line 1.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text.lines().enumerate().peekable();
        while let Some((i, raw)) = lines.next() {
            let loc = Loc { file, line: i + 1 };
            let line = raw.trim();
            if line.is_empty() || line.starts_with("**") {
                continue;
            }
            if let Some(rest) = line.strip_prefix('*') {
                // A keyword line ending with a comma continues on the next
                // (non-comment) line.
                let mut full = rest.to_string();
                while full.trim_end().ends_with(',') {
                    match lines.next() {
                        Some((_, next)) if next.trim().starts_with("**") => continue,
                        Some((_, next)) => full.push_str(next.trim()),
                        None => break,
                    }
                }
                let mut parts = full.split(',');
                let keyword = normalize(parts.next().unwrap_or(""));
                if keyword.is_empty() {
                    return Err(deck_error(
                        path,
                        loc.line,
                        "*",
                        DeckFault::Malformed,
                        "a keyword line without a keyword (`*` alone)".into(),
                    ));
                }
                let params: Vec<Param> = parts
                    .filter(|p| !p.trim().is_empty())
                    .map(|p| match p.split_once('=') {
                        Some((n, v)) => Param {
                            name: normalize(n),
                            value: Some(v.trim().to_string()),
                        },
                        None => Param {
                            name: normalize(p),
                            value: None,
                        },
                    })
                    .collect();
                if keyword == "INCLUDE" {
                    self.include(path, loc, &params, depth)?;
                    continue;
                }
                self.cards.push(Card {
                    keyword,
                    params,
                    loc,
                    data: Vec::new(),
                });
                continue;
            }
            let Some(card) = self.cards.last_mut() else {
                return Err(deck_error(
                    path,
                    loc.line,
                    "data line",
                    DeckFault::Malformed,
                    format!("comes before any keyword (`{line}`)"),
                ));
            };
            let continued = line.ends_with(',');
            let mut fields: Vec<String> = line.split(',').map(|f| f.trim().to_string()).collect();
            if continued {
                fields.pop();
            }
            card.data.push(Data {
                fields,
                continued,
                loc,
            });
        }
        Ok(())
    }

    /// `*INCLUDE, INPUT=file` at `loc` of `path`: the file read in place.
    fn include(&mut self, path: &Path, loc: Loc, params: &[Param], depth: usize) -> Result<()> {
        let err = |fault, message: String| deck_error(path, loc.line, "*INCLUDE", fault, message);
        let mut input = None;
        for p in params {
            match (p.name.as_str(), &p.value) {
                ("INPUT", Some(v)) if !v.is_empty() => input = Some(v.trim_matches('"')),
                _ => {
                    return Err(err(
                        DeckFault::Unsupported,
                        format!(
                            "parameter {} is not supported (*INCLUDE takes INPUT=file only)",
                            p.name
                        ),
                    ));
                }
            }
        }
        let Some(input) = input else {
            return Err(err(
                DeckFault::Malformed,
                "needs INPUT=file (the file to include)".into(),
            ));
        };
        if depth + 1 > MAX_INCLUDE_DEPTH {
            return Err(err(
                DeckFault::Include,
                format!(
                    "includes nest deeper than {MAX_INCLUDE_DEPTH} files (does {input} include itself?)"
                ),
            ));
        }
        let target = path.parent().unwrap_or(Path::new("")).join(input);
        // A refusal (not a regular file, too large) is told at the *INCLUDE line.
        let data = input_file::read(&target, "included deck file", MESH_FILE_CAP, |e| {
            err(
                DeckFault::Include,
                format!("cannot read the included file {}: {e}", target.display()),
            )
        })
        .map_err(|e| match e {
            Error::InputFile { message, .. } => err(
                DeckFault::Include,
                format!(
                    "cannot read the included file {}: {message}",
                    target.display()
                ),
            ),
            e => e,
        })?;
        let text = String::from_utf8(data).map_err(|_| {
            err(
                DeckFault::Include,
                format!("the included file {} is not UTF-8 text", target.display()),
            )
        })?;
        self.lex_file(&text, &target, depth + 1)
    }

    /// The error of a line of this deck.
    pub fn error(&self, loc: Loc, keyword: &str, fault: DeckFault, message: String) -> Error {
        deck_error(&self.files[loc.file], loc.line, keyword, fault, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Comments, blank lines, case, continued keyword lines and trailing commas
    /// are read as CalculiX reads them; a byte-order mark is skipped.
    #[test]
    fn cards_and_fields() {
        let text = "\u{feff}** a comment\n*Node,  nset=All\n1, 0.0, 0.0\n\n2, 1.0, 0.0,\n*SOLID   section, elset=E,\n  material=Steel\n1.5\n";
        let d = Deck::lex(text, Path::new("m.inp")).unwrap();
        assert_eq!(d.cards.len(), 2);
        assert_eq!(d.cards[0].keyword, "NODE");
        assert_eq!(d.cards[0].params[0].name, "NSET");
        assert_eq!(d.cards[0].params[0].value.as_deref(), Some("All"));
        assert_eq!(d.cards[0].data[1].fields, ["2", "1.0", "0.0"]);
        assert!(d.cards[0].data[1].continued);
        assert_eq!(d.cards[0].data[1].loc.line, 5);
        assert_eq!(d.cards[1].keyword, "SOLID SECTION");
        assert_eq!(d.cards[1].params.len(), 2);
        assert_eq!(d.cards[1].params[1].value.as_deref(), Some("Steel"));
        assert_eq!(d.cards[1].data[0].loc.line, 8);
    }
}
