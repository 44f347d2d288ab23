"""Baselines of the leaderboard: fitted on the train split, predicting the held-out split.

Each baseline returns a prediction table in the format that
:mod:`drillfatigue.benchmark.score` scores (keys, ``log10_damage_rate_per_h``
and a conformal interval where the model has one):

- ``gbm``: the gradient boosting as served (:func:`drillfatigue.surrogate.served_gbm.fit_served_gbm`):
  every training case, early stopping on whole cases, non-decreasing in the
  dogleg inputs, cross-conformal interval by case scaled per query;
- ``ensemble``: the torch deep ensemble as the ``train`` stage fits it
  (:class:`drillfatigue.surrogate.model.DeepEnsembleRegressor`, censored
  Gaussian likelihood), split-conformal interval on calibration cases set
  apart from the train split (``surrogate.calibration_fraction`` of its cases);
- ``gp``: the Gaussian process of the evaluation
  (:func:`drillfatigue.surrogate.evaluation.fit_gp`), same calibration cases;
- ``physics``: no training. API RP7G / Lubinski bending of pipe rotating in a
  dogleg (:func:`drillfatigue.fatigue.rp7g.lubinski_bending_stress_Pa`) under
  the soft-string drilling tension of the case
  (:func:`drillfatigue.softstring.torque_drag.torque_drag_for_case`), at each
  row's hole curvature, with the case's S-N curve, stress concentration and
  Goodman correction of the location; one fully reversed cycle per revolution
  (docs/fatigue.md#api-rp7g). It needs the held-out cases' configurations
  (the design's ``case_json``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.benchmark.score import LOWER, PREDICTION, UPPER
from drillfatigue.benchmark.splits import GROUP_COLUMN, KEY_COLUMNS
from drillfatigue.config import CaseConfig, FatigueConfig
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate.conformal import SplitConformal
from drillfatigue.surrogate.data import check_columns, log10_target
from drillfatigue.surrogate.evaluation import fit_gp
from drillfatigue.surrogate.facade import censor_level, regressor_from_config
from drillfatigue.surrogate.gbm import design_matrix, monotone_constraints
from drillfatigue.surrogate.model import Preprocessor
from drillfatigue.surrogate.served_gbm import (fit_served_gbm, half_width, interval_bins,
                                               interval_scale)

#: Young's modulus of steel for the physics baseline, Pa (the string's default material).
E_STEEL_PA = 207e9
#: Half the distance between tool joints of the RP7G formula (180 in), m.
HALF_JOINT_SPACING_M = 4.572
#: Seconds per minute and per hour: rpm -> revolutions per hour.
_REV_PER_H_PER_RPM = 60.0
_RAD_PER_M_PER_DEG_PER_30M = math.pi / 180.0 / 30.0


#: Inputs the tuned ensemble also sees on a log scale: column -> offset added before log10
#: (same unit as the column). Damage grows as a power of speed and bending, and the
#: distance from the bit spans three decades; a log scale makes those near-linear.
LOG_FEATURES: dict[str, float] = {"s_from_bit_m": 1.0, "operation.rpm": 0.0,
                                  "local_dls_deg_per_30m": 0.1,
                                  "local_max_dls_deg_per_30m": 0.1}


def log_feature_name(column: str) -> str:
    """Name of the derived column ``log10(column + offset)``."""
    return f"log10_{column}"


def add_log_features(frame: pd.DataFrame) -> pd.DataFrame:
    """``frame`` with the :data:`LOG_FEATURES` columns added (``log10_<column>``)."""
    out = frame.copy()
    for col, offset in LOG_FEATURES.items():
        values = out[col].to_numpy(dtype=np.float64) + offset
        if np.any(values <= 0):
            raise InputError(col, f"a value <= {-offset} has no log", f"> {-offset}")
        out[log_feature_name(col)] = np.log10(values)
    return out


def prediction_table(heldout: pd.DataFrame, mu: np.ndarray, lower: np.ndarray | None = None,
                     upper: np.ndarray | None = None) -> pd.DataFrame:
    """Keys of the held-out rows with a prediction (and interval), log10 rate per hour."""
    out = heldout[list(KEY_COLUMNS)].reset_index(drop=True).copy()
    out[PREDICTION] = np.asarray(mu, dtype=np.float64)
    if lower is not None and upper is not None:
        out[LOWER] = np.asarray(lower, dtype=np.float64)
        out[UPPER] = np.asarray(upper, dtype=np.float64)
    return out


def _target(frame: pd.DataFrame, cfg: SurrogateConfig) -> np.ndarray:
    return log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)


def calibration_cases(groups: np.ndarray, cfg: SurrogateConfig) -> np.ndarray:
    """Rows of the calibration cases: ``cfg.calibration_fraction`` of the cases (at
    least one), drawn with ``cfg.split_seed``; shape (n,) bool."""
    g = np.asarray(groups).astype(str)
    cases = np.unique(g)
    if cases.size < 3:
        raise InputError("train split", f"only {cases.size} case(s)",
                         ">= 3 cases (training and calibration cases)")
    n_cal = max(1, int(round(cfg.calibration_fraction * cases.size)))
    cal = np.random.default_rng(cfg.split_seed).permutation(cases)[:n_cal]
    return np.isin(g, cal)


def _preprocessor(train: pd.DataFrame, cfg: SurrogateConfig) -> Preprocessor:
    return Preprocessor(cfg.features, cfg.categorical).fit(train)


def _design(pre: Preprocessor, frame: pd.DataFrame) -> np.ndarray:
    return design_matrix(pre, pre.numeric_array(frame), pre.category_codes(frame))


def fit_predict_gbm(train: pd.DataFrame, heldout: pd.DataFrame, cfg: SurrogateConfig
                    ) -> pd.DataFrame:
    """The served gradient boosting fitted on every training case (cross-conformal)."""
    check_columns(train, cfg)
    pre = _preprocessor(train, cfg)
    x = _design(pre, train)
    y = _target(train, cfg)
    fit = np.ones(len(train), dtype=bool)
    model, meta = fit_served_gbm(x, y, train[cfg.group_column].to_numpy(), fit, None, cfg,
                                 monotone_constraints(pre))
    x_h = _design(pre, heldout)
    mu = model.predict(x_h)
    half = half_width(mu, meta, interval_bins(meta), interval_scale(model, x_h))
    return prediction_table(heldout, mu, mu - half, mu + half)


def fit_predict_ensemble(train: pd.DataFrame, heldout: pd.DataFrame, cfg: SurrogateConfig
                         ) -> pd.DataFrame:
    """The torch deep ensemble with a split-conformal interval on calibration cases.

    Features named ``log10_<column>`` (:data:`LOG_FEATURES`) are derived from
    their columns first (:func:`add_log_features`).
    """
    if any(f.startswith("log10_") for f in cfg.features):
        train, heldout = add_log_features(train), add_log_features(heldout)
    check_columns(train, cfg)
    groups = train[cfg.group_column].to_numpy()
    cal = calibration_cases(groups, cfg)
    y = _target(train, cfg)
    reg = regressor_from_config(cfg)
    reg.fit(train.loc[~cal], y[~cal], groups=groups[~cal])
    mu_c, sd_c = reg.predict_dist(train.loc[cal])
    conf = SplitConformal(cfg.coverage).fit(mu_c, sd_c, y[cal], censor_below=censor_level(cfg))
    mu, sd = reg.predict_dist(heldout)
    lo, hi = conf.interval(mu, sd)
    return prediction_table(heldout, mu, lo, hi)


def fit_predict_gp(train: pd.DataFrame, heldout: pd.DataFrame, cfg: SurrogateConfig
                   ) -> pd.DataFrame:
    """The evaluation's Gaussian process, split-conformal on calibration cases."""
    check_columns(train, cfg)
    cal = calibration_cases(train[cfg.group_column].to_numpy(), cfg)
    pre = _preprocessor(train.loc[~cal], cfg)
    x, y = _design(pre, train), _target(train, cfg)
    gp, _ = fit_gp(x[~cal], y[~cal], cfg)
    mu_c, sd_c = gp.predict(x[cal], return_std=True)
    conf = SplitConformal(cfg.coverage).fit(mu_c, np.maximum(sd_c, 1e-9), y[cal],
                                            censor_below=censor_level(cfg))
    mu, sd = gp.predict(_design(pre, heldout), return_std=True)
    lo, hi = conf.interval(mu, np.maximum(sd, 1e-9))
    return prediction_table(heldout, mu, lo, hi)


def case_configs(design: pd.DataFrame) -> dict[str, CaseConfig]:
    """Case id -> validated case configuration, from a design table (``case_id``,
    ``case_json``: the research sweep's ``cases.parquet``)."""
    for col in (GROUP_COLUMN, "case_json"):
        if col not in design.columns:
            raise InputError("--design", f"column {col!r} missing",
                             "the design's cases.parquet (case_id, case_json)")
    return {str(c): CaseConfig.model_validate(json.loads(text))
            for c, text in zip(design[GROUP_COLUMN], design["case_json"], strict=True)}


def physics_log10_rate(rows: pd.DataFrame, case: CaseConfig, fatigue: FatigueConfig
                       ) -> np.ndarray:
    """RP7G / Lubinski log10 damage rate per hour of one case's rows.

    Parameters
    ----------
    rows : DataFrame
        Rows of one case: ``md_m``, ``s_from_bit_m``, ``local_dls_deg_per_30m``,
        ``component_type``, ``location`` (body, connection or upset) and
        ``operation.wob_N`` (the weight on bit of the drilling tension; without
        it, the case's own: :func:`~drillfatigue.softstring.torque_drag.torque_drag_for_case`).
    case : CaseConfig
        The case's configuration (well, string, operation, friction).
    fatigue : FatigueConfig
        S-N curves, stress concentration factors and grade of the locations.

    Returns
    -------
    ndarray, shape (len(rows),)
        log10 of rpm x 60 / N(S) per hour, S the stress range 2 SCF sigma_b at
        the location (Goodman on the soft-string tension stress), N from the
        location's S-N curve; the moment E I K L / tanh(K L) kappa of the pipe
        body (Lubinski) acts on the location's section. A rate of zero (no
        curvature, or below the curve's endurance) is returned as -inf.
    """
    # start-up: the physics baseline alone loads the simulator's soft-string model
    from drillfatigue.softstring.torque_drag import torque_drag_for_case
    from drillfatigue.fatigue.rp7g import lubinski_bending_stress_Pa
    from drillfatigue.fatigue.run import build_curve
    from drillfatigue.fatigue.sn import correct_mean_stress, get_grade
    from drillfatigue.string import build_segments

    wob = (float(rows["operation.wob_N"].iloc[0]) if "operation.wob_N" in rows.columns
           else None)
    td = torque_drag_for_case(case, wob_N=wob)
    seg = build_segments(case.string, case.operation.mud_density_kg_per_m3)
    fat = fatigue
    ultimate = get_grade(fat.grade).tensile_Pa
    order = np.argsort(td.md_m)
    tension = np.clip(np.interp(rows["md_m"].to_numpy(float), td.md_m[order],
                                td.tension_drilling_N[order]), 0.0, None)
    kappa = rows["local_dls_deg_per_30m"].to_numpy(float) * _RAD_PER_M_PER_DEG_PER_30M
    s = rows["s_from_bit_m"].to_numpy(float)
    j = np.abs(seg.joint_s_from_bit_m[None, :] - s[:, None]).argmin(axis=1)
    out = np.empty(len(rows))
    rpm = abs(float(case.operation.rpm))
    curves: dict[str, Any] = {}
    for i, (loc, ctype) in enumerate(zip(rows["location"].astype(str),
                                         rows["component_type"].astype(str), strict=True)):
        od_b, id_b = float(seg.body_od_m[j[i]]), float(seg.body_id_m[j[i]])
        od, idm = ((float(seg.conn_od_m[j[i]]), float(seg.conn_id_m[j[i]]))
                   if loc == "connection" else (od_b, id_b))
        i_b = math.pi * (od_b**4 - id_b**4) / 64.0
        i_l = math.pi * (od**4 - idm**4) / 64.0
        area = math.pi * (od**2 - idm**2) / 4.0
        sigma_body = float(lubinski_bending_stress_Pa(E_STEEL_PA, od_b, kappa[i], tension[i],
                                                      i_b, HALF_JOINT_SPACING_M))
        sigma = sigma_body * (od / od_b) * (i_b / i_l)  # the same moment on the location
        where = loc if loc in ("body", "connection", "upset") else "body"
        scf = float(getattr(fat.scf[ctype], where).bending) if ctype in fat.scf else 1.0
        if where not in curves:
            curves[where] = build_curve(getattr(fat, where).curve, fat.effective_environment)
        S = correct_mean_stress(np.array([2.0 * scf * sigma]), np.array([tension[i] / area]),
                                "goodman", ultimate)
        n = float(curves[where].cycles_to_failure(S)[0])
        rate = rpm * _REV_PER_H_PER_RPM / n if n > 0 and math.isfinite(n) else 0.0
        out[i] = math.log10(rate) if rate > 0 else -math.inf
    return out


def predict_physics(heldout: pd.DataFrame, design: pd.DataFrame, cfg: SurrogateConfig,
                    fatigue: FatigueConfig) -> pd.DataFrame:
    """The physics baseline on every held-out row (no training, no interval).

    A rate below the censoring floor (or zero) is answered at the floor, as the
    target is floored (``surrogate.rate_floor_per_h``).
    """
    cases = case_configs(design)
    missing = sorted(set(heldout[GROUP_COLUMN].astype(str)) - set(cases))
    if missing:
        raise InputError("--design", f"{len(missing)} held-out case(s) not in the design, "
                         f"e.g. {missing[0]}", "the held-out split's design (case_json)")
    mu = np.empty(len(heldout))
    ids = heldout[GROUP_COLUMN].astype(str).to_numpy()
    for case_id in pd.unique(ids):
        sel = ids == case_id
        mu[sel] = physics_log10_rate(heldout.loc[sel], cases[case_id], fatigue)
    mu = np.maximum(mu, math.log10(cfg.rate_floor_per_h))
    return prediction_table(heldout, mu)


#: Fitted baselines: name -> function(train, heldout, cfg) -> prediction table.
FITTED: dict[str, Callable[[pd.DataFrame, pd.DataFrame, SurrogateConfig], pd.DataFrame]] = {
    "gbm": fit_predict_gbm, "ensemble": fit_predict_ensemble, "gp": fit_predict_gp}
