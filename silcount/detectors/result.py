"""The result of one detector run for one light: :class:`Silhouette`, with both cost models' tallies.

The ``paper`` tally is ``sum(steps x annotated cost)`` from ``silcount/models/``
(:func:`silcount.counting.models.paper_tally`), memoised per (model, mesh
parameters, step) and evaluated once per key (:func:`silcount.counting.models.unit_cost`, without sympy
for the models' integer costs); the ``true`` tally is what
the detector's engine observed or charged.  How the edges differ from the
reference silhouette is computed only when asked for (:attr:`Silhouette.agreement`,
:func:`compare_with_reference`, :func:`differences`): a detection never runs a
second, reference detection of its own.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache, cached_property
from typing import Any

import numpy as np
from numba import njit

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.detectors.adjacency import silhouette_edge_ids
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh


@dataclass
class EngineRun:
    """What one engine of a detector found and counted for one light, before it becomes a :class:`Silhouette`.

    ``edge_ids``: the edges found, as the algorithm leaves them (any order; TA's, HSD's and literal EESD's S
    may hold an edge more than once); ``steps``: step -> runs; ``true_tally``: kind -> count, as executed
    (``naive``) or charged (``fast``); ``ties``: facing values exactly 0; ``is_facing``: the light-facing
    flags of the faces, or a function computing them, to orient the edges; ``pairs``: the (from, to) vertex
    pairs in S's order, for detectors whose S keeps a direction (TA, HSD); ``notes``: the detector's own.
    """

    edge_ids: np.ndarray
    steps: dict[str, int]
    true_tally: dict[str, int]
    ties: int
    is_facing: np.ndarray | Callable[[], np.ndarray]
    pairs: np.ndarray | None = None
    notes: dict[str, Any] = field(default_factory=dict)


@dataclass
class Silhouette:
    """The result of one detector run for one light.

    ``edges``, ``oriented`` and ``tally`` are computed on first access (a
    query that only needs ``edge_ids`` pays for nothing else); the ``paper``
    tally's per-step costs are evaluated once per (model, mesh parameters).
    """

    detector: str
    variant: str
    engine: str
    edge_ids: np.ndarray  # (k,) ids into mesh.edges, ascending
    steps: dict[str, int]  # how many times each named step ran
    true_tally: dict[str, int]  # the ``true`` cost model: kind -> count, as observed
    paper_model: str | None  # the cost model file whose per-line costs give the ``paper`` cost model, if any
    paper_params: dict[str, float]  # the mesh's own e_n, f_n, m at which those costs are evaluated
    ties: int = 0  # faces whose facing value is exactly 0 (gaussmap, cones: such evaluations, once per edge)
    notes: dict[str, Any] = field(default_factory=dict)
    mesh: Mesh | None = field(default=None, repr=False)  # the mesh the ids index
    light: Light | None = field(default=None, repr=False)  # the light they answer
    orient: Callable[[], np.ndarray] | None = field(default=None, repr=False)  # computes ``oriented``

    @cached_property
    def edges(self) -> np.ndarray:
        """(k, 2) welded vertex indices, rows sorted, rows in order."""
        assert self.mesh is not None
        return self.mesh.edges[self.edge_ids]

    @cached_property
    def oriented(self) -> np.ndarray:
        """(k, 2) the same edges, as traversed by their light-facing face."""
        assert self.orient is not None
        return self.orient()

    @cached_property
    def tally(self) -> dict[str, dict[str, int]]:
        """Cost model (``"paper"``, ``"true"``) -> kind -> count; the paper model is evaluated on first access.
        A detector without a paper cost model (``paper_model`` is ``None``) has the ``true`` tally alone."""
        if self.paper_model is None:
            return {"true": self.true_tally}
        return {"paper": paper_tally(self.paper_model, self.steps, self.paper_params), "true": self.true_tally}

    @property
    def n_edges(self) -> int:
        return int(self.edge_ids.size)

    @cached_property
    def agreement(self) -> dict[str, int]:
        """:func:`compare_with_reference` of these edges, on first access (one reference kernel run).

        The reference detector's own result agrees with itself: zeros, without a second run.
        """
        if self.detector == "reference":
            return differences(self.edge_ids, self.edge_ids)
        assert self.mesh is not None and self.light is not None
        return compare_with_reference(self.mesh, self.light, self.edge_ids)


@njit(cache=True)
def _common(a, b):  # pragma: no cover - compiled
    """How many ids two ascending arrays of distinct ids share: one merge pass."""
    i = j = n = 0
    while i < a.size and j < b.size:
        if a[i] < b[j]:
            i += 1
        elif a[i] > b[j]:
            j += 1
        else:
            n += 1
            i += 1
            j += 1
    return n


def differences(found: np.ndarray, reference: np.ndarray) -> dict[str, int]:
    """How ascending distinct edge ids ``found`` differ from ``reference`` (counts of edges).

    ``missed_edges``: reference edges not found; ``extra_edges``: edges found
    that the reference does not have; ``disagreement_with_reference``: both.
    """
    found = np.ascontiguousarray(found, dtype=np.int64)
    reference = np.ascontiguousarray(reference, dtype=np.int64)
    common = int(_common(found, reference))
    missed, extra = int(reference.size) - common, int(found.size) - common
    return {"missed_edges": missed, "extra_edges": extra, "disagreement_with_reference": missed + extra}


def compare_with_reference(mesh: Mesh, light: Light, edge_ids: np.ndarray) -> dict[str, int]:
    """:func:`differences` of ascending distinct ``edge_ids`` from the reference silhouette of ``mesh``, ``light``."""
    return differences(edge_ids, silhouette_edge_ids(mesh, light))


@cache
def _units(model: str, params: tuple[tuple[str, float], ...]) -> dict[str, tuple[tuple[str, int], ...]]:
    """The ``paper`` cost of one run of each step at ``params``, filled in as steps are asked for (one
    :func:`silcount.counting.models.unit_cost` per model, parameters and step)."""
    return {}


def paper_tally(model: str, steps: dict[str, int], params: dict[str, float]) -> dict[str, int]:
    """:func:`silcount.counting.models.paper_tally`, memoised: ``sum(count x unit cost)``, the same integers."""
    units = _units(model, tuple(sorted(params.items())))
    total = {k: 0 for k in KINDS}
    for step, count in steps.items():
        unit = units.get(step)
        if unit is None:
            unit = units[step] = tuple(models.unit_cost(model, step, params).items())
        for kind, c in unit:
            total[kind] = total.get(kind, 0) + int(count) * c
    return total


__all__ = ["EngineRun", "Silhouette", "compare_with_reference", "differences", "paper_tally"]
