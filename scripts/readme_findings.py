"""Regenerate the README's verdict counts and docs/findings.md's tables from the claims (run by `make report`,
after `silcount report`).

Two blocks between ``<!-- findings:start -->`` and ``<!-- findings:end -->`` are replaced by the findings of
the claims `silcount report` has just written (``reports/claims/claims.json``, read back rather than judged
again, render experiments included): in README.md the verdict counts per paper, in docs/findings.md the counts,
every FAILS with its numbers and the failed attributions.  Neither page carries a typed verdict;
``tests/test_readme.py`` checks both against :func:`silcount.papers.claims.findings_markdown`.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from silcount.atomic import write_text
from silcount.papers.claims.base import Claim
from silcount.papers.claims.rendering import findings as findings_table

START, END = "<!-- findings:start -->", "<!-- findings:end -->"
ROOT = Path(__file__).resolve().parents[1]
PAGES = ("README.md", "docs/findings.md")


def counts(findings: str) -> str:
    """The README's block: the verdict counts per paper (the findings' first table)."""
    return findings.partition("\n\n")[0].strip()


def block(page: str, findings: str) -> str:
    """The generated text of ``page`` (one of :data:`PAGES`), between the markers."""
    return f"{START}\n{counts(findings) if page == 'README.md' else findings.strip()}\n{END}"


def splice(page: str, text: str, findings: str) -> str:
    head, sep, tail = text.partition(START)
    if not sep or END not in tail:
        raise SystemExit(f"{page} has no {START} ... {END} block")
    return head + block(page, findings) + tail.partition(END)[2]


def main() -> int:
    claims = [Claim.from_json(d) for d in json.loads((ROOT / "reports" / "claims" / "claims.json").read_text())]
    findings = findings_table(claims)
    for page in PAGES:
        path = ROOT / page
        text = path.read_text()
        new = splice(page, text, findings)
        if new != text:
            write_text(path, new)
        print(f"{page} findings: {'updated' if new != text else 'unchanged'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
