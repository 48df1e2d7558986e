"""Access to ``silcount/models/``: the papers' per-line costs, loops and printed numbers as data.

The TOML files under ``silcount/models/`` (one per paper and algorithm, see
``silcount/models/README.md``) are the single source of every printed number.  This
module parses them; sympy expressions are parsed once and cached (sympy is
imported on the first expression, so loading a detector does not load it).
"""

from __future__ import annotations

import ast
import operator
import os
import tomllib
from functools import cache
from importlib.resources import files
from numbers import Integral
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.counting.arithmetic import KINDS

if TYPE_CHECKING:
    import sympy as sp


SYMBOLS = ("n", "f_n", "e_n", "m")
"""The papers' size symbols."""
_OPERATORS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul}


def models_dir() -> Path:
    """The models directory: the package's data ``silcount/models/`` (``$SILCOUNT_MODELS_DIR`` overrides it).

    Read through :mod:`importlib.resources`, so an installed wheel finds the copy it ships; the package
    must be installed as files (not zipped), as pip installs it.
    """
    env = os.environ.get("SILCOUNT_MODELS_DIR")
    return Path(env) if env else Path(str(files("silcount") / "models"))


_ADDED: dict[str, Path] = {}
"""Model files of papers outside the package (``--paper DIR``, the ``silcount.papers`` entry points), by name."""


def add_file(name: str, path: Path) -> None:
    """Make ``load(name)`` read ``path``: a model file of a paper folder outside the package.

    A name the package already has, or that another folder gave, is refused (ValueError): a name means one file.
    """
    if _ADDED.get(name, path) != path or (name not in _ADDED and _builtin_path(name).is_file()):
        raise ValueError(f"model {name!r} ({path}) is already defined by {_ADDED.get(name) or _builtin_path(name)}")
    _ADDED[name] = path
    load.cache_clear()


def drop_files(names) -> None:
    """Forget the files :func:`add_file` gave these names (a paper found broken after it was read)."""
    for name in names:
        _ADDED.pop(name, None)
    load.cache_clear()


def _builtin_path(name: str) -> Path:
    """``<models>/<name>.toml``, or ``<models>/papers/<paper>/<name>.toml`` (a built-in paper's folder)."""
    root = models_dir()
    found = sorted((root / "papers").glob(f"*/{name}.toml"))
    return found[0] if found else root / f"{name}.toml"


def model_path(name: str) -> Path:
    """The file model ``name`` is read from (it need not exist: :func:`load` then raises FileNotFoundError)."""
    return _ADDED.get(name) or _builtin_path(name)


@cache
def load(name: str) -> dict:
    """The parsed TOML of model ``name`` (:func:`model_path`: a built-in paper's folder, ``silcount/models/``, a
    folder added with :func:`add_file`, or the file ``name`` itself if it ends in ``.toml``: a plug-in detector's
    own model, :class:`silcount.detectors.spec.DetectorSpec`)."""
    path = Path(name) if name.endswith(".toml") else model_path(name)
    with open(path, "rb") as fh:
        return tomllib.load(fh)


@cache
def symbols() -> dict[str, "sp.Symbol"]:
    """The papers' size symbols ``n``, ``f_n``, ``e_n``, ``m`` (positive)."""
    import sympy as sp

    return {name: sp.Symbol(name, positive=True) for name in SYMBOLS}


def expr(text: str | int) -> "sp.Expr":
    """Parse a cost expression from silcount/models/ with the papers' symbols."""
    import sympy as sp

    return sp.sympify(str(text), locals=symbols())


@cache
def step_costs(name: str) -> dict[str, dict[str, "sp.Expr"]]:
    """Per-step costs of model ``name``: step -> kind -> sympy expression."""
    steps = load(name).get("steps", {})
    return {step: {kind: expr(v) for kind, v in spec.get("cost", {}).items()} for step, spec in steps.items()}


def paper_tally(name: str, steps: dict[str, int], params: dict[str, int | float]) -> dict[str, int]:
    """The ``paper`` cost model: ``sum(steps[s] * cost[s])`` evaluated at ``params``.

    ``params`` gives the mesh's own ``e_n``, ``f_n`` and ``m``.  Steps the
    model does not annotate cost nothing in this model (they are reported in
    ``steps``); every kind of :data:`KINDS` is present in the result.
    """
    import sympy as sp

    costs = step_costs(name)
    sym = symbols()
    subs = {sym[k]: sp.sympify(v) for k, v in params.items() if k in sym}  # as subs() converts them
    total: dict[str, int] = {k: 0 for k in KINDS}
    for step, count in steps.items():
        for kind, cost in costs.get(step, {}).items():
            value = cost if cost.is_number else cost.xreplace(subs)  # numbers for symbols: Add, Mul evaluate
            if not value.is_number:
                raise ValueError(f"cost of {name}:{step}:{kind} = {cost} needs {value.free_symbols}")
            total[kind] = total.get(kind, 0) + int(count) * int(value)
    return total


def _integer_value(node: ast.expr, values: dict[str, int]) -> int | None:
    """The value of a cost text's syntax tree made of integers, ``+``, ``-``, ``*`` and symbols with integer
    ``values``; ``None`` for anything else."""
    if isinstance(node, ast.Constant) and type(node.value) is int:
        return node.value
    if isinstance(node, ast.Name):
        return values.get(node.id)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        inner = _integer_value(node.operand, values)
        return None if inner is None else -inner
    if isinstance(node, ast.BinOp) and type(node.op) in _OPERATORS:
        left, right = _integer_value(node.left, values), _integer_value(node.right, values)
        return None if left is None or right is None else _OPERATORS[type(node.op)](left, right)
    return None


def unit_cost(name: str, step: str, params: dict[str, int | float]) -> dict[str, int]:
    """:func:`paper_tally` of one run of ``step``: without sympy where every cost of the step is an integer
    polynomial of integer ``params`` (integers, ``+``, ``-``, ``*``: the exact integers sympy gives; every
    cost in silcount/models/ is a sum of integers or ``e_n``), else by :func:`paper_tally` itself."""
    whole = {k: v for k, v in params.items() if k in SYMBOLS and isinstance(v, Integral) and not isinstance(v, bool)}
    values = {k: int(v) for k, v in whole.items()}
    total: dict[str, int] = {k: 0 for k in KINDS}
    for kind, text in load(name).get("steps", {}).get(step, {}).get("cost", {}).items():
        value = _integer_value(ast.parse(str(text), mode="eval").body, values)
        if value is None:
            return paper_tally(name, {step: 1}, params)
        total[kind] = total.get(kind, 0) + value
    return total
