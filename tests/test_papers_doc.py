"""docs/papers-as-data.md works as written: its paper's files, written out, and its commands, run."""

from __future__ import annotations

import re
import shlex
import tomllib
from pathlib import Path

import pytest
from common import forget_user_papers

from silcount.cli.main import main

DOC = Path(__file__).resolve().parent.parent / "docs" / "papers-as-data.md"
BLOCK = re.compile(r"```(\w+)\n(.*?)```", re.S)


def blocks(lang: str) -> list[str]:
    return [body for kind, body in BLOCK.findall(DOC.read_text()) if kind == lang]


@pytest.fixture(autouse=True)
def _forget_user_papers():
    yield
    forget_user_papers()


def test_the_docs_paper_and_commands_run_as_written(tmp_path, monkeypatch, capsys):
    files = 0
    for body in blocks("toml"):
        tomllib.loads(body)  # every TOML block of the page parses
        first = body.splitlines()[0]
        if first.startswith("# my-paper/"):
            path = tmp_path / first.removeprefix("# ")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(body)
            files += 1
    assert files == 2
    commands = [line.removeprefix("$ ") for body in blocks("console") for line in body.splitlines()]
    assert len(commands) == 3 and all(c.startswith("silcount ") for c in commands)
    monkeypatch.chdir(tmp_path)
    outputs = []
    for command in commands:
        assert main(shlex.split(command)[1:]) == 0, command
        outputs.append(capsys.readouterr())
    # what the page says the commands give
    assert "[1] HOLDS: Mine 2026, 2 (mine-crow-1977)" in outputs[0].out
    assert "[2] FAILS: Mine 2026, 2 (mine-crow-1980)" in outputs[0].out
    assert "the entry's year is 1977, not 1980" in outputs[0].out
    written = sorted(p.name for p in (tmp_path / "my-paper-report").iterdir())
    assert written == ["claims.json", "claims.md", "claims.txt", "rules.md"]
    assert "no operation-count table" in outputs[2].err
