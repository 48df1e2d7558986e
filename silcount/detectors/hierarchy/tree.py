"""Bounded plane hierarchies: the exact, output-sensitive query that ``gaussmap`` and ``cones`` share.

The literature's output-sensitive detectors (Gooch et al., "Interactive
Technical Illustration", I3D 1999, Sec. 4.1; Sander et al., "Silhouette
Clipping", SIGGRAPH 2000, Sec. 3; Johnson and Cohen, "Spatialized Normal
Cone Hierarchies", I3D 2001, Sec. 3) all keep a tree over clusters of edges
whose nodes carry bounds that prove "no silhouette edge below here" for a
whole set of lights.  They differ in how the edges are clustered: by their
arcs on the Gauss sphere (:mod:`.gaussmap`) or by their faces' planes, normal
and offset (:mod:`.cones`).  This module is the rest: the tree, the rule that
decides a face and a node, and the counted build's cost.  The compiled build
is :mod:`.build`, the compiled query :mod:`.walk` (glue in
:mod:`.query`), and both on counting arithmetic :mod:`.naive`.

A face's plane
--------------
Whether face ``f`` faces a light depends only on its plane: its unit normal
``u`` and offset ``c = p0 . u``.  Each face keeps both in float32
(:func:`.build.face_planes`), 16 bytes.  Under a light, the face's
float32 *pre-test* value is ``w = fl32(fl32(fl32(s0 u0) + fl32(s1 u1)) + fl32(s2 u2))``
for a directional light (``s``: the direction scaled by a power of two,
rounded to float32) and ``w = fl(fl(fl(fl(L0 u0) + fl(L1 u1)) + fl(L2 u2)) - c)``
in float64 for a point light ``L``.  :func:`pretest` gives the threshold
``thr`` for the light and proves: **if ``|w| > thr``, the exact facing value
``v`` (``d . n`` or ``(L - p0) . n`` in float64, in the reference's operation
order) has ``w``'s sign and is not 0.**  Otherwise ``v`` itself is evaluated
(from the mesh's float64 ``p0`` and normal), as the reference does.  A face
whose plane cannot be trusted (a zero, tiny, huge or non-finite normal, a
``|p0|_1`` beyond ``2**100``) keeps a NaN plane, which fails every
comparison: it is always evaluated exactly.

The tree
--------
The edges with exactly two faces (almost all, on a manifold mesh) and the
others (boundary and non-manifold edges) are two trees over one leaf order:
each sorted by the key its detector gives (a Z-order code, :class:`KeyScheme`),
cut into leaves of ``leaf_size`` consecutive edges, and grouped ``fanout``
nodes at a time up to one root per tree.  A two-faced edge keeps its id and
its two faces' planes side by side (a leaf is one run of memory, 36 bytes an
edge); the others keep theirs as a CSR.  A face evaluated exactly is found
through the mesh's own edge-to-side table.  Every node keeps the box of its
faces' planes (``u`` and ``c``, lo and hi: eight float32, 32 bytes) in level
order (each tree's root, then each level from its first node), where node
``j`` of a level has children ``j K .. j K + K - 1`` on the next; a node with
an untrusted face below it has the box ``[-inf, inf]``.  A node of the other
tree also records whether a one-faced edge is below it.

Why the prune test is exact
---------------------------
Over a node's box, the lower bound ``lb`` of its faces' pre-test values is
the pre-test's own arithmetic applied to, per axis, the smaller of
``fl(s_i lo_i)`` and ``fl(s_i hi_i)`` (minus ``c``'s upper bound, for a point
light), in the same order; ``ub`` likewise with the larger ones (minus ``c``'s
lower bound).  Rounding to nearest is monotone: ``fl(x y)`` lies between its
values at the interval's ends, and ``fl(x + y)`` and ``fl(x - y)`` are
monotone in each argument, so ``lb <= w <= ub`` for every face below.  If
``lb > thr``, every face below has ``w > thr``, so every exact ``v`` is ``> 0``:
all faces are lit; if ``ub < -thr``, all are unlit.  With no face lit no edge
below has exactly one lit face; with every face lit only a one-faced edge
does, so the subtree is skipped unless one is below.  A box of
``[-inf, inf]`` gives ``lb`` of ``-inf`` or NaN and ``ub`` of ``inf`` or NaN, which
decide nothing; nor does any light :func:`pretest` cannot scale
(``thr = inf``): every node is then opened and every face evaluated exactly.
No epsilon is involved beyond the pre-test's own proven margin.

Costs
-----
The ``naive`` engine builds the tree and runs the query on counting
arithmetic; the ``fast`` engine builds it with compiled kernels and counts
the query's steps in the compiled walk, charging each step what the naive
engine executes for it (docs/counting.md, "gaussmap and cones").  The build
is tallied apart from the query (``notes['build']``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from silcount.counting.arithmetic import Memory, OpCounter
from silcount.detectors.base import add_scaled
from silcount.mesh.lights import DirectionalLight, Light

LEAF_SIZE = 8
FANOUT = 4
DIGIT_BITS = 12  # the radix sort's widest digit: 4096 buckets, two passes for the keys' 24 bits
UNIT_RANGE = 2.0**300  # normals with a largest |component| outside [1 / UNIT_RANGE, UNIT_RANGE] get no plane
P_RANGE = 2.0**100  # faces with a |p0| coordinate beyond get no plane (the offset stays far from float32's range)
PRETEST_MARGIN = 2.0**-20  # the pre-test's threshold, relative to the scale of its values (see pretest)
PRETEST_RANGE = 2.0**300  # lights whose scale is outside [1 / PRETEST_RANGE, PRETEST_RANGE] are not pre-tested
TASK_LEVEL = 3  # the compiled query walks the subtrees rooted on this level in parallel (64 with fan-out 4)


@dataclass(eq=False)
class Hierarchy:
    """Two bounded trees over a mesh's edges in one leaf order (see the module docstring)."""

    order: np.ndarray  # (T,) int32: edge ids in leaf order, the n_pairs two-faced edges first
    n_pairs: int
    planes: np.ndarray  # (2 n_pairs + S, 4) float32: each pair edge's two faces' planes u0 u1 u2 c, in side
    # order, then the other edges' faces' planes as a CSR (NaN rows: untrusted)
    other_start: np.ndarray  # (T - n_pairs + 1,) int64: the other edges' CSR offsets into planes, from 2 n_pairs
    box: np.ndarray  # (N, 8) float32, level order (pair tree, then other tree): u, c lo; u, c hi
    pair_levels: np.ndarray  # (Dp + 1,) int64: each level's first slot in box, root first (empty tree: [0])
    other_levels: np.ndarray  # (Do + 1,) int64, the same for the other tree (its slots follow the pair tree's)
    boundary: np.ndarray  # (N,) bool: a one-faced edge is below the node
    p0_max: float  # largest |p0|_1 of a face with a plane (the point pre-test's P)
    leaf_size: int
    fanout: int
    build_steps: dict[str, int]
    build_tally: dict[str, int]

    @property
    def n_nodes(self) -> int:
        return int(self.box.shape[0])

    @property
    def nbytes(self) -> int:
        """Bytes of every array the tree holds."""
        return int(sum(a.nbytes for a in vars(self).values() if isinstance(a, np.ndarray)))


@dataclass(frozen=True)
class KeyScheme:
    """How a detector orders its edges: each edge's key from its two key faces' planes, in both engines.

    An edge's key faces are its first two sides' faces (a one-faced edge's face twice).
    ``setup(planes)``: per-mesh constants from the ``(F, 4)`` float32 planes (compiled);
    ``fast(planes, key_faces, consts, idx_bits)``: the uint64 keys of the edges whose key faces are the
    rows of ``key_faces`` (n x 2, uint32), each shifted left by ``idx_bits`` with the row in the low bits
    (compiled); ``setup_naive(planes, F, counter)`` and
    ``naive(planes, fa, fb, consts, counter)``: the same constants and one key on counting arithmetic
    (``planes`` a :class:`Memory`); ``key_cost`` and ``setup_cost(F)``: what those execute.
    """

    name: str
    bits: int
    setup: Callable[[np.ndarray], tuple]
    fast: Callable[..., np.ndarray]
    setup_naive: Callable[[Memory, int, OpCounter], tuple]
    naive: Callable[[Memory, int, int, tuple, OpCounter], int]
    key_cost: dict[str, int]
    setup_cost: Callable[[int], dict[str, int]]


# ---- the trees' shape ------------------------------------------------------------------------------------
def levels(n_edges: int, leaf_size: int, fanout: int) -> list[int]:
    """Node counts per level, leaves first, up to the root (empty for no edges)."""
    if n_edges == 0:
        return []
    sizes = [-(-n_edges // leaf_size)]
    while sizes[-1] > 1:
        sizes.append(-(-sizes[-1] // fanout))
    return sizes


def level_starts(n_edges: int, leaf_size: int, fanout: int, first: int = 0) -> np.ndarray:
    """Each level's first slot, root level first, from slot ``first``; the last entry ends the tree."""
    sizes = levels(n_edges, leaf_size, fanout)[::-1]
    return (first + np.concatenate([[0], np.cumsum(sizes, dtype=np.int64)])).astype(np.int64)


def digit_bits(n: int) -> int:
    """The radix sort's digit for ``n`` keys: ``log2 n`` bits, at most :data:`DIGIT_BITS` (a pass costs about
    ``n + 2**bits``, so a small tree does not pay for thousands of empty buckets)."""
    return min(DIGIT_BITS, max(1, (n - 1).bit_length()))


def sort_passes(n: int, key_bits: int) -> int:
    """The radix sort's passes over ``n`` keys of ``key_bits`` bits (none for no key)."""
    return -(-key_bits // digit_bits(n)) if n else 0


# ---- the light's pre-test ----------------------------------------------------------------------------------
def up32(x: float) -> float:
    """The smallest float32 value ``>= x`` (as a float)."""
    r = np.float32(x)
    if float(r) < x:
        r = np.nextafter(r, np.float32(np.inf))
    return float(r)


def pretest(light: Light, p0_max: float) -> tuple[np.ndarray, float]:
    """The float32 light and the threshold of a face's pre-test (the module docstring's ``s`` and ``thr``).

    Each face keeps ``u``, its unit normal, and ``c = p0 . u``, in float32 (:func:`.build.face_planes`:
    each ``u_i`` within ``2**-24`` of the true unit normal ``n^``'s, ``c`` within ``2**-24 |c| + 2**-47.9 |p0|_1``
    of ``p0 . n^``).  ``|w| > thr`` proves the sign of the exact facing value ``v`` and that ``v != 0``:

    * **Directional** ``d``, scaled by a power of two (exact) to ``s`` with largest |component| in ``[1/2, 1)``:
      ``w = fl32(fl32(fl32(s0 u0) + fl32(s1 u1)) + fl32(s2 u2))`` with ``s`` in float32, ``thr = 2**-20 S``,
      ``S = |s|_1 >= 1/2``.  Rounding ``s`` moves ``s . n^`` by at most ``2**-25 S`` (plus ``3 * 2**-150``
      where a component underflows), ``u`` by ``2**-24 S (1 + 2**-24)``, and the float32 sum of three
      products errs by ``gamma_3 = 3 * 2**-24 / (1 - 3 * 2**-24)`` of ``sum |s_i u_i| <= S (1 + 2**-24)^2``:
      in all under ``4.6 * 2**-24 S + 2**-147 < 0.3 thr``.  So ``s . n^`` has ``w``'s sign and
      ``|s . n^| > 0.7 thr``, and ``|d . n| = 2**e |n| |s . n^|`` exceeds float64's error bound for ``v``,
      ``gamma_3 sum |d_i n_i| <= 3.1 * 2**-53 * 2**e |n| S`` plus underflow terms below ``2**-1070`` (``2**e``
      and ``|n|_inf`` are in ``[2**-300, 2**300]``, so ``|d . n| > 2**-622``).
    * **Point** ``L``: ``w = fl(fl(fl(fl(L0 u0) + fl(L1 u1)) + fl(L2 u2)) - c)`` in float64, ``thr = 2**-20 Q``,
      ``Q = 3 |L|_inf + 5 P >= |L|_1 + 5 P`` with ``P = p0_max`` (every face with a plane has ``|p0|_1 <= P``,
      so ``|c| <= 1.01 P``).  ``L . u`` is within ``2**-24 |L|_1`` of ``L . n^``, ``c`` within
      ``2**-24 * 1.76 P + 2**-47.9 * 3 P`` of ``p0 . n^``, and the float64 sums add ``2**-50 (|L|_1 + 1.8 P)``:
      under ``2**-22 Q = thr / 4``.  So ``(L - p0) . n^`` has ``w``'s sign and magnitude above ``0.75 thr``,
      while ``v``'s own error (``fl(L_i - p0_i)``, three products, two sums) is below ``2**-50.9 |n| Q``;
      with ``Q`` and ``|n|_inf`` in ``[2**-300, 2**300]`` nothing over- or underflows in float64.  ``c`` is a
      float32: every face with a plane has ``P <= 2**100`` (so ``|c| < 2**102``, far from float32's
      overflow), and point lights are pre-tested only when ``Q >= 2**-100`` (so the absolute error of a
      ``c`` or ``u_i`` rounded into float32's subnormal range, at most ``2**-150``, stays below ``2**-30 thr``).

    Every light whose ``S``'s scale ``2**e`` (directional) is outside ``[2**-300, 2**300]``, or whose ``Q``
    (point) is outside ``[2**-100, 2**300]``, gets ``thr = inf``: nothing is pre-tested or pruned.  A
    directional light's ``thr`` is rounded up to a float32 (:func:`up32`; a larger threshold only proves
    less), so that the compiled walk compares its float32 ``w`` and bounds with it in float32, exactly as a
    float64 comparison would; a point light's is compared in float64.
    """
    v = [float(x) for x in light.vector]
    if isinstance(light, DirectionalLight):
        m = max(abs(x) for x in v)
        if not (1.0 / PRETEST_RANGE <= m <= PRETEST_RANGE):
            return np.zeros(3, dtype=np.float32), math.inf
        e = math.frexp(m)[1]
        s = [math.ldexp(x, -e) for x in v]
        return np.array(s, dtype=np.float32), up32(PRETEST_MARGIN * (abs(s[0]) + abs(s[1]) + abs(s[2])))
    q = 3.0 * max(abs(x) for x in v) + 5.0 * p0_max  # Python floats: an overflow is inf, silently
    if not (2.0**-100 <= q <= PRETEST_RANGE):
        return np.zeros(3, dtype=np.float32), math.inf
    return np.zeros(3, dtype=np.float32), PRETEST_MARGIN * q


# ---- what the query reports, and what it costs ---------------------------------------------------------------
STEP_NAMES = ("node_test", "node_lit", "node_lit_open", "node_unlit", "node_open", "leaf_open", "edge_test",
              "edge_test_other", "face_test", "face_exact", "add")  # fmt: skip
"""The query's steps: a node tested; proved all lit and skipped; proved all lit but opened (a one-faced edge
below); proved all unlit and skipped; an internal node opened; a leaf opened; an edge tested by the reference
rule; of those, the other tree's (faces read through its CSR); a face pre-tested; a face evaluated exactly (its
pre-test undecided); a silhouette edge output."""


def setup_cost(directional: bool, scaled: bool) -> dict[str, int]:
    """The light's pre-test constants (:func:`pretest`), once per query: the light (3 R); its largest
    |coordinate| (2 C); a directional light's range (2 C), then, if in range, ``s = d 2**-e`` (3 M), ``S``
    (2 A) and ``thr = 2**-20 S`` (1 M); a point light's ``Q = 3 m + 5 P`` (2 M, 1 A), its range (2 C), then,
    if in range, ``thr`` (1 M).  ``scaled``: the light is in range (``thr`` finite)."""
    if directional:
        return {"read": 3, "cmp": 4, "mul": 4, "add": 2} if scaled else {"read": 3, "cmp": 4}
    return {"read": 3, "cmp": 4, "mul": 3 if scaled else 2, "add": 1}


def node_cost(directional: bool) -> dict[str, int]:
    """One node's bounds and first decision: its box's ``u`` (and ``c``) ends (6 R, or 8 R); per axis the two
    products (2 M) and their order (1 C); the two sums of three terms (4 A), less ``c`` for a point light (2 A);
    ``lb > thr`` (1 C)."""
    if directional:
        return {"read": 6, "mul": 6, "cmp": 4, "add": 4}
    return {"read": 8, "mul": 6, "cmp": 4, "add": 6}


def face_cost(directional: bool) -> dict[str, int]:
    """One face's pre-test and its share of the edge's count: its plane (3 R, or 4 R with ``c``), three products
    (3 M), the sums (2 A, a point light 3 A with ``- c``), ``|w| > thr`` (1 C); then its sign (``w > 0``, or
    ``v > 0`` after an exact evaluation: 1 C) added to the edge's count (1 A)."""
    if directional:
        return {"read": 3, "mul": 3, "add": 3, "cmp": 2}
    return {"read": 4, "mul": 3, "add": 4, "cmp": 2}


def exact_cost(directional: bool) -> dict[str, int]:
    """One face's exact value, as the reference computes it: the face through the mesh's tables (the edge id,
    its first side's slot, the side, its face: 4 R); the normal (3 R), 3 M, 2 A; a point light also ``p0``
    (3 R) and ``L - p0`` (3 A)."""
    if directional:
        return {"read": 7, "mul": 3, "add": 2}
    return {"read": 10, "mul": 3, "add": 5}


def query_cost(steps: dict[str, int], directional: bool, scaled: bool) -> dict[str, int]:
    """The ``true`` tally of :func:`.naive.query_naive` with these steps (docs/counting.md);
    ``scaled``: the light's pre-test threshold is finite (:func:`setup_cost`).

    Besides the per-step costs above: a node not proved lit also tests ``ub < -thr`` (1 C); a node proved
    lit reads its boundary flag (1 R); every tested edge tests ``count == 1`` (1 C), and the other tree's
    edges read their CSR range (2 R); a silhouette edge's id is read (1 R) and written out (1 W).
    """
    tally: dict[str, int] = {}
    lit = steps["node_lit"] + steps["node_lit_open"]
    add_scaled(tally, setup_cost(directional, scaled), 1)
    add_scaled(tally, node_cost(directional), steps["node_test"])
    add_scaled(tally, {"cmp": 1}, steps["node_test"] - lit)
    add_scaled(tally, {"read": 1}, lit)
    add_scaled(tally, {"cmp": 1}, steps["edge_test"])
    add_scaled(tally, {"read": 2}, steps["edge_test_other"])
    add_scaled(tally, face_cost(directional), steps["face_test"])
    add_scaled(tally, exact_cost(directional), steps["face_exact"])
    add_scaled(tally, {"read": 1, "write": 1}, steps["add"])
    return tally


__all__ = ["Hierarchy", "KeyScheme", "LEAF_SIZE", "FANOUT", "DIGIT_BITS", "UNIT_RANGE", "P_RANGE", "TASK_LEVEL",
           "PRETEST_MARGIN", "PRETEST_RANGE", "STEP_NAMES", "digit_bits", "sort_passes", "levels", "level_starts",
           "pretest", "up32", "query_cost", "node_cost", "face_cost", "exact_cost", "setup_cost"]  # fmt: skip
