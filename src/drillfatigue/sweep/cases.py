"""Per-case functions run by the sweep workers: simulate one case, evaluate its fatigue.

Both are plain module-level functions (pickled by name for process pools and
Dask). The simulator and the fatigue chain are imported when a case runs, so
this module imports without them.

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

from drillfatigue.errors import SimulationError

__all__ = ["fatigue_case", "fatigue_tasks", "run_case", "warmup"]


def _simulate_fn() -> Any:
    import drillfatigue

    fn = getattr(drillfatigue, "simulate", None)
    if fn is None:  # pragma: no cover - until the simulator lands
        from drillfatigue.dynamics import simulate as fn  # type: ignore[attr-defined,no-redef]
    return fn


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
    from drillfatigue.config import case_from_dict

    cfg = case_from_dict(case)
    _simulate_fn()(cfg, Path(case_dir), progress=False, resume=False)
    summary_path = Path(case_dir) / "summary.json"
    if not summary_path.is_file():
        raise SimulationError(f"simulation wrote no summary.json in {case_dir}")
    summary = json.loads(summary_path.read_text(encoding="utf-8"))
    status = summary.get("status", "complete")
    if status != "complete":
        raise SimulationError(f"simulation ended with status {status!r}: "
                              f"{summary.get('message', summary.get('error', ''))}")
    return summary


def warmup() -> None:
    """Compile the simulator's kernels once (fills numba's on-disk cache).

    Uses the simulator's own ``warmup()`` hook when it provides one
    (``drillfatigue.dynamics.warmup``); otherwise does nothing and the first
    case of each worker compiles (safe only with a per-worker cache folder).
    """
    try:
        from drillfatigue import dynamics
    except ImportError:  # pragma: no cover
        return
    hook = getattr(dynamics, "warmup", None)
    if callable(hook):
        hook()


def fatigue_tasks(case_ids: list[str], sweep_root: str | Path,
                  fatigue_cfg: dict[str, Any]) -> list[tuple[str, dict[str, Any]]]:
    """Fatigue tasks ``(case_id, inputs)`` for the completed runs among ``case_ids``.

    The inputs hold the run folder, the run's DONE marker text (so a re-run
    simulation re-evaluates) and the fatigue settings.
    """
    tasks = []
    for cid in case_ids:
        run_dir = Path(sweep_root) / cid
        done = run_dir / "DONE"
        if not done.is_file():
            continue
        tasks.append((cid, {"run_dir": str(run_dir),
                            "run_marker": done.read_text(encoding="utf-8"),
                            "fatigue": fatigue_cfg}))
    return tasks


def fatigue_case(task: dict[str, Any], case_dir: Path) -> Any:
    """Evaluate the fatigue of one finished run into ``case_dir``."""
    from drillfatigue.config import FatigueConfig, validate
    from drillfatigue.fatigue import evaluate_run  # type: ignore[attr-defined]

    cfg = validate(FatigueConfig, task["fatigue"], "fatigue")
    return evaluate_run(Path(task["run_dir"]), cfg, Path(case_dir))
