"""Comparisons between algorithms: per pair and table point, the asymptotic orderings, cycle ratios, equal counts.

Judged on the papers'-convention re-derivation (:func:`silcount.papers.formulas.convention`)
with the paper's cycle weights (EESD paper Sec. 6: Mult 4, Add 2, Compare 3,
Read 1, Write 2) and, as separate claims, as raw operation counts; the
printed closed forms are reported beside.  Where the outcome depends on m,
the threshold is given.  Every model reading (HSD's side loop) is a reading
of the claim, and so is every reading of a primitive the comparison charges
where those readings disagree on the annotated cost (a step's ``primitive``
in models/: the edge inverse, 1 Mult or none; EESD's intersection test, the
plane equation or a ray crossing), each charged the arithmetic its
computation executes (:func:`silcount.papers.primitives.kernel_cost`; reads and
writes as annotated): no verdict rests on a reading called AMBIGUOUS elsewhere
(docs/claims.md, rules 5 and 13).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cache

import sympy as sp

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.papers import formulas as F
from silcount.papers import primitives
from silcount.papers.claims.base import (
    Claim,
    Reading,
    algo,
    cycles,
    judged_by_readings,
    num,
    paper_weights,
    show_readings,
    unit_weights,
)
from silcount.papers.claims.context import Evidence

WEIGHTS = "the EESD paper's cycle weights"  # Sec. 6 (Mult 4, Add 2, Compare 3, Read 1, Write 2); HSD 2011 gives none
SCALES = {"cycles": (WEIGHTS, paper_weights), "raw": ("raw operation counts", unit_weights)}


@dataclass(frozen=True)
class ModelReading:
    """One model's reading in a comparison: its loop bounds' reading and the steps charged a primitive's cost."""

    loop: str = ""
    overrides: F.Override = ()


def _primitive_entry(key: str) -> dict:
    from silcount.papers import registry

    names = registry.claim_files()
    for name in names:
        for c in models.load(name).get("claims", []):
            if c["id"] == key:
                return c
    raise KeyError(f"no claim {key!r} in {', '.join(names)}")


@cache
def _contested(model: str) -> dict[str, tuple[str, tuple[tuple[str, str], ...]]]:
    """The primitives of ``model``'s steps whose computations disagree on the annotated arithmetic (some give it,
    some not): claim -> (label, its (kernel, name) pairs).  A step's ``primitive`` names its ``claim`` (whose
    ``kernels`` are the computations), a ``label`` and the ``cost`` it annotates within the step;
    ``primitive_names`` names the computations for the readings (else the kernels' descriptions)."""
    out = {}
    for spec in F.steps(model).values():
        prim = spec.get("primitive")
        if prim:
            annotated = {k: int(v) for k, v in prim["cost"].items() if int(v)}
            kernels = tuple(_primitive_entry(prim["claim"])["kernels"])
            if len({primitives.kernel_cost(k) == annotated for k in kernels}) == 2:
                names = spec.get("primitive_names", {})
                named = tuple((k, names.get(k, primitives.KERNELS[k][1])) for k in kernels)
                out[prim["claim"]] = (prim["label"], named)
    return out


def _overrides(model: str, chosen: dict[str, str]) -> F.Override:
    """``model``'s steps whose primitive has a chosen computation, each charged its cost instead of the part of
    the annotation the primitive names (reads and writes as annotated)."""
    out = []
    for step, spec in F.steps(model).items():
        prim = spec.get("primitive")
        if prim and prim["claim"] in chosen:
            total = {k: F.parse(v) for k, v in spec["cost"].items()}
            for k, v in prim["cost"].items():
                total[k] -= F.parse(v)
            for k, v in primitives.kernel_cost(chosen[prim["claim"]]).items():
                total[k] = total.get(k, 0) + v
            out.append((step, tuple(sorted((k, str(v)) for k, v in total.items() if v != 0))))
    return tuple(out)


def readings_of(*model_list: str, kinds: tuple[str, ...] = KINDS):
    """(name, one ModelReading per model) for every reading of the comparison: each model's loop readings, times
    each contested primitive's computations, one computation per primitive for all the models that use it
    (a primitive whose computations differ in none of the compared ``kinds`` changes nothing, and is left out)."""
    contested: dict[str, tuple[str, tuple[tuple[str, str], ...]]] = {}
    for mdl in model_list:
        for claim, (label, named) in _contested(mdl).items():
            costs = [primitives.kernel_cost(k) for k, _ in named]
            if any(len({cost.get(kind, 0) for cost in costs}) > 1 for kind in kinds):
                contested[claim] = (label, named)
    for loops in itertools.product(*(F.readings(mdl) for mdl in model_list)):
        for picks in itertools.product(*(k for _, k in contested.values())):
            chosen = {claim: kernel for claim, (kernel, _) in zip(contested, picks)}
            labels = [label for label, _ in contested.values()]
            names = [r for r in loops if r] + [f"{label} as {name}" for label, (_, name) in zip(labels, picks)]
            yield ", ".join(names), tuple(ModelReading(r, _overrides(mdl, chosen)) for mdl, r in zip(model_list, loops))


def convention_form(model: str, r: ModelReading) -> F.Form:
    """The papers'-convention sum of ``model`` under reading ``r``, in n and m."""
    return F.in_n(F.convention(model, r.loop, r.overrides), model)


def cycles_under(model: str, r: ModelReading, weights: tuple) -> sp.Expr:
    """The cycle total (sympy, in n and m) of ``model``'s papers'-convention sum under reading ``r``."""
    return F.weighted(convention_form(model, r), dict(weights))


def _value(model: str, reading: ModelReading, weights: tuple, point: dict):
    return sp.nsimplify(cycles_under(model, reading, weights).subs({F.n: point["n"], F.m: point["m"]}))


def _printed_value(model: str, weights: tuple, point: dict):
    return sp.nsimplify(cycles(model, "printed", weights).subs({F.n: point["n"], F.m: point["m"]}))


def _threshold(diff: sp.Expr, var: sp.Symbol, what: str) -> str:
    """Where ``diff < 0`` (the winner cheaper), as an inequality in ``var``."""
    diff = sp.expand(diff)
    if not diff.has(var):
        return f"for every {var}" if diff < 0 else f"for no {var}"
    roots = [r for r in sp.solve(sp.Eq(diff, 0), var) if r.is_real and r > 0]
    if not roots:
        return f"for every {var} > 0" if diff.subs(var, 1) < 0 else f"for no {var} > 0"
    r = roots[0]
    below = diff.subs(var, r / 2) < 0
    return f"{what} for {var} {'<' if below else '>'} {float(r):.4g}"


def pairwise(c: dict, source: str, ev: Evidence) -> list[Claim]:
    """``winner`` cheaper than ``other`` at each of ``points``, with cycle weights and as raw counts."""
    winner, other = c["winner"], c["other"]
    out = []
    for point, (scale, (label, weights_of)) in itertools.product(c["points"], SCALES.items()):
        w = weights_of()
        readings = []
        for name, (rw, ro) in readings_of(winner, other):
            a, b = _value(winner, rw, w, point), _value(other, ro, w, point)
            at_n = cycles_under(winner, rw, w).subs(F.n, point["n"]) - cycles_under(other, ro, w).subs(F.n, point["n"])
            readings.append(
                Reading(
                    name or "as printed",
                    bool(a < b),
                    f"{algo(winner)} {num(a)} vs {algo(other)} {num(b)}; at n = {point['n']}: "
                    + _threshold(at_n, F.m, f"{algo(winner)} cheaper"),
                )
            )
        pa, pb = (_printed_value(mdl, w, point) for mdl in (winner, other))
        out.append(
            judged_by_readings(
                c,
                source,
                "comparison",
                readings,
                f"{label}, papers'-convention re-derivation; the printed closed forms give "
                f"{algo(winner)} {num(pa)} vs {algo(other)} {num(pb)}.",
                rederived=show_readings(readings) if len(readings) > 1 else readings[0].outcome,
                keep_one=False,
            )
        )
        out[-1].key = f"{c['id']} n={point['n']} m={point['m']} {scale}"
        out[-1].statement = f"{c['statement']} at n={point['n']}, m={point['m']} ({label})"
    return out


def cycle_ratio(c: dict, source: str, ev: Evidence) -> Claim:
    """``numerator / denominator`` cycles equal ``ratio`` (within ``tolerance``) at ``faces`` faces."""
    w = paper_weights()
    readings = []
    for mv in c["m_values"]:
        for name, (rn, rd) in readings_of(c["numerator"], c["denominator"]):
            num_, den = (cycles_under(mdl, r, w) for mdl, r in ((c["numerator"], rn), (c["denominator"], rd)))
            at = float((num_ / den).subs({F.n: c["faces"], F.m: mv}))
            limit = sp.limit(num_ / den, F.n, sp.oo)
            solve = [x for x in sp.solve(sp.Eq(limit, c["ratio"]), F.m) if x.is_real] if limit.has(F.m) else []
            readings.append(
                Reading(
                    f"m = {mv}" + (f", {name}" if name else ""),
                    abs(at - c["ratio"]) <= c["tolerance"] * c["ratio"],
                    f"ratio {at:.3f} at n = {c['faces']}; limit {sp.sstr(limit)}"
                    + (
                        f", equal to {c['ratio']} only at m = {', '.join(f'{float(x):.4g}' for x in solve)}"
                        if solve
                        else ""
                    ),
                )
            )
    raw = [
        float(
            (
                cycles(c["numerator"], "printed", unit_weights()) / cycles(c["denominator"], "printed", unit_weights())
            ).subs({F.n: c["faces"], F.m: mv})
        )
        for mv in c["m_values"]
    ]
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"{WEIGHTS}, papers'-convention sums; {c['tolerance_note']} Raw counts of the printed forms: "
        + ", ".join(f"m={mv}: {r:.3f}" for mv, r in zip(c["m_values"], raw))
        + ".",
    )


def joint_ratio(c: dict, source: str, ev: Evidence) -> Claim:
    """Two cycle-ratio claims of one sentence, judged together under each reading."""
    parts = [cycle_ratio({**c, **sub, "id": c["id"], "quote": c["quote"]}, source, ev) for sub in c["ratios"]]
    readings = []
    by_name = [{r.reading: r for r in p.readings} for p in parts[1:]]
    if any(set(named) != {r.reading for r in parts[0].readings} for named in by_name):
        raise ValueError(f"{c['id']}: the sentence's ratios are not read alike")
    for r in parts[0].readings:
        others = [named[r.reading] for named in by_name]  # one reading of the sentence for all its ratios
        readings.append(
            Reading(r.reading, r.holds and all(o.holds for o in others), "; ".join(x.outcome for x in [r, *others]))
        )
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"both ratios of the sentence must hold under one reading; {WEIGHTS}.",
    )


def equal_kinds(c: dict, source: str, ev: Evidence) -> Claim:
    """The models' counts of ``kinds`` are equal at ``point``."""
    readings = []
    for name, combo in readings_of(*c["models"], kinds=tuple(c["kinds"])):
        vals = {
            kind: [F.evaluate(convention_form(mdl, r), **c["point"])[kind] for mdl, r in zip(c["models"], combo)]
            for kind in c["kinds"]
        }
        ok = all(len(set(v)) == 1 for v in vals.values())
        outcome = "; ".join(
            f"{kind}: " + ", ".join(f"{algo(mdl)} {num(x)}" for mdl, x in zip(c["models"], v))
            for kind, v in vals.items()
        )
        readings.append(Reading(name or "as printed", ok, outcome))
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"papers'-convention counts at n={c['point']['n']}, m={c['point']['m']} (Fig. 6's point).",
        rederived=show_readings(readings) if len(readings) > 1 else readings[0].outcome,
        keep_one=False,
    )


def differ_kinds(c: dict, source: str, ev: Evidence) -> Claim:
    """Two models' counts of ``kind`` differ ("more different is in number of ...") at ``point``: once as any
    difference, once as a difference beyond ``negligible`` (relative to the larger count, ``negligible_note``)."""
    (a, b), kind, point = c["models"], c["kind"], c["point"]
    readings = []
    for name, (ra, rb) in readings_of(a, b, kinds=(kind,)):
        x, y = (F.evaluate(convention_form(mdl, r), **point)[kind] for mdl, r in ((a, ra), (b, rb)))
        rel = abs(x - y) / max(abs(x), abs(y), 1)
        shown = f"{algo(a)} {num(x)}, {algo(b)} {num(y)} (differ by {float(rel):.2%})"
        for how, ok in (
            ("any difference", x != y),
            (f"a difference beyond {c['negligible']:.0%}", rel > c["negligible"]),
        ):
            readings.append(Reading(", ".join(r for r in (name, how) if r), bool(ok), shown))
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"papers'-convention {kind} counts at n={point['n']}, m={point['m']} (Fig. 6's point); " + c["negligible_note"],
    )


RULES = {
    "pairwise": pairwise,
    "differ_kinds": differ_kinds,
    "cycle_ratio": cycle_ratio,
    "joint_ratio": joint_ratio,
    "equal_kinds": equal_kinds,
}
