"""The solve from Python: progress per increment, a callback's exception stops
the solve, the GIL is released, arrays are views of the solver's buffers, and
a model can be solved again."""

import threading
import time

import numpy as np
import pytest

import cfe
from conftest import EXAMPLES, plate_on_base_dict


def test_progress_per_increment():
    seen = []
    r = cfe.Model(plate_on_base_dict()).solve(progress=seen.append)
    assert [s.increment for s in seen] == list(range(1, 11))
    assert all(isinstance(s, cfe.Increment) and s.increments == 10 for s in seen)
    np.testing.assert_allclose([s.load_factor for s in seen], np.arange(1, 11) / 10)
    assert [s.iterations for s in seen] == r.summary["iterations"]


def test_callback_exception_stops_the_solve():
    seen = []

    def stop(info):
        seen.append(info)
        if info.increment == 3:
            raise KeyError("enough")

    with pytest.raises(KeyError, match="enough"):
        cfe.Model(plate_on_base_dict()).solve(progress=stop)
    assert len(seen) == 3


def test_gil_released_during_the_solve():
    """Another Python thread runs while the solver works: between the call and
    the first increment's callback (pair search, factorization, first solve) a
    counting thread keeps counting, which it could not if the solve held the GIL."""
    model = cfe.Model.from_file(EXAMPLES / "plate_on_base.toml", refine=8)
    done = threading.Event()
    ticks = [0]
    during = []

    def count():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.0002)

    t = threading.Thread(target=count)
    t.start()
    try:
        time.sleep(0.01)
        before = ticks[0]
        started = time.perf_counter()
        model.solve(progress=lambda info: during.append((ticks[0], time.perf_counter())))
    finally:
        done.set()
        t.join()
    first, at = during[0]
    # At least one tick per 5 ms of the first increment (a tick takes ~0.3 ms).
    assert first - before >= max(3, int((at - started) / 0.005)), (first - before, at - started)


def test_arrays_are_views_of_the_solver_buffers():
    r = cfe.Model(plate_on_base_dict()).solve()
    for p in r.parts.values():
        assert np.shares_memory(p.displacement, r.displacements)
        assert np.shares_memory(p.sigma_yy, p.stress)
        assert p.displacement.shape == (len(p.points), 2)
        assert p.stress.shape == (len(p.points), 3)
        assert p.element_stress.shape == (len(p.triangles) + len(p.quads), 3)
        assert p.displacement.dtype == np.float64
    assert r.displacements.size == 2 * sum(len(p.points) for p in r.parts.values())


def test_summary_and_second_solve():
    model = cfe.Model(plate_on_base_dict())
    a, b = model.solve(), model.solve()
    np.testing.assert_array_equal(a.displacements, b.displacements)
    s = a.summary
    assert s["status"] == "completed" and s["unknowns"] == 910
    assert [p["name"] for p in s["parts"]] == ["base", "plate"]
    assert s["interfaces"][0]["pairs"] == 29
    assert s["interfaces"][0]["bonded"] == int(a.interfaces["plate-base"].bonded.sum())


def test_check_describes_the_model():
    text = cfe.Model(plate_on_base_dict()).check()
    assert "910" in text and "29 pairs" in text


def test_solve_with_out_writes_the_cli_files(tmp_path):
    r = cfe.Model(plate_on_base_dict()).solve(out=tmp_path)
    for f in ("results.pvd", "pairs.csv", "summary.json", "sigma_yy.png", "displacement.png", "vtu/parts_0010.vtu"):
        assert (tmp_path / f).is_file(), f
    assert r.max_displacement["value"] == pytest.approx(1.279561e-2, rel=1e-6)


def test_solve_write_every_writes_only_those_increments(tmp_path):
    """write_every = 4 writes the VTU files of increments 4, 8 and the last (10),
    "last" only the last; the pairs table and summary stay complete; bad values
    are refused before solving."""
    model = cfe.Model(plate_on_base_dict())
    for every, written in ((4, [4, 8, 10]), ("last", [10])):
        out = tmp_path / str(every)
        r = model.solve(out=out, write_every=every)
        parts = sorted(p.name for p in (out / "vtu").glob("parts_*.vtu"))
        assert parts == [f"parts_{i:04d}.vtu" for i in written]
        pvd = (out / "results.pvd").read_text()
        assert pvd.count("parts_") == len(written)
        assert r.summary["converged_increments"] == 10
    for bad in (0, -1, "first", 2.5, True):
        with pytest.raises(cfe.ModelError, match="write_every"):
            model.solve(out=tmp_path / "bad", write_every=bad)
