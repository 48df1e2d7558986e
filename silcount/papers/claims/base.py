"""The claim record, the three verdicts, and the helpers every rule family shares.

Verdict rules (``docs/claims.md``): HOLDS = true under the paper's own
conventions; FAILS = false under the paper's own definitions, or under every
reasonable reading; AMBIGUOUS = reasonable readings disagree and the paper
gives no way to decide (the claim then lists each reading and its outcome).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache

from silcount.counting import models
from silcount.detectors import get

HOLDS, FAILS, AMBIGUOUS = "HOLDS", "FAILS", "AMBIGUOUS"
VERDICTS = (HOLDS, FAILS, AMBIGUOUS)


@dataclass
class Reading:
    """One reading of an ambiguous statement and what it gives."""

    reading: str
    holds: bool
    outcome: str

    def as_json(self) -> dict:
        return {"reading": self.reading, "holds": self.holds, "outcome": self.outcome}


@dataclass
class Claim:
    """One checkable statement of a paper, located, quoted and judged."""

    key: str
    family: str
    paper: str  # file name in the papers directory
    section: str
    lines: str  # "a-b", 1-based inclusive
    quote: str
    statement: str
    printed: str
    rederived: str
    measured: str | None
    verdict: str
    reason: str
    readings: list[Reading] = field(default_factory=list)
    id: int = 0
    # which reading the papers' own tables or figures use (silcount/models/: ``table_reading``), "" when not recorded
    table_reading: str = ""
    # the key of the FAILS claim whose slip this FAILS restates at another place (a table cell computed from a
    # printed line that already fails, ...); "" for an independent erratum
    follows_from: str = ""
    # the claims file's ``check`` that judged it ("" for a derivation or table-cell claim); not in the reports,
    # so not in a claim's equality either (a claim read back from JSON is the claim)
    check: str = field(default="", compare=False)

    @property
    def where(self) -> str:
        if not self.lines:  # a paper silcount has no text of: its place is named as the paper names it
            return self.section
        return f"Sec. {self.section}, lines {self.lines}"

    def as_json(self) -> dict:
        return {
            "id": self.id,
            "key": self.key,
            "family": self.family,
            "paper": self.paper,
            "where": self.where,
            "section": self.section,
            "lines": self.lines,
            "quote": self.quote,
            "statement": self.statement,
            "readings": [r.as_json() for r in self.readings],
            "printed": self.printed,
            "rederived": self.rederived,
            "measured": self.measured,
            "verdict": self.verdict,
            "reason": self.reason,
            "table_reading": self.table_reading or None,
            "follows_from": self.follows_from or None,
        }

    @classmethod
    def from_json(cls, d: dict) -> "Claim":
        """The claim :meth:`as_json` wrote (``where`` is derived, so it is not read back)."""
        fields = {k: v for k, v in d.items() if k not in ("where", "readings", "table_reading", "follows_from")}
        readings = [Reading(**r) for r in d["readings"]]
        return cls(
            **fields, readings=readings, table_reading=d["table_reading"] or "", follows_from=d["follows_from"] or ""
        )


def from_readings(readings: list[Reading]) -> str:
    """HOLDS when every reading holds, FAILS when none does, AMBIGUOUS otherwise."""
    held = {r.holds for r in readings}
    return HOLDS if held == {True} else FAILS if held == {False} else AMBIGUOUS


def show_readings(readings: list[Reading]) -> str:
    return "; ".join(f"{r.reading}: {'holds' if r.holds else 'fails'} ({r.outcome})" for r in readings)


def num(x) -> str:
    import sympy as sp

    x = sp.nsimplify(x)
    if x.is_Integer:
        return str(int(x))
    return f"{float(x):.4g}"


def algo(model: str) -> str:
    return get(models.load(model)["algorithm"]).label


def source_of(model_or_paper: str) -> str:
    return models.load(model_or_paper)["source_file"]


@cache
def cycles(model: str, which: str, weights: tuple, reading: str = ""):
    """Cycle total (sympy, in n and m) of one of a model's paper forms under ``weights`` (sorted items)."""
    from silcount.papers import formulas as F

    return F.weighted(F.paper_forms(model, reading)[which], dict(weights))


def paper_weights() -> tuple:
    from silcount.counting.arithmetic import KINDS

    w = models.load("eesd2012-paper")["cycle_weights"]
    return tuple(sorted((k, float(w[k])) for k in KINDS))


def unit_weights() -> tuple:
    from silcount.counting.arithmetic import KINDS

    return tuple(sorted((k, 1.0) for k in KINDS))


def judged_by_readings(
    c: dict,
    source: str,
    family: str,
    readings: list[Reading],
    reason: str,
    *,
    rederived: str | None = None,
    measured: str | None = None,
    keep_one: bool = True,
) -> Claim:
    """:func:`claim_from_data` judged by its readings: the verdict :func:`from_readings`, the rederived value
    :func:`show_readings` unless given; ``keep_one=False`` reports no readings when there is just one."""
    return claim_from_data(
        c,
        source,
        family,
        rederived=show_readings(readings) if rederived is None else rederived,
        measured=measured,
        verdict=from_readings(readings),
        reason=reason,
        readings=readings if keep_one or len(readings) > 1 else [],
    )


def claim_from_data(c: dict, source: str, family: str, **judged) -> Claim:
    """A claim whose location, quote, statement, printed value (and ``table_reading``) come from a
    ``[[claims]]`` entry."""
    judged.setdefault("table_reading", c.get("table_reading", ""))
    judged.setdefault("follows_from", c.get("follows_from", ""))
    return Claim(
        key=c["id"],
        family=family,
        paper=c.get("paper", source),
        # a paper of several sources (the literature's) names each claim's own: "<citation>, <section>"
        section=f"{c['citation']}, {c['section']}" if "citation" in c else c["section"],
        lines=c.get("lines", ""),
        quote=c.get("quote", ""),
        statement=c["statement"],
        printed=c["printed"],
        check=c.get("check", ""),
        **judged,
    )
