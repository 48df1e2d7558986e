"""Hybrid Silhouette Detection (HSD): HSD paper Sec. V and VI 6.3.

HSD merges adjacent faces "that ha[ve] same normal vectors" into polygons and
runs the Triangular Algorithm over the polygons' sides (:mod:`.ta`, with S
starting empty as in the HSD paper's TA, Sec. 4.1).  The merge
(:func:`silcount.mesh.coplanar.merge`) does not depend on the light and is cached
per mesh, so a per-light query only runs TA over the polygons.

* A polygon's visibility is that of its representative, the lowest-index
  face of its region (``counted_visibility`` of that face, after one read of
  the representative table).
* Its sides are the region's boundary sides, in mesh side order; a region
  with holes simply has several loops of sides.

Variants
--------
``intended``
    the ``tight`` merge: exactly coplanar faces with the same orientation
    (criterion in :mod:`silcount.mesh.coplanar`).  Merged faces always share
    their facing sign, so no reference silhouette edge lies inside a polygon
    and the result has the reference's edges wherever TA's has (closed or
    open, manifold, consistently wound meshes).
``literal``
    the paper's "same normal vectors" read loosely, as ``trimesh`` facets
    (an angle tolerance): real silhouette edges can fall inside a polygon and
    are lost (``notes['reference_edges_inside_polygons']``,
    ``agreement['missed_edges']``).

Cost
----
The detection tally covers TA over the polygons only; the merge's steps and
``true`` tally are in ``notes['merge']``.  The ``paper`` model uses the
polygon mesh's parameters (``f_n`` polygons, ``e_n`` polygon edges, ``m``
mean polygon sides), HSD paper Sec. 6.3.  Steps as TA: ``visibility`` (per
polygon), ``search_S``, ``delete``, ``add``, ``shift``.  Boundary,
non-manifold and inconsistently wound edges never lie inside a polygon and
are handled as TA handles them.
"""

from __future__ import annotations

import numpy as np

from silcount.counting.arithmetic import Memory, OpCounter, plain
from silcount.detectors.adjacency import edge_faces, edge_ids_of, facing_flags, many_edge_ids, shared_facing_flags
from silcount.detectors.base import (
    EngineRun,
    MeshMemory,
    SilhouetteBatch,
    add_scaled,
    add_scaled_many,
    counted_visibility,
    visibility_true_cost,
)
from silcount.detectors.edge_array import (
    CountedEdgeArray,
    Replay,
    keys_to_directed,
    plain_array_s,
    replay,
    replay_many,
    side_keys,
)
from silcount.detectors.result import Silhouette
from silcount.detectors.spec import DetectorSpec
from silcount.detectors.ta import array_true_tally, edges_in, finish, finish_many, many_counts, toggle
from silcount.mesh.coplanar import Merge, merge
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

NAME = "hsd"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "hsd2011-hsd"
CRITERION = {"intended": "tight", "literal": "facets"}
REPRESENTATIVE_COST = {"read": 1}  # rep[p]


def _naive(mesh: Mesh, light: Light, mg: Merge):
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    rep = Memory(mg.rep, counter)
    start = Memory(mg.poly_start, counter)
    side_from = Memory(mesh.side_from[mg.poly_sides], counter)
    side_to = Memory(mesh.side_to[mg.poly_sides], counter)
    V, P = mesh.n_vertices, mg.n_polygons
    S = CountedEdgeArray(mg.poly_sides.size, counter)
    steps = {"visibility": 0, "search_S": 0, "delete": 0, "add": 0, "shift": 0}
    poly_facing = np.zeros(P, dtype=bool)
    ties = 0
    for p in range(P):  # for each polygon
        visible, value = counted_visibility(mem, plain(rep[p]))  # its representative's visibility
        steps["visibility"] += 1
        ties += value == 0.0
        poly_facing[p] = visible
        if not visible:
            continue
        first, last = plain(start[p]), plain(start[p + 1])
        for q in range(first, last):  # for each boundary side
            toggle(S, side_from[q], side_to[q], V, steps)  # TA's side step
    ids, pairs = edges_in(S, mesh)
    return EngineRun(ids, steps, dict(counter), ties, poly_facing, pairs)


def _fast(mesh: Mesh, light: Light, mg: Merge) -> EngineRun:
    poly_facing, ties = facing_flags(mesh, light, mg.rep)
    return _run(
        mesh, light, mg, poly_facing, ties, replay(mg.poly_start, _poly_keys(mesh, mg), poly_facing, 2 * mesh.n_edges)
    )


def _poly_keys(mesh: Mesh, mg: Merge) -> np.ndarray:
    """The directed keys of the polygons' boundary sides, polygon by polygon."""
    return side_keys(mesh)[mg.poly_sides]


def _run(mesh: Mesh, light: Light, mg: Merge, poly_facing: np.ndarray, ties: int, r: Replay) -> EngineRun:
    """The ``fast`` engine's run from the polygons' flags and S's replay over them."""
    ids, pairs = keys_to_directed(mesh.edges, r.live_keys)
    P = mg.n_polygons
    steps = {"visibility": P, "search_S": r.searched, "delete": r.deleted, "add": r.added, "shift": r.shifted}
    true: dict[str, int] = {}
    add_scaled(true, visibility_true_cost(light), P)
    add_scaled(true, REPRESENTATIVE_COST, P)
    for kind, c in array_true_tally(
        r.searched, r.examined, r.deleted, r.added, r.shifted, int(np.count_nonzero(poly_facing))
    ).items():
        true[kind] = true.get(kind, 0) + c
    return EngineRun(ids, steps, true, ties, poly_facing, pairs)


def _finish(mesh: Mesh, light: Light, variant: str, engine: str, mg: Merge, run: EngineRun, reference) -> Silhouette:
    """The :class:`Silhouette` of ``run``; ``reference``: the light's reference edge ids (ascending)."""
    inside = int(np.count_nonzero(mg.interior[reference]))
    run.notes.update({
        "merge": mg.summary(),
        "representative": "lowest-index face of each polygon",
        "reference_edges_inside_polygons": inside,
    })  # fmt: skip
    assert isinstance(run.is_facing, np.ndarray)  # both engines give the polygons' flags
    run.is_facing = run.is_facing[mg.region]  # the polygons' flags, per face
    return finish(mesh, light, NAME, variant, engine, run, PAPER_MODEL, paper_params=mg.paper_params())


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """HSD's silhouette: TA over the merged polygons; the merge's cost is in ``notes['merge']``."""
    mg = merge(mesh, CRITERION[variant])
    run = (_naive if engine == "naive" else _fast)(mesh, light, mg)
    reference = edge_ids_of(mesh, shared_facing_flags(mesh, light)[0])
    return _finish(mesh, light, variant, engine, mg, run, reference)


def detect_many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
    """:func:`detect` (``fast``) for each light, the lights' replays of S on threads side by side
    (:func:`.edge_array.replay_many`) and their reference edges in one pass
    (:func:`.adjacency.many_edge_ids`), as one :class:`.batch.SilhouetteBatch`: the same answers and tallies."""
    mg = merge(mesh, CRITERION[variant])
    p0, nrm = edge_faces(mesh)[:2]
    many = replay_many(mg.poly_start, _poly_keys(mesh, mg), p0[mg.rep], nrm[mg.rep], lights, 2 * mesh.n_edges)
    refs = many_edge_ids(mesh, lights)
    P = mg.n_polygons
    steps, true = many_counts(many, lights, P)
    add_scaled_many(true, REPRESENTATIVE_COST, P)
    inside = [int(np.count_nonzero(mg.interior[ref[0]])) for ref in refs]
    notes = {"merge": mg.summary(), "representative": "lowest-index face of each polygon"}
    own = {"reference_edges_inside_polygons": inside}
    return finish_many(mesh, lights, NAME, variant, many, steps, true, PAPER_MODEL, mg.paper_params(), own, notes)


def plain_setup(mesh: Mesh) -> None:
    """The coplanar merge of the plain loops, once per mesh (cached with it), outside any timing."""
    merge(mesh, CRITERION["intended"])


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """HSD's own loops (``intended``), compiled and uncounted: TA's S over the boundary sides of the merged
    polygons (HSD paper Sec. V; the merge cached with the mesh, as in :func:`detect`); ascending edge ids."""
    mg = merge(mesh, CRITERION["intended"])
    sides = mg.poly_sides
    facing = facing_flags(mesh, light, mg.rep)[0]
    return plain_array_s(mesh, mg.poly_start, mesh.side_from[sides], mesh.side_to[sides], facing)


SPEC = DetectorSpec(
    name=NAME,
    label="HSD",
    detect=detect,
    role="paper",
    paper_model=PAPER_MODEL,
    variants=("intended", "literal"),
    engines=("fast", "naive"),
    visited_step="search_S",
    plain_edge_ids=plain_edge_ids,
    plain_setup=plain_setup,
    growth_variant="intended",
    style=("#edae49", "o"),
    detect_many=detect_many,
)
