"""The receiver plane: the floor that planar shadows project onto and truncated volumes stop at.

Stencil paper Sec. 4 projects onto "the ground" (``N``: its normal, ``C``:
a point on it); Sec. 5 clips each shadow quadrilateral "between occluder and
shadow receiver".  A scene names no receiver, so we take the first
non-casting object whose vertices are coplanar, and write its plane
``N . X = D`` with ``N`` the unit mean face normal (pointing up, out of the
floor) and ``D = N . C``.
"""

from __future__ import annotations

import numpy as np

from silcount.errors import BadArgument
from silcount.render.scene import Scene


def floor_plane(scene: Scene) -> tuple[int, np.ndarray, float]:
    """(object index, unit normal N, offset D) of the floor: ``N . X = D``."""
    for k, o in enumerate(scene.objects):
        if o.casts_shadow:
            continue
        v = o.mesh.vertices
        n = o.mesh.face_normals.sum(axis=0)
        if np.linalg.norm(n) == 0:
            continue
        n = n / np.linalg.norm(n)
        d = float(n @ v[0])
        if np.allclose(v @ n, d, atol=1e-9 * max(1.0, float(np.abs(v).max()))):
            return k, n, d
    raise BadArgument(
        f"{scene.path}: planar shadows and truncated volumes need a flat non-casting receiver (a floor); none found"
    )
