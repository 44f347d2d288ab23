"""``pipeline/paper_scale.py``: the measured case-2 row and note of a full run."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]


def _script():
    spec = importlib.util.spec_from_file_location("paper_scale", ROOT / "pipeline" / "paper_scale.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


CHECKS = {
    "status": "complete", "n_segments_final": 136, "max_abs_axial_N": 3.4e5,
    "max_bending_Nm": 2.9e4, "max_abs_torque_Nm": 3.3e4, "max_contact_force_N": 4.0e4,
    "bit_bounce_count": 1045, "off_bottom_fraction_after_10s": 0.027,
    "top_end_tvd_at_end_m": 1.9, "energy_balance_error_rel": 8e-5, "real_time_factor": 0.39,
    "drilling": {
        "on_bottom_fraction": 0.973, "mean_wob_N": 99957.0, "wob_set_N": 1e5,
        "wob_error_rel": -0.0004, "mean_rop_m_per_h": 17.8,
        "rop_bit_law_m_per_s": 20.0 / 3600.0, "bit_rpm_mean": 150.0,
        "mean_surface_torque_Nm": 4220.0, "surface_torque_tnd_Nm": 3690.0,
        "tob_bit_law_Nm": 2630.0, "block_min_m": 5.04, "block_max_m": 9.0,
        "block_within_travel": True, "string_top_below_rotary": True,
        "whirl_class": "chaotic", "bounce_class": "bounce", "bit_bounce_count": 1045,
        "stick_slip_class": "stick_slip", "stick_slip_severity": 3.0},
}


def test_note_states_the_acceptance_figures_and_explains_a_fraction_below_95_percent():
    ps = _script()
    note = ps.case2_full_note(CHECKS)
    assert "on bottom 97.3% of the time" in note
    assert "mean ROP 17.8 m/h against the bit law's 20.0 m/h" in note
    assert "mean surface torque 4.22 kN m against the soft-string 3.69 kN m" in note
    assert "Below the 95 %" not in note
    low = {**CHECKS, "drilling": {**CHECKS["drilling"], "on_bottom_fraction": 0.7}}
    assert "Below the 95 %" in ps.case2_full_note(low)
    row = ps.case2_full_row({"rows": [{"profile": "profile_1", "wall_s": 2058.0}],
                             "boundaries": "rig", "config": {"safety_factor": 0.3}})
    assert row["ours"] == "34.3 min" and "rig: autodriller on WOB" in row["run"]
    assert row["paper"] == "38 h / 3 = 12.7 h"
