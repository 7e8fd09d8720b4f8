"""meshio in and out: a Gmsh file read by meshio equals the library's own Gmsh
reader; a mesh and a part's results survive a round trip through meshio and a
VTU file."""

import numpy as np
import pytest

import cfe
from conftest import REPO, assert_same_results, plate_on_base_dict, rectangle

meshio = pytest.importorskip("meshio")

GMSH = REPO / "tests" / "data" / "gmsh"


def test_gmsh_file_through_meshio_equals_the_library_reader():
    """The Gmsh plate on a base read by meshio (physical surfaces choose each
    part, physical curves name the boundaries) gives the numbers of the TOML
    file that reads the same .msh itself."""
    reference = cfe.Model.from_file(GMSH / "plate_on_base.toml").solve()
    m = meshio.read(GMSH / "plate_on_base_41.msh")
    base = cfe.Mesh.from_meshio(m, surfaces=["base"], part="base")
    plate = cfe.Mesh.from_meshio(m, surfaces=["plate"], part="plate")
    assert base.triangles.shape == (480, 3) and plate.triangles.shape == (336, 3)
    assert {"bottom", "top"} <= set(plate.boundaries)
    d = plate_on_base_dict()
    d["part"][0] = {"name": "base", "material": "steel", "mesh": base}
    d["part"][1] = {"name": "plate", "material": "steel", "mesh": plate}
    assert_same_results(cfe.Model(d).solve(), reference, rtol=1e-12)


def test_mesh_round_trip():
    """cfe.Mesh → meshio.Mesh → cfe.Mesh keeps points, elements and boundaries,
    also through a file."""
    a = cfe.Mesh(**rectangle([0.0, 3.0], [0.0, 2.0], (3, 2)), part="p")
    b = cfe.Mesh.from_meshio(a.to_meshio(), part="p")
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    assert a.boundaries.keys() == b.boundaries.keys()
    for k in a.boundaries:
        np.testing.assert_array_equal(a.boundaries[k], b.boundaries[k])


def test_meshio_mesh_as_a_part(tmp_path):
    """A meshio.Mesh given as a part's `mesh` (written to and read from a file
    first) gives the numbers of the built-in mesher."""
    reference = cfe.Model(plate_on_base_dict()).solve()
    plate = cfe.Mesh(**rectangle([30.0, 170.0], [120.0, 135.0], (28, 6)), part="plate")
    path = tmp_path / "plate.msh"
    meshio.write(path, plate.to_meshio(), file_format="gmsh22", binary=False)
    d = plate_on_base_dict()
    d["part"][1] = {"name": "plate", "material": "steel", "mesh": meshio.read(path)}
    assert_same_results(cfe.Model(d).solve(), reference, rtol=1e-12)


def test_results_to_meshio_and_back(tmp_path):
    """A part's results as a meshio mesh, written to VTU and read back: the same
    points, cells, displacements and stresses, nodal and per element."""
    r = cfe.Model(plate_on_base_dict()).solve()
    for name, part in r.parts.items():
        m = r.to_meshio(name)
        path = tmp_path / f"{name}.vtu"
        meshio.write(path, m)
        back = meshio.read(path)
        np.testing.assert_allclose(back.points[:, :2], part.points)
        np.testing.assert_array_equal(back.cells_dict["triangle"], part.triangles)
        np.testing.assert_allclose(back.point_data["displacement"][:, :2], part.displacement)
        np.testing.assert_allclose(back.point_data["von_mises"], part.von_mises)
        np.testing.assert_allclose(back.cell_data["sigma_yy"][0], part.element_stress[part.triangle_ids, 1])
    assert set(r.to_meshio()) == {"base", "plate"}


def _pairs_csv(path):
    """pairs.csv as a dict of columns (text), one entry per row."""
    import csv

    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def test_meshio_reads_every_vtu_array_of_a_run(tmp_path):
    """Every ``parts_*.vtu`` and ``pairs_*.vtu`` of a run (10 increments, all
    written), read with meshio, holds every array with its shape and values: the
    field data the increment's load factor i/10 and step, every array of every
    file its shape; the last increment's pairs file the positions, displacements,
    normals, states and contact columns of the run's pairs.csv and results, and
    its parts file the results' displacements, nodal and element stresses, von
    Mises and part ids. (meshio 5.3.5 gave the displacement's values to
    LOAD_FACTOR and failed on some pairs files while the field data's blocks came
    first in the appended data.)"""
    r = cfe.Model(plate_on_base_dict()).solve(out=tmp_path)
    csv = _pairs_csv(tmp_path / "pairs.csv")
    last = 10
    assert set(csv["increment"].astype(int)) == {last}
    increments = list(range(1, last + 1))
    parts_files = sorted((tmp_path / "vtu").glob("parts_*.vtu"))
    pairs_files = sorted((tmp_path / "vtu").glob("pairs_*.vtu"))
    assert [p.name for p in parts_files] == [f"parts_{i:04d}.vtu" for i in increments]
    assert [p.name for p in pairs_files] == [f"pairs_{i:04d}.vtu" for i in increments]
    names = list(r.parts)
    n_points = sum(len(p.points) for p in r.parts.values())
    n_cells = sum(len(p.element_stress) for p in r.parts.values())
    itf = r.interfaces["plate-base"]
    k = len(itf)
    codes = {"open": 0, "bonded": 1, "slip": 2}
    num = lambda c: csv[c].astype(float)  # noqa: E731
    pair_scalars = ("gap_n", "slip_s", "force_n", "force_s", "violation_amount", "gap0", "gap", "slip",
                    "pressure", "shear", "tributary", "state", "bonded", "settled", "violation", "interface_id")

    def check_fields(m, inc):
        assert set(m.field_data) == {"TIME", "STEP", "LOAD_FACTOR"}
        np.testing.assert_allclose(m.field_data["LOAD_FACTOR"], [inc / last], rtol=1e-14)
        np.testing.assert_array_equal(m.field_data["STEP"], [1.0])
        assert m.field_data["TIME"].shape == (1,)

    for inc, path in zip(increments, pairs_files):
        m = meshio.read(path)
        check_fields(m, inc)
        pd = m.point_data
        assert m.points.shape == (k, 3)
        assert [c.type for c in m.cells] == ["vertex"] and m.cells[0].data.shape == (k, 1)
        assert set(pd) == set(pair_scalars) | {"displacement", "normal"}
        for name in pair_scalars:
            assert pd[name].shape == (k,), name
        for name in ("displacement", "normal"):
            assert pd[name].shape == (k, 3), name
            np.testing.assert_array_equal(pd[name][:, 2], 0.0)
        np.testing.assert_allclose(np.linalg.norm(pd["normal"], axis=1), 1.0, rtol=1e-12)
        if inc != last:
            continue
        np.testing.assert_allclose(m.points[:, :2], np.column_stack([num("x"), num("y")]), rtol=1e-15)
        for name in ("gap_n", "slip_s", "force_n", "force_s", "violation_amount", "gap0", "gap", "slip",
                     "pressure", "shear", "tributary"):
            np.testing.assert_allclose(pd[name], num(name), rtol=1e-15, atol=0, err_msg=name)
            np.testing.assert_allclose(pd[name], getattr(itf, name), rtol=1e-15, atol=0, err_msg=name)
        state = np.array([codes[s] for s in csv["state"]])
        np.testing.assert_array_equal(pd["state"], state)
        np.testing.assert_array_equal(pd["bonded"], (state == 1).astype(int))
        np.testing.assert_array_equal(pd["settled"], (csv["settled"] == "true").astype(int))
        np.testing.assert_array_equal(pd["violation"], itf.violation)
        np.testing.assert_array_equal(pd["interface_id"], np.zeros(k, dtype=int))
        node_part = r.parts[itf.node_part]
        np.testing.assert_allclose(pd["displacement"][:, :2], node_part.displacement[itf.node], rtol=1e-15)
        np.testing.assert_allclose(pd["normal"][:, :2], itf.normal, rtol=1e-15)

    for inc, path in zip(increments, parts_files):
        m = meshio.read(path)
        check_fields(m, inc)
        assert m.points.shape == (n_points, 3)
        assert [c.type for c in m.cells] == ["triangle"] and m.cells[0].data.shape == (n_cells, 3)
        pd, cd = m.point_data, m.cell_data
        assert set(pd) == {"displacement", "sigma_xx", "sigma_yy", "sigma_xy", "von_mises", "part_id"}
        assert set(cd) == {"sigma_xx", "sigma_yy", "sigma_xy", "von_mises", "part_id"}
        assert pd["displacement"].shape == (n_points, 3)
        np.testing.assert_array_equal(pd["displacement"][:, 2], 0.0)
        for name in ("sigma_xx", "sigma_yy", "sigma_xy", "von_mises", "part_id"):
            assert pd[name].shape == (n_points,), name
            assert cd[name][0].shape == (n_cells,), name
        if inc != last:
            continue
        expected_points = np.concatenate([p.points for p in r.parts.values()])
        np.testing.assert_allclose(m.points[:, :2], expected_points, rtol=1e-15)
        np.testing.assert_array_equal(m.points[:, 2], 0.0)
        np.testing.assert_array_equal(pd["displacement"][:, :2], r.displacements.reshape(-1, 2))
        part_id = np.concatenate([np.full(len(r.parts[n].points), i) for i, n in enumerate(names)])
        np.testing.assert_array_equal(pd["part_id"], part_id)
        cell_part = np.concatenate([np.full(len(r.parts[n].element_stress), i) for i, n in enumerate(names)])
        np.testing.assert_array_equal(cd["part_id"][0], cell_part)
        stress = np.concatenate([p.stress for p in r.parts.values()])
        element_stress = np.concatenate([p.element_stress for p in r.parts.values()])
        for c, name in enumerate(("sigma_xx", "sigma_yy", "sigma_xy")):
            np.testing.assert_allclose(pd[name], stress[:, c], rtol=1e-12, atol=1e-9, err_msg=name)
            np.testing.assert_allclose(cd[name][0], element_stress[:, c], rtol=1e-12, atol=1e-9, err_msg=name)
        vm = np.concatenate([p.von_mises for p in r.parts.values()])
        evm = np.concatenate([p.element_von_mises for p in r.parts.values()])
        np.testing.assert_allclose(pd["von_mises"], vm, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(cd["von_mises"][0], evm, rtol=1e-12, atol=1e-9)
