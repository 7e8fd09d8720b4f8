"""Bad input raises cfe.CfeError subclasses carrying the library's messages:
the key and line of a file, the dict entry, the part, the array at fault."""

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES, plate_on_base_dict, rectangle


def test_bad_key_names_key_and_line(tmp_path):
    text = (EXAMPLES / "plate_on_base.toml").read_text()
    lines = text.splitlines()
    k = next(i for i, l in enumerate(lines) if l.startswith("nu = 0.31"))
    lines.insert(k + 1, "colour = 3")
    path = tmp_path / "bad.toml"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(cfe.ParseError) as e:
        cfe.Model.from_file(path)
    assert "colour" in str(e.value) and str(path) in str(e.value)
    assert e.value.line == k + 2
    assert isinstance(e.value, cfe.CfeError)


def test_unknown_part_names_part_and_line():
    text = (EXAMPLES / "plate_on_base.toml").read_text().replace('nodes = "plate"', 'nodes = "plat"')
    with pytest.raises(cfe.ParseError) as e:
        cfe.Model.from_toml(text)
    msg = str(e.value)
    assert "'plat'" in msg and "not defined" in msg and "base, plate" in msg
    line = next(i for i, l in enumerate(text.splitlines(), 1) if l.startswith('nodes = "plat"'))
    assert e.value.line == line and f"line {line}" in msg


def test_dict_errors_name_the_entry():
    d = plate_on_base_dict()
    d["part"][1]["colour"] = "red"
    with pytest.raises(cfe.ParseError) as e:
        cfe.Model(d)
    assert "colour" in str(e.value) and "part[1]" in str(e.value)
    assert e.value.entry.startswith("part[1]")
    d = plate_on_base_dict()
    d["interface"][0]["host"] = "bass"
    with pytest.raises(cfe.ParseError) as e:
        cfe.Model(d)
    assert "interface[0].host" in str(e.value) and "'bass'" in str(e.value)
    with pytest.raises(cfe.ParseError, match="cannot be written"):
        cfe.Model(plate_on_base_dict(title=object()))


def test_bad_material_and_settings():
    d = plate_on_base_dict()
    d["materials"]["steel"]["nu"] = 0.5
    with pytest.raises(cfe.ModelError) as e:
        cfe.Model(d)
    assert e.value.key == "materials.steel.nu" and "(-1, 0.5)" in str(e.value)
    assert str(e.value).startswith("problem dict: `materials.steel.nu`"), str(e.value)
    with pytest.raises(cfe.ModelError, match="increments"):
        cfe.Model(plate_on_base_dict(analysis={"increments": 0}))


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda m: m.update(points=np.zeros((5, 3, 1))), "points"),
        (lambda m: m.update(points=m["points"][:, :1]), r"shape \(n, 2\)"),
        (lambda m: m.update(triangles=m["triangles"][:, :2]), r"shape \(n, 3\)"),
        (lambda m: m.update(triangles=m["triangles"] + 1000), "uses node"),
        (lambda m: m.update(triangles=-m["triangles"]), "negative"),
        (lambda m: m.update(triangles=m["triangles"] + 0.5), "node indices"),
        (lambda m: m.update(triangles=None), "no elements"),
        (lambda m: m["boundaries"].update(bottom=np.array([[0, 22]])), "inside the part"),
        (lambda m: m["boundaries"].update(bottom=np.zeros((2, 3), dtype=int)), "edges"),
        (lambda m: m.update(points=np.zeros_like(m["points"])), "degenerate"),
    ],
)
def test_bad_arrays(change, message):
    arrays = rectangle([0.0, 200.0], [0.0, 120.0], (20, 12))
    change(arrays)
    d = plate_on_base_dict()
    d["part"][0] = {"name": "base", "material": "steel", **arrays}
    with pytest.raises(cfe.MeshError, match=message) as e:
        cfe.Model(d)
    assert "'base'" in str(e.value)


def test_mesh_and_arrays_both_given():
    d = plate_on_base_dict()
    arrays = rectangle([0.0, 200.0], [0.0, 120.0], (20, 12))
    d["part"][0] = {"name": "base", "material": "steel", "mesh": cfe.Mesh(**arrays), **arrays}
    with pytest.raises(cfe.ModelError, match="not both"):
        cfe.Model(d)
    d = plate_on_base_dict()
    d["part"][0].update(arrays)
    with pytest.raises(cfe.ParseError, match="given in memory"):
        cfe.Model(d)


def test_unsupported_part_is_a_singular_error():
    d = plate_on_base_dict(support=[{"part": "base", "boundary": "bottom", "fix": ["y"]}])
    with pytest.raises(cfe.SingularError) as e:
        cfe.Model(d).solve()
    assert "base" in str(e.value)


def test_part_pushed_beyond_friction_is_a_singular_error():
    """The seed's plate pushed sideways (Q = 400 N) beyond what friction holds
    (μP = 0.2 × 1500 N): no state of rest, refused at the first increment with
    the part and the inclined-plane numbers (P = 150 N, Q = 40 N, μP = 30 N at
    λ = 0.1); with μ = 0.3 it is held."""
    load = plate_on_base_dict()["load"]
    load[0]["force"] = [400.0, -1500.0]
    model = cfe.Model(plate_on_base_dict(load=load))
    with pytest.raises(cfe.SingularError) as e:
        model.solve(law="coulomb", friction=0.2)
    assert e.value.parts == ["plate"]
    message = str(e.value)
    assert "increment 1" in message and "harder than friction holds them" in message
    assert "1.5000e2" in message and "4.0000e1" in message and "3.0000e1" in message
    r = model.solve(law="coulomb", friction=0.3)
    assert r.summary["status"] == "completed"


def test_orphan_coupling_nodes_are_listed():
    d = plate_on_base_dict()
    d["part"][1]["rectangle"]["y"] = [125.0, 140.0]
    d["load"][0]["from"], d["load"][0]["to"] = [86.0, 140.0], [114.0, 140.0]
    with pytest.raises(cfe.CouplingError) as e:
        cfe.Model(d).solve()
    assert e.value.interface == "plate-base"
    assert len(e.value.nodes) == 29


def test_missing_file_and_bad_law(tmp_path):
    with pytest.raises(cfe.ParseError, match="cannot read problem file"):
        cfe.Model.from_file(tmp_path / "missing.toml")
    with pytest.raises(cfe.ModelError, match="law"):
        cfe.Model(plate_on_base_dict()).solve(law="glue")
