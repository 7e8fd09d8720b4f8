"""Shared helpers of the cfe Python tests: the repository's paths, the `cfe`
binary (for comparisons with the command line) and structured meshes built with
NumPy exactly as the library's rectangle mesher builds them."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
EXAMPLES = REPO / "examples"


def cfe_binary():
    """The `cfe` command-line program built by cargo, or None."""
    env = os.environ.get("CFE_BIN")
    if env:
        return Path(env)
    for profile in ("release", "debug"):
        p = REPO / "target" / profile / "cfe"
        if p.exists():
            return p
    found = shutil.which("cfe")
    return Path(found) if found else None


@pytest.fixture
def cli():
    """The `cfe` binary; the test is skipped when it has not been built."""
    exe = cfe_binary()
    if exe is None:
        pytest.skip("the cfe binary is not built (cargo build --release)")
    return exe


def lerp(a, b, n):
    """The mesher's node coordinates along one axis: a + (b − a) i / n, b at i = n."""
    v = a + (b - a) * np.arange(n + 1, dtype=np.float64) / n
    v[-1] = b
    return v


def rectangle(x, y, cells, quads=False):
    """The rectangle mesher's mesh as arrays: points (node (i, j) at j (nx + 1) + i),
    triangles (two per cell, split along the rising diagonal) or quads, and the
    boundaries bottom/right/top/left as edges, counter-clockwise."""
    nx, ny = cells
    xs, ys = lerp(x[0], x[1], nx), lerp(y[0], y[1], ny)
    points = np.array([[xi, yj] for yj in ys for xi in xs])

    def node(i, j):
        return j * (nx + 1) + i

    elements = []
    for j in range(ny):
        for i in range(nx):
            n00, n10, n11, n01 = node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)
            if quads:
                elements.append([n00, n10, n11, n01])
            else:
                elements.append([n00, n10, n11])
                elements.append([n00, n11, n01])
    boundaries = {
        "bottom": np.array([[node(i, 0), node(i + 1, 0)] for i in range(nx)]),
        "right": np.array([[node(nx, j), node(nx, j + 1)] for j in range(ny)]),
        "top": np.array([[node(i + 1, ny), node(i, ny)] for i in reversed(range(nx))]),
        "left": np.array([[node(0, j + 1), node(0, j)] for j in reversed(range(ny))]),
    }
    key = "quads" if quads else "triangles"
    return {"points": points, key: np.array(elements), "boundaries": boundaries}


def plate_on_base_dict(**overrides):
    """The seed's plate on a base (examples/plate_on_base.toml) as a dict."""
    d = {
        "title": "Plate on a base",
        "plane": "stress",
        "materials": {"steel": {"E": 210000.0, "nu": 0.31}},
        "part": [
            {
                "name": "base",
                "material": "steel",
                "rectangle": {"x": [0.0, 200.0], "y": [0.0, 120.0], "cells": [20, 12]},
            },
            {
                "name": "plate",
                "material": "steel",
                "rectangle": {"x": [30.0, 170.0], "y": [120.0, 135.0], "cells": [28, 6]},
            },
        ],
        "interface": [
            {
                "name": "plate-base",
                "host": "base",
                "nodes": "plate",
                "boundary": "bottom",
                "law": "contact",
                "c_n": 1e9,
                "c_s": 1e9,
            }
        ],
        "support": [{"part": "base", "boundary": "bottom", "fix": ["x", "y"]}],
        "load": [
            {
                "part": "plate",
                "boundary": "top",
                "from": [86.0, 135.0],
                "to": [114.0, 135.0],
                "force": [0.0, -1500.0],
            }
        ],
        "analysis": {"increments": 10, "scheme": "active-set"},
    }
    d.update(overrides)
    return d


def assert_same_results(a, b, rtol=1e-9):
    """Two results of the same model agree: displacements and stresses of every
    part, and every pair's state, gap and forces (to round-off)."""
    assert list(a.parts) == list(b.parts)
    for name, pa in a.parts.items():
        pb = b.parts[name]
        scale = np.abs(pa.displacement).max()
        np.testing.assert_allclose(pa.points, pb.points, rtol=0, atol=1e-12)
        np.testing.assert_allclose(pa.displacement, pb.displacement, rtol=0, atol=rtol * scale)
        s = np.abs(pa.stress).max()
        np.testing.assert_allclose(pa.stress, pb.stress, rtol=0, atol=rtol * s)
        np.testing.assert_allclose(pa.element_stress, pb.element_stress, rtol=0, atol=rtol * s)
    assert list(a.interfaces) == list(b.interfaces)
    for name, ia in a.interfaces.items():
        ib = b.interfaces[name]
        np.testing.assert_array_equal(ia.bonded, ib.bonded)
        np.testing.assert_array_equal(ia.node, ib.node)
        f = np.abs(ia.force_n).max()
        np.testing.assert_allclose(ia.force_n, ib.force_n, rtol=0, atol=rtol * f)
        g = np.abs(ia.gap_n).max()
        np.testing.assert_allclose(ia.gap_n, ib.gap_n, rtol=0, atol=rtol * g)
