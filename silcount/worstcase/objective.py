"""What the worst-case search maximises: a run's cost in one cost model and kind (or cycles), and bounds on it.

:class:`Measure` prices one detector run (``fast`` engine, whose step counts and ``true`` tally are those of
the ``naive`` engine, ``tests/test_engines.py``): the ``true`` or ``paper`` tally (``docs/counting.md``), one
operation kind, their ``total``, or cycles under a profile (:mod:`silcount.counting.cycles`).
:class:`Bound` is what an execution must exceed: a paper's printed line (``MODEL`` or ``MODEL:LINE``, from the
model's ``[closed_form]``, as :func:`silcount.papers.formulas.printed_lines` reads it) or a closed form
typed in (symbols ``n``, ``f_n``, ``e_n``, ``m``; with the kind symbols ``A M C R W`` per kind, without them
for the measured quantity), evaluated at the run's own ``f_n``, ``e_n``, ``m`` (and ``n = f_n``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from typing import Any

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.detectors import detect
from silcount.detectors.registry import get
from silcount.detectors.result import Silhouette
from silcount.errors import BadArgument
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh
from silcount.options import WORST_CASE_KINDS

COST_MODELS = ("true", "paper")
OP_KINDS = WORST_CASE_KINDS
KIND_LETTERS = dict(zip("AMCRW", KINDS))


@dataclass(frozen=True)
class Measure:
    """Which cost of a run the search reads: ``detector`` (its ``variant``; ``None``: every variant it has, the
    dearest counting), ``model`` and ``kind``, or cycles under ``profile`` (a :mod:`silcount.counting.cycles`
    profile name or file); ``pricing``: the model file whose annotations price the ``paper`` cost model (the
    detector's own by default; a printed line's own model when the bound is one)."""

    detector: str
    model: str = "true"
    kind: str = "total"
    variant: str | None = "intended"
    profile: str | None = None
    pricing: str | None = None

    def __post_init__(self) -> None:
        spec = get(self.detector)
        if self.model not in COST_MODELS:
            raise BadArgument(f"cost model {self.model!r}: one of {', '.join(COST_MODELS)}")
        if self.model == "paper" and spec.paper_model is None:
            raise BadArgument(f"detector {self.detector!r} has no paper cost model")
        if self.kind not in OP_KINDS:
            raise BadArgument(f"operation kind {self.kind!r}: one of {', '.join(OP_KINDS)}")
        if self.variant is not None and self.variant not in spec.variants:
            raise BadArgument(f"detector {self.detector!r} has no variant {self.variant!r}")
        if self.profile is not None:
            from silcount.counting.cycles import load_profile

            load_profile(self.profile)  # an unknown profile fails here, before any run

    @property
    def variants(self) -> tuple[str, ...]:
        return get(self.detector).variants if self.variant is None else (self.variant,)

    def run(self, mesh: Mesh, light: Light, variant: str) -> Silhouette:
        return detect(mesh, light, self.detector, variant=variant, engine="fast")

    def tally(self, run: Silhouette) -> dict[str, int]:
        if self.model == "paper" and self.pricing is not None:
            return models.paper_tally(self.pricing, run.steps, run.paper_params)
        return dict(run.tally[self.model])

    def value(self, tally: dict[str, int]) -> float:
        """The measured quantity of a tally: one kind, the total of the five, or cycles."""
        if self.profile is not None:
            from silcount.counting.cycles import load_profile

            return float(load_profile(self.profile).cycles(tally))
        if self.kind in ("total", "any"):
            return float(sum(tally.get(k, 0) for k in KINDS))
        return float(tally.get(self.kind, 0))

    def describe(self) -> str:
        what = f"cycles ({self.profile})" if self.profile else self.kind
        variant = self.variant or "every variant"
        priced = f" priced by {self.pricing}" if self.model == "paper" and self.pricing else ""
        return f"{self.detector} ({variant}), {self.model} cost model{priced}, {what}"


@dataclass(frozen=True)
class Bound:
    """A bound per kind, as sympy expressions in ``n, f_n, e_n, m`` (``per_kind``), or one for the measured
    quantity (``scalar``); ``text`` says where it came from."""

    text: str
    per_kind: dict = field(default_factory=dict)
    scalar: Any = None
    model: str | None = None  # the model file of a printed line

    def at(self, params: dict) -> dict[str, float]:
        """The bound at a run's own ``f_n``, ``e_n``, ``m`` (``n`` is ``f_n``): kind -> value, or ``{"value": x}``."""
        sym = models.symbols()
        subs = {sym[k]: params[k] for k in ("f_n", "e_n", "m") if k in params}
        subs[sym["n"]] = params.get("f_n", 0)
        if self.scalar is not None:
            return {"value": float(self.scalar.subs(subs))}
        return {k: float(x.subs(subs)) for k, x in self.per_kind.items()}


def parse_bound(text: str) -> Bound:
    """``MODEL`` or ``MODEL:LINE`` (the model's printed line, 1-based; the first by default), or a closed form."""
    import sympy as sp

    name, _, line = text.partition(":")
    if "(" not in name and "*" not in name and models.model_path(name).is_file():
        lines = models.load(name).get("closed_form", {}).get("lines", [])
        i = int(line) - 1 if line.isdigit() else 0
        if not lines or not 0 <= i < len(lines):
            raise BadArgument(f"bound {text!r}: model {name} has no printed line {i + 1}")
        out = _split(sp, lines[i]["expr"], f"{name} printed line {i + 1}: {lines[i]['printed']}")
        return Bound(out.text, out.per_kind, out.scalar, model=name)
    return _split(sp, text, f"closed form {text}")


@cache
def _letters():
    import sympy as sp

    return {letter: sp.Symbol(letter) for letter in KIND_LETTERS}


def _split(sp, text: str, what: str) -> Bound:
    letters = _letters()
    try:
        expr = sp.sympify(text, locals={**models.symbols(), **letters})
    except (sp.SympifyError, SyntaxError, TypeError):
        raise BadArgument(f"bound {text!r} is not a closed form in n, f_n, e_n, m (and A, M, C, R, W)") from None
    allowed = set(models.symbols().values()) | set(letters.values())
    if not expr.free_symbols <= allowed:
        raise BadArgument(f"bound {text!r}: unknown symbols {sorted(map(str, expr.free_symbols - allowed))}")
    if not expr.free_symbols & set(letters.values()):
        return Bound(what, scalar=expr)
    poly = sp.expand(expr)
    per = {KIND_LETTERS[s]: sp.expand(poly.coeff(letters[s])) for s in KIND_LETTERS}
    if sp.expand(poly - sum(per[KIND_LETTERS[s]] * letters[s] for s in KIND_LETTERS)) != 0:
        raise BadArgument(f"bound {text!r} has a term without an operation kind")
    return Bound(what, per_kind=per)


def excess(measure: Measure, tally: dict[str, int], bound: dict[str, float]) -> tuple[float, list[str]]:
    """How far a run's tally goes past a bound: the largest ``cost / bound`` over the kinds the measure reads
    (above 1: exceeded), and the kinds exceeded."""
    if "value" in bound:
        v = measure.value(tally)
        return _ratio(v, bound["value"]), (["value"] if v > bound["value"] else [])
    kinds = list(KINDS) if measure.kind == "any" else [measure.kind]
    if measure.kind == "total":
        v, b = float(sum(tally.get(k, 0) for k in KINDS)), float(sum(bound.values()))
        return _ratio(v, b), (["total"] if v > b else [])
    ratios = {k: _ratio(tally.get(k, 0), bound.get(k, 0.0)) for k in kinds}
    return max(ratios.values()), [k for k in kinds if tally.get(k, 0) > bound.get(k, 0.0)]


def _ratio(v: float, b: float) -> float:
    if b > 0:
        return float(v) / b
    return float("inf") if v > 0 else 0.0


__all__ = ["Bound", "COST_MODELS", "Measure", "OP_KINDS", "excess", "parse_bound"]
