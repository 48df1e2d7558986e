"""The reference detector: edge adjacency, O(F + E).  The ground truth.

Each face's light-facing flag is computed once; an edge is a silhouette edge
iff exactly one of the faces incident to it is light-facing.  On a closed,
consistently wound mesh this is the textbook definition the papers use
("an edge shared by one face towards the light and one away", HSD paper
Sec. III).  The same rule decides the other cases, and is documented:

* a boundary edge (one face) is a silhouette edge iff its face is light-facing,
  so open casters still get the side quads their lit boundary needs;
* a non-manifold edge (three or more faces) is one iff exactly one is facing;
* faces whose facing value is exactly 0 are not light-facing (ties, counted).

Steps: ``visibility`` once per face, ``edge_test`` once per edge, ``add``
once per silhouette edge.

Speed: the ``fast`` engine is the shared kernels of
:mod:`silcount.detectors.adjacency` (one pass over the faces, one over the
edge-to-face pairs) plus the tally, which has no data-dependent branch.
"""

from __future__ import annotations

import numpy as np

from silcount.counting.arithmetic import Memory, OpCounter, plain
from silcount.detectors.adjacency import (
    edge_ids_of,
    facing_of_bits,
    many_edge_ids,
    shared_facing_flags,
    silhouette_edge_ids,
)
from silcount.detectors.base import (
    EngineRun,
    MeshMemory,
    Silhouette,
    SilhouetteBatch,
    add_scaled,
    add_scaled_many,
    counted_visibility,
    make_batch,
    make_silhouette,
    oriented_edges,
    visibility_cost_many,
    visibility_true_cost,
)
from silcount.detectors.spec import DetectorSpec
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

NAME = "reference"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "silcount-reference"


def _naive(mesh: Mesh, light: Light) -> EngineRun:
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    F = mesh.n_faces
    flags = Memory(np.zeros(F, dtype=np.int64), counter)
    ties = 0
    for p in range(F):
        is_facing, value = counted_visibility(mem, p)
        ties += value == 0.0
        flags[p] = int(is_facing)
    start, order = mesh.edge_sides
    edge_start = Memory(start, counter)
    edge_face = Memory(mesh.side_face[order], counter)
    out: list[int] = []
    S = Memory(np.zeros(mesh.n_edges, dtype=np.int64), counter)
    for e in range(mesh.n_edges):
        lo, hi = plain(edge_start[e]), plain(edge_start[e + 1])
        count = 0
        for j in range(lo, hi):
            count = flags[plain(edge_face[j])] + count
        if count == 1:
            S[len(out)] = e
            out.append(e)
    steps = {"visibility": F, "edge_test": mesh.n_edges, "add": len(out)}
    return EngineRun(np.asarray(out, dtype=np.int64), steps, dict(counter), ties, np.asarray(flags.data).astype(bool))


def fast_tally(mesh: Mesh, light: Light, k: int) -> tuple[dict, dict]:
    """Steps and ``true`` tally of the loops of :func:`_naive` with ``k`` silhouette edges (no branch on data)."""
    F, E, H = mesh.n_faces, mesh.n_edges, mesh.n_sides
    true: dict[str, int] = {}
    add_scaled(true, visibility_true_cost(light), F)
    add_scaled(true, {"write": 1}, F)  # flags[p] = ...
    add_scaled(true, {"read": 2, "cmp": 1}, E)  # edge_start[e], [e+1]; count == 1
    add_scaled(true, {"read": 2, "add": 1}, H)  # face id, flag, count +
    add_scaled(true, {"write": 1}, k)  # S[k] = e
    return {"visibility": F, "edge_test": E, "add": k}, true


def _fast(mesh: Mesh, light: Light) -> EngineRun:
    is_facing, ties = shared_facing_flags(mesh, light)
    ids = edge_ids_of(mesh, is_facing)
    steps, true = fast_tally(mesh, light, int(ids.size))
    return EngineRun(ids, steps, true, ties, is_facing)


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """Silhouette by edge adjacency.  ``variant`` is accepted for a uniform API; there is one."""
    run = _naive(mesh, light) if engine == "naive" else _fast(mesh, light)
    return make_silhouette(mesh, light, NAME, variant, engine, run, PAPER_MODEL)


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The reference rule uncounted (:func:`.adjacency.silhouette_edge_ids`): ascending edge ids."""
    return silhouette_edge_ids(mesh, light)


def fast_tally_many(mesh: Mesh, lights: list[Light], k: np.ndarray) -> tuple[dict, dict]:
    """:func:`fast_tally` of every light at once: ``k`` (n,) silhouette edges; name -> (n,) int64."""
    F, E, H = mesh.n_faces, mesh.n_edges, mesh.n_sides
    true: dict[str, np.ndarray] = {}
    add_scaled_many(true, visibility_cost_many(lights), F)
    add_scaled_many(true, {"write": 1}, F)
    add_scaled_many(true, {"read": 2, "cmp": 1}, E)
    add_scaled_many(true, {"read": 2, "add": 1}, H)
    add_scaled_many(true, {"write": 1}, k)
    return {"visibility": F, "edge_test": E, "add": k}, true


def detect_many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
    """:func:`detect` (``fast``) for each light, 64 lights per pass (:func:`.adjacency.many_edge_ids`), as one
    :class:`.batch.SilhouetteBatch`; a light's facing flags are unpacked only if ``oriented`` is asked for."""
    many = many_edge_ids(mesh, lights)
    ids = [got[0] for got in many]
    steps, true = fast_tally_many(mesh, lights, np.array([x.size for x in ids], dtype=np.int64))

    def orient(i: int, edge_ids: np.ndarray) -> np.ndarray:
        return oriented_edges(mesh, edge_ids, facing_of_bits(many[i][2], many[i][3]))

    ties = [got[1] for got in many]
    return make_batch(mesh, lights, NAME, variant, ids, steps, true, ties, PAPER_MODEL, orient=orient)


SPEC = DetectorSpec(
    name=NAME,
    label="reference",
    detect=detect,
    role="yardstick",
    paper_model=PAPER_MODEL,
    variants=("intended",),
    engines=("fast", "naive"),
    visited_step="edge_test",
    plain_edge_ids=plain_edge_ids,
    growth_variant="intended",
    style=("#555555", "s"),
    detect_many=detect_many,
)
