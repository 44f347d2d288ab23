"""The well path between two nodes whose tangents turn by nearly or exactly pi.

``path_point`` (the simulator's numba kernel) and ``arc_points`` (its numpy
twin, which places the wellbore's nodes) write the minimum-curvature arc with
``1 / sin(beta)``: near a half turn that factor carries a relative error of
~eps / (pi - beta), and at beta = pi it is the reciprocal of a rounding error.
The reference here is the circle itself, in closed form: a point at arc
length ``s`` of a circle of radius ``R = dMD / beta`` is ``2 R sin(theta/2)``
from the start and ``2 R sin((beta - theta)/2)`` from the end
(``theta = s / R``), and its tangent makes the angle ``theta`` with ``t1``.
Tolerances: 1e-12 for unit vectors, and for positions 1e-12 relative to dMD
(a few ulps of R times the O(1) trigonometric factors) plus the rounding of
coordinates 1 500 m from the origin (8 ulps of 1 500 m, 1.8e-12 m).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from drillfatigue.well.kernels import path_point
from drillfatigue.well.survey import _half_turn_steps, dogleg_rad
from drillfatigue.well.wellbore import arc_points

TOL = 1e-12
P1 = np.array([10.0, -20.0, 1500.0])
P_ROUND = 8.0 * np.finfo(float).eps * float(np.linalg.norm(P1))


def _unit(inc: float, azi: float) -> np.ndarray:
    return np.array([math.sin(inc) * math.cos(azi), math.sin(inc) * math.sin(azi),
                     math.cos(inc)])


def _turned_back(t1: np.ndarray, gap: float, roll: float) -> np.ndarray:
    """A unit vector at angle ``pi - gap`` from ``t1``, the off-axis part along ``roll``."""
    if gap == 0.0:
        return -t1
    a = np.cross(t1, [0.0, 0.0, 1.0] if abs(t1[2]) < 0.9 else [1.0, 0.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(t1, a)
    off = math.cos(roll) * a + math.sin(roll) * b
    return -math.cos(gap) * t1 + math.sin(gap) * off


def _nodes(t1: np.ndarray, t2: np.ndarray, dmd: float) -> tuple[np.ndarray, ...]:
    """Two path nodes joined by the survey's minimum-curvature step."""
    beta = float(dogleg_rad(t1, t2))
    p1 = P1
    p2 = p1 + _half_turn_steps(t1[None], t2[None], np.array([beta]), np.array([dmd]))[0]
    return np.array([0.0, dmd]), np.stack([p1, p2]), np.stack([t1, t2]), beta


def _kernel(md: float, node_md, node_pos, node_tan) -> tuple[np.ndarray, np.ndarray]:
    pos = np.empty(3)
    tan = np.empty(3)
    path_point(md, node_md, node_pos, node_tan, 0, pos, tan)
    return pos, tan


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, math.pi), st.floats(0.0, 2.0 * math.pi),
       st.one_of(st.just(0.0), st.floats(1e-300, 1e-3, exclude_max=True)),
       st.floats(0.0, 2.0 * math.pi), st.floats(0.1, 100.0), st.floats(0.0, 1.0))
@example(0.0, 0.0, 0.0, 0.0, 10.0, 0.5)           # straight down, then straight up
@example(math.pi / 2, 0.3, 0.0, 0.0, 10.0, 0.25)  # horizontal, exactly reversed
@example(1.0, 2.0, 1e-9, 1.0, 30.0, 0.7)
def test_path_point_near_a_half_turn_is_on_the_circle(inc, azi, gap, roll, dmd, frac) -> None:
    t1 = _unit(inc, azi)
    t2 = _turned_back(t1, gap, roll)
    node_md, node_pos, node_tan, beta = _nodes(t1, t2, dmd)
    R = dmd / beta
    s = frac * dmd
    th = s / R
    pos, tan = _kernel(s, node_md, node_pos, node_tan)

    assert abs(np.linalg.norm(tan) - 1.0) <= TOL
    angle = math.atan2(np.linalg.norm(np.cross(t1, tan)), float(np.dot(t1, tan)))
    assert abs(angle - th) <= 4 * TOL
    assert abs(np.linalg.norm(pos - node_pos[0]) - 2.0 * R * math.sin(0.5 * th)) <= TOL * dmd + P_ROUND
    assert abs(np.linalg.norm(pos - node_pos[1])
               - 2.0 * R * math.sin(0.5 * (beta - th))) <= TOL * dmd + P_ROUND
    # the numpy twin that places the wellbore's nodes gives the same point
    apos, atan = arc_points(node_pos[:1], t1[None], t2[None], np.array([dmd]), np.array([s]))
    np.testing.assert_allclose(apos[0], pos, rtol=0.0, atol=TOL * dmd + P_ROUND)
    np.testing.assert_allclose(atan[0], tan, rtol=0.0, atol=TOL)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, math.pi), st.floats(0.0, 2.0 * math.pi),
       st.one_of(st.just(0.0), st.floats(1e-300, 1e-3, exclude_max=True)),
       st.floats(0.0, 2.0 * math.pi), st.floats(0.1, 100.0))
def test_path_point_ends_on_the_next_node(inc, azi, gap, roll, dmd) -> None:
    """At s = dMD the kernel's arc lands on the node the survey placed, with tangent t2."""
    t1 = _unit(inc, azi)
    t2 = _turned_back(t1, gap, roll)
    node_md, node_pos, node_tan, _ = _nodes(t1, t2, dmd)
    pos, tan = _kernel(dmd * (1.0 - 1e-15), node_md, node_pos, node_tan)
    np.testing.assert_allclose(pos, node_pos[1], rtol=0.0, atol=TOL * dmd + P_ROUND)
    np.testing.assert_allclose(tan, t2, rtol=0.0, atol=TOL)


def test_exact_reversal_turns_in_the_vertical_plane_as_the_survey_does() -> None:
    """Horizontal north, then exactly south (t1 + t2 = 0), over 10 m: the path dips half a
    circle of radius 10/pi below the start (towards increasing tvd) and is vertical-down
    half way, in the plane the survey's step chooses for such tangents."""
    t = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    step = _half_turn_steps(t[:1], t[1:], np.array([math.pi]), np.array([10.0]))[0]
    node_pos = np.stack([np.zeros(3), step])
    r = 10.0 / math.pi
    np.testing.assert_allclose(step, [0.0, 0.0, 2.0 * r], rtol=0.0, atol=1e-14)
    pos, tan = _kernel(5.0, np.array([0.0, 10.0]), node_pos, t)
    np.testing.assert_allclose(pos, [r, 0.0, r], rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(tan, [0.0, 0.0, 1.0], rtol=0.0, atol=1e-12)
    pos, tan = _kernel(10.0 * (1.0 - 1e-15), np.array([0.0, 10.0]), node_pos, t)
    np.testing.assert_allclose(pos, step, rtol=0.0, atol=1e-12)
