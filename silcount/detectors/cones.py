"""The spatialized normal-cone hierarchy: Johnson and Cohen, I3D 2001, Sec. 3; Sander et al., SIGGRAPH 2000, Sec. 3.

A tree over clusters of edges; each node keeps a bound on its faces'
positions and one on their normals, so that a single test proves "no
silhouette edge below here" for the light at hand and the whole subtree is
skipped.  Johnson and Cohen bound a cluster's normals by a cone (axis and
half-angle) and its positions by a sphere; Sander et al. anchor such cones
at the cluster.  Point and directional lights.

silcount's reading
------------------
* **Clusters** are ``leaf_size`` consecutive edges in the 5-D Z-order of
  the point ``p0(f1) + p0(f2)`` (the first vertices of the edge's two faces,
  12 bits per axis of the mesh's box) and of the direction of ``n1 + n2``
  (its octahedral-map cell, 12 bits per axis), grouped ``fanout`` at a time
  up to one root (:mod:`.hierarchy`): a tree clustered by position and
  normal at once, as Johnson and Cohen's spatialized normal cones are,
  built bottom-up.  (A key of position alone tested about three times as
  many edges on the 1.04 M-face bunny: 15 % of E against 5-8 %.)
* **The bounds** are axis-aligned boxes of the faces' normals (the cone's
  bounding box) and of their ``p0``.  A cone test needs the angle between
  the light and the cone's axis, whose rounding would need its own error
  margin; the boxes' test is exact in floating point (proof in
  :mod:`.hierarchy`), so the answer is exactly the ``reference`` edge set,
  ties, grazing lights and lights in a face's plane included.  A box holds
  its cone, so it prunes no node a cone would keep and may keep some a cone
  would prune: the counts are, if anything, this hierarchy's worst.

Parameters: ``leaf_size`` (default 8) and ``fanout`` (default 4); see
``docs/literature.md``.  The build's own tally is in ``notes['build']``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.detectors.hierarchy import FANOUT, LEAF_SIZE, KeyScheme
from silcount.detectors.hierarchy_query import detect as detect_with
from silcount.detectors.hierarchy_query import plain_query, tree_for
from silcount.detectors.morton import counted_octahedral, interleave5, octahedral
from silcount.detectors.result import Silhouette
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

NAME = "cones"  # what it declares of itself: see silcount.detectors.MODULES
LABEL = "normal cones"
PAPER_MODEL = "silcount-cones"
ONE_VARIANT = True
LITERATURE = True
VISITED_STEP = "edge_test"
PLAIN_QUADRATIC = False
GROWTH_VARIANT = "intended"
STYLE = ("#e07a1f", "v")  # colour, marker in figures
BITS = 12  # per coordinate of the 5-D key: 3 of position, 2 of normal direction
QUANT = float((1 << BITS) - 1)  # a position's cell: [0, QUANT]
QUANT_N = float((1 << (BITS - 1)) - 1)  # a direction's: (p + 1) * QUANT_N in [0, 2 QUANT_N] for p in [-1, 1]


def _frame(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``2 lo`` and the scale that maps ``[2 lo, 2 hi]`` onto ``[0, QUANT]`` (1 for a flat axis)."""
    lo2, hi2 = lo + lo, hi + hi
    span = hi2 - lo2
    return lo2, QUANT / np.where(span > 0.0, span, 1.0)


@njit(cache=True, inline="always")
def _cell(p0, a, b, lo2, scale, c):  # pragma: no cover - compiled
    """Axis ``c``'s grid cell of ``p0(a) + p0(b)`` (0 for a non-finite value)."""
    q = (p0[a, c] + p0[b, c] - lo2[c]) * scale[c]
    return np.uint64(q) if np.isfinite(q) else np.uint64(0)


@njit(cache=True, parallel=True)
def _keys(p0, nrm, f1, f2, lo2, scale):  # pragma: no cover - compiled
    """5-D Z-order codes of ``p0(f1) + p0(f2)`` and the direction of ``n1 + n2``, as :func:`key_naive` computes."""
    T = f1.size
    keys = np.empty(T, dtype=np.uint64)
    for i in prange(T):
        a, b = f1[i], f2[i]
        nx, ny = octahedral(nrm[a, 0] + nrm[b, 0], nrm[a, 1] + nrm[b, 1], nrm[a, 2] + nrm[b, 2], QUANT_N)
        keys[i] = interleave5(_cell(p0, a, b, lo2, scale, 0), _cell(p0, a, b, lo2, scale, 1),
                              _cell(p0, a, b, lo2, scale, 2), nx, ny)  # fmt: skip
    return keys


@njit(cache=True)
def _box(p):  # pragma: no cover - compiled
    """Per axis the smallest and largest of ``p``'s rows, NaN where any is NaN (as numpy's ``min``, ``max``)."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    nan = np.zeros(3, dtype=np.bool_)
    for i in range(p.shape[0]):
        for c in range(3):
            v = p[i, c]
            nan[c] |= v != v
            if v < lo[c]:
                lo[c] = v
            if v > hi[c]:
                hi[c] = v
    for c in range(3):
        if nan[c]:
            lo[c] = hi[c] = np.nan
    return lo, hi


def keys_fast(mesh: Mesh, f1: np.ndarray, f2: np.ndarray) -> np.ndarray:
    """The edges' 5-D keys (position in the box of every ``p0``, normal direction), compiled."""
    p0 = mesh.face_p0
    lo2, scale = _frame(*_box(p0))
    return _keys(p0, mesh.face_normals, f1, f2, lo2, scale)


def setup_naive(p0: Memory, F: int, counter: OpCounter) -> tuple:
    """The box of every stored ``p0`` (3 R, 6 C per face), then ``2 lo`` and the scale (9 A, 3 C, 3 div)."""
    lo: list[Num | float] = [math.inf] * 3
    hi: list[Num | float] = [-math.inf] * 3
    for f in range(F):
        v = [p0[f, c] for c in range(3)]
        lo = [x if x < m else m for x, m in zip(v, lo)]
        hi = [x if x > m else m for x, m in zip(v, hi)]
    lo2 = [x + x for x in lo]
    hi2 = [x + x for x in hi]
    span = [h - low for h, low in zip(hi2, lo2)]
    scale = [QUANT / (s if s > 0.0 else Num(1.0, counter)) for s in span]
    return lo2, scale


def key_naive(p0: Memory, nrm: Memory, f1: int, f2: int, consts: tuple, counter: OpCounter) -> int:
    """One edge's key on counting arithmetic (12 R, 15 A, 12 M, 5 C, 2 div).

    Position: ``p0(f1) + p0(f2)`` (6 R, 3 A), its cell (3 A, 3 M); direction: ``n1 + n2`` (6 R, 3 A),
    its octahedral cell (6 A, 9 M, 5 C, 2 div).
    """
    lo2, scale = consts
    c = [p0[f1, k] + p0[f2, k] for k in range(3)]
    q = [plain((c[k] - lo2[k]) * scale[k]) for k in range(3)]
    cells = [np.uint64(x) if np.isfinite(x) else np.uint64(0) for x in q]
    nx, ny = counted_octahedral([nrm[f1, k] + nrm[f2, k] for k in range(3)], QUANT_N)
    return int(interleave5(cells[0], cells[1], cells[2], nx, ny))


SCHEME = KeyScheme(
    name=NAME,
    bits=5 * BITS,
    fast=keys_fast,
    setup_naive=setup_naive,
    naive=key_naive,
    key_cost={"read": 12, "add": 15, "mul": 12, "cmp": 5, "div": 2},
    setup_cost=lambda F: {"read": 3 * F, "cmp": 6 * F + 3, "add": 9, "div": 3},
)


def detect(
    mesh: Mesh,
    light: Light,
    variant: str = "intended",
    engine: str = "fast",
    leaf_size: int = LEAF_SIZE,
    fanout: int = FANOUT,
) -> Silhouette:
    """The normal-cone hierarchy's silhouette: exactly the reference edge set.  ``variant``: there is one."""
    return detect_with(mesh, light, NAME, PAPER_MODEL, SCHEME, variant, engine, leaf_size, fanout)


def plain_setup(mesh: Mesh) -> None:
    """Build the default tree once per mesh (cached with it, the one :func:`detect` uses), outside any timing."""
    tree_for(mesh, SCHEME)


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The per-light query uncounted but for its step counters, on the cached tree, one numba thread:
    :func:`.hierarchy_query.plain_query`; ascending edge ids."""
    return plain_query(mesh, SCHEME, light)
