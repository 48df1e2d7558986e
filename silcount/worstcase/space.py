"""The search space of the worst-case search: a genome (shape, size, face order, light, perturbation) and its mesh.

A :class:`Genome` is a small record of integers and floats, so that a search can mutate it, a report can
print it and a seed rebuilds it.  :func:`build` turns it into a mesh and a light, deterministically:

* **shapes** (:data:`SHAPES`): the structured generators of the test suite's strategies and of
  :mod:`silcount.mesh.shapes`: icospheres, a dome over a grid closed by an apex fan, an open strip and grid,
  a latitude-longitude sphere, a torus, a prism over a regular polygon (n-gon caps, quad sides), and a
  triangulated prism (its caps fanned into coplanar triangles: ties);
* **size**: a level per shape (:func:`size_of`), so that a family is one genome grown over its levels;
* **subdivisions**: midpoint subdivisions of a triangle mesh (0-2; none for the prisms, whose quads would
  leave T-junctions), and a seeded **perturbation** of the
  vertices along their offsets from the centre (amplitude 0-0.3 of the bounding radius);
* **face orders** (:data:`ORDERS`): TA and HSD read the faces in index order and their array S depends on it
  (:mod:`silcount.papers.witness`): as built, reversed, a seeded shuffle, the lit faces first or last, a sweep
  along the light (nearest or farthest first), and a stride (every s-th face, then the next residue);
* **corner orders**: as built, or each face's corners rotated by a seeded amount (which side a face lists
  first; the winding is kept).  Vertex numbering is no gene: :func:`silcount.mesh.model.from_polygons` welds and
  renumbers the vertices in coordinate order, so a shuffle would be undone;
* **lights** (:data:`LIGHTS`): directional or point, from two angles; axis-aligned; grazing along a face's
  edge (the light in the face's plane); a point light on a face's plane (exact ties);
* **defects** (only where the search allows them): faces removed (open), one face reversed.

No rule here encodes a known witness: the independent-set ordering of :mod:`silcount.papers.witness` is not
an order of :data:`ORDERS`, and the pillow is not a shape (the dome is a grid heightfield closed by a fan,
its height a gene).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, replace

import numpy as np

from silcount.mesh.lights import DirectionalLight, Light, PointLight
from silcount.mesh.model import Mesh, from_polygons
from silcount.mesh.shapes import icosphere, plane, torus, uv_sphere

SHAPES = ("icosphere", "dome", "strip", "grid", "uv_sphere", "torus", "prism", "fan_prism")
CLOSED_SHAPES = ("icosphere", "dome", "uv_sphere", "torus", "prism", "fan_prism")
QUAD_SHAPES = ("prism", "fan_prism")  # quad sides: no midpoint subdivision (it would leave T-junctions)
ORDERS = ("as_built", "reversed", "shuffle", "lit_first", "unlit_first", "near_first", "far_first", "stride")
LIGHTS = ("angles", "axis", "grazing", "on_plane", "point")
MAX_LEVEL = 14


@dataclass(frozen=True)
class Genome:
    """One point of the search space; every field is a gene (see the module docstring)."""

    shape: str = "icosphere"
    level: int = 1
    subdiv: int = 0
    perturb: float = 0.0
    height: float = 0.5
    order: str = "as_built"
    stride: int = 2
    rotate_corners: bool = False
    light: str = "angles"
    theta: float = 0.7
    phi: float = 0.3
    axis: int = 4
    face: int = 0
    defect: str = "none"
    defect_count: int = 0
    seed: int = 0

    def key(self) -> str:
        """The genome as canonical JSON: its identity in caches, reports and files."""
        return json.dumps(asdict(self), sort_keys=True)

    def at_level(self, level: int) -> Genome:
        return replace(self, level=int(level))

    def canonical(self) -> Genome:
        """The same mesh and light with every gene that does not act set to its default (one cache key each)."""
        d, base = asdict(self), asdict(Genome())
        used = {"shape", "level", "perturb", "order", "rotate_corners", "light", "defect"}
        used |= {"subdiv"} if self.shape not in QUAD_SHAPES else set()
        used |= {"height"} if self.shape == "dome" else set()
        used |= {"stride"} if self.order == "stride" else set()
        used |= {"axis"} if self.light == "axis" else {"theta", "phi"}
        used |= {"face"} if self.light in ("grazing", "on_plane") or self.defect == "reverse" else set()
        used |= {"defect_count"} if self.defect == "remove" else set()
        if self.order == "shuffle" or self.perturb > 0 or self.rotate_corners or self.defect == "remove":
            used.add("seed")
        return Genome(**{k: (v if k in used else base[k]) for k, v in d.items()})

    def rule(self) -> str:
        """The family rule: the genes that act, but the level, as one line."""
        d, base = asdict(self.canonical()), asdict(Genome())
        d.pop("level")
        return ", ".join(f"{k}={v}" for k, v in d.items() if v != base[k] or k in ("shape", "order", "light"))


def size_of(shape: str, level: int) -> dict:
    """The shape's own size parameters at ``level`` (1 .. :data:`MAX_LEVEL`)."""
    lv = max(1, min(int(level), MAX_LEVEL))
    if shape == "icosphere":
        return {"subdivisions": min(lv - 1, 6)}
    if shape == "dome":
        return {"k": int(round(2 * 1.6 ** (lv - 1)))}
    if shape == "strip":
        return {"cells": int(round(4 * 2.0 ** (lv - 1)))}
    if shape == "grid":
        return {"n": int(round(2 * 1.45 ** (lv - 1)))}
    if shape == "uv_sphere":
        return {"slices": int(round(4 * 1.45 ** (lv - 1))), "stacks": max(2, int(round(3 * 1.45 ** (lv - 1))))}
    if shape == "torus":
        return {"n_major": int(round(6 * 1.45 ** (lv - 1))), "n_minor": int(round(4 * 1.45 ** (lv - 1)))}
    return {"sides": int(3 * 2 ** (lv - 1))}


def dome(k: int, height: float) -> Mesh:
    """A closed, consistently wound dome: z = height (1 - x^2)(1 - y^2) over a k x k grid of [-1, 1]^2, closed
    below by a fan of 4k triangles to an apex at z = -0.5."""
    xs = np.linspace(-1.0, 1.0, k + 1)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    verts = np.stack([X.ravel(), Y.ravel(), (height * (1 - X**2) * (1 - Y**2)).ravel()], axis=1)
    at = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = at[:-1, :-1].ravel(), at[1:, :-1].ravel(), at[1:, 1:].ravel(), at[:-1, 1:].ravel()
    faces = np.stack([np.stack([a, b, c], 1), np.stack([a, c, d], 1)], 1).reshape(-1, 3).tolist()
    rim = list(at[:, 0][:-1]) + list(at[-1, :][:-1]) + list(at[::-1, -1][:-1]) + list(at[0, ::-1][:-1])
    apex = len(verts)
    faces += [[int(q), int(p), apex] for p, q in zip(rim, rim[1:] + rim[:1])]
    return from_polygons(np.vstack([verts, [(0.0, 0.0, -0.5)]]), faces, name=f"dome{k}")


def prism(sides: int, fan: bool) -> Mesh:
    """A prism over a regular ``sides``-gon: n-gon caps (or caps fanned from their centre into coplanar
    triangles) and quad sides; closed and consistently wound."""
    t = 2 * np.pi * np.arange(sides) / sides
    ring = np.stack([np.cos(t), np.sin(t)], 1)
    verts = np.vstack([np.column_stack([ring, -np.ones(sides)]), np.column_stack([ring, np.ones(sides)])])
    quads = [[i, (i + 1) % sides, sides + (i + 1) % sides, sides + i] for i in range(sides)]
    if not fan:
        return from_polygons(
            verts, [list(range(sides))[::-1], list(range(sides, 2 * sides))] + quads, name=f"prism{sides}"
        )
    verts = np.vstack([verts, [(0.0, 0.0, -1.0), (0.0, 0.0, 1.0)]])
    lo, hi = 2 * sides, 2 * sides + 1
    caps = [[lo, (i + 1) % sides, i] for i in range(sides)] + [
        [hi, sides + i, sides + (i + 1) % sides] for i in range(sides)
    ]
    return from_polygons(verts, caps + quads, name=f"fan_prism{sides}")


def base_mesh(shape: str, level: int, height: float = 0.5) -> Mesh:
    """The shape at ``level``, as built (before subdivision, perturbation and reordering)."""
    p = size_of(shape, level)
    if shape == "icosphere":
        return icosphere(p["subdivisions"])
    if shape == "dome":
        return dome(p["k"], height)
    if shape == "strip":
        m = plane(1, p["cells"])
        m.name = f"strip{p['cells']}"
        return m
    if shape == "grid":
        m = plane(p["n"], p["n"])
        m.name = f"grid{p['n']}"
        return m
    if shape == "uv_sphere":
        return uv_sphere(p["slices"], p["stacks"])
    if shape == "torus":
        return torus(n_major=p["n_major"], n_minor=p["n_minor"])
    if shape in ("prism", "fan_prism"):
        return prism(p["sides"], fan=shape == "fan_prism")
    raise ValueError(f"unknown shape {shape!r}")


def _polygons(mesh: Mesh) -> list[list[int]]:
    c, s = mesh.corners.tolist(), mesh.face_start.tolist()
    return [c[s[i] : s[i + 1]] for i in range(mesh.n_faces)]


def _subdivide(verts: np.ndarray, faces: list[list[int]]) -> tuple[np.ndarray, list[list[int]]]:
    """One midpoint subdivision of the triangles (other polygons kept): shared edge midpoints are one vertex."""
    mid: dict[tuple[int, int], int] = {}
    pts = [tuple(v) for v in verts.tolist()]

    def m(a: int, b: int) -> int:
        k = (min(a, b), max(a, b))
        if k not in mid:
            mid[k] = len(pts)
            pts.append(tuple((np.asarray(pts[a]) + np.asarray(pts[b])) / 2.0))
        return mid[k]

    out: list[list[int]] = []
    for f in faces:
        if len(f) != 3:
            out.append(f)
            continue
        a, b, c = f
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
    return np.asarray(pts, dtype=np.float64), out


def _light(g: Genome, verts: np.ndarray, faces: list[list[int]]) -> Light:
    d = np.array([np.sin(g.theta) * np.cos(g.phi), np.sin(g.theta) * np.sin(g.phi), np.cos(g.theta)])
    centre = (verts.min(0) + verts.max(0)) / 2
    radius = float(np.linalg.norm(verts - centre, axis=1).max()) or 1.0
    f = faces[g.face % len(faces)]
    p0, p1, p2 = verts[f[0]], verts[f[1]], verts[f[2]]
    n = np.cross(p1 - p0, p2 - p0)
    if g.light == "axis":
        v = np.zeros(3)
        v[g.axis % 3] = 1.0 if g.axis % 6 < 3 else -1.0
        return DirectionalLight(v)
    if g.light == "grazing" and np.any(n):
        # along the face's first side, tilted towards the light angles within the face's plane: facing value 0
        edge = p1 - p0
        nn = n / np.linalg.norm(n)
        along = d - np.dot(d, nn) * nn
        v = along if np.any(np.abs(along) > 1e-12) else edge
        return DirectionalLight(v)
    if g.light == "on_plane" and np.any(n):
        nn = n / np.linalg.norm(n)
        along = d - np.dot(d, nn) * nn
        if not np.any(np.abs(along) > 1e-12):
            along = p1 - p0
        return PointLight(p0 + 3.0 * radius * along / np.linalg.norm(along))
    if g.light == "point":
        return PointLight(centre + 3.0 * radius * d)
    return DirectionalLight(d)


def _order(g: Genome, verts: np.ndarray, faces: list[list[int]], light: Light) -> np.ndarray:
    F = len(faces)
    idx = np.arange(F)
    if g.order == "as_built":
        return idx
    if g.order == "reversed":
        return idx[::-1]
    if g.order == "shuffle":
        return np.random.default_rng([g.seed, 1]).permutation(F)
    if g.order == "stride":
        s = max(2, int(g.stride))
        return np.concatenate([idx[r::s] for r in range(s)])
    tri = np.array([f[:3] for f in faces])
    p0, p1, p2 = verts[tri[:, 0]], verts[tri[:, 1]], verts[tri[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    to = np.asarray(light.vector)[None, :] - (0 if light.is_directional else p0)
    lit = np.einsum("ij,ij->i", to, n) > 0
    if g.order in ("lit_first", "unlit_first"):
        first = lit if g.order == "lit_first" else ~lit
        return np.concatenate([idx[first], idx[~first]])
    centroid = (p0 + p1 + p2) / 3
    if light.is_directional:  # nearest the light: furthest along its direction
        near = np.argsort(-(centroid @ np.asarray(light.vector)), kind="stable")
    else:
        near = np.argsort(np.linalg.norm(centroid - np.asarray(light.vector), axis=1), kind="stable")
    return near if g.order == "near_first" else near[::-1]


def build(g: Genome) -> tuple[Mesh, Light]:
    """The mesh and light of genome ``g`` (deterministic: every random choice is seeded by ``g.seed``)."""
    base = base_mesh(g.shape, g.level, g.height)
    verts, faces = base.vertices.copy(), _polygons(base)
    for _ in range(max(0, min(int(g.subdiv), 2)) if g.shape not in QUAD_SHAPES else 0):
        verts, faces = _subdivide(verts, faces)
    if g.perturb > 0:
        centre = verts.mean(0)
        radius = float(np.linalg.norm(verts - centre, axis=1).max()) or 1.0
        noise = np.random.default_rng([g.seed, 2]).uniform(-1.0, 1.0, size=len(verts))
        verts = verts + (g.perturb * radius * noise)[:, None] * (verts - centre) / radius
    if g.defect == "remove" and g.defect_count > 0 and len(faces) > 4:
        gone = set(
            np.random.default_rng([g.seed, 3])
            .choice(len(faces), min(g.defect_count, len(faces) // 4), replace=False)
            .tolist()
        )
        faces = [f for i, f in enumerate(faces) if i not in gone]
    elif g.defect == "reverse" and faces:
        faces[g.face % len(faces)] = faces[g.face % len(faces)][::-1]
    light = _light(g, verts, faces)
    order = _order(g, verts, faces, light)
    faces = [faces[i] for i in order.tolist()]
    if g.rotate_corners:
        turns = np.random.default_rng([g.seed, 4]).integers(0, 3, size=len(faces)).tolist()
        faces = [f[t % len(f) :] + f[: t % len(f)] for f, t in zip(faces, turns)]
    name = f"{base.name}-s{g.subdiv}-{g.order}"
    return from_polygons(verts, faces, name=name), light


__all__ = ["CLOSED_SHAPES", "Genome", "LIGHTS", "MAX_LEVEL", "ORDERS", "SHAPES", "base_mesh", "build", "size_of"]
