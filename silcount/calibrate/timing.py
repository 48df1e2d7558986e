"""Measured time and counted operations, per algorithm, mesh and light.

Time is the wall time of :func:`silcount.detectors.plain_edge_ids`, each
algorithm's own loops compiled and uncounted (the ``intended`` variant), best
of ``repeats`` runs after one warm-up (numba compilation and HSD's per-mesh
merge are paid before the clock starts, as a renderer pays them once).  The
tally of the same run is the ``fast`` engine's ``intended`` tally for the same
mesh and light, under both cost models (``paper`` and ``true``).

The algorithms are the papers' four (TA, VnV, HSD, EESD); the ``reference``
rule is not one of them (its plain form is numpy, not a loop).  Beside them,
:data:`LITERATURE` (``gaussmap``, ``cones``): their time is their per-light
query, the fast engine's compiled traversal on the tree cached with the mesh,
on one numba thread (:func:`silcount.detectors.hierarchy_query.plain_query`; the warm-up
call builds the tree, so the build is not timed, as HSD's merge is not), and
their tally is the query's alone (the build's is ``notes['build']``).  Lights: ``LIGHTS``
point lights uniformly on the sphere of 3 bounding radii about the mesh centre,
seed 0 (:func:`silcount.mesh.lights.random_lights`, the recipe of ``silcount audit``).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd

from silcount.counting.cycles import TRUE_KINDS
from silcount.detectors import LITERATURE, PAPERS, detect, plain_edge_ids
from silcount.errors import BadArgument, UnreadableInput
from silcount.mesh.lights import random_lights
from silcount.mesh.model import Mesh
from silcount.mesh.shapes import builtin_mesh
from silcount.progress import progress

ALGORITHMS = PAPERS
TIMED = ALGORITHMS + LITERATURE  # a live run times these; the fit is the ALGORITHMS' alone (calibrate.calibration)
SERIES = tuple(f"icosphere{k}" for k in range(5))
LIGHTS = 4
MODELS = ("paper", "true")
KEY = ["mesh", "detector", "light"]


def series_meshes() -> list[tuple[str, Mesh]]:
    """The icosphere series (F = 20 * 4**k, k = 0..4), as ``(group, mesh)``."""
    return [("icosphere", builtin_mesh(name)) for name in SERIES]


def corpus_meshes(root: Path) -> list[tuple[str, Mesh]]:
    """Every mesh file under ``root`` (sorted), loaded by :func:`silcount.mesh.io.load_mesh`, named by its path."""
    from silcount.mesh.io import load_mesh

    exts = {".obj", ".off", ".ply", ".stl", ".glb", ".gltf"}
    files = sorted(p for p in root.rglob("*") if p.suffix.lower() in exts and p.is_file())
    out = []
    for path in files:
        mesh = load_mesh(path)
        mesh.name = path.relative_to(root).as_posix()  # file names, not stems: cylinder.obj and cylinder.stl differ
        out.append(("corpus", mesh))
    return out


def _best(fn, repeats: int) -> float:
    fn()
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def tallies(
    meshes: list[tuple[str, Mesh]],
    n_lights: int = LIGHTS,
    show: bool | None = False,
    detectors: tuple[str, ...] = ALGORITHMS,
) -> pd.DataFrame:
    """One row per (mesh, detector, light): sizes and the ``paper_<kind>`` / ``true_<kind>`` counts."""
    rows = []
    bar = progress(len(meshes) * len(detectors), "tallies", show)
    for group, mesh in meshes:
        for det in detectors:
            for i, light in enumerate(random_lights(mesh, n_lights)):
                res = detect(mesh, light, det, variant="intended", engine="fast")
                row = {"group": group, "mesh": mesh.name, "faces": mesh.n_faces, "edges": mesh.n_edges}
                row |= {"detector": det, "light": i}
                for model in MODELS:
                    unknown = sorted(set(res.tally[model]) - set(TRUE_KINDS))
                    if unknown:
                        raise BadArgument(f"{det} counts {', '.join(unknown)}, which no cycle profile weighs")
                    row |= {f"{model}_{k}": int(res.tally[model].get(k, 0)) for k in TRUE_KINDS}
                rows.append(row)
            bar.update(1)
    bar.close()
    return pd.DataFrame(rows)


def timings(
    meshes: list[tuple[str, Mesh]],
    n_lights: int = LIGHTS,
    repeats: int = 3,
    show: bool | None = False,
    detectors: tuple[str, ...] = TIMED,
) -> pd.DataFrame:
    """One row per (mesh, detector, light): ``seconds``, the best of ``repeats`` plain runs."""
    rows = []
    bar = progress(len(meshes) * len(detectors), "timing", show)
    for _, mesh in meshes:
        for det in detectors:
            for i, light in enumerate(random_lights(mesh, n_lights)):
                seconds = _best(lambda m=mesh, li=light, d=det: plain_edge_ids(m, li, d), repeats)
                rows.append({"mesh": mesh.name, "detector": det, "light": i, "seconds": seconds})
            bar.update(1)
    bar.close()
    return pd.DataFrame(rows)


def samples(tally: pd.DataFrame, times: pd.DataFrame) -> pd.DataFrame:
    """Tallies joined with timings on (mesh, detector, light); every tally row must have a time."""
    joined = tally.merge(times, on=KEY, how="left", validate="one_to_one")
    missing = joined[joined["seconds"].isna()]
    if len(missing):
        first = missing.iloc[0]
        raise UnreadableInput(f"no timing for {first['mesh']} / {first['detector']} / light {first['light']}")
    return joined.sort_values(["group", "faces", "mesh", "detector", "light"], kind="stable").reset_index(drop=True)
