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

Three interval shapes (``surrogate.gbm_interval``): ``constant`` (one
width), ``per_decade`` (Mondrian bins of the predicted decade) and
``scaled`` (normalised conformal within the same bins: Papadopoulos,
Proedrou, Vovk & Gammerman 2002; Lei et al. 2018, sec. 5.2). With
``scaled``, a small gradient boosting (the *scale model*) learns the log of
the calibration rows' absolute residual from the inputs, its prediction
``s(x)`` is cross-fitted over folds of whole calibration cases (a row's own
residual never shapes its scale), the conformal scores are ``|r| / s(x)``
and a query's half-width is its bin's multiplier times ``s(x)`` (an
answer beyond the horizon keeps the one global width of ``per_decade``:
its calibration rows are mostly censored with zero residual). The
residual spread is not a function of the predicted rate alone: on the
research-scale data the served model misses a factor 2 on a quarter of the
rows where the string may settle in partial stick-slip (above ~140 rpm) and
on 2 % in the full stick-slip of low rpm, so one width per decade covered
0.99 of the rows at 80-110 rpm and 0.84 above 160 rpm (the learned scale is
about twice as large above 160 rpm as below 110 rpm) (docs/surrogate.md, "An
interval that follows the error"). The scale model travels with the
regressor as its attribute :data:`SCALE_ATTRIBUTE` (pickled with it).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from sklearn.base import clone
from sklearn.ensemble import HistGradientBoostingRegressor

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import (SplitConformal, censored_residuals, mondrian_bins,
                                             mondrian_half_width)
from drillfatigue.surrogate.data import case_folds
from drillfatigue.surrogate.gbm import fit_gbm

#: the scale model of ``gbm_interval: scaled``: a smooth, small gradient boosting of
#: log(|residual| + SCALE_FLOOR_LOG10) (few shallow trees on well-populated leaves: it
#: learns where the error is large, not each case's residual)
SCALE_MAX_ITER = 30
SCALE_LEARNING_RATE = 0.15
SCALE_MAX_LEAF_NODES = 15
SCALE_MIN_SAMPLES_LEAF = 200
#: decades added to |residual| before its log: a zero residual (a censored row predicted
#: beyond the horizon) has a finite log, and no scale collapses to zero
SCALE_FLOOR_LOG10 = 0.02
#: the attribute of the fitted regressor that holds its scale model
SCALE_ATTRIBUTE = "drillfatigue_interval_scale_"


def fit_scale_model(x: np.ndarray, residual: np.ndarray, seed: int
                    ) -> HistGradientBoostingRegressor:
    """The scale model: log(|residual| + :data:`SCALE_FLOOR_LOG10`) from the inputs."""
    return HistGradientBoostingRegressor(
        max_iter=SCALE_MAX_ITER, learning_rate=SCALE_LEARNING_RATE,
        max_leaf_nodes=SCALE_MAX_LEAF_NODES, min_samples_leaf=SCALE_MIN_SAMPLES_LEAF,
        early_stopping=False, random_state=seed).fit(x, np.log(residual + SCALE_FLOOR_LOG10))


def scale_model(model: HistGradientBoostingRegressor) -> HistGradientBoostingRegressor | None:
    """The scale model a :func:`fit_served_gbm` regressor carries (None: not ``scaled``)."""
    return getattr(model, SCALE_ATTRIBUTE, None)


def interval_scale(model: HistGradientBoostingRegressor, x: np.ndarray) -> np.ndarray | None:
    """Scale ``s(x)`` (decades) of each row of the design matrix ``x``; None when the model
    has no scale model (``gbm_interval`` ``per_decade`` or ``constant``)."""
    sm = scale_model(model)
    return None if sm is None else np.exp(sm.predict(x))


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
        ``conformal_bin_min_rows`` rows or more; ``scaled``: the same bins of
        normalised scores, module doc), censoring, the early stopping of
        :func:`~drillfatigue.surrogate.gbm.fit_gbm`.
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
        ``n_train_rows`` and, with ``per_decade`` or ``scaled``,
        ``conformal_bins_log10`` and ``conformal_half_widths``
        (:func:`~drillfatigue.surrogate.conformal.mondrian_bins`; with
        ``scaled`` multipliers of the query's scale, and the model carries its
        scale model: :func:`interval_scale`).
    """
    g = np.asarray(groups).astype(str)
    fit = np.asarray(fit, dtype=bool)
    censor = -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None
    x_f, y_f, g_f = x[fit], y[fit], g[fit]
    model, info = fit_gbm(x_f, y_f, g_f, cfg, monotone)
    if calibration is None:
        # at most one fold per case (a small training set keeps working as with 5 folds)
        k = min(cfg.conformal_folds, int(np.unique(g_f).size))
        folds = case_folds(g_f, k, cfg.split_seed)
        mu_c, y_c, g_c = out_of_fold_predictions(model, x_f, y_f, folds), y_f, g_f
        field, allowed = "surrogate.conformal_folds", "more training cases"
        meta: dict[str, Any] = {"calibration": "cross", "conformal_folds": k}
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
    scale_c = None
    if cfg.gbm_interval == "scaled":
        # the scale of a calibration row comes from a scale model that did not see the
        # row's case (folds of whole calibration cases); the served one sees them all
        x_c = x_f if calibration is None else x[calibration]
        r_c = censored_residuals(mu_c, y_c, censor)
        n_cases = int(np.unique(g_c).size)
        if n_cases < 2:
            raise InputError(field, "one calibration case cannot cross-fit the interval's "
                             "scale", allowed)
        folds_c = case_folds(g_c, min(cfg.conformal_folds, n_cases), cfg.split_seed)
        scale_c = np.empty_like(r_c)
        for k in np.unique(folds_c):
            out = folds_c == k
            scale_c[out] = np.exp(fit_scale_model(x_c[~out], r_c[~out], cfg.split_seed)
                                  .predict(x_c[out]))
        setattr(model, SCALE_ATTRIBUTE, fit_scale_model(x_c, r_c, cfg.split_seed))
        meta["scale_floor_log10"] = SCALE_FLOOR_LOG10
        # an answer "longer than the horizon" keeps the one global width: its calibration
        # rows are mostly censored with a zero residual, which would shrink its scale
        meta["censor_level_log10"] = censor
    if cfg.gbm_interval in ("per_decade", "scaled"):
        edges, half = mondrian_bins(mu_c, y_c, cfg.coverage, cfg.conformal_bin_min_rows,
                                    censor_below=censor, scale=scale_c)
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
               bins: tuple[np.ndarray, np.ndarray] | None,
               scale: np.ndarray | None = None) -> float | np.ndarray:
    """Interval half-width (decades) of predictions ``mu``: their bin's with ``bins``
    (:func:`interval_bins` of ``meta``) times the rows' ``scale`` for a ``scaled``
    interval (:func:`interval_scale`; a prediction beyond the horizon keeps the one
    global width), else ``meta``'s one conformal quantile.

    Raises
    ------
    ValueError
        A ``scaled`` interval without the rows' scale.
    """
    if meta.get("interval") == "scaled":
        if scale is None or bins is None:
            raise ValueError("a scaled interval needs its bins and the rows' scale "
                             "(interval_scale of the served regressor)")
        half = mondrian_half_width(mu, *bins) * scale
        level = meta.get("censor_level_log10")
        if level is not None:
            half = np.where(mu < level, float(meta["conformal_quantile"]), half)
        return half
    if bins is not None:
        return mondrian_half_width(mu, *bins)
    return float(meta["conformal_quantile"])
