"""Hypothesis strategies shared by the test suite: random closed meshes and lights.

* convex hulls of random points (closed, convex, outward winding);
* perturbed tori (closed, genus 1, non-convex);
* subdivided icospheres with radial noise (closed, star-shaped, non-convex).
"""

from __future__ import annotations

import numpy as np
import trimesh
from hypothesis import strategies as st

import silcount
from silcount.mesh.model import Mesh, from_polygons


@st.composite
def convex_hulls(draw, min_points: int = 5, max_points: int = 24) -> Mesh:
    seed = draw(st.integers(0, 2**32 - 1))
    k = draw(st.integers(min_points, max_points))
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(k, 3))
    hull = trimesh.convex.convex_hull(pts)
    return from_polygons(hull.vertices, hull.faces, name=f"hull{seed}")


@st.composite
def perturbed_tori(draw) -> Mesh:
    seed = draw(st.integers(0, 2**32 - 1))
    n_major = draw(st.integers(5, 10))
    n_minor = draw(st.integers(3, 6))
    base = silcount.mesh.shapes.torus(1.0, draw(st.floats(0.2, 0.6)), n_major, n_minor)
    rng = np.random.default_rng(seed)
    v = base.vertices + rng.uniform(-0.03, 0.03, size=base.vertices.shape)
    return from_polygons(v, base.faces, name=f"torus{seed}")


@st.composite
def bumpy_spheres(draw) -> Mesh:
    seed = draw(st.integers(0, 2**32 - 1))
    sub = draw(st.integers(0, 2))
    t = trimesh.creation.icosphere(subdivisions=sub)
    rng = np.random.default_rng(seed)
    v = t.vertices * rng.uniform(0.6, 1.4, size=(len(t.vertices), 1))
    return from_polygons(v, t.faces, name=f"bumpy{seed}")


def closed_meshes() -> st.SearchStrategy[Mesh]:
    """Random small closed, consistently wound triangle meshes."""
    return st.one_of(convex_hulls(), perturbed_tori(), bumpy_spheres())


@st.composite
def lights_for(draw, mesh: Mesh, directional: bool | None = None):
    """A point light outside the bounding sphere (1.5 to 5 radii away) or a directional light."""
    if directional is None:
        directional = draw(st.booleans())
    d = np.array([draw(st.floats(-1, 1)) for _ in range(3)])
    if not np.any(np.abs(d) > 1e-3):
        d = np.array([0.3, 0.5, 0.8])
    d /= np.linalg.norm(d)
    if directional:
        return silcount.DirectionalLight(d)
    r = draw(st.floats(1.5, 5.0)) * max(mesh.bounding_radius, 1e-9)
    return silcount.PointLight(mesh.centre + r * d)


@st.composite
def mesh_and_light(draw, meshes: st.SearchStrategy[Mesh] | None = None):
    mesh = draw(meshes if meshes is not None else closed_meshes())
    return mesh, draw(lights_for(mesh))
