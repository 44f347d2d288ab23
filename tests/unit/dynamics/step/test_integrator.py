"""Convergence: a result changes by < 1 % when the step is halved (docs/model.md#integration)."""

from __future__ import annotations

import numpy as np

from testkit.short_runs import given_tob_run


def test_halving_the_step_changes_results_by_less_than_1_percent() -> None:
    ref = given_tob_run(None)
    dt = ref.summary["dt_s"]
    half = given_tob_run(dt / 2)
    # the lobes (0.2 mm) keep the bit on bottom: a bouncing bit is a non-smooth,
    # chaotic event sequence, not a test of the step size
    assert ref.summary["bit_bounce_count"] == half.summary["bit_bounce_count"] == 0
    ta, tb = ref.channels["time_s"], half.channels["time_s"]
    for key in ("surface_torque_Nm", "wob_N", "bit_rpm"):
        # the half-step history interpolated to the reference recording times;
        # error relative to the largest value of the history
        b = np.interp(ta, tb, half.channels[key])
        err = np.abs(ref.channels[key] - b).max() / np.abs(b).max()
        assert err < 0.01, (key, err)
    la, lb = ref.loads, half.loads
    for j in range(la.shape[1]):
        for k in range(6):
            b = np.interp(ref.times_s, half.times_s, lb[:, j, k])
            err = np.abs(la[:, j, k] - b).max() / (np.abs(lb[:, :, k]).max() + 1.0)
            assert err < 0.01, (j, k, err)
