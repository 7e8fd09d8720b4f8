#!/usr/bin/env python3
"""Writes the Gmsh-made meshes of cfe's tests with Gmsh itself (`pip install gmsh`).
The tests read the committed files and do not need Gmsh.

Run: `python3 tests/data/gmsh/make_reference.py` (writes next to this script).

The seed's plate on a base (SPEC §4) in one shared file, two independently meshed
surfaces: base x in [0, 200], y in [0, 120] and plate x in [30, 170], y in [120, 135].
Their faces at y = 120 are separate curves with their own nodes (not merged).
Physical surfaces "base" and "plate"; physical curves "bottom", "right", "top" and
"left" each hold that side of both rectangles, so in cfe each part gets the four
names of the built-in rectangle mesher.

  plate_on_base_41.msh      transfinite: base 20 x 12 cells, plate 28 x 6 cells, each
                            cell split along its rising diagonal, as cfe's structured
                            mesher does (MSH 4.1 ASCII)
  plate_on_base_41_bin.msh  the same, MSH 4.1 binary
  plate_on_base_22.msh      the same, MSH 2.2 ASCII
  plate_on_base_22_bin.msh  the same, MSH 2.2 binary
  plate_on_base_free.msh    unstructured (Delaunay) triangles: size 10 in the base,
                            2.5 in the plate (MSH 4.1 ASCII)
"""

import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))


def rectangle(x0, x1, y0, y1):
    """Four points and curves (bottom, right, top, left), counter-clockwise."""
    g = gmsh.model.geo
    p = [g.addPoint(x0, y0, 0), g.addPoint(x1, y0, 0), g.addPoint(x1, y1, 0),
         g.addPoint(x0, y1, 0)]
    c = [g.addLine(p[k], p[(k + 1) % 4]) for k in range(4)]
    s = g.addPlaneSurface([g.addCurveLoop(c)])
    return p, c, s


def build(structured):
    gmsh.model.add("plate_on_base")
    g = gmsh.model.geo
    base_p, base_c, base_s = rectangle(0, 200, 0, 120)
    plate_p, plate_c, plate_s = rectangle(30, 170, 120, 135)
    if structured:
        for c, n in zip(base_c, [20, 12, 20, 12]):
            g.mesh.setTransfiniteCurve(c, n + 1)
        for c, n in zip(plate_c, [28, 6, 28, 6]):
            g.mesh.setTransfiniteCurve(c, n + 1)
        # "Right": each cell split along its rising diagonal (lower left to upper right).
        g.mesh.setTransfiniteSurface(base_s, "Right", base_p)
        g.mesh.setTransfiniteSurface(plate_s, "Right", plate_p)
    else:
        for p in base_p:
            g.mesh.setSize([(0, p)], 10.0)
        for p in plate_p:
            g.mesh.setSize([(0, p)], 2.5)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [base_s], 1, "base")
    gmsh.model.addPhysicalGroup(2, [plate_s], 2, "plate")
    for k, name in enumerate(["bottom", "right", "top", "left"]):
        gmsh.model.addPhysicalGroup(1, [base_c[k], plate_c[k]], 11 + k, name)
    gmsh.model.mesh.generate(2)


def write(name, version, binary):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(os.path.join(HERE, name))
    print("wrote", name)


def main():
    gmsh.initialize(sys.argv)
    gmsh.option.setNumber("General.Terminal", 0)
    build(structured=True)
    write("plate_on_base_41.msh", 4.1, False)
    write("plate_on_base_41_bin.msh", 4.1, True)
    write("plate_on_base_22.msh", 2.2, False)
    write("plate_on_base_22_bin.msh", 2.2, True)
    gmsh.clear()
    build(structured=False)
    write("plate_on_base_free.msh", 4.1, False)
    gmsh.finalize()


if __name__ == "__main__":
    main()
