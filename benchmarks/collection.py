"""Synthesised collections: sizes drawn from a real collection's, each met by subdividing a corpus mesh.

The meshes of Thingi10K (``../shared/collections/thingi10k-sizes.csv``, its README) are not available
here, only their face counts.  A mesh of a drawn size ``F`` is synthesised from the shared corpus: of
every corpus file and midpoint subdivision level (:mod:`silcount.study.subdivide`, which moves no
point) up to :data:`MAX_FACES`, the one whose face count is nearest ``F`` on a log scale (ties: the
fewer faces, then the file's name), written as a binary little-endian PLY (doubles, ``int`` indices),
which silcount reads back exactly.  The corpus runs from 80 to 86,482 faces and each level quadruples
them, so every drawn size is met within a factor of about 1.3.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from benchmarks.common import ROOT

if TYPE_CHECKING:
    from silcount.mesh.model import Mesh

MAX_FACES = 6_000_000
THINGI = "thingi10k-sizes.csv"


def collections_dir() -> Path:
    """``$SILCOUNT_COLLECTIONS_DIR``, else ``../shared/collections`` beside the checkout."""
    return Path(os.environ.get("SILCOUNT_COLLECTIONS_DIR") or ROOT.parent / "shared" / "collections")


def thingi_sizes() -> np.ndarray:
    """The face counts of Thingi10K's 9,997 meshes, in the file's order."""
    import pandas as pd

    return pd.read_csv(collections_dir() / THINGI, usecols=["num_faces"])["num_faces"].to_numpy(np.int64)


def corpus_folder() -> Path:
    return Path(os.environ.get("SILCOUNT_CORPUS_DIR") or ROOT.parent / "shared" / "corpus")


@dataclass(frozen=True)
class Recipe:
    """A corpus file at a subdivision level: its faces after subdivision."""

    file: str
    level: int
    faces: int


@cache
def _sources() -> tuple[tuple[str, Mesh], ...]:
    """Every corpus file silcount loads, as (label, Mesh), by label."""
    from silcount.errors import SilcountError
    from silcount.mesh.io import load_mesh
    from silcount.study import find_files

    out = []
    for label, path in find_files([corpus_folder()]):
        try:
            out.append((label, load_mesh(path)))
        except SilcountError as exc:  # a corpus file silcount refuses is no source; say which
            print(f"collection: {label} left out as a source: {exc}", file=sys.stderr)
            continue
    return tuple(out)


@cache
def recipes() -> tuple[Recipe, ...]:
    """Every (corpus file, level) with at most :data:`MAX_FACES` faces."""
    from silcount.study.subdivide import faces_after

    out = []
    for label, mesh in _sources():
        level = 0
        while (faces := faces_after(mesh, level)) <= MAX_FACES:
            out.append(Recipe(label, level, faces))
            level += 1
    return tuple(out)


def nearest(faces: int) -> Recipe:
    """The recipe whose face count is nearest ``faces`` on a log scale (see the module docstring)."""
    return min(recipes(), key=lambda r: (abs(math.log(r.faces / faces)), r.faces, r.file))


def synthesise(recipe: Recipe):
    """The corpus file of ``recipe`` subdivided to its level (a :class:`silcount.Mesh`)."""
    from silcount.study.subdivide import subdivide

    mesh = dict(_sources())[recipe.file]
    return subdivide(mesh, recipe.level, max_memory=1 << 62)


def ply_bytes(mesh) -> bytes:
    """``mesh`` as a binary little-endian PLY: vertices as doubles, faces as ``uchar``-counted ``int`` lists."""
    sizes = mesh.face_sizes.astype(np.int64)
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {mesh.n_vertices}\nproperty double x\nproperty double y\nproperty double z\n"
        f"element face {mesh.n_faces}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode("ascii")
    body = np.zeros(mesh.n_faces + 4 * int(sizes.sum()), dtype=np.uint8)
    start = np.concatenate([[0], np.cumsum(1 + 4 * sizes)[:-1]])  # each face's count byte
    body[start] = sizes.astype(np.uint8)
    corner_at = np.repeat(start + 1, sizes) + 4 * (np.arange(sizes.sum()) - np.repeat(mesh.face_start[:-1], sizes))
    index_bytes = mesh.corners.astype("<i4").view(np.uint8).reshape(-1, 4)
    body[corner_at[:, None] + np.arange(4)] = index_bytes
    return header + np.ascontiguousarray(mesh.vertices, dtype="<f8").tobytes() + body.tobytes()


def write(recipe: Recipe, folder: Path, name: str) -> Path:
    """``recipe``'s mesh written to ``folder/name.ply``."""
    path = folder / f"{name}.ply"
    path.write_bytes(ply_bytes(synthesise(recipe)))
    return path


def draw(n: int, seed: int, big: int, big_faces: int = 1_000_000) -> list[int]:
    """``n`` sizes drawn (seeded, without replacement) from Thingi10K's, at least ``big`` of them of
    ``big_faces`` faces or more: the big ones drawn first from the meshes of that size, the rest from all others."""
    sizes = thingi_sizes()
    rng = np.random.default_rng(seed)
    large = np.flatnonzero(sizes >= big_faces)
    pick = list(rng.choice(large, size=min(big, large.size), replace=False))
    rest = np.setdiff1d(np.arange(sizes.size), pick)
    pick += list(rng.choice(rest, size=n - len(pick), replace=False))
    return [int(sizes[i]) for i in pick]
