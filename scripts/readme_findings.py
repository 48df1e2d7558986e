"""Regenerate the README's findings table from the claims (run by `make report`, after `silcount report`).

The block between ``<!-- findings:start -->`` and ``<!-- findings:end -->`` in
README.md is replaced by the findings of the claims `silcount report` has just
written (``reports/claims/claims.json``, read back rather than judged again,
render experiments included), so the README never carries a typed verdict;
``tests/test_readme.py`` checks it against :func:`silcount.papers.claims.findings_markdown`.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from silcount.atomic import write_text
from silcount.papers.claims.base import Claim
from silcount.papers.claims.rendering import findings as findings_table

START, END = "<!-- findings:start -->", "<!-- findings:end -->"


def block(findings: str) -> str:
    """The README's block: the verdict counts, then every FAILS under a fold."""
    counts, _, rest = findings.partition("\n\n")
    return (
        f"{START}\n{counts.strip()}\n\n<details><summary>Every FAILS verdict, with its numbers "
        f"(generated from the claims)</summary>\n\n{rest.strip()}\n\n</details>\n{END}"
    )


def splice(readme: str, findings: str) -> str:
    head, sep, tail = readme.partition(START)
    if not sep or END not in tail:
        raise SystemExit(f"README.md has no {START} ... {END} block")
    return head + block(findings) + tail.partition(END)[2]


def main() -> int:
    root = Path(__file__).resolve().parents[1]
    path = root / "README.md"
    claims = [Claim.from_json(d) for d in json.loads((root / "reports" / "claims" / "claims.json").read_text())]
    text = path.read_text()
    new = splice(text, findings_table(claims))
    if new != text:
        write_text(path, new)
    print(f"README.md findings: {'updated' if new != text else 'unchanged'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
