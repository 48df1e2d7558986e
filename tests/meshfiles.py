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


_PLY_CODES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
    "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
    "double": "d", "float64": "d",
}  # fmt: skip


def ply_bytes(
    vertices,
    faces,
    fmt: str = "ascii",
    count_type: str = "uchar",
    index_type: str = "int",
    coord_type: str = "float",
    extra_vertex: bool = False,
    extra_face: bool = False,
    strips: list[list[int]] | None = None,
) -> bytes:
    """A PLY file written here, independently of silcount and trimesh: any format, list and index types,
    optional extra properties (a normal and a colour per vertex, a flag before and a colour after each face's
    list, an ``edge`` element between), faces as ``face`` records or ``tristrips`` (``strips``)."""
    import struct

    order = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}[fmt]
    head = ["ply", f"format {fmt} 1.0", "comment written by tests/meshfiles.py", f"element vertex {len(vertices)}"]
    head += [f"property {coord_type} {a}" for a in "xyz"]
    if extra_vertex:
        head += [f"property float n{a}" for a in "xyz"] + [f"property uchar {c}" for c in ("red", "green", "blue")]
    if extra_face:
        head += ["element edge 1", "property int vertex1", "property int vertex2"]
    records = [list(f) for f in faces] if strips is None else strips
    head += [f"element {'face' if strips is None else 'tristrips'} {len(records)}"]
    if extra_face:
        head += ["property uchar flags"]
    head += [f"property list {count_type} {index_type} vertex_indices"]
    if extra_face:
        head += ["property float quality"]
    head += ["end_header"]
    coords = np.asarray(vertices).tolist()
    if coord_type not in ("float", "float32", "double", "float64"):
        coords = [[int(x) for x in v] for v in coords]
    vrows = [list(v) + ([0.0, 0.0, 1.0, 255, 128, 0] if extra_vertex else []) for v in coords]
    vtypes = [coord_type] * 3 + (["float"] * 3 + ["uchar"] * 3 if extra_vertex else [])
    frows, ftypes = [], []
    for r in records:
        frows.append(([7] if extra_face else []) + [len(r)] + list(r) + ([0.5] if extra_face else []))
        ftypes.append(
            (["uchar"] if extra_face else []) + [count_type] + [index_type] * len(r) + (["float"] if extra_face else [])
        )
    erows = [[0, 1]] if extra_face else []
    etypes = [["int", "int"]] if extra_face else []
    out = ("\n".join(head) + "\n").encode()
    rows = [(r, vtypes) for r in vrows] + list(zip(erows, etypes)) + list(zip(frows, ftypes))
    if fmt == "ascii":
        return (
            out
            + "".join(" ".join(repr(x) if isinstance(x, float) else str(x) for x in r) + "\n" for r, _ in rows).encode()
        )
    body = b"".join(struct.pack(order + "".join(_PLY_CODES[t] for t in ts), *r) for r, ts in rows)
    return out + body
