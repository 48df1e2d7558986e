"""``silcount.testing``: the public assertion passes on the same result and names each field that differs."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import silcount
from silcount import PointLight
from silcount.testing import assert_silhouettes_equal

LIGHT = PointLight((2.0, 3.0, 5.0))


def _run(engine: str = "fast"):
    return silcount.detect(silcount.builtin_mesh("triangle_cube"), LIGHT, "ta", "intended", engine)


def test_the_same_run_twice_is_equal():
    assert_silhouettes_equal(_run(), _run())


def test_naive_and_fast_are_equal_but_for_the_engine():
    naive, fast = _run("naive"), _run("fast")
    assert_silhouettes_equal(naive, fast, check_engine=False)
    with pytest.raises(AssertionError, match="differ in engine"):
        assert_silhouettes_equal(naive, fast)


@pytest.mark.parametrize(
    "field, value",
    [
        ("edge_ids", np.array([0, 1, 2])),
        ("detector", "vnv"),
        ("variant", "literal"),
        ("paper_model", "hsd2011-ta"),
        ("paper_params", {"f_n": 1.0}),
        ("steps", {"visibility": -1}),
        ("true_tally", {"add": -1}),
        ("ties", 99),
        ("notes", {"planted": True}),
    ],
)
def test_each_field_that_differs_is_named(field, value):
    a = _run()
    b = dataclasses.replace(a, **{field: value})
    with pytest.raises(AssertionError, match=f"differ in {field}"):
        assert_silhouettes_equal(a, b)


def test_ignored_notes_are_left_out():
    a = _run()
    b = dataclasses.replace(a, notes=a.notes | {"rays_cast": 7})
    assert_silhouettes_equal(a, b, ignore_notes={"rays_cast"})
    with pytest.raises(AssertionError, match="differ in notes"):
        assert_silhouettes_equal(a, b)
