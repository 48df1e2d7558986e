"""The re-derivation (silcount/formulas.py) against brute force and the paper text.

Independent checks: the loop structure of each printed pseudo-code is written
out here as Python loops that add the per-line costs (EESD paper Sec. 5.1-5.3,
HSD paper Sec. VI); TA's add/delete branch counts are checked by running the
array-S algorithm on real closed meshes; printed lines are re-parsed from the
text with sympy's implicit multiplication.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from sympy.parsing.sympy_parser import (
    convert_xor,
    implicit_multiplication_application,
    parse_expr,
    split_symbols,
    standard_transformations,
)

import silcount
from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.papers import formulas as F
from silcount.papers import primitives

MODELS = ("eesd2012-ta", "eesd2012-vnv", "eesd2012-eesd", "hsd2011-ta", "hsd2011-vnv", "hsd2011-hsd")


def _cost(model: str, step: str) -> dict[str, int]:
    """A step's annotated cost at numeric e_n (read from silcount/models/: the per-line costs are data)."""
    return {k: v for k, v in models.load(model)["steps"][step].get("cost", {}).items()}


def _add(total, model, step, e):
    for kind, expr in _cost(model, step).items():
        total[kind] += int(F.parse(expr).subs(F.e_n, e))


def brute_printed_charge(model: str, f: int, e: int, m: int) -> dict[str, int]:
    """The printed sums' loops, executed: every conditional line charged every time (as the sums do)."""
    total = dict.fromkeys(KINDS, 0)
    algorithm = models.load(model)["algorithm"]
    if algorithm in ("ta", "hsd"):
        sides = m if algorithm == "ta" else 1  # HSD's printed sum: one side per polygon
        for _face in range(f):
            _add(total, model, "visibility", e)
            for _side in range(sides):
                _add(total, model, "search_S", e)
                _add(total, model, "delete", e)  # the sums charge the delete branch, never add
    elif algorithm == "vnv":
        for _edge in range(e):
            for _face in range(f):
                _add(total, model, "visibility", e)
                _add(total, model, "counter", e)
            _add(total, model, "check_counter", e)
            _add(total, model, "add", e)
    else:  # eesd
        for _edge in range(e):
            _add(total, model, "extend", e)
            _add(total, model, "ray", e)
            for _face in range(f):
                _add(total, model, "intersection", e)
    return total


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("f, e, m", [(1, 1, 1), (3, 5, 3), (4, 6, 3), (7, 9, 4), (5, 12, 6)])
def test_charged_sum_equals_brute_force_loops(model, f, e, m):
    expected = brute_printed_charge(model, f, e, m)
    got = {k: int(x.subs({F.f_n: f, F.e_n: e, F.m: m})) for k, x in F.charged(model).items()}
    assert got == expected


@pytest.mark.parametrize("model", MODELS)
def test_printed_first_line_is_the_charged_sum(model):
    # the first printed line is the per-line costs times the printed loop charges, term by term
    assert F.difference(F.printed_lines(model)[0].form, F.charged(model)) == {}


_T = standard_transformations + (split_symbols, implicit_multiplication_application, convert_xor)


@pytest.mark.parametrize("model", MODELS)
def test_transcriptions_match_the_printed_text(model):
    ren = {F.e_n: sp.Symbol("e"), F.f_n: sp.Symbol("f"), F.n: sp.Symbol("n"), F.m: sp.Symbol("m")}
    for line in models.load(model)["closed_form"]["lines"]:
        text = line["printed"].lstrip("= ").replace("^*", "*").replace("e_n", "e").replace("f_n", "f").replace(" ", "")
        parsed = parse_expr(text, transformations=_T)
        assert sp.expand(parsed - F.parse(line["expr"]).subs(ren)) == 0, line["printed"]


def test_ta_final_line_drops_the_visibility_compares():
    # line 2 has n*(1C + 6nmC); the printed line 3 keeps only 6n^2 m C (Sec. 5.1)
    steps = F.expansion_steps("eesd2012-ta")
    assert steps[0][2] == {}
    assert steps[1][2] == {"cmp": -F.n}


def test_vnv_eesd_hsd_expansions_are_consistent():
    for model in ("eesd2012-vnv", "eesd2012-eesd", "hsd2011-hsd"):
        assert all(diff == {} for *_, diff in F.expansion_steps(model))


def test_printed_forms_at_table_one_by_hand():
    # hand arithmetic at n=10, m=5 from the printed last lines (EESD Sec. 5.1-5.3)
    ta = F.evaluate(F.printed_final("eesd2012-ta"), n=10, m=5)
    assert ta["read"] == 6 * 100 * 5 + 5 * 10 + 8 * 10 == 3130
    vnv = F.evaluate(F.printed_final("eesd2012-vnv"), n=100, m=10)
    assert vnv["read"] == 48 * 100**2 + 6 * 100 == 480600
    eesd = F.evaluate(F.printed_final("eesd2012-eesd"), n=10, m=5)
    assert (eesd["mul"], eesd["add"]) == (18 * 100 + 180, 18 * 100 + 360)


def test_paper_cycle_totals_by_hand():
    w = {"mul": 4, "add": 2, "cmp": 3, "read": 1, "write": 2}
    n, m = F.n, F.m
    # TA: 3*6n^2m + (6n^2m + mn + 8n) + 4(m+10)n + 2*8n + 2*2mn
    assert sp.expand(F.weighted(F.printed_final("eesd2012-ta"), w) - (24 * n**2 * m + 9 * m * n + 64 * n)) == 0
    # HSD: 3(6n^2+n) + (6n^2+9n) + 4*11n + 2*8n + 2*2n
    assert sp.expand(F.weighted(F.printed_final("hsd2011-hsd"), w) - (24 * n**2 + 76 * n)) == 0
    # VnV: 240n^2 + 108n^2 + 18n^2 + 18n + 48n^2 + 6n + 12n ; EESD: 72n^2+72n + 36n^2+72n + 18n^2 + 12n + 24n
    assert sp.expand(F.weighted(F.printed_final("eesd2012-vnv"), w) - (414 * n**2 + 36 * n)) == 0
    assert sp.expand(F.weighted(F.printed_final("eesd2012-eesd"), w) - (126 * n**2 + 180 * n)) == 0


def _ta_branch_counts(mesh, light):
    """Run TA's array S (starting empty) over light-facing faces; count adds and deletes."""
    facing = (
        silcount.mesh.lights.facing_values(mesh.face_p0, mesh.face_normals, light) > 0.0
    )  # independent of the detectors
    S: list[tuple[int, int]] = []
    adds = deletes = 0
    for p in np.flatnonzero(facing):
        corners = mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]]
        for a, b in zip(corners, np.roll(corners, -1)):
            if (b, a) in S:
                S.remove((b, a))
                deletes += 1
            else:
                S.append((a, b))
                adds += 1
    return adds, deletes, int(facing.sum()), len(S)


@pytest.mark.parametrize("name", ["tetrahedron", "quad_cube", "icosahedron", "torus", "icosphere2"])
def test_ta_branch_fractions_match_simulation(name):
    mesh = silcount.builtin_mesh(name)
    light = silcount.PointLight(tuple(mesh.centre + np.array([2.0, 3.0, 5.0]) * mesh.bounding_radius))
    adds, deletes, visible, sil = _ta_branch_counts(mesh, light)
    subs = {
        F.f_n: mesh.n_faces,
        F.e_n: mesh.n_edges,
        F.m: sp.Rational(mesh.n_sides, mesh.n_faces),
        F.v: sp.Rational(visible, mesh.n_faces),
        F.s: sp.Rational(sil, mesh.n_edges),
    }
    assert F.step_runs("eesd2012-ta", "add")[1].subs(subs) == adds
    assert F.step_runs("eesd2012-ta", "delete")[1].subs(subs) == deletes
    assert F.step_runs("eesd2012-ta", "search_S")[1].subs(subs) == adds + deletes


@pytest.mark.parametrize(
    "kernel, expected",
    [
        ("dot", {"mul": 3, "add": 2}),  # a0b0 + a1b1 + a2b2
        ("vector_add", {"add": 3}),
        ("ray_point", {"mul": 3, "add": 3}),  # x0 + t d
        ("light_vector", {"add": 3}),  # L - p0
        ("normal_from_corners", {"add": 9, "mul": 6}),  # 2 differences (6A) + cross product (6M + 3A)
        ("light_vector_homogeneous", {"add": 3, "mul": 3}),  # L - w p0
        ("edge_inverse", {}),  # a swap of two ids
        ("point_in_plane", {"mul": 3, "add": 3, "cmp": 1}),  # a Rx + b Ry + c Rz + d == 0
        ("ray_plane", {"mul": 7, "add": 5, "cmp": 1}),  # (n.x0 + d) (3M 3A), n.dir (3M 2A), product sign (1M 1C)
        ("visibility_precomputed", {"add": 5, "mul": 3, "cmp": 1}),  # L - p0, dot, sign
    ],
)
def test_kernel_costs_by_hand(kernel, expected):
    assert primitives.kernel_cost(kernel) == expected


def test_corrected_visibility_cost_is_what_the_detectors_execute():
    from silcount.detectors.base import visibility_true_cost

    measured = visibility_true_cost(silcount.PointLight((0.0, 0.0, 5.0)))
    for model in (m for m in MODELS if "visibility" in models.load(m)["steps"]):
        spec = models.load(model)["steps"]["visibility"]["cost_corrected"]
        assert {k: int(v) for k, v in spec.items()} == measured


def test_rederived_hsd_uses_m_minus_one():
    form = F.forms("hsd2011-hsd")["rederived"]
    # search: f_n (m-1) e_n compares + one visibility compare per polygon
    assert sp.expand(form["cmp"] - (6 * F.n**2 * (F.m - 1) + F.n)) == 0


def test_leading_and_degree():
    assert F.leading(3 * F.n**2 * F.m + F.n) == 3 * F.n**2 * F.m
    assert F.degree(F.weighted(F.forms("eesd2012-eesd")["rederived"], dict.fromkeys(KINDS, 1))) == 2


def _brute_convention(model: str, f: int, e: int, m: int, worst: bool) -> dict[str, int]:
    """The pseudo-code's loops executed by hand: every condition true (convention) or the dearer arm per kind."""
    total = dict.fromkeys(KINDS, 0)
    algorithm = models.load(model)["algorithm"]

    def arm(*steps_):
        out = dict.fromkeys(KINDS, 0)
        for step in steps_:
            _add(out, model, step, e)
        return out

    def charge(cost):
        for k in KINDS:
            total[k] += cost[k]

    if algorithm in ("ta", "hsd"):
        then, other = arm("delete"), arm("add")
        branch = {k: max(then[k], other[k]) for k in KINDS} if worst else then
        for _face in range(f):
            _add(total, model, "visibility", e)
            for _side in range(m):
                _add(total, model, "search_S", e)
                charge(branch)
    elif algorithm == "vnv":
        for _edge in range(e):
            for _face in range(f):
                _add(total, model, "visibility", e)
                _add(total, model, "counter", e)
            _add(total, model, "check_counter", e)
            _add(total, model, "add", e)
    else:
        for _edge in range(e):
            _add(total, model, "extend", e)
            _add(total, model, "ray", e)
            for _face in range(f):
                _add(total, model, "intersection", e)
                _add(total, model, "add", e)
    return total


@pytest.mark.parametrize("model", ("eesd2012-ta", "eesd2012-vnv", "eesd2012-eesd", "hsd2011-ta", "hsd2011-vnv"))
@pytest.mark.parametrize("f, e, m", [(1, 1, 1), (4, 6, 3), (7, 9, 4)])
def test_convention_and_worst_case_equal_the_loops_run_by_hand(model, f, e, m):
    for worst, form in ((False, F.convention(model)), (True, F.worst_case(model))):
        got = {k: int(x.subs({F.f_n: f, F.e_n: e, F.m: m})) for k, x in form.items()}
        assert got == _brute_convention(model, f, e, m, worst), (model, worst)


def test_the_papers_convention_is_the_first_printed_line_for_ta_and_vnv():
    for model in ("eesd2012-ta", "eesd2012-vnv", "hsd2011-ta", "hsd2011-vnv"):
        assert F.difference(F.convention(model), F.printed_lines(model)[0].form) == {}
    # EESD: the annotated 1Add of 'Add v1v2 to S' per (edge, face) is missing from the printed line
    assert F.difference(F.convention("eesd2012-eesd"), F.printed_lines("eesd2012-eesd")[0].form) == {
        "add": F.e_n * F.f_n
    }


def test_worst_case_charges_the_hsd_papers_dearer_add():
    # HSD paper 6.1: add = 1W + 1R + 2W = 3W, delete = 1R + 2W: the worst case writes 3 per side
    assert sp.expand(F.worst_case("hsd2011-ta")["write"] - 3 * F.f_n * F.m) == 0
    assert sp.expand(F.worst_case("eesd2012-ta")["write"] - 2 * F.f_n * F.m) == 0


def test_hsd_readings_give_the_printed_sum_or_m_minus_one():
    one, minus = F.readings("hsd2011-hsd")
    assert F.difference(F.convention("hsd2011-hsd", one), F.printed_lines("hsd2011-hsd")[0].form) == {}
    assert sp.expand(F.convention("hsd2011-hsd", minus)["cmp"] - F.f_n * (1 + (F.m - 1) * F.e_n)) == 0


@pytest.mark.parametrize("model", ["hsd2011-vnv", "eesd2012-vnv"])
def test_corrected_vnv_differs_from_the_rederived_by_the_visibility_step_alone(model):
    # VnV runs the visibility test once per (edge, face) pair: printed 8A + 10M + 1C + 8R, executed
    # 14A + 9M + 1C + 16R (the test above), so correcting it adds 6 e_n f_n adds, 8 e_n f_n reads and
    # removes e_n f_n multiplies; nothing else changes.
    e, f = F.e_n, F.f_n
    corrected, rederived = F.rederive(model, corrected=True), F.rederive(model)
    diff = {k: sp.expand(corrected[k] - rederived[k]) for k in corrected}
    assert diff == {k: 0 for k in KINDS} | {"add": 6 * e * f, "mul": -e * f, "read": 8 * e * f}


def test_max_of_two_costs_by_hand():
    n, m = sp.symbols("n m", positive=True)
    assert F._max(0, 5) == 5 and F._max(5, 0) == 5  # a zero cost: the other one
    assert F._max(1, 5) == 5 and F._max(3, 2) == 3  # numbers
    assert F._max(n * m, n * m + n) == n * m + n  # the difference -n: the second
    assert F._max(n * m + n / 2, n * m) == n * m + n / 2  # the difference n/2, a fraction: the first
    assert F._max(n, m) == sp.Max(n, m)  # the difference n - m has both signs: undecided
    assert F._max(2 * n, n + 1) == sp.Max(2 * n, n + 1)


def test_show_prints_a_form_as_the_papers_do():
    # multiplies first, then adds, compares, reads, writes; a zero kind is left out, a coefficient of 1 kept
    n, m = F.n, F.m
    form = {"add": sp.Integer(1), "mul": 2 * n * m + n, "cmp": sp.Integer(0), "read": 3 * n, "write": sp.Integer(0)}
    assert F.show(form) == "(n*(2*m + 1))M + (1)A + (3*n)R"
    assert F.show({k: sp.Integer(0) for k in KINDS}) == "0"


def test_forms_in_n_carry_the_corrected_visibility_cost():
    # forms() is what the figures draw.  In n (f_n = n, e_n = 6n), VnV's corrected visibility step adds
    # 6 * 6n * n = 36 n^2 adds and 8 * 6n^2 = 48 n^2 reads and removes 6 n^2 multiplies (see above).
    n = F.n
    forms = F.forms("hsd2011-vnv")
    diff = {k: sp.expand(forms["corrected"][k] - forms["rederived"][k]) for k in KINDS}
    assert diff == {k: 0 for k in KINDS} | {"add": 36 * n**2, "mul": -6 * n**2, "read": 48 * n**2}
    assert forms["printed"] == F.printed_final("hsd2011-vnv")
