"""Rock face under the bit (lobed profile, contact, depth of cut, ROP from WOB) and the
connection event sequence."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config.base import validate
from drillfatigue.config.bit import BitConfig
from drillfatigue.config.rig import ConnectionConfig, RigConfig
from drillfatigue.dynamics.bit import laws as BR
from drillfatigue.dynamics.top import connection as C
from drillfatigue.dynamics.bit import rockface as RF
from drillfatigue.errors import InputError


def test_lobed_face_has_n_lobes_zero_mean_and_peak_to_peak_2a() -> None:
    phi = np.linspace(0.0, 2.0 * np.pi, 3601)[:-1]
    h = np.array([RF.rock_face_height(p, 1e-3, 3) for p in phi])
    assert h.mean() == pytest.approx(0.0, abs=1e-15)
    assert h.max() - h.min() == pytest.approx(2e-3, rel=1e-6)
    peaks = np.flatnonzero((h > np.roll(h, 1)) & (h > np.roll(h, -1)))
    assert peaks.size == 3


def test_contact_force_never_pulls_and_is_zero_off_bottom() -> None:
    out = np.empty(2)
    assert RF.rock_face_contact(-1e-3, 0.0, 0.0, 10.0, 1e-3, 3, 1e8, 1e5, out) == 0
    assert out[0] == 0.0
    # pressed in but moving away fast: the dash-pot would pull, the face does not
    assert RF.rock_face_contact(1e-5, -1.0, 0.0, 0.0, 0.0, 3, 1e8, 1e5, out) == 1
    assert out[0] == 0.0
    assert RF.rock_face_contact(1e-4, 0.0, 0.0, 0.0, 0.0, 3, 1e8, 1e5, out) == 1
    assert out[0] == pytest.approx(1e4)


def _off_bottom_fraction(force_N: float, omega: float, m: float = 2000.0, a: float = 1e-3,
                         n: int = 3, k: float = 1e9) -> float:
    """A bit mass pressed by a constant force on the lobed face turning at omega; time off bottom."""
    c = 2.0 * 0.2 * math.sqrt(k * m)
    dt = 2e-6
    u = force_N / k  # static penetration
    ud = 0.0
    out = np.empty(2)
    t_end = 6.0 * 2.0 * math.pi / (n * omega)  # six lobe periods
    steps = int(t_end / dt)
    off = 0
    for i in range(steps):
        phi = omega * i * dt
        on = RF.rock_face_contact(u, ud, phi, omega, a, n, k, c, out)
        ud += dt * (force_N - out[0]) / m
        u += dt * ud
        if i > steps // 3 and not on:
            off += 1
    return off / (steps - steps // 3)


def test_bit_leaves_bottom_only_above_the_lobe_acceleration_limit() -> None:
    # closed form: the face's largest acceleration A (n Omega)^2 against F / m; with
    # m = 2 t, A = 1 mm, n = 3 and F = 20 kN the limit is Omega = sqrt(F / (m A)) / n = 33.3 rad/s.
    # 20 % below it the bit stays on (the stiff contact follows the face), 20 % above it leaves.
    w_lim = math.sqrt(20e3 / (2000.0 * 1e-3)) / 3.0
    assert _off_bottom_fraction(20e3, 0.8 * w_lim) == 0.0
    assert _off_bottom_fraction(20e3, 1.2 * w_lim) > 0.02


#: An 8 1/2 in PDC bit in a medium-hard rock, in the ranges Detournay, Richard & Shepherd
#: (Int. J. Rock Mech. Min. Sci. 45 (2008) 1347) identified: bit radius a (m), intrinsic
#: specific energy eps (Pa), zeta, contact strength sigma (Pa), wear flat l (m), mu gamma.
PDC = {"a": 0.10795, "eps": 200e6, "zeta": 0.6, "sigma": 60e6, "l": 2e-3, "mg": 0.6}


def _detournay(wob_N: float, omega_rad_s: float, out: np.ndarray) -> None:
    BR.detournay_law(PDC["a"], PDC["eps"], PDC["zeta"], PDC["sigma"], PDC["l"], PDC["mg"],
                     wob_N, omega_rad_s, out)


def test_detournay_points_lie_on_the_friction_line() -> None:
    # Detournay & Defourny (1992): E = (1 - mu gamma zeta) eps + mu gamma S in the cutting phase
    a, eps, zeta, mg = PDC["a"], PDC["eps"], PDC["zeta"], PDC["mg"]
    out = np.empty(3)
    for wob in (2e4, 5e4, 1e5, 2e5):
        _detournay(wob, 15.7, out)
        tob, rop, d = out
        e_spec = 2.0 * tob / (a * a * d)
        s_str = wob / (a * d)
        assert e_spec == pytest.approx((1.0 - mg * zeta) * eps + mg * s_str, rel=1e-12)
        assert rop == pytest.approx(d * 15.7 / (2.0 * math.pi), rel=1e-12)


def test_detournay_no_cut_below_the_wear_flat_limit_and_continuous_above() -> None:
    wf = PDC["sigma"] * PDC["a"] * PDC["l"]
    out = np.empty(3)
    _detournay(0.9 * wf, 15.7, out)
    assert out[1] == 0.0 and out[0] == pytest.approx(0.5 * PDC["mg"] * PDC["a"] * 0.9 * wf)
    below = out.copy()
    _detournay(wf * (1 + 1e-9), 15.7, out)
    assert out[0] == pytest.approx(0.5 * PDC["mg"] * PDC["a"] * wf, rel=1e-6)
    assert out[1] < 1e-9 and below[0] < out[0]
    _detournay(1e5, 15.7, out)  # operating point of these numbers: 6.7 mm/rev, 60 m/h
    assert out[2] == pytest.approx(6.7e-3, rel=0.01)
    assert out[1] * 3600.0 == pytest.approx(60.0, rel=0.01)
    _detournay(1e5, -1.0, out)  # backwards: friction only, resisting
    assert out[0] < 0.0 and out[1] == 0.0


def test_rop_from_wob_is_the_bit_law_and_zero_below_thresholds() -> None:
    bit = BitConfig(model="yigit_christoforou")
    rop, tob = RF.rop_tob_from_wob(bit, np.array([0.0, 1e3, 1e5]), 150.0)
    assert rop[0] == 0.0 and rop[1] == 0.0  # off bottom; below the 5 kN threshold
    om = 150.0 * 2 * math.pi / 60.0
    assert rop[2] == pytest.approx(1.4e-8 * 1e5 * math.sqrt(om), rel=1e-12)  # c1 WOB sqrt(Omega)
    assert RF.rop_slope_m_per_N_s(bit, 1e5, 150.0) == pytest.approx(1.4e-8 * math.sqrt(om), rel=1e-6)
    with pytest.raises(ValueError, match="yigit_christoforou"):
        RF.rop_tob_from_wob(BitConfig(), 1e5, 150.0)


def test_detournay_bit_model_is_the_law_with_a_continuous_torque_through_rest() -> None:
    # bit.model detournay through the simulator's bit kernel: at drilling speed exactly the
    # unregularised law (detournay_law) with the same parameters (the default 8 1/2 in bit:
    # 6.7 mm/rev and 60 m/h at 100 kN and 150 rpm, docs/rig.md); the torque rises through zero
    # speed as tanh(omega / 0.5 rad/s); backwards only the wear-flat friction; off bottom nothing
    bit = BitConfig(model="detournay")
    mid, p = BR.pack_bit_params(bit)
    assert mid == BR.DETOURNAY
    om = 150.0 * 2 * math.pi / 60.0
    out, ref = np.empty(2), np.empty(3)
    BR.bit_response(mid, p, 1e5, om, out)
    _detournay(1e5, om, ref)  # PDC above: BitConfig's detournay defaults
    assert out[0] == pytest.approx(ref[0], rel=1e-12) and out[1] == pytest.approx(ref[1], rel=1e-12)
    assert ref[2] == pytest.approx(6.72e-3, rel=1e-3) and out[1] * 3600 == pytest.approx(60.5, rel=1e-2)
    rop, tob = RF.rop_tob_from_wob(bit, 1e5, 150.0)
    assert float(rop) == out[1] and float(tob) == out[0]
    # dROP/dWOB = Omega / (2 pi zeta eps a)
    assert RF.rop_slope_m_per_N_s(bit, 1e5, 150.0) == pytest.approx(
        om / (2 * math.pi * 0.6 * 200e6 * bit.bit_radius_m), rel=1e-6)
    BR.bit_response(mid, p, 1e5, 0.0, out)
    assert out[0] == 0.0 and out[1] == 0.0
    BR.bit_response(mid, p, 1e5, 1e-4, out)
    assert out[0] == pytest.approx(ref[0] * math.tanh(1e-4 / 0.5), rel=1e-9)
    BR.bit_response(mid, p, 1e5, -om, out)
    wf = 60e6 * bit.bit_radius_m * 2e-3
    assert out[0] == pytest.approx(-0.5 * 0.6 * bit.bit_radius_m * wf, rel=1e-12) and out[1] == 0.0
    BR.bit_response(mid, p, 0.0, om, out)
    assert out[0] == 0.0 and out[1] == 0.0


# --- connections --------------------------------------------------------------------------


def test_connection_sequence_phases_rpm_block_and_slips() -> None:
    cfg = ConnectionConfig(enabled=True)
    sch = C.connection_schedule(100.0, cfg)
    assert sch.duration_s == pytest.approx(cfg.duration_s)
    names = [n for n, _, _ in sch.phases()]
    assert names == ["pickup", "stop", "slips", "stand", "slips_out", "ramp", "tag"]
    out = np.empty(C.N_CC)
    ts = np.linspace(90.0, 100.0 + cfg.duration_s + 10.0, 20001)
    ph = np.array([C.connection_controls(t, sch.t_start_s, sch.params, out) for t in ts])
    rec = []
    for t in ts:
        C.connection_controls(t, sch.t_start_s, sch.params, out)
        rec.append(out.copy())
    rec = np.array(rec)
    # phases in order, each once
    seq = [int(p) for i, p in enumerate(ph) if i == 0 or p != ph[i - 1]]
    assert seq == [0, 1, 2, 3, 4, 5, 6, 7, 0]
    # rotation: full while picking up, ramps 1 -> 0, zero in slips, ramps back, full when drilling
    rpm = rec[:, C.CC_RPM_FACTOR]
    assert np.all(rpm[ph == C.PH_PICKUP] == 1.0)
    assert np.all(rpm[(ph == C.PH_SLIPS) | (ph == C.PH_STAND)] == 0.0)
    assert np.all(np.abs(np.diff(rpm)) < 0.01)  # continuous ramps (no jump), sampled every 0.015 s
    # block: up by pickup_m, held, down by pickup_m: the integral of its velocity command is zero
    v = np.nan_to_num(rec[:, C.CC_BLOCK_V])
    dt = ts[1] - ts[0]
    assert np.sum(v[ph == C.PH_PICKUP]) * dt == pytest.approx(-cfg.pickup_m, rel=2e-3)
    assert np.sum(v) * dt == pytest.approx(0.0, abs=2e-3)
    assert np.all(rec[ph == C.PH_DRILL, C.CC_BLOCK_V] != rec[ph == C.PH_DRILL, C.CC_BLOCK_V])  # NaN
    # slips only in slips/stand; the stand length is removed from the block travel after the stand
    assert np.all((rec[:, C.CC_SLIPS] == 1.0) == ((ph == C.PH_SLIPS) | (ph == C.PH_STAND)))
    after = ts >= sch.t_start_s[4]
    assert np.all(rec[after, C.CC_TRAVEL_SHIFT] == cfg.stand_length_m)
    assert np.all(rec[~after, C.CC_TRAVEL_SHIFT] == 0.0)


def test_planned_connections_at_a_steady_rop() -> None:
    cfg = ConnectionConfig(enabled=True)
    rop = 30.0 / 3600.0
    starts = C.plan_connections(7000.0, 30.0, 0.0, 28.5, rop, cfg)
    # first after 30 m at 30 m/h (3600 s), then one stand (3420 s) + one connection (160 s) later
    assert starts == pytest.approx([3600.0])
    starts = C.plan_connections(8000.0, 30.0, 0.0, 28.5, rop, cfg)
    assert starts == pytest.approx([3600.0, 3600.0 + 160.0 + 3420.0])


def test_a_stand_that_does_not_fit_the_block_travel_is_refused() -> None:
    with pytest.raises(InputError) as exc:
        validate(RigConfig, {"block": {"travel_m": 25.0}, "connection": {"enabled": True}}, "rig")
    assert exc.value.field == "rig.connection"
