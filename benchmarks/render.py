"""Frame times of the software stencil renderer (issue 5, "Performance"; issue 15, "Rendering").

1. z-pass and z-fail frames at 512x512 and 1024x1024 on the shared
   cow_and_cubes scene and on the shared bunny (``$SILCOUNT_MESH_DIR/bunny.ply``,
   scaled x10, standing on the shared floor), split into silhouette (the
   ``reference`` detector), volume build and rasterisation (the depth pass
   of the scene plus the stencil pass of the volumes), for three rasterisers
   measured in the same run: the baseline (the single-threaded rasteriser of
   commit 318ab63, ``tests/oracles/render_baseline.py``), the current one on one
   part, and on ``numba.get_num_threads()`` parts (the default).
1b. The rasterisation alone (depth pass, stencil pass) on cow_and_cubes, wall
   and CPU time, the three rasterisers interleaved run by run.
1c. ``--whole-process`` (``benchmarks.render_process``): ``silcount render
   cow_and_cubes.json --method zfail`` as a whole process, this tree against
   commit 318ab63 (``git archive`` into a temporary folder, its own numba
   cache), interleaved, after one warm-up each (numba caches filled), plus
   where the time goes: Python with numpy and numba imported, ``silcount.cli.main`` imported, the first frame
   (numba caches loaded, threads started) and a second frame.  Python's
   bytecode is cached (``PYTHONDONTWRITEBYTECODE`` dropped, the cache in a
   temporary folder), as it is after an install.  With ``--llvmpipe``
   too, a whole llvmpipe process runs interleaved with them (see 1d).
2. The papers' frame-rate analogue: a closed torus of 32 x 23 quads split
   into 1,472 triangles, 2,208 edges (the papers' bunny has ~2,200 edges; the
   shared bunny is 24,363 edges and open, so a closed mesh of the papers'
   size stands in), on the floor at 512x512, z-fail.  Detection is timed
   with :func:`silcount.detectors.plain_edge_ids`: each algorithm's own loops (TA's
   linear searches of S, VnV's and EESD's E x F loops), compiled and
   uncounted -- neither the counting ``naive`` engine nor the ``fast``
   engine's shortcut; "rest" is the volume build and rasterisation.
   Printed beside the papers' FPS (HSD paper Sec. VII; EESD paper Sec. 6),
   which were measured on a GPU pipeline at an unstated resolution: compare
   the ranking, not the numbers.

Timings are the best of ``--repeat`` runs after one warm-up (numba
compilation), wall clock, column by column (as ``timeit`` advises: on a
shared machine the minimum is the least disturbed estimate); expect noise.

    .venv/bin/python -m benchmarks.render [--repeat 5] [--quick]
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import json
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numba
import numpy as np

import silcount
from benchmarks.common import best_time
from benchmarks.render_process import BASELINE_COMMIT, whole_process
from silcount.cli.render import shared_scene_dir
from silcount.detectors import DETECTORS, plain_edge_ids
from silcount.mesh import shapes
from silcount.render import stencil
from silcount.render.camera import Camera
from silcount.render.masks import compare_masks
from silcount.render.raster import COUNTS, DEPTH, ZFAIL, homogeneous, new_buffers, rasterize, to_clip
from silcount.render.scene import load_scene
from silcount.render.stencil import render_stencil
from tests.oracles.render_baseline import rasterize_serial

PAPER_FPS = {  # HSD 2011 Sec. VII: HSD 75.53 vs at most 67.54 conventional; EESD 2012 Sec. 6: TA, VnV, EESD
    "hsd": ("HSD paper", 75.53),
    "conventional (best)": ("HSD paper", 67.54),
    "ta": ("EESD paper", 69.93),
    "vnv": ("EESD paper", 65.51),
    "eesd": ("EESD paper", 73.16),
}


def baseline(*args) -> np.ndarray:
    """The baseline rasteriser, in :func:`rasterize`'s signature: it counts nothing (:data:`COUNTS` all 0)."""
    rasterize_serial(*args)
    return np.zeros(len(COUNTS), dtype=np.int64)


def rasterisers() -> dict[str, Callable[..., object]]:
    """The three rasterisers compared, by label."""
    return {
        "baseline": baseline,
        "1 part": functools.partial(rasterize, parts=1),
        f"{numba.get_num_threads()} parts": rasterize,
    }


@contextlib.contextmanager
def using(raster):
    """Render stencil frames with ``raster`` (the stencil module's rasteriser, restored afterwards)."""
    saved = stencil.rasterize
    stencil.rasterize = raster
    try:
        yield
    finally:
        stencil.rasterize = saved


def best_frame(scene, method: str, detector: str, repeat: int) -> dict[str, float]:
    render_stencil(scene, method, detector)  # warm-up: numba compilation, cached meshes
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = render_stencil(scene, method, detector)
        total = time.perf_counter() - t0
        runs.append(dict(r.timings, total=total))
    return {k: 1000 * min(run[k] for run in runs) for k in runs[0]}


def best_detection(mesh, light, detector: str, repeat: int) -> float:
    """Best time (ms) of the detector's own loops, uncounted (:func:`plain_edge_ids`), after a warm-up."""
    plain_edge_ids(mesh, light, detector)
    return 1000 * best_time(lambda: plain_edge_ids(mesh, light, detector), repeat)


def scene_file(tmp: Path, name: str, objects: list[dict], eye, target, light) -> Path:
    shared = shared_scene_dir()
    assert shared is not None, "main() checks for the shared scenes first"
    floor = shared / "meshes" / "floor.obj"
    doc = {
        "spec": "silcount-scene/1",
        "resolution": [512, 512],
        "camera": {"eye": eye, "target": target, "up": [0, 1, 0], "fov_y_deg": 45.0, "near": 0.1},
        "light": {"position": light},
        "objects": [{"name": "floor", "mesh": str(floor), "casts_shadow": False}] + objects,
    }
    path = tmp / f"{name}.json"
    path.write_text(json.dumps(doc))
    return path


def bunny_scene(tmp: Path) -> Path | None:
    mesh_dir = os.environ.get("SILCOUNT_MESH_DIR")
    if not mesh_dir or not (Path(mesh_dir) / "bunny.ply").exists():
        return None
    bunny = Path(mesh_dir) / "bunny.ply"
    lo = silcount.load_mesh(bunny).vertices.min(axis=0)
    return scene_file(
        tmp,
        "bunny_on_floor",
        [{"name": "bunny", "mesh": str(bunny), "scale": 10.0, "translate": [0.0, float(-10 * lo[1]), 0.0]}],
        eye=[2.5, 2.2, 3.0],
        target=[-0.2, 0.8, 0.0],
        light=[2.0, 5.0, 1.0],
    )


def torus_scene(tmp: Path) -> Path:
    m = shapes.torus(n_major=32, n_minor=23)
    obj = tmp / "torus_2208.obj"
    obj.write_text(
        "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in m.vertices.tolist())
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in m.faces.tolist())
    )
    return scene_file(
        tmp,
        "torus_2208",
        [{"name": "torus", "mesh": str(obj), "rotate_deg": [60, 0, 20], "translate": [0, 1.6, 0]}],
        eye=[6, 5, 8],
        target=[0, 0.5, 0],
        light=[0, 5, 5],
    )


def raster_passes(scene, runs: int) -> None:
    """Depth pass and z-fail stencil pass of cow_and_cubes alone, the rasterisers interleaved run by run."""
    camera = Camera.of(scene)
    clip = to_clip(homogeneous(scene.triangles), camera.view_projection)
    ids = np.arange(len(clip), dtype=np.int64)
    vclip = render_stencil(scene, "zfail").volume_clip
    vids = np.zeros(len(vclip), dtype=np.int64)
    rs = rasterisers()
    times: dict[str, dict[str, list[float]]] = {k: {"dw": [], "dc": [], "sw": [], "sc": []} for k in rs}
    outputs = {}
    for _ in range(runs + 1):  # the first run is the warm-up
        for label, raster in rs.items():
            depth, st, tri = new_buffers(scene.width, scene.height)
            c0, w0 = time.process_time(), time.perf_counter()
            raster(clip, ids, DEPTH, depth, st, tri)
            c1, w1 = time.process_time(), time.perf_counter()
            raster(vclip, vids, ZFAIL, depth, st, tri)
            c2, w2 = time.process_time(), time.perf_counter()
            for key, v in (("dw", w1 - w0), ("dc", c1 - c0), ("sw", w2 - w1), ("sc", c2 - c1)):
                times[label][key].append(v)
            outputs[label] = (depth, st, tri)
    same = all(all(np.array_equal(a, b) for a, b in zip(outputs["baseline"], o)) for o in outputs.values())
    print(
        f"\n# cow_and_cubes rasterisation alone, {len(clip)} scene and {len(vclip)} volume triangles, "
        f"best of {runs} interleaved runs, ms (CPU time sums the threads); buffers identical: {same}"
    )
    print(
        f"{'rasteriser':<10} {'depth wall':>10} {'depth cpu':>9} {'stencil wall':>12} {'stencil cpu':>11} "
        f"{'vs baseline':>11}"
    )
    base = None
    for label, t in times.items():
        b = {k: 1000 * min(v[1:]) for k, v in t.items()}
        base = base or b
        print(
            f"{label:<10} {b['dw']:10.2f} {b['dc']:9.2f} {b['sw']:12.2f} {b['sc']:11.2f} "
            f"{(base['dw'] + base['sw']) / (b['dw'] + b['sw']):10.2f}x"
        )


def resized(scenes: list[tuple[str, Path]], sizes: tuple[int, ...]):
    """(name, size, scene at size x size) for every scene and size, each scene file loaded once."""
    for name, path in scenes:
        base = load_scene(path)
        for size in sizes:
            yield name, size, base.with_resolution(size, size)


def llvmpipe_frames(scenes: list[tuple[str, Path]], sizes: tuple[int, ...], runs: int) -> None:
    """Section 1d: silcount's frames and llvmpipe's, interleaved run by run; masks compared."""
    from silcount.render.opengl import GLFrame

    print(f"\n# The same frames on llvmpipe (OpenGL), best of {runs} interleaved runs, ms")
    print(
        f"{'scene':<16} {'size':>9} {'method':<6} {'sil+volume':>10} {'raster':>7} {'GL draw':>8} "
        f"{'silcount':>8} {'llvmpipe':>8} {'silcount/llvmpipe':>17}  masks"
    )
    for name, size, sc in resized(scenes, sizes):
        gl = GLFrame(size, size)
        for method in ("zpass", "zfail"):
            res = render_stencil(sc, method)  # warm-up
            gl.set_scene(res.scene.clip)
            gl.frame(res.volume_clip, method)
            mask = gl.coverage() & (gl.stencil() != 0)
            cmp = compare_masks(res.mask, mask, res.coverage)
            cpu, raster, draw, frames = [], [], [], []
            for _ in range(runs):
                t0 = time.perf_counter()
                r = render_stencil(sc, method)
                t1 = time.perf_counter()
                gl.frame(r.volume_clip, method)
                draw.append(time.perf_counter() - t1)
                frames.append(t1 - t0)  # the whole call: mask, eye-in-shadow test and warnings included
                cpu.append(r.timings["silhouette"] + r.timings["volume"])
                raster.append(r.timings["raster"])
            gl_frames = [c + d for c, d in zip(cpu, draw)]
            own, theirs = 1000 * min(frames), 1000 * min(gl_frames)
            print(
                f"{name:<16} {size:>4}x{size:<4} {method:<6} {1000 * min(cpu):10.2f} {1000 * min(raster):7.2f} "
                f"{1000 * min(draw):8.2f} {own:8.2f} {theirs:8.2f} {own / theirs:16.2f}x  "
                f"{cmp.mismatched} px differ, {cmp.far} far from an edge"
            )
        print(f"  ({gl.renderer})")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="512x512 only, 2 repeats")
    ap.add_argument(
        "--whole-process",
        action="store_true",
        help=f"also time whole `silcount render` processes against {BASELINE_COMMIT}",
    )
    ap.add_argument("--llvmpipe", action="store_true", help="also time the same frames on Mesa llvmpipe (gl extra)")
    args = ap.parse_args()
    repeat = 2 if args.quick else args.repeat
    sizes = (512,) if args.quick else (512, 1024)
    scenes_dir = shared_scene_dir()
    if scenes_dir is None:
        print("no shared scenes: set SILCOUNT_SCENE_DIR", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        scenes = [("cow_and_cubes", scenes_dir / "cow_and_cubes.json")]
        bunny = bunny_scene(tmp)
        if bunny is None:
            print("(bunny_on_floor skipped: SILCOUNT_MESH_DIR unset)")
        else:
            scenes.append(("bunny_on_floor", bunny))
        print(f"# Stencil frames (reference detector), best of {repeat} runs, ms; baseline = commit {BASELINE_COMMIT}")
        print(
            f"{'scene':<16} {'size':>9} {'method':<6} {'rasteriser':<10} {'silhouette':>10} {'volume':>7} "
            f"{'raster':>7} {'total':>7} {'vs baseline':>11}"
        )
        for name, size, sc in resized(scenes, sizes):
            for method in ("zpass", "zfail"):
                first = None
                for label, raster in rasterisers().items():
                    with using(raster):
                        t = best_frame(sc, method, "reference", repeat)
                    first = first or t["total"]
                    print(
                        f"{name:<16} {size:>4}x{size:<4} {method:<6} {label:<10} {t['silhouette']:10.2f} "
                        f"{t['volume']:7.2f} {t['raster']:7.2f} {t['total']:7.2f} "
                        f"{first / t['total']:10.2f}x"
                    )
        raster_passes(load_scene(scenes_dir / "cow_and_cubes.json"), max(10, 4 * repeat))
        if args.llvmpipe:
            llvmpipe_frames(scenes, sizes, max(10, 4 * repeat))
        if args.whole_process:
            whole_process(scenes_dir / "cow_and_cubes.json", max(3, repeat), args.llvmpipe)
        torus = load_scene(torus_scene(tmp))
        caster = torus.casters[0].mesh
        print(
            f"\n# The papers' FPS analogue: torus of {caster.n_edges} edges on a floor, 512x512, z-fail, "
            f"best of {repeat} runs"
        )
        print(f"{'detector':<12} {'detect ms':>9} {'rest ms':>8} {'frame ms':>9} {'FPS':>7}   paper FPS")
        for det in DETECTORS:
            t = best_frame(torus, "zfail", det, repeat)
            rest = t["volume"] + t["raster"]
            detect = best_detection(caster, torus.light, det, repeat)
            frame = detect + rest
            src, fps = PAPER_FPS.get(det, ("", None))
            paper = f"{fps:.2f} ({src})" if fps else "-"
            print(f"{det:<12} {detect:9.2f} {rest:8.2f} {frame:9.2f} {1000 / frame:7.1f}   {paper}")
        print(
            f"{'(conventional)':<12} {'':>9} {'':>8} {'':>9} {'':>7}   "
            f"{PAPER_FPS['conventional (best)'][1]:.2f} (HSD paper, best)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
