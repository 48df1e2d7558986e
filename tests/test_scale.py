"""The sweep-time model (``silcount.study.scale``): list scheduling and the formula, by hand."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from silcount.study import scale


def toy(**over) -> scale.SweepProfile:
    data = {
        "about": {"machine": "m", "date": "d", "settings": "s"},
        "units": [["a.obj", 0, 300, 10, 3.0], ["b.obj", 0, 200, 8, 2.0], ["c.obj", 0, 100, 4, 2.0]],
        "startup_s": 1.0,
        "task_overhead_s": 0.0,
        "client_per_unit_s": 0.0,
        "client_final_per_unit_s": 0.0,
        "measured": {"1x1": 8.0, "2": 5.0},
    }
    return scale.SweepProfile.from_dict({**data, **over})


def test_makespan_by_hand():
    seconds, size = np.array([3.0, 2.0, 2.0]), np.array([300, 200, 100])
    assert scale.makespan(seconds, size, 1) == 7.0
    assert scale.makespan(seconds, size, 2) == 4.0  # 3 | 2 + 2
    assert scale.makespan(seconds, size, 3) == 3.0
    # the order is by size, not by time: the 3 s unit last on two workers gives 2 | 2 + 3
    assert scale.makespan(seconds, np.array([100, 200, 300]), 2) == 5.0


@given(st.lists(st.floats(0.0, 100.0), min_size=1, max_size=30), st.integers(1, 8))
def test_makespan_lies_between_the_bounds_of_list_scheduling(seconds, workers):
    t = np.array(seconds)
    span = scale.makespan(t, np.arange(t.size), workers)
    lower = max(t.max(), t.sum() / workers)
    assert lower - 1e-9 <= span <= t.sum() / workers + t.max() + 1e-9  # Graham's bound


def test_predict_adds_start_up_overheads_and_the_client():
    p = toy(task_overhead_s=0.5, client_final_per_unit_s=0.25)
    u = p.units
    # 1 + (3.5 | 2.5 + 2.5) + 3 * 0.25
    assert scale.predict(p, u["seconds"].to_numpy(), u["bytes"].to_numpy(), 2) == pytest.approx(1 + 5.0 + 0.75)
    slow_client = toy(client_per_unit_s=10.0)  # a client slower than the workers bounds the sweep
    assert scale.predict(slow_client, u["seconds"].to_numpy(), u["bytes"].to_numpy(), 2) == pytest.approx(31.0)


def test_check_and_estimate():
    c = scale.check(toy())
    assert c["model_s"].tolist() == [8.0, 5.0] and c["within_tolerance"].all()
    e = scale.estimate(toy(), units=1000, workers=(1, 4))
    assert e["wall_s"].iloc[0] > 3.9 * (e["wall_s"].iloc[1] - 1.0)  # four workers: about a quarter of the work
    assert e.equals(scale.estimate(toy(), units=1000, workers=(1, 4)))  # seeded


def test_the_committed_profile_renders():
    text = scale.page(scale.load_profile())
    assert "## The model against the real sweep" in text and "| 64 |" in text
