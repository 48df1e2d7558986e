"""Extended Edge Silhouette Detection (EESD): EESD paper Sec. 3.3 (algorithm) and 5.3 (costs).

As printed::

    For e1=1(v1v2) to Number Of Edges
      v1'=v1+ Δv1
      R=ray of light source to v1'
      for f=1 to Number of Faces
        if Intersection(R,f)=false then
          Add v1v2 to S

"If it has an intersection with one of the faces of occluder it is not a
silhouette but on the contrary, if it doesn't have any intersection with
occluder it is a silhouette" (Sec. 3.3).

The outward point (``extend``; the paper leaves Δv1's direction open)
---------------------------------------------------------------------
silcount offsets the edge's *midpoint* ``M = (v1 + v2) / 2`` rather than
``v1``: next to ``v1`` the ray passes through the fan of every face around
``v1``, next to the midpoint only the edge's own faces are near.  With
``e = v2 - v1`` and ``d`` the viewing direction (``M - L`` for a point light
at ``L``; the light's direction for a directional light), ``w = d x e`` is
the normal of the plane through the edge that contains the light rays, so it
points across the edge *as seen from the light*.  ``c`` is the corner that
follows the edge in its first face ``f1`` (first side in side order).  The
point is moved to the side of that plane opposite ``c``::

    P = M + sgn * EPS * sqrt((e.e) / (w.w)) * w,     sgn = -1 if (c - M).w > 0 else +1

i.e. by ``EPS = 1e-6`` edge lengths, perpendicular to the edge in the image
plane, away from ``f1``.  On a closed mesh, at a silhouette edge both faces
lie on ``c``'s side, so ``P`` escapes locally; at any other edge the second
face lies on ``P``'s side and the ray meets it.  A tie ``(c - M).w == 0``
moves towards ``+w``.  An edge seen end-on (``w = 0``) gives ``P = NaN``, a
ray that meets nothing.

The ray (``ray``): a point light casts from ``L`` in direction ``P - L``,
hits counting for ``t`` in ``(0, inf)`` ("from light source to v1' ... and
extend to infinity"); a directional light's ray is the whole line through
``P`` along the light direction, ``t`` in ``(-inf, inf)`` (the source is at
infinity).

Variants
--------
``intended``
    ``Intersection(R, f)`` is a real ray-polygon test: Moller-Trumbore on the
    face's fan triangles ``(p0, p_k, p_k+1)`` (:mod:`silcount.mesh.raytrace`, tie
    rule there; exact for convex polygons, as the papers' faces are), and the
    edge is added once, after the face loop, iff no face is hit (a hit
    counter, as VnV's).  On convex meshes this is the reference silhouette;
    on non-convex ones a silhouette edge whose ``P`` is hidden
    behind another part of the mesh is missed (a subset of the reference,
    ``agreement['missed_edges']``).  On a closed mesh a line that passes through
    the solid meets its surface, so only the edges of the *outline* (the
    boundary of the mesh's projection from the light) survive: 202 of the
    cow's 765 contour edges for one light at 3 radii.  A face seen within about
    ``EPS`` radians of edge-on can let the ray pass beyond it, so in such
    near-ties an edge outside the reference can appear (``extra_edges``).
``literal``
    As printed: "if aR_x+bR_y+cR_z+d=0 then the ray intersected the plane"
    (Sec. 5.3), evaluated at the ray's point ``R = v1'`` (our ``P``) and
    compared exactly with zero, with the plane ``(a, b, c) = n``,
    ``d = -(n . p0)`` of each face precomputed (step ``plane``, which the paper
    assumes done: "calculation of equation of all planes", Sec. 5); and
    ``Add v1v2 to S`` runs inside the face loop for every face whose plane
    misses ``P``.  S then holds each edge once per such face:
    ``notes['duplicates_in_S']`` and ``notes['on_plane_pairs']``.

Boundary and non-manifold edges
-------------------------------
EESD never evaluates light-facing.  A boundary edge has only ``f1``, so ``P``
escapes locally and the edge is reported unless another part of the mesh
blocks the ray, whether its face faces the light or not (the reference
requires a light-facing face).  A non-manifold edge is reported iff none of
its other faces (nor anything else) covers ``P`` on the far side of ``f1``.
``oriented`` (for extrusion) uses the reference's facing flags, uncounted.

Steps and ``true`` costs (docs/counting.md)
-------------------------------------------
``extend`` and ``ray`` (every edge), ``intersection`` (every edge-face pair),
``add`` (every edge added), as in ``silcount/models/eesd2012-eesd.toml``; ``true``-only:
``triangle_test`` (every edge-fan-triangle pair) and ``check_hits`` (every
edge) for ``intended``, ``plane`` (every face) for ``literal``.  Every counted
routine is branch-free (all values computed, then a fixed number of
compares), so its cost is a constant that the ``fast`` engine charges per run;
square roots count as kind ``sqrt``, divisions as ``div``.

The counted routines (``naive`` arithmetic, fixed costs) are in :mod:`.counted`.

Engines
-------
``naive`` runs the double loop on counting arithmetic.  ``fast`` computes the
same points compiled in the same order of operations and casts only the rays
that matter: a ray that meets one of its own edge's faces (the same
Moller-Trumbore test, bit for bit, on the edge's faces' fan triangles:
:func:`.rays.own_blocked`, every light of a :func:`detect_many` batch in one
pass over the edges, the lights innermost) is blocked in
the full loop too, so only the rays that miss their own faces are cast against
every triangle: on a closed mesh these are exactly the edges whose faces lie
on one side as seen from the light, i.e. the reference silhouette (10,720 rays
for 1,556,880 edges on the 1M-face subdivided bunny).  ``notes['rays_cast']``
(fast engine only).  A point light's rays go through
:class:`silcount.mesh.raytrace.RayTracer`'s 3-D grid; a directional light's
are parallel lines, so they meet one 2-D grid of the triangles projected along
them, built per light (:func:`silcount.mesh.parallel_rays.lines_any_hit`): the
same test on the triangles of one cell.

``literal``'s exact-zero plane tests are found by
:func:`silcount.detectors.eesd.onplane.zeros_per_point` (a box tree over the ``P``
points that the planes walk in packets, in parallel, pruning soundly), which
tests only the points whose boxes the plane crosses: O(F sqrt(E)) rather than O(E F), 7.6 s
on the 1.04 M-face subdivided bunny and 25 s on a 1 M-face torus (2 cores, load about 1) against an
estimated 40 min for all pairs.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from silcount.counting.arithmetic import KINDS, Memory, Num, OpCounter, plain
from silcount.detectors.adjacency import facing_of_bits, many_edge_ids, shared_facing_flags
from silcount.detectors.base import (
    EngineRun,
    MeshMemory,
    SilhouetteBatch,
    add_scaled,
    add_scaled_many,
    make_batch,
    make_silhouette,
    on_threads,
    oriented_edges,
    unique_ids,
)
from silcount.detectors.batch import merge_groups, rows_of
from silcount.detectors.eesd.counted import (
    ADD_COST,
    CHECK_COST,
    EPS,
    FACE_READS,
    HIT_COUNT_COST,
    PAIR_LITERAL_COST,
    TRIANGLE_READS,
    counted_outward_point,
    counted_plane,
    counted_ray,
    counted_triangle_hit,
    routine_cost,
)
from silcount.detectors.eesd.onplane import zeros_per_point
from silcount.detectors.eesd.rays import (
    face_planes,
    fan_triangles,
    light_values,
    outward_points_and_rays,
    outward_points_of,
    own_blocked,
    plain_edge_ids,
    ray_data,
    rays_through,
    tracer,
)
from silcount.detectors.result import Silhouette
from silcount.detectors.spec import DetectorSpec
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh
from silcount.mesh.parallel_rays import lines_any_hit

NAME = "eesd"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "eesd2012-eesd"

# ---------------------------------------------------------------- engines


def _naive(mesh: Mesh, light: Light, variant: str):
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    directional = isinstance(light, DirectionalLight)
    table = Memory(mesh.edges.reshape(-1), counter)
    apex = Memory(ray_data(mesh)["apex"], counter)
    E, F = mesh.n_edges, mesh.n_faces
    S = Memory(np.zeros(max(E * F, 1), dtype=np.int64), counter)
    out: list[int] = []
    steps = {"extend": 0, "ray": 0, "intersection": 0, "add": 0}
    point = lambda i: [mem.vertices[3 * plain(i) + k] for k in range(3)]  # noqa: E731
    if variant == "literal":
        planes = Memory(np.zeros(4 * F), counter)
        for f in range(F):
            for k, x in enumerate(counted_plane(mem, f)):
                planes[4 * f + k] = x
        steps["plane"] = F
        on_plane = 0
    else:
        steps.update(triangle_test=0, check_hits=0)
    for e in range(E):  # For e1 = 1 (v1v2) to Number Of Edges
        v1, v2, c = point(table[2 * e]), point(table[2 * e + 1]), point(apex[e])
        light_vals = [mem.light[k] for k in range(3)]
        p = counted_outward_point(v1, v2, c, light_vals, directional)  # v1' = v1 + Δv1
        steps["extend"] += 1
        o, d, t_min, t_max = counted_ray(p, light_vals, directional)  # R = ray of light source to v1'
        steps["ray"] += 1
        hits = Num(0, counter)
        for f in range(F):  # for f = 1 to Number of Faces
            steps["intersection"] += 1  # if Intersection(R, f) = false then
            if variant == "literal":
                a, b, cc, dd = (planes[4 * f + k] for k in range(4))
                if a * p[0] + b * p[1] + cc * p[2] + dd == 0.0:
                    on_plane += 1
                    continue
                S[len(out)] = e  # Add v1v2 to S (every missed face)
                out.append(e)
                steps["add"] += 1
                continue
            lo, hi = plain(mem.face_start[f]), plain(mem.face_start[f + 1])
            first = point(mem.corners[lo])
            prev = point(mem.corners[lo + 1])
            for s in range(lo + 2, hi):  # the face's fan triangles
                nxt = point(mem.corners[s])
                hits = hits + counted_triangle_hit(o, d, first, prev, nxt, t_min, t_max)
                steps["triangle_test"] += 1
                prev = nxt
        if variant == "intended":
            steps["check_hits"] += 1
            if hits == 0:  # no face met: a silhouette edge
                S[len(out)] = e
                out.append(e)
                steps["add"] += 1
    ids = np.asarray(out, dtype=np.int64)
    notes = {"on_plane_pairs": on_plane} if variant == "literal" else {}
    return ids, steps, dict(counter), notes


def _fast_intended(mesh: Mesh, lights: list[Light]) -> list[tuple[np.ndarray, int]]:
    """The ``fast`` engine's runs for lights of one kind: (ids, rays cast) per light."""
    # 1. Each ray against its own edge's faces (the same test, bit for bit), every light in one pass over the
    #    edges.  A hit there is a hit in the full face loop, so those edges are settled without casting.
    own = own_blocked(mesh, lights)
    cands = [np.flatnonzero(~own[:, j]) for j in range(len(lights))]
    points = [outward_points_of(mesh, light, cand) for light, cand in zip(lights, cands, strict=True)]
    # 2. Only the rays that miss their own faces can be silhouettes: cast them against everything.  A
    #    directional light's rays are parallel lines, answered in the plane perpendicular to them, a light a
    #    thread; a point light's go through the tracer's grid (itself parallel).
    if lights[0].is_directional:
        tris = fan_triangles(mesh)
        hits = on_threads(lambda j: lines_any_hit(points[j], light_values(lights[j]), tris), range(len(lights)))
    else:
        rays = tracer(mesh)
        hits = []
        for light, p in zip(lights, points, strict=True):
            o, d, t_min, t_max = rays_through(p, light)
            hits.append(rays.any_hit(o, d, t_min, t_max, what=f"{NAME}: its rays"))
    return [(cand[~hit], int(cand.size)) for cand, hit in zip(cands, hits, strict=True)]


def _intended_tally(mesh: Mesh, light: Light, k: Any, add=add_scaled) -> tuple[dict[str, Any], dict[str, Any]]:
    """Steps and ``true`` tally of :func:`_naive`'s ``intended`` loops with ``k`` edges added (every face is
    tested for every edge: the loops have no data-dependent bound); with ``add=add_scaled_many``, ``k`` one
    count per light of ``light``'s kind and the tally one array per kind."""
    E, F = mesh.n_edges, mesh.n_faces
    T = ray_data(mesh)["tri_face"].size
    steps = {
        "extend": E,
        "ray": E,
        "intersection": E * F,
        "add": k,
        "triangle_test": E * T,
        "check_hits": E,
    }
    true: dict[str, Any] = {}
    add(true, routine_cost("extend", light), E)
    add(true, routine_cost("ray", light), E)
    add(true, {"read": 2}, E)  # the edge's two vertex indices
    add(true, {"read": 1 + 3 + 3 + 3 + 3}, E)  # far corner index; v1, v2, c, light
    add(true, {"read": FACE_READS}, E * F)
    add(true, routine_cost("triangle_test", light), E * T)
    add(true, {"read": TRIANGLE_READS}, E * T)
    add(true, HIT_COUNT_COST, E * T)
    add(true, CHECK_COST, E)
    add(true, ADD_COST, k)
    return steps, true


def _fast_literal(mesh: Mesh, light: Light):
    E, F = mesh.n_edges, mesh.n_faces
    zeros = zeros_per_point(
        outward_points_and_rays(mesh, light)[0], face_planes(mesh), f"{NAME}:literal: its plane tests"
    )
    adds_per_edge = F - zeros
    ids = np.flatnonzero(adds_per_edge)  # S holds edge e adds_per_edge[e] times
    adds = int(adds_per_edge.sum())
    steps = {"extend": E, "ray": E, "intersection": E * F, "add": adds, "plane": F}
    true: dict[str, int] = {}
    add_scaled(true, routine_cost("plane", light), F)
    add_scaled(true, {"write": 4}, F)  # the plane table
    add_scaled(true, routine_cost("extend", light), E)
    add_scaled(true, routine_cost("ray", light), E)
    add_scaled(true, {"read": 2 + 1 + 3 + 3 + 3 + 3}, E)
    add_scaled(true, PAIR_LITERAL_COST, E * F)
    add_scaled(true, ADD_COST, adds)
    return ids, steps, true, {"on_plane_pairs": int(zeros.sum())}


def _silhouette(mesh: Mesh, light: Light, variant: str, engine: str, ids, steps, true, notes) -> Silhouette:
    flags, ties = shared_facing_flags(mesh, light)
    if variant == "literal":
        notes["S_length"] = steps["add"]
        notes["duplicates_in_S"] = steps["add"] - int(unique_ids(ids).size)
    run = EngineRun(ids, steps, true, ties, flags, notes=notes)
    return make_silhouette(mesh, light, NAME, variant, engine, run, PAPER_MODEL)


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """EESD's silhouette of ``mesh`` for ``light`` with its steps and both tallies."""
    if engine == "naive":
        got = _naive(mesh, light, variant)
    elif variant == "literal":
        got = _fast_literal(mesh, light)
    else:
        ((ids, cast),) = _fast_intended(mesh, [light])
        got = (ids, *_intended_tally(mesh, light, int(ids.size)), {"rays_cast": cast})
    return _silhouette(mesh, light, variant, engine, *got)


def detect_many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
    """:func:`detect` (``fast``) for each light as one :class:`.batch.SilhouetteBatch`: ``intended``'s own-face
    test for every light of a kind in one pass over the edges (:func:`.rays.own_blocked`) and its tallies as
    arrays, ``literal``'s plane tests per light; the same answers and tallies."""
    n = len(lights)
    many = many_edge_ids(mesh, lights)  # the facing flags and ties (the reference's pass, kept with the mesh)
    ids: list[np.ndarray] = [np.zeros(0, dtype=np.int64)] * n
    light_notes: dict[str, list] = {}
    if variant == "literal":
        runs = [_fast_literal(mesh, light) for light in lights]
        ids = [r[0] for r in runs]
        steps, true = rows_of([r[1] for r in runs]), rows_of([r[2] for r in runs])
        adds = [r[1]["add"] for r in runs]
        light_notes["on_plane_pairs"] = [r[3]["on_plane_pairs"] for r in runs]
        light_notes["S_length"] = adds
        light_notes["duplicates_in_S"] = [a - int(unique_ids(x).size) for a, x in zip(adds, ids, strict=True)]
    else:
        cast = [0] * n
        step_parts, true_parts = [], []
        for kind in (True, False):
            which = [i for i, light in enumerate(lights) if light.is_directional == kind]
            if not which:
                continue
            for i, (got, c) in zip(which, _fast_intended(mesh, [lights[i] for i in which]), strict=True):
                ids[i], cast[i] = got, c
            k = np.array([ids[i].size for i in which], dtype=np.int64)
            group_steps, group_true = _intended_tally(mesh, lights[which[0]], k, add_scaled_many)
            step_parts.append((np.array(which), group_steps))
            true_parts.append((np.array(which), group_true))
        steps, true = merge_groups(n, step_parts), merge_groups(n, true_parts, KINDS)
        light_notes["rays_cast"] = cast

    def orient(i: int, u: np.ndarray) -> np.ndarray:
        return oriented_edges(mesh, u, facing_of_bits(many[i][2], many[i][3]))

    ties = [got[1] for got in many]
    return make_batch(
        mesh, lights, NAME, variant, ids, steps, true, ties, PAPER_MODEL, orient=orient, light_notes=light_notes
    )


SPEC = DetectorSpec(
    name=NAME,
    label="EESD",
    detect=detect,
    role="paper",
    paper_model=PAPER_MODEL,
    variants=("intended", "literal"),
    engines=("fast", "naive"),
    visited_step="extend",
    plain_edge_ids=plain_edge_ids,
    plain_quadratic=True,
    growth_variant="literal",
    style=("#2e933c", "o"),
    detect_many=detect_many,
)


__all__ = [
    "detect",
    "detect_many",
    "plain_edge_ids",
    "EPS",
    "outward_points_and_rays",
    "face_planes",
    "routine_cost",
    "counted_triangle_hit",
]
