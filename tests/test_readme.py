"""The README's findings table is the claims' own rendering, not typed text."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _script():
    spec = importlib.util.spec_from_file_location("readme_findings", ROOT / "scripts" / "readme_findings.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_findings_are_generated_from_the_claims():
    from silcount.papers.claims import findings_markdown

    script = _script()
    readme = (ROOT / "README.md").read_text()
    assert script.splice(readme, findings_markdown()) == readme, "run `make report` to regenerate the README block"


def test_the_two_commands_open_the_readme():
    readme = (ROOT / "README.md").read_text()
    assert "```sh\nmake report\nmake test\n```" in readme.split("## ")[0]
