"""The simulated window of a case chosen by the convergence of its governing damage rate.

A damage rate estimated from a window too short to hold a few stick-slip
periods, whirl episodes or bit-bounce bursts depends on where the window
happens to end. :func:`run_case_converged` (``sweep.window.mode: converged``)
simulates a case for ``sweep.window_s``, measures how much the damage rate of
its governing location moved over the last third of the recorded window
(:func:`governing_rate_change`) and, while that change is above
``sweep.window.tol_rel``, simulates the case again with the window multiplied
by ``growth``, up to ``max_s``. The simulator is deterministic, so the window
chosen is a function of the case and these settings alone.

The measure uses the uniaxial route of the fatigue chain (rainflow of the
surface stress, the location's S-N curve, Miner), which costs a small part of
a critical-plane evaluation, with the ``fatigue`` section's curves, SCFs and
pressure: the governing location is the joint and location with the largest
uniaxial damage rate over the whole recorded window. With ``D(t)`` the damage
of the record from its start to ``t`` and ``T`` its length,

    change = |D(T)/T - D(2T/3)/(2T/3)| / (D(T)/T)

a case with no damage at all (every cycle below the endurance limit) has
change 0: its rate is exactly zero over any part of the window.

A re-simulation starts from t = 0 (a run cannot be continued with a longer
duration: its checkpoint is keyed by the whole configuration), so an extended
case costs the sum of its windows. ``window.json`` in the case's run folder
records every window tried with its change, the window used and whether it
converged; the dataset carries the last two per case.
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from pathlib import Path
from typing import Any

import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import FatigueConfig, Params, validate
from drillfatigue.files import atomic_write_text
from drillfatigue.fatigue.run import evaluate_run
from drillfatigue.sweep.cases import run_case
from drillfatigue.sweep.design import apply_overrides

__all__ = ["WINDOW_FILE", "governing_rate_change", "run_case_converged", "window_inputs"]

#: Record of the windows tried, in the case's run folder.
WINDOW_FILE = "window.json"
#: Share of the recorded window the running rate is compared at.
HEAD_FRACTION = 2.0 / 3.0


def window_inputs(params: Params) -> dict[str, Any]:
    """The settings :func:`run_case_converged` needs beside the case (JSON-ready)."""
    cfg = params.sweep
    return {"first_s": cfg.window_s, "max_s": cfg.window.max_s, "growth": cfg.window.growth,
            "tol_rel": cfg.window.tol_rel, "path": cfg.window_path,
            "fatigue": params.fatigue.model_dump(mode="json")}


def governing_rate_change(run_dir: str | Path, cfg: FatigueConfig,
                          head_fraction: float = HEAD_FRACTION) -> dict[str, Any]:
    """Change of the governing location's damage rate over the last third of a run's record.

    Returns
    -------
    dict
        ``joint`` and ``location`` of the governing location (None without
        damage), ``rate_per_h`` over the whole record and ``head_rate_per_h``
        over its first ``head_fraction``, ``record_s`` (length of the record)
        and ``rate_change_rel`` (see the module doc).
    """
    return _rate_change(run_dir, cfg, head_fraction)[0]


def _rate_change(run_dir: str | Path, cfg: FatigueConfig,
                 head_fraction: float = HEAD_FRACTION) -> tuple[dict[str, Any], pd.DataFrame]:
    """:func:`governing_rate_change` and the uniaxial evaluation of the whole record it
    is taken from (:func:`drillfatigue.fatigue.run.evaluate_run`, criterion ``uniaxial``)."""
    run_dir = Path(run_dir)
    full = evaluate_run(run_dir, cfg, None, criterion="uniaxial")
    t = pd.read_parquet(run_dir / rundir.LOADS, columns=["time_s"])["time_s"].to_numpy(dtype=float)
    t0, t1 = float(t.min()), float(t.max())
    record_s = t1 - t0
    out: dict[str, Any] = {"joint": None, "location": None, "rate_per_h": 0.0,
                           "head_rate_per_h": 0.0, "record_s": record_s, "rate_change_rel": 0.0}
    if not len(full) or not float(full["damage"].max()) > 0.0 or record_s <= 0.0:
        return out, full
    row = full.loc[full["damage"].idxmax()]
    joint, location = int(row["joint"]), str(row["location"])
    cut = t0 + head_fraction * record_s
    with tempfile.TemporaryDirectory(prefix="window-") as tmp:
        head = Path(tmp)
        loads = pd.read_parquet(run_dir / rundir.LOADS)
        # the governing joint's rows only: the head is evaluated at that joint alone
        loads[(loads["time_s"] <= cut) & (loads["joint"] == joint)].to_parquet(
            head / rundir.LOADS, index=False)
        for name in (rundir.JOINTS, rundir.CASE):
            if (run_dir / name).is_file():
                shutil.copyfile(run_dir / name, head / name)
        (head / rundir.SUMMARY).write_text(json.dumps(
            {"status": "complete", "duration_s": cut - t0}), encoding="utf-8")
        part = evaluate_run(head, cfg, None, joints=[joint], criterion="uniaxial")
    d_head = float(part.loc[part["location"] == location, "damage"].iloc[0])
    rate = float(row["damage"]) / record_s * 3600.0
    head_rate = d_head / (cut - t0) * 3600.0
    out.update(joint=joint, location=location, rate_per_h=rate, head_rate_per_h=head_rate,
               rate_change_rel=abs(rate - head_rate) / rate)
    return out, full


def run_case_converged(inputs: dict[str, Any], case_dir: Path,
                       uniaxial: list[pd.DataFrame] | None = None) -> dict[str, Any]:
    """Simulate ``inputs['case']`` into ``case_dir`` with the window chosen as the module
    doc says (``inputs['window']``: :func:`window_inputs`); return the run's summary.

    ``uniaxial``: a list that receives the uniaxial evaluation of the run kept (every
    joint and location; the window check made it), which
    :func:`drillfatigue.sweep.cases.fatigue_case` can reuse."""
    case, win = inputs["case"], inputs["window"]
    cfg = validate(FatigueConfig, win["fatigue"], "fatigue")
    window = float(win["first_s"])
    max_s, growth, tol = float(win["max_s"]), float(win["growth"]), float(win["tol_rel"])
    tries: list[dict[str, Any]] = []
    while True:
        summary = run_case(apply_overrides(case, {win["path"]: window}, "sweep.window_path"),
                           Path(case_dir))
        check, full = _rate_change(case_dir, cfg)
        tries.append({"window_s": window, **check})
        converged = check["rate_change_rel"] <= tol
        if converged or window >= max_s or not math.isfinite(check["rate_change_rel"]):
            break
        window = min(window * growth, max_s)
    record = {"window_s": window, "converged": bool(converged), "tol_rel": tol,
              "rate_change_rel": check["rate_change_rel"], "tries": tries}
    atomic_write_text(Path(case_dir) / WINDOW_FILE, json.dumps(record, indent=2) + "\n")
    if uniaxial is not None:
        uniaxial.append(full)
    return summary


#: Simulated time of the warm-up run, s (recorded from t = 0).
WARMUP_DURATION_S = 0.02


def _warmup(inputs: dict[str, Any]) -> None:
    """Compile the simulator's and the uniaxial fatigue route's kernels for ``inputs['case']``
    (a short copy of it, run into a temporary folder). Errors are left to the real case."""
    short = apply_overrides(inputs["case"], {"operation.duration_s": WARMUP_DURATION_S,
                                             "recording.start_s": 0.0,
                                             "solver.checkpoint_every_s": 0.0})
    try:
        with tempfile.TemporaryDirectory(prefix="warmup-") as tmp:
            run_case(short, Path(tmp) / "run")
            governing_rate_change(Path(tmp) / "run",
                                  validate(FatigueConfig, inputs["window"]["fatigue"], "fatigue"))
    except Exception:  # noqa: BLE001 - the real run of this case reports the error
        return


run_case_converged.warmup = _warmup  # type: ignore[attr-defined]
