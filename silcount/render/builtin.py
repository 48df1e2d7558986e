"""Built-in scenes where the stencil paper's literal steps matter, generated in code (no shared files).

* ``overlapping_shadows``: two floating boxes under an overhead light, placed so that their shadows on
  the floor overlap; there the eye ray enters both volumes, the stencil is 2, and the printed final test
  ``If (~Stencil % 2)`` (:func:`silcount.render.stencil.shadow_from_stencil`, ``parity``) lights the
  overlap.  By hand: box A spans ``[-0.5, 0.5] x [2.5, 3.5] x [-0.5, 0.5]``, box B
  ``[0.2, 1.2] x [1, 2] x [-0.5, 0.5]``, light ``(0, 8, 0)``; the segment from the floor point
  ``(0.7, 0, 0)`` to the light is ``(0.7 (1 - s), 8 s, 0)``, inside B for ``s`` in ``[1/8, 1/4]``
  (``x`` in ``[0.525, 0.6125]``) and inside A for ``s`` in ``[5/16, 7/16]`` (``x`` in ``[0.394, 0.481]``).
* ``ledge``: a floor ``y = 0`` that ends at ``x = 1``, a riser down to a lower floor ``y = -2``, and a box
  whose shadow, lit from ``(-4, 6, 0)``, falls across the edge.  The truncated volume stops at the first
  floor's plane (:func:`silcount.render.receiver.floor_plane`), so the riser and the lower floor are
  receivers beyond the clipping plane: the paper's "new pixel" truncation loses their shadow.

Coordinates are world coordinates (no transform), so :func:`write_scene_files` writes scene files that
:func:`silcount.render.scene.load_scene` reads back to exactly the triangles of :func:`builtin_scene`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from silcount.atomic import make_folder, write_text
from silcount.errors import check_choice
from silcount.mesh.lights import PointLight
from silcount.mesh.model import Mesh, from_polygons
from silcount.render.scene import SPEC, Scene, SceneObject

DEFAULT_RESOLUTION = 512


def box(lo, hi, name: str) -> Mesh:
    """The axis-aligned box ``[lo, hi]``, 12 triangles wound counter-clockwise seen from outside."""
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    v = np.array([[(lo, hi)[i >> 2][0], (lo, hi)[(i >> 1) & 1][1], (lo, hi)[i & 1][2]] for i in range(8)])
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    return from_polygons(v, [t for a, b, c, d in quads for t in ([a, b, c], [a, c, d])], name=name)


def quad(corners, name: str) -> Mesh:
    """One planar quad ``(p0, p1, p2, p3)`` (counter-clockwise seen from its front) as two triangles."""
    return from_polygons(np.asarray(corners, dtype=np.float64), [[0, 1, 2], [0, 2, 3]], name=name)


def _floor(x0: float, x1: float, y: float, z0: float, z1: float, name: str) -> Mesh:
    """A horizontal rectangle facing +y."""
    return quad([[x0, y, z0], [x0, y, z1], [x1, y, z1], [x1, y, z0]], name)


def _overlapping_shadows() -> tuple[dict, list[tuple[Mesh, bool]]]:
    camera = {"eye": [6.0, 5.0, 8.0], "target": [0.3, 0.5, 0.0], "up": [0.0, 1.0, 0.0], "fov_y_deg": 45.0}
    objects = [
        (_floor(-10, 10, 0.0, -10, 10, "floor"), False),
        (box([-0.5, 2.5, -0.5], [0.5, 3.5, 0.5], "box_a"), True),
        (box([0.2, 1.0, -0.5], [1.2, 2.0, 0.5], "box_b"), True),
    ]
    return {"camera": camera, "light": [0.0, 8.0, 0.0]}, objects


def _ledge() -> tuple[dict, list[tuple[Mesh, bool]]]:
    camera = {"eye": [7.0, 5.0, 7.0], "target": [1.0, -0.5, 0.0], "up": [0.0, 1.0, 0.0], "fov_y_deg": 50.0}
    objects = [
        (_floor(-10, 1, 0.0, -10, 10, "upper_floor"), False),
        (quad([[1, -2, -10], [1, -2, 10], [1, 0, 10], [1, 0, -10]], "riser"), False),
        (_floor(1, 10, -2.0, -10, 10, "lower_floor"), False),
        (box([-0.5, 0.5, -0.5], [0.5, 1.5, 0.5], "box"), True),
    ]
    return {"camera": camera, "light": [-4.0, 6.0, 0.0]}, objects


BUILTIN = {"overlapping_shadows": _overlapping_shadows, "ledge": _ledge}


def _parts(name: str):
    check_choice("built-in scene", name, BUILTIN)
    return BUILTIN[name]()


def builtin_scene(name: str, resolution: int = DEFAULT_RESOLUTION) -> Scene:
    """The built-in scene ``name`` at ``resolution`` x ``resolution``, built in memory."""
    setup, objects = _parts(name)
    cam = setup["camera"]
    return Scene(
        Path("builtin") / f"{name}.json",
        int(resolution),
        int(resolution),
        np.array(cam["eye"]),
        np.array(cam["target"]),
        np.array(cam["up"]),
        float(cam["fov_y_deg"]),
        0.1,
        PointLight(setup["light"]),
        [SceneObject(m.name, m, casts) for m, casts in objects],
    )


def _obj_text(mesh: Mesh) -> str:
    return "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in mesh.vertices.tolist()) + "".join(
        f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in mesh.faces.tolist()
    )


def scene_document(name: str, resolution: int = DEFAULT_RESOLUTION) -> dict:
    """The ``silcount-scene/1`` document of a built-in scene; meshes at ``meshes/<scene>.<object>.obj``."""
    setup, objects = _parts(name)
    return {
        "spec": SPEC,
        "resolution": [int(resolution), int(resolution)],
        "camera": setup["camera"] | {"near": 0.1},
        "light": {"position": setup["light"]},
        "objects": [
            {"name": m.name, "mesh": f"meshes/{name}.{m.name}.obj", "casts_shadow": casts} for m, casts in objects
        ],
    }


def write_scene_files(dest: Path, resolution: int = DEFAULT_RESOLUTION) -> list[Path]:
    """Write every built-in scene as ``dest/<name>.json`` plus its OBJ meshes under ``dest/meshes/``."""
    make_folder(dest / "meshes")
    written = []
    for name in BUILTIN:
        _, objects = _parts(name)
        for m, _casts in objects:
            written.append(write_text(dest / "meshes" / f"{name}.{m.name}.obj", _obj_text(m)))
        doc = scene_document(name, resolution)
        written.append(write_text(dest / f"{name}.json", json.dumps(doc, indent=2) + "\n"))
    return written
