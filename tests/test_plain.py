"""The uncounted kernels that time each algorithm's real work return the detectors' own edges."""

import numpy as np
from hypothesis import HealthCheck, given, settings
from strategies import examples, mesh_and_light

import silcount
from silcount.detectors import DETECTORS, plain_edge_ids


@settings(max_examples=examples(30), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mesh_and_light())
def test_plain_kernels_equal_the_detectors(ml):
    mesh, light = ml
    for name in DETECTORS:
        expected = silcount.detect(mesh, light, name, variant="intended").edge_ids
        got = plain_edge_ids(mesh, light, name)
        assert np.array_equal(got, expected), name


def test_plain_eesd_with_a_ray_parallel_to_a_face():
    # found by the long hypothesis profile: a light straight above the cube's centre sends the ray of each top edge
    # parallel to a side face, Moller-Trumbore's det is 0; numba's Python error model raised on 1 / det until
    # EESD's plain loop was compiled with error_model="numpy", as the ray tracer is
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.0, 0.0, 1.7320508075688772))
    expected = silcount.detect(mesh, light, "eesd").edge_ids
    assert np.array_equal(plain_edge_ids(mesh, light, "eesd"), expected)


def test_plain_kernels_on_the_quad_cube_with_polygon_faces():
    # Light above the top face: its four sides are the silhouette, for every algorithm.
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.1, 0.2, 10.0))
    ref = silcount.detect(mesh, light, "reference").edge_ids
    assert ref.size == 4
    for name in DETECTORS:
        assert np.array_equal(plain_edge_ids(mesh, light, name), ref), name
