"""Every checkable statement of the three papers, located, quoted and judged.

Families (one module each): :mod:`.derivations` (every ``=`` of every printed
derivation), :mod:`.cells` (every printed table cell), :mod:`.comparisons`
(pairs per table point, orderings, ratios), :mod:`.fps` (frame rates),
:mod:`.inventory` (primitives, the mesh model, complexity), :mod:`.algorithms`
(the algorithms and stencil steps as written, the projection),
:mod:`.citations` (dates and attributions).  The prose claims are data in
``silcount/models/<paper>-claims.toml``; their ``check`` names the rule.  The verdict
rules are in ``docs/claims.md``.  Importing this package is cheap: sympy,
pandas and the detectors load on the first call.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from silcount.papers.claims.base import AMBIGUOUS, CLAIM_FILES, FAILS, HOLDS, VERDICTS, Claim, Reading

if TYPE_CHECKING:
    import pandas as pd

    from silcount.counting.cycles import Profile
    from silcount.papers.claims.context import Evidence


def default_evidence(real: bool = False, render: bool = True) -> "Evidence":
    """The icosphere sweep's exponents (:func:`silcount.papers.growth.icosphere_evidence`), TA's witness family
    (:func:`silcount.papers.witness.witness_evidence`) and, with ``render``, the render experiments' pixel
    mismatches of the literal stencil steps (:func:`silcount.render.experiments.stencil_step_evidence`)."""
    from silcount.papers import growth, witness
    from silcount.papers.claims.context import Evidence

    stencil = None
    if render:
        from silcount.render.experiments import stencil_step_evidence

        stencil = stencil_step_evidence()
    return Evidence(
        exponents=growth.icosphere_evidence(),
        stencil=stencil,
        real=real,
        worst=witness.witness_evidence(),
    )


def all_claims(evidence: "Evidence | None" = None) -> list[Claim]:
    """Every claim, numbered, in a fixed order: derivations, table cells, then each paper's claims file.

    ``evidence=None`` is ``default_evidence(render=False)``: the render experiments run only when asked
    for (``all_claims(default_evidence())``, as ``silcount claims`` and ``silcount report`` do); without
    them the stencil claims keep their verdicts, judged by their readings, and say "not measured".
    """
    from silcount.counting import models
    from silcount.papers.claims import (
        algorithms,
        cells,
        citations,
        comparisons,
        derivations,
        facing,
        fps,
        inventory,
        toggles,
        trends,
    )

    ev = default_evidence(render=False) if evidence is None else evidence
    with_evidence: dict[str, Callable[[dict, str, Evidence], Claim]] = {
        **inventory.RULES,
        **facing.RULES,
        **algorithms.RULES,
        **toggles.RULES,
        **citations.RULES,
    }
    plain: dict[str, Callable[[dict, str], Claim]] = {**comparisons.RULES, **trends.RULES, **fps.RULES}
    multi: dict[str, Callable[[dict, str], list[Claim]]] = {**comparisons.MULTI, **fps.MULTI}
    out = derivations.derivation_claims() + cells.cell_claims()
    for name in CLAIM_FILES:
        data = models.load(name)
        for c in data.get("claims", []):
            check, source = c["check"], data["source_file"]
            if check in multi:
                out += multi[check](c, source)
            elif check in plain:
                out.append(plain[check](c, source))
            else:
                out.append(with_evidence[check](c, source, ev))
    for i, claim in enumerate(out, start=1):
        claim.id = i
    _check_follows(out)
    return out


def _check_follows(out: list[Claim]) -> None:
    """``follows_from`` names a FAILS claim, and only a FAILS claim restates one."""
    verdict = {c.key: c.verdict for c in out}
    for c in out:
        if c.follows_from and (c.verdict != FAILS or verdict.get(c.follows_from) != FAILS):
            raise ValueError(f"{c.key}: follows_from {c.follows_from!r} needs both claims to be FAILS")


def claims_frame(evidence: "Evidence | None" = None) -> "pd.DataFrame":
    """Every claim as a pandas DataFrame with the report's columns (``readings`` as a list of dicts)."""
    from silcount.papers.claims.rendering import frame

    return frame(all_claims(evidence))


def findings_markdown(evidence: "Evidence | None" = None) -> str:
    """The README's findings table, generated from the claims: verdict counts per paper and every FAILS;
    ``evidence=None`` is :func:`default_evidence` with the render experiments, as the claims report has them."""
    from silcount.papers.claims.rendering import findings

    return findings(all_claims(evidence if evidence is not None else default_evidence()))


def format_claims(fmt: str, extra_profile: "Profile | None" = None, evidence: "Evidence | None" = None) -> str:
    """The claims as ``text``, ``md`` or ``json`` (``extra_profile``: reported with the cycle orderings;
    ``evidence``: as :func:`all_claims`)."""
    from silcount.papers.claims.rendering import RENDER

    return RENDER[fmt](all_claims(evidence), extra_profile)


def report(out_dir):
    """The committed outputs: ``<out_dir>/claims/claims.{txt,md,json}``, with the render experiments' evidence."""
    from pathlib import Path

    from silcount.papers.claims.rendering import write_all

    return write_all(all_claims(default_evidence()), Path(out_dir) / "claims")


__all__ = [
    "AMBIGUOUS",
    "FAILS",
    "HOLDS",
    "VERDICTS",
    "Claim",
    "Reading",
    "all_claims",
    "claims_frame",
    "default_evidence",
    "findings_markdown",
    "format_claims",
    "report",
]
