"""``drillfatigue benchmark card|score|leaderboard``: the research dataset as a benchmark.

``card`` writes the dataset folder's ``README.md`` and ``croissant.json``;
``score`` scores a model's prediction file on the held-out split with the
project's metrics; ``leaderboard`` fits the baselines on the train split,
scores them and writes the leaderboard page (docs/dataset.md).
"""

from __future__ import annotations

import json
import math
import shlex
import sys
from pathlib import Path
from typing import Any

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import out_option, params_option
from drillfatigue.errors import InputError

#: the command that generates the research dataset (docs/pipeline.md)
RESEARCH_COMMAND = ("drillfatigue dataset research --params params.yaml --n-cases 2048 "
                    "--heldout-cases 128")

benchmark_app = typer.Typer(help="The research dataset: card, scoring, leaderboard.",
                            no_args_is_help=True)
app.add_typer(benchmark_app, name="benchmark")

_DATASET = typer.Option(Path("data/research/dataset"), "--dataset", "-d",
                        help="dataset folder (train.parquet, heldout.parquet)")
_PARAMS = params_option(Path("params.yaml"),
                        help="params.yaml: surrogate.criterion, rate_floor_per_h, horizon_h")


def json_ready(data: Any) -> Any:
    """``data`` with NaN and infinities as None (strict JSON)."""
    if isinstance(data, dict):
        return {str(k): json_ready(v) for k, v in data.items()}
    if isinstance(data, list | tuple):
        return [json_ready(v) for v in data]
    if isinstance(data, float) and not math.isfinite(data):
        return None
    return data


def _surrogate_cfg(params: Path) -> Any:
    # start-up: the benchmark's modules load only when its command runs
    from drillfatigue.config import load_params
    from drillfatigue.config.surrogate import SurrogateConfig

    return load_params(params).surrogate if params.is_file() else SurrogateConfig()


@benchmark_app.command("card")
def card(dataset: Path = _DATASET, params: Path = _PARAMS,
         command: str = typer.Option(RESEARCH_COMMAND, "--command",
                                     help="the command that generated the splits"),
         commit: str | None = typer.Option(None, "--commit",
                                           help="commit that generated them (default: HEAD)"),
         spread: Path | None = typer.Option(None, "--spread",
                                            help="the replicates stage's spread.json "
                                                 "(the noise ceiling; absent: not measured)")
         ) -> None:
    """Write the dataset's card (README.md) and Croissant metadata (croissant.json)."""
    # start-up: the benchmark's modules load only when its command runs
    from drillfatigue.benchmark.card import write_card

    if spread is not None and not spread.is_file():
        raise InputError("--spread", f"{spread} not found", "the replicates stage's spread.json")
    cfg = _surrogate_cfg(params)
    paths = write_card(dataset, rate_floor_per_h=cfg.rate_floor_per_h, horizon_h=cfg.horizon_h,
                       command=command, commit=commit, spread_path=spread)
    typer.echo(f"wrote {paths[0]} and {paths[1]}")


@benchmark_app.command("score")
def score(predictions: Path = typer.Option(..., "--predictions", help="prediction file "
                                           "(parquet, or CSV by suffix)"),
          dataset: Path = _DATASET, params: Path = _PARAMS,
          criterion: str | None = typer.Option(None, "--criterion", "-c",
                                               help="fatigue criterion of the target "
                                                    "(default: surrogate.criterion)"),
          out: Path | None = out_option(None, help="write the metrics as JSON")
          ) -> None:
    """Score a model's predictions on the held-out split with the project's metrics."""
    # start-up: the benchmark's modules load only when its command runs
    from drillfatigue.benchmark.score import read_predictions, score_predictions
    from drillfatigue.benchmark.splits import load_splits
    from drillfatigue.files import atomic_write_text, check_output_file

    if out is not None:
        check_output_file(out, "--out", [("--predictions", predictions)])
    cfg = _surrogate_cfg(params)
    pred = read_predictions(predictions)
    heldout = load_splits(dataset)["heldout"]
    metrics = score_predictions(pred, heldout, criterion=criterion or cfg.criterion,
                                rate_floor_per_h=cfg.rate_floor_per_h, horizon_h=cfg.horizon_h)
    h = metrics["headline"]

    def f(x: Any) -> str:
        return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.3f}"

    typer.echo(f"{metrics['n_cases']} held-out cases, {metrics['n_rows']} rows "
               f"(criterion {metrics['criterion']}, horizon {metrics['horizon_h']:g} h)")
    typer.echo(f"factor 2, deciding rows ({h['n_deciding_rows']}): {f(h['factor2_deciding'])}; "
               f"coverage: {f(h['coverage_deciding'])}")
    typer.echo(f"factor 2, governing component ({h['n_governing_components']}): "
               f"{f(h['factor2_governing_component'])}; case max: {f(h['factor2_case_max'])}")
    typer.echo(f"longer than the horizon: precision {f(h['longer_than_precision'])}, "
               f"recall {f(h['longer_than_recall'])}; RMSE all rows {f(h['rmse_all'])} decades")
    if out is not None:
        atomic_write_text(out, json.dumps(json_ready(metrics), indent=2) + "\n")
        typer.echo(f"metrics -> {out}")


@benchmark_app.command("leaderboard")
def leaderboard(dataset: Path = _DATASET, params: Path = _PARAMS,
                out_dir: Path = out_option(Path("data/research/leaderboard"),
                                           help="folder of the baselines' prediction files"),
                design: Path | None = typer.Option(None, "--design", help="the held-out "
                                                   "design's cases.parquet (physics baseline)"),
                models: str = typer.Option("gbm,ensemble,gp,physics", "--models",
                                           help="comma-separated baselines"),
                variants: Path | None = typer.Option(None, "--variants",
                                                     help="JSON: name -> {model, surrogate "
                                                          "overrides}"),
                page: Path = out_option(Path("docs/leaderboard.md"),
                                        help="the markdown page to write", what="page"),
                results: Path = out_option(Path("benchmarks/results/leaderboard.json"),
                                           help="the full scores (JSON) to write", what="json"),
                note: str = typer.Option("", "--note", help="a note shown on the page")
                ) -> None:
    """Fit the baselines on the train split, score them, write the leaderboard."""
    # start-up: the benchmark's modules load only when its command runs
    import pandas as pd

    from drillfatigue.benchmark.leaderboard import leaderboard_markdown, run_leaderboard
    from drillfatigue.config import load_params
    from drillfatigue.files import atomic_write_text, check_output_file

    for path, option in ((page, "--out-page"), (results, "--out-json")):
        check_output_file(path, option, [("--dataset", dataset)])
    if not params.is_file():
        raise InputError("--params", f"{params} not found", "the project's params.yaml")
    p = load_params(params)
    design_frame = None
    if design is not None:
        if not design.is_file():
            raise InputError("--design", f"{design} not found", "the design's cases.parquet")
        design_frame = pd.read_parquet(design)
    spec = None
    if variants is not None:
        if not variants.is_file():
            raise InputError("--variants", f"{variants} not found", "a JSON file")
        spec = json.loads(variants.read_text(encoding="utf-8"))
    names = [m.strip() for m in models.split(",") if m.strip()]
    result = run_leaderboard(dataset, out_dir, p.surrogate, p.fatigue, design=design_frame,
                             models=names, variants=spec,
                             log=lambda s: print(s, file=sys.stderr))
    argv = ["drillfatigue", "benchmark", "leaderboard"] + (sys.argv[3:] if len(sys.argv) > 3
                                                        and sys.argv[1:3] == ["benchmark",
                                                                              "leaderboard"]
                                                        else [])
    command = " ".join(shlex.quote(a) for a in argv)
    result["command"] = command
    atomic_write_text(results, json.dumps(json_ready(result), indent=2) + "\n")
    atomic_write_text(page, leaderboard_markdown(result, command=command, note=note))
    typer.echo(f"leaderboard of {len(result['models'])} models -> {page}, {results}")
