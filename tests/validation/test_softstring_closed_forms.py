"""Soft-string torque and drag against the closed forms of docs/validation.md.

References: Johancsik, Friesen & Dawson, SPE 11380 (1984) for the cell
equations; the capstan (Euler-Eytelwein) formula for a weightless rope on a bend.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.softstring.march import soft_string_march, soft_string_torque_drag
from drillfatigue.well.survey import tangent_vectors

W = 300.0  # buoyed weight per length, N/m
R = 0.084  # tool-joint contact radius, m
MU = 0.3


def straight(inc_deg: float, length: float = 1000.0, n: int = 50):
    md = np.linspace(0.0, length, n + 1)
    inc = np.full(n + 1, math.radians(inc_deg))
    azi = np.full(n + 1, 0.7)
    return md, inc, azi, np.full(n, W), np.full(n, R)


@pytest.mark.parametrize("inc_deg", [0.0, 30.0, 60.0, 90.0])
def test_straight_inclined_hole_gradients(inc_deg):
    md, inc, azi, w, r = straight(inc_deg)
    td = soft_string_torque_drag(md, inc, azi, w, r, MU, MU, wob_N=2e4, tob_Nm=3e3)
    I = math.radians(inc_deg)
    L = md[-1] - md
    # same discrete formula as the closed form: only round-off (1e-9 relative)
    tol = dict(rtol=1e-9, atol=1e-9 * W * 1000)
    np.testing.assert_allclose(td.tension_pickup_N, (W * math.cos(I) + MU * W * math.sin(I)) * L, **tol)
    np.testing.assert_allclose(td.tension_slackoff_N, (W * math.cos(I) - MU * W * math.sin(I)) * L, **tol)
    np.testing.assert_allclose(td.tension_rotating_N, W * math.cos(I) * L, **tol)
    np.testing.assert_allclose(td.tension_drilling_N, W * math.cos(I) * L - 2e4, **tol)
    np.testing.assert_allclose(td.torque_rotating_Nm, MU * W * math.sin(I) * R * L, **tol)
    np.testing.assert_allclose(td.torque_drilling_Nm, MU * W * math.sin(I) * R * L + 3e3, **tol)
    np.testing.assert_allclose(td.normal_rotating_N_per_m, W * math.sin(I), rtol=1e-9, atol=1e-9 * W)


def test_vertical_hole_hook_load_is_buoyed_weight_minus_wob():
    md, inc, azi, w, r = straight(0.0, 800.0, 37)
    w = np.linspace(250.0, 1400.0, 37)  # collars at the bottom heavier: any profile
    td = soft_string_torque_drag(md, inc, azi, w, r, MU, MU, wob_N=8e4)
    buoyed = float(np.sum(w * np.diff(md)))
    s = td.summary()
    for mode in ("pickup", "slackoff", "rotating"):
        assert s[f"hookload_{mode}_N"] == pytest.approx(buoyed, rel=1e-12)
    assert s["hookload_drilling_N"] == pytest.approx(buoyed - 8e4, rel=1e-12)
    assert s["surface_torque_rotating_Nm"] == 0.0
    # neutral point where the drilling tension changes sign
    k = np.flatnonzero(td.tension_drilling_N < 0)[0]
    cells = w * np.diff(md)
    assert np.sum(cells[k:]) < 8e4 <= np.sum(cells[k - 1:])


def bend(theta: float, n_cell: int, length: float = 100.0):
    """Horizontal-plane bend of total angle theta (azimuth turns), in horizontal hole."""
    md = np.linspace(0.0, length, n_cell + 1)
    inc = np.full(n_cell + 1, math.pi / 2)
    azi = np.linspace(theta, 0.0, n_cell + 1)  # from top to bit
    return md, inc, azi


@pytest.mark.parametrize("theta_deg", [30.0, 90.0])
def test_capstan_weightless_pipe(theta_deg):
    theta = math.radians(theta_deg)
    errs = []
    for n_cell in (10, 100, 1000):
        md, inc, azi = bend(theta, n_cell)
        td = soft_string_torque_drag(md, inc, azi, np.zeros(n_cell), np.full(n_cell, R), MU, MU,
                                     wob_N=-1e4)  # 10 kN tension at the lower end
        ratio_up = td.tension_drilling_N[0] / 1e4
        # pick-up / slack-off need a tension at the lower end: drilling mode has it but no
        # axial friction; run the pick-up march with the same bit tension directly
        t = np.empty(n_cell + 1)
        m = np.empty(n_cell + 1)
        nn = np.empty(n_cell)
        tan = np.ascontiguousarray(tangent_vectors(inc, azi))
        soft_string_march(tan, md, np.zeros(n_cell), np.full(n_cell, R), MU, 0.0, 1e4, 0.0, t, m, nn)
        pick = t[0] / 1e4
        soft_string_march(tan, md, np.zeros(n_cell), np.full(n_cell, R), -MU, 0.0, 1e4, 0.0, t, m, nn)
        slack = t[0] / 1e4
        assert ratio_up == pytest.approx(1.0, abs=1e-12)  # rotating: no axial friction
        errs.append((abs(pick / math.exp(MU * theta) - 1), abs(slack / math.exp(-MU * theta) - 1)))
    # converges as the cells shrink; with 1000 cells the error is ~ mu^2 theta^2/(2 n) < 3e-4
    assert errs[2][0] < errs[1][0] < errs[0][0]
    assert errs[2][1] < errs[1][1] < errs[0][1]
    bound = MU**2 * theta**2 / (2 * 1000) * 1.5
    assert errs[2][0] < bound and errs[2][1] < bound


def test_build_section_tension_lifts_pipe_off_low_side():
    """In a build, tension pulls the pipe to the high side and reduces the side force."""
    n = 200
    md = np.linspace(0, 200.0, n + 1)
    inc = np.linspace(math.radians(40), math.radians(60), n + 1)
    azi = np.zeros(n + 1)
    lo = soft_string_torque_drag(md, inc, azi, np.full(n, W), np.full(n, R), MU, MU, wob_N=0.0)
    hi = soft_string_torque_drag(md, inc, azi, np.full(n, W), np.full(n, R), MU, MU, wob_N=-2e4)
    assert hi.normal_drilling_N_per_m[-1] < lo.normal_drilling_N_per_m[-1]


def test_bad_arrays_rejected():
    md, inc, azi, w, r = straight(30.0)
    with pytest.raises(ValueError):
        soft_string_torque_drag(md[::-1], inc, azi, w, r, MU, MU)
    with pytest.raises(ValueError):
        soft_string_torque_drag(md, inc, azi, w[:-1], r, MU, MU)
