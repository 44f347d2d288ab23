"""The rig boundaries inside the simulator against their references (issue "Drilling as a rig
drills"; docs/rig.md).

1. Autodriller step response. A 300 m vertical string (60 m of 6 3/4 in collars, 240 m of
   5 in drill pipe; 18 segments, no wall contact, flat rock face), drilling at 120 rpm
   with the autodriller holding 40 kN; at t = 2 s the set-point steps to 50 kN. Reference:
   the closed loop of a single mass on the same string, ``rig.second_order_step`` with
   the string's axial stiffness (block to rock: joints, top spring and rock spring in
   series, from the model), the gains, and ``c = dROP/dWOB`` of the bit law at 40 kN and
   120 rpm, without the measurement filter (the closed form has none). The loop
   (0.3 rad/s, damping ratio 1) is 40x slower than the string's first axial mode
   (~13 rad/s), so the quasi-static closed form should hold to a few per cent;
   the issue's bound is 10 % of the step, asked here of the WOB averaged over 20 ms.
2. Torsional stick-slip with the PI top drive. The well of ``tests/testkit/rig_references.py``
   (2000 m of 5 in pipe above 200 m of collars, in 1.2 SG mud, default top drive with
   Kp = 2e4 N m s/rad, Ki = 4e4 N m/rad, 40 rpm after a 5 s ramp) on bottom at a held
   block: the bit law's torque at the WOB the string starts with (rop_c1 = 0, so the bit
   does not drill off and the WOB stays put) is the only velocity-weakening torque.
   Reference: ``torsional_reference`` (10-lump chain, LSODA, its own PI) with the same
   WOB and no BHA friction. Bounds of the issue: break-off torque within 10 %, period
   within 20 %. The simulator's chain is 10 pipe segments of 200 m above one collar
   segment: the same lumping as the reference, up to where the joints sit.
3. Slack-off buckling. The set-up of ``test_buckling_detected_in_simulation.py`` (100 m of
   5 in pipe in 50 segments, 60 deg straight hole, frictionless, a small lateral
   imperfection of the 25 m buckle's shape), now slacked off by the block: the string
   starts at 0.3 F_DP on the bit, the autodriller (downhole WOB) lowers the block until
   the mean compression of the middle of the string is 0.8 or 1.2 F_DP and holds it for
   3 s. The buckling detector on the final shape: no buckle at 0.8 F_DP, a sinusoidal one
   at 1.2 F_DP, so the onset is within the issue's +-20 % of Dawson-Paslay.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run import buckling as BD
from drillfatigue.softstring import buckling as B
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.dynamics.bit.rockface import rop_slope_m_per_N_s
from drillfatigue.string import build_segments

from testkit.rig_references import TorsionalWell, stick_slip_metrics, torsional_reference

COLLAR = {"type": "collar", "od_m": 0.17145, "id_m": 0.0714}
PIPE = {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086}


def _string_stiffness(model: Any) -> float:
    """Axial stiffness block -> rock of the model: joints, top spring, rock spring in series."""
    n = model.n0
    return 1.0 / (float((1.0 / model.jp[: n - 1, L.J_KA]).sum()) + 1.0 / model.jp[n - 1, L.J_KA]
                  + 1.0 / model.bp[L.B_KROCK])


def _wob_set_index() -> int:
    return L.B_BLKP + R.BP_WOBSET


#: closed-loop natural frequency of the step test (rad/s) and the time after the step (s)
STEP_WN_RAD_S = 0.3
STEP_AFTER_S = 25.0


@pytest.mark.parametrize("measurement", ["wob", "hook_load"])
def test_autodriller_step_response_of_the_simulator_matches_the_closed_loop(measurement: str) -> None:
    w0, w1, t_step, t_after = 40e3, 50e3, 2.0, STEP_AFTER_S
    rpm = 120.0
    base = {
        "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 500.0}}},
        "string": {"components": [dict(COLLAR, length_m=60.0, n_segments=6),
                                  dict(PIPE, length_m=240.0, n_segments=12)]},
        "operation": {"duration_s": t_step + t_after, "bit_md_m": 310.0, "top_md_m": 10.0,
                      "rpm": rpm, "rpm_ramp_s": 0.0},
        "bit": {"model": "yigit_christoforou"},
        "solver": {"relax_s": 0.0},
    }
    cfg0 = case_from_dict(base)
    c_rop = rop_slope_m_per_N_s(cfg0.bit, w0, rpm)
    # string stiffness from a first build, then gains for 2 rad/s and damping ratio 1
    probe = dict(base, rig={"block_mode": "held"})
    probe["operation"] = dict(base["operation"], top_axial="fixed")
    k = _string_stiffness(build_model(case_from_dict(probe), straight_path(500.0))[0])
    wn, zeta = STEP_WN_RAD_S, 1.0
    ki = wn * wn / k
    kp = 2.0 * zeta * wn / k - c_rop
    cfg = case_from_dict(dict(base, rig={
        "block_mode": "autodriller", "rock": {"lobe_amplitude_m": 0.0},
        "autodriller": {"measurement": measurement, "wob_set_N": w0, "kp_m_per_s_per_N": kp,
                        "ki_m_per_s2_per_N": ki, "control_period_s": 0.0,
                        "measurement_filter_s": 0.0}}))
    model, state = build_model(cfg, straight_path(500.0))
    assert _string_stiffness(model) == pytest.approx(k, rel=1e-12)
    every = 10
    n0 = round(t_step / model.dt)
    advance_model(model, state, n0, every=every)
    model.bp[_wob_set_index()] = w1
    res = advance_model(model, state, round(t_after / model.dt), every=every)
    t = res["channels"][:, 0] - t_step
    wob = res["channels"][:, 1 + L.H_WOB]
    # 20 ms moving average: the string's axial modes ring at tens of Hz on top of the loop
    m = max(1, round(0.02 / (every * model.dt)))
    kern = np.ones(m) / m
    wob_f = np.convolve(wob, kern, mode="valid")
    t_f = np.convolve(t, kern, mode="valid")
    ref = w0 + R.second_order_step(t_f, k, kp, ki, c_rop, w1 - w0)
    err = float(np.abs(wob_f - ref).max()) / (w1 - w0)
    print(f"autodriller step ({measurement}): worst deviation {err:.4f} of the step")
    assert err <= 0.10, f"worst deviation {err:.3f} of the step"


def test_stick_slip_with_pi_top_drive_matches_the_torsional_reference() -> None:
    well = TorsionalWell(t_static_Nm=0.0, t_coulomb_Nm=0.0)
    cfg = case_from_dict({
        "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 2400.0}}},
        "string": {"components": [dict(COLLAR, length_m=200.0, n_segments=1),
                                  dict(PIPE, length_m=2000.0, n_segments=10)]},
        "operation": {"duration_s": 60.0, "bit_md_m": 2210.0, "top_md_m": 10.0,
                      "rpm": well.rpm, "rpm_ramp_s": well.ramp_s,
                      "neutral_point_s_from_bit_m": 80.0,
                      "mud_damping_torsional_N_m_s_per_m": well.mud_damping_Nms_per_rad_per_m},
        "bit": {"model": "yigit_christoforou", "rop_c1_m_per_N_sqrt_s": 0.0},
        "solver": {"relax_s": 0.0, "joint_damping_ratio": well.spring_damping_ratio,
                   "boundary_damping_ratio": well.spring_damping_ratio},
        "rig": {"block_mode": "held", "rock": {"lobe_amplitude_m": 0.0},
                "top_drive": {"tuning": "pi", "kp_Nm_s_per_rad": well.kp_Nms_per_rad,
                              "ki_Nm_per_rad": well.ki_Nm_per_rad}},
        "recording": {"loads_rate_hz": 10.0, "channels_rate_hz": 200.0,
                      "kinematics_rate_hz": 1.0},
    })
    model, state = build_model(cfg, straight_path(2400.0))
    wob = model.wob0_N
    every = max(1, round(0.005 / model.dt))
    res = advance_model(model, state, round(60.0 / model.dt), every=every)
    ch = res["channels"]
    sim = {"t": ch[:, 0], "omega_bit": ch[:, 1 + L.H_BITRPM] * math.pi / 30.0,
           "torque_surface": ch[:, 1 + L.H_TSURF]}
    # the WOB the bit law sees stays at the start value (nothing is drilled off)
    assert np.abs(ch[:, 1 + L.H_WOB] / wob - 1.0).max() < 0.05
    target = well.rpm * math.pi / 30.0
    got = stick_slip_metrics(sim, target, 20.0)
    ref = stick_slip_metrics(torsional_reference(
        TorsionalWell(t_static_Nm=0.0, t_coulomb_Nm=0.0, wob_N=wob), "pi", 60.0), target, 20.0)
    print(f"stick-slip at WOB {wob:.0f} N: simulator {got}, reference {ref}")
    assert ref["n_cycles"] >= 3 and got["n_cycles"] >= 3, (ref, got)
    assert got["break_off_Nm"] == pytest.approx(ref["break_off_Nm"], rel=0.10), (ref, got)
    assert got["period_s"] == pytest.approx(ref["period_s"], rel=0.20), (ref, got)


INC_DEG = 60.0
HOLE_D = 0.2159
HOLD_S = 3.0


def _slack_off_detection(ratio: float) -> tuple[BD.BucklingDetection, float, float]:
    od, idm = PIPE["od_m"], PIPE["id_m"]
    segs = build_segments(case_from_dict({"string": {"components": [
        dict(PIPE, length_m=100.0, n_segments=50)]}}).string, 1200.0)
    w = float(segs.buoyed_weight_N[0] / segs.length_m[0])
    ei = float(segs.ei_Nm2[0])
    r_c = HOLE_D / 2 - float(segs.contact_radius_m[0])
    f_dp = B.sinusoidal_onset_straight_N(ei, w, math.radians(INC_DEG), r_c)
    # the middle of the string (20..80 m from the bit) is asked to carry ratio x F_DP on
    # average: the bit carries that plus the axial weight of the lower 50 m
    w_ax = w * math.cos(math.radians(INC_DEG))
    wob_target = ratio * f_dp + 50.0 * w_ax
    k_pipe = 1.0 / (100.0 / float(segs.ea_N[0]))
    wn = 5.0
    cfg = case_from_dict({
        "string": {"components": [dict(PIPE, length_m=100.0, n_segments=50)]},
        "operation": {"duration_s": HOLD_S, "bit_md_m": 110.0, "top_md_m": 10.0, "rpm": 0.0,
                      "rpm_ramp_s": 0.0},
        "friction": {"mu_static": 0.0, "mu_dynamic": 0.0},
        "bit": {"model": "yigit_christoforou"},
        "solver": {"relax_s": 0.3},
        "rig": {"block_mode": "autodriller", "rock": {"lobe_amplitude_m": 0.0},
                "autodriller": {"measurement": "wob", "wob_set_N": 0.3 * f_dp + 50.0 * w_ax,
                                "kp_m_per_s_per_N": 2.0 * wn / k_pipe,
                                "ki_m_per_s2_per_N": wn * wn / k_pipe,
                                "control_period_s": 0.0, "measurement_filter_s": 0.0}},
    })
    model, state = build_model(cfg, straight_path(200.0, inclination_deg=INC_DEG,
                                                  hole_diameter_m=HOLE_D))
    assert od == 0.127 and idm == 0.1086
    axis = model.path.wall[0, 3:6]
    low = np.array([0.0, 0.0, 1.0]) - axis[2] * axis
    lateral = np.cross(axis, low / np.linalg.norm(low))
    n = model.n0
    s = 2.0 * np.arange(n)
    state.v[:n] += 1e-3 * np.outer(np.sin(2.0 * np.pi * s / 25.0), lateral)
    block0 = float(state.sc[L.C_BLK + R.BS_X])
    model.bp[_wob_set_index()] = wob_target
    res = advance_model(model, state, round(HOLD_S / model.dt),
                        every=round(0.05 / model.dt))
    force = -float(res["loads"][-1, 10:40, 0].mean())
    slack = float(state.sc[L.C_BLK + R.BS_X]) - block0
    assert slack > 0.0  # the block was lowered
    x = state.x[:n]
    p0 = model.path.wall[0, 0:3]
    along = (x - p0) @ axis
    centre = p0 + along[:, None] * axis
    s_bit = float(along.max()) - along
    order = np.argsort(s_bit)
    rho, theta = BD.lateral_offsets(x[order], centre[order], np.tile(axis, (n, 1)), r_c)
    wave = 2.0 * math.pi * (ei * r_c / (w * math.sin(math.radians(INC_DEG)))) ** 0.25
    det = BD.detect_buckling(s_bit[order], rho, theta, np.ones(n, bool), window_m=2.0 * wave)
    return det, force / f_dp, wave


@pytest.mark.slow
def test_slack_off_by_the_block_buckles_the_string_within_20_percent_of_dawson_paslay() -> None:
    det, got, _ = _slack_off_detection(0.8)
    print(f"slack-off to {got:.3f} F_DP: {det.state_names()}")
    assert got == pytest.approx(0.8, abs=0.05)
    assert set(det.state_names()) == {"none"}
    det, got, wave = _slack_off_detection(1.2)
    print(f"slack-off to {got:.3f} F_DP: {det.state_names()}, wavelengths "
          f"{det.wavelength_m[det.state == 1]} m against {wave:.1f} m")
    assert got == pytest.approx(1.2, abs=0.05)
    assert "sinusoidal" in det.state_names()
    assert "helical" not in det.state_names()
    waves = det.wavelength_m[det.state == 1]
    assert 0.75 * wave < float(np.nanmedian(waves)) < 1.25 * wave
