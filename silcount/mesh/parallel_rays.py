"""Parallel lines against a triangle soup: a 2-D grid of the triangles projected along the lines' direction.

Used by the EESD detector's ``fast`` engine under a directional light, whose
rays (EESD paper Sec. 3.3: "a ray from the light source ... if it has an
intersection with one of the faces of occluder it is not a silhouette") are
lines of one direction through each edge's outward point, every ``t``.  The
test is :func:`silcount.mesh.raytrace.moller_trumbore`, the tracer's own, on
the triangles a line's cell lists; :func:`lines_any_hit` answers as
:meth:`silcount.mesh.raytrace.RayTracer.any_hit` does for those lines
(tested against it and against the test over every triangle).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from silcount.mesh.raytrace import moller_trumbore


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


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _lines_any_hit(origins, d, tris, done):  # pragma: no cover - compiled
    """:func:`lines_any_hit`: a per-call 2-D grid over the triangles projected along ``d``."""
    T, R = tris.shape[0], origins.shape[0]
    out = done.copy()
    if T == 0 or not (np.isfinite(d[0]) and np.isfinite(d[1]) and np.isfinite(d[2])) or not d.any():
        return out
    e1, e2 = _plane_frame(d)
    box = np.empty((T, 4))  # x lo, y lo, x hi, y hi (x lo = inf: a non-finite triangle, never listed)
    x0 = y0 = np.inf
    x1 = y1 = -np.inf
    area = big = 0.0  # big: the largest |coordinate| of a listed box
    n = 0
    for i in range(T):
        for k in range(2):
            e = e1 if k == 0 else e2
            a, b, c = _project(tris[i, 0], e), _project(tris[i, 1], e), _project(tris[i, 2], e)
            box[i, k], box[i, 2 + k] = min(a, b, c), max(a, b, c)
        lx, ly, hx, hy = box[i, 0], box[i, 1], box[i, 2], box[i, 3]
        if not (np.isfinite(lx) and np.isfinite(ly) and np.isfinite(hx) and np.isfinite(hy)):
            box[i, 0] = np.inf
            continue
        x0, y0, x1, y1 = min(x0, lx), min(y0, ly), max(x1, hx), max(y1, hy)
        area += (hx - lx) * (hy - ly)
        big = max(big, abs(lx), abs(ly), abs(hx), abs(hy))
        n += 1
    if n == 0:
        return out
    cell = max(np.sqrt(area / n), 1e-12 * max(x1 - x0, y1 - y0, 1e-300))  # about one triangle's box
    while ((x1 - x0) / cell + 1.0) * ((y1 - y0) / cell + 1.0) > 4.0 * n + 16.0:
        cell *= 1.5  # at most about four cells a triangle
    # Each box is padded (rounding of the projection, and the tracer's own margin) by at most ``most``, the
    # same formula at the largest coordinate (rounding is monotone), so the grid spans [x0 - most, x1 + most].
    most = 1e-7 * cell + 4e-16 * (big + big)
    x0, y0, x1, y1 = x0 - most, y0 - most, x1 + most, y1 + most
    gx = int((x1 - x0) / cell) + 1
    gy = int((y1 - y0) / cell) + 1
    inv = 1.0 / cell  # a cell index is int((v - lo) * inv): monotone in v, the same for boxes and points
    rng = np.empty((T, 4), dtype=np.int64)  # each triangle's cells: x from, x to, y from, y to (none unlisted)
    for i in range(T):
        if box[i, 0] == np.inf:
            rng[i, 0], rng[i, 1], rng[i, 2], rng[i, 3] = 0, -1, 0, -1
            continue
        for k in range(2):
            pad = 1e-7 * cell + 4e-16 * (abs(box[i, k]) + abs(box[i, 2 + k]))
            box[i, k] -= pad
            box[i, 2 + k] += pad
        rng[i, 0], rng[i, 1] = min(int((box[i, 0] - x0) * inv), gx - 1), min(int((box[i, 2] - x0) * inv), gx - 1)
        rng[i, 2], rng[i, 3] = min(int((box[i, 1] - y0) * inv), gy - 1), min(int((box[i, 3] - y0) * inv), gy - 1)
    count = np.zeros(gx * gy + 1, dtype=np.int64)
    for i in range(T):
        for y in range(rng[i, 2], rng[i, 3] + 1):
            for x in range(rng[i, 0], rng[i, 1] + 1):
                count[y * gx + x + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for i in range(T):
        for y in range(rng[i, 2], rng[i, 3] + 1):
            for x in range(rng[i, 0], rng[i, 1] + 1):
                items[fill[y * gx + x]] = i
                fill[y * gx + x] += 1
    for r in range(R):
        if out[r]:
            continue
        o = origins[r]
        px, py = _project(o, e1), _project(o, e2)
        if not (x0 <= px <= x1 and y0 <= py <= y1):  # outside every box (a NaN too): no hit, as in the tracer
            continue
        c = min(int((py - y0) * inv), gy - 1) * gx + min(int((px - x0) * inv), gx - 1)
        for j in range(start[c], start[c + 1]):
            i = items[j]
            if box[i, 0] <= px <= box[i, 2] and box[i, 1] <= py <= box[i, 3]:
                tr = tris[i]
                hit = moller_trumbore(o[0], o[1], o[2], d[0], d[1], d[2], tr[0, 0], tr[0, 1], tr[0, 2], tr[1, 0],
                                      tr[1, 1], tr[1, 2], tr[2, 0], tr[2, 1], tr[2, 2], -np.inf, np.inf)[0]  # fmt: skip
                if hit:
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
    per call, ``O(T)``; a line's query is one cell instead of a walk across the 3-D grid.  One thread, the
    GIL released: callers run several lights side by side (:func:`silcount.detectors.eesd.detector.detect_many`).
    """
    o = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3))
    d = np.ascontiguousarray(np.asarray(direction, dtype=np.float64).reshape(3))
    tris = np.ascontiguousarray(np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3))
    done = np.zeros(o.shape[0], dtype=np.bool_) if done is None else np.ascontiguousarray(done, dtype=np.bool_)
    return _lines_any_hit(o, d, tris, done)


__all__ = ["lines_any_hit"]
