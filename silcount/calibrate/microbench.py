"""Micro-benchmark kernels for :mod:`silcount.calibrate.measure`: one loop per operation kind.

Latency kernels are one dependent chain (each operation needs the previous
result); throughput kernels run eight independent chains (``STREAMS``) so the
core may overlap them.  Every kernel returns its final values, so the compiler
cannot drop the work; the loop runs ``n`` times.  Reads chase a random cyclic
permutation of indices (``i = nxt[i]``), so every load waits for the previous
one (latency) or eight chases run side by side (throughput).  A write is a
store followed by a reload of the same slot through an index the compiler
cannot see through (``slot[0]`` at run time), the store-to-load round trip.
"""

from __future__ import annotations

import math

from numba import njit

STREAMS = 8


@njit(cache=True)
def lat_add(n, x, c):  # pragma: no cover - compiled
    for _ in range(n):
        x = x + c
    return x


@njit(cache=True)
def lat_mul(n, x, c):  # pragma: no cover - compiled
    for _ in range(n):
        x = x * c
    return x


@njit(cache=True)
def lat_div(n, x, c):  # pragma: no cover - compiled
    for _ in range(n):
        x = c / x
    return x


@njit(cache=True)
def lat_sqrt_add(n, x, c):  # pragma: no cover - compiled
    for _ in range(n):
        x = math.sqrt(x) + c
    return x


@njit(cache=True)
def lat_cmp_add(n, x, c):  # pragma: no cover - compiled
    """x + (c if x < limit else 2c): the compare's result feeds the next add."""
    limit = 1e300
    for _ in range(n):
        x = x + (c if x < limit else c + c)
    return x


@njit(cache=True)
def lat_read(n, nxt):  # pragma: no cover - compiled
    i = 0
    for _ in range(n):
        i = nxt[i]
    return i


@njit(cache=True)
def lat_write_add(n, x, c, buf, slot):  # pragma: no cover - compiled
    """Store x + c, reload it through a run-time index: add + store + forwarded load per step."""
    j = slot[0]
    for _ in range(n):
        buf[j] = x + c
        x = buf[slot[1]]
    return x


@njit(cache=True)
def tp_add(n, x, c):  # pragma: no cover - compiled
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = x
    for _ in range(n):
        a0 += c
        a1 += c
        a2 += c
        a3 += c
        a4 += c
        a5 += c
        a6 += c
        a7 += c
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit(cache=True)
def tp_mul(n, x, c):  # pragma: no cover - compiled
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = x
    for _ in range(n):
        a0 *= c
        a1 *= c
        a2 *= c
        a3 *= c
        a4 *= c
        a5 *= c
        a6 *= c
        a7 *= c
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit(cache=True)
def tp_div(n, x, c):  # pragma: no cover - compiled
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = x
    for _ in range(n):
        a0 = c / a0
        a1 = c / a1
        a2 = c / a2
        a3 = c / a3
        a4 = c / a4
        a5 = c / a5
        a6 = c / a6
        a7 = c / a7
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit(cache=True)
def tp_sqrt_add(n, x, c):  # pragma: no cover - compiled
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = x
    for _ in range(n):
        a0 = math.sqrt(a0) + c
        a1 = math.sqrt(a1) + c
        a2 = math.sqrt(a2) + c
        a3 = math.sqrt(a3) + c
        a4 = math.sqrt(a4) + c
        a5 = math.sqrt(a5) + c
        a6 = math.sqrt(a6) + c
        a7 = math.sqrt(a7) + c
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit(cache=True)
def tp_cmp_add(n, x, c):  # pragma: no cover - compiled
    limit = 1e300
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = x
    for _ in range(n):
        a0 += c if a0 < limit else c + c
        a1 += c if a1 < limit else c + c
        a2 += c if a2 < limit else c + c
        a3 += c if a3 < limit else c + c
        a4 += c if a4 < limit else c + c
        a5 += c if a5 < limit else c + c
        a6 += c if a6 < limit else c + c
        a7 += c if a7 < limit else c + c
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit(cache=True)
def tp_read(n, nxt, starts):  # pragma: no cover - compiled
    i0, i1, i2, i3, i4, i5, i6, i7 = (
        starts[0],
        starts[1],
        starts[2],
        starts[3],
        starts[4],
        starts[5],
        starts[6],
        starts[7],
    )
    for _ in range(n):
        i0 = nxt[i0]
        i1 = nxt[i1]
        i2 = nxt[i2]
        i3 = nxt[i3]
        i4 = nxt[i4]
        i5 = nxt[i5]
        i6 = nxt[i6]
        i7 = nxt[i7]
    return i0 + i1 + i2 + i3 + i4 + i5 + i6 + i7


@njit(cache=True)
def tp_write(n, x, buf):  # pragma: no cover - compiled
    """Eight independent stores per step into an L1-sized buffer (x changes so no store is dead)."""
    m = buf.size - 8
    j = 0
    for _ in range(n):
        buf[j] = x
        buf[j + 1] = x
        buf[j + 2] = x
        buf[j + 3] = x
        buf[j + 4] = x
        buf[j + 5] = x
        buf[j + 6] = x
        buf[j + 7] = x
        x += 1.0
        j += 8
        if j > m:
            j = 0
    return x
