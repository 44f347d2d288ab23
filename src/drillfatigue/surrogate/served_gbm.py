"""The served gradient boosting's fit and conformal calibration, one procedure for all.

:meth:`drillfatigue.surrogate.facade.Surrogate.fit` (``surrogate.served_model:
gbm``) and the evaluation's gradient-boosting baseline
(:func:`drillfatigue.surrogate.evaluation.evaluate`) both call
:func:`fit_served_gbm`, so the metrics report the model that is served.

Two calibrations (``surrogate.gbm_calibration``):

- ``split``: the model is fitted on the training rows and calibrated on the
  rows of separate calibration cases (split conformal prediction: Vovk,
  Gammerman & Shafer 2005; Lei et al. 2018). Finite-sample coverage >= c for
  an exchangeable new case, per Mondrian bin of the prediction.
- ``cross``: cross-conformal by case. The training cases are dealt into K
  folds of whole cases (``surrogate.conformal_folds``, seeded); each fold's
  rows are predicted by a model of the same hyper-parameters and the same
  number of trees (the one chosen by the early stopping of the full fit),
  fitted on the other K - 1 folds. The out-of-fold absolute residuals of
  every training case feed the conformal quantiles (one global, and per
  Mondrian bin of the out-of-fold prediction); the served model is the one
  fitted on all training cases, answering its prediction -/+ the bin's
  half-width.

What ``cross`` guarantees, honestly: the CV+ interval of Barber, Candès,
Ramdas & Tibshirani ("Predictive inference with the jackknife+", Ann.
Statist. 49 (2021), sec. 3 and thm. 4) keeps the K fold models and takes
quantiles of mu_{-k(i)}(x) -/+ R_i over the calibration points i; it
covers >= 1 - 2 alpha - O(K/n) in the worst case and about 1 - alpha in
practice; Vovk's cross-conformal predictor ("Cross-conformal predictors",
Ann. Math. Artif. Intell. 74 (2015)) has a similar, weaker-than-split
validity. Here the served answer uses the full model's prediction with
quantiles of the out-of-fold residuals, the common approximation (one
model to serve, not K): it has no finite-sample guarantee. The full model
has seen (K / (K - 1)) times the cases of each fold model, so its errors on a
new case are, if anything, smaller than the out-of-fold ones (the interval
errs wide), and the Mondrian bin of a query is that of the full model's
prediction while the bins were filled by the fold models' predictions
(the two differ by the models' disagreement). Rows of one case share its
errors: the exchangeable unit is the case, so the quantiles carry the
case-to-case scatter of the number of training cases (all of them here,
against the calibration cases alone with ``split``). Its coverage is
measured, not assumed: docs/surrogate.md, "Cross-conformal calibration".
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from sklearn.base import clone
from sklearn.ensemble import HistGradientBoostingRegressor

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import SplitConformal, mondrian_bins, mondrian_half_width
from drillfatigue.surrogate.data import case_folds
from drillfatigue.surrogate.gbm import fit_gbm


def out_of_fold_predictions(model: HistGradientBoostingRegressor, x: np.ndarray, y: np.ndarray,
                            folds: np.ndarray) -> np.ndarray:
    """Each row predicted by a copy of ``model`` fitted on the rows of the other folds.

    Parameters
    ----------
    model : HistGradientBoostingRegressor
        Its hyper-parameters (``max_iter`` included) are copied
        (``sklearn.base.clone``); its fitted state is not used.
    x : ndarray, shape (n, d)
    y : ndarray, shape (n,)
    folds : ndarray of int, shape (n,)
        Fold per row (:func:`~drillfatigue.surrogate.data.case_folds`).

    Returns
    -------
    ndarray, shape (n,)
    """
    mu = np.empty(y.shape[0], dtype=np.float64)
    for k in np.unique(folds):
        out = folds == k
        mu[out] = clone(model).fit(x[~out], y[~out]).predict(x[out])
    return mu


def fit_served_gbm(x: np.ndarray, y: np.ndarray, groups: np.ndarray, fit: np.ndarray,
                   calibration: np.ndarray | None, cfg: SurrogateConfig,
                   monotone: np.ndarray | None = None
                   ) -> tuple[HistGradientBoostingRegressor, dict[str, Any]]:
    """Fit the gradient boosting on the ``fit`` rows and calibrate its interval.

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Encoded inputs (:func:`~drillfatigue.surrogate.gbm.design_matrix`).
    y : ndarray, shape (n,)
        log10 damage rate per hour.
    groups : ndarray, shape (n,)
        Case id per row.
    fit : ndarray of bool, shape (n,)
        Training rows (:func:`~drillfatigue.surrogate.data.gbm_rows`).
    calibration : ndarray of bool, shape (n,), or None
        Split-conformal calibration rows (cases disjoint from ``fit``); None:
        cross-conformal by case over the ``fit`` rows (``cfg.conformal_folds``
        folds seeded by ``cfg.split_seed``).
    cfg : SurrogateConfig
        ``coverage``, ``gbm_interval`` (``per_decade``: Mondrian bins of
        ``conformal_bin_min_rows`` rows or more), censoring, the early
        stopping of :func:`~drillfatigue.surrogate.gbm.fit_gbm`.
    monotone : ndarray of int, shape (d,), optional
        scikit-learn ``monotonic_cst``.

    Returns
    -------
    model, meta
        The gradient boosting fitted on all ``fit`` rows; ``meta``: the
        early stopping's ``n_iter``, ``val_loss``, ``n_val_cases``;
        ``calibration`` (``cross`` or ``split``), ``conformal_folds`` (cross),
        ``n_calibration_rows``, ``n_calibration_cases``,
        ``conformal_quantile`` (global half-width, decades), ``sigma_log10``
        (RMS calibration residual: out-of-fold with ``cross``),
        ``interval``, ``train_cases`` (sorted case ids of the ``fit`` rows),
        ``n_train_rows`` and, with ``per_decade``, ``conformal_bins_log10``
        and ``conformal_half_widths``
        (:func:`~drillfatigue.surrogate.conformal.mondrian_bins`).
    """
    g = np.asarray(groups).astype(str)
    fit = np.asarray(fit, dtype=bool)
    censor = -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None
    x_f, y_f, g_f = x[fit], y[fit], g[fit]
    model, info = fit_gbm(x_f, y_f, g_f, cfg, monotone)
    if calibration is None:
        folds = case_folds(g_f, cfg.conformal_folds, cfg.split_seed)
        mu_c, y_c, g_c = out_of_fold_predictions(model, x_f, y_f, folds), y_f, g_f
        field, allowed = "surrogate.conformal_folds", "more training cases"
        meta: dict[str, Any] = {"calibration": "cross", "conformal_folds": cfg.conformal_folds}
    else:
        calibration = np.asarray(calibration, dtype=bool)
        if np.any(calibration & fit):
            raise InputError("calibration rows", "shared with the training rows",
                             "calibration cases the model does not train on")
        mu_c, y_c, g_c = model.predict(x[calibration]), y[calibration], g[calibration]
        field, allowed = "surrogate.calibration_fraction", "a larger fraction"
        meta = {"calibration": "split"}
    if y_c.size == 0:
        raise InputError(field, "no calibration rows", allowed)
    q = SplitConformal(cfg.coverage).fit(mu_c, np.ones_like(mu_c), y_c,
                                         censor_below=censor).quantile_
    if not np.isfinite(q):
        raise InputError(field, "too few calibration rows for the coverage", allowed)
    meta = info | meta | {
        "n_calibration_rows": int(y_c.size), "n_calibration_cases": int(np.unique(g_c).size),
        "conformal_quantile": float(q),
        "sigma_log10": float(np.sqrt(np.mean((mu_c - y_c) ** 2))),
        "interval": cfg.gbm_interval, "n_train_rows": int(fit.sum()),
        "train_cases": sorted(np.unique(g_f).tolist())}
    if cfg.gbm_interval == "per_decade":
        edges, half = mondrian_bins(mu_c, y_c, cfg.coverage, cfg.conformal_bin_min_rows,
                                    censor_below=censor)
        meta |= {"conformal_bins_log10": edges.tolist(), "conformal_half_widths": half.tolist()}
    return model, meta


def interval_bins(meta: dict[str, Any]) -> tuple[np.ndarray, np.ndarray] | None:
    """The per-decade bins of a :func:`fit_served_gbm` ``meta`` as arrays (edges,
    half-widths); None for a constant width (``gbm_interval: constant``, older models)."""
    if "conformal_half_widths" not in meta:
        return None
    return (np.asarray(meta["conformal_bins_log10"], dtype=np.float64),
            np.asarray(meta["conformal_half_widths"], dtype=np.float64))


def half_width(mu: np.ndarray, meta: dict[str, Any],
               bins: tuple[np.ndarray, np.ndarray] | None) -> float | np.ndarray:
    """Interval half-width (decades) of predictions ``mu``: their bin's with ``bins``
    (:func:`interval_bins` of ``meta``), else ``meta``'s one conformal quantile."""
    if bins is not None:
        return mondrian_half_width(mu, *bins)
    return float(meta["conformal_quantile"])
