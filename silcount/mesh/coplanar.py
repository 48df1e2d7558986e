"""Merging adjacent coplanar faces into polygons: the first half of HSD (HSD paper Sec. V, VI 6.3).

HSD keeps "each part of occluder that has same normal vectors" as one polygon
and runs TA over the polygons.  The merge must never put a silhouette edge
inside a polygon, for any light; two criteria are provided.

``tight`` (HSD ``intended``)
    Faces ``f`` and ``g`` sharing a two-sided edge that they traverse in
    opposite directions are merged iff, exactly,

    * every corner of ``g`` lies on the plane of ``f``'s first three corners,
      and every corner of ``f`` on the plane of ``g``'s first three corners
      (``orient3d == 0``), and
    * ``n_f . n_g > 0`` for the normals from the first three corners (the
      same orientation, and neither degenerate).

    Then ``(L - p0_g) . n_g = c (L - p0_f) . n_f`` with ``c > 0`` for every
    point ``L`` (and ``d . n_g = c d . n_f`` for every direction), so the two
    faces have the same light-facing sign for every light, in exact
    arithmetic: no silhouette edge of the reference can lie between them.
    (With floating-point facing values, a light within rounding distance of
    the common plane can still split them: that is a tie, not a silhouette.)
    Equality of oriented planes is transitive, so a region's members all
    share one plane and orientation.  ``orient3d`` is first evaluated in
    floating point with Shewchuk's static error bound (``errboundA``,
    "Adaptive Precision Floating-Point Arithmetic", 1997); a test the bound
    cannot decide, and every ``n_f . n_g``, is evaluated exactly: by
    Shewchuk's expansions (:mod:`silcount.mesh.exact`) in one compiled pass
    over the pairs when every coordinate is in their exact range, else on
    integers (:mod:`silcount.mesh.coplanar_ints`: all coordinates scaled by one
    common power of two, the same exact rational arithmetic as
    :class:`fractions.Fraction` without its normalisation).

``facets`` (HSD ``literal``)
    The paper's "same normal vectors" read loosely, as ``trimesh``'s
    ``Trimesh.facets`` (adjacent triangles whose normals agree within an
    angle tolerance; polygons are fan-triangulated first and each face joins
    the facets of its triangles).  On scanned meshes this merges faces that
    are not coplanar and hides real silhouette edges inside polygons.

A region's polygon is given by its *boundary sides*: the sides of its faces
whose edge is not interior (an edge is interior iff it has exactly two sides,
traversed in opposite directions, by two faces of the same region).  A region
may have holes, so its sides need not form one cycle; they are kept in mesh
side order (face index, then corner order).  Regions are numbered by their
lowest face index, which is also the face that decides the polygon's
visibility (its *representative*).

The merge cost is reported separately (:attr:`Merge.steps`, :attr:`Merge.true`):
it is not run on counting memory; its ``true`` tally applies the per-test
costs of :data:`MERGE_STEP_COST` (the operations each vectorised test
performs, listed there) to the measured step counts.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from silcount.errors import check_choice
from silcount.mesh.coplanar_ints import common_shift, coplanar_pairs_ints, mask_ids, normals_agree_ints
from silcount.mesh.exact import ERRBOUND_A, exact_range_ok, normals_dot_sign, orient3d_sign
from silcount.mesh.model import Mesh

CRITERIA = ("tight", "facets")

# Operations of one evaluation of each merge step (counting rules in docs/counting.md).
MERGE_STEP_COST: dict[str, dict[str, int]] = {
    # read both sides' faces and first vertices, compare faces and directions
    "candidate_edge": {"read": 4, "cmp": 2},
    # float orient3d: 12 coordinates, 9 differences, 3x3 determinant (9 mul, 5 add),
    # permanent (9 mul, 5 add; |x| free), bound = errboundA * permanent (1 mul), |det| > bound
    "orient3d_filter": {"read": 12, "add": 19, "mul": 19, "cmp": 1},
    # the same determinant on exact integers, then its sign
    "orient3d_exact": {"read": 12, "add": 14, "mul": 9, "cmp": 1},
    # exact normal (p1 - p0) x (p2 - p0) of each face of a coplanar pair, once per face:
    # 9 coordinates, 6 differences, 6 mul, 3 add
    "exact_normal": {"read": 9, "add": 9, "mul": 6},
    # n_f . n_g > 0 per coplanar pair: 6 normal components, 3 mul, 2 add, the sign
    "normal_check": {"read": 6, "add": 2, "mul": 3, "cmp": 1},
    # grouping: each merged edge links two face labels (2 reads, 1 compare); each face gets a label
    "link": {"read": 2, "cmp": 1},
    "label": {"write": 1},
}


@dataclass(frozen=True)
class Merge:
    """Faces grouped into polygons, with each polygon's boundary sides."""

    criterion: str
    region: np.ndarray  # (F,) polygon id of each face
    rep: np.ndarray  # (P,) representative (lowest-index) face of each polygon
    poly_start: np.ndarray  # (P+1,) CSR offsets into poly_sides
    poly_sides: np.ndarray  # boundary sides (mesh side ids), grouped by polygon, in side order
    interior: np.ndarray  # (E,) bool: the edge lies inside a polygon
    steps: dict[str, int] = field(default_factory=dict)
    true: dict[str, int] = field(default_factory=dict)

    @property
    def n_polygons(self) -> int:
        return int(self.rep.size)

    @property
    def n_polygon_edges(self) -> int:
        return int(self.interior.size - np.count_nonzero(self.interior))

    @property
    def mean_sides(self) -> float:
        return self.poly_sides.size / max(self.n_polygons, 1)

    def paper_params(self) -> dict[str, float]:
        """The papers' ``f_n``, ``e_n``, ``m`` of the polygon mesh (HSD paper Sec. 6.3)."""
        return {"f_n": self.n_polygons, "e_n": self.n_polygon_edges, "m": self.mean_sides}

    def summary(self) -> dict:
        return {
            "criterion": self.criterion,
            "polygons": self.n_polygons,
            "polygon_edges": self.n_polygon_edges,
            "interior_edges": int(np.count_nonzero(self.interior)),
            "mean_sides": self.mean_sides,
            "steps": dict(self.steps),
            "true": dict(self.true),
        }


def _opposite_pairs(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Edges with two sides in opposite directions on two different faces: (edge ids, face f, face g)."""
    ms = mesh.manifold_sides
    e = np.flatnonzero(ms[:, 0] >= 0)
    s0, s1 = ms[e, 0], ms[e, 1]
    f, g = mesh.side_face[s0], mesh.side_face[s1]
    ok = (mesh.side_from[s0] != mesh.side_from[s1]) & (f != g)
    return e[ok], f[ok], g[ok]


@nb.njit(cache=True, inline="always")
def _plane_tests(V, corners, face_start, sizes, first3, plane, other, w, lens, off):  # pragma: no cover - compiled
    """Every corner of face ``other`` (but the plane's own first three) against ``plane``'s plane.

    Returns (tests, tests the float filter left unsure, off plane).  The float determinant and its
    bound are :func:`silcount.mesh.coplanar_ints._orient3d_float`'s, operation for operation; an unsure
    test is decided exactly (:func:`orient3d_sign`) unless an earlier test already put the pair off
    the plane.
    """
    i0, i1, i2 = first3[plane, 0], first3[plane, 1], first3[plane, 2]
    tests = unsure = 0
    for k in range(sizes[other]):
        q = corners[face_start[other] + k]
        if q == i0 or q == i1 or q == i2:
            continue  # trivially on the plane
        tests += 1
        ad0, ad1, ad2 = V[i0, 0] - V[q, 0], V[i0, 1] - V[q, 1], V[i0, 2] - V[q, 2]
        bd0, bd1, bd2 = V[i1, 0] - V[q, 0], V[i1, 1] - V[q, 1], V[i1, 2] - V[q, 2]
        cd0, cd1, cd2 = V[i2, 0] - V[q, 0], V[i2, 1] - V[q, 1], V[i2, 2] - V[q, 2]
        bc = bd0 * cd1 - cd0 * bd1
        ca = cd0 * ad1 - ad0 * cd1
        ab = ad0 * bd1 - bd0 * ad1
        det = ad2 * bc + bd2 * ca + cd2 * ab
        perm = (
            (abs(bd0 * cd1) + abs(cd0 * bd1)) * abs(ad2)
            + (abs(cd0 * ad1) + abs(ad0 * cd1)) * abs(bd2)
            + (abs(ad0 * bd1) + abs(bd0 * ad1)) * abs(cd2)
        )
        if abs(det) > ERRBOUND_A * perm:
            off = True
        else:
            unsure += 1
            if not off and orient3d_sign(V, i0, i1, i2, q, w, lens) != 0:
                off = True
    return tests, unsure, off


@nb.njit(cache=True, parallel=True)
def _coplanar_pairs(V, corners, face_start, sizes, first3, f, g):  # pragma: no cover - compiled
    """Per opposite pair: (orient3d tests, of them unsure, coplanar, coplanar with ``n_f . n_g > 0``).

    In parallel chunks; see :func:`_tight_links`.  Both predicates are exact (Shewchuk's expansions).
    """
    n = f.size
    tests = np.zeros(n, dtype=np.int64)
    unsure = np.zeros(n, dtype=np.int64)
    coplanar = np.empty(n, dtype=np.bool_)
    merged = np.zeros(n, dtype=np.bool_)
    n_chunks = 256
    for c in nb.prange(n_chunks):
        w = np.empty((20, 512))
        lens = np.empty(9, dtype=np.int64)
        wn = np.empty((24, 2048))
        lens_n = np.empty(18, dtype=np.int64)
        for i in range(c * n // n_chunks, (c + 1) * n // n_chunks):
            a, b = f[i], g[i]
            tri_a, tri_b = sizes[a] == 3, sizes[b] == 3
            off = False
            if tri_a or not tri_b:
                t, u, off = _plane_tests(V, corners, face_start, sizes, first3, a, b, w, lens, off)
                tests[i] += t
                unsure[i] += u
            if not tri_a:
                t, u, off = _plane_tests(V, corners, face_start, sizes, first3, b, a, w, lens, off)
                tests[i] += t
                unsure[i] += u
            coplanar[i] = not off
            if not off:
                sign = normals_dot_sign(
                    V, first3[a, 0], first3[a, 1], first3[a, 2], first3[b, 0], first3[b, 1], first3[b, 2], wn, lens_n
                )
                merged[i] = sign > 0
    return tests, unsure, coplanar, merged


def _tight_links(mesh: Mesh, pairs: tuple) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """Face pairs to merge under the exact criterion, and the step counts of the tests.

    ``pairs``: :func:`_opposite_pairs` of the mesh.  Every corner of the other face is tested against
    this face's plane, both ways round; when one face is a triangle T, the other face's corners
    against T's plane suffice (with n_T . n_P > 0 they put P's plane on T's, so T's corners lie on
    P's plane too).
    """
    _, f, g = pairs
    steps = {"candidate_edge": int(mesh.n_edges)}
    first3 = mesh.corners[mesh.face_start[:-1, None] + np.arange(3)]  # (F, 3)
    V = mesh.vertices
    fast = exact_range_ok(V)  # Shewchuk's expansions are exact in this range; else exact Python integers
    if fast:
        tests, unsure, coplanar, merged = _coplanar_pairs(
            V, mesh.corners, mesh.face_start, mesh.face_sizes, first3, f, g
        )
        steps["orient3d_filter"], steps["orient3d_exact"] = int(tests.sum()), int(unsure.sum())
    else:
        coplanar = coplanar_pairs_ints(mesh, f, g, first3, steps)
    cand = np.flatnonzero(coplanar)
    steps["normal_check"] = int(cand.size)
    if not cand.size:
        return f[cand], g[cand], steps
    faces = mask_ids(mesh.n_faces, f[cand], g[cand])
    steps["exact_normal"] = int(faces.size)
    if fast:
        cand = np.flatnonzero(merged)
    else:
        cand = cand[normals_agree_ints(V, first3, faces, f[cand], g[cand], common_shift(V))]
    return f[cand], g[cand], steps


def _facet_links(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """Face pairs in one ``trimesh`` facet (polygons fan-triangulated; each face joins its triangles' facets)."""
    import trimesh

    sizes = mesh.face_sizes
    n_tri = sizes - 2
    tri_face = np.repeat(np.arange(mesh.n_faces), n_tri)
    fan = np.arange(n_tri.sum()) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri)
    base = mesh.face_start[tri_face]
    tris = np.stack([mesh.corners[base], mesh.corners[base + fan + 1], mesh.corners[base + fan + 2]], axis=1)
    tm = trimesh.Trimesh(mesh.vertices, tris, process=False)
    facets = tm.facets
    if len(facets):
        lens = np.array([len(x) for x in facets])
        members = tri_face[np.concatenate(facets)]
        heads = np.repeat(tri_face[[x[0] for x in facets]], lens)
    else:
        lens = np.zeros(0, dtype=np.int64)
        members = heads = np.zeros(0, dtype=np.int64)
    # the triangles of one polygon belong together
    same_face = np.flatnonzero(np.diff(tri_face) == 0)
    f = np.concatenate([heads, tri_face[same_face]])
    g = np.concatenate([members, tri_face[same_face + 1]])
    return f, g, {"triangles": int(tris.shape[0]), "facets": int(len(facets)), "facet_triangles": int(lens.sum())}


def _build(mesh: Mesh, criterion: str) -> Merge:
    F = mesh.n_faces
    pairs = _opposite_pairs(mesh)
    f, g, steps = _tight_links(mesh, pairs) if criterion == "tight" else _facet_links(mesh)
    from scipy.sparse import coo_matrix  # scipy (~0.5 s): only when a merge runs
    from scipy.sparse.csgraph import connected_components

    graph = coo_matrix((np.ones(f.size, dtype=np.int8), (f, g)), shape=(F, F))
    _, label = connected_components(graph, directed=False)
    rep = np.full(label.max() + 1, F, dtype=np.int64)
    np.minimum.at(rep, label, np.arange(F))
    order = np.argsort(rep)  # number the polygons by their lowest face
    renum = np.empty_like(order)
    renum[order] = np.arange(order.size)
    region = renum[label]
    rep = rep[order]
    e, a, b = pairs
    interior = np.zeros(mesh.n_edges, dtype=bool)
    interior[e[region[a] == region[b]]] = True
    boundary = np.flatnonzero(~interior[mesh.side_edge])
    poly_sides = boundary[np.argsort(region[mesh.side_face[boundary]], kind="stable")]
    poly_start = np.zeros(rep.size + 1, dtype=np.int64)
    np.cumsum(np.bincount(region[mesh.side_face[poly_sides]], minlength=rep.size), out=poly_start[1:])
    true: dict[str, int] = {}
    if criterion == "tight":
        steps["link"] = int(f.size)
        steps["label"] = F
        for step, n in steps.items():
            for kind, c in MERGE_STEP_COST.get(step, {}).items():
                true[kind] = true.get(kind, 0) + c * n
    return Merge(criterion, region, rep, poly_start, poly_sides, interior, steps, true)


_CACHE: "weakref.WeakKeyDictionary[Mesh, dict[str, Merge]]" = weakref.WeakKeyDictionary()


def merge(mesh: Mesh, criterion: str = "tight") -> Merge:
    """The polygons of ``mesh`` under ``criterion`` (``tight`` or ``facets``), cached per mesh."""
    check_choice("merge criterion", criterion, CRITERIA, error=ValueError)
    per_mesh = _CACHE.setdefault(mesh, {})
    if criterion not in per_mesh:
        per_mesh[criterion] = _build(mesh, criterion)
    return per_mesh[criterion]


__all__ = ["Merge", "merge", "CRITERIA", "MERGE_STEP_COST"]
