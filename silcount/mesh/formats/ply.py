"""Stanford PLY, read here (not by trimesh) so that polygons survive and every short element is named.

trimesh triangulates PLY polygons, reads no ``tristrips`` element and turns a
point cloud into a "truncated" body; silcount reads the format as Greg Turk's
PLY specification defines it:

* ``format ascii 1.0``, ``binary_little_endian`` and ``binary_big_endian``;
* every scalar type (``char uchar short ushort int uint float double`` and the
  sized names ``int8 .. float64``), for coordinates, list counts and indices;
* any elements in any order, with any extra properties (normals, colours,
  quality, ...), which are skipped; ``comment`` and ``obj_info`` lines;
* ``vertex`` (its ``x``, ``y``, ``z``), ``face`` (its ``vertex_indices`` or
  ``vertex_index`` list, or its only list) polygons of any size, and
  ``tristrips`` (triangle strips, restarted at index ``-1``; the degenerate
  triangles that join strips are not faces and are skipped);
* a file with vertices and no face (a point cloud) is "no faces" (exit 4).

ASCII bodies are read as the specification's stream of numbers (line breaks
carry no meaning), parsed in C, or one record a line when lines carry values
the header does not declare (:mod:`.ply_lines`); binary bodies with
``np.frombuffer``.  An element whose records all have the same list lengths
(every face a triangle) is read in one vectorised step; else record by record.

Refused on purpose (exit 3, said so): an unknown format or property type.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from silcount.errors import UnreadableInput
from silcount.mesh.formats.common import Parsed, numbers, refuse_if_short
from silcount.mesh.formats.ply_lines import Lines, by_lines
from silcount.mesh.formats.strips import decode_strips

TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}  # fmt: skip
FORMATS = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}
_END = re.compile(rb"end_header[ \t]*(\r\n|\n|\r|$)")
FACE_LISTS = ("vertex_indices", "vertex_index")


class _Corrupt(ValueError):
    """A problem in the file, in silcount's words; the reader adds the path."""


@dataclass
class Prop:
    name: str
    type: str  # numpy type code without byte order ("u1", "f4", ...)
    count: str | None = None  # the list count's type code; None for a scalar


@dataclass
class Element:
    name: str
    n: int
    props: list[Prop]


@dataclass
class Header:
    fmt: str  # a key of FORMATS
    elements: list[Element]
    body_at: int


def parse_header(head: bytes) -> Header:
    """The header of a PLY file (``head``: its first bytes, the whole header included)."""
    if not re.match(rb"ply[ \t]*(\r\n|\n|\r)", head):
        raise _Corrupt("not a PLY file (no 'ply' magic and 'end_header')")
    m = _END.search(head)
    if m is None:
        raise _Corrupt("not a PLY file (no 'ply' magic and 'end_header')")
    try:
        lines = head[: m.start()].decode("ascii").splitlines()[1:]
    except UnicodeDecodeError:
        raise _Corrupt("corrupt PLY header: non-ASCII bytes in the header") from None
    fmt, elements = None, []
    for line in lines:
        parts = line.split()
        if not parts or parts[0] in ("comment", "obj_info"):
            continue
        bad = f"corrupt PLY header: malformed line {line.strip()[:60]!r}"
        if parts[0] == "format":
            if len(parts) < 2:
                raise _Corrupt(bad)
            fmt = parts[1]
        elif parts[0] == "element":
            if len(parts) != 3 or not re.fullmatch(r"\d+", parts[2]):
                raise _Corrupt(bad)
            elements.append(Element(parts[1], int(parts[2]), []))
        elif parts[0] == "property":
            if not elements:
                raise _Corrupt("corrupt PLY header: a property before any element")
            if parts[1:2] == ["list"]:
                if len(parts) != 5 or parts[2] not in TYPES or parts[3] not in TYPES:
                    raise _Corrupt(bad)
                elements[-1].props.append(Prop(parts[4], TYPES[parts[3]], TYPES[parts[2]]))
            else:
                if len(parts) != 3 or parts[1] not in TYPES:
                    raise _Corrupt(bad)
                elements[-1].props.append(Prop(parts[2], TYPES[parts[1]]))
        else:
            raise _Corrupt(bad)
    if fmt not in FORMATS:
        raise _Corrupt(f"corrupt PLY header: unknown format {fmt!r}")
    return Header(fmt, elements, m.end())


class _Body:
    """The body as units: numbers (ASCII, each one unit) or bytes (binary); gathers values at unit offsets."""

    def __init__(self, data: bytes, fmt: str):
        self.ascii = fmt == "ascii"
        self.order = FORMATS[fmt]
        self.kind = "ASCII" if self.ascii else "binary"
        if self.ascii:
            text = data.decode("latin-1")
            vals = numbers(text)
            if vals is None:
                raise _Corrupt(_bad_token(text))
            self.vals = vals
            self.size = vals.size
        else:
            self.buf = np.frombuffer(data, dtype=np.uint8)
            self.data = data
            self.size = len(data)

    def width(self, code: str) -> int:
        return 1 if self.ascii else int(code[1])

    def gather(self, offsets: np.ndarray, code: str) -> np.ndarray:
        if self.ascii:
            return self.vals[offsets]
        w = int(code[1])
        idx = offsets[:, None] + np.arange(w)
        return self.buf[idx].copy().view(np.dtype(self.order + code)).reshape(-1)

    def table(self, pos: int, n: int, rec: int, layout: list[tuple[Prop, int, int]]) -> dict[str, np.ndarray]:
        """``n`` records of ``rec`` units, one layout: property j's values as ``v{j}``, a list's counts as ``n{j}``."""
        out: dict[str, np.ndarray] = {}
        if self.ascii:
            grid = self.vals[pos : pos + n * rec].reshape(n, rec)
            for j, (p, o, c) in enumerate(layout):
                if p.count is None:
                    out[f"v{j}"] = grid[:, o]
                else:
                    out[f"n{j}"], out[f"v{j}"] = grid[:, o], grid[:, o + 1 : o + 1 + c]
            return out
        names: list[str] = []
        formats: list = []
        offsets: list[int] = []
        for j, (p, o, c) in enumerate(layout):
            if p.count is not None:
                names.append(f"n{j}")
                formats.append(self.order + p.count)
                offsets.append(o)
                o += int(p.count[1])
            names.append(f"v{j}")
            formats.append((self.order + p.type, (c,)) if p.count else self.order + p.type)
            offsets.append(o)
        dt = np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": max(rec, 1)})
        arr = np.frombuffer(self.data, dtype=dt, count=n, offset=pos) if rec else np.zeros(n, dtype=dt)
        return {k: arr[k] for k in names}

    def one(self, offset: int, code: str) -> float:
        if self.ascii:
            return float(self.vals[offset])
        return struct.unpack_from(self.order + _STRUCT[code], self.data, offset)[0]


_STRUCT = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I", "f4": "f", "f8": "d"}


def _bad_token(text: str) -> str:
    for lineno, line in enumerate(text.splitlines(), 1):
        for tok in line.split():
            try:
                float(tok)
            except ValueError:
                return f"corrupt ASCII PLY: body line {lineno}: {tok[:20]!r} is not a number"
    return "corrupt ASCII PLY: the body is not a list of numbers"


def _count(body: _Body, off: int, prop: Prop, elem: Element, i: int) -> int:
    c = body.one(off, prop.count or "")
    if not (np.isfinite(c) and c >= 0 and c == np.floor(c)):
        raise _Corrupt(f"corrupt {body.kind} PLY: element '{elem.name}' record {i}: list length {c:g} is not a count")
    return int(c)


def _short(body: _Body, elem: Element, i: int) -> _Corrupt:
    return _Corrupt(
        f"truncated {body.kind} PLY: element '{elem.name}' ran short: "
        f"the body ends after {i} of the {elem.n} records the header promises"
    )


def read_element(body: _Body, pos: int, elem: Element, wanted: set[str]) -> tuple[int, dict[str, tuple]]:
    """Walk ``elem`` from unit ``pos``; return the end and, per wanted property, its values.

    A scalar gives ``(values,)``, a list ``(counts, flat values)``.
    """
    n, props = elem.n, elem.props
    out: dict[str, tuple] = {}
    if not props:
        return pos, out  # an element without properties holds no data, however many records it has
    if n == 0:
        return pos, {
            p.name: ((np.zeros(0),) if p.count is None else (np.zeros(0, np.int64), np.zeros(0)))
            for p in props
            if p.name in wanted
        }
    # the layout of the first record; if every record has it, the element is one array
    layout, off = [], pos
    for p in props:
        if p.count is None:
            layout.append((off - pos, 0))
            off += body.width(p.type)
        else:
            if off + body.width(p.count) > body.size:
                raise _short(body, elem, 0)
            c = _count(body, off, p, elem, 0)
            layout.append((off - pos, c))
            off += body.width(p.count) + c * body.width(p.type)
    rec = off - pos
    if pos + n * rec <= body.size:
        table = body.table(pos, n, rec, [(p, o, c) for p, (o, c) in zip(props, layout)])
        if all(p.count is None or np.all(table[f"n{j}"] == c) for j, (p, (o, c)) in enumerate(zip(props, layout))):
            for j, (p, (_, c)) in enumerate(zip(props, layout)):
                if p.name in wanted:
                    vals = np.asarray(table[f"v{j}"])
                    out[p.name] = (vals,) if p.count is None else (np.full(n, c, dtype=np.int64), vals.reshape(-1))
            return pos + n * rec, out
    return _walk(body, pos, elem, wanted)


def _walk(body: _Body, pos: int, elem: Element, wanted: set[str]) -> tuple[int, dict[str, tuple]]:
    """Record by record, for elements whose list lengths vary."""
    spots: dict[str, list[int]] = {p.name: [] for p in elem.props if p.name in wanted}
    counts: dict[str, list[int]] = {p.name: [] for p in elem.props if p.name in wanted and p.count is not None}
    off = pos
    for i in range(elem.n):
        for p in elem.props:
            if p.count is None:
                if p.name in spots:
                    spots[p.name].append(off)
                off += body.width(p.type)
            else:
                if off + body.width(p.count) > body.size:
                    raise _short(body, elem, i)
                c = _count(body, off, p, elem, i)
                off += body.width(p.count)
                if p.name in spots:
                    spots[p.name].append(off)
                    counts[p.name].append(c)
                off += c * body.width(p.type)
        if off > body.size:
            raise _short(body, elem, i)
    out: dict[str, tuple] = {}
    for p in elem.props:
        if p.name not in wanted:
            continue
        at = np.asarray(spots[p.name], dtype=np.int64)
        if p.count is None:
            out[p.name] = (body.gather(at, p.type),)
        else:
            cs = np.asarray(counts[p.name], dtype=np.int64)
            within = np.arange(int(cs.sum()), dtype=np.int64) - np.repeat(np.cumsum(cs) - cs, cs)
            out[p.name] = (cs, body.gather(np.repeat(at, cs) + body.width(p.type) * within, p.type))
    return off, out


def _index_list(elem: Element) -> Prop:
    lists = [p for p in elem.props if p.count is not None]
    named = [p for p in lists if p.name in FACE_LISTS]
    if named or len(lists) == 1:
        return (named or lists)[0]
    raise _Corrupt(f"corrupt PLY header: element '{elem.name}' has no 'vertex_indices' list")


def _as_indices(values: np.ndarray, body: _Body, elem: Element) -> np.ndarray:
    if values.dtype.kind == "f":
        bad = values != np.floor(values)
        if bad.any():
            raise _Corrupt(
                f"corrupt {body.kind} PLY: element '{elem.name}': index {values[bad][0]:g} is not an integer"
            )
        values = np.clip(values, -(2.0**62), 2.0**62)
    return values.astype(np.int64)


def read(path: Path, data: bytes) -> Parsed:
    try:
        return _read(data)
    except _Corrupt as exc:
        raise UnreadableInput(f"{path}: {exc}") from None


def _read(data: bytes) -> Parsed:
    header = parse_header(data[: 1 << 20])
    body = _Body(data[header.body_at :], header.fmt)
    lines = Lines()
    if body.ascii:
        lines = by_lines(data[header.body_at :], body.vals, header.elements, data[: header.body_at].count(b"\n"))
    if lines.vals is not None:
        body.vals, body.size = lines.vals, lines.vals.size
    try:
        return _elements(header, body, [lines.note] if lines.note else [])
    except _Corrupt:
        if lines.short:  # one record a line, extra values, and short: the stream's misreading would not say so
            raise _Corrupt(lines.short) from None
        raise


def _elements(header: Header, body: _Body, notes: list[str]) -> Parsed:
    pos = 0
    verts = np.zeros((0, 3))
    polys: list[tuple[np.ndarray, np.ndarray]] = []
    names = [e.name for e in header.elements]
    n_face = 0
    for elem in header.elements:
        wanted: set[str] = set()
        if elem.name == "vertex":
            have = {p.name for p in elem.props if p.count is None}
            if not {"x", "y", "z"} <= have:
                raise _Corrupt("corrupt PLY header: the 'vertex' element has no x, y, z properties")
            wanted = {"x", "y", "z"}
        elif elem.name in ("face", "tristrips"):
            wanted = {_index_list(elem).name}
        pos, got = read_element(body, pos, elem, wanted)
        if elem.name == "vertex":
            f4 = {p.name for p in elem.props if p.type == "f4"}  # ASCII "float" coordinates: rounded to float32
            with np.errstate(over="ignore", invalid="ignore"):
                xyz = [got[k][0].astype(np.float32 if k in f4 else np.float64) for k in ("x", "y", "z")]
            verts = np.stack(xyz, axis=1).astype(np.float64)
        elif elem.name == "face":
            counts, flat = got[_index_list(elem).name]
            polys.append((counts, _as_indices(flat, body, elem)))
            n_face += counts.size
        elif elem.name == "tristrips":
            prop = _index_list(elem)
            counts, flat = got[prop.name]
            flat = _as_indices(flat, body, elem)
            restart = -1 if prop.type[0] == "i" or body.ascii else 2 ** (8 * int(prop.type[1])) - 1
            tri = decode_strips(flat, counts, restart)
            polys.append((np.full(len(tri), 3, dtype=np.int64), tri.reshape(-1)))
    sizes = np.concatenate([c for c, _ in polys]) if polys else np.zeros(0, np.int64)
    corners = np.concatenate([f for _, f in polys]) if polys else np.zeros(0, np.int64)
    if "face" not in names and "tristrips" not in names:
        why = f"a point cloud: {len(verts)} vertices and no 'face' or 'tristrips' element"
    else:
        why = f"a point cloud: {len(verts)} vertices and empty 'face'/'tristrips' elements"

    def where(i: int) -> str:
        return f"face {i}" if i < n_face else f"tristrip triangle {i - n_face}"

    return Parsed(verts, sizes, corners, where, no_faces=why, notes=notes)


def estimate(path: Path, size: int) -> tuple[int, int]:
    """(vertices, faces) from the header; a binary body too short for its counts is refused here."""
    with open(path, "rb") as fh:
        head = fh.read(1 << 20)
    try:
        header = parse_header(head)
    except _Corrupt as exc:
        raise UnreadableInput(f"{path}: {exc}") from None
    counts = {e.name: e.n for e in header.elements}
    nv, nf = counts.get("vertex", 0), counts.get("face", 0)
    if header.fmt == "ascii":
        refuse_if_short(path, "PLY", nv, nf, size)
        return nv, nf
    minimum = 0
    for e in header.elements:
        per = sum(
            int(p.type[1]) if p.count is None else int(p.count[1]) + (3 * int(p.type[1]) if e.name == "face" else 0)
            for p in e.props
        )
        minimum += e.n * per
        if size - header.body_at < minimum:
            raise UnreadableInput(
                f"{path}: truncated binary PLY: element '{e.name}' ran short: the header's counts need at least "
                f"{minimum} bytes, the body has {size - header.body_at}"
            )
    return nv, nf
