#!/usr/bin/env python3
"""Receding contact of the plate on a base: cfe side by side with CalculiX.

The same problem as examples/plate_on_base.toml (SPEC §4: plane stress, t = 1,
E = 210000 MPa, nu = 0.31, 1500 N down on the plate's top between x = 86 and 114),
with one more support: the plate's top centre (100, 135) is fixed in x. The
problem is symmetric about x = 100, so that support carries no force; it only
removes the plate's rigid sliding, which frictionless contact leaves free.

For every law of CASES the script
  1. writes the cfe problem file and runs `cfe run` on it;
  2. reads cfe's mesh back from the run's VTU (points, cells, part ids) and its
     pairs table (pairs.csv), so that CalculiX gets exactly the same nodes and
     triangles;
  3. writes the CalculiX input (.inp): CPS3 elements, the base's bottom clamped,
     the same nodal loads (the uniform traction integrated exactly over the
     partly loaded edges, as cfe does), node-to-surface contact with the plate's
     bottom nodes as slaves and the base's top faces as master, a linear
     pressure-overclosure penalty and, for the frictional laws, *FRICTION;
  4. runs ccx and reads the contact pressure and status of every slave node
     from the .dat file (*CONTACT PRINT, CSTR) and the displacements of the
     plate's ends and centre from the .dat (*NODE PRINT, U);
  5. prints a Markdown table: per law, the contact zone (the x-extent of the
     pairs carrying compression), the number of closed pairs, the total normal
     force and the displacements, for cfe and CalculiX.

cfe's pair forces are forces per pair (N); CalculiX prints contact stresses
(MPa), turned into forces with the slave node's tributary length (t = 1).

Needs: the `cfe` binary (default target/release/cfe), `ccx` (CalculiX 2.x:
`apt-get install calculix-ccx`), Python 3 (standard library only).
Usage (from the repository root):
    python3 crates/cfe-tools/calculix/plate_on_base.py [--cfe PATH] [--ccx PATH]
        [--work DIR] [--laws stick,frictionless,coulomb]
Its output is pasted, as a static table clearly labelled as produced by this
script, into the verification report (`CALCULIX` in crates/cfe-tools/src/verification/
fits.rs); the test suite does not need CalculiX.
"""

import argparse
import os
import subprocess
import sys

from ccx_deck import (contact_lines, element_lines, material_lines, node_lines, parse_dat,
                      run_ccx as run_ccx_deck, run_cfe as run_cfe_problem)

E, NU, T = 210000.0, 0.31, 1.0
LOAD = 1500.0
LOAD_FROM, LOAD_TO, LOAD_Y = 86.0, 114.0, 135.0
PLATE_Y0 = 120.0
MU = 0.2
# The pair penalty of the seed example (N/mm per pair), and for CalculiX a
# pressure-overclosure slope (MPa/mm) of the same stiffness per unit length:
# c_n / (tributary length 5 mm).
C_PAIR = 1e9
K_LINE = C_PAIR / 5.0

# See main(): CalculiX's CSTR of an expanded plane element is half the pressure.
CCX_2D = 2.0

CASES = {
    # law name: (cfe interface lines, CalculiX friction coefficient or None)
    "stick": ('law = "contact"\nc_n = 1e9\nc_s = 1e9\n', "stick"),
    "frictionless": ('law = "frictionless"\nc_n = 1e9\n', None),
    "coulomb": (f'law = "coulomb"\nfriction = {MU}\nc_n = 1e9\nc_s = 1e9\n', MU),
}


def problem(interface_lines):
    """The cfe problem file of the plate on a base with the given interface law."""
    return f"""title = "Plate on a base (CalculiX comparison)"
plane = "stress"
[materials.steel]
E = {E}
nu = {NU}
[[part]]
name = "base"
material = "steel"
rectangle = {{ x = [0.0, 200.0], y = [0.0, 120.0], cells = [20, 12] }}
[[part]]
name = "plate"
material = "steel"
rectangle = {{ x = [30.0, 170.0], y = [120.0, 135.0], cells = [28, 6] }}
[[interface]]
name = "plate-base"
host = "base"
nodes = "plate"
boundary = "bottom"
{interface_lines}
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
[[support]]
part = "plate"
at = [100.0, 135.0]
fix = ["x"]
[[load]]
part = "plate"
boundary = "top"
from = [{LOAD_FROM}, {LOAD_Y}]
to = [{LOAD_TO}, {LOAD_Y}]
force = [0.0, {-LOAD}]
[analysis]
increments = 10
"""


def run_cfe(cfe, work, name, lines):
    mesh, pairs, _ = run_cfe_problem(cfe, os.path.join(work, f"cfe_{name}"), problem(lines), 2)
    return mesh, pairs


def nodal_loads(points, plate_nodes):
    """The uniform downward traction LOAD / (LOAD_TO − LOAD_FROM) over the segment,
    integrated exactly with the linear shape functions of the plate's top edges."""
    q = LOAD / (LOAD_TO - LOAD_FROM)
    top = sorted((points[n][0], n) for n in plate_nodes if abs(points[n][1] - LOAD_Y) < 1e-9)
    f = {}
    for (xa, na), (xb, nb) in zip(top, top[1:]):
        lo, hi = max(xa, LOAD_FROM), min(xb, LOAD_TO)
        if hi <= lo:
            continue
        L = xb - xa
        # ∫ N_a dx and ∫ N_b dx over [lo, hi], N_a = (xb − x)/L, N_b = (x − xa)/L.
        ia = ((xb - lo) ** 2 - (xb - hi) ** 2) / (2 * L)
        ib = ((hi - xa) ** 2 - (lo - xa) ** 2) / (2 * L)
        f[na] = f.get(na, 0.0) - q * ia
        f[nb] = f.get(nb, 0.0) - q * ib
    return f


def write_inp(path, mesh, friction):
    points, cells, part, _ = mesh
    base = [i for i, p in enumerate(part) if p == 0]
    plate = [i for i, p in enumerate(part) if p == 1]
    plate_nodes = sorted({n for c in plate for n in cells[c]})
    base_nodes = sorted({n for c in base for n in cells[c]})
    L = []
    L.append("*HEADING\nPlate on a base, cfe mesh (written by plate_on_base.py)")
    L += node_lines(points)
    for name, ids in (("EBASE", base), ("EPLATE", plate)):
        L += element_lines("CPS3", name, ids, lambda c: cells[c])
    L += material_lines(E, NU, ["EBASE", "EPLATE"], T)
    slaves = [n for n in plate_nodes if abs(points[n][1] - PLATE_Y0) < 1e-9]
    L.append("*NSET, NSET=SLAVE\n" + ",\n".join(str(n + 1) for n in slaves))
    # Master faces: base triangle edges on y = PLATE_Y0 (CPS3 face k joins nodes k, k+1).
    faces = []
    for c in base:
        nodes = cells[c]
        for k in range(3):
            a, b = nodes[k], nodes[(k + 1) % 3]
            if abs(points[a][1] - PLATE_Y0) < 1e-9 and abs(points[b][1] - PLATE_Y0) < 1e-9:
                faces.append(f"{c + 1}, S{k + 1}")
    L.append("*SURFACE, NAME=MASTER, TYPE=ELEMENT\n" + "\n".join(faces))
    L.append("*SURFACE, NAME=SLAVES, TYPE=NODE\nSLAVE")
    # The tension at large clearance stays CalculiX's default (3 MPa): with
    # 1e-4 MPa, as the 3D comparison needs, the stick and frictionless rows of
    # the table are the same to every printed digit (contact pressures within
    # 6e-5 MPa, u_y within 3e-8 mm, measured 2026-11-28), and CalculiX's
    # Coulomb run no longer converges (too many cutbacks in the first
    # increment).
    L += contact_lines("SLAVES", "MASTER", K_LINE, friction)
    fixed = [n for n in base_nodes if abs(points[n][1]) < 1e-9]
    centre = [n for n in plate_nodes if abs(points[n][0] - 100.0) < 1e-9 and abs(points[n][1] - LOAD_Y) < 1e-9]
    L.append("*BOUNDARY")
    L += [f"{n + 1}, 1, 2" for n in fixed]
    L += [f"{n + 1}, 1, 1" for n in centre]
    L.append("*STEP, INC=1000\n*STATIC\n0.1, 1.0, 1e-5, 0.1")
    L.append("*CLOAD")
    L += [f"{n + 1}, 2, {v:.12g}" for n, v in sorted(nodal_loads(points, plate_nodes).items())]
    L.append("*NODE PRINT, NSET=SLAVE\nU")
    L.append("*CONTACT PRINT\nCSTR, CDIS")
    L.append("*END STEP")
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")
    return slaves


def run_ccx(ccx, work, name, mesh, friction):
    folder = os.path.join(work, f"ccx_{name}")
    os.makedirs(folder, exist_ok=True)
    slaves = write_inp(os.path.join(folder, "plate.inp"), mesh, friction)
    run_ccx_deck(ccx, folder)
    return slaves, parse_dat(os.path.join(folder, "plate.dat"))


def tributary(xs):
    """Tributary lengths of sorted points on a line (half of each neighbouring gap)."""
    n = len(xs)
    return [((xs[i + 1] - xs[i]) if i + 1 < n else 0) / 2 + ((xs[i] - xs[i - 1]) if i > 0 else 0) / 2
            for i in range(n)]


def summarise(label, xs, force, uy_ends, uy_mid):
    closed = [x for x, f in zip(xs, force) if f > 1e-6 * LOAD]
    lo, hi = (min(closed), max(closed)) if closed else (float("nan"),) * 2
    return [label, f"{lo:g}–{hi:g}", str(len(closed)), f"{sum(force):.1f}",
            f"{max(force):.1f}", f"{uy_ends:.4e}", f"{uy_mid:.4e}"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfe", default="target/release/cfe")
    ap.add_argument("--ccx", default="ccx")
    ap.add_argument("--work", default="results/calculix")
    ap.add_argument("--laws", default=",".join(CASES))
    args = ap.parse_args()
    rows, profiles = [], {}
    # The mesh (identical for every law) from the stick run.
    mesh, _ = run_cfe(args.cfe, args.work, "stick", CASES["stick"][0])
    points, _, _, _ = mesh
    for name in args.laws.split(","):
        lines, friction = CASES[name]
        try:
            cfe_mesh, pairs = run_cfe(args.cfe, args.work, name, lines)
            u = cfe_mesh[3]
        except subprocess.CalledProcessError as e:
            print(f"cfe failed for {name}: {e.stderr.decode().strip()}", file=sys.stderr)
            cfe_mesh, pairs, u = None, [], None
        slaves, dat = run_ccx(args.ccx, args.work, name, mesh, friction)
        slaves = sorted(slaves, key=lambda n: points[n][0])
        xs = [points[n][0] for n in slaves]
        trib = tributary(xs)
        # cfe: the pair's normal force (pairs.csv `force_n`, positive = compression).
        by_x = {float(p["x"]): p for p in pairs}
        f_cfe = [float(by_x[x]["force_n"]) if x in by_x else 0.0 for x in xs]
        # CalculiX: contact pressure (first CSTR column) × tributary length × t
        # × CCX_2D. CalculiX expands a plane element into a 3D wedge with two node
        # layers across the thickness, and the CSTR of a 2D slave node is half
        # the pressure: the raw Σ CSTR·length·t is half the applied load (the
        # table's Σ f_n column checks the scaled sum against the load).
        cstr = dat.get("CSTR", {})
        f_ccx = [CCX_2D * cstr.get(n, [0.0])[0] * w * T for n, w in zip(slaves, trib)]
        ends = [slaves[0], slaves[-1]]
        mid = min(slaves, key=lambda n: abs(points[n][0] - 100.0))
        u_ccx = dat.get("U", {})
        if u is not None:
            rows.append(summarise(f"{name}: cfe", xs, f_cfe,
                                  sum(u[n][1] for n in ends) / 2, u[mid][1]))
        rows.append(summarise(f"{name}: CalculiX", xs, f_ccx,
                              sum(u_ccx[n][1] for n in ends) / 2, u_ccx[mid][1]))
        profiles[name] = (xs, f_cfe, f_ccx)
    print("| law: code | contact zone x | closed pairs | Σ f_n (N) | max f_n (N) | u_y plate ends (mm) | u_y plate centre (mm) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print()
    for name, (xs, fa, fb) in profiles.items():
        print(f"{name}: x, f_n cfe, f_n CalculiX")
        print("; ".join(f"{x:g}: {a:.1f} / {b:.1f}" for x, a, b in zip(xs, fa, fb)))


if __name__ == "__main__":
    sys.exit(main())
