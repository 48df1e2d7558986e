"""The three goals of the worst-case search: exceed a bound, the fastest-growing family, the worst work per output.

* :func:`exceed`: an execution whose cost exceeds a bound at the mesh's own parameters (the upper-bound check,
  ``docs/claims.md`` rule 7), shrunk to the smallest mesh of the generators that still exceeds it;
* :func:`family`: rules (a genome without its level) searched by their local exponent at small sizes,
  the best grown over at least two decades of faces and fitted (:func:`silcount.study.fits.power_fit`, exponent,
  95 % bootstrap interval and complexity class), as Singularity (FSE 2018) grows input patterns;
* :func:`per_output`: for output-sensitive detectors (``gaussmap``, ``cones``), the largest fraction of the
  edges ``E`` tested (``edge_test / E``, the reference scan tests all ``E``), with nodes and edges tested per
  silhouette edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from silcount.study.fits import power_fit
from silcount.worstcase.objective import Bound, Measure, excess
from silcount.worstcase.search import Evaluator, Scored, is_closed, run_search, shrink
from silcount.worstcase.space import MAX_LEVEL, Genome, build

MIN_FACES = 64  # the smallest mesh of a family's fit
LOCAL_FACES = 1_000  # a rule's local exponent: between its levels of MIN_FACES .. LOCAL_FACES faces
MAX_FACES = 40_000  # the largest mesh a family is grown to
GROW = 3  # rules grown and fitted after the search
PER_OUTPUT_MIN_FACES = 500  # per-output: smaller meshes are one or two leaves, every edge tested by construction
PER_OUTPUT_LEVELS = 9  # per-output: the levels searched (up to 6,144 faces on a 3,072-gon prism)


@dataclass
class Outcome:
    """What one search found: the goal, whether it was met, the witness genome and its numbers."""

    goal: str
    measure: str
    method: str
    seed: int
    budget: int
    evaluations: int
    infeasible: int
    found: bool
    genome: Genome | None
    numbers: dict = field(default_factory=dict)
    rows: list = field(default_factory=list)  # family: one row per grown rule; exceed: the witness's kinds

    def summary(self) -> dict:
        from dataclasses import asdict

        out = asdict(self)
        out["genome"] = None if self.genome is None else asdict(self.genome)
        return out


def _run_all(measure: Measure, g: Genome, closed_only: bool):
    """The genome's mesh and light, and its dearest run over the measure's variants, or ``None`` if the mesh
    is outside the allowed space (a closed mesh required and this one open)."""
    if closed_only and not is_closed(g):
        return None
    mesh, light = build(g)
    if closed_only and not mesh.is_watertight:
        return None
    runs = [(v, measure.run(mesh, light, v)) for v in measure.variants]
    return mesh, light, runs


def exceed(
    measure: Measure,
    bound: Bound,
    *,
    seed: int = 0,
    budget: int = 400,
    method: str = "evolve",
    closed_only: bool = True,
    tick=None,
) -> Outcome:
    """Search for an execution whose cost exceeds ``bound``; shrink it with what is left of the budget."""

    def score(g: Genome) -> Scored | None:
        got = _run_all(measure, g, closed_only)
        if got is None:
            return None
        mesh, _, runs = got
        best = None
        for variant, run in runs:
            tally = measure.tally(run)
            at = bound.at(run.paper_params)
            ratio, over = excess(measure, tally, at)
            cand = (ratio, variant, tally, at, over, dict(run.paper_params))
            if best is None or ratio > best[0]:
                best = cand
        assert best is not None
        ratio, variant, tally, at, over, params = best
        detail = {"variant": variant, "cost": tally, "bound": at, "over": over, "params": params}
        return Scored(g, ratio, bool(over), mesh.n_faces, detail)

    ev = Evaluator(score, budget, closed_only, tick=tick)
    ranked = run_search(ev, method, seed, closed_only)
    best = ranked[0] if ranked else None
    if best is not None and best.met:
        best = shrink(ev, best)
    found = best is not None and best.met
    numbers = {}
    if best is not None:  # a zero bound exceeded: no finite ratio (JSON has no infinity)
        numbers = {"ratio": best.score if math.isfinite(best.score) else None, "faces": best.faces, **best.detail}
    return Outcome(
        "exceed",
        measure.describe() + f" against {bound.text}",
        method,
        seed,
        budget,
        ev.evaluations,
        ev.infeasible,
        found,
        best.genome if found and best is not None else None,
        numbers,
    )


def _series(g: Genome, closed_only: bool, measure: Measure, stop: int = MAX_FACES):
    """(faces, cost) of ``g`` at each level from the first of at least :data:`MIN_FACES` faces up to ``stop``
    faces (tiny meshes are left out: their lower-order terms bend the fit)."""
    for level in range(1, MAX_LEVEL + 1):
        got = _run_all(measure, g.at_level(level), closed_only)
        if got is None:
            return
        mesh, _, runs = got
        if mesh.n_faces > stop:
            return
        if mesh.n_faces >= MIN_FACES:
            yield mesh.n_faces, max(measure.value(measure.tally(r)) for _, r in runs)


def family(
    measure: Measure,
    *,
    seed: int = 0,
    budget: int = 200,
    method: str = "evolve",
    closed_only: bool = True,
    tick=None,
    grow: int = GROW,
) -> Outcome:
    """Search rules by their local exponent between the first two levels of at least :data:`MIN_FACES` and
    :data:`LOCAL_FACES` faces, grow the best ``grow`` distinct rules over every level up to :data:`MAX_FACES`
    faces and fit each; the fastest fit over at least two decades wins."""

    def score(g: Genome) -> Scored | None:
        g = g.at_level(1)
        points = list(_series(g, closed_only, measure, stop=LOCAL_FACES))
        if len(points) < 2:
            return None
        (f1, c1), (f2, c2) = points[0], points[-1]
        if f2 <= f1 or c1 <= 0 or c2 <= 0:
            return None
        return Scored(g, math.log(c2 / c1) / math.log(f2 / f1), False, f1)

    ev = Evaluator(score, budget, closed_only, tick=tick)
    ranked = run_search(ev, method, seed, closed_only, max_level=1)
    rows: list[dict] = []
    seen = set()
    for s in ranked:
        rule = s.genome.rule()
        if rule in seen or not math.isfinite(s.score):
            continue
        seen.add(rule)
        series = list(_series(s.genome, closed_only, measure))
        fit = power_fit([f for f, _ in series], [c for _, c in series])
        decades = math.log10(series[-1][0] / series[0][0]) if len(series) > 1 else 0.0
        rows.append(
            {
                "rule": rule,
                "genome": s.genome,
                "local": s.score,
                "alpha": fit["alpha"],
                "ci": fit["alpha_ci"],
                "class": fit["classes"],
                "faces": [f for f, _ in series],
                "costs": [c for _, c in series],
                "decades": decades,
            }
        )
        if len(rows) == grow:
            break
    valid = [r for r in rows if r["alpha"] is not None and r["decades"] >= 2.0]
    best = max(valid, key=lambda r: r["alpha"]) if valid else None
    numbers = (
        {}
        if best is None
        else {k: best[k] for k in ("rule", "alpha", "ci", "class", "faces", "costs", "decades", "local")}
    )
    return Outcome(
        "family",
        measure.describe(),
        method,
        seed,
        budget,
        ev.evaluations,
        ev.infeasible,
        best is not None,
        None if best is None else best["genome"],
        numbers,
        rows,
    )


def per_output(
    measure: Measure, *, seed: int = 0, budget: int = 200, method: str = "evolve", closed_only: bool = True, tick=None
) -> Outcome:
    """Search for the largest fraction of the edges an output-sensitive detector tests (``edge_test / E``), on
    meshes of at least :data:`PER_OUTPUT_MIN_FACES` faces (a mesh of one or two leaves is all tested)."""

    def score(g: Genome) -> Scored | None:
        got = _run_all(measure, g, closed_only)
        if got is None:
            return None
        mesh, light, runs = got
        if mesh.n_faces < PER_OUTPUT_MIN_FACES:
            return None
        _, run = runs[0]
        if "edge_test" not in run.steps:
            from silcount.errors import BadArgument

            raise BadArgument(f"detector {measure.detector!r} counts no 'edge_test' step: no work per output")
        k = max(run.n_edges, 1)
        detail = {
            "edges": mesh.n_edges,
            "silhouette_edges": run.n_edges,
            "edges_tested": run.steps["edge_test"],
            "nodes_tested": run.steps.get("node_test", 0),
            "edges_per_output": run.steps["edge_test"] / k,
            "nodes_per_output": run.steps.get("node_test", 0) / k,
            "light": light.describe(),
        }
        return Scored(g, run.steps["edge_test"] / mesh.n_edges, False, mesh.n_faces, detail)

    ev = Evaluator(score, budget, closed_only, tick=tick)
    ranked = run_search(ev, method, seed, closed_only, max_level=PER_OUTPUT_LEVELS)
    best = ranked[0] if ranked and math.isfinite(ranked[0].score) else None
    numbers = {} if best is None else {"fraction_of_E": best.score, "faces": best.faces, **best.detail}
    return Outcome(
        "per-output",
        measure.describe(),
        method,
        seed,
        budget,
        ev.evaluations,
        ev.infeasible,
        best is not None,
        None if best is None else best.genome,
        numbers,
    )
