"""Rule 15 (docs/claims.md): two statements of a paper that give one quantity two meanings.

The meaning of n (EESD Sec. 5, HSD Sec. VI: "n vertices" against the substitution f_n = n, e_n = 6n) and
HSD's sides per polygon (Sec. VI 6.3: "decreased by 1" against the printed sum's 1) have one structure: under
each reading one of the two statements is false.  Both are judged by one rule, so both FAIL; the claims that
depend on which one was meant are judged under both readings.
"""

from __future__ import annotations

import pytest

from silcount.counting import models
from silcount.papers import formulas
from silcount.papers.claims import AMBIGUOUS, FAILS, HOLDS, inventory


def _claim_data(claims_file: str, key: str) -> tuple[dict, str]:
    data = models.load(claims_file)
    (c,) = [c for c in data["claims"] if c["id"] == key]
    return c, data["source_file"]


@pytest.mark.parametrize(
    "claims_file, key",
    [
        ("eesd2012-claims", "eesd-n-meaning"),
        ("hsd2011-claims", "hsd-n-meaning"),
        ("hsd2011-claims", "hsd-decreased-by-one"),
    ],
)
def test_each_two_meanings_claim_fails_with_every_reading_false(claims_file, key):
    c, source = _claim_data(claims_file, key)
    rule = inventory.RULES[c["check"]]
    claim = rule(c, source, None)
    assert claim.verdict == FAILS, claim.reason
    assert len(claim.readings) == 2 and not any(r.holds for r in claim.readings)
    assert claim.reason.endswith("two meanings; under each, one of them is false.")


def test_the_sides_claim_by_hand():
    """HSD Sec. VI 6.3 at m = 5 (Fig. 5): 'decreased by 1' gives 4 sides, the printed sum 1."""
    loop = models.load("hsd2011-hsd")["loops"]["sides"]
    prose, printed = formulas.parse(loop["bound"]), formulas.parse(loop["bound_printed"])
    assert prose.subs(formulas.m, 5) == 4 and printed.subs(formulas.m, 5) == 1


def test_the_rule_holds_where_the_two_statements_agree(monkeypatch):
    """The verdict is computed: a paper whose sentence and sum agreed would HOLD under both readings."""
    c, source = _claim_data("hsd2011-claims", "hsd-decreased-by-one")
    real = models.load

    def agreeing(name: str):
        data = real(name)
        if name != c["model"]:
            return data
        loops = {**data["loops"], "sides": {**data["loops"]["sides"], "bound_printed": "m - 1"}}
        return {**data, "loops": loops}

    monkeypatch.setattr(formulas.models, "load", agreeing)
    claim = inventory.loop_bound(c, source, None)
    assert claim.verdict == HOLDS and all(r.holds for r in claim.readings)


def test_a_claim_that_depends_on_the_meaning_is_judged_under_both():
    """HSD's first printed line uses m -> 1: it is the annotations summed under one reading and not the other."""
    from silcount.papers.claims import derivations

    (line1,) = [c for c in derivations.derivation_claims() if c.key == "hsd2011-hsd annotations -> line 1"]
    assert line1.verdict == AMBIGUOUS
    assert [r.holds for r in line1.readings] == [True, False]
