"""Hole-geometry features of string positions against the closed form of a J well."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.well import build_survey
from drillfatigue.well.features import POSITION_COLUMNS, position_features, survey_features

KOP_M, BUILD_DEG_PER_30M, INC_DEG = 400.0, 6.0, 60.0
END_OF_BUILD_M = KOP_M + INC_DEG / BUILD_DEG_PER_30M * 30.0  # 700 m


@pytest.fixture(scope="module")
def survey():
    cfg = WellConfig(profile="j", profiles={"j": {"kind": "j", "kop_m": KOP_M,
                                                  "dls_deg_per_30m": BUILD_DEG_PER_30M,
                                                  "inc_deg": INC_DEG, "td_m": 1500.0}})
    return build_survey(cfg)


def test_j_well_closed_form(survey) -> None:
    """Constant build: inclination is linear in MD, so interpolation between
    stations is exact (1e-9 deg: round-off of the minimum-curvature angles)."""
    md = np.array([300.0, 460.0, 520.0, 640.0, 1000.0])
    bit = np.array([380.0, 580.0, 580.0, 680.0, 1100.0])
    f = survey_features(survey, md, bit)
    assert set(f) == set(POSITION_COLUMNS)

    def inc(x):
        return np.clip((x - KOP_M) / 30.0 * BUILD_DEG_PER_30M, 0.0, INC_DEG)

    np.testing.assert_allclose(f["local_inc_deg"], inc(md), atol=1e-9)
    np.testing.assert_allclose(f["bit_inc_deg"], inc(bit), atol=1e-9)
    # row and bit both inside the build: the mean build rate is the build rate
    np.testing.assert_allclose(f["build_to_bit_deg_per_30m"][1:4], BUILD_DEG_PER_30M, rtol=1e-9)
    # vertical above the KOP, hold below the end of build
    assert f["build_to_bit_deg_per_30m"][0] == pytest.approx(0.0, abs=1e-12)
    assert f["build_to_bit_deg_per_30m"][4] == pytest.approx(0.0, abs=1e-9)
    # dogleg: the build rate inside the build (stations well inside it), 0 in the hold
    np.testing.assert_allclose(f["local_dls_deg_per_30m"][2:4], BUILD_DEG_PER_30M, rtol=1e-9)
    assert f["bit_dls_deg_per_30m"][4] == pytest.approx(0.0, abs=1e-9)
    # windowed maximum of the interpolated dogleg (which ramps over the station
    # interval after a change): the window [KOP - 70, KOP - 10] sees no build,
    # [KOP + 30, KOP + 90] sees it all, and the hold from one station interval
    # past the end of build on sees none
    step = np.diff(survey.md_m).max()
    w = survey_features(survey, np.array([KOP_M - 40.0, KOP_M + 60.0,
                                          END_OF_BUILD_M + step + 30.0 + 1.0]),
                        np.full(3, 1200.0), ("local_max_dls_deg_per_30m",))
    np.testing.assert_allclose(w["local_max_dls_deg_per_30m"], [0.0, BUILD_DEG_PER_30M, 0.0],
                               atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.0, 1500.0), min_size=1, max_size=30))
def test_windowed_max_bounds_local_value(survey, mds) -> None:
    """local <= windowed max <= survey max, for any depth."""
    md = np.array(mds)
    f = survey_features(survey, md, md + 10.0,
                        ("local_dls_deg_per_30m", "local_max_dls_deg_per_30m"))
    assert np.all(f["local_max_dls_deg_per_30m"] >= f["local_dls_deg_per_30m"] - 1e-12)
    assert np.all(f["local_max_dls_deg_per_30m"] <= survey.dls_deg_per_30m.max() + 1e-12)


def test_bad_surveys_name_the_column() -> None:
    md = np.array([0.0, 100.0, 200.0])
    dls = np.zeros(3)
    with pytest.raises(InputError, match="inc_deg"):
        position_features(md, dls, None, np.ones(1), np.ones(1))
    # no inclination needed: fine without it
    out = position_features(md, dls, None, np.ones(1), np.ones(1),
                            ("local_dls_deg_per_30m", "bit_dls_deg_per_30m"))
    assert out["bit_dls_deg_per_30m"][0] == 0.0
    with pytest.raises(InputError, match="md_m"):
        position_features(md[::-1], dls, np.zeros(3), np.ones(1), np.ones(1))
    with pytest.raises(InputError, match="dls_deg_per_30m"):
        position_features(md, np.array([0.0, np.nan, 0.0]), np.zeros(3), np.ones(1), np.ones(1))
    with pytest.raises(InputError, match="not a position feature"):
        position_features(md, dls, np.zeros(3), np.ones(1), np.ones(1), ("md_m",))

