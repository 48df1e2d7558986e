"""A worst-case row per detector: the typical exponent beside the worst family found, and the worst work per output.

For each registered detector: the exponent of its total true operations on the icosphere series (as built,
the default light of :class:`.space.Genome`: the typical growth), beside the fastest family the search finds
(:func:`.goals.family`); for the output-sensitive detectors (those counting a ``node_test`` step: gaussmap,
cones) also the largest fraction of the edges ``E`` they test (:func:`.goals.per_output`, open and defective
meshes included), with the mesh and light that cause it.  ``silcount report`` writes the rows into
``reports/worst-case/`` with a small budget; ``benchmarks/worst_case.py`` with a larger one.
"""

from __future__ import annotations

from silcount.detectors import detect
from silcount.detectors.registry import specs
from silcount.study.fits import power_fit
from silcount.worstcase.goals import family, per_output
from silcount.worstcase.objective import Measure
from silcount.worstcase.space import Genome, build

TYPICAL_LEVELS = range(2, 7)  # icospheres of 80 .. 20,480 faces


def typical(detector: str) -> float | None:
    """Total true operations against faces on the icosphere series (as built, the default light)."""
    faces, costs = [], []
    for level in TYPICAL_LEVELS:
        mesh, light = build(Genome(shape="icosphere", level=level))
        run = detect(mesh, light, detector, engine="fast")
        faces.append(mesh.n_faces)
        costs.append(sum(run.tally["true"].values()))
    return power_fit(faces, costs)["alpha"]


def row(detector: str, budget: int, seed: int = 0, grow: int = 3) -> dict:
    """One detector's row (see the module docstring), each search with ``budget`` evaluations."""
    fam = family(Measure(detector), seed=seed, budget=budget, grow=grow)
    n = fam.numbers
    out = {
        "detector": detector,
        "typical": typical(detector),
        "worst": n.get("alpha"),
        "worst_ci": n.get("ci"),
        "worst_class": n.get("class"),
        "worst_rule": n.get("rule", ""),
        "budget": budget,
    }
    probe = detect(*build(Genome(shape="icosphere", level=1)), detector, engine="fast")
    if "node_test" in probe.steps:
        po = per_output(Measure(detector), seed=seed, budget=budget, closed_only=False)
        m = po.numbers
        out |= {
            "worst_fraction_of_E": m.get("fraction_of_E"),
            "edges_per_output": m.get("edges_per_output"),
            "nodes_per_output": m.get("nodes_per_output"),
            "mesh_and_light": f"{po.genome.rule()}, level={po.genome.level}; {m.get('light')}" if po.genome else "",
        }
    return out


def rows(budget: int, seed: int = 0, grow: int = 3) -> list[dict]:
    return [row(spec.name, budget, seed, grow) for spec in specs()]


def markdown(table: list[dict]) -> str:
    lines = [
        "| detector | typical exponent | worst exponent found [95 % CI] | its class (Akaike weight) | worst family "
        "| worst fraction of E tested | edges / nodes tested per silhouette edge | mesh and light |",
        "|---|---:|---:|---|---|---:|---:|---|",
    ]
    for r in table:
        ci = r["worst_ci"]
        worst = (
            f"{r['worst']:.3f} [{ci[0]:.3f}, {ci[1]:.3f}]" if r["worst"] is not None and ci else "none over 2 decades"
        )
        typ = f"{r['typical']:.3f}" if r["typical"] is not None else "-"
        frac = f"{r['worst_fraction_of_E']:.3f}" if r.get("worst_fraction_of_E") is not None else ""
        per = (
            f"{r['edges_per_output']:.2f} / {r['nodes_per_output']:.2f}"
            if r.get("edges_per_output") is not None
            else ""
        )
        where = r.get("mesh_and_light", "")
        c = r.get("worst_class")
        cls = f"{c['chosen']} ({c['weight']:.2f}; runner-up {c['runner_up']})" if c else ""
        lines.append(f"| {r['detector']} | {typ} | {worst} | {cls} | {r['worst_rule']} | {frac} | {per} | {where} |")
    return "\n".join(lines) + "\n"
