"""Case study 3 of the founding paper: the horizontal section of profile 1.

docs/model.md#case-studies: the string trips in for 800 s, the top drive ramps to 50 rpm
within 40 s, then a 60 s window is recorded; loads 8, 40 and 80 m behind the
bit; lives in hours (paper: 191, 625, 677 h, the location nearest the build
section lowest).

Modelling choices (documented assumptions; the paper does not give them), by
``mode``: ``tripping`` (default, the paper's sequence): the bit is off bottom
during the whole run and the string trips in at ``trip_speed_m_per_s`` (the
simulator's tripping mode: top held axially, string length growing at the trip
speed); a run cannot stop the trip, so the string keeps sliding in while it
rotates in the window. ``on_bottom``: the trip is represented by the string's
initial placement in the hole (a run cannot switch from tripping to
drilling), the bit is on bottom with the neutral point at the top of the
collars and a slow ROP, and ``trip_s`` is simulated at zero rpm before the
ramp. Either run ends
with the bit at ``bit_md_end_m``. The rpm follows a table: 0 during the trip, a linear ramp to
``rpm`` over ``ramp_s``, then constant. Fatigue: the configured criterion at
both locations of each joint; life in hours = recorded window / damage.

Outputs in ``out_dir``: ``case3_life.csv``, ``case3_summary.json``,
``case3_loads.png``, ``case3_life.png``, and the run folder ``runs/profile_1``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import FatigueConfig
from drillfatigue.config.studies import Case3Config
from drillfatigue.fatigue.run import evaluate_run
from drillfatigue.plotting import subplots
from drillfatigue.studies.common import (
    hours,
    run_simulation,
    save_figure,
    string_components,
    study_fatigue,
    warm_up,
    write_csv,
    write_json,
)

#: The paper's lives at 8, 40, 80 m behind the bit, hours (docs/model.md#case-studies).
PAPER_LIFE_H: dict[float, float] = {8.0: 191.0, 40.0: 625.0, 80.0: 677.0}
#: The paper's run time of the 60 s window, hours.
PAPER_WALL_H = 2.0


def joints_behind_bit(cfg: Case3Config, bit_md_m: float) -> list[tuple[int, float]]:
    """Joints nearest each of ``cfg.s_from_bit_m``: (index, distance from the bit, m)."""
    s = cfg.string
    dp_len = bit_md_m - s.dc_length_m
    lengths = [s.dc_length_m / s.dc_segments] * s.dc_segments + \
        [dp_len / s.dp_segments] * s.dp_segments
    ends = np.cumsum(lengths)[:-1]
    return [(int(np.argmin(np.abs(ends - d))), float(ends[np.argmin(np.abs(ends - d))]))
            for d in cfg.s_from_bit_m]


def case_dict(cfg: Case3Config, joints: list[int], well: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], float]:
    """The simulator case and the bit MD at t = 0 (``well``: section defining the profile)."""
    t_on = cfg.trip_s
    dur = cfg.duration_s
    bit0 = cfg.bit_md_end_m - cfg.advance_m_per_s * dur
    table = [[0.0, 0.0], [t_on, 0.0], [t_on + cfg.ramp_s, cfg.rpm], [dur, cfg.rpm]]
    if t_on == 0.0:
        table = table[1:]
    if cfg.mode == "on_bottom":
        op: dict[str, Any] = {"top_axial": "neutral_point", "bit_on_bottom": True,
                              "rop_m_per_s": cfg.rop_m_per_s, "lobe_count": 3,
                              "lobe_amplitude_m": 0.001}
    else:
        op = {"top_axial": "fixed", "bit_on_bottom": False,
              "trip_speed_m_per_s": cfg.trip_speed_m_per_s}
    case = {
        "well": {**(well or {}), "profile": cfg.profile},
        "string": {"components": string_components(cfg.string, bit0)},
        "operation": {"duration_s": dur, "bit_md_m": bit0, "rpm_table": table, **op},
        "recording": {"loads_rate_hz": cfg.loads_rate_hz, "channels_rate_hz": cfg.loads_rate_hz,
                      "kinematics_rate_hz": 10.0, "joints": sorted(set(joints)),
                      "start_s": t_on + cfg.ramp_s},
    }
    return case, bit0


def run_case3(cfg: Case3Config, out_dir: Path, *, dpi: int = 110,
              well: dict[str, Any] | None = None,
              fatigue: FatigueConfig | None = None) -> dict[str, Any]:
    """Run case 3 and write its table and figures; return the summary dictionary.

    ``well``/``fatigue``: as in :func:`drillfatigue.studies.case2.run_case2`.
    """
    out_dir = Path(out_dir)
    bit0 = cfg.bit_md_end_m - cfg.advance_m_per_s * cfg.duration_s
    picks = joints_behind_bit(cfg, bit0)
    case, _ = case_dict(cfg, [j for j, _ in picks], well)
    run_dir = out_dir / "runs" / cfg.profile
    warm_up(case)  # the wall time below excludes numba compilation
    _, summary, wall = run_simulation(case, run_dir)
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    t = np.unique(loads["time_s"].to_numpy())
    span = float(t[-1] - t[0] + (t[1] - t[0])) if t.size > 1 else 0.0
    fat = fatigue if fatigue is not None else study_fatigue()
    dmg = evaluate_run(run_dir, fat, None, joints=sorted({j for j, _ in picks}),
                       criterion=cfg.criterion)
    rows = []
    for want, (j, s) in zip(cfg.s_from_bit_m, picks, strict=True):
        d = dmg[dmg["joint"] == j].set_index("location")["damage"]
        life = {loc: (hours(span) / float(d[loc]) if float(d[loc]) > 0 else math.inf)
                for loc in d.index}
        rows.append({"s_from_bit_m": want, "joint": j, "joint_s_from_bit_m": s,
                     "md_m": float(loads.loc[loads["joint"] == j, "md_m"].mean()),
                     "life_h": min(life.values()), "life_h_connection": life["connection"],
                     "life_h_body": life["body"],
                     "paper_life_h": PAPER_LIFE_H.get(float(want), math.nan)})
    table = pd.DataFrame(rows)
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "case3_life.csv", table)
    ours_order = list(table.sort_values("life_h")["s_from_bit_m"])
    summ = {
        "config": cfg.model_dump(mode="json"), "recorded_s": span, "wall_s": wall,
        "simulated_s": float(summary["duration_s"]), "paper_wall_h": PAPER_WALL_H,
        "paper_window_s": 60.0, "criterion": cfg.criterion,
        "lowest_life_s_from_bit_m": ours_order[0],
        "nearest_build_lowest": bool(ours_order[0] == max(cfg.s_from_bit_m)),
        "rows": table.to_dict(orient="records"),
    }
    _figures(out_dir, loads, picks, cfg, table, dpi)
    write_json(out_dir / "case3_summary.json", summ)
    return summ


def _figures(out_dir: Path, loads: pd.DataFrame, picks: list[tuple[int, float]],
             cfg: Case3Config, table: pd.DataFrame, dpi: int) -> None:
    fig, ax = subplots(3, 1, figsize=(8, 8), sharex=True)
    for j, s in picks:
        h = loads[loads["joint"] == j]
        kw = {"lw": 0.6, "label": f"{s:.0f} m behind the bit"}
        ax[0].plot(h["time_s"], h["axial_N"] / 1e3, **kw)
        ax[1].plot(h["time_s"], h["torque_Nm"] / 1e3, **kw)
        ax[2].plot(h["time_s"], np.hypot(h["bending_x_Nm"], h["bending_y_Nm"]) / 1e3, **kw)
    ax[0].set_ylabel("axial force, kN")
    ax[1].set_ylabel("torque, kN·m")
    ax[2].set_ylabel("bending moment, kN·m")
    ax[2].set_xlabel("time, s")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"Case 3: {cfg.profile} horizontal section, {cfg.rpm:.0f} rpm window")
    save_figure(fig, out_dir / "case3_loads.png", dpi)

    fig, ax = subplots(figsize=(6, 4))
    x = np.arange(len(table))
    life = table["life_h"].to_numpy(dtype=float)
    ax.bar(x - 0.2, np.where(np.isfinite(life), life, np.nan), 0.4,
           label=f"ours, {cfg.criterion}")  # an infinite life (no damage) is left out
    ax.bar(x + 0.2, table["paper_life_h"], 0.4, label="paper")
    ax.set_xticks(x, [f"{v:.0f} m" for v in table["s_from_bit_m"]])
    ax.set_yscale("log")
    ax.set_xlabel("distance behind the bit")
    ax.set_ylabel("life, h")
    ax.legend(fontsize=8)
    ax.set_title("Case 3: fatigue life")
    save_figure(fig, out_dir / "case3_life.png", dpi)
