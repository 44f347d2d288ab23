"""Tangency length of the span from the bit (``span_record.tangency_length_m``)
against the beam's boundary-value problem solved independently.

Reference: the beam EI y'''' = q pinned at x = 0 (y = 0, y'' = 0) whose offset,
slope and curvature at x = L are the wall's, y_w = r - kappa x^2 / 2
(docs/bending.md). With L from the kernel, the polynomial y = sum c_k x^k + q x^4 /
(24 EI) is fitted by a 4 x 4 linear solve (numpy) to y(0) = 0, y''(0) = 0,
y'(L) = -kappa L, y''(L) = -kappa; the remaining condition y(L) = r - kappa L^2 / 2
must then hold. Tolerance 1e-9 of r: double-precision round-off of the solve.
In a straight hole the length is the pendulum's (24 EI r / q)^(1/4) (Lubinski & Woods,
API Drilling and Production Practice 1953, no weight on bit).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.span.record import tangency_length_m


def _offset_misfit(ei: float, r: float, q: float, kappa: float, length: float) -> float:
    L = length
    # unknowns c0..c3 of y = c0 + c1 x + c2 x^2 + c3 x^3 + q x^4 / (24 EI)
    a = np.array([[1.0, 0.0, 0.0, 0.0],            # y(0)
                  [0.0, 0.0, 2.0, 0.0],            # y''(0)
                  [0.0, 1.0, 2.0 * L, 3.0 * L * L],  # y'(L)
                  [0.0, 0.0, 2.0, 6.0 * L]])       # y''(L)
    p4 = q / (24.0 * ei)
    b = np.array([0.0, 0.0, -kappa * L - 4.0 * p4 * L ** 3, -kappa - 12.0 * p4 * L * L])
    c = np.linalg.solve(a, b)
    y_l = c[0] + c[1] * L + c[2] * L * L + c[3] * L ** 3 + p4 * L ** 4
    return y_l - (r - 0.5 * kappa * L * L)


def test_straight_hole_is_the_pendulum_length() -> None:
    ei, r, q = 8.5e6, 0.0222, 1170.0  # 6 3/4 in collars, 8 1/2 in hole, 70 deg
    length = tangency_length_m(ei, r, q, 0.0)
    assert abs(length / (24.0 * ei * r / q) ** 0.25 - 1.0) < 1e-12
    assert abs(length - 7.89) < 0.01


@settings(max_examples=200, deadline=None)
@given(ei=st.floats(1e5, 1e8), r=st.floats(1e-3, 0.1), q=st.floats(10.0, 5e3),
       kappa=st.floats(-0.02, 0.02))
def test_tangency_conditions_hold(ei: float, r: float, q: float, kappa: float) -> None:
    length = tangency_length_m(ei, r, q, kappa)
    assert math.isfinite(length) and length > 0.0
    assert abs(_offset_misfit(ei, r, q, kappa, length)) <= 1e-9 * max(r, kappa * length ** 2)
    # the load onto the outer wall (kappa > 0) lengthens the span, onto the inner one
    # shortens it
    straight = tangency_length_m(ei, r, q, 0.0)
    assert (length - straight) * kappa >= -1e-12 * straight


def test_no_load_or_no_room_gives_no_tangency() -> None:
    assert math.isinf(tangency_length_m(8.5e6, 0.02, 0.0, 0.0))
    assert math.isinf(tangency_length_m(8.5e6, 0.0, 1000.0, 0.001))
