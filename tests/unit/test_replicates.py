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
