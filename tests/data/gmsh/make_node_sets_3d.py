"""Writes node_sets_3d.msh (MSH 2.2, ASCII): a beam 4 x 1 x 1 (x, y, z) of
8 x 2 x 2 HEX8, with the Gmsh physical groups a solid part's node sets come
from. Plain Python (no Gmsh): the structured grid written element by element,
each physical group on its own elementary entity, as Gmsh writes MSH 2.2.

  volume  "beam"   (3, 1)  every hexahedron
  surface "root"   (2, 1)  the face x = 0 (quadrilaterals)
  surface "end"    (2, 2)  the face x = 4
  curve   "hinge"  (1, 1)  the edge x = 0, z = 0 along y (2-node lines)
  curve   "tip"    (1, 2)  the edge x = 4, z = 1 along y
  point   "corner" (0, 1)  the node at the origin

Run: python3 make_node_sets_3d.py (writes next to this script).
"""

import os

NX, NY, NZ = 8, 2, 2
LX, LY, LZ = 4.0, 1.0, 1.0


def node(i, j, k):
    """Gmsh node tag (1-based) of grid point (i, j, k)."""
    return 1 + i + (NX + 1) * (j + (NY + 1) * k)


def main():
    nodes = []
    for k in range(NZ + 1):
        for j in range(NY + 1):
            for i in range(NX + 1):
                nodes.append((node(i, j, k), LX * i / NX, LY * j / NY, LZ * k / NZ))
    elements = []  # (type, physical, entity, node tags)
    elements.append((15, 1, 101, [node(0, 0, 0)]))
    for j in range(NY):
        elements.append((1, 1, 201, [node(0, j, 0), node(0, j + 1, 0)]))
    for j in range(NY):
        elements.append((1, 2, 202, [node(NX, j, NZ), node(NX, j + 1, NZ)]))
    for j in range(NY):
        for k in range(NZ):
            elements.append(
                (3, 1, 301, [node(0, j, k), node(0, j, k + 1), node(0, j + 1, k + 1), node(0, j + 1, k)])
            )
            elements.append(
                (3, 2, 302, [node(NX, j, k), node(NX, j + 1, k), node(NX, j + 1, k + 1), node(NX, j, k + 1)])
            )
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                elements.append(
                    (
                        5,
                        1,
                        401,
                        [
                            node(i, j, k),
                            node(i + 1, j, k),
                            node(i + 1, j + 1, k),
                            node(i, j + 1, k),
                            node(i, j, k + 1),
                            node(i + 1, j, k + 1),
                            node(i + 1, j + 1, k + 1),
                            node(i, j + 1, k + 1),
                        ],
                    )
                )
    names = [(0, 1, "corner"), (1, 1, "hinge"), (1, 2, "tip"), (2, 1, "root"), (2, 2, "end"), (3, 1, "beam")]
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    out += [f'{d} {t} "{n}"' for d, t, n in names]
    out += ["$EndPhysicalNames", "$Nodes", str(len(nodes))]
    out += [f"{t} {x!r} {y!r} {z!r}" for t, x, y, z in nodes]
    out += ["$EndNodes", "$Elements", str(len(elements))]
    for e, (kind, phys, ent, ns) in enumerate(elements, start=1):
        out.append(" ".join(map(str, [e, kind, 2, phys, ent] + ns)))
    out.append("$EndElements")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "node_sets_3d.msh")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
