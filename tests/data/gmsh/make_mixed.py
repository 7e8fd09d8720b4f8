#!/usr/bin/env python3
"""Writes mixed.msh, a small mesh of quadrilaterals and triangles, with Gmsh itself
(`pip install gmsh`). The tests read the committed file and do not need Gmsh.

Run: `python3 tests/data/gmsh/make_mixed.py` (writes next to this script).

The rectangle x in [0, 2], y in [0, 1] in the plane z = 0 as two surfaces sharing
the curve x = 1 (one curve, so its nodes are shared: the mesh is conforming):

  left  [0, 1] x [0, 1]  transfinite 2 x 2 cells, recombined into 4 quadrilaterals
  right [1, 2] x [0, 1]  transfinite 2 x 2 cells, each split along its rising
                         diagonal ("Right"): 8 triangles

15 nodes (a 5 x 3 grid, spacing 0.5). Physical surface "body" holds both surfaces;
physical curves "left" (x = 0), "right" (x = 2), "bottom" (y = 0, both pieces) and
"top" (y = 1, both pieces), 2 line elements per unit of length.

  mixed.msh  MSH 4.1 ASCII
"""

import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))


def build():
    gmsh.model.add("mixed")
    g = gmsh.model.geo
    # 4 --- 5 --- 6
    # |  ql |  tr |
    # 1 --- 2 --- 3
    p = [g.addPoint(x, y, 0) for y in (0, 1) for x in (0, 1, 2)]
    bottom = [g.addLine(p[0], p[1]), g.addLine(p[1], p[2])]
    top = [g.addLine(p[4], p[3]), g.addLine(p[5], p[4])]
    left, middle, right = g.addLine(p[3], p[0]), g.addLine(p[1], p[4]), g.addLine(p[2], p[5])
    s_left = g.addPlaneSurface([g.addCurveLoop([bottom[0], middle, top[0], left])])
    s_right = g.addPlaneSurface([g.addCurveLoop([bottom[1], right, top[1], -middle])])
    for c in bottom + top + [left, middle, right]:
        g.mesh.setTransfiniteCurve(c, 3)
    g.mesh.setTransfiniteSurface(s_left, "Left", [p[0], p[1], p[4], p[3]])
    g.mesh.setTransfiniteSurface(s_right, "Right", [p[1], p[2], p[5], p[4]])
    g.mesh.setRecombine(2, s_left)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [s_left, s_right], 1, "body")
    gmsh.model.addPhysicalGroup(1, [left], 11, "left")
    gmsh.model.addPhysicalGroup(1, [right], 12, "right")
    gmsh.model.addPhysicalGroup(1, bottom, 13, "bottom")
    gmsh.model.addPhysicalGroup(1, top, 14, "top")
    gmsh.model.mesh.generate(2)
    # The transfinite spacing leaves round-off (0.4999999999987): snap to the grid of 0.5.
    tags, xyz, par = gmsh.model.mesh.getNodes(includeBoundary=True, returnParametricCoord=False)
    for k, tag in enumerate(tags):
        gmsh.model.mesh.setNode(tag, [round(2 * v) / 2 for v in xyz[3 * k:3 * k + 3]], [])


def main():
    gmsh.initialize(sys.argv)
    gmsh.option.setNumber("General.Terminal", 0)
    build()
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write(os.path.join(HERE, "mixed.msh"))
    print("wrote mixed.msh")
    gmsh.finalize()


if __name__ == "__main__":
    main()
