"""The ``well`` config section: defaults, discriminated profiles, range checks."""

from __future__ import annotations

import pydantic
import pytest

from drillfatigue.config import WellConfig, case_from_dict, load_params
from drillfatigue.config.well import FamilyMemberProfile, JProfile
from drillfatigue.errors import InputError


def test_defaults_are_valid_and_paper_like() -> None:
    cfg = WellConfig()
    assert list(cfg.profiles) == ["profile_1", "profile_2", "profile_3"]
    assert cfg.active_profile == "profile_1"
    assert cfg.hole[0].diameter_m == pytest.approx(8.5 * 0.0254)
    assert all(isinstance(p, FamilyMemberProfile) for p in cfg.profiles.values())


def test_partial_case_keeps_other_defaults() -> None:
    case = case_from_dict({"well": {"profiles": {"a": {"kind": "j", "inc_deg": 60}}}})
    p = case.well.profiles["a"]
    assert isinstance(p, JProfile) and p.inc_deg == 60 and p.kop_m == 400.0
    assert case.well.active_profile == "a"


def test_config_is_frozen() -> None:
    cfg = WellConfig()
    with pytest.raises(pydantic.ValidationError):  # frozen instance
        cfg.min_clearance_m = 0.1  # type: ignore[misc]


@pytest.mark.parametrize(
    ("data", "field"),
    [
        ({"profiles": {}}, "well.profiles"),
        ({"profiles": {"a": {"kind": "vertical", "td_m": 0}}}, "well.profiles.a.vertical.td_m"),
        ({"profiles": {"a": {"kind": "j", "kop_m": -1}}}, "well.profiles.a.j.kop_m"),
        ({"profiles": {"a": {"kind": "j", "dls_deg_per_30m": 90}}},
         "well.profiles.a.j.dls_deg_per_30m"),
        ({"profiles": {"a": {"kind": "family_member", "member": 4}}},
         "well.profiles.a.family_member.member"),
        ({"profiles": {"a": {"kind": "family_member", "tangent_inc_deg": 90}}},
         "well.profiles.a.family_member.tangent_inc_deg"),
        ({"profiles": {"a": {"kind": "survey_file", "path": ""}}},
         "well.profiles.a.survey_file.path"),
        ({"profiles": {"a": {"kind": "survey_file"}}}, "well.profiles.a.survey_file.path"),
        ({"family": {"tvd_end_m": -5}}, "well.family.tvd_end_m"),
        ({"hole": []}, "well.hole"),
        ({"hole": [{"md_top_m": 10.0, "diameter_m": 0.2}]}, "well.hole"),
        ({"hole": [{"md_top_m": 0.0, "diameter_m": 2.0}]}, "well.hole[0].diameter_m"),
        ({"max_cylinder_length_m": 0}, "well.max_cylinder_length_m"),
        ({"chord_error_fraction": 0}, "well.chord_error_fraction"),
        ({"station_spacing_m": -1}, "well.station_spacing_m"),
        ({"profile": "x"}, "well.profile"),
    ],
)
def test_bad_values_name_the_field(data: dict, field: str) -> None:
    with pytest.raises(InputError) as exc:
        case_from_dict({"well": data})
    assert exc.value.field == field
    assert str(exc.value).startswith(f"{field}: ")


def test_repository_params_yaml_is_valid() -> None:
    from pathlib import Path

    params = Path(__file__).resolve().parents[3] / "params.yaml"
    cfg = load_params(params).well
    assert {"profile_1", "profile_2", "profile_3"} <= set(cfg.profiles)
