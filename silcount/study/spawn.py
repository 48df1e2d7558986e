"""A *spawn* context whose processes do not run the caller's ``__main__`` again.

A spawned process normally re-imports the parent's main script (as ``__mp_main__``) so that it can unpickle
functions defined there.  The corpus's workers run silcount's own functions only, and the re-import breaks a
plain script: an unguarded ``silcount.corpus(...)`` at its top level runs again in each worker, which
multiprocessing refuses ("... before the current process has finished its bootstrapping phase"), and a script
piped through stdin has no file to import (``FileNotFoundError: '<stdin>'``).  So each process is started
while ``sys.modules["__main__"]`` is a bare module: the preparation data it is sent
(``multiprocessing.spawn.get_preparation_data``) then names no main module, and the child keeps its own.
"""

from __future__ import annotations

import multiprocessing.context
import sys
import threading
import types

_LOCK = threading.Lock()  # one start at a time, so that every start restores the real __main__


class SpawnProcess(multiprocessing.context.SpawnProcess):
    """A spawned process, started without the caller's ``__main__`` (named as multiprocessing's own)."""

    @staticmethod
    def _Popen(process_obj):
        with _LOCK:
            main = sys.modules["__main__"]
            sys.modules["__main__"] = types.ModuleType("__main__")
            try:
                return multiprocessing.context.SpawnProcess._Popen(process_obj)
            finally:
                sys.modules["__main__"] = main


class _Context(multiprocessing.context.SpawnContext):
    Process = SpawnProcess


def spawn_context() -> multiprocessing.context.SpawnContext:
    """The ``spawn`` context for :class:`concurrent.futures.ProcessPoolExecutor`, without ``__main__``'s re-run."""
    return _Context()
