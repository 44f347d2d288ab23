"""Well-plan ranking: which candidate profile gives the string the longest fatigue life.

What the founding paper motivates, made a tool (``drillfatigue plan rank``).
A candidates file lists profiles with shared end points (KOP, DLS varied; the
``family_member`` kind solves the build rate so each lands horizontal at the
shared end point) and the drilling window they are compared on::

    family: {tvd_end_m: 650.0, displacement_m: 500.0, azi_deg: 0.0}   # shared end point
    window:                      # a case2 section: drilling window, string, sampling
      bit_md_start_m: 480.0
      bit_md_end_m: 880.0
      n_samples: 4
    fatigue: {n_refine: 4}       # a fatigue section for the confirmation runs
    candidates:
      early_gentle: {kind: family_member, member: 1, kop_m: 350.0}
      late_steep:   {kind: family_member, member: 2, kop_m: 450.0}
      two_builds:   {kind: family_member, member: 3, kop_m: 350.0}

Surrogate prediction (fast): for each candidate, the string is placed at
``surrogate_bit_positions`` bit depths over the window; every joint of the
string x location (body, connection) at each depth is one query row whose
features (``operation.*``, ``friction.*``, ``bit.*``, ``rig.*``, ``md_m``, ``s_from_bit_m``, the
hole-geometry columns of :mod:`drillfatigue.well.features`, component type,
location) are taken from the same
simulator case the confirmation would run. A component's damage over the
window is the time-weighted sum of its predicted rates; the critical
component is the one with the largest damage; its life is given in
repetitions of the window, with the interval from summing the rows' interval
bounds the same way (each bound is a calibrated per-row bound; the summed
bound is conservative, not a calibrated joint interval). Out-of-domain rows
are counted and reported.

The window drills with the rig boundaries as the sweep does (``boundaries:
rig_rop``): the autodriller drills at the window's ``rop_m_per_s`` (its ROP
limit) unless the WOB reaches its limit first; the query rows carry it as
``operation.rop_m_per_s``, the name the sweep varies.

Simulator confirmation (slow, top-k by the surrogate): the case-2 machinery
(:mod:`drillfatigue.studies.case2`) on the candidate's profile, all joints
recorded, the critical component's life in windows by the configured
criterion.

Outputs: ``ranking.csv``, ``ranking.json``, ``ranking.png`` in the output folder.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from pydantic import Field, field_validator

from drillfatigue.config import WellConfig, case_from_dict
from drillfatigue.config.base import StrictModel, read_yaml, validate
from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.config.studies import Case2Config
from drillfatigue.config.well import FamilySpec, ProfileSpec
from drillfatigue.errors import InputError
from drillfatigue.fatigue.run import LOCATIONS, evaluate_run, joint_locations
from drillfatigue.files import OutputFolder
from drillfatigue.plotting import subplots
from drillfatigue.studies.case2 import case_dict, sample_bit_md
from drillfatigue.studies.common import (
    recorded_span_s, run_simulation, save_figure, write_csv, write_json,
)
from drillfatigue.well import build_survey
from drillfatigue.well.features import survey_features

#: Kind of the ownership marker of a plan-ranking output folder.
PLAN_KIND = "plan"

#: Tolerance on the shared end point, m.
END_POINT_TOL_M = 1.0
INPUT_SECTIONS = ("well", "operation", "friction", "bit", "rig")
#: Largest share of a candidate's query rows out of the surrogate's domain for which it is
#: ranked: a candidate mostly out of domain gets no surrogate life, and a best plan is named
#: only when every candidate is ranked. A ranked candidate's life is that of its in-domain
#: locations (the rows out of domain add no number; their share is reported beside it).
MAX_OOD_FRACTION = 0.5


class CandidateFile(StrictModel):
    """A candidates file (see the module docstring)."""

    family: FamilySpec = Field(default_factory=FamilySpec)
    window: Case2Config = Field(default_factory=lambda: Case2Config(
        n_samples=4, sample_s=4.0, boundaries="rig_rop", implicit_bit_torque=False))
    surrogate_bit_positions: int = Field(17, ge=2, le=1000)
    fatigue: FatigueConfig = Field(default_factory=lambda: FatigueConfig(plots=False),
                                   description="fatigue settings of the confirmation runs")
    candidates: dict[str, ProfileSpec] = Field(min_length=1)

    @field_validator("candidates")
    @classmethod
    def _names(cls, v: dict[str, Any]) -> dict[str, Any]:
        for name in v:
            if not name or not all(c.isalnum() or c in "_-." for c in name):
                raise ValueError(f"bad candidate name {name!r} "
                                 "(allowed: letters, digits, _ - .)")
        return v


def load_candidates(path: str | Path) -> CandidateFile:
    """Read and validate a candidates file; check the shared end point."""
    cset = validate(CandidateFile, read_yaml(path), "candidates")
    check_end_points(cset)
    return cset


def well_section(cset: CandidateFile) -> dict[str, Any]:
    """The ``well`` section holding every candidate as a named profile."""
    return {"profiles": {k: v.model_dump(mode="json") for k, v in cset.candidates.items()},
            "family": cset.family.model_dump(mode="json")}


def check_end_points(cset: CandidateFile) -> None:
    """Every candidate must end at the same point (the one most candidates share), within
    1 m, and be long enough for the window."""
    ends = {}
    for name in cset.candidates:
        wc = validate(WellConfig, {**well_section(cset), "profile": name}, "candidates")
        try:
            sv = build_survey(wc)
        except InputError as exc:
            raise InputError(f"candidates.{name}", exc.problem, exc.allowed) from None
        ends[name] = (np.asarray(sv.pos_m[-1]), float(sv.md_m[-1]))
        if sv.md_m[-1] < cset.window.bit_md_end_m:
            raise InputError(f"candidates.{name}", f"total depth {sv.md_m[-1]:.0f} m is "
                             f"shorter than the window's end ({cset.window.bit_md_end_m} m)",
                             f"TD >= {cset.window.bit_md_end_m} m")
    # reference: the end point most candidates share (so the odd one out is named)
    names = list(ends)
    near = {a: sum(np.linalg.norm(ends[a][0] - ends[b][0]) <= END_POINT_TOL_M for b in names)
            for a in names}
    ref = max(names, key=lambda a: near[a])
    for name, (p, _) in ends.items():
        gap = float(np.linalg.norm(p - ends[ref][0]))
        if gap > END_POINT_TOL_M:
            raise InputError(f"candidates.{name}", f"ends {gap:.1f} m away from the shared "
                             f"end point of {ref}", f"the same end point within "
                             f"{END_POINT_TOL_M} m")


def _flat_inputs(case: dict[str, Any]) -> dict[str, Any]:
    """Scalar ``<section>.<field>`` inputs of a validated case (as the dataset has them)."""
    full = case_from_dict(case).model_dump(mode="json")
    row = {}
    for section in INPUT_SECTIONS:
        for key, value in (full.get(section) or {}).items():
            if isinstance(value, bool | int | float | str):
                row[f"{section}.{key}"] = value
    rig = full.get("rig") or {}
    # the sweep varies the ROP target under the name operation.rop_m_per_s (the rig
    # section refuses that operation field, so the case carries it in the rig):
    # the rop block's set-point or the autodriller's ROP limit
    if rig.get("block_mode") == "rop":
        row["operation.rop_m_per_s"] = rig["rop_set_m_per_s"]
    elif rig.get("block_mode") == "autodriller" and rig.get("autodriller"):
        ad = rig["autodriller"]
        row["operation.rop_m_per_s"] = ad["rop_limit_m_per_s"]
        row["operation.wob_N"] = ad["wob_set_N"]  # the driller's set-point, as the sweep names it
        for key, value in ad.items():
            if isinstance(value, bool | int | float | str):
                row[f"rig.autodriller.{key}"] = value
    return row


def candidate_rows(cset: CandidateFile, name: str,
                   locations: tuple[str, ...] | None = None) -> pd.DataFrame:
    """Surrogate query rows of one candidate (see the module docstring).

    Each joint is queried at the locations the fatigue chain evaluates there
    (:func:`drillfatigue.fatigue.run.joint_locations` with the candidates'
    fatigue settings: body, connection and, on drill pipe, the upset run-out),
    limited to ``locations`` when given (the levels a surrogate knows).
    """
    w = cset.window
    well = well_section(cset)
    sv = build_survey(validate(WellConfig, {**well, "profile": name}, "candidates"))
    bits = np.linspace(w.bit_md_start_m, w.bit_md_end_m, cset.surrogate_bit_positions)
    n_dc, n_dp = w.string.dc_segments, w.string.dp_segments
    parts = []
    for b in bits:
        case = case_dict(w, name, float(b), None, well)
        base = _flat_inputs(case)
        dc_len = w.string.dc_length_m
        seg = [dc_len / n_dc] * n_dc + [(b - dc_len) / n_dp] * n_dp
        s = np.cumsum(seg)[:-1]
        ctype = np.where(s < dc_len - 1e-9, "collar", "drill_pipe")
        md = b - s
        geo = survey_features(sv, md, np.full(md.shape, b))
        for loc in LOCATIONS:
            if locations is not None and loc not in locations:
                continue
            keep = np.array([loc in joint_locations(str(c), cset.fatigue) for c in ctype])
            if not keep.any():
                continue
            f = pd.DataFrame({"s_from_bit_m": s, "md_m": md, **geo,
                              "component_type": ctype, "location": loc,
                              "joint": np.arange(s.size)})[keep].reset_index(drop=True)
            for k, v in base.items():
                f[k] = v
            f["bit_position_md_m"] = b
            parts.append(f)
    out = pd.concat(parts, ignore_index=True)
    out["candidate"] = name
    return out


def predict_candidates(cset: CandidateFile, surrogate: Any) -> pd.DataFrame:
    """Surrogate life (windows) of each candidate's critical component, with bounds."""
    rows = []
    w = cset.window
    dt_h = (w.window_s / (cset.surrogate_bit_positions - 1)) / 3600.0
    for name in cset.candidates:
        known = surrogate.categories.get("location") if hasattr(surrogate, "categories") else None
        q = candidate_rows(cset, name, tuple(known) if known is not None else None)
        missing = [c for c in list(surrogate.features) + list(surrogate.categorical)
                   if c not in q.columns]
        if missing:
            raise InputError("surrogate", f"model needs column(s) {', '.join(missing)} that a "
                             "well-plan query cannot supply", "a surrogate trained on case, "
                             "location and well-curvature features")
        # no number out of domain: a candidate is ranked only when at most
        # MAX_OOD_FRACTION of its rows are out of domain, on its in-domain rows
        pred = surrogate.predict(q, refuse=True)
        # trapezoid weights over the bit positions
        wts = np.full(cset.surrogate_bit_positions, dt_h)
        wts[[0, -1]] *= 0.5
        pos = np.searchsorted(np.unique(q["bit_position_md_m"]), q["bit_position_md_m"])
        q = q.assign(wt=wts[pos], rate=pred["damage_rate_per_h"].to_numpy(),
                     lo=pred["damage_rate_per_h_lower"].to_numpy(),
                     hi=pred["damage_rate_per_h_upper"].to_numpy(),
                     ood=pred["ood"].to_numpy(dtype=bool))
        for col in ("rate", "lo", "hi"):
            q[col] = q[col].where(~q["ood"], 0.0)
        q["d"], q["d_lo"], q["d_hi"] = q["rate"] * q["wt"], q["lo"] * q["wt"], q["hi"] * q["wt"]
        comp = q.groupby(["joint", "location"]).agg(
            d=("d", "sum"), d_lo=("d_lo", "sum"), d_hi=("d_hi", "sum"),
            s_from_bit_m=("s_from_bit_m", "mean"), component_type=("component_type", "first"))
        ood_fraction = float(q["ood"].mean())
        if ood_fraction > MAX_OOD_FRACTION:
            rows.append({"candidate": name, "critical_s_from_bit_m": math.nan,
                         "critical_component": "", "life_windows_surrogate": math.nan,
                         "life_windows_surrogate_lower": math.nan,
                         "life_windows_surrogate_upper": math.nan,
                         "ood_fraction": ood_fraction,
                         "no_answer": f"{100 * ood_fraction:.0f} % of the query rows are out "
                                      f"of the surrogate's domain (at most "
                                      f"{100 * MAX_OOD_FRACTION:.0f} % ranked)"})
            continue
        k = comp["d"].idxmax()
        c = comp.loc[k]
        rows.append({
            "candidate": name, "critical_s_from_bit_m": float(c["s_from_bit_m"]),
            "critical_component": f"{c['component_type']} {k[1]}",
            "life_windows_surrogate": 1.0 / c["d"] if c["d"] > 0 else math.inf,
            "life_windows_surrogate_lower": 1.0 / c["d_hi"] if c["d_hi"] > 0 else math.inf,
            "life_windows_surrogate_upper": 1.0 / c["d_lo"] if c["d_lo"] > 0 else math.inf,
            "ood_fraction": ood_fraction, "no_answer": "",
        })
    return pd.DataFrame(rows)


def simulate_candidate(cset: CandidateFile, name: str, out_dir: Path) -> pd.DataFrame:
    """Simulate a candidate's sample windows (case-2 machinery, all joints recorded).

    Returns one row per (sample, joint, location) with the damage over the
    recorded part, ``damage_rate_per_h_<criterion>``, the window share each
    sample stands for (``share_s``), the query features of
    :func:`candidate_rows` and ``case_id`` (``<candidate>_<sample>``); the
    summed simulation wall time is in ``frame.attrs['wall_s']``. These rows are
    also a surrogate training set.
    """
    w = cset.window
    fat = cset.fatigue
    well = well_section(cset)
    sv = build_survey(validate(WellConfig, {**well, "profile": name}, "candidates"))
    parts = []
    wall = 0.0
    for k, b in enumerate(sample_bit_md(w)):
        run_dir = out_dir / name / f"sample_{k}"
        case = case_dict(w, name, b, None, well)
        _, _, t = run_simulation(case, run_dir)
        wall += t
        df = evaluate_run(run_dir, fat, None, criterion=w.criterion)
        span = recorded_span_s(run_dir)
        df["damage_rate_per_h_" + w.criterion] = df["damage"] / (span / 3600.0)
        df["share_s"] = w.window_s / w.n_samples
        df["span_s"] = span
        df["sample"] = k
        df["case_id"] = f"{name}_{k}"
        df["candidate"] = name
        md = df["md_m"].to_numpy(dtype=float)
        df = df.assign(**survey_features(sv, md, md + df["s_from_bit_m"].to_numpy(dtype=float)))
        for key, v in _flat_inputs(case).items():
            df[key] = v
        parts.append(df)
    out = pd.concat(parts, ignore_index=True)
    out.attrs["wall_s"] = wall
    return out


def simulator_life(rows: pd.DataFrame) -> dict[str, Any]:
    """Life (windows) of the critical component from :func:`simulate_candidate` rows."""
    d = (rows["damage"] / rows["span_s"] * rows["share_s"]).groupby(
        [rows["joint"], rows["location"]]).sum()
    info = rows.groupby(["joint", "location"])[["s_from_bit_m", "component_type"]].first()
    k = d.idxmax()
    return {"candidate": str(rows["candidate"].iloc[0]),
            "life_windows_simulator": 1.0 / float(d[k]) if d[k] > 0 else math.inf,
            "simulator_critical_s_from_bit_m": float(info.loc[k, "s_from_bit_m"]),
            "simulator_critical_component": f"{info.loc[k, 'component_type']} {k[1]}",
            "simulator_wall_s": float(rows.attrs.get("wall_s", math.nan))}


def confirm_candidate(cset: CandidateFile, name: str, out_dir: Path) -> dict[str, Any]:
    """Simulator life (windows) of a candidate's critical component (case-2 machinery)."""
    return simulator_life(simulate_candidate(cset, name, out_dir))


def rank_plans(cset: CandidateFile, surrogate: Any, out_dir: Path, confirm: int = 0,
               dpi: int = 110) -> pd.DataFrame:
    """Rank the candidates by surrogate life, confirm the top ``confirm`` by simulation.

    Writes ``ranking.csv``, ``ranking.json`` and ``ranking.png`` in ``out_dir``
    (and the confirmation runs under ``out_dir/runs``); returns the table (best
    first). ``out_dir`` is a ``plan`` output folder
    (:class:`drillfatigue.files.OutputFolder`): a folder holding files
    drillfatigue did not write is refused before any work.
    """
    out_dir = Path(out_dir)
    folder = OutputFolder(out_dir, PLAN_KIND)
    table = predict_candidates(cset, surrogate)
    table = table.sort_values("life_windows_surrogate", ascending=False, kind="stable",
                              na_position="last")
    table = table.reset_index(drop=True)
    answered = (table["no_answer"] == "").to_numpy()
    ranks = pd.array(np.cumsum(answered), dtype="Int64")
    ranks[~answered] = pd.NA
    table["rank_surrogate"] = ranks
    # a best plan only when the surrogate answers for every candidate
    best = str(table["candidate"].iloc[0]) if bool(answered.all()) else None
    k = min(confirm, int(answered.sum()))
    if k:
        conf = pd.DataFrame([confirm_candidate(cset, n, folder.file("runs"))
                             for n in table["candidate"].iloc[:k]])
        table = table.merge(conf, on="candidate", how="left")
        ranks = table["life_windows_simulator"].rank(ascending=False, method="min")
        table["rank_simulator"] = ranks.astype("Int64")
    write_csv(folder.file("ranking.csv"), table)
    agree = None
    if k:
        sub = table.iloc[:k]
        agree = bool(list(sub.sort_values("life_windows_simulator", ascending=False)["candidate"])
                     == list(sub["candidate"]))
    write_json(folder.file("ranking.json"), {
                                          "best": best,
                                          "no_best_reason": None if best is not None else
                                          "the surrogate has no answer for "
                                          + ", ".join(table.loc[table["no_answer"] != "",
                                                                "candidate"])
                                          + f" (more than {100 * MAX_OOD_FRACTION:.0f} % of "
                                          "their query rows out of its domain)",
                                          "order_surrogate": list(table["candidate"]),
                                          "confirmed": k, "simulator_agrees": agree,
                                          "window_s": cset.window.window_s,
                                          "rows": table.to_dict(orient="records")})
    _plot(table, folder.file("ranking.png"), dpi)
    return table


def _plot(table: pd.DataFrame, path: Path, dpi: int) -> None:
    fig, ax = subplots(figsize=(max(5.0, 1.2 * len(table)), 4))
    x = np.arange(len(table))
    y = table["life_windows_surrogate"].to_numpy()
    if not np.any(np.isfinite(y) & (y > 0)) and not (
            "life_windows_simulator" in table
            and np.any(np.isfinite(table["life_windows_simulator"].to_numpy(dtype=float)))):
        ax.text(0.5, 0.5, "no answer: the surrogate's domain does not cover these\n"
                f"candidates (more than {100 * MAX_OOD_FRACTION:.0f} % of their rows out "
                "of it)", ha="center", va="center", transform=ax.transAxes)
        ax.set_xticks(x, table["candidate"], rotation=20)
        ax.set_yticks([])
        ax.set_title("Well-plan ranking: no best plan")
        save_figure(fig, path, dpi)
        return
    lo = y - table["life_windows_surrogate_lower"].to_numpy()
    hi = table["life_windows_surrogate_upper"].to_numpy() - y
    ax.errorbar(x - 0.1, y, yerr=[np.clip(lo, 0, None), np.clip(hi, 0, None)], fmt="o",
                capsize=4, label="surrogate (interval)")
    if "life_windows_simulator" in table:
        ax.plot(x + 0.1, table["life_windows_simulator"], "s", label="simulator")
    ax.set_xticks(x, table["candidate"], rotation=20)
    ax.set_yscale("log")
    ax.set_ylabel("life of the critical component,\nrepetitions of the drilling window")
    ax.legend(fontsize=8)
    ax.set_title("Well-plan ranking (best first)")
    save_figure(fig, path, dpi)
