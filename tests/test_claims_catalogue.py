"""The claims' catalogue: every claim located, quoted and judged; verdicts follow the models and the readings.

Expected verdicts are recomputed by hand from the paper text (the sums in the comments), not read back
from silcount's own output.  The claims are the ``all_claims`` and ``by_key`` fixtures (``conftest.py``).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from silcount.counting import models
from silcount.papers import claims, formulas, projection, tables
from silcount.papers.claims import base, cells
from silcount.papers.quotes import check, papers_dir

ROOT = Path(__file__).resolve().parent.parent


def test_every_claim_is_located_quoted_and_judged(all_claims):
    assert [c.id for c in all_claims] == list(range(1, len(all_claims) + 1))
    assert len({c.key for c in all_claims}) == len(all_claims)
    for c in all_claims:
        assert c.verdict in claims.VERDICTS and c.reason and c.statement and c.quote, c.key
        assert c.paper in base.PAPER_FILE.values(), c.key
        assert c.verdict != claims.AMBIGUOUS or len(c.readings) >= 2, f"{c.key}: AMBIGUOUS needs readings"
        if c.readings:
            assert c.verdict == base.from_readings(c.readings), c.key


def test_every_quote_occurs_in_its_paper_at_its_lines(all_claims):
    root = papers_dir()
    if root is None or not root.is_dir():
        pytest.skip(f"paper texts not found ({'SILCOUNT_PAPERS_DIR is unset' if root is None else root})")
    texts = {name: (root / name).read_text() for name in base.PAPER_FILE.values()}
    bad = [f"{c.key}: lines {c.lines}" for c in all_claims if not check(texts[c.paper], c.quote, c.lines)]
    assert not bad, bad


def test_the_quote_check_can_fail():
    text = "one two\nthree four\nfive"
    assert check(text, "two three", "1-2") and check(text, "one ... five", "1-3")
    assert not check(text, "two three", "2-2") and not check(text, "two four", "1-2")
    assert not check(text, "five ... one", "1-3")


def test_no_verdict_rests_on_a_reading_called_ambiguous(by_key):
    """A claim that uses one reading of HSD's side-loop bound uses both; the HSD-model claims all do.

    That the sentence and the sum disagree is itself a FAILS (rule 15, ``tests/test_claims_two_meanings.py``);
    what depends on which one the authors meant is judged under both."""
    both = set(formulas.readings("hsd2011-hsd"))
    assert len(both) == 2 and by_key["hsd-decreased-by-one"].verdict == claims.FAILS
    users = 0
    for c in by_key.values():
        named = " ".join(r.reading for r in c.readings)
        if any(r in named for r in both):
            users += 1
            assert all(r in named for r in both), c.key
    hsd_model = [k for k in by_key if k.startswith("hsd2011-hsd ") or k.startswith("hsd-cheaper")]
    assert users >= len(hsd_model) - 2  # the substitution and expansion steps use no loop bound


def _clear_caches():
    for fn in (
        models.load,
        models.step_costs,
        formulas.charged,
        formulas.rederive,
        formulas.forms,
        formulas.printed_lines,
        formulas.convention,
        formulas.worst_case,
        formulas.witness,
        formulas.paper_forms,
        base.cycles,
        projection.analyse,
        tables._rows,
    ):
        fn.cache_clear()


def test_verdict_follows_the_models(tmp_path, monkeypatch, by_key):
    """Correct the TA Read cell of EESD Table 1 in a copy of silcount/models/: its verdict must follow."""
    copy = tmp_path / "models"
    shutil.copytree(ROOT / "silcount" / "models", copy)
    path = copy / "eesd2012-paper.toml"
    path.write_text(path.read_text().replace("read = 3110", "read = 3130"))
    monkeypatch.setenv("SILCOUNT_MODELS_DIR", str(copy))
    _clear_caches()
    try:
        after = next(c for c in cells.cell_claims() if c.key == "EESD Table 1 ta read")
    finally:
        monkeypatch.delenv("SILCOUNT_MODELS_DIR")
        _clear_caches()
    assert by_key["EESD Table 1 ta read"].verdict == claims.FAILS and after.verdict == claims.HOLDS


def test_digit_slip_names_the_conversion_suspects():
    assert "dropped" in cells.digit_slip(48600, 480600)
    assert "differs" in cells.digit_slip(3110, 3130)
    assert cells.digit_slip(100, 75) == ""


def test_every_ambiguous_verdict_says_which_reading_the_tables_use(all_claims):
    ambiguous = [c for c in all_claims if c.verdict == claims.AMBIGUOUS]
    assert ambiguous
    missing = [c.key for c in ambiguous if not c.table_reading]
    assert not missing, f"AMBIGUOUS without table_reading: {missing}"
    for c in ambiguous:
        assert "\n" not in c.table_reading and len(c.table_reading) < 400, c.key  # one line
        # either a commitment, quoting a table or figure, or the honest "none"
        assert any(w in c.table_reading for w in ("Table", "Fig.", "Figs.")), c.key


def test_the_hsd_side_loop_reading_reaches_every_claim_judged_under_it(by_key):
    text = models.load("hsd2011-hsd")["table_reading"]
    for key in ("hsd2011-hsd annotations -> line 1", "hsd2011-hsd closed form vs re-derived", "hsd-decreased-by-one"):
        assert by_key[key].table_reading == text, key
    assert "600100" in text and "540100" in text  # TA's and HSD's compares at Fig. 6's point, by hand


def test_claims_without_evidence_run_no_render_experiment_and_keep_every_verdict(all_claims, monkeypatch):
    from silcount.render import experiments

    def refuse():
        raise AssertionError("the render experiments ran without being asked for")

    monkeypatch.setattr(experiments, "stencil_step_evidence", refuse)
    quick = claims.all_claims()
    assert [(c.key, c.verdict) for c in quick] == [(c.key, c.verdict) for c in all_claims]
    with pytest.raises(AssertionError, match="without being asked"):
        claims.default_evidence()  # asking for them runs them
