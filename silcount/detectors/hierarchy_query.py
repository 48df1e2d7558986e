"""The compiled query over a bounded edge hierarchy, its counted cost, and the detector glue.

:func:`query_fast` walks the tree of :mod:`.hierarchy` level by level over
its level-order boxes, skipping every node whose boxes prove all its faces
lit or all unlit (the proof is in :mod:`.hierarchy`'s docstring), and tests
the edges of the leaves it reaches by the reference rule, pre-testing each
face's sign from its float32 plane (:func:`.hierarchy_walk.pretest`).  It
tests the nodes, edges and faces of the depth-first walk of
:func:`.hierarchy_naive.query_naive`; :func:`query_cost` charges those steps
what that walk executes for them (``docs/counting.md``).  :func:`detect` is
what ``gaussmap`` and ``cones`` call."""

from __future__ import annotations

import math
import weakref

import numba
import numpy as np

from silcount.counting.arithmetic import OpCounter
from silcount.detectors.adjacency import facing_flags
from silcount.detectors.base import EngineRun, add_scaled, make_silhouette
from silcount.detectors.hierarchy import FANOUT, LEAF_SIZE, STEP_NAMES, Hierarchy, KeyScheme, overflows
from silcount.detectors.hierarchy_build import build_fast
from silcount.detectors.hierarchy_naive import build_naive, query_naive
from silcount.detectors.hierarchy_walk import TASK_LEVEL, pretest, query_parallel, query_serial
from silcount.detectors.reference import fast_tally as reference_tally
from silcount.detectors.result import Silhouette
from silcount.errors import BadArgument
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh

PARALLEL_NODES = 1 << 15  # smaller trees are walked serially (waking the thread pool costs more than it saves)


def query_fast(mesh: Mesh, tree: Hierarchy, light: Light) -> tuple[np.ndarray, dict[str, int], int]:
    """Edge ids (unsorted), steps and face-evaluation ties of one query, compiled.

    Trees of at least ``PARALLEL_NODES`` nodes are walked in parallel subtrees
    (:func:`.hierarchy_walk.query_parallel`), smaller ones serially; the ids and steps are the same either way.
    """
    directional = isinstance(light, DirectionalLight)
    out = np.empty(tree.order.size + tree.rest.size, dtype=np.int64)
    stats = np.zeros(10, dtype=np.int64)
    nbox, pbox = tree.nbox, tree.pbox
    if overflows(tree, light):  # no box is trusted: every node is opened
        nbox, pbox = np.full_like(nbox, np.nan), np.full_like(pbox, np.nan)
    l32, thr = pretest(light, tree.p0_max)
    args = (nbox, pbox, tree.boundary, tree.level_start, tree.leaf_size, tree.fanout, tree.edge_start, tree.edge_faces,
            tree.order, tree.rest, tree.rest_start, tree.rest_faces, tree.p0, tree.nrm, tree.plane,
            np.asarray(light.vector, dtype=np.float64), l32, thr, directional, out, stats)  # fmt: skip
    if tree.n_nodes >= PARALLEL_NODES:
        k = query_parallel(*args, TASK_LEVEL)
    else:
        k = query_serial(*args)
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
