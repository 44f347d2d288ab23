"""``drillfatigue sweep design|run`` and ``drillfatigue dataset build|card|export|research|restamp``.

``sweep run`` runs the whole chain outside DVC (design, simulate, fatigue,
dataset) with the same library functions as the pipeline stages; it is
resumable. ``dataset export --histories`` writes the raw load histories as
Parquet partitioned by case.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.config import load_params_requiring, validate
from drillfatigue.config.sweep import SweepConfig
from drillfatigue.errors import InputError

sweep_app = typer.Typer(help="Case design and parallel, resumable sweeps.", no_args_is_help=True)
dataset_app = typer.Typer(help="The damage dataset: build, card, history export.",
                          no_args_is_help=True)
app.add_typer(sweep_app, name="sweep")
app.add_typer(dataset_app, name="dataset")

ParamsOpt = typer.Option(Path("params.yaml"), "--params", help="params.yaml to read")


def _fail(exc: Exception) -> None:
    print(f"error: {exc}", file=sys.stderr)
    raise typer.Exit(1)


@sweep_app.command("design")
def design(params: Path = ParamsOpt,
           out: Path | None = typer.Option(None, "--out",
                                           help="default: sweep.cases_path")) -> None:
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
        n_workers: int | None = typer.Option(None, "--n-workers", min=1),
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


@dataset_app.command("build")
def build(params: Path = ParamsOpt) -> None:
    """Assemble damage.parquet, README.md and metrics.json from finished cases."""
    from drillfatigue.sweep.stages import dataset_stage  # start-up: scipy.stats and the runner, ~0.9 s

    p = load_params_requiring(params, "sweep", "dataset build")
    metrics = dataset_stage(p)
    print(f"{metrics['n_rows']} rows from {metrics['n_cases_in_dataset']} cases -> "
          f"{p.sweep.dataset_dir}")


@dataset_app.command("card")
def card(params: Path = ParamsOpt) -> None:
    """Regenerate the dataset card (with the damage table and metrics)."""
    build(params)


@dataset_app.command("export")
def export(histories: bool = typer.Option(False, "--histories",
                                          help="export the raw load and channel histories"),
           params: Path = ParamsOpt,
           out: Path = typer.Option(Path("data/dataset/histories"), "--out"),
           sweep_dir: Path | None = typer.Option(None, "--sweep-dir",
                                                 help="default: sweep.sweep_dir")) -> None:
    """Export raw histories to Parquet partitioned by case (OUT/loads, OUT/channels)."""
    from drillfatigue.sweep.dataset import export_histories  # start-up: scipy.stats, the runner, ~0.9 s

    if not histories:
        raise InputError("dataset export", "nothing selected to export", "--histories")
    root = sweep_dir if sweep_dir is not None else Path(load_params_requiring(
        params, "sweep", "dataset export without --sweep-dir").sweep.sweep_dir)
    path = export_histories(root, out)
    print(f"histories -> {path}/loads, {path}/channels (partitioned by case_id)")


@dataset_app.command("research")
def research(params: Path = ParamsOpt,
             n_cases: int = typer.Option(2048, "--n-cases", min=1,
                                         help="training cases (sweep.seed)"),
             heldout_cases: int = typer.Option(128, "--heldout-cases", min=0,
                                               help="held-out cases (heldout.seed)"),
             out: Path = typer.Option(Path("data/research"), "--out"),
             workers: int = typer.Option(2, "--workers", min=1),
             histories: bool = typer.Option(False, "--histories",
                                            help="also keep each case's run folder"),
             progress: bool = typer.Option(True, "--progress/--no-progress")) -> None:
    """Generate the research dataset: one rows file per finished case (resumable from a
    fresh clone), assembled into OUT/dataset/{train,heldout}.parquet."""
    from drillfatigue.sweep.research import run_research  # start-up: the sweep's pool, ~1 s

    p = load_params_requiring(params, "sweep", "dataset research")
    res = run_research(p, out, n_cases=n_cases, heldout_cases=heldout_cases,
                       n_workers=workers, histories=histories, progress=progress)
    print(f"research: {res['n_run']} run, {res['n_skipped']} already done, "
          f"{res['n_failed']} failed; train {res['n_rows_train']} rows of "
          f"{res['n_cases_train']} cases, heldout {res['n_rows_heldout']} rows of "
          f"{res['n_cases_heldout']} cases -> {out}/dataset")


@dataset_app.command("restamp")
def restamp(params: Path = ParamsOpt,
            out: Path = typer.Option(Path("data/research"), "--out",
                                     help="the research folder (dataset research --out)"),
            sample: int = typer.Option(16, "--sample", min=1,
                                       help="committed cases to re-run"),
            workers: int = typer.Option(2, "--workers", min=1),
            progress: bool = typer.Option(True, "--progress/--no-progress")) -> None:
    """After a code change, re-run a sample of the committed research cases; when every
    one is equal bit for bit, record this code's physics digest in OUT/digests.json so the
    case files stay valid (a difference is refused, exit code 2)."""
    from drillfatigue.sweep.restamp import restamp as run_restamp  # start-up: the sweep's pool

    p = load_params_requiring(params, "sweep", "dataset restamp")
    res = run_restamp(p, out, n_cases=sample, n_workers=workers, progress=progress)
    if res["status"] == "current":
        print(f"restamp: the case files of {out} are already valid at physics digest "
              f"{res['physics_digest'][:12]}; nothing run")
    else:
        print(f"restamp: {res['n_cases']} cases ({res['n_rows']} rows) re-run equal bit for "
              f"bit; physics digest {res['physics_digest'][:12]} recorded in {out}/digests.json")
