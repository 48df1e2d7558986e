"""Cycle profiles: one weight per operation kind, to turn tallies into cycles.

Profiles (see ``models/cycles/`` and the EESD paper, Sec. 6):

* ``paper``: the printed weights, "Mults 4 cycles, Adds 2 cycles, Compares 3
  cycles, Reads 1 cycle and Writes 2 cycles" (``models/eesd2012-paper.toml``);
* ``unit``: every operation costs 1 (a plain operation count);
* ``skylake-latency`` and ``skylake-throughput``: scalar double-precision
  latency and reciprocal throughput on Intel Skylake, each value cited in
  ``models/cycles/skylake.toml``;
* a user's own TOML file: ``[weights]`` with ``add, mul, cmp, read, write``
  (and optionally ``name``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from silcount.counting import paper as models
from silcount.counting.arithmetic import KINDS
from silcount.errors import BadArgument, UnreadableInput


@dataclass(frozen=True)
class Profile:
    """Cycle weights per operation kind."""

    name: str
    weights: dict[str, float]
    source: str

    def cycles(self, tally: dict[str, float]) -> float:
        """Cycle-weighted total of a tally (kinds without a weight cost nothing, e.g. ``div``)."""
        return sum(self.weights.get(k, 0) * v for k, v in tally.items())


def _microarch(name: str, table: str) -> Profile:
    data = models.load(f"cycles/{name}")
    weights = {k: float(v["value"]) for k, v in data[table].items()}
    return Profile(f"{name}-{table}", weights, "; ".join(sorted({v["source"] for v in data[table].values()})))


def builtin_profiles() -> dict[str, Profile]:
    """Every built-in profile by name."""
    paper = models.load("eesd2012-paper")["cycle_weights"]
    return {
        "paper": Profile("paper", {k: float(paper[k]) for k in KINDS}, f"EESD paper Sec. {paper['section']}"),
        "unit": Profile("unit", {k: 1.0 for k in KINDS}, "every operation 1 cycle"),
        "skylake-latency": _microarch("skylake", "latency"),
        "skylake-throughput": _microarch("skylake", "rthroughput"),
    }


def load_profile(spec: str) -> Profile:
    """A built-in profile by name, or a user's TOML file path."""
    profiles = builtin_profiles()
    if spec in profiles:
        return profiles[spec]
    path = Path(spec)
    if not path.exists():
        raise BadArgument(f"unknown cycle profile {spec!r}: not one of {', '.join(profiles)} and no such file")
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise UnreadableInput(f"cannot read cycle profile {path}: {exc}") from exc
    weights = data.get("weights", {})
    missing = [k for k in KINDS if k not in weights]
    if missing:
        raise BadArgument(f"cycle profile {path} lacks weights for {', '.join(missing)}")
    return Profile(str(data.get("name", path.stem)), {k: float(v) for k, v in weights.items()}, str(path))
