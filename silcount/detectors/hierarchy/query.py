"""The compiled query over a bounded plane hierarchy, its counted cost, and the detector glue.

:func:`query_fast` runs :func:`.walk.query` (the proof that its
pruning is exact is in :mod:`.tree`); it tests the nodes, edges and faces
of :func:`.naive.query_naive`, and :func:`.tree.query_cost`
charges those steps what that walk executes for them (``docs/counting.md``).
:func:`detect` is what ``gaussmap`` and ``cones`` call."""

from __future__ import annotations

import math
import weakref

import numba
import numpy as np
from numba import njit

from silcount.counting.arithmetic import OpCounter
from silcount.detectors.adjacency import edge_faces, facing_flags
from silcount.detectors.base import EngineRun, SilhouetteBatch, make_batch, make_silhouette, oriented_edges
from silcount.detectors.batch import rows_of
from silcount.detectors.hierarchy.build import build_fast
from silcount.detectors.hierarchy.naive import build_naive, query_naive
from silcount.detectors.hierarchy.tree import FANOUT, LEAF_SIZE, STEP_NAMES, TASK_LEVEL, Hierarchy, KeyScheme, pretest
from silcount.detectors.hierarchy.tree import query_cost as _query_cost
from silcount.detectors.hierarchy.walk import N_STATS, TIES, query, query_serial
from silcount.detectors.reference import fast_tally as reference_tally
from silcount.detectors.reference import fast_tally_many as reference_tally_many
from silcount.detectors.result import Silhouette
from silcount.detectors.spec import DetectorSpec
from silcount.errors import BadArgument
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh
from silcount.threads import fitted

PARALLEL_NODES = 1 << 21
"""Smaller trees are walked on one thread: waking the thread pool and sharing the subtrees out cost more than
they save.  Measured on 2 cores (load 0.5, ``OMP_WAIT_POLICY=passive``), median over 8 lights of the best of
5 walks: gaussmap on the 1.04 M-face bunny (259,487 nodes) 0.49 ms on one thread, 0.74 ms on two; on
4.17 M faces 1.04 against 1.15 ms; cones on 1.04 M faces 0.70 against 0.83-1.07 ms.  Larger trees than
those keep the parallel walk, which was not measured there.  The one-thread walk first ran inside the parallel
kernel with numba's thread count lowered to 1 around it; as its own serial kernel (:func:`.walk.query_serial`)
a gaussmap query of that bunny went from 0.52-0.55 to 0.44 ms (load 0.4, best of 15, one light)."""
_SCRATCH: "weakref.WeakKeyDictionary[Hierarchy, np.ndarray]" = weakref.WeakKeyDictionary()


def query_fast(mesh: Mesh, tree: Hierarchy, light: Light) -> tuple[np.ndarray, dict[str, int], int]:
    """Edge ids (ascending), steps and face-evaluation ties of one query, compiled.

    Trees of at least :data:`PARALLEL_NODES` nodes are walked in parallel subtrees when more than one of numba's
    threads has a free core (:func:`silcount.threads.fitted`), smaller ones on the caller's thread outside any
    parallel region (:func:`.walk.query_serial`: numba's pool neither woken nor resized); the ids and steps are
    the same either way.  The edges are written into one output buffer kept with the tree (the subtrees write
    from their own first positions, so a fresh buffer would be touched page by page on every query), then
    sorted out of it (:func:`ascending_ids`).
    """
    s, thr = pretest(light, tree.p0_max)
    p0, nrm = edge_faces(mesh)[:2]
    out = _SCRATCH.get(tree)
    if out is None:
        out = _SCRATCH.setdefault(tree, np.empty(tree.order.size, dtype=np.int64))
    stats = np.zeros(N_STATS, dtype=np.int64)
    start, sides = mesh.edge_sides
    directional = isinstance(light, DirectionalLight)
    args = (tree.box, tree.boundary, tree.pair_levels, tree.other_levels, tree.leaf_size, tree.fanout, tree.order,
            tree.n_pairs, tree.planes, tree.other_start, (start, sides, mesh.side_face), p0, nrm,
            np.asarray(light.vector, dtype=np.float64), s, thr, directional, out, stats)  # fmt: skip
    if tree.n_nodes < PARALLEL_NODES:
        k = query_serial(*args)
    else:
        with fitted() as threads:  # the cores free now (silcount.threads); one free core: the serial kernel
            k = query(*args, TASK_LEVEL, threads) if threads > 1 else query_serial(*args)
    steps = dict(zip(STEP_NAMES[:-1], stats[: len(STEP_NAMES) - 1].tolist(), strict=True))
    steps["add"] = int(k)
    return ascending_ids(out[:k], max(mesh.n_edges - 1, 0).bit_length()), steps, int(stats[TIES])


RADIX_BITS = 11  # a digit: 2,048 counters, two passes for meshes of up to 4 M edges


@njit(cache=True)
def _radix_pass(src, dst, shift, count):  # pragma: no cover - compiled
    """One stable counting pass of :func:`ascending_ids` on the digit at ``shift``."""
    mask = (1 << RADIX_BITS) - 1
    count[:] = 0
    for i in range(src.size):
        count[(src[i] >> shift) & mask] += 1
    total = 0
    for d in range(count.size):
        c = count[d]
        count[d] = total
        total += c
    for i in range(src.size):
        d = (src[i] >> shift) & mask
        dst[count[d]] = src[i]
        count[d] += 1


@njit(cache=True)
def ascending_ids(ids, bits):  # pragma: no cover - compiled
    """A sorted copy of ``ids`` (non-negative, below ``2 ** bits``): LSD radix sort, ``RADIX_BITS`` a pass.

    The walk writes its edges leaf by leaf; the result holds them ascending.  ``np.sort`` took 0.3-0.4 ms
    of a 0.5 ms gaussmap query of the 1.04 M-face bunny (13 k edges, load 9).
    """
    count = np.empty(1 << RADIX_BITS, dtype=np.int64)
    a = np.empty(ids.size, dtype=np.int64)
    _radix_pass(ids, a, 0, count)
    b = np.empty(ids.size, dtype=np.int64)
    shift = RADIX_BITS
    while shift < bits:
        _radix_pass(a, b, shift, count)
        a, b = b, a
        shift += RADIX_BITS
    return a


def plain_query(mesh: Mesh, scheme: KeyScheme, light: Light) -> np.ndarray:
    """What a renderer would run per light: :func:`query_fast` on the default tree of ``scheme`` (built on
    first use and cached with the mesh) on one numba thread, as every plain loop runs; ascending edge ids.

    The kernel also increments its step counters (one integer add per step; nothing else of the tally
    is computed).
    """
    tree = tree_for(mesh, scheme)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        return query_fast(mesh, tree, light)[0]
    finally:
        numba.set_num_threads(threads)


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
        true = _query_cost(steps, directional, math.isfinite(pretest(light, tree.p0_max)[1]))
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


def detect_many(mesh: Mesh, lights: list[Light], name: str, paper_model: str, scheme: KeyScheme, variant: str,
                leaf_size: int, fanout: int) -> SilhouetteBatch:  # fmt: skip
    """:func:`detect` (``fast``) for each light as one :class:`.batch.SilhouetteBatch`: the tree built (or
    reused) once, the compiled query per light, the steps, tallies and notes as arrays, no Silhouette per
    light; the build's notes shared by every light."""
    if leaf_size < 1 or fanout < 2:
        raise BadArgument(f"{name}: leaf_size must be >= 1 and fanout >= 2, got {leaf_size} and {fanout}")
    tree = tree_for(mesh, scheme, leaf_size, fanout)
    got = [query_fast(mesh, tree, light) for light in lights]
    trues = [
        _query_cost(steps, isinstance(light, DirectionalLight), math.isfinite(pretest(light, tree.p0_max)[1]))
        for light, (_, steps, _) in zip(lights, got, strict=True)
    ]
    k = np.array([ids.size for ids, _, _ in got], dtype=np.int64)
    ref_true = sum(reference_tally_many(mesh, lights, k)[1].values(), np.zeros(len(lights), dtype=np.int64))
    saving = ref_true - np.array([sum(t.values()) for t in trues], dtype=np.int64)
    build = sum(tree.build_tally.values())
    E = max(mesh.n_edges, 1)
    notes = {
        "build": dict(tree.build_tally),
        "build_steps": dict(tree.build_steps),
        "tree_bytes": tree.nbytes,
        "leaf_size": leaf_size,
        "fanout": fanout,
    }
    light_notes: dict[str, list] = {
        "edges_visited_fraction": [steps["edge_test"] / E for _, steps, _ in got],
        "break_even_lights": [math.ceil(build / s) if s > 0 else None for s in saving.tolist()],
    }

    def orient(i: int, u: np.ndarray) -> np.ndarray:
        return oriented_edges(mesh, u, facing_flags(mesh, lights[i])[0])

    return make_batch(mesh, lights, name, variant, [ids for ids, _, _ in got], rows_of([s for _, s, _ in got]),
                      rows_of(trues), [t for _, _, t in got], paper_model, orient=orient, notes=notes,
                      light_notes=light_notes)  # fmt: skip


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


__all__ = ["detect", "detect_many", "query_fast", "tree_for", "plain_query"]


def hierarchy_spec(name: str, label: str, paper_model: str, scheme: KeyScheme, style: tuple[str, str]) -> DetectorSpec:
    """The spec of the detector ``name`` on the bounded plane tree with key scheme ``scheme`` (Gooch et al.'s
    Gauss map, the normal cones): exactly the reference edge set, one variant, both engines.

    Its ``detect`` takes the tree's shape too (``leaf_size``, ``fanout``); its plain loops are the per-light
    query on the default tree cached with the mesh (:func:`plain_query`), whose build ``plain_setup`` runs
    outside any timing.
    """

    def detect_one(
        mesh: Mesh,
        light: Light,
        variant: str = "intended",
        engine: str = "fast",
        leaf_size: int = LEAF_SIZE,
        fanout: int = FANOUT,
    ) -> Silhouette:
        return detect(mesh, light, name, paper_model, scheme, variant, engine, leaf_size, fanout)

    def many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
        return detect_many(mesh, lights, name, paper_model, scheme, variant, LEAF_SIZE, FANOUT)

    def plain_setup(mesh: Mesh) -> None:
        tree_for(mesh, scheme)

    def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
        return plain_query(mesh, scheme, light)

    return DetectorSpec(
        name=name,
        label=label,
        detect=detect_one,
        role="literature",
        paper_model=paper_model,
        variants=("intended",),
        engines=("fast", "naive"),
        visited_step="edge_test",
        plain_edge_ids=plain_edge_ids,
        plain_setup=plain_setup,
        growth_variant="intended",
        style=style,
        detect_many=many,
    )
