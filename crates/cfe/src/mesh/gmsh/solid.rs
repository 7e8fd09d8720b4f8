//! Gmsh 3D meshes: a file with volume elements (4-node tetrahedra, Gmsh type 4,
//! and 8-node hexahedra, type 5) read into a [`GmshMesh3d`], and the solid part
//! meshes ([`Mesh<D3>`]) built from its physical volumes, with named boundaries
//! from its physical surfaces.
//!
//! The file is parsed by the same reader as a 2D one (MSH 2.2 and 4.1, ASCII and
//! binary, with the same checks); a file is 3D when it holds volume elements. In
//! 3D, triangles (type 2) and quadrilaterals (type 3) are surface elements, read
//! for the physical surfaces; points and lines are read and dropped. Second-order
//! volume elements, prisms and pyramids are refused while the file is read.

use super::{
    Element, Group, MshVersion, Parser, PhysicalName, Selection, UNUSED, physical_groups_in,
    physical_name,
};
use crate::dim::D3;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryFace, FaceNodes, Mesh, NodeSet, SolidElement};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// A 3D Gmsh mesh as read from a file: its nodes in space, its volume elements
/// and the surface elements that carry its physical surfaces, in the file's order.
#[derive(Debug, Clone, PartialEq)]
pub struct GmshMesh3d {
    /// The file it was read from (used in messages).
    pub path: PathBuf,
    /// Format version.
    pub version: MshVersion,
    /// Binary (true) or ASCII file.
    pub binary: bool,
    /// The tag of each node (same order as `nodes`).
    pub node_tags: Vec<u64>,
    /// Node coordinates (x, y, z), in the order of `$Nodes`.
    pub nodes: Vec<[f64; 3]>,
    /// Points (Gmsh type 15): node sets, through their physical points.
    pub points: Vec<Element<1>>,
    /// 2-node lines (Gmsh type 1): node sets, through their physical curves.
    pub lines: Vec<Element<2>>,
    /// 3-node triangles (Gmsh type 2): boundary faces, through their physical
    /// surfaces.
    pub triangles: Vec<Element<3>>,
    /// 4-node quadrilaterals (Gmsh type 3): boundary faces, through their physical
    /// surfaces.
    pub quads: Vec<Element<4>>,
    /// 4-node tetrahedra (Gmsh type 4), nodes in the file's order.
    pub tetrahedra: Vec<Element<4>>,
    /// 8-node hexahedra (Gmsh type 5), nodes in the file's order.
    pub hexahedra: Vec<Element<8>>,
    /// The physical-name table.
    pub physical_names: Vec<PhysicalName>,
}

/// A Gmsh file of either dimension, as its elements make it: a file with volume
/// elements is 3D, any other a plane mesh.
#[derive(Debug, Clone, PartialEq)]
pub enum GmshFile {
    /// A plane mesh (triangles and quadrilaterals, no volume element), exactly as
    /// [`GmshMesh::parse`](super::GmshMesh::parse) reads it.
    Plane(super::GmshMesh),
    /// A solid mesh (tetrahedra and hexahedra).
    Solid(GmshMesh3d),
}

impl GmshFile {
    /// Reads and parses the file at `path` (the same file checks as
    /// [`GmshMesh::read`](super::GmshMesh::read)).
    pub fn read(path: &Path) -> Result<GmshFile> {
        GmshFile::parse(&super::file_bytes(path)?, path)
    }

    /// Parses the contents of an MSH file of either dimension; `path` is used in
    /// messages.
    pub fn parse(data: &[u8], path: &Path) -> Result<GmshFile> {
        let mut parser = Parser::read(data, path)?;
        Ok(if parser.is_solid() {
            GmshFile::Solid(parser.solid()?)
        } else {
            GmshFile::Plane(parser.plane()?)
        })
    }

    /// The dimension of the mesh: 2 or 3.
    pub fn dimension(&self) -> usize {
        match self {
            GmshFile::Plane(_) => 2,
            GmshFile::Solid(_) => 3,
        }
    }
}

/// The dimension (2 or 3) of an ASCII MSH 2.2 or 4.1 file's contents `data`
/// from its `$Elements` section alone (a file is 3D when it holds a 4-node
/// tetrahedron or an 8-node hexahedron, Gmsh types 4 and 5, as
/// [`GmshFile::dimension`] says of the parsed file), without reading its
/// nodes: the element lines are skipped by their count, only their types
/// read. `None` for a binary file or anything this light reading does not
/// follow (the file is then parsed: [`GmshFile::parse`]).
pub fn peek_dimension(data: &[u8]) -> Option<usize> {
    let text = std::str::from_utf8(data.get(..data.len().min(1 << 12))?).ok()?;
    let mut lines = text.lines();
    if lines.next()?.trim() != "$MeshFormat" {
        return None;
    }
    let mut format = lines.next()?.split_whitespace();
    let version = format.next()?;
    if format.next()? != "0" {
        return None; // binary
    }
    let start = find(data, b"\n$Elements")? + 10;
    let body = std::str::from_utf8(&data[start..]).ok()?;
    let mut lines = body.lines().map(str::trim).filter(|l| !l.is_empty());
    let solid = |t: u32| t == 4 || t == 5;
    let mut header = lines.next()?.split_whitespace();
    match version {
        "4.1" => {
            let blocks: usize = header.next()?.parse().ok()?;
            for _ in 0..blocks {
                let mut block = lines.next()?.split_whitespace();
                let (_dim, _tag) = (block.next()?, block.next()?);
                let kind: u32 = block.next()?.parse().ok()?;
                let count: usize = block.next()?.parse().ok()?;
                if solid(kind) {
                    return Some(3);
                }
                for _ in 0..count {
                    lines.next()?;
                }
            }
            (lines.next()? == "$EndElements").then_some(2)
        }
        "2.2" => {
            let count: usize = header.next()?.parse().ok()?;
            for _ in 0..count {
                let kind: u32 = lines.next()?.split_whitespace().nth(1)?.parse().ok()?;
                if solid(kind) {
                    return Some(3);
                }
            }
            (lines.next()? == "$EndElements").then_some(2)
        }
        _ => None,
    }
}

/// The first position of `needle` in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// Reads the 3D Gmsh file at `path` into one solid part per physical volume
/// (named by its physical name, or by its number when it has none), in the order
/// of their tags: [`GmshMesh3d::read`] then [`GmshMesh3d::parts`].
pub fn read_gmsh_3d(path: &Path) -> Result<Vec<(String, Mesh<D3>)>> {
    GmshMesh3d::read(path)?.parts()
}

/// The sorted corners of a face (a triangle's padded with [`UNUSED`]): the key
/// under which the faces with the same nodes meet.
fn face_key(nodes: &[usize]) -> [usize; 4] {
    let mut key = [UNUSED; 4];
    key[..nodes.len()].copy_from_slice(nodes);
    key.sort_unstable();
    key
}

/// A face's corners turned to start at its smallest node (its cyclic order
/// kept), padded with [`UNUSED`]: two faces with the same corners run the same way
/// round exactly when these are equal.
fn cyclic(nodes: &[usize]) -> [usize; 4] {
    let first = (0..nodes.len()).min_by_key(|&k| nodes[k]).unwrap_or(0);
    let mut out = [UNUSED; 4];
    for (k, slot) in out.iter_mut().take(nodes.len()).enumerate() {
        *slot = nodes[(first + k) % nodes.len()];
    }
    out
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · (b × c).
fn triple(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1])
        + a[1] * (b[2] * c[0] - b[0] * c[2])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

fn length(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The Gmsh (and VTK) node of a HEX8 at natural corner (ξ, η, ζ), each ±1
/// (`true` for +1): the bottom face 0-1-2-3, the top 4-7 above it.
fn hex_node(xi: bool, eta: bool, zeta: bool) -> usize {
    let bottom = match (xi, eta) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    };
    bottom + if zeta { 4 } else { 0 }
}

/// The Jacobian determinants of a HEX8's trilinear map at its eight corners
/// (× 8: each column the edge from the corner's −1 neighbour to its +1 one), in
/// Gmsh node order. All positive for a valid element.
pub(crate) fn hex8_corner_jacobians(x: &[[f64; 3]; 8]) -> [f64; 8] {
    let mut out = [0.0; 8];
    for (c, j) in out.iter_mut().enumerate() {
        let (xi, eta, zeta) = (matches!(c % 4, 1 | 2), matches!(c % 4, 2 | 3), c >= 4);
        let a = sub(x[hex_node(true, eta, zeta)], x[hex_node(false, eta, zeta)]);
        let b = sub(x[hex_node(xi, true, zeta)], x[hex_node(xi, false, zeta)]);
        let d = sub(x[hex_node(xi, eta, true)], x[hex_node(xi, eta, false)]);
        *j = triple(a, b, d);
    }
    out
}

/// Six times the signed volume of a TET4 (positive when node 3 lies on the side
/// of face 0-1-2 its right-hand normal points to).
pub(crate) fn tet4_six_volume(x: &[[f64; 3]; 4]) -> f64 {
    triple(sub(x[1], x[0]), sub(x[2], x[0]), sub(x[3], x[0]))
}

/// Whether the volume element `tag` with file nodes `nodes` (4: TET4, 8: HEX8)
/// has a negative volume throughout (`true`: to be mirrored) or a positive one
/// (`false`); a degenerate element (volume or a corner Jacobian within 1e-10 h³ of
/// zero, h its longest edge) or a hexahedron whose corner Jacobians differ in sign
/// is an error message naming it and its nodes by their tags.
fn orientation(
    tag: u64,
    nodes: &[usize],
    coords: &[[f64; 3]],
    node_tags: &[u64],
) -> std::result::Result<bool, String> {
    let x = |k: usize| coords[nodes[k]];
    let edges: &[[usize; 2]] = if nodes.len() == 4 {
        &crate::mesh::TET4_EDGES
    } else {
        &crate::mesh::HEX8_EDGES
    };
    let h = edges
        .iter()
        .map(|&[a, b]| length(sub(x(a), x(b))))
        .fold(0.0, f64::max);
    let tol = 1e-10 * h * h * h;
    let nodes_text = || {
        nodes
            .iter()
            .map(|&n| node_tags[n].to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if nodes.len() == 4 {
        let v6 = tet4_six_volume(&[x(0), x(1), x(2), x(3)]);
        // Not above the tolerance: degenerate (or not a number).
        let spans = v6.abs() > tol;
        if !spans {
            return Err(format!(
                "element {tag} (4-node tetrahedron) is degenerate: nodes {} span a volume of {:e}",
                nodes_text(),
                v6 / 6.0
            ));
        }
        return Ok(v6 < 0.0);
    }
    let corners: [[f64; 3]; 8] = std::array::from_fn(x);
    let j = hex8_corner_jacobians(&corners);
    let positive = j.iter().all(|&v| v > tol);
    let negative = j.iter().all(|&v| v < -tol);
    if positive || negative {
        return Ok(negative);
    }
    let (k, worst) = j
        .iter()
        .copied()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("eight corners");
    let signs = j
        .iter()
        .map(|&v| {
            if v > tol {
                "+"
            } else if v < -tol {
                "−"
            } else {
                "0"
            }
        })
        .collect::<Vec<_>>()
        .join(" ");
    let [a, b, c] = x(k);
    Err(format!(
        "element {tag} (8-node hexahedron) is inverted or degenerate: the signs of its Jacobian at its corners (nodes {}) are {signs}, e.g. {worst:e} at node {} ({a}, {b}, {c}); every corner of a hexahedron must have a positive Jacobian (a folded or twisted element, or nodes out of Gmsh's order)",
        nodes_text(),
        node_tags[nodes[k]],
    ))
}

/// How an element's faces are used in a part: by how many elements, and the
/// first one's outward face.
#[derive(Debug, Clone, Copy)]
struct FaceUse {
    count: usize,
    face: BoundaryFace,
}

/// A node set in the making: its nodes and its edges.
type NodesAndEdges = (Vec<usize>, Vec<[usize; 2]>);

/// A solid part's selection: physical volumes of tetrahedra and hexahedra.
const VOLUMES: Selection = Selection {
    dim: 3,
    what: "volume",
    leave_out: "leave the selection out",
    kinds: "4-node tetrahedra or 8-node hexahedra",
};

impl GmshMesh3d {
    /// Reads and parses the 3D file at `path` (a regular file of at most
    /// [`MESH_FILE_CAP`](crate::mesh::input_file::MESH_FILE_CAP) bytes).
    pub fn read(path: &Path) -> Result<GmshMesh3d> {
        GmshMesh3d::parse(&super::file_bytes(path)?, path)
    }

    /// Parses the contents of a 3D MSH file; `path` is used in messages. The file
    /// is read and checked as [`GmshMesh::parse`](super::GmshMesh::parse) reads
    /// a plane one, except that its nodes lie anywhere in space and its lines are
    /// not checked; further, every element of a physical surface must be a face
    /// of a volume element of the file (else an error naming the surface and the
    /// element). Second-order volume elements are refused: their faces' nodal
    /// weights are zero or negative at the corners, which breaks the sign test of
    /// the bonded-in-compression law. A file without volume elements is an error
    /// (it is a plane mesh: [`GmshMesh::parse`](super::GmshMesh::parse)).
    pub fn parse(data: &[u8], path: &Path) -> Result<GmshMesh3d> {
        Parser::read(data, path)?.solid()
    }

    /// The physical groups of dimension `dim` (0 points, 1 curves, 2 surfaces,
    /// 3 volumes): every tag that has a name or is used by an element, with its
    /// name if it has one, ascending.
    pub fn physical_groups(&self, dim: u8) -> Vec<(i32, Option<&str>)> {
        let used: Vec<&[i32]> = match dim {
            0 => self.points.iter().map(|e| &e.physical[..]).collect(),
            1 => self.lines.iter().map(|e| &e.physical[..]).collect(),
            2 => (self.triangles.iter().map(|e| &e.physical[..]))
                .chain(self.quads.iter().map(|e| &e.physical[..]))
                .collect(),
            3 => (self.tetrahedra.iter().map(|e| &e.physical[..]))
                .chain(self.hexahedra.iter().map(|e| &e.physical[..]))
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

    /// `'name' (tag)`, or the tag alone, for physical group (`dim`, `tag`).
    fn group_text(&self, dim: u8, tag: i32) -> String {
        match self.name(dim, tag) {
            Some(n) => format!("'{n}' ({tag})"),
            None => tag.to_string(),
        }
    }

    /// One solid part per physical volume, in the order of their tags, each
    /// named by its physical name (by its number when it has none) and built by
    /// [`GmshMesh3d::part_mesh`] from that volume alone. A file without physical
    /// volumes is an error (take its elements as one part with
    /// `part_mesh(name, None)`).
    pub fn parts(&self) -> Result<Vec<(String, Mesh<D3>)>> {
        let volumes = self.physical_groups(3);
        if volumes.is_empty() {
            return Err(Error::Parse {
                line: None,
                path: self.path.clone(),
                message: format!(
                    "file {} has no physical volume to make parts of: name each part's volume in Gmsh (Physical Volume), or take every element as one part",
                    self.file_name()
                ),
            });
        }
        let mut names = BTreeSet::new();
        let mut parts = Vec::with_capacity(volumes.len());
        for (tag, name) in volumes {
            let name = name.map(str::to_string).unwrap_or_else(|| tag.to_string());
            if !names.insert(name.clone()) {
                return Err(Error::Parse {
                    line: None,
                    path: self.path.clone(),
                    message: format!(
                        "file {} has two physical volumes that make a part named '{name}' (one named '{name}', one numbered {name}): rename one",
                        self.file_name()
                    ),
                });
            }
            let mesh = self.part_mesh(&name, Some(&[Group::Tag(tag)]))?;
            parts.push((name, mesh));
        }
        Ok(parts)
    }

    /// Builds the solid mesh of part `part` from the volume elements of the
    /// physical volumes `volumes` (every volume element of the file when `None`).
    ///
    /// Only the nodes those elements use are kept, renumbered in file order; the
    /// elements are the tetrahedra (TET4) then the hexahedra (HEX8), each in file
    /// order. An element whose node order gives it a negative volume throughout is
    /// mirrored (as a clockwise triangle is flipped in 2D; Gmsh writes positive
    /// ones); a degenerate element, or a hexahedron whose corner Jacobians differ
    /// in sign (inverted at some corners), is an error naming its tag. The elements
    /// must fit together: a face used by three elements, or by two on the same
    /// side of it, is an error.
    ///
    /// Each physical surface whose elements lie on the part's boundary becomes a
    /// named boundary (`Mesh::boundaries`; a surface without a name is named by its
    /// number): the part's boundary faces with the nodes of its triangles and
    /// quadrilaterals, oriented outward from the part, in file order. Surfaces with
    /// no element on the part's boundary (on another part, or wholly inside this
    /// one) are left out. A surface with elements both on the part's boundary and
    /// inside it (a face of two of its elements), or on none of its faces though
    /// between its nodes, is an error naming the surface and the element.
    pub fn part_mesh(&self, part: &str, volumes: Option<&[Group]>) -> Result<Mesh<D3>> {
        let err = |message: String| Error::Mesh {
            part: part.to_string(),
            message,
        };
        let chosen = self.chosen_elements(volumes).map_err(err)?;
        // The nodes used, renumbered in file order.
        let mut local = vec![UNUSED; self.nodes.len()];
        for (_, nodes) in &chosen {
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
        let elements = self.oriented_elements(&chosen, &local).map_err(err)?;
        let faces = self.face_uses(&elements, &chosen, &file_of).map_err(err)?;
        let boundaries = self.named_boundaries(&faces, &local).map_err(err)?;
        let node_sets = self.named_node_sets(&local);
        Ok(Mesh {
            nodes,
            elements,
            boundaries,
            node_sets,
        })
    }

    /// The named node sets of a part (`local`: the file's nodes in the part's
    /// numbering, or [`UNUSED`]) from the physical points and curves: each
    /// group's points and line ends that are nodes of the part, its lines
    /// with both ends in the part kept as the set's edges (along which
    /// `--refine` adds nodes). A group without a node in the part is left out;
    /// a point and a curve group of the same name make one set.
    fn named_node_sets(&self, local: &[usize]) -> BTreeMap<String, NodeSet> {
        let mut by_group: BTreeMap<(u8, i32), NodesAndEdges> = BTreeMap::new();
        for e in &self.points {
            let n = local[e.nodes[0]];
            if n != UNUSED {
                for &p in &e.physical {
                    by_group.entry((0, p)).or_default().0.push(n);
                }
            }
        }
        for e in &self.lines {
            let [a, b] = e.nodes.map(|n| local[n]);
            for &p in &e.physical {
                let (nodes, edges) = by_group.entry((1, p)).or_default();
                nodes.extend([a, b].into_iter().filter(|&n| n != UNUSED));
                if a != UNUSED && b != UNUSED {
                    edges.push([a, b]);
                }
            }
        }
        let mut sets: BTreeMap<String, NodesAndEdges> = BTreeMap::new();
        for ((dim, p), (nodes, edges)) in by_group {
            if nodes.is_empty() {
                continue;
            }
            let name = (self.name(dim, p).map(str::to_string)).unwrap_or_else(|| p.to_string());
            let set = sets.entry(name).or_default();
            set.0.extend(nodes);
            set.1.extend(edges);
        }
        (sets.into_iter())
            .map(|(name, (nodes, edges))| (name, NodeSet::new(nodes, edges)))
            .collect()
    }

    /// The elements of the physical volumes `volumes` (all when `None`) as (tag,
    /// file nodes), tetrahedra then hexahedra, each in file order
    /// ([`Selection::choose`]).
    fn chosen_elements(
        &self,
        volumes: Option<&[Group]>,
    ) -> std::result::Result<Vec<(u64, &[usize])>, String> {
        VOLUMES.choose(
            &self.file_name(),
            volumes,
            || self.physical_groups(3),
            &self.physical_names,
            &self.tetrahedra,
            &self.hexahedra,
        )
    }

    /// "node 12 (0, 1, 0.5)" for file node `n`.
    fn node_text(&self, n: usize) -> String {
        let [x, y, z] = self.nodes[n];
        format!("node {} ({x}, {y}, {z})", self.node_tags[n])
    }

    /// The `chosen` elements in the part's numbering (`local`), of positive volume
    /// (a negative one mirrored); a degenerate or inverted one is an error.
    fn oriented_elements(
        &self,
        chosen: &[(u64, &[usize])],
        local: &[usize],
    ) -> std::result::Result<Vec<SolidElement>, String> {
        let mut elements = Vec::with_capacity(chosen.len());
        for (tag, file_nodes) in chosen {
            let negative = orientation(*tag, file_nodes, &self.nodes, &self.node_tags)
                .map_err(|m| format!("{m} (file {})", self.file_name()))?;
            let l = |k: usize| local[file_nodes[k]];
            elements.push(match file_nodes.len() {
                4 => {
                    let n = [l(0), l(1), l(2), l(3)];
                    SolidElement::Tet4(if negative {
                        [n[0], n[2], n[1], n[3]]
                    } else {
                        n
                    })
                }
                _ => {
                    let n: [usize; 8] = std::array::from_fn(l);
                    SolidElement::Hex8(if negative {
                        [n[0], n[3], n[2], n[1], n[4], n[7], n[6], n[5]]
                    } else {
                        n
                    })
                }
            });
        }
        Ok(elements)
    }

    /// Every face of the part's `elements`, by its sorted nodes: how many elements
    /// use it (1 on the part's boundary, 2 inside) and the first one's outward
    /// face. A face used by three elements, or by two that lie on the same side of
    /// it, is an error naming the elements by their tags (`chosen`) and the nodes
    /// by theirs (`file_of`).
    fn face_uses(
        &self,
        elements: &[SolidElement],
        chosen: &[(u64, &[usize])],
        file_of: &[usize],
    ) -> std::result::Result<HashMap<[usize; 4], FaceUse>, String> {
        let mut uses: HashMap<[usize; 4], FaceUse> = HashMap::with_capacity(4 * elements.len());
        let nodes_text = |f: &FaceNodes| {
            f.as_slice()
                .iter()
                .map(|&n| self.node_tags[file_of[n]].to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (e, el) in elements.iter().enumerate() {
            for f in 0..el.face_count() {
                let nodes = el.face(f);
                let face = BoundaryFace {
                    nodes,
                    element: e,
                    face: f,
                };
                let key = face_key(nodes.as_slice());
                let u = uses.entry(key).or_insert(FaceUse { count: 0, face });
                u.count += 1;
                let first = u.face;
                match u.count {
                    1 => {}
                    2 => {
                        let reversed: Vec<usize> = nodes.as_slice().iter().rev().copied().collect();
                        if cyclic(first.nodes.as_slice()) != cyclic(&reversed) {
                            return Err(format!(
                                "elements {} and {} of file {} lie on the same side of their common face (nodes {}): one folds over the other (overlapping elements?)",
                                chosen[first.element].0,
                                chosen[e].0,
                                self.file_name(),
                                nodes_text(&nodes),
                            ));
                        }
                    }
                    _ => {
                        return Err(format!(
                            "element {} of file {} has the face with nodes {} that element {} and another element already have: a face can bound two elements at most (overlapping elements?)",
                            chosen[e].0,
                            self.file_name(),
                            nodes_text(&nodes),
                            chosen[first.element].0,
                        ));
                    }
                }
            }
        }
        Ok(uses)
    }

    /// The named boundaries of a part from the physical surfaces whose elements are
    /// its boundary faces (`faces`: the part's faces by sorted nodes; `local`: the
    /// file's nodes in the part's numbering, or [`UNUSED`]).
    fn named_boundaries(
        &self,
        faces: &HashMap<[usize; 4], FaceUse>,
        local: &[usize],
    ) -> std::result::Result<BTreeMap<String, Vec<BoundaryFace>>, String> {
        // Per physical surface: its faces on the part's boundary; its first
        // element inside the part (and how many); its first element between the
        // part's nodes that is no face of the part.
        let mut by_tag: BTreeMap<i32, Vec<BoundaryFace>> = BTreeMap::new();
        let mut inside: BTreeMap<i32, (usize, u64, &[usize])> = BTreeMap::new();
        let mut stray: BTreeMap<i32, (u64, &[usize])> = BTreeMap::new();
        let surface_elements = self
            .triangles
            .iter()
            .map(|e| (e.tag, &e.nodes[..], &e.physical[..]))
            .chain(
                self.quads
                    .iter()
                    .map(|e| (e.tag, &e.nodes[..], &e.physical[..])),
            );
        for (tag, file_nodes, physical) in surface_elements {
            if physical.is_empty() {
                continue;
            }
            let mut nodes = [UNUSED; 4];
            for (slot, &n) in nodes.iter_mut().zip(file_nodes) {
                *slot = local[n];
            }
            if nodes[..file_nodes.len()].contains(&UNUSED) {
                continue;
            }
            match faces.get(&face_key(&nodes[..file_nodes.len()])) {
                Some(FaceUse { count: 1, face }) => {
                    for &p in physical {
                        by_tag.entry(p).or_default().push(*face);
                    }
                }
                Some(_) => {
                    for &p in physical {
                        inside.entry(p).or_insert((0, tag, file_nodes)).0 += 1;
                    }
                }
                None => {
                    for &p in physical {
                        stray.entry(p).or_insert((tag, file_nodes));
                    }
                }
            }
        }
        let kind = |nodes: &[usize]| {
            if nodes.len() == 3 {
                "3-node triangle"
            } else {
                "4-node quadrilateral"
            }
        };
        let nodes_text = |nodes: &[usize]| {
            nodes
                .iter()
                .map(|&n| self.node_text(n))
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (p, &(tag, nodes)) in &stray {
            if !by_tag.contains_key(p) {
                continue;
            }
            return Err(format!(
                "element {tag} ({}) of physical surface {} in file {} has only nodes of the part ({}) but is no face of the part's elements: a boundary must lie on the part's element faces",
                kind(nodes),
                self.group_text(2, *p),
                self.file_name(),
                nodes_text(nodes),
            ));
        }
        for (p, &(count, tag, nodes)) in &inside {
            let Some(on_boundary) = by_tag.get(p) else {
                continue;
            };
            let faces = |n: usize| format!("{n} face{}", if n == 1 { "" } else { "s" });
            return Err(format!(
                "physical surface {} of file {} lies partly inside the part: it has {} on the part's boundary and {} inside it (each a face of two of the part's elements), e.g. element {tag} ({}) with {}; a boundary must lie on the part's boundary: split the surface in Gmsh so that its inner faces form a physical surface of their own, or put only boundary surfaces in the physical group",
                self.group_text(2, *p),
                self.file_name(),
                faces(on_boundary.len()),
                faces(count),
                kind(nodes),
                nodes_text(nodes),
            ));
        }
        let mut boundaries: BTreeMap<String, Vec<BoundaryFace>> = BTreeMap::new();
        for (p, faces) in by_tag {
            let name = self
                .name(2, p)
                .map(str::to_string)
                .unwrap_or_else(|| p.to_string());
            boundaries.entry(name).or_default().extend(faces);
        }
        for faces in boundaries.values_mut() {
            let mut seen = std::collections::HashSet::new();
            faces.retain(|f| seen.insert((f.element, f.face)));
        }
        Ok(boundaries)
    }
}

impl Parser<'_> {
    /// The 3D mesh read ([`run`](Parser::run) done): a file without volume
    /// elements is an error.
    pub(super) fn solid(&mut self) -> Result<GmshMesh3d> {
        if !self.is_solid() {
            return Err(Error::Parse {
                line: None,
                path: self.path.to_path_buf(),
                message: format!(
                    "file {} has no volume elements (4-node tetrahedra or 8-node hexahedra): it is a plane mesh ({} triangles, {} quadrilaterals), read as a 2D one",
                    self.file_name(),
                    self.triangles.len(),
                    self.quads.len()
                ),
            });
        }
        Ok(GmshMesh3d {
            path: self.path.to_path_buf(),
            version: self.version,
            binary: self.binary,
            node_tags: std::mem::take(&mut self.node_tags),
            nodes: std::mem::take(&mut self.coords),
            points: std::mem::take(&mut self.points),
            lines: std::mem::take(&mut self.lines),
            triangles: std::mem::take(&mut self.triangles),
            quads: std::mem::take(&mut self.quads),
            tetrahedra: std::mem::take(&mut self.tetrahedra),
            hexahedra: std::mem::take(&mut self.hexahedra),
            physical_names: std::mem::take(&mut self.physical_names),
        })
    }

    /// 3D: every volume element has a volume: a degenerate one, or a hexahedron
    /// inverted at some corners, is an error naming it and its line or byte (a
    /// damaged node tag or element type would otherwise be read as a flat element
    /// that no part takes in).
    pub(super) fn check_volume_elements(&self) -> Result<()> {
        let all = self
            .tetrahedra
            .iter()
            .map(|e| (e.tag, &e.nodes[..]))
            .zip(&self.tetrahedron_meta)
            .chain(
                self.hexahedra
                    .iter()
                    .map(|e| (e.tag, &e.nodes[..]))
                    .zip(&self.hexahedron_meta),
            );
        for ((tag, nodes), m) in all {
            orientation(tag, nodes, &self.coords, &self.node_tags)
                .map_err(|message| self.err_at(m.at, message))?;
        }
        Ok(())
    }

    /// 3D: every element of a physical surface is a face of a volume element of
    /// the file. One that is not (a damaged node tag, or a surface whose volume is
    /// in no physical volume) would name no boundary, and a boundary would lose
    /// it silently.
    pub(super) fn check_surface_faces(&self) -> Result<()> {
        let mut found: HashMap<[usize; 4], bool> = self
            .triangles
            .iter()
            .filter(|e| !e.physical.is_empty())
            .map(|e| face_key(&e.nodes))
            .chain(
                self.quads
                    .iter()
                    .filter(|e| !e.physical.is_empty())
                    .map(|e| face_key(&e.nodes)),
            )
            .map(|k| (k, false))
            .collect();
        if found.is_empty() {
            return Ok(());
        }
        let mut mark = |nodes: &[usize]| {
            if let Some(f) = found.get_mut(&face_key(nodes)) {
                *f = true;
            }
        };
        for e in &self.tetrahedra {
            for face in crate::mesh::TET4_FACES {
                mark(&face.map(|k| e.nodes[k]));
            }
        }
        for e in &self.hexahedra {
            for face in crate::mesh::HEX8_FACES {
                mark(&face.map(|k| e.nodes[k]));
            }
        }
        let stray = self
            .triangles
            .iter()
            .zip(&self.triangle_meta)
            .map(|(e, m)| (e.tag, &e.nodes[..], &e.physical, m.at, 2))
            .chain(
                self.quads
                    .iter()
                    .zip(&self.quad_meta)
                    .map(|(e, m)| (e.tag, &e.nodes[..], &e.physical, m.at, 3)),
            )
            .filter(|(_, nodes, physical, _, _)| !physical.is_empty() && !found[&face_key(nodes)])
            .min_by_key(|s| s.3);
        if let Some((tag, nodes, physical, at, t)) = stray {
            let surfaces = physical
                .iter()
                .map(|&p| {
                    match self
                        .physical_names
                        .iter()
                        .find(|n| n.dim == 2 && n.tag == p)
                    {
                        Some(n) => format!("'{}' ({p})", n.name),
                        None => p.to_string(),
                    }
                })
                .collect::<Vec<_>>()
                .join(", ");
            return Err(self.err_at(
                at,
                format!(
                    "{} of physical surface {surfaces}, with nodes {}, is not a face of any tetrahedron or hexahedron of the file: a physical surface must lie on element faces (a damaged node tag, or a surface whose volume is in no physical volume?)",
                    self.element_text(tag, t, at),
                    nodes
                        .iter()
                        .map(|&n| self.node_tags[n].to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's corners in Gmsh order.
    const CUBE: [[f64; 3]; 8] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];

    /// A parallelepiped's corner Jacobians (× 8) all equal its volume (det J =
    /// V / 8 everywhere); mirrored they are all −V; with two top nodes swapped
    /// (a twisted element) they differ in sign.
    #[test]
    fn hex8_corner_jacobians_tell_the_orientation() {
        // x → A x with A = [[2, 1, 0], [0, 3, 0], [0.5, 0, 1]], det A = 6.
        let a = |p: [f64; 3]| [2. * p[0] + p[1], 3. * p[1], 0.5 * p[0] + p[2]];
        let sheared = CUBE.map(a);
        for j in hex8_corner_jacobians(&sheared) {
            assert!((j - 6.0).abs() < 1e-14, "{j}");
        }
        let m = [0, 3, 2, 1, 4, 7, 6, 5].map(|k| sheared[k]);
        for j in hex8_corner_jacobians(&m) {
            assert!((j + 6.0).abs() < 1e-14, "{j}");
        }
        let twisted = [0, 1, 2, 3, 5, 4, 6, 7].map(|k| CUBE[k]);
        let j = hex8_corner_jacobians(&twisted);
        assert!(
            j.iter().any(|&v| v > 0.0) && j.iter().any(|&v| v < 0.0),
            "{j:?}"
        );
    }

    /// Six times a tetrahedron's volume: 1 for the unit corner tetrahedron in
    /// Gmsh's order, −1 with two nodes swapped, 6 det A after a linear map A.
    #[test]
    fn tet4_six_volume_is_signed() {
        let t = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        assert_eq!(tet4_six_volume(&t), 1.0);
        assert_eq!(tet4_six_volume(&[t[0], t[2], t[1], t[3]]), -1.0);
        let a = |p: [f64; 3]| [2. * p[0] + p[1], 3. * p[1], 0.5 * p[0] + p[2]];
        assert!((tet4_six_volume(&t.map(a)) - 6.0).abs() < 1e-14);
    }

    /// Faces with the same corners in the same cyclic order have the same key
    /// and cyclic form from any starting corner; reversed, the cyclic form
    /// differs.
    #[test]
    fn face_keys_and_cyclic_order() {
        assert_eq!(face_key(&[5, 2, 9]), [2, 5, 9, UNUSED]);
        assert_eq!(face_key(&[4, 1, 3, 2]), [1, 2, 3, 4]);
        assert_eq!(cyclic(&[9, 2, 5]), cyclic(&[2, 5, 9]));
        assert_ne!(cyclic(&[9, 2, 5]), cyclic(&[9, 5, 2]));
        assert_eq!(cyclic(&[7, 3, 8, 6]), [3, 8, 6, 7]);
    }
}
