"""`solve(out=…)` from Python deletes and overwrites only what cfe wrote, as `cfe
run` does: a user's files survive a re-run, a folder holding files cfe did not
write at its names (or no cfe run) is refused untouched with an `OutputError`
naming them unless `force=True`, a `vtu` link is never followed, and a folder
another run holds is refused naming its process."""

import os

import pytest

import cfe
from conftest import plate_on_base_dict


def _tree(folder):
    """Every file under `folder` (relative, `/`-separated) with its bytes; links
    are not followed."""
    found = {}
    for root, dirs, files in os.walk(folder, followlinks=False):
        for name in files + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            path = os.path.join(root, name)
            rel = os.path.relpath(path, folder).replace(os.sep, "/")
            found[rel] = os.readlink(path) if os.path.islink(path) else open(path, "rb").read()
    return found


def test_rerun_keeps_the_users_files(tmp_path):
    """A re-run removes the earlier run's files only: the user's `notes.tmp`,
    `thesis.docx.tmp` and `vtu/parts_experiment.vtu` stay, a folder `build.tmp/`
    too, and the series of the earlier run beyond the new run's increments is gone."""
    model = cfe.Model(plate_on_base_dict())
    model.solve(out=tmp_path)
    assert (tmp_path / "vtu" / "parts_0010.vtu").is_file()
    assert (tmp_path / ".cfe-manifest").is_file() and not (tmp_path / ".cfe-lock").exists()
    user = {"notes.tmp": b"n", "thesis.docx.tmp": b"t", "vtu/parts_experiment.vtu": b"e", "build.tmp/x": b"x"}
    for rel, data in user.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_bytes(data)
    model.solve(out=tmp_path, write_every="last")
    after = _tree(tmp_path)
    for rel, data in user.items():
        assert after[rel] == data, rel
    series = sorted(r for r in after if r.startswith("vtu/pa") and r != "vtu/parts_experiment.vtu")
    assert series == ["vtu/pairs_0010.vtu", "vtu/parts_0010.vtu"]


def test_a_users_summary_is_refused_untouched_unless_forced(tmp_path):
    """A `summary.json` of the user's in a folder without a cfe run: refused, the
    error names it, nothing changes; `force=True` replaces it and only it."""
    (tmp_path / "summary.json").write_text("mine")
    (tmp_path / "notes.txt").write_text("notes")
    before = _tree(tmp_path)
    model = cfe.Model(plate_on_base_dict())
    with pytest.raises(cfe.OutputError, match="summary.json") as e:
        model.solve(out=tmp_path)
    assert [str(f) for f in e.value.files] == ["summary.json"]
    assert _tree(tmp_path) == before
    r = model.solve(out=tmp_path, force=True)
    assert r.status == "completed"
    assert '"status": "completed"' in (tmp_path / "summary.json").read_text()
    assert (tmp_path / "notes.txt").read_text() == "notes"
    # Results.write takes the same rules.
    (tmp_path / "vtu" / "pairs_0099.vtu").write_text("mine")
    with pytest.raises(cfe.OutputError, match="pairs_0099"):
        r.write(tmp_path)
    r.write(tmp_path, force=True)
    assert not (tmp_path / "vtu" / "pairs_0099.vtu").exists()


def test_a_folder_without_a_cfe_run_is_refused(tmp_path):
    """A non-empty folder without a cfe run (only `notes.txt`) is refused naming
    what it holds."""
    (tmp_path / "notes.txt").write_text("notes")
    with pytest.raises(cfe.OutputError, match="holds no cfe run") as e:
        cfe.Model(plate_on_base_dict()).solve(out=tmp_path)
    assert [str(f) for f in e.value.files] == ["notes.txt"]
    assert sorted(os.listdir(tmp_path)) == ["notes.txt"]


def test_a_vtu_link_is_never_followed(tmp_path):
    """`vtu` a symbolic link to another folder: refused even with force; the
    files there stay."""
    out, other = tmp_path / "out", tmp_path / "other"
    model = cfe.Model(plate_on_base_dict())
    model.solve(out=out)
    (out / "vtu").rename(other)
    (out / "vtu").symlink_to(other, target_is_directory=True)
    there = _tree(other)
    for force in (False, True):
        with pytest.raises(cfe.OutputError, match="symbolic link"):
            model.solve(out=out, force=force)
    assert _tree(other) == there


def test_a_folder_in_use_is_refused_naming_its_process(tmp_path):
    """While another run holds the folder's lock, a solve into it is refused with
    the `pid` the lock file names and nothing changes; once that run has ended
    the folder is free."""
    import fcntl

    model = cfe.Model(plate_on_base_dict())
    model.solve(out=tmp_path)
    # Hold the lock as a run does: flock on .cfe-lock with a process id inside.
    with open(tmp_path / ".cfe-lock", "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        f.write("4242\n")
        f.flush()
        before = _tree(tmp_path)
        with pytest.raises(cfe.OutputError, match="process 4242") as e:
            model.solve(out=tmp_path)
        assert e.value.pid == 4242
        assert _tree(tmp_path) == before
    # The lock file stays behind, unlocked, as after a killed run: no obstacle.
    assert model.solve(out=tmp_path).status == "completed"
    assert not (tmp_path / ".cfe-lock").exists()
