"""EESD's rays (EESD paper Sec. 3.3, 5.3): outward points, rays, the planes, and the plain loop that casts them.

Every edge ``v1 v2`` is pushed outward from its first face by ``EPS`` edge
lengths (``extend``) and a ray is cast from there towards the light
(``ray``); the edge is a silhouette edge iff the ray meets no face.  This
module computes those points and rays compiled, in the counted routines'
order of operations (:mod:`.counted`), keeps the per-mesh arrays the
engines share (each edge's far corner, the fan triangles, the ray tracer,
each edge's own fan triangles), the face planes of the ``literal`` reading,
and :func:`plain_edge_ids`: the printed double loop compiled and uncounted, for
timing (:mod:`silcount.calibrate.timing`).
"""

from __future__ import annotations

import weakref

import numpy as np
from numba import njit, prange

from silcount.detectors.eesd.counted import EPS
from silcount.mesh.chunks import run_chunks
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh
from silcount.mesh.raytrace import RayTracer, moller_trumbore

_CACHE: "weakref.WeakKeyDictionary[Mesh, dict]" = weakref.WeakKeyDictionary()


def ray_data(mesh: Mesh) -> dict:
    """Per-mesh arrays (cached): each edge's far corner in f1, fan triangles, their faces, the tracer."""
    got = _CACHE.get(mesh)
    if got is None:
        start, order = mesh.edge_sides
        first_side = order[start[:-1]]
        apex = mesh.side_to[mesh.side_next[first_side]]
        fan = mesh.face_sizes - 2
        tri_face = np.repeat(np.arange(mesh.n_faces, dtype=np.int64), fan)
        tri_start = np.zeros(mesh.n_faces + 1, dtype=np.int64)
        np.cumsum(fan, out=tri_start[1:])
        k = np.arange(tri_face.size) - tri_start[tri_face] + 1
        s0 = mesh.face_start[tri_face]
        tri_idx = np.stack([mesh.corners[s0], mesh.corners[s0 + k], mesh.corners[s0 + k + 1]], axis=1)
        got = {"apex": apex, "tri_face": tri_face, "tri_start": tri_start, "tri_idx": tri_idx}
        _CACHE[mesh] = got
    return got


def fan_triangles(mesh: Mesh) -> np.ndarray:
    """The mesh's fan triangles (T, 3, 3), the ones every ray is tested against (cached with the mesh)."""
    data = ray_data(mesh)
    if "triangles" not in data:
        data["triangles"] = np.ascontiguousarray(mesh.vertices[data["tri_idx"]], dtype=np.float64)
    return data["triangles"]


def tracer(mesh: Mesh) -> RayTracer:
    """The ray tracer over the mesh's fan triangles (cached with the mesh)."""
    data = ray_data(mesh)
    if "tracer" not in data:
        data["tracer"] = RayTracer(fan_triangles(mesh))
    return data["tracer"]


_ALL = np.zeros(0, dtype=np.int64)  # :func:`_outward`'s "every edge"


def light_values(light: Light) -> np.ndarray:
    """The light's direction or position, as the counted routines read it."""
    return np.asarray(light.vector, dtype=np.float64)


@njit(cache=True, error_model="numpy", inline="always")  # an end-on edge (w = 0): inf or NaN, as numpy's
def _outward_point(V, a, b, c, L, directional, eps):  # pragma: no cover - compiled
    """``P`` of edge ``a b`` with far corner ``c``: :func:`.counted.counted_outward_point`, operation
    for operation."""
    m0 = (V[a, 0] + V[b, 0]) * 0.5
    m1 = (V[a, 1] + V[b, 1]) * 0.5
    m2 = (V[a, 2] + V[b, 2]) * 0.5
    e0, e1, e2 = V[b, 0] - V[a, 0], V[b, 1] - V[a, 1], V[b, 2] - V[a, 2]
    if directional:
        d0, d1, d2 = L[0], L[1], L[2]
    else:
        d0, d1, d2 = m0 - L[0], m1 - L[1], m2 - L[2]
    w0 = d1 * e2 - d2 * e1
    w1 = d2 * e0 - d0 * e2
    w2 = d0 * e1 - d1 * e0
    side = (V[c, 0] - m0) * w0 + (V[c, 1] - m1) * w1 + (V[c, 2] - m2) * w2
    sgn = -1.0 if side > 0.0 else 1.0
    ee = e0 * e0 + e1 * e1 + e2 * e2
    ww = w0 * w0 + w1 * w1 + w2 * w2
    scale = eps * np.sqrt(ee / ww) * sgn
    return m0 + w0 * scale, m1 + w1 * scale, m2 + w2 * scale


@njit(cache=True, error_model="numpy")
def _outward(V, edges, apex, which, L, directional, eps):  # pragma: no cover - compiled
    """``P`` of the edges ``which`` (all edges when ``which`` is empty and there are edges)."""
    n = which.size if which.size else edges.shape[0]
    p = np.empty((n, 3))
    for k in range(n):
        i = which[k] if which.size else k
        p[k, 0], p[k, 1], p[k, 2] = _outward_point(V, edges[i, 0], edges[i, 1], apex[i], L, directional, eps)
    return p


_OWN_BLOCK = 256  # edges per parallel task of :func:`_own_blocked` (its per-light scratch allocated once a task)


@njit(cache=True, parallel=True, error_model="numpy")
def _own_blocked(
    lo, hi, out, V, edges, apex, Ls, directional, eps, start, order, side_face, tri_start, tri_idx
):  # pragma: no cover
    """(E, n) bool: does light ``j``'s ray of edge ``e`` meet a fan triangle of one of the edge's faces?
    Edge-major, the lights innermost: for each edge, every light's ray (as :func:`outward_points_and_rays`
    makes it), then each of the edge's fan triangles against every light's ray by the tracer's test, the
    answers or-ed.  The loops over the lights have no branch, so the compiler runs them several lights to an
    instruction; every light tests every triangle of the edge (no early exit), and the answer, any hit, is
    the one a per-light search that stops at its first hit gives.  Edges ``lo .. hi - 1`` into ``out`` (all
    False there); returns 0."""
    n = Ls.shape[0]
    tasks = (hi - lo + _OWN_BLOCK - 1) // _OWN_BLOCK
    for task in prange(tasks):
        o0, o1, o2 = np.empty(n), np.empty(n), np.empty(n)
        d0, d1, d2 = np.empty(n), np.empty(n), np.empty(n)
        hit = np.empty(n, dtype=np.bool_)
        t_lo = -np.inf if directional else 0.0
        for e in range(lo + task * _OWN_BLOCK, min(hi, lo + (task + 1) * _OWN_BLOCK)):
            a, b, c = edges[e, 0], edges[e, 1], apex[e]
            for j in range(n):
                lx, ly, lz = Ls[j, 0], Ls[j, 1], Ls[j, 2]
                p0, p1, p2 = _outward_point(V, a, b, c, (lx, ly, lz), directional, eps)
                if directional:
                    o0[j], o1[j], o2[j], d0[j], d1[j], d2[j] = p0, p1, p2, lx, ly, lz
                else:
                    o0[j], o1[j], o2[j], d0[j], d1[j], d2[j] = lx, ly, lz, p0 - lx, p1 - ly, p2 - lz
                hit[j] = False
            for s in range(start[e], start[e + 1]):
                f = side_face[order[s]]
                for t in range(tri_start[f], tri_start[f + 1]):
                    x, y, z = tri_idx[t, 0], tri_idx[t, 1], tri_idx[t, 2]
                    ax, ay, az = V[x, 0], V[x, 1], V[x, 2]
                    bx, by, bz = V[y, 0], V[y, 1], V[y, 2]
                    cx, cy, cz = V[z, 0], V[z, 1], V[z, 2]
                    for j in range(n):
                        h, _ = moller_trumbore(o0[j], o1[j], o2[j], d0[j], d1[j], d2[j], ax, ay, az, bx, by, bz,
                                               cx, cy, cz, t_lo, np.inf)  # fmt: skip
                        hit[j] |= h
            for j in range(n):
                out[e, j] = hit[j]
    return 0


def outward_points_and_rays(mesh: Mesh, light: Light):
    """``extend`` and ``ray`` for every edge, compiled, in the counted routines' order of operations.

    Returns ``P`` (E, 3), ray origins (E, 3), directions (E, 3), and scalar ``t_min``, ``t_max``.
    """
    L = light_values(light)
    p = _outward(mesh.vertices, mesh.edges, ray_data(mesh)["apex"], _ALL, L, light.is_directional, EPS)
    return (p, *rays_through(p, light))


def rays_through(p: np.ndarray, light: Light):
    """``origins, directions, t_min, t_max`` of the rays through points ``p`` (k, 3): a directional light's
    line through each point, ``t`` unbounded; a point light's ray from the light, ``t > 0``."""
    L = light_values(light)
    if light.is_directional:
        return p, np.broadcast_to(L, p.shape), -np.inf, np.inf
    return np.broadcast_to(L, p.shape), p - L, 0.0, np.inf


def outward_points_of(mesh: Mesh, light: Light, which: np.ndarray) -> np.ndarray:
    """``P`` (k, 3) of the edges ``which`` (k > 0), bit for bit as :func:`outward_points_and_rays` gives them."""
    which = np.ascontiguousarray(which, dtype=np.int64)
    if which.size == 0:
        return np.empty((0, 3))
    data = ray_data(mesh)
    return _outward(mesh.vertices, mesh.edges, data["apex"], which, light_values(light), light.is_directional, EPS)


def own_blocked(mesh: Mesh, lights: list[Light]) -> np.ndarray:
    """(E, n) bool: light ``j``'s ray of edge ``e`` (:func:`outward_points_and_rays`' ray) meets one of the
    edge's own faces' fan triangles by :func:`silcount.mesh.raytrace.moller_trumbore`, for lights all
    directional or all point lights, every light in one pass over the edges."""
    kinds = {light.is_directional for light in lights}
    if len(kinds) != 1:
        raise ValueError("own_blocked takes lights of one kind")
    Ls = np.ascontiguousarray([light_values(light) for light in lights], dtype=np.float64)
    data = ray_data(mesh)
    start, order = mesh.edge_sides
    out = np.zeros((mesh.n_edges, len(Ls)), dtype=np.bool_)
    args = (mesh.vertices, mesh.edges, data["apex"], Ls, kinds.pop(), EPS, start, order, mesh.side_face,
            data["tri_start"], data["tri_idx"])  # fmt: skip
    run_chunks(mesh.n_edges, lambda lo, hi: _own_blocked(lo, hi, out, *args))  # Ctrl-C between chunks
    return out


def face_planes(mesh: Mesh) -> np.ndarray:
    """(F, 4) ``a, b, c, d`` of every face, in :func:`counted_plane`'s order of operations."""
    p0 = mesh.face_p0
    s = mesh.face_start[:-1]
    e1 = mesh.vertices[mesh.corners[s + 1]] - p0
    e2 = mesh.vertices[mesh.corners[s + 2]] - p0
    n = np.stack(
        [
            e1[:, 1] * e2[:, 2] - e1[:, 2] * e2[:, 1],
            e1[:, 2] * e2[:, 0] - e1[:, 0] * e2[:, 2],
            e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0],
        ],
        axis=1,
    )
    d = 0.0 - (n[:, 0] * p0[:, 0] + n[:, 1] * p0[:, 1] + n[:, 2] * p0[:, 2])
    return np.ascontiguousarray(np.concatenate([n, d[:, None]], axis=1))


@njit(cache=True, error_model="numpy")  # as the inlined ray-triangle test: det == 0 gives inf, not an exception
def _each_ray_against_every_face(origins, directions, t_min, t_max, vertices, face_start, corners):  # pragma: no cover
    """The printed loop: for each edge, its ray against every face (fan triangles); kept iff none is met."""
    out = np.empty(origins.shape[0], dtype=np.int64)
    k = 0
    for e in range(origins.shape[0]):
        ox, oy, oz = origins[e, 0], origins[e, 1], origins[e, 2]
        dx, dy, dz = directions[e, 0], directions[e, 1], directions[e, 2]
        hits = 0
        for f in range(face_start.size - 1):
            s = face_start[f]
            a = corners[s]
            for j in range(s + 1, face_start[f + 1] - 1):
                b, c = corners[j], corners[j + 1]
                hit, _ = moller_trumbore(
                    ox,
                    oy,
                    oz,
                    dx,
                    dy,
                    dz,
                    vertices[a, 0],
                    vertices[a, 1],
                    vertices[a, 2],
                    vertices[b, 0],
                    vertices[b, 1],
                    vertices[b, 2],
                    vertices[c, 0],
                    vertices[c, 1],
                    vertices[c, 2],
                    t_min,
                    t_max,
                )
                if hit:
                    hits += 1
                    break
        if hits == 0:
            out[k] = e
            k += 1
    return out[:k]


def plain_edge_ids(mesh: Mesh, light: Light) -> np.ndarray:
    """EESD's own loops (``intended``), compiled and uncounted: ascending edge ids (O(E F) per light)."""
    _, origins, directions, t_min, t_max = outward_points_and_rays(mesh, light)
    return _each_ray_against_every_face(
        np.ascontiguousarray(origins),
        np.ascontiguousarray(directions),
        float(t_min),
        float(t_max),
        mesh.vertices,
        mesh.face_start,
        mesh.corners,
    )


__all__ = [
    "ray_data",
    "tracer",
    "light_values",
    "outward_points_and_rays",
    "outward_points_of",
    "rays_through",
    "own_blocked",
    "face_planes",
    "plain_edge_ids",
]
