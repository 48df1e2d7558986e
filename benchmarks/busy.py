"""Every parallel kernel on a busy machine: quiet, with one core held by a spinning process, and on one thread.

    SILCOUNT_MESH_DIR=/path/to/shared/data python -m benchmarks.busy [--rounds 3] [--repeat 5] \
        [--baseline-tree DIR] [--configs this,before,passive,workqueue]

Issue 42, item 4: with one core busy, a parallel kernel must take at most 1.2x its one-thread time.  Each
kernel (the ``prange`` kernels, reached the way silcount calls them) is timed four ways, interleaved round by
round (``--rounds``), each the best of ``--repeat`` calls (going round two lights, or two orders of 64 lights,
so that no call reads back a result the mesh keeps from the call before):

* ``quiet``: numba's default thread count, no spinner;
* ``one``: ``numba.set_num_threads(1)``, no spinner;
* ``busy``: default threads while a spinning process (``multiprocessing``, started and stopped here) holds
  a core;
* ``busy one``: one thread with the spinner: what the kernel can do on what the spinner leaves, so that
  ``busy / busy one`` isolates the cost of the threads from the load that other work adds on a shared machine.

The ratio the target names is ``busy / one``; on a machine that other work already loads, ``busy one`` is
slower than ``one`` too, and ``busy / busy one`` is the fair reading.  The load average is printed with
every block.

The kernels: the reference query through ``silcount.detect`` and alone
(:func:`silcount.detectors.adjacency.silhouette_edge_ids`), ``detect_many`` of 64 lights, the hierarchies'
compiled queries (gaussmap, directional; cones, point) alone and through ``detect``, on the 1.04 M-face
bunny (:func:`benchmarks.common.build_mesh`, 3 rounds); gaussmap's tree build (its key, sort and box
kernels) on the 261 k-face bunny (2 rounds); the renderer's fill (:func:`silcount.render.raster.rasterize`)
of the 261 k-face bunny's triangles at 512x512; EESD (its ray caster and own-face kernels) and EESD
``literal`` (the point-on-plane walk) on the shared 16 k-face bunny.

``--configs`` runs each configuration in a fresh process (the layer and the wait policy are read when
numba loads its layer): ``this`` (this tree: passive wait, thread count fitted to the free cores,
:mod:`silcount.threads`); and, on ``--baseline-tree`` (the package before that change alone, e.g. ``git
archive 5b16ce7 silcount | tar -x -C DIR``: a tree with its own ``benchmarks`` would hide this one),
``before`` (numba's defaults: ``omp``, spinning wait), ``passive`` (``OMP_WAIT_POLICY=passive`` alone) and
``workqueue`` (``NUMBA_THREADING_LAYER=workqueue``).
"""

from __future__ import annotations

import argparse
import itertools
import json
import multiprocessing as mp
import os
import subprocess
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import silcount
from benchmarks.common import best_time, build_mesh, child_command, lights, load_line, tree_env

MODES = ("quiet", "one", "busy", "busy one")
TARGET = 1.2


def _spin(stop) -> None:  # the busy core
    while not stop.is_set():
        pass


def load_meshes(folder: Path) -> dict[str, silcount.Mesh]:
    """The 1.04 M- and 261 k-face bunnies (built once, kept in ``folder`` for the child processes) and the
    shared 16 k-face bunny."""
    out = {}
    for rounds in (3, 2):
        path = folder / f"bunny_sub{rounds}.npz"
        if not path.exists():
            m = build_mesh(rounds)
            np.savez(path, v=m.vertices, f=m.faces)
        got = np.load(path)
        out[f"sub{rounds}"] = silcount.from_polygons(got["v"], got["f"], name=f"bunny_sub{rounds}")
    out["sub0"] = silcount.load_mesh(Path(os.environ["SILCOUNT_MESH_DIR"]) / "bunny.ply")
    return out


def kernels(meshes: dict[str, silcount.Mesh]) -> dict[str, Callable[[], object]]:
    """Each kernel as a call of no arguments, warmed up (compiled or loaded, per-mesh caches filled)."""
    from silcount.detectors import adjacency, detect_many
    from silcount.detectors.hierarchy import cones, gaussmap
    from silcount.detectors.hierarchy import query as hq
    from silcount.detectors.hierarchy.build import build_fast
    from silcount.render.raster import DEPTH, homogeneous, new_buffers, rasterize

    big, mid, small = meshes["sub3"], meshes["sub2"], meshes["sub0"]
    ls = lights(big, 4)
    d, p = ls[1], ls[0]
    # the reference keeps the last light's facing flags and detect_many the last lights' results with the mesh:
    # calls that go round two lights (two orders of the 64) never only read them back
    dirs = itertools.cycle([ls[1], ls[3]]).__next__
    points = itertools.cycle([ls[0], ls[2]]).__next__
    many = lights(big, 64, seed=3)
    batches = itertools.cycle([many, many[::-1]]).__next__
    g_tree, c_tree = hq.tree_for(big, gaussmap.SCHEME), hq.tree_for(big, cones.SCHEME)
    tri = mid.vertices[mid.faces]
    lo, hi = tri.reshape(-1, 3).min(0), tri.reshape(-1, 3).max(0)
    clip = homogeneous(((tri - lo) / (hi - lo)) * 1.8 - 0.9)
    clip[..., 2] = clip[..., 2] * 0.5  # depth inside the near and far planes
    ids = np.arange(clip.shape[0])
    small_lights = itertools.cycle(lights(small, 2)).__next__

    def fill():
        depth, stencil, tri_id = new_buffers(512, 512)
        rasterize(clip, ids, DEPTH, depth, stencil, tri_id)

    out = {
        "reference detect (1.04 M)": lambda: silcount.detect(big, dirs(), "reference").edge_ids,
        "reference kernel (1.04 M)": lambda: adjacency.silhouette_edge_ids(big, dirs()),
        "detect_many 64 lights (1.04 M)": lambda: detect_many(big, batches()),
        "gaussmap query, directional": lambda: hq.query_fast(big, g_tree, d),
        "cones query, point": lambda: hq.query_fast(big, c_tree, p),
        "gaussmap detect, directional": lambda: silcount.detect(big, dirs(), "gaussmap").edge_ids,
        "cones detect, point": lambda: silcount.detect(big, points(), "cones").edge_ids,
        "gaussmap build (261 k)": lambda: build_fast(mid, gaussmap.SCHEME, 8, 4),
        "render fill 512x512 (261 k)": fill,
        "eesd detect (16 k)": lambda: silcount.detect(small, small_lights(), "eesd").edge_ids,
        "eesd literal detect (16 k)": lambda: silcount.detect(small, small_lights(), "eesd", "literal").edge_ids,
    }
    for fn in out.values():
        fn()
    return out


def measure(ks: dict[str, Callable[[], object]], rounds: int, repeat: int) -> dict:
    """Best time of each kernel in each mode over ``rounds`` interleaved rounds; the load seen by each mode."""
    import numba

    full = numba.get_num_threads()
    best = {k: dict.fromkeys(MODES, float("inf")) for k in ks}
    loads: dict[str, list[float]] = {m: [] for m in MODES}

    def block(mode: str, threads: int) -> None:
        numba.set_num_threads(threads)
        try:
            for name, fn in ks.items():
                best[name][mode] = min(best[name][mode], best_time(fn, repeat))
        finally:
            numba.set_num_threads(full)
        loads[mode].append(os.getloadavg()[0])

    ctx = mp.get_context("spawn")
    for _ in range(rounds):
        block("quiet", full)
        block("one", 1)
        stop = ctx.Event()
        spinner = ctx.Process(target=_spin, args=(stop,), daemon=True)
        spinner.start()
        time.sleep(0.5)  # until it spins
        try:
            block("busy", full)
            block("busy one", 1)
        finally:
            stop.set()
            spinner.join()
    return {"best": best, "loads": loads, "threads": full, "layer": numba.threading_layer()}


def child(args: argparse.Namespace) -> None:
    meshes = load_meshes(Path(args.folder))
    print(json.dumps(measure(kernels(meshes), args.rounds, args.repeat)))


CONFIGS: dict[str, tuple[bool, dict[str, str]]] = {  # name -> (on the baseline tree, environment)
    "this": (False, {}),
    "before": (True, {}),
    "passive": (True, {"OMP_WAIT_POLICY": "passive"}),
    "workqueue": (True, {"NUMBA_THREADING_LAYER": "workqueue"}),
}


def run_config(name: str, args: argparse.Namespace) -> dict:
    on_baseline, extra = CONFIGS[name]
    if on_baseline and not args.baseline_tree:
        raise SystemExit(f"configuration {name!r} needs --baseline-tree")
    env = tree_env(args.baseline_tree if on_baseline else None)
    for var in ("OMP_WAIT_POLICY", "NUMBA_THREADING_LAYER", "NUMBA_NUM_THREADS"):  # the configuration's own only
        env.pop(var, None)
    env.update(extra)
    if on_baseline:
        env["NUMBA_CACHE_DIR"] = env.get("NUMBA_CACHE_DIR", "/tmp/numba") + "-baseline"
    cmd = child_command(__spec__.name, "--child", "--folder", args.folder, "--rounds", str(args.rounds),
                        "--repeat", str(args.repeat))  # fmt: skip
    out = subprocess.run(cmd, env=env, check=True, stdout=subprocess.PIPE, text=True).stdout  # stderr shown
    return json.loads(out.strip().splitlines()[-1])


def report(name: str, got: dict) -> None:
    loads = "; ".join(f"{m} {min(v):.1f}-{max(v):.1f}" for m, v in got["loads"].items())
    print(f"\n== {name}: layer {got['layer']}, {got['threads']} threads; 1-min load during {loads} ==")
    print(f"{'kernel':32s} {'quiet':>9s} {'one':>9s} {'busy':>9s} {'busy one':>9s}  busy/one  busy/busy one")
    worst = 0.0
    for kernel, t in got["best"].items():
        r1, r2 = t["busy"] / t["one"], t["busy"] / t["busy one"]
        worst = max(worst, r1)
        cells = " ".join(f"{t[m] * 1e3:9.2f}" for m in MODES)
        flag = "" if r1 <= TARGET else "  over"
        print(f"{kernel:32s} {cells}  {r1:7.2f}x {r2:9.2f}x{flag}")
    print(f"(ms, best of each mode) worst busy/one {worst:.2f}x; target <= {TARGET}x")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--configs", default="this")
    ap.add_argument("--baseline-tree", default=None)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--folder", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args)
        return
    with tempfile.TemporaryDirectory(prefix="silcount-busy-") as folder:
        args.folder = folder
        load_meshes(Path(folder))  # built once, read by every child
        print(load_line())
        for name in args.configs.split(","):
            report(name, run_config(name, args))
        print(load_line())


if __name__ == "__main__":
    main()
