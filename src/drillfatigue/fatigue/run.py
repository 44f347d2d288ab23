"""Fatigue of a simulator run directory: ``damage.parquet``, ``summary.json``, plots.

A run directory holds ``loads.parquet`` (columns ``time_s, joint, md_m,
axial_N, shear_x_N, shear_y_N, bending_x_Nm, bending_y_Nm, torque_Nm``, and
optionally ``span_bending_x_Nm, span_bending_y_Nm``, the span correction the
chain adds to the joint moment),
``joints.parquet`` (``joint, component, component_type, s_from_bit_m,
body_od_m, body_id_m, conn_od_m, conn_id_m``) and ``summary.json`` with
``status == "complete"``. Rates and lives are per hour of the recorded
window (:func:`drillfatigue.rundir.recorded_span_s`), not of the run's ``duration_s``.
Every input is checked before anything is written, so bad input leaves no output behind.

Locations: ``body`` (body section, body SCFs), ``connection`` (connection
section, thread-root SCFs) and, for drill pipe and heavy-weight pipe,
``upset`` (the run-out of the upset into the body: body section, upset SCFs).
Mud pressure: when ``case.yaml`` gives the well and the mud density (and
``fatigue.pressure`` is on), each joint carries the hydrostatic pressure at
the TVD of its mean MD over the window inside and outside, plus the pump
pressure inside (:func:`joint_pressures`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import case_from_dict
from drillfatigue.config.base import read_yaml
from drillfatigue.config.fatigue import UPSET_TYPES, FatigueConfig, UserCurveConfig
from drillfatigue.config.string import COMPONENT_TYPES
from drillfatigue.errors import InputError
from drillfatigue.fatigue.critical_plane import (
    CRITERIA,
    CriterionParams,
    DamageOptions,
    PlaneSearch,
    evaluate_location,
    loads_channels,
)
from drillfatigue.fatigue.rainflow import RainflowStream, find_cycles, rainflow_matrix
from drillfatigue.fatigue.rp7g import (
    E_RP7G_PA,
    HALF_JOINT_SPACING_M,
    RP7G_GRADES,
    max_permissible_dogleg,
    rp7g_damage_rate_profile,
)
from drillfatigue.fatigue.sn import (
    SNCurve,
    correct_mean_stress,
    get_curve,
    get_grade,
    user_curve,
)
from drillfatigue.fatigue.stress import (
    LOAD_COLUMNS,
    SCF,
    Pressure,
    Section,
    hydrostatic_pressure_Pa,
    surface_coefficients,
    true_wall_force_N,
)
from drillfatigue.files import OutputFolder, atomic_output, atomic_write_bytes
from drillfatigue.plotting import subplots
from drillfatigue.units import HOUR_S
from drillfatigue.well import build_survey

LOADS_COLUMNS: tuple[str, ...] = rundir.LOADS_COLUMNS
#: Optional ``loads.parquet`` columns: the span-bending correction between the
#: supports (docs/bending.md), recorded apart from the rigid joint moment
#: ``bending_x_Nm``/``bending_y_Nm``; the fatigue chain reads their sum.
SPAN_COLUMNS: tuple[str, ...] = ("span_bending_x_Nm", "span_bending_y_Nm")
JOINTS_COLUMNS: tuple[str, ...] = rundir.JOINTS_COLUMNS
DAMAGE_COLUMNS: tuple[str, ...] = (
    "joint", "md_m", "s_from_bit_m", "component", "component_type", "location", "criterion",
    "damage", "damage_rate_per_h", "life_h", "life_windows", "critical_angle_deg",
    "critical_plane_deg", "uniaxial_damage")
LOCATIONS: tuple[str, ...] = ("body", "connection", "upset")
#: Kind of the ownership marker of a fatigue output folder.
FATIGUE_KIND = "fatigue"
#: Figures written with ``fatigue.plots``.
PLOT_FILES: list[str] = ["stress_history.png", "rainflow_matrix.png", "damage_along_string.png"]
#: every file a fatigue evaluation may write in its folder (checked for foreign files of
#: these names before anything in the folder changes)
FILES: tuple[str, ...] = ("damage.parquet", "api_rp7g.parquet", "summary.json", *PLOT_FILES)


def joint_locations(component_type: str, cfg: FatigueConfig) -> tuple[str, ...]:
    """Locations evaluated at a joint of this component type."""
    if cfg.upset_location and component_type in UPSET_TYPES:
        return LOCATIONS
    return LOCATIONS[:2]


def location_section(info: Any, loc: str) -> tuple[float, float]:
    """(OD, ID) of a location from a ``joints.parquet`` row: the connection
    section at the connection, the body section at the body and at the upset
    run-out (where the taper meets the body wall)."""
    if loc == "connection":
        return float(info["conn_od_m"]), float(info["conn_id_m"])
    return float(info["body_od_m"]), float(info["body_id_m"])


def joint_pressures(case: Any, md_m: dict[int, float], pump_pressure_Pa: float
                    ) -> dict[int, Pressure]:
    """Mud pressure of each joint from the case's well and mud density.

    p_o = rho_mud g TVD(md), p_i = p_o + ``pump_pressure_Pa``; TVD interpolated
    along the survey's minimum-curvature positions (the wells start at the
    surface, taken as the mud level).

    Parameters
    ----------
    case : drillfatigue.config.CaseConfig
    md_m : dict
        Joint -> its mean MD over the window, m.
    pump_pressure_Pa : float
    """

    survey = build_survey(case.well)
    rho = float(case.operation.mud_density_kg_per_m3)
    out = {}
    for j, md in md_m.items():
        tvd = float(np.interp(md, survey.md_m, survey.pos_m[:, 2]))
        p_o = float(hydrostatic_pressure_Pa(max(tvd, 0.0), rho))
        out[j] = Pressure(p_o + pump_pressure_Pa, p_o)
    return out


def _atomic_write_parquet(df: pd.DataFrame, path: Path) -> None:
    with atomic_output(path) as tmp:
        df.to_parquet(tmp, index=False)


def build_curve(spec: str | UserCurveConfig, environment: str) -> SNCurve:
    """S-N curve from a config entry (library name or user curve)."""
    if isinstance(spec, str):
        return get_curve(spec, environment)
    return user_curve(spec.m1, spec.log_a1, spec.m2, spec.knee_N, spec.cutoff_N, spec.name,
                      spec.reference)


def _read_parquet(path: Path, columns: Sequence[str]) -> pd.DataFrame:
    if not path.is_file():
        raise InputError(str(path), "file not found", "a run directory written by simulate")
    try:
        df = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises several types for a corrupt file
        raise InputError(str(path), f"cannot read parquet: {type(exc).__name__}",
                         "a valid parquet file") from None
    missing = [c for c in columns if c not in df.columns]
    if missing:
        raise InputError(str(path), f"missing column(s) {', '.join(missing)}",
                         "columns " + ", ".join(columns))
    return df


def read_run(run_dir: Path) -> tuple[pd.DataFrame, pd.DataFrame, dict[str, Any]]:
    """Read and check a run directory; raise InputError on anything unusable.

    A research case evaluates its run three or four times (the window check, each
    criterion): the last two runs read are kept, keyed by their files' identity
    (device, inode, size and modification time), and a copy is returned."""
    run_dir = Path(run_dir)
    key = _run_key(run_dir)
    if key is not None:
        hit = _RUN_CACHE.get(key)
        if hit is None:
            hit = _read_run(run_dir)
            _RUN_CACHE[key] = hit
            while len(_RUN_CACHE) > 2:
                del _RUN_CACHE[next(iter(_RUN_CACHE))]
        loads, joints, summary = hit
        return loads.copy(), joints.copy(), json.loads(json.dumps(summary))
    return _read_run(run_dir)


#: The last runs read (:func:`read_run`), oldest first.
_RUN_CACHE: dict[tuple[Any, ...], tuple[pd.DataFrame, pd.DataFrame, dict[str, Any]]] = {}


def _run_key(run_dir: Path) -> tuple[Any, ...] | None:
    """Identity of a run's files, or None when one is missing (then nothing is cached)."""
    key: list[Any] = [str(run_dir.resolve())]
    for name in (rundir.SUMMARY, rundir.LOADS, rundir.JOINTS):
        try:
            st = (run_dir / name).stat()
        except OSError:
            return None
        key += [st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns]
    return tuple(key)


def _read_run(run_dir: Path) -> tuple[pd.DataFrame, pd.DataFrame, dict[str, Any]]:
    if not run_dir.is_dir():
        raise InputError(str(run_dir), "run directory not found", "an existing directory")
    sp = run_dir / rundir.SUMMARY
    if not sp.is_file():
        raise InputError(str(sp), "file not found", "a run directory written by simulate")
    try:
        summary = json.loads(sp.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise InputError(str(sp), f"invalid JSON: {exc.msg}", "valid JSON") from None
    status = summary.get("status")
    if status != "complete":
        raise InputError(f"{sp}: status", f"run is {status!r}, not usable for fatigue",
                         "'complete'")
    dur = summary.get("duration_s")
    if not isinstance(dur, int | float) or not math.isfinite(dur) or dur <= 0:
        raise InputError(f"{sp}: duration_s", f"must be a number > 0, got {dur!r}", "> 0")
    loads = _read_parquet(run_dir / rundir.LOADS, LOADS_COLUMNS)
    joints = _read_parquet(run_dir / rundir.JOINTS, JOINTS_COLUMNS)
    if len(loads) == 0:
        raise InputError(str(run_dir / rundir.LOADS), "zero-length history (no rows)",
                         "at least two time samples per joint")
    num = loads[list(LOADS_COLUMNS)]
    bad = [c for c in LOADS_COLUMNS if not np.all(np.isfinite(num[c].to_numpy(dtype=float)))]
    if bad:
        raise InputError(str(run_dir / rundir.LOADS),
                         f"NaN or infinite values in column {bad[0]}", "finite numbers")
    have = [c for c in SPAN_COLUMNS if c in loads.columns]
    if have:
        if len(have) != len(SPAN_COLUMNS):
            raise InputError(str(run_dir / "loads.parquet"),
                             f"has {have[0]} without its partner column",
                             "both or neither of " + ", ".join(SPAN_COLUMNS))
        for c in SPAN_COLUMNS:
            if not np.all(np.isfinite(loads[c].to_numpy(dtype=float))):
                raise InputError(str(run_dir / "loads.parquet"),
                                 f"NaN or infinite values in column {c}", "finite numbers")
        # the steel sees the joint moment plus the span correction
        loads = loads.assign(
            bending_x_Nm=loads["bending_x_Nm"].to_numpy(dtype=float)
            + loads["span_bending_x_Nm"].to_numpy(dtype=float),
            bending_y_Nm=loads["bending_y_Nm"].to_numpy(dtype=float)
            + loads["span_bending_y_Nm"].to_numpy(dtype=float))
    if joints["joint"].duplicated().any():
        raise InputError(str(run_dir / rundir.JOINTS), "a joint appears in more than one row",
                         "one row per recorded joint")
    unknown = sorted(set(joints["component_type"]) - set(COMPONENT_TYPES))
    if unknown:
        raise InputError(str(run_dir / rundir.JOINTS),
                         f"unknown component_type {unknown[0]!r}", ", ".join(COMPONENT_TYPES))
    return loads, joints, summary


def _joint_loads(loads: pd.DataFrame, j: int, where: str) -> tuple[np.ndarray, np.ndarray, float]:
    sub = loads[loads["joint"] == j].sort_values("time_s", kind="stable")
    t = sub["time_s"].to_numpy(dtype=float)
    if t.size < 2:
        raise InputError(where, f"joint {j} has {t.size} time sample(s)", ">= 2 samples")
    if np.any(np.diff(t) <= 0):
        raise InputError(where, f"joint {j} has repeated time stamps", "strictly increasing time")
    return t, sub[list(LOAD_COLUMNS)].to_numpy(dtype=np.float64), float(sub["md_m"].iloc[-1])


RP7G_COLUMNS: tuple[str, ...] = (
    "joint", "md_m", "s_from_bit_m", "component", "component_type", "location",
    "hole_dls_deg_per_30m", "tension_N", "sigma_b_Pa", "rp7g_damage_rate_per_h", "rp7g_life_h",
    "max_permissible_dls_deg_per_30m", "dynamic_damage_rate_per_h", "dynamic_to_rp7g_ratio")
_RAD_PER_M_TO_DEG_PER_30M = 30.0 * 180.0 / math.pi


def api_rp7g_baseline(loads: pd.DataFrame, joints: pd.DataFrame, case: Any,
                      cfg: FatigueConfig, sel: Sequence[int]) -> pd.DataFrame:
    """API RP7G / Lubinski baseline of each selected joint's pipe body, same run.

    The same well, string and operating point as the dynamic run: hole
    curvature at the joint's mean MD over the window (the case's well survey),
    tension = the joint's mean axial force (compression clipped to 0, the
    baseline's plain-beam limit), the case's rpm, the body section of
    ``joints.parquet``, the body S-N curve, body bending SCF and Goodman
    correction of ``cfg``; one fully reversed cycle per revolution
    (docs/fatigue.md#api-rp7g, :func:`drillfatigue.fatigue.rp7g.rp7g_damage_rate_profile`).
    The maximum permissible dogleg (RP7G endurance line) is given for grades
    E-75 and S-135 only (NaN otherwise); joint spacing 30 ft (L = 180 in).

    Parameters
    ----------
    loads, joints : DataFrame
        ``loads.parquet`` and ``joints.parquet`` of the run.
    case : drillfatigue.config.CaseConfig
        The run's case (``case.yaml``).
    cfg : FatigueConfig
    sel : sequence of int
        Joints to evaluate.

    Returns
    -------
    DataFrame
        :data:`RP7G_COLUMNS` (the ``dynamic_*`` columns are NaN here; filled by
        :func:`evaluate_run`).
    """
    survey = build_survey(case.well)
    sub = loads[loads["joint"].isin(list(sel))]
    mean = sub.groupby("joint")[["md_m", "axial_N"]].mean()
    jrow = joints.set_index("joint")
    curve = build_curve(cfg.body.curve, cfg.effective_environment)
    grade = get_grade(cfg.grade)
    rpm = abs(float(case.operation.rpm))
    rop = max(float(case.operation.rop_m_per_s), 1e-9)  # the rate per hour does not use ROP
    rows = []
    for j in sel:
        md, axial = float(mean.loc[j, "md_m"]), float(mean.loc[j, "axial_N"])
        info = jrow.loc[j]
        od, idm = float(info["body_od_m"]), float(info["body_id_m"])
        kappa = float(np.interp(md, survey.md_m, survey.dls_rad_per_m))
        scf = float(cfg.scf[str(info["component_type"])].body.bending)
        res = rp7g_damage_rate_profile(np.array([md]), np.array([kappa]), np.array([axial]), rpm,
                                       rop, od, idm, curve, scf=scf, ultimate_Pa=grade.tensile_Pa)
        rate = float(res["damage_rate_per_h"][0])
        dl_max = float("nan")
        if cfg.grade in RP7G_GRADES:
            sec = Section(od, idm)
            dl_max = max_permissible_dogleg(cfg.grade, max(axial, 0.0), od, sec.inertia_m4,
                                            sec.area_m2, HALF_JOINT_SPACING_M, E_RP7G_PA) \
                * _RAD_PER_M_TO_DEG_PER_30M
        rows.append({"joint": int(j), "md_m": md, "s_from_bit_m": float(info["s_from_bit_m"]),
                     "component": str(info["component"]),
                     "component_type": str(info["component_type"]), "location": "body",
                     "hole_dls_deg_per_30m": kappa * _RAD_PER_M_TO_DEG_PER_30M,
                     "tension_N": max(axial, 0.0), "sigma_b_Pa": float(res["sigma_b_Pa"][0]),
                     "rp7g_damage_rate_per_h": rate,
                     "rp7g_life_h": 1.0 / rate if rate > 0 else math.inf,
                     "max_permissible_dls_deg_per_30m": dl_max,
                     "dynamic_damage_rate_per_h": math.nan, "dynamic_to_rp7g_ratio": math.nan})
    return pd.DataFrame(rows, columns=list(RP7G_COLUMNS))


def _run_case(run_dir: Path) -> Any:
    """The run's case (``case.yaml``) when it states its well, string and operation,
    else None (then there is no API RP7G column)."""
    p = run_dir / rundir.CASE
    if not p.is_file():
        return None
    data = read_yaml(p)
    if not isinstance(data, dict) or not all(k in data for k in ("well", "string", "operation")):
        return None
    try:
        return case_from_dict(data)
    except InputError as exc:
        raise InputError(f"{p}: {exc.field}", exc.problem, exc.allowed) from None


def evaluate_run(run_dir: Path, cfg: FatigueConfig, out_dir: Path | None = None, *,
                 joints: Sequence[int] | None = None, criterion: str | None = None,
                 rp7g_baseline: bool = True,
                 uniaxial_damage: Mapping[tuple[int, str], float] | None = None
                 ) -> pd.DataFrame:
    """Fatigue damage of every selected joint and location of a run.

    Parameters
    ----------
    run_dir : Path
        Simulator run directory (see module docstring).
    cfg : FatigueConfig
    out_dir : Path, optional
        Where to write ``damage.parquet``, ``summary.json`` and plots; nothing
        is written when None. A ``fatigue`` output folder
        (:class:`drillfatigue.files.OutputFolder`): a folder holding files
        drillfatigue did not write is refused before any work, and a rerun
        replaces only the files an earlier evaluation wrote there.
    joints : sequence of int, optional
        Joints to evaluate (default ``cfg.joints``, else all).
    criterion : str, optional
        Overrides ``cfg.criterion``.
    rp7g_baseline : bool
        With ``out_dir``, and when the run's ``case.yaml`` states its well,
        string and operation: also write ``api_rp7g.parquet``
        (:func:`api_rp7g_baseline`, beside the dynamic body damage rate) and
        put both in ``summary.json`` and the damage-along-string plot.
    uniaxial_damage : mapping, optional
        The ``uniaxial_damage`` of every selected (joint, location), already
        evaluated on this run with these settings (an evaluation with criterion
        ``uniaxial``): the uniaxial route is not run again. Ignored with
        ``residue: carry`` or ``load_classes`` (their uniaxial route differs).

    Returns
    -------
    pandas.DataFrame
        One row per joint x location with :data:`DAMAGE_COLUMNS`.
    """
    crit = criterion if criterion is not None else cfg.criterion
    if crit not in CRITERIA:
        raise InputError("criterion", f"unknown criterion {crit!r}", ", ".join(CRITERIA))
    run_dir = Path(run_dir)
    if out_dir is not None:
        OutputFolder.check(out_dir, FATIGUE_KIND, names=FILES)
    loads, jt, summary = read_run(run_dir)
    duration_s = rundir.recorded_span_s(loads["time_s"].to_numpy())
    if duration_s <= 0.0:
        raise InputError(str(run_dir / rundir.LOADS), "fewer than two time samples",
                         "at least two time samples per joint")
    sel = list(joints) if joints is not None else cfg.joints
    all_joints = sorted(int(j) for j in jt["joint"])
    if sel is None:
        sel = all_joints
    missing = [j for j in sel if j not in all_joints]
    if missing:
        raise InputError("joints", f"joint {missing[0]} is not in joints.parquet",
                         f"recorded joints {all_joints[:10]}{' ...' if len(all_joints) > 10 else ''}")
    env = cfg.effective_environment
    curves = {loc: build_curve(getattr(cfg, loc).curve, env) for loc in LOCATIONS}
    grade = get_grade(cfg.grade)
    params = CriterionParams(cfg.torsion_to_tension_ratio, cfg.findley_k, cfg.fatemi_socie_k,
                             grade.yield_Pa)
    where = str(run_dir / rundir.LOADS)
    per_joint = {j: _joint_loads(loads, j, where) for j in sel}  # validate all before work
    want_case = (out_dir is not None and rp7g_baseline) or cfg.pressure
    case = _run_case(run_dir) if want_case else None
    pressures: dict[int, Pressure] = {}
    if cfg.pressure and case is not None:
        mean_md = loads[loads["joint"].isin(sel)].groupby("joint")["md_m"].mean()
        pressures = joint_pressures(case, {int(j): float(mean_md.loc[j]) for j in sel},
                                    cfg.pump_pressure_Pa)
    if not (out_dir is not None and rp7g_baseline):
        case = None
    jrow = jt.set_index("joint")
    rows: list[dict[str, Any]] = []
    crit_info: dict[tuple[int, str], Any] = {}
    given = (uniaxial_damage if crit != "uniaxial" and cfg.residue != "carry"
             and cfg.load_classes is None else None)
    search = PlaneSearch(cfg.n_surface_points, cfg.plane_step_deg, cfg.family_b,
                         cfg.n_shear_axes, cfg.n_refine, cfg.n_refine_points)
    options = DamageOptions(cfg.residue, cfg.mean_stress, grade.tensile_Pa,
                            walker_gamma=cfg.walker_gamma,
                            compressive_alpha=cfg.compressive_alpha)
    for j in sel:
        info = jrow.loc[j]
        t, L, md = per_joint[j]
        LT = loads_channels(L)  # one transposition shared by both locations
        pres = pressures.get(int(j))
        for loc in joint_locations(str(info["component_type"]), cfg):
            od, idm = location_section(info, loc)
            try:
                section = Section(float(od), float(idm))
            except InputError as exc:
                raise InputError(f"joints.parquet: joint {j} {loc}", exc.problem,
                                 exc.allowed) from None
            s = getattr(cfg.scf[str(info["component_type"])], loc)
            scf = SCF(s.axial, s.bending, s.torsion)
            res = evaluate_location(L, section, scf, curves[loc], crit, params, search=search,
                                    options=options, channels=LT, pressure=pres,
                                    with_uniaxial=given is None)
            uni = res.uniaxial_damage if given is None else float(given[(int(j), loc)])
            if cfg.residue == "carry" or cfg.load_classes is not None:
                Lp = L
                if pres is not None and not pres.is_zero:
                    Lp = L.copy()
                    Lp[:, 0] = true_wall_force_N(L[:, 0], section, pres)
                uni = _uniaxial_streamed(t, Lp, section, scf, curves[loc], cfg,
                                         grade.tensile_Pa, res.critical_point)
                if crit == "uniaxial":
                    res.damage = uni
            D = res.damage
            rows.append({
                "joint": int(j), "md_m": md, "s_from_bit_m": float(info["s_from_bit_m"]),
                "component": str(info["component"]),
                "component_type": str(info["component_type"]), "location": loc,
                "criterion": crit, "damage": D,
                "damage_rate_per_h": D / (duration_s / HOUR_S),
                "life_h": (duration_s / HOUR_S) / D if D > 0 else math.inf,
                "life_windows": 1.0 / D if D > 0 else math.inf,
                "critical_angle_deg": res.critical_angle_deg,
                "critical_plane_deg": res.critical_plane_deg,
                "uniaxial_damage": uni,
            })
            crit_info[(int(j), loc)] = (section, scf, res.critical_point, pres)
    df = pd.DataFrame(rows, columns=list(DAMAGE_COLUMNS))
    if out_dir is not None:
        rp7g = None
        if rp7g_baseline and case is not None:
            rp7g = api_rp7g_baseline(loads, jt, case, cfg, sel)
            body = df[df["location"] == "body"].set_index("joint")["damage_rate_per_h"]
            rp7g["dynamic_damage_rate_per_h"] = rp7g["joint"].map(body).to_numpy(dtype=float)
            with np.errstate(divide="ignore", invalid="ignore"):
                rp7g["dynamic_to_rp7g_ratio"] = (rp7g["dynamic_damage_rate_per_h"]
                                                 / rp7g["rp7g_damage_rate_per_h"])
        _write_outputs(Path(out_dir), df, per_joint, crit_info, cfg, crit, duration_s, run_dir,
                       curves, rp7g)
    return df


def _uniaxial_streamed(t: np.ndarray, L: np.ndarray, section: Section, scf: SCF, curve: SNCurve,
                       cfg: FatigueConfig, ultimate_Pa: float, point: int) -> float:
    """Uniaxial damage at one point by chunks (residue 'carry') or load classes."""
    cs, _, _ = surface_coefficients(section, scf, cfg.n_surface_points)
    sig = L @ cs[point]
    if cfg.residue == "carry":
        dt = float(np.median(np.diff(t)))
        n_chunk = sig.size if cfg.chunk_length_s is None else max(2, int(cfg.chunk_length_s / dt))
        stream = RainflowStream("half")
        parts = [stream.feed(sig[i:i + n_chunk]) for i in range(0, sig.size, n_chunk)]
        parts.append(stream.finish())
        S, Sm, cnt = (np.concatenate([p.ranges for p in parts]),
                      np.concatenate([p.means for p in parts]),
                      np.concatenate([p.count for p in parts]))
    else:
        c = find_cycles(sig, cfg.residue, cfg.load_classes)
        S, Sm, cnt = c.ranges, c.means, c.count
    if cnt.size == 0:
        return 0.0
    Seq = correct_mean_stress(S, Sm, cfg.mean_stress, ultimate_Pa, cfg.walker_gamma,
                              cfg.compressive_alpha)
    tf = curve.thickness_factor((section.od_m - section.id_m) / 2.0)
    return float(np.sum(cnt / curve.cycles_to_failure(Seq * tf)))


def _write_outputs(out: Path, df: pd.DataFrame, per_joint: dict[int, Any],
                   crit_info: dict[tuple[int, str], Any], cfg: FatigueConfig, crit: str,
                   duration_s: float, run_dir: Path, curves: dict[str, SNCurve],
                   rp7g: pd.DataFrame | None = None) -> None:
    folder = OutputFolder(out, FATIGUE_KIND, names=FILES)
    written = ["damage.parquet", "summary.json"]
    _atomic_write_parquet(df, folder.file("damage.parquet"))
    if rp7g is not None:
        _atomic_write_parquet(rp7g, folder.file("api_rp7g.parquet"))
        written.append("api_rp7g.parquet")
    g = df.loc[df["damage"].idxmax()] if len(df) and df["damage"].max() > 0 else None
    summary: dict[str, Any] = {
        "run_dir": str(run_dir), "criterion": crit, "recorded_s": duration_s,
        "n_joints": int(df["joint"].nunique()), "grade": cfg.grade,
        "environment": cfg.effective_environment, "residue": cfg.residue,
        "mean_stress_uniaxial": cfg.mean_stress,
        "sn_curves": {k: {"name": c.name, "reference": c.reference} for k, c in curves.items()},
        "governing": None if g is None else {
            "joint": int(g["joint"]), "location": str(g["location"]),
            "md_m": float(g["md_m"]), "damage": float(g["damage"]),
            "life_h": float(g["life_h"]), "life_windows": float(g["life_windows"]),
            "critical_angle_deg": float(g["critical_angle_deg"]),
            "critical_plane_deg": float(g["critical_plane_deg"])},
        "max_damage": float(df["damage"].max()) if len(df) else 0.0,
        "min_life_h": float(df["life_h"].min()) if len(df) else math.inf,
    }
    if rp7g is not None and len(rp7g):
        w = rp7g.loc[rp7g["rp7g_damage_rate_per_h"].idxmax()]
        dyn_body = df[df["location"] == "body"]
        summary["api_rp7g"] = {
            "method": "API RP7G / Lubinski tool-joint bending, Hansford-Lubinski damage "
                      "(one reversed cycle per revolution), pipe body",
            "max_damage_rate_per_h": float(w["rp7g_damage_rate_per_h"]),
            "min_life_h": float(w["rp7g_life_h"]), "joint": int(w["joint"]),
            "md_m": float(w["md_m"]),
            "dynamic_body_max_damage_rate_per_h": float(dyn_body["damage_rate_per_h"].max())
            if len(dyn_body) else math.nan,
            "min_max_permissible_dls_deg_per_30m":
                float(rp7g["max_permissible_dls_deg_per_30m"].min()),
            "max_hole_dls_deg_per_30m": float(rp7g["hole_dls_deg_per_30m"].max()),
        }
    atomic_write_bytes(folder.file("summary.json"),
                        json.dumps(summary, indent=2, default=float).encode("utf-8"))
    if cfg.plots and g is not None:
        for name in PLOT_FILES:
            folder.file(name)
        _plots(out, df, per_joint, crit_info[(int(g["joint"]), str(g["location"]))],
               int(g["joint"]), cfg, rp7g, duration_s)
        written += PLOT_FILES
    # outputs of an earlier evaluation this one did not write (no baseline, no plots)
    folder.remove(n for n in sorted(folder.owned) if n not in written)


def _plots(out: Path, df: pd.DataFrame, per_joint: dict[int, Any], info: Any, joint: int,
           cfg: FatigueConfig, rp7g: pd.DataFrame | None = None,
           duration_s: float = 1.0) -> None:
    section, scf, point, pres = info
    t, L, _ = per_joint[joint]
    if pres is not None and not pres.is_zero:
        L = L.copy()
        L[:, 0] = true_wall_force_N(L[:, 0], section, pres)  # sigma_z of the true wall force
    cs, ct, phi = surface_coefficients(section, scf, cfg.n_surface_points)
    sig, tau = L @ cs[point], L @ ct[point]

    def save(fig: Any, name: str) -> None:
        with atomic_output(out / name) as tmp:
            fig.savefig(tmp, dpi=100)

    fig, ax = subplots(figsize=(7, 3.5))
    ax.plot(t, sig / 1e6, lw=0.6, label="sigma_z")
    ax.plot(t, tau / 1e6, lw=0.6, label="tau_z-theta")
    ax.set(xlabel="time (s)", ylabel="stress (MPa)",
           title=f"joint {joint}, critical point {np.degrees(phi[point]):.0f} deg")
    ax.legend()
    fig.tight_layout()
    save(fig, "stress_history.png")

    mat, edges = rainflow_matrix(find_cycles(sig, "half"))
    fig, ax = subplots(figsize=(5, 4.5))
    im = ax.imshow(mat, origin="lower", extent=[edges[0] / 1e6, edges[-1] / 1e6,
                                                edges[0] / 1e6, edges[-1] / 1e6], cmap="viridis")
    fig.colorbar(im, ax=ax, label="cycles")
    ax.set(xlabel="to (MPa)", ylabel="from (MPa)", title="rainflow matrix of sigma_z")
    fig.tight_layout()
    save(fig, "rainflow_matrix.png")

    fig, ax = subplots(figsize=(7, 3.5))
    for loc, grp in df.groupby("location"):
        grp = grp.sort_values("s_from_bit_m")
        ax.semilogy(grp["s_from_bit_m"], grp["damage"].clip(lower=1e-30), "o-", ms=3, label=loc)
    if rp7g is not None and len(rp7g):
        r = rp7g.sort_values("s_from_bit_m")
        per_window = r["rp7g_damage_rate_per_h"] * (duration_s / HOUR_S)
        ax.semilogy(r["s_from_bit_m"], per_window.clip(lower=1e-30), "k--", lw=1,
                    label="API RP7G (body)")
    ax.set(xlabel="distance from bit (m)", ylabel="damage per window", title="damage along string")
    ax.legend()
    fig.tight_layout()
    save(fig, "damage_along_string.png")
