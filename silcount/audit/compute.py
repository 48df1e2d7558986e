"""The audit of one mesh: every detector, every light, both cost models.  No formatting here.

:func:`run_audit` returns a JSON-ready ``dict`` (schema ``silcount-audit/1``,
documented in ``docs/audit.md``); :mod:`silcount.audit.layout` renders it.

Decisions, named:

* **Default lights**: :data:`DEFAULT_LIGHT_COUNT` point lights, seed
  :data:`DEFAULT_SEED`, from :func:`silcount.mesh.lights.random_lights`:
  directions drawn from a normal distribution with
  ``numpy.random.default_rng(seed)`` and normalised, placed at
  :data:`~silcount.mesh.lights.LIGHT_DISTANCE` times the bounding radius from
  the bounding-box centre.
* **Aggregate over lights**: ``silhouette_edges``, ``tallies``, ``steps``,
  ``cycles``, ``missed_edges``, ``extra_edges`` and ``time_s`` are *sums* over
  the lights; ``agrees_with_reference`` holds iff it holds for every light.
  ``formula_printed`` is per light (the formula does not depend on the light);
  its ratios compare the summed measurement with ``lights x printed``.
* **Agreement** is exact equality of edge sets with the ``reference``
  detector's, which is always run (and reported only when asked for); with
  the ``fast`` engine the reported ``reference`` run is that result.
* **All lights at once**: every run goes through
  :func:`silcount.detectors.detect_many` (identical to a run per light; the
  reference, TA, HSD and EESD batch their lights), and each light's
  ``time_s`` is its share of that pass (their sum, the aggregate's, is the
  pass's wall time).
* **Hierarchies** (``gaussmap``, ``cones``): their tree is built once per
  mesh; its tally (``hierarchy.build``) is kept apart from the per-light
  ``tallies``, which are the query's alone.  ``query_saving`` is the
  reference's ``true`` total minus the detector's (summed over the lights in
  the aggregate), ``break_even_lights`` the lights after which build plus
  queries cost fewer ``true`` operations than the reference's queries
  (``ceil(build / mean saving)``; null when a query saves nothing), and
  ``edges_visited_fraction`` the edges whose faces the query evaluated, over
  E (the mean over the lights in the aggregate).
* **Cycles**: tallies weighted by a cycle profile (``paper``: the EESD
  paper's Mult 4, Add 2, Compare 3, Read 1, Write 2, EESD 2012 Sec. 6); see
  :mod:`silcount.audit.costs`.
* **Refused runs** (``refused``, present only when some run was): a run
  whose work passes the limit (:class:`silcount.errors.TooMuchWork`,
  ``--max-work``) is left out of ``detectors`` and ``per_light`` and named
  here with its one-line reason; every other run is reported as usual.  The
  reference is never refused (its work is linear in the mesh).
* **Dubious input is audited, with warnings**: a light exactly on the plane
  of some faces (ties, not light-facing), a point light inside the mesh
  (generalised winding number above one half), an open, non-manifold,
  inconsistently wound mesh, degenerate or duplicate faces.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from silcount.audit.costs import cycle_profile, printed_formula, weighted
from silcount.counting.arithmetic import KINDS
from silcount.detectors import Silhouette, detect_many, differences, get, is_reference_run, names, runs
from silcount.errors import TooMuchWork
from silcount.mesh.lights import DirectionalLight, Light, PointLight, random_lights
from silcount.mesh.model import Mesh
from silcount.mesh.stats import mesh_statistics, mesh_warnings
from silcount.options import DEFAULT_LIGHT_COUNT, DEFAULT_SEED
from silcount.progress import progress
from silcount.version import __version__

SCHEMA = "silcount-audit/1"


@dataclass(frozen=True)
class AuditSettings:
    """What to run: detectors, variants (``intended``/``literal``), engine, cycle profile."""

    detectors: tuple[str, ...] = field(default_factory=names)  # every registered detector
    variants: tuple[str, ...] = ("intended",)
    engine: str = "fast"
    cycles: str = "paper"
    with_edges: bool = False
    with_time: bool = True
    # (detector, model): the printed closed form set beside a detector's measurement when it is not the
    # detector's own paper model, from a paper given with ``--paper DIR`` (docs/papers-as-data.md)
    formulas: tuple[tuple[str, str], ...] = ()


def winding_number(mesh: Mesh, point) -> float:
    """Generalised winding number of the faces (fan-triangulated) about ``point``.

    1 inside and 0 outside a closed outward-wound mesh; fractional on open
    ones.  Van Oosterom & Strackee's solid angle, summed over triangles.
    """
    fan = mesh.face_sizes - 2  # triangles per polygon
    first = np.repeat(mesh.face_start[:-1], fan)
    offs = np.arange(fan.sum()) - np.repeat(np.cumsum(fan) - fan, fan) + 1
    a = mesh.vertices[mesh.corners[first]] - point
    b = mesh.vertices[mesh.corners[first + offs]] - point
    c = mesh.vertices[mesh.corners[first + offs + 1]] - point
    la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    den = (
        la * lb * lc
        + np.einsum("ij,ij->i", a, b) * lc
        + np.einsum("ij,ij->i", b, c) * la
        + np.einsum("ij,ij->i", c, a) * lb
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        omega = 2.0 * np.arctan2(num, den)
    return float(np.nansum(omega) / (4.0 * np.pi))


def describe_light(light: Light) -> dict:
    if isinstance(light, DirectionalLight):
        return {"kind": "directional", "direction": list(light.direction)}
    return {"kind": "point", "position": list(light.position)}


def _light_checks(mesh: Mesh, light: Light, ties: int, index: int) -> tuple[dict, list[str]]:
    info = describe_light(light)
    info["ties"] = ties
    warnings = []
    if ties:
        warnings.append(f"light {index}: on the plane of {ties} faces (ties: not light-facing)")
    if isinstance(light, PointLight):
        w = winding_number(mesh, np.asarray(light.position))
        info["winding_number"] = w
        info["inside"] = bool(abs(w) > 0.5)
        if info["inside"]:
            warnings.append(f"light {index}: inside the mesh (winding number {w:.3g}): every face sees its back")
    return info, warnings


def missing_parts(settings: AuditSettings) -> list[str]:
    """One warning per requested detector that lacks a part this audit uses: the engine, the paper cost model."""
    out = []
    for name in settings.detectors:
        spec = get(name)
        if settings.engine not in spec.engines:
            out.append(f"detector {name}: no {settings.engine} engine, left out of this audit")
        elif spec.paper_model is None:
            out.append(f"detector {name}: no paper cost model, its paper columns are empty")
    return out


def _ratios(measured: dict[str, int], printed: dict[str, float], lights: int) -> dict[str, float | None]:
    return {k: (measured.get(k, 0) / (lights * v) if v else None) for k, v in printed.items()}


def _one_run(
    mesh: Mesh,
    name: str,
    variant: str,
    settings: AuditSettings,
    ref: Silhouette,
    profile: tuple[str, dict],
    res: Silhouette,
    elapsed: float,
) -> dict:
    """One run's entry of a light: ``res`` under the light, which took ``elapsed`` seconds."""
    diff = differences(res.edge_ids, ref.edge_ids)  # the audit's one reference run, for every detector
    missed, extra = diff["missed_edges"], diff["extra_edges"]
    tallies = {model: {k: int(v) for k, v in sorted(t.items(), key=_kind_order)} for model, t in res.tally.items()}
    out = {
        "detector": name,
        "variant": variant,
        "silhouette_edges": res.n_edges,
        "agrees_with_reference": missed == 0 and extra == 0,
        "missed_edges": missed,
        "extra_edges": extra,
        "tallies": tallies,
        "steps": dict(sorted(res.steps.items())),
        "cycles": {model: weighted(t, profile[1]) for model, t in tallies.items()},
        "formula_printed": printed_formula(name, mesh, res.notes, dict(settings.formulas).get(name)),
        "time_s": elapsed if settings.with_time else None,
    }
    _with_ratios(out, profile, 1)
    if "build" in res.notes:
        out["hierarchy"] = _hierarchy(res, ref, profile[1])
    if settings.with_edges:
        out["edges"] = mesh.vertices[res.edges].tolist()
    return out


def _hierarchy(res: Silhouette, ref: Silhouette, weights: dict) -> dict:
    """A hierarchy's build (kept apart from the query's tallies), its break-even and the edges it visited."""
    n = res.notes
    build = {k: int(v) for k, v in sorted((dict.fromkeys(KINDS, 0) | n["build"]).items(), key=_kind_order)}
    return {
        "leaf_size": int(n["leaf_size"]),
        "fanout": int(n["fanout"]),
        "tree_bytes": int(n["tree_bytes"]),
        "build": build,
        "build_steps": dict(sorted(n["build_steps"].items())),
        "build_cycles": weighted(build, weights),
        "edges_visited_fraction": float(n["edges_visited_fraction"]),
        "query_saving": sum(ref.true_tally.values()) - sum(res.true_tally.values()),
        "break_even_lights": n["break_even_lights"],
    }


def _aggregate_hierarchy(results: list[dict]) -> dict:
    """The build once (one tree per mesh), the savings summed, the visited fraction averaged over the lights."""
    out = dict(results[0]["hierarchy"])
    saving = sum(r["hierarchy"]["query_saving"] for r in results)
    total = sum(out["build"].values())
    out["edges_visited_fraction"] = sum(r["hierarchy"]["edges_visited_fraction"] for r in results) / len(results)
    out["query_saving"] = saving
    out["break_even_lights"] = -(-total * len(results) // saving) if saving > 0 else None
    return out


def _kind_order(item: tuple[str, int]) -> tuple[int, str]:
    k = item[0]
    return (KINDS.index(k) if k in KINDS else len(KINDS), k)


def _add_counts(total: dict[str, int], part: dict[str, int]) -> dict[str, int]:
    out = dict(total)
    for k, v in part.items():
        out[k] = out.get(k, 0) + v
    return dict(sorted(out.items(), key=_kind_order))


def _aggregate(results: list[dict], with_time: bool) -> dict:
    first = results[0]
    agg = {
        "detector": first["detector"],
        "variant": first["variant"],
        "silhouette_edges": sum(r["silhouette_edges"] for r in results),
        "agrees_with_reference": all(r["agrees_with_reference"] for r in results),
        "lights_agreeing": sum(r["agrees_with_reference"] for r in results),
        "missed_edges": sum(r["missed_edges"] for r in results),
        "extra_edges": sum(r["extra_edges"] for r in results),
        "tallies": {},
        "steps": {},
        "cycles": {},
        "formula_printed": first["formula_printed"]
        and {k: v for k, v in first["formula_printed"].items() if k not in ("ratio", "cycles_ratio")},
        "time_s": sum(r["time_s"] for r in results) if with_time else None,
    }
    for r in results:
        for model, t in r["tallies"].items():
            agg["tallies"][model] = _add_counts(agg["tallies"].get(model, {}), t)
            agg["cycles"][model] = agg["cycles"].get(model, 0) + r["cycles"][model]
        agg["steps"] = dict(sorted(_add_counts(agg["steps"], r["steps"]).items()))
    if "hierarchy" in first:
        agg["hierarchy"] = _aggregate_hierarchy(results)
    return agg


def _with_ratios(entry: dict, profile: tuple[str, dict], lights: int) -> None:
    """Put the printed formula's cycles and its ratios to the measured tallies (summed over ``lights``)."""
    printed = entry["formula_printed"]
    if printed is None:
        return
    printed["cycles"] = printed_cycles = weighted(printed["tally"], profile[1])
    printed["ratio"] = {model: _ratios(t, printed["tally"], lights) for model, t in entry["tallies"].items()}
    printed["cycles_ratio"] = {
        model: (c / (lights * printed_cycles) if printed_cycles else None) for model, c in entry["cycles"].items()
    }


def run_audit(
    mesh: Mesh,
    lights: list[Light],
    settings: AuditSettings | None = None,
    source: str | None = None,
    quiet: bool = False,
) -> dict:
    """Audit ``mesh`` under each light with each requested detector; see the module docstring."""
    if not lights:
        lights = random_lights(mesh, DEFAULT_LIGHT_COUNT, DEFAULT_SEED)
    settings = settings or AuditSettings()
    profile = cycle_profile(settings.cycles)
    stats = mesh_statistics(mesh)
    warnings = list(mesh.load_warnings) + mesh_warnings(stats) + missing_parts(settings)
    usable = [d for d in settings.detectors if settings.engine in get(d).engines]  # missing_parts says so
    todo = runs(usable, settings.variants)
    per_light = []
    with progress(len(lights) * (len(todo) + 1), f"audit {mesh.name}", enabled=None if not quiet else False) as bar:
        # every run under all the lights at once (detect_many: identical to detect per light), each light's
        # time its share of the pass; the reference first, always (a requested fast reference run is it)
        batches: dict[str, tuple[Sequence[Silhouette], float]] = {}
        refused: dict[str, str] = {}
        for key, name, variant in [("", "reference", "intended"), *todo]:
            if key and is_reference_run(name, settings.engine):
                batches[key] = batches[""]
                continue
            bar.set_postfix_str(key or "reference", refresh=False)
            engine = "fast" if not key else settings.engine
            t0 = time.perf_counter()
            try:
                got = detect_many(mesh, lights, name, variant, engine)
            except TooMuchWork as exc:
                if not key:
                    raise
                refused[key] = str(exc)
            else:
                batches[key] = (got, (time.perf_counter() - t0) / len(lights))
            bar.update(len(lights))
        done = [run for run in todo if run[0] not in refused]
        refs = batches[""][0]
        for i, (light, ref) in enumerate(zip(lights, refs, strict=True)):
            info, light_warnings = _light_checks(mesh, light, ref.ties, i)
            warnings += light_warnings
            results = {}
            for key, name, variant in done:
                res, share = batches[key]
                results[key] = _one_run(mesh, name, variant, settings, ref, profile, res[i], share)
            per_light.append({"light": info, "detectors": results})
    detectors = {}
    for key, _, _ in done:
        detectors[key] = _aggregate([pl["detectors"][key] for pl in per_light], settings.with_time)
        _with_ratios(detectors[key], profile, len(lights))
    return {
        "silcount_version": __version__,
        "schema": SCHEMA,
        "source": source or mesh.name,
        "mesh": stats,
        "settings": {
            "engine": settings.engine,
            "variants": list(settings.variants),
            "detectors": list(settings.detectors),
            "cycles": profile[0],
        },
        "lights": [pl["light"] for pl in per_light],
        "warnings": warnings,
        "detectors": detectors,
        "per_light": per_light,
    } | ({"refused": refused} if refused else {})
