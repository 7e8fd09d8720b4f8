"""The contact laws from Python (issue 12): an interference between a block and a
stiff, rigidly supported layer found within a search distance gives the closed-form
pressure p = E δ / L on every pair, with the initial gap, the pressure, the shear,
the slip and the states in the result's arrays and the summary."""

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES
from problems import interference_fit

TEXT = interference_fit()


def test_interference_pressure_and_arrays():
    result = cfe.Model.from_toml(TEXT).solve()
    assert result.summary["status"] == "completed"
    assert result.summary["proportional_shortcut"] is False
    fit = result.interfaces["fit"]
    p = 1000.0 * 0.01 / 10.0
    assert fit.gap0 == pytest.approx(np.full(5, -0.01), abs=1e-12)
    assert fit.pressure == pytest.approx(np.full(5, p), rel=1e-3)
    assert np.all(fit.shear == 0.0)
    assert list(fit.state) == ["bonded"] * 5
    assert np.all(fit.gap == fit.gap0 + fit.gap_n)
    assert fit.tributary == pytest.approx([0.125, 0.25, 0.25, 0.25, 0.125])
    assert fit.slip.shape == (5,)
    summary = result.summary["interfaces"][0]
    assert summary["max_pressure"] == pytest.approx(p, rel=1e-3)
    assert summary["unpaired"] == 0 and summary["contact_length"] == pytest.approx(1.0)


def test_law_override_with_friction():
    """`solve(law="coulomb", friction=μ)` makes every interface follow the Coulomb
    law, as `cfe run --law coulomb --friction μ`: the friction law holds on every
    closed pair (|f_s| ≤ μ f_n), some pairs slip, and the load is carried; a
    coulomb override without friction, or friction with another law, is refused."""
    model = cfe.Model.from_file(EXAMPLES / "plate_on_base.toml")
    r = model.solve(law="coulomb", friction=0.2)
    assert r.summary["status"] == "completed"
    pairs = r.interfaces["plate-base"]
    closed = pairs.force_n > 0
    limit = 0.2 * pairs.force_n[closed] * (1 + 1e-6) + 1e-6
    assert np.all(np.abs(pairs.force_s[closed]) <= limit)
    assert "slip" in list(pairs.state)
    assert abs(pairs.force_n.sum() - 1500.0) < 1e-6 * 1500.0
    with pytest.raises(cfe.ModelError, match="friction"):
        model.solve(law="coulomb")
    with pytest.raises(cfe.ModelError, match="friction"):
        model.solve(law="contact", friction=0.2)
