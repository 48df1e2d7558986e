"""Hypothesis strategies shared by the test suite: meshes and lights drawn as data, so failures shrink.

Every mesh is built from drawn structure (coordinates, face lists, subdivision
counts, perturbation arrays), never from one opaque seed, so hypothesis can
shrink a failure to a small mesh and a simple light.

Closed, consistently wound meshes:

* convex hulls of drawn points (float, or integer lattice points: coplanar
  neighbours and exact ties);
* perturbed tori and bumpy icospheres (non-convex; the perturbation is a
  drawn array, zero by default when shrunk);
* axis-aligned boxes on the integer lattice, each side subdivided into a
  drawn grid of quads, each quad kept or split into two triangles (coplanar
  neighbours, quads, ties with axis-aligned lights);
* extrusions of a drawn convex n-gon (n-gon caps, or caps fanned into
  coplanar triangles; quad sides).

Defective meshes (:func:`defective`): a closed mesh with drawn faces removed
(open: boundary edges), reversed (inconsistent winding) or a fin added on a
drawn edge (non-manifold: three faces on one edge), and the arbitrary
triangle sets of :func:`triangle_sets`.

Lights (:func:`hard_lights_for`): far point lights and directional lights as
before, and the cases where rules decide: axis-aligned directional lights,
point lights on a face's plane (exact ties on lattice meshes), grazing
directional lights along a face's edge, lights inside the mesh, at a mesh
vertex and at a corner of the bounding box.

:func:`examples` scales a test's ``max_examples`` with the hypothesis
profile: 10x under ``SILCOUNT_HYPOTHESIS_PROFILE=long``.
"""

from __future__ import annotations

import os

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import silcount
from silcount.mesh import shapes
from silcount.mesh.model import Mesh, from_polygons

SCALE = {"ci": 1, "long": 10}.get(os.environ.get("SILCOUNT_HYPOTHESIS_PROFILE", "ci"), 1)


def examples(n: int) -> int:
    """``n`` examples under the ``ci`` profile, ``10 n`` under ``long``."""
    return n * SCALE


_coord = st.floats(-3.0, 3.0, allow_nan=False, allow_infinity=False, width=64)


# ---- closed meshes ------------------------------------------------------------------------------
def _hull(points: np.ndarray, name: str) -> Mesh:
    import trimesh

    assume(np.linalg.matrix_rank(points - points[0]) == 3)
    hull = trimesh.convex.convex_hull(points)
    mesh = from_polygons(hull.vertices, hull.faces, name=name)
    assume(mesh.is_closed and mesh.is_consistently_wound)
    return mesh


def _points(draw, k: int, element: st.SearchStrategy) -> np.ndarray:
    rows = draw(st.lists(st.tuples(element, element, element), min_size=k, max_size=k, unique=True))
    return np.array(rows, dtype=np.float64)


@st.composite
def convex_hulls(draw, min_points: int = 5, max_points: int = 24) -> Mesh:
    """The convex hull of drawn float points."""
    k = draw(st.integers(min_points, max_points))
    return _hull(_points(draw, k, _coord), f"hull{k}")


@st.composite
def lattice_hulls(draw) -> Mesh:
    """The convex hull of drawn integer points: coplanar triangles, exact facing values."""
    k = draw(st.integers(4, 14))
    return _hull(_points(draw, k, st.integers(-2, 2)), f"lattice{k}")


@st.composite
def perturbed_tori(draw) -> Mesh:
    n_major = draw(st.integers(5, 10))
    n_minor = draw(st.integers(3, 6))
    base = shapes.torus(1.0, draw(st.floats(0.2, 0.6)), n_major, n_minor)
    noise = draw(hnp.arrays(np.float64, base.vertices.shape, elements=st.floats(-0.03, 0.03)))
    return from_polygons(base.vertices + noise, base.faces, name=f"torus{n_major}x{n_minor}")


@st.composite
def bumpy_spheres(draw) -> Mesh:
    import trimesh

    t = trimesh.creation.icosphere(subdivisions=draw(st.integers(0, 2)))
    scale = draw(hnp.arrays(np.float64, (len(t.vertices), 1), elements=st.floats(0.6, 1.4)))
    return from_polygons(t.vertices * scale, t.faces, name="bumpy")


@st.composite
def boxes(draw, max_cells: int = 2) -> Mesh:
    """An axis-aligned box on the integer lattice, each side a drawn grid of quads, some split into triangles."""
    lo = np.array(draw(st.lists(st.integers(-2, 2), min_size=3, max_size=3)))
    cells = draw(st.lists(st.integers(1, max_cells), min_size=3, max_size=3))
    size = np.array([c * draw(st.integers(1, 2)) for c in cells])
    verts: dict[tuple, int] = {}

    def vid(p) -> int:
        return verts.setdefault(tuple(p), len(verts))

    faces: list[list[int]] = []
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, 1):
            for i in range(cells[u]):
                for j in range(cells[v]):
                    quad = []
                    for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = lo.astype(np.float64).copy()
                        p[axis] += side * size[axis]
                        p[u] += (i + du) * size[u] / cells[u]
                        p[v] += (j + dv) * size[v] / cells[v]
                        quad.append(vid(p))
                    if side == 0:  # outward: (u, v, axis) is right-handed, so the low side turns the other way
                        quad = quad[::-1]
                    split = draw(st.sampled_from([None, 0, 1]))
                    if split is None:
                        faces.append(quad)
                    else:
                        a, b, c, d = quad[split:] + quad[:split]
                        faces += [[a, b, c], [a, c, d]]
    pts = np.array(sorted(verts, key=verts.get), dtype=np.float64)
    return from_polygons(pts, faces, name=f"box{cells}")


@st.composite
def extrusions(draw) -> Mesh:
    """A drawn convex n-gon extruded along z: n-gon (or fanned) caps and quad sides."""
    n = draw(st.integers(3, 8))
    regular = draw(st.booleans())
    if regular:
        ang = 2 * np.pi * np.arange(n) / n
    else:
        gaps = np.array(draw(st.lists(st.floats(0.2, 1.0), min_size=n, max_size=n)))
        ang = 2 * np.pi * np.cumsum(gaps) / gaps.sum()
    r = draw(st.floats(0.5, 2.0))
    h = draw(st.sampled_from([0.5, 1.0, 2.0]))
    ring = np.stack([r * np.cos(ang), r * np.sin(ang)], axis=1)
    pts = np.vstack([np.c_[ring, np.zeros(n)], np.c_[ring, np.full(n, h)]])
    faces: list[list[int]] = [[i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n)]
    bottom, top = list(range(n))[::-1], list(range(n, 2 * n))
    for cap in (bottom, top):
        if draw(st.booleans()):
            faces.append(cap)
        else:
            faces += [[cap[0], cap[k], cap[k + 1]] for k in range(1, n - 1)]
    return from_polygons(pts, faces, name=f"prism{n}")


def closed_meshes() -> st.SearchStrategy[Mesh]:
    """Random small closed, consistently wound meshes: triangle meshes, polygons, coplanar neighbours."""
    return st.one_of(convex_hulls(), perturbed_tori(), bumpy_spheres(), boxes(), extrusions(), lattice_hulls())


def small_closed_meshes(max_faces: int = 60) -> st.SearchStrategy[Mesh]:
    """Closed meshes small enough for the O(E F) ``naive`` engines."""
    small = st.one_of(
        convex_hulls(max_points=12), perturbed_tori(), bumpy_spheres(), boxes(), extrusions(), lattice_hulls()
    )
    return small.filter(lambda m: m.n_faces <= max_faces)


# ---- defective meshes ---------------------------------------------------------------------------
@st.composite
def defective(draw, base: st.SearchStrategy[Mesh] | None = None) -> Mesh:
    """A closed mesh with drawn defects: faces removed (open), reversed (inconsistent), fins (non-manifold)."""
    mesh = draw(base if base is not None else small_closed_meshes(40))
    F = mesh.n_faces
    polys = [mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]].tolist() for p in range(F)]
    verts = mesh.vertices.copy()
    ops = draw(st.lists(st.sampled_from(["remove", "reverse", "fin"]), min_size=1, max_size=3))
    for op in ops:
        k = draw(st.integers(0, len(polys) - 1))
        if op == "remove" and len(polys) > 1:
            polys.pop(k)
        elif op == "reverse":
            polys[k] = polys[k][::-1]
        elif op == "fin":
            j = draw(st.integers(0, len(polys[k]) - 1))
            a, b = polys[k][j], polys[k][(j + 1) % len(polys[k])]
            off = np.array(draw(st.lists(st.integers(-2, 2), min_size=3, max_size=3)), dtype=np.float64)
            assume(np.any(off != 0))
            verts = np.vstack([verts, (verts[a] + verts[b]) / 2 + off])
            polys.append(draw(st.sampled_from([[a, b, len(verts) - 1], [b, a, len(verts) - 1]])))
    return from_polygons(verts, polys, name=f"{mesh.name}-{'-'.join(ops)}")


@st.composite
def triangle_sets(draw) -> Mesh:
    """Arbitrary small triangle sets on few drawn vertices: boundary, non-manifold, inconsistent, duplicates."""
    k = draw(st.integers(4, 7))
    v = _points(draw, k, st.integers(-2, 2).map(float) | _coord)
    tris = draw(st.lists(st.lists(st.integers(0, k - 1), min_size=3, max_size=3, unique=True), min_size=1, max_size=16))
    return from_polygons(v, tris, name=f"tris{k}")


def any_meshes() -> st.SearchStrategy[Mesh]:
    """Closed, open, non-manifold and inconsistently wound meshes, small enough for every ``naive`` engine."""
    return st.one_of(small_closed_meshes(40), defective(), triangle_sets())


# ---- lights -------------------------------------------------------------------------------------
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
def hard_lights_for(draw, mesh: Mesh):
    """Lights where the edge-case rules decide: ties, grazing, inside, on a vertex or the bounding box."""
    kind = draw(st.sampled_from(["far", "axis", "on_plane", "grazing", "inside", "vertex", "bbox"]))
    if kind == "far":
        return draw(lights_for(mesh))
    if kind == "axis":
        d = np.zeros(3)
        d[draw(st.integers(0, 2))] = draw(st.sampled_from([-1.0, 1.0]))
        return silcount.DirectionalLight(d)
    p = draw(st.integers(0, mesh.n_faces - 1))
    c = mesh.corners[mesh.face_start[p] : mesh.face_start[p] + 3]
    p0, p1, p2 = mesh.vertices[c]
    if kind == "on_plane":  # p0 + a e1 + b e2: exactly on the plane when the coordinates are small integers
        a, b = draw(st.integers(-2, 3)), draw(st.integers(-2, 3))
        return silcount.PointLight(p0 + a * (p1 - p0) + b * (p2 - p0))
    if kind == "grazing":  # along one of the face's edges
        d = draw(st.sampled_from([p1 - p0, p2 - p1, p0 - p2]))
        assume(np.any(d != 0))
        return silcount.DirectionalLight(d)
    if kind == "inside":
        return silcount.PointLight(draw(st.sampled_from([mesh.centre, mesh.vertices.mean(axis=0), (p0 + p1 + p2) / 3])))
    if kind == "vertex":
        return silcount.PointLight(mesh.vertices[draw(st.integers(0, mesh.n_vertices - 1))])
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    pick = np.array(draw(st.lists(st.integers(0, 1), min_size=3, max_size=3)))
    return silcount.PointLight(np.where(pick == 1, hi, lo))


@st.composite
def mesh_and_light(draw, meshes: st.SearchStrategy[Mesh] | None = None):
    mesh = draw(meshes if meshes is not None else closed_meshes())
    return mesh, draw(lights_for(mesh))


def clear_of_ties(mesh: Mesh, light, angle: float = 1e-5, sliver: float = 1e-4) -> bool:
    """Does the light see every face at more than ``angle`` radians from edge-on, and is no face a sliver?

    EESD's offset point is ``1e-6`` edge lengths from its edge, so a face seen
    within about that angle of edge-on can let its ray pass (documented in
    ``detectors/eesd/detector.py``); so can a body thinner than that offset, which has a sliver face (its
    first corners' height, ``|n| / longest edge``, under ``sliver`` of that edge: hypothesis found a
    tetrahedron 1.2e-7 thick whose edge of length 2 EESD kept, its point offset 2e-6 beside the body).
    Properties of EESD's edges hold only clear of both.
    """
    n = mesh.face_normals
    d = np.broadcast_to(np.asarray(light.direction), n.shape) if light.is_directional else light.position - mesh.face_p0
    dot = np.abs(np.einsum("ij,ij->i", d, n))
    size = np.linalg.norm(d, axis=1) * np.linalg.norm(n, axis=1)
    s = mesh.face_start[:-1]
    corners = [mesh.vertices[mesh.corners[s + k]] for k in range(3)]
    longest = np.max([np.linalg.norm(corners[k] - corners[k - 1], axis=1) for k in range(3)], axis=0)
    thick = np.linalg.norm(n, axis=1) > sliver * longest**2
    return bool(np.all(dot > np.sin(angle) * size) and np.all(thick))
