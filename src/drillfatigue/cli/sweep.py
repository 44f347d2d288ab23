"""``drillfatigue sweep design|run``: case design and parallel, resumable sweeps.

``sweep run`` runs the whole chain outside DVC (design, simulate, fatigue,
dataset) with the same library functions as the pipeline stages; it is
resumable.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import out_option, params_option
from drillfatigue.config import load_params_requiring, validate
from drillfatigue.config.sweep import SweepConfig

sweep_app = typer.Typer(help="Case design and parallel, resumable sweeps.", no_args_is_help=True)
app.add_typer(sweep_app, name="sweep")

ParamsOpt = params_option(Path("params.yaml"), help="params.yaml to read")


def _fail(exc: Exception) -> None:
    print(f"error: {exc}", file=sys.stderr)
    raise typer.Exit(1)


@sweep_app.command("design")
def design(params: Path = ParamsOpt,
           out: Path | None = out_option(None, help="cases file to write "
                                         "(default: sweep.cases_path)")) -> None:
    """Sample the cases of params.yaml's sweep section into cases.parquet."""
    # start-up: scipy.stats and the runner, ~0.9 s
    from drillfatigue.sweep.stages import check_design_outputs, design_stage

    p = load_params_requiring(params, "sweep", "sweep design")
    check_design_outputs(out or p.sweep.cases_path, "--out" if out else "sweep.cases_path")
    frame = design_stage(p, out)
    print(f"{len(frame)} cases -> {out or p.sweep.cases_path}")


@sweep_app.command("run")
def run(params: Path = ParamsOpt,
        scheduler: str | None = typer.Option(
            None, "--scheduler", help="serial, processes, local-cluster or tcp://host:port"),
        n_workers: int | None = typer.Option(None, "--workers", min=1,
                                             help="worker processes (default: sweep.n_workers)"),
        progress: bool = typer.Option(True, "--progress/--no-progress")) -> None:
    """Design, simulate, evaluate fatigue and assemble the dataset (resumable)."""
    # start-up: the sweep package imports scipy.stats and the runner, ~0.9 s
    from drillfatigue.sweep.runner import SweepFailedError
    from drillfatigue.sweep.stages import (check_sweep_outputs, dataset_stage, design_stage,
                                           fatigue_stage, simulate_stage)

    p = load_params_requiring(params, "sweep", "sweep run")
    if scheduler is not None:  # validate the override like the config field
        validate(SweepConfig, {"scheduler": scheduler}, "sweep")
    check_sweep_outputs(p)  # every output folder at once, not after the simulations
    design_stage(p)
    try:
        sim = simulate_stage(p, scheduler=scheduler, n_workers=n_workers, progress=progress)
        fat = fatigue_stage(p, scheduler=scheduler, n_workers=n_workers, progress=progress)
    except SweepFailedError as exc:
        _fail(exc)
    metrics = dataset_stage(p)
    print(f"simulate: {sim.n_done} done, {sim.n_skipped} already done, {sim.n_failed} failed; "
          f"fatigue: {fat.n_done} done, {fat.n_skipped} already done, {fat.n_failed} failed; "
          f"dataset: {metrics['n_rows']} rows -> {p.sweep.dataset_dir}")
