"""Buckling onset loads against their closed forms (Dawson & Paslay 1984; Chen et al. 1990;
Wu & Juvkam-Wold 1993; Lubinski 1950; curved-hole balance of docs/rig.md).

The closed forms are evaluated here by independent arithmetic (hand-written
numbers, not the module's functions) and the module must match them to
round-off: tolerance 1e-12 relative for the explicit formulas, 1e-9 for the
general quartic solver (np.roots plus one Newton step on a quartic whose
coefficients span ~20 orders of magnitude).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.softstring import buckling as B

# 5 in 19.5 lb/ft drill pipe (docs/model.md#bodies) in 8 1/2 in hole, 1.2 SG mud
OD, ID = 0.127, 0.1086
EI = 207e9 * math.pi / 64.0 * (OD**4 - ID**4)
W = 250.0  # N/m buoyed weight, typical of this pipe with tool joints
RC = (0.2159 - 0.1683) / 2.0  # clearance to the tool joints


def test_dawson_paslay_number_for_5in_pipe_at_60_deg() -> None:
    # EI = 207e9 * pi/64 * (0.127^4 - 0.1086^4) = 1.22997e6 N m^2 (hand arithmetic)
    assert EI == pytest.approx(1.22997e6, rel=1e-5)
    expected = 2.0 * math.sqrt(EI * W * math.sin(math.radians(60.0)) / RC)
    got = B.sinusoidal_onset_straight_N(EI, W, math.radians(60.0), RC)
    assert got == pytest.approx(expected, rel=1e-12)
    assert got == pytest.approx(211.56e3, rel=1e-4)  # 2 sqrt(1.22997e6*250*0.86603/0.0238)


def test_helical_forms_are_their_multiples_of_dawson_paslay() -> None:
    inc = math.radians(90.0)
    fs = B.sinusoidal_onset_straight_N(EI, W, inc, RC)
    assert B.helical_onset_straight_N(EI, W, inc, RC, "chen") == pytest.approx(math.sqrt(2.0) * fs,
                                                                                rel=1e-12)
    assert B.helical_onset_straight_N(EI, W, inc, RC, "wu") == pytest.approx(
        (2.0 * math.sqrt(2.0) - 1.0) * fs, rel=1e-12)


def test_vertical_forms() -> None:
    x = (EI * W * W) ** (1.0 / 3.0)
    assert B.vertical_onset_N(EI, W, "sinusoidal") == pytest.approx(1.94 * x, rel=1e-12)
    assert B.vertical_onset_N(EI, W, "helical") == pytest.approx(5.55 * x, rel=1e-12)


@pytest.mark.parametrize("dls_deg_per_30m", [1.0, 3.0, 8.0])
@pytest.mark.parametrize("inc_deg", [30.0, 60.0, 90.0])
def test_curved_hole_build_and_drop_closed_forms(dls_deg_per_30m: float, inc_deg: float) -> None:
    k = math.radians(dls_deg_per_30m) / 30.0
    inc = math.radians(inc_deg)
    ws = W * math.sin(inc)
    for c in (B.C_SINUSOIDAL, B.C_HELICAL_CHEN):
        a = RC / (c * c * EI)
        build = (k + math.sqrt(k * k + 4.0 * a * ws)) / (2.0 * a)  # a F^2 = w sinI + F k
        drop = (-k + math.sqrt(k * k + 4.0 * a * ws)) / (2.0 * a)  # a F^2 = w sinI - F k
        assert B.onset_curved_plane_N(EI, W, inc, RC, k, "build", c) == pytest.approx(build, rel=1e-12)
        assert B.onset_curved_plane_N(EI, W, inc, RC, k, "drop", c) == pytest.approx(drop, rel=1e-12)
        # the balance itself holds at the computed loads
        assert a * build**2 == pytest.approx(ws + build * k, rel=1e-12)
        assert a * drop**2 == pytest.approx(ws - drop * k, rel=1e-12)
        # the general vector solver: build = centre of curvature on the high side
        t = np.array([math.sin(inc), 0.0, math.cos(inc)])
        low = np.array([0.0, 0.0, 1.0]) - t[2] * t
        g = W * low
        high = -low / np.linalg.norm(low)
        assert B.onset_load_N(EI, RC, g, k * high, c) == pytest.approx(build, rel=1e-9)
        assert B.onset_load_N(EI, RC, g, -k * high, c) == pytest.approx(drop, rel=1e-9)
        assert drop < B.onset_load_N(EI, RC, g, np.zeros(3), c) < build


def test_straight_limit_of_the_curved_form() -> None:
    inc = math.radians(45.0)
    fs = B.sinusoidal_onset_straight_N(EI, W, inc, RC)
    assert B.onset_curved_plane_N(EI, W, inc, RC, 1e-9, "build") == pytest.approx(fs, rel=1e-6)
    assert B.onset_curved_plane_N(EI, W, inc, RC, 1e-9, "drop") == pytest.approx(fs, rel=1e-6)
    assert B.onset_curved_plane_N(EI, W, inc, RC, 0.0, "drop") == pytest.approx(fs, rel=1e-12)


def test_turn_in_a_horizontal_hole_adds_curvature_force_at_right_angles() -> None:
    # horizontal hole turning in azimuth: F k is horizontal, w is vertical: q = sqrt(w^2 + F^2 k^2)
    k = math.radians(5.0) / 30.0
    g = np.array([0.0, 0.0, W])
    f = B.onset_load_N(EI, RC, g, np.array([0.0, k, 0.0]))
    a = RC / (4.0 * EI)
    assert (a * f * f) ** 2 == pytest.approx(W * W + f * f * k * k, rel=1e-9)


def test_helix_pitch_and_contact_force() -> None:
    f = 300e3
    assert B.helix_pitch_m(f, EI) == pytest.approx(math.pi * math.sqrt(8.0 * EI / f), rel=1e-12)
    assert B.helix_pitch_m(f, EI) == pytest.approx(17.99, rel=1e-3)  # pi sqrt(8*1.2301e6/3e5)
    assert B.helical_contact_force_N_per_m(f, EI, RC) == pytest.approx(RC * f * f / (4 * EI), rel=1e-12)
