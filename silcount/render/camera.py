"""The contract's camera: ``gluLookAt`` and ``gluPerspective`` with an infinite far plane.

The projection is ``gluPerspective`` with ``far -> infinity`` (Everitt &
Kilgard 2002, Sec. 4): row 3 is ``(0, 0, -1, -2 near)``, so a point at
infinity (``w = 0``) lands exactly on the far plane (NDC z = 1) and is never
clipped.  Pixel ``(row, col)`` samples NDC ``x = 2 (col + 0.5) / W - 1``,
``y = 1 - 2 (row + 0.5) / H`` (scene README, "The mask").
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from silcount.errors import BadArgument


@dataclass(frozen=True)
class Camera:
    eye: np.ndarray
    target: np.ndarray
    up: np.ndarray
    fov_y_deg: float
    near: float
    width: int
    height: int

    @classmethod
    def of(cls, scene) -> "Camera":
        return cls(scene.eye, scene.target, scene.up, scene.fov_y_deg, scene.near, scene.width, scene.height)

    @cached_property
    def view(self) -> np.ndarray:
        """4x4 world -> eye (``gluLookAt``)."""
        f = self.target - self.eye
        s = np.cross(f, self.up)
        if np.linalg.norm(f) == 0 or np.linalg.norm(s) == 0:
            raise BadArgument("camera: eye equals target, or up is parallel to the view direction")
        f = f / np.linalg.norm(f)
        s = s / np.linalg.norm(s)
        u = np.cross(s, f)
        m = np.eye(4)
        m[0, :3], m[1, :3], m[2, :3] = s, u, -f
        m[:3, 3] = -m[:3, :3] @ self.eye
        return m

    @property
    def aspect(self) -> float:
        return self.width / self.height

    @cached_property
    def projection(self) -> np.ndarray:
        """4x4 eye -> clip, ``gluPerspective`` with an infinite far plane."""
        f = 1.0 / np.tan(np.radians(self.fov_y_deg) / 2.0)
        return np.array([[f / self.aspect, 0, 0, 0], [0, f, 0, 0], [0, 0, -1, -2 * self.near], [0, 0, -1, 0]])

    @cached_property
    def view_projection(self) -> np.ndarray:
        return self.projection @ self.view

    def pixel_rays(self) -> np.ndarray:
        """(H, W, 3) world directions through the pixel centres, scaled so that ``t`` is eye depth ``-z_eye``.

        A hit at parameter ``t`` lies ``t`` in front of the eye along the view
        axis, so the near plane is ``t = near`` exactly as the rasteriser clips.
        """
        tan_y = np.tan(np.radians(self.fov_y_deg) / 2.0)
        col = np.arange(self.width) + 0.5
        row = np.arange(self.height) + 0.5
        x = (2.0 * col / self.width - 1.0) * tan_y * self.aspect
        y = (1.0 - 2.0 * row / self.height) * tan_y
        d_eye = np.stack(np.broadcast_arrays(x[None, :], y[:, None], -np.ones((1, 1))), axis=-1)
        return d_eye @ self.view[:3, :3]  # R^T d  (rows of R are the camera axes)

    def eye_depth_from_ndc_z(self, z_ndc: np.ndarray) -> np.ndarray:
        """Invert the infinite projection: ``z_ndc = 1 - 2 near / w``  ->  ``w = -z_eye``."""
        with np.errstate(divide="ignore"):
            return 2.0 * self.near / (1.0 - z_ndc)
