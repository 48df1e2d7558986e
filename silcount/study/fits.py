"""Power-law fits ``y ~ c F^alpha`` (or ``c x^alpha`` for another size ``x``) over meshes, with a bootstrap
interval for the exponent.

The fit is ordinary least squares of ``log y`` on ``log F`` (McGuire,
"Observations on silhouette sizes", JGT 2004, fits the same form and reports
``0.7 F^0.8`` for the silhouette over real models, ``F^0.5`` for convex ones).
``alpha_ci`` is the 2.5 and 97.5 percentiles of the slope over
:data:`BOOTSTRAP` resamples of the meshes with replacement, drawn with
``numpy.random.default_rng(BOOTSTRAP_SEED)`` (fixed: the same data give the
same interval); resamples whose ``F`` are all equal have no slope and are
skipped.  Meshes with ``y <= 0`` (no silhouette, no operation) cannot be on a
log scale and are left out; ``meshes`` is the number used.  Fewer than two
distinct ``F``: no fit (``alpha`` and ``c`` are ``None``).  ``classes`` is the
complexity class of the same points (:func:`silcount.study.classes.choose`:
AIC over 1, log n, ..., n^3, Akaike weights, 1000 seeded bootstrap resamples),
``None`` with fewer than three distinct sizes or a size of at most 1 (where
``log n`` is not positive).  ``against`` names
the size fitted against (``F``, the faces, unless another is passed: the
silhouette ``s`` or ``s log2 F`` of :mod:`silcount.study.literature`).
"""

from __future__ import annotations

import numpy as np

from silcount.study.classes import choose

BOOTSTRAP = 2000
BOOTSTRAP_SEED = 0
CI = (2.5, 97.5)


def _slopes(lx: np.ndarray, ly: np.ndarray) -> np.ndarray:
    """Least-squares slope of each row of ``ly`` on the same row of ``lx`` (NaN where ``lx`` is constant)."""
    dx = lx - lx.mean(axis=-1, keepdims=True)
    dy = ly - ly.mean(axis=-1, keepdims=True)
    var = (dx * dx).sum(axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(var > 0, (dx * dy).sum(axis=-1) / np.where(var > 0, var, 1.0), np.nan)


def power_fit(faces, values, subset: str = "", against: str = "F") -> dict:
    """``{"alpha", "c", "alpha_ci", "meshes", "subset", "against", "classes"}`` for ``values ~ c faces^alpha``
    (``faces``: any positive size, named by ``against``)."""
    x = np.asarray(faces, dtype=np.float64)
    y = np.asarray(values, dtype=np.float64)
    keep = (x > 0) & (y > 0) & np.isfinite(y)
    x, y = x[keep], y[keep]
    out: dict = {"alpha": None, "c": None, "alpha_ci": None, "meshes": int(x.size), "subset": subset}
    out["against"] = against
    out["classes"] = choose(x, y).as_dict() if np.unique(x).size >= 3 and (x > 1).all() else None
    if np.unique(x).size < 2:
        return out
    lx, ly = np.log(x), np.log(y)
    alpha = float(_slopes(lx, ly))
    out["alpha"] = alpha
    out["c"] = float(np.exp(ly.mean() - alpha * lx.mean()))
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    idx = rng.integers(0, x.size, size=(BOOTSTRAP, x.size))
    boot = _slopes(lx[idx], ly[idx])
    boot = boot[np.isfinite(boot)]
    if boot.size:
        lo, hi = np.percentile(boot, CI)
        out["alpha_ci"] = [float(lo), float(hi)]
    return out
