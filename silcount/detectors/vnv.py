"""The Visible-non-Visible algorithm (VnV): HSD paper Sec. IV 4.2 and VI 6.2; EESD paper Sec. 3.2 and 5.2.

As printed (EESD paper Sec. 3.2)::

    For E=1 to Number Of Edges
      For F=1 to Number Of Faces
        If F.visible =True then
          E_counter =E_counter+1
      If e_counter=1 then
        Add E to S

The double loop is the algorithm's cost structure (``e_n * f_n`` visibility
tests, the papers' sums in Sec. 5.2 / 6.2), so both variants keep it.

Variants
--------
``literal``
    Exactly as printed: the loop never asks whether face F contains edge E,
    and the counter is never reset ("counter never reset" reading: it starts
    at 0 once, before the edge loop).  After edge number ``e`` (1-based) it
    holds ``e * v`` with ``v`` the number of light-facing faces, so the output
    is the first edge when ``v == 1`` and nothing otherwise.  The other
    reading (reset per edge) would output every edge when ``v == 1`` and
    nothing otherwise; its edge count is in ``notes['reset_reading_edges']``.
``intended``
    The counter is reset for every edge and counts only the faces that
    contain the edge: inside ``If F.visible`` (the printed test comes first,
    so every pair still pays one visibility test, as the papers charge), a
    ``contains`` test scans F's sides for edge E (reads ``face_start[F]``,
    ``face_start[F+1]``, then one read of ``side_edge`` and one compare per
    side examined, stopping at the match).  The counter rises only on a match.

Boundary and non-manifold edges (``intended``): the edge is a silhouette edge
iff exactly one of its incident faces is light-facing, as in the reference:
a boundary edge iff its face faces the light; a non-manifold edge iff
exactly one of its faces does.

Steps
-----
``visibility`` (every edge-face pair), ``counter`` (every increment),
``check_counter`` (every edge), ``add`` (every edge added), as in
``silcount/models/eesd2012-vnv.toml``; ``true``-only: ``contains`` (intended, every
pair whose face is light-facing).

Engines
-------
``naive`` runs the double loop on counting arithmetic (small meshes only:
it is O(E F)).  ``fast`` computes VnV's counters from the data and applies
VnV's own test ``e_counter == 1`` to them: ``intended``'s counter of edge E
is the number of light-facing faces whose sides list E (one ``bincount``
over the light-facing faces' sides; a face lists an edge at most once, since
faces with a repeated corner are dropped); ``literal``'s never-reset counter
after edge ``e`` (0-based) is ``(e + 1) * v``.  It never consults the
reference rule.  ``E*F`` visibility tests; per light-facing face with
``m_f`` sides, ``E`` containment scans, each examining all ``m_f`` sides
except when E is the face's side at 0-based place ``j``, which stops after
``j + 1``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.detectors.adjacency import facing_of_bits, many_edge_ids, shared_facing_flags
from silcount.detectors.base import (
    EngineRun,
    MeshMemory,
    Silhouette,
    SilhouetteBatch,
    add_scaled,
    add_scaled_many,
    counted_visibility,
    make_batch,
    make_silhouette,
    oriented_edges,
    visibility_cost_many,
    visibility_true_cost,
)
from silcount.detectors.edge_array import popcount
from silcount.detectors.spec import DetectorSpec
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh

NAME = "vnv"  # what it declares of itself: SPEC, at the end
PAPER_MODEL = "eesd2012-vnv"

COUNTER_COST = {"add": 1}  # counter + 1
CHECK_COST = {"cmp": 1}  # counter == 1 (the counter is a local: no read)
ADD_COST = {"write": 1}  # S[k] = E
CONTAINS_COST = {"read": 2}  # face_start[F], face_start[F+1]
SIDE_EXAMINED_COST = {"read": 1, "cmp": 1}  # side_edge[s] == E


def _naive(mesh: Mesh, light: Light, variant: str):
    counter = OpCounter()
    mem = MeshMemory(mesh, light, counter)
    side_edge = Memory(mesh.side_edge, counter)
    E, F = mesh.n_edges, mesh.n_faces
    S = Memory(np.zeros(E, dtype=np.int64), counter)
    out: list[int] = []
    flags = np.zeros(F, dtype=bool)
    ties = 0
    steps = {"visibility": 0, "counter": 0, "check_counter": 0, "add": 0}
    if variant == "intended":
        steps["contains"] = 0
    count = Num(0, counter)  # literal: set once, never reset
    for e in range(E):  # For E = 1 to Number Of Edges
        if variant == "intended":
            count = Num(0, counter)
        for f in range(F):  # For F = 1 to Number Of Faces
            visible, value = counted_visibility(mem, f)  # If F.visible = True then
            steps["visibility"] += 1
            if e == 0:
                flags[f], ties = visible, ties + (value == 0.0)
            if not visible:
                continue
            if variant == "intended":  # ... and F contains E
                steps["contains"] += 1
                lo, hi = plain(mem.face_start[f]), plain(mem.face_start[f + 1])
                if not any(side_edge[s] == e for s in range(lo, hi)):  # stops at the match
                    continue
            count = count + 1  # E_counter = E_counter + 1
            steps["counter"] += 1
        steps["check_counter"] += 1
        if count == 1:  # If e_counter = 1 then
            S[len(out)] = e  # Add E to S
            out.append(e)
            steps["add"] += 1
    return EngineRun(np.asarray(out, dtype=np.int64), steps, dict(counter), ties, flags)


@njit(cache=True)
def _facing_sides(face_start, side_edge, is_facing, E):  # pragma: no cover - compiled
    """Over the light-facing faces' sides: each edge's E_counter, the number of those sides (one counter
    increment each), and the sides behind each one in its face (which ``contains`` does not examine
    when it stops there)."""
    counters = np.zeros(E, dtype=np.int64)
    sides = 0
    behind = 0
    for f in range(is_facing.size):
        if is_facing[f]:
            lo, hi = face_start[f], face_start[f + 1]
            sides += hi - lo
            for s in range(lo, hi):
                counters[side_edge[s]] += 1
                behind += hi - s - 1
    return counters, sides, behind


def _fast(mesh: Mesh, light: Light, variant: str):
    is_facing, ties = shared_facing_flags(mesh, light)
    E, F = mesh.n_edges, mesh.n_faces
    n_vis = int(np.count_nonzero(is_facing))
    if variant == "intended":
        # E_counter of each edge: the light-facing faces whose sides list it (a face lists an edge once)
        counters, sides, behind = _facing_sides(mesh.face_start, mesh.side_edge, is_facing, E)
        increments = int(sides)  # one E_counter increment per light-facing side
        ids = np.flatnonzero(counters == 1)  # If e_counter = 1 then Add E to S
        # contains(F, E) examines every side of F when E is not among them, else stops at E's side
        examined = int(E * sides - behind)
    else:
        # E_counter is never reset: after edge e (0-based) it holds (e + 1) * n_vis
        counters = n_vis * np.arange(1, E + 1, dtype=np.int64)
        ids = np.flatnonzero(counters == 1)
        increments = int(counters[-1]) if E else 0
    steps = {"visibility": E * F, "counter": increments, "check_counter": E, "add": int(ids.size)}
    true: dict[str, int] = {}
    add_scaled(true, visibility_true_cost(light), E * F)
    add_scaled(true, COUNTER_COST, increments)
    add_scaled(true, CHECK_COST, E)
    add_scaled(true, ADD_COST, ids.size)
    if variant == "intended":
        steps["contains"] = E * n_vis
        add_scaled(true, CONTAINS_COST, E * n_vis)
        add_scaled(true, SIDE_EXAMINED_COST, examined)
    return EngineRun(ids, steps, true, ties, is_facing)


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """VnV's silhouette of ``mesh`` for ``light`` with its steps and both tallies."""
    run = (_naive if engine == "naive" else _fast)(mesh, light, variant)
    if variant == "literal":
        n_vis = int(np.count_nonzero(run.is_facing))
        run.notes["reset_reading_edges"] = mesh.n_edges if n_vis == 1 else 0
    return make_silhouette(mesh, light, NAME, variant, engine, run, PAPER_MODEL)


@njit(cache=True, nogil=True)
def _facing_sides_many(face_start, side_edge, bits, lights, E):  # pragma: no cover - compiled
    """:func:`_facing_sides` for each light of one 64-light word pass (bit ``lights[j]`` of ``bits[f]``: face
    ``f`` faces light ``j``): each light's edges of ``E_counter == 1`` (CSR, ascending), its light-facing
    sides, the sides behind them and its light-facing faces.

    The lights are answered bit-parallel: one pass over the faces' sides gives each edge the word of lights
    for which one of its sides faces them (``once``) and the word for which two or more do (``more``); the
    edge's counter is 1 for exactly the lights of ``once & ~more``.  The three counts are sums over each
    light's facing faces of 1, ``n`` and ``n (n - 1) / 2`` (a face of ``n`` sides adds ``hi - s - 1`` for each
    side ``s``).  The same numbers as the counters of every light in turn (:func:`_facing_sides`, light by light
    in ``tests/test_detect_many.py``), in one pass over the sides instead of one per light: 16x less time over
    the shared corpus's meshes."""
    n = lights.size
    F = bits.size
    zero, one = np.uint64(0), np.uint64(1)
    pass_bits = zero
    slot = np.full(64, -1, dtype=np.int64)  # the light of each bit of the word
    for j in range(n):
        pass_bits |= one << np.uint64(lights[j])
        slot[lights[j]] = j
    once = np.zeros(E, dtype=np.uint64)
    more = np.zeros(E, dtype=np.uint64)
    for f in range(F):
        word = bits[f] & pass_bits
        for s in range(face_start[f], face_start[f + 1]):
            e = side_edge[s]
            more[e] |= once[e] & word
            once[e] |= word
    sizes = face_start[1:] - face_start[:-1]
    pairs = sizes * (sizes - 1) // 2
    sides = np.zeros(n, dtype=np.int64)
    behind = np.zeros(n, dtype=np.int64)
    facing = np.zeros(n, dtype=np.int64)
    for j in range(n):
        bit = np.uint64(lights[j])
        a = b = c = 0
        for f in range(F):
            on = np.int64((bits[f] >> bit) & one)
            a += on
            b += on * sizes[f]
            c += on * pairs[f]
        facing[j], sides[j], behind[j] = a, b, c
    counts = np.zeros(n + 1, dtype=np.int64)
    for e in range(E):
        once[e] &= ~more[e]  # from here on: the lights whose counter of edge e is exactly 1
        x = once[e]
        while x != zero:
            low = x & (~x + one)
            counts[slot[_bit_index(low)] + 1] += 1
            x ^= low
    offsets = np.cumsum(counts)
    ids = np.empty(offsets[n], dtype=np.int64)
    fill = offsets[:n].copy()
    for e in range(E):
        x = once[e]
        while x != zero:
            low = x & (~x + one)
            j = slot[_bit_index(low)]
            ids[fill[j]] = e
            fill[j] += 1
            x ^= low
    return offsets, ids, sides, behind, facing


@njit(cache=True, inline="always")
def _bit_index(low):  # pragma: no cover - compiled
    """The index of the one set bit of ``low`` (a power of two): the set bits below it."""
    return popcount(low - np.uint64(1))


def detect_many(mesh: Mesh, lights: list[Light], variant: str = "intended") -> SilhouetteBatch:
    """:func:`detect` (``fast``) for each light from the reference's 64-light facing words
    (:func:`.adjacency.many_edge_ids`): ``intended``'s counters for every light of a word pass in one compiled
    loop (:func:`_facing_sides_many`), ``literal``'s from each light's count of light-facing faces; one
    :class:`.batch.SilhouetteBatch`, the same answers and tallies."""
    many = many_edge_ids(mesh, lights)
    E, F = mesh.n_edges, mesh.n_faces
    n = len(lights)
    ids: list[np.ndarray] = []
    sides = np.zeros(n, dtype=np.int64)
    behind = np.zeros(n, dtype=np.int64)
    n_vis = np.zeros(n, dtype=np.int64)
    lo = 0
    while lo < n:  # one word pass at a time: the lights sharing one array of facing words
        hi = lo
        while hi < n and many[hi][2] is many[lo][2]:
            hi += 1
        bits = many[lo][2]
        which = np.array([many[i][3] for i in range(lo, hi)], dtype=np.int64)
        off, got, sides[lo:hi], behind[lo:hi], n_vis[lo:hi] = _facing_sides_many(
            mesh.face_start, mesh.side_edge, bits, which, E
        )
        if variant == "intended":
            ids += [got[off[j] : off[j + 1]] for j in range(hi - lo)]
        lo = hi
    if variant == "intended":
        increments = sides
    else:  # E_counter is never reset: after edge e it holds (e + 1) * n_vis, 1 only at e = 0 with n_vis = 1
        ids = [np.zeros(1 if v == 1 and E else 0, dtype=np.int64) for v in n_vis.tolist()]
        increments = E * n_vis
    k = np.array([x.size for x in ids], dtype=np.int64)
    steps: dict = {"visibility": E * F, "counter": increments, "check_counter": E, "add": k}
    true: dict[str, np.ndarray] = {}
    add_scaled_many(true, visibility_cost_many(lights), E * F)
    add_scaled_many(true, COUNTER_COST, increments)
    add_scaled_many(true, CHECK_COST, E)
    add_scaled_many(true, ADD_COST, k)
    light_notes = {}
    if variant == "intended":
        steps["contains"] = E * n_vis
        add_scaled_many(true, CONTAINS_COST, E * n_vis)
        add_scaled_many(true, SIDE_EXAMINED_COST, E * sides - behind)
    else:
        light_notes["reset_reading_edges"] = [E if v == 1 else 0 for v in n_vis.tolist()]

    def orient(i: int, u: np.ndarray) -> np.ndarray:
        return oriented_edges(mesh, u, facing_of_bits(many[i][2], many[i][3]))

    ties = [got[1] for got in many]
    return make_batch(
        mesh, lights, NAME, variant, ids, steps, true, ties, PAPER_MODEL, orient=orient, light_notes=light_notes
    )


@njit(cache=True)
def _each_edge_against_every_face(edges, vertices, face_start, corners, light, directional):  # pragma: no cover
    """The printed double loop: per edge, per face, visibility and, for a visible face, containment."""
    out = np.empty(edges.shape[0], dtype=np.int64)
    k = 0
    for e in range(edges.shape[0]):
        a, b = edges[e, 0], edges[e, 1]
        counter = 0
        for f in range(face_start.size - 1):
            s = face_start[f]
            i0, i1, i2 = corners[s], corners[s + 1], corners[s + 2]
            e1x, e1y, e1z = (
                vertices[i1, 0] - vertices[i0, 0],
                vertices[i1, 1] - vertices[i0, 1],
                vertices[i1, 2] - vertices[i0, 2],
            )
            e2x, e2y, e2z = (
                vertices[i2, 0] - vertices[i0, 0],
                vertices[i2, 1] - vertices[i0, 1],
                vertices[i2, 2] - vertices[i0, 2],
            )
            nx, ny, nz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
            if directional:
                dx, dy, dz = light[0], light[1], light[2]
            else:
                dx, dy, dz = light[0] - vertices[i0, 0], light[1] - vertices[i0, 1], light[2] - vertices[i0, 2]
            if dx * nx + dy * ny + dz * nz > 0.0:
                m = face_start[f + 1] - s
                for j in range(m):
                    u, w = corners[s + j], corners[s + (j + 1) % m]
                    if (u == a and w == b) or (u == b and w == a):
                        counter += 1
                        break
        if counter == 1:
            out[k] = e
            k += 1
    return out[:k]


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """VnV's own loops (``intended``), compiled and uncounted (HSD paper Sec. 4.2): for each edge, for each
    face, the visibility test and, for a visible face, whether it contains the edge; O(E F) per light."""
    src = np.asarray(light.vector, dtype=np.float64)
    directional = isinstance(light, DirectionalLight)
    return _each_edge_against_every_face(mesh.edges, mesh.vertices, mesh.face_start, mesh.corners, src, directional)


SPEC = DetectorSpec(
    name=NAME,
    label="VnV",
    detect=detect,
    role="paper",
    paper_model=PAPER_MODEL,
    variants=("intended", "literal"),
    engines=("fast", "naive"),
    visited_step="check_counter",
    plain_edge_ids=plain_edge_ids,
    plain_quadratic=True,
    growth_variant="literal",
    style=("#d1495b", "o"),
    detect_many=detect_many,
)
