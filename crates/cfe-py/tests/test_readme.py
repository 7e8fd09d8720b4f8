"""The README's Python example runs and gives the seed's plate-on-base numbers
(Matplotlib replaced by a recorder: it is optional for the tests)."""

import re
import sys
import types

import numpy as np
import pytest

from conftest import REPO


def test_readme_example(monkeypatch, capsys):
    text = (REPO / "README.md").read_text()
    section = text[text.index("## Python") :]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len(code.strip().splitlines()) <= 25
    plots = []
    pyplot = types.ModuleType("matplotlib.pyplot")
    pyplot.plot = lambda *a, **k: plots.append(a)
    pyplot.xlabel = pyplot.ylabel = pyplot.show = lambda *a, **k: None
    matplotlib = types.ModuleType("matplotlib")
    matplotlib.pyplot = pyplot
    monkeypatch.setitem(sys.modules, "matplotlib", matplotlib)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", pyplot)
    ns = {}
    exec(compile(code, "README.md", "exec"), ns)
    result = ns["result"]
    assert result.max_displacement["value"] == pytest.approx(1.279561e-2, rel=1e-6)
    assert "Increment(increment=10" in capsys.readouterr().out
    x, uy, _ = plots[0]
    np.testing.assert_allclose(x, np.linspace(30, 170, 29))
    # The plate dips most under the load and its ends lift off the base.
    assert np.argmin(uy) == 14 and uy[0] > uy[14] and uy[-1] > uy[14]
    assert not result.interfaces["base/plate"].bonded[[0, -1]].any()


def test_readme_solid_example(monkeypatch):
    """The README's 3D Python example runs from the repository root: the 3D plate on
    a base is solid, its pairs carry the 60 kN load to the base's support."""
    text = (REPO / "README.md").read_text()
    section = text[text.index("## Python") :]
    code = re.findall(r"```python\n(.*?)```", section, re.S)[1]
    assert len(code.strip().splitlines()) <= 12
    monkeypatch.chdir(REPO)
    ns = {}
    exec(compile(code, "README.md", "exec"), ns)
    assert ns["model"].dimension == 3
    result = ns["result"]
    assert result.status == "completed"
    pairs = ns["pairs"]
    assert pairs.force.sum(axis=0)[2] == pytest.approx(60000.0, rel=1e-6)
    assert result.reactions["base/bottom"][2] == pytest.approx(60000.0, rel=1e-6)
    assert [c.type for c in ns["mesh"].cells] == ["tetra"]
