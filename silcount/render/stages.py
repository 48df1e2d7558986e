"""The stencil frame stage by stage: each stage's operations, fragments, stencil updates and seconds, as a table.

The stages (:data:`.stencil.STAGES`; the OpenGL frame uses the same names) are the frame a shadow-volume
renderer draws (stencil paper Sec. 5, steps (1)-(8); Everitt & Kilgard 2002):

* ``detection``: the detector on each caster; its counts are the detector's own ``true`` tally
  (:attr:`silcount.detectors.result.Silhouette.true_tally`).  Empty for ``pertriangle``, which finds no
  silhouette (Sintorn, Olsson & Assarsson 2011).
* ``volume``: building the volume triangles (the sides, the light and dark caps) in clip space.
* ``depth``: step (1), the scene into the depth buffer.
* ``stencil``: steps (4)-(5), the volume faces into the stencil.
* ``lit``: steps (6)-(7), the lit pass: the stencil test on each visible sample.
* ``final``: step (8)'s result, the mask.

:func:`.stencil.render_stencil` records events (raster counts from :func:`.raster.rasterize`, triangles and
vertices from the volume builders); :data:`COSTS` gives each event's operations in silcount's kinds
(:data:`silcount.counting.arithmetic.KINDS`), read from the code that performs it:

* a vertex transform (:func:`.raster.to_clip`, a 4x4 matrix times a 4-vector): 16 mul, 12 add;
* a vertex extruded to infinity for a point light (:func:`.volumes.to_infinity`, ``p - L``): 3 add (a
  directional light's far point is a copy of ``-d``: nothing);
* a face's facing test: :func:`silcount.detectors.base.visibility_true_cost` (the detectors' own count);
* a volume triangle emitted (gathered into the pass's array): 12 read, 12 write (3 vertices x 4 coordinates);
* a buffer pixel cleared: 1 write (depth and ids for ``depth``, the stencil for ``stencil``, the mask for
  ``final``);
* a fragment (a pixel centre inside a drawn triangle, :func:`.raster._fill_rows`): its depth
  ``(e12 z0 + e20 z1 + e01 z2) / area`` (4 mul, 2 add), the three edge functions stepped (3 add), the
  depth read and the test ``LESS``: 5 add, 4 mul, 1 read, 1 cmp;
* a depth write (``depth``'s passed fragments): 2 write (depth and triangle id);
* a stencil update: 1 read, 1 add, 1 write;
* a coverage test (``lit``, every pixel): 1 read (the id), 1 cmp, 1 write (the flag);
* a stencil test (``lit``, every covered pixel): 1 read, 1 cmp (``!= 0``; ``parity``'s ``& 1`` and
  ``!= 0`` are counted as the one test too), 1 write;
* a mask write (``final``, every covered pixel): 1 read, 1 write.

Triangle set-up (clipping, snapping, edge functions, row spans) is not counted: the counts are the
per-fragment work, which is what grows with the volumes' projected area (Aila & Akenine-Moller 2004), and
the per-vertex and per-face work.  ``fragments`` counts the depth pass's and the stencil pass's fragments and
the lit pass's visible samples; ``stencil_updates`` the stencil writes.  Seconds are ``time.perf_counter``
around each stage; ``frame_seconds`` the whole frame (every row carries it).
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import numpy as np
import pandas as pd

from silcount.atomic import atomic_path, write_text
from silcount.counting.arithmetic import KINDS
from silcount.detectors.base import visibility_true_cost
from silcount.errors import BadArgument
from silcount.mesh.lights import DirectionalLight, Light
from silcount.options import STAGE_FORMATS
from silcount.render.scene import Scene
from silcount.render.stencil import STAGES, Framebuffer, FrameLog, render_stencil

COSTS: dict[str, dict[str, int]] = {
    "vertices_transformed": {"mul": 16, "add": 12},
    "triangles_emitted": {"read": 12, "write": 12},
    "pixels_cleared": {"write": 1},
    "fragments": {"add": 5, "mul": 4, "read": 1, "cmp": 1},
    "depth_writes": {"write": 2},
    "stencil_updates": {"read": 1, "add": 1, "write": 1},
    "coverage_tests": {"read": 1, "cmp": 1, "write": 1},
    "stencil_tests": {"read": 1, "cmp": 1, "write": 1},
    "mask_writes": {"read": 1, "write": 1},
}
"""Operations per event (the module's docstring says where each is read from); the light-dependent ones are
:func:`costs`'."""

COLUMNS = ("stage", "detector", "method", *KINDS, "div", "fragments", "stencil_updates", "seconds", "frame_seconds")


def costs(light: Light) -> dict[str, dict[str, int]]:
    """:data:`COSTS` with the light's: the facing test, the extrusion (nothing for a directional light)."""
    extrude = {} if isinstance(light, DirectionalLight) else {"add": 3}
    return COSTS | {"faces_tested": visibility_true_cost(light), "vertices_extruded": extrude}


def stage_counts(log: FrameLog, light: Light) -> dict[str, Counter]:
    """Each stage's operations (kind -> count) from its events; ``detection`` is the detectors' tally."""
    table = costs(light)
    out = {}
    for stage in STAGES:
        ops: Counter = Counter(log.detection) if stage == "detection" else Counter()
        events = log.events[stage]
        for event, n in events.items():
            for kind, c in table.get(event, {}).items():
                ops[kind] += c * n
        out[stage] = ops
    return out


def stage_table(log: FrameLog, light: Light, method: str, detector: str) -> pd.DataFrame:
    """One row per stage (:data:`COLUMNS`) of a rendered frame's log."""
    counts = stage_counts(log, light)
    rows = []
    for stage in STAGES:
        events = log.events[stage]
        fragments = events["stencil_tests"] if stage == "lit" else events["fragments"]
        row: dict[str, object] = {"stage": stage, "detector": detector, "method": method}
        row |= {kind: int(counts[stage][kind]) for kind in (*KINDS, "div")}
        row |= {"fragments": int(fragments), "stencil_updates": int(events["stencil_updates"])}
        row |= {"seconds": log.seconds[stage], "frame_seconds": log.frame_seconds}
        rows.append(row)
    return pd.DataFrame(rows, columns=list(COLUMNS))


def write_table(table: pd.DataFrame, path: Path) -> Path:
    """Write a stage table by ``path``'s extension (:data:`silcount.options.STAGE_FORMATS`), atomically."""
    suffix = path.suffix.lower()
    if suffix not in STAGE_FORMATS:
        raise BadArgument(f"{path}: a stage table is written as {', '.join(STAGE_FORMATS)}, by its extension")
    if suffix == ".csv":
        return write_text(path, table.to_csv(index=False))
    if suffix == ".json":
        return write_text(path, json.dumps(table.to_dict(orient="records"), indent=2) + "\n")
    with atomic_path(path) as tmp:
        table.to_parquet(tmp, engine="pyarrow", index=False)
    return path


def frame_stages(
    scene: Scene,
    method: str = "zfail",
    detector: str = "reference",
    resolution: tuple[int, int] | None = None,
    variant: str = "intended",
    shadow_test: str = "nonzero",
    volume: str = "infinite",
    framebuffer: Framebuffer | None = None,
    scene_clip: np.ndarray | None = None,
) -> pd.DataFrame:
    """Render ``scene`` (at ``resolution`` = (width, height) if given) by ``method`` (``zpass``, ``zfail``,
    ``pertriangle``) and return its stages, one row each (:data:`COLUMNS`).  Frames timed one after another
    should share a ``framebuffer`` (:class:`.stencil.Framebuffer`), as a GL application's frames share theirs,
    and may share the scene's clip coordinates (``scene_clip``, :func:`.opengl.scene_clip` of the scene at this
    resolution), as :func:`.opengl.gl_frame` uploads them once: the depth stage then transforms no vertex.

    The counts are exact and deterministic (the same for any number of threads); ``volume`` ``truncated``
    is refused (its "new pixel" step has no count here).  For ``pertriangle`` the detector column is empty.
    """
    if volume == "truncated":
        raise BadArgument("stage counts cover infinite and uncapped ('sides') volumes, not truncated ones")
    if resolution is not None:
        scene = scene.with_resolution(*resolution)
    res = render_stencil(
        scene,
        method,
        detector,
        variant,
        shadow_test=shadow_test,
        volume=volume,
        framebuffer=framebuffer,
        scene_clip=scene_clip,
    )
    return stage_table(res.log, scene.light, method, "" if method == "pertriangle" else detector)


__all__ = ["COLUMNS", "COSTS", "costs", "frame_stages", "stage_counts", "stage_table", "write_table"]
