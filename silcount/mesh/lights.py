"""Light sources and the light-facing test shared by every detector.

A face is *light-facing* iff ``(L - p0) . n > 0`` for a point light at ``L``,
or ``d . n > 0`` for a directional light whose direction ``d`` points towards
the light; ``p0`` is the face's first vertex and ``n`` the (unnormalised)
normal ``(p1 - p0) x (p2 - p0)``.  Exactly zero is *not* light-facing; such
faces are ties and are counted (HSD paper, Sec. III; EESD paper, Sec. 2,
``||v, f|| = (v - f_v) . n_f``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silcount.errors import BadArgument


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
