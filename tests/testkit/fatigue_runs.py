"""Synthetic simulator run directories for the fatigue tests.

``write_run_dir`` writes the run-directory contract of the simulator:
``loads.parquet``, ``joints.parquet``, ``summary.json``, ``case.yaml``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue import rundir

LOAD_NAMES = ("axial_N", "shear_x_N", "shear_y_N", "bending_x_Nm", "bending_y_Nm", "torque_Nm")


def synthetic_loads(n_t: int, dt: float = 1e-3, rpm: float = 120.0, seed: int = 0,
                    scale: float = 1.0) -> np.ndarray:
    """Drill-pipe-like loads, shape (n_t, 6): rotating bending in a dogleg
    (a constant moment seen in the rotating joint frame), axial bit-lobe
    vibration, torsional oscillation and a little smoothed noise."""
    if n_t < 9:
        return np.zeros((n_t, 6))
    rng = np.random.default_rng(seed)
    t = np.arange(n_t) * dt
    w = 2 * np.pi * rpm / 60.0
    noise = rng.normal(size=(n_t, 6))
    k = np.ones(9) / 9.0
    noise = np.column_stack([np.convolve(noise[:, i], k, mode="same") for i in range(6)])
    M = 8e3 * scale
    L = np.empty((n_t, 6))
    L[:, 0] = 2.0e5 + 3e4 * np.sin(3 * w * t) + 2e3 * noise[:, 0]
    L[:, 1] = 2e3 * np.sin(w * t + 0.3) + 200 * noise[:, 1]
    L[:, 2] = 2e3 * np.cos(w * t + 0.3) + 200 * noise[:, 2]
    L[:, 3] = M * np.sin(w * t) + 0.05 * M * np.sin(17 * w * t) + 0.02 * M * noise[:, 3]
    L[:, 4] = M * np.cos(w * t) + 0.05 * M * np.cos(17 * w * t) + 0.02 * M * noise[:, 4]
    L[:, 5] = 1.5e4 + 4e3 * np.sin(0.4 * t * 2 * np.pi) + 300 * noise[:, 5]
    return L


def write_run_dir(path: Path, *, n_joints: int = 3, n_t: int = 1500, dt: float = 1e-3,
                  status: str = "complete", seed: int = 0, drop_column: str | None = None,
                  nan: bool = False, loads: dict[int, np.ndarray] | None = None) -> Path:
    """Write a synthetic run directory; returns ``path``."""
    path.mkdir(parents=True, exist_ok=True)
    t = np.arange(n_t) * dt
    frames = []
    jrows = []
    for j in range(n_joints):
        L = loads[j] if loads is not None else synthetic_loads(n_t, dt, seed=seed + j,
                                                               scale=1.0 + 0.3 * j)
        df = pd.DataFrame({"time_s": t, "joint": j, "md_m": 500.0 - 9.0 * j})
        for i, name in enumerate(LOAD_NAMES):
            df[name] = L[:, i]
        frames.append(df)
        ctype = "collar" if j == 0 else "drill_pipe"
        jrows.append({"joint": j, "component": f"{ctype}_{j}", "component_type": ctype,
                      "s_from_bit_m": 9.0 * j,
                      "body_od_m": 0.1714 if j == 0 else 0.127,
                      "body_id_m": 0.0714 if j == 0 else 0.1086,
                      "conn_od_m": 0.1714 if j == 0 else 0.168,
                      "conn_id_m": 0.0714 if j == 0 else 0.0826})
    loads_df = pd.concat(frames, ignore_index=True)
    if nan:
        loads_df.loc[5, "torque_Nm"] = np.nan
    if drop_column is not None:
        loads_df = loads_df.drop(columns=[drop_column])
    loads_df.to_parquet(path / rundir.LOADS, index=False)
    pd.DataFrame(jrows).to_parquet(path / rundir.JOINTS, index=False)
    (path / rundir.SUMMARY).write_text(json.dumps({"duration_s": n_t * dt if n_t else 1.0,
                                                   "status": status}))
    (path / "case.yaml").write_text("fatigue:\n  plane_step_deg: 15.0\n  n_refine: 2\n")
    return path
