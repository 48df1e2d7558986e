"""The measured generic kinds: a claim judged on silcount's own runs, never on the number the paper prints.

For papers silcount re-derives nothing of (the literature's published figures, ``examples/literature-paper/``):
the printed value is reported beside the measurement, and the verdict is the measurement's alone.  Meshes, lights
and quantities: :mod:`silcount.papers.measure`.  Each entry's fields (``docs/papers-as-data.md``):

* ``measured_comparison``: ``first`` does less than ``second`` on each of ``meshes``, for each of ``quantities``
  (a reading each; HOLDS when ``first``'s per-light mean is below ``second``'s);
* ``measured_log_ratio``: ``log q / log size`` of ``detector``'s ``quantity`` on ``mesh`` is ``exponent`` within
  ``tolerance`` (Gooch et al.'s "log s / log f"); or, where how close "about" asks is itself a reading, within
  each of ``readings`` (``name``, ``tolerance``) in turn;
* ``measured_growth``: ``quantity ~ a size**b`` with ``b`` about ``exponent`` (``relation = "about"``, within
  ``tolerance``) or at most it (``"at most"``), per reading: a series of ``meshes`` (``detector``'s runs) or a
  ``corpus`` fit of the corpus study (:func:`silcount.study.corpus`, over ``$SILCOUNT_CORPUS_DIR``);
* ``measured_big_oh``: ``detector``'s ``quantity`` over a series of ``meshes`` is O(``bound``), per reading a
  ``bound`` in ``E``, ``F`` and ``s`` (the silhouette): the fitted exponent of ``quantity / bound`` against
  ``against`` is at most ``tolerance``.
"""

from __future__ import annotations

import math
import os

from silcount.papers import measure as M
from silcount.papers.claims.base import Claim, Reading, judged_by_readings
from silcount.papers.claims.context import Evidence


def _folder(source: str) -> str:
    from silcount.papers import registry

    return str(registry.by_source(source).folder)


def _runs(c: dict, source: str, detector: str, meshes: list[str]) -> list[M.Measured]:
    return [M.measure(detector, spec, c.get("lights", 16), c.get("seed", 0), _folder(source)) for spec in meshes]


def measured_comparison(c: dict, source: str, ev: Evidence) -> Claim:
    readings, where = [], []
    for spec in c["meshes"]:
        first, second = (
            M.measure(d, spec, c.get("lights", 16), c.get("seed", 0), _folder(source))
            for d in (
                c["first"],
                c["second"],
            )
        )
        where.append(first.where)
        for q in c["quantities"]:
            a, b = first.value(q), second.value(q)
            ratio = f"{b / a:.3g}x" if a else "-"
            readings.append(
                Reading(
                    f"{M.LABEL[q]} per light on {spec}",
                    a < b,
                    f"{first.detector} {a:,.1f} against {second.detector} {b:,.1f} "
                    f"({second.detector}/{first.detector} {ratio})",
                )
            )
    return judged_by_readings(
        c,
        source,
        "measured comparison",
        readings,
        f"silcount's own runs on {'; '.join(where)}: {c['first']} against {c['second']}, fast engine, intended "
        "variant; the printed figures are not used.",
        rederived="",
        measured="; ".join(f"{r.reading}: {r.outcome}" for r in readings),
    )


def measured_log_ratio(c: dict, source: str, ev: Evidence) -> Claim:
    run = M.measure(c.get("detector", "reference"), c["mesh"], c.get("lights", 16), c.get("seed", 0), _folder(source))
    q, size = run.value(c["quantity"]), M.size_of(run, c.get("against", "F"))
    got = math.log(q) / math.log(size)
    ratio = f"log {c['quantity']} / log {c.get('against', 'F')}"
    tolerances = c.get("readings") or [{"name": ratio, "tolerance": c["tolerance"]}]
    readings = [
        Reading(
            r["name"],
            abs(got - c["exponent"]) <= r["tolerance"],
            f"{got:.3f} against {c['exponent']} +- {r['tolerance']}",
        )
        for r in tolerances
    ]
    return judged_by_readings(
        c,
        source,
        "measured ratio",
        readings,
        f"silcount's own runs on {run.where}: {M.LABEL[c['quantity']]} {q:,.1f} per light, {ratio} = {got:.3f} "
        f"against {c['exponent']} +- " + " or +- ".join(str(r["tolerance"]) for r in tolerances) + ".",
        rederived="",
        measured=f"{got:.3f} ({M.LABEL[c['quantity']]} {q:,.1f} per light on {run.where})",
        keep_one=False,
    )


def _series_fit(c: dict, source: str, r: dict) -> tuple[float, float, str]:
    """``(b, a, where)`` of a reading's series: its meshes' runs, or a fit of the corpus study."""
    if "corpus" in r:
        fit = M.corpus_fits(os.environ.get("SILCOUNT_CORPUS_DIR", ""))[r["corpus"]]
        lo, hi = fit["alpha_ci"]
        return fit["alpha"], fit["c"], f"corpus fit {r['corpus']}: {fit['meshes']} meshes, 95% CI [{lo:.3f}, {hi:.3f}]"
    runs = _runs(c, source, r.get("detector", "reference"), r["meshes"])
    against = c.get("against", "F")
    b, a = M.fit([M.size_of(m, against) for m in runs], [m.value(c["quantity"]) for m in runs])
    span = f"{against} = {M.size_of(runs[0], against):,.0f} .. {M.size_of(runs[-1], against):,.0f}"
    return b, a, f"{len(runs)} meshes ({', '.join(r['meshes'])}; {span})"


def measured_growth(c: dict, source: str, ev: Evidence) -> Claim:
    want, tol, relation = c["exponent"], c["tolerance"], c.get("relation", "about")
    if relation not in ("about", "at most"):
        raise ValueError(f"{c['id']}: relation {relation!r}; choose from about, at most")
    readings = []
    for r in c["readings"]:
        b, a, where = _series_fit(c, source, r)
        holds = abs(b - want) <= tol if relation == "about" else b <= want + tol
        if holds and "coefficient" in c:
            holds = abs(math.log(a / c["coefficient"])) <= math.log(c.get("coefficient_factor", 2.0))
        label = M.LABEL.get(c["quantity"], c["quantity"])
        size = c.get("against", "F")
        size = f"({size})" if " " in size else size
        readings.append(Reading(r["name"], holds, f"{label} ~ {a:.3g} {size}^{b:.3f}, {where}"))
    bound = f"{want} +- {tol}" if relation == "about" else f"at most {want} + {tol}"
    if "coefficient" in c:
        bound += f", coefficient {c['coefficient']} within a factor {c.get('coefficient_factor', 2.0)}"
    return judged_by_readings(
        c,
        source,
        "measured growth",
        readings,
        f"silcount's own fits (least squares in log-log); the exponent judged: {bound}.",
        rederived="",
        measured="; ".join(f"{r.reading}: {r.outcome}" for r in readings),
    )


def _bound_values(bound: str, runs: list[M.Measured]) -> list[float]:
    import sympy as sp

    E, F, s = sp.symbols("E F s", positive=True)
    fn = sp.lambdify((E, F, s), sp.sympify(bound, locals={"E": E, "F": F, "s": s}))
    return [float(fn(m.edges, m.faces, m.silhouette)) for m in runs]


def measured_big_oh(c: dict, source: str, ev: Evidence) -> Claim:
    runs = _runs(c, source, c["detector"], c["meshes"])
    against = c.get("against", "E")
    sizes = [M.size_of(m, against) for m in runs]
    readings = []
    for r in c["readings"]:
        per = [m.value(c["quantity"]) / v for m, v in zip(runs, _bound_values(r["bound"], runs), strict=True)]
        b, _ = M.fit(sizes, per)
        readings.append(
            Reading(
                r["name"],
                b <= c["tolerance"],
                f"{c['quantity']} / ({r['bound']}) ~ {against}^{b:.3f} ({per[0]:.3g} .. {per[-1]:.3g})",
            )
        )
    span = f"{against} = {sizes[0]:,.0f} .. {sizes[-1]:,.0f}"
    return judged_by_readings(
        c,
        source,
        "measured O()",
        readings,
        f"silcount's own runs of {c['detector']} on {len(runs)} meshes ({span}): a bound holds when "
        f"{M.LABEL[c['quantity']]} over it grows as {against}^b with b <= {c['tolerance']}.",
        rederived="",
        measured="; ".join(f"{r.reading}: {r.outcome}" for r in readings),
    )


RULES = {
    "measured_comparison": measured_comparison,
    "measured_log_ratio": measured_log_ratio,
    "measured_growth": measured_growth,
    "measured_big_oh": measured_big_oh,
}
