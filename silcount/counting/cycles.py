"""Cycle profiles: one weight per operation kind, each with its source, to turn tallies into cycles.

Every profile weighs every kind the ``true`` cost model counts
(:data:`TRUE_KINDS`: the papers' five plus EESD's ``div`` and ``sqrt``); a
profile lacking one is refused, naming the kind, and so is a tally holding a
kind its profile does not weigh.  Built-in profiles (``silcount/models/cycles/``):

* ``paper``: the EESD paper's printed weights (Sec. 6: "Mults 4 cycles, Adds 2
  cycles, Compares 3 cycles, Reads 1 cycle and Writes 2 cycles",
  ``silcount/models/papers/eesd2012/eesd2012-paper.toml``).  The paper gives no weight for a division
  or a square root; a weight of 0 would let EESD's divisions and roots cost
  nothing, and refusing them would leave EESD's ``true`` tally without a
  paper-weighted total.  So ``div`` and ``sqrt`` get a labelled *extension*
  (``silcount/models/cycles/paper-extension.toml``): the paper's ``mul`` weight times
  the smallest divsd/mulsd (sqrtsd/mulsd) latency ratio among the llvm-mca
  profiles, i.e. the cheapest division any of LLVM's CPU models allows,
  relative to the paper's own multiply.  Its source says "extension, not in
  the paper" wherever it is shown;
* ``unit``: every operation costs 1 (a plain operation count);
* ``<cpu>-latency`` and ``<cpu>-throughput`` for each
  ``silcount/models/cycles/<cpu>-llvm-mca.toml``: llvm-mca's latency and reciprocal
  throughput of the scalar SSE2 instruction behind each kind
  (:mod:`silcount.calibrate.mca`, ``scripts/make_cycle_profiles.py``).  These
  replace the former ``skylake.toml``, whose values were cited from memory:
  llvm-mca 14 agrees on add, mul (4, 0.5) and the load (5, 0.5) and store
  throughput (1), but gives ucomisd latency 2 and throughput 1 (the file had
  CMPSD's 4 and 0.5) and a store latency of 1 (the file had 4, a
  store-forwarding delay, which is not the cost of a store);
* ``<machine>-measured-latency`` / ``-throughput`` (and ``-latency-dram``) for
  each ``silcount/models/cycles/measured-<machine>.toml`` written by ``silcount
  calibrate --measure`` (:mod:`silcount.calibrate.measure`), in nanoseconds;
* a user's own TOML file: ``[weights]`` with every kind of :data:`TRUE_KINDS`
  (a number, or ``{value = ..., source = "..."}``) and optionally ``name``.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.errors import BadArgument, UnreadableInput

TRUE_KINDS: tuple[str, ...] = (*KINDS, "div", "sqrt")
"""Every kind the ``true`` cost model counts; every profile weighs each of them."""


@dataclass(frozen=True)
class Profile:
    """Weights per operation kind (cycles, or ``unit``), each with its source."""

    name: str
    weights: dict[str, float]
    source: str
    sources: dict[str, str] = field(default_factory=dict)
    unit: str = "cycles"

    def __post_init__(self) -> None:
        missing = [k for k in TRUE_KINDS if k not in self.weights]
        if missing:
            raise BadArgument(f"cycle profile {self.name} lacks a weight for {', '.join(missing)}")

    def cycles(self, tally: Mapping[str, float]) -> float:
        """Weighted total of a tally; a kind counted but not weighed fails, naming it."""
        w = self.weights
        total: float = 0  # summed in the tally's order, as sum() over it would
        for k, v in tally.items():
            if v:
                if k not in w:
                    unweighed = sorted(k for k, v in tally.items() if v and k not in w)
                    raise BadArgument(f"cycle profile {self.name} has no weight for {', '.join(unweighed)}")
                total += w[k] * v
        return total


def cycles_many(profiles: Sequence[Profile], tallies: Sequence[Mapping[str, int]]) -> list[np.ndarray]:
    """:meth:`Profile.cycles` of each tally under each profile (one array per profile): the same doubles, bit
    for bit, summed by numpy a column at a time.

    Tallies are grouped by their kinds' order and each group's weighted counts are added kind by kind in that
    order, as :meth:`Profile.cycles` adds them (a zero count adds ``+0.0``, which changes no sum of
    non-negative terms; the products are of the same doubles, an ``int`` count rounding to the same double in
    both); a kind counted but not weighed fails the same way, naming it.
    """
    out = [np.zeros(len(tallies)) for _ in profiles]
    groups: dict[tuple[str, ...], list[int]] = {}
    for i, tally in enumerate(tallies):
        groups.setdefault(tuple(tally), []).append(i)
    for kinds, rows in groups.items():
        counts = np.array([[tallies[i][k] for k in kinds] for i in rows], dtype=np.float64).reshape(len(rows), -1)
        for profile, column in zip(profiles, out, strict=True):
            total = np.zeros(len(rows))
            for j, k in enumerate(kinds):
                if k in profile.weights:
                    total += profile.weights[k] * counts[:, j]
                elif np.any(counts[:, j]):
                    profile.cycles(tallies[rows[int(np.flatnonzero(counts[:, j])[0])]])  # raises, naming the kinds
            column[rows] = total
    return out


def cycles_of_counts(profiles: Sequence[Profile], kinds: Sequence[str], counts: np.ndarray) -> list[np.ndarray]:
    """:func:`cycles_many` of tallies held as columns (a detector's batch of lights): ``counts`` (n, kinds)
    integers, negative where a light's tally lacks the kind, each tally's kinds in the order of ``kinds``.
    The same doubles, bit for bit: the weighted counts are added kind by kind in that order (an absent or
    zero count adds ``+0.0``); a kind counted but not weighed fails, naming it."""
    counts = np.asarray(counts, dtype=np.int64).reshape(-1, len(kinds))
    values = np.where(counts >= 0, counts, 0).astype(np.float64)
    out = []
    for profile in profiles:
        total = np.zeros(counts.shape[0])
        for j, k in enumerate(kinds):
            if k in profile.weights:
                total += profile.weights[k] * values[:, j]
            elif np.any(values[:, j]):
                i = int(np.flatnonzero(values[:, j])[0])
                profile.cycles({c: int(v) for c, v in zip(kinds, counts[i].tolist(), strict=True) if v >= 0})
        out.append(total)
    return out


def cycles_dir() -> Path:
    return models.models_dir() / "cycles"


def _read(path: Path) -> dict:
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise UnreadableInput(f"cannot read cycle profile {path}: {exc}") from exc


def paper_profile() -> Profile:
    """The EESD paper's five printed weights plus the labelled div/sqrt extension."""
    printed = models.load("eesd2012-paper")["cycle_weights"]
    ext = _read(cycles_dir() / "paper-extension.toml")["weights"]
    weights = {k: float(printed[k]) for k in KINDS} | {k: float(ext[k]["value"]) for k in ("div", "sqrt")}
    sources = {k: f"EESD paper Sec. {printed['section']}" for k in KINDS}
    sources |= {k: f"extension, not in the paper: {ext[k]['source']}" for k in ("div", "sqrt")}
    return Profile("paper", weights, f"EESD paper Sec. {printed['section']} (div, sqrt: extension)", sources)


def _table(name: str, data: dict, table: str, path: Path, unit: str, read_key: str = "read") -> Profile:
    rows = dict(data[table])
    rows["read"] = rows[read_key]
    weights = {k: float(rows[k]["value"]) for k in TRUE_KINDS if k in rows}
    sources = {k: str(rows[k].get("instruction") or rows[k].get("method")) for k in TRUE_KINDS if k in rows}
    return Profile(name, weights, f"{path.name} [{table}]", sources, unit)


def mca_profiles() -> dict[str, Profile]:
    """``<cpu>-latency`` and ``<cpu>-throughput`` from every ``silcount/models/cycles/<cpu>-llvm-mca.toml``."""
    out = {}
    for path in sorted(cycles_dir().glob("*-llvm-mca.toml")):
        data = _read(path)
        cpu = data["llvm_mcpu"]
        for table, suffix in (("latency", "latency"), ("rthroughput", "throughput")):
            prof = _table(f"{cpu}-{suffix}", data, table, path, "cycles")
            out[prof.name] = Profile(
                prof.name, prof.weights, f"llvm-mca {data['llvm_version']} -mcpu={cpu} {table}", prof.sources
            )
    return out


def measured_profiles() -> dict[str, Profile]:
    """The profiles of every ``silcount/models/cycles/measured-<machine>.toml`` (nanoseconds per operation)."""
    out: dict[str, Profile] = {}
    for path in sorted(cycles_dir().glob("measured-*.toml")):
        out |= measured_file_profiles(path)
    return out


def measured_file_profiles(path: Path) -> dict[str, Profile]:
    """``<name>-measured-latency``, ``-throughput`` (reads from L1) and ``-latency-dram`` of one measured file."""
    data = _read(path)
    base = f"{data['name']}-measured"
    profs = (
        _table(f"{base}-latency", data, "latency", path, "ns"),
        _table(f"{base}-throughput", data, "rthroughput", path, "ns"),
        _table(f"{base}-latency-dram", data, "latency", path, "ns", read_key="read_dram"),
    )
    return {p.name: p for p in profs}


def builtin_profiles() -> dict[str, Profile]:
    """Every built-in profile by name: paper, unit, the llvm-mca ones, the measured ones."""
    unit = Profile(
        "unit", {k: 1.0 for k in TRUE_KINDS}, "every operation 1", {k: "1 by definition" for k in TRUE_KINDS}
    )
    return {"paper": paper_profile(), "unit": unit, **mca_profiles(), **measured_profiles()}


def load_profile(spec: str) -> Profile:
    """A built-in profile by name, or a user's TOML file path (``[weights]`` for every kind)."""
    profiles = builtin_profiles()
    if spec in profiles:
        return profiles[spec]
    path = Path(spec)
    if not path.exists():
        raise BadArgument(f"unknown cycle profile {spec!r}: not one of {', '.join(profiles)} and no such file")
    data = _read(path)
    raw = data.get("weights", {})
    missing = [k for k in TRUE_KINDS if k not in raw]
    if missing:
        raise BadArgument(f"cycle profile {path} lacks a weight for {', '.join(missing)}")
    weights, sources = {}, {}
    for k, v in raw.items():
        weights[k] = float(v["value"] if isinstance(v, dict) else v)
        sources[k] = str(v.get("source", path)) if isinstance(v, dict) else str(path)
    return Profile(str(data.get("name", path.stem)), weights, str(path), sources)
