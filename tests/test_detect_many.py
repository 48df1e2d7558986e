"""detect_many against detect, light by light: the same Silhouette, field by field (ties included)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import silcount
from silcount.detectors import DETECTORS, detect, detect_many
from silcount.errors import BadArgument
from silcount.mesh import shapes
from silcount.mesh.lights import DirectionalLight, PointLight
from silcount.testing import assert_silhouettes_equal


def _open_nonmanifold():
    """A cube missing one face, plus a fin: boundary and three-sided edges besides two-sided ones."""
    cube = shapes.triangle_cube()
    faces = [list(cube.corners[cube.face_start[p] : cube.face_start[p + 1]]) for p in range(1, cube.n_faces)]
    v = np.vstack([cube.vertices, [[2.0, 2.0, 2.0]]])
    a, b = faces[0][0], faces[0][1]
    return silcount.from_polygons(v, faces + [[a, b, len(v) - 1]], name="open_fin")


MESHES = {
    "torus": shapes.torus(1.0, 0.35, 12, 8),
    "cube": shapes.triangle_cube(),
    "open_fin": _open_nonmanifold(),
}

coord = st.one_of(st.floats(-5, 5, allow_nan=False), st.sampled_from([0.0, 1.0, -1.0, 0.5]))
light = st.builds(
    lambda kind, x, y, z: (
        DirectionalLight((x, y, z if (x, y, z) != (0, 0, 0) else 1.0)) if kind else PointLight((x, y, z))
    ),
    st.booleans(),
    coord,
    coord,
    coord,
)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(sorted(MESHES)), st.lists(light, min_size=1, max_size=70))
def test_reference_many_equals_single(mesh_name, lights):
    """Point lights on face planes (ties), directional lights, and more than one 64-light batch."""
    mesh = MESHES[mesh_name]
    many = detect_many(mesh, lights)
    assert len(many) == len(lights)
    for L, got in zip(lights, many, strict=True):
        assert_silhouettes_equal(got, detect(mesh, L))


def test_ties_are_counted_per_light():
    cube = shapes.triangle_cube()
    lo = cube.vertices.min(axis=0)
    lights = [PointLight(tuple(lo)), PointLight((9.0, 9.0, 9.0)), PointLight(tuple(lo + [0.0, 0.0, 0.0]))]
    many = detect_many(cube, lights)
    assert [r.ties for r in many] == [detect(cube, L).ties for L in lights]
    assert many[0].ties > 0


@pytest.mark.parametrize("name", DETECTORS)
@pytest.mark.parametrize("variant", ["intended", "literal"])
def test_every_detector_many_equals_single(name, variant):
    mesh = MESHES["torus"]
    lights = [PointLight((3.0, 1.0, 2.0)), DirectionalLight((0.2, -1.0, 0.4))]
    for L, got in zip(lights, detect_many(mesh, lights, name, variant), strict=True):
        assert_silhouettes_equal(got, detect(mesh, L, name, variant))


def test_bad_arguments():
    with pytest.raises(BadArgument):
        detect_many(MESHES["cube"], [PointLight((0, 0, 5))], "nope")
    assert detect_many(MESHES["cube"], []) == []


@pytest.mark.parametrize("name", DETECTORS)
def test_a_full_batch_of_64_lights_and_more_equals_single(name):
    # 70 fixed lights (so the fast `make mutation` selection, which runs no hypothesis test, sees them): a
    # full 64-light batch, whose every bit position maps back to its light, then a second batch of 6.
    # Point and directional lights alternate, and every fifth point light is on the cube's plane x = 0.5.
    rng = np.random.default_rng(11)
    lights = []
    for k in range(70):
        x, y, z = rng.uniform(-4.0, 4.0, 3)
        if k % 2:
            lights.append(DirectionalLight((x, y, z)))
        else:
            lights.append(PointLight((0.5, y, z) if k % 10 == 0 else (x, y, z)))
    # Every detector: the batched engines (reference, TA, HSD, EESD) and the per-light ones.
    many = {mesh_name: detect_many(mesh, lights, name) for mesh_name, mesh in MESHES.items()}
    for mesh_name, mesh in MESHES.items():
        for L, got in zip(lights, many[mesh_name], strict=True):
            assert_silhouettes_equal(got, detect(mesh, L, name))
    # the on-plane lights: ties, per light (HSD counts its polygons' representatives only)
    assert sum(r.ties for r in many["cube"]) >= (7 if name == "hsd" else 7 * 2)
