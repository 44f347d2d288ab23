"""Per-case functions run by the sweep workers: simulate one case, evaluate its fatigue.

Both are plain module-level functions (pickled by name for process pools and
Dask).

Layout written (one folder per case, moved into place atomically by the
runner, see :mod:`drillfatigue.sweep.runner`)::

    data/sweep/<case_id>/     loads.parquet, joints.parquet, channels.parquet,
                              summary.json, case.yaml, DONE
    data/fatigue/<case_id>/   damage.parquet, summary.json, DONE

Fatigue is a separate pass (own stage) rather than folded into the
simulation: the simulation is the expensive part, and a change of fatigue
settings (S-N curve, SCFs, criteria) then re-evaluates damage without
re-simulating. The fatigue task's inputs contain the hash of the run's DONE
marker and the fatigue settings, so either change re-runs the evaluation.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import FatigueConfig, case_from_dict, validate
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.errors import SimulationError
from drillfatigue.fatigue.run import api_rp7g_baseline, evaluate_run
from drillfatigue.files import atomic_output, atomic_write_text
from drillfatigue.units import HOUR_S
from drillfatigue.well import build_survey
from drillfatigue.well.features import survey_features

__all__ = ["api_rp7g_rows", "fatigue_case", "fatigue_tasks", "position_columns", "run_case",
           "warmup_fatigue", "warmup_simulation"]


def run_case(case: dict[str, Any], case_dir: Path) -> dict[str, Any]:
    """Simulate one case into ``case_dir``.

    Parameters
    ----------
    case : dict
        Full case (CaseConfig sections) as JSON-ready dict.
    case_dir : Path
        Empty folder to write the run into.

    Returns
    -------
    dict
        The run's ``summary.json`` content.

    Raises
    ------
    SimulationError
        Divergence, or a run that ends ``failed``/``incomplete``.
    """
    cfg = case_from_dict(case)
    simulate(cfg, Path(case_dir), progress=False, resume=False)
    summary_path = Path(case_dir) / rundir.SUMMARY
    if not summary_path.is_file():
        raise SimulationError(f"simulation wrote no summary.json in {case_dir}")
    summary = json.loads(summary_path.read_text(encoding="utf-8"))
    status = summary.get("status", "complete")
    if status != "complete":
        raise SimulationError(f"simulation ended with status {status!r}: "
                              f"{summary.get('message', summary.get('error', ''))}")
    return summary


WARMUP_DURATION_S = 0.01


def warmup_simulation(case: dict[str, Any]) -> None:
    """Compile the simulator's kernels for ``case``'s options (fills numba's on-disk cache).

    Simulates a copy of the case shortened to :data:`WARMUP_DURATION_S`,
    writing nothing. Kernels are typed on float64 arrays, so the
    string length does not matter; the options (friction model, bit model ...)
    select the same code as the real cases. Errors are left to the cases
    themselves (they are recorded per case), so a bad case cannot stop the sweep here.
    """
    short = json.loads(json.dumps(case))
    short.setdefault("operation", {})["duration_s"] = WARMUP_DURATION_S
    short.setdefault("solver", {})["checkpoint_every_s"] = 0.0
    try:
        simulate(case_from_dict(short), None, progress=False, resume=False)  # no output
    except Exception:  # noqa: BLE001 - the real run of this case reports the error
        return


run_case.warmup = warmup_simulation  # type: ignore[attr-defined]


def fatigue_tasks(case_ids: list[str], sweep_root: str | Path, fatigue_cfg: dict[str, Any],
                  criteria: list[str] | None = None, api_rp7g: bool = True,
                  cases: dict[str, dict[str, Any]] | None = None
                  ) -> list[tuple[str, dict[str, Any]]]:
    """Fatigue tasks ``(case_id, inputs)`` for the completed runs among ``case_ids``.

    The inputs hold the run folder, the run's DONE marker text (so a re-run
    simulation re-evaluates), the fatigue settings, the criteria to evaluate
    and, for the API RP7G baseline, the case (well and operation).
    """
    tasks = []
    for cid in case_ids:
        run_dir = Path(sweep_root) / cid
        done = run_dir / "DONE"
        if not done.is_file():
            continue
        inputs: dict[str, Any] = {"run_dir": str(run_dir),
                                  "run_marker": done.read_text(encoding="utf-8"),
                                  "fatigue": fatigue_cfg, "criteria": list(criteria or []),
                                  "api_rp7g": bool(api_rp7g)}
        if cases is not None and cid in cases:
            inputs["case"] = cases[cid]
        tasks.append((cid, inputs))
    return tasks


def position_columns(case: dict[str, Any], md_m: Any, s_from_bit_m: Any) -> dict[str, Any]:
    """Hole-geometry features of rows of a case (:mod:`drillfatigue.well.features`):
    local dogleg and inclination, windowed maximum dogleg, inclination and
    dogleg at the bit (MD = md + s_from_bit), mean build rate to the bit."""
    md = np.asarray(md_m, dtype=float)
    return survey_features(build_survey(case_from_dict(case).well), md,
                           md + np.asarray(s_from_bit_m, dtype=float))


def api_rp7g_rows(run_dir: Path, case: dict[str, Any], cfg: Any) -> list[dict[str, Any]]:
    """API RP7G (Lubinski) damage rate of each recorded joint's pipe body, as damage rows.

    The rows of :func:`drillfatigue.fatigue.run.api_rp7g_baseline` (hole
    curvature at the joint's mean MD, mean tension, the case's rpm, body
    section, S-N curve and SCF) in the damage-table layout: criterion
    ``api_rp7g``, ``damage_rate_per_h``, ``life_h``; there is no critical plane.
    """
    loads = pd.read_parquet(run_dir / rundir.LOADS, columns=["joint", "md_m", "axial_N"])
    joints = pd.read_parquet(run_dir / rundir.JOINTS)
    sel = sorted(int(j) for j in loads["joint"].unique())
    base = api_rp7g_baseline(loads, joints, case_from_dict(case), cfg, sel)
    out = base[["joint", "md_m", "s_from_bit_m", "component", "component_type", "location"]].copy()
    out["criterion"] = "api_rp7g"
    out["damage_rate_per_h"] = base["rp7g_damage_rate_per_h"]
    out["life_h"] = base["rp7g_life_h"]
    out["critical_angle_deg"] = float("nan")
    return out.to_dict("records")


def fatigue_case(task: dict[str, Any], case_dir: Path,
                 uniaxial: pd.DataFrame | None = None) -> Any:
    """Evaluate the fatigue of one finished run into ``case_dir``.

    Writes ``damage.parquet``: the rows of :func:`drillfatigue.fatigue.evaluate_run`
    for every criterion in ``task['criteria']`` (default: the configured one),
    plus the API RP7G rows (:func:`api_rp7g_rows`) when ``task['api_rp7g']``
    and the case are given, and (with the case) the hole-geometry columns of
    :func:`position_columns`; and ``summary.json``
    (rows, criteria, max damage rate).

    ``uniaxial``: the run's evaluation with criterion ``uniaxial`` over every joint and
    location, already made with these settings (the window check's,
    :func:`drillfatigue.sweep.window.run_case_converged`): the other criteria reuse its
    ``uniaxial_damage`` instead of running the uniaxial route again (same numbers).
    """
    cfg = validate(FatigueConfig, task["fatigue"], "fatigue")
    run_dir = Path(task["run_dir"])
    criteria = list(task.get("criteria") or [cfg.criterion])
    others = [c for c in criteria if c != "uniaxial"]
    given = None
    if uniaxial is not None:
        given = {(int(j), str(loc)): float(u) for j, loc, u in
                 zip(uniaxial["joint"], uniaxial["location"], uniaxial["uniaxial_damage"],
                     strict=True)}
    parts = [evaluate_run(run_dir, cfg, None, criterion=c, uniaxial_damage=given)
             for c in others]
    if "uniaxial" in criteria:
        if parts and cfg.residue != "carry" and cfg.load_classes is None:
            # evaluate_run's uniaxial_damage column is the uniaxial route's
            # damage at the worst surface point (the same number a 'uniaxial'
            # evaluation returns): reuse it instead of a second evaluation.
            uni = parts[0].copy()
            uni["criterion"] = "uniaxial"
            uni["damage"] = uni["uniaxial_damage"]
            times = pd.read_parquet(run_dir / rundir.LOADS, columns=["time_s"])["time_s"]
            duration_h = rundir.recorded_span_s(times.to_numpy()) / HOUR_S
            with np.errstate(divide="ignore"):
                uni["damage_rate_per_h"] = uni["damage"] / duration_h
                uni["life_h"] = duration_h / uni["damage"]
                uni["life_windows"] = 1.0 / uni["damage"]
            uni["critical_angle_deg"] = float("nan")
            uni["critical_plane_deg"] = float("nan")
            parts.append(uni)
        else:
            parts.append(evaluate_run(run_dir, cfg, None, criterion="uniaxial"))
    if task.get("api_rp7g") and task.get("case") is not None:
        parts.append(pd.DataFrame(api_rp7g_rows(run_dir, task["case"], cfg)))
    frame = pd.concat(parts, ignore_index=True, sort=False)
    if task.get("case") is not None:
        frame = frame.assign(**position_columns(task["case"], frame["md_m"],
                                                frame["s_from_bit_m"]))
    out = Path(case_dir)
    with atomic_output(out / "damage.parquet") as tmp:
        frame.to_parquet(tmp, index=False)
    worst = frame.groupby("criterion")["damage_rate_per_h"].max()
    summary = {"criteria": sorted(frame["criterion"].unique().tolist()), "n_rows": len(frame),
               "max_damage_rate_per_h": {str(k): float(v) for k, v in worst.items()}}
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, sort_keys=True))
    return summary


def warmup_fatigue(task: dict[str, Any]) -> None:
    """Compile the fatigue kernels: evaluate ``task``'s criteria at its run's first joint.

    Errors are left to the real evaluation (recorded per case).
    """
    try:
        cfg = validate(FatigueConfig, task["fatigue"], "fatigue")
        run_dir = Path(task["run_dir"])
        joint = int(pd.read_parquet(run_dir / rundir.JOINTS, columns=["joint"])["joint"].iloc[0])
        for crit in list(task.get("criteria") or [cfg.criterion]):
            evaluate_run(run_dir, cfg, None, joints=[joint], criterion=crit)
    except Exception:  # noqa: BLE001 - the real evaluation reports the error
        return


fatigue_case.warmup = warmup_fatigue  # type: ignore[attr-defined]
