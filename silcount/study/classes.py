"""Complexity classes with confidence: a growth series against 1, log n, ..., n^3, chosen by AIC, bootstrapped.

A growth series is ``(sizes, costs)``: operation counts of one detector over meshes of
``n`` faces (or any size above 1).  Each class of :data:`CLASSES` is the model

    ``log cost = log a + log g(n) + e``,   ``e ~ N(0, s^2)`` independent,

one scale ``a`` per class, fitted by least squares on ``log cost`` (the
multiplicative error model: a mesh's count is off by a factor, not by a fixed
number of operations, and the corpus's counts span five decades).  There is no
additive term ``+ b``: with one, the constant class is nested in every other
(``b`` alone is class 1) and the largest meshes would dominate the residuals,
so a class would win for having a parameter, not for its shape.  With one scale
each, the classes are not nested and every model has the same two
parameters (``log a`` and ``s``).

**Criterion: AIC** (Akaike 1974), as plasma-umass/bigO selects classes:
``AIC = N ln(RSS / N) + 2k`` with ``RSS`` the residual sum of squares of
``log cost``, ``k = 2``.  Because every class has the same ``k``, AICc and BIC
differ from AIC by one constant for every class: the ranking, the differences
``delta`` and the Akaike weights ``w_i = exp(-delta_i / 2) / sum_j exp(-delta_j / 2)``
(Burnham and Anderson 2002, Sec. 2.9) are the same under the three; the
criterion is named for the weights' meaning (the probability that a class is
the best approximating one among these nine), not because it changes the pick.
The residuals are all on the one scale (``log cost``): big_O (pberkes/big_O
pull request #45) compared residuals of some classes on a log scale with
others' on the linear scale and misclassified quadratics, and its choice on
noisy timings changes from call to call (issue #37); hence the weights, and the
bootstrap below, rather than a bare residual comparison.

**Bootstrap over meshes**: :data:`RESAMPLES` resamples of the points with
replacement, drawn by ``numpy.random.default_rng(seed)`` (seed
:data:`SEED` unless given: the same series give the same shares); each
resample picks its own class by AIC, and ``share`` is the fraction of
resamples picking each class.  Resamples with fewer than two distinct sizes
have no shape and are skipped (``resamples`` counts those used).  A class that
fits exactly (``RSS = 0``, a noiseless series) is floored at ``N * 1e-24``
(a residual of 1e-12 per point, below float precision of the logs).

Where two classes differ little over the sizes measured (``n`` and ``n log n``
over three decades: ``log log n`` moves by less than one), the weights split
and the shares say so; docs/complexity.md gives the synthetic check
(``python -m benchmarks.classes``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from silcount.errors import BadArgument

if TYPE_CHECKING:
    import pandas as pd

RESAMPLES = 1000
SEED = 0
PARAMETERS = 2  # log a and the residual variance: the same for every class
RSS_FLOOR = 1e-24  # per point: an exact fit's log(0) would be -inf


CLASSES: tuple[tuple[str, Callable[[np.ndarray], np.ndarray]], ...] = (
    ("1", lambda ln: np.zeros_like(ln)),
    ("log n", lambda ln: np.log(ln)),
    ("sqrt n", lambda ln: 0.5 * ln),
    ("n", lambda ln: ln),
    ("n log n", lambda ln: ln + np.log(ln)),
    ("n^1.5", lambda ln: 1.5 * ln),
    ("n^2", lambda ln: 2.0 * ln),
    ("n^2 log n", lambda ln: 2.0 * ln + np.log(ln)),
    ("n^3", lambda ln: 3.0 * ln),
)
"""Each class's name and ``log g(n)`` as a function of ``ln n``, slowest first."""

NAMES: tuple[str, ...] = tuple(name for name, _ in CLASSES)


@dataclass(frozen=True)
class ClassChoice:
    """The class chosen for one series: its Akaike weight, the runner-up, and every class's weight and
    bootstrap share (tuples in :data:`NAMES` order; :attr:`table` gives them as a pandas DataFrame)."""

    chosen: str
    weight: float
    runner_up: str
    runner_up_weight: float
    share: float  # of the bootstrap resamples that pick ``chosen``
    weights: tuple[float, ...]
    shares: tuple[float, ...]
    scales: tuple[float, ...]  # a of cost = a g(n), per class
    points: int
    resamples: int

    @property
    def table(self) -> pd.DataFrame:
        """One row per class: ``class, a, weight, share``, slowest class first."""
        import pandas as pd

        return pd.DataFrame({"class": NAMES, "a": self.scales, "weight": self.weights, "share": self.shares})

    def text(self) -> str:
        """``n^1.5 (w 0.83, bootstrap 0.91; runner-up n log n, w 0.17)``."""
        return (
            f"{self.chosen} (w {self.weight:.2f}, bootstrap {self.share:.2f}; "
            f"runner-up {self.runner_up}, w {self.runner_up_weight:.2f})"
        )

    def as_dict(self) -> dict:
        """JSON-ready: the choice, its weight and share, the runner-up, and per class its weight and share."""
        return {
            "chosen": self.chosen,
            "weight": self.weight,
            "share": self.share,
            "runner_up": self.runner_up,
            "runner_up_weight": self.runner_up_weight,
            "weights": dict(zip(NAMES, self.weights)),
            "shares": dict(zip(NAMES, self.shares)),
            "points": self.points,
            "resamples": self.resamples,
            "criterion": "AIC",
        }


def log_classes(ln: np.ndarray) -> np.ndarray:
    """``log g(n)`` of every class at ``ln = log n`` (any shape): shape ``(len(CLASSES), *ln.shape)``."""
    return np.stack([g(ln) for _, g in CLASSES])


def aic(lg: np.ndarray, ly: np.ndarray) -> np.ndarray:
    """AIC of each class (first axis of ``lg``) for ``log cost = log a + lg + e``, over the last axis (points).

    ``ly`` broadcasts against ``lg``; ``log a`` is the mean residual, so ``RSS`` is ``N`` times their variance.
    """
    r = ly - lg
    n = r.shape[-1]
    rss = ((r - r.mean(axis=-1, keepdims=True)) ** 2).sum(axis=-1)
    return n * np.log(np.maximum(rss, n * RSS_FLOOR) / n) + 2 * PARAMETERS


def akaike_weights(criterion: np.ndarray) -> np.ndarray:
    """``exp(-delta / 2)`` normalised, ``delta`` the criterion less its least value (first axis: classes)."""
    delta = criterion - criterion.min(axis=0, keepdims=True)
    w = np.exp(-0.5 * delta)
    return w / w.sum(axis=0, keepdims=True)


def _checked(sizes, costs) -> tuple[np.ndarray, np.ndarray]:
    n = np.asarray(sizes, dtype=np.float64)
    y = np.asarray(costs, dtype=np.float64)
    if n.shape != y.shape or n.ndim != 1:
        raise BadArgument(f"a growth series needs sizes and costs of one length, got shapes {n.shape} and {y.shape}")
    if not (np.isfinite(n).all() and np.isfinite(y).all()) or (n <= 1).any() or (y <= 0).any():
        raise BadArgument("a growth series needs finite sizes above 1 (log n > 0) and positive costs")
    if np.unique(n).size < 3:
        raise BadArgument(f"choosing a class needs at least 3 distinct sizes, got {np.unique(n).size}")
    return np.log(n), np.log(y)


def choose(sizes, costs, resamples: int = RESAMPLES, seed: int = SEED) -> ClassChoice:
    """The class of :data:`CLASSES` that AIC picks for ``costs`` over ``sizes``, its Akaike weight, the
    runner-up, and the share of ``resamples`` bootstrap resamples of the points picking each class."""
    if resamples < 1:
        raise BadArgument(f"resamples {resamples}: need at least one")
    ln, ly = _checked(sizes, costs)
    lg = log_classes(ln)
    crit = aic(lg, ly)
    weights = akaike_weights(crit)
    scales = np.exp((ly - lg).mean(axis=-1))
    order = np.argsort(-weights, kind="stable")
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, ln.size, size=(resamples, ln.size))
    distinct = (np.diff(np.sort(ln[idx], axis=1), axis=1) != 0).any(axis=1)  # at least two distinct sizes
    idx = idx[distinct]
    picks = aic(lg[:, idx], ly[idx]).argmin(axis=0)
    shares = np.bincount(picks, minlength=len(CLASSES)) / max(idx.shape[0], 1)
    best, second = int(order[0]), int(order[1])
    return ClassChoice(
        chosen=NAMES[best],
        weight=float(weights[best]),
        runner_up=NAMES[second],
        runner_up_weight=float(weights[second]),
        share=float(shares[best]),
        weights=tuple(float(w) for w in weights),
        shares=tuple(float(s) for s in shares),
        scales=tuple(float(a) for a in scales),
        points=int(ln.size),
        resamples=int(idx.shape[0]),
    )
