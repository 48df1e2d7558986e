"""Splitting a unit into parts (detectors x a batch of lights) and joining the parts' results into the unit's.

A unit is split for two reasons (docs/corpus.md, "Memory" and "Scheduling"):

* **memory**: its estimated peak (:mod:`silcount.study.units`) is over the worker's budget.  Its
  detectors are first packed, in their order, into groups that fit; a detector that does not fit alone
  then runs its lights in batches as large as fit.  A unit whose one detector cannot fit even one light
  is refused: its error row says so in one line, and the sweep goes on.
* **balance**: its estimated time is a large share of the whole sweep's, so that run alone at the end it
  would leave the other workers idle.  Its lights are cut into batches run as separate tasks.

Every part loads the file and runs the reference (its agreement columns need it), so a split costs
those once more per part.  :func:`merge` gives exactly the result of the unsplit unit (the same rows in
the same order, the same mesh record): rows are keyed by light and run; the mesh's silhouette mean and
deviation are recomputed from the rows' ``reference_edges`` over all lights; the timings come from the
parts that start at light 0 (see :func:`silcount.study.work.audit_task`).
"""

from __future__ import annotations

import math

import numpy as np

from silcount.study.units import total_lights
from silcount.study.work import Part, Settings, row_columns


def light_batches(lights: int, parts: int) -> list[tuple[int, int]]:
    """``lights`` cut into ``parts`` contiguous batches as equal as can be (the first ones one larger)."""
    parts = max(1, min(parts, lights))
    size, extra = divmod(lights, parts)
    bounds = np.cumsum([0] + [size + (k < extra) for k in range(parts)])
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]


def by_memory(settings: Settings, budget: int, need) -> list[Part] | str:
    """Parts whose ``need(detectors, lights)`` (estimated peak bytes) is within ``budget``, or the refusal line.

    ``need`` must grow with the detectors and with the lights.
    """
    L = total_lights(settings)
    whole = tuple(settings.detectors)
    if need(whole, L) <= budget:
        return [Part(whole, 0, L)]
    groups: list[list[str]] = []
    for name in whole:  # pack in order: contiguous groups keep the unit's run order by detector
        if groups and need((*groups[-1], name), L) <= budget:
            groups[-1].append(name)
        else:
            groups.append([name])
    parts: list[Part] = []
    for group in map(tuple, groups):
        if need(group, L) <= budget:
            parts.append(Part(group, 0, L))
            continue
        fits = max((n for n in range(1, L) if need(group, n) <= budget), default=0)
        if fits == 0:
            return (
                f"refused: {group[0]} needs about {need(group, 1) / 2**20:,.0f} MiB for one light, "
                f"over the memory budget of {budget / 2**20:,.0f} MiB (--memory-budget)"
            )
        parts += [Part(group, lo, hi) for lo, hi in light_batches(L, math.ceil(L / fits))]
    return parts


def by_time(parts: list[Part], pieces: int) -> list[Part]:
    """Each part cut into ``pieces`` batches of its lights (fewer when it has fewer lights)."""
    out = []
    for p in parts:
        out += [Part(p.detectors, p.lo + lo, p.lo + hi) for lo, hi in light_batches(p.hi - p.lo, pieces)]
    return out


def _rows(part_result: dict) -> list[dict]:
    """A part's rows, one dict each; a ``steps_`` column a row lacks is absent (never ``None`` otherwise)."""
    rows = part_result["rows"]
    cols, values = rows["columns"], rows["values"]
    n = len(values[0]) if values else 0
    return [
        {k: v[i] for k, v in zip(cols, values, strict=True) if not (v[i] is None and k.startswith("steps_"))}
        for i in range(n)
    ]


def merge(results: list[dict], parts: list[Part], settings: Settings) -> dict:
    """The unit's result from its parts' (in the order of ``parts``); the first part's error if one failed."""
    failed = next((r for r in results if r.get("error")), None)
    if failed is not None:
        return failed
    if len(results) == 1 and parts[0].detectors == tuple(settings.detectors):
        return results[0]
    rows = {(row["light"], row["detector"]): row for r in results for row in _rows(r)}
    keys = [key for key, _, _ in settings.runs()]
    L = total_lights(settings)
    ordered = [rows[(light, key)] for light in range(L) for key in keys]
    first = [r for r, p in zip(results, parts, strict=True) if p.lo == 0]  # one per detector group, in order
    record = dict(first[0]["mesh"])
    silhouettes = np.array([rows[(light, keys[0])]["reference_edges"] for light in range(L)], dtype=np.float64)
    record["lights"] = L
    record["silhouette_edges_mean"] = float(silhouettes.mean())
    record["silhouette_edges_std"] = float(silhouettes.std())
    builds = {k: v for r in first for k, v in r["mesh"]["build"].items()}
    record["build"] = {k: builds[k] for k in keys if k in builds}
    kinds = list(first[0]["mesh"]["time_by_light_kind"])
    record["time_by_light_kind"] = {
        kind: {d: t for r in first for d, t in r["mesh"]["time_by_light_kind"][kind].items()} for kind in kinds
    }
    record["time_per_light_s"] = next(
        iter(record["time_by_light_kind"].values()), {d: None for d in settings.detectors}
    )
    errors = [e for r in first for e in r["mesh"]["time_errors"]]
    if len(kinds) > 1:  # each kind's errors together, as the unsplit unit lists them
        errors = [e for kind in kinds for e in errors if e.startswith(f"{kind} lights: ")]
    record["time_errors"] = errors
    return {**results[0], "mesh": record, "rows": row_columns(ordered)}
