"""``drillfatigue simulate CASE.yaml --out RUN_DIR [--resume]``: run one case."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

import typer

from drillfatigue.cli.app import app
from drillfatigue import rundir
from drillfatigue.config import load_case
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.errors import InputError, Interrupted, SimulationError


def _completed_summary(out: Path, started: float) -> dict[str, Any] | None:
    """The summary of a run this command completed in ``out`` (written after ``started``,
    status complete), or None: a Ctrl-C that lands after the last history is renamed
    finds every final file written, and the run is reported complete, not interrupted."""
    path = out / rundir.SUMMARY
    try:
        if path.stat().st_mtime < started:
            return None  # an earlier run's summary
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(summary, dict) or summary.get("status") != "complete":
        return None
    if any(not (out / name).is_file() for name in summary.get("files") or []):
        return None
    return summary


@app.command("simulate")
def simulate_cmd(
    case: Path = typer.Argument(..., help="case YAML file (sections as in params.yaml)"),
    out: Path = typer.Option(..., "--out", "-o", help="run directory to write"),
    resume: bool = typer.Option(False, "--resume", help="continue from RUN_DIR/checkpoint.npz"),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="show a progress bar"),
) -> None:
    """Simulate the drill string of CASE and write loads, channels and a summary to RUN_DIR."""
    cfg = load_case(case)
    if out.exists() and not out.is_dir():
        raise InputError("--out", f"{str(out)!r} exists and is not a folder", "a folder path")
    if resume and not (out / rundir.CHECKPOINT).is_file():
        raise InputError("--resume", f"no checkpoint in {str(out)!r}",
                         f"a run directory with {rundir.CHECKPOINT} (set solver.checkpoint_every_s)")
    started = time.time()
    try:
        res = simulate(cfg, out, progress=progress, resume=resume)
    except SimulationError as exc:
        print(f"error: simulation failed: {exc}", file=sys.stderr)
        raise typer.Exit(1) from None
    except KeyboardInterrupt:
        s = _completed_summary(out, started)
        if s is None:
            raise Interrupted(f"the run in {str(out)!r} is incomplete (no final files "
                              "written); continue it with --resume") from None
    else:
        s = res.summary
    print(f"{s['status']}: {s['duration_s']:.3f} s simulated in {s['wall_time_s']:.1f} s "
          f"({s['real_time_factor']:.3g}x real time) -> {out}")
