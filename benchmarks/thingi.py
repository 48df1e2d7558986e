"""Check the sweep-time model on a real sweep of meshes of Thingi10K's sizes, at 1 and 2 workers, and its tail.

``--meshes`` sizes are drawn (seeded) from ``thingi10k-sizes.csv``, at least ``--big`` of them of 1 M faces or
more, and each is synthesised by subdividing a corpus mesh to about that size (:mod:`benchmarks.collection`).
The folder is then swept by :func:`silcount.study.corpus` with ``silcount corpus``'s default settings
(``--lights`` aside), no cache, Dask's ``processes`` scheduler, once per configuration (``1x1``: one worker
on one numba thread; ``2``: two workers on one thread each), each in a fresh process.  For each it prints
the measured wall time beside the model's (:func:`silcount.study.scale.plan_collection`, from the committed
unit fits and corpus profile; target: within 20 %), and the tail: the time from the first idle worker (fewer
tasks left than workers) to the last task's end, measured from the client's task completion times and
predicted from the model's schedule.  The machine's load is printed before and after each run.

    python -m benchmarks.thingi [--meshes 100] [--big 3] [--seed 0] [--workers 1x1,2] [--lights 64] [--save F]
    python -m benchmarks.thingi --replay F     # the model (as committed now) against a saved run
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from benchmarks import collection
from benchmarks.common import child_command, load_line, tree_env

TARGET = 0.20


def one(folder: str, workers: int, lights: int) -> dict:
    """One sweep in this process: wall time, the tasks' completion times, failures."""
    from silcount.study import corpus

    timeline: list[float] = []
    t0 = time.perf_counter()
    result = corpus([folder], lights=lights, workers=workers, cache=False, quiet=True, timeline=timeline)
    wall = time.perf_counter() - t0
    return {"wall_s": wall, "done_s": [t - t0 for t in timeline], "failed": result.failed,
            "errors": [e for e in result.meshes["error"] if e]}  # fmt: skip


STARTUP = (
    "from silcount.study.work import Settings, audit_task; from pathlib import Path; "
    "audit_task('tetrahedron.obj', Path({path!r}).read_bytes(), 0, Settings())"
)


def startup(workers: int, env: dict) -> float:
    """The wall time of ``workers`` fresh processes started at once, each importing silcount and auditing the
    built-in tetrahedron (a worker's start and its first unit's warm-up), until the last is done."""
    from benchmarks.common import ROOT

    code = STARTUP.format(path=str(ROOT / "data" / "tetrahedron.obj"))
    t0 = time.perf_counter()
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env) for _ in range(workers)]
    if any(p.wait() for p in procs):
        sys.exit("a start-up process failed")
    return time.perf_counter() - t0


def measured_tail(done: list[float], workers: int) -> float:
    """From the first idle worker (the completion after which fewer tasks remain than workers) to the last."""
    done = sorted(done)
    first_idle = done[max(len(done) - workers, 0)] if workers > 1 else done[-1]
    return done[-1] - first_idle


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--meshes", type=int, default=100)
    ap.add_argument("--big", type=int, default=3, help="meshes of at least 1 M faces among them (default 3)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", default="1x1,2")
    ap.add_argument("--lights", type=int, default=64)
    ap.add_argument("--save", type=Path, default=None, help="also write the sizes and measurements to this JSON")
    ap.add_argument("--replay", type=Path, default=None, help="print the model against a --save file; run nothing")
    ap.add_argument("--one", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(one(args.one[0], int(args.one[1]), int(args.one[2]))))
        return
    if args.replay:
        saved = json.loads(args.replay.read_text())
        show(saved)
        return
    sizes = collection.draw(args.meshes, args.seed, args.big)
    saved = {"seed": args.seed, "lights": args.lights, "drawn": sizes, "faces": [], "runs": {}}
    with tempfile.TemporaryDirectory(prefix="silcount-thingi-") as tmp:
        for k, size in enumerate(sizes):
            recipe = collection.nearest(size)
            collection.write(recipe, Path(tmp), f"{k:03d}-{Path(recipe.file).stem}-L{recipe.level}")
            saved["faces"].append(recipe.faces)
        for config in args.workers.split(","):
            workers, _, threads = config.partition("x")
            env = tree_env(None, **({"NUMBA_NUM_THREADS": threads} if threads else {}))
            before = load_line()
            started = startup(int(workers), env)
            out = subprocess.run(
                child_command(__spec__.name, "--one", tmp, workers, str(args.lights)),
                capture_output=True, text=True, env=env,
            )  # fmt: skip
            if out.returncode:
                sys.exit(f"{config}: failed:\n{out.stderr}")
            saved["runs"][config] = json.loads(out.stdout.strip().splitlines()[-1]) | {
                "load_before": before,
                "load_after": load_line(),
                "startup_s": started,
            }
            if args.save:
                args.save.write_text(json.dumps(saved))
    show(saved)


def show(saved: dict) -> None:
    """The measured runs of ``saved`` beside the model's predictions from the committed profiles."""
    from silcount.study import scale
    from silcount.study.units import default_budget
    from silcount.study.work import Settings

    faces = saved["faces"]
    big = sum(f >= 1_000_000 for f in faces)
    print(
        f"{len(faces)} meshes drawn from Thingi10K's sizes (seed {saved['seed']}), {sum(faces):,} faces in all, "
        f"{big} of 1 M faces or more (largest {max(faces):,}); {saved['lights']} directional lights, every "
        "detector, plain loops timed, processes scheduler, no cache"
    )
    profile = scale.load_profile()
    settings = Settings(lights=saved["lights"])
    for config, r in saved["runs"].items():
        w = int(config.partition("x")[0])
        here = replace(profile, startup_s=r["startup_s"])  # this run's start-up, measured just before it
        model = scale.plan_collection(here, faces, w, settings, default_budget(w))
        err = model.wall_s / r["wall_s"] - 1
        verdict = "within" if abs(err) <= TARGET else "OUTSIDE"
        print(
            f"{config:4s}: measured {r['wall_s']:7.1f} s, model {model.wall_s:7.1f} s ({100 * err:+.1f} %, "
            f"{verdict} the {100 * TARGET:.0f} % target); {len(r['done_s'])} tasks (model {model.tasks}); "
            f"tail {measured_tail(r['done_s'], w):.1f} s (model {model.tail_s:.1f} s); "
            f"{r['failed']} failed {r['errors'][:2]}"
        )
        print(
            f"      start-up {r['startup_s']:.1f} s (measured before the run; quiet: {profile.startup_s:.1f} s); "
            f"first task done at {min(r['done_s']):.1f} s; before: {r['load_before']}; after: {r['load_after']}"
        )


if __name__ == "__main__":
    main()
