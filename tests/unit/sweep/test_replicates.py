"""Noise-floor statistics of the replicates study and its case generation."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from drillfatigue.config.replicates import ReplicatesConfig
from drillfatigue.errors import InputError
from drillfatigue.sweep.design import case_id_of
from drillfatigue.metrics import decade_label, factor2_by_decade
from drillfatigue.sweep.replicates import FACTOR2_DECADES, replicate_cases, replicate_spread


def _table(y: np.ndarray) -> pd.DataFrame:
    """Rows of y[g, k] (group g, replicate k) as a replicate table; 3 groups per case."""
    n_groups, k = y.shape
    g, r = np.meshgrid(np.arange(n_groups), np.arange(k), indexing="ij")
    g, r = g.ravel(), r.ravel()
    return pd.DataFrame({"base_case_id": [f"c{i // 3}" for i in g], "joint": g % 3,
                         "location": "body", "replicate": r,
                         "damage_rate_per_h": 10.0 ** y.ravel()})


def test_gaussian_noise_recovers_sigma_and_factor2_ceiling():
    # 3000 groups x 4 replicates around group means spread over 6 decades, noise
    # sigma 0.2: 9000 degrees of freedom give a relative standard error of sigma of
    # 1/sqrt(2 * 9000) = 0.75 %; tolerance 3 % (4 standard errors). The factor-2
    # ceiling is P(|N(0, 0.2)| < log10 2) = 0.867; its estimate from 12000 rows
    # has a standard error below 0.004; tolerance 0.015.
    rng = np.random.default_rng(1)
    sigma = 0.2
    means = rng.uniform(-8.0, -2.0, size=(3000, 1))
    y = means + rng.normal(0.0, sigma, size=(3000, 4))
    out = replicate_spread(_table(y), floor_per_h=1e-12)
    assert out["sigma_log10"] == pytest.approx(sigma, rel=0.03)
    expected = 2.0 * stats.norm.cdf(FACTOR2_DECADES / sigma) - 1.0
    assert out["ceiling_factor2_fraction"] == pytest.approx(expected, abs=0.015)
    assert out["ceiling_r2"] == pytest.approx(1.0 - out["sigma_log10"] ** 2 / np.var(y, ddof=1),
                                              abs=1e-12)
    assert out["n_groups"] == 3000 and out["n_rows"] == 12000 and out["n_cases"] == 1000
    assert out["max_case_sigma_log10"] >= out["sigma_log10"]


def test_ceiling_by_decade_separates_noisy_and_quiet_decades():
    # groups in decade 1e-07 carry noise sigma 0.4, groups in 1e-03 none: the
    # per-decade ceilings are P(|N(0, 0.4)| < log10 2) = 0.547 and exactly 1,
    # while the pooled ceiling mixes them. 2000 groups x 4 replicates per decade:
    # standard error of the noisy fraction < 0.006, tolerance 0.025.
    rng = np.random.default_rng(7)
    noisy = rng.uniform(-6.9, -6.1, size=(2000, 1)) + rng.normal(0.0, 0.4, size=(2000, 4))
    quiet = np.repeat(rng.uniform(-2.9, -2.1, size=(2000, 1)), 4, axis=1)
    out = replicate_spread(_table(np.vstack([noisy, quiet])), floor_per_h=1e-12)
    by = out["ceiling_factor2_by_decade"]
    assert by["1e-03"] == {"n": 8000, "factor2_fraction": 1.0}
    expected = 2.0 * stats.norm.cdf(FACTOR2_DECADES / 0.4) - 1.0
    assert by["1e-07"]["factor2_fraction"] == pytest.approx(expected, abs=0.025)
    # a group is binned by its mean, whose noise has sd 0.4 / sqrt(4) = 0.2: about
    # 10 % of the noisy groups (uniform in [-6.9, -6.1]) fall into 1e-08 or 1e-06
    assert sum(v["n"] for v in by.values()) == 16000
    assert by["1e-07"]["n"] >= 6800 and set(by) <= {"1e-08", "1e-07", "1e-06", "1e-03"}
    assert list(by) == sorted(by, key=float)


def test_factor2_by_decade_by_hand():
    y = np.array([-5.5, -5.0, -4.2, -4.9, -3.0, -12.0])
    err = np.array([0.1, -0.5, 0.0, 0.31, -0.29, 2.0])
    out = factor2_by_decade(y, err)
    # decades: -5.5 -> 1e-06; -5.0, -4.9 -> 1e-05; -4.2 -> 1e-05; -3.0 -> 1e-03; floor -> 1e-12
    assert list(out) == ["1e-12", "1e-06", "1e-05", "1e-03"]
    assert out["1e-06"] == {"n": 1, "factor2_fraction": 1.0}
    assert out["1e-05"]["n"] == 3 and out["1e-05"]["factor2_fraction"] == pytest.approx(1 / 3)
    assert out["1e-03"] == {"n": 1, "factor2_fraction": 1.0}  # 0.29 < log10 2 = 0.301
    assert out["1e-12"]["factor2_fraction"] == 0.0
    assert decade_label(np.log10(np.array([1e-3, 9.99e-4])))[0] == "1e-03"
    assert factor2_by_decade(np.array([]), np.array([])) == {}
    with pytest.raises(ValueError, match="shape"):
        factor2_by_decade(y, err[:2])


def test_unequal_replicate_counts_pool_by_degrees_of_freedom():
    # group A: 2 replicates (1 dof), group B: 3 replicates (2 dof); pooled variance
    # = (SS_A + SS_B) / 3, by hand.
    frame = pd.DataFrame({"base_case_id": ["a", "a", "b", "b", "b", "c"],
                          "joint": [0, 0, 0, 0, 0, 0], "location": "body",
                          "replicate": [0, 1, 0, 1, 2, 0],
                          "damage_rate_per_h": 10.0 ** np.array([-5.0, -4.0, -6.0, -6.5, -7.0, -3.0])})
    out = replicate_spread(frame, floor_per_h=1e-12)
    ss = 2 * 0.5**2 + (0.5**2 + 0.0 + 0.5**2)
    assert out["sigma_log10"] == pytest.approx(math.sqrt(ss / 3.0), rel=1e-12)
    assert out["n_groups"] == 2 and out["n_rows"] == 5  # the single run of case c is ignored
    assert out["case_sigma_log10"]["a"] == pytest.approx(0.5 * math.sqrt(2.0), rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-10.0, 0.0), min_size=1, max_size=20), st.integers(2, 6))
def test_identical_replicates_have_no_spread(levels, k):
    y = np.repeat(np.asarray(levels)[:, None], k, axis=1)
    out = replicate_spread(_table(y), floor_per_h=1e-12)
    assert out["sigma_log10"] == pytest.approx(0.0, abs=1e-9)
    assert out["ceiling_factor2_fraction"] == 1.0


def test_zero_rates_are_censored_at_the_floor():
    frame = pd.DataFrame({"base_case_id": "a", "joint": 0, "location": "body",
                          "replicate": [0, 1], "damage_rate_per_h": [0.0, 1e-12]})
    out = replicate_spread(frame, floor_per_h=1e-12)
    assert out["sigma_log10"] == 0.0


def test_missing_column_is_an_input_error():
    with pytest.raises(InputError, match="replicate"):
        replicate_spread(pd.DataFrame({"base_case_id": ["a"]}), floor_per_h=1e-12)


def _cases() -> pd.DataFrame:
    rows = []
    for i, rpm in enumerate([150.0, 90.0, 120.0]):
        case = {"operation": {"rpm": rpm, "rop_m_per_s": 0.005}, "well": {"profile": "p1"}}
        rows.append({"case_id": case_id_of(case), "design_index": 2 - i,
                     "case_json": json.dumps(case)})
    return pd.DataFrame(rows)


def test_replicate_cases_scale_the_variable_of_the_first_design_rows():
    cfg = ReplicatesConfig(n_cases=2, n_replicates=3, rel_step=1e-3)
    reps = replicate_cases(_cases(), cfg)
    # design_index 0 and 1 are the rpm 120 and 90 cases
    assert len(reps) == 4 and reps["replicate"].tolist() == [1, 2, 1, 2]
    np.testing.assert_allclose(reps["value"], [120.0 * 1.001, 120.0 * 1.002, 90.0 * 1.001,
                                               90.0 * 1.002], rtol=1e-15)
    for text, value, cid in zip(reps["case_json"], reps["value"], reps["case_id"], strict=True):
        case = json.loads(text)
        assert case["operation"]["rpm"] == value and case["operation"]["rop_m_per_s"] == 0.005
        assert case_id_of(case) == cid
    assert reps["case_id"].nunique() == 4
    assert not set(reps["case_id"]) & set(_cases()["case_id"])


@pytest.mark.parametrize("variable", ["operation.nope", "well.profile"])
def test_replicate_cases_reject_a_missing_or_non_numeric_field(variable):
    with pytest.raises(InputError) as err:
        replicate_cases(_cases(), ReplicatesConfig(n_cases=1, variable=variable))
    assert err.value.field == "replicates.variable"


def test_config_bounds_are_named():
    from drillfatigue.config import validate

    with pytest.raises(InputError) as err:
        validate(ReplicatesConfig, {"n_replicates": 1}, "replicates")
    assert err.value.field == "replicates.n_replicates" and ">= 2" in err.value.one_line()


def test_symmetric_replicates_alternate_about_the_design_value():
    cfg = ReplicatesConfig(n_cases=1, n_replicates=5, rel_step=1e-2, symmetric=True)
    reps = replicate_cases(_cases(), cfg)
    np.testing.assert_allclose(reps["value"], [120.0 * 1.01, 120.0 * 0.99, 120.0 * 1.02,
                                               120.0 * 0.98], rtol=1e-15)
    # the design value and its draws centre on it: their mean is the design value
    assert math.isclose((120.0 + reps["value"].sum()) / 5, 120.0, rel_tol=1e-14)


@given(st.integers(1, 200))
def test_step_multiples(k):
    from drillfatigue.sweep.replicates import step_multiple

    assert step_multiple(k, False) == k
    m = step_multiple(k, True)
    assert abs(m) == (k + 1) // 2 and (m > 0) == (k % 2 == 1)


def test_symmetric_replicates_keep_the_sign_of_the_field():
    from drillfatigue.config import validate

    with pytest.raises(InputError) as err:
        validate(ReplicatesConfig, {"n_replicates": 41, "rel_step": 0.05, "symmetric": True},
                 "replicates")
    assert "sign" in err.value.one_line()
    assert validate(ReplicatesConfig, {"n_replicates": 41, "rel_step": 0.04,
                                       "symmetric": True}, "replicates").symmetric
