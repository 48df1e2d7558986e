"""Each algorithm's own loops, compiled and uncounted: what a frame really pays.

The ``naive`` engines count every operation (slow by design) and the
``fast`` engines derive the same tallies without running the O(n^2) loops
(so their time says nothing about the algorithm).  These kernels run the
``intended`` variant of each printed algorithm as written, in numba, with no
counting: the time to compare with the papers' frame rates (HSD paper
Sec. VII, EESD paper Sec. 6; ``scripts/bench_render.py``).

* ``ta``: visibility once per face, then each side of a light-facing face
  searches the array S linearly from the front, deletes (shifting the tail)
  or appends (HSD paper Sec. 4.1);
* ``hsd``: the same over the boundary sides of the merged polygons
  (the merge is per mesh and cached, as in :mod:`.hsd`);
* ``vnv``: for each edge, for each face, the visibility test and, for a
  visible face, whether it contains the edge (HSD paper Sec. 4.2, with the
  containment test of :mod:`.vnv`'s ``intended`` variant);
* ``eesd``: for each edge, the ray past its outward point (:mod:`.eesd`)
  tested against every face (fan triangles, Moller-Trumbore); the edge is
  kept iff no face is hit (EESD paper Sec. 3.3).

``gaussmap`` and ``cones`` (:data:`QUERIED`, not in :data:`PLAIN`, the set
the corpus study times) have no loops of their own here: theirs is the fast
engine's compiled query, :func:`.hierarchy_query.query_fast`, on the tree
built once per mesh and cached with it (built by the first call, as HSD's
merge is), on one numba thread like every loop here, its output sorted.
That kernel also increments its step counters (one integer add per step;
nothing else of the tally is computed).

Each returns the ascending edge ids that :func:`silcount.detect` returns for
the same detector (tested in ``tests/test_plain.py``).
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit

from silcount.detectors import cones, gaussmap
from silcount.detectors.adjacency import facing_flags, silhouette_edge_ids
from silcount.detectors.eesd import outward_points_and_rays
from silcount.detectors.hierarchy import Hierarchy, KeyScheme
from silcount.detectors.hierarchy_query import query_fast, tree_for
from silcount.errors import check_choice
from silcount.mesh.coplanar import merge
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh
from silcount.mesh.raytrace import _moller_trumbore

PLAIN = ("reference", "ta", "vnv", "hsd", "eesd")
SCHEMES: dict[str, KeyScheme] = {"gaussmap": gaussmap.SCHEME, "cones": cones.SCHEME}
QUERIED = tuple(SCHEMES)  # timed by their compiled query on the cached tree


@njit(cache=True)
def _toggle(start, side_from, side_to, facing, V):  # pragma: no cover - compiled
    """TA's array S over the sides of the light-facing faces (or polygons); returns the live keys."""
    S = np.empty(side_from.size, dtype=np.int64)
    n = 0
    for p in range(start.size - 1):
        if not facing[p]:
            continue
        for q in range(start[p], start[p + 1]):
            a, b = side_from[q], side_to[q]
            rev = b * V + a
            pos = -1
            for i in range(n):
                if S[i] == rev:
                    pos = i
                    break
            if pos >= 0:
                for i in range(pos, n - 1):
                    S[i] = S[i + 1]
                n -= 1
            else:
                S[n] = a * V + b
                n += 1
    return S[:n]


@njit(cache=True)
def _vnv(edges, vertices, face_start, corners, light, directional):  # pragma: no cover - compiled
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


@njit(cache=True, error_model="numpy")  # as the inlined ray-triangle test: det == 0 gives inf, not an exception
def _eesd(origins, directions, t_min, t_max, vertices, face_start, corners):  # pragma: no cover - compiled
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
                hit, _ = _moller_trumbore(
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


def _ids_of_keys(mesh: Mesh, keys: np.ndarray) -> np.ndarray:
    V = np.int64(mesh.n_vertices)
    a, b = keys // V, keys % V
    table = mesh.edges[:, 0] * V + mesh.edges[:, 1]
    return np.unique(np.searchsorted(table, np.minimum(a, b) * V + np.maximum(a, b)))


def plain_edge_ids(mesh: Mesh, light: Light, name: str) -> np.ndarray:
    """Run detector ``name``'s own loops (``intended`` variant) without counting; ascending edge ids."""
    check_choice("plain kernel", name, PLAIN + QUERIED, error=ValueError)
    V = mesh.n_vertices
    if name in SCHEMES:
        tree = tree_of(mesh, name)
        threads = numba.get_num_threads()
        numba.set_num_threads(1)  # one thread, as every loop here runs (the query may be a parallel kernel)
        try:
            ids = query_fast(mesh, tree, light)[0]
        finally:
            numba.set_num_threads(threads)
        return np.sort(ids)
    if name == "reference":
        return silhouette_edge_ids(mesh, light)
    if name == "ta":
        keys = _toggle(mesh.face_start, mesh.side_from, mesh.side_to, facing_flags(mesh, light)[0], V)
        return _ids_of_keys(mesh, keys)
    if name == "hsd":
        mg = merge(mesh, "tight")
        sides = mg.poly_sides
        keys = _toggle(
            mg.poly_start, mesh.side_from[sides], mesh.side_to[sides], facing_flags(mesh, light, mg.rep)[0], V
        )
        return _ids_of_keys(mesh, keys)
    directional = isinstance(light, DirectionalLight)
    src = np.asarray(light.vector, dtype=np.float64)
    if name == "vnv":
        return _vnv(mesh.edges, mesh.vertices, mesh.face_start, mesh.corners, src, directional)
    if name == "eesd":
        _, origins, directions, t_min, t_max = outward_points_and_rays(mesh, light)
        return _eesd(
            np.ascontiguousarray(origins),
            np.ascontiguousarray(directions),
            float(t_min),
            float(t_max),
            mesh.vertices,
            mesh.face_start,
            mesh.corners,
        )
    raise AssertionError(f"{name!r} is in PLAIN + QUERIED but has no plain kernel here")


def tree_of(mesh: Mesh, name: str) -> Hierarchy:
    """The default tree of ``gaussmap`` or ``cones`` for ``mesh``: the one their ``detect`` caches (built if absent)."""
    return tree_for(mesh, SCHEMES[name])
