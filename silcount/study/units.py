"""A unit's time and peak memory from its faces: power laws fitted to measured units, and the memory budget.

The measurements are ``silcount/models/measured/unit-profile.json``, taken by ``scripts/unit_profile.py``:
units of ``silcount corpus``'s default settings (64 directional lights, every detector, plain loops timed)
on corpus meshes subdivided from 1 k to 4 M faces and the 1.04 M-face bunny, each in a fresh process on
one numba thread; every detector alone (with the reference, which always runs) at four sizes; every
detector on 8 lights at three.  Per detector set, :func:`silcount.study.fits.power_fit` fits
``seconds ~ c F^alpha`` and ``extra ~ c F^alpha`` (the peak resident set above the warm worker's), with a
bootstrap interval for ``alpha``.

Estimates (docs/corpus.md, "Memory"):

* the time is fitted over the units whose plain loops of VnV and EESD (``O(E F)``) are not timed
  (``E F`` over ``time_max_pairs``, with ``E = 1.5 F``); below, those loops add ``per_pair_s`` seconds per
  edge-face pair, the mean excess of the measured units there over the fit;
* a set of detectors ``S`` (not every detector) on ``F`` faces costs at most what every detector costs,
  and: in time, the reference's alone plus what each other detector adds to it (its fit alone minus the
  reference's, never below zero); in memory, the sum of each detector's peak alone (the reference's
  included), because a unit keeps every detector's results, and the hierarchies' trees stay cached with
  the mesh, while the next detector runs (at 256 k faces every detector together needed 1.8x the largest
  of them alone);
* ``n`` of the unit's ``L`` lights cost the share ``(1 - p) + p n / L`` of its ``L`` lights, ``p`` the
  lights' share measured on every detector at 64 and 8 lights (the largest of the three sizes);
* the peak memory is the warm worker's (the largest measured) plus :data:`MARGIN` times the fit, a margin
  that covers every measured unit (``tests/test_units.py`` checks it against the committed data).

Each fit carries the complexity class of its points (``power_fit``'s ``classes``,
:mod:`silcount.study.classes`), which ``scale.md`` shows; the estimates use the power law.  Kinds of
mesh are not distinguished: every fit is over all the measured meshes, and :func:`UnitModel.fit_of` is
the one place a kind would choose its own fit.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from silcount.detectors import get
from silcount.detectors import names as registered
from silcount.study.fits import power_fit
from silcount.study.work import Settings

PROFILE = "unit-profile.json"
MARGIN = 1.5
"""Estimated peak memory above the warm worker's: this times the fit (every measured unit is below it)."""
MEMORY_SHARE = 0.75
"""The default budget: this share of the machine's physical memory, divided among the local workers."""
ALL = "all"


def total_lights(settings: Settings) -> int:
    """A unit's lights: ``lights`` of each kind (:func:`silcount.study.work.mesh_lights`)."""
    return settings.lights * (2 if settings.light_kind == "both" else 1)


@dataclass(frozen=True)
class UnitModel:
    """The fits of :mod:`silcount.study.units` (see its docstring) and the data they came from."""

    fits: dict[tuple[str, str], dict]  # (detector set, "seconds" | "extra_bytes") -> power_fit
    base_bytes: int
    light_share: dict[str, float]  # "seconds" | "extra_bytes" -> p
    lights: int  # the lights of the fitted units
    units: list[dict]
    about: dict  # machine, date, settings
    per_pair_s: float  # seconds per edge-face pair of the timed quadratic plain loops (both of them, one light)

    def fit_of(self, detectors: str, what: str) -> dict:
        """The power fit of ``what`` for a detector set (``all`` or one detector's name)."""
        return self.fits[(detectors, what)]

    def _at(self, detectors: str, what: str, faces: float) -> float:
        f = self.fit_of(detectors, what)
        return float(f["c"] * max(faces, 1.0) ** f["alpha"])

    def cost(self, faces: float, detectors, lights: int, what: str) -> float:
        """The fitted ``what`` of ``detectors`` on ``faces`` faces under ``lights`` lights (module docstring)."""
        names = tuple(detectors)
        whole = self._at(ALL, what, faces)
        if not set(names) >= set(registered()):
            alone = {d: self._at(d, what, faces) for d in names}
            if what == "seconds":  # the reference once, and what each other detector adds to it
                ref = self._at("reference", what, faces)
                part = ref + sum(max(t - ref, 0.0) for d, t in alone.items() if d != "reference")
            else:  # each detector's whole peak, the reference's included: results and caches pile up
                part = sum(alone.values())
            whole = min(whole, part)
        p = self.light_share[what]
        return whole * ((1.0 - p) + p * lights / self.lights)

    def seconds(self, faces: float, settings: Settings, detectors=None, lights: int | None = None) -> float:
        """Estimated seconds of a unit (or of a part: ``detectors`` under ``lights`` of its lights)."""
        n = total_lights(settings) if lights is None else lights
        names = tuple(detectors or settings.detectors)
        seconds = self.cost(faces, names, n, "seconds")
        if settings.timing and lights is None and pairs(faces) <= settings.time_max_pairs:  # a whole unit
            share = sum(get(d).plain_quadratic for d in names) / 2  # the fit's units time both, on one kind
            seconds += share * self.per_pair_s * pairs(faces) * (2 if settings.light_kind == "both" else 1)
        return seconds

    def peak_bytes(self, faces: float, settings: Settings, detectors=None, lights: int | None = None) -> int:
        """Estimated peak resident bytes of a worker running a unit or a part (with :data:`MARGIN`)."""
        n = total_lights(settings) if lights is None else lights
        extra = self.cost(faces, detectors or settings.detectors, n, "extra_bytes")
        return int(self.base_bytes + MARGIN * extra)


def pairs(faces: float) -> float:
    """The edge-face pairs of a closed triangle mesh of ``faces`` faces (``E = 1.5 F``)."""
    return 1.5 * float(faces) ** 2


def model_from(data: dict) -> UnitModel:
    """The fits of a profile's ``units`` (as ``scripts/unit_profile.py`` writes them)."""
    units = [u for u in data["units"] if not u.get("error")]
    lights = max(u["lights"] for u in units)
    limit = Settings().time_max_pairs
    fits: dict[tuple[str, str], dict] = {}
    for det in sorted({u["detectors"] for u in units}):
        own = [u for u in units if u["detectors"] == det and u["lights"] == lights and pairs(u["faces"]) > limit]
        faces = [u["faces"] for u in own]
        fits[(det, "seconds")] = power_fit(faces, [u["seconds"] for u in own], subset=det)
        fits[(det, "extra_bytes")] = power_fit(faces, [u["peak_bytes"] - u["base_bytes"] for u in own], subset=det)
    share = {"seconds": 1.0, "extra_bytes": 1.0}  # without a pair of runs: all of it per light (the larger)
    full = {u["file"]: u for u in units if u["detectors"] == ALL and u["lights"] == lights}
    pairs_ = [
        (u, full[u["file"]]) for u in units if u["detectors"] == ALL and u["lights"] < lights and u["file"] in full
    ]
    if pairs_:
        few, whole = max(pairs_, key=lambda pair: pair[0]["faces"])  # the largest mesh measured both ways
        for what, value in (
            ("seconds", lambda u: u["seconds"]),
            ("extra_bytes", lambda u: u["peak_bytes"] - u["base_bytes"]),
        ):
            per_light = (value(whole) - value(few)) / (lights - few["lights"])
            share[what] = float(np.clip(per_light * lights / value(whole), 0.0, 1.0))
    quadratic = []  # the plain loops of VnV and EESD, timed on small meshes only: seconds per pair over the fit
    for u in units:
        if u["detectors"] == ALL and u["lights"] == lights and pairs(u["faces"]) <= limit:
            fit = fits[(ALL, "seconds")]
            quadratic.append(max(u["seconds"] - fit["c"] * u["faces"] ** fit["alpha"], 0.0) / pairs(u["faces"]))
    per_pair = float(np.mean(quadratic)) if quadratic else 0.0
    base = max(u["base_bytes"] for u in units)
    return UnitModel(fits, base, share, lights, units, dict(data.get("about", {})), per_pair)


@cache
def load_model() -> UnitModel:
    """The committed profile's model (package data, under :func:`silcount.counting.models.models_dir`)."""
    from silcount.counting.models import models_dir

    return model_from(json.loads((models_dir() / "measured" / PROFILE).read_text(encoding="utf-8")))


def physical_memory() -> int | None:
    """The machine's physical memory in bytes (``os.sysconf``), or None where it cannot be known."""
    try:
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def default_budget(workers: int) -> int | None:
    """:data:`MEMORY_SHARE` of the physical memory over ``workers`` workers (None: unknown, no budget).

    The workers run at once, each up to its budget; the rest is left to the client (which holds every
    file's bytes and every result), the system and the machine's other users.
    """
    total = physical_memory()
    return None if total is None else int(MEMORY_SHARE * total / max(workers, 1))


def faces_of(path: Path) -> int | None:
    """The faces a mesh file declares, read cheaply (its header or line counts), or None if it cannot say."""
    from silcount.errors import SilcountError
    from silcount.mesh.io import READERS

    reader = READERS.get(path.suffix.lower())
    if reader is None:
        return None
    try:
        return int(reader.estimate(path, path.stat().st_size)[1])
    except (SilcountError, OSError, ValueError):
        return None
