"""Measured complexity: detector tallies over a size sweep, fitted exponents.

Every registered detector (:func:`silcount.detectors.names`) runs with the ``fast``
engine on the icosphere series (F = 20 * 4**k faces) and on the shared real
meshes (``$SILCOUNT_MESH_DIR``) for one fixed point light; for each cost model
and operation kind the exponent b of ``count ~ a F**b`` is fitted by least
squares on log-log over the icospheres; :func:`measure_exponent` adds the
complexity class of the same points (:mod:`silcount.study.classes`).  The papers claim O(n^2) for TA, VnV
and EESD with n = faces (EESD paper Sec. 5; HSD paper Sec. VI).

The tables' "measured" columns need meshes whose n (faces) and m (sides per
face) match the tables' points (n=10, m=5; n=100, m=10).  No closed mesh can:
a closed mesh has 2E = m F, and genus 0 forces m < 6 (Euler's formula with
every vertex of degree >= 3).  :func:`table_mesh` takes the duals of the
icosahedron series, the closest closed polygon meshes: the dodecahedron
(F=12, m=5) and the dual of icosphere2 (F=162, m=5.93).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from silcount.counting.arithmetic import KINDS
from silcount.detectors import detect, get, names
from silcount.errors import SilcountError
from silcount.mesh.lights import PointLight
from silcount.mesh.model import Mesh, from_polygons
from silcount.mesh.shapes import builtin_mesh
from silcount.study.classes import ClassChoice, choose

SWEEP_MESHES = tuple(f"icosphere{k}" for k in range(0, 5))
REAL_MESHES = ("cow.obj", "fandisk.obj", "bunny.ply", "teapot.obj")


def standard_light(mesh: Mesh) -> PointLight:
    """A fixed point light, 5 bounding radii from the mesh centre, off every axis."""
    direction = np.array([0.36, 0.48, 0.8])
    return PointLight(tuple(mesh.centre + 5.0 * mesh.bounding_radius * direction))


def dual(mesh: Mesh, name: str) -> Mesh:
    """The polyhedral dual of a closed triangle mesh: a vertex per face (its centroid), a face per vertex."""
    tri = mesh.faces
    centroids = mesh.vertices[tri].mean(axis=1)
    faces = []
    for vert in range(mesh.n_vertices):
        ring = np.flatnonzero((tri == vert).any(axis=1))
        normal = mesh.vertices[vert] - mesh.centre
        u = np.cross(normal, [0.3, 0.5, 0.8])
        u /= np.linalg.norm(u)
        w = np.cross(normal / np.linalg.norm(normal), u)
        rel = centroids[ring] - mesh.vertices[vert]
        faces.append(list(ring[np.argsort(np.arctan2(rel @ w, rel @ u))]))
    return from_polygons(centroids, faces, name=name)


def table_mesh(n: int, m: float) -> Mesh:
    """The closed mesh nearest to a table point: duals of icosphere k (F = 12, 42, 162, ...), nearest in log F."""
    sizes = {k: 10 * 4**k + 2 for k in range(0, 4)}
    k = min(sizes, key=lambda k: abs(np.log(sizes[k] / n)))
    return dual(builtin_mesh(f"icosphere{k}"), "dodecahedron" if k == 0 else f"dual_icosphere{k}")


@dataclass
class Run:
    """One detector on one mesh: sizes and tallies by cost model."""

    detector: str
    variant: str
    mesh: str
    faces: int
    edges: int
    mean_sides: float
    tally: dict[str, dict[str, int]] = field(default_factory=dict)
    steps: dict[str, int] = field(default_factory=dict)
    error: str = ""  # always empty: a failing detector raises (kept for the figures' filters)


def run(detector: str, mesh: Mesh) -> Run:
    """Tallies of ``detector`` (its measured variant, fast engine) on ``mesh`` for :func:`standard_light`."""
    variant = get(detector).growth_variant  # the variant whose loops are the printed pseudo-code's
    out = Run(detector, variant, mesh.name, mesh.n_faces, mesh.n_edges, float(mesh.mean_sides))
    try:
        res = detect(mesh, standard_light(mesh), detector, variant=variant, engine="fast")
    except SilcountError:
        raise
    except Exception as exc:  # no silent hole: the command fails, naming the detector and the mesh
        raise SilcountError(
            f"measurement failed: detector {detector!r} on {mesh.name}: {type(exc).__name__}: {exc}"
        ) from exc
    # a detector without a paper cost model has the true tally alone
    out.tally = {m: {k: int(res.tally[m].get(k, 0)) for k in KINDS} for m in ("paper", "true") if m in res.tally}
    out.steps = dict(res.steps)
    return out


def real_meshes() -> list[Mesh]:
    """The shared real meshes that exist under ``$SILCOUNT_MESH_DIR`` (none when it is unset)."""
    from silcount.mesh.io import load_mesh

    root = os.environ.get("SILCOUNT_MESH_DIR")
    if not root:
        return []
    return [load_mesh(Path(root) / name) for name in REAL_MESHES if (Path(root) / name).exists()]


@cache
def sweep(with_real: bool = True) -> tuple[Run, ...]:
    """Every available detector over the icosphere series (and the real meshes)."""
    meshes = [builtin_mesh(name) for name in SWEEP_MESHES] + (real_meshes() if with_real else [])
    return tuple(run(d, mesh) for d in names() for mesh in meshes)


def fit_exponent(faces, counts) -> float | None:
    """Least-squares slope of log(count) against log(faces); None with fewer than 2 positive counts."""
    f, c = np.asarray(faces, float), np.asarray(counts, float)
    keep = c > 0
    if keep.sum() < 2:
        return None
    return float(np.polyfit(np.log(f[keep]), np.log(c[keep]), 1)[0])


def exponents(runs: tuple[Run, ...]) -> dict[tuple[str, str, str], float | None]:
    """(detector, cost model, kind) -> fitted exponent over the icosphere runs."""
    out = {}
    for det in sorted({r.detector for r in runs}):
        series = [r for r in runs if r.detector == det and r.mesh in SWEEP_MESHES and not r.error]
        for model in ("paper", "true"):
            if not all(model in r.tally for r in series):
                continue
            for kind in KINDS:
                out[(det, model, kind)] = fit_exponent(
                    [r.faces for r in series], [r.tally[model][kind] for r in series]
                )
    return out


@dataclass(frozen=True)
class Exponent:
    """A measured growth exponent b (count ~ a F**b) of one detector's total, with a 95% confidence interval.

    The complexity claims take any sequence of these (``source`` names where they come from: this module's
    icosphere sweep, or another sweep such as the corpus one), so a second source plugs in as an argument.
    ``classes``: the complexity class of the same points (:func:`silcount.study.classes.choose`), shown
    beside the exponent; None where not fitted.
    """

    detector: str
    cost_model: str
    exponent: float
    low: float
    high: float
    points: int
    source: str
    classes: ClassChoice | None = None

    def text(self) -> str:
        """``F^1.29 [1.20, 1.39], class n log n (w 0.90, bootstrap 0.74; runner-up n^1.5, w 0.08)``."""
        fitted = f"F^{self.exponent:.2f} [{self.low:.2f}, {self.high:.2f}]"
        return fitted + ("" if self.classes is None else f", class {self.classes.text()}")


def measure_exponent(detector: str, cost_model: str, faces, counts, source: str) -> Exponent:
    """The :class:`Exponent` of ``counts`` over ``faces``: the fitted exponent, its 95% interval and the class."""
    b, lo, hi = fit_with_interval(faces, counts)
    f, c = np.asarray(faces, float), np.asarray(counts, float)
    keep = c > 0
    return Exponent(detector, cost_model, b, lo, hi, int(keep.sum()), source, choose(f[keep], c[keep]))


def fit_with_interval(faces, counts) -> tuple[float, float, float]:
    """Least-squares slope of log(count) on log(faces) and its 95% t-interval (needs >= 3 positive points)."""
    from scipy import stats

    f, c = np.asarray(faces, float), np.asarray(counts, float)
    keep = c > 0
    if keep.sum() < 3:
        raise ValueError(f"an exponent with an interval needs 3 positive counts, got {int(keep.sum())}")
    fit = stats.linregress(np.log(f[keep]), np.log(c[keep]))
    half = float(stats.t.ppf(0.975, int(keep.sum()) - 2) * fit.stderr)
    return float(fit.slope), float(fit.slope) - half, float(fit.slope) + half


def icosphere_evidence(runs: tuple[Run, ...] | None = None) -> tuple[Exponent, ...]:
    """Fitted exponents of every detector's total operations (true and paper cost models) over the icospheres."""
    runs = sweep(with_real=False) if runs is None else runs
    out = []
    for det in sorted({r.detector for r in runs}):
        series = sorted((r for r in runs if r.detector == det and r.mesh in SWEEP_MESHES), key=lambda r: r.faces)
        for model in ("true", "paper"):
            source = f"icosphere sweep ({', '.join(r.mesh for r in series)}; fast engine, one point light)"
            totals = [sum(r.tally[model].values()) for r in series]
            out.append(measure_exponent(det, model, [r.faces for r in series], totals, source))
    return tuple(out)
