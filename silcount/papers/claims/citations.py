"""Dates and attributions against the paper's own reference list (and its own earlier statements).

A citation claim names an author and (where the text gives one) a year; the
reference entry it cites is quoted too (``ref_quote``).  HOLDS when the entry
names the author and carries the year; FAILS otherwise.  An "earlier use"
claim ("first proposed in Y") FAILS when the same paper reports the thing in
use before Y.  A cross-reference ("... in section 8") HOLDS when the heading of
the section holding that content (``ref_quote``) carries the number.
"""

from __future__ import annotations

import re

from silcount.papers.claims.base import FAILS, HOLDS, Claim, claim_from_data
from silcount.papers.claims.context import Evidence


def citation(c: dict, source: str, ev: Evidence) -> Claim:
    ref = c["ref_quote"]
    years = sorted({int(y) for y in re.findall(r"(?<!\d)(?:19|20)\d\d(?!\d)", ref)})
    author_ok = not c["author"] or c["author"].lower() in ref.lower()
    year_ok = "year" not in c or c["year"] in years
    problems = ([] if author_ok else [f"the entry does not name {c['author']}"]) + (
        [] if year_ok else [f"the entry's year is {', '.join(map(str, years)) or 'not given'}, not {c.get('year')}"]
    )
    return claim_from_data(
        c,
        source,
        "attribution",
        rederived=f"reference entry: {ref[:100]}" + ("..." if len(ref) > 100 else ""),
        measured=None,
        verdict=HOLDS if not problems else FAILS,
        reason=(
            "; ".join(problems)
            if problems
            else "the cited entry names the author" + (" and the year" if "year" in c else "")
        )
        + f" (reference list, lines {c['ref_lines']}).",
    )


def earlier_use(c: dict, source: str, ev: Evidence) -> Claim:
    earlier = c["earlier_year"] < c["year"]
    return claim_from_data(
        c,
        source,
        "attribution",
        rederived=f"the same paper, lines {c['earlier_lines']}: '{c['earlier_quote']}' ({c['earlier_year']})",
        measured=None,
        verdict=FAILS if earlier else HOLDS,
        reason=f"the paper itself reports the stencil buffer in shadow volumes in {c['earlier_year']}, before "
        f"{c['year']}"
        if earlier
        else "no earlier use in the paper.",
    )


ROMAN = {"I": 1, "V": 5, "X": 10, "L": 50}


def roman(numeral: str) -> int:
    values = [ROMAN[ch] for ch in numeral]
    return sum(-v if i + 1 < len(values) and v < values[i + 1] else v for i, v in enumerate(values))


def section_reference(c: dict, source: str, ev: Evidence) -> Claim:
    """A cross-reference "... in section N" against the heading of that content (``ref_quote``: "IX. ...")."""
    numeral = c["ref_quote"].split(".")[0].strip()
    actual = roman(numeral)
    ok = actual == int(c["section_number"])
    return claim_from_data(
        c,
        source,
        "cross-reference",
        rederived=f"heading '{c['ref_quote']}' (lines {c['ref_lines']}): section {numeral} = {actual}",
        measured=None,
        verdict=HOLDS if ok else FAILS,
        reason=f"the paper's own heading numbers it {actual}"
        + (", as cited." if ok else f", not {c['section_number']}."),
    )


RULES = {"citation": citation, "earlier_use": earlier_use, "section_reference": section_reference}
