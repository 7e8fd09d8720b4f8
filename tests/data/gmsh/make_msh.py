#!/usr/bin/env python3
"""Writes the small hand-made Gmsh meshes of cfe's tests (tests/data/gmsh/*.msh).

Pure Python (no Gmsh needed). Run from anywhere: `python3 tests/data/gmsh/make_msh.py`.

The geometry: two unit squares side by side, left [0,1]x[0,1] and right [1,2]x[0,1],
in the plane z = 0.25.

    60 ---c5--- 5 ---c4--- 40
    |  \      / |          |
    c6  \100 /  c7   s2    c3
    |  /    \   |          |
    1 ---c1--- 2 ---c2---- 3

Node tags are sparse and not sorted in the file. The left square (surface s1) has
four triangles around node 100, the right one (s2) two; one triangle of each is
written clockwise. Physical groups: surfaces 1 "left" {s1}, 2 "right" {s2}; curves
11 "bottom" {c1, c2}, 12 "top" {c4, c5}, 13 (no name) {c3}, 14 "interface" {c7},
15 "sides" {c3, c6}; point 21 "corner" {p1}. Line c4 is written against the
counter-clockwise direction. c3 is in two physical curves (MSH 2.2 repeats it).

Files written:
  square_41.msh          MSH 4.1 ASCII (with a $NodeData section to skip)
  square_41_bin.msh      MSH 4.1 binary, little-endian, size_t 8 (what Gmsh writes)
  square_41_bin_be.msh   MSH 4.1 binary, big-endian, size_t 4 (allowed by the format)
  square_22.msh          MSH 2.2 ASCII
  square_22_bin.msh      MSH 2.2 binary
  quads_41_bin.msh       as square, the right square one 4-node quadrilateral
  quads_22.msh           the same in MSH 2.2 ASCII
  partial_curve_41.msh   as square_41.msh (without $NodeData), plus physical curve
                         16 "cut" {c5, c7}: on the whole file's mesh c5 is boundary
                         but c7 is inside (an error); for each square alone both
                         lie on its boundary or belong to the other square
"""

import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
Z = 0.25

# node tag -> (x, y), in file order
NODES = [(1, (0.0, 0.0)), (2, (1.0, 0.0)), (3, (2.0, 0.0)), (40, (2.0, 1.0)),
         (5, (1.0, 1.0)), (60, (0.0, 1.0)), (100, (0.5, 0.5))]
# node blocks of MSH 4.1: (dim, entity, [node tags])
NODE_BLOCKS = [(0, 1, [1]), (0, 2, [2]), (0, 3, [3]), (0, 4, [40]), (0, 5, [5]),
               (0, 6, [60]), (2, 1, [100])]
# entities: points (tag, node), curves (tag, [bounding points]), surfaces (tag, [curves])
POINTS = [(1, 1), (2, 2), (3, 3), (4, 40), (5, 5), (6, 60)]
CURVES = [(1, [1, -2]), (2, [2, -3]), (3, [3, -4]), (4, [5, -4]), (5, [5, -6]),
          (6, [6, -1]), (7, [2, -5])]
SURFACES = [(1, [1, 7, 5, 6]), (2, [2, 3, -4, -7])]
PHYSICAL = {  # (dim, entity) -> physical tags
    (0, 1): [21],
    (1, 1): [11], (1, 2): [11], (1, 3): [13, 15], (1, 4): [12], (1, 5): [12],
    (1, 6): [15], (1, 7): [14],
    (2, 1): [1], (2, 2): [2],
}
NAMES = [(0, 21, "corner"), (1, 11, "bottom"), (1, 12, "top"), (1, 14, "interface"),
         (1, 15, "sides"), (2, 1, "left"), (2, 2, "right")]
# element blocks: (dim, entity, gmsh type, [(element tag, [node tags])])
LINES = [(1, 1, 1, [(201, [1, 2])]), (1, 2, 1, [(202, [2, 3])]),
         (1, 3, 1, [(203, [3, 40])]), (1, 4, 1, [(204, [5, 40])]),
         (1, 5, 1, [(205, [5, 60])]), (1, 6, 1, [(206, [60, 1])]),
         (1, 7, 1, [(207, [2, 5])])]
LEFT = (2, 1, 2, [(301, [1, 2, 100]), (302, [2, 5, 100]), (303, [5, 60, 100]),
                  (304, [60, 100, 1])])  # 304 is clockwise
RIGHT_TRI = (2, 2, 2, [(401, [2, 3, 40]), (402, [2, 5, 40])])  # 402 is clockwise
RIGHT_QUAD = (2, 2, 3, [(401, [2, 3, 40, 5])])
POINT = (0, 1, 15, [(501, [1])])


def element_blocks(quads):
    return [POINT] + LINES + [LEFT, RIGHT_QUAD if quads else RIGHT_TRI]


def bbox(node_tags):
    xy = dict(NODES)
    xs = [xy[n][0] for n in node_tags]
    ys = [xy[n][1] for n in node_tags]
    return [min(xs), min(ys), Z, max(xs), max(ys), Z]


def entity_boxes():
    curve_box = {}
    for (dim, ent, _, els) in LINES:
        curve_box[ent] = bbox([n for (_, ns) in els for n in ns])
    surf_box = {1: bbox([1, 2, 5, 60]), 2: bbox([2, 3, 40, 5])}
    return curve_box, surf_box


# partial_curve_41.msh: the same groups plus curve 16 "cut" = {c5, c7}.
PARTIAL_PHYSICAL = dict(PHYSICAL)
PARTIAL_PHYSICAL[(1, 5)] = [12, 16]
PARTIAL_PHYSICAL[(1, 7)] = [14, 16]
PARTIAL_NAMES = NAMES[:5] + [(1, 16, "cut")] + NAMES[5:]


def physical_names_ascii(names=NAMES):
    out = "$PhysicalNames\n%d\n" % len(names)
    for d, t, n in names:
        out += '%d %d "%s"\n' % (d, t, n)
    return out + "$EndPhysicalNames\n"


# ------------------------------------------------------------------ MSH 4.1

def msh41_ascii(quads=False, physical=PHYSICAL, names=NAMES, node_data=True):
    s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + physical_names_ascii(names)
    curve_box, surf_box = entity_boxes()
    s += "$Entities\n%d %d %d 0\n" % (len(POINTS), len(CURVES), len(SURFACES))
    xy = dict(NODES)
    for tag, node in POINTS:
        ph = physical.get((0, tag), [])
        s += "%d %r %r %r %d%s\n" % (tag, xy[node][0], xy[node][1], Z, len(ph),
                                     "".join(" %d" % p for p in ph))
    for dim, ents, boxes in ((1, CURVES, curve_box), (2, SURFACES, surf_box)):
        for tag, bounds in ents:
            ph = physical.get((dim, tag), [])
            s += "%d %s %d%s %d%s\n" % (tag, " ".join(repr(v) for v in boxes[tag]), len(ph),
                                        "".join(" %d" % p for p in ph), len(bounds),
                                        "".join(" %d" % b for b in bounds))
    s += "$EndEntities\n"
    tags = [t for t, _ in NODES]
    s += "$Nodes\n%d %d %d %d\n" % (len(NODE_BLOCKS), len(NODES), min(tags), max(tags))
    for dim, ent, ns in NODE_BLOCKS:
        s += "%d %d 0 %d\n" % (dim, ent, len(ns))
        s += "".join("%d\n" % n for n in ns)
        s += "".join("%r %r %r\n" % (xy[n][0], xy[n][1], Z) for n in ns)
    s += "$EndNodes\n"
    blocks = element_blocks(quads)
    etags = [t for b in blocks for t, _ in b[3]]
    s += "$Elements\n%d %d %d %d\n" % (len(blocks), len(etags), min(etags), max(etags))
    for dim, ent, typ, els in blocks:
        s += "%d %d %d %d\n" % (dim, ent, typ, len(els))
        for t, ns in els:
            s += "%d %s\n" % (t, " ".join(str(n) for n in ns))
    s += "$EndElements\n"
    if not node_data:
        return s.encode()
    # A section cfe does not read: skipped.
    s += '$NodeData\n1\n"displacement"\n1\n0.0\n3\n0\n1\n1\n1 0.5\n$EndNodeData\n'
    return s.encode()


def msh41_binary(quads=False, big_endian=False, size_t=8):
    e = ">" if big_endian else "<"
    z = "Q" if size_t == 8 else "I"
    i32 = lambda v: struct.pack(e + "i", v)
    sz = lambda v: struct.pack(e + z, v)
    f64 = lambda *v: struct.pack(e + "%dd" % len(v), *v)
    b = b"$MeshFormat\n4.1 1 %d\n" % size_t + i32(1) + b"\n$EndMeshFormat\n"
    b += physical_names_ascii().encode()
    curve_box, surf_box = entity_boxes()
    xy = dict(NODES)
    b += b"$Entities\n" + sz(len(POINTS)) + sz(len(CURVES)) + sz(len(SURFACES)) + sz(0)
    for tag, node in POINTS:
        ph = PHYSICAL.get((0, tag), [])
        b += i32(tag) + f64(xy[node][0], xy[node][1], Z) + sz(len(ph))
        b += b"".join(i32(p) for p in ph)
    for dim, ents, boxes in ((1, CURVES, curve_box), (2, SURFACES, surf_box)):
        for tag, bounds in ents:
            ph = PHYSICAL.get((dim, tag), [])
            b += i32(tag) + f64(*boxes[tag]) + sz(len(ph)) + b"".join(i32(p) for p in ph)
            b += sz(len(bounds)) + b"".join(i32(x) for x in bounds)
    b += b"\n$EndEntities\n"
    tags = [t for t, _ in NODES]
    b += b"$Nodes\n" + sz(len(NODE_BLOCKS)) + sz(len(NODES)) + sz(min(tags)) + sz(max(tags))
    for dim, ent, ns in NODE_BLOCKS:
        b += i32(dim) + i32(ent) + i32(0) + sz(len(ns))
        b += b"".join(sz(n) for n in ns)
        b += b"".join(f64(xy[n][0], xy[n][1], Z) for n in ns)
    b += b"\n$EndNodes\n"
    blocks = element_blocks(quads)
    etags = [t for blk in blocks for t, _ in blk[3]]
    b += b"$Elements\n" + sz(len(blocks)) + sz(len(etags)) + sz(min(etags)) + sz(max(etags))
    for dim, ent, typ, els in blocks:
        b += i32(dim) + i32(ent) + i32(typ) + sz(len(els))
        for t, ns in els:
            b += sz(t) + b"".join(sz(n) for n in ns)
    b += b"\n$EndElements\n"
    # A binary section cfe does not read: skipped.
    b += b"$Custom\n" + bytes(range(256)) + b"\n$EndCustom\n"
    return b


# ------------------------------------------------------------------ MSH 2.2

def elements_22(quads):
    """(element tag, type, [physical, elementary], nodes), an element repeated once
    per physical group as Gmsh writes MSH 2.2 (the repeats get new tags)."""
    out = []
    extra = 600
    for dim, ent, typ, els in element_blocks(quads):
        for t, ns in els:
            for k, p in enumerate(PHYSICAL.get((dim, ent), [0])):
                tag = t if k == 0 else extra
                extra += k > 0
                out.append((tag, typ, [p, ent], ns))
    return out


def msh22_ascii(quads=False):
    s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" + physical_names_ascii()
    s += "$Nodes\n%d\n" % len(NODES)
    s += "".join("%d %r %r %r\n" % (t, x, y, Z) for t, (x, y) in NODES)
    s += "$EndNodes\n"
    els = elements_22(quads)
    s += "$Elements\n%d\n" % len(els)
    for t, typ, tags, ns in els:
        s += "%d %d %d %s %s\n" % (t, typ, len(tags), " ".join(map(str, tags)),
                                   " ".join(map(str, ns)))
    s += "$EndElements\n"
    s += '$Comments\nwritten by make_msh.py\n$EndComments\n'
    return s.encode()


def msh22_binary(quads=False):
    i32 = lambda *v: struct.pack("<%di" % len(v), *v)
    b = b"$MeshFormat\n2.2 1 8\n" + i32(1) + b"\n$EndMeshFormat\n"
    b += physical_names_ascii().encode()
    b += b"$Nodes\n%d\n" % len(NODES)
    b += b"".join(i32(t) + struct.pack("<3d", x, y, Z) for t, (x, y) in NODES)
    b += b"\n$EndNodes\n"
    els = elements_22(quads)
    b += b"$Elements\n%d\n" % len(els)
    # One header per run of elements of the same type and number of tags.
    k = 0
    while k < len(els):
        j = k
        while j < len(els) and els[j][1] == els[k][1] and len(els[j][2]) == len(els[k][2]):
            j += 1
        b += i32(els[k][1], j - k, len(els[k][2]))
        for t, typ, tags, ns in els[k:j]:
            b += i32(t, *tags, *ns)
        k = j
    b += b"\n$EndElements\n"
    return b


def main():
    files = {
        "square_41.msh": msh41_ascii(),
        "square_41_bin.msh": msh41_binary(),
        "square_41_bin_be.msh": msh41_binary(big_endian=True, size_t=4),
        "square_22.msh": msh22_ascii(),
        "square_22_bin.msh": msh22_binary(),
        "quads_41_bin.msh": msh41_binary(quads=True),
        "quads_22.msh": msh22_ascii(quads=True),
        "partial_curve_41.msh": msh41_ascii(physical=PARTIAL_PHYSICAL, names=PARTIAL_NAMES,
                                            node_data=False),
    }
    for name, data in files.items():
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(data)
        print("wrote", name, len(data), "bytes")


if __name__ == "__main__":
    main()
