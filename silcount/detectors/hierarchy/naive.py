"""The bounded plane hierarchy on counting arithmetic: the ``naive`` engine of ``gaussmap`` and ``cones``.

:func:`build_naive` builds the tree :func:`~silcount.detectors.hierarchy.build.build_fast`
builds, and :func:`query_naive` answers a light with every scalar operation
counted (``docs/counting.md``, "gaussmap and cones"): each tree walked level
by level from its root, each face pre-tested from its float32 plane and
evaluated exactly where that cannot decide.  The compiled
:func:`~silcount.detectors.hierarchy.query.query_fast` takes the same steps.
The tests hold the two engines' trees, edge sets, steps and tallies equal.

Float32 values are read as numpy ``float32`` scalars, so that a counted
product or sum rounds as the compiled kernel's does; under a point light
they are widened to float64 first, as the kernel widens them.
"""

from __future__ import annotations

import math

import numpy as np

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.detectors.adjacency import edge_faces
from silcount.detectors.base import MeshMemory, counted_face_normal
from silcount.detectors.hierarchy.build import build_sizes
from silcount.detectors.hierarchy.tree import (
    P_RANGE,
    PRETEST_MARGIN,
    PRETEST_RANGE,
    STEP_NAMES,
    UNIT_RANGE,
    Hierarchy,
    KeyScheme,
    digit_bits,
    level_starts,
    up32,
)
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh


def _abs(x: Num) -> Num:
    """``|x|``: a sign cleared, not an arithmetic operation (not counted)."""
    return Num(abs(x.value), x.counter)


def read32(mem: Memory, idx, wide: bool) -> Num:
    """One float32 element (1 R), kept in float32, or widened exactly to float64 with ``wide``."""
    mem.counter["read"] += 1
    v = mem.data[idx]
    return Num(np.float64(v) if wide else np.float32(v), mem.counter)


# ---- the build --------------------------------------------------------------------------------------------
def build_naive(mesh: Mesh, scheme: KeyScheme, leaf_size: int, fanout: int, counter: OpCounter) -> Hierarchy:
    """:func:`~silcount.detectors.hierarchy.build.build_fast`'s tree, built on counting arithmetic."""
    mem = MeshMemory(mesh, DirectionalLight((0.0, 0.0, 1.0)), counter)  # the build reads no light
    F = mesh.n_faces
    p0, nrm = Memory(np.zeros((F, 3)), counter), Memory(np.zeros((F, 3)), counter)
    for f in range(F):
        corner, n = counted_face_normal(mem, f)
        for c in range(3):
            p0[f, c], nrm[f, c] = corner[c], n[c]
    p0_max: Num | float = 0.0
    for f in range(F):  # the largest |p0|_1 within 2**100
        big = _abs(p0[f, 0]) + _abs(p0[f, 1]) + _abs(p0[f, 2])
        within, larger = big <= P_RANGE, big > p0_max
        if within and larger:
            p0_max = big
    p_max = float(plain(p0_max))
    plane = Memory(np.zeros((F, 4), dtype=np.float32), counter)
    for f in range(F):
        _plane_naive(p0, nrm, f, p_max, plane)
    consts = scheme.setup_naive(plane, F, counter)
    _, _, two_ids, pair_faces_plain, other_plain, o_start_plain, o_faces_plain = edge_faces(mesh)
    T2, T1 = pair_faces_plain.shape[0], other_plain.size
    ids_plain = np.arange(T2, dtype=np.int64) if two_ids is None else two_ids
    pf = Memory(pair_faces_plain, counter)
    keys = Memory(np.zeros(T2, dtype=np.uint64), counter)
    for j in range(T2):
        keys[j] = scheme.naive(plane, plain(pf[j, 0]), plain(pf[j, 1]), consts, counter)
    o_start, o_faces = Memory(o_start_plain, counter), Memory(o_faces_plain, counter)
    okeys = Memory(np.zeros(T1, dtype=np.uint64), counter)
    for r in range(T1):
        s, t = plain(o_start[r]), plain(o_start[r + 1])
        a, b = plain(o_faces[s]), plain(o_faces[s + 1 if t - s > 1 else s])
        okeys[r] = scheme.naive(plane, a, b, consts, counter)
    perm = _counted_radix_argsort(keys, T2, scheme.bits, counter)
    operm = _counted_radix_argsort(okeys, T1, scheme.bits, counter)
    S1 = int(o_start_plain[-1]) if T1 else 0
    order = Memory(np.zeros(T2 + T1, dtype=np.int32), counter)
    planes = Memory(np.zeros((2 * T2 + S1, 4), dtype=np.float32), counter)
    ids = Memory(ids_plain, counter)
    for i in range(T2):  # the pair edges' records
        j = plain(perm[i])
        order[i] = ids[j]
        for h in range(2):
            f = plain(pf[j, h])
            for c in range(4):
                planes[2 * i + h, c] = read32(plane, (f, c), False)
    other = Memory(other_plain, counter)
    other_start = Memory(np.zeros(T1 + 1, dtype=np.int64), counter)
    w = 2 * T2
    for i in range(T1):  # the other edges' records
        r = plain(operm[i])
        order[T2 + i] = other[r]
        for q in range(plain(o_start[r]), plain(o_start[r + 1])):
            f = plain(o_faces[q])
            for c in range(4):
                planes[w, c] = read32(plane, (f, c), False)
            w += 1
        other_start[i + 1] = w - 2 * T2
    pair_lv = level_starts(T2, leaf_size, fanout)
    other_lv = level_starts(T1, leaf_size, fanout, int(pair_lv[-1]))
    N = int(other_lv[-1])
    box = Memory(np.zeros((N, 8), dtype=np.float32), counter)
    boundary = Memory(np.zeros(N, dtype=np.bool_), counter)
    _boxes_naive(planes, 0, None, T2, pair_lv, leaf_size, fanout, box, boundary)
    _boxes_naive(planes, 2 * T2, other_start, T1, other_lv, leaf_size, fanout, box, boundary)
    trusted = int(np.count_nonzero(~np.isnan(np.asarray(plane.data)[:, 0])))
    return Hierarchy(
        order=np.asarray(order.data),
        n_pairs=T2,
        planes=np.asarray(planes.data),
        other_start=np.asarray(other_start.data),
        box=np.asarray(box.data),
        pair_levels=pair_lv,
        other_levels=other_lv,
        boundary=np.asarray(boundary.data),
        p0_max=p_max,
        leaf_size=leaf_size,
        fanout=fanout,
        build_steps=build_sizes(F, trusted, T2, T1, S1, N, leaf_size, fanout, scheme),
        build_tally=dict(counter),
    )


def _plane_naive(p0: Memory, nrm: Memory, f: int, p_max: float, plane: Memory) -> None:
    """Face ``f``'s plane as :func:`.build.face_planes` computes it, stored as float32 (NaN if untrusted)."""
    n = [nrm[f, c] for c in range(3)]
    p = [p0[f, c] for c in range(3)]
    m = _abs(n[0]) + _abs(n[1]) + _abs(n[2])
    big = _abs(p[0]) + _abs(p[1]) + _abs(p[2])
    low, high, near = m >= 1.0 / UNIT_RANGE, m <= UNIT_RANGE, big <= p_max
    if not (low and high and near):
        for c in range(4):
            plane[f, c] = np.float32(np.nan)
        return
    x = [v / m for v in n]
    r = Num(math.sqrt(plain(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])), m.counter)
    m.counter.tick("sqrt")
    u = [v / r for v in x]
    c = p[0] * u[0] + p[1] * u[1] + p[2] * u[2]
    for k in range(3):
        plane[f, k] = np.float32(plain(u[k]))
    plane[f, 3] = np.float32(plain(c))


def _boxes_naive(planes: Memory, base: int, start: Memory | None, T: int, lv: np.ndarray, leaf_size: int,
                 fanout: int, box: Memory, boundary: Memory) -> None:  # fmt: skip
    """One tree's boxes and boundary flags in level order: its leaves, then each level up from its children."""
    if lv.size < 2:
        return
    first_leaf = int(lv[-2])
    inf = np.float32(np.inf)
    for j in range(int(lv[-1]) - first_leaf):
        lo: list = [inf] * 4
        hi: list = [-inf] * 4
        bad = flag = False
        for e in range(j * leaf_size, min(T, j * leaf_size + leaf_size)):
            if start is None:
                q0, q1 = 2 * e, 2 * e + 2
            else:
                s, t = start[e], start[e + 1]
                flag |= (t - s) == 1
                q0, q1 = plain(s), plain(t)
            for q in range(base + q0, base + q1):
                v = [read32(planes, (q, c), False) for c in range(4)]
                bad |= v[0] != v[0]
                lo = [x if x < y else y for x, y in zip(v, lo)]
                hi = [x if x > y else y for x, y in zip(v, hi)]
        for c in range(4):
            box[first_leaf + j, c] = -inf if bad else plain(lo[c])
            box[first_leaf + j, 4 + c] = inf if bad else plain(hi[c])
        boundary[first_leaf + j] = flag
    for level in range(lv.size - 3, -1, -1):
        first, below, end = int(lv[level]), int(lv[level + 1]), int(lv[level + 2])
        for j in range(below - first):
            lo, hi = [inf] * 4, [-inf] * 4
            flag = False
            for k in range(below + j * fanout, min(end, below + j * fanout + fanout)):
                clo = [read32(box, (k, c), False) for c in range(4)]
                chi = [read32(box, (k, 4 + c), False) for c in range(4)]
                lo = [x if x < y else y for x, y in zip(clo, lo)]
                hi = [x if x > y else y for x, y in zip(chi, hi)]
                flag |= bool(plain(boundary[k]))
            for c in range(4):
                box[first + j, c], box[first + j, 4 + c] = plain(lo[c]), plain(hi[c])
            boundary[first + j] = flag


def _counted_radix_argsort(keys: Memory, n: int, key_bits: int, counter: OpCounter) -> Memory:
    """The compiled radix sort on counting arithmetic, as a stable argsort (digit extraction is index arithmetic)."""
    bits = digit_bits(n)
    radix = 1 << bits
    k, idx = Memory(np.array(keys.data, dtype=np.uint64), counter), Memory(np.arange(n, dtype=np.int64), counter)
    k2, idx2 = Memory(np.zeros(n, dtype=np.uint64), counter), Memory(np.zeros(n, dtype=np.int64), counter)
    for shift in range(0, key_bits if n else 0, bits):
        hist = Memory(np.zeros(radix + 1, dtype=np.int64), counter)
        for i in range(n):
            d = (int(plain(k[i])) >> shift) & (radix - 1)
            hist[d + 1] = hist[d + 1] + 1
        for d in range(radix):
            hist[d + 1] = hist[d + 1] + hist[d]
        for i in range(n):
            key = k[i]
            d = (int(plain(key)) >> shift) & (radix - 1)
            slot = hist[d]
            k2[plain(slot)] = key
            idx2[plain(slot)] = idx[i]
            hist[d] = slot + 1
        k, k2, idx, idx2 = k2, k, idx2, idx
    return idx


# ---- the query ----------------------------------------------------------------------------------------------
def pretest_naive(light: Light, p0_max: float, counter: OpCounter) -> tuple[list, Num | float]:
    """:func:`.tree.pretest` on counting arithmetic (:func:`.tree.setup_cost`): the same ``s`` (as
    float32 values) and ``thr``."""
    lv = Memory(np.asarray(light.vector, dtype=np.float64), counter)
    v = [lv[c] for c in range(3)]
    a = [_abs(x) for x in v]
    m = a[0] if a[0] > a[1] else a[1]
    m = m if m > a[2] else a[2]
    if isinstance(light, DirectionalLight):
        low, high = m >= 1.0 / PRETEST_RANGE, m <= PRETEST_RANGE
        if not (low and high):
            return [np.float32(0.0)] * 3, math.inf
        scale = 2.0 ** -math.frexp(plain(m))[1]  # the exponent: index arithmetic
        s = [x * scale for x in v]
        thr = (_abs(s[0]) + _abs(s[1]) + _abs(s[2])) * PRETEST_MARGIN
        return [np.float32(plain(x)) for x in s], Num(up32(plain(thr)), counter)  # rounded up: not an operation
    q = m * 3.0 + Num(p0_max, counter) * 5.0
    low, high = q >= 2.0**-100, q <= PRETEST_RANGE
    if not (low and high):
        return [np.float32(0.0)] * 3, math.inf
    return [np.float32(0.0)] * 3, q * PRETEST_MARGIN


def query_naive(mesh: Mesh, tree: Hierarchy, light: Light, counter: OpCounter) -> tuple[np.ndarray, dict, int]:
    """:func:`~silcount.detectors.hierarchy.query.query_fast` on counting arithmetic."""
    directional = isinstance(light, DirectionalLight)
    s, thr_num = pretest_naive(light, tree.p0_max, counter)
    thr = np.float64(plain(thr_num))  # compared in float64, never rounded to float32
    L = [float(x) for x in light.vector]  # the light, already read (in the pre-test's 3 R)
    p0_plain, nrm_plain = edge_faces(mesh)[:2]
    p0, nrm = Memory(p0_plain, counter), Memory(nrm_plain, counter)
    box, boundary = Memory(tree.box, counter), Memory(tree.boundary, counter)
    planes, order, start = Memory(tree.planes, counter), Memory(tree.order, counter), Memory(tree.other_start, counter)
    csr_start, csr_sides = (Memory(a, counter) for a in mesh.edge_sides)
    side_face = Memory(mesh.side_face, counter)
    steps = dict.fromkeys(STEP_NAMES, 0)
    out: list[int] = []
    ties = 0

    def sign(q: int, e: int, h: int) -> Num:
        """Face row ``q`` (side ``h`` of the edge at leaf position ``e``) lit: the pre-test where it decides, else
        the exact value (``face_exact``), the face found through the mesh's edge-to-side table."""
        nonlocal ties
        steps["face_test"] += 1
        u = [read32(planes, (q, c), not directional) for c in range(3)]
        if directional:
            w = Num(s[0], counter) * u[0] + Num(s[1], counter) * u[1] + Num(s[2], counter) * u[2]
        else:
            w = L[0] * u[0] + L[1] * u[1] + L[2] * u[2] - read32(planes, (q, 3), True)
        if Num(np.float64(abs(plain(w))), counter) > thr:
            return Num(int(w > 0.0), counter)
        steps["face_exact"] += 1
        f = plain(side_face[plain(csr_sides[plain(csr_start[plain(order[e])]) + h])])
        n = [nrm[f, c] for c in range(3)]
        a = L if directional else [L[c] - p0[f, c] for c in range(3)]
        v = a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
        ties += plain(v) == 0.0
        return Num(int(v > 0.0), counter)

    def test_edge(e: int, q0: int, q1: int) -> None:
        steps["edge_test"] += 1
        count: Num | int = 0
        for q in range(q0, q1):
            count = sign(q, e, q - q0) + count
        if count == 1:
            out.append(int(plain(order[e])))
            counter.tick("write")  # into the output
            steps["add"] += 1

    for pairs in (True, False):
        lv = tree.pair_levels if pairs else tree.other_levels
        lo_e = 0 if pairs else tree.n_pairs
        T = tree.n_pairs if pairs else tree.order.size - tree.n_pairs
        frontier = [0] if lv.size > 1 else []
        for level in range(lv.size - 1):
            leaf = level == lv.size - 2
            nxt: list[int] = []
            for j in frontier:
                i = int(lv[level]) + j
                steps["node_test"] += 1
                lb, ub = _counted_bounds(box, i, s, L, directional)
                if lb > thr:
                    if not plain(boundary[i]):
                        steps["node_lit"] += 1
                        continue
                    steps["node_lit_open"] += 1
                elif ub < -thr:
                    steps["node_unlit"] += 1
                    continue
                if not leaf:
                    steps["node_open"] += 1
                    below = int(lv[level + 2] - lv[level + 1])
                    nxt += range(j * tree.fanout, min(j * tree.fanout + tree.fanout, below))
                    continue
                steps["leaf_open"] += 1
                for e in range(j * tree.leaf_size, min(T, j * tree.leaf_size + tree.leaf_size)):
                    if pairs:
                        test_edge(e, 2 * e, 2 * e + 2)
                    else:
                        steps["edge_test_other"] += 1
                        base = 2 * tree.n_pairs
                        test_edge(lo_e + e, base + plain(start[e]), base + plain(start[e + 1]))
            frontier = nxt
    return np.asarray(out, dtype=np.int64), steps, int(ties)


def _counted_bounds(box: Memory, i: int, s: list, L: list, directional: bool) -> tuple[Num, Num]:
    """Node ``i``'s lower and upper bounds of its faces' pre-test values, as the compiled walk computes them."""
    lb = ub = None
    for c in range(3):
        lo_c, hi_c = read32(box, (i, c), not directional), read32(box, (i, 4 + c), not directional)
        a = s[c] if directional else L[c]
        p, q = lo_c * a, hi_c * a
        lo, hi = (p, q) if p <= q else (q, p)
        lb, ub = (lo, hi) if c == 0 else (lb + lo, ub + hi)
    assert lb is not None and ub is not None
    if not directional:
        lb = lb - read32(box, (i, 7), True)
        ub = ub - read32(box, (i, 3), True)
    return Num(np.float64(plain(lb)), lb.counter), Num(np.float64(plain(ub)), ub.counter)


__all__ = ["build_naive", "query_naive", "pretest_naive", "read32"]
