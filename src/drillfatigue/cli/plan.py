"""``drillfatigue plan rank``: well-plan ranking by predicted fatigue life.

::

    drillfatigue plan rank CANDIDATES.yaml [--model DIR] [--confirm K] [--out DIR]

The candidates file format is in :mod:`drillfatigue.studies.plan`. Bad input
(file, candidates, model folder) is one line on stderr, exit code 2, and
nothing is written.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import model_option, out_option, params_option
from drillfatigue.config import load_params, note_default_section
from drillfatigue.config.studies import PlanConfig
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder

plan_app = typer.Typer(help="Well-plan ranking by predicted fatigue life.", no_args_is_help=True)
app.add_typer(plan_app, name="plan")


@plan_app.command("rank")
def rank(
    candidates: Path = typer.Argument(..., help="candidates YAML (profiles with shared end "
                                                "points, drilling window)"),
    model_dir: Path | None = model_option(None, help="surrogate model folder "
                                          "(default: plan.surrogate_dir)"),
    confirm: int = typer.Option(None, "--confirm",
                                help="simulate the top K (default: plan.confirm_top_k)"),
    out: Path | None = out_option(None, help="output folder (default: plan.out_dir)"),
    params: Path | None = params_option(None, help="params file whose plan section to use (the "
                                        "whole file is validated); default: params.yaml when it "
                                        "exists, else the defaults"),
) -> None:
    """Rank candidate well plans by the predicted life of the critical component."""
    # start-up: the studies import every stage (~0.9 s)
    from drillfatigue.studies.plan import PLAN_KIND, load_candidates, rank_plans

    if params is None and Path("params.yaml").is_file():
        params = Path("params.yaml")
    # the whole file is validated: a typo in another section is not silently ignored
    cfg = load_params(params).plan if params is not None else PlanConfig()
    note = note_default_section(params, "plan") if params is not None else None
    if note:
        print(note, file=sys.stderr)
    model_dir = model_dir if model_dir is not None else Path(cfg.surrogate_dir)
    confirm = confirm if confirm is not None else cfg.confirm_top_k
    out = out if out is not None else Path(cfg.out_dir)
    OutputFolder.check(out, PLAN_KIND, "--out")
    if confirm < 0 or confirm > 50:
        raise InputError("--confirm", f"got {confirm}", "0 <= K <= 50")
    cset = load_candidates(candidates)
    if not model_dir.is_dir():
        raise InputError("--model", f"folder {str(model_dir)!r} not found",
                         "a model folder written by the train stage")
    from drillfatigue.surrogate import Surrogate  # optional extra [surrogate]: torch

    model = Surrogate.load(model_dir)
    table = rank_plans(cset, model, out, confirm=confirm)
    cols = [c for c in ("rank_surrogate", "candidate", "life_windows_surrogate",
                        "life_windows_surrogate_lower", "life_windows_surrogate_upper",
                        "critical_component", "ood_fraction", "life_windows_simulator",
                        "rank_simulator")
            if c in table.columns]
    typer.echo(table[cols].to_string(index=False, float_format=lambda v: f"{v:.3g}",
                                     na_rep="no answer"))
    refused = table[table["no_answer"] != ""]
    for _, row in refused.iterrows():
        typer.echo(f"{row['candidate']}: no answer: {row['no_answer']}")
    if len(refused):
        typer.echo("no best plan: the surrogate has no answer for every candidate")
    typer.echo(f"wrote {out / 'ranking.csv'}, {out / 'ranking.png'}")
