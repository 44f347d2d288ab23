"""The deepest point of a straight segment between its tested points
(``contact.deepest_point``) against the exact geometry of a line and a circular arc.

Reference: a hole centre line that is a circle of radius rho = 1 / kappa about C;
a straight axis at distance d from C (inside the bend, the inner wall side). The
axis's offset from the centre line towards C is rho - |P(u) - C|, largest at the
foot of the perpendicular from C, where it is rho - d (closed form). Expanding,
|P - C| = sqrt(d^2 + (u - u0)^2) = d + (u - u0)^2 / (2 d) - (u - u0)^4 / (8 d^3) + ...:
the parabola through three points s apart misses the largest offset by at most the
quartic term, s^4 / (8 d^3) (about 1 um for s = 3 m, rho = 215 m): tolerance
2 s^4 / (8 d^3) on the offset and 2 % of the spacing on where it is.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.contact.wall import deepest_point

HOLE_R = 0.10795


def _chord(kappa: float, gap_m: float, u0: float, offs: np.ndarray) -> tuple[np.ndarray, float]:
    """Axis offsets from the wall g(u) = (rho - |P - C|) - R of a line whose closest
    approach to C is at u0, ``gap_m`` beyond the centre line's offset rho - d."""
    rho = 1.0 / kappa
    d = rho - gap_m
    dist = rho - np.sqrt(d * d + (offs - u0) ** 2)
    return dist - HOLE_R, gap_m - HOLE_R


@settings(max_examples=300, deadline=None)
@given(kappa=st.floats(1e-3, 2e-2), gap=st.floats(0.0, 0.12), n=st.integers(3, 8),
       spacing=st.floats(0.5, 3.0), frac=st.floats(0.05, 0.95), k=st.integers(0, 6))
def test_vertex_is_the_arcs_deepest_point(kappa: float, gap: float, n: int, spacing: float,
                                          frac: float, k: int) -> None:
    offs = (np.arange(n) - 0.5 * (n - 1)) * spacing
    # the true deepest point strictly inside an interval between two points
    j = min(k, n - 2)
    u0 = offs[j] + frac * spacing
    g, g_true = _chord(kappa, gap, u0, offs)
    rng = np.random.default_rng(n * 1000 + j)
    order = rng.permutation(n)  # the kernel does not need the points sorted
    kd, u, gv = deepest_point(np.ascontiguousarray(offs[order]), np.ascontiguousarray(g[order]),
                              n)
    d = 1.0 / kappa - gap
    tol_g = 2.0 * (2.0 * spacing) ** 4 / (8.0 * d ** 3)
    if kd < 0:
        # no vertex only where it would not be deeper than the best point by the tolerance
        assert g_true - g.max() <= tol_g
        return
    assert g[order][kd] == g.max()
    assert abs(gv - g_true) <= tol_g
    assert abs(u - u0) <= 0.02 * spacing
    assert gv > g.max()


def test_straight_hole_has_no_vertex_between_points() -> None:
    # a line's offset from a straight cylinder's axis is convex: largest at an end
    offs = np.linspace(-2.0, 2.0, 5)
    dist = np.hypot(0.01 + 0.003 * offs, 0.004 - 0.001 * offs)
    kd, _, _ = deepest_point(offs, dist - HOLE_R, 5)
    assert kd == -1


def test_fewer_than_three_points_have_no_vertex() -> None:
    offs = np.array([1.0, -1.0])
    assert deepest_point(offs, np.array([-0.001, -0.002]), 2)[0] == -1


def test_build_chord_of_the_simulator_test() -> None:
    # 4.35 m collar segment, 4 points (spacing 1.45 m), in an 8 deg / 30 m build:
    # the middle passes the wall between the two inner points by s^2 kappa / 8 less
    # their offset from the vertex
    kappa = math.radians(8.0) / 30.0
    offs = np.array([2.175, 0.725, -0.725, -2.175])
    g, g_true = _chord(kappa, 0.0002 + HOLE_R, 0.2, offs)
    kd, u, gv = deepest_point(offs, g, 4)
    assert kd >= 0 and abs(u - 0.2) < 1e-3 and abs(gv - g_true) < 1e-6
    assert g_true - g.max() > 0.5e-3  # what the tested points alone would miss (mm)
