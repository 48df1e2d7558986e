"""What an audit puts beside a measured tally: cycle-weighted totals and the paper's printed formula.

Cycle profiles come from :mod:`silcount.cycles` when it is installed; until
then the ``paper`` profile is the EESD paper's "Mults 4 cycles, Adds 2
cycles, Compares 3 cycles, Reads 1 cycle and Writes 2 cycles" (EESD 2012,
Sec. 6) and ``unit`` weighs every operation 1.  A TOML file with a
``[weights]`` table (``add = 2`` ...) is a user profile.  Kinds a profile does
not weigh (e.g. ``div`` under the paper's profile) add nothing to the total.

The printed closed forms come from :mod:`silcount.formulas` (``models/``);
until it is installed, ``printed_formula`` returns ``None`` and the audit
reports ``formula_printed: null``.
"""
from __future__ import annotations

import importlib
import tomllib
from pathlib import Path

from .errors import BadArgument
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


def printed_formula(detector: str, mesh: Mesh) -> dict | None:
    """The paper's printed closed form for ``detector`` at this mesh's ``n`` and ``m``, or ``None``."""
    formulas = _optional("formulas")
    if formulas is None or not hasattr(formulas, "printed_at_mesh"):
        return None
    return formulas.printed_at_mesh(detector, mesh)
