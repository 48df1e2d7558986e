"""SLOW, OFFLINE: ``examples/edge-detector`` installed into a fresh virtual environment beside silcount, then
found through its entry point by ``silcount audit``, ``silcount corpus`` and ``silcount render --detector``.

The environment is made without pip (``venv --without-pip``); a ``.pth`` file adds this interpreter's own
site folder (numpy, numba, ..., pip and setuptools) behind the new one, and ``PYTHONPATH`` this checkout, so
nothing is downloaded: pip installs the copy of the example with ``--no-index --no-deps
--no-build-isolation`` (setuptools from that site folder builds it).  Where that setuptools cannot build a
wheel offline (before 70.1 without the ``wheel`` package), setuptools' ``egg_info`` writes the example's
metadata into the site folder instead and the package is copied beside it (:func:`_install`).  About a
minute on a quiet machine.
"""

from __future__ import annotations

import importlib.util
import json
import shutil
import subprocess
import sys
import sysconfig
from importlib import metadata
from pathlib import Path

import pytest
from plugins import REPO, env_with, scene

EXAMPLE = REPO / "examples" / "edge-detector"


def _run(command: list[str], env: dict[str, str], cwd=None) -> subprocess.CompletedProcess:
    got = subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd, timeout=600)
    assert got.returncode == 0, f"{command[:6]}: {got.stderr[-2000:]}"
    return got


def _can_build_wheels() -> bool:
    """setuptools builds wheels offline with its own ``bdist_wheel`` (70.1 on) or the ``wheel`` package's."""
    version = tuple(int(p) for p in metadata.version("setuptools").split(".")[:2])
    return version >= (70, 1) or importlib.util.find_spec("wheel") is not None


def _install(python: str, source, purelib, env: dict[str, str]) -> None:
    """pip installs the example (offline, no build isolation); where setuptools cannot build a wheel here,
    setuptools writes the example's metadata (``egg_info``: its entry points read from its pyproject.toml)
    into the environment's site folder and the package is copied beside it, as pip would place them."""
    if _can_build_wheels():
        _run([python, "-m", "pip", "install", "--quiet", "--no-index", "--no-deps", "--no-build-isolation",
              str(source)], env)  # fmt: skip
        return
    _run([python, "-c", "from setuptools import setup; setup()", "egg_info", "--egg-base", str(purelib)], env, source)
    shutil.copytree(source / "silcount_edge_detector", purelib / "silcount_edge_detector")


@pytest.mark.slow
def test_the_example_installs_beside_silcount_and_runs_in_its_commands(tmp_path):
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", str(venv)], env_with())
    python = str(venv / "bin" / "python")
    env = env_with()
    where = _run([python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], env).stdout.strip()
    purelib = Path(where)
    assert purelib.is_relative_to(venv)
    (purelib / "beside.pth").write_text(f"import site; site.addsitedir({sysconfig.get_path('purelib')!r})\n")
    source = tmp_path / "edge-detector"  # a copy: the build writes its metadata beside the sources
    shutil.copytree(EXAMPLE, source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    _install(python, source, purelib, env)

    silcount = [python, "-m", "silcount.cli.main"]
    got = _run([*silcount, "audit", "data/icosphere1.obj", "--format", "json", "--quiet"], env, cwd=REPO)
    audit = json.loads(got.stdout)
    assert got.stderr == ""
    assert audit["settings"]["detectors"][-1] == "vtk-edge"
    edge = audit["detectors"]["vtk-edge"]
    assert edge["agrees_with_reference"] and set(edge["tallies"]) == {"paper", "true"}
    assert edge["steps"]["edge_test"] == 16 * 120  # 16 lights x the E = 120 edges of icosphere1

    got = _run([*silcount, "corpus", "data/tetrahedron.obj", "data/icosphere1.obj", "--lights", "2",
                "--detectors", "reference,vtk-edge", "--scheduler", "threads", "--workers", "1", "--no-cache",
                "--quiet", "--format", "json"], env, cwd=REPO)  # fmt: skip
    meshes = json.loads(got.stdout)["meshes"]
    assert [m["file"].rsplit("/", 1)[-1] for m in meshes] == ["icosphere1.obj", "tetrahedron.obj"]
    for m in meshes:  # the closed meshes: VTK's rule is the reference there; no plain loops, no time
        edge = m["detectors"]["vtk-edge"]
        assert edge["missed_edges"] == edge["extra_edges"] == 0 and edge["paper"]["total"] > 0
        assert m["time_per_light_s"]["vtk-edge"] is None and m["time_per_light_s"]["reference"] is not None
    assert (
        "detector vtk-edge: no plain loops, its time column is empty"
        in _run(
            [
                *silcount,
                "corpus",
                "data/tetrahedron.obj",
                "--lights",
                "2",
                "--detectors",
                "vtk-edge",
                "--scheduler",
                "threads",
                "--workers",
                "1",
                "--no-cache",
                "--quiet",
            ],
            env,
            cwd=REPO,  # fmt: skip
        ).stdout
    )

    out = tmp_path / "edge.png"
    got = _run([*silcount, "render", str(scene(tmp_path)), "--method", "zfail", "--detector", "vtk-edge",
                "--out", str(out)], env)  # fmt: skip
    assert out.exists() and "vtk-edge intended" in got.stdout
