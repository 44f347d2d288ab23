"""Block and top-drive kernels (drillfatigue.dynamics.top.rig) and the rig configuration checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config import case_from_dict
from drillfatigue.config.base import validate
from drillfatigue.config.rig import RigConfig
from drillfatigue.dynamics.top.setup import check_rig_setup, string_axial_properties
from drillfatigue.dynamics.top import rig as R
from drillfatigue.errors import InputError


def _block_params(**kw: float) -> np.ndarray:
    p = np.zeros(R.N_BLOCK_P)
    p[R.BP_VMAX] = kw.get("vmax", 1.5)
    p[R.BP_AMAX] = kw.get("amax", 0.5)
    p[R.BP_TRAVEL] = kw.get("travel", 30.0)
    p[R.BP_VSET] = kw.get("vset", 0.0)
    p[R.BP_WOBSET] = kw.get("wob_set", 1e5)
    p[R.BP_KP] = kw.get("kp", 5.7e-7)
    p[R.BP_KI] = kw.get("ki", 5.7e-8)
    p[R.BP_TS] = kw.get("ts", 0.0)
    p[R.BP_HOFF] = kw.get("hoff", 1e6)
    p[R.BP_ROPLIM] = kw.get("roplim", 1.0)
    return p


def test_velocity_mode_ramps_at_the_acceleration_limit_then_holds_the_speed() -> None:
    p = _block_params(vset=1.0)
    s = R.new_block_state()
    xs = []
    for _ in range(100):
        assert R.block_step(R.BLOCK_VELOCITY, p, s, 0.0, 0.0, 0.01) == R.BLOCK_OK
        xs.append(s[R.BS_X])
    # 1 s at 0.5 m/s^2: v = 0.5, x = 0.25 m (trapezoidal rule is exact for a linear ramp)
    assert s[R.BS_V] == pytest.approx(0.5, rel=1e-12)
    assert s[R.BS_X] == pytest.approx(0.25, rel=1e-12)


def test_block_stops_at_the_floor_and_at_the_crown() -> None:
    p = _block_params(vset=1.5, amax=100.0, travel=3.0)
    s = R.new_block_state(2.8)
    codes = [R.block_step(R.BLOCK_VELOCITY, p, s, 0.0, 0.0, 0.1) for _ in range(3)]
    assert codes == [R.BLOCK_OK, R.BLOCK_AT_FLOOR, R.BLOCK_AT_FLOOR]  # 2.875, then 3.0 and held
    assert s[R.BS_X] == 3.0 and s[R.BS_V] == 0.0
    p[R.BP_VSET] = -1.5
    s = R.new_block_state(0.2)
    codes = [R.block_step(R.BLOCK_VELOCITY, p, s, 0.0, 0.0, 0.1) for _ in range(2)]
    assert codes == [R.BLOCK_OK, R.BLOCK_AT_CROWN]
    assert s[R.BS_X] == 0.0


def test_held_block_decelerates_to_rest_and_stays() -> None:
    p = _block_params()
    s = R.new_block_state(10.0, 1.0)
    for _ in range(300):
        R.block_step(R.BLOCK_HELD, p, s, 0.0, 0.0, 0.01)
    # 1 m/s stopped at 0.5 m/s^2: 2 s and 1 m
    assert s[R.BS_V] == 0.0
    assert s[R.BS_X] == pytest.approx(11.0, rel=1e-12)


def test_unknown_mode_is_a_status_not_a_crash() -> None:
    assert R.block_step(17, _block_params(), R.new_block_state(), 0.0, 0.0, 0.01) == R.BLOCK_BAD_MODE
    assert R.top_drive_step(5, np.ones(R.N_TD_P), R.new_top_drive_state(), 1.0, 0.0, 0.0, 0.01) \
        == R.TD_BAD_MODE


def test_autodriller_samples_and_holds_its_command() -> None:
    p = _block_params(ts=0.1, amax=1e3, roplim=1.0)
    s = R.new_block_state()
    cmds = []
    for k in range(35):
        R.block_step(R.BLOCK_AUTODRILLER_WOB, p, s, 5e4 + 1e3 * k, 0.0, 0.01)
        cmds.append(s[R.BS_VCMD])
    changes = np.flatnonzero(np.diff(cmds)) + 1
    assert list(changes) == [10, 20, 30]  # a new command every 0.1 s
    # first command: e = 5e4 N, I = e Ts: v = kp e + ki e Ts
    assert cmds[0] == pytest.approx(5.7e-7 * 5e4 + 5.7e-8 * 5e4 * 0.1, rel=1e-12)


def test_hook_load_autodriller_sees_off_bottom_minus_hook_load() -> None:
    p = _block_params(hoff=8e5)
    a = R.new_block_state()
    b = R.new_block_state()
    R.block_step(R.BLOCK_AUTODRILLER_HOOK, p, a, 0.0, 8e5 - 3e4, 0.01)
    R.block_step(R.BLOCK_AUTODRILLER_WOB, p, b, 3e4, 0.0, 0.01)
    assert a[R.BS_WOBMEAS] == pytest.approx(3e4)
    assert np.array_equal(a, b)


def test_autodriller_does_not_wind_up_against_its_rop_limit() -> None:
    p = _block_params(roplim=0.01, amax=1e3)
    s = R.new_block_state()
    for _ in range(1000):  # WOB far below the set-point for 10 s: the command sits at the limit
        R.block_step(R.BLOCK_AUTODRILLER_WOB, p, s, 0.0, 0.0, 0.01)
    assert s[R.BS_VCMD] == pytest.approx(0.01)
    assert s[R.BS_I] * p[R.BP_KI] <= 0.01 + 1e-12  # the integral alone never exceeds the limit
    # at the set-point the command falls below the limit at once (no wound-up integral)
    R.block_step(R.BLOCK_AUTODRILLER_WOB, p, s, 1e5, 0.0, 0.01)
    assert s[R.BS_VCMD] < 0.01


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 3), st.floats(-2.0, 2.0), st.floats(0.0, 3e5)),
                min_size=1, max_size=60),
       st.floats(1e-3, 0.2), st.floats(0.0, 30.0))
def test_block_respects_its_limits(seq, dt, x0) -> None:
    p = _block_params(kp=1e-5, ki=1e-6, hoff=2e5)
    s = R.new_block_state(x0)
    for mode, vset, meas in seq:
        p[R.BP_VSET] = vset
        v0 = s[R.BS_V]
        st_ = R.block_step(mode, p, s, meas, meas, dt)
        assert st_ >= 0
        assert 0.0 <= s[R.BS_X] <= p[R.BP_TRAVEL]
        assert abs(s[R.BS_V]) <= p[R.BP_VMAX] + 1e-12
        if st_ == R.BLOCK_OK:
            assert abs(s[R.BS_V] - v0) <= p[R.BP_AMAX] * dt * (1 + 1e-12)


# --- top drive ----------------------------------------------------------------------------


def _td_params(j=932.0, kp=2e4, ki=4e4, tmax=5e4) -> np.ndarray:
    p = np.zeros(R.N_TD_P)
    p[R.TP_J], p[R.TP_KP], p[R.TP_KI], p[R.TP_TMAX] = j, kp, ki, tmax
    return p


def test_stiff_top_drive_imposes_the_speed_and_reports_the_holding_torque() -> None:
    p = _td_params()
    s = R.new_top_drive_state()
    dt = 1e-3
    for k in range(1000):
        t = k * dt
        R.top_drive_step(R.TOP_DRIVE_STIFF, p, s, 2.0 * t, 2.0, 3e3, dt)
    assert s[R.TS_OMEGA] == pytest.approx(2.0, rel=1e-12)
    assert s[R.TS_PHI] == pytest.approx(1.0, rel=1e-9)  # integral of 2 t over 1 s
    assert s[R.TS_T] == pytest.approx(3e3 + 932.0 * 2.0)


def test_pi_top_drive_step_response_matches_the_closed_loop() -> None:
    # J w' = Kp e + Ki int(e): w(s)/w_set(s) = (Kp s + Ki) / (J s^2 + Kp s + Ki), the form of
    # R.second_order_step with k = 1/J, c = 0. Semi-implicit Euler at dt = 1e-4 s against a
    # closed-loop time scale J/Kp = 47 ms: error O(dt) ~ 0.5 %; tolerance 1 % of the step.
    p = _td_params()
    s = R.new_top_drive_state()
    dt = 1e-4
    n = 20000
    w = np.empty(n)
    for k in range(n):
        R.top_drive_step(R.TOP_DRIVE_PI, p, s, 1.0, 0.0, 0.0, dt)  # Kp x 1 rad/s < torque limit
        w[k] = s[R.TS_OMEGA]
    t = dt * np.arange(1, n + 1)
    ref = R.second_order_step(t, 1.0 / 932.0, 2e4, 4e4, 0.0, 1.0)
    assert np.max(np.abs(w - ref)) < 0.01 * 1.0


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(-30.0, 30.0), st.floats(-1e5, 1e5)), min_size=1, max_size=50),
       st.floats(1e-4, 1e-2))
def test_pi_top_drive_torque_stays_within_its_limit(seq, dt) -> None:
    p = _td_params(tmax=3e4)
    s = R.new_top_drive_state()
    for wset, tload in seq:
        R.top_drive_step(R.TOP_DRIVE_PI, p, s, wset, 0.0, tload, dt)
        assert abs(s[R.TS_T]) <= 3e4 * (1 + 1e-12)


def test_soft_torque_gains_and_first_mode() -> None:
    # quarter-wave limit without an end inertia; a heavy end inertia gives the lumped
    # pendulum sqrt(GJ/L / J_end) (x tan x ~ x^2 for small x)
    c, length = 3200.0, 2000.0
    assert R.torsional_first_mode_rad_s(length, c, 100.0, 0.0) == pytest.approx(math.pi * c / (2 * length))
    j_pipe, j_end = 10.0, 1e4
    gj_over_l = j_pipe * c * c / length**2  # GJ/L = (rho Jp L) c^2 / L^2
    assert R.torsional_first_mode_rad_s(length, c, j_pipe, j_end) == pytest.approx(
        math.sqrt(gj_over_l / j_end), rel=1e-3)
    kp, ki = R.soft_torque_gains(297.0, 932.0, 1.2)
    assert kp == 297.0 and ki == pytest.approx(932.0 * 1.44, rel=1e-12)  # J omega_ss^2
    # impedance of 5 in pipe: Jp sqrt(G rho)
    jp = math.pi / 32 * (0.127**4 - 0.1086**4)
    z = R.torsional_impedance_Nms_per_rad(79.6e9 * jp, 7850.0 * jp)
    assert z == pytest.approx(jp * math.sqrt(79.6e9 * 7850.0), rel=1e-12)


# --- configuration ------------------------------------------------------------------------


def test_inputs_a_mode_cannot_use_are_errors_naming_the_mode() -> None:
    with pytest.raises(InputError) as exc:
        validate(RigConfig, {"block_mode": "held", "rop_set_m_per_s": 0.01}, "rig")
    assert exc.value.field == "rig.rop_set_m_per_s" and "block_mode held" in exc.value.problem
    with pytest.raises(InputError) as exc:
        validate(RigConfig, {"block_mode": "rop", "rop_set_m_per_s": 0.01,
                             "autodriller": {"wob_set_N": 5e4}}, "rig")
    assert exc.value.field == "rig.autodriller"
    with pytest.raises(InputError) as exc:
        validate(RigConfig, {"top_drive": {"tuning": "stiff", "kp_Nm_s_per_rad": 1e4}}, "rig")
    assert "tuning stiff" in str(exc.value)


def test_block_speed_above_its_limit_is_refused() -> None:
    with pytest.raises(InputError) as exc:
        validate(RigConfig, {"block_mode": "trip", "trip_speed_m_per_s": -2.0,
                             "block": {"max_speed_m_per_s": 1.5}}, "rig")
    assert exc.value.field == "rig.trip_speed_m_per_s"
    assert "\n" not in str(exc.value) and "(allowed:" in str(exc.value)


def test_effective_inputs_list_only_what_the_mode_uses() -> None:
    eff = validate(RigConfig, {"block_mode": "rop", "rop_set_m_per_s": 0.005}, "rig").effective_inputs()
    assert eff["rop_set_m_per_s"] == 0.005 and "autodriller" not in eff
    eff = RigConfig().effective_inputs()
    assert eff["autodriller"]["wob_set_N"] == 1e5 and eff["top_drive"] == {"tuning": "stiff"}


CASE = {"operation": {"bit_md_m": 1000.0, "top_md_m": 0.0, "duration_s": 100.0}}


def test_default_autodriller_is_stable_on_the_default_string() -> None:
    info = check_rig_setup(RigConfig(), case_from_dict(CASE))
    assert info["phase_margin_rad"] > math.radians(45.0)


def test_unstable_autodriller_gains_are_refused_before_any_step() -> None:
    rig = validate(RigConfig, {"autodriller": {"kp_m_per_s_per_N": 5e-6}}, "rig")
    with pytest.raises(InputError) as exc:
        check_rig_setup(rig, case_from_dict(CASE))
    msg = str(exc.value)
    assert exc.value.field == "rig.autodriller.kp_m_per_s_per_N" and "unstable" in msg
    assert "<= kp_m_per_s_per_N <=" in msg and "\n" not in msg


def test_connection_longer_than_the_window_is_refused() -> None:
    rig = validate(RigConfig, {"connection": {"enabled": True}}, "rig")
    with pytest.raises(InputError) as exc:
        check_rig_setup(rig, case_from_dict(CASE))  # 160 s of connection in a 100 s window
    assert exc.value.field == "rig.connection"


def test_string_axial_properties_of_a_uniform_pipe() -> None:
    case = case_from_dict({"string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                                      "length_m": 500.0, "n_segments": 10,
                                                      "tool_joint_length_fraction": 0.0}]},
                           "operation": {"bit_md_m": 800.0, "top_md_m": 0.0}})
    props = string_axial_properties(case)
    ea = 207e9 * math.pi / 4 * (0.127**2 - 0.1086**2)
    assert props["k_axial_N_per_m"] == pytest.approx(ea / 800.0, rel=1e-6)  # top pipe extended to 800 m
    assert props["wave_speed_m_per_s"] == pytest.approx(math.sqrt(207e9 / 7850.0), rel=1e-3)


def test_string_first_torsional_mode_matches_the_shaft_with_end_inertia() -> None:
    # 1800 m of pipe (no tool joints) over 200 m of collars: the lumped chain of the
    # simulator's segments against x tan x = J_pipe / J_bha with the collars rigid. The
    # collars' own compliance (GJ of 6 3/4 in collars is 7x the pipe's over 1/9 of the
    # length) and the 20 m lumping move the mode by a few tenths of a per cent (measured
    # -0.12 %): tolerance 1 %.
    from drillfatigue.dynamics.top.setup import string_torsional_properties

    pipe = {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 1800.0, "n_segments": 90,
            "tool_joint_length_fraction": 0.0}
    collar = {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 200.0, "n_segments": 20}
    case = case_from_dict({"string": {"components": [collar, pipe]},
                           "operation": {"bit_md_m": 2000.0, "top_md_m": 0.0}})
    props = string_torsional_properties(case)
    jp = math.pi / 32 * (0.127**4 - 0.1086**4)
    jc = math.pi / 32 * (0.17145**4 - 0.0714**4)
    g = 207e9 / (2 * 1.3)
    c = math.sqrt(g / 7850.0)
    w1 = R.torsional_first_mode_rad_s(1800.0, c, 7850.0 * jp * 1800.0, 7850.0 * jc * 200.0)
    assert props["first_mode_rad_s"] == pytest.approx(w1, rel=0.01)
    assert props["impedance_Nms_per_rad"] == pytest.approx(jp * math.sqrt(g * 7850.0), rel=1e-6)


def test_packed_parameters_follow_the_modes() -> None:
    from drillfatigue.dynamics.top.setup import block_params, top_drive_params

    mode, p = block_params(RigConfig(), hook_off_N=8e5)
    assert mode == R.BLOCK_AUTODRILLER_HOOK and p[R.BP_HOFF] == 8e5 and p[R.BP_WOBSET] == 1e5
    mode, p = block_params(validate(RigConfig, {"block_mode": "trip", "trip_speed_m_per_s": -0.5}))
    assert mode == R.BLOCK_VELOCITY and p[R.BP_VSET] == -0.5
    mode, p = block_params(validate(RigConfig, {"autodriller": {"measurement": "wob"}}))
    assert mode == R.BLOCK_AUTODRILLER_WOB
    case = case_from_dict(CASE)
    mode, p, info = top_drive_params(RigConfig(), case)
    assert mode == R.TOP_DRIVE_STIFF and p[R.TP_J] == pytest.approx(10.5**2 * 8.0 + 50.0)
    mode, p, info = top_drive_params(validate(RigConfig, {"top_drive": {"tuning": "soft_torque"}}), case)
    from drillfatigue.dynamics.top.setup import string_torsional_properties
    props = string_torsional_properties(case)
    assert mode == R.TOP_DRIVE_PI
    assert p[R.TP_KP] == pytest.approx(props["impedance_Nms_per_rad"])
    assert p[R.TP_KI] == pytest.approx(p[R.TP_J] * props["first_mode_rad_s"] ** 2)
    mode, p, info = top_drive_params(validate(RigConfig, {"top_drive": {"tuning": "soft_torque",
                                                                        "stick_slip_period_s": 5.0}}), case)
    assert info["stick_slip_omega_rad_s"] == pytest.approx(2 * math.pi / 5.0)


def test_drilling_window_metrics_on_known_signals() -> None:
    t = np.arange(0.0, 110.0, 0.5)
    wob = np.where((t >= 10.0) & (t < 30.0), 0.0, 1e5)  # off bottom 20 s of the 100 s after t_skip
    m = R.drilling_window_metrics(t, wob, np.full(t.size, 0.01), np.full(t.size, 5e3),
                                  np.linspace(0.0, 20.0, t.size), 30.0, 1e5,
                                  string_top_above_rotary_m=np.full(t.size, -0.5))
    assert m["on_bottom_fraction"] == pytest.approx(0.8, abs=0.5 / 100.0)  # one sample of 200
    assert m["mean_wob_N"] == pytest.approx(0.8e5, rel=0.01)
    assert m["wob_error_rel"] == pytest.approx(-0.2, abs=0.01)
    assert m["mean_rop_m_per_s"] == pytest.approx(0.01) and m["mean_surface_torque_Nm"] == pytest.approx(5e3)
    assert m["block_within_travel"] and m["string_top_below_rotary"]
    m = R.drilling_window_metrics(t, wob, wob, wob, np.linspace(-1.0, 31.0, t.size), 30.0, 1e5,
                                  string_top_above_rotary_m=np.linspace(-1, 3, t.size))
    assert not m["block_within_travel"] and not m["string_top_below_rotary"]
    with pytest.raises(ValueError, match="t_skip_s"):
        R.drilling_window_metrics(t[:10], wob[:10], wob[:10], wob[:10], wob[:10], 30.0, 1e5)
