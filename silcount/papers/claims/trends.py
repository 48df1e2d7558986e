"""Comparisons as the sizes grow: the leading terms as n grows, a lead between two table points or as m grows,
and a cost the papers call common to the algorithms.

EESD paper Sec. 1 and 6 ("with increasing of the n and m the result will be more obvious"), Sec. 5 ("calculation
of equation of all planes" the same for all three); HSD paper Sec. VII ("when the number of faces increases the
HSD will have better result", "number of edge in each face increased the speed of HSD ... increased").  Judged on
the papers'-convention sums under every reading :func:`.comparisons.readings_of` gives (docs/claims.md, rule 8).
"""

from __future__ import annotations

import sympy as sp

from silcount.papers import formulas as F
from silcount.papers.claims.base import Claim, Reading, algo, judged_by_readings, num, paper_weights
from silcount.papers.claims.comparisons import (
    SCALES,
    WEIGHTS,
    ModelReading,
    _primitive_entry,
    _threshold,
    _value,
    cycles_under,
    readings_of,
)
from silcount.papers.claims.context import Evidence


def _leading(model: str, reading: ModelReading, weights: tuple) -> sp.Expr:
    return sp.expand(F.leading(cycles_under(model, reading, weights)) / F.n**2)


def fewest_asymptotic(c: dict, source: str, ev: Evidence) -> Claim:
    """``winner`` has the smallest leading cycle term as n grows, at each m of ``m_values``; with
    ``advantage_points`` (the two figures the sentence compares), also read as the winner's lead growing from the
    first point to the second: each other's cycles over the winner's larger at the second."""
    w = paper_weights()
    readings = _advantage_readings(c, w) if "advantage_points" in c else []
    for mv in c["m_values"]:
        for name, combo in readings_of(c["winner"], *c["others"]):
            lw = _leading(c["winner"], combo[0], w)
            parts, ok = [], True
            for other, ro in zip(c["others"], combo[1:]):
                lo = _leading(other, ro, w)
                ok &= bool((lw - lo).subs(F.m, mv) < 0)
                parts.append(
                    f"vs {algo(other)} ({sp.sstr(lo)}) n^2: " + _threshold(lw - lo, F.m, f"{algo(c['winner'])} fewer")
                )
            readings.append(
                Reading(f"m = {mv}" + (f", {name}" if name else ""), ok, f"({sp.sstr(lw)}) n^2; " + "; ".join(parts))
            )
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"leading cycle terms ({WEIGHTS}) of the papers'-convention sums as n grows. " + c.get("m_note", ""),
    )


def _leads(c: dict, combo: tuple, w: tuple, first: dict, second: dict) -> list[tuple[str, sp.Expr, sp.Expr]]:
    """(other, its cost over the winner's at ``first``, at ``second``) for each of ``others``, under ``combo``."""
    own = [_value(c["winner"], combo[0], w, p) for p in (first, second)]
    return [
        (other, *(_value(other, ro, w, p) / v for p, v in zip((first, second), own)))
        for other, ro in zip(c["others"], combo[1:])
    ]


def _lead_grows(a: sp.Expr, b: sp.Expr) -> bool:
    """A lead that grows, with the winner ahead (a lead above 1) at the end."""
    return bool(b > a and b > 1)


def _advantage_readings(c: dict, w: tuple, scale: str = "") -> list[Reading]:
    """The winner's lead over each other (their cost over its own) at the two ``advantage_points``: a reading
    holds when every lead grows and the winner is ahead (a lead above 1) at the second point."""
    first, second = c["advantage_points"]
    out = []
    for name, combo in readings_of(c["winner"], *c["others"]):
        ratios = [(other, (a, b)) for other, a, b in _leads(c, combo, w, first, second)]
        grows = all(_lead_grows(a, b) for _, (a, b) in ratios)
        shown = "; ".join(
            f"{algo(other)} / {algo(c['winner'])} {float(a):.3f} at (n={first['n']}, m={first['m']}) -> "
            f"{float(b):.3f} at (n={second['n']}, m={second['m']})"
            for other, (a, b) in ratios
        )
        tag = ", ".join(x for x in (scale, name) if x)
        out.append(Reading(f"{c['advantage_note']}" + (f", {tag}" if tag else ""), grows, shown))
    return out


def advantage_grows(c: dict, source: str, ev: Evidence) -> Claim:
    """``winner``'s lead over each of ``others`` (their cost over its own) grows from the first of
    ``advantage_points`` to the second and ends above 1, under every reading (:func:`readings_of`), with cycle
    weights and as raw counts."""
    readings = [r for label, weights_of in SCALES.values() for r in _advantage_readings(c, weights_of(), label)]
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"papers'-convention sums at the two points, {WEIGHTS} and raw counts; {c['advantage_note']}, read as "
        f"{algo(c['winner'])} ahead of each other at the second point by a larger factor than at the first.",
    )


def common_cost(c: dict, source: str, ev: Evidence) -> Claim:
    """A cost the paper calls the same for ``charged``'s models: read as charged alike by their sums (``charged``
    maps a model to the step whose annotation includes it, ``""`` for none; ``cost_of`` names the claim that
    prices it; evaluated at ``point`` with the paper's substitutions), and as needed alike by the algorithms
    (``needed_note``: why each needs it)."""
    cost = sum(int(v) for v in _primitive_entry(c["cost_of"])["cost"].values())
    parts, totals = [], []
    for model, step in c["charged"].items():
        runs = sp.Integer(0) if not step else F.step_runs(model, step)[0]
        at = int(sp.nsimplify(runs.subs(F.substitutions(model)).subs({F.n: c["point"]["n"], F.m: c["point"]["m"]})))
        totals.append(at * cost)
        parts.append(
            f"{algo(model)}: {at * cost} operations ("
            + (f"{step}, {sp.sstr(runs)} runs x {cost}" if step else "charged nowhere")
            + ")"
        )
    readings = [
        Reading(
            "charged alike by the three sums",
            len(set(totals)) == 1,
            f"at n={c['point']['n']}, m={c['point']['m']}: " + "; ".join(parts),
        ),
        Reading("needed alike by the three algorithms", True, c["needed_note"]),
    ]
    return judged_by_readings(c, source, "comparison", readings, c["reason_note"])


def grows_with_m(c: dict, source: str, ev: Evidence) -> Claim:
    """``winner`` gets faster as the sides per face grow from ``m_from`` to ``m_to`` at each of ``n_values``: read
    as its own cycles falling, and as its lead over each other (their cycles over its own) growing, ahead at the
    end (:func:`_lead_grows`); cycle weights."""
    w = paper_weights()
    readings = []
    for n_ in c["n_values"]:
        lo, hi = {"n": n_, "m": c["m_from"]}, {"n": n_, "m": c["m_to"]}
        for name, combo in readings_of(c["winner"], *c["others"]):
            own = [_value(c["winner"], combo[0], w, p) for p in (lo, hi)]
            tag = f"n = {n_}" + (f", {name}" if name else "")
            readings.append(
                Reading(
                    f"{algo(c['winner'])}'s own cycles fall, {tag}",
                    bool(own[1] < own[0]),
                    f"{algo(c['winner'])} {num(own[0])} at m = {lo['m']}, {num(own[1])} at m = {hi['m']}",
                )
            )
            for other, a, b in _leads(c, combo, w, lo, hi):
                readings.append(
                    Reading(
                        f"{algo(c['winner'])}'s lead over {algo(other)} grows, {tag}",
                        _lead_grows(a, b),
                        f"{algo(other)} / {algo(c['winner'])} {float(a):.3f} at m = {lo['m']}, {float(b):.3f} at "
                        f"m = {hi['m']}",
                    )
                )
    return judged_by_readings(
        c,
        source,
        "comparison",
        readings,
        f"{WEIGHTS}, papers'-convention sums, m from {c['m_from']} to {c['m_to']} (the m of Figs. 5 and 6). "
        "'The speed of HSD will be increased' is read as HSD's own cost and as its lead over the others.",
    )


RULES = {
    "advantage_grows": advantage_grows,
    "common_cost": common_cost,
    "fewest_asymptotic": fewest_asymptotic,
    "grows_with_m": grows_with_m,
}
