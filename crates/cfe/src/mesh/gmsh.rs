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
//! `$NodeData`, ...) is skipped. Node and element tags may be sparse. A plane mesh
//! must be planar (z = const); z is dropped.
//!
//! A file with volume elements (4-node tetrahedra, 8-node hexahedra) is a 3D mesh:
//! [`GmshMesh3d`] (module `solid`) reads it, its physical volumes becoming solid
//! parts and its physical surfaces their named boundaries; [`GmshFile`] reads a file
//! of either dimension. [`GmshMesh::parse`] refuses a 3D file, naming its first
//! volume element.
//!
//! The reader is strict: a file that is not consistent (an element block outside
//! `$Entities` or outside its entity's bounding box, a count or tag range that
//! differs from its header, a repeated tag or element, a physical-curve line on no
//! element edge, ...) is refused with the block or element and its line or byte,
//! never read into a part with elements or boundary lines missing (see
//! [`GmshMesh::parse`]).

mod solid;

pub use solid::{GmshFile, GmshMesh3d, peek_dimension, read_gmsh_3d};

use super::{BoundaryEdge, Mesh, NodeSet, Tiling, dist};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::fmt::Display;
use std::path::{Path, PathBuf};

/// The bytes of the Gmsh file at `path` (a regular file of at most
/// [`MESH_FILE_CAP`](super::input_file::MESH_FILE_CAP) bytes:
/// [`input_file::read`](super::input_file::read)).
fn file_bytes(path: &Path) -> Result<Vec<u8>> {
    super::input_file::read(path, "Gmsh file", super::input_file::MESH_FILE_CAP, |e| {
        Error::Parse {
            line: None,
            path: path.to_path_buf(),
            message: format!("cannot read the Gmsh file: {e}"),
        }
    })
}

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
    /// Its elementary entity: the entity of its block (4.1) or its second tag
    /// (2.2); 0 when the file gives none. The elements of one entity share its
    /// physical groups.
    pub entity: i32,
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
    /// Points (Gmsh type 15): node sets, through their physical points.
    pub points: Vec<Element<1>>,
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

/// The element types the reader keeps (points are read and dropped; the volume
/// kinds make the file a 3D one, read by [`GmshMesh3d`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Point,
    Line,
    Triangle,
    Quad,
    Tetrahedron,
    Hexahedron,
}

impl Kind {
    fn from_type(t: i32) -> Option<Kind> {
        match t {
            15 => Some(Kind::Point),
            1 => Some(Kind::Line),
            2 => Some(Kind::Triangle),
            3 => Some(Kind::Quad),
            4 => Some(Kind::Tetrahedron),
            5 => Some(Kind::Hexahedron),
            _ => None,
        }
    }

    /// The Gmsh element type.
    fn gmsh_type(self) -> i32 {
        match self {
            Kind::Point => 15,
            Kind::Line => 1,
            Kind::Triangle => 2,
            Kind::Quad => 3,
            Kind::Tetrahedron => 4,
            Kind::Hexahedron => 5,
        }
    }

    fn node_count(self) -> usize {
        match self {
            Kind::Point => 1,
            Kind::Line => 2,
            Kind::Triangle => 3,
            Kind::Quad => 4,
            Kind::Tetrahedron => 4,
            Kind::Hexahedron => 8,
        }
    }

    /// The dimension of the element (0 point, 1 curve, 2 surface, 3 volume).
    fn dim(self) -> i32 {
        match self {
            Kind::Point => 0,
            Kind::Line => 1,
            Kind::Triangle | Kind::Quad => 2,
            Kind::Tetrahedron | Kind::Hexahedron => 3,
        }
    }
}

/// The most nodes an element kind the reader keeps has (the 8-node hexahedron).
const MAX_NODES: usize = 8;

/// Whether Gmsh element type `t` is a second- or higher-order volume element
/// (10-node tetrahedron, 20- and 27-node hexahedra, 15- and 18-node prisms, 13-
/// and 14-node pyramids, and the higher orders of tetrahedra and hexahedra).
fn is_quadratic_volume(t: i32) -> bool {
    matches!(t, 11 | 12 | 13 | 14 | 17 | 18 | 19 | 29 | 30 | 31 | 92 | 93)
}

impl GmshMesh {
    /// Reads and parses the file at `path` (a regular file of at most
    /// [`MESH_FILE_CAP`](super::input_file::MESH_FILE_CAP) bytes:
    /// [`input_file::read`](super::input_file::read)).
    pub fn read(path: &Path) -> Result<GmshMesh> {
        GmshMesh::parse(&file_bytes(path)?, path)
    }

    /// Parses the contents of an MSH file; `path` is used in messages. Errors name the
    /// file and the line (ASCII) or byte offset (binary) at fault.
    ///
    /// Beyond the format itself, the file must be consistent: the counts and tag
    /// ranges its section headers announce are those of its data; node and element
    /// tags are unique and every node an element names exists; (4.1) every element
    /// block's entity is in `$Entities` with the dimension of its element type, its
    /// elements' nodes lie in the entity's bounding box (up to 2 % of the model's
    /// size), and physical names need `$Entities` to carry them; physical names
    /// are unique per dimension, by tag and by name; (2.2) the elements of one
    /// elementary entity are in the same physical groups, and an element repeated
    /// with the same nodes is a copy for another physical group of the same entity;
    /// every line of a physical curve is an edge of a triangle or quadrilateral of
    /// the file. Anything else is an error naming the block or element and its line
    /// (ASCII) or byte (binary), never a mesh with elements or boundary lines left
    /// out. A binary file whose data does not read as its header says, but does
    /// read with another byte order or size_t width, is reported as exactly that.
    ///
    /// A file with volume elements (4-node tetrahedra, 8-node hexahedra) is a 3D
    /// mesh, read by [`GmshMesh3d::parse`]: here it is an error
    /// naming its first volume element.
    pub fn parse(data: &[u8], path: &Path) -> Result<GmshMesh> {
        Parser::read(data, path)?.plane()
    }

    /// The physical groups of dimension `dim` (1 curves, 2 surfaces): every tag that
    /// has a name or is used by an element, with its name if it has one, ascending.
    pub fn physical_groups(&self, dim: u8) -> Vec<(i32, Option<&str>)> {
        let used: Vec<&[i32]> = match dim {
            0 => self.points.iter().map(|e| &e.physical[..]).collect(),
            1 => self.lines.iter().map(|e| &e.physical[..]).collect(),
            2 => (self.triangles.iter().map(|e| &e.physical[..]))
                .chain(self.quads.iter().map(|e| &e.physical[..]))
                .collect(),
            _ => Vec::new(),
        };
        physical_groups_in(&self.physical_names, dim, used)
    }

    /// The name of physical group (`dim`, `tag`), if it has one.
    pub fn name(&self, dim: u8, tag: i32) -> Option<&str> {
        physical_name(&self.physical_names, dim, tag)
    }

    fn file_name(&self) -> String {
        self.path.display().to_string()
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
            node_sets: BTreeMap::new(),
        };
        // The elements must tile the part: overlapping or folded elements would
        // pass every per-element check and give a wrong answer.
        mesh.check_tiling()
            .map_err(|t| err(self.tiling_message(t, &chosen, &file_of)))?;

        self.name_boundaries(&mut mesh, &local).map_err(err)?;
        mesh.node_sets = self.named_node_sets(&local);
        Ok(mesh)
    }

    /// The elements of the physical surfaces `surfaces` (all when `None`) as
    /// (tag, file nodes), in file order within each type: triangles, then
    /// quadrilaterals ([`Selection::choose`]).
    fn chosen_elements(
        &self,
        surfaces: Option<&[Group]>,
    ) -> std::result::Result<Vec<(u64, &[usize])>, String> {
        SURFACES.choose(
            &self.file_name(),
            surfaces,
            || self.physical_groups(2),
            &self.physical_names,
            &self.triangles,
            &self.quads,
        )
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

    /// The named node sets of a plane part (`local`: the file's nodes in the
    /// part's numbering, or `UNUSED`): each physical point group's points that
    /// are nodes of the part (a group with none is left out; the physical
    /// curves are boundaries).
    fn named_node_sets(&self, local: &[usize]) -> BTreeMap<String, NodeSet> {
        let mut by_tag: BTreeMap<i32, Vec<usize>> = BTreeMap::new();
        for e in &self.points {
            let n = local[e.nodes[0]];
            if n != UNUSED {
                for &p in &e.physical {
                    by_tag.entry(p).or_default().push(n);
                }
            }
        }
        let mut sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
        for (p, nodes) in by_tag {
            let name = (self.name(0, p).map(str::to_string)).unwrap_or_else(|| p.to_string());
            sets.entry(name).or_default().extend(nodes);
        }
        (sets.into_iter())
            .map(|(name, nodes)| (name, NodeSet::new(nodes, Vec::new())))
            .collect()
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
        // Lines between two of the part's nodes that are no edge of its elements.
        let mut stray: BTreeMap<i32, (u64, [usize; 2])> = BTreeMap::new();
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
                None => {
                    for &tag in &line.physical {
                        stray.entry(tag).or_insert((line.tag, line.nodes));
                    }
                }
            }
        }
        // A curve that names a boundary of the part must lie on it whole: a line
        // across the part (between two of its nodes, on no element edge) would be
        // left out of the boundary silently.
        for (tag, &(line_tag, [a, b])) in &stray {
            if !by_tag.contains_key(tag) {
                continue;
            }
            let curve = match self.name(1, *tag) {
                Some(n) => format!("'{n}' ({tag})"),
                None => tag.to_string(),
            };
            return Err(format!(
                "line element {line_tag} of physical curve {curve} in file {} runs from node {} to node {}, both nodes of the part, but is no edge of the part's elements: a boundary must run along the part's element edges",
                self.file_name(),
                self.node_tags[a],
                self.node_tags[b],
            ));
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

/// "big-endian, data size 4 (4-byte size_t)" for a binary layout
/// (little-endian, size_t width).
fn layout_text((little_endian, size_t): (bool, usize)) -> String {
    format!(
        "{}, data size {size_t} ({size_t}-byte size_t)",
        if little_endian {
            "little-endian"
        } else {
            "big-endian"
        }
    )
}

/// The nodes of a part built from a file: the file's nodes in the part's
/// numbering (`local`, [`UNUSED`] for the others), the part's coordinates, and
/// the file's node (index into [`GmshMesh::nodes`]) of each part node.
struct PartNodes {
    local: Vec<usize>,
    nodes: Vec<[f64; 2]>,
    file_of: Vec<usize>,
}

/// The physical groups of dimension `dim` of a file whose physical-name table
/// is `names` and whose elements of that dimension are in the groups `used`:
/// every tag that has a name or is used by an element, with its name if it has
/// one, ascending.
fn physical_groups_in<'a>(
    names: &'a [PhysicalName],
    dim: u8,
    used: Vec<&[i32]>,
) -> Vec<(i32, Option<&'a str>)> {
    let mut tags: BTreeSet<i32> = names
        .iter()
        .filter(|p| p.dim == dim)
        .map(|p| p.tag)
        .collect();
    tags.extend(used.into_iter().flatten().copied());
    tags.into_iter()
        .map(|t| (t, physical_name(names, dim, t)))
        .collect()
}

/// The name of physical group (`dim`, `tag`) in the table `names`, if it has one.
fn physical_name(names: &[PhysicalName], dim: u8, tag: i32) -> Option<&str> {
    names
        .iter()
        .find(|p| p.dim == dim && p.tag == tag)
        .map(|p| p.name.as_str())
}

/// The physical groups a part's mesh is taken from — the surfaces of a plane
/// part, the volumes of a solid one — and how messages name them.
struct Selection {
    /// Their dimension (2 surfaces, 3 volumes).
    dim: u8,
    /// The group as messages name it (`surface`, `volume`).
    what: &'static str,
    /// How the problem file leaves the selection out (to take every group).
    leave_out: &'static str,
    /// The element kinds such a group holds, as messages name them.
    kinds: &'static str,
}

/// A plane part's selection: physical surfaces of triangles and quadrilaterals.
const SURFACES: Selection = Selection {
    dim: 2,
    what: "surface",
    leave_out: "leave `surfaces` out",
    kinds: "3-node triangles or 4-node quadrilaterals",
};

impl Selection {
    /// The group tags `groups` refer to among the file's groups of this dimension
    /// `available` (`names` its physical-name table). A name that matches no named
    /// group may be a number ("3" for group 3).
    fn resolve(
        &self,
        file: &str,
        groups: &[Group],
        available: &[(i32, Option<&str>)],
        names: &[PhysicalName],
    ) -> std::result::Result<BTreeSet<i32>, String> {
        let what = self.what;
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
                let other = match g {
                    Group::Name(n) if names.iter().any(|p| p.dim != self.dim && &p.name == n) => {
                        format!(" ('{n}' is not a {what})")
                    }
                    _ => String::new(),
                };
                return Err(format!(
                    "file {file} has no physical {what} {g}{other}; its physical {what}s are: {}",
                    describe(available)
                ));
            }
            out.extend(found);
        }
        Ok(out)
    }

    /// The elements of the groups `groups` (all when `None`) of file `file` as
    /// (tag, file nodes): those of `first` (the simplices), then those of
    /// `second`, each in file order. `available` gives the file's groups of this
    /// dimension, `names` is its physical-name table. An empty selection, an
    /// unknown group or no element is an error.
    fn choose<'a, 'n, const A: usize, const B: usize>(
        &self,
        file: &str,
        groups: Option<&[Group]>,
        available: impl FnOnce() -> Vec<(i32, Option<&'n str>)>,
        names: &[PhysicalName],
        first: &'a [Element<A>],
        second: &'a [Element<B>],
    ) -> std::result::Result<Vec<(u64, &'a [usize])>, String> {
        let what = self.what;
        let selected = match groups {
            Some([]) => {
                return Err(format!(
                    "no physical {what} of file {file} is selected: list some, or {} to take them all",
                    self.leave_out
                ));
            }
            Some(groups) => Some(self.resolve(file, groups, &available(), names)?),
            None => None,
        };
        let picks = |physical: &[i32]| match &selected {
            None => true,
            Some(s) => physical.iter().any(|t| s.contains(t)),
        };
        let chosen: Vec<(u64, &[usize])> = first
            .iter()
            .filter(|e| picks(&e.physical))
            .map(|e| (e.tag, &e.nodes[..]))
            .chain(
                second
                    .iter()
                    .filter(|e| picks(&e.physical))
                    .map(|e| (e.tag, &e.nodes[..])),
            )
            .collect();
        if chosen.is_empty() {
            let scope = match groups {
                Some(groups) => format!(
                    " in physical {what}(s) {}",
                    groups
                        .iter()
                        .map(|g| g.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                None => String::new(),
            };
            return Err(format!("file {file} has no {}{scope}", self.kinds));
        }
        Ok(chosen)
    }
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
    /// A binary layout (little-endian, size_t width) to read the data in instead
    /// of the header's (to tell a header that does not match its data).
    layout: Option<(bool, usize)>,
    /// Binary: where the header's layout (data size, endianness marker) is given.
    layout_pos: usize,
    /// 4.1: physical tags of each entity (dim, tag).
    entities: HashMap<(i32, i32), Vec<i32>>,
    /// 4.1: the bounding box (min x, y, z, max x, y, z) of each entity (dim, tag);
    /// a point's is its position.
    entity_boxes: HashMap<(i32, i32), [f64; 6]>,
    seen_entities: bool,
    node_index: HashMap<u64, usize>,
    node_tags: Vec<u64>,
    /// (x, y, z) per node.
    coords: Vec<[f64; 3]>,
    /// Points (Gmsh type 15), for the physical points (node sets); not merged
    /// or checked as the other kinds are (a point is its node).
    points: Vec<Element<1>>,
    lines: Vec<Element<2>>,
    triangles: Vec<Element<3>>,
    quads: Vec<Element<4>>,
    tetrahedra: Vec<Element<4>>,
    hexahedra: Vec<Element<8>>,
    /// Where each element is in the file, per kind.
    line_meta: Vec<Meta>,
    triangle_meta: Vec<Meta>,
    quad_meta: Vec<Meta>,
    tetrahedron_meta: Vec<Meta>,
    hexahedron_meta: Vec<Meta>,
    seen_nodes: bool,
    seen_elements: bool,
}

/// Where an element is in the file (byte offset), for messages.
#[derive(Debug, Clone, Copy)]
struct Meta {
    at: usize,
}

impl<'a> Parser<'a> {
    fn new(data: &'a [u8], path: &'a Path, layout: Option<(bool, usize)>) -> Self {
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
            layout,
            layout_pos: 0,
            entities: HashMap::new(),
            entity_boxes: HashMap::new(),
            seen_entities: false,
            node_index: HashMap::new(),
            node_tags: Vec::new(),
            coords: Vec::new(),
            points: Vec::new(),
            lines: Vec::new(),
            triangles: Vec::new(),
            quads: Vec::new(),
            tetrahedra: Vec::new(),
            hexahedra: Vec::new(),
            line_meta: Vec::new(),
            triangle_meta: Vec::new(),
            quad_meta: Vec::new(),
            tetrahedron_meta: Vec::new(),
            hexahedron_meta: Vec::new(),
            seen_nodes: false,
            seen_elements: false,
        }
    }

    /// Reads a whole file (any dimension) and checks it (see [`GmshMesh::parse`]);
    /// the mesh is then taken out as a 2D ([`Parser::plane`]) or a 3D one.
    fn read(data: &'a [u8], path: &'a Path) -> Result<Parser<'a>> {
        let mut parser = Parser::new(data, path, None);
        let error = match parser.run() {
            Ok(()) => return Ok(parser),
            Err(e) => e,
        };
        if !parser.binary || parser.layout_pos == 0 {
            return Err(error);
        }
        // A binary file that fails: does its data read in another layout than
        // the one its header gives?
        let header = (parser.little_endian, parser.size_t);
        let sizes: &[usize] = match parser.version {
            MshVersion::V41 => &[8, 4],
            MshVersion::V22 => &[8],
        };
        for &size_t in sizes {
            for little_endian in [true, false] {
                let layout = (little_endian, size_t);
                if layout == header {
                    continue;
                }
                if Parser::new(data, path, Some(layout)).run().is_ok() {
                    return Err(parser.err_at(
                        parser.layout_pos,
                        format!(
                            "the binary header says {} but the data reads as {}: the header does not match the data (written by hand or by another program?); fix the header",
                            layout_text(header),
                            layout_text(layout)
                        ),
                    ));
                }
            }
        }
        Err(match error {
            // Name the layout when it is not the usual one.
            Error::Parse {
                path,
                line,
                message,
            } if header != (true, 8) => Error::Parse {
                path,
                line,
                message: format!(
                    "{message} (reading the binary data as {}, as the header says)",
                    layout_text(header)
                ),
            },
            e => e,
        })
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

    /// "line 12" (ASCII) or "byte 340" (binary) for the position `pos`.
    fn place(&self, pos: usize) -> String {
        if self.binary {
            format!("byte {pos}")
        } else {
            let line = self.data[..pos.min(self.data.len())]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            format!("line {line}")
        }
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

    /// The position of the next value: ASCII skips the whitespace before it
    /// (binary data has none).
    fn mark(&mut self) -> usize {
        if !self.binary {
            self.skip_whitespace();
        }
        self.pos
    }

    /// ASCII: the current line must end here (after spaces), so that a value
    /// missing from or added to a line is an error rather than a shift of every
    /// later value. Binary data has no lines.
    fn line_end(&mut self, what: &str) -> Result<()> {
        if self.binary {
            return Ok(());
        }
        while self.pos < self.data.len() && matches!(self.data[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        match self.data.get(self.pos) {
            None | Some(b'\n') => Ok(()),
            Some(_) => {
                let start = self.pos;
                let extra = self.token("the end of the line").unwrap_or("?");
                Err(self.err_at(
                    start,
                    format!("unexpected '{extra}' at the end of {what}: the line has more values than it should"),
                ))
            }
        }
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

    fn run(&mut self) -> Result<()> {
        if self.data.starts_with(b"\xEF\xBB\xBF") {
            return Err(self.err_at(
                0,
                "the file starts with a UTF-8 byte-order mark (bytes EF BB BF), which Gmsh does not write: save the file without a byte-order mark (e.g. \"UTF-8\" rather than \"UTF-8 with BOM\")",
            ));
        }
        self.skip_whitespace();
        let first = self.token("$MeshFormat").ok();
        if first != Some("$MeshFormat") {
            return Err(self.err_at(0, "not a Gmsh MSH file: it does not start with $MeshFormat"));
        }
        if self.data.get(self.pos) == Some(&b'\r') && self.data.get(self.pos + 1) != Some(&b'\n') {
            return Err(self.err_at(
                self.pos,
                "the lines of the file end in a carriage return alone (CR, classic Mac OS line endings): cfe reads lines ending in LF or CR LF; convert the file (e.g. `tr '\\r' '\\n' < old.msh > new.msh` for an ASCII file)",
            ));
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
                "$Entities" if self.version == MshVersion::V41 => {
                    if self.seen_entities {
                        return Err(self.err_at(start, "the file has two $Entities sections"));
                    }
                    if self.seen_elements {
                        return Err(self.err_at(
                            start,
                            "$Entities comes after $Elements: the element blocks could not find their physical groups",
                        ));
                    }
                    self.seen_entities = true;
                    self.entities_section()?
                }
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
        // A file with volume elements is a 3D mesh: its nodes are anywhere in
        // space, and its lines are not read into boundaries.
        let solid = self.is_solid();
        if !solid {
            self.check_planar()?;
        }
        if self.version == MshVersion::V41
            && !self.seen_entities
            && let Some(p) = self.physical_names.first()
        {
            return Err(Error::Parse {
                line: None,
                path: self.path.to_path_buf(),
                message: format!(
                    "the file names physical groups ('{}', ...) but has no $Entities section, which carries the physical groups of the elements in MSH 4.1: no element would be in any group",
                    p.name
                ),
            });
        }
        self.section = "$Elements";
        // Repeated elements: MSH 2.2 writes an element once per physical group it
        // is in (the copies are merged); any other repeat is an error.
        let (lines, line_meta) = {
            let (elements, meta) = (
                std::mem::take(&mut self.lines),
                std::mem::take(&mut self.line_meta),
            );
            self.merge_copies(elements, meta, 1)
        }?;
        let (triangles, triangle_meta) = {
            let (elements, meta) = (
                std::mem::take(&mut self.triangles),
                std::mem::take(&mut self.triangle_meta),
            );
            self.merge_copies(elements, meta, 2)
        }?;
        let (quads, quad_meta) = {
            let (elements, meta) = (
                std::mem::take(&mut self.quads),
                std::mem::take(&mut self.quad_meta),
            );
            self.merge_copies(elements, meta, 3)
        }?;
        (self.lines, self.line_meta) = (lines, line_meta);
        (self.triangles, self.triangle_meta) = (triangles, triangle_meta);
        (self.quads, self.quad_meta) = (quads, quad_meta);
        if solid {
            let tetrahedra = std::mem::take(&mut self.tetrahedra);
            let meta = std::mem::take(&mut self.tetrahedron_meta);
            (self.tetrahedra, self.tetrahedron_meta) = self.merge_copies(tetrahedra, meta, 4)?;
            let hexahedra = std::mem::take(&mut self.hexahedra);
            let meta = std::mem::take(&mut self.hexahedron_meta);
            (self.hexahedra, self.hexahedron_meta) = self.merge_copies(hexahedra, meta, 5)?;
        }
        self.check_element_tags()?;
        self.check_entity_groups()?;
        if solid {
            self.check_volume_elements()?;
            self.check_surface_faces()?;
        } else {
            self.check_curve_lines()?;
        }
        Ok(())
    }

    /// Whether the file holds volume elements (a 3D mesh).
    fn is_solid(&self) -> bool {
        !(self.tetrahedra.is_empty() && self.hexahedra.is_empty())
    }

    /// The 2D mesh read ([`run`](Parser::run) done): a file with volume elements
    /// is an error pointing at the first one.
    fn plane(&mut self) -> Result<GmshMesh> {
        if self.is_solid() {
            let (kind, tag, at) = [
                (
                    4,
                    self.tetrahedra.first().map(|e| e.tag),
                    self.tetrahedron_meta.first(),
                ),
                (
                    5,
                    self.hexahedra.first().map(|e| e.tag),
                    self.hexahedron_meta.first(),
                ),
            ]
            .into_iter()
            .filter_map(|(k, t, m)| Some((k, t?, m?.at)))
            .min_by_key(|&(_, _, at)| at)
            .expect("a solid file has a volume element");
            self.section = "$Elements";
            return Err(self.err_at(
                at,
                format!(
                    "{} is a volume element: file {} is a 3D mesh ({} tetrahedra, {} hexahedra), and a 2D part is meshed with triangles and quadrilaterals; 3D Gmsh files are read by the library (`cfe::mesh::gmsh::GmshMesh3d`), not yet from a problem file",
                    self.element_text(tag, kind, at),
                    self.file_name(),
                    self.tetrahedra.len(),
                    self.hexahedra.len(),
                ),
            ));
        }
        Ok(GmshMesh {
            path: self.path.to_path_buf(),
            version: self.version,
            binary: self.binary,
            node_tags: std::mem::take(&mut self.node_tags),
            nodes: self.coords.iter().map(|c| [c[0], c[1]]).collect(),
            points: std::mem::take(&mut self.points),
            lines: std::mem::take(&mut self.lines),
            triangles: std::mem::take(&mut self.triangles),
            quads: std::mem::take(&mut self.quads),
            physical_names: std::mem::take(&mut self.physical_names),
        })
    }

    /// "element 12 (3-node triangle, line 40)" for messages.
    fn element_text(&self, tag: u64, gmsh_type: i32, at: usize) -> String {
        format!(
            "element {tag} ({}, {})",
            element_type_name(gmsh_type),
            self.place(at)
        )
    }

    /// The elements of one kind (Gmsh type `gmsh_type`) with repeats removed: an
    /// element with the same nodes as an earlier one is, in MSH 2.2, a copy for
    /// another physical group of the same elementary entity (merged: the first
    /// one's tag and place, the union of the groups); any other repeat is an error
    /// naming both.
    fn merge_copies<const N: usize>(
        &self,
        elements: Vec<Element<N>>,
        meta: Vec<Meta>,
        gmsh_type: i32,
    ) -> Result<(Vec<Element<N>>, Vec<Meta>)> {
        let mut first: HashMap<[usize; N], usize> = HashMap::with_capacity(elements.len());
        let mut out: Vec<Element<N>> = Vec::with_capacity(elements.len());
        let mut out_meta: Vec<Meta> = Vec::with_capacity(elements.len());
        for (e, m) in elements.into_iter().zip(meta) {
            let mut key = e.nodes;
            key.sort_unstable();
            let Some(&i) = first.get(&key) else {
                first.insert(key, out.len());
                out.push(e);
                out_meta.push(m);
                continue;
            };
            let kept = &mut out[i];
            let adds_group = e.physical.iter().any(|p| !kept.physical.contains(p));
            if self.version == MshVersion::V22 && kept.entity == e.entity && adds_group {
                kept.physical.extend(e.physical);
                kept.physical.sort_unstable();
                kept.physical.dedup();
                continue;
            }
            let why = if self.version == MshVersion::V22 {
                "MSH 2.2 repeats an element only as a copy for another physical group of the same elementary entity"
            } else {
                "MSH 4.1 lists each element once"
            };
            return Err(self.err_at(
                m.at,
                format!(
                    "{} has the same nodes as {}: {why}; a repeated element is an overlap or a damaged node tag",
                    self.element_text(e.tag, gmsh_type, m.at),
                    self.element_text(kept.tag, gmsh_type, out_meta[i].at),
                ),
            ));
        }
        Ok((out, out_meta))
    }

    /// Element tags are unique (after MSH 2.2's copies are merged).
    fn check_element_tags(&self) -> Result<()> {
        let mut tags: Vec<(u64, usize, i32)> = Vec::with_capacity(
            self.lines.len()
                + self.triangles.len()
                + self.quads.len()
                + self.tetrahedra.len()
                + self.hexahedra.len(),
        );
        tags.extend(
            self.lines
                .iter()
                .zip(&self.line_meta)
                .map(|(e, m)| (e.tag, m.at, 1)),
        );
        tags.extend(
            self.triangles
                .iter()
                .zip(&self.triangle_meta)
                .map(|(e, m)| (e.tag, m.at, 2)),
        );
        tags.extend(
            self.quads
                .iter()
                .zip(&self.quad_meta)
                .map(|(e, m)| (e.tag, m.at, 3)),
        );
        tags.extend(
            self.tetrahedra
                .iter()
                .zip(&self.tetrahedron_meta)
                .map(|(e, m)| (e.tag, m.at, 4)),
        );
        tags.extend(
            self.hexahedra
                .iter()
                .zip(&self.hexahedron_meta)
                .map(|(e, m)| (e.tag, m.at, 5)),
        );
        tags.sort_unstable();
        if let Some(w) = tags.windows(2).find(|w| w[0].0 == w[1].0) {
            let (tag, at, t) = w[1];
            return Err(self.err_at(
                at,
                format!(
                    "{} has the tag of {}: element tags must be unique",
                    self.element_text(tag, t, at),
                    self.element_text(w[0].0, w[0].2, w[0].1)
                ),
            ));
        }
        Ok(())
    }

    /// The elements of one entity (dimension, tag) are in the same physical groups:
    /// groups are given to entities, so an element that differs (MSH 2.2 gives the
    /// groups per element) is damaged, and would be left out of its part or put in
    /// another.
    fn check_entity_groups(&self) -> Result<()> {
        // Per (dimension, entity): its first element's tag, groups, place and type.
        type First<'a> = (u64, &'a [i32], usize, i32);
        let mut first: HashMap<(u8, i32), First> = HashMap::new();
        let all = self
            .lines
            .iter()
            .map(|e| (e.tag, &e.physical[..], e.entity))
            .zip(self.line_meta.iter().map(|m| (1u8, 1, *m)))
            .chain(
                self.triangles
                    .iter()
                    .map(|e| (e.tag, &e.physical[..], e.entity))
                    .zip(self.triangle_meta.iter().map(|m| (2u8, 2, *m))),
            )
            .chain(
                self.quads
                    .iter()
                    .map(|e| (e.tag, &e.physical[..], e.entity))
                    .zip(self.quad_meta.iter().map(|m| (2u8, 3, *m))),
            )
            .chain(
                self.tetrahedra
                    .iter()
                    .map(|e| (e.tag, &e.physical[..], e.entity))
                    .zip(self.tetrahedron_meta.iter().map(|m| (3u8, 4, *m))),
            )
            .chain(
                self.hexahedra
                    .iter()
                    .map(|e| (e.tag, &e.physical[..], e.entity))
                    .zip(self.hexahedron_meta.iter().map(|m| (3u8, 5, *m))),
            );
        for ((tag, physical, entity), (dim, t, m)) in all {
            if entity == 0 {
                continue;
            }
            let (tag0, physical0, at0, t0) = *first
                .entry((dim, entity))
                .or_insert((tag, physical, m.at, t));
            if physical0 != physical {
                return Err(self.err_at(
                    m.at,
                    format!(
                        "{} of entity {} (dimension {dim}) is in physical group(s) {physical:?}, but {} of the same entity is in {physical0:?}: the elements of an entity share its physical groups",
                        self.element_text(tag, t, m.at),
                        entity,
                        self.element_text(tag0, t0, at0),
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every line of a physical curve is an edge of a triangle or quadrilateral of
    /// the file: a line that is not (a damaged node tag, or a curve of a surface
    /// whose elements are not in the file) would name no boundary, and a boundary
    /// would silently lose it.
    fn check_curve_lines(&self) -> Result<()> {
        let mut found: HashMap<(usize, usize), bool> = self
            .lines
            .iter()
            .filter(|l| !l.physical.is_empty())
            .map(|l| {
                (
                    (l.nodes[0].min(l.nodes[1]), l.nodes[0].max(l.nodes[1])),
                    false,
                )
            })
            .collect();
        if found.is_empty() {
            return Ok(());
        }
        let mut mark = |nodes: &[usize]| {
            for k in 0..nodes.len() {
                let (a, b) = (nodes[k], nodes[(k + 1) % nodes.len()]);
                if let Some(f) = found.get_mut(&(a.min(b), a.max(b))) {
                    *f = true;
                }
            }
        };
        self.triangles.iter().for_each(|e| mark(&e.nodes));
        self.quads.iter().for_each(|e| mark(&e.nodes));
        let stray = self.lines.iter().zip(&self.line_meta).find(|(l, _)| {
            !l.physical.is_empty()
                && !found[&(l.nodes[0].min(l.nodes[1]), l.nodes[0].max(l.nodes[1]))]
        });
        if let Some((l, m)) = stray {
            let curves = l
                .physical
                .iter()
                .map(|&t| {
                    match self
                        .physical_names
                        .iter()
                        .find(|p| p.dim == 1 && p.tag == t)
                    {
                        Some(p) => format!("'{}' ({t})", p.name),
                        None => t.to_string(),
                    }
                })
                .collect::<Vec<_>>()
                .join(", ");
            return Err(self.err_at(
                m.at,
                format!(
                    "{} of physical curve {curves}, from node {} to node {}, is not an edge of any triangle or quadrilateral of the file: a physical curve must run along element edges (a damaged node tag, or a curve whose surface is in no physical surface?)",
                    self.element_text(l.tag, 1, m.at),
                    self.node_tags[l.nodes[0]],
                    self.node_tags[l.nodes[1]],
                ),
            ));
        }
        Ok(())
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
        let size_start = {
            self.skip_whitespace();
            self.pos
        };
        let data_size: usize = self.ascii("the data size")?;
        match file_type {
            0 => {}
            1 => {
                self.binary = true;
                match (self.version, data_size) {
                    (MshVersion::V41, 4 | 8) | (MshVersion::V22, 8) => self.size_t = data_size,
                    _ => {
                        let expected = match self.version {
                            MshVersion::V41 => "8 (or 4, from a 32-bit machine)",
                            MshVersion::V22 => "8",
                        };
                        return Err(self.err_at(
                            size_start,
                            format!(
                                "the header gives data size {data_size} (the size of size_t); a binary MSH {version} file has data size {expected}"
                            ),
                        ));
                    }
                }
                self.next_line()?;
                let marker = self.pos;
                let one = self.bytes::<4>("the endianness marker (int 1)")?;
                let (le, be) = (i32::from_le_bytes(one), i32::from_be_bytes(one));
                self.little_endian = if le == 1 {
                    true
                } else if be == 1 {
                    false
                } else {
                    return Err(self.err_at(
                        marker,
                        format!(
                            "the endianness marker (the integer 1, after the format line) reads as {le} little-endian and {be} big-endian (bytes {one:02X?}): the binary header is damaged"
                        ),
                    ));
                };
                // The data's layout is known from here on.
                self.layout_pos = size_start;
                if let Some((little_endian, size_t)) = self.layout {
                    (self.little_endian, self.size_t) = (little_endian, size_t);
                }
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
        let mut by_tag: HashMap<(u8, i32), usize> = HashMap::new();
        let mut by_name: HashMap<(u8, String), usize> = HashMap::new();
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
            let i = self.physical_names.len();
            let earlier = [
                *by_tag.entry((dim, tag)).or_insert(i),
                *by_name.entry((dim, name.clone())).or_insert(i),
            ];
            if let Some(&j) = earlier.iter().find(|&&j| j != i) {
                let p = &self.physical_names[j];
                return Err(self.err(format!(
                    "physical name '{name}' (dimension {dim}, tag {tag}) repeats the tag or the name of '{}' (tag {}): each physical group of a dimension has one tag and one name",
                    p.name, p.tag
                )));
            }
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
                let mut bbox = [0.0; 6];
                for b in bbox.iter_mut().take(if dim == 0 { 3 } else { 6 }) {
                    *b = self.float("an entity coordinate")?;
                }
                if dim == 0 {
                    bbox.copy_within(0..3, 3);
                }
                self.entity_boxes.insert((dim as i32, tag), bbox);
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
        let header = self.mark();
        let blocks = self.size("the number of node blocks")?;
        let blocks = self.count(blocks, "number of node blocks")?;
        let total = self.size("the number of nodes")?;
        let total = self.count(total, "number of nodes")?;
        let min_tag = self.size("the smallest node tag")?;
        let max_tag = self.size("the largest node tag")?;
        self.line_end("the $Nodes header")?;
        self.node_tags.reserve(total);
        self.coords.reserve(total);
        for _ in 0..blocks {
            let block_start = self.mark();
            let dim = self.int("the entity dimension")?;
            let entity = self.int("the entity tag")?;
            let parametric = self.int("the parametric flag")?;
            let n = self.size("the number of nodes in the block")?;
            let n = self.count(n, "number of nodes in the block")?;
            self.line_end("a node block's header")?;
            if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
                return Err(self.err_at(
                    block_start,
                    format!(
                        "the node block of entity {entity} has dimension {dim} and parametric flag {parametric}: expected a dimension 0 to 3 and a flag 0 or 1"
                    ),
                ));
            }
            let start = self.pos;
            let mut tags = Vec::with_capacity(n);
            for _ in 0..n {
                tags.push(self.size("a node tag")?);
                self.line_end("a node tag's line")?;
            }
            let extra = if parametric == 1 { dim as usize } else { 0 };
            for tag in tags {
                let xyz = [self.float("x")?, self.float("y")?, self.float("z")?];
                for _ in 0..extra {
                    self.float("a parametric coordinate")?;
                }
                self.line_end("a node's coordinates")?;
                self.add_node(tag, xyz, start)?;
            }
        }
        if self.node_tags.len() != total {
            return Err(self.err_at(
                header,
                format!(
                    "the $Nodes header announces {total} nodes, but its blocks hold {}",
                    self.node_tags.len()
                ),
            ));
        }
        let lo = self.node_tags.iter().copied().min();
        let hi = self.node_tags.iter().copied().max();
        if let (Some(lo), Some(hi)) = (lo, hi)
            && (lo, hi) != (min_tag, max_tag)
        {
            return Err(self.err_at(
                header,
                format!(
                    "the $Nodes header gives node tags {min_tag} to {max_tag}, but the nodes' tags run from {lo} to {hi}"
                ),
            ));
        }
        Ok(())
    }

    fn nodes_22(&mut self) -> Result<()> {
        let n: u64 = self.ascii("the number of nodes")?;
        let n = self.count(n, "number of nodes")?;
        self.line_end("the number of nodes")?;
        self.node_tags.reserve(n);
        self.coords.reserve(n);
        if self.binary {
            self.next_line()?;
        }
        for _ in 0..n {
            if !self.binary {
                self.skip_whitespace();
            }
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
                let v = (
                    self.ascii("a node tag")?,
                    [self.ascii("x")?, self.ascii("y")?, self.ascii("z")?],
                );
                self.line_end("a node's line")?;
                v
            };
            self.add_node(tag, xyz, start)?;
        }
        Ok(())
    }

    /// The kind of Gmsh element type `t`, or the error for a type cfe does not read.
    fn kind(&self, t: i32, at: usize) -> Result<Kind> {
        if is_quadratic_volume(t) {
            return Err(self.err_at(
                at,
                format!(
                    "element type {t} ({}) in file {} is a second-order (quadratic) element, which cfe does not read: a quadratic face's nodal weights are zero or negative at its corners, which breaks the sign test of the bonded-in-compression law; mesh with first-order elements (Gmsh: Mesh.ElementOrder = 1) into 4-node tetrahedra or 8-node hexahedra",
                    element_type_name(t),
                    self.file_name()
                ),
            ));
        }
        Kind::from_type(t).ok_or_else(|| {
            self.err_at(
                at,
                format!(
                    "element type {t} ({}) in file {} is not supported: cfe reads 3-node triangles and 4-node quadrilaterals (and 2-node lines and points for physical groups), and in 3D 4-node tetrahedra and 8-node hexahedra (a hex-dominant mesh's prisms and pyramids are not read: mesh the volume with tetrahedra, or with hexahedra alone)",
                    element_type_name(t),
                    self.file_name()
                ),
            )
        })
    }

    /// How far (2 % of the model's size) a node may lie outside its entity's
    /// bounding box: Gmsh samples a curved entity to bound it, and the sampled box
    /// can miss a node on the curve (by 0.24 % of the model's size in
    /// examples/roller_in_cradle/roller.msh).
    fn box_slack(&self) -> f64 {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for c in &self.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        let d2: f64 = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum();
        0.02 * d2.sqrt()
    }

    /// 4.1: the nodes of an element lie in the bounding box `$Entities` gives its
    /// entity (up to `slack`): an element block given another entity of the same
    /// dimension would put its elements in that entity's physical groups. Boxes of
    /// all zeros (written by programs that do not compute them) are not checked.
    #[allow(clippy::too_many_arguments)]
    fn check_in_box(
        &self,
        dim: i32,
        entity: i32,
        tag: u64,
        gmsh_type: i32,
        node_tags: &[u64],
        slack: f64,
        at: usize,
    ) -> Result<()> {
        let Some(b) = self.entity_boxes.get(&(dim, entity)) else {
            return Ok(());
        };
        if b.iter().all(|&v| v == 0.0) {
            return Ok(());
        }
        for t in node_tags {
            let x = self.coords[self.node_index[t]];
            if (0..3).any(|k| x[k] < b[k] - slack || x[k] > b[k + 3] + slack) {
                return Err(self.err_at(
                    at,
                    format!(
                        "{} of entity {entity} (dimension {dim}) has node {t} at ({}, {}, {}), outside the entity's bounding box ({}, {}, {}) to ({}, {}, {}) in $Entities: the element is not in its entity (a damaged entity tag?)",
                        self.element_text(tag, gmsh_type, at),
                        x[0], x[1], x[2], b[0], b[1], b[2], b[3], b[4], b[5]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Stores one element, its node tags resolved to node indices.
    fn add_element(
        &mut self,
        kind: Kind,
        tag: u64,
        node_tags: &[u64],
        physical: Vec<i32>,
        entity: i32,
        at: usize,
    ) -> Result<()> {
        let meta = Meta { at };
        let mut nodes = [0usize; MAX_NODES];
        for (slot, &t) in nodes.iter_mut().zip(node_tags) {
            *slot = *self.node_index.get(&t).ok_or_else(|| {
                self.err_at(
                    at,
                    format!(
                        "element {tag} ({}) refers to node {t}, which is not defined in $Nodes",
                        element_type_name(kind.gmsh_type())
                    ),
                )
            })?;
        }
        match kind {
            Kind::Point => self.points.push(Element {
                tag,
                nodes: [nodes[0]],
                physical,
                entity,
            }),
            Kind::Line => {
                self.lines.push(Element {
                    tag,
                    nodes: [nodes[0], nodes[1]],
                    physical,
                    entity,
                });
                self.line_meta.push(meta);
            }
            Kind::Triangle => {
                self.triangles.push(Element {
                    tag,
                    nodes: [nodes[0], nodes[1], nodes[2]],
                    physical,
                    entity,
                });
                self.triangle_meta.push(meta);
            }
            Kind::Quad => {
                self.quads.push(Element {
                    tag,
                    nodes: [nodes[0], nodes[1], nodes[2], nodes[3]],
                    physical,
                    entity,
                });
                self.quad_meta.push(meta);
            }
            Kind::Tetrahedron => {
                self.tetrahedra.push(Element {
                    tag,
                    nodes: [nodes[0], nodes[1], nodes[2], nodes[3]],
                    physical,
                    entity,
                });
                self.tetrahedron_meta.push(meta);
            }
            Kind::Hexahedron => {
                self.hexahedra.push(Element {
                    tag,
                    nodes,
                    physical,
                    entity,
                });
                self.hexahedron_meta.push(meta);
            }
        }
        Ok(())
    }

    fn elements_41(&mut self) -> Result<()> {
        if self.binary {
            self.next_line()?;
        }
        let header = self.mark();
        let blocks = self.size("the number of element blocks")?;
        let blocks = self.count(blocks, "number of element blocks")?;
        let total = self.size("the number of elements")?;
        let min_tag = self.size("the smallest element tag")?;
        let max_tag = self.size("the largest element tag")?;
        self.line_end("the $Elements header")?;
        let mut node_tags = [0u64; MAX_NODES];
        let mut read = 0u64;
        let (mut lo, mut hi) = (u64::MAX, 0u64);
        let slack = self.box_slack();
        for _ in 0..blocks {
            let block_start = self.mark();
            let dim = self.int("the entity dimension")?;
            let entity = self.int("the entity tag")?;
            let t = self.int("the element type")?;
            let kind = self.kind(t, block_start)?;
            let n = self.size("the number of elements in the block")?;
            let n = self.count(n, "number of elements in the block")?;
            self.line_end("an element block's header")?;
            let fits = kind.dim();
            if dim != fits {
                return Err(self.err_at(
                    block_start,
                    format!(
                        "the element block of entity {entity} has dimension {dim}, but its elements ({}s, type {t}) have dimension {fits}",
                        element_type_name(t)
                    ),
                ));
            }
            let physical = match self.entities.get(&(dim, entity)) {
                Some(p) => p.clone(),
                None if self.seen_entities => {
                    return Err(self.err_at(
                        block_start,
                        format!(
                            "the element block of {n} {}s is in entity {entity} of dimension {dim}, which $Entities does not list: its elements' physical groups are unknown",
                            element_type_name(t)
                        ),
                    ));
                }
                None => Vec::new(),
            };
            for _ in 0..n {
                let start = self.mark();
                let tag = self.size("an element tag")?;
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    *slot = self.size("a node tag")?;
                }
                self.line_end("an element's line")?;
                lo = lo.min(tag);
                hi = hi.max(tag);
                self.add_element(
                    kind,
                    tag,
                    &node_tags[..kind.node_count()],
                    physical.clone(),
                    entity,
                    start,
                )?;
                self.check_in_box(
                    dim,
                    entity,
                    tag,
                    t,
                    &node_tags[..kind.node_count()],
                    slack,
                    start,
                )?;
            }
            read += n as u64;
        }
        if read != total {
            return Err(self.err_at(
                header,
                format!(
                    "the $Elements header announces {total} elements, but its blocks hold {read}"
                ),
            ));
        }
        if read > 0 && (lo, hi) != (min_tag, max_tag) {
            return Err(self.err_at(
                header,
                format!(
                    "the $Elements header gives element tags {min_tag} to {max_tag}, but the elements' tags run from {lo} to {hi}"
                ),
            ));
        }
        Ok(())
    }

    fn elements_22(&mut self) -> Result<()> {
        let n: u64 = self.ascii("the number of elements")?;
        let n = self.count(n, "number of elements")?;
        self.line_end("the number of elements")?;
        let mut node_tags = [0u64; MAX_NODES];
        if !self.binary {
            for _ in 0..n {
                self.skip_whitespace();
                let start = self.pos;
                let tag: u64 = self.ascii("an element tag")?;
                let t: i32 = self.ascii("an element type")?;
                let kind = self.kind(t, start)?;
                let ntags: usize = self.ascii("the number of tags")?;
                let mut physical = Vec::new();
                let mut entity = 0;
                for k in 0..ntags {
                    let v: i32 = self.ascii("a tag")?;
                    match k {
                        0 if v != 0 => physical.push(v),
                        1 => entity = v,
                        _ => {}
                    }
                }
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    *slot = self.ascii("a node tag")?;
                }
                self.line_end("an element's line")?;
                self.add_element(
                    kind,
                    tag,
                    &node_tags[..kind.node_count()],
                    physical,
                    entity,
                    start,
                )?;
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
                let mut entity = 0;
                for k in 0..ntags {
                    let v = self.bin_i32("a tag")?;
                    match k {
                        0 if v != 0 => physical.push(v),
                        1 => entity = v,
                        _ => {}
                    }
                }
                for slot in node_tags.iter_mut().take(kind.node_count()) {
                    let v = self.bin_i32("a node tag")?;
                    *slot = u64::try_from(v).unwrap_or(u64::MAX);
                }
                let tag = u64::try_from(tag)
                    .map_err(|_| self.err_at(start, format!("negative element tag {tag}")))?;
                self.add_element(
                    kind,
                    tag,
                    &node_tags[..kind.node_count()],
                    physical,
                    entity,
                    start,
                )?;
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
