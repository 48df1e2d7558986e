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
from numba import njit, prange

from silcount.mesh.lights import DirectionalLight, Light
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


_CHUNK = 1 << 16  # faces or edges per parallel chunk


@njit(cache=True, parallel=True)
def _facing_kernel(p0, nrm, light, directional):  # pragma: no cover - compiled
    F = p0.shape[0]
    flags = np.empty(F, dtype=np.bool_)
    n_chunks = (F + _CHUNK - 1) // _CHUNK
    ties = np.zeros(n_chunks, dtype=np.int64)
    lx, ly, lz = light[0], light[1], light[2]
    for c in prange(n_chunks):
        t = 0
        for p in range(c * _CHUNK, min(F, (c + 1) * _CHUNK)):
            if directional:
                dx, dy, dz = lx, ly, lz
            else:
                dx, dy, dz = lx - p0[p, 0], ly - p0[p, 1], lz - p0[p, 2]
            dot = dx * nrm[p, 0] + dy * nrm[p, 1] + dz * nrm[p, 2]
            flags[p] = dot > 0.0
            t += dot == 0.0
        ties[c] = t
    return flags, ties.sum()


@njit(cache=True, parallel=True)
def _pair_kernel(flags, pair_faces):  # pragma: no cover - compiled
    E = pair_faces.shape[0]
    out = np.empty(E, dtype=np.int64)
    n_chunks = (E + _CHUNK - 1) // _CHUNK
    counts = np.zeros(n_chunks, dtype=np.int64)
    for c in prange(n_chunks):
        k = c * _CHUNK
        for e in range(c * _CHUNK, min(E, (c + 1) * _CHUNK)):
            if flags[pair_faces[e, 0]] != flags[pair_faces[e, 1]]:
                out[k] = e
                k += 1
        counts[c] = k - c * _CHUNK
    k = 0
    for c in range(n_chunks):  # compact the chunks' runs, in order
        for i in range(counts[c]):
            out[k + i] = out[c * _CHUNK + i]
        k += counts[c]
    return out[:k]


@njit(cache=True, parallel=True)
def _facing_bits_kernel(p0, nrm, lights, directional):  # pragma: no cover - compiled
    """Bit ``j`` of word ``p``: face ``p`` faces light ``j`` (<= 64 lights), as :func:`_facing_kernel`."""
    F, L = p0.shape[0], lights.shape[0]
    bits = np.zeros(F, dtype=np.uint64)
    n_chunks = (F + _CHUNK - 1) // _CHUNK
    ties = np.zeros((n_chunks, L), dtype=np.int64)
    for c in prange(n_chunks):
        for p in range(c * _CHUNK, min(F, (c + 1) * _CHUNK)):
            x, y, z = p0[p, 0], p0[p, 1], p0[p, 2]
            nx, ny, nz = nrm[p, 0], nrm[p, 1], nrm[p, 2]
            word = np.uint64(0)
            for j in range(L):
                if directional[j]:
                    dx, dy, dz = lights[j, 0], lights[j, 1], lights[j, 2]
                else:
                    dx, dy, dz = lights[j, 0] - x, lights[j, 1] - y, lights[j, 2] - z
                dot = dx * nx + dy * ny + dz * nz
                if dot > 0.0:
                    word |= np.uint64(1) << np.uint64(j)
                elif dot == 0.0:
                    ties[c, j] += 1
            bits[p] = word
    return bits, ties.sum(axis=0)


@njit(cache=True, parallel=True)
def _pair_bits_kernel(bits, pair_faces, n_lights):  # pragma: no cover - compiled
    """The reference rule for every light at once: one XOR per two-sided edge; per light ascending ids."""
    E = pair_faces.shape[0]
    n_chunks = (E + _CHUNK - 1) // _CHUNK
    counts = np.zeros((n_chunks, n_lights), dtype=np.int64)
    for c in prange(n_chunks):
        for e in range(c * _CHUNK, min(E, (c + 1) * _CHUNK)):
            x = bits[pair_faces[e, 0]] ^ bits[pair_faces[e, 1]]
            j = 0
            while x:
                if x & np.uint64(1):
                    counts[c, j] += 1
                x >>= np.uint64(1)
                j += 1
    offset = np.zeros((n_chunks, n_lights), dtype=np.int64)  # where chunk c's ids of light j start
    start = np.zeros(n_lights + 1, dtype=np.int64)
    for j in range(n_lights):
        total = 0
        for c in range(n_chunks):
            offset[c, j] = total
            total += counts[c, j]
        start[j + 1] = start[j] + total
    out = np.empty(start[n_lights], dtype=np.int64)
    for c in prange(n_chunks):
        pos = np.empty(n_lights, dtype=np.int64)
        for j in range(n_lights):
            pos[j] = start[j] + offset[c, j]
        for e in range(c * _CHUNK, min(E, (c + 1) * _CHUNK)):
            x = bits[pair_faces[e, 0]] ^ bits[pair_faces[e, 1]]
            j = 0
            while x:
                if x & np.uint64(1):
                    out[pos[j]] = e
                    pos[j] += 1
                x >>= np.uint64(1)
                j += 1
    return start, out


def facing_flags(mesh: Mesh, light: Light, faces: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Light-facing flags and ties (of all faces, or of ``faces``), computed as
    :func:`~silcount.detectors.base.counted_visibility` does, in its operation order."""
    p0, nrm = _precompute(mesh)[:2]
    if faces is not None:
        p0, nrm = p0[faces], nrm[faces]
    directional = isinstance(light, DirectionalLight)
    src = light.direction if isinstance(light, DirectionalLight) else light.position
    flags, ties = _facing_kernel(p0, nrm, np.asarray(src, dtype=np.float64), directional)
    return flags, int(ties)


def edge_ids_of(mesh: Mesh, is_facing: np.ndarray) -> np.ndarray:
    """Ids of the edges with exactly one light-facing incident face, ascending: the reference rule."""
    _, _, two_ids, pair_faces, other, o_start, o_faces = _precompute(mesh)
    return _with_other_edges(two_ids, _pair_kernel(is_facing, pair_faces), other, o_start, o_faces, is_facing)


def _with_other_edges(two_ids, ids, other, o_start, o_faces, is_facing) -> np.ndarray:
    """Two-sided edges' ids (positions among them) to edge ids, with the other edges that pass the rule."""
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


BATCH = 64  # lights per pass of :func:`many_edge_ids` (one bit each in a uint64 per face)


def many_edge_ids(mesh: Mesh, lights: list[Light]) -> list[tuple[np.ndarray, int, np.ndarray, int]]:
    """For each light: (reference edge ids, ties, the packed facing words, its bit), 64 lights per pass.

    Each face's facing flags for up to 64 lights are one ``uint64`` (computed as
    :func:`facing_flags` does); one pass over the two-sided edges XORs their two
    faces' words, and each set bit is a silhouette edge of that light.
    """
    p0, nrm, two_ids, pair_faces, other, o_start, o_faces = _precompute(mesh)
    out = []
    for lo in range(0, len(lights), BATCH):
        batch = lights[lo : lo + BATCH]
        pos = np.array([L.direction if isinstance(L, DirectionalLight) else L.position for L in batch])
        directional = np.array([isinstance(L, DirectionalLight) for L in batch])
        bits, ties = _facing_bits_kernel(p0, nrm, pos.reshape(-1, 3), directional)
        start, ids = _pair_bits_kernel(bits, pair_faces, len(batch))
        for j in range(len(batch)):
            flags = facing_of_bits(bits, j) if other.size else None
            mine = _with_other_edges(two_ids, ids[start[j] : start[j + 1]], other, o_start, o_faces, flags)
            out.append((mine, int(ties[j]), bits, j))
    return out


def facing_of_bits(bits: np.ndarray, j: int) -> np.ndarray:
    """The facing flags of light ``j`` from the packed words of :func:`many_edge_ids`."""
    return ((bits >> np.uint64(j)) & np.uint64(1)).astype(bool)
