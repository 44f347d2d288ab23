"""Noise floor of the simulated damage: replicate runs under imperceptible input changes.

Drill-string dynamics with wall contact, friction and bit bounce is chaotic in
parts of the operating space: two runs whose rpm differs by 0.01 % can end in
different whirl states and damage rates a decade apart. Whatever maps
operating conditions to damage (a surrogate, a look-up table, an engineer) then
meets an error it cannot remove. This module measures it.

:func:`replicate_cases` copies the first designed cases with one numeric field
scaled by ``1 + k * rel_step``; :func:`replicate_spread` pools the spread of
``y = log10(max(rate, floor))`` over the replicates of each (case, joint,
location) and gives

``sigma_log10``
    pooled within-group standard deviation, sum of squared deviations from
    each group's mean over the sum of (K - 1): unbiased for the variance.
``ceiling_factor2_fraction``
    the fraction of rows a perfect predictor of the replicate mean would get
    within a factor of 2: each row's deviation from the mean of the other
    K - 1 replicates, scaled by sqrt((K - 1) / K) so that its variance is
    sigma^2 (a leave-one-out mean carries sigma^2 / (K - 1) of its own), is
    compared with log10(2).
``ceiling_r2``
    1 - sigma^2 / var(y) on the replicated rows; the evaluate stage uses
    sigma with the test set's variance instead.
``ceiling_factor2_by_decade``
    the same ceiling per decade of damage rate (:func:`drillfatigue.metrics.factor2_by_decade`,
    groups binned by their mean y): the chaos sits in some decades and not in
    others, so the evaluate stage sets each model's factor-2 fraction per
    decade beside it.

:func:`replicates_stage` runs the study through the sweep engine (resumable,
parallel, failures recorded) and writes ``spread.json`` and
``spread.parquet``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.config import Params
from drillfatigue.config.replicates import ReplicatesConfig
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output, atomic_write_text
from drillfatigue.metrics import FACTOR2_DECADES, factor2_by_decade
from drillfatigue.sweep.cases import fatigue_case, run_case
from drillfatigue.sweep.design import (_split_path, apply_overrides, canonical_json, case_id_of,
                                       read_cases, write_cases)
from drillfatigue.sweep.runner import CaseFn
from drillfatigue.sweep.stages import fatigue_stage, heldout_params, simulate_stage

__all__ = ["FACTOR2_DECADES", "heldout_draws_params", "heldout_draws_stage", "replicate_cases",
           "replicate_spread", "replicates_stage", "step_multiple"]

GROUP_KEYS = ("base_case_id", "joint", "location")


def _get(case: dict[str, Any], path: str) -> Any:
    node: Any = case
    for key in _split_path(path):
        try:
            node = node[key]
        except (KeyError, IndexError, TypeError):
            raise InputError("replicates.variable", f"unknown configuration path {path!r}",
                             "a numeric field of the case sections, e.g. operation.rpm") from None
    return node


def step_multiple(k: int, symmetric: bool) -> int:
    """Signed multiple of the step of replicate ``k`` (>= 1): ``k``, or with
    ``symmetric`` +1, -1, +2, -2, ... for k = 1, 2, 3, 4, ..."""
    if not symmetric:
        return k
    return (k + 1) // 2 if k % 2 else -(k // 2)


def replicate_cases(cases: pd.DataFrame, cfg: ReplicatesConfig) -> pd.DataFrame:
    """Perturbed copies of the first ``cfg.n_cases`` designed cases.

    Parameters
    ----------
    cases : DataFrame
        Case table of the design stage (``case_id``, ``design_index``, ``case_json``).
    cfg : ReplicatesConfig
        Number of cases and replicates, the perturbed field and the step.

    Returns
    -------
    DataFrame
        One row per extra replicate (k = 1 .. n_replicates - 1 of each case):
        ``case_id`` (of the perturbed case), ``design_index``,
        ``base_case_id``, ``replicate`` (k), ``value`` (the perturbed field,
        in its own unit) and ``case_json``; a case table the simulate and
        fatigue stages accept.

    Raises
    ------
    InputError
        ``replicates.variable`` when the field is missing or not numeric.
    """
    order = np.argsort(cases["design_index"].to_numpy(), kind="stable") \
        if "design_index" in cases.columns else np.arange(len(cases))
    base = cases.iloc[order[: cfg.n_cases]]
    rows: list[dict[str, Any]] = []
    for cid, idx, text in zip(base["case_id"], base.get("design_index", range(len(base))),
                              base["case_json"], strict=True):
        case = json.loads(text)
        value = _get(case, cfg.variable)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise InputError("replicates.variable", f"{cfg.variable} is {value!r}, not a number",
                             "a numeric field of the case sections, e.g. operation.rpm")
        for k in range(1, cfg.n_replicates):
            new = float(value) * (1.0 + step_multiple(k, cfg.symmetric) * cfg.rel_step)
            rep = apply_overrides(case, {cfg.variable: new}, prefix="replicates.variable")
            rows.append({"case_id": case_id_of(rep), "design_index": int(idx),
                         "base_case_id": str(cid), "replicate": k, "value": new,
                         "case_json": canonical_json(rep)})
    return pd.DataFrame(rows, columns=["case_id", "design_index", "base_case_id", "replicate",
                                       "value", "case_json"])


def replicate_spread(frame: pd.DataFrame, *, floor_per_h: float,
                     rate_column: str = "damage_rate_per_h") -> dict[str, Any]:
    """Pooled spread of log10 damage rate across replicates (see the module docstring).

    Parameters
    ----------
    frame : DataFrame
        Columns ``base_case_id``, ``joint``, ``location``, ``replicate`` and
        ``rate_column`` (damage per hour); one row per replicate of each
        (case, joint, location). Groups with fewer than 2 replicates are
        ignored; a NaN rate counts as zero (censored at the floor).
    floor_per_h : float
        Censoring floor of the rate per hour (as the surrogate's target).

    Returns
    -------
    dict
        ``sigma_log10`` (decades), ``ceiling_factor2_fraction``,
        ``ceiling_r2``, ``var_log10``, ``n_groups``, ``n_rows``,
        ``n_cases``, ``case_sigma_log10`` ({base case id: pooled sigma}),
        ``fraction_cases_sigma_above_factor2``, ``max_case_sigma_log10`` and
        ``ceiling_factor2_by_decade`` (:func:`drillfatigue.metrics.factor2_by_decade` of the
        leave-one-out deviations, by the group's mean log10 rate).
    """
    missing = {*GROUP_KEYS, "replicate", rate_column} - set(frame.columns)
    if missing:
        raise InputError("replicates", f"spread table lacks columns {sorted(missing)}",
                         f"{', '.join(GROUP_KEYS)}, replicate, {rate_column}")
    rate = frame[rate_column].to_numpy(dtype=float)
    y = np.log10(np.maximum(np.nan_to_num(rate, nan=0.0), floor_per_h))
    g = frame.assign(_y=y).groupby(list(GROUP_KEYS), sort=False)["_y"]
    k = g.transform("count").to_numpy(dtype=float)
    total = g.transform("sum").to_numpy()
    keep = k >= 2
    if not keep.any():
        nan = float("nan")
        return {"sigma_log10": nan, "ceiling_factor2_fraction": nan, "ceiling_r2": nan,
                "var_log10": nan, "n_groups": 0, "n_rows": 0, "n_cases": 0,
                "case_sigma_log10": {}, "fraction_cases_sigma_above_factor2": nan,
                "max_case_sigma_log10": nan, "ceiling_factor2_by_decade": {}}
    y, k, total = y[keep], k[keep], total[keep]
    case = frame["base_case_id"].to_numpy()[keep]
    sq = (y - total / k) ** 2
    dof = (k - 1.0) / k  # per row: a group of K rows has K - 1 degrees of freedom
    sigma = math.sqrt(sq.sum() / dof.sum())
    loo = (y - (total - y) / (k - 1.0)) * np.sqrt((k - 1.0) / k)
    case_sigma = np.sqrt(pd.Series(sq).groupby(case).sum() / pd.Series(dof).groupby(case).sum())
    var_y = float(np.var(y, ddof=1)) if len(y) > 1 else float("nan")
    return {"sigma_log10": float(sigma),
            "ceiling_factor2_fraction": float(np.mean(np.abs(loo) < FACTOR2_DECADES)),
            "ceiling_r2": float(1.0 - sigma**2 / var_y) if var_y > 0 else float("nan"),
            # each group of K rows adds K times 1 / K
            "var_log10": var_y, "n_groups": int(round(float((1.0 / k).sum()))),
            "n_rows": int(len(y)), "n_cases": int(len(case_sigma)),
            "case_sigma_log10": {str(c): float(s) for c, s in case_sigma.items()},
            "fraction_cases_sigma_above_factor2": float(np.mean(case_sigma > FACTOR2_DECADES)),
            "max_case_sigma_log10": float(case_sigma.max()),
            "ceiling_factor2_by_decade": factor2_by_decade(total / k, loo)}


def _damage_rows(fatigue_dir: Path, case_id: str, criterion: str) -> pd.DataFrame | None:
    path = fatigue_dir / case_id / "damage.parquet"
    if not (fatigue_dir / case_id / "DONE").is_file() or not path.is_file():
        return None
    frame = pd.read_parquet(path, columns=["joint", "location", "criterion", "damage_rate_per_h"])
    return frame[frame["criterion"] == criterion].drop(columns="criterion")


def replicates_stage(params: Params, *, progress: bool = False, case_fn: CaseFn = run_case,
                     fatigue_fn: CaseFn = fatigue_case) -> dict[str, Any]:
    """Run the noise-floor study of ``params.replicates``; return the spread statistics.

    Simulates and evaluates the replicate cases under ``<out_dir>/sweep`` and
    ``<out_dir>/fatigue`` with the sweep's scheduler, retries and failure
    threshold (finished replicates are skipped on a rerun); the design runs
    themselves (replicate 0) are read from the sweep's fatigue folder. Writes
    ``<out_dir>/cases.parquet``, ``spread.parquet`` (one row per case, joint,
    location and replicate) and ``spread.json`` (the statistics, the
    criterion, the settings and the sweep reports).
    """
    cfg = params.replicates
    out = Path(cfg.out_dir)
    criterion = params.surrogate.criterion
    cases = read_cases(params.sweep.cases_path)
    reps = replicate_cases(cases, cfg)
    reports: dict[str, Any] = {}
    if len(reps):
        cases_path = write_cases(reps, out / "cases.parquet")
        reports["simulate"] = simulate_stage(params, cases_path=cases_path,
                                             sweep_dir=out / "sweep", progress=progress,
                                             case_fn=case_fn).to_dict()
        reports["fatigue"] = fatigue_stage(params, cases_path=cases_path, sweep_dir=out / "sweep",
                                           fatigue_dir=out / "fatigue", progress=progress,
                                           fatigue_fn=fatigue_fn).to_dict()
    parts = []
    members = [(cid, cid, 0) for cid in dict.fromkeys(reps["base_case_id"])]
    members += list(zip(reps["case_id"], reps["base_case_id"], reps["replicate"], strict=True))
    for cid, base, k in members:
        root = Path(params.sweep.fatigue_dir) if k == 0 else out / "fatigue"
        rows = _damage_rows(root, cid, criterion)
        if rows is not None:
            parts.append(rows.assign(base_case_id=base, replicate=int(k), case_id=cid))
    table = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(
        columns=["joint", "location", "damage_rate_per_h", "base_case_id", "replicate", "case_id"])
    stats = replicate_spread(table, floor_per_h=params.surrogate.rate_floor_per_h)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_output(out / "spread.parquet") as tmp:
        table.to_parquet(tmp, index=False)
    result = {"criterion": criterion, "variable": cfg.variable, "rel_step": cfg.rel_step,
              "symmetric": cfg.symmetric, "n_replicates": cfg.n_replicates, **stats,
              "sweeps": reports}
    atomic_write_text(out / "spread.json", json.dumps(result, indent=2, sort_keys=True) + "\n")
    return result


def heldout_draws_params(params: Params) -> Params:
    """:func:`~drillfatigue.sweep.stages.heldout_params` with the ``replicates`` section
    turned into the held-out draws': every held-out case, ``heldout.draws`` runs
    at rpm x (1 +- k ``heldout.draw_rel_step``) alternating in sign, into
    ``heldout.draws_dir`` (no case when ``heldout.draws`` is 1)."""
    h = params.heldout
    hp = heldout_params(params)
    n_cases = len(read_cases(h.cases_path)) if h.draws > 1 else 0
    rep = ReplicatesConfig(n_cases=n_cases, n_replicates=max(h.draws, 2),
                           variable="operation.rpm", rel_step=h.draw_rel_step, symmetric=True,
                           out_dir=h.draws_dir)
    return hp.model_copy(update={"replicates": rep})


def heldout_draws_stage(params: Params, *, progress: bool = False,
                        case_fn: CaseFn = run_case,
                        fatigue_fn: CaseFn = fatigue_case) -> dict[str, Any]:
    """Run the held-out draws (:func:`heldout_draws_params`) as a replicates study.

    The held-out design's runs are draw 0; the others run under
    ``<draws_dir>/sweep`` and ``<draws_dir>/fatigue``; ``spread.parquet``
    holds every draw's damage rate per case, joint and location, which
    ``evaluate --draws`` averages into the rate of the operating condition
    (:func:`drillfatigue.surrogate.evaluation.mean_of_draws_log10`), and
    ``spread.json`` the spread of the draws.
    """
    if not Path(params.heldout.cases_path).is_file():
        raise InputError("heldout.cases_path", f"{params.heldout.cases_path} does not exist",
                         "the heldout stage's design (run it first)")
    return replicates_stage(heldout_draws_params(params), progress=progress, case_fn=case_fn,
                            fatigue_fn=fatigue_fn)
