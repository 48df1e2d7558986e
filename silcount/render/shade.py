"""A shaded picture so a person can see the scene (stencil paper Sec. 5, Phong terms).

``I = Ia Ka + Kd Il (N . L) + Il Ks (N . H)^n`` per pixel, with flat face
normals turned towards the eye, ``L`` and ``H`` unit vectors at the
surface point, dot products clamped at 0; pixels in shadow get the ambient
term only (the paper's step (1): "render all scene just with ambient").
Each object has its own colour; the background is dark grey.
"""

from __future__ import annotations

import numpy as np

from silcount.mesh.lights import DirectionalLight
from silcount.render.camera import Camera
from silcount.render.scene import Scene

KA, KD, KS, SHININESS, IA, IL = 0.25, 0.75, 0.35, 32.0, 1.0, 1.0
PALETTE = np.array(
    [
        [0.80, 0.80, 0.78],
        [0.85, 0.45, 0.30],
        [0.35, 0.55, 0.85],
        [0.45, 0.75, 0.40],
        [0.85, 0.75, 0.35],
        [0.65, 0.45, 0.80],
    ]
)
BACKGROUND = np.array([0.12, 0.12, 0.14])


def shade(scene: Scene, tri_id: np.ndarray, eye_depth: np.ndarray, shadow: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 Phong image from a per-pixel triangle id, eye depth and shadow mask."""
    camera = Camera.of(scene)
    H, W = tri_id.shape
    dirs = camera.pixel_rays().reshape(-1, 3)
    ids = tri_id.reshape(-1)
    hit = np.flatnonzero(ids >= 0)
    out = np.tile(BACKGROUND, (H * W, 1))
    tris = scene.triangles[ids[hit]]
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    view = -dirs[hit] / np.linalg.norm(dirs[hit], axis=1, keepdims=True)
    n *= np.where(np.einsum("ij,ij->i", n, view) < 0, -1.0, 1.0)[:, None]
    p = scene.eye + eye_depth.reshape(-1)[hit, None] * dirs[hit]
    if isinstance(scene.light, DirectionalLight):
        to_light = np.broadcast_to(np.asarray(scene.light.direction, dtype=np.float64), p.shape)
    else:
        to_light = np.asarray(scene.light.position) - p
    lv = to_light / np.linalg.norm(to_light, axis=1, keepdims=True)
    h = lv + view
    h /= np.maximum(np.linalg.norm(h, axis=1, keepdims=True), 1e-300)
    diffuse = KD * IL * np.clip(np.einsum("ij,ij->i", n, lv), 0, None)
    specular = IL * KS * np.clip(np.einsum("ij,ij->i", n, h), 0, None) ** SHININESS
    lit = ~shadow.reshape(-1)[hit]
    colour = PALETTE[scene.triangle_object[ids[hit]] % len(PALETTE)]
    out[hit] = colour * (IA * KA + lit[:, None] * diffuse[:, None]) + lit[:, None] * specular[:, None]
    return (np.clip(out, 0, 1) * 255 + 0.5).astype(np.uint8).reshape(H, W, 3)
