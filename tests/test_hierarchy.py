"""The bounded edge tree that gaussmap and cones share: its shape, its parallel walk, its overflow guard.

The detectors' answers are held to the reference in ``test_literature.py``;
this file checks the machinery those answers rest on, against plain
re-derivations (a recursive tree built by hand, a serial walk).
"""

from __future__ import annotations

import numpy as np
import pytest

import silcount
from silcount.detectors import cones, gaussmap, hierarchy, hierarchy_build, hierarchy_query, hierarchy_walk
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


@pytest.mark.parametrize("n_edges", [1, 2, 7, 9, 33, 65, 200])
@pytest.mark.parametrize("leaf_size, fanout", [(1, 2), (3, 3), (8, 4), (2, 5)])
def test_level_slots_number_each_level_from_its_first_node(n_edges, leaf_size, fanout):
    # the recursion's nodes, grouped by depth in preorder, are each level's nodes left to right
    nodes, depth = hierarchy.shape(n_edges, leaf_size, fanout)
    level_of, level_start = hierarchy.level_slots(nodes, depth, n_edges, leaf_size, fanout)
    expected = recursive_preorder(n_edges, leaf_size, fanout)
    by_level = sorted(range(len(expected)), key=lambda i: (expected[i][2], expected[i][0]))
    assert sorted(level_of.tolist()) == list(range(len(expected)))
    assert [int(level_of[i]) for i in by_level] == list(range(len(expected)))
    assert np.diff(level_start).tolist() == hierarchy.levels(n_edges, leaf_size, fanout)[::-1]


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
    tree = hierarchy_build.build_fast(mesh, scheme, 2, 2)  # deep enough for many depth-3 tasks
    for light in LIGHTS:
        serial = hierarchy_query.query_fast(mesh, tree, light)
        monkeypatch.setattr(hierarchy_query, "PARALLEL_NODES", 0)
        parallel = hierarchy_query.query_fast(mesh, tree, light)
        monkeypatch.undo()
        assert np.array_equal(serial[0], parallel[0])  # the same order: tasks are compacted in preorder
        assert serial[1] == parallel[1] and serial[2] == parallel[2]
        assert np.array_equal(np.sort(serial[0]), silhouette_edge_ids(mesh, light))


@pytest.mark.parametrize("scheme", [gaussmap.SCHEME, cones.SCHEME], ids=["gaussmap", "cones"])
def test_a_light_whose_offsets_could_overflow_opens_every_node_and_stays_exact(scheme):
    mesh = silcount.builtin_mesh("torus")
    tree = hierarchy_build.build_fast(mesh, scheme, 4, 4)
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
        fast = hierarchy_build.build_fast(mesh, scheme, 3, 3)
        naive = build_naive(mesh, scheme, 3, 3, OpCounter())
    assert (fast.rest.size > 0) == overflowing
    for name, value in vars(fast).items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(value, getattr(naive, name), equal_nan=value.dtype.kind == "f"), name
    assert fast.build_steps == naive.build_steps and fast.build_tally == naive.build_tally


# ---- the compiled query's float32 pre-test (hierarchy_walk.pretest) -------------------------------------
def _grazing(mesh):
    """Each sampled face's unit normal, a unit tangent, its ``p0`` and the offsets 2**-k (k = 18 .. 40, both
    sides) and 0 from its plane: the pre-test's float32 sign is wrong or 0 for many such lights."""
    n = mesh.face_normals / np.linalg.norm(mesh.face_normals, axis=1, keepdims=True)
    t = np.cross(n, np.roll(n, 1, axis=1) + np.array([0.1, 0.2, 0.3]))
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    eps = [0.0] + [s * 2.0**-k for k in range(18, 41, 2) for s in (1.0, -1.0)]
    return [(n[f], t[f], mesh.face_p0[f], e) for f in range(0, mesh.n_faces, max(1, mesh.n_faces // 40)) for e in eps]


def grazing_lights(mesh, scales=(1.0,)) -> list:
    """Directional lights within 2**-k of each sampled face's plane, at each scale."""
    return [silcount.DirectionalLight(sc * (t + e * n)) for n, t, _, e in _grazing(mesh) for sc in scales]


def grazing_points(mesh, reach=(3.0,)) -> list:
    """Point lights within 2**-k (times their distance) of each sampled face's plane, ``reach`` away along it."""
    return [silcount.PointLight(p + r * (t + e * n)) for n, t, p, e in _grazing(mesh) for r in reach]


def exact_everywhere(light, p0_max):
    """What :func:`hierarchy_walk.pretest` returns for a light it cannot pre-test: every face exact."""
    return np.zeros(3, dtype=np.float32), np.inf


@pytest.mark.parametrize("mesh_name", ["icosphere3", "torus", "quad_cube"])
@pytest.mark.parametrize("scheme", [gaussmap.SCHEME, cones.SCHEME], ids=["gaussmap", "cones"])
def test_the_pretest_changes_no_answer_step_or_tie(monkeypatch, mesh_name, scheme):
    # Lights grazing the faces (directional ones scaled from 2**-310, not pre-tested, to 2**290; point lights
    # from 1e-3 to 1e80 away): each query equals the one that evaluates every face exactly, in ids (order
    # included), steps and ties, and has the reference's edges.
    mesh = silcount.builtin_mesh(mesh_name)
    tree = hierarchy_build.build_fast(mesh, scheme, 2, 2)
    lights = grazing_lights(mesh, scales=(1.0, 2.0**-290, 3.0 * 2.0**290, 2.0**-310))
    lights += grazing_points(mesh, reach=(1e-3, 1.0, 3.0, 1e80))
    with_pretest = [hierarchy_query.query_fast(mesh, tree, light) for light in lights]
    monkeypatch.setattr(hierarchy_query, "pretest", exact_everywhere)
    for light, got in zip(lights, with_pretest):
        exact = hierarchy_query.query_fast(mesh, tree, light)
        assert np.array_equal(got[0], exact[0]) and got[1:] == exact[1:], light
        assert np.array_equal(np.sort(got[0]), silhouette_edge_ids(mesh, light)), light


@pytest.mark.parametrize("kind, margin", [("dir", 0.0), ("dir", 2.0**-25), ("point", 0.0), ("point", 2.0**-27)])
def test_a_loosened_pretest_margin_is_caught(monkeypatch, kind, margin):
    # The proofs need a margin of about 2**-21.8 (hierarchy_walk.pretest; the query uses 2**-20).  With none,
    # or with one near float32's typical error, a face within that error of its plane is taken as proved, and
    # some grazing light gets a wrong edge set: of these 1,000 lights, directional 194 at 0 and 7 at 2**-25;
    # point 302 at 0 and 14 at 2**-27.  Margins of 2**-24 (directional) and 2**-26 (point) are not caught:
    # the proofs' bounds are worst cases these lights do not reach.
    mesh = silcount.builtin_mesh("icosphere3")
    tree = hierarchy_build.build_fast(mesh, gaussmap.SCHEME, 2, 2)
    lights = grazing_lights(mesh) if kind == "dir" else grazing_points(mesh)

    def wrong():
        return [light for light in lights
                if not np.array_equal(np.sort(hierarchy_query.query_fast(mesh, tree, light)[0]),
                                      silhouette_edge_ids(mesh, light))]  # fmt: skip

    assert wrong() == []
    monkeypatch.setattr(hierarchy_walk, "PRETEST_MARGIN", margin)
    assert wrong()


def test_face_planes_are_within_their_stated_error_and_nan_where_untrusted():
    rng = np.random.default_rng(5)
    nrm = rng.normal(size=(2000, 3)) * np.exp2(rng.integers(-290, 290, size=(2000, 1)))
    p0 = rng.normal(size=(2000, 3)) * 100.0
    nrm[:4] = [[0.0, 0.0, 0.0], [np.inf, 0.0, 1.0], [2.0**-301, 0.0, 0.0], [2.0**301, 1.0, 0.0]]
    p0[4] = [1e3, 0.0, 0.0]  # beyond p0_max
    plane = hierarchy_build.face_planes(nrm, p0, 500.0)
    assert plane.dtype == np.float32 and plane.shape == (2000, 4) and np.isnan(plane[:5]).all()
    m = np.abs(nrm[5:]).max(axis=1, keepdims=True)
    true = (nrm[5:] / m) / np.linalg.norm(nrm[5:] / m, axis=1, keepdims=True)
    assert np.abs(plane[5:, :3].astype(np.float64) - true).max() <= 2.0**-24
    c = (p0[5:] * true).sum(axis=1)
    err = np.abs(plane[5:, 3].astype(np.float64) - c)
    assert (err <= 2.0**-24 * np.abs(c) + 2.0**-47 * np.abs(p0[5:]).sum(axis=1)).all()


def _perpendicular(v: np.ndarray, rng) -> np.ndarray:
    """Random unit vectors perpendicular to the rows of ``v``."""
    t = np.cross(v, rng.normal(size=v.shape))
    return t / np.linalg.norm(t, axis=1, keepdims=True)


@pytest.mark.parametrize("seed", range(4))
def test_every_pretest_decision_is_the_exact_sign(seed):
    # The pre-test's rule, emulated in numpy (float32 operations round as numba's do, in the same order),
    # against the exact facing value on 40 lights x 5,000 faces, most of them within 2**-10 .. 2**-45 of the
    # light's plane, at scales from 2**-280 to 2**280 (point lights' scenes: 2**-140 to 2**140): wherever the
    # pre-test decides, its sign is the exact value's and that value is not 0; and it decides most faces that
    # are not near the plane where the scales let it pre-test at all (point lights: P <= 2**100 and
    # Q >= 2**-100; this test found that a float32 offset overflows beyond that).
    rng = np.random.default_rng(seed)
    for _ in range(20):
        d = rng.normal(size=3) * 2.0 ** rng.integers(-280, 280)
        dh = d / np.linalg.norm(d)
        eps = np.where(rng.random(5000) < 0.8, rng.choice([-1.0, 1.0], 5000) * 2.0 ** -rng.uniform(10, 45, 5000), 1.0)
        nrm = (_perpendicular(np.tile(dh, (5000, 1)), rng) + eps[:, None] * dh) * 2.0 ** rng.integers(
            -280, 280, (5000, 1)
        )
        plane = hierarchy_build.face_planes(nrm, np.zeros_like(nrm), 0.0)
        l32, thr = hierarchy_walk.pretest(silcount.DirectionalLight(d), 0.0)
        u = plane[:, :3]
        w = (l32[0] * u[:, 0] + l32[1] * u[:, 1]) + l32[2] * u[:, 2]  # float32 throughout
        v = (d[0] * nrm[:, 0] + d[1] * nrm[:, 1]) + d[2] * nrm[:, 2]
        decided = np.abs(w) > thr
        assert w.dtype == np.float32 and (np.sign(w[decided]) == np.sign(v[decided])).all()
        assert (v[decided] != 0).all() and decided[eps == 1.0].mean() > 0.99
    tested = 0
    for _ in range(20):
        scale = 2.0 ** rng.integers(-140, 140)
        p0 = rng.normal(size=(5000, 3)) * scale
        L = rng.normal(size=3) * scale * 4.0
        n = rng.normal(size=(5000, 3))
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        t = _perpendicular(n, rng)
        eps = np.where(rng.random(5000) < 0.8, rng.choice([-1.0, 1.0], 5000) * 2.0 ** -rng.uniform(10, 45, 5000), 1.0)
        p0[:4000] = L - (t[:4000] + eps[:4000, None] * n[:4000]) * scale  # faces whose plane passes near L
        nrm = n * 2.0 ** rng.integers(-280, 280, (5000, 1))
        p0_max = float(np.abs(p0).max())
        plane = hierarchy_build.face_planes(nrm, p0, p0_max)
        _, thr = hierarchy_walk.pretest(silcount.PointLight(L), p0_max)
        w = ((L[0] * plane[:, 0] + L[1] * plane[:, 1]) + L[2] * plane[:, 2]) - plane[:, 3]  # float64
        a = L - p0
        v = (a[:, 0] * nrm[:, 0] + a[:, 1] * nrm[:, 1]) + a[:, 2] * nrm[:, 2]
        decided = np.abs(w) > thr
        assert w.dtype == np.float64 and (np.sign(w[decided]) == np.sign(v[decided])).all()
        assert (v[decided] != 0).all()
        if np.isfinite(thr):  # the light's and the faces' scales let it pre-test (hierarchy_walk.pretest)
            tested += 1
            assert decided[4000:].mean() > 0.99
        else:
            assert not decided.any()
    assert tested >= 5


def _interleave_by_bits(cells: list[int], bits: int) -> int:
    """A Z-order code bit by bit: bit b of cell i goes to position len(cells) * b + i."""
    return sum(((c >> b) & 1) << (len(cells) * b + i) for b in range(bits) for i, c in enumerate(cells))


def test_the_z_order_codes_are_the_bit_by_bit_interleaving():
    from silcount.detectors import morton

    rng = np.random.default_rng(3)
    for _ in range(300):
        c5 = [int(x) for x in rng.integers(0, 4096, 5)]
        c2 = [int(x) for x in rng.integers(0, 1 << 21, 2)]
        c3 = [int(x) for x in rng.integers(0, 1 << 21, 3)]
        assert int(morton.interleave5(*(np.uint64(c) for c in c5))) == _interleave_by_bits(c5, 12)
        assert int(morton.interleave2(*(np.uint64(c) for c in c2))) == _interleave_by_bits(c2, 21)
        assert int(morton.interleave3(*(np.uint64(c) for c in c3))) == _interleave_by_bits(c3, 21)
    top = [np.uint64(4095)] * 5
    assert int(morton.interleave5(*top)) == (1 << 60) - 1


def test_the_cones_frame_box_is_numpys_min_and_max():
    rng = np.random.default_rng(4)
    p = rng.normal(size=(1000, 3)) * 1e3
    p[10, 1] = np.inf
    p[20, 2] = -np.inf
    for arr in (p, np.vstack([p, [[np.nan, 0.0, 1.0]]])):
        lo, hi = cones._box(arr)
        assert np.array_equal(lo, arr.min(axis=0), equal_nan=True) and np.array_equal(
            hi, arr.max(axis=0), equal_nan=True
        )
