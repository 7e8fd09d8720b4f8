"""Problem texts shared by the Python tests (the Rust tests build the same
problems with `Problem` in crates/cfe/tests/common/mod.rs)."""


def block_on_base(iface, tail, base_cells=(5, 3), block_cells=(4, 4)):
    """A unit block (node part, x ∈ [0, 1], y ∈ [0, 1]) on a wider base (host,
    x ∈ [−0.5, 1.5], y ∈ [−1, 0], its bottom clamped), non-matching meshes of
    `base_cells` and `block_cells`, both steel (E = 1000, ν = 0.3), plane stress;
    `iface` holds the interface's keys (its law), `tail` the block's supports and
    loads and the analysis."""
    return f"""
plane = "stress"
[materials.steel]
E = 1000.0
nu = 0.3
[[part]]
name = "base"
material = "steel"
rectangle = {{ x = [-0.5, 1.5], y = [-1.0, 0.0], cells = [{base_cells[0]}, {base_cells[1]}] }}
[[part]]
name = "block"
material = "steel"
rectangle = {{ x = [0.0, 1.0], y = [0.0, 1.0], cells = [{block_cells[0]}, {block_cells[1]}] }}
[[interface]]
host = "base"
nodes = "block"
boundary = "bottom"
{iface}
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
{tail}
"""


def interference_fit(thickness=None):
    """A block (node part, soft: E = 1000, ν = 0.3, x ∈ [0, 1], height L = 10,
    4 × 8 Q4) pressed by an interference δ = 0.01 (its bottom at y = −δ, found
    within the search distance 0.05) onto a thin, stiff (E = 1e6), rigidly
    supported base layer (host, y ∈ [−0.1, 0], 5 × 1 Q4), its top held in y and
    one top corner in x, frictionless, one increment: p = E δ / L on every pair
    (plane stress). The interface is named "fit"; both parts are `thickness`
    thick when given."""
    t = "" if thickness is None else f"thickness = {thickness}\n"
    return f"""
plane = "stress"
[materials.soft]
E = 1000.0
nu = 0.3
[materials.hard]
E = 1.0e6
nu = 0.3
[[part]]
name = "base"
material = "hard"
{t}rectangle = {{ x = [-0.5, 1.5], y = [-0.1, 0.0], cells = [5, 1], elements = "q4" }}
[[part]]
name = "block"
material = "soft"
{t}rectangle = {{ x = [0.0, 1.0], y = [-0.01, 9.99], cells = [4, 8], elements = "q4" }}
[[interface]]
name = "fit"
host = "base"
nodes = "block"
boundary = "bottom"
law = "frictionless"
search_distance = 0.05
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
[[support]]
part = "block"
boundary = "top"
fix = ["y"]
[[support]]
part = "block"
at = [0.0, 9.99]
fix = ["x"]
[analysis]
increments = 1
"""
