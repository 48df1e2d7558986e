"""Mesh statistics for audits: sizes, the papers' size assumptions, topology, defects.

The papers assume ``V = 2n`` vertices and ``E = 6n`` edges for ``n`` faces
(EESD 2012 Sec. 5, after Gorman; HSD 2011 Sec. VI), i.e. ``V/F = 2``,
``E/F = 6``, ``E/V = 3``.  A closed triangle mesh has ``E/F = 3/2`` and
``V/F`` about ``1/2`` (Euler's formula), so the measured ratios are printed
beside the assumed ones.

Definitions used here:

* *components*: connected components of the face graph (faces sharing an
  edge), ``scipy.sparse.csgraph``;
* *Euler characteristic* ``chi = V - E + F``; *genus* ``(2C - chi) / 2``,
  only for a closed, consistently wound mesh (else ``None``);
* *degenerate face*: zero area (Newell normal exactly zero); *zero-normal
  face*: the normal from the first three corners, which the light-facing
  test uses, is exactly zero, so the face is a tie under every light;
* *coplanar polygons*: HSD's merge of adjacent exactly coplanar faces
  (HSD 2011 Sec. V), its polygon count and mean sides ``m``;
* *duplicate face*: the same set of vertices as an earlier face (counted
  beyond the first).
"""

from __future__ import annotations

import numpy as np

from silcount.mesh.coplanar import merge
from silcount.mesh.model import Mesh, unique_rows, weld

NEAR_DUPLICATE_RELATIVE = 1e-9
"""Vertices closer than this times the bounding radius are reported as near-duplicates."""

PAPER_RATIOS = {"V/F": 2.0, "E/F": 6.0, "E/V": 3.0}


def newell_normals(mesh: Mesh) -> np.ndarray:
    """(F, 3) Newell normals (twice the vector area) of every polygon."""
    a = mesh.vertices[mesh.side_from]
    b = mesh.vertices[mesh.side_to]
    per_side = np.cross(a, b)
    return np.add.reduceat(per_side, mesh.face_start[:-1], axis=0)


def n_components(mesh: Mesh) -> int:
    """Connected components of faces joined through shared edges."""
    start, order = mesh.edge_sides
    faces_by_edge = mesh.side_face[order]
    first = np.repeat(faces_by_edge[start[:-1]], mesh.edge_valence)
    from scipy.sparse import coo_matrix  # scipy: only when statistics are computed
    from scipy.sparse.csgraph import connected_components

    graph = coo_matrix((np.ones(order.size, dtype=np.int8), (first, faces_by_edge)), shape=(mesh.n_faces,) * 2)
    return int(connected_components(graph, directed=False)[0])


def duplicate_faces(mesh: Mesh) -> int:
    """Faces with the same vertex set as an earlier face."""
    order = np.lexsort((mesh.corners, mesh.side_face))  # corners sorted within each face
    rank = np.arange(mesh.n_sides) - mesh.face_start[mesh.side_face]
    table = np.full((mesh.n_faces, int(mesh.face_sizes.max())), -1, dtype=np.int64)
    table[mesh.side_face, rank] = mesh.corners[order]
    base = mesh.n_vertices + 1  # one int64 key per row when it fits: sorting keys is ~2x faster than rows
    if table.shape[1] * np.log2(base) < 62:
        key = np.zeros(mesh.n_faces, dtype=np.int64)
        for col in table.T:
            key = key * base + (col + 1)
        key.sort()
        return int(np.count_nonzero(key[1:] == key[:-1]))
    return mesh.n_faces - int(unique_rows(table)[0].shape[0])


def near_duplicate_vertices(mesh: Mesh) -> tuple[int, float]:
    """How many welded vertices would merge at a tolerance of 1e-9 bounding radii, and that tolerance.

    Welding is exact by default; a CAD export that writes the same corner as
    ``0.0`` and ``-2.7e-16`` (the shared featuretype.stl) stays open until
    such vertices merge (``--weld-tolerance``).
    """
    tol = NEAR_DUPLICATE_RELATIVE * max(mesh.bounding_radius, np.finfo(float).tiny)
    return mesh.n_vertices - weld(mesh.vertices, tol)[0].shape[0], tol


def mesh_statistics(mesh: Mesh) -> dict:
    """Everything ``silcount audit`` reports about a mesh, JSON-ready."""
    V, F, E = mesh.n_vertices, mesh.n_faces, mesh.n_edges
    comps = n_components(mesh)
    chi = V - E + F
    genus = (2 * comps - chi) // 2 if mesh.is_watertight and (2 * comps - chi) % 2 == 0 else None
    area2 = np.linalg.norm(newell_normals(mesh), axis=1)
    near, near_tol = near_duplicate_vertices(mesh)
    return {
        "name": mesh.name,
        "vertices": V,
        "faces": F,
        "edges": E,
        "sides": mesh.n_sides,
        "mean_sides": mesh.mean_sides,
        "ratios": {"V/F": V / F, "E/F": E / F, "E/V": E / V},
        "paper_ratios": dict(PAPER_RATIOS),
        "closed": mesh.is_closed,
        "consistently_wound": mesh.is_consistently_wound,
        "watertight": mesh.is_watertight,
        "boundary_edges": int(mesh.boundary_edges.size),
        "nonmanifold_edges": int(mesh.nonmanifold_edges.size),
        "inconsistent_edges": int(mesh.inconsistent_edges.size),
        "degenerate_faces": int(np.count_nonzero(area2 == 0.0)),
        "zero_normal_faces": int(np.count_nonzero(~np.any(mesh.face_normals != 0.0, axis=1))),
        "duplicate_faces": duplicate_faces(mesh),
        "collapsed_faces_dropped": int(mesh.dropped_faces),
        "weld_tolerance": mesh.weld_tolerance,
        "near_duplicate_vertices": near,
        "near_duplicate_tolerance": near_tol,
        "components": comps,
        "euler_characteristic": chi,
        "genus": genus,
        "bounding_radius": mesh.bounding_radius,
        "coplanar": coplanar_polygons(mesh),
    }


def coplanar_polygons(mesh: Mesh) -> dict:
    """HSD's polygons: adjacent, exactly coplanar, same-orientation faces merged (``tight``).

    See :mod:`silcount.mesh.coplanar`.
    """
    merged = merge(mesh, "tight")
    return {
        "criterion": merged.criterion,
        "polygons": merged.n_polygons,
        "polygon_edges": merged.n_polygon_edges,
        "interior_edges": int(np.count_nonzero(merged.interior)),
        "mean_sides": merged.mean_sides,
    }


def mesh_warnings(stats: dict) -> list[str]:
    """Human-readable warnings for a usable but dubious mesh."""
    out = []
    if stats["boundary_edges"]:
        out.append(
            f"open mesh: {stats['boundary_edges']} boundary edges "
            "(a boundary edge is a silhouette edge iff its face is light-facing)"
        )
    if stats["nonmanifold_edges"]:
        out.append(f"{stats['nonmanifold_edges']} non-manifold edges (shared by more than two faces)")
    if stats["inconsistent_edges"]:
        out.append(f"inconsistent winding: {stats['inconsistent_edges']} edges traversed the same way by both faces")
    if stats["degenerate_faces"]:
        out.append(f"{stats['degenerate_faces']} degenerate (zero-area) faces")
    if stats["zero_normal_faces"]:
        out.append(
            f"{stats['zero_normal_faces']} faces with a zero normal from their first three corners "
            "(ties under every light)"
        )
    if stats["closed"] and stats["euler_characteristic"] % 2:
        out.append(
            f"closed, but the Euler characteristic {stats['euler_characteristic']} is odd: "
            "some vertices are non-manifold (pinched); genus undefined"
        )
    if stats["near_duplicate_vertices"]:
        out.append(
            f"{stats['near_duplicate_vertices']} vertices lie within {stats['near_duplicate_tolerance']:.3g} "
            f"of another and were not welded (welding tolerance {stats['weld_tolerance']:g}); "
            f"--weld-tolerance {stats['near_duplicate_tolerance']:.3g} merges them"
        )
    if stats["duplicate_faces"]:
        out.append(f"{stats['duplicate_faces']} duplicate faces")
    if stats["collapsed_faces_dropped"]:
        out.append(f"{stats['collapsed_faces_dropped']} faces collapsed by welding were dropped")
    return out
