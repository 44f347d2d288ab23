"""A long straight segment in a build: the contact-point spacing rule keeps
what can pass the wall unseen below its share of the clearance.

Reference: plane geometry of a chord in a circle (docs/bending.md): a
chord of length s of a circle of curvature kappa sits s^2 kappa / 8 inside the
arc at its middle, so along a straight segment the inner-wall penetration can
exceed its values at two tested points s apart by at most s^2 kappa/8 (times
1 + c kappa, c the clearance: the inner wall's radius is 1/kappa - c; a 1e-3
correction here, covered by the 1 % tolerance).
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.config.string import StringConfig
from drillfatigue.string import build_segments
from drillfatigue.string.contacts import contact_points

HOLE = 0.2159
KAPPA = math.radians(8.0) / 30.0  # 8 deg/30 m build


def _penetration(x: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Wall penetration of points x (n, 2) in the build plane with radius r: the
    hole centre line is the circle of radius 1/kappa about the origin."""
    d = np.abs(np.hypot(x[:, 0], x[:, 1]) - 1.0 / KAPPA)
    return d + r - 0.5 * HOLE


def test_collar_segment_in_a_build_is_held_by_its_contact_points() -> None:
    cfg = StringConfig(preset="paper_bha")
    seg = build_segments(cfg, 1200.0)
    cp = contact_points(cfg, seg, HOLE, KAPPA)
    k = int(np.flatnonzero(seg.component_type_code == 1)[-1])  # a 9.33 m collar segment
    s_pts, r_pts, _ = cp.of_segment(k)
    L = float(seg.length_m[k])
    r_body = float(seg.od_m[k]) / 2
    clearance = 0.5 * HOLE - r_body
    rng = np.random.default_rng(7)
    worst_excess = 0.0
    for _ in range(300):
        # a chord whose ends lie anywhere across the hole: a rigid segment in any
        # position the contact forces might leave it in
        a0 = rng.uniform(0.0, 0.2)
        e0, e1 = rng.uniform(-1.0, 1.0, 2) * clearance
        p0 = (1.0 / KAPPA + e0) * np.array([math.cos(a0), math.sin(a0)])
        a1 = a0 + L * KAPPA
        p1 = (1.0 / KAPPA + e1) * np.array([math.cos(a1), math.sin(a1)])
        u = (p1 - p0) / np.linalg.norm(p1 - p0)
        s_fine = np.linspace(0.0, L, 4001)
        fine = _penetration(p0 + s_fine[:, None] * u, np.full(s_fine.size, r_body))
        tested = _penetration(p0 + s_pts[:, None] * u, r_pts)
        worst_excess = max(worst_excess, fine.max() - tested.max())
    f_c = 0.25 * clearance  # the rule's share of the clearance
    assert worst_excess <= 1.01 * f_c
    # without the extra points (ends only) a chord can pass much deeper unseen
    assert L * L * KAPPA / 8.0 > 2.0 * f_c
