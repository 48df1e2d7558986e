"""What every reader returns, and the checks all readers share: bad faces dropped and counted, numbers parsed fast.

A reader turns file bytes into a :class:`Parsed`: vertices as read, faces as
CSR (``sizes``, ``corners``) with indices *not yet checked*, and a function
naming face ``i`` in the file's own terms (``line 12``, ``face 3``).
:func:`clean_faces` then applies the rule "a bad face is not a bad file":

* a face indexing a vertex the file does not have is dropped;
* a face with fewer than three distinct vertices is dropped;
* a face visiting one vertex twice, not in a row (a polygon touching itself),
  is dropped;
* a vertex repeated in a row (``f 1 2 3 3``, a triangle written as a quad) is
  read once: the face is the polygon of its distinct corners.

Each rule that fires gives one warning with its count and the first face it hit;
only a file with no usable face left is refused (:class:`InvalidMesh`, exit 4).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput


@dataclass
class Parsed:
    """A file's geometry as read: vertices (V, 3), faces in CSR form with unchecked 0-based indices."""

    vertices: np.ndarray
    sizes: np.ndarray  # (F,) corners per face
    corners: np.ndarray  # (sum of sizes,) 0-based vertex indices, possibly out of range
    where: Callable[[int], str]  # face i -> where it is in the file ("line 12", "face 3")
    written: np.ndarray | None = None  # the indices as written in the file, when they differ from ``corners``
    no_faces: str = ""  # why the file has no face, when ``sizes`` is empty
    notes: list[str] = field(default_factory=list)  # warnings the reader itself raised


_CHUNK = 1 << 22


def count_in_file(path: Path, needles: tuple[bytes, ...]) -> list[int]:
    """Occurrences of each byte string in the file, streamed in chunks (a match may straddle two)."""
    counts = [0] * len(needles)
    tails = [b""] * len(needles)
    with open(path, "rb") as fh:
        while chunk := fh.read(_CHUNK):
            for i, nd in enumerate(needles):
                block = tails[i] + chunk
                counts[i] += block.count(nd)
                tails[i] = block[-(len(nd) - 1) :] if len(nd) > 1 else b""
    return counts


def faces_from_lists(polys: list[list[int]]) -> tuple[np.ndarray, np.ndarray]:
    """CSR (sizes, corners) from a list of index lists."""
    sizes = np.fromiter(map(len, polys), dtype=np.int64, count=len(polys))
    corners = np.fromiter((i for p in polys for i in p), dtype=np.int64, count=int(sizes.sum()))
    return sizes, corners


def text_of(data: bytes, path: Path, fmt: str) -> str:
    """The file as text (latin-1: every byte maps to one character); NUL bytes mean a binary file."""
    if b"\x00" in data:
        raise UnreadableInput(f"{path}: binary data, not a text {fmt} file")
    return data.decode("latin-1")


def numbers(text: str, dtype: type = np.float64) -> np.ndarray | None:
    """Whitespace-separated numbers parsed in C (``np.fromstring``), or None when a token is not one."""
    try:
        return np.fromstring(text, dtype=dtype, sep=" ")
    except (ValueError, DeprecationWarning):
        return None


_INT_TOKEN = re.compile(r"[+-]?\d+")


def as_int(token: str, what: str) -> int:
    """An integer token, or ValueError with silcount's own words (never Python's)."""
    if not _INT_TOKEN.fullmatch(token):
        raise ValueError(f"{what} {token[:20]!r} is not an integer")
    return int(token)


def as_float(token: str, what: str) -> float:
    try:
        return float(token)
    except ValueError:
        raise ValueError(f"{what} {token[:20]!r} is not a number") from None


def refuse_if_short(path: Path, fmt: str, nv: int, nf: int, size: int) -> None:
    """A text header whose counts cannot fit in the file (a vertex takes at least 6 bytes, "0 0 0\\n",
    a triangle 8, "3 0 1 2\\n") is corrupt or truncated, not a large mesh."""
    if 6 * nv + 8 * nf > size:
        raise UnreadableInput(
            f"{path}: corrupt or truncated {fmt}: the header promises {nv} vertices and "
            f"{nf} faces, more than a {size}-byte file can hold"
        )


def plural(n: int, word: str) -> str:
    """``n word``, with an ``s`` unless ``n`` is one: ``plural(1, "face")`` is ``1 face``, ``plural(2, "face")``
    ``2 faces``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def clean_faces(parsed: Parsed) -> tuple[np.ndarray, np.ndarray, list[str], str]:
    """Apply the bad-face rules (module docstring): (sizes, corners, warnings, why none is usable or "")."""
    sizes, corners, nv = parsed.sizes.astype(np.int64), parsed.corners.astype(np.int64), len(parsed.vertices)
    n = sizes.size
    if n and sizes.min() == sizes.max() == 3:  # the common case, checked in a few vectorised passes
        t = corners.reshape(-1, 3)
        if (
            t.min() >= 0
            and t.max() < nv
            and not np.any((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 2] == t[:, 0]))
        ):
            return sizes, corners, list(parsed.notes), ""
    start = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(sizes, out=start[1:])
    face_of = np.repeat(np.arange(n, dtype=np.int64), sizes)
    reasons: list[tuple[np.ndarray, Callable[[int, int], str]]] = []

    out_corner = (corners < 0) | (corners >= nv)
    out_of_range = np.zeros(n, dtype=bool)
    out_of_range[face_of[out_corner]] = True
    written = parsed.written if parsed.written is not None else corners

    def out_text(count: int, first: int) -> str:
        bad = int(written[start[first] + int(np.flatnonzero(out_corner[start[first] : start[first + 1]])[0])])
        return (
            f"{plural(count, 'face')} indexing a missing vertex (first: {parsed.where(first)}, "
            f"vertex {bad}; the file has {nv} {'vertex' if nv == 1 else 'vertices'})"
        )

    reasons.append((out_of_range, out_text))

    # a vertex repeated in a row is read once (cyclically: the last corner is followed by the first)
    nxt = np.arange(1, corners.size + 1, dtype=np.int64)
    nonempty = sizes > 0
    nxt[start[1:][nonempty] - 1] = start[:-1][nonempty]
    repeat = corners == corners[nxt]
    runs = np.zeros(n, dtype=bool)
    runs[face_of[repeat]] = True
    if repeat.any():
        all_equal = nonempty & (np.bincount(face_of[repeat], minlength=n) == sizes)
        repeat[start[:-1][all_equal]] = False  # such a face keeps one corner: too few vertices, counted below
        keep = ~repeat
        sizes = np.bincount(face_of[keep], minlength=n).astype(np.int64)
        corners, face_of = corners[keep], face_of[keep]
    distinct = sizes.copy()
    touching = np.zeros(n, dtype=bool)
    big = sizes > 3  # after removing runs, a triangle cannot repeat a vertex; a larger polygon can
    if big.any():
        sel = big[face_of]
        order = np.lexsort((corners[sel], face_of[sel]))
        c, f = corners[sel][order], face_of[sel][order]
        dup = (c[1:] == c[:-1]) & (f[1:] == f[:-1])
        np.subtract.at(distinct, f[1:][dup], 1)
        touching[f[1:][dup]] = True
    few = (distinct < 3) & ~out_of_range
    touching &= ~few & ~out_of_range
    reasons.append(
        (few, lambda k, i: f"{plural(k, 'face')} with fewer than 3 distinct vertices (first: {parsed.where(i)})")
    )
    reasons.append((touching, lambda k, i: f"{plural(k, 'face')} visiting a vertex twice (first: {parsed.where(i)})"))
    drop = out_of_range | few | touching
    warnings = list(parsed.notes)
    for mask, text in reasons:
        if mask.any():
            warnings.append(f"dropped {text(int(mask.sum()), int(np.flatnonzero(mask)[0]))}")
    read_once = runs & ~drop
    if read_once.any():
        warnings.append(
            f"{plural(int(read_once.sum()), 'face')} repeating a vertex in a row, read as the polygon of "
            f"their distinct corners (first: {parsed.where(int(np.flatnonzero(read_once)[0]))})"
        )
    if n and drop.all():
        return sizes[:0], corners[:0], warnings, "; ".join(w.removeprefix("dropped ") for w in warnings)
    if drop.any():
        corners = corners[~drop[face_of]]
        sizes = sizes[~drop]
    return sizes, corners, warnings, ""


def polygons(sizes: np.ndarray, corners: np.ndarray) -> np.ndarray | list[np.ndarray]:
    """Faces as :func:`silcount.mesh.model.from_polygons` takes them: one (F, k) array when all have k corners."""
    if sizes.size and np.all(sizes == sizes[0]):
        return corners.reshape(-1, int(sizes[0]))
    return np.split(corners, np.cumsum(sizes)[:-1])
