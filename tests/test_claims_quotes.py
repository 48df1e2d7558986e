"""Every quote stored in silcount/models/ occurs in its paper, over its stored lines (whitespace-insensitive).

Checks the data without building the claims (fast): the claims files (with the
captions and rows their ``table_reading`` cites), the table rows, the per-line
annotations and the printed closed-form lines.
"""

from __future__ import annotations

import pytest

from silcount.counting import models
from silcount.papers import registry
from silcount.papers.quotes import check, papers_dir

CLAIM_FILES = registry.claim_files()
ALGORITHMS = tuple(name for p in registry.builtin() for name in p.algorithms)


def _quotes():
    for name in CLAIM_FILES:
        data = models.load(name)
        for c in data["claims"]:
            yield f"{name}:{c['id']}", c.get("paper", data["source_file"]), c["quote"], c["lines"]
            for prefix in ("ref_", "earlier_", "table_", "entries_"):
                if f"{prefix}quote" in c:
                    yield f"{name}:{c['id']}:{prefix}", data["source_file"], c[f"{prefix}quote"], c[f"{prefix}lines"]
    for name in ("eesd2012-paper",):
        data = models.load(name)
        for t in data["tables"]:
            for r in t["rows"]:
                yield f"{t['id']}:{r['algorithm']}", data["source_file"], r["quote"], r["lines"]
    for name in ALGORITHMS:
        data = models.load(name)
        for step, spec in data["steps"].items():
            yield f"{name}:{step}", data["source_file"], spec["quote"], spec["lines"]
        for i, line in enumerate(data["closed_form"]["lines"]):
            yield f"{name}:line {i + 1}", data["source_file"], line.get("quote", line["printed"]), line["lines"]
        if "table_quote" in data:
            yield f"{name}:table_reading", data["source_file"], data["table_quote"], data["table_lines"]


QUOTES = list(_quotes())


@pytest.mark.parametrize("where, paper, quote, lines", QUOTES, ids=[q[0] for q in QUOTES])
def test_quote_is_in_the_paper(where, paper, quote, lines):
    root = papers_dir()
    if root is None or not root.is_dir():
        pytest.skip(f"paper texts not found ({'SILCOUNT_PAPERS_DIR is unset' if root is None else root})")
    assert check((root / paper).read_text(), quote, lines), f"{where}: not at lines {lines}"
