"""Geomview OFF, read here (not by trimesh) so that polygons survive as authored and truncation is named.

trimesh triangulates OFF polygons and reads only the plain ``OFF`` header
with one record per line; silcount reads the format as the Geomview manual
("OFF files", Object File Formats) defines it:

* the header keyword ``[ST][C][N][4][n]OFF`` (``OFF``, ``COFF``, ``NOFF``,
  ``STOFF``, ``CNOFF``, ``4OFF``, ``nOFF`` with its dimension, ...), which is
  optional, as the manual says ("many existing files lack this keyword"); the
  ModelNet misprint with the counts glued to it (``OFF490 518 0``) is read too;
* the counts ``NVertices NFaces [NEdges]`` on the header line itself or on a
  later line (``NEdges`` is not used; it may be missing);
* ``#`` comments and blank lines anywhere, leading blanks, CRLF line ends;
* vertices: the first three coordinates (``4OFF``: divided by the fourth,
  homogeneous one); normals, colours and texture coordinates after them are
  skipped;
* faces ``N v[0] .. v[N-1] colorspec``: the colour runs to the end of the line
  and is ignored;
* records split over lines: when the file is not one record per line it is
  read as the manual's token stream (a vertex is ``dimension`` numbers, plus 3
  for ``N``, 4 for ``C`` and 2 for ``ST``; a face's colour still ends at the
  end of its line).

Refused on purpose: ``OFF BINARY`` (the binary variant; exit 3, said so), and
an ``nOFF`` whose vertices are not 3-dimensional (exit 3).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.formats.common import Parsed, as_float, as_int, numbers, refuse_if_short, text_of

_KEYWORD = re.compile(r"(ST)?(C)?(N)?(4)?(n)?OFF(\d*)")
_COMMENT = re.compile(r"#[^\n]*")
_INT = re.compile(r"[+-]?\d+")
_I64 = 2**63 - 1  # an index beyond int64 is out of range anyway: kept at the limit, as np.fromstring does

Rows = list[tuple[int, list[str]]]  # (0-based line number, tokens) of every non-blank line


class _Corrupt(ValueError):
    """A problem in the file, in silcount's words; the reader adds the path."""


def _rows(text: str) -> Rows:
    if "#" in text:
        text = _COMMENT.sub("", text)
    return [(i, toks) for i, line in enumerate(text.split("\n")) if (toks := line.split())]


def _header(rows: Rows) -> tuple[Rows, int, int, int, dict[str, bool]]:
    """(the body rows, vertices, faces, dimension, flags) from the keyword and counts.

    Numbers after ``NEdges`` on the counts line begin the body (the spec's token stream)."""
    if not rows:
        raise _Corrupt("no OFF header")
    first = rows[0][1][0]
    m = _KEYWORD.fullmatch(first)
    flags = {"ST": False, "C": False, "N": False, "4": False, "n": False}
    pending: list[str] = []
    if m:
        for key, group in zip(flags, m.groups()[:5]):
            flags[key] = group is not None
        pending = ([m.group(6)] if m.group(6) else []) + rows[0][1][1:]
        r = 1
    elif _INT.fullmatch(first):  # the keyword is optional
        pending, r = list(rows[0][1]), 1
    else:
        raise _Corrupt("no OFF header")
    if pending[:1] == ["BINARY"]:
        raise _Corrupt("binary OFF ('OFF BINARY') is not read; convert it to text OFF or PLY")
    need = 3 if flags["n"] else 2
    line = rows[0][0]
    while len(pending) < need:
        if r >= len(rows):
            raise _Corrupt("no vertex and face counts")
        line = rows[r][0]
        pending += rows[r][1]
        r += 1
    try:
        head = [as_int(t, "count") for t in pending[:need]]
    except ValueError as exc:
        raise _Corrupt(f"the counts line: {exc}") from None
    dim = head[0] if flags["n"] else 3
    nv, nf = head[-2], head[-1]
    if nv < 0 or nf < 0:
        raise _Corrupt("negative counts")
    if len(pending) == need and r < len(rows) and len(rows[r][1]) == 1 and _INT.fullmatch(rows[r][1][0]):
        r += 1  # NEdges alone on its line
    if dim != 3:
        raise _Corrupt(f"{dim}-dimensional vertices (nOFF); silcount reads 3-D meshes")
    rest = pending[need + 1 :]
    return ([(line, rest)] if rest else []) + rows[r:], nv, nf, dim + flags["4"], flags


def _per_vertex(dims: int, flags: dict[str, bool]) -> int:
    return dims + 3 * flags["N"] + 4 * flags["C"] + 2 * flags["ST"]


def _line_mode(body: Rows, nv: int, nf: int, dims: int) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """One record per line: (vertices, sizes, corners), or None when the file is not written that way."""
    if len(body) < nv + nf or any(len(t) < dims for _, t in body[:nv]):
        return None
    frows = body[nv : nv + nf]
    ks = numbers(" ".join(t[0] for _, t in frows), np.int64) if frows else np.zeros(0, np.int64)
    if ks is None or ks.size != nf or np.any(ks < 0):
        return None
    if any(len(t) < k + 1 for (_, t), k in zip(frows, ks.tolist())):
        return None
    vals = numbers(" ".join(" ".join(t[:dims]) for _, t in body[:nv]))
    corners = numbers(" ".join(" ".join(t[1 : k + 1]) for (_, t), k in zip(frows, ks.tolist())), np.int64)
    if vals is None or vals.size != nv * dims or corners is None or corners.size != int(ks.sum()):
        return None
    return vals.reshape(nv, dims), ks, corners


def _stream_mode(body: Rows, nv: int, nf: int, dims: int, per: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The manual's token stream (records may span lines); a face's colour ends at the end of its line."""
    toks = [t for _, ts in body for t in ts]
    line = np.repeat([i for i, _ in body], [len(ts) for _, ts in body]) if body else np.zeros(0, np.int64)
    got = len(toks) // per if per else 0
    if got < nv:
        raise _Corrupt(
            f"truncated: the header promises {nv} vertices and {nf} faces, the file ends after {got} vertices"
        )
    coords = []
    for k in range(nv):
        rec = toks[k * per : k * per + dims]
        try:
            coords.append([as_float(t, "coordinate") for t in rec])
        except ValueError as exc:
            raise _Corrupt(f"line {int(line[k * per]) + 1}: vertex {k}: {exc}") from None
    pos = nv * per
    sizes, corners = [], []
    for f in range(nf):
        if pos >= len(toks):
            raise _Corrupt(
                f"truncated: the header promises {nv} vertices and {nf} faces, the file ends after {f} faces"
            )
        try:
            k = as_int(toks[pos], "a face's vertex count")
            if k < 0:
                raise ValueError(f"a face's vertex count {k} is negative")
            if pos + 1 + k > len(toks):
                raise _Corrupt(
                    f"truncated: the header promises {nv} vertices and {nf} faces, the file ends inside face {f}"
                )
            corners += [max(min(as_int(t, "vertex index"), _I64), -_I64) for t in toks[pos + 1 : pos + 1 + k]]
        except ValueError as exc:
            if isinstance(exc, _Corrupt):
                raise
            raise _Corrupt(f"line {int(line[pos]) + 1}: face {f}: {exc}") from None
        sizes.append(k)
        last = int(line[pos + k])
        pos += 1 + k
        while pos < len(toks) and line[pos] == last:  # the colorspec, to the end of the line
            pos += 1
    return (
        np.asarray(coords, dtype=np.float64).reshape(nv, dims),
        np.asarray(sizes, dtype=np.int64),
        np.asarray(corners, dtype=np.int64),
    )


def read(path: Path, data: bytes) -> Parsed:
    rows = _rows(text_of(data, path, "OFF"))
    try:
        body, nv, nf, dims, flags = _header(rows)
        got = _line_mode(body, nv, nf, dims)
        verts, sizes, corners = got if got is not None else _stream_mode(body, nv, nf, dims, _per_vertex(dims, flags))
    except _Corrupt as exc:
        raise UnreadableInput(f"{path}: corrupt OFF: {exc}") from None
    except OverflowError:
        raise UnreadableInput(f"{path}: corrupt OFF: a number too large for its field") from None
    if flags["4"]:
        with np.errstate(all="ignore"):
            verts = verts[:, :3] / verts[:, 3:4]
    return Parsed(
        verts,
        sizes,
        corners,
        lambda i: f"face {i}",
        no_faces=f"the header counts {nv} vertices and 0 faces" if nf == 0 else "",
    )


def estimate(path: Path, size: int) -> tuple[int, int]:
    """(vertices, faces) from the header, read from the first 64 KiB."""
    with open(path, "rb") as fh:
        head = fh.read(1 << 16).decode("latin-1")
    rows = _rows(head)
    try:
        _, nv, nf, _, _ = _header(rows[:8])
    except _Corrupt as exc:
        raise UnreadableInput(f"{path}: corrupt OFF: {exc}") from None
    refuse_if_short(path, "OFF", nv, nf, size)
    return nv, nf
