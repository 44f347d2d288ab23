"""build_segments and the string config section."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config import StringConfig, case_from_dict
from drillfatigue.errors import InputError
from drillfatigue.string import COMPONENT_TYPES, build_segments
from drillfatigue.string.segments import HoleFit


def test_default_string_is_the_papers_120_segments() -> None:
    segs = build_segments(StringConfig(), 1200.0)
    assert segs.n_segments == 120
    assert segs.n_joints == 119
    assert segs.component_type[:20] == ["collar"] * 20
    assert segs.component_type[20:] == ["drill_pipe"] * 100
    assert set(segs.component_type) <= set(COMPONENT_TYPES)


def test_tube_properties_follow_the_formulas() -> None:
    cfg = StringConfig(components=[{"type": "collar", "od_m": 0.2, "id_m": 0.1, "length_m": 30.0,
                                    "n_segments": 3}])
    segs = build_segments(cfg, 1000.0)
    ro, ri, seg_len = 0.1, 0.05, 10.0
    area = math.pi * (ro ** 2 - ri ** 2)
    m = 7850.0 * area * seg_len
    np.testing.assert_allclose(segs.mass_kg, m)
    np.testing.assert_allclose(segs.inertia_axial_kg_m2, m * (ro ** 2 + ri ** 2) / 2)
    np.testing.assert_allclose(segs.inertia_transverse_kg_m2,
                               m * (3 * (ro ** 2 + ri ** 2) + seg_len ** 2) / 12)
    np.testing.assert_allclose(segs.buoyed_weight_N, m * 9.80665 * (1 - 1000.0 / 7850.0))
    np.testing.assert_allclose(segs.s_from_bit_m, [5.0, 15.0, 25.0])
    np.testing.assert_allclose(segs.joint_s_from_bit_m, [10.0, 20.0])
    np.testing.assert_allclose(segs.ea_N, 207e9 * area)
    np.testing.assert_allclose(segs.contact_radius_m, 0.1)


def test_tool_joints_add_mass_and_contact_radius_and_joint_sections() -> None:
    cfg = StringConfig(components=[
        {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 18.0, "n_segments": 2},
        {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 27.0, "n_segments": 3,
         "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826, "tool_joint_length_fraction": 0.05}])
    segs = build_segments(cfg, 0.0)
    body = 7850 * math.pi / 4 * (0.127 ** 2 - 0.1086 ** 2)
    tj = 7850 * math.pi / 4 * (0.1683 ** 2 - 0.0826 ** 2)
    assert math.isclose(segs.mass_per_length_kg_per_m[-1], 0.95 * body + 0.05 * tj)
    assert math.isclose(segs.contact_radius_m[-1], 0.1683 / 2)
    # the joint between collar and pipe takes the weaker (pipe) section
    assert segs.joint_component_type == ["collar", "drill_pipe", "drill_pipe", "drill_pipe"]
    assert segs.conn_od_m[1] == pytest.approx(0.1683)
    assert segs.body_od_m[0] == pytest.approx(0.17145)


@pytest.mark.parametrize("bad, field", [
    ({"type": "collar", "od_m": 0.1, "id_m": 0.12, "length_m": 9.0}, "id_m"),
    ({"type": "collar", "od_m": 0.1, "id_m": 0.05, "length_m": -1.0}, "length_m"),
    ({"type": "pipe", "od_m": 0.1, "id_m": 0.05, "length_m": 9.0}, "type"),
    ({"type": "collar", "od_m": 0.1, "id_m": 0.05, "length_m": 9.0, "contact_radius_m": 0.01},
     "contact_radius_m"),
    ({"type": "collar", "od_m": 0.1, "id_m": 0.05, "length_m": 9.0, "n_segments": 0}, "n_segments"),
    ({"type": "collar", "od_m": 0.1, "id_m": 0.05, "length_m": 9.0, "colour": "red"}, "colour"),
])
def test_bad_components_are_rejected_with_the_field(bad: dict, field: str) -> None:
    with pytest.raises(InputError) as err:
        case_from_dict({"string": {"components": [bad]}})
    assert field in str(err.value) or "components[0]" in err.value.field


def test_operation_rejects_inconsistent_top_and_bit() -> None:
    with pytest.raises(InputError, match="top_md_m"):
        case_from_dict({"operation": {"bit_md_m": 100.0, "top_md_m": 200.0}})
    # off bottom there is no neutral point to solve for; a given hook load or a
    # fixed top are the documented choices (hook_load carries a free top, e.g. whirl)
    with pytest.raises(InputError, match="off-bottom"):
        case_from_dict({"operation": {"bit_on_bottom": False, "top_axial": "neutral_point"}})
    assert case_from_dict({"operation": {"bit_on_bottom": False,
                                         "top_axial": "hook_load"}}).operation.top_axial == "hook_load"
    # tripping needs the bit off bottom and the top fixed
    with pytest.raises(InputError, match="tripping"):
        case_from_dict({"operation": {"bit_on_bottom": True, "trip_speed_m_per_s": 0.5}})
    with pytest.raises(InputError, match="tripping"):
        case_from_dict({"operation": {"bit_on_bottom": False, "top_axial": "hook_load",
                                      "trip_speed_m_per_s": -0.5}})


def _hole(kappa: float, kop_md_m: float = 0.0) -> HoleFit:
    """An 8 1/2 in hole, vertical to ``kop_md_m``, then curving at ``kappa``; bit at 2000 m."""
    return HoleFit(md_m=np.array([0.0, kop_md_m, 5000.0]),
                   curvature_rad_per_m=np.array([0.0, kappa]), radius_m=np.full(2, 0.10795),
                   bit_md_lo_m=2000.0, bit_md_hi_m=2000.0, top_md_m=0.0)


def test_hole_fit_rule_splits_collars_and_keeps_drill_pipe_joints() -> None:
    """Reference: chord geometry, L^2 kappa / 8 <= f_seg c (exact arithmetic, no tolerance)."""
    cfg = StringConfig(preset="paper_bha")
    kappa = math.radians(8.0) / 30.0
    listed = build_segments(cfg, 1200.0)
    fitted = build_segments(cfg, 1200.0, _hole(kappa))
    c = 0.10795 - 0.5 * 0.17145
    for ci, comp in enumerate(cfg.components):
        lengths = fitted.length_m[fitted.component_index == ci]
        assert lengths.sum() == pytest.approx(comp.length_m, rel=1e-12)
        if comp.type == "drill_pipe":  # whole joints, as listed
            np.testing.assert_array_equal(lengths, listed.length_m[listed.component_index == ci])
        else:
            assert np.all(lengths ** 2 * kappa / 8.0 <= 0.5 * c * (1.0 + 1e-12))
            # the fewest equal segments that fit: one fewer would not
            n = lengths.size
            if n > comp.n_segments:
                assert (comp.length_m / (n - 1)) ** 2 * kappa / 8.0 > 0.5 * c
    # 168 m of collars: sqrt(8 * 0.5 * 0.02223 / 4.654e-3) = 4.37 m -> 39 segments
    assert int((fitted.component_index == 3).sum()) == 39
    # drill pipe listed in 31.25 m segments (the reduced default string) is re-cut at whole
    # joints: one 9.144 m joint per segment, since two (18.3 m) do not fit
    dp = StringConfig(components=[{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": 500.0, "tool_joint_od_m": 0.1683,
                                   "n_segments": 16}])
    cut = build_segments(dp, 1200.0, _hole(kappa))
    assert cut.n_segments == 55  # 54 joints and the 6.2 m pup joint on top
    np.testing.assert_allclose(cut.length_m[:-1], 9.144, rtol=1e-12)
    assert cut.length_m[-1] == pytest.approx(500.0 - 54 * 9.144, rel=1e-9)
    assert cut.length_m.sum() == pytest.approx(500.0, rel=1e-12)
    # the pipe in the vertical above a kick-off keeps its listed 31.25 m (3 whole joints)
    part = build_segments(dp, 1200.0, _hole(kappa, kop_md_m=1700.0))
    in_build = 2000.0 - np.cumsum(part.length_m) > 1700.0 - 1e-9  # top end below the kick-off
    np.testing.assert_allclose(part.length_m[in_build], 9.144, rtol=1e-12)
    assert np.all(part.length_m[~in_build][1:-1] == pytest.approx(3 * 9.144, rel=1e-12))
    # a straight hole or the rule switched off: the listed segments, bit for bit
    straight = build_segments(cfg, 1200.0, _hole(0.0))
    off = build_segments(cfg.model_copy(update={"segment_fit_fraction": None}), 1200.0,
                         _hole(kappa))
    for segs in (straight, off):
        np.testing.assert_array_equal(segs.length_m, listed.length_m)
        np.testing.assert_array_equal(segs.mass_kg, listed.mass_kg)
