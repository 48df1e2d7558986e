"""The claims' outputs: the JSON and its schema, the frame, the findings, every format, the committed reports.

Expected verdicts are recomputed by hand from the paper text (the sums in the comments), not read back
from silcount's own output.  The claims are the ``all_claims`` and ``by_key`` fixtures (``conftest.py``).
"""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema

from silcount.cli.main import main
from silcount.papers import claims
from silcount.papers.claims import FAILS
from silcount.papers.claims.rendering import findings, render_json, render_md, render_text

ROOT = Path(__file__).resolve().parent.parent


KEYS = {
    "id",
    "key",
    "family",
    "paper",
    "where",
    "quote",
    "statement",
    "readings",
    "printed",
    "rederived",
    "measured",
    "verdict",
    "reason",
}


def test_json_keys_and_schema(capsys):
    assert main(["claims", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data and all(KEYS <= set(d) for d in data)
    schema = json.loads((ROOT / "docs" / "schemas" / "claims.schema.json").read_text())
    jsonschema.validate(data, schema)


def test_frame_and_findings(all_claims):
    df = claims.claims_frame()
    assert list(df.columns)[:4] == ["id", "key", "family", "paper"] and len(df) == len(all_claims)
    table = claims.findings_markdown()
    assert "| EESD 2012 |" in table and "FAILS" in table


def test_user_cycle_profile(tmp_path, capsys):
    prof = tmp_path / "mine.toml"
    prof.write_text('name = "mine"\n[weights]\nadd = 1\nmul = 1\ncmp = 1\nread = 100\nwrite = 100\ndiv = 1\nsqrt = 1\n')
    assert main(["claims", "--format", "text", "--cycles", str(prof)]) == 0
    assert "mine: " in capsys.readouterr().out
    assert main(["claims", "--cycles", str(tmp_path / "missing.toml")]) == 2


def test_committed_reports_are_regenerated(tmp_path):
    written = claims.report(tmp_path)
    assert [p.name for p in written] == ["claims.txt", "claims.md", "claims.json"]
    for p in written:
        assert (ROOT / "reports" / "claims" / p.name).read_text() == p.read_text(), (
            "reports/claims is stale: run silcount.papers.claims.report('reports')"
        )


def test_table_readings_are_rendered_in_md_json_and_text(all_claims):
    from silcount.papers.claims.rendering import render_json, render_md, render_text

    md = render_md(all_claims)
    section = md.split("## AMBIGUOUS verdicts: the reading the papers' own tables and figures use")[1]
    rows = [line for line in section.splitlines() if line.startswith("| ") and not line.startswith("| # ")]
    ambiguous = [c for c in all_claims if c.verdict == claims.AMBIGUOUS]
    assert len(rows) == len(ambiguous)
    assert all(row.startswith(f"| {c.id} | {c.key} |") for row, c in zip(rows, ambiguous))
    data = json.loads(render_json(all_claims))
    assert all("table_reading" in d for d in data)
    assert all(d["table_reading"] for d in data if d["verdict"] == claims.AMBIGUOUS)
    assert "    tables:    Figs. 5 and 6" in render_text(all_claims)


FOLLOWS = {
    "eesd2012-ta closed form vs re-derived": "eesd2012-ta line 2 -> line 3",
    "eesd2012-eesd closed form vs re-derived": "eesd2012-eesd annotations -> line 1",
    "hsd2011-ta closed form vs re-derived": "hsd2011-ta line 2 -> line 3",
    "EESD Table 1 ta cmp": "eesd2012-ta line 2 -> line 3",
    "EESD Table 2 ta cmp": "eesd2012-ta line 2 -> line 3",
    "EESD Table 1 eesd add": "eesd2012-eesd annotations -> line 1",
    "EESD Table 2 eesd add": "eesd2012-eesd annotations -> line 1",
    "hsd-ratios-together": "hsd-vnv-six-times",
    # line 1 is exceeded only in Add, the 6n^2 Adds it leaves out of its own annotations
    "eesd2012-eesd line 1 upper bound": "eesd2012-eesd annotations -> line 1",
    "eesd-visibility": "eesd-normal",  # the sum of the normal, light-ray, dot and sign costs
    "eesd-gorman-ratio": "eesd-mesh-size",  # V/F = 2, E/V = 3: V = 2n, E = 6n again
    "eesd-vnv-visibility": "eesd-normal",  # VnV's copy of the visibility annotation
    "hsd-visibility": "hsd-normal",  # the HSD paper's own sum of the same costs
    "eesd-step4": "eesd-pseudocode",  # the Sec. 3.3 loops written as a sum
    "hsd-vnv-ray-from-eye": "hsd-ta-ray-from-eye",  # the facing test's ray from the eye, said again for VnV
}


def test_restated_slips_name_the_claim_they_follow_from(all_claims, by_key):
    """Issue 24: a FAILS that restates another FAILS at another place is kept and marked, in every format."""
    assert {c.key: c.follows_from for c in all_claims if c.follows_from} == FOLLOWS
    for key, source in FOLLOWS.items():
        assert by_key[key].verdict == by_key[source].verdict == FAILS
    assert not by_key["EESD Table 1 ta read"].follows_from  # a typo in the cell is the cell's own erratum
    data = {c["key"]: c for c in json.loads(render_json(all_claims))}
    assert all(data[k]["follows_from"] == v for k, v in FOLLOWS.items())
    assert data["eesd-dot"]["follows_from"] is None
    jsonschema.validate(list(data.values()), json.loads((ROOT / "docs/schemas/claims.schema.json").read_text()))
    assert "    follows:   eesd2012-ta line 2 -> line 3" in render_text(all_claims)
    assert "| eesd2012-ta line 2 -> line 3 |" in render_md(all_claims)
    fails = sum(c.verdict == FAILS for c in all_claims)
    row = f"| all | {len(all_claims)} |"
    line = next(x for x in findings(all_claims).splitlines() if x.startswith(row))
    assert f"| {fails} | {fails - len(FOLLOWS)} |" in line
    assert "of them independent errata" in findings(all_claims)


def test_claims_read_back_from_json_render_the_same_findings(all_claims):
    # scripts/readme_findings.py rebuilds the README's table from reports/claims/claims.json
    from silcount.papers.claims.base import Claim

    back = [Claim.from_json(d) for d in json.loads(render_json(all_claims))]
    assert back == all_claims
    assert findings(back) == findings(all_claims)
