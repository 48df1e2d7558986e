"""The coplanar merge's ``true`` tally observed: the counted form (``coplanar_counted``) equals ``coplanar.merge``.

The counted form executes the exact merge one scalar at a time on counting
arithmetic with exact rationals (``fractions.Fraction``), so its tally is what
it did, not a cost table times step counts.  Expected values for the
triangle cube are a hand count.
"""

from __future__ import annotations

import numpy as np
from coplanar_counted import merge_counted
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import any_meshes, boxes, examples, extrusions, lattice_hulls

import silcount
from silcount.mesh.coplanar import merge
from silcount.mesh.model import from_polygons


def nonzero(d: dict) -> dict:
    return {k: int(v) for k, v in d.items() if v}


def assert_same(mesh) -> None:
    fast, naive = merge(mesh, "tight"), merge_counted(mesh)
    assert np.array_equal(fast.region, naive.region)
    assert np.array_equal(fast.rep, naive.rep)
    assert np.array_equal(fast.poly_start, naive.poly_start)
    assert np.array_equal(fast.poly_sides, naive.poly_sides)
    assert np.array_equal(fast.interior, naive.interior)
    assert nonzero(fast.steps) == nonzero(naive.steps)
    assert nonzero(fast.true) == nonzero(naive.true)


def test_triangle_cube_by_hand():
    # 12 triangles, 18 edges, every edge two-sided and traversed both ways: 18 candidates (4 R, 2 C each).
    # Two triangles: one test each, the far corner of g against f's plane (12 R, 19 A, 19 M, 1 C): 18 tests.
    # The 6 diagonals are exactly coplanar (det = 0 is within any bound): 6 exact tests (12 R, 14 A, 9 M, 1 C);
    # the 12 cube edges have |det| = 1 > bound.  6 normal checks (6 R, 2 A, 3 M, 1 C) need the exact normals
    # of all 12 faces (9 R, 9 A, 6 M); all 6 pass: 6 links (2 R, 1 C); 12 labels (1 W).
    m = silcount.builtin_mesh("triangle_cube")
    steps = {
        "candidate_edge": 18,
        "orient3d_filter": 18,
        "orient3d_exact": 6,
        "normal_check": 6,
        "exact_normal": 12,
        "link": 6,
        "label": 12,
    }
    true = {
        "read": 18 * 4 + 18 * 12 + 6 * 12 + 12 * 9 + 6 * 6 + 6 * 2,
        "add": 18 * 19 + 6 * 14 + 12 * 9 + 6 * 2,
        "mul": 18 * 19 + 6 * 9 + 12 * 6 + 6 * 3,
        "cmp": 18 * 2 + 18 + 6 + 6 + 6,
        "write": 12,
    }
    assert true == {"read": 516, "add": 546, "mul": 486, "cmp": 72, "write": 12}
    for mg in (merge_counted(m), merge(m, "tight")):
        assert nonzero(mg.steps) == steps and nonzero(mg.true) == true
        assert mg.rep.size == 6 and int(mg.interior.sum()) == 6
        assert np.diff(mg.poly_start).tolist() == [4] * 6


def test_quad_and_triangle_on_one_plane_both_ways_round():
    # a unit square (quad) with a triangle beside it on z = 0 (merged) and one folded up (not merged); a
    # quad-triangle pair is tested one way round, the quad's corners against the triangle's plane
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0], [-1, 0.5, 1]], dtype=float)
    m = from_polygons(v, [[0, 1, 2, 3], [1, 4, 2], [0, 3, 5]])
    assert_same(m)
    mg = merge_counted(m)
    assert mg.rep.tolist() == [0, 2] and mg.region.tolist() == [0, 0, 1]


def test_two_coplanar_quads():
    # two quads side by side on z = 0, tested both ways round, skipping the plane's own first three corners:
    # g = (1, 2, 3, 4) against f's plane (0, 1, 4): corners 2, 3 (2 tests); f = (0, 1, 4, 5) against g's
    # plane (1, 2, 3): corners 0, 4, 5 (3 tests).  All exactly on the plane: 5 exact tests.
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    m = from_polygons(v, [[0, 1, 4, 5], [1, 2, 3, 4]])
    mg = merge_counted(m)
    assert mg.steps["orient3d_filter"] == 5 and mg.steps["orient3d_exact"] == 5 and mg.steps["link"] == 1
    assert mg.rep.tolist() == [0] and np.diff(mg.poly_start).tolist() == [6]
    assert_same(m)


@settings(max_examples=examples(30), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(boxes(), extrusions(), lattice_hulls(), any_meshes()))
def test_counted_merge_equals_the_fast_merge(mesh):
    assert_same(mesh)
