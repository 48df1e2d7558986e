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
    return "\n".join(lines)


__all__ = ["SweepProfile", "load_profile", "makespan", "predict", "check", "estimate", "page"]
