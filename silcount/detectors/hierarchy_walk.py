"""The compiled walk over a bounded edge hierarchy: level by level, with a float32 pre-test of faces.

:func:`query_parallel` (and :func:`query_serial`, for small trees) answer one
light on a :class:`.hierarchy.Hierarchy`.  They walk the level-order boxes from
the root, skipping every node whose boxes prove all its faces lit or all unlit
(the proof is in :mod:`.hierarchy`'s docstring), and test the edges of the
leaves they reach by the reference rule.  Each face's sign is first decided
from its float32 plane where that is provably right (:func:`pretest`).  The
nodes, edges and faces they test are those of
:func:`.hierarchy_naive.query_naive`'s depth-first walk (docs/literature.md,
"The compiled query").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from silcount.mesh.lights import DirectionalLight, Light


@njit(cache=True)
def _facing_value(p0, nrm, f, lx, ly, lz, directional):  # pragma: no cover - compiled
    """``d . n`` or ``(L - p0) . n`` of local face ``f``, in :func:`.adjacency.facing_flags`' operation order."""
    if directional:
        return lx * nrm[f, 0] + ly * nrm[f, 1] + lz * nrm[f, 2]
    return (lx - p0[f, 0]) * nrm[f, 0] + (ly - p0[f, 1]) * nrm[f, 1] + (lz - p0[f, 2]) * nrm[f, 2]


@njit(cache=True)
def _test_edges(starts, faces, ids, lo, hi, p0, nrm, plane, light, l32, thr, directional, out, k,
                stats):  # fmt: skip  # pragma: no cover - compiled
    """The reference rule for edges ``lo .. hi - 1`` of a face CSR: exactly one face lit; returns the new ``k``.

    Each face is first pre-tested with its float32 plane (:func:`pretest`): ``l32 . u`` in float32
    under a directional light, ``L . u - c`` in float64 under a point light; beyond ``thr`` either way
    its facing value's sign is proved and is not 0; otherwise the exact value is evaluated.  Adds the edges
    tested, their faces evaluated and the ties among them to ``stats`` 6, 7 and 9.
    """
    lx, ly, lz = light[0], light[1], light[2]
    dx, dy, dz = l32[0], l32[1], l32[2]
    ties = 0
    for e in range(lo, hi):
        count = 0
        for q in range(starts[e], starts[e + 1]):
            f = faces[q]
            if directional:
                w = dx * plane[f, 0] + dy * plane[f, 1] + dz * plane[f, 2]  # float32
                if abs(w) > thr:  # the sign is proved (a NaN fails): no branch on it
                    count += w > 0.0
                    continue
            else:
                wp = ((lx * plane[f, 0] + ly * plane[f, 1]) + lz * plane[f, 2]) - plane[f, 3]  # float64
                if abs(wp) > thr:
                    count += wp > 0.0
                    continue
            d = _facing_value(p0, nrm, f, lx, ly, lz, directional)
            ties += d == 0.0
            count += d > 0.0
        out[k] = ids[e]  # kept only if the edge has exactly one lit face (no branch on the answer)
        k += count == 1
    if hi > lo:
        stats[6] += hi - lo
        stats[7] += starts[hi] - starts[lo]
        stats[9] += ties
    return k


@njit(cache=True, inline="always")
def _products(a, n_lo, n_hi):  # pragma: no cover - compiled
    """``fl(a n_lo)`` and ``fl(a n_hi)``, smaller first (one compare, as the counted ``_ordered``)."""
    p = a * n_lo
    q = a * n_hi
    if p <= q:
        return p, q
    return q, p


@njit(cache=True, inline="always")
def _axis(lc, n_lo, n_hi, p_lo, p_hi, directional):  # pragma: no cover - compiled
    """The extremes of one axis's rounded term ``fl(a n)`` over a node's boxes (at their corners).

    ``a`` is the light's coordinate ``lc`` (directional) or ``fl(lc - p)`` for ``p`` in ``[p_lo, p_hi]``,
    whose extremes are ``fl(lc - p_hi)`` and ``fl(lc - p_lo)``; ``n`` is in ``[n_lo, n_hi]``.
    """
    if directional:
        return _products(lc, n_lo, n_hi)
    lo_c, hi_c = _products(lc - p_hi, n_lo, n_hi)
    lo2, hi2 = _products(lc - p_lo, n_lo, n_hi)
    if lo2 < lo_c:
        lo_c = lo2
    if hi2 > hi_c:
        hi_c = hi2
    return lo_c, hi_c


@njit(cache=True)
def _walk(level, j0, nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, p0, nrm, plane,
          light, l32, thr, directional, out, k, stats, buf, task_level, tasks):  # fmt: skip  # pragma: no cover
    """Level by level from node ``j0`` of ``level``: edge ids into ``out[k:]``; the new ``k``.

    The frontier (the nodes of one level whose parents were opened, ascending) is read forwards, and
    the opened nodes' children make the next one; ``buf`` holds two frontiers (each as long as the
    subtree's widest level).  A node the bounds decide is skipped with its subtree.  With
    ``task_level >= 0`` the children on that level are not tested but appended to ``tasks``
    (``tasks[0]`` counts them), for :func:`query_parallel` to run in parallel.  ``stats`` (in
    :data:`.hierarchy.STEP_NAMES` order, then ties): node tests, nodes proved all lit, all lit but opened
    (a boundary edge below), all unlit, internal nodes opened, leaves opened, edges tested, their faces
    evaluated, (unused), face ties among the evaluations.  The nodes tested are those of the depth-first
    walk of :func:`.hierarchy_naive.query_naive` (a node is tested iff every ancestor was opened), and
    the three axes' terms are summed in axis order, as it sums them.
    """
    lx, ly, lz = light[0], light[1], light[2]
    D = level_start.size - 1
    T = order.size
    half = buf.size // 2
    cur, nxt = buf[:half], buf[half:]
    cur[0] = j0
    n = 1
    tested = lit = lit_open = unlit = opened = leaves = 0
    while n > 0:
        first = level_start[level]
        leaf = level == D - 1
        m = 0
        for t in range(n):
            j = cur[t]
            i = first + j
            tested += 1
            if directional:
                x0, x1 = _products(lx, nbox[i, 0], nbox[i, 3])
                y0, y1 = _products(ly, nbox[i, 1], nbox[i, 4])
                z0, z1 = _products(lz, nbox[i, 2], nbox[i, 5])
            else:
                x0, x1 = _axis(lx, nbox[i, 0], nbox[i, 3], pbox[i, 0], pbox[i, 3], False)
                y0, y1 = _axis(ly, nbox[i, 1], nbox[i, 4], pbox[i, 1], pbox[i, 4], False)
                z0, z1 = _axis(lz, nbox[i, 2], nbox[i, 5], pbox[i, 2], pbox[i, 5], False)
            lb = (x0 + y0) + z0
            ub = (x1 + y1) + z1
            if lb > 0.0:
                if not boundary[i]:
                    lit += 1
                    continue
                lit_open += 1
            elif ub <= 0.0:
                unlit += 1
                continue
            if leaf:
                leaves += 1
                k = _test_edges(e_start, e_faces, order, j * leaf_size, min(j * leaf_size + leaf_size, T), p0, nrm,
                                plane, light, l32, thr, directional, out, k, stats)  # fmt: skip
                continue
            opened += 1
            hi = min(j * fanout + fanout, level_start[level + 2] - level_start[level + 1])
            if level + 1 == task_level:
                for c in range(j * fanout, hi):
                    tasks[0] += 1
                    tasks[tasks[0]] = c
            else:
                for c in range(j * fanout, hi):
                    nxt[m] = c
                    m += 1
        cur, nxt = nxt, cur
        n = m
        level += 1
    stats[0] += tested
    stats[1] += lit
    stats[2] += lit_open
    stats[3] += unlit
    stats[4] += opened
    stats[5] += leaves
    return k


TASK_LEVEL = 3  # subtrees rooted on this level are the parallel tasks (64 with the default fan-out)


@njit(cache=True)
def query_serial(nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, rest, r_start, r_faces,
                 p0, nrm, plane, light, l32, thr, directional, out, stats):  # fmt: skip  # pragma: no cover - compiled
    """:func:`query_parallel` in one thread: the whole walk, then ``rest``."""
    k = 0
    if level_start.size > 1:
        widest = np.max(level_start[1:] - level_start[:-1])
        k = _walk(0, 0, nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, p0, nrm, plane,
                  light, l32, thr, directional, out, 0, stats, np.empty(2 * widest, dtype=np.int64), -1,
                  np.zeros(1, dtype=np.int64))  # fmt: skip
    return _test_edges(r_start, r_faces, rest, 0, rest.size, p0, nrm, plane, light, l32, thr, directional, out, k,
                       stats)  # fmt: skip


@njit(cache=True, parallel=True)
def query_parallel(nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, rest, r_start,
                   r_faces, p0, nrm, plane, light, l32, thr, directional, out, stats,
                   task_level):  # fmt: skip  # pragma: no cover - compiled
    """Silhouette edge ids into ``out``, ascending by position (tree edges in leaf order, then ``rest``).

    The levels above ``task_level`` are walked first; the subtrees rooted on it that this walk reaches
    are then walked in parallel, each writing from its first edge position; the runs are compacted in
    order.  The steps are those of one serial walk: each node is tested exactly once either way.
    """
    D = level_start.size - 1
    k = 0
    if D <= task_level:  # no level to split on
        return query_serial(nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, rest,
                             r_start, r_faces, p0, nrm, plane, light, l32, thr, directional, out, stats)  # fmt: skip
    width = level_start[task_level] - level_start[task_level - 1]  # the widest level above the split
    tasks = np.zeros(level_start[task_level + 1] - level_start[task_level] + 1, dtype=np.int64)
    k = _walk(0, 0, nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order, p0, nrm, plane,
              light, l32, thr, directional, out, 0, stats, np.empty(2 * width, dtype=np.int64), task_level,
              tasks)  # fmt: skip
    n_tasks = tasks[0]
    span = fanout ** (D - 1 - task_level)  # a task's leaves (at most), so its widest level
    counts = np.zeros(n_tasks, dtype=np.int64)
    t_stats = np.zeros((n_tasks, stats.size), dtype=np.int64)
    bufs = np.empty((n_tasks, 2 * span), dtype=np.int64)
    for t in prange(n_tasks):
        j = tasks[t + 1]
        base = j * span * leaf_size
        counts[t] = _walk(task_level, j, nbox, pbox, boundary, level_start, leaf_size, fanout, e_start, e_faces, order,
                          p0, nrm, plane, light, l32, thr, directional, out, base, t_stats[t], bufs[t], -1,
                          tasks[:1]) - base  # fmt: skip
    for t in range(n_tasks):  # the tasks' runs, compacted in order (after the top walk's own)
        base = tasks[t + 1] * span * leaf_size
        for j in range(counts[t]):
            out[k + j] = out[base + j]
        k += counts[t]
        stats += t_stats[t]
    return _test_edges(r_start, r_faces, rest, 0, rest.size, p0, nrm, plane, light, l32, thr, directional, out, k,
                       stats)  # fmt: skip


PRETEST_MARGIN = 2.0**-20  # the pre-test's threshold, relative to the scale of its values (see pretest)
PRETEST_RANGE = 2.0**300  # lights whose scale is outside [1 / PRETEST_RANGE, PRETEST_RANGE] are not pre-tested


def pretest(light: Light, p0_max: float) -> tuple[np.ndarray, float]:
    """The float32 light and the threshold of the compiled query's pre-test of a face (:func:`_test_edges`).

    Each face keeps ``u``, its unit normal, and ``c = p0 . u``, in float32 (:func:`.hierarchy_build.face_planes`:
    each ``u_i`` within ``2**-24`` of the true unit normal ``n^``'s, ``c`` within ``2**-24 |c| + 2**-47.9 |p0|_1``
    of ``p0 . n^``).  ``|w| > thr`` proves the sign of the exact facing value ``v`` (:mod:`.hierarchy`'s
    operation order) and that ``v != 0``:

    * **Directional** ``d``, scaled by a power of two (exact) to ``s`` with largest |component| in ``[1/2, 1)``:
      ``w = fl32(fl32(fl32(s0 u0) + fl32(s1 u1)) + fl32(s2 u2))`` with ``s`` in float32, ``thr = 2**-20 S``,
      ``S = |s|_1 >= 1/2``.  Rounding ``s`` moves ``s . n^`` by at most ``2**-25 S`` (plus ``3 * 2**-150``
      where a component underflows), ``u`` by ``2**-24 S (1 + 2**-24)``, and the float32 sum of three
      products errs by ``gamma_3 = 3 * 2**-24 / (1 - 3 * 2**-24)`` of ``sum |s_i u_i| <= S (1 + 2**-24)^2``:
      in all under ``4.6 * 2**-24 S + 2**-147 < 0.3 thr``.  So ``s . n^`` has ``w``'s sign and
      ``|s . n^| > 0.7 thr``, and ``|d . n| = 2**e |n| |s . n^|`` exceeds float64's error bound for ``v``,
      ``gamma_3 sum |d_i n_i| <= 3.1 * 2**-53 * 2**e |n| S`` plus underflow terms below ``2**-1070`` (``2**e``
      and ``|n|_inf`` are in ``[2**-300, 2**300]``, so ``|d . n| > 2**-622``).
    * **Point** ``L``: ``w = fl(fl(fl(fl(L0 u0) + fl(L1 u1)) + fl(L2 u2)) - c)`` in float64, ``thr = 2**-20 Q``,
      ``Q = 3 |L|_inf + 5 P >= |L|_1 + 5 P`` with ``P = p0_max`` (every pre-tested face has ``|p0_i| <= P``,
      so ``|c| <= 1.01 sqrt(3) P``).  ``L . u`` is within ``2**-24 |L|_1`` of ``L . n^``, ``c`` within
      ``2**-24 * 1.76 P + 2**-47.9 * 3 P`` of ``p0 . n^``, and the float64 sums add ``2**-50 (|L|_1 + 1.8 P)``:
      under ``2**-22 Q = thr / 4``.  So ``(L - p0) . n^`` has ``w``'s sign and magnitude above ``0.75 thr``,
      while ``v``'s own error (``fl(L_i - p0_i)``, three products, two sums) is below ``2**-50.9 |n| Q``;
      with ``Q`` and ``|n|_inf`` in ``[2**-300, 2**300]`` nothing over- or underflows in float64.  ``c`` is a
      float32: point lights are pre-tested only when ``P <= 2**100`` (so ``|c| < 2**102``, far from float32's
      overflow) and ``Q >= 2**-100`` (so the absolute error of a ``c`` or ``u_i`` rounded into float32's
      subnormal range, at most ``2**-150``, stays below ``2**-30 thr``).

    A face with a NaN plane fails both comparisons and is evaluated exactly; so is every face under a
    light whose ``S``'s scale ``2**e`` (directional) is outside ``[2**-300, 2**300]``, or whose ``Q`` (point)
    is outside ``[2**-100, 2**300]`` or ``P > 2**100`` (``thr = inf``).
    """
    v = np.asarray(light.vector, dtype=np.float64)
    if isinstance(light, DirectionalLight):
        m = float(np.abs(v).max())
        if not (1.0 / PRETEST_RANGE <= m <= PRETEST_RANGE):
            return np.zeros(3, dtype=np.float32), math.inf
        s = np.ldexp(v, -int(np.frexp(m)[1]))
        return s.astype(np.float32), PRETEST_MARGIN * float(np.abs(s).sum())
    q = 3.0 * float(np.abs(v).max()) + 5.0 * p0_max  # Python floats: an overflow is inf, silently
    if not (2.0**-100 <= q <= PRETEST_RANGE and p0_max <= 2.0**100):  # c's float32 range (see above)
        return np.zeros(3, dtype=np.float32), math.inf
    return np.zeros(3, dtype=np.float32), PRETEST_MARGIN * q


__all__ = ["query_serial", "query_parallel", "pretest", "PRETEST_MARGIN", "PRETEST_RANGE", "TASK_LEVEL"]
