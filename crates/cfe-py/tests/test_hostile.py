"""Hostile Python input raises a Python exception naming what is wrong; it never
kills the interpreter (segfault, abort on a failed allocation) nor hangs.

The cases that used to kill the interpreter run in a child interpreter, so that a
regression fails its test instead of ending the test session: the child must exit
normally (return code 0) having caught the expected exception."""

import inspect
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import cfe

# ---------------------------------------------------------------- helpers


def problem(**part):
    p = {"name": "a", "material": "m"}
    p.update(part)
    return {
        "materials": {"m": {"E": 1.0, "nu": 0.3}},
        "part": [p],
        "support": [{"part": "a", "boundary": "bottom", "fix": ["x", "y"]}],
    }


#: Prelude of every child: a valid one-part problem whose mesh is given as arrays
#: (`problem` as above).
PRELUDE = """
import itertools
import numpy as np
import cfe

pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
tri = np.array([[0, 1, 2], [0, 2, 3]])
bnd = {"bottom": np.array([[0, 1]])}

""" + inspect.getsource(problem)

# The child prints the exception's class and message; anything else is a failure.
CHILD = """
{prelude}
{setup}
try:
    {call}
except Exception as e:
    print("raised", type(e).__name__, str(e)[:400])
else:
    print("returned")
"""


def in_child(setup, call, timeout=120):
    """Runs `setup` then `call` in a fresh interpreter; returns what it printed.
    The child must end normally within `timeout` s (a liveness bound, far above
    the fraction of a second these take)."""
    code = CHILD.format(prelude=PRELUDE, setup=textwrap.dedent(setup), call=call)
    r = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout
    )
    assert r.returncode == 0, f"the interpreter died ({r.returncode}): {r.stderr[-2000:]}"
    return r.stdout.strip()


def raises_in_child(setup, call, kind, *words):
    out = in_child(setup, call)
    assert out.startswith(f"raised {kind} "), out
    for w in words:
        assert w in out, out


PTS = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
TRI = np.array([[0, 1, 2], [0, 2, 3]])
BND = {"bottom": np.array([[0, 1]])}

# ------------------------------------- cases that used to kill the interpreter


def test_a_dict_containing_itself():
    raises_in_child("d = problem(); d['analysis'] = d", "cfe.Model(d)", "ValueError", "`analysis.analysis`", "contains itself")


def test_a_list_containing_itself():
    raises_in_child(
        "l = [1.0]; l.append(l); d = problem(); d['materials']['m']['E'] = l",
        "cfe.Model(d)",
        "ValueError",
        "`materials.m.E[1]`",
        "contains itself",
    )


def test_a_cycle_through_another_container():
    raises_in_child(
        "a = {}; b = [a]; a['x'] = b",
        "cfe.Model({'title': 't', 'analysis': a})",
        "ValueError",
        "`analysis.x[0]`",
        "contains itself",
    )


def test_dicts_nested_100_000_deep():
    raises_in_child(
        """
        d = {}
        c = d
        for _ in range(100_000):
            c["x"] = {}
            c = c["x"]
        """,
        "cfe.Model({'title': 't', 'analysis': d})",
        "ValueError",
        "nested deeper than 64 levels",
        "`analysis.x.x",
    )


def test_lists_nested_100_000_deep():
    raises_in_child(
        """
        l = []
        c = l
        for _ in range(100_000):
            n = []
            c.append(n)
            c = n
        """,
        "cfe.Model({'title': l})",
        "ValueError",
        "nested deeper than 64 levels",
        "`title[0][0]",
    )


def test_tolist_returning_itself():
    raises_in_child(
        """
        class Selfish:
            def tolist(self):
                return self
        """,
        "cfe.Model({'title': Selfish()})",
        "ValueError",
        "`title`",
        "contains itself",
    )


def test_fspath_returning_itself():
    raises_in_child(
        """
        class Selfish:
            def __fspath__(self):
                return self
        """,
        "cfe.Model({'title': Selfish()})",
        "ValueError",
        "contains itself",
    )


def test_tolist_returning_a_new_array_like_forever():
    raises_in_child(
        """
        class Endless:
            def tolist(self):
                return Endless()
        """,
        "cfe.Model({'title': Endless()})",
        "ValueError",
        "nested deeper than 64 levels",
    )


def test_refine_of_array_meshes_beyond_memory():
    """Refining given meshes 10⁶ times (about 8·10¹² unknowns) is refused by the
    same size check as structured parts, before any allocation."""
    raises_in_child(
        "",
        "cfe.Model(problem(points=pts, triangles=tri, boundaries=bnd), refine=10**6)",
        "TooLargeError",
        "at refinement 1000000",
        "GiB of memory are available",
    )


def test_refine_of_a_cfe_mesh_beyond_memory():
    raises_in_child(
        "m = cfe.Mesh(pts, tri, boundaries=bnd)",
        "cfe.Model(problem(mesh=m), refine=10**6)",
        "TooLargeError",
        "at refinement 1000000",
    )


def test_refine_of_a_meshio_mesh_beyond_memory():
    pytest.importorskip("meshio")
    raises_in_child(
        "m = cfe.Mesh(pts, tri, boundaries=bnd).to_meshio()",
        "cfe.Model(problem(mesh=m), refine=10**6)",
        "TooLargeError",
        "at refinement 1000000",
    )


def test_refine_of_given_meshes_whose_size_overflows():
    """A factor whose refined node count overflows 64 bits (checked arithmetic)."""
    raises_in_child(
        "",
        "cfe.Model(problem(points=pts, triangles=tri, boundaries=bnd), refine=2**63)",
        "TooLargeError",
        "at refinement 9223372036854775808",
    )


def test_a_list_whose_iter_never_ends():
    """A list subclass is converted by its own items: an overridden, endless
    `__iter__` is not called (no hang)."""
    out = in_child(
        """
        class Endless(list):
            def __iter__(self):
                return itertools.count()
        """,
        "print(cfe._cfe.dict_to_toml({'a': Endless([1, 2])}))",
    )
    assert [l for l in out.splitlines() if l] == ["a = [1, 2]", "returned"], out


def test_tolist_that_empties_the_dict_being_read():
    """A value's `tolist()` clearing the dict being converted does not upset the
    walk (it reads a snapshot of the items)."""
    out = in_child(
        """
        d = {}
        class Clears:
            def tolist(self):
                d.clear()
                return 1
        d["a"] = Clears()
        d["b"] = 2
        """,
        "print(cfe._cfe.dict_to_toml(d))",
    )
    assert [l for l in out.splitlines() if l] == ["a = 1", "b = 2", "returned"], out


# ---------------------------------------------------------------- plain raises


@pytest.mark.parametrize("refine", [-1, 10**30])
def test_refine_out_of_range(refine):
    with pytest.raises(OverflowError):
        cfe.Model(problem(points=PTS, triangles=TRI, boundaries=BND), refine=refine)


def test_refine_zero():
    with pytest.raises(cfe.ModelError, match="at least 1"):
        cfe.Model(problem(points=PTS, triangles=TRI, boundaries=BND), refine=0)


def test_a_huge_integer_value():
    with pytest.raises(cfe.ParseError, match="`analysis.increments`: integer out of range"):
        cfe.Model({**problem(points=PTS, triangles=TRI, boundaries=BND), "analysis": {"increments": 10**100}})


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_points(bad):
    p = PTS.copy()
    p[2, 1] = bad
    with pytest.raises(cfe.MeshError, match="node 2 has a non-finite coordinate"):
        cfe.Mesh(p, TRI, boundaries=BND)


def test_non_finite_material_value():
    d = problem(points=PTS, triangles=TRI, boundaries=BND)
    d["materials"]["m"]["E"] = float("nan")
    with pytest.raises(cfe.ModelError, match="materials.m.E"):
        cfe.Model(d)


def test_negative_index():
    with pytest.raises(cfe.MeshError, match="negative node index -2"):
        cfe.Mesh(PTS, np.array([[0, 1, -2]]))


@pytest.mark.parametrize("i", [4, 2**40, 2**63 - 1])
def test_index_out_of_range(i):
    with pytest.raises(cfe.MeshError, match=f"uses node {i}, but the part has 4 nodes"):
        cfe.Mesh(PTS, np.array([[0, 1, i]]))


def test_boundary_index_out_of_range():
    with pytest.raises(cfe.MeshError, match="uses a node out of range"):
        cfe.Mesh(PTS, TRI, boundaries={"b": np.array([[0, 10**12]])})


@pytest.mark.parametrize(
    "indices", [np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), np.array([[0.0, 1.0, 1e30]])]
)
def test_indices_beyond_int64(indices):
    """Values int64 cannot hold are refused, not wrapped to other indices."""
    with pytest.raises(cfe.MeshError, match="beyond the int64 range"):
        cfe.Mesh(PTS, indices)


@pytest.mark.parametrize(
    "points, triangles, message",
    [
        (PTS, np.array([0, 1, 2]), r"`triangles` must have shape \(n, 3\), got \[3\]"),
        (PTS[None], TRI, r"`points` must have shape \(n, 2\), got \[1, 4, 2\]"),
        (np.zeros((4, 1)), TRI, r"`points` must have shape \(n, 2\), got \[4, 1\]"),
        (PTS, np.zeros((0, 3), dtype=np.int64), "no elements"),
        (np.zeros((0, 2)), TRI, "uses node 0, but the part has 0 nodes"),
        ([["a", "b"]], TRI, "`points` must be an array of numbers"),
        (PTS, np.array([["x", "y", "z"]]), "`triangles` must be an array of node indices"),
        (PTS, np.array([[0, 1, 2.5]]), "non-integer values"),
    ],
)
def test_bad_shapes_types_and_empty_arrays(points, triangles, message):
    with pytest.raises(cfe.MeshError, match=message):
        cfe.Mesh(points, triangles)


def test_wrong_dtype_to_the_native_mesh():
    with pytest.raises(cfe.MeshError, match="`points` must be a NumPy array of f64"):
        cfe._cfe.Mesh(PTS.astype(np.float32), TRI)


def test_non_contiguous_arrays_give_the_same_mesh():
    """Fortran-ordered and strided views are read by their values."""
    wide = np.zeros((4, 4))
    wide[:, ::2] = PTS
    m = cfe._cfe.Mesh(
        wide[:, ::2], np.asfortranarray(TRI.astype(np.int64)), None, {"bottom": np.array([[0, 9, 1]])[:, ::2]}
    )
    ref = cfe.Mesh(PTS, TRI, boundaries=BND)
    np.testing.assert_array_equal(m.points, ref.points)
    np.testing.assert_array_equal(m.triangles, ref.triangles)
    np.testing.assert_array_equal(m.boundaries["bottom"], ref.boundaries["bottom"])


def test_a_sequence_raising_in_iter():
    class Raising(list):
        def __iter__(self):
            raise RuntimeError("no iteration")

    d = problem(points=PTS, triangles=TRI, boundaries=BND)
    d["part"] = Raising(d["part"])
    with pytest.raises(RuntimeError, match="no iteration"):
        cfe.Model(d)


def test_a_mapping_raising_in_len_and_iter():
    from collections.abc import Mapping

    class Raising(Mapping):
        def __getitem__(self, key):
            raise KeyError(key)

        def __len__(self):
            raise RuntimeError("no length")

        def __iter__(self):
            raise RuntimeError("no iteration")

    with pytest.raises(RuntimeError, match="no (length|iteration)"):
        cfe.Model(Raising())


def test_nul_in_strings():
    """NUL in a key, a value, a part name or a path is an ordinary error."""
    with pytest.raises(cfe.ParseError, match="unknown field"):
        cfe.Model({"ti\0tle": "t"})
    with pytest.raises(cfe.ParseError, match="NUL"):
        cfe.Model.from_file("a\0b.toml")
    d = problem(points=PTS, triangles=TRI, boundaries=BND)
    d["part"][0]["material"] = "m\0"
    with pytest.raises(cfe.ParseError):
        cfe.Model(d)
    model = cfe.Model(problem(points=PTS, triangles=TRI, boundaries=BND))
    with pytest.raises(cfe.ModelError, match="no part named"):
        model.mesh("a\0")


def test_unencodable_string():
    with pytest.raises(UnicodeEncodeError):
        cfe.Model({"title": "\ud800"})


def test_non_string_key():
    with pytest.raises(cfe.ParseError, match="keys must be strings"):
        cfe.Model({1: 2})


@pytest.mark.parametrize("write_every", [10**30, -1, 0, 2.5, True])
def test_write_every_out_of_range(write_every):
    model = cfe.Model(problem(points=PTS, triangles=TRI, boundaries=BND))
    with pytest.raises(cfe.ModelError, match="write_every"):
        model.solve(write_every=write_every)


@pytest.mark.parametrize("mu", [float("nan"), float("inf"), -1.0])
def test_friction_out_of_range(mu):
    model = cfe.Model(problem(points=PTS, triangles=TRI, boundaries=BND))
    with pytest.raises(cfe.ModelError, match="friction coefficient"):
        model.solve(law="coulomb", friction=mu)
