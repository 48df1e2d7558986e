"""ASCII PLY records read line by line, for writers that put more values on a record's line than its header declares.

The PLY specification makes an ASCII body one stream of numbers, so that a
record may span lines; files in the wild put every record on its own line,
and some writers put more on it than the header declares: VCGLIB (MeshLab)
declares a face's colour as four ``uchar`` properties and writes it as a list,
one value more per face line.  Read as a stream, every record after the first
is then misaligned ("list length 0.599829 is not a count").

:func:`by_lines` applies when the body has exactly one non-empty line per
record and every line holds at least its record's declared values (list
counts read from the line itself): the declared values are kept, the extra
ones dropped, and one warning says how many.  Anything else (a record split
over lines, a body that really is short) is left to the stream reader and its
strict diagnosis.  Vectorised: one pass over the bytes, one per property.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from silcount.mesh.formats.common import plural


class Element(Protocol):
    name: str
    n: int
    props: list


def _owner(records: Sequence[Element], row: int) -> tuple[int, Element]:
    """The element record ``row`` (counted over all elements with properties) belongs to, and its first row."""
    start = 0
    for e in records:
        if row < start + e.n:
            break
        start += e.n
    return start, e


@dataclass
class Lines:
    """What reading by lines found: the numbers to read and the warning, or why the body is short."""

    vals: np.ndarray | None = None  # the body's numbers without the extra values; None: read the stream as it is
    note: str = ""  # the one warning about the extra values
    short: str = ""  # a line-per-record body with extra values that ends before its last record: the diagnosis


def by_lines(body: bytes, vals: np.ndarray, elements: Sequence[Element], header_lines: int) -> Lines:
    """Read ``vals`` (the body's numbers, in order) one record per line when that is the body's shape
    (module docstring); ``Lines()`` when it is not, or when no line carries extra values."""
    b = np.frombuffer(body, dtype=np.uint8)
    ws = (b == 32) | ((b >= 9) & (b <= 13))
    starts = np.flatnonzero(~ws & np.concatenate(([True], ws[:-1])))
    if not vals.size or starts.size != vals.size:  # the tokens are not the numbers parsed (cannot happen)
        return Lines()
    breaks = np.flatnonzero((b == 10) | ((b == 13) & (np.concatenate((b[1:], [0])) != 10)))
    line = np.searchsorted(breaks, starts)  # the body line of each number
    first = np.flatnonzero(np.concatenate(([True], line[1:] != line[:-1])))  # each non-empty line's first number
    per_line = np.diff(np.concatenate((first, [vals.size])))
    records = [e for e in elements if e.props]
    n_lines, n_records = first.size, sum(e.n for e in records)
    if n_lines > n_records:
        return Lines()
    declared = np.zeros(n_lines, dtype=np.int64)
    row = 0
    for e in records:
        if row >= n_lines:
            break
        k = min(e.n, n_lines - row)
        at, have = first[row : row + k], per_line[row : row + k]
        off = np.zeros(k, dtype=np.int64)
        for p in e.props:
            if p.count is None:
                off += 1
                continue
            inside = off < have
            c = np.where(inside, vals[at + np.minimum(off, have - 1)], 0)
            if not np.all(np.isfinite(c) & (c >= 0) & (c == np.floor(c))):
                return Lines()  # not a count where a line-per-record body has one: the stream reader says why
            off += 1 + np.minimum(c, have).astype(np.int64)
        declared[row : row + k] = off
        row += k
    extra = per_line - declared
    fits = extra >= 0
    if not fits[:-1].all() or not (extra > 0).any():
        return Lines()  # a record spans lines, or nothing is extra: the stream reader reads it as it always did
    if n_lines < n_records or not fits[-1]:
        done = n_lines if fits[-1] else n_lines - 1
        start, e = _owner(records, done)
        return Lines(
            short=f"truncated ASCII PLY: element '{e.name}' ran short: the body ends after {done - start} of the "
            f"{e.n} records the header promises"
        )
    within = np.arange(vals.size, dtype=np.int64) - np.repeat(first, per_line)
    keep = within < np.repeat(declared, per_line)
    hit = int(np.flatnonzero(extra)[0])
    start, e = _owner(records, hit)
    n_rec, n_val = int(np.count_nonzero(extra)), int(extra.sum())
    note = (
        f"ASCII PLY: {plural(n_rec, 'record')} {'carries' if n_rec == 1 else 'carry'} {plural(n_val, 'value')} "
        f"past the properties the header declares (first: element '{e.name}' record {hit - start}, line "
        f"{header_lines + int(line[first[hit]]) + 1}); every record is on its own line, so the declared "
        "properties were read and the extra values ignored"
    )
    return Lines(vals[keep], note)
