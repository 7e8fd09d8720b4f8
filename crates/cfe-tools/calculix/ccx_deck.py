"""What the CalculiX comparison scripts share (plate_on_base.py in 2D,
plate_on_base_3d.py in 3D): running `cfe run` and reading its mesh back from the
VTU, writing the parts of a CalculiX deck that do not depend on the model
(nodes, elements, the material, the contact pair and its surface interaction),
running `ccx` and reading its .dat file.

Python 3, standard library only; imported by the two scripts (which run from
anywhere: Python puts a script's own folder first on its path).
"""

import csv
import os
import re
import struct
import subprocess
import time
import xml.etree.ElementTree as ET


def read_vtu(path, dim):
    """Points, cells (node lists), per-cell part ids and point displacements of a
    VTU written by cfe (raw appended data, UInt64 headers); points and
    displacements as `dim`-tuples (the VTU stores three components)."""
    raw = open(path, "rb").read()
    start = raw.index(b"<AppendedData")
    data = raw[raw.index(b"_", start) + 1:]
    root = ET.fromstring(raw[:start].decode() + "</VTKFile>")
    fmt = {"Float64": "d", "Int64": "q", "Int32": "i", "UInt8": "B"}

    def array(elem):
        off = int(elem.get("offset"))
        (n,) = struct.unpack_from("<Q", data, off)
        code = fmt[elem.get("type")]
        count = n // struct.calcsize(code)
        return list(struct.unpack_from(f"<{count}{code}", data, off + 8))

    piece = root.find(".//Piece")
    pts = array(piece.find("Points/DataArray"))
    points = [tuple(pts[3 * i:3 * i + dim]) for i in range(len(pts) // 3)]
    cells_el = {d.get("Name"): d for d in piece.find("Cells")}
    conn, offs = array(cells_el["connectivity"]), array(cells_el["offsets"])
    cells, prev = [], 0
    for o in offs:
        cells.append(conn[prev:o])
        prev = o
    cd = {d.get("Name"): d for d in piece.find("CellData")}
    pd = {d.get("Name"): d for d in piece.find("PointData")}
    part = array(cd["part_id"])
    disp = array(pd["displacement"])
    u = [tuple(disp[3 * i:3 * i + dim]) for i in range(len(points))]
    return points, cells, part, u


def run_cfe(cfe, folder, problem_text, dim, args=()):
    """Writes `problem_text` as folder/problem.toml, runs `cfe run` on it (with
    `args`) into folder/out and returns the last increment's mesh (as
    [`read_vtu`]), the pairs table (pairs.csv rows) and the wall-clock seconds
    of the process. Raises CalledProcessError (its stderr captured) when cfe
    fails."""
    os.makedirs(folder, exist_ok=True)
    toml = os.path.join(folder, "problem.toml")
    with open(toml, "w") as f:
        f.write(problem_text)
    out = os.path.join(folder, "out")
    t0 = time.perf_counter()
    subprocess.run([cfe, "run", toml, "--out", out, *args], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    seconds = time.perf_counter() - t0
    vtus = sorted(f for f in os.listdir(os.path.join(out, "vtu")) if f.startswith("parts_"))
    mesh = read_vtu(os.path.join(out, "vtu", vtus[-1]), dim)
    with open(os.path.join(out, "pairs.csv")) as f:
        pairs = list(csv.DictReader(f))
    return mesh, pairs, seconds


def run_ccx(ccx, folder, env=None):
    """Runs `ccx -i plate` in `folder` (its log in folder/ccx.log; `env` the
    process's environment, None: this one's) and returns the wall-clock
    seconds. Raises CalledProcessError when ccx fails."""
    t0 = time.perf_counter()
    with open(os.path.join(folder, "ccx.log"), "w") as log:
        subprocess.run([ccx, "-i", "plate"], cwd=folder, check=True, stdout=log,
                       stderr=subprocess.STDOUT, env=env)
    return time.perf_counter() - t0


# The .dat blocks read, by the first words of their header.
DAT_BLOCKS = {"displacements": "U", "contact stress": "CSTR",
              "relative contact displacement": "CDIS"}


def parse_dat(path):
    """The last time's blocks of a ccx .dat file: {'U': {node: values},
    'CSTR': {...}, 'CDIS': {...}} (0-based nodes; the blocks of one key at one
    time — *NODE PRINT of several node sets — merged)."""
    blocks, current, time_of = {}, None, {}
    pattern = r"\s*(" + "|".join(DAT_BLOCKS) + r")\b.*time\s+([0-9.Ee+-]+)"
    for line in open(path):
        m = re.match(pattern, line)
        if m:
            key = DAT_BLOCKS[m.group(1)]
            t = float(m.group(2))
            if time_of.get(key) != t:
                blocks[key] = {}
                time_of[key] = t
            current = blocks[key]
            continue
        parts = line.split()
        if current is not None and parts and re.match(r"^\d+$", parts[0]):
            current[int(parts[0]) - 1] = [float(v) for v in parts[1:]]
    return blocks


def node_lines(points):
    """*NODE (set NALL) of `points` (2D points get z = 0), 1-based."""
    lines = ["*NODE, NSET=NALL"]
    for i, p in enumerate(points):
        z = f"{p[2]:.12g}" if len(p) > 2 else "0"
        lines.append(f"{i + 1}, {p[0]:.12g}, {p[1]:.12g}, {z}")
    return lines


def element_lines(kind, elset, ids, nodes_of):
    """*ELEMENT of type `kind` into `elset`: the cells `ids` (0-based) with the
    node lists `nodes_of(cell)`, all 1-based."""
    return [f"*ELEMENT, TYPE={kind}, ELSET={elset}"] + [
        f"{c + 1}, " + ", ".join(str(n + 1) for n in nodes_of(c)) for c in ids]


def material_lines(e, nu, elsets, thickness=None):
    """The elastic material STEEL and a *SOLID SECTION of it on each of `elsets`
    (with the plane elements' `thickness` when given)."""
    lines = ["*MATERIAL, NAME=STEEL\n*ELASTIC\n" + f"{e}, {nu}"]
    for s in elsets:
        section = f"*SOLID SECTION, ELSET={s}, MATERIAL=STEEL"
        lines.append(section if thickness is None else section + "\n" + f"{thickness}")
    return lines


def contact_lines(slave, master, slope, friction, sigma_inf=None,
                  pair_type="NODE TO SURFACE", pair_options=""):
    """The contact pair `slave`, `master` (surface names) with the surface
    interaction SI1: a linear pressure-overclosure of `slope` (MPa/mm; with the
    tension at large clearance `sigma_inf` when given, node-to-surface only)
    and, for `friction` "stick" or a coefficient, *FRICTION with the stick
    slope `slope` ("stick": μ = 1e3); None: frictionless."""
    behaviour = f"{slope:.6g}" if sigma_inf is None else f"{slope:.6g}, {sigma_inf:g}"
    lines = [f"*CONTACT PAIR, INTERACTION=SI1, TYPE={pair_type}{pair_options}\n{slave}, {master}",
             "*SURFACE INTERACTION, NAME=SI1",
             "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n" + behaviour]
    if friction == "stick":
        lines.append("*FRICTION\n" + f"1e3, {slope:.6g}")
    elif friction is not None:
        lines.append("*FRICTION\n" + f"{friction}, {slope:.6g}")
    return lines


def parse_frd_contact(path):
    """The last CONTACT block of a ccx .frd file (ASCII, written by *CONTACT
    FILE with CSTR): {node (0-based): [COPEN, CSLIP1, CSLIP2, CPRESS, CSHEAR1,
    CSHEAR2]}, CalculiX's contact stresses extrapolated to the slave nodes
    (face-to-face contact)."""
    block, current = {}, None
    for line in open(path):
        if line.startswith(" -4"):
            current = {} if line.split()[1] == "CONTACT" else None
            if current is not None:
                block = current
        elif line.startswith(" -3"):
            current = None
        elif current is not None and line.startswith(" -1"):
            # " -1", the node in 10 columns, then values of 12 columns each.
            node = int(line[3:13])
            rest = line[13:].rstrip("\n")
            current[node - 1] = [float(rest[i:i + 12]) for i in range(0, len(rest), 12)]
    return block
