"""The README and docs/ hold nothing that can go stale unseen.

* The README's verdict counts and docs/findings.md's tables are the claims' own rendering, not typed text.
* Every ``python`` block of the README runs as written, and every ``silcount`` line of its ``sh`` blocks
  (after the first, ``make report`` / ``make test``), from a folder of their own that holds ``data/``.
* Every relative link of the README and of docs/ resolves; docs/architecture.md names every module.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
PAGES = [README, *sorted((ROOT / "docs").glob("*.md"))]


def _script():
    spec = importlib.util.spec_from_file_location("readme_findings", ROOT / "scripts" / "readme_findings.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _blocks(text: str, lang: str) -> list[str]:
    return re.findall(rf"^```{lang}\n(.*?)^```$", text, flags=re.S | re.M)


def test_the_findings_are_generated_from_the_claims():
    from silcount.papers.claims import findings_markdown

    script = _script()
    findings = findings_markdown()
    for page in script.PAGES:
        text = (ROOT / page).read_text()
        assert script.splice(page, text, findings) == text, f"run `make report` to regenerate {page}'s block"
    # the README carries the counts only, the findings page every FAILS
    assert "| paper | where |" not in README.read_text() and "| paper | where |" in findings
    assert "| paper | where |" in (ROOT / "docs" / "findings.md").read_text()


def test_the_splice_replaces_only_the_block():
    script = _script()
    text = "head\n<!-- findings:start -->\nold\n<!-- findings:end -->\ntail\n"
    findings = "| counts |\n\n| every FAILS |\n"
    assert script.splice("README.md", text, findings) == (
        "head\n<!-- findings:start -->\n| counts |\n<!-- findings:end -->\ntail\n"
    )
    assert "| every FAILS |" in script.splice("docs/findings.md", text, findings)
    with pytest.raises(SystemExit):
        script.splice("README.md", "no block\n", findings)


def test_the_two_commands_open_the_readme():
    readme = README.read_text()
    assert "```sh\nmake report\nmake test\n```" in readme.split("## ")[0]
    # the README's test command is what CI runs
    assert "make test" in (ROOT / ".ci" / "run").read_text()


def test_the_readme_stays_short():
    assert len(README.read_text().splitlines()) <= 170, "move detail to docs/"


LINK = re.compile(r"\]\(([^)\s]+)\)")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_relative_link_resolves(page):
    broken = []
    for target in LINK.findall(page.read_text()):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        path = (page.parent / target.split("#")[0]).resolve()
        if not path.exists():
            broken.append(target)
    assert broken == [], f"{page.name}: {broken}"


def test_the_link_check_sees_a_broken_link(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("[a](missing.md) [b](https://example.org) [c](#anchor)\n")
    assert [t for t in LINK.findall(page.read_text()) if not re.match(r"[a-z]+:|#", t)] == ["missing.md"]


def test_the_top_level_models_is_the_packaged_folder():
    assert (ROOT / "models").is_symlink()
    assert (ROOT / "models").resolve() == (ROOT / "silcount" / "models").resolve()


def test_architecture_names_every_module():
    text = (ROOT / "docs" / "architecture.md").read_text()
    tree = text.split("```")[3]  # the repository's tree: the second code block
    named: dict[str, set[str]] = {}
    section = ""
    for line in tree.splitlines():
        m = re.match(r"  (\w+)/", line)
        if m:
            section = m.group(1)
        elif re.match(r"\S", line):
            section = "" if line.startswith("silcount/") else "outside"
        if section != "outside":
            named.setdefault(section, set()).update(re.findall(r"\b(\w+)\.py\b", line))
    actual: dict[str, set[str]] = {}
    for path in (ROOT / "silcount").rglob("*.py"):
        rel = path.relative_to(ROOT / "silcount")
        if path.name == "__init__.py" and len(rel.parts) > 1:
            continue  # a subpackage's own __init__: the subpackage is named
        actual.setdefault(rel.parts[0] if len(rel.parts) > 1 else "", set()).add(path.stem)
    for section in actual:
        missing, extra = actual[section] - named.get(section, set()), named.get(section, set()) - actual[section]
        assert not missing and not extra, f"silcount/{section}: missing {sorted(missing)}, not a file {sorted(extra)}"


@pytest.fixture
def folder(tmp_path):
    """A folder of its own that holds the repository's data/, as the README's examples expect."""
    (tmp_path / "data").symlink_to(ROOT / "data")
    return tmp_path


def _env(folder: Path) -> dict[str, str]:
    # this checkout's silcount; the corpus cache in the test's folder, not the user's
    return {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(folder / "cache")}


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(_blocks(README.read_text(), "python"))))
def test_every_python_block_of_the_readme_runs(folder, index):
    code = _blocks(README.read_text(), "python")[index]
    (folder / "example.py").write_text(code)
    done = subprocess.run(
        [sys.executable, "example.py"], cwd=folder, env=_env(folder), capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, done.stderr[-3000:]


def _commands() -> list[list[str]]:
    out = []
    for block in _blocks(README.read_text(), "sh")[1:]:  # the first is make report / make test
        out += [shlex.split(line)[1:] for line in block.splitlines() if line.startswith("silcount ")]
    return out


def test_the_readme_has_commands_to_run():
    assert len(_commands()) >= 3 and len(_blocks(README.read_text(), "python")) >= 1


@pytest.mark.slow
def test_every_silcount_line_of_the_readme_runs(folder):
    cli = "import sys; from silcount.cli.main import run; sys.argv[0] = 'silcount'; run()"
    for args in _commands():
        done = subprocess.run(
            [sys.executable, "-c", cli, *args],
            cwd=folder,
            env=_env(folder),
            capture_output=True,
            text=True,
            timeout=900,
        )
        assert done.returncode == 0, f"silcount {' '.join(args)}: {done.stderr[-2000:]}"
