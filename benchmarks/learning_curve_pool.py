"""Retrospective learning curve: the adaptive design's acquisitions replayed on a simulated pool.

Pool-based active learning (Settles 2012, ch. 2.3): instead of simulating the
cases an acquisition asks for, it chooses them from a pool of cases already
simulated, so several acquisitions and seeds are compared on the same
simulations at the cost of the model fits alone.

- Pool: the cases of a training dataset (``--dataset``, rows of
  :func:`drillfatigue.sweep.dataset.build_dataset`) with their design table
  (``--design``: ``case_id``, ``design_index``), a scrambled Sobol design of
  ``sweep.seed`` of ``--params``; each case's point in the unit cube is that
  Sobol sequence's point ``design_index``.
- Test set: a held-out dataset (``--heldout``, a design of its own seed).
- Sobol: the first ``n`` cases in design order (``design_index``).
- Adaptive, per acquisition (``--acquisitions``) and seed (``--seeds``):
  the first ``--n-initial`` cases in design order, then batches of
  ``--batch`` chosen from the pool cases not yet taken by
  :func:`drillfatigue.sweep.adaptive.choose_batch` with
  ``sweep.adaptive``'s ``n_members``, ``pool_factor`` and
  ``space_filling_share``, the bootstrap seeded ``1000 * seed + round``:
  ``governing`` (:func:`~drillfatigue.sweep.adaptive.acquisition_scores` on
  the governing rate per case and component type), ``rows``
  (:func:`~drillfatigue.sweep.adaptive.row_scores` on the rows' log10 rate,
  the rows the pool holds), ``mix`` (a share space-filling, the rest by
  ``rows``), ``state`` (benchmark only: the ``governing`` disagreement on each
  case's simulated stick-slip severity, aimed at the boundary between full
  and partial stick-slip where the served model misses); and the control
  ``space_filling`` (max-min distance alone: no
  model, no seed), which tells a disagreement's gain from mere spreading.
- At each size the served model (gradient boosting,
  :func:`drillfatigue.surrogate.gbm.fit_gbm` on every row of the cases taken,
  the encoding of :func:`drillfatigue.surrogate.gbm.design_matrix`, the
  ``surrogate`` section of ``--params``) is scored with
  :func:`drillfatigue.surrogate.evaluation.deciding_metrics` on the whole
  held-out set and on ``--subsets`` disjoint subsets of its cases (the spread
  a deterministic Sobol curve has from the test cases alone); the Sobol
  design at ``--n-max`` is also refitted with ``--fit-seeds`` other
  early-stopping splits (``surrogate.split_seed``), the spread the served
  fit has on the same cases.

Ratio per metric: the simulations the adaptive curve needs to reach the Sobol
curve's value at ``--n-max`` (linear interpolation between sizes), over
``--n-max``; ``null`` when it is not reached. Given for the curve averaged
over the seeds, per seed, and per held-out subset (the seed-averaged curves).

Usage::

    python benchmarks/learning_curve_pool.py \\
        --dataset /work/research/data/dataset/damage.parquet \\
        --heldout /work/research/data/heldout/dataset/damage.parquet \\
        --design /work/research/data/design/cases.parquet \\
        --params /work/research/params.yaml [--n-initial 32] [--batch 16] [--n-max 128] \\
        [--seeds 3] [--subsets 4] [--acquisitions governing rows mix space_filling]

writes ``benchmarks/results/learning_curve_pool.json`` (rewritten after each
curve; ``--keep`` keeps the Sobol curve and the runs already there and runs
only the acquisitions and seeds missing). The controls ``mix_sobol`` (half
of each batch the next cases of the Sobol sequence, the rest as ``rows``),
``random`` (seeded random cases) and ``oracle`` (the cases the served model
of the round gets most wrong, summed squared error of their rows clipped at
the horizon: known only in a replay, the most an acquisition aimed at the
error could take) are benchmark-only. Per round each run records how well
its score ranks the served model's actual error on the pool cases
(Spearman) and the share of that error its batch takes.
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
from scipy.stats import spearmanr

from drillfatigue.config import load_params
from drillfatigue.surrogate.data import log10_target
from drillfatigue.surrogate.io import write_json
from drillfatigue.sweep.adaptive import (
    acquisition_scores,
    case_targets,
    choose_batch,
    row_matrix,
    row_scores,
    unit_features,
)
from drillfatigue.sweep.design import base_case_from_params, design_space, sobol_unit

sys.path.insert(0, str(Path(__file__).resolve().parent))
from learning_curve import (  # noqa: E402  (the served fit, its scores and the ratio)
    METRICS,
    deciding_scores,
    fit_served,
    heldout_predictions,
    reach_ratio,
)

RESULT = Path(__file__).parent / "results" / "learning_curve_pool.json"
#: the case's simulated torsional state, the ``state`` acquisition's target
STATE_COLUMN = "stick_slip_severity"


class Pool:
    """The pool, the test set and the served model's fit and score."""

    def __init__(self, args: argparse.Namespace) -> None:
        params = load_params(args.params)
        self.sweep, self.cfg = params.sweep, params.surrogate
        cfg = self.cfg
        rows = pd.read_parquet(args.dataset)
        design = pd.read_parquet(args.design, columns=["case_id", "design_index",
                                                       "case_json"])
        design = design[design["case_id"].isin(set(rows[cfg.group_column].astype(str)))]
        design = design.sort_values("design_index").reset_index(drop=True)
        self.order = design["case_id"].astype(str).tolist()
        space = design_space(self.sweep, base_case_from_params(params))
        unit = sobol_unit(int(design["design_index"].max()) + 1, space.dim, self.sweep.seed,
                          "--design")
        self.x_unit = unit_features(space, unit[design["design_index"].to_numpy()])
        self.rows = rows.assign(case_id=rows[cfg.group_column].astype(str))
        self.y_rows = log10_target(self.rows[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
        self.test = pd.read_parquet(args.heldout)
        self.test_ids = sorted(self.test[cfg.group_column].astype(str).unique())
        # the row-level members' inputs: the surrogate's features, as the design stage's
        # row source encodes them (every row of the pool is known here)
        levels = {c: sorted(self.rows[c].astype(str).unique()) for c in cfg.categorical}
        self.x_rows = row_matrix(self.rows, cfg.features, cfg.categorical, levels)
        self.row_index = {cid: np.flatnonzero(self.rows["case_id"].to_numpy() == cid)
                          for cid in self.order}
        self.censor = (-math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None)
        rng = np.random.default_rng(args.subset_seed)
        perm = rng.permutation(len(self.test_ids))
        self.subsets = [set(np.asarray(self.test_ids)[perm[k::args.subsets]])
                        for k in range(args.subsets)]

    def fit_score(self, ids: list[str], split_seed: int | None = None) -> dict[str, Any]:
        """Served model on every row of ``ids``, scored on the held-out set and its subsets
        (``split_seed``: another early-stopping split than the served ``surrogate.split_seed``).
        """
        cfg = self.cfg if split_seed is None else self.cfg.model_copy(
            update={"split_seed": split_seed})
        train = self.rows.iloc[np.concatenate([self.row_index[c] for c in ids])]
        predict, info = fit_served(train, cfg)
        pred = heldout_predictions(self.test, predict(self.test), cfg)
        out = {"n_cases": len(ids), "n_train_rows": int(len(train)), "n_iter": info["n_iter"],
               **deciding_scores(pred, cfg.horizon_h)}
        out["subsets"] = [deciding_scores(pred[pred["case_id"].isin(s)], cfg.horizon_h)
                          for s in self.subsets]
        out["_predict"] = predict
        return out

    def case_error(self, predict: Any, cand: list[str]) -> np.ndarray:
        """Squared error of ``predict`` summed over each candidate's rows, both sides clipped
        at the horizon (an error beyond it changes no answer), in ``cand`` order."""
        idx = np.concatenate([self.row_index[c] for c in cand])
        c = self.censor if self.censor is not None else -np.inf
        e = (np.maximum(predict(self.rows.iloc[idx]), c) - np.maximum(self.y_rows[idx], c))**2
        g = self.rows["case_id"].to_numpy()[idx]
        return pd.Series(e).groupby(g).sum().reindex(cand).to_numpy(dtype=np.float64)

    def scores(self, acquisition: str, taken: list[str], cand: list[str], seed: int,
               ad: Any) -> np.ndarray:
        """Disagreement of the candidates (zeros for the space-filling control)."""
        pos = {c: i for i, c in enumerate(self.order)}
        if acquisition == "space_filling":
            return np.zeros(len(cand))
        if acquisition == "state":
            # disagreement on the torsional state the string settles in (its simulated
            # stick-slip severity, a post-run output of the cases taken): full stick-slip
            # and partial stick-slip coexist above ~120 rpm, and the boundary between them
            # is where the served model misses (docs/surrogate.md, "What limits it")
            sev = self.rows.drop_duplicates("case_id").set_index("case_id")[STATE_COLUMN]
            y = sev.reindex(taken).to_numpy(dtype=np.float64)
            return acquisition_scores(self.x_unit[[pos[c] for c in taken]], y,
                                      self.x_unit[[pos[c] for c in cand]],
                                      n_members=ad.n_members, seed=seed, censor_log10=None)
        if acquisition == "governing":
            tr = self.rows.iloc[np.concatenate([self.row_index[c] for c in taken])]
            y = case_targets(tr, self.cfg.target_column, self.cfg.rate_floor_per_h)
            y = y.reindex(taken).to_numpy(dtype=np.float64)
            return acquisition_scores(self.x_unit[[pos[c] for c in taken]], y,
                                      self.x_unit[[pos[c] for c in cand]],
                                      n_members=ad.n_members, seed=seed,
                                      censor_log10=self.censor)
        ti = np.concatenate([self.row_index[c] for c in taken])
        ci = np.concatenate([self.row_index[c] for c in cand])
        s = row_scores(self.x_rows[ti], self.y_rows[ti], self.rows["case_id"].to_numpy()[ti],
                       self.x_rows[ci], self.rows["case_id"].to_numpy()[ci],
                       n_members=ad.n_members, seed=seed, censor_log10=self.censor)
        return s.reindex(cand).to_numpy(dtype=np.float64)


def run_adaptive(pool: Pool, acquisition: str, seed: int, args: argparse.Namespace,
                 sizes: list[int]) -> dict[str, Any]:
    ad = pool.sweep.adaptive
    pos = {c: i for i, c in enumerate(pool.order)}
    taken = pool.order[:args.n_initial]
    curve = [pool.fit_score(taken)]
    t_acq = 0.0
    rounds = []
    for rnd, n in enumerate(sizes[1:], start=1):
        cand = [c for c in pool.order if c not in set(taken)]
        err = pool.case_error(curve[-1].pop("_predict"), cand)
        t0 = time.perf_counter()
        n_new = n - len(taken)
        score = np.zeros(len(cand))
        x_cand = pool.x_unit[[pos[c] for c in cand]]
        if acquisition == "oracle":
            # the cases the served model gets most wrong (known only in a replay): the most an
            # acquisition aimed at the error could take
            score = err.copy()
            pick = np.argsort(-err, kind="stable")[:n_new]
        elif acquisition == "random":
            pick = np.random.default_rng(1000 * seed + rnd).choice(len(cand), n_new,
                                                                   replace=False)
        elif acquisition == "mix_sobol":
            # the space-filling share: the next cases of the Sobol sequence (design order)
            n_sobol = int(math.floor(ad.space_filling_share * n_new + 0.5))
            first = np.arange(n_sobol)
            taken_x = pool.x_unit[[pos[c] for c in taken + cand[:n_sobol]]]
            rest = cand[n_sobol:]
            s_rest = pool.scores("rows", taken + cand[:n_sobol], rest, 1000 * seed + rnd, ad)
            score[n_sobol:] = s_rest
            disputed = choose_batch("rows", x_cand[n_sobol:], s_rest, taken_x, n_new - n_sobol,
                                    math.ceil(ad.pool_factor * args.batch))
            pick = np.concatenate([first, n_sobol + disputed])
        else:
            score = pool.scores(acquisition, taken, cand, 1000 * seed + rnd, ad)
            mode = ("mix" if acquisition in ("mix", "space_filling")
                    else "governing" if acquisition == "state" else acquisition)
            share = 1.0 if acquisition == "space_filling" else ad.space_filling_share
            pick = choose_batch(mode, x_cand, score, pool.x_unit[[pos[c] for c in taken]],
                                n_new, math.ceil(ad.pool_factor * args.batch), share)
        t_acq += time.perf_counter() - t0
        # does the disagreement find the error? the served model's error on the pool cases
        rounds.append({
            "n_cases": len(taken),
            "spearman_score_error": (float(spearmanr(score, err).statistic)
                                     if np.ptp(score) > 0 else None),
            "error_share_taken": float(err[pick].sum() / err.sum()),
            "error_share_oracle": float(np.sort(err)[::-1][:n_new].sum() / err.sum()),
            "case_share_taken": n_new / len(cand)})
        taken = taken + [cand[i] for i in pick]
        curve.append(pool.fit_score(taken))
    curve[-1].pop("_predict")
    profiles = pool.rows.drop_duplicates("case_id").set_index("case_id")["well.profile"]
    return {"acquisition": acquisition, "seed": seed, "wall_s_acquisition": round(t_acq, 1),
            "cases": taken, "rounds": rounds,
            "profiles": {str(k): int(v) for k, v in
                         profiles.reindex(taken).value_counts().sort_index().items()},
            "curve": curve}


def summarise(result: dict[str, Any], args: argparse.Namespace) -> dict[str, Any]:
    sizes = result["sizes"]
    sobol = result["sobol"]["curve"]
    out: dict[str, Any] = {}
    for acq in args.acquisitions:
        runs = [r for r in result["adaptive"] if r["acquisition"] == acq]
        if not runs:
            continue
        res: dict[str, Any] = {"n_seeds": len(runs)}
        for metric, sign in METRICS:
            mean = [float(np.mean([r["curve"][i][metric] for r in runs]))
                    for i in range(len(sizes))]
            target = sobol[-1][metric]
            per_subset = []
            for k in range(args.subsets):
                m_k = [float(np.mean([r["curve"][i]["subsets"][k][metric] for r in runs]))
                       for i in range(len(sizes))]
                per_subset.append(reach_ratio(sizes, m_k, sobol[-1]["subsets"][k][metric],
                                              sign, args.n_max))
            # simulations to reach Sobol's value at each size, over that size
            by_ref = {str(n_ref): reach_ratio(sizes, mean, sobol[i][metric], sign, n_ref)
                      for i, n_ref in enumerate(sizes) if i > 0}
            res[metric] = {
                "sobol_curve": [c[metric] for c in sobol], "mean_curve": mean,
                "ratio_by_sobol_size": by_ref,
                "per_seed_curve": [[c[metric] for c in r["curve"]] for r in runs],
                "sobol_final": target, "adaptive_final": mean[-1],
                "ratio": reach_ratio(sizes, mean, target, sign, args.n_max),
                "per_seed_ratio": [reach_ratio(sizes, [c[metric] for c in r["curve"]], target,
                                               sign, args.n_max) for r in runs],
                "per_subset_ratio": per_subset}
        out[acq] = res
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dataset", required=True)
    ap.add_argument("--heldout", required=True)
    ap.add_argument("--design", required=True)
    ap.add_argument("--params", required=True)
    ap.add_argument("--n-initial", type=int, default=32)
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--n-max", type=int, default=128)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--subsets", type=int, default=4)
    ap.add_argument("--subset-seed", type=int, default=0)
    ap.add_argument("--fit-seeds", type=int, default=4,
                    help="refits of the Sobol design at --n-max with other early-stopping splits")
    ap.add_argument("--acquisitions", nargs="+",
                    default=["governing", "rows", "mix", "space_filling", "mix_sobol",
                             "random", "oracle"],
                    choices=["governing", "rows", "mix", "space_filling", "mix_sobol",
                             "random", "oracle", "state"])
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--keep", action="store_true",
                    help="keep the Sobol curve and the runs already in --out (same settings "
                         "but --acquisitions/--seeds) and run the rest")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    pool = Pool(args)
    if not 0 < args.n_initial < args.n_max <= len(pool.order):
        ap.error(f"need 0 < --n-initial < --n-max <= {len(pool.order)} (the pool)")
    sizes = list(range(args.n_initial, args.n_max, args.batch)) + [args.n_max]
    result: dict[str, Any] = {
        "benchmark": "learning_curve_pool", "python": platform.python_version(),
        "machine": platform.machine(),
        "settings": {k: v for k, v in vars(args).items() if k != "out"},
        "adaptive_block": pool.sweep.adaptive.model_dump(mode="json"),
        "pool_cases": len(pool.order), "heldout_cases": len(pool.test_ids),
        "heldout_rows": int(len(pool.test)),
        "served_model": "gbm (fit_gbm on every row of the cases taken)",
        "metric": "held-out rows predicted within surrogate.horizon_h (deciding_metrics rows)",
        "sizes": sizes}
    kept: list[dict[str, Any]] = []
    if args.keep and Path(args.out).is_file():
        old = json.loads(Path(args.out).read_text(encoding="utf-8"))
        same = ("acquisitions", "seeds", "keep")
        if {k: v for k, v in old["settings"].items() if k not in same} != \
                {k: v for k, v in result["settings"].items() if k not in same}:
            ap.error(f"--keep: {args.out} was run with other settings")
        result["sobol"], kept = old["sobol"], old["adaptive"]
        result["wall_s_kept"] = old.get("wall_s", 0.0) + old.get("wall_s_kept", 0.0)
    else:
        result["sobol"] = {"cases": pool.order[:args.n_max], "curve": [
            {k: v for k, v in pool.fit_score(pool.order[:n]).items() if k != "_predict"}
            for n in sizes]}
        # the served fit's own noise: the Sobol design at --n-max, other early-stopping splits
        result["sobol"]["split_seed_final"] = [
            {k: v for k, v in pool.fit_score(pool.order[:args.n_max], s).items()
             if k not in ("subsets", "_predict")} | {"split_seed": s}
            for s in range(1, args.fit_seeds + 1)]
    result["adaptive"] = kept
    print(f"sobol done ({time.perf_counter() - t0:.0f} s)", flush=True)
    done = {(r["acquisition"], r["seed"]) for r in kept}
    args.acquisitions = list(dict.fromkeys(
        [r["acquisition"] for r in kept] + list(args.acquisitions)))
    for acq in args.acquisitions:
        for seed in range(1 if acq in ("space_filling", "oracle") else args.seeds):
            if (acq, seed) in done:
                continue
            result["adaptive"].append(run_adaptive(pool, acq, seed, args, sizes))
            result["summary"] = summarise(result, args)
            result["wall_s"] = round(time.perf_counter() - t0, 1)
            write_json(result, args.out)
            s = result["summary"][acq]
            print(f"{acq} seed {seed}: factor 2 ratio {s['factor2_fraction']['ratio']} "
                  f"rmse ratio {s['rmse']['ratio']} ({result['wall_s']:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
