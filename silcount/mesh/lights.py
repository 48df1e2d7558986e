"""Light sources and the light-facing test shared by every detector.

A face is *light-facing* iff ``(L - p0) . n > 0`` for a point light at ``L``,
or ``d . n > 0`` for a directional light whose direction ``d`` points towards
the light; ``p0`` is the face's first vertex and ``n`` the (unnormalised)
normal ``(p1 - p0) x (p2 - p0)``.  Exactly zero is *not* light-facing; such
faces are ties and are counted (HSD paper, Sec. III; EESD paper, Sec. 2,
``||v, f|| = (v - f_v) . n_f``).

Random lights (:func:`random_lights`, the recipe of ``silcount audit``, the
corpus sweep, ``silcount calibrate`` and the benchmarks): unit directions
drawn from a normal distribution with ``numpy.random.default_rng(seed)``, one
row of three per light, each normalised; a point light sits
:data:`LIGHT_DISTANCE` bounding radii from the bounding-box centre along its
direction.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from silcount.errors import BadArgument

if TYPE_CHECKING:
    from silcount.mesh.model import Mesh

LIGHT_DISTANCE = 3.0
"""How far a random point light stands from the mesh's centre, in bounding radii."""


def _vec3(values, what: str) -> np.ndarray:
    arr = np.asarray(values, dtype=np.float64).reshape(-1)
    if arr.shape != (3,):
        raise BadArgument(f"{what} must have exactly 3 components, got {arr.size}")
    if not np.all(np.isfinite(arr)):
        raise BadArgument(f"{what} must be finite, got {arr.tolist()}")
    return arr


@dataclass(frozen=True)
class PointLight:
    """A point light at ``position`` (world coordinates)."""

    position: tuple[float, float, float]

    def __init__(self, position) -> None:
        object.__setattr__(self, "position", tuple(_vec3(position, "point light position").tolist()))

    @property
    def is_directional(self) -> bool:
        return False

    @property
    def vector(self) -> tuple[float, float, float]:
        """The light's defining vector: its position."""
        return self.position

    def describe(self) -> str:
        return "point " + ",".join(f"{c:.6g}" for c in self.position)


@dataclass(frozen=True)
class DirectionalLight:
    """A directional light; ``direction`` points *towards* the light (need not be unit)."""

    direction: tuple[float, float, float]

    def __init__(self, direction) -> None:
        d = _vec3(direction, "light direction")
        if not np.any(d != 0.0):
            raise BadArgument("light direction is the zero vector")
        object.__setattr__(self, "direction", tuple(d.tolist()))

    @property
    def is_directional(self) -> bool:
        return True

    @property
    def vector(self) -> tuple[float, float, float]:
        """The light's defining vector: its direction (towards the light)."""
        return self.direction

    def describe(self) -> str:
        return "directional " + ",".join(f"{c:.6g}" for c in self.direction)


Light = PointLight | DirectionalLight


def facing_values(p0: np.ndarray, normals: np.ndarray, light: Light) -> np.ndarray:
    """The signed value whose sign decides light-facing, one per face.

    ``p0`` (F, 3) first vertices, ``normals`` (F, 3) unnormalised normals.
    """
    if isinstance(light, DirectionalLight):
        return normals @ np.asarray(light.direction)
    to_light = np.asarray(light.position)[None, :] - p0
    return np.einsum("ij,ij->i", to_light, normals)


def random_directions(count: int, seed: int | np.random.SeedSequence) -> np.ndarray:
    """``count`` unit directions (``(count, 3)``), uniform on the sphere: normal draws from
    ``numpy.random.default_rng(seed)``, each row normalised."""
    dirs = np.random.default_rng(seed).normal(size=(count, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    return dirs


def sphere_lights(mesh: Mesh, directions: np.ndarray, distance: float = LIGHT_DISTANCE) -> list[Light]:
    """A point light ``distance`` bounding radii from ``mesh``'s centre along each of ``directions``."""
    radius = distance * max(mesh.bounding_radius, 1e-12)
    return [PointLight(mesh.centre + radius * d) for d in directions]


def random_lights(
    mesh: Mesh, count: int, seed: int | np.random.SeedSequence = 0, distance: float = LIGHT_DISTANCE
) -> list[Light]:
    """``count`` point lights uniformly on the sphere of ``distance`` x the bounding radius (seeded)."""
    return sphere_lights(mesh, random_directions(count, seed), distance)
