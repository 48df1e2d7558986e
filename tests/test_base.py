"""The shared result assembly (``detectors/base.py``): id normalisation and the reference comparison, by hand."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import silcount
from silcount import DirectionalLight
from silcount.detectors import result
from silcount.detectors.base import unique_ids
from silcount.detectors.result import compare_with_reference, differences


@pytest.mark.parametrize(
    "ids, expected",
    [
        ([], []),
        ([7], [7]),
        ([3, 1], [1, 3]),  # two ids, descending
        ([2, 2], [2]),  # two ids, equal
        ([0, 5, 3], [0, 3, 5]),  # the first is the least: only the tail is out of order
        ([1, 4, 4, 9], [1, 4, 9]),  # ascending but not strictly
        ([9, 3, 9, 0, 3], [0, 3, 9]),
        ([[4, 2], [2, 8]], [2, 4, 8]),  # any shape is flattened
    ],
)
def test_unique_ids_sorts_and_drops_repeats(ids, expected):
    out = unique_ids(np.asarray(ids, dtype=np.int64))
    assert out.dtype == np.int64 and out.tolist() == expected


def test_compare_with_reference_counts_missed_and_extra_edges():
    # the quad cube lit along +x: the reference silhouette is the four edges of the x = +0.5 quad
    cube = silcount.builtin_mesh("quad_cube")
    light = DirectionalLight((1.0, 0.0, 0.0))
    ref = silcount.detect(cube, light, "reference").edge_ids
    assert ref.size == 4
    others = np.setdiff1d(np.arange(cube.n_edges), ref)
    found = np.sort(np.concatenate([ref[:1], others[:2]]))  # one reference edge and two others
    assert compare_with_reference(cube, light, found) == {
        "missed_edges": 3,
        "extra_edges": 2,
        "disagreement_with_reference": 5,
    }
    assert compare_with_reference(cube, light, ref)["disagreement_with_reference"] == 0


@pytest.mark.parametrize("name", ["reference", "ta", "vnv", "hsd", "eesd"])
def test_every_result_carries_the_mesh_sizes_the_paper_models_take(name):
    # the quad cube by hand: 12 edges, 6 faces, 4 sides per face
    cube = silcount.builtin_mesh("quad_cube")
    res = silcount.detect(cube, DirectionalLight((0.2, 0.3, 1.0)), name)
    assert {k: res.paper_params[k] for k in ("e_n", "f_n", "m")} == {"e_n": 12, "f_n": 6, "m": 4.0}
    assert "missed_edges" not in res.notes  # the comparison with the reference is res.agreement, on request


@pytest.mark.parametrize("name", ["reference", "ta", "vnv", "hsd", "eesd", "gaussmap", "cones"])
def test_detect_runs_no_reference_detection_until_agreement_is_asked_for(name, monkeypatch):
    calls = []
    real = result.silhouette_edge_ids
    monkeypatch.setattr(result, "silhouette_edge_ids", lambda mesh, light: calls.append(1) or real(mesh, light))
    cube = silcount.builtin_mesh("quad_cube")
    res = silcount.detect(cube, DirectionalLight((0.2, 0.3, 1.0)), name)
    assert calls == []
    assert res.agreement == {"missed_edges": 0, "extra_edges": 0, "disagreement_with_reference": 0}
    assert res.agreement is res.agreement  # computed once
    assert len(calls) == (0 if name == "reference" else 1)  # the reference agrees with itself without a rerun


@given(st.sets(st.integers(0, 60)), st.sets(st.integers(0, 60)))
def test_differences_are_the_set_differences(found, reference):
    got = differences(np.array(sorted(found), dtype=np.int64), np.array(sorted(reference), dtype=np.int64))
    missed, extra = len(reference - found), len(found - reference)
    assert got == {"missed_edges": missed, "extra_edges": extra, "disagreement_with_reference": missed + extra}


def test_every_built_in_declares_itself_and_its_paper_model_annotates_it():
    from silcount.counting import models
    from silcount.detectors import DETECTORS, builtin, registry

    assert DETECTORS == ("reference", "ta", "vnv", "hsd", "eesd", "gaussmap", "cones")
    for spec in builtin.specs():
        assert registry.get(spec.name) is spec and registry.source_of(spec.name) == "built-in"
        assert models.load(spec.paper_model)["algorithm"] == spec.name  # the file annotates this detector
        res = spec.detect(silcount.builtin_mesh("tetrahedron"), DirectionalLight((0.2, 0.3, 1.0)))
        assert res.paper_model == spec.paper_model and res.detector == spec.name
        assert callable(spec.plain_edge_ids) and spec.missing == ()


def test_the_registry_names_the_papers_and_their_quadratic_loops():
    # Independent of the modules' declarations: the papers' four (HSD paper Sec. 4, EESD paper Sec. 3),
    # and the two whose printed loops run over every (edge, face) pair (VnV's, EESD's).
    from silcount.detectors import specs, with_role

    assert with_role("paper") == ("ta", "vnv", "hsd", "eesd") and with_role("literature") == ("gaussmap", "cones")
    assert tuple(s.name for s in specs() if s.plain_quadratic) == ("vnv", "eesd")


def test_runs_name_each_distinct_run_as_the_reports_do():
    """The run keys of ``silcount audit`` and ``silcount corpus``, by hand: one run for a one-variant detector."""
    from silcount.detectors import is_reference_run, runs

    got = runs(("reference", "ta", "cones"), ("intended", "literal"))
    assert got == [
        ("reference", "reference", "intended"),
        ("ta", "ta", "intended"),
        ("ta:literal", "ta", "literal"),
        ("cones", "cones", "intended"),
    ]
    assert runs(("hsd",), ("literal",)) == [("hsd:literal", "hsd", "literal")]
    assert is_reference_run("reference", "fast") and not is_reference_run("reference", "naive")
    assert not is_reference_run("ta", "fast")
