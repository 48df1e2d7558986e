"""The Triangular Algorithm (TA): HSD paper Sec. IV 4.1 and VI 6.1; EESD paper Sec. 3.1 and 5.1.

For each light-facing face (in index order), for each side ``v_p -> v_q`` in
the face's corner order: if the reverse directed edge ``v_q -> v_p`` is in the
array S, delete it; otherwise append ``v_p -> v_q``.  What S holds at the end
is the silhouette, each edge in the direction its light-facing face traverses
it (that is ``oriented``).  S is an array searched linearly from the front
(:mod:`.edge_array`, counting rules in ``docs/counting.md``).

Variants
--------
``intended``
    S starts empty ("S : Array of edges=0", HSD paper Sec. 4.1).
``literal``
    "First lets have an array of all edges (S)" (EESD paper Sec. 3.1): S
    starts with every undirected edge of the edge table, in edge-table order
    (rows sorted), each directed from its lower to its higher vertex index.
    An edge whose faces both face away is then never touched and stays in S,
    and a light-facing side that runs lower -> higher finds no reverse and is
    appended beside its initial copy: the output differs from the reference
    (``agreement['missed_edges']``, ``agreement['extra_edges']``).  Building the
    initial array is the step ``init_S`` (2 reads, 1 mul, 1 add to pack, one
    append per edge); the paper does not cost it.

Meshes other than closed, consistently wound ones
-------------------------------------------------
TA works on directed edges, so it only cancels a side against an
opposite-direction side:

* a boundary edge is a silhouette edge iff its one face is light-facing
  (as in the reference);
* an inconsistently wound edge whose two faces both face the light is added
  twice (two copies of the same directed edge stay in S): TA reports it, the
  reference does not;
* on a non-manifold edge the light-facing sides cancel in opposite-direction
  pairs, front-most copy first; what remains is reported.

Copies of one edge left in S are counted in ``notes['duplicates_in_S']``;
``edges`` lists each edge once, ``oriented`` uses its front-most copy.

Steps
-----
``visibility`` (every face), ``search_S`` (every side of a light-facing
face), ``delete``, ``add`` (annotated by the papers, ``silcount/models/``), plus the
``true``-only steps ``shift`` (elements moved left by deletions) and, for
``literal``, ``init_S``.

Engines
-------
``naive`` runs the loop on counting memory (:class:`.CountedEdgeArray`);
``fast`` replays it with a Fenwick tree (:func:`.edge_array.replay`) and
charges the same counts.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from silcount.counting.arithmetic import Memory, OpCounter, plain
from silcount.detectors.adjacency import edge_faces, facing_flags, shared_facing_flags
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
    unique_ids,
    visibility_cost_many,
    visibility_true_cost,
)
from silcount.detectors.edge_array import (
    CountedEdgeArray,
    Replay,
    first_orientation,
    keys_to_directed,
    packed_edges,
    plain_array_s,
    replay,
    replay_many,
    side_keys,
)
from silcount.detectors.spec import DetectorSpec
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

NAME = "ta"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "eesd2012-ta"

# ``true`` cost of the work around the array, per event (see docs/counting.md).
FACING_FACE_COST = {"read": 2}  # face_start[p], face_start[p+1]
SIDE_COST = {"read": 2, "mul": 1, "add": 1}  # v_p, v_q; reverse key v_q*V + v_p
ADD_COST = {"mul": 1, "add": 2, "write": 1}  # key v_p*V + v_q; S[len] = key; len + 1
DELETE_COST = {"add": 1}  # len - 1
INIT_COST = {"read": 2, "mul": 1, "add": 2, "write": 1}  # literal start: one packed edge appended


def array_true_tally(
    searched: Any, examined: Any, deleted: Any, added: Any, shifted: Any, facing_polygons: Any, add=add_scaled
) -> dict[str, Any]:
    """``true`` cost of the side loop and S operations from the replay's counts (shared with HSD): integers,
    or with ``add=add_scaled_many`` one array of counts per light."""
    true: dict[str, Any] = {}
    add(true, FACING_FACE_COST, facing_polygons)
    add(true, SIDE_COST, searched)
    add(true, {"read": 1, "cmp": 1}, examined)
    add(true, DELETE_COST, deleted)
    add(true, {"read": 1, "write": 1}, shifted)
    add(true, ADD_COST, added)
    return true


def _naive(mesh: Mesh, light: Light, variant: str):
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    side_to = Memory(mesh.side_to, counter)
    V, E, F = mesh.n_vertices, mesh.n_edges, mesh.n_faces
    S = CountedEdgeArray(E + mesh.n_sides, counter)
    steps = {"visibility": 0, "search_S": 0, "delete": 0, "add": 0, "shift": 0}
    if variant == "literal":  # "First lets have an array of all edges (S)"
        table = Memory(mesh.edges.reshape(-1), counter)
        for e in range(E):
            S.append(table[2 * e] * V + table[2 * e + 1])
        steps["init_S"] = E
    flags = np.zeros(F, dtype=bool)
    ties = 0
    for p in range(F):  # For p = 1 to Number Of Faces
        visible, value = counted_visibility(mem, p)  # If p.visible = True then
        steps["visibility"] += 1
        ties += value == 0.0
        flags[p] = visible
        if not visible:
            continue
        first, last = plain(mem.face_start[p]), plain(mem.face_start[p + 1])
        for q in range(first, last):  # For q = 1 to Number Of Side
            toggle(S, mem.corners[q], side_to[q], V, steps)
    ids, pairs = edges_in(S, mesh)
    return EngineRun(ids, steps, dict(counter), ties, flags, pairs)


def toggle(S: CountedEdgeArray, vp, vq, V: int, steps: dict[str, int]) -> None:
    """One side ``v_p -> v_q`` of a light-facing face: the body of TA's inner loop (also HSD's)."""
    steps["search_S"] += 1
    pos = S.find(vq * V + vp)  # If v_p v_q^-1 belongs to S
    if pos >= 0:
        steps["shift"] += S.length.value - pos - 1
        S.delete(pos)  # Delete it from S
        steps["delete"] += 1
    else:
        S.append(vp * V + vq)  # Add v_p v_q to S
        steps["add"] += 1


def edges_in(S: CountedEdgeArray, mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """The edge ids and directed (from, to) pairs of what S holds, in S's order."""
    return packed_edges(mesh, S.keys())


def _fast(mesh: Mesh, light: Light, variant: str) -> EngineRun:
    is_facing, ties = shared_facing_flags(mesh, light)
    r = replay(mesh.face_start, side_keys(mesh), is_facing, 2 * mesh.n_edges, _initial(mesh, variant))
    return _run(mesh, light, variant, is_facing, ties, r)


def _initial(mesh: Mesh, variant: str) -> np.ndarray | None:
    """What S holds before the face loop: every edge (``literal``: "an array of all edges"), else nothing."""
    return 2 * np.arange(mesh.n_edges, dtype=np.int64) if variant == "literal" else None


def _run(mesh: Mesh, light: Light, variant: str, is_facing: np.ndarray, ties: int, r: Replay) -> EngineRun:
    """The ``fast`` engine's run from the faces' flags and S's replay over them."""
    E, F = mesh.n_edges, mesh.n_faces
    ids, pairs = keys_to_directed(mesh.edges, r.live_keys)
    steps = {"visibility": F, "search_S": r.searched, "delete": r.deleted, "add": r.added, "shift": r.shifted}
    true: dict[str, int] = {}
    add_scaled(true, visibility_true_cost(light), F)
    if variant == "literal":
        steps["init_S"] = E
        add_scaled(true, INIT_COST, E)
    for kind, c in array_true_tally(
        r.searched, r.examined, r.deleted, r.added, r.shifted, int(np.count_nonzero(is_facing))
    ).items():
        true[kind] = true.get(kind, 0) + c
    return EngineRun(ids, steps, true, ties, is_facing, pairs)


def finish(
    mesh: Mesh,
    light: Light,
    detector: str,
    variant: str,
    engine: str,
    run: EngineRun,
    paper_model: str,
    paper_params: dict | None = None,
) -> Silhouette:
    """The :class:`Silhouette` of what S holds (``run.pairs``): unique edges, front-most copy's direction,
    duplicates noted."""
    ids, pairs = run.edge_ids, run.pairs
    assert pairs is not None
    run.edge_ids = unique_ids(ids)  # sorted once; S's order stays in ``ids`` for the orientation
    run.notes["S_length"] = int(ids.size)
    run.notes["duplicates_in_S"] = int(ids.size - run.edge_ids.size)
    return make_silhouette(
        mesh,
        light,
        detector,
        variant,
        engine,
        run,
        paper_model,
        paper_params,
        lambda u: first_orientation(ids, pairs, u),
    )


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """TA's silhouette of ``mesh`` for ``light`` with its steps and both tallies."""
    run = (_naive if engine == "naive" else _fast)(mesh, light, variant)
    return finish(mesh, light, NAME, variant, engine, run, PAPER_MODEL)


def detect_many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
    """:func:`detect` (``fast``) for each light, the lights' replays of S on threads side by side
    (:func:`.edge_array.replay_many`), as one :class:`.batch.SilhouetteBatch`: the same answers and tallies."""
    p0, nrm = edge_faces(mesh)[:2]
    many = replay_many(mesh.face_start, side_keys(mesh), p0, nrm, lights, 2 * mesh.n_edges, _initial(mesh, variant))
    E, F = mesh.n_edges, mesh.n_faces
    steps, true = many_counts(many, lights, F)
    if variant == "literal":
        steps["init_S"] = E
        add_scaled_many(true, INIT_COST, E)
    return finish_many(mesh, lights, NAME, variant, many, steps, true, PAPER_MODEL)


def many_counts(many: list[tuple[np.ndarray, int, Replay]], lights: list[Light], P: int) -> tuple[dict, dict]:
    """Steps and ``true`` tallies (name -> (n,) int64) of the lights' replays over ``P`` polygons (faces for
    TA): visibility of every polygon, then :func:`array_true_tally`; the order of :func:`_run`'s dicts."""
    got = {
        f: np.array([getattr(r, f) for _, _, r in many], dtype=np.int64)
        for f in ("searched", "examined", "deleted", "added", "shifted")
    }
    facing = np.array([np.count_nonzero(flags) for flags, _, _ in many], dtype=np.int64)
    steps = {"visibility": P, "search_S": got["searched"], "delete": got["deleted"], "add": got["added"]}
    steps["shift"] = got["shifted"]
    true: dict[str, np.ndarray] = {}
    add_scaled_many(true, visibility_cost_many(lights), P)
    extra = array_true_tally(**got, facing_polygons=facing, add=add_scaled_many)
    for kind, c in extra.items():
        true[kind] = true.get(kind, 0) + c
    return steps, true


def finish_many(
    mesh: Mesh,
    lights: list[Light],
    detector: str,
    variant: str,
    many: list[tuple[np.ndarray, int, Replay]],
    steps: dict,
    true: dict,
    paper_model: str,
    paper_params: dict | None = None,
    light_notes: dict | None = None,
    notes: dict | None = None,
) -> SilhouetteBatch:
    """:func:`finish` for every light's replay at once: what S holds (each edge once), ``notes['S_length']``
    and ``['duplicates_in_S']`` per light, each light's front-most copy's direction when asked for."""
    held = [keys_to_directed(mesh.edges, r.live_keys) for _, _, r in many]
    ids = [unique_ids(x) for x, _ in held]
    length = [int(x.size) for x, _ in held]
    own = {"S_length": length, "duplicates_in_S": [n - int(u.size) for n, u in zip(length, ids, strict=True)]}

    def orient(i: int, u: np.ndarray) -> np.ndarray:
        return first_orientation(held[i][0], held[i][1], u)

    return make_batch(
        mesh,
        lights,
        detector,
        variant,
        ids,
        steps,
        true,
        [t for _, t, _ in many],
        paper_model,
        paper_params,
        orient,
        notes,
        {**(light_notes or {}), **own},
    )


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """TA's own loops (``intended``), compiled and uncounted (HSD paper Sec. 4.1): visibility once per face,
    then S over the light-facing faces' sides (:func:`.edge_array.plain_array_s`); ascending edge ids."""
    return plain_array_s(mesh, mesh.face_start, mesh.side_from, mesh.side_to, facing_flags(mesh, light)[0])


SPEC = DetectorSpec(
    name=NAME,
    label="TA",
    detect=detect,
    role="paper",
    paper_model=PAPER_MODEL,
    variants=("intended", "literal"),
    engines=("fast", "naive"),
    visited_step="search_S",
    plain_edge_ids=plain_edge_ids,
    growth_variant="intended",
    style=("#1b6ca8", "o"),
    detect_many=detect_many,
)
