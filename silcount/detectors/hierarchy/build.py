"""The compiled build of a bounded plane hierarchy (:mod:`.tree`): planes, keys, sort, records, boxes.

:func:`build_fast` builds the tree :func:`.naive.build_naive` builds on
counting arithmetic, array for array (tested), and charges it the counted
build's tally from the tree's sizes (:func:`build_cost`).  It reads the two
faces of every two-faced edge from the reference's per-mesh cache
(:func:`.adjacency.edge_faces`), which every detector shares.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit, prange

from silcount.detectors.adjacency import edge_faces
from silcount.detectors.base import add_scaled
from silcount.detectors.hierarchy.prefetch import ROWS_AHEAD, prefetch
from silcount.detectors.hierarchy.tree import (
    P_RANGE,
    UNIT_RANGE,
    Hierarchy,
    KeyScheme,
    digit_bits,
    level_starts,
    levels,
    sort_passes,
)
from silcount.mesh.model import Mesh
from silcount.threads import fitted_call


@njit(cache=True, parallel=True)
def _p0_max(p0, limit):  # pragma: no cover - compiled
    """The largest ``|p0|_1`` within ``limit`` (a NaN or infinite one never is)."""
    F = p0.shape[0]
    n_chunks = max(1, min(64, F // 4096))
    best = np.zeros(n_chunks)
    for t in prange(n_chunks):
        m = 0.0
        for f in range(t * F // n_chunks, (t + 1) * F // n_chunks):
            big = (abs(p0[f, 0]) + abs(p0[f, 1])) + abs(p0[f, 2])
            if big <= limit and big > m:
                m = big
        best[t] = m
    return best.max()


@njit(cache=True, parallel=True)
def _face_planes(nrm, p0, lo, hi, p_max, plane):  # pragma: no cover - compiled
    """:func:`face_planes` into ``plane`` (NaN rows where untrusted), without temporaries."""
    for f in prange(nrm.shape[0]):
        m = (abs(nrm[f, 0]) + abs(nrm[f, 1])) + abs(nrm[f, 2])
        big = (abs(p0[f, 0]) + abs(p0[f, 1])) + abs(p0[f, 2])
        if not (lo <= m and m <= hi and big <= p_max):  # a NaN or infinite value fails too
            plane[f, :] = np.nan
            continue
        x, y, z = nrm[f, 0] / m, nrm[f, 1] / m, nrm[f, 2] / m
        r = math.sqrt(x * x + y * y + z * z)
        x, y, z = x / r, y / r, z / r
        plane[f, 0], plane[f, 1], plane[f, 2] = x, y, z
        plane[f, 3] = (p0[f, 0] * x + p0[f, 1] * y) + p0[f, 2] * z


def trusted_p0_max(p0: np.ndarray) -> float:
    """The largest ``|p0|_1`` within ``2**100``: the faces that may get a plane, and the point pre-test's ``P``."""
    return float(_p0_max(np.ascontiguousarray(p0, dtype=np.float64), P_RANGE)) if p0.shape[0] else 0.0


def face_planes(nrm: np.ndarray, p0: np.ndarray, p0_max: float) -> np.ndarray:
    """Each face's unit normal ``u`` and offset ``c = p0 . u``, rounded to float32 (F x 4): the pre-test of a
    face's sign (:func:`.tree.pretest`).  A row is NaN (the face is then always evaluated exactly) where
    the normal's ``|n|_1`` is outside ``[2**-300, 2**300]`` (zero, tiny, huge or not finite) or ``|p0|_1``
    exceeds ``p0_max`` (or is not finite).

    The float64 quotient ``(n / m) / |n / m|`` (``m = |n|_1``: ``n / m`` has a 1-norm of 1 and a length in
    ``[1 / sqrt(3), 1]``, so no step over- or underflows) is within a few float64 ulps of ``n / |n|``, and
    rounding to float32 adds at most ``2**-25`` a component: every stored component is within ``2**-24`` of the
    true unit normal's.  The offset is computed in float64 from the float64 unit normal (within ``2**-47.9 |p0|_1`` of
    ``p0 . n / |n|``), then rounded to float32 (``2**-24`` of itself more).
    """
    plane = np.empty((nrm.shape[0], 4), dtype=np.float32)
    _face_planes(np.ascontiguousarray(nrm, dtype=np.float64), np.ascontiguousarray(p0, dtype=np.float64),
                 1.0 / UNIT_RANGE, UNIT_RANGE, p0_max, plane)  # fmt: skip
    return plane


@njit(cache=True, parallel=True)
def _radix_sort(keys, spare, lo_bit, hi_bit, digit_bits, threads):  # pragma: no cover - compiled
    """A stable LSD radix sort of uint64 ``keys`` on bits ``lo_bit .. hi_bit - 1``, between ``keys`` and ``spare``;
    returns the low ``lo_bit`` bits of the sorted keys (the positions), as int64.

    The edges' positions are in the keys' low bits, so this is the stable argsort of the keys proper;
    each pass counts digits per thread chunk, then scatters each chunk in order.
    """
    n = keys.size
    a, b = keys, spare
    radix = 1 << digit_bits
    mask = np.uint64(radix - 1)
    n_chunks = max(1, min(threads, n // 65536))
    size = (n + n_chunks - 1) // n_chunks
    shift = lo_bit
    while shift < hi_bit:
        sh = np.uint64(shift)
        hist = np.zeros((n_chunks, radix), dtype=np.int64)
        for t in prange(n_chunks):
            for i in range(t * size, min(n, t * size + size)):
                hist[t, np.int64((a[i] >> sh) & mask)] += 1
        s = 0
        for d in range(radix):
            for t in range(n_chunks):
                c = hist[t, d]
                hist[t, d] = s
                s += c
        for t in prange(n_chunks):
            h = hist[t]
            for i in range(t * size, min(n, t * size + size)):
                d = np.int64((a[i] >> sh) & mask)
                b[h[d]] = a[i]
                h[d] += 1
        a, b = b, a
        shift += digit_bits
    low = np.uint64((1 << lo_bit) - 1)
    for i in prange(n):  # the positions, in place
        a[i] &= low
    return a.view(np.int64)


def sorted_positions(keys: np.ndarray, key_bits: int, idx_bits: int, room: np.ndarray | None = None) -> np.ndarray:
    """The positions packed into ``keys``' low ``idx_bits``, in the stable order of the keys above them
    (``keys`` is overwritten).

    ``room``: memory the caller writes only afterwards (uint8), used as the sort's second buffer where it
    is large enough and an even number of passes leaves the result in ``keys``; else a fresh buffer.
    """
    if keys.size == 0:
        return np.zeros(0, dtype=np.int64)
    even = sort_passes(keys.size, key_bits) % 2 == 0
    if room is not None and even and room.nbytes >= keys.nbytes:
        spare = room[: keys.nbytes].view(np.uint64)
    else:
        spare = np.empty_like(keys)
    return _radix_sort(keys, spare, idx_bits, idx_bits + key_bits, digit_bits(keys.size),
                       numba.get_num_threads())  # fmt: skip


@njit(cache=True, inline="always")
def _widen(b, x0, x1, x2, x3):  # pragma: no cover - compiled
    """Box ``b`` (``l0 .. l3, h0 .. h3``) widened by one face row, in order: a strictly smaller (larger) value
    replaces the bound, as in the counted build."""
    return (x0 if x0 < b[0] else b[0], x1 if x1 < b[1] else b[1], x2 if x2 < b[2] else b[2],
            x3 if x3 < b[3] else b[3], x0 if x0 > b[4] else b[4], x1 if x1 > b[5] else b[5],
            x2 if x2 > b[6] else b[6], x3 if x3 > b[7] else b[7])  # fmt: skip


@njit(cache=True, inline="always")
def _store_box(box, j, b, bad):  # pragma: no cover - compiled
    """Leaf ``j``'s box ``b``, or ``[-inf, inf]`` where a row was NaN (``bad``)."""
    inf = np.float32(np.inf)
    for c in range(4):
        box[j, c] = -inf if bad else b[c]
        box[j, 4 + c] = inf if bad else b[4 + c]


@njit(cache=True, parallel=True)
def _gather_pairs(pos, two_ids, every, pair_faces, plane, order, planes, leaf_size, box, chunks):  # pragma: no cover
    """The two-faced edges into the tree's arrays, first, in leaf order: their ids (``order``), both faces'
    planes side by side (``planes``), and each leaf's box over them (``box``, the tree's leaf slots).

    Two passes, each of independent reads, so that the processor overlaps their cache misses: each edge's
    id and its rows' face ids (parked in the rows' first four bytes), then leaf by leaf each row's plane by
    that face id, widening the leaf's box as it is written.  One pass of dependent reads took 1.7x as long
    on the 1.04 M bunny.  Each thread takes a run and asks for the rows ``ROWS_AHEAD`` ahead
    (:mod:`.prefetch`): 14-20 ms -> 11-12 ms on the 1.04 M bunny; boxing the leaves here rather than in a
    third pass over the planes (:func:`_leaf_boxes`) saved 2 ms more.
    """
    parked = planes.view(np.int32)
    n = pos.size
    for t in prange(chunks):
        end = (t + 1) * n // chunks
        for i in range(t * n // chunks, end):
            if i + ROWS_AHEAD < end:
                prefetch(pair_faces, pos[i + ROWS_AHEAD])
                if not every:
                    prefetch(two_ids, pos[i + ROWS_AHEAD])
            j = pos[i]
            order[i] = j if every else two_ids[j]
            parked[2 * i, 0] = pair_faces[j, 0]
            parked[2 * i + 1, 0] = pair_faces[j, 1]
    leaves, rows = box.shape[0], 2 * n
    inf = np.float32(np.inf)
    for t in prange(chunks):
        last = (t + 1) * leaves // chunks
        end = min(rows, 2 * leaf_size * last)
        for leaf in range(t * leaves // chunks, last):
            b = (inf, inf, inf, inf, -inf, -inf, -inf, -inf)
            bad = False
            for q in range(2 * leaf_size * leaf, min(rows, 2 * leaf_size * (leaf + 1))):
                if q + ROWS_AHEAD < end:
                    prefetch(plane, np.int64(parked[q + ROWS_AHEAD, 0]))
                f = parked[q, 0]
                x0, x1, x2, x3 = plane[f, 0], plane[f, 1], plane[f, 2], plane[f, 3]
                planes[q, 0], planes[q, 1], planes[q, 2], planes[q, 3] = x0, x1, x2, x3
                bad |= x0 != x0
                b = _widen(b, x0, x1, x2, x3)
            _store_box(box, leaf, b, bad)


@njit(cache=True)
def _gather_others(pos, other, o_start, o_faces, plane, order, start, planes):  # pragma: no cover
    """The other edges in leaf order: ids, and their faces' planes as a CSR."""
    w = 0
    start[0] = 0
    for i in range(pos.size):
        r = pos[i]
        order[i] = other[r]
        for q in range(o_start[r], o_start[r + 1]):
            f = o_faces[q]
            for c in range(4):
                planes[w, c] = plane[f, c]
            w += 1
        start[i + 1] = w


@njit(cache=True, parallel=True)
def _leaf_boxes(planes, T, start, leaf_size, box, boundary):  # pragma: no cover - compiled
    """Each leaf's box over its edges' faces' planes (``[-inf, inf]`` if one is NaN), its boundary flag, for
    the tree of the other edges: edge ``e`` (of ``T``) reads face rows ``start[e] .. start[e + 1]`` of
    ``planes``, each widening the box in order (:func:`_widen`)."""
    inf = np.float32(np.inf)
    for j in prange(box.shape[0]):
        b = (inf, inf, inf, inf, -inf, -inf, -inf, -inf)
        bad = flag = False
        for e in range(j * leaf_size, min(T, j * leaf_size + leaf_size)):
            flag |= start[e + 1] - start[e] == 1
            for q in range(start[e], start[e + 1]):
                bad |= planes[q, 0] != planes[q, 0]
                b = _widen(b, planes[q, 0], planes[q, 1], planes[q, 2], planes[q, 3])
        _store_box(box, j, b, bad)
        boundary[j] = flag


@njit(cache=True, parallel=True)
def _upper_boxes(box, boundary, lv, fanout):  # pragma: no cover - compiled
    """Every internal node's box and flag from its children's, level by level up, in order."""
    for level in range(lv.size - 3, -1, -1):
        first, below, end = lv[level], lv[level + 1], lv[level + 2]
        for j in prange(below - first):
            p = first + j
            for c in range(4):
                box[p, c] = np.inf
                box[p, 4 + c] = -np.inf
            flag = False
            for k in range(below + j * fanout, min(end, below + j * fanout + fanout)):
                for c in range(4):
                    if box[k, c] < box[p, c]:
                        box[p, c] = box[k, c]
                    if box[k, 4 + c] > box[p, 4 + c]:
                        box[p, 4 + c] = box[k, 4 + c]
                flag |= boundary[k]
            boundary[p] = flag


def tree_boxes(planes: np.ndarray, start: np.ndarray, T: int, lv: np.ndarray, leaf_size: int, fanout: int,
               box: np.ndarray, boundary: np.ndarray) -> None:  # fmt: skip
    """The other edges' tree's boxes and flags (slots ``lv[0] .. lv[-1]``) over its ``T`` edges' rows of
    ``planes`` (the CSR ``start``): its leaves, then each level up."""
    if lv.size < 2:
        return
    _leaf_boxes(planes, T, start, leaf_size, box[lv[-2] : lv[-1]], boundary[lv[-2] : lv[-1]])
    _upper_boxes(box, boundary, lv, fanout)


def other_key_faces(o_start: np.ndarray, o_faces: np.ndarray) -> np.ndarray:
    """The other edges' key faces (T1 x 2, uint32): their first two sides' faces, a one-faced edge's twice."""
    second = np.where(o_start[1:] - o_start[:-1] > 1, o_start[:-1] + 1, o_start[:-1])
    return np.stack([o_faces[o_start[:-1]], o_faces[second]], axis=1).astype(np.uint32)


def index_bits(n: int) -> int:
    """The low bits a key gives to its edge's position (at least one)."""
    return max(1, int(n - 1).bit_length())


@fitted_call
def build_fast(mesh: Mesh, scheme: KeyScheme, leaf_size: int, fanout: int) -> Hierarchy:
    """The two trees over the mesh's edges, each sorted by ``scheme``'s keys, built by compiled kernels.

    The build tally is charged from the tree's sizes (:func:`build_cost`), as
    :func:`.naive.build_naive` executes it.
    """
    p0, nrm, two_ids, pair_faces, other, o_start, o_faces = edge_faces(mesh)
    p0_max = trusted_p0_max(p0)
    plane = face_planes(nrm, p0, p0_max)
    consts = scheme.setup(plane)
    T2, T1 = pair_faces.shape[0], other.size
    bits = index_bits(T2)
    S1 = int(o_start[-1]) if T1 else 0
    planes = np.empty((2 * T2 + S1, 4), dtype=np.float32)
    keys = scheme.fast(plane, pair_faces, consts, bits)
    # the sort's second buffer in the planes' memory, which the gather fills only afterwards: 12 MiB fewer
    # fresh pages on the 1.04 M bunny (a fresh page costs its first touch)
    pos = sorted_positions(keys, scheme.bits, bits, planes.reshape(-1).view(np.uint8))
    del keys  # the build's peak stays near the finished tree's size (benchmarks/literature.py)
    order = np.empty(T2 + T1, dtype=np.int32)
    pair_lv = level_starts(T2, leaf_size, fanout)
    other_lv = level_starts(T1, leaf_size, fanout, int(pair_lv[-1]))
    N = int(other_lv[-1])
    box, boundary = np.empty((N, 8), dtype=np.float32), np.zeros(N, dtype=np.bool_)
    pair_leaves = box[pair_lv[-2] : pair_lv[-1]] if pair_lv.size > 1 else box[:0]  # the pair edges' flags stay 0
    _gather_pairs(pos, np.zeros(0, dtype=np.int64) if two_ids is None else two_ids, two_ids is None, pair_faces, plane,
                  order, planes, leaf_size, pair_leaves, numba.get_num_threads())  # fmt: skip
    del pos
    if pair_lv.size > 1:
        _upper_boxes(box, boundary, pair_lv, fanout)
    other_start = np.zeros(T1 + 1, dtype=np.int64)
    if T1:
        obits = index_bits(T1)
        opos = sorted_positions(scheme.fast(plane, other_key_faces(o_start, o_faces), consts, obits), scheme.bits,
                                obits)  # fmt: skip
        _gather_others(opos, other, o_start, o_faces, plane, order[T2:], other_start, planes[2 * T2 :])
    tree_boxes(planes[2 * T2 :], other_start, T1, other_lv, leaf_size, fanout, box, boundary)
    sizes = build_sizes(mesh.n_faces, int(np.count_nonzero(plane[:, 0] == plane[:, 0])), T2, T1, S1, N,
                        leaf_size, fanout, scheme)  # fmt: skip
    return Hierarchy(order, T2, planes, other_start, box, pair_lv, other_lv, boundary, p0_max, leaf_size,
                     fanout, sizes, build_cost(sizes, scheme))  # fmt: skip


def build_sizes(F: int, trusted: int, T2: int, T1: int, S1: int, N: int, leaf_size: int, fanout: int,
                scheme: KeyScheme) -> dict[str, int]:  # fmt: skip
    """The sizes the build's tally depends on (``notes['build_steps']``)."""
    leaves = sum(levels(T2, leaf_size, fanout)[:1]) + sum(levels(T1, leaf_size, fanout)[:1])
    return {"faces": F, "trusted_faces": trusted, "pair_edges": T2, "other_edges": T1, "other_sides": S1,
            "nodes": N, "leaves": leaves, "pair_sort_passes": sort_passes(T2, scheme.bits),
            "other_sort_passes": sort_passes(T1, scheme.bits)}  # fmt: skip


def build_cost(sizes: dict[str, int], scheme: KeyScheme) -> dict[str, int]:
    """The ``true`` tally of :func:`.naive.build_naive` for a tree of these sizes (docs/counting.md)."""
    F, trusted = sizes["faces"], sizes["trusted_faces"]
    T2, T1, S1 = sizes["pair_edges"], sizes["other_edges"], sizes["other_sides"]
    N = sizes["nodes"]
    tally: dict[str, int] = {}
    # per face: p0 and normal (counted_face_normal: 13 R, 9 A, 6 M), stored (6 W); p0_max: p0 read back (3 R),
    # |p0|_1 (2 A), within 2**100 (1 C), larger than the best (1 C)
    add_scaled(tally, {"read": 16, "add": 11, "mul": 6, "write": 6, "cmp": 2}, F)
    # the plane: the normal and p0 read (6 R), |n|_1 and |p0|_1 (4 A), the three range tests (3 C), stored
    # (4 W); a trusted face's n / m (3 div), |.| (3 M, 2 A, 1 sqrt), u (3 div), c (3 M, 2 A)
    add_scaled(tally, {"read": 6, "add": 4, "cmp": 3, "write": 4}, F)
    add_scaled(tally, {"div": 6, "mul": 6, "add": 4, "sqrt": 1}, trusted)
    add_scaled(tally, scheme.setup_cost(F), 1)
    # keys: a pair edge's two faces (2 R); another edge's CSR start and end (2 R), its key faces (2 R); the key
    # (the scheme's cost), stored (1 W)
    add_scaled(tally, {"read": 2, "write": 1}, T2)
    add_scaled(tally, {"read": 4, "write": 1}, T1)
    add_scaled(tally, scheme.key_cost, T2 + T1)
    # per tree an LSD radix sort (digit_bits(T)-bit digits): per pass and key 5 R, 2 A, 4 W (histogram: key,
    # bucket, +1, stored; scatter: key, index, bucket; key, index, bucket stored; +1); per pass and bucket
    # 2 R, 1 A, 1 W (the prefix sums)
    for T, passes in ((T2, sizes["pair_sort_passes"]), (T1, sizes["other_sort_passes"])):
        add_scaled(tally, {"read": 5, "add": 2, "write": 4}, passes * T)
        add_scaled(tally, {"read": 2, "add": 1, "write": 1}, passes * (1 << digit_bits(T)))
    # records: per edge its sorted index and id (2 R), the id stored (1 W); a pair edge's two faces (2 R) and
    # their planes (8 R), stored (8 W); another edge's CSR range (2 R), its end stored (1 W), per side the face
    # and its plane (5 R), stored (4 W)
    add_scaled(tally, {"read": 12, "write": 9}, T2)
    add_scaled(tally, {"read": 4, "write": 2}, T1)
    add_scaled(tally, {"read": 5, "write": 4}, S1)
    # boxes: per leaf edge of the other tree its CSR range (2 R), 'one face' (1 A, 1 C); per face side its
    # plane (4 R), 'NaN' (1 C), the eight widening compares (8 C); per node its box and flag stored (9 W);
    # per child a node reads the child's box and flag (9 R), 8 compares
    add_scaled(tally, {"read": 2, "add": 1, "cmp": 1}, T1)
    add_scaled(tally, {"read": 4, "cmp": 9}, 2 * T2 + S1)
    add_scaled(tally, {"write": 9}, N)
    roots = int(T2 > 0) + int(T1 > 0)
    add_scaled(tally, {"read": 9, "cmp": 8}, N - roots)
    return tally


__all__ = ["build_fast", "build_cost", "build_sizes", "face_planes", "trusted_p0_max", "index_bits",
           "sorted_positions", "tree_boxes", "other_key_faces"]  # fmt: skip
