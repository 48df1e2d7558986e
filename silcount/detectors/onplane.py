"""Which points lie *exactly* on which planes, as a float test decides, without testing every pair.

EESD's printed "Intersection" (EESD paper Sec. 5.3) is ``a x + b y + c z + d = 0``
compared exactly with zero, for every edge point and every face plane.  To
count the pairs that test true without evaluating ``E x F`` of them, the
points go into a bounding-box tree (Morton order, 16 points per leaf) and
each plane walks it, pruning every box on which the test cannot return zero.
Planes walk in packets of :data:`PACKET` consecutive ones (one traversal,
each stack entry carrying the bit mask of the planes still alive in it), the
packets in parallel (numba ``prange``): every plane makes exactly the prune
decisions and point tests of a walk of its own, so the counts are the same.

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
PACKET = 32  # planes walked together (consecutive faces: neighbours on most meshes)
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
def _node_data(lo, hi):  # pragma: no cover - compiled
    """Per node: centre, half extent (``hi - centre``) and largest magnitude per axis; empty flag."""
    n = lo.shape[0]
    centre = np.empty((n, 3))
    half = np.empty((n, 3))
    big = np.empty((n, 3))
    empty = np.empty(n, dtype=np.bool_)
    for node in range(n):
        empty[node] = lo[node, 0] > hi[node, 0]
        for k in range(3):
            c = 0.5 * (lo[node, k] + hi[node, k])
            centre[node, k] = c
            half[node, k] = hi[node, k] - c
            big[node, k] = max(abs(lo[node, k]), abs(hi[node, k]))
    return centre, half, big, empty


@nb.njit(cache=True)
def _walk(planes, first, n, pts, centre, half, big, empty, size, out, count_only):  # pragma: no cover - compiled
    """Walk the tree with the packet of planes ``first .. first + n - 1`` (n <= 64) at once.

    Each stack entry carries the planes still alive in it (a bit mask): a plane
    leaves a node's subtree when its own prune test (the single-plane test of
    the module docstring, unchanged) rejects the node; a node is skipped when no
    plane is left.  Returns how many (point, plane) zeros were found; unless
    ``count_only``, writes each zero's point position to ``out``.
    """
    stack = np.empty(64, dtype=np.int64)
    masks = np.empty(64, dtype=np.uint64)
    stack[0] = 1
    masks[0] = (np.uint64(1) << np.uint64(n)) - np.uint64(1) if n < 64 else ~np.uint64(0)
    top, found = 1, 0
    while top > 0:
        top -= 1
        node = stack[top]
        mask = masks[top]
        if empty[node]:
            continue  # an empty padding node
        cx, cy, cz = centre[node, 0], centre[node, 1], centre[node, 2]
        hx, hy, hz = half[node, 0], half[node, 1], half[node, 2]
        bx, by, bz = big[node, 0], big[node, 1], big[node, 2]
        alive = np.uint64(0)
        for j in range(n):
            bit = np.uint64(1) << np.uint64(j)
            if not (mask & bit):
                continue
            a, b, c, d = planes[first + j, 0], planes[first + j, 1], planes[first + j, 2], planes[first + j, 3]
            reach = abs(a) * hx + abs(b) * hy + abs(c) * hz
            bound = abs(a) * bx + abs(b) * by + abs(c) * bz + abs(d)
            value = a * cx + b * cy + c * cz + d
            if not (abs(value) - reach > _SLACK * bound + 1e-300):
                alive |= bit
        if alive == 0:
            continue
        if node >= size:
            leaf = node - size
            for i in range(leaf * LEAF, min((leaf + 1) * LEAF, pts.shape[0])):
                x, y, z = pts[i, 0], pts[i, 1], pts[i, 2]
                for j in range(n):
                    if alive & (np.uint64(1) << np.uint64(j)):
                        if (
                            planes[first + j, 0] * x
                            + planes[first + j, 1] * y
                            + planes[first + j, 2] * z
                            + planes[first + j, 3]
                            == 0.0
                        ):
                            if not count_only:
                                out[found] = i
                            found += 1
        else:
            stack[top] = 2 * node
            masks[top] = alive
            stack[top + 1] = 2 * node + 1
            masks[top + 1] = alive
            top += 2
    return found


@nb.njit(cache=True, parallel=True)
def _search(planes, pts, lo, hi, size):  # pragma: no cover - compiled
    """Point positions of every zero, by packets of :data:`PACKET` consecutive planes, packets in parallel."""
    F = planes.shape[0]
    centre, half, big, empty = _node_data(lo, hi)
    n_packets = (F + PACKET - 1) // PACKET
    counts = np.zeros(n_packets, dtype=np.int64)
    dummy = np.empty(0, dtype=np.int64)
    for k in nb.prange(n_packets):
        first = k * PACKET
        counts[k] = _walk(planes, first, min(PACKET, F - first), pts, centre, half, big, empty, size, dummy, True)
    start = np.zeros(n_packets + 1, dtype=np.int64)
    for k in range(n_packets):
        start[k + 1] = start[k] + counts[k]
    hits = np.empty(start[n_packets], dtype=np.int64)
    for k in nb.prange(n_packets):
        if counts[k]:
            first = k * PACKET
            n = min(PACKET, F - first)
            _walk(planes, first, n, pts, centre, half, big, empty, size, hits[start[k] : start[k + 1]], False)
    return hits


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
    hits = _search(np.ascontiguousarray(planes, dtype=np.float64), pts, lo, hi, size)
    np.add.at(out, order[hits], 1)
    return out


__all__ = ["zeros_per_point"]
