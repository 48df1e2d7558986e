"""The baseline: the single-threaded rasteriser of commit 318ab63, unchanged.

:func:`silcount.render.raster.rasterize` (two cores, clipped and snapped once,
filled in row strips) must equal it bit for bit on depth, stencil and ids
(``tests/test_render_bands.py``), and ``benchmarks/render.py`` times it
against this one in the same run.  It shares the clipper and the span solver.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from silcount.render.raster import _MAXV, DEPTH, GUARD, SUBPIXEL, ZPASS, _clip, _span


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
def rasterize_serial(clip, ids, mode, depth, stencil, tri_id):
    """The single-threaded rasteriser of commit 318ab63, kept as the baseline :func:`rasterize` must equal
    bit for bit (``tests/test_render_bands.py``) and be timed against (``benchmarks/render.py``)."""
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
