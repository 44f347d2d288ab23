"""Property: the O(1) point-in-cylinder search equals brute-force distance to the centre line."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.contact.wall import build_cylinder_chain, find_contact

R_HOLE = 0.108
R_PIPE = 0.0635


def chain_points(turns_deg, seg_len):
    """3D centre line: each joint turns the direction by the given (dinc, dazi) in degrees."""
    pts = [np.zeros(3)]
    inc, azi = 0.3, 0.0
    for dinc, dazi in turns_deg:
        d = np.array([math.sin(inc) * math.cos(azi), math.sin(inc) * math.sin(azi), math.cos(inc)])
        pts.append(pts[-1] + seg_len * d)
        inc += math.radians(dinc)
        azi += math.radians(dazi)
    return np.array(pts)


def brute_distance(x, pts):
    """Minimum distance from x to the polyline through pts (clamped point-segment distances)."""
    best = np.inf
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        ab = b - a
        t = np.clip((x - a) @ ab / (ab @ ab), 0.0, 1.0)
        best = min(best, float(np.linalg.norm(x - a - t * ab)))
    return best


turn = st.tuples(st.floats(-12.0, 12.0), st.floats(-12.0, 12.0))


@settings(max_examples=50, deadline=None)
@given(
    turns=st.lists(turn, min_size=1, max_size=6),
    seg_len=st.floats(0.5, 3.0),
    where=st.floats(0.02, 0.98),
    offset=st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2), st.floats(-0.2, 0.2)),
    hint=st.integers(-2, 10),
)
def test_matches_brute_force_polyline_distance(turns, seg_len, where, offset, hint):
    pts = chain_points(turns, seg_len)
    chain = build_cylinder_chain(pts, R_HOLE)
    n = len(chain[2])
    # a point near the centre line, somewhere along the chain
    s_tot = where * n * seg_len
    i = min(int(s_tot // seg_len), n - 1)
    x = pts[i] + (s_tot - i * seg_len) * chain[1][i] + np.array(offset)
    out = np.empty(6)
    idx = find_contact(x, R_PIPE, *chain, hint, out)
    assume(idx >= 0)  # a point beyond the chain's ends (offset pushes it out): nothing to compare
    d = brute_distance(x, pts)
    # tolerance: round-off of dot products on O(10 m) coordinates
    assert abs(out[5] - d) < 1e-9
    assert abs(out[0] - (d - (R_HOLE - R_PIPE))) < 1e-9
    if out[5] > 1e-9:
        assert abs(np.linalg.norm(out[1:4]) - 1.0) < 1e-12
    # the same answer whatever the starting hint
    out_full = np.empty(6)
    find_contact(x, R_PIPE, *chain, idx, out_full)
    np.testing.assert_allclose(out_full, out, atol=1e-12)
