"""detect_many against detect, light by light: the same Silhouette, field by field (ties included)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import silcount
from silcount.counting.arithmetic import KINDS
from silcount.detectors import DETECTORS, detect, detect_many, differences, get
from silcount.detectors.batch import ABSENT, SilhouetteBatch, common_many
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


def _assert_batch_matches(batch, mesh, lights, name, variant="intended"):
    """Every array of ``batch`` against :func:`detect` light by light (the per-light engine, a second path)."""
    assert isinstance(batch, SilhouetteBatch) and len(batch) == len(lights)
    assert batch.offsets[0] == 0 and np.all(np.diff(batch.offsets) >= 0) and batch.offsets[-1] == batch.ids.size
    assert batch.kinds[: len(KINDS)] == KINDS
    for i, L in enumerate(lights):
        one = detect(mesh, L, name, variant)
        assert batch.edge_ids(i).tolist() == one.edge_ids.tolist()
        assert batch.n_edges[i] == one.n_edges
        assert {s: int(v) for s, v in zip(batch.step_names, batch.steps[i]) if v != ABSENT} == one.steps
        assert {k: int(v) for k, v in zip(batch.kinds, batch.true[i]) if v != ABSENT} == one.true_tally
        assert batch.ties[i] == one.ties
        assert batch.light_notes_of(i) == one.notes
        if one.paper_model is not None:
            kinds, paper = batch.paper_counts()
            assert {k: int(v) for k, v in zip(kinds, paper[i]) if v != ABSENT} == one.tally["paper"]
        assert_silhouettes_equal(batch[i], one)


@settings(max_examples=12, deadline=None)
@given(
    st.sampled_from(sorted(MESHES)), st.lists(light, min_size=1, max_size=6), st.sampled_from(["intended", "literal"])
)
def test_every_detector_batch_equals_single_field_by_field(mesh_name, lights, variant):
    """Each built-in's columnar batch (CSR edges, step and tally arrays, ties, notes) against ``detect``."""
    mesh = MESHES[mesh_name]
    for name in DETECTORS:
        v = variant if variant in get(name).variants else "intended"
        _assert_batch_matches(detect_many(mesh, lights, name, v), mesh, lights, name, v)


def test_the_csr_form_by_hand():
    """The tetrahedron (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1), lit towards (-1,-1,-1), its face (1,3,2)'s
    outward normal, then from the opposite side: face (1,3,2) alone, then the other three, are lit, so both
    silhouettes are that face's three edges, the three that do not touch (1,1,1) (the mesh numbers the
    welded vertices in its own order)."""
    tet = shapes.tetrahedron()
    apex = int(np.flatnonzero((tet.vertices == 1.0).all(axis=1))[0])
    a, b, c = sorted({0, 1, 2, 3} - {apex})
    face = [[a, b], [a, c], [b, c]]
    lights = [DirectionalLight((-1.0, -1.1, -0.9)), DirectionalLight((1.0, 1.1, 0.9))]
    batch = detect_many(tet, lights, "reference")
    assert batch.offsets.tolist() == [0, 3, 6] and batch.n_edges.tolist() == [3, 3]
    for i in range(2):
        assert tet.edges[batch.edge_ids(i)].tolist() == face
    assert tet.edges[batch.ids].tolist() == face * 2
    assert batch.step("visibility").tolist() == [4, 4] and batch.step("add").tolist() == [3, 3]
    assert batch.step("nope") is None and batch.ties.tolist() == [0, 0]
    assert batch[-1].edge_ids.tolist() == batch.edge_ids(1).tolist() and len(batch[0:1]) == 1
    with pytest.raises(IndexError):
        batch[2]


def test_common_many_is_differences_per_light():
    mesh = MESHES["open_fin"]
    lights = [PointLight((3.0, 1.0, 2.0)), DirectionalLight((0.2, -1.0, 0.4)), PointLight((0.1, 0.2, 0.3))]
    refs = detect_many(mesh, lights, "reference")
    for name in ("ta", "eesd"):
        got = detect_many(mesh, lights, name, "literal")
        common = common_many(got, refs)
        for i in range(len(lights)):
            d = differences(got[i].edge_ids, refs[i].edge_ids)
            assert refs.n_edges[i] - common[i] == d["missed_edges"]
            assert got.n_edges[i] - common[i] == d["extra_edges"]


def test_a_list_of_silhouettes_becomes_a_batch_of_the_same_objects():
    """A plug-in's ``detect_many`` may return a list: it is wrapped, its objects handed back as they are."""
    mesh = MESHES["cube"]
    lights = [PointLight((3.0, 1.0, 2.0)), DirectionalLight((0.2, -1.0, 0.4))]
    results = [detect(mesh, L, "ta") for L in lights]
    batch = SilhouetteBatch.of_silhouettes(results)
    assert list(batch) == results and batch[1] is results[1]
    assert batch.step("search_S").tolist() == [r.steps["search_S"] for r in results]
    assert batch.ties.tolist() == [r.ties for r in results]
    assert SilhouetteBatch.of_silhouettes([]) == []


def test_a_corpus_unit_reads_the_arrays_and_makes_no_silhouette(monkeypatch):
    """The sweep's unit builds its rows from every built-in's batch arrays: no ``batch[i]``, no ``Silhouette``."""
    from silcount.detectors import batch as batch_module
    from silcount.detectors import result
    from silcount.study.work import Settings, _audit

    def refuse(*args, **kwargs):
        raise AssertionError("a Silhouette was made")

    monkeypatch.setattr(batch_module.SilhouetteBatch, "__getitem__", refuse)
    monkeypatch.setattr(result.Silhouette, "__init__", refuse)
    lights = [PointLight((3.0, 1.0, 2.0)), DirectionalLight((0.2, -1.0, 0.4))]
    got = _audit(MESHES["torus"], 0, lights, Settings(lights=2, light_kind="both", timing=False))
    assert len(got["rows"]["values"][0]) == 2 * len(DETECTORS)
