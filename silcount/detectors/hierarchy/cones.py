"""The spatialized normal-cone hierarchy: Johnson & Cohen, I3D 2001, Sec. 3; Sander et al., SIGGRAPH 2000, Sec. 3.

A tree over clusters of edges; each node keeps a bound on its faces'
positions and one on their normals, so that a single test proves "no
silhouette edge below here" for the light at hand and the whole subtree is
skipped.  Johnson and Cohen bound a cluster's normals by a cone (axis and
half-angle) and its positions by a sphere; Sander et al. anchor such cones
at the cluster.  Point and directional lights.

silcount's reading
------------------
* **What a position bound is for.**  Whether a face faces a point light
  ``L`` depends on its plane alone: its unit normal ``u`` and its offset
  ``c = p0 . u`` (``L . u > c``).  A face's position along its plane does not
  enter the test; its position across it, ``c``, does.  So silcount bounds a
  cluster by the box of its faces' planes: the box of their unit normals
  (which holds the normal cone) and the interval of their offsets (the
  anchored cone's position bound, in the one coordinate the test reads).
* **Clusters** are ``leaf_size`` consecutive edges in the 3-D Z-order of the
  edge's two faces' planes summed: the octahedral-map cell of ``u1 + u2``
  (8 bits per axis) and the cell of ``c1 + c2`` in the mesh's range of
  offsets (8 bits); grouped ``fanout`` at a time up to one root
  (:mod:`.tree`): a tree clustered by normal and position at once, as
  Johnson and Cohen's spatialized normal cones are, built bottom-up.  (On
  the 1.04 M-face bunny, a key of the faces' first vertices and normal
  direction, 5-D, reached 1.6x as many leaves per point light.)
* **The test** is exact in floating point (proof in :mod:`.tree`), so
  the answer is exactly the ``reference`` edge set, ties, grazing lights and
  lights in a face's plane included.  A box of normals holds their cone and
  an offset interval holds every offset a sphere would allow, so the box
  prunes no node the cone and sphere would keep for the faces' planes.

Parameters: ``leaf_size`` (default 8) and ``fanout`` (default 4); see
``docs/literature.md``.  The build's own tally is in ``notes['build']``.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.detectors.hierarchy.morton import counted_octahedral, interleave3, octahedral, plane_sum
from silcount.detectors.hierarchy.naive import read32
from silcount.detectors.hierarchy.query import hierarchy_spec
from silcount.detectors.hierarchy.tree import KeyScheme

NAME = "cones"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "silcount-cones"
BITS = 8  # per coordinate of the 3-D key: two of normal direction, one of offset
QUANT = float((1 << BITS) - 1)  # an offset's cell: [0, QUANT]
QUANT_N = QUANT / 2.0  # a direction's: (p + 1) * QUANT_N in [0, QUANT] for p in [-1, 1]


@njit(cache=True)
def _offset_range(plane):  # pragma: no cover - compiled
    """The smallest and largest offset of a face with a plane, as :func:`setup_naive` (NaN loses every compare)."""
    lo, hi = np.inf, -np.inf
    for f in range(plane.shape[0]):
        c = np.float64(plane[f, 3])
        if c < lo:
            lo = c
        if c > hi:
            hi = c
    return lo, hi


def _frame(lo, hi) -> tuple:
    """``2 lo`` and the scale that maps ``[2 lo, 2 hi]`` onto ``[0, QUANT]`` (``QUANT`` for a flat range), on
    floats or counted values alike (3 A, 1 C, 1 div)."""
    lo2, hi2 = lo + lo, hi + hi
    span = hi2 - lo2
    one = Num(1.0, span.counter) if isinstance(span, Num) else 1.0
    return lo2, QUANT / (span if span > 0.0 else one)


def setup(plane: np.ndarray) -> tuple:
    """The offsets' frame, compiled (the same floats as :func:`setup_naive`)."""
    lo, hi = _offset_range(plane)
    return _frame(float(lo), float(hi))


@njit(cache=True, inline="always")
def _offset_cell(q):  # pragma: no cover - compiled
    """The cell of a scaled offset: ``q`` within ``[0, QUANT]``, else the nearer end (a NaN: 0)."""
    if q >= 0.0:
        return np.uint64(q) if q <= QUANT else np.uint64(QUANT)
    return np.uint64(0)


@njit(cache=True, parallel=True)
def _keys(plane, kf, lo2, scale, idx_bits, keys, chunks):  # pragma: no cover - compiled
    """3-D Z-order codes of the planes' sum (direction of ``u1 + u2``, cell of ``c1 + c2``), as :func:`key_naive`,
    shifted left by ``idx_bits`` above the row."""
    T = kf.shape[0]
    sh = np.uint64(idx_bits)
    for t in prange(chunks):  # each thread a run of edges, asking ROWS_AHEAD edges ahead for their faces' planes
        end = (t + 1) * T // chunks
        for i in range(t * T // chunks, end):
            x, y, z, w = plane_sum(plane, kf, i, end)
            nx, ny = octahedral(x, y, z, QUANT_N)
            q = (w - lo2) * scale
            keys[i] = (interleave3(nx, ny, _offset_cell(q)) << sh) | np.uint64(i)


def keys_fast(plane: np.ndarray, key_faces: np.ndarray, consts: tuple, idx_bits: int) -> np.ndarray:
    """The edges' 3-D plane keys, compiled."""
    keys = np.empty(key_faces.shape[0], dtype=np.uint64)
    _keys(plane, key_faces, consts[0], consts[1], idx_bits, keys, numba.get_num_threads())
    return keys


def setup_naive(plane: Memory, F: int, counter: OpCounter) -> tuple:
    """The offsets' range over the faces (1 R, 2 C a face), then ``2 lo`` and the scale (3 A, 1 C, 1 div)."""
    lo, hi = Num(np.inf, counter), Num(-np.inf, counter)
    for f in range(F):
        c = read32(plane, (f, 3), True)
        lo = c if c < lo else lo
        hi = c if c > hi else hi
    return _frame(lo, hi)


def key_naive(plane: Memory, f1: int, f2: int, consts: tuple, counter: OpCounter) -> int:
    """One edge's key on counting arithmetic (8 R, 11 A, 10 M, 7 C, 2 div).

    Direction: ``u1 + u2`` (6 R, 3 A), its octahedral cell (6 A, 9 M, 5 C, 2 div); offset: ``c1 + c2`` (2 R,
    1 A), less ``2 lo`` (1 A), scaled (1 M), its cell (two compares, 2 C).
    """
    lo2, scale = consts
    u = [read32(plane, (f1, c), True) + read32(plane, (f2, c), True) for c in range(3)]
    nx, ny = counted_octahedral(u, QUANT_N)
    q = (read32(plane, (f1, 3), True) + read32(plane, (f2, 3), True) - lo2) * scale
    above, below = q >= 0.0, q <= QUANT
    cell = (np.uint64(plain(q)) if below else np.uint64(QUANT)) if above else np.uint64(0)
    return int(interleave3(nx, ny, cell))


SCHEME = KeyScheme(
    name=NAME,
    bits=3 * BITS,
    setup=setup,
    fast=keys_fast,
    setup_naive=setup_naive,
    naive=key_naive,
    key_cost={"read": 8, "add": 11, "mul": 10, "cmp": 7, "div": 2},
    setup_cost=lambda F: {"read": F, "cmp": 2 * F + 1, "add": 3, "div": 1},
)


SPEC = hierarchy_spec(NAME, "normal cones", PAPER_MODEL, SCHEME, ("#e07a1f", "v"))
detect = SPEC.detect
