"""Counting arithmetic: the evidence behind the ``true`` cost model.

The ``naive`` engine of every detector runs its pseudo-code on these types,
so every scalar operation it performs is tallied as it happens:

* :class:`Num` wraps one scalar; ``+``/``-`` count one ``add``, ``*`` one
  ``mul``, ``/`` one ``div``, each comparison one ``cmp``.
* :class:`Memory` wraps an array; reading one element counts one ``read``,
  storing one counts one ``write``.  Elements come back as :class:`Num`.

Loop bookkeeping (the loop variable's increment and bound test) is not
counted, in the papers or here; see ``docs/counting.md`` for every rule.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

KINDS: tuple[str, ...] = ("add", "mul", "cmp", "read", "write")
"""The papers' five operation kinds; tallies may carry others (e.g. ``div``)."""


class OpCounter(Counter):
    """A tally being accumulated: kind -> count."""

    def tick(self, kind: str, n: int = 1) -> None:
        self[kind] += n


class Num:
    """A scalar whose arithmetic and comparisons are counted on ``counter``."""

    __slots__ = ("value", "counter")

    def __init__(self, value, counter: OpCounter) -> None:
        self.value = value
        self.counter = counter

    def _v(self, other):
        return other.value if isinstance(other, Num) else other

    def _op(self, kind: str, value) -> "Num":
        self.counter[kind] += 1
        return Num(value, self.counter)

    def __add__(self, o):
        return self._op("add", self.value + self._v(o))

    __radd__ = __add__

    def __sub__(self, o):
        return self._op("add", self.value - self._v(o))

    def __rsub__(self, o):
        return self._op("add", self._v(o) - self.value)

    def __mul__(self, o):
        return self._op("mul", self.value * self._v(o))

    __rmul__ = __mul__

    def __truediv__(self, o):
        return self._op("div", self.value / self._v(o))

    def __rtruediv__(self, o):
        return self._op("div", self._v(o) / self.value)

    def _cmp(self, result) -> bool:
        self.counter["cmp"] += 1
        return bool(result)

    def __lt__(self, o):
        return self._cmp(self.value < self._v(o))

    def __le__(self, o):
        return self._cmp(self.value <= self._v(o))

    def __gt__(self, o):
        return self._cmp(self.value > self._v(o))

    def __ge__(self, o):
        return self._cmp(self.value >= self._v(o))

    def __eq__(self, o):
        return self._cmp(self.value == self._v(o))

    def __ne__(self, o):
        return self._cmp(self.value != self._v(o))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Num({self.value!r})"


class Memory:
    """An array whose element reads and writes are counted (one per scalar)."""

    __slots__ = ("data", "counter")

    def __init__(self, data, counter: OpCounter) -> None:
        self.data = np.asarray(data) if not isinstance(data, list) else data
        self.counter = counter

    def __len__(self) -> int:
        return len(self.data)

    def __getitem__(self, idx) -> Num:
        self.counter["read"] += 1
        value = self.data[idx]
        return Num(value.item() if hasattr(value, "item") else value, self.counter)

    def __setitem__(self, idx, value) -> None:
        self.counter["write"] += 1
        self.data[idx] = value.value if isinstance(value, Num) else value


def plain(x):
    """The raw value of a :class:`Num` (free: used for control flow and indexing)."""
    return x.value if isinstance(x, Num) else x
