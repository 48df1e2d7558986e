"""silcount.study.classes: complexity classes by AIC, Akaike weights and the bootstrap over meshes.

Expected values come from a hand count (the three-point series below) or from the class a series was drawn
from; the scatter of the synthetic series is the one the committed corpus series have (reports/corpus/meshes.csv).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from silcount.errors import BadArgument
from silcount.study.classes import NAMES, choose, log_classes

ROOT = Path(__file__).resolve().parent.parent


def test_a_three_point_series_by_hand():
    """ln n = 1, 2, 3 and ln cost = 0, 1, 3.  Residuals about the best log a (RSS on ln cost), by hand:
    n^1.5: (-1.5, -2, -1.5) -> 1/6; n and n^2: 2/3; sqrt n: 13/6; 1: 42/9 (= 28/6).  AIC = 3 ln(RSS/3) + 4, so the
    weight of n (and of n^2) over n^1.5's is (4)^-1.5 = 1/8, sqrt n's is 13^-1.5."""
    got = choose(np.exp([1.0, 2.0, 3.0]), np.exp([0.0, 1.0, 3.0]))
    w = dict(zip(NAMES, got.weights))
    assert got.chosen == "n^1.5"
    assert w["n"] / w["n^1.5"] == pytest.approx(1 / 8)
    assert w["n^2"] / w["n^1.5"] == pytest.approx(1 / 8)
    assert w["sqrt n"] / w["n^1.5"] == pytest.approx(13**-1.5)
    assert w["1"] / w["n^1.5"] == pytest.approx(28**-1.5)
    assert sum(got.weights) == pytest.approx(1.0)
    # n log n: residuals (-1, -1 - ln 2, -ln 3), RSS = their variance x 3; its weight ratio (RSS / (1/6))^-1.5
    r = np.array([-1.0, -1.0 - math.log(2), -math.log(3)])
    rss = float(((r - r.mean()) ** 2).sum())
    assert w["n log n"] / w["n^1.5"] == pytest.approx((6 * rss) ** -1.5)
    assert got.runner_up == "n log n" and got.runner_up_weight == max(v for k, v in w.items() if k != "n^1.5")
    # the scale of n^1.5: ln a = mean(0 - 1.5, 1 - 3, 3 - 4.5) = -5/3
    assert got.table.set_index("class").loc["n^1.5", "a"] == pytest.approx(math.exp(-5 / 3))


@pytest.mark.parametrize("name", NAMES)
def test_every_noiseless_class_is_recovered_with_all_the_weight(name):
    n = np.geomspace(80, 86482, 12)
    got = choose(n, 7.0 * np.exp(log_classes(np.log(n))[NAMES.index(name)]))
    assert (got.chosen, got.share) == (name, 1.0)
    assert got.weight == pytest.approx(1.0)


def test_a_constant_series_is_class_1():
    """Fails if the classes were ``a + b g(n)`` chosen by residual sum alone: the constant would be nested in
    every other class, whose extra term never fits worse, and ``1`` could not win."""
    n = np.geomspace(80, 86482, 51)
    cost = 500.0 * np.exp(0.3 * np.random.default_rng(3).standard_normal(n.size))
    got = choose(n, cost)
    assert got.chosen == "1" and got.share >= 0.95


def test_the_choice_and_weights_do_not_depend_on_units_or_order():
    n = np.geomspace(100, 1e5, 20)
    cost = n**1.5 * np.exp(0.4 * np.random.default_rng(5).standard_normal(n.size))
    a, b = choose(n, cost), choose(n[::-1], 1000.0 * cost[::-1])
    assert a.chosen == b.chosen
    np.testing.assert_allclose(a.weights, b.weights, rtol=1e-9, atol=1e-300)


def test_the_bootstrap_is_seeded_and_counts_its_resamples():
    n = np.geomspace(80, 86482, 51)
    cost = n * np.exp(0.83 * np.random.default_rng(7).standard_normal(n.size))
    a, b, c = choose(n, cost), choose(n, cost), choose(n, cost, seed=1)
    assert a == b and a.resamples == 1000 and sum(a.shares) == pytest.approx(1.0)
    assert a.shares != c.shares  # another seed, other resamples
    assert choose(n, cost, resamples=50).resamples == 50


def test_resamples_of_one_size_are_skipped():
    """Three points: resamples with one distinct size (3 of 27 equally likely draws) have no shape."""
    got = choose([10.0, 100.0, 1000.0], [10.0, 100.0, 1000.0], resamples=2700, seed=0)
    assert 2700 * (1 - 3 / 27) * 0.9 < got.resamples < 2700 * (1 - 3 / 27) * 1.1


@pytest.mark.parametrize(
    ("sizes", "costs"),
    [
        ([2, 3, 1], [1, 2, 3]),
        ([2, 3, 4], [1, 0, 3]),
        ([2, 3, 3], [1, 2, 3]),
        ([2, 3], [1, 2]),
        ([2, 3, np.nan], [1, 2, 3]),
    ],
)
def test_a_series_that_cannot_be_fitted_is_a_bad_argument(sizes, costs):
    with pytest.raises(BadArgument):
        choose(sizes, costs)


def corpus_scatter() -> dict[str, float]:
    """The residual standard deviation of ln(total operations) about the power-law fit, per committed corpus
    series (51 meshes): the scatter a measured series has."""
    import pandas as pd

    meshes = pd.read_csv(ROOT / "reports" / "corpus" / "meshes.csv")
    lf = np.log(meshes["faces"].to_numpy(float))
    out = {}
    for col in (c for c in meshes.columns if c.endswith(":true_total")):
        ly = np.log(meshes[col].to_numpy(float))
        out[col] = float(np.std(ly - np.polyval(np.polyfit(lf, ly, 1), lf), ddof=2))
    return out


def synthetic(name: str, sizes: np.ndarray, scatter: float, seed: int) -> np.ndarray:
    return np.exp(
        log_classes(np.log(sizes))[NAMES.index(name)]
        + scatter * np.random.default_rng(seed).standard_normal(sizes.size)
    )


def corpus_sizes() -> np.ndarray:
    import pandas as pd

    return pd.read_csv(ROOT / "reports" / "corpus" / "meshes.csv")["faces"].to_numpy(float)


@pytest.mark.parametrize("name", ["n", "n log n", "n^1.5", "n^2"])
def test_known_classes_win_95_percent_of_1000_bootstraps_at_the_scatter_of_eesd(name):
    """Issue 40's target, over the corpus's 51 sizes, with the scatter of EESD's true-model series (0.32;
    reference's and VnV's are smaller): n, n^1.5 and n^2, and n log n too, win >= 95 % of 1000 resamples.
    (At TA's 0.83 n and n^2 win 94.7 % and at HSD's 1.73 81 %: ``python -m benchmarks.classes``.)"""
    scatter = corpus_scatter()["eesd:true_total"]
    assert 0.25 < scatter < 0.35
    got = choose(corpus_sizes(), synthetic(name, corpus_sizes(), scatter, seed=1))
    assert got.chosen == name and got.shares[NAMES.index(name)] >= 0.95


def test_at_the_scatter_of_ta_n_log_n_is_not_told_from_n():
    """The limit, as found: at the scatter of TA's true-model series (0.83, the median of the seven), fresh
    draws of an n log n series pick n log n in under 95 % of 400 draws over the corpus's range, mostly
    taking it for n (docs/complexity.md gives the span that would tell them apart)."""
    scatter = corpus_scatter()["ta:true_total"]
    assert scatter == float(np.median(list(corpus_scatter().values())))
    picks = [
        choose(corpus_sizes(), synthetic("n log n", corpus_sizes(), scatter, s), resamples=1).chosen for s in range(400)
    ]
    assert 0.5 < picks.count("n log n") / 400 < 0.95
    assert picks.count("n") > picks.count("n^1.5")  # the confusion is with n


def test_no_rule_could_tell_n_log_n_from_n_better_at_the_scatter_of_ta():
    """Why the 95 % target cannot be met at TA's scatter: between two one-scale classes with normal noise of
    known sigma, the best possible rule (Neyman-Pearson: the likelihood ratio, once the scale is projected
    out) errs with probability Phi(-|d| / (2 sigma)), d the centred ln ln n over the sizes.  AIC's share of
    right picks on 4000 fresh n log n and n series equals that closed form (83.7 % at 0.83), so AIC is already
    as good as any rule here and the limit is the corpus's sizes, not the criterion."""
    from scipy.stats import norm

    from silcount.study.classes import aic

    sizes, scatter = corpus_sizes(), corpus_scatter()["ta:true_total"]
    d = np.log(np.log(sizes)) - np.log(np.log(sizes)).mean()
    bound = float(norm.cdf(np.linalg.norm(d) / (2 * scatter)))
    assert 0.80 < bound < 0.87
    lg = log_classes(np.log(sizes))
    rng = np.random.default_rng(3)
    for name in ("n", "n log n"):
        ly = lg[NAMES.index(name)] + scatter * rng.standard_normal((4000, sizes.size))
        right = float(np.mean(aic(lg[:, None, :], ly[None]).argmin(axis=0) == NAMES.index(name)))
        assert abs(right - bound) < 0.03  # binomial sd 0.006; the other seven classes take a little more


def test_the_corpus_fits_carry_the_class_of_their_points():
    from silcount.study.fits import power_fit

    n = np.geomspace(80, 86482, 8)
    fit = power_fit(n, 3.0 * n**2)
    assert fit["classes"]["chosen"] == "n^2" and fit["classes"]["criterion"] == "AIC"
    assert fit["classes"] == choose(n, 3.0 * n**2).as_dict()
    assert power_fit([10, 100, 10], [1, 2, 3])["classes"] is None  # two distinct sizes: no class
    assert power_fit([0.5, 10, 100], [1, 2, 3])["classes"] is None  # log 0.5 < 0: log n is no cost there


def test_the_o_verdict_shows_each_familys_class_and_keeps_its_outcome():
    """The complexity rule (docs/claims.md, rule 7) prints the class beside the exponent; the verdict and its
    grounds are those of the same exponents without a class."""
    from silcount.counting import models
    from silcount.papers.claims import HOLDS, inventory
    from silcount.papers.claims.context import Evidence
    from silcount.papers.growth import Exponent, measure_exponent

    faces = [20, 80, 320, 1280, 5120]  # reports/figures/growth.md: TA's true totals on the icosphere sweep
    typical = measure_exponent("ta", "true", faces, [1330, 6413, 37404, 241500, 1683750], "icosphere sweep (...)")
    witness_faces = [320, 1280, 5120, 20480]
    worst = measure_exponent("ta", "true", witness_faces, [3.0 * f**1.95 for f in witness_faces], "witness family 'w'")
    assert (typical.classes.chosen, worst.classes.chosen) == ("n log n", "n^2")
    bare = [Exponent(e.detector, e.cost_model, e.exponent, e.low, e.high, e.points, e.source) for e in (typical, worst)]
    entry = next(c for c in models.load("eesd2012-claims")["claims"] if c["id"] == "eesd-complexity-ta")
    with_class = inventory.complexity(entry, "eesd.txt", Evidence(exponents=(typical,), worst=(worst,)))
    without = inventory.complexity(entry, "eesd.txt", Evidence(exponents=(bare[0],), worst=(bare[1],)))
    assert with_class.verdict == without.verdict == HOLDS
    assert f"F^{typical.exponent:.2f} [{typical.low:.2f}, {typical.high:.2f}], class n log n (w " in with_class.measured
    assert "runner-up n^1.5" in with_class.measured
    assert "reached by the witness family 'w' (F^1.95 [1.95, 1.95], class n^2 (w " in with_class.reason
    assert "class" not in without.reason
