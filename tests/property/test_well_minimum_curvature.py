"""Invariants of minimum curvature: a step is never longer than its MD interval."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from drillfatigue.well import minimum_curvature

angles = st.tuples(st.floats(0.0, math.pi), st.floats(0.0, 2.0 * math.pi - 1e-9))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 200.0), angles), min_size=1, max_size=25),
       angles)
# a half turn in one interval: tan(beta/2) * |t1 + t2| gave a chord 1.79 times dMD
@example(steps=[(1.0, (math.pi, 0.0))], first=(2.220446049250313e-16, 0.0))
@example(steps=[(1.0, (math.pi, 0.0))], first=(0.0, 0.0))
def test_step_length_at_most_md_interval(steps, first) -> None:
    dmd = np.array([s[0] for s in steps])
    md = np.concatenate([[0.0], np.cumsum(dmd)])
    inc = np.array([first[0]] + [s[1][0] for s in steps])
    azi = np.array([first[1]] + [s[1][1] for s in steps])
    sv = minimum_curvature(md, inc, azi)
    chord = np.linalg.norm(np.diff(sv.pos_m, axis=0), axis=1)
    # The chord is a difference of positions of size up to the total MD: each
    # carries ~eps * MD of round-off, so short steps far down the hole need an
    # absolute allowance of a few eps * MD besides the 1e-12 relative one.
    atol = 8.0 * np.finfo(float).eps * md[-1]
    # Chord of an arc: 2R sin(beta/2) <= R beta = dMD.
    assert np.all(chord <= dmd * (1.0 + 1e-12) + atol)
    straight = sv.dls_rad_per_m[1:] * dmd < 1e-9
    np.testing.assert_allclose(chord[straight], dmd[straight], rtol=1e-12, atol=atol)
    assert np.all(sv.dls_rad_per_m >= 0.0)


@settings(max_examples=30, deadline=None)
@given(angles, st.lists(st.floats(0.1, 100.0), min_size=1, max_size=10))
def test_straight_hole_positions_are_md_times_tangent(direction, dmd) -> None:
    md = np.concatenate([[0.0], np.cumsum(dmd)])
    inc = np.full(md.size, direction[0])
    azi = np.full(md.size, direction[1])
    sv = minimum_curvature(md, inc, azi)
    np.testing.assert_allclose(sv.pos_m, md[:, None] * sv.tangent[0], atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 2e-3), st.floats(0.0, 2.0 * math.pi - 1e-9), st.floats(0.0, math.pi),
       st.floats(0.01, 200.0))
def test_chord_near_a_half_turn_is_the_arcs(gap, azi, inc, dmd) -> None:
    """Two stations whose tangents are pi - gap apart, on both sides of the switch to the
    bisector form: the chord is the arc's, 2 dMD sin(beta/2) / beta (closed form), to
    1e-12 relative plus the round-off of beta itself near pi (~ulp(pi) / (pi - beta) of
    tan(beta/2) below the switch, where the ratio factor is still used)."""
    t1 = np.array([math.sin(inc) * math.cos(azi), math.sin(inc) * math.sin(azi), math.cos(inc)])
    # a second tangent pi - gap away from t1: rotate -t1 by gap about an axis normal to t1
    axis = np.cross(t1, [0.0, 0.0, 1.0] if abs(t1[2]) < 0.9 else [1.0, 0.0, 0.0])
    axis /= np.linalg.norm(axis)
    m = -t1
    t2 = (m * math.cos(gap) + np.cross(axis, m) * math.sin(gap)
          + axis * np.dot(axis, m) * (1.0 - math.cos(gap)))
    inc2 = math.acos(max(-1.0, min(1.0, t2[2])))
    azi2 = math.atan2(t2[1], t2[0]) % (2.0 * math.pi)
    sv = minimum_curvature(np.array([0.0, dmd]), np.array([inc, inc2]),
                           np.array([azi, azi2]))
    beta = sv.dls_rad_per_m[1] * dmd
    chord = float(np.linalg.norm(sv.pos_m[1] - sv.pos_m[0]))
    expected = 2.0 * dmd * math.sin(beta / 2.0) / beta
    tol = 1e-12 + 4.0 * np.finfo(float).eps / max(math.pi - beta, 1e-3)
    assert abs(chord - expected) <= tol * dmd + 8.0 * np.finfo(float).eps * dmd


def test_exact_half_turn_is_taken_in_the_vertical_plane() -> None:
    """Straight down then straight up over 10 m: the chord is 2 * 10 / pi m (a semicircle
    of radius 10 / pi), horizontal; north, where sin(pi) rounded (1.2e-16) tips the second
    tangent."""
    sv = minimum_curvature(np.array([0.0, 10.0]), np.array([0.0, math.pi]),
                           np.array([0.0, 0.0]))
    np.testing.assert_allclose(sv.pos_m[1], [20.0 / math.pi, 0.0, 0.0], rtol=1e-15,
                               atol=1e-14)


def test_exactly_antiparallel_tangents_turn_in_the_vertical_plane() -> None:
    """t1 + t2 == 0 exactly (no survey angles give it, a path's tangents may): the chord
    2 dMD / pi lies in t1's vertical plane, perpendicular to t1, towards increasing tvd;
    north when t1 is vertical."""
    from drillfatigue.well.survey import _half_turn_steps

    c = math.sqrt(0.5)
    t1 = np.array([[0.0, 0.0, 1.0], [c, 0.0, c], [0.0, -1.0, 0.0]])
    steps = _half_turn_steps(t1, -t1, np.full(3, math.pi), np.full(3, 10.0))
    expected = 20.0 / math.pi * np.array([[1.0, 0.0, 0.0], [-c, 0.0, c], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(steps, expected, rtol=1e-15, atol=1e-14)
