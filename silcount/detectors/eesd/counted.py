"""EESD's counted routines (EESD paper Sec. 3.3, 5.3): the ``naive`` engine's arithmetic and its fixed costs.

``extend`` (the outward point ``P``), ``ray``, ``triangle_test`` (Moller-Trumbore
in :mod:`silcount.mesh.raytrace`'s order) and the literal ``plane`` step, on
counting arithmetic; each is branch-free, so :func:`routine_cost` measures its
``true`` cost once by running it, and the ``fast`` engine charges that per run.
The definitions of the point and the ray are documented in :mod:`.eesd`.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from silcount.counting.arithmetic import Num, OpCounter, plain
from silcount.detectors.base import MeshMemory, counted_face_normal
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import from_polygons

EPS = 1e-6  # the outward offset, in edge lengths

CHECK_COST = {"cmp": 1}  # hits == 0
ADD_COST = {"write": 1}  # S[k] = edge
HIT_COUNT_COST = {"add": 1}  # hits = hits + hit
FACE_READS = 10  # face_start[f], [f+1]; p0 and p1: index and 3 coordinates each
TRIANGLE_READS = 4  # the next corner: index and 3 coordinates
PAIR_LITERAL_COST = {"read": 4, "mul": 3, "add": 3, "cmp": 1}  # a, b, c, d; aPx+bPy+cPz+d == 0


def _sqrt(x: Num) -> Num:
    x.counter["sqrt"] += 1
    return Num(math.sqrt(x.value) if x.value >= 0 else math.nan, x.counter)


def _div(a, b: Num) -> Num:
    """IEEE division (inf/NaN instead of an exception), one ``div``."""
    b.counter["div"] += 1
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # inf, as the compiled kernels give
        return Num(float(np.float64(plain(a)) / np.float64(b.value)), b.counter)


def counted_outward_point(v1, v2, c, light_vals, directional: bool) -> list[Num]:
    """The ``extend`` step: ``P`` from the edge's vertices, the far corner ``c`` of f1 and the light."""
    m = [(v1[k] + v2[k]) * 0.5 for k in range(3)]
    e = [v2[k] - v1[k] for k in range(3)]
    d = light_vals if directional else [m[k] - light_vals[k] for k in range(3)]
    w = [d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0]]
    g = [c[k] - m[k] for k in range(3)]
    side = g[0] * w[0] + g[1] * w[1] + g[2] * w[2]
    sgn = -1.0 if side > 0.0 else 1.0
    ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    scale = EPS * _sqrt(_div(ee, ww)) * sgn
    return [m[k] + w[k] * scale for k in range(3)]


def counted_ray(p, light_vals, directional: bool):
    """The ``ray`` step: (origin, direction, t_min, t_max) of the ray through ``p``."""
    if directional:
        return p, light_vals, -math.inf, math.inf
    return light_vals, [p[k] - light_vals[k] for k in range(3)], 0.0, math.inf


def counted_triangle_hit(o, d, a, b, c, t_min: float, t_max: float) -> bool:
    """Moller-Trumbore on counting arithmetic, in :mod:`silcount.mesh.raytrace`'s order; branch-free."""
    e1 = [b[k] - a[k] for k in range(3)]
    e2 = [c[k] - a[k] for k in range(3)]
    p = [d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]]
    det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2]
    inv = _div(1.0, det)
    s = [o[k] - a[k] for k in range(3)]
    u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv
    q = [s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]]
    v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv
    t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv
    checks = [det != 0.0, u >= 0.0, v >= 0.0, u + v <= 1.0, t > t_min, t < t_max]
    return all(checks)


def counted_plane(mem: MeshMemory, f: int) -> list[Num]:
    """The literal ``plane`` step: ``(a, b, c, d)`` of face ``f`` from its first three corners."""
    p0, n = counted_face_normal(mem, f)
    return n + [0.0 - (n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2])]


@cache
def _routine_costs(directional: bool) -> dict[str, tuple[tuple[str, int], ...]]:
    """The fixed ``true`` cost of each counted routine, measured by running it once."""
    out = {}
    counter = OpCounter()
    nums = lambda xs: [Num(float(x), counter) for x in xs]  # noqa: E731
    light_vals = nums([0.0, 0.0, 1.0] if directional else [0.0, 0.0, 5.0])
    counted_outward_point(nums([0, 0, 0]), nums([1, 0, 0]), nums([0, 1, 0]), light_vals, directional)
    out["extend"], counter = tuple(sorted(counter.items())), OpCounter()
    light_vals = nums([0.0, 0.0, 1.0] if directional else [0.0, 0.0, 5.0])
    o, d, lo, hi = counted_ray(nums([0.5, 0.5, 0.0]), light_vals, directional)
    out["ray"], counter = tuple(sorted(counter.items())), OpCounter()
    counted_triangle_hit(
        nums([0.2, 0.2, 5]), nums([0, 0, -1]), nums([0, 0, 0]), nums([1, 0, 0]), nums([0, 1, 0]), lo, hi
    )
    out["triangle_test"], counter = tuple(sorted(counter.items())), OpCounter()
    tri = from_polygons(np.eye(3), [[0, 1, 2]])
    counted_plane(MeshMemory(tri, DirectionalLight((0, 0, 1)), counter), 0)
    out["plane"] = tuple(sorted(counter.items()))
    return out


def routine_cost(name: str, light: Light) -> dict[str, int]:
    """``true`` cost of one run of ``extend``, ``ray``, ``triangle_test`` or ``plane`` for this kind of light."""
    return dict(_routine_costs(isinstance(light, DirectionalLight))[name])


__all__ = [
    "EPS",
    "CHECK_COST",
    "ADD_COST",
    "HIT_COUNT_COST",
    "FACE_READS",
    "TRIANGLE_READS",
    "PAIR_LITERAL_COST",
    "counted_outward_point",
    "counted_ray",
    "counted_triangle_hit",
    "counted_plane",
    "routine_cost",
]
