"""Calibration and training cases of the served gradient boosting, measured at research scale.

Reads a research-scale run (read-only): its ``params.yaml`` surrogate
section, its training dataset (``data/dataset/damage.parquet``) and its
held-out design (``data/heldout/dataset/damage.parquet``). The case split is
the one :meth:`drillfatigue.surrogate.Surrogate.fit` makes
(:func:`drillfatigue.surrogate.data.split_by_case`); the preprocessor is fitted
on its train cases, as the ensemble's is. Per variant, the served gradient
boosting is fitted and calibrated by the library's one procedure
(:func:`drillfatigue.surrogate.served_gbm.fit_served_gbm` on the rows of
:func:`drillfatigue.surrogate.data.gbm_rows`) and scored on every held-out row
with :func:`drillfatigue.surrogate.evaluation.deciding_metrics` (the rows
whose predicted life is within the horizon):

- ``split_train60``: split conformal on the calibration cases, trained on the
  train cases only (the served model before cross-conformal calibration);
- ``split_free``: split conformal, trained on the train and test cases;
- ``cross_free`` (the defaults): cross-conformal by case over every case,
  trained on every case;
- ``cross_free_iter1000`` / ``cross_free_k10``: the same with the tree cap
  raised from 300 to 1000, or 10 folds;
- ``cross_free_per_decade`` / ``cross_free_scaled`` / ``cross_free_scaled_k10``:
  cross-conformal over every case with one width per decade, or with the
  width scaled by the scale model (``surrogate.gbm_interval``), on 5 folds,
  and scaled on 10 folds (the library's default ``conformal_folds``).

A variant that names no ``conformal_folds`` takes the research run's.

Then, for ``cross_free``, the half-width per bin of the prediction from
the out-of-fold residuals of all cases and of each part of the split alone
(``cross_quantile_by_split_part``: how much the width depends on which
cases calibrate it).

Reported per variant: fit time, trees kept, training / calibration cases and
rows; on the deciding rows factor 2, RMSE, coverage and mean width; coverage,
factor 2 and width per decade of the simulated and of the predicted rate;
governing rate per case and component type (factor 2, RMSE, per type);
"beyond the horizon" precision and recall; all held-out rows (R², RMSE,
coverage, width). Coverages carry their standard error over the held-out
cases (``coverage_se_cases``: rows of a case share its errors, so the case is
the sampling unit) and ``coverage_censored`` (a row simulated beyond the
horizon counts as covered once the interval reaches down to it, as the
calibration scores it).

Usage: ``python benchmarks/surrogate_calibration.py [--research /work/research]
[--out benchmarks/results/surrogate_calibration.json] [--variants a,b]``
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from drillfatigue.config.base import validate
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.metrics import decade_label
from drillfatigue.numba_cache import scope_numba_cache
from drillfatigue.surrogate.conformal import conformal_quantile
from drillfatigue.surrogate.data import (case_folds, gbm_rows, log10_target, read_dataset,
                                         split_by_case)
from drillfatigue.surrogate.evaluation import deciding_metrics, score
from drillfatigue.surrogate.gbm import design_matrix, fit_gbm, monotone_constraints
from drillfatigue.surrogate.io import write_json
from drillfatigue.surrogate.model import Preprocessor
from drillfatigue.surrogate.served_gbm import (fit_served_gbm, half_width, interval_bins,
                                               interval_scale, out_of_fold_predictions)

RESULT = Path(__file__).parent / "results" / "surrogate_calibration.json"
#: name -> overrides of the research run's surrogate section
VARIANTS: dict[str, dict[str, Any]] = {
    "split_train60": {"gbm_calibration": "split", "gbm_cases": "train"},
    "split_free": {"gbm_calibration": "split", "gbm_cases": "free"},
    "cross_free": {"gbm_calibration": "cross", "gbm_cases": "free"},
    "cross_free_iter1000": {"gbm_calibration": "cross", "gbm_cases": "free",
                            "hgb_max_iter": 1000},
    "cross_free_k10": {"gbm_calibration": "cross", "gbm_cases": "free", "conformal_folds": 10},
    "cross_free_per_decade": {"gbm_calibration": "cross", "gbm_cases": "free",
                              "gbm_interval": "per_decade", "conformal_folds": 5},
    "cross_free_scaled": {"gbm_calibration": "cross", "gbm_cases": "free",
                          "gbm_interval": "scaled", "conformal_folds": 5},
    "cross_free_scaled_k10": {"gbm_calibration": "cross", "gbm_cases": "free",
                              "gbm_interval": "scaled", "conformal_folds": 10},
}
_ROW_COLUMNS = ("well.profile", "component_type", "location", "s_from_bit_m", "operation.rpm")
#: bands of rpm of the coverage breakdown: full stick-slip below ~110 rpm, both states above
RPM_BANDS = (0.0, 110.0, 140.0, 160.0, 1e9)


def coverage_by(pred: pd.DataFrame, within: np.ndarray, covered: np.ndarray,
                width: np.ndarray, key: pd.Series) -> dict[str, Any]:
    """Coverage (a censored row counted as the calibration counts it), its standard error
    over cases and the mean width of the deciding rows, per value of ``key``."""
    out: dict[str, Any] = {}
    k = key.astype(str).to_numpy()
    for v in sorted(set(k[within])):
        sel = within & (k == v)
        out[v] = {"rows": int(sel.sum()), "cases": int(pred["case_id"][sel].nunique()),
                  "coverage": float(np.mean(covered[sel])),
                  "coverage_se_cases": coverage_se_by_case(covered[sel],
                                                           pred["case_id"].to_numpy()[sel]),
                  "mean_width": float(np.mean(width[sel]))}
    return out


def _slim(d: dict[str, Any]) -> dict[str, Any]:
    """Per-decade entries without MAE (the table reads factor 2, coverage, width)."""
    return {k: {kk: v for kk, v in row.items() if kk != "mae"} for k, row in d.items()}


def coverage_se_by_case(covered: np.ndarray, cases: np.ndarray) -> float:
    """Standard error of a coverage fraction over cases (rows of a case are correlated).

    The fraction is a ratio of per-case sums, sum_c k_c / sum_c n_c; its
    linearised (cluster-robust) variance is C / (C - 1) sum_c (k_c - p n_c)^2
    / (sum_c n_c)^2 over the C cases (Cochran, Sampling Techniques, 3rd ed.,
    sec. 6.4, ratio estimator).
    """
    if covered.size == 0:
        return float("nan")
    frame = pd.DataFrame({"k": covered.astype(float), "c": cases})
    per = frame.groupby("c")["k"].agg(["sum", "size"])
    n_c = per.shape[0]
    if n_c < 2:
        return float("nan")
    p = per["sum"].sum() / per["size"].sum()
    var = n_c / (n_c - 1) * np.sum((per["sum"] - p * per["size"]) ** 2) / per["size"].sum() ** 2
    return float(np.sqrt(var))


def _add_case_se(d: dict[str, Any], pred: pd.DataFrame, key: str, c: float) -> None:
    """Add ``coverage_se_cases`` and ``n_cases`` per decade of ``key`` (rows within horizon)."""
    y, mu = pred["y_true"].to_numpy(), pred["hgb"].to_numpy()
    cov = (y >= pred["hgb_lower"].to_numpy()) & (y <= pred["hgb_upper"].to_numpy())
    within = mu >= c
    ref = y if key == "by_decade" else mu
    label = decade_label(ref)
    cases = pred["case_id"].to_numpy()
    for k, row in d[key].items():
        sel = within & (label == k)
        row["coverage_se_cases"] = coverage_se_by_case(cov[sel], cases[sel])
        row["n_cases"] = int(np.unique(cases[sel]).size)


def run_variant(cfg: SurrogateConfig, frame: pd.DataFrame, held: pd.DataFrame,
                pre: Preprocessor) -> dict[str, Any]:
    """Fit, calibrate and score one variant on the held-out design."""
    y = log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    groups = frame[cfg.group_column].to_numpy()
    split = split_by_case(groups, cfg)
    fit, cal = gbm_rows(split, cfg, heldout=True)
    x = design_matrix(pre, pre.numeric_array(frame), pre.category_codes(frame))
    t0 = time.perf_counter()
    model, meta = fit_served_gbm(x, y, groups, fit, cal, cfg, monotone_constraints(pre))
    fit_s = time.perf_counter() - t0
    x_h = design_matrix(pre, pre.numeric_array(held), pre.category_codes(held))
    y_h = log10_target(held[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    mu = model.predict(x_h)
    half = np.broadcast_to(half_width(mu, meta, interval_bins(meta), interval_scale(model, x_h)),
                           mu.shape)
    pred = pd.DataFrame({"case_id": held[cfg.group_column].astype(str).to_numpy(),
                         "y_true": y_h, "hgb": mu, "hgb_lower": mu - half,
                         "hgb_upper": mu + half})
    for col in _ROW_COLUMNS:
        if col in held.columns:
            pred[col] = held[col].to_numpy()
    d = deciding_metrics(pred, ("hgb",), cfg.horizon_h)["hgb"]
    level = -math.log10(cfg.horizon_h)
    for key in ("by_decade", "by_predicted_decade"):
        _add_case_se(d, pred, key, level)
    within = mu >= level
    cov = (y_h >= mu - half) & (y_h <= mu + half)
    d["rows"]["coverage_se_cases"] = coverage_se_by_case(
        cov[within], pred["case_id"].to_numpy()[within])
    cov_c = cov | ((y_h <= level) & (mu - half <= level))
    breakdown = {"rpm_band": pd.cut(pred["operation.rpm"], RPM_BANDS).astype(str),
                 "profile": pred["well.profile"], "component_type": pred["component_type"]}
    coverage_breakdown = {name: coverage_by(pred, within, cov_c, 2.0 * half, key)
                          for name, key in breakdown.items()}
    gov = d["governing"]
    return {
        "fit_s": round(fit_s, 2), "n_iter": meta["n_iter"], "hgb_max_iter": cfg.hgb_max_iter,
        "calibration": meta["calibration"], "conformal_folds": meta.get("conformal_folds"),
        "n_train_cases": len(meta["train_cases"]), "n_train_rows": meta["n_train_rows"],
        "n_calibration_cases": meta["n_calibration_cases"],
        "n_calibration_rows": meta["n_calibration_rows"],
        "conformal_bins_log10": meta.get("conformal_bins_log10"),
        "conformal_half_widths": meta.get("conformal_half_widths"),
        "all_rows": score(y_h, mu, mu - half, mu + half),
        "deciding_rows": d["rows"],
        "by_decade": _slim(d["by_decade"]),
        "by_predicted_decade": _slim(d["by_predicted_decade"]),
        "governing": {k: gov[k] for k in ("n", "rmse", "factor2_fraction",
                                          "same_location_fraction")}
        | {"by_component_type": gov["by_component_type"]},
        "beyond_horizon": d["beyond_horizon"],
        "coverage_censored_by": coverage_breakdown,
    }


def quantile_by_split_part(cfg: SurrogateConfig, frame: pd.DataFrame,
                           pre: Preprocessor) -> dict[str, Any]:
    """The cross-conformal quantile per bin, from the out-of-fold residuals of each part.

    The same out-of-fold predictions (``cross_free``: 5 folds over all
    cases); per unit bin of the prediction from the horizon up, the
    conformal quantile (``cfg.coverage``, censored rows scored as in the
    calibration) of the residuals of all cases and of the split's train,
    calibration and test cases alone: how much the half-width depends on
    which cases calibrate it.
    """
    y = log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    g = frame[cfg.group_column].astype(str).to_numpy()
    split = split_by_case(g, cfg)
    x = design_matrix(pre, pre.numeric_array(frame), pre.category_codes(frame))
    model, _ = fit_gbm(x, y, g, cfg, monotone_constraints(pre))
    mu = out_of_fold_predictions(model, x, y, case_folds(g, cfg.conformal_folds, cfg.split_seed))
    level = -math.log10(cfg.horizon_h)
    score_ = np.abs(y - mu)
    cens = y <= level
    score_[cens] = np.maximum(mu[cens] - level, 0.0)
    parts = {"all": np.ones(y.size, bool), "train": split.train,
             "calibration": split.calibration, "test": split.test}
    out: dict[str, Any] = {}
    for lo in range(math.floor(level), math.floor(mu.max()) + 1):
        b = (mu >= lo) & (mu < lo + 1)
        if b.sum() < cfg.conformal_bin_min_rows:
            continue
        out[decade_label(np.array([float(lo)]))[0]] = {
            name: {"half_width": conformal_quantile(score_[b & m], cfg.coverage),
                   "n_rows": int((b & m).sum()), "n_cases": int(np.unique(g[b & m]).size)}
            for name, m in parts.items() if (b & m).sum() >= cfg.conformal_bin_min_rows}
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--research", default="/work/research")
    parser.add_argument("--out", default=str(RESULT))
    parser.add_argument("--variants", default=",".join(VARIANTS))
    parser.add_argument("--no-parts", action="store_true",
                        help="skip the half-widths by part of the split")
    args = parser.parse_args(argv)
    scope_numba_cache()
    root = Path(args.research)
    section = yaml.safe_load((root / "params.yaml").read_text(encoding="utf-8"))["surrogate"]
    base = validate(SurrogateConfig, section, "surrogate")
    frame = read_dataset(root / "data" / "dataset" / "damage.parquet")
    held = read_dataset(root / "data" / "heldout" / "dataset" / "damage.parquet")
    split = split_by_case(frame[base.group_column].to_numpy(), base)
    pre = Preprocessor(base.features, base.categorical).fit(frame.loc[split.train])
    result: dict[str, Any] = {
        "research": str(root), "n_cases": int(frame[base.group_column].nunique()),
        "n_rows": int(len(frame)), "n_heldout_cases": int(held[base.group_column].nunique()),
        "n_heldout_rows": int(len(held)), "coverage_nominal": base.coverage,
        "horizon_h": base.horizon_h, "machine": platform.machine(),
        "python": platform.python_version(), "variants": {}}
    for name in args.variants.split(","):
        cfg = base.model_copy(update=VARIANTS[name])
        res = run_variant(validate(SurrogateConfig, cfg.model_dump(), "surrogate"), frame, held,
                          pre)
        result["variants"][name] = res
        r = res["deciding_rows"]
        print(f"{name:22s} fit {res['fit_s']:6.1f} s  trees {res['n_iter']:4d}  cases "
              f"{res['n_train_cases']}/{res['n_calibration_cases']}  deciding: f2 "
              f"{r['factor2_fraction']:.3f} rmse {r['rmse']:.3f} cov {r['coverage']:.3f} "
              f"width {r['mean_width']:.3f}  governing f2 "
              f"{res['governing']['factor2_fraction']:.3f}  beyond precision "
              f"{res['beyond_horizon']['precision']:.3f}", flush=True)
        write_json(result, args.out)
    if not args.no_parts:
        cfg = base.model_copy(update=VARIANTS["cross_free"])
        result["cross_quantile_by_split_part"] = quantile_by_split_part(cfg, frame, pre)
        write_json(result, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
