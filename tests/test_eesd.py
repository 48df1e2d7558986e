"""EESD: hand-counted tallies, naive == fast, intended vs reference (convex: equal; tori: subset)."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from strategies import clear_of_ties, closed_meshes, convex_hulls, examples, lights_for, perturbed_tori

import silcount
from silcount.mesh import shapes

# ``true`` costs counted by reading eesd.py's counted routines (point light):
# extend: M = (v1+v2)*0.5 (3A 3M), e = v2-v1 (3A), d = M-L (3A), w = d x e (6M 3A), c-M (3A),
#   side = (c-M).w (3M 2A), side > 0 (1C), e.e (3M 2A), w.w (3M 2A), ee/ww (1 div), sqrt (1),
#   EPS * root * sgn (2M), P = M + w*scale (3M 3A): 24A 23M 1C 1div 1sqrt.
EXTEND = {"add": 24, "mul": 23, "cmp": 1, "div": 1, "sqrt": 1}
RAY = {"add": 3}  # D = P - L
# Moller-Trumbore: e1, e2 (6A), p = D x e2 (6M 3A), det (3M 2A), 1/det (1 div), s = O-a (3A),
# u (3M 2A + 1M), q = s x e1 (6M 3A), v (3M 2A + 1M), t (3M 2A + 1M), u+v (1A), and the six
# compares det != 0, u >= 0, v >= 0, u+v <= 1, t > t_min, t < t_max: 24A 27M 1div 6C.
TRIANGLE = {"add": 24, "mul": 27, "div": 1, "cmp": 6}
EDGE_READS = 2 + 1 + 9 + 3  # the edge's two vertex indices, f1's far corner, 9 coordinates, the light
FACE_READS = 10  # face_start[f], [f+1]; p0 and p1 (index + 3 coordinates each)
TRIANGLE_READS = 4  # the next fan corner (index + 3 coordinates)
# literal plane of a face: face_start, 3 corner indices, 9 coordinates (13R); e1, e2 (6A);
# n = e1 x e2 (6M 3A); d = 0 - n.p0 (3M 2A + 1A); 4 writes of the plane table.
PLANE = {"read": 13, "add": 12, "mul": 9, "write": 4}
PAIR_LITERAL = {"read": 4, "mul": 3, "add": 3, "cmp": 1}  # a, b, c, d; aPx+bPy+cPz+d == 0


def tally(*parts):
    out = {"add": 0, "mul": 0, "cmp": 0, "read": 0, "write": 0}
    for times, cost in parts:
        for k, v in cost.items():
            out[k] = out.get(k, 0) + times * v
    return out


def both_engines(mesh, light, variant):
    a = silcount.detect(mesh, light, "eesd", variant, "fast")
    b = silcount.detect(mesh, light, "eesd", variant, "naive")
    assert np.array_equal(a.edges, b.edges) and np.array_equal(a.oriented, b.oriented)
    assert a.steps == b.steps and a.tally == b.tally
    for key in ("on_plane_pairs", "duplicates_in_S", "missed_edges", "extra_edges"):
        assert a.notes.get(key) == b.notes.get(key)
    return a


def test_tetrahedron_intended_by_hand():
    # Light at (5,5,5): a convex solid, so the rays beside the base's three edges escape and the
    # others meet their second face: the reference silhouette, ids 0, 1, 3.
    m = silcount.builtin_mesh("tetrahedron")
    res = both_engines(m, silcount.PointLight((5.0, 5.0, 5.0)), "intended")
    assert res.edge_ids.tolist() == [0, 1, 3] and res.agreement["missed_edges"] == 0
    # E = 6, F = T = 4: 24 edge-face pairs, 24 triangle tests
    assert res.steps == {"extend": 6, "ray": 6, "intersection": 24, "triangle_test": 24, "check_hits": 6, "add": 3}
    expected = tally(
        (6, EXTEND),
        (6, RAY),
        (6, {"read": EDGE_READS}),
        (24, {"read": FACE_READS}),
        (24, TRIANGLE),
        (24, {"read": TRIANGLE_READS, "add": 1}),
        (6, {"cmp": 1}),
        (3, {"write": 1}),
    )
    assert res.tally["true"] == expected
    assert expected == {"add": 762, "mul": 786, "cmp": 156, "read": 426, "write": 3, "div": 30, "sqrt": 6}
    # paper: extend 6(3A+1R+1W) + ray 6(3A+3M+1R+1W) + intersection 24(3M+3A+1C) + add 3(1A)
    assert res.tally["paper"] == {"add": 111, "mul": 90, "cmp": 24, "read": 12, "write": 12}


def test_quad_cube_intended_by_hand():
    # Light above the top face: its four edges; every quad is two fan triangles (T = 12).
    m = silcount.builtin_mesh("quad_cube")
    res = both_engines(m, silcount.PointLight((0.0, 0.0, 10.0)), "intended")
    assert {tuple(e) for e in res.edges.tolist()} == {(1, 3), (1, 5), (3, 7), (5, 7)}
    assert res.steps == {"extend": 12, "ray": 12, "intersection": 72, "triangle_test": 144, "check_hits": 12, "add": 4}
    expected = tally(
        (12, EXTEND),
        (12, RAY),
        (12, {"read": EDGE_READS}),
        (72, {"read": FACE_READS}),
        (144, TRIANGLE),
        (144, {"read": TRIANGLE_READS, "add": 1}),
        (12, {"cmp": 1}),
        (4, {"write": 1}),
    )
    assert res.tally["true"] == expected
    assert expected == {"add": 3924, "mul": 4164, "cmp": 888, "read": 1476, "write": 4, "div": 156, "sqrt": 12}
    assert res.tally["paper"] == {"add": 36 + 36 + 216 + 4, "mul": 36 + 216, "cmp": 72, "read": 24, "write": 24}


def test_quad_cube_literal_by_hand():
    # Light (0,0,10): every P has its edge-axis coordinate 0 and the other two moved off +-0.5, so it
    # lies on none of the six planes x, y, z = +-0.5: all 72 pairs "miss", S gets every edge 6 times.
    m = silcount.builtin_mesh("quad_cube")
    res = both_engines(m, silcount.PointLight((0.0, 0.0, 10.0)), "literal")
    assert res.n_edges == 12 and res.notes["S_length"] == 72 and res.notes["duplicates_in_S"] == 60
    assert res.notes["on_plane_pairs"] == 0 and res.agreement["extra_edges"] == 8
    assert res.steps == {"plane": 6, "extend": 12, "ray": 12, "intersection": 72, "add": 72}
    expected = tally(
        (6, PLANE), (12, EXTEND), (12, RAY), (12, {"read": EDGE_READS}), (72, PAIR_LITERAL), (72, {"write": 1})
    )
    assert res.tally["true"] == expected
    assert res.tally["paper"] == {"add": 36 + 36 + 216 + 72, "mul": 36 + 216, "cmp": 72, "read": 24, "write": 24}
    # Directional light straight down: w = d x e has no z component, so each of the 8 horizontal
    # edges' P lies exactly in its own top or bottom plane (value 0*Px + 0*Py + 1*(+-0.5) -+ 0.5 = 0);
    # the 4 vertical edges are seen end-on (w = 0, P = NaN, never 0).  72 - 8 = 64 adds.
    res = both_engines(m, silcount.DirectionalLight((0.0, 0.0, 1.0)), "literal")
    assert res.notes["on_plane_pairs"] == 8 and res.steps["add"] == 64 and res.n_edges == 12
    # directional: extend skips d = M - L (21 A), the ray is the line through P (no operation)
    assert res.tally["true"] == tally(
        (6, PLANE), (12, {**EXTEND, "add": 21}), (12, {"read": EDGE_READS}), (72, PAIR_LITERAL), (64, {"write": 1})
    )


small_meshes = closed_meshes().filter(lambda m: m.n_faces <= 80)


@settings(max_examples=examples(20), deadline=None)
@given(data=st.data(), variant=st.sampled_from(["intended", "literal"]))
def test_naive_equals_fast(data, variant):
    mesh = data.draw(small_meshes)
    both_engines(mesh, data.draw(lights_for(mesh)), variant)


@settings(max_examples=examples(30), deadline=None)
@given(data=st.data())
def test_intended_equals_reference_on_convex_hulls(data):
    mesh = data.draw(convex_hulls(max_points=60))
    light = data.draw(lights_for(mesh))
    assume(clear_of_ties(mesh, light))  # EESD near-ties: see strategies.clear_of_ties
    ref = silcount.detect(mesh, light, "reference")
    res = silcount.detect(mesh, light, "eesd", "intended")
    assert np.array_equal(res.edges, ref.edges) and np.array_equal(res.oriented, ref.oriented)
    # literal adds every edge of a closed mesh (a point off all face planes at once): extra edges
    lit = silcount.detect(mesh, light, "eesd", "literal")
    assert lit.n_edges == mesh.n_edges and lit.agreement["extra_edges"] == mesh.n_edges - ref.n_edges > 0


@settings(max_examples=examples(30), deadline=None)
@given(data=st.data())
def test_intended_is_a_subset_of_reference_on_tori(data):
    mesh = data.draw(perturbed_tori())
    light = data.draw(lights_for(mesh))
    assume(clear_of_ties(mesh, light))  # EESD near-ties: see strategies.clear_of_ties
    ref = silcount.detect(mesh, light, "reference")
    res = silcount.detect(mesh, light, "eesd", "intended")
    ref_set = {tuple(e) for e in ref.edges.tolist()}
    got = {tuple(e) for e in res.edges.tolist()}
    assert got <= ref_set
    assert res.agreement["extra_edges"] == 0 and res.agreement["missed_edges"] == len(ref_set - got)


def test_torus_self_occlusion_is_reported():
    # The built-in torus lit from a low directional light: parts of the inner rim hide silhouette
    # edges behind the near side of the ring, so EESD misses some and says how many.
    m = silcount.builtin_mesh("torus")
    light = silcount.DirectionalLight((0.1, 0.3, 1.0))
    ref = silcount.detect(m, light, "reference")
    res = silcount.detect(m, light, "eesd")
    assert set(map(tuple, res.edges.tolist())) < set(map(tuple, ref.edges.tolist()))
    assert res.agreement["missed_edges"] == ref.n_edges - res.n_edges > 0


def test_shared_meshes_subset(shared_mesh):
    for name in ("cow.obj", "fandisk.obj", "bunny.ply"):
        mesh = shared_mesh(name)
        light = silcount.PointLight(mesh.centre + 3 * mesh.bounding_radius * np.array([0.3, 0.8, 0.5]))
        ref = silcount.detect(mesh, light, "reference")
        res = silcount.detect(mesh, light, "eesd")
        missed = np.setdiff1d(ref.edge_ids, res.edge_ids)
        assert res.agreement["missed_edges"] == missed.size
        if mesh.is_watertight:
            assert np.setdiff1d(res.edge_ids, ref.edge_ids).size == 0


def test_open_triangle_soup_naive_equals_fast(shared_mesh):
    # 100 unconnected triangles: every edge is a boundary edge with one face
    soup = shared_mesh("soup.stl")
    light = silcount.PointLight(soup.centre + 3 * soup.bounding_radius * np.array([0.3, 0.8, 0.5]))
    for variant in ("intended", "literal"):
        both_engines(soup, light, variant)


def test_fast_casts_enough_rays_on_a_real_mesh(shared_mesh):
    # The fast engine settles most edges by their own faces and casts only the rest through the grid.
    # Check it against rays tested against every fan triangle (the naive loop's decisions, by the
    # same compiled test), on the cow, for the reference silhouette edges and 500 random others.
    from silcount.detectors.eesd.rays import outward_points_and_rays, ray_data, tracer

    mesh = shared_mesh("cow.obj")
    rng = np.random.default_rng(3)
    for light in (
        silcount.PointLight(mesh.centre + 2.5 * mesh.bounding_radius * np.array([0.6, 0.7, -0.4])),
        silcount.DirectionalLight((-0.3, 1.0, 0.2)),
    ):
        res = silcount.detect(mesh, light, "eesd")
        ref = silcount.detect(mesh, light, "reference")
        edges = np.union1d(ref.edge_ids, rng.choice(mesh.n_edges, 500, replace=False))
        _, origins, directions, t_min, t_max = outward_points_and_rays(mesh, light)
        rays, T = tracer(mesh), ray_data(mesh)["tri_idx"].shape[0]
        escapes = np.zeros(edges.size, dtype=bool)
        for lo in range(0, edges.size, 200):
            e = np.repeat(edges[lo : lo + 200], T)
            tri = np.tile(np.arange(T), e.size // T)
            hit = rays.hits_triangle(origins[e], directions[e], tri, t_min, t_max)
            escapes[lo : lo + 200] = ~hit.reshape(-1, T).any(axis=1)
        assert np.array_equal(np.intersect1d(res.edge_ids, edges), edges[escapes])
        assert 0 < res.n_edges < ref.n_edges
        assert res.n_edges <= res.notes["rays_cast"] < mesh.n_edges  # every silhouette edge's ray was cast


@pytest.mark.parametrize("name", ["cow.obj", "soup.stl"])
def test_own_face_pass_is_the_tracers_test_on_each_edges_own_faces(shared_mesh, name):
    # own_blocked answers, for several lights of a kind at once, whether each edge's ray meets one of its own
    # faces.  Check it, edge by edge, against RayTracer.hits_triangle (the tracer's own test, no grid) on the
    # edge's faces' fan triangles, listed here from the mesh's sides; and the outward
    # points of a subset against outward_points_and_rays, bit for bit.
    from silcount.detectors.eesd.rays import outward_points_and_rays, outward_points_of, own_blocked, ray_data, tracer

    mesh = shared_mesh(name)
    rng = np.random.default_rng(5)
    data, rays = ray_data(mesh), tracer(mesh)
    start, order = mesh.edge_sides
    owner = np.repeat(np.arange(mesh.n_edges), np.diff(start))  # each side's edge, sides in edge order
    faces = mesh.side_face[order]
    n_tri = np.diff(data["tri_start"])[faces]
    edge_of = np.repeat(owner, n_tri)  # one row per (edge, own triangle)
    tri = np.repeat(data["tri_start"][faces], n_tri) + (
        np.arange(n_tri.sum()) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri)
    )
    far = mesh.centre + 3 * mesh.bounding_radius * rng.normal(size=(3, 3))
    for lights in (
        [silcount.DirectionalLight(d) for d in rng.normal(size=(3, 3))],
        [silcount.PointLight(p) for p in far],
    ):
        got = own_blocked(mesh, lights)
        for j, light in enumerate(lights):
            _, origins, directions, t_min, t_max = outward_points_and_rays(mesh, light)
            hit = rays.hits_triangle(origins[edge_of], directions[edge_of], tri, t_min, t_max)
            expected = np.zeros(mesh.n_edges, dtype=bool)
            expected[edge_of[hit]] = True
            assert np.array_equal(got[:, j], expected)
            assert 0 < expected.sum() < mesh.n_edges or name == "soup.stl"
            some = np.sort(rng.choice(mesh.n_edges, 50, replace=False))
            assert (
                outward_points_of(mesh, light, some).tobytes()
                == outward_points_and_rays(mesh, light)[0][some].tobytes()
            )
    with pytest.raises(ValueError, match="one kind"):
        own_blocked(mesh, [silcount.DirectionalLight((0, 0, 1)), silcount.PointLight((0, 0, 9))])


def _extend_by_routine(mesh, light):
    """P of every edge by the naive engine's counted routine, on plain numbers."""
    from silcount.counting.arithmetic import Num, OpCounter
    from silcount.detectors.eesd.counted import counted_outward_point
    from silcount.detectors.eesd.rays import ray_data

    counter = OpCounter()
    directional = isinstance(light, silcount.DirectionalLight)
    L = [Num(float(x), counter) for x in (light.direction if directional else light.position)]
    num = lambda p: [Num(float(x), counter) for x in p]  # noqa: E731
    V, apex = mesh.vertices, ray_data(mesh)["apex"]
    return np.array(
        [
            [x.value for x in counted_outward_point(num(V[a]), num(V[b]), num(V[apex[i]]), L, directional)]
            for i, (a, b) in enumerate(mesh.edges)
        ]
    )


@pytest.mark.parametrize(
    "light", [silcount.PointLight((0.7, 2.9, -1.3)), silcount.DirectionalLight((-0.3, 1.0, 0.2))], ids=str
)
def test_extend_step_geometry(light):
    # EESD paper Sec. 3.3: each edge is pushed "outward" by a small amount. P = m + w * scale, with m the
    # midpoint, w = d x e (d: from the light to m, or the light's direction), |P - m| = EPS |e|, on the side
    # of the edge away from its first face's far corner c.  Checked from the geometry, not the code.
    from silcount.detectors.eesd.counted import EPS
    from silcount.detectors.eesd.rays import outward_points_and_rays, ray_data

    mesh = shapes.torus(n_major=12, n_minor=8)
    P = outward_points_and_rays(mesh, light)[0]
    v1, v2 = mesh.vertices[mesh.edges[:, 0]], mesh.vertices[mesh.edges[:, 1]]
    m, e = (v1 + v2) / 2, v2 - v1
    directional = isinstance(light, silcount.DirectionalLight)
    d = np.broadcast_to(light.direction, m.shape) if directional else m - light.position
    off, c = P - m, mesh.vertices[ray_data(mesh)["apex"]] - m
    length = np.linalg.norm(e, axis=1)
    assert np.allclose(np.linalg.norm(off, axis=1), EPS * length, rtol=1e-6, atol=0)
    assert np.allclose(np.einsum("ij,ij->i", off, e), 0, atol=1e-12)
    assert np.allclose(np.einsum("ij,ij->i", off, d), 0, atol=1e-12)
    assert (np.einsum("ij,ij->i", off, c) < 0).all()  # away from the far corner
    assert np.array_equal(P, _extend_by_routine(mesh, light))  # the fast engine's P is the routine's, bit for bit


def test_extend_step_with_the_light_in_the_faces_plane():
    # A flat grid lit from a point in its own plane: the far corner lies in the plane of the edge and the
    # light, side = 0 exactly for every edge, and the routine's tie rule (sgn = +1) decides the direction.
    from silcount.detectors.eesd.rays import outward_points_and_rays

    g = np.arange(4.0)
    x, y = np.meshgrid(g, g)
    verts = np.stack([x.ravel(), y.ravel(), np.zeros(16)], axis=1)
    quads = [[4 * i + j, 4 * i + j + 1, 4 * i + j + 5, 4 * i + j + 4] for i in range(3) for j in range(3)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    mesh = silcount.from_polygons(verts, np.array(tris))
    light = silcount.PointLight((9.0, 1.3, 0.0))  # no edge points at it: w = d x e is never 0
    P = outward_points_and_rays(mesh, light)[0]
    assert np.array_equal(P, _extend_by_routine(mesh, light))


@pytest.mark.parametrize(
    "direction, on_planes",
    [
        # dy = 0: the 4 z-edges' P stay in their x = 0 or 1 plane, the 4 x-edges' P in their z = 1 or 3 plane
        ((0.3, 0.0, 0.8), {"x": 4, "z": 4}),
        # dx = 0: the 4 z-edges' P stay in their y = 0.5 or 2.5 plane, the 4 y-edges' P in their z plane
        ((0.0, 0.6, 0.8), {"y": 4, "z": 4}),
        # a point light at y = 0.5: only the edges at y = 0.5 have d = M - L with dy = 0; their 2 z-edges
        # stay in their x plane, their 2 x-edges in their z plane (and the light itself is on y = 0.5)
        ("point (3, 0.5, 7)", {"x": 2, "z": 2}),
    ],
)
def test_literal_on_plane_rule_by_hand_on_a_box_off_the_origin(direction, on_planes):
    # EESD literal skips a face when P satisfies its plane, a Px + b Py + c Pz + d == 0.  The box
    # x 0..1, y 0.5..2.5, z 1..3 has its faces on planes with a, b, c and d of both signs and none
    # symmetric about 0 (on the unit cube a sign slip in the c or d term moves P from its own top face
    # onto the bottom one and the count stays 8).  w = d x e has a zero component exactly where the
    # light direction does, so P keeps that coordinate of its edge exactly; counted by hand above.
    v = [[x, y, z] for x in (0.0, 1.0) for y in (0.5, 2.5) for z in (1.0, 3.0)]  # shapes.quad_cube's layout
    f = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    box = silcount.from_polygons(np.array(v), f)
    light = silcount.PointLight((3.0, 0.5, 7.0)) if isinstance(direction, str) else silcount.DirectionalLight(direction)
    res = both_engines(box, light, "literal")
    on = sum(on_planes.values())
    assert res.notes["on_plane_pairs"] == on
    assert res.steps["add"] == res.notes["S_length"] == 72 - on and res.n_edges == 12


def test_literal_on_plane_rule_by_hand_on_a_box_of_face_fans():
    # The same box with each face split into 4 triangles around its centre, the centre first: every
    # triangle's first two edges have both in-plane components nonzero, so each product of the face
    # normal's cross product matters (on the quad box one of them is always 0).  Light direction
    # (0.3, 0, 0.8): w = d x e = (-0.8 ey, 0.8 ex - 0.3 ez, 0.3 ey) keeps P's x and z exactly for the
    # edges with ey = 0.  The 4 box edges along x lie in a z = 1 or 3 face, the 4 along z in an x = 0
    # or 1 face, and P stays on all 4 triangles of that face: 8 x 4 = 32 pairs.  The 8 spokes of the
    # y faces (ey = 0 too) have midpoints on no x or z face plane, and their P leaves the y plane.
    corners = [[x, y, z] for x in (0.0, 1.0) for y in (0.5, 2.5) for z in (1.0, 3.0)]
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    v = np.array(corners + [np.mean([corners[i] for i in q], axis=0) for q in quads])
    tris = [[8 + k, q[i], q[(i + 1) % 4]] for k, q in enumerate(quads) for i in range(4)]
    box = silcount.from_polygons(v, tris)
    assert (box.n_faces, box.n_edges) == (24, 36)
    res = both_engines(box, silcount.DirectionalLight((0.3, 0.0, 0.8)), "literal")
    assert res.notes["on_plane_pairs"] == 32
    assert res.steps["add"] == 36 * 24 - 32


def test_triangle_hit_ties_in_both_engines():
    # EESD's ray-triangle test is Moller-Trumbore with a closed triangle: u >= 0, v >= 0, u + v <= 1 and
    # t strictly after the origin.  Rays straight down through the edges of the triangle (0,0,0),
    # (1,0,0), (0,1,0) meet it exactly (dyadic numbers: u, v, u + v and det = 1 are exact): they hit.
    # One ulp outside, they miss; a ray starting on the triangle has t = 0 = t_min and misses.  The
    # naive engine's counted routine and the fast engine's compiled tracer must both say so.
    from silcount.counting.arithmetic import Num, OpCounter
    from silcount.detectors.eesd.counted import counted_triangle_hit
    from silcount.mesh.raytrace import RayTracer

    tri = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    tracer, counter = RayTracer(tri), OpCounter()
    num = lambda p: [Num(float(x), counter) for x in p]  # noqa: E731
    tiny = 2.0**-20
    cases = [
        ((0.25, 0.0, 1.0), True),  # v = 0
        ((0.0, 0.25, 1.0), True),  # u = 0
        ((0.5, 0.5, 1.0), True),  # u + v = 1
        ((-tiny, 0.25, 1.0), False),
        ((0.25, -tiny, 1.0), False),
        ((0.5, 0.5 + tiny, 1.0), False),
        ((0.25, 0.25, 0.0), False),  # starts on the triangle: t = 0, not after t_min = 0
    ]
    down = (0.0, 0.0, -1.0)
    for origin, expected in cases:
        counted = counted_triangle_hit(num(origin), num(down), *(num(p) for p in tri[0]), 0.0, np.inf)
        compiled = tracer.hits_triangle(np.array([origin]), np.array([down]), np.array([0]), 0.0, np.inf)[0]
        assert bool(counted) == bool(compiled) == expected, origin
