"""Z-order (Morton) codes: the bit interleaving that turns a quadtree or octree cell into one integer.

Used by the hierarchies' keys (:mod:`.gaussmap`, :mod:`.cones`).  Integer
bit manipulation is index arithmetic and is not counted (``docs/counting.md``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

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
