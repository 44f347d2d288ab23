"""BHA components, cutting at joints, contact points and mud mass of the string layer."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.config.string import ComponentConfig, StringConfig
from drillfatigue.errors import InputError
from drillfatigue.string import build_segments
from drillfatigue.string.added_mass import (confined_added_mass_coefficient, lateral_mass_kg,
                                            lateral_mud_mass_per_m)
from drillfatigue.string.contacts import (KIND_BLADE, KIND_BODY, KIND_TOOL_JOINT,
                                          contact_points, max_point_spacing_m)

REF = Path(__file__).resolve().parents[2] / "data" / "segments_reference.npz"
HOLE = 0.2159


def _mixed() -> StringConfig:
    return StringConfig(components=[
        ComponentConfig(type="bit", od_m=0.2159, id_m=0.05, length_m=0.3),
        ComponentConfig(type="stabilizer", od_m=0.17145, id_m=0.0714, length_m=1.5,
                        contact_radius_m=0.107),
        ComponentConfig(type="collar", od_m=0.17145, id_m=0.0714, length_m=60.0, n_segments=7),
        ComponentConfig(type="sub", od_m=0.17145, id_m=0.0714, length_m=9.0,
                        linear_mass_kg_per_m=160.0),
        ComponentConfig(type="hwdp", od_m=0.127, id_m=0.0762, length_m=91.44,
                        tool_joint_od_m=0.1651, tool_joint_id_m=0.0762,
                        tool_joint_length_fraction=0.08, n_segments=10),
        ComponentConfig(type="drill_pipe", od_m=0.127, id_m=0.1086, length_m=533.0,
                        tool_joint_od_m=0.1683, tool_joint_id_m=0.0826,
                        tool_joint_length_fraction=0.05, n_segments=61)],
        shear_coefficient=0.6)


@pytest.mark.parametrize("name, rho", [("default", 1200.0), ("mixed", 1450.0)])
def test_configs_without_new_fields_give_the_same_segments_bit_for_bit(name: str,
                                                                       rho: float) -> None:
    """``segments_reference.npz`` holds every array of the segmentation of these
    two strings as cut by equal-length segmentation; without the new fields the
    cut must be identical (``==``, no tolerance)."""
    ref = np.load(REF)
    seg = build_segments(StringConfig() if name == "default" else _mixed(), rho)
    for k, v in vars(seg).items():
        assert np.array_equal(np.asarray(v), ref[f"{name}.{k}"]), k


def test_drill_pipe_cut_at_whole_joints_with_a_pup() -> None:
    c = ComponentConfig(type="drill_pipe", od_m=0.127, id_m=0.1086, length_m=100.0,
                        tool_joint_od_m=0.1683, joints_per_segment=2)
    lens = c.segment_lengths_m
    assert c.n_joints == 10  # 10 x 9.144 = 91.44, 8.56 m pup
    assert lens[:4] == [2 * 9.144] * 4
    assert sum(lens) == pytest.approx(100.0, rel=1e-14)
    # the pup (8.56 m, more than half a joint) is its own segment
    assert lens[-2] == pytest.approx(2 * 9.144) and lens[-1] == pytest.approx(100.0 - 91.44)
    short = ComponentConfig(type="hwdp", od_m=0.127, id_m=0.0762, length_m=3 * 9.144 + 2.0,
                            joints_per_segment=1, joint_length_m=9.144)
    assert short.segment_lengths_m == pytest.approx([9.144, 9.144, 11.144])


def test_new_fields_are_checked() -> None:
    with pytest.raises(ValueError, match="joints_per_segment is for"):
        ComponentConfig(type="collar", od_m=0.17, id_m=0.07, length_m=9.0, joints_per_segment=1)
    with pytest.raises(ValueError, match="blade_od_m must be >= od_m"):
        ComponentConfig(type="stabilizer", od_m=0.17, id_m=0.07, length_m=1.5, blade_od_m=0.1)
    with pytest.raises(ValueError, match="for stabilizers"):
        ComponentConfig(type="collar", od_m=0.17, id_m=0.07, length_m=9.0, blade_od_m=0.2)
    with pytest.raises(InputError, match="preset"):
        case_from_dict({"string": {"preset": "paper_bha", "components": []}})
    # a blade that does not fit the hole is refused by the case check
    with pytest.raises(InputError, match="contact radius"):
        case_from_dict({"string": {"components": [
            {"type": "stabilizer", "od_m": 0.17, "id_m": 0.07, "length_m": 1.5,
             "blade_od_m": 0.22}]}})


def test_paper_bha_preset_and_its_contact_points() -> None:
    cfg = StringConfig(preset="paper_bha")
    assert [c.type for c in cfg.components] == ["stabilizer", "collar", "stabilizer", "collar",
                                                "drill_pipe"]
    seg = build_segments(cfg, 1200.0)
    dp = np.flatnonzero(seg.component_type_code == 4)
    assert np.allclose(seg.length_m[dp[:-1]], 9.144)
    kappa = math.radians(8.0) / 30.0
    cp = contact_points(cfg, seg, HOLE, kappa)
    r_tj, r_body_dp, r_blade = 0.1683 / 2, 0.127 / 2, 0.2143 / 2
    for k in dp:
        s, r, kind = cp.of_segment(int(k))
        # tool joints at both ends of every one-joint segment, body points between
        assert kind[0] == KIND_TOOL_JOINT and kind[-1] == KIND_TOOL_JOINT
        assert r[0] == r_tj and r[-1] == r_tj
        assert np.all(r[kind == KIND_BODY] == r_body_dp)
        # never a tool-joint radius away from a tool joint
        assert np.all(r[kind != KIND_TOOL_JOINT] < r_tj)
        assert np.all(np.diff(s) <= cp.max_spacing_m[k] + 1e-9)
    s, r, kind = cp.of_segment(0)  # near-bit stabilizer: blade centre and ends
    blade = kind == KIND_BLADE
    assert blade.sum() == 3 and np.all(r[blade] == r_blade)
    np.testing.assert_allclose(s[blade], [0.525, 0.75, 0.975])
    # collars: extra points no further apart than the curvature rule, 3.1 m here
    c = np.flatnonzero(seg.component_type_code == 1)[-1]
    s, r, kind = cp.of_segment(int(c))
    clearance = HOLE / 2 - 0.17145 / 2
    assert cp.max_spacing_m[c] == pytest.approx(math.sqrt(8 * 0.25 * clearance / kappa))
    assert 2.9 < cp.max_spacing_m[c] < 3.3  # docs/bending.md: about 3-4 m
    assert np.max(np.diff(s)) <= cp.max_spacing_m[c] + 1e-12 and len(s) == 5  # 9.33 m / 3.09 m


def test_legacy_drill_pipe_segments_get_tool_joints_where_the_joints_are() -> None:
    cfg = StringConfig()  # 8 m segments, not aligned with the 9.144 m joints
    seg = build_segments(cfg, 1200.0)
    cp = contact_points(cfg, seg, HOLE, 0.0)
    dp0 = float(np.cumsum(seg.length_m)[19])  # drill pipe starts above 20 collar segments
    top = np.cumsum(seg.length_m)
    z = top[cp.segment] - seg.length_m[cp.segment] + cp.s_m
    tj = cp.kind == KIND_TOOL_JOINT
    k = np.round((z[tj] - dp0) / 9.144, 9)
    # every tool-joint point at a joint boundary or at the pipe's top connection
    assert np.all((k == np.round(k)) | np.isclose(z[tj], top[-1], rtol=0, atol=1e-9))
    assert np.isclose(z[tj], top[-1]).sum() == 1
    assert np.all(cp.radius_m[tj] == 0.1683 / 2)


def test_spacing_rule_values() -> None:
    # straight hole: only the sag rule; neither: no extra points
    assert max_point_spacing_m(0.022, 0.0) == math.inf
    s = max_point_spacing_m(0.022, 0.0, ei_Nm2=8.5e6, weight_per_m_N=1400.0)
    assert s == pytest.approx((384 * 8.5e6 * 0.022 / 1400.0) ** 0.25)
    with pytest.raises(InputError):
        max_point_spacing_m(0.0, 1e-3)


def test_added_mass_coefficient_and_mud_masses() -> None:
    # unconfined limit C_a -> 1 (a cylinder in open fluid, potential flow)
    assert confined_added_mass_coefficient(0.127, 1e3) == pytest.approx(1.0, abs=1e-7)
    # Fritz (1972) concentric form, 5 in pipe in 8 1/2 in hole: 2.06
    R, r = HOLE / 2, 0.127 / 2
    assert confined_added_mass_coefficient(0.127, HOLE) == pytest.approx(
        (R * R + r * r) / (R * R - r * r), rel=1e-14)
    assert 2.0 < confined_added_mass_coefficient(0.127, HOLE) < 2.1
    seg = build_segments(StringConfig(), 1200.0)
    mi, ma = lateral_mud_mass_per_m(seg, 1200.0, HOLE, coefficient=1.0)
    np.testing.assert_allclose(mi, 1200.0 * np.pi * (seg.id_m / 2) ** 2, rtol=1e-14)
    np.testing.assert_allclose(ma, 1200.0 * np.pi * (seg.od_m / 2) ** 2, rtol=1e-14)
    m = lateral_mass_kg(seg, 1200.0, HOLE)
    # drill pipe: steel ~29 kg/m + bore mud ~11 kg/m + 2.06 x 15.2 kg/m displaced
    k = seg.component_type.index("drill_pipe")
    per_m = m[k] / seg.length_m[k]
    assert per_m == pytest.approx(seg.mass_per_length_kg_per_m[k] + 1200 * np.pi
                                  * (0.1086 / 2) ** 2 + 2.0591 * 1200 * np.pi * (0.127 / 2) ** 2,
                                  rel=1e-3)
    with pytest.raises(InputError):
        lateral_mud_mass_per_m(seg, -1.0, HOLE)


# --- named BHAs under the listed components (string.bha) ---------------------------

def _dp(length_m: float = 400.0) -> dict:
    return {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": length_m,
            "n_segments": 13}


@pytest.mark.parametrize("name", ["slick", "pendulum", "packed", "mwd_jar_hwdp"])
def test_a_named_bha_goes_below_the_listed_components_and_round_trips(name: str) -> None:
    from drillfatigue.config.string import BHAS, StringConfig

    cfg = StringConfig(bha=name, components=[_dp()])
    assert len(cfg.components) == len(BHAS[name]) + 1
    assert cfg.components[-1].type == "drill_pipe"
    assert cfg.total_length_m == pytest.approx(cfg.bha_length_m + 400.0)
    dump = cfg.model_dump(mode="json")
    assert dump["bha"] == name and len(dump["components"]) == 1  # written out as given
    again = StringConfig(**dump)
    assert again.model_dump(mode="json") == dump
    assert [c.type for c in again.components] == [c.type for c in cfg.components]


def test_the_design_bhas_hold_every_bha_component_type_the_simulator_models() -> None:
    from drillfatigue.config.string import BHAS

    types = {c["type"] for bha in BHAS.values() for c in bha}
    assert types == {"collar", "stabilizer", "hwdp", "jar", "mwd"}


def test_a_bha_without_components_above_it_is_refused() -> None:
    from drillfatigue.config.string import StringConfig

    with pytest.raises(ValueError, match="components above the BHA"):
        StringConfig.model_validate({"bha": "slick", "components": None})
    with pytest.raises(ValueError, match="bha"):
        StringConfig.model_validate({"bha": "banana", "components": [_dp()]})
