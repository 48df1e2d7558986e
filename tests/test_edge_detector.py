"""The example plug-in ``examples/edge-detector``: VTK's edge rule, checked by hand counts, its two engines
against each other, and silcount's reference where the two rules must agree.  Imported from the example's
folder; ``tests/test_plugin_venv.py`` installs it and runs it through silcount's commands."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from silcount.detectors import detect as builtin_detect
from silcount.mesh.lights import DirectionalLight, PointLight
from silcount.mesh.shapes import builtin_mesh, icosphere, plane, quad_cube

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples" / "edge-detector"))
from silcount_edge_detector import SPEC, detect  # noqa: E402


def test_a_cube_lit_off_every_axis_has_the_six_edges_of_its_hexagon():
    # by hand: (1, 2, 3) lights +x, +y, +z; each of them meets two unlit faces, 3 x 2 = 6 edges, each joining
    # a lit face to an unlit one: its two endpoints differ in one coordinate, the lit and unlit axes' other
    mesh, light = quad_cube(), DirectionalLight((1.0, 2.0, 3.0))
    for engine in ("fast", "naive"):
        res = detect(mesh, light, engine=engine)
        assert res.n_edges == 6 and res.steps["dot"] == 12  # every edge of a closed cube is winged
    assert np.array_equal(res.edge_ids, builtin_detect(mesh, light).edge_ids)


def test_a_light_along_an_axis_gives_no_edge_where_the_reference_gives_four():
    # by hand: light (0, 0, 1); the four side faces have d = 0 exactly, so every product d1 * d2 with a side
    # face is 0, never < 0; the reference counts a tie as unlit, so the top's four edges are its silhouette.
    # Ties, one per zero d: the top ring's 4 edges and the bottom ring's 4 one each, the 4 vertical edges two
    light = DirectionalLight((0.0, 0.0, 1.0))
    for engine in ("fast", "naive"):
        res = detect(quad_cube(), light, engine=engine)
        assert res.n_edges == 0 and res.ties == 4 + 4 + 2 * 4
    assert builtin_detect(quad_cube(), light).n_edges == 4


def test_an_open_mesh_has_no_silhouette_on_its_border():
    # by hand: the 2 x 14 grid has E = 100, 2 x (2 + 14) = 32 of them on its border; the 68 inside are winged,
    # both their faces lit from above; VTK's default leaves the border edges out, the reference keeps all 32
    mesh = plane()
    for engine in ("fast", "naive"):
        res = detect(mesh, PointLight((0.2, 0.3, 2.0)), engine=engine)
        assert res.n_edges == 0 and res.steps["dot"] == 68
    assert builtin_detect(mesh, PointLight((0.2, 0.3, 2.0))).n_edges == 32


def test_the_naive_engine_counts_a_tetrahedron_by_hand():
    # by hand, directional light: 4 faces x 13 reads (start, 3 corner ids, 9 coordinates) + 6 edges x 2 reads
    # (its left and right face) + 6 winged edges x 9 reads (two normals, the light) = 118 reads
    mesh = builtin_mesh("tetrahedron")
    res = detect(mesh, DirectionalLight((0.3, 0.4, 1.0)), engine="naive")
    assert res.true_tally["read"] == 118
    assert res.true_tally["cmp"] == 6 * 2 + 6 * 1  # the winged test's two, the sign test's one
    assert res.true_tally["write"] == 4 * 3 + res.n_edges  # the normals, and S
    # its paper model (this package's own TOML): the point-light annotation, 17 reads per winged edge
    assert res.tally["paper"]["read"] == 4 * 13 + 6 * 2 + 6 * 17


MESHES = ("tetrahedron", "quad_cube", "torus", "icosphere1")
LIGHTS = (DirectionalLight((0.3, -0.5, 0.8)), PointLight((2.0, 1.5, -3.0)), PointLight((0.1, 0.2, 0.05)))


@pytest.mark.parametrize("name", MESHES)
def test_the_fast_engine_is_the_naive_engine(name):
    """Two implementations: the counted loop and numpy's arrays give the same edges, steps and tallies."""
    mesh = builtin_mesh(name)
    for light in LIGHTS:
        a, b = detect(mesh, light, engine="naive"), detect(mesh, light, engine="fast")
        assert np.array_equal(a.edge_ids, b.edge_ids), (name, light)
        assert a.steps == b.steps and a.true_tally == b.true_tally and a.ties == b.ties, (name, light)
        assert a.tally == b.tally


def test_on_a_closed_consistently_wound_mesh_it_is_the_reference():
    """The edge's midpoint and a face's first corner lie on the face's plane: the same sign, the same edges."""
    mesh = icosphere(2)
    rng = np.random.default_rng(7)
    for d in rng.normal(size=(8, 3)):
        for light in (DirectionalLight(tuple(d)), PointLight(tuple(4.0 * d))):
            assert np.array_equal(detect(mesh, light).edge_ids, builtin_detect(mesh, light).edge_ids)


def test_its_spec_declares_what_it_has():
    assert SPEC.name == "vtk-edge" and SPEC.engines == ("fast", "naive") and SPEC.missing == ("plain loops",)
    assert Path(SPEC.paper_model).is_file()
