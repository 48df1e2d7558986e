"""The compiled query over a bounded edge hierarchy, its counted cost, and the detector glue.

:func:`query_fast` walks the tree of :mod:`.hierarchy` depth first, skipping
every node whose boxes prove all its faces lit or all unlit (the proof is
in :mod:`.hierarchy`'s docstring), and tests the edges of the leaves it
reaches by the reference rule.  :func:`query_cost` charges its steps what
:func:`.hierarchy_naive.query_naive` executes for them.  :func:`detect` is
what ``gaussmap`` and ``cones`` call.
"""

from __future__ import annotations

import math
import weakref

import numba
import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import OpCounter
from silcount.detectors.adjacency import facing_flags
from silcount.detectors.base import EngineRun, add_scaled, make_silhouette
from silcount.detectors.hierarchy import FANOUT, LEAF_SIZE, STEP_NAMES, Hierarchy, KeyScheme, build_fast, overflows
from silcount.detectors.hierarchy_naive import build_naive, query_naive
from silcount.detectors.reference import fast_tally as reference_tally
from silcount.detectors.result import Silhouette
from silcount.errors import BadArgument
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh


@njit(cache=True)
def _facing_value(p0, nrm, f, lx, ly, lz, directional):  # pragma: no cover - compiled
    """``d . n`` or ``(L - p0) . n`` of local face ``f``, in :func:`.adjacency.facing_flags`' operation order."""
    if directional:
        return lx * nrm[f, 0] + ly * nrm[f, 1] + lz * nrm[f, 2]
    return (lx - p0[f, 0]) * nrm[f, 0] + (ly - p0[f, 1]) * nrm[f, 1] + (lz - p0[f, 2]) * nrm[f, 2]


@njit(cache=True)
def _test_edges(starts, faces, ids, lo, hi, p0, nrm, lx, ly, lz, directional, out, k, stats):  # pragma: no cover
    """The reference rule for edges ``lo .. hi - 1`` of a face CSR: exactly one face lit; returns the new ``k``.

    Adds the edges tested, their faces evaluated and the ties among them to ``stats`` 6, 7 and 9.
    """
    ties = 0
    for e in range(lo, hi):
        count = 0
        for q in range(starts[e], starts[e + 1]):
            d = _facing_value(p0, nrm, faces[q], lx, ly, lz, directional)
            ties += d == 0.0
            count += d > 0.0
        if count == 1:
            out[k] = ids[e]
            k += 1
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
def _walk(lo, hi, bounds, boundary, nodes, e_start, e_faces, order, p0, nrm, light, directional, out, k, stats,
          tasks, task_depth, depth):  # fmt: skip  # pragma: no cover - compiled
    """The forward pass over nodes ``lo .. hi - 1`` (whole subtrees); edge ids into ``out[k:]``; the new ``k``.

    A node the bounds decide jumps to its skip.  With ``task_depth >= 0`` a node at that depth is not
    tested but appended to ``tasks`` (``tasks[0]`` counts them), for :func:`_query` to run in parallel.
    ``stats`` (in :data:`.hierarchy.STEP_NAMES` order, then ties): node tests, nodes proved all lit,
    all lit but opened (a boundary edge below), all unlit, internal nodes opened, leaves opened, edges
    tested, their faces evaluated, (unused), face ties among the evaluations.  The node counts are kept
    in locals and added to ``stats`` at the end; the three axes' terms are summed in axis order, as
    :func:`.hierarchy_naive.query_naive` sums them.
    """
    lx, ly, lz = light[0], light[1], light[2]
    tested = lit = lit_open = unlit = opened = leaves = 0
    i = lo
    while i < hi:
        skip = nodes[i, 2]
        if task_depth >= 0 and depth[i] == task_depth:
            tasks[0] += 1
            tasks[tasks[0]] = i
            i = skip
            continue
        tested += 1
        x0, x1 = _axis(lx, bounds[i, 0], bounds[i, 3], bounds[i, 6], bounds[i, 9], directional)
        y0, y1 = _axis(ly, bounds[i, 1], bounds[i, 4], bounds[i, 7], bounds[i, 10], directional)
        z0, z1 = _axis(lz, bounds[i, 2], bounds[i, 5], bounds[i, 8], bounds[i, 11], directional)
        lb = (x0 + y0) + z0
        ub = (x1 + y1) + z1
        if lb > 0.0:
            if not boundary[i]:
                lit += 1
                i = skip
                continue
            lit_open += 1
        elif ub <= 0.0:
            unlit += 1
            i = skip
            continue
        if skip != i + 1:
            opened += 1
        else:
            leaves += 1
            k = _test_edges(e_start, e_faces, order, nodes[i, 0], nodes[i, 1], p0, nrm, lx, ly, lz, directional, out,
                            k, stats)  # fmt: skip
        i += 1
    stats[0] += tested
    stats[1] += lit
    stats[2] += lit_open
    stats[3] += unlit
    stats[4] += opened
    stats[5] += leaves
    return k


_TASK_DEPTH = 3  # subtrees at this depth are the parallel tasks (64 with the default fan-out)
_PARALLEL_NODES = 1 << 15  # smaller trees are walked serially (waking the thread pool costs more than it saves)


@njit(cache=True)
def _query_serial(bounds, boundary, nodes, depth, e_start, e_faces, order, rest, r_start, r_faces, p0, nrm, light,
                  directional, out, stats):  # fmt: skip  # pragma: no cover - compiled
    """:func:`_query` in one thread: the whole walk, then ``rest``."""
    k = 0
    if nodes.shape[0] > 0:
        k = _walk(0, nodes.shape[0], bounds, boundary, nodes, e_start, e_faces, order, p0, nrm, light, directional,
                  out, 0, stats, np.zeros(1, dtype=np.int64), -1, depth)  # fmt: skip
    return _test_edges(r_start, r_faces, rest, 0, rest.size, p0, nrm, light[0], light[1], light[2], directional,
                       out, k, stats)  # fmt: skip


@njit(cache=True, parallel=True)
def _query(bounds, boundary, nodes, depth, e_start, e_faces, order, rest, r_start, r_faces, p0, nrm, light,
           directional, out, stats, task_depth, max_tasks):  # fmt: skip  # pragma: no cover - compiled
    """Silhouette edge ids into ``out``, ascending by position (tree edges in leaf order, then ``rest``).

    The nodes above ``task_depth`` are walked first; the subtrees they reach at that depth (at most
    ``max_tasks``, the fan-out to that power) are then walked in parallel, each writing from its first
    edge position; the runs are compacted in order.  The steps are those of one serial walk: each node
    is tested exactly once either way.
    """
    N = nodes.shape[0]
    tasks = np.zeros(min(N, max_tasks) + 1, dtype=np.int64)
    k = 0
    if N > 0:
        k = _walk(0, N, bounds, boundary, nodes, e_start, e_faces, order, p0, nrm, light, directional, out, 0,
                  stats, tasks, task_depth, depth)  # fmt: skip
    n_tasks = tasks[0]
    counts = np.zeros(n_tasks, dtype=np.int64)
    t_stats = np.zeros((n_tasks, stats.size), dtype=np.int64)
    for t in prange(n_tasks):
        i = tasks[t + 1]
        base = nodes[i, 0]
        counts[t] = _walk(i, nodes[i, 2], bounds, boundary, nodes, e_start, e_faces, order, p0, nrm, light,
                          directional, out, base, t_stats[t], tasks, -1, depth) - base  # fmt: skip
    for t in range(n_tasks):  # the tasks' runs, compacted in preorder (after the top walk's own)
        base = nodes[tasks[t + 1], 0]
        for j in range(counts[t]):
            out[k + j] = out[base + j]
        k += counts[t]
        stats += t_stats[t]
    return _test_edges(r_start, r_faces, rest, 0, rest.size, p0, nrm, light[0], light[1], light[2], directional,
                       out, k, stats)  # fmt: skip


def query_fast(mesh: Mesh, tree: Hierarchy, light: Light) -> tuple[np.ndarray, dict[str, int], int]:
    """Edge ids (unsorted), steps and face-evaluation ties of one query, compiled.

    Trees of at least ``_PARALLEL_NODES`` nodes are walked in parallel subtrees (:func:`_query`), smaller
    ones serially; the ids and steps are the same either way.
    """
    directional = isinstance(light, DirectionalLight)
    out = np.empty(tree.order.size + tree.rest.size, dtype=np.int64)
    stats = np.zeros(10, dtype=np.int64)
    bounds = np.full_like(tree.bounds, np.nan) if overflows(tree, light) else tree.bounds
    args = (bounds, tree.boundary, tree.nodes, tree.depth, tree.edge_start, tree.edge_faces, tree.order, tree.rest,
            tree.rest_start, tree.rest_faces, tree.p0, tree.nrm, np.asarray(light.vector, dtype=np.float64),
            directional, out, stats)  # fmt: skip
    if tree.n_nodes >= _PARALLEL_NODES:
        k = _query(*args, _TASK_DEPTH, tree.fanout**_TASK_DEPTH)
    else:
        k = _query_serial(*args)
    steps = {name: int(v) for name, v in zip(STEP_NAMES[:-1], stats[:8])}
    steps["add"] = int(k)
    return out[:k], steps, int(stats[9])


def plain_query(mesh: Mesh, scheme: KeyScheme, light: Light) -> np.ndarray:
    """What a renderer would run per light: :func:`query_fast` on the default tree of ``scheme`` (built on
    first use and cached with the mesh) on one numba thread, as every plain loop runs; ascending edge ids.

    The kernel also increments its step counters (one integer add per step; nothing else of the tally
    is computed).
    """
    tree = tree_for(mesh, scheme)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # the query is a parallel kernel on large trees
    try:
        ids = query_fast(mesh, tree, light)[0]
    finally:
        numba.set_num_threads(threads)
    return np.sort(ids)


# ---- the query's counted costs ------------------------------------------------------------------------
def query_cost(steps: dict[str, int], directional: bool) -> dict[str, int]:
    """The ``true`` tally of :func:`.hierarchy_naive.query_naive` with these steps (docs/counting.md)."""
    if directional:
        face = {"read": 3, "mul": 3, "add": 2, "cmp": 1}
        node = {"read": 6, "mul": 6, "cmp": 3, "add": 4}
    else:
        face = {"read": 6, "mul": 3, "add": 5, "cmp": 1}
        node = {"read": 12, "add": 10, "mul": 12, "cmp": 12}
    lit = steps["node_lit"] + steps["node_lit_open"]
    opened = steps["node_open"] + steps["leaf_open"]
    tally: dict[str, int] = {}
    add_scaled(tally, {"read": 3}, 1)  # the light, once
    add_scaled(tally, node, steps["node_test"])
    add_scaled(tally, {"cmp": 1}, steps["node_test"])  # lb > 0
    add_scaled(tally, {"read": 1}, lit)  # the boundary flag
    add_scaled(tally, {"cmp": 1}, steps["node_test"] - lit)  # ub <= 0
    add_scaled(tally, {"read": 1}, steps["node_lit"] + steps["node_unlit"])  # skip
    add_scaled(tally, {"read": 1, "cmp": 1}, opened)  # skip; "a leaf"
    add_scaled(tally, {"read": 2}, steps["leaf_open"])  # its edge range
    add_scaled(tally, {"read": 2, "cmp": 1}, steps["edge_test"])  # CSR pair; count == 1
    add_scaled(tally, {"read": 1, "add": 1}, steps["edge_side"])  # face id; count + flag
    add_scaled(tally, face, steps["edge_side"])
    add_scaled(tally, {"read": 1, "write": 1}, steps["add"])  # the edge id, into the output
    return tally


# ---- a detector over a hierarchy -----------------------------------------------------------------------
def detect(mesh: Mesh, light: Light, name: str, paper_model: str, scheme: KeyScheme, variant: str, engine: str,
           leaf_size: int, fanout: int) -> Silhouette:  # fmt: skip
    """Build (or reuse) the tree of ``scheme`` and answer one light; the build's tally is in ``notes['build']``.

    ``notes``: ``build`` (kind -> count, the tree's construction, apart from the query's ``true`` tally),
    ``build_steps``, ``tree_bytes``, ``edges_visited_fraction`` (edges whose faces the query evaluated, over E),
    ``break_even_lights`` (lights after which build plus queries cost fewer ``true`` operations than the
    reference's queries; ``None`` when a query is no cheaper).
    """
    if leaf_size < 1 or fanout < 2:
        raise BadArgument(f"{name}: leaf_size must be >= 1 and fanout >= 2, got {leaf_size} and {fanout}")
    directional = isinstance(light, DirectionalLight)
    if engine == "naive":
        tree = build_naive(mesh, scheme, leaf_size, fanout, OpCounter())
        counter = OpCounter()
        ids, steps, ties = query_naive(mesh, tree, light, counter)
        true = dict(counter)
    else:
        tree = tree_for(mesh, scheme, leaf_size, fanout)
        ids, steps, ties = query_fast(mesh, tree, light)
        true = query_cost(steps, directional)
    E = max(mesh.n_edges, 1)
    ref_true = reference_true_total(mesh, light, int(ids.size))
    saving = ref_true - sum(true.values())
    notes = {
        "build": dict(tree.build_tally),
        "build_steps": dict(tree.build_steps),
        "tree_bytes": tree.nbytes,
        "edges_visited_fraction": steps["edge_test"] / E,
        "break_even_lights": math.ceil(sum(tree.build_tally.values()) / saving) if saving > 0 else None,
        "leaf_size": leaf_size,
        "fanout": fanout,
    }
    run = EngineRun(ids, steps, true, ties, lambda: facing_flags(mesh, light)[0], notes=notes)
    return make_silhouette(mesh, light, name, variant, engine, run, paper_model)


def reference_true_total(mesh: Mesh, light: Light, k: int) -> int:
    """The reference detector's ``true`` total for one light with ``k`` silhouette edges (its formula)."""
    return sum(reference_tally(mesh, light, k)[1].values())


# ---- per-mesh cache of fast builds ------------------------------------------------------------------
_BUILT: "weakref.WeakKeyDictionary[Mesh, dict]" = weakref.WeakKeyDictionary()


def tree_for(mesh: Mesh, scheme: KeyScheme, leaf_size: int = LEAF_SIZE, fanout: int = FANOUT) -> Hierarchy:
    """The fast tree of ``scheme`` for ``mesh``, built on first use and kept with the mesh (what ``detect`` uses)."""
    per_mesh = _BUILT.setdefault(mesh, {})
    key = (scheme.name, leaf_size, fanout)
    if key not in per_mesh:
        per_mesh[key] = build_fast(mesh, scheme, leaf_size, fanout)
    return per_mesh[key]


__all__ = ["detect", "query_fast", "query_cost", "tree_for", "plain_query"]
