"""Projected planar shadows (stencil paper Sec. 4, the "shadow matrix").

The printed matrix (plane ``N . X = D``, light ``L``, an undefined ``E``)::

    | LxNx+E  LxNy    LxNz    -E Lx - D Lx |
    | LyNx    LyNy+E  LyNz    -E Ly - D Ly |
    | LzNx    LzNy    LzNz+E  -E Lz - D Lz |
    | Nx      Ny      Nz      -D           |

maps ``P`` to ``L + E (P - L) / (N.P - D)``.  Its own derivation
(``S = L + alpha (P - L)``, ``(S - C) . N = 0``) gives
``alpha = (D - N.L) / (N.P - N.L)``: the denominator must be ``N.(P - L)``,
not ``N.P - D``.  ``literal`` is the printed matrix with ``E = D - N.L`` (the
numerator the derivation needs); it sends floor points to infinity and
misses the plane.  ``intended`` is the same layout with ``N.L`` where the
printed ``D`` stands in the last row and column, which is Blinn's shadow
matrix ``(pi . l) I - l pi^T`` (``pi = (N, -D)``, ``l = (L, 1)``);
with ``w = N.L - N.P > 0`` for points below the light.  A
directional light uses ``l = (d, 0)``.

The receiver is the scene's floor: the first non-casting object whose
vertices are coplanar.  The mask is the floor pixels covered by the
projected caster triangles (depth is ignored on the plane, as the paper's
stencil-restricted drawing does); casters receive nothing from this method.
"""

from __future__ import annotations

import numpy as np

from silcount.errors import BadArgument, check_choice
from silcount.mesh.lights import DirectionalLight, Light
from silcount.render.camera import Camera
from silcount.render.raster import DEPTH, homogeneous, new_buffers, rasterize, to_clip
from silcount.render.receiver import floor_plane
from silcount.render.scene import Scene
from silcount.render.stencil import SceneDepth, depth_pass

VARIANTS = ("intended", "literal")
__all__ = ["VARIANTS", "floor_plane", "planar_mask", "shadow_matrix"]


def shadow_matrix(normal: np.ndarray, offset: float, light: Light, variant: str = "intended") -> np.ndarray:
    """4x4 projection onto the plane ``normal . X = offset`` from ``light`` (see module docstring)."""
    check_choice("planar variant", variant, VARIANTS)
    N, D = np.asarray(normal, dtype=np.float64), float(offset)
    if isinstance(light, DirectionalLight):
        l = np.append(np.asarray(light.direction), 0.0)
    else:
        l = np.append(np.asarray(light.position), 1.0)
    NL = float(N @ l[:3])
    if variant == "literal":
        if isinstance(light, DirectionalLight):
            raise BadArgument("the printed shadow matrix is for a point light only")
        L = l[:3]
        E = D - NL
        M = np.zeros((4, 4))
        M[:3, :3] = np.outer(L, N) + E * np.eye(3)
        M[:3, 3] = -E * L - D * L
        M[3] = [*N, -D]
        return M
    pi = np.append(N, -D)
    return (pi @ l) * np.eye(4) - np.outer(l, pi)  # w = N.L - N.P (point light), N.d (directional)


def planar_mask(
    scene: Scene, variant: str = "intended", depth: SceneDepth | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """(mask, floor pixels): the floor pixels covered by the casters' projected triangles."""
    camera = Camera.of(scene)
    sd = depth if depth is not None else depth_pass(scene, camera)
    k, N, D = floor_plane(scene)
    floor = sd.coverage & (scene.triangle_object[np.maximum(sd.tri_id, 0)] == k)
    casters = [o.triangles for o in scene.casters]
    if not casters:
        return np.zeros_like(floor), floor
    M = shadow_matrix(N, D, scene.light, variant)
    projected = homogeneous(np.concatenate(casters)) @ M.T
    clip = to_clip(projected, camera.view_projection)
    z, stencil, tri_id = new_buffers(camera.width, camera.height)
    z[:] = np.inf
    rasterize(clip, np.zeros(len(clip), dtype=np.int64), DEPTH, z, stencil, tri_id)
    return floor & (tri_id >= 0), floor
