"""DVC stage ``evaluate``: score the surrogate and the GP / gradient-boosting baselines.

On the model's held-out test cases (the case-wise split stored with the
model) it writes ``data/surrogate/metrics.json`` (R^2, RMSE, MAE of log10 damage
rate, interval coverage and width, factor-of-2 fraction, per model; the same
errors on each case's governing damage rate and on the rows that could set
the string's life, under ``governing``; with ``--noise-floor``, the
replicate ceiling and the models' factor-of-2 fraction per decade of damage
rate, under ``noise_floor.by_decade``, also printed as a table),
``data/surrogate/plots/predictions.csv`` (DVC plots: y_true vs each model),
``parity.png`` and ``residuals.png``.

Usage: ``python pipeline/evaluate.py [--params params.yaml] [--data data/dataset/damage.parquet]
[--model data/surrogate/model] [--metrics data/surrogate/metrics.json] [--plots data/surrogate/plots]
[--synthetic-cases N] [--noise-floor data/replicates/spread.json] [--heldout PATH]
[--draws data/heldout/draws/spread.parquet]``

``--heldout`` (default: ``surrogate.heldout_path``; none: the model's test
cases) scores every row of a dataset of its own design instead; the
``deciding`` block of the metrics scores the rows whose predicted life is
within ``surrogate.horizon_h`` and the governing damage per component.
``--draws`` (the ``heldout_draws`` stage's ``spread.parquet``) adds
``deciding_draws``: the same rows scored against the mean rate of each
case's draws (rpm moved by ``heldout.draw_rel_step``) beside the single run.
"""

from __future__ import annotations

import sys
from argparse import Namespace
from typing import TYPE_CHECKING, Any

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import Params, SurrogateConfig  # noqa: E402
from drillfatigue.errors import InputError  # noqa: E402
from drillfatigue.stage import Option, stage_main  # noqa: E402

if TYPE_CHECKING:
    import pandas as pd


#: Kind of the ownership marker of the evaluation plots folder.
PLOTS_KIND = "evaluation"

OPTIONS = (
    Option("--data", default="data/dataset/damage.parquet"),
    Option("--model", default="data/surrogate/model"),
    Option("--metrics", default="data/surrogate/metrics.json"),
    Option("--plots", default="data/surrogate/plots", folder=PLOTS_KIND),
    Option("--synthetic-cases", type=int, default=0),
    Option("--noise-floor", help="spread.json of the replicates stage: adds the noise floor"),
    Option("--heldout", help="held-out dataset to score (default: surrogate.heldout_path)"),
    Option("--draws", help="spread.parquet of the heldout_draws stage: also scores the "
                           "held-out rows against the mean rate of their case's draws"),
)


def evaluate_models(params: Params, args: Namespace) -> str:
    from drillfatigue.files import OutputFolder
    from drillfatigue.surrogate import Surrogate, make_synthetic_dataset
    from drillfatigue.surrogate.data import read_dataset
    from drillfatigue.surrogate.evaluation import evaluate, plot_parity, plot_residuals
    from drillfatigue.surrogate.io import write_csv, write_json

    cfg = params.surrogate
    frame = (make_synthetic_dataset(args.synthetic_cases, seed=cfg.split_seed)
             if args.synthetic_cases > 0 else read_dataset(args.data))
    model = Surrogate.load(args.model)
    held_path = args.heldout or cfg.heldout_path
    heldout = read_dataset(held_path) if held_path else None
    metrics, pred = evaluate(frame, model, cfg, heldout=heldout)
    if args.noise_floor:
        from drillfatigue.surrogate.evaluation import noise_floor_metrics, read_spread

        spread = read_spread(args.noise_floor, cfg.criterion)
        metrics["noise_floor"] = noise_floor_metrics(spread, pred["y_true"].to_numpy(), metrics)
    if args.draws:
        metrics["deciding_draws"] = _draws_metrics(args.draws, pred, heldout, cfg)
    plots = OutputFolder(args.plots, PLOTS_KIND, "--plots")
    write_json(metrics, args.metrics)
    write_csv(pred, plots.file("predictions.csv"))
    plot_parity(pred, str(plots.file("parity.png")))
    plot_residuals(pred, str(plots.file("residuals.png")))
    return "\n".join(_summary_lines(metrics, cfg.horizon_h))


def _draws_metrics(draws_path: str, pred: pd.DataFrame, heldout: pd.DataFrame | None,
                   cfg: SurrogateConfig) -> dict[str, Any]:
    """The held-out rows scored against the mean rate of their case's draws."""
    import pandas as pd

    from drillfatigue.surrogate.evaluation import draws_metrics, mean_of_draws_log10

    if heldout is None:
        raise InputError("--draws", "given without a held-out dataset",
                         "--heldout or surrogate.heldout_path")
    if not (pred["case_id"].astype(str).to_numpy()
            == heldout["case_id"].astype(str).to_numpy()).all():
        raise InputError("--draws", "the scored rows are not the held-out rows in order",
                         "the held-out dataset the model was evaluated on")
    table = pd.read_parquet(draws_path)
    y_draws = mean_of_draws_log10(heldout, table, cfg.rate_floor_per_h)
    y_log = mean_of_draws_log10(heldout, table, cfg.rate_floor_per_h, average="log10")
    models = tuple(m for m in ("ensemble", "gp", "hgb") if m in pred.columns)
    return draws_metrics(pred, y_draws, models, cfg.horizon_h, y_log)


def _cell(v: float | None, width: int) -> str:
    """A fraction to 3 decimals, or '-' where the decade has no rows."""
    return f"{v:{width}.3f}" if v is not None else f"{'-':>{width}s}"


def _summary_lines(metrics: dict[str, Any], horizon_h: float) -> list[str]:
    """The printed summary: scores per model, against the draws, by decade."""
    lines = [f"scored on {metrics['test_source']} cases ({metrics['n_test_cases']}); "
             f"horizon {horizon_h:.3g} h"]
    for m in ("ensemble", "gp", "hgb"):
        s = metrics[m]
        d = metrics["deciding"][m]
        rows, gov, bh = d["rows"], d["governing"], d["beyond_horizon"]
        lines.append(
            f"{m:9s} R2 {s['r2']:.4f}  RMSE {s['rmse']:.4f}  coverage {s['coverage']:.3f}  "
            f"factor-2 {s['factor2_fraction']:.3f}; predicted within the horizon "
            f"({rows['n']} rows): RMSE {rows['rmse']:.3f}, factor-2 "
            f"{rows['factor2_fraction']:.3f}, coverage {rows['coverage']:.3f}; governing per "
            f"component: factor-2 {gov['factor2_fraction']:.3f}; 'longer than' precision "
            f"{bh['precision']:.3f}")
    dd = metrics.get("deciding_draws", {})
    if dd.get("n_rows"):
        for m in ("ensemble", "gp", "hgb"):
            if m not in dd["single_run"]:
                continue
            one, avg = dd["single_run"][m]["rows"], dd["mean_of_draws"][m]["rows"]
            geo = dd["log_mean_of_draws"][m]["rows"]
            lines.append(
                f"{m:9s} predicted within the horizon, against the single run / the mean "
                f"rate of the case's draws / their mean log10 ({dd['n_cases']} cases): "
                f"factor-2 {one['factor2_fraction']:.3f} / {avg['factor2_fraction']:.3f} / "
                f"{geo['factor2_fraction']:.3f}, RMSE {one['rmse']:.3f} / {avg['rmse']:.3f} / "
                f"{geo['rmse']:.3f}")
    table = metrics.get("noise_floor", {}).get("by_decade")
    if table:
        lines.append("factor-2 fraction by decade of damage rate per h "
                     "(ceiling: replicate runs against each other)")
        lines.append(f"{'decade':>8s} {'ceiling':>8s} {'ensemble':>9s} {'gp':>6s} {'hgb':>6s} "
                     f"{'test rows':>10s}")
        for key, row in table.items():
            lines.append(
                f"{key:>8s} {_cell(row['ceiling_factor2'], 8)} {_cell(row.get('ensemble'), 9)} "
                f"{_cell(row.get('gp'), 6)} {_cell(row.get('hgb'), 6)} "
                f"{row.get('n_test_rows', 0):10d}")
    return lines


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, evaluate_models, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
