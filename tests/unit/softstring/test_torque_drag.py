"""Tests of ``drillfatigue tnd`` and the case-level soft-string driver."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

from drillfatigue.cli import main
from drillfatigue.config import case_from_dict
from drillfatigue.softstring.torque_drag import torque_drag_for_case
from drillfatigue.string import build_segments

# explicit string (the defaults may change): 180 m of collars in 20 segments, 900 m of DP
STRING = {"components": [
    {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 180.0, "n_segments": 20},
    {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 900.0,
     "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826, "tool_joint_length_fraction": 0.05,
     "n_segments": 100},
]}
VERTICAL = {
    "well": {"profiles": {"v": {"kind": "vertical", "td_m": 1200.0}}},
    "string": STRING,
    "operation": {"bit_md_m": 1080.0, "top_md_m": 0.0},
}
J_WELL = {
    "well": {"profiles": {"j": {"kind": "j", "kop_m": 300.0, "dls_deg_per_30m": 3.0,
                                "inc_deg": 40.0, "td_m": 1500.0}}},
    "string": STRING,
    "operation": {"bit_md_m": 1400.0},
}


def write_case(tmp_path, data, name="case.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data))
    return p


def test_vertical_hook_load_is_buoyed_weight_minus_wob():
    case = case_from_dict(VERTICAL)
    seg = build_segments(case.string, case.operation.mud_density_kg_per_m3)
    assert seg.length_m.sum() == pytest.approx(1080.0)  # string exactly fills the span
    td = torque_drag_for_case(case, cell_m=7.0)
    s = td.summary()
    buoyed = float(seg.buoyed_weight_N.sum())
    assert s["hookload_rotating_N"] == pytest.approx(buoyed, rel=1e-10)
    assert s["hookload_pickup_N"] == pytest.approx(buoyed, rel=1e-10)
    # WOB = buoyed weight below the neutral point at the top of the collars
    ncoll = 20
    assert td.wob_N == pytest.approx(float(seg.buoyed_weight_N[:ncoll].sum()), rel=1e-10)
    assert s["hookload_drilling_N"] == pytest.approx(buoyed - td.wob_N, rel=1e-10)
    assert td.tob_Nm > 0.0  # from the bit law at that WOB and rpm
    # neutral point at the top of the collars: tension changes sign there
    k = np.argmin(np.abs(td.md_m - (1080.0 - 180.0)))
    assert abs(td.tension_drilling_N[k]) < 1e-6 * buoyed


def test_tortuous_vertical_hole_turns_the_string_against_the_wall():
    """well.tortuosity reaches the soft string: in a vertical hole the plan gives no side
    force, a 1 deg sine over 30 m gives T |kappa| (mean |kappa| = 4 A / P), so the rotating
    torque is mu (4 A / P) times the integral of r T along the string (buoyed weight below
    each point); 2 %: the weight's normal part and the partial last wave
    (tests/validation/test_tortuosity_softstring.py)."""
    data = {**VERTICAL, "well": {**VERTICAL["well"], "tortuosity": {
        "model": "sine", "amplitude_deg": 1.0, "period_m": 30.0}}}
    case = case_from_dict(data)
    plan = torque_drag_for_case(case_from_dict(VERTICAL)).summary()
    td = torque_drag_for_case(case).summary()
    assert plan["surface_torque_rotating_Nm"] == 0.0
    seg = build_segments(case.string, case.operation.mud_density_kg_per_m3)
    below = np.concatenate([[0.0], np.cumsum(seg.buoyed_weight_N)[:-1]])  # at each bottom
    r_t = np.sum(seg.contact_radius_m * (below * seg.length_m + 0.5 * seg.buoyed_weight_N
                                         * seg.length_m))
    kappa = 4.0 * math.radians(1.0) / 30.0
    assert td["surface_torque_rotating_Nm"] == pytest.approx(
        case.friction.mu_dynamic * kappa * r_t, rel=0.02)  # measured 0.06 %
    assert td["hookload_pickup_N"] > plan["hookload_pickup_N"]
    assert td["hookload_slackoff_N"] < plan["hookload_slackoff_N"]


def test_given_hook_load_sets_wob():
    data = {**J_WELL, "operation": {**J_WELL["operation"], "top_axial": "hook_load",
                                    "hook_load_N": 1.5e5}}
    td = torque_drag_for_case(case_from_dict(data))
    assert td.tension_drilling_N[0] == pytest.approx(1.5e5, rel=1e-9)
    too_much = {**data, "operation": {**data["operation"], "hook_load_N": 9e6}}
    from drillfatigue.errors import InputError
    with pytest.raises(InputError) as exc:
        torque_drag_for_case(case_from_dict(too_much))
    assert exc.value.field == "operation.hook_load_N"


def test_cell_size_converged_in_j_well():
    case = case_from_dict(J_WELL)
    a = torque_drag_for_case(case, cell_m=10.0, wob_N=5e4).summary()
    b = torque_drag_for_case(case, cell_m=1.0, wob_N=5e4).summary()
    for k in ("hookload_pickup_N", "hookload_slackoff_N", "surface_torque_rotating_Nm"):
        assert a[k] == pytest.approx(b[k], rel=5e-3)  # cells of 10 m vs 1 m in a 3 deg/30 m build
    assert b["hookload_pickup_N"] > b["hookload_rotating_N"] > b["hookload_slackoff_N"]


def test_cli_json_and_plot(tmp_path, capsys):
    case = write_case(tmp_path, J_WELL)
    png = tmp_path / "tnd.png"
    assert main(["tnd", str(case), "--json", "-o", str(png), "--wob-kN", "50"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["wob_N"] == pytest.approx(5e4)
    assert out["hookload_pickup_N"] > out["hookload_slackoff_N"]
    assert png.stat().st_size > 1000
    assert main(["tnd", str(case)]) == 0
    text = capsys.readouterr().out
    assert "pick-up" in text and "surface torque" in text


@pytest.mark.parametrize(
    "args, field",
    [
        (["-o", "{tmp}/plot.txt"], "--out"),
        (["--cell-m", "0"], "--cell-m"),
        (["--wob-kN", "-3"], "--wob-kN: -3 is outside the physical range (allowed: 0 <= "
                             "wob_kN <= 1000)"),
        # the bound of drillfatigue.limits, as in query and twin (was 1e5 kN here)
        (["--wob-kN", "5000"], "--wob-kN: 5000 is outside the physical range"),
    ],
)
def test_cli_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys, args, field):
    case = write_case(tmp_path, J_WELL)
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    before = set(tmp_path.iterdir())
    assert main(["tnd", str(case), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {field}") and "allowed" in err[0]
    assert set(tmp_path.iterdir()) == before


def test_cli_bit_beyond_td(tmp_path, capsys):
    data = {**J_WELL, "operation": {"bit_md_m": 1600.0}}
    assert main(["tnd", str(write_case(tmp_path, data))]) == 2
    assert "operation.bit_md_m" in capsys.readouterr().err


def test_inclined_straight_case_matches_closed_form():
    """A j-well held at 40 deg: in the hold, tension gradient is w cos I +- mu w sin I."""
    case = case_from_dict(J_WELL)
    td = torque_drag_for_case(case, cell_m=5.0, wob_N=0.0)
    seg = build_segments(case.string, case.operation.mud_density_kg_per_m3)
    w_dp = seg.buoyed_weight_N[-1] / seg.length_m[-1]
    inc = math.radians(40.0)
    mu = case.friction.mu_dynamic
    hold = (td.md_m > 700.0) & (td.md_m < 1000.0)  # drill pipe in the 40 deg hold
    md = td.md_m[hold]
    for t, sign in ((td.tension_pickup_N[hold], 1), (td.tension_slackoff_N[hold], -1)):
        grad = -np.diff(t) / np.diff(md)
        np.testing.assert_allclose(grad, w_dp * (math.cos(inc) + sign * mu * math.sin(inc)), rtol=1e-9)


def test_neutral_point_at_top_of_collars_in_deviated_well():
    """Default WOB puts the drilling-mode neutral point at the top of the collars
    (docs/model.md#top-boundary)."""
    td = torque_drag_for_case(case_from_dict(J_WELL), cell_m=5.0)
    k = int(np.argmin(np.abs(td.md_m - (1400.0 - 180.0))))
    assert td.md_m[k] == pytest.approx(1220.0)
    assert abs(td.tension_drilling_N[k]) < 1e-9 * td.wob_N
    assert td.tension_drilling_N[k - 1] > 0 > td.tension_drilling_N[k + 1]
