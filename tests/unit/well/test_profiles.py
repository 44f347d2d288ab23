"""Profile builders, including the case-2 family with shared end points."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.well import build_survey, key_points, profile_report


def _one(spec: dict, **kw) -> WellConfig:
    return WellConfig(profiles={"p": spec}, **kw)


def test_family_shares_surface_and_end_point() -> None:
    cfg = WellConfig(family={"tvd_end_m": 700.0, "displacement_m": 450.0, "azi_deg": 30.0})
    az = math.radians(30.0)
    target = np.array([450.0 * math.cos(az), 450.0 * math.sin(az), 700.0])
    for name in ("profile_1", "profile_2", "profile_3"):
        sv = build_survey(cfg, name)
        np.testing.assert_array_equal(sv.pos_m[0], 0.0)
        assert np.linalg.norm(sv.pos_m[-1] - target) < 0.1  # the requirement
        assert np.linalg.norm(sv.pos_m[-1] - target) < 1e-6  # what the solver reaches
        assert math.degrees(sv.inc_rad[-1]) == pytest.approx(90.0, abs=1e-9)


def test_family_members_differ_as_in_the_paper() -> None:
    cfg = WellConfig()
    rep = profile_report(cfg)
    kops = {n: key_points(cfg, n)[1].md_m for n in rep}
    # (1) early kick-off, gradual build; (2) later kick-off, higher dogleg;
    # (3) two builds with a tangent.
    assert kops["profile_1"] < kops["profile_2"]
    assert rep["profile_1"]["max_dls_deg_per_30m"] < rep["profile_2"]["max_dls_deg_per_30m"]
    labels = [k.label for k in key_points(cfg, "profile_3")]
    assert labels == ["surface", "KOP", "end of build 1", "end of tangent", "end of build 2",
                      "TD"]
    # Member 1: R = tvd_end - kop = 300 m, so DLS = 30 / 300 rad per 30 m.
    assert rep["profile_1"]["max_dls_deg_per_30m"] == pytest.approx(
        math.degrees(30.0 / 300.0), rel=1e-9)
    for r in rep.values():
        assert 900.0 < r["td_m"] < 1100.0


def test_family_member_that_cannot_land_is_rejected() -> None:
    with pytest.raises(InputError, match=r"well\.profiles\.p\.kop_m"):
        build_survey(_one({"kind": "family_member", "member": 2, "kop_m": 700.0}))
    with pytest.raises(InputError, match="displacement"):
        build_survey(_one({"kind": "family_member", "member": 1, "kop_m": 50.0},
                          family={"displacement_m": 100.0}))


def test_j_profile_geometry() -> None:
    cfg = _one({"kind": "j", "kop_m": 300.0, "dls_deg_per_30m": 3.0, "inc_deg": 30.0,
                "azi_deg": 90.0, "td_m": 900.0})
    sv = build_survey(cfg)
    R = 30.0 / math.radians(3.0)
    build = math.radians(30.0) * R
    hold = 900.0 - 300.0 - build
    i = math.radians(30.0)
    expected = np.array([0.0, R * (1 - math.cos(i)) + hold * math.sin(i),
                         300.0 + R * math.sin(i) + hold * math.cos(i)])
    np.testing.assert_allclose(sv.pos_m[-1], expected, atol=1e-8)
    assert sv.md_m[-1] == pytest.approx(900.0)
    assert sv.max_dls_deg_per_30m == pytest.approx(3.0, rel=1e-9)
    assert np.all(np.diff(sv.md_m) <= 30.0 + 1e-9)
    with pytest.raises(InputError, match="td_m"):
        build_survey(_one({"kind": "j", "kop_m": 300.0, "dls_deg_per_30m": 3.0,
                           "inc_deg": 30.0, "td_m": 350.0}))


def test_build_horizontal_and_vertical() -> None:
    sv = build_survey(_one({"kind": "build_horizontal", "kop_m": 200.0, "dls_deg_per_30m": 10.0,
                            "azi_deg": 180.0, "horizontal_length_m": 100.0}))
    R = 30.0 / math.radians(10.0)
    np.testing.assert_allclose(sv.pos_m[-1], [-(R + 100.0), 0.0, 200.0 + R], atol=1e-8)
    sv = build_survey(_one({"kind": "vertical", "td_m": 123.0}))
    np.testing.assert_allclose(sv.pos_m[-1], [0.0, 0.0, 123.0])
    assert sv.max_dls_deg_per_30m == 0.0


def test_s_shape_returns_to_final_inclination() -> None:
    sv = build_survey(_one({"kind": "s_shape", "final_inc_deg": 10.0}))
    assert math.degrees(sv.inc_rad[-1]) == pytest.approx(10.0, abs=1e-9)
    assert math.degrees(sv.inc_rad.max()) == pytest.approx(40.0, abs=1e-9)
    assert sv.max_dls_deg_per_30m == pytest.approx(5.0, rel=1e-9)


def test_build_turn_is_three_dimensional_with_constant_dls() -> None:
    sv = build_survey(_one({"kind": "build_turn", "azi_start_deg": 10.0, "azi_end_deg": 80.0}))
    assert math.degrees(sv.azi_rad[-1]) == pytest.approx(80.0, abs=1e-9)
    assert math.degrees(sv.inc_rad[-1]) == pytest.approx(70.0, abs=1e-9)
    assert sv.pos_m[-1, 1] > 50.0 and sv.pos_m[-1, 0] > 50.0
    curved = sv.dls_deg_per_30m[sv.dls_deg_per_30m > 1e-9]
    np.testing.assert_allclose(curved, 5.0, rtol=1e-9)
    # Not planar: the trajectory's points do not lie in one vertical plane.
    horiz = sv.pos_m[:, :2] - sv.pos_m[0, :2]
    u = horiz[-1] / np.linalg.norm(horiz[-1])
    assert np.abs(horiz[:, 0] * u[1] - horiz[:, 1] * u[0]).max() > 10.0


def test_unknown_profile_name() -> None:
    with pytest.raises(InputError, match="nope"):
        build_survey(WellConfig(), "nope")


def test_default_profile_is_first_or_named() -> None:
    cfg = WellConfig()
    assert cfg.active_profile == "profile_1"
    cfg2 = WellConfig(profile="profile_2")
    np.testing.assert_array_equal(build_survey(cfg2).md_m, build_survey(cfg, "profile_2").md_m)
