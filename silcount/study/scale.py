"""How long a sweep of a large collection takes: a list-scheduling model over measured units (docs/corpus.md).

The inputs are measurements of this machine, taken by ``scripts/corpus_profile.py`` and committed as
``silcount/models/measured/corpus-profile.json``:

* ``units``: every unit of the shared corpus (file, level, bytes, faces) and its seconds on one numba
  thread, run in one warm process (:func:`silcount.study.work.audit_task`);
* ``startup_s``: a fresh worker process until its first unit can start (Python, silcount, numba's
  cached kernels and the first unit's warm-up, measured on the smallest built-in mesh);
* ``task_overhead_s``: the scheduler's round trip per unit (the file's bytes out, the rows back),
  measured with units that do no work but carry the same bytes and return the same results;
* ``client_per_unit_s``: the client's work per finished unit during the sweep (the cache entry);
* ``client_final_per_unit_s``: its work per unit after the last one (the frames and fits, measured
  over a fully cached sweep);
* ``measured``: the wall time of the real sweep at ``1x1`` (one worker, one numba thread) and ``2``
  (two workers, one thread each), taken in the same run, to check the model against.

The model: a sweep of units with times ``t_i`` on ``W`` workers takes ::

    startup + max(makespan_W(t_i + overhead), N * client_per_unit) + N * client_final_per_unit

where ``makespan_W`` is greedy list scheduling in the sweep's own order (largest file first, each unit
to the worker that is free first).  A 10,000-unit collection is drawn from the measured units with
replacement (seeded), i.e. it is assumed to look like the shared corpus.
"""

from __future__ import annotations

import heapq
import json
from dataclasses import dataclass

import numpy as np
import pandas as pd

PROFILE = "corpus-profile.json"
COLLECTION = 10_000
WORKERS = (1, 8, 64)
TOLERANCE = 0.20  # the model must predict the measured walls within 20 %


@dataclass(frozen=True)
class SweepProfile:
    """The measured inputs of the model (see the module docstring)."""

    units: pd.DataFrame  # file, level, bytes, faces, seconds
    startup_s: float
    task_overhead_s: float
    client_per_unit_s: float
    client_final_per_unit_s: float
    measured: dict[str, float]  # configuration -> wall seconds (the mean of its runs)
    about: dict  # machine, date, settings
    measured_runs: dict[str, list[float]]  # configuration -> every run's wall seconds
    work_per_pass_s: list[float]  # the units' total seconds in each pass

    @classmethod
    def from_dict(cls, data: dict) -> SweepProfile:
        return cls(
            units=pd.DataFrame(data["units"], columns=["file", "level", "bytes", "faces", "seconds"]),
            startup_s=float(data["startup_s"]),
            task_overhead_s=float(data["task_overhead_s"]),
            client_per_unit_s=float(data["client_per_unit_s"]),
            client_final_per_unit_s=float(data["client_final_per_unit_s"]),
            measured={k: float(v) for k, v in data["measured"].items()},
            about=dict(data["about"]),
            measured_runs={k: [float(x) for x in v] for k, v in data.get("measured_runs", {}).items()},
            work_per_pass_s=[float(x) for x in data.get("work_per_pass_s", [])],
        )


def load_profile() -> SweepProfile:
    """The committed profile (package data, under :func:`silcount.counting.models.models_dir`)."""
    from silcount.counting.models import models_dir

    return SweepProfile.from_dict(json.loads((models_dir() / "measured" / PROFILE).read_text(encoding="utf-8")))


def makespan(seconds: np.ndarray, size: np.ndarray, workers: int) -> float:
    """Greedy list scheduling: units in descending ``size`` (ties by position), each to the first free worker."""
    order = sorted(range(len(seconds)), key=lambda i: (-int(size[i]), i))
    free = [0.0] * max(int(workers), 1)
    for i in order:
        heapq.heappush(free, heapq.heappop(free) + float(seconds[i]))
    return max(free)


def predict(profile: SweepProfile, seconds: np.ndarray, size: np.ndarray, workers: int) -> float:
    """The model's wall time of a sweep of these units on ``workers`` workers (one numba thread each)."""
    return _wall(profile, len(seconds), makespan(np.asarray(seconds) + profile.task_overhead_s, size, workers))


def _wall(profile: SweepProfile, n: int, span: float) -> float:
    """The model's formula (module docstring) for ``n`` units whose workers' makespan is ``span``."""
    return profile.startup_s + max(span, n * profile.client_per_unit_s) + n * profile.client_final_per_unit_s


def check(profile: SweepProfile) -> pd.DataFrame:
    """The model against the real sweep: one row per measured configuration ``WxT``/``W``."""
    rows = []
    u = profile.units
    for config, wall in profile.measured.items():
        workers = int(config.partition("x")[0])
        model = predict(profile, u["seconds"].to_numpy(), u["bytes"].to_numpy(), workers)
        rows.append({"configuration": config, "workers": workers, "measured_s": wall, "model_s": model,
                     "error": model / wall - 1.0})  # fmt: skip
    out = pd.DataFrame(rows)
    out["within_tolerance"] = out["error"].abs() <= TOLERANCE
    return out


def estimate(profile: SweepProfile, units: int = COLLECTION, workers=WORKERS, seed: int = 0) -> pd.DataFrame:
    """The model's wall time of ``units`` units drawn (with replacement, seeded) from the measured ones."""
    u = profile.units
    pick = np.random.default_rng(seed).integers(0, len(u), units)
    seconds, size = u["seconds"].to_numpy()[pick], u["bytes"].to_numpy()[pick]
    rows = []
    for w in workers:
        span = makespan(seconds + profile.task_overhead_s, size, w)
        client = units * profile.client_per_unit_s
        rows.append({
            "workers": int(w),
            "wall_s": _wall(profile, units, span),
            "work_s": float(seconds.sum()),
            "makespan_s": span,
            "client_s": client,
            "client_after_s": units * profile.client_final_per_unit_s,
            "bound": "client" if client > span else "workers",
        })  # fmt: skip
    return pd.DataFrame(rows)


def _hms(s: float) -> str:
    h, rem = divmod(round(s), 3600)
    m, sec = divmod(rem, 60)
    return f"{h} h {m:02d} min" if h else f"{m} min {sec:02d} s"


def page(profile: SweepProfile) -> str:
    """``reports/corpus/scale.md``: the check against the real sweep, then the 10,000-unit estimate."""
    a = profile.about
    u = profile.units
    lines = [
        "# silcount corpus: how long would 10,000 meshes take?",
        "",
        f"Measured on {a['machine']} on {a['date']} by `scripts/corpus_profile.py` "
        f"({a['settings']}); the model is in `silcount/study/scale.py` and docs/corpus.md.",
        "",
        "## Inputs",
        "",
        f"- {len(u)} units of the shared corpus, {u['seconds'].sum():.1f} s of work in all on one numba thread "
        f"(the mean of passes of {', '.join(f'{x:.1f}' for x in profile.work_per_pass_s)} s; "
        f"median {u['seconds'].median() * 1e3:.0f} ms, largest {u['seconds'].max():.2f} s: "
        f"{u['file'].iloc[int(np.argmax(u['seconds'].to_numpy()))]});",
        f"- a worker's start-up {profile.startup_s:.2f} s; the scheduler's round trip per unit "
        f"{profile.task_overhead_s * 1e3:.1f} ms;",
        f"- the client's work per finished unit {profile.client_per_unit_s * 1e3:.1f} ms during the sweep and "
        f"{profile.client_final_per_unit_s * 1e3:.1f} ms after it (frames and fits).",
        "",
        "## The model against the real sweep",
        "",
        "| configuration | measured (mean of runs) | runs | model | error |",
        "|---|---|---|---|---|",
    ]
    c = check(profile)
    for r in c.to_dict("records"):
        model, err = f"{r['model_s']:.1f} s", f"{100 * r['error']:+.1f} %"
        runs = ", ".join(f"{x:.1f}" for x in profile.measured_runs.get(r["configuration"], []))
        lines.append(f"| {r['configuration']} | {r['measured_s']:.1f} s | {runs} | {model} | {err} |")
    ok = bool(c["within_tolerance"].all())
    lines += [
        "",
        f"{'Every' if ok else 'Not every'} prediction is within {100 * TOLERANCE:.0f} % of the measured wall time "
        "(`1x1`: one worker on one numba thread; `2`: two workers on one thread each).",
        "",
        f"## A collection of {COLLECTION:,} meshes like the shared corpus",
        "",
        "| workers | wall time | workers' makespan | client during (bound by) | client after |",
        "|---|---|---|---|---|",
    ]
    for e in estimate(profile).to_dict("records"):
        during, after = f"{_hms(e['client_s'])} ({e['bound']})", _hms(e["client_after_s"])
        lines.append(f"| {e['workers']} | {_hms(e['wall_s'])} | {_hms(e['makespan_s'])} | {during} | {after} |")
    lines += [
        "",
        f"{COLLECTION:,} units drawn with replacement (seed 0) from the measured ones; each worker one core. "
        "The wall time is the start-up, then the workers' makespan or the client's work during the sweep, "
        "whichever is longer, then the client's frames and fits after it, which run on one core and so "
        "bound every sweep of this size from below. The estimate assumes the collection's sizes are "
        "distributed as the shared corpus's, and scales the client's work linearly in the number of units.",
        "",
    ]
    lines += collection_lines(profile, collection_sizes())
    return "\n".join(lines)


# ---- a collection of real sizes -------------------------------------------------------------------------
COLLECTIONS_ENV = "SILCOUNT_COLLECTIONS_DIR"
THINGI = "thingi10k-sizes.csv"


@dataclass(frozen=True)
class Planned:
    """The model of a sweep of units of known faces: its wall time and its schedule's figures."""

    wall_s: float
    makespan_s: float
    work_s: float
    tasks: int
    tail_s: float  # from the first idle worker (nothing left to start) to the workers' end
    largest_task_s: float


def schedule_tasks(seconds: list[float], workers: int) -> tuple[float, float]:
    """Greedy list scheduling of tasks in the order given, each to the first free worker: the makespan and
    the time at which a worker first finds nothing left to start."""
    free = [0.0] * max(int(workers), 1)
    for t in seconds:
        heapq.heappush(free, heapq.heappop(free) + float(t))
    return max(free), min(free)


def plan_collection(profile: SweepProfile, faces, workers: int, settings=None, budget: int | None = None) -> Planned:
    """The model's sweep of files of ``faces`` faces on ``workers`` workers (one numba thread each): the
    units split and ordered as :func:`silcount.study.schedule.plan_tasks` does, each task's time the
    unit model's (:mod:`silcount.study.units`) plus the round trip, then the formula of the module docstring."""
    from silcount.study.schedule import Item, plan_tasks
    from silcount.study.work import Settings

    settings = settings or Settings()
    items = [Item(f"{k}.ply", b"", "", 0, None, int(f)) for k, f in enumerate(faces)]
    tasks, refused = plan_tasks(items, list(range(len(items))), settings, workers, budget)
    seconds = [t.seconds + profile.task_overhead_s for t in tasks]
    span, first_idle = schedule_tasks(seconds, workers)
    return Planned(
        wall_s=_wall(profile, len(items), span),
        makespan_s=span,
        work_s=float(sum(t.seconds for t in tasks)),
        tasks=len(tasks),
        tail_s=span - first_idle,
        largest_task_s=max(seconds, default=0.0),
    )


def collection_sizes() -> np.ndarray | None:
    """Thingi10K's face counts (``$SILCOUNT_COLLECTIONS_DIR``, else ``../shared/collections`` beside the
    checkout, ``thingi10k-sizes.csv``), or None when the file is not there."""
    import os
    from pathlib import Path

    env = os.environ.get(COLLECTIONS_ENV)
    folder = Path(env) if env else Path(__file__).resolve().parents[3] / "shared" / "collections"
    path = folder / THINGI
    if not path.is_file():
        return None
    return pd.read_csv(path, usecols=["num_faces"])["num_faces"].to_numpy(np.int64)


QUIET_LOAD = 1.5
"""The profile's units run one at a time on one thread, so its own process puts about 1 on the load."""


def _load_reading(load: float) -> str:
    """How to read the profile's times at the highest 1-minute load seen while it was measured."""
    if load <= QUIET_LOAD:
        return "the measuring process's own, a quiet machine's times."
    return "the machine was shared, and its times are a busy machine's (several times a quiet one's)."


def collection_lines(profile: SweepProfile, sizes: np.ndarray | None) -> list[str]:
    """scale.md's section on a Thingi10K-shaped sweep (its sizes; a line saying why not without them)."""
    from silcount.study.units import load_model
    from silcount.study.work import Settings

    lines = ["## A collection shaped like Thingi10K", ""]
    if sizes is None:
        return lines + [f"Skipped: no `{THINGI}` (set ${COLLECTIONS_ENV}).", ""]
    model = load_model()
    settings = Settings()
    big = sizes.max()
    lines += [
        f"Thingi10K's {sizes.size:,} meshes (`{THINGI}`): median {int(np.median(sizes)):,} faces, largest "
        f"{int(big):,}, {int(sizes.sum()) / 1e6:.1f} M faces in all. Each unit's time and peak memory come from "
        "the power laws fitted to units measured from 1 k to 4 M faces (`unit-profile.json`, "
        "`silcount/study/units.py`), with `silcount corpus`'s default settings (64 directional lights, every "
        "detector, the plain loops timed), on one numba thread per worker:",
        "",
        "| fit | alpha (95 % interval) | class (Akaike weight; runner-up) | at 1 M faces |",
        "|---|---|---|---|",
    ]
    for what, unit in (("seconds", "s"), ("extra_bytes", "MiB")):
        f = model.fit_of("all", what)
        at = f["c"] * 1e6 ** f["alpha"] / (2**20 if unit == "MiB" else 1)
        ci = f["alpha_ci"] or [float("nan")] * 2
        name = "time" if what == "seconds" else "peak memory above the warm worker's"
        k = f.get("classes")  # silcount.study.classes, over the same points
        cls = f"{k['chosen']} ({k['weight']:.2f}; {k['runner_up']} {k['runner_up_weight']:.2f})" if k else "-"
        lines.append(f"| {name} | {f['alpha']:.2f} ({ci[0]:.2f}-{ci[1]:.2f}) | {cls} | {at:,.1f} {unit} |")
    largest = model.peak_bytes(float(big), settings)
    loads = [u["load_1min"] for u in model.units if "load_1min" in u]
    a = model.about
    lines += [
        "",
        f"Measured on {a.get('machine', '?')} on {a.get('date', '?')} by `scripts/unit_profile.py`, at a 1-minute "
        f"load of {min(loads, default=float('nan')):.1f}-{max(loads, default=float('nan')):.1f}: "
        + _load_reading(max(loads, default=float("nan"))),
        "",
        f"The largest mesh needs about {largest / 2**30:.1f} GiB in one worker (the fit with its margin) and "
        f"{model.seconds(float(big), settings):,.0f} s.",
        "",
        "| workers | wall time | workers' makespan | tasks (units split) | tail (first idle worker to end) |",
        "|---|---|---|---|---|",
    ]
    for w in WORKERS:
        p = plan_collection(profile, sizes, w, settings, None)
        lines.append(f"| {w} | {_hms(p.wall_s)} | {_hms(p.makespan_s)} | {p.tasks:,} | {p.tail_s:.1f} s |")
    lines += [
        "",
        "Units are ordered largest first by their estimated time, and a unit estimated at more than 1/(2W) "
        "of the sweep's work on W workers runs as up to W batches of its lights "
        "(`silcount/study/schedule.py`); no memory budget splits a unit here (the page does not depend on the "
        "machine's memory): give each worker at least the largest mesh's need above. "
        "The client's terms are the shared corpus's (above), per unit. "
        "`python -m benchmarks.thingi` checks this model on a real sweep of meshes of Thingi10K's sizes.",
        "",
    ]
    return lines


__all__ = ["SweepProfile", "load_profile", "makespan", "predict", "check", "estimate", "page", "plan_collection",
           "schedule_tasks", "collection_sizes", "Planned"]  # fmt: skip
