//! The never-rules of docs/architecture.md, checked on the sources. The crate
//! boundaries enforce the rest (cfe cannot import cfe-tools or cfe-cli).
//!
//! 1. Numerics know no input file: dim, mesh, fem, domain, dofs, coupling, assembly and
//!    solve never import the problem-file module (`model`), the orchestration
//!    (`analysis`), the writers (`output`) or the TOML parser.
//! 2. The solver reads no input and writes no files: solve touches no file system.
//! 3. Elements know no interface: fem and the coupling element never name `Interface`.
//! 4. The library knows no command line: no clap, indicatif or anyhow in cfe.
//! 5. The writers know no analysis: output never names `Analysis`, `analysis` or the
//!    run loop (`run`) above it.
//!
//! And the layering itself: the file-level import graph of `crates/cfe/src` has no
//! circle, and each file imports only files of its own or lower layers in the
//! order [`LAYERS`] (the order docs/architecture.md states).

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

/// The linear algebra sits below the contact scheme and has no circle: the
/// factorization (`factor.rs` and its dense kernels, `factor/dense.rs`) and the
/// matrix it reads (`lower.rs`) never import the Cholesky facade (`linear.rs`),
/// and no linear back end or the seam imports the scheme.
#[test]
fn the_linear_algebra_is_below_the_scheme_without_a_circle() {
    never(
        "the factorization does not import the Cholesky facade",
        &[
            "solve/factor.rs",
            "solve/factor",
            "solve/halt.rs",
            "solve/lower.rs",
        ],
        &["super::linear", "solve::linear"],
    );
    never(
        "the linear algebra does not import the contact scheme",
        &[
            "solve/backend.rs",
            "solve/direct.rs",
            "solve/iterative.rs",
            "solve/system.rs",
            "solve/system",
            "solve/linear.rs",
            "solve/paths.rs",
            "solve/factor.rs",
            "solve/factor",
            "solve/halt.rs",
            "solve/lower.rs",
            "solve/columns.rs",
            "solve/capacitance.rs",
            "solve/subtree.rs",
            "solve/symbolic.rs",
        ],
        &["nonlinear", "super::contact", "solve::contact"],
    );
}

/// The writers take plain data (points, cells, named field arrays): output never
/// reaches into the analysis or the run loop above it.
#[test]
fn the_writers_know_no_analysis() {
    never(
        "the writers know no analysis",
        &["output"],
        &["crate::analysis", "crate::run", "Analysis"],
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

// ───────────────────────── the file-level import graph ─────────────────────────

use std::collections::{BTreeMap, BTreeSet, VecDeque};

/// The layers of `crates/cfe/src`, from the bottom up: a file of one layer imports
/// files of its own layer or of layers listed before it, never of a later one.
/// `lib` is the crate root (`lib.rs`). docs/architecture.md states this order in
/// the same words (checked below).
const LAYERS: [&str; 15] = [
    "error", "dim", "mesh", "fem", "domain", "dofs", "coupling", "assembly", "solve", "results",
    "model", "analysis", "output", "run", "lib",
];

/// Which file imports which: `graph[a][b]` is the first line of `a` that reaches
/// into `b`.
type Graph = BTreeMap<String, BTreeMap<String, usize>>;

/// `text` with its comments (line, doc and block) and its string, byte-string,
/// raw-string and character literals blanked out; newlines kept, so line numbers
/// stay. Lifetimes (`'a`) are code.
fn blank_comments_and_strings(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    let mut i = 0;
    while i < c.len() {
        let at = |k: usize| c.get(k).copied().unwrap_or('\0');
        if c[i] == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
                out.push(' ');
            }
        } else if c[i] == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
        } else if (c[i] == 'r' || (c[i] == 'b' && at(i + 1) == 'r'))
            && (i == 0 || !ident(c[i - 1]))
            && {
                let mut k = i + if c[i] == 'b' { 2 } else { 1 };
                while at(k) == '#' {
                    k += 1;
                }
                at(k) == '"'
            }
        {
            // A raw string: r"…", r#"…"#, br#"…"#.
            let mut k = i + if c[i] == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while at(k) == '#' {
                hashes += 1;
                k += 1;
            }
            k += 1;
            while k < c.len() && !(c[k] == '"' && (1..=hashes).all(|h| at(k + h) == '#')) {
                k += 1;
            }
            let end = (k + 1 + hashes).min(c.len());
            for &ch in &c[i..end] {
                blank(&mut out, ch);
            }
            i = end;
        } else if c[i] == '"' {
            out.push(' ');
            i += 1;
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    blank(&mut out, c[i]);
                    i += 1;
                }
                if i < c.len() {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
            out.push(' ');
            i += 1;
        } else if c[i] == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            // A character literal ('x', '\n', '\u{…}'); a lifetime has no closing quote.
            let mut k = i + 1;
            if at(k) == '\\' {
                k += 2;
            } else {
                k += 1;
            }
            while k < c.len() && c[k] != '\'' {
                k += 1;
            }
            let end = (k + 1).min(c.len());
            for &ch in &c[i..end] {
                blank(&mut out, ch);
            }
            i = end;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// The tokens of code (comments and literals already blanked): identifiers, `::`
/// and single punctuation characters, each with its line.
fn tokens(code: &str) -> Vec<(String, usize)> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < c.len() {
        if c[i] == '\n' {
            line += 1;
            i += 1;
        } else if c[i].is_whitespace() {
            i += 1;
        } else if c[i].is_alphanumeric() || c[i] == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push((c[start..i].iter().collect(), line));
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push(("::".into(), line));
            i += 2;
        } else {
            out.push((c[i].to_string(), line));
            i += 1;
        }
    }
    out
}

/// The module path of a source file: `lib.rs` → [], `a.rs` and `a/mod.rs` → [a],
/// `a/b.rs` → [a, b].
fn module_of(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file.split('/').map(String::from).collect();
    let last = parts.pop().unwrap();
    if last != "mod.rs" && last != "lib.rs" {
        parts.push(last.trim_end_matches(".rs").to_string());
    }
    parts
}

/// The file of module `m` among `files`, if it has one of its own.
fn file_of(m: &[String], files: &BTreeSet<String>) -> Option<String> {
    if m.is_empty() {
        return files.get("lib.rs").cloned();
    }
    let stem = m.join("/");
    [format!("{stem}.rs"), format!("{stem}/mod.rs")]
        .into_iter()
        .find(|f| files.contains(f))
}

/// The absolute form of a path written in module `m`: `crate::`, `self::` and
/// `super::` resolved; in a `use`, a first segment naming a child module of `m` is
/// relative to `m`. `None` for paths into other crates.
fn absolute(
    path: &[String],
    m: &[String],
    in_use: bool,
    files: &BTreeSet<String>,
) -> Option<Vec<String>> {
    let mut base: Vec<String>;
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => {
            base = Vec::new();
            rest = &path[1..];
        }
        Some("self") => {
            base = m.to_vec();
            rest = &path[1..];
        }
        Some("super") => {
            base = m.to_vec();
            while rest.first().map(String::as_str) == Some("super") {
                base.pop()?;
                rest = &rest[1..];
            }
        }
        Some(first) if in_use => {
            let mut child = m.to_vec();
            child.push(first.to_string());
            file_of(&child, files)?;
            base = m.to_vec();
        }
        _ => return None,
    }
    base.extend(rest.iter().filter(|s| *s != "self").cloned());
    Some(base)
}

/// The paths of the use tree starting at `t[*i]` (after `use`), up to its `;`,
/// each with the name it brings in: `a::{b, c::{d, e as f}, g::*}` → (a::b, b),
/// (a::c::d, d), (a::c::e, f), (a::g, none: a glob).
fn use_tree(
    t: &[(String, usize)],
    i: &mut usize,
    prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let s = |k: usize| t.get(k).map_or("", |(s, _)| s.as_str());
    let mut path = prefix;
    loop {
        match s(*i) {
            "::" => *i += 1,
            "{" => {
                *i += 1;
                while !matches!(s(*i), "}" | ";" | "") {
                    use_tree(t, i, path.clone(), out);
                    if s(*i) == "," {
                        *i += 1;
                    }
                }
                *i += 1;
                return;
            }
            "*" => {
                *i += 1;
                out.push((path, None));
                return;
            }
            "as" => {
                let alias = s(*i + 1).to_string();
                *i += 2;
                out.push((path, Some(alias)));
                return;
            }
            w if !w.is_empty() && w.chars().all(|ch| ch.is_alphanumeric() || ch == '_') => {
                path.push(w.to_string());
                *i += 1;
            }
            _ => {
                if let Some(last) = path.last().filter(|l| *l != "self").cloned() {
                    out.push((path, Some(last)));
                } else if path.last().is_some_and(|l| l == "self") {
                    path.pop();
                    let name = path.last().cloned();
                    out.push((path, name));
                }
                return;
            }
        }
    }
}

/// What one file says, read from its tokens: the names it re-exports (`pub use`,
/// at its top level: name → absolute path and line), the identifiers of its code
/// outside `use` declarations, and its other references: the absolute paths of
/// its plain `use`s and of the `crate::`/`self::`/`super::` paths in its code, each
/// with its line.
#[derive(Default)]
struct FileRefs {
    reexports: BTreeMap<String, (Vec<String>, usize)>,
    idents: BTreeSet<String>,
    paths: Vec<(Vec<String>, usize)>,
}

fn is_ident(w: &str) -> bool {
    !w.is_empty() && w.chars().all(|ch| ch.is_alphanumeric() || ch == '_')
}

fn read_refs(file: &str, text: &str, names: &BTreeSet<String>) -> FileRefs {
    let t = tokens(&blank_comments_and_strings(text));
    let s = |k: usize| t.get(k).map_or("", |(s, _)| s.as_str());
    let mut refs = FileRefs::default();
    // Inline modules: (name, brace depth of its body).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let mut i = 0;
    while i < t.len() {
        let mut module = module_of(file);
        module.extend(inline.iter().map(|(n, _)| n.clone()));
        let line = t[i].1;
        match s(i) {
            "{" => {
                depth += 1;
                i += 1;
            }
            "}" => {
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
                depth -= 1;
                i += 1;
            }
            "mod" if is_ident(s(i + 1)) && s(i + 2) == "{" => {
                inline.push((s(i + 1).to_string(), depth + 1));
                i += 2;
            }
            "mod" if is_ident(s(i + 1)) && s(i + 2) == ";" => {
                // A declaration places the child; it is not a use of it.
                module.push(s(i + 1).to_string());
                assert!(
                    file_of(&module, names).is_some(),
                    "{file}:{line}: no file for `mod {}`",
                    s(i + 1)
                );
                i += 3;
            }
            "use" if s(i + 1) != "<" => {
                // `pub use` / `pub(crate) use`: a re-export.
                let public = s(i.wrapping_sub(1)) == "pub"
                    || (s(i.wrapping_sub(1)) == ")"
                        && (1..i)
                            .rev()
                            .find(|&k| s(k) == "(")
                            .is_some_and(|k| s(k - 1) == "pub"));
                i += 1;
                let mut paths = Vec::new();
                use_tree(&t, &mut i, Vec::new(), &mut paths);
                for (p, name) in paths {
                    let Some(abs) = absolute(&p, &module, true, names) else {
                        continue;
                    };
                    match name {
                        Some(name) if public && inline.is_empty() => {
                            refs.reexports.insert(name, (abs, line));
                        }
                        _ => refs.paths.push((abs, line)),
                    }
                }
            }
            "crate" | "self" | "super" if s(i + 1) == "::" && s(i.wrapping_sub(1)) != "::" => {
                let mut p = vec![s(i).to_string()];
                let mut k = i + 1;
                while s(k) == "::" && is_ident(s(k + 1)) {
                    p.push(s(k + 1).to_string());
                    k += 2;
                }
                refs.idents.extend(p[1..].iter().cloned());
                if let Some(abs) = absolute(&p, &module, false, names) {
                    refs.paths.push((abs, line));
                }
                i = k;
            }
            w => {
                if is_ident(w) {
                    refs.idents.insert(w.to_string());
                }
                i += 1;
            }
        }
    }
    refs
}

/// The file that defines what `path` (absolute) names: the file of its longest
/// prefix that is a module with a file, and through that file's re-exports on to
/// the file the re-exported item comes from (`crate::coupling::Law` →
/// `coupling/law.rs` when `coupling/mod.rs` says `pub use law::Law`).
fn defining_file(
    path: &[String],
    files: &BTreeSet<String>,
    refs: &BTreeMap<String, FileRefs>,
    hops: usize,
) -> Option<String> {
    let n = (0..=path.len())
        .rev()
        .find(|&n| file_of(&path[..n], files).is_some())?;
    let file = file_of(&path[..n], files)?;
    if let Some((target, _)) = path.get(n).and_then(|name| refs[&file].reexports.get(name))
        && hops < 32
    {
        let mut next = target.clone();
        next.extend(path[n + 1..].iter().cloned());
        return defining_file(&next, files, refs, hops + 1);
    }
    Some(file)
}

/// The file-level import graph of the sources `files` (path relative to `src` →
/// text): an edge from a file to every other file that defines an item it names
/// through a `use` or a `crate::`/`self::`/`super::` path in its code. Names are
/// followed through re-exports to the file that defines them; a `pub use` is a use
/// of its file only where that file's code names the item too (otherwise it only
/// passes the name on), and a `mod name;` declaration only places the child.
/// Comments, doc comments and literals are not code; an inline `mod name { … }`
/// (such as the tests) shifts what `self` and `super` mean inside it.
fn import_graph(files: &BTreeMap<String, String>) -> Graph {
    let names: BTreeSet<String> = files.keys().cloned().collect();
    let refs: BTreeMap<String, FileRefs> = files
        .iter()
        .map(|(f, text)| (f.clone(), read_refs(f, text, &names)))
        .collect();
    let mut graph = Graph::new();
    for (file, r) in &refs {
        let used_reexports = r
            .reexports
            .iter()
            .filter(|(name, _)| r.idents.contains(*name))
            .map(|(_, p)| p);
        let edges = graph.entry(file.clone()).or_default();
        for (path, line) in r.paths.iter().chain(used_reexports) {
            if let Some(target) = defining_file(path, &names, &refs, 0).filter(|t| t != file) {
                edges.entry(target).or_insert(*line);
            }
        }
    }
    graph
}

/// The layer of a file: its top-level module (`lib` for `lib.rs`).
fn layer_of(file: &str) -> String {
    module_of(file)
        .first()
        .cloned()
        .unwrap_or_else(|| "lib".into())
}

/// Every import that goes up the layer order `layers` (or leaves it), as
/// `file:line imports target (layer → layer)`.
fn upward_imports(graph: &Graph, layers: &[&str]) -> Vec<String> {
    let rank = |f: &str| layers.iter().position(|l| *l == layer_of(f));
    let mut broken = Vec::new();
    for (a, edges) in graph {
        for (b, line) in edges {
            match (rank(a), rank(b)) {
                (Some(ra), Some(rb)) if rb <= ra => {}
                (Some(_), Some(_)) => broken.push(format!(
                    "{a}:{line} imports {b} ({} is above {})",
                    layer_of(b),
                    layer_of(a)
                )),
                _ => broken.push(format!(
                    "{a}:{line} imports {b}: a layer missing from the order"
                )),
            }
        }
    }
    broken
}

/// The circles of the graph: each strongly connected group of two or more files
/// (sorted), found by Tarjan's algorithm.
fn circles(graph: &Graph) -> Vec<Vec<String>> {
    struct Tarjan<'a> {
        graph: &'a Graph,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        groups: Vec<Vec<String>>,
    }
    impl<'a> Tarjan<'a> {
        fn visit(&mut self, v: &'a str) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            self.on_stack.insert(v);
            for w in self.graph.get(v).into_iter().flat_map(|e| e.keys()) {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if self.on_stack.contains(w) {
                    let iw = self.index[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
            if self.low[v] == self.index[v] {
                let mut group = Vec::new();
                loop {
                    let w = self.stack.pop().unwrap();
                    self.on_stack.remove(w);
                    group.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if group.len() > 1 {
                    group.sort();
                    self.groups.push(group);
                }
            }
        }
    }
    let mut t = Tarjan {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        groups: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.groups.sort();
    t.groups
}

/// One circle through the files of `group` (a strongly connected group), as
/// `a:line → b:line → … → a`: the shortest way back to its first file.
fn describe_circle(graph: &Graph, group: &[String]) -> String {
    let start = &group[0];
    let mut came_from: BTreeMap<&str, &str> = BTreeMap::new();
    let mut queue = VecDeque::from([start.as_str()]);
    let mut end = None;
    while let Some(v) = queue.pop_front() {
        for w in graph[v].keys().filter(|w| group.contains(w)) {
            if w == start {
                end = Some(v);
                break;
            }
            if !came_from.contains_key(w.as_str()) {
                came_from.insert(w, v);
                queue.push_back(w);
            }
        }
        if end.is_some() {
            break;
        }
    }
    let mut path = vec![start.as_str()];
    let mut v = end.expect("a strongly connected group has a circle");
    while v != start {
        path.push(v);
        v = came_from[v];
    }
    path[1..].reverse();
    path.push(start);
    path.windows(2)
        .map(|w| format!("{}:{}", w[0], graph[w[0]][w[1]]))
        .chain(std::iter::once(start.to_string()))
        .collect::<Vec<_>>()
        .join(" → ")
}

/// Every source file of the library, path relative to `src` → text.
fn library_sources() -> BTreeMap<String, String> {
    let root = src();
    let mut files = BTreeMap::new();
    let mut stack = vec![root.clone()];
    while let Some(p) = stack.pop() {
        if p.is_dir() {
            for e in std::fs::read_dir(&p).unwrap() {
                stack.push(e.unwrap().path());
            }
        } else if p.extension().is_some_and(|e| e == "rs") {
            let rel = p
                .strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            files.insert(rel, std::fs::read_to_string(&p).unwrap());
        }
    }
    files
}

/// The library's files import one another in no circle, and each imports only
/// files of its own or lower layers in the order of [`LAYERS`], the order
/// docs/architecture.md states.
#[test]
fn the_library_has_no_import_circle_and_no_upward_arrow() {
    let graph = import_graph(&library_sources());
    let found: Vec<String> = circles(&graph)
        .into_iter()
        .map(|g| format!("{} ({})", describe_circle(&graph, &g), g.join(", ")))
        .collect();
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
    let up = upward_imports(&graph, &LAYERS);
    assert!(
        up.is_empty(),
        "imports against the layer order:\n{}",
        up.join("\n")
    );
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/architecture.md"),
    )
    .unwrap();
    let order = LAYERS.join(" < ");
    assert!(
        doc.contains(&order),
        "docs/architecture.md must state the layer order `{order}`"
    );
}

fn fixture(files: &[(&str, &str)]) -> BTreeMap<String, String> {
    files
        .iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect()
}

/// The graph finds a circle through `use`, a `crate::` path in code and
/// `super::`, names its files, and sees none in comments, doc comments, strings
/// or a test module's `use super::*`.
#[test]
fn the_graph_finds_a_circle_and_ignores_comments_and_strings() {
    let circle = fixture(&[
        ("lib.rs", "mod a;\nmod b;\n"),
        ("a/mod.rs", "mod inner;\nuse crate::b::Thing;\n"),
        ("a/inner.rs", "pub fn f() -> u8 { super::super::b::g() }\n"),
        (
            "b.rs",
            "pub struct Thing;\npub fn g() -> u8 { crate::a::inner::f() }\n",
        ),
    ]);
    let graph = import_graph(&circle);
    assert_eq!(graph["a/inner.rs"].keys().collect::<Vec<_>>(), ["b.rs"]);
    let found = circles(&graph);
    assert_eq!(found, [vec!["a/inner.rs".to_string(), "b.rs".to_string()]]);
    assert_eq!(
        describe_circle(&graph, &found[0]),
        "a/inner.rs:1 → b.rs:2 → a/inner.rs"
    );
    let quiet = fixture(&[
        ("lib.rs", "mod a;\nmod b;\n"),
        (
            "a.rs",
            "//! Uses crate::b::Thing.\n/// See crate::b.\nfn f() -> &'static str { \"crate::b::g\" } // crate::b\n/* use crate::b::Thing; */\nconst C: char = '\"'; fn h() { crate::b::g(); }\n",
        ),
        (
            "b.rs",
            "pub fn g() {}\nconst S: &str = r#\"use crate::a::f;\"#;\n#[cfg(test)]\nmod tests {\n    use super::*;\n    fn t<'a>(x: &'a str) -> &'a str { self::helper(x) }\n    fn helper(x: &str) -> &str { x }\n}\n",
        ),
    ]);
    let graph = import_graph(&quiet);
    assert_eq!(
        graph["a.rs"].iter().collect::<Vec<_>>(),
        [(&"b.rs".to_string(), &5)]
    );
    assert!(graph["b.rs"].is_empty(), "{:?}", graph["b.rs"]);
    assert!(circles(&graph).is_empty());
}

/// A re-export passes a name on to the file that defines it: a module's face
/// re-exporting its child while the child reads the face's own items is no
/// circle, unless the face's code uses the re-exported item too.
#[test]
fn the_graph_follows_reexports_to_the_defining_file() {
    let face = |code: &str| {
        fixture(&[
            ("lib.rs", "mod m;\nmod user;\n"),
            ("m/mod.rs", code),
            (
                "m/child.rs",
                "use super::Other;\npub struct Thing(Other);\n",
            ),
            ("user.rs", "fn f(_: crate::m::Thing) {}\n"),
        ])
    };
    let graph = import_graph(&face(
        "mod child;\npub use child::Thing;\npub struct Other;\n",
    ));
    assert!(graph["m/mod.rs"].is_empty());
    assert_eq!(graph["user.rs"].keys().collect::<Vec<_>>(), ["m/child.rs"]);
    assert!(circles(&graph).is_empty());
    let graph = import_graph(&face(
        "mod child;\npub use child::Thing;\npub struct Other;\npub fn g(_: Thing) {}\n",
    ));
    assert_eq!(
        circles(&graph),
        [vec!["m/child.rs".to_string(), "m/mod.rs".to_string()]]
    );
}

/// The layer check names an import that goes up the order (a `use` of a later
/// layer, here a grouped one), and accepts imports down and within a layer.
#[test]
fn the_layer_check_finds_an_upward_arrow() {
    let files = fixture(&[
        ("lib.rs", "mod low;\nmod high;\npub use low::Base;\n"),
        (
            "low/mod.rs",
            "mod part;\npub struct Base;\npub use part::Piece;\n",
        ),
        (
            "low/part.rs",
            "use crate::{high::{Top, other}, low::Base};\npub struct Piece;\n",
        ),
        (
            "high.rs",
            "use crate::low::Base;\npub struct Top;\npub mod other {}\n",
        ),
    ]);
    let graph = import_graph(&files);
    assert!(circles(&graph).is_empty());
    assert_eq!(
        upward_imports(&graph, &["low", "high", "lib"]),
        ["low/part.rs:1 imports high.rs (high is above low)"]
    );
    assert!(upward_imports(&graph, &["high", "low", "lib"]).len() == 1);
    assert_eq!(
        upward_imports(&graph, &["low", "lib"]),
        [
            "high.rs:1 imports low/mod.rs: a layer missing from the order",
            "low/part.rs:1 imports high.rs: a layer missing from the order"
        ]
    );
}
