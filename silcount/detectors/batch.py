"""The result of one detector run for many lights, columnar: :class:`SilhouetteBatch`.

A batch holds every light's edge ids as CSR (``offsets``, ``ids``: light ``i``'s ascending distinct ids are
``ids[offsets[i]:offsets[i + 1]]``), its steps and ``true`` tallies as ``(lights, names)`` integer arrays
(``-1``: that light's run did not count that step or kind) and its ties as one array.  It is a
``Sequence[Silhouette]``: ``batch[i]`` and iteration make the light's :class:`.result.Silhouette` when it is
asked for, equal field by field to what :func:`silcount.detectors.detect` returns for that light
(``tests/test_detect_many.py``).  Consumers of many lights (the corpus sweep) read the arrays instead
(:meth:`SilhouetteBatch.paper_counts`, :func:`common_many`) and make no per-light object.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, overload

import numpy as np
from numba import njit

from silcount.counting import models
from silcount.counting.arithmetic import KINDS
from silcount.detectors.result import Silhouette, _common, _units
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

ABSENT = -1
"""The count of a step or kind that a light's run did not count (counts are never negative)."""


@dataclass(eq=False)
class SilhouetteBatch(Sequence[Silhouette]):
    """One detector's ``detect_many`` result: light ``i``'s run is row ``i`` of every array.

    ``notes`` are the light-independent notes (a tree's build, HSD's merge), shared by every light;
    ``light_notes`` name -> one value per light; ``orient(i, ids)`` gives light ``i``'s ``oriented`` edges.
    A batch made of ready :class:`Silhouette` results (:meth:`of_silhouettes`: a plug-in's list, a ``naive``
    engine) hands those same objects back.
    """

    detector: str
    variant: str
    engine: str
    offsets: np.ndarray  # (n + 1,) int64
    ids: np.ndarray  # (offsets[-1],) int64, each light's ascending distinct edge ids
    step_names: tuple[str, ...]
    steps: np.ndarray  # (n, len(step_names)) int64, ABSENT where not counted
    kinds: tuple[str, ...]  # KINDS first, then other kinds in order of first appearance
    true: np.ndarray  # (n, len(kinds)) int64, ABSENT where the light's tally lacks the kind
    ties: np.ndarray  # (n,) int64
    paper_model: str | None
    paper_params: dict[str, float]
    mesh: Mesh | None = field(default=None, repr=False)
    lights: list[Light] = field(default_factory=list, repr=False)
    notes: dict[str, Any] = field(default_factory=dict)
    light_notes: dict[str, list] = field(default_factory=dict)
    orient: Callable[[int, np.ndarray], np.ndarray] | None = field(default=None, repr=False)
    items: list[Silhouette] | None = field(default=None, repr=False)

    def __len__(self) -> int:
        return int(self.offsets.size) - 1

    @overload
    def __getitem__(self, i: int) -> Silhouette: ...

    @overload
    def __getitem__(self, i: slice) -> list[Silhouette]: ...

    def __getitem__(self, i: int | slice) -> Silhouette | list[Silhouette]:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        n = len(self)
        if not -n <= i < n:
            raise IndexError(f"light {i} of a batch of {n}")
        i = int(i) % n
        if self.items is not None:
            return self.items[i]
        return self._silhouette(i)

    def __iter__(self) -> Iterator[Silhouette]:
        return (self[i] for i in range(len(self)))

    def __eq__(self, other: object) -> bool:
        """Equal to a sequence of the same Silhouettes (``detect_many(mesh, []) == []``)."""
        if isinstance(other, Sequence) and not isinstance(other, str):
            return len(self) == len(other) and all(a == b for a, b in zip(self, other, strict=True))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def edge_ids(self, i: int) -> np.ndarray:
        """Light ``i``'s ascending distinct edge ids (a view into :attr:`ids`)."""
        return self.ids[self.offsets[i] : self.offsets[i + 1]]

    @property
    def n_edges(self) -> np.ndarray:
        """(n,) each light's silhouette edge count."""
        return np.diff(self.offsets)

    def step(self, name: str) -> np.ndarray | None:
        """(n,) the counts of step ``name`` (``ABSENT`` where not counted), or ``None`` if no light counted it."""
        return self.steps[:, self.step_names.index(name)] if name in self.step_names else None

    def light_notes_of(self, i: int) -> dict[str, Any]:
        """Light ``i``'s notes: the shared ones and its own."""
        if self.items is not None:
            return self.items[i].notes
        return {**self.notes, **{k: v[i] for k, v in self.light_notes.items()}}

    def paper_counts(self) -> tuple[tuple[str, ...], np.ndarray]:
        """The ``paper`` tally of every light as (kinds, (n, kinds) int64), ``ABSENT`` where a light's tally lacks
        a kind: :func:`.result.paper_tally`'s integers (``sum(steps x unit cost)``), one product per step."""
        assert self.paper_model is not None
        units = _units(self.paper_model, tuple(sorted(self.paper_params.items())))
        costs = []
        for step in self.step_names:
            unit = units.get(step)
            if unit is None:
                unit = units[step] = tuple(models.unit_cost(self.paper_model, step, self.paper_params).items())
            costs.append(dict(unit))
        kinds = tuple(dict.fromkeys([*KINDS, *(k for c in costs for k in c)]))
        n = len(self)
        out = np.zeros((n, len(kinds)), dtype=np.int64)
        present = np.zeros((n, len(kinds)), dtype=bool)
        present[:, : len(KINDS)] = True
        for j, cost in enumerate(costs):
            col = self.steps[:, j]
            counted = col != ABSENT
            for kind, c in cost.items():
                k = kinds.index(kind)
                out[:, k] += np.where(counted, col, 0) * int(c)
                present[:, k] |= counted
        return kinds, np.where(present, out, ABSENT)

    def _silhouette(self, i: int) -> Silhouette:
        ids = self.edge_ids(i).copy()
        orient = self.orient
        steps = {s: int(v) for s, v in zip(self.step_names, self.steps[i].tolist(), strict=True) if v != ABSENT}
        true = {k: int(v) for k, v in zip(self.kinds, self.true[i].tolist(), strict=True) if v != ABSENT}
        return Silhouette(
            detector=self.detector,
            variant=self.variant,
            engine=self.engine,
            edge_ids=ids,
            steps=steps,
            true_tally=true,
            paper_model=self.paper_model,
            paper_params=dict(self.paper_params),
            ties=int(self.ties[i]),
            notes=self.light_notes_of(i),
            mesh=self.mesh,
            light=self.lights[i] if self.lights else None,
            orient=None if orient is None else (lambda: orient(i, ids)),
        )

    @classmethod
    def of_silhouettes(cls, results: Sequence[Silhouette], mesh: Mesh | None = None) -> SilhouetteBatch:
        """The batch of ready results (a plug-in's ``detect_many`` list, a per-light run): their arrays, and the
        same objects handed back by ``batch[i]``.  An empty list makes an empty batch."""
        results = list(results)
        first = results[0] if results else None
        steps, step_names = counts_of([r.steps for r in results])
        true, kinds = counts_of([r.true_tally for r in results], KINDS)
        return cls(
            detector=first.detector if first else "",
            variant=first.variant if first else "intended",
            engine=first.engine if first else "fast",
            offsets=csr_offsets([r.edge_ids.size for r in results]),
            ids=np.concatenate([r.edge_ids for r in results]).astype(np.int64) if results else np.zeros(0, np.int64),
            step_names=step_names,
            steps=steps,
            kinds=kinds,
            true=true,
            ties=np.array([r.ties for r in results], dtype=np.int64),
            paper_model=first.paper_model if first else None,
            paper_params=dict(first.paper_params) if first else {},
            mesh=first.mesh if first else mesh,
            lights=[r.light for r in results if r.light is not None],
            notes={},
            items=results,
        )


def csr_offsets(sizes: Sequence[int] | np.ndarray) -> np.ndarray:
    """(n + 1,) int64 offsets of rows of these sizes."""
    out = np.zeros(len(sizes) + 1, dtype=np.int64)
    np.cumsum(np.asarray(sizes, dtype=np.int64), out=out[1:])
    return out


def counts_of(rows: Sequence[Mapping[str, int]], first: tuple[str, ...] = ()) -> tuple[np.ndarray, tuple[str, ...]]:
    """Per-light ``name -> count`` dicts as ((n, names) int64, names): ``first`` always present (0 if missing),
    the other names in order of first appearance, ``ABSENT`` where a light's dict lacks one."""
    names = tuple(dict.fromkeys([*first, *(k for r in rows for k in r)]))
    out = np.full((len(rows), len(names)), ABSENT, dtype=np.int64)
    out[:, : len(first)] = 0
    col = {k: j for j, k in enumerate(names)}
    for i, r in enumerate(rows):
        for k, v in r.items():
            out[i, col[k]] = int(v)
    return out, names


def columns_of(
    counts: Mapping[str, np.ndarray | int], n: int, first: tuple[str, ...] = ()
) -> tuple[np.ndarray, tuple[str, ...]]:
    """``name -> (n,) counts`` (or one count for every light) as ((n, names) int64, names), ``first`` first
    (0 where not given), every light counting every name."""
    names = tuple(dict.fromkeys([*first, *counts]))
    out = np.zeros((n, len(names)), dtype=np.int64)
    for j, k in enumerate(names):
        if k in counts:
            out[:, j] = counts[k]
    return out, names


def merge_groups(
    n: int, parts: Sequence[tuple[np.ndarray, Mapping[str, np.ndarray | int]]], first: tuple[str, ...] = ()
) -> dict[str, np.ndarray]:
    """Counts computed per group of lights (``(rows, name -> counts)``: the lights of one kind) as name -> (n,)
    int64 in light order; a name another group lacks is ``ABSENT`` there, but the names of ``first`` are 0."""
    names = dict.fromkeys([*first, *(k for _, counts in parts for k in counts)])
    out = {k: np.full(n, 0 if k in first else ABSENT, dtype=np.int64) for k in names}
    for rows, counts in parts:
        for k, v in counts.items():
            out[k][rows] = v
    return out


def rows_of(dicts: Sequence[Mapping[str, int]]) -> dict[str, np.ndarray]:
    """Per-light ``name -> count`` dicts as name -> (n,) int64, ``ABSENT`` where a light lacks the name."""
    arr, names = counts_of(dicts)
    return {k: arr[:, j] for j, k in enumerate(names)}


@njit(cache=True, nogil=True)
def _common_many(a_off, a_ids, b_off, b_ids):  # pragma: no cover - compiled
    """Per row, how many ids two CSR arrays of ascending distinct ids share: one merge pass a row."""
    n = a_off.size - 1
    out = np.zeros(n, dtype=np.int64)
    for r in range(n):
        out[r] = _common(a_ids[a_off[r] : a_off[r + 1]], b_ids[b_off[r] : b_off[r + 1]])
    return out


def common_many(found: SilhouetteBatch, reference: SilhouetteBatch) -> np.ndarray:
    """(n,) how many edges each light's ``found`` shares with its ``reference`` (the same lights, in order):
    the common count of :func:`.result.differences`, for every light in one compiled pass."""
    if len(found) != len(reference):
        raise ValueError(f"{len(found)} results against {len(reference)} reference results")
    return _common_many(found.offsets, found.ids, reference.offsets, reference.ids)


__all__ = [
    "ABSENT",
    "SilhouetteBatch",
    "columns_of",
    "common_many",
    "counts_of",
    "csr_offsets",
    "merge_groups",
    "rows_of",
]
