"""The rules that decide edge cases, hand-counted, in every detector and both engines.

Each case is a mesh of one to four faces small enough to work out on paper:

* a three-face fin (a non-manifold edge) lit so that one, two and three of its faces face the light;
* faces whose facing value is exactly 0 (a point light on a face's plane, a directional light along it);
* boundary edges (a lone triangle, lit and unlit; lights inside a closed box: no face lit);
* an inconsistently wound pair whose two faces both face the light.

Expected edges are named by vertex *positions* (welding renumbers vertices), and
are worked out beside each case from the rules in the detectors' docstrings:
reference and VnV ``intended``: exactly one light-facing incident face; TA and
HSD: light-facing sides cancel in opposite-direction pairs; VnV ``literal``:
the never-reset counter is 1 after the first edge only when exactly one face
is lit; EESD: every edge whose offset point's ray meets nothing.
"""

from __future__ import annotations

import numpy as np
import pytest
from plain_rules import facing, sides

import silcount
from silcount import DirectionalLight, PointLight, from_polygons

ENGINES = ("naive", "fast")

A, B = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)
C0, C1, C2 = (0.5, 1.0, 0.0), (0.5, -1.0, 0.0), (0.5, 0.0, 1.0)


def named(res) -> set[frozenset]:
    """The result's edges as sets of two vertex positions."""
    verts = res_mesh[id(res)].vertices
    return {frozenset((tuple(verts[a]), tuple(verts[b]))) for a, b in res.edges.tolist()}


res_mesh: dict[int, silcount.Mesh] = {}


def run(mesh, light, name, variant="intended", engine="fast"):
    res = silcount.detect(mesh, light, name, variant, engine)
    res_mesh[id(res)] = mesh
    return res


def E(*pairs) -> set[frozenset]:
    return {frozenset(p) for p in pairs}


# ---- a three-face fin on the edge A-B -------------------------------------------------------------
# f0 = A B C0: normal (B-A) x (C0-A) = (0, 0, 1); f1 = B A C1: (A-B) x (C1-B) = (0, 0, 1) (f0's neighbour,
# opposite direction on A-B); f2 = A B C2: (B-A) x (C2-A) = (0, -1, 0), the fin, A -> B like f0.
FIN = from_polygons(np.array([A, B, C0, C1, C2]), [[0, 1, 2], [1, 0, 3], [0, 1, 4]], name="fin")
BOUNDARY_F0, BOUNDARY_F1, BOUNDARY_F2 = E((B, C0), (C0, A)), E((A, C1), (C1, B)), E((B, C2), (C2, A))
FIN_CASES = [
    # d = (0, 0, 1): f0, f1 lit (1 each), f2 not (0): two lit faces on A-B, so A-B is not a silhouette edge;
    # TA: f0 appends A->B, f1's B->A deletes it.
    ((0.0, 0.0, 1.0), 2, BOUNDARY_F0 | BOUNDARY_F1, BOUNDARY_F0 | BOUNDARY_F1),
    # d = (0, -1, -1): f0, f1 give -1, f2 gives 1: exactly one lit face on A-B; TA appends A->B alone.
    ((0.0, -1.0, -1.0), 1, E((A, B)) | BOUNDARY_F2, E((A, B)) | BOUNDARY_F2),
    # d = (0, -1, 1): all three lit; reference: not exactly one; TA: A->B appended, deleted, appended again.
    ((0.0, -1.0, 1.0), 3, BOUNDARY_F0 | BOUNDARY_F1 | BOUNDARY_F2, E((A, B)) | BOUNDARY_F0 | BOUNDARY_F1 | BOUNDARY_F2),
]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("direction, n_lit, by_rule, by_ta", FIN_CASES)
def test_three_face_fin(direction, n_lit, by_rule, by_ta, engine):
    light = DirectionalLight(direction)
    assert not FIN.is_closed and FIN.edge_valence.max() == 3
    for name in ("reference", "vnv"):
        assert named(run(FIN, light, name, engine=engine)) == by_rule, name
    for name in ("ta", "hsd"):  # A-B has three sides: never inside an HSD polygon
        assert named(run(FIN, light, name, engine=engine)) == by_ta, name
    lit = run(FIN, light, "vnv", "literal", engine)
    assert lit.steps["counter"] == FIN.n_edges * n_lit  # 7 edges, the counter never reset
    assert lit.edge_ids.tolist() == ([0] if n_lit == 1 else [])
    assert run(FIN, light, "reference", engine=engine).steps["add"] == len(by_rule)


# ---- facing value exactly 0 ------------------------------------------------------------------------
CUBE = silcount.builtin_mesh("quad_cube")  # [-0.5, 0.5]^3, six outward quads
X_FACE = E(*[((0.5, y0, z0), (0.5, y1, z1)) for (y0, z0), (y1, z1) in [((-0.5, -0.5), (0.5, -0.5)),
    ((0.5, -0.5), (0.5, 0.5)), ((0.5, 0.5), (-0.5, 0.5)), ((-0.5, 0.5), (-0.5, -0.5))]])  # fmt: skip
TIE_CASES = [
    # point light (5, 0, 0.5) on the top face's plane z = 0.5: top (L - p0) . n = 0 (a tie, not lit); x = +0.5: 4.5 x
    # (area) > 0 lit; y = +-0.5 and the bottom and x = -0.5 faces: negative.  One lit face, one tie.
    (PointLight((5.0, 0.0, 0.5)), 1),
    # directional (1, 0, 0): the four faces parallel to it give exactly 0; only x = +0.5 is lit.
    (DirectionalLight((1.0, 0.0, 0.0)), 4),
]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("light, ties", TIE_CASES)
def test_a_facing_value_of_exactly_zero_is_not_lit(light, ties, engine):
    for name in ("reference", "ta", "vnv", "hsd"):
        res = run(CUBE, light, name, engine=engine)
        assert named(res) == X_FACE, name
        assert res.ties == ties, name
        assert res.agreement["missed_edges"] == 0 and res.agreement["extra_edges"] == 0, name
    lit = run(CUBE, light, "vnv", "literal", engine)  # one lit face: the counter is 1 after edge 0 only
    assert lit.edge_ids.tolist() == [0] and lit.steps["counter"] == CUBE.n_edges
    ta = run(CUBE, light, "ta", engine=engine)
    assert ta.steps["search_S"] == 4 and ta.steps["add"] == 4  # only the x = +0.5 quad's four sides


def test_triangle_with_light_on_its_plane_is_a_tie_in_both_engines():
    tri = from_polygons(np.array([A, B, C0]), [[0, 1, 2]])
    for engine in ENGINES:
        for name in ("reference", "ta", "vnv", "hsd"):
            res = run(tri, PointLight((3.0, 7.0, 0.0)), name, engine=engine)
            assert res.n_edges == 0 and res.ties == 1, (name, engine)


def test_a_tie_decided_by_rounding_follows_the_papers_formula():
    # The facing value is (L - p0) . n with n = (p1 - p0) x (p2 - p0) (HSD paper Sec. VI 6.1, EESD
    # paper Sec. 5.1).  Here, found by a search, that value rounds to exactly 0.0 (a tie), while the
    # same quantities taken from p1, (L - p1) . n = 4.4e-16, or with n = (p1 - p0) x (p2 - p1),
    # -4.4e-16, do not: every engine must compute it from p0 and the two edges out of p0.
    p = np.array([[0.0, -1.6, 1.0], [1.3, -0.1, -0.4], [1.8, -0.5, 1.5]])
    light = (1.2400000000000002, -0.5599999999999999, 0.6400000000000001)

    def sub(a, b):
        return [a[k] - b[k] for k in range(3)]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    p0, p1, p2 = (list(map(float, q)) for q in p)
    assert dot(sub(light, p0), cross(sub(p1, p0), sub(p2, p0))) == 0.0  # plain Python, the papers' formula
    assert dot(sub(light, p1), cross(sub(p1, p0), sub(p2, p0))) != 0.0
    assert dot(sub(light, p0), cross(sub(p1, p0), sub(p2, p1))) != 0.0
    tri = from_polygons(p, [[0, 1, 2]])
    for engine in ENGINES:
        for name in ("reference", "ta", "vnv", "hsd", "eesd"):
            assert run(tri, PointLight(light), name, engine=engine).ties == 1, (name, engine)


# ---- boundary edges ----------------------------------------------------------------------------------
TRI = from_polygons(np.array([A, B, C0]), [[0, 1, 2]], name="triangle")  # normal (0, 0, 1)
ALL3 = E((A, B), (B, C0), (C0, A))


@pytest.mark.parametrize("engine", ENGINES)
def test_boundary_edges_of_a_lone_triangle(engine):
    up, down = PointLight((0.2, 0.3, 4.0)), PointLight((0.2, 0.3, -4.0))
    for name in ("reference", "ta", "vnv", "hsd"):
        assert named(run(TRI, up, name, engine=engine)) == ALL3, name  # its one face lit: all three edges
        assert run(TRI, down, name, engine=engine).n_edges == 0, name  # unlit: none
    # EESD never asks which way the face looks: the offset points escape on both sides
    assert named(run(TRI, up, "eesd", engine=engine)) == ALL3
    assert named(run(TRI, down, "eesd", engine=engine)) == ALL3
    # VnV literal: one lit face -> edge 0 only; no lit face -> the counter stays 0 and never reads 1
    assert run(TRI, up, "vnv", "literal", engine).edge_ids.tolist() == [0]
    dark = run(TRI, down, "vnv", "literal", engine)
    assert dark.n_edges == 0 and dark.steps["counter"] == 0 and dark.steps["add"] == 0


@pytest.mark.parametrize("engine", ENGINES)
def test_light_inside_a_closed_box_lights_nothing(engine):
    # from the centre every outward face looks away: (L - p0) . n = -0.5 x area < 0
    light = PointLight((0.0, 0.1, -0.2))
    for name in ("reference", "ta", "vnv", "hsd"):
        res = run(CUBE, light, name, engine=engine)
        assert res.n_edges == 0 and res.ties == 0, name
    lit = run(CUBE, light, "vnv", "literal", engine)
    assert lit.n_edges == 0 and lit.steps["counter"] == 0
    assert lit.notes["reset_reading_edges"] == 0


# ---- an inconsistently wound pair ----------------------------------------------------------------------
# f0 = A B C0: normal (0, 0, 1); f1 = A B C3 with C3 = (0.5, -1, 1): (B-A) x (C3-A) = (0, -1, -1), also A -> B.
C3 = (0.5, -1.0, 1.0)
FOLD = from_polygons(np.array([A, B, C0, C3]), [[0, 1, 2], [0, 1, 3]], name="fold")


@pytest.mark.parametrize("engine", ENGINES)
def test_inconsistently_wound_pair_both_lit(engine):
    assert not FOLD.is_consistently_wound
    light = DirectionalLight((0.0, -2.0, 1.0))  # f0: 1 > 0, f1: 2 - 1 = 1 > 0: both lit
    others = E((B, C0), (C0, A), (B, C3), (C3, A))
    for name in ("reference", "vnv"):  # two lit faces on A-B: not a silhouette edge
        assert named(run(FOLD, light, name, engine=engine)) == others, name
    for name in ("ta", "hsd"):  # both append A -> B (no B -> A to cancel): A-B stays, twice
        res = run(FOLD, light, name, engine=engine)
        assert named(res) == others | E((A, B)), name
        assert res.notes["duplicates_in_S"] == 1 and res.agreement["extra_edges"] == 1, name
    lit = run(FOLD, light, "vnv", "literal", engine)
    assert lit.n_edges == 0 and lit.steps["counter"] == 2 * FOLD.n_edges  # two lit faces: 2, 4, ...


@pytest.mark.parametrize("engine", ENGINES)
def test_inconsistently_wound_pair_one_lit(engine):
    light = DirectionalLight((0.0, 1.0, 0.5))  # f0: 0.5 > 0 lit; f1: -1 - 0.5 < 0
    for name in ("reference", "vnv", "ta", "hsd"):
        assert named(run(FOLD, light, name, engine=engine)) == ALL3, name


def test_a_directed_edge_repeated_while_its_first_copy_is_first_in_S():
    # TA's S holds directed edges; a search deletes the front-most copy of the reverse edge.  Faces
    # (0,1,2) and (0,1,3) both traverse 0 -> 1, so its second copy is appended while the first sits at
    # the front of S (slot 0); then (1,0,4) deletes one copy: the front-most, which moves every later
    # element; (1,0,5) deletes the last copy, and (1,0,6) must then find none and append 1 -> 0.  The
    # fast engine's replay must keep the copies of a key in order, as the naive S does, and know when
    # none is left.  All five faces are lit.
    v = np.array(
        [[0, 0, 0], [1, 0, 0], [0.5, 1, 0.2], [0.5, 1, -0.2], [0.5, -1, 0.3], [0.5, -1, -0.3], [0.5, -1, 0.6]],
        dtype=float,
    )
    mesh = from_polygons(v, [[0, 1, 2], [0, 1, 3], [1, 0, 4], [1, 0, 5], [1, 0, 6]])
    light = PointLight((0.4, 0.1, 9.0))
    for name in ("ta", "hsd"):
        for variant in ("intended", "literal"):
            fast, naive = (run(mesh, light, name, variant, engine) for engine in ("fast", "naive"))
            assert fast.tally == naive.tally and fast.steps == naive.steps, (name, variant)
            assert np.array_equal(fast.edges, naive.edges) and np.array_equal(fast.oriented, naive.oriented)
            if name == "ta" and variant == "intended":  # every face lit: S ends with 1 -> 0 and the 10 spokes
                assert fast.steps["add"] - fast.steps["delete"] == fast.notes["S_length"] == 11


# ---- which way a silhouette edge runs ------------------------------------------------------------------
def plain_oriented(mesh, edges: list[list[int]], light) -> list[tuple[int, int, int]]:
    """(a, b, k): each edge as traversed by its first light-facing side in side order (faces in order,
    corners in order), else by its first side, and that side's place k among the edge's sides, from the
    plain-Python facing flags: the rule ``Silhouette.oriented`` documents."""
    lit = facing(mesh, light)[0]
    by_edge: dict[frozenset, list[tuple[bool, int, int]]] = {}
    for p in range(mesh.n_faces):
        for a, b in sides(mesh, p):
            by_edge.setdefault(frozenset((a, b)), []).append((lit[p], a, b))
    out = []
    for a, b in edges:
        run_ = by_edge[frozenset((a, b))]
        k = next((k for k, s in enumerate(run_) if s[0]), 0)
        out.append((run_[k][1], run_[k][2], k))
    return out


# each silhouette edge of a closed, consistently wound mesh has one lit side, sometimes the first of its two
# and sometimes the second; the fin's A-B has three lit sides and the fold's A-B two; VnV literal and EESD
# also return edges with no lit side, which keep their first side's direction
ORIENT_CASES = [
    (silcount.builtin_mesh("quad_cube"), PointLight((1.7, 2.3, 3.1))),
    (silcount.builtin_mesh("tetrahedron"), DirectionalLight((0.3, -0.7, 0.4))),
    (FIN, DirectionalLight((0.0, -1.0, 1.0))),
    (FIN, DirectionalLight((0.0, -1.0, -1.0))),
    (FOLD, DirectionalLight((0.0, -2.0, 1.0))),
]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("case", range(len(ORIENT_CASES)))
def test_oriented_edges_run_along_their_first_lit_side(case, engine):
    mesh, light = ORIENT_CASES[case]
    later = 0
    for name, variant in [("reference", "intended"), ("vnv", "intended"), ("vnv", "literal"), ("eesd", "intended")]:
        res = run(mesh, light, name, variant, engine)
        expected = plain_oriented(mesh, res.edges.tolist(), light)
        assert res.n_edges > 0 or variant == "literal", name  # literal VnV: edges only when one face is lit
        assert [(a, b) for a, b in res.oriented.tolist()] == [e[:2] for e in expected], (name, variant)
        later += sum(k > 0 for *_, k in expected)
    if mesh.is_closed:  # the rule is exercised: some edges' first lit side is not their first side
        assert later > 0


# ---- naive == fast on fixed small meshes -----------------------------------------------------------------
# The hypothesis properties hold the engines equal on drawn meshes; these fixed cases keep that check in
# the fast selection `make mutation` runs (which deselects hypothesis): a point light off every axis, one
# near the origin, and a directional light.  (A Fenwick query of TA's S that skipped node 1, i.e.
# miscounted a reverse edge found in slot 1, passed every other test of the selection.)
FIXED = ["tetrahedron", "quad_cube", "triangle_cube", "icosahedron", "plane"]
FIXED_LIGHTS = [PointLight((2.3, 1.7, 3.1)), PointLight((0.05, -0.1, 0.02)), DirectionalLight((-0.4, 0.9, 0.3))]


@pytest.mark.parametrize("name", ["reference", "ta", "vnv", "hsd", "eesd"])
def test_naive_equals_fast_on_fixed_small_meshes(name):
    for mesh_name in FIXED:
        mesh = silcount.builtin_mesh(mesh_name)
        for light in FIXED_LIGHTS:
            for variant in ("intended", "literal") if name != "reference" else ("intended",):
                a, b = (run(mesh, light, name, variant, engine) for engine in ENGINES)
                where = (mesh_name, light, variant)
                assert np.array_equal(a.edges, b.edges) and np.array_equal(a.oriented, b.oriented), where
                assert a.steps == b.steps and a.tally == b.tally and a.ties == b.ties, where
                assert a.notes == {k: v for k, v in b.notes.items() if k != "rays_cast"}, where  # fast EESD's own note
