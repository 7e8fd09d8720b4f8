"""Line probes from Python (issue 40): `result.lines[name]` holds a `[[line]]`'s
samples as NumPy arrays, the same numbers as the `lines/<name>.csv` a run writes,
and a tied block on a base under a uniform pressure is uniformly stressed along
a vertical line through the block (σyy = −p, σxx = σxy = 0, closed form)."""

import csv

import numpy as np

import cfe
from problems import block_on_base

P = 2.0

TAIL = f"""[[load]]
part = "block"
boundary = "top"
force = [0.0, -{P}]
[[line]]
name = "up"
from = [0.5, 0.25]
to = [0.5, 1.0]
points = 4
part = "block"
"""


def test_result_lines_match_the_file_and_the_uniform_stress(tmp_path):
    """`result.lines["up"]`: 4 samples with s, x, part, u, stress, von_mises;
    a rigid tie under a uniform top pressure P on a unit block whose base is
    much wider: σyy = −P along the block's centre line to 2 %, and the CSV has
    the same numbers to its printed precision."""
    model = cfe.Model.from_toml(block_on_base('law = "rigid"', TAIL))
    r = model.solve(out=tmp_path)
    assert r.status == "completed"
    line = r.lines["up"]
    assert line["x"].shape == (4, 2) and line["u"].shape == (4, 2)
    assert line["stress"].shape == (4, 3)
    assert line["part"] == ["block"] * 4
    np.testing.assert_allclose(line["s"], [0.0, 0.25, 0.5, 0.75], atol=1e-12)
    np.testing.assert_allclose(line["x"][:, 0], 0.5, atol=1e-12)
    # Far from the tied face the block is nearly uniformly compressed.
    top = line["stress"][-1]
    assert abs(top[1] + P) < 0.02 * P, top
    assert abs(top[0]) < 0.05 * P and abs(top[2]) < 0.05 * P, top
    with open(tmp_path / "lines" / "up.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4
    for k, row in enumerate(rows):
        assert row["part"] == "block"
        np.testing.assert_allclose(float(row["s"]), line["s"][k], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(float(row["uy"]), line["u"][k, 1], rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(float(row["syy"]), line["stress"][k, 1], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(
            float(row["von_mises"]), line["von_mises"][k], rtol=1e-9, atol=1e-12
        )


def test_a_model_without_lines_has_none():
    """No `[[line]]`: `result.lines` is empty."""
    r = cfe.Model.from_toml(block_on_base('law = "rigid"', TAIL.split("[[line]]")[0])).solve()
    assert r.lines == {}
