"""The Gauss-map hierarchy: Gooch, Sloan, Gooch, Shirley and Riesenfeld, I3D 1999, Sec. 4.1 (silcount's build).

Each edge is an arc on the Gauss sphere between its two faces' normals; a
directional light ``d`` sees an edge as a silhouette edge iff the arc
crosses the great circle ``d . x = 0``.  Gooch et al. bucket the arcs on a
hierarchically subdivided sphere and visit only the buckets that circle
crosses (they report 5.1x over brute force on a 78,804-face sphere).

silcount's reading
------------------
* **The subdivided sphere** is the octahedron unfolded onto a square
  (octahedral map) and split as a quadtree: a cell is a prefix of the
  2-D Z-order (Morton) code of 12 + 12 bits.  An arc is placed by the code
  of its point ``u1 + u2`` (the sum of its ends, the faces' unit normals, so
  on the arc).  The paper's choice of subdivision is open; this one gives a
  cell of every level in one integer.
* **Buckets** are ``leaf_size`` consecutive arcs in that order, grouped
  ``fanout`` at a time up to one root (:mod:`.tree`); a bucket's bound
  is the box of its arcs' end points (the faces' float32 unit normals, with
  their offsets).  The circle "passes through" a node unless the box proves
  every face below lit or every face unlit (proof in :mod:`.tree`), so
  the answer is exactly the ``reference`` edge set, ties and grazing lights
  included.
* **Point lights** (which the Gauss map does not handle: facing then depends
  on position) are answered exactly by the same traversal, the node's bound
  then the box of its faces' planes (normal and offset); since the buckets
  group edges by normal only, the offsets of a bucket spread over the mesh
  and prune less.  The counts show what that fallback costs.

Parameters: ``leaf_size`` (default 8) and ``fanout`` (default 4); see
``docs/literature.md`` for how they were chosen.  The build's own tally is in
``notes['build']``; the key's integer bit interleaving is index arithmetic
and is not counted (``docs/counting.md``).
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import Memory, OpCounter
from silcount.detectors.hierarchy.morton import counted_octahedral, interleave2, octahedral, plane_sum
from silcount.detectors.hierarchy.naive import read32
from silcount.detectors.hierarchy.query import hierarchy_spec
from silcount.detectors.hierarchy.tree import KeyScheme

NAME = "gaussmap"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "silcount-gaussmap"
BITS = 12  # per axis of the octahedral map
QUANT = float((1 << BITS) - 1) / 2.0  # (q + 1) * QUANT lies in [0, 2**12 - 1] for q in [-1, 1]


@njit(cache=True, parallel=True)
def _keys(plane, kf, idx_bits, keys, chunks):  # pragma: no cover - compiled
    """Z-order codes of the octahedral cells of the arcs' points ``u1 + u2``, with :func:`key_naive`'s arithmetic,
    shifted left by ``idx_bits`` above the row."""
    T = kf.shape[0]
    sh = np.uint64(idx_bits)
    for t in prange(chunks):  # each thread a run of edges, asking ROWS_AHEAD edges ahead for their faces' planes
        end = (t + 1) * T // chunks
        for i in range(t * T // chunks, end):
            x, y, z, _ = plane_sum(plane, kf, i, end)
            cx, cy = octahedral(x, y, z, QUANT)
            keys[i] = (interleave2(cx, cy) << sh) | np.uint64(i)


def keys_fast(plane: np.ndarray, key_faces: np.ndarray, consts: tuple, idx_bits: int) -> np.ndarray:
    """Octahedral Z-order keys of the arcs ``u1 + u2`` (an untrusted face's NaN plane: cell 0)."""
    keys = np.empty(key_faces.shape[0], dtype=np.uint64)
    _keys(plane, key_faces, idx_bits, keys, numba.get_num_threads())
    return keys


def key_naive(plane: Memory, f1: int, f2: int, consts: tuple, counter: OpCounter) -> int:
    """One arc's key on counting arithmetic: ``u1 + u2`` (6 R, 3 A), its octahedral cell (6 A, 9 M, 5 C, 2 div)."""
    u = [read32(plane, (f1, c), True) + read32(plane, (f2, c), True) for c in range(3)]
    cx, cy = counted_octahedral(u, QUANT)
    return int(interleave2(cx, cy))


SCHEME = KeyScheme(
    name=NAME,
    bits=2 * BITS,
    setup=lambda plane: (),
    fast=keys_fast,
    setup_naive=lambda plane, F, counter: (),
    naive=key_naive,
    key_cost={"read": 6, "add": 9, "mul": 9, "cmp": 5, "div": 2},
    setup_cost=lambda F: {},
)


SPEC = hierarchy_spec(NAME, "Gauss map", PAPER_MODEL, SCHEME, ("#7b4ea3", "^"))
detect = SPEC.detect
