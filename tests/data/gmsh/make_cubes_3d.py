#!/usr/bin/env python3
"""Writes the 3D Gmsh meshes of cfe's tests (tests/data/gmsh/cubes_*.msh) with the
Gmsh SDK (`pip install gmsh`; the tests read the committed files and need no Gmsh).

Run from anywhere: `python3 tests/data/gmsh/make_cubes_3d.py`.

The geometry: two unit cubes side by side, each meshed on its own (not fragmented:
each has its own nodes on the face x = 1 they share):

    "hexa"   [0, 1] x [0, 1] x [0, 1]   8-node hexahedra, 2 x 2 x 2 (transfinite)
    "tetra"  [1, 2] x [0, 1] x [0, 1]   4-node tetrahedra, size 0.45

Physical volumes 1 "hexa", 2 "tetra". Physical surfaces:

    11 "fixed"      x = 0 (hexa)
    12 "interface"  x = 1 of both cubes (a face of each part)
    13 "load"       x = 2 (tetra)
    14 "bottom"     z = 0 of both cubes
    15 (no name)    y = 1 of the hexa cube

Node coordinates are rounded to 12 significant digits, so every encoding holds
the same doubles. Files written (the same mesh in each encoding):
  cubes_41.msh       MSH 4.1 ASCII
  cubes_41_bin.msh   MSH 4.1 binary
  cubes_22.msh       MSH 2.2 ASCII
  cubes_22_bin.msh   MSH 2.2 binary
"""

import os

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
EPS = 1e-6


def faces_at(volume, axis, value):
    """The surfaces of `volume` lying in the plane coordinate[axis] = value."""
    out = []
    for dim, tag in gmsh.model.getBoundary([(3, volume)], oriented=False):
        box = gmsh.model.getBoundingBox(dim, tag)
        if abs(box[axis] - value) < EPS and abs(box[axis + 3] - value) < EPS:
            out.append(tag)
    assert out, (volume, axis, value)
    return out


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("cubes")
    occ = gmsh.model.occ
    hexa = occ.addBox(0, 0, 0, 1, 1, 1)
    tetra = occ.addBox(1, 0, 0, 1, 1, 1)
    occ.synchronize()

    # The hexahedral cube: transfinite, 2 cells a side, recombined.
    surfaces = [t for _, t in gmsh.model.getBoundary([(3, hexa)], oriented=False)]
    curves = set()
    for s in surfaces:
        for _, c in gmsh.model.getBoundary([(2, s)], oriented=False):
            curves.add(c)
    for c in sorted(curves):
        gmsh.model.mesh.setTransfiniteCurve(c, 3)
    for s in surfaces:
        gmsh.model.mesh.setTransfiniteSurface(s)
        gmsh.model.mesh.setRecombine(2, s)
    gmsh.model.mesh.setTransfiniteVolume(hexa)
    gmsh.model.mesh.setRecombine(3, hexa)

    # The tetrahedral cube: unstructured.
    points = gmsh.model.getBoundary([(3, tetra)], recursive=True)
    gmsh.model.mesh.setSize(points, 0.45)

    gmsh.model.addPhysicalGroup(3, [hexa], 1, "hexa")
    gmsh.model.addPhysicalGroup(3, [tetra], 2, "tetra")
    gmsh.model.addPhysicalGroup(2, faces_at(hexa, 0, 0.0), 11, "fixed")
    gmsh.model.addPhysicalGroup(
        2, faces_at(hexa, 0, 1.0) + faces_at(tetra, 0, 1.0), 12, "interface"
    )
    gmsh.model.addPhysicalGroup(2, faces_at(tetra, 0, 2.0), 13, "load")
    gmsh.model.addPhysicalGroup(
        2, faces_at(hexa, 2, 0.0) + faces_at(tetra, 2, 0.0), 14, "bottom"
    )
    gmsh.model.addPhysicalGroup(2, faces_at(hexa, 1, 1.0), 15)

    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.model.mesh.generate(3)
    # Coordinates rounded to 12 significant digits, so that the ASCII files
    # (written with 16) give back the binary files' doubles exactly.
    tags, coords, _ = gmsh.model.mesh.getNodes()
    for k, tag in enumerate(tags):
        xyz = [float(f"{c:.12g}") for c in coords[3 * k : 3 * k + 3]]
        gmsh.model.mesh.setNode(tag, xyz, [])

    for name, version, binary in [
        ("cubes_41.msh", 4.1, 0),
        ("cubes_41_bin.msh", 4.1, 1),
        ("cubes_22.msh", 2.2, 0),
        ("cubes_22_bin.msh", 2.2, 1),
    ]:
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.write(os.path.join(HERE, name))
    gmsh.finalize()


if __name__ == "__main__":
    main()
