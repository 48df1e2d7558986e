"""Locating a claim's quote in its paper: whitespace-insensitive, ``...`` joining separate spans.

Every claim carries ``paper`` (a file name in the papers directory),
``lines`` (``"a-b"``, 1-based, inclusive) and ``quote``.  :func:`locate` finds
each span of the quote, in order, and returns the line range it covers;
:func:`check` says whether the stored range is that range.  The papers are
read-only inputs outside the repository, named by ``$SILCOUNT_PAPERS_DIR``
(the Makefile sets ``../shared/papers``); only the tests read them.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

SPAN_JOIN = "..."


def papers_dir() -> Path | None:
    """Where the paper texts are: ``$SILCOUNT_PAPERS_DIR`` (the Makefile sets ``../shared/papers``), or None."""
    env = os.environ.get("SILCOUNT_PAPERS_DIR")
    return Path(env) if env else None


def _squeeze(text: str) -> tuple[str, list[int]]:
    """``text`` without whitespace, and for each kept character its 1-based line number."""
    chars, lines, line = [], [], 1
    for ch in text:
        if ch == "\n":
            line += 1
        if not ch.isspace():
            chars.append(ch)
            lines.append(line)
    return "".join(chars), lines


def spans(quote: str) -> list[str]:
    """The quote's separate spans, whitespace removed."""
    return [re.sub(r"\s+", "", part) for part in quote.split(SPAN_JOIN) if part.strip()]


def locate(text: str, quote: str, start_line: int = 1) -> tuple[int, int] | None:
    """The (first, last) line the quote's spans cover, each span after the previous one, the first at or
    after ``start_line``; None when a span is missing."""
    flat, line_of = _squeeze(text)
    pos = next((i for i, ln in enumerate(line_of) if ln >= start_line), len(flat))
    first = last = None
    for part in spans(quote):
        at = flat.find(part, pos)
        if at < 0:
            return None
        first = line_of[at] if first is None else first
        last = line_of[at + len(part) - 1]
        pos = at + len(part)
    return None if first is None or last is None else (first, last)


def parse_lines(lines: str) -> tuple[int, int]:
    a, _, b = lines.partition("-")
    return int(a), int(b or a)


def check(text: str, quote: str, lines: str) -> bool:
    """Does the quote occur in ``text`` exactly over the stored line range?"""
    first, _ = parse_lines(lines)
    return locate(text, quote, first) == parse_lines(lines)
