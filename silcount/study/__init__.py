"""A study of real meshes: every detector under many lights on every file of a collection, on Dask.

The papers' claims are about "complex scenes" and "more than two million
faces" (HSD 2011 Sec. VII; EESD 2012 Sec. 6); McGuire ("Observations on
silhouette sizes", JGT 2004) measured the silhouette of real models growing
as about ``0.7 F^0.8``.  :func:`corpus` sweeps a collection and fits the same
laws to silcount's measurements.

>>> result = corpus(["meshes/"], lights=64, subdivide=(0, 1))   # doctest: +SKIP
>>> result.rows        # pandas.DataFrame, one row per mesh x light x detector
>>> result.meshes      # one row per mesh and level
>>> result.fits["silhouette_edges"]["alpha"], result.fits["silhouette_edges"]["alpha_ci"]

Modules: :mod:`.work` (one file at one level, on a worker), :mod:`.subdivide`,
:mod:`.schedule` (Dask), :mod:`.units` (a unit's time and memory), :mod:`.parts` (a unit split
and joined), :mod:`.cache`, :mod:`.tables`, :mod:`.fits` (with :mod:`.classes`, the complexity class of
each fitted series),
:mod:`.figures`, :mod:`.output` (``--out DIR``), :mod:`.literature` and
:mod:`.literature_page` (the papers' detectors beside ``gaussmap`` and ``cones``).
"""

from __future__ import annotations

import hashlib
import importlib
import os
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.detectors import get
from silcount.detectors import names as registered
from silcount.errors import BadArgument, UnreadableInput
from silcount.mesh.io import FORMATS, parse_size
from silcount.study.cache import Cache, default_cache_dir
from silcount.study.schedule import Item, check_scheduler, run_items
from silcount.study.tables import document, fits, meshes_frame, rows_frame
from silcount.study.units import faces_of
from silcount.study.work import LIGHT_KINDS, Settings

if TYPE_CHECKING:
    import pandas as pd


@dataclass
class CorpusResult:
    """What a sweep gives: the per-row table, the per-mesh table, the fits and the JSON document."""

    rows: pd.DataFrame
    meshes: pd.DataFrame
    fits: dict[str, dict]
    document: dict
    settings: Settings

    @property
    def failed(self) -> int:
        """How many (mesh, level) units could not be audited."""
        return int((self.meshes["error"] != "").sum())


def find_files(paths) -> list[tuple[str, Path]]:
    """(label, path) of every mesh file: a file as given (labelled by its name), a folder searched
    recursively for the loaders' extensions (labelled by its path inside the folder); sorted by label."""
    found: dict[str, Path] = {}
    for given in paths:
        p = Path(given)
        if p.is_dir():
            pairs = [(f.relative_to(p).as_posix(), f) for f in sorted(p.rglob("*")) if f.is_file()]
            pairs = [(label, f) for label, f in pairs if f.suffix.lower() in FORMATS]
        elif p.exists():
            pairs = [(p.name, p)]
        else:
            raise UnreadableInput(f"{p}: no such file or folder")
        for label, f in pairs:
            other = found.get(label)
            if other is not None and other.resolve() != f.resolve():
                raise BadArgument(f"two files are both named {label!r} in the sweep: {other} and {f}")
            found[label] = f
    if not found:
        raise UnreadableInput(f"no mesh files ({', '.join(FORMATS)}) under {', '.join(map(str, paths))}")
    return sorted(found.items())


def _settings(lights, light_kind, seed, detectors, variant, timing, time_lights) -> Settings:
    if lights < 1:
        raise BadArgument(f"--lights {lights}: need at least one light")
    if light_kind not in LIGHT_KINDS:
        raise BadArgument(f"--light-kind {light_kind!r}: choose {', '.join(LIGHT_KINDS)}")
    names = tuple(registered() if detectors is None else detectors)
    if not names:
        raise BadArgument("the detector list is empty")
    for d in names:
        get(d)
    variants = {"intended": ("intended",), "literal": ("literal",), "both": ("intended", "literal")}.get(variant)
    if variants is None:
        raise BadArgument(f"--variant {variant!r}: choose intended, literal or both")
    return Settings(
        lights=int(lights),
        light_kind=light_kind,
        seed=int(seed),
        detectors=names,
        variants=variants,
        timing=bool(timing),
        time_lights=int(time_lights),
    )


def corpus(
    paths,
    lights: int = 64,
    light_kind: str = "directional",
    seed: int = 0,
    detectors=None,
    variant: str = "intended",
    subdivide=(0,),
    scheduler: str = "processes",
    workers: int | None = None,
    cache: str | os.PathLike | bool | None = True,
    timing: bool = True,
    time_lights: int = 1,
    quiet: bool = False,
    memory_budget: int | str | None = None,
    timeline: list[float] | None = None,
) -> CorpusResult:
    """Sweep every mesh file under ``paths`` (see the module docstring and ``silcount corpus --help``).

    ``cache``: ``True`` for :func:`~silcount.study.cache.default_cache_dir`, a
    folder, or ``False``/``None`` for none.  ``scheduler``: ``threads``,
    ``processes`` or ``tcp://HOST:PORT``; ``workers`` applies to the first two.
    A mesh that cannot be audited is a row of ``meshes`` with its ``error``;
    it never stops the sweep (``CorpusResult.failed`` counts them).
    ``memory_budget``: a worker's peak memory, bytes or a size such as ``"4GB"`` (default: a share of the
    machine's memory over the local workers, :func:`silcount.study.units.default_budget`); a unit over it
    runs in parts, or is refused in its error row (:mod:`silcount.study.parts`).  ``timeline``, if given,
    gets the ``time.perf_counter()`` of each finished task (a unit, or a part of one).
    """
    settings = _settings(lights, light_kind, seed, detectors, variant, timing, time_lights)
    levels = sorted({int(v) for v in subdivide})
    if not levels or levels[0] < 0:
        raise BadArgument(f"--subdivide {subdivide}: levels are integers >= 0")
    check_scheduler(scheduler)
    budget = parse_size(memory_budget, "--memory-budget") if isinstance(memory_budget, str) else memory_budget
    if budget is not None and budget <= 0:
        raise BadArgument(f"--memory-budget {memory_budget}: need a positive size")
    folder = default_cache_dir() if cache is True else (Path(cache) if cache else None)
    items = []
    for label, path in find_files(paths):
        try:
            data, error = path.read_bytes(), None
        except OSError as exc:  # this mesh's error row; the sweep goes on
            data, error = b"", f"{path}: cannot read: {exc.strerror or exc}"
        sha = hashlib.sha256(data).hexdigest()
        faces = None if error else faces_of(path)
        items += [Item(label, data, sha, level, error, faces) for level in levels]
    # the tables' first use of pandas imports it (0.2-0.3 s): done on a thread while the workers start and run,
    # not after the last unit; the tables below import it again (a dictionary look-up, or a wait for this import)
    threading.Thread(target=importlib.import_module, args=("pandas",), name="import-pandas", daemon=True).start()
    results = run_items(items, settings, scheduler, workers, Cache(folder), quiet, budget, timeline)
    labels = [it.label for it in items]
    rows = rows_frame(labels, results)
    meshes = meshes_frame(labels, results, rows, settings)
    fit = fits(meshes, settings, rows)
    return CorpusResult(rows, meshes, fit, document(meshes, rows, fit, settings, levels), settings)


__all__ = ["corpus", "CorpusResult", "Settings", "find_files"]
