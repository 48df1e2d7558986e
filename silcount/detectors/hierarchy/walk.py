"""The compiled query over a bounded plane hierarchy: each tree level by level, its subtrees in parallel.

:func:`query` answers one light on a :class:`.tree.Hierarchy`.  It walks
each tree's level-order boxes from its root, skipping every node whose bounds
prove all its faces lit or all unlit (the proof is in :mod:`.tree`), and
tests the edges of the leaves it reaches by the reference rule, each face by
its float32 pre-test and, where that cannot decide, exactly.  The nodes,
edges and faces it tests are those of :func:`.naive.query_naive`,
which takes the same walk on counting arithmetic.

Layout of the walk: a level's frontier (the nodes whose parents were opened,
ascending) is read forwards and the opened nodes' children make the next
frontier, written without a branch on the decision.  A leaf of the pair tree
is one run of 2 x 16-byte planes an edge: its edges are pre-tested in one
branch-free pass, and only a leaf where some pre-test cannot decide is
passed again, evaluating exactly the faces it could not decide.  The levels
above :data:`.tree.TASK_LEVEL` are walked first; the subtrees rooted on
it that the walk reaches are then shared out between the threads (task
``t`` to thread ``t mod threads``), each writing its edges from its first
edge position, and the runs are compacted in order.  :func:`query_serial` walks
each tree whole on the caller's thread, outside any parallel region (for small
trees, :data:`.query.PARALLEL_NODES`).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from silcount.detectors.hierarchy.prefetch import prefetch

# ``stats`` slots: the STEP_NAMES of .hierarchy but 'add' (the returned count), then the ties
NODE_TEST, NODE_LIT, NODE_LIT_OPEN, NODE_UNLIT, NODE_OPEN, LEAF_OPEN, EDGE_TEST, EDGE_OTHER, FACE_TEST, FACE_EXACT = (
    range(10)
)
TIES = 10
N_STATS = 11


AHEAD = 8  # leaves (or frontier nodes) ahead whose memory is asked for before it is read


@njit(cache=True, inline="always")
def _exact(p0, nrm, f, lx, ly, lz, directional):  # pragma: no cover - compiled
    """``d . n`` or ``(L - p0) . n`` of face ``f``, in :func:`.adjacency.facing_flags`' operation order."""
    if directional:
        return lx * nrm[f, 0] + ly * nrm[f, 1] + lz * nrm[f, 2]
    return (lx - p0[f, 0]) * nrm[f, 0] + (ly - p0[f, 1]) * nrm[f, 1] + (lz - p0[f, 2]) * nrm[f, 2]


@njit(cache=True, inline="always")
def _w32(planes, q, s):  # pragma: no cover - compiled
    """Face row ``q``'s pre-test value under a directional light, in float32."""
    return (s[0] * planes[q, 0] + s[1] * planes[q, 1]) + s[2] * planes[q, 2]


@njit(cache=True, inline="always")
def _w64(planes, q, light):  # pragma: no cover - compiled
    """Face row ``q``'s pre-test value under a point light, in float64 (the plane widened exactly)."""
    return ((light[0] * planes[q, 0] + light[1] * planes[q, 1]) + light[2] * planes[q, 2]) - planes[q, 3]


@njit(cache=True, inline="always")
def _face_lit(planes, q, e, h, mesh_csr, p0, nrm, light, s, thr, thr32, directional,
              stats):  # fmt: skip  # pragma: no cover - compiled
    """Face row ``q`` (side ``h`` of edge ``e``) lit: by its pre-test where ``|w| > thr`` (float32 under a
    directional light, whose ``thr`` is a float32, :func:`.tree.pretest`), else by its exact value
    (``face_exact``; a 0 is a tie), the face found through the mesh's edge-to-side CSR ``mesh_csr``."""
    if directional:
        w32 = _w32(planes, q, s)
        if abs(w32) > thr32:
            return w32 > 0
    else:
        w = _w64(planes, q, light)
        if abs(w) > thr:
            return w > 0.0
    start, sides, side_face = mesh_csr
    v = _exact(p0, nrm, side_face[sides[start[e] + h]], light[0], light[1], light[2], directional)
    stats[FACE_EXACT] += 1
    stats[TIES] += v == 0.0
    return v > 0.0


@njit(cache=True)
def _pair_leaves(leaves, n, leaf_size, order, mesh_csr, planes, p0, nrm, light, s, thr, thr32, directional, out, k,
                 stats):  # fmt: skip  # pragma: no cover - compiled
    """The two-faced edges of ``leaves[:n]`` (face rows ``2 e``, ``2 e + 1``): silhouette ids into ``out[k:]``;
    returns the new ``k``.

    Per leaf one branch-free pass of pre-tests; only if one of them cannot decide, the leaf again with
    :func:`_face_lit` (each face's pre-test again, the exact value where it cannot decide).
    """
    T = order.size
    edges = 0
    for t in range(n):
        if t + AHEAD < n:  # a later leaf's rows and ids, asked for now
            ahead = leaves[t + AHEAD] * leaf_size
            for r in range(2 * ahead, 2 * min(T, ahead + leaf_size), 4):
                prefetch(planes, r)
            prefetch(order, ahead)
        lo = leaves[t] * leaf_size
        hi = min(T, lo + leaf_size)
        edges += hi - lo
        k0 = k
        undecided = False
        if directional:
            for e in range(lo, hi):
                wa = _w32(planes, 2 * e, s)
                wb = _w32(planes, 2 * e + 1, s)
                undecided |= not (abs(wa) > thr32 and abs(wb) > thr32)
                out[k] = order[e]  # kept only if exactly one face is lit (no branch on the answer)
                k += (wa > 0) != (wb > 0)
        else:
            for e in range(lo, hi):
                wa = _w64(planes, 2 * e, light)
                wb = _w64(planes, 2 * e + 1, light)
                undecided |= not (abs(wa) > thr and abs(wb) > thr)
                out[k] = order[e]
                k += (wa > 0.0) != (wb > 0.0)
        if undecided:
            k = k0
            for e in range(lo, hi):
                a = _face_lit(planes, 2 * e, order[e], 0, mesh_csr, p0, nrm, light, s, thr, thr32, directional, stats)
                b = _face_lit(planes, 2 * e + 1, order[e], 1, mesh_csr, p0, nrm, light, s, thr, thr32, directional,
                              stats)  # fmt: skip
                out[k] = order[e]
                k += a != b
    stats[EDGE_TEST] += edges
    stats[FACE_TEST] += 2 * edges
    return k


@njit(cache=True)
def _other_leaves(leaves, n, leaf_size, order, start, mesh_csr, planes, p0, nrm, light, s, thr, thr32, directional,
                  out, k, stats):  # fmt: skip  # pragma: no cover - compiled
    """The other edges of ``leaves[:n]`` (their faces' rows ``start[e] .. start[e + 1]``): as :func:`_pair_leaves`."""
    T = order.size
    edges = sides = 0
    for t in range(n):
        if t + AHEAD < n:
            ahead = leaves[t + AHEAD] * leaf_size
            for r in range(start[ahead], start[min(T, ahead + leaf_size)], 4):
                prefetch(planes, r)
        lo = leaves[t] * leaf_size
        hi = min(T, lo + leaf_size)
        edges += hi - lo
        sides += start[hi] - start[lo]
        k0 = k
        undecided = False
        for e in range(lo, hi):
            count = 0
            for q in range(start[e], start[e + 1]):
                if directional:
                    w32 = _w32(planes, q, s)
                    undecided |= not abs(w32) > thr32
                    count += w32 > 0
                else:
                    w = _w64(planes, q, light)
                    undecided |= not abs(w) > thr
                    count += w > 0.0
            out[k] = order[e]
            k += count == 1
        if undecided:
            k = k0
            for e in range(lo, hi):
                count = 0
                for q in range(start[e], start[e + 1]):
                    count += _face_lit(planes, q, order[e], q - start[e], mesh_csr, p0, nrm, light, s, thr, thr32,
                                       directional, stats)  # fmt: skip
                out[k] = order[e]
                k += count == 1
    stats[EDGE_TEST] += edges
    stats[EDGE_OTHER] += edges
    stats[FACE_TEST] += sides
    return k


@njit(cache=True, inline="always")
def _decide(box, i, s, light, thr, thr32, directional):  # pragma: no cover - compiled
    """Node ``i``'s bounds decide: 1 every face lit, -1 every face unlit, 0 neither (see :mod:`.tree`)."""
    if directional:
        lb = ub = np.float32(0.0)
        for c in range(3):
            a = s[c] * box[i, c]
            b = s[c] * box[i, 4 + c]
            if a <= b:
                lo, hi = a, b
            else:
                lo, hi = b, a
            lb, ub = (lo, hi) if c == 0 else (lb + lo, ub + hi)
        if lb > thr32:
            return 1
        if ub < -thr32:
            return -1
        return 0
    lb64 = ub64 = 0.0
    for c in range(3):
        a = light[c] * np.float64(box[i, c])
        b = light[c] * np.float64(box[i, 4 + c])
        if a <= b:
            lo64, hi64 = a, b
        else:
            lo64, hi64 = b, a
        lb64, ub64 = (lo64, hi64) if c == 0 else (lb64 + lo64, ub64 + hi64)
    lb64 = lb64 - np.float64(box[i, 7])
    ub64 = ub64 - np.float64(box[i, 3])
    if lb64 > thr:
        return 1
    if ub64 < -thr:
        return -1
    return 0


@njit(cache=True)
def _walk(pairs, lv, level, j0, box, boundary, leaf_size, fanout, order, start, mesh_csr, planes, p0, nrm, light, s,
          thr, thr32, directional, out, k, stats, buf, task_level, tasks):  # fmt: skip  # pragma: no cover - compiled
    """One tree (``pairs``: the pair tree, else the other) from node ``j0`` of ``level``, level by level.

    ``lv``: the tree's level starts; ``order``, ``planes``, ``start``: that tree's slices; ``mesh_csr``: the
    mesh's edge-to-side CSR and each side's face (``start``, ``sides``, ``side_face``), for exact values.  Edge
    ids into ``out[k:]``; returns the new ``k``.  ``buf`` holds two frontiers (each the subtree's widest level
    plus a fan-out).  With ``task_level >= 0`` the children on that level are not tested but appended to
    ``tasks`` (``tasks[0]`` counts them).  A node is tested iff every ancestor was opened, as in
    :func:`.naive.query_naive`.
    """
    D = lv.size - 1
    half = buf.size // 2
    cur, nxt = buf[:half], buf[half:]
    cur[0] = j0
    n = 1
    tested = lit = lit_open = unlit = opened = leaves = 0
    while n > 0:
        first = lv[level]
        leaf = level == D - 1
        below = 0 if leaf else lv[level + 2] - lv[level + 1]
        m = 0
        for t in range(n):
            if t + AHEAD < n:
                prefetch(box, first + cur[t + AHEAD])
            j = cur[t]
            i = first + j
            d = _decide(box, i, s, light, thr, thr32, directional)
            b = boundary[i]
            lit += (d == 1) and not b
            lit_open += (d == 1) and b
            unlit += d == -1
            keep = d == 0 or (d == 1 and b)
            if leaf:  # the leaves opened on this level, listed; their edges are tested below
                nxt[m] = j
                m += keep
                continue
            opened += keep
            c0 = j * fanout
            count = min(fanout, below - c0) * keep
            if level + 1 == task_level:
                for c in range(count):
                    tasks[tasks[0] + 1 + c] = c0 + c
                tasks[0] += count
            else:
                for c in range(fanout):
                    nxt[m + c] = c0 + c
                m += count
        if leaf:
            leaves = m
            if pairs:
                k = _pair_leaves(nxt, m, leaf_size, order, mesh_csr, planes, p0, nrm, light, s, thr, thr32, directional,
                                 out, k, stats)  # fmt: skip
            else:
                k = _other_leaves(nxt, m, leaf_size, order, start, mesh_csr, planes, p0, nrm, light, s, thr, thr32,
                                  directional, out, k, stats)  # fmt: skip
            m = 0
        tested += n
        cur, nxt = nxt, cur
        n = m
        level += 1
    stats[NODE_TEST] += tested
    stats[NODE_LIT] += lit
    stats[NODE_LIT_OPEN] += lit_open
    stats[NODE_UNLIT] += unlit
    stats[NODE_OPEN] += opened
    stats[LEAF_OPEN] += leaves
    return k


@njit(cache=True)
def _span(lv, level, fanout):  # pragma: no cover - compiled
    """The widest level of a subtree rooted on ``level`` (its leaves, at most)."""
    return fanout ** (lv.size - 2 - level)


@njit(cache=True)
def _tree_top(tr, box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes, other_start, mesh_csr,
              p0, nrm, light, s, thr, thr32, directional, out, stats, task_level,
              tasks):  # fmt: skip  # pragma: no cover - compiled
    """Tree ``tr`` (0: the pair tree, 1: the other) walked from its root on this thread, down to ``task_level``
    if the tree is deeper (the subtrees there appended to ``tasks``, :func:`_walk`), else whole; its edge ids
    into ``out`` from the tree's first position (0, or ``n_pairs``): their count."""
    pairs = tr == 0
    lv = pair_lv if pairs else other_lv
    if lv.size < 2:
        return 0
    lo = 0 if pairs else n_pairs
    hi = n_pairs if pairs else order.size
    st = other_start if not pairs else other_start[:1]
    fbase = 0 if pairs else 2 * n_pairs
    split = task_level if (task_level >= 0 and lv.size - 1 > task_level) else -1
    widest = lv[1] - lv[0]
    for lvl in range(lv.size - 1):
        if split < 0 or lvl <= split:
            widest = max(widest, lv[lvl + 1] - lv[lvl])
    buf = np.empty(2 * (widest + fanout), dtype=np.int64)
    return _walk(pairs, lv, 0, 0, box, boundary, leaf_size, fanout, order[lo:hi], st, mesh_csr, planes[fbase:], p0,
                 nrm, light, s, thr, thr32, directional, out[lo:], 0, stats, buf, split, tasks)  # fmt: skip


@njit(cache=True)
def query_serial(box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes, other_start, mesh_csr,
                 p0, nrm, light, s, thr, directional, out, stats):  # fmt: skip  # pragma: no cover - compiled
    """:func:`query` with each tree walked whole on the caller's thread, outside any parallel region (so
    numba's thread pool is neither woken nor resized): the same ids, in the same order, and the same steps."""
    thr32 = np.float32(thr)
    no_tasks = np.zeros(1, dtype=np.int64)
    k = _tree_top(0, box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes, other_start,
                  mesh_csr, p0, nrm, light, s, thr, thr32, directional, out, stats, -1, no_tasks)  # fmt: skip
    m = _tree_top(1, box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes, other_start,
                  mesh_csr, p0, nrm, light, s, thr, thr32, directional, out, stats, -1, no_tasks)  # fmt: skip
    for j in range(m):  # the other tree's run, after the pair tree's
        out[k + j] = out[n_pairs + j]
    return k + m


@njit(cache=True, parallel=True)
def query(box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes, other_start, mesh_csr, p0, nrm,
          light, s, thr, directional, out, stats, task_level, threads):  # fmt: skip  # pragma: no cover - compiled
    """Silhouette edge ids into ``out`` (pair tree, then other tree; ascending by leaf position): their count.

    ``task_level < 0``: each tree walked whole on this thread.  Otherwise each tree deeper than
    ``task_level`` is walked down to it, and the subtrees rooted there that the walk reaches are walked by
    ``threads`` threads; the step counts are those of one serial walk (every node is tested once either way).
    """
    n_trees = 2
    T = order.size
    thr32 = np.float32(thr)  # exact: a directional light's thr is a float32 (.hierarchy.pretest)
    n_tasks_max = 1
    for tr in range(n_trees):
        lv = pair_lv if tr == 0 else other_lv
        if task_level >= 0 and lv.size - 1 > task_level:
            n_tasks_max += lv[task_level + 1] - lv[task_level]
    tasks = np.zeros((n_trees, n_tasks_max), dtype=np.int64)
    run_base = np.zeros(n_trees, dtype=np.int64)
    run_count = np.zeros(n_trees, dtype=np.int64)
    for tr in range(n_trees):  # the top of each tree (or all of it)
        run_base[tr] = 0 if tr == 0 else n_pairs
        run_count[tr] = _tree_top(tr, box, boundary, pair_lv, other_lv, leaf_size, fanout, order, n_pairs, planes,
                                  other_start, mesh_csr, p0, nrm, light, s, thr, thr32, directional, out, stats,
                                  task_level, tasks[tr])  # fmt: skip
    total = tasks[0, 0] + tasks[1, 0]
    # the reached subtrees on task_level, both trees' in order, shared out between the threads
    tree_of = np.empty(total, dtype=np.int64)
    node_of = np.empty(total, dtype=np.int64)
    w = 0
    for tr in range(n_trees):
        for t in range(tasks[tr, 0]):
            tree_of[w] = tr
            node_of[w] = tasks[tr, t + 1]
            w += 1
    counts = np.zeros(total, dtype=np.int64)
    bases = np.zeros(total, dtype=np.int64)
    t_stats = np.zeros((threads, stats.size), dtype=np.int64)
    for th in prange(threads):
        bufs = np.empty(0, dtype=np.int64)
        for t in range(th, total, threads):
            pairs = tree_of[t] == 0
            lv = pair_lv if pairs else other_lv
            lo = 0 if pairs else n_pairs
            hi = n_pairs if pairs else T
            st = other_start if not pairs else other_start[:1]
            fbase = 0 if pairs else 2 * n_pairs
            span = _span(lv, task_level, fanout)
            if bufs.size < 2 * (span + fanout):
                bufs = np.empty(2 * (span + fanout), dtype=np.int64)
            base = node_of[t] * span * leaf_size  # the subtree's first edge position in its tree
            bases[t] = lo + base
            counts[t] = _walk(pairs, lv, task_level, node_of[t], box, boundary, leaf_size, fanout, order[lo:hi], st,
                              mesh_csr, planes[fbase:], p0, nrm, light, s, thr, thr32, directional, out[lo:], base,
                              t_stats[th], bufs, -1, tasks[0, :1]) - base  # fmt: skip
    k = 0
    t = 0
    for tr in range(n_trees):  # the runs compacted in order: a tree's own run (if shallow), else its tasks'
        for j in range(run_count[tr]):
            out[k + j] = out[run_base[tr] + j]
        k += run_count[tr]
        while t < total and tree_of[t] == tr:
            for j in range(counts[t]):
                out[k + j] = out[bases[t] + j]
            k += counts[t]
            t += 1
    for th in range(threads):
        stats += t_stats[th]
    return k


__all__ = ["query", "query_serial", "N_STATS", "TIES"]
