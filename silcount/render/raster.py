"""The rasteriser: homogeneous clipping, pixel-centre sampling, depth and an integer stencil.

* Triangles arrive in clip coordinates ``(x, y, z, w)``; points at infinity
  (``w_world = 0``) are ordinary input.  Each triangle is clipped
  (Sutherland-Hodgman, in homogeneous space) against the near plane
  ``z >= -w``, a guard band ``|x|, |y| <= 2 w`` and ``w > 0``; an
  intersection is always computed from the inside vertex towards the
  outside one, so two triangles sharing an edge get bit-identical new
  vertices.
* Vertices snap to a fixed-point grid of 1/256 pixel and edge functions are
  evaluated in exact int64 arithmetic.  A pixel is drawn iff its centre
  ``(col + 0.5, row + 0.5)`` is inside, or on a top or left edge (the
  Direct3D/OpenGL top-left rule): two triangles sharing an edge cover each
  pixel centre exactly once.
* Depth is NDC ``z = z_c / w_c``, which is affine in screen space, so
  interpolating it with screen-space barycentrics is perspective-correct.
  The depth test is ``LESS`` against a buffer cleared to 1 (the far plane).
* Facing is the clip-space winding: counter-clockwise in NDC (y up) is
  front-facing, as OpenGL's default ``glFrontFace(GL_CCW)``.

* Two cores (issue 15): :func:`rasterize` first clips and snaps every
  triangle once, then fills in parallel parts (``prange``): the screen is
  cut into ``BANDS_PER_PART * parts`` equal row bands, part ``p`` takes
  bands ``p, p + parts, ...`` one at a time and draws every triangle that
  reaches the band, in input order, into the band's rows only (a triangle
  is set up once per band it reaches, so bands are few and tall).  Each
  pixel therefore
  sees the same triangles in the same order with the same arithmetic as
  the single-threaded ``rasterize_serial`` of ``tests/oracles/render_baseline.py``
  (commit 318ab63, kept as the baseline), so depth, stencil and ids are
  bit-identical for any number of parts.  Row spans step from row to row
  by exact integer quotient and remainder instead of three divisions per
  row (shadow-volume sides are long slivers, about 1.4 pixels per row).
  The depth pass's spans (the scene's, long) run without a branch
  (:func:`_depth_span`), several columns to an instruction, on the same
  bits; the stencil passes' short spans keep the branching loop, which was
  faster there.
* A triangle with all three vertices beyond one screen edge (``x > w``,
  ``x < -w``, ``y > w`` or ``y < -w``: a half-space, so the whole triangle
  is, and its snapped vertices lie at or beyond the last pixel centre's
  half-pixel margin) is rejected before clipping; one inside every clip
  plane skips the clipper (Sutherland-Hodgman returns it unchanged).  The
  clip planes stay at the guard band: clipping at the screen edges would
  move snapped vertices and change pixels, and the fill already visits
  only on-screen rows and, per row, only the covered columns.

Modes: ``DEPTH`` writes depth and a triangle id; ``ZPASS`` adds +1 (front)
/ -1 (back) to the stencil where the depth test passes; ``ZFAIL`` adds +1
(back) / -1 (front) where it fails: the two-sided stencil of the stencil
paper Sec. 5 steps (4)-(5) and of Everitt & Kilgard 2002.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from silcount.threads import fitted

DEPTH, ZPASS, ZFAIL = 0, 1, 2
SUBPIXEL = 256
GUARD = 2.0
_W_MIN = 1e-9
_MAXV = 16


@njit(cache=True)
def _plane_distance(p, k, guard):
    if k == 0:
        return p[2] + p[3]  # near: z >= -w
    if k == 1:
        return guard * p[3] + p[0]  # x >= -g w
    if k == 2:
        return guard * p[3] - p[0]  # x <= g w
    if k == 3:
        return guard * p[3] + p[1]
    if k == 4:
        return guard * p[3] - p[1]
    return p[3] - _W_MIN  # w > 0


@njit(cache=True)
def _clip(tri, poly, tmp, guard):
    """Clip one triangle (3, 4) into ``poly``; returns the vertex count."""
    n = 3
    for i in range(3):
        for c in range(4):
            poly[i, c] = tri[i, c]
    for k in range(6):
        m = 0
        for i in range(n):
            a = poly[i]
            b = poly[(i + 1) % n]
            da = _plane_distance(a, k, guard)
            db = _plane_distance(b, k, guard)
            if da >= 0.0:
                for c in range(4):
                    tmp[m, c] = a[c]
                m += 1
            if (da >= 0.0) != (db >= 0.0):
                # from the inside vertex towards the outside one: order-independent
                if da >= 0.0:
                    t = da / (da - db)
                    for c in range(4):
                        tmp[m, c] = a[c] + t * (b[c] - a[c])
                else:
                    t = db / (db - da)
                    for c in range(4):
                        tmp[m, c] = b[c] + t * (a[c] - b[c])
                m += 1
        n = m
        for i in range(n):
            for c in range(4):
                poly[i, c] = tmp[i, c]
        if n < 3:
            return 0
    return n


@njit(cache=True, inline="always")
def _span(ax, ay, bx, by, bias, py, lo, hi):
    """Narrow the column range [lo, hi] of row centre ``py`` to where ``E_ab + bias > 0`` (exact integers)."""
    # E(c) = (bx - ax)(py - ay) - (by - ay)(c S + S/2 - ax) = base + step c
    base = (bx - ax) * (py - ay) - (by - ay) * (SUBPIXEL // 2 - ax)
    step = -(by - ay) * SUBPIXEL
    k = -(base + bias)  # need step * c > k
    if step > 0:
        lo = max(lo, k // step + 1)
    elif step < 0:
        hi = min(hi, -(k // -step) - 1)
    elif k >= 0:
        hi = lo - 1
    return lo, hi


BANDS_PER_PART = 2  # row bands per thread, interleaved (part p fills bands p, p + parts, ...)


@njit(cache=True)
def _trivial(tri, guard):
    """-1: beyond one screen edge (draws nothing); 1: inside every clip plane (clipping is the identity); 0."""
    right = left = top = bottom = True
    inside = True
    for i in range(3):
        x, y, w = tri[i, 0], tri[i, 1], tri[i, 3]
        right &= x > w
        left &= x < -w
        top &= y > w
        bottom &= y < -w
        for k in range(6):
            inside &= _plane_distance(tri[i], k, guard) >= 0.0
    if right or left or top or bottom:
        return -1
    return 1 if inside else 0


@njit(cache=True)
def _prepare(clip, W, H, X, Y, Z, nv, area, rows):
    """Clip and snap every triangle: ``nv[t]`` vertices in ``X, Y, Z[t]`` (0 if nothing to draw), ``area[t]``,
    and ``rows[t]`` the pixel rows its bounding box can reach."""
    poly = np.empty((_MAXV, 4))
    tmp = np.empty((_MAXV, 4))
    for t in range(clip.shape[0]):
        nv[t] = 0
        kind = _trivial(clip[t], GUARD)
        if kind < 0:
            continue
        if kind > 0:
            n = 3
            for i in range(3):
                for c in range(4):
                    poly[i, c] = clip[t, i, c]
        else:
            n = _clip(clip[t], poly, tmp, GUARD)
            if n < 3:
                continue
        for i in range(n):
            w = poly[i, 3]
            X[t, i] = int(np.rint((0.5 * poly[i, 0] / w + 0.5) * W * SUBPIXEL))
            Y[t, i] = int(np.rint((0.5 - 0.5 * poly[i, 1] / w) * H * SUBPIXEL))
            Z[t, i] = poly[i, 2] / w
        a = 0
        for i in range(n):
            j = (i + 1) % n
            a += X[t, i] * Y[t, j] - X[t, j] * Y[t, i]
        if a != 0:
            nv[t] = n
            area[t] = a
            ymin, ymax = Y[t, 0], Y[t, 0]
            for i in range(1, n):
                ymin, ymax = min(ymin, Y[t, i]), max(ymax, Y[t, i])
            rows[t, 0] = (ymin - SUBPIXEL // 2) // SUBPIXEL  # conservative: _fill_rows finds the exact rows
            rows[t, 1] = (ymax - SUBPIXEL // 2) // SUBPIXEL + 1


@njit(cache=True, inline="always")
def _edge_start(ax, ay, bx, by, bias, py):
    """The edge ``a -> b`` at row centre ``py`` as :func:`_span` sees it, ready to step row by row.

    :func:`_span` needs ``k // D`` with ``k = -(E_ab(col 0) + bias)``, ``D = |step|``; from one row to
    the next ``k`` changes by ``dk``, so the quotient and remainder step exactly by ``dk // D``,
    ``dk % D`` and a carry: the same integers as dividing on every row.  Returns
    ``(sign of step, q, m, D, dq, dm)``; for a horizontal edge (``step == 0``) ``q`` is ``k`` itself.
    """
    base = (bx - ax) * (py - ay) - (by - ay) * (SUBPIXEL // 2 - ax)
    step = -(by - ay) * SUBPIXEL
    k = -(base + bias)
    dk = -(bx - ax) * SUBPIXEL
    if step == 0:
        return 0, k, 0, 1, dk, 0
    d = step if step > 0 else -step
    return (1 if step > 0 else -1), k // d, k % d, d, dk // d, dk % d


@njit(cache=True, inline="always")
def _bound(kind, q, lo, hi):
    """Narrow ``[lo, hi]`` by one edge, as :func:`_span` does."""
    if kind > 0:
        lo = max(lo, q + 1)
    elif kind < 0:
        hi = min(hi, -q - 1)
    elif q >= 0:
        hi = lo - 1
    return lo, hi


@njit(cache=True, inline="always")
def _depth_span(depth, tri_id, lo, hi, e01, e12, e20, d01, d12, d20, z0, z1, z2, inv, ident):
    """``DEPTH`` on columns ``lo..hi`` of one row: where ``z < depth``, write ``z`` and ``ident``; the number
    written.  The edge functions are exact integers below 2**53, so stepping them as doubles gives the very
    values the integers convert to, and ``z`` the same bits; without branches, the compiler takes several
    columns to an instruction (a tiled GPU's rasteriser tests a block of samples at once likewise)."""
    f01, f12, f20 = float(e01), float(e12), float(e20)
    g01, g12, g20 = float(d01), float(d12), float(d20)
    span, ids = depth[lo : hi + 1], tri_id[lo : hi + 1]  # 0-based views: the loop then vectorises
    hits = 0
    for j in range(span.size):
        k = float(j)
        z = ((f12 + k * g12) * z0 + (f20 + k * g20) * z1 + (f01 + k * g01) * z2) * inv
        old = span[j]
        passed = z < old
        span[j] = z if passed else old
        ids[j] = ident if passed else ids[j]
        hits += passed
    return hits


@njit(cache=True)
def _fill_rows(x0, y0, z0, x1, y1, z1, x2, y2, z2, front, mode, ident, depth, stencil, tri_id, row_lo, row_hi, counts):
    """The baseline's fill (:mod:`.baseline`) on rows ``row_lo..row_hi`` only: the same spans and the same
    depths, with the spans stepped row by row (:func:`_edge_start`) and the edge functions column by column
    (exact integers either way).  ``counts`` (:data:`COUNTS`) gains the fragments, the depth tests passed
    and the stencil updates."""
    H, W = depth.shape
    area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
    half = SUBPIXEL // 2
    c0 = max(0, int(math.ceil((min(x0, min(x1, x2)) - half) / SUBPIXEL)))
    c1 = min(W - 1, int(math.floor((max(x0, max(x1, x2)) - half) / SUBPIXEL)))
    r0 = max(row_lo, int(math.ceil((min(y0, min(y1, y2)) - half) / SUBPIXEL)))
    r1 = min(row_hi, int(math.floor((max(y0, max(y1, y2)) - half) / SUBPIXEL)))
    if r0 > r1 or c0 > c1:
        return
    fragments = hits = 0  # hits: the fragments that write (DEPTH, ZPASS: passed; ZFAIL: failed)
    # top-left rule: an edge a->b owns its centres iff dy < 0, or dy == 0 and dx > 0
    b01 = 1 if (y1 - y0 < 0 or (y1 == y0 and x1 - x0 > 0)) else 0
    b12 = 1 if (y2 - y1 < 0 or (y2 == y1 and x2 - x1 > 0)) else 0
    b20 = 1 if (y0 - y2 < 0 or (y0 == y2 and x0 - x2 > 0)) else 0
    inv = 1.0 / area
    d01, d12, d20 = -(y1 - y0) * SUBPIXEL, -(y2 - y1) * SUBPIXEL, -(y0 - y2) * SUBPIXEL
    py = r0 * SUBPIXEL + half
    ka, qa, ma, da, dqa, dma = _edge_start(x0, y0, x1, y1, b01, py)
    kb, qb, mb, db, dqb, dmb = _edge_start(x1, y1, x2, y2, b12, py)
    kc, qc, mc, dc, dqc, dmc = _edge_start(x2, y2, x0, y0, b20, py)
    for r in range(r0, r1 + 1):
        lo, hi = _bound(ka, qa, c0, c1)
        lo, hi = _bound(kb, qb, lo, hi)
        lo, hi = _bound(kc, qc, lo, hi)
        if lo <= hi:
            fragments += hi - lo + 1
            py = r * SUBPIXEL + half
            px = lo * SUBPIXEL + half
            e01 = (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)
            e12 = (x2 - x1) * (py - y1) - (y2 - y1) * (px - x1)
            e20 = (x0 - x2) * (py - y2) - (y0 - y2) * (px - x2)
            if mode == DEPTH:
                hits += _depth_span(depth[r], tri_id[r], lo, hi, e01, e12, e20, d01, d12, d20, z0, z1, z2, inv, ident)
            else:
                for c in range(lo, hi + 1):  # short spans (volume sides are slivers): branching is faster here
                    z = (e12 * z0 + e20 * z1 + e01 * z2) * inv
                    passed = z < depth[r, c]
                    if mode == ZPASS:
                        if passed:
                            stencil[r, c] += 1 if front else -1
                            hits += 1
                    elif not passed:
                        stencil[r, c] += -1 if front else 1
                        hits += 1
                    e01 += d01
                    e12 += d12
                    e20 += d20
        qa, ma = qa + dqa, ma + dma
        if ma >= da:
            qa, ma = qa + 1, ma - da
        qb, mb = qb + dqb, mb + dmb
        if mb >= db:
            qb, mb = qb + 1, mb - db
        qc, mc = qc + dqc, mc + dmc
        if mc >= dc:
            qc, mc = qc + 1, mc - dc
    counts[0] += fragments
    counts[1] += fragments - hits if mode == ZFAIL else hits
    counts[2] += 0 if mode == DEPTH else hits


@njit(cache=True)
def _clear_rows(mode, depth, stencil, tri_id, row_lo, row_hi):
    """Rows ``row_lo..row_hi`` of the buffers ``mode`` writes, cleared: depth to the far plane (1) and ids to
    -1 (``DEPTH``), else the stencil to 0."""
    if mode == DEPTH:
        depth[row_lo : row_hi + 1, :] = 1.0
        tri_id[row_lo : row_hi + 1, :] = -1
    else:
        stencil[row_lo : row_hi + 1, :] = 0


@njit(cache=True)
def _fill_part(X, Y, Z, nv, area, rows, ids, mode, depth, stencil, tri_id, part, parts, bands, counts, clear):
    """Bands ``part, part + parts, ...`` of the ``bands`` equal row bands, one after the other; in each (cleared
    first if ``clear``, :func:`_clear_rows`), every prepared triangle that reaches it, in input order, into the
    band's rows only."""
    H = depth.shape[0]
    for band in range(part, bands, parts):
        row_lo = band * H // bands
        row_hi = (band + 1) * H // bands - 1
        if clear:
            _clear_rows(mode, depth, stencil, tri_id, row_lo, row_hi)
        for t in range(nv.shape[0]):
            n = nv[t]
            if n < 3 or rows[t, 0] > row_hi or rows[t, 1] < row_lo:
                continue
            front = area[t] < 0  # y points down on screen: counter-clockwise in NDC has negative screen area
            for k in range(1, n - 1):
                a2 = (X[t, k] - X[t, 0]) * (Y[t, k + 1] - Y[t, 0]) - (Y[t, k] - Y[t, 0]) * (X[t, k + 1] - X[t, 0])
                if a2 == 0 or (a2 > 0) != (area[t] > 0):
                    continue  # a sliver that snapping collapsed or flipped
                j1, j2 = (k, k + 1) if area[t] > 0 else (k + 1, k)
                _fill_rows(
                    X[t, 0],
                    Y[t, 0],
                    Z[t, 0],
                    X[t, j1],
                    Y[t, j1],
                    Z[t, j1],
                    X[t, j2],
                    Y[t, j2],
                    Z[t, j2],
                    front,
                    mode,
                    ids[t],
                    depth,
                    stencil,
                    tri_id,
                    row_lo,
                    row_hi,
                    counts,
                )


@njit(cache=True, parallel=True)
def _fill_parts(X, Y, Z, nv, area, rows, ids, mode, depth, stencil, tri_id, parts, bands, counts, clear):
    for part in prange(parts):
        _fill_part(X, Y, Z, nv, area, rows, ids, mode, depth, stencil, tri_id, part, parts, bands, counts[part], clear)


COUNTS = ("fragments", "depth_passed", "stencil_updates")
"""What :func:`rasterize` counts: pixel centres drawn (each triangle's, overdraw included), those whose depth
test ``LESS`` passed, and stencil writes (``ZPASS``: the passed ones, ``ZFAIL``: the failed ones).  Every pixel
is drawn by one part, so the sums do not depend on the number of parts."""


def rasterize(clip, ids, mode, depth, stencil, tri_id, parts: int | None = None, clear: bool = False) -> np.ndarray:
    """Rasterise (T, 3, 4) clip-space triangles into the buffers on ``parts`` threads (default: numba's threads
    that have a free core, :func:`silcount.threads.fitted`); returns the :data:`COUNTS` (int64, in that order).

    ``clear``: the buffers ``mode`` writes are cleared first (any content before is ignored), each row band by
    the thread that then draws into it, as a tiled GPU clears a tile when it first draws into it: the band is
    in that core's cache when its triangles arrive, and the two cores clear side by side."""
    T = clip.shape[0]
    X = np.empty((T, _MAXV), dtype=np.int64)
    Y = np.empty((T, _MAXV), dtype=np.int64)
    Z = np.empty((T, _MAXV))
    nv = np.empty(T, dtype=np.int64)
    area = np.zeros(T, dtype=np.int64)
    rows = np.empty((T, 2), dtype=np.int64)
    H, W = depth.shape
    if not T:
        if clear:
            _clear_rows(mode, depth, stencil, tri_id, 0, H - 1)
        return np.zeros(len(COUNTS), dtype=np.int64)
    _prepare(clip, W, H, X, Y, Z, nv, area, rows)
    with fitted() as threads:  # the cores free now (silcount.threads)
        parts = parts or threads
        counts = np.zeros((parts, len(COUNTS)), dtype=np.int64)  # one row per part: no two threads add to one cell
        if parts == 1:
            _fill_part(X, Y, Z, nv, area, rows, ids, mode, depth, stencil, tri_id, 0, 1, 1, counts[0], clear)
        else:
            bands = min(H, BANDS_PER_PART * parts)
            _fill_parts(X, Y, Z, nv, area, rows, ids, mode, depth, stencil, tri_id, parts, bands, counts, clear)
    return counts.sum(axis=0)


def new_buffers(width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Depth (float64, cleared to the far plane, 1), stencil (int32, 0) and triangle id (int32, -1) buffers.

    The ids are 32-bit, as a GPU's are: a depth pass writes an id with every passing fragment, and 64-bit ids
    made the pass move 16 bytes per fragment against llvmpipe's 4 (its D24S8 depth-stencil)."""
    return (
        np.ones((height, width)),
        np.zeros((height, width), dtype=np.int32),
        np.full((height, width), -1, dtype=np.int32),
    )


CLIP_ROWS = 8192
"""The most rows one BLAS product of :func:`to_clip` takes: OpenBLAS runs a larger product on several
threads, which on a loaded machine costs far more than the product (57,218 triangles: 0.45 ms at best,
98 ms median, on 2 busy cores; in parts of at most this many rows, 1.3 ms median)."""


def to_clip(points_h: np.ndarray, view_projection: np.ndarray) -> np.ndarray:
    """(T, 3, 4) homogeneous world triangles -> clip space, C-contiguous float64.

    (3T, 4) x (4, 4) products rather than T stacked (3, 4) x (4, 4) ones: several times faster, and the
    same BLAS kernel per element (``tests/test_render_bands.py`` checks the masks against commit 318ab63).
    The rows go in near-equal parts of at most :data:`CLIP_ROWS` (:func:`numpy.array_split`), so that no part
    is a single row (numpy would take that one to another kernel) and none is threaded by OpenBLAS: the
    same bits as one product, whatever the parts."""
    p = np.ascontiguousarray(points_h, dtype=np.float64)
    flat = p.reshape(-1, 4)
    out = np.empty_like(flat)
    vt = np.asarray(view_projection, dtype=np.float64).T
    for part in np.array_split(np.arange(len(flat)), max(1, -(-len(flat) // CLIP_ROWS))):
        if len(part):
            np.matmul(flat[part[0] : part[-1] + 1], vt, out=out[part[0] : part[-1] + 1])
    return out.reshape(p.shape)


def homogeneous(triangles: np.ndarray, w: float = 1.0) -> np.ndarray:
    """(T, 3, 3) -> (T, 3, 4) with the given ``w``."""
    out = np.empty(triangles.shape[:-1] + (4,))
    out[..., :3] = triangles
    out[..., 3] = w
    return out
