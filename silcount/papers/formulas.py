"""Re-derivation of the papers' closed forms with sympy.

Each algorithm's model file (``models/<paper>-<algorithm>.toml``) gives the
per-line costs as annotated (``cost``), how often the printed sum charges each
line (``runs``), the pseudo-code's loop structure (``within`` the loops of
``[loops]``, reached on a ``branch`` fraction of their iterations), corrected
per-line costs (``cost_corrected``) and the printed expansion line by line
(``[closed_form]``).  From these this module computes, per operation kind:

* :func:`charged`: ``sum(runs * cost)``: what the printed sum charges;
* :func:`rederive`: ``sum(prod(loop bounds) * branch * cost)``: what the
  pseudo-code executes, symbolic in ``v`` (fraction of faces light-facing) and
  ``s`` (fraction of edges that are silhouette edges) on a closed 2-manifold;
* :func:`printed_lines`: each printed line parsed by kind;

and compares them term by term (:func:`expansion_steps`,
:func:`rederivation_differences`).  The papers' own evaluation point is
``v = 1, s = 0`` (``[evaluation]`` of the paper file): the printed TA sum
runs the side loop for every face, which is exact only when every face is
light-facing, and then a closed mesh has no silhouette edge.

Kind symbols in printed forms: A (add), M (mul), C (cmp), R (read), W (write).
Sources: EESD paper Sec. 5.1-5.3; HSD paper Sec. VI 6.1-6.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import sympy as sp

from silcount.counting import paper as models
from silcount.counting.arithmetic import KINDS, Num, OpCounter

n, f_n, e_n, m = (models.symbols()[k] for k in ("n", "f_n", "e_n", "m"))
v, s = sp.Symbol("v", nonnegative=True), sp.Symbol("s", nonnegative=True)
KIND_SYMBOLS = {kind: sp.Symbol(sym) for kind, sym in zip(KINDS, "AMCRW")}
LOCALS = {**models.symbols(), "v": v, "s": s, **{str(sym): sym for sym in KIND_SYMBOLS.values()}}

Form = dict[str, sp.Expr]
"""A cost as a sympy expression per operation kind."""


def parse(text: str | int) -> sp.Expr:
    """A cost expression from models/ (symbols n, f_n, e_n, m, v, s, A, M, C, R, W)."""
    return sp.sympify(str(text), locals=LOCALS)


def by_kind(expr: sp.Expr) -> Form:
    """Split a printed form ``a*A + b*M + ...`` into its coefficient per kind."""
    poly = sp.expand(expr)
    out = {kind: sp.expand(poly.coeff(sym)) for kind, sym in KIND_SYMBOLS.items()}
    rest = sp.expand(poly - sum(out[k] * KIND_SYMBOLS[k] for k in KINDS))
    if rest != 0:
        raise ValueError(f"form has a term without an operation kind: {rest}")
    return out


def zero_form() -> Form:
    return {k: sp.Integer(0) for k in KINDS}


def _step_cost(spec: dict, corrected: bool) -> Form:
    cost = spec.get("cost_corrected") if corrected and "cost_corrected" in spec else spec.get("cost", {})
    form = zero_form()
    for kind, value in cost.items():
        form[kind] = parse(value)
    return form


def steps(model: str) -> dict[str, dict]:
    return models.load(model).get("steps", {})


def step_runs(model: str, step: str) -> tuple[sp.Expr, sp.Expr]:
    """(runs charged by the printed sum, runs by the pseudo-code's loop structure)."""
    spec = steps(model)[step]
    loops = models.load(model).get("loops", {})
    structure = sp.Integer(1)
    for name in spec.get("within", []):
        structure *= parse(loops[name]["bound"])
    return parse(spec.get("runs", "0")), sp.simplify(structure * parse(spec.get("branch", "1")))


def _sum_over_steps(model: str, structural: bool, corrected: bool) -> Form:
    """``sum(runs * cost)`` over the steps, with the printed or the structural run counts."""
    total = zero_form()
    for step, spec in steps(model).items():
        runs = step_runs(model, step)[1 if structural else 0]
        for kind, c in _step_cost(spec, corrected).items():
            total[kind] += runs * c
    return {k: sp.expand(x) for k, x in total.items()}


@cache
def charged(model: str) -> Form:
    """``sum(runs * cost)`` over the steps: the printed sum, rebuilt from its lines."""
    return _sum_over_steps(model, structural=False, corrected=False)


@cache
def rederive(model: str, corrected: bool = False) -> Form:
    """``sum(loop bounds * branch * cost)``: the pseudo-code's cost, symbolic in v and s."""
    return _sum_over_steps(model, structural=True, corrected=corrected)


def paper_file(model: str) -> str:
    return models.load(model)["closed_form"]["substitutions"]


def substitutions(model: str) -> dict[sp.Symbol, sp.Expr]:
    """The paper's substitutions f_n -> n, e_n -> 6n."""
    sub = models.load(paper_file(model))["substitutions"]
    return {f_n: parse(sub["f_n"]), e_n: parse(sub["e_n"])}


def evaluation_point(model: str) -> dict[sp.Symbol, sp.Expr]:
    """The (v, s) at which the printed sums are meant (the paper file's ``[evaluation]``)."""
    ev = models.load(paper_file(model))["evaluation"]
    return {v: parse(ev["v"]), s: parse(ev["s"])}


def in_n(form: Form, model: str) -> Form:
    """A form with the paper's substitutions and evaluation point applied: a function of n and m."""
    subs = {**substitutions(model), **evaluation_point(model)}
    return {k: sp.expand(x.subs(subs)) for k, x in form.items()}


@dataclass(frozen=True)
class PrintedLine:
    printed: str
    form: Form


@cache
def printed_lines(model: str) -> tuple[PrintedLine, ...]:
    """Every printed line of the model's closed form, split by kind."""
    lines = models.load(model)["closed_form"]["lines"]
    return tuple(PrintedLine(line["printed"], by_kind(parse(line["expr"]))) for line in lines)


def printed_final(model: str) -> Form:
    """The last printed line: the closed form in n and m."""
    return printed_lines(model)[-1].form


def difference(a: Form, b: Form) -> Form:
    """``a - b`` per kind, only the kinds that differ."""
    return {k: sp.expand(a[k] - b[k]) for k in KINDS if sp.expand(a[k] - b[k]) != 0}


def expansion_steps(model: str) -> list[tuple[str, str, Form]]:
    """Each printed line against the previous one (after the substitutions): (previous, line, difference)."""
    lines = printed_lines(model)
    subs = substitutions(model)
    out = []
    for prev, cur in zip(lines, lines[1:]):
        prev_n = {k: sp.expand(x.subs(subs)) for k, x in prev.form.items()}
        out.append((prev.printed, cur.printed, difference(cur.form, prev_n)))
    return out


@dataclass(frozen=True)
class StepDifference:
    step: str
    line: str
    printed_runs: sp.Expr
    derived_runs: sp.Expr
    kinds: Form  # derived - printed, per kind, at the evaluation point
    note: str


@cache
def rederivation_differences(model: str) -> tuple[StepDifference, ...]:
    """Steps whose charge in the printed sum differs from the loop structure, at the evaluation point."""
    out = []
    point = evaluation_point(model)
    for step, spec in steps(model).items():
        printed, derived = step_runs(model, step)
        cost = _step_cost(spec, False)
        diff = {k: sp.factor(sp.expand((derived - printed).subs(point) * c)) for k, c in cost.items()}
        diff = {k: d for k, d in diff.items() if d != 0}
        if sp.simplify(printed - derived) != 0:
            out.append(
                StepDifference(
                    step, spec.get("line", ""), printed, derived, diff, spec.get("branch_note", spec.get("note", ""))
                )
            )
    return tuple(out)


def evaluate(form: Form, **point) -> dict[str, sp.Expr]:
    """A form evaluated at ``n=..., m=...`` (exact rationals)."""
    subs = {LOCALS[k]: sp.nsimplify(val) for k, val in point.items()}
    return {k: sp.nsimplify(x.subs(subs)) for k, x in form.items()}


def weighted(form: Form, weights: dict[str, float]) -> sp.Expr:
    """Cycle-weighted total of a form."""
    return sp.expand(sum(sp.nsimplify(weights.get(k, 0)) * x for k, x in form.items()))


def leading(expr: sp.Expr, var: sp.Symbol = n) -> sp.Expr:
    """The leading term of ``expr`` as ``var`` grows."""
    poly = sp.Poly(sp.expand(expr), var)
    deg = poly.degree()
    return sp.expand(poly.coeff_monomial(var**deg) * var**deg)


def degree(expr: sp.Expr, var: sp.Symbol = n) -> int:
    return sp.Poly(sp.expand(expr), var).degree()


@cache
def forms(model: str) -> dict[str, Form]:
    """The three forms of a model in n and m: ``printed`` (last line), ``rederived``, ``corrected``.

    Cached: treat the result as read-only.
    """
    return {
        "printed": printed_final(model),
        "rederived": in_n(rederive(model), model),
        "corrected": in_n(rederive(model, corrected=True), model),
    }


# --- Kernels: the papers' per-line operations, executed on counting arithmetic.


def _vec(counter: OpCounter, *vals: float) -> list[Num]:
    return [Num(x, counter) for x in vals]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _kernel_dot(c):
    _dot(_vec(c, 1, 2, 3), _vec(c, 4, 5, 6))


def _kernel_vector_add(c):
    a, b = _vec(c, 1, 2, 3), _vec(c, 4, 5, 6)
    [a[i] + b[i] for i in range(3)]


def _kernel_ray_point(c):
    x0, d, t = _vec(c, 1, 2, 3), _vec(c, 4, 5, 6), Num(0.5, c)
    [x0[i] + t * d[i] for i in range(3)]


def _kernel_light_vector(c):
    light, p0 = _vec(c, 0, 0, 5), _vec(c, 1, 0, 0)
    [light[i] - p0[i] for i in range(3)]


def _kernel_normal(c):
    p0, p1, p2 = _vec(c, 1, 0, 0), _vec(c, 0, 1, 0), _vec(c, 0, 0, 1)
    e1 = [p1[i] - p0[i] for i in range(3)]
    e2 = [p2[i] - p0[i] for i in range(3)]
    [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]


def _kernel_visibility(c):
    from silcount.detectors.base import visibility_true_cost
    from silcount.mesh.lights import PointLight

    c.update(visibility_true_cost(PointLight((0.0, 0.0, 5.0))))


KERNELS = {
    "dot": (_kernel_dot, "a.b on counting arithmetic"),
    "vector_add": (_kernel_vector_add, "a+b, three components"),
    "ray_point": (_kernel_ray_point, "x0 + t d"),
    "light_vector": (_kernel_light_vector, "L - p0"),
    "normal_from_corners": (_kernel_normal, "(p1-p0) x (p2-p0)"),
    "visibility": (_kernel_visibility, "silcount's counted_visibility (point light)"),
}


def kernel_cost(name: str) -> dict[str, int]:
    """What kernel ``name`` costs, measured by executing it on counting arithmetic."""
    counter = OpCounter()
    KERNELS[name][0](counter)
    return {k: int(x) for k, x in counter.items() if x}


def show(form: Form) -> str:
    """A form as the papers print it: ``(...)M + (...)A + ...``."""
    order = ("mul", "add", "cmp", "read", "write")
    sym = {k: str(KIND_SYMBOLS[k]) for k in KINDS}
    parts = [f"({sp.sstr(sp.factor_terms(form[k]))}){sym[k]}" for k in order if form[k] != 0]
    return " + ".join(parts) if parts else "0"
