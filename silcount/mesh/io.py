"""Loading meshes from files: every valid file read, the rest refused early and exactly.

The readers live in :mod:`silcount.mesh.formats` (one module per format, each
saying which features of its specification it reads and which it refuses on
purpose, and why it is not trimesh's); :data:`READERS` maps each extension to
one.  ``docs/loading.md`` is the user's version of all this.

Every failure is one :class:`~silcount.errors.SilcountError` naming the file,
never with Python's own exception text:

* :class:`UnreadableInput` (exit 3): missing, a directory, empty, an unknown
  extension, binary junk, a corrupt or truncated file (saying which element
  ran short), a file that is not a mesh at all;
* :class:`InvalidMesh` (exit 4): parsed, but unusable: NaN/Inf coordinates,
  no faces (a point cloud, only ``l``/``p`` elements), no usable face, every
  face degenerate, or too large for the memory limit.

A bad face is not a bad file: faces indexing missing vertices or with fewer
than three distinct vertices are dropped, each kind with a warning giving its
count (:func:`silcount.mesh.formats.common.clean_faces`); the warnings are kept
in :attr:`Mesh.load_warnings <silcount.mesh.model.Mesh.load_warnings>` and the
audit reports them with its own.

Memory is checked *before* parsing, from counts that are cheap to get: the
PLY/OFF header, the binary STL triangle count, the number of ``v``/``f``
lines of an OBJ or ``endfacet`` lines of an ASCII STL; and once more after
parsing, from the faces actually read (a ``tristrips`` element's triangle count
is known only then).  The estimate is :data:`BYTES_PER_FACE` per face plus
:data:`BYTES_PER_VERTEX` per vertex (a generous upper bound: the mesh, its edge
table and one detector's fast engine peak at about 400 bytes per face on an
icosphere of 81,920 faces, measured with tracemalloc).  The limit is, in order,
the ``max_memory`` argument, the ``SILCOUNT_MAX_MEMORY`` environment variable
(bytes, or with a K/M/G/T suffix), or the machine's available physical memory
(``os.sysconf``).

Dubious but usable meshes (open, non-manifold, inconsistently wound,
zero-area or duplicate faces) load fine; ``silcount audit`` reports them.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

from silcount.errors import BadArgument, InvalidMesh, UnreadableInput
from silcount.mesh.formats import gltf, obj, off, ply, stl
from silcount.mesh.formats.common import Parsed, clean_faces, polygons
from silcount.mesh.model import Mesh, from_polygons


class Reader(NamedTuple):
    """A format: ``estimate(path, size) -> (vertices, faces)`` without parsing, ``read(path, data) -> Parsed``."""

    estimate: Callable[[Path, int], tuple[int, int]]
    read: Callable[[Path, bytes], Parsed]


READERS: dict[str, Reader] = {
    ".obj": Reader(obj.estimate, obj.read),
    ".off": Reader(off.estimate, off.read),
    ".ply": Reader(ply.estimate, ply.read),
    ".stl": Reader(stl.estimate, stl.read),
    ".glb": Reader(gltf.estimate, gltf.read),
    ".gltf": Reader(gltf.estimate, gltf.read),
}
FORMATS = tuple(READERS)
BYTES_PER_FACE = 1024
BYTES_PER_VERTEX = 512
MAX_MEMORY_ENV = "SILCOUNT_MAX_MEMORY"


# ---- memory ------------------------------------------------------------------------------
def parse_size(text: str, what: str = "memory size") -> int:
    """``"1500"``, ``"64K"``, ``"2G"`` ... as bytes (powers of 1024)."""
    m = re.fullmatch(r"\s*(\d+(?:\.\d+)?)\s*([kKmMgGtT]?)[iI]?[bB]?\s*", str(text))
    if not m:
        raise BadArgument(f"{what} {text!r} is not a size such as 500M or 2G")
    scale = 1024 ** " KMGT".index(m.group(2).upper() or " ")
    return int(float(m.group(1)) * scale)


def format_size(n: int) -> str:
    """``1023`` -> ``1023 bytes``, ``1536`` -> ``1.5 KiB``, ... ``TiB``: the unit that keeps the number below 1024."""
    if n < 1024:
        return f"{int(n)} byte{'' if n == 1 else 's'}"
    units, k, value = ("KiB", "MiB", "GiB", "TiB"), 0, n / 1024
    while value >= 1024 and k < len(units) - 1:
        value, k = value / 1024, k + 1
    return f"{value:.1f} {units[k]}"


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


def _refuse_if_too_large(path: Path, n_vertices: int, n_faces: int, max_memory: int | None) -> None:
    need, limit = estimate_bytes(n_vertices, n_faces), memory_limit(max_memory)
    if need > limit:
        raise InvalidMesh(
            f"{path}: too large: {n_vertices} vertices and {n_faces} faces need about "
            f"{format_size(need)}, over the limit of {format_size(limit)} "
            f"(set --max-memory or ${MAX_MEMORY_ENV} to raise it)"
        )


# ---- entry point -------------------------------------------------------------------------
def read_file(path: str | os.PathLike, max_memory: int | None = None) -> Parsed:
    """The file's geometry as read, before faces are checked and vertices welded (see :func:`load_mesh`)."""
    p = Path(path)
    try:
        p.stat()  # a missing file, a broken link or a link loop (ELOOP) raise here, each named below
        if p.is_dir():
            raise UnreadableInput(f"{p}: is a directory, not a mesh file")
        ext = p.suffix.lower()
        if ext not in READERS:
            raise UnreadableInput(f"{p}: unknown extension {p.suffix!r}; silcount reads {', '.join(FORMATS)}")
        size = p.stat().st_size
        if size == 0:
            raise UnreadableInput(f"{p}: the file is empty")
        reader = READERS[ext]
        nv, nf = reader.estimate(p, size)
        _refuse_if_too_large(p, nv, nf, max_memory)
        parsed = reader.read(p, p.read_bytes())
    except PermissionError:
        raise UnreadableInput(f"{p}: permission denied") from None
    except FileNotFoundError:
        broken = f"a symbolic link to {os.readlink(p)}, which does not exist" if p.is_symlink() else "no such file"
        raise UnreadableInput(f"{p}: {broken}") from None
    except OSError as exc:
        raise UnreadableInput(f"{p}: cannot read: {exc.strerror or 'input/output error'}") from None
    except MemoryError:
        raise InvalidMesh(f"{p}: too large: ran out of memory while parsing") from None
    _refuse_if_too_large(p, len(parsed.vertices), len(parsed.sizes), max_memory)
    return parsed


def load_mesh(path: str | os.PathLike, max_memory: int | None = None, weld_tolerance: float = 0.0) -> Mesh:
    """Load, check, weld a mesh file; see :mod:`silcount.mesh.model` and this module's docstring."""
    p = Path(path)
    parsed = read_file(p, max_memory)
    if parsed.sizes.size == 0:
        raise InvalidMesh(f"{p}: no faces: {parsed.no_faces or 'the file holds no face'}")
    sizes, corners, warnings, unusable = clean_faces(parsed)
    if unusable:
        raise InvalidMesh(f"{p}: no usable face: {unusable}")
    try:
        mesh = from_polygons(parsed.vertices, polygons(sizes, corners), name=p.stem, weld_tolerance=weld_tolerance)
    except InvalidMesh as exc:
        raise InvalidMesh(f"{p}: {exc}") from None
    except MemoryError:
        raise InvalidMesh(f"{p}: too large: ran out of memory while welding") from None
    mesh.load_warnings = tuple(warnings)
    return mesh
