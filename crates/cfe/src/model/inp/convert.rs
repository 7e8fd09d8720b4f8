//! The read deck ([`super::read::Read`]) turned into cfe's model: each
//! `*SOLID SECTION`'s element set a part (its mesh as arrays, its boundaries the
//! surfaces and loaded faces it carries), the parts, materials, interfaces and
//! steps written as the problem-file schema and built by the same builder as a
//! TOML problem (so every check and error is shared), then the supports and the
//! concentrated and pressure loads resolved to nodal values per step.

use super::lexer::Loc;
use super::read::{Behavior, Read, SurfaceKind};
use super::{DeckFault, InpModel};
use crate::domain::{Law, Load, Support};
use crate::error::{Error, Result};
use crate::fem::{PlaneKind, axisymmetric, loads};
use crate::mesh::{BoundarySelection, Element, ElementKind, Mesh};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// A part in the making: its section, elements (deck ids, sorted) and nodes
/// (deck ids, sorted: the local numbering).
struct PartDraft {
    name: String,
    section: usize,
    elements: Vec<u64>,
    nodes: Vec<u64>,
    boundaries: Vec<(String, BoundarySelection)>,
}

/// A TOML string literal.
fn quote(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A float as TOML (Rust's shortest round-trip form, always with `.` or `e`).
fn float(v: f64) -> String {
    format!("{v:?}")
}

/// The TOML text of the converted model with, per line, the deck line it
/// comes from (for the builder's errors).
#[derive(Default)]
struct Toml {
    text: String,
    lines: Vec<Option<Loc>>,
}

impl Toml {
    fn line(&mut self, loc: Option<Loc>, s: String) {
        self.text.push_str(&s);
        self.text.push('\n');
        self.lines.push(loc);
    }
}

/// The model of the read deck, its meshes refined `refine` times.
pub fn convert(read: &Read, refine: usize) -> Result<InpModel> {
    let deck = read.deck;
    let err = |loc: Loc, kw: &str, fault, msg: String| deck.error(loc, kw, fault, msg);
    if read.steps.is_empty() {
        let loc = deck
            .cards
            .last()
            .map(|c| c.loc)
            .unwrap_or(Loc { file: 0, line: 1 });
        return Err(err(
            loc,
            "*STEP",
            DeckFault::Malformed,
            "is missing: the deck has no *STEP … *STATIC … *END STEP, so nothing to solve".into(),
        ));
    }
    if read.sections.is_empty() {
        return Err(err(
            Loc { file: 0, line: 1 },
            "*SOLID SECTION",
            DeckFault::Malformed,
            "is missing: no element set is given a material, so the deck has no body".into(),
        ));
    }
    // Parts: one per section.
    let mut elem_part: HashMap<u64, usize> = HashMap::new();
    let mut drafts: Vec<PartDraft> = Vec::with_capacity(read.sections.len());
    for (s, sec) in read.sections.iter().enumerate() {
        let Some(set) = read.elsets.get(&sec.elset) else {
            return Err(err(
                sec.loc,
                "*SOLID SECTION",
                DeckFault::Undefined,
                format!("names element set {}, which is not defined", sec.name),
            ));
        };
        match read.materials.get(&sec.material) {
            None => {
                return Err(err(
                    sec.loc,
                    "*SOLID SECTION",
                    DeckFault::Undefined,
                    format!(
                        "names material {}, which no *MATERIAL defines",
                        sec.material
                    ),
                ));
            }
            Some(m) if m.elastic.is_none() => {
                return Err(err(
                    m.loc,
                    "*MATERIAL",
                    DeckFault::Malformed,
                    format!("{} has no *ELASTIC constants", m.name),
                ));
            }
            Some(_) => {}
        }
        if let Some(other) = drafts
            .iter()
            .find(|d| d.name.eq_ignore_ascii_case(&sec.name))
        {
            return Err(err(
                sec.loc,
                "*SOLID SECTION",
                DeckFault::Conflict,
                format!(
                    "gives element set {} a second section (first at line {})",
                    sec.name, read.sections[other.section].loc.line
                ),
            ));
        }
        let elements: Vec<u64> = set
            .iter()
            .copied()
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect();
        let mut nodes = BTreeSet::new();
        for &e in &elements {
            if let Some(&p) = elem_part.get(&e) {
                return Err(err(
                    sec.loc,
                    "*SOLID SECTION",
                    DeckFault::Conflict,
                    format!(
                        "puts element {e} in a second section (it is in element set {} already)",
                        drafts[p].name
                    ),
                ));
            }
            elem_part.insert(e, s);
            let el = &read.elements[&e];
            for n in &el.nodes {
                if !read.nodes.contains_key(n) {
                    return Err(err(
                        el.loc,
                        "*ELEMENT",
                        DeckFault::Undefined,
                        format!("element {e} uses node {n}, which no *NODE defines"),
                    ));
                }
                nodes.insert(*n);
            }
        }
        drafts.push(PartDraft {
            name: sec.name.clone(),
            section: s,
            elements,
            nodes: nodes.into_iter().collect(),
            boundaries: Vec::new(),
        });
    }
    if let Some((id, el)) = read
        .elements
        .iter()
        .find(|(id, _)| !elem_part.contains_key(id))
    {
        return Err(err(
            el.loc,
            "*ELEMENT",
            DeckFault::Malformed,
            format!(
                "element {id} is in no *SOLID SECTION's element set: every element needs a material and a thickness"
            ),
        ));
    }
    // One plane kind for the whole model.
    let mut plane: Option<(PlaneKind, u64)> = None;
    for (id, el) in &read.elements {
        match plane {
            None => plane = Some((el.plane, *id)),
            Some((p, first)) if p != el.plane => {
                let name = |p: PlaneKind| match p {
                    PlaneKind::Strain => "plane strain (CPE)",
                    PlaneKind::Axisymmetric => "axisymmetric (CAX)",
                    PlaneKind::Stress => "plane stress (CPS)",
                };
                return Err(err(
                    el.loc,
                    "*ELEMENT",
                    DeckFault::Conflict,
                    format!(
                        "element {id} is {} but element {first} is {}: cfe solves one plane kind per model",
                        name(el.plane),
                        name(p)
                    ),
                ));
            }
            _ => {}
        }
    }
    let plane = plane.map(|p| p.0).unwrap_or(PlaneKind::Stress);
    let axisymmetric = plane == PlaneKind::Axisymmetric;
    // A section's thickness; an axisymmetric section has none (CalculiX: the
    // value under *SOLID SECTION "has no effect" for CAX elements).
    let thickness_of = |section: usize| {
        if axisymmetric {
            1.0
        } else {
            read.sections[section].thickness
        }
    };
    // Each node in one part: (part, local index).
    let mut node_part: HashMap<u64, (usize, usize)> = HashMap::new();
    for (p, d) in drafts.iter().enumerate() {
        for (i, n) in d.nodes.iter().enumerate() {
            if let Some((q, _)) = node_part.insert(*n, (p, i)) {
                return Err(err(
                    read.sections[d.section].loc,
                    "*SOLID SECTION",
                    DeckFault::Conflict,
                    format!(
                        "makes node {n} part of element set {}, but it is a node of element set {} too: cfe meshes each section's body on its own nodes; give each body its own nodes (duplicate the nodes where they meet) and join the bodies with *TIE or *CONTACT PAIR",
                        d.name, drafts[q].name
                    ),
                ));
            }
        }
    }
    let local = |n: u64| node_part[&n].1;
    let part_names: Vec<String> = drafts.iter().map(|d| d.name.clone()).collect();
    // A surface's part and its boundary selection.
    let surface_part = |key: &str, loc: Loc, kw: &str| -> Result<(usize, BoundarySelection)> {
        let s = &read.surfaces[key];
        let mut part = None;
        let mut check = |p: usize, what: String| -> Result<()> {
            match part {
                None => part = Some(p),
                Some(q) if q != p => {
                    return Err(err(
                        loc,
                        kw,
                        DeckFault::Conflict,
                        format!(
                            "uses surface {}, which lies on two bodies ({} and {}, by {what}): a pair's surface lies on one body",
                            s.name, part_names[q], part_names[p]
                        ),
                    ));
                }
                _ => {}
            }
            Ok(())
        };
        let selection = match &s.kind {
            SurfaceKind::Faces(faces) => {
                let mut edges = Vec::with_capacity(faces.len());
                for &(e, k) in faces {
                    let el = &read.elements[&e];
                    let c = el.nodes.len();
                    if k >= c {
                        return Err(err(
                            s.loc,
                            "*SURFACE",
                            DeckFault::Malformed,
                            format!("gives face S{} of element {e}, which has {c} faces", k + 1),
                        ));
                    }
                    check(elem_part[&e], format!("element {e}"))?;
                    edges.push([local(el.nodes[k]), local(el.nodes[(k + 1) % c])]);
                }
                BoundarySelection::Edges(edges)
            }
            SurfaceKind::Nodes(nodes) => {
                let mut list = Vec::with_capacity(nodes.len());
                for n in nodes {
                    let Some(&(p, i)) = node_part.get(n) else {
                        return Err(err(
                            s.loc,
                            "*SURFACE",
                            DeckFault::Undefined,
                            format!(
                                "surface {} holds node {n}, which is in no element of a section",
                                s.name
                            ),
                        ));
                    };
                    check(p, format!("node {n}"))?;
                    list.push(i);
                }
                BoundarySelection::Nodes(list)
            }
        };
        match part {
            Some(p) => Ok((p, selection)),
            None => Err(err(
                s.loc,
                "*SURFACE",
                DeckFault::Malformed,
                format!("surface {} is empty", s.name),
            )),
        }
    };
    // Interfaces' surfaces become boundaries of their parts.
    struct PairDraft {
        host: usize,
        nodes: usize,
        boundary: String,
        set_size: Option<usize>,
    }
    let mut pair_drafts = Vec::with_capacity(read.pairs.len());
    for pair in &read.pairs {
        let kw = if pair.interaction.is_some() {
            "*CONTACT PAIR"
        } else {
            "*TIE"
        };
        let (sp, selection) = surface_part(&pair.slave, pair.loc, kw)?;
        let (mp, _) = surface_part(&pair.master, pair.loc, kw)?;
        if let SurfaceKind::Nodes(_) = read.surfaces[&pair.master].kind {
            return Err(err(
                pair.loc,
                kw,
                DeckFault::Unsupported,
                format!(
                    "has master surface {}, a node surface: the master is element faces (TYPE=ELEMENT)",
                    read.surfaces[&pair.master].name
                ),
            ));
        }
        if sp == mp {
            return Err(err(
                pair.loc,
                kw,
                DeckFault::Conflict,
                format!(
                    "joins two surfaces of the same body ({}): cfe's interfaces join two parts",
                    part_names[sp]
                ),
            ));
        }
        let name = read.surfaces[&pair.slave].name.clone();
        let set_size = match &selection {
            BoundarySelection::Nodes(l) => Some(l.iter().collect::<BTreeSet<_>>().len()),
            BoundarySelection::Edges(_) => None,
        };
        if !drafts[sp].boundaries.iter().any(|(n, _)| *n == name) {
            drafts[sp].boundaries.push((name.clone(), selection));
        }
        pair_drafts.push(PairDraft {
            host: mp,
            nodes: sp,
            boundary: name,
            set_size,
        });
    }
    // Pressures: each face's value per step; a later step's change is the
    // load of that step (cfe's loads of earlier steps stay at full value).
    type DloadGroup = (usize, usize, u64, Vec<[usize; 2]>, String);
    let mut dload_groups: Vec<DloadGroup> = Vec::new();
    {
        let mut state: HashMap<(u64, usize), (f64, usize, Loc)> = HashMap::new();
        let mut index: HashMap<(Loc, usize, usize, u64), usize> = HashMap::new();
        for line in &read.dloads {
            for &e in &line.target.ids {
                let el = &read.elements[&e];
                let c = el.nodes.len();
                if line.face >= c {
                    return Err(err(
                        line.loc,
                        "*DLOAD",
                        DeckFault::Malformed,
                        format!(
                            "loads face P{} of element {e}, which has {c} faces",
                            line.face + 1
                        ),
                    ));
                }
                let before = state.get(&(e, line.face)).copied();
                if let Some((_, s, l)) = before
                    && s == line.step
                {
                    return Err(err(
                        line.loc,
                        "*DLOAD",
                        DeckFault::Conflict,
                        format!(
                            "loads face P{} of element {e} a second time in this step (first at line {})",
                            line.face + 1,
                            l.line
                        ),
                    ));
                }
                state.insert((e, line.face), (line.value, line.step, line.loc));
                let delta = line.value - before.map(|b| b.0).unwrap_or(0.0);
                if delta == 0.0 {
                    continue;
                }
                let p = elem_part[&e];
                let key = (line.card, p, line.step, delta.to_bits());
                let g = *index.entry(key).or_insert_with(|| {
                    dload_groups.push((p, line.step, delta.to_bits(), Vec::new(), String::new()));
                    dload_groups.len() - 1
                });
                dload_groups[g].3.push([
                    local(el.nodes[line.face]),
                    local(el.nodes[(line.face + 1) % c]),
                ]);
                if dload_groups[g].4.is_empty() {
                    let file = if line.card.file == 0 {
                        String::new()
                    } else {
                        format!("{}:", deck.files[line.card.file].display())
                    };
                    dload_groups[g].4 = format!("*DLOAD line {file}{} #{}", line.card.line, g + 1);
                }
            }
        }
        for (p, _, _, edges, name) in &dload_groups {
            drafts[*p]
                .boundaries
                .push((name.clone(), BoundarySelection::Edges(edges.clone())));
        }
    }
    // The meshes.
    let mut meshes = BTreeMap::new();
    for d in &drafts {
        let nodes: Vec<[f64; 2]> = d.nodes.iter().map(|n| read.nodes[n].0).collect();
        let elements: Vec<Element> = d
            .elements
            .iter()
            .map(|e| {
                let el = &read.elements[e];
                let l: Vec<usize> = el.nodes.iter().map(|&n| local(n)).collect();
                match el.kind {
                    ElementKind::T3 => Element::T3([l[0], l[1], l[2]]),
                    ElementKind::Q4 => Element::Q4([l[0], l[1], l[2], l[3]]),
                }
            })
            .collect();
        let mesh = Mesh::from_arrays(&d.name, nodes, elements, d.boundaries.clone())
            .map_err(|e| match e {
                Error::Mesh { part, message } => Error::Mesh {
                    message: format!(
                        "{message} (element and node numbers here count the part's elements and nodes from 0, in the order of their deck numbers)"
                    ),
                    part,
                },
                e => e,
            })?;
        meshes.insert(d.name.clone(), mesh);
    }
    // A slave node set must be the nodes of boundary edges it joins.
    for (pair, pd) in read.pairs.iter().zip(&pair_drafts) {
        if let Some(n) = pd.set_size {
            let mesh = &meshes[&drafts[pd.nodes].name];
            let got = mesh
                .boundary_nodes(&pd.boundary)
                .map(|b| b.len())
                .unwrap_or(0);
            if got != n {
                return Err(err(
                    pair.loc,
                    "*SURFACE",
                    DeckFault::Malformed,
                    format!(
                        "slave surface {} holds {n} nodes, but only {got} of them lie on boundary edges joining two of its nodes: a slave node surface is nodes along the body's boundary",
                        pd.boundary
                    ),
                ));
            }
        }
    }
    // Refinement: the slave node sets are checked on the deck's meshes above;
    // everything below (penalties, pressures, supports) is on the refined ones.
    let coarse = if refine > 1 {
        let nodes = meshes.values().map(|m| m.nodes.len()).sum::<usize>();
        crate::model::build::check_size(crate::model::build::refined_nodes(nodes, refine), refine)?;
        let refined = meshes
            .iter()
            .map(|(k, m)| (k.clone(), m.refined(refine)))
            .collect();
        Some(std::mem::replace(&mut meshes, refined))
    } else {
        None
    };
    // The schema as TOML text, each entry marked with its deck line.
    let mut t = Toml::default();
    if let Some(title) = &read.title {
        t.line(None, format!("title = {}", quote(title)));
    }
    t.line(
        None,
        format!(
            "plane = {}",
            quote(match plane {
                PlaneKind::Strain => "strain",
                PlaneKind::Stress => "stress",
                PlaneKind::Axisymmetric => "axisymmetric",
            })
        ),
    );
    let mut used: Vec<&str> = read.sections.iter().map(|s| s.material.as_str()).collect();
    used.sort_unstable();
    used.dedup();
    for key in used {
        let m = &read.materials[key];
        let (e, nu, loc) = m.elastic.expect("checked");
        t.line(Some(loc), format!("[materials.{}]", quote(&m.name)));
        t.line(Some(loc), format!("E = {}", float(e)));
        t.line(Some(loc), format!("nu = {}", float(nu)));
    }
    let mut notes: Vec<String> = Vec::new();
    for d in &drafts {
        let sec = &read.sections[d.section];
        let loc = Some(sec.loc);
        t.line(loc, "[[part]]".into());
        t.line(loc, format!("name = {}", quote(&d.name)));
        t.line(
            loc,
            format!("material = {}", quote(&read.materials[&sec.material].name)),
        );
        if axisymmetric {
            if sec.thickness != 1.0 {
                notes.push(format!(
                    "*SOLID SECTION at line {}: the thickness {} of an axisymmetric section has no effect (as in CalculiX)",
                    sec.loc.line, sec.thickness
                ));
            }
        } else {
            t.line(loc, format!("thickness = {}", float(sec.thickness)));
        }
    }
    let mut names: HashMap<String, usize> = HashMap::new();
    for (pair, pd) in read.pairs.iter().zip(&pair_drafts) {
        let loc = Some(pair.loc);
        let slave = &read.surfaces[&pair.slave].name;
        let master = &read.surfaces[&pair.master].name;
        let base = pair
            .tie_name
            .clone()
            .unwrap_or_else(|| format!("{slave}-{master}"));
        let k = names.entry(base.clone()).or_insert(0);
        *k += 1;
        let name = if *k == 1 {
            base
        } else {
            format!("{base} #{k}")
        };
        t.line(loc, "[[interface]]".into());
        t.line(loc, format!("name = {}", quote(&name)));
        t.line(loc, format!("host = {}", quote(&drafts[pd.host].name)));
        t.line(loc, format!("nodes = {}", quote(&drafts[pd.nodes].name)));
        t.line(loc, format!("boundary = {}", quote(&pd.boundary)));
        if pair.segment {
            t.line(loc, "coupling = \"segment\"".into());
        }
        let Some(key) = &pair.interaction else {
            t.line(loc, "law = \"rigid\"".into());
            continue;
        };
        let Some(inter) = read.interactions.get(key) else {
            return Err(err(
                pair.loc,
                "*CONTACT PAIR",
                DeckFault::Undefined,
                format!("names interaction {key}, which no *SURFACE INTERACTION defines"),
            ));
        };
        let Some(behavior) = inter.behavior else {
            return Err(err(
                inter.loc,
                "*SURFACE INTERACTION",
                DeckFault::Malformed,
                format!("{key} has no *SURFACE BEHAVIOR (PRESSURE-OVERCLOSURE=LINEAR or HARD)"),
            ));
        };
        // A pressure per overclosure times the slave face's mean edge length and
        // the thickness is a force per gap of one pair.
        let mesh = &meshes[&drafts[pd.nodes].name];
        let edges = &mesh.boundaries[&pd.boundary];
        let length: f64 = edges
            .iter()
            .map(|e| crate::mesh::dist(mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]))
            .sum::<f64>()
            / edges.len() as f64;
        // Axisymmetric: c_n is per unit circumference (cfe multiplies it by
        // the pair's ring 2π r̄), so the slope times the edge length alone.
        let thickness = thickness_of(drafts[pd.nodes].section);
        let per_pair = length * thickness;
        match behavior {
            Behavior::Linear(k) => {
                let c_n = k * per_pair;
                t.line(loc, format!("c_n = {}", float(c_n)));
                notes.push(if axisymmetric {
                    format!(
                        "interface '{name}': PRESSURE-OVERCLOSURE=LINEAR slope {k} × mean slave edge {length} = c_n {c_n} per unit circumference (each pair's penalty is c_n × its ring 2π r̄)"
                    )
                } else {
                    format!(
                        "interface '{name}': PRESSURE-OVERCLOSURE=LINEAR slope {k} × mean slave edge {length} × thickness {thickness} = c_n {c_n} per pair"
                    )
                });
            }
            Behavior::Hard => notes.push(format!(
                "interface '{name}': PRESSURE-OVERCLOSURE=HARD is cfe's default penalty (c_n = 1e5 × the softer part's E·t)"
            )),
        }
        let law = match inter.friction {
            None => Law::Frictionless,
            Some(f) if f.rough => Law::Contact,
            Some(f) if f.mu == 0.0 => Law::Frictionless,
            Some(f) => {
                t.line(loc, format!("friction = {}", float(f.mu)));
                Law::Coulomb
            }
        };
        t.line(loc, format!("law = {}", quote(law.as_str())));
        if law != Law::Frictionless
            && let Some(s) = inter.friction.and_then(|f| f.stick_slope)
        {
            t.line(loc, format!("c_s = {}", float(s * per_pair)));
        }
    }
    if read.steps.len() == 1 {
        t.line(Some(read.steps[0].loc), "[analysis]".into());
        t.line(
            Some(read.steps[0].loc),
            format!("increments = {}", read.steps[0].increments.unwrap_or(1)),
        );
    } else {
        for s in &read.steps {
            t.line(Some(s.loc), "[[step]]".into());
            t.line(Some(s.loc), format!("name = {}", quote(&s.name)));
            t.line(
                Some(s.loc),
                format!("increments = {}", s.increments.unwrap_or(1)),
            );
        }
    }
    let mut supports = supports(read, &drafts, &node_part)?;
    if let Some(coarse) = &coarse {
        refine_supports(coarse, &drafts, &mut supports, refine);
    }
    // CalculiX's point forces on axisymmetric elements are totals over the
    // ring's circumference (its manual, "Eight-node axisymmetric element (CAX8
    // and CAX8R)": forces "have to be defined for the complete circumference"),
    // as Abaqus's and cfe's; only its printed reactions (*NODE PRINT RF) are per
    // 2° segment.
    if axisymmetric && !read.cloads.is_empty() {
        notes.push("*CLOAD on an axisymmetric (CAX) deck: each force is the total over the ring's circumference, as CalculiX and Abaqus read it (not per 2° segment: only CalculiX's printed reactions are)".into());
    }
    let loads_ = cloads(read, &drafts, &node_part)?;
    let mut pressure_loads = Vec::with_capacity(dload_groups.len());
    for (p, step, bits, _, name) in &dload_groups {
        let mesh = &meshes[&drafts[*p].name];
        let edges: Vec<([usize; 2], [[f64; 2]; 2])> = mesh.boundaries[name]
            .iter()
            .map(|e| (e.nodes, [mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]]))
            .collect();
        // CalculiX's P is a pressure (force per area); cfe's per length of
        // edge in a plane model, integrated with 2πr over the ring's surface in
        // an axisymmetric one.
        let nodal = if axisymmetric {
            axisymmetric::pressure_forces(&edges, f64::from_bits(*bits))
        } else {
            let thickness = thickness_of(drafts[*p].section);
            loads::pressure_forces(&edges, f64::from_bits(*bits) * thickness)
        };
        pressure_loads.push(load(name.clone(), *p, nodal, *step));
    }
    Ok(InpModel {
        toml: t.text,
        lines: t.lines,
        meshes,
        supports,
        loads: loads_.into_iter().chain(pressure_loads).collect(),
        notes,
    })
}

/// The supports of a deck refined `k` times: each holds, besides its nodes,
/// the nodes [`Mesh::refined`] puts inside every edge of the deck's `coarse`
/// meshes whose two ends are held alike (the same components, values and
/// step, by this support or another: a face clamped node by node stays
/// clamped), the first such support of the edge's first end taking them. The
/// new nodes are numbered as `Mesh::refined` numbers them: the input nodes keep
/// their indices, then the k − 1 new nodes of each edge, edges in the order the
/// elements first use them.
fn refine_supports(
    coarse: &BTreeMap<String, Mesh>,
    drafts: &[PartDraft],
    supports: &mut [Support],
    k: usize,
) {
    type Key = ([bool; 3], [u64; 3], usize);
    let key = |s: &Support| (s.fix, s.value.map(f64::to_bits), s.step);
    for (p, d) in drafts.iter().enumerate() {
        let mesh = &coarse[&d.name];
        let mut held: HashMap<usize, Vec<(usize, Key)>> = HashMap::new();
        for (i, s) in supports.iter().enumerate().filter(|(_, s)| s.part == p) {
            for &n in &s.nodes {
                held.entry(n).or_default().push((i, key(s)));
            }
        }
        let mut added: Vec<(usize, std::ops::Range<usize>)> = Vec::new();
        let mut seen: std::collections::HashSet<(usize, usize)> = std::collections::HashSet::new();
        let mut next = mesh.nodes.len();
        for el in &mesh.elements {
            for [a, b] in el.edges() {
                if !seen.insert((a.min(b), a.max(b))) {
                    continue;
                }
                let (lo, hi) = (a.min(b), a.max(b));
                if let (Some(at_lo), Some(at_hi)) = (held.get(&lo), held.get(&hi)) {
                    let mut keys: Vec<Key> = Vec::new();
                    for &(i, kl) in at_lo {
                        if !keys.contains(&kl) && at_hi.iter().any(|&(_, kh)| kh == kl) {
                            keys.push(kl);
                            added.push((i, next..next + k - 1));
                        }
                    }
                }
                next += k - 1;
            }
        }
        for (i, range) in added {
            supports[i].nodes.extend(range);
        }
    }
}

/// A load from its nodal forces.
fn load(name: String, part: usize, nodal: Vec<(usize, [f64; 2])>, step: usize) -> Load {
    let mut resultant = [0.0; 2];
    for (_, f) in &nodal {
        resultant[0] += f[0];
        resultant[1] += f[1];
    }
    Load {
        name,
        part,
        nodal,
        resultant,
        step,
    }
}

/// The node of a load or support line in a part, or an error naming it.
fn node_in_part(
    read: &Read,
    node_part: &HashMap<u64, (usize, usize)>,
    n: u64,
    loc: Loc,
    kw: &str,
) -> Result<(usize, usize)> {
    node_part.get(&n).copied().ok_or_else(|| {
        read.deck.error(
            loc,
            kw,
            DeckFault::Undefined,
            format!("acts on node {n}, which is in no element of a *SOLID SECTION"),
        )
    })
}

/// The `*BOUNDARY` lines as cfe's supports. Per node and component, the first
/// statement (in the model data or the first step) holds it from the first
/// step on; a later step may restate it with the same value, or give a value
/// to a component held at 0 so far (it ramps in that step). Nodes of one part
/// with the same components, values, step and line form one support.
fn supports(
    read: &Read,
    drafts: &[PartDraft],
    node_part: &HashMap<u64, (usize, usize)>,
) -> Result<Vec<Support>> {
    struct State {
        value: f64,
        step: usize,
        label: String,
        loc: Loc,
    }
    let mut state: HashMap<(u64, usize), State> = HashMap::new();
    let mut order: Vec<(u64, usize)> = Vec::new();
    for line in &read.boundaries {
        for &n in &line.target.ids {
            node_in_part(read, node_part, n, line.loc, "*BOUNDARY")?;
            for &(c, v) in &line.dofs {
                let dof = ["1 (x)", "2 (y)"][c];
                match state.get_mut(&(n, c)) {
                    None if line.step > 0 => {
                        return Err(read.deck.error(
                            line.loc,
                            "*BOUNDARY",
                            DeckFault::Unsupported,
                            format!("first holds node {n}'s DOF {dof} in step {} (of {}): cfe holds a support's DOFs in every step, so hold it from the first step (with value 0 there) and give its value in this one", line.step + 1, read.steps.len()),
                        ));
                    }
                    None => {
                        state.insert(
                            (n, c),
                            State {
                                value: v,
                                step: line.step,
                                label: line.target.label.clone(),
                                loc: line.loc,
                            },
                        );
                        order.push((n, c));
                    }
                    Some(s) if s.value == v => {}
                    Some(s) if s.step == line.step => {
                        return Err(read.deck.error(
                            line.loc,
                            "*BOUNDARY",
                            DeckFault::Conflict,
                            format!("gives node {n}'s DOF {dof} the value {v}, but line {} gave it {} in the same step", s.loc.line, s.value),
                        ));
                    }
                    Some(s) if s.value == 0.0 => {
                        *s = State {
                            value: v,
                            step: line.step,
                            label: line.target.label.clone(),
                            loc: line.loc,
                        };
                    }
                    Some(s) => {
                        return Err(read.deck.error(
                            line.loc,
                            "*BOUNDARY",
                            DeckFault::Unsupported,
                            format!("changes node {n}'s prescribed DOF {dof} from {} (line {}) to {v}: a prescribed value ramps once and then holds in cfe (changing it in a later step is not supported yet)", s.value, s.loc.line),
                        ));
                    }
                }
            }
        }
    }
    // Group: per node, its components with the same line and step together.
    type Key = (usize, String, usize, [bool; 2], [u64; 2], Loc);
    let mut groups: Vec<(Key, Vec<usize>)> = Vec::new();
    let mut index: HashMap<Key, usize> = HashMap::new();
    let mut done: BTreeSet<u64> = BTreeSet::new();
    for &(n, _) in &order {
        if !done.insert(n) {
            continue;
        }
        let (p, i) = node_part[&n];
        let comps: Vec<(usize, &State)> = (0..2)
            .filter_map(|c| state.get(&(n, c)).map(|s| (c, s)))
            .collect();
        let same = comps.len() == 2
            && comps[0].1.loc == comps[1].1.loc
            && comps[0].1.step == comps[1].1.step;
        let sets: Vec<Vec<(usize, &State)>> = if same {
            vec![comps]
        } else {
            comps.into_iter().map(|c| vec![c]).collect()
        };
        for set in sets {
            let mut fix = [false; 2];
            let mut value = [0u64; 2];
            for (c, s) in &set {
                fix[*c] = true;
                value[*c] = s.value.to_bits();
            }
            let s = set[0].1;
            let key = (p, s.label.clone(), s.step, fix, value, s.loc);
            let g = *index.entry(key.clone()).or_insert_with(|| {
                groups.push((key, Vec::new()));
                groups.len() - 1
            });
            groups[g].1.push(i);
        }
    }
    let mut names: HashMap<String, usize> = HashMap::new();
    Ok(groups
        .into_iter()
        .map(|((p, label, step, fix, value, _), nodes)| {
            let base = format!("{}/{label}", drafts[p].name);
            let k = names.entry(base.clone()).or_insert(0);
            *k += 1;
            let name = if *k == 1 {
                base
            } else {
                format!("{base} #{k}")
            };
            Support {
                name,
                part: p,
                nodes,
                fix: [fix[0], fix[1], false],
                value: [f64::from_bits(value[0]), f64::from_bits(value[1]), 0.0],
                step,
            }
        })
        .collect())
}

/// The `*CLOAD` lines as cfe's loads: per node and component, a later step's
/// new value is the load of that step by its change (cfe's loads of earlier
/// steps stay at full value: the sum ramps from the old value to the new, as
/// CalculiX's OP=MOD does). One load per card and part. In an axisymmetric
/// deck each force is the total over its node's ring, as the deck gives it.
fn cloads(
    read: &Read,
    drafts: &[PartDraft],
    node_part: &HashMap<u64, (usize, usize)>,
) -> Result<Vec<Load>> {
    let mut state: HashMap<(u64, usize), (f64, usize, Loc)> = HashMap::new();
    // (card, part, step, nodal forces)
    type Group = (Loc, usize, usize, Vec<(usize, [f64; 2])>);
    let mut groups: Vec<Group> = Vec::new();
    let mut index: HashMap<(Loc, usize), usize> = HashMap::new();
    for line in &read.cloads {
        let Some(c) = line.dof else { continue };
        for &n in &line.target.ids {
            let (p, i) = node_in_part(read, node_part, n, line.loc, "*CLOAD")?;
            let before = state.get(&(n, c)).copied();
            if let Some((_, s, l)) = before
                && s == line.step
            {
                return Err(read.deck.error(
                    line.loc,
                    "*CLOAD",
                    DeckFault::Conflict,
                    format!(
                        "loads node {n}'s DOF {} a second time in this step (first at line {})",
                        c + 1,
                        l.line
                    ),
                ));
            }
            state.insert((n, c), (line.value, line.step, line.loc));
            let delta = line.value - before.map(|b| b.0).unwrap_or(0.0);
            if delta == 0.0 {
                continue;
            }
            let g = *index.entry((line.card, p)).or_insert_with(|| {
                groups.push((line.card, p, line.step, Vec::new()));
                groups.len() - 1
            });
            let mut f = [0.0; 2];
            f[c] = delta;
            groups[g].3.push((i, f));
        }
    }
    let parts_per_card = |card: Loc| groups.iter().filter(|g| g.0 == card).count();
    let mut out = Vec::with_capacity(groups.len());
    for (card, p, step, nodal) in &groups {
        let file = if card.file == 0 {
            String::new()
        } else {
            format!("{}:", read.deck.files[card.file].display())
        };
        let mut name = format!("*CLOAD line {file}{}", card.line);
        if parts_per_card(*card) > 1 {
            name = format!("{name}/{}", drafts[*p].name);
        }
        out.push(load(name, *p, nodal.clone(), *step));
    }
    Ok(out)
}
