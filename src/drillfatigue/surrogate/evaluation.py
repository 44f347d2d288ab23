"""Scoring of the surrogate against baselines on the same case-wise split.

Baselines, trained on the same training cases and calibrated on the same
calibration cases as the ensemble, scored on the same test cases:

- **Gaussian process** (scikit-learn ``GaussianProcessRegressor``, constant x
  anisotropic RBF + white noise, ``normalize_y``): exact GP cost grows as n^3,
  so it is fitted on a seeded subsample of at most ``gp_max_rows`` (<= 2000)
  training rows. Intervals: the GP standard deviation conformalised like the
  ensemble's (normalised scores on the calibration set).
- **HistGradientBoosting** (``HistGradientBoostingRegressor``, squared error,
  native categorical support via one-hot inputs): intervals from split
  conformal prediction on absolute residuals (constant width).

All models see the same inputs: standardised numeric features and one-hot
categorical levels (the ensemble's fitted :class:`Preprocessor`).

Metrics on log10 damage rate per hour (test rows): R^2, RMSE, MAE (decades),
interval coverage and mean width (decades), and the fraction of rows whose
predicted damage is within a factor of 2 of the simulated one
(|log10 pred - log10 true| <= log10 2).

Where it counts (:func:`governing_metrics`): a string's life is set by its most
damaged component, so the same errors are also scored on each test case's
governing damage rate (largest over its rows, simulated vs predicted, whichever
rows they are) and on the rows whose simulated life is at most
``surrogate.relevant_life_h`` (default 1e5 h of operation: a component that
lasts longer does not limit any plan).
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from sklearn.ensemble import HistGradientBoostingRegressor
from sklearn.exceptions import ConvergenceWarning
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.metrics import factor2_by_decade
from drillfatigue.plotting import subplots
from drillfatigue.surrogate.conformal import SplitConformal, conformal_quantile
from drillfatigue.surrogate.data import Split, check_columns, log10_target
from drillfatigue.surrogate.facade import Surrogate
from drillfatigue.surrogate.io import save_figure

LOG10_2 = math.log10(2.0)


def score(y: np.ndarray, mu: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> dict[str, float]:
    """Regression and interval metrics on log10 damage rate (all arrays shape (n,))."""
    y, mu, lower, upper = (np.asarray(a, dtype=np.float64) for a in (y, mu, lower, upper))
    err = mu - y
    ss_res = float(np.sum(err**2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    return {
        "r2": 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"),
        "rmse": float(np.sqrt(np.mean(err**2))),
        "mae": float(np.mean(np.abs(err))),
        "coverage": float(np.mean((y >= lower) & (y <= upper))),
        "mean_width": float(np.mean(upper - lower)),
        "factor2_fraction": float(np.mean(np.abs(err) <= LOG10_2)),
        "n": int(y.size),
    }


def split_from_model(frame: pd.DataFrame, model: Surrogate, cfg: SurrogateConfig) -> Split:
    """The split the model was trained with (case ids stored in its metadata)."""
    g = frame[cfg.group_column].astype(str).to_numpy()
    sp = model.metadata["split"]
    return Split(train=np.isin(g, sp["train_cases"]), calibration=np.isin(g, sp["calibration_cases"]),
                 test=np.isin(g, sp["test_cases"]))


def _design(model: Surrogate, frame: pd.DataFrame) -> np.ndarray:
    x_num, x_cat = model.encode(frame)
    p = model.preprocessor
    z = (x_num - p.mean_) / p.scale_
    blocks = [z]
    for j, col in enumerate(p.categorical):
        blocks.append((x_cat[:, j:j + 1] == np.arange(len(p.categories_[col]))).astype(float))
    return np.hstack(blocks)


def evaluate(frame: pd.DataFrame, model: Surrogate, cfg: SurrogateConfig,
             baselines: bool = True) -> tuple[dict[str, Any], pd.DataFrame]:
    """Score the ensemble (and the baselines) on the model's test cases.

    Returns
    -------
    metrics : dict
        Per model ("ensemble", "gp", "hgb") the :func:`score` dict, plus
        dataset facts (test rows/cases, censored fraction, OOD fraction).
    predictions : DataFrame
        Test rows: case id, y_true and per model the prediction and interval
        (log10 damage rate per hour), the ensemble's OOD flag.
    """
    check_columns(frame, cfg)
    y = log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    sp = split_from_model(frame, model, cfg)
    if not sp.test.any():
        raise InputError(cfg.group_column, "no test case of the model in the dataset",
                         "the dataset the model was trained on")
    test = frame.loc[sp.test]
    y_te = y[sp.test]
    pred = model.predict(test)
    metrics: dict[str, Any] = {
        "coverage_nominal": model.coverage,
        "criterion": cfg.criterion,
        "n_test_rows": int(sp.test.sum()),
        "n_test_cases": int(test[cfg.group_column].nunique()),
        "censored_fraction_test": float(np.mean(y_te <= math.log10(cfg.rate_floor_per_h))),
        "ood_fraction_test": float(pred["ood"].mean()),
    }
    out = pd.DataFrame({"case_id": test[cfg.group_column].to_numpy(), "y_true": y_te})
    mu = pred["log10_damage_rate_per_h"].to_numpy()
    lo = pred["log10_damage_rate_per_h_lower"].to_numpy()
    hi = pred["log10_damage_rate_per_h_upper"].to_numpy()
    metrics["ensemble"] = score(y_te, mu, lo, hi)
    ind = ~pred["ood"].to_numpy()
    if ind.any():
        metrics["ensemble_in_domain"] = score(y_te[ind], mu[ind], lo[ind], hi[ind])
    out["ensemble"], out["ensemble_lower"], out["ensemble_upper"] = mu, lo, hi
    out["ensemble_ood"] = ~ind
    if not baselines:
        return metrics, out

    x_tr = _design(model, frame.loc[sp.train])
    x_ca = _design(model, frame.loc[sp.calibration])
    x_te = _design(model, test)
    y_tr, y_ca = y[sp.train], y[sp.calibration]

    # Gaussian process on a subsample
    rng = np.random.default_rng(cfg.split_seed)
    n_gp = min(cfg.gp_max_rows, x_tr.shape[0])
    sub = np.sort(rng.choice(x_tr.shape[0], n_gp, replace=False))
    d = x_tr.shape[1]
    kernel = (ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.ones(d), (1e-2, 1e3))
              + WhiteKernel(1e-2, (1e-6, 1.0)))
    gp = GaussianProcessRegressor(kernel, normalize_y=True, random_state=cfg.split_seed,
                                  n_restarts_optimizer=0)
    with warnings.catch_warnings():
        # a length scale at its upper bound means an irrelevant input: expected, not a fault
        warnings.simplefilter("ignore", ConvergenceWarning)
        gp.fit(x_tr[sub], y_tr[sub])
    mu_c, sd_c = gp.predict(x_ca, return_std=True)
    conf = SplitConformal(model.coverage).fit(mu_c, np.maximum(sd_c, 1e-9), y_ca)
    mu_t, sd_t = gp.predict(x_te, return_std=True)
    lo_t, hi_t = conf.interval(mu_t, np.maximum(sd_t, 1e-9))
    metrics["gp"] = score(y_te, mu_t, lo_t, hi_t) | {"train_rows": int(n_gp)}
    out["gp"], out["gp_lower"], out["gp_upper"] = mu_t, lo_t, hi_t

    # gradient boosting, conformalised absolute residuals
    hgb = HistGradientBoostingRegressor(max_iter=cfg.hgb_max_iter, random_state=cfg.split_seed,
                                        early_stopping=True, validation_fraction=cfg.validation_fraction)
    hgb.fit(x_tr, y_tr)
    q = conformal_quantile(np.abs(y_ca - hgb.predict(x_ca)), model.coverage)
    mu_h = hgb.predict(x_te)
    metrics["hgb"] = score(y_te, mu_h, mu_h - q, mu_h + q) | {"train_rows": int(x_tr.shape[0])}
    out["hgb"], out["hgb_lower"], out["hgb_upper"] = mu_h, mu_h - q, mu_h + q
    best = min(("ensemble", "gp", "hgb"), key=lambda k: metrics[k]["rmse"])
    metrics["best_rmse_model"] = best
    metrics["governing"] = governing_metrics(out, relevant_life_h=cfg.relevant_life_h)
    return metrics, out


def governing_metrics(pred: pd.DataFrame, models: tuple[str, ...] = ("ensemble", "gp", "hgb"),
                      relevant_life_h: float = 1e5) -> dict[str, Any]:
    """Errors where they decide the string's life.

    Parameters
    ----------
    pred : DataFrame
        Test rows as returned by :func:`evaluate`: ``case_id``, ``y_true`` and
        one column per model (log10 damage rate per hour).
    models : tuple of str
        Model columns to score (missing ones are skipped).
    relevant_life_h : float
        Rows whose simulated life 1/rate is at most this (h, > 0) are relevant.

    Returns
    -------
    dict
        ``n_cases``, ``n_relevant_rows``, ``relevant_life_h``; per model
        ``case_max`` (RMSE, MAE and factor-2 fraction of the per-case maximum
        of the prediction against the per-case maximum of the simulation, one
        value per case), ``relevant_rows`` (the same on the relevant rows;
        NaN when there is none) and ``factor2_by_decade`` (factor-2 fraction
        per decade of the simulated rate,
        :func:`drillfatigue.metrics.factor2_by_decade`).
    """
    if not relevant_life_h > 0:
        raise ValueError(f"relevant_life_h must be > 0, got {relevant_life_h}")
    case = pred["case_id"].to_numpy()
    y = pred["y_true"].to_numpy(dtype=np.float64)
    rel = y >= -math.log10(relevant_life_h)
    out: dict[str, Any] = {"n_cases": int(pd.unique(case).size), "n_relevant_rows": int(rel.sum()),
                           "relevant_life_h": float(relevant_life_h)}

    def errs(e: np.ndarray) -> dict[str, float]:
        if e.size == 0:
            return {"rmse": float("nan"), "mae": float("nan"), "factor2_fraction": float("nan"),
                    "n": 0}
        return {"rmse": float(np.sqrt(np.mean(e**2))), "mae": float(np.mean(np.abs(e))),
                "factor2_fraction": float(np.mean(np.abs(e) <= LOG10_2)), "n": int(e.size)}

    for m in models:
        if m not in pred:
            continue
        mu = pred[m].to_numpy(dtype=np.float64)
        by = pd.DataFrame({"y": y, "mu": mu}).groupby(case).max()
        out[m] = {"case_max": errs((by["mu"] - by["y"]).to_numpy()),
                  "relevant_rows": errs(mu[rel] - y[rel]),
                  "factor2_by_decade": factor2_by_decade(y, mu - y)}
    return out


def read_spread(path: str | Path, criterion: str) -> dict[str, Any]:
    """Read the replicates stage's ``spread.json`` for a model of ``criterion``.

    Raises
    ------
    InputError
        ``--noise-floor`` when the file is missing or measured another criterion.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError("--noise-floor", f"{path} not found",
                         "the spread.json written by the replicates stage")
    spread = json.loads(path.read_text(encoding="utf-8"))
    if spread.get("criterion", criterion) != criterion:
        raise InputError("--noise-floor", f"replicates measured criterion "
                         f"{spread.get('criterion')!r}, the model {criterion!r}",
                         "the same criterion (surrogate.criterion)")
    return spread


def noise_floor_metrics(spread: dict[str, Any], y_test: np.ndarray,
                        metrics: dict[str, Any]) -> dict[str, Any]:
    """What no estimator can beat on this data, beside what each model reached.

    Parameters
    ----------
    spread : dict
        ``spread.json`` of the replicates stage
        (:func:`drillfatigue.sweep.replicates.replicate_spread`): pooled
        replicate sigma of log10 damage rate (decades) and the factor-of-2
        ceiling measured on the replicated rows.
    y_test : array
        Test targets (log10 damage rate per hour) of the evaluation.
    metrics : dict
        The :func:`evaluate` metrics (per model ``rmse``).

    Returns
    -------
    dict
        ``sigma_log10``; ``ceiling_r2_test`` = 1 - sigma^2 / var(y_test);
        ``ceiling_factor2_fraction``; per model ``excess_rmse`` =
        sqrt(max(rmse^2 - sigma^2, 0)), the part of the error a better
        estimator could still remove; the study's settings; ``by_decade``
        when the spread has ``ceiling_factor2_by_decade``: per decade of
        damage rate the ceiling and its replicated rows beside each model's
        factor-2 fraction and test rows (from ``metrics["governing"]``; a
        decade missing on one side has None there).
    """
    sigma = float(spread.get("sigma_log10", float("nan")))
    var_y = float(np.var(y_test, ddof=1)) if len(y_test) > 1 else float("nan")
    out: dict[str, Any] = {
        "sigma_log10": sigma,
        "ceiling_r2_test": float(1.0 - sigma**2 / var_y) if var_y > 0 else float("nan"),
        "ceiling_factor2_fraction": float(spread.get("ceiling_factor2_fraction", float("nan"))),
        "n_cases": int(spread.get("n_cases", 0)),
        "n_replicates": int(spread.get("n_replicates", 0)),
        "variable": spread.get("variable"), "rel_step": spread.get("rel_step"),
    }
    for m in ("ensemble", "gp", "hgb"):
        if m in metrics and "rmse" in metrics[m]:
            out[f"excess_rmse_{m}"] = float(math.sqrt(max(metrics[m]["rmse"] ** 2 - sigma**2, 0.0)))
    ceil = spread.get("ceiling_factor2_by_decade")
    if ceil:
        gov = metrics.get("governing", {})
        models = [m for m in ("ensemble", "gp", "hgb") if "factor2_by_decade" in gov.get(m, {})]
        keys = set(ceil)
        for m in models:
            keys |= set(gov[m]["factor2_by_decade"])
        table: dict[str, dict[str, Any]] = {}
        for key in sorted(keys, key=float):
            c = ceil.get(key)
            row: dict[str, Any] = {"ceiling_factor2": c["factor2_fraction"] if c else None,
                                   "n_replicate_rows": c["n"] if c else 0, "n_test_rows": 0}
            for m in models:  # all models are scored on the same test rows
                f = gov[m]["factor2_by_decade"].get(key)
                row[m] = f["factor2_fraction"] if f else None
                if f:
                    row["n_test_rows"] = f["n"]
            table[key] = row
        out["by_decade"] = table
    return out


def plot_parity(pred: pd.DataFrame, path: str, models: tuple[str, ...] = ("ensemble", "gp", "hgb")) -> None:
    """Predicted vs simulated log10 damage rate, one panel per model (PNG)."""
    models = tuple(m for m in models if m in pred.columns)
    fig, axes = subplots(1, len(models), figsize=(4.2 * len(models), 4), squeeze=False)
    y = pred["y_true"].to_numpy()
    lim = (float(np.min(y)) - 0.5, float(np.max(y)) + 0.5)
    for ax, m in zip(axes[0], models, strict=False):
        ax.plot(lim, lim, "k-", lw=1)
        ax.fill_between(lim, np.array(lim) - LOG10_2, np.array(lim) + LOG10_2, color="0.85",
                        label="factor 2")
        ax.plot(y, pred[m], ".", ms=3, alpha=0.6)
        ax.set_xlim(lim)
        ax.set_ylim(lim)
        ax.set_title(m)
        ax.set_xlabel("simulated log10 damage rate (1/h)")
        ax.set_ylabel("predicted log10 damage rate (1/h)")
        ax.legend(loc="upper left")
    fig.tight_layout()
    save_figure(fig, path)


def plot_residuals(pred: pd.DataFrame, path: str,
                   models: tuple[str, ...] = ("ensemble", "gp", "hgb")) -> None:
    """Residual (predicted - simulated) vs predicted log10 damage rate (PNG)."""
    models = tuple(m for m in models if m in pred.columns)
    fig, ax = subplots(figsize=(7, 4))
    for m in models:
        ax.plot(pred[m], pred[m] - pred["y_true"], ".", ms=3, alpha=0.5, label=m)
    ax.axhline(0.0, color="k", lw=1)
    for s in (-LOG10_2, LOG10_2):
        ax.axhline(s, color="0.5", lw=1, ls="--")
    ax.set_xlabel("predicted log10 damage rate (1/h)")
    ax.set_ylabel("residual (decades)")
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path)
