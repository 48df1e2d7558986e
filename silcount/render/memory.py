"""How much memory a render needs, from its resolution, counted from the buffers the renderer allocates.

Every buffer of a render is one value per pixel, so the need is bytes per pixel times ``width x height``
(the scene's triangles, a few MB, are left out: their meshes passed :func:`silcount.mesh.io.load_mesh`'s
own limit).  The counts, per pixel, read from the code: the arrays alive at once (Python keeps a
function's locals to its end) in the phase where most are, temporaries included, with every pixel
covered (``h`` below is the fraction of pixels that hit a surface; the estimate takes ``h = 1``):

* ``zpass``/``zfail``/``pertriangle`` (:func:`.stencil.render_stencil`, then :func:`.methods.render_method`): depth
  float64 8, triangle ids int64 8, stencil int32 4 (the depth pass's own stencil is freed when it
  returns), coverage and mask 1 each, and the eye depth (``1 - z`` and the quotient, 8 each) made while
  the stencil result is alive: 38.
* ``planar`` (:func:`.planar.planar_mask`): the depth pass's depth and ids (16), the floor (1), the
  projected casters' depth, stencil and ids (20), the mask and its test (2): 39, so 40.  (The floor test's
  ``np.maximum`` and object ids, 16, are freed before those 20 are made; the eye depth comes after.)
* ``raycast`` (:func:`.raycast.raycast`): at the shadow rays, the pixel rays (24), ``t`` and ``tri``
  (16), ``hit`` and the mask (2), and per hit pixel its indices (8 and 8), first vertex and normal
  (24 each), the facing test (1), the shadow rays' indices (8), origins and directions (24 each), the
  ignore list and its index (16), the tracer's ``t_min`` and ``t_max`` (16) and answers (16):
  42 + 161 h, so 210.  (The first hits peak lower: rays, their origins copied, three per-ray
  parameters and two answers, 88.)
* writing a mask PNG (:func:`.masks.write_mask`): ``np.where`` gives int64 (8), then uint8 (1) and
  Pillow's copy (1), beside the result (mask, coverage, ids, eye depth: 18): 28.
* ``--image`` (:func:`.shade.shade`): beside the result (18), the pixel rays and the background (24
  each), and per hit pixel its index (8), triangle (72), normal, view, point, light and half vectors
  (24 each), two light terms (8 each), the lit flags (1), the colour (24) and the temporaries of the
  final sum (56 at most): 66 + 321 h, 387, so 400.

``python -m benchmarks.render_memory`` measures the peak resident memory per pixel (the slope between
1024^2 and 2048^2 pixels).  On the shared ``cube_on_floor`` scene, where ``h = 0.72``: zpass 34.8, zfail 37.0,
planar 34.0 (its untouched stencil is never resident: ``np.zeros`` is ``calloc``), raycast 160.4
(counted: 42 + 161 x 0.72 = 158), zfail with ``--image`` 300.0 (counted: 66 + 321 x 0.72 = 297).  With
its floor scaled to cover every pixel (``--full``, ``h = 1``): zpass 34.8, zfail 36.8, planar 34.1,
raycast 206.2, zfail with ``--image`` 390.4, raycast with ``--image`` 384.7.
"""

from __future__ import annotations

BYTES_PER_PIXEL = {"zpass": 38, "zfail": 38, "pertriangle": 38, "planar": 40, "raycast": 210}
WRITE_BYTES_PER_PIXEL = 28
IMAGE_BYTES_PER_PIXEL = 400


def render_bytes(width: int, height: int, method: str, image: bool = False) -> int:
    """Upper estimate of the memory ``silcount render`` needs for ``method`` at ``width x height``."""
    per_pixel = max(BYTES_PER_PIXEL[method], WRITE_BYTES_PER_PIXEL, IMAGE_BYTES_PER_PIXEL if image else 0)
    return per_pixel * int(width) * int(height)
