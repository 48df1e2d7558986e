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
  2-D Z-order (Morton) code of 21 + 21 bits.  An arc is placed by the code
  of its point ``n1 + n2`` (a positive combination of its ends, so on the
  arc).  The paper's choice of subdivision is open; this one gives a cell
  of every level in one integer.
* **Buckets** are ``leaf_size`` consecutive arcs in that order, grouped
  ``fanout`` at a time up to one root (:mod:`.hierarchy`); a bucket's bound
  is the box of its arcs' end normals.  The circle "passes through" a node
  unless the box's exact floating-point bounds prove every face below lit
  or every face unlit (proof in :mod:`.hierarchy`), so the answer is exactly
  the ``reference`` edge set, ties and grazing lights included.
* **Point lights** (which the Gauss map does not handle: facing then depends
  on position) are answered exactly by the same traversal with each node's
  box of ``p0`` added to its bound; since the buckets group edges by normal
  only, those boxes span much of the mesh and prune little.  The counts
  show what that fallback costs.

Parameters: ``leaf_size`` (default 8) and ``fanout`` (default 4); see
``docs/literature.md`` for how they were chosen.  The build's own tally is in
``notes['build']``; the key's integer bit interleaving is index arithmetic
and is not counted (``docs/counting.md``).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import Memory, OpCounter
from silcount.detectors.hierarchy import FANOUT, LEAF_SIZE, KeyScheme
from silcount.detectors.hierarchy_query import detect as detect_with
from silcount.detectors.hierarchy_query import plain_query, tree_for
from silcount.detectors.morton import counted_octahedral, interleave2, octahedral
from silcount.detectors.result import Silhouette
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

NAME = "gaussmap"  # what it declares of itself: see silcount.detectors.MODULES
LABEL = "Gauss map"
PAPER_MODEL = "silcount-gaussmap"
ONE_VARIANT = True
LITERATURE = True
VISITED_STEP = "edge_test"
PLAIN_QUADRATIC = False
GROWTH_VARIANT = "intended"
STYLE = ("#7b4ea3", "^")  # colour, marker in figures
QUANT = float((1 << 20) - 1)  # (q + 1) * QUANT lies in [0, 2**21 - 2] for q in [-1, 1]


@njit(cache=True, parallel=True)
def _keys(nrm, f1, f2, quant):  # pragma: no cover - compiled
    """Z-order codes of the octahedral cells of the arcs' points ``n1 + n2``, with :func:`key_naive`'s arithmetic."""
    T = f1.size
    keys = np.empty(T, dtype=np.uint64)
    for i in prange(T):
        a, b = f1[i], f2[i]
        cx, cy = octahedral(nrm[a, 0] + nrm[b, 0], nrm[a, 1] + nrm[b, 1], nrm[a, 2] + nrm[b, 2], quant)
        keys[i] = interleave2(cx, cy)
    return keys


def keys_fast(mesh: Mesh, f1: np.ndarray, f2: np.ndarray) -> np.ndarray:
    """Octahedral Z-order keys of the arcs ``n1 + n2`` (non-finite points, from overflowing normals: cell 0)."""
    return _keys(mesh.face_normals, f1, f2, QUANT)


def key_naive(p0: Memory, nrm: Memory, f1: int, f2: int, consts: tuple, counter: OpCounter) -> int:
    """One arc's key on counting arithmetic: ``n1 + n2`` (6 R, 3 A), its octahedral cell (6 A, 9 M, 5 C, 2 div)."""
    cx, cy = counted_octahedral([nrm[f1, c] + nrm[f2, c] for c in range(3)], QUANT)
    return int(interleave2(cx, cy))


SCHEME = KeyScheme(
    name=NAME,
    bits=42,
    fast=keys_fast,
    setup_naive=lambda p0, F, counter: (),
    naive=key_naive,
    key_cost={"read": 6, "add": 9, "mul": 9, "cmp": 5, "div": 2},
    setup_cost=lambda F: {},
)


def detect(
    mesh: Mesh,
    light: Light,
    variant: str = "intended",
    engine: str = "fast",
    leaf_size: int = LEAF_SIZE,
    fanout: int = FANOUT,
) -> Silhouette:
    """The Gauss-map hierarchy's silhouette: exactly the reference edge set.  ``variant``: there is one."""
    return detect_with(mesh, light, NAME, PAPER_MODEL, SCHEME, variant, engine, leaf_size, fanout)


def plain_setup(mesh: Mesh) -> None:
    """Build the default tree once per mesh (cached with it, the one :func:`detect` uses), outside any timing."""
    tree_for(mesh, SCHEME)


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """The per-light query uncounted but for its step counters, on the cached tree, one numba thread:
    :func:`.hierarchy_query.plain_query`; ascending edge ids."""
    return plain_query(mesh, SCHEME, light)
