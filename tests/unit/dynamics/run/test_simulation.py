"""The simulator's run folder: nothing lost, nothing partial under a final name, divergence caught.

* A folder holding files this package did not write is refused (one-line
  error, exit 2, nothing touched); a rerun into its own folder replaces only
  the files of the earlier run, never a user's file beside them.
* An interrupted (SIGINT) or diverged run leaves no ``loads.parquet`` /
  ``channels.parquet``: the data stays in the parts folder (interrupted) or is
  merged under ``<name>.partial.parquet`` (failed); SIGINT prints one line
  ``error: interrupted ...`` and exits 130.
* A speed no drill string reaches (``status.MAX_SPEED_M_PER_S``,
  ``MAX_SPIN_RAD_S``) stops the run with the divergence error, naming the
  time and the segment where it started.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from drillfatigue import rundir
from drillfatigue.cli import main
from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run import simulation as api
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.errors import InputError, SimulationError

ROOT = Path(__file__).resolve().parents[4]
CASE = {
    "well": {"profiles": {"vertical": {"kind": "vertical", "td_m": 300.0}}},
    "string": {"components": [
        {"type": "collar", "name": "DC", "od_m": 0.17145, "id_m": 0.0714, "length_m": 20.0,
         "n_segments": 2},
        {"type": "drill_pipe", "name": "DP", "od_m": 0.127, "id_m": 0.1086, "length_m": 60.0,
         "tool_joint_od_m": 0.1683, "n_segments": 6}]},
    "operation": {"bit_md_m": 90.0, "duration_s": 0.2, "rpm": 100.0, "rpm_ramp_s": 0.1,
                  "tob_Nm": 1000.0, "rop_m_per_s": 0.01},
    "solver": {"checkpoint_every_s": 0.05, "chunk_steps": 200},
    "recording": {"loads_rate_hz": 100.0, "channels_rate_hz": 100.0, "kinematics_rate_hz": 20.0},
}


def _case(**op: object) -> dict:
    return {**CASE, "operation": {**CASE["operation"], **op}}


def test_a_folder_with_foreign_files_is_refused_and_left_untouched(tmp_path: Path,
                                                                     capsys) -> None:
    run = tmp_path / "run"
    run.mkdir()
    mine = {"summary.docx": b"my report", "loads.xlsx": b"my table"}
    for name, data in mine.items():
        (run / name).write_bytes(data)
    with pytest.raises(InputError, match="--out"):
        simulate(case_from_dict(_case()), run, progress=False)
    case = tmp_path / "case.yaml"
    case.write_text(yaml.safe_dump(_case()))
    assert main(["simulate", str(case), "--out", str(run), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --out:") and "\n" not in err
    assert sorted(p.name for p in run.iterdir()) == sorted(mine)
    for name, data in mine.items():
        assert (run / name).read_bytes() == data


def test_a_rerun_replaces_only_its_own_files(tmp_path: Path) -> None:
    run = tmp_path / "run"
    simulate(case_from_dict(_case()), run, progress=False)
    # the user adds files whose names start like the run's files
    (run / "loads.xlsx").write_bytes(b"mine")
    (run / "summary.docx").write_bytes(b"mine too")
    res = simulate(case_from_dict(_case(duration_s=0.1)), run, progress=False)
    assert res.status == "complete"
    assert (run / "loads.xlsx").read_bytes() == b"mine"
    assert (run / "summary.docx").read_bytes() == b"mine too"
    assert json.loads((run / rundir.SUMMARY).read_text())["duration_s"] == pytest.approx(0.1)
    assert not (run / rundir.PARTS).exists() and not (run / rundir.CHECKPOINT).exists()


def test_a_foreign_file_of_a_run_files_name_is_refused_before_the_old_run_changes(
        tmp_path: Path, capsys) -> None:
    """A complete run, then a file of the user's under one of the names a run writes
    (here the checkpoint's): the rerun is refused before it deletes or rewrites anything."""
    run = tmp_path / "run"
    simulate(case_from_dict(_case()), run, progress=False)
    (run / rundir.CHECKPOINT).write_bytes(b"mine")
    before = {p.name: p.read_bytes() for p in run.iterdir() if p.is_file()}
    case = tmp_path / "case.yaml"
    case.write_text(yaml.safe_dump(_case(duration_s=0.1)))
    assert main(["simulate", str(case), "--out", str(run), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert "checkpoint.npz exists and was not written by drillfatigue" in err and "\n" not in err
    assert {p.name: p.read_bytes() for p in run.iterdir() if p.is_file()} == before
    assert not (run / rundir.PARTS).exists()
    with pytest.raises(InputError, match="checkpoint.npz"):  # the library call too
        simulate(case_from_dict(_case(duration_s=0.1)), run, progress=False)
    assert {p.name: p.read_bytes() for p in run.iterdir() if p.is_file()} == before


def test_a_diverged_run_leaves_no_history_under_a_final_name(tmp_path: Path,
                                                              monkeypatch) -> None:
    real = api.build_model

    def kicked(config, path):
        model, state = real(config, path)
        state.v[3, 0] = 2.0 * status.MAX_SPEED_M_PER_S  # segment 3 far beyond any real speed
        return model, state

    monkeypatch.setattr(api, "build_model", kicked)
    run = tmp_path / "run"
    with pytest.raises(SimulationError):
        simulate(case_from_dict(_case()), run, progress=False)
    summary = json.loads((run / rundir.SUMMARY).read_text())
    assert summary["status"] == "failed" and "diverged" in summary["message"]
    for stem in rundir.HISTORIES:
        assert not (run / rundir.history_name(stem)).exists(), stem


def test_the_divergence_error_names_the_time_and_the_segment_where_it_started(
        monkeypatch) -> None:
    real = api.build_model

    def kicked(config, path):
        model, state = real(config, path)
        # a spin no string reaches, on one segment in the middle of the string
        state.w[5, 2] = 1.5 * status.MAX_SPIN_RAD_S
        return model, state

    monkeypatch.setattr(api, "build_model", kicked)
    with pytest.raises(SimulationError) as info:
        simulate(case_from_dict(_case()), None, progress=False)
    msg = str(info.value)
    assert "diverged at t = " in msg and "segment 5 " in msg and "speed" in msg
    t = float(msg.split("t = ")[1].split(" s")[0])
    assert 0.0 < t < 1e-3  # the first step: before the spin spreads along the string


def test_a_free_top_under_a_huge_torque_is_stopped_by_the_speed_bound() -> None:
    # case 1 (a free 5 m pipe in a horizontal hole) driven by 20 kN m instead of 200 N m:
    # spin-up without bound (> 70 000 rpm within 0.5 s), no real string does that
    data = yaml.safe_load((ROOT / "data" / "cases" / "case1_whirl.yaml").read_text())
    data["operation"].update(duration_s=0.5, top_torque_Nm=20000.0)
    with pytest.raises(SimulationError, match=r"diverged at t = .* in segment \d+ .*speed"):
        simulate(case_from_dict(data), None, progress=False)


def test_sigint_prints_one_line_and_leaves_no_final_histories(tmp_path: Path) -> None:
    case = tmp_path / "case.yaml"
    # 600 s of this short string take several seconds of wall time: the signal arrives
    # while it runs (60 s could finish within the 0.2 s poll below). The kernels are
    # compiled into numba's on-disk cache first: a SIGINT that lands inside numba's
    # compiler (a cold cache on a fresh clone) is not delivered as KeyboardInterrupt.
    simulate(case_from_dict(_case(duration_s=0.06)), None, progress=False)
    case.write_text(yaml.safe_dump(_case(duration_s=600.0)))
    run = tmp_path / "run"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen([sys.executable, "-m", "drillfatigue", "simulate", str(case),
                             "--out", str(run), "--no-progress"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            # a shell's Ctrl-C: the default disposition, whatever an earlier
                            # test left in this process (an ignored SIGINT is inherited)
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 240.0
    while not (run / rundir.CHECKPOINT).exists():  # running, one checkpoint written
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: interrupted"), err
    assert json.loads((run / rundir.SUMMARY).read_text())["status"] == "incomplete"
    for stem in rundir.HISTORIES:
        assert not (run / rundir.history_name(stem)).exists(), stem
    assert list((run / rundir.PARTS).glob("loads.*.parquet"))
    assert np.isfinite(json.loads((run / rundir.SUMMARY).read_text())["duration_s"])


def test_sigint_after_the_final_rename_reports_a_complete_run(tmp_path: Path, capsys,
                                                              monkeypatch) -> None:
    """A Ctrl-C that lands while a complete run writes its summary (every history renamed)
    used to exit 130 "incomplete ... continue it with --resume" beside a summary saying
    complete; the run is complete and is reported so."""
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(_case(duration_s=0.06)))
    real = api.atomic_write_json

    def write_after_ctrl_c(path: Path, data: object) -> object:
        if Path(path).name == rundir.SUMMARY:
            assert all((tmp_path / "run" / rundir.history_name(k)).exists()
                       for k in ("loads", "channels"))
            os.kill(os.getpid(), signal.SIGINT)  # held by the simulator until it has written
        return real(path, data)

    monkeypatch.setattr(api, "atomic_write_json", write_after_ctrl_c)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        rc = main(["simulate", str(tmp_path / "case.yaml"), "--out", str(tmp_path / "run"),
                   "--no-progress"])
    finally:
        signal.signal(signal.SIGINT, previous)
    out, err = capsys.readouterr()
    assert rc == 0, err
    assert out.startswith("complete: ") and err == ""
    assert json.loads((tmp_path / "run" / rundir.SUMMARY).read_text())["status"] == "complete"


def test_ctrl_c_after_simulate_returned_finds_the_complete_run(tmp_path: Path, capsys,
                                                               monkeypatch) -> None:
    """The CLI's side: a KeyboardInterrupt that reaches it after the run wrote a complete
    summary (in this command) reports the run complete; an earlier run's summary does not
    count."""
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(_case(duration_s=0.06)))
    real = api.Runner.run

    def run_then_ctrl_c(self, *args: object, **kwargs: object) -> object:
        real(self, *args, **kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(api.Runner, "run", run_then_ctrl_c)
    argv = ["simulate", str(tmp_path / "case.yaml"), "--out", str(tmp_path / "run"),
            "--no-progress"]
    assert main(argv) == 0
    assert capsys.readouterr().out.startswith("complete: ")

    def ctrl_c_at_once(self, *args: object, **kwargs: object) -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(api.Runner, "run", ctrl_c_at_once)  # the old summary stays
    assert main(argv) == 130
    assert capsys.readouterr().err.startswith("error: interrupted: ")
