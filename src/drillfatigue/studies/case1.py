"""Case study 1 of the founding paper: whirl of a short pipe and the friction models.

docs/model.md#case-studies and docs/model.md#friction: a 5 m pipe cut into 5 segments, free ends, in a
horizontal hole, driven by a constant torque at the top; Karnopp against the
hybrid tanh-exponential friction model, at low and high friction. The paper
saw the pipe climb the wall and slide back at low friction, and continuous
contact with backward whirl at high friction; tanh-exponential reproduced
Karnopp 2.6x faster (47 vs 18 min).

Set-up: the named case ``data/cases/case1_whirl.yaml`` (its comments give the
choices: 8 1/2 in horizontal hole along north, 5 in drill-pipe body without tool
joints, r_p = 63.5 mm, R_h = 107.95 mm, so rolling without slip is
Omega_w = -r_p/(R_h - r_p) omega = -1.43 omega; free top, bit off bottom,
constant torque applied at once), with this study's friction model and level,
torque and duration. The study has no rig section on purpose: nothing is drilled
(bit off bottom, no ROP), and the paper's free ends and torque drive are the
boundary conditions a block and a top-drive speed controller would replace
(docs/rig.md#the-stages-and-the-rig-boundaries). Wall times are measured after a short warm-up run, so
they exclude numba compilation.

Whirl analysis from ``kinematics.parquet``: the orbit angle of each segment
centre in the hole cross-section, theta = atan2(z, y) (right-handed about the
hole axis +x, the same sense as positive rpm), unwrapped; whirl rate =
d theta/dt (least squares over the second half of the run), compared with the
rolling value from the mean spin rate over the same interval.

Outputs: ``case1_whirl.csv``, ``case1_summary.json``, ``case1_orbits.png``,
``case1_whirl_rate.png``, runs in ``runs/<model>_<level>``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import case_from_dict
from drillfatigue.config.base import read_yaml
from drillfatigue.config.studies import Case1Config
from drillfatigue.plotting import subplots
from drillfatigue.studies.common import (
    run_simulation,
    save_figure,
    warm_up,
    write_csv,
    write_json,
)
from drillfatigue.well import build_survey
from drillfatigue.units import rad_per_s_from_rpm

#: The named reference case this study varies (pipe, hole, torque, free top).
CASE_FILE = Path(__file__).resolve().parents[3] / "data" / "cases" / "case1_whirl.yaml"
PIPE_OD_M = 0.127
PIPE_ID_M = 0.1086
HOLE_D_M = 0.2159
#: The paper's wall times of the whirl runs, minutes (docs/model.md#case-studies).
PAPER_WALL_MIN: dict[str, float] = {"karnopp": 47.0, "tanh_exp": 18.0}


def rolling_ratio() -> float:
    """Omega_w / omega of rolling without slip: -r_p / (R_h - r_p) (docs/model.md#friction)."""
    r_p, r_h = PIPE_OD_M / 2, HOLE_D_M / 2
    return -r_p / (r_h - r_p)


def case_dict(cfg: Case1Config, model: str, mu_dynamic: float) -> dict[str, Any]:
    """One whirl run: the named case ``data/cases/case1_whirl.yaml`` with this study's
    friction model, friction level, pipe, torque and duration."""
    case = read_yaml(CASE_FILE)
    comp = dict(case["string"]["components"][0])
    comp.update(length_m=cfg.pipe_length_m, n_segments=cfg.n_segments)
    case["string"] = {"components": [comp]}
    op = dict(case["operation"])
    op.update(duration_s=cfg.duration_s, top_torque_Nm=cfg.top_torque_Nm,
              top_md_m=op["bit_md_m"] - cfg.pipe_length_m)
    case["operation"] = op
    case["friction"] = {**case.get("friction", {}), "model": model, "mu_dynamic": mu_dynamic,
                        "mu_static": min(mu_dynamic * cfg.static_over_dynamic, 1.5)}
    rec = dict(case.get("recording", {}))
    rec.update(kinematics_rate_hz=cfg.kinematics_rate_hz,
               events_start_s=min(rec.get("events_start_s", 0.0), 0.5 * cfg.duration_s))
    case["recording"] = rec
    return case


def hole_centre(case: dict[str, Any], x_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hole centre (east, TVD) at the given north coordinates (horizontal section along north)."""
    sv = build_survey(case_from_dict(case).well)
    pos = np.asarray(sv.pos_m)
    north, east, tvd = pos[:, 0], pos[:, 1], pos[:, 2]
    order = np.argsort(north)
    return (np.interp(x_m, north[order], east[order]), np.interp(x_m, north[order], tvd[order]))


def orbit_angles(kin: pd.DataFrame, case: dict[str, Any]) -> pd.DataFrame:
    """Orbit of each segment centre about the hole axis (horizontal, along north).

    Adds ``dy_m``, ``dz_m`` (east and down offsets from the hole centre) and the
    unwrapped orbit angle ``theta_rad = atan2(dz, dy)`` (right-handed about +x).
    """
    kin = kin.sort_values(["segment", "time_s"]).copy()
    yc, zc = hole_centre(case, kin["x_m"].to_numpy())
    kin["dy_m"] = kin["y_m"] - yc
    kin["dz_m"] = kin["z_m"] - zc
    kin["theta_rad"] = np.arctan2(kin["dz_m"], kin["dy_m"])
    kin["theta_rad"] = kin.groupby("segment")["theta_rad"].transform(
        lambda a: np.unwrap(a.to_numpy()))
    return kin


def whirl_rate(kin: pd.DataFrame, t_from: float) -> float:
    """Mean orbit rate of the segment centres after ``t_from``, rad/s (slope of theta(t))."""
    rates = []
    for _, g in kin[kin["time_s"] >= t_from].groupby("segment"):
        if len(g) >= 3:
            rates.append(np.polyfit(g["time_s"], g["theta_rad"], 1)[0])
    return float(np.mean(rates)) if rates else math.nan


def run_case1(cfg: Case1Config, out_dir: Path, *, dpi: int = 110) -> dict[str, Any]:
    """Run the four whirl cases and write the table and figures."""
    out_dir = Path(out_dir)
    rows = []
    orbits: dict[str, pd.DataFrame] = {}
    spins: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for model in cfg.models:
        for level, mu in (("low", cfg.mu_low), ("high", cfg.mu_high)):
            name = f"{model}_{level}"
            run_dir = out_dir / "runs" / name
            case = case_dict(cfg, model, mu)
            warm_up(case)
            _, summary, wall = run_simulation(case, run_dir)
            kin = orbit_angles(pd.read_parquet(run_dir / rundir.KINEMATICS), case)
            ch = pd.read_parquet(run_dir / rundir.CHANNELS)
            t_from = 0.5 * cfg.duration_s
            late = ch[ch["time_s"] >= t_from]
            omega = rad_per_s_from_rpm(float(np.mean(late["top_rpm"])))
            rate = whirl_rate(kin, t_from)
            orbits[name] = kin
            if level == "high":  # the rolling reference, from the spin rate, rad/s
                spins[name] = (ch["time_s"].to_numpy(),
                               rad_per_s_from_rpm(ch["top_rpm"].to_numpy()))
            contact = kin[kin["time_s"] >= t_from]
            rows.append({
                "model": model, "friction": level, "mu_dynamic": mu,
                "spin_rpm": omega * 60 / (2 * math.pi),
                "whirl_rate_rad_per_s": rate,
                "whirl_ratio": rate / omega if omega != 0 else math.nan,
                "rolling_ratio": rolling_ratio(),
                "rolling_whirl_rate_rad_per_s": rolling_ratio() * omega,
                "direction": ("none" if not np.isfinite(rate) or abs(rate) < 0.05 * abs(omega)
                              else ("forward" if rate * omega > 0 else "backward")),
                "simulator_whirl_class": summary.get("events", {}).get("whirl_class"),
                "contact_fraction": float((contact["normal_N"] > 0).mean()),
                "wall_s": wall, "simulated_s": float(summary["duration_s"]),
                "paper_wall_min": PAPER_WALL_MIN.get(model, math.nan),
            })
    table = pd.DataFrame(rows)
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "case1_whirl.csv", table)
    walls = table.groupby("model")["wall_s"].sum().to_dict()
    speedup = (walls["karnopp"] / walls["tanh_exp"]
               if "karnopp" in walls and "tanh_exp" in walls and walls["tanh_exp"] > 0
               else math.nan)
    summ = {"config": cfg.model_dump(mode="json"), "rolling_ratio": rolling_ratio(),
            "wall_s_by_model": walls, "speedup_karnopp_over_tanh_exp": speedup,
            "paper_speedup": 47.0 / 18.0, "rows": table.to_dict(orient="records")}
    _figures(out_dir, orbits, spins, dpi)
    write_json(out_dir / "case1_summary.json", summ)
    return summ


def _figures(out_dir: Path, orbits: dict[str, pd.DataFrame],
             spins: dict[str, tuple[np.ndarray, np.ndarray]], dpi: int) -> None:
    names = list(orbits)
    ncol = min(len(names), 2)
    nrow = math.ceil(len(names) / ncol)
    fig, axes = subplots(nrow, ncol, figsize=(4.2 * ncol, 4.2 * nrow), squeeze=False)
    r_h = HOLE_D_M / 2
    clear = r_h - PIPE_OD_M / 2
    ang = np.linspace(0, 2 * np.pi, 200)
    for ax, name in zip(axes.ravel(), names, strict=False):
        kin = orbits[name]
        for seg, g in kin.groupby("segment"):
            ax.plot(g["dy_m"] * 1e3, g["dz_m"] * 1e3, lw=0.5, label=f"segment {seg}")
        ax.plot(clear * 1e3 * np.cos(ang), clear * 1e3 * np.sin(ang), "k--", lw=0.8,
                label="centre at wall contact")
        ax.set_aspect("equal")
        ax.invert_yaxis()
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("east, mm")
        ax.set_ylabel("down, mm")
    axes.ravel()[0].legend(fontsize=6)
    fig.suptitle("Case 1: orbits of the segment centres in the hole cross-section")
    save_figure(fig, out_dir / "case1_orbits.png", dpi)

    fig, ax = subplots(figsize=(8, 4))
    for i, name in enumerate(names):
        kin = orbits[name]
        g = kin.groupby("time_s")["theta_rad"].mean()
        rate = np.gradient(g.to_numpy(), g.index.to_numpy())
        k = max(1, len(rate) // 50)
        smooth = np.convolve(rate, np.ones(k) / k, mode="valid")  # no edge artefacts
        t = g.index.to_numpy()[k // 2: k // 2 + smooth.size]
        style = {"lw": 2.2, "alpha": 0.5} if name.startswith("karnopp") else {"lw": 0.9}
        ax.plot(t, smooth, color=f"C{i}", label=name, **style)
        if name in spins:
            ts, w = spins[name]
            ax.plot(ts, rolling_ratio() * w, ":", color=f"C{i}", lw=0.8,
                    label=f"{name}: rolling without slip")
    ax.set_xlabel("time, s")
    ax.set_ylabel("whirl rate dθ/dt, rad/s\n(< 0 backward)")
    ax.legend(fontsize=8)
    ax.set_title("Case 1: whirl rate (mean over segments, moving average)")
    save_figure(fig, out_dir / "case1_whirl_rate.png", dpi)
