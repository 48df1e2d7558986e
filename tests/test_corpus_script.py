"""``silcount.corpus`` works from a plain script, with no ``if __name__ == "__main__":`` guard (issue 44, item 6).

Its worker processes are spawned; a spawned process used to run the caller's main script again, so an
unguarded call failed with multiprocessing's "bootstrapping phase" RuntimeError, and a script piped through
stdin with ``FileNotFoundError: '<stdin>'``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

SCRIPT = """\
import silcount

print("top level ran")
study = silcount.corpus(["meshes"], lights=2, detectors=["reference"], workers=2, cache=False, quiet=True)
print(len(study.rows), study.failed)
"""


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "meshes").mkdir()
    for name in ("tetrahedron.obj", "icosahedron.obj"):
        shutil.copy(ROOT / "data" / name, tmp_path / "meshes" / name)
    (tmp_path / "sweep.py").write_text(SCRIPT)
    return tmp_path


def _check(done: subprocess.CompletedProcess) -> None:
    assert done.returncode == 0, done.stderr[-3000:]
    # the script's top level ran once, in this process only: 2 meshes x 2 lights x 1 detector
    assert done.stdout.splitlines() == ["top level ran", "4 0"], done.stdout


@pytest.mark.slow
def test_an_unguarded_script(folder):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    _check(
        subprocess.run([sys.executable, "sweep.py"], cwd=folder, env=env, capture_output=True, text=True, timeout=600)
    )


@pytest.mark.slow
def test_a_script_on_stdin(folder):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-"], input=SCRIPT, cwd=folder, env=env, capture_output=True, text=True, timeout=600
    )
    _check(done)
