"""The edge-adjacency kernels every detector shares: light-facing flags and the reference rule.

:func:`facing_flags` computes each face's light-facing flag exactly as
:func:`~silcount.detectors.base.counted_visibility` does, in its operation
order (``(L - p0) . n > 0``; ``d . n > 0`` for a directional light; exactly 0
is not light-facing and is counted as a tie).  :func:`silhouette_edge_ids`
applies the reference rule (an edge is a silhouette edge iff exactly one of
its incident faces is light-facing) and is the yardstick every other
detector's result is compared with.

Speed: per-mesh arrays (the two faces of every two-sided edge as uint32, the
CSR of the other edges) are kept in a per-mesh cache, so a query after the
first is one pass over the faces' ``p0`` and normals and one pass over the
edge-to-face pairs.
"""

from __future__ import annotations

import weakref

import numpy as np
from numba import njit

from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

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
        got = (
            np.ascontiguousarray(mesh.face_p0),
            np.ascontiguousarray(mesh.face_normals),
            None if other.size == 0 else two_ids,
            pair_faces,
            other,
            o_start,
            o_faces,
        )
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
    :func:`~silcount.detectors.base.counted_visibility` does, in its operation order."""
    p0, nrm = _precompute(mesh)[:2]
    if faces is not None:
        p0, nrm = p0[faces], nrm[faces]
    src = light.direction if light.is_directional else light.position
    flags, ties = _facing_kernel(p0, nrm, np.asarray(src, dtype=np.float64), bool(light.is_directional))
    return flags, int(ties)


def edge_ids_of(mesh: Mesh, is_facing: np.ndarray) -> np.ndarray:
    """Ids of the edges with exactly one light-facing incident face, ascending: the reference rule."""
    _, _, two_ids, pair_faces, other, o_start, o_faces = _precompute(mesh)
    ids = _pair_kernel(is_facing, pair_faces)
    if two_ids is None:
        return ids
    ids = two_ids[ids]
    if other.size:
        per_edge = np.add.reduceat(is_facing[o_faces].astype(np.int64), o_start[:-1])
        ids = np.sort(np.concatenate([ids, other[per_edge == 1]]))  # disjoint sets
    return ids


def silhouette_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The reference silhouette as ascending edge ids (no tallies): the yardstick for the others."""
    return edge_ids_of(mesh, facing_flags(mesh, light)[0])
