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

Light-facing is the detectors' rule (:func:`silcount.detectors.reference.facing_flags`,
``(L - p0) . n > 0``).  For a directional light every far vertex is the one
point ``(-d, 0)``: the sides are triangles and the dark cap vanishes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silcount.detectors import detect
from silcount.detectors.adjacency import facing_flags
from silcount.detectors.base import Silhouette
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh


@dataclass
class Volume:
    """The shadow volume of one caster, in homogeneous world coordinates."""

    silhouette: Silhouette
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


def side_triangles(mesh: Mesh, oriented: np.ndarray, light: Light) -> np.ndarray:
    """(S, 3, 4) side quads ``(b, a, a_inf, b_inf)`` of the oriented silhouette edges ``(a, b)``, as triangles."""
    a = mesh.vertices[oriented[:, 0]]
    b = mesh.vertices[oriented[:, 1]]
    ah = np.concatenate([a, np.ones((len(a), 1))], axis=1)
    bh = np.concatenate([b, np.ones((len(b), 1))], axis=1)
    ai, bi = to_infinity(a, light), to_infinity(b, light)
    first = np.stack([bh, ah, ai], axis=1)
    if isinstance(light, DirectionalLight):
        return first
    return np.concatenate([first, np.stack([bh, ai, bi], axis=1)], axis=0)


def build_volume(
    mesh: Mesh,
    light: Light,
    detector: str = "reference",
    variant: str = "intended",
    silhouette: Silhouette | None = None,
) -> Volume:
    """Run ``detector`` (engine ``fast``) and build the caster's volume; pass ``silhouette`` to reuse one."""
    sil = silhouette if silhouette is not None else detect(mesh, light, detector, variant=variant, engine="fast")
    lit, _ = facing_flags(mesh, light)  # the detectors' own facing test: caps agree with the sides
    if isinstance(light, DirectionalLight):
        dark = np.zeros((0, 3, 4))
    else:
        dark = to_infinity(mesh.vertices[mesh.faces[~lit]], light)
    return Volume(sil, side_triangles(mesh, sil.oriented, light), lit, dark)
