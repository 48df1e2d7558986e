"""Round trips through a second implementation: meshes written by trimesh load back as the same welded mesh,
and the shared real meshes (``SILCOUNT_MESH_DIR``) load as trimesh reads them.

Vertices sit on a grid of 1/16 so that every format (float32 STL and PLY, 8-digit OBJ) stores them exactly:
the comparison is exact, vertex by vertex and corner by corner.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from silcount.mesh.io import load_mesh
from silcount.mesh.model import Mesh, from_polygons

EXPORTS = {  # name -> (extension, trimesh export arguments)
    "obj": (".obj", {"file_type": "obj"}),
    "off": (".off", {"file_type": "off"}),
    "ply_ascii": (".ply", {"file_type": "ply", "encoding": "ascii"}),
    "ply_binary": (".ply", {"file_type": "ply", "encoding": "binary"}),
    "stl_ascii": (".stl", {"file_type": "stl_ascii"}),
    "stl_binary": (".stl", {"file_type": "stl"}),
    "glb": (".glb", {"file_type": "glb"}),
}


def same(a: Mesh, b: Mesh) -> None:
    assert np.array_equal(a.vertices, b.vertices)
    assert np.array_equal(a.face_start, b.face_start)
    assert np.array_equal(a.corners, b.corners)


@st.composite
def grid_hulls(draw) -> trimesh.Trimesh:
    seed = draw(st.integers(0, 2**32 - 1))
    pts = np.random.default_rng(seed).integers(-64, 65, size=(draw(st.integers(5, 30)), 3)) / 16.0
    return trimesh.convex.convex_hull(pts)


@pytest.mark.parametrize("name", sorted(EXPORTS))
@settings(max_examples=int(os.environ.get("SILCOUNT_FUZZ_EXAMPLES", "60")) // 3 or 1, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])  # fmt: skip
@given(hull=grid_hulls())
def test_a_mesh_written_by_trimesh_loads_back_the_same(tmp_path, name, hull):
    ext, kwargs = EXPORTS[name]
    path = tmp_path / f"m{ext}"
    blob = hull.export(**kwargs)
    path.write_bytes(blob.encode() if isinstance(blob, str) else blob)
    got = load_mesh(path)
    same(got, from_polygons(hull.vertices, hull.faces))
    assert got.load_warnings == () and got.is_watertight


def _shared_files() -> list[Path]:
    d = os.environ.get("SILCOUNT_MESH_DIR")
    if not d:
        return []
    return sorted(p for p in Path(d).iterdir() if p.suffix.lower() in (".obj", ".off", ".ply", ".stl"))


@pytest.mark.skipif(not os.environ.get("SILCOUNT_MESH_DIR"), reason="SILCOUNT_MESH_DIR is unset: no shared meshes")
@pytest.mark.parametrize("path", _shared_files(), ids=lambda p: p.name)
def test_the_shared_meshes_load_as_trimesh_reads_them(path):
    got = load_mesh(path)
    t = trimesh.load(str(path), force="mesh", process=False)
    if got.is_triangle_mesh:
        same(got, from_polygons(np.asarray(t.vertices), np.asarray(t.faces)))
    else:  # trimesh triangulates polygons: the same vertices, and one triangle per polygon corner beyond two
        assert np.array_equal(got.vertices, from_polygons(np.asarray(t.vertices), np.asarray(t.faces)).vertices)
        assert int((got.face_sizes - 2).sum()) == len(t.faces)
