"""Ground-truth shadow masks by ray casting (scene README, "The mask").

For each pixel centre: the first hit from the eye (``t`` is eye depth, so
hits start at the near plane, as the rasteriser clips), then

* a caster triangle that does not face the light (``(L - p0) . n <= 0``,
  the detectors' rule) is in shadow: a caster's back-facing side;
* otherwise a shadow ray from the hit point towards the light, against the
  casters only, ignoring the hit triangle itself and with a relative
  ``t_min`` of ``1e-9`` of the segment (the segment runs to ``t = 1`` at the
  light; to infinity for a directional light), decides.

It shares no code with the stencil path but the scene reader and the
camera's pixel-centre convention: the tracer is :class:`silcount.mesh.raytrace.RayTracer`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silcount.mesh.lights import DirectionalLight, facing_values
from silcount.mesh.raytrace import RayTracer
from silcount.render.camera import Camera
from silcount.render.scene import Scene

SHADOW_T_MIN = 1e-9


@dataclass
class RaycastResult:
    mask: np.ndarray  # (H, W) bool
    coverage: np.ndarray  # (H, W) bool
    tri_id: np.ndarray  # (H, W) first-hit triangle in scene order, -1 none
    depth_t: np.ndarray  # (H, W) eye depth of the first hit, inf none


def raycast(scene: Scene) -> RaycastResult:
    camera = Camera.of(scene)
    H, W = camera.height, camera.width
    dirs = camera.pixel_rays().reshape(-1, 3)
    tris = scene.triangles
    t, tri = RayTracer(tris).first_hit(np.broadcast_to(scene.eye, dirs.shape), dirs, t_min=scene.near)
    hit = tri >= 0
    caster_obj = np.array([o.casts_shadow for o in scene.objects])
    is_caster = caster_obj[scene.triangle_object]
    mask = np.zeros(H * W, dtype=bool)
    idx = np.flatnonzero(hit)
    ht = tri[idx]
    p0 = tris[ht, 0]
    normals = np.cross(tris[ht, 1] - p0, tris[ht, 2] - p0)
    back = is_caster[ht] & (facing_values(p0, normals, scene.light) <= 0.0)
    mask[idx[back]] = True
    rest = idx[~back]
    caster_ids = np.flatnonzero(is_caster)
    if caster_ids.size and rest.size:
        local = np.full(len(tris), -1, dtype=np.int64)
        local[caster_ids] = np.arange(caster_ids.size)
        points = scene.eye + t[rest, None] * dirs[rest]
        if isinstance(scene.light, DirectionalLight):
            to_light, t_max = np.broadcast_to(np.asarray(scene.light.direction), points.shape), np.inf
        else:
            to_light, t_max = np.asarray(scene.light.position) - points, 1.0
        blocked = RayTracer(tris[caster_ids]).any_hit(
            points, to_light, t_min=SHADOW_T_MIN, t_max=t_max, ignore=local[tri[rest]]
        )
        mask[rest[blocked]] = True
    return RaycastResult(mask.reshape(H, W), hit.reshape(H, W), tri.reshape(H, W), t.reshape(H, W))
