"""What the benchmarks share: the bunny mesh, the lights, a best-of timer, the memory floor, child processes.

Everything here uses only what every tree a benchmark compares with has (silcount's top-level names):
a child process imports this module beside a baseline tree's silcount.

A benchmark that compares this tree with a baseline checkout runs one child process per tree:
:func:`child_command` runs a module of this package (``python -P -m benchmarks.NAME``: ``-P`` keeps the
working directory off ``sys.path``) and :func:`tree_env` puts the tree's ``silcount`` first on
``PYTHONPATH`` and this checkout (for ``benchmarks``) after it, so the child imports the tree's package
without any edit of ``sys.path``.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

import silcount

ROOT = Path(__file__).resolve().parent.parent
"""The checkout holding this package."""


def build_mesh(rounds: int) -> silcount.Mesh:
    """The shared bunny (``$SILCOUNT_MESH_DIR/bunny.ply``, 16,301 faces) after ``rounds`` rounds of 1-to-4
    midpoint subdivision (``trimesh.remesh.subdivide``; 3 rounds: 1,043,264 faces)."""
    import trimesh

    base = Path(os.environ["SILCOUNT_MESH_DIR"]) / "bunny.ply"
    m = silcount.load_mesh(base)
    v, f = m.vertices, m.faces
    for _ in range(rounds):
        v, f = trimesh.remesh.subdivide(v, f)
    return silcount.from_polygons(v, f, name=f"bunny_sub{rounds}")


def lights(mesh: silcount.Mesh, k: int, seed: int = 1) -> list:
    """``k`` random lights, alternately point (even ``i``, 3 bounding radii out) and directional (odd ``i``).

    The recipe of :func:`silcount.mesh.lights.random_lights` (normal draws from
    ``numpy.random.default_rng(seed)``, normalised), written with numpy and silcount's top-level names
    alone, because a child process runs it on a baseline tree's silcount (318ab63 and later), which may
    predate that function.  Each direction is drawn and normalised on its own, as before this package.
    """
    rng = np.random.default_rng(seed)
    out = []
    for i in range(k):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        out.append(
            silcount.DirectionalLight(d) if i % 2 else silcount.PointLight(mesh.centre + 3 * mesh.bounding_radius * d)
        )
    return out


def best_time(fn, repeat: int) -> float:
    """The least wall time of ``repeat`` calls of ``fn`` (the least disturbed estimate on a shared machine)."""
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def read_bandwidth() -> float:
    """Bytes per second of the faster of ``np.sum`` and ``np.max`` over 256 MiB (larger than any cache here)."""
    a = np.ones(256 * 2**20 // 8)
    a.sum()
    return a.nbytes / min(best_time(a.sum, 7), best_time(a.max, 7))


def floor_of(mesh: silcount.Mesh) -> tuple[float, float, float]:
    """The reference query's memory floor: the bytes it must read (each face's ``p0`` and normal, 48 B; each
    two-sided edge's two face ids as int32, 8 B), the read bandwidth, and their quotient in seconds."""
    F, E2 = mesh.n_faces, int(np.count_nonzero(mesh.edge_valence == 2))
    need = 48 * F + 8 * E2
    bw = read_bandwidth()
    return need, bw, need / bw


def load_line() -> str:
    """The machine's load averages (1, 5, 15 min) and its cores, to print beside every figure."""
    return f"load average {' '.join(f'{x:.1f}' for x in os.getloadavg())} on {os.cpu_count()} cores"


def child_command(module: str, *args: str) -> list[str]:
    """``python -P -m module args``: a module of this package in a fresh process (see :func:`tree_env`)."""
    return [sys.executable, "-P", "-m", module, *args]


def tree_env(tree: str | Path | None = None, **extra: str) -> dict[str, str]:
    """This process's environment with ``PYTHONPATH`` set to ``tree`` (a checkout whose ``silcount`` the child
    imports; none: this checkout's), then this checkout (for ``benchmarks``), then what was there; plus ``extra``."""
    first = [str(Path(tree).resolve())] if tree is not None else []
    rest = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return {**os.environ, "PYTHONPATH": os.pathsep.join([*first, str(ROOT), *rest]), **extra}
