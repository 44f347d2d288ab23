"""Minimum curvature against welleng and against closed-form circular arcs.

References: Sawaryn & Thorogood, SPE Drilling & Completion 20(1) 2005 (the
method); welleng 0.30 ``welleng.utils.MinCurve`` (independent implementation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from welleng.utils import MinCurve

from drillfatigue.well import minimum_curvature


def _random_3d_survey(seed: int, n: int = 40) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    md = np.concatenate([[0.0], np.cumsum(rng.uniform(5.0, 60.0, n - 1))])
    inc = np.clip(np.cumsum(rng.normal(0.0, 0.08, n)), 0.0, math.pi)
    azi = np.mod(np.cumsum(rng.normal(0.0, 0.15, n)) + 1.0, 2.0 * math.pi)
    return md, inc, azi


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_positions_match_welleng(seed: int) -> None:
    md, inc, azi = _random_3d_survey(seed)
    ours = minimum_curvature(md, inc, azi)
    ref = MinCurve(md, inc, azi, frame="nev")
    # Both are the same closed-form step summed over <= 40 stations of
    # <= 60 m; double-precision round-off is ~1e-13 m per step, so 1e-8 m
    # leaves room for the two implementations' different operation order.
    np.testing.assert_allclose(ours.pos_m, np.asarray(ref.poss), atol=1e-8, rtol=0.0)
    # welleng's dogleg per interval (rad) divided by our interval = our DLS.
    np.testing.assert_allclose(ours.dls_rad_per_m[1:] * np.diff(md),
                               np.asarray(ref.dogleg)[1:], atol=1e-12)


def test_constant_build_arc_is_circle() -> None:
    """Vertical -> constant build in the north plane: N = R(1 - cos I), TVD = R sin I."""
    R = 400.0  # m, build rate 1/R rad/m = 4.30 deg/30 m
    md = np.linspace(0.0, R * math.pi / 2.0, 31)
    inc = md / R
    sv = minimum_curvature(md, inc, np.zeros_like(md))
    # Exact for minimum curvature on a true arc: only round-off (~1e-12 m).
    np.testing.assert_allclose(sv.pos_m[:, 0], R * (1.0 - np.cos(inc)), atol=1e-9)
    np.testing.assert_allclose(sv.pos_m[:, 2], R * np.sin(inc), atol=1e-9)
    np.testing.assert_allclose(sv.pos_m[:, 1], 0.0, atol=1e-12)


def test_dls_of_constant_build_section() -> None:
    dls_deg_per_30m = 6.0
    kappa = math.radians(dls_deg_per_30m) / 30.0
    md = np.array([0.0, 100.0, 110.0, 140.0, 200.0, 230.0])
    inc = np.where(md > 100.0, (md - 100.0) * kappa, 0.0)
    sv = minimum_curvature(md, inc, np.full(md.size, math.radians(30.0)))
    assert sv.dls_rad_per_m[0] == 0.0
    assert sv.dls_rad_per_m[1] == pytest.approx(0.0, abs=1e-15)
    # Unequal station spacing, same build rate: DLS is the same everywhere.
    np.testing.assert_allclose(sv.dls_deg_per_30m[2:], dls_deg_per_30m, rtol=1e-12)
    # 100 ft = 30.48 m, so deg/100 ft = deg/30 m * 30.48 / 30.
    np.testing.assert_allclose(sv.dls_deg_per_100ft[2:], dls_deg_per_30m * 30.48 / 30.0,
                               rtol=1e-12)


def test_3d_turn_matches_welleng_dls_and_start_offset() -> None:
    md = np.array([0.0, 30.0, 60.0, 90.0])
    inc = np.radians([10.0, 20.0, 30.0, 30.0])
    azi = np.radians([350.0, 10.0, 40.0, 40.0])  # crosses north
    start = np.array([100.0, -50.0, 20.0])
    sv = minimum_curvature(md, inc, azi, start_pos_m=start)
    ref = MinCurve(md, inc, azi, frame="nev")
    np.testing.assert_allclose(sv.pos_m - start, np.asarray(ref.poss), atol=1e-9)
    assert sv.dls_rad_per_m[-1] == pytest.approx(0.0, abs=1e-15)
