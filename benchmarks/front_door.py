"""The command line's front door as whole processes (issue 43): ``--help`` and one ``silcount render``.

1. ``silcount --help`` and ``silcount CMD --help`` for every subcommand that
   ``silcount --help`` lists (read from its usage line, so the script times
   any version of the tool).  Target: each at most 0.3 s.
2. ``silcount render cow_and_cubes.json --method zfail`` against the same
   frame on Mesa's llvmpipe through OpenGL as a whole process
   (``tests/oracles/gl_stencil.py``: a GL application's baked scene, one frame,
   the mask as a PNG), interleaved run by run, with the two masks compared
   pixel by pixel.  Target: silcount within 2x of llvmpipe.  Beside them, the
   floor of any numba program writing that mask (:data:`FLOOR`: numpy, numba,
   one cached kernel, a PNG), so that the ratio can be read against it.  Needs the ``gl``
   extra (moderngl, PyOpenGL); without it only part 1 runs.

Each command runs once as a warm-up (numba's cache and Python's bytecode
filled), then ``--runs`` times; the median and the best are printed with the
machine's load (:func:`benchmarks.common.load_line`) before and after, and the median CPU
time (user + system, every thread: on a shared machine it varies less than
the wall clock, which the targets are about).  Bytecode is cached
(``PYTHONDONTWRITEBYTECODE`` dropped), as after an install.  The tool is the
``silcount`` console script beside ``sys.executable`` (``-m
silcount.cli.main`` without one), so ``PYTHONPATH`` picks the tree timed
(another checkout's first: ``PYTHONPATH=/that/checkout:.``).  From the checkout's root:

    .venv/bin/python -m benchmarks.front_door [--runs 5] [--scene SCENE.json]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import ROOT, load_line
from silcount.render.masks import compare_masks, read_mask
from silcount.render.scene import load_scene
from tests.oracles.gl_stencil import bake

HELP_TARGET = 0.3  # seconds, each --help
RENDER_TARGET = 2.0  # silcount render / llvmpipe, whole processes


def silcount_command() -> list[str]:
    script = Path(sys.executable).parent / "silcount"
    return [str(script)] if script.exists() else [sys.executable, "-m", "silcount.cli.main"]


def _children_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def timed(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall clock and CPU time (user + system, every thread) of one whole process."""
    c0, t0 = _children_cpu(), time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0, _children_cpu() - c0


def series(
    cmds: dict[str, list[str]], runs: int, env: dict[str, str], envs: dict[str, dict[str, str]] | None = None
) -> dict[str, list[tuple[float, float]]]:
    """Each command once as a warm-up, then ``runs`` rounds, the commands interleaved within each round.

    ``envs`` gives some commands their own environment."""
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in cmds}
    for i in range(runs + 1):
        for label, cmd in cmds.items():
            t = timed(cmd, (envs or {}).get(label, env))
            if i:
                times[label].append(t)
    return times


def medians(ts: list[tuple[float, float]]) -> tuple[float, float, float]:
    """Median wall clock, best wall clock, median CPU time."""
    walls = [w for w, _ in ts]
    return statistics.median(walls), min(walls), statistics.median(c for _, c in ts)


def subcommands(tool: list[str], env: dict[str, str]) -> list[str]:
    """The subcommands ``silcount --help`` lists, from its usage line's ``{a,b,...}``."""
    out = subprocess.run(tool + ["--help"], env=env, check=True, capture_output=True, text=True).stdout
    found = re.search(r"\{([\w,-]+)\}", out)
    if found is None:
        raise SystemExit(f"bench_front_door: no {{subcommand,...}} list in `silcount --help`:\n{out}")
    return found.group(1).split(",")


def help_times(tool: list[str], runs: int, env: dict[str, str]) -> None:
    cmds = {"silcount --help": tool + ["--help"]}
    cmds.update({f"silcount {c} --help": tool + [c, "--help"] for c in subcommands(tool, env)})
    times = series(cmds, runs, env)
    print(f"\n# --help as whole processes, {runs} interleaved runs after one warm-up, s (target <= {HELP_TARGET})")
    print(f"{'command':<28} {'median':>7} {'best':>6} {'CPU':>6}")
    for label, ts in times.items():
        med, best, cpu = medians(ts)
        print(f"{label:<28} {med:7.3f} {best:6.3f} {cpu:6.3f}{'' if med <= HELP_TARGET else '   over target'}")


# the least a numba program that writes a mask pays: numpy, numba (which imports scipy.linalg for BLAS when its
# typing registries load), one cached kernel loaded and run, PIL writing a 512 x 512 PNG; with the collector
# settings of silcount's console script (silcount.cli.main.run), without which it costs 0.2 s more
FLOOR = """import gc

gc.set_threshold(10_000, *gc.get_threshold()[1:])

import numba
import numpy as np
from PIL import Image


@numba.njit(cache=True)
def total(a):
    return a.sum()


total(np.ones(3))
Image.fromarray(np.zeros((512, 512), dtype=np.uint8)).save(__file__ + ".png")
gc.freeze()
"""


def render_times(tool: list[str], scene: Path, runs: int, env: dict[str, str]) -> None:
    with tempfile.TemporaryDirectory() as td:
        baked, ours, theirs, floor = f"{td}/scene.npz", f"{td}/silcount.png", f"{td}/gl.png", Path(td) / "floor.py"
        bake(load_scene(scene), baked)
        floor.write_text(FLOOR)
        gl = ROOT / "tests" / "oracles" / "gl_stencil.py"
        cmds = {
            "silcount render": tool + ["render", str(scene), "--method", "zfail", "--out", ours],
            "llvmpipe (OpenGL)": [sys.executable, str(gl), baked, theirs, "zfail"],
            "numba floor": [sys.executable, str(floor)],
        }
        times = series(cmds, runs, env, {"numba floor": dict(env, NUMBA_CACHE_DIR=f"{td}/numba")})
        cmp = compare_masks(read_mask(ours), read_mask(theirs))
    print(
        f"\n# `silcount render {scene.name} --method zfail` against llvmpipe, whole processes, {runs} interleaved runs"
    )
    print(f"{'process':<20} {'median':>7} {'best':>6} {'CPU':>6}")
    for label, ts in times.items():
        print(f"{label:<20} " + " ".join(f"{x:{w}.3f}" for x, w in zip(medians(ts), (7, 6, 6))))
    ours_t, gl_t = medians(times["silcount render"]), medians(times["llvmpipe (OpenGL)"])
    print(
        f"ratio silcount / llvmpipe: median {ours_t[0] / gl_t[0]:.2f}, best {ours_t[1] / gl_t[1]:.2f} "
        f"(target <= {RENDER_TARGET}); CPU time {ours_t[2] / gl_t[2]:.2f}"
    )
    low = medians(times["numba floor"])
    print(
        f"numba floor / llvmpipe: median {low[0] / gl_t[0]:.2f}, CPU time {low[2] / gl_t[2]:.2f} "
        "(what any numba program writing the mask pays before silcount's own work)"
    )
    print(f"masks, silcount against llvmpipe: {cmp.describe()}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=5, help="timed runs of each command (default 5)")
    ap.add_argument(
        "--scene", type=Path, default=None, help="default: $SILCOUNT_SCENE_DIR/cow_and_cubes.json (the shared scene)"
    )
    ap.add_argument("--no-render", action="store_true", help="time the --help commands only")
    args = ap.parse_args()
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    tool = silcount_command()
    print(f"# {' '.join(tool)} (PYTHONPATH={env.get('PYTHONPATH', '')}); {load_line()}")
    help_times(tool, args.runs, env)
    if args.no_render:
        pass
    elif importlib.util.find_spec("moderngl") is None or importlib.util.find_spec("OpenGL") is None:
        print("\n# render part skipped: the gl extra (moderngl, PyOpenGL) is not installed")
    else:
        scene = args.scene or Path(os.environ.get("SILCOUNT_SCENE_DIR", "")) / "cow_and_cubes.json"
        render_times(tool, scene, args.runs, env)
    print(f"\n# {load_line()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
