"""Ctrl-C stops `solve(out=…)`: SIGINT sets the run's stop flag, the run ends
`interrupted` with the converged increments on disk, and Python gets a
`KeyboardInterrupt` (run in a child process, which the test interrupts)."""

import json
import os
import signal
import subprocess
import sys
import textwrap

import pytest

from problems import block_on_base

# A Coulomb block pushed sideways far beyond friction in many increments (tens of
# seconds to the end); only the last increment's VTU files are written.
PROBLEM = block_on_base(
    'law = "coulomb"\nfriction = 0.3',
    '[[support]]\npart = "block"\nboundary = "top"\nfix = ["x"]\nvalue = [0.005, 0.0]\n'
    '[[load]]\npart = "block"\nboundary = "top"\nforce = [0.0, -1.0]\n'
    '[analysis]\nincrements = 20000\noutput_every = "last"',
    base_cells=(40, 24),
    block_cells=(32, 32),
)

# The child's start: it loads the problem file (its first argument) and prints
# "started" at its first increment; the caller's lines follow.
CHILD_START = textwrap.dedent(
    """
    import sys
    import cfe

    model = cfe.Model.from_file(sys.argv[1])
    started = False

    def progress(info):
        global started
        if not started:
            started = True
            print("started", flush=True)
    """
)

CHILD = CHILD_START + textwrap.dedent(
    """
    try:
        model.solve(out=sys.argv[2], progress=progress)
    except KeyboardInterrupt as e:
        print("interrupted", getattr(e, "increment", None), flush=True)
        sys.exit(3)
    print("completed", flush=True)
    """
)


def interrupt(code, *args):
    """Runs `code` with `args` in a child interpreter, sends it SIGINT once it
    prints "started", and returns its return code, stdout and stderr (it must end
    within 120 s, a liveness bound)."""
    child = subprocess.Popen(
        [sys.executable, "-c", code, *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline().strip() == "started", child.stderr.read()
        child.send_signal(signal.SIGINT)
        stdout, stderr = child.communicate(timeout=120)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    return child.returncode, stdout, stderr


@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to a child process")
def test_ctrl_c_stops_a_run_into_a_folder(tmp_path):
    """SIGINT during `solve(out=…)` ends the child with KeyboardInterrupt long
    before its last increment; `summary.json` says `interrupted` with the
    increments it converged, the same number the exception carries."""
    problem = tmp_path / "problem.toml"
    problem.write_text(PROBLEM)
    out = tmp_path / "out"
    returncode, stdout, stderr = interrupt(CHILD, problem, out)
    assert returncode == 3, (returncode, stdout, stderr)
    word, increment = stdout.split()
    assert word == "interrupted"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert summary["converged_increments"] == int(increment)
    assert 1 <= int(increment) < 20000
    assert not list(out.rglob("*.tmp"))


CHILD_IN_MEMORY = CHILD_START + textwrap.dedent(
    """
    try:
        model.solve(progress=progress)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(3)
    print("completed", flush=True)
    """
)


@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to a child process")
def test_ctrl_c_stops_a_solve_in_memory(tmp_path):
    """SIGINT during an in-memory `solve()` ends the child with KeyboardInterrupt
    long before its last increment: the signal-hook handler registered for the
    solve chains to Python's, whose KeyboardInterrupt is raised (a liveness
    bound, not a speed assertion; these increments are short, so this checks
    the chaining, not where inside an increment the solver stops)."""
    problem = tmp_path / "problem.toml"
    problem.write_text(PROBLEM)
    returncode, stdout, stderr = interrupt(CHILD_IN_MEMORY, problem)
    assert returncode == 3, (returncode, stdout, stderr)
    assert stdout.strip() == "interrupted"
