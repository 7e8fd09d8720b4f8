"""The pairs' pressure and shear from Python are stresses: force / (tributary
length × the node part's thickness), for a thickness other than 1."""

import numpy as np
import pytest

import cfe

# A block (node part, t thick, E = 1000, height 10) pressed by an interference
# δ = 0.01 onto a stiff, rigidly supported layer, its top held: uniaxial strain
# ε = δ / L, so σyy = −E δ / L whatever t, carried by forces t times larger.
TEXT = """
plane = "stress"
[materials.soft]
E = 1000.0
nu = 0.3
[materials.hard]
E = 1.0e6
nu = 0.3
[[part]]
name = "base"
material = "hard"
thickness = {t}
rectangle = {{ x = [-0.5, 1.5], y = [-0.1, 0.0], cells = [5, 1], elements = "q4" }}
[[part]]
name = "block"
material = "soft"
thickness = {t}
rectangle = {{ x = [0.0, 1.0], y = [-0.01, 9.99], cells = [4, 8], elements = "q4" }}
[[interface]]
name = "fit"
host = "base"
nodes = "block"
boundary = "bottom"
law = "frictionless"
search_distance = 0.05
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
[[support]]
part = "block"
boundary = "top"
fix = ["y"]
[[support]]
part = "block"
at = [0.0, 9.99]
fix = ["x"]
[analysis]
increments = 1
"""


@pytest.mark.parametrize("t", [2.5, 10.0])
def test_pressure_is_a_stress_for_any_thickness(t):
    """`interfaces[name].pressure` is p = E δ / L (the block's σyy) for t = 2.5
    and 10, while the forces are p × tributary × t; the summary's
    `max_pressure` agrees."""
    result = cfe.Model.from_toml(TEXT.format(t=t)).solve()
    assert result.summary["status"] == "completed"
    fit = result.interfaces["fit"]
    p = 1000.0 * 0.01 / 10.0
    assert fit.pressure == pytest.approx(np.full(5, p), rel=1e-3)
    assert fit.force_n == pytest.approx(p * fit.tributary * t, rel=1e-3)
    assert np.all(fit.shear == 0.0)
    assert result.summary["interfaces"][0]["max_pressure"] == pytest.approx(p, rel=1e-3)
    block = result.parts["block"]
    bottom = block.boundary_nodes("bottom")
    assert block.sigma_yy[bottom] == pytest.approx(np.full(5, -p), rel=1e-2)
