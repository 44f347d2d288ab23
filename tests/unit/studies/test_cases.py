"""Case-study helpers: config sections, window sampling, joint choice, whirl analysis,
candidate query rows, report formatting (no simulation)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from drillfatigue.config import FatigueConfig
from drillfatigue.config import case_from_dict
from drillfatigue.config.base import validate
from drillfatigue.config.studies import (
    Case1Config,
    Case2Config,
    Case3Config,
    PlanConfig,
    ReportConfig,
    StringSpec,
)
from drillfatigue.errors import InputError
from drillfatigue.studies import case1, case2, case3, plan, report, stages


def test_sections_default_constructible():
    for model in (Case1Config, Case2Config, Case3Config, PlanConfig, ReportConfig):
        model()
    assert Case2Config().window_s == pytest.approx(800.0)  # (880 - 480) / 0.5
    assert Case3Config().duration_s == pytest.approx(13.0)


@pytest.mark.parametrize("model, data, field", [
    (Case2Config, {"n_samples": 0}, "case2.n_samples"),
    (Case2Config, {"rop_m_per_s": 2.0}, "case2.rop_m_per_s"),
    (Case2Config, {"bit_md_end_m": 400.0}, "case2"),
    (Case2Config, {"settle_s": 5.0, "sample_s": 4.0}, "case2"),
    (Case2Config, {"target_s_from_bit_m": 600.0}, "case2"),
    (Case2Config, {"string": {"dc_segments": 0}}, "case2.string.dc_segments"),
    (Case2Config, {"colour": 1}, "case2.colour"),
    (Case1Config, {"mu_low": 0.5, "mu_high": 0.4}, "case1"),
    (Case1Config, {"models": ["magic"]}, "case1.models"),
    (Case3Config, {"window_s": 0.0}, "case3.window_s"),
    (Case3Config, {"mode": "sideways"}, "case3.mode"),
    (Case3Config, {"bha": "tricone"}, "case3.bha"),
    (Case3Config, {"dp_joints_per_segment": 0}, "case3.dp_joints_per_segment"),
    (Case3Config, {"tortuosity": {"model": "sine", "amplitude_deg": -0.5, "period_m": 30.0}},
     "case3.tortuosity.amplitude_deg"),
    (Case3Config, {"tortuosity": {"model": "sine", "amplitude_deg": 0.5, "period_m": 30.0,
                                  "wave": 1}}, "case3.tortuosity.wave"),
    (PlanConfig, {"confirm_top_k": -1}, "plan.confirm_top_k"),
])
def test_sections_reject_bad_values(model, data, field):
    name = field.split(".")[0]
    with pytest.raises(InputError) as exc:
        validate(model, data, name)
    assert exc.value.one_line().startswith(field)
    assert "allowed" in exc.value.one_line()


def test_case2_target_joint_and_samples():
    # default reduced string: 9 collar segments of 20 m -> joint 1 is 40 m from the bit
    assert case2.target_joint(Case2Config()) == (1, pytest.approx(40.0))
    # paper string: 20 collar segments of 9 m -> joints at 36 m (j=3) and 45 m: 36 is nearer
    paper = Case2Config(string=StringSpec(dc_segments=20, dp_segments=100))
    assert case2.target_joint(paper) == (3, pytest.approx(36.0))
    one = Case2Config(n_samples=1, sample_s=800.0, settle_s=0.0)
    assert case2.sample_bit_md(one) == [pytest.approx(480.0)]  # the paper's continuous window
    cfg = Case2Config(n_samples=8, sample_s=4.0, boundaries="prescribed_rop")
    starts = np.array(case2.sample_bit_md(cfg))
    ends = starts + cfg.rop_m_per_s * cfg.sample_s
    assert starts.size == cfg.n_samples and starts[0] > 480.0 and ends[-1] < 880.0
    assert np.allclose(np.diff(starts), 400.0 / cfg.n_samples)  # evenly spread
    case = case2.case_dict(cfg, "profile_2", float(starts[0]), 1)
    assert case["string"]["components"][1]["length_m"] == pytest.approx(starts[0] - 180.0)
    assert case["recording"]["joints"] == [1] and case["well"]["profile"] == "profile_2"
    assert "rig" not in case and case["operation"]["rop_m_per_s"] == cfg.rop_m_per_s
    # rig_rop: the same window drilled as the sweep drills, the autodriller at the ROP
    # target (its ROP limit) with the WOB limit (its set-point)
    rr = case2.case_dict(cfg.model_copy(update={"boundaries": "rig_rop"}), "profile_2",
                         float(starts[0]), 1)
    full = case_from_dict(rr)
    assert full.rig is not None and full.rig.block_mode == "autodriller"
    ad = full.rig.effective_autodriller
    assert ad.rop_limit_m_per_s == cfg.rop_m_per_s and ad.wob_set_N == cfg.wob_set_N
    assert full.operation.rop_m_per_s == 0.0
    assert full.bit.model == "yigit_christoforou" and full.operation.bit_on_bottom
    assert full.rig.rock.lobe_amplitude_m == cfg.lobe_amplitude_m


def test_case3_joints_and_case():
    cfg = Case3Config()
    bit0 = cfg.bit_md_end_m - cfg.advance_m_per_s * cfg.duration_s
    assert bit0 == cfg.bit_md_end_m  # rig: the bit starts on bottom at bit_md_end_m
    picks = case3.joints_behind_bit(cfg, bit0)
    # paper BHA: stabilizer 0-1.5 m, collar to 10.5 m, stabilizer to 12 m, then 9.33 m
    # collar segments: 12 + 3 x 9.33 = 40 m and 12 + 7 x 9.33 = 77.3 m
    assert [round(s, 1) for _, s in picks] == [10.5, 40.0, 77.3]
    case, b = case3.case_dict(cfg, [j for j, _ in picks])
    assert b == pytest.approx(bit0)
    table = case["operation"]["rpm_table"]
    assert table[-2] == [cfg.trip_s + cfg.ramp_s, cfg.rpm] and table[1] == [cfg.trip_s, 0.0]
    assert case["recording"]["start_s"] == cfg.trip_s + cfg.ramp_s
    # case 2's rig boundaries and the span options, explicitly
    assert case["rig"]["block_mode"] == "autodriller" and case["bit"]["model"] == \
        "yigit_christoforou"
    assert case["rig"]["rock"]["lobe_amplitude_m"] == cfg.lobe_amplitude_m
    assert case["operation"]["bit_on_bottom"] is True
    assert case["contact"] == {"points": "string", "span_bending": True}
    assert case["string"]["lateral_mud_mass"] is True
    comps = case["string"]["components"]
    assert [c["type"] for c in comps] == ["stabilizer", "collar", "stabilizer", "collar",
                                          "drill_pipe"]
    assert sum(c["length_m"] for c in comps) == pytest.approx(bit0)  # reaches the surface
    assert comps[-1]["joints_per_segment"] == 1
    # the paper's lives: 191 h nearest the build (80 m), 625 h at 40 m, 677 h at 8 m
    assert case3.PAPER_LIFE_H == {80.0: 191.0, 40.0: 625.0, 8.0: 677.0}
    trip, _ = case3.case_dict(Case3Config(mode="tripping"), [0])
    assert trip["operation"]["bit_on_bottom"] is False and "rig" not in trip
    assert trip["operation"]["trip_speed_m_per_s"] > 0
    bare = Case3Config(bha="bare_collars", dp_joints_per_segment=None)
    assert [round(s) for _, s in case3.joints_behind_bit(bare, bit0)] == [9, 36, 81]


def _synthetic_run(root, span_amp_Nm: float, axial_amp_N: float):
    """A run folder of one collar joint: span moment rotating once per second at
    amplitude ``span_amp_Nm`` in the pipe frame, axial force alternating at 3/s."""
    n = 1000  # 10 s at 100 Hz, 100 samples per revolution
    t = np.arange(n) / 100.0
    ph = 2.0 * np.pi * t
    loads = pd.DataFrame({
        "time_s": t, "joint": 0, "md_m": 900.0,
        "axial_N": axial_amp_N * np.sin(3.0 * ph), "shear_x_N": 0.0, "shear_y_N": 0.0,
        "bending_x_Nm": 0.0, "bending_y_Nm": 0.0, "torque_Nm": 0.0,
        "span_bending_x_Nm": span_amp_Nm * np.cos(ph),
        "span_bending_y_Nm": span_amp_Nm * np.sin(ph)})
    root.mkdir()
    loads.to_parquet(root / "loads.parquet", index=False)
    pd.DataFrame({"joint": [0], "component": [0], "component_type": ["collar"],
                  "s_from_bit_m": [80.0], "body_od_m": [0.17145], "body_id_m": [0.0714],
                  "conn_od_m": [0.17145], "conn_id_m": [0.0714]}).to_parquet(
        root / "joints.parquet", index=False)
    (root / "summary.json").write_text('{"status": "complete", "duration_s": 10.0}')
    return root


def test_case3_decomposition_and_amplitudes(tmp_path):
    """Each load group alone through the fatigue chain, and its stress amplitude.

    Reference: a moment M rotating in the pipe frame gives every surface point a
    fully reversed bending stress of amplitude K_b M r / I (beam theory); 100
    samples per revolution resolve the peak to cos(1.8 deg) = 0.9995, so 1e-3.
    """
    fat = FatigueConfig(plots=False)
    run = _synthetic_run(tmp_path / "run", 8000.0, 0.0)
    amp = case3.stress_amplitudes(run, fat, [0]).set_index(["location", "load"])
    r_o, r_i = 0.17145 / 2, 0.0714 / 2
    s_ref = 8000.0 * r_o / (np.pi / 4.0 * (r_o ** 4 - r_i ** 4))
    assert amp.loc[("body", "span_bending"), "sigma_amplitude_Pa"] == \
        pytest.approx(s_ref, rel=1e-3)
    k_b = fat.scf["collar"].connection.bending
    assert amp.loc[("connection", "span_bending"), "sigma_amplitude_Pa"] == \
        pytest.approx(k_b * s_ref, rel=1e-3)
    assert amp.loc[("body", "axial_torsion"), "sigma_amplitude_Pa"] == 0.0
    assert amp.loc[("body", "joint_bending"), "sigma_amplitude_Pa"] == 0.0
    dec = case3.decompose_damage(run, fat, [0], "matake").set_index(["location", "load"])
    # only the span correction loads this joint: it alone gives the full damage
    assert dec.loc[("connection", "all"), "damage"] > 0
    assert dec.loc[("connection", "span_bending"), "damage"] == \
        pytest.approx(dec.loc[("connection", "all"), "damage"], rel=1e-12)
    assert dec.loc[("connection", "axial_torsion"), "damage"] == 0.0
    assert dec.loc[("connection", "joint_bending"), "damage"] == 0.0
    # an axial force alone: the axial group carries it, its amplitude is K_a F / A
    run2 = _synthetic_run(tmp_path / "run2", 0.0, 3e5)
    amp2 = case3.stress_amplitudes(run2, fat, [0]).set_index(["location", "load"])
    assert amp2.loc[("body", "axial_torsion"), "sigma_amplitude_Pa"] == \
        pytest.approx(3e5 / (np.pi * (r_o ** 2 - r_i ** 2)), rel=1e-3)
    dec2 = case3.decompose_damage(run2, fat, [0], "matake").set_index(["location", "load"])
    assert dec2.loc[("connection", "span_bending"), "damage"] == 0.0
    assert dec2.loc[("connection", "axial_torsion"), "damage"] == \
        pytest.approx(dec2.loc[("connection", "all"), "damage"], rel=1e-12)


def test_rolling_ratio():
    # -r_p / (R_h - r_p) with r_p = 63.5 mm, R_h = 107.95 mm (docs/model.md#friction)
    assert case1.rolling_ratio() == pytest.approx(-0.0635 / (0.10795 - 0.0635))


def test_whirl_rate_recovers_a_synthetic_backward_orbit():
    cfg = Case1Config()
    case = case1.case_dict(cfg, "tanh_exp", cfg.mu_high)
    t = np.linspace(0.0, 2.0, 401)
    omega_w = -12.0  # rad/s, backward; several turns so the unwrap is exercised
    rows = []
    for seg, x in enumerate(np.linspace(136.0, 139.5, 5)):
        yc, zc = case1.hole_centre(case, np.full(t.size, x))
        r = 0.04445
        rows.append(pd.DataFrame({
            "time_s": t, "segment": seg, "x_m": x,
            "y_m": yc + r * np.cos(omega_w * t + seg), "z_m": zc + r * np.sin(omega_w * t + seg),
            "normal_N": 1.0}))
    kin = case1.orbit_angles(pd.concat(rows, ignore_index=True), case)
    assert np.allclose(np.hypot(kin["dy_m"], kin["dz_m"]), 0.04445, atol=1e-6)
    assert case1.whirl_rate(kin, 0.5) == pytest.approx(omega_w, rel=1e-6)


def test_candidate_rows_carry_the_profile():
    cset = plan.CandidateFile.model_validate({
        "candidates": {"p1": {"kind": "family_member", "member": 1, "kop_m": 350.0},
                       "p2": {"kind": "family_member", "member": 2, "kop_m": 450.0}},
        "surrogate_bit_positions": 3})
    plan.check_end_points(cset)
    w = cset.window
    n_joints = w.string.dc_segments + w.string.dp_segments - 1
    rows = {n: plan.candidate_rows(cset, n) for n in cset.candidates}
    for r in rows.values():
        # body and connection at every joint, the upset run-out at drill-pipe joints
        assert (r["location"] == "body").sum() == (r["location"] == "connection").sum() \
            == 3 * n_joints
        upset = r[r["location"] == "upset"]
        assert set(upset["component_type"]) == {"drill_pipe"}
        assert len(upset) == 3 * int((r.loc[r["location"] == "body", "component_type"]
                                      == "drill_pipe").sum() // 3)
        assert (r.loc[r["s_from_bit_m"] < 179.0, "component_type"] == "collar").all()
        assert np.allclose(r["md_m"], r["bit_position_md_m"] - r["s_from_bit_m"])
        assert set(r["operation.bit_md_m"]) == set(np.linspace(480.0, 880.0, 3))
        # the window drills as the sweep does (the autodriller at the ROP target with its
        # WOB limit); the target is the feature operation.rop_m_per_s
        assert set(r["rig.block_mode"]) == {"autodriller"}
        assert set(r["operation.rop_m_per_s"]) == {w.rop_m_per_s}
        assert set(r["rig.autodriller.rop_limit_m_per_s"]) == {w.rop_m_per_s}
        assert set(r["bit.model"]) == {"yigit_christoforou"}
    # within the builds the local DLS is each profile's solved build rate (5.7, 8.6 deg/30 m)
    assert rows["p1"]["local_dls_deg_per_30m"].max() == pytest.approx(5.73, abs=0.01)
    assert rows["p2"]["local_dls_deg_per_30m"].max() == pytest.approx(8.59, abs=0.01)


def test_report_formatting():
    assert report._fmt(math.inf) == "∞" and report._fmt(None) == "n/a"
    assert report._fmt(12.3456) == "12.3" and report._fmt(1.5e7) == "1.50e+07"
    assert report._fmt(True) == "yes"
    md = report._table(pd.DataFrame({"a": [1.0, 2.5], "b": ["x", "y"]}), {"a": "A", "b": "B"})
    assert md.splitlines() == ["| A | B |", "|---|---|", "| 1 | x |", "| 2.5 | y |"]


def test_case3_report_line_names_the_load_and_the_gap():
    row = {"s_from_bit_m": 40.0, "joint_s_from_bit_m": 40.0, "component_type": "collar",
           "hole_dls_deg_per_30m": 0.0, "life_ratio_ours_to_paper": 486.0,
           "dominant_load": "axial_torsion", "life_h_axial_torsion_only": 3.2e5,
           "sigma_amplitude_MPa_span_bending": 0.02}
    line = report._case3_why(row)
    assert "straight hole" in line and "axial force, shears and torque" in line
    assert "line contact" in line and "factor of 10" in line
    near = {**row, "hole_dls_deg_per_30m": 5.73, "life_ratio_ours_to_paper": 0.52,
            "dominant_load": "joint_bending", "life_h_joint_bending_only": 1216.0,
            "sigma_amplitude_MPa_joint_bending": 75.0}
    line = report._case3_why(near)
    assert "curved up to 5.73°/30 m within 10 m" in line and "curvature" in line
    assert "factor of 10" not in line


def test_case3_local_dogleg_counts_the_intervals_around_the_joint():
    """Minimum curvature: a station's DLS is that of the interval ending there."""
    class Survey:
        md_m = np.array([0.0, 100.0, 130.0, 160.0])
        dls_deg_per_30m = np.array([0.0, 0.0, 6.0, 0.0])  # build over 100-130 m only
    assert case3.local_dls_deg_per_30m(Survey, 95.0) == 6.0   # 100-130 within 10 m
    assert case3.local_dls_deg_per_30m(Survey, 85.0) == 0.0
    assert case3.local_dls_deg_per_30m(Survey, 139.0) == 6.0
    assert case3.local_dls_deg_per_30m(Survey, 145.0) == 0.0
    assert case3.local_dls_deg_per_30m(Survey, 400.0) == 0.0  # beyond the survey
def test_report_shows_the_drilling_metrics_of_each_profile():
    # two samples of profile_1 and one of profile_2, as case 2's summary holds them
    row = {"profile": "profile_1", "sample": 0, "wob_set_N": 1e5, "metrics_from_s": 10.0,
           "on_bottom_fraction": 0.9, "mean_wob_N": 98e3, "wob_error_rel": -0.02,
           "mean_rop_m_per_h": 19.0, "mean_surface_torque_Nm": 11e3, "block_min_m": 5.0,
           "block_max_m": 5.4, "stick_slip_severity": 0.3, "whirl_class": "chaotic",
           "bounce_class": "bounce", "stick_slip_class": "none"}
    rows = [row, {**row, "sample": 1, "on_bottom_fraction": 1.0, "mean_wob_N": 100e3,
                  "wob_error_rel": 0.0, "stick_slip_class": "oscillation"},
            {**row, "profile": "profile_2", "mean_rop_m_per_h": 20.0, "bounce_class": "none"}]
    lines = report._case2_drilling_lines({"boundaries": "rig", "drilling": rows})
    text = "\n".join(lines)
    assert "from 10 s on" in text
    table = [ln for ln in lines[1].splitlines() if ln.startswith("| profile_")]
    cells = [[c.strip() for c in ln.strip("|").split("|")] for ln in table]
    assert [c[0] for c in cells] == ["profile_1", "profile_2"]
    # columns: on bottom, WOB, set-point, error %, ROP, torque, block range, classes, severity
    assert cells[0][1] == "0.95" and cells[0][2] == "99" and cells[0][3] == "100"
    assert cells[0][4] == "-1" and cells[0][6] == "11"
    assert cells[0][7] == "0.4"  # block travel range 5.4 - 5.0 m
    assert cells[0][8:11] == ["chaotic", "bounce", "none, oscillation"]
    assert cells[1][5] == "20" and cells[1][9] == "none"
    assert report._case2_drilling_lines({"drilling": []}) == []


def test_report_shows_the_rop_and_torque_references_and_the_rig_checks():
    row = {"profile": "profile_1", "sample": 0, "wob_set_N": 1e5, "metrics_from_s": 10.0,
           "on_bottom_fraction": 0.7, "mean_wob_N": 98e3, "wob_error_rel": -0.02,
           "mean_rop_m_per_h": 17.0, "rop_bit_law_m_per_s": 20.0 / 3600.0,
           "mean_surface_torque_Nm": 4e3, "surface_torque_tnd_Nm": 3.5e3, "block_min_m": 5.0,
           "block_max_m": 9.0, "block_within_travel": True, "string_top_below_rotary": False,
           "stick_slip_severity": 2.0, "whirl_class": "chaotic", "bounce_class": "bounce",
           "stick_slip_class": "stick_slip"}
    lines = report._case2_drilling_lines({"boundaries": "rig", "drilling": [row]})
    head = lines[1].splitlines()[0]
    assert "bit law's ROP" in head and "soft-string torque" in head
    cells = [c.strip() for c in lines[1].splitlines()[2].strip("|").split("|")]
    # on bottom, WOB, set-point, error, ROP, law's ROP, torque, T&D torque, range, checks
    assert cells[5:8] == ["17", "20", "4"] and cells[8] == "3.5"
    assert cells[10:12] == ["yes", "no"]


def test_timings_row_shows_the_earlier_measurement_and_metrics_carry_the_references():
    row = {"run": "case 2, profile_1 x 800 s (measured)", "ours": "30.0 min",
           "paper": "38 h / 3 = 12.7 h", "before": "17.8 min (prescribed ROP)"}
    text = "\n".join(report._timings_section({"rows": [row], "note": ""}, None, None))
    assert "| 30.0 min (before: 17.8 min (prescribed ROP)) | 38 h / 3 = 12.7 h |" in text
    drill = {"profile": "profile_1", "sample": 0, "on_bottom_fraction": 0.7,
             "wob_error_rel": -0.01, "mean_rop_m_per_h": 17.0, "mean_surface_torque_Nm": 4e3,
             "block_within_travel": True, "string_top_below_rotary": True,
             "stick_slip_class": "stick_slip", "whirl_class": "chaotic", "bounce_class": "bounce",
             "rop_over_bit_law": 0.9, "surface_torque_over_tnd": 1.1}
    summ = {"rows": [], "order_agrees": True, "drilling": [drill]}
    m = stages._metrics("case2", summ, 1.0)
    assert m["rop_over_bit_law_profile_1"] == 0.9
    assert m["surface_torque_over_tnd_profile_1"] == 1.1


def test_case3_tortuosity_config():
    """The default is the "2 deg/30 m" torque-and-drag tortuosity (sine, A = 0.5 deg over
    30 m, peak 3.1 deg/30 m); null keeps the plan only and leaves the section's dump as it
    was; the tortuous well takes the block in place of the section's own."""
    cfg = Case3Config()
    assert cfg.tortuosity is not None
    assert (cfg.tortuosity.model, cfg.tortuosity.amplitude_deg, cfg.tortuosity.period_m,
            cfg.tortuosity.direction) == ("sine", 0.5, 30.0, "inclination")
    assert cfg.tortuosity.peak_added_dls_deg_per_30m == pytest.approx(math.pi, rel=1e-12)
    off = validate(Case3Config, {"tortuosity": None}, "case3")
    assert off.tortuosity is None
    assert case3.case_dict(off, None)[0] == case3.case_dict(cfg, None)[0]  # the plan run
    well = {"profile": "profile_1", "tortuosity": {"model": "random", "amplitude_deg": 2.0,
                                                   "period_m": 10.0}}
    tw = case3.tortuous_well(cfg, well)
    assert tw["tortuosity"]["amplitude_deg"] == 0.5 and tw["profile"] == "profile_1"
    assert well["tortuosity"]["model"] == "random"  # the section is not changed
    case, _ = case3.case_dict(cfg, None, tw)
    assert case_from_dict(case).well.tortuosity == cfg.tortuosity
    with pytest.raises(ValueError, match="tortuosity is null"):
        case3.tortuous_well(off, well)


def test_case3_bending_amplitudes_and_lives_table():
    t = np.linspace(0.0, 1.0, 101)
    loads = pd.DataFrame({"joint": 3, "time_s": t,
                          "bending_x_Nm": 2e3 * np.cos(2 * np.pi * t),
                          "bending_y_Nm": 2e3 * np.sin(2 * np.pi * t),
                          "span_bending_x_Nm": 5e2, "span_bending_y_Nm": 0.0})
    amp = case3.bending_amplitudes_Nm(loads, 3)
    assert amp["joint_bending_amplitude_Nm"] == pytest.approx(2e3, rel=1e-3)
    assert amp["span_bending_amplitude_Nm"] == 0.0  # constant: no range
    plan = pd.DataFrame({"s_from_bit_m": [8.0, 80.0], "paper_life_h": [677.0, 191.0],
                         "joint_s_from_bit_m": [10.5, 78.2], "life_h": [1e5, 508.0],
                         "dominant_load": ["span_bending", "joint_bending"],
                         "joint_bending_amplitude_Nm": [3.1e3, 11.4e3],
                         "span_bending_amplitude_Nm": [4.6e3, 0.2e3]})
    tort = plan.assign(joint_s_from_bit_m=[6.0, 78.3], life_h=[1.06e3, 1.5e4],
                       dominant_load=["joint_bending", "axial_torsion"])
    lives = report.case3_lives_table(plan, tort)
    assert list(lives["load_plan"]) == ["span correction (3.1 / 4.6 kN·m)",
                                        "joint bending (11.4 / 0.2 kN·m)"]
    assert list(lives["life_h_tortuous"]) == [1.06e3, 1.5e4]
    assert list(lives["joint_s_from_bit_m_tortuous"]) == [6.0, 78.3]
    assert "life_h_tortuous" not in report.case3_lives_table(plan, None)
