"""Invariants of minimum curvature: a step is never longer than its MD interval."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.well import minimum_curvature

angles = st.tuples(st.floats(0.0, math.pi), st.floats(0.0, 2.0 * math.pi - 1e-9))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 200.0), angles), min_size=1, max_size=25),
       angles)
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
