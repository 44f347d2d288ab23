"""Tripping in and out: the string length follows the trip speed, axial drag follows the motion.

Off bottom with the top held, the top segment grows (tripping in) or shrinks
(tripping out) at ``operation.trip_speed_m_per_s``; a short top segment merges
with the one below; tripping out stops at a two-segment minimum. The hook load
while moving in a straight 30 deg hole must match the soft-string closed forms
(docs/validation.md): pick-up w L (cos I + mu sin I), slack-off w L (cos I - mu sin I).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import drillfatigue
from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.string import build_segments


def _case(trip: float, *, duration: float = 3.0, n: int = 20, length: float = 200.0):
    return case_from_dict({
        # kick-off at 1 m, 60 deg/30 m to 30 deg: straight from 16 m on
        "well": {"profiles": {"j": {"kind": "j", "kop_m": 1.0, "dls_deg_per_30m": 60.0,
                                    "inc_deg": 30.0, "td_m": 600.0}}},
        "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": length, "n_segments": n}]},
        "operation": {"duration_s": duration, "bit_md_m": 50.0 + length, "top_md_m": 50.0,
                      "bit_on_bottom": False, "top_axial": "fixed", "rpm": 0.0,
                      "rpm_ramp_s": 0.0, "trip_speed_m_per_s": trip},
        "solver": {"relax_s": 0.3},
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 10.0,
                      "loads_rate_hz": 10.0},
    })


def _string_length(res) -> float:
    n = res.state.n_active
    return float(2.0 * res.model.seg[:n, L.S_H].sum())


def test_pick_up_and_slack_off_hook_loads_match_the_closed_forms() -> None:
    cfg = _case(0.5)
    segs = build_segments(cfg.string, cfg.operation.mud_density_kg_per_m3)
    w = float(segs.buoyed_weight_N[0] / segs.length_m[0])
    inc, mu, length = math.radians(30.0), cfg.friction.mu_dynamic, 200.0
    loads = {}
    for trip in (0.5, -0.5):
        res = drillfatigue.simulate(_case(trip), None, progress=False)
        ch = res.channels
        loads[trip] = float(ch["hook_load_N"][ch["time_s"] > 1.5].mean())
        # the string length changed at the trip speed (3 s)
        assert _string_length(res) == pytest.approx(length + 3.0 * trip, rel=1e-9)
    # 5 %: steady sliding after 1.5 s; measured pick-up 0.1 %, slack-off 3.4 % (the
    # string's own axial inertia and the contact dash-pot smear the slack-off)
    assert loads[-0.5] == pytest.approx(w * length * (math.cos(inc) + mu * math.sin(inc)), rel=0.05)
    assert loads[0.5] == pytest.approx(w * length * (math.cos(inc) - mu * math.sin(inc)), rel=0.05)


def test_tripping_out_merges_short_top_segments_and_stops_at_the_minimum() -> None:
    res = drillfatigue.simulate(_case(-2.0, duration=2.0, n=10, length=20.0), None,
                                progress=False)
    sm = res.summary
    # 20 m of 2 m segments, 4 m pulled out: the top shrinks below 1 m and merges
    assert sm["segments_merged"] >= 1
    # (a merge spans the two bodies' actual end points: the joint's stretch and tilt
    # enter the length, ~1e-5 relative)
    assert _string_length(res) == pytest.approx(16.0, rel=1e-4)
    assert not sm["trip_out_stopped_at_minimum"]
    # a two-segment string cannot be pulled out further: the guard stops it
    res = drillfatigue.simulate(_case(-2.0, duration=2.0, n=2, length=4.0), None,
                                progress=False)
    assert res.summary["trip_out_stopped_at_minimum"]
    assert res.state.n_active == 2
    assert _string_length(res) > 0.0
    assert np.isfinite(res.channels["hook_load_N"]).all()
