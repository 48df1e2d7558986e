"""The corpus cache: one JSON file per (file content, subdivision level, settings, silcount version).

An interrupted sweep resumes: every finished unit of work is written here by
the client as soon as it arrives (atomically, so a kill never leaves half an
entry), and a rerun with the same settings skips it.  The key is the SHA-256
of ``{"sha256", "level", "settings", "silcount_version", "code"}`` as
canonical JSON, so renaming or moving a file keeps its entry and editing it
does not.  ``code`` (:func:`code_digest`) digests the sources a unit's result
depends on and ``silcount/models/``: a development tree's version string does not change when a
detector does, and a stale count must never be read back.  Failed
meshes are not cached (their error may be transient, e.g. memory).

The timing settings (:data:`TIMING_FIELDS`) are not in the key: the counts do
not depend on them.  An entry remembers the timing settings it was made with;
a sweep that wants times accepts only an entry timed the same way, a sweep
without times accepts any entry and gets its times blanked (so ``silcount
report``, which writes no wall times, reuses a timed sweep's entries).

The default folder is ``$XDG_CACHE_HOME/silcount/corpus`` (``~/.cache/...``
when unset); ``--cache DIR`` overrides it.
"""

from __future__ import annotations

import hashlib
import json
import os
from functools import cache
from pathlib import Path

from silcount.atomic import make_folder, write_text
from silcount.counting.models import models_dir
from silcount.study.work import Settings
from silcount.version import __version__


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/silcount/corpus``, else ``~/.cache/silcount/corpus``."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "silcount" / "corpus"


TIMING_FIELDS = ("timing", "time_lights", "time_max_faces", "time_max_pairs")


def timing_of(settings: Settings) -> dict:
    d = settings.as_dict()
    return {k: d[k] for k in TIMING_FIELDS}


UNIT_SOURCES = (
    "*.py",
    "counting/**/*.py",
    "mesh/**/*.py",
    "detectors/**/*.py",
    "study/work.py",
    "study/subdivide.py",
)
"""The sources a unit's result depends on (under ``silcount/``): the layers below ``study`` and the unit's own."""


@cache
def code_digest() -> str:
    """SHA-256 over :data:`UNIT_SOURCES` and ``silcount/models/**/*.toml`` (relative path and bytes of each)."""
    h = hashlib.sha256()
    package = Path(__file__).resolve().parents[1]
    files = sorted({(package, p) for pattern in UNIT_SOURCES for p in package.glob(pattern)})
    files += sorted((models_dir(), p) for p in models_dir().rglob("*.toml"))
    for root, path in files:
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def cache_key(sha256: str, level: int, settings: Settings) -> str:
    """The entry's name: a digest of what determines its counts (timing settings aside)."""
    counts = {k: v for k, v in settings.as_dict().items() if k not in TIMING_FIELDS}
    what = {
        "sha256": sha256,
        "level": int(level),
        "settings": counts,
        "silcount_version": __version__,
        "code": code_digest(),
    }
    return hashlib.sha256(json.dumps(what, sort_keys=True).encode()).hexdigest()


class Cache:
    """Entries under ``folder`` (created on first write); ``folder=None`` caches nothing."""

    def __init__(self, folder: Path | None) -> None:
        self.folder = folder

    def path(self, key: str) -> Path | None:
        return None if self.folder is None else self.folder / f"{key}.json"

    def get(self, key: str, settings: Settings) -> dict | None:
        """The cached result usable for ``settings``, or ``None`` (absent, unreadable, timed otherwise)."""
        path = self.path(key)
        if path is None or not path.is_file():
            return None
        try:
            entry = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError):
            return None
        timing = entry.pop("timing", None)
        if settings.timing:
            return entry if timing == timing_of(settings) else None
        mesh = entry.get("mesh", {})
        mesh["time_per_light_s"] = {d: None for d in mesh.get("time_per_light_s", {})}
        by_kind = mesh.get("time_by_light_kind", {})
        mesh["time_by_light_kind"] = {kind: {d: None for d in times} for kind, times in by_kind.items()}
        mesh["time_errors"] = []
        return entry

    def put(self, key: str, result: dict, settings: Settings) -> None:
        """Store a successful result with its timing settings (an ``error`` result is not stored)."""
        path = self.path(key)
        if path is None or result.get("error"):
            return
        make_folder(path.parent)
        write_text(path, json.dumps({**result, "timing": timing_of(settings)}, sort_keys=True))
