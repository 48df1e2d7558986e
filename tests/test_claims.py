"""The claims report: computed verdicts, regenerated reports, the CLI.

Verdicts are never typed: the test that edits a copy of models/ shows that a
verdict follows the data (a corrected table cell turns FAILS into HOLDS).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from silcount.cli.main import main
from silcount.counting import paper as models
from silcount.papers import claims, formulas, projection, tables

ROOT = Path(__file__).resolve().parent.parent
KEYS = {"id", "paper", "section", "statement", "printed", "rederived", "measured", "verdict", "reason"}


def _clear_caches():
    for fn in (
        models.load,
        models.step_costs,
        formulas.charged,
        formulas.rederive,
        formulas.forms,
        formulas.printed_lines,
        formulas.rederivation_differences,
        claims._cycles_cached,
        projection.analyse,
        tables.cells,
        tables._measured,
    ):
        fn.cache_clear()


@pytest.fixture(scope="module")
def all_claims():
    return claims.all_claims(real=False)


def test_every_claim_has_a_verdict_and_a_reason(all_claims):
    assert [c.id for c in all_claims] == list(range(1, len(all_claims) + 1))
    assert len({c.key for c in all_claims}) == len(all_claims)
    for c in all_claims:
        assert c.verdict in (claims.HOLDS, claims.FAILS, claims.AMBIGUOUS)
        assert c.reason and c.statement and c.printed


def test_every_models_claim_and_cell_is_reported(all_claims):
    keys = {c.key for c in all_claims}
    for paper_file in claims.PAPER_FILES:
        for c in models.load(paper_file).get("claims", []):
            assert c["id"] in keys
    n_cells = sum(
        len(r["cells"])
        for pf in claims.PAPER_FILES
        for t in models.load(pf).get("tables", [])
        for r in t["rows"]
        if "cells" in r
    )
    assert sum(c.key.startswith("EESD Table") for c in all_claims) == n_cells == 30


def test_json_keys(capsys):
    assert main(["claims", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data and all(KEYS <= set(d) for d in data)


def test_user_cycle_profile(tmp_path, capsys):
    prof = tmp_path / "mine.toml"
    prof.write_text('name = "mine"\n[weights]\nadd = 1\nmul = 1\ncmp = 1\nread = 100\nwrite = 100\n')
    assert main(["claims", "--format", "text", "--cycles", str(prof)]) == 0
    assert "mine: " in capsys.readouterr().out
    assert main(["claims", "--cycles", str(tmp_path / "missing.toml")]) == 2


def test_verdict_follows_the_models(tmp_path, monkeypatch):
    """Correct the TA Read cell of EESD Table 1 in a copy of models/: its verdict must follow."""
    copy = tmp_path / "models"
    shutil.copytree(ROOT / "models", copy)
    path = copy / "eesd2012-paper.toml"
    rederived = formulas.evaluate(formulas.forms("eesd2012-ta")["rederived"], n=10, m=5)["read"]
    text = path.read_text().replace("read = 3110", f"read = {int(rederived)}")
    path.write_text(text)
    key = "EESD Table 1 ta read"
    before = next(c for c in claims.all_claims(real=False) if c.key == key)
    monkeypatch.setenv("SILCOUNT_MODELS_DIR", str(copy))
    _clear_caches()
    try:
        after = next(c for c in claims.all_claims(real=False) if c.key == key)
    finally:
        monkeypatch.delenv("SILCOUNT_MODELS_DIR")
        _clear_caches()
    assert before.verdict == claims.FAILS and before.printed == "3110"
    assert after.verdict == claims.HOLDS


def test_digit_slip_names_the_conversion_suspects():
    assert "dropped" in claims.digit_slip(48600, 480600)
    assert "differs" in claims.digit_slip(3110, 3130)
    assert claims.digit_slip(100, 75) == ""


@pytest.mark.parametrize("name", ["claims.txt", "claims.md", "claims.json"])
def test_committed_reports_are_regenerated(tmp_path, name):
    written = claims.report(tmp_path)
    tmp_path = tmp_path / "claims"
    assert [p.name for p in written] == ["claims.txt", "claims.md", "claims.json"]
    committed = ROOT / "reports" / "claims" / name
    assert committed.read_text() == (tmp_path / name).read_text(), (
        "reports/claims is stale: run `silcount report` (or claims.report('reports'))"
    )
