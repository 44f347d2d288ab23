"""Exact, indexed and streamed rainflow (fatigue.rainflow, fatigue.kernels)."""

from __future__ import annotations

import fatpack
import numpy as np
import pytest
import rainflow

from drillfatigue.errors import InputError
from drillfatigue.fatigue.rainflow import (RainflowStream, concatenate_reversals, find_cycles,
                                           find_cycles_indexed, find_exact_reversals)


def _sorted(r: np.ndarray, n: np.ndarray) -> list[tuple[float, float]]:
    return sorted(zip(np.round(r, 9).tolist(), n.tolist(), strict=True))


@pytest.mark.parametrize("seed", range(6))
def test_indexed_kernel_matches_fatpack_and_rainflow_package(seed: int) -> None:
    rng = np.random.default_rng(seed)
    y = np.cumsum(rng.normal(size=3000)) + rng.normal(size=3000)
    i0, i1, cnt = find_cycles_indexed(y, "half")
    mine = _sorted(np.abs(y[i1] - y[i0]), cnt)
    # independent oracle: the rainflow package (ASTM E1049 3-point algorithm)
    oracle = _sorted(np.array([c[0] for c in rainflow.extract_cycles(y)]),
                     np.array([c[2] for c in rainflow.extract_cycles(y)]))
    assert mine == oracle
    # fatpack on the exact reversals: same closed cycles, residue as half cycles
    rev, _ = find_exact_reversals(y)
    cyc, res = fatpack.find_rainflow_cycles(rev)
    fp = _sorted(np.r_[np.abs(cyc[:, 1] - cyc[:, 0]), np.abs(np.diff(res))],
                 np.r_[np.ones(len(cyc)), np.full(len(res) - 1, 0.5)])
    assert mine == fp
    # the stored indices are reversal samples of the signal
    _, ridx = find_exact_reversals(y)
    assert np.isin(i0, ridx).all() and np.isin(i1, ridx).all()


@pytest.mark.parametrize("seed", range(3))
def test_repeat_mode_kernel_matches_fatpack_route(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    y = rng.normal(size=2000)
    i0, i1, cnt = find_cycles_indexed(y, "repeat")
    assert np.all(cnt == 1.0)
    c = find_cycles(y, "repeat")  # fatpack cycles of the residue joined to itself
    np.testing.assert_allclose(np.sort(c.ranges), np.sort(np.abs(y[i1] - y[i0])), rtol=0,
                               atol=0)
    # repeating closes every half cycle: the count is (n_full + n_half/2 + 1/2) at most
    h = find_cycles(y, "half")
    assert cnt.size <= h.count.sum() + 0.5


@pytest.mark.parametrize("r1,r2,expected", [
    ([0.0, 5.0], [6.0, 1.0], [0.0, 6.0, 1.0]),  # fatpack 0.7.8 keeps 5
    ([0.0, 5.0], [4.0, 1.0], [0.0, 5.0, 1.0]),  # fatpack 0.7.8 keeps 4
    ([0.0, 5.0], [4.0, 7.0], [0.0, 5.0, 4.0, 7.0]),
    ([0.0, 5.0], [6.0, 7.0], [0.0, 7.0]),
])
def test_concatenate_reversals_keeps_true_turning_points(r1: list[float], r2: list[float],
                                                         expected: list[float]) -> None:
    got = concatenate_reversals(np.array(r1), np.array(r2))
    np.testing.assert_array_equal(got, expected)


def test_exact_reversals_keep_plateau_start_and_ends() -> None:
    y = np.array([0.0, 1.0, 1.0, 1.0, 0.5, 0.5, 2.0, 3.0])
    r, i = find_exact_reversals(y)
    np.testing.assert_array_equal(r, [0.0, 1.0, 0.5, 3.0])
    np.testing.assert_array_equal(i, [0, 1, 4, 7])


def test_constant_and_monotone_signals_give_no_full_cycle() -> None:
    assert len(find_cycles(np.ones(50))) == 0
    c = find_cycles(np.linspace(0, 1, 50))
    assert c.count.tolist() == [0.5] and c.ranges[0] == pytest.approx(1.0)
    i0, _, _ = find_cycles_indexed(np.ones(10))
    assert i0.size == 0


@pytest.mark.parametrize("bad", [np.zeros(0), np.array([0.0, np.nan, 1.0])])
def test_bad_signals_raise(bad: np.ndarray) -> None:
    with pytest.raises(InputError):
        find_cycles(bad)
    with pytest.raises(InputError):
        find_cycles_indexed(bad)


def test_unknown_residue_mode_raises() -> None:
    with pytest.raises(InputError, match="allowed: half, repeat, carry"):
        find_cycles(np.arange(5.0), residue="fold")


@pytest.mark.parametrize("chunk", [7, 100, 999])
def test_stream_counts_equal_whole_history(chunk: int) -> None:
    rng = np.random.default_rng(7)
    y = np.cumsum(rng.normal(size=4000))
    whole = find_cycles(y, "half")
    s = RainflowStream("half")
    parts = [s.feed(y[i:i + chunk]) for i in range(0, y.size, chunk)] + [s.finish()]
    got = _sorted(np.concatenate([p.ranges for p in parts]),
                  np.concatenate([p.count for p in parts]))
    assert got == _sorted(whole.ranges, whole.count)


def test_exact_reversals_keep_a_turn_whose_differences_multiply_below_the_smallest_double() -> None:
    # differences of 2 and 1.7e-171 around the dip: their product (3e-342) underflows to
    # -0.0; the turn is a change of sign and is kept, and the dip's cycle closes
    e = 1.7317028894306911e-171
    rev, idx = find_exact_reversals(np.array([2.0, 0.0, -e, 0.0, -1.0]))
    np.testing.assert_array_equal(rev, [2.0, -e, 0.0, -1.0])
    np.testing.assert_array_equal(idx, [0, 2, 3, 4])
    tiny = concatenate_reversals(np.array([0.0, e]), np.array([2 * e, -1.0]))
    np.testing.assert_array_equal(tiny, [0.0, 2 * e, -1.0])
