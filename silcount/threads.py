"""How many threads a parallel numba kernel gets: the cores that no other work is running on right now.

numba's ``omp`` layer splits a ``prange`` loop evenly between its threads and waits for the last one.  On a
machine where another process holds a core, one of two threads waits for the scheduler's next time slice
(milliseconds) while the other finishes: with the default spinning wait and a spinning process beside it,
a 1.9 ms gaussmap ``detect`` of the 1.04 M-face bunny took 230 ms and the reference kernel 16x its one-thread
time (load 3.3; ``benchmarks/busy.py``, docs/performance.md, "Busy machines").  ``silcount/__init__.py``
therefore asks the OpenMP runtime for a passive wait (``OMP_WAIT_POLICY=passive``: an idle pool thread
sleeps and leaves its core to others), and :func:`fitted` lowers the thread count of one call to the cores
that are free at its start.

"Free" is read from the kernel's count of runnable threads (``/proc/loadavg``'s fourth field, which
counts the caller itself): the cores this process may use (``os.sched_getaffinity``) minus the other
threads that are running or waiting to run, at least one.  Reading it costs about 4 us.  Where that file
does not exist (not Linux) every core counts as free.  The count only ever goes down from numba's own
(``numba.get_num_threads()``, the caller's ceiling: a corpus worker's one thread stays one), and it is the
caller's thread's setting, restored on exit (``numba.set_num_threads`` is per thread).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import wraps
from typing import ParamSpec, TypeVar

P = ParamSpec("P")
R = TypeVar("R")

LOADAVG = "/proc/loadavg"
_fd: list[int] = []  # the file kept open: a pread of it is 4 us, an open and a read 30 us


def _runnable() -> int | None:
    """Threads running or ready to run on the whole machine, the caller included (None: unknown here)."""
    if not _fd:
        try:
            _fd.append(os.open(LOADAVG, os.O_RDONLY))
        except OSError:
            return None
    field = os.pread(_fd[0], 128, 0).split()[3]  # b"0.52 0.58 0.59 3/171 12345": running/total
    return int(field.partition(b"/")[0])


def free_cores() -> int:
    """The cores of this process's affinity set that no other runnable thread is waiting for, at least 1."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    running = _runnable()
    if running is None:
        return cores
    return max(1, min(cores, cores - (running - 1)))


@contextmanager
def fitted() -> Iterator[int]:
    """numba's thread count for this thread lowered to :func:`free_cores` inside the block; the count used."""
    import numba

    before = numba.get_num_threads()
    threads = min(before, free_cores())
    if threads == before:
        yield threads
        return
    numba.set_num_threads(threads)
    try:
        yield threads
    finally:
        numba.set_num_threads(before)


def fitted_call(fn: Callable[P, R]) -> Callable[P, R]:
    """``fn`` run inside :func:`fitted`: for the Python functions that launch parallel kernels."""

    @wraps(fn)
    def call(*args: P.args, **kwargs: P.kwargs) -> R:
        with fitted():
            return fn(*args, **kwargs)

    return call
