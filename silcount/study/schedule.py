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
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

from silcount.errors import BadArgument
from silcount.progress import progress
from silcount.study.cache import Cache, cache_key
from silcount.study.work import Settings, audit_task

LOCAL = ("threads", "processes")
CONNECT_TIMEOUT = "20s"


@dataclass(frozen=True)
class Item:
    """One unit of work: a file's name in the sweep, its bytes and digest, a subdivision level."""

    label: str
    data: bytes
    sha256: str
    level: int
    read_error: str | None = None  # the client could not read the file: an error row, nothing to run


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
) -> list[dict]:
    """Every item's result (cached ones read back), in the order of ``items``."""
    check_scheduler(scheduler)
    cache = cache or Cache(None)
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

        if todo and scheduler in LOCAL:
            _local(items, todo, settings, scheduler, workers or os.cpu_count() or 1, finish)
        elif todo:
            _distributed(items, todo, settings, scheduler, finish)
    return [r for r in results if r is not None]


def _local(
    items: list[Item], todo: list[int], settings: Settings, scheduler: str, workers: int, finish: Callable
) -> None:
    import dask
    from dask.callbacks import Callback

    names = {f"silcount-corpus-{i}": i for i in todo}

    class Collect(Callback):
        def _posttask(self, key, result, dsk, state, id):  # noqa: A002 - dask's signature
            if key in names:
                finish(names[key], result)

    tasks = [
        dask.delayed(audit_task, pure=False)(
            items[i].label, items[i].data, items[i].level, settings, dask_key_name=f"silcount-corpus-{i}"
        )
        for i in todo
    ]
    with Collect():
        dask.compute(*tasks, scheduler=scheduler, num_workers=workers)


def _distributed(items: list[Item], todo: list[int], settings: Settings, address: str, finish: Callable) -> None:
    from distributed import Client, as_completed

    try:
        client = Client(address, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise BadArgument(f"--scheduler {address}: cannot reach the Dask scheduler: {exc}") from None
    with client:
        futures = {}
        for i in todo:
            it = items[i]
            data = client.scatter(it.data, hash=True)
            key = f"silcount-corpus-{it.sha256[:16]}-{it.level}-{i}"
            futures[client.submit(audit_task, it.label, data, it.level, settings, key=key, pure=False)] = i
        for fut in as_completed(list(futures)):
            i = futures[fut]
            if fut.status == "finished":
                finish(i, fut.result())
            else:  # the task itself never raises: this is the cluster losing it (KilledWorker, cancelled)
                lost = fut.exception()
                finish(i, _failed(items[i], f"{type(lost).__name__}: {lost}"))


def _failed(item: Item, error: str) -> dict:
    """The result of a unit that did not run."""
    return {"mesh": {}, "rows": [], "error": " ".join(error.split()), "sha256": item.sha256, "level": item.level}
