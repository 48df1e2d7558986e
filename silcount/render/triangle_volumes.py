"""Per-triangle shadow volumes: every light-facing triangle extruded on its own, no silhouette (issue 41).

The silhouette-free baseline of the literature (Sintorn, Olsson & Assarsson 2011, "An efficient alias-free
shadow algorithm for opaque and transparent objects using per-triangle shadow volumes"): each caster triangle
that faces the light, ``(L - p0) . n > 0`` (``d . n > 0`` for a directional light towards ``d``), the rule of
the detectors, becomes a closed volume of its own:

* the light cap, the triangle itself as it is wound (its front face looks at the light, out of the volume);
* the dark cap, the triangle's corners sent to infinity away from the light, ``(p - L, 0)`` (``(-d, 0)``),
  wound the other way round: seen from the light the projection keeps the triangle's turn, so the reversed
  winding makes its front face look away from the light, out of the volume;
* three sides, one quad per edge ``(a, b)`` of the triangle's own traversal, wound ``(b, a, a_inf, b_inf)``,
  the reverse of the cap's traversal, so that each side's front face looks out (the orientation
  :mod:`.volumes` gives a silhouette edge, here written again from the triangles and the light alone).

A pixel's z-fail count is then the number of these volumes holding its surface point, which is not zero
exactly where a caster triangle lies between the point and the light.  For a directional light every far
corner is the one point ``(-d, 0)``: the dark cap and the second triangle of each side have no area and
draw nothing.  The light caps are returned as indices: a renderer draws them from the very clip
coordinates of its depth pass, so that their depth equals the stored depth bit for bit (z-fail counts them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silcount.mesh.lights import DirectionalLight, Light


@dataclass
class TriangleVolumes:
    """The per-triangle volumes of a set of triangles, in homogeneous world coordinates."""

    lit: np.ndarray  # (T,) bool: the triangles that face the light; their light caps are the triangles themselves
    sides: np.ndarray  # (6 L, 3, 4) two triangles per edge of each lit triangle (L lit triangles)
    dark_caps: np.ndarray  # (L, 3, 4) each lit triangle at infinity, winding reversed


def faces_light(triangles: np.ndarray, light: Light) -> np.ndarray:
    """(T,) bool: ``(L - p0) . ((p1 - p0) x (p2 - p0)) > 0``, or ``d . n > 0`` for a directional light."""
    p0, p1, p2 = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    n = np.cross(p1 - p0, p2 - p0)
    if isinstance(light, DirectionalLight):
        return n @ np.asarray(light.direction, dtype=np.float64) > 0
    return np.einsum("ij,ij->i", np.asarray(light.position, dtype=np.float64) - p0, n) > 0


def triangle_volumes(triangles: np.ndarray, light: Light) -> TriangleVolumes:
    """Every light-facing triangle of the (T, 3, 3) world ``triangles`` extruded on its own (module docstring)."""
    lit = faces_light(triangles, light)
    near = triangles[lit]
    far = np.zeros(near.shape[:2] + (4,))
    if isinstance(light, DirectionalLight):
        far[..., :3] = -np.asarray(light.direction, dtype=np.float64)
    else:
        far[..., :3] = near - np.asarray(light.position, dtype=np.float64)
    near_h = np.concatenate([near, np.ones(near.shape[:2] + (1,))], axis=2)
    sides = []
    for i in range(3):  # the edge (a, b) = corners (i, i + 1) in the triangle's own order
        j = (i + 1) % 3
        a, b, a_inf, b_inf = near_h[:, i], near_h[:, j], far[:, i], far[:, j]
        sides += [np.stack([b, a, a_inf], axis=1), np.stack([b, a_inf, b_inf], axis=1)]
    return TriangleVolumes(lit, np.concatenate(sides, axis=0), far[:, ::-1])
