"""Measure the inputs of the sweep-time model (silcount/study/scale.py) and write its profile JSON.

    python -m scripts.corpus_profile [CORPUS_DIR] [--out silcount/models/measured/corpus-profile.json]

(from the checkout's root: it runs the sweep of :mod:`benchmarks.corpus`)

On the shared corpus (``SILCOUNT_CORPUS_DIR``, else the folder given) with the settings of
``benchmarks/corpus.py`` (level 0, 64 directional lights, every detector, ``intended``, ``fast``, no
plain-loop timing), in one run:

1. every unit in this process on one numba thread, after a warm-up, in the sweep's order: its seconds
   (the mean of ``REPEAT`` passes, interleaved with the real sweeps of step 5);
2. a worker's start-up: a fresh Python process importing silcount and auditing the built-in
   tetrahedron (the first unit's warm-up), its wall time;
3. the scheduler's round trip per unit: Dask's ``processes`` scheduler, one worker, with units that
   take the same bytes and return the results of step 1 without working, against one such unit
   (after a first one that starts the process pool);
4. the client's work per unit: writing each result's cache entry (during the sweep), and a sweep over
   a full cache (its frames and fits, after it), per unit;
5. the real sweep at ``1x1`` and ``2`` (``benchmarks.corpus.run_config``, fresh processes), ``REPEAT``
   times each: the mean walls the model is checked against (every run is kept in the profile).

It prints the model's check and estimate from what it measured.  Timings on a shared machine are noisy.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import pickle
import platform
import subprocess
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

import numba

from benchmarks.corpus import corpus_dir, run_config
from silcount.study import find_files, scale, schedule
from silcount.study.cache import Cache, cache_key
from silcount.study.units import faces_of
from silcount.study.work import Settings, audit_task

ROOT = Path(__file__).resolve().parent.parent
REPEAT = 2  # interleaved passes of the unit times and the real sweeps; the profile keeps their means
OUT = ROOT / "silcount" / "models" / "measured" / scale.PROFILE
SETTINGS = Settings(timing=False)  # 64 directional lights, seed 0, every detector, intended, fast
STARTUP = (
    "from silcount.study.work import Settings, audit_task; from pathlib import Path; "
    "audit_task('tetrahedron.obj', Path({path!r}).read_bytes(), 0, Settings(timing=False))"
)


def echo(stored: str, label: str, data: bytes, level: int) -> dict:
    """A unit that does no work: it takes the bytes and returns the result stored (pickled) at ``stored``."""
    return pickle.loads(Path(stored).read_bytes())


def items_of(folder: Path) -> list[schedule.Item]:
    """The sweep's units, in its order (largest first)."""
    items = []
    for label, path in find_files([folder]):
        data = path.read_bytes()
        items.append(schedule.Item(label, data, hashlib.sha256(data).hexdigest(), 0, None, faces_of(path)))
    return sorted(items, key=lambda it: -schedule.unit_cost(it, SETTINGS))


def unit_times(items: list[schedule.Item]) -> tuple[list[dict], list[float]]:
    """Every unit once in this process on one numba thread (after a warm-up): results and seconds."""
    numba.set_num_threads(1)
    audit_task("tetrahedron.obj", (ROOT / "data" / "tetrahedron.obj").read_bytes(), 0, SETTINGS)  # warm-up
    results, seconds = [], []
    for it in items:
        t = time.perf_counter()
        results.append(audit_task(it.label, it.data, it.level, SETTINGS))
        seconds.append(time.perf_counter() - t)
    return results, seconds


def cpu_model() -> str:
    """The CPU's model name from /proc/cpuinfo (Linux), else the platform's processor string."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def startup() -> float:
    code = STARTUP.format(path=str(ROOT / "data" / "tetrahedron.obj"))
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    return time.perf_counter() - t


def round_trip(items: list[schedule.Item], results: list[dict]) -> float:
    import dask

    with tempfile.TemporaryDirectory() as tmp:
        stored = []
        for i, r in enumerate(results):
            stored.append(Path(tmp) / f"{i}.pickle")
            stored[-1].write_bytes(pickle.dumps(r))

        def run(n: int) -> float:
            tasks = [dask.delayed(echo, pure=False)(str(s), it.label, it.data, 0) for it, s in zip(items[:n], stored)]
            t = time.perf_counter()
            dask.compute(*tasks, scheduler="processes", pool=pool, chunksize=1)  # as the sweep hands units out
            return time.perf_counter() - t

        with schedule.process_pool(1) as pool:  # one pool for every run: its start is not in the difference
            run(1)  # the worker's start and first unit
            one, every = run(1), run(len(items))
    return (every - one) / (len(items) - 1)


def client_costs(items: list[schedule.Item], results: list[dict], folder: Path) -> tuple[float, float]:
    from silcount.study import corpus

    with tempfile.TemporaryDirectory() as tmp:
        cache = Cache(Path(tmp))
        t = time.perf_counter()
        for it, r in zip(items, results):
            cache.put(cache_key(it.sha256, 0, SETTINGS), r, SETTINGS)
        during = (time.perf_counter() - t) / len(items)
        t = time.perf_counter()  # every entry is in the cache (the keys above are the sweep's)
        corpus([folder], lights=64, subdivide=[0], timing=False, quiet=True, cache=tmp, scheduler="threads", workers=1)
        after = (time.perf_counter() - t) / len(items)
    return during, after


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    folder = corpus_dir(args.folder)
    items = items_of(folder)
    passes: list[list[float]] = []
    walls: dict[str, list[float]] = {"1x1": [], "2": []}
    for r in range(REPEAT):  # interleaved: the machine's load drifts between the two kinds of measurement
        results, seconds = unit_times(items)
        passes.append(seconds)
        print(f"pass {r + 1}: units: {len(items)}, {sum(seconds):.1f} s of work on one numba thread")
        for config in walls:
            bench_args = argparse.Namespace(subdivide="0", with_time=False)
            walls[config].append(run_config(folder, config, bench_args, None)["wall_s"])
            print(f"pass {r + 1}: the real sweep at {config}: {walls[config][-1]:.1f} s")
    seconds = [sum(ts) / len(ts) for ts in zip(*passes)]
    up = startup()
    print(f"a worker's start-up: {up:.2f} s")
    trip = round_trip(items, results)
    print(f"the scheduler's round trip per unit: {trip * 1e3:.1f} ms")
    during, after = client_costs(items, results, folder)
    print(f"the client per unit: {during * 1e3:.1f} ms during, {after * 1e3:.1f} ms after")
    profile = {
        "about": {
            "machine": f"{platform.machine()}, {os.cpu_count()} cores ({cpu_model()})",
            "date": date.today().isoformat(),
            "settings": "level 0, 64 directional lights, every detector, intended, fast, no plain-loop timing",
        },
        "units": [
            [it.label, it.level, len(it.data), int(r["mesh"].get("faces") or 0), round(s, 6)]
            for it, r, s in zip(items, results, seconds)
        ],
        "startup_s": round(up, 6),
        "task_overhead_s": round(trip, 6),
        "client_per_unit_s": round(during, 6),
        "client_final_per_unit_s": round(after, 6),
        "measured": {k: round(sum(v) / len(v), 3) for k, v in walls.items()},
        "measured_runs": {k: [round(x, 3) for x in v] for k, v in walls.items()},
        "work_per_pass_s": [round(sum(ts), 3) for ts in passes],
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(profile, indent=1) + "\n")
    p = scale.SweepProfile.from_dict(profile)
    print(scale.check(p).to_string(index=False))
    print(scale.estimate(p).to_string(index=False))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
