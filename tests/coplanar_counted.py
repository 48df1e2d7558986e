"""HSD's exact coplanar merge (``tight``) executed on counting arithmetic: the naive form of :func:`coplanar.merge`.

HSD paper Sec. V and VI 6.3 merge the faces "that ha[ve] same normal
vectors" before running TA over the polygons.  :mod:`silcount.mesh.coplanar`
does it with vectorised tests and charges its ``true`` tally as step counts
times a per-test cost table.  This module runs the same criterion one scalar
at a time on :class:`~silcount.counting.arithmetic.Num` and
:class:`~silcount.counting.arithmetic.Memory`, so its tally is *observed*;
a test holds its polygons, steps and tally equal to the fast form's.  It is
O(E) Python work with exact rational arithmetic (:class:`fractions.Fraction`,
not the fast form's scaled integers): small meshes only.

What runs, and what it is charged (the conventions of the fast form's table,
``docs/counting.md``):

``candidate_edge`` (every edge)
    the edge's two sides' faces and first vertices from the per-edge side
    table (4 R; an edge without exactly two sides has ``-1`` sentinels in
    every slot), ``f != g`` and ``from_f != from_g`` (2 C, both evaluated).
``orient3d_filter`` (per candidate pair, per tested corner)
    Which corners are tested: every corner of ``g`` against the plane of
    ``f``'s first three corners when ``f`` is a triangle or ``g`` is not;
    every corner of ``f`` against ``g``'s plane when ``f`` is not a triangle
    (both ways round for two polygons); a corner that *is* one of the plane's
    three vertices is skipped.  Face sizes and the skip are not charged (the
    table's convention).  The test reads 12 coordinates, forms 9
    differences, Shewchuk's determinant (9 M, 5 A) and permanent (9 M, 5 A;
    ``abs`` clears a sign bit and is free), the bound (1 M) and one compare:
    12 R, 19 A, 19 M, 1 C.  Every test of a pair runs (no early exit).
``orient3d_exact`` (tests the bound cannot decide)
    the 12 coordinates again, exact, 9 differences and the determinant:
    12 R, 14 A, 9 M, 1 C.
``exact_normal`` (each face of an all-coplanar pair, once)
    9 exact coordinates, ``(p1 - p0) x (p2 - p0)``: 9 R, 9 A, 6 M; the table
    charges no write for keeping it.
``normal_check`` (all-coplanar pairs)
    the two normals (6 R), ``n_f . n_g`` (3 M, 2 A), ``> 0`` (1 C).
``link`` (pairs that pass)
    the two faces' current component labels (2 R), compared (1 C); joining
    two components is not instrumented (the fast form's
    ``connected_components`` is not either).
``label`` (every face)
    its polygon id stored (1 W).

Polygons are numbered by their lowest face, which is their representative;
boundary sides are kept in mesh side order, as in :mod:`.coplanar`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.mesh.model import Mesh

# Shewchuk's static bound for orient3dfast (predicates.c): o3derrboundA = (7 + 56 eps) eps, eps = 2^-53.
_EPS = 2.0**-53
_O3D_ERRBOUND_A = (7.0 + 56.0 * _EPS) * _EPS


@dataclass(frozen=True)
class CountedMerge:
    """The polygons of the exact merge and the merge's observed steps and ``true`` tally."""

    region: np.ndarray
    rep: np.ndarray
    poly_start: np.ndarray
    poly_sides: np.ndarray
    interior: np.ndarray
    steps: dict[str, int]
    true: dict[str, int]


def _free_abs(x: Num) -> Num:
    """``|x|``: a sign-bit clear, not counted."""
    return Num(abs(plain(x)), x.counter)


def _coords(mem: Memory, v: int) -> list[Num]:
    return [mem[3 * v + c] for c in range(3)]


def _orient3d_filter(coord: Memory, a: int, b: int, c: int, d: int) -> bool:
    """Is ``d`` certainly off the plane ``abc``?  Float orient3d against its static error bound."""
    pa, pb, pc, pd = (_coords(coord, v) for v in (a, b, c, d))
    ad = [pa[k] - pd[k] for k in range(3)]
    bd = [pb[k] - pd[k] for k in range(3)]
    cd = [pc[k] - pd[k] for k in range(3)]
    bc = bd[0] * cd[1] - cd[0] * bd[1]
    ca = cd[0] * ad[1] - ad[0] * cd[1]
    ab = ad[0] * bd[1] - bd[0] * ad[1]
    det = ad[2] * bc + bd[2] * ca + cd[2] * ab
    perm = (
        (_free_abs(bd[0] * cd[1]) + _free_abs(cd[0] * bd[1])) * _free_abs(ad[2])
        + (_free_abs(cd[0] * ad[1]) + _free_abs(ad[0] * cd[1])) * _free_abs(bd[2])
        + (_free_abs(ad[0] * bd[1]) + _free_abs(bd[0] * ad[1])) * _free_abs(cd[2])
    )
    bound = perm * _O3D_ERRBOUND_A
    return _free_abs(det) > bound


def _orient3d_exact_zero(exact: Memory, a: int, b: int, c: int, d: int) -> bool:
    """Is ``d`` exactly on the plane ``abc``?  The determinant on exact rationals."""
    pa, pb, pc, pd = (_coords(exact, v) for v in (a, b, c, d))
    ad = [pa[k] - pd[k] for k in range(3)]
    bd = [pb[k] - pd[k] for k in range(3)]
    cd = [pc[k] - pd[k] for k in range(3)]
    det = (
        ad[2] * (bd[0] * cd[1] - cd[0] * bd[1])
        + bd[2] * (cd[0] * ad[1] - ad[0] * cd[1])
        + cd[2] * (ad[0] * bd[1] - bd[0] * ad[1])
    )
    return det == 0


def _exact_normal(exact: Memory, p0: int, p1: int, p2: int) -> list[Num]:
    a, b, c = (_coords(exact, v) for v in (p0, p1, p2))
    e1 = [b[k] - a[k] for k in range(3)]
    e2 = [c[k] - a[k] for k in range(3)]
    return [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]


def _side_table(mesh: Mesh) -> np.ndarray:
    """(E, 4): the two sides' faces and first vertices of each two-sided edge; ``-1`` for the other edges."""
    start, order = mesh.edge_sides
    table = np.full((mesh.n_edges, 4), -1, dtype=np.int64)
    for e in range(mesh.n_edges):
        if start[e + 1] - start[e] == 2:
            s0, s1 = order[start[e]], order[start[e] + 1]
            table[e] = (mesh.side_face[s0], mesh.side_face[s1], mesh.side_from[s0], mesh.side_from[s1])
    return table


def merge_counted(mesh: Mesh) -> CountedMerge:
    """The ``tight`` merge of ``mesh``, one scalar at a time on counting arithmetic."""
    counter = OpCounter()
    E, F = mesh.n_edges, mesh.n_faces
    coord = Memory(mesh.vertices.reshape(-1), counter)
    exact = Memory([Fraction(float(x)) for x in mesh.vertices.reshape(-1)], counter)
    table = Memory(_side_table(mesh).reshape(-1), counter)
    corners = [mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]].tolist() for p in range(F)]
    steps = dict.fromkeys(
        ("candidate_edge", "orient3d_filter", "orient3d_exact", "normal_check", "exact_normal", "link", "label"), 0
    )

    pairs: list[tuple[int, int]] = []
    for e in range(E):
        face_f, face_g, from_f, from_g = (table[4 * e + k] for k in range(4))
        steps["candidate_edge"] += 1
        different_faces, opposite = face_f != face_g, from_f != from_g  # both compares run
        if different_faces and opposite:
            pairs.append((int(plain(face_f)), int(plain(face_g))))

    def on_plane(plane: int, other: int) -> bool:
        a, b, c = corners[plane][:3]
        result = True
        for d in corners[other]:
            if d in (a, b, c):
                continue  # one of the plane's own vertices
            steps["orient3d_filter"] += 1
            if _orient3d_filter(coord, a, b, c, d):
                result = False
                continue
            steps["orient3d_exact"] += 1
            if not _orient3d_exact_zero(exact, a, b, c, d):
                result = False
        return result

    coplanar: list[tuple[int, int]] = []
    for f, g in pairs:
        tri_f, tri_g = len(corners[f]) == 3, len(corners[g]) == 3
        ok = True
        if tri_f or not tri_g:
            ok = on_plane(f, g) and ok
        if not tri_f:
            ok = on_plane(g, f) and ok
        if ok:
            coplanar.append((f, g))

    normal: dict[int, list[Num]] = {}
    normals = Memory(np.zeros(3 * F, dtype=object), counter)
    merged: list[tuple[int, int]] = []
    for f, g in coplanar:
        for p in (f, g):
            if p not in normal:
                steps["exact_normal"] += 1
                normal[p] = _exact_normal(exact, *corners[p][:3])
                normals.data[3 * p : 3 * p + 3] = [plain(x) for x in normal[p]]  # kept: no write charged
        steps["normal_check"] += 1
        nf = [normals[3 * f + k] for k in range(3)]
        ng = [normals[3 * g + k] for k in range(3)]
        if nf[0] * ng[0] + nf[1] * ng[1] + nf[2] * ng[2] > 0:
            merged.append((f, g))

    parent = list(range(F))

    def root(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    labels = Memory(np.arange(F, dtype=np.int64), counter)
    for f, g in merged:
        steps["link"] += 1
        if labels[f] != labels[g]:
            lo, hi = sorted((root(f), root(g)))
            parent[hi] = lo
            for p in range(F):  # relabel, uncounted: the lowest face of each component
                labels.data[p] = root(p)

    roots = [root(p) for p in range(F)]
    reps = sorted(set(roots))
    number = {r: k for k, r in enumerate(reps)}
    region_mem = Memory(np.zeros(F, dtype=np.int64), counter)
    for p in range(F):
        steps["label"] += 1
        region_mem[p] = number[roots[p]]
    region = np.asarray(region_mem.data)

    interior = np.zeros(E, dtype=bool)
    start, order = mesh.edge_sides
    for e in range(E):
        if start[e + 1] - start[e] == 2:
            s0, s1 = order[start[e]], order[start[e] + 1]
            f, g = mesh.side_face[s0], mesh.side_face[s1]
            interior[e] = f != g and mesh.side_from[s0] != mesh.side_from[s1] and region[f] == region[g]
    by_poly: list[list[int]] = [[] for _ in reps]
    for s in range(mesh.n_sides):
        if not interior[mesh.side_edge[s]]:
            by_poly[region[mesh.side_face[s]]].append(s)
    poly_start = np.zeros(len(reps) + 1, dtype=np.int64)
    poly_start[1:] = np.cumsum([len(x) for x in by_poly])
    poly_sides = np.array([s for x in by_poly for s in x], dtype=np.int64)
    return CountedMerge(region, np.array(reps, dtype=np.int64), poly_start, poly_sides, interior, steps, dict(counter))


__all__ = ["CountedMerge", "merge_counted"]
