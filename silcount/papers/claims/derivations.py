"""Every ``=`` of every printed derivation, its own claim (EESD paper Sec. 5.1-5.3; HSD paper Sec. VI).

Per algorithm model, five claims a reader can follow one by one:

1. ``annotations``: the per-line annotations give the first printed line under
   the papers' convention (every condition true, the then-branch charged);
2. ``upper bound``: the first printed line bounds every execution (each
   conditional at its dearest arm); where it does not, an execution of
   silcount's naive engine that exceeds it is named, built by hand or, for a
   model without one, found by the worst-case search
   (:func:`silcount.papers.witness.witness_for`);
3. ``substitution``: line 1 -> line 2 with ``f_n = n, e_n = 6n``;
4. ``expansion``: line 2 -> line 3, multiplied out;
5. ``end to end``: the last line (the closed form) against the convention.

Where the model carries ``[[readings]]`` (HSD's side-loop bound), each claim
is judged under every reading (``readings``), never under one alone, and
carries the model's ``table_reading`` (which reading the papers' tables and
figures use).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.papers import formulas as F
from silcount.papers.claims.base import Claim, Reading, algo, from_readings, show_readings, source_of
from silcount.papers.quotes import SPAN_JOIN, parse_lines

if TYPE_CHECKING:
    from silcount.papers.registry import Paper

POINTS = ({"n": 10, "m": 5}, {"n": 100, "m": 10})


def _located(parts: list[tuple[str, str]]) -> tuple[str, str]:
    """Join (quote, lines) parts in file order: the quote with ``...``, the covering line range."""
    seen, quotes, first, last = set(), [], None, None
    for quote, lines in parts:
        if quote in seen:
            continue
        seen.add(quote)
        quotes.append(quote)
        a, b = parse_lines(lines)
        first, last = (a if first is None else min(first, a)), (b if last is None else max(last, b))
    return f" {SPAN_JOIN} ".join(quotes), f"{first}-{last}"


def _step_parts(model: str) -> list[tuple[str, str]]:
    return [(spec["quote"], spec["lines"]) for spec in F.steps(model).values() if "quote" in spec]


def _line_part(model: str, i: int) -> tuple[str, str]:
    line = models.load(model)["closed_form"]["lines"][i]
    return line.get("quote", line["printed"]), line["lines"]


def _diff_text(diff: dict) -> str:
    return ", ".join(
        f"{k}: {'+' if not str(d).startswith('-') else ''}{sp.sstr(sp.factor(d))}" for k, d in diff.items()
    )


def _claim(
    model: str,
    key: str,
    parts,
    statement: str,
    printed: str,
    rederived: str,
    verdict: str,
    reason: str,
    readings,
    measured: str | None = None,
    follows_from: str = "",
):
    quote, lines = _located(parts)
    return Claim(
        key=f"{model} {key}",
        family="derivation",
        paper=source_of(model),
        section=models.load(model)["closed_form"]["section"],
        lines=lines,
        quote=quote,
        statement=f"{algo(model)} ({models.load(model)['paper']}): {statement}",
        printed=printed,
        rederived=rederived,
        measured=measured,
        verdict=verdict,
        reason=reason,
        readings=readings if len(readings) > 1 else [],
        table_reading=models.load(model).get("table_reading", "") if len(readings) > 1 else "",
        follows_from=follows_from,
    )


def _per_reading(model: str, judge) -> tuple[list[Reading], str]:
    out = [Reading(r or "as printed", *judge(r)) for r in F.readings(model)]
    return out, (show_readings(out) if len(out) > 1 else out[0].outcome)


def _annotations(model: str) -> Claim:
    def judge(r):
        diff = F.difference(F.paper_forms(model, r)["convention"], F.paper_forms(model, r)["first"])
        return (not diff, "equal, term by term" if not diff else "the annotations give more: " + _diff_text(diff))

    readings, reason = _per_reading(model, judge)
    return _claim(
        model,
        "annotations -> line 1",
        _step_parts(model) + [_line_part(model, 0)],
        "the first printed line is the per-line annotations summed under the papers' convention "
        "(every condition true, the then-branch charged)",
        F.printed_lines(model)[0].printed,
        F.show(F.paper_forms(model, F.readings(model)[0])["convention"]),
        from_readings(readings),
        f"in n (f_n = n, e_n = 6n): {reason}.",
        readings,
    )


def _exceeds(form: dict, bound: dict) -> list[str]:
    """Kinds where ``form`` exceeds ``bound`` at one of the papers' table points."""
    out = []
    for k in KINDS:
        for p in POINTS:
            a, b = (sp.nsimplify(x.subs({F.n: p["n"], F.m: p["m"]})) for x in (form[k], bound[k]))
            if a > b:
                out.append(f"{k} {sp.sstr(a)} > {sp.sstr(b)} at n={p['n']}, m={p['m']}")
                break
    return out


def _upper_bound(model: str) -> Claim:
    """FAILS needs an execution silcount has run (:func:`silcount.papers.witness.bound_witness`), never an
    assignment of v and s: "every face lit" cannot happen on a closed mesh."""
    from silcount.papers import witness

    ran: list[str] = []
    only_omitted: list[bool] = []  # per failing reading: the witness exceeds only kinds line 1 leaves out

    def judge(r):
        pf = F.paper_forms(model, r)
        over = _exceeds(pf["worst"], pf["first"])
        if not over:
            return True, "no kind of the tight worst case exceeds it"
        run = witness.witness_for(model)  # hand-built, else found by the worst-case search
        if run is None or not run.over:
            raise ValueError(
                f"{model} ({r}): worst case exceeds the printed line but no executed witness does (none hand-built, "
                f"none found by the worst-case search in {witness.BOUND_BUDGET} evaluations)"
            )
        ran[:] = [run.describe()]
        omitted = {k for k, d in F.difference(pf["convention"], pf["first"]).items() if d.subs({F.n: 10, F.m: 5}) > 0}
        at = {F.LOCALS[k]: sp.nsimplify(v) for k, v in run.params.items() if k in F.LOCALS}
        annotated = {k: x.subs(at) for k, x in F.convention(model, r).items()}
        # the slip of line 1 alone: the run exceeds it only where line 1 leaves annotations out, and by no more
        # than the annotations charge at the run's own f_n, e_n, m
        only_omitted.append(all(k in omitted and run.cost[k] <= annotated[k] for k in run.over))
        return False, f"an execution silcount ran exceeds it: {run.excess()} ({run.detector} on {run.mesh})"

    readings, reason = _per_reading(model, judge)
    notes = [
        f"'{spec['line']}': {spec['branch_note']}"
        for spec in F.steps(model).values()
        if spec.get("branch_note") and F.parse(spec.get("branch", "1")) != 1
    ]
    return _claim(
        model,
        "line 1 upper bound",
        [_line_part(model, 0)],
        "the first printed line is a valid upper bound (every conditional at its dearest arm)",
        F.printed_lines(model)[0].printed,
        "tight worst case: " + F.show(F.paper_forms(model, F.readings(model)[0])["worst"]),
        from_readings(readings),
        f"{reason}."
        + (f" Witness: {ran[0]}." if ran else "")
        + (f" Branch counts of the pseudo-code: {' '.join(notes)}" if notes else ""),
        readings,
        measured=ran[0] if ran else None,
        # line 1 exceeded only in kinds it drops from its own annotations: the slip of 'annotations -> line 1'
        follows_from=f"{model} annotations -> line 1"
        if only_omitted and all(only_omitted) and from_readings(readings) == "FAILS"
        else "",
    )


def _step(model: str, i: int, key: str, what: str) -> Claim:
    prev, cur, diff = F.expansion_steps(model)[i]
    return _claim(
        model,
        key,
        [_line_part(model, i), _line_part(model, i + 1)],
        f"'{cur}' follows from '{prev}' ({what})",
        cur,
        F.show({k: sp.expand(x.subs(F.substitutions(model))) for k, x in F.printed_lines(model)[i].form.items()}),
        "HOLDS" if not diff else "FAILS",
        ("the two lines are equal after f_n -> n, e_n -> 6n" if not diff else f"'{cur}' differs: {_diff_text(diff)}")
        + ".",
        [],
    )


def _end_to_end(model: str) -> Claim:
    def judge(r):
        pf = F.paper_forms(model, r)
        diff = F.difference(pf["convention"], pf["printed"])
        return (not diff, "equal" if not diff else "the annotations give " + _diff_text(diff) + " more")

    readings, reason = _per_reading(model, judge)
    last = len(models.load(model)["closed_form"]["lines"]) - 1
    return _claim(
        model,
        "closed form vs re-derived",
        _step_parts(model) + [_line_part(model, last)],
        "the printed closed form equals its annotations summed under the papers' convention",
        F.printed_lines(model)[last].printed,
        F.show(F.paper_forms(model, F.readings(model)[0])["convention"]),
        from_readings(readings),
        f"{reason}.",
        readings,
    )


def derivation_claims(papers: "tuple[Paper, ...] | None" = None) -> list[Claim]:
    """The five claims of each algorithm model of ``papers`` (default: the built-ins), in the papers' order."""
    from silcount.papers import registry

    out = []
    for model in (m for p in (registry.builtin() if papers is None else papers) for m in p.algorithms):
        chain = [
            _annotations(model),
            _step(model, 0, "line 1 -> line 2", "the substitution f_n = n, e_n = 6n"),
            _step(model, 1, "line 2 -> line 3", "multiplying out"),
        ]
        end = _end_to_end(model)
        failed = [c.key for c in chain if c.verdict == "FAILS"]
        if end.verdict == "FAILS" and failed:
            end.follows_from = failed[0]  # the end-to-end mismatch is the failing `=` of the chain, restated
        out += [chain[0], _upper_bound(model), *chain[1:], end]
    return out


def slip_of(model: str, kind: str) -> str:
    """The key of the derivation claim whose `=` moves ``kind`` away from the annotations, or ''."""
    pf = F.paper_forms(model)
    if sp.expand(pf["convention"][kind] - pf["first"][kind]) != 0:
        return f"{model} annotations -> line 1"
    for i, (_, _, d) in enumerate(F.expansion_steps(model)):
        if kind in d:
            return f"{model} line {i + 1} -> line {i + 2}"
    return ""
