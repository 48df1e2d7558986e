"""The uncounted kernels that time each algorithm's real work return the detectors' own edges."""

import numpy as np
from hypothesis import HealthCheck, given, settings
from strategies import examples, mesh_and_light

import silcount
from silcount.detectors.plain import PLAIN, plain_edge_ids


@settings(max_examples=examples(30), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mesh_and_light())
def test_plain_kernels_equal_the_detectors(ml):
    mesh, light = ml
    for name in PLAIN:
        expected = silcount.detect(mesh, light, name, variant="intended").edge_ids
        assert np.array_equal(plain_edge_ids(mesh, light, name), expected), name


def test_plain_kernels_on_the_quad_cube_with_polygon_faces():
    # Light above the top face: its four sides are the silhouette, for every algorithm.
    mesh = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.1, 0.2, 10.0))
    ref = silcount.detect(mesh, light, "reference").edge_ids
    assert ref.size == 4
    for name in PLAIN:
        assert np.array_equal(plain_edge_ids(mesh, light, name), ref), name
