"""Loading meshes from files.

OBJ and OFF are parsed here so that polygon faces survive as authored (the
quad cube has 12 edges only as quads; trimesh would triangulate them).  PLY,
STL, GLB and GLTF are read with trimesh.  Every failure becomes
:class:`UnreadableInput` (cannot read or parse) or :class:`InvalidMesh`
(parsed, but unusable), each naming the file.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .errors import InvalidMesh, UnreadableInput
from .mesh import Mesh, from_polygons

FORMATS = (".obj", ".off", ".ply", ".stl", ".glb", ".gltf")


def _parse_obj(text: str, path: Path) -> tuple[np.ndarray, list[list[int]]]:
    verts: list[list[float]] = []
    faces: list[list[int]] = []
    for lineno, raw in enumerate(text.splitlines(), 1):
        parts = raw.split("#", 1)[0].split()
        if not parts:
            continue
        tag = parts[0]
        try:
            if tag == "v":
                if len(parts) < 4:
                    raise ValueError("a vertex needs 3 coordinates")
                verts.append([float(parts[1]), float(parts[2]), float(parts[3])])
            elif tag == "f":
                if len(parts) < 4:
                    raise ValueError("a face needs at least 3 vertices")
                idx = []
                for tok in parts[1:]:
                    i = int(tok.split("/", 1)[0])
                    if i == 0:
                        raise ValueError("OBJ indices start at 1")
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                faces.append(idx)
        except ValueError as exc:
            raise UnreadableInput(f"{path}: line {lineno}: {exc}: {raw.strip()[:60]!r}") from None
    return np.asarray(verts, dtype=np.float64).reshape(-1, 3), faces


def _parse_off(text: str, path: Path) -> tuple[np.ndarray, list[list[int]]]:
    tokens = [ln.split("#", 1)[0].split() for ln in text.splitlines()]
    tokens = [t for t in tokens if t]
    if not tokens or not tokens[0][0].endswith("OFF"):
        raise UnreadableInput(f"{path}: not an OFF file (no OFF header)")
    head = tokens[0][1:] or (tokens.pop(1) if len(tokens) > 1 else [])
    try:
        nv, nf = int(head[0]), int(head[1])
        body = tokens[1:]
        if len(body) < nv + nf:
            raise ValueError(f"expected {nv} vertices and {nf} faces, file has {len(body)} records")
        verts = np.array([[float(x) for x in body[i][:3]] for i in range(nv)], dtype=np.float64).reshape(-1, 3)
        faces = []
        for rec in body[nv:nv + nf]:
            k = int(rec[0])
            if len(rec) < k + 1:
                raise ValueError(f"face record {' '.join(rec)!r} is short")
            faces.append([int(x) for x in rec[1:k + 1]])
    except (ValueError, IndexError) as exc:
        raise UnreadableInput(f"{path}: corrupt OFF: {exc}") from None
    return verts, faces


def _load_trimesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    try:
        loaded = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types on corrupt input
        raise UnreadableInput(f"{path}: cannot parse as {path.suffix[1:].upper()}: {exc}".strip()) from None
    verts = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))), dtype=np.int64)
    return verts, faces


def load_mesh(path: str | os.PathLike) -> Mesh:
    """Load, weld and validate a mesh file; see :mod:`silcount.mesh`."""
    p = Path(path)
    if not p.exists():
        raise UnreadableInput(f"{p}: no such file")
    if p.is_dir():
        raise UnreadableInput(f"{p}: is a directory, not a mesh file")
    ext = p.suffix.lower()
    if ext not in FORMATS:
        raise UnreadableInput(f"{p}: unknown extension {p.suffix!r}; silcount reads {', '.join(FORMATS)}")
    if p.stat().st_size == 0:
        raise UnreadableInput(f"{p}: the file is empty")
    if ext in (".obj", ".off"):
        try:
            text = p.read_text(encoding="utf-8", errors="strict")
        except (UnicodeDecodeError, OSError) as exc:
            raise UnreadableInput(f"{p}: not a text {ext[1:].upper()} file: {exc}") from None
        verts, faces = (_parse_obj if ext == ".obj" else _parse_off)(text, p)
    else:
        verts, faces = _load_trimesh(p)
    if len(faces) == 0:
        raise InvalidMesh(f"{p}: the mesh has no faces")
    try:
        return from_polygons(verts, faces, name=p.stem)
    except InvalidMesh as exc:
        raise InvalidMesh(f"{p}: {exc}") from None
