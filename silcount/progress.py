"""Progress bars for long work, by tqdm, with the project's rules.

On stderr only (never stdout, never inside JSON); only when stderr is a
terminal (tqdm's ``disable=None``) and the caller did not ask for quiet;
invisible for the first :data:`DELAY_S` seconds, so quick commands print
nothing extra; erased when done (``leave=False``).
"""

from __future__ import annotations

import sys
from typing import TextIO

from tqdm import tqdm

DELAY_S = 1.0


def progress(total: int, label: str, enabled: bool | None = None, stream: TextIO | None = None) -> tqdm:
    """A tqdm bar of ``total`` steps; ``enabled=None`` shows it only on a terminal."""
    return tqdm(
        total=max(int(total), 1),
        desc=label,
        file=stream if stream is not None else sys.stderr,
        disable=None if enabled is None else not enabled,
        delay=DELAY_S,
        leave=False,
        dynamic_ncols=True,
        unit="run",
    )
