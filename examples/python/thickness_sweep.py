"""Parameter sweep: how long is the contact zone under the plate as the plate gets
thicker?

The seed's plate on a base (examples/plate_on_base.toml) with the plate's
thickness h (its height, 15 mm in the seed) from 5 to 40 mm, meshed with the same
element size (5 mm × 2.5 mm); the 1500 N load stays on the central fifth of its
top. A thin plate bends and rests on the base only under the load; a thick one
spreads the load and stays bonded over more of its length. The length of the
contact zone is the distance between the outermost bonded pairs.

    python examples/python/thickness_sweep.py [--out thickness_sweep.png]

Prints a table; with Matplotlib installed, also plots it.
"""

import argparse

import numpy as np

import cfe


def model(h):
    """The plate on a base with a plate of thickness (height) h."""
    top = 120.0 + h
    return cfe.Model(
        {
            "title": f"Plate on a base, h = {h} mm",
            "materials": {"steel": {"E": 210000.0, "nu": 0.31}},
            "part": [
                {"name": "base", "material": "steel",
                 "rectangle": {"x": [0.0, 200.0], "y": [0.0, 120.0], "cells": [20, 12]}},
                {"name": "plate", "material": "steel",
                 "rectangle": {"x": [30.0, 170.0], "y": [120.0, top], "cells": [28, max(2, round(h / 2.5))]}},
            ],
            "interface": [{"name": "contact", "host": "base", "nodes": "plate", "boundary": "bottom",
                           "c_n": 1e9, "c_s": 1e9}],
            "support": [{"part": "base", "boundary": "bottom", "fix": ["x", "y"]}],
            "load": [{"part": "plate", "boundary": "top", "from": [86.0, top], "to": [114.0, top],
                      "force": [0.0, -1500.0]}],
            "analysis": {"increments": 1},
        }
    )


def contact_length(result):
    """The distance between the outermost bonded pairs of the interface."""
    pairs = result.interfaces["contact"]
    x = pairs.x[pairs.bonded]
    return float(x.max() - x.min()) if len(x) else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="thickness_sweep.png", help="the plot (needs Matplotlib)")
    args = parser.parse_args()

    thicknesses = np.array([5.0, 7.5, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0])
    lengths, sag = [], []
    print(f"{'h (mm)':>8} {'contact (mm)':>13} {'bonded':>7} {'max |u| (mm)':>13}")
    for h in thicknesses:
        r = model(h).solve()
        pairs = r.interfaces["contact"]
        lengths.append(contact_length(r))
        sag.append(r.max_displacement["value"])
        print(f"{h:8.1f} {lengths[-1]:13.1f} {int(pairs.bonded.sum()):4d}/{len(pairs):<2d} {sag[-1]:13.4e}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("Matplotlib is not installed: no plot")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(thicknesses, lengths, "o-")
    ax.axhline(140.0, color="grey", lw=0.8, ls="--", label="plate length")
    ax.axhline(28.0, color="grey", lw=0.8, ls=":", label="loaded length")
    ax.set_xlabel("plate thickness h (mm)")
    ax.set_ylabel("length of the contact zone (mm)")
    ax.set_title("Plate on a base: contact zone against plate thickness")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
