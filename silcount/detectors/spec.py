"""What a detector declares of itself: :class:`DetectorSpec`, the one record every consumer reads.

A detector is a ``detect(mesh, light, variant, engine) -> Silhouette`` function and the facts the audit,
the corpus study, the calibration, the figures, the tables and the renders need about it.  Built-in and
plug-in detectors declare the same record and register it the same way
(:func:`silcount.detectors.registry.register_detector`; ``docs/extending.md``).  What a detector lacks
(a ``naive`` engine, a ``paper`` cost model, plain loops) is ``None`` or left out of its tuples, and every
consumer leaves the matching column empty and says so.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from silcount.detectors.batch import SilhouetteBatch
    from silcount.detectors.result import Silhouette
    from silcount.mesh.lights import Light
    from silcount.mesh.model import Mesh

VARIANTS = ("intended", "literal")
ENGINES = ("fast", "naive")
ROLES = ("paper", "yardstick", "literature")
"""``paper``: one of the papers' detectors under audit (TA, VnV, HSD, EESD): ``silcount calibrate`` fits its
weights to them and the claims rank them; ``literature``: the literature's output-sensitive hierarchies,
with their own page, fits and figure; ``yardstick``: set beside them (silcount's reference, and a plug-in's
default)."""


@dataclass(frozen=True, kw_only=True)
class DetectorSpec:
    """One detector: ``name``, ``label`` and ``detect`` are required, every other field has a default.

    * ``name``: the key of every table, run and file (``silcount audit --detectors NAME``); letters, digits,
      ``_`` and ``-``;
    * ``label``: how tables and figures name it;
    * ``detect(mesh, light, variant="intended", engine="fast") -> Silhouette``;
    * ``role``: one of :data:`ROLES`;
    * ``paper_model``: its ``paper`` cost model, a ``silcount/models/`` file's stem or the path of a TOML
      file of the same form (a plug-in ships its own); ``None``: no paper cost model;
    * ``variants``: the distinct variants it runs (of :data:`VARIANTS`; one variant: ``variant`` accepted and
      ignored, one run); ``engines``: the engines it has (of :data:`ENGINES`, ``fast`` always);
    * ``visited_step``: the step counting the edges (sides) its per-light loop examines, or ``None``;
    * ``plain_edge_ids(mesh, light)``: its own loops compiled and uncounted, what a frame really pays (timed by
      ``silcount calibrate`` and the corpus study), the ascending ids ``detect`` returns; ``None``: no time
      column; ``plain_setup(mesh)``: the per-mesh preprocessing those loops use, run outside the timings;
      ``plain_quadratic``: they visit every (edge, face) pair;
    * ``growth_variant``: the variant whose measured growth is set beside the paper's closed form;
    * ``style``: its (colour, marker) in every figure;
    * ``detect_many(mesh, lights, variant)``: the ``fast`` engine for many lights in one pass, the same results
      as ``detect`` per light, or ``None``; it returns a :class:`.batch.SilhouetteBatch` (columnar: no
      Python object per light) or a ``list[Silhouette]``, which :func:`silcount.detectors.detect_many` wraps.
    """

    name: str
    label: str
    detect: Callable[..., Silhouette]
    role: str = "yardstick"
    paper_model: str | None = None
    variants: tuple[str, ...] = ("intended",)
    engines: tuple[str, ...] = ("fast",)
    visited_step: str | None = None
    plain_edge_ids: Callable[[Mesh, Light], np.ndarray] | None = None
    plain_setup: Callable[[Mesh], Any] | None = None
    plain_quadratic: bool = False
    growth_variant: str = "intended"
    style: tuple[str, str] = ("#000000", "x")
    detect_many: Callable[[Mesh, list[Light], str], SilhouetteBatch | list[Silhouette]] | None = None

    def __post_init__(self) -> None:
        """Check every field's form: a spec that gets past here runs in every consumer."""
        name = self.name
        if not (isinstance(name, str) and name and all(c.isalnum() or c in "_-" for c in name)):
            raise ValueError(f"name {name!r}: letters, digits, '_' and '-' only, not empty")
        if not (isinstance(self.label, str) and self.label):
            raise ValueError(f"{name}: label {self.label!r} must be a non-empty string")
        for field in ("detect", "plain_edge_ids", "plain_setup", "detect_many"):
            value = getattr(self, field)
            if (value is not None or field == "detect") and not callable(value):
                raise ValueError(f"{name}: {field} must be callable, got {type(value).__name__}")
        _subset(name, "role", (self.role,), ROLES)
        _subset(name, "variants", self.variants, VARIANTS)
        _subset(name, "engines", self.engines, ENGINES)
        if "intended" not in self.variants or "fast" not in self.engines:
            raise ValueError(f"{name}: variants must include 'intended' and engines 'fast'")
        _subset(name, "growth_variant", (self.growth_variant,), self.variants)
        if not (isinstance(self.style, tuple) and len(self.style) == 2 and all(isinstance(s, str) for s in self.style)):
            raise ValueError(f"{name}: style must be (colour, marker), got {self.style!r}")
        if self.plain_setup is not None and self.plain_edge_ids is None:
            raise ValueError(f"{name}: plain_setup without plain_edge_ids")

    @property
    def missing(self) -> tuple[str, ...]:
        """What this detector lacks, as the outputs say it: ``naive engine``, ``paper model``, ``plain loops``."""
        out = []
        if "naive" not in self.engines:
            out.append("naive engine")
        if self.paper_model is None:
            out.append("paper model")
        if self.plain_edge_ids is None:
            out.append("plain loops")
        return tuple(out)


def _subset(name: str, field: str, values: tuple[str, ...], allowed: tuple[str, ...]) -> None:
    if not isinstance(values, tuple) or not values or any(v not in allowed for v in values):
        raise ValueError(f"{name}: {field} {values!r} must be taken from {', '.join(allowed)}")


__all__ = ["DetectorSpec", "ENGINES", "ROLES", "VARIANTS"]
