"""simulate(): run directory contents, Ctrl-C + resume, divergence, CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

import drillfatigue
from drillfatigue import rundir
from drillfatigue.cli import main
from drillfatigue.config import case_from_dict, load_case
from drillfatigue.dynamics.run import simulation as api
from drillfatigue.dynamics.step.pack import stable_step
from drillfatigue.errors import SimulationError

CASE = {
    "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 300.0}}},
    "string": {"components": [
        {"type": "collar", "name": "DC", "od_m": 0.17145, "id_m": 0.0714, "length_m": 20.0,
         "n_segments": 2},
        {"type": "drill_pipe", "name": "DP", "od_m": 0.127, "id_m": 0.1086, "length_m": 60.0,
         "tool_joint_od_m": 0.1683, "n_segments": 6}]},
    "operation": {"bit_md_m": 90.0, "duration_s": 1.0, "rpm": 100.0, "rpm_ramp_s": 0.3,
                  "tob_Nm": 1000.0, "rop_m_per_s": 0.01},
    "solver": {"checkpoint_every_s": 0.25, "chunk_steps": 500},
    "recording": {"loads_rate_hz": 200.0, "channels_rate_hz": 200.0, "kinematics_rate_hz": 20.0},
}


def _cfg():
    return case_from_dict(CASE)


def test_run_directory_has_the_contracted_files_and_columns(tmp_path: Path) -> None:
    res = drillfatigue.simulate(_cfg(), tmp_path / "run", progress=False)
    run = tmp_path / "run"
    assert res.status == "complete"
    loads = pq.read_table(run / "loads.parquet")
    # the span-bending correction is recorded by default (contact.span_bending)
    assert loads.column_names == ["time_s", "joint", "md_m", "axial_N", "shear_x_N", "shear_y_N",
                                  "bending_x_Nm", "bending_y_Nm", "torque_Nm",
                                  "span_bending_x_Nm", "span_bending_y_Nm"]
    n_joints = 7  # 8 segments (the top one stretched to reach the surface)
    assert loads.num_rows == 200 * n_joints
    joints = pq.read_table(run / "joints.parquet").to_pandas()
    assert list(joints.columns) == ["joint", "component", "component_type", "s_from_bit_m",
                                    "body_od_m", "body_id_m", "conn_od_m", "conn_id_m"]
    assert joints["component_type"].iloc[0] == "collar"
    assert joints["component"].iloc[-1] == "DP"
    np.testing.assert_allclose(joints["s_from_bit_m"], np.arange(1, 8) * 10.0)
    ch = pq.read_table(run / "channels.parquet")
    for col in ("time_s", "surface_torque_Nm", "hook_load_N", "wob_N", "tob_Nm", "top_rpm",
                "bit_rpm", "bit_md_m", "rop_m_per_s"):
        assert col in ch.column_names
    kin = pq.read_table(run / "kinematics.parquet")
    assert kin.num_rows == 20 * 8
    summary = json.loads((run / "summary.json").read_text())
    assert summary["status"] == "complete"
    assert summary["config_hash"] == api.config_hash(load_case(run / "case.yaml"))
    assert summary["figures"]["bit_rpm"]["max"] > 50.0
    assert summary["energy_balance_error_rel"] < 0.01
    assert not (run / "checkpoint.npz").exists() and not (run / ".parts").exists()
    # the one definition of the format is what the files hold
    assert tuple(loads.column_names) == rundir.LOADS_COLUMNS + rundir.SPAN_COLUMNS
    assert tuple(joints.columns) == rundir.JOINTS_COLUMNS
    assert tuple(ch.column_names) == rundir.CHANNELS_COLUMNS
    assert tuple(kin.column_names) == rundir.KINEMATICS_COLUMNS
    assert tuple(pq.read_table(run / rundir.CONTACTS).column_names) == rundir.CONTACTS_COLUMNS
    # loads: md = bit md - distance from the bit; tension in the pipe near the top
    df = loads.to_pandas()
    last = df[df["time_s"] == df["time_s"].max()]
    assert (last["md_m"].to_numpy() == pytest.approx(90.0 + 0.01 - np.arange(1, 8) * 10.0, abs=1e-3))
    assert last["axial_N"].iloc[-1] > 0 > last["axial_N"].iloc[0]


class _Interrupt:
    """Progress bar stand-in that presses Ctrl-C after 0.6 s of simulated time."""

    def __init__(self, total: float) -> None:
        pass

    def update(self, sim_t: float, wall: float) -> None:
        if sim_t >= 0.6:
            raise KeyboardInterrupt

    def close(self) -> None:
        pass


def test_ctrl_c_leaves_incomplete_run_and_resume_is_bit_for_bit(tmp_path: Path,
                                                               monkeypatch) -> None:
    ref = tmp_path / "ref"
    drillfatigue.simulate(_cfg(), ref, progress=False)
    run = tmp_path / "run"
    monkeypatch.setattr(api, "_Progress", _Interrupt)
    with pytest.raises(KeyboardInterrupt):
        drillfatigue.simulate(_cfg(), run, progress=True)
    summary = json.loads((run / "summary.json").read_text())
    assert summary["status"] == "incomplete"
    assert 0.5 < summary["duration_s"] < 1.0
    # nothing under a final name; the histories so far are valid parts
    assert not (run / "loads.parquet").exists() and not (run / "channels.parquet").exists()
    parts = sorted((run / ".parts").glob("loads.*.parquet"))
    rows = sum(pq.read_table(p).num_rows for p in parts)
    assert 0 < rows < pq.read_table(ref / "loads.parquet").num_rows
    assert (run / "checkpoint.npz").exists()
    res = drillfatigue.simulate(_cfg(), run, progress=False, resume=True)
    assert res.status == "complete"
    for name in ("loads", "channels", "kinematics"):
        a = pq.read_table(ref / f"{name}.parquet")
        b = pq.read_table(run / f"{name}.parquet")
        assert a.equals(b), name  # bit for bit


def test_divergence_raises_and_marks_the_run_failed(tmp_path: Path, monkeypatch) -> None:
    real = api.build_model

    def unstable(config, path):
        model, state = real(config, path)
        # 3x the Gershgorin bound of the joints alone (the bound is conservative and
        # the run's step sits below it anyway, so a fixed multiple of dt may not diverge)
        n0 = model.n0
        model.dt = 3.0 * stable_step(model.seg[:n0], model.jp[:n0], model.bp)
        return model, state

    monkeypatch.setattr(api, "build_model", unstable)
    with pytest.raises(SimulationError, match=r"diverged at t = .* in segment \d+"):
        drillfatigue.simulate(_cfg(), tmp_path / "run", progress=False)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["status"] == "failed"


def test_cli_simulate_and_errors(tmp_path: Path, capsys) -> None:
    import yaml

    case = tmp_path / "case.yaml"
    small = dict(CASE, operation=dict(CASE["operation"], duration_s=0.2))
    case.write_text(yaml.safe_dump(small))
    assert main(["simulate", str(case), "--out", str(tmp_path / "run"), "--no-progress"]) == 0
    assert "complete" in capsys.readouterr().out
    # bad input: one line, exit 2, nothing written
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(dict(CASE, operation={"bit_md_m": 30.0})))
    assert main(["simulate", str(bad), "--out", str(tmp_path / "bad_run")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: operation.bit_md_m:") and "\n" not in err
    assert not (tmp_path / "bad_run").exists()
    assert main(["simulate", str(case), "--out", str(tmp_path / "none"), "--resume"]) == 2
    assert "checkpoint" in capsys.readouterr().err
    assert not (tmp_path / "none").exists()
