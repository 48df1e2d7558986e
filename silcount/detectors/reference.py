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

Speed: the ``fast`` query keeps per-mesh arrays (the two faces of every
two-sided edge as uint32, the CSR of the other edges) in a per-mesh cache, so
a query after the first is one pass over the faces' ``p0`` and normals (the
facing flags, computed exactly as :func:`~.base.counted_visibility` does, in
the same operation order) and one pass over the edge-to-face pairs.
"""
from __future__ import annotations

import weakref

import numpy as np
from numba import njit

from ..counting import Memory, OpCounter, plain
from ..lights import Light
from ..mesh import Mesh
from .base import MeshMemory, Silhouette, add_scaled, counted_visibility, make_silhouette, visibility_true_cost

NAME = "reference"


def _naive(mesh: Mesh, light: Light) -> tuple[np.ndarray, dict, OpCounter, int, np.ndarray]:
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
    return np.asarray(out, dtype=np.int64), steps, counter, ties, flags.data.astype(bool)


_PRECOMPUTED: "weakref.WeakKeyDictionary[Mesh, tuple]" = weakref.WeakKeyDictionary()


def _precompute(mesh: Mesh) -> tuple:
    """Per-mesh arrays of the fast query (cached): p0, normals, two-sided edges' faces, the rest as CSR."""
    got = _PRECOMPUTED.get(mesh)
    if got is None:
        two = mesh.edge_valence == 2
        two_ids = np.flatnonzero(two)
        # unsigned, so that numba's gathers need no negative-index wraparound test (2x faster)
        pair_faces = np.ascontiguousarray(mesh.side_face[mesh.manifold_sides[two_ids]].astype(np.uint32))
        other = np.flatnonzero(~two)
        start, order = mesh.edge_sides
        counts = mesh.edge_valence[other]
        o_start = np.zeros(other.size + 1, dtype=np.int64)
        np.cumsum(counts, out=o_start[1:])
        within = np.arange(o_start[-1]) - np.repeat(o_start[:-1], counts)
        o_faces = mesh.side_face[order[np.repeat(start[other], counts) + within]]
        got = (np.ascontiguousarray(mesh.face_p0), np.ascontiguousarray(mesh.face_normals),
               None if other.size == 0 else two_ids, pair_faces, other, o_start, o_faces)
        _PRECOMPUTED[mesh] = got
    return got


@njit(cache=True)
def _facing_kernel(p0, nrm, light, directional):  # pragma: no cover - compiled
    F = p0.shape[0]
    flags = np.empty(F, dtype=np.bool_)
    ties = 0
    lx, ly, lz = light[0], light[1], light[2]
    for p in range(F):
        if directional:
            dx, dy, dz = lx, ly, lz
        else:
            dx, dy, dz = lx - p0[p, 0], ly - p0[p, 1], lz - p0[p, 2]
        dot = dx * nrm[p, 0] + dy * nrm[p, 1] + dz * nrm[p, 2]
        flags[p] = dot > 0.0
        ties += dot == 0.0
    return flags, ties


@njit(cache=True)
def _pair_kernel(flags, pair_faces):  # pragma: no cover - compiled
    out = np.empty(pair_faces.shape[0], dtype=np.int64)
    k = 0
    for e in range(pair_faces.shape[0]):
        if flags[pair_faces[e, 0]] != flags[pair_faces[e, 1]]:
            out[k] = e
            k += 1
    return out[:k]


def facing_flags(mesh: Mesh, light: Light, faces: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Light-facing flags and ties (of all faces, or of ``faces``), computed as
    :func:`~.base.counted_visibility` does, in its operation order."""
    p0, nrm = _precompute(mesh)[:2]
    if faces is not None:
        p0, nrm = p0[faces], nrm[faces]
    src = light.direction if light.is_directional else light.position
    flags, ties = _facing_kernel(p0, nrm, np.asarray(src, dtype=np.float64), bool(light.is_directional))
    return flags, int(ties)


def _edge_ids(mesh: Mesh, is_facing: np.ndarray) -> np.ndarray:
    """Ids of the edges with exactly one light-facing incident face, ascending: the reference rule."""
    _, _, two_ids, pair_faces, other, o_start, o_faces = _precompute(mesh)
    ids = _pair_kernel(is_facing, pair_faces)
    if two_ids is None:
        return ids
    ids = two_ids[ids]
    if other.size:
        per_edge = np.add.reduceat(is_facing[o_faces].astype(np.int64), o_start[:-1])
        ids = np.sort(np.concatenate([ids, other[per_edge == 1]]))     # disjoint sets
    return ids


def silhouette_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The reference silhouette as ascending edge ids (no tallies): the yardstick for the others."""
    return _edge_ids(mesh, facing_flags(mesh, light)[0])


def _fast(mesh: Mesh, light: Light) -> tuple[np.ndarray, dict, dict, int, np.ndarray]:
    is_facing, ties = facing_flags(mesh, light)
    ids = _edge_ids(mesh, is_facing)
    F, E, H = mesh.n_faces, mesh.n_edges, mesh.n_sides
    true: dict[str, int] = {}
    add_scaled(true, visibility_true_cost(light), F)
    add_scaled(true, {"write": 1}, F)                       # flags[p] = ...
    add_scaled(true, {"read": 2, "cmp": 1}, E)              # edge_start[e], [e+1]; count == 1
    add_scaled(true, {"read": 2, "add": 1}, H)              # face id, flag, count +
    add_scaled(true, {"write": 1}, ids.size)                # S[k] = e
    steps = {"visibility": F, "edge_test": E, "add": int(ids.size)}
    return ids, steps, true, ties, is_facing


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """Silhouette by edge adjacency.  ``variant`` is accepted for a uniform API; there is one."""
    if engine == "naive":
        ids, steps, counter, ties, flags = _naive(mesh, light)
        true = dict(counter)
    else:
        ids, steps, true, ties, flags = _fast(mesh, light)
    return make_silhouette(mesh, light, NAME, variant, engine, ids, steps, true, ties, flags)
