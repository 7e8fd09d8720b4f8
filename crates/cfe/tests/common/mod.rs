//! Shared helpers of the integration tests: build a model from text and solve it
//! without writing files.
#![allow(dead_code)]

use cfe::analysis::Analysis;
use cfe::analysis::Start;
use cfe::coupling::PairState;
use cfe::model::Model;
use cfe::solve::nonlinear::{IncrementResult, Solver};
use std::path::Path;

/// Prepares an analysis from problem text.
pub fn analysis(text: &str) -> Analysis {
    let model = Model::from_str(text, Path::new("test.toml"), 1).expect("valid problem");
    Analysis::new(model).expect("pairs found")
}

/// Solves every increment in memory and returns them all.
pub fn solve(a: &Analysis) -> Vec<IncrementResult> {
    let mut all = Vec::new();
    a.solve_from(Start::AllBonded, |inc| {
        all.push(inc.clone());
        Ok(())
    })
    .expect("converges");
    all
}

/// Runs `solver` to its end and returns every increment.
pub fn run_all(mut solver: Solver<'_>) -> Vec<IncrementResult> {
    let mut all = Vec::new();
    solver
        .run(|inc| {
            all.push(inc.clone());
            Ok(())
        })
        .expect("converges");
    all
}

/// Solves `a` and asserts the run completed with the law on every pair.
pub fn solve_completed(a: &Analysis) -> cfe::analysis::Results {
    let res = a.solve().unwrap();
    assert_eq!(
        res.summary.status,
        cfe::analysis::RunStatus::Completed,
        "{:?}",
        res.summary.warnings
    );
    res
}

/// The path of `examples/<name>` (e.g. `"plate_on_base.toml"`).
pub fn example_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// The analysis of `examples/<name>`, its meshes refined `refine` times.
pub fn example(name: &str, refine: usize) -> Analysis {
    Analysis::new(Model::from_file(&example_path(name), refine).unwrap()).unwrap()
}

/// The external load of `a` on its free equations (the right-hand side of a
/// linear solve).
pub fn free_load(a: &Analysis) -> Vec<f64> {
    let f = cfe::assembly::external_force(&a.model.loads, &a.dofs);
    a.dofs
        .eq
        .iter()
        .enumerate()
        .filter(|(_, e)| **e != usize::MAX)
        .map(|(d, _)| f[d])
        .collect()
}

/// The free equations of the DOFs of interface `i`'s coupling elements,
/// element by element in their DOF order (an equation shared by elements
/// repeats).
pub fn coupling_equations(a: &Analysis, i: usize) -> Vec<usize> {
    let iface = &a.interfaces[i];
    iface
        .elements
        .iter()
        .flat_map(|c| {
            c.dofs(&a.dofs, iface.host, iface.node_part)
                .as_slice()
                .to_vec()
        })
        .map(|d| a.dofs.eq[d])
        .filter(|&e| e != usize::MAX)
        .collect()
}

/// Three patterns of one interface with `n` pairs: all bonded; the three
/// outermost pairs at each end open; every third pair open.
pub fn contact_patterns(n: usize) -> [Vec<Vec<PairState>>; 3] {
    let bonded = vec![vec![PairState::Bonded; n]];
    let mut ends = bonded.clone();
    for k in [0, 1, 2, n - 3, n - 2, n - 1] {
        ends[0][k] = PairState::Open;
    }
    let mut thirds = bonded.clone();
    for k in (0..n).step_by(3) {
        thirds[0][k] = PairState::Open;
    }
    [bonded, ends, thirds]
}

/// Displacement (x, y) of the node of `part` at `at`.
pub fn displacement_at(a: &Analysis, inc: &IncrementResult, part: &str, at: [f64; 2]) -> [f64; 2] {
    let p = a.model.part_index(part).expect("part");
    let n = a.model.parts[p]
        .mesh
        .nodes
        .iter()
        .position(|x| (x[0] - at[0]).abs() < 1e-9 && (x[1] - at[1]).abs() < 1e-9)
        .expect("node at point");
    let g = a.dofs.node(p, n);
    [inc.u[2 * g], inc.u[2 * g + 1]]
}

/// Checks the contact conditions of a converged increment: no bonded pair
/// penetrates by more than 1e-4 of the largest displacement, every open pair has
/// gap_n > 0 and carries no force.
pub fn check_contact_conditions(a: &Analysis, inc: &IncrementResult) {
    let umax = inc
        .u
        .chunks(2)
        .map(|d| d[0].hypot(d[1]))
        .fold(0.0, f64::max);
    for row in a.pair_rows(inc) {
        if row.state == PairState::Bonded {
            assert!(
                -row.gap_n <= 1e-4 * umax,
                "bonded pair at x = {} penetrates by {:e}",
                row.x,
                -row.gap_n
            );
        } else {
            assert!(
                row.gap_n > 0.0,
                "open pair at x = {} has gap {:e}",
                row.x,
                row.gap_n
            );
            assert!(
                row.force_n == 0.0 && row.force_s == 0.0,
                "open pair at x = {} carries force",
                row.x
            );
        }
    }
}

/// The sum of all support reactions (x, y).
pub fn total_reaction(a: &Analysis, inc: &IncrementResult) -> [f64; 2] {
    a.reactions(inc)
        .iter()
        .fold([0.0; 2], |t, r| [t[0] + r[0], t[1] + r[1]])
}

// ------------------------------------------------------------------ problems

/// A TOML value as the problem files write it: numbers by their shortest exact
/// text (`1000.0`, `0.3`), strings quoted, pairs as arrays.
pub trait Toml {
    /// The value's TOML text.
    fn toml(&self) -> String;
}

impl Toml for f64 {
    fn toml(&self) -> String {
        format!("{self:?}")
    }
}

impl Toml for usize {
    fn toml(&self) -> String {
        self.to_string()
    }
}

impl Toml for &str {
    fn toml(&self) -> String {
        format!("\"{self}\"")
    }
}

impl Toml for [f64; 2] {
    fn toml(&self) -> String {
        format!("[{:?}, {:?}]", self[0], self[1])
    }
}

impl Toml for [usize; 2] {
    fn toml(&self) -> String {
        format!("[{}, {}]", self[0], self[1])
    }
}

impl<const N: usize> Toml for [&str; N] {
    fn toml(&self) -> String {
        let items: Vec<String> = self.iter().map(|s| format!("\"{s}\"")).collect();
        format!("[{}]", items.join(", "))
    }
}

/// A value written exactly as given (`1e9`, `nan`, an inline table).
pub struct Raw<'a>(pub &'a str);

impl Toml for Raw<'_> {
    fn toml(&self) -> String {
        self.0.to_string()
    }
}

/// A structured part's `rectangle` key.
#[derive(Clone, Debug)]
struct Rect {
    x: [f64; 2],
    y: [f64; 2],
    cells: [usize; 2],
    elements: Option<String>,
}

impl Rect {
    fn toml(&self) -> String {
        let elements = match &self.elements {
            Some(kind) => format!(", elements = \"{kind}\""),
            None => String::new(),
        };
        format!(
            "{{ x = {}, y = {}, cells = {}{elements} }}",
            self.x.toml(),
            self.y.toml(),
            self.cells.toml()
        )
    }
}

/// One line of a table.
#[derive(Clone, Debug)]
enum Line {
    /// `key = value`.
    Key(String, String),
    /// A structured part's rectangle.
    Rect(Rect),
    /// Text written as given (one or more lines).
    Raw(String),
}

/// A table (`[[part]]`, `[analysis]` …) and its lines, or (no header) raw text.
#[derive(Clone, Debug)]
struct Table {
    header: String,
    lines: Vec<Line>,
}

/// A problem file built table by table, written as the tests' problem texts
/// were: a leading empty line, the top-level keys, then the tables in the order
/// they were added, either one after the other (`compact`) or separated by an
/// empty line (`spaced`). Keys go to the last table added, except those of
/// `law`, `friction`, `iface_key` and `iface`, which go to the last interface.
/// Numbers are written by their shortest exact text, so a test's problem is the
/// one its numbers say.
#[derive(Clone, Debug)]
pub struct Problem {
    leading_newline: bool,
    spaced: bool,
    head: Vec<String>,
    tables: Vec<Table>,
}

impl Problem {
    /// An empty problem whose tables follow one another.
    pub fn compact() -> Problem {
        Problem {
            leading_newline: true,
            spaced: false,
            head: Vec::new(),
            tables: Vec::new(),
        }
    }

    /// An empty problem whose tables are separated by an empty line.
    pub fn spaced() -> Problem {
        Problem {
            spaced: true,
            ..Problem::compact()
        }
    }

    /// The text starts with its first key, not an empty line.
    pub fn no_leading_newline(mut self) -> Problem {
        self.leading_newline = false;
        self
    }

    /// A top-level key (`plane`, `title`), written before the tables.
    pub fn head(mut self, key: &str, value: impl Toml) -> Problem {
        self.head.push(format!("{key} = {}", value.toml()));
        self
    }

    /// `plane = "stress"` or `"strain"`.
    pub fn plane(self, plane: &str) -> Problem {
        self.head("plane", plane)
    }

    /// Starts a table with this header (`[analysis]`, `[[step]]`).
    pub fn table(mut self, header: &str) -> Problem {
        self.tables.push(Table {
            header: header.to_string(),
            lines: Vec::new(),
        });
        self
    }

    /// A key of the last table.
    pub fn key(mut self, key: &str, value: impl Toml) -> Problem {
        self.last_table()
            .lines
            .push(Line::Key(key.to_string(), value.toml()));
        self
    }

    /// Text written as given after the tables so far (supports, loads, the
    /// analysis of a test's own).
    pub fn raw(mut self, text: &str) -> Problem {
        self.tables.push(Table {
            header: String::new(),
            lines: vec![Line::Raw(text.to_string())],
        });
        self
    }

    /// `[materials.<name>]` with Young's modulus and Poisson's ratio.
    pub fn material(self, name: &str, e: f64, nu: f64) -> Problem {
        self.table(&format!("[materials.{name}]"))
            .key("E", e)
            .key("nu", nu)
    }

    /// A `[[part]]` of `material` (its mesh follows, e.g. [`Problem::rectangle`]).
    pub fn part(self, name: &str, material: &str) -> Problem {
        self.table("[[part]]")
            .key("name", name)
            .key("material", material)
    }

    /// The last part's mesh: a structured rectangle of T3 cells.
    pub fn rectangle(mut self, x: [f64; 2], y: [f64; 2], cells: [usize; 2]) -> Problem {
        self.last_table().lines.push(Line::Rect(Rect {
            x,
            y,
            cells,
            elements: None,
        }));
        self
    }

    /// The last part's mesh: a structured rectangle of `elements` ("q4", "t3").
    pub fn rectangle_of(
        self,
        x: [f64; 2],
        y: [f64; 2],
        cells: [usize; 2],
        elements: &str,
    ) -> Problem {
        let mut p = self.rectangle(x, y, cells);
        if let Some(Line::Rect(r)) = p.last_table().lines.last_mut() {
            r.elements = Some(elements.to_string());
        }
        p
    }

    /// The last part's mesh: an annulus sector about `center` (radii `r`,
    /// angles `theta` in degrees, `cells` radially and around) of `elements`
    /// ("q4", "t3").
    pub fn annulus(
        self,
        center: [f64; 2],
        r: [f64; 2],
        theta: [f64; 2],
        cells: [usize; 2],
        elements: &str,
    ) -> Problem {
        let mesh = format!(
            "{{ center = {}, r = {}, theta = {}, cells = {}, elements = \"{elements}\" }}",
            center.toml(),
            r.toml(),
            theta.toml(),
            cells.toml()
        );
        self.key("annulus", Raw(&mesh))
    }

    /// The cells of part `name`'s rectangle.
    pub fn cells(mut self, name: &str, cells: [usize; 2]) -> Problem {
        self.rect_of(name).cells = cells;
        self
    }

    /// An `[[interface]]`: `nodes`' `boundary` coupled to `host`.
    pub fn interface(self, host: &str, nodes: &str, boundary: &str) -> Problem {
        self.table("[[interface]]")
            .key("host", host)
            .key("nodes", nodes)
            .key("boundary", boundary)
    }

    /// A named `[[interface]]`.
    pub fn named_interface(self, name: &str, host: &str, nodes: &str, boundary: &str) -> Problem {
        self.table("[[interface]]")
            .key("name", name)
            .key("host", host)
            .key("nodes", nodes)
            .key("boundary", boundary)
    }

    /// The last interface's law.
    pub fn law(self, law: &str) -> Problem {
        self.iface_line(Line::Key("law".into(), law.toml()))
    }

    /// The last interface's friction coefficient.
    pub fn friction(self, mu: f64) -> Problem {
        self.iface_line(Line::Key("friction".into(), mu.toml()))
    }

    /// A key of the last interface.
    pub fn iface_key(self, key: &str, value: impl Toml) -> Problem {
        self.iface_line(Line::Key(key.to_string(), value.toml()))
    }

    /// Keys of the last interface written as given (nothing for "").
    pub fn iface(self, keys: &str) -> Problem {
        self.iface_line(Line::Raw(keys.to_string()))
    }

    /// A `[[support]]` fixing `fix` on `part`'s `boundary`.
    pub fn support<const N: usize>(self, part: &str, boundary: &str, fix: [&str; N]) -> Problem {
        self.table("[[support]]")
            .key("part", part)
            .key("boundary", boundary)
            .key("fix", fix)
    }

    /// A `[[support]]` fixing `fix` at `part`'s node at `at`.
    pub fn support_at<const N: usize>(self, part: &str, at: [f64; 2], fix: [&str; N]) -> Problem {
        self.table("[[support]]")
            .key("part", part)
            .key("at", at)
            .key("fix", fix)
    }

    /// The symmetry supports of a quarter annulus `part` (θ from 0 to 90°): its
    /// `start` edge (on the x axis) held in y, its `end` edge (on the y axis)
    /// in x.
    pub fn quarter_symmetry(self, part: &str) -> Problem {
        self.support(part, "start", ["y"])
            .support(part, "end", ["x"])
    }

    /// `part`'s bottom on rollers (y fixed) and its node at `at` held in x.
    pub fn rollers(self, part: &str, at: [f64; 2]) -> Problem {
        self.support(part, "bottom", ["y"])
            .support_at(part, at, ["x"])
    }

    /// A `[[load]]`: a pressure `p` on `part`'s `boundary`.
    pub fn pressure(self, part: &str, boundary: &str, p: f64) -> Problem {
        self.table("[[load]]")
            .key("part", part)
            .key("boundary", boundary)
            .key("pressure", p)
    }

    /// A `[[load]]`: `force` on `part`'s `boundary`.
    pub fn load(self, part: &str, boundary: &str, force: [f64; 2]) -> Problem {
        self.table("[[load]]")
            .key("part", part)
            .key("boundary", boundary)
            .key("force", force)
    }

    /// `[analysis]` with its number of increments.
    pub fn increments(self, n: usize) -> Problem {
        self.table("[analysis]").key("increments", n)
    }

    /// The problem text.
    pub fn text(&self) -> String {
        let mut s = String::new();
        if self.leading_newline {
            s.push('\n');
        }
        for h in &self.head {
            s.push_str(h);
            s.push('\n');
        }
        for (i, t) in self.tables.iter().enumerate() {
            if self.spaced && i > 0 {
                s.push('\n');
            }
            if !t.header.is_empty() {
                s.push_str(&t.header);
                s.push('\n');
            }
            for line in &t.lines {
                match line {
                    Line::Key(k, v) => s.push_str(&format!("{k} = {v}")),
                    Line::Rect(r) => s.push_str(&format!("rectangle = {}", r.toml())),
                    Line::Raw(text) => s.push_str(text),
                }
                if !s.ends_with('\n') {
                    s.push('\n');
                }
            }
        }
        s
    }

    fn last_table(&mut self) -> &mut Table {
        self.tables.last_mut().expect("a table to add the key to")
    }

    fn iface_line(mut self, line: Line) -> Problem {
        let t = self
            .tables
            .iter_mut()
            .rev()
            .find(|t| t.header == "[[interface]]")
            .expect("an interface");
        t.lines.push(line);
        self
    }

    fn rect_of(&mut self, name: &str) -> &mut Rect {
        let quoted = name.toml();
        let is_named = |l: &Line| matches!(l, Line::Key(k, v) if k == "name" && *v == quoted);
        self.tables
            .iter_mut()
            .filter(|t| t.header == "[[part]]" && t.lines.iter().any(is_named))
            .flat_map(|t| t.lines.iter_mut())
            .find_map(|l| match l {
                Line::Rect(r) => Some(r),
                _ => None,
            })
            .expect("a rectangle part of that name")
    }

    // ---------------------------------------------------------- the problems

    /// A unit block (node part, x ∈ [0, 1], y ∈ [0, 1], 4 × 4 cells) on a wider
    /// base (host, x ∈ [−0.5, 1.5], y ∈ [−1, 0], 5 × 3 cells), non-matching
    /// meshes, both steel (E = 1000, ν = 0.3), plane stress, the block's bottom
    /// on the base through an interface (its keys follow: [`Problem::law`]), the
    /// base's bottom clamped.
    pub fn block_on_base() -> Problem {
        Problem::compact()
            .plane("stress")
            .material("steel", 1000.0, 0.3)
            .part("base", "steel")
            .rectangle([-0.5, 1.5], [-1.0, 0.0], [5, 3])
            .part("block", "steel")
            .rectangle([0.0, 1.0], [0.0, 1.0], [4, 4])
            .interface("base", "block", "bottom")
            .support("base", "bottom", ["x", "y"])
    }

    /// [`Problem::block_on_base`] with the Coulomb law (friction `mu`), pressed
    /// by P = 1 on its top while the top is pushed sideways by 0.005, far beyond
    /// the elastic range, over `increments` increments.
    pub fn coulomb_block_pushed_far(mu: f64, increments: usize) -> Problem {
        Problem::block_on_base()
            .law("coulomb")
            .friction(mu)
            .support("block", "top", ["x"])
            .key("value", [0.005, 0.0])
            .load("block", "top", [0.0, -1.0])
            .increments(increments)
    }

    /// A block (node part, soft: E = 1000, ν = 0.3; x ∈ [0, 1], height `h`, its
    /// bottom at `bottom`, 4 × 8 Q4) over a thin, stiff (E = 1e6) base layer
    /// (host, x ∈ [−0.5, 1.5], y ∈ [−0.1, 0], 5 × 1 Q4), plane stress, the block's
    /// bottom on the layer through an interface (its keys follow), the layer's
    /// bottom clamped.
    pub fn block_on_layer(bottom: f64, h: f64) -> Problem {
        Problem::compact()
            .plane("stress")
            .material("soft", 1000.0, 0.3)
            .material("hard", 1.0e6, 0.3)
            .part("base", "hard")
            .rectangle_of([-0.5, 1.5], [-0.1, 0.0], [5, 1], "q4")
            .part("block", "soft")
            .rectangle_of([0.0, 1.0], [bottom, bottom + h], [4, 8], "q4")
            .interface("base", "block", "bottom")
            .support("base", "bottom", ["x", "y"])
    }

    /// The seed's plate on a base (examples/plate_on_base.toml without its
    /// title, names, penalties and load): a steel plate (node part, x ∈ [30, 170],
    /// y ∈ [120, 135], 28 × 6 cells) on a steel base (host, x ∈ [0, 200],
    /// y ∈ [0, 120], 20 × 12 cells, its bottom clamped), E = 210000, ν = 0.31,
    /// the tables separated by empty lines.
    pub fn plate_on_base() -> Problem {
        Problem::spaced()
            .material("steel", 210000.0, 0.31)
            .part("base", "steel")
            .rectangle([0.0, 200.0], [0.0, 120.0], [20, 12])
            .part("plate", "steel")
            .rectangle([30.0, 170.0], [120.0, 135.0], [28, 6])
            .interface("base", "plate", "bottom")
            .support("base", "bottom", ["x", "y"])
    }

    /// The seed's load on the plate of [`Problem::plate_on_base`]: 1500 down on
    /// its top's x ∈ [86, 114].
    pub fn plate_load_down(self) -> Problem {
        self.load_from_to("plate", [86.0, 135.0], [114.0, 135.0], [0.0, -1500.0])
    }

    /// A `[[load]]`: `force` on `part`'s top between `from` and `to`.
    pub fn load_from_to(
        self,
        part: &str,
        from: [f64; 2],
        to: [f64; 2],
        force: [f64; 2],
    ) -> Problem {
        self.table("[[load]]")
            .key("part", part)
            .key("boundary", "top")
            .key("from", from)
            .key("to", to)
            .key("force", force)
    }
}

/// A problem text built on first use, for a `static`: it reads as a `&str`
/// (`BASE.replace(…)`, `format!("{BASE}")`, `&BASE`).
pub struct Text(std::sync::LazyLock<String>);

impl Text {
    /// The text `make` returns.
    pub const fn new(make: fn() -> String) -> Text {
        Text(std::sync::LazyLock::new(make))
    }
}

impl std::ops::Deref for Text {
    type Target = str;
    fn deref(&self) -> &str {
        &self.0
    }
}

impl std::fmt::Display for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

// ------------------------------------------------------------------ run folders

/// The `summary.json` of the run written to `out`.
pub fn summary_json(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// The VTU files in `out/vtu`, sorted (none when the folder does not exist).
pub fn vtu_files(out: &Path) -> Vec<String> {
    let mut v: Vec<String> = match std::fs::read_dir(out.join("vtu")) {
        Ok(d) => d
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    v.sort();
    v
}

/// The number of files `pvd` (the text of `out`'s `results.pvd`) names; each
/// must exist.
pub fn pvd_files_exist(out: &Path, pvd: &str) -> usize {
    let named: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    for f in &named {
        assert!(out.join(f).is_file(), "{f} named but missing");
    }
    named.len()
}
