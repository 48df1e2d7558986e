"""Reading ``silcount-scene/1`` files (``../shared/scenes/README.md``, a contract).

Transform order, exactly as the contract says: ``scale`` (number or
``[sx, sy, sz]``), then ``rotate_deg`` about world X, then Y, then Z
(right-handed, counter-clockwise seen from the positive end of the axis, as
``glRotate``), then ``translate``.  Vertices are used as stored: the mesh is
read with :func:`silcount.mesh.io.load_mesh`, whose exact-position welding moves
no coordinate, so every world triangle has the coordinates the file gives.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from silcount.errors import BadArgument, UnreadableInput
from silcount.mesh.io import load_mesh
from silcount.mesh.lights import DirectionalLight, Light, PointLight
from silcount.mesh.model import Mesh, from_polygons

SPEC = "silcount-scene/1"


def rotation_xyz(degrees) -> np.ndarray:
    """``Rz @ Ry @ Rx``: rotate about X first, then Y, then Z (world axes, as ``glRotate``)."""
    rx, ry, rz = np.radians(np.asarray(degrees, dtype=np.float64))
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


@dataclass
class SceneObject:
    """One object: its world-space triangle mesh and whether it casts shadows."""

    name: str
    mesh: Mesh  # world-space, welded (triangles)
    casts_shadow: bool

    @property
    def triangles(self) -> np.ndarray:
        """(T, 3, 3) world triangles in face order."""
        return self.mesh.vertices[self.mesh.faces]


@dataclass
class Scene:
    """A parsed scene: resolution, camera, light and world-space objects."""

    path: Path
    width: int
    height: int
    eye: np.ndarray
    target: np.ndarray
    up: np.ndarray
    fov_y_deg: float
    near: float
    light: Light
    objects: list[SceneObject]

    @property
    def name(self) -> str:
        return self.path.stem

    @cached_property
    def triangles(self) -> np.ndarray:
        """(T, 3, 3) all world triangles, objects in file order."""
        return np.concatenate([o.triangles for o in self.objects], axis=0)

    @cached_property
    def triangle_object(self) -> np.ndarray:
        """(T,) object index of each triangle of :attr:`triangles`."""
        return np.repeat(np.arange(len(self.objects)), [o.mesh.n_faces for o in self.objects])

    @property
    def casters(self) -> list[SceneObject]:
        return [o for o in self.objects if o.casts_shadow]

    def with_resolution(self, width: int, height: int) -> "Scene":
        """The same scene sampled at another resolution (tests render small)."""
        return Scene(
            self.path,
            int(width),
            int(height),
            self.eye,
            self.target,
            self.up,
            self.fov_y_deg,
            self.near,
            self.light,
            self.objects,
        )


def _vec(value, what: str, path: Path) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise UnreadableInput(f"{path}: {what} must be numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise UnreadableInput(f"{path}: {what} must be 3 finite numbers, got {value!r}")
    return arr


def _resolution(value, path: Path) -> tuple[int, int]:
    """``[width, height]``: two JSON integers (``512.5`` is refused, not rendered at 512)."""
    if (
        not isinstance(value, list)
        or len(value) != 2
        or not all(isinstance(v, int) and not isinstance(v, bool) for v in value)
    ):
        raise UnreadableInput(f"{path}: resolution must be [width, height], two whole numbers of pixels, got {value!r}")
    return value[0], value[1]


def _object(spec: dict, base: Path, path: Path, max_memory: int | None = None) -> SceneObject:
    if not isinstance(spec, dict) or "mesh" not in spec:
        raise UnreadableInput(f"{path}: every object needs a 'mesh' path, got {spec!r}")
    name = str(spec.get("name", Path(spec["mesh"]).stem))
    mesh = load_mesh(base / spec["mesh"], max_memory=max_memory)
    if not mesh.is_triangle_mesh:
        raise UnreadableInput(f"{path}: object {name!r}: scene meshes must be triangle meshes")
    scale = spec.get("scale", 1.0)
    s = np.full(3, float(scale)) if isinstance(scale, (int, float)) else _vec(scale, f"object {name!r} scale", path)
    if not np.all(np.isfinite(s)):
        raise UnreadableInput(f"{path}: object {name!r} scale must be finite, got {scale!r}")
    R = rotation_xyz(_vec(spec.get("rotate_deg", [0, 0, 0]), f"object {name!r} rotate_deg", path))
    t = _vec(spec.get("translate", [0, 0, 0]), f"object {name!r} translate", path)
    world = (mesh.vertices * s) @ R.T + t
    return SceneObject(name, from_polygons(world, mesh.faces, name=name), bool(spec.get("casts_shadow", True)))


def load_scene(path: str | os.PathLike, max_memory: int | None = None) -> Scene:
    """Parse a ``silcount-scene/1`` JSON file; every failure names the file.  ``max_memory``: the meshes'
    limit (:func:`silcount.mesh.io.load_mesh`)."""
    p = Path(path)
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UnreadableInput(f"{p}: no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise UnreadableInput(f"{p}: not a readable JSON scene: {exc}") from None
    if not isinstance(doc, dict) or doc.get("spec") != SPEC:
        raise UnreadableInput(
            f"{p}: not a {SPEC} file (spec field is {doc.get('spec') if isinstance(doc, dict) else None!r})"
        )
    try:
        width, height = _resolution(doc["resolution"], p)
        cam, light_spec, objs = doc["camera"], doc["light"], doc["objects"]
        fov, near = float(cam["fov_y_deg"]), float(cam["near"])
    except (KeyError, TypeError, ValueError) as exc:
        raise UnreadableInput(f"{p}: missing or malformed field: {exc}") from None
    if width <= 0 or height <= 0 or not 0 < fov < 180 or not near > 0:
        raise UnreadableInput(f"{p}: need positive resolution, 0 < fov_y_deg < 180 and near > 0")
    try:
        if "position" in light_spec:
            light: Light = PointLight(_vec(light_spec["position"], "light position", p))
        else:
            light = DirectionalLight(_vec(light_spec["direction"], "light direction", p))
    except (KeyError, TypeError, BadArgument) as exc:
        raise UnreadableInput(f"{p}: bad light: {exc}") from None
    objects = [_object(o, p.parent, p, max_memory) for o in objs]
    if not objects:
        raise UnreadableInput(f"{p}: the scene has no objects")
    return Scene(
        p,
        width,
        height,
        _vec(cam["eye"], "camera eye", p),
        _vec(cam["target"], "camera target", p),
        _vec(cam["up"], "camera up", p),
        fov,
        near,
        light,
        objects,
    )
