"""Torsional stick-slip with a PI top drive: kernels against an independent lumped reference.

The reference (tests/testkit/rig_references.py) is a 10-lump torsional model of a
stated well (2000 m of 5 in pipe over a 200 m collar BHA; BHA friction static
8 kN m, Coulomb 5 kN m, Stribeck 1 rad/s; top drive 932 kg m^2 with a PI of
Kp = 2e4 N m s/rad, Ki = 4e4 N m/rad; 40 rpm) integrated by LSODA at rtol
1e-7; the same chain stepped with the numba top-drive kernel at a fixed
0.1 ms step must give the same stick-slip. The issue's bounds are 10 % on
the break-off torque and 20 % on the period; the fixed-step scheme is
first order with a step 100x below the fastest time scale of the chain, so
the test asks 2 %. Measured (off bottom, PI): period 5.26 s in both, break-off
torque 9.41 kN m in both (differences < 0.01 %); on bottom (bit law at
100 kN): 7.35 s and 14.46 kN m in both.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

import testkit.rig_references as RR

from drillfatigue.dynamics.top import rig as R

WELL = RR.TorsionalWell()


@pytest.mark.parametrize(("tuning", "wob_N"), [("pi", 0.0), ("stiff", 0.0), ("pi", 1e5)])
def test_kernel_stick_slip_matches_the_lumped_reference(tuning: str, wob_N: float) -> None:
    w = dataclasses.replace(WELL, wob_N=wob_N)
    target = w.rpm * 2.0 * math.pi / 60.0
    ker = RR.stick_slip_metrics(RR.torsional_with_kernels(w, tuning), target, 20.0)
    ref = RR.stick_slip_metrics(RR.torsional_reference(w, tuning), target, 20.0)
    assert ref["n_cycles"] >= 3  # a developed stick-slip, not a transient
    assert ker["n_cycles"] == ref["n_cycles"]
    assert ker["period_s"] == pytest.approx(ref["period_s"], rel=0.02)
    assert ker["break_off_Nm"] == pytest.approx(ref["break_off_Nm"], rel=0.02)
    # the string must carry at least the static friction (plus the bit's torque) to break free
    assert ref["break_off_Nm"] > w.t_static_Nm


def test_soft_torque_tuning_removes_a_stick_slip_the_stiff_pi_has() -> None:
    # moderate velocity weakening at 60 rpm (static 6.5 kN m, Coulomb 5 kN m, Stribeck 2 rad/s):
    # the stiff PI reflects the torsional waves and the string sticks and slips; the soft-torque
    # gains (Kp = pipe impedance, Ki = J omega_1^2 at the first torsional mode) absorb them
    w = dataclasses.replace(WELL, rpm=60.0, t_static_Nm=6.5e3, t_coulomb_Nm=5e3, omega_stribeck_rad_s=2.0)
    target = w.rpm * 2.0 * math.pi / 60.0
    stiff = RR.stick_slip_metrics(RR.torsional_with_kernels(w, "pi", t_end=80.0), target, 30.0)
    c = math.sqrt(w.gj_Nm2 / w.pipe_inertia_per_m_kg_m)
    w1 = R.torsional_first_mode_rad_s(w.pipe_length_m, c, w.pipe_inertia_per_m_kg_m * w.pipe_length_m,
                                      w.bha_inertia_kg_m2)
    kp, ki = R.soft_torque_gains(R.torsional_impedance_Nms_per_rad(w.gj_Nm2, w.pipe_inertia_per_m_kg_m),
                                 w.td_inertia_kg_m2, w1)
    soft = RR.stick_slip_metrics(RR.torsional_with_kernels(w, "pi", t_end=80.0, kp=kp, ki=ki), target, 30.0)
    assert stiff["n_cycles"] >= 5 and stiff["severity"] > 1.5
    assert soft["n_cycles"] == 0 and soft["severity"] < 0.5
    # the stick-slip period is near the first torsional mode the soft-torque rule tunes for
    assert stiff["period_s"] == pytest.approx(2.0 * math.pi / w1, rel=0.15)
