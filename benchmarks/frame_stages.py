"""Time the shadow-volume frame stage by stage (issue 41): each stage's share, and the stages' sum against the frame.

Each shared scene at 512^2 and 1024^2 (``--sizes``), by each method (``zpass`` and ``zfail`` with each
``--detectors`` detector, ``pertriangle``), through :func:`silcount.render.stages.frame_stages`: after one
warm-up frame (numba's kernels compiled or loaded), the frame with the least wall time of ``--repeat`` is
kept.  Printed per frame: each stage's share of the frame's wall time, the stages' sum over the frame's wall
time (target: within 5 %), the frame's milliseconds and the whole call's (the frame plus its diagnostics:
eye in a volume, open casters), and each stage's share of the operations.  The load is printed first.

    python -m benchmarks.frame_stages [--sizes 512,1024] [--repeat 3] [--detectors reference] [--scenes a,b]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

from benchmarks.common import ROOT, load_line

SCENES = ("cube_on_floor", "icosahedron_on_floor", "torus_self_shadow", "cow_and_cubes", "eye_in_shadow")
TARGET = 0.05  # the stages' sum within 5 % of the frame's wall time


def best_frame(scene, method: str, detector: str, repeat: int):
    """The stage table of the fastest of ``repeat`` frames (after a warm-up), and that call's wall time."""
    from silcount.render.stages import frame_stages
    from silcount.render.stencil import Framebuffer

    fb = Framebuffer.of(scene.width, scene.height)  # kept between frames, as a GL framebuffer is
    frame_stages(scene, method, detector, framebuffer=fb)
    best, wall = None, float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        table = frame_stages(scene, method, detector, framebuffer=fb)
        t = time.perf_counter() - t0
        if best is None or table["frame_seconds"].iloc[0] < best["frame_seconds"].iloc[0]:
            best, wall = table, t
    return best, wall


def main() -> None:
    from silcount.counting.arithmetic import KINDS
    from silcount.render.scene import load_scene
    from silcount.render.stencil import STAGES

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="512,1024", help="square resolutions")
    parser.add_argument("--repeat", type=int, default=3, help="frames per case; the fastest is kept")
    parser.add_argument("--detectors", default="reference", help="detectors for zpass and zfail, comma-separated")
    parser.add_argument("--scenes", default=",".join(SCENES), help="shared scenes, comma-separated")
    args = parser.parse_args()
    folder = Path(os.environ.get("SILCOUNT_SCENE_DIR", ROOT.parent / "shared" / "scenes"))
    sizes = [int(v) for v in args.sizes.split(",")]
    methods = [(m, d) for m in ("zpass", "zfail") for d in args.detectors.split(",")] + [("pertriangle", "")]
    print(f"{load_line()}; best of {args.repeat} frames after a warm-up; shares of the frame's wall time")
    head = " ".join(f"{s:>9}" for s in STAGES)
    print(f"{'scene':<21} {'size':>5} {'method':<21} {head} {'sum/frame':>9} {'frame ms':>9} {'call ms':>8}")
    worst = 0.0
    op_lines = []
    for name in args.scenes.split(","):
        base = load_scene(folder / f"{name}.json")
        for n in sizes:
            scene = base.with_resolution(n, n)
            for method, detector in methods:
                table, wall = best_frame(scene, method, detector or "reference", args.repeat)
                frame = float(table["frame_seconds"].iloc[0])
                shares = table["seconds"] / frame
                ratio = float(table["seconds"].sum()) / frame
                worst = max(worst, abs(ratio - 1))
                label = f"{method} {detector}".strip()
                cells = " ".join(f"{100 * s:>8.1f}%" for s in shares)
                print(f"{name:<21} {n:>5} {label:<21} {cells} {ratio:>9.4f} {1e3 * frame:>9.1f} {1e3 * wall:>8.1f}")
                ops = table[list(KINDS) + ["div"]].sum(axis=1)
                op_cells = " ".join(f"{100 * o / ops.sum():>8.1f}%" for o in ops)
                op_lines.append(f"{name:<21} {n:>5} {label:<21} {op_cells} {int(ops.sum()):>14,}")
    verdict = "met" if worst <= TARGET else "NOT met"
    print(f"\nworst |sum/frame - 1|: {100 * worst:.2f} % (target {100 * TARGET:.0f} %: {verdict})")
    print("\nshares of the operations (all kinds summed)")
    print(f"{'scene':<21} {'size':>5} {'method':<21} {head} {'operations':>14}")
    print("\n".join(op_lines))
    print(load_line())


if __name__ == "__main__":
    main()
