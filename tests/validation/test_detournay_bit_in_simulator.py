"""The Detournay depth-of-cut bit law drilling through the rig boundaries (docs/rig.md).

Law (Detournay & Defourny, Int. J. Rock Mech. Min. Sci. 29 (1992) 13; the bit-level form
of Richard, Germay & Detournay, J. Sound Vib. 305 (2007) 432): cutting plus frictional
contact,

    W = zeta eps a d + sigma a l,    T = eps a^2 d / 2 + mu gamma a (sigma a l) / 2,
    ROP = d Omega / (2 pi)

(the wear flats carry ``sigma a l`` once the bit cuts). Closed-form steady state written
here from that algebra: at WOB ``W`` and bit speed ``Omega`` the depth of cut per revolution
is ``d = (W - sigma a l) / (zeta eps a)``.

Run: a 300 m vertical string (60 m of 6 3/4 in collars, 240 m of 5 in pipe; 18 segments, no
wall contact, flat rock face), the stiff top drive at 120 rpm, the autodriller on the
downhole WOB with gains for a 0.5 rad/s critically damped loop (string stiffness from the
model) and its default 0.5 s measurement filter and 0.1 s control period, drilling at 90 kN,
the set-point stepped to 100 kN at 1 s. After the loop settled (the last 5 s of 25 s): the
mean WOB, the depth of cut (drilled length over the revolutions of the bit), the mean ROP
and the mean TOB against the closed form at the mean WOB and bit speed. Bounds: the WOB
within 0.5 % of its set-point (the integral action removes the error; what is left is the
loop's tail); the depth of cut, ROP and TOB within 0.5 % of the closed form (the law is
linear in W, so the mean over the axial ringing of the string is the law at the mean WOB;
the 0.5 % leaves room for the correlation of the ringing WOB with the bit speed). Measured:
WOB -4e-6, depth of cut, ROP and TOB within 1e-5 of the closed form (6.720 mm/rev,
48.38 m/h, 8.25 kN m). The filter matters: the Detournay bit adds almost no axial damping
(dROP/dWOB is 1.5e-10 m/(N s), 300x less than the Yigit-Christoforou law's), the string rings
axially by +-11 kN, and without the filter the command hits the ROP limit at every peak,
where the anti-windup stops the integral; the mean WOB then settles 8 % low (measured).
Off bottom (the same string lifted 1 m, block held) the rock face does not move.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path

COLLAR = {"type": "collar", "od_m": 0.17145, "id_m": 0.0714}
PIPE = {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086}
A = 0.10795  # 8 1/2 in bit radius, m
EPS, ZETA, SIGMA, WEAR, MUG = 200e6, 0.6, 60e6, 2e-3, 0.6
BIT = {"model": "detournay", "bit_radius_m": A, "detournay_eps_Pa": EPS, "detournay_zeta": ZETA,
       "detournay_sigma_Pa": SIGMA, "detournay_wear_flat_m": WEAR, "detournay_mu_gamma": MUG}
RPM = 120.0
W0, W1, T_STEP, T_END, T_AVG = 90e3, 100e3, 1.0, 25.0, 5.0


def _base(rig: dict[str, Any], duration: float, bit_md: float = 310.0,
          on_bottom: bool = True) -> dict[str, Any]:
    op = {"duration_s": duration, "bit_md_m": bit_md, "top_md_m": 10.0, "rpm": RPM,
          "rpm_ramp_s": 0.0}
    if not on_bottom:
        op.update(bit_on_bottom=False, top_axial="fixed")
    return {
        "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 500.0}}},
        "string": {"components": [dict(COLLAR, length_m=60.0, n_segments=6),
                                  dict(PIPE, length_m=240.0, n_segments=12)]},
        "operation": op, "bit": BIT, "solver": {"relax_s": 0.0}, "rig": rig,
    }


def _stiffness(model: Any) -> float:
    n = model.n0
    return 1.0 / (float((1.0 / model.jp[: n - 1, L.J_KA]).sum()) + 1.0 / model.jp[n - 1, L.J_KA]
                  + 1.0 / model.bp[L.B_KROCK])


def closed_form(wob_N: float, omega_rad_s: float) -> tuple[float, float, float]:
    """Depth of cut (m/rev), ROP (m/s), TOB (N m) of the law at a steady WOB and speed."""
    wf = SIGMA * A * WEAR
    d = (wob_N - wf) / (ZETA * EPS * A)
    return d, d * omega_rad_s / (2.0 * math.pi), 0.5 * EPS * A * A * d + 0.5 * MUG * A * wf


def test_detournay_bit_drills_at_the_closed_form_depth_of_cut() -> None:
    probe = case_from_dict(_base({"block_mode": "held", "rock": {"lobe_amplitude_m": 0.0}}, 1.0,
                                 on_bottom=False))
    k = _stiffness(build_model(probe, straight_path(500.0))[0])
    omega = RPM * math.pi / 30.0
    c_rop = omega / (2.0 * math.pi * ZETA * EPS * A)  # dROP/dWOB of the law
    wn = 0.5
    cfg = case_from_dict(_base({
        "block_mode": "autodriller", "rock": {"lobe_amplitude_m": 0.0},
        "autodriller": {"measurement": "wob", "wob_set_N": W0,
                        "kp_m_per_s_per_N": 2.0 * wn / k - c_rop,
                        "ki_m_per_s2_per_N": wn * wn / k}}, T_END))
    model, state = build_model(cfg, straight_path(500.0))
    advance_model(model, state, round(T_STEP / model.dt), every=10)
    model.bp[L.B_BLKP + R.BP_WOBSET] = W1
    ch = advance_model(model, state, round((T_END - T_STEP) / model.dt), every=1)["channels"]
    t = ch[:, 0]
    sel = t >= T_END - T_AVG
    wob = float(ch[sel, 1 + L.H_WOB].mean())
    om = float(ch[sel, 1 + L.H_BITRPM].mean()) * math.pi / 30.0
    md = ch[sel, 1 + L.H_BITMD]
    drilled = float(md[-1] - md[0])
    revs = om * float(t[sel][-1] - t[sel][0]) / (2.0 * math.pi)
    rop = float(ch[sel, 1 + L.H_ROP].mean())
    tob = float(ch[sel, 1 + L.H_TOB].mean())
    d_ref, rop_ref, tob_ref = closed_form(wob, om)
    print(f"WOB {wob:.1f} N ({wob / W1 - 1:+.2e}), d {drilled / revs * 1e3:.4f} vs "
          f"{d_ref * 1e3:.4f} mm/rev ({drilled / revs / d_ref - 1:+.2e}), ROP {rop * 3600:.3f} vs "
          f"{rop_ref * 3600:.3f} m/h ({rop / rop_ref - 1:+.2e}), TOB {tob:.1f} vs {tob_ref:.1f} N m "
          f"({tob / tob_ref - 1:+.2e})")
    assert np.all(ch[sel, 1 + L.H_WOB] > 0.0)  # on bottom all along
    assert wob == pytest.approx(W1, rel=5e-3)
    assert drilled / revs == pytest.approx(d_ref, rel=5e-3)
    assert rop == pytest.approx(rop_ref, rel=5e-3)
    assert tob == pytest.approx(tob_ref, rel=5e-3)


def test_detournay_bit_off_bottom_cuts_nothing() -> None:
    cfg = case_from_dict(_base({"block_mode": "held", "rock": {"lobe_amplitude_m": 0.0}}, 0.5,
                               bit_md=309.0, on_bottom=False))
    model, state = build_model(cfg, straight_path(500.0))
    ch = advance_model(model, state, round(0.5 / model.dt), every=10)["channels"]
    assert np.all(ch[:, 1 + L.H_WOB] == 0.0)
    assert np.all(ch[:, 1 + L.H_ROP] == 0.0) and np.all(ch[:, 1 + L.H_TOB] == 0.0)
