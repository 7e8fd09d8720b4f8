//! Gmsh input: reads MSH 4.1 and 2.2 files, ASCII and binary, into a [`GmshMesh`]
//! (nodes, 2-node lines, 3-node triangles and 4-node quadrilaterals, each with the
//! physical groups it belongs to, and the physical-name table), and builds a part's
//! [`Mesh`] from a set of physical surfaces, with its named boundaries from the
//! physical curves.
//!
//! The reader is pure Rust and keeps every element type cfe knows in its own list;
//! [`GmshMesh::part_mesh`] makes the triangles T3 and the 4-node quadrilaterals Q4
//! elements.
//!
//! Sections read: `$MeshFormat`, `$PhysicalNames`, `$Entities` (4.1: the physical
//! tags of each entity), `$Nodes`, `$Elements`; any other section (`$Periodic`,
//! `$NodeData`, ...) is skipped. Node and element tags may be sparse. The mesh must
//! be planar (z = const); z is dropped.

use super::{BoundaryEdge, Mesh, Tiling, dist};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::fmt::Display;
use std::path::{Path, PathBuf};

/// The MSH format versions cfe reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MshVersion {
    /// MSH 2.2 (legacy; physical and elementary tags per element).
    V22,
    /// MSH 4.1 (entities carry the physical tags; node and element blocks).
    V41,
}

/// One element as the file gives it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Element<const N: usize> {
    /// The element's tag in the file.
    pub tag: u64,
    /// Its nodes: indices into [`GmshMesh::nodes`], in the file's order (which may be
    /// clockwise).
    pub nodes: [usize; N],
    /// The physical groups it belongs to (empty when none), ascending.
    pub physical: Vec<i32>,
}

/// An entry of `$PhysicalNames`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PhysicalName {
    /// Dimension: 0 point, 1 curve, 2 surface, 3 volume.
    pub dim: u8,
    /// The physical tag.
    pub tag: i32,
    /// Its name.
    pub name: String,
}

/// A Gmsh mesh as read from a file: everything cfe uses, in the file's order.
#[derive(Debug, Clone, PartialEq)]
pub struct GmshMesh {
    /// The file it was read from (used in messages).
    pub path: PathBuf,
    /// Format version.
    pub version: MshVersion,
    /// Binary (true) or ASCII file.
    pub binary: bool,
    /// The tag of each node (same order as `nodes`).
    pub node_tags: Vec<u64>,
    /// Node coordinates (x, y), in the order of `$Nodes`.
    pub nodes: Vec<[f64; 2]>,
    /// 2-node lines (Gmsh type 1): boundaries, through their physical curves.
    pub lines: Vec<Element<2>>,
    /// 3-node triangles (Gmsh type 2).
    pub triangles: Vec<Element<3>>,
    /// 4-node quadrilaterals (Gmsh type 3).
    pub quads: Vec<Element<4>>,
    /// The physical-name table.
    pub physical_names: Vec<PhysicalName>,
}

/// A physical group named in a problem file: by name or by number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Group {
    /// A name from `$PhysicalNames`.
    Name(String),
    /// A physical tag.
    Tag(i32),
}

impl Display for Group {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Group::Name(n) => write!(f, "'{n}'"),
            Group::Tag(t) => write!(f, "{t}"),
        }
    }
}

/// The name Gmsh's documentation gives element type `t`.
pub fn element_type_name(t: i32) -> &'static str {
    match t {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrilateral",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node line",
        9 => "6-node triangle",
        10 => "9-node quadrilateral",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        13 => "18-node prism",
        14 => "14-node pyramid",
        15 => "1-node point",
        16 => "8-node quadrilateral",
        17 => "20-node hexahedron",
        18 => "15-node prism",
        19 => "13-node pyramid",
        20 => "9-node incomplete triangle",
        21 => "10-node triangle",
        22 => "12-node incomplete triangle",
        23 => "15-node triangle",
        24 => "15-node incomplete triangle",
        25 => "21-node triangle",
        26 => "4-node line",
        27 => "5-node line",
        28 => "6-node line",
        29 => "20-node tetrahedron",
        30 => "35-node tetrahedron",
        31 => "56-node tetrahedron",
        92 => "64-node hexahedron",
        93 => "125-node hexahedron",
        _ => "unknown type",
    }
}

/// The element types the reader keeps (points are read and dropped).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Point,
    Line,
    Triangle,
    Quad,
}

impl Kind {
    fn from_type(t: i32) -> Option<Kind> {
        match t {
            15 => Some(Kind::Point),
            1 => Some(Kind::Line),
            2 => Some(Kind::Triangle),
            3 => Some(Kind::Quad),
            _ => None,
        }
    }

    fn node_count(self) -> usize {
        match self {
            Kind::Point => 1,
            Kind::Line => 2,
            Kind::Triangle => 3,
            Kind::Quad => 4,
        }
    }
}

impl GmshMesh {
    /// Reads and parses the file at `path`.
    pub fn read(path: &Path) -> Result<GmshMesh> {
        let data = std::fs::read(path).map_err(|e| Error::Parse {
            line: None,
            path: path.to_path_buf(),
            message: format!("cannot read the Gmsh file: {e}"),
        })?;
        GmshMesh::parse(&data, path)
    }

    /// Parses the contents of an MSH file; `path` is used in messages. Errors name the
    /// file and the line (ASCII) or byte offset (binary) at fault.
    pub fn parse(data: &[u8], path: &Path) -> Result<GmshMesh> {
        Parser::new(data, path).run()
    }

    /// The physical groups of dimension `dim` (1 curves, 2 surfaces): every tag that
    /// has a name or is used by an element, with its name if it has one, ascending.
    pub fn physical_groups(&self, dim: u8) -> Vec<(i32, Option<&str>)> {
        let mut tags: BTreeSet<i32> = self
            .physical_names
            .iter()
            .filter(|p| p.dim == dim)
            .map(|p| p.tag)
            .collect();
        match dim {
            1 => tags.extend(self.lines.iter().flat_map(|e| e.physical.iter().copied())),
            2 => {
                tags.extend(
                    self.triangles
                        .iter()
                        .flat_map(|e| e.physical.iter().copied()),
                );
                tags.extend(self.quads.iter().flat_map(|e| e.physical.iter().copied()));
            }
            _ => {}
        }
        tags.into_iter().map(|t| (t, self.name(dim, t))).collect()
    }

    /// The name of physical group (`dim`, `tag`), if it has one.
    pub fn name(&self, dim: u8, tag: i32) -> Option<&str> {
        self.physical_names
            .iter()
            .find(|p| p.dim == dim && p.tag == tag)
            .map(|p| p.name.as_str())
    }

    fn file_name(&self) -> String {
        self.path.display().to_string()
    }

    /// The physical surface tags `groups` refer to. A name that matches no named
    /// surface may be a number ("3" for surface 3).
    fn resolve_surfaces(&self, groups: &[Group]) -> std::result::Result<BTreeSet<i32>, String> {
        let available = self.physical_groups(2);
        let mut out = BTreeSet::new();
        for g in groups {
            let found: Vec<i32> = match g {
                Group::Tag(t) => available
                    .iter()
                    .filter(|(a, _)| a == t)
                    .map(|(a, _)| *a)
                    .collect(),
                Group::Name(n) => {
                    let named: Vec<i32> = available
                        .iter()
                        .filter(|(_, name)| *name == Some(n.as_str()))
                        .map(|(a, _)| *a)
                        .collect();
                    match n.trim().parse::<i32>() {
                        Ok(t) if named.is_empty() => available
                            .iter()
                            .filter(|(a, _)| *a == t)
                            .map(|(a, _)| *a)
                            .collect(),
                        _ => named,
                    }
                }
            };
            if found.is_empty() {
                let curve = match g {
                    Group::Name(n)
                        if self
                            .physical_names
                            .iter()
                            .any(|p| p.dim != 2 && &p.name == n) =>
                    {
                        format!(" ('{n}' is not a surface)")
                    }
                    _ => String::new(),
                };
                return Err(format!(
                    "file {} has no physical surface {g}{curve}; its physical surfaces are: {}",
                    self.file_name(),
                    describe(&available)
                ));
            }
            out.extend(found);
        }
        Ok(out)
    }

    /// Builds the mesh of part `part` from the elements of the physical surfaces
    /// `surfaces` (all 2D elements of the file when `None`).
    ///
    /// Only the nodes those elements use are kept, renumbered in file order. Every
    /// triangle is made counter-clockwise (clockwise ones are flipped). Each physical
    /// curve's lines that lie on the part's boundary become a named boundary
    /// (`Mesh::boundaries`; a curve without a name is named by its number), its edges
    /// oriented counter-clockwise with respect to the part and ordered along the
    /// curve; curves with no edge on the part's boundary (inside the part, or on
    /// another part of a shared file) are left out. A curve with edges both on the
    /// part's boundary and inside it (an edge shared by two of the part's elements)
    /// is an error naming the curve and one inner edge. Quadrilaterals become Q4
    /// elements, counter-clockwise like the triangles.
    pub fn part_mesh(&self, part: &str, surfaces: Option<&[Group]>) -> Result<Mesh> {
        let err = |message: String| Error::Mesh {
            part: part.to_string(),
            message,
        };
        let chosen = self.chosen_elements(surfaces).map_err(err)?;
        let used = self.used_nodes(&chosen);
        let elements = self.ccw_elements(&chosen, &used).map_err(err)?;
        let PartNodes {
            local,
            nodes,
            file_of,
        } = used;
        let mut mesh = Mesh {
            nodes,
            elements,
            boundaries: BTreeMap::new(),
        };
        // The elements must tile the part: overlapping or folded elements would
        // pass every per-element check and give a wrong answer.
        mesh.check_tiling()
            .map_err(|t| err(self.tiling_message(t, &chosen, &file_of)))?;

        self.name_boundaries(&mut mesh, &local).map_err(err)?;
        Ok(mesh)
    }

    /// The elements of the physical surfaces `surfaces` (all when `None`) as
    /// (tag, file nodes), in file order within each type: triangles, then
    /// quadrilaterals. An empty selection, an unknown surface or no element is an
    /// error.
    fn chosen_elements(
        &self,
        surfaces: Option<&[Group]>,
    ) -> std::result::Result<Vec<(u64, &[usize])>, String> {
        let selected = match surfaces {
            Some([]) => {
                return Err(format!(
                    "no physical surface of file {} is selected: list some, or leave `surfaces` out to take them all",
                    self.file_name()
                ));
            }
            Some(groups) => Some(self.resolve_surfaces(groups)?),
            None => None,
        };
        let picks = |physical: &[i32]| match &selected {
            None => true,
            Some(s) => physical.iter().any(|t| s.contains(t)),
        };
        let chosen: Vec<(u64, &[usize])> = self
            .triangles
            .iter()
            .filter(|t| picks(&t.physical))
            .map(|t| (t.tag, &t.nodes[..]))
            .chain(
                self.quads
                    .iter()
                    .filter(|q| picks(&q.physical))
                    .map(|q| (q.tag, &q.nodes[..])),
            )
            .collect();
        if chosen.is_empty() {
            let scope = match surfaces {
                Some(groups) => format!(
                    " in physical surface(s) {}",
                    groups
                        .iter()
                        .map(|g| g.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                None => String::new(),
            };
            return Err(format!(
                "file {} has no 3-node triangles or 4-node quadrilaterals{scope}",
                self.file_name()
            ));
        }
        Ok(chosen)
    }

    /// The nodes used by the `chosen` elements, renumbered in file order.
    fn used_nodes(&self, chosen: &[(u64, &[usize])]) -> PartNodes {
        let mut local = vec![UNUSED; self.nodes.len()];
        for (_, nodes) in chosen {
            for &n in nodes.iter() {
                local[n] = 0;
            }
        }
        let mut nodes = Vec::new();
        let mut file_of = Vec::new();
        for (i, l) in local.iter_mut().enumerate() {
            if *l != UNUSED {
                *l = nodes.len();
                nodes.push(self.nodes[i]);
                file_of.push(i);
            }
        }
        PartNodes {
            local,
            nodes,
            file_of,
        }
    }

    /// The `chosen` elements in the part's node numbering, counter-clockwise (a
    /// clockwise one is reversed); a degenerate element is an error.
    fn ccw_elements(
        &self,
        chosen: &[(u64, &[usize])],
        used: &PartNodes,
    ) -> std::result::Result<Vec<super::Element>, String> {
        let mut elements = Vec::with_capacity(chosen.len());
        for (tag, file_nodes) in chosen {
            let mut el: Vec<usize> = file_nodes.iter().map(|&n| used.local[n]).collect();
            let x: Vec<[f64; 2]> = el.iter().map(|&n| used.nodes[n]).collect();
            let area = super::polygon_area(x.iter().copied());
            let h = (0..x.len())
                .map(|k| dist(x[k], x[(k + 1) % x.len()]))
                .fold(0.0, f64::max);
            if area.abs() <= 1e-10 * h * h {
                return Err(format!(
                    "element {tag} of file {} is degenerate: nodes {:?} at {x:?}, area {area:e}",
                    self.file_name(),
                    file_nodes
                        .iter()
                        .map(|&n| self.node_tags[n])
                        .collect::<Vec<_>>(),
                ));
            }
            if area < 0.0 {
                el.reverse();
            }
            elements.push(match el[..] {
                [a, b, c] => super::Element::T3([a, b, c]),
                [a, b, c, d] => super::Element::Q4([a, b, c, d]),
                _ => unreachable!("the reader keeps 3- and 4-node elements only"),
            });
        }
        Ok(elements)
    }

    /// The message for a part whose elements do not tile it, naming elements and
    /// nodes by their tags in the file.
    fn tiling_message(&self, t: Tiling, chosen: &[(u64, &[usize])], file_of: &[usize]) -> String {
        let tag = |e: usize| chosen[e].0;
        let node_tag = |n: usize| self.node_tags[file_of[n]];
        match t {
            Tiling::Shared { edge, elements } => format!(
                "elements {:?} of file {} all use the edge between nodes {} and {}: an edge can border two elements at most (overlapping elements?)",
                elements.iter().map(|&e| tag(e)).collect::<Vec<_>>(),
                self.file_name(),
                node_tag(edge[0]),
                node_tag(edge[1])
            ),
            Tiling::SameSide { edge, elements } => format!(
                "elements {} and {} of file {} lie on the same side of their common edge (nodes {} and {}): one folds over the other",
                tag(elements[0]),
                tag(elements[1]),
                self.file_name(),
                node_tag(edge[0]),
                node_tag(edge[1])
            ),
            Tiling::Overlap {
                area,
                enclosed,
                pairs,
            } if pairs.is_empty() => format!(
                "the elements of file {} cover an area of {area:e} but their boundary encloses {enclosed:e}: elements overlap",
                self.file_name()
            ),
            Tiling::Overlap { pairs, .. } => format!(
                "elements of file {} overlap: {}",
                self.file_name(),
                pairs
                    .iter()
                    .map(|[a, b]| format!("{} and {}", tag(*a), tag(*b)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }

    /// Names the boundaries of a part's `mesh` after the physical curves whose lines
    /// are its boundary edges (`local`: the file's nodes in the part's numbering, or
    /// `UNUSED`), each chained in order. A curve partly inside the part is an error.
    fn name_boundaries(&self, mesh: &mut Mesh, local: &[usize]) -> std::result::Result<(), String> {
        // Named boundaries from the physical curves. Each element edge, by its sorted
        // node pair: how many elements use it, and the first one's oriented edge.
        let mut uses: HashMap<(usize, usize), (usize, BoundaryEdge)> =
            HashMap::with_capacity(2 * mesh.elements.len());
        for (e, el) in mesh.elements.iter().enumerate() {
            for [a, b] in el.edges() {
                uses.entry((a.min(b), a.max(b)))
                    .and_modify(|u| u.0 += 1)
                    .or_insert((
                        1,
                        BoundaryEdge {
                            nodes: [a, b],
                            element: e,
                        },
                    ));
            }
        }
        // Per physical curve: its edges on the part's boundary, and its lines that
        // are interior edges of the part (how many, and the first one).
        let mut by_tag: BTreeMap<i32, Vec<BoundaryEdge>> = BTreeMap::new();
        let mut inside: BTreeMap<i32, (usize, [usize; 2])> = BTreeMap::new();
        for line in &self.lines {
            let [a, b] = line.nodes.map(|n| local[n]);
            if a == UNUSED || b == UNUSED {
                continue;
            }
            match uses.get(&(a.min(b), a.max(b))) {
                Some((1, edge)) => {
                    for &tag in &line.physical {
                        by_tag.entry(tag).or_default().push(*edge);
                    }
                }
                Some(_) => {
                    for &tag in &line.physical {
                        inside.entry(tag).or_insert((0, line.nodes)).0 += 1;
                    }
                }
                None => {}
            }
        }
        // A curve partly on the boundary and partly inside the part is an error
        // (curves wholly inside are left out below, as they name no boundary).
        for (tag, &(count, [a, b])) in &inside {
            let Some(on_boundary) = by_tag.get(tag) else {
                continue;
            };
            let curve = match self.name(1, *tag) {
                Some(n) => format!("'{n}' ({tag})"),
                None => tag.to_string(),
            };
            let at = |n: usize| {
                let [x, y] = self.nodes[n];
                format!("node {} ({x}, {y})", self.node_tags[n])
            };
            let edges = |n: usize| format!("{n} edge{}", if n == 1 { "" } else { "s" });
            return Err(format!(
                "physical curve {curve} of file {} lies partly inside the part: it has {} on the part's boundary and {} inside it (shared by two of the part's elements), e.g. the edge from {} to {}; a boundary must lie on the part's boundary: split the curve in Gmsh so that its inner lines form a physical curve of their own, or put only boundary curves in the physical group",
                self.file_name(),
                edges(on_boundary.len()),
                edges(count),
                at(a),
                at(b),
            ));
        }
        for (tag, edges) in by_tag {
            let name = self
                .name(1, tag)
                .map(str::to_string)
                .unwrap_or_else(|| tag.to_string());
            mesh.boundaries.entry(name).or_default().extend(edges);
        }
        for edges in mesh.boundaries.values_mut() {
            *edges = chain_order(std::mem::take(edges));
        }
        Ok(())
    }
}

/// A file node used by no chosen element (in the map to the part's numbering).
const UNUSED: usize = usize::MAX;

/// The nodes of a part built from a file: the file's nodes in the part's
/// numbering (`local`, [`UNUSED`] for the others), the part's coordinates, and
/// the file's node (index into [`GmshMesh::nodes`]) of each part node.
struct PartNodes {
    local: Vec<usize>,
    nodes: Vec<[f64; 2]>,
    file_of: Vec<usize>,
}

/// `"left" (1), "right" (2), 7` for a list of physical groups.
fn describe(groups: &[(i32, Option<&str>)]) -> String {
    if groups.is_empty() {
        return "none".into();
    }
    groups
        .iter()
        .map(|(t, n)| match n {
            Some(n) => format!("'{n}' ({t})"),
            None => t.to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Orders oriented edges along their chains (each edge's end is the next one's
/// start), open chains first from their free start, then closed loops; duplicates
/// are dropped. Deterministic for a given input order.
pub(super) fn chain_order(mut edges: Vec<BoundaryEdge>) -> Vec<BoundaryEdge> {
    let mut seen = HashSet::new();
    edges.retain(|e| seen.insert(e.nodes));
    let ends: HashSet<usize> = edges.iter().map(|e| e.nodes[1]).collect();
    let mut from: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        from.entry(e.nodes[0]).or_default().push(i);
    }
    let starts: Vec<usize> = (0..edges.len())
        .filter(|&i| !ends.contains(&edges[i].nodes[0]))
        .collect();
    let mut used = vec![false; edges.len()];
    let mut out = Vec::with_capacity(edges.len());
    for s in starts.into_iter().chain(0..edges.len()) {
        let mut cur = s;
        while !used[cur] {
            used[cur] = true;
            out.push(edges[cur]);
            if let Some(next) = from
                .get(&edges[cur].nodes[1])
                .and_then(|v| v.iter().copied().find(|&j| !used[j]))
            {
                cur = next;
            }
        }
    }
    out
}

// ---------------------------------------------------------------- parser

/// Byte-level reader of an MSH file: ASCII tokens, or binary values in the file's
/// byte order and `size_t` width.
struct Parser<'a> {
    path: &'a Path,
    data: &'a [u8],
    pos: usize,
    /// The section being read (for messages).
    section: &'a str,
    binary: bool,
    little_endian: bool,
    size_t: usize,
    version: MshVersion,
    physical_names: Vec<PhysicalName>,
    /// 4.1: physical tags of each entity (dim, tag).
    entities: HashMap<(i32, i32), Vec<i32>>,
    node_index: HashMap<u64, usize>,
    node_tags: Vec<u64>,
    /// (x, y, z) per node.
    coords: Vec<[f64; 3]>,
    lines: Vec<Element<2>>,
    triangles: Vec<Element<3>>,
    quads: Vec<Element<4>>,
    seen_nodes: bool,
    seen_elements: bool,
}

impl<'a> Parser<'a> {
    fn new(data: &'a [u8], path: &'a Path) -> Self {
        Parser {
            path,
            data,
            pos: 0,
            section: "",
            binary: false,
            little_endian: true,
            size_t: 8,
            version: MshVersion::V41,
            physical_names: Vec::new(),
            entities: HashMap::new(),
            node_index: HashMap::new(),
            node_tags: Vec::new(),
            coords: Vec::new(),
            lines: Vec::new(),
            triangles: Vec::new(),
            quads: Vec::new(),
            seen_nodes: false,
            seen_elements: false,
        }
    }

    // ------------------------------------------------------------ messages

    fn err_at(&self, pos: usize, msg: impl Display) -> Error {
        let line = (!self.binary).then(|| {
            self.data[..pos.min(self.data.len())]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1
        });
        let place = match line {
            Some(line) => format!("line {line}"),
            None => format!("byte {pos}"),
        };
        let section = if self.section.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.section)
        };
        Error::Parse {
            line,
            path: self.path.to_path_buf(),
            message: format!("{place}{section}: {msg}"),
        }
    }

    fn err(&self, msg: impl Display) -> Error {
        self.err_at(self.pos, msg)
    }

    fn file_name(&self) -> String {
        self.path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_else(|| self.path.display().to_string())
    }

    // ------------------------------------------------------------ ASCII

    fn skip_whitespace(&mut self) {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next whitespace-delimited token.
    fn token(&mut self, what: &str) -> Result<&'a str> {
        self.skip_whitespace();
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.err(format!("unexpected end of file; expected {what}")));
        }
        std::str::from_utf8(&self.data[start..self.pos])
            .map_err(|_| self.err_at(start, format!("expected {what}, found non-text bytes")))
    }

    /// The next token parsed as a `T`.
    fn ascii<T: std::str::FromStr>(&mut self, what: &str) -> Result<T> {
        self.skip_whitespace();
        let start = self.pos;
        let t = self.token(what)?;
        t.parse()
            .map_err(|_| self.err_at(start, format!("expected {what}, found '{t}'")))
    }

    /// Moves past the end of the current line (binary data starts on the next one).
    fn next_line(&mut self) -> Result<()> {
        while self.pos < self.data.len() && matches!(self.data[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        if self.data.get(self.pos) != Some(&b'\n') {
            return Err(self.err("expected the end of the line before the binary data"));
        }
        self.pos += 1;
        Ok(())
    }

    // ------------------------------------------------------------ binary

    fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let Some(b) = self.data.get(self.pos..self.pos + N) else {
            return Err(self.err(format!(
                "unexpected end of file in binary data; expected {what}"
            )));
        };
        self.pos += N;
        Ok(b.try_into().expect("slice of length N"))
    }

    fn bin_i32(&mut self, what: &str) -> Result<i32> {
        let b = self.bytes::<4>(what)?;
        Ok(if self.little_endian {
            i32::from_le_bytes(b)
        } else {
            i32::from_be_bytes(b)
        })
    }

    fn bin_f64(&mut self, what: &str) -> Result<f64> {
        let b = self.bytes::<8>(what)?;
        Ok(if self.little_endian {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    fn bin_size(&mut self, what: &str) -> Result<u64> {
        if self.size_t == 4 {
            let b = self.bytes::<4>(what)?;
            Ok(u64::from(if self.little_endian {
                u32::from_le_bytes(b)
            } else {
                u32::from_be_bytes(b)
            }))
        } else {
            let b = self.bytes::<8>(what)?;
            Ok(if self.little_endian {
                u64::from_le_bytes(b)
            } else {
                u64::from_be_bytes(b)
            })
        }
    }

    // ------------------------------------------------------------ either (MSH 4.1)

    fn int(&mut self, what: &str) -> Result<i32> {
        if self.binary {
            self.bin_i32(what)
        } else {
            self.ascii(what)
        }
    }

    fn size(&mut self, what: &str) -> Result<u64> {
        if self.binary {
            self.bin_size(what)
        } else {
            self.ascii(what)
        }
    }

    fn float(&mut self, what: &str) -> Result<f64> {
        if self.binary {
            self.bin_f64(what)
        } else {
            self.ascii(what)
        }
    }

    /// A count, as a `usize`, for sizing loops and vectors (a count larger than the
    /// file is an error rather than an allocation).
    fn count(&mut self, value: u64, what: &str) -> Result<usize> {
        usize::try_from(value)
            .ok()
            .filter(|&n| n <= self.data.len())
            .ok_or_else(|| self.err(format!("{what} {value} is larger than the file")))
    }

    // ------------------------------------------------------------ sections

    fn run(mut self) -> Result<GmshMesh> {
        self.skip_whitespace();
        let first = self.token("$MeshFormat").ok();
        if first != Some("$MeshFormat") {
            return Err(self.err_at(0, "not a Gmsh MSH file: it does not start with $MeshFormat"));
        }
        self.section = "$MeshFormat";
        self.mesh_format()?;
        loop {
            self.skip_whitespace();
            if self.pos >= self.data.len() {
                break;
            }
            let start = self.pos;
            let name = self.token("a section")?;
            if !name.starts_with('$') || name.starts_with("$End") {
                return Err(self.err_at(
                    start,
                    format!("expected a section header ($Name), found '{name}'"),
                ));
            }
            self.section = name;
            match name {
                "$PhysicalNames" => self.physical_names_section()?,
                "$Entities" if self.version == MshVersion::V41 => self.entities_section()?,
                "$Nodes" => {
                    if self.seen_nodes {
                        return Err(self.err_at(start, "the file has two $Nodes sections"));
                    }
                    self.seen_nodes = true;
                    match self.version {
                        MshVersion::V41 => self.nodes_41()?,
                        MshVersion::V22 => self.nodes_22()?,
                    }
                }
                "$Elements" => {
                    if self.seen_elements {
                        return Err(self.err_at(start, "the file has two $Elements sections"));
                    }
                    if !self.seen_nodes {
                        return Err(self.err_at(start, "$Elements comes before $Nodes"));
                    }
                    self.seen_elements = true;
                    match self.version {
                        MshVersion::V41 => self.elements_41()?,
                        MshVersion::V22 => self.elements_22()?,
                    }
                }
                _ => {
                    self.skip_section(name)?;
                    continue;
                }
            }
            self.end_section()?;
        }
        self.section = "";
        for (present, name) in [
            (self.seen_nodes, "$Nodes"),
            (self.seen_elements, "$Elements"),
        ] {
            if !present {
                return Err(Error::Parse {
                    line: None,
                    path: self.path.to_path_buf(),
                    message: format!("the file has no {name} section"),
                });
            }
        }
        self.check_planar()?;
        if self.version == MshVersion::V22 {
            // MSH 2.2 repeats an element once per physical group it belongs to.
            self.lines = merge_duplicates(std::mem::take(&mut self.lines));
            self.triangles = merge_duplicates(std::mem::take(&mut self.triangles));
            self.quads = merge_duplicates(std::mem::take(&mut self.quads));
        }
        Ok(GmshMesh {
            path: self.path.to_path_buf(),
            version: self.version,
            binary: self.binary,
            node_tags: self.node_tags,
            nodes: self.coords.iter().map(|c| [c[0], c[1]]).collect(),
            lines: self.lines,
            triangles: self.triangles,
            quads: self.quads,
            physical_names: self.physical_names,
        })
    }

    fn end_section(&mut self) -> Result<()> {
        let expected = format!("$End{}", &self.section[1..]);
        let start = {
            self.skip_whitespace();
            self.pos
        };
        let t = self.token(&expected)?;
        if t != expected {
            return Err(self.err_at(start, format!("expected {expected}, found '{t}'")));
        }
        Ok(())
    }

    /// Skips a section cfe does not use, up to and including its `$End` line.
    fn skip_section(&mut self, name: &str) -> Result<()> {
        let end = format!("$End{}", &name[1..]);
        let needle = format!("\n{end}");
        let found = self.data[self.pos..]
            .windows(needle.len())
            .position(|w| w == needle.as_bytes());
        match found {
            Some(i) => {
                self.pos += i + needle.len();
                Ok(())
            }
            None => Err(self.err(format!("section {name} has no {end}"))),
        }
    }

    fn mesh_format(&mut self) -> Result<()> {
        let start = {
            self.skip_whitespace();
            self.pos
        };
        let version = self.token("the format version")?;
        self.version = match version {
            "4.1" => MshVersion::V41,
            "2.2" => MshVersion::V22,
            v => {
                return Err(self.err_at(
                    start,
                    format!(
                        "MSH version {v} is not supported: cfe reads MSH 4.1 and 2.2 (in Gmsh: Mesh.MshFileVersion = 4.1 or 2.2)"
                    ),
                ));
            }
        };
        let file_type: i32 = self.ascii("the file type (0 ASCII, 1 binary)")?;
        let data_size: usize = self.ascii("the data size")?;
        match file_type {
            0 => {}
            1 => {
                self.binary = true;
                match (self.version, data_size) {
                    (MshVersion::V41, 4 | 8) | (MshVersion::V22, 8) => self.size_t = data_size,
                    _ => {
                        return Err(self.err(format!(
                            "data size {data_size} is not supported for a binary MSH {version} file (expected 8)"
                        )));
                    }
                }
                self.next_line()?;
                let one = self.bytes::<4>("the endianness marker (int 1)")?;
                self.little_endian = if i32::from_le_bytes(one) == 1 {
                    true
                } else if i32::from_be_bytes(one) == 1 {
                    false
                } else {
                    return Err(self.err(format!(
                        "bad endianness marker {one:?}: expected the integer 1"
                    )));
                };
            }
            t => {
                return Err(self.err(format!("file type {t} is not 0 (ASCII) or 1 (binary)")));
            }
        }
        self.end_section()
    }

    fn physical_names_section(&mut self) -> Result<()> {
        let n: u64 = self.ascii("the number of physical names")?;
        let n = self.count(n, "number of physical names")?;
        for _ in 0..n {
            let dim: u8 = self.ascii("a physical dimension")?;
            let tag: i32 = self.ascii("a physical tag")?;
            self.skip_whitespace();
            if self.data.get(self.pos) != Some(&b'"') {
                return Err(self.err("expected a quoted physical name"));
            }
            let start = self.pos + 1;
            let Some(len) = self.data[start..]
                .iter()
                .position(|&b| b == b'"' || b == b'\n')
                .filter(|&i| self.data[start + i] == b'"')
            else {
                return Err(self.err("physical name without a closing quote"));
            };
            let name = String::from_utf8_lossy(&self.data[start..start + len]).into_owned();
            self.pos = start + len + 1;
            self.physical_names.push(PhysicalName { dim, tag, name });
        }
        Ok(())
    }

    fn entities_section(&mut self) -> Result<()> {
        if self.binary {
            self.next_line()?;
        }
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            let what = ["points", "curves", "surfaces", "volumes"][d];
            let n = self.size(&format!("the number of {what}"))?;
            *c = self.count(n, &format!("number of {what}"))?;
        }
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let tag = self.int("an entity tag")?;
                // A point has its coordinates, other entities their bounding box.
                for _ in 0..if dim == 0 { 3 } else { 6 } {
                    self.float("an entity coordinate")?;
                }
                let np = self.size("the number of physical tags")?;
                let np = self.count(np, "number of physical tags")?;
                let mut physical = Vec::with_capacity(np);
                for _ in 0..np {
                    physical.push(self.int("a physical tag")?);
                }
                if dim > 0 {
                    let nb = self.size("the number of bounding entities")?;
                    let nb = self.count(nb, "number of bounding entities")?;
                    for _ in 0..nb {
                        self.int("a bounding entity tag")?;
                    }
                }
                physical.sort_unstable();
                physical.dedup();
                self.entities.insert((dim as i32, tag), physical);
            }
        }
        Ok(())
    }

    fn add_node(&mut self, tag: u64, xyz: [f64; 3], at: usize) -> Result<()> {
        if self.node_index.insert(tag, self.node_tags.len()).is_some() {
            return Err(self.err_at(at, format!("node {tag} is defined twice")));
        }
        if let Some(c) = xyz.iter().position(|v| !v.is_finite()) {
            // At the current position: the end of the node's own line.
            return Err(self.err(format!(
                "node {tag} has a non-finite {} coordinate ({})",
                ["x", "y", "z"][c],
                xyz[c]
            )));
        }
        self.node_tags.push(tag);
        self.coords.push(xyz);
        Ok(())
    }

    fn nodes_41(&mut self) -> Result<()> {
        if self.binary {
            self.next_line()?;
        }
        let blocks = self.size("the number of node blocks")?;
        let blocks = self.count(blocks, "number of node blocks")?;
        let total = self.size("the number of nodes")?;
        let total = self.count(total, "number of nodes")?;
        self.size("the smallest node tag")?;
        self.size("the largest node tag")?;
        self.node_tags.reserve(total);
        self.coords.reserve(total);
        for _ in 0..blocks {
            let dim = self.int("the entity dimension")?;
            self.int("the entity tag")?;
            let parametric = self.int("the parametric flag")?;
            let n = self.size("the number of nodes in the block")?;
            let n = self.count(n, "number of nodes in the block")?;
            let start = self.pos;
            let mut tags = Vec::with_capacity(n);
            for _ in 0..n {
                tags.push(self.size("a node tag")?);
            }
            let extra = if parametric == 1 {
                dim.clamp(0, 3) as usize
            } else {
                0
            };
            for tag in tags {
                let xyz = [self.float("x")?, self.float("y")?, self.float("z")?];
                for _ in 0..extra {
                    self.float("a parametric coordinate")?;
                }
                self.add_node(tag, xyz, start)?;
            }
        }
        Ok(())
    }

    fn nodes_22(&mut self) -> Result<()> {
        let n: u64 = self.ascii("the number of nodes")?;
        let n = self.count(n, "number of nodes")?;
        self.node_tags.reserve(n);
        self.coords.reserve(n);
        if self.binary {
            self.next_line()?;
        }
        for _ in 0..n {
            let start = self.pos;
            let (tag, xyz) = if self.binary {
                let tag = self.bin_i32("a node tag")?;
                let tag = u64::try_from(tag)
                    .map_err(|_| self.err_at(start, format!("negative node tag {tag}")))?;
                (
                    tag,
                    [self.bin_f64("x")?, self.bin_f64("y")?, self.bin_f64("z")?],
                )
            } else {
                (
                    self.ascii("a node tag")?,
                    [self.ascii("x")?, self.ascii("y")?, self.ascii("z")?],
                )
            };
            self.add_node(tag, xyz, start)?;
        }
        Ok(())
    }

    /// The kind of Gmsh element type `t`, or the error for a type cfe does not read.
    fn kind(&self, t: i32, at: usize) -> Result<Kind> {
        Kind::from_type(t).ok_or_else(|| {
            self.err_at(
                at,
                format!(
                    "element type {t} ({}) in file {} is not supported: cfe reads 3-node triangles and 4-node quadrilaterals (and 2-node lines and points for physical groups)",
                    element_type_name(t),
                    self.file_name()
                ),
            )
        })
    }

    /// Stores one element, its node tags resolved to node indices.
    fn add_element(
        &mut self,
        kind: Kind,
        tag: u64,
        node_tags: &[u64],
        physical: Vec<i32>,
        at: usize,
    ) -> Result<()> {
        let mut nodes = [0usize; 4];
        for (slot, &t) in nodes.iter_mut().zip(node_tags) {
            *slot = *self.node_index.get(&t).ok_or_else(|| {
                self.err_at(
                    at,
                    format!(
                        "element {tag} ({}) refers to node {t}, which is not defined in $Nodes",
                        element_type_name(match kind {
                            Kind::Point => 15,
                            Kind::Line => 1,
                            Kind::Triangle => 2,
                            Kind::Quad => 3,
                        })
                    ),
                )
            })?;
        }
        match kind {
            Kind::Point => {}
            Kind::Line => self.lines.push(Element {
                tag,
                nodes: [nodes[0], nodes[1]],
                physical,
            }),
            Kind::Triangle => self.triangles.push(Element {
                tag,
                nodes: [nodes[0], nodes[1], nodes[2]],
                physical,
            }),
            Kind::Quad => self.quads.push(Element {
                tag,
                nodes,
                physical,
            }),
        }
        Ok(())
    }

    fn elements_41(&mut self) -> Result<()> {
        if self.binary {
            self.next_line()?;
        }
        let blocks = self.size("the number of element blocks")?;
        let blocks = self.count(blocks, "number of element blocks")?;
        self.size("the number of elements")?;
        self.size("the smallest element tag")?;
        self.size("the largest element tag")?;
        let mut node_tags = [0u64; 4];
        for _ in 0..blocks {
            let block_start = self.pos;
            let dim = self.int("the entity dimension")?;
            let entity = self.int("the entity tag")?;
            let t = self.int("the element type")?;
            let kind = self.kind(t, block_start)?;
            let n = self.size("the number of elements in the block")?;
            let n = self.count(n, "number of elements in the block")?;
            let physical = self
                .entities
                .get(&(dim, entity))
                .cloned()
                .unwrap_or_default();
            for _ in 0..n {
                let start = self.pos;
                let tag = self.size("an element tag")?;
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    *slot = self.size("a node tag")?;
                }
                self.add_element(
                    kind,
                    tag,
                    &node_tags[..kind.node_count()],
                    physical.clone(),
                    start,
                )?;
            }
        }
        Ok(())
    }

    fn elements_22(&mut self) -> Result<()> {
        let n: u64 = self.ascii("the number of elements")?;
        let n = self.count(n, "number of elements")?;
        let mut node_tags = [0u64; 4];
        if !self.binary {
            for _ in 0..n {
                self.skip_whitespace();
                let start = self.pos;
                let tag: u64 = self.ascii("an element tag")?;
                let t: i32 = self.ascii("an element type")?;
                let kind = self.kind(t, start)?;
                let ntags: usize = self.ascii("the number of tags")?;
                let mut physical = Vec::new();
                for k in 0..ntags {
                    let v: i32 = self.ascii("a tag")?;
                    if k == 0 && v != 0 {
                        physical.push(v);
                    }
                }
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    *slot = self.ascii("a node tag")?;
                }
                self.add_element(kind, tag, &node_tags[..kind.node_count()], physical, start)?;
            }
            return Ok(());
        }
        self.next_line()?;
        let mut read = 0usize;
        while read < n {
            let header = self.pos;
            let t = self.bin_i32("an element type")?;
            let kind = self.kind(t, header)?;
            let follow = self.bin_i32("the number of elements that follow")?;
            let ntags = self.bin_i32("the number of tags")?;
            let (Ok(follow), Ok(ntags)) = (usize::try_from(follow), usize::try_from(ntags)) else {
                return Err(self.err_at(header, "negative count in an element header"));
            };
            if follow == 0 || follow > n - read {
                return Err(self.err_at(
                    header,
                    format!(
                        "element header announces {follow} elements, but {} remain",
                        n - read
                    ),
                ));
            }
            for _ in 0..follow {
                let start = self.pos;
                let tag = self.bin_i32("an element tag")?;
                let mut physical = Vec::new();
                for k in 0..ntags {
                    let v = self.bin_i32("a tag")?;
                    if k == 0 && v != 0 {
                        physical.push(v);
                    }
                }
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    let v = self.bin_i32("a node tag")?;
                    *slot = u64::try_from(v).unwrap_or(u64::MAX);
                }
                let tag = u64::try_from(tag)
                    .map_err(|_| self.err_at(start, format!("negative element tag {tag}")))?;
                self.add_element(kind, tag, &node_tags[..kind.node_count()], physical, start)?;
            }
            read += follow;
        }
        Ok(())
    }

    /// cfe is 2D: every node must lie in one plane z = const.
    fn check_planar(&self) -> Result<()> {
        let Some(first) = self.coords.first() else {
            return Ok(());
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for c in &self.coords {
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        let size = dist(lo, hi);
        let tol = 1e-9 * size.max(first[2].abs()).max(f64::MIN_POSITIVE);
        if let Some((i, c)) = self.coords.iter().enumerate().find(|(_, c)| {
            let dz = (c[2] - first[2]).abs();
            dz.is_nan() || dz > tol
        }) {
            return Err(Error::Parse {
                line: None,
                path: self.path.to_path_buf(),
                message: format!(
                    "the mesh is not planar: node {} has z = {} but node {} has z = {}; cfe is 2D and needs a mesh in a plane z = const",
                    self.node_tags[i], c[2], self.node_tags[0], first[2]
                ),
            });
        }
        Ok(())
    }
}

/// Merges elements with the same nodes (MSH 2.2 writes an element once per physical
/// group), keeping the first one's tag and order and the union of the groups.
fn merge_duplicates<const N: usize>(elements: Vec<Element<N>>) -> Vec<Element<N>> {
    let mut first: HashMap<[usize; N], usize> = HashMap::with_capacity(elements.len());
    let mut out: Vec<Element<N>> = Vec::with_capacity(elements.len());
    for e in elements {
        let mut key = e.nodes;
        key.sort_unstable();
        match first.get(&key) {
            Some(&i) => {
                let p = &mut out[i].physical;
                p.extend(e.physical);
                p.sort_unstable();
                p.dedup();
            }
            None => {
                first.insert(key, out.len());
                out.push(e);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square in MSH 2.2 ASCII: nodes 7, 8, 9, 10 (sparse tags), triangle 1
    /// counter-clockwise, triangle 2 clockwise, line 3 the bottom (physical curve 5,
    /// no name), line 4 the top ("top"), surface "sq" (physical 1).
    const SQUARE_22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
1 6 \"top\"
2 1 \"sq\"
$EndPhysicalNames
$Nodes
4
7 0 0 0
8 1 0 0
9 1 1 0
10 0 1 0
$EndNodes
$Elements
4
3 1 2 5 1 7 8
4 1 2 6 2 9 10
1 2 2 1 1 7 8 9
2 2 2 1 1 7 10 9
$EndElements
";

    fn parse(text: &str) -> Result<GmshMesh> {
        GmshMesh::parse(text.as_bytes(), Path::new("x.msh"))
    }

    fn message(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    /// MSH 2.2 ASCII: sparse node tags map to compact indices, physical tags and
    /// names are kept, elements keep the file's node order.
    #[test]
    fn reads_ascii_22() {
        let m = parse(SQUARE_22).unwrap();
        assert_eq!(m.version, MshVersion::V22);
        assert_eq!(m.node_tags, vec![7, 8, 9, 10]);
        assert_eq!(m.nodes[2], [1.0, 1.0]);
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.triangles[1].nodes, [0, 3, 2]);
        assert_eq!(m.triangles[1].physical, vec![1]);
        assert_eq!(m.lines[0].physical, vec![5]);
        assert_eq!(m.name(2, 1), Some("sq"));
        assert_eq!(m.physical_groups(1), vec![(5, None), (6, Some("top"))]);
    }

    /// A clockwise triangle is flipped: every triangle of the part mesh is
    /// counter-clockwise and the mesh passes validation.
    #[test]
    fn clockwise_triangles_are_flipped() {
        let m = parse(SQUARE_22).unwrap();
        let mesh = m.part_mesh("p", None).unwrap();
        mesh.validate("p").unwrap();
        assert!((0..2).all(|e| mesh.element_area(e) > 0.0));
        assert!((mesh.element_area(1) - 0.5).abs() < 1e-15);
    }

    /// Physical curves become boundaries oriented counter-clockwise w.r.t. the part
    /// (the top line, written left to right, runs right to left); an unnamed curve
    /// is named by its number.
    #[test]
    fn physical_curves_become_oriented_boundaries() {
        let mesh = parse(SQUARE_22).unwrap().part_mesh("p", None).unwrap();
        assert_eq!(mesh.boundaries.keys().collect::<Vec<_>>(), vec!["5", "top"]);
        let top = &mesh.boundaries["top"];
        assert_eq!(top.len(), 1);
        assert_eq!(
            top[0].nodes.map(|n| mesh.nodes[n]),
            [[1.0, 1.0], [0.0, 1.0]]
        );
        assert_eq!(top[0].element, 1);
        let bottom = &mesh.boundaries["5"];
        assert_eq!(
            bottom[0].nodes.map(|n| mesh.nodes[n]),
            [[0.0, 0.0], [1.0, 0.0]]
        );
    }

    /// An unsupported element type names the type, its description, the file and
    /// the line.
    #[test]
    fn unsupported_element_type_is_named() {
        let text = SQUARE_22.replace("2 2 2 1 1 7 10 9", "2 9 2 1 1 7 8 9 10 7 8");
        let e = message(&text);
        assert!(
            e.contains("element type 9 (6-node triangle) in file x.msh is not supported")
                && e.contains("3-node triangles and 4-node quadrilaterals")
                && e.contains("line 21"),
            "{e}"
        );
    }

    /// Versions other than 4.1 and 2.2 are refused with the supported ones named.
    #[test]
    fn unsupported_version_is_an_error() {
        for v in ["4.0", "3.0", "2.1"] {
            let e = message(&SQUARE_22.replace("2.2 0 8", &format!("{v} 0 8")));
            assert!(
                e.contains(&format!("MSH version {v} is not supported"))
                    && e.contains("4.1 and 2.2"),
                "{e}"
            );
        }
    }

    /// Missing $Nodes or $Elements, or a file that is not MSH, are errors naming
    /// what is missing.
    #[test]
    fn missing_sections_are_errors() {
        let start = SQUARE_22.find("$Elements").unwrap();
        let e = message(&SQUARE_22[..start]);
        assert!(
            e.contains("x.msh") && e.contains("no $Elements section"),
            "{e}"
        );
        let nodes = SQUARE_22.find("$Nodes").unwrap();
        let e = message(&format!("{}{}", &SQUARE_22[..nodes], &SQUARE_22[start..]));
        assert!(e.contains("$Elements comes before $Nodes"), "{e}");
        let e = message("solid cube\n");
        assert!(e.contains("not a Gmsh MSH file"), "{e}");
        let e = message(&SQUARE_22.replace("$EndNodes", "$EndNode"));
        assert!(e.contains("expected $EndNodes"), "{e}");
    }

    /// An element that refers to an undefined node names the element and the node.
    #[test]
    fn undefined_node_is_an_error() {
        let e = message(&SQUARE_22.replace("1 2 2 1 1 7 8 9", "1 2 2 1 1 7 8 99"));
        assert!(
            e.contains("element 1 (3-node triangle) refers to node 99") && e.contains("line 20"),
            "{e}"
        );
    }

    /// A mesh that is not in one plane z = const is refused; a plane z = 3 is fine.
    #[test]
    fn non_planar_mesh_is_an_error() {
        let e = message(&SQUARE_22.replace("9 1 1 0", "9 1 1 0.5"));
        assert!(
            e.contains("not planar") && e.contains("node 9 has z = 0.5"),
            "{e}"
        );
        let text = SQUARE_22
            .replace(" 0 0\n", " 0 3\n")
            .replace(" 1 0\n", " 1 3\n");
        parse(&text).unwrap();
    }

    /// A part from a physical surface that does not exist lists the available ones
    /// and says when the name is a curve's.
    #[test]
    fn unknown_surface_lists_available_ones() {
        let m = parse(SQUARE_22).unwrap();
        let e = m
            .part_mesh("p", Some(&[Group::Name("plate".into())]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("part 'p'")
                && e.contains("no physical surface 'plate'")
                && e.contains("'sq' (1)"),
            "{e}"
        );
        let e = m
            .part_mesh("p", Some(&[Group::Name("top".into())]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("'top' is not a surface"), "{e}");
        let e = m
            .part_mesh("p", Some(&[Group::Tag(4)]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no physical surface 4"), "{e}");
        let e = m.part_mesh("p", Some(&[])).unwrap_err().to_string();
        assert!(
            e.contains("no physical surface of file x.msh is selected"),
            "{e}"
        );
        // By number, or by the number written as a name.
        for g in [
            Group::Tag(1),
            Group::Name("1".into()),
            Group::Name("sq".into()),
        ] {
            assert_eq!(m.part_mesh("p", Some(&[g])).unwrap().elements.len(), 2);
        }
    }

    /// A degenerate (zero-area) triangle is refused with its Gmsh element tag.
    #[test]
    fn degenerate_triangle_names_its_tag() {
        let text = SQUARE_22.replace("10 0 1 0", "10 0.5 0.5 0");
        let e = parse(&text)
            .unwrap()
            .part_mesh("p", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("element 2 of file x.msh is degenerate"), "{e}");
    }

    /// Sections cfe does not read are skipped, with or without content.
    #[test]
    fn unknown_sections_are_skipped() {
        let text = SQUARE_22.replace(
            "$Nodes",
            "$Periodic\n1\n1 1 2\n$EndPeriodic\n$Comments\n$EndComments\n$Nodes",
        );
        assert_eq!(parse(&text).unwrap(), {
            let mut m = parse(SQUARE_22).unwrap();
            m.path = PathBuf::from("x.msh");
            m
        });
        let e = message(&format!("{SQUARE_22}$Foo\n1 2 3\n"));
        assert!(e.contains("section $Foo has no $EndFoo"), "{e}");
    }

    /// Edges are ordered along their chain whatever the input order; a closed
    /// loop is kept whole; duplicates are dropped.
    #[test]
    fn chain_order_follows_the_curve() {
        let e = |a, b| BoundaryEdge {
            nodes: [a, b],
            element: 0,
        };
        let out = chain_order(vec![e(2, 3), e(0, 1), e(3, 4), e(1, 2), e(0, 1)]);
        assert_eq!(out, vec![e(0, 1), e(1, 2), e(2, 3), e(3, 4)]);
        let out = chain_order(vec![e(5, 6), e(7, 5), e(6, 7)]);
        assert_eq!(out, vec![e(5, 6), e(6, 7), e(7, 5)]);
    }

    /// MSH 2.2 repeats an element once per physical group; the reader merges the
    /// copies into one element with both groups.
    #[test]
    fn repeated_22_elements_are_merged() {
        let text = SQUARE_22
            .replace("$Elements\n4\n", "$Elements\n5\n")
            .replace("4 1 2 6 2 9 10\n", "4 1 2 6 2 9 10\n11 1 2 8 2 10 9\n");
        let m = parse(&text).unwrap();
        assert_eq!(m.lines.len(), 2);
        assert_eq!(m.lines[1].tag, 4);
        assert_eq!(m.lines[1].physical, vec![6, 8]);
    }
}
