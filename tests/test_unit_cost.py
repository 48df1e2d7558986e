"""The ``paper`` cost of one step without sympy (:func:`silcount.counting.models.unit_cost`) against sympy's own
evaluation (:func:`silcount.counting.models.paper_tally`), for every step of every model and beyond them."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from silcount.counting import models as paper

# silcount's own models and the built-in papers' (silcount/models/papers/<paper>/), each loaded by name
FILES = [*paper.models_dir().glob("*.toml"), *paper.models_dir().glob("papers/*/*.toml")]
MODELS = sorted(p.stem for p in FILES if p.name != "paper.toml" and "steps" in paper.load(p.stem))


@pytest.mark.parametrize("model", MODELS)
@settings(max_examples=10, deadline=None)
@given(e_n=st.integers(0, 10**12), f_n=st.integers(0, 10**12), m=st.floats(3.0, 12.0))
def test_every_step_costs_what_sympy_says(model, e_n, f_n, m):
    params = {"e_n": e_n, "f_n": f_n, "m": m}
    for step in paper.load(model)["steps"]:
        assert paper.unit_cost(model, step, params) == paper.paper_tally(model, {step: 1}, params), (model, step)


@settings(max_examples=60, deadline=None)
@given(a=st.integers(-50, 50), b=st.integers(-50, 50), e_n=st.integers(0, 10**9), n=st.integers(1, 10**6))
def test_integer_polynomials_are_evaluated_exactly_and_the_rest_by_sympy(a, b, e_n, n):
    # A user's model may write any expression: integer polynomials are evaluated here, anything else
    # (a division, a power, a symbol with a fractional value such as m) by sympy; both agree.
    costs = {"add": f"{a}*e_n - ({b})*n + 3*(2+e_n)", "mul": "e_n/2", "cmp": f"m*{a}", "read": "e_n**2", "write": "-n"}
    params = {"e_n": e_n, "n": n, "m": 4.5, "f_n": 7}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(paper, "load", lambda name: {"steps": {"s": {"cost": {name: costs[name]}}}})
        for kind, text in costs.items():
            paper.step_costs.cache_clear()
            assert paper.unit_cost(kind, "s", params) == paper.paper_tally(kind, {"s": 1}, params), text
    paper.step_costs.cache_clear()


def test_a_step_without_a_cost_costs_nothing():
    assert paper.unit_cost("hsd2011-hsd", "no such step", {"e_n": 5}) == {k: 0 for k in paper.KINDS}
