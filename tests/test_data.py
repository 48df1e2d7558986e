"""The committed built-in meshes in data/ load back to the meshes silcount.mesh.shapes makes."""

from pathlib import Path

import numpy as np
import pytest

import silcount
from silcount.mesh.shapes import BUILTIN

DATA = Path(__file__).resolve().parent.parent / "data"


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_committed_file_round_trips(name):
    made = silcount.builtin_mesh(name)
    loaded = silcount.load_mesh(DATA / f"{name}.obj")
    assert np.array_equal(made.vertices, loaded.vertices)
    assert np.array_equal(made.face_start, loaded.face_start)
    assert np.array_equal(made.corners, loaded.corners)


def test_papers_table1_edge_counts_of_builtins():
    # HSD paper Table 1: Cube 12, Sphere 30, Plane 100 edges.
    assert silcount.builtin_mesh("quad_cube").n_edges == 12
    assert silcount.builtin_mesh("icosahedron").n_edges == 30
    assert silcount.builtin_mesh("plane").n_edges == 100
