"""The leaderboard: fit the baselines on the train split, score them on the held-out split.

:func:`run_leaderboard` fits every baseline of
:mod:`drillfatigue.benchmark.baselines` on the train split, writes each one's
prediction file, scores it with :func:`drillfatigue.benchmark.score.score_predictions`
(the same function as ``drillfatigue benchmark score``) and returns the scores;
:func:`leaderboard_markdown` renders them as the docs page.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd
from pydantic import ValidationError

from drillfatigue.benchmark.baselines import FITTED, predict_physics
from drillfatigue.benchmark.splits import DATASET_VERSION, load_splits
from drillfatigue.benchmark.score import score_predictions
from drillfatigue.config import FatigueConfig
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output

LEADERBOARD_KIND = "leaderboard"
#: Every baseline, in the order of the page.
MODELS: tuple[str, ...] = ("gbm", "ensemble", "gp", "physics")
DESCRIPTIONS = {
    "gbm": "gradient boosting as served (`surrogate.served_model: gbm`), cross-conformal "
           "interval",
    "ensemble": "torch deep ensemble of the `train` stage, split-conformal interval",
    "gp": "Gaussian process of the evaluation (subsample of `surrogate.gp_max_rows` rows)",
    "physics": "API RP7G / Lubinski bending under the soft-string tension, the S-N curve of "
               "the location; no training, no interval",
}


def prediction_file(model: str) -> str:
    """File name of a baseline's predictions in the leaderboard folder."""
    return f"predictions_{model}.parquet"


def run_leaderboard(dataset_dir: str | Path, out_dir: str | Path, cfg: SurrogateConfig,
                    fatigue: FatigueConfig, *, design: pd.DataFrame | None = None,
                    models: Sequence[str] = MODELS,
                    variants: Mapping[str, Mapping[str, Any]] | None = None,
                    log: Callable[[str], None] = print) -> dict[str, Any]:
    """Fit, predict and score the baselines.

    Parameters
    ----------
    dataset_dir : path
        The dataset folder (``train.parquet``, ``heldout.parquet``).
    out_dir : path
        Folder of the prediction files (a leaderboard folder: refused when it
        holds files drillfatigue did not write).
    cfg : SurrogateConfig
        Features, target criterion, censoring and the models' settings
        (``params.yaml`` ``surrogate``).
    fatigue : FatigueConfig
        S-N curves and stress concentrations of the physics baseline.
    design : DataFrame, optional
        The held-out cases' design (``case_id``, ``case_json``); the physics
        baseline needs it.
    models : sequence of str
        Baselines to run (:data:`MODELS`).
    variants : mapping, optional
        Extra entries ``name -> {"model": baseline, **surrogate overrides}``:
        a baseline fitted with other settings (features, layers, epochs ...).

    Returns
    -------
    dict
        ``dataset`` (version, cases and rows per split), ``settings`` and
        ``models``: per entry its score (:func:`score_predictions`), ``fit_s``
        (fit and predict wall time, s) and ``description``.
    """
    unknown = [m for m in models if m not in MODELS]
    if unknown:
        raise InputError("--models", f"unknown model(s) {unknown}", ", ".join(MODELS))
    entries: dict[str, tuple[str, SurrogateConfig]] = {m: (m, cfg) for m in models}
    for name, spec in (variants or {}).items():
        spec = dict(spec)
        base = spec.pop("model", None)
        if base not in FITTED:
            raise InputError(f"variant {name}", f"model {base!r}", ", ".join(FITTED))
        try:
            entries[name] = (base, SurrogateConfig.model_validate(cfg.model_dump() | spec))
        except ValidationError as exc:
            err = exc.errors()[0]
            field = ".".join(str(x) for x in err["loc"])
            raise InputError(f"variant {name}: {field}", err["msg"],
                             "surrogate settings (docs/surrogate.md)") from None
    if "physics" in entries and design is None:
        raise InputError("--design", "the physics baseline needs the held-out cases' design",
                         "the design's cases.parquet, or --models without physics")
    frames = load_splits(dataset_dir)
    train, heldout = frames["train"], frames["heldout"]
    folder = OutputFolder(out_dir, LEADERBOARD_KIND, "--out",
                          [prediction_file(m) for m in entries])
    result: dict[str, Any] = {
        "dataset": {"dir": str(dataset_dir), "version": DATASET_VERSION,
                    "n_train_cases": int(train["case_id"].nunique()),
                    "n_train_rows": int(len(train)),
                    "n_heldout_cases": int(heldout["case_id"].nunique()),
                    "n_heldout_rows": int(len(heldout))},
        "settings": {"criterion": cfg.criterion, "horizon_h": cfg.horizon_h,
                     "rate_floor_per_h": cfg.rate_floor_per_h, "coverage_nominal": cfg.coverage},
        "models": {},
    }
    for name, (base, mcfg) in entries.items():
        log(f"{name}: fitting on {result['dataset']['n_train_cases']} cases ...")
        t0 = time.perf_counter()
        if base == "physics":
            pred = predict_physics(heldout, design, mcfg, fatigue)  # type: ignore[arg-type]
        else:
            pred = FITTED[base](train, heldout, mcfg)
        fit_s = time.perf_counter() - t0
        path = folder.file(prediction_file(name))
        with atomic_output(path) as tmp:
            pred.to_parquet(tmp, index=False)
        scores = score_predictions(pred, heldout, criterion=cfg.criterion,
                                   rate_floor_per_h=cfg.rate_floor_per_h, horizon_h=cfg.horizon_h)
        overrides = {k: v for k, v in (variants or {}).get(name, {}).items() if k != "model"}
        result["models"][name] = {"baseline": base, "description": DESCRIPTIONS[base],
                                  "overrides": overrides, "fit_s": round(fit_s, 1),
                                  "predictions": str(path), **scores}
        h = scores["headline"]
        log(f"{name}: factor 2 {h['factor2_deciding']:.3f} on {h['n_deciding_rows']} deciding "
            f"rows, {fit_s:.0f} s")
    return result


def _fmt(x: Any, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    if isinstance(x, float):
        return f"{x:.{digits}f}"
    return str(x)


def leaderboard_markdown(result: Mapping[str, Any], *, command: str, note: str = "") -> str:
    """The leaderboard page (markdown) of a :func:`run_leaderboard` result."""
    d, s, models = result["dataset"], result["settings"], result["models"]
    order = sorted(models, key=lambda m: -(models[m]["headline"]["factor2_deciding"]
                                           if math.isfinite(models[m]["headline"]
                                                            ["factor2_deciding"]) else -1))
    lines = [
        "# Leaderboard",
        "",
        "Models of the [research dataset](dataset.md) scored on its held-out split by "
        "`drillfatigue benchmark score` (the project's metrics, [definitions]"
        "(surrogate.md#the-target-lives-beyond-the-horizon-are-censored)). Generated by:",
        "",
        "```",
        command,
        "```",
        "",
    ]
    if note:
        lines += ["!!! note", "", f"    {note}", ""]
    lines += [
        f"Dataset version {d['version']}: fitted on {d['n_train_cases']} training cases "
        f"({d['n_train_rows']} rows), scored on {d['n_heldout_cases']} held-out cases "
        f"({d['n_heldout_rows']} rows). Target: log10 damage rate per hour, criterion "
        f"`{s['criterion']}`, floored at {s['rate_floor_per_h']:g} per h; horizon "
        f"{s['horizon_h']:g} h; nominal interval coverage {s['coverage_nominal']:.0%}.",
        "",
        "**Deciding rows** are those whose predicted life is within the horizon (what a user "
        "reads as a number); coverage there counts a row simulated beyond the horizon as "
        "covered once the interval reaches down to it. **Governing component**: the largest "
        "rate per case and component type, predicted against simulated. **Longer than**: "
        "precision and recall of the answers \"life beyond the horizon\".",
        "",
        "| model | factor 2, deciding rows | coverage | mean width (decades) | factor 2, governing "
        "component | factor 2, case max | longer than: precision | recall | RMSE, all rows "
        "(decades) | fit + predict (s) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for m in order:
        h = models[m]["headline"]
        lines.append(
            f"| {m} | {_fmt(h['factor2_deciding'])} ({h['n_deciding_rows']} rows) | "
            f"{_fmt(h['coverage_deciding'])} | {_fmt(h['mean_width_deciding'], 2)} | "
            f"{_fmt(h['factor2_governing_component'])} | {_fmt(h['factor2_case_max'])} | "
            f"{_fmt(h['longer_than_precision'])} | {_fmt(h['longer_than_recall'])} | "
            f"{_fmt(h['rmse_all'], 2)} | {_fmt(models[m]['fit_s'], 0)} |")
    lines += ["", "## Models", ""]
    for m in order:
        extra = models[m].get("overrides") or {}
        more = f" Settings changed: `{extra}`." if extra else ""
        lines.append(f"- **{m}**: {models[m]['description']}.{more}")
    decades = sorted({k for m in order for k in models[m]["deciding"]["by_decade"]}, key=float)
    lines += _breakdown(models, order, "by_decade", decades,
                        "Factor 2 per decade of the simulated rate (deciding rows)",
                        "decade (1/h)")
    groups = sorted({k for m in order
                     for k in models[m]["deciding"].get("by_component_type_location", {})})
    lines += _breakdown(models, order, "by_component_type_location", groups,
                        "Factor 2 per component type and location (deciding rows)",
                        "component, location")
    lines += ["", "## Submitting a model", "",
              "Fit on `train.parquet` only, predict every row of `heldout.parquet` and score the "
              "file as [the dataset page](dataset.md#scoring-a-model) shows; the full metrics "
              "of each row above are in `benchmarks/results/leaderboard.json`.", ""]
    return "\n".join(lines)


def _breakdown(models: dict[str, Any], order: list[str], key: str, rows: list[str],
               title: str, head: str) -> list[str]:
    """A section of the page: factor 2 (rows) of each model per entry of the deciding
    metrics' ``key`` breakdown, "–" where a model has no row there."""
    lines = ["", f"## {title}", "", f"| {head} | " + " | ".join(order) + " |",
             "|---|" + "---|" * len(order)]
    for k in rows:
        cells = []
        for m in order:
            e = models[m]["deciding"].get(key, {}).get(k)
            cells.append(f"{_fmt(e['factor2_fraction'])} ({e['n']})" if e and e["n"] else "–")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    return lines
