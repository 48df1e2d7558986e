"""The rasteriser by itself: coverage on shared edges, the fill rule, depth at known pixels, clipping."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from silcount.render.camera import Camera
from silcount.render.raster import DEPTH, ZFAIL, ZPASS, homogeneous, new_buffers, rasterize, to_clip


def clip_from_screen(points, width, height, z=0.0):
    """(T, 3, 2) screen positions in pixels (x right, y down) -> (T, 3, 4) clip coordinates with w = 1."""
    p = np.asarray(points, dtype=np.float64)
    out = np.zeros(p.shape[:-1] + (4,))
    out[..., 0] = 2.0 * p[..., 0] / width - 1.0
    out[..., 1] = 1.0 - 2.0 * p[..., 1] / height
    out[..., 2] = z
    out[..., 3] = 1.0
    return np.ascontiguousarray(out)


def stencil_count(clip, width, height):
    depth, stencil, tri_id = new_buffers(width, height)
    rasterize(clip, np.arange(len(clip), dtype=np.int64), ZPASS, depth, stencil, tri_id)
    return stencil


def test_two_triangles_sharing_a_diagonal_through_pixel_centres_cover_each_centre_once():
    # A 8x8 screen; the square's diagonal (0,0)-(8,8) passes exactly through the centres (i+.5, i+.5).
    # (0,0) top-left -> (8,8) bottom-right -> (8,0) top-right turns counter-clockwise as seen: front-facing.
    W = H = 8
    tris = [[(0, 0), (8, 8), (8, 0)], [(0, 0), (0, 8), (8, 8)]]
    stencil = stencil_count(clip_from_screen(tris, W, H), W, H)
    assert np.array_equal(stencil, np.ones((H, W)))


def test_back_facing_pair_decrements_each_centre_once():
    W = H = 8
    tris = [[(0, 0), (8, 0), (8, 8)], [(0, 0), (8, 8), (0, 8)]]  # the same two, reversed winding
    assert np.array_equal(stencil_count(clip_from_screen(tris, W, H), W, H), -np.ones((H, W)))


def test_top_left_rule_gives_a_shared_vertical_edge_to_the_right_triangle():
    # Two triangles share the vertical edge x = 3.5 (the centres of column 3): it is the left edge of the
    # right-hand triangle, so column 3 belongs to triangle 1.  Rows 2..5 lie strictly between the ends.
    W = H = 8
    left = [(0.0, 0.0), (0.0, 8.0), (3.5, 8.0)]
    left2 = [(0.0, 0.0), (3.5, 8.0), (3.5, 0.0)]
    right = [(3.5, 0.0), (3.5, 8.0), (8.0, 8.0)]
    clip = clip_from_screen([left, left2, right], W, H)
    depth, stencil, tri_id = new_buffers(W, H)
    rasterize(clip, np.array([0, 0, 1]), DEPTH, depth, stencil, tri_id)
    assert np.all(tri_id[2:6, 3] == 1)
    assert np.all(tri_id[2:6, 2] == 0)


def test_a_horizontal_shared_edge_goes_to_the_triangle_below_it():
    # Edge y = 3.5 through the centres of row 3: the top edge of the lower triangle owns them.
    W = H = 8
    upper = [(0.0, 0.0), (8.0, 3.5), (8.0, 0.0)]
    upper2 = [(0.0, 0.0), (0.0, 3.5), (8.0, 3.5)]
    lower = [(0.0, 3.5), (0.0, 8.0), (8.0, 8.0)]
    lower2 = [(0.0, 3.5), (8.0, 8.0), (8.0, 3.5)]
    clip = clip_from_screen([upper, upper2, lower, lower2], W, H)
    depth, stencil, tri_id = new_buffers(W, H)
    rasterize(clip, np.array([0, 0, 1, 1]), DEPTH, depth, stencil, tri_id)
    assert np.all(tri_id[3] == 1) and np.all(tri_id[2] == 0)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 6), st.integers(0, 2**32 - 1), st.booleans())
def test_any_triangulated_screen_covers_each_centre_exactly_once(k, seed, snap):
    # A k x k grid over the whole screen, interior vertices jittered (optionally snapped onto pixel
    # centres, the hardest ties), each cell split along a random diagonal: every centre exactly once.
    W, H = 24, 16
    rng = np.random.default_rng(seed)
    gx = np.linspace(0, W, k + 1)
    gy = np.linspace(0, H, k + 1)
    X, Y = np.meshgrid(gx, gy, indexing="ij")
    jx, jy = 0.3 * W / k, 0.3 * H / k
    X[1:-1, 1:-1] += rng.uniform(-jx, jx, (k - 1, k - 1))
    Y[1:-1, 1:-1] += rng.uniform(-jy, jy, (k - 1, k - 1))
    if snap:
        X[1:-1, 1:-1] = np.floor(X[1:-1, 1:-1]) + 0.5
        Y[1:-1, 1:-1] = np.floor(Y[1:-1, 1:-1]) + 0.5
    tris = []
    for i in range(k):
        for j in range(k):
            a, b, c, d = (
                (X[i, j], Y[i, j]),
                (X[i + 1, j], Y[i + 1, j]),
                (X[i + 1, j + 1], Y[i + 1, j + 1]),
                (X[i, j + 1], Y[i, j + 1]),
            )
            # a->b->c->d runs right then down: clockwise as seen, so list them d, c, b, a (front-facing)
            tris += [[a, c, b], [a, d, c]] if rng.random() < 0.5 else [[a, d, b], [b, d, c]]
    assert np.array_equal(stencil_count(clip_from_screen(tris, W, H), W, H), np.ones((H, W)))


def test_known_tilted_quad_depth_at_known_pixels():
    # Eye at the origin looking down -z, fov 90, 64x64, near 0.5.  The plane z_eye = -(2 + 0.5 x_eye).
    # Ray through pixel centre with NDC (x, y): d = (x, y, -1) (tan 45 = 1), hits at t = 2 / (1 - 0.5 x),
    # so eye depth is t and NDC depth is 1 - 2 near / t (infinite far plane), worked out here by hand.
    W = H = 64
    cam = Camera(np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), 90.0, 0.5, W, H)
    xs = np.array([-5.0, 5.0])
    corners = np.array([[x, y, -(2 + 0.5 * x)] for x in xs for y in (-5.0, 5.0)])
    quad = np.array([[corners[0], corners[2], corners[3]], [corners[0], corners[3], corners[1]]])
    clip = to_clip(homogeneous(quad), cam.view_projection)
    depth, stencil, tri_id = new_buffers(W, H)
    rasterize(clip, np.array([0, 1]), DEPTH, depth, stencil, tri_id)
    for row, col in [(32, 32), (0, 0), (10, 50), (63, 63), (40, 7)]:
        x = 2 * (col + 0.5) / W - 1
        t = 2.0 / (1.0 - 0.5 * x)
        assert tri_id[row, col] >= 0
        # vertices snap to 1/256 pixel: allow that much screen-space slope
        assert abs(depth[row, col] - (1.0 - 2 * 0.5 / t)) < 1e-5
        assert abs(cam.eye_depth_from_ndc_z(depth[row, col]) - t) < 1e-4 * t


def test_points_at_infinity_reach_the_far_plane_and_fail_the_depth_test():
    # A triangle whose vertices are directions (w = 0) straight ahead: depth 1, never LESS than the clear value.
    W = H = 16
    cam = Camera(np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), 60.0, 0.1, W, H)
    tri = np.array([[[-1, -1, -1, 0], [1, -1, -1, 0], [0, 1, -1, 0]]], dtype=np.float64)
    clip = to_clip(tri, cam.view_projection)
    assert np.allclose(clip[..., 2] / clip[..., 3], 1.0)
    depth, stencil, tri_id = new_buffers(W, H)
    rasterize(clip, np.array([0]), ZFAIL, depth, stencil, tri_id)
    assert stencil[W // 2, H // 2] == -1  # front-facing, depth test fails: decrement
    rasterize(clip, np.array([0]), ZPASS, depth, stencil, tri_id)
    assert stencil[W // 2, H // 2] == -1  # and z-pass sees nothing


def test_near_plane_clipping_keeps_only_the_part_in_front():
    # A floor-like triangle from behind the eye to far ahead: drawn only where in front of the near plane,
    # and no pixel twice.  The horizon row (y = 0) separates it from the empty upper half.
    W = H = 32
    cam = Camera(np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), 90.0, 0.1, W, H)
    tri = np.array([[[-50, -1, 5], [50, -1, 5], [0, -1, -100]]], dtype=np.float64)
    clip = to_clip(homogeneous(tri), cam.view_projection)
    assert np.array_equal(np.unique(stencil_count(clip, W, H)), [0, 1])
    covered = stencil_count(clip, W, H) == 1
    assert not covered[: H // 2].any() and covered[-1].all()


def test_pixel_rays_project_to_the_contract_pixel_centres():
    # The ray through pixel (row, col) must land at NDC x = 2 (col + .5) / W - 1, y = 1 - 2 (row + .5) / H
    # under the projection matrix (two independent formulas: ray construction vs. gluPerspective/gluLookAt).
    cam = Camera(np.array([6.0, 5, 8]), np.array([0, 0.5, 0]), np.array([0, 1.0, 0]), 45.0, 0.1, 40, 30)
    rays = cam.pixel_rays()
    for row, col in [(0, 0), (29, 39), (12, 7), (15, 20)]:
        p = np.append(cam.eye + 3.0 * rays[row, col], 1.0)
        c = cam.view_projection @ p
        assert np.allclose([c[0] / c[3], c[1] / c[3]], [2 * (col + 0.5) / 40 - 1, 1 - 2 * (row + 0.5) / 30])
        assert np.isclose(c[3], 3.0)  # t is eye depth: w_clip = -z_eye


@pytest.mark.parametrize("rows", [3, 8190, 8193, 16386, 3 * 57218])
def test_to_clip_in_parts_has_the_bits_of_one_product(rows):
    """The parts of CLIP_ROWS rows give every element the bits of one (rows, 4) x (4, 4) product (the masks
    of commit 318ab63 depend on them), including a part that would otherwise be one row (8193)."""
    from silcount.render.raster import CLIP_ROWS

    rng = np.random.default_rng(rows)
    vp = rng.uniform(-2, 2, (4, 4))
    p = rng.uniform(-5, 5, (rows // 3, 3, 4))
    assert CLIP_ROWS == 8192
    expected = (p.reshape(-1, 4) @ vp.T).reshape(p.shape)
    assert np.array_equal(to_clip(p, vp), expected)
