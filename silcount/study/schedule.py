"""Running the corpus's units of work on Dask: in-process threads or processes, or a cluster.

* ``threads`` / ``processes`` (no service to start): Dask's local schedulers
  (``dask.compute(..., scheduler=..., num_workers=N)``); a scheduler callback
  takes each result as it finishes, in the client process.
* ``tcp://HOST:PORT``: an existing ``dask.distributed`` cluster
  (``dask scheduler`` plus ``dask worker tcp://HOST:PORT`` processes).  The
  client scatters each file's bytes, so workers need no shared filesystem,
  and collects results with ``as_completed``; a unit whose worker died
  (``KilledWorker``) becomes that mesh's error row.

Either way every finished unit goes to the cache (:mod:`silcount.study.cache`)
at once, and the results are returned in the order of ``items``, whatever the
order of completion: nothing downstream depends on the scheduler or the
worker count.

Scheduling (docs/corpus.md, "Scheduling"):

* **largest first.**  Units start in decreasing order of :func:`unit_cost`,
  their estimated seconds (:mod:`silcount.study.units`, from the faces the
  file declares times ``4 ** level``, as each subdivision level quadruples
  them; the file's bytes, which say little across formats, only for a file
  whose faces cannot be read cheaply), so that the biggest mesh does not
  start last and leave the other workers idle at the end.  Locally the order is carried by
  the task names (Dask's local schedulers run independent tasks in
  descending name order; ``tests/test_corpus.py`` checks the start order);
  on a cluster by ``priority``.  Dask's ``processes`` scheduler hands its
  workers batches of 6 ready tasks by default (its ``chunksize``): the six
  largest units then ran one after another on one worker while the other
  took the next six, and the last batch left a worker idle for a whole
  batch; units are therefore handed out one at a time (``chunksize=1``), on
  silcount's own pool, shut down without waiting so that the workers' exit
  overlaps the client's tables.
* **memory and balance** (:mod:`silcount.study.parts`).  A unit whose estimated
  peak is over the worker's memory budget runs in parts (groups of its
  detectors, then batches of its lights) that fit, or is refused in one line;
  a unit that would take more than ``1 / (2 W)`` of the estimated sweep on
  ``W`` workers runs as up to ``W`` batches of its lights, so that it does not
  run alone at the end.  The parts' results are joined into the unit's
  before they are cached.
* **one level of parallelism.**  Each unit runs numba's parallel kernels on
  ``cores // workers`` threads locally (all cores for one worker, one thread
  each for two workers on two cores) and on one thread on a cluster, whose
  workers are meant to hold one thread per core.  Two workers that each ran
  numba's OpenMP pool on every core spun against each other: the shared
  corpus took 84.2 s on two workers against 87.8 s on one.

Ctrl-C: a terminal sends SIGINT to the whole foreground process group, the
``processes`` workers included, which printed two ``KeyboardInterrupt``
tracebacks (67 lines) when it came while they were starting.  The workers are
therefore spawned with SIGINT blocked, which they inherit, and the client,
which gets the signal as ever, terminates them (they write nothing: every
result is cached by the client, so a rerun resumes from the finished units).
"""

from __future__ import annotations

import math
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import CancelledError
from contextlib import contextmanager
from dataclasses import dataclass

from silcount.errors import BadArgument
from silcount.progress import progress
from silcount.study import parts as split
from silcount.study.cache import Cache, cache_key
from silcount.study.units import default_budget, load_model
from silcount.study.work import Part, Settings, audit_task, row_columns

LOCAL = ("threads", "processes")
CONNECT_TIMEOUT = "20s"
RESUBMITS = 3  # times a unit whose scattered input died with a worker is sent again


@dataclass(frozen=True)
class Item:
    """One unit of work: a file's name in the sweep, its bytes and digest, a subdivision level."""

    label: str
    data: bytes
    sha256: str
    level: int
    read_error: str | None = None  # the client could not read the file: an error row, nothing to run
    faces: int | None = None  # the faces the file declares (None: unknown), before subdivision


@dataclass(frozen=True)
class Task:
    """What a worker runs: item ``index`` whole (``part`` None) or one of its parts, and its estimated seconds."""

    index: int
    part: Part | None
    seconds: float


def check_scheduler(scheduler: str) -> None:
    if scheduler not in LOCAL and not scheduler.startswith("tcp://"):
        raise BadArgument(f"--scheduler {scheduler!r}: choose threads, processes or tcp://HOST:PORT")


def run_items(
    items: list[Item],
    settings: Settings,
    scheduler: str = "processes",
    workers: int | None = None,
    cache: Cache | None = None,
    quiet: bool = False,
    memory_budget: int | None = None,
    timeline: list[float] | None = None,
) -> list[dict]:
    """Every item's result (cached ones read back), in the order of ``items``.

    ``memory_budget``: a worker's peak bytes (default :func:`~silcount.study.units.default_budget` of the
    local workers; none on a cluster); ``timeline``, if given, gets the ``time.perf_counter()`` of each
    finished task (a unit or a part).
    """
    check_scheduler(scheduler)
    cache = cache or Cache(None)
    local = workers or os.cpu_count() or 1
    if memory_budget is None and scheduler in LOCAL:
        memory_budget = default_budget(local)
    keys = [cache_key(it.sha256, it.level, settings) for it in items]
    results: list[dict | None] = [
        _failed(it, it.read_error) if it.read_error else cache.get(k, settings) for it, k in zip(items, keys)
    ]
    todo = [i for i, r in enumerate(results) if r is None]
    failures = sum(bool(r and r.get("error")) for r in results)
    with progress(len(items), "corpus meshes", enabled=None if not quiet else False) as bar:
        bar.update(len(items) - len(todo))

        def finish(i: int, result: dict) -> None:
            nonlocal failures
            results[i] = result
            cache.put(keys[i], result, settings)
            failures += bool(result.get("error"))
            bar.set_postfix_str(f"failures {failures}", refresh=False)
            bar.update()

        tasks, refused = plan_tasks(items, todo, settings, local if scheduler in LOCAL else 1, memory_budget)
        for i, line in refused.items():
            finish(i, _failed(items[i], line))
        joiner = _Joiner(tasks, settings, finish, timeline)
        if tasks and scheduler in LOCAL:
            _local(items, tasks, settings, scheduler, local, joiner.done)
        elif tasks:
            _distributed(items, tasks, settings, scheduler, joiner.done)
    return [r for r in results if r is not None]


def plan_tasks(
    items: list[Item], todo: list[int], settings: Settings, workers: int, budget: int | None
) -> tuple[list[Task], dict[int, str]]:
    """The tasks of the units ``todo``, largest first, and the units refused (index -> their one line).

    See "memory and balance" in the module docstring.  A unit whose faces are unknown runs whole.
    """
    model = load_model()
    seconds = {i: unit_cost(items[i], settings) for i in todo}
    total = sum(seconds.values())
    tasks: list[Task] = []
    refused: dict[int, str] = {}
    for i in todo:
        faces = _faces(items[i])
        if faces is None:
            tasks.append(Task(i, None, seconds[i]))
            continue
        planned: list[Part] | str = [Part(tuple(settings.detectors), 0, split.total_lights(settings))]
        if budget is not None:
            planned = split.by_memory(settings, budget, lambda d, n, f=faces: model.peak_bytes(f, settings, d, n))
        if isinstance(planned, str):
            refused[i] = planned
            continue
        if workers > 1 and total > 0:
            planned = split.by_time(planned, min(workers, math.ceil(2 * workers * seconds[i] / total)))
        if len(planned) == 1:
            tasks.append(Task(i, None, seconds[i]))
            continue
        tasks += [Task(i, p, model.seconds(faces, settings, p.detectors, p.hi - p.lo)) for p in planned]
    tasks.sort(key=lambda t: (-t.seconds, t.index, t.part.lo if t.part else 0))
    return tasks, refused


class _Joiner:
    """Takes each task's result; when a unit's tasks are all in, its result (parts merged) goes to ``finish``."""

    def __init__(self, tasks: list[Task], settings: Settings, finish: Callable, timeline: list[float] | None):
        self.settings, self.finish, self.timeline = settings, finish, timeline
        rank = {d: k for k, d in enumerate(settings.detectors)}
        self.tasks: dict[int, list[Task]] = {}
        for t in tasks:
            self.tasks.setdefault(t.index, []).append(t)
        for own in self.tasks.values():  # parts in the unit's order: detector groups, then batches of lights
            own.sort(key=lambda t: (rank[t.part.detectors[0]], t.part.lo) if t.part else (0, 0))
        self.got: dict[int, dict[Task, dict]] = {}

    def done(self, task: Task, result: dict) -> None:
        if self.timeline is not None:
            self.timeline.append(time.perf_counter())
        own = self.tasks[task.index]
        got = self.got.setdefault(task.index, {})
        got[task] = result
        if len(got) < len(own):
            return
        del self.got[task.index]
        parts = [t.part for t in own if t.part is not None]
        if not parts:
            self.finish(task.index, result)
        else:
            self.finish(task.index, split.merge([got[t] for t in own], parts, self.settings))


def _faces(item: Item) -> int | None:
    """The unit's faces after subdivision (each level quadruples a triangle mesh's), or None if unknown."""
    return None if item.faces is None else item.faces * 4**item.level


def unit_cost(item: Item, settings: Settings) -> float:
    """The scheduling estimate of a unit's work: its estimated seconds (:mod:`silcount.study.units`), or,
    when its faces are unknown, its file's bytes times ``4 ** level`` over :data:`BYTES_PER_SECOND`."""
    faces = _faces(item)
    if faces is None:
        return len(item.data) * 4**item.level / BYTES_PER_SECOND
    return load_model().seconds(faces, settings)


BYTES_PER_SECOND = 1e6
"""A file's bytes per second of work, for a unit whose faces are unknown (ranks it among the others)."""


def audit_on_threads(
    threads: int, label: str, data: bytes, level: int, settings: Settings, part: Part | None = None
) -> dict:
    """:func:`~silcount.study.work.audit_task` with numba's parallel kernels on ``threads`` threads.

    ``numba.set_num_threads`` is per thread, so a Dask thread pool's threads each keep their own setting;
    the previous one is restored afterwards.
    """
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))  # type: ignore[attr-defined]
    try:
        return (
            audit_task(label, data, level, settings) if part is None else audit_task(label, data, level, settings, part)
        )
    finally:
        numba.set_num_threads(before)


def _local(
    items: list[Item], tasks: list[Task], settings: Settings, scheduler: str, workers: int, done: Callable
) -> None:
    # the processes start before Dask's import (0.3 s of the client's time), so that their own start overlaps it
    pool = None
    try:
        with _ctrl_c_remembered() as heard:
            pool = process_pool(min(workers, len(tasks))) if scheduler == "processes" else None  # threads: Dask's
            _compute(items, tasks, settings, scheduler, workers, done, pool, heard)
            if pool is not None:  # the workers' exit waited for here, where a Ctrl-C is the sweep's to report:
                pool.shutdown(wait=True)  # left to the interpreter's exit, a Ctrl-C then printed a traceback
    except KeyboardInterrupt:
        if pool is not None:
            stop_workers(pool)  # they do not hear Ctrl-C themselves (process_pool)
            _settle(pool)
        raise
    finally:
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)  # after an error, queued units do not run


def _compute(
    items: list[Item],
    tasks: list[Task],
    settings: Settings,
    scheduler: str,
    workers: int,
    done: Callable,
    pool,
    heard: Callable[[], None],
) -> None:
    """``tasks`` on Dask's local ``scheduler`` (on ``pool`` for ``processes``), each result to ``done``;
    ``heard()`` raises a Ctrl-C that Python swallowed (:func:`_ctrl_c_remembered`)."""
    import dask
    from dask import multiprocessing, threaded
    from dask.callbacks import Callback

    heard()  # a Ctrl-C during the import can land in an import lock's callback, where Python ignores it

    # ``tasks`` is largest first; Dask starts independent tasks in descending name order
    names = {f"silcount-corpus-{len(tasks) - rank:06d}": t for rank, t in enumerate(tasks)}
    threads = max(1, (os.cpu_count() or 1) // workers)

    class Collect(Callback):
        def _posttask(self, key, result, dsk, state, id):  # noqa: A002 - dask's signature
            heard()
            if key in names:
                done(names[key], result)

    delayed = [
        dask.delayed(audit_on_threads, pure=False)(
            threads,
            items[t.index].label,
            items[t.index].data,
            items[t.index].level,
            settings,
            t.part,
            dask_key_name=name,
        )  # fmt: skip
        for name, t in names.items()
    ]
    with Collect():
        # the scheduler's function itself, not its name: a name makes Dask import distributed (0.3 s) to
        # look for a default client, which a named local scheduler ignores anyway
        get = multiprocessing.get if scheduler == "processes" else threaded.get
        dask.compute(*delayed, scheduler=get, num_workers=workers, pool=pool, chunksize=1)  # one at a time


def process_pool(workers: int):
    """The ``processes`` scheduler's pool of ``workers`` processes, all started at once; the caller shuts it down.

    Its processes are *spawned*, as by Dask's default context (``multiprocessing.context``: a process forked
    from a client whose numba thread pool has run would hang), whatever Dask's configuration says: the pool is
    made before Dask is imported.  Dask's worker initializer only re-seeds numpy's global random state when
    numpy was inherited by a fork, so it is not needed.  Each process starts on a first no-op call
    (:func:`_started`), so that its start (0.25 s) and its import of silcount and numba (0.5 s) begin now,
    not at the first unit's submission.  They start with SIGINT blocked (:func:`_ctrl_c_held`): a Ctrl-C is
    the client's to handle, by :func:`stop_workers`.
    """
    from concurrent.futures import ProcessPoolExecutor

    from silcount.study.spawn import spawn_context

    pool = ProcessPoolExecutor(workers, mp_context=spawn_context())  # workers do not re-run the caller's __main__
    try:
        with _ctrl_c_held():
            for _ in range(workers):  # a submission without an idle process starts one, in this thread
                pool.submit(_started)
    except KeyboardInterrupt:  # held while they started, delivered on release
        stop_workers(pool)
        raise
    return pool


@contextmanager
def _ctrl_c_held() -> Iterator[None]:
    """Hold Ctrl-C while processes start: they never hear it, and a Ctrl-C that comes meanwhile is raised after.

    SIGINT is blocked in this thread, and a process inherits the signal mask of the thread that forks it
    (through ``exec`` too), so the workers start with SIGINT blocked.  The client's other threads (an
    import, Dask's, tqdm's) do not block it, so the kernel hands a Ctrl-C to one of them; Python's
    handler then runs in this thread, which would interrupt a worker's start half-way (the worker dies
    on ``EOFError`` reading what it was never sent): meanwhile the handler only notes the signal.
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield  # only the main thread may set handlers; not POSIX
        return
    heard: list[int] = []
    handler = signal.signal(signal.SIGINT, lambda signum, frame: heard.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        signal.signal(signal.SIGINT, handler if handler is not None else signal.default_int_handler)
    if heard:
        raise KeyboardInterrupt


@contextmanager
def _ctrl_c_remembered() -> Iterator[Callable[[], None]]:
    """Ctrl-C raises ``KeyboardInterrupt`` as ever, and is remembered: the check it yields raises it again.

    Python raises the interrupt in whatever bytecode the main thread runs; when that is a callback called
    from C (an import lock's weakref callback while Dask is imported), it prints "Exception ignored" and
    drops it, and the sweep ran on as if Ctrl-C had never come.  Here such a drop prints nothing (the
    unraisable hook passes over a ``KeyboardInterrupt``, every other report goes to the hook as before), and
    the sweep's checks (after Dask's import, after each unit) raise it.
    """
    if threading.current_thread() is not threading.main_thread():
        yield lambda: None  # only the main thread may set handlers
        return
    heard: list[int] = []

    def on_sigint(signum, frame):
        heard.append(signum)
        raise KeyboardInterrupt

    def check() -> None:
        if heard:
            raise KeyboardInterrupt

    hook = sys.unraisablehook

    def unraisable(report) -> None:
        if not isinstance(report.exc_value, KeyboardInterrupt):
            hook(report)

    handler = signal.signal(signal.SIGINT, on_sigint)
    sys.unraisablehook = unraisable
    try:
        yield check
    finally:
        sys.unraisablehook = hook
        signal.signal(signal.SIGINT, handler if handler is not None else signal.default_int_handler)


def stop_workers(pool) -> None:
    """Terminate the processes of ``pool`` (a ``ProcessPoolExecutor``) now, mid-unit if need be.

    ``ProcessPoolExecutor`` has no public way to do it before Python 3.14 (``terminate_workers``); its
    ``_processes`` maps each worker's pid to its ``multiprocessing.Process``.
    """
    terminate = getattr(pool, "terminate_workers", None)
    if terminate is not None:
        terminate()
        return
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        process.terminate()


def _settle(pool, timeout: float = 5.0) -> None:
    """Wait for the management thread of ``pool``, whose workers were stopped, to see them gone and close
    its wake-up pipe.

    Before Python 3.12 the interpreter's exit hook (``concurrent.futures.process._python_exit``) writes to
    that pipe without the lock the thread closes it under; when the two meet, the exit prints an ignored
    ``OSError: [Errno 9] Bad file descriptor`` traceback after "silcount: interrupted".  Joined first, the
    thread has closed the pipe and the hook skips it.  ``_executor_manager_thread`` is private: a pool
    without it is left as it is.
    """
    thread = getattr(pool, "_executor_manager_thread", None)
    if thread is not None:
        thread.join(timeout)


def _started() -> None:
    """Nothing: the call that starts a worker process (its unpickling imports this module, silcount and numba)."""


def _distributed(items: list[Item], tasks: list[Task], settings: Settings, address: str, done: Callable) -> None:
    """``tasks`` on a cluster, largest first; a task whose input died with a worker is sent again.

    The client scatters each file's bytes to one worker.  When that worker dies, the bytes go with it and
    the unit is cancelled ("already forgotten"): the client still holds them, so it scatters them again and
    resubmits, at most :data:`RESUBMITS` times.  A unit that itself killed its workers (Dask's
    ``KilledWorker``) or failed to resubmit becomes that mesh's error row.
    """
    from distributed import Client, as_completed

    try:
        client = Client(address, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise BadArgument(f"--scheduler {address}: cannot reach the Dask scheduler: {exc}") from None
    with client:
        futures: dict = {}

        def submit(rank: int, attempt: int):
            t = tasks[rank]
            it = items[t.index]
            data = client.scatter(it.data, hash=False)
            key = f"silcount-corpus-{it.sha256[:16]}-{it.level}-{t.index}-{rank}-{attempt}"
            fut = client.submit(
                audit_on_threads, 1, it.label, data, it.level, settings, t.part, key=key, pure=False,
                priority=len(tasks) - rank,
            )  # fmt: skip
            futures[fut] = (rank, attempt)
            return fut

        running = as_completed([submit(rank, 0) for rank in range(len(tasks))])
        for fut in running:
            rank, attempt = futures.pop(fut)
            i = tasks[rank].index
            try:  # a unit whose result died with its worker is run again by the scheduler: result() waits
                result = fut.result()
            except CancelledError as lost:  # its scattered bytes died with a worker
                if attempt < RESUBMITS:
                    running.add(submit(rank, attempt + 1))
                    continue
                result = _failed(items[i], f"{type(lost).__name__}: {lost}")
            except Exception as lost:  # the task never raises: the cluster lost it for good (KilledWorker)
                result = _failed(items[i], f"{type(lost).__name__}: {lost}")
            done(tasks[rank], result)


def _failed(item: Item, error: str) -> dict:
    """The result of a unit that did not run."""
    error = " ".join(error.split())
    return {"mesh": {}, "rows": row_columns([]), "error": error, "sha256": item.sha256, "level": item.level}
