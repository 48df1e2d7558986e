"""The rasteriser: homogeneous clipping, pixel-centre sampling, depth and an integer stencil.

* Triangles arrive in clip coordinates ``(x, y, z, w)``; points at infinity
  (``w_world = 0``) are ordinary input.  Each triangle is clipped
  (Sutherland-Hodgman, in homogeneous space) against the near plane
  ``z >= -w``, a guard band ``|x|, |y| <= 2 w`` and ``w > 0``; an
  intersection is always computed from the inside vertex towards the
  outside one, so two triangles sharing an edge get bit-identical new
  vertices.
* Vertices snap to a fixed-point grid of 1/256 pixel and edge functions are
  evaluated in exact int64 arithmetic.  A pixel is drawn iff its centre
  ``(col + 0.5, row + 0.5)`` is inside, or on a top or left edge (the
  Direct3D/OpenGL top-left rule): two triangles sharing an edge cover each
  pixel centre exactly once.
* Depth is NDC ``z = z_c / w_c``, which is affine in screen space, so
  interpolating it with screen-space barycentrics is perspective-correct.
  The depth test is ``LESS`` against a buffer cleared to 1 (the far plane).
* Facing is the clip-space winding: counter-clockwise in NDC (y up) is
  front-facing, as OpenGL's default ``glFrontFace(GL_CCW)``.

Modes: ``DEPTH`` writes depth and a triangle id; ``ZPASS`` adds +1 (front)
/ -1 (back) to the stencil where the depth test passes; ``ZFAIL`` adds +1
(back) / -1 (front) where it fails: the two-sided stencil of the stencil
paper Sec. 5 steps (4)-(5) and of Everitt & Kilgard 2002.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

DEPTH, ZPASS, ZFAIL = 0, 1, 2
SUBPIXEL = 256
GUARD = 2.0
_W_MIN = 1e-9
_MAXV = 16


@njit(cache=True)
def _plane_distance(p, k, guard):
    if k == 0:
        return p[2] + p[3]  # near: z >= -w
    if k == 1:
        return guard * p[3] + p[0]  # x >= -g w
    if k == 2:
        return guard * p[3] - p[0]  # x <= g w
    if k == 3:
        return guard * p[3] + p[1]
    if k == 4:
        return guard * p[3] - p[1]
    return p[3] - _W_MIN  # w > 0


@njit(cache=True)
def _clip(tri, poly, tmp, guard):
    """Clip one triangle (3, 4) into ``poly``; returns the vertex count."""
    n = 3
    for i in range(3):
        for c in range(4):
            poly[i, c] = tri[i, c]
    for k in range(6):
        m = 0
        for i in range(n):
            a = poly[i]
            b = poly[(i + 1) % n]
            da = _plane_distance(a, k, guard)
            db = _plane_distance(b, k, guard)
            if da >= 0.0:
                for c in range(4):
                    tmp[m, c] = a[c]
                m += 1
            if (da >= 0.0) != (db >= 0.0):
                # from the inside vertex towards the outside one: order-independent
                if da >= 0.0:
                    t = da / (da - db)
                    for c in range(4):
                        tmp[m, c] = a[c] + t * (b[c] - a[c])
                else:
                    t = db / (db - da)
                    for c in range(4):
                        tmp[m, c] = b[c] + t * (a[c] - b[c])
                m += 1
        n = m
        for i in range(n):
            for c in range(4):
                poly[i, c] = tmp[i, c]
        if n < 3:
            return 0
    return n


@njit(cache=True, inline="always")
def _span(ax, ay, bx, by, bias, py, lo, hi):
    """Narrow the column range [lo, hi] of row centre ``py`` to where ``E_ab + bias > 0`` (exact integers)."""
    # E(c) = (bx - ax)(py - ay) - (by - ay)(c S + S/2 - ax) = base + step c
    base = (bx - ax) * (py - ay) - (by - ay) * (SUBPIXEL // 2 - ax)
    step = -(by - ay) * SUBPIXEL
    k = -(base + bias)  # need step * c > k
    if step > 0:
        lo = max(lo, k // step + 1)
    elif step < 0:
        hi = min(hi, -(k // -step) - 1)
    elif k >= 0:
        hi = lo - 1
    return lo, hi


@njit(cache=True)
def _fill(x0, y0, z0, x1, y1, z1, x2, y2, z2, front, mode, ident, depth, stencil, tri_id):
    """Fill one snapped triangle with positive area ``E01(v2) > 0`` (interior where all E > 0).

    Each row's span is solved from the three edge functions, so only covered
    pixels are visited (long thin shadow-volume sides have huge bounding boxes).
    """
    H, W = depth.shape
    area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
    half = SUBPIXEL // 2
    c0 = max(0, int(math.ceil((min(x0, min(x1, x2)) - half) / SUBPIXEL)))
    c1 = min(W - 1, int(math.floor((max(x0, max(x1, x2)) - half) / SUBPIXEL)))
    r0 = max(0, int(math.ceil((min(y0, min(y1, y2)) - half) / SUBPIXEL)))
    r1 = min(H - 1, int(math.floor((max(y0, max(y1, y2)) - half) / SUBPIXEL)))
    # top-left rule: an edge a->b owns its centres iff dy < 0, or dy == 0 and dx > 0
    b01 = 1 if (y1 - y0 < 0 or (y1 == y0 and x1 - x0 > 0)) else 0
    b12 = 1 if (y2 - y1 < 0 or (y2 == y1 and x2 - x1 > 0)) else 0
    b20 = 1 if (y0 - y2 < 0 or (y0 == y2 and x0 - x2 > 0)) else 0
    inv = 1.0 / area
    for r in range(r0, r1 + 1):
        py = r * SUBPIXEL + half
        lo, hi = _span(x0, y0, x1, y1, b01, py, c0, c1)
        lo, hi = _span(x1, y1, x2, y2, b12, py, lo, hi)
        lo, hi = _span(x2, y2, x0, y0, b20, py, lo, hi)
        for c in range(lo, hi + 1):
            px = c * SUBPIXEL + half
            e01 = (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)
            e12 = (x2 - x1) * (py - y1) - (y2 - y1) * (px - x1)
            e20 = (x0 - x2) * (py - y2) - (y0 - y2) * (px - x2)
            z = (e12 * z0 + e20 * z1 + e01 * z2) * inv
            passed = z < depth[r, c]
            if mode == DEPTH:
                if passed:
                    depth[r, c] = z
                    tri_id[r, c] = ident
            elif mode == ZPASS:
                if passed:
                    stencil[r, c] += 1 if front else -1
            else:
                if not passed:
                    stencil[r, c] += -1 if front else 1


@njit(cache=True)
def rasterize(clip, ids, mode, depth, stencil, tri_id):
    """Rasterise (T, 3, 4) clip-space triangles into the buffers (see module docstring)."""
    H, W = depth.shape
    poly = np.empty((_MAXV, 4))
    tmp = np.empty((_MAXV, 4))
    X = np.empty(_MAXV, dtype=np.int64)
    Y = np.empty(_MAXV, dtype=np.int64)
    Z = np.empty(_MAXV)
    for t in range(clip.shape[0]):
        n = _clip(clip[t], poly, tmp, GUARD)
        if n < 3:
            continue
        for i in range(n):
            w = poly[i, 3]
            X[i] = int(np.rint((0.5 * poly[i, 0] / w + 0.5) * W * SUBPIXEL))
            Y[i] = int(np.rint((0.5 - 0.5 * poly[i, 1] / w) * H * SUBPIXEL))
            Z[i] = poly[i, 2] / w
        area = 0
        for i in range(n):
            j = (i + 1) % n
            area += X[i] * Y[j] - X[j] * Y[i]
        if area == 0:
            continue
        # y points down on screen: counter-clockwise in NDC has negative screen area
        front = area < 0
        for k in range(1, n - 1):
            a2 = (X[k] - X[0]) * (Y[k + 1] - Y[0]) - (Y[k] - Y[0]) * (X[k + 1] - X[0])
            if a2 == 0 or (a2 > 0) != (area > 0):
                continue  # a sliver that snapping collapsed or flipped
            if area > 0:
                _fill(
                    X[0],
                    Y[0],
                    Z[0],
                    X[k],
                    Y[k],
                    Z[k],
                    X[k + 1],
                    Y[k + 1],
                    Z[k + 1],
                    front,
                    mode,
                    ids[t],
                    depth,
                    stencil,
                    tri_id,
                )
            else:
                _fill(
                    X[0],
                    Y[0],
                    Z[0],
                    X[k + 1],
                    Y[k + 1],
                    Z[k + 1],
                    X[k],
                    Y[k],
                    Z[k],
                    front,
                    mode,
                    ids[t],
                    depth,
                    stencil,
                    tri_id,
                )


def new_buffers(width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Depth (cleared to the far plane, 1), stencil (0) and triangle id (-1) buffers."""
    return (
        np.ones((height, width)),
        np.zeros((height, width), dtype=np.int32),
        np.full((height, width), -1, dtype=np.int64),
    )


def to_clip(points_h: np.ndarray, view_projection: np.ndarray) -> np.ndarray:
    """(T, 3, 4) homogeneous world triangles -> clip space, C-contiguous float64."""
    return np.ascontiguousarray(points_h @ view_projection.T, dtype=np.float64)


def homogeneous(triangles: np.ndarray, w: float = 1.0) -> np.ndarray:
    """(T, 3, 3) -> (T, 3, 4) with the given ``w``."""
    out = np.empty(triangles.shape[:-1] + (4,))
    out[..., :3] = triangles
    out[..., 3] = w
    return out
