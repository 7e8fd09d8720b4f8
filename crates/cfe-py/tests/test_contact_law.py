"""The contact law reported per pair from Python as from the command line: a mesh on
which the strict stick law has no consistent state (the bar in its bearing meshed
with falling diagonals) finishes with its settled pair flagged, and a violation
limit below it raises LawViolationError naming the pair."""

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES


def falling_bearing_text(extra=""):
    text = (EXAMPLES / "bar_in_bearing.toml").read_text()
    text = text.replace("cells = [120, 8] }", 'cells = [120, 8], diagonal = "falling" }')
    text = text.replace("cells = [15, 9] }", 'cells = [15, 9], diagonal = "falling" }')
    return text.replace("[analysis]", "[analysis]\n" + extra, 1)


def test_settled_pair_is_flagged():
    result = cfe.Model.from_toml(falling_bearing_text()).solve()
    assert result.summary["status"] == "completed_with_violations"
    lower = result.interfaces["bar-lower"]
    flagged = np.flatnonzero(lower.violation)
    assert len(flagged) == 1
    k = flagged[0]
    # A bonded pair pulling: violation kind 1, settled, and its force is the amount.
    assert lower.violation[k] == 1 and lower.settled[k] and lower.bonded[k]
    assert lower.force_n[k] < 0
    assert lower.violation_amount[k] == pytest.approx(-lower.force_n[k], rel=1e-9)
    # Every other pair of both interfaces satisfies the law.
    upper = result.interfaces["bar-upper"]
    assert not upper.violation.any() and not upper.settled.any()
    for i in (upper, lower):
        ok = i.violation == 0
        assert np.all(i.force_n[ok & i.bonded] >= -1e-6 * 100.0)
        assert np.all(i.force_n[ok & ~i.bonded] == 0.0)
    record = result.summary["violations"][-1]
    assert record["kind"] == "tension" and record["node"] == lower.node[k]


def test_violation_limit_raises():
    text = falling_bearing_text("max_violation = 0.01")
    with pytest.raises(cfe.LawViolationError) as e:
        cfe.Model.from_toml(text).solve()
    assert e.value.increment == 1
    assert e.value.pairs == [("bar-lower", 150)]
    assert "bonded in tension" in str(e.value)
    assert isinstance(e.value, cfe.CfeError)
