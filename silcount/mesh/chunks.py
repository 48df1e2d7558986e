"""Long compiled loops run in chunks from Python: Ctrl-C between chunks, and a limit on the work done.

A numba kernel does not see signals: Python's SIGINT handler only sets a flag
that the interpreter acts on once the kernel returns.  So every kernel whose
run grows with a hostile input (stacked triangles, a ray through a pile of
them, a plane through a flat mesh) is called on consecutive ranges of its
items by :func:`run_chunks`, each range sized to take about
:data:`TARGET_S` seconds (doubled while chunks run fast, cut in proportion when one
runs slow): a KeyboardInterrupt lands between two chunks, within a second or two.

Each chunk reports its elementary tests (ray-triangle tests, plane-point
tests); a :class:`Meter` sums them over one computation and raises
:class:`silcount.errors.TooMuchWork` once they pass the work limit: the
``--max-work`` option (:func:`limit_work`), else ``$SILCOUNT_MAX_WORK``,
else :data:`DEFAULT_MAX_WORK`.  The count is that of the results' own
computation, so it is the same on every run and every schedule.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import time
from collections.abc import Callable, Iterator

from silcount.errors import BadArgument, TooMuchWork

WORK_ENV = "SILCOUNT_MAX_WORK"
# tests of one computation (one light's rays, one light's plane walk).  EESD literal on a 1 M-face torus makes
# 2.8e10 plane tests in about 25 s on 2 cores (so the limit is some 90 s of them; a 4 M-face torus's,
# about 2.2e11 by F^1.5, are refused), the rays of every light on it 1.7e7
DEFAULT_MAX_WORK = 100_000_000_000
TARGET_S = 0.25  # a chunk's wall time aimed at
FIRST = 16  # items in the first chunk (doubled up to the target: a few chunks more, none too long)

_LIMIT: contextvars.ContextVar[int | None] = contextvars.ContextVar("silcount_max_work", default=None)


def parse_work(text: str, what: str) -> int:
    """``"2e10"`` or ``"20000000000"`` -> 20000000000; a :class:`BadArgument` naming ``what`` otherwise."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value >= 1 and value < 2**63):
        raise BadArgument(f"{what} {text!r}: expected a number of tests >= 1 (e.g. 2e10)")
    return int(value)


def work_limit() -> int:
    """The limit in force: :func:`limit_work`'s, else ``$SILCOUNT_MAX_WORK``, else :data:`DEFAULT_MAX_WORK`."""
    got = _LIMIT.get()
    if got is not None:
        return got
    env = os.environ.get(WORK_ENV)
    return parse_work(env, f"${WORK_ENV}") if env else DEFAULT_MAX_WORK


@contextlib.contextmanager
def limit_work(limit: int | None) -> Iterator[None]:
    """Within the block, :func:`work_limit` is ``limit`` (None: unchanged)."""
    token = _LIMIT.set(limit) if limit is not None else None
    try:
        yield
    finally:
        if token is not None:
            _LIMIT.reset(token)


class Meter:
    """The elementary tests of one computation named ``what``, against the limit in force when it was made."""

    def __init__(self, what: str) -> None:
        self.what, self.limit, self.done = what, work_limit(), 0

    def add(self, tests: int) -> None:
        self.done += int(tests)
        if self.done > self.limit:
            raise TooMuchWork(self.what, self.done, self.limit)


def run_chunks(n: int, run: Callable[[int, int], int], meter: Meter | None = None, first: int = FIRST) -> None:
    """``run(lo, hi)`` over consecutive ranges covering ``0 .. n``, each sized to take about :data:`TARGET_S`;
    ``run`` returns its elementary tests, added to ``meter``.  Between two calls Python handles signals."""
    lo, size = 0, first
    while lo < n:
        hi = min(n, lo + size)
        t0 = time.perf_counter()
        tests = run(lo, hi)
        took = time.perf_counter() - t0
        if meter is not None:
            meter.add(tests)
        lo = hi
        if took < TARGET_S / 4:
            size *= 2
        elif took > TARGET_S:
            size = max(1, int(size * TARGET_S / took))


__all__ = ["WORK_ENV", "DEFAULT_MAX_WORK", "Meter", "limit_work", "parse_work", "run_chunks", "work_limit"]
