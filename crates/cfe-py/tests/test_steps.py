"""Load steps from Python (issue 12): a model file with `[[step]]` tables runs, the
progress callback and the results name each increment's step, and a tied (linear)
model loaded in two steps ends on the one-step solution of the summed loads."""

import numpy as np

import cfe
from conftest import EXAMPLES
from problems import block_on_base


def block(tail):
    """The unit block tied (law "rigid") on its base; `tail` the loads and steps."""
    return block_on_base('law = "rigid"', tail)


DOWN = '[[load]]\npart = "block"\nboundary = "top"\nforce = [0.0, -1.0]\n'
SIDE = '[[load]]\npart = "block"\nboundary = "top"\nforce = [0.3, 0.0]\n'
STEPS = '[[step]]\nname = "press"\nincrements = 1\n[[step]]\nname = "shear"\nincrements = 2\n'


def test_two_steps_name_their_increments_and_superpose():
    """Each increment reports its step, the step's load factor and the monotonic
    time; after step 2 the displacements equal one step of both loads."""
    text = block(STEPS + DOWN + SIDE + 'step = "shear"\n')
    model = cfe.Model.from_toml(text)
    assert model.steps == [
        {"name": "press", "increments": 1},
        {"name": "shear", "increments": 2},
    ]
    assert model.settings["increments"] == 3
    seen = []
    res = model.solve(progress=seen.append)
    assert [(i.increment, i.step, i.load_factor, i.time) for i in seen] == [
        (1, "press", 1.0, 1.0),
        (2, "shear", 0.5, 1.5),
        (3, "shear", 1.0, 2.0),
    ]
    assert (res.step, res.load_factor, res.time) == ("shear", 1.0, 2.0)
    steps = res.summary["increment_steps"]
    assert [s["step"] for s in steps] == ["press", "shear", "shear"]
    assert res.summary["proportional_shortcut"] is False
    assert "2 steps" in res.summary["proportional_shortcut_off"]
    one = cfe.Model.from_toml(block("[analysis]\nincrements = 1\n" + DOWN + SIDE)).solve()
    scale = np.abs(one.displacements).max()
    assert np.abs(res.displacements - one.displacements).max() < 1e-10 * scale


def test_cattaneo_example_runs_in_two_steps():
    """The Cattaneo–Mindlin example (normal load, then a tangential load below
    μP′) completes with some pairs sticking and some slipping at the end."""
    model = cfe.Model.from_file(EXAMPLES / "hertz" / "cattaneo.toml")
    assert [s["name"] for s in model.steps] == ["normal", "shear"]
    res = model.solve()
    assert res.status == "completed"
    assert res.step == "shear"
    states = res.summary["interfaces"][0]
    assert states["slip"] > 0 and states["bonded"] > 0
