"""Adaptive design: a space-filling start, then batches where an ensemble disagrees most.

``sweep.method: adaptive`` (settings :class:`drillfatigue.config.sweep.AdaptiveConfig`):

1. ``n_initial`` scrambled Sobol cases (seed ``sweep.seed``; the first
   cases of the plain Sobol design of that seed) are simulated and evaluated
   (round 0).
2. Each round fits ``n_members`` gradient-boosting models, each on a bootstrap
   resample of the finished cases, to the case-level target the served model
   is judged on: the governing (largest) log10 damage rate per component type,
   censored at the horizon (a rate below ``-log10 horizon_h`` is "longer than
   the horizon" and counts as the horizon's rate). Inputs: the case's point in
   the unit design cube (numeric variables as their unit coordinate,
   categorical ones one-hot, scaled by 1/sqrt(2) so that a change of level is
   a distance of 1, like a full range of a numeric variable).
3. A seeded Sobol pool of ``candidates`` points (seed ``adaptive.seed +
   round``) is scored by the members' disagreement: the standard deviation
   over members of the prediction clipped at the horizon, summed over
   component types (a dispute about a life beyond the horizon scores zero:
   it changes no answer a user gets).
4. Diversity: among the ``pool_factor * batch_size`` most disputed
   candidates, the most disputed one is taken first, then greedily the one
   farthest from every case already in the design or the batch (max-min
   distance in the scaled unit cube), so one disputed region does not take the
   whole batch.
5. The batch is simulated and evaluated; rounds repeat until ``n_cases``.

Determinism and resumption: every random choice is seeded, and the
simulations are bit-for-bit reproducible, so a rerun makes the same choices.
The target function caches each finished case by its id (the sweep folders of
:func:`drillfatigue.sweep.stages.adaptive_targets`): after an interruption the design is rebuilt from
the start, the finished cases are read back instead of simulated, and the
design continues where it stopped.

References
----------
Settles, B. (2012). Active Learning, ch. 3 (query by committee).
Brinker, K. (2003). Incorporating diversity in active learning with support
vector machines. ICML (max-min diversity in batch selection).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd
from pydantic import BaseModel
from sklearn.ensemble import GradientBoostingRegressor

from drillfatigue.config import CaseConfig
from drillfatigue.config.sweep import AdaptiveConfig, SweepConfig
from drillfatigue.sweep.design import DesignSpace, design_space, sobol_unit

__all__ = ["ADAPTIVE_KIND", "TargetFn", "acquisition_scores", "adaptive_design",
           "case_targets", "diverse_batch", "unit_features"]

#: Kind of the ownership marker of the adaptive design's cache folder.
ADAPTIVE_KIND = "adaptive_design"
#: ``target_fn(cases) -> DataFrame``: index ``case_id`` (every case of ``cases``), one
#: column per target (log10 governing damage rate per hour of a component type), NaN for a
#: failed case or a component type the case has no row of.
TargetFn = Callable[[pd.DataFrame], pd.DataFrame]


def unit_features(space: DesignSpace, unit: np.ndarray) -> np.ndarray:
    """Scaled design-cube coordinates of unit points (n, dim): see the module doc, step 2."""
    blocks = []
    for j, path in enumerate(space.names):
        spec = space.cfg.variables[path]
        u = unit[:, j]
        if spec.choices is None:
            blocks.append(u[:, None])
        else:
            k = len(spec.choices)
            idx = np.minimum((u * k).astype(np.int64), k - 1)
            blocks.append((idx[:, None] == np.arange(k)).astype(np.float64) / math.sqrt(2.0))
    if not blocks:
        return np.zeros((unit.shape[0], 0))
    return np.hstack(blocks)


def acquisition_scores(x: np.ndarray, y: np.ndarray, x_cand: np.ndarray, *, n_members: int,
                       seed: int, censor_log10: float | None) -> np.ndarray:
    """Disagreement of a bootstrap ensemble of gradient boosting at the candidates.

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Scaled unit coordinates of the finished cases.
    y : ndarray, shape (n, k)
        Targets (NaN: missing, left out of that target's fit).
    x_cand : ndarray, shape (m, d)
    n_members : int
        Bootstrap members (each a resample of the cases with replacement).
    seed : int
    censor_log10 : float or None
        Targets and predictions below it count as it (the horizon's rate).

    Returns
    -------
    ndarray, shape (m,)
        Sum over targets of the standard deviation over members.
    """
    rng = np.random.default_rng(seed)
    score = np.zeros(x_cand.shape[0])
    y = np.asarray(y, dtype=np.float64).reshape(x.shape[0], -1)
    for t in range(y.shape[1]):
        ok = np.isfinite(y[:, t])
        if ok.sum() < 2:
            continue
        xt, yt = x[ok], y[ok, t]
        if censor_log10 is not None:
            yt = np.maximum(yt, censor_log10)
        preds = np.empty((n_members, x_cand.shape[0]))
        for m in range(n_members):
            idx = rng.integers(0, xt.shape[0], xt.shape[0])
            # small trees, few cases per leaf: the ensemble is fitted on 10-100 cases
            # (the classic booster: ~10x faster than the histogram one at this size)
            model = GradientBoostingRegressor(
                n_estimators=100, learning_rate=0.1, max_depth=3, min_samples_leaf=2,
                random_state=int(rng.integers(0, 2**31 - 1)))
            preds[m] = model.fit(xt[idx], yt[idx]).predict(x_cand)
        if censor_log10 is not None:
            preds = np.maximum(preds, censor_log10)
        score += preds.std(axis=0)
    return score


def diverse_batch(x_cand: np.ndarray, score: np.ndarray, x_design: np.ndarray, n: int,
                  pool_size: int) -> np.ndarray:
    """Indices of ``n`` candidates: module doc, step 4.

    The first is the most disputed candidate; each next one maximises the
    smallest distance to the design points ``x_design`` and the candidates
    already chosen, among the ``pool_size`` most disputed (ties: the more
    disputed). The choice does not depend on ``n`` beyond its length: a
    shorter batch is the start of a longer one.
    """
    n = min(n, x_cand.shape[0])
    pool_n = min(x_cand.shape[0], max(n, pool_size))
    order = np.lexsort((np.arange(score.size), -score))  # most disputed first, stable
    pool = order[:pool_n]
    chosen = [int(pool[0])]
    ref = np.vstack([x_design, x_cand[pool[:1]]]) if x_design.size else x_cand[pool[:1]]
    dmin = np.min(np.linalg.norm(x_cand[pool][:, None, :] - ref[None, :, :], axis=2), axis=1)
    dmin[0] = -np.inf
    while len(chosen) < n:
        j = int(np.argmax(dmin))  # argmax takes the first maximum: the more disputed
        chosen.append(int(pool[j]))
        d_new = np.linalg.norm(x_cand[pool] - x_cand[pool[j]], axis=1)
        dmin = np.minimum(dmin, d_new)
        dmin[j] = -np.inf
    return np.asarray(chosen, dtype=np.int64)


def case_targets(rows: pd.DataFrame, target_column: str, floor_per_h: float,
                 group_column: str = "case_id") -> pd.DataFrame:
    """Governing log10 damage rate per hour per case and component type.

    ``rows``: dataset rows (:func:`drillfatigue.sweep.dataset.build_dataset`);
    zero or missing rates count as ``floor_per_h`` (as the surrogate's target).
    """
    rate = pd.to_numeric(rows[target_column], errors="coerce").fillna(0.0).to_numpy()
    y = np.log10(np.maximum(rate, floor_per_h))
    kind = rows["component_type"].astype(str) if "component_type" in rows else "all"
    table = pd.DataFrame({"case_id": rows[group_column].astype(str).to_numpy(), "kind": kind,
                          "y": y}).pivot_table(index="case_id", columns="kind", values="y",
                                               aggfunc="max")
    table.columns = [f"log10_governing_rate_per_h_{c}" for c in table.columns]
    return table


def adaptive_design(cfg: SweepConfig, base_case: dict[str, Any], target_fn: TargetFn, *,
                    censor_log10: float | None, model: type[BaseModel] = CaseConfig,
                    on_round: Callable[[int, pd.DataFrame], None] | None = None
                    ) -> pd.DataFrame:
    """Build the adaptive design (module doc); return the case table with a ``round`` column.

    Parameters
    ----------
    cfg : SweepConfig
        ``n_cases`` (total), ``seed`` (initial Sobol design), ``variables``,
        ``adaptive`` (the rounds).
    base_case : dict
        The base case (see :func:`drillfatigue.sweep.design.base_case_from_params`).
    target_fn : TargetFn
        Simulates and evaluates the cases given (cached by case id for
        resumption: :func:`drillfatigue.sweep.stages.adaptive_targets`); called once per round with that
        round's new cases, then the targets of every case so far are used.
    censor_log10 : float or None
        log10 damage rate per hour at the horizon (None: no censoring).
    model : pydantic model class
        Model every case must satisfy (tests pass a stand-in).
    on_round : callable, optional
        ``on_round(round, cases_so_far)`` after each round is evaluated.

    Returns
    -------
    DataFrame
        The columns of :func:`drillfatigue.sweep.design.design_cases` plus
        ``round`` (0: the initial design) and ``acquisition_score`` (the
        disagreement when chosen; NaN in round 0); at most ``n_cases`` rows
        (fewer only if the pools hold no new case).
    """
    ad: AdaptiveConfig = cfg.adaptive
    space = design_space(cfg, base_case, model=model)
    d = space.dim
    unit0 = sobol_unit(ad.n_initial, d, cfg.seed, "sweep.adaptive.n_initial")
    frame = space.cases(unit0).head(cfg.n_cases)
    units = [unit0[frame["design_index"].to_numpy()]]
    frame = frame.assign(round=0, acquisition_score=np.nan)
    targets = target_fn(frame)
    next_index = unit0.shape[0]
    rnd = 0
    if on_round is not None:
        on_round(rnd, frame)
    while len(frame) < cfg.n_cases and d > 0:
        rnd += 1
        x = unit_features(space, np.vstack(units))
        y = targets.reindex(frame["case_id"]).to_numpy(dtype=np.float64)
        pool_unit = sobol_unit(ad.candidates, d, ad.seed + rnd, "sweep.adaptive.candidates")
        pool = space.cases(pool_unit, first_index=next_index, skip=set(frame["case_id"]))
        next_index += pool_unit.shape[0]
        if not len(pool):
            break
        pool_u = pool_unit[pool["design_index"].to_numpy() - (next_index - pool_unit.shape[0])]
        x_cand = unit_features(space, pool_u)
        score = acquisition_scores(x, y, x_cand, n_members=ad.n_members, seed=ad.seed + rnd,
                                   censor_log10=censor_log10)
        n_new = min(ad.batch_size, cfg.n_cases - len(frame))
        pick = diverse_batch(x_cand, score, x, n_new, math.ceil(ad.pool_factor * ad.batch_size))
        batch = pool.iloc[pick].assign(round=rnd, acquisition_score=score[pick])
        units.append(pool_u[pick])
        targets = pd.concat([targets, target_fn(batch.drop(columns=["round",
                                                                    "acquisition_score"]))])
        frame = pd.concat([frame, batch], ignore_index=True)
        if on_round is not None:
            on_round(rnd, frame)
    frame = frame.reset_index(drop=True)
    frame.attrs["design"] = {"method": "adaptive", "seed": cfg.seed,
                             "boundaries": cfg.boundaries, "n_requested": cfg.n_cases,
                             "n_initial": int((frame["round"] == 0).sum()), "n_rounds": rnd,
                             "adaptive": ad.model_dump(mode="json")}
    return frame
