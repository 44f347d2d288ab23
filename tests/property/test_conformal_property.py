"""Properties of the split-conformal quantile (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.surrogate.conformal import conformal_quantile

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
