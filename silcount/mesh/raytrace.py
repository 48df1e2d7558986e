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
padded) bounding box overlaps.  Traversal is the 3D-DDA of Amanatides & Woo
over the ray's clipped ``t`` range; ``first_hit`` stops once the best hit
lies before the current cell's exit.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_CELLS_PER_TRIANGLE = 2.0


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
    """Walk the grid for one ray; returns (t, triangle) of the nearest hit, or of any hit in any_mode."""
    best_t, best_i = np.inf, -1
    for k in range(3):
        if not (np.isfinite(o[k]) and np.isfinite(d[k])):
            return best_t, best_i
    if not (t_min < t_max):
        return best_t, best_i
    t0, t1 = t_min, t_max
    for k in range(3):
        lo_k, hi_k = origin[k], origin[k] + size[k] * dims[k]
        if d[k] == 0.0:
            if o[k] < lo_k or o[k] > hi_k:
                return best_t, best_i
        else:
            ta, tb = (lo_k - o[k]) / d[k], (hi_k - o[k]) / d[k]
            if ta > tb:
                ta, tb = tb, ta
            t0, t1 = max(t0, ta), min(t1, tb)
    if not (t0 <= t1) or not np.isfinite(t0):
        return best_t, best_i
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
            if hit and (t < best_t or (t == best_t and i < best_i)):
                best_t, best_i = t, i
                if any_mode:
                    return best_t, best_i
        k = 0
        if t_next[1] < t_next[k]:
            k = 1
        if t_next[2] < t_next[k]:
            k = 2
        exit_t = t_next[k]
        if best_i >= 0 and best_t < exit_t:
            return best_t, best_i
        if exit_t > t1:
            return best_t, best_i
        cell[k] += step[k]
        if cell[k] < 0 or cell[k] >= dims[k]:
            return best_t, best_i
        t_next[k] += t_delta[k]


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _trace(origins, directions, t_min, t_max, ignore, any_mode, tris, start, items, origin, size, dims):
    R = origins.shape[0]
    out_t = np.empty(R)
    out_i = np.empty(R, dtype=np.int64)
    for r in nb.prange(R):
        out_t[r], out_i[r] = _trace_one(
            origins[r], directions[r], t_min[r], t_max[r], ignore[r], any_mode, tris, start, items, origin, size, dims
        )
    return out_t, out_i


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _hits_one_each(origins, directions, tris, which, t_min, t_max):
    R = origins.shape[0]
    out = np.zeros(R, dtype=np.bool_)
    for r in nb.prange(R):
        o, d, tr = origins[r], directions[r], tris[which[r]]
        out[r] = _meets(o, d, tr, t_min[r], t_max[r])[0]
    return out


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _hits_any_of(origins, directions, start, tris, t_min, t_max):
    """Ray ``r`` (row ``r`` of ``origins`` and ``directions``, or their one row) against
    ``tris[start[r]:start[r + 1]]``."""
    R = start.size - 1
    out = np.zeros(R, dtype=np.bool_)
    step_o = np.int64(origins.shape[0] > 1)  # 0: every ray shares row 0
    step_d = np.int64(directions.shape[0] > 1)
    for r in nb.prange(R):
        o = origins[r * step_o]
        d = directions[r * step_d]
        for i in range(start[r], start[r + 1]):
            if _meets(o, d, tris[i], t_min, t_max)[0]:
                out[r] = True
                break
    return out


@nb.njit(cache=True)
def _plane_frame(d):  # pragma: no cover - compiled
    """Two unit vectors perpendicular to ``d`` and to each other."""
    n = d / np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.6 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(n, a)
    e1 /= np.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])
    return e1, np.cross(n, e1)


@nb.njit(cache=True, inline="always")
def _project(x, e):  # pragma: no cover - compiled
    return x[0] * e[0] + x[1] * e[1] + x[2] * e[2]


@nb.njit(cache=True, parallel=True, error_model="numpy")
def _lines_any_hit(origins, d, tris, done):  # pragma: no cover - compiled
    """:func:`lines_any_hit`: a per-call 2-D grid over the triangles projected along ``d``."""
    T, R = tris.shape[0], origins.shape[0]
    out = done.copy()
    if T == 0 or not (np.isfinite(d[0]) and np.isfinite(d[1]) and np.isfinite(d[2])) or not d.any():
        return out
    e1, e2 = _plane_frame(d)
    box = np.empty((T, 4))  # x lo, y lo, x hi, y hi (x lo = inf: a non-finite triangle, never listed)
    for i in nb.prange(T):
        for k in range(2):
            e = e1 if k == 0 else e2
            a, b, c = _project(tris[i, 0], e), _project(tris[i, 1], e), _project(tris[i, 2], e)
            box[i, k], box[i, 2 + k] = min(a, b, c), max(a, b, c)
        if not (np.isfinite(box[i, 0]) and np.isfinite(box[i, 1]) and np.isfinite(box[i, 2])
                and np.isfinite(box[i, 3])):  # fmt: skip
            box[i, 0] = np.inf
    x0 = y0 = np.inf
    x1 = y1 = -np.inf
    area = 0.0
    n = 0
    for i in range(T):
        if box[i, 0] < np.inf:
            x0, y0 = min(x0, box[i, 0]), min(y0, box[i, 1])
            x1, y1 = max(x1, box[i, 2]), max(y1, box[i, 3])
            area += (box[i, 2] - box[i, 0]) * (box[i, 3] - box[i, 1])
            n += 1
    if n == 0:
        return out
    cell = max(np.sqrt(area / n), 1e-12 * max(x1 - x0, y1 - y0, 1e-300))  # about one triangle's box
    while ((x1 - x0) / cell + 1.0) * ((y1 - y0) / cell + 1.0) > 4.0 * n + 16.0:
        cell *= 1.5  # at most about four cells a triangle
    for i in nb.prange(T):  # padded: rounding of the projection, and the tracer's own margin
        if box[i, 0] < np.inf:
            for k in range(2):
                pad = 1e-7 * cell + 4e-16 * (abs(box[i, k]) + abs(box[i, 2 + k]))
                box[i, k] -= pad
                box[i, 2 + k] += pad
    x0 = y0 = np.inf
    x1 = y1 = -np.inf
    for i in range(T):  # the grid spans the padded boxes
        if box[i, 0] < np.inf:
            x0, y0 = min(x0, box[i, 0]), min(y0, box[i, 1])
            x1, y1 = max(x1, box[i, 2]), max(y1, box[i, 3])
    gx = int((x1 - x0) / cell) + 1
    gy = int((y1 - y0) / cell) + 1
    count = np.zeros(gx * gy + 1, dtype=np.int64)
    for i in range(T):
        if box[i, 0] < np.inf:
            ax, bx = min(int((box[i, 0] - x0) / cell), gx - 1), min(int((box[i, 2] - x0) / cell), gx - 1)
            ay, by = min(int((box[i, 1] - y0) / cell), gy - 1), min(int((box[i, 3] - y0) / cell), gy - 1)
            for y in range(ay, by + 1):
                for x in range(ax, bx + 1):
                    count[y * gx + x + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for i in range(T):
        if box[i, 0] < np.inf:
            ax, bx = min(int((box[i, 0] - x0) / cell), gx - 1), min(int((box[i, 2] - x0) / cell), gx - 1)
            ay, by = min(int((box[i, 1] - y0) / cell), gy - 1), min(int((box[i, 3] - y0) / cell), gy - 1)
            for y in range(ay, by + 1):
                for x in range(ax, bx + 1):
                    items[fill[y * gx + x]] = i
                    fill[y * gx + x] += 1
    for r in nb.prange(R):
        if out[r]:
            continue
        o = origins[r]
        px, py = _project(o, e1), _project(o, e2)
        if not (x0 <= px <= x1 and y0 <= py <= y1):  # outside every box (a NaN too): no hit, as in the tracer
            continue
        c = min(int((py - y0) / cell), gy - 1) * gx + min(int((px - x0) / cell), gx - 1)
        for j in range(start[c], start[c + 1]):
            i = items[j]
            if box[i, 0] <= px <= box[i, 2] and box[i, 1] <= py <= box[i, 3]:
                if _meets(o, d, tris[i], -np.inf, np.inf)[0]:
                    out[r] = True
                    break
    return out


def lines_any_hit(origins, direction, triangles, done=None) -> np.ndarray:
    """(R,) bool: does the line ``o + t d`` (every ``t``: the ray of a directional light, both ways) through
    each origin meet any of ``triangles`` (T, 3, 3), by the tracer's test?  ``done``: lines already known to
    hit (left ``True``, not cast).

    Every line shares the one direction, so the triangles are projected onto a plane perpendicular to it
    and listed in a 2-D grid (cells of about one triangle's projected box, each triangle in every cell its
    box overlaps, padded as the 3-D grid pads); a line's point in that plane selects one cell, whose
    triangles whose box holds the point are tested with :func:`moller_trumbore` for ``t`` in
    ``(-inf, inf)``, as :meth:`RayTracer.any_hit` tests the triangles along the line.  The grid is built
    per call, ``O(T)``; a line's query is one cell instead of a walk across the 3-D grid.
    """
    o = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3))
    d = np.ascontiguousarray(np.asarray(direction, dtype=np.float64).reshape(3))
    tris = np.ascontiguousarray(np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3))
    done = np.zeros(o.shape[0], dtype=np.bool_) if done is None else np.ascontiguousarray(done, dtype=np.bool_)
    return _lines_any_hit(o, d, tris, done)


def _rows(a) -> np.ndarray:
    """A (R, 3) array, or the one row of a broadcast one (all rows equal, stride 0) as (1, 3)."""
    a = np.asarray(a, dtype=np.float64).reshape(-1, 3)
    if a.shape[0] > 1 and a.strides[0] == 0:
        return np.ascontiguousarray(a[:1])
    return np.ascontiguousarray(a)


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
        pad = 1e-7 * float(size.min())
        rng = _cell_ranges(lo, hi, b0, size, dims, pad)
        self._origin, self._size, self._dims = b0, size, dims
        self._start, self._items = _fill_grid(rng, dims)

    def _run(self, origins, directions, t_min, t_max, ignore, any_mode: bool):
        o = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3))
        d = np.ascontiguousarray(np.asarray(directions, dtype=np.float64).reshape(-1, 3))
        R = o.shape[0]
        if d.shape[0] != R:
            raise ValueError(f"{R} origins but {d.shape[0]} directions")
        ign = _per_ray(-1 if ignore is None else ignore, R, np.int64)
        return _trace(
            o,
            d,
            _per_ray(t_min, R, np.float64),
            _per_ray(t_max, R, np.float64),
            ign,
            any_mode,
            self.triangles,
            self._start,
            self._items,
            self._origin,
            self._size,
            self._dims,
        )

    def first_hit(self, origins, directions, t_min=0.0, t_max=np.inf) -> tuple[np.ndarray, np.ndarray]:
        """(R,) hit distance (np.inf where none) and (R,) triangle index (-1 where none).

        ``t`` is in units of the given (not necessarily unit) direction; hits
        count for ``t_min < t < t_max``.  Equal distances go to the lower index.
        """
        return self._run(origins, directions, t_min, t_max, None, False)

    def any_hit(self, origins, directions, t_min=0.0, t_max=np.inf, ignore=None) -> np.ndarray:
        """(R,) bool: does the ray meet any triangle with t in (t_min, t_max)?

        ``ignore``: optional (R,) triangle index to skip per ray (-1 none).
        """
        return self._run(origins, directions, t_min, t_max, ignore, True)[1] >= 0

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


def hits_any_of(origins, directions, start, triangles, t_min: float = 0.0, t_max: float = np.inf) -> np.ndarray:
    """(R,) bool: does ray r meet any of ``triangles[start[r]:start[r + 1]]`` (the tracer's test, no grid)?

    ``triangles`` is (N, 3, 3), laid out in ray order: read in order, they stream, where the same triangles
    reached through an index into a tracer's list are scattered reads (EESD's own faces on armadillo.obj:
    15 ms a light through an index, 4 ms laid out).  ``origins`` and ``directions`` are (R, 3), or one row
    broadcast to (R, 3); each ray stops at its first hit, so the answer is that of testing every triangle.
    """
    start = np.ascontiguousarray(start, dtype=np.int64)
    o, d = _rows(origins), _rows(directions)
    R = start.size - 1
    for name, a in (("origins", o), ("directions", d)):
        if a.shape[0] not in (1, R):
            raise ValueError(f"{R} rays but {a.shape[0]} {name}")
    tris = np.ascontiguousarray(np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3))
    return _hits_any_of(o, d, start, tris, float(t_min), float(t_max))


__all__ = ["RayTracer", "hits_any_of", "lines_any_hit", "moller_trumbore"]
