"""The bit stays on a lobed rock face when the face's dynamic force is below the WOB.

Reference: the linear rod model of :func:`drillfatigue.dynamics.top.setup.lobe_force_amplitude_N`
(docs/rig.md, "Why the case-2 bit bounces"): the face ``A sin(n Omega t)`` drives the
bit through the rock spring into the string's axial driving-point impedance (collars,
then drill pipe continuing upward), ``|F| = A / |1/k + 1/(i w Z)|``. The bit pressed
with a mean WOB above ``|F|`` follows the face; below it, it leaves the face.

Set-up: the 100 m vertical string of ``tests/unit/dynamics/top/test_boundaries.py`` (40 m of
6 3/4 in collars, 60 m of 5 in pipe), autodriller on a 40 kN WOB, stiff top drive,
three lobes. Bounds: the rod model is linear and leaves out the mud, the joint and
rock damping and the block's spring at the top, so it is used only well away from the
threshold: at 120 rpm and 1 mm it gives |F| / WOB = 0.26 and the bit must be on bottom
at least 95 % of the time (the case-2 acceptance); at 300 rpm and 3 mm it gives
|F| / WOB = 5.8 and the bit must leave bottom (on bottom below 95 %), so the check
can fail both ways.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.dynamics.top.setup import lobe_force_amplitude_N, rod_input_impedance

E_PA = 207e9
RHO = 7850.0
COLLAR = (0.17145, 0.0714)
PIPE = (0.127, 0.1086)
WOB_N = 40e3


def _area(od: float, i_d: float) -> float:
    return math.pi / 4.0 * (od**2 - i_d**2)


def _case(rpm: float, amplitude_m: float) -> dict[str, Any]:
    return {
        "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 300.0}}},
        "string": {"components": [
            {"type": "collar", "od_m": COLLAR[0], "id_m": COLLAR[1], "length_m": 40.0,
             "n_segments": 4},
            {"type": "drill_pipe", "od_m": PIPE[0], "id_m": PIPE[1], "length_m": 60.0,
             "n_segments": 6}]},
        "operation": {"duration_s": 3.0, "bit_md_m": 110.0, "top_md_m": 10.0, "rpm": rpm,
                      "rpm_ramp_s": 0.0},
        "bit": {"model": "yigit_christoforou"},
        "rig": {"block_mode": "autodriller",
                # the loop of tests/unit/dynamics/top/test_boundaries.py (stable on this short string)
                "autodriller": {"measurement": "wob", "wob_set_N": WOB_N,
                                "control_period_s": 0.0, "measurement_filter_s": 0.0,
                                "kp_m_per_s_per_N": 1e-7, "ki_m_per_s2_per_N": 1e-6},
                "rock": {"lobe_count": 3, "lobe_amplitude_m": amplitude_m}},
        "solver": {"dt_s": 2.5e-4},
        "recording": {"loads_rate_hz": 100.0, "channels_rate_hz": 4000.0,
                      "kinematics_rate_hz": 10.0},
    }


@pytest.mark.parametrize("rpm, amplitude_m, on_bottom", [(120.0, 1e-3, True),
                                                          (300.0, 3e-3, False)])
def test_bit_follows_the_lobes_when_the_rod_model_force_is_below_the_wob(
        rpm: float, amplitude_m: float, on_bottom: bool) -> None:
    res = simulate(case_from_dict(_case(rpm, amplitude_m)), None, progress=False)
    k_rock = float(res.summary["rig"]["rock_contact_stiffness_N_per_m"])
    sections = [(40.0, E_PA * _area(*COLLAR), RHO * _area(*COLLAR)),
                (60.0, E_PA * _area(*PIPE), RHO * _area(*PIPE))]
    ratio = lobe_force_amplitude_N(rpm, 3, amplitude_m, k_rock, sections) / WOB_N
    ch = res.channels
    t = np.asarray(ch["time_s"])
    wob = np.asarray(ch["wob_N"])[t >= 0.5]  # after the first lobe periods
    frac = float((wob > 0.0).mean())
    print(f"{rpm:g} rpm, {amplitude_m * 1e3:g} mm: |F| / WOB = {ratio:.2f}, on bottom {frac:.3f}")
    if on_bottom:
        assert ratio < 0.5, ratio
        assert frac >= 0.95, (frac, ratio)
    else:
        assert ratio > 2.0, ratio
        assert frac < 0.95, (frac, ratio)


def test_rod_impedance_closed_forms() -> None:
    """The transmission-line rule against its closed forms (exact up to round-off)."""
    ea_c, m_c = E_PA * _area(*COLLAR), RHO * _area(*COLLAR)
    ea_p, m_p = E_PA * _area(*PIPE), RHO * _area(*PIPE)
    z_c, z_p = math.sqrt(ea_c * m_c), math.sqrt(ea_p * m_p)
    c = math.sqrt(E_PA / RHO)
    # a rod continuing upward without end: its characteristic impedance at any frequency
    assert rod_input_impedance(30.0, [(1.0, ea_c, m_c)]) == pytest.approx(z_c, rel=1e-12)
    # a quarter-wave collar section over the pipe: the quarter-wave transformer Z_c^2 / Z_p
    w = 2.0 * math.pi * c / (4.0 * 180.0)
    z = rod_input_impedance(w, [(180.0, ea_c, m_c), (300.0, ea_p, m_p)])
    assert z.real == pytest.approx(z_c**2 / z_p, rel=1e-9)
    assert abs(z.imag) < 1e-6 * z_c
    # a half-wave section is transparent
    z = rod_input_impedance(2.0 * w, [(180.0, ea_c, m_c), (300.0, ea_p, m_p)])
    assert z.real == pytest.approx(z_p, rel=1e-9)
    # a rigid face (k -> inf) on a semi-infinite collar: |F| = w Z A
    f = lobe_force_amplitude_N(150.0, 3, 1e-3, 1e15, [(1.0, ea_c, m_c)])
    assert f == pytest.approx(3 * 150.0 * 2.0 * math.pi / 60.0 * z_c * 1e-3, rel=1e-6)
