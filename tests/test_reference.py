"""The reference detector, checked against silhouettes worked out by hand."""

import numpy as np
import pytest
from hypothesis import given, settings
from strategies import examples, mesh_and_light

import silcount
from silcount.detectors.adjacency import many_edge_ids, silhouette_edge_ids


def test_quad_cube_light_on_axis_sees_square_ring():
    # Light far above +z: only the top face (z = +0.5) faces it; its 4 sides are the silhouette.
    m = silcount.builtin_mesh("quad_cube")
    res = silcount.detect(m, silcount.PointLight((0.0, 0.0, 10.0)), "reference")
    top = {tuple(sorted(e)) for e in ([1, 3], [3, 7], [7, 5], [5, 1])}  # vertices with z bit set
    assert {tuple(e) for e in res.edges.tolist()} == top
    assert res.steps == {"visibility": 6, "edge_test": 12, "add": 4}


def test_tetrahedron_vertex_light_three_edges():
    # A light beyond vertex 0 along (1,1,1): the three faces at vertex 0 face it, the base (1,3,2) does not.
    m = silcount.builtin_mesh("tetrahedron")
    res = silcount.detect(m, silcount.PointLight((5.0, 5.0, 5.0)), "reference")
    assert res.n_edges == 3
    # welding sorts vertices, so name them by position: the silhouette is the base triangle
    apex = int(np.flatnonzero((m.vertices == [1, 1, 1]).all(axis=1))[0])
    assert apex not in set(np.unique(res.edges).tolist())


def test_naive_equals_fast_on_torus():
    m = silcount.builtin_mesh("torus")
    light = silcount.PointLight((2.0, 1.0, 3.0))
    a = silcount.detect(m, light, "reference", engine="fast")
    b = silcount.detect(m, light, "reference", engine="naive")
    assert np.array_equal(a.edges, b.edges) and np.array_equal(a.oriented, b.oriented)
    assert a.tally == b.tally and a.steps == b.steps


@settings(max_examples=examples(40), deadline=None)
@given(mesh_and_light())
def test_naive_equals_fast_to_the_unit(ml):
    mesh, light = ml
    a = silcount.detect(mesh, light, "reference", engine="fast")
    b = silcount.detect(mesh, light, "reference", engine="naive")
    assert np.array_equal(a.edges, b.edges) and np.array_equal(a.oriented, b.oriented)
    assert a.tally == b.tally and a.steps == b.steps and a.ties == b.ties


# One counted_visibility, by hand (as in test_ta.py): point light 16 R 14 A 9 M 1 C; directional 3 A fewer.
VIS_POINT = {"read": 16, "add": 14, "mul": 9, "cmp": 1}


def test_tetrahedron_tally_by_hand():
    # The loops of the reference (reference._naive): per face one visibility and one flag write;
    # per edge edge_start[e], edge_start[e+1] (2 R) and count == 1 (1 C); per side (12 of them) the
    # face id and its flag (2 R) and count + (1 A); per silhouette edge one write.  Tetrahedron
    # (F 4, E 6, 12 sides), light beyond the apex: 3 faces lit, 3 silhouette edges.
    m = silcount.builtin_mesh("tetrahedron")
    for light, vis_add in ((silcount.PointLight((5.0, 5.0, 5.0)), 14), (silcount.DirectionalLight((1, 1, 1)), 11)):
        for engine in ("naive", "fast"):
            res = silcount.detect(m, light, "reference", engine=engine)
            assert res.steps == {"visibility": 4, "edge_test": 6, "add": 3}
            assert res.tally["true"] == {
                "read": 4 * 16 + 6 * 2 + 12 * 2,
                "add": 4 * vis_add + 12,
                "mul": 4 * 9,
                "cmp": 4 * 1 + 6,
                "write": 4 + 3,
            }
        (many,) = silcount.detect_many(m, [light])
        assert many.steps == res.steps and many.tally == res.tally


def test_defaults_are_the_intended_variant_and_the_fast_engine():
    from silcount.detectors import reference

    m = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.0, 0.0, 10.0))
    for res in (reference.detect(m, light), reference.detect_many(m, [light])[0]):
        assert (res.variant, res.engine) == ("intended", "fast")


def _two_tetrahedra_sharing_an_edge():
    # Two closed tetrahedra glued along the edge 0-1 only: that edge has 4 faces (the mesh's one
    # non-two-sided edge); every other edge has two.
    # (not mirror images: their faces at the shared edge must not pair up in parallel planes, or the
    # shared edge could never have exactly one lit face)
    v = [[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, 0.5, 1], [0.3, -1, 0.2], [0.6, -0.4, -1]]
    a = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    b = [[0, 1, 4], [0, 5, 1], [1, 5, 4], [0, 4, 5]]
    return silcount.from_polygons(np.array(v, dtype=float), a + b)


def test_a_single_non_manifold_edge():
    # The rule by hand, face by face: an edge is a silhouette edge iff exactly one of its faces is lit.
    m = _two_tetrahedra_sharing_an_edge()
    assert int(np.count_nonzero(m.edge_valence != 2)) == 1
    rng = np.random.default_rng(3)
    lights = [silcount.PointLight((0.3, 4.0, 2.0)), silcount.DirectionalLight((0.2, -1.0, 0.5))]
    lights += [silcount.DirectionalLight(tuple(d)) for d in rng.normal(size=(12, 3))]
    # all four faces at the shared edge have normals across x; only directions about 349-360 degrees
    # round x (in the y-z plane) light exactly one of them (face 0-2-1, normal -z)
    lights.append(silcount.DirectionalLight((0.3, 0.99, -0.1)))
    shared_edge_found = 0
    for light in lights:
        flags = []
        for f in range(m.n_faces):
            p = m.vertices[m.corners[m.face_start[f] : m.face_start[f + 1]]]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            d = light.direction if isinstance(light, silcount.DirectionalLight) else np.subtract(light.position, p[0])
            flags.append(float(np.dot(d, n)) > 0)
        expected = []
        for e, (u, w) in enumerate(m.edges.tolist()):
            faces = [f for f in range(m.n_faces) if {u, w} <= set(m.corners[m.face_start[f] : m.face_start[f + 1]])]
            if sum(flags[f] for f in faces) == 1:
                expected.append(e)
                shared_edge_found += len(faces) == 4
        for engine in ("naive", "fast"):
            assert silcount.detect(m, light, "reference", engine=engine).edge_ids.tolist() == expected
        assert silcount.detect_many(m, [light])[0].edge_ids.tolist() == expected
    assert shared_edge_found  # some light makes the four-face edge a silhouette edge


def height_field(n: int, z: np.ndarray) -> silcount.Mesh:
    """An n x n grid of unit squares, two triangles each, over the (n+1)^2 heights ``z`` (x-major)."""
    g = np.arange(n + 1, dtype=float)
    x, y = np.meshgrid(g, g, indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), z])
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    faces = np.concatenate([np.column_stack([i, i + n + 1, i + 1]), np.column_stack([i + 1, i + n + 1, i + n + 2])])
    return silcount.from_polygons(v, faces)


def test_ties_on_a_mesh_of_several_parallel_chunks():
    # 140,450 coplanar triangles (more than two of the kernels' 65,536-face chunks) and a light
    # parallel to them: every facing value is exactly 0, so every face is a tie, counted once.
    m = height_field(265, np.zeros(266 * 266))
    assert m.n_faces == 2 * 265 * 265 > 2 * 65536
    light = silcount.DirectionalLight((1.0, 0.5, 0.0))
    assert silcount.detect(m, light, "reference").ties == m.n_faces
    assert silcount.detect_many(m, [light, silcount.DirectionalLight((0.0, 0.0, 1.0))])[0].ties == m.n_faces


def strip(n_faces: int) -> silcount.Mesh:
    """A flat zigzag strip of triangles in z = 0, all wound to +z but the last, wound to -z.

    Triangle i is on vertices i, i+1, i+2; the last shares edge (F-1, F) with its neighbour, the strip's
    last two-sided edge.  Lit from +z, faces 0 .. F-2 face the light and the last does not: the
    silhouette is the F boundary edges of the lit faces and (F-1, F), so F + 1 edges.
    """
    i = np.arange(n_faces + 2)
    v = np.column_stack([0.5 * i, i % 2, np.zeros(i.size)]).astype(float)
    t = np.arange(n_faces)
    faces = np.where((t % 2 == 0)[:, None], np.column_stack([t, t + 2, t + 1]), np.column_stack([t, t + 1, t + 2]))
    faces[-1] = faces[-1][[0, 2, 1]]
    return silcount.from_polygons(v, faces)


@pytest.mark.parametrize("n_faces", [65_537, 65_538])
def test_a_last_chunk_of_one_face_or_one_edge_is_not_dropped(n_faces):
    # 65,537 faces: the faces' last chunk holds one face; 65,538 faces: 65,537 two-sided edges, so the
    # edges' last chunk holds only (F-1, F), the one edge between a lit and an unlit face
    m = strip(n_faces)
    assert m.n_faces == n_faces and int((m.edge_valence == 2).sum()) == n_faces - 1
    up, along = silcount.DirectionalLight((0.0, 0.0, 1.0)), silcount.DirectionalLight((1.0, 0.0, 0.0))
    last = int(np.flatnonzero((m.edges == [n_faces - 1, n_faces]).all(axis=1))[0])
    for res in (silcount.detect(m, up, "reference"), silcount.detect_many(m, [up, along])[0]):
        assert res.n_edges == n_faces + 1 and last in res.edge_ids.tolist() and res.ties == 0
    for res in (silcount.detect(m, along, "reference"), silcount.detect_many(m, [along, up])[0]):
        assert res.ties == n_faces and res.n_edges == 0  # along the plane: every facing value is exactly 0


def test_silhouettes_spread_over_several_parallel_chunks_match_numpy():
    # A bumpy height field of 140,450 faces and 210,145 two-sided edges: three and four of the kernels'
    # 65,536-element chunks, with silhouette edges in every chunk, so each chunk's run of ids must be
    # found and compacted in order.  Expected: the rule "exactly one lit face", from numpy's facing
    # values (L - p0) . ((p1 - p0) x (p2 - p0)) and a count of lit faces per edge.
    m = height_field(265, np.random.default_rng(5).uniform(0.0, 0.8, 266 * 266))
    assert m.n_faces > 2 * 65_536 and int((m.edge_valence == 2).sum()) > 3 * 65_536
    p0, p1, p2 = (m.vertices[m.faces[:, k]] for k in range(3))
    nrm = np.cross(p1 - p0, p2 - p0)
    lights = [
        silcount.PointLight((130.0, 120.0, 3.0)),
        silcount.DirectionalLight((0.3, -0.2, 0.25)),
        silcount.PointLight((-40.0, 300.0, 1.5)),
        silcount.DirectionalLight((-0.1, 0.35, 0.2)),  # two of each kind: each light's bit is its own
    ]
    many = silcount.detect_many(m, lights)
    raw = [ids for ids, *_ in many_edge_ids(m, lights)]  # detect_many's kernel output, before make_silhouette
    for light, res_many, raw_ids in zip(lights, many, raw, strict=True):
        d = np.asarray(light.direction)[None, :] if light.is_directional else np.asarray(light.position) - p0
        lit = (d * nrm).sum(axis=1) > 0.0
        n_lit = np.bincount(m.side_edge, weights=lit[m.side_face], minlength=m.n_edges)
        expected = np.flatnonzero(n_lit == 1)
        assert expected.size > 1000
        for res in (silcount.detect(m, light, "reference"), res_many):
            assert np.array_equal(res.edge_ids, expected), light
        # the kernels' own output, before make_silhouette sorts and de-duplicates: ascending, no repeats
        assert np.array_equal(silhouette_edge_ids(m, light), expected) and np.array_equal(raw_ids, expected)


def test_shared_facing_flags_reuse_only_the_identical_light():
    # The counted engines share the last light's flags per mesh; a light one ulp away, the same coordinates
    # as the other kind of light, or -0.0 for 0.0 must each be computed afresh and equal facing_flags.
    from silcount.detectors.adjacency import facing_flags, shared_facing_flags

    m = silcount.builtin_mesh("icosphere2")
    z = float(m.vertices[:, 2].max())
    base = (0.0, 0.3, z)
    lights = [
        silcount.DirectionalLight(base),
        silcount.PointLight(base),
        silcount.DirectionalLight((0.3, 0.0, -1.0)),
        silcount.DirectionalLight((0.0, 0.3, np.nextafter(z, np.inf))),
        silcount.DirectionalLight((-0.0, 0.3, z)),
        silcount.DirectionalLight(base),
    ]
    results = []
    for light in lights:
        flags, ties = shared_facing_flags(m, light)
        want, want_ties = facing_flags(m, light)
        assert np.array_equal(flags, want) and ties == want_ties
        results.append(flags)
    assert not np.array_equal(results[0], results[1])  # a point and a directional light differ here
    assert not np.array_equal(results[0], results[2])  # another direction: other flags
    assert shared_facing_flags(m, lights[-1])[0] is results[-1]  # the same light again: the kept result
