"""What an audit puts beside a measured tally: cycle-weighted totals and the paper's printed formula.

Cycle profiles come from :mod:`silcount.cycles` when it is installed; until
then the ``paper`` profile is the EESD paper's "Mults 4 cycles, Adds 2
cycles, Compares 3 cycles, Reads 1 cycle and Writes 2 cycles" (EESD 2012,
Sec. 6) and ``unit`` weighs every operation 1.  A TOML file with a
``[weights]`` table (``add = 2`` ...) is a user profile.  Kinds a profile does
not weigh (e.g. ``div`` under the paper's profile) add nothing to the total.

The printed closed forms are the last printed line of each model's
``[closed_form]`` in ``models/``, through :mod:`silcount.formulas`, evaluated
at the mesh's ``n`` (faces; HSD: merged polygons) and ``m`` (mean sides).
"""
from __future__ import annotations

import importlib
import tomllib
from pathlib import Path

from .errors import BadArgument
from . import models
from .mesh import Mesh

FALLBACK_PROFILES = {
    "paper": {"mul": 4, "add": 2, "cmp": 3, "read": 1, "write": 2},
    "unit": {"mul": 1, "add": 1, "cmp": 1, "read": 1, "write": 1},
}


def _optional(module: str):
    try:
        return importlib.import_module(f".{module}", __package__)
    except ModuleNotFoundError as exc:
        if exc.name != f"{__package__}.{module}":
            raise
        return None


def _profile_from_file(path: Path) -> dict[str, float]:
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise BadArgument(f"{path}: not a readable cycle-profile TOML: {exc}") from None
    weights = data.get("weights", data)
    if not isinstance(weights, dict) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                for v in weights.values()):
        raise BadArgument(f"{path}: a cycle profile needs a [weights] table of numbers (add = 2, ...)")
    return {str(k): v for k, v in weights.items()}


def cycle_profile(spec: str) -> tuple[str, dict[str, float]]:
    """``(name, kind -> cycles)`` for a profile name or a TOML file path."""
    cycles = _optional("cycles")
    if cycles is not None and hasattr(cycles, "load_profile"):
        prof = cycles.load_profile(spec)
        return str(getattr(prof, "name", spec)), dict(getattr(prof, "weights", prof))
    if spec in FALLBACK_PROFILES:
        return spec, dict(FALLBACK_PROFILES[spec])
    path = Path(spec)
    if path.suffix == ".toml" and path.is_file():
        return path.stem, _profile_from_file(path)
    raise BadArgument(f"unknown cycle profile {spec!r}: give {', '.join(FALLBACK_PROFILES)} or a .toml file")


def weighted(tally: dict[str, float], weights: dict[str, float]) -> float:
    """``sum(count * weight)`` over the kinds the profile weighs; an int when every term is."""
    total = sum(tally.get(k, 0) * w for k, w in weights.items())
    return int(total) if float(total).is_integer() else float(total)


def formula_point(detector: str, mesh: Mesh, notes: dict) -> tuple[float, float]:
    """The papers' ``n`` and ``m`` for this mesh: faces and mean sides; for HSD its polygons (HSD Sec. 6.3)."""
    merged = notes.get("merge")
    if detector == "hsd" and isinstance(merged, dict):
        return merged["polygons"], merged["mean_sides"]
    return mesh.n_faces, mesh.mean_sides


def printed_formula(detector: str, mesh: Mesh, notes: dict | None = None) -> dict | None:
    """The paper's printed closed form for ``detector`` at this mesh's ``n`` and ``m``, or ``None``.

    ``n`` is the papers' face count (they substitute ``f_n = n``, ``e_n = 6n``),
    ``m`` the mean sides per face; ``None`` for ``reference`` (no paper) or
    while :mod:`silcount.formulas` is not installed.
    """
    formulas = _optional("formulas")
    if formulas is None:
        return None
    model = models.DEFAULT_PAPER_MODEL[detector]
    spec = models.load(model)
    if "closed_form" not in spec:
        return None
    n, m = formula_point(detector, mesh, notes or {})
    values = formulas.evaluate(formulas.printed_final(model), n=n, m=m)
    return {
        "model": model,
        "source": f"{spec.get('source_file', model)} Sec. {spec['closed_form'].get('section', '?')}",
        "printed": formulas.printed_lines(model)[-1].printed,
        "n": n,
        "m": m,
        "tally": {k: (int(v) if v.is_integer else float(v)) for k, v in values.items()},
    }
