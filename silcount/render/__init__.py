"""A software stencil shadow-volume renderer that checks shadow masks pixel by pixel.

Pipeline (stencil paper, ``stencil-zbuffer-2011-real-time-shadow.txt`` Sec. 5;
Everitt & Kilgard 2002 for the robust z-fail):

``scene.py`` (silcount-scene/1) -> ``camera.py`` (look-at, infinite far
perspective) -> ``raster.py`` (depth + integer stencil, pixel centres,
top-left rule) -> ``volumes.py`` (side quads and caps from a detector's
oriented silhouette) -> ``stencil.py`` (z-pass, z-fail) -> mask.
``raycast.py`` is the independent ground truth, ``planar.py`` the projected
planar shadows of the stencil paper Sec. 4, ``shade.py`` the Phong picture,
``masks.py`` PNG I/O and mask comparison.
"""

from __future__ import annotations

from silcount.render.camera import Camera
from silcount.render.masks import compare_masks, read_mask, write_mask
from silcount.render.scene import Scene, SceneObject, load_scene
from silcount.render.stencil import StencilResult, render_stencil

__all__ = [
    "Scene",
    "SceneObject",
    "load_scene",
    "Camera",
    "StencilResult",
    "render_stencil",
    "compare_masks",
    "read_mask",
    "write_mask",
]
