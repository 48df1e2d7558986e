"""RayTracer against an independent brute-force solver and against hand-made cases."""

import numpy as np
import pytest

from silcount.mesh.parallel_rays import lines_any_hit
from silcount.mesh.raytrace import RayTracer, moller_trumbore


def brute_force(tris, origins, directions, t_min, t_max):
    """Every ray against every triangle by solving O + tD = a + u e1 + v e2 with numpy.linalg.

    Returns the nearest t, its triangle, and each ray's smallest distance of a
    barycentric coordinate (or of t) to its bound over all triangles, so that
    tests can leave out rays that graze an edge within rounding.
    """
    R, T = len(origins), len(tris)
    a, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    best_t = np.full(R, np.inf)
    best_i = np.full(R, -1)
    margin = np.full(R, np.inf)
    for r in range(R):
        A = np.stack([-np.broadcast_to(directions[r], (T, 3)), e1, e2], axis=2)  # (T, 3, 3) columns
        ok = np.abs(np.linalg.det(A)) > 1e-12
        sol = np.full((T, 3), np.nan)
        sol[ok] = np.linalg.solve(A[ok], (origins[r] - a[ok])[:, :, None])[:, :, 0]
        t, u, v = sol[:, 0], sol[:, 1], sol[:, 2]
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > t_min) & (t < t_max)
        margin[r] = np.nanmin(np.abs(np.concatenate([u, v, 1 - u - v, t - t_min, t_max - t])))
        if hit.any():
            j = np.flatnonzero(hit)[np.argmin(t[hit])]
            best_t[r], best_i[r] = t[j], j
    return best_t, best_i, margin


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_triangles_match_brute_force(seed):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-1, 1, size=(300, 1, 3))
    tris = centres + rng.normal(scale=0.3, size=(300, 3, 3))
    origins = rng.uniform(-2, 2, size=(400, 3))
    directions = rng.normal(size=(400, 3)) * rng.uniform(0.1, 3.0, size=(400, 1))  # not unit
    t_min, t_max = 0.05, 2.5
    rt = RayTracer(tris)
    t, i = rt.first_hit(origins, directions, t_min, t_max)
    bt, bi, margin = brute_force(tris, origins, directions, t_min, t_max)
    clear = margin > 1e-9
    assert clear.mean() > 0.95
    assert np.array_equal(i[clear], bi[clear])
    assert np.allclose(t[clear], bt[clear], rtol=1e-9) or np.array_equal(t[clear], bt[clear])
    assert (i >= 0).sum() > 50 and (i < 0).sum() > 50  # both outcomes exercised
    assert np.array_equal(rt.any_hit(origins, directions, t_min, t_max)[clear], (bi >= 0)[clear])


def test_nearest_hit_and_t_is_in_units_of_direction():
    # Two parallel squares' triangles at z = 1 and z = 3; a ray from z = 0 upwards with |D| = 2.
    tri_lo = [[-1, -1, 1], [1, -1, 1], [0, 1, 1]]
    tri_hi = [[-1, -1, 3], [1, -1, 3], [0, 1, 3]]
    rt = RayTracer(np.array([tri_hi, tri_lo], dtype=float))
    t, i = rt.first_hit([[0, 0, 0]], [[0, 0, 2]])
    assert i.tolist() == [1] and t.tolist() == [0.5]  # z = 1 at t = 1/2
    t, i = rt.first_hit([[0, 0, 0]], [[0, 0, 2]], t_min=0.5)  # open range: z = 1 excluded
    assert i.tolist() == [0] and t.tolist() == [1.5]
    assert rt.any_hit([[0, 0, 0]], [[0, 0, 2]], t_max=0.5).tolist() == [False]
    assert rt.any_hit([[0, 0, 0]], [[0, 0, 2]], t_max=0.5000001).tolist() == [True]
    assert rt.any_hit([[0, 0, 0]], [[0, 0, 2]], ignore=[1]).tolist() == [True]  # the upper one
    assert rt.any_hit([[0, 0, 0]], [[0, 0, -2]]).tolist() == [False]  # pointing away
    assert rt.any_hit([[0, 0, 0]], [[0, 0, -2]], t_min=-np.inf).tolist() == [True]  # the whole line


def test_ray_through_shared_edge_hits_one_of_the_two():
    # The unit square split along its diagonal (0,0)-(1,1) into two triangles; rays along -z
    # through points of the diagonal (and of the shared vertices) must hit one of them.
    a, b, c, d = [0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]
    rt = RayTracer(np.array([[a, b, c], [a, c, d]], dtype=float))
    s = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    origins = np.stack([s, s, np.full_like(s, 5.0)], axis=1)
    t, i = rt.first_hit(origins, np.tile([0.0, 0.0, -1.0], (5, 1)))
    assert np.all(i >= 0) and np.all(t == 5.0)
    # and across the square's outer edge x = 1 it is inclusive too, just outside it misses
    assert rt.any_hit([[1.0, 0.5, 5.0], [1.0 + 1e-12, 0.5, 5.0]], [[0, 0, -1], [0, 0, -1]]).tolist() == [True, False]


def test_grazing_ray_in_the_triangle_plane_misses():
    rt = RayTracer(np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], dtype=float))
    # det == 0 exactly: the ray runs inside the plane z = 0, across the triangle
    assert rt.any_hit([[-1.0, 0.25, 0.0]], [[1.0, 0.0, 0.0]]).tolist() == [False]


def test_no_hit_conventions_and_degenerate_input():
    rt = RayTracer(np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], dtype=float))
    t, i = rt.first_hit([[5, 5, 5], [np.nan, 0, 0], [0.1, 0.1, 1]], [[1, 0, 0], [0, 0, -1], [0, 0, 0]])
    assert t.tolist() == [np.inf] * 3 and i.tolist() == [-1] * 3
    assert RayTracer(np.zeros((0, 3, 3))).any_hit([[0, 0, 0]], [[1, 0, 0]]).tolist() == [False]


def test_per_ray_ranges_and_hits_triangle():
    tris = np.array([[[-1, -1, 1], [1, -1, 1], [0, 1, 1]]], dtype=float)
    rt = RayTracer(tris)
    o, d = np.zeros((3, 3)), np.tile([0.0, 0.0, 1.0], (3, 1))
    assert rt.any_hit(o, d, t_min=np.array([0.0, 1.0, 0.5]), t_max=np.array([2.0, 2.0, 0.9])).tolist() == [
        True,
        False,
        False,
    ]
    assert rt.hits_triangle(o, d, np.zeros(3, dtype=int), t_max=np.array([2.0, 1.0, 1.5])).tolist() == [
        True,
        False,
        True,
    ]


def every_triangle(tris, origins, direction):
    """Each line against every triangle, by the tracer's own test (t in (-inf, inf)): no grid at all."""
    rt = RayTracer(tris)
    R, T = len(origins), len(tris)
    o = np.repeat(origins, T, axis=0)
    d = np.broadcast_to(direction, (R * T, 3))
    return rt.hits_triangle(o, d, np.tile(np.arange(T), R), -np.inf, np.inf).reshape(R, T).any(axis=1)


@pytest.mark.parametrize("seed", range(4))
def test_parallel_lines_match_every_triangles_test(seed):
    # Lines of one direction (a directional light's EESD rays) through random points, points on the
    # triangles' vertices and edges, far points, NaN and inf points, against random triangles, slivers,
    # triangles containing the direction (never hit) and a degenerate one, at scales from 1e-6 to 1e6: the
    # 2-D grid's answer is the OR of the tracer's test over every triangle, and the 3-D tracer's any_hit.
    rng = np.random.default_rng(seed)
    scale = 10.0 ** rng.integers(-6, 7)
    d = rng.normal(size=3)
    tris = rng.uniform(-1, 1, size=(150, 1, 3)) + rng.normal(scale=0.2, size=(150, 3, 3))
    tris[:20, 2] = tris[:20, 0] + 1e-3 * (tris[:20, 1] - tris[:20, 0]) + 1e-4 * rng.normal(size=(20, 3))  # slivers
    tris[20:30, 2] = tris[20:30, 0] + 0.7 * d  # the line's direction lies in their planes
    tris[30, 2] = tris[30, 0]  # degenerate
    tris *= scale
    points = rng.uniform(-1.5, 1.5, size=(400, 3)) * scale
    on_edges = tris[40:80, 0] + rng.uniform(0, 1, size=(40, 1)) * (tris[40:80, 1] - tris[40:80, 0])
    odd = np.array([[np.nan, 0.0, 0.0], [np.inf, 1.0, 2.0], [1e9 * scale, 0.0, 0.0]])
    origins = np.vstack([points, tris[40:80, 0], on_edges, odd])
    got = lines_any_hit(origins, d, tris)
    assert np.array_equal(got, every_triangle(tris, origins, d))
    assert np.array_equal(got, RayTracer(tris).any_hit(origins, np.broadcast_to(d, origins.shape), -np.inf, np.inf))
    assert 0 < got.sum() < len(origins) - 3 and not got[-3:].any()
    done = rng.random(len(origins)) < 0.3
    assert np.array_equal(lines_any_hit(origins, d, tris, done=done), got | done)


def test_a_non_finite_triangle_is_never_listed_and_changes_no_answer():
    # The tracer's test never meets a triangle with an infinite or NaN corner (its determinant or
    # coordinates are NaN); the grid leaves such a triangle out, and the other triangles answer as before.
    rng = np.random.default_rng(7)
    tris = rng.uniform(-1, 1, size=(80, 1, 3)) + rng.normal(scale=0.3, size=(80, 3, 3))
    origins = rng.uniform(-1.5, 1.5, size=(300, 3))
    d = np.array([0.2, -0.4, 1.0])
    plain = lines_any_hit(origins, d, tris)
    for bad in (np.inf, -np.inf, np.nan):
        odd = tris.copy()
        odd[[3, 40], 1, 0] = bad
        expected = lines_any_hit(origins, d, np.delete(tris, [3, 40], axis=0))
        assert np.array_equal(lines_any_hit(origins, d, odd), expected)
    assert 0 < plain.sum() < len(origins)


def test_parallel_lines_with_no_triangle_or_no_direction_hit_nothing():
    o = np.zeros((3, 3))
    assert not lines_any_hit(o, [0.0, 0.0, 1.0], np.zeros((0, 3, 3))).any()
    tri = np.array([[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]])
    assert lines_any_hit(o, [0.0, 0.0, 1.0], tri).all()
    assert not lines_any_hit(o, [0.0, 0.0, 0.0], tri).any()
    assert not lines_any_hit(o, [0.0, np.nan, 1.0], tri).any()


def nearest_by_every_triangle(tris, origins, directions, t_min, t_max):
    """first_hit by :func:`moller_trumbore` on every triangle, no grid: nearest t, ties to the lower index."""
    best_t, best_i = np.full(len(origins), np.inf), np.full(len(origins), -1)
    for r, (o, d) in enumerate(zip(origins, directions, strict=True)):
        for i, tr in enumerate(tris):
            hit, t = moller_trumbore(*o, *d, *tr[0], *tr[1], *tr[2], t_min, t_max)
            if hit and t < best_t[r]:
                best_t[r], best_i[r] = t, i
    return best_t, best_i


def overlapping_soup(rng, copies: int) -> np.ndarray:
    """Stacked copies of one large triangle, copies of another turned about its centre (every one
    overlapping the centre), a few random triangles, and slivers along the large one's edge."""
    big = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]])
    stack = np.repeat(big[None], copies, axis=0)
    angles = rng.uniform(0, 2 * np.pi, size=copies)
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    turned = np.stack([big[:, 0] * c - big[:, 1] * s, big[:, 0] * s + big[:, 1] * c, np.full((copies, 3), 0.3)], axis=2)
    turned[..., 2] += rng.normal(scale=0.05, size=(copies, 1))  # tilted a little, so t differs
    random = rng.uniform(-1, 1, size=(40, 1, 3)) + rng.normal(scale=0.3, size=(40, 3, 3))
    slivers = np.repeat(big[None], 20, axis=0)
    slivers[:, 2] = big[0] + 1e-4 * rng.normal(size=(20, 3))
    return np.concatenate([stack, turned, random, slivers])


def test_overlapping_triangles_keep_the_grid_linear():
    # Copies of one triangle each cover every cell of the grid that their box spans: listing each in
    # every cell made T x cells entries (3.7e9 for 30,000 copies).  The listings stay within 8 per
    # triangle, whatever the overlap, and a non-overlapping soup keeps its fine grid.
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    for copies in (1, 500, 5000):
        rt = RayTracer(np.repeat(tri[None], copies, axis=0))
        assert rt._items.size <= 8 * copies
        assert rt.first_hit([[0.2, 0.2, 1.0]], [[0.0, 0.0, -1.0]])[1][0] == 0
    rng = np.random.default_rng(3)
    spread = rng.uniform(-10, 10, size=(4000, 1, 3)) + rng.normal(scale=0.05, size=(4000, 3, 3))
    assert np.prod(RayTracer(spread)._dims) > 4000


@pytest.mark.parametrize("seed", range(3))
def test_overlapping_triangles_answer_as_every_triangle(seed):
    # The coarsened grid changes which triangles a ray is tested against, never the answer: nearest
    # hit (t and index, ties to the lower index) and any hit equal the tracer's test on every triangle.
    rng = np.random.default_rng(seed)
    tris = overlapping_soup(rng, 150)
    rt = RayTracer(tris)
    assert rt._items.size <= 8 * len(tris) and np.prod(rt._dims) < 2 * len(tris)  # the coarsened path
    aimed = np.concatenate([tris[rng.integers(0, len(tris), 60)].mean(axis=1), rng.uniform(-1.5, 1.5, (40, 3))])
    origins = aimed + rng.normal(size=(100, 3)) * 2.0
    directions = (aimed - origins) * rng.uniform(0.5, 2.0, size=(100, 1))
    t, i = rt.first_hit(origins, directions, 0.0, 10.0)
    bt, bi = nearest_by_every_triangle(tris, origins, directions, 0.0, 10.0)
    assert np.array_equal(i, bi) and np.array_equal(t, bt)
    assert np.array_equal(rt.any_hit(origins, directions, 0.0, 10.0), bi >= 0)
    assert 20 < (i >= 0).sum() < 100
    assert (bi[bi >= 0] < 150).sum() > 0  # some rays end on the stacked copies: the lowest index of the pile
