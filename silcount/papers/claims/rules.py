"""The rules that judge a claims file's entries: one signature, one registry.

A rule is ``rule(entry, source, evidence) -> Claim | list[Claim]``: ``entry`` is the ``[[claims]]`` table of a
claims file, ``source`` what its claims carry as ``paper`` (the paper's text file, or its id), ``evidence`` the
measurements (:class:`~silcount.papers.claims.context.Evidence`).  A claims entry names its rule by ``check``.

Each rule judges either one of the *generic kinds* (:data:`GENERIC`, ``docs/papers-as-data.md``: a paper given as
data uses these with no Python of its own), or it was written for a single claim of one paper (``kind`` empty),
which the claims reports list (:func:`single_claim_keys`).  A plugin adds a rule with :func:`register`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from silcount.papers.claims.base import Claim
    from silcount.papers.claims.context import Evidence

RuleFn = Callable[[dict, str, "Evidence"], "Claim | list[Claim]"]

# The generic kinds: check name -> the kind of claim it judges.  The derivation claims (each step, the annotations
# summed, the upper bound) and the table cells are generated from a paper's algorithms and tables, with no check.
GENERIC = {
    "pairwise": "a comparison at a point (raw or weighted)",
    "equal_kinds": "a comparison at a point (raw or weighted)",
    "differ_kinds": "a comparison at a point (raw or weighted)",
    "measured_comparison": "a comparison at a point, measured",
    "cycle_ratio": "a ratio",
    "joint_ratio": "a ratio",
    "mesh_ratio": "a ratio",
    "measured_log_ratio": "a ratio, measured",
    "complexity": "an O() claim",
    "big_oh": "an O() claim",
    "measured_big_oh": "an O() claim, measured",
    "advantage_grows": "growth with n",
    "fewest_asymptotic": "growth with n",
    "grows_with_m": "growth with n",
    "measured_growth": "growth with n, measured",
    "kernel_cost": "a primitive's cost",
    "citation": "a citation against the paper's own reference list",
    "cited_topic": "a citation against the paper's own reference list",
    "no_entry": "a citation against the paper's own reference list",
    "section_reference": "a citation against the paper's own reference list",
}


@dataclass(frozen=True)
class Rule:
    """A registered rule: its ``check`` name, the function, and its generic kind ("" for a single-claim rule)."""

    name: str
    fn: RuleFn
    kind: str

    def judge(self, entry: dict, source: str, evidence: "Evidence") -> "list[Claim]":
        """The claims this rule gives for ``entry`` (one, or several where a rule judges an entry per point)."""
        out = self.fn(entry, source, evidence)
        return out if isinstance(out, list) else [out]


_ADDED: dict[str, Rule] = {}


def register(name: str, fn: RuleFn, kind: str = "") -> None:
    """Add a rule (a plugin's own); a name already taken is refused (ValueError)."""
    if name in rules():
        raise ValueError(f"a rule named {name!r} is already registered")
    _ADDED[name] = Rule(name, fn, kind)


@cache
def _builtin() -> dict[str, Rule]:
    from silcount.papers.claims import (
        algorithms,
        citations,
        comparisons,
        facing,
        fps,
        inventory,
        measured,
        toggles,
        trends,
    )

    table: dict[str, RuleFn] = {}
    for module in (inventory, facing, algorithms, toggles, citations, comparisons, trends, fps, measured):
        for name, fn in module.RULES.items():
            if name in table:
                raise ValueError(f"rule {name!r} is defined twice")
            table[name] = fn
    return {name: Rule(name, fn, GENERIC.get(name, "")) for name, fn in table.items()}


def rules() -> dict[str, Rule]:
    """Every registered rule by ``check`` name: the built-in ones, then those added with :func:`register`."""
    return {**_builtin(), **_ADDED}


def single_claim_keys(checks: dict[str, str]) -> list[str]:
    """The keys (of ``checks``: claim key -> its check) of the claims a single-claim rule judged."""
    table = rules()
    return [key for key, check in checks.items() if not table[check].kind]
