"""Split conformal calibration: finite-sample quantile and coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import SplitConformal, conformal_quantile


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
