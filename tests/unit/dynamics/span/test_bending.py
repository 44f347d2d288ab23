"""Span-bending kernels and their Python layer: loads, statuses, errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.dynamics.span import bending as K
from drillfatigue.errors import InputError
from drillfatigue.dynamics.span.beam import (chain_span_moments, continuous_beam_moments,
                                         spans_from_supports)


def test_transverse_load_keeps_the_normal_part_of_weight_inertia_and_drag() -> None:
    inc = math.radians(60.0)
    axis = np.array([[math.sin(inc), 0.0, math.cos(inc)]])  # x north, z down (TVD)
    e1 = np.array([[0.0, 1.0, 0.0]])
    e2 = np.array([[-math.cos(inc), 0.0, math.sin(inc)]])  # high side is -e2
    g = np.array([0.0, 0.0, 1.0])
    inertia = np.array([[3.0, 5.0, 0.0]])
    drag = np.array([[0.0, -1.0, 2.0]])
    q = np.empty((1, 2))
    K.transverse_load(np.array([266.0]), axis, g, inertia, drag, e1, e2, q)
    f = 266.0 * g + inertia[0] + drag[0]
    f_n = f - (f @ axis[0]) * axis[0]
    # w sin(inc) of the weight is normal to the axis (the weight's lateral part)
    assert q[0] == pytest.approx([f_n @ e1[0], f_n @ e2[0]], rel=1e-14)
    assert (266.0 * g - (266.0 * g @ axis[0]) * axis[0]) @ e2[0] == pytest.approx(
        266.0 * math.sin(inc))


def test_axial_factors_against_extended_precision() -> None:
    """Series (|s| < SERIES_S) and closed forms against the closed forms in 40-digit
    arithmetic (mpmath): within 1e-12 on both sides of the switch and far off it."""
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 40

    def exact(s: float) -> list[float]:
        v = mp.sqrt(abs(mp.mpf(s)))
        if s > 0:
            f = (3 * (v / mp.tanh(v) - 1) / v**2, 6 * (1 - v / mp.sinh(v)) / v**2,
                 24 * (v / 2 - mp.tanh(v / 2)) / v**3)
        else:
            f = (3 * (1 - v / mp.tan(v)) / v**2, 6 * (v / mp.sin(v) - 1) / v**2,
                 24 * (mp.tan(v / 2) - v / 2) / v**3)
        return [float(x) for x in f]

    for s in (1e-7, 1e-3, 0.999 * K.SERIES_S, 1.001 * K.SERIES_S, 0.3, 4.0, 60.0):
        for sign in (1.0, -1.0):
            if sign * s <= -(math.pi**2) * 0.99:
                continue
            np.testing.assert_allclose(K.axial_factors(sign * s), exact(sign * s), rtol=1e-12)
    assert all(math.isnan(x) for x in K.axial_factors(-(math.pi ** 2)))
    # very stiff tension spans stay finite (no overflow in sinh/cosh)
    assert all(math.isfinite(x) for x in K.axial_factors(1e6))


def test_errors_are_input_errors() -> None:
    with pytest.raises(InputError, match="span_m"):
        continuous_beam_moments([9.0, -1.0], 1e6, [[0.0, -1.0], [0.0, -1.0]])
    with pytest.raises(InputError, match="Euler"):
        continuous_beam_moments([9.0], 1e6, [0.0, -1.0], axial_N=-1e6)
    with pytest.raises(InputError, match="ends"):
        continuous_beam_moments([9.0], 1e6, [0.0, -1.0], ends=("free", "pinned"))
    with pytest.raises(InputError, match="read point"):
        continuous_beam_moments([9.0], 1e6, [0.0, -1.0], read_span=[0], read_x_m=[9.5])
    with pytest.raises(InputError, match="support_s_m"):
        spans_from_supports([0.0, 2.0, 2.0])
    with pytest.raises(InputError, match="support_s_m"):
        chain_span_moments(np.array([0.0, 20.0]), np.array([0.0, 9.0, 18.0]),
                           np.full(2, 1e6), np.zeros(2), np.zeros((2, 2)), np.array([1.0]))


def test_clamped_single_span_and_deflection() -> None:
    # clamped-clamped: wL^2/12 at the ends, wL^2/24 at mid span, deflection wL^4/384EI
    L, EI, w = 9.0, 1.2e6, 300.0
    r = continuous_beam_moments([L], EI, [0.0, -w], ends=("clamped", "clamped"),
                                read_span=[0], read_x_m=[L / 2])
    assert r.support_Nm[:, 0] == pytest.approx([w * L * L / 12] * 2, rel=1e-12)
    assert r.read_Nm[0, 0] == pytest.approx(-w * L * L / 24, rel=1e-12)
    assert r.midspan_deflection_m[0] == pytest.approx(w * L**4 / (384 * EI), rel=1e-12)
    # simply supported: 5 w L^4 / 384 EI
    r = continuous_beam_moments([L], EI, [0.0, -w])
    assert r.midspan_deflection_m[0] == pytest.approx(5 * w * L**4 / (384 * EI), rel=1e-12)
