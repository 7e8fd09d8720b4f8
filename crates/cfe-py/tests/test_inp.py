"""CalculiX/Abaqus decks from Python (issue 40): Model.from_inp reads the
seed's plate on a base as a deck with the TOML model's results, and a deck
construct outside the subset raises ParseError naming the line and keyword."""

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES


def test_plate_on_base_deck_gives_the_toml_results():
    """Same displacements and pair states as examples/plate_on_base.toml."""
    deck = cfe.Model.from_inp(EXAMPLES / "plate_on_base.inp")
    toml = cfe.Model.from_file(EXAMPLES / "plate_on_base.toml")
    assert deck.parts == ["BASE", "PLATE"]
    assert any("*NODE PRINT" in n for n in deck.notes)
    a, b = deck.solve(), toml.solve()
    assert a.status == "completed" and b.status == "completed"
    for pa, pb in zip(["BASE", "PLATE"], ["base", "plate"]):
        ua, ub = a.parts[pa].displacement, b.parts[pb].displacement
        assert np.max(np.abs(ua - ub)) <= 1e-10 * np.max(np.abs(ub))
    (ia,), (ib,) = a.interfaces.values(), b.interfaces.values()
    assert list(ia.state) == list(ib.state)
    assert np.allclose(ia.force_n, ib.force_n, rtol=1e-9, atol=1e-9 * np.max(np.abs(ib.force_n)))


def test_unsupported_keyword_names_line_and_keyword(tmp_path):
    """*PLASTIC is refused at its line, as a ParseError with keyword and fault."""
    lines = (EXAMPLES / "plate_on_base.inp").read_text().splitlines()
    k = next(i for i, l in enumerate(lines) if l.startswith("210000.0, 0.31"))
    lines.insert(k + 1, "*PLASTIC")
    lines.insert(k + 2, "250., 0.")
    path = tmp_path / "plastic.inp"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(cfe.ParseError) as e:
        cfe.Model.from_inp(path)
    assert e.value.line == k + 2
    assert e.value.keyword == "*PLASTIC"
    assert e.value.fault == "unsupported"
    assert "linear elastic" in str(e.value) and str(path) in str(e.value)
