#!/usr/bin/env python3
"""Receding contact of the 3D plate on a base: cfe side by side with CalculiX.

The same problem as examples/plate_on_base_3d.toml (steel, E = 210000 MPa,
nu = 0.31; a TET4 plate x 30..170, y 0..40, z 120..135 in 5 mm cells on a HEX8
base x 0..200, y 0..40, z 0..120 in 20 mm cells; 60 kN down, spread uniformly
over the plate's top between x = 85 and 115, the whole depth; the base's bottom
clamped; the plate held in x at (100, 0, 135) and (100, 40, 135) and in y at
the first: statically determinate, no load), with an explicit pair penalty
c_n = C_PAIR (and c_s = C_PAIR for the frictional laws) instead of the
example's default.

For every law of CASES the script
  1. writes the cfe problem file and runs `cfe run` on it (`--refine K` when
     asked: the timing comparison);
  2. reads cfe's mesh back from the run's VTU (points, cells, part ids) and its
     pairs table (pairs.csv: normal force, tributary area of every pair), so
     that CalculiX gets exactly the same nodes and elements;
  3. writes the CalculiX input (.inp): C3D4 elements for the plate, C3D8 for
     the base (one deck), the same supports, the same nodal loads (the uniform
     traction integrated over the loaded triangles, each node a third of its
     triangles' force, as cfe does for a TET4 face), node-to-surface contact
     with the plate's bottom nodes as slaves and the base's top faces as
     master, a linear pressure-overclosure penalty of the same stiffness per
     area as c_n per pair (c_n / the interior pair's tributary area, 25 mm²
     at K = 1) and, for the frictional laws, *FRICTION with a stick slope of
     the same stiffness;
  4. runs ccx and reads the contact pressure of every slave node from the .dat
     file (*CONTACT PRINT, CSTR) and the displacements (*NODE PRINT, U);
  5. prints a Markdown table: per law, the contact zone (the x- and y-extent
     of the pairs carrying compression), the number of closed pairs, the total
     normal force and u_z of the plate's bottom at its centre (100, 20, 120)
     and ends (30 and 170, 20, 120) and of its top centre (100, 20, 135), for
     cfe and CalculiX; then the wall-clock seconds of both runs.

cfe's pair forces are forces per pair (N); CalculiX prints contact pressures
(MPa), turned into forces with the pair's tributary area from cfe's pairs.csv
(the same slave face mesh).

Needs: the `cfe` binary (default target/release/cfe), `ccx` (CalculiX 2.x:
`apt-get install calculix-ccx`), Python 3 (standard library only).
Usage (from the repository root):
    python3 crates/cfe-tools/calculix/plate_on_base_3d.py [--cfe PATH] [--ccx PATH]
        [--work DIR] [--laws frictionless,stick,coulomb] [--refine K] [--repeat N]
With --model bench --refine 4 both codes solve the benchmark's 3D model
(examples/plate_on_base_3d_bench.toml's mesh, about 59k unknowns) and each run is
repeated N times (--repeat N), the fastest kept (wall clock of the whole process:
`cfe run` with all its outputs, ccx with its .dat/.frd, one thread:
OMP_NUM_THREADS=1). The timing at K = 4:
    python3 crates/cfe-tools/calculix/plate_on_base_3d.py --model bench --refine 4 \
        --laws frictionless --contact surface --c-pair 3.28125e7 --repeat 3
CalculiX's node-to-surface contact does not converge on the bench model at
K = 2, 3 or 4 (its residual stalls and it cuts the increment below 1e-4 of the
load, whatever the slope, 8e7 or 1.05e7 MPa/mm, with or without SMALL
SLIDING): --contact surface gives it face-to-face contact (SURFACE TO SURFACE,
the slave surface the plate's bottom faces), which converges in 10 increments
of 0.1 with the default controls when the slope is about 50 E (CalculiX's
manual: 5 to 50 times E): --c-pair 3.28125e7 per pair is 1.05e7 MPa/mm at K = 4
(the interior pair's area 1.25 × 2.5 mm²), and cfe gets the same stiffness per
pair. Its nodal contact pressures are read from the .frd (*CONTACT FILE, CSTR:
extrapolated from the integration points to the slave nodes).
Its table at K = 1 is pasted, as a static table clearly labelled as produced by
this script, into the verification report (`CALCULIX_3D` in
crates/cfe-tools/src/verification/solid_peer.rs); the test suite does not need
CalculiX.
"""

import argparse
import os
import subprocess
import sys

from ccx_deck import (contact_lines, element_lines, material_lines, node_lines, parse_dat,
                      parse_frd_contact,
                      run_ccx as run_ccx_deck, run_cfe as run_cfe_problem)

E, NU = 210000.0, 0.31
LOAD = 60000.0
LOAD_X = (85.0, 115.0)
TOP, BOTTOM = 135.0, 120.0
MU = 0.2
# The pair penalty (N/mm per pair), and for CalculiX a pressure-overclosure
# slope (MPa/mm) of the same stiffness per area: c_n / the tributary area of an
# interior pair (5 mm × 5 mm at K = 1; divided by K² when refined).
C_PAIR = 1e9
# CalculiX's tension at large clearances (MPa), as small as it takes.
SIGMA_INF = 1e-4

CASES = {
    # law name: (cfe interface lines for the pair penalty c, CalculiX friction
    # coefficient or None)
    "frictionless": (lambda c: f'law = "frictionless"\nc_n = {c:g}\n', None),
    "stick": (lambda c: f'law = "contact"\nc_n = {c:g}\nc_s = {c:g}\n', "stick"),
    "coulomb": (lambda c: f'law = "coulomb"\nfriction = {MU}\nc_n = {c:g}\nc_s = {c:g}\n', MU),
}


# The meshes: (plate cells, base cells) of the example and of the benchmark's
# 3D model (examples/plate_on_base_3d_bench.toml: fewer cells across the depth
# and the thickness, so that K = 4 has about 59k unknowns).
MODELS = {
    "example": ([28, 8, 3], [10, 2, 6]),
    "bench": ([28, 4, 2], [10, 1, 3]),
}


def problem(interface_lines, model="example"):
    """The cfe problem file of the 3D plate on a base with the given interface law."""
    plate, base = MODELS[model]
    return f"""title = "Plate on a base 3D (CalculiX comparison)"
[materials.steel]
E = {E}
nu = {NU}
[[part]]
name = "base"
material = "steel"
box = {{ x = [0.0, 200.0], y = [0.0, 40.0], z = [0.0, 120.0], cells = {base}, elements = "hex8" }}
[[part]]
name = "plate"
material = "steel"
box = {{ x = [30.0, 170.0], y = [0.0, 40.0], z = [120.0, 135.0], cells = {plate}, elements = "tet4" }}
[[interface]]
name = "plate-base"
host = "base"
nodes = "plate"
boundary = "bottom"
{interface_lines}
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y", "z"]
[[load]]
name = "patch"
part = "plate"
boundary = "top"
from = [{LOAD_X[0]}, 0.0, {TOP}]
to = [{LOAD_X[1]}, 40.0, {TOP}]
force = [0.0, 0.0, {-LOAD}]
[[support]]
part = "plate"
at = [100.0, 0.0, {TOP}]
fix = ["x", "y"]
[[support]]
part = "plate"
at = [100.0, 40.0, {TOP}]
fix = ["x"]
[analysis]
increments = 10
scheme = "active-set"
"""


def run_cfe(cfe, work, name, lines, refine, model):
    """Runs cfe on the problem with `lines`; returns its mesh, pairs and seconds."""
    folder = os.path.join(work, f"cfe_{name}_{model}_k{refine}")
    return run_cfe_problem(cfe, folder, problem(lines, model), 3,
                           ["--refine", str(refine), "--force"])


def volume(p, n):
    """Six times the signed volume of the tetrahedron n[0..4] of points p."""
    a, b, c, d = (p[i] for i in n[:4])
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    w = [d[k] - a[k] for k in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def area(p, n):
    """The area of the triangle n of points p."""
    a, b, c = (p[i] for i in n)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    x = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    return 0.5 * sum(t * t for t in x) ** 0.5


def nodal_loads(points, cells, plate):
    """The uniform downward traction LOAD / (patch area) over the top triangles of the
    plate inside the patch, a third of each triangle's force on each of its nodes
    (exact for linear shape functions)."""
    patch = (LOAD_X[1] - LOAD_X[0]) * 40.0
    q = LOAD / patch
    f = {}
    eps = 1e-9
    for c in plate:
        top = [n for n in cells[c] if abs(points[n][2] - TOP) < eps]
        if len(top) != 3:
            continue
        if all(LOAD_X[0] - eps <= points[n][0] <= LOAD_X[1] + eps for n in top):
            a = area(points, top)
            for n in top:
                f[n] = f.get(n, 0.0) - q * a / 3.0
    return f


# C3D4 and C3D8 faces (Abaqus/CalculiX numbering, 0-based local nodes).
TET_FACES = [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)]
HEX_FACES = [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]


def write_inp(path, mesh, friction, k_area, step_inc, contact="node"):
    """The CalculiX deck on the cfe mesh `mesh`; `contact` "node": node-to-surface
    contact (the tension SIGMA_INF at large clearance), "surface": face-to-face
    (CalculiX's SURFACE TO SURFACE, the contact stresses written to the .frd at
    the slave nodes). Returns the slave nodes and the nearest-plate-node finder."""
    points, cells, part, _ = mesh
    base = [i for i, p in enumerate(part) if p == 0]
    plate = [i for i, p in enumerate(part) if p == 1]
    plate_nodes = sorted({n for c in plate for n in cells[c]})
    base_nodes = sorted({n for c in base for n in cells[c]})
    L = ["*HEADING\nPlate on a base 3D, cfe mesh (written by plate_on_base_3d.py)"]
    L += node_lines(points)

    def tet(c):
        n = list(cells[c])
        if volume(points, n) < 0:
            n[1], n[2] = n[2], n[1]
        return n

    L += element_lines("C3D8", "EBASE", base, lambda c: cells[c])
    L += element_lines("C3D4", "EPLATE", plate, tet)
    L += material_lines(E, NU, ["EBASE", "EPLATE"])
    slaves = [n for n in plate_nodes if abs(points[n][2] - BOTTOM) < 1e-9]
    L.append("*NSET, NSET=SLAVE\n" + ",\n".join(str(n + 1) for n in slaves))
    faces = []
    for c in base:
        for k, f in enumerate(HEX_FACES):
            if all(abs(points[cells[c][i]][2] - BOTTOM) < 1e-9 for i in f):
                faces.append(f"{c + 1}, S{k + 1}")
    L.append("*SURFACE, NAME=MASTER, TYPE=ELEMENT\n" + "\n".join(faces))
    # The slave surface as the plate's bottom faces (C3D4 face k of its nodes
    # TET_FACES[k]), so that CalculiX takes each slave node's area from them.
    sfaces = []
    for c in plate:
        n = tet(c)
        for k, f in enumerate(TET_FACES):
            if all(abs(points[n[i]][2] - BOTTOM) < 1e-9 for i in f):
                sfaces.append(f"{c + 1}, S{k + 1}")
    L.append("*SURFACE, NAME=SLAVES, TYPE=ELEMENT\n" + "\n".join(sfaces))
    # K, and the tension σ∞ at large clearances (node-to-surface only; CalculiX's
    # default, 3 MPa, pulls the open slave nodes down: 1e-4 MPa × 25 mm² is 4e-8
    # of the load per pair).
    if contact == "node":
        L += contact_lines("SLAVES", "MASTER", k_area, friction, SIGMA_INF)
    else:
        L += contact_lines("SLAVES", "MASTER", k_area, friction, None, "SURFACE TO SURFACE")
    fixed = [n for n in base_nodes if abs(points[n][2]) < 1e-9]

    def at(x, y, z):
        return min(plate_nodes, key=lambda n: (points[n][0] - x) ** 2 + (points[n][1] - y) ** 2
                   + (points[n][2] - z) ** 2)

    L.append("*BOUNDARY")
    L += [f"{n + 1}, 1, 3" for n in fixed]
    L.append(f"{at(100.0, 0.0, TOP) + 1}, 1, 2")
    L.append(f"{at(100.0, 40.0, TOP) + 1}, 1, 1")
    L.append(f"*STEP, INC=1000\n*STATIC\n{step_inc}, 1.0, 1e-5, {step_inc}")
    L.append("*CLOAD")
    L += [f"{n + 1}, 3, {v:.12g}" for n, v in sorted(nodal_loads(points, cells, plate).items())]
    L.append("*NODE PRINT, NSET=SLAVE\nU")
    probes = sorted({at(100.0, 20.0, TOP), at(100.0, 20.0, BOTTOM), at(30.0, 20.0, BOTTOM),
                     at(170.0, 20.0, BOTTOM)})
    L.append("*NSET, NSET=PROBES\n" + ", ".join(str(n + 1) for n in probes))
    L.append("*NODE PRINT, NSET=PROBES\nU")
    if contact == "node":
        L.append("*CONTACT PRINT\nCSTR")
    else:
        # Face-to-face contact prints its stresses per integration point: the
        # nodal ones (extrapolated to the slave nodes) go to the .frd.
        L.append("*CONTACT FILE\nCSTR")
    L.append("*END STEP")
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")
    return slaves, at


def run_ccx(ccx, work, name, mesh, friction, k_area, step_inc, refine, model, contact="node"):
    suffix = "" if contact == "node" else "_s2s"
    folder = os.path.join(work, f"ccx_{name}_{model}_k{refine}{suffix}")
    os.makedirs(folder, exist_ok=True)
    slaves, at = write_inp(os.path.join(folder, "plate.inp"), mesh, friction, k_area, step_inc,
                           contact)
    seconds = run_ccx_deck(ccx, folder, dict(os.environ, OMP_NUM_THREADS="1"))
    dat = parse_dat(os.path.join(folder, "plate.dat"))
    if contact != "node":
        # CPRESS (the fourth value) as the first, as the .dat's CSTR has it.
        dat["CSTR"] = {n: v[3:] for n, v in
                       parse_frd_contact(os.path.join(folder, "plate.frd")).items()}
    return slaves, at, dat, seconds


def summarise(label, pts, force, probes):
    closed = [p for p, f in zip(pts, force) if f > 1e-6 * LOAD]
    if closed:
        x = f"{min(p[0] for p in closed):g}–{max(p[0] for p in closed):g}"
        y = f"{min(p[1] for p in closed):g}–{max(p[1] for p in closed):g}"
    else:
        x = y = "none"
    return [label, x, y, str(len(closed)), f"{sum(force):.1f}", f"{max(force):.1f}"] + [
        f"{v:.4e}" for v in probes]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cfe", default="target/release/cfe")
    ap.add_argument("--ccx", default="ccx")
    ap.add_argument("--work", default="results/calculix3d")
    ap.add_argument("--laws", default=",".join(CASES))
    ap.add_argument("--refine", type=int, default=1)
    ap.add_argument("--c-pair", type=float, default=C_PAIR,
                    help="the pair penalty c_n (c_s) of cfe, N/mm; CalculiX gets c / the "
                    "interior pair's area (at K = 4 of the bench model CalculiX does not "
                    "converge with 1e9: 1.25e8 keeps its slope at 4e7 MPa/mm)")
    ap.add_argument("--model", default="example", choices=list(MODELS),
                    help="example: examples/plate_on_base_3d.toml's mesh (the verification "
                    "table); bench: the benchmark's 3D model (the timing at K = 4)")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--contact", default="node", choices=["node", "surface"],
                    help="CalculiX's contact: node-to-surface (the verification table) or "
                    "face-to-face (SURFACE TO SURFACE: what converges on the bench model at "
                    "K = 2 to 4, with a slope of about 50 E)")
    ap.add_argument("--inc", type=float, default=0.1,
                    help="CalculiX's (fixed) increment, a fraction of the load")
    args = ap.parse_args()
    k = args.refine
    plate_cells = MODELS[args.model][0]
    # The tributary area of an interior pair: the plate's cell in x times in y.
    k_area = args.c_pair / ((140.0 / plate_cells[0] / k) * (40.0 / plate_cells[1] / k))
    rows, times = [], []
    for name in args.laws.split(","):
        lines, friction = CASES[name]
        lines = lines(args.c_pair)
        t_cfe, t_ccx = [], []
        for _ in range(args.repeat):
            try:
                mesh, pairs, s = run_cfe(args.cfe, args.work, name, lines, k, args.model)
                t_cfe.append(s)
            except subprocess.CalledProcessError as e:
                print(f"cfe failed for {name}: {e.stderr.decode().strip()[-400:]}", file=sys.stderr)
                raise
        points, u = mesh[0], mesh[3]
        for _ in range(args.repeat):
            slaves, at, dat, s = run_ccx(args.ccx, args.work, name, mesh, friction, k_area,
                                         args.inc, k, args.model, args.contact)
            t_ccx.append(s)
        times.append((name, len(points) * 3, min(t_cfe), t_cfe, min(t_ccx), t_ccx))
        by_node = {}
        for p in pairs:
            by_node[(round(float(p["x"]), 6), round(float(p["y"]), 6))] = p
        pts = [points[n] for n in slaves]
        keys = [(round(p[0], 6), round(p[1], 6)) for p in pts]
        f_cfe = [float(by_node[q]["force_n"]) for q in keys]
        trib = [float(by_node[q]["tributary"]) for q in keys]
        cstr = dat.get("CSTR", {})
        f_ccx = [cstr.get(n, [0.0])[0] * a for n, a in zip(slaves, trib)]
        probe_nodes = [at(100.0, 20.0, BOTTOM), at(30.0, 20.0, BOTTOM), at(170.0, 20.0, BOTTOM),
                       at(100.0, 20.0, TOP)]
        uc = dat.get("U", {})
        rows.append(summarise(f"{name}: cfe", pts, f_cfe, [u[n][2] for n in probe_nodes]))
        rows.append(summarise(f"{name}: CalculiX", pts, f_ccx,
                              [uc[n][2] if n in uc else float("nan") for n in probe_nodes]))
    print(f"Model {args.model}, refinement K = {k}, CalculiX pressure-overclosure slope "
          f"{k_area:.4g} MPa/mm\n")
    print("| law: code | contact zone x | contact zone y | closed pairs | Σ f_n (N) | max f_n (N) "
          "| u_z bottom centre (mm) | u_z bottom end x=30 (mm) | u_z bottom end x=170 (mm) "
          "| u_z top centre (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print()
    print("| law | 3 × nodes | cfe run (s, fastest) | cfe runs | ccx (s, fastest) | ccx runs | ccx / cfe |")
    print("|---|---|---|---|---|---|---|")
    for name, n, a, ta, b, tb in times:
        print(f"| {name} | {n} | {a:.2f} | {', '.join(f'{t:.2f}' for t in ta)} | {b:.2f} | "
              f"{', '.join(f'{t:.2f}' for t in tb)} | {b / a:.1f} |")


if __name__ == "__main__":
    sys.exit(main())
