"""Solid (3D) models through the Python package: the one `cfe.Model` reads them
from files, TOML, dicts, arrays of tetrahedra and hexahedra and meshio meshes,
and returns 3D results (displacements (n, 3), six stresses, the pairs' second
tangent and global force, history with z, `to_meshio`), checked against closed
forms, the command line's own output files, and invariances."""

import csv
import subprocess

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES, REPO

E, NU, P = 70e3, 0.3, 40.0


def blocks_toml(base_cells=(2, 2, 2), base_kind="hex8", top_cells=(3, 3, 3), top_kind="tet4",
                law="rigid", pressure=P, mesh_keys=True):
    """Two blocks stacked, a base [0,1]×[0,2]×[0,1] and a top [0,1]×[0,2]×[1,2.5],
    meshed independently (faces not nested: 2 × 2 against 3 × 3), tied through
    one interface, held by symmetry rollers (x on the left sides, y on the front
    sides, z under the base) and pressed by a uniform pressure on the top."""
    bx = by = ""
    if mesh_keys:
        bx = (f'box = {{ x = [0.0, 1.0], y = [0.0, 2.0], z = [0.0, 1.0], '
              f'cells = {list(base_cells)}, elements = "{base_kind}" }}')
        by = (f'box = {{ x = [0.0, 1.0], y = [0.0, 2.0], z = [1.0, 2.5], '
              f'cells = {list(top_cells)}, elements = "{top_kind}" }}')
    supports = "".join(
        f'\n[[support]]\npart = "{p}"\nboundary = "{b}"\nfix = ["{c}"]\n'
        for p, b, c in [("base", "left", "x"), ("base", "front", "y"), ("base", "bottom", "z"),
                        ("top", "left", "x"), ("top", "front", "y")]
    )
    return f"""title = "two blocks"
[materials.al]
E = {E}
nu = {NU}

[[part]]
name = "base"
material = "al"
{bx}

[[part]]
name = "top"
material = "al"
{by}

[[interface]]
name = "tie"
host = "base"
nodes = "top"
boundary = "bottom"
law = "{law}"
{supports}
[[load]]
part = "top"
boundary = "top"
pressure = {pressure}
"""


@pytest.mark.parametrize("kind", ["hex8", "tet4"])
def test_tied_blocks_with_nested_faces_give_the_closed_form(kind):
    """A block pressed by p through a tied interface whose node-part face mesh (4 × 4)
    is finer than the host's (2 × 2), nodes not matching: σzz = −p, the other stresses
    0, the top sinks by pL/E and widens by νp/E (closed form, to the penalty's 1e-5)."""
    model = cfe.Model.from_toml(blocks_toml(base_kind=kind, top_kind=kind, top_cells=(4, 4, 3)))
    assert model.dimension == 3
    r = model.solve()
    assert r.status == "completed" and r.dimension == 3
    L = 2.5
    for name in ("base", "top"):
        part = r.parts[name]
        assert part.stress.shape == (len(part.points), 6)
        assert part.element_stress.shape == (len(part.tetrahedra) + len(part.hexahedra), 6)
        assert part.displacement.shape == (len(part.points), 3)
        np.testing.assert_allclose(part.sigma_zz, -P, rtol=1e-5)
        np.testing.assert_allclose(part.element_stress[:, 2], -P, rtol=1e-5)
        np.testing.assert_allclose(part.stress[:, [0, 1, 3, 4, 5]], 0, atol=1e-5 * P)
        np.testing.assert_allclose(part.von_mises, P, rtol=1e-5)
        x, y, z = part.points.T
        np.testing.assert_allclose(part.uz, -P * z / E, atol=1e-5 * P * L / E)
        np.testing.assert_allclose(part.ux, NU * P * x / E, atol=1e-5 * P * L / E)
        np.testing.assert_allclose(part.uy, NU * P * y / E, atol=1e-5 * P * L / E)
    tie = r.interfaces["tie"]
    assert len(tie) == 5 * 5
    # The pairs carry the load: Σ f_n = p A, the global forces agree (on the top, +z).
    np.testing.assert_allclose(tie.force_n.sum(), P * 2.0, rtol=1e-9)
    np.testing.assert_allclose(tie.force.sum(axis=0), [0, 0, P * 2.0], atol=1e-6 * P * 2.0)
    np.testing.assert_allclose(tie.normal, np.tile([0, 0, 1.0], (len(tie), 1)), atol=1e-12)
    np.testing.assert_allclose(r.reactions["base/bottom"], [0, 0, P * 2.0], atol=1e-6 * P * 2.0)
    # The second tangent completes a right-handed orthonormal frame.
    np.testing.assert_allclose(np.cross(tie.t1, tie.t2), tie.normal, atol=1e-12)
    np.testing.assert_allclose(np.einsum("ij,ij->i", tie.t1, tie.t2), 0, atol=1e-12)
    np.testing.assert_allclose(tie.force_t2, 0, atol=1e-6 * P * 2.0)


def test_tied_blocks_with_non_nested_faces_balance_and_approach_the_closed_form():
    """TET4 (4 × 4 face) on HEX8 (2 × 2) tied: the coupling transmits p A exactly and the
    top's mean settlement is pL/E within 1e-3 (a non-nested face pair passes the patch
    test only approximately: the measured error is 3e-4)."""
    r = cfe.Model.from_toml(blocks_toml(top_cells=(4, 4, 3))).solve()
    assert r.status == "completed"
    tie = r.interfaces["tie"]
    np.testing.assert_allclose(tie.force_n.sum(), P * 2.0, rtol=1e-9)
    np.testing.assert_allclose(r.reactions["base/bottom"][2], P * 2.0, rtol=1e-9)
    top = r.parts["top"]
    settlement = top.uz[np.isclose(top.points[:, 2], 2.5)].mean()
    assert settlement == pytest.approx(-P * 2.5 / E, rel=1e-3)


def read_vtu_displacements(path):
    import meshio

    return np.asarray(meshio.read(path).point_data["displacement"])


def test_plate_on_base_matches_the_command_line(cli, tmp_path):
    """`Model.from_file` of examples/plate_on_base_3d.toml gives the displacements and
    pair forces `cfe run` writes (its VTU and pairs.csv read back), to round-off."""
    out = tmp_path / "run"
    subprocess.run([str(cli), "run", str(EXAMPLES / "plate_on_base_3d.toml"), "--out", str(out)],
                   check=True, capture_output=True)
    r = cfe.Model.from_file(EXAMPLES / "plate_on_base_3d.toml").solve()
    assert r.status == "completed"
    vtus = sorted((out / "vtu").glob("parts*.vtu")) or sorted(out.rglob("*.vtu"))
    last = [v for v in vtus if "pair" not in v.name][-1]
    u_cli = read_vtu_displacements(last)
    u_py = np.concatenate([r.parts[p].displacement for p in ("base", "plate")])
    scale = np.abs(u_py).max()
    np.testing.assert_allclose(u_py, u_cli, rtol=0, atol=1e-12 * scale)
    rows = [row for row in csv.DictReader(open(out / "pairs.csv"))]
    final = max(int(row["increment"]) for row in rows)
    rows = [row for row in rows if int(row["increment"]) == final]
    pairs = r.interfaces["plate-base"]
    assert [int(row["node"]) for row in rows] == pairs.node.tolist()
    f_scale = np.abs(pairs.force_n).max()
    for col, values in [("force_n", pairs.force_n), ("force_s", pairs.force_s),
                        ("force_t2", pairs.force_t2), ("gap_n", pairs.gap_n),
                        ("force_x", pairs.force[:, 0]), ("force_y", pairs.force[:, 1]),
                        ("force_z", pairs.force[:, 2]), ("z", pairs.z)]:
        ref = np.array([float(row[col]) for row in rows])
        tol = 1e-12 * (np.abs(ref).max() if col in ("gap_n", "z") else f_scale)
        np.testing.assert_allclose(values, ref, rtol=0, atol=tol, err_msg=col)
    assert [row["state"] for row in rows] == list(pairs.state)
    # The history has the z columns, and its last row is the results' state.
    h = r.history
    np.testing.assert_allclose(h["reaction:base/bottom.fz"][-1], r.reactions["base/bottom"][2])
    np.testing.assert_allclose(h["interface:plate-base.fz"][-1], pairs.force[:, 2].sum(), rtol=1e-12)


def model_from_meshes(meshes, law="rigid", refine=1):
    """The two blocks as a dict whose parts give `meshes[name]` as arrays or a mesh."""
    problem = {
        "materials": {"al": {"E": E, "nu": NU}},
        "part": [dict({"name": n, "material": "al"}, **meshes[n]) for n in ("base", "top")],
        "interface": [{"name": "tie", "host": "base", "nodes": "top", "boundary": "bottom",
                       "law": law}],
        "support": [{"part": p, "boundary": b, "fix": [c]}
                    for p, b, c in [("base", "left", "x"), ("base", "front", "y"),
                                    ("base", "bottom", "z"), ("top", "left", "x"),
                                    ("top", "front", "y")]],
        "load": [{"part": "top", "boundary": "top", "pressure": P}],
    }
    return cfe.Model(problem, refine=refine)


def hex_block(x, y, z, cells):
    """The box mesher's HEX8 mesh as arrays: node (i, j, k) at (k (ny+1) + j)(nx+1) + i,
    corners in the VTK order, each side a boundary of faces named as the mesher names it."""
    nx, ny, nz = cells
    xs, ys, zs = (np.linspace(a, b, n + 1) for (a, b), n in zip((x, y, z), cells))
    points = np.array([[xi, yj, zk] for zk in zs for yj in ys for xi in xs])

    def node(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    hexa = [[node(i + a, j + b, k + c) for a, b, c in
             [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]]
            for k in range(nz) for j in range(ny) for i in range(nx)]
    sides = {"left": (0, 0), "right": (0, nx), "front": (1, 0), "back": (1, ny),
             "bottom": (2, 0), "top": (2, nz)}
    boundaries = {}
    for name, (axis, at) in sides.items():
        others = [a for a in range(3) if a != axis]
        n = [nx, ny, nz]
        faces = []
        for p in range(n[others[0]]):
            for q in range(n[others[1]]):
                corners = []
                for dp, dq in [(0, 0), (1, 0), (1, 1), (0, 1)]:
                    ijk = [0, 0, 0]
                    ijk[axis], ijk[others[0]], ijk[others[1]] = at, p + dp, q + dq
                    corners.append(node(*ijk))
                faces.append(corners)
        boundaries[name] = np.array(faces)
    return {"points": points, "hexahedra": np.array(hexa), "boundaries": boundaries}


def test_arrays_and_meshio_give_the_results_of_the_file():
    """The same two blocks from the file's `box` keys, from arrays (HEX8 built with
    NumPy, TET4 read off the file's mesh), and from meshio meshes give the same
    displacements, stresses and pair forces."""
    ref = cfe.Model.from_toml(blocks_toml())
    r0 = ref.solve()
    top = ref.mesh("top")
    arrays = {
        "base": hex_block((0.0, 1.0), (0.0, 2.0), (0.0, 1.0), (2, 2, 2)),
        "top": {"points": top.points, "tetrahedra": top.tetrahedra, "boundaries": top.boundaries},
    }
    base = cfe.Mesh(**arrays["base"], part="base")
    np.testing.assert_array_equal(base.hexahedra, ref.mesh("base").hexahedra)
    np.testing.assert_array_equal(base.points, ref.mesh("base").points)
    from_meshio = {n: {"mesh": ref.mesh(n).to_meshio()} for n in ("base", "top")}
    for meshes in (arrays, from_meshio):
        model = model_from_meshes(meshes)
        assert model.dimension == 3
        r = model.solve()
        assert r.status == "completed"
        for n in ("base", "top"):
            scale = np.abs(r0.parts[n].displacement).max()
            np.testing.assert_allclose(r.parts[n].displacement, r0.parts[n].displacement,
                                       rtol=0, atol=1e-12 * scale)
            np.testing.assert_allclose(r.parts[n].stress, r0.parts[n].stress, rtol=0, atol=1e-9 * P)
        np.testing.assert_allclose(r.interfaces["tie"].force, r0.interfaces["tie"].force,
                                   rtol=0, atol=1e-10 * P)
    # `refine` subdivides meshes given as arrays as it does the file's boxes.
    for n in ("base", "top"):
        refined = model_from_meshes(arrays, refine=2).mesh(n)
        boxed = cfe.Model.from_toml(blocks_toml(), refine=2).mesh(n)
        assert refined.points.shape == boxed.points.shape
        assert refined.tetrahedra.shape == boxed.tetrahedra.shape
        assert refined.hexahedra.shape == boxed.hexahedra.shape


def test_meshio_physical_groups_name_parts_and_boundaries():
    """A meshio mesh of two physical volumes with physical surfaces: `volumes` picks a
    part's cells and the surfaces on its boundary become its named boundaries (those
    inside it or on the other volume left out), as the 2D path does with surfaces."""
    import meshio

    lower = cfe.Mesh(**hex_block((0.0, 1.0), (0.0, 1.0), (0.0, 1.0), (1, 1, 2)))
    pts = lower.points
    hexa = lower.hexahedra
    bottom = lower.boundaries["bottom"]
    top = lower.boundaries["top"]
    middle = np.array([[4, 5, 7, 6]])[:, [0, 1, 3, 2]]  # the face z = 0.5, inside
    mesh = meshio.Mesh(
        pts,
        [("hexahedron", hexa), ("quad", bottom), ("quad", top), ("quad", middle)],
        cell_data={"gmsh:physical": [np.array([1, 2]), np.array([3]), np.array([4]), np.array([5])]},
        field_data={"low": np.array([1, 3]), "high": np.array([2, 3]), "floor": np.array([3, 2]),
                    "roof": np.array([4, 2]), "mid": np.array([5, 2])},
    )
    low = cfe.Mesh.from_meshio(mesh, volumes=["low"], part="low")
    assert low.dimension == 3 and len(low.hexahedra) == 1 and len(low.points) == 8
    # Its own faces: the floor; the middle face bounds it too (the other volume is not in it).
    assert sorted(low.boundaries) == ["floor", "mid"]
    high = cfe.Mesh.from_meshio(mesh, volumes=[2], part="high")
    assert sorted(high.boundaries) == ["mid", "roof"]
    both = cfe.Mesh.from_meshio(mesh, part="both")
    assert sorted(both.boundaries) == ["floor", "roof"]  # the middle face is inside
    with pytest.raises(cfe.MeshError, match="no physical volume 'nope'"):
        cfe.Mesh.from_meshio(mesh, volumes=["nope"])
    with pytest.raises(cfe.MeshError, match="`volumes`, not `surfaces`"):
        cfe.Mesh.from_meshio(mesh, surfaces=["floor"])


def test_to_meshio_round_trip(tmp_path):
    """`Results.to_meshio` holds tetra/hexahedron cells with the displacements and six
    stresses, which survive a VTU file; `Mesh.to_meshio` read back by `from_meshio`
    gives the same mesh, boundaries included."""
    import meshio

    model = cfe.Model.from_toml(blocks_toml())
    r = model.solve()
    for name, kind in (("base", "hexahedron"), ("top", "tetra")):
        part = r.parts[name]
        m = r.to_meshio(name)
        assert [c.type for c in m.cells] == [kind]
        path = tmp_path / f"{name}.vtu"
        meshio.write(path, m)
        back = meshio.read(path)
        np.testing.assert_array_equal(back.points, part.points)
        np.testing.assert_array_equal(back.point_data["displacement"], part.displacement)
        for i, c in enumerate(["sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_xz"]):
            np.testing.assert_array_equal(back.point_data[c], part.stress[:, i])
            np.testing.assert_array_equal(back.cell_data[c][0], part.element_stress[:, i])
        np.testing.assert_array_equal(back.point_data["von_mises"], part.von_mises)
        mesh = model.mesh(name)
        again = cfe.Mesh.from_meshio(mesh.to_meshio(), part=name)
        np.testing.assert_array_equal(again.points, mesh.points)
        np.testing.assert_array_equal(again.tetrahedra, mesh.tetrahedra)
        np.testing.assert_array_equal(again.hexahedra, mesh.hexahedra)
        assert again.boundaries.keys() == mesh.boundaries.keys()
        for b in mesh.boundaries:
            np.testing.assert_array_equal(again.boundaries[b], mesh.boundaries[b])


def rotation(axis, angle):
    """The rotation matrix about the unit `axis` by `angle` (Rodrigues)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_rigid_rotation_rotates_the_results():
    """The clamped two-block model turned by a rigid rotation R (arrays) gives R u,
    R σ Rᵀ, the same normal forces and the pair forces turned by R (to round-off)."""
    def clamped(points_of, law):
        ref = cfe.Model.from_toml(blocks_toml())
        meshes = {}
        for n in ("base", "top"):
            m = ref.mesh(n)
            meshes[n] = {"points": points_of(m.points), "tetrahedra": m.tetrahedra if len(m.tetrahedra) else None,
                         "hexahedra": m.hexahedra if len(m.hexahedra) else None, "boundaries": m.boundaries}
        problem = {
            "materials": {"al": {"E": E, "nu": NU}},
            "part": [dict({"name": n, "material": "al"}, **meshes[n]) for n in ("base", "top")],
            "interface": [{"name": "tie", "host": "base", "nodes": "top", "boundary": "bottom", "law": law}],
            "support": [{"part": "base", "boundary": "bottom", "fix": ["x", "y", "z"]}],
            "load": [{"part": "top", "boundary": "top", "pressure": P},
                     {"part": "top", "boundary": "right", "pressure": 0.3 * P}],
        }
        return cfe.Model(problem).solve()

    R = rotation([1.0, 2.0, 0.5], 0.7)
    r0 = clamped(lambda p: p, "contact")
    r1 = clamped(lambda p: p @ R.T, "contact")
    for n in ("base", "top"):
        u0, u1 = r0.parts[n].displacement, r1.parts[n].displacement
        scale = np.abs(u0).max()
        np.testing.assert_allclose(u1, u0 @ R.T, rtol=0, atol=1e-9 * scale)
        s0 = r0.parts[n].stress
        t0 = np.array([[[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]] for s in s0])
        s1 = r1.parts[n].stress
        t1 = np.array([[[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]] for s in s1])
        np.testing.assert_allclose(t1, R @ t0 @ R.T, rtol=0, atol=1e-7 * P)
        np.testing.assert_allclose(r1.parts[n].von_mises, r0.parts[n].von_mises, rtol=0, atol=1e-7 * P)
    i0, i1 = r0.interfaces["tie"], r1.interfaces["tie"]
    np.testing.assert_array_equal(i0.state, i1.state)
    np.testing.assert_allclose(i1.force_n, i0.force_n, rtol=0, atol=1e-9 * P)
    np.testing.assert_allclose(i1.force, i0.force @ R.T, rtol=0, atol=1e-9 * P)
    np.testing.assert_allclose(i1.normal, i0.normal @ R.T, atol=1e-12)


def test_bad_arrays_raise_actionable_mesh_errors():
    """Wrong shapes and mixed dimensions raise `MeshError`/`ModelError` saying what to give."""
    block = hex_block((0.0, 1.0), (0.0, 1.0), (0.0, 1.0), (1, 1, 1))
    pts, hexa = block["points"], block["hexahedra"]
    tets = np.array([[0, 1, 3, 4]])
    with pytest.raises(cfe.MeshError, match=r"`triangles` must have shape \(n, 3\).*`tetrahedra=` in a solid"):
        cfe.Mesh(pts[:, :2], triangles=tets)
    with pytest.raises(cfe.MeshError, match=r"not in a plane z = const.*`tetrahedra=`"):
        cfe.Mesh(pts, triangles=tets)
    with pytest.raises(cfe.MeshError, match=r"tetrahedra and hexahedra need points \(n, 3\)"):
        cfe.Mesh(pts[:, :2], tetrahedra=tets)
    with pytest.raises(cfe.MeshError, match=r"need points \(n, 3\) \(x, y, z\), got shape \[8, 2\]"):
        cfe._cfe.Mesh(np.ascontiguousarray(pts[:, :2]), tetrahedra=tets)  # the native check
    with pytest.raises(cfe.MeshError, match=r"`tetrahedra` must have shape \(n, 4\).*`hexahedra=`"):
        cfe.Mesh(pts, tetrahedra=hexa)
    with pytest.raises(cfe.MeshError, match="plane .* or solid .* not both"):
        cfe.Mesh(pts, triangles=np.array([[0, 1, 2]]), tetrahedra=tets)
    with pytest.raises(cfe.MeshError, match=r"uses node 9, but the part has 8 nodes"):
        cfe.Mesh(pts, tetrahedra=np.array([[0, 1, 3, 9]]))
    with pytest.raises(cfe.MeshError, match="not a face of an element on the part's boundary"):
        cfe.Mesh(pts, hexahedra=hexa, boundaries={"diag": np.array([[0, 1, 6]])})
    with pytest.raises(cfe.MeshError, match=r"edges \(j, 2\) bound a plane mesh"):
        cfe.Mesh(pts, hexahedra=hexa, boundaries={"edge": np.array([[0, 1]])})
    # A flat hexahedron (all corners in one plane) is degenerate.
    flat = pts.copy()
    flat[:, 2] = 0.0
    with pytest.raises(cfe.MeshError, match="mesh of part 'flat'"):
        cfe.Mesh(flat, hexahedra=hexa, part="flat")
    # A mirrored (negative) element is turned, as the Gmsh reader turns it.
    turned = cfe.Mesh(pts, hexahedra=hexa[:, [0, 3, 2, 1, 4, 7, 6, 5]])
    np.testing.assert_array_equal(turned.hexahedra, hexa)
    plane = {"points": np.array([[0.0, 0], [1, 0], [0, 1]]), "triangles": np.array([[0, 1, 2]])}
    with pytest.raises(cfe.ModelError, match="mix plane and solid"):
        model_from_meshes({"base": block, "top": plane})
    both = {"base": dict(block, box={"x": [0.0, 1.0], "y": [0.0, 1.0], "z": [0.0, 1.0], "cells": [1, 1, 1]}),
            "top": block}
    with pytest.raises(cfe.ParseError, match="mesh given in memory and a `box` or `gmsh` key"):
        model_from_meshes(both)
    with pytest.raises(cfe.ModelError, match="part 'nowhere', which the problem does not define"):
        cfe.Model.from_toml(blocks_toml(), meshes={"nowhere": cfe.Mesh(pts, hexahedra=hexa)})
    # A solid interface's coupling error keeps its typed class and interface.
    with pytest.raises(cfe.CouplingError, match="lie on no host boundary face") as e:
        cfe.Model.from_toml(blocks_toml().replace("z = [1.0, 2.5]", "z = [1.5, 2.5]")).check()
    assert e.value.interface == "tie"
    with pytest.raises(cfe.ModelError, match="thickness"):
        cfe.Model.from_toml(blocks_toml().replace('material = "al"\nbox', 'material = "al"\nthickness = 2.0\nbox', 1))


def test_check_and_faces_by_node_set():
    """A solid boundary given as a node set takes every boundary face among its nodes;
    `check` describes the solid model."""
    block = hex_block((0.0, 1.0), (0.0, 1.0), (0.0, 1.0), (2, 2, 2))
    on_top = np.flatnonzero(np.isclose(block["points"][:, 2], 1.0))
    mesh = cfe.Mesh(block["points"], hexahedra=block["hexahedra"], boundaries={"lid": on_top})
    assert mesh.boundaries["lid"].shape == (4, 4)
    assert set(mesh.boundaries["lid"].ravel()) == set(on_top)
    # Outward: the lid's faces turn counter-clockwise seen from above (+z).
    p = mesh.points
    for f in mesh.boundaries["lid"]:
        n = np.cross(p[f[2]] - p[f[0]], p[f[3]] - p[f[1]])
        assert n[2] > 0
    text = cfe.Model.from_toml(blocks_toml()).check()
    assert "solid model" in text


def test_progress_out_and_law_override_in_3d(tmp_path):
    """A solid solve reports each increment with its history row (fz included), writes
    `cfe run`'s files with `out` (parts VTU of tetrahedra, pairs.csv with the 3D
    columns), and `law="coulomb"` overrides the interface law as in 2D."""
    model = cfe.Model.from_toml(blocks_toml(law="contact", top_cells=(4, 4, 3)).replace(
        'pressure = 40.0', 'pressure = 40.0\n\n[analysis]\nincrements = 2'))
    seen = []
    r = model.solve(progress=seen.append, out=tmp_path / "run", law="coulomb", friction=0.3)
    assert [i.increment for i in seen] == [1, 2]
    assert seen[-1].history["reaction:base/bottom.fz"] == pytest.approx(r.reactions["base/bottom"][2])
    assert r.interfaces["tie"].law == "coulomb" and r.interfaces["tie"].friction == 0.3
    header = (tmp_path / "run" / "pairs.csv").read_text().splitlines()[0].split(",")
    assert {"z", "force_t2", "force_x", "force_y", "force_z"} <= set(header)
    import meshio

    parts = meshio.read(sorted((tmp_path / "run" / "vtu").glob("parts_*.vtu"))[-1])
    assert {c.type for c in parts.cells} == {"hexahedron", "tetra"}
    u = np.concatenate([r.parts["base"].displacement, r.parts["top"].displacement])
    np.testing.assert_array_equal(parts.point_data["displacement"], u)
    summary = r.write(tmp_path / "again")
    assert summary["status"] == r.status == "completed"
    assert (tmp_path / "again" / "deformed.png").exists()


def test_dict_with_box_keys_reads_as_the_file():
    """A problem dict with the file's 3D keys (`box`, `fix = ["x", "y", "z"]`, a
    three-component force at a point box) is the solid model the TOML text makes."""
    problem = {
        "materials": {"al": {"E": E, "nu": NU}},
        "part": [{"name": "base", "material": "al",
                  "box": {"x": [0.0, 1.0], "y": [0.0, 2.0], "z": [0.0, 1.0], "cells": [2, 2, 2],
                          "elements": "hex8"}},
                 {"name": "top", "material": "al",
                  "box": {"x": [0.0, 1.0], "y": [0.0, 2.0], "z": [1.0, 2.5], "cells": [4, 4, 3],
                          "elements": "tet4"}}],
        "interface": [{"name": "tie", "host": "base", "nodes": "top", "boundary": "bottom", "law": "rigid"}],
        "support": [{"part": "base", "boundary": "bottom", "fix": ["x", "y", "z"]}],
        "load": [{"part": "top", "boundary": "top", "force": [10.0, 0.0, -80.0]}],
    }
    from_dict = cfe.Model(problem)
    assert from_dict.dimension == 3
    r = from_dict.solve()
    r_toml = cfe.Model.from_toml(from_dict.text).solve()
    np.testing.assert_array_equal(r.displacements, r_toml.displacements)
    # The supports carry the applied force back.
    np.testing.assert_allclose(r.reactions["base/bottom"], [-10.0, 0.0, 80.0], atol=1e-8 * 80)


@pytest.mark.parametrize("msh", ["cubes_41.msh", "cubes_22.msh"])
def test_meshio_reads_a_gmsh_file_as_the_library_does(msh):
    """A 3D Gmsh file read by meshio and `Mesh.from_meshio(volumes=[...])` gives each
    physical volume's mesh exactly as the library's reader (`gmsh = { file, volumes }`):
    the same nodes, elements, and physical surfaces as named boundaries."""
    import meshio

    folder = REPO / "tests" / "data" / "gmsh"
    text = "[materials.s]\nE = 1.0\nnu = 0.3\n" + "".join(
        f'[[part]]\nname = "{n}"\nmaterial = "s"\ngmsh = {{ file = "{msh}", volumes = ["{n}"] }}\n'
        for n in ("hexa", "tetra")
    )
    model = cfe.Model.from_toml(text, path=folder / "cubes.toml")
    assert model.dimension == 3
    read = meshio.read(folder / msh)
    for n in ("hexa", "tetra"):
        ours, theirs = cfe.Mesh.from_meshio(read, volumes=[n], part=n), model.mesh(n)
        np.testing.assert_array_equal(ours.points, theirs.points)
        np.testing.assert_array_equal(ours.tetrahedra, theirs.tetrahedra)
        np.testing.assert_array_equal(ours.hexahedra, theirs.hexahedra)
        assert ours.boundaries.keys() == theirs.boundaries.keys() and len(ours.boundaries) >= 3
        for b in theirs.boundaries:
            np.testing.assert_array_equal(ours.boundaries[b], theirs.boundaries[b])
