"""Torsional stick-slip from a velocity-weakening bit (Yigit & Christoforou; docs/model.md#bit).

1000 m of string (200 m of collars, 800 m of drill pipe) on bottom in a
vertical hole, the neutral point at the top of the collars (WOB ~ 250 kN),
TOB from the Yigit-Christoforou law, whose torque falls with bit speed: a
negative damping WOB b0 mu0 d mu_b / d Omega. At low rpm it exceeds the mud's
torsional damping and the bit sticks and slips (speed repeatedly ~0, bursts to
several times the top speed); at high rpm the slope of the law is small
(~b2 / (b3 Omega^2)) and the steady rotation is stable. The run starts at
speed in torsional equilibrium with the law's TOB (no start-up kick), so the
high-rpm run has no transient to lock into the stick-slip limit cycle.
"""

from __future__ import annotations

import numpy as np

import drillfatigue
from drillfatigue.config import case_from_dict

WINDOW_S = 4.0


def _run(rpm: float):
    cfg = case_from_dict({
        "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 1500.0}}},
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 200.0, "n_segments": 4},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 800.0,
             "n_segments": 16}]},
        "operation": {"duration_s": 12.0, "bit_md_m": 1000.0, "rpm": rpm, "rpm_ramp_s": 0.0,
                      "top_axial": "neutral_point", "rop_m_per_s": 0.0},
        "bit": {"model": "yigit_christoforou"},
        "recording": {"channels_rate_hz": 50.0, "loads_rate_hz": 1.0, "kinematics_rate_hz": 1.0,
                      "events_start_s": WINDOW_S},
    })
    res = drillfatigue.simulate(cfg, None, progress=False)
    ch = res.channels
    return res.summary, ch["bit_rpm"][ch["time_s"] >= WINDOW_S]


def test_low_rpm_sticks_and_slips() -> None:
    summary, bit = _run(30.0)
    stuck = bit < 0.02 * 30.0
    # repeatedly near zero: at least two separate stick phases in the 8 s window
    # (measured: period ~6 s, stuck half of it), and slip bursts far above the top speed
    assert np.count_nonzero(np.diff(stuck.astype(int)) == 1) + int(stuck[0]) >= 2
    assert bit.max() > 3.0 * 30.0
    # severity (max - min) / mean bit rpm (measured 5.4); 1 = the usual stick-slip mark
    assert summary["stick_slip_severity"] > 1.0


def test_high_rpm_suppresses_stick_slip() -> None:
    summary, bit = _run(150.0)
    assert bit.min() > 0.5 * 150.0
    assert summary["stick_slip_severity"] < 0.2  # measured 0.025
