"""Small mesh files written on the fly (tmp_path) in every format silcount reads, for the bad-input and fuzz tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

# the regular tetrahedron (alternate cube corners), outward winding: closed, 4 faces, 6 edges
TETRA_V = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
TETRA_F = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])


def obj_text(vertices, faces) -> str:
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=float).tolist()]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def off_text(vertices, faces) -> str:
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=float).tolist()]
    lines += [f"{len(f)} " + " ".join(str(i) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def tetra_bytes(fmt: str) -> bytes:
    """The tetrahedron as a file: obj, off, ply (ascii), ply_bin, stl (ascii), stl_bin."""
    if fmt == "obj":
        return obj_text(TETRA_V, TETRA_F).encode()
    if fmt == "off":
        return off_text(TETRA_V, TETRA_F).encode()
    t = trimesh.Trimesh(TETRA_V, TETRA_F, process=False)
    if fmt == "ply":
        return t.export(file_type="ply", encoding="ascii")
    if fmt == "ply_bin":
        return t.export(file_type="ply", encoding="binary")
    if fmt == "stl":
        return t.export(file_type="stl_ascii").encode()
    if fmt == "stl_bin":
        return t.export(file_type="stl")
    raise ValueError(fmt)


EXT = {"obj": ".obj", "off": ".off", "ply": ".ply", "ply_bin": ".ply", "stl": ".stl", "stl_bin": ".stl"}
FMTS = tuple(EXT)


def write(tmp: Path, name: str, data: bytes | str) -> Path:
    p = Path(tmp) / name
    p.write_bytes(data.encode() if isinstance(data, str) else data)
    return p
