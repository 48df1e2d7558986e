"""What every detector shares: light-facing, counted visibility, and assembling the result.

The light-facing test is the papers' visibility step (HSD paper Sec. VI 6.1;
EESD paper Sec. 5.1): a face normal from the first three corners, a vector
from the face to the light, a dot product and the sign of the result.
:func:`counted_visibility` is the one scalar implementation every ``naive``
engine calls; :func:`visibility_true_cost` measures its cost by running it,
so the ``fast`` engines charge exactly what the ``naive`` ones execute.
:func:`make_silhouette` assembles the result type, :class:`.result.Silhouette`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import cache
from typing import TypeVar

import numba
import numpy as np

from silcount.counting.arithmetic import KINDS, Memory, Num, OpCounter, plain
from silcount.detectors.batch import SilhouetteBatch, columns_of, csr_offsets
from silcount.detectors.result import EngineRun, Silhouette
from silcount.detectors.spec import ENGINES, VARIANTS
from silcount.mesh.lights import DirectionalLight, Light, PointLight
from silcount.mesh.model import Mesh, from_polygons

T = TypeVar("T")
R = TypeVar("R")


class MeshMemory:
    """The mesh and light as counted memory, for the ``naive`` engines."""

    def __init__(self, mesh: Mesh, light: Light, counter: OpCounter) -> None:
        self.vertices = Memory(mesh.vertices.reshape(-1), counter)
        self.corners = Memory(mesh.corners, counter)
        self.face_start = Memory(mesh.face_start, counter)
        self.directional = isinstance(light, DirectionalLight)
        self.light = Memory(np.asarray(light.vector, dtype=np.float64), counter)


def counted_face_normal(mem: MeshMemory, p: int) -> tuple[list[Num], list[Num]]:
    """Face ``p``'s first vertex and normal ``(p1 - p0) x (p2 - p0)``, on counting arithmetic.

    Reads the face's start offset, its first three corner indices and their
    nine coordinates (13 R); 9 A and 6 M.
    """
    s = plain(mem.face_start[p])
    idx = [plain(mem.corners[s + k]) for k in range(3)]
    pts = [[mem.vertices[3 * i + c] for c in range(3)] for i in idx]
    e1 = [pts[1][c] - pts[0][c] for c in range(3)]
    e2 = [pts[2][c] - pts[0][c] for c in range(3)]
    return pts[0], [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]


def counted_visibility(mem: MeshMemory, p: int) -> tuple[bool, float]:
    """Is face ``p`` light-facing?  Executed on counting arithmetic.

    Reads the face's start offset and first three corner indices, their nine
    coordinates and the light's three; computes ``e1 = p1 - p0``,
    ``e2 = p2 - p0``, ``n = e1 x e2``, ``d = L - p0`` (point light) or
    ``d = direction``, ``d . n`` and one comparison with 0.
    Returns the flag and the plain value of ``d . n`` (to count ties).
    """
    p0, nrm = counted_face_normal(mem, p)
    lv = [mem.light[c] for c in range(3)]
    d = lv if mem.directional else [lv[c] - p0[c] for c in range(3)]
    dot = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]
    return dot > 0.0, plain(dot)


@cache
def _visibility_cost(directional: bool) -> tuple[tuple[str, int], ...]:
    tri = from_polygons(np.eye(3), [[0, 1, 2]])
    light: Light = DirectionalLight((0, 0, 1)) if directional else PointLight((0, 0, 5))
    counter = OpCounter()
    counted_visibility(MeshMemory(tri, light, counter), 0)
    return tuple(sorted(counter.items()))


def visibility_true_cost(light: Light) -> dict[str, int]:
    """The ``true`` cost of one :func:`counted_visibility` call (it has no data-dependent branch)."""
    return dict(_visibility_cost(isinstance(light, DirectionalLight)))


def add_scaled(total: dict[str, int], cost: dict[str, int], times: int) -> None:
    """``total += times * cost``, kind by kind."""
    for kind, c in cost.items():
        total[kind] = total.get(kind, 0) + int(c) * int(times)


def add_scaled_many(total: dict[str, np.ndarray], cost: Mapping[str, int | np.ndarray], times) -> None:
    """:func:`add_scaled` for many lights at once: ``times`` and the costs one int64 value per light (or one
    for all); the kinds enter ``total`` in the same order."""
    times = np.asarray(times, dtype=np.int64)
    for kind, c in cost.items():
        total[kind] = total.get(kind, 0) + np.asarray(c, dtype=np.int64) * times


def visibility_cost_many(lights: Sequence[Light]) -> dict[str, np.ndarray]:
    """:func:`visibility_true_cost` of each light, as kind -> (n,) int64 (both kinds of light count the same
    kinds, in the same order)."""
    costs = [visibility_true_cost(light) for light in lights]
    kinds = dict.fromkeys(k for c in costs for k in c) if costs else visibility_true_cost(DirectionalLight((0, 0, 1)))
    return {k: np.array([c.get(k, 0) for c in costs], dtype=np.int64) for k in kinds}


def oriented_edges(mesh: Mesh, edge_ids: np.ndarray, is_facing: np.ndarray) -> np.ndarray:
    """Each edge as traversed by its light-facing face.

    For an edge with several light-facing sides the first in side order is
    used; an edge with none (possible only in ``literal`` output) keeps the
    direction of its first side.
    """
    edge_ids = np.asarray(edge_ids, dtype=np.int64)
    out = mesh.edges[edge_ids].copy()
    if edge_ids.size == 0:
        return out
    # the sides of the requested edges only (O(k), not a sort of all sides), in side order
    start, order = mesh.edge_sides
    cnt = mesh.edge_valence[edge_ids]
    group = np.cumsum(cnt) - cnt
    local = np.arange(int(cnt.sum())) - np.repeat(group, cnt)
    sides = order[np.repeat(start[edge_ids], cnt) + local]
    # first facing side per edge, else first side: minimum of (not facing, position in the edge)
    rank = np.where(is_facing[mesh.side_face[sides]], 0, 1) * (int(cnt.max()) + 1) + local
    best = np.minimum.reduceat(rank, group) % (int(cnt.max()) + 1)
    pick = sides[group + best]
    out[:, 0] = mesh.side_from[pick]
    out[:, 1] = mesh.side_to[pick]
    return out


@numba.njit(cache=True, nogil=True)
def _ascending(s):  # pragma: no cover - compiled
    """Are the ids strictly ascending?  One pass, stopping at the first that is not."""
    for i in range(1, s.size):
        if s[i] <= s[i - 1]:
            return False
    return True


def unique_ids(ids) -> np.ndarray:
    """Sorted distinct int64 ids; by sorting (numpy 2.4's hash-based ``np.unique`` is ~20x slower on 1M ids).

    Ids already strictly ascending come back as they are (one compiled comparison pass: numpy's
    ``all(s[1:] > s[:-1])`` costs ~10 us a call in its wrappers, and a corpus unit makes hundreds).
    """
    s = np.asarray(ids, dtype=np.int64).reshape(-1)
    if s.size < 2 or _ascending(s):
        return s
    s = np.sort(s)
    keep = np.empty(s.size, dtype=bool)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def on_threads(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
    """``[fn(x) for x in items]``, on numba's thread count of threads (``fn`` runs compiled code that releases
    the GIL: each light's sequential kernel, side by side); in order, an exception raised as it was.  Thread
    ``t`` takes items ``t, t + threads, ...`` in one task (a task per item cost 37 us of submission each:
    0.35 s of a corpus sweep's 9 s of units)."""
    threads = max(1, min(numba.get_num_threads(), len(items)))
    if threads == 1:
        return [fn(x) for x in items]
    with ThreadPoolExecutor(threads) as pool:
        parts = list(pool.map(lambda t: [fn(x) for x in items[t::threads]], range(threads)))
    out: list[R] = [None] * len(items)  # type: ignore[list-item]  # every slot is filled below
    for t, part in enumerate(parts):
        out[t::threads] = part
    return out


def make_silhouette(
    mesh: Mesh,
    light: Light,
    detector: str,
    variant: str,
    engine: str,
    run: EngineRun,
    paper_model: str | None,
    paper_params: dict[str, float] | None = None,
    orient: Callable[[np.ndarray], np.ndarray] | None = None,
) -> Silhouette:
    """Assemble a :class:`Silhouette` from an engine's :class:`.result.EngineRun`: sorted unique edges, both
    cost models (``paper_model``: the detector's ``silcount/models/`` file); ``edges`` and ``oriented`` lazily.

    ``run.is_facing`` (or the function it holds) gives :func:`oriented_edges` unless ``orient`` (called with
    the ascending ids) is given.  No reference detection is run here: :attr:`.result.Silhouette.agreement`
    does that when asked.
    """
    ids = unique_ids(run.edge_ids)
    params = {"e_n": mesh.n_edges, "f_n": mesh.n_faces, "m": mesh.mean_sides}
    if paper_params:
        params.update(paper_params)
    true = {k: 0 for k in KINDS}
    true.update({k: int(v) for k, v in run.true_tally.items()})
    is_facing = run.is_facing

    def oriented() -> np.ndarray:
        if orient is not None:
            return orient(ids)
        return oriented_edges(mesh, ids, is_facing() if callable(is_facing) else is_facing)

    return Silhouette(
        detector=detector,
        variant=variant,
        engine=engine,
        edge_ids=ids,
        steps={k: int(v) for k, v in run.steps.items()},
        true_tally=true,
        paper_model=paper_model,
        paper_params=params,
        ties=int(run.ties),
        notes=dict(run.notes),
        mesh=mesh,
        light=light,
        orient=oriented,
    )


def make_batch(
    mesh: Mesh,
    lights: Sequence[Light],
    detector: str,
    variant: str,
    ids: Sequence[np.ndarray],
    steps: Mapping[str, np.ndarray | int],
    true: Mapping[str, np.ndarray | int],
    ties: np.ndarray | Sequence[int],
    paper_model: str | None,
    paper_params: dict[str, float] | None = None,
    orient: Callable[[int, np.ndarray], np.ndarray] | None = None,
    notes: dict | None = None,
    light_notes: dict[str, list] | None = None,
) -> SilhouetteBatch:
    """Assemble the ``fast`` engine's :class:`.batch.SilhouetteBatch` for ``lights``, as :func:`make_silhouette`
    assembles one light's result: each light's ids sorted and distinct (``ids[i]``, any order), steps and
    ``true`` tallies name -> one count per light (KINDS first), the paper parameters of the mesh."""
    n = len(lights)
    uniq = [unique_ids(x) for x in ids]
    params = {"e_n": mesh.n_edges, "f_n": mesh.n_faces, "m": mesh.mean_sides}
    if paper_params:
        params.update(paper_params)
    step_arr, step_names = columns_of(steps, n)
    true_arr, kinds = columns_of(true, n, KINDS)
    np.maximum(true_arr[:, : len(KINDS)], 0, out=true_arr[:, : len(KINDS)])  # every light's tally has KINDS
    return SilhouetteBatch(
        detector=detector,
        variant=variant,
        engine="fast",
        offsets=csr_offsets([u.size for u in uniq]),
        ids=np.concatenate(uniq) if uniq else np.zeros(0, dtype=np.int64),
        step_names=step_names,
        steps=step_arr,
        kinds=kinds,
        true=true_arr,
        ties=np.asarray(ties, dtype=np.int64).reshape(n),
        paper_model=paper_model,
        paper_params=params,
        mesh=mesh,
        lights=list(lights),
        notes=dict(notes or {}),
        light_notes=dict(light_notes or {}),
        orient=orient,
    )


__all__ = [
    "MeshMemory",
    "make_batch",
    "SilhouetteBatch",
    "add_scaled_many",
    "visibility_cost_many",
    "counted_face_normal",
    "counted_visibility",
    "visibility_true_cost",
    "add_scaled",
    "oriented_edges",
    "make_silhouette",
    "on_threads",
    "EngineRun",
    "unique_ids",
    "VARIANTS",
    "ENGINES",
    "Num",
    "plain",
]
