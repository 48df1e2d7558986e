"""Which points lie *exactly* on which planes, as a float test decides, without testing every pair.

EESD's printed "Intersection" (EESD paper Sec. 5.3) is ``a x + b y + c z + d = 0``
compared exactly with zero, for every edge point and every face plane.  To
count the pairs that test true without evaluating ``E x F`` of them, the
points go into a bounding-box tree (Morton order, 16 points per leaf) and
each plane walks it, pruning every box on which the test cannot return zero.
Planes walk in packets of :data:`PACKET` consecutive ones (one traversal,
each stack entry carrying which planes are still alive in it), the
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

A packet is first tested as one: its mid plane ``m`` (each coefficient's
mid-range) and spread ``delta`` (each coefficient's largest ``|p_j - m|``)
bound every plane ``p_j`` of it, ``|p_j(x) - m(x)| <= delta . (|x|, 1)``.
So a box (or, in a leaf, a single point) where ``|m(x)|`` exceeds that spread
by more than ``1e-12 (peak . (X, 1) + delta . (X, 1))`` (``peak``: each
coefficient's largest magnitude in the packet) holds a zero of no plane of
the packet: the margin exceeds the ``3u`` bound above plus the rounding of
the ten-term sums that compute it (each below ``10u`` of the same
magnitudes) by three orders.  A packet with a non-finite coefficient, or
whose planes spread by more than 1e-3 of a coefficient's magnitude (where
the packet test rarely decides and would only add work), is not tested as
one.  On a subdivided mesh the 64 consecutive faces of a packet
are one original triangle's coplanar pieces, so the packet test decides
nearly every box and point that the planes' own tests would, once instead
of 64 times (EESD literal on the 1.04 M-face bunny: 29.5 s before, 7.2 s).

Incoherent packets: where consecutive faces are not coplanar (a torus, a
sphere: no coplanar runs) the planes are regrouped by :func:`_plane_order`,
nearly equal planes together, so that a packet's walk visits little more
than one of its planes' would (EESD literal on a 160 k-face torus: about
1.5x less CPU time; the counts do not depend on the grouping).  Every walk
runs in chunks of packets from Python (:func:`silcount.mesh.chunks.run_chunks`):
Ctrl-C between chunks, and the tests (a plane's prune test at a node, its
test of a point) held to the work limit.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from silcount.mesh.chunks import Meter, run_chunks

LEAF = 16
PACKET = 64  # planes walked together (consecutive faces: neighbours on most meshes)
_STRIPES_PER_THREAD = 8  # interleaved groups of a chunk's packets, per thread
_DEPTH = 128  # stack entries: two per tree level, far more than a tree of 2^63 leaves needs
_SLACK = 1e-14
_PACKET_SLACK = 1e-12  # the packet test's margin (module docstring)
_COHERENT = 1e-3  # packets whose planes differ more rarely decide a box as one: not tested as one


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
def _packet_bounds(planes, first, n):  # pragma: no cover - compiled
    """Whether to test the packet as one (finite, and coherent: every spread within ``_COHERENT`` of its
    coefficient's largest magnitude), its mid plane, spread and largest magnitudes (4 each)."""
    mid, spread, peak = np.zeros(4), np.zeros(4), np.zeros(4)
    finite, coherent = True, True
    for k in range(4):
        lo, hi = np.inf, -np.inf
        for j in range(first, first + n):
            v = planes[j, k]
            finite &= np.isfinite(v)
            lo, hi = min(lo, v), max(hi, v)
            peak[k] = max(peak[k], abs(v))
        mid[k] = 0.5 * (lo + hi)
        for j in range(first, first + n):
            spread[k] = max(spread[k], abs(planes[j, k] - mid[k]))
        coherent &= spread[k] <= _COHERENT * peak[k]
    return finite and coherent, mid, spread, peak


@nb.njit(cache=True, inline="always")
def _packet_misses(mid, spread, peak, cx, cy, cz, hx, hy, hz, bx, by, bz):  # pragma: no cover - compiled
    """No plane of the packet has a zero in the box (centre c, half extent h, magnitudes b); see the docstring."""
    value = mid[0] * cx + mid[1] * cy + mid[2] * cz + mid[3]
    reach = abs(mid[0]) * hx + abs(mid[1]) * hy + abs(mid[2]) * hz
    dev = spread[0] * bx + spread[1] * by + spread[2] * bz + spread[3]
    scale = peak[0] * bx + peak[1] * by + peak[2] * bz + peak[3]
    return abs(value) - reach - dev > _PACKET_SLACK * (scale + dev) + 1e-300


@nb.njit(cache=True)
def _walk(planes, absp, first, n, xs, ys, zs, centre, half, big, empty, size, out, count_only):  # pragma: no cover
    """Walk the tree with the packet of planes ``first .. first + n - 1`` (n <= PACKET) at once.

    Each stack entry carries one byte per plane, 1 while the plane is alive in
    it: a plane leaves a node's subtree when its own prune test (the
    single-plane test of the module docstring, unchanged) rejects the node; a
    node is skipped when no plane is left, or when the packet test (module
    docstring) rejects it; in a leaf the packet test also rules out the points
    no plane can be on.  The prune test runs branch-free
    over the whole packet, and the leaf test over a leaf's points held as
    separate x, y, z arrays, so both loops vectorise.  Returns how many
    (point, plane) zeros were found; unless ``count_only``, writes each zero's
    point position to ``out``.
    """
    stack = np.empty(_DEPTH, dtype=np.int64)
    alive_in = np.zeros((_DEPTH, PACKET), dtype=np.uint8)
    pa, pb, pc, pd = np.zeros(PACKET), np.zeros(PACKET), np.zeros(PACKET), np.zeros(PACKET)
    qa, qb, qc, qd = np.zeros(PACKET), np.zeros(PACKET), np.zeros(PACKET), np.zeros(PACKET)
    # padding planes (j >= n) are all zero and never alive
    last = first + n
    pa[:n], pb[:n], pc[:n], pd[:n] = (
        planes[first:last, 0],
        planes[first:last, 1],
        planes[first:last, 2],
        planes[first:last, 3],
    )
    qa[:n], qb[:n], qc[:n], qd[:n] = absp[first:last, 0], absp[first:last, 1], absp[first:last, 2], absp[first:last, 3]
    alive_in[0, :n] = 1
    alive = np.zeros(PACKET, dtype=np.uint8)
    near = np.ones(LEAF, dtype=np.bool_)  # a leaf's points the packet test leaves to the planes' own
    as_one, m, sp, pk = _packet_bounds(planes, first, n)
    mid, spread, peak = (m[0], m[1], m[2], m[3]), (sp[0], sp[1], sp[2], sp[3]), (pk[0], pk[1], pk[2], pk[3])
    stack[0] = 1
    top, found, n_points, tests = 1, 0, xs.shape[0], 0
    while top > 0:
        top -= 1
        node = stack[top]
        if empty[node]:
            continue  # an empty padding node
        cx, cy, cz = centre[node, 0], centre[node, 1], centre[node, 2]
        hx, hy, hz = half[node, 0], half[node, 1], half[node, 2]
        bx, by, bz = big[node, 0], big[node, 1], big[node, 2]
        if as_one and _packet_misses(mid, spread, peak, cx, cy, cz, hx, hy, hz, bx, by, bz):
            continue
        any_alive = np.uint8(0)
        for j in range(PACKET):
            reach = qa[j] * hx + qb[j] * hy + qc[j] * hz
            bound = qa[j] * bx + qb[j] * by + qc[j] * bz + qd[j]
            value = pa[j] * cx + pb[j] * cy + pc[j] * cz + pd[j]
            pruned = abs(value) - reach > _SLACK * bound + 1e-300
            a = alive_in[top, j] & np.uint8(0 if pruned else 1)
            alive[j] = a
            any_alive |= a
        tests += n  # the planes' prune tests at this node
        if any_alive == 0:
            continue
        if node >= size:
            lo = (node - size) * LEAF
            hi = min(lo + LEAF, n_points)
            n_near = hi - lo
            if as_one:
                n_near = 0
                for i in range(lo, hi):
                    x, y, z = xs[i], ys[i], zs[i]
                    near[i - lo] = not _packet_misses(mid, spread, peak, x, y, z, 0.0, 0.0, 0.0, abs(x), abs(y), abs(z))
                    n_near += near[i - lo]
            if n_near == 0:
                continue
            for j in range(n):
                if alive[j]:
                    a, b, c, d = pa[j], pb[j], pc[j], pd[j]
                    zeros = 0
                    tests += hi - lo
                    for i in range(lo, hi):  # branch-free, so that it vectorises
                        zeros += (a * xs[i] + b * ys[i] + c * zs[i] + d == 0.0) & near[i - lo]
                    if zeros and not count_only:
                        for i in range(lo, hi):
                            if near[i - lo] and a * xs[i] + b * ys[i] + c * zs[i] + d == 0.0:
                                out[found] = i
                                found += 1
                    elif zeros:
                        found += zeros
        else:
            stack[top], stack[top + 1] = 2 * node, 2 * node + 1
            alive_in[top, :] = alive
            alive_in[top + 1, :] = alive
            top += 2
    return found, tests


@nb.njit(cache=True, parallel=True)
def _count(planes, absp, xs, ys, zs, centre, half, big, empty, size, k0, k1, counts, threads):  # pragma: no cover
    """Packets ``k0 .. k1 - 1``: their zeros into ``counts``; returns their tests (``threads``: numba's count).

    The chunk's packets are dealt to ``S`` interleaved stripes (packet ``k0 + i``
    to stripe ``i mod S``), :data:`_STRIPES_PER_THREAD` per thread and at most
    one per packet, so that every thread gets a similar mix of cheap and dear
    packets.  ``prange`` hands each thread a contiguous block of the stripes, so
    ``S`` must follow the chunk: with a fixed 256 stripes, a chunk of 128
    packets or fewer (:func:`silcount.mesh.chunks.run_chunks` sizes a chunk to
    0.25 s: about 100 packets on a 250 k-face torus) gave every packet to the
    first thread and left the second idle.  Each packet's count is its own, so
    the result does not depend on the schedule.
    """
    F = planes.shape[0]
    dummy = np.empty(0, dtype=np.int64)
    tests = 0
    stripes = min(k1 - k0, _STRIPES_PER_THREAD * threads)
    for s in nb.prange(stripes):
        for k in range(k0 + s, k1, stripes):
            first = k * PACKET
            n = min(PACKET, F - first)
            counts[k], t = _walk(planes, absp, first, n, xs, ys, zs, centre, half, big, empty, size, dummy, True)
            tests += t
    return tests


@nb.njit(cache=True, parallel=True)
def _positions(planes, absp, xs, ys, zs, centre, half, big, empty, size, k0, k1, start, hits):  # pragma: no cover
    """Packets ``k0 .. k1 - 1`` again, those with zeros: each zero's point position into ``hits``
    (packet k's from ``start[k]``); returns their tests."""
    F = planes.shape[0]
    tests = 0
    for k in nb.prange(k0, k1):
        if start[k + 1] > start[k]:
            first = k * PACKET
            n = min(PACKET, F - first)
            out = hits[start[k] : start[k + 1]]
            tests += _walk(planes, absp, first, n, xs, ys, zs, centre, half, big, empty, size, out, False)[1]
    return tests


def _search(planes, xs, ys, zs, lo, hi, size, meter: Meter) -> np.ndarray:
    """Point positions of every zero, by packets of :data:`PACKET` consecutive planes, packets in parallel,
    in chunks of packets (:func:`silcount.mesh.chunks.run_chunks`) whose tests ``meter`` holds to the limit."""
    F = planes.shape[0]
    absp = np.abs(planes)
    c, h, b, e = _node_data(lo, hi)
    n_packets = (F + PACKET - 1) // PACKET
    counts = np.zeros(n_packets, dtype=np.int64)
    threads = nb.get_num_threads()
    run_chunks(
        n_packets, lambda k0, k1: _count(planes, absp, xs, ys, zs, c, h, b, e, size, k0, k1, counts, threads), meter
    )
    start = np.zeros(n_packets + 1, dtype=np.int64)
    np.cumsum(counts, out=start[1:])
    hits = np.empty(start[n_packets], dtype=np.int64)
    run_chunks(
        n_packets, lambda k0, k1: _positions(planes, absp, xs, ys, zs, c, h, b, e, size, k0, k1, start, hits), meter
    )
    return hits


@nb.njit(cache=True)
def _coherent_packets(planes):  # pragma: no cover - compiled
    """Per full packet of consecutive planes: is it tested as one (:func:`_packet_bounds`)?"""
    out = np.zeros(planes.shape[0] // PACKET, dtype=np.bool_)
    for k in range(out.size):
        out[k] = _packet_bounds(planes, k * PACKET, PACKET)[0]
    return out


def _plane_order(planes: np.ndarray) -> np.ndarray:
    """The order the planes are walked in: the full packets of consecutive planes that are tested as one
    first, as they are; then the other planes by the Morton code of their normalised coefficients
    ``(a, b, c, d) / |(a, b, c)|`` (8 bits each), so that a packet holds nearly the same planes, which
    walk nearly the same boxes (the walk's cost is the union of its planes' boxes); degenerate planes
    last.  The order changes no count: each (point, plane) test is the same whichever packet it is in."""
    kept = np.repeat(_coherent_packets(planes), PACKET)
    rest = np.flatnonzero(~np.concatenate([kept, np.zeros(len(planes) - kept.size, dtype=np.bool_)]))
    sub = planes[rest]
    with np.errstate(invalid="ignore", divide="ignore"):
        key = sub / np.linalg.norm(sub[:, :3], axis=1)[:, None]
    ok = np.isfinite(key).all(axis=1)
    lo, hi = key[ok].min(axis=0, initial=np.inf), key[ok].max(axis=0, initial=-np.inf)
    q = ((key[ok] - lo) / np.where(hi > lo, hi - lo, 1.0) * 255.0).astype(np.uint64)
    code = np.zeros(len(q), dtype=np.uint64)
    for bit in range(8):
        for k in range(4):
            code |= ((q[:, k] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(4 * bit + k)
    good = rest[ok][np.argsort(code, kind="stable")]
    return np.concatenate([np.flatnonzero(kept), good, rest[~ok]])


def zeros_per_point(points: np.ndarray, planes: np.ndarray, what: str = "plane-point tests") -> np.ndarray:
    """(P,) for each point, how many planes ``(a, b, c, d)`` give exactly ``((a x + b y) + c z) + d == 0``.

    Points with a NaN coordinate are on no plane.  ``what`` names the computation whose tests are held to
    the work limit (:class:`silcount.mesh.chunks.Meter`).
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
    xs, ys, zs = (np.ascontiguousarray(pts[:, k]) for k in range(3))
    planes = np.asarray(planes, dtype=np.float64)
    walked = np.ascontiguousarray(planes[_plane_order(planes)])
    hits = _search(walked, xs, ys, zs, lo, hi, size, Meter(what))
    np.add.at(out, order[hits], 1)
    return out


__all__ = ["zeros_per_point"]
