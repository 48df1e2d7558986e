"""The literature's output-sensitive detectors (``gaussmap``, ``cones``): exactly the reference edges, naive == fast.

What is checked, and how:

* drawn meshes (closed, open, non-manifold, inconsistently wound, polygons,
  arbitrary triangle sets) under hard lights (``strategies.hard_lights_for``),
  for both detectors and several tree shapes: the fast edge set is the
  ``reference`` detector's, and the ``naive`` engine (counting arithmetic)
  agrees with the ``fast`` one in edges, steps, ``true`` tally, build tally
  and ties;
* fixed examples on every built-in mesh under the lights where rules decide
  (axis-aligned directional lights: ties on the cube; a light at a vertex, in
  a face's plane, inside the mesh, at the bounding box; grazing lights);
* step counts and ``true`` tallies worked out by hand on trees small enough
  to follow (the quad cube, the tetrahedron, one triangle), from the counting
  rules of :func:`silcount.detectors.hierarchy.naive.query_naive` (the loop the ``fast`` engine
  charges; ``docs/counting.md``, "gaussmap and cones");
* adversarial lights: aimed within one float64 step of every node's decision
  boundary (found by bisection on the pre-test's own arithmetic, emulated in
  numpy), in and near every face's plane, and grazing every face; the real
  trees answer every one of them exactly, and a tree whose leaf boxes leave
  out one face's plane (a loosened bound) is caught by lights aimed at it;
* output sensitivity: on the icosphere series the fraction of edges tested
  falls as the mesh grows.

Only the public API is used, plus the hooks the detectors name for this:
``hierarchy_build.build_fast``, the ``Hierarchy`` boxes and ``hierarchy_query.query_fast``.
"""

from __future__ import annotations

import dataclasses
from functools import partial

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import any_meshes, closed_meshes, examples, hard_lights_for

import silcount
from silcount.detectors.hierarchy import build as hierarchy_build
from silcount.detectors.hierarchy import cones, gaussmap
from silcount.detectors.hierarchy import tree as hierarchy
from silcount.detectors.hierarchy.query import query_fast
from silcount.mesh.model import from_polygons

DETECTORS = ("gaussmap", "cones")
SCHEMES = {"gaussmap": gaussmap.SCHEME, "cones": cones.SCHEME}
MODULES = {"gaussmap": gaussmap, "cones": cones}
SHAPES = ((1, 2), (2, 3), (8, 4))  # (leaf_size, fanout): one edge per leaf, small odd fan-out, the default
NAIVE_MAX_FACES = 200  # the naive engine is pure Python
ZERO_STEPS = dict.fromkeys(hierarchy.STEP_NAMES, 0)


def _settings(n: int):
    return settings(max_examples=examples(n), deadline=None, suppress_health_check=[HealthCheck.too_slow])


def reference_ids(mesh, light) -> np.ndarray:
    return silcount.detect(mesh, light, "reference").edge_ids


def nonzero(tally: dict[str, int]) -> dict[str, int]:
    return {k: v for k, v in tally.items() if v}


def check_exact(mesh, light, name, leaf_size, fanout, naive: bool) -> None:
    """Fast edges == reference edges (and the notes say so); naive == fast where the naive engine is affordable."""
    mod = MODULES[name]
    fast = mod.detect(mesh, light, engine="fast", leaf_size=leaf_size, fanout=fanout)
    ref = reference_ids(mesh, light)
    assert np.array_equal(fast.edge_ids, ref), (name, leaf_size, fanout, light)
    assert fast.agreement["missed_edges"] == fast.agreement["extra_edges"] == 0
    assert fast.agreement["disagreement_with_reference"] == 0
    assert fast.notes["leaf_size"] == leaf_size and fast.notes["fanout"] == fanout
    assert fast.steps["add"] == ref.size
    if naive and mesh.n_faces <= NAIVE_MAX_FACES:
        slow = mod.detect(mesh, light, engine="naive", leaf_size=leaf_size, fanout=fanout)
        assert np.array_equal(slow.edge_ids, fast.edge_ids)
        assert slow.steps == fast.steps
        assert slow.true_tally == fast.true_tally
        assert slow.notes["build"] == fast.notes["build"]
        assert slow.notes["build_steps"] == fast.notes["build_steps"]
        assert slow.ties == fast.ties


# ---- 1. properties over drawn meshes and hard lights -----------------------------------------------------------
@_settings(30)
@given(data=st.data())
def test_exact_and_naive_equals_fast_on_any_mesh_under_hard_lights(data):
    mesh = data.draw(any_meshes())
    light = data.draw(hard_lights_for(mesh))
    for name in DETECTORS:
        for leaf_size, fanout in SHAPES:
            check_exact(mesh, light, name, leaf_size, fanout, naive=True)


@_settings(15)
@given(data=st.data(), shape=st.tuples(st.integers(1, 9), st.integers(2, 7)))
def test_exact_on_larger_closed_meshes_any_tree_shape(data, shape):
    mesh = data.draw(closed_meshes())
    light = data.draw(hard_lights_for(mesh))
    for name in DETECTORS:
        check_exact(mesh, light, name, *shape, naive=False)


def test_public_entry_point_is_the_module_with_default_shape():
    mesh = silcount.builtin_mesh("icosahedron")
    light = silcount.PointLight((0.5, 2.0, 3.0))
    for name in DETECTORS:
        a = silcount.detect(mesh, light, name)
        b = MODULES[name].detect(mesh, light, "intended", "fast", hierarchy.LEAF_SIZE, hierarchy.FANOUT)
        assert a.detector == name and np.array_equal(a.edge_ids, b.edge_ids) and a.steps == b.steps
        assert a.notes["leaf_size"] == 8 and a.notes["fanout"] == 4
        assert set(a.steps) == set(hierarchy.STEP_NAMES)
        with pytest.raises(silcount.SilcountError):
            MODULES[name].detect(mesh, light, leaf_size=0)
        with pytest.raises(silcount.SilcountError):
            MODULES[name].detect(mesh, light, fanout=1)


# ---- 2. fixed examples on the built-in meshes -----------------------------------------------------------------
BUILTINS = ("tetrahedron", "quad_cube", "triangle_cube", "icosahedron", "torus", "plane", "icosphere2")


def fixed_lights(mesh) -> list:
    """The lights where the rules decide, for any mesh."""
    lights = [silcount.DirectionalLight(s * e) for e in np.eye(3) for s in (1.0, -1.0)]  # ties on the cube
    lights.append(silcount.DirectionalLight((0.3, -0.5, 0.8)))
    c = mesh.corners[mesh.face_start[0] : mesh.face_start[0] + 3]
    p0, p1, p2 = mesh.vertices[c]
    lights.append(silcount.DirectionalLight(p1 - p0))  # grazing face 0 along its first side
    lights.append(silcount.PointLight(mesh.vertices[0]))  # at a vertex
    lights.append(silcount.PointLight(mesh.vertices[-1]))
    lights.append(silcount.PointLight(p0 + 2.0 * (p1 - p0) - (p2 - p0)))  # in face 0's plane
    lights.append(silcount.PointLight(p0))  # at face 0's first vertex: every face there has a zero vector
    lights.append(silcount.PointLight(mesh.centre))  # inside
    lights.append(silcount.PointLight(mesh.vertices.max(axis=0)))  # a corner of the bounding box
    lights.append(silcount.PointLight(mesh.centre + 4.0 * max(mesh.bounding_radius, 1.0) * np.array([0.6, 0.0, 0.8])))
    return lights


@pytest.mark.parametrize("mesh_name", BUILTINS)
def test_builtin_meshes_under_fixed_lights(mesh_name):
    mesh = silcount.builtin_mesh(mesh_name)
    naive = mesh.n_faces <= NAIVE_MAX_FACES
    for light in fixed_lights(mesh):
        for name in DETECTORS:
            for leaf_size, fanout in ((1, 2), (8, 4)):
                check_exact(mesh, light, name, leaf_size, fanout, naive=naive and (leaf_size, fanout) == (1, 2))


def test_cube_axis_lights_count_face_ties_per_evaluation():
    # Light along +z on the quad cube: the four side faces have d . n = 0 exactly (ties, not lit).  The
    # reference evaluates each face once (4 ties); the hierarchy counts a tie per face evaluation.  With
    # leaf_size=12 the whole cube is one leaf, every edge is tested and each side face is evaluated once per
    # incident edge (4 each): 16 ties.  The silhouette is the top face's 4 sides either way.
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.DirectionalLight((0.0, 0.0, 1.0))
    assert silcount.detect(mesh, light, "reference").ties == 4
    for name in DETECTORS:
        for engine in ("fast", "naive"):
            res = MODULES[name].detect(mesh, light, engine=engine, leaf_size=12, fanout=4)
            assert res.ties == 16 and res.n_edges == 4


def test_faces_that_overflow_are_evaluated_exactly_and_far_lights_prune_nothing():
    # Coordinates of 1e160: one normal (1e320) overflows to inf, so that face has no plane and is evaluated
    # exactly wherever it is reached (its nodes' boxes are [-inf, inf]); another normal is 1e160, whose
    # exact products with a light at 1e307 overflow to inf (the reference's own rule, matched); a light at
    # 1.5e308 cannot be scaled by the pre-test (thr = inf): every node is opened.
    big = 1e160
    with np.errstate(over="ignore", invalid="ignore"):
        check_overflowing_mesh(big)


def check_overflowing_mesh(big: float) -> None:
    mesh = from_polygons(
        np.array([[0, 0, 0], [big, 0, 0], [0, big, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], dtype=np.float64),
        [[0, 1, 2], [3, 4, 5], [0, 3, 4], [0, 4, 1]],
    )
    assert not np.isfinite(mesh.face_normals).all()
    lights = [silcount.DirectionalLight((0, 0, 1)), silcount.DirectionalLight((0.2, -0.3, 1)),
              silcount.PointLight((0.2, 0.3, 5.0)), silcount.PointLight((1e307, 1e307, 1e307)),
              silcount.PointLight((1.5e308, -1.5e308, 1.5e308)),
              silcount.PointLight((0.0, 0.0, 1.0))]  # fmt: skip
    for light in lights:
        for name in DETECTORS:
            for shape in SHAPES:
                check_exact(mesh, light, name, *shape, naive=True)
    for name in DETECTORS:
        res = MODULES[name].detect(mesh, lights[4], leaf_size=1, fanout=2)
        assert res.notes["build_steps"]["trusted_faces"] < mesh.n_faces  # the face with an infinite normal
        # no light scale for the far light: every node reached is opened, none pruned, every face exact
        assert res.steps["node_test"] == res.notes["build_steps"]["nodes"]
        assert res.steps["node_open"] + res.steps["leaf_open"] == res.steps["node_test"] > 1
        assert res.steps["face_exact"] == res.steps["face_test"]


# ---- 3. hand counts -----------------------------------------------------------------------------------------
# The counting rules (docs/counting.md, "gaussmap and cones", the loop of hierarchy/naive.py query_naive): every
# element read is 1 R, every +/- 1 A, * 1 M, comparison 1 C; loop bookkeeping and control flow are free.
#
#   once per query      directional d: the light (3 R), its largest |coordinate| (2 C), the range (2 C),
#                       s = d 2**-e (3 M), S = |s|_1 (2 A), thr = 2**-20 S (1 M): 3 R 4 C 4 M 2 A.
#                       point L: 3 R, 2 C, Q = 3 m + 5 P (2 M, 1 A), the range (2 C), thr (1 M): 3 R 4 C 3 M 1 A
#   per node tested     directional: the box's u ends (6 R); per axis the two products s_c lo_c, s_c hi_c (2 M)
#                       and their order (1 C); the two sums (4 A); `lb > thr` (1 C): 6 R 6 M 4 C 4 A.
#                       point: also c's ends (2 R) and `- c` on both sums (2 A): 8 R 6 M 4 C 6 A
#   lb > thr            the boundary flag (1 R)
#   not lb > thr        `ub < -thr` (1 C)
#   per edge tested     `count == 1` (1 C); an edge of the other tree also its CSR range (2 R)
#   per face            its plane (3 R; a point light 4 R with c), three products (3 M), the sums (2 A; a
#                       point light 3 A with - c), `|w| > thr` (1 C), the sign (1 C), count + flag (1 A)
#   per exact value     the face through the mesh's tables (4 R), the normal (3 R), 3 M, 2 A; a point light
#                       also p0 (3 R) and L - p0 (3 A)
#   per silhouette edge the edge id (1 R) and the output slot (1 W)
#
# A directional light d = +z gives s = (0, 0, 0.5) (2**-1 d: |d|_inf = 1 = 0.5 * 2**1) and thr = 2**-21.


def run_both(mesh, light, name, leaf_size, fanout):
    return [
        MODULES[name].detect(mesh, light, engine=engine, leaf_size=leaf_size, fanout=fanout)
        for engine in ("fast", "naive")
    ]


@pytest.mark.parametrize("name", DETECTORS)
def test_quad_cube_one_leaf_by_hand(name):
    # leaf_size=12: the cube's 12 two-faced edges are one leaf, which is the root.  Its box: u in [-1, 1]^3
    # (the six unit normals +-e_k), c = 0.5 for every face (each plane 0.5 from the centre).  Light d = +z:
    # x, y products -0 and 0, z -0.5 and 0.5: lb = -0.5, ub = 0.5, neither decides: node_test 1, leaf_open 1,
    # all 12 edges tested (24 faces).  The top face's w = 0.5 and the bottom's -0.5 are decided; the four
    # side faces have w = 0: each of their 16 evaluations (4 top, 4 bottom, 8 vertical edge ends) is exact,
    # a tie.  Only the top is lit: its 4 sides are the silhouette (add 4).  Both key schemes: one leaf.
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.DirectionalLight((0.0, 0.0, 1.0))
    want = {**ZERO_STEPS, "node_test": 1, "leaf_open": 1, "edge_test": 12, "face_test": 24, "face_exact": 16,
            "add": 4}  # fmt: skip
    # true tally:
    #   R: 3 (light) + 6 (node) + 24*3 (planes) + 16*7 (exact) + 4 = 197      M: 4 + 6 + 24*3 + 16*3 = 130
    #   A: 2 + 4 + 24*3 + 16*2 = 110      C: 4 + 4 + 1 (ub) + 12 + 24*2 = 69      W: 4
    for res in run_both(mesh, light, name, 12, 4):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 197, "add": 110, "mul": 130, "cmp": 69, "write": 4}, res.engine
        assert res.ties == 16
        assert res.notes["build_steps"]["nodes"] == 1 and res.notes["build_steps"]["leaves"] == 1
        assert res.notes["edges_visited_fraction"] == 1.0
    # a point light (0, 0, 10): P = |p0|_1 = 1.5, Q = 37.5, thr = 37.5 2**-20.  The root: lb = -10 - 0.5,
    # ub = 10 - 0.5: opened.  Faces: top w = 10 - 0.5, bottom -10.5, sides 0 - 0.5 = -0.5: all decided (no
    # exact value, no tie); the same 4 silhouette edges.
    #   R: 3 + 8 + 24*4 + 4 = 111    M: 3 + 6 + 24*3 = 81    A: 1 + 6 + 24*4 = 103    C: 4 + 5 + 12 + 48 = 69
    light = silcount.PointLight((0.0, 0.0, 10.0))
    want = {**want, "face_exact": 0}
    for res in run_both(mesh, light, name, 12, 4):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 111, "add": 103, "mul": 81, "cmp": 69, "write": 4}, res.engine
        assert res.ties == 0


@pytest.mark.parametrize("name", DETECTORS)
def test_quad_cube_root_with_twelve_leaves_by_hand(name):
    # leaf_size=1, fanout=12: a root and 12 one-edge leaves (13 nodes).  Every cube edge joins two
    # perpendicular faces; a leaf's u box is the box of those two unit normals.  Light d = +z, s_z = 0.5:
    #   root: z in [-1, 1]: lb = -0.5, ub = 0.5: opened (node_open 1);
    #   the 4 top edges (+e_z and a side): z in [0, 1]: lb = 0, not > thr: opened; the top face lit, the side a
    #     tie (w = 0: exact): silhouette (add 4);
    #   the 4 vertical edges (two sides): z in [0, 0]: lb = ub = 0: neither beyond thr, opened; both faces ties;
    #   the 4 bottom edges (-e_z and a side): z in [-1, 0]: ub = 0, not < -thr: opened; the side a tie.
    # The threshold that keeps a float32 plane's sign honest leaves faces exactly edge-on undecided: all 12
    # leaves are opened, and the 16 side-face evaluations are exact ties.
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.DirectionalLight((0.0, 0.0, 1.0))
    want = {**ZERO_STEPS, "node_test": 13, "node_open": 1, "leaf_open": 12, "edge_test": 12, "face_test": 24,
            "face_exact": 16, "add": 4}  # fmt: skip
    # true tally:
    #   R: 3 + 13*6 + 24*3 + 16*7 + 4 = 269      M: 4 + 13*6 + 24*3 + 16*3 = 202      W: 4
    #   A: 2 + 13*4 + 24*3 + 16*2 = 158          C: 4 + 13*4 + 13 (ub: no node is lit) + 12 + 24*2 = 129
    for res in run_both(mesh, light, name, 1, 12):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 269, "add": 158, "mul": 202, "cmp": 129, "write": 4}, res.engine
        assert res.ties == 16
        assert res.notes["build_steps"]["nodes"] == 13 and res.notes["build_steps"]["leaves"] == 12
        assert res.notes["edges_visited_fraction"] == 1.0


@pytest.mark.parametrize("name", DETECTORS)
def test_tetrahedron_root_with_six_leaves_by_hand(name):
    # builtin tetrahedron: faces f0 (3,2,1) n (4,4,-4), f1 (3,0,2) n (4,-4,4), f2 (3,1,0) n (-4,4,4), all with
    # p0 = v3 = (1,1,1), and f3 (2,0,1) n (-4,-4,-4), p0 = (1,-1,-1); unit normals with components +-a,
    # a = 1/sqrt(3) in float32, and every offset c = a.  Edges: (0,1): f2 f3; (0,2): f1 f3; (0,3): f1 f2;
    # (1,2): f0 f3; (1,3): f0 f2; (2,3): f0 f1.  leaf_size=1, fanout=6: a root and 6 leaves.
    # Light d = +z (s_z = 0.5): f1, f2 lit (w = 0.5 a), f0, f3 not (-0.5 a); the silhouette is the 4 edges
    # with one of f1, f2: (0,1), (0,2), (1,3), (2,3).
    #   root: z in [-a, a]: lb = -0.5 a < thr, ub = 0.5 a > -thr: opened;
    #   (0,3) = f1 f2: z in [a, a]: lb = -0 + -0 + 0.5 a > thr, no boundary edge: pruned as lit;
    #   (1,2) = f0 f3: z in [-a, -a]: ub = 0 + 0 - 0.5 a < -thr: pruned as unlit;
    #   the other 4: z in [-a, a]: opened, tested (all faces decided), each a silhouette edge.
    mesh = silcount.builtin_mesh("tetrahedron")
    want = {**ZERO_STEPS, "node_test": 7, "node_lit": 1, "node_unlit": 1, "node_open": 1, "leaf_open": 4,
            "edge_test": 4, "face_test": 8, "add": 4}  # fmt: skip
    # directional true tally:
    #   R: 3 + 7*6 + 1 (boundary flag) + 8*3 + 4 = 74      M: 4 + 7*6 + 8*3 = 70      A: 2 + 7*4 + 8*3 = 54
    #   C: 4 + 7*4 + 6 (ub, the six not lit) + 4 + 8*2 = 58      W: 4
    light = silcount.DirectionalLight((0.0, 0.0, 1.0))
    for res in run_both(mesh, light, name, 1, 6):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 74, "add": 54, "mul": 70, "cmp": 58, "write": 4}, res.engine
        assert res.ties == 0
    # Point light (0, 0, 10): P = 3, Q = 45.  Faces: w = 10 u_z - a: f1, f2 9a (lit), f0, f3 -11a; the same
    # traversal: (0,3) = f1 f2: lb = -0 + -0 + 10a - a = 9a > thr: lit; (1,2) = f0 f3: ub = 0 + 0 - 10a - a
    # < -thr: unlit; the root and the other 4 leaves straddle.
    #   R: 3 + 7*8 + 1 + 8*4 + 4 = 96      M: 3 + 7*6 + 8*3 = 69      A: 1 + 7*6 + 8*4 = 75
    #   C: 4 + 7*4 + 6 + 4 + 8*2 = 58      W: 4
    light = silcount.PointLight((0.0, 0.0, 10.0))
    for res in run_both(mesh, light, name, 1, 6):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 96, "add": 75, "mul": 69, "cmp": 58, "write": 4}, res.engine
    assert np.array_equal(res.edge_ids, reference_ids(mesh, light))


@pytest.mark.parametrize("name", DETECTORS)
def test_lit_node_with_a_boundary_edge_is_opened_by_hand(name):
    # One triangle (0,0,0) (1,0,0) (0,1,0): u = (0,0,1), c = 0, three one-faced edges: the other tree, one leaf
    # (leaf_size=3), the root.  Light d = +z: lb = 0 + 0 + 0.5 > thr: every face lit, but a one-faced edge is
    # below, and a one-faced edge with its face lit is a silhouette edge: node_lit_open 1, the leaf is opened
    # and its 3 edges (1 face each) are the silhouette.
    mesh = from_polygons(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64), [[0, 1, 2]])
    light = silcount.DirectionalLight((0.0, 0.0, 1.0))
    want = {**ZERO_STEPS, "node_test": 1, "node_lit_open": 1, "leaf_open": 1, "edge_test": 3, "edge_test_other": 3,
            "face_test": 3, "add": 3}  # fmt: skip
    #   R: 3 + 6 + 1 (boundary flag) + 3*2 (CSR ranges) + 3*3 + 3 = 28      M: 4 + 6 + 3*3 = 19
    #   A: 2 + 4 + 3*3 = 15      C: 4 + 4 (lb > thr; no ub test on this path) + 3 + 3*2 = 17      W: 3
    for res in run_both(mesh, light, name, 3, 4):
        assert res.steps == want, res.engine
        assert nonzero(res.true_tally) == {"read": 28, "add": 15, "mul": 19, "cmp": 17, "write": 3}, res.engine
        assert res.n_edges == 3
    # from below (d = -z) the node is unlit (ub = -0.5 < -thr): pruned, nothing tested, no silhouette
    #   R: 3 + 6 = 9    M: 4 + 6 = 10    A: 2 + 4 = 6    C: 4 + 4 + 1 = 9
    for res in run_both(mesh, silcount.DirectionalLight((0.0, 0.0, -1.0)), name, 3, 4):
        assert res.steps == {**ZERO_STEPS, "node_test": 1, "node_unlit": 1}, res.engine
        assert nonzero(res.true_tally) == {"read": 9, "add": 6, "mul": 10, "cmp": 9}, res.engine
        assert res.n_edges == 0


# ---- 4. adversarial lights: at every node's decision boundary, in every face's plane ----------------------------
def node_decision(box: np.ndarray, light, p0_max: float) -> int:
    """A node's decision (1 lit, -1 unlit, 0 open) for ``light``, as hierarchy/tree.py derives it: the pre-test's
    arithmetic on the box's corners, in numpy (float32 operations round as the compiled ones do)."""
    s, thr = hierarchy.pretest(light, p0_max)
    lo, hi = box[:4], box[4:]
    if light.is_directional:
        a, b = s * lo[:3], s * hi[:3]  # float32
        lb = (np.minimum(a, b)[0] + np.minimum(a, b)[1]) + np.minimum(a, b)[2]
        ub = (np.maximum(a, b)[0] + np.maximum(a, b)[1]) + np.maximum(a, b)[2]
    else:
        L = np.asarray(light.vector, dtype=np.float64)
        a, b = L * lo[:3].astype(np.float64), L * hi[:3].astype(np.float64)
        lb = (np.minimum(a, b)[0] + np.minimum(a, b)[1]) + np.minimum(a, b)[2] - np.float64(hi[3])
        ub = (np.maximum(a, b)[0] + np.maximum(a, b)[1]) + np.maximum(a, b)[2] - np.float64(lo[3])
    return 1 if float(lb) > thr else (-1 if float(ub) < -thr else 0)


def bisected(make, t0: float, t1: float, decide) -> list:
    """Lights ``make(t)`` on both sides of a change of ``decide`` between ``t0`` and ``t1``, one float64 step
    apart (none if the two ends decide alike)."""
    d0, d1 = decide(make(t0)), decide(make(t1))
    if d0 == d1:
        return []
    while np.nextafter(t0, t1) != t1:
        mid = 0.5 * (t0 + t1)
        if mid in (t0, t1):
            break
        if decide(make(mid)) == d0:
            t0 = mid
        else:
            t1 = mid
    return [make(t0), make(t1)]


def aimed_lights(mesh, tree) -> list[list]:
    """Per node, lights one float64 step either side of its decision boundaries: bisected between a light that
    opens it (grazing a direction n, or on a plane of normal n) and one that decides it (along n, or far out
    along it), for n the box's middle and its two extreme corners, either way round."""
    out = []
    p0 = mesh.face_p0
    centre = p0.mean(axis=0)
    reach = 4.0 * max(mesh.bounding_radius, 1.0)
    for box in tree.box:
        mine: list = []
        out.append(mine)
        if not np.isfinite(box).all():
            continue
        lo, hi = box[:3].astype(np.float64), box[4:7].astype(np.float64)
        decide = partial(node_decision, box, p0_max=tree.p0_max)
        for corner in (0.5 * (lo + hi), lo, hi):
            if not corner.any():
                continue
            n = corner / np.linalg.norm(corner)
            t = np.cross(n, [0.3, 0.5, 0.7])
            t /= np.linalg.norm(t)
            c = 0.5 * (float(box[3]) + float(box[7]))
            foot = centre + (c - centre @ n) * n  # a point of the plane of normal n and offset c
            for sign in (1.0, -1.0):
                mine += bisected(lambda x, n=n, t=t, sign=sign: silcount.DirectionalLight(t + x * sign * n), 0.0,
                                 1e3, decide)  # fmt: skip
                mine += bisected(lambda x, n=n, foot=foot, sign=sign: silcount.PointLight(foot + x * sign * n), 0.0,
                                 reach, decide)  # fmt: skip
    return out


def face_lights(mesh) -> list:
    """Per face: lights in its plane (small integer combinations of its sides) and grazing it along its sides."""
    out = []
    for f in range(mesh.n_faces):
        c = mesh.corners[mesh.face_start[f] : mesh.face_start[f] + 3]
        p0, p1, p2 = mesh.vertices[c]
        for a, b in ((0, 0), (2, -1), (-1, 2), (3, 3), (-2, 0)):
            out.append(silcount.PointLight(p0 + a * (p1 - p0) + b * (p2 - p0)))
        out += [silcount.DirectionalLight(s * d) for d in (p1 - p0, p2 - p1, p0 - p2) if d.any() for s in (1, -1)]
    return out


def adversarial_lights(mesh, tree) -> list:
    """Axis lights, lights at every node's decision boundaries and in every face's plane; deduplicated."""
    lights = [silcount.DirectionalLight(s * e) for e in np.eye(3) for s in (1.0, -1.0)]
    lights += [light for per_node in aimed_lights(mesh, tree) for light in per_node] + face_lights(mesh)
    return list({(light.is_directional, light.vector): light for light in lights}.values())


def wrong_answers(mesh, tree, lights, refs) -> list:
    return [
        light for light, ref in zip(lights, refs) if not np.array_equal(np.sort(query_fast(mesh, tree, light)[0]), ref)
    ]


def octahedron():
    """The octahedron +-e_k."""
    v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
    faces = [[4, 0, 2], [2, 1, 4], [3, 4, 1], [0, 4, 3], [5, 2, 0], [1, 2, 5], [1, 5, 3], [0, 3, 5]]
    return from_polygons(v, faces, name="octahedron")


ADVERSARIAL_MESHES = {
    "quad_cube": lambda: silcount.builtin_mesh("quad_cube"),
    "tetrahedron": lambda: silcount.builtin_mesh("tetrahedron"),
    "triangle_cube": lambda: silcount.builtin_mesh("triangle_cube"),
    "icosahedron": lambda: silcount.builtin_mesh("icosahedron"),
    "octahedron": octahedron,
    "open_cube": lambda: from_polygons(  # the quad cube without its top: 4 boundary edges
        silcount.builtin_mesh("quad_cube").vertices,
        [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4]],
    ),
}


@pytest.mark.parametrize("mesh_name", sorted(ADVERSARIAL_MESHES))
def test_true_trees_answer_every_adversarial_light_exactly(mesh_name):
    mesh = ADVERSARIAL_MESHES[mesh_name]()
    for name in DETECTORS:
        for leaf_size, fanout in SHAPES:
            tree = hierarchy_build.build_fast(mesh, SCHEMES[name], leaf_size, fanout)
            lights = adversarial_lights(mesh, tree)
            refs = [r.edge_ids for r in silcount.detect_many(mesh, lights, "reference")]
            assert wrong_answers(mesh, tree, lights, refs) == [], (name, leaf_size, fanout)
            # the lights do land on the bounds: with one edge per leaf, at least as many nodes as leaves have
            # aimed lights a float64 step apart on both sides of one of their decisions
            if leaf_size == 1:
                aimed = sum(1 for per_node in aimed_lights(mesh, tree) if per_node)
                assert aimed >= tree.build_steps["leaves"], (name, aimed, tree.build_steps)


@_settings(8)
@given(data=st.data(), shape=st.sampled_from(SHAPES))
def test_true_trees_answer_adversarial_lights_on_any_mesh(data, shape):
    mesh = data.draw(any_meshes())
    name = data.draw(st.sampled_from(DETECTORS))
    tree = hierarchy_build.build_fast(mesh, SCHEMES[name], *shape)
    lights = adversarial_lights(mesh, tree)
    refs = [r.edge_ids for r in silcount.detect_many(mesh, lights, "reference")]
    assert wrong_answers(mesh, tree, lights, refs) == []


def loosened(tree, mesh):
    """A copy of a one-edge-per-leaf pair tree whose leaf boxes leave out each edge's second face: a bound
    that no longer holds every plane below it."""
    box = tree.box.copy()
    first_leaf = int(tree.pair_levels[-2])
    for j in range(tree.n_pairs):
        box[first_leaf + j, :4] = box[first_leaf + j, 4:] = tree.planes[2 * j]
    return dataclasses.replace(tree, box=box)


def split_lights(mesh, tree) -> list:
    """Per two-faced edge, lights that light its first face and not its second (a directional light along
    u_a - u_b; a point light off the edge along it), where the faces' planes differ."""
    out = []
    start, sides = mesh.edge_sides
    for j, e in enumerate(tree.order[: tree.n_pairs]):
        ua, ub = tree.planes[2 * j, :3].astype(np.float64), tree.planes[2 * j + 1, :3].astype(np.float64)
        if np.allclose(ua, ub):
            continue
        d = ua - ub
        out.append(silcount.DirectionalLight(d))
        mid = mesh.vertices[mesh.edges[e]].mean(axis=0)
        out.append(silcount.PointLight(mid + d * max(mesh.bounding_radius, 1.0)))
    return out


@pytest.mark.parametrize("mesh_name", ["quad_cube", "tetrahedron", "icosahedron", "octahedron"])
def test_a_loosened_leaf_bound_is_caught(mesh_name):
    # Leaf boxes that miss one face's plane "prove" an edge's faces all lit when only the first is: lights
    # that light the first face and not the second get a wrong edge set from the loosened tree (the edge is
    # missed), while the true tree answers all of them exactly.
    mesh = ADVERSARIAL_MESHES[mesh_name]()
    for name in DETECTORS:
        tree = hierarchy_build.build_fast(mesh, SCHEMES[name], 1, 2)
        lights = split_lights(mesh, tree)
        refs = [r.edge_ids for r in silcount.detect_many(mesh, lights, "reference")]
        assert lights and wrong_answers(mesh, tree, lights, refs) == []
        wrong = wrong_answers(mesh, loosened(tree, mesh), lights, refs)
        assert len(wrong) >= len(lights) // 2, (name, len(wrong), len(lights))


# ---- 5. output sensitivity ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", DETECTORS)
def test_fraction_of_edges_tested_falls_with_mesh_size(name):
    # An output-sensitive method tests far fewer than E edges on a finer mesh (the silhouette of a sphere has
    # about sqrt(F) edges): measured from steps, not time.
    for light in (silcount.DirectionalLight((0.3, 0.5, 0.8)), silcount.DirectionalLight((0.0, 0.0, 1.0))):
        fractions = []
        for k in (1, 2, 3, 4):
            mesh = silcount.builtin_mesh(f"icosphere{k}")
            res = silcount.detect(mesh, light, name)
            assert np.array_equal(res.edge_ids, reference_ids(mesh, light))
            assert res.notes["edges_visited_fraction"] == res.steps["edge_test"] / mesh.n_edges
            fractions.append(res.steps["edge_test"] / mesh.n_edges)
        assert all(b < a for a, b in zip(fractions, fractions[1:])), fractions
        assert fractions[-1] < 0.25, fractions
