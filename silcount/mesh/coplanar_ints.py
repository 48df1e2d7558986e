"""The tight merge's tests on exact Python integers, for coordinates outside the expansions' range.

:mod:`silcount.mesh.coplanar` decides coplanarity and orientation with Shewchuk's expansions
(:mod:`silcount.mesh.exact`), exact for every nonzero ``|x|`` in ``[2^-150, 2^150]``.  Outside that
range (or to check the compiled kernel, ``tests/test_speed_exact.py``) the same decisions are made
here: the float filter vectorised in numpy, then every test it cannot decide, and every
``n_f . n_g``, on Python integers (all coordinates scaled by one common power of two: the exact
rational arithmetic of :class:`fractions.Fraction` without its normalisation).
"""

from __future__ import annotations

import numpy as np

from silcount.mesh.exact import ERRBOUND_A
from silcount.mesh.model import Mesh

_CHUNK = 1 << 18


def exact_ints(x: np.ndarray, shift: int) -> np.ndarray:
    """``x * 2**shift`` as exact Python integers (object array); ``shift`` makes every value integral."""
    mant, expo = np.frexp(x)
    m = (mant * 2.0**53).astype(np.int64)
    s = np.maximum(expo.astype(np.int64) - 53 + shift, 0)  # zeros have m == 0
    return np.left_shift(m.astype(object), s.astype(object))


def mask_ids(n: int, *ids: np.ndarray) -> np.ndarray:
    """The distinct values of ``ids`` (all in ``0..n-1``), ascending."""
    seen = np.zeros(n, dtype=bool)
    for x in ids:
        seen[x.ravel()] = True
    return np.flatnonzero(seen)


def common_shift(x: np.ndarray) -> int:
    nz = x[x != 0.0]
    if nz.size == 0:
        return 0
    _, expo = np.frexp(nz)
    return int(max(0, 53 - int(expo.min())))


def _orient3d_float(a, b, c, d) -> tuple[np.ndarray, np.ndarray]:
    """Shewchuk's orient3dfast and its static error bound, vectorised over rows."""
    ad, bd, cd = a - d, b - d, c - d
    bc = bd[:, 0] * cd[:, 1] - cd[:, 0] * bd[:, 1]
    ca = cd[:, 0] * ad[:, 1] - ad[:, 0] * cd[:, 1]
    ab = ad[:, 0] * bd[:, 1] - bd[:, 0] * ad[:, 1]
    det = ad[:, 2] * bc + bd[:, 2] * ca + cd[:, 2] * ab
    perm = (
        (np.abs(bd[:, 0] * cd[:, 1]) + np.abs(cd[:, 0] * bd[:, 1])) * np.abs(ad[:, 2])
        + (np.abs(cd[:, 0] * ad[:, 1]) + np.abs(ad[:, 0] * cd[:, 1])) * np.abs(bd[:, 2])
        + (np.abs(ad[:, 0] * bd[:, 1]) + np.abs(bd[:, 0] * ad[:, 1])) * np.abs(cd[:, 2])
    )
    return det, ERRBOUND_A * perm


def _orient3d_exact_zero(a, b, c, d) -> np.ndarray:
    """Exact ``orient3d == 0`` on object arrays of integers."""
    ad, bd, cd = a - d, b - d, c - d
    det = (
        ad[:, 2] * (bd[:, 0] * cd[:, 1] - cd[:, 0] * bd[:, 1])
        + bd[:, 2] * (cd[:, 0] * ad[:, 1] - ad[:, 0] * cd[:, 1])
        + cd[:, 2] * (ad[:, 0] * bd[:, 1] - bd[:, 0] * ad[:, 1])
    )
    return np.asarray(det == 0, dtype=bool)


def _cross(u, v):
    return np.stack(
        [
            u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],
            u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
            u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0],
        ],
        axis=1,
    )


def normals_agree_ints(V, first3, faces, f, g, shift) -> np.ndarray:
    """``n_f . n_g > 0`` exactly, on Python integers (coordinates outside the expansions' exact range)."""
    used = mask_ids(V.shape[0], first3[faces])
    exact = np.empty((V.shape[0], 3), dtype=object)
    exact[used] = exact_ints(V[used], shift)
    normals = np.empty((first3.shape[0], 3), dtype=object)
    for lo in range(0, faces.size, _CHUNK):
        part = faces[lo : lo + _CHUNK]
        p0, p1, p2 = (exact[first3[part, i]] for i in range(3))
        normals[part] = _cross(p1 - p0, p2 - p0)
    same = np.zeros(f.size, dtype=bool)
    for lo in range(0, f.size, _CHUNK):
        a, b = f[lo : lo + _CHUNK], g[lo : lo + _CHUNK]
        same[lo : lo + _CHUNK] = np.asarray((normals[a] * normals[b]).sum(axis=1) > 0, dtype=bool)
    return same


def coplanar_pairs_ints(mesh: Mesh, f: np.ndarray, g: np.ndarray, first3: np.ndarray, steps: dict) -> np.ndarray:
    """``coplanar`` of :func:`silcount.mesh.coplanar._coplanar_pairs`, in numpy and Python integers.

    Sets ``steps["orient3d_filter"]`` and ``steps["orient3d_exact"]`` as the kernel counts them.
    """
    sizes = mesh.face_sizes
    tri_f, tri_g = sizes[f] == 3, sizes[g] == 3
    one, two = np.flatnonzero(tri_f | ~tri_g), np.flatnonzero(~tri_f)
    plane = np.concatenate([f[one], g[two]])
    other = np.concatenate([g[one], f[two]])
    pair = np.concatenate([one, two])
    k = sizes[other]
    t_pair = np.repeat(pair, k)
    t_plane = np.repeat(plane, k)
    t_point = mesh.corners[np.repeat(mesh.face_start[other], k) + np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)]
    on_plane_corner = (first3[t_plane] == t_point[:, None]).any(axis=1)  # trivially on the plane
    t_pair, t_plane, t_point = t_pair[~on_plane_corner], t_plane[~on_plane_corner], t_point[~on_plane_corner]
    V = mesh.vertices
    a, b, c = (V[first3[t_plane, i]] for i in range(3))
    det, bound = _orient3d_float(a, b, c, V[t_point])
    steps["orient3d_filter"] = int(t_pair.size)
    off_plane = np.abs(det) > bound
    unsure = np.flatnonzero(~off_plane)
    steps["orient3d_exact"] = int(unsure.size)
    if unsure.size:
        used = mask_ids(V.shape[0], first3[t_plane[unsure]], t_point[unsure])
        exact = np.empty((V.shape[0], 3), dtype=object)
        exact[used] = exact_ints(V[used], common_shift(V))
        for lo in range(0, unsure.size, _CHUNK):  # bounded memory for the object arrays
            part = unsure[lo : lo + _CHUNK]
            a, b, c = (exact[first3[t_plane[part], i]] for i in range(3))
            zero = _orient3d_exact_zero(a, b, c, exact[t_point[part]])
            off_plane[part[~zero]] = True
    coplanar = np.ones(f.size, dtype=bool)
    coplanar[t_pair[off_plane]] = False
    return coplanar
