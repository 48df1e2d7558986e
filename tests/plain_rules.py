"""Plain-Python pieces of the second implementation the tests compare the package with.

Independent of the package's kernels: a face's facing value
``(L - p0) . ((p1 - p0) x (p2 - p0))`` from its first three corners (the same
operation order, so bit-identical), and a face's directed sides in corner order.
"""

from __future__ import annotations


def facing(mesh, light) -> tuple[list[bool], int]:
    """Each face's light-facing flag and the number of exact ties, from the face's first three corners."""
    flags, ties = [], 0
    for p in range(mesh.n_faces):
        s = mesh.face_start[p]
        p0, p1, p2 = (mesh.vertices[mesh.corners[s + k]] for k in range(3))
        e1, e2 = p1 - p0, p2 - p0
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        d = light.direction if light.is_directional else tuple(light.position[c] - p0[c] for c in range(3))
        value = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
        flags.append(bool(value > 0.0))
        ties += value == 0.0
    return flags, ties


def sides(mesh, p) -> list[tuple[int, int]]:
    """Face ``p``'s directed sides ``(from, to)`` in corner order."""
    c = mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]].tolist()
    return [(c[k], c[(k + 1) % len(c)]) for k in range(len(c))]
