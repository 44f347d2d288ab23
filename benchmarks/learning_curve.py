"""Learning curve: held-out accuracy of the served model against the number of simulations,
Sobol design alone against the adaptive design (``sweep.method: adaptive``).

A cheap configuration of the default sweep's physics: ``params.yaml``'s
base case, string, variables, rig boundaries and fatigue chain, with a fixed
short window (``--window-s``, 3 s ramp included) instead of the converged one.
Per repeat ``k`` (``--repeats``):

- training designs of seed ``sweep.seed + k``: Sobol with ``--n-max`` cases
  (its first ``n`` cases are the Sobol design at ``n``; the first points of
  the sequence when ``n`` is not a power of two), and adaptive
  (``--n-initial`` Sobol cases of the same seed, then batches of ``--batch``
  chosen from pools of ``--candidates``, adaptive seed
  ``sweep.adaptive.seed + k``) up to ``--n-max``;
- a held-out Sobol design of seed ``heldout.seed + k`` (``--heldout`` cases,
  those shared with a training design left out);
- every case simulated and evaluated once with the stages' code
  (:func:`drillfatigue.sweep.stages.adaptive_targets`, one cache per
  repeat: the adaptive and Sobol designs share their first cases);
- at each size ``n`` the served model (gradient boosting,
  :func:`drillfatigue.surrogate.gbm.fit_gbm`: early stopping on whole cases,
  monotone in dogleg, censored at ``surrogate.horizon_h``) is fitted on all
  rows of the first ``n`` cases and scored on the held-out rows that decide
  life (:func:`drillfatigue.surrogate.evaluation.deciding_metrics`: rows whose
  predicted life is within the horizon): factor-2 fraction and RMSE in
  decades of the damage rate, and the precision of the "beyond the horizon"
  answers.

The ratio reported, per metric (also the factor-2 fraction and RMSE of the
governing rate per case and component type, the acquisition's target): the
number of simulations the adaptive design needs to reach the Sobol design's
accuracy at ``--n-max`` (first size where its curve,
averaged over the repeats, is at least as good; linear interpolation between
sizes), over ``--n-max``; ``null`` when the adaptive curve never reaches it.

Usage: ``python benchmarks/learning_curve.py [--repeats 1] [--n-max 48] [--n-initial 16]
[--batch 8] [--heldout 24] [--window-s 8] [--cache DIR]`` ->
``benchmarks/results/learning_curve.json`` (rewritten after each repeat; ``--keep``
keeps the repeats already there and runs the rest).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.config import load_params
from drillfatigue.numba_cache import scope_numba_cache
from drillfatigue.surrogate.data import log10_target
from drillfatigue.surrogate.evaluation import deciding_metrics
from drillfatigue.surrogate.gbm import design_matrix, fit_gbm, monotone_constraints
from drillfatigue.surrogate.io import write_json
from drillfatigue.surrogate.model import Preprocessor
from drillfatigue.sweep.adaptive import adaptive_design
from drillfatigue.sweep.dataset import build_dataset
from drillfatigue.sweep.design import base_case_from_params, design_cases
from drillfatigue.sweep.stages import adaptive_targets

ROOT = Path(__file__).resolve().parents[1]
RESULT = Path(__file__).parent / "results" / "learning_curve.json"
#: (metric, +1 if higher is better): on the deciding rows, then on the governing rate per
#: case and component type (the acquisition's target)
METRICS = (("factor2_fraction", +1), ("rmse", -1), ("governing_factor2_fraction", +1),
           ("governing_rmse", -1))


def _params(args: argparse.Namespace, k: int, cache: Path) -> Any:
    params = load_params(ROOT / "params.yaml")
    sw = params.sweep
    ad = sw.adaptive.model_copy(update={
        "n_initial": args.n_initial, "batch_size": args.batch, "candidates": args.candidates,
        "seed": sw.adaptive.seed + k, "cache_dir": str(cache / f"repeat_{k}")})
    sweep = sw.model_copy(update={
        "method": "adaptive", "n_cases": args.n_max, "seed": sw.seed + k,
        "window_s": args.window_s, "window": sw.window.model_copy(update={"mode": "fixed"}),
        "scheduler": "serial", "n_workers": 1, "adaptive": ad})
    return params.model_copy(update={"sweep": sweep})


def fit_served(train: pd.DataFrame, cfg: Any) -> tuple[Any, dict[str, Any]]:
    """The served model (``fit_gbm`` on the surrogate's encoding) fitted on every row of
    ``train``: its ``predict(frame) -> log10 rate`` and the fit's info."""
    pre = Preprocessor(cfg.features, cfg.categorical).fit(train)

    def x_of(f: pd.DataFrame) -> np.ndarray:
        return design_matrix(pre, pre.numeric_array(f), pre.category_codes(f))

    y = log10_target(train[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    model, info = fit_gbm(x_of(train), y, train[cfg.group_column].astype(str).to_numpy(), cfg,
                          monotone_constraints(pre))
    return (lambda f: model.predict(x_of(f))), info


def heldout_predictions(test: pd.DataFrame, mu: np.ndarray, cfg: Any) -> pd.DataFrame:
    """The held-out rows with the prediction ``mu`` as :func:`deciding_metrics` reads them."""
    pred = pd.DataFrame({"case_id": test[cfg.group_column].astype(str).to_numpy(),
                         "y_true": log10_target(test[cfg.target_column].to_numpy(),
                                                cfg.rate_floor_per_h),
                         "hgb": mu, "hgb_lower": mu, "hgb_upper": mu})
    for col in ("well.profile", "component_type", "location", "s_from_bit_m"):
        if col in test.columns:
            pred[col] = test[col].to_numpy()
    return pred


def deciding_scores(pred: pd.DataFrame, horizon_h: float) -> dict[str, float]:
    """Factor 2, RMSE and precision on the deciding rows, and the governing errors."""
    dec = deciding_metrics(pred, ("hgb",), horizon_h)["hgb"]
    return {"factor2_fraction": dec["rows"]["factor2_fraction"], "rmse": dec["rows"]["rmse"],
            "n_rows_deciding": dec["rows"]["n"],
            "beyond_horizon_precision": dec["beyond_horizon"]["precision"],
            "governing_rmse": dec["governing"]["rmse"],
            "governing_factor2_fraction": dec["governing"]["factor2_fraction"]}


def _fit_score(rows: pd.DataFrame, train_ids: list[str], test: pd.DataFrame,
               cfg: Any) -> dict[str, Any]:
    train = rows[rows[cfg.group_column].isin(train_ids)]
    predict, info = fit_served(train, cfg)
    pred = heldout_predictions(test, predict(test), cfg)
    return {"n_cases": len(train_ids), "n_train_rows": int(len(train)), "n_iter": info["n_iter"],
            **deciding_scores(pred, cfg.horizon_h)}


def _sizes(n_initial: int, batch: int, n_max: int) -> list[int]:
    return list(range(n_initial, n_max, batch)) + [n_max]


def reach_ratio(sizes: list[int], curve: list[float], target: float, sign: int,
                n_ref: int) -> float | None:
    """Simulations (interpolated) at which ``curve`` first reaches ``target``, over ``n_ref``."""
    for i, (n, v) in enumerate(zip(sizes, curve, strict=True)):
        if sign * (v - target) >= 0.0:
            if i == 0:
                return n / n_ref
            n0, v0 = sizes[i - 1], curve[i - 1]
            return (n0 + (n - n0) * (target - v0) / (v - v0)) / n_ref
    return None


def run_repeat(args: argparse.Namespace, k: int, cache: Path) -> dict[str, Any]:
    params = _params(args, k, cache)
    cfg, sur = params.sweep, params.surrogate
    base = base_case_from_params(params)
    target = adaptive_targets(params)
    censor = -math.log10(sur.horizon_h) if sur.censoring == "likelihood" else None
    t0 = time.perf_counter()
    adaptive = adaptive_design(cfg, base, target, censor_log10=censor)
    t_adaptive = time.perf_counter() - t0
    # the first n_max points of the Sobol sequence (a power of two is a balanced design)
    sobol = design_cases(cfg.model_copy(update={"method": "sobol"}), base).head(args.n_max)
    target(sobol)
    held = design_cases(cfg.model_copy(update={"method": "sobol", "n_cases": args.heldout,
                                               "seed": params.heldout.seed + k}), base)
    held = held.head(args.heldout)
    held = held[~held["case_id"].isin(set(sobol["case_id"]) | set(adaptive["case_id"]))]
    target(held)
    t_sim = time.perf_counter() - t0
    cache_dir = Path(cfg.adaptive.cache_dir)
    every = pd.concat([adaptive.drop(columns=["round", "acquisition_score"]), sobol, held]
                      ).drop_duplicates("case_id")
    rows = build_dataset(every, cache_dir / "sweep", cache_dir / "fatigue")
    test = rows[rows["case_id"].isin(held["case_id"])]
    done = set(rows["case_id"])
    sizes = _sizes(args.n_initial, args.batch, args.n_max)
    curves: dict[str, list[dict[str, Any]]] = {}
    for name, frame in (("sobol", sobol), ("adaptive", adaptive)):
        ids = [c for c in frame["case_id"] if c in done]
        curves[name] = [_fit_score(rows, ids[:n], test, sur) for n in sizes]
    return {"repeat": k, "seed": cfg.seed, "adaptive_seed": cfg.adaptive.seed,
            "heldout_seed": params.heldout.seed + k, "n_heldout_cases": int(held["case_id"].size),
            "n_heldout_rows": int(len(test)), "n_simulated": len(done),
            "n_failed": int(len(every) - len(done)),
            "adaptive_rounds": [int(n) for n in adaptive["round"].value_counts().sort_index()],
            "adaptive_profiles": {str(k2): int(v) for k2, v in
                                  adaptive["well.profile"].value_counts().sort_index().items()},
            "sobol_profiles": {str(k2): int(v) for k2, v in
                               sobol["well.profile"].value_counts().sort_index().items()},
            "wall_s_adaptive_design": round(t_adaptive, 1),
            "wall_s_simulation": round(t_sim, 1),
            "wall_s_total": round(time.perf_counter() - t0, 1),
            "sizes": sizes, "curves": curves}


def summarise(repeats: list[dict[str, Any]], n_max: int) -> dict[str, Any]:
    sizes = repeats[0]["sizes"]
    out: dict[str, Any] = {"sizes": sizes}
    for metric, sign in METRICS:
        mean = {m: [float(np.mean([r["curves"][m][i][metric] for r in repeats]))
                    for i in range(len(sizes))] for m in ("sobol", "adaptive")}
        target = mean["sobol"][-1]
        ratio = reach_ratio(sizes, mean["adaptive"], target, sign, n_max)
        out[metric] = {"mean_curve": mean, "sobol_final": target,
                       "adaptive_final": mean["adaptive"][-1],
                       "ratio_adaptive_to_sobol": ratio,
                       "per_repeat_ratio": [reach_ratio(
                           sizes, [c[metric] for c in r["curves"]["adaptive"]],
                           r["curves"]["sobol"][-1][metric], sign, n_max) for r in repeats]}
    return out


def main(argv: list[str] | None = None) -> int:
    scope_numba_cache()  # before any kernel module is imported
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--n-max", type=int, default=48)
    ap.add_argument("--n-initial", type=int, default=16)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--candidates", type=int, default=1024)
    ap.add_argument("--heldout", type=int, default=24)
    ap.add_argument("--window-s", type=float, default=8.0)
    ap.add_argument("--cache", default=None, help="simulation cache (default: a temporary folder)")
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--keep", action="store_true",
                    help="keep the repeats already in --out (same settings) and run the rest")
    args = ap.parse_args(argv)
    cache = Path(args.cache) if args.cache else Path(tempfile.mkdtemp(prefix="learning_curve_"))
    result: dict[str, Any] = {
        "benchmark": "learning_curve", "python": platform.python_version(),
        "machine": platform.machine(), "settings": {
            k: v for k, v in vars(args).items() if k not in ("cache", "out", "keep")},
        "served_model": "gbm (fit_gbm on every row of the first n cases)",
        "metric": "held-out rows predicted within surrogate.horizon_h (deciding_metrics rows)",
        "repeats": []}
    t0 = time.perf_counter()
    if args.keep and Path(args.out).is_file():
        old = json.loads(Path(args.out).read_text(encoding="utf-8"))
        if old.get("settings") != result["settings"] | {"repeats": old["settings"]["repeats"]}:
            ap.error(f"--keep: {args.out} was run with other settings")
        result["repeats"] = old["repeats"][:args.repeats]
        t0 -= old.get("wall_s", 0.0)
    for k in range(len(result["repeats"]), args.repeats):
        result["repeats"].append(run_repeat(args, k, cache))
        result["summary"] = summarise(result["repeats"], args.n_max)
        result["wall_s"] = round(time.perf_counter() - t0, 1)
        write_json(result, args.out)
        s = result["summary"]
        print(f"repeat {k}: factor 2 sobol {s['factor2_fraction']['sobol_final']:.3f} "
              f"adaptive {s['factor2_fraction']['adaptive_final']:.3f}, ratio "
              f"{s['factor2_fraction']['ratio_adaptive_to_sobol']}; rmse sobol "
              f"{s['rmse']['sobol_final']:.3f} adaptive {s['rmse']['adaptive_final']:.3f}, "
              f"ratio {s['rmse']['ratio_adaptive_to_sobol']} ({result['wall_s']:.0f} s)",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
