"""Measure the frame budget (issue 41 item 4): every stage's time, software and llvmpipe, on every occluder.

The occluders: the shared scenes, and :data:`CORPUS` meshes from ``$SILCOUNT_CORPUS_DIR`` at 1, 4 and 16
times their faces (0, 1, 2 levels of :func:`silcount.study.subdivide.subdivide_once`) over the floor of
``cube_on_floor.json`` (:func:`silcount.render.budget.over_floor`); 512^2 and 1024^2; z-fail with each
built-in detector (fast engine, intended variant) and the per-triangle baseline
(:func:`silcount.render.budget.measure`).  Prints the load, each frame's stage sum against its wall time
(the issue's target: within 5 %) and the worst; ``--write`` commits the rows to
``silcount/models/measured/frame-budget.csv`` (and the circumstances to ``frame-budget.json``), which
``silcount report`` renders as "The frame budget".

    python -m benchmarks.frame_budget [--write] [--repeat 5] [--scenes a,b] [--corpus a,b]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from benchmarks.common import load_line

SCENES = ("cube_on_floor", "icosahedron_on_floor", "torus_self_shadow", "cow_and_cubes", "eye_in_shadow")
CORPUS = ("cylinder.stl", "decimated-knight.off", "camel_b.obj")
LEVELS = (0, 1, 2)
TARGET = 0.05


def occluders(scene_dir: Path, corpus_dir: Path, scenes: list[str], corpus: list[str]):
    """The shared scenes, then each corpus mesh at each level over the floor."""
    from silcount.mesh.io import load_mesh
    from silcount.render.budget import over_floor
    from silcount.render.scene import load_scene
    from silcount.study.subdivide import subdivide_once

    out = [load_scene(scene_dir / f"{name}.json") for name in scenes]
    template = load_scene(scene_dir / "cube_on_floor.json")
    for file in corpus:
        mesh = load_mesh(corpus_dir / file)
        stem = Path(file).stem
        for level in range(max(LEVELS) + 1):
            if level in LEVELS:
                out.append(over_floor(mesh, f"{stem}-x{4**level}", template))
            mesh = subdivide_once(mesh)
    return out


def main() -> int:
    from silcount.detectors import names
    from silcount.render import budget

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="commit the rows under silcount/models/measured/")
    ap.add_argument("--repeat", type=int, default=5, help="frames per case after a warm-up; the median kept")
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--corpus", default=",".join(CORPUS))
    ap.add_argument("--detectors", default=",".join(names()))
    args = ap.parse_args()
    scene_dir = Path(os.environ.get("SILCOUNT_SCENE_DIR", "../shared/scenes"))
    corpus_dir = Path(os.environ.get("SILCOUNT_CORPUS_DIR", "../shared/corpus"))
    load = os.getloadavg()
    print(load_line(), flush=True)
    t0 = time.perf_counter()
    scenes = occluders(scene_dir, corpus_dir, args.scenes.split(","), [c for c in args.corpus.split(",") if c])
    table = budget.measure(
        scenes, args.detectors.split(","), args.repeat, progress=lambda s: print(f"  {s}", file=sys.stderr, flush=True)
    )
    frames = table.groupby(["scene", "size", "renderer", "method", "detector"], sort=False).agg(
        total=("seconds", "sum"), frame=("frame_seconds", "first")
    )
    ratio = frames["total"] / frames["frame"]
    worst = float((ratio - 1).abs().max())
    print(ratio.groupby(level="renderer").agg(["min", "max"]).to_string())
    print(
        f"worst |stage sum / frame - 1|: {100 * worst:.2f} % (target {100 * TARGET:.0f} %: "
        f"{'met' if worst <= TARGET else 'NOT met'}); {time.perf_counter() - t0:.0f} s; {load_line()}"
    )
    if args.write:
        from silcount.counting.models import models_dir

        command = "python -m benchmarks.frame_budget --write" + (f" --repeat {args.repeat}" if args.repeat != 5 else "")
        for path in budget.write(table, budget.machine(load, args.repeat, command), models_dir() / "measured"):
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
