"""Section 1c of ``benchmarks.render``: ``silcount render`` as whole processes, this tree against a baseline commit.

``silcount render SCENE --method zfail`` is timed as a whole process, this
tree against :data:`BASELINE_COMMIT` (``git archive`` into a temporary
folder, its own numba cache), interleaved, after one warm-up each, plus where
the time goes (see ``benchmarks/render.py``'s docstring, 1c); with ``--llvmpipe`` a
whole llvmpipe process (``tests/oracles/gl_stencil.py``) runs interleaved with them.

    .venv/bin/python -m benchmarks.render_process SCENE.json [--runs 3] [--llvmpipe]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from silcount.render.masks import compare_masks, read_mask
from silcount.render.scene import load_scene

REPO = Path(__file__).resolve().parents[1]
BASELINE_COMMIT = "318ab63"


def _timed(cmd: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


STAGES = """
import time; t0 = time.perf_counter()
import numpy, numba; t1 = time.perf_counter()
import silcount.cli.main; t2 = time.perf_counter()
from silcount.render.methods import render_method
from silcount.render.scene import load_scene
scene = load_scene({scene!r}); t3 = time.perf_counter()
render_method(scene, "zfail"); t4 = time.perf_counter()
render_method(scene, "zfail"); t5 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4)
"""


def whole_process(scene: Path, runs: int, llvmpipe: bool) -> None:
    """``silcount render`` as whole processes, this tree against :data:`BASELINE_COMMIT` (and llvmpipe), interleaved."""
    with tempfile.TemporaryDirectory() as td:
        old = Path(td) / "tree"
        old.mkdir()
        archive = subprocess.run(["git", "-C", str(REPO), "archive", BASELINE_COMMIT], capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive.stdout, check=True)
        trees = {"this tree": (REPO, os.environ.get("NUMBA_CACHE_DIR", "")), BASELINE_COMMIT: (old, f"{td}/numba")}
        out = Path(td) / "mask.png"
        times: dict[str, list[float]] = {k: [] for k in [*trees, "llvmpipe"]}
        stages: dict[str, list[list[float]]] = {k: [] for k in times}
        if llvmpipe:
            from tests.oracles.gl_stencil import bake

            baked = Path(td) / "scene.npz"
            bake(load_scene(scene), str(baked))
            gl_cmd = [
                sys.executable,
                str(REPO / "tests" / "oracles" / "gl_stencil.py"),
                str(baked),
                f"{td}/gl.png",
                "zfail",
            ]
        base_env = dict(os.environ, PYTHONPYCACHEPREFIX=f"{td}/pycache")  # bytecode cached, as after an install
        base_env.pop("PYTHONDONTWRITEBYTECODE", None)
        for i in range(runs + 1):  # run 0 fills each tree's numba cache and the bytecode cache
            for label, (tree, cache) in trees.items():
                env = dict(base_env, PYTHONPATH=str(tree))
                env.pop("NUMBA_CACHE_DIR") if not cache else env.update(NUMBA_CACHE_DIR=cache)
                # -P: the working directory (this checkout, when run from it) must not shadow the tree's silcount
                cmd = [sys.executable, "-P", "-m", "silcount.cli.main", "render", str(scene), "--method", "zfail"]
                t = _timed(cmd + ["--out", str(out)], env)
                run = subprocess.run(
                    [sys.executable, "-P", "-c", STAGES.format(scene=str(scene))],
                    env=env,
                    capture_output=True,
                    check=True,
                )
                if i:
                    times[label].append(t)
                    stages[label].append([float(x) for x in run.stdout.split()])
            if llvmpipe:
                t0 = time.perf_counter()
                run = subprocess.run(gl_cmd, env=base_env, capture_output=True, check=True)
                if i:
                    times["llvmpipe"].append(time.perf_counter() - t0)
                    stages["llvmpipe"].append([float(x) for x in run.stdout.split()])
        print(f"\n# Whole process `silcount render cow_and_cubes.json --method zfail`, {runs} interleaved runs, s")
        print(
            f"{'tree':<10} {'best':>6} {'median':>7}   stages (best): numpy+numba, silcount.cli.main, scene, "
            "first frame, second frame"
        )
        for label in trees:
            st = [min(col) for col in zip(*stages[label])]
            print(
                f"{label:<10} {min(times[label]):6.2f} {statistics.median(times[label]):7.2f}   "
                + ", ".join(f"{x:.3f}" for x in st)
            )
        print(
            f"ratio this tree / {BASELINE_COMMIT} (best): {min(times['this tree']) / min(times[BASELINE_COMMIT]):.2f}"
        )
        if llvmpipe:
            st = [min(col) for col in zip(*stages["llvmpipe"])]
            cmp = compare_masks(read_mask(out), read_mask(f"{td}/gl.png"))
            print(
                f"{'llvmpipe':<10} {min(times['llvmpipe']):6.2f} {statistics.median(times['llvmpipe']):7.2f}   "
                f"stages (best): numpy+PIL+baked scene {st[0]:.3f}, GL context+scene upload {st[1]:.3f}, "
                f"silhouette+volume (numpy)+frame+read-back {st[2]:.3f}, PNG {st[3]:.3f}"
            )
            print(
                f"ratio this tree / llvmpipe (best): {min(times['this tree']) / min(times['llvmpipe']):.2f} "
                f"(target: within 3x); masks: {cmp.describe()}"
            )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", type=Path, help="a scene file (benchmarks.render uses the shared cow_and_cubes.json)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--llvmpipe", action="store_true", help="also time a whole llvmpipe process (gl extra)")
    args = ap.parse_args()
    whole_process(args.scene, args.runs, args.llvmpipe)
    return 0


if __name__ == "__main__":
    sys.exit(main())
