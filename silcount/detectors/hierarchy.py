"""Bounded edge hierarchies: the exact, output-sensitive query that ``gaussmap`` and ``cones`` share.

The literature's output-sensitive detectors (Gooch et al., "Interactive
Technical Illustration", I3D 1999, Sec. 4.1; Sander et al., "Silhouette
Clipping", SIGGRAPH 2000, Sec. 3; Johnson and Cohen, "Spatialized Normal
Cone Hierarchies", I3D 2001, Sec. 3) all keep a tree over clusters of edges
whose nodes carry bounds that prove "no silhouette edge below here" for a
whole set of lights.  They differ in how the edges are clustered: by their
arcs on the Gauss sphere (:mod:`.gaussmap`) or by position (:mod:`.cones`).
This module is the rest: the tree, its bounds and its counted build cost (the compiled build is
:mod:`.hierarchy_build`, the query :mod:`.hierarchy_query` over the kernels of :mod:`.hierarchy_walk`,
the counted engine :mod:`.hierarchy_naive`).

The tree
--------
The edges are sorted by a key the caller gives (a Z-order code, see
:class:`KeyScheme`), cut into leaves of ``leaf_size`` consecutive edges, and
``fanout`` consecutive nodes of one level make a node of the next, up to one
root.  The nodes are numbered in depth-first preorder, each with the range of
edge positions below it and a skip to the node after its subtree, so that
the counted query is one forward pass that jumps over what it prunes
(:func:`shape`).  Every node keeps two axis-aligned boxes over the faces of
the edges below it: of their normals ``n = (p1 - p0) x (p2 - p0)`` and of
their first vertices ``p0``, exactly the values
:func:`~silcount.detectors.adjacency.facing_flags` uses, and whether a
boundary edge (one face) is below it.  The boxes and flags are stored in
level order (the root, then each level from its first node), where a node's
children are adjacent and node ``j`` of a level has children ``j K .. j K +
K - 1`` on the next: the compiled query walks them level by level, reading
each level forwards (:mod:`.hierarchy_query`); ``level_of`` maps a preorder
number to its level-order slot.  A leaf's edge is
tested by the reference rule (exactly one of its faces lit), so boundary
and non-manifold edges are in the tree like the others.  The faces are
renumbered in the order the sorted edges first reach them and their ``p0``
and normals copied in that order, so that a leaf's edges read neighbouring
memory.

Why the prune test is exact
---------------------------
A face is light-facing iff ``fl(fl(fl(a0 n0) + fl(a1 n1)) + fl(a2 n2)) > 0``
with ``a = L - p0`` (``fl(L_i - p0_i)``) or ``a = d``, in this operation
order.  In IEEE arithmetic with rounding to nearest, ``fl(x + y)`` is
non-decreasing in each argument, ``fl(x * y)`` is monotone in each argument
for the other fixed, and ``fl(L - x)`` is non-increasing in ``x``.  So over
a box of ``p0`` and a box of ``n`` every rounded term ``fl(a_i n_i)`` lies
between the smallest and the largest of its values at the box's corners
(``fl`` of the exact extreme, which a product takes at a corner), and the
rounded sum lies between the same sums of those corner extremes, computed
in the same order.  If that lower bound is ``> 0`` every face below the
node faces the light; if the upper bound is ``<= 0`` none does.  With no
face lit no edge below has exactly one lit face; with every face lit only a
boundary edge does, so the subtree is skipped unless a boundary edge is
below it; no epsilon is involved, and a node is opened
whenever the bounds do not decide.  Overflow to infinity keeps every
monotonicity; a NaN (``inf - inf`` in a sum) makes both comparisons false,
which only opens the node.  Faces whose normal or ``p0`` is not finite
(an overflowing cross product) are never boxed: their edges go to ``rest``,
tested on every query.

Costs
-----
The ``naive`` engine builds the tree and runs the query on counting
arithmetic; the ``fast`` engine builds it with compiled kernels and counts
the query's steps in the compiled traversal, charging each step the cost
the naive engine executes for it (docs/counting.md, "gaussmap and cones").
The build is tallied apart from the query (``notes['build']``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from silcount.counting.arithmetic import Memory, OpCounter
from silcount.detectors.base import add_scaled
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh

LEAF_SIZE = 8
FANOUT = 4
DIGIT_BITS = 11  # the radix sort's digit: 2048 buckets, four passes for 42 bits, six for 63


@dataclass(eq=False)
class Hierarchy:
    """A bounded tree over a mesh's edges (see the module docstring); faces are numbered locally."""

    order: np.ndarray  # (T,) int64: the tree's edge ids in leaf order
    edge_start: np.ndarray  # (T + 1,) int64: CSR of their faces (local ids) in ``edge_faces``
    edge_faces: np.ndarray  # (sum of valences,) int32
    nodes: np.ndarray  # (N, 3) int64, preorder (root 0): the subtree's edge positions lo, hi; its skip
    level_of: np.ndarray  # (N,) int64: the level-order slot of each preorder node (root 0)
    level_start: np.ndarray  # (D + 1,) int64: each level's first slot, root level first
    nbox: np.ndarray  # (N, 6) float64, level order: the normal box, lo (3) then hi (3)
    pbox: np.ndarray  # (N, 6) float64, level order: the p0 box, lo (3) then hi (3)
    boundary: np.ndarray  # (N,) bool, level order: a boundary edge is below the node
    rest: np.ndarray  # (R,) int64: edges with a non-finite face, tested on every query
    rest_start: np.ndarray  # (R + 1,) int64: CSR of their faces (local ids)
    rest_faces: np.ndarray  # int32
    p0: np.ndarray  # (F, 3) float64: each local face's first vertex
    nrm: np.ndarray  # (F, 3) float64: each local face's normal
    plane: np.ndarray  # (F, 4) float32: each local face's unit normal and offset, NaN where untrusted
    p0_max: float  # largest |p0| coordinate in the tree (the query's overflow guard)
    leaf_size: int
    fanout: int
    build_steps: dict[str, int]
    build_tally: dict[str, int]

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def bounds(self) -> np.ndarray:
        """(N, 12), level order: normal box lo, hi, then p0 box lo, hi (a copy of ``nbox`` and ``pbox``)."""
        return np.hstack([self.nbox, self.pbox])

    @property
    def nbytes(self) -> int:
        """Bytes of every array the tree holds (its own copies of ``p0`` and the normals included)."""
        return int(sum(a.nbytes for a in vars(self).values() if isinstance(a, np.ndarray)))


@dataclass(frozen=True)
class KeyScheme:
    """How a detector orders its edges: the key of each tree edge, in both engines, and its counted costs.

    An edge's key is computed from two of its faces ``f1``, ``f2`` (its first two sides' faces; a
    boundary edge's one face twice).  ``fast(mesh, f1, f2)``: uint64 keys, vectorised or compiled;
    ``setup_naive(p0, F, counter)``: per-mesh constants from the stored ``p0`` (counted);
    ``naive(p0, nrm, f1, f2, consts, counter)``: one key on counting arithmetic, the same integer;
    ``key_cost``: what ``naive`` executes per key; ``setup_cost(F)``: what ``setup_naive`` executes.
    """

    name: str
    bits: int
    fast: Callable[[Mesh, np.ndarray, np.ndarray], np.ndarray]
    setup_naive: Callable[[Memory, int, OpCounter], tuple]
    naive: Callable[[Memory, Memory, int, int, tuple, OpCounter], int]
    key_cost: dict[str, int]
    setup_cost: Callable[[int], dict[str, int]]


# ---- the tree's shape and edges (shared by both engines) ------------------------------------------------
def levels(n_edges: int, leaf_size: int, fanout: int) -> list[int]:
    """Node counts per level, leaves first, up to the root (empty for no edges)."""
    if n_edges == 0:
        return []
    sizes = [-(-n_edges // leaf_size)]
    while sizes[-1] > 1:
        sizes.append(-(-sizes[-1] // fanout))
    return sizes


def shape(n_edges: int, leaf_size: int, fanout: int) -> tuple[np.ndarray, np.ndarray]:
    """The tree over ``n_edges`` sorted edges in depth-first preorder (root first, a node before its subtree).

    ``nodes[i]``: the subtree's edge positions ``lo, hi`` and its ``skip``, the node after the
    subtree, so that a query is one forward pass that jumps over pruned subtrees; node ``i`` is a
    leaf iff ``skip == i + 1``.  ``depth``: 0 at the root.
    """
    sizes = levels(n_edges, leaf_size, fanout)
    if not sizes:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    start, end, depth = [], [], []
    n_leaves = sizes[0]
    for level, size in enumerate(sizes):  # node j of a level covers leaves [j K^level, (j + 1) K^level)
        span = fanout**level
        own = np.arange(size, dtype=np.int64)
        start.append(own * span)
        end.append(np.minimum(own * span + span, n_leaves))
        depth.append(np.full(size, len(sizes) - 1 - level, dtype=np.int64))
    starts, ends, depths = (np.concatenate(x) for x in (start, end, depth))
    pre = np.lexsort((depths, starts))  # by first leaf, ancestors before descendants
    starts, ends, depths = starts[pre], ends[pre], depths[pre]
    nodes = np.empty((starts.size, 3), dtype=np.int64)
    nodes[:, 0] = starts * leaf_size
    nodes[:, 1] = np.minimum(ends * leaf_size, n_edges)
    nodes[:, 2] = np.searchsorted(starts, ends, side="left")
    return nodes, depths


def level_slots(nodes: np.ndarray, depth: np.ndarray, n_edges: int, leaf_size: int,
                fanout: int) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The level-order slot of each preorder node, and each level's first slot (root level first).

    Node ``j`` of level ``l`` (``l = 0`` at the root) is slot ``level_start[l] + j``; its children are
    slots ``level_start[l + 1] + j K ..`` on the next level, its leaves ``j K**(D - 1 - l) ..``.
    """
    sizes = levels(n_edges, leaf_size, fanout)[::-1]
    level_start = np.concatenate([[0], np.cumsum(sizes, dtype=np.int64)]).astype(np.int64)
    if not sizes:
        return np.zeros(0, dtype=np.int64), level_start
    span = np.asarray(fanout, dtype=np.int64) ** (len(sizes) - 1 - depth)  # leaves below a node of each depth
    return level_start[depth] + nodes[:, 0] // leaf_size // span, level_start


UNIT_RANGE = 2.0**300  # normals with a largest |component| outside [1 / UNIT_RANGE, UNIT_RANGE] get no unit normal


def n_leaves(nodes: np.ndarray) -> int:
    """How many of the preorder ``nodes`` are leaves (``skip == i + 1``)."""
    return int(np.count_nonzero(nodes[:, 2] == np.arange(1, nodes.shape[0] + 1)))


def split_edges(mesh: Mesh) -> tuple[np.ndarray | None, np.ndarray]:
    """The tree's edge ids (every face finite; ``None`` when that is every edge) and the others (``rest``)."""
    if np.isfinite(mesh.face_p0).all() and np.isfinite(mesh.face_normals).all():  # the common case, at once
        return None, np.zeros(0, dtype=np.int64)
    finite = np.isfinite(mesh.face_p0).all(axis=1) & np.isfinite(mesh.face_normals).all(axis=1)
    start, order = mesh.edge_sides
    bad = np.add.reduceat((~finite[mesh.side_face[order]]).astype(np.int64), start[:-1]) > 0
    return np.flatnonzero(~bad), np.flatnonzero(bad)


@njit(cache=True, parallel=True)
def _first_two_faces(start, order, side_face, ids, every):  # pragma: no cover - compiled
    """:func:`key_faces` of every edge (``every``) or of ``ids``, in parallel."""
    T = start.size - 1 if every else ids.size
    f1, f2 = np.empty(T, dtype=np.int64), np.empty(T, dtype=np.int64)
    for i in prange(T):
        e = np.int64(i) if every else ids[i]
        s = start[e]
        f1[i] = side_face[order[s]]
        f2[i] = side_face[order[s + 1 if start[e + 1] - s > 1 else s]]
    return f1, f2


def key_faces(mesh: Mesh, ids: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Each tree edge's key faces: its first two sides' faces (a boundary edge's one face twice)."""
    start, order = mesh.edge_sides
    every = ids is None
    return _first_two_faces(start, order, mesh.side_face, np.zeros(0, dtype=np.int64) if every else ids, every)


def tree_edges(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The edges in the tree (every face finite), the others, the edges' face CSR, and each edge's key faces."""
    start, order = mesh.edge_sides
    ids, rest = split_edges(mesh)
    f1, f2 = key_faces(mesh, ids)
    ids = np.arange(mesh.n_edges, dtype=np.int64) if ids is None else ids
    return ids, rest, start, mesh.side_face[order], np.stack([f1, f2], axis=1)


def build_cost(sizes: dict[str, int], scheme: KeyScheme) -> tuple[dict[str, int], dict[str, int]]:
    """Steps and ``true`` tally of :func:`.hierarchy_naive.build_naive` for a tree of these sizes."""
    F, T, S = sizes["faces"], sizes["tree_edges"], sizes["tree_sides"]
    passes = -(-scheme.bits // DIGIT_BITS) if T else 0
    tally: dict[str, int] = {}
    add_scaled(tally, {"read": 13, "add": 9, "mul": 6, "write": 6}, F)  # p0 and normal, stored
    add_scaled(tally, scheme.setup_cost(F), 1)
    add_scaled(tally, {"read": 3, "write": 1}, T)  # start, the key's two faces; the key stored
    add_scaled(tally, scheme.key_cost, T)
    # radix sort, per pass: histogram (key, bucket: 2 R, 1 A, 1 W); prefix sums (2 R, 1 A, 1 W per
    # bucket); scatter (key, index, bucket: 3 R; key, index, bucket: 3 W; 1 A)
    add_scaled(tally, {"read": 5, "add": 2, "write": 4}, passes * T)
    add_scaled(tally, {"read": 2, "add": 1, "write": 1}, passes * (1 << DIGIT_BITS))
    # renumbering: per edge its index, id, start pair (4 R), order and CSR end (2 W); per side the face
    # and its local id (2 R), "not yet numbered" (1 C), the local id stored (1 W); per face its first
    # visit (1 W, p0 and normal copied: 6 R, 6 W) and the final scan's test (1 R, 1 C)
    add_scaled(tally, {"read": 4, "write": 2}, T)
    add_scaled(tally, {"read": 2, "cmp": 1, "write": 1}, S)
    add_scaled(tally, {"read": 7, "cmp": 1, "write": 7}, F)
    add_scaled(tally, {"read": 2, "write": 1}, sizes["rest_sides"])  # a rest edge's face, its local id
    # bounds, last node first: per node its skip (1 R), "a leaf" (1 C), its box, flag, edge range and
    # skip stored (16 W); per leaf its edge range (2 R); per leaf edge its CSR pair (2 R), "one face"
    # (1 A, 1 C); per side the face, its p0 and normal (7 R) and 12 compares; per internal node the
    # last "child within" test (1 C); per child that test, its box, flag and skip (14 R), 12 compares
    N, leaves = sizes["nodes"], sizes["leaves"]
    add_scaled(tally, {"read": 1, "cmp": 1, "write": 16}, N)
    add_scaled(tally, {"read": 2}, leaves)
    add_scaled(tally, {"read": 2, "add": 1, "cmp": 1}, T)
    add_scaled(tally, {"read": 7, "cmp": 12}, S)
    add_scaled(tally, {"cmp": 1}, N - leaves)
    add_scaled(tally, {"read": 14, "cmp": 13}, max(N - 1, 0))
    return {**sizes, "sort_passes": passes}, tally


# ---- what the query reports, and when its boxes cannot be trusted ----------------------------------
STEP_NAMES = ("node_test", "node_lit", "node_lit_open", "node_unlit", "node_open", "leaf_open", "edge_test",
              "edge_side", "add")  # fmt: skip


def overflows(tree: Hierarchy, light: Light) -> bool:
    """Could ``L - p0`` overflow for this light?  Then no box is trusted and every node is opened."""
    return (not isinstance(light, DirectionalLight)) and float(np.abs(light.vector).max()) + tree.p0_max > 1e307


__all__ = ["Hierarchy", "KeyScheme", "LEAF_SIZE", "FANOUT", "UNIT_RANGE", "build_cost", "levels", "shape",
           "level_slots", "tree_edges", "split_edges", "key_faces", "overflows", "n_leaves", "STEP_NAMES"]  # fmt: skip
