"""An installed wheel works outside the checkout: the papers as data ship with it (issue 25).

The wheel is built from this tree, installed into a folder outside it, and
run from there with the checkout out of reach: ``silcount.__file__`` is the
installed copy, the models are read from the installed package data, and a
``silcount audit`` of a tetrahedron gives paper tallies.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

RUN = """
import json, sys
import silcount
from silcount.counting import models
from silcount.cli.main import run
from silcount.study import scale
units = len(scale.load_profile().units)  # the sweep-time model's measurements ship too
print(json.dumps({"file": silcount.__file__, "models": str(models.models_dir()), "units": units}))
sys.argv = ["silcount", "audit", sys.argv[1], "--detectors", "reference", "--random-lights", "1",
            "--format", "json", "--out", sys.argv[2], "--quiet"]
run()
"""


@pytest.mark.slow
def test_a_wheel_installed_outside_the_tree_audits_a_mesh(tmp_path):
    wheels, site, src = tmp_path / "wheels", tmp_path / "site", tmp_path / "src"
    # built from a copy: setuptools writes build/ beside the sources, and nothing may be written into the tree
    shutil.copytree(ROOT / "silcount", src / "silcount", ignore=shutil.ignore_patterns("__pycache__"))
    for name in ("pyproject.toml", "README.md"):  # not setup.cfg: its egg_base is the checkout's .venv
        shutil.copy(ROOT / name, src / name)
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--quiet"]
    built = subprocess.run(
        [*pip[:-1], "wheel", "--no-deps", "-w", str(wheels), str(src)], capture_output=True, text=True
    )
    assert built.returncode == 0, built.stderr[-2000:]
    # a license as a TOML table printed ~50 lines of setuptools deprecation warnings; an SPDX string prints none
    assert "Warning" not in built.stdout + built.stderr, (built.stdout + built.stderr)[-3000:]
    (wheel,) = wheels.glob("silcount-*.whl")
    subprocess.run([*pip, "install", "--no-deps", "--target", str(site), str(wheel)], check=True)
    env = {k: v for k, v in os.environ.items() if not k.startswith("SILCOUNT_")}
    env.update(PYTHONPATH=str(site), NUMBA_CACHE_DIR=str(tmp_path / "numba"), PYTHONDONTWRITEBYTECODE="1")
    mesh, out = tmp_path / "tetrahedron.obj", tmp_path / "audit.json"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    done = subprocess.run(
        [sys.executable, "-c", RUN, str(mesh), str(out)], cwd=tmp_path, env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-2000:]
    where = json.loads(done.stdout.splitlines()[0])
    assert Path(where["file"]).is_relative_to(site)
    assert Path(where["models"]).is_relative_to(site) and (Path(where["models"]) / "eesd2012-ta.toml").is_file()
    assert where["units"] > 0
    detectors = json.loads(out.read_text())["detectors"]
    assert set(detectors) == {"reference"}
    assert all(sum(d["tallies"]["paper"].values()) > 0 for d in detectors.values())
