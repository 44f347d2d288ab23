"""Score a model's prediction file on the held-out split with the project's metrics.

A prediction file (parquet, or CSV by suffix) has one row per held-out row:
``case_id``, ``joint``, ``location`` (the row's keys), ``log10_damage_rate_per_h``
(the predicted log10 Miner damage per hour of rotation) and, optionally, an
interval ``log10_damage_rate_per_h_lower`` / ``_upper`` (both or neither).
Every held-out row must be predicted once; nothing else may be in the file.

The metrics are those of the surrogate's evaluation (docs/surrogate.md),
computed by the same functions on the target floored at the censoring floor:

- **deciding rows** (:func:`drillfatigue.surrogate.evaluation.deciding_metrics`):
  the rows whose *predicted* life is within the horizon, what a user reads as
  a number: factor-2 fraction, RMSE, interval coverage (also counting a row
  simulated beyond the horizon as covered once the interval reaches down to
  it), per decade of the simulated and of the predicted rate, per well profile,
  per component type and per component type and location; the "longer than
  the horizon" answers as a classification (precision, recall); the governing
  (largest) rate per case and component type;
- **governing** (:func:`drillfatigue.surrogate.evaluation.governing_metrics`):
  the per-case maximum and the rows whose *simulated* life is within the
  horizon, factor 2 per decade (:func:`drillfatigue.metrics.factor2_by_decade`);
- **all rows** (:func:`drillfatigue.surrogate.evaluation.score`): R², RMSE,
  MAE, factor 2 and coverage on every held-out row.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.benchmark.splits import KEY_COLUMNS
from drillfatigue.errors import InputError
from drillfatigue.surrogate.data import log10_target
from drillfatigue.surrogate.evaluation import deciding_metrics, governing_metrics, score

PREDICTION = "log10_damage_rate_per_h"
LOWER = f"{PREDICTION}_lower"
UPPER = f"{PREDICTION}_upper"
#: Columns every prediction file has.
PREDICTION_COLUMNS: tuple[str, ...] = (*KEY_COLUMNS, PREDICTION)
#: Held-out columns carried beside the predictions for the breakdowns.
_CONTEXT = ("well.profile", "string.bha", "component_type", "location", "s_from_bit_m")
_INTERVAL_KEYS = ("coverage", "mean_width", "coverage_censored")
#: Column name of the model inside the metrics functions.
_M = "model"


def read_predictions(path: str | Path, option: str = "--predictions") -> pd.DataFrame:
    """Read a prediction file (parquet, or CSV by suffix) and check its columns."""
    p = Path(path)
    if not p.is_file():
        raise InputError(option, f"{p} not found", "a prediction file (docs/dataset.md)")
    try:
        frame = pd.read_csv(p) if p.suffix.lower() == ".csv" else pd.read_parquet(p)
    except Exception as exc:  # pyarrow and pandas raise many kinds for a file that is not one
        raise InputError(option, f"{p} is not a readable parquet or CSV file "
                         f"({type(exc).__name__})", "parquet, or CSV by suffix") from None
    check_predictions(frame, option)
    return frame


def check_predictions(frame: pd.DataFrame, option: str = "--predictions") -> None:
    """Raise InputError for a missing column, a half interval, a value that is not a
    finite number, a lower bound above the upper one or a row given twice."""
    missing = [c for c in PREDICTION_COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(option, f"columns {missing} missing", ", ".join(PREDICTION_COLUMNS)
                         + f" (optional {LOWER}, {UPPER})")
    if (LOWER in frame.columns) != (UPPER in frame.columns):
        raise InputError(option, "an interval needs both bounds", f"{LOWER} and {UPPER}, or neither")
    for col in (PREDICTION, LOWER, UPPER):
        if col not in frame.columns:
            continue
        values = pd.to_numeric(frame[col], errors="coerce").to_numpy(dtype=np.float64)
        bad = ~np.isfinite(values)
        if bad.any():
            raise InputError(f"{option} {col}", f"{int(bad.sum())} value(s) missing, "
                             "not numbers or infinite", "finite log10 damage rates per hour")
    if LOWER in frame.columns and (frame[LOWER] > frame[UPPER]).any():
        raise InputError(option, f"{int((frame[LOWER] > frame[UPPER]).sum())} row(s) with "
                         "the lower bound above the upper", f"{LOWER} <= {UPPER}")
    dup = frame.duplicated(list(KEY_COLUMNS))
    if dup.any():
        first = frame.loc[dup, list(KEY_COLUMNS)].iloc[0].tolist()
        raise InputError(option, f"{int(dup.sum())} row(s) given twice, e.g. {first}",
                         "one prediction per case, joint and location")


def _keys(frame: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame({"case_id": frame["case_id"].astype(str).to_numpy(),
                         "joint": pd.to_numeric(frame["joint"]).astype(np.int64).to_numpy(),
                         "location": frame["location"].astype(str).to_numpy()})


def align(pred: pd.DataFrame, heldout: pd.DataFrame, option: str = "--predictions"
          ) -> pd.DataFrame:
    """The predictions in the held-out rows' order.

    Raises
    ------
    InputError
        A predicted row that is not a held-out row, or a held-out row without
        a prediction.
    """
    try:
        left = _keys(heldout)
        right = _keys(pred)
    except (TypeError, ValueError):
        raise InputError(f"{option} joint", "not an integer joint index",
                         "the held-out rows' joint") from None
    for col in (PREDICTION, LOWER, UPPER):
        if col in pred.columns:
            right[col] = pd.to_numeric(pred[col]).to_numpy(dtype=np.float64)
    both = left.merge(right, on=list(KEY_COLUMNS), how="outer", indicator=True)
    extra = both[both["_merge"] == "right_only"]
    if len(extra):
        first = extra[list(KEY_COLUMNS)].iloc[0].tolist()
        raise InputError(option, f"{len(extra)} row(s) not in the held-out split, e.g. {first}",
                         "the held-out split's case_id, joint and location")
    lacking = both[both["_merge"] == "left_only"]
    if len(lacking):
        first = lacking[list(KEY_COLUMNS)].iloc[0].tolist()
        raise InputError(option, f"{len(lacking)} held-out row(s) without a prediction, "
                         f"e.g. {first}", "every held-out row predicted")
    return left.merge(right, on=list(KEY_COLUMNS), how="left", validate="one_to_one")


def _strip_intervals(tree: Any) -> Any:
    if isinstance(tree, Mapping):
        return {k: _strip_intervals(v) for k, v in tree.items() if k not in _INTERVAL_KEYS}
    return tree


def score_predictions(pred: pd.DataFrame, heldout: pd.DataFrame, *, criterion: str = "matake",
                      rate_floor_per_h: float = 1e-12, horizon_h: float = 1e5,
                      option: str = "--predictions") -> dict[str, Any]:
    """The project's metrics of one prediction table on the held-out split.

    Parameters
    ----------
    pred : DataFrame
        :data:`PREDICTION_COLUMNS` and optionally the interval columns.
    heldout : DataFrame
        The held-out split (:func:`drillfatigue.benchmark.splits.load_split`).
    criterion : str
        Target: ``damage_rate_per_h_<criterion>``.
    rate_floor_per_h, horizon_h : float
        Censoring floor of the rate (1/h) and life horizon (h), as the
        surrogate's configuration (``surrogate.rate_floor_per_h``,
        ``surrogate.horizon_h``).

    Returns
    -------
    dict
        ``headline`` (the leaderboard's numbers), ``deciding``, ``governing``,
        ``all_rows`` and the scoring's settings; interval metrics only when the
        file has an interval.
    """
    check_predictions(pred, option)
    target = f"damage_rate_per_h_{criterion}"
    if target not in heldout.columns:
        raise InputError("--criterion", f"no column {target!r} in the held-out split",
                         ", ".join(c[len("damage_rate_per_h_"):] for c in heldout.columns
                                   if c.startswith("damage_rate_per_h_")))
    if not (horizon_h > 0 and rate_floor_per_h > 0):
        raise InputError("horizon_h, rate_floor_per_h", "must be > 0", "positive numbers")
    rows = align(pred, heldout, option)
    y = log10_target(heldout[target].to_numpy(), rate_floor_per_h)
    mu = rows[PREDICTION].to_numpy(dtype=np.float64)
    interval = LOWER in rows.columns
    lo = rows[LOWER].to_numpy(dtype=np.float64) if interval else mu
    hi = rows[UPPER].to_numpy(dtype=np.float64) if interval else mu
    table = pd.DataFrame({"case_id": rows["case_id"].to_numpy(), "y_true": y,
                          _M: mu, f"{_M}_lower": lo, f"{_M}_upper": hi})
    for col in _CONTEXT:
        if col in heldout.columns:
            table[col] = heldout[col].to_numpy()
    deciding = deciding_metrics(table, (_M,), horizon_h)[_M]
    governing = governing_metrics(table, (_M,), relevant_life_h=horizon_h)[_M]
    all_rows = score(y, mu, lo, hi)
    all_rows.pop("n", None)
    r = deciding["rows"]
    headline = {
        "factor2_deciding": r["factor2_fraction"], "n_deciding_rows": r["n"],
        "coverage_deciding": r.get("coverage_censored") if interval else None,
        "mean_width_deciding": r.get("mean_width") if interval else None,
        "rmse_deciding": r["rmse"],
        "factor2_governing_component": deciding["governing"]["factor2_fraction"],
        "n_governing_components": deciding["governing"]["n"],
        "factor2_case_max": governing["case_max"]["factor2_fraction"],
        "longer_than_precision": deciding["beyond_horizon"]["precision"],
        "longer_than_recall": deciding["beyond_horizon"]["recall"],
        "rmse_all": all_rows["rmse"], "r2_all": all_rows["r2"],
    }
    out: dict[str, Any] = {
        "criterion": criterion, "target": f"log10 max({target}, {rate_floor_per_h:g})",
        "rate_floor_per_h": float(rate_floor_per_h), "horizon_h": float(horizon_h),
        "n_rows": int(len(table)), "n_cases": int(table["case_id"].nunique()),
        "interval": interval,
        "censored_fraction": float(np.mean(y < -math.log10(horizon_h))),
        "headline": headline, "deciding": deciding, "governing": governing,
        "all_rows": all_rows,
    }
    return out if interval else _strip_intervals(out)
