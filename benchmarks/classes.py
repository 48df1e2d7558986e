"""Class selection on synthetic series of known class, with the scatter and sizes of the committed corpus series.

Issue 40's target: over the corpus's sizes (the 51 meshes of ``reports/corpus/meshes.csv``, 80 to 86,482
faces) and with the scatter the measured series have (the residual standard deviation of ln(total
operations) about each committed corpus series' power-law fit), the right class of
:func:`silcount.study.classes.choose` must win >= 95 % of 1000 bootstrap resamples for n, n^1.5 and n^2.
For each detector's scatter and each known class this prints

* ``boot``: the share of 1000 bootstrap resamples of one seeded synthetic series picking the right class
  (the issue's measure);
* ``draws``: the fraction of 1000 fresh synthetic series (new noise, seeded) whose whole-series choice is
  right: how often a corpus like this one would name the class;

then, for n against n log n, the best share of right picks that any rule can reach over these sizes
(``best``: Neyman-Pearson, ``Phi(|d| / (2 sigma))`` with ``d`` the centred ln ln n; :func:`best_any_rule`), and the
span of sizes (decades, 51 sizes spread evenly in log from 80 faces) that
fresh draws of each need to pick their own class in >= 95 % of 1000 draws.  Deterministic (seeded); no timing
beyond the run's own wall time.

    python -m benchmarks.classes [--meshes reports/corpus/meshes.csv]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from benchmarks.common import ROOT, load_line
from silcount.study.classes import NAMES, aic, choose, log_classes

KNOWN = ("n", "n log n", "n^1.5", "n^2")
DRAWS = 1000
SMALLEST = 80.0  # faces of the corpus's smallest meshes
SPANS = np.arange(1.0, 40.01, 0.25)


def scatter(meshes: Path) -> dict[str, float]:
    """Residual standard deviation of ln(total) about the log-log fit, per ``<detector>:true_total`` series."""
    import pandas as pd

    frame = pd.read_csv(meshes)
    frame = frame[frame["error"].isna() | (frame["error"].astype(str) == "")]
    lf = np.log(frame["faces"].to_numpy(float))
    out = {}
    for col in (c for c in frame.columns if c.endswith(":true_total")):
        ly = np.log(frame[col].to_numpy(float))
        out[col.split(":")[0]] = float(np.std(ly - np.polyval(np.polyfit(lf, ly, 1), lf), ddof=2))
    return out


def series(name: str, sizes: np.ndarray, sigma: float, rng: np.random.Generator, draws: int = 1) -> np.ndarray:
    """``draws`` synthetic ln(cost) rows of class ``name``: ln g(n) plus normal noise of standard deviation sigma."""
    lg = log_classes(np.log(sizes))[NAMES.index(name)]
    return lg + sigma * rng.standard_normal((draws, sizes.size))


def right_draws(name: str, sizes: np.ndarray, sigma: float, seed: int = 2) -> float:
    """The fraction of :data:`DRAWS` fresh series of class ``name`` for which AIC picks ``name``."""
    ly = series(name, sizes, sigma, np.random.default_rng(seed), DRAWS)
    picks = aic(log_classes(np.log(sizes))[:, None, :], ly[None]).argmin(axis=0)
    return float(np.mean(picks == NAMES.index(name)))


def best_any_rule(sizes: np.ndarray, sigma: float) -> float:
    """The highest share of right picks between n and n log n, both ways alike, that any rule can reach at ``sigma``.

    The two models differ by ``ln ln n`` up to their scales; once the common scale is projected out, two simple
    hypotheses remain and the likelihood ratio (here: the smaller RSS, i.e. AIC) is the most powerful test
    (Neyman-Pearson), erring with probability ``Phi(-|d| / (2 sigma))``, ``d`` the centred ``ln ln n``."""
    from scipy.stats import norm

    d = np.log(np.log(sizes))
    return float(norm.cdf(np.linalg.norm(d - d.mean()) / (2.0 * sigma)))


def span_needed(sigma: float, points: int) -> float | None:
    """The least span (decades) over which both n and n log n are picked in >= 95 % of fresh draws; None past 40."""
    for span in SPANS:
        sizes = SMALLEST * np.logspace(0.0, span, points)
        if min(right_draws(name, sizes, sigma) for name in ("n", "n log n")) >= 0.95:
            return float(span)
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=Path, default=ROOT / "reports" / "corpus" / "meshes.csv")
    args = parser.parse_args()
    import pandas as pd

    t0 = time.perf_counter()
    sizes = pd.read_csv(args.meshes)["faces"].to_numpy(float)
    decades = np.log10(sizes.max() / sizes.min())
    print(f"{load_line()}; {sizes.size} sizes, {sizes.min():.0f} to {sizes.max():.0f} faces ({decades:.2f} decades)")
    levels = sorted(scatter(args.meshes).items(), key=lambda kv: kv[1])
    head = " | ".join(f"{k} boot | {k} draws" for k in KNOWN)
    print(f"\n| series (its scatter) | sigma | {head} | n vs n log n: best any rule | decades for 95 % |")
    print("|---|---:|" + "---:|" * (2 * len(KNOWN)) + "---:|---:|")
    for det, sigma in levels:
        cells = []
        for name in KNOWN:
            boot = choose(sizes, np.exp(series(name, sizes, sigma, np.random.default_rng(1))[0]))
            cells += [f"{boot.shares[NAMES.index(name)]:.3f}", f"{right_draws(name, sizes, sigma):.3f}"]
        span = span_needed(sigma, sizes.size)
        shown = "> 40" if span is None else f"<= {span:.2f}" if span == SPANS[0] else f"{span:.2f}"  # the least tried
        best = best_any_rule(sizes, sigma)
        print(f"| {det} | {sigma:.3f} | " + " | ".join(cells) + f" | {best:.3f} | {shown} |")
    print(f"\n({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    main()
