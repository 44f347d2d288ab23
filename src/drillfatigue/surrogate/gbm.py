"""Gradient boosting on the surrogate's inputs: stopped on whole cases, monotone in dogleg.

Used as a baseline by the evaluation and, with ``surrogate.served_model: gbm``,
as the served model behind the same :class:`~drillfatigue.surrogate.Surrogate`
interface. Inputs are the ensemble's encoding (:func:`design_matrix`):
standardised numeric features and one-hot categorical levels.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
from sklearn.ensemble import HistGradientBoostingRegressor
from sklearn.model_selection import GroupShuffleSplit

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.surrogate.model import Preprocessor

#: inputs in which damage may not decrease (docs/surrogate.md, "Monotone in dogleg")
MONOTONE_FEATURES = ("local_dls_deg_per_30m", "local_max_dls_deg_per_30m")


def design_matrix(pre: Preprocessor, x_num: np.ndarray, x_cat: np.ndarray) -> np.ndarray:
    """Standardised numeric features then one-hot levels, shape (n, d)."""
    blocks = [(np.asarray(x_num, dtype=np.float64) - pre.mean_) / pre.scale_]
    for j, col in enumerate(pre.categorical):
        blocks.append((x_cat[:, j:j + 1] == np.arange(len(pre.categories_[col]))).astype(float))
    return np.hstack(blocks)


def monotone_constraints(pre: Preprocessor, features: Sequence[str] = MONOTONE_FEATURES
                         ) -> np.ndarray:
    """scikit-learn ``monotonic_cst`` over :func:`design_matrix` columns (1: non-decreasing)."""
    n = len(pre.numeric) + sum(len(pre.categories_[c]) for c in pre.categorical)
    cst = np.zeros(n, dtype=np.int64)
    for f in features:
        if f in pre.numeric:
            cst[pre.numeric.index(f)] = 1
    return cst


def _loss(y: np.ndarray, mu: np.ndarray, censor_below: float | None) -> float:
    """Mean squared error; a censored row (y <= level) only counts mu above the level."""
    if censor_below is None:
        return float(np.mean((mu - y) ** 2))
    err = np.where(y <= censor_below, np.maximum(mu - censor_below, 0.0), mu - y)
    return float(np.mean(err**2))


def fit_gbm(x: np.ndarray, y: np.ndarray, groups: np.ndarray, cfg: SurrogateConfig,
            monotone: np.ndarray | None = None) -> tuple[HistGradientBoostingRegressor,
                                                          dict[str, Any]]:
    """Gradient boosting with early stopping on whole cases.

    scikit-learn's own early stopping holds out random rows, so rows of one
    case land on both sides and the stopping point is set by near-copies of
    training rows. Here a seeded fraction ``cfg.validation_fraction`` of the
    training *cases* is held out (``GroupShuffleSplit`` on ``groups``); the
    model is grown to ``cfg.hgb_max_iter`` trees on the rest, the number of
    trees with the least validation loss (squared error; a censored row, life
    beyond ``cfg.horizon_h``, counts only a prediction above its level, as in
    the ensemble's validation) is kept, and the model is refitted with that
    many trees on all training rows.

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Encoded inputs (:func:`design_matrix`).
    y : ndarray, shape (n,)
        log10 damage rate per hour.
    groups : ndarray, shape (n,)
        Case id per row.
    cfg : SurrogateConfig
    monotone : ndarray of int, shape (d,), optional
        scikit-learn ``monotonic_cst`` (1: non-decreasing in that input).

    Returns
    -------
    model, info
        The refitted ``HistGradientBoostingRegressor``; ``info`` with
        ``n_iter`` (trees kept), ``val_loss`` (its validation loss) and
        ``n_val_cases``.
    """
    censor = -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None
    kw = {"random_state": cfg.split_seed, "early_stopping": False,
          "monotonic_cst": None if monotone is None else list(map(int, monotone))}
    split = GroupShuffleSplit(n_splits=1, test_size=cfg.validation_fraction,
                              random_state=cfg.split_seed)
    fit_i, val_i = next(split.split(x, y, groups))
    probe = HistGradientBoostingRegressor(max_iter=cfg.hgb_max_iter, **kw).fit(x[fit_i], y[fit_i])
    losses = [_loss(y[val_i], mu, censor) for mu in probe.staged_predict(x[val_i])]
    best = int(np.argmin(losses)) + 1
    model = HistGradientBoostingRegressor(max_iter=best, **kw).fit(x, y)
    return model, {"n_iter": best, "val_loss": float(losses[best - 1]),
                   "n_val_cases": int(pd.unique(groups[val_i]).size)}
