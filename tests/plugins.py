"""Detector plug-ins for the tests: a site folder holding a distribution's metadata and its modules, found by
:mod:`importlib.metadata` once the folder is on ``PYTHONPATH``, as pip would install them; and the CLI run in
a fresh process with it (the registry fills once per process)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

BARE = '''
"""A detector with the fast engine alone, no paper cost model and no plain loops: the reference rule."""
from silcount import DetectorSpec
from silcount.detectors.adjacency import shared_facing_flags, edge_ids_of
from silcount.detectors.base import EngineRun, make_silhouette


def detect(mesh, light, variant="intended", engine="fast"):
    facing, ties = shared_facing_flags(mesh, light)
    ids = edge_ids_of(mesh, facing)
    run = EngineRun(ids, {"edge_test": mesh.n_edges}, {"read": mesh.n_edges}, ties, facing)
    return make_silhouette(mesh, light, "bare", variant, engine, run, None)


SPEC = DetectorSpec(name="bare", label="bare rule", detect=detect)
'''


def site(root: Path, dist: str, entry_points: dict[str, str], modules: dict[str, str]) -> Path:
    """``root`` as a site folder: distribution ``dist`` with ``entry_points`` (name -> ``module:attr``) in the
    group ``silcount.detectors`` and ``modules`` (name -> source); returns ``root``."""
    meta = root / f"{dist}-0.1.dist-info"
    meta.mkdir(parents=True, exist_ok=True)
    (meta / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {dist}\nVersion: 0.1\n")
    lines = [f"{name} = {target}" for name, target in entry_points.items()]
    (meta / "entry_points.txt").write_text("[silcount.detectors]\n" + "\n".join(lines) + "\n")
    for name, source in modules.items():
        (root / f"{name}.py").write_text(source)
    return root


def env_with(*paths: Path) -> dict[str, str]:
    """The environment with ``paths`` after this checkout on ``PYTHONPATH`` and no inherited plug-in state."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), *map(str, paths)])
    env.pop("SILCOUNT_PLUGINS_WARNED", None)
    return env


def silcount(args: list[str], env: dict[str, str], cwd: Path | None = None) -> subprocess.CompletedProcess:
    """``python -m silcount.cli.main ARGS`` (the ``silcount`` command) in a fresh process."""
    command = [sys.executable, "-m", "silcount.cli.main", *args]
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd, timeout=600)


def scene(root: Path) -> Path:
    """A small scene of the built-in data (a cube over a floor) under ``root``; its path."""
    data = REPO / "data"
    for name in ("triangle_cube.obj", "plane.obj"):
        (root / name).write_bytes((data / name).read_bytes())
    path = root / "s.json"
    objects = [
        {"name": "floor", "mesh": "plane.obj", "casts_shadow": False, "rotate_deg": [-90, 0, 0]},
        {"name": "cube", "mesh": "triangle_cube.obj", "translate": [0, 1, 0]},
    ]
    camera = {"eye": [4, 3, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50.0, "near": 0.1}
    doc = {"spec": "silcount-scene/1", "resolution": [24, 16], "camera": camera, "light": {"position": [-1, 6, 2]}}
    path.write_text(json.dumps(doc | {"objects": objects}))
    return path
