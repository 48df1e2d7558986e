"""Every checkable statement of the three papers, located, quoted and judged.

Families (one module each): :mod:`.derivations` (every ``=`` of every printed
derivation), :mod:`.cells` (every printed table cell), :mod:`.comparisons`
(pairs per table point, orderings, ratios), :mod:`.fps` (frame rates),
:mod:`.inventory` (primitives, the mesh model, complexity), :mod:`.algorithms`
(the algorithms and stencil steps as written, the projection),
:mod:`.citations` (dates and attributions).  The prose claims are data in each
paper's claims files (:mod:`silcount.papers.registry`); their ``check`` names the
rule (:mod:`.rules`).  The verdict rules are in ``docs/claims.md``.  Importing this package is cheap: sympy,
pandas and the detectors load on the first call.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from silcount.papers.claims.base import AMBIGUOUS, FAILS, HOLDS, VERDICTS, Claim, Reading

if TYPE_CHECKING:
    import pandas as pd

    from silcount.counting.cycles import Profile
    from silcount.papers.claims.context import Evidence
    from silcount.papers.registry import Paper


def default_evidence(real: bool = False, render: bool = True) -> "Evidence":
    """The icosphere sweep's exponents (:func:`silcount.papers.growth.icosphere_evidence`), the worst-case
    families of each detector an O() claim names (:func:`silcount.papers.witness.worst_cases`: TA's built by
    hand, any other detector's found by the worst-case search) and, with ``render``, the render experiments' pixel
    mismatches of the literal stencil steps (:func:`silcount.render.experiments.stencil_step_evidence`)."""
    from silcount.papers import growth, witness
    from silcount.papers.claims.context import Deferred, Evidence

    stencil = None
    if render:
        from silcount.render.experiments import stencil_step_evidence

        stencil = stencil_step_evidence()
    return Evidence(  # the sweeps run when a rule first reads them (the built-in papers' O() claims do)
        exponents=Deferred(growth.icosphere_evidence),
        stencil=stencil,
        real=real,
        worst=witness.worst_cases,
    )


def all_claims(evidence: "Evidence | None" = None, papers: "tuple[Paper, ...] | None" = None) -> list[Claim]:
    """Every claim of ``papers`` (default: the built-ins), numbered, in a fixed order: derivations, table cells,
    then each paper's claims files, each entry judged by the rule its ``check`` names (:mod:`.rules`).

    ``evidence=None`` is ``default_evidence(render=False)``: the render experiments run only when asked
    for (``all_claims(default_evidence())``, as ``silcount claims`` and ``silcount report`` do); without
    them the stencil claims keep their verdicts, judged by their readings, and say "not measured".
    """
    from silcount.counting import models
    from silcount.papers import registry
    from silcount.papers.claims import cells, derivations
    from silcount.papers.claims.rules import rules

    chosen = registry.builtin() if papers is None else papers
    ev = default_evidence(render=False) if evidence is None else evidence
    table = rules()
    out = derivations.derivation_claims(chosen) + cells.cell_claims(chosen)
    for name in (n for p in chosen for n in p.claims):
        data = models.load(name)
        for c in data.get("claims", []):
            out += table[c["check"]].judge(c, data["source_file"], ev)
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


def format_claims(
    fmt: str,
    extra_profile: "Profile | None" = None,
    evidence: "Evidence | None" = None,
    papers: "tuple[Paper, ...] | None" = None,
) -> str:
    """The claims as ``text``, ``md`` or ``json`` (``extra_profile``: reported with the cycle orderings;
    ``evidence``, ``papers``: as :func:`all_claims`)."""
    from silcount.papers.claims.rendering import RENDER

    return RENDER[fmt](all_claims(evidence, papers), extra_profile)


def write_claims(out_dir, evidence: "Evidence | None" = None, papers: "tuple[Paper, ...] | None" = None):
    """``claims.{txt,md,json}`` and ``rules.md`` of ``papers`` (default: the built-ins) into ``out_dir``."""
    from pathlib import Path

    from silcount.papers.claims.rendering import write_all

    return write_all(all_claims(evidence, papers), Path(out_dir))


def report(out_dir):
    """The committed outputs: ``<out_dir>/claims/claims.{txt,md,json}`` and ``rules.md``, with the render
    experiments' evidence."""
    from pathlib import Path

    return write_claims(Path(out_dir) / "claims", default_evidence())


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
    "write_claims",
]
