"""A rig block lowering at its ROP set-point starts in steady drilling (docs/rig.md).

The 100 m vertical string of ``tests/unit/dynamics/top/test_boundaries.py`` with
``block_mode: rop`` at 2 mm/s and 120 rpm, no rpm ramp and a flat rock face.
Reference: the Yigit-Christoforou / Sarker ROP law in closed form,
``ROP = c1 WOB sqrt(Omega) + c2`` above its thresholds, so the steady WOB for
the set-point is ``W* = (ROP_set - c2) / (c1 sqrt(Omega))`` (40.3 kN here).
In steady drilling the bit cuts what the block lowers, so from the first step
the mean ROP is the set-point and the mean WOB is ``W*``.

Tolerances: the set-up is exact straight-hole statics (vertical hole, no wall),
so what is left is the string's axial response to the mud drag and the top
boundary's spring (measured: 1e-5 of the set-point on the mean ROP and of W* on
the mean WOB over the 0.5 s); 0.5 % bounds it with room. The old start (neutral
point at the top of the collars, 49.8 kN) gives a mean ROP 21 % above the
set-point over the same 0.5 s (the drill-off time constant
``1 / (k c1 sqrt(Omega))`` of this string is about 2 s), 40 times the bound.
"""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.simulation import check_rig, simulate
from drillfatigue.dynamics.bit.rockface import rop_tob_from_wob, steady_wob_for_rop_N
from drillfatigue.errors import InputError

ROP_SET = 0.002
RPM = 120.0

CASE: dict[str, Any] = {
    "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 300.0}}},
    "string": {"components": [
        {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 40.0, "n_segments": 4},
        {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 60.0,
         "n_segments": 6}]},
    "operation": {"duration_s": 0.5, "bit_md_m": 110.0, "top_md_m": 10.0, "rpm": RPM,
                  "rpm_ramp_s": 0.0},
    "bit": {"model": "yigit_christoforou"},
    "rig": {"block_mode": "rop", "rop_set_m_per_s": ROP_SET, "rock": {"lobe_amplitude_m": 0.0}},
    "solver": {"dt_s": 2.5e-4},
    "recording": {"loads_rate_hz": 100.0, "channels_rate_hz": 4000.0,
                  "kinematics_rate_hz": 10.0},
}


def test_a_rop_block_starts_at_the_set_point_rop_and_the_laws_steady_wob() -> None:
    cfg = case_from_dict(CASE)
    bit = cfg.bit
    omega = RPM * 2.0 * math.pi / 60.0
    w_closed = (ROP_SET - bit.rop_c2_m_per_s) / (bit.rop_c1_m_per_N_sqrt_s * math.sqrt(omega))
    # the inverse used at set-up is the closed form above the thresholds
    wob, lo, hi = steady_wob_for_rop_N(bit, ROP_SET, RPM, 1e6)
    assert wob == pytest.approx(w_closed, rel=1e-12)
    assert lo < ROP_SET < hi
    res = simulate(cfg, None, progress=False)
    assert res.summary["rig"]["rop_start_wob_N"] == pytest.approx(w_closed, rel=1e-12)
    assert res.model.wob0_N == pytest.approx(w_closed, rel=1e-12)
    ch = res.channels
    rop = np.asarray(ch["rop_m_per_s"])
    wob_t = np.asarray(ch["wob_N"])
    assert np.all(wob_t > 0.0)
    assert float(rop.mean()) == pytest.approx(ROP_SET, rel=0.005)
    assert float(wob_t.mean()) == pytest.approx(w_closed, rel=0.005)
    # the block lowered at the set-point all along, and the bit drilled as much
    blk = np.asarray(ch["block_velocity_m_per_s"])
    assert np.allclose(blk, ROP_SET, rtol=1e-12)
    md = np.asarray(ch["bit_md_m"])
    t = np.asarray(ch["time_s"])
    assert (md[-1] - md[0]) / (t[-1] - t[0]) == pytest.approx(ROP_SET, rel=0.005)


def test_an_rop_set_point_the_bit_law_cannot_reach_is_refused_before_any_step(tmp_path: Any) -> None:
    # 0.06 m/s needs more than 1000 kN at 120 rpm (the law gives 0.0496 m/s there)
    d = copy.deepcopy(CASE)
    d["rig"]["rop_set_m_per_s"] = 0.06
    out = tmp_path / "run"
    with pytest.raises(InputError) as exc:
        simulate(case_from_dict(d), out, progress=False)
    assert exc.value.field == "rig.rop_set_m_per_s"
    # 1.4e-8 x 1e6 N x sqrt(4 pi) = 0.04963 m/s
    assert exc.value.allowed == "0 < rop_set_m_per_s <= 0.04963"
    assert not out.exists() or not any(out.iterdir())
    # below the law's bit-speed threshold nothing is cut at any WOB
    d["rig"]["rop_set_m_per_s"] = ROP_SET
    d["operation"]["rpm"] = 0.3
    with pytest.raises(InputError) as exc:
        simulate(case_from_dict(d), None, progress=False)
    assert exc.value.field == "rig.rop_set_m_per_s"
    assert "threshold" in exc.value.problem
    # a sharp WOB threshold (no fade-in band): the law jumps from 0 to c1 W_th sqrt(Omega)
    d["operation"]["rpm"] = RPM
    d["bit"]["threshold_band"] = 0.0
    d["rig"]["rop_set_m_per_s"] = 1e-5
    with pytest.raises(InputError) as exc:
        check_rig(case_from_dict(d))
    assert exc.value.field == "rig.rop_set_m_per_s"
    # 1.4e-8 x 5 kN x sqrt(4 pi) = 2.481e-4 m/s
    assert exc.value.allowed.startswith("0.0002481 <= rop_set_m_per_s")


def test_the_inverse_in_the_threshold_band_and_for_the_detournay_law() -> None:
    cfg = case_from_dict(CASE)
    bit = cfg.bit
    # a set-point whose WOB lies in the Sarker fade-in band (5 to 5.5 kN): bisection
    target = float(rop_tob_from_wob(bit, 5.2e3, RPM)[0])
    wob, _, _ = steady_wob_for_rop_N(bit, target, RPM, 1e6)
    assert wob == pytest.approx(5.2e3, rel=1e-9)
    det = case_from_dict({**CASE, "bit": {"model": "detournay"}}).bit
    wob, _, _ = steady_wob_for_rop_N(det, ROP_SET, RPM, 1e6)
    rop, _ = rop_tob_from_wob(det, wob, RPM)
    assert float(rop) == pytest.approx(ROP_SET, rel=1e-9)


@pytest.mark.parametrize("operation", [{"top_axial": "fixed"},
                                       {"neutral_point_s_from_bit_m": 30.0}])
def test_a_rop_block_on_bottom_takes_no_other_axial_start(operation: dict[str, Any]) -> None:
    d = copy.deepcopy(CASE)
    d["operation"].update(operation)
    with pytest.raises(InputError) as exc:
        case_from_dict(d)
    assert exc.value.field == "operation.top_axial"
