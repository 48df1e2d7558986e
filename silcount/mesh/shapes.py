"""Built-in meshes, generated deterministically (``scripts/make_data.py`` writes them to ``data/``).

The papers' Table 1 (HSD 2011) names a 12-edge cube, a 30-edge "sphere" (an
icosahedron has exactly 30 edges) and a 100-edge plane; the icosphere
series serves size sweeps.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np

from silcount.errors import check_choice
from silcount.mesh.model import Mesh, from_polygons


def tetrahedron() -> Mesh:
    """The regular tetrahedron with vertices at alternate corners of the unit cube, outward winding."""
    v = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    f = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]
    return from_polygons(v, f, name="tetrahedron")


def quad_cube() -> Mesh:
    """The unit cube as 6 quads: V=8, F=6, E=12 (the papers' 'Cube', HSD Table 1)."""
    v = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    # vertex index = 4x + 2y + z (bits); faces counter-clockwise seen from outside
    f = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    return from_polygons(v, f, name="quad_cube")


def triangle_cube() -> Mesh:
    """The unit cube as 12 triangles (each quad split on a diagonal): E=18."""
    q = quad_cube()
    tris = []
    for p in range(q.n_faces):
        a, b, c, d = q.corners[q.face_start[p] : q.face_start[p + 1]]
        tris += [[a, b, c], [a, c, d]]
    return from_polygons(q.vertices, tris, name="triangle_cube")


def icosahedron() -> Mesh:
    """The regular icosahedron: V=12, F=20, E=30 (the papers' 30-edge 'Sphere')."""
    import trimesh

    t = trimesh.creation.icosahedron()
    return from_polygons(t.vertices, t.faces, name="icosahedron")


def icosphere(subdivisions: int) -> Mesh:
    """Loop-subdivided icosahedron on the unit sphere: F = 20 * 4**subdivisions."""
    import trimesh

    t = trimesh.creation.icosphere(subdivisions=subdivisions)
    return from_polygons(t.vertices, t.faces, name=f"icosphere{subdivisions}")


def plane(nx: int = 2, ny: int = 14) -> Mesh:
    """An open triangulated grid of ``nx`` x ``ny`` cells in z = 0; the default has E = 100."""
    xs, ys = np.meshgrid(np.arange(nx + 1, dtype=float), np.arange(ny + 1, dtype=float), indexing="ij")
    v = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    idx = np.arange(v.shape[0]).reshape(nx + 1, ny + 1)
    f = []
    for i in range(nx):
        for j in range(ny):
            a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
            f += [[a, b, c], [a, c, d]]
    return from_polygons(v, f, name="plane")


def torus(major: float = 1.0, minor: float = 0.35, n_major: int = 24, n_minor: int = 12) -> Mesh:
    """A closed triangulated torus about the z axis (genus 1), outward winding."""
    u = 2 * np.pi * np.arange(n_major) / n_major
    w = 2 * np.pi * np.arange(n_minor) / n_minor
    uu, ww = np.meshgrid(u, w, indexing="ij")
    r = major + minor * np.cos(ww)
    v = np.stack([r * np.cos(uu), r * np.sin(uu), minor * np.sin(ww)], axis=-1).reshape(-1, 3)
    f = []
    for i in range(n_major):
        for j in range(n_minor):
            a = i * n_minor + j
            b = ((i + 1) % n_major) * n_minor + j
            c = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor
            d = i * n_minor + (j + 1) % n_minor
            f += [[a, b, c], [a, c, d]]
    return from_polygons(v, f, name="torus")


BUILTIN: dict[str, Callable[[], Mesh]] = {
    "tetrahedron": tetrahedron,
    "quad_cube": quad_cube,
    "triangle_cube": triangle_cube,
    "icosahedron": icosahedron,
    "plane": plane,
    "torus": torus,
    **{f"icosphere{k}": functools.partial(icosphere, k) for k in range(0, 6)},
}


def builtin_mesh(name: str) -> Mesh:
    """One of :data:`BUILTIN` by name."""
    check_choice("built-in mesh", name, BUILTIN)
    return BUILTIN[name]()
