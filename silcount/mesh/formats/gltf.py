"""glTF 2.0 (``.gltf``, ``.glb``), read by trimesh: glTF stores indexed triangles, which trimesh keeps as they
are (``process=False``: no vertex merged, no face reordered), so there is nothing to gain from a reader of our own.
"""

from __future__ import annotations

import contextlib
import logging
import warnings
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.formats.common import Parsed


@contextlib.contextmanager
def _quiet_trimesh():
    """trimesh logs and warns on odd input; silcount reports errors itself, in one line."""
    log = logging.getLogger("trimesh")
    level, propagate = log.level, log.propagate
    log.setLevel(logging.CRITICAL + 1)
    log.propagate = False
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        log.setLevel(level)
        log.propagate = propagate


def read(path: Path, data: bytes) -> Parsed:
    import trimesh

    fmt = path.suffix[1:].upper()
    try:
        with _quiet_trimesh():
            loaded = trimesh.load(str(path), force="mesh", process=False)
            verts = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), dtype=np.float64).reshape(-1, 3)
            faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))), dtype=np.int64)
    except FileNotFoundError as exc:  # trimesh's resolver: a buffer or image file the glTF names is not there
        raise UnreadableInput(f"{path}: the file {exc} it refers to is missing (looked in {path.parent})") from None
    except Exception:  # trimesh raises many types on corrupt input; all mean "cannot parse"
        raise UnreadableInput(f"{path}: cannot parse as {fmt}: not a valid {fmt} file") from None
    if faces.size and (faces.ndim != 2 or faces.shape[1] < 3):
        raise UnreadableInput(f"{path}: cannot parse as {fmt}: faces of shape {faces.shape}")
    if faces.ndim != 2:
        faces = faces.reshape(-1, 3)
    return Parsed(
        verts,
        np.full(len(faces), faces.shape[1], dtype=np.int64),
        faces.reshape(-1),
        lambda i: f"triangle {i}",
        no_faces=f"{len(verts)} vertices and no triangle (points or lines only)",
    )


def estimate(path: Path, size: int) -> tuple[int, int]:
    return size // 12, size // 12  # at least 12 bytes per indexed triangle
