"""The mesh model: welding, the edge table, classification (counted by hand)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import silcount
from silcount.errors import InvalidMesh
from silcount.mesh.model import from_polygons


def test_quad_cube_counts():
    m = silcount.builtin_mesh("quad_cube")
    assert (m.n_vertices, m.n_faces, m.n_edges) == (8, 6, 12)
    assert m.mean_sides == 4
    assert m.is_closed and m.is_consistently_wound


def test_welding_merges_soup_and_negative_zero():
    # two triangles of a square given as a soup with a -0.0 duplicate
    v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-0.0, 0, 0], [1, 1, 0], [0, 1, 0]]
    m = from_polygons(v, [[0, 1, 2], [3, 4, 5]])
    assert m.n_vertices == 4
    assert m.n_edges == 5
    assert m.boundary_edges.size == 4


def test_edges_sorted_rows():
    m = silcount.builtin_mesh("icosahedron")
    e = m.edges
    assert np.all(e[:, 0] < e[:, 1])
    assert np.all(np.diff(e[:, 0] * m.n_vertices + e[:, 1]) > 0)


def test_collapsed_face_dropped():
    v = [[0, 0, 0], [1, 0, 0], [1, 0, 0], [0, 1, 0]]
    m = from_polygons(v, [[0, 1, 2], [0, 1, 3]])
    assert m.n_faces == 1 and m.dropped_faces == 1


def test_polygons_repeating_a_corner_are_dropped_whatever_its_position():
    # six distinct points; after welding, vertex 6 is vertex 0 again
    v = [[0, 0, 0], [1, 0, 0], [2, 1, 0], [1, 2, 0], [0, 2, 0], [-1, 1, 0], [0, 0, 0]]
    faces = [[0, 1, 2, 3], [0, 1, 0, 2], [1, 2, 3, 4, 1, 5], [0, 1, 2, 3, 4], [0, 1, 2, 3, 6], [2, 3, 6, 4, 5]]
    m = from_polygons(v, faces)
    # by hand: the second and third repeat a corner that is not their neighbour, the fifth (6 = 0) wraps
    # around to its first corner, the sixth repeats none
    assert m.dropped_faces == 3
    assert m.n_faces == 3


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(st.integers(0, 5), min_size=3, max_size=7), min_size=1, max_size=12))
def test_dropped_faces_are_those_with_a_repeated_corner(faces):
    v = np.arange(18, dtype=float).reshape(6, 3) ** 1.5  # six distinct points
    expected = sum(len(set(f)) != len(f) for f in faces)
    if expected == len(faces):
        with pytest.raises(InvalidMesh):
            from_polygons(v, faces)
        return
    assert from_polygons(v, faces).dropped_faces == expected


def test_inconsistent_winding_detected():
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    m = from_polygons(v, [[0, 1, 2], [1, 2, 3]])  # both traverse 1->2
    assert m.inconsistent_edges.size == 1


@pytest.mark.parametrize("bad", [[[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], [[0, 0, np.inf], [1, 0, 0], [0, 1, 0]]])
def test_nonfinite_rejected(bad):
    with pytest.raises(silcount.InvalidMesh):
        from_polygons(bad, [[0, 1, 2]])


def test_out_of_range_index_rejected():
    with pytest.raises(silcount.InvalidMesh, match="only 3 vertices"):
        from_polygons([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 5]])


def test_weld_tolerance_merges_near_duplicates_only_when_asked():
    # the featuretype.stl situation: the same corner stored as z = 0.0 and z = -2.7e-16
    v = [[0, 0, 0.0], [1, 0, 0], [0, 1, 0], [0, 0, -2.7e-16], [0, -1, 0]]
    faces = [[0, 1, 2], [3, 4, 1]]
    assert from_polygons(v, faces).n_vertices == 5
    merged = from_polygons(v, faces, weld_tolerance=1e-9)
    assert merged.n_vertices == 4 and merged.n_edges == 5


@pytest.mark.parametrize("n_vertices", [8, 20_000])  # a key per row fits in int64 / does not (pentagons)
def test_duplicate_faces_against_a_plain_count(n_vertices):
    from silcount.mesh.stats import duplicate_faces

    rng = np.random.default_rng(n_vertices)
    pool = rng.choice(n_vertices, size=8, replace=False)
    faces = [list(rng.choice(pool, size=int(rng.integers(3, 6)), replace=False)) for _ in range(200)]
    last = n_vertices - 3
    faces += [[i, i + 1, i + 2] for i in range(0, last + 1, 3)] + [[last, last + 1, last + 2]]
    mesh = silcount.from_polygons(rng.random((n_vertices, 3)), faces)
    assert mesh.n_vertices == n_vertices  # every vertex used: none is dropped
    seen: set = set()
    expected = 0
    for f in faces:  # a face repeats an earlier one when it has the same vertex set
        key = tuple(sorted(f))
        expected += key in seen
        seen.add(key)
    assert expected > 10 and duplicate_faces(mesh) == expected


@pytest.mark.parametrize("seed", range(5))
def test_unique_rows_is_numpys_unique_over_rows(seed):
    from silcount.mesh.model import unique_rows

    rng = np.random.default_rng(seed)
    a = np.round(rng.normal(size=(500, 3)), 1) + 0.0  # few distinct values: many repeated rows, ties per column
    a[rng.integers(0, 500, 50)] = a[rng.integers(0, 500, 50)]
    a[:3] = [[0.0, -0.0, 1.0], [-0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]  # signed zeros compare equal
    rows, first, inverse = unique_rows(a)
    expected = np.unique(a, axis=0, return_index=True, return_inverse=True)
    assert np.array_equal(rows, expected[0]) and np.array_equal(first, expected[1])
    assert np.array_equal(inverse, expected[2].reshape(-1))
    assert unique_rows(np.zeros((0, 3)))[0].shape == (0, 3)
