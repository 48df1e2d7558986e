"""The bounded edge tree that gaussmap and cones share: its shape, its parallel walk, its overflow guard.

The detectors' answers are held to the reference in ``test_literature.py``;
this file checks the machinery those answers rest on, against plain
re-derivations (a recursive tree built by hand, a serial walk).
"""

from __future__ import annotations

import numpy as np
import pytest

import silcount
from silcount.detectors import cones, gaussmap, hierarchy, hierarchy_query
from silcount.detectors.adjacency import silhouette_edge_ids


def recursive_preorder(n_edges: int, leaf_size: int, fanout: int) -> list[tuple[int, int, int]]:
    """(edge lo, edge hi, depth) of every node, by an explicit recursion over the levels (root first)."""
    sizes = hierarchy.levels(n_edges, leaf_size, fanout)
    out: list[tuple[int, int, int]] = []

    def visit(level: int, j: int, depth: int) -> None:
        span = fanout**level
        lo_leaf, hi_leaf = j * span, min((j + 1) * span, sizes[0])
        out.append((lo_leaf * leaf_size, min(hi_leaf * leaf_size, n_edges), depth))
        if level > 0:
            for child in range(j * fanout, min((j + 1) * fanout, sizes[level - 1])):
                visit(level - 1, child, depth + 1)

    if sizes:
        visit(len(sizes) - 1, 0, 0)
    return out


@pytest.mark.parametrize("n_edges", [1, 2, 7, 8, 9, 33, 64, 65, 200])
@pytest.mark.parametrize("leaf_size, fanout", [(1, 2), (3, 3), (8, 4), (2, 5)])
def test_shape_is_the_preorder_of_the_level_tree(n_edges, leaf_size, fanout):
    nodes, depth = hierarchy.shape(n_edges, leaf_size, fanout)
    expected = recursive_preorder(n_edges, leaf_size, fanout)
    assert [tuple(r) for r in nodes[:, :2].tolist()] == [(lo, hi) for lo, hi, _ in expected]
    assert depth.tolist() == [d for _, _, d in expected]
    for i, (_, _, d) in enumerate(expected):  # skip: the first later node not inside this subtree
        after = next((j for j in range(i + 1, len(expected)) if expected[j][2] <= d), len(expected))
        assert nodes[i, 2] == after
    leaves = [i for i in range(len(nodes)) if nodes[i, 2] == i + 1]
    assert hierarchy.n_leaves(nodes) == len(leaves)
    spans = [tuple(nodes[i, :2]) for i in leaves]  # the leaves tile the edges in order
    assert spans[0][0] == 0 and spans[-1][1] == n_edges
    assert all(a[1] == b[0] for a, b in zip(spans, spans[1:]))


def test_an_empty_tree_has_no_nodes():
    nodes, depth = hierarchy.shape(0, 8, 4)
    assert nodes.shape == (0, 3) and depth.size == 0


LIGHTS = [
    silcount.DirectionalLight((0.3, 0.5, 0.8)),
    silcount.DirectionalLight((0.0, 0.0, 1.0)),
    silcount.PointLight((0.2, 3.0, 1.1)),
    silcount.PointLight((0.5, 0.5, 0.5)),
]


@pytest.mark.parametrize("mesh_name", ["torus", "icosphere3", "plane", "quad_cube"])
@pytest.mark.parametrize("scheme", [gaussmap.SCHEME, cones.SCHEME], ids=["gaussmap", "cones"])
def test_the_parallel_walk_equals_the_serial_one(monkeypatch, mesh_name, scheme):
    """Subtrees walked in parallel (forced on small trees) give the serial walk's ids in order, and its steps."""
    mesh = silcount.builtin_mesh(mesh_name)
    tree = hierarchy.build_fast(mesh, scheme, 2, 2)  # deep enough for many depth-3 tasks
    for light in LIGHTS:
        serial = hierarchy_query.query_fast(mesh, tree, light)
        monkeypatch.setattr(hierarchy_query, "_PARALLEL_NODES", 0)
        parallel = hierarchy_query.query_fast(mesh, tree, light)
        monkeypatch.undo()
        assert np.array_equal(serial[0], parallel[0])  # the same order: tasks are compacted in preorder
        assert serial[1] == parallel[1] and serial[2] == parallel[2]
        assert np.array_equal(np.sort(serial[0]), silhouette_edge_ids(mesh, light))


@pytest.mark.parametrize("scheme", [gaussmap.SCHEME, cones.SCHEME], ids=["gaussmap", "cones"])
def test_a_light_whose_offsets_could_overflow_opens_every_node_and_stays_exact(scheme):
    mesh = silcount.builtin_mesh("torus")
    tree = hierarchy.build_fast(mesh, scheme, 4, 4)
    light = silcount.PointLight((1e308, -1e308, 3.0))
    assert hierarchy.overflows(tree, light)
    ids, steps, _ = hierarchy_query.query_fast(mesh, tree, light)
    assert steps["node_test"] == tree.n_nodes  # nothing pruned
    assert steps["edge_test"] == mesh.n_edges
    assert np.array_equal(np.sort(ids), silhouette_edge_ids(mesh, light))


def test_tree_for_is_the_tree_detect_uses():
    mesh = silcount.builtin_mesh("icosahedron")
    first = hierarchy_query.tree_for(mesh, gaussmap.SCHEME)
    silcount.detect(mesh, LIGHTS[0], "gaussmap")
    assert hierarchy_query.tree_for(mesh, gaussmap.SCHEME) is first
    assert hierarchy_query.tree_for(mesh, gaussmap.SCHEME, 2, 2) is not first


@pytest.mark.parametrize("scheme", [gaussmap.SCHEME, cones.SCHEME], ids=["gaussmap", "cones"])
@pytest.mark.parametrize("overflowing", [False, True])
def test_the_compiled_build_is_the_counted_build_array_for_array(scheme, overflowing):
    # The fast build reads each edge's faces in place and frees its temporaries early; the tree it
    # returns must still be the naive build's, every array, the non-finite faces' ``rest`` included
    # (coordinates of 1e160: the first face's normal, 1e320, overflows; test_literature.py's mesh).
    from silcount.counting.arithmetic import OpCounter
    from silcount.detectors.hierarchy_naive import build_naive
    from silcount.mesh.model import from_polygons

    if overflowing:
        big = 1e160
        v = np.array([[0, 0, 0], [big, 0, 0], [0, big, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], dtype=np.float64)
        mesh = from_polygons(v, [[0, 1, 2], [3, 4, 5], [0, 3, 4], [0, 4, 1]])
    else:
        mesh = silcount.builtin_mesh("icosphere2")
    with np.errstate(over="ignore", invalid="ignore"):  # the overflowing normal, as in test_literature.py
        fast = hierarchy.build_fast(mesh, scheme, 3, 3)
        naive = build_naive(mesh, scheme, 3, 3, OpCounter())
    assert (fast.rest.size > 0) == overflowing
    for name, value in vars(fast).items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(value, getattr(naive, name), equal_nan=value.dtype.kind == "f"), name
    assert fast.build_steps == naive.build_steps and fast.build_tally == naive.build_tally
