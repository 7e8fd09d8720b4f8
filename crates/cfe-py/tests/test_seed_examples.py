"""The seed's examples solved from Python: the numbers the command line prints
and writes, the physics they must show (equilibrium, contact conditions, the
state patterns of SPEC §4)."""

import csv
import json
import subprocess

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def plate():
    return cfe.Model.from_file(EXAMPLES / "plate_on_base.toml").solve()


@pytest.fixture(scope="module")
def bar():
    return cfe.Model.from_file(EXAMPLES / "bar_in_bearing.toml").solve()


def test_plate_on_base_known_values(plate):
    """max |u| = 1.279561e-2 at (100, 135) in the plate, as `cfe run` prints; the
    arrays give the same maximum at the same node."""
    md = plate.max_displacement
    assert md["value"] == pytest.approx(1.279561e-2, rel=1e-6)
    assert (md["x"], md["y"], md["part"]) == (100.0, 135.0, "plate")
    p = plate.parts["plate"]
    mag = np.hypot(p.ux, p.uy)
    k = int(np.argmax(mag))
    assert k == md["node"]
    assert mag[k] == md["value"]
    np.testing.assert_array_equal(p.points[k], [100.0, 135.0])
    assert plate.status == "completed"
    assert plate.load_factor == 1.0


def test_plate_on_base_physics(plate):
    """The base's reaction balances the 1500 N load; bonded pairs carry
    compression and do not penetrate (beyond the penalty's compliance), open
    pairs carry nothing and are separated; bonded under the load, open at both
    ends of the plate."""
    fx, fy = plate.reactions["base/bottom"]
    assert fy == pytest.approx(1500.0, rel=1e-9)
    assert abs(fx) < 1e-6
    i = plate.interfaces["plate-base"]
    assert len(i) == 29
    assert i.force_n.sum() == pytest.approx(1500.0, rel=1e-9)
    b = i.bonded
    assert np.all(i.force_n[b] >= 0.0)
    assert np.all(i.gap_n[b] <= 1e-12) and np.all(-i.gap_n[b] < 1500.0 / 1e9)
    assert np.all(i.force_n[~b] == 0.0) and np.all(i.gap_n[~b] > 0.0)
    order = np.argsort(i.x)
    states = b[order]
    assert not states[0] and not states[-1]
    centre = np.abs(i.x[order] - 100.0) <= 14.0
    assert states[centre].all()
    np.testing.assert_allclose(i.normal, np.tile([0.0, 1.0], (len(i), 1)), atol=1e-12)
    assert i.state[b].tolist() == ["bonded"] * int(b.sum())


def test_bar_in_bearing_reactions_balance_the_load(bar):
    """The three supports' reactions balance the 100 N upward load; the bar
    presses up on the upper block near its right corner and down on the lower
    block near its left corner."""
    total = sum(bar.reactions.values())
    np.testing.assert_allclose(total, [0.0, -100.0], atol=1e-7)
    up, low = bar.interfaces["bar-upper"], bar.interfaces["bar-lower"]
    assert up.force_n.sum() + low.force_n.sum() > 100.0  # the bearing levers the bar
    assert up.bonded[np.argmax(up.x)] and not up.bonded[np.argmin(up.x)]
    assert low.bonded[np.argmin(low.x)] and not low.bonded[np.argmax(low.x)]
    for i in (up, low):
        assert np.all(i.force_n[i.bonded] >= 0.0)
        assert np.all(i.force_n[~i.bonded] == 0.0)


def _pairs_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("example", ["plate_on_base", "bar_in_bearing"])
def test_same_numbers_as_the_cli(example, cli, tmp_path):
    """`cfe run` and `Model.solve` give the same pairs table and the same
    summary figures, to round-off; `Results.write` writes the same files as the
    command line. Round-off here is 1e-8: the solver picks a low-rank update or a
    refactorization by measured time, so two runs may take different (equally
    accurate) paths, and an update is accepted when it balances the load to 1e-8."""
    problem = EXAMPLES / f"{example}.toml"
    out = tmp_path / "cli"
    subprocess.run([str(cli), "run", str(problem), "--out", str(out)], check=True, capture_output=True)
    r = cfe.Model.from_file(problem).solve()

    rows = _pairs_csv(out / "pairs.csv")
    assert len(rows) == sum(len(i) for i in r.interfaces.values())
    k = 0
    for name, i in r.interfaces.items():
        for j in range(len(i)):
            row = rows[k]
            k += 1
            assert row["interface"] == name
            assert int(row["node"]) == i.node[j]
            assert int(row["host_element"]) == i.host_element[j]
            assert row["state"] == i.state[j]
            for col in ("gap_n", "slip_s", "force_n", "force_s"):
                scale = np.abs(getattr(i, col)).max()
                assert float(row[col]) == pytest.approx(getattr(i, col)[j], rel=1e-8, abs=1e-8 * scale)

    summary = json.loads((out / "summary.json").read_text())
    for key in ("status", "unknowns", "matrix_nonzeros", "factor_nonzeros", "iterations", "converged_increments"):
        assert summary[key] == r.summary[key], key
    assert summary["max_displacement"]["value"] == pytest.approx(r.summary["max_displacement"]["value"], rel=1e-9)
    for a, b in zip(summary["reactions"], r.summary["reactions"]):
        assert a["support"] == b["support"]
        assert a["fy"] == pytest.approx(b["fy"], rel=1e-10, abs=1e-8)

    written = tmp_path / "py"
    s = r.write(written)
    assert s["status"] == "completed"
    files = lambda d: sorted(p.relative_to(d).as_posix() for p in d.rglob("*") if p.is_file())
    assert files(written) == files(out)
    # The same table: the same columns and states exactly, the numbers to round-off.
    again = _pairs_csv(written / "pairs.csv")
    assert len(again) == len(rows)
    numeric = ("gap_n", "slip_s", "force_n", "force_s", "violation_amount")
    for a, b in zip(again, rows):
        assert a.keys() == b.keys()
        for key in a:
            if key in numeric:
                assert float(a[key]) == pytest.approx(float(b[key]), rel=1e-8, abs=1e-12)
            else:
                assert a[key] == b[key], key
