"""Shadow volumes from a detector's oriented silhouette (stencil paper Sec. 5, Fig. 5).

Each silhouette edge ``(a, b)``, as traversed by its light-facing face
(``Silhouette.oriented``), is extruded away from the light to infinity: the
far vertices are the homogeneous directions ``(a - L, 0)``, ``(b - L, 0)``.
The side quad is wound ``(b, a, a_inf, b_inf)``, the reverse of the lit
face's traversal, so that with the light cap (the lit faces, as they are)
and the dark cap (the unlit faces projected to infinity, winding kept) the
volume is a closed surface whose front faces point out of it.  That is the
orientation two-sided stencil counting needs (Everitt & Kilgard 2002,
Sec. 3-4).  The paper clips each quad "between occluder and receiver"
(Sec. 5, the ``X_new`` formula); we extrude to infinity instead, which with
an infinite far plane needs no receiver and no clipping and is what makes
z-fail robust.

``truncated`` volumes (``receiver`` given) are the stencil paper's speed-up
(Sec. 5: "we will clip each infinite quadrilateral to the finite
quadrilateral between occluder and shadow receiver"): each far vertex is the
"new pixel" ``L + E (F - L) / (NF - D)``, the point where the ray from the
light through the silhouette vertex ``F`` meets the receiver plane
``N . X = N . C``.  We implement that geometric step, ``F`` moved along
``F - L`` to the plane (:func:`to_receiver`), which is the printed formula
under its one exact reading ``E = N.C - N.L``, ``D = N.L``; whether the
printed E and D admit that reading is decided symbolically by
:mod:`silcount.papers.projection`, not here.  The dark cap (z-fail) is the
unlit faces moved to the plane the same way.  The truncated volume is exact
for receivers on the light's side of the plane and loses every shadow beyond
it (a lower floor, a wall below the plane's level): a receiver that is not
the clipping plane.

``pertriangle`` volumes need no silhouette (the per-triangle shadow volumes
of Sintorn, Olsson & Assarsson 2011, drawn as stencil volumes): every
light-facing triangle is extruded on its own, its light cap (the triangle),
its dark cap (the triangle at infinity, winding reversed so that it faces
away from the light) and three side quads (:func:`pertriangle_volume`).
Two light-facing triangles that share an edge draw the same quad with
opposite windings; both use the same triangles of it, with the same first
vertex, so the rasteriser computes the same depths and the two cancel
exactly.

Light-facing is the detectors' rule (:func:`silcount.detectors.reference.facing_flags`,
``(L - p0) . n > 0``).  For a directional light every far vertex is the one
point ``(-d, 0)``: the sides are triangles and the dark cap vanishes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silcount.detectors import detect
from silcount.detectors.adjacency import facing_flags
from silcount.detectors.result import Silhouette
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh


@dataclass
class Volume:
    """The shadow volume of one caster, in homogeneous world coordinates."""

    silhouette: Silhouette | None  # None: per-triangle volumes, which find no silhouette
    sides: np.ndarray  # (S, 3, 4) side triangles, two per silhouette edge (one if directional)
    lit_faces: np.ndarray  # (F,) bool: the light cap (the caller reuses the scene's own triangles)
    dark_cap: np.ndarray  # (D, 3, 4) unlit faces at infinity (empty for a directional light)


def to_infinity(points: np.ndarray, light: Light) -> np.ndarray:
    """(..., 3) points -> (..., 4) their directions away from the light, ``w = 0``."""
    out = np.zeros(points.shape[:-1] + (4,))
    if isinstance(light, DirectionalLight):
        out[..., :3] = -np.asarray(light.direction)
    else:
        out[..., :3] = points - np.asarray(light.position)
    return out


def to_receiver(points: np.ndarray, light: Light, normal: np.ndarray, offset: float) -> np.ndarray:
    """(..., 3) points -> (..., 4) the stencil paper's "new pixel" (Sec. 5): each point moved away from the
    light onto the plane ``normal . X = offset``, ``w = 1``.

    Point light: ``L + alpha (F - L)``, ``alpha = (D - N.L) / (N.F - N.L)``; directional light (towards-light
    direction ``d``): ``F - t d``, ``t = (N.F - D) / (N.d)``.  Where the ray from the light through ``F``
    does not meet the plane at or beyond ``F`` (``alpha < 1``, ``t < 0``, or parallel), there is no
    receiver to stop at and the vertex stays at infinity (``w = 0``, as :func:`to_infinity`).
    """
    N, D = np.asarray(normal, dtype=np.float64), float(offset)
    out = to_infinity(points, light)
    NF = points @ N
    if isinstance(light, DirectionalLight):
        d = np.asarray(light.direction, dtype=np.float64)
        nd = float(N @ d)
        t = (NF - D) / nd if nd != 0 else np.full(NF.shape, -1.0)
        ok = t >= 0
        moved = points - t[..., None] * d
    else:
        L = np.asarray(light.position, dtype=np.float64)
        NL = float(N @ L)
        den = NF - NL
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = np.where(den != 0, (D - NL) / np.where(den != 0, den, 1.0), -1.0)
        ok = alpha >= 1
        moved = L + alpha[..., None] * (points - L)
    out[ok, :3] = moved[ok]
    out[ok, 3] = 1.0
    return out


def side_triangles(mesh: Mesh, oriented: np.ndarray, light: Light, far: np.ndarray | None = None) -> np.ndarray:
    """(S, 3, 4) side quads ``(b, a, a_far, b_far)`` of the oriented silhouette edges ``(a, b)``, as triangles.

    ``far``: (V, 4) far vertex of every mesh vertex (:func:`to_receiver`); default at infinity.
    """
    a = mesh.vertices[oriented[:, 0]]
    b = mesh.vertices[oriented[:, 1]]
    ah = np.concatenate([a, np.ones((len(a), 1))], axis=1)
    bh = np.concatenate([b, np.ones((len(b), 1))], axis=1)
    if far is None:
        ai, bi = to_infinity(a, light), to_infinity(b, light)
        if isinstance(light, DirectionalLight):
            return np.stack([bh, ah, ai], axis=1)  # every far vertex is the one point (-d, 0)
    else:
        ai, bi = far[oriented[:, 0]], far[oriented[:, 1]]
    return np.concatenate([np.stack([bh, ah, ai], axis=1), np.stack([bh, ai, bi], axis=1)], axis=0)


def build_volume(
    mesh: Mesh,
    light: Light,
    detector: str = "reference",
    variant: str = "intended",
    silhouette: Silhouette | None = None,
    receiver: tuple[np.ndarray, float] | None = None,
) -> Volume:
    """Run ``detector`` (engine ``fast``) and build the caster's volume; pass ``silhouette`` to reuse one.

    ``receiver`` = ``(N, D)``: the truncated volume, its far vertices on the plane ``N . X = D``
    (:func:`to_receiver`); None: the infinite volume.
    """
    sil = silhouette if silhouette is not None else detect(mesh, light, detector, variant=variant, engine="fast")
    lit, _ = facing_flags(mesh, light)  # the detectors' own facing test: caps agree with the sides
    if receiver is not None:
        far = to_receiver(mesh.vertices, light, *receiver)
        return Volume(sil, side_triangles(mesh, sil.oriented, light, far), lit, far[mesh.faces[~lit]])
    if isinstance(light, DirectionalLight):
        dark = np.zeros((0, 3, 4))
    else:
        dark = to_infinity(mesh.vertices[mesh.faces[~lit]], light)
    return Volume(sil, side_triangles(mesh, sil.oriented, light), lit, dark)


@dataclass
class IndexedVolume:
    """Per-triangle volumes as indices into one point table: the mesh's vertices, then each one's far point."""

    points: np.ndarray  # (2V, 4) homogeneous world: vertex i is row i, its point at infinity row V + i
    lit_faces: np.ndarray  # (F,) bool: the light-facing faces, each one's own light cap
    sides: np.ndarray  # (S, 3) int: side triangles, two per edge of each light-facing face (one if directional)
    dark_cap: np.ndarray  # (D, 3) int: each light-facing face at infinity, reversed (none if directional)

    def volume(self) -> Volume:
        """The same triangles as a :class:`Volume` (coordinates, no silhouette)."""
        return Volume(None, self.points[self.sides], self.lit_faces, self.points[self.dark_cap])


def pertriangle_volume(mesh: Mesh, light: Light) -> IndexedVolume:
    """Every light-facing face extruded on its own (Sintorn, Olsson & Assarsson 2011, as stencil volumes).

    Face ``(i, j, k)`` gives the edges ``(i, j), (j, k), (k, i)``; edge ``(a, b)`` gives the side quad
    ``(b, a, a_inf, b_inf)`` as the silhouette's sides do.  With ``u < v`` the quad of ``(u, v)`` is drawn
    as ``(v, u, u_inf), (v, u_inf, v_inf)`` and that of ``(v, u)`` as the same two triangles reversed
    with the first vertex kept, ``(v, u_inf, u), (v, v_inf, u_inf)``: the shared quads of neighbours
    cancel bit for bit.  The dark cap is ``(i_inf, k_inf, j_inf)``.
    """
    lit, _ = facing_flags(mesh, light)
    V = len(mesh.vertices)
    points = np.concatenate(
        [np.concatenate([mesh.vertices, np.ones((V, 1))], axis=1), to_infinity(mesh.vertices, light)], axis=0
    )
    f = mesh.faces[lit].astype(np.int64)
    a, b = f.reshape(-1), f[:, [1, 2, 0]].reshape(-1)
    u, v = np.minimum(a, b), np.maximum(a, b)
    forward = (a < b)[:, None]
    first = np.where(forward, np.stack([v, u, V + u], axis=1), np.stack([v, V + u, u], axis=1))
    if isinstance(light, DirectionalLight):  # every far point is (-d, 0): one triangle per edge, no dark cap
        return IndexedVolume(points, lit, first, np.zeros((0, 3), dtype=np.int64))
    second = np.where(forward, np.stack([v, V + u, V + v], axis=1), np.stack([v, V + v, V + u], axis=1))
    dark = V + f[:, [0, 2, 1]]
    return IndexedVolume(points, lit, np.concatenate([first, second], axis=0), dark)
