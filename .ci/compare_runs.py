#!/usr/bin/env python3
"""Compares two output folders of `cfe run` on the same model (e.g. the direct
solver against `mpirun -n 2 cfe run ... --solver petsc`): both completed, every
pair of pairs.csv in the same state, pair forces (normal, tangential) and pair
gaps/slips, the largest displacement and the reactions within TOLERANCE of the
first run's largest value of each. Python standard library only.

usage: compare_runs.py REFERENCE OTHER TOLERANCE
Exits 1 (and says what differs) when they do not agree.
"""

import csv
import json
import sys
from pathlib import Path


def pairs(folder):
    with open(Path(folder) / "pairs.csv", newline="") as f:
        return {(r["interface"], r["node"], r["increment"]): r for r in csv.DictReader(f)}


def summary(folder):
    with open(Path(folder) / "summary.json") as f:
        return json.load(f)


def relative(a, b):
    """The largest |a_i - b_i| over the largest |a_i| (0 when both are all 0)."""
    scale = max((abs(x) for x in a), default=0.0)
    diff = max((abs(x - y) for x, y in zip(a, b)), default=0.0)
    return diff / scale if scale > 0 else diff


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    ref, other, tol = sys.argv[1], sys.argv[2], float(sys.argv[3])
    problems = []
    s_ref, s_other = summary(ref), summary(other)
    for name, s in (("reference", s_ref), ("other", s_other)):
        if s["status"] != "completed":
            problems.append(f"{name} run is {s['status']}")
    p_ref, p_other = pairs(ref), pairs(other)
    if p_ref.keys() != p_other.keys():
        problems.append("pairs.csv lists other pairs or increments")
    keys = sorted(p_ref.keys() & p_other.keys())
    states = [k for k in keys if p_ref[k]["state"] != p_other[k]["state"]]
    if states:
        problems.append(f"{len(states)} pair states differ, first {states[0]}")
    for columns in (("force_n", "force_s"), ("gap_n", "slip_s")):
        a = [float(p_ref[k][c]) for k in keys for c in columns]
        b = [float(p_other[k][c]) for k in keys for c in columns]
        d = relative(a, b)
        print(f"{'/'.join(columns)}: largest difference {d:.2e} of the largest value")
        if d > tol:
            problems.append(f"{'/'.join(columns)} differ by {d:.2e} > {tol:.0e}")
    u = [s_ref["max_displacement"]["value"]], [s_other["max_displacement"]["value"]]
    d = relative(*u)
    print(f"largest displacement: difference {d:.2e}")
    if d > tol:
        problems.append(f"the largest displacement differs by {d:.2e} > {tol:.0e}")
    r = [
        [c[k] for c in s["reactions"] for k in ("fx", "fy", "fz") if k in c]
        for s in (s_ref, s_other)
    ]
    d = relative(*r)
    print(f"reactions: difference {d:.2e}")
    if d > tol:
        problems.append(f"the reactions differ by {d:.2e} > {tol:.0e}")
    if problems:
        sys.exit(f"{other} does not agree with {ref}: " + "; ".join(problems))
    print(f"{other} agrees with {ref} to {tol:.0e} ({len(keys)} pair rows, same states)")


if __name__ == "__main__":
    main()
