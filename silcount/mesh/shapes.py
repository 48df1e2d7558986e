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


def uv_sphere(slices: int, stacks: int) -> Mesh:
    """A latitude-longitude unit sphere: ``slices`` meridians, ``stacks`` bands from pole to pole, the polar bands
    closed by triangle fans and every other band's quads split: F = 2 x slices x (stacks - 1) triangles (Gooch et
    al., I3D 1999, Table 1: 199 x 199 gives their 78,804-face sphere)."""
    if slices < 3 or stacks < 2:
        raise ValueError(f"a uv sphere needs slices >= 3 and stacks >= 2, got {slices} x {stacks}")
    theta = np.pi * np.arange(1, stacks) / stacks  # the stacks - 1 rings between the poles
    phi = 2 * np.pi * np.arange(slices) / slices
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], axis=-1).reshape(-1, 3)
    v = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]])
    south = v.shape[0] - 1

    def at(i: int, j: int) -> int:
        return 1 + i * slices + j % slices

    f = [[0, at(0, j), at(0, j + 1)] for j in range(slices)]
    for i in range(stacks - 2):
        for j in range(slices):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            f += [[a, b, c], [a, c, d]]
    f += [[south, at(stacks - 2, j + 1), at(stacks - 2, j)] for j in range(slices)]
    return from_polygons(v, f, name=f"uv_sphere{slices}x{stacks}")


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
