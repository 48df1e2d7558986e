"""zeros_per_point against every point-plane pair evaluated with numpy."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from strategies import examples

from silcount.detectors.eesd.onplane import _packet_bounds, _packet_misses, zeros_per_point


def brute_force(points, planes):
    a, b, c, d = (planes[:, k][None, :] for k in range(4))
    x, y, z = (points[:, k][:, None] for k in range(3))
    return np.count_nonzero(((a * x + b * y) + c * z) + d == 0.0, axis=1)


def test_grid_points_on_axis_planes_and_random_planes():
    # Points of a 9x9x9 grid with spacing 1/4 (exact in binary) lie exactly on the planes
    # x, y or z = k/4 (some scaled by 3: 3x - 3k/4 = 0 is still exact); random planes hold none.
    rng = np.random.default_rng(0)
    g = np.arange(-4, 5) / 4.0
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    pts = np.concatenate([pts, rng.normal(size=(500, 3)), [[np.nan, 0.0, 0.0]]])
    axis = []
    for k in range(3):
        for off in (-1.0, -0.25, 0.5, 0.75):
            n = np.zeros(3)
            n[k] = 3.0
            axis.append([*n, -3.0 * off])
    planes = np.concatenate([np.array(axis), rng.normal(size=(300, 4))])
    got = zeros_per_point(pts, planes)
    expected = brute_force(pts, planes)
    assert np.array_equal(got, expected)
    assert expected.sum() >= 12 * 81  # every axis plane holds a 9x9 layer
    assert got[-1] == 0


def test_random_points_near_one_plane():
    # Points sampled on the plane x + 2y - z = 0.5 with dyadic coordinates land on it exactly; their
    # neighbours 1e-12 away do not.  Brute force decides which ones the float test calls zero.
    rng = np.random.default_rng(1)
    xy = rng.integers(-64, 64, size=(2000, 2)) / 32.0
    on = np.column_stack([xy, xy[:, 0] + 2 * xy[:, 1] - 0.5])
    pts = np.concatenate([on, on + 1e-12 * rng.normal(size=on.shape)])
    planes = np.array([[1.0, 2.0, -1.0, -0.5], [2.0, 4.0, -2.0, -1.0], [1.0, 2.0, -1.0, -0.25]])
    got = zeros_per_point(pts, planes)
    assert np.array_equal(got, brute_force(pts, planes))
    assert got[:2000].min() == 2 and got[2000:].max() < 2


def test_zeros_in_every_packet_position():
    # Axis planes scattered among 2,000 random ones land at every position of a packet and in many
    # packets, so the per-plane alive flags, the padding of the last packet and the stripes are all used.
    rng = np.random.default_rng(2)
    g = np.arange(-8, 9) / 8.0
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    pts = np.concatenate([pts, rng.normal(size=(3000, 3))])
    planes = rng.normal(size=(2003, 4))
    where = rng.choice(len(planes), size=150, replace=False)
    for j in where:
        n = np.zeros(3)
        n[rng.integers(3)] = rng.choice([1.0, -2.0, 0.5])
        planes[j] = [*n, -n.sum() * rng.choice(g)]
    got = zeros_per_point(pts, planes)
    expected = brute_force(pts, planes)
    assert np.array_equal(got, expected)
    assert expected.sum() >= 150 * 17 * 17


def test_point_counts_that_fill_the_last_leaves():
    # The tree has 2^k leaves of 16 points; when the points fill the last two leaves (n_leaves = 2^k or
    # 2^k - 1), the last internal node's box is needed.  Every point of the dyadic grid lies on exactly
    # three of its 24 axis planes, so a leaf the walk never reaches shows as a missing count.
    g = np.arange(-4, 4) / 4.0
    grid = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)  # 512 points
    planes = np.array([[*np.eye(3)[k], -off] for k in range(3) for off in g])
    for n in (1, 16, 17, 32, 33, 48, 64, 240, 256, 496, 512):
        got = zeros_per_point(grid[:n], planes)
        expected = brute_force(grid[:n], planes)
        assert np.array_equal(got, expected), n
        assert expected.tolist() == [3] * n


def test_an_all_zero_plane_holds_every_point():
    # A degenerate face (zero normal) gives the plane (0, 0, 0, 0): the float test is 0 == 0 for every
    # point, so nothing may be pruned although the prune bound is 0.
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(100, 3))
    planes = np.array([[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 5.0]])
    assert zeros_per_point(pts, planes).tolist() == [1] * 100


def test_plane_counts_at_the_packet_edges_and_degenerate_inputs():
    # 65 planes: the last packet holds one plane, the one that holds the points; one plane alone;
    # points that are all NaN (on no plane).
    pts = np.array([[0.25, 0.5, 1.0], [0.25, -3.0, 2.0], [1.0, 1.0, 1.0]])
    x_quarter = [1.0, 0.0, 0.0, -0.25]
    planes = np.vstack([np.tile([0.0, 0.0, 1.0, 9.0], (64, 1)), [x_quarter]])
    assert zeros_per_point(pts, planes).tolist() == [1, 1, 0]
    assert zeros_per_point(pts, np.array([x_quarter])).tolist() == [1, 1, 0]
    assert zeros_per_point(np.full((4, 3), np.nan), planes).tolist() == [0, 0, 0, 0]


def _near_copies(base: np.ndarray, rng: np.random.Generator, n: int = 64) -> np.ndarray:
    """``n`` planes, each coefficient ``base``'s or a neighbouring float (a quarter exact copies)."""
    step = rng.integers(-1, 2, size=(n, 4))
    step[: n // 4] = 0
    towards = np.where(step > 0, np.inf, -np.inf)
    return np.where(step == 0, base, np.nextafter(base, towards))


def test_a_packet_of_near_copies_keeps_every_zero():
    # One packet of 64 planes within one ulp of x + 2y - z = 0.5 in each coefficient: the packet test (mid plane and
    # spread) rules out nearly every box and point at once, and must keep each point that one of the
    # planes holds exactly.  The points on the base plane are exact (dyadic); others sit 1e-12 away.
    rng = np.random.default_rng(4)
    xy = rng.integers(-64, 64, size=(3000, 2)) / 32.0
    on = np.column_stack([xy, xy[:, 0] + 2 * xy[:, 1] - 0.5])
    pts = np.concatenate([on, on + 1e-12 * rng.normal(size=on.shape), rng.normal(size=(2000, 3))])
    planes = _near_copies(np.array([1.0, 2.0, -1.0, -0.5]), rng)
    got = zeros_per_point(pts, planes)
    expected = brute_force(pts, planes)
    assert np.array_equal(got, expected)
    assert expected[:3000].min() >= 16 and expected[:3000].max() < 64  # the exact copies, and not every plane


@given(
    base=hnp.arrays(np.float64, 4, elements=st.integers(-8, 8).map(lambda k: k / 4.0)),
    seed=st.integers(0, 2**32 - 1),
)
@settings(max_examples=examples(40), deadline=None)
def test_packets_of_near_copies_equal_every_pair(base, seed):
    # Dyadic base planes (some degenerate: all-zero normals), 64-plane packets of copies within a
    # ulp, and dyadic points on the base plane where it has a z term: the count of exact zeros
    # equals every pair evaluated, for each packet position of the copies.
    rng = np.random.default_rng(seed)
    xy = rng.integers(-32, 32, size=(400, 2)) / 16.0
    pts = rng.integers(-32, 32, size=(400, 3)) / 16.0
    if base[2] != 0.0:
        pts[:, :2] = xy
        pts[:, 2] = -(base[0] * xy[:, 0] + base[1] * xy[:, 1] + base[3]) / base[2]
    planes = np.concatenate([rng.normal(size=(rng.integers(0, 64), 4)), _near_copies(base, rng)])
    assert np.array_equal(zeros_per_point(pts, planes), brute_force(pts, planes))


def test_the_packet_test_counts_the_spread():
    # Two planes 2^-20 apart in d; a point exactly on the second.  The packet test keeps it (its mid
    # plane is 2^-21 away, within the spread); the same test without the spread would rule it out,
    # which the brute-force comparisons above would catch as a missing zero.
    planes = np.array([[1.0, 0.0, 0.0, -0.5], [1.0, 0.0, 0.0, -0.5 - 2.0**-20]])
    finite, mid, spread, peak = _packet_bounds(planes, 0, 2)
    assert finite and spread[3] == 2.0**-21
    x = 0.5 + 2.0**-20
    assert brute_force(np.array([[x, 0.0, 0.0]]), planes).tolist() == [1]
    args = (x, 0.0, 0.0, 0.0, 0.0, 0.0, abs(x), 0.0, 0.0)
    assert not _packet_misses(mid, spread, peak, *args)
    assert _packet_misses(mid, np.zeros(4), peak, *args)
    assert _packet_misses(mid, spread, peak, x + 1e-3, *args[1:])  # far from both: ruled out


def test_regrouped_planes_count_as_every_pair_on_a_curved_grid():
    # Planes of a curved surface (no coplanar runs: regrouped by _plane_order) mixed with coherent
    # runs of 64 copies (kept as packets), axis planes through a dyadic grid (exact zeros), zero and NaN
    # planes: the counts equal every pair's, and the order is a permutation keeping the coherent runs.
    from silcount.detectors.eesd.onplane import PACKET, _plane_order

    rng = np.random.default_rng(5)
    g = np.arange(-4, 5) / 4.0
    grid = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    u = rng.uniform(0, 2 * np.pi, size=(600, 2))
    torus = np.stack([(1 + 0.35 * np.cos(u[:, 1])) * np.cos(u[:, 0]), (1 + 0.35 * np.cos(u[:, 1])) * np.sin(u[:, 0]),
                      0.35 * np.sin(u[:, 1])], axis=1)  # fmt: skip
    normals = torus - np.stack([np.cos(u[:, 0]), np.sin(u[:, 0]), 0 * u[:, 0]], axis=1)
    tangent = np.concatenate([normals, -(normals * torus).sum(axis=1, keepdims=True)], axis=1)
    axis = np.array([[0.0, 0.0, 4.0, -1.0], [2.0, 0.0, 0.0, 1.0]])
    runs = np.repeat(axis, PACKET, axis=0)
    planes = np.concatenate([runs, tangent, axis, [[0.0, 0.0, 0.0, 0.0], [np.nan, 1.0, 0.0, 0.0]]])
    points = np.concatenate([grid, torus, [[np.nan, 0.0, 0.0]]])
    order = _plane_order(planes)
    assert np.array_equal(np.sort(order), np.arange(len(planes)))
    assert np.array_equal(order[: 2 * PACKET], np.arange(2 * PACKET))  # the coherent runs, as they were
    got = zeros_per_point(points, planes)
    assert np.array_equal(got, brute_force(points, planes))
    assert got[: len(grid)].min() >= 1 and got.sum() > 2 * 81 * (PACKET + 1)


def test_the_plane_tests_are_held_to_the_work_limit():
    # Every plane through every point of a flat grid: tests grow with points x planes; past the limit the
    # walk stops between chunks with TooMuchWork naming the computation, and under it counts as before.
    from silcount.errors import TooMuchWork
    from silcount.mesh.chunks import limit_work

    g = np.arange(64) / 8.0
    pts = np.stack([*np.meshgrid(g, g, indexing="ij"), np.zeros((64, 64))], axis=-1).reshape(-1, 3)
    planes = np.repeat([[0.0, 0.0, 1.0, 0.0]], 500, axis=0) * np.arange(1, 501)[:, None]
    with limit_work(10_000), pytest.raises(TooMuchWork, match="flat grid: over 10,000"):
        zeros_per_point(pts, planes, "flat grid")
    with limit_work(10**9):
        assert np.array_equal(zeros_per_point(pts, planes, "flat grid"), np.full(len(pts), 500))
