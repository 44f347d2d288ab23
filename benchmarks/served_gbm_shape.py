"""Is the served gradient boosting's shape what limits its factor 2? Loss and trees at research scale.

Reads a research-scale run (read-only: its ``params.yaml`` surrogate section,
its training and held-out datasets) and fits the served gradient boosting's
regressor on the served encoding (the inputs of ``surrogate.features``, the
monotone constraints in dogleg severity, early stopping on whole cases as
:func:`drillfatigue.surrogate.gbm.fit_gbm` does) in variants of its loss and
of its trees: out of fold over ``surrogate.conformal_folds`` folds of whole
training cases and on the held-out design, scored on the deciding rows
(:func:`drillfatigue.surrogate.evaluation.deciding_metrics`, as
``benchmarks/stick_slip_state.py`` scores them).

Variants (scikit-learn ``HistGradientBoostingRegressor`` arguments; ``max_iter``
is the tree cap the early stopping searches under):

- ``served``: the defaults (squared error, 31 leaves, at least 20 rows a
  leaf, learning rate 0.1, ``surrogate.hgb_max_iter`` trees at most);
- ``absolute_error``: the median instead of the mean (a bimodal conditional
  distribution, as in the cases that may settle in either torsional state,
  has its mean between the modes and its median on the larger one); early
  stopping on the validation factor 2;
- smaller steps and more trees, bigger or smaller trees, fewer or more rows
  a leaf, L2 regularisation, half the inputs per split.

Usage: ``python benchmarks/served_gbm_shape.py --research /work/research
[--out benchmarks/results/served_gbm_shape.json] [--variants a,b]``
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from sklearn.ensemble import HistGradientBoostingRegressor
from sklearn.model_selection import GroupShuffleSplit

from drillfatigue.config import load_params
from drillfatigue.surrogate.data import case_folds, log10_target
from drillfatigue.surrogate.gbm import design_matrix, monotone_constraints
from drillfatigue.surrogate.io import write_json
from drillfatigue.surrogate.model import Preprocessor

sys.path.insert(0, str(Path(__file__).parent))
from stick_slip_state import _score  # noqa: E402  (the deciding-row score of that benchmark)

RESULT = Path(__file__).parent / "results" / "served_gbm_shape.json"
LOG10_2 = math.log10(2.0)
#: name -> HistGradientBoostingRegressor arguments over the served ones (``max_iter``: the cap)
VARIANTS: dict[str, dict[str, Any]] = {
    "served": {},
    "absolute_error": {"loss": "absolute_error"},
    "learning_rate_0.05_1000_trees": {"learning_rate": 0.05, "max_iter": 1000},
    "63_leaves_40_rows": {"max_leaf_nodes": 63, "min_samples_leaf": 40},
    "63_leaves_40_rows_1000_trees": {"max_leaf_nodes": 63, "min_samples_leaf": 40,
                                     "max_iter": 1000},
    "63_leaves_20_rows_1000_trees": {"max_leaf_nodes": 63, "min_samples_leaf": 20,
                                     "max_iter": 1000},
    "15_leaves": {"max_leaf_nodes": 15},
    "10_rows_a_leaf": {"min_samples_leaf": 10},
    "100_rows_a_leaf": {"min_samples_leaf": 100},
    "l2_10": {"l2_regularization": 10.0},
    "half_the_inputs_per_split": {"max_features": 0.5},
}


def fit_variant(x: np.ndarray, y: np.ndarray, groups: np.ndarray, cfg: Any,
                monotone: list[int], args: dict[str, Any]) -> tuple[Any, int]:
    """Early stopping on whole cases, then a refit on all rows with the trees kept.

    The validation cases are :func:`~drillfatigue.surrogate.gbm.fit_gbm`'s; the
    stopping point is the least squared error (squared-error loss) or the
    highest factor-2 share (any other loss, whose mean it does not predict).
    """
    kw = {"random_state": cfg.split_seed, "early_stopping": False, "monotonic_cst": monotone,
          **{k: v for k, v in args.items() if k != "max_iter"}}
    cap = int(args.get("max_iter", cfg.hgb_max_iter))
    split = GroupShuffleSplit(n_splits=1, test_size=cfg.validation_fraction,
                              random_state=cfg.split_seed)
    fit_i, val_i = next(split.split(x, y, groups))
    probe = HistGradientBoostingRegressor(max_iter=cap, **kw).fit(x[fit_i], y[fit_i])
    yv = y[val_i]
    if kw.get("loss", "squared_error") == "squared_error":
        losses = [float(np.mean((yv - p) ** 2)) for p in probe.staged_predict(x[val_i])]
    else:
        losses = [-float(np.mean(np.abs(yv - p) < LOG10_2))
                  for p in probe.staged_predict(x[val_i])]
    best = int(np.argmin(losses)) + 1
    return HistGradientBoostingRegressor(max_iter=best, **kw).fit(x, y), best


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--research", required=True, help="a research-scale run's folder")
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--variants", default=",".join(VARIANTS))
    args = ap.parse_args(argv)
    names = args.variants.split(",")
    unknown = [n for n in names if n not in VARIANTS]
    if unknown:
        print(f"error: --variants: unknown {unknown}; allowed: {', '.join(VARIANTS)}",
              file=sys.stderr)
        return 2
    r = Path(args.research)
    cfg = load_params(r / "params.yaml").surrogate
    tr = pd.read_parquet(r / "data/dataset/damage.parquet")
    te = pd.read_parquet(r / "data/heldout/dataset/damage.parquet")
    ytr = log10_target(tr[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    yte = log10_target(te[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    pre = Preprocessor(list(cfg.features), cfg.categorical).fit(tr)
    x = design_matrix(pre, pre.numeric_array(tr), pre.category_codes(tr))
    xt = design_matrix(pre, pre.numeric_array(te), pre.category_codes(te))
    mono = [int(v) for v in monotone_constraints(pre)]
    g = tr["case_id"].to_numpy()
    folds = case_folds(g, cfg.conformal_folds, cfg.split_seed)
    res: dict[str, Any] = {
        "command": f"python benchmarks/served_gbm_shape.py --research {args.research}",
        "date": time.strftime("%Y-%m-%d"), "machine": platform.machine(),
        "n_train_cases": int(pd.unique(g).size),
        "n_heldout_cases": int(te["case_id"].nunique()), "variants": {}}
    for name in names:
        t0 = time.perf_counter()
        oof = np.empty(len(ytr))
        trees = []
        for k in np.unique(folds):
            t = folds != k
            m, n_trees = fit_variant(x[t], ytr[t], g[t], cfg, mono, VARIANTS[name])
            oof[~t] = m.predict(x[~t])
            trees.append(n_trees)
        m, n_trees = fit_variant(x, ytr, g, cfg, mono, VARIANTS[name])
        res["variants"][name] = {
            "arguments": VARIANTS[name], "trees_kept": n_trees,
            "trees_kept_per_fold": trees,
            "out_of_fold": _score(tr, ytr, oof, cfg.horizon_h),
            "heldout": _score(te, yte, m.predict(xt), cfg.horizon_h),
            "wall_s": round(time.perf_counter() - t0, 1)}
        print(name, json.dumps(res["variants"][name]), flush=True)
    write_json(res, args.out)  # atomic: no half-written result under the final name
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
