"""Regenerate the README's findings table from the claims (run by `make report`).

The block between ``<!-- findings:start -->`` and ``<!-- findings:end -->`` in
README.md is replaced by :func:`silcount.papers.claims.findings_markdown`, so
the README never carries a typed verdict; ``tests/test_readme.py`` checks it.
"""

from __future__ import annotations

import sys
from pathlib import Path

from silcount.atomic import write_text
from silcount.papers.claims import findings_markdown

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
    path = Path(__file__).resolve().parents[1] / "README.md"
    text = path.read_text()
    new = splice(text, findings_markdown())
    if new != text:
        write_text(path, new)
    print(f"README.md findings: {'updated' if new != text else 'unchanged'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
