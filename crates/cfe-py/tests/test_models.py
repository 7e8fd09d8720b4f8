"""The same model three ways in: a file, TOML text, dicts (with parts as arrays,
as cfe.Mesh objects or as node-set boundaries); the results agree to round-off."""

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES, assert_same_results, plate_on_base_dict, rectangle


@pytest.fixture(scope="module")
def reference():
    return cfe.Model.from_file(EXAMPLES / "plate_on_base.toml").solve()


def test_toml_text_equals_file(reference):
    text = (EXAMPLES / "plate_on_base.toml").read_text()
    assert_same_results(cfe.Model.from_toml(text).solve(), reference, rtol=0)


def test_dict_equals_file(reference):
    model = cfe.Model(plate_on_base_dict())
    assert model.parts == ["base", "plate"]
    assert model.interfaces == ["plate-base"]
    assert model.settings["increments"] == 10
    assert_same_results(model.solve(), reference, rtol=0)


def test_dict_takes_numpy_values_and_integers(reference):
    """NumPy arrays and scalars, integers for floats, None for a left-out key."""
    d = plate_on_base_dict()
    d["materials"]["steel"]["E"] = 210000  # an integer
    d["part"][1]["rectangle"]["x"] = np.array([30.0, 170.0])
    d["part"][1]["rectangle"]["cells"] = np.array([28, 6])
    d["part"][1]["thickness"] = np.float64(1.0)
    d["interface"][0]["tolerance"] = None
    assert_same_results(cfe.Model(d).solve(), reference, rtol=0)


def test_arrays_equal_their_toml_twin(reference):
    """Both parts given as arrays (the mesher's numbering) give the TOML model's
    numbers."""
    d = plate_on_base_dict()
    d["part"][0] = {"name": "base", "material": "steel", **rectangle([0.0, 200.0], [0.0, 120.0], (20, 12))}
    d["part"][1] = {"name": "plate", "material": "steel", **rectangle([30.0, 170.0], [120.0, 135.0], (28, 6))}
    r = cfe.Model(d).solve()
    assert_same_results(r, reference, rtol=1e-12)
    assert r.max_displacement["value"] == pytest.approx(1.279561e-2, rel=1e-6)


def test_node_sets_and_clockwise_triangles(reference):
    """Boundaries as node sets and clockwise triangles (reversed by the library)
    make the same mesh as edges and counter-clockwise triangles."""
    base = rectangle([0.0, 200.0], [0.0, 120.0], (20, 12))
    base["triangles"] = base["triangles"][:, ::-1].copy()
    base["boundaries"] = {k: np.unique(v) for k, v in base["boundaries"].items()}
    mesh = cfe.Mesh(**base, part="base")
    assert mesh.triangles.shape == (480, 3)
    np.testing.assert_array_equal(mesh.boundary_nodes("bottom"), np.arange(21))
    d = plate_on_base_dict()
    d["part"][0] = {"name": "base", "material": "steel", "mesh": mesh}
    assert_same_results(cfe.Model(d).solve(), reference, rtol=1e-12)


def test_toml_with_given_meshes(reference):
    """TOML text whose part has no mesh key, its mesh given as arrays."""
    text = (EXAMPLES / "plate_on_base.toml").read_text()
    text = text.replace('rectangle = { x = [30.0, 170.0], y = [120.0, 135.0], cells = [28, 6] } # 336 T3', "")
    assert "rectangle = { x = [30.0" not in text
    plate = cfe.Mesh(**rectangle([30.0, 170.0], [120.0, 135.0], (28, 6)), part="plate")
    r = cfe.Model.from_toml(text, meshes={"plate": plate}).solve()
    assert_same_results(r, reference, rtol=1e-12)


def test_quads_from_arrays_equal_toml_q4():
    """A Q4 part from arrays equals `elements = "q4"` in the file."""
    d = plate_on_base_dict()
    d["part"][1]["rectangle"]["elements"] = "q4"
    ref = cfe.Model(d).solve()
    d["part"][1] = {"name": "plate", "material": "steel", **rectangle([30.0, 170.0], [120.0, 135.0], (28, 6), quads=True)}
    r = cfe.Model(d).solve()
    assert r.parts["plate"].quads.shape == (168, 4)
    assert len(r.parts["plate"].triangles) == 0
    assert_same_results(r, ref, rtol=1e-12)


def test_refined_model_and_run():
    """`refine` multiplies the unknowns as `cfe run --refine` does; `cfe.run`
    accepts a path, a dict or text."""
    coarse = cfe.run(EXAMPLES / "plate_on_base.toml")
    fine = cfe.run(plate_on_base_dict(), refine=2)
    assert fine.summary["unknowns"] > 3 * coarse.summary["unknowns"]
    assert fine.summary["refine"] == 2
    text = cfe.run((EXAMPLES / "plate_on_base.toml").read_text())
    assert text.max_displacement["value"] == coarse.max_displacement["value"]


def test_law_override():
    """`law="rigid"` ties every pair, as `cfe run --law rigid`."""
    r = cfe.Model.from_file(EXAMPLES / "plate_on_base.toml").solve(law="rigid")
    i = r.interfaces["plate-base"]
    assert i.law == "rigid" and i.bonded.all()
    assert (i.force_n < 0).any()  # tied: the plate's ends pull on the base
