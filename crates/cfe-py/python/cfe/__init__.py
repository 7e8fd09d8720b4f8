"""cfe: contact between independently meshed parts by coupling finite elements (2D and 3D).

Each part of an assembly is meshed on its own; the parts interact across their
shared faces through coupling finite elements (CFEs), bonded where the faces press
together and free where they pull apart. This package drives the Rust solver from
Python:

* a :class:`Model` from a problem file (:meth:`Model.from_file`), TOML text
  (:meth:`Model.from_toml`), or dicts mirroring the TOML schema (``Model(dict)``)
  whose parts may be given as arrays (``points``, ``triangles``, ``quads``,
  ``boundaries``; in 3D ``tetrahedra``, ``hexahedra``) or as a :class:`Mesh` /
  ``meshio.Mesh``. One class for both dimensions: a model is plane (``rectangle``,
  ``annulus``, 2D Gmsh, triangles/quads) or solid (``box``, 3D Gmsh,
  tetrahedra/hexahedra), told from its parts (:attr:`Model.dimension`);
* :meth:`Model.solve` (the GIL is released; an optional progress callback) returns
  :class:`Results`: per part displacements and stresses, per interface the pairs'
  positions, states, gaps, slips and forces, reactions, the summary, all NumPy arrays
  made from the solver's buffers; :meth:`Results.to_meshio` and
  :meth:`Results.write` (the files of ``cfe run``).

Errors are :class:`CfeError` subclasses carrying the library's messages (file,
line, key, part, node).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np

from . import _cfe
from ._cfe import (
    CfeError,
    ConvergenceError,
    CouplingError,
    LawViolationError,
    MeshError,
    ModelError,
    OutputError,
    ParseError,
    PrecisionError,
    SingularError,
    TooLargeError,
)

__version__: str = _cfe.__version__

__all__ = [
    "CfeError",
    "ConvergenceError",
    "CouplingError",
    "Increment",
    "InterfaceResult",
    "LawViolationError",
    "Mesh",
    "MeshError",
    "Model",
    "ModelError",
    "OutputError",
    "ParseError",
    "PartResult",
    "PrecisionError",
    "Results",
    "SingularError",
    "TooLargeError",
    "run",
]

PathLike = Union[str, "os.PathLike[str]"]

#: The keys of a part dict that give its mesh as arrays.
_ARRAY_KEYS = ("points", "triangles", "quads", "boundaries", "tetrahedra", "hexahedra")


class Increment(NamedTuple):
    """What a progress callback receives after each converged increment."""

    #: 1-based increment number.
    increment: int
    #: Number of increments of the analysis.
    increments: int
    #: Load factor of the increment's step (1 at the step's last increment).
    load_factor: float
    #: Linear solves (active-set iterations) of the increment.
    iterations: int
    #: The increment's load step (its name; ``step-1`` without ``[[step]]``).
    step: str = "step-1"
    #: Total time: step index − 1 + load factor (monotonic over the steps).
    time: float = 0.0
    #: The increment's row of the run's history: ``history.csv``'s columns
    #: (``increment``, ``step``, ``step_index``, ``load_factor``, ``time``,
    #: ``reaction:SUPPORT.fx``…, ``interface:NAME.force_n``…,
    #: ``probe:NAME.ux``…) to scalars, the same values :attr:`Results.history`
    #: holds for it at the end.
    history: Optional[Dict[str, Any]] = None


# ---------------------------------------------------------------- meshes


class Mesh:
    """A part's mesh given as arrays, checked by the library: plane or solid.

    Plane: ``points`` (n, 2) node coordinates; ``triangles`` (m, 3) and/or
    ``quads`` (k, 4) 0-based node indices, either way round (clockwise elements
    are reversed); ``boundaries`` maps a name to edges (j, 2) (node pairs, each an
    element edge on the part's boundary) or to nodes (j,) (every boundary edge
    joining two of them). Element ``e`` of the part is ``triangles[e]`` for
    ``e < m`` and ``quads[e - m]`` after.

    Solid: ``points`` (n, 3); ``tetrahedra`` (m, 4) and/or ``hexahedra`` (k, 8)
    in the Gmsh/VTK node order (elements of negative volume are mirrored);
    ``boundaries`` maps a name to faces (j, 3) or (j, 4) (each a face of an
    element on the part's boundary, either way round; a list of both arrays for
    a boundary of triangles and quadrangles, or one (j, 4) array whose
    triangles have -1 as fourth corner) or to nodes (j,) (every boundary face
    whose corners are all among them). Element ``e`` is ``tetrahedra[e]`` for
    ``e < m`` and ``hexahedra[e - m]`` after.

    Bad shapes (e.g. (n, 4) cells given as ``triangles``, (n, 2) points with
    tetrahedra), indices out of range, degenerate or inverted elements and
    edges or faces off the boundary raise :class:`MeshError`.
    """

    def __init__(
        self,
        points: Any,
        triangles: Any = None,
        quads: Any = None,
        boundaries: Optional[Mapping[str, Any]] = None,
        *,
        tetrahedra: Any = None,
        hexahedra: Any = None,
        part: str = "mesh",
    ) -> None:
        pts = _float_array(points, "points", part)
        solid = tetrahedra is not None or hexahedra is not None
        if solid and (triangles is not None or quads is not None):
            raise MeshError(
                f"mesh of part '{part}': a mesh is plane (`triangles`, `quads`) or solid "
                "(`tetrahedra`, `hexahedra`), not both: give the part's elements of one dimension"
            )
        if solid:
            if pts.ndim != 2 or pts.shape[1] != 3:
                raise MeshError(
                    f"mesh of part '{part}': tetrahedra and hexahedra need points (n, 3) (x, y, z), "
                    f"got shape {pts.shape}"
                )
            tet = None if tetrahedra is None else _int_array(tetrahedra, "tetrahedra", part)
            hexa = None if hexahedra is None else _int_array(hexahedra, "hexahedra", part)
            bnd = None
            if boundaries is not None:
                bnd = {}
                for k, v in boundaries.items():
                    what = f"boundaries['{k}']"
                    if isinstance(v, (list, tuple)) and v and not np.isscalar(v[0]) and np.ndim(v[0]) == 2:
                        bnd[str(k)] = [_int_array(a, what, part) for a in v]
                    else:
                        bnd[str(k)] = _int_array(v, what, part)
            self._native = _cfe.Mesh(pts, None, None, bnd, tetrahedra=tet, hexahedra=hexa, part=part)
            return
        if pts.ndim == 2 and pts.shape[1] == 3:
            # meshio and Gmsh give 3D points; a planar mesh has z = const.
            z = pts[:, 2]
            if z.size and np.ptp(z) > 1e-12 * max(1.0, float(np.abs(pts[:, :2]).max())):
                raise MeshError(
                    f"mesh of part '{part}': the points are not in a plane z = const "
                    "(a solid mesh takes `tetrahedra=` and/or `hexahedra=`)"
                )
            pts = np.ascontiguousarray(pts[:, :2])
        tri = None if triangles is None else _int_array(triangles, "triangles", part)
        quad = None if quads is None else _int_array(quads, "quads", part)
        bnd = None
        if boundaries is not None:
            bnd = {str(k): _int_array(v, f"boundaries['{k}']", part) for k, v in boundaries.items()}
        self._native = _cfe.Mesh(pts, tri, quad, bnd, part=part)

    @classmethod
    def _wrap(cls, native: Any) -> "Mesh":
        m = cls.__new__(cls)
        m._native = native
        return m

    @property
    def dimension(self) -> int:
        """2 for a plane mesh (triangles, quads), 3 for a solid one (tetrahedra, hexahedra)."""
        return self._native.dimension

    @property
    def points(self) -> np.ndarray:
        """Node coordinates (n, 2), or (n, 3) in a solid mesh."""
        return self._native.points

    @property
    def triangles(self) -> np.ndarray:
        """Triangles (m, 3), counter-clockwise."""
        return self._native.triangles

    @property
    def quads(self) -> np.ndarray:
        """Quadrilaterals (k, 4), counter-clockwise."""
        return self._native.quads

    @property
    def tetrahedra(self) -> np.ndarray:
        """Tetrahedra (m, 4), of positive volume (empty in a plane mesh)."""
        return self._native.tetrahedra

    @property
    def hexahedra(self) -> np.ndarray:
        """Hexahedra (k, 8), of positive volume (empty in a plane mesh)."""
        return self._native.hexahedra

    @property
    def boundaries(self) -> Dict[str, np.ndarray]:
        """Named boundaries: name -> edges (j, 2), the part on each edge's left
        (plane); name -> faces (j, 3) or (j, 4), outward by the right-hand rule
        (solid; a boundary of triangles and quadrangles is (j, 4) with -1 as its
        triangles' fourth corner)."""
        return dict(self._native.boundaries)

    def boundary_nodes(self, name: str) -> np.ndarray:
        """The nodes of boundary ``name``, each once, in order along it (plane)
        or in the order of its faces (solid)."""
        return _chain_nodes(self.boundaries[name])

    def __repr__(self) -> str:
        return repr(self._native)

    @classmethod
    def from_meshio(
        cls,
        mesh: Any,
        *,
        surfaces: Optional[Sequence[Union[str, int]]] = None,
        volumes: Optional[Sequence[Union[str, int]]] = None,
        part: str = "mesh",
    ) -> "Mesh":
        """A mesh from a ``meshio.Mesh``: its ``triangle`` and ``quad`` cells (of the
        physical ``surfaces`` only, names or Gmsh tags, when given; the nodes they
        use are renumbered in order), its boundaries from the cell sets and the
        Gmsh physical curves (``gmsh:physical`` cell data named by ``field_data``)
        of its ``line`` cells. Lines that lie wholly inside the part are left out.

        A mesh with ``tetra`` or ``hexahedron`` cells is solid, read the same way
        one dimension up: its volume cells (of the physical ``volumes`` only,
        when given), its boundaries from the cell sets and the Gmsh physical
        surfaces of its ``triangle`` and ``quad`` cells (faces wholly inside the
        part left out); ``line`` and ``vertex`` cells are ignored.
        """
        kinds = {block.type for block in mesh.cells}
        if kinds & {"tetra", "hexahedron"}:
            if surfaces is not None:
                raise MeshError(
                    f"mesh of part '{part}': the meshio mesh is solid (tetra, hexahedron): "
                    "select its physical volumes with `volumes`, not `surfaces`"
                )
            return cls._from_meshio_solid(mesh, volumes, part)
        if volumes is not None:
            raise MeshError(
                f"mesh of part '{part}': `volumes` selects a solid mesh's cells, and this meshio mesh "
                "has no tetra or hexahedron cells (select its physical surfaces with `surfaces`)"
            )
        points = np.asarray(mesh.points, dtype=np.float64)
        tags = _physical_tags(mesh)
        selected: Optional[set] = None
        if surfaces is not None:
            names = {n: int(v[0]) for n, v in getattr(mesh, "field_data", {}).items() if int(v[1]) == 2}
            selected = set()
            for s in surfaces:
                if isinstance(s, str):
                    if s not in names:
                        raise MeshError(
                            f"mesh of part '{part}': the meshio mesh has no physical surface '{s}' "
                            f"(it has: {', '.join(sorted(names)) or 'none'})"
                        )
                    selected.add(names[s])
                else:
                    selected.add(int(s))
        tri: List[np.ndarray] = []
        quad: List[np.ndarray] = []
        lines: List[tuple] = []  # (block index, cells)
        for b, block in enumerate(mesh.cells):
            kind, data = block.type, np.asarray(block.data)
            if kind in ("triangle", "quad"):
                if selected is not None:
                    if tags is None or tags[b] is None:
                        raise MeshError(
                            f"mesh of part '{part}': `surfaces` needs Gmsh physical tags (cell data 'gmsh:physical')"
                        )
                    data = data[np.isin(tags[b], list(selected))]
                (tri if kind == "triangle" else quad).append(data)
            elif kind == "line":
                lines.append((b, data))
            elif kind not in ("vertex",):
                raise MeshError(
                    f"mesh of part '{part}': cell type '{kind}' is not supported (triangle, quad; line for boundaries)"
                )
        tri_a = np.concatenate(tri) if tri else np.zeros((0, 3), dtype=np.int64)
        quad_a = np.concatenate(quad) if quad else np.zeros((0, 4), dtype=np.int64)
        # Keep only the nodes the elements use, in order.
        used = np.unique(np.concatenate([tri_a.ravel(), quad_a.ravel()]))
        local = np.full(len(points), -1, dtype=np.int64)
        local[used] = np.arange(len(used))
        # Boundaries: cell sets first, then named (or numbered) physical curves.
        edges: Dict[str, List[np.ndarray]] = {}
        for name, per_block in getattr(mesh, "cell_sets", {}).items():
            if name.startswith("gmsh:"):
                continue
            for (b, data) in lines:
                if b < len(per_block) and per_block[b] is not None and len(per_block[b]):
                    edges.setdefault(name, []).append(data[np.asarray(per_block[b], dtype=np.int64)])
        if tags is not None:
            curve_names = {int(v[0]): n for n, v in getattr(mesh, "field_data", {}).items() if int(v[1]) == 1}
            from_tags: Dict[str, List[np.ndarray]] = {}
            for (b, data) in lines:
                if tags[b] is None:
                    continue
                for t in np.unique(tags[b]):
                    if t == 0:
                        continue  # no physical group
                    name = curve_names.get(int(t), str(int(t)))
                    from_tags.setdefault(name, []).append(data[tags[b] == t])
            for name, e in from_tags.items():
                edges.setdefault(name, e)
        free = _free_edges(tri_a, quad_a)
        boundaries = {}
        for name, blocks in edges.items():
            e = np.concatenate(blocks).astype(np.int64)
            e = e[(local[e] >= 0).all(axis=1)]
            on_boundary = [tuple(sorted(x)) in free for x in e.tolist()]
            if not any(on_boundary):
                continue  # a curve inside the part (or of another part) names no boundary
            boundaries[name] = local[e]
        return cls(
            points[used],
            local[tri_a] if len(tri_a) else None,
            local[quad_a] if len(quad_a) else None,
            boundaries,
            part=part,
        )

    @classmethod
    def _from_meshio_solid(
        cls, mesh: Any, volumes: Optional[Sequence[Union[str, int]]], part: str
    ) -> "Mesh":
        """:meth:`from_meshio` of a mesh with ``tetra``/``hexahedron`` cells."""
        points = np.asarray(mesh.points, dtype=np.float64)
        tags = _physical_tags(mesh)
        selected = _selected_groups(mesh, volumes, 3, "volume", part)
        tet: List[np.ndarray] = []
        hexa: List[np.ndarray] = []
        faces: List[tuple] = []  # (block index, cells)
        for b, block in enumerate(mesh.cells):
            kind, data = block.type, np.asarray(block.data)
            if kind in ("tetra", "hexahedron"):
                if selected is not None:
                    if tags is None or tags[b] is None:
                        raise MeshError(
                            f"mesh of part '{part}': `volumes` needs Gmsh physical tags (cell data 'gmsh:physical')"
                        )
                    data = data[np.isin(tags[b], list(selected))]
                (tet if kind == "tetra" else hexa).append(data)
            elif kind in ("triangle", "quad"):
                faces.append((b, data))
            elif kind not in ("vertex", "line"):
                raise MeshError(
                    f"mesh of part '{part}': cell type '{kind}' is not supported in a solid mesh "
                    "(tetra, hexahedron; triangle and quad for boundaries)"
                )
        tet_a = np.concatenate(tet) if tet else np.zeros((0, 4), dtype=np.int64)
        hex_a = np.concatenate(hexa) if hexa else np.zeros((0, 8), dtype=np.int64)
        used = np.unique(np.concatenate([tet_a.ravel(), hex_a.ravel()])).astype(np.int64)
        local = np.full(len(points), -1, dtype=np.int64)
        local[used] = np.arange(len(used))
        # Boundaries: cell sets first, then named (or numbered) physical surfaces.
        found: Dict[str, List[np.ndarray]] = {}
        for name, per_block in getattr(mesh, "cell_sets", {}).items():
            if name.startswith("gmsh:"):
                continue
            for (b, data) in faces:
                if b < len(per_block) and per_block[b] is not None and len(per_block[b]):
                    found.setdefault(name, []).append(data[np.asarray(per_block[b], dtype=np.int64)])
        if tags is not None:
            surface_names = {int(v[0]): n for n, v in getattr(mesh, "field_data", {}).items() if int(v[1]) == 2}
            from_tags: Dict[str, List[np.ndarray]] = {}
            for (b, data) in faces:
                if tags[b] is None:
                    continue
                for t in np.unique(tags[b]):
                    if t == 0:
                        continue  # no physical group
                    name = surface_names.get(int(t), str(int(t)))
                    from_tags.setdefault(name, []).append(data[tags[b] == t])
            for name, f in from_tags.items():
                found.setdefault(name, f)
        free = _free_faces(tet_a, hex_a)
        boundaries: Dict[str, Any] = {}
        for name, blocks in found.items():
            kept = []
            for f in blocks:
                f = np.asarray(f, dtype=np.int64)
                f = f[(local[f] >= 0).all(axis=1)]
                on = np.array([tuple(sorted(x)) in free for x in f.tolist()], dtype=bool)
                if on.any():
                    kept.append(local[f[on]])
            if kept:
                # A surface inside the part (or of another part) names no boundary.
                boundaries[name] = kept if len(kept) > 1 else kept[0]
        return cls(
            points[used],
            None,
            None,
            boundaries,
            tetrahedra=local[tet_a] if len(tet_a) else None,
            hexahedra=local[hex_a] if len(hex_a) else None,
            part=part,
        )

    def to_meshio(self) -> Any:
        """The mesh as a ``meshio.Mesh`` (points with z = 0, ``triangle`` and ``quad``
        cells, each boundary a ``line`` block with a cell set of its name); its
        :meth:`from_meshio` gives this mesh back. A solid mesh: its points,
        ``tetra`` and ``hexahedron`` cells, each boundary a ``triangle`` and/or
        ``quad`` block with a cell set of its name (and Gmsh physical tags: the
        elements physical volume 1, boundary i physical surface i + 1)."""
        import meshio

        if self.dimension == 3:
            return _mesh_to_meshio_solid(self)

        points = np.column_stack([self.points, np.zeros(len(self.points))])
        cells = []
        if len(self.triangles):
            cells.append(("triangle", self.triangles))
        if len(self.quads):
            cells.append(("quad", self.quads))
        n_elem_blocks = len(cells)
        names = list(self.boundaries)
        for name in names:
            cells.append(("line", self.boundaries[name]))
        sets = {}
        for i, name in enumerate(names):
            per_block = [np.zeros(0, dtype=np.int64) for _ in cells]
            per_block[n_elem_blocks + i] = np.arange(len(self.boundaries[name]))
            sets[name] = per_block
        # The same as Gmsh physical groups, so that a .msh file keeps the names:
        # the elements physical surface 1, boundary i physical curve i + 1.
        tags = [1] * n_elem_blocks + list(range(1, len(names) + 1))
        physical = [np.full(len(c[1]), t, dtype=np.int64) for c, t in zip(cells, tags)]
        field_data = {name: np.array([i + 1, 1]) for i, name in enumerate(names)}
        return meshio.Mesh(
            points,
            cells,
            cell_sets=sets,
            cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical},
            field_data=field_data,
        )


def _mesh_to_meshio_solid(mesh: "Mesh") -> Any:
    """:meth:`Mesh.to_meshio` of a solid mesh."""
    import meshio

    cells = []
    if len(mesh.tetrahedra):
        cells.append(("tetra", mesh.tetrahedra))
    if len(mesh.hexahedra):
        cells.append(("hexahedron", mesh.hexahedra))
    n_elem_blocks = len(cells)
    tags = [1] * n_elem_blocks
    sets: Dict[str, List[int]] = {}
    names = list(mesh.boundaries)
    for i, name in enumerate(names):
        for block in _face_blocks(mesh.boundaries[name]):
            sets.setdefault(name, []).append(len(cells))
            cells.append(("triangle" if block.shape[1] == 3 else "quad", block))
            tags.append(i + 2)
    cell_sets = {}
    for name, blocks in sets.items():
        per_block = [np.zeros(0, dtype=np.int64) for _ in cells]
        for b in blocks:
            per_block[b] = np.arange(len(cells[b][1]))
        cell_sets[name] = per_block
    physical = [np.full(len(c[1]), t, dtype=np.int64) for c, t in zip(cells, tags)]
    field_data = {name: np.array([i + 2, 2]) for i, name in enumerate(names)}
    return meshio.Mesh(
        mesh.points,
        cells,
        cell_sets=cell_sets,
        cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical},
        field_data=field_data,
    )


def _face_blocks(faces: np.ndarray) -> List[np.ndarray]:
    """A boundary's faces as blocks of one kind: (j, 3) triangles and/or (j, 4)
    quadrangles (a (j, 4) array's rows with -1 as fourth corner are triangles)."""
    faces = np.asarray(faces)
    if faces.shape[1] == 3:
        return [faces]
    tri = faces[:, 3] < 0
    blocks = []
    if tri.any():
        blocks.append(np.ascontiguousarray(faces[tri, :3]))
    if (~tri).any():
        blocks.append(np.ascontiguousarray(faces[~tri]))
    return blocks


def _selected_groups(
    mesh: Any, groups: Optional[Sequence[Union[str, int]]], dim: int, what: str, part: str
) -> Optional[set]:
    """The Gmsh tags of the physical groups ``groups`` (names or tags) of dimension ``dim``."""
    if groups is None:
        return None
    names = {n: int(v[0]) for n, v in getattr(mesh, "field_data", {}).items() if int(v[1]) == dim}
    selected = set()
    for s in groups:
        if isinstance(s, str):
            if s not in names:
                raise MeshError(
                    f"mesh of part '{part}': the meshio mesh has no physical {what} '{s}' "
                    f"(it has: {', '.join(sorted(names)) or 'none'})"
                )
            selected.add(names[s])
        else:
            selected.add(int(s))
    return selected


def _free_faces(tet: np.ndarray, hexa: np.ndarray) -> set:
    """The faces (sorted corners) used by one element only."""
    faces = []
    tet_faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [3, 1, 2]]
    hex_faces = [[0, 3, 2, 1], [0, 1, 5, 4], [0, 4, 7, 3], [1, 2, 6, 5], [2, 3, 7, 6], [4, 5, 6, 7]]
    for cells, local in ((tet, tet_faces), (hexa, hex_faces)):
        if len(cells):
            for f in local:
                faces.extend(map(tuple, np.sort(cells[:, f], axis=1).tolist()))
    counts: Dict[tuple, int] = {}
    for f in faces:
        counts[f] = counts.get(f, 0) + 1
    return {f for f, c in counts.items() if c == 1}


def _float_array(a: Any, what: str, part: str) -> np.ndarray:
    try:
        return np.ascontiguousarray(a, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise MeshError(f"mesh of part '{part}': `{what}` must be an array of numbers: {e}") from None


def _int_array(a: Any, what: str, part: str) -> np.ndarray:
    try:
        raw = np.asarray(a)
        if raw.dtype.kind == "f":
            if raw.size and not np.all(raw == np.round(raw)):
                raise ValueError("it has non-integer values")
        elif raw.size and raw.dtype.kind not in "iu":
            raise ValueError(f"its type is {raw.dtype}")
        # Values int64 cannot hold would wrap around (to negative indices).
        if raw.size and raw.dtype.kind in "uf" and not np.all(np.abs(raw) < 2.0**63):
            raise ValueError("it has values beyond the int64 range")
        return np.ascontiguousarray(raw, dtype=np.int64)
    except (TypeError, ValueError) as e:
        raise MeshError(f"mesh of part '{part}': `{what}` must be an array of node indices: {e}") from None


def _physical_tags(mesh: Any) -> Optional[List[Optional[np.ndarray]]]:
    data = getattr(mesh, "cell_data", {}).get("gmsh:physical")
    if data is None:
        return None
    return [None if d is None else np.asarray(d).astype(np.int64) for d in data]


def _free_edges(tri: np.ndarray, quad: np.ndarray) -> set:
    edges = []
    for cells in (tri, quad):
        if len(cells):
            k = cells.shape[1]
            for i in range(k):
                edges.append(np.sort(np.stack([cells[:, i], cells[:, (i + 1) % k]], axis=1), axis=1))
    if not edges:
        return set()
    all_edges, counts = np.unique(np.concatenate(edges), axis=0, return_counts=True)
    return set(map(tuple, all_edges[counts == 1].tolist()))


def _chain_nodes(edges: np.ndarray) -> np.ndarray:
    seen: Dict[int, None] = {}
    for row in np.asarray(edges).tolist():
        for n in row:
            if n >= 0:  # -1 pads a triangle in a solid boundary of both kinds
                seen.setdefault(n)
    return np.fromiter(seen.keys(), dtype=np.int64, count=len(seen))


# ---------------------------------------------------------------- models


class Model:
    """A checked, meshed model, ready to solve.

    ``Model(problem)`` builds one from a dict mirroring the TOML schema of a problem
    file (``{"materials": {...}, "part": [...], "interface": [...], "support":
    [...], "load": [...], "analysis": {...}}``); a part may give its mesh as
    arrays (``points``, ``triangles``, ``quads``, ``boundaries``; a solid part
    ``points`` (n, 3), ``tetrahedra``, ``hexahedra``, ``boundaries``; see
    :class:`Mesh`) or as ``mesh`` (a :class:`Mesh` or a ``meshio.Mesh``) instead
    of ``rectangle``/``annulus``/``box``/``gmsh``. The model is plane or solid
    from its parts (``box`` and 3D meshes make it solid, with ``fix = ["x", "y",
    "z"]``, three-component ``force``, ``at``, ``from``, ``to``: the problem
    file's schema). ``None`` values are left out. Errors name
    the dict entry (e.g. ``part[1].host``) and the key; a dict nested deeper than
    64 levels or containing itself raises ``ValueError``. ``refine`` subdivides every
    mesh (as ``cfe run --refine``; refused with :class:`TooLargeError` when the
    refined model would not fit in memory); ``path`` locates relative Gmsh files.
    """

    def __init__(
        self,
        problem: Mapping[str, Any],
        *,
        refine: int = 1,
        path: Optional[PathLike] = None,
    ) -> None:
        problem = dict(problem)
        meshes: Dict[str, Mesh] = {}
        parts = problem.get("part")
        if isinstance(parts, Sequence) and not isinstance(parts, (str, bytes)):
            new_parts = []
            for i, spec in enumerate(parts):
                if not isinstance(spec, Mapping):
                    new_parts.append(spec)
                    continue
                spec = dict(spec)
                given = {k: spec.pop(k) for k in _ARRAY_KEYS if k in spec}
                mesh = spec.pop("mesh", None)
                name = spec.get("name", f"part[{i}]")
                if given and mesh is not None:
                    raise ModelError(f"part '{name}': give `mesh` or arrays ({', '.join(given)}), not both")
                if given:
                    if "points" not in given:
                        raise MeshError(
                            f"mesh of part '{name}': arrays need `points` (n, 2), or (n, 3) with tetrahedra/hexahedra"
                        )
                    mesh = Mesh(
                        given["points"],
                        given.get("triangles"),
                        given.get("quads"),
                        given.get("boundaries"),
                        tetrahedra=given.get("tetrahedra"),
                        hexahedra=given.get("hexahedra"),
                        part=str(name),
                    )
                if mesh is not None:
                    if not isinstance(mesh, Mesh):
                        mesh = Mesh.from_meshio(mesh, part=str(name))
                    if not isinstance(name, str):
                        raise ParseError(f"problem dict, part[{i}].name: a part with a mesh needs a name (string)")
                    meshes[name] = mesh
                new_parts.append(spec)
            problem["part"] = new_parts
        text = _cfe.dict_to_toml(problem)
        where = Path(path) if path is not None else Path("problem.toml")
        try:
            native = _cfe.Model.from_toml(
                text, refine, where, {k: m._native for k, m in meshes.items()}
            )
        except ParseError as e:
            raise _from_dict_error(e, text, where) from None
        except (ModelError, PrecisionError) as e:
            # A value refused with its key: the generated text's file and line
            # mean nothing to the dict's author, the dotted key does.
            line = getattr(e, "line", None)
            if line is None or not isinstance(getattr(e, "key", None), str):
                raise
            new = type(e)(str(e).replace(f"{where}:{line}: ", "problem dict: ", 1))
            new.key = e.key
            new.path = None
            new.line = None
            raise new from None
        self._init(native, meshes)

    def _init(self, native: Any, meshes: Optional[Dict[str, Mesh]] = None) -> None:
        self._native = native
        self._meshes = meshes or {}

    @classmethod
    def _wrap(cls, native: Any) -> "Model":
        m = cls.__new__(cls)
        m._init(native)
        return m

    @classmethod
    def from_dict(cls, problem: Mapping[str, Any], *, refine: int = 1, path: Optional[PathLike] = None) -> "Model":
        """The same as ``Model(problem, refine=..., path=...)``."""
        return cls(problem, refine=refine, path=path)

    @classmethod
    def from_file(cls, path: PathLike, *, refine: int = 1) -> "Model":
        """Reads, checks and meshes the problem file at ``path`` (as ``cfe run``),
        plane or solid (told from its parts: ``box`` or a 3D Gmsh mesh is solid)."""
        return cls._wrap(_cfe.Model.from_file(Path(path), refine))

    @classmethod
    def from_inp(cls, path: PathLike) -> "Model":
        """Reads a CalculiX/Abaqus input deck (as ``cfe run model.inp``): its
        common subset mapped onto cfe's model (README, "Running a CalculiX/Abaqus
        deck"); anything outside it raises :class:`ParseError` with ``line``,
        ``keyword`` and ``fault``. The keywords it ignored are in :attr:`notes`."""
        return cls._wrap(_cfe.Model.from_inp(Path(path)))

    @property
    def notes(self) -> List[str]:
        """What reading the input noted: a deck's ignored keywords (with their
        lines) and how its contact behaviour was mapped."""
        return list(self._native.notes)

    @classmethod
    def from_toml(
        cls,
        text: str,
        *,
        refine: int = 1,
        path: Optional[PathLike] = None,
        meshes: Optional[Mapping[str, Any]] = None,
    ) -> "Model":
        """Reads, checks and meshes a problem given as TOML text. ``path`` (default
        ``problem.toml``) is used in messages and to find Gmsh files; ``meshes``
        gives the meshes (:class:`Mesh` or ``meshio.Mesh``) of parts that have no
        mesh key, by part name."""
        given = {}
        for name, m in (meshes or {}).items():
            given[name] = m if isinstance(m, Mesh) else Mesh.from_meshio(m, part=name)
        where = Path(path) if path is not None else None
        native = _cfe.Model.from_toml(text, refine, where, {k: m._native for k, m in given.items()})
        model = cls._wrap(native)
        model._meshes = given
        return model

    @property
    def dimension(self) -> int:
        """2 for a plane model, 3 for a solid one."""
        return self._native.dimension

    @property
    def title(self) -> str:
        """The title."""
        return self._native.title

    @property
    def parts(self) -> List[str]:
        """The part names, in order."""
        return list(self._native.parts)

    @property
    def interfaces(self) -> List[str]:
        """The interface names, in order."""
        return list(self._native.interfaces)

    @property
    def settings(self) -> Dict[str, Any]:
        """The analysis settings (increments, scheme, max_iterations, gap_tolerance,
        solver: ``"direct"`` or ``"cg"``, set by ``"analysis": {"solver": "cg"}``)."""
        return dict(self._native.settings)

    @property
    def steps(self) -> List[Dict[str, Any]]:
        """The load steps in order, each a dict of ``name`` and ``increments``
        (one step, ``step-1``, without ``[[step]]`` tables)."""
        return [dict(s) for s in self._native.steps]

    @property
    def refine(self) -> int:
        """The refinement factor the model was meshed with."""
        return self._native.refine

    @property
    def text(self) -> str:
        """The problem as TOML text (for a dict model, the text it became)."""
        return self._native.text

    def mesh(self, part: str) -> Mesh:
        """The mesh of ``part`` as meshed (before coupling nodes move onto host edges)."""
        return Mesh._wrap(self._native.mesh(part))

    def check(self) -> str:
        """Finds the coupling pairs without solving; the description ``cfe check`` prints."""
        return self._native.check()

    def solve(
        self,
        progress: Optional[Callable[[Increment], Any]] = None,
        *,
        out: Optional[PathLike] = None,
        law: Optional[str] = None,
        friction: Optional[float] = None,
        write_every: Optional[Union[int, str]] = None,
        force: bool = False,
    ) -> "Results":
        """Solves every increment in memory, with the GIL released, and returns the
        :class:`Results` of the last one.

        ``progress(increment)`` is called after each converged increment with an
        :class:`Increment` (with its ``history`` row: reactions, contact
        resultants, probe displacements); an exception it raises stops the solve and propagates.
        Ctrl-C (SIGINT) stops it inside the increment being solved, at its next
        iteration, fixed-point step or supernode of a factorization, and raises
        ``KeyboardInterrupt``. With ``out``, every converged increment is also
        written into that folder as ``cfe run`` does (VTU series, pairs.csv,
        summary.json, PNGs; after Ctrl-C the summary says ``interrupted``); the
        callback cannot stop such a run, its exception is raised at the end.
        ``law`` (``"rigid"``, ``"contact"``, ``"frictionless"`` or ``"coulomb"``,
        the last with ``friction`` = μ) makes every interface follow that law, as
        ``cfe run --law … --friction …``. ``write_every`` (with ``out``: N ≥ 1 or
        ``"last"``, as ``cfe run --write-every``) writes the VTU files of every N-th
        increment only (the last of each step always), overriding the file's
        ``output_every``. The model is not changed: it can be solved again.

        ``out`` is refused with :class:`OutputError` (nothing in it touched) when
        it is not empty and holds no cfe run, or holds files at the names cfe
        writes that no cfe run wrote (the error's ``files``), or when another run
        writes into it (``pid``), as ``cfe run``; ``force=True`` writes into it
        anyway, as ``cfe run --force``: the files at cfe's names are replaced,
        every other file is left alone. A folder holding an earlier cfe run needs
        no ``force``: the files that run listed in its ``.cfe-manifest`` are
        removed first, nothing else.
        """
        callback = None if progress is None else _increments_to(progress)
        raw = self._native.solve(
            callback, None if out is None else Path(out), law, friction, write_every, force
        )
        return Results(raw, self, law, friction)

    def __repr__(self) -> str:
        return repr(self._native)


def _increments_to(progress: Callable[[Increment], Any]) -> Callable[[Dict[str, Any]], None]:
    """The native solver's per-increment dict handed to ``progress`` as an
    :class:`Increment`."""

    def callback(info: Dict[str, Any]) -> None:
        progress(Increment(**{k: info[k] for k in Increment._fields if k in info}))

    return callback


def run(
    problem: Union[PathLike, str, Mapping[str, Any], Model],
    *,
    refine: int = 1,
    progress: Optional[Callable[[Increment], Any]] = None,
    out: Optional[PathLike] = None,
    law: Optional[str] = None,
    friction: Optional[float] = None,
    write_every: Optional[Union[int, str]] = None,
    force: bool = False,
) -> "Results":
    """Builds and solves a model in one call: ``problem`` is a :class:`Model`, a
    dict (see :class:`Model`), a path to a problem file, or TOML text (a string
    with a newline). See :meth:`Model.solve` for the other arguments."""
    if isinstance(problem, Model):
        model = problem
    elif isinstance(problem, Mapping):
        model = Model(problem, refine=refine)
    elif isinstance(problem, str) and "\n" in problem:
        model = Model.from_toml(problem, refine=refine)
    else:
        model = Model.from_file(problem, refine=refine)
    return model.solve(
        progress, out=out, law=law, friction=friction, write_every=write_every, force=force
    )


def _from_dict_error(e: ParseError, text: str, path: Path) -> ParseError:
    """A parse error of a dict's TOML text, re-told with the dict entry at fault
    (e.g. ``part[1].host``) instead of the generated text's line."""
    line = getattr(e, "line", None)
    message = str(e)
    prefix = f"{path}: "
    if message.startswith(prefix):
        message = message[len(prefix):]
    where = _dict_location(text, line) if line else None
    new = ParseError(f"problem dict{', ' + where if where else ''}: {message}")
    new.path = None
    new.line = None
    new.entry = where
    return new


def _dict_location(text: str, line: int) -> Optional[str]:
    lines = text.splitlines()
    counts: Dict[str, int] = {}
    header: Optional[str] = None
    for raw in lines[:line]:
        s = raw.strip()
        if s.startswith("[["):
            name = s[2:-2].strip()
            counts[name] = counts.get(name, -1) + 1
            header = f"{name}[{counts[name]}]"
        elif s.startswith("["):
            name = s[1:-1].strip()
            head, _, rest = name.partition(".")
            header = f"{head}[{counts[head]}].{rest}" if head in counts and rest else name
    key = None
    if 0 < line <= len(lines) and "=" in lines[line - 1]:
        key = lines[line - 1].split("=", 1)[0].strip()
    return ".".join(x for x in (header, key) if x) or None


# ---------------------------------------------------------------- results


@dataclass
class PartResult:
    """One part's results at the last converged increment.

    ``points`` are the reference positions (coupling nodes moved onto their host
    edges), ``displacement`` (n, 2) a view of :attr:`Results.displacements`;
    ``stress`` (n, 3) nodal (σxx, σyy, σxy) averaged within the part,
    ``element_stress`` (m, 3) per element (element order: see ``triangle_ids``,
    ``quad_ids``). In an axisymmetric model (``plane = "axisymmetric"``: x = r,
    y = z) ``sigma_theta`` (n,) and ``element_sigma_theta`` (m,) hold the hoop
    stress σθθ (``None`` otherwise), and von Mises includes it.

    A solid part (:attr:`dimension` 3): ``points`` (n, 3), ``displacement``
    (n, 3), ``stress`` (n, 6) and ``element_stress`` (m, 6) in the order σxx,
    σyy, σzz, σxy, σyz, σxz (the VTU files' ``sigma_*`` arrays), von Mises of
    the six; its elements are ``tetrahedra`` and ``hexahedra`` (element order:
    ``tetrahedron_ids``, ``hexahedron_ids``; ``triangles`` and ``quads`` are
    empty), its ``boundaries`` faces (see :attr:`Mesh.boundaries`), its
    ``material`` E and ν only (no thickness).
    """

    name: str
    points: np.ndarray
    triangles: np.ndarray
    triangle_ids: np.ndarray
    quads: np.ndarray
    quad_ids: np.ndarray
    boundaries: Dict[str, np.ndarray]
    material: Dict[str, float]
    displacement: np.ndarray
    stress: np.ndarray
    element_stress: np.ndarray
    von_mises: np.ndarray
    element_von_mises: np.ndarray
    sigma_theta: Optional[np.ndarray] = None
    element_sigma_theta: Optional[np.ndarray] = None
    #: A solid part's tetrahedra (m, 4) and hexahedra (k, 8) with their element
    #: indices (``None`` in a plane part).
    tetrahedra: Optional[np.ndarray] = None
    tetrahedron_ids: Optional[np.ndarray] = None
    hexahedra: Optional[np.ndarray] = None
    hexahedron_ids: Optional[np.ndarray] = None

    @property
    def dimension(self) -> int:
        """2 for a plane part, 3 for a solid one."""
        return int(self.points.shape[1])

    #: The stress components (names of the columns of ``stress``) by dimension.
    _COMPONENTS = {
        2: ("sigma_xx", "sigma_yy", "sigma_xy"),
        3: ("sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_xz"),
    }

    def _column(self, name: str) -> np.ndarray:
        names = self._COMPONENTS[self.dimension]
        if name not in names:
            raise AttributeError(f"{name} is a solid part's stress: a plane part has {', '.join(names)}")
        return self.stress[:, names.index(name)]

    @property
    def sigma_xx(self) -> np.ndarray:
        """Nodal σxx (a view of ``stress``)."""
        return self._column("sigma_xx")

    @property
    def sigma_yy(self) -> np.ndarray:
        """Nodal σyy (a view of ``stress``)."""
        return self._column("sigma_yy")

    @property
    def sigma_xy(self) -> np.ndarray:
        """Nodal σxy (a view of ``stress``)."""
        return self._column("sigma_xy")

    @property
    def sigma_zz(self) -> np.ndarray:
        """Nodal σzz of a solid part (a view of ``stress``)."""
        return self._column("sigma_zz")

    @property
    def sigma_yz(self) -> np.ndarray:
        """Nodal σyz of a solid part (a view of ``stress``)."""
        return self._column("sigma_yz")

    @property
    def sigma_xz(self) -> np.ndarray:
        """Nodal σxz of a solid part (a view of ``stress``)."""
        return self._column("sigma_xz")

    @property
    def ux(self) -> np.ndarray:
        """Nodal x displacement (a view)."""
        return self.displacement[:, 0]

    @property
    def uy(self) -> np.ndarray:
        """Nodal y displacement (a view)."""
        return self.displacement[:, 1]

    @property
    def uz(self) -> np.ndarray:
        """Nodal z displacement of a solid part (a view)."""
        if self.dimension != 3:
            raise AttributeError("uz is a solid part's displacement: a plane part has ux, uy")
        return self.displacement[:, 2]

    def boundary_nodes(self, name: str) -> np.ndarray:
        """The nodes of boundary ``name``, each once, in order along it (plane)
        or in the order of its faces (solid)."""
        return _chain_nodes(self.boundaries[name])

    def to_meshio(self) -> Any:
        """The part as a ``meshio.Mesh``: points (z = 0), ``triangle`` and ``quad``
        cells, point data ``displacement`` (3 components, z = 0, as in the VTU
        files) and the nodal stresses and von Mises, cell data the element ones.
        A solid part: its points, ``tetra`` and ``hexahedron`` cells, point data
        ``displacement`` (n, 3), the six ``sigma_*`` and ``von_mises``, cell data
        the element ones (the arrays of the VTU files)."""
        import meshio

        if self.dimension == 3:
            cells, blocks = [], []
            if len(self.tetrahedra):
                cells.append(("tetra", self.tetrahedra))
                blocks.append(self.tetrahedron_ids)
            if len(self.hexahedra):
                cells.append(("hexahedron", self.hexahedra))
                blocks.append(self.hexahedron_ids)
            names = self._COMPONENTS[3]
            point_data = {"displacement": np.ascontiguousarray(self.displacement)}
            point_data.update({k: self.stress[:, i] for i, k in enumerate(names)})
            point_data["von_mises"] = self.von_mises
            values = {k: self.element_stress[:, i] for i, k in enumerate(names)}
            values["von_mises"] = self.element_von_mises
            cell_data = {k: [v[ids] for ids in blocks] for k, v in values.items()}
            return meshio.Mesh(self.points, cells, point_data=point_data, cell_data=cell_data)

        n = len(self.points)
        points = np.column_stack([self.points, np.zeros(n)])
        cells, blocks = [], []
        if len(self.triangles):
            cells.append(("triangle", self.triangles))
            blocks.append(self.triangle_ids)
        if len(self.quads):
            cells.append(("quad", self.quads))
            blocks.append(self.quad_ids)
        point_data = {
            "displacement": np.column_stack([self.displacement, np.zeros(n)]),
            "sigma_xx": self.sigma_xx,
            "sigma_yy": self.sigma_yy,
            "sigma_xy": self.sigma_xy,
            "von_mises": self.von_mises,
        }
        cell_values = {
            "sigma_xx": self.element_stress[:, 0],
            "sigma_yy": self.element_stress[:, 1],
            "sigma_xy": self.element_stress[:, 2],
            "von_mises": self.element_von_mises,
        }
        if self.sigma_theta is not None:
            point_data["sigma_theta"] = self.sigma_theta
            cell_values["sigma_theta"] = self.element_sigma_theta
        cell_data = {k: [v[ids] for ids in blocks] for k, v in cell_values.items()}
        return meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data)


@dataclass
class InterfaceResult:
    """One interface's coupling pairs at the last converged increment, one entry
    per pair (as the rows of ``pairs.csv``): ``node`` (the coupling node in the
    node part), ``host_element``, ``position`` (k, 2), ``normal`` (k, 2, unit,
    from the host towards the node part), ``bonded`` and ``settled`` (state kept
    against the contact law to settle an active-set cycle) booleans, ``gap_n`` =
    [[u_n]] (> 0: separated), ``slip_s`` = [[u_s]], ``force_n`` (> 0: pressing)
    and ``force_s`` on the node part in the local frame, ``violation`` (0: the law
    holds, 1: a bonded pair pulls, 2: an open pair penetrates, 3: a stick pair
    beyond μ f_n, 4: a slip pair off μ f_n, 5: a stick pair that pulls while
    carrying shear, tension and friction) and ``violation_amount`` (the tensile
    force, the penetration depth or the friction excess; for 5 the pull, the
    friction excess being its whole ``abs(force_s)``). The contact laws add ``friction`` (μ),
    ``unpaired`` (nodes beyond the search distance), ``gap0`` (initial normal
    gap), ``gap`` (g0 + [[u_n]]), ``slip`` (the slip not carried elastically),
    ``pressure`` and ``shear`` (stresses: the forces / (``tributary`` length ×
    the node part's thickness)), and ``state``
    (``"bonded"``, ``"open"`` or ``"slip"``).

    In a solid model ``position`` and ``normal`` are (k, 3), the tangential
    quantities have a second component along the pair's second tangent:
    ``slip_s``, ``force_s``, ``slip`` and ``shear`` are along ``t1`` and
    ``slip_t2``, ``force_t2``, ``slip_t2_plastic`` and ``shear_t2`` along
    ``t2`` (``t1``, ``t2``: (k, 3) unit vectors in the face plane, with
    ``normal`` a right-handed frame); ``force`` (k, 3) is the force on the
    node part in global components (``pairs.csv``'s ``force_x``/``_y``/``_z``),
    ``tributary`` an area (the traction's thickness is 1). These are ``None``
    in a plane model."""

    name: str
    host: str
    node_part: str
    law: str
    c_n: float
    c_s: float
    node: np.ndarray
    host_element: np.ndarray
    position: np.ndarray
    normal: np.ndarray
    bonded: np.ndarray
    settled: np.ndarray
    gap_n: np.ndarray
    slip_s: np.ndarray
    force_n: np.ndarray
    force_s: np.ndarray
    violation: np.ndarray
    violation_amount: np.ndarray
    friction: float
    unpaired: int
    gap0: np.ndarray
    gap: np.ndarray
    slip: np.ndarray
    pressure: np.ndarray
    shear: np.ndarray
    tributary: np.ndarray
    slip_t2: Optional[np.ndarray] = None
    force_t2: Optional[np.ndarray] = None
    slip_t2_plastic: Optional[np.ndarray] = None
    shear_t2: Optional[np.ndarray] = None
    force: Optional[np.ndarray] = None
    t1: Optional[np.ndarray] = None
    t2: Optional[np.ndarray] = None
    extra: Dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def x(self) -> np.ndarray:
        """The pairs' x positions (a view of ``position``)."""
        return self.position[:, 0]

    @property
    def y(self) -> np.ndarray:
        """The pairs' y positions (a view of ``position``)."""
        return self.position[:, 1]

    @property
    def z(self) -> np.ndarray:
        """The pairs' z positions in a solid model (a view of ``position``)."""
        if self.position.shape[1] != 3:
            raise AttributeError("z is a solid model's pair position: a plane pair has x, y")
        return self.position[:, 2]

    @property
    def state(self) -> np.ndarray:
        """``"bonded"``, ``"open"`` or ``"slip"`` per pair."""
        if "state" in self.extra:
            return np.array(self.extra["state"])
        return np.where(self.bonded, "bonded", "open")

    def __len__(self) -> int:
        return len(self.node)


class Results:
    """The results of a solved model at its last converged increment.

    ``parts`` and ``interfaces`` map names to :class:`PartResult` and
    :class:`InterfaceResult`; ``reactions`` maps each support to its reaction
    ``[fx, fy]``; ``summary`` is the content of ``summary.json``; ``history``
    maps each column of ``history.csv`` to its values over the increments;
    ``displacements`` the displacements of all DOFs (x, y of each node, parts in
    order), of which every part's ``displacement`` is a view.

    A solid model's (:attr:`dimension` 3) reactions are ``[fx, fy, fz]``, its
    displacements x, y, z of each node, its history has the z columns
    (``reaction:SUPPORT.fz``, ``interface:NAME.fx``/``fy``/``fz``,
    ``probe:NAME.uz``); ``lines`` is empty (line probes are plane only).
    """

    def __init__(
        self,
        raw: Dict[str, Any],
        model: Model,
        law: Optional[str] = None,
        friction: Optional[float] = None,
    ) -> None:
        self._model = model
        self._law = law
        self._friction = friction
        self.summary: Dict[str, Any] = raw["summary"]
        self.load_factor: float = raw["load_factor"]
        #: The last increment's load step (its name) and total time.
        self.step: str = raw["step"]
        self.time: float = raw["time"]
        self.displacements: np.ndarray = raw["u"]
        #: 2 for a plane model, 3 for a solid one.
        self.dimension: int = int(raw.get("dimension", 2))
        dim = self.dimension
        self.parts: Dict[str, PartResult] = {}
        for p in raw["parts"]:
            n = len(p["points"])
            start = dim * p["node_offset"]
            if dim == 3:
                empty = np.zeros(0, dtype=np.int64)
                p = dict(
                    p,
                    triangles=np.zeros((0, 3), dtype=np.int64),
                    triangle_ids=empty,
                    quads=np.zeros((0, 4), dtype=np.int64),
                    quad_ids=empty,
                )
            self.parts[p["name"]] = PartResult(
                name=p["name"],
                points=p["points"],
                triangles=p["triangles"],
                triangle_ids=p["triangle_ids"],
                quads=p["quads"],
                quad_ids=p["quad_ids"],
                boundaries=dict(p["boundaries"]),
                material=dict(p["material"]),
                displacement=self.displacements[start : start + dim * n].reshape(n, dim),
                stress=p["nodal_stress"],
                element_stress=p["element_stress"],
                von_mises=p["nodal_von_mises"],
                element_von_mises=p["element_von_mises"],
                sigma_theta=p.get("nodal_sigma_theta"),
                element_sigma_theta=p.get("element_sigma_theta"),
                tetrahedra=p.get("tetrahedra"),
                tetrahedron_ids=p.get("tetrahedron_ids"),
                hexahedra=p.get("hexahedra"),
                hexahedron_ids=p.get("hexahedron_ids"),
            )
        known = {f for f in InterfaceResult.__dataclass_fields__ if f != "extra"}
        self.interfaces: Dict[str, InterfaceResult] = {}
        for i in raw["interfaces"]:
            # Fields the library adds later pass through in `extra`.
            extra = {k: v for k, v in i.items() if k not in known}
            self.interfaces[i["name"]] = InterfaceResult(**{k: i[k] for k in known if k in i}, extra=extra)
        self.reactions: Dict[str, np.ndarray] = {
            r["support"]: np.array([r["fx"], r["fy"]] + ([r["fz"]] if r.get("fz") is not None else []))
            for r in self.summary["reactions"]
        }
        #: Every converged increment, as the columns of ``history.csv``:
        #: ``increment``, ``step`` (a list of names), ``step_index``,
        #: ``load_factor``, ``time``, ``reaction:SUPPORT.fx``/``.fy``,
        #: ``interface:NAME.force_n``/``.force_s``/``.contact_length``/``.max_pressure``,
        #: ``probe:NAME.ux``/``.uy`` — NumPy arrays, one entry per increment.
        self.history: Dict[str, Any] = dict(raw.get("history", {}))
        #: The line probes (``[[line]]``) at the last increment, by name: each a
        #: dict of ``s`` (distance from the line's start), ``x`` ``(n, 2)``,
        #: ``part`` (a list of part names), ``u`` ``(n, 2)``, ``stress``
        #: ``(n, 3)`` (σxx, σyy, σxy) and ``von_mises`` — the columns of
        #: ``lines/<name>.csv``, for the points of the line that lie in a part.
        self.lines: Dict[str, Dict[str, Any]] = dict(raw.get("lines", {}))

    @property
    def status(self) -> str:
        """The run status of the summary (``completed`` ...)."""
        return self.summary["status"]

    @property
    def max_displacement(self) -> Dict[str, Any]:
        """The largest |u| with its position, part and node (from the summary)."""
        return dict(self.summary["max_displacement"])

    def to_meshio(self, part: Optional[str] = None) -> Any:
        """Part ``part`` as a ``meshio.Mesh`` (see :meth:`PartResult.to_meshio`),
        or, without ``part``, a dict of them by part name."""
        if part is not None:
            return self.parts[part].to_meshio()
        return {name: p.to_meshio() for name, p in self.parts.items()}

    def write(self, folder: PathLike, *, force: bool = False) -> Dict[str, Any]:
        """Writes the files of ``cfe run`` into ``folder`` (results.pvd, vtu/,
        pairs.csv, summary.json, sigma_yy.png, displacement.png), increment by
        increment. The per-increment files need every increment, which these
        results do not keep, so the model is solved again (the solve is
        deterministic: the same numbers); ``Model.solve(out=folder)`` does both
        in one pass. ``folder`` is checked as by ``Model.solve(out=…)``, ``force``
        as there. Returns the new summary."""
        raw = self._model._native.solve(
            None, Path(folder), self._law, self._friction, None, force
        )
        return raw["summary"]

    def __repr__(self) -> str:
        md = self.summary.get("max_displacement", {})
        return (
            f"Results('{self.summary.get('title')}', {self.summary.get('unknowns')} unknowns, "
            f"status {self.status}, max |u| = {md.get('value', float('nan')):e} in part '{md.get('part')}')"
        )
