"""The served gradient boosting's training cases and its cross-conformal calibration by case."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config.base import validate
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import mondrian_half_width
from drillfatigue.surrogate.data import Split, gbm_rows
from drillfatigue.surrogate.served_gbm import (SCALE_ATTRIBUTE, fit_served_gbm, half_width,
                                               interval_bins, interval_scale)

COVERAGE = 0.9


def _grouped(n_cases: int, rows: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Heteroscedastic grouped data: the case's level x0 sets the rate and its spread.

    y = 3 x0 + 0.5 x1 + (0.05 + 0.5 x0^2) (case effect + row noise), the case
    effect N(0, 0.5^2) shared by the case's rows, the row noise N(0, 1); x0 is
    drawn per case, x1 per row. The residual spread grows 11-fold across the
    range of the prediction (0..3.5 decades), and rows of a case share part of
    it, so the exchangeable unit is the case.
    """
    rng = np.random.default_rng(seed)
    x0 = np.repeat(rng.uniform(0.0, 1.0, n_cases), rows)
    x1 = rng.uniform(0.0, 1.0, n_cases * rows)
    case = np.repeat(rng.normal(0.0, 0.5, n_cases), rows)
    y = 3.0 * x0 + 0.5 * x1 + (0.05 + 0.5 * x0**2) * (case + rng.normal(0.0, 1.0, x0.size))
    groups = np.repeat([f"c{seed}_{i:04d}" for i in range(n_cases)], rows)
    return np.column_stack([x0, x1]), y, groups


CFG = SurrogateConfig(hgb_max_iter=100, censoring="none", conformal_bin_min_rows=50,
                      conformal_folds=5, coverage=COVERAGE, gbm_interval="per_decade")
N_CASES, ROWS = 100, 10


def _decade_coverage(model, meta, x, y, groups) -> tuple[np.ndarray, np.ndarray]:
    """Coverage and number of cases per unit bin 0..3 of the served prediction."""
    mu = model.predict(x)
    half = mondrian_half_width(mu, np.asarray(meta["conformal_bins_log10"]),
                               np.asarray(meta["conformal_half_widths"]))
    d = np.clip(np.floor(mu), 0, 3)
    ok = np.abs(y - mu) <= half
    return (np.array([ok[d == k].mean() for k in range(4)]),
            np.array([np.unique(groups[d == k]).size for k in range(4)]))


def test_cross_conformal_covers_each_bin_where_split_with_few_cases_is_noisier() -> None:
    # 100 training cases x 10 rows; the split variant trains on 60 cases and
    # calibrates on 20 (the 60/20/20 split), the cross variant trains on all 100
    # and calibrates on their out-of-fold residuals; both scored on 300 new cases
    x_new, y_new, g_new = _grouped(300, ROWS, seed=99)
    case_idx = np.repeat(np.arange(N_CASES), ROWS)
    train, cal = case_idx < 60, (case_idx >= 60) & (case_idx < 80)
    dev_cross, dev_split = [], []
    for r in range(5):
        x, y, g = _grouped(N_CASES, ROWS, seed=r)
        cross, m_c = fit_served_gbm(x, y, g, np.ones(y.size, bool), None, CFG)
        split, m_s = fit_served_gbm(x, y, g, train, cal,
                                    CFG.model_copy(update={"gbm_calibration": "split"}))
        assert m_c["calibration"] == "cross" and m_c["n_calibration_cases"] == N_CASES
        assert m_c["n_calibration_rows"] == N_CASES * ROWS
        assert len(m_c["train_cases"]) == N_CASES and m_c["conformal_folds"] == 5
        assert m_s["calibration"] == "split" and m_s["n_calibration_cases"] == 20
        assert len(m_c["conformal_half_widths"]) >= 3  # several bins: heteroscedastic
        cov, n_new = _decade_coverage(cross, m_c, x_new, y_new, g_new)
        _, n_cal = _decade_coverage(cross, m_c, x, y, g)
        # Tolerance: a bin's coverage differs from nominal by the scatter of its
        # calibration quantile and of the new rows' coverage; rows of a case share
        # part of its error, so counting cases as the units (binomial variance
        # c (1 - c) / cases on each side) bounds the scatter from above. 3 sigma.
        sigma = np.sqrt(COVERAGE * (1 - COVERAGE) * (1.0 / n_cal + 1.0 / n_new))
        assert np.all(np.abs(cov - COVERAGE) <= 3.0 * sigma), (r, cov, sigma)
        dev_cross.extend(cov - COVERAGE)
        dev_split.extend(_decade_coverage(split, m_s, x_new, y_new, g_new)[0] - COVERAGE)
    rms_cross = math.sqrt(np.mean(np.square(dev_cross)))
    rms_split = math.sqrt(np.mean(np.square(dev_split)))
    # measured: 0.036 against 0.072 (6 repeats); 20 calibration cases against 100
    # give the split bins fewer rows (merged to 2-3 bins) and more scatter
    assert rms_split > 1.4 * rms_cross, (rms_split, rms_cross)
    assert abs(np.mean(dev_cross)) < 0.02  # no bias beyond the scatter of 5 x 4 bins


def test_cross_conformal_is_seeded() -> None:
    x, y, g = _grouped(30, ROWS, seed=5)
    every = np.ones(y.size, bool)
    m1, a = fit_served_gbm(x, y, g, every, None, CFG)
    m2, b = fit_served_gbm(x, y, g, every, None, CFG)
    assert a == b
    np.testing.assert_array_equal(m1.predict(x), m2.predict(x))
    # another seed deals other folds: other out-of-fold residuals, same served model
    m3, c = fit_served_gbm(x, y, g, every, None, CFG.model_copy(update={"split_seed": 1}))
    assert c["conformal_half_widths"] != a["conformal_half_widths"] or \
        c["conformal_quantile"] != a["conformal_quantile"]


def test_split_calibration_refuses_rows_it_trained_on() -> None:
    x, y, g = _grouped(20, 5, seed=1)
    every = np.ones(y.size, bool)
    with pytest.raises(InputError, match="shared with the training rows"):
        fit_served_gbm(x, y, g, every, every, CFG.model_copy(update={"gbm_calibration": "split"}))
    # 2 cases, 5 folds asked: cross-conformal on 2 folds, one case each
    cfg = CFG.model_copy(update={"conformal_bin_min_rows": 10})
    assert fit_served_gbm(x[:10], y[:10], g[:10], every[:10], None, cfg)[1][
        "conformal_folds"] == 2


def test_cross_calibration_takes_at_most_one_fold_per_case() -> None:
    # 12 cases of 10 rows with 20 folds asked: 12 folds of one case each, recorded
    x, y, g = _grouped(12, 10, seed=3)
    every = np.ones(y.size, bool)
    cfg = CFG.model_copy(update={"conformal_folds": 20, "conformal_bin_min_rows": 10})
    _, meta = fit_served_gbm(x, y, g, every, None, cfg)
    assert meta["calibration"] == "cross" and meta["conformal_folds"] == 12


def test_gbm_rows_follow_calibration_and_heldout() -> None:
    tr = np.array([1, 1, 0, 0, 0, 0], bool)
    ca = np.array([0, 0, 1, 1, 0, 0], bool)
    te = np.array([0, 0, 0, 0, 1, 1], bool)
    sp = Split(train=tr, calibration=ca, test=te)
    fit, cal = gbm_rows(sp, CFG, heldout=True)
    assert fit.all() and cal is None  # cross, held-out design: every case trains
    fit, cal = gbm_rows(sp, CFG, heldout=False)
    np.testing.assert_array_equal(fit, tr | ca)  # its own test cases are scored
    assert cal is None
    split = CFG.model_copy(update={"gbm_calibration": "split"})
    fit, cal = gbm_rows(sp, split, heldout=True)
    np.testing.assert_array_equal(fit, tr | te)
    np.testing.assert_array_equal(cal, ca)
    fit, cal = gbm_rows(sp, split.model_copy(update={"gbm_cases": "train"}), heldout=True)
    np.testing.assert_array_equal(fit, tr)
    np.testing.assert_array_equal(cal, ca)


@pytest.mark.parametrize(("key", "value", "allowed"), [
    ("conformal_folds", 1, "greater than or equal to 2"),
    ("conformal_folds", 101, "less than or equal to 100"),
    ("gbm_calibration", "jackknife", "'cross' or 'split'"),
    ("gbm_cases", "all", "'free' or 'train'"),
])
def test_config_refuses_bad_calibration_settings(key: str, value: object, allowed: str) -> None:
    with pytest.raises(InputError) as exc:
        validate(SurrogateConfig, {key: value}, "surrogate")
    line = exc.value.one_line()
    assert line.startswith(f"surrogate.{key}: ") and "\n" not in line
    assert allowed in line, line


def _regional(n_cases: int, rows: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grouped data whose error size is set by an input that barely moves the prediction.

    y = 2 x0 + 0.1 x1 + s(x1) (case effect N(0, 0.5^2) + row noise N(0, 1)),
    s = 0.15 below x1 = 0.5 and 0.6 above (x0, x1 drawn per case): like the
    drill string's rpm, which moves the damage rate little but decides
    whether the string may settle in partial stick-slip, where the errors are
    several times larger. A width per bin of the prediction cannot see x1.
    """
    rng = np.random.default_rng(seed)
    x0 = np.repeat(rng.uniform(0.0, 1.0, n_cases), rows)
    x1 = np.repeat(rng.uniform(0.0, 1.0, n_cases), rows)
    case = np.repeat(rng.normal(0.0, 0.5, n_cases), rows)
    s = np.where(x1 > 0.5, 0.6, 0.15)
    y = 2.0 * x0 + 0.1 * x1 + s * (case + rng.normal(0.0, 1.0, x0.size))
    groups = np.repeat([f"r{seed}_{i:04d}" for i in range(n_cases)], rows)
    return np.column_stack([x0, x1]), y, groups


def test_scaled_interval_follows_the_error_where_the_decade_bins_cannot() -> None:
    # 200 training cases x 10 rows; scored on 400 new cases (~2000 rows per region):
    # the per-decade width over-covers the quiet half and under-covers the noisy one;
    # the scaled width covers both near the nominal 0.9, and is narrower on average
    x, y, g = _regional(200, ROWS, seed=3)
    x_new, y_new, _ = _regional(400, ROWS, seed=77)
    every = np.ones(y.size, dtype=bool)
    noisy = x_new[:, 1] > 0.5
    out = {}
    for kind in ("per_decade", "scaled"):
        cfg = CFG.model_copy(update={"gbm_interval": kind})
        model, meta = fit_served_gbm(x, y, g, every, None, cfg)
        assert meta["interval"] == kind
        mu = model.predict(x_new)
        half = half_width(mu, meta, interval_bins(meta), interval_scale(model, x_new))
        ok = np.abs(y_new - mu) <= half
        out[kind] = (ok[~noisy].mean(), ok[noisy].mean(), float(np.mean(half)))
    quiet_d, noisy_d, _ = out["per_decade"]
    quiet_s, noisy_s, _ = out["scaled"]
    # tolerance 0.05: ~200 cases per region, the case effect shared by its 10 rows
    # (standard error of a coverage ~0.02)
    assert quiet_d > 0.97 and noisy_d < 0.85
    assert abs(quiet_s - COVERAGE) < 0.05 and abs(noisy_s - COVERAGE) < 0.05
    assert out["scaled"][2] < out["per_decade"][2]


def test_scaled_interval_needs_its_scale_and_travels_with_the_model() -> None:
    import pickle

    x, y, g = _regional(40, ROWS, seed=5)
    every = np.ones(y.size, dtype=bool)
    model, meta = fit_served_gbm(x, y, g, every, None,
                                 CFG.model_copy(update={"gbm_interval": "scaled"}))
    with pytest.raises(ValueError, match="scale"):
        half_width(model.predict(x), meta, interval_bins(meta))
    again = pickle.loads(pickle.dumps(model))
    np.testing.assert_array_equal(interval_scale(again, x), interval_scale(model, x))
    assert np.all(interval_scale(model, x) > 0.0)
    # per_decade and constant models carry no scale model
    plain, _ = fit_served_gbm(x, y, g, every, None, CFG)
    assert not hasattr(plain, SCALE_ATTRIBUTE) and interval_scale(plain, x) is None


def test_scaled_interval_keeps_the_global_width_beyond_the_horizon() -> None:
    # rows predicted beyond the horizon answer "longer than": their calibration rows are
    # mostly censored with a zero residual, so their width is the one global quantile
    x, y, g = _regional(60, ROWS, seed=8)
    every = np.ones(y.size, dtype=bool)
    cfg = CFG.model_copy(update={"gbm_interval": "scaled", "censoring": "likelihood",
                                 "horizon_h": 10.0 ** -0.5})
    model, meta = fit_served_gbm(x, y, g, every, None, cfg)
    mu = model.predict(x)
    half = half_width(mu, meta, interval_bins(meta), interval_scale(model, x))
    beyond = mu < 0.5
    assert beyond.any() and (~beyond).any()
    np.testing.assert_array_equal(half[beyond], meta["conformal_quantile"])
    assert np.ptp(half[~beyond]) > 0.0
