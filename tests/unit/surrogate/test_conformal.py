"""Split conformal calibration: finite-sample quantile and coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import (
    SplitConformal,
    conformal_quantile,
    mondrian_bins,
    mondrian_half_width,
)


def test_quantile_uses_finite_sample_rank() -> None:
    scores = np.arange(1.0, 11.0)  # 1..10
    # n = 10, c = 0.9: k = ceil(11 * 0.9) = 10 -> the largest score
    assert conformal_quantile(scores, 0.9) == 10.0
    # c = 0.5: k = ceil(5.5) = 6
    assert conformal_quantile(scores[::-1], 0.5) == 6.0
    # c = 0.95 needs k = 11 > n: unbounded interval
    assert math.isinf(conformal_quantile(scores, 0.95))


def test_quantile_rejects_bad_input() -> None:
    with pytest.raises(InputError):
        conformal_quantile(np.array([]), 0.9)
    with pytest.raises(InputError):
        conformal_quantile(np.array([1.0, np.nan]), 0.9)
    with pytest.raises(InputError):
        conformal_quantile(np.ones(5), 1.0)


def test_coverage_on_held_out_heteroscedastic_data() -> None:
    # y = mu + sigma_true * t(5) noise, predicted sigma off by a smooth factor:
    # normalised scores are still exchangeable, so coverage must hold.
    rng = np.random.default_rng(42)
    n_cal, n_test, c = 2000, 20000, 0.90

    def draw(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x = rng.uniform(0, 1, n)
        mu = np.sin(6 * x)
        sigma_true = 0.05 + 0.3 * x
        y = mu + sigma_true * rng.standard_t(5, n)
        return mu, sigma_true * (0.7 + 0.6 * x), y

    conf = SplitConformal(c).fit(*draw(n_cal))
    mu, sd, y = draw(n_test)
    lo, hi = conf.interval(mu, sd)
    cov = np.mean((y >= lo) & (y <= hi))
    # coverage given the calibration set is Beta(k, n_cal + 1 - k): std
    # sqrt(c(1-c)/n_cal) = 0.0067; test-set binomial std sqrt(c(1-c)/n_test) =
    # 0.0021; 4 combined standard errors = 0.028
    tol = 4.0 * math.sqrt(c * (1 - c) * (1 / n_cal + 1 / n_test))
    assert abs(cov - c) <= tol
    assert conf.n_calibration_ == n_cal


def test_non_positive_sigma_rejected() -> None:
    with pytest.raises(InputError):
        SplitConformal().fit(np.zeros(3), np.array([1.0, 0.0, 1.0]), np.zeros(3))


def test_censored_rows_covered_when_the_interval_reaches_their_level() -> None:
    # censored at c = -5: the truth is only "<= -5". Row 0 (mu -6) is covered by
    # any interval (score 0); row 1 (mu -4, sigma 0.5) needs mu - q sigma <= -5,
    # q >= 2; the uncensored row 2 keeps |y - mu| / sigma = 1.
    conf = SplitConformal(0.5).fit(np.array([-6.0, -4.0, -3.0]), np.array([1.0, 0.5, 1.0]),
                                   np.array([-12.0, -12.0, -2.0]), censor_below=-5.0)
    # n = 3, c = 0.5: k = ceil(2) = 2 -> sorted scores (0, 1, 2) -> 1
    assert conf.quantile_ == 1.0
    conf = SplitConformal(0.7).fit(np.array([-6.0, -4.0, -3.0]), np.array([1.0, 0.5, 1.0]),
                                   np.array([-12.0, -12.0, -2.0]), censor_below=-5.0)
    assert conf.quantile_ == 2.0  # k = ceil(2.8) = 3: the censored row 1 sets it


def test_censored_coverage_holds_on_exchangeable_data() -> None:
    # y ~ N(0, 1) censored at 0.5 (about 69 % censored); predictor mu = 0, sigma = 1:
    # the calibrated interval covers a fresh draw (censored: reaches 0.5) 90 % of the time
    rng = np.random.default_rng(3)
    y_cal, y_new = rng.normal(size=2000), rng.normal(size=20000)
    conf = SplitConformal(0.9).fit(np.zeros(2000), np.ones(2000), y_cal, censor_below=0.5)
    lo, hi = conf.interval(np.zeros(20000), np.ones(20000))
    covered = np.where(y_new <= 0.5, lo <= 0.5, (lo <= y_new) & (y_new <= hi))
    # binomial std of the coverage at n = 20000 is 0.002, the calibration
    # quantile's own spread (n = 2000) about 0.007: 0.02 is ~3 sigma
    assert abs(covered.mean() - 0.9) <= 0.02


def _decades(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Predicted log10 rate over 8 decades, noise sd growing as the rate falls.

    The prediction is unbiased; the residual sd is 0.05 decades at 1 per h and
    1.25 decades at 1e-8 per h (long lives: the gbm's residuals on the
    research-scale dataset grow the same way).
    """
    mu = rng.uniform(-8.0, 0.0, n)
    return mu, mu + (0.05 - 0.15 * mu) * rng.standard_normal(n)


def test_mondrian_covers_every_decade_where_one_width_does_not() -> None:
    rng = np.random.default_rng(7)
    c, n_cal, n_test = 0.90, 4000, 40000
    mu_c, y_c = _decades(n_cal, rng)
    edges, half = mondrian_bins(mu_c, y_c, c, min_rows=50)
    np.testing.assert_array_equal(edges, np.arange(-7.0, 0.0))  # 500 rows a decade: no merge
    q = conformal_quantile(np.abs(y_c - mu_c), c)
    mu, y = _decades(n_test, rng)
    w = mondrian_half_width(mu, edges, half)
    b = np.searchsorted(edges, mu, side="right")
    bc = np.searchsorted(edges, mu_c, side="right")
    const_miss = 0
    for k in range(edges.size + 1):
        n_k, m_k = int(np.sum(bc == k)), int(np.sum(b == k))
        # the bin's coverage given its calibration rows is Beta with sd
        # sqrt(c(1-c)/n_k); the test rows add a binomial sd sqrt(c(1-c)/m_k):
        # 3 combined sd = 0.042 for 500 + 5000 rows
        tol = 3.0 * math.sqrt(c * (1 - c) * (1 / n_k + 1 / m_k))
        sel = b == k
        cov = np.mean(np.abs(y[sel] - mu[sel]) <= w[sel])
        assert abs(cov - c) <= tol, (k, cov, tol)
        const_miss += abs(np.mean(np.abs(y[sel] - mu[sel]) <= q) - c) > tol
    # the one global width over-covers the precise decades and under-covers the noisy ones
    assert const_miss >= 4
    sel_low, sel_high = b == 0, b == edges.size
    assert np.mean(np.abs(y[sel_low] - mu[sel_low]) <= q) < c - 0.15
    assert np.mean(np.abs(y[sel_high] - mu[sel_high]) <= q) > c + 0.05


def test_mondrian_bins_merge_until_min_rows() -> None:
    # rows per decade -3..1: 5, 100, 3, 100, 20 (min 50). The smallest bin merges
    # into its smaller neighbour (the lower on a tie): 3 -> [-2, 0), then 5 ->
    # [-3, 0), then 20 -> [0, 2): two bins of 108 and 120 rows split at 0.
    counts = {-3: 5, -2: 100, -1: 3, 0: 100, 1: 20}
    mu = np.concatenate([d + (np.arange(n) + 0.5) / n for d, n in counts.items()])
    y = mu + np.where(mu < 0.0, 0.5, 0.1) * np.cos(np.arange(mu.size))
    edges, half = mondrian_bins(mu, y, 0.9, min_rows=50)
    np.testing.assert_array_equal(edges, [0.0])
    np.testing.assert_array_equal(np.bincount(np.searchsorted(edges, mu, side="right")),
                                  [108, 120])
    for k, sel in enumerate((mu < 0.0, mu >= 0.0)):
        assert half[k] == conformal_quantile(np.abs(y - mu)[sel], 0.9)
    # fewer rows than min_rows: one bin, the global quantile
    e1, h1 = mondrian_bins(mu, y, 0.9, min_rows=500)
    assert e1.size == 0 and h1[0] == conformal_quantile(np.abs(y - mu), 0.9)
    # beyond the outer edges: the outer bins
    np.testing.assert_array_equal(mondrian_half_width(np.array([-30.0, 30.0]), edges, half), half)
    with pytest.raises(InputError, match="min_rows"):
        mondrian_bins(mu, y, 0.9, min_rows=8)  # 8 rows: ceil(0.9 * 9) = 9 > 8


def test_mondrian_censored_rows_and_the_bin_below_the_level() -> None:
    rng = np.random.default_rng(3)
    mu = rng.uniform(-8.0, 0.0, 2000)
    y = mu + 0.3 * rng.standard_normal(2000)
    level = -5.0
    yc = np.where(y <= level, level, y)  # censored at the level
    edges, half = mondrian_bins(mu, yc, 0.9, min_rows=50, censor_below=level)
    np.testing.assert_array_equal(edges, [-5.0, -4.0, -3.0, -2.0, -1.0])
    # scores as SplitConformal: a censored row is covered once the interval reaches the level
    s = np.abs(yc - mu)
    cens = yc <= level
    s[cens] = np.maximum(mu[cens] - level, 0.0)
    # below the level: the global width, not the (zero) quantile of mostly censored rows
    assert half[0] == SplitConformal(0.9).fit(mu, np.ones_like(mu), yc, censor_below=level).quantile_
    assert half[0] == conformal_quantile(s, 0.9) > 0.0
    assert conformal_quantile(s[mu < level], 0.9) == 0.0
    top = mu >= -1.0
    assert half[-1] == conformal_quantile(s[top], 0.9)
    # fewer than min_rows predictions at or above the level: one bin, the global width
    few = (mu < level) | (np.arange(mu.size) < 40)
    e1, h1 = mondrian_bins(mu[few], yc[few], 0.9, min_rows=50, censor_below=level)
    assert e1.size == 0 and h1[0] == conformal_quantile(s[few], 0.9)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-12.0, 3.0, allow_nan=False), min_size=1, max_size=300),
       st.integers(9, 80), st.sampled_from([None, -5.0]))
def test_mondrian_bins_property(mus: list[float], min_rows: int, level: float | None) -> None:
    mu = np.asarray(mus)
    y = mu + np.sin(7.0 * mu)
    try:
        edges, half = mondrian_bins(mu, y, 0.9, min_rows=min_rows, censor_below=level)
    except InputError:
        # only a single bin of too few rows for a finite quantile is refused
        assert mu.size < 9
        return
    assert half.shape == (edges.size + 1,) and np.all(np.diff(edges) > 0)
    b = np.searchsorted(edges, mu, side="right")
    counts = np.bincount(b, minlength=half.size)
    binned = counts if level is None or edges.size == 0 or edges[0] != level else counts[1:]
    if binned.size > 1:
        assert binned.min() >= min_rows
    assert np.all(np.isfinite(half)) or mu.size < 9
    np.testing.assert_array_equal(mondrian_half_width(mu, edges, half), half[b])


def test_mondrian_bins_of_normalised_scores_are_multipliers_of_the_scale() -> None:
    # a constant scale c divides every score by c: the same bins, half-widths / c;
    # a row's scale must be finite and positive
    rng = np.random.default_rng(4)
    mu = rng.uniform(-5.0, 0.0, 2000)
    y = mu + rng.normal(0.0, 0.3, mu.size)
    edges, half = mondrian_bins(mu, y, 0.9, 50, censor_below=-5.0)
    e2, h2 = mondrian_bins(mu, y, 0.9, 50, censor_below=-5.0, scale=np.full(mu.size, 2.0))
    np.testing.assert_array_equal(e2, edges)
    np.testing.assert_allclose(h2, half / 2.0, rtol=1e-12)
    for bad in (np.zeros(mu.size), np.full(mu.size, np.nan), np.ones(3)):
        with pytest.raises(InputError, match="scale"):
            mondrian_bins(mu, y, 0.9, 50, scale=bad)
