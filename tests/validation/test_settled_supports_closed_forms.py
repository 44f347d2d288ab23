"""Continuous beams on supports at different heights against closed forms.

References
----------
* Force method on the simply supported beam (Timoshenko, *Strength of Materials*,
  part I, 3rd ed. 1955, art. 55 "continuous beams", settlement of supports), with
  the simple beam's deflections of Roark's *Formulas for Stress and Strain*, 8th ed.,
  table 8.1: uniform load w over the span l, deflection at x
  w x (l^3 - 2 l x^2 + x^3) / (24 EI) (case 2e); point load P at a, b = l - a,
  deflection under it P a^2 b^2 / (3 EI l) (case 1e). The middle support of a beam on
  three supports is the redundant: its reaction R makes the simple beam pass through
  the support's height; the moment over it is the simple beam's w a b / 2 + R a b / l.
  This route never forms the three-moment equation the kernel solves.
* Beam-column (Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed. 1961,
  section 1.10-1.13): EI w'''' - T w'' = q. Two equal spans pinned at their outer
  ends, the middle support displaced by Delta: by symmetry each span is pinned at
  its outer end with zero slope at the middle, where w = Delta. With k^2 = |T|/EI,
  v = k L, the general solution w = A + B x + C sinh kx + D cosh kx - q x^2/(2T)
  (sin and cos in compression) with w(0) = 0, w''(0) = 0, w'(L) = 0, w(L) = Delta
  gives the moment over the middle support M = -EI w''(L); without load
  M = EI Delta v^2 / (L^2 (v coth v - 1)) in tension, EI Delta v^2 / (L^2 (1 - v cot v))
  in compression, 3 EI Delta / L^2 without axial force.

Tolerances: the closed forms and the kernel are both exact; what differs is
rounding, in the closed forms' cancellation (v coth v - 1 for small v) and in the
kernel's power series below |T L^2/EI| = 0.02 (truncation below 1e-13): 1e-9
relative.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.dynamics.span.beam import chain_span_moments, continuous_beam_moments

EI = 207e9 * math.pi / 64.0 * (0.17145 ** 4 - 0.0714 ** 4)  # 6 3/4 in collar, N m^2
W = 1244.0  # its buoyed weight per length in 1.2 SG mud, N/m


@pytest.mark.parametrize("q_y, d", [
    (0.0, (0.0, 0.021, 0.0)),           # a stabilizer's stand-off, no load
    (-W, (0.0, 0.021, 0.0)),            # the same under the weight (load -y: the stand-off
    (-W, (0.0, -0.021, 0.0)),           # lifts against it) and a support below its chord
    (-W, (0.004, -0.012, 0.017)),       # three heights
    (350.0, (-0.01, 0.0, 0.013)),       # load +y, supports on a line but the middle one
])
def test_three_supports_at_different_heights_force_method(q_y: float, d: tuple) -> None:
    L1, L2 = 7.0, 11.0
    l = L1 + L2
    a, b = L1, L2
    # simple beam from support 0 to support 2: deflection at the middle support (along +y)
    chord = d[0] + (d[2] - d[0]) * a / l
    defl_q = q_y * a * (l ** 3 - 2 * l * a ** 2 + a ** 3) / (24 * EI)
    flex = a ** 2 * b ** 2 / (3 * EI * l)
    R = (d[1] - chord - defl_q) / flex  # force of the middle support on the beam, +y
    m_support = q_y * a * b / 2 + R * a * b / l  # sagging: curving towards +y
    x = 3.0  # a read point in the first span
    m_read = q_y * x * (l - x) / 2 + R * x * b / l
    offsets = np.zeros((3, 2))
    offsets[:, 1] = d
    r = continuous_beam_moments([L1, L2], EI, np.array([[0.0, q_y]] * 2), 0.0,
                                read_span=[0], read_x_m=[x], support_offsets_m=offsets)
    # module convention: M_x is the sagging moment of the +y load component
    scale = abs(m_support) + 3 * EI * 0.02 / l ** 2
    assert r.support_Nm[1, 0] == pytest.approx(m_support, abs=1e-9 * scale)
    assert r.read_Nm[0, 0] == pytest.approx(m_read, abs=1e-9 * scale)
    assert r.support_Nm[0, 0] == 0.0 and r.support_Nm[2, 0] == 0.0
    np.testing.assert_allclose(r.support_Nm[:, 1], 0.0, atol=1e-15)
    # the same offsets on the x component turn the moment vector: (M_x, M_y) -> (., -M)
    offsets_x = offsets[:, ::-1].copy()
    rx = continuous_beam_moments([L1, L2], EI, np.array([[q_y, 0.0]] * 2), 0.0,
                                 support_offsets_m=offsets_x)
    assert -rx.support_Nm[1, 1] == pytest.approx(m_support, abs=1e-9 * scale)


def _two_span_beam_column(L: float, T: float, q: float, delta: float) -> float:
    """Moment over the middle support of two equal pinned spans (module docstring)."""
    if T == 0.0:
        return 3 * EI * delta / L ** 2 - q * L ** 2 / 8
    k = math.sqrt(abs(T) / EI)
    if T > 0:
        f = (math.sinh, math.cosh)
        d1 = (lambda x: k * math.cosh(k * x), lambda x: k * math.sinh(k * x))
        d2 = (lambda x: k * k * math.sinh(k * x), lambda x: k * k * math.cosh(k * x))
    else:
        f = (math.sin, math.cos)
        d1 = (lambda x: k * math.cos(k * x), lambda x: -k * math.sin(k * x))
        d2 = (lambda x: -k * k * math.sin(k * x), lambda x: -k * k * math.cos(k * x))
    # w = A + B x + C f0(kx) + D f1(kx) - q x^2 / (2 T)
    D = (q / T) / d2[1](0.0)  # w''(0) = D f1''(0) - q / T = 0
    A = -D * f[1](0.0)        # w(0) = 0
    # w'(L) = 0 and w(L) = delta for B, C
    lhs = np.array([[1.0, d1[0](L)], [L, f[0](k * L)]])
    rhs = np.array([q * L / T - D * d1[1](L), delta - A - D * f[1](k * L) + q * L ** 2 / (2 * T)])
    B, C = np.linalg.solve(lhs, rhs)
    assert abs(B) >= 0.0
    return -EI * (C * d2[0](L) + D * d2[1](L) - q / T)


@pytest.mark.parametrize("T", [0.0, 1e4, 2e5, 2e6, -1e5, -5e5])
@pytest.mark.parametrize("q, delta", [(0.0, 0.021), (W, 0.021), (W, -0.008)])
def test_two_spans_middle_support_displaced_beam_column(T: float, q: float,
                                                        delta: float) -> None:
    """Load and displacement along +y (the middle support displaced towards the side the
    load pushes: delta > 0 sags the beam over it)."""
    L = 9.0
    want = _two_span_beam_column(L, T, q, delta)
    if q == 0.0 and T != 0.0:
        v = L * math.sqrt(abs(T) / EI)
        den = v / math.tanh(v) - 1.0 if T > 0 else 1.0 - v / math.tan(v)
        assert want == pytest.approx(EI * delta * v ** 2 / (L ** 2 * den), rel=1e-9)
    offsets = np.zeros((3, 2))
    offsets[1, 1] = delta
    r = continuous_beam_moments([L, L], EI, np.array([[0.0, q]] * 2), T,
                                support_offsets_m=offsets)
    scale = abs(want) + 3 * EI * abs(delta) / L ** 2
    assert r.support_Nm[1, 0] == pytest.approx(want, abs=1e-9 * scale)


def test_chain_of_segments_with_offsets_matches_the_beam() -> None:
    """The chain form (supports given along a string of segments of different
    properties, spans taking them over their length) with offsets is the beam on those
    spans with those offsets: two spans over three collar segments."""
    bounds = np.array([0.0, 4.0, 9.0, 16.0])
    sup = np.array([0.0, 9.0, 16.0])
    offsets = np.array([[0.0, 0.0], [0.003, 0.021], [0.0, -0.002]])
    q = np.array([[10.0, -W]] * 3)
    sup_M, read_M, cut = chain_span_moments(sup, bounds, np.full(3, EI), np.full(3, 3e4), q,
                                            np.array([9.0, 12.0]), support_offsets_m=offsets)
    r = continuous_beam_moments([9.0, 7.0], EI, q[:2], 3e4, read_span=[1], read_x_m=[3.0],
                                support_offsets_m=offsets)
    assert np.all(cut == 0)
    np.testing.assert_allclose(sup_M, r.support_Nm, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(read_M[1], r.read_Nm[0], rtol=1e-12, atol=1e-9)
