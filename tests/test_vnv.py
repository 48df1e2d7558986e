"""VnV: hand-counted tallies, naive == fast, intended == reference, literal's disagreement."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import closed_meshes, examples, lights_for
from test_engines import facing, reference_edges

import silcount

# One counted visibility test (base.counted_visibility), counted by reading the code:
# reads: face_start[p] 1 + three corner indices 3 + nine coordinates 9 + three light values 3 = 16;
# adds: e1 3 + e2 3 + the cross product's three differences 3 + (L - p0) 3 + the dot product's 2 = 14
# (a directional light skips L - p0: 11); muls: cross 6 + dot 3 = 9; one compare with 0.
VIS_POINT = {"add": 14, "mul": 9, "cmp": 1, "read": 16}
VIS_DIRECTIONAL = {"add": 11, "mul": 9, "cmp": 1, "read": 16}
# The papers' annotation of the same step (silcount/models/eesd2012-vnv.toml, Sec. 5.2): 8A + 10M + 1C + 8R.


def tally(*parts):
    out = {"add": 0, "mul": 0, "cmp": 0, "read": 0, "write": 0}
    for times, cost in parts:
        for k, v in cost.items():
            out[k] += times * v
    return out


def both_engines(mesh, light, variant):
    a = silcount.detect(mesh, light, "vnv", variant, "fast")
    b = silcount.detect(mesh, light, "vnv", variant, "naive")
    assert np.array_equal(a.edges, b.edges) and np.array_equal(a.oriented, b.oriented)
    assert a.steps == b.steps and a.tally == b.tally
    return a


def test_tetrahedron_intended_by_hand():
    # Light at (5,5,5): the three faces around vertex (1,1,1) face it, the base (0,2,1) does not.
    # Silhouette: the base's edges [0,1], [0,2], [1,2] = ids 0, 1, 3.
    m = silcount.builtin_mesh("tetrahedron")
    res = both_engines(m, silcount.PointLight((5.0, 5.0, 5.0)), "intended")
    assert res.edge_ids.tolist() == [0, 1, 3]
    # E = 6, F = 4: 24 visibility tests.  3 facing faces x 6 edges = 18 containment scans.
    # Each facing triangle: the 3 edges it lacks examine 3 sides each (9), its own 3 are found
    # after 1, 2, 3 sides (6): 15 sides per face, 45 in all.  Counter: 3 sides x 3 faces = 9.
    assert res.steps == {"visibility": 24, "contains": 18, "counter": 9, "check_counter": 6, "add": 3}
    assert res.tally["true"] == tally(
        (24, VIS_POINT),
        (18, {"read": 2}),
        (45, {"read": 1, "cmp": 1}),
        (9, {"add": 1}),
        (6, {"cmp": 1}),
        (3, {"write": 1}),
    )
    assert res.tally["true"] == {"add": 345, "mul": 216, "cmp": 75, "read": 465, "write": 3}
    # paper: 24 x (8A+10M+1C+8R) + 9 x 1A + 6 x (1C+1R) + 3 x 1W
    assert res.tally["paper"] == {"add": 201, "mul": 240, "cmp": 30, "read": 198, "write": 3}


def test_tetrahedron_literal_by_hand():
    # Never reset, never checks containment: the counter reads 3, 6, ..., 18 after the edges: never 1.
    m = silcount.builtin_mesh("tetrahedron")
    res = both_engines(m, silcount.PointLight((5.0, 5.0, 5.0)), "literal")
    assert res.n_edges == 0 and res.agreement["missed_edges"] == 3
    assert res.steps == {"visibility": 24, "counter": 18, "check_counter": 6, "add": 0}
    assert res.tally["true"] == {"add": 24 * 14 + 18, "mul": 216, "cmp": 24 + 6, "read": 24 * 16, "write": 0}
    assert res.tally["paper"] == {"add": 24 * 8 + 18, "mul": 240, "cmp": 24 + 6, "read": 24 * 8 + 6, "write": 0}


def test_quad_cube_by_hand():
    # Light far above: only the top face (vertices 1,3,7,5; 4 sides) faces it.
    m = silcount.builtin_mesh("quad_cube")
    for light, vis in (
        (silcount.PointLight((0.0, 0.0, 10.0)), VIS_POINT),
        (silcount.DirectionalLight((0.0, 0.0, 1.0)), VIS_DIRECTIONAL),
    ):
        res = both_engines(m, light, "intended")
        assert {tuple(e) for e in res.edges.tolist()} == {(1, 3), (1, 5), (3, 7), (5, 7)}
        # 12 x 6 = 72 visibility tests; 12 containment scans of the top face: the 8 edges it lacks
        # examine 4 sides each (32), its own 4 are found after 1+2+3+4 = 10: 42 sides.
        assert res.steps == {"visibility": 72, "contains": 12, "counter": 4, "check_counter": 12, "add": 4}
        assert res.tally["true"] == tally(
            (72, vis),
            (12, {"read": 2}),
            (42, {"read": 1, "cmp": 1}),
            (4, {"add": 1}),
            (12, {"cmp": 1}),
            (4, {"write": 1}),
        )
        assert res.tally["paper"] == {"add": 576 + 4, "mul": 720, "cmp": 72 + 12, "read": 576 + 12, "write": 4}
    # literal, one facing face: the counter is 1 after the first edge only, so edge 0 = [0,1]
    # (a bottom-left edge, not on the top face) is reported and the 4 true ones are missed.
    res = both_engines(m, silcount.PointLight((0.0, 0.0, 10.0)), "literal")
    assert res.edges.tolist() == [[0, 1]]
    assert res.agreement["missed_edges"] == 4 and res.agreement["extra_edges"] == 1
    assert res.notes["reset_reading_edges"] == 12
    assert res.steps == {"visibility": 72, "counter": 12, "check_counter": 12, "add": 1}


small_meshes = closed_meshes().filter(lambda m: m.n_faces <= 130)


@settings(max_examples=examples(12), deadline=None)
@given(data=st.data(), variant=st.sampled_from(["intended", "literal"]))
def test_naive_equals_fast(data, variant):
    mesh = data.draw(small_meshes)
    both_engines(mesh, data.draw(lights_for(mesh)), variant)


@settings(max_examples=examples(40), deadline=None)
@given(data=st.data())
def test_intended_equals_reference_and_literal_disagrees(data):
    mesh = data.draw(closed_meshes())
    light = data.draw(lights_for(mesh))
    ref = silcount.detect(mesh, light, "reference")
    res = silcount.detect(mesh, light, "vnv", "intended")
    assert np.array_equal(res.edges, ref.edges) and np.array_equal(res.oriented, ref.oriented)
    lit = silcount.detect(mesh, light, "vnv", "literal")
    flags = facing(mesh, light)[0]  # computed in the test, not by the package's kernel
    n_facing = sum(flags)
    assert {tuple(e) for e in res.edges.tolist()} == reference_edges(mesh, flags)
    # counter never reset: after edge e (1-based) it holds e * n_facing, so it is 1 only after the
    # first edge and only when exactly one face faces the light
    assert lit.steps["counter"] == mesh.n_edges * n_facing
    assert lit.edge_ids.tolist() == ([0] if n_facing == 1 else [])
    # the reference has at least 3 edges on a closed mesh lit from outside: literal misses them (all, or all
    # but edge 0) and reports edge 0 only when it is not one of them
    assert ref.n_edges >= 3
    in_ref = 0 in ref.edge_ids.tolist()
    if n_facing == 1:
        assert (lit.agreement["missed_edges"], lit.agreement["extra_edges"]) == (ref.n_edges - in_ref, 1 - in_ref)
    else:
        assert (lit.agreement["missed_edges"], lit.agreement["extra_edges"]) == (ref.n_edges, 0)


def test_open_triangle_soup(shared_mesh):
    # every edge of a soup is a boundary edge: intended reports those of light-facing triangles
    soup = shared_mesh("soup.stl")
    light = silcount.DirectionalLight((0.2, -0.5, 1.0))
    res = both_engines(soup, light, "intended")
    assert np.array_equal(res.edges, silcount.detect(soup, light, "reference").edges)
    # independently: a soup triangle's three edges are silhouette edges iff it faces the light
    flags = facing(soup, light)[0]
    assert res.n_edges == 3 * sum(flags) and 0 < sum(flags) < soup.n_faces
    lit = both_engines(soup, light, "literal")  # many lit faces: the never-reset counter passes 1 before edge 0 ends
    assert lit.n_edges == 0 and lit.steps["counter"] == soup.n_edges * sum(flags)


def test_defaults_and_engine_dispatch(monkeypatch):
    # vnv.detect called directly: intended and fast by default; "naive" runs the counted loop, anything else the fast
    from silcount.detectors import vnv

    m = silcount.builtin_mesh("tetrahedron")
    light = silcount.PointLight((5.0, 5.0, 5.0))
    default = vnv.detect(m, light)
    assert (default.variant, default.engine) == ("intended", "fast") and default.edge_ids.tolist() == [0, 1, 3]

    def refuse(*args):
        raise AssertionError("wrong engine")

    with monkeypatch.context() as mp:
        mp.setattr(vnv, "_naive", refuse)
        assert vnv.detect(m, light, engine="fast").edge_ids.tolist() == [0, 1, 3]
    with monkeypatch.context() as mp:
        mp.setattr(vnv, "_fast", refuse)
        assert vnv.detect(m, light, engine="naive").edge_ids.tolist() == [0, 1, 3]
