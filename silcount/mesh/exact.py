"""Exact signs of small polynomials in float64 coordinates: Shewchuk's expansion arithmetic, in numba.

J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
Robust Geometric Predicates" (1997): a real number is held exactly as an
*expansion*, a sum of non-overlapping doubles in increasing magnitude;
``two_diff`` and ``two_product`` give a difference or product of two doubles
as such a sum, ``scale_expansion_zeroelim`` multiplies an expansion by a
double, ``fast_expansion_sum_zeroelim`` adds two expansions.  Zero
components are dropped, so the work adapts to the data: when every
coordinate difference is exact (one component), the products stay short.
The sign of an expansion is the sign of its last (largest) component; an
empty expansion is zero.

When every coordinate difference is exact, ``orient3d`` sums its six triple
products (four doubles each, by ``two_product``) exactly with ``msum``
partials, and ``n_f . n_g`` is first decided by a float filter with a static
error bound (about 90 ulps of the sum of products' magnitudes, over ten times
the worst rounding), the full expansions only when the filter cannot decide.

Used by :mod:`silcount.mesh.coplanar` for the exact ``orient3d == 0`` and
``n_f . n_g > 0`` tests of the ``tight`` merge.  The arithmetic is exact as
long as no intermediate overflows or underflows: :func:`exact_range_ok`
checks that every nonzero coordinate magnitude lies in
``[2^-150, 2^150]`` (then every value in a degree-4 polynomial of coordinate
differences is an integer multiple of ``2^-808`` and below ``2^620``); the
caller falls back to Python integers otherwise.  Requires round-to-nearest
float64 without fused multiply-add contraction (numba's default).
"""

from __future__ import annotations

import numba as nb
import numpy as np

_SPLITTER = 134217729.0  # 2^27 + 1
_LO, _HI = 2.0**-150, 2.0**150


ERRBOUND_A = (7.0 + 56.0 * 2.0**-53) * 2.0**-53
"""Shewchuk's static error bound of orient3dfast, relative to the permanent (1997, ``o3derrboundA``)."""


def exact_range_ok(values: np.ndarray) -> bool:
    """Every nonzero ``|value|`` in ``[2^-150, 2^150]``: the range where these predicates are exact."""
    a = np.abs(values[values != 0.0])
    return bool(a.size == 0 or (a.min() >= _LO and a.max() <= _HI))


@nb.njit(cache=True, inline="always")
def _two_diff(a, b):  # pragma: no cover - compiled
    x = a - b
    bv = a - x
    av = x + bv
    br = bv - b
    ar = a - av
    return x, ar + br


@nb.njit(cache=True, inline="always")
def _two_sum(q, now):  # pragma: no cover - compiled
    """Shewchuk's Two-Sum: ``x = fl(q + now)`` and its exact rounding error."""
    x = q + now
    bv = x - q
    return x, (q - (x - bv)) + (now - bv)


@nb.njit(cache=True, inline="always")
def _split(a):  # pragma: no cover - compiled
    c = _SPLITTER * a
    abig = c - a
    ahi = c - abig
    return ahi, a - ahi


@nb.njit(cache=True, inline="always")
def _two_product(a, b):  # pragma: no cover - compiled
    x = a * b
    ahi, alo = _split(a)
    bhi, blo = _split(b)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


@nb.njit(cache=True)
def _scale(w, e, elen, b, h):  # pragma: no cover - compiled
    """Row ``h`` of ``w`` = row ``e`` (length ``elen``) times ``b`` (scale_expansion_zeroelim); its length."""
    if elen == 0 or b == 0.0:
        return 0
    bhi, blo = _split(b)
    q, hh = _two_product(w[e, 0], b)
    hidx = 0
    if hh != 0.0:
        w[h, hidx] = hh
        hidx += 1
    for i in range(1, elen):
        enow = w[e, i]
        p1 = enow * b
        ehi, elo = _split(enow)
        err1 = p1 - ehi * bhi
        err2 = err1 - elo * bhi
        err3 = err2 - ehi * blo
        p0 = elo * blo - err3
        s = q + p0
        bv = s - q
        hh = (q - (s - bv)) + (p0 - bv)
        if hh != 0.0:
            w[h, hidx] = hh
            hidx += 1
        q = p1 + s
        hh = s - (q - p1)
        if hh != 0.0:
            w[h, hidx] = hh
            hidx += 1
    if q != 0.0:
        w[h, hidx] = q
        hidx += 1
    return hidx


@nb.njit(cache=True)
def _sum(w, e, elen, f, flen, h):  # pragma: no cover - compiled
    """Row ``h`` = row ``e`` + row ``f`` (fast_expansion_sum_zeroelim); its length.  ``h`` may be ``e``
    only if ``flen == 0``."""
    if elen == 0:
        for i in range(flen):
            w[h, i] = w[f, i]
        return flen
    if flen == 0:
        for i in range(elen):
            w[h, i] = w[e, i]
        return elen
    ei, fi = 0, 0
    enow, fnow = w[e, 0], w[f, 0]
    if (fnow > enow) == (fnow > -enow):
        q = enow
        ei += 1
    else:
        q = fnow
        fi += 1
    hidx = 0
    if ei < elen and fi < flen:
        enow, fnow = w[e, ei], w[f, fi]
        if (fnow > enow) == (fnow > -enow):
            x = enow + q
            hh = q - (x - enow)
            ei += 1
        else:
            x = fnow + q
            hh = q - (x - fnow)
            fi += 1
        q = x
        if hh != 0.0:
            w[h, hidx] = hh
            hidx += 1
    while ei < elen or fi < flen:  # the rest in order of magnitude: e's while f is spent or e's is smaller
        if fi >= flen or (ei < elen and (w[f, fi] > w[e, ei]) == (w[f, fi] > -w[e, ei])):
            now = w[e, ei]
            ei += 1
        else:
            now = w[f, fi]
            fi += 1
        q, hh = _two_sum(q, now)
        if hh != 0.0:
            w[h, hidx] = hh
            hidx += 1
    if q != 0.0:
        w[h, hidx] = q
        hidx += 1
    return hidx


@nb.njit(cache=True)
def _mul(w, e, elen, f, flen, out, tmp, acc):  # pragma: no cover - compiled
    """Row ``out`` = row ``e`` times row ``f`` (the sum of ``e * f[i]``); rows ``tmp``, ``acc`` scratch."""
    if flen == 1:
        return _scale(w, e, elen, w[f, 0], out)
    n = 0
    for i in range(flen):
        m = _scale(w, e, elen, w[f, i], tmp)
        n = _sum(w, out, n, tmp, m, acc)
        for k in range(n):
            w[out, k] = w[acc, k]
    return n


@nb.njit(cache=True, inline="always")
def _diff_expansion(w, row, a, b):  # pragma: no cover - compiled
    """Row ``row`` = ``a - b`` of two doubles as an expansion (0, 1 or 2 components); its length."""
    x, y = _two_diff(a, b)
    n = 0
    if y != 0.0:
        w[row, n] = y
        n += 1
    if x != 0.0:
        w[row, n] = x
        n += 1
    return n


@nb.njit(cache=True)
def _cross_component(w, u1, n1, v2, n2, u2, n3, v1, n4, out, s):  # pragma: no cover - compiled
    """Row ``out`` = ``u1 * v2 - u2 * v1`` (rows and lengths); rows ``s .. s+3`` scratch."""
    la = _mul(w, u1, n1, v2, n2, s, s + 1, s + 2)
    lb = _mul(w, u2, n3, v1, n4, s + 3, s + 1, s + 2)
    for i in range(lb):
        w[s + 3, i] = -w[s + 3, i]
    return _sum(w, s, la, s + 3, lb, out)


@nb.njit(cache=True, inline="always")
def _sign(w, row, n):  # pragma: no cover - compiled
    if n == 0:
        return 0
    return 1 if w[row, n - 1] > 0.0 else -1


@nb.njit(cache=True, inline="always")
def _grow(parts, n, x):  # pragma: no cover - compiled
    """Add double ``x`` to the expansion ``parts[:n]`` exactly (msum / grow_expansion_zeroelim); new length."""
    k = 0
    for i in range(n):
        y = parts[i]
        if abs(x) < abs(y):
            x, y = y, x
        hi = x + y
        lo = y - (hi - x)
        if lo != 0.0:
            parts[k] = lo
            k += 1
        x = hi
    if x != 0.0:
        parts[k] = x
        k += 1
    return k


@nb.njit(cache=True, inline="always")
def _grow_product3(parts, n, a, b, c):  # pragma: no cover - compiled
    """Add ``a * b * c`` exactly: ``a b = x + y`` (two_product), then ``x c`` and ``y c`` (two_product each)."""
    x, y = _two_product(a, b)
    x1, x0 = _two_product(x, c)
    y1, y0 = _two_product(y, c)
    n = _grow(parts, n, x0)
    n = _grow(parts, n, y0)
    n = _grow(parts, n, y1)
    return _grow(parts, n, x1)


@nb.njit(cache=True)
def orient3d_sign_exact_diffs(ad, bd, cd, parts):  # pragma: no cover - compiled
    """Exact sign of ``det[ad, bd, cd]`` for differences that are exact doubles: six triple products
    (four doubles each) summed exactly; ``parts`` scratch of 32."""
    n = _grow_product3(parts, 0, ad[2], bd[0], cd[1])
    n = _grow_product3(parts, n, -ad[2], cd[0], bd[1])
    n = _grow_product3(parts, n, bd[2], cd[0], ad[1])
    n = _grow_product3(parts, n, -bd[2], ad[0], cd[1])
    n = _grow_product3(parts, n, cd[2], ad[0], bd[1])
    n = _grow_product3(parts, n, -cd[2], bd[0], ad[1])
    if n == 0:
        return 0
    return 1 if parts[n - 1] > 0.0 else -1


@nb.njit(cache=True)
def orient3d_sign(V, ia, ib, ic, id_, w, lens):  # pragma: no cover - compiled
    """Exact sign of ``det[a - d, b - d, c - d]`` for rows ``ia, ib, ic, id_`` of ``V``.

    ``w`` is scratch of shape (20, 512) float64, ``lens`` int64 scratch of 9.
    Rows 3..11 of ``w`` hold ``a - d``, ``b - d``, ``c - d`` (``lens[row - 3]``).
    """
    exact = True
    for k in range(3):
        lens[k] = _diff_expansion(w, 3 + k, V[ia, k], V[id_, k])
        lens[3 + k] = _diff_expansion(w, 6 + k, V[ib, k], V[id_, k])
        lens[6 + k] = _diff_expansion(w, 9 + k, V[ic, k], V[id_, k])
        exact = exact and lens[k] < 2 and lens[3 + k] < 2 and lens[6 + k] < 2
    if exact:  # every difference is one double (or zero): the short path
        for r in range(3, 12):
            w[0, r] = w[r, 0] if lens[r - 3] else 0.0
        return orient3d_sign_exact_diffs(w[0, 3:6], w[0, 6:9], w[0, 9:12], w[1])
    total = 0
    for t in range(3):
        # det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady)
        if t == 0:
            z, p, q = 5, 6, 9
        elif t == 1:
            z, p, q = 8, 9, 3
        else:
            z, p, q = 11, 3, 6
        m = _cross_component(w, p, lens[p - 3], q + 1, lens[q - 2], q, lens[q - 3], p + 1, lens[p - 2], 1, 12)
        m = _mul(w, 1, m, z, lens[z - 3], 2, 12, 13)
        total = _sum(w, 0, total, 2, m, 16)
        for k in range(total):
            w[0, k] = w[16, k]
    return _sign(w, 0, total)


@nb.njit(cache=True, inline="always")
def _minor(w, lens, a, b, c, d):  # pragma: no cover - compiled
    """``x_a x_b - x_c x_d`` in floats and ``|x_a x_b| + |x_c x_d|`` for one-double rows (0 if empty)."""
    xa = w[a, 0] if lens[a] else 0.0
    xb = w[b, 0] if lens[b] else 0.0
    xc = w[c, 0] if lens[c] else 0.0
    xd = w[d, 0] if lens[d] else 0.0
    return xa * xb - xc * xd, abs(xa * xb) + abs(xc * xd)


@nb.njit(cache=True)
def normals_dot_sign(V, p0, p1, p2, q0, q1, q2, w, lens):  # pragma: no cover - compiled
    """Exact sign of ``((p1 - p0) x (p2 - p0)) . ((q1 - q0) x (q2 - q0))`` for rows of ``V``.

    ``w`` scratch of shape (24, 2048) float64, ``lens`` int64 scratch of 18.
    """
    exact = True
    for k in range(3):
        lens[k] = _diff_expansion(w, k, V[p1, k], V[p0, k])
        lens[3 + k] = _diff_expansion(w, 3 + k, V[p2, k], V[p0, k])
        lens[6 + k] = _diff_expansion(w, 6 + k, V[q1, k], V[q0, k])
        lens[9 + k] = _diff_expansion(w, 9 + k, V[q2, k], V[q0, k])
        exact = exact and lens[k] < 2 and lens[3 + k] < 2 and lens[6 + k] < 2 and lens[9 + k] < 2
    if exact:  # exact differences: a float filter first (error bound below), else the full expansions
        dot, bound = 0.0, 0.0
        for k in range(3):
            i, j = (k + 1) % 3, (k + 2) % 3
            nf, pf = _minor(w, lens, i, 3 + j, j, 3 + i)
            ng, pg = _minor(w, lens, 6 + i, 9 + j, 6 + j, 9 + i)
            dot += nf * ng
            bound += pf * pg
        # |dot - exact| <= (gamma_3 + 2 gamma_2)(1 + gamma_2)^2 sum P_f P_g ~ 7u sum P_f P_g; 1e-14 is ~90u
        if abs(dot) > 1e-14 * bound:
            return 1 if dot > 0.0 else -1
    for side in range(2):
        e1, e2 = 6 * side, 6 * side + 3
        for k in range(3):
            i, j = (k + 1) % 3, (k + 2) % 3
            # n_k = e1_i e2_j - e1_j e2_i, into row 12 + 3 side + k
            lens[12 + 3 * side + k] = _cross_component(
                w,
                e1 + i,
                lens[e1 + i],
                e2 + j,
                lens[e2 + j],
                e1 + j,
                lens[e1 + j],
                e2 + i,
                lens[e2 + i],
                12 + 3 * side + k,
                18,
            )
    total = 0
    for k in range(3):  # rows 0..2 are free now
        m = _mul(w, 12 + k, lens[12 + k], 15 + k, lens[15 + k], 1, 18, 19)
        total = _sum(w, 0, total, 1, m, 2)
        for i in range(total):
            w[0, i] = w[2, i]
    return _sign(w, 0, total)


__all__ = ["exact_range_ok", "orient3d_sign", "normals_dot_sign"]
