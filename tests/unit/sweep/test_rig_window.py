"""The sweep on the rig boundaries (ROP set-point) and the window chosen per case by the
convergence of its governing damage rate."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue import rundir
from drillfatigue.config import FatigueConfig, Params, SweepConfig, validate
from drillfatigue.errors import InputError
from drillfatigue.sweep import window as window_module
from drillfatigue.sweep.dataset import _input_table, window_record
from drillfatigue.sweep.design import base_case_from_params, design_cases
from drillfatigue.sweep.window import governing_rate_change, run_case_converged

RIG_SWEEP = {"boundaries": "rig", "rig": {"block_mode": "rop"}, "method": "lhs", "n_cases": 3,
             "seed": 5, "fixed": {"bit.model": "yigit_christoforou"},
             "variables": {"operation.rop_m_per_s": {"low": 0.002, "high": 0.01},
                           "operation.lobe_amplitude_m": {"low": 0.0, "high": 0.002}}}


def _design(sweep: dict) -> pd.DataFrame:
    params = Params()
    return design_cases(validate(SweepConfig, sweep, "sweep"), base_case_from_params(params))


def test_rop_design_variable_is_the_blocks_set_point():
    d = _design(RIG_SWEEP)
    for _, row in d.iterrows():
        case = json.loads(row["case_json"])
        assert case["rig"]["block_mode"] == "rop"
        assert case["rig"]["rop_set_m_per_s"] == row["operation.rop_m_per_s"]
        assert case["rig"]["rock"]["lobe_amplitude_m"] == row["operation.lobe_amplitude_m"]
        # the operation fields the rig took over are back at their defaults
        assert case["operation"]["rop_m_per_s"] == 0.0
        assert case["operation"]["lobe_amplitude_m"] == 0.0
        assert case["bit"]["model"] == "yigit_christoforou"
    # the dataset's inputs keep the operation names with the set-points' values
    table = _input_table(d, list(RIG_SWEEP["variables"]))
    assert np.allclose(table["operation.rop_m_per_s"], d["operation.rop_m_per_s"])
    assert (table["rig.block_mode"] == "rop").all()


def test_rig_section_may_not_set_what_the_design_gives():
    bad = {**RIG_SWEEP, "rig": {"block_mode": "rop", "rop_set_m_per_s": 0.004}}
    with pytest.raises(InputError) as exc:
        _design(bad)
    assert exc.value.field == "sweep.rig.rop_set_m_per_s"


def test_rop_variable_needs_block_mode_rop():
    with pytest.raises(InputError) as exc:
        _design({**RIG_SWEEP, "rig": {"block_mode": "held"}})
    assert exc.value.field == "sweep.variables.operation.rop_m_per_s"


def test_rig_needs_the_bit_law():
    with pytest.raises(InputError) as exc:
        _design({**RIG_SWEEP, "fixed": {}})
    assert "bit.model" in exc.value.problem


@pytest.mark.parametrize("sweep, field", [
    ({"window": {"mode": "converged"}}, "window_s"),
    ({"window_s": 40.0, "window": {"mode": "converged", "max_s": 20.0}}, "window.max_s"),
])
def test_window_settings_checked(sweep, field):
    with pytest.raises(InputError) as exc:
        validate(SweepConfig, sweep, "sweep")
    assert field in f"{exc.value.field} {exc.value.problem}"


# --- the convergence measure on synthetic runs with a closed-form answer ---------------

RATE_HZ = 100.0
CYCLE_HZ = 2.0


def _write_run(folder: Path, duration_s: float, amplitude_Nm) -> None:
    """A one-joint collar run: bending at CYCLE_HZ with the amplitude ``amplitude_Nm(t)``."""
    folder.mkdir(parents=True, exist_ok=True)
    t = np.arange(0.0, duration_s + 1e-9, 1.0 / RATE_HZ)
    bend = amplitude_Nm(t) * np.sin(2.0 * np.pi * CYCLE_HZ * t)
    zero = np.zeros_like(t)
    pd.DataFrame({"time_s": t, "joint": np.zeros(t.size, dtype=np.int64), "md_m": 500.0 + zero,
                  "axial_N": zero, "shear_x_N": zero, "shear_y_N": zero, "bending_x_Nm": bend,
                  "bending_y_Nm": zero, "torque_Nm": zero}).to_parquet(folder / rundir.LOADS,
                                                                      index=False)
    pd.DataFrame({"joint": [0], "component": ["DC"], "component_type": ["collar"],
                  "s_from_bit_m": [5.0], "body_od_m": [0.17145], "body_id_m": [0.0714],
                  "conn_od_m": [0.17145], "conn_id_m": [0.0714]}).to_parquet(
        folder / rundir.JOINTS, index=False)
    (folder / rundir.SUMMARY).write_text(json.dumps({"status": "complete",
                                                     "duration_s": duration_s}))


FATIGUE = FatigueConfig(pressure=False)


def test_stationary_loading_has_no_rate_change(tmp_path):
    """Whole cycles in both parts of the record: the same rate, to the one cycle that
    straddles the cut (1 in 40 here)."""
    _write_run(tmp_path / "run", 30.0, lambda t: 4.0e4 + 0.0 * t)
    r = governing_rate_change(tmp_path / "run", FATIGUE)
    assert r["joint"] == 0 and r["rate_per_h"] > 0.0
    assert r["rate_change_rel"] < 1.0 / 40.0


def test_damage_only_in_the_last_third_is_a_full_change(tmp_path):
    """No load cycle before 2/3 of the record: the head rate is zero
    and the change is exactly 1."""
    _write_run(tmp_path / "run", 30.0, lambda t: np.where(t > 25.0, 4.0e4, 0.0))
    r = governing_rate_change(tmp_path / "run", FATIGUE)
    assert r["head_rate_per_h"] == 0.0 and r["rate_change_rel"] == 1.0


def test_no_damage_counts_as_converged(tmp_path):
    _write_run(tmp_path / "run", 10.0, lambda t: 0.0 * t)
    assert governing_rate_change(tmp_path / "run", FATIGUE)["rate_change_rel"] == 0.0


def _inputs(first_s: float) -> dict:
    return {"case": {"operation": {"duration_s": first_s}},
            "window": {"first_s": first_s, "max_s": 4 * first_s, "growth": 2.0, "tol_rel": 0.1,
                       "path": "operation.duration_s",
                       "fatigue": FATIGUE.model_dump(mode="json")}}


@pytest.mark.parametrize("settle_s, windows, converged", [
    (0.0, [10.0], True),                 # stationary from the start
    (6.0, [10.0, 20.0, 40.0], False),    # a start-up transient that still weighs at the cap
])
def test_window_is_extended_until_the_rate_settles(tmp_path, monkeypatch, settle_s, windows,
                                                   converged):
    seen: list[float] = []

    def fake_run(case: dict, case_dir: Path) -> dict:
        duration = case["operation"]["duration_s"]
        seen.append(duration)
        # large cycles until settle_s, small (still damaging) ones after
        _write_run(Path(case_dir), duration, lambda t: np.where(t < settle_s, 8.0e4, 4.0e4))
        return {"duration_s": duration}

    monkeypatch.setattr(window_module, "run_case", fake_run)
    run_case_converged(_inputs(10.0), tmp_path)
    record = json.loads((tmp_path / window_module.WINDOW_FILE).read_text())
    assert seen == windows
    assert [t["window_s"] for t in record["tries"]] == windows
    assert record["window_s"] == windows[-1] and record["converged"] is converged
    cols = window_record(tmp_path)
    assert cols["window_converged"] == float(converged)
    assert cols["window_rate_change_rel"] == pytest.approx(record["rate_change_rel"])
