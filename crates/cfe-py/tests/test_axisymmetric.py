"""Axisymmetric models from Python: the model dict's `plane = "axisymmetric"`
(x = r, y = z), the hoop stress σθθ as arrays, against Lamé."""

import numpy as np
import pytest

import cfe

E, NU, A, B, P = 210000.0, 0.3, 10.0, 20.0, 100.0


def lame(r):
    """Lamé's thick cylinder A ≤ r ≤ B under internal pressure P, εzz = 0:
    (u, σrr, σθθ)."""
    aa = P * A * A / (B * B - A * A)
    bb = aa * B * B
    u = (1 + NU) / E * ((1 - 2 * NU) * aa * r + bb / r)
    return u, aa - bb / r**2, aa + bb / r**2


def cylinder():
    """The cylinder as a model dict: 16 × 8 Q4, pressure on the bore, top and
    bottom held in z."""
    return {
        "plane": "axisymmetric",
        "materials": {"steel": {"E": E, "nu": NU}},
        "part": [
            {
                "name": "tube",
                "material": "steel",
                "rectangle": {"x": [A, B], "y": [0.0, 2.0], "cells": [16, 8], "elements": "q4"},
            }
        ],
        "support": [
            {"part": "tube", "boundary": "bottom", "fix": ["y"]},
            {"part": "tube", "boundary": "top", "fix": ["y"]},
        ],
        "load": [{"part": "tube", "boundary": "left", "pressure": P}],
        "analysis": {"increments": 1},
    }


def test_thick_cylinder_from_a_dict_matches_lame():
    """The radial displacement within 1e-3 of u(a) and the element σrr, σθθ
    within 1 % of P of Lamé's (as tests/axisymmetric.rs measures at this mesh:
    6.5e-4 and 1.8e-3); von Mises includes σθθ."""
    result = cfe.Model.from_dict(cylinder()).solve()
    assert result.summary["status"] == "completed"
    tube = result.parts["tube"]
    r = tube.points[:, 0]
    u, _, _ = lame(r)
    assert np.max(np.abs(tube.displacement[:, 0] - u)) < 1e-3 * lame(A)[0]
    assert tube.sigma_theta is not None and tube.element_sigma_theta is not None
    centroids = np.array(
        [tube.points[q, 0].mean() for q in tube.quads]
    )
    order = tube.quad_ids
    _, srr, stt = lame(centroids)
    assert np.max(np.abs(tube.element_stress[order, 0] - srr)) < 1e-2 * P
    assert np.max(np.abs(tube.element_sigma_theta[order] - stt)) < 1e-2 * P
    s = tube.element_stress[order]
    h = tube.element_sigma_theta[order]
    vm = np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - h) ** 2 + (h - s[:, 0]) ** 2) + 3 * s[:, 2] ** 2)
    assert tube.element_von_mises[order] == pytest.approx(vm, rel=1e-12)


def test_plane_models_have_no_hoop_stress():
    """A plane model's parts carry no σθθ arrays (the same part in plane
    strain, held in x at one node as a plane part needs)."""
    model = cylinder()
    model["plane"] = "strain"
    model["support"].append({"part": "tube", "at": [A, 0.0], "fix": ["x"]})
    result = cfe.Model.from_dict(model).solve()
    assert result.parts["tube"].sigma_theta is None


def test_negative_radius_is_a_mesh_error_naming_part_and_node():
    """A node at r < 0 is refused with the part, node and radius as attributes."""
    model = cylinder()
    model["part"][0]["rectangle"]["x"] = [-1.0, B]
    with pytest.raises(cfe.MeshError) as e:
        cfe.Model.from_dict(model)
    assert (e.value.part, e.value.node, e.value.r) == ("tube", 0, -1.0)
