"""The frame budget's measurements (issue 41 item 4): every stage's time on both renderers, as committed data.

Stage times depend on the machine and its load, so they are measured by a command
(``python -m benchmarks.frame_budget --write``) and committed as
``silcount/models/measured/frame-budget.csv`` (one row per scene, resolution, renderer, method, detector
and stage) with ``frame-budget.json`` beside it (the machine, its load before and after, the command); the
report (:mod:`silcount.papers.budget`) renders from them, so it is the same on every run, as
``corpus-profile.json`` is for the corpus sweep.

A frame is measured on the software renderer (:func:`.stages.frame_stages`: ``seconds`` per stage,
``frame_seconds``) and on Mesa llvmpipe (:func:`.opengl.gl_frame`: each stage's wall time bounded by
``glFinish``, the frame's wall time).  Of ``repeat`` frames after a warm-up, the one with the median frame
time is kept, its stage times with it; Python's cyclic garbage collector is off while they run
(:func:`no_gc`).  The software rows also carry the frame's deterministic counts
(operations of every kind summed, fragments, stencil updates); the llvmpipe rows carry GL's samples passed.

The occluders (:func:`over_floor`) are the shared scenes, and meshes placed over the floor of
``cube_on_floor.json`` under its camera and light (the scene contract, ``shared/scenes/README.md``): scaled
so their largest extent is :data:`EXTENT`, centred on the floor's origin, resting on it (y = 0).
"""

from __future__ import annotations

import gc
import json
import os
import platform
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from silcount.atomic import write_text
from silcount.counting.arithmetic import KINDS
from silcount.mesh.model import Mesh, from_polygons
from silcount.render.scene import Scene, SceneObject

DATA = "frame-budget.csv"
META = "frame-budget.json"
SIZES = (512, 1024)
EXTENT = 2.0
"""The largest side of a placed mesh's bounding box (the shared cube is 1, the floor 10 wide)."""
COLUMNS = [
    "scene",
    "faces",
    "size",
    "renderer",
    "method",
    "detector",
    "stage",
    "seconds",
    "frame_seconds",
    "operations",
    "fragments",
    "stencil_updates",
    "leads",
]
"""``leads``: in how many of the ``repeat`` frames the stage took the most time (the renderer's dominant stage
is settled when one stage led every frame; :func:`silcount.papers.budget.dominance`)."""
RENDERERS = ("software", "llvmpipe")
PERTRIANGLE = "pertriangle"


def over_floor(mesh: Mesh, name: str, template: Scene) -> Scene:
    """``mesh`` scaled to :data:`EXTENT`, centred in x and z, resting on ``template``'s floor (its objects
    that cast nothing), under ``template``'s camera, light and resolution; the mesh casts shadows."""
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    scale = EXTENT / float(np.max(hi - lo))
    centre = np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])
    world = (mesh.vertices - centre) * scale
    caster = SceneObject(name, from_polygons(world, mesh.faces, name=name), True)
    floors = [o for o in template.objects if not o.casts_shadow]
    return Scene(
        template.path.with_name(f"{name}.json"),
        template.width,
        template.height,
        template.eye,
        template.target,
        template.up,
        template.fov_y_deg,
        template.near,
        template.light,
        [*floors, caster],
    )


def caster_faces(scene: Scene) -> int:
    """F: the faces of the scene's shadow casters."""
    return sum(o.mesh.n_faces for o in scene.casters)


def _median(frames: list[Any], key: Callable[[Any], float]) -> Any:
    frames = sorted(frames, key=key)
    return frames[(len(frames) - 1) // 2]


def leads(stages: Iterable[str], seconds: Iterable[Iterable[float]]) -> dict[str, int]:
    """Per stage, the number of frames (``seconds``: each frame's stage times, in ``stages``' order) in which it
    took the most time."""
    names = list(stages)
    out = dict.fromkeys(names, 0)
    for frame in seconds:
        out[names[int(np.argmax(list(frame)))]] += 1
    return out


@contextmanager
def no_gc() -> Iterator[None]:
    """Collect, then keep Python's cyclic collector off while frames are timed (as :mod:`timeit` does): a
    collection between two stages' timers is time in the frame that no stage holds."""
    gc.collect()
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def software_rows(scene: Scene, method: str, detector: str, repeat: int, clip: np.ndarray) -> list[dict]:
    """The software frame (median of ``repeat`` after a warm-up), one row per stage; the frames share one
    framebuffer and the scene's clip coordinates ``clip`` (:func:`.opengl.scene_clip`), as the llvmpipe frames
    of a scene and size share their :class:`.opengl.GLFrame` and the scene uploaded to it."""
    from silcount.render.stages import frame_stages
    from silcount.render.stencil import Framebuffer

    fb = Framebuffer.of(scene.width, scene.height)
    frame_stages(scene, method, detector, framebuffer=fb, scene_clip=clip)
    with no_gc():
        frames = [frame_stages(scene, method, detector, framebuffer=fb, scene_clip=clip) for _ in range(repeat)]
    table = _median(frames, lambda t: t["frame_seconds"].iloc[0])
    led = leads(table["stage"], (f["seconds"] for f in frames))
    ops = table[[*KINDS, "div"]].sum(axis=1)
    return [
        {
            "stage": r.stage,
            "seconds": float(r.seconds),
            "frame_seconds": float(r.frame_seconds),
            "operations": int(o),
            "fragments": int(r.fragments),
            "stencil_updates": int(r.stencil_updates),
            "leads": led[r.stage],
        }
        for r, o in zip(table.itertuples(), ops, strict=True)
    ]


def llvmpipe_rows(scene: Scene, method: str, detector: str, repeat: int, gl) -> list[dict]:
    """The llvmpipe frame (median of ``repeat`` after a warm-up), one row per stage; fragments are GL's
    samples passed (empty where the stage draws nothing)."""
    from silcount.render.opengl import gl_frame

    gl_frame(scene, method, detector, gl=gl)
    with no_gc():
        frames = [gl_frame(scene, method, detector, gl=gl) for _ in range(repeat)]
    res = _median(frames, lambda r: r.seconds_frame)
    led = leads(res.stages["stage"], (f.stages["seconds_wall"] for f in frames))
    return [
        {
            "stage": r.stage,
            "seconds": float(r.seconds_wall),
            "frame_seconds": float(res.seconds_frame),
            "operations": pd.NA,
            "fragments": pd.NA if pd.isna(r.fragments) else int(r.fragments),
            "stencil_updates": pd.NA,
            "leads": led[r.stage],
        }
        for r in res.stages.itertuples()
    ]


def cases(detectors: Iterable[str]) -> list[tuple[str, str]]:
    """(method, detector): z-fail with each detector, then the per-triangle baseline (no detector)."""
    return [("zfail", d) for d in detectors] + [(PERTRIANGLE, "")]


def measure(
    scenes: Iterable[Scene],
    detectors: Iterable[str],
    repeat: int = 3,
    sizes: Iterable[int] = SIZES,
    progress: Callable[[str], None] | None = None,
) -> pd.DataFrame:
    """Every scene at every size, every case of :func:`cases`, on both renderers: the rows of :data:`COLUMNS`."""
    from silcount.render.opengl import GLFrame, scene_clip

    rows = []
    for base in scenes:
        for size in sizes:
            scene = base.with_resolution(size, size)
            gl = GLFrame(size, size)
            clip = scene_clip(scene)  # computed once, for both renderers' frames
            gl.set_scene(clip)
            head = {"scene": scene.name, "faces": caster_faces(scene), "size": size}
            for method, detector in cases(detectors):
                if progress is not None:
                    progress(f"{scene.name} {size} {method} {detector}".strip())
                for renderer in RENDERERS:
                    got = (
                        software_rows(scene, method, detector or "reference", repeat, clip)
                        if renderer == "software"
                        else llvmpipe_rows(scene, method, detector or "reference", repeat, gl)
                    )
                    case = {"renderer": renderer, "method": method, "detector": detector}
                    rows += [head | case | r for r in got]
    return pd.DataFrame(rows, columns=COLUMNS).astype(
        {"operations": "Int64", "fragments": "Int64", "stencil_updates": "Int64", "leads": int}
    )


def machine(load_before: tuple[float, float, float], repeat: int, command: str) -> dict:
    """The measurement's circumstances, written beside the data."""
    from silcount.render.opengl import GLFrame

    return {
        "cpu": platform.processor() or platform.machine(),
        "cores": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count(),
        "gl_renderer": GLFrame(8, 8).renderer,
        "load_before": [round(x, 2) for x in load_before],
        "load_after": [round(x, 2) for x in os.getloadavg()],
        "repeat": repeat,
        "kept": "the frame with the median wall time of `repeat`, after one warm-up frame, the garbage collector off",
        "command": command,
    }


def write(table: pd.DataFrame, meta: dict, folder: Path) -> list[Path]:
    """Write :data:`DATA` (times to 0.1 microsecond) and :data:`META` under ``folder``."""
    csv = table.to_csv(index=False, float_format="%.7f")
    return [write_text(folder / DATA, csv), write_text(folder / META, json.dumps(meta, indent=2) + "\n")]


def read(folder: Path | None = None) -> tuple[pd.DataFrame, dict]:
    """The committed measurements and their circumstances (``silcount/models/measured/`` by default)."""
    from silcount.counting.models import models_dir

    folder = folder or models_dir() / "measured"
    table = pd.read_csv(
        folder / DATA, keep_default_na=False, na_values={"operations": [""], "fragments": [""], "stencil_updates": [""]}
    )
    table = table.astype(
        {"operations": "Int64", "fragments": "Int64", "stencil_updates": "Int64", "leads": int, "detector": str}
    )
    return table, json.loads((folder / META).read_text(encoding="utf-8"))


__all__ = [
    "COLUMNS",
    "DATA",
    "META",
    "SIZES",
    "caster_faces",
    "cases",
    "leads",
    "measure",
    "over_floor",
    "read",
    "write",
]
