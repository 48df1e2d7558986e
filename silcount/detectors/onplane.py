"""Which points lie *exactly* on which planes, as a float test decides, without testing every pair.

EESD's printed "Intersection" (EESD paper Sec. 5.3) is ``a x + b y + c z + d = 0``
compared exactly with zero, for every edge point and every face plane.  To
count the pairs that test true without evaluating ``E x F`` of them, the
points go into a bounding-box tree (Morton order, 16 points per leaf) and
each plane walks it, pruning every box on which the test cannot return zero.

Soundness: the test computes ``s = ((a x + b y) + c z)`` in floats, then
``s + d``, which is exactly zero iff ``s == -d``.  The rounding error of
``s`` is at most ``3u (|a x| + |b y| + |c z|)`` (``u = 2^-53``), so a zero
needs ``|a x + b y + c z + d| <= 3u (|a x| + |b y| + |c z|)`` in exact
arithmetic.  A box is pruned only when the plane's value over the box (centre
value -+ the box's reach) stays farther from zero than
``1e-14 (|a| X + |b| Y + |c| Z + |d|)``, with ``X, Y, Z`` the box's largest
coordinates in magnitude: far more than that bound plus the rounding of the
centre value itself.  Surviving points are tested with the exact expression.
"""

from __future__ import annotations

import numba as nb
import numpy as np

LEAF = 16
_SLACK = 1e-14


def _morton_order(points: np.ndarray) -> np.ndarray:
    lo, hi = points.min(axis=0), points.max(axis=0)
    q = ((points - lo) / np.where(hi > lo, hi - lo, 1.0) * 1023.0).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for bit in range(10):
        for k in range(3):
            code |= ((q[:, k] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + k)
    return np.argsort(code, kind="stable")


@nb.njit(cache=True)
def _boxes(pts, n_leaves, size):  # pragma: no cover - compiled
    """Boxes of an implicit complete binary tree (node 1 the root, leaves size..2*size-1)."""
    lo = np.full((2 * size, 3), np.inf)
    hi = np.full((2 * size, 3), -np.inf)
    n = pts.shape[0]
    for leaf in range(n_leaves):
        node = size + leaf
        for i in range(leaf * LEAF, min((leaf + 1) * LEAF, n)):
            for k in range(3):
                lo[node, k] = min(lo[node, k], pts[i, k])
                hi[node, k] = max(hi[node, k], pts[i, k])
    for node in range(size - 1, 0, -1):
        for k in range(3):
            lo[node, k] = min(lo[2 * node, k], lo[2 * node + 1, k])
            hi[node, k] = max(hi[2 * node, k], hi[2 * node + 1, k])
    return lo, hi


@nb.njit(cache=True)
def _walk(plane, pts, lo, hi, size, n_leaves, out, count_only):  # pragma: no cover - compiled
    a, b, c, d = plane[0], plane[1], plane[2], plane[3]
    stack = np.empty(64, dtype=np.int64)
    stack[0] = 1
    top, found = 1, 0
    while top > 0:
        top -= 1
        node = stack[top]
        if lo[node, 0] > hi[node, 0]:
            continue  # an empty padding node
        cx, cy, cz = (
            0.5 * (lo[node, 0] + hi[node, 0]),
            0.5 * (lo[node, 1] + hi[node, 1]),
            0.5 * (lo[node, 2] + hi[node, 2]),
        )
        reach = abs(a) * (hi[node, 0] - cx) + abs(b) * (hi[node, 1] - cy) + abs(c) * (hi[node, 2] - cz)
        big = (
            abs(a) * max(abs(lo[node, 0]), abs(hi[node, 0]))
            + abs(b) * max(abs(lo[node, 1]), abs(hi[node, 1]))
            + abs(c) * max(abs(lo[node, 2]), abs(hi[node, 2]))
            + abs(d)
        )
        centre = a * cx + b * cy + c * cz + d
        if abs(centre) - reach > _SLACK * big + 1e-300:
            continue
        if node >= size:
            leaf = node - size
            for i in range(leaf * LEAF, min((leaf + 1) * LEAF, pts.shape[0])):
                if a * pts[i, 0] + b * pts[i, 1] + c * pts[i, 2] + d == 0.0:
                    if not count_only:
                        out[found] = i
                    found += 1
        else:
            stack[top] = 2 * node
            stack[top + 1] = 2 * node + 1
            top += 2
    return found


@nb.njit(cache=True, parallel=True)
def _search(planes, pts, lo, hi, size, n_leaves):  # pragma: no cover - compiled
    F = planes.shape[0]
    counts = np.zeros(F, dtype=np.int64)
    dummy = np.empty(0, dtype=np.int64)
    for f in nb.prange(F):
        counts[f] = _walk(planes[f], pts, lo, hi, size, n_leaves, dummy, True)
    start = np.zeros(F + 1, dtype=np.int64)
    for f in range(F):
        start[f + 1] = start[f] + counts[f]
    hits = np.empty(start[F], dtype=np.int64)
    for f in nb.prange(F):
        if counts[f]:
            _walk(planes[f], pts, lo, hi, size, n_leaves, hits[start[f] : start[f + 1]], False)
    return start, hits


def zeros_per_point(points: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """(P,) for each point, how many planes ``(a, b, c, d)`` give exactly ``((a x + b y) + c z) + d == 0``.

    Points with a NaN coordinate are on no plane.
    """
    points = np.asarray(points, dtype=np.float64)
    out = np.zeros(len(points), dtype=np.int64)
    finite = np.flatnonzero(np.isfinite(points).all(axis=1))
    if finite.size == 0 or len(planes) == 0:
        return out
    order = finite[_morton_order(points[finite])]
    pts = np.ascontiguousarray(points[order])
    n_leaves = -(-len(pts) // LEAF)
    size = 1 << max(0, int(np.ceil(np.log2(n_leaves))))
    lo, hi = _boxes(pts, n_leaves, size)
    _, hits = _search(np.ascontiguousarray(planes, dtype=np.float64), pts, lo, hi, size, n_leaves)
    np.add.at(out, order[hits], 1)
    return out


__all__ = ["zeros_per_point"]
