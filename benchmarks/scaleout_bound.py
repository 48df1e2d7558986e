"""The scale-out bound of the corpus sweep on this machine: two workers against one, measured inside the workers.

    python -m benchmarks.scaleout_bound [CORPUS_DIR] [--repeat 3] [--subdivide 0]

The sweep of ``benchmarks.corpus`` (its ``one``: the shared corpus, level 0 or ``--subdivide``'s levels,
64 directional lights, every detector, ``intended``, ``fast``, no plain-loop timing, no cache) runs at ``1x1``
(one worker on one numba thread) and at ``2`` (two workers, one thread each: the sweep's rule on two cores),
``--repeat`` times interleaved, each run in a fresh process.  Every worker records each unit's start and end:
the sweep's spawned workers do not re-run the caller's main module (:mod:`silcount.study.spawn`), so each
measured sweep gets a ``sitecustomize`` on its ``PYTHONPATH`` that imports this module at every interpreter's
start, and this module's top level wraps ``silcount.study.schedule.audit_task`` when ``SILCOUNT_BOUND_LOG``
names a folder.

From each run:

* **busy**: the units' seconds summed over the workers: the work, with each worker's first unit loading
  numba's cached kernels, and at two workers their contention for the shared caches and memory;
* **lead**: from the sweep's start to the first unit's start (the pool's spawn, the workers' imports);
* **tail**: from the last unit's end to the sweep's return (the client's frames and fits).

It prints the means and three ratios of ``1x1`` to ``2``: the measured speed-up of the wall times; the
ceiling of the work alone, ``busy(1x1) / (busy(2) / 2)``, what two workers would give with no lead, no tail
and a perfect split; and the ceiling with the measured lead and tail,
``(lead + busy + tail)(1x1) / (lead + busy / 2 + tail)(2)``.  A target above the work's ceiling cannot be
met by scheduling or start-up: only by less contention between the two workers.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from statistics import mean

from benchmarks.common import child_command, tree_env
from benchmarks.corpus import corpus_dir, one

LOG = os.environ.get("SILCOUNT_BOUND_LOG")
if LOG:  # in the measured sweep's client and, through the sitecustomize of :func:`run`, in each of its workers
    import silcount.study.schedule as _schedule

    _audit = _schedule.audit_task

    def _logged(label, data, level, settings, part=None):
        start = time.time()
        result = _audit(label, data, level, settings, part)
        with open(Path(LOG) / f"{os.getpid()}.txt", "a") as out:
            out.write(f"{start!r} {time.time()!r}\n")
        return result

    _schedule.audit_task = _logged

CONFIGS = ("1x1", "2")


def run(folder: Path, config: str, levels: str) -> dict:
    """``config`` in a fresh process: wall, lead, tail, busy, and each worker's unit count."""
    workers, _, threads = config.partition("x")
    with tempfile.TemporaryDirectory() as log, tempfile.TemporaryDirectory() as hook:
        Path(hook, "sitecustomize.py").write_text(f"import {__spec__.name}  # wraps audit_task in every worker\n")
        env = tree_env(None, SILCOUNT_BOUND_LOG=log)
        env["PYTHONPATH"] = os.pathsep.join([hook, env["PYTHONPATH"]])
        if threads:
            env["NUMBA_NUM_THREADS"] = threads
        cmd = child_command(__spec__.name, str(folder), "--one", workers, "--subdivide", levels)
        out = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if out.returncode:
            sys.exit(f"{config}: the sweep failed:\n{out.stderr}")
        sweep = json.loads(out.stdout.strip().splitlines()[-1])
        units = {
            f.stem: [tuple(float(x) for x in line.split()) for line in f.read_text().splitlines()]
            for f in Path(log).glob("*.txt")
        }
    spans = [s for per in units.values() for s in per]
    start, wall = sweep["start_epoch"], sweep["wall_s"]
    return {
        "wall": wall,
        "lead": min(a for a, _ in spans) - start,
        "tail": start + wall - max(b for _, b in spans),
        "busy": sum(b - a for a, b in spans),
        "units": sorted(len(per) for per in units.values()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--subdivide", default="0", help="levels, as benchmarks.corpus's (default 0)")
    ap.add_argument("--one", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    folder = corpus_dir(args.folder)
    if args.one is not None:
        print(json.dumps(one(folder, args.one, [int(v) for v in args.subdivide.split(",")], False)))
        return
    load = os.getloadavg()[0]
    print(f"corpus {folder}, levels {args.subdivide}, 64 directional lights, every detector; load {load:.1f}")
    runs: dict[str, list[dict]] = {c: [] for c in CONFIGS}
    for r in range(args.repeat):
        for config in CONFIGS:
            got = run(folder, config, args.subdivide)
            runs[config].append(got)
            print(
                f"run {r + 1} {config:>3}: wall {got['wall']:.2f} s = lead {got['lead']:.2f} + busy {got['busy']:.2f}"
                f" over {len(got['units'])} worker(s) {got['units']} + tail {got['tail']:.2f}"
            )
    m = {c: {k: mean(x[k] for x in runs[c]) for k in ("wall", "lead", "tail", "busy")} for c in CONFIGS}
    one_, two = m["1x1"], m["2"]
    for config, x in m.items():
        print(f"means {config:>3}: " + ", ".join(f"{k} {x[k]:.2f}" for k in ("wall", "lead", "busy", "tail")))
    print(f"contention: busy at 2 / busy at 1x1 = {two['busy'] / one_['busy']:.3f}")
    print(f"measured speed-up of 2 over 1x1: {one_['wall'] / two['wall']:.2f}x")
    print(f"ceiling of the work alone (no lead, no tail, a perfect split): {one_['busy'] / (two['busy'] / 2):.2f}x")
    serial = (one_["lead"] + one_["busy"] + one_["tail"]) / (two["lead"] + two["busy"] / 2 + two["tail"])
    print(f"ceiling with the measured lead and tail (a perfect split): {serial:.2f}x")
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
