"""What the rules may measure with: growth exponents (any source, witness families too), stencil steps, real meshes."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import overload

from silcount.papers.growth import Exponent


class Deferred(Sequence[Exponent]):
    """Exponents measured on first use: a paper whose rules never read them (a user's paper) never runs the sweep."""

    def __init__(self, measure: Callable[[], tuple[Exponent, ...]]) -> None:
        self._measure = measure

    @cached_property
    def _values(self) -> tuple[Exponent, ...]:
        return tuple(self._measure())

    @overload
    def __getitem__(self, i: int) -> Exponent: ...
    @overload
    def __getitem__(self, i: slice) -> Sequence[Exponent]: ...
    def __getitem__(self, i):
        return self._values[i]

    def __len__(self) -> int:
        return len(self._values)

    def __iter__(self) -> Iterator[Exponent]:
        return iter(self._values)


@dataclass(frozen=True)
class Evidence:
    """Measured inputs of the claims.

    ``exponents``: growth exponents with confidence intervals, from any number of sources (the icosphere
    sweep of :mod:`silcount.papers.growth` by default; the corpus sweep plugs in here); ``stencil``: the
    render experiments' mismatch of each literal stencil step against ray casting, or None when not
    measured; ``real``: whether the shared real meshes (``$SILCOUNT_MESH_DIR``) are measured too;
    ``worst``: growth exponents on witness families, inputs built or found to be expensive
    (:mod:`silcount.papers.witness`): lower bounds on the worst case, which judges an O() claim.  Either
    the exponents themselves, or a function from a detector's name to its exponents, asked only for the
    detectors whose O() claims are judged (:meth:`worst_for`): a user's paper about any registered detector
    gets its worst case searched for, and no other detector's is.
    """

    exponents: Sequence[Exponent]
    stencil: dict[str, dict] | None = None
    real: bool = False
    worst: Sequence[Exponent] | Callable[[str], Sequence[Exponent]] = ()

    def worst_for(self, detector: str) -> list[Exponent]:
        """The witness families' exponents of ``detector``'s total true operations."""
        got = self.worst(detector) if callable(self.worst) else self.worst
        return [e for e in got if e.detector == detector and e.cost_model == "true"]
