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
