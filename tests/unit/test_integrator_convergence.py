"""Convergence: a result changes by < 1 % when the step is halved (docs/model.md#integration)."""

from __future__ import annotations

import numpy as np

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.api import simulate
from drillfatigue.dynamics.model import straight_path


def _run(dt: float | None):
    cfg = case_from_dict({
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 30.0, "n_segments": 3},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 90.0,
             "n_segments": 9}]},
        "operation": {"bit_md_m": 120.0, "duration_s": 1.5, "rpm": 120.0, "rpm_ramp_s": 0.5,
                      "tob_Nm": 1500.0, "rop_m_per_s": 0.01, "lobe_amplitude_m": 0.0002},
        "solver": {"dt_s": dt},
        "recording": {"loads_rate_hz": 100.0, "channels_rate_hz": 100.0},
    })
    return simulate(cfg, None, progress=False, path=straight_path(300.0))


def test_halving_the_step_changes_results_by_less_than_1_percent() -> None:
    ref = _run(None)
    dt = ref.summary["dt_s"]
    half = _run(dt / 2)
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
