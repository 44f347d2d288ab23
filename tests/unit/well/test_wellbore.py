"""Cylinder chain of the wellbore and the point-on-path query."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config import WellConfig
from drillfatigue.well import build_wellbore, minimum_curvature
from drillfatigue.well.kernels import path_point


@pytest.fixture(scope="module")
def family_bores() -> dict:
    cfg = WellConfig()
    return {name: build_wellbore(cfg, name) for name in cfg.profiles}


def _arc_cfg(**kw) -> WellConfig:
    return WellConfig(profiles={"arc": {"kind": "build_horizontal", "kop_m": 0.0,
                                        "dls_deg_per_30m": 9.0, "horizontal_length_m": 50.0}},
                      **kw)


def test_chain_is_continuous(family_bores: dict) -> None:
    for wb in family_bores.values():
        np.testing.assert_array_equal(wb.p1_m[:-1], wb.p0_m[1:])
        np.testing.assert_array_equal(wb.md0_m[1:], wb.md1_m[:-1])
        np.testing.assert_allclose(np.linalg.norm(wb.axis, axis=1), 1.0, atol=1e-14)
        np.testing.assert_allclose(wb.p0_m + wb.axis * wb.length_m[:, None], wb.p1_m,
                                   atol=1e-9)
        # Nodes lie on the survey path, ends included.
        np.testing.assert_allclose(wb.node_pos_m[-1], wb.survey.pos_m[-1], atol=1e-9)
        assert wb.node_md_m[0] == wb.survey.md_m[0]
        assert wb.node_md_m[-1] == wb.survey.md_m[-1]
        assert np.all(wb.length_m <= 10.0 + 1e-9)


def test_chord_error_below_one_percent_of_clearance(family_bores: dict) -> None:
    clearance = WellConfig().min_clearance_m
    for wb in family_bores.values():
        assert wb.sagitta_limit_m == pytest.approx(0.01 * clearance)
        # Largest distance of the true path from each cylinder axis: sample the
        # arc at 5 interior points per cylinder (the maximum is at the middle).
        f = np.linspace(0.1, 0.9, 5)
        md = (wb.md0_m[:, None] + f * (wb.md1_m - wb.md0_m)[:, None]).ravel()
        pos, _ = wb.point_at_md(md)
        i = np.repeat(np.arange(wb.n), f.size)
        v = pos - wb.p0_m[i]
        s = np.einsum("ij,ij->i", v, wb.axis[i])
        dist = np.linalg.norm(v - s[:, None] * wb.axis[i], axis=1)
        assert dist.max() <= wb.sagitta_limit_m * (1.0 + 1e-9)
        # ... and the bound is used, not wildly undershot, in the builds.
        assert dist.max() > 0.5 * wb.sagitta_limit_m


def test_resampling_follows_clearance_argument() -> None:
    cfg = _arc_cfg()
    coarse = build_wellbore(cfg, min_clearance_m=0.05)
    fine = build_wellbore(cfg, min_clearance_m=0.005)
    kappa = math.radians(9.0) / 30.0
    for wb, c in ((coarse, 0.05), (fine, 0.005)):
        in_arc = wb.md1_m <= math.pi / 2 / kappa
        L = wb.md1_m[in_arc] - wb.md0_m[in_arc]
        assert np.all(L**2 * kappa / 8.0 <= 0.01 * c * (1 + 1e-9))
    assert fine.n > 2 * coarse.n


def test_point_at_md_on_circular_arc() -> None:
    """Build from vertical at 9 deg/30 m from the surface: a circle of radius R."""
    wb = build_wellbore(_arc_cfg())
    R = 30.0 / math.radians(9.0)
    md = np.array([0.0, 1.234, 57.3, 100.0, 150.05, R * math.pi / 2.0])
    pos, tan = wb.point_at_md(md)
    th = md / R
    # Interpolation is on the arc itself (not the chord): round-off only.
    # A chord interpolation would miss by up to the sagitta, 2e-4 m here.
    np.testing.assert_allclose(pos[:, 0], R * (1.0 - np.cos(th)), atol=1e-9)
    np.testing.assert_allclose(pos[:, 2], R * np.sin(th), atol=1e-9)
    np.testing.assert_allclose(tan[:, 0], np.sin(th), atol=1e-12)
    np.testing.assert_allclose(tan[:, 2], np.cos(th), atol=1e-12)
    np.testing.assert_allclose(wb.curvature_at_md(md[1:-1]), 1.0 / R, rtol=1e-9)
    # Beyond TD the path continues straight (horizontal here).
    p, t = wb.point_at_md(float(wb.node_md_m[-1]) + 10.0)
    np.testing.assert_allclose(p, wb.node_pos_m[-1] + [10.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(t, [1.0, 0.0, 0.0], atol=1e-12)


def test_point_at_md_matches_survey_stations(family_bores: dict) -> None:
    wb = family_bores["profile_3"]
    pos, _ = wb.point_at_md(wb.survey.md_m)
    np.testing.assert_allclose(pos, wb.survey.pos_m, atol=1e-9)


def test_path_point_kernel_equals_point_at_md(family_bores: dict) -> None:
    wb = family_bores["profile_2"]
    rng = np.random.default_rng(3)
    mds = np.concatenate([rng.uniform(-20.0, wb.node_md_m[-1] + 20.0, 300),
                          wb.node_md_m[::37]])
    ref_pos, ref_tan = wb.point_at_md(mds)
    out_pos, out_tan = np.empty(3), np.empty(3)
    hint = 0
    for k, md in enumerate(mds):
        # Alternate a good hint (previous) and arbitrary ones, including bad values.
        h = hint if k % 2 else int(rng.integers(-5, wb.n + 5))
        hint = path_point(md, wb.node_md_m, wb.node_pos_m, wb.node_tan, h, out_pos, out_tan)
        np.testing.assert_allclose(out_pos, ref_pos[k], atol=1e-9)
        np.testing.assert_allclose(out_tan, ref_tan[k], atol=1e-12)
        assert 0 <= hint < wb.n
        if wb.node_md_m[0] <= md <= wb.node_md_m[-1]:
            assert wb.node_md_m[hint] <= md <= wb.node_md_m[hint + 1]


def test_cylinder_index_and_hole_sections() -> None:
    cfg = _arc_cfg(hole=[{"md_top_m": 0.0, "diameter_m": 0.3111},
                         {"md_top_m": 123.4, "diameter_m": 0.2159}])
    wb = build_wellbore(cfg)
    assert 123.4 in wb.node_md_m  # the hole change is a node
    assert wb.hole_radius_at_md(100.0) == pytest.approx(0.3111 / 2)
    assert wb.hole_radius_at_md(150.0) == pytest.approx(0.2159 / 2)
    i = wb.cylinder_index(np.array([-1.0, 0.0, 123.4, 1e6]))
    assert i[0] == 0 and i[1] == 0 and i[-1] == wb.n - 1
    assert wb.md0_m[i[2]] == pytest.approx(123.4)
    for md in (0.3, 60.0, 61.7, 200.0):
        k = wb.cylinder_index(md)
        assert wb.md0_m[k] <= md < wb.md1_m[k]


def test_wellbore_from_given_survey_straight_segments_are_single_nodes_per_10m() -> None:
    md = np.array([0.0, 95.0])
    sv = minimum_curvature(md, np.zeros(2), np.zeros(2))
    wb = build_wellbore(WellConfig(), survey=sv)
    assert wb.n == 10  # 95 m straight hole, cap 10 m
    np.testing.assert_allclose(wb.length_m, 9.5)
