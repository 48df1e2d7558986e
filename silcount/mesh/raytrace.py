"""Ray casting against a triangle soup: a uniform grid built in numba, traversed in parallel.

Used by the EESD detector (EESD paper, Sec. 3.3: "a ray from the light
source ... if it has an intersection with one of the faces of occluder it is
not a silhouette") and by the shadow renderer's ray-cast reference.

The intersection test is Moller-Trumbore in float64, in one fixed order of
operations (:func:`moller_trumbore`) that silcount's counted EESD test
repeats on counting arithmetic, so both give bit-identical answers:

* ``e1 = b - a``, ``e2 = c - a``, ``p = D x e2``, ``det = e1 . p``, ``inv = 1 / det``,
  ``s = O - a``, ``u = (s . p) inv``, ``q = s x e1``, ``v = (D . q) inv``, ``t = (e2 . q) inv``;
* a hit iff ``det != 0`` and ``u >= 0`` and ``v >= 0`` and ``u + v <= 1`` and
  ``t_min < t < t_max``.

Tie rule: the barycentric bounds are *inclusive*, so a ray through a shared
edge or vertex hits (at least) one of the triangles that share it whenever
the computed coordinates land exactly on the edge (e.g. axis-aligned cases);
a ray lying in a triangle's plane (``det == 0``, grazing) never hits it; the
``t`` range is open at both ends.  Rounding can still separate two
triangles' computed coordinates by an ulp on general edges; the inclusive
rule closes the exact cases, it does not make the test watertight.

The grid: cells of equal size, about two per triangle, over the
triangles' bounding box; each triangle is listed in every cell its (slightly
padded) bounding box overlaps.  Those listings are bounded by
:data:`_ENTRIES_PER_TRIANGLE` per triangle: where triangles overlap (stacked
copies of one triangle list each in every cell, T x cells entries) the cells
are made coarser, halving the cells along each axis until the listings fit
(one cell lists each triangle once).  The grid decides only which triangles a
ray is tested against, never the answer: a coarser grid tests more of them.
Traversal is the 3D-DDA of Amanatides & Woo over the ray's clipped ``t``
range; ``first_hit`` stops once the best hit lies before the current cell's
exit.  Rays are traced in chunks (:func:`silcount.mesh.chunks.run_chunks`,
Ctrl-C between chunks) and their ray-triangle tests counted against the work
limit when the caller names the computation.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from silcount.mesh.chunks import Meter, run_chunks

_CELLS_PER_TRIANGLE = 2.0
_ENTRIES_PER_TRIANGLE = 8  # the grid's listings at most (about 2.2 on closed meshes)


@nb.njit(cache=True, error_model="numpy", inline="always")
def moller_trumbore(ox, oy, oz, dx, dy, dz, ax, ay, az, bx, by, bz, cx, cy, cz, t_min, t_max):
    """(hit, t) for one ray and one triangle, in the documented order of operations."""
    e1x, e1y, e1z = bx - ax, by - ay, bz - az
    e2x, e2y, e2z = cx - ax, cy - ay, cz - az
    px = dy * e2z - dz * e2y
    py = dz * e2x - dx * e2z
    pz = dx * e2y - dy * e2x
    det = e1x * px + e1y * py + e1z * pz
    inv = 1.0 / det
    sx, sy, sz = ox - ax, oy - ay, oz - az
    u = (sx * px + sy * py + sz * pz) * inv
    qx = sy * e1z - sz * e1y
    qy = sz * e1x - sx * e1z
    qz = sx * e1y - sy * e1x
    v = (dx * qx + dy * qy + dz * qz) * inv
    t = (e2x * qx + e2y * qy + e2z * qz) * inv
    hit = (det != 0.0) & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > t_min) & (t < t_max)
    return hit, t


@nb.njit(cache=True, error_model="numpy", inline="always")
def _meets(o, d, tr, t_min, t_max):  # pragma: no cover - compiled
    """:func:`moller_trumbore` of the ray ``o + t d`` and the triangle ``tr`` (3, 3): ``(hit, t)``."""
    return moller_trumbore(
        o[0], o[1], o[2], d[0], d[1], d[2],
        tr[0, 0], tr[0, 1], tr[0, 2], tr[1, 0], tr[1, 1], tr[1, 2], tr[2, 0], tr[2, 1], tr[2, 2],
        t_min, t_max,
    )  # fmt: skip


@nb.njit(cache=True)
def _cell_ranges(lo, hi, origin, size, dims, pad):
    T = lo.shape[0]
    rng = np.empty((T, 6), dtype=np.int64)
    for i in range(T):
        for k in range(3):
            a = int(np.floor((lo[i, k] - pad - origin[k]) / size[k]))
            b = int(np.floor((hi[i, k] + pad - origin[k]) / size[k]))
            rng[i, 2 * k] = min(max(a, 0), dims[k] - 1)
            rng[i, 2 * k + 1] = min(max(b, 0), dims[k] - 1)
    return rng


@nb.njit(cache=True)
def _entries(rng):
    """How many (cell, triangle) listings the cell ranges ``rng`` make."""
    total = 0
    for i in range(rng.shape[0]):
        total += (rng[i, 1] - rng[i, 0] + 1) * (rng[i, 3] - rng[i, 2] + 1) * (rng[i, 5] - rng[i, 4] + 1)
    return total


@nb.njit(cache=True)
def _fill_grid(rng, dims):
    n_cells = dims[0] * dims[1] * dims[2]
    count = np.zeros(n_cells + 1, dtype=np.int64)
    for i in range(rng.shape[0]):
        for x in range(rng[i, 0], rng[i, 1] + 1):
            for y in range(rng[i, 2], rng[i, 3] + 1):
                for z in range(rng[i, 4], rng[i, 5] + 1):
                    count[(x * dims[1] + y) * dims[2] + z + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for i in range(rng.shape[0]):
        for x in range(rng[i, 0], rng[i, 1] + 1):
            for y in range(rng[i, 2], rng[i, 3] + 1):
                for z in range(rng[i, 4], rng[i, 5] + 1):
                    c = (x * dims[1] + y) * dims[2] + z
                    items[fill[c]] = i
                    fill[c] += 1
    return start, items


@nb.njit(cache=True, error_model="numpy")
def _trace_one(o, d, t_min, t_max, ignore, any_mode, tris, start, items, origin, size, dims):
    """Walk the grid for one ray; returns (t, triangle) of the nearest hit, or of any hit in any_mode, and the
    ray-triangle tests made."""
    best_t, best_i, tests = np.inf, -1, 0
    for k in range(3):
        if not (np.isfinite(o[k]) and np.isfinite(d[k])):
            return best_t, best_i, tests
    if not (t_min < t_max):
        return best_t, best_i, tests
    t0, t1 = t_min, t_max
    for k in range(3):
        lo_k, hi_k = origin[k], origin[k] + size[k] * dims[k]
        if d[k] == 0.0:
            if o[k] < lo_k or o[k] > hi_k:
                return best_t, best_i, tests
        else:
            ta, tb = (lo_k - o[k]) / d[k], (hi_k - o[k]) / d[k]
            if ta > tb:
                ta, tb = tb, ta
            t0, t1 = max(t0, ta), min(t1, tb)
    if not (t0 <= t1) or not np.isfinite(t0):
        return best_t, best_i, tests
    cell = np.empty(3, dtype=np.int64)
    step = np.empty(3, dtype=np.int64)
    t_next = np.empty(3)
    t_delta = np.empty(3)
    for k in range(3):
        c = int(np.floor((o[k] + t0 * d[k] - origin[k]) / size[k]))
        c = min(max(c, 0), dims[k] - 1)
        cell[k] = c
        if d[k] > 0.0:
            step[k] = 1
            t_next[k] = (origin[k] + (c + 1) * size[k] - o[k]) / d[k]
            t_delta[k] = size[k] / d[k]
        elif d[k] < 0.0:
            step[k] = -1
            t_next[k] = (origin[k] + c * size[k] - o[k]) / d[k]
            t_delta[k] = -size[k] / d[k]
        else:
            step[k] = 0
            t_next[k] = np.inf
            t_delta[k] = np.inf
    while True:
        c = (cell[0] * dims[1] + cell[1]) * dims[2] + cell[2]
        for j in range(start[c], start[c + 1]):
            i = items[j]
            if i == ignore:
                continue
            tr = tris[i]
            hit, t = _meets(o, d, tr, t_min, t_max)
            tests += 1
            if hit and (t < best_t or (t == best_t and i < best_i)):
                best_t, best_i = t, i
                if any_mode:
                    return best_t, best_i, tests
        k = 0
        if t_next[1] < t_next[k]:
            k = 1
        if t_next[2] < t_next[k]:
            k = 2
        exit_t = t_next[k]
        if best_i >= 0 and best_t < exit_t:
            return best_t, best_i, tests
        if exit_t > t1:
            return best_t, best_i, tests
        cell[k] += step[k]
        if cell[k] < 0 or cell[k] >= dims[k]:
            return best_t, best_i, tests
        t_next[k] += t_delta[k]


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _trace(lo, hi, origins, directions, t_min, t_max, ignore, any_mode, tris, start, items, origin, size, dims,
           out_t, out_i):  # fmt: skip
    """Rays ``lo .. hi - 1`` into ``out_t``, ``out_i``; returns their ray-triangle tests."""
    tests = 0
    for r in nb.prange(lo, hi):
        out_t[r], out_i[r], n = _trace_one(
            origins[r], directions[r], t_min[r], t_max[r], ignore[r], any_mode, tris, start, items, origin, size, dims
        )
        tests += n
    return tests


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _hits_one_each(origins, directions, tris, which, t_min, t_max):
    R = origins.shape[0]
    out = np.zeros(R, dtype=np.bool_)
    for r in nb.prange(R):
        o, d, tr = origins[r], directions[r], tris[which[r]]
        out[r] = _meets(o, d, tr, t_min[r], t_max[r])[0]
    return out


def _per_ray(value, R: int, dtype) -> np.ndarray:
    arr = np.asarray(value, dtype=dtype)
    return np.ascontiguousarray(np.broadcast_to(arr, (R,)))


class RayTracer:
    """Nearest-hit and any-hit queries of many rays against fixed triangles (T, 3, 3)."""

    def __init__(self, triangles: np.ndarray) -> None:
        tris = np.ascontiguousarray(np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3))
        self.triangles = tris
        T = tris.shape[0]
        if T == 0:
            self._origin, self._size = np.zeros(3), np.ones(3)
            self._dims = np.ones(3, dtype=np.int64)
            self._start, self._items = np.zeros(2, dtype=np.int64), np.zeros(0, dtype=np.int64)
            return
        lo, hi = tris.min(axis=1), tris.max(axis=1)
        b0, b1 = lo.min(axis=0), hi.max(axis=0)
        diag = float(np.linalg.norm(b1 - b0)) or 1.0
        ext = np.maximum(b1 - b0, 1e-3 * diag)
        margin = 1e-6 * diag
        b0, ext = b0 - margin - 0.5 * (ext - (b1 - b0)), ext + 2 * margin
        cell = (np.prod(ext) / (_CELLS_PER_TRIANGLE * T)) ** (1.0 / 3.0)
        dims = np.clip(np.ceil(ext / cell), 1, 1024).astype(np.int64)
        size = ext / dims
        while True:
            pad = 1e-7 * float(size.min())
            rng = _cell_ranges(lo, hi, b0, size, dims, pad)
            if _entries(rng) <= _ENTRIES_PER_TRIANGLE * T or dims.max() == 1:
                break
            dims = (dims + 1) // 2  # overlapping triangles: coarser cells (module docstring)
            size = ext / dims
        self._origin, self._size, self._dims = b0, size, dims
        self._start, self._items = _fill_grid(rng, dims)

    def _run(self, origins, directions, t_min, t_max, ignore, any_mode: bool, what: str | None):
        o = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3))
        d = np.ascontiguousarray(np.asarray(directions, dtype=np.float64).reshape(-1, 3))
        R = o.shape[0]
        if d.shape[0] != R:
            raise ValueError(f"{R} origins but {d.shape[0]} directions")
        ign = _per_ray(-1 if ignore is None else ignore, R, np.int64)
        lo_t, hi_t = _per_ray(t_min, R, np.float64), _per_ray(t_max, R, np.float64)
        out_t, out_i = np.empty(R), np.empty(R, dtype=np.int64)
        grid = (self.triangles, self._start, self._items, self._origin, self._size, self._dims)
        run_chunks(
            R,
            lambda a, b: _trace(a, b, o, d, lo_t, hi_t, ign, any_mode, *grid, out_t, out_i),
            None if what is None else Meter(what),
        )
        return out_t, out_i

    def first_hit(self, origins, directions, t_min=0.0, t_max=np.inf, what=None) -> tuple[np.ndarray, np.ndarray]:
        """(R,) hit distance (np.inf where none) and (R,) triangle index (-1 where none).

        ``t`` is in units of the given (not necessarily unit) direction; hits
        count for ``t_min < t < t_max``.  Equal distances go to the lower index.
        ``what``: the computation's name, to hold its ray-triangle tests to the work limit
        (:class:`silcount.mesh.chunks.Meter`; None: not held).
        """
        return self._run(origins, directions, t_min, t_max, None, False, what)

    def any_hit(self, origins, directions, t_min=0.0, t_max=np.inf, ignore=None, what=None) -> np.ndarray:
        """(R,) bool: does the ray meet any triangle with t in (t_min, t_max)?

        ``ignore``: optional (R,) triangle index to skip per ray (-1 none); ``what`` as in :meth:`first_hit`.
        """
        return self._run(origins, directions, t_min, t_max, ignore, True, what)[1] >= 0

    def hits_triangle(self, origins, directions, which, t_min=0.0, t_max=np.inf) -> np.ndarray:
        """(R,) bool: does ray r meet triangle ``which[r]`` (the same test, no grid)?"""
        o = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3))
        d = np.ascontiguousarray(np.asarray(directions, dtype=np.float64).reshape(-1, 3))
        R = o.shape[0]
        return _hits_one_each(
            o,
            d,
            self.triangles,
            _per_ray(which, R, np.int64),
            _per_ray(t_min, R, np.float64),
            _per_ray(t_max, R, np.float64),
        )


__all__ = ["RayTracer", "moller_trumbore"]
