"""Every JSON output validates against its JSON Schema in docs/schemas/ (real outputs, not hand-written examples)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from silcount.cli.main import main

ROOT = Path(__file__).resolve().parent.parent
SCHEMAS = ROOT / "docs" / "schemas"


def schema(name: str) -> dict:
    doc = json.loads((SCHEMAS / f"{name}.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(doc)
    return doc


def run_json(capsys, *args: str):
    capsys.readouterr()
    assert main(list(args)) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("mesh", ["tetrahedron.obj", "quad_cube.obj", "plane.obj"])
def test_audit_json_validates(capsys, mesh):
    doc = run_json(capsys, "audit", str(ROOT / "data" / mesh), "--format", "json", "--random-lights", "2",
                   "--variant", "both", "--with-edges")
    jsonschema.validate(doc, schema("audit"))


def test_committed_audits_validate():
    s = schema("audit")
    paths = sorted((ROOT / "reports" / "audit").glob("*.json"))
    assert paths
    for p in paths:
        jsonschema.validate(json.loads(p.read_text()), s)


def test_the_audit_schema_rejects_a_broken_document(capsys):
    doc = run_json(capsys, "audit", str(ROOT / "data" / "tetrahedron.obj"), "--format", "json", "--light", "0,0,5")
    del doc["detectors"]["ta"]["tallies"]["true"]["read"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(doc, schema("audit"))
