"""``docs/extending.md`` runs as written: its detector module, its in-process registration, its entry point
and its commands, each in a fresh process (the registry fills once per process)."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
import tomllib

from plugins import REPO, env_with, silcount, site

DOC = (REPO / "docs" / "extending.md").read_text()


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", DOC, flags=re.S)


def test_the_tutorial_detector_registers_in_process(tmp_path):
    module, script = blocks("python")
    assert module.startswith("# my_detector.py\n")
    (tmp_path / "my_detector.py").write_text(module)
    got = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env_with(tmp_path), timeout=600
    )
    assert got.returncode == 0, got.stderr
    assert got.stdout.strip() == str(("reference", "ta", "vnv", "hsd", "eesd", "gaussmap", "cones", "mine"))


def test_the_tutorial_entry_point_puts_the_detector_in_every_command(tmp_path):
    module = blocks("python")[0]
    (toml,) = blocks("toml")
    entry_points = tomllib.loads(toml)["project"]["entry-points"]["silcount.detectors"]
    env = env_with(site(tmp_path, "my-detector", entry_points, {"my_detector": module}))
    commands = blocks("sh")[0].strip().splitlines()
    assert [c.split()[1] for c in commands] == ["audit", "corpus"]
    for command in commands:
        words = shlex.split(command)
        assert words[0] == "silcount"
        got = silcount(words[1:], env, cwd=REPO)
        assert got.returncode == 0, (command, got.stderr)
        assert got.stderr == "" and "mine" in got.stdout, command
