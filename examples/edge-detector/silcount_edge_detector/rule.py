"""VTK's edge-based silhouette rule (``vtkPolyDataSilhouette``), on silcount's meshes and counting arithmetic.

VTK keeps, for each edge, the normal of the face that traverses it from its lower to its higher vertex id
(the *left* normal) and of the face that traverses it the other way (the *right* normal); an edge with both
is *winged*.  For a light direction ``v`` (VTK's ``SPECIFIED_VECTOR``) it takes ``d1 = v . n_left`` and
``d2 = v . n_right``; for a point light (VTK's ``SPECIFIED_ORIGIN``) ``v`` is the vector from the edge's
midpoint to the light.  A winged edge is a silhouette edge iff the signs differ, ``d1 * d2 < 0`` as VTK
writes it.  VTK's options are left at their defaults: no border edges, no feature angle.

So it differs from silcount's reference rule where that rule decides more than "one face lit, one not":
a boundary edge is never a silhouette edge here; a face whose facing value is 0 makes no silhouette edge
with either neighbour; on a non-manifold edge or an inconsistently wound one the last face (in face
order) of each direction is the one kept, as VTK's ``std::map`` overwrites it; an edge traversed twice in
the same direction is not winged.  Normals are ``(p1 - p0) x (p2 - p0)`` of a face's first three corners,
silcount's (VTK uses Newell's normal of the whole polygon: the same direction on planar convex faces).

Steps (counted by both engines, charged by :data:`PAPER_MODEL`): ``normal`` once per face, ``edge_test``
once per edge (the winged check), ``dot`` once per winged edge (its two dot products and the sign test),
``add`` once per silhouette edge.
"""

from __future__ import annotations

import weakref

import numpy as np

from silcount.counting.arithmetic import Memory, OpCounter, plain
from silcount.detectors.base import EngineRun, MeshMemory, add_scaled, counted_face_normal
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh

NORMAL_COST = {"read": 13, "add": 9, "mul": 6, "write": 3}  # counted_face_normal, then n[f] = ... (3 W)
EDGE_TEST_COST = {"read": 2, "cmp": 2}  # left[e], right[e]; both >= 0
DOT_COST = {"read": 9, "add": 4, "mul": 7, "cmp": 1}  # 6 normal and 3 light reads; two dots; d1 * d2 < 0
MIDPOINT_COST = {"read": 8, "add": 6, "mul": 3}  # two vertex ids and their 6 coordinates; L - (a + b) * 0.5
ADD_COST = {"write": 1}  # S[k] = e
_WINGS: weakref.WeakKeyDictionary[Mesh, np.ndarray] = weakref.WeakKeyDictionary()


def wings(mesh: Mesh) -> np.ndarray:
    """(E, 2) each edge's left face (the last, in face order, to traverse it low -> high) and right face
    (high -> low), ``-1`` where none does; cached with the mesh."""
    got = _WINGS.get(mesh)
    if got is None:
        got = np.full((mesh.n_edges, 2), -1, dtype=np.int64)
        side = np.arange(mesh.n_sides)  # ascending side ids: face order; a later write wins, as in VTK
        right = (mesh.side_from > mesh.side_to).astype(np.int64)
        got[mesh.side_edge[side], right[side]] = mesh.side_face[side]
        _WINGS[mesh] = got
    return got


def naive(mesh: Mesh, light: Light) -> EngineRun:
    """The rule executed on counting arithmetic: every read, operation and comparison is counted."""
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    normals = Memory(np.zeros(3 * mesh.n_faces), counter)
    for f in range(mesh.n_faces):
        _, n = counted_face_normal(mem, f)
        for c in range(3):
            normals[3 * f + c] = n[c]
    wing = Memory(wings(mesh).reshape(-1), counter)
    edges = Memory(mesh.edges.reshape(-1), counter)
    found: list[int] = []
    S = Memory(np.zeros(mesh.n_edges, dtype=np.int64), counter)
    ties = winged = 0
    for e in range(mesh.n_edges):
        left, right = wing[2 * e], wing[2 * e + 1]
        has_left, has_right = left >= 0, right >= 0  # VTK's winged test: two co-faces (both compared)
        if not (has_left and has_right):
            continue
        winged += 1
        lv = [mem.light[c] for c in range(3)]
        if not mem.directional:
            a, b = plain(edges[2 * e]), plain(edges[2 * e + 1])
            pa = [mem.vertices[3 * a + c] for c in range(3)]
            pb = [mem.vertices[3 * b + c] for c in range(3)]
            lv = [lv[c] - (pa[c] + pb[c]) * 0.5 for c in range(3)]
        nl = [normals[3 * plain(left) + c] for c in range(3)]
        nr = [normals[3 * plain(right) + c] for c in range(3)]
        d1 = lv[0] * nl[0] + lv[1] * nl[1] + lv[2] * nl[2]
        d2 = lv[0] * nr[0] + lv[1] * nr[1] + lv[2] * nr[2]
        ties += (plain(d1) == 0.0) + (plain(d2) == 0.0)
        if d1 * d2 < 0.0:
            S[len(found)] = e
            found.append(e)
    steps = {"normal": mesh.n_faces, "edge_test": mesh.n_edges, "dot": winged, "add": len(found)}
    ids = np.asarray(found, dtype=np.int64)
    return EngineRun(ids, steps, dict(counter), ties, lambda: _facing(mesh, light))


def fast(mesh: Mesh, light: Light) -> EngineRun:
    """The same rule on numpy arrays, the same floating-point operations in the same order; its ``true`` tally
    is :func:`naive`'s, from the counts of winged and silhouette edges (:func:`fast_tally`)."""
    w = wings(mesh)
    ok = (w[:, 0] >= 0) & (w[:, 1] >= 0)
    n = mesh.face_normals
    nl, nr = n[w[ok, 0]], n[w[ok, 1]]
    v = np.asarray(light.vector, dtype=np.float64)
    if not isinstance(light, DirectionalLight):
        ends = mesh.vertices[mesh.edges[ok]]
        v = v - (ends[:, 0] + ends[:, 1]) * 0.5
    d1 = _dot(v, nl)
    d2 = _dot(v, nr)
    ids = np.flatnonzero(ok)[d1 * d2 < 0.0]
    ties = int((d1 == 0.0).sum() + (d2 == 0.0).sum())
    steps, true = fast_tally(mesh, light, int(ok.sum()), int(ids.size))
    return EngineRun(ids, steps, true, ties, lambda: _facing(mesh, light))


def _dot(v: np.ndarray, n: np.ndarray) -> np.ndarray:
    """``v . n`` row by row, summed left to right as the counted engine sums it."""
    v = np.broadcast_to(v, n.shape)
    return v[:, 0] * n[:, 0] + v[:, 1] * n[:, 1] + v[:, 2] * n[:, 2]


def fast_tally(mesh: Mesh, light: Light, winged: int, k: int) -> tuple[dict[str, int], dict[str, int]]:
    """Steps and ``true`` tally of :func:`naive` with ``winged`` winged and ``k`` silhouette edges."""
    true: dict[str, int] = {}
    add_scaled(true, NORMAL_COST, mesh.n_faces)
    add_scaled(true, EDGE_TEST_COST, mesh.n_edges)
    add_scaled(true, DOT_COST, winged)
    if not isinstance(light, DirectionalLight):
        add_scaled(true, MIDPOINT_COST, winged)
    add_scaled(true, ADD_COST, k)
    return {"normal": mesh.n_faces, "edge_test": mesh.n_edges, "dot": winged, "add": k}, true


def _facing(mesh: Mesh, light: Light) -> np.ndarray:
    """Each face's light-facing flag (silcount's rule), to orient the edges as silcount orients every result."""
    from silcount.detectors.adjacency import facing_flags

    return facing_flags(mesh, light)[0]
