"""A model meshed with the Gmsh Python API: the seed's plate on a base, each part
meshed on its own (unstructured triangles, or quadrilaterals with --quads), the
base coarse (10 mm) and the plate fine (2.5 mm), handed to cfe as arrays.

    pip install gmsh
    python examples/python/gmsh_model.py [--quads] [--out gmsh_model.png]

The two rectangles are separate Gmsh surfaces that share no curve, so their nodes
on the common face y = 120 are independent: the plate's become the coupling nodes
on the base's edges. Prints the contact pattern; with Matplotlib installed, plots
the plate's vertical displacement along the interface.
"""

import argparse

import numpy as np

import cfe


def mesh_parts(quads):
    """Meshes the base and the plate with Gmsh; returns each part's arrays."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        base = occ.addRectangle(0.0, 0.0, 0.0, 200.0, 120.0)
        plate = occ.addRectangle(30.0, 120.0, 0.0, 140.0, 15.0)
        occ.synchronize()
        for surface, size in ((base, 10.0), (plate, 2.5)):
            points = gmsh.model.getBoundary([(2, surface)], recursive=True)
            gmsh.model.mesh.setSize(points, size)
            if quads:
                gmsh.model.mesh.setRecombine(2, surface)

        def curve(x0, y0, x1, y1):
            """The one curve inside the box [x0, x1] × [y0, y1]."""
            eps = 1e-6
            found = gmsh.model.getEntitiesInBoundingBox(x0 - eps, y0 - eps, -eps, x1 + eps, y1 + eps, eps, 1)
            assert len(found) == 1, found
            return found[0][1]

        curves = {
            "base": {"bottom": curve(0, 0, 200, 0)},
            "plate": {"bottom": curve(30, 120, 170, 120), "top": curve(30, 135, 170, 135)},
        }
        # Physical groups too, so that `gmsh.write("plate_on_base.msh")` would make a
        # file the problem-file's `gmsh` key (or meshio) reads with these names.
        for name, surface in (("base", base), ("plate", plate)):
            gmsh.model.addPhysicalGroup(2, [surface], name=name)
        gmsh.model.mesh.generate(2)

        tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = dict(zip(tags.tolist(), coords.reshape(-1, 3)[:, :2]))
        parts = {}
        for name, surface in (("base", base), ("plate", plate)):
            kinds, _, nodes = gmsh.model.mesh.getElements(2, surface)
            cells = {int(k): np.asarray(n, dtype=np.int64) for k, n in zip(kinds, nodes)}
            tri = cells.get(2, np.zeros(0, dtype=np.int64)).reshape(-1, 3)  # 3-node triangles
            quad = cells.get(3, np.zeros(0, dtype=np.int64)).reshape(-1, 4)  # 4-node quadrangles
            used = np.unique(np.concatenate([tri.ravel(), quad.ravel()]))
            local = {t: i for i, t in enumerate(used.tolist())}
            renumber = np.vectorize(local.__getitem__, otypes=[np.int64])
            boundaries = {}
            for bname, c in curves[name].items():
                kinds, _, nodes = gmsh.model.mesh.getElements(1, c)
                lines = np.asarray(nodes[list(kinds).index(1)], dtype=np.int64).reshape(-1, 2)
                boundaries[bname] = renumber(lines)
            parts[name] = {
                "points": np.array([xy[t] for t in used.tolist()]),
                "triangles": renumber(tri) if len(tri) else None,
                "quads": renumber(quad) if len(quad) else None,
                "boundaries": boundaries,
            }
        return parts
    finally:
        gmsh.finalize()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quads", action="store_true", help="recombine into quadrilaterals (Q4)")
    parser.add_argument("--out", default="gmsh_model.png", help="the plot (needs Matplotlib)")
    args = parser.parse_args()

    parts = mesh_parts(args.quads)
    model = cfe.Model(
        {
            "title": "Plate on a base, meshed with the Gmsh API",
            "materials": {"steel": {"E": 210000.0, "nu": 0.31}},
            "part": [
                {"name": "base", "material": "steel", **parts["base"]},
                {"name": "plate", "material": "steel", **parts["plate"]},
            ],
            "interface": [{"name": "contact", "host": "base", "nodes": "plate", "boundary": "bottom",
                           "c_n": 1e9, "c_s": 1e9}],
            "support": [{"part": "base", "boundary": "bottom", "fix": ["x", "y"]}],
            "load": [{"part": "plate", "boundary": "top", "from": [86.0, 135.0], "to": [114.0, 135.0],
                      "force": [0.0, -1500.0]}],
        }
    )
    print(model.check())
    result = model.solve()
    pairs = result.interfaces["contact"]
    order = np.argsort(pairs.x)
    print("pairs along the interface (x: state):")
    print("  " + " ".join(f"{x:.0f}:{'B' if b else 'o'}" for x, b in zip(pairs.x[order], pairs.bonded[order])))
    md = result.max_displacement
    print(f"max |u| = {md['value']:.6e} at ({md['x']:.3f}, {md['y']:.3f}) in part '{md['part']}'")
    print(f"reaction of the base: {result.reactions['base/bottom']}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("Matplotlib is not installed: no plot")
        return
    plate = result.parts["plate"]
    bottom = plate.boundary_nodes("bottom")
    bottom = bottom[np.argsort(plate.points[bottom, 0])]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(plate.points[bottom, 0], plate.uy[bottom], "o-", ms=3)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("uy of the plate's bottom (mm)")
    ax.set_title("Gmsh-meshed plate on a base")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
