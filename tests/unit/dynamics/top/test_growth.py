"""Drilling progression: the string grows at the ROP by splitting segments off its top
(docs/model.md#top-boundary).

The top segment lengthens from its fixed top end; when it exceeds its nominal
length by one segment a nominal segment is split off its bottom, so the
resolution stays the same as the string grows. Rows are preallocated to the
largest count the run can reach (no reallocation in the stepping loop).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import drillfatigue
from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import straight_path

STRING = {"components": [{"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 10.0,
                          "n_segments": 5}]}


def _drill(rop: float, duration: float, **bit: object):
    cfg = case_from_dict({
        "string": STRING,
        "operation": {"bit_md_m": 12.0, "top_md_m": 0.0, "duration_s": duration, "rpm": 60.0,
                      "rpm_ramp_s": 0.2, "rop_m_per_s": rop, "top_axial": "neutral_point",
                      "neutral_point_s_from_bit_m": 6.0},
        "bit": bit,
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 10.0, "loads_rate_hz": 10.0},
    })
    return drillfatigue.simulate(cfg, None, progress=False, path=straight_path(100.0))


def test_prescribed_rop_splits_nominal_segments_and_keeps_the_string_on_bottom() -> None:
    res = _drill(1.0, 5.0)
    m, s, sm = res.model, res.state, res.summary
    # 12 m of hole: 4 x 2 m segments and a 4 m top; a 2 m segment splits off the top
    # whenever the top exceeds 4 m + 2 m ... i.e. every 2 m drilled: 2 splits in 5 m
    assert sm["segments_added"] == 2
    n = s.n_active
    assert n == 7 == sm["n_segments_final"]
    assert m.n >= n and m.seg.shape[0] == m.n  # preallocated rows, never reallocated
    lengths = 2.0 * m.seg[:n, L.S_H]
    np.testing.assert_allclose(lengths[:-1], 2.0, rtol=1e-12)
    assert sm["bit_md_final_m"] == pytest.approx(12.0 + 5.0, rel=1e-9)
    assert lengths.sum() == pytest.approx(17.0, rel=1e-9)  # from the fixed top to the bit
    # the new segments hang on: continuous string, bit on bottom all the way
    kin = res.kinematics.to_pandas()
    assert kin[kin.segment == 6].time_s.min() > 4.0 - 1e-9  # created at 4 m drilled
    assert res.channels["wob_N"][res.channels["time_s"] > 0.5].min() > 0.0
    assert sm["bit_bounce_count"] == 0
    ch = res.channels
    assert ch["n_segments"][-1] == 7


def test_computed_rop_advances_the_bit_by_the_law() -> None:
    res = _drill(0.0, 2.0, model="yigit_christoforou", rop_c1_m_per_N_sqrt_s=5e-7)
    ch = res.channels
    t, rop = ch["time_s"], ch["rop_m_per_s"]
    drilled = res.summary["bit_md_final_m"] - 12.0
    assert drilled > 0.01  # ~ 5e-7 x 7.5 kN x sqrt(6.3 rad/s) x 2 s
    # the bit MD follows the integral of the law's ROP (1 % : recording-rate quadrature)
    assert drilled == pytest.approx(np.trapezoid(rop, t) + rop[0] * t[0], rel=0.01)
    # ... and the ROP is the Sarker law c1 WOB sqrt(Omega) above the thresholds
    late = t > 1.0
    law = 5e-7 * ch["wob_N"][late] * np.sqrt(np.abs(ch["bit_rpm"][late]) * math.pi / 30.0)
    np.testing.assert_allclose(rop[late], law, rtol=1e-6)
