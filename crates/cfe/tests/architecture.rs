//! The never-rules of docs/architecture.md, checked on the sources. The crate
//! boundaries enforce the rest (cfe cannot import cfe-tools or cfe-cli).
//!
//! 1. Numerics know no input file: dim, mesh, fem, domain, dofs, coupling, assembly and
//!    solve never import the problem-file module (`model`), the orchestration
//!    (`analysis`), the writers (`output`) or the TOML parser.
//! 2. The solver reads no input and writes no files: solve touches no file system.
//! 3. Elements know no interface: fem and the coupling element never name `Interface`.
//! 4. The library knows no command line: no clap, indicatif or anyhow in cfe.

use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `path` (or `path` itself), with its code lines: line
/// comments and doc comments dropped.
fn code(path: &Path) -> Vec<(PathBuf, Vec<(usize, String)>)> {
    let mut files = Vec::new();
    let mut stack = vec![path.to_path_buf()];
    while let Some(p) = stack.pop() {
        if p.is_dir() {
            for e in std::fs::read_dir(&p).unwrap() {
                stack.push(e.unwrap().path());
            }
        } else if p.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&p).unwrap();
            let lines = text
                .lines()
                .enumerate()
                .map(|(i, l)| (i + 1, l.split("//").next().unwrap_or("").to_string()))
                .filter(|(_, l)| !l.trim().is_empty())
                .collect();
            files.push((p, lines));
        }
    }
    assert!(!files.is_empty(), "no sources under {}", path.display());
    files
}

/// Fails naming every line of the sources under `paths` that contains one of `banned`.
fn never(rule: &str, paths: &[&str], banned: &[&str]) {
    let mut broken = Vec::new();
    for p in paths {
        for (file, lines) in code(&src().join(p)) {
            for (n, line) in lines {
                for b in banned {
                    if line.contains(b) {
                        broken.push(format!("{}:{n}: {}", file.display(), line.trim()));
                    }
                }
            }
        }
    }
    assert!(broken.is_empty(), "{rule}:\n{}", broken.join("\n"));
}

const NUMERICS: [&str; 9] = [
    "dim.rs",
    "mesh",
    "fem",
    "domain.rs",
    "dofs.rs",
    "coupling",
    "assembly",
    "solve",
    "error.rs",
];

#[test]
fn numerics_know_no_input_file() {
    never(
        "numerics know no input file",
        &NUMERICS,
        &["crate::model", "crate::analysis", "crate::output", "toml::"],
    );
}

#[test]
fn the_solver_reads_no_input_and_writes_no_files() {
    never(
        "the solver reads no input and writes no files",
        &["solve"],
        &[
            "std::fs",
            "File::",
            "crate::model",
            "crate::output",
            "std::io",
        ],
    );
}

#[test]
fn elements_know_no_interface() {
    never(
        "elements know no interface",
        &["fem", "coupling/element.rs", "coupling/law.rs"],
        &["Interface", "InterfaceDef"],
    );
}

#[test]
fn the_library_knows_no_command_line() {
    never(
        "the library knows no command line",
        &["."],
        &["clap::", "indicatif::", "anyhow::"],
    );
    let manifest =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml")).unwrap();
    for dep in ["clap", "indicatif", "anyhow"] {
        assert!(
            !manifest.lines().any(|l| l.trim_start().starts_with(dep)),
            "cfe depends on {dep}"
        );
    }
}

/// The public surface is small: the numerical layers are declared through `layer!`
/// (public only with the `internals` feature), and the embedding crates — the CLI and
/// the Python package — reach the library through the crate root and the public
/// modules only, never into a layer.
#[test]
fn embedders_use_the_public_api_only() {
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    for layer in ["assembly", "coupling", "dofs", "fem", "solve"] {
        assert!(
            lib.contains(&format!("layer!({layer});")),
            "lib.rs must declare `{layer}` with layer!, not as a public module"
        );
        assert!(
            !lib.contains(&format!("pub mod {layer};")),
            "lib.rs makes `{layer}` public without the internals feature"
        );
    }
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut broken = Vec::new();
    for embedder in ["cfe-cli/src", "cfe-py/src"] {
        for (file, lines) in code(&crates.join(embedder)) {
            for (n, line) in lines {
                for layer in ["assembly", "coupling", "dofs", "fem", "solve"] {
                    if line.contains(&format!("cfe::{layer}::")) {
                        broken.push(format!("{}:{n}: {}", file.display(), line.trim()));
                    }
                }
            }
        }
    }
    assert!(
        broken.is_empty(),
        "the embedders reach into a layer module:\n{}",
        broken.join("\n")
    );
}
