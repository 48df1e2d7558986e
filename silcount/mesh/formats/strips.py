"""Triangle strips (the PLY ``tristrips`` element of scan repositories), decoded into triangles."""

from __future__ import annotations

import numpy as np


def decode_strips(strips: np.ndarray, counts: np.ndarray, restart: int = -1) -> np.ndarray:
    """(T, 3) triangles of triangle strips: each record one or more strips separated by ``restart``.

    Triangle ``j`` of a strip is ``(s[j], s[j+1], s[j+2])`` for even ``j`` and
    ``(s[j+1], s[j], s[j+2])`` for odd ``j`` (one winding throughout);
    triangles repeating a vertex join strips and are skipped.
    """
    ends = np.cumsum(counts)
    s = np.insert(strips.astype(np.int64), ends[:-1], restart) if counts.size > 1 else strips.astype(np.int64)
    if s.size < 3:
        return np.zeros((0, 3), dtype=np.int64)
    live = s != restart
    ok = live[:-2] & live[1:-1] & live[2:]
    idx = np.arange(s.size)
    start = np.maximum.accumulate(np.where(live, -1, idx)) + 1
    j = np.flatnonzero(ok)
    odd = (j - start[j]) % 2 == 1
    a, b, c = s[j], s[j + 1], s[j + 2]
    tri = np.stack([np.where(odd, b, a), np.where(odd, a, b), c], axis=1)
    keep = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
    return tri[keep]
