"""silcount's own measurements for the measured generic claim kinds (``docs/papers-as-data.md``).

A claims entry names its meshes by *spec*: a built-in mesh (``icosphere3``), a latitude-longitude sphere
``uv_sphere:SLICESxSTACKS`` (:func:`silcount.mesh.shapes.uv_sphere`), or a file, relative to the paper's folder,
in ``$SILCOUNT_MESH_DIR`` or in ``$SILCOUNT_CORPUS_DIR``.  Every detector runs with the ``fast`` engine, its
``intended`` variant, under ``lights`` directional lights of seed ``seed`` (unit directions drawn from a normal
distribution: orthographic views, as in Gooch et al. 1999 and Benichou & Elber 1999).  Per light, three
quantities: ``silhouette`` (edges returned), ``operations`` (the true tally's total) and ``visited`` (the edges
its per-light loop examines, its spec's ``visited_step``); a measurement is their mean over the lights.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.model import Mesh

QUANTITIES = ("silhouette", "operations", "visited")
LABEL = {"silhouette": "silhouette edges", "operations": "true operations", "visited": "edges visited"}


@dataclass(frozen=True)
class Measured:
    """One detector on one mesh: sizes and the per-light means of :data:`QUANTITIES`."""

    detector: str
    mesh: str
    faces: int
    edges: int
    lights: int
    silhouette: float
    operations: float
    visited: float

    def value(self, quantity: str) -> float:
        if quantity not in QUANTITIES:
            raise ValueError(f"unknown quantity {quantity!r}; choose from {', '.join(QUANTITIES)}")
        return float(getattr(self, quantity))

    @property
    def where(self) -> str:
        return f"{self.mesh} (F={self.faces:,}, E={self.edges:,}; {self.lights} directional lights)"


@cache
def mesh_of(spec: str, folder: str = "") -> Mesh:
    """The mesh a spec names (see the module docstring); ``folder``: the paper's, for a relative file."""
    from silcount.mesh import shapes
    from silcount.mesh.io import load_mesh

    if spec in shapes.BUILTIN:
        return shapes.builtin_mesh(spec)
    if spec.startswith("uv_sphere:"):
        slices, _, stacks = spec.removeprefix("uv_sphere:").partition("x")
        return shapes.uv_sphere(int(slices), int(stacks))
    for root in (folder, os.environ.get("SILCOUNT_MESH_DIR", ""), os.environ.get("SILCOUNT_CORPUS_DIR", "")):
        if root and (Path(root) / spec).is_file():
            return load_mesh(Path(root) / spec)
    raise UnreadableInput(
        f"mesh {spec!r}: not a built-in mesh, a uv_sphere:SxT, nor a file of the paper's folder, "
        "$SILCOUNT_MESH_DIR or $SILCOUNT_CORPUS_DIR"
    )


def directions(count: int, seed: int) -> np.ndarray:
    """``count`` unit directions, normal draws of ``seed`` normalised."""
    d = np.random.default_rng(seed).normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@cache
def measure(detector: str, spec: str, lights: int = 16, seed: int = 0, folder: str = "") -> Measured:
    """``detector`` on the mesh of ``spec`` under ``lights`` directional lights: the per-light means."""
    from silcount.detectors import detect, get
    from silcount.mesh.lights import DirectionalLight

    mesh = mesh_of(spec, folder)
    step = get(detector).visited_step  # None: the detector names no visited step, so "visited" is NaN
    rows = []
    for d in directions(lights, seed):
        res = detect(mesh, DirectionalLight(tuple(d)), detector, engine="fast")
        rows.append((res.n_edges, sum(res.tally["true"].values()), res.steps.get(step, 0) if step else float("nan")))
    s, ops, visited = np.mean(np.array(rows, dtype=float), axis=0)
    return Measured(detector, spec, mesh.n_faces, mesh.n_edges, lights, float(s), float(ops), float(visited))


def size_of(m: Measured, against: str) -> float:
    """The size a growth is fitted against: ``F`` (faces) or ``E`` (edges)."""
    if against not in ("F", "E"):
        raise ValueError(f"unknown size {against!r}; choose from F, E")
    return float(m.faces if against == "F" else m.edges)


def fit(xs: list[float], ys: list[float]) -> tuple[float, float]:
    """``(b, a)`` of ``y ~ a x**b``: least squares in log-log."""
    b, log_a = np.polyfit(np.log(xs), np.log(ys), 1)
    return float(b), float(np.exp(log_a))


@cache
def corpus_fits(folder: str, levels: tuple[int, ...] = (0,)) -> dict:
    """The corpus study's fits (:func:`silcount.study.corpus`, as `silcount report` runs it: 64 directional lights,
    seed 0, no wall times, the default cache) over the meshes of ``folder``."""
    from silcount.study import corpus

    if not Path(folder).is_dir():
        raise UnreadableInput(f"corpus {folder!r}: not a folder ($SILCOUNT_CORPUS_DIR)")
    return corpus([Path(folder)], subdivide=levels, timing=False, quiet=True).fits
