"""Benchmark `silcount corpus` on the shared corpus: wall time per worker count, peak memory per worker.

Settings of issue 13: every file of the corpus (``SILCOUNT_CORPUS_DIR``, else
``../shared/corpus`` beside the repository, else the folder given), 64
directional lights, every detector (``intended``: the papers' four, the
reference, gaussmap and cones) on the ``fast`` engine, Dask's local
``processes`` scheduler, no cache, no timing of the plain loops (``--with-time``
adds it).  Each configuration runs in a fresh Python process so that
``getrusage(RUSAGE_CHILDREN).ru_maxrss`` is the peak resident memory of *its*
worker processes (the largest one), beside the client's own peak.

``--workers`` lists configurations: ``N`` is N workers, each running numba's
kernels on ``cores // N`` threads (the sweep's rule, docs/corpus.md); ``NxT``
pins numba to T threads in every process (``NUMBA_NUM_THREADS``), so ``1x1``
is the one-core baseline of a pure scale-out ratio.  ``--baseline-tree DIR``
runs every configuration a second time with the package imported from DIR (a
checkout of an earlier commit; ``PYTHONPATH``), and prints the ratios.  The
ratio lines compare runs of this invocation.

    python -m benchmarks.corpus [CORPUS_DIR] [--workers 1x1,1,2] [--subdivide 0] [--with-time]
                                [--baseline-tree DIR]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

from benchmarks.common import ROOT, child_command, tree_env

TARGET_S = 300.0


def corpus_dir(given: str | None) -> Path:
    for candidate in (given, os.environ.get("SILCOUNT_CORPUS_DIR"), str(ROOT.parent / "shared" / "corpus")):
        if candidate and Path(candidate).is_dir():
            return Path(candidate)
    sys.exit("no corpus: pass a folder, set SILCOUNT_CORPUS_DIR, or put one at ../shared/corpus")


def one(folder: Path, workers: int, levels: list[int], with_time: bool) -> dict:
    """One sweep in this process; wall time, meshes, failures, peak RSS of the client and of the largest worker."""
    from silcount.study import corpus

    start, t0 = time.time(), time.perf_counter()  # the wall clock's start, for timelines read against it
    result = corpus(
        [folder],
        lights=64,
        light_kind="directional",
        subdivide=levels,
        scheduler="processes",
        workers=workers,
        cache=False,
        timing=with_time,
        quiet=True,
    )
    wall = time.perf_counter() - t0
    for child in multiprocessing.active_children():  # the pool is shut down without waiting: reap its workers,
        child.join()  # after the clock, so that RUSAGE_CHILDREN counts them
    return {
        "workers": workers,
        "wall_s": wall,
        "start_epoch": start,
        "meshes": len(result.meshes),
        "failed": result.failed,
        "rows": len(result.rows),
        "faces": int(result.meshes["faces"].fillna(0).sum()),
        "client_peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "worker_peak_mib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
    }


def run_config(folder: Path, config: str, args, tree: str | None) -> dict:
    """One configuration (``N`` or ``NxT``) in a fresh process; the package from ``tree`` when given."""
    workers, _, threads = config.partition("x")
    env = tree_env(tree or None)
    if threads:
        env["NUMBA_NUM_THREADS"] = threads
    cmd = child_command(__spec__.name, str(folder), "--one", workers, "--subdivide", args.subdivide)
    out = subprocess.run(cmd + (["--with-time"] if args.with_time else []), capture_output=True, text=True, env=env)
    if out.returncode:
        sys.exit(f"{config} ({tree or 'this tree'}): failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1]) | {"config": config}


def show(label: str, r: dict) -> None:
    verdict = "under" if r["wall_s"] < TARGET_S else "OVER"
    print(
        f"{label:24s} {r['wall_s']:8.1f} s wall ({verdict} the {TARGET_S:.0f} s target), "
        f"{r['meshes']} meshes ({r['failed']} failed), {r['faces']:,} faces, {r['rows']:,} rows; "
        f"peak RSS: largest worker {r['worker_peak_mib']:.0f} MiB, client {r['client_peak_mib']:.0f} MiB"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?")
    ap.add_argument("--workers", default="1x1,1,2", help="configurations N or NxT (default 1x1,1,2)")
    ap.add_argument("--subdivide", default="0")
    ap.add_argument("--with-time", action="store_true")
    ap.add_argument("--baseline-tree", default=None, help="a checkout of an earlier commit to compare with")
    ap.add_argument("--one", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    folder = corpus_dir(args.folder)
    levels = [int(v) for v in args.subdivide.split(",")]
    if args.one is not None:
        print(json.dumps(one(folder, args.one, levels, args.with_time)))
        return
    print(
        f"corpus {folder}, levels {levels}, 64 directional lights, 7 detectors intended, fast engine, "
        f"processes scheduler, {'with' if args.with_time else 'no'} plain-loop timing; load {os.getloadavg()[0]:.1f}"
    )
    runs = {}
    for config in args.workers.split(","):
        runs[config] = run_config(folder, config, args, None)
        show(f"{config} (this tree)", runs[config])
        if args.baseline_tree:
            base = run_config(folder, config, args, args.baseline_tree)
            show(f"{config} (baseline)", base)
            print(f"{'':24s} this tree is {base['wall_s'] / runs[config]['wall_s']:.2f}x the baseline's speed")
    for one_ in ("1x1", "1"):
        for config, r in runs.items():
            if one_ in runs and config not in ("1x1", "1"):
                print(f"speed-up of {config} over {one_}: {runs[one_]['wall_s'] / r['wall_s']:.2f}x")
    print(f"load average after: {os.getloadavg()[0]:.1f} (figures taken under this load)")


if __name__ == "__main__":
    main()
