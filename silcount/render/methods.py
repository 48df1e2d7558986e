"""One entry point for the mask methods: ``zpass``, ``zfail``, ``pertriangle``, ``planar``, ``raycast``.

Returns the mask, the coverage, what the shaded picture needs and the
messages a user must see (open casters; the eye inside a shadow volume with
z-pass, where the count is wrong by the number of volumes holding the eye).
For ``planar`` the variant selects the shadow matrix (:mod:`.planar`); for
the stencil methods it is passed to the detector, and ``shadow_test`` and
``volume`` select the literal forms of the stencil paper's steps
(:func:`.stencil.shadow_from_stencil`, :mod:`.volumes`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from silcount.errors import check_choice
from silcount.options import RENDER_METHODS as METHODS
from silcount.render.camera import Camera
from silcount.render.planar import planar_mask
from silcount.render.raycast import raycast
from silcount.render.scene import Scene
from silcount.render.stencil import FrameLog, depth_pass, render_stencil


@dataclass
class Rendered:
    mask: np.ndarray
    coverage: np.ndarray
    tri_id: np.ndarray
    eye_depth: np.ndarray
    messages: list[str] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)  # seconds: silhouette, volume, raster
    log: FrameLog | None = None  # the stencil methods' stages (:mod:`.stages`)


def render_method(
    scene: Scene,
    method: str,
    detector: str = "reference",
    variant: str = "intended",
    shadow_test: str = "nonzero",
    volume: str = "infinite",
) -> Rendered:
    check_choice("method", method, METHODS)
    camera = Camera.of(scene)
    if method == "raycast":
        rc = raycast(scene)
        return Rendered(rc.mask, rc.coverage, rc.tri_id, rc.depth_t)
    if method == "planar":
        sd = depth_pass(scene, camera)
        mask, _ = planar_mask(scene, variant, depth=sd)
        return Rendered(mask, sd.coverage, sd.tri_id, camera.eye_depth_from_ndc_z(sd.depth))
    res = render_stencil(scene, method, detector, variant, shadow_test=shadow_test, volume=volume)
    messages = list(res.warnings)
    if res.eye_in_shadow:
        if method == "zpass":
            messages.append(
                "the eye is inside a shadow volume: z-pass counts from the eye, and the near plane cuts "
                "the volume, so every count is off and this mask is wrong; use --method zfail"
            )
        else:
            messages.append(
                f"the eye is inside a shadow volume ({'z-fail' if method == 'zfail' else 'per-triangle z-fail'} "
                "counts from infinity and is unaffected)"
            )
    return Rendered(
        res.mask,
        res.coverage,
        res.scene.tri_id,
        camera.eye_depth_from_ndc_z(res.scene.depth),
        messages,
        res.timings,
        res.log,
    )


__all__ = ["METHODS", "Rendered", "render_method"]
