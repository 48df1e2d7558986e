"""Papers as data: the built-in papers' folders, a user's paper with ``--paper DIR``, the ``silcount.papers``
entry points, and a broken paper: one line naming it, the built-ins still working (docs/papers-as-data.md)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest
from common import forget_user_papers

from silcount.cli.main import main
from silcount.counting import models
from silcount.papers import plugins, registry
from silcount.papers.claims import all_claims
from silcount.papers.claims.context import Evidence
from silcount.papers.claims.rendering import render_md, rules_markdown

ROOT = Path(__file__).resolve().parent.parent
NO_EVIDENCE = Evidence(exponents=())  # the rules these papers name measure nothing

# A reference list entry and two attributions to it, one with the entry's year and one without (by hand).
REFERENCES = """\
# A small paper of two attributions, checked against its own reference list.
source_file = "tiny"
title = "a tiny paper"

[[claims]]
id = "tiny-right-year"
section = "2"
statement = "Crow proposed shadow volumes in 1977"
printed = "Crow [1], 1977"
check = "citation"
author = "Crow"
year = 1977
ref_quote = "[1] F. C. Crow. Shadow algorithms for computer graphics. SIGGRAPH 1977."
ref_lines = "40-40"

[[claims]]
id = "tiny-wrong-year"
section = "2"
statement = "Crow proposed shadow volumes in 1980"
printed = "Crow [1], 1980"
check = "citation"
author = "Crow"
year = 1980
ref_quote = "[1] F. C. Crow. Shadow algorithms for computer graphics. SIGGRAPH 1977."
ref_lines = "40-40"
"""
MANIFEST = """\
id = "tiny"
label = "Tiny 2026"
title = "A tiny paper"
citation = "Someone, 2026"
algorithms = []
tables = []
claims = ["tiny-claims"]
"""


def make_paper(folder: Path, claims: str = REFERENCES, manifest: str = MANIFEST) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "paper.toml").write_text(manifest)
    (folder / "tiny-claims.toml").write_text(claims)
    return folder


@pytest.fixture(autouse=True)
def _forget_user_papers():
    """Each test reads its own folders: drop the model names and papers earlier tests added."""
    yield
    forget_user_papers()


def test_the_builtin_papers_are_the_package_folders():
    folders = sorted(p.name for p in (ROOT / "silcount" / "models" / "papers").iterdir())
    papers = registry.builtin()
    assert [p.id for p in papers] == folders == ["eesd2012", "hsd2011", "stencil2011"]
    for p in papers:
        for name in (*p.algorithms, *p.tables, *p.claims):
            assert models.model_path(name) == ROOT / "silcount" / "models" / "papers" / p.id / f"{name}.toml"
        assert p.text_path() is not None and p.text_path().name == p.text


def test_a_users_paper_is_judged_by_the_generic_rules(tmp_path):
    paper = plugins.from_folders([make_paper(tmp_path / "tiny")])
    claims = all_claims(NO_EVIDENCE, paper)
    assert [(c.key, c.verdict) for c in claims] == [("tiny-right-year", "HOLDS"), ("tiny-wrong-year", "FAILS")]
    assert [c.id for c in claims] == [1, 2] and {c.paper for c in claims} == {"tiny"}
    md = render_md(claims)
    assert "| Tiny 2026 | 2 | 1 | 1 | 1 | 0 |" in md
    assert "Tiny 2026 (Someone, 2026): silcount has no text of this paper, so no quote is checked" in md
    rules = rules_markdown(claims)
    assert "| a citation against the paper's own reference list | 2 |" in rules
    assert "single-claim rule: 0 of 2" in rules


TEXT = "A tiny paper.\n\nShadow volumes were\nproposed by Crow in 1977 [1].\n"


@pytest.mark.parametrize("lines, code", [("4-4", 0), ("1-2", 3)])
def test_a_paper_with_a_text_has_its_quotes_checked_at_their_lines(tmp_path, capsys, lines, code):
    quotes = iter(['quote = "Shadow volumes were ... Crow"\nlines = "3-4"', f'quote = "in 1977"\nlines = "{lines}"'])
    quoted = re.sub('section = "2"', lambda m: f"{m.group(0)}\n{next(quotes)}", REFERENCES)
    quoted = quoted.replace('source_file = "tiny"', 'source_file = "tiny.txt"')  # the text's name
    folder = make_paper(tmp_path / "texted", quoted, MANIFEST + 'text = "tiny.txt"\n')
    (folder / "tiny.txt").write_text(TEXT)
    assert main(["claims", "--paper", str(folder), "--no-render", "--format", "json"]) == code
    out = capsys.readouterr()
    if code:  # by hand: "in 1977" is on line 4 of TEXT, not on lines 1-2
        (line,) = out.err.strip().splitlines()
        assert str(folder) in line and "'tiny-wrong-year'" in line and "not at lines 1-2 of tiny.txt" in line
    else:
        assert [c["quote"] for c in json.loads(out.out)] == ["Shadow volumes were ... Crow", "in 1977"]


def test_a_claim_carries_its_citation_where_there_is_no_text(tmp_path):
    cited = REFERENCES.replace('section = "2"', 'citation = "Crow, SIGGRAPH 1977"\nsection = "Table 1"', 1)
    (claim, _) = all_claims(NO_EVIDENCE, plugins.from_folders([make_paper(tmp_path / "tiny", cited)]))
    assert claim.where == "Crow, SIGGRAPH 1977, Table 1"


def test_the_report_lists_the_claims_a_single_claim_rule_judged():
    text = (ROOT / "reports" / "claims" / "rules.md").read_text()
    assert "| 71 | EESD 2012 | eesd-plane-test-logic | `plane_test` |" in text  # Sec. 5.3's own rule
    assert "kernel_cost" not in text  # a primitive's cost is a generic kind


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("command", ["claims", "tables", "figures", "audit"])
def test_a_paper_whose_toml_does_not_parse_fails_with_one_line_naming_it(tmp_path, capsys, command):
    folder = make_paper(tmp_path / "broken", claims="[[claims]\nid = ")
    args = [command, "--paper", str(folder)] + (["--out", str(tmp_path / "out")] if command == "figures" else [])
    if command == "audit":
        args += [str(ROOT / "data" / "tetrahedron.obj"), "--light", "5,5,5"]
    assert main(args) == 3
    line = _one_error_line(capsys)
    assert str(folder) in line and "tiny-claims.toml" in line


def test_a_paper_naming_a_check_that_does_not_exist_fails_with_one_line_naming_it(tmp_path, capsys):
    folder = make_paper(tmp_path / "unknown", REFERENCES.replace('check = "citation"', 'check = "no_such_rule"', 1))
    assert main(["claims", "--paper", str(folder)]) == 3
    line = _one_error_line(capsys)
    assert str(folder) in line and "'tiny-right-year'" in line and "'no_such_rule'" in line


def test_a_claims_file_must_name_its_paper(tmp_path, capsys):
    folder = make_paper(tmp_path / "other", REFERENCES.replace('source_file = "tiny"', 'source_file = "other"'))
    assert main(["claims", "--paper", str(folder)]) == 3
    assert "source_file 'other' is not the paper's 'tiny'" in _one_error_line(capsys)


def test_a_paper_may_not_redefine_a_builtin_model(tmp_path, capsys):
    folder = make_paper(
        tmp_path / "clash", manifest=MANIFEST.replace("algorithms = []", 'algorithms = ["eesd2012-ta"]')
    )
    shutil.copy(models.model_path("eesd2012-ta"), folder / "eesd2012-ta.toml")
    assert main(["tables", "--paper", str(folder)]) == 3
    assert "'eesd2012-ta'" in _one_error_line(capsys)


def _entry_points(monkeypatch, points: dict[str, object]) -> None:
    """Installed entry points of the group silcount.papers, as importlib.metadata lists them."""
    eps = [
        SimpleNamespace(name=name, value=f"plugin_{name}:PAPER", load=lambda obj=obj: obj)
        for name, obj in points.items()
    ]
    import importlib.metadata

    real = importlib.metadata.entry_points

    def entry_points(**select):
        return eps if select.get("group") == plugins.ENTRY_POINT_GROUP else real(**select)

    monkeypatch.setattr(importlib.metadata, "entry_points", entry_points)


def test_an_entry_point_paper_is_read_and_a_broken_one_left_out_with_one_line(tmp_path, monkeypatch):
    good = make_paper(tmp_path / "good")
    bad = make_paper(tmp_path / "bad", REFERENCES.replace('check = "citation"', 'check = "nope"', 1))
    _entry_points(monkeypatch, {"good": str(good), "bad": lambda: bad, "raises": _raise})
    said: list[str] = []
    found = plugins.plugins(said.append)
    assert [p.id for p in found] == ["tiny"] and found[0].folder == good
    assert len(said) == 2
    assert "entry point 'bad'" in said[0] and "'nope'" in said[0] and "left out" in said[0]
    assert "entry point 'raises'" in said[1] and "RuntimeError: the plugin's own import failed" in said[1]


def _raise():
    raise RuntimeError("the plugin's own import failed")


def test_a_broken_entry_point_leaves_the_builtin_tables_byte_identical(tmp_path, monkeypatch, capsys):
    _entry_points(monkeypatch, {"broken": str(make_paper(tmp_path / "broken", claims="not toml ["))})
    assert main(["tables", "--format", "csv"]) == 0
    out = capsys.readouterr()
    assert out.out == (ROOT / "reports" / "tables" / "tables.csv").read_text()
    (line,) = out.err.strip().splitlines()
    assert "entry point 'broken'" in line and "tiny-claims.toml" in line


def test_audit_sets_a_users_closed_form_beside_the_measurement(tmp_path, capsys):
    folder = make_paper(tmp_path / "mine", manifest=MANIFEST.replace("algorithms = []", 'algorithms = ["mine-ta"]'))
    shutil.copy(models.model_path("eesd2012-ta"), folder / "mine-ta.toml")
    mesh = ROOT / "data" / "tetrahedron.obj"
    common = [str(mesh), "--detectors", "ta", "--light", "5,5,5", "--format", "json", "--quiet"]
    assert main(["audit", *common]) == 0
    builtin = json.loads(capsys.readouterr().out)["detectors"]["ta"]["formula_printed"]
    assert main(["audit", *common, "--paper", str(folder)]) == 0
    mine = json.loads(capsys.readouterr().out)["detectors"]["ta"]["formula_printed"]
    assert builtin["model"] == "eesd2012-ta" and mine["model"] == "mine-ta"
    assert {k: v for k, v in mine.items() if k != "model"} == {k: v for k, v in builtin.items() if k != "model"}


def test_import_silcount_reads_no_paper_and_no_entry_point():
    code = (
        "import sys, silcount; "
        "print(sorted(m for m in sys.modules if m.startswith(('silcount.papers', 'importlib.metadata'))))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def test_the_uv_sphere_is_gooch_et_al_s_78804_face_sphere():
    from silcount.mesh.shapes import uv_sphere

    mesh = uv_sphere(199, 199)
    assert mesh.n_faces == 78_804  # Gooch et al., I3D 1999, Table 1
    assert mesh.n_vertices - mesh.n_edges + mesh.n_faces == 2  # a closed genus-0 mesh
    small = uv_sphere(4, 3)  # by hand: 4 + 4 fan triangles and one band of 4 quads: 16 triangles, 10 vertices
    assert (small.n_faces, small.n_vertices, small.n_edges) == (16, 10, 24)


LITERATURE = ROOT / "examples" / "literature-paper"


def test_the_literature_paper_is_data_only_and_its_report_validates():
    assert sorted(p.suffix for p in LITERATURE.iterdir()) == [".toml", ".toml"]  # no Python of its own
    (paper,) = plugins.from_folders([LITERATURE])  # every check it names is registered
    assert paper.text == "" and paper.source == "literature"
    import jsonschema

    schema = json.loads((ROOT / "docs" / "schemas" / "claims.schema.json").read_text())
    report = json.loads((ROOT / "reports" / "literature-paper" / "claims.json").read_text())
    jsonschema.validate(report, schema)
    assert [c["key"] for c in report] == [c["id"] for c in models.load("literature-claims")["claims"]]


def test_a_measured_verdict_is_the_measurements_not_the_printed_number(tmp_path):
    from silcount.papers import measure

    run = measure.measure("reference", "tetrahedron", 4, 0)
    assert (run.faces, run.edges, run.visited) == (4, 6, 6.0)  # the yardstick examines every edge, by hand
    claim = """\
source_file = "tiny"
[[claims]]
id = "same"
section = "1"
statement = "the reference does less than itself"
printed = "PRINTED"
check = "measured_comparison"
meshes = ["tetrahedron"]
first = "reference"
second = "reference"
quantities = ["visited"]
lights = 4
"""
    verdicts = set()
    for printed in ("10x faster", "no faster"):
        folder = make_paper(tmp_path / printed.replace(" ", "-"), claim.replace("PRINTED", printed))
        (c,) = all_claims(NO_EVIDENCE, plugins.from_folders([folder]))
        verdicts.add(c.verdict)
        forget_user_papers()
    assert verdicts == {"FAILS"}  # 6 edges against 6: not fewer, whatever the paper prints


def test_a_log_ratio_judged_at_each_tolerance_a_reading(tmp_path):
    """The reference visits all 6 of the tetrahedron's 6 edges (by hand): log 6 / log E = 1.0, which is 0.9
    within 0.2 and not within 0.05, so the two tolerances as readings give AMBIGUOUS."""
    claim = """\
source_file = "tiny"
[[claims]]
id = "ratio"
section = "1"
statement = "log visited / log E is about 0.9"
printed = "0.9"
check = "measured_log_ratio"
table_reading = "none"
mesh = "tetrahedron"
quantity = "visited"
against = "E"
exponent = 0.9
lights = 4
readings = [{ name = "to 0.05", tolerance = 0.05 }, { name = "to 0.2", tolerance = 0.2 }]
"""
    (c,) = all_claims(NO_EVIDENCE, plugins.from_folders([make_paper(tmp_path / "p", claim)]))
    assert [(r.reading, r.holds) for r in c.readings] == [("to 0.05", False), ("to 0.2", True)]
    assert c.verdict == "AMBIGUOUS" and "1.000" in c.readings[0].outcome
