"""The shadow-volume frame on Mesa llvmpipe, stage by stage: each stage's share of the frame (issue 41).

For every shared scene at 512x512 and 1024x1024, z-fail (the ``reference`` detector) and per-triangle
volumes (no detector), :func:`silcount.render.opengl.gl_frame` runs one warm-up frame and then ``--runs``
frames; the frame with the median wall time is printed: each stage's wall time (bounded by ``glFinish``) and
its share of the frame, the GL timer query's time, the samples passed, and the sum of the stage times
against the frame's wall time (the issue's target: within 5 %).  The baseline measured in the same run is
z-fail's frame: per-triangle's frame is printed as a ratio of it.  The load averages are printed beside the
figures (two cores shared with other work: expect noise).

    .venv/bin/python -m benchmarks.frame_gl [--runs 5] [--sizes 512 1024]
"""

from __future__ import annotations

import argparse
import sys

from benchmarks.common import load_line
from silcount.cli.render import shared_scene_dir
from silcount.render.opengl import STAGES, GLFrame, gl_frame, scene_clip
from silcount.render.scene import load_scene

SCENES = ("cube_on_floor", "icosahedron_on_floor", "torus_self_shadow", "cow_and_cubes", "eye_in_shadow")
METHODS = ("zfail", "pertriangle")


def median_frame(scene, method: str, gl: GLFrame, runs: int):
    """One warm-up frame, then ``runs`` frames; the one with the median wall time."""
    gl_frame(scene, method, gl=gl)
    frames = sorted((gl_frame(scene, method, gl=gl) for _ in range(runs)), key=lambda r: r.seconds_frame)
    return frames[len(frames) // 2]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=5, help="timed frames per scene, size and method (median shown)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    args = ap.parse_args()
    scenes_dir = shared_scene_dir()
    if scenes_dir is None:
        print("no shared scenes: set SILCOUNT_SCENE_DIR", file=sys.stderr)
        return 2
    print(f"# The frame on llvmpipe, stage by stage: the median of {args.runs} frames, ms ({load_line()})")
    print("# share = stage wall / frame wall; GL = the stage's GL_TIME_ELAPSED query; fragments = samples passed")
    head = " ".join(f"{s:>15}" for s in STAGES)
    print(f"{'scene':<21} {'size':>4} {'method':<11} {head} {'frame':>8} {'sum/frame':>9} {'vs zfail':>8}")
    for name in SCENES:
        base = load_scene(scenes_dir / f"{name}.json")
        for size in args.sizes:
            sc = base.with_resolution(size, size)
            gl = GLFrame(size, size)
            gl.set_scene(scene_clip(sc))
            baseline = None
            for method in METHODS:
                res = median_frame(sc, method, gl, args.runs)
                st = res.stages.set_index("stage")
                frame = res.seconds_frame
                baseline = baseline or frame
                cells = " ".join(f"{1e3 * st.seconds_wall[s]:7.2f} ({st.seconds_wall[s] / frame:5.1%})" for s in STAGES)
                print(
                    f"{name:<21} {size:>4} {method:<11} {cells} {1e3 * frame:8.2f} "
                    f"{st.seconds_wall.sum() / frame:9.4f} {frame / baseline:7.2f}x"
                )
                gpu = " ".join(f"{1e3 * st.seconds_gpu[s]:15.3f}" for s in STAGES)
                frags = " ".join(f"{'-' if st.fragments.isna()[s] else int(st.fragments[s]):>15}" for s in STAGES)
                print(f"{'':<21} {'':>4} {'  GL ms':<11} {gpu}")
                print(f"{'':<21} {'':>4} {'  fragments':<11} {frags}")
    print(f"({GLFrame(8, 8).renderer}; {load_line()})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
