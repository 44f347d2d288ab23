"""Properties of the split-conformal quantile and the cross-conformal folds (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import conformal_quantile
from drillfatigue.surrogate.data import case_folds

scores_st = st.lists(st.floats(0.0, 1e3, allow_nan=False), min_size=1, max_size=200)


@settings(max_examples=40, deadline=None)
@given(scores=scores_st, c=st.floats(0.05, 0.99))
def test_calibration_set_itself_is_covered(scores: list[float], c: float) -> None:
    s = np.asarray(scores)
    q = conformal_quantile(s, c)
    if math.isinf(q):
        assert math.ceil((s.size + 1) * c) > s.size
    else:
        # at least ceil((n+1)c) of the n calibration scores are <= q
        assert np.sum(s <= q) >= math.ceil((s.size + 1) * c)
        assert q in s


@settings(max_examples=40, deadline=None)
@given(scores=scores_st, c1=st.floats(0.05, 0.99), c2=st.floats(0.05, 0.99))
def test_monotone_in_coverage(scores: list[float], c1: float, c2: float) -> None:
    lo, hi = sorted((c1, c2))
    assert conformal_quantile(np.asarray(scores), lo) <= conformal_quantile(np.asarray(scores), hi)


@settings(max_examples=30, deadline=None)
@given(scores=scores_st, c=st.floats(0.05, 0.99), perm_seed=st.integers(0, 2**31 - 1))
def test_invariant_to_order(scores: list[float], c: float, perm_seed: int) -> None:
    s = np.asarray(scores)
    p = np.random.default_rng(perm_seed).permutation(s)
    assert conformal_quantile(s, c) == conformal_quantile(p, c)


@settings(max_examples=40, deadline=None)
@given(case_of_row=st.lists(st.integers(0, 30), min_size=2, max_size=300),
       k=st.integers(2, 12), seed=st.integers(0, 2**31 - 1))
def test_cross_conformal_folds_hold_whole_cases(case_of_row: list[int], k: int,
                                                seed: int) -> None:
    groups = np.array([f"case{c:03d}" for c in case_of_row])
    n_cases = np.unique(groups).size
    if not 2 <= k <= n_cases:
        with pytest.raises(InputError, match="conformal_folds"):
            case_folds(groups, k, seed)
        return
    folds = case_folds(groups, k, seed)
    assert folds.shape == groups.shape and set(folds) == set(range(k))
    # no case on both sides of any fold: one fold per case
    per_case = pd.Series(folds).groupby(groups).nunique()
    assert (per_case == 1).all()
    # the folds' case counts differ by at most one
    cases_per_fold = pd.Series(groups).groupby(folds).nunique()
    assert cases_per_fold.max() - cases_per_fold.min() <= 1
    # seeded: the same folds again, whatever the order of the rows
    np.testing.assert_array_equal(case_folds(groups, k, seed), folds)
    perm = np.random.default_rng(seed).permutation(groups.size)
    np.testing.assert_array_equal(case_folds(groups[perm], k, seed), folds[perm])
