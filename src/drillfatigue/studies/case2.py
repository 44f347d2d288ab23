"""Case study 2 of the founding paper: three well profiles with the same start and end.

docs/model.md#case-studies: 100 drill-pipe + 20 collar segments, 150 rpm, ROP 0.5 m/s, hook
load putting the neutral point at the top of the collars, 800 s of drilling
from just above the kick-off into the horizontal (the string grows 480 -> 880
m). Reported: internal force and torque of the segment 40 m behind the bit as
it passes through the build, the stress history at its connection, and the
fatigue life in repetitions of the 800 s window by the critical-plane
criterion (default Matake, docs/fatigue.md) and by API RP7G (Lubinski). The paper's
lives: profile 2: 12.8 > profile 1: 10.3 > profile 3: 5.9 windows.

Reduced mode (``n_samples > 1``): the 800 s are represented by ``n_samples``
short windows at bit depths spread evenly over 480 -> 880 m; each window's
damage per second (over its recorded part, after ``settle_s``) stands for its
share of the 800 s (quasi-stationary sampling). With ``n_samples = 1`` and
``sample_s = 800`` it is the paper's single continuous window.

Boundaries (``boundaries``): ``rig`` (default) drills as a rig does: the
autodriller holds ``wob_set_N`` on the bit, the bit law gives the ROP, the
string grows by the block's travel, the lobes are the rock face's
(``docs/rig.md``); each window is continuous, and ``case2_drilling.csv`` reports
per profile the on-bottom fraction after ``metrics_skip_s``, the mean WOB
against its set-point, the ROP and surface torque, the block and string-top
checks and the whirl, bounce and stick-slip classes. ``prescribed_rop`` is the
founding paper's set-up (the bit guided at ``rop_m_per_s``), kept for validation.

Outputs in ``out_dir``: ``case2_life.csv``, ``case2_diagnostics.csv``, ``case2_drilling.csv``,
``case2_summary.json``, figures ``case2_loads.png``, ``case2_connection_stress.png``,
``case2_life.png``, and the run folders ``runs/<profile>/sample_<k>``; with
``tortuosity`` set, also ``case2_life_tortuous.csv``, ``case2_diagnostics_tortuous.csv``
and ``runs/<profile>_tortuous/sample_<k>`` (every profile again in its plan with
that tortuosity).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import CaseConfig, FatigueConfig
from drillfatigue.config.studies import Case2Config
from drillfatigue.dynamics.top.rig import drilling_window_metrics
from drillfatigue.dynamics.bit.rockface import rop_tob_from_wob
from drillfatigue.softstring.torque_drag import torque_drag_for_case
from drillfatigue.fatigue.run import evaluate_run
from drillfatigue.fatigue.stress import SCF, Section, surface_stresses
from drillfatigue.plotting import subplots
from drillfatigue.studies.common import (
    rig_drilling_sections,
    rp7g_rates,
    run_simulation,
    save_figure,
    string_components,
    study_fatigue,
    warm_up,
    write_csv,
    write_json,
)
from drillfatigue.well import build_survey

#: The paper's lives in 800 s windows (docs/model.md#case-studies).
PAPER_LIFE_WINDOWS: dict[str, float] = {"profile_1": 10.3, "profile_2": 12.8, "profile_3": 5.9}
#: The paper's run time for the three 800 s profiles, hours (docs/model.md#case-studies).
PAPER_WALL_H = 38.0


def target_joint(cfg: Case2Config) -> tuple[int, float]:
    """Joint index (from the bit) nearest ``target_s_from_bit_m`` and its distance, m.

    Joint j joins segments j and j+1 (segment 0 at the bit); its distance from
    the bit is the summed length of segments 0..j.
    """
    s = cfg.string
    dp_len = cfg.bit_md_start_m - s.dc_length_m
    lengths = [s.dc_length_m / s.dc_segments] * s.dc_segments + \
        [dp_len / s.dp_segments] * s.dp_segments
    ends = np.cumsum(lengths)[:-1]
    j = int(np.argmin(np.abs(ends - cfg.target_s_from_bit_m)))
    return j, float(ends[j])


def sample_bit_md(cfg: Case2Config) -> list[float]:
    """Bit MD at the start of each sample window, m."""
    span = cfg.bit_md_end_m - cfg.bit_md_start_m
    n = cfg.n_samples
    drilled = cfg.rop_m_per_s * cfg.sample_s
    return [cfg.bit_md_start_m + k * span / n + 0.5 * max(span / n - drilled, 0.0)
            for k in range(n)]


def case_dict(cfg: Case2Config, profile: str, bit_md_m: float, joint: int | None,
              well: dict[str, Any] | None = None) -> dict[str, Any]:
    """The simulator case of one sample window of one profile.

    ``joint``: the only joint recorded (None: all). ``well``: a ``well`` section
    defining ``profile`` (default: the project's case-2 family).
    """
    if cfg.boundaries == "rig":
        # the rig drills: the autodriller holds the WOB, the bit law gives the ROP, the
        # lobed face is the rock's
        operation: dict[str, Any] = {"duration_s": cfg.sample_s, "bit_md_m": bit_md_m,
                                     "rpm": cfg.rpm, "rpm_ramp_s": cfg.rpm_ramp_s,
                                     "top_axial": "neutral_point", "bit_on_bottom": True}
        extra: dict[str, Any] = rig_drilling_sections(
            wob_set_N=cfg.wob_set_N, measurement=cfg.autodriller_measurement,
            initial_travel_m=cfg.block_initial_travel_m, lobe_amplitude_m=cfg.lobe_amplitude_m)
    elif cfg.boundaries == "rig_rop":
        # the sweep's rig mode: the autodriller drills at the ROP target (its ROP limit)
        # unless the WOB reaches its limit (the set-point) first; the run starts in
        # steady drilling and the bit cuts what the bit law lets it
        operation = {"duration_s": cfg.sample_s, "bit_md_m": bit_md_m, "rpm": cfg.rpm,
                     "rpm_ramp_s": cfg.rpm_ramp_s, "top_axial": "neutral_point",
                     "bit_on_bottom": True}
        extra = rig_drilling_sections(
            wob_set_N=cfg.wob_set_N, measurement=cfg.autodriller_measurement,
            initial_travel_m=cfg.block_initial_travel_m, lobe_amplitude_m=cfg.lobe_amplitude_m)
        extra["rig"]["autodriller"]["rop_limit_m_per_s"] = cfg.rop_m_per_s
    else:
        operation = {"duration_s": cfg.sample_s, "bit_md_m": bit_md_m, "rpm": cfg.rpm,
                     "rpm_ramp_s": cfg.rpm_ramp_s, "top_axial": "neutral_point",
                     "rop_m_per_s": cfg.rop_m_per_s, "bit_on_bottom": True,
                     "lobe_count": 3, "lobe_amplitude_m": cfg.lobe_amplitude_m}
        extra = {}
    return {
        **extra,
        "well": {**(well or {}), "profile": profile},
        "string": {"components": string_components(cfg.string, bit_md_m)},
        "operation": operation,
        "recording": {"loads_rate_hz": cfg.loads_rate_hz, "channels_rate_hz": cfg.loads_rate_hz,
                      "kinematics_rate_hz": 10.0, "joints": None if joint is None else [joint],
                      "start_s": cfg.settle_s},
        "solver": {"relax_s": cfg.relax_s, "safety_factor": cfg.safety_factor,
                   "implicit_bit_torque": cfg.implicit_bit_torque},
    }


#: bit speed below which the bit counts as stuck, as a fraction of the mean (stick-slip)
STUCK_FRACTION = 0.1
#: stick-slip severity (max - min) / mean bit speed above which the rotation is called a
#: torsional oscillation when the bit never sticks
OSCILLATION_SEVERITY = 0.5


def drilling_metrics(run_dir: Path, summary: dict[str, Any], cfg: Case2Config, profile: str,
                     sample: int, case: CaseConfig | None = None) -> dict[str, Any]:
    """What one rig-driven window did at the rig and the bit (case-2 metrics).

    From the run's channels after ``metrics_skip_s``
    (:func:`drillfatigue.dynamics.top.rig.drilling_window_metrics`): the on-bottom
    fraction, mean WOB and its error from the set-point, mean ROP and surface
    torque, the block within its travel and the string top never above the
    rotary; the classes of the run: whirl (the simulator's dominant class), bit
    bounce (lift-offs counted, ``bounce`` when any) and stick-slip (``stick_slip``
    when the bit speed falls below ``STUCK_FRACTION`` of its mean, ``oscillation``
    when the severity exceeds ``OSCILLATION_SEVERITY``, else ``none``).

    With the run's ``case`` the references beside them: the bit law's ROP and
    TOB at the mean WOB and mean bit speed (``rop_bit_law_m_per_s``,
    ``rop_over_bit_law``, ``tob_bit_law_Nm``), and the soft-string drilling
    torque at the surface for that WOB and TOB (Coulomb wall friction with the
    case's ``mu_dynamic``, no mud drag; ``surface_torque_tnd_Nm``,
    ``surface_torque_over_tnd``).
    """
    ch = pd.read_parquet(run_dir / "channels.parquet")
    t = ch["time_s"].to_numpy()
    skip = max(cfg.metrics_skip_s - float(t[0]), 0.0)
    if t[-1] - t[0] <= skip:
        # a window shorter than the start-up (reduced test runs): all of it, said so
        skip = 0.0
    out: dict[str, Any] = {"profile": profile, "sample": sample,
                           "wob_set_N": cfg.wob_set_N, "metrics_from_s": float(t[0]) + skip}
    out.update(drilling_window_metrics(
        t, ch["wob_N"].to_numpy(), ch["rop_m_per_s"].to_numpy(),
        ch["surface_torque_Nm"].to_numpy(), ch["block_travel_m"].to_numpy(),
        float(summary["rig"]["effective_inputs"]["block"]["travel_m"]), cfg.wob_set_N,
        ch["string_top_above_rotary_m"].to_numpy(), t_skip_s=skip))
    sel = t >= t[0] + skip
    rpm = ch["bit_rpm"].to_numpy()[sel]
    mean = float(rpm.mean())
    sev = float((rpm.max() - rpm.min()) / mean) if mean > 0 else math.inf
    out["mean_rop_m_per_h"] = out["mean_rop_m_per_s"] * 3600.0
    out["block_travel_range_m"] = out["block_max_m"] - out["block_min_m"]
    out["bit_rpm_mean"] = mean
    out["stick_slip_severity"] = sev
    out["stick_slip_class"] = ("stick_slip" if rpm.min() < STUCK_FRACTION * mean else
                               "oscillation" if sev > OSCILLATION_SEVERITY else "none")
    out["whirl_class"] = summary.get("whirl_class")
    out["bit_bounce_count"] = summary.get("bit_bounce_count")
    out["bounce_class"] = "bounce" if (summary.get("bit_bounce_count") or 0) > 0 else "none"
    out["mean_tob_Nm"] = float(ch["tob_Nm"].to_numpy()[sel].mean())
    if case is not None:
        rop_law, tob_law = rop_tob_from_wob(case.bit, out["mean_wob_N"], mean)
        out["rop_bit_law_m_per_s"] = float(rop_law)
        out["rop_over_bit_law"] = (out["mean_rop_m_per_s"] / float(rop_law)
                                   if rop_law > 0 else math.nan)
        out["tob_bit_law_Nm"] = float(tob_law)
        tnd = torque_drag_for_case(case, wob_N=out["mean_wob_N"], tob_Nm=float(tob_law))
        out["surface_torque_tnd_Nm"] = float(tnd.torque_drilling_Nm[0])
        out["surface_torque_over_tnd"] = (out["mean_surface_torque_Nm"]
                                          / out["surface_torque_tnd_Nm"])
    out["drilled_m"] = float(ch["bit_md_m"].iloc[-1] - ch["bit_md_m"].iloc[0])
    out["simulated_s"] = float(summary["duration_s"])
    out["wall_s"] = float(summary["wall_time_s"])
    return out


def run_case2(cfg: Case2Config, out_dir: Path, *, dpi: int = 110,
              well: dict[str, Any] | None = None,
              fatigue: FatigueConfig | None = None) -> dict[str, Any]:
    """Run case 2 and write its tables and figures; return the summary dictionary.

    ``well``: a ``well`` section defining the profiles (default: the project's
    case-2 family); ``fatigue``: fatigue settings (default: project defaults).
    Every profile runs in its plan (``case2_life.csv``, ``case2_diagnostics.csv``,
    ``runs/<profile>``) and, when ``cfg.tortuosity`` is set, again in the plan
    with that tortuosity (``case2_life_tortuous.csv``, ``runs/<profile>_tortuous``;
    the summary's ``tortuous`` entry).
    """
    out_dir = Path(out_dir)
    fat = fatigue if fatigue is not None else study_fatigue()
    joint, s_joint = target_joint(cfg)
    plan = _run_profiles(cfg, out_dir, "", well, fat, joint, warm=True)
    table = plan["table"]
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "case2_life.csv", table)
    write_csv(out_dir / "case2_diagnostics.csv", pd.DataFrame(plan["diag"]))
    if plan["drilling"]:
        write_csv(out_dir / "case2_drilling.csv", pd.DataFrame(plan["drilling"]))
    order_paper = [p for p in sorted(PAPER_LIFE_WINDOWS, key=lambda p: -PAPER_LIFE_WINDOWS[p])
                   if p in cfg.profiles]
    config = cfg.model_dump(mode="json")
    if cfg.tortuosity is None:
        config.pop("tortuosity")  # the summary of the plans alone
    summary: dict[str, Any] = {
        "config": config,
        "target_joint": joint, "target_s_from_bit_m": s_joint, "window_s": cfg.window_s,
        "criterion": cfg.criterion,
        **_orders(table, order_paper),
        "wall_s_total": float(table["wall_s"].sum()),
        "paper_wall_h": PAPER_WALL_H,
        "rows": table.to_dict(orient="records"),
        "boundaries": cfg.boundaries,
        "drilling": plan["drilling"],
    }
    if cfg.tortuosity is not None:
        tort = _run_profiles(cfg, out_dir, "_tortuous",
                             {**(well or {}), "tortuosity": cfg.tortuosity.model_dump(mode="json")},
                             fat, joint, warm=False)
        write_csv(out_dir / "case2_life_tortuous.csv", tort["table"])
        write_csv(out_dir / "case2_diagnostics_tortuous.csv", pd.DataFrame(tort["diag"]))
        summary["tortuous"] = {
            "tortuosity": cfg.tortuosity.model_dump(mode="json"),
            "peak_added_dls_deg_per_30m": cfg.tortuosity.peak_added_dls_deg_per_30m,
            **_orders(tort["table"], order_paper),
            "wall_s_total": float(tort["table"]["wall_s"].sum()),
            "rows": tort["table"].to_dict(orient="records"),
            "drilling": tort["drilling"],
        }
    _figures(out_dir, cfg, plan["histories"], table, joint, s_joint, dpi, fat)
    write_json(out_dir / "case2_summary.json", summary)
    return summary


def _orders(table: pd.DataFrame, order_paper: list[str]) -> dict[str, Any]:
    """The profiles from the longest life down, by the critical plane and by RP7G, and
    whether the critical plane's order is the paper's."""
    order_ours = list(table.sort_values("life_windows_critical_plane",
                                        ascending=False)["profile"])
    order_rp7g = list(table.sort_values("life_windows_api_rp7g", ascending=False)["profile"])
    return {"order_ours": order_ours, "order_api_rp7g": order_rp7g, "order_paper": order_paper,
            "order_agrees": [p for p in order_ours if p in order_paper] == order_paper}


def _run_profiles(cfg: Case2Config, out_dir: Path, suffix: str,
                  well: dict[str, Any] | None, fat: FatigueConfig,
                  joint: int, *, warm: bool) -> dict[str, Any]:
    """Run every profile's sample windows in the hole ``well`` gives, into
    ``out_dir/runs/<profile><suffix>/sample_<k>``; return the life table (with ranks),
    the per-sample diagnostics, the drilling metrics and the load histories. ``warm``:
    compile the kernels on the first case first (once per study)."""
    window_s = cfg.window_s
    rows: list[dict[str, Any]] = []
    diag: list[dict[str, Any]] = []
    drilling: list[dict[str, Any]] = []
    histories: dict[str, list[pd.DataFrame]] = {}
    for profile in cfg.profiles:
        wall = 0.0
        d_cp = {"body": 0.0, "connection": 0.0}
        d_rp7g = 0.0
        histories[profile] = []
        for k, bit0 in enumerate(sample_bit_md(cfg)):
            case = case_dict(cfg, profile, bit0, joint, well)
            if warm and not rows and k == 0:
                warm_up(case)  # wall times below exclude numba compilation
            run_dir = out_dir / "runs" / f"{profile}{suffix}" / f"sample_{k}"
            cc, summary, w = run_simulation(case, run_dir)
            wall += w
            loads = pd.read_parquet(run_dir / rundir.LOADS)
            t = np.unique(loads["time_s"].to_numpy())
            span = float(t[-1] - t[0] + (t[1] - t[0])) if t.size > 1 else 0.0
            share = window_s / cfg.n_samples  # seconds of the 800 s this sample stands for
            dmg = evaluate_run(run_dir, fat, None, joints=[joint], criterion=cfg.criterion)
            for _, r in dmg.iterrows():  # drill-pipe joints also have an upset location
                loc = str(r["location"])
                d_cp[loc] = d_cp.get(loc, 0.0) + float(r["damage"]) / span * share
            rp = rp7g_rates(run_dir, case, fat)
            rate_h = float(rp.loc[rp["joint"] == joint, "damage_rate_per_h"].iloc[0])
            d_rp7g += rate_h * share / 3600.0
            if cfg.boundaries == "rig":
                drilling.append(drilling_metrics(run_dir, summary, cfg, profile, k, cc))
            loads = loads.assign(sample=k, t_window_s=loads["time_s"] + k * share)
            histories[profile].append(loads)
            survey = build_survey(cc.well)
            md = loads["md_m"].to_numpy()
            diag.append({
                "profile": profile, "sample": k, "bit_md_start_m": bit0,
                "joint_md_mean_m": float(md.mean()),
                "local_dls_deg_per_30m": float(np.interp(md.mean(), survey.md_m,
                                                         survey.dls_deg_per_30m)),
                "axial_mean_N": float(loads["axial_N"].mean()),
                "torque_mean_Nm": float(loads["torque_Nm"].mean()),
                "bending_amplitude_Nm": float(np.hypot(loads["bending_x_Nm"],
                                                       loads["bending_y_Nm"]).mean()),
                "damage_connection_per_s": float(dmg.loc[dmg["location"] == "connection",
                                                         "damage"].iloc[0]) / span,
                "rp7g_rate_per_h": rate_h,
                "wall_s": w, "simulated_s": float(summary["duration_s"]),
                "max_contact_force_N": float(summary.get("events", {}).get(
                    "max_contact_force_N", math.nan) or math.nan),
            })
        life_cp = {loc: (1.0 / d if d > 0 else math.inf) for loc, d in d_cp.items()}
        rows.append({
            "profile": profile,
            "life_windows_critical_plane": min(life_cp.values()),
            "life_windows_connection": life_cp["connection"],
            "life_windows_body": life_cp["body"],
            "life_windows_api_rp7g": 1.0 / d_rp7g if d_rp7g > 0 else math.inf,
            "paper_life_windows": PAPER_LIFE_WINDOWS.get(profile, math.nan),
            "wall_s": wall,
            "simulated_s": cfg.n_samples * cfg.sample_s,
        })
    table = pd.DataFrame(rows)
    table["rank_ours"] = table["life_windows_critical_plane"].rank(ascending=False,
                                                                   method="min").astype(int)
    table["rank_api_rp7g"] = table["life_windows_api_rp7g"].rank(ascending=False,
                                                                 method="min").astype(int)
    table["rank_paper"] = table["paper_life_windows"].rank(ascending=False,
                                                           method="min").astype("Int64")
    return {"table": table, "diag": diag, "drilling": drilling, "histories": histories}


def _figures(out_dir: Path, cfg: Case2Config, histories: dict[str, list[pd.DataFrame]],
             table: pd.DataFrame, joint: int, s_joint: float, dpi: int,
             fat: FatigueConfig) -> None:
    fig, ax = subplots(3, 1, figsize=(8, 8), sharex=True)
    for i, (profile, parts) in enumerate(histories.items()):
        series = [(h["md_m"].to_numpy(), h["axial_N"].to_numpy() / 1e3,
                   h["torque_Nm"].to_numpy() / 1e3,
                   np.hypot(h["bending_x_Nm"], h["bending_y_Nm"]).to_numpy() / 1e3)
                  for h in parts]
        if len(parts) == 1:  # one continuous window: the history along the build
            md, *ys = series[0]
            for a, y in zip(ax, ys, strict=True):
                a.plot(md, y, lw=0.5, color=f"C{i}", label=profile)
        else:  # sampled windows: mean and min-max range of each sample
            md = np.array([x[0].mean() for x in series])
            for q, a in enumerate(ax, start=1):
                y = [x[q] for x in series]
                mean = np.array([v.mean() for v in y])
                err = [mean - np.array([v.min() for v in y]),
                       np.array([v.max() for v in y]) - mean]
                a.errorbar(md + 2.0 * (i - 1), mean, yerr=err, fmt="o-", ms=3, lw=0.8,
                           capsize=2, color=f"C{i}", label=profile)
    ax[0].set_ylabel("axial force, kN\n(> 0 tension)")
    ax[1].set_ylabel("torque, kN·m")
    ax[2].set_ylabel("bending moment, kN·m")
    ax[2].set_xlabel(f"MD of the joint {s_joint:.0f} m behind the bit, m")
    ax[0].legend(fontsize=8)
    how = "" if cfg.n_samples == 1 else ": mean and range of each sampled window"
    ax[0].set_title(f"Case 2: loads of joint {joint} ({s_joint:.0f} m behind the bit){how}",
                    fontsize=10)
    save_figure(fig, out_dir / "case2_loads.png", dpi)

    s = fat.scf["drill_pipe" if s_joint > cfg.string.dc_length_m else "collar"].connection
    fig, ax = subplots(2, 1, figsize=(8, 6), sharex=True)
    k_show = min(cfg.n_samples // 2, cfg.n_samples - 1)
    for i, (profile, parts) in enumerate(histories.items()):
        h = parts[k_show]
        j = pd.read_parquet(Path(out_dir) / "runs" / profile / f"sample_{k_show}" /
                            rundir.JOINTS)
        sec = Section(float(j["conn_od_m"].iloc[0]), float(j["conn_id_m"].iloc[0]))
        L = h[["axial_N", "shear_x_N", "shear_y_N", "bending_x_Nm", "bending_y_Nm",
               "torque_Nm"]].to_numpy(dtype=float)
        sig, tau, _ = surface_stresses(L, sec, SCF(s.axial, s.bending, s.torsion), 36)
        p = int(np.argmax(sig.max(axis=1) - sig.min(axis=1)))
        kw = {"lw": 0.6, "color": f"C{i}",
              "label": f"{profile} (joint MD {h['md_m'].mean():.0f} m)"}
        ax[0].plot(h["time_s"], sig[p] / 1e6, **kw)
        ax[1].plot(h["time_s"], tau[p] / 1e6, **kw)
    ax[0].set_ylabel("axial stress σ_z, MPa")
    ax[1].set_ylabel("shear stress τ, MPa")
    ax[1].set_xlabel(f"time in sample {k_show} of the window, s")
    ax[0].legend(fontsize=8)
    ax[0].set_title("Case 2: connection stress (SCF applied) at the surface point of "
                    "largest range")
    save_figure(fig, out_dir / "case2_connection_stress.png", dpi)

    fig, ax = subplots(figsize=(7, 4))
    x = np.arange(len(table))
    w = 0.27
    def fin(col: str) -> np.ndarray:  # an infinite life (no damage) is left out of the bars
        v = table[col].to_numpy(dtype=float)
        return np.where(np.isfinite(v), v, np.nan)

    ax.bar(x - w, fin("life_windows_critical_plane"), w, label=f"ours, {cfg.criterion}")
    ax.bar(x, fin("life_windows_api_rp7g"), w, label="ours, API RP7G")
    ax.bar(x + w, fin("paper_life_windows"), w, label="paper")
    ax.set_xticks(x, table["profile"])
    ax.set_yscale("log")
    ax.set_ylabel("life, repetitions of the 800 s window")
    ax.legend(fontsize=8)
    ax.set_title("Case 2: fatigue life by profile")
    save_figure(fig, out_dir / "case2_life.png", dpi)
