"""Adaptive design: a space-filling start, then batches where an ensemble disagrees most.

``sweep.method: adaptive`` (settings :class:`drillfatigue.config.sweep.AdaptiveConfig`):

1. ``n_initial`` scrambled Sobol cases (seed ``sweep.seed``; the first
   cases of the plain Sobol design of that seed) are simulated and evaluated
   (round 0).
2. Each round fits ``n_members`` gradient-boosting models, each on a bootstrap
   resample of the finished cases, to the target of ``adaptive.acquisition``:

   - ``governing``: the case-level governing (largest) log10 damage rate per
     component type, censored at the horizon (a rate below ``-log10
     horizon_h`` is "longer than the horizon" and counts as the horizon's
     rate). Inputs: the case's point in the unit design cube (numeric
     variables as their unit coordinate, categorical ones one-hot, scaled by
     1/sqrt(2) so that a change of level is a distance of 1, like a full
     range of a numeric variable).
   - ``rows`` and ``mix``: the log10 damage rate of every row (case and
     location), the target the served model is fitted and judged on,
     censored the same way. Inputs: the surrogate's features
     (:func:`row_matrix`); the resample draws whole cases. A candidate's rows
     are built from its inputs (:func:`template_rows`).
3. A seeded Sobol pool of ``candidates`` points (seed ``adaptive.seed +
   round``) is scored by the members' disagreement: the standard deviation
   over members of the prediction clipped at the horizon (a dispute about a
   life beyond the horizon scores zero: it changes no answer a user gets),
   summed over component types (``governing``) or over the candidate's rows
   (``rows``, ``mix``: :func:`row_scores`).
4. Diversity: among the ``pool_factor * batch_size`` most disputed
   candidates, the most disputed one is taken first, then greedily the one
   farthest from every case already in the design or the batch (max-min
   distance in the scaled unit cube), so one disputed region does not take the
   whole batch. ``mix`` takes only ``1 - space_filling_share`` of the batch so,
   and the rest by max-min distance alone over the whole pool
   (:func:`space_filling_batch`): a share of every batch keeps filling the
   space whatever the ensemble disputes (:func:`choose_batch`).
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
Johnson, M. E., Moore, L. M., Ylvisaker, D. (1990). Minimax and maximin
distance designs. J. Stat. Plan. Inference 26, 131-148 (the max-min rule).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from pydantic import BaseModel
from sklearn.ensemble import GradientBoostingRegressor, HistGradientBoostingRegressor
from threadpoolctl import threadpool_limits

from drillfatigue.config import CaseConfig, case_from_dict
from drillfatigue.config.sweep import AdaptiveConfig, SweepConfig
from drillfatigue.errors import InputError
from drillfatigue.sweep.design import DesignSpace, design_space, sobol_unit
from drillfatigue.well import build_survey
from drillfatigue.well.features import survey_features

__all__ = ["ADAPTIVE_KIND", "ACQUISITIONS", "RowSource", "TargetFn", "acquisition_scores",
           "adaptive_design", "case_targets", "choose_batch", "diverse_batch", "row_matrix",
           "row_scores", "space_filling_batch", "template_rows", "unit_features"]

#: Kind of the ownership marker of the adaptive design's cache folder.
ADAPTIVE_KIND = "adaptive_design"
#: ``sweep.adaptive.acquisition`` values (module doc, step 3).
ACQUISITIONS = ("governing", "rows", "mix")
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


def space_filling_batch(x_cand: np.ndarray, x_design: np.ndarray, n: int,
                        exclude: Sequence[int] | np.ndarray = ()) -> np.ndarray:
    """Indices of ``n`` candidates chosen greedily by max-min distance, disagreement ignored.

    Each pick is the candidate farthest from the design points ``x_design``
    and the picks before it (ties: the lower index; with no design point the
    first pick is candidate 0 of those not excluded). ``exclude``: candidates
    not to take (already in the batch).
    """
    free = np.ones(x_cand.shape[0], dtype=bool)
    free[np.asarray(list(exclude), dtype=np.int64)] = False
    n = min(n, int(free.sum()))
    if x_design.size:
        dmin = np.min(np.linalg.norm(x_cand[:, None, :] - x_design[None, :, :], axis=2), axis=1)
    else:
        dmin = np.full(x_cand.shape[0], np.inf)
    dmin = np.where(free, dmin, -np.inf)
    chosen: list[int] = []
    while len(chosen) < n:
        j = int(np.argmax(dmin))
        chosen.append(j)
        dmin = np.minimum(dmin, np.linalg.norm(x_cand - x_cand[j], axis=1))
        dmin[chosen] = -np.inf
    return np.asarray(chosen, dtype=np.int64)


def choose_batch(acquisition: str, x_cand: np.ndarray, score: np.ndarray, x_design: np.ndarray,
                 n: int, pool_size: int, space_filling_share: float = 0.5) -> np.ndarray:
    """Indices of the ``n`` candidates a round adds (module doc, step 4).

    ``governing`` and ``rows``: :func:`diverse_batch` on the disagreement
    ``score``. ``mix``: ``round(space_filling_share * n)`` candidates
    (half up) are taken by max-min distance alone
    (:func:`space_filling_batch`, from the design and the disputed picks),
    after the other ``n - that`` taken by :func:`diverse_batch`; the
    disputed picks come first in the result.
    """
    if acquisition not in ACQUISITIONS:
        raise InputError("sweep.adaptive.acquisition", f"unknown acquisition {acquisition!r}",
                         ", ".join(ACQUISITIONS))
    n = min(n, x_cand.shape[0])
    if acquisition != "mix":
        return diverse_batch(x_cand, score, x_design, n, pool_size)
    n_space = min(n, int(math.floor(space_filling_share * n + 0.5)))
    disputed = diverse_batch(x_cand, score, x_design, n - n_space, pool_size) \
        if n > n_space else np.zeros(0, dtype=np.int64)
    ref = np.vstack([x_design.reshape(-1, x_cand.shape[1]), x_cand[disputed]])
    spread = space_filling_batch(x_cand, ref, n_space, exclude=disputed)
    return np.concatenate([disputed, spread]).astype(np.int64)


def row_matrix(rows: pd.DataFrame, features: Sequence[str], categorical: Sequence[str],
               levels: Mapping[str, Sequence[str]]) -> np.ndarray:
    """Inputs of the row-level ensemble: the numeric ``features`` as they are (trees need no
    scaling) and the ``categorical`` columns one-hot on ``levels`` (an unseen level is all zero).
    """
    blocks = [rows[list(features)].to_numpy(dtype=np.float64)]
    for col in categorical:
        v = rows[col].astype(str).to_numpy()
        blocks.append((v[:, None] == np.asarray(levels[col], dtype=object)[None, :]
                       ).astype(np.float64))
    return np.hstack(blocks)


def row_scores(x: np.ndarray, y: np.ndarray, groups: np.ndarray, x_cand: np.ndarray,
               cand_groups: np.ndarray, *, n_members: int, seed: int,
               censor_log10: float | None, max_iter: int = 100) -> pd.Series:
    """Row-level disagreement of a case-bootstrap ensemble, summed over each candidate's rows.

    Each of ``n_members`` histogram gradient-boosting models is fitted on the
    rows of a resample of the finished cases (cases drawn with replacement,
    every row of a drawn case taken: the rows of a case are correlated); the
    score of a candidate case is the sum over its rows of the standard
    deviation over members of the predicted log10 damage rate, predictions
    and targets clipped at ``censor_log10`` (a dispute beyond the horizon
    scores zero). A case with more locations weighs more, as its rows do in
    the row-level metrics.

    Parameters
    ----------
    x, y, groups : ndarray, shapes (n, d), (n,), (n,)
        Encoded rows (:func:`row_matrix`), log10 damage rate per hour, case id
        of the finished cases.
    x_cand, cand_groups : ndarray, shapes (m, d), (m,)
        Rows of the candidate cases and their case ids.
    n_members, seed, censor_log10
        As :func:`acquisition_scores`.
    max_iter : int
        Trees per member (learning rate 0.1, scikit-learn's other defaults).

    Returns
    -------
    Series
        Score per candidate case id (order of first appearance in ``cand_groups``).
    """
    rng = np.random.default_rng(seed)
    y = np.asarray(y, dtype=np.float64)
    ok = np.isfinite(y)
    x, y, groups = x[ok], y[ok], np.asarray(groups)[ok]
    if censor_log10 is not None:
        y = np.maximum(y, censor_log10)
    ids, inverse = np.unique(groups, return_inverse=True)
    members = [np.flatnonzero(inverse == k) for k in range(ids.size)]
    preds = np.empty((n_members, x_cand.shape[0]))
    # one OpenMP thread: on a shared machine the thread barriers of many small fits cost
    # more than they save (measured on 2 loaded cores: 2.6 s against 0.04 s for 160 rows)
    with threadpool_limits(limits=1, user_api="openmp"):
        for m in range(n_members):
            take = np.concatenate([members[k] for k in rng.integers(0, ids.size, ids.size)])
            model = HistGradientBoostingRegressor(
                max_iter=max_iter, learning_rate=0.1, early_stopping=False,
                random_state=int(rng.integers(0, 2**31 - 1)))
            preds[m] = model.fit(x[take], y[take]).predict(x_cand)
    if censor_log10 is not None:
        preds = np.maximum(preds, censor_log10)
    spread = pd.Series(preds.std(axis=0), index=pd.Index(np.asarray(cand_groups), name="case_id"))
    order = pd.unique(np.asarray(cand_groups))
    return spread.groupby(level=0, sort=False).sum().reindex(order)


def template_rows(candidates: pd.DataFrame, finished_rows: pd.DataFrame,
                  variables: Sequence[str]) -> pd.DataFrame:
    """Dataset-like rows of cases not simulated yet, from their inputs.

    The locations of a case (joint, component, location, distance from the
    bit) come from the simulator's segmentation of the string, which depends
    on the well profile and the bit depth: a candidate takes them from the
    finished case with the same values of the categorical design variables
    and the nearest bit MD (``operation.bit_md_m``; without that variable,
    the first such case). Its design variables are the candidate's, the MD of
    each location is moved by the difference of bit MD, and the hole-geometry
    columns are computed from the candidate's well at those positions as the
    fatigue stage computes them for its rows
    (:func:`drillfatigue.sweep.cases.position_columns`). Other columns are
    the template's.

    Parameters
    ----------
    candidates : DataFrame
        Case table (:func:`drillfatigue.sweep.design.design_cases` columns,
        ``case_json`` included).
    finished_rows : DataFrame
        Dataset rows of finished cases (``case_id``, the design variables,
        ``md_m``, ``s_from_bit_m``, location columns).
    variables : sequence of str
        The design variables (columns of both tables).

    Returns
    -------
    DataFrame
        Rows of every candidate that has a template, ``case_id`` the candidate's.
    """
    bit = "operation.bit_md_m"
    cat = [v for v in variables if v in finished_rows
           and not pd.api.types.is_numeric_dtype(finished_rows[v])]
    first = finished_rows.drop_duplicates("case_id")
    parts = []
    surveys: dict[str, Any] = {}
    for _, cand in candidates.iterrows():
        pool = first
        for v in cat:
            pool = pool[pool[v].astype(str) == str(cand[v])]
        if not len(pool):
            continue
        if bit in variables and bit in pool:
            k = int(np.argmin(np.abs(pool[bit].to_numpy(dtype=np.float64) - float(cand[bit]))))
        else:
            k = 0
        tmpl = pool.iloc[k]
        rows = finished_rows[finished_rows["case_id"] == tmpl["case_id"]].copy()
        shift = float(cand[bit]) - float(tmpl[bit]) if bit in variables and bit in pool else 0.0
        rows["md_m"] = rows["md_m"].to_numpy(dtype=np.float64) + shift
        for v in variables:
            if v in rows:
                rows[v] = cand[v]
        rows["case_id"] = cand["case_id"]
        # as sweep.cases.position_columns (the fatigue stage's rows), one survey per well section
        well = json.loads(cand["case_json"])["well"]
        key = json.dumps(well, sort_keys=True)
        if key not in surveys:
            surveys[key] = build_survey(case_from_dict(json.loads(cand["case_json"])).well)
        md = rows["md_m"].to_numpy(dtype=np.float64)
        geo = survey_features(surveys[key], md,
                              md + rows["s_from_bit_m"].to_numpy(dtype=np.float64))
        rows = rows.assign(**{c: np.asarray(v) for c, v in geo.items() if c in rows})
        parts.append(rows)
    if not parts:
        return finished_rows.iloc[:0].copy()
    return pd.concat(parts, ignore_index=True)


@dataclass(frozen=True)
class RowSource:
    """What the row-level acquisitions (``rows``, ``mix``) need beside the case targets.

    Attributes
    ----------
    finished : callable
        ``finished(cases) -> DataFrame``: the dataset rows of finished cases
        (:func:`drillfatigue.sweep.dataset.build_dataset`).
    candidates : callable
        ``candidates(cases, finished_rows) -> DataFrame``: rows of cases not
        simulated (:func:`template_rows`).
    features, categorical : tuple of str
        The surrogate's numeric and categorical inputs (``surrogate.features``,
        ``surrogate.categorical``).
    target_column : str
        Damage rate per hour column (``surrogate.target_column``).
    floor_per_h : float
        Rate a zero counts as (``surrogate.rate_floor_per_h``).
    """

    finished: Callable[[pd.DataFrame], pd.DataFrame]
    candidates: Callable[[pd.DataFrame, pd.DataFrame], pd.DataFrame]
    features: tuple[str, ...]
    categorical: tuple[str, ...]
    target_column: str
    floor_per_h: float

    def log10_rate(self, rows: pd.DataFrame) -> np.ndarray:
        """log10 damage rate per hour of rows, a zero or missing rate at the floor."""
        rate = pd.to_numeric(rows[self.target_column], errors="coerce").fillna(0.0).to_numpy()
        return np.log10(np.maximum(rate, self.floor_per_h))

    def levels(self, rows: pd.DataFrame) -> dict[str, list[str]]:
        """Levels of the categorical inputs seen in ``rows`` (sorted)."""
        return {c: sorted(rows[c].astype(str).unique()) for c in self.categorical if c in rows}


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


def _row_acquisition(src: RowSource, frame: pd.DataFrame, pool: pd.DataFrame, *,
                     n_members: int, seed: int, censor_log10: float | None) -> np.ndarray:
    """:func:`row_scores` of the ``pool`` cases (zero for one with no rows), in pool order."""
    done = src.finished(frame)
    if not len(done):
        return np.zeros(len(pool))
    cand = src.candidates(pool, done)
    if not len(cand):
        return np.zeros(len(pool))
    # an input the rows lack (a case input no design variable varies) is constant: left out
    num = [c for c in src.features if c in done and c in cand]
    cat = [c for c in src.categorical if c in done and c in cand]
    levels = src.levels(done)
    score = row_scores(row_matrix(done, num, cat, levels),
                       src.log10_rate(done), done["case_id"].astype(str).to_numpy(),
                       row_matrix(cand, num, cat, levels),
                       cand["case_id"].astype(str).to_numpy(), n_members=n_members, seed=seed,
                       censor_log10=censor_log10)
    return score.reindex(pool["case_id"].astype(str)).fillna(0.0).to_numpy(dtype=np.float64)


def adaptive_design(cfg: SweepConfig, base_case: dict[str, Any], target_fn: TargetFn, *,
                    censor_log10: float | None, model: type[BaseModel] = CaseConfig,
                    on_round: Callable[[int, pd.DataFrame], None] | None = None,
                    rows: RowSource | None = None) -> pd.DataFrame:
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
    rows : RowSource, optional
        The rows of finished and candidate cases, needed by the acquisitions
        ``rows`` and ``mix``.

    Returns
    -------
    DataFrame
        The columns of :func:`drillfatigue.sweep.design.design_cases` plus
        ``round`` (0: the initial design) and ``acquisition_score`` (the
        disagreement when chosen; NaN in round 0); at most ``n_cases`` rows
        (fewer only if the pools hold no new case).
    """
    ad: AdaptiveConfig = cfg.adaptive
    if ad.acquisition != "governing" and rows is None:
        raise InputError("sweep.adaptive.acquisition",
                         f"{ad.acquisition!r} needs the dataset rows of the cases",
                         "governing, or rows/mix with the design stage's row source")
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
        if ad.acquisition == "governing":
            score = acquisition_scores(x, y, x_cand, n_members=ad.n_members,
                                       seed=ad.seed + rnd, censor_log10=censor_log10)
        else:
            assert rows is not None
            score = _row_acquisition(rows, frame, pool, n_members=ad.n_members,
                                     seed=ad.seed + rnd, censor_log10=censor_log10)
        n_new = min(ad.batch_size, cfg.n_cases - len(frame))
        pick = choose_batch(ad.acquisition, x_cand, score, x, n_new,
                            math.ceil(ad.pool_factor * ad.batch_size), ad.space_filling_share)
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
