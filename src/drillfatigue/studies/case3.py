"""Case study 3 of the founding paper: the horizontal section of profile 1.

docs/model.md#case-studies and docs/case3.md: the string trips in for 800 s, the
top drive ramps to 50 rpm within 40 s, then a 60 s window is recorded; loads
8, 40 and 80 m behind the bit; lives in hours. The paper's location 1 (191 h)
is the one nearest the build, 80 m behind the bit; 40 m: 625 h; 8 m: 677 h.

``mode`` (documented assumptions; the paper does not give them):

``rig`` (default): the paper's sequence with the bit on bottom and the lobed bit
excitation, on case 2's rig boundaries (:func:`common.rig_drilling_sections`):
the autodriller holds ``wob_set_N`` on the bit, the bit law gives the ROP, the
rock face has three lobes. A run cannot switch the block from tripping to the
autodriller, so the trip is represented by its end state: the string placed in
the hole with the bit on bottom at ``bit_md_end_m``, at rest for ``trip_s``;
then the rpm ramps to ``rpm`` over ``ramp_s`` and the window is recorded.
``on_bottom``: the same sequence with the bit guided at ``rop_m_per_s`` (the
paper's prescribed-ROP set-up). ``tripping``: off bottom during the whole run,
the string sliding in at ``trip_speed_m_per_s``.

The string (``bha``): the ``paper_bha`` preset's BHA (near-bit stabilizer, 9 m
collar, string stabilizer, 168 m of collars, docs/bending.md) under drill pipe
reaching the surface; with ``contact_points: string``, ``span_bending`` and
``lateral_mud_mass`` (docs/bending.md) the collars and pipe touch the wall at
their stabilizers, tool joints and chord-rule points and carry the bending of
their weight between them. Each location is the joint nearest its distance.

Fatigue: the configured criterion at every location of each joint; life in
hours = recorded window / damage, beside the paper's life and the ratio. The
damage is decomposed by load (:func:`decompose_damage`: the fatigue chain rerun
on the axial force, shears and torque only, on the rigid joint moment only and
on the span correction only) and each load's stress amplitude is measured
(:func:`stress_amplitudes`), so a life far from the paper's shows which load
makes the difference.

Outputs in ``out_dir``: ``case3_life.csv`` (lives, paper lives, ratios, the
decomposed lives and stress amplitudes of the location that sets each life),
``case3_decomposition.csv`` (every joint, location and load), ``case3_summary.json``,
``case3_loads.png``, ``case3_life.png``, and the run folder ``runs/profile_1``.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import FatigueConfig
from drillfatigue.config.string import ComponentConfig
from drillfatigue.config.studies import Case3Config
from drillfatigue.dynamics.top.rig import drilling_window_metrics
from drillfatigue.fatigue.run import SPAN_COLUMNS, evaluate_run, joint_locations, location_section
from drillfatigue.fatigue.stress import LOAD_COLUMNS, SCF, Section, surface_stresses
from drillfatigue.plotting import subplots
from drillfatigue.studies.common import (
    hours,
    paper_bha_components,
    rig_drilling_sections,
    run_simulation,
    save_figure,
    span_sections,
    string_components,
    study_fatigue,
    warm_up,
    write_csv,
    write_json,
)
from drillfatigue.well import build_survey

#: The paper's lives at 80 (location 1, nearest the build), 40 and 8 m behind the
#: bit, hours (docs/case3.md).
PAPER_LIFE_H: dict[float, float] = {80.0: 191.0, 40.0: 625.0, 8.0: 677.0}
#: The paper's run time of the 60 s window, hours.
PAPER_WALL_H = 2.0
#: Ratio of our life to the paper's beyond which (either way) the output names the load
#: that makes the difference.
FAR_RATIO = 10.0
#: Load groups of the decomposition: the loads.parquet columns each one keeps (all
#: others are set to zero before the fatigue chain runs).
LOAD_GROUPS: dict[str, tuple[str, ...]] = {
    "axial_torsion": ("axial_N", "shear_x_N", "shear_y_N", "torque_Nm"),
    "joint_bending": ("bending_x_Nm", "bending_y_Nm"),
    "span_bending": SPAN_COLUMNS,
}
#: Surface points of the stress amplitudes (every 10 deg).
AMPLITUDE_POINTS = 36


def string_for(cfg: Case3Config, bit_md_m: float) -> list[dict[str, Any]]:
    """The case's string components, from the bit up, reaching the surface."""
    if cfg.bha == "paper_bha":
        return paper_bha_components(bit_md_m, cfg.string.dp_segments, cfg.dp_joints_per_segment)
    return string_components(cfg.string, bit_md_m)


def joint_distances_m(components: list[dict[str, Any]]) -> np.ndarray:
    """Distance from the bit of every joint (joint j joins segments j and j+1), m."""
    lengths = [x for c in components for x in ComponentConfig(**c).segment_lengths_m]
    return np.cumsum(lengths)[:-1]


def joints_behind_bit(cfg: Case3Config, bit_md_m: float) -> list[tuple[int, float]]:
    """Joints of the listed string nearest each of ``cfg.s_from_bit_m``: (index, distance
    from the bit, m). The simulator may cut segments shorter where the hole curves
    (``string.segment_fit_fraction``): :func:`run_case3` picks from the run's own joints."""
    ends = joint_distances_m(string_for(cfg, bit_md_m))
    return [(int(np.argmin(np.abs(ends - d))), float(ends[np.argmin(np.abs(ends - d))]))
            for d in cfg.s_from_bit_m]


def picks_from_run(joints: pd.DataFrame, want_m: list[float]) -> list[tuple[int, float]]:
    """The run's joints (``joints.parquet`` indexed by joint) nearest each distance from
    the bit in ``want_m``: (joint, its distance from the bit, m)."""
    s = joints["s_from_bit_m"].to_numpy(dtype=float)
    idx = joints.index.to_numpy()
    return [(int(idx[np.argmin(np.abs(s - d))]), float(s[np.argmin(np.abs(s - d))]))
            for d in want_m]


def case_dict(cfg: Case3Config, joints: list[int] | None, well: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], float]:
    """The simulator case and the bit MD at t = 0 (``well``: section defining the profile;
    ``joints``: the joints recorded, None: all)."""
    t_on = cfg.trip_s
    dur = cfg.duration_s
    bit0 = cfg.bit_md_end_m - cfg.advance_m_per_s * dur
    table = [[0.0, 0.0], [t_on, 0.0], [t_on + cfg.ramp_s, cfg.rpm], [dur, cfg.rpm]]
    if t_on == 0.0:
        table = table[1:]
    extra: dict[str, Any] = {}
    if cfg.mode == "rig":
        op: dict[str, Any] = {"top_axial": "neutral_point", "bit_on_bottom": True}
        extra = rig_drilling_sections(
            wob_set_N=cfg.wob_set_N, measurement=cfg.autodriller_measurement,
            initial_travel_m=cfg.block_initial_travel_m, lobe_amplitude_m=cfg.lobe_amplitude_m)
    elif cfg.mode == "on_bottom":
        op = {"top_axial": "neutral_point", "bit_on_bottom": True,
              "rop_m_per_s": cfg.rop_m_per_s, "lobe_count": 3,
              "lobe_amplitude_m": cfg.lobe_amplitude_m}
    else:
        op = {"top_axial": "fixed", "bit_on_bottom": False,
              "trip_speed_m_per_s": cfg.trip_speed_m_per_s}
    span = span_sections(points=cfg.contact_points, span_bending=cfg.span_bending,
                         lateral_mud_mass=cfg.lateral_mud_mass)
    case = {
        **extra,
        "contact": span["contact"],
        "well": {**(well or {}), "profile": cfg.profile},
        "string": {"components": string_for(cfg, bit0), **span["string"]},
        "operation": {"duration_s": dur, "bit_md_m": bit0, "rpm_table": table, **op},
        "recording": {"loads_rate_hz": cfg.loads_rate_hz, "channels_rate_hz": cfg.loads_rate_hz,
                      "kinematics_rate_hz": 10.0,
                      "joints": None if joints is None else sorted(set(joints)),
                      "start_s": t_on + cfg.ramp_s},
    }
    return case, bit0


def decompose_damage(run_dir: Path, fat: FatigueConfig, joints: list[int], criterion: str
                     ) -> pd.DataFrame:
    """Damage of each joint and location from each load group alone.

    The fatigue chain (:func:`evaluate_run`, same criterion, S-N curves, SCFs and
    mud pressure) is rerun on copies of the run whose ``loads.parquet`` keeps only
    the columns of one :data:`LOAD_GROUPS` entry (the others zero): the axial force,
    shears and torque; the rigid joint moment; the span-bending correction (absent
    from a run without ``contact.span_bending``: zero). Damage does not add over
    groups (the stresses combine inside each cycle), so the group whose damage is
    nearest the full one is the load that sets the life.

    Returns
    -------
    DataFrame
        ``joint, location, load, damage`` with ``load`` = ``all`` or a group name.
    """
    full = evaluate_run(run_dir, fat, None, joints=joints, criterion=criterion)
    rows = [{"joint": int(r.joint), "location": str(r.location), "load": "all",
             "damage": float(r.damage)} for r in full.itertuples()]
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    zeroable = [c for c in (*LOAD_COLUMNS, *SPAN_COLUMNS) if c in loads.columns]
    with tempfile.TemporaryDirectory(prefix="case3_decomposition_") as tmp:
        for name, keep in LOAD_GROUPS.items():
            part = Path(tmp) / name
            part.mkdir()
            for f in (rundir.JOINTS, rundir.SUMMARY, rundir.CASE):
                if (run_dir / f).is_file():
                    shutil.copy2(run_dir / f, part / f)
            only = loads.assign(**{c: 0.0 for c in zeroable if c not in keep})
            only.to_parquet(part / rundir.LOADS, index=False)
            dmg = evaluate_run(part, fat, None, joints=joints, criterion=criterion)
            rows += [{"joint": int(r.joint), "location": str(r.location), "load": name,
                      "damage": float(r.damage)} for r in dmg.itertuples()]
    return pd.DataFrame(rows)


def stress_amplitudes(run_dir: Path, fat: FatigueConfig, joints: list[int]) -> pd.DataFrame:
    """Stress amplitude of each load group at each joint and location, Pa.

    Surface stresses (:func:`surface_stresses`, the location's section and SCFs)
    of the group's loads alone; the amplitude is half the largest range over the
    window at any of :data:`AMPLITUDE_POINTS` surface points, for the axial
    stress ``sigma_amplitude_Pa`` and the shear stress ``tau_amplitude_Pa``.
    """
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    jt = pd.read_parquet(run_dir / rundir.JOINTS).set_index("joint")
    rows = []
    for j in joints:
        h = loads[loads["joint"] == j].sort_values("time_s")
        info = jt.loc[j]
        for loc in joint_locations(str(info["component_type"]), fat):
            od, idm = location_section(info, loc)
            s = getattr(fat.scf[str(info["component_type"])], loc)
            for name, keep in LOAD_GROUPS.items():
                L = np.zeros((len(h), len(LOAD_COLUMNS)))
                for k, c in enumerate(LOAD_COLUMNS):
                    src = c
                    if name == "span_bending" and c in ("bending_x_Nm", "bending_y_Nm"):
                        src = "span_" + c  # the span correction in the bending channels
                    if (src in keep or c in keep) and src in h.columns:
                        L[:, k] = h[src].to_numpy(dtype=float)
                sig, tau, _ = surface_stresses(L, Section(od, idm),
                                               SCF(s.axial, s.bending, s.torsion),
                                               AMPLITUDE_POINTS)
                rows.append({"joint": int(j), "location": loc, "load": name,
                             "sigma_amplitude_Pa": float(0.5 * np.max(np.ptp(sig, axis=1))),
                             "tau_amplitude_Pa": float(0.5 * np.max(np.ptp(tau, axis=1)))})
    return pd.DataFrame(rows)


def local_dls_deg_per_30m(survey: Any, md_m: float, half_m: float = 10.0) -> float:
    """Largest dogleg severity of the hole within ``half_m`` of ``md_m``, deg/30 m.

    A survey's DLS at a station is that of the interval ending there (minimum
    curvature), so the intervals that overlap [md - half, md + half] count.
    """
    md = np.asarray(survey.md_m, dtype=float)
    dls = np.asarray(survey.dls_deg_per_30m, dtype=float)
    lo = int(np.searchsorted(md, md_m - half_m, side="right"))
    hi = int(np.searchsorted(md, md_m + half_m, side="left"))
    sel = dls[max(lo, 1):min(hi, md.size - 1) + 1]
    return float(sel.max()) if sel.size else 0.0


def _life_h(span_s: float, damage: float) -> float:
    return hours(span_s) / damage if damage > 0 else math.inf


#: The holes of the study: the well section's (the plan) and the plan with the
#: configured ``tortuosity``; the tortuous hole's files carry the suffix.
HOLE_SUFFIX: dict[str, str] = {"plan": "", "tortuous": "_tortuous"}


def bending_amplitudes_Nm(loads: pd.DataFrame, joint: int) -> dict[str, float]:
    """Bending moment amplitude of a joint over the window, N m: half the largest range
    of the moment projected on 36 directions, for the rigid joint moment
    (``joint_bending_amplitude_Nm``) and the span correction (``span_bending_amplitude_Nm``,
    0 in a run without it)."""
    h = loads[loads["joint"] == joint]
    phi = np.linspace(0.0, math.pi, AMPLITUDE_POINTS // 2, endpoint=False)
    out: dict[str, float] = {}
    for name, cols in (("joint", ("bending_x_Nm", "bending_y_Nm")), ("span", SPAN_COLUMNS)):
        if len(h) == 0 or not all(c in h.columns for c in cols):
            out[f"{name}_bending_amplitude_Nm"] = 0.0
            continue
        proj = h[list(cols)].to_numpy(dtype=float) @ np.stack([np.cos(phi), np.sin(phi)])
        out[f"{name}_bending_amplitude_Nm"] = float(0.5 * np.ptp(proj, axis=0).max())
    return out


def tortuous_well(cfg: Case3Config, well: dict[str, Any] | None) -> dict[str, Any]:
    """The well section of the tortuous hole: ``well`` with ``cfg.tortuosity`` (which
    replaces any tortuosity of the section)."""
    if cfg.tortuosity is None:
        raise ValueError("case3.tortuosity is null: there is no tortuous hole to run")
    return {**(well or {}), "tortuosity": cfg.tortuosity.model_dump(mode="json")}


def run_case3(cfg: Case3Config, out_dir: Path, *, dpi: int = 110,
              well: dict[str, Any] | None = None,
              fatigue: FatigueConfig | None = None) -> dict[str, Any]:
    """Run case 3 and write its tables and figures; return the summary dictionary.

    ``well``/``fatigue``: as in :func:`drillfatigue.studies.case2.run_case2`. The case
    runs in the well section's hole (the plan: ``case3_life.csv``,
    ``case3_decomposition.csv``, ``runs/<profile>``) and, when ``cfg.tortuosity`` is set,
    again in that hole with the tortuosity (``case3_life_tortuous.csv``,
    ``case3_decomposition_tortuous.csv``, ``runs/<profile>_tortuous``; the summary's
    ``tortuous`` entry). With ``tortuosity: null`` the outputs are the plan's alone.
    """
    out_dir = Path(out_dir)
    fat = fatigue if fatigue is not None else study_fatigue()
    plan = _run_hole(cfg, out_dir / "runs" / cfg.profile, well, fat)
    table = plan["table"]
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "case3_life.csv", table)
    write_csv(out_dir / "case3_decomposition.csv", plan["decomposition"])
    ours_order = list(table.sort_values("life_h")["s_from_bit_m"])
    config = cfg.model_dump(mode="json")
    if cfg.tortuosity is None:
        config.pop("tortuosity")  # the summary of the plan alone
    summary = plan["summary"]
    summ: dict[str, Any] = {
        "config": config, "recorded_s": plan["span_s"], "wall_s": plan["wall_s"],
        "simulated_s": float(summary["duration_s"]), "paper_wall_h": PAPER_WALL_H,
        "paper_window_s": 60.0, "criterion": cfg.criterion, "far_ratio": FAR_RATIO,
        "n_segments": summary.get("n_segments_final"),
        "lowest_life_s_from_bit_m": ours_order[0],
        "nearest_build_lowest": bool(ours_order[0] == max(cfg.s_from_bit_m)),
        "span_bending_unsolved_samples": summary.get("span_bending_unsolved_samples"),
        "rows": table.to_dict(orient="records"),
    }
    if cfg.mode == "rig":
        summ["drilling"] = _drilling(out_dir / "runs" / cfg.profile, summary, cfg)
    tort: dict[str, Any] | None = None
    if cfg.tortuosity is not None:
        tort_dir = out_dir / "runs" / f"{cfg.profile}{HOLE_SUFFIX['tortuous']}"
        tort = _run_hole(cfg, tort_dir, tortuous_well(cfg, well), fat)
        write_csv(out_dir / "case3_life_tortuous.csv", tort["table"])
        write_csv(out_dir / "case3_decomposition_tortuous.csv", tort["decomposition"])
        ts = tort["summary"]
        summ["tortuous"] = {
            "tortuosity": cfg.tortuosity.model_dump(mode="json"),
            "peak_added_dls_deg_per_30m": cfg.tortuosity.peak_added_dls_deg_per_30m,
            "recorded_s": tort["span_s"], "wall_s": tort["wall_s"],
            "simulated_s": float(ts["duration_s"]), "n_segments": ts.get("n_segments_final"),
            "lowest_life_s_from_bit_m":
                float(tort["table"].sort_values("life_h")["s_from_bit_m"].iloc[0]),
            "span_bending_unsolved_samples": ts.get("span_bending_unsolved_samples"),
            "rows": tort["table"].to_dict(orient="records"),
        }
        if cfg.mode == "rig":
            summ["tortuous"]["drilling"] = _drilling(tort_dir, ts, cfg)
    _figures(out_dir, plan["loads"], plan["picks"], cfg, table, dpi,
             None if tort is None else tort["table"])
    write_json(out_dir / "case3_summary.json", summ)
    return summ


def _run_hole(cfg: Case3Config, run_dir: Path, well: dict[str, Any] | None,
              fat: FatigueConfig) -> dict[str, Any]:
    """Simulate the case in the hole of ``well`` into ``run_dir`` and evaluate its lives:
    the life table, the decomposition, the loads, the picked joints, the recorded span,
    the simulation's wall time (numba compilation excluded) and its summary."""
    # every joint is recorded: the simulator's hole-fit rule sets where the joints are
    case, _ = case_dict(cfg, None, well)
    warm_up(case)  # the wall time below excludes numba compilation
    cc, summary, wall = run_simulation(case, run_dir)
    survey = build_survey(cc.well)
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    t = np.unique(loads["time_s"].to_numpy())
    span = float(t[-1] - t[0] + (t[1] - t[0])) if t.size > 1 else 0.0
    jt = pd.read_parquet(run_dir / rundir.JOINTS).set_index("joint")
    picks = picks_from_run(jt, list(cfg.s_from_bit_m))
    sel = sorted({j for j, _ in picks})
    dec = decompose_damage(run_dir, fat, sel, cfg.criterion)
    amp = stress_amplitudes(run_dir, fat, sel)
    dec = dec.merge(amp, on=["joint", "location", "load"], how="left")
    dec["life_h"] = [_life_h(span, d) for d in dec["damage"]]
    rows = []
    for want, (j, s) in zip(cfg.s_from_bit_m, picks, strict=True):
        d = dec[(dec["joint"] == j) & (dec["load"] == "all")].set_index("location")["damage"]
        md = float(loads.loc[loads["joint"] == j, "md_m"].mean())
        life = {loc: _life_h(span, float(d[loc])) for loc in d.index}
        crit_loc = min(life, key=lambda k: life[k])
        paper = PAPER_LIFE_H.get(float(want), math.nan)
        ratio = life[crit_loc] / paper if math.isfinite(paper) else math.nan
        row: dict[str, Any] = {
            "s_from_bit_m": want, "joint": j, "joint_s_from_bit_m": s,
            "component_type": str(jt.loc[j, "component_type"]),
            "md_m": md,
            "hole_dls_deg_per_30m": local_dls_deg_per_30m(survey, md),
            "life_h": life[crit_loc], "critical_location": crit_loc,
            **{f"life_h_{loc}": v for loc, v in life.items()},
            "paper_life_h": paper, "life_ratio_ours_to_paper": ratio,
            "far_from_paper": bool(math.isfinite(ratio) and
                                   (ratio > FAR_RATIO or ratio < 1.0 / FAR_RATIO)),
        }
        at = dec[(dec["joint"] == j) & (dec["location"] == crit_loc)].set_index("load")
        for name in LOAD_GROUPS:
            row[f"life_h_{name}_only"] = float(at.loc[name, "life_h"])
            row[f"sigma_amplitude_MPa_{name}"] = float(at.loc[name, "sigma_amplitude_Pa"]) / 1e6
            row[f"tau_amplitude_MPa_{name}"] = float(at.loc[name, "tau_amplitude_Pa"]) / 1e6
        # the load whose damage alone comes nearest the full damage sets the life
        dmg = {name: float(at.loc[name, "damage"]) for name in LOAD_GROUPS}
        full = float(at.loc["all", "damage"])
        row["dominant_load"] = (max(dmg, key=lambda k: dmg[k]) if full > 0 else "none")
        row.update(bending_amplitudes_Nm(loads, j))
        rows.append(row)
    return {"table": pd.DataFrame(rows), "decomposition": dec, "loads": loads, "picks": picks,
            "span_s": span, "wall_s": wall, "summary": summary}


def _drilling(run_dir: Path, summary: dict[str, Any], cfg: Case3Config) -> dict[str, Any]:
    """What the rig did in the recorded window (after the ramp): on-bottom fraction,
    WOB against its set-point, ROP, surface torque, block and string-top checks."""
    ch = pd.read_parquet(run_dir / "channels.parquet")
    t = ch["time_s"].to_numpy()
    skip = max(cfg.trip_s + cfg.ramp_s - float(t[0]), 0.0)
    out: dict[str, Any] = drilling_window_metrics(
        t, ch["wob_N"].to_numpy(), ch["rop_m_per_s"].to_numpy(),
        ch["surface_torque_Nm"].to_numpy(), ch["block_travel_m"].to_numpy(),
        float(summary["rig"]["effective_inputs"]["block"]["travel_m"]), cfg.wob_set_N,
        ch["string_top_above_rotary_m"].to_numpy(), t_skip_s=skip)
    out["wob_set_N"] = cfg.wob_set_N
    out["bit_bounce_count"] = summary.get("bit_bounce_count")
    out["whirl_class"] = summary.get("whirl_class")
    return out


def _figures(out_dir: Path, loads: pd.DataFrame, picks: list[tuple[int, float]],
             cfg: Case3Config, table: pd.DataFrame, dpi: int,
             tortuous: pd.DataFrame | None = None) -> None:
    fig, ax = subplots(3, 1, figsize=(8, 8), sharex=True)
    for j, s in picks:
        h = loads[loads["joint"] == j]
        kw = {"lw": 0.6, "label": f"{s:.0f} m behind the bit"}
        ax[0].plot(h["time_s"], h["axial_N"] / 1e3, **kw)
        ax[1].plot(h["time_s"], h["torque_Nm"] / 1e3, **kw)
        mx, my = h["bending_x_Nm"].to_numpy(), h["bending_y_Nm"].to_numpy()
        if SPAN_COLUMNS[0] in h.columns:  # what the fatigue chain reads: joint + span
            mx = mx + h[SPAN_COLUMNS[0]].to_numpy()
            my = my + h[SPAN_COLUMNS[1]].to_numpy()
        ax[2].plot(h["time_s"], np.hypot(mx, my) / 1e3, **kw)
    ax[0].set_ylabel("axial force, kN")
    ax[1].set_ylabel("torque, kN·m")
    ax[2].set_ylabel("bending moment\n(joint + span), kN·m")
    ax[2].set_xlabel("time, s")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"Case 3: {cfg.profile} horizontal section, {cfg.rpm:.0f} rpm window")
    save_figure(fig, out_dir / "case3_loads.png", dpi)

    fig, ax = subplots(figsize=(6, 4))
    x = np.arange(len(table))
    life = table["life_h"].to_numpy(dtype=float)
    if tortuous is None:
        ax.bar(x - 0.2, np.where(np.isfinite(life), life, np.nan), 0.4,
               label=f"ours, {cfg.criterion}")  # an infinite life (no damage) is left out
        ax.bar(x + 0.2, table["paper_life_h"], 0.4, label="paper")
    else:
        tl = tortuous["life_h"].to_numpy(dtype=float)
        ax.bar(x - 0.27, np.where(np.isfinite(life), life, np.nan), 0.27,
               label=f"ours, plan hole, {cfg.criterion}")
        ax.bar(x, np.where(np.isfinite(tl), tl, np.nan), 0.27, label="ours, tortuous hole")
        ax.bar(x + 0.27, table["paper_life_h"], 0.27, label="paper")
    ax.set_xticks(x, [f"{v:.0f} m" for v in table["s_from_bit_m"]])
    ax.set_yscale("log")
    ax.set_xlabel("distance behind the bit")
    ax.set_ylabel("life, h")
    ax.legend(fontsize=8)
    ax.set_title("Case 3: fatigue life")
    save_figure(fig, out_dir / "case3_life.png", dpi)
