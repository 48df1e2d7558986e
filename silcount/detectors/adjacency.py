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
from silcount.threads import fitted_call

_PRECOMPUTED: "weakref.WeakKeyDictionary[Mesh, tuple]" = weakref.WeakKeyDictionary()


def edge_faces(mesh: Mesh) -> tuple:
    """Per-mesh arrays of the fast query, cached with the mesh and shared by every detector that needs them.

    ``(p0, normals, two_ids, pair_faces, other, o_start, o_faces)``: each face's ``p0`` and normal
    (contiguous float64); the ids of the edges with exactly two faces (``None`` when that is every edge)
    and their two faces in side order (uint32, one row each); the other edges' ids and their faces as a
    CSR (``o_start``, ``o_faces``), in side order.
    """
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


_CHUNK = 1 << 16  # faces or edges per parallel chunk; a mesh of one chunk runs serially


@njit(cache=True)
def facing_range(p0, nrm, light, directional, flags, lo, hi):  # pragma: no cover - compiled
    """Flags of faces ``lo .. hi - 1`` into ``flags``; returns their ties."""
    lx, ly, lz = light[0], light[1], light[2]
    t = 0
    for p in range(lo, hi):
        if directional:
            dx, dy, dz = lx, ly, lz
        else:
            dx, dy, dz = lx - p0[p, 0], ly - p0[p, 1], lz - p0[p, 2]
        dot = dx * nrm[p, 0] + dy * nrm[p, 1] + dz * nrm[p, 2]
        flags[p] = dot > 0.0
        t += dot == 0.0
    return t


@njit(cache=True, parallel=True)
def _facing_parallel(p0, nrm, light, directional, flags):  # pragma: no cover - compiled
    F = p0.shape[0]
    n_chunks = (F + _CHUNK - 1) // _CHUNK
    ties = np.zeros(n_chunks, dtype=np.int64)
    for c in prange(n_chunks):
        ties[c] = facing_range(p0, nrm, light, directional, flags, c * _CHUNK, min(F, (c + 1) * _CHUNK))
    return ties.sum()


def _facing_kernel(p0, nrm, light, directional) -> tuple[np.ndarray, int]:
    """Light-facing flags and ties; one chunk runs serially (waking the thread pool costs more than it saves)."""
    flags = np.empty(p0.shape[0], dtype=np.bool_)
    if p0.shape[0] <= _CHUNK:
        return flags, facing_range(p0, nrm, light, directional, flags, 0, p0.shape[0])
    return flags, _facing_parallel(p0, nrm, light, directional, flags)


@njit(cache=True)
def _pair_range(flags, pair_faces, out, lo, hi):  # pragma: no cover - compiled
    """Positions ``lo <= e < hi`` of the two-sided edges whose faces differ, written from ``out[lo]``; how many."""
    k = lo
    for e in range(lo, hi):
        if flags[pair_faces[e, 0]] != flags[pair_faces[e, 1]]:
            out[k] = e
            k += 1
    return k - lo


@njit(cache=True, parallel=True)
def _pair_parallel(flags, pair_faces, out):  # pragma: no cover - compiled
    E = pair_faces.shape[0]
    n_chunks = (E + _CHUNK - 1) // _CHUNK
    counts = np.zeros(n_chunks, dtype=np.int64)
    for c in prange(n_chunks):
        counts[c] = _pair_range(flags, pair_faces, out, c * _CHUNK, min(E, (c + 1) * _CHUNK))
    k = 0
    for c in range(n_chunks):  # compact the chunks' runs, in order
        for i in range(counts[c]):
            out[k + i] = out[c * _CHUNK + i]
        k += counts[c]
    return k


def _pair_kernel(flags, pair_faces) -> np.ndarray:
    """Positions of the two-sided edges with exactly one light-facing face, ascending."""
    out = np.empty(pair_faces.shape[0], dtype=np.int64)
    if pair_faces.shape[0] <= _CHUNK:
        return out[: _pair_range(flags, pair_faces, out, 0, pair_faces.shape[0])]
    return out[: _pair_parallel(flags, pair_faces, out)]


@njit(cache=True, parallel=True)
def _facing_bits_kernel(p0, nrm, dirs, dir_bit, points, point_bit):  # pragma: no cover - compiled
    """Bit ``j`` of word ``p``: face ``p`` faces light ``j`` (<= 64 lights), as :func:`_facing_kernel`.

    The directional lights (``dirs[k]``, bit ``dir_bit[k]``) and the point
    lights (``points[k]``, bit ``point_bit[k]``) each get a branch-free loop,
    with :func:`_facing_kernel`'s arithmetic (``d . n`` and ``(L - p0) . n``).
    Returns the words and the ties per bit.
    """
    F, nd, npt = p0.shape[0], dirs.shape[0], points.shape[0]
    bits = np.zeros(F, dtype=np.uint64)
    n_chunks = (F + _CHUNK - 1) // _CHUNK
    ties_d = np.zeros((n_chunks, nd), dtype=np.int64)
    ties_p = np.zeros((n_chunks, npt), dtype=np.int64)
    dx, dy, dz = dirs[:, 0].copy(), dirs[:, 1].copy(), dirs[:, 2].copy()
    lx, ly, lz = points[:, 0].copy(), points[:, 1].copy(), points[:, 2].copy()
    for c in prange(n_chunks):
        for p in range(c * _CHUNK, min(F, (c + 1) * _CHUNK)):
            x, y, z = p0[p, 0], p0[p, 1], p0[p, 2]
            nx, ny, nz = nrm[p, 0], nrm[p, 1], nrm[p, 2]
            word = np.uint64(0)
            for k in range(nd):
                dot = dx[k] * nx + dy[k] * ny + dz[k] * nz
                word |= np.uint64(dot > 0.0) << dir_bit[k]
                ties_d[c, k] += dot == 0.0
            for k in range(npt):
                dot = (lx[k] - x) * nx + (ly[k] - y) * ny + (lz[k] - z) * nz
                word |= np.uint64(dot > 0.0) << point_bit[k]
                ties_p[c, k] += dot == 0.0
            bits[p] = word
    ties = np.zeros(nd + npt, dtype=np.int64)
    ties[dir_bit.astype(np.int64)] = ties_d.sum(axis=0)
    ties[point_bit.astype(np.int64)] = ties_p.sum(axis=0)
    return bits, ties


_DEBRUIJN = np.uint64(0x03F79D71B4CB0A89)
_DEBRUIJN_BIT = np.array(
    [0, 1, 48, 2, 57, 49, 28, 3, 61, 58, 50, 42, 38, 29, 17, 4, 62, 55, 59, 36, 53, 51, 43, 22, 45, 39, 33, 30, 24, 18,
     12, 5, 63, 47, 56, 27, 60, 41, 37, 16, 54, 35, 52, 21, 44, 32, 23, 11, 46, 26, 40, 15, 34, 20, 31, 10, 25, 14, 19,
     9, 13, 8, 7, 6],
    dtype=np.int64,
)  # fmt: skip


@njit(cache=True, inline="always")
def _lowest_bit(x):  # pragma: no cover - compiled
    """Position of the lowest set bit of ``x != 0`` (de Bruijn multiplication)."""
    return _DEBRUIJN_BIT[((x & (~x + np.uint64(1))) * _DEBRUIJN) >> np.uint64(58)]


@njit(cache=True, parallel=True)
def _pair_bits_kernel(bits, pair_faces, n_lights):  # pragma: no cover - compiled
    """The reference rule for every light at once: one XOR per two-sided edge; per light ascending ids."""
    E = pair_faces.shape[0]
    n_chunks = (E + _CHUNK - 1) // _CHUNK
    counts = np.zeros((n_chunks, n_lights), dtype=np.int64)
    xor = np.empty(E, dtype=np.uint64)  # kept for the second pass: a sequential read instead of two gathers
    for c in prange(n_chunks):
        for e in range(c * _CHUNK, min(E, (c + 1) * _CHUNK)):
            x = bits[pair_faces[e, 0]] ^ bits[pair_faces[e, 1]]
            xor[e] = x
            while x:
                counts[c, _lowest_bit(x)] += 1
                x &= x - np.uint64(1)
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
            x = xor[e]
            while x:
                j = _lowest_bit(x)
                out[pos[j]] = e
                pos[j] += 1
                x &= x - np.uint64(1)
    return start, out


@fitted_call
def facing_flags(mesh: Mesh, light: Light, faces: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Light-facing flags and ties (of all faces, or of ``faces``), computed as
    :func:`~silcount.detectors.base.counted_visibility` does, in its operation order."""
    p0, nrm = edge_faces(mesh)[:2]
    if faces is not None:
        p0, nrm = p0[faces], nrm[faces]
    directional = isinstance(light, DirectionalLight)
    src = light.direction if isinstance(light, DirectionalLight) else light.position
    flags, ties = _facing_kernel(p0, nrm, np.asarray(src, dtype=np.float64), directional)
    return flags, int(ties)


_LAST_FACING: "weakref.WeakKeyDictionary[Mesh, tuple[bytes, np.ndarray, int]]" = weakref.WeakKeyDictionary()


def shared_facing_flags(mesh: Mesh, light: Light) -> tuple[np.ndarray, int]:
    """:func:`facing_flags` of every face, the last light's result kept with the mesh.

    The counted ``fast`` engines call this. Detectors run one after another under one light, as in a
    corpus sweep, so they evaluate each face once, not once each. The key is the light's kind and the
    bytes of its coordinates, so only the identical light reuses a result. The flags are shared and
    never written to. The plain loops, which are timed, call :func:`facing_flags` and pay for their own.
    """
    key = bytes([isinstance(light, DirectionalLight)]) + np.asarray(light.vector, dtype=np.float64).tobytes()
    got = _LAST_FACING.get(mesh)
    if got is None or got[0] != key:
        flags, ties = facing_flags(mesh, light)
        got = (key, flags, ties)
        _LAST_FACING[mesh] = got
    return got[1], got[2]


@fitted_call
def edge_ids_of(mesh: Mesh, is_facing: np.ndarray) -> np.ndarray:
    """Ids of the edges with exactly one light-facing incident face, ascending: the reference rule."""
    _, _, two_ids, pair_faces, other, o_start, o_faces = edge_faces(mesh)
    ids = _pair_kernel(is_facing, pair_faces)
    return _with_other_edges(two_ids, ids, other, o_start, None if two_ids is None else is_facing[o_faces])


def _with_other_edges(two_ids, ids, other, o_start, other_facing) -> np.ndarray:
    """Two-sided edges' ids (positions among them) to edge ids, with the other edges that pass the rule.

    ``other_facing``: the facing flags of the other edges' faces (``o_faces``).
    """
    if two_ids is None:
        return ids
    ids = two_ids[ids]
    if other.size:
        per_edge = np.add.reduceat(other_facing.astype(np.int64), o_start[:-1])
        ids = np.sort(np.concatenate([ids, other[per_edge == 1]]))  # disjoint sets
    return ids


def silhouette_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The reference silhouette as ascending edge ids (no tallies): the yardstick for the others."""
    return edge_ids_of(mesh, facing_flags(mesh, light)[0])


BATCH = 64  # lights per pass of :func:`many_edge_ids` (one bit each in a uint64 per face)


_LAST_MANY: "weakref.WeakKeyDictionary[Mesh, tuple[bytes, list]]" = weakref.WeakKeyDictionary()


@fitted_call
def many_edge_ids(mesh: Mesh, lights: list[Light]) -> list[tuple[np.ndarray, int, np.ndarray, int]]:
    """For each light: (reference edge ids, ties, the packed facing words, its bit), 64 lights per pass.

    Each face's facing flags for up to 64 lights are one ``uint64`` (computed as
    :func:`facing_flags` does); one pass over the two-sided edges XORs their two
    faces' words, and each set bit is a silhouette edge of that light.  Boundary
    and non-manifold edges count their faces' bits per light.

    The last call's result is kept with the mesh (shared, never written to), as :func:`shared_facing_flags`
    keeps the last light's flags: a sweep asks for the same lights' reference again (HSD's notes count the
    reference edges inside its polygons), and only the identical lights, kind and coordinates, reuse it.
    """
    key = b"".join(bytes([L.is_directional]) + np.asarray(L.vector, dtype=np.float64).tobytes() for L in lights)
    got = _LAST_MANY.get(mesh)
    if got is not None and got[0] == key:
        return list(got[1])
    p0, nrm, two_ids, pair_faces, other, o_start, o_faces = edge_faces(mesh)
    out = []
    for lo in range(0, len(lights), BATCH):
        batch = lights[lo : lo + BATCH]
        directional = np.array([isinstance(L, DirectionalLight) for L in batch])
        pos = np.array([L.vector for L in batch], dtype=np.float64)
        dirs, points = pos[directional].reshape(-1, 3), pos[~directional].reshape(-1, 3)
        dir_bit, point_bit = (np.flatnonzero(m).astype(np.uint64) for m in (directional, ~directional))
        bits, ties = _facing_bits_kernel(p0, nrm, dirs, dir_bit, points, point_bit)
        start, ids = _pair_bits_kernel(bits, pair_faces, len(batch))
        other_bits = bits[o_faces]
        for j in range(len(batch)):
            flags = ((other_bits >> np.uint64(j)) & np.uint64(1)).astype(bool) if other.size else None
            mine = _with_other_edges(two_ids, ids[start[j] : start[j + 1]], other, o_start, flags)
            out.append((mine, int(ties[j]), bits, j))
    _LAST_MANY[mesh] = (key, out)
    return list(out)


def facing_of_bits(bits: np.ndarray, j: int) -> np.ndarray:
    """The facing flags of light ``j`` from the packed words of :func:`many_edge_ids`."""
    return ((bits >> np.uint64(j)) & np.uint64(1)).astype(bool)
