"""A progress bar on stderr for work that takes more than a second.

Never on stdout and never inside JSON: it writes to ``sys.stderr`` only, and
only when stderr is a terminal and the caller did not ask for quiet.  It
stays invisible for the first :data:`DELAY_S` seconds, so quick commands
print nothing extra, and erases itself when done.
"""
from __future__ import annotations

import sys
import time
from typing import TextIO

DELAY_S = 1.0
WIDTH = 30


class Progress:
    """``with Progress(total, "auditing") as bar: ... bar.advance()``."""

    def __init__(self, total: int, label: str, enabled: bool | None = None, stream: TextIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = (getattr(self.stream, "isatty", lambda: False)()) if enabled is None else enabled
        self.total = max(int(total), 1)
        self.label = label
        self.done = 0
        self._start = time.monotonic()
        self._shown = False

    def advance(self, n: int = 1, what: str = "") -> None:
        self.done += n
        if not self.enabled or time.monotonic() - self._start < DELAY_S:
            return
        frac = min(self.done / self.total, 1.0)
        bar = "#" * int(frac * WIDTH)
        self.stream.write(f"\r{self.label} [{bar:<{WIDTH}}] {self.done}/{self.total} {what[:30]:<30}")
        self.stream.flush()
        self._shown = True

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        if self._shown:
            self.stream.write("\r" + " " * (len(self.label) + WIDTH + 45) + "\r")
            self.stream.flush()
