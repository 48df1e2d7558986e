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

from silcount.papers.claims.base import FAILS, HOLDS, Claim, Reading, claim_from_data, judged_by_readings
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


def _references(c: dict) -> list[str]:
    """The paper's reference entries: the claim's ``entries_quote``, its whole list as quoted at ``entries_lines``."""
    return [line.strip() for line in c["entries_quote"].splitlines() if re.match(r"- \[\d+\]", line.strip())]


def cited_topic(c: dict, source: str, ev: Evidence) -> Claim:
    """A citation for a topic: the cited entries (``ref_quote``) are judged by their titles, once by whether a
    title names the topic (``topic_words``) and, where ``related_words`` is given, once by whether a title names
    a field that may cover it.  A group citation holds when one of its entries does."""
    ref = c["ref_quote"].lower()
    tests = [("a cited title names the topic", c["topic_words"])]
    if "related_words" in c:
        tests.append(("a cited title names a field that may cover it", c["related_words"]))
    readings = [
        Reading(name, any(w.lower() in ref for w in words), "looked for: " + ", ".join(repr(w) for w in words))
        for name, words in tests
    ]
    return judged_by_readings(
        c,
        source,
        "attribution",
        readings,
        f"{c['topic_note']} (reference list, lines {c['ref_lines']}).",
        rederived=f"cited: {c['ref_quote'][:160]}" + ("..." if len(c["ref_quote"]) > 160 else ""),
        keep_one=False,
    )


def no_entry(c: dict, source: str, ev: Evidence) -> Claim:
    """An attribution by name: some entry of the paper's own reference list names one of ``names``."""
    entries = _references(c)
    found = [e for e in entries if any(nm.lower() in e.lower() for nm in c["names"])]
    return claim_from_data(
        c,
        source,
        "attribution",
        rederived=f"{len(entries)} reference entries; naming {' or '.join(c['names'])}: {len(found)}",
        measured=None,
        verdict=HOLDS if found else FAILS,
        reason=(
            f"entry: {found[0][:100]}" if found else f"no entry of the reference list names {' or '.join(c['names'])}"
        )
        + f"; {c['names_note']}",
    )


RULES = {
    "cited_topic": cited_topic,
    "no_entry": no_entry,
    "citation": citation,
    "earlier_use": earlier_use,
    "section_reference": section_reference,
}
