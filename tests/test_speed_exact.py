"""The numba expansion predicates (silcount.mesh.exact) against exact rational arithmetic (fractions)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from silcount.mesh.exact import exact_range_ok, normals_dot_sign, orient3d_sign


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def _orient_fraction(a, b, c, d) -> int:
    a, b, c, d = ([Fraction(float(x)) for x in p] for p in (a, b, c, d))
    ad = [a[k] - d[k] for k in range(3)]
    bd = [b[k] - d[k] for k in range(3)]
    cd = [c[k] - d[k] for k in range(3)]
    det = (
        ad[2] * (bd[0] * cd[1] - cd[0] * bd[1])
        + bd[2] * (cd[0] * ad[1] - ad[0] * cd[1])
        + cd[2] * (ad[0] * bd[1] - bd[0] * ad[1])
    )
    return _sign(det)


def _normal(p0, p1, p2):
    p0, p1, p2 = ([Fraction(float(x)) for x in p] for p in (p0, p1, p2))
    u = [p1[k] - p0[k] for k in range(3)]
    v = [p2[k] - p0[k] for k in range(3)]
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


# coordinates of mixed magnitudes, and near-degenerate configurations (nearly or exactly coplanar)
coord = st.one_of(
    st.floats(-4.0, 4.0, allow_nan=False, allow_infinity=False),
    st.sampled_from([0.0, 1.0, -1.0, 0.5, 1e-30, 3.0e20, 0.1, 0.2, 0.3]),
    st.integers(-8, 8).map(float),
)
point = st.tuples(coord, coord, coord).map(np.array)


def _near_plane(a, b, c, s, t, jitter):
    """A point a + s (b - a) + t (c - a), rounded, then nudged by ``jitter`` ulps in one coordinate."""
    d = a + s * (b - a) + t * (c - a)
    if jitter:
        d = d.copy()
        d[0] = np.nextafter(d[0], np.inf if jitter > 0 else -np.inf)
    return d


@settings(max_examples=400, deadline=None)
@given(point, point, point, st.floats(-2, 2), st.floats(-2, 2), st.sampled_from([-1, 0, 0, 1]), point)
def test_orient3d_sign_is_exact(a, b, c, s, t, jitter, free):
    d = _near_plane(a, b, c, s, t, jitter)
    w, lens = np.empty((20, 512)), np.empty(9, dtype=np.int64)
    for q in (d, free):
        pts = np.stack([a, b, c, q])
        if not exact_range_ok(pts):
            continue
        assert orient3d_sign(pts, 0, 1, 2, 3, w, lens) == _orient_fraction(a, b, c, q)


@settings(max_examples=300, deadline=None)
@given(point, point, point, point, point, point, st.sampled_from(["free", "same", "reversed", "degenerate"]))
def test_normals_dot_sign_is_exact(p0, p1, p2, q0, q1, q2, kind):
    if kind == "same":  # n . n >= 0, zero iff degenerate
        q0, q1, q2 = p1, p2, p0
    elif kind == "reversed":
        q0, q1, q2 = p0, p2, p1
    elif kind == "degenerate":  # collinear corners: a zero normal
        q0, q1, q2 = p0, p1, p1
    pts = np.stack([p0, p1, p2, q0, q1, q2])
    if not exact_range_ok(pts):
        return
    w, lens = np.empty((24, 2048)), np.empty(18, dtype=np.int64)
    want = _sign(sum(x * y for x, y in zip(_normal(p0, p1, p2), _normal(q0, q1, q2), strict=True)))
    assert normals_dot_sign(pts, 0, 1, 2, 3, 4, 5, w, lens) == want


def test_exact_range():
    assert exact_range_ok(np.array([0.0, 1.0, -(2.0**150)]))
    assert not exact_range_ok(np.array([2.0**-151]))
    assert not exact_range_ok(np.array([1e300]))


@settings(max_examples=40, deadline=None)
@given(
    st.integers(2, 4),
    st.integers(2, 4),
    st.floats(-3.0, 3.0),
    st.floats(-3.0, 3.0),
    st.booleans(),
    st.lists(st.integers(0, 24), max_size=4),
    st.sampled_from([1.0, 2.0**-20, 3.0e10]),
)
def test_merge_kernel_agrees_with_python_integers(nx, ny, ax, ay, split, nudged, scale):
    # The tight merge's compiled kernel (float filter, Shewchuk's expansions) against its second
    # implementation on exact Python integers (used outside the expansions' range), on a tilted grid of
    # quads or triangles: rounding makes neighbours nearly coplanar, and nudged vertices break planes.
    from silcount.mesh.coplanar import _coplanar_pairs, _opposite_pairs
    from silcount.mesh.coplanar_ints import common_shift, coplanar_pairs_ints, normals_agree_ints
    from silcount.mesh.model import from_polygons

    i, j = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0), indexing="ij")
    v = np.stack([i.ravel(), j.ravel(), np.zeros(i.size)], axis=1)
    cx, sx, cy, sy = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay)
    rx, ry = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]]), np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    v = scale * (v @ rx @ ry)
    for k in nudged:
        if k < len(v):
            v[k, 2] = np.nextafter(v[k, 2], np.inf)
    at = lambda a, b: a * (ny + 1) + b  # noqa: E731
    quads = [[at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)] for a in range(nx) for b in range(ny)]
    faces = [t for q in quads for t in ([q[:3], [q[0], q[2], q[3]]] if split else [q])]
    assume(exact_range_ok(v))  # the kernel's domain (subnormal sines leave it)
    mesh = from_polygons(v, faces)
    _, f, g = _opposite_pairs(mesh)
    first3 = mesh.corners[mesh.face_start[:-1, None] + np.arange(3)]
    tests, unsure, coplanar, merged = _coplanar_pairs(
        mesh.vertices, mesh.corners, mesh.face_start, mesh.face_sizes, first3, f, g
    )
    steps: dict = {}
    assert np.array_equal(coplanar, coplanar_pairs_ints(mesh, f, g, first3, steps))
    assert (steps["orient3d_filter"], steps["orient3d_exact"]) == (tests.sum(), unsure.sum())
    cand = np.flatnonzero(coplanar)
    faces_used = np.unique(np.concatenate([f[cand], g[cand]]))
    same = normals_agree_ints(mesh.vertices, first3, faces_used, f[cand], g[cand], common_shift(mesh.vertices))
    assert np.array_equal(np.flatnonzero(merged), cand[same])
