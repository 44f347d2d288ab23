"""Learning curve of the served model on the research dataset, with the spread of its fits.

Reads the assembled research dataset (``drillfatigue dataset research``:
``--dataset`` with ``train.parquet`` and ``heldout.parquet``) and the training design
(``--design``, whose ``design_index`` is the order of the Sobol sequence). At each
size ``n`` of ``--sizes`` the served model (gradient boosting,
:func:`drillfatigue.surrogate.gbm.fit_gbm` through ``learning_curve.fit_served``:
early stopping on whole cases, monotone in dogleg, censored at the horizon) is
fitted ``--fits`` times and scored on the whole held-out split, on the rows that
decide life (``learning_curve.deciding_scores``):

- below the full size, fit ``j`` trains on the ``j``-th block of ``n``
  consecutive cases of the Sobol sequence (design indices ``j n`` to
  ``(j + 1) n - 1``; a block of ``2^k`` points of a scrambled Sobol sequence is
  a balanced design of its own), so the spread measures which ``n`` cases were
  simulated as well as the fit;
- at the full size (one block) fit ``j`` changes the early-stopping split's seed
  (``surrogate.split_seed + j``), so the spread there is the fit's alone.

``--model NAME --variants FILE`` fits the torch ensemble entry ``NAME`` of a
leaderboard variants file instead (``fit_predict_ensemble`` with its
settings; at the full size the fits change the members' seeds as well).

The replicate ceiling (the factor-2 fraction a perfect model of the mean scores
against one noisy replicate) is read from ``--spread`` when given.

Usage: ``python benchmarks/learning_curve_research.py [--dataset data/research/dataset]
[--design data/research/design/train.parquet] [--sizes 64 128 256 512 1024 2048]
[--fits 5] [--spread data/replicates/spread.json]`` ->
``benchmarks/results/learning_curve_research.json``, rewritten after each size (a
rerun with ``--keep`` keeps the sizes already there with the same settings);
``--table`` prints that file's curve as the markdown table of docs/dataset.md.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.benchmark.baselines import fit_predict_ensemble
from drillfatigue.benchmark.splits import load_splits
from drillfatigue.config import load_params
from drillfatigue.surrogate.io import write_json

sys.path.insert(0, str(Path(__file__).resolve().parent))
from learning_curve import METRICS, deciding_scores, fit_served, heldout_predictions  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RESULT = Path(__file__).parent / "results" / "learning_curve_research.json"


def case_order(design: pd.DataFrame, train: pd.DataFrame) -> list[str]:
    """Training case ids in the order of the Sobol sequence (only cases in ``train``)."""
    present = set(train["case_id"].astype(str))
    order = design.sort_values("design_index")["case_id"].astype(str)
    return [c for c in order if c in present]


def fit_blocks(order: list[str], n: int, fits: int) -> list[list[str]]:
    """The training cases of each fit at size ``n``: consecutive blocks of the sequence;
    the whole sequence, once per fit, when only one block fits."""
    n_blocks = len(order) // n
    if n_blocks <= 1:
        return [order[:n]] * fits
    return [order[j * n:(j + 1) * n] for j in range(min(fits, n_blocks))]


def _fit_predict(rows: pd.DataFrame, test: pd.DataFrame, cfg: Any,
                 variant: dict[str, Any] | None) -> tuple[np.ndarray, dict[str, Any]]:
    """Log10 rates predicted for ``test``: the served gradient boosting, or the torch
    ensemble of a leaderboard variant (its settings over ``cfg``)."""
    if variant is None:
        predict, info = fit_served(rows, cfg)
        return predict(test), {"n_iter": info["n_iter"]}
    pred = fit_predict_ensemble(rows, test, cfg)
    return pred["log10_damage_rate_per_h"].to_numpy(), {"seeds": list(cfg.seeds)}


def run_size(train: pd.DataFrame, test: pd.DataFrame, order: list[str], n: int, fits: int,
             sur: Any, variant: dict[str, Any] | None = None) -> dict[str, Any]:
    blocks = fit_blocks(order, n, fits)
    one_block = len(blocks) > 1 and blocks[0] is blocks[1]
    by_case = train.groupby(train["case_id"].astype(str), sort=False).indices
    base = sur if variant is None else sur.model_validate(sur.model_dump() | variant)
    runs = []
    for j, ids in enumerate(blocks):
        t0 = time.perf_counter()
        cfg = base
        if one_block:  # the fit's own spread: another early-stopping split, other seeds
            cfg = base.model_copy(update={"split_seed": base.split_seed + j, "seeds": tuple(
                s + j * len(base.seeds) for s in base.seeds)})
        rows = train.iloc[np.concatenate([by_case[c] for c in ids])]
        mu, info = _fit_predict(rows, test, cfg, variant)
        scores = deciding_scores(heldout_predictions(test, mu, cfg), cfg.horizon_h)
        runs.append({"fit": j, "first_design_index": None if one_block else j * n,
                     "split_seed": cfg.split_seed, "n_train_rows": int(len(rows)), **info,
                     "fit_s": round(time.perf_counter() - t0, 1), **scores})
    summary = {}
    for metric, _ in METRICS:
        vals = np.array([r[metric] for r in runs], dtype=float)
        summary[metric] = {"mean": float(vals.mean()), "std": float(vals.std(ddof=1))
                           if len(vals) > 1 else 0.0, "min": float(vals.min()),
                           "max": float(vals.max())}
    return {"n_cases": n, "varies": "early-stopping seed" if one_block else "case block",
            "fits": runs, "summary": summary}


def markdown_table(result: dict[str, Any]) -> str:
    """The curve as a markdown table: mean ± standard deviation over the fits (range)."""
    lines = ["| training cases | fits | varies | factor 2, deciding rows | RMSE (decades) "
             "| factor 2, governing component |", "|---|---|---|---|---|---|"]
    for size in result["sizes"]:
        s = size["summary"]
        cells = [f"{s[m]['mean']:.3f} ± {s[m]['std']:.3f} ({s[m]['min']:.3f}–{s[m]['max']:.3f})"
                 for m in ("factor2_fraction", "rmse", "governing_factor2_fraction")]
        lines.append(f"| {size['n_cases']} | {len(size['fits'])} | {size['varies']} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dataset", default="data/research/dataset")
    ap.add_argument("--design", default="data/research/design/train.parquet")
    ap.add_argument("--params", default=str(ROOT / "params.yaml"))
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512, 1024, 2048])
    ap.add_argument("--fits", type=int, default=5)
    ap.add_argument("--spread", default=None, help="replicate spread JSON (its ceiling)")
    ap.add_argument("--variants", default=None,
                    help="leaderboard variants JSON; with --model, the torch entry to fit")
    ap.add_argument("--model", default=None,
                    help="a torch ensemble entry of --variants instead of the served model")
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--keep", action="store_true",
                    help="keep the sizes already in --out (same settings) and run the rest")
    ap.add_argument("--table", action="store_true",
                    help="print the curve in --out as a markdown table and exit (no fit)")
    args = ap.parse_args(argv)
    if args.table:
        print(markdown_table(json.loads(Path(args.out).read_text(encoding="utf-8"))))
        return 0
    sur = load_params(args.params).surrogate
    variant = None
    if args.model:
        if not args.variants:
            ap.error("--model needs --variants")
        variant = dict(json.loads(Path(args.variants).read_text(encoding="utf-8"))[args.model])
        if variant.pop("model") != "ensemble":
            ap.error(f"--model: {args.model} is not a torch ensemble entry")
    splits = load_splits(args.dataset)
    train, test = splits["train"], splits["heldout"]
    order = case_order(pd.read_parquet(args.design, columns=["case_id", "design_index"]), train)
    too_big = [n for n in args.sizes if n > len(order)]
    if too_big:
        ap.error(f"--sizes: {too_big} larger than the {len(order)} training cases")
    settings = {"dataset": args.dataset, "sizes": args.sizes, "fits": args.fits,
                "model": args.model or "gbm (served)", "variant": variant,
                "n_train_cases": len(order), "n_heldout_cases": int(test["case_id"].nunique()),
                "n_heldout_rows": int(len(test))}
    result: dict[str, Any] = {
        "benchmark": "learning_curve_research", "python": platform.python_version(),
        "machine": platform.machine(), "settings": settings,
        "served_model": "gbm (fit_gbm on every row of the training cases)" if variant is None
        else f"{args.model}: torch ensemble, split-conformal on calibration cases",
        "metric": "held-out rows predicted within surrogate.horizon_h (deciding_metrics rows)",
        "command": "python benchmarks/learning_curve_research.py "
                   + " ".join(a for a in (argv if argv is not None else sys.argv[1:])
                              if a != "--keep"),
        "sizes": []}
    if args.spread:
        spread = json.loads(Path(args.spread).read_text(encoding="utf-8"))
        result["replicate_ceiling_factor2"] = spread["ceiling_factor2_fraction"]
        result["replicate_sigma_decades"] = spread["sigma_log10"]
    t0 = time.perf_counter()
    if args.keep and Path(args.out).is_file():
        old = json.loads(Path(args.out).read_text(encoding="utf-8"))
        if old.get("settings") != settings:
            ap.error(f"--keep: {args.out} was run with other settings")
        result["sizes"] = old["sizes"]
        t0 -= old.get("wall_s", 0.0)
    for n in args.sizes[len(result["sizes"]):]:
        result["sizes"].append(run_size(train, test, order, n, args.fits, sur, variant))
        result["wall_s"] = round(time.perf_counter() - t0, 1)
        write_json(result, args.out)
        s = result["sizes"][-1]["summary"]
        print(f"{n} cases: factor 2 {s['factor2_fraction']['mean']:.3f} "
              f"± {s['factor2_fraction']['std']:.3f}, rmse {s['rmse']['mean']:.3f} "
              f"± {s['rmse']['std']:.3f} ({result['wall_s']:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
