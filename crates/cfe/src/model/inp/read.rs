//! The deck's cards interpreted: nodes, elements, sets, surfaces, materials,
//! sections, interactions, steps and the loads and boundary conditions of each
//! step, in the deck's own terms (ids, set names), each with its line. Every
//! keyword, parameter and option outside the subset is refused here, with its
//! line; [`super::convert`] turns the result into cfe's model.

use super::keywords;
use super::lexer::{Card, Data, Deck, Loc, Param};
use super::{DeckFault, MAX_ABS};
use crate::error::Result;
use crate::fem::PlaneKind;
use crate::mesh::ElementKind;
use std::collections::{BTreeMap, HashMap};

/// An element: its type, its corner nodes (deck ids, in the deck's order) and
/// its plane kind (CPS: stress, CPE: strain, CAX: axisymmetric).
#[derive(Debug, Clone)]
pub struct Elem {
    pub kind: ElementKind,
    pub plane: PlaneKind,
    pub nodes: Vec<u64>,
    pub loc: Loc,
}

/// A `*MATERIAL` with its `*ELASTIC` constants.
#[derive(Debug, Clone)]
pub struct Material {
    pub name: String,
    pub elastic: Option<(f64, f64, Loc)>,
    pub loc: Loc,
}

/// A `*SOLID SECTION`: an element set with a material and a thickness.
#[derive(Debug, Clone)]
pub struct Section {
    /// The element set as written (the part's name).
    pub name: String,
    pub elset: String,
    pub material: String,
    pub thickness: f64,
    pub loc: Loc,
}

/// What a `*SURFACE` holds.
#[derive(Debug, Clone)]
pub enum SurfaceKind {
    /// Element faces: (element id, face k, 0-based: corners k and k + 1).
    Faces(Vec<(u64, usize)>),
    /// Nodes (deck ids).
    Nodes(Vec<u64>),
}

/// A `*SURFACE`.
#[derive(Debug, Clone)]
pub struct Surface {
    pub name: String,
    pub kind: SurfaceKind,
    pub loc: Loc,
}

/// `*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=…`.
#[derive(Debug, Clone, Copy)]
pub enum Behavior {
    /// LINEAR: the slope of the contact pressure against the overclosure.
    Linear(f64),
    /// HARD: no slope given (cfe's default penalty).
    Hard,
}

/// `*FRICTION`: μ and the stick slope (shear stress per slip), or ROUGH.
#[derive(Debug, Clone, Copy)]
pub struct Friction {
    pub mu: f64,
    pub stick_slope: Option<f64>,
    pub rough: bool,
}

/// A `*SURFACE INTERACTION` with its sub-options.
#[derive(Debug, Clone)]
pub struct Interaction {
    pub behavior: Option<Behavior>,
    pub friction: Option<Friction>,
    pub loc: Loc,
}

/// A `*CONTACT PAIR` line or a `*TIE` line: slave and master surfaces.
#[derive(Debug, Clone)]
pub struct Pair {
    /// The interaction's name (upper-case); `None` for a tie.
    pub interaction: Option<String>,
    /// The tie's NAME, if any.
    pub tie_name: Option<String>,
    /// SURFACE TO SURFACE (cfe's segment coupling) rather than NODE TO SURFACE.
    pub segment: bool,
    pub slave: String,
    pub master: String,
    pub loc: Loc,
}

/// A `*STEP` with the increments of its `*STATIC`.
#[derive(Debug, Clone)]
pub struct StepDef {
    pub name: String,
    pub increments: Option<usize>,
    pub loc: Loc,
}

/// Nodes or elements a load line names: the ids and the label (the set's name
/// as written, or `N<id>`/`E<id>`).
#[derive(Debug, Clone)]
pub struct Target {
    pub ids: Vec<u64>,
    pub label: String,
}

/// A `*BOUNDARY` line: the nodes, the components (0: x, 1: y) with their values.
#[derive(Debug, Clone)]
pub struct BoundaryLine {
    pub target: Target,
    pub dofs: Vec<(usize, f64)>,
    /// The step (0-based; the model data before the first *STEP count as step 0).
    pub step: usize,
    pub loc: Loc,
}

/// A `*CLOAD` line.
#[derive(Debug, Clone)]
pub struct CloadLine {
    pub target: Target,
    pub dof: Option<usize>,
    pub value: f64,
    pub step: usize,
    pub card: Loc,
    pub loc: Loc,
}

/// A `*DLOAD` line: a pressure on face `face` of the elements.
#[derive(Debug, Clone)]
pub struct DloadLine {
    pub target: Target,
    pub face: usize,
    pub value: f64,
    pub step: usize,
    pub card: Loc,
    pub loc: Loc,
}

/// Which keyword the sub-options (`*ELASTIC`, `*FRICTION`, …) belong to.
#[derive(Debug, Clone, PartialEq)]
enum Context {
    None,
    Material(String),
    Interaction(String),
}

/// The deck read into its own terms.
#[derive(Debug)]
pub struct Read<'d> {
    pub deck: &'d Deck,
    pub title: Option<String>,
    pub nodes: BTreeMap<u64, ([f64; 2], Loc)>,
    pub elements: BTreeMap<u64, Elem>,
    pub nsets: HashMap<String, Vec<u64>>,
    pub elsets: HashMap<String, Vec<u64>>,
    pub surfaces: HashMap<String, Surface>,
    pub materials: HashMap<String, Material>,
    pub sections: Vec<Section>,
    pub interactions: HashMap<String, Interaction>,
    pub pairs: Vec<Pair>,
    pub steps: Vec<StepDef>,
    pub boundaries: Vec<BoundaryLine>,
    pub cloads: Vec<CloadLine>,
    pub dloads: Vec<DloadLine>,
    /// The keywords accepted and ignored, with their lines and why.
    pub ignored: Vec<String>,
    /// The notes on how the deck was mapped (e.g. a HARD contact's penalty).
    pub notes: Vec<String>,
    in_step: bool,
    context: Context,
}

/// `*KEY` for messages.
fn star(k: &str) -> String {
    format!("*{k}")
}

impl<'d> Read<'d> {
    /// Reads every card of `deck`.
    pub fn new(deck: &'d Deck) -> Result<Read<'d>> {
        let mut r = Read {
            deck,
            title: None,
            nodes: BTreeMap::new(),
            elements: BTreeMap::new(),
            nsets: HashMap::new(),
            elsets: HashMap::new(),
            surfaces: HashMap::new(),
            materials: HashMap::new(),
            sections: Vec::new(),
            interactions: HashMap::new(),
            pairs: Vec::new(),
            steps: Vec::new(),
            boundaries: Vec::new(),
            cloads: Vec::new(),
            dloads: Vec::new(),
            ignored: Vec::new(),
            notes: Vec::new(),
            in_step: false,
            context: Context::None,
        };
        for card in &deck.cards {
            r.card(card)?;
        }
        if r.in_step {
            let s = r
                .steps
                .last()
                .map(|s| s.loc)
                .unwrap_or(Loc { file: 0, line: 1 });
            return Err(r
                .deck
                .error(s, "*STEP", DeckFault::Malformed, "has no *END STEP".into()));
        }
        Ok(r)
    }

    fn err(&self, loc: Loc, keyword: &str, fault: DeckFault, message: String) -> crate::Error {
        self.deck.error(loc, keyword, fault, message)
    }

    /// The card's parameters, refusing any not in `allowed`.
    fn params<'c>(
        &self,
        card: &'c Card,
        allowed: &[&str],
    ) -> Result<HashMap<&'c str, Option<&'c str>>> {
        let mut out = HashMap::new();
        for Param { name, value } in &card.params {
            if !allowed.contains(&name.as_str()) {
                let reads = if allowed.is_empty() {
                    "it takes no parameters".to_string()
                } else {
                    format!("it reads {}", allowed.join(", "))
                };
                return Err(self.err(
                    card.loc,
                    &star(&card.keyword),
                    DeckFault::Unsupported,
                    format!("has parameter {name}, which cfe does not support ({reads})"),
                ));
            }
            out.insert(name.as_str(), value.as_deref());
        }
        Ok(out)
    }

    /// A parameter that must have a non-empty value.
    fn required<'c>(
        &self,
        card: &Card,
        p: &HashMap<&str, Option<&'c str>>,
        name: &str,
    ) -> Result<&'c str> {
        match p.get(name) {
            Some(Some(v)) if !v.is_empty() => Ok(v),
            _ => Err(self.err(
                card.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                format!("needs {name}=…"),
            )),
        }
    }

    fn no_data(&self, card: &Card) -> Result<()> {
        match card.data.first() {
            Some(d) => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                format!("takes no data lines (found `{}`)", d.fields.join(", ")),
            )),
            None => Ok(()),
        }
    }

    /// Field `i` of a data line as a finite number of magnitude ≤ [`MAX_ABS`]
    /// (Fortran's `1.5D3` read as 1.5e3).
    fn num(&self, card: &Card, d: &Data, i: usize, what: &str) -> Result<f64> {
        let f = d.fields.get(i).map(|s| s.as_str()).unwrap_or("");
        let v: Option<f64> = f.replace(['d', 'D'], "e").parse().ok();
        match v {
            Some(v) if v.is_finite() && v.abs() <= MAX_ABS => Ok(v),
            _ => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                format!(
                    "needs {what} as field {} (a finite number of magnitude at most {MAX_ABS:e}), found `{f}`",
                    i + 1
                ),
            )),
        }
    }

    /// Field `i` as an optional number (absent or empty: `None`).
    fn opt_num(&self, card: &Card, d: &Data, i: usize, what: &str) -> Result<Option<f64>> {
        match d.fields.get(i) {
            None => Ok(None),
            Some(f) if f.is_empty() => Ok(None),
            Some(_) => self.num(card, d, i, what).map(Some),
        }
    }

    /// Field `i` as a positive integer id.
    fn id(&self, card: &Card, d: &Data, i: usize, what: &str) -> Result<u64> {
        let f = d.fields.get(i).map(|s| s.as_str()).unwrap_or("");
        match f.parse::<u64>() {
            Ok(v) if v > 0 => Ok(v),
            _ => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                format!(
                    "needs {what} as field {} (a positive integer), found `{f}`",
                    i + 1
                ),
            )),
        }
    }

    fn fields_at_most(&self, card: &Card, d: &Data, n: usize, what: &str) -> Result<()> {
        if d.fields.len() > n {
            return Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                format!(
                    "has {} fields, more than the {n} it takes ({what})",
                    d.fields.len()
                ),
            ));
        }
        Ok(())
    }

    /// The nodes a field names: a node id or a node set.
    fn node_target(&self, card: &Card, d: &Data) -> Result<Target> {
        let f = d.fields.first().map(|s| s.as_str()).unwrap_or("");
        if f.chars().next().is_some_and(|c| c.is_ascii_digit()) {
            let id = self.id(card, d, 0, "a node number or a node set")?;
            if !self.nodes.contains_key(&id) {
                return Err(self.err(
                    d.loc,
                    &star(&card.keyword),
                    DeckFault::Undefined,
                    format!("names node {id}, which no *NODE defines"),
                ));
            }
            return Ok(Target {
                ids: vec![id],
                label: format!("N{id}"),
            });
        }
        match self.nsets.get(&f.to_uppercase()) {
            Some(ids) => Ok(Target {
                ids: ids.clone(),
                label: f.to_string(),
            }),
            None if f.is_empty() => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                "needs a node number or a node set as its first field".into(),
            )),
            None => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Undefined,
                format!("names node set {f}, which no *NSET (or NSET= of *NODE) defines"),
            )),
        }
    }

    /// The elements a field names: an element id or an element set.
    fn elem_target(&self, card: &Card, d: &Data) -> Result<Target> {
        let f = d.fields.first().map(|s| s.as_str()).unwrap_or("");
        if f.chars().next().is_some_and(|c| c.is_ascii_digit()) {
            let id = self.id(card, d, 0, "an element number or an element set")?;
            if !self.elements.contains_key(&id) {
                return Err(self.err(
                    d.loc,
                    &star(&card.keyword),
                    DeckFault::Undefined,
                    format!("names element {id}, which no *ELEMENT defines"),
                ));
            }
            return Ok(Target {
                ids: vec![id],
                label: format!("E{id}"),
            });
        }
        match self.elsets.get(&f.to_uppercase()) {
            Some(ids) => Ok(Target {
                ids: ids.clone(),
                label: f.to_string(),
            }),
            None => Err(self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Undefined,
                format!("names element set `{f}`, which no *ELSET (or ELSET= of *ELEMENT) defines"),
            )),
        }
    }

    /// The current step's index, for a load keyword (which must be in a step
    /// unless `model_data_ok`).
    fn step_index(&self, card: &Card, model_data_ok: bool) -> Result<usize> {
        if self.in_step {
            Ok(self.steps.len() - 1)
        } else if model_data_ok {
            Ok(0)
        } else {
            Err(self.err(
                card.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                "must be inside a *STEP … *END STEP".into(),
            ))
        }
    }

    /// OP= and AMPLITUDE= of a load keyword: OP=NEW (which removes the earlier
    /// steps' loads) is refused after the first step.
    fn load_params(&self, card: &Card, extra: &[&str]) -> Result<()> {
        let mut allowed = vec!["OP", "AMPLITUDE"];
        allowed.extend_from_slice(extra);
        let p = self.params(card, &allowed)?;
        let kw = star(&card.keyword);
        if p.contains_key("AMPLITUDE") {
            return Err(self.err(
                card.loc,
                &kw,
                DeckFault::Unsupported,
                format!(
                    "has AMPLITUDE=, which is not supported: {}",
                    keywords::refused("AMPLITUDE")
                ),
            ));
        }
        if let Some(op) = p.get("OP")
            && !op.is_some_and(|v| v.eq_ignore_ascii_case("MOD") || v.eq_ignore_ascii_case("NEW"))
        {
            return Err(self.err(
                card.loc,
                &kw,
                DeckFault::Malformed,
                "has OP= other than MOD or NEW".into(),
            ));
        }
        if matches!(p.get("OP"), Some(Some(v)) if v.eq_ignore_ascii_case("NEW"))
            && self.steps.len() > 1
        {
            return Err(self.err(
                card.loc,
                &kw,
                DeckFault::Unsupported,
                "has OP=NEW after the first step, which removes the earlier steps' loads: cfe keeps them (a step's loads ramp from their earlier values; unloading by removal is not supported)".into(),
            ));
        }
        Ok(())
    }

    fn card(&mut self, card: &Card) -> Result<()> {
        let kw = card.keyword.as_str();
        // Sub-options belong to the keyword before them.
        let sub = matches!(
            kw,
            "ELASTIC"
                | "DENSITY"
                | "EXPANSION"
                | "CONDUCTIVITY"
                | "SPECIFIC HEAT"
                | "SURFACE BEHAVIOR"
                | "FRICTION"
        );
        if !sub {
            self.context = Context::None;
        }
        if let Some(why) = keywords::ignored(kw) {
            let file = &self.deck.files[card.loc.file];
            self.ignored.push(format!(
                "*{kw} at {}:{} ignored: {why}",
                file.display(),
                card.loc.line
            ));
            return Ok(());
        }
        match kw {
            "HEADING" => {
                self.params(card, &[])?;
                self.title = card.data.first().map(|d| d.fields.join(", "));
            }
            "NODE" => self.node(card)?,
            "ELEMENT" => self.element(card)?,
            "NSET" | "ELSET" => self.set(card)?,
            "SURFACE" => self.surface(card)?,
            "MATERIAL" => {
                let p = self.params(card, &["NAME"])?;
                let name = self.required(card, &p, "NAME")?.to_string();
                self.no_data(card)?;
                let key = name.to_uppercase();
                if self.materials.contains_key(&key) {
                    return Err(self.err(
                        card.loc,
                        "*MATERIAL",
                        DeckFault::Conflict,
                        format!("defines material {name} a second time"),
                    ));
                }
                self.materials.insert(
                    key.clone(),
                    Material {
                        name,
                        elastic: None,
                        loc: card.loc,
                    },
                );
                self.context = Context::Material(key);
            }
            "ELASTIC" => self.elastic(card)?,
            "SOLID SECTION" => self.section(card)?,
            "STEP" => self.step(card)?,
            "STATIC" => self.static_(card)?,
            "END STEP" => {
                self.params(card, &[])?;
                if !self.in_step {
                    return Err(self.err(
                        card.loc,
                        "*END STEP",
                        DeckFault::Malformed,
                        "has no *STEP to end".into(),
                    ));
                }
                let s = self.steps.last().expect("in a step");
                if s.increments.is_none() {
                    return Err(self.err(
                        card.loc,
                        "*END STEP",
                        DeckFault::Malformed,
                        format!(
                            "ends step {} (line {}) without a *STATIC procedure: cfe solves static steps",
                            s.name, s.loc.line
                        ),
                    ));
                }
                self.in_step = false;
            }
            "BOUNDARY" => self.boundary(card)?,
            "CLOAD" => self.cload(card)?,
            "DLOAD" => self.dload(card)?,
            "CONTACT PAIR" => {
                let p = self.params(card, &["INTERACTION", "TYPE", "SMALL SLIDING"])?;
                let interaction = self.required(card, &p, "INTERACTION")?.to_uppercase();
                let segment = match p.get("TYPE").map(|v| v.map(super::lexer::normalize)) {
                    None | Some(None) => false,
                    Some(Some(t)) if t == "NODE TO SURFACE" => false,
                    Some(Some(t)) if t == "SURFACE TO SURFACE" => true,
                    Some(Some(t)) => {
                        return Err(self.err(
                            card.loc,
                            "*CONTACT PAIR",
                            DeckFault::Unsupported,
                            format!(
                                "has TYPE={t}: cfe reads NODE TO SURFACE and SURFACE TO SURFACE"
                            ),
                        ));
                    }
                };
                self.pair_lines(card, Some(interaction), None, segment)?;
            }
            "TIE" => {
                let p = self.params(card, &["NAME", "ADJUST", "TYPE"])?;
                if matches!(p.get("ADJUST"), Some(Some(v)) if v.eq_ignore_ascii_case("NO")) {
                    return Err(self.err(
                        card.loc,
                        "*TIE",
                        DeckFault::Unsupported,
                        "has ADJUST=NO: cfe always moves a tie's slave nodes onto the master face"
                            .into(),
                    ));
                }
                let name = p.get("NAME").and_then(|v| v.map(|s| s.to_string()));
                self.pair_lines(card, None, name, false)?;
            }
            "SURFACE INTERACTION" => {
                let p = self.params(card, &["NAME"])?;
                let name = self.required(card, &p, "NAME")?.to_uppercase();
                if let Some(d) = card.data.first() {
                    return Err(self.err(
                        d.loc,
                        "*SURFACE INTERACTION",
                        DeckFault::Unsupported,
                        "has a data line (an out-of-plane thickness): cfe takes the thickness from *SOLID SECTION; remove the line".into(),
                    ));
                }
                if self.interactions.contains_key(&name) {
                    return Err(self.err(
                        card.loc,
                        "*SURFACE INTERACTION",
                        DeckFault::Conflict,
                        format!("defines interaction {name} a second time"),
                    ));
                }
                self.interactions.insert(
                    name.clone(),
                    Interaction {
                        behavior: None,
                        friction: None,
                        loc: card.loc,
                    },
                );
                self.context = Context::Interaction(name);
            }
            "SURFACE BEHAVIOR" => self.behavior(card)?,
            "FRICTION" => self.friction(card)?,
            _ => {
                let why = keywords::refused(kw);
                return Err(self.err(
                    card.loc,
                    &star(kw),
                    DeckFault::Unsupported,
                    format!("is not supported: {why}"),
                ));
            }
        }
        Ok(())
    }

    fn node(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["NSET"])?;
        let set = p.get("NSET").copied().flatten().map(|s| s.to_uppercase());
        let mut ids = Vec::with_capacity(card.data.len());
        for d in &card.data {
            self.fields_at_most(card, d, 4, "number, x, y, z")?;
            let id = self.id(card, d, 0, "the node number")?;
            let x = self.num(card, d, 1, "x")?;
            let y = self.opt_num(card, d, 2, "y")?.unwrap_or(0.0);
            let z = self.opt_num(card, d, 3, "z")?.unwrap_or(0.0);
            if z != 0.0 {
                return Err(self.err(
                    d.loc,
                    "*NODE",
                    DeckFault::Unsupported,
                    format!("gives node {id} z = {z}: cfe is two-dimensional (plane elements lie in z = 0)"),
                ));
            }
            if let Some((_, first)) = self.nodes.insert(id, ([x, y], d.loc)) {
                return Err(self.err(
                    d.loc,
                    "*NODE",
                    DeckFault::Conflict,
                    format!(
                        "defines node {id} a second time (first at line {})",
                        first.line
                    ),
                ));
            }
            ids.push(id);
        }
        if let Some(set) = set {
            self.nsets.entry(set).or_default().extend(ids);
        }
        Ok(())
    }

    fn element(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["TYPE", "ELSET"])?;
        let t = self.required(card, &p, "TYPE")?.to_uppercase();
        let (kind, plane) = match t.as_str() {
            "CPS3" => (ElementKind::T3, PlaneKind::Stress),
            "CPE3" => (ElementKind::T3, PlaneKind::Strain),
            "CPS4" => (ElementKind::Q4, PlaneKind::Stress),
            "CPE4" => (ElementKind::Q4, PlaneKind::Strain),
            "CAX3" => (ElementKind::T3, PlaneKind::Axisymmetric),
            "CAX4" => (ElementKind::Q4, PlaneKind::Axisymmetric),
            "CPS4R" | "CPE4R" => {
                return Err(self.err(
                    card.loc,
                    "*ELEMENT",
                    DeckFault::Unsupported,
                    format!("has TYPE={t} (reduced integration with hourglass control), which is not supported: cfe's Q4 is fully integrated (2×2), as CPS4/CPE4"),
                ));
            }
            _ => {
                return Err(self.err(
                    card.loc,
                    "*ELEMENT",
                    DeckFault::Unsupported,
                    format!("has TYPE={t}, which is not supported: cfe reads CPS3, CPE3, CPS4, CPE4 (linear plane triangles and quadrilaterals) and CAX3, CAX4 (axisymmetric)"),
                ));
            }
        };
        let corners = match kind {
            ElementKind::T3 => 3,
            ElementKind::Q4 => 4,
        };
        let set = p.get("ELSET").copied().flatten().map(|s| s.to_uppercase());
        let mut ids = Vec::with_capacity(card.data.len());
        let mut lines = card.data.iter();
        while let Some(first) = lines.next() {
            // A line ending with a comma continues on the next.
            let mut d = first.clone();
            let mut last = first;
            while last.continued {
                match lines.next() {
                    Some(next) => {
                        d.fields.extend(next.fields.iter().cloned());
                        last = next;
                    }
                    None => break,
                }
            }
            if d.fields.len() != corners + 1 {
                return Err(self.err(
                    d.loc,
                    "*ELEMENT",
                    DeckFault::Malformed,
                    format!(
                        "has {} fields; a {t} element takes its number and {corners} nodes",
                        d.fields.len()
                    ),
                ));
            }
            let id = self.id(card, &d, 0, "the element number")?;
            let nodes = (1..=corners)
                .map(|i| self.id(card, &d, i, "a node number"))
                .collect::<Result<Vec<u64>>>()?;
            let el = Elem {
                kind,
                plane,
                nodes,
                loc: d.loc,
            };
            if let Some(first) = self.elements.insert(id, el) {
                return Err(self.err(
                    d.loc,
                    "*ELEMENT",
                    DeckFault::Conflict,
                    format!(
                        "defines element {id} a second time (first at line {})",
                        first.loc.line
                    ),
                ));
            }
            ids.push(id);
        }
        if let Some(set) = set {
            self.elsets.entry(set).or_default().extend(ids);
        }
        Ok(())
    }

    fn set(&mut self, card: &Card) -> Result<()> {
        let node = card.keyword == "NSET";
        let key = if node { "NSET" } else { "ELSET" };
        let p = self.params(card, &[key, "GENERATE", "UNSORTED", "INTERNAL"])?;
        let name = self.required(card, &p, key)?.to_uppercase();
        let generate = p.contains_key("GENERATE");
        let mut ids: Vec<u64> = Vec::new();
        for d in &card.data {
            if generate {
                self.fields_at_most(card, d, 3, "start, end, increment")?;
                let a = self.id(card, d, 0, "the first number")?;
                let b = self.id(card, d, 1, "the last number")?;
                let inc = if d.fields.get(2).is_some_and(|f| !f.is_empty()) {
                    self.id(card, d, 2, "the increment")?
                } else {
                    1
                };
                if b < a {
                    return Err(self.err(
                        d.loc,
                        &star(&card.keyword),
                        DeckFault::Malformed,
                        format!("GENERATE runs from {a} down to {b}: the last number must not be below the first"),
                    ));
                }
                // Only defined ids are taken, so the work is bounded by the
                // deck's size, not by the range.
                let defined: Vec<u64> = if node {
                    self.nodes.range(a..=b).map(|(k, _)| *k).collect()
                } else {
                    self.elements.range(a..=b).map(|(k, _)| *k).collect()
                };
                ids.extend(defined.into_iter().filter(|k| (k - a) % inc == 0));
                continue;
            }
            for (i, f) in d.fields.iter().enumerate() {
                if f.is_empty() {
                    continue;
                }
                if f.chars().next().is_some_and(|c| c.is_ascii_digit()) {
                    let id = self.id(card, d, i, "a number")?;
                    let known = if node {
                        self.nodes.contains_key(&id)
                    } else {
                        self.elements.contains_key(&id)
                    };
                    if !known {
                        let (what, by) = if node {
                            ("node", "*NODE")
                        } else {
                            ("element", "*ELEMENT")
                        };
                        return Err(self.err(
                            d.loc,
                            &star(&card.keyword),
                            DeckFault::Undefined,
                            format!("names {what} {id}, which no {by} before it defines"),
                        ));
                    }
                    ids.push(id);
                } else {
                    let sets = if node { &self.nsets } else { &self.elsets };
                    match sets.get(&f.to_uppercase()) {
                        Some(members) => ids.extend(members.iter().copied()),
                        None => {
                            return Err(self.err(
                                d.loc,
                                &star(&card.keyword),
                                DeckFault::Undefined,
                                format!("names set `{f}`, which is not defined before it"),
                            ));
                        }
                    }
                }
            }
        }
        let set = if node {
            &mut self.nsets
        } else {
            &mut self.elsets
        };
        set.entry(name).or_default().extend(ids);
        Ok(())
    }

    fn surface(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["NAME", "TYPE"])?;
        let name = self.required(card, &p, "NAME")?.to_string();
        let nodes = match p.get("TYPE").copied().flatten().map(|s| s.to_uppercase()) {
            None => false,
            Some(t) if t == "ELEMENT" => false,
            Some(t) if t == "NODE" => true,
            Some(t) => {
                return Err(self.err(
                    card.loc,
                    "*SURFACE",
                    DeckFault::Unsupported,
                    format!("has TYPE={t}: cfe reads TYPE=ELEMENT (element faces) and TYPE=NODE"),
                ));
            }
        };
        let mut kind = if nodes {
            SurfaceKind::Nodes(Vec::new())
        } else {
            SurfaceKind::Faces(Vec::new())
        };
        for d in &card.data {
            match &mut kind {
                SurfaceKind::Nodes(list) => {
                    self.fields_at_most(card, d, 1, "a node or a node set")?;
                    list.extend(self.node_target(card, d)?.ids);
                }
                SurfaceKind::Faces(list) => {
                    self.fields_at_most(
                        card,
                        d,
                        2,
                        "an element or element set, and a face S1 to S4",
                    )?;
                    let t = self.elem_target(card, d)?;
                    let label = d
                        .fields
                        .get(1)
                        .map(|s| s.to_uppercase())
                        .unwrap_or_default();
                    let face = self.face(card, d, &label, 'S')?;
                    for id in t.ids {
                        list.push((id, face));
                    }
                }
            }
        }
        let key = name.to_uppercase();
        if self.surfaces.contains_key(&key) {
            return Err(self.err(
                card.loc,
                "*SURFACE",
                DeckFault::Conflict,
                format!("defines surface {name} a second time"),
            ));
        }
        self.surfaces.insert(
            key,
            Surface {
                name,
                kind,
                loc: card.loc,
            },
        );
        Ok(())
    }

    /// A face label `S1`…`S4` (`P1`…`P4` for *DLOAD): face k joins corners k
    /// and k + 1 (the last joins back to the first), as Abaqus numbers the
    /// edges of plane elements. 0-based.
    fn face(&self, card: &Card, d: &Data, label: &str, letter: char) -> Result<usize> {
        let k = label
            .strip_prefix(letter)
            .and_then(|k| k.parse::<usize>().ok())
            .filter(|k| (1..=4).contains(k));
        k.map(|k| k - 1).ok_or_else(|| {
            self.err(
                d.loc,
                &star(&card.keyword),
                DeckFault::Unsupported,
                format!(
                    "has face label `{label}`: cfe reads {letter}1 to {letter}4 (face k joins the element's corners k and k + 1)"
                ),
            )
        })
    }

    fn elastic(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["TYPE"])?;
        if let Some(Some(t)) = p.get("TYPE")
            && !t.eq_ignore_ascii_case("ISO")
        {
            return Err(self.err(
                card.loc,
                "*ELASTIC",
                DeckFault::Unsupported,
                format!("has TYPE={t}: cfe's materials are isotropic (TYPE=ISO)"),
            ));
        }
        let Context::Material(m) = self.context.clone() else {
            return Err(self.err(
                card.loc,
                "*ELASTIC",
                DeckFault::Malformed,
                "must follow a *MATERIAL".into(),
            ));
        };
        let d = match card.data.as_slice() {
            [d] => d,
            [] => {
                return Err(self.err(
                    card.loc,
                    "*ELASTIC",
                    DeckFault::Malformed,
                    "needs a data line: E, ν".into(),
                ));
            }
            [_, d, ..] => {
                return Err(self.err(
                    d.loc,
                    "*ELASTIC",
                    DeckFault::Unsupported,
                    "has more than one data line (temperature-dependent constants): cfe reads one E and one ν".into(),
                ));
            }
        };
        if d.fields.len() > 2 && d.fields[2..].iter().any(|f| !f.is_empty()) {
            return Err(self.err(
                d.loc,
                "*ELASTIC",
                DeckFault::Unsupported,
                "gives a temperature (third field): cfe reads one E and one ν".into(),
            ));
        }
        let e = self.num(card, d, 0, "Young's modulus E")?;
        let nu = self.num(card, d, 1, "Poisson's ratio ν")?;
        if let Some(mat) = self.materials.get_mut(&m) {
            mat.elastic = Some((e, nu, d.loc));
        }
        Ok(())
    }

    fn section(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["ELSET", "MATERIAL"])?;
        let name = self.required(card, &p, "ELSET")?.to_string();
        let material = self.required(card, &p, "MATERIAL")?.to_uppercase();
        let thickness = match card.data.as_slice() {
            [] => 1.0,
            [d] => {
                self.fields_at_most(card, d, 1, "the thickness")?;
                self.opt_num(card, d, 0, "the thickness")?.unwrap_or(1.0)
            }
            [_, d, ..] => {
                return Err(self.err(
                    d.loc,
                    "*SOLID SECTION",
                    DeckFault::Malformed,
                    "has more than one data line (it takes one: the thickness)".into(),
                ));
            }
        };
        self.sections.push(Section {
            elset: name.to_uppercase(),
            name,
            material,
            thickness,
            loc: card.loc,
        });
        Ok(())
    }

    fn step(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["NAME", "NLGEOM", "INC", "AMPLITUDE"])?;
        if self.in_step {
            return Err(self.err(
                card.loc,
                "*STEP",
                DeckFault::Malformed,
                "starts a step inside another (the one before has no *END STEP)".into(),
            ));
        }
        match p.get("NLGEOM") {
            None => {}
            Some(Some(v)) if v.eq_ignore_ascii_case("NO") => {}
            Some(_) => {
                return Err(self.err(
                    card.loc,
                    "*STEP",
                    DeckFault::Unsupported,
                    "has NLGEOM: cfe is geometrically linear (small displacements)".into(),
                ));
            }
        }
        if let Some(a) = p.get("AMPLITUDE")
            && !a.is_some_and(|a| a.eq_ignore_ascii_case("RAMP"))
        {
            return Err(self.err(
                card.loc,
                "*STEP",
                DeckFault::Unsupported,
                "has AMPLITUDE other than RAMP: cfe ramps a step's loads linearly".into(),
            ));
        }
        if let Some(Some(inc)) = p.get("INC")
            && inc.parse::<u64>().is_err()
        {
            return Err(self.err(
                card.loc,
                "*STEP",
                DeckFault::Malformed,
                format!("has INC={inc}, not a positive integer"),
            ));
        }
        self.no_data(card)?;
        let name = match p.get("NAME").copied().flatten() {
            Some(n) => n.to_string(),
            None => format!("step-{}", self.steps.len() + 1),
        };
        self.steps.push(StepDef {
            name,
            increments: None,
            loc: card.loc,
        });
        self.in_step = true;
        Ok(())
    }

    fn static_(&mut self, card: &Card) -> Result<()> {
        self.params(card, &["DIRECT", "SOLVER"])?;
        if !self.in_step {
            return Err(self.err(
                card.loc,
                "*STATIC",
                DeckFault::Malformed,
                "must be inside a *STEP".into(),
            ));
        }
        if self.steps.last().is_some_and(|s| s.increments.is_some()) {
            return Err(self.err(
                card.loc,
                "*STATIC",
                DeckFault::Conflict,
                "is the step's second procedure".into(),
            ));
        }
        let increments = match card.data.as_slice() {
            [] => 1,
            [d] => {
                self.fields_at_most(
                    card,
                    d,
                    4,
                    "initial increment, time period, minimum, maximum",
                )?;
                let initial = self.opt_num(card, d, 0, "the initial increment")?;
                let period = self.opt_num(card, d, 1, "the time period")?.unwrap_or(1.0);
                match initial {
                    None => 1,
                    Some(i) if i > 0.0 && period > 0.0 => {
                        let n = period / i;
                        let max = super::super::check::MAX_INCREMENTS as f64;
                        if n > max {
                            return Err(self.err(
                                d.loc,
                                "*STATIC",
                                DeckFault::Unsupported,
                                format!("asks for {n:e} increments (time period {period} / initial increment {i}), more than cfe's {max:e}"),
                            ));
                        }
                        // Round-off in the ratio (1 / 0.1) is not an extra increment.
                        (n * (1.0 - 1e-9)).ceil().max(1.0) as usize
                    }
                    Some(_) => {
                        return Err(self.err(
                            d.loc,
                            "*STATIC",
                            DeckFault::Malformed,
                            format!("needs a positive initial increment and time period (found {}, {period})", initial.unwrap_or(0.0)),
                        ));
                    }
                }
            }
            [_, d, ..] => {
                return Err(self.err(
                    d.loc,
                    "*STATIC",
                    DeckFault::Malformed,
                    "has more than one data line".into(),
                ));
            }
        };
        if let Some(s) = self.steps.last_mut() {
            s.increments = Some(increments);
        }
        Ok(())
    }

    fn boundary(&mut self, card: &Card) -> Result<()> {
        self.load_params(card, &["TYPE"])?;
        if let Some(t) = card.params.iter().find(|p| p.name == "TYPE")
            && !t
                .value
                .as_deref()
                .is_some_and(|v| v.eq_ignore_ascii_case("DISPLACEMENT"))
        {
            return Err(self.err(
                card.loc,
                "*BOUNDARY",
                DeckFault::Unsupported,
                "has TYPE other than DISPLACEMENT: cfe prescribes displacements only".into(),
            ));
        }
        let step = self.step_index(card, true)?;
        for d in &card.data {
            self.fields_at_most(card, d, 4, "node or node set, first DOF, last DOF, value")?;
            let target = self.node_target(card, d)?;
            let second = d
                .fields
                .get(1)
                .map(|s| s.to_uppercase())
                .unwrap_or_default();
            let dofs: Vec<(usize, f64)> = match second.as_str() {
                "ENCASTRE" | "PINNED" => vec![(0, 0.0), (1, 0.0)],
                "XSYMM" => vec![(0, 0.0)],
                "YSYMM" => vec![(1, 0.0)],
                _ => {
                    let first = self.id(card, d, 1, "the first DOF")?;
                    let last = if d.fields.get(2).is_some_and(|f| !f.is_empty()) {
                        self.id(card, d, 2, "the last DOF")?
                    } else {
                        first
                    };
                    let value = self.opt_num(card, d, 3, "the value")?.unwrap_or(0.0);
                    if last < first || last > 3 {
                        return Err(self.err(
                            d.loc,
                            "*BOUNDARY",
                            DeckFault::Unsupported,
                            format!("holds DOFs {first} to {last}: cfe's nodes have DOFs 1 (x) and 2 (y) (3, z, is held by the plane elements)"),
                        ));
                    }
                    if last == 3 && value != 0.0 {
                        return Err(self.err(
                            d.loc,
                            "*BOUNDARY",
                            DeckFault::Unsupported,
                            format!("prescribes {value} on DOF 3 (z): cfe is two-dimensional"),
                        ));
                    }
                    (first..=last.min(2))
                        .map(|k| (k as usize - 1, value))
                        .collect()
                }
            };
            self.boundaries.push(BoundaryLine {
                target,
                dofs,
                step,
                loc: d.loc,
            });
        }
        Ok(())
    }

    fn cload(&mut self, card: &Card) -> Result<()> {
        self.load_params(card, &[])?;
        let step = self.step_index(card, false)?;
        for d in &card.data {
            self.fields_at_most(card, d, 3, "node or node set, DOF, magnitude")?;
            let target = self.node_target(card, d)?;
            let dof = self.id(card, d, 1, "the DOF")?;
            let value = self.num(card, d, 2, "the magnitude")?;
            let dof = match dof {
                1 | 2 => Some(dof as usize - 1),
                3 if value == 0.0 => None,
                _ => {
                    return Err(self.err(
                        d.loc,
                        "*CLOAD",
                        DeckFault::Unsupported,
                        format!("loads DOF {dof}: cfe's nodes take forces in DOFs 1 (x) and 2 (y)"),
                    ));
                }
            };
            self.cloads.push(CloadLine {
                target,
                dof,
                value,
                step,
                card: card.loc,
                loc: d.loc,
            });
        }
        Ok(())
    }

    fn dload(&mut self, card: &Card) -> Result<()> {
        self.load_params(card, &[])?;
        let step = self.step_index(card, false)?;
        for d in &card.data {
            self.fields_at_most(card, d, 3, "element or element set, load label, magnitude")?;
            let target = self.elem_target(card, d)?;
            let label = d
                .fields
                .get(1)
                .map(|s| s.to_uppercase())
                .unwrap_or_default();
            if !label.starts_with('P') || label.starts_with("PRESS") {
                return Err(self.err(
                    d.loc,
                    "*DLOAD",
                    DeckFault::Unsupported,
                    format!("has load label `{label}`: cfe reads face pressures P1 to P4 only (no body forces, gravity or centrifugal loads)"),
                ));
            }
            let face = self.face(card, d, &label, 'P')?;
            let value = self.num(card, d, 2, "the pressure")?;
            self.dloads.push(DloadLine {
                target,
                face,
                value,
                step,
                card: card.loc,
                loc: d.loc,
            });
        }
        Ok(())
    }

    fn pair_lines(
        &mut self,
        card: &Card,
        interaction: Option<String>,
        tie_name: Option<String>,
        segment: bool,
    ) -> Result<()> {
        if card.data.is_empty() {
            return Err(self.err(
                card.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                "needs a data line: slave surface, master surface".into(),
            ));
        }
        for d in &card.data {
            if d.fields.len() != 2 || d.fields.iter().any(|f| f.is_empty()) {
                return Err(self.err(
                    d.loc,
                    &star(&card.keyword),
                    DeckFault::Malformed,
                    format!(
                        "needs two fields, the slave surface and the master surface (found `{}`)",
                        d.fields.join(", ")
                    ),
                ));
            }
            for f in &d.fields {
                if !self.surfaces.contains_key(&f.to_uppercase()) {
                    return Err(self.err(
                        d.loc,
                        &star(&card.keyword),
                        DeckFault::Undefined,
                        format!("names surface {f}, which no *SURFACE before it defines"),
                    ));
                }
            }
            self.pairs.push(Pair {
                interaction: interaction.clone(),
                tie_name: tie_name.clone(),
                segment,
                slave: d.fields[0].to_uppercase(),
                master: d.fields[1].to_uppercase(),
                loc: d.loc,
            });
        }
        Ok(())
    }

    /// The interaction the sub-option `card` belongs to.
    fn interaction(&mut self, card: &Card) -> Result<&mut Interaction> {
        let Context::Interaction(name) = self.context.clone() else {
            return Err(self.err(
                card.loc,
                &star(&card.keyword),
                DeckFault::Malformed,
                "must follow a *SURFACE INTERACTION".into(),
            ));
        };
        Ok(self.interactions.get_mut(&name).expect("defined"))
    }

    fn behavior(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["PRESSURE-OVERCLOSURE"])?;
        let kind = self
            .required(card, &p, "PRESSURE-OVERCLOSURE")?
            .to_uppercase();
        let behavior = match kind.as_str() {
            "HARD" => {
                self.no_data(card)?;
                Behavior::Hard
            }
            "LINEAR" => {
                let d = match card.data.as_slice() {
                    [d] => d,
                    _ => {
                        return Err(self.err(
                            card.loc,
                            "*SURFACE BEHAVIOR",
                            DeckFault::Malformed,
                            "with PRESSURE-OVERCLOSURE=LINEAR needs one data line: the slope (pressure per overclosure)".into(),
                        ));
                    }
                };
                let k = self.num(card, d, 0, "the slope")?;
                for i in 1..d.fields.len() {
                    if self
                        .opt_num(card, d, i, "a value")?
                        .is_some_and(|v| v != 0.0)
                    {
                        return Err(self.err(
                            d.loc,
                            "*SURFACE BEHAVIOR",
                            DeckFault::Unsupported,
                            format!("gives field {} (a tension at large clearance or a clearance offset): cfe's open pairs carry no force; give the slope only", i + 1),
                        ));
                    }
                }
                if k <= 0.0 {
                    return Err(self.err(
                        d.loc,
                        "*SURFACE BEHAVIOR",
                        DeckFault::Malformed,
                        format!("gives the slope {k}: it must be positive"),
                    ));
                }
                Behavior::Linear(k)
            }
            _ => {
                return Err(self.err(
                    card.loc,
                    "*SURFACE BEHAVIOR",
                    DeckFault::Unsupported,
                    format!("has PRESSURE-OVERCLOSURE={kind}: cfe's contact is a linear penalty (LINEAR, or HARD with cfe's default penalty)"),
                ));
            }
        };
        self.interaction(card)?.behavior = Some(behavior);
        Ok(())
    }

    fn friction(&mut self, card: &Card) -> Result<()> {
        let p = self.params(card, &["ROUGH"])?;
        let friction = if p.contains_key("ROUGH") {
            self.no_data(card)?;
            Friction {
                mu: f64::INFINITY,
                stick_slope: None,
                rough: true,
            }
        } else {
            let d = match card.data.as_slice() {
                [d] => d,
                _ => {
                    return Err(self.err(
                        card.loc,
                        "*FRICTION",
                        DeckFault::Malformed,
                        "needs one data line: μ, stick slope".into(),
                    ));
                }
            };
            self.fields_at_most(card, d, 2, "μ, stick slope")?;
            let mu = self.num(card, d, 0, "the friction coefficient μ")?;
            let stick_slope = self.opt_num(card, d, 1, "the stick slope")?;
            if mu < 0.0 || stick_slope.is_some_and(|s| s <= 0.0) {
                return Err(self.err(
                    d.loc,
                    "*FRICTION",
                    DeckFault::Malformed,
                    "needs μ ≥ 0 and a positive stick slope".into(),
                ));
            }
            Friction {
                mu,
                stick_slope,
                rough: false,
            }
        };
        self.interaction(card)?.friction = Some(friction);
        Ok(())
    }
}
