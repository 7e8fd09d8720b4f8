"""Histories from Python (issue 40): `result.history` holds every converged
increment as the columns of history.csv (NumPy arrays), equal to the file a run
writes; a tied block loaded, unloaded (`scale = 0.0`) and reversed has the
probe's displacement proportional to the load factor of each increment, back to
exactly 0 when unloaded, and the reaction balancing the applied load."""

import csv

import numpy as np

import cfe
from problems import block_on_base

TAIL = """[[load]]
name = "down"
part = "block"
boundary = "top"
force = [0.0, -2.0]
[[probe]]
name = "tip"
part = "block"
at = [1.0, 1.0]
[[step]]
name = "load"
increments = 2
[[step]]
name = "unload"
increments = 2
scale = 0.0
[[step]]
name = "reverse"
increments = 1
scale = -1.0
"""


def test_history_columns_follow_the_load_path(tmp_path):
    """Column names and per-increment values; the file has the same numbers."""
    model = cfe.Model.from_toml(block_on_base('law = "rigid"', TAIL))
    r = model.solve(out=tmp_path)
    h = r.history
    assert list(h)[:5] == ["increment", "step", "step_index", "load_factor", "time"]
    assert list(h["increment"]) == [1, 2, 3, 4, 5]
    assert h["step"] == ["load", "load", "unload", "unload", "reverse"]
    amplitude = np.array([0.5, 1.0, 0.5, 0.0, -1.0])
    fy = h["reaction:base/bottom.fy"]
    assert isinstance(fy, np.ndarray)
    np.testing.assert_allclose(fy, 2.0 * amplitude, atol=1e-9)
    uy = h["probe:tip.uy"]
    assert uy[1] < 0
    np.testing.assert_allclose(uy, amplitude * uy[1], rtol=0, atol=1e-12 * abs(uy[1]))
    assert uy[3] == 0.0
    np.testing.assert_allclose(h["interface:base/block.force_n"], 2.0 * amplitude, atol=1e-6)
    with open(tmp_path / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 5
    np.testing.assert_array_equal([float(x["probe:tip.uy"]) for x in rows], uy)
    assert (tmp_path / "history.png").is_file()
    assert len(r.summary["history"]) == 5


def test_progress_receives_each_increments_history_row(tmp_path):
    """The progress callback gets every increment's history row as it converges,
    in memory and with ``out``: the same columns, in order, and the same values
    as ``result.history`` (and history.csv) at the end — the reaction following
    the load path (2 × amplitude) while the run goes on."""
    model = cfe.Model.from_toml(block_on_base('law = "rigid"', TAIL))
    amplitude = [0.5, 1.0, 0.5, 0.0, -1.0]
    for out in [None, tmp_path]:
        seen = []
        r = model.solve(lambda inc: seen.append(inc), out=out)
        h = r.history
        assert [inc.increment for inc in seen] == [1, 2, 3, 4, 5]
        for k, inc in enumerate(seen):
            row = inc.history
            assert list(row) == list(h), out
            for name, column in h.items():
                assert row[name] == column[k], (out, name, k)
            assert row["increment"] == inc.increment and row["step"] == inc.step
            assert row["load_factor"] == inc.load_factor and row["time"] == inc.time
            assert abs(row["reaction:base/bottom.fy"] - 2.0 * amplitude[k]) < 1e-9
    with open(tmp_path / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [float(x["probe:tip.uy"]) for x in rows] == [inc.history["probe:tip.uy"] for inc in seen]
