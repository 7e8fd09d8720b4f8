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
