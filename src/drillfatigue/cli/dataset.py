"""``drillfatigue dataset build|card|export|research|restamp``: the damage dataset.

``dataset build`` assembles the dataset from a sweep's finished cases;
``dataset export --histories`` writes the raw load histories as Parquet
partitioned by case; ``dataset research`` generates the research dataset and
``dataset restamp`` keeps its case files valid across code changes.
"""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import out_option, params_option
from drillfatigue.config import load_params_requiring
from drillfatigue.errors import InputError

dataset_app = typer.Typer(help="The damage dataset: build, card, history export.",
                          no_args_is_help=True)
app.add_typer(dataset_app, name="dataset")

ParamsOpt = params_option(Path("params.yaml"), help="params.yaml to read")


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
           out: Path = out_option(Path("data/dataset/histories"), help="folder to write "
                                  "(OUT/loads, OUT/channels)"),
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
             out: Path = out_option(Path("data/research"), help="research folder to write "
                                    "(its dataset in OUT/dataset)"),
             workers: int = typer.Option(2, "--workers", min=1, help="worker processes"),
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
            out: Path = out_option(Path("data/research"), help="the research folder "
                                   "(dataset research --out)"),
            sample: int = typer.Option(16, "--sample", min=1,
                                       help="committed cases to re-run"),
            workers: int = typer.Option(2, "--workers", min=1, help="worker processes"),
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
