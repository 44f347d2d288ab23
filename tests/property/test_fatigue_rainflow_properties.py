"""Hypothesis invariants of counting and Miner damage (fatigue)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from drillfatigue.fatigue.rainflow import RainflowStream, find_cycles, find_exact_reversals
from drillfatigue.fatigue.sn import get_curve

CURVE = get_curve("D")  # bi-linear: the knee makes 1/N non-convex, a harder case


def damage(y: np.ndarray, residue: str = "half") -> float:
    c = find_cycles(y, residue)
    return float(np.sum(c.count / CURVE.cycles_to_failure(c.ranges)))


signals = st.lists(st.floats(-400e6, 400e6, allow_nan=False), min_size=5, max_size=200).map(
    np.array)


@settings(max_examples=40, deadline=None)
@given(y=signals, where=st.floats(0.0, 1.0), frac=st.floats(0.05, 0.95))
# a reversal whose neighbouring differences multiply below the smallest double (the
# turn test once took their product, which underflowed to -0.0 and lost the reversal)
@example(y=np.array([2.0, 0.0, -1.7317028894306911e-171, 0.0, -1.0]), where=0.0, frac=0.5)
def test_inserting_a_cycle_never_decreases_damage(y: np.ndarray, where: float,
                                                  frac: float) -> None:
    rev, idx = find_exact_reversals(y)
    assume(rev.size >= 3)  # an interior reversal is needed
    k = 1 + int(where * (rev.size - 3))  # an interior reversal
    h = frac * min(abs(rev[k] - rev[k - 1]), abs(rev[k + 1] - rev[k]))
    back = rev[k] - np.sign(rev[k] - rev[k - 1]) * h  # small excursion inside both ranges
    y2 = np.insert(y, idx[k] + 1, [back, rev[k]])
    d1, d2 = damage(y), damage(y2)
    extra = 1.0 / CURVE.cycles_to_failure(h)[0]
    # never decreases, up to the round-off of summing the cycles in another order
    # (the extra cycle can be far below one ulp of d1)
    assert d2 >= d1 * (1.0 - 1e-12)
    # the inserted excursion is closed as one full cycle; nothing else changes
    assert abs(d2 - (d1 + extra)) <= 1e-9 * max(d2, 1e-300)


@settings(max_examples=30, deadline=None)
@given(y=signals, chunk=st.integers(2, 60))
def test_carry_stream_damage_equals_whole_history(y: np.ndarray, chunk: int) -> None:
    s = RainflowStream("half")
    parts = [s.feed(y[i:i + chunk]) for i in range(0, y.size, chunk)] + [s.finish()]
    d = sum(float(np.sum(p.count / CURVE.cycles_to_failure(p.ranges))) for p in parts)
    ref = damage(y)
    assert abs(d - ref) <= 1e-9 * max(ref, 1e-300)


@settings(max_examples=30, deadline=None)
@given(y=signals, scale=st.floats(0.1, 10.0))
def test_miner_damage_scales_monotonically_with_stress(y: np.ndarray, scale: float) -> None:
    d1, d2 = damage(y), damage(y * scale)
    assert (d2 >= d1) if scale >= 1.0 else (d2 <= d1)


@settings(max_examples=60, deadline=None)
@given(S=st.lists(st.floats(0.0, 2000.0, allow_nan=False), min_size=1, max_size=300),
       which=st.integers(0, 4))
def test_batched_miner_sum_equals_scalar_sn_evaluation(S: list[float], which: int) -> None:
    """The vectorised batch (integer slopes) and the scalar path (other slopes)
    of the multi-plane kernel give sum cnt/N(S) of ``sn_inverse_life`` to 1e-12
    relative (only the order of the sum and of the power products differ)."""
    from drillfatigue.fatigue import kernels as K
    from drillfatigue.fatigue.sn import user_curve

    curve = (get_curve("D"), get_curve("B1"), get_curve("W3", "free_corrosion"),
             user_curve(3.5, 12.2, 4.5, 1e7), user_curve(3.0, 12.5, 5.0, 1e7, cutoff_N=1e8)
             )[which]
    a, m, ia, cut = curve.kernel_arrays()
    Sa = np.array(S)
    cnt = np.where(np.arange(Sa.size) % 3 == 0, 0.5, 1.0)
    got = K._miner_batch(Sa, cnt, Sa.size, a, m, ia, cut)
    ref = sum(c * K.sn_inverse_life(x, a, m, ia, cut) for x, c in zip(Sa, cnt, strict=False))
    assert got == pytest.approx(ref, rel=1e-12, abs=0.0)
