"""The hierarchy query's edge ids come out ascending, sorted by its compiled radix sort (checked against numpy)."""

from __future__ import annotations

import numpy as np
import pytest

from silcount.detectors.hierarchy.query import ascending_ids


@pytest.mark.parametrize(("n", "bits"), [(0, 1), (1, 0), (5, 3), (1000, 11), (5000, 12), (20000, 22), (3000, 33)])
def test_ascending_ids_is_numpys_sort(n, bits):
    rng = np.random.default_rng(n + bits)
    ids = rng.integers(0, 1 << bits, size=n, dtype=np.int64) if bits else np.zeros(n, dtype=np.int64)
    got = ascending_ids(ids, bits)
    assert got.dtype == np.int64
    np.testing.assert_array_equal(got, np.sort(ids))


def test_the_input_is_left_as_it_was():
    ids = np.array([9, 3, 7, 1], dtype=np.int64)
    ascending_ids(ids, 4)
    np.testing.assert_array_equal(ids, [9, 3, 7, 1])


def test_query_fast_returns_the_reference_edges_ascending():
    import silcount
    from silcount.detectors.adjacency import silhouette_edge_ids
    from silcount.detectors.hierarchy import gaussmap
    from silcount.detectors.hierarchy.query import query_fast, tree_for

    mesh = silcount.builtin_mesh("torus")
    light = silcount.DirectionalLight((0.3, 0.5, 0.8))
    ids = query_fast(mesh, tree_for(mesh, gaussmap.SCHEME), light)[0]
    np.testing.assert_array_equal(ids, silhouette_edge_ids(mesh, light))  # in that order, not only as a set
