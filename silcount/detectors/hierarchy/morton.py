"""Z-order (Morton) codes and the octahedral map: how the hierarchies' keys turn a cell into one integer.

Used by the hierarchies' keys (:mod:`.gaussmap`, :mod:`.cones`), which start from the sum of an edge's two
planes (:func:`plane_sum`).  Integer
bit manipulation is index arithmetic and is not counted (``docs/counting.md``);
the octahedral map's floating-point work is, in :func:`counted_octahedral`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from silcount.counting.arithmetic import plain
from silcount.detectors.hierarchy.prefetch import ROWS_AHEAD, prefetch

_M = np.uint64


@njit(cache=True)
def _spread2(x):  # pragma: no cover - compiled
    """Bits 0..20 of ``x`` moved to the even positions 0, 2, ..., 40."""
    x = x & _M(0x1FFFFF)
    x = (x | (x << _M(16))) & _M(0x0000FFFF0000FFFF)
    x = (x | (x << _M(8))) & _M(0x00FF00FF00FF00FF)
    x = (x | (x << _M(4))) & _M(0x0F0F0F0F0F0F0F0F)
    x = (x | (x << _M(2))) & _M(0x3333333333333333)
    return (x | (x << _M(1))) & _M(0x5555555555555555)


@njit(cache=True)
def _spread3(x):  # pragma: no cover - compiled
    """Bits 0..20 of ``x`` moved to positions 0, 3, ..., 60."""
    x = x & _M(0x1FFFFF)
    x = (x | (x << _M(32))) & _M(0x1F00000000FFFF)
    x = (x | (x << _M(16))) & _M(0x1F0000FF0000FF)
    x = (x | (x << _M(8))) & _M(0x100F00F00F00F00F)
    x = (x | (x << _M(4))) & _M(0x10C30C30C30C30C3)
    return (x | (x << _M(2))) & _M(0x1249249249249249)


@njit(cache=True)
def interleave2(x, y):  # pragma: no cover - compiled
    """The 42-bit Z-order code of 21-bit cell indices ``x``, ``y`` (uint64 scalars; ``x`` in the even bits)."""
    return _spread2(x) | (_spread2(y) << _M(1))


@njit(cache=True)
def interleave3(x, y, z):  # pragma: no cover - compiled
    """The 63-bit Z-order code of 21-bit cell indices ``x``, ``y``, ``z`` (uint64 scalars)."""
    return _spread3(x) | (_spread3(y) << _M(1)) | (_spread3(z) << _M(2))


@njit(cache=True, inline="always")
def plane_sum(plane, kf, i, end):  # pragma: no cover - compiled
    """The two key faces' planes of edge ``i`` summed in float64 (``u1 + u2``, ``c1 + c2``), asking for the rows
    of the edge :data:`.prefetch.ROWS_AHEAD` ahead (if before ``end``, the thread's run)."""
    if i + ROWS_AHEAD < end:
        prefetch(plane, np.int64(kf[i + ROWS_AHEAD, 0]))
        prefetch(plane, np.int64(kf[i + ROWS_AHEAD, 1]))
    a, b = kf[i, 0], kf[i, 1]
    x = np.float64(plane[a, 0]) + np.float64(plane[b, 0])
    y = np.float64(plane[a, 1]) + np.float64(plane[b, 1])
    z = np.float64(plane[a, 2]) + np.float64(plane[b, 2])
    return x, y, z, np.float64(plane[a, 3]) + np.float64(plane[b, 3])


@njit(cache=True)
def octahedral(x, y, z, quant):  # pragma: no cover - compiled
    """Cell indices of direction ``(x, y, z)`` on the octahedral map, ``(p + 1) * quant`` per axis.

    The direction over its 1-norm, the lower hemisphere folded out to the square's corners; the same
    operations, in the same order, as :func:`counted_octahedral`.  A non-finite point goes to cell 0.
    """
    sx = 1.0 if x >= 0.0 else -1.0
    sy = 1.0 if y >= 0.0 else -1.0
    sz = 1.0 if z >= 0.0 else -1.0
    s = x * sx + y * sy + z * sz
    if s == 0.0:
        s = 1.0
    px, py = x / s, y / s
    fx = (1.0 - py * sy) * sx
    fy = (1.0 - px * sx) * sy
    if z < 0.0:
        px, py = fx, fy
    qx, qy = (px + 1.0) * quant, (py + 1.0) * quant
    cx = _M(qx) if np.isfinite(qx) else _M(0)
    cy = _M(qy) if np.isfinite(qy) else _M(0)
    return cx, cy


def counted_octahedral(u: list, quant: float) -> tuple[np.uint64, np.uint64]:
    """:func:`octahedral` of ``u`` (three counted values) on counting arithmetic: 6 A, 9 M, 5 C, 2 div."""
    sign = [1.0 if x >= 0.0 else -1.0 for x in u]
    a = [u[c] * sign[c] for c in range(3)]
    s = a[0] + a[1] + a[2]
    if s == 0.0:
        s = 1.0
    px, py = u[0] / s, u[1] / s
    fx = (1.0 - py * sign[1]) * sign[0]
    fy = (1.0 - px * sign[0]) * sign[1]
    if u[2] < 0.0:
        px, py = fx, fy
    q = [plain((px + 1.0) * quant), plain((py + 1.0) * quant)]
    cx, cy = (_M(v) if np.isfinite(v) else _M(0) for v in q)
    return cx, cy
