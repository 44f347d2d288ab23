"""Synthetic stand-ins for the simulator and fatigue, to test and benchmark the sweep engine.

:func:`synthetic_case` writes a run folder with the same files and columns as
the real simulator (``channels.parquet``, ``loads.parquet``, ``joints.parquet``,
``summary.json``, ``case.json``; loads and joints with exactly the columns
:func:`drillfatigue.fatigue.evaluate_run` reads), deterministically from the case inputs, after
a CPU-bound numba loop of ``work`` iterations. :func:`synthetic_fatigue` writes
a ``damage.parquet`` with the fatigue contract's columns. Neither has any
physical meaning.

Fault injection (for tests), read from ``case["synthetic"]``:

``work`` (int)
    Iterations of the CPU-bound kernel (default 1000).
``sleep_s`` (float)
    Sleep after the work (lets a test kill a sweep mid-way).
``fail_times`` / ``crash_times`` (int) with ``counter_dir`` (str)
    Raise a ``SimulationError`` / kill the worker process (SIGKILL) on the
    first N attempts; attempts are counted in files under ``counter_dir``.
"""

from __future__ import annotations

import hashlib
import json
import os
import signal
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from drillfatigue import rundir
from drillfatigue.errors import SimulationError
from testkit.synthetic_kernels import burn as _burn
from drillfatigue.units import HOUR_S

__all__ = ["synthetic_case", "synthetic_fatigue", "warmup"]

CRITERIA = ("uniaxial", "matake", "api_rp7g")
N_TIME = 200
N_JOINT = 3


def warmup(inputs: dict[str, Any] | None = None) -> None:
    """Compile :func:`_burn` once so workers only read numba's cache."""
    _burn(10, 0.5)


def _seed(case: dict[str, Any]) -> int:
    text = json.dumps(case, sort_keys=True, separators=(",", ":"))
    return int(hashlib.sha256(text.encode()).hexdigest()[:8], 16)


def _count_attempt(case: dict[str, Any], opts: dict[str, Any], key: str) -> int:
    """Increment and return the attempt counter of this case for ``key``."""
    folder = Path(opts["counter_dir"])
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{key}-{_seed(case)}"
    n = int(path.read_text()) + 1 if path.exists() else 1
    path.write_text(str(n))
    return n


def _numbers(data: Any) -> list[float]:
    if isinstance(data, bool):
        return [float(data)]
    if isinstance(data, int | float):
        return [float(data)]
    if isinstance(data, dict):
        return [x for k in sorted(data) if k != "synthetic" for x in _numbers(data[k])]
    if isinstance(data, list):
        return [x for v in data for x in _numbers(v)]
    return []


def synthetic_case(case: dict[str, Any], case_dir: Path) -> dict[str, Any]:
    """Write a fake run folder for ``case`` into ``case_dir``; see the module doc."""
    opts = dict(case.get("synthetic") or {})
    if opts.get("crash_times") and _count_attempt(case, opts, "crash") <= int(opts["crash_times"]):
        os.kill(os.getpid(), signal.SIGKILL)
    if opts.get("fail_times") and _count_attempt(case, opts, "fail") <= int(opts["fail_times"]):
        raise SimulationError("synthetic divergence at t = 1.0 s, segment 3")
    seed = _seed(case)
    level = float(np.tanh(np.sum(np.abs(_numbers(case))) / 100.0)) + 0.1
    burn = _burn(int(opts.get("work", 1000)), 0.1 + 0.8 * (seed % 1000) / 1000.0)
    if opts.get("sleep_s"):
        time.sleep(float(opts["sleep_s"]))
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 10.0, N_TIME)
    torque = (1.0e4 * level * (1.0 + 0.3 * np.sin(2.0 * np.pi * 0.5 * t))
              + rng.normal(0, 50, N_TIME))
    channels = pd.DataFrame({
        "time_s": t, "surface_torque_Nm": torque, "hook_load_N": 8.0e5 + 0.0 * t,
        "wob_N": 5.0e4 * level + 0.0 * t, "tob_Nm": 2.0e3 * level + 0.0 * t,
        "top_rpm": 120.0 + 0.0 * t, "bit_rpm": 120.0 + 40.0 * np.sin(t),
        "bit_md_m": 1000.0 + 0.01 * t, "rop_m_per_s": 0.01 + 0.0 * t})
    s_bit = np.array([8.0, 40.0, 80.0])  # distance from the bit of the recorded joints, m
    joints = pd.DataFrame({
        "joint": np.arange(N_JOINT), "component": ["DC", "DP", "DP"],
        "component_type": ["collar", "drill_pipe", "drill_pipe"], "s_from_bit_m": s_bit,
        "body_od_m": [0.17145, 0.127, 0.127], "body_id_m": [0.0714, 0.1086, 0.1086],
        "conn_od_m": [0.17145, 0.1683, 0.1683], "conn_id_m": [0.0714, 0.0826, 0.0826]})
    tt, jj = (a.ravel() for a in np.meshgrid(t, np.arange(N_JOINT), indexing="ij"))
    bend = level * 1.0e3 * (1.0 + jj)
    loads = pd.DataFrame({
        "time_s": tt, "joint": jj, "md_m": 1000.0 + 0.01 * tt - s_bit[jj],
        "axial_N": rng.normal(-1e4, 1e3, tt.size),
        "shear_x_N": rng.normal(0, 1e2, tt.size), "shear_y_N": rng.normal(0, 1e2, tt.size),
        "bending_x_Nm": bend * np.sin(tt + jj), "bending_y_Nm": bend * np.cos(tt + jj),
        "torque_Nm": np.repeat(torque, N_JOINT)})
    case_dir = Path(case_dir)
    channels.to_parquet(case_dir / rundir.CHANNELS, index=False)
    joints.to_parquet(case_dir / rundir.JOINTS, index=False)
    loads.to_parquet(case_dir / rundir.LOADS, index=False)
    summary = {"status": "complete", "duration_s": float(t[-1]), "wall_time_s": 0.0,
               "stick_slip_severity": float(np.ptp(channels["bit_rpm"]) / 120.0),
               "whirl_class": "forward" if seed % 2 else "backward",
               "bit_bounce_count": int(seed % 3), "max_contact_force_N": 1.0e4 * level,
               "burn": float(burn)}
    (case_dir / rundir.SUMMARY).write_text(json.dumps(summary, sort_keys=True), encoding="utf-8")
    (case_dir / "case.json").write_text(json.dumps(case, sort_keys=True), encoding="utf-8")
    return summary


def synthetic_fatigue(task: dict[str, Any], case_dir: Path) -> pd.DataFrame:
    """Write a fake ``damage.parquet`` for the run in ``task['run_dir']``."""
    run_dir = Path(task["run_dir"])
    joints = pd.read_parquet(run_dir / rundir.JOINTS)
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    duration_s = float(json.loads((run_dir / rundir.SUMMARY).read_text())["duration_s"])
    rows = []
    md_end = loads.groupby("joint")["md_m"].last()
    for _, j in joints.iterrows():
        amp = float(loads.loc[loads["joint"] == j["joint"], "bending_x_Nm"].abs().max())
        for location in ("body", "connection"):
            for k, criterion in enumerate(CRITERIA):
                damage = 1e-9 * amp * (1.0 + k) * (3.5 if location == "connection" else 1.0)
                rows.append({"joint": int(j["joint"]), "md_m": float(md_end[j["joint"]]),
                             "s_from_bit_m": j["s_from_bit_m"], "component": j["component"],
                             "component_type": j["component_type"], "location": location,
                             "criterion": criterion, "damage": damage,
                             "damage_rate_per_h": damage * HOUR_S / duration_s,
                             "life_h": duration_s / HOUR_S / damage, "life_windows": 1.0 / damage,
                             "critical_angle_deg": np.nan if criterion == "api_rp7g" else 10.0 * k})
    frame = pd.DataFrame(rows)
    frame.to_parquet(Path(case_dir) / "damage.parquet", index=False)
    summary = json.dumps({"n_rows": len(frame)})
    (Path(case_dir) / "summary.json").write_text(summary, encoding="utf-8")
    return frame


#: A small string and short run for the sweep-stage tests (params.yaml sections).
TINY_PARAMS = {
    "operation": {"duration_s": 0.3, "bit_md_m": 500.0, "rop_m_per_s": 0.005, "rpm": 60.0},
    "string": {"components": [
        {"type": "collar", "name": "DC", "od_m": 0.17145, "id_m": 0.0714, "length_m": 60.0,
         "n_segments": 6},
        {"type": "drill_pipe", "name": "DP", "od_m": 0.127, "id_m": 0.1086, "length_m": 440.0,
         "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
         "tool_joint_length_fraction": 0.05, "n_segments": 10}]},
    "recording": {"joints": [2, 8], "loads_rate_hz": 100.0},
    "fatigue": {"plots": False},
}
