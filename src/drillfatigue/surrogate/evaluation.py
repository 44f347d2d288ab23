"""Scoring of the surrogate against baselines on the same held-out cases.

The test cases are the model's test split, or every case of a held-out
dataset of its own design when one is given (``surrogate.heldout_path``).
Baselines, scored on the same test cases as the ensemble:

- **Gaussian process** (scikit-learn ``GaussianProcessRegressor``, constant x
  anisotropic RBF + white noise, ``normalize_y``): exact GP cost grows as n^3,
  so it is fitted on a seeded subsample of at most ``gp_max_rows`` (<= 2000)
  training rows. Intervals: the GP standard deviation conformalised like the
  ensemble's (normalised scores on the calibration set).
- **HistGradientBoosting** (``HistGradientBoostingRegressor``, squared error,
  one-hot categorical inputs, non-decreasing in the dogleg inputs
  :data:`drillfatigue.surrogate.gbm.MONOTONE_FEATURES`), early stopping on
  whole cases (:func:`drillfatigue.surrogate.gbm.fit_gbm`), trained and
  calibrated by the served gradient boosting's own procedure
  (:func:`drillfatigue.surrogate.served_gbm.fit_served_gbm` on the rows of
  :func:`drillfatigue.surrogate.data.gbm_rows`): by default on every case
  the evaluation does not score, its interval from the out-of-fold absolute
  residuals (cross-conformal by case, ``surrogate.gbm_calibration``), per bin
  of the predicted decade (Mondrian,
  :func:`drillfatigue.surrogate.conformal.mondrian_bins`) or one constant
  width (``surrogate.gbm_interval``). When the model's own test cases are
  scored, they are left out of its training (``hgb.same_cases_as_served``
  then says false when the served model trained on them).

All models see the same inputs: standardised numeric features and one-hot
categorical levels (the ensemble's fitted :class:`Preprocessor`).

Metrics on log10 damage rate per hour (test rows): R^2, RMSE, MAE (decades),
interval coverage and mean width (decades), and the fraction of rows whose
predicted damage is within a factor of 2 of the simulated one
(|log10 pred - log10 true| <= log10 2).

Where it counts: a string's life is set by its most damaged component and
lives beyond ``surrogate.horizon_h`` (1e5 h of rotation) are answered as
"longer than". :func:`deciding_metrics` scores the rows whose *predicted*
life is within the horizon (what a user reads as a number), per decade, well
profile and component type, the "longer than" answers as a classification,
and the governing damage per case and component type (the headline).
:func:`governing_metrics` keeps the per-case maximum and the rows whose
*simulated* life is within the horizon. :func:`monotone_check` catches
predictions that fall as the dogleg severity rises.
"""

from __future__ import annotations

import copy

import json
import math
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from sklearn.exceptions import ConvergenceWarning
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.metrics import decade_label, factor2_by_decade
from drillfatigue.plotting import subplots
from drillfatigue.surrogate.conformal import SplitConformal
from drillfatigue.surrogate.data import Split, check_columns, gbm_rows, log10_target
from drillfatigue.surrogate.facade import Surrogate
from drillfatigue.surrogate.gbm import design_matrix, monotone_constraints
from drillfatigue.surrogate.io import save_figure
from drillfatigue.surrogate.served_gbm import (fit_served_gbm, half_width, interval_bins,
                                               interval_scale)

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


def fitted_cases(model: Surrogate, frame: pd.DataFrame, cfg: SurrogateConfig,
                 baselines: bool = True) -> set[str]:
    """Case ids a held-out dataset scored against ``model`` must not share.

    The ensemble's training and calibration cases, the cases the served
    gradient boosting trained on (``gbm.train_cases`` in the metadata), and,
    with ``baselines``, those the evaluation's baselines train and calibrate
    on when it scores a held-out dataset (:func:`~drillfatigue.surrogate.data.gbm_rows`:
    the split's test cases too with ``gbm_cases: free``).
    """
    sp = model.metadata["split"]
    cases = set(sp["train_cases"]) | set(sp["calibration_cases"])
    cases |= set((model.metadata.get("gbm") or {}).get("train_cases") or ())
    if baselines:
        fit, _ = gbm_rows(split_from_model(frame, model, cfg), cfg, heldout=True)
        cases |= set(map(str, frame.loc[fit, cfg.group_column]))
    return cases


def _design(model: Surrogate, frame: pd.DataFrame) -> np.ndarray:
    return design_matrix(model.preprocessor, *model.encode(frame))


def evaluate(frame: pd.DataFrame, model: Surrogate, cfg: SurrogateConfig,
             baselines: bool = True, heldout: pd.DataFrame | None = None
             ) -> tuple[dict[str, Any], pd.DataFrame]:
    """Score the ensemble (and the baselines) on held-out cases.

    Parameters
    ----------
    frame : DataFrame
        The dataset the model was trained on (its split is in the model's
        metadata); the baselines train and calibrate on the same cases.
    heldout : DataFrame, optional
        A dataset of its own design (same schema): every row is scored. None:
        the model's test cases of ``frame`` are scored.

    Returns
    -------
    metrics : dict
        Per model ("ensemble", "gp", "hgb") the :func:`score` dict, plus
        dataset facts (test rows/cases, censored fraction, OOD fraction),
        ``governing`` (:func:`governing_metrics`), ``deciding``
        (:func:`deciding_metrics`: the rows whose predicted life is within the
        horizon, censoring, governing damage per component) and
        ``monotone_dls`` (:func:`monotone_check` per model).
    predictions : DataFrame
        Test rows: case id, profile, component type, location, y_true and per
        model the prediction and interval (log10 damage rate per hour), the
        ensemble's OOD flag.
    """
    check_columns(frame, cfg)
    y = log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    sp = split_from_model(frame, model, cfg)
    if heldout is None:
        if not sp.test.any():
            raise InputError(cfg.group_column, "no test case of the model in the dataset",
                             "the dataset the model was trained on")
        test = frame.loc[sp.test]
        y_te = y[sp.test]
        source = "split"
    else:
        check_columns(heldout, cfg)
        test = heldout
        y_te = log10_target(heldout[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
        # case ids hash the case's settings: a shared id is the same simulation
        shared = set(map(str, heldout[cfg.group_column])) & fitted_cases(model, frame, cfg,
                                                                         baselines)
        if shared:
            raise InputError("--heldout", f"{len(shared)} case(s) also in the model's "
                             "training cases or calibration cases",
                             "a dataset of its own design (held-out stage)")
        source = "heldout"
    # the ensemble's own answers, whichever model is served (a served gradient boosting
    # is scored as the hgb baseline below)
    ens = copy.copy(model)
    ens.gbm = None
    x_num, x_cat = ens.encode(test)
    r = ens.predict_array(x_num, x_cat)
    metrics: dict[str, Any] = {
        "test_source": source,
        "coverage_nominal": model.coverage,
        "criterion": cfg.criterion,
        "horizon_h": cfg.horizon_h,
        "censoring": cfg.censoring,
        "n_test_rows": int(len(test)),
        "n_test_cases": int(test[cfg.group_column].nunique()),
        "censored_fraction_test": float(np.mean(y_te <= math.log10(cfg.rate_floor_per_h))),
        "beyond_horizon_fraction_test": float(np.mean(y_te < -math.log10(cfg.horizon_h))),
        "ood_fraction_test": float(r["ood"].mean()),
    }
    out = pd.DataFrame({"case_id": test[cfg.group_column].astype(str).to_numpy(),
                        "y_true": y_te})
    for col in ("well.profile", "component_type", "location", "s_from_bit_m"):
        if col in test.columns:
            out[col] = test[col].to_numpy()
    mu, lo, hi = r["log10"], r["lower"], r["upper"]
    metrics["ensemble"] = score(y_te, mu, lo, hi)
    ind = ~r["ood"]
    if ind.any():
        metrics["ensemble_in_domain"] = score(y_te[ind], mu[ind], lo[ind], hi[ind])
    out["ensemble"], out["ensemble_lower"], out["ensemble_upper"] = mu, lo, hi
    out["ensemble_ood"] = ~ind
    models: tuple[str, ...] = ("ensemble",)
    monotone: dict[str, Any] = {"ensemble": monotone_check(
        lambda f: ens.predict_array(*ens.encode(f), ood=False)["log10"], test,
        model.domain)}
    if baselines:
        x_all = _design(model, frame)
        x_tr, x_ca = x_all[sp.train], x_all[sp.calibration]
        x_te = _design(model, test)
        y_tr, y_ca = y[sp.train], y[sp.calibration]
        censor = -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None

        gp, n_gp = fit_gp(x_tr, y_tr, cfg)
        mu_c, sd_c = gp.predict(x_ca, return_std=True)
        conf = SplitConformal(model.coverage).fit(mu_c, np.maximum(sd_c, 1e-9), y_ca,
                                                  censor_below=censor)
        mu_t, sd_t = gp.predict(x_te, return_std=True)
        lo_t, hi_t = conf.interval(mu_t, np.maximum(sd_t, 1e-9))
        metrics["gp"] = score(y_te, mu_t, lo_t, hi_t) | {"train_rows": int(n_gp)}
        out["gp"], out["gp_lower"], out["gp_upper"] = mu_t, lo_t, hi_t

        # gradient boosting, early stopping on whole cases, monotone in the dogleg
        # inputs, trained and calibrated as the served model is (one function)
        fit_rows, cal_rows = gbm_rows(sp, cfg, heldout=heldout is not None)
        hgb, info = fit_served_gbm(x_all, y, frame[cfg.group_column].to_numpy(), fit_rows,
                                   cal_rows, cfg, monotone_constraints(model.preprocessor))
        served = (model.metadata.get("gbm") or {}).get("train_cases")
        info = info | {"same_cases_as_served": (None if served is None
                                                else served == info["train_cases"]),
                       "n_train_cases": len(info["train_cases"])}
        info.pop("train_cases")
        mu_h = hgb.predict(x_te)
        half = half_width(mu_h, info, interval_bins(info), interval_scale(hgb, x_te))
        metrics["hgb"] = (score(y_te, mu_h, mu_h - half, mu_h + half)
                          | {"train_rows": int(fit_rows.sum())} | info)
        out["hgb"], out["hgb_lower"], out["hgb_upper"] = mu_h, mu_h - half, mu_h + half
        monotone["hgb"] = monotone_check(lambda f: hgb.predict(_design(model, f)), test,
                                         model.domain)
        models = ("ensemble", "gp", "hgb")
        metrics["best_rmse_model"] = min(models, key=lambda k: metrics[k]["rmse"])
    metrics["governing"] = governing_metrics(out, models, relevant_life_h=cfg.horizon_h)
    metrics["deciding"] = deciding_metrics(out, models, cfg.horizon_h)
    metrics["monotone_dls"] = monotone
    return metrics, out


def fit_gp(x: np.ndarray, y: np.ndarray, cfg: SurrogateConfig
           ) -> tuple[GaussianProcessRegressor, int]:
    """The Gaussian-process baseline fitted on a seeded subsample of the rows.

    Constant x anisotropic RBF + white noise, ``normalize_y``, one start of
    the optimiser; exact GP cost grows as n^3, so at most ``cfg.gp_max_rows``
    rows (drawn with ``cfg.split_seed``).

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Encoded inputs (:func:`~drillfatigue.surrogate.gbm.design_matrix`).
    y : ndarray, shape (n,)
        log10 damage rate per hour.

    Returns
    -------
    gp, n_rows
        The fitted regressor and the number of rows it saw.
    """
    rng = np.random.default_rng(cfg.split_seed)
    n_gp = min(cfg.gp_max_rows, x.shape[0])
    sub = np.sort(rng.choice(x.shape[0], n_gp, replace=False))
    d = x.shape[1]
    kernel = (ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.ones(d), (1e-2, 1e3))
              + WhiteKernel(1e-2, (1e-6, 1.0)))
    gp = GaussianProcessRegressor(kernel, normalize_y=True, random_state=cfg.split_seed,
                                  n_restarts_optimizer=0)
    with warnings.catch_warnings():
        # a length scale at its upper bound means an irrelevant input: expected, not a fault
        warnings.simplefilter("ignore", ConvergenceWarning)
        gp.fit(x[sub], y[sub])
    return gp, int(n_gp)


def _errs(e: np.ndarray, covered: np.ndarray | None = None, width: np.ndarray | None = None,
          covered_censored: np.ndarray | None = None) -> dict[str, float]:
    if e.size == 0:
        res = {"rmse": float("nan"), "mae": float("nan"), "factor2_fraction": float("nan"),
               "n": 0}
    else:
        res = {"rmse": float(np.sqrt(np.mean(e**2))), "mae": float(np.mean(np.abs(e))),
               "factor2_fraction": float(np.mean(np.abs(e) <= LOG10_2)), "n": int(e.size)}
    if covered is not None:
        res["coverage"] = float(np.mean(covered)) if covered.size else float("nan")
    if width is not None:
        res["mean_width"] = float(np.mean(width)) if width.size else float("nan")
    if covered_censored is not None:
        res["coverage_censored"] = (float(np.mean(covered_censored)) if covered_censored.size
                                    else float("nan"))
    return res


def deciding_metrics(pred: pd.DataFrame, models: tuple[str, ...] = ("ensemble", "gp", "hgb"),
                     horizon_h: float = 1e5) -> dict[str, Any]:
    """Errors on the answers that decide a string's life, as a user meets them.

    A user sees the prediction, not the simulation: the rows "with life within
    the horizon" are those whose *predicted* life is at most ``horizon_h``
    (predicted log10 rate >= -log10 horizon_h); a row predicted beyond it is
    answered "longer than the horizon" and is scored as a classification.

    Parameters
    ----------
    pred : DataFrame
        Test rows of :func:`evaluate`: ``case_id``, ``y_true``, per model ``m``
        the columns ``m``, ``m_lower``, ``m_upper`` (log10 damage rate per
        hour); optional ``well.profile``, ``component_type``, ``location``,
        ``s_from_bit_m`` for the breakdowns and the governing location.
    models : tuple of str
    horizon_h : float
        Horizon, h (> 0).

    Returns
    -------
    dict
        Per model: ``rows`` (RMSE, MAE, factor-2 fraction, interval coverage
        and mean width on the rows predicted within the horizon; also
        ``coverage_censored``, where a row simulated beyond the horizon
        counts as covered once the interval reaches down to the horizon, as
        the calibration scores it), ``by_decade``
        (the same per decade of the simulated rate), ``by_predicted_decade``
        (per decade of the predicted rate: a user sees the prediction, and a
        Mondrian interval's coverage is guaranteed per bin of the prediction,
        not per decade of the truth, which regression to the mean moves:
        rows simulated at low rates and predicted within the horizon are
        over-predicted by selection), ``by_profile``, ``by_component_type``,
        ``by_component_type_location`` (``"collar connection"``, ...),
        ``beyond_horizon`` (precision, recall and counts of the "longer than
        the horizon" answers against the simulation) and ``governing`` (per
        case and component type: the largest predicted against the largest
        simulated rate; ``same_location_fraction``: the predicted governing
        row is the simulated one's location and distance from the bit; the
        error scored where either is within the horizon).
    """
    if not horizon_h > 0:
        raise ValueError(f"horizon_h must be > 0, got {horizon_h}")
    c = -math.log10(horizon_h)
    y = pred["y_true"].to_numpy(dtype=np.float64)
    out: dict[str, Any] = {"horizon_h": float(horizon_h)}
    for m in models:
        if m not in pred:
            continue
        mu = pred[m].to_numpy(dtype=np.float64)
        lo = pred[f"{m}_lower"].to_numpy(dtype=np.float64)
        hi = pred[f"{m}_upper"].to_numpy(dtype=np.float64)
        within = mu >= c
        cov = (y >= lo) & (y <= hi)
        wid = hi - lo
        # a life simulated beyond the horizon is censored ("longer than"): covered when
        # the interval reaches down to the horizon, as the conformal calibration scores it
        cov_c = cov | ((y < c) & (lo <= c))
        res: dict[str, Any] = {"rows": _errs(mu[within] - y[within], cov[within], wid[within],
                                             cov_c[within])}
        # per decade of the simulated rate (where the truth lies) and of the predicted
        # one (what a user sees, and what Mondrian bins condition on)
        for key, dec in (("by_decade", decade_label(y)), ("by_predicted_decade",
                                                          decade_label(mu))):
            res[key] = {}
            for k in sorted(set(dec[within]), key=float):
                sel = within & (dec == k)
                res[key][str(k)] = _errs(mu[sel] - y[sel], cov[sel], wid[sel], cov_c[sel])
        groups = [(pred[col].astype(str).to_numpy(), key) for col, key in
                  (("well.profile", "by_profile"), ("component_type", "by_component_type"))
                  if col in pred]
        if "component_type" in pred and "location" in pred:
            groups.append(((pred["component_type"].astype(str) + " "
                            + pred["location"].astype(str)).to_numpy(),
                           "by_component_type_location"))
        for g, key in groups:
            res[key] = {str(k): _errs(mu[within & (g == k)] - y[within & (g == k)],
                                      cov[within & (g == k)])
                        for k in sorted(set(g[within]))}
        pb, tb = ~within, y < c
        res["beyond_horizon"] = {
            "n_predicted": int(pb.sum()), "n_simulated": int(tb.sum()),
            "precision": float(np.mean(tb[pb])) if pb.any() else float("nan"),
            "recall": float(np.mean(pb[tb])) if tb.any() else float("nan")}
        res["governing"] = _governing_per_component(pred, m, c)
        out[m] = res
    return out


def _governing_per_component(pred: pd.DataFrame, m: str, c: float) -> dict[str, Any]:
    """Largest predicted vs largest simulated rate per case and component type."""
    keys = ["case_id"] + (["component_type"] if "component_type" in pred else [])
    y = pred["y_true"].to_numpy(dtype=np.float64)
    mu = pred[m].to_numpy(dtype=np.float64)
    frame = pred.assign(_row=np.arange(len(pred)))
    where = [col for col in ("location", "s_from_bit_m") if col in pred]
    e, same, both_beyond, n = [], [], 0, 0
    by_type: dict[str, list[float]] = {}
    for key, g in frame.groupby(keys, sort=True):
        rows = g["_row"].to_numpy()
        i_sim, i_pred = rows[np.argmax(y[rows])], rows[np.argmax(mu[rows])]
        n += 1
        if y[i_sim] < c and mu[i_pred] < c:
            both_beyond += 1  # answered "longer than the horizon", and so it is
            continue
        e.append(mu[i_pred] - y[i_sim])
        ctype = str(key[1]) if len(keys) > 1 else "all"
        by_type.setdefault(ctype, []).append(e[-1])
        same.append(all(pred[col].iloc[i_sim] == pred[col].iloc[i_pred] for col in where))
    res: dict[str, Any] = {"n_groups": n, "n_both_beyond_horizon": both_beyond,
                           **_errs(np.asarray(e)),
           "same_location_fraction": float(np.mean(same)) if same else float("nan")}
    res["by_component_type"] = {k: _errs(np.asarray(v)) for k, v in sorted(by_type.items())}
    return res


def monotone_check(predict: Callable[[pd.DataFrame], np.ndarray], rows: pd.DataFrame,
                   domain: Any = None, n_grid: int = 9, max_rows: int = 200,
                   tol_decades: float = 0.05, seed: int = 0) -> dict[str, Any]:
    """Catch predictions that fall as the dogleg severity rises.

    Each of up to ``max_rows`` rows (seeded sample of ``rows``) is moved
    along a grid of ``n_grid`` local dogleg severities (``local_dls_deg_per_30m``
    from the domain's lower to upper bound, or the rows' range without a
    domain), everything else held; the windowed maximum dogleg
    (``local_max_dls_deg_per_30m``), when present, is raised to at least the
    local value (it cannot be smaller). A *violation* is a step where the
    predicted log10 damage rate drops by more than ``tol_decades`` (0.05: a
    12 % drop, well below the factor-2 scale of the errors).

    Parameters
    ----------
    predict : callable
        DataFrame -> log10 damage rate per hour, shape (n,).
    rows : DataFrame
        Rows with the model's inputs.
    domain : DomainChecker, optional
        Bounds of the grid.

    Returns
    -------
    dict
        ``n_rows``, ``fraction_rows_violating``, ``fraction_steps_violating``,
        ``max_drop_decades``, ``grid_deg_per_30m`` (the grid), ``tol_decades``;
        an empty dict when the rows have no ``local_dls_deg_per_30m``.
    """
    f = "local_dls_deg_per_30m"
    if f not in rows.columns or len(rows) == 0:
        return {}
    if domain is not None and f in getattr(domain, "names", []):
        j = domain.names.index(f)
        lo, hi = float(domain.min_[j]), float(domain.max_[j])
    else:
        lo, hi = float(rows[f].min()), float(rows[f].max())
    grid = np.linspace(lo, hi, int(n_grid))
    rng = np.random.default_rng(seed)
    pick = rows.iloc[np.sort(rng.choice(len(rows), min(max_rows, len(rows)), replace=False))]
    big = pick.loc[pick.index.repeat(grid.size)].reset_index(drop=True)
    g = np.tile(grid, len(pick))
    big[f] = g
    if "local_max_dls_deg_per_30m" in big.columns:
        big["local_max_dls_deg_per_30m"] = np.maximum(big["local_max_dls_deg_per_30m"], g)
    yk = np.asarray(predict(big), dtype=np.float64).reshape(len(pick), grid.size)
    drop = yk[:, :-1] - yk[:, 1:]  # > 0: the prediction fell as the dogleg rose
    bad = drop > tol_decades
    return {"n_rows": int(len(pick)), "fraction_rows_violating": float(bad.any(axis=1).mean()),
            "fraction_steps_violating": float(bad.mean()),
            "max_drop_decades": float(max(drop.max(), 0.0)), "grid_deg_per_30m": grid.tolist(),
            "tol_decades": float(tol_decades)}


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


def mean_of_draws_log10(rows: pd.DataFrame, draws: pd.DataFrame, floor_per_h: float,
                        min_draws: int = 2, average: str = "rate") -> np.ndarray:
    """log10 of each row's damage rate per hour averaged over its case's draws.

    A draw is a run of the same case with rpm moved by a fraction of a
    percent (the ``heldout_draws`` stage); runs that close land in different
    states of the string's dynamics (docs/surrogate.md#what-limits-it).
    ``average="rate"``: Miner damage adds linearly in time, so over hours
    that visit those states alike the rate is the arithmetic mean of the
    draws' rates. ``average="log10"``: the mean of the draws' floored log10
    rates (the geometric mean), what a model fitted to single runs in log10
    estimates; scored against it, the single run's spread alone is averaged
    away. Rates are floored at ``floor_per_h`` as the surrogate's target is;
    a draw's missing rate (no cycle) counts as zero.

    Parameters
    ----------
    rows : DataFrame
        ``case_id``, ``joint``, ``location`` per row to score.
    draws : DataFrame
        ``base_case_id``, ``joint``, ``location``, ``replicate``,
        ``damage_rate_per_h`` (the replicates stage's ``spread.parquet``).
    floor_per_h : float
        Censoring floor of the rate, per hour (> 0).
    min_draws : int
        Fewest draws a row needs; rows with fewer get NaN.
    average : {"rate", "log10"}

    Returns
    -------
    ndarray, shape (len(rows),)
    """
    need = {"base_case_id", "joint", "location", "replicate", "damage_rate_per_h"}
    if need - set(draws.columns):
        raise InputError("draws", f"table lacks columns {sorted(need - set(draws.columns))}",
                         ", ".join(sorted(need)))
    if average not in ("rate", "log10"):
        raise InputError("average", f"{average!r}", "rate or log10")
    rate = np.maximum(np.nan_to_num(draws["damage_rate_per_h"].to_numpy(float), nan=0.0),
                      floor_per_h)
    d = draws.assign(v=rate if average == "rate" else np.log10(rate))
    agg = (d.groupby(["base_case_id", "joint", "location"])["v"]
           .agg(["mean", "size"]).reset_index()
           .rename(columns={"base_case_id": "case_id"}))
    agg["case_id"] = agg["case_id"].astype(str)
    keys = rows[["case_id", "joint", "location"]].astype({"case_id": str})
    m = keys.merge(agg, on=["case_id", "joint", "location"], how="left")
    mean = m["mean"].to_numpy(float)
    y = np.log10(mean) if average == "rate" else mean
    return np.where(m["size"].fillna(0).to_numpy() >= min_draws, y, np.nan)


def draws_metrics(pred: pd.DataFrame, y_draws: np.ndarray, models: tuple[str, ...],
                  horizon_h: float, y_draws_log: np.ndarray | None = None) -> dict[str, Any]:
    """:func:`deciding_metrics` against the mean of draws, beside the single run.

    ``pred``: the test rows of :func:`evaluate`; ``y_draws``: per row the
    log10 mean rate of its draws (:func:`mean_of_draws_log10`, NaN where a
    row has too few); ``y_draws_log``, optional: the mean of their log10
    rates (``average="log10"``), scored as ``log_mean_of_draws``. Every
    block scores the same rows, those with draws.
    """
    y_draws = np.asarray(y_draws, dtype=float)
    have = np.isfinite(y_draws)
    if not have.any():
        return {"n_rows": 0, "n_cases": 0}
    sub = pred.loc[have].copy()
    out: dict[str, Any] = {"n_rows": int(have.sum()), "n_cases": int(sub["case_id"].nunique()),
                           "single_run": deciding_metrics(sub, models, horizon_h)}
    sub["y_true"] = y_draws[have]
    out["mean_of_draws"] = deciding_metrics(sub, models, horizon_h)
    if y_draws_log is not None:
        sub["y_true"] = np.asarray(y_draws_log, dtype=float)[have]
        out["log_mean_of_draws"] = deciding_metrics(sub, models, horizon_h)
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
