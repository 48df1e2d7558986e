"""Assertions on silcount's results, for the tests of silcount and of code built on it (as ``pandas.testing``).

:func:`assert_silhouettes_equal` says whether two :class:`~silcount.detectors.Silhouette` results are the
same answer at the same cost: what an engine, a batched run (:func:`silcount.detectors.detect_many`) or a
new detector's second implementation must reproduce.  It raises :class:`AssertionError` naming the first
field that differs.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from silcount.detectors.result import Silhouette

ARRAYS = ("edge_ids", "edges", "oriented")
"""The fields compared element by element (``numpy.array_equal``: same shape, same values)."""
FIELDS = ("detector", "variant", "paper_model", "paper_params", "steps", "true_tally", "tally", "ties")
"""The fields compared with ``==`` (besides ``engine`` and ``notes``, whose comparison can be narrowed)."""


def assert_silhouettes_equal(
    left: Silhouette, right: Silhouette, *, check_engine: bool = True, ignore_notes: Iterable[str] = ()
) -> None:
    """Assert that ``left`` and ``right`` are the same result: the same edges (ids, vertex pairs, orientation),
    the same steps and tallies under both cost models, the same ties, notes and identity (detector, variant,
    paper model and its parameters, and engine unless ``check_engine`` is false, as when a ``naive`` run is
    compared with a ``fast`` one); the notes named in ``ignore_notes`` (one engine's alone) are left out."""
    diffs = _first_difference(left, right, check_engine, set(ignore_notes))
    if diffs is not None:
        name, a, b = diffs
        raise AssertionError(f"Silhouettes differ in {name}: {a!r} != {b!r}")


def _first_difference(
    left: Silhouette, right: Silhouette, check_engine: bool, ignore: set[str]
) -> tuple[str, Any, Any] | None:
    for name in ARRAYS:
        a, b = getattr(left, name), getattr(right, name)
        if not np.array_equal(a, b):
            return name, a, b
    for name in FIELDS + (("engine",) if check_engine else ()):
        a, b = getattr(left, name), getattr(right, name)
        if a != b:
            return name, a, b
    a_notes = {k: v for k, v in left.notes.items() if k not in ignore}
    b_notes = {k: v for k, v in right.notes.items() if k not in ignore}
    if a_notes != b_notes:
        return "notes", a_notes, b_notes
    return None


__all__ = ["assert_silhouettes_equal"]
