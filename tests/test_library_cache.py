"""Imported as a library, silcount keeps numba's cache out of the source tree (issue 44, item 6).

The ``silcount`` command always had a default for ``NUMBA_CACHE_DIR``; ``import silcount`` from a script
had none, so numba wrote its ``*.nbi``/``*.nbc`` files into ``silcount/*/__pycache__`` and compiled every
kernel again.  Each test runs a fresh interpreter with ``NUMBA_CACHE_DIR`` unset.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["PYTHONPATH"] = str(ROOT)  # this checkout's silcount, whatever the installed one is
    return {**env, **extra}


def _run(python: str, code: str, env: dict[str, str]) -> str:
    done = subprocess.run([python, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip()


def _numba_files() -> dict[Path, float]:
    return {p: p.stat().st_mtime for ext in ("*.nbi", "*.nbc") for p in (ROOT / "silcount").rglob(ext)}


def test_a_library_import_caches_kernels_in_the_environment_not_the_tree(tmp_path):
    # a virtual environment of its own (sys.prefix = tmp_path/venv) that sees this one's packages,
    # so that the default folder is a fresh one the test can look into
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    purelib = Path(
        subprocess.check_output(
            [str(venv / "bin" / "python"), "-c", "import site; print(site.getsitepackages()[0])"], text=True
        ).strip()
    )
    (purelib / "outer.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    before = _numba_files()
    code = (
        "import silcount\n"
        "mesh = silcount.builtin_mesh('tetrahedron')\n"
        "res = silcount.detect(mesh, silcount.PointLight((0.0, 0.0, 5.0)), 'reference')\n"
        "print(silcount.__file__)\n"
    )
    where = _run(str(venv / "bin" / "python"), code, _env())
    assert Path(where).resolve().is_relative_to(ROOT), where
    cached = list((venv / "cache" / "numba").rglob("*.nbi"))
    assert cached, "no kernel was cached in the environment's folder"
    after = _numba_files()
    assert {p for p, t in after.items() if before.get(p) != t} == set(), "numba wrote into the source tree"


def test_numba_imported_first_is_told_too():
    code = (
        "import numba\nimport silcount, sys\nfrom numba.core import config\nprint(config.CACHE_DIR)\nprint(sys.prefix)"
    )
    cache_dir, prefix = _run(sys.executable, code, _env()).splitlines()
    expected = os.path.join(prefix, "cache", "numba") if sys.prefix != sys.base_prefix else None
    if expected is None:  # outside a virtual environment: the user's cache folder
        expected = os.path.join(os.path.expanduser("~"), ".cache", "silcount", "numba")
    assert cache_dir == expected


def test_outside_a_virtual_environment_the_user_cache_folder(tmp_path):
    # sys.prefix == sys.base_prefix as for a system Python; XDG_CACHE_HOME names the user's cache
    code = "import sys\nsys.prefix = sys.base_prefix\nimport silcount, os\nprint(os.environ['NUMBA_CACHE_DIR'])"
    out = _run(sys.executable, code, _env(XDG_CACHE_HOME=str(tmp_path)))
    assert out == str(tmp_path / "silcount" / "numba")


def test_the_users_setting_is_kept(tmp_path):
    code = "import silcount, os\nprint(os.environ['NUMBA_CACHE_DIR'])"
    assert _run(sys.executable, code, _env(NUMBA_CACHE_DIR=str(tmp_path))) == str(tmp_path)
