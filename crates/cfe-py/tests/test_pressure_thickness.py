"""The pairs' pressure and shear from Python are stresses: force / (tributary
length × the node part's thickness), for a thickness other than 1."""

import numpy as np
import pytest

import cfe
from problems import interference_fit

# The block pressed by an interference δ = 0.01 onto a stiff, rigidly supported
# layer, its top held, both t thick: uniaxial strain ε = δ / L, so σyy = −E δ / L
# whatever t, carried by forces t times larger.


@pytest.mark.parametrize("t", [2.5, 10.0])
def test_pressure_is_a_stress_for_any_thickness(t):
    """`interfaces[name].pressure` is p = E δ / L (the block's σyy) for t = 2.5
    and 10, while the forces are p × tributary × t; the summary's
    `max_pressure` agrees."""
    result = cfe.Model.from_toml(interference_fit(thickness=t)).solve()
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
