"""The compiled build of a bounded edge hierarchy (:mod:`.hierarchy`): sort, renumber, box.

:func:`build_fast` builds the tree :func:`.hierarchy_naive.build_naive` builds on
counting arithmetic, array for array (tested), and charges it the counted
build's tally from the tree's sizes (:func:`.hierarchy.build_cost`).  It also
keeps each face's plane in float32 (:func:`face_planes`), for the compiled
query's pre-test (:mod:`.hierarchy_walk`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from silcount.detectors.hierarchy import (
    DIGIT_BITS,
    UNIT_RANGE,
    Hierarchy,
    KeyScheme,
    build_cost,
    key_faces,
    level_slots,
    n_leaves,
    shape,
    split_edges,
)
from silcount.mesh.model import Mesh


@njit(cache=True)
def _radix_argsort(keys, n_bits, digit_bits):  # pragma: no cover - compiled
    """A stable LSD radix argsort of uint64 ``keys`` below ``2**n_bits``, moving (key, index) pairs."""
    n = keys.size
    k, idx = keys.copy(), np.arange(n)
    k2, idx2 = np.empty_like(k), np.empty_like(idx)
    radix = 1 << digit_bits
    mask = np.uint64(radix - 1)
    shift = 0
    while shift < n_bits:
        hist = np.zeros(radix + 1, dtype=np.int64)
        for i in range(n):
            hist[np.int64((k[i] >> np.uint64(shift)) & mask) + 1] += 1
        for d in range(radix):
            hist[d + 1] += hist[d]
        for i in range(n):
            d = np.int64((k[i] >> np.uint64(shift)) & mask)
            k2[hist[d]] = k[i]
            idx2[hist[d]] = idx[i]
            hist[d] += 1
        k, k2 = k2, k
        idx, idx2 = idx2, idx
        shift += digit_bits
    return idx


@njit(cache=True, parallel=True)
def _renumber(perm, every, ids, start, sides, side_face, p0, nrm):  # pragma: no cover - compiled
    """Sorted edge ids, their face CSR in local face ids, and ``p0`` and normals in local order.

    ``perm`` sorts the tree's edges: every edge (``every``) or ``ids``; edge ``e``'s faces are
    ``side_face[sides[start[e]:start[e + 1]]]`` (read in place: no copy of the 2E face references).
    Faces are numbered in the order the sorted edges first reach them, then the faces no tree edge
    reaches (a non-finite value).  The gathers run in parallel; only the numbering, a forward pass over
    the gathered face ids, is serial.
    """
    T, F = perm.size, p0.shape[0]
    order = np.empty(T, dtype=np.int64)
    e_start = np.empty(T + 1, dtype=np.int64)
    e_start[0] = 0
    for i in prange(T):  # the sorted edges and their face counts
        e = perm[i] if every else ids[perm[i]]
        order[i] = e
        e_start[i + 1] = start[e + 1] - start[e]
    for i in range(T):
        e_start[i + 1] += e_start[i]
    e_faces = np.empty(e_start[T], dtype=np.int32)
    for i in prange(T):  # their faces' global ids, in sorted order
        e, w = order[i], e_start[i]
        for q in range(start[e], start[e + 1]):
            e_faces[w] = side_face[sides[q]]
            w += 1
    local = np.full(F, -1, dtype=np.int32)
    nxt = 0
    for w in range(e_faces.size):  # first reach numbers a face; the CSR then holds local ids
        f = e_faces[w]
        if local[f] < 0:
            local[f] = nxt
            nxt += 1
        e_faces[w] = local[f]
    for f in range(F):
        if local[f] < 0:
            local[f] = nxt
            nxt += 1
    lp0, lnrm = np.empty_like(p0), np.empty_like(nrm)
    for f in prange(F):  # p0 and normals copied into local order
        n = local[f]
        for c in range(3):
            lp0[n, c] = p0[f, c]
            lnrm[n, c] = nrm[f, c]
    return order, e_start, e_faces, local, lp0, lnrm


@njit(cache=True, inline="always")
def _widen(b, lo, hi):  # pragma: no cover - compiled
    """Box ``b`` (lo 3, hi 3) widened by the box ``lo .. hi``: first-seen wins a tie, as in the counted build."""
    for c in range(3):
        if lo[c] < b[c]:
            b[c] = lo[c]
        if hi[c] > b[3 + c]:
            b[3 + c] = hi[c]


@njit(cache=True, parallel=True)
def _level_bounds(e_start, e_faces, nrm, p0, level_start, leaf_size, fanout, nbox, pbox, boundary):  # pragma: no cover
    """Every node's boxes and boundary flag in level order: the leaves from their edges' faces, then
    each level up from its children, in order (the counted build's values, compare for compare); the
    nodes of a level in parallel."""
    D = level_start.size - 1
    T = e_start.size - 1
    for lvl in range(D - 1, -1, -1):
        first, size = level_start[lvl], level_start[lvl + 1] - level_start[lvl]
        for j in prange(size):
            nb, pb = nbox[first + j], pbox[first + j]
            nb[:3] = np.inf
            pb[:3] = np.inf
            nb[3:] = -np.inf
            pb[3:] = -np.inf
            flag = False
            if lvl == D - 1:  # a leaf: its edges' faces
                for e in range(j * leaf_size, min(j * leaf_size + leaf_size, T)):
                    flag |= e_start[e + 1] - e_start[e] == 1
                    for q in range(e_start[e], e_start[e + 1]):
                        f = e_faces[q]
                        _widen(nb, nrm[f], nrm[f])
                        _widen(pb, p0[f], p0[f])
            else:  # its children, in order
                below, n_below = level_start[lvl + 1], level_start[lvl + 2] - level_start[lvl + 1]
                for k in range(below + j * fanout, below + min(j * fanout + fanout, n_below)):
                    _widen(nb, nbox[k, :3], nbox[k, 3:])
                    _widen(pb, pbox[k, :3], pbox[k, 3:])
                    flag |= boundary[k]
            boundary[first + j] = flag


@njit(cache=True, parallel=True)
def _face_planes(nrm, p0, plane, lo, hi, p_max):  # pragma: no cover - compiled
    """:func:`face_planes` into ``plane`` (NaN rows where untrusted), without temporaries."""
    for f in prange(nrm.shape[0]):
        m = max(abs(nrm[f, 0]), abs(nrm[f, 1]), abs(nrm[f, 2]))
        big = max(abs(p0[f, 0]), abs(p0[f, 1]), abs(p0[f, 2]))
        if not (lo <= m <= hi and big <= p_max):  # NaN fails too
            plane[f, :] = np.nan
            continue
        x, y, z = nrm[f, 0] / m, nrm[f, 1] / m, nrm[f, 2] / m
        r = math.sqrt(x * x + y * y + z * z)
        x, y, z = x / r, y / r, z / r
        plane[f, 0], plane[f, 1], plane[f, 2] = x, y, z
        plane[f, 3] = (p0[f, 0] * x + p0[f, 1] * y) + p0[f, 2] * z


def face_planes(nrm: np.ndarray, p0: np.ndarray, p0_max: float) -> np.ndarray:
    """Each face's unit normal ``u`` and offset ``c = p0 . u``, rounded to float32 (F x 4): the compiled
    query's pre-test of a face's sign (:func:`.hierarchy_walk.pretest`).  A row is NaN (the face is then
    always evaluated exactly) where the normal's largest |component| is outside ``[2**-300, 2**300]``
    (zero, tiny, huge or not finite) or a ``p0`` coordinate exceeds ``p0_max`` in magnitude.

    The float64 quotient ``(n / m) / |n / m|`` (``m`` its largest |component|, so no step over- or
    underflows) is within a few float64 ulps of ``n / |n|``, and rounding to float32 adds at most
    ``2**-25`` a component: every stored component is within ``2**-24`` of the true unit normal's.
    The offset is computed in float64 from the float64 unit normal (within ``2**-47.9 |p0|_1`` of
    ``p0 . n / |n|``), then rounded to float32 (``2**-24`` of itself more).
    """
    plane = np.empty((nrm.shape[0], 4), dtype=np.float32)
    _face_planes(np.ascontiguousarray(nrm, dtype=np.float64), np.ascontiguousarray(p0, dtype=np.float64), plane,
                 1.0 / UNIT_RANGE, UNIT_RANGE, p0_max)  # fmt: skip
    return plane


def build_fast(mesh: Mesh, scheme: KeyScheme, leaf_size: int, fanout: int) -> Hierarchy:
    """The tree over the mesh's edges, sorted by ``scheme``'s keys, built by compiled kernels.

    The build tally is charged from the tree's sizes and ``scheme``'s per-key and set-up costs, as
    :func:`.hierarchy_naive.build_naive` executes them (it has no data-dependent branch but the
    first visit of each face, which happens once per face).
    """
    start, sides = mesh.edge_sides
    ids, rest = split_edges(mesh)
    keys = scheme.fast(mesh, *key_faces(mesh, ids))  # each temporary freed as soon as it is used:
    perm = _radix_argsort(np.ascontiguousarray(keys, dtype=np.uint64), scheme.bits, DIGIT_BITS)
    del keys  # the build's peak stays near the finished tree's size (scripts/bench_literature.py)
    every = ids is None
    order, e_start, e_faces, local, lp0, lnrm = _renumber(perm, every, np.zeros(0, dtype=np.int64) if every else ids,
                                                          start, sides, mesh.side_face, mesh.face_p0,
                                                          mesh.face_normals)  # fmt: skip
    del perm, ids
    counts = mesh.edge_valence[rest]
    r_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    r_sides = sides[np.repeat(start[rest], counts) + np.arange(r_start[-1]) - np.repeat(r_start[:-1], counts)]
    r_faces = local[mesh.side_face[r_sides]]
    del local, r_sides
    nodes, depth = shape(order.size, leaf_size, fanout)
    level_of, level_start = level_slots(nodes, depth, order.size, leaf_size, fanout)
    del depth
    nbox, pbox = np.empty((nodes.shape[0], 6)), np.empty((nodes.shape[0], 6))
    boundary = np.zeros(nodes.shape[0], dtype=np.bool_)
    _level_bounds(e_start, e_faces, lnrm, lp0, level_start, leaf_size, fanout, nbox, pbox, boundary)
    p0_max = float(np.abs(pbox[0]).max()) if order.size else 0.0
    sizes = {"faces": mesh.n_faces, "tree_edges": int(order.size), "tree_sides": int(e_faces.size),
             "rest_edges": int(rest.size), "rest_sides": int(r_faces.size), "nodes": int(nodes.shape[0]),
             "leaves": n_leaves(nodes)}  # fmt: skip
    steps, tally = build_cost(sizes, scheme)
    return Hierarchy(order, e_start, e_faces, nodes, level_of, level_start, nbox, pbox, boundary, rest, r_start,
                     r_faces.astype(np.int32), lp0, lnrm, face_planes(lnrm, lp0, p0_max), p0_max, leaf_size, fanout,
                     steps, tally)  # fmt: skip


__all__ = ["build_fast", "face_planes"]
