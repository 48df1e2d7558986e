"""A software stencil shadow-volume renderer that checks shadow masks pixel by pixel.

Pipeline (stencil paper, ``stencil-zbuffer-2011-real-time-shadow.txt`` Sec. 5;
Everitt & Kilgard 2002 for the robust z-fail):

``scene.py`` (silcount-scene/1) -> ``camera.py`` (look-at, infinite far
perspective) -> ``raster.py`` (depth + integer stencil, pixel centres,
top-left rule) -> ``volumes.py`` (side quads and caps from a detector's
oriented silhouette) -> ``stencil.py`` (z-pass, z-fail) -> mask.
``stencil.py`` also draws per-triangle volumes (``pertriangle``, no silhouette) and logs the frame's
stages, which ``stages.py`` turns into a table of operations, fragments and seconds; ``budget.py`` measures
every stage on both renderers (this one and ``opengl.py``'s llvmpipe) over the occluders of the frame budget.
``raycast.py`` is the independent ground truth, ``planar.py`` the projected
planar shadows of the stencil paper Sec. 4 (onto the floor of
``receiver.py``), ``shade.py`` the Phong picture, ``masks.py`` PNG I/O and
mask comparison.  The single-threaded rasteriser of commit 318ab63 that
``raster.py`` must equal bit for bit is the benchmarks' and tests' oracle,
``tests/oracles/render_baseline.py``, outside the package.  ``builtin.py``
builds the scenes where the paper's literal steps matter (overlapping
shadows, a receiver below the clipping plane) and ``experiments.py``
measures those steps against ray casting for the claims.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# public name -> the module that defines it, loaded on first use (PEP 562): importing one module of the
# package (``silcount compare`` needs masks.py alone) never loads the rasteriser's numba kernels
_LAZY: dict[str, str] = {
    "Scene": "silcount.render.scene",
    "SceneObject": "silcount.render.scene",
    "load_scene": "silcount.render.scene",
    "Camera": "silcount.render.camera",
    "StencilResult": "silcount.render.stencil",
    "render_stencil": "silcount.render.stencil",
    "frame_stages": "silcount.render.stages",
    "compare_masks": "silcount.render.masks",
    "read_mask": "silcount.render.masks",
    "write_mask": "silcount.render.masks",
}

if TYPE_CHECKING:
    from silcount.render.camera import Camera
    from silcount.render.masks import compare_masks, read_mask, write_mask
    from silcount.render.scene import Scene, SceneObject, load_scene
    from silcount.render.stages import frame_stages
    from silcount.render.stencil import StencilResult, render_stencil


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'silcount.render' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value


__all__ = [
    "Scene",
    "SceneObject",
    "load_scene",
    "Camera",
    "StencilResult",
    "render_stencil",
    "frame_stages",
    "compare_masks",
    "read_mask",
    "write_mask",
]
