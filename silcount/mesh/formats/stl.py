"""STL, ASCII and binary, read here (not by trimesh) so that a truncated binary file is told apart from an ASCII one.

* Binary: an 80-byte header, a little-endian ``uint32`` triangle count, then 50
  bytes per triangle.  A file whose size is exactly ``84 + 50 n`` is binary even
  when its header starts with ``solid`` (many exporters write that).
* ASCII: ``solid`` ... ``facet normal`` / ``outer loop`` / three ``vertex``
  lines / ``endloop`` / ``endfacet`` ... ``endsolid``; keywords in any case,
  several solids in one file.

STL stores each triangle's corners by value: silcount welds them by position.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.formats.common import Parsed, count_in_file, text_of

_DTYPE = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])
_KEYWORDS = ("solid", "facet", "outer", "endfacet", "endsolid")


def kind(path: Path, size: int) -> tuple[str, int]:
    """``("binary", n)`` when the size matches the header's triangle count, else ``("ascii", 0)``."""
    with open(path, "rb") as fh:
        head = fh.read(84)
    if len(head) == 84:
        n = int(np.frombuffer(head[80:84], "<u4")[0])
        if size == 84 + 50 * n:
            return "binary", n
    if head.lstrip()[:5].lower() == b"solid" and b"\x00" not in head[:5]:
        return "ascii", 0
    if len(head) < 84:
        raise UnreadableInput(f"{path}: truncated STL: {size} bytes, shorter than a binary STL header (84)")
    n = int(np.frombuffer(head[80:84], "<u4")[0])
    raise UnreadableInput(
        f"{path}: corrupt or truncated binary STL: the header promises {n} triangles "
        f"({84 + 50 * n} bytes), the file has {size} bytes"
    )


def _triangles(verts: np.ndarray, where) -> Parsed:
    n = len(verts) // 3
    return Parsed(
        verts,
        np.full(n, 3, dtype=np.int64),
        np.arange(3 * n, dtype=np.int64),
        where,
        no_faces="the file holds no facet (0 triangles)",
    )


def _read_binary(data: bytes) -> Parsed:
    n = int(np.frombuffer(data[80:84], "<u4")[0])
    tri = np.frombuffer(data, dtype=_DTYPE, count=n, offset=84)
    return _triangles(tri["v"].reshape(-1, 3).astype(np.float64), lambda i: f"triangle {i}")


def _read_ascii(text: str, path: Path) -> Parsed:
    verts: list[list[float]] = []
    in_loop = 0
    for lineno, raw in enumerate(text.splitlines(), 1):
        parts = raw.split()
        if not parts:
            continue
        tag = parts[0].lower()
        try:
            if tag == "vertex":
                if len(parts) != 4:
                    raise ValueError("a vertex needs 3 coordinates")
                try:
                    verts.append([float(parts[1]), float(parts[2]), float(parts[3])])
                except ValueError:
                    raise ValueError("a vertex coordinate is not a number") from None
                in_loop += 1
            elif tag == "endloop":
                if in_loop != 3:
                    raise ValueError(f"a facet loop has {in_loop} vertices, STL needs 3")
                in_loop = 0
            elif tag not in _KEYWORDS:
                raise ValueError(f"unexpected {parts[0][:20]!r}")
        except ValueError as exc:
            raise UnreadableInput(f"{path}: line {lineno}: corrupt ASCII STL: {exc}") from None
    if in_loop or len(verts) % 3:
        raise UnreadableInput(f"{path}: truncated ASCII STL: the last facet is incomplete")
    return _triangles(np.asarray(verts, dtype=np.float64).reshape(-1, 3), lambda i: f"facet {i}")


def read(path: Path, data: bytes) -> Parsed:
    if kind(path, len(data))[0] == "binary":
        return _read_binary(data)
    return _read_ascii(text_of(data, path, "STL"), path)


def estimate(path: Path, size: int) -> tuple[int, int]:
    """(vertices, faces): the binary header's count, or the ``endfacet`` keywords of an ASCII file."""
    k, n = kind(path, size)
    if k == "ascii":
        n = count_in_file(path, (b"endfacet",))[0]
    return 3 * n, n
