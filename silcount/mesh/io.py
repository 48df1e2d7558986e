"""Loading meshes from files, refusing bad input early and clearly.

OBJ, OFF and STL (ASCII and binary) are parsed here: OBJ and OFF so that
polygon faces survive as authored (the quad cube has 12 edges only as quads;
trimesh would triangulate them), STL so that a truncated binary file is told
apart from an ASCII one.  PLY, GLB and GLTF are read with trimesh after their
header has been checked here.

Every failure is one :class:`~silcount.errors.SilcountError` naming the file:

* :class:`UnreadableInput` (exit 3): missing, a directory, empty, an unknown
  extension, binary junk, a corrupt or truncated file, a file that is not a
  mesh at all;
* :class:`InvalidMesh` (exit 4): parsed, but unusable: NaN/Inf coordinates,
  faces indexing missing vertices, no faces, every face degenerate, or too
  large for the memory limit.

Memory is checked *before* parsing, from counts that are cheap to get: the
PLY/OFF header, the binary STL triangle count, the number of ``v``/``f``
lines of an OBJ or ``endfacet`` lines of an ASCII STL.  The estimate is
:data:`BYTES_PER_FACE` per face plus :data:`BYTES_PER_VERTEX` per vertex (a
generous upper bound: the mesh, its edge table and one detector's fast
engine peak at about 400 bytes per face on an icosphere of 81,920 faces,
measured with tracemalloc; OBJ parsing into Python lists adds about as much
again).  The limit is, in order, the ``max_memory`` argument, the
``SILCOUNT_MAX_MEMORY`` environment variable (bytes, or with a K/M/G/T
suffix), or the machine's available physical memory (``os.sysconf``).

Dubious but usable meshes (open, non-manifold, inconsistently wound,
zero-area or duplicate faces) load fine; ``silcount audit`` reports them.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import warnings
from pathlib import Path

import numpy as np

from silcount.errors import BadArgument, InvalidMesh, UnreadableInput
from silcount.mesh.model import Mesh, from_polygons

FORMATS = (".obj", ".off", ".ply", ".stl", ".glb", ".gltf")
BYTES_PER_FACE = 1024
BYTES_PER_VERTEX = 512
MAX_MEMORY_ENV = "SILCOUNT_MAX_MEMORY"
_CHUNK = 1 << 22


# ---- memory ------------------------------------------------------------------------------
def parse_size(text: str, what: str = "memory size") -> int:
    """``"1500"``, ``"64K"``, ``"2G"`` ... as bytes (powers of 1024)."""
    m = re.fullmatch(r"\s*(\d+(?:\.\d+)?)\s*([kKmMgGtT]?)[iI]?[bB]?\s*", str(text))
    if not m:
        raise BadArgument(f"{what} {text!r} is not a size such as 500M or 2G")
    scale = 1024 ** " KMGT".index(m.group(2).upper() or " ")
    return int(float(m.group(1)) * scale)


def memory_limit(max_memory: int | None = None) -> int:
    """The byte budget a mesh may need: argument, else ``$SILCOUNT_MAX_MEMORY``, else available RAM."""
    if max_memory is not None:
        return int(max_memory)
    env = os.environ.get(MAX_MEMORY_ENV)
    if env:
        return parse_size(env, f"${MAX_MEMORY_ENV}")
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # not POSIX: no limit we can know
        return 1 << 62


def estimate_bytes(n_vertices: int, n_faces: int) -> int:
    """Upper estimate of the memory an audit of this many vertices and faces needs."""
    return int(n_vertices) * BYTES_PER_VERTEX + int(n_faces) * BYTES_PER_FACE


def _count_in_file(path: Path, needles: tuple[bytes, ...]) -> list[int]:
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


def _refuse_if_too_large(path: Path, n_vertices: int, n_faces: int, max_memory: int | None) -> None:
    need, limit = estimate_bytes(n_vertices, n_faces), memory_limit(max_memory)
    if need > limit:
        raise InvalidMesh(
            f"{path}: too large: {n_vertices} vertices and {n_faces} faces need about "
            f"{need / 2**20:.1f} MiB, over the limit of {limit / 2**20:.1f} MiB "
            f"(set --max-memory or ${MAX_MEMORY_ENV} to raise it)"
        )


def _refuse_if_short(path: Path, fmt: str, nv: int, nf: int, size: int) -> None:
    """A text header whose counts cannot fit in the file (a vertex takes at least 6 bytes, "0 0 0\\n",
    a triangle 8, "3 0 1 2\\n") is corrupt or truncated, not a large mesh."""
    if 6 * nv + 8 * nf > size:
        raise UnreadableInput(
            f"{path}: corrupt or truncated {fmt}: the header promises {nv} vertices and "
            f"{nf} faces, more than a {size}-byte file can hold"
        )


# ---- OBJ ---------------------------------------------------------------------------------
def _text(data: bytes, path: Path, fmt: str) -> str:
    if b"\x00" in data:
        raise UnreadableInput(f"{path}: binary data, not a text {fmt} file")
    return data.decode("latin-1")


def _parse_obj(text: str, path: Path) -> tuple[np.ndarray, list[list[int]]]:
    verts: list[list[float]] = []
    faces: list[list[int]] = []
    face_line: list[int] = []
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
                face_line.append(lineno)
        except ValueError as exc:
            raise UnreadableInput(f"{path}: line {lineno}: {exc}: {raw.strip()[:60]!r}") from None
    if not verts and not faces:
        raise UnreadableInput(f"{path}: not an OBJ mesh: no vertex ('v') or face ('f') statements")
    for poly, lineno in zip(faces, face_line):
        bad = [i for i in poly if not 0 <= i < len(verts)]
        if bad:
            raise InvalidMesh(
                f"{path}: line {lineno}: a face indexes a missing vertex "
                f"({bad[0] + 1 if bad[0] >= 0 else bad[0] - len(verts)}; the file has {len(verts)} vertices)"
            )
    return np.asarray(verts, dtype=np.float64).reshape(-1, 3), faces


# ---- OFF ---------------------------------------------------------------------------------
def _off_header(text: str) -> tuple[list[list[str]], int, int]:
    tokens = [ln.split("#", 1)[0].split() for ln in text.splitlines()]
    tokens = [t for t in tokens if t]
    if not tokens or tokens[0][0] not in ("OFF", "COFF", "NOFF", "CNOFF"):
        raise ValueError("no OFF header")
    head = tokens[0][1:]
    body = tokens[1:]
    if not head:
        if not body:
            raise ValueError("no vertex and face counts")
        head = body.pop(0)
    if len(head) < 2:
        raise ValueError("the counts line needs vertex and face counts")
    nv, nf = int(head[0]), int(head[1])
    if nv < 0 or nf < 0:
        raise ValueError("negative counts")
    return body, nv, nf


def _parse_off(text: str, path: Path) -> tuple[np.ndarray, list[list[int]]]:
    try:
        body, nv, nf = _off_header(text)
        if len(body) < nv + nf:
            raise ValueError(f"the header promises {nv} vertices and {nf} faces, the file has {len(body)} records")
        rows = body[:nv]
        if any(len(r) < 3 for r in rows):
            raise ValueError("a vertex record has fewer than 3 coordinates")
        verts = np.array([[float(x) for x in r[:3]] for r in rows], dtype=np.float64).reshape(-1, 3)
        faces = []
        for rec in body[nv : nv + nf]:
            k = int(rec[0])
            if k < 0 or len(rec) < k + 1:
                raise ValueError(f"face record {' '.join(rec)[:60]!r} is short")
            faces.append([int(x) for x in rec[1 : k + 1]])
    except (ValueError, IndexError, OverflowError) as exc:
        raise UnreadableInput(f"{path}: corrupt OFF: {exc}") from None
    for k, poly in enumerate(faces):
        bad = [i for i in poly if not 0 <= i < nv]
        if bad:
            raise InvalidMesh(f"{path}: face {k} indexes vertex {bad[0]}, but the file has {nv} vertices")
    return verts, faces


# ---- STL ---------------------------------------------------------------------------------
_STL_DTYPE = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def _stl_kind(path: Path, size: int) -> tuple[str, int]:
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


def _parse_stl_binary(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray]:
    n = int(np.frombuffer(data[80:84], "<u4")[0])
    tri = np.frombuffer(data, dtype=_STL_DTYPE, count=n, offset=84)
    return tri["v"].reshape(-1, 3).astype(np.float64), np.arange(3 * n, dtype=np.int64).reshape(-1, 3)


def _parse_stl_ascii(text: str, path: Path) -> tuple[np.ndarray, np.ndarray]:
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
                verts.append([float(parts[1]), float(parts[2]), float(parts[3])])
                in_loop += 1
            elif tag == "endloop":
                if in_loop != 3:
                    raise ValueError(f"a facet loop has {in_loop} vertices, STL needs 3")
                in_loop = 0
            elif tag not in ("solid", "facet", "outer", "endfacet", "endsolid"):
                raise ValueError(f"unexpected {parts[0][:20]!r}")
        except ValueError as exc:
            raise UnreadableInput(f"{path}: line {lineno}: corrupt ASCII STL: {exc}") from None
    if in_loop or len(verts) % 3:
        raise UnreadableInput(f"{path}: truncated ASCII STL: the last facet is incomplete")
    n = len(verts) // 3
    return np.asarray(verts, dtype=np.float64).reshape(-1, 3), np.arange(3 * n, dtype=np.int64).reshape(-1, 3)


# ---- PLY (header checked here, body read by trimesh) -------------------------------------
_PLY_SIZES = {
    "char": 1,
    "uchar": 1,
    "int8": 1,
    "uint8": 1,
    "short": 2,
    "ushort": 2,
    "int16": 2,
    "uint16": 2,
    "int": 4,
    "uint": 4,
    "int32": 4,
    "uint32": 4,
    "float": 4,
    "float32": 4,
    "double": 8,
    "float64": 8,
}


def _ply_header(path: Path, size: int) -> tuple[int, int]:
    """Validate a PLY header; return (vertices, faces); refuse a binary body too short for its counts."""
    with open(path, "rb") as fh:
        head = fh.read(1 << 16)
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        raise UnreadableInput(f"{path}: not a PLY file (no 'ply' magic and 'end_header')")
    nl = head.find(b"\n", end)
    body_at = nl + 1 if nl >= 0 else len(head)
    fmt, elements = None, []
    try:
        for line in head[:end].decode("ascii").splitlines()[1:]:
            parts = line.split()
            if not parts or parts[0] in ("comment", "obj_info"):
                continue
            if parts[0] == "format":
                fmt = parts[1]
            elif parts[0] == "element":
                elements.append([parts[1], int(parts[2]), []])
            elif parts[0] == "property":
                if not elements:
                    raise ValueError("a property before any element")
                types = parts[2:4] if parts[1:2] == ["list"] else parts[1:2]
                if len(parts) < (5 if parts[1:2] == ["list"] else 3) or any(t not in _PLY_SIZES for t in types):
                    raise ValueError(f"malformed property line {line.strip()[:60]!r}")
                elements[-1][2].append(parts[1:])
    except (UnicodeDecodeError, IndexError, ValueError) as exc:
        raise UnreadableInput(f"{path}: corrupt PLY header: {exc}") from None
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise UnreadableInput(f"{path}: corrupt PLY header: unknown format {fmt!r}")
    counts = {name: n for name, n, _ in elements}
    if any(n < 0 for n in counts.values()):
        raise UnreadableInput(f"{path}: corrupt PLY header: a negative element count")
    nv, nf = counts.get("vertex", 0), counts.get("face", 0)
    if fmt == "ascii":
        _refuse_if_short(path, "PLY", nv, nf, size)
    else:
        minimum = 0
        for _, n, props in elements:
            per = 0
            for p in props:
                if p[0] == "list":
                    per += _PLY_SIZES[p[1]] + 3 * _PLY_SIZES[p[2]]
                else:
                    per += _PLY_SIZES[p[0]]
            minimum += n * per
        if size - body_at < minimum:
            raise UnreadableInput(
                f"{path}: truncated binary PLY: the header's {nv} vertices and {nf} faces "
                f"need at least {minimum} bytes, the body has {size - body_at}"
            )
    return nv, nf


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


def _load_trimesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    try:
        with _quiet_trimesh():
            loaded = trimesh.load(str(path), force="mesh", process=False)
            verts = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))), dtype=np.float64).reshape(-1, 3)
            faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))), dtype=np.int64)
    except Exception as exc:  # trimesh raises many types on corrupt input; all mean "cannot parse"
        reason = " ".join(str(exc).split())[:120] or type(exc).__name__
        raise UnreadableInput(f"{path}: cannot parse as {path.suffix[1:].upper()}: {reason}") from None
    if faces.size and (faces.ndim != 2 or faces.shape[1] < 3):
        raise UnreadableInput(f"{path}: cannot parse as {path.suffix[1:].upper()}: faces of shape {faces.shape}")
    return verts, faces


# ---- entry point -------------------------------------------------------------------------
def _size_estimate(path: Path, ext: str, size: int) -> tuple[int, int]:
    """(vertices, faces) as cheaply as the format allows, for the memory check."""
    if ext == ".obj":
        nv, nf = _count_in_file(path, (b"\nv ", b"\nf "))
        with open(path, "rb") as fh:
            first = fh.read(2)  # the first line has no newline before it
        return nv + (first == b"v "), nf + (first == b"f ")
    if ext == ".stl":
        kind, n = _stl_kind(path, size)
        if kind == "ascii":
            n = _count_in_file(path, (b"endfacet",))[0]
        return 3 * n, n
    if ext == ".ply":
        return _ply_header(path, size)
    if ext == ".off":
        with open(path, "rb") as fh:
            head = fh.read(4096).decode("latin-1")
        try:
            _, nv, nf = _off_header(head)
        except (ValueError, IndexError, OverflowError) as exc:
            raise UnreadableInput(f"{path}: corrupt OFF: {exc}") from None
        _refuse_if_short(path, "OFF", nv, nf, size)
        return nv, nf
    return size // 12, size // 12  # glb/gltf: at least 12 bytes per indexed triangle


def load_mesh(path: str | os.PathLike, max_memory: int | None = None, weld_tolerance: float = 0.0) -> Mesh:
    """Load, weld and validate a mesh file; see :mod:`silcount.mesh.model` and this module's docstring."""
    p = Path(path)
    try:
        if not p.exists():
            raise UnreadableInput(f"{p}: no such file")
        if p.is_dir():
            raise UnreadableInput(f"{p}: is a directory, not a mesh file")
        ext = p.suffix.lower()
        if ext not in FORMATS:
            raise UnreadableInput(f"{p}: unknown extension {p.suffix!r}; silcount reads {', '.join(FORMATS)}")
        size = p.stat().st_size
        if size == 0:
            raise UnreadableInput(f"{p}: the file is empty")
        nv, nf = _size_estimate(p, ext, size)
        _refuse_if_too_large(p, nv, nf, max_memory)
        if ext in (".obj", ".off", ".stl"):
            data = p.read_bytes()
            if ext == ".stl":
                kind, _ = _stl_kind(p, size)
                verts, faces = (
                    _parse_stl_binary(data, p) if kind == "binary" else _parse_stl_ascii(_text(data, p, "STL"), p)
                )
            else:
                verts, faces = (_parse_obj if ext == ".obj" else _parse_off)(_text(data, p, ext[1:].upper()), p)
        else:
            verts, faces = _load_trimesh(p)
        if ext == ".ply" and (len(verts) < nv or len(faces) < nf):
            raise UnreadableInput(
                f"{p}: truncated PLY: the header promises {nv} vertices and {nf} faces, "
                f"the body has {len(verts)} and {len(faces)}"
            )
    except PermissionError:
        raise UnreadableInput(f"{p}: permission denied") from None
    except OSError as exc:
        raise UnreadableInput(f"{p}: cannot read: {exc.strerror or exc}") from None
    except MemoryError:
        raise InvalidMesh(f"{p}: too large: ran out of memory while parsing") from None
    if len(faces) == 0:
        raise InvalidMesh(f"{p}: the mesh has no faces")
    try:
        return from_polygons(verts, faces, name=p.stem, weld_tolerance=weld_tolerance)
    except InvalidMesh as exc:
        raise InvalidMesh(f"{p}: {exc}") from None
