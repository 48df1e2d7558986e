"""Wavefront OBJ, read here (not by trimesh) so that polygons survive as authored.

trimesh triangulates OBJ polygons (the quad cube would have 18 edges, not 12)
and may merge or split vertices by texture coordinate; silcount keeps every
face as written and welds by position itself.

What is read (Wavefront OBJ spec, Appendix B1 of the Advanced Visualizer manual):

* ``v x y z [w]`` vertices (``w``, a weight for rational curves, and the
  common ``v x y z r g b`` colour extension are ignored);
* ``f`` (and the old ``fo``) faces of any size, with ``v``, ``v/vt``,
  ``v/vt/vn`` and ``v//vn`` references, positive (1-based) and negative
  (relative: ``-1`` is the last vertex defined *before* the face) indices;
* ``\\`` at the end of a line continues the statement on the next line;
* ``#`` starts a comment anywhere on a line (a ``\\`` inside a comment does not
  continue it); blank lines, CRLF line ends, leading blanks;
* ``vt``, ``vn``, ``vp``, ``g``, ``o``, ``s``, ``mg``, ``usemtl``, ``mtllib``
  and any other statement: ignored (texture, normals and grouping do not change
  the surface).

``l`` (polyline) and ``p`` (point) elements are not faces: a file with only
those is refused as "no faces" and says how many it has. Free-form geometry
(``curv``, ``surf``) is not tessellated: such a file is refused the same way.

Speed: statements are sorted by their first token in Python, their numbers
parsed in C (``np.fromstring``); when that fast path meets anything unusual it
hands the file to the line-by-line reader, which gives the exact line of the
problem.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.formats.common import Parsed, as_float, as_int, count_in_file, faces_from_lists, numbers, text_of

_COMMENT = re.compile(r"#[^\n]*")
_CONTINUED = re.compile(r"^(?:[^\n]*\\[ \t\r]*\n)+[^\n]*", re.M)
_BACKSLASH_NEWLINE = re.compile(r"\\[ \t\r]*\n")
_LEADING = re.compile(r"^[ \t\f\v]+", re.M)
_SLASH_TAIL = re.compile(r"/\S*")
_EMPTY_VERTEX_REF = re.compile(r"(?:^|\s)/")
_FACE_TAGS = ("f", "fo")
_I64 = 2**63 - 1  # indices beyond int64 are out of range anyway; kept at the limit, as np.fromstring does


def _join_continuations(text: str) -> str:
    """Join ``\\``-continued lines into one statement, keeping the line count (empty lines follow it)."""

    def join(m: re.Match) -> str:
        s = m.group(0)
        k = len(_BACKSLASH_NEWLINE.findall(s))
        return _BACKSLASH_NEWLINE.sub(" ", s) + "\n" * k

    return _CONTINUED.sub(join, text)


def logical_lines(text: str) -> list[str]:
    """The statements, one per physical line number (line ``i + 1`` of the file is entry ``i``), left-aligned."""
    if "#" in text:
        text = _COMMENT.sub("", text)
    if "\\" in text:
        text = _join_continuations(text)
    if _LEADING.search(text):
        text = _LEADING.sub("", text)
    return text.split("\n")


def read(path: Path, data: bytes) -> Parsed:
    lines = logical_lines(text_of(data, path, "OBJ"))
    fast = _read_fast(lines)
    return fast if fast is not None else _read_slow(path, lines)


def _where(face_lines: np.ndarray):
    return lambda i: f"line {int(face_lines[i]) + 1}"


def _no_faces(tags: dict[str, int]) -> str:
    found = [
        f"{tags[t]} {name} ('{t}')"
        for t, name in (("l", "line"), ("p", "point"), ("curv", "curve"), ("surf", "surface"))
        if tags.get(t)
    ]
    if found:
        return f"the file has {' and '.join(found)} elements and no face ('f'); silcount reads polygon faces only"
    return "the file has vertices but no face ('f') statement"


def _finish(verts: np.ndarray, sizes, raw, before, face_lines, tags: dict[str, int]) -> Parsed:
    raw = np.asarray(raw, dtype=np.int64)
    nbefore = np.repeat(np.asarray(before, dtype=np.int64), sizes)
    corners = np.where(raw > 0, raw - 1, np.where(raw < 0, raw + nbefore, -1))
    face_lines = np.asarray(face_lines, dtype=np.int64)
    return Parsed(
        verts, np.asarray(sizes, dtype=np.int64), corners, _where(face_lines), written=raw, no_faces=_no_faces(tags)
    )


def _read_fast(lines: list[str]) -> Parsed | None:
    """The vectorised reader; None when anything is unusual (the slow reader then says what)."""
    heads_arr = np.array([ln[:2] for ln in lines])
    is_v = (heads_arr == "v ") | (heads_arr == "v\t")
    is_f = (heads_arr == "f ") | (heads_arr == "f\t")
    if np.any(np.isin(heads_arr, ("v", "f", "v\r", "f\r", "fo"))):
        return None  # "v"/"f" alone, or the old "fo": the slow reader handles them
    v_at, f_at = np.flatnonzero(is_v), np.flatnonzero(is_f)
    if v_at.size == 0 and f_at.size == 0:
        return None
    v_lines = [lines[i][2:] for i in v_at]
    v_counts = np.fromiter(map(len, map(str.split, v_lines)), dtype=np.int64, count=len(v_lines))
    if v_counts.size and np.any(v_counts < 3):
        return None
    vals = numbers(" ".join(v_lines))
    if vals is None or vals.size != int(v_counts.sum()):
        return None
    if v_counts.size and np.all(v_counts == 3):
        verts = vals.reshape(-1, 3)
    else:
        first = np.zeros(v_counts.size, dtype=np.int64)
        np.cumsum(v_counts[:-1], out=first[1:])
        verts = vals[first[:, None] + np.arange(3)]
    f_lines = [lines[i][2:] for i in f_at]
    sizes = np.fromiter(map(len, map(str.split, f_lines)), dtype=np.int64, count=len(f_lines))
    joined = " ".join(f_lines)
    if "/" in joined:
        if _EMPTY_VERTEX_REF.search(joined):
            return None
        joined = _SLASH_TAIL.sub("", joined)
    raw = numbers(joined, np.int64)
    if raw is None or raw.size != int(sizes.sum()):
        return None
    before = np.cumsum(is_v)[f_at]
    tags = _other_tags(heads_arr) if f_at.size == 0 else {}
    return _finish(verts.reshape(-1, 3), sizes, raw, before, f_at, tags)


def _other_tags(heads_arr: np.ndarray) -> dict[str, int]:
    return {
        "l": int(np.count_nonzero((heads_arr == "l ") | (heads_arr == "l\t"))),
        "p": int(np.count_nonzero((heads_arr == "p ") | (heads_arr == "p\t"))),
        "curv": int(np.count_nonzero(heads_arr == "cu")),
        "surf": int(np.count_nonzero(heads_arr == "su")),
    }


def _read_slow(path: Path, lines: list[str]) -> Parsed:
    """Line by line: the reference reader, and the one that names the line of a problem."""
    verts: list[list[float]] = []
    polys: list[list[int]] = []
    before: list[int] = []
    face_lines: list[int] = []
    tags = {"l": 0, "p": 0, "curv": 0, "surf": 0}
    for i, line in enumerate(lines):
        parts = line.split()
        if not parts:
            continue
        tag = parts[0]
        try:
            if tag == "v":
                if len(parts) < 4:
                    raise ValueError("a vertex needs 3 coordinates")
                verts.append([as_float(t, "coordinate") for t in parts[1:4]])
            elif tag in _FACE_TAGS:
                idx = []
                for tok in parts[1:]:
                    ref = tok.split("/", 1)[0]
                    if not ref:
                        raise ValueError(f"the face corner {tok[:20]!r} has no vertex index")
                    idx.append(max(min(as_int(ref, "vertex index"), _I64), -_I64))
                polys.append(idx)
                before.append(len(verts))
                face_lines.append(i)
            elif tag in tags:
                tags[tag] += 1
        except ValueError as exc:
            raise UnreadableInput(f"{path}: line {i + 1}: {exc}: {line.strip()[:60]!r}") from None
    if not verts and not polys:
        raise UnreadableInput(f"{path}: not an OBJ mesh: no vertex ('v') or face ('f') statements")
    sizes, raw = faces_from_lists(polys)
    return _finish(np.asarray(verts, dtype=np.float64).reshape(-1, 3), sizes, raw, before, face_lines, tags)


def estimate(path: Path, size: int) -> tuple[int, int]:
    """(vertices, faces): the ``v`` and ``f`` statements at line starts, counted without parsing."""
    nv, nf = count_in_file(path, (b"\nv ", b"\nf "))
    with open(path, "rb") as fh:
        first = fh.read(2)  # the first line has no newline before it
    return nv + (first == b"v "), nf + (first == b"f ")
