"""The `silcount audit` and `silcount report` command lines: options, formats, outputs, streams."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from common import run_cli
from meshfiles import tetra_bytes, write

import silcount
from silcount.cli import report as report_cmd


@pytest.fixture
def tetra(tmp_path) -> Path:
    return write(tmp_path, "tetra.obj", tetra_bytes("obj"))


def test_no_arguments_prints_help():
    rc, out, err = run_cli()
    assert rc == 0 and "audit" in out and "report" in out and err == ""


def test_default_text_audit_has_both_cost_models(tetra):
    rc, out, err = run_cli("audit", str(tetra), "--random-lights", "2", "--quiet")
    assert rc == 0 and err == ""
    assert "Detectors, paper cost model (summed over the lights)" in out
    assert "Detectors, true cost model" in out and "Lights (2)" in out


def test_markdown_audit(tetra):
    rc, out, _ = run_cli("audit", str(tetra), "--light", "0,0,5", "--format", "md", "--detectors", "reference")
    assert rc == 0 and out.startswith("# silcount audit of")
    assert [c.strip() for c in out.split("| detector")[1].split("\n")[0].split("|")][1:3] == ["edges", "agrees"]


def test_json_audit_with_explicit_lights_only(tetra):
    rc, out, err = run_cli(
        "audit",
        str(tetra),
        "--light",
        "0,0,5",
        "--directional",
        "1,0,0",
        "--format",
        "json",
        "--detectors",
        "reference",
    )
    assert rc == 0 and err == ""
    doc = json.loads(out)  # progress and notes never reach stdout
    assert [l["kind"] for l in doc["lights"]] == ["point", "directional"]
    assert doc["lights"][1]["direction"] == [1.0, 0.0, 0.0]
    assert len(doc["per_light"]) == 2


def test_random_lights_added_to_explicit_ones_and_seeded(tetra):
    args = (
        "audit",
        str(tetra),
        "--light",
        "0,0,5",
        "--random-lights",
        "3",
        "--format",
        "json",
        "--detectors",
        "reference",
    )
    a = json.loads(run_cli(*args, "--seed", "7")[1])
    b = json.loads(run_cli(*args, "--seed", "7")[1])
    c = json.loads(run_cli(*args, "--seed", "8")[1])
    assert len(a["lights"]) == 4 and a["lights"] == b["lights"] and a["lights"] != c["lights"]


def test_variant_both_reports_intended_and_literal(tetra):
    rc, out, _ = run_cli(
        "audit", str(tetra), "--light", "0,0,5", "--variant", "both", "--format", "json", "--detectors", "reference,ta"
    )
    doc = json.loads(out)
    assert set(doc["detectors"]) == {"reference", "ta", "ta:literal"}
    assert doc["detectors"]["ta:literal"]["variant"] == "literal"


def test_naive_engine_gives_the_fast_engines_tallies(tetra):
    def tallies(engine):
        rc, out, _ = run_cli(
            "audit", str(tetra), "--random-lights", "2", "--engine", engine, "--format", "json", "--variant", "both"
        )
        assert rc == 0
        return {k: (d["silhouette_edges"], d["tallies"], d["steps"]) for k, d in json.loads(out)["detectors"].items()}

    assert tallies("naive") == tallies("fast")


def test_unit_and_file_cycle_profiles(tetra, tmp_path):
    rc, out, _ = run_cli(
        "audit", str(tetra), "--light", "0,0,5", "--cycles", "unit", "--format", "json", "--detectors", "reference"
    )
    d = json.loads(out)["detectors"]["reference"]
    assert d["cycles"]["true"] == sum(d["tallies"]["true"][k] for k in ("add", "mul", "cmp", "read", "write"))
    weights = "add = 0\nmul = 0\ncmp = 0\nread = 10\nwrite = 0\ndiv = 0\nsqrt = 0\n"
    prof = write(tmp_path, "mine.toml", "[weights]\n" + weights)
    rc, out, _ = run_cli(
        "audit", str(tetra), "--light", "0,0,5", "--cycles", str(prof), "--format", "json", "--detectors", "reference"
    )
    d = json.loads(out)["detectors"]["reference"]
    assert rc == 0 and d["cycles"]["true"] == 10 * d["tallies"]["true"]["read"]


def test_out_file_is_written_and_stdout_stays_empty(tetra, tmp_path):
    target = tmp_path / "sub" / "audit.json"
    rc, out, err = run_cli("audit", str(tetra), "--light", "0,0,5", "--format", "json", "--out", str(target))
    assert rc == 0 and out == "" and str(target) in err
    assert json.loads(target.read_text())["source"] == str(tetra)
    assert [p.name for p in target.parent.iterdir()] == ["audit.json"]  # no temporary file left behind


def test_no_mesh_audits_every_builtin_mesh(tmp_path):
    rc, out, _ = run_cli("audit", "--random-lights", "1", "--detectors", "reference", "--format", "json")
    docs = json.loads(out)
    assert rc == 0 and [d["mesh"]["name"] for d in docs] == list(silcount.mesh.shapes.BUILTIN)
    rc, _, err = run_cli(
        "audit", "--random-lights", "1", "--detectors", "reference", "--format", "md", "--out", str(tmp_path / "all")
    )
    assert rc == 0 and sorted(p.name for p in (tmp_path / "all").iterdir()) == sorted(
        f"{n}.md" for n in silcount.mesh.shapes.BUILTIN
    )


def test_report_runs_each_part_and_prints_where_it_wrote(tmp_path, monkeypatch):
    monkeypatch.setattr(report_cmd, "report_meshes", lambda: ("tetrahedron",))
    monkeypatch.setattr(report_cmd, "PARTS", ())
    rc, out, _ = run_cli("report", "--out", str(tmp_path))
    assert rc == 0
    assert "audit: wrote 2 files" in out and str(tmp_path / "audit" / "tetrahedron.md") in out
    assert json.loads((tmp_path / "audit" / "tetrahedron.json").read_text())["detectors"]["reference"]["time_s"] is None


def test_negative_light_coordinates_need_no_equals_sign(tetra):
    rc, out, err = run_cli(
        "audit",
        str(tetra),
        "--light",
        "-1,-2,5",
        "--directional",
        "-.5,0,1",
        "--format",
        "json",
        "--detectors",
        "reference",
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["lights"][0]["position"] == [-1.0, -2.0, 5.0] and doc["lights"][1]["direction"] == [-0.5, 0.0, 1.0]
