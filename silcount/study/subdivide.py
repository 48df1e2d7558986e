"""Midpoint subdivision: more faces from the same real shape, for the corpus's size sweep.

One level splits every face without moving any point (no smoothing: the
surface, its bounding box and its sharp features stay exactly as authored):

* a **triangle** ``(a, b, c)`` becomes four, by its edge midpoints
  ``ab, bc, ca``: ``(a, ab, ca)``, ``(ab, b, bc)``, ``(ca, bc, c)``,
  ``(ab, bc, ca)`` (1-to-4, Loop's topology without Loop's weights);
* a **polygon of m >= 4 sides** (quads included) becomes ``m`` quads, by its
  edge midpoints and its centroid: ``(v_i, mid(v_i, v_i+1), centroid,
  mid(v_i-1, v_i))`` (Catmull-Clark's topology without its weights), so a quad
  mesh stays a quad mesh of four times the faces and an n-gon's quads keep the
  polygon's plane only if the polygon was planar.

Orientation is kept (each child is wound as its parent), children follow their
parent in face order, and the result goes through
:func:`silcount.mesh.model.from_polygons` (exact welding), as a loaded file does.

A consequence to keep in mind when reading the sweep: the new edges inside a
planar face join coplanar children, so they are never silhouette edges, and a
silhouette edge of the source becomes two.  Silhouette size therefore grows as
``F^0.5`` along one source's levels, whatever the source; the corpus reports
fits over the sources (level 0) beside fits over every level.
"""

from __future__ import annotations

import numpy as np

from silcount.errors import InvalidMesh
from silcount.mesh.io import estimate_bytes, memory_limit
from silcount.mesh.model import Mesh, from_polygons


def faces_after(mesh: Mesh, levels: int) -> int:
    """Face count after ``levels`` subdivisions: triangles x 4, an m-gon x m then x 4 per further level."""
    if levels == 0:
        return mesh.n_faces
    sizes = mesh.face_sizes
    first = int(np.count_nonzero(sizes == 3)) * 4 + int(sizes[sizes > 3].sum())
    return first * 4 ** (levels - 1)


def subdivide_once(mesh: Mesh) -> Mesh:
    """One midpoint level (see the module docstring)."""
    V, E = mesh.n_vertices, mesh.n_edges
    verts = mesh.vertices
    mids = 0.5 * (verts[mesh.edges[:, 0]] + verts[mesh.edges[:, 1]])
    sizes = mesh.face_sizes
    start = mesh.face_start[:-1]
    side_mid = V + mesh.side_edge  # midpoint vertex of each side (corner s -> corner s+1)
    prev_side = mesh.side_next.copy()
    prev_side[mesh.side_next] = np.arange(mesh.n_sides)  # the side ending at corner s
    poly = np.flatnonzero(sizes > 3)
    centroids = np.add.reduceat(verts[mesh.corners], start, axis=0)[poly] / sizes[poly, None]
    centre_of = np.full(mesh.n_faces, -1, dtype=np.int64)
    centre_of[poly] = V + E + np.arange(poly.size)
    all_verts = np.concatenate([verts, mids, centroids])
    if poly.size == 0:  # all triangles: one (4F, 3) array
        a, b, c = (mesh.corners[start + k] for k in range(3))
        ab, bc, ca = (side_mid[start + k] for k in range(3))
        tris = np.stack([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))], axis=1)
        return from_polygons(all_verts, tris.reshape(-1, 3), name=mesh.name)
    faces: list[list[int]] = []
    corners, sm, ps = mesh.corners.tolist(), side_mid.tolist(), prev_side.tolist()
    for f, (s, m) in enumerate(zip(start.tolist(), sizes.tolist())):
        if m == 3:
            a, b, c = corners[s : s + 3]
            ab, bc, ca = sm[s : s + 3]
            faces += [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        else:
            cf = int(centre_of[f])
            faces += [[corners[q], sm[q], cf, sm[ps[q]]] for q in range(s, s + m)]
    return from_polygons(all_verts, faces, name=mesh.name)


def subdivide(mesh: Mesh, levels: int, max_memory: int | None = None) -> Mesh:
    """``levels`` midpoint levels; :class:`InvalidMesh` when the result would not fit the memory limit
    (:func:`silcount.mesh.io.memory_limit`, the rule ``load_mesh`` applies to files)."""
    faces = faces_after(mesh, levels)
    need, limit = estimate_bytes(faces // 2 + mesh.n_vertices, faces), memory_limit(max_memory)
    if need > limit:
        raise InvalidMesh(
            f"subdivision level {levels}: {faces} faces need about {need / 2**20:.1f} MiB, "
            f"over the limit of {limit / 2**20:.1f} MiB"
        )
    for _ in range(levels):
        mesh = subdivide_once(mesh)
    return mesh
