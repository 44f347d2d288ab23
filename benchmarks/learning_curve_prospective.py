"""Prospective learning curve at research scale: the adaptive design run for real.

The replays (``learning_curve_pool.py``) choose among cases already simulated;
here the adaptive design asks the simulator for the cases it wants, from
fresh Sobol candidate pools, as the ``design`` stage with
``sweep.method: adaptive`` does, and is compared with the Sobol design
continued to the same number of simulations.

- Research run (``--research``): its ``params.yaml`` (the converged window
  rule, the surrogate section), its training design (the first
  ``--n-initial`` Sobol cases of ``sweep.seed``), simulation, fatigue and
  datasets, and its held-out dataset (a design of its own seed): the test set.
- Sobol arm: the same Sobol sequence continued to ``--n-max`` cases; the
  cases beyond the research run's are read from ``--extension`` (a folder
  holding ``data/design/cases.parquet`` for ``--n-max`` cases and the run
  and fatigue folders ``data/sweep_new``, ``data/fatigue_new`` of the cases
  the research run lacks, simulated with the stages' code and settings).
- Adaptive arm: :func:`drillfatigue.sweep.adaptive.adaptive_design` with the
  research run's ``sweep.adaptive`` block, ``n_initial`` = ``--n-initial``
  (the same first cases), batches of ``--batch`` from pools of
  ``--candidates``, acquisition ``--acquisition``, up to ``--n-max``; the
  cases simulated and evaluated by
  :func:`drillfatigue.sweep.stages.adaptive_targets` into ``--cache``. The
  initial cases are not simulated again: their run and fatigue folders are
  copied from the research run (the case function recognises them by the
  SHA-256 of their inputs). That is valid only while the simulator and
  fatigue chain give those outputs bit for bit; ``--check`` names case ids
  the extension simulated again, whose files are compared with the research
  run's before anything else runs (every file byte for byte; ``summary.json``
  as JSON without its wall time and real-time factor).
- At each size the served model (gradient boosting, ``fit_gbm``, as in
  ``learning_curve.py``) is fitted on every row of the first ``n`` cases of
  each arm and scored on the held-out rows that decide life (factor 2, RMSE,
  precision of "beyond the horizon", governing errors), on the whole test set
  and on ``--subsets`` disjoint subsets of its cases.

Ratio per metric: simulations the adaptive arm needs to reach the Sobol arm's
value at ``--n-max`` (interpolated), over ``--n-max``; ``null`` when not
reached. The Sobol arm's own ratio against that value is recorded beside it:
the arms share their first ``--n-initial`` cases, so an adaptive ratio no
lower than the Sobol arm's own is the held-out score's noise, not a saving.

Usage (the research run is ``dvc repro evaluate`` at ``sweep.n_cases: 256``,
``heldout.n_cases: 64``; the extension a copy of it at ``sweep.n_cases: 512``
whose ``simulate``/``fatigue`` stage code ran the missing cases into
``data/sweep_new``, ``data/fatigue_new``)::

    python benchmarks/learning_curve_prospective.py --research ../research4 \\
        --extension ../research5 --cache ../research5/adaptive_mix \\
        [--n-initial 256] [--n-max 512] [--batch 64] [--candidates 1024] \\
        [--acquisition mix] [--check 21a88f2045fa 1178c708e999]

writes ``benchmarks/results/learning_curve_prospective.json`` (about 40 min
of adaptive rounds on 2 cores; pools of 4096 candidates cost about 11 min of
acquisition a round). ``--resummarise`` recomputes the summary of a stored
result from its curves (and marks it ``summary_recomputed_from_curves``).
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import platform
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.numba_cache import scope_numba_cache

sys.path.insert(0, str(Path(__file__).parent))
RESULT = Path(__file__).parent / "results" / "learning_curve_prospective.json"
#: files of a run or fatigue folder that carry timings only (DONE hashes the others)
TIMING_FILES = ("DONE",)
#: keys of a summary.json that carry timings, not results
TIMING_KEYS = ("wall_time_s", "real_time_factor")


def _copy_or(known: dict[str, str], key: str, case_dir: Path) -> bool:
    src = known.get(key)
    if src is None:
        return False
    for f in Path(src).iterdir():
        if f.name != "DONE" and f.is_file():
            shutil.copy2(f, case_dir / f.name)
    return True


def seeded_case(inputs: dict[str, Any], case_dir: Path, *, window: dict[str, Any],
                known: dict[str, str]) -> Any:
    """The simulator's converged-window case, or the research run's folder of the same
    inputs (by SHA-256) copied."""
    from drillfatigue.sweep.design import inputs_sha256
    from drillfatigue.sweep.window import run_case_converged
    if _copy_or(known, inputs_sha256(inputs), case_dir):
        return None
    return run_case_converged({"case": inputs, "window": window}, case_dir)


def seeded_fatigue(task: dict[str, Any], case_dir: Path, *, known: dict[str, str]) -> Any:
    """The fatigue stage's case, or the research run's fatigue folder of the same case."""
    from drillfatigue.sweep.cases import fatigue_case
    from drillfatigue.sweep.design import inputs_sha256
    if "case" in task and _copy_or(known, inputs_sha256(task["case"]), case_dir):
        return None
    return fatigue_case(task, case_dir)


def check_identical(research: Path, extension: Path, ids: list[str]) -> list[str]:
    """Files of the cases ``ids`` that differ between the research run and the extension's
    new simulation of them (timing files excepted)."""
    diff = []
    for cid in ids:
        for old_root, new_root in (("data/sweep", "data/sweep_new"),
                                   ("data/fatigue", "data/fatigue_new")):
            old, new = research / old_root / cid, extension / new_root / cid
            if not new.is_dir():
                raise SystemExit(f"--check: {new} does not exist")
            for f in sorted(old.iterdir()):
                if f.name in TIMING_FILES:
                    continue
                if f.name == "summary.json":
                    a, b = (json.loads(g.read_text()) for g in (f, new / f.name))
                    same = ({k: v for k, v in a.items() if k not in TIMING_KEYS}
                            == {k: v for k, v in b.items() if k not in TIMING_KEYS})
                else:
                    same = (new / f.name).read_bytes() == f.read_bytes()
                if not same:
                    diff.append(str(new / f.name))
    return diff


def summarise(curves: dict[str, list[dict[str, Any]]], sizes: list[int], n_max: int,
              n_subsets: int) -> dict[str, Any]:
    """Per metric: both curves, the adaptive arm's reach ratio against the Sobol arm's value
    at ``n_max`` (whole test set and per subset), and the Sobol arm's own ratio against
    that value: both arms share the first cases, so a ratio at or below the Sobol arm's
    own says the held-out score moved within its noise, not that the acquisition paid."""
    from learning_curve import reach_ratio
    summary: dict[str, Any] = {}
    for metric, sign in (("factor2_fraction", +1), ("rmse", -1),
                         ("governing_factor2_fraction", +1), ("governing_rmse", -1)):
        s_curve = [c[metric] for c in curves["sobol"]]
        a_curve = [c[metric] for c in curves["adaptive"]]

        def sub(arm: str, i: int, metric: str = metric) -> list[float]:
            return [c["subsets"][i][metric] for c in curves[arm]]

        summary[metric] = {
            "sobol": s_curve, "adaptive": a_curve,
            "ratio_adaptive_to_sobol": reach_ratio(sizes, a_curve, s_curve[-1], sign, n_max),
            "sobol_self_ratio": reach_ratio(sizes, s_curve, s_curve[-1], sign, n_max),
            "per_subset_ratio": [reach_ratio(sizes, sub("adaptive", i), sub("sobol", i)[-1],
                                             sign, n_max) for i in range(n_subsets)],
            "per_subset_sobol_self_ratio": [reach_ratio(sizes, sub("sobol", i),
                                                        sub("sobol", i)[-1], sign, n_max)
                                            for i in range(n_subsets)]}
    return summary


def resummarise(path: Path) -> int:
    """Recompute the summary of a stored result from its curves (no simulation, no fit)."""
    from drillfatigue.surrogate.io import write_json
    result = json.loads(path.read_text())
    result["summary"] = summarise(result["curves"], result["sizes"],
                                  result["settings"]["n_max"], result["settings"]["subsets"])
    result["summary_recomputed_from_curves"] = True
    write_json(result, path)
    return 0


def main(argv: list[str] | None = None) -> int:
    scope_numba_cache()  # before any kernel module is imported
    from drillfatigue.config import load_params
    from drillfatigue.surrogate.io import write_json
    from drillfatigue.sweep.adaptive import adaptive_design
    from drillfatigue.sweep.dataset import build_dataset
    from drillfatigue.sweep.design import base_case_from_params, inputs_sha256
    from drillfatigue.sweep.stages import adaptive_cache_dir, adaptive_rows, adaptive_targets
    from drillfatigue.sweep.window import window_inputs
    from learning_curve import deciding_scores, fit_served, heldout_predictions

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--research")
    ap.add_argument("--extension")
    ap.add_argument("--cache", help="the adaptive arm's simulation cache")
    ap.add_argument("--n-initial", type=int, default=256)
    ap.add_argument("--n-max", type=int, default=512)
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--candidates", type=int, default=1024)
    ap.add_argument("--acquisition", default="mix")
    ap.add_argument("--subsets", type=int, default=4)
    ap.add_argument("--check", nargs="*", default=[])
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--resummarise", action="store_true",
                    help="recompute the summary of --out from its stored curves and stop")
    args = ap.parse_args(argv)
    if args.resummarise:
        return resummarise(Path(args.out))
    missing = [k for k in ("research", "extension", "cache") if getattr(args, k) is None]
    if missing:
        ap.error("the following arguments are required: "
                 + ", ".join("--" + k for k in missing))
    research, extension = Path(args.research), Path(args.extension)
    t0 = time.perf_counter()

    if not args.check:
        print("warning: no --check cases: the research run's folders seed the adaptive arm "
              "unverified", file=sys.stderr)
    bad = check_identical(research, extension, args.check)
    if bad:
        raise SystemExit("the research run's outputs are not reproduced bit for bit by this "
                         "code, so they cannot seed the adaptive arm: " + ", ".join(bad[:5]))

    params = load_params(research / "params.yaml")
    sw, sur = params.sweep, params.surrogate
    ad = sw.adaptive.model_copy(update={
        "n_initial": args.n_initial, "batch_size": args.batch, "candidates": args.candidates,
        "acquisition": args.acquisition, "cache_dir": str(Path(args.cache))})
    params = params.model_copy(update={"sweep": sw.model_copy(update={
        "method": "adaptive", "n_cases": args.n_max, "adaptive": ad})})
    design = pd.read_parquet(research / "data/design/cases.parquet")
    by_hash = {inputs_sha256(json.loads(t)): c
               for c, t in zip(design["case_id"], design["case_json"], strict=True)}
    known_runs = {h: str(research / "data/sweep" / c) for h, c in by_hash.items()}
    known_fatigue = {h: str(research / "data/fatigue" / c) for h, c in by_hash.items()}
    cases_path = Path(args.cache) / "cases.parquet"
    target = adaptive_targets(
        params, cases_path=cases_path,
        case_fn=functools.partial(seeded_case, window=window_inputs(params), known=known_runs),
        fatigue_fn=functools.partial(seeded_fatigue, known=known_fatigue))
    censor = -math.log10(sur.horizon_h) if sur.censoring == "likelihood" else None
    rounds: list[dict[str, Any]] = []

    def on_round(rnd: int, frame: pd.DataFrame) -> None:
        rounds.append({"round": rnd, "n_cases": len(frame),
                       "wall_s": round(time.perf_counter() - t0, 1)})
        print(f"round {rnd}: {len(frame)} cases ({rounds[-1]['wall_s']:.0f} s)", flush=True)

    adaptive = adaptive_design(params.sweep, base_case_from_params(params), target,
                               censor_log10=censor, on_round=on_round,
                               rows=adaptive_rows(params, cases_path))
    t_adaptive = time.perf_counter() - t0
    cache = adaptive_cache_dir(params, cases_path)
    adaptive_rows_ = build_dataset(adaptive.drop(columns=["round", "acquisition_score"]),
                                   cache / "sweep", cache / "fatigue")

    sobol = pd.read_parquet(extension / "data/design/cases.parquet").head(args.n_max)
    in_research = sobol["case_id"].isin(set(design["case_id"]))
    sobol_rows = pd.concat([
        build_dataset(sobol[in_research], research / "data/sweep", research / "data/fatigue"),
        build_dataset(sobol[~in_research], extension / "data/sweep_new",
                      extension / "data/fatigue_new")], ignore_index=True)
    test = pd.read_parquet(research / "data/heldout/dataset/damage.parquet")
    sizes = list(range(args.n_initial, args.n_max, args.batch)) + [args.n_max]

    test_ids = np.array(sorted(test[sur.group_column].astype(str).unique()))
    subsets = [test_ids[i::args.subsets] for i in range(args.subsets)] if args.subsets else []
    curves: dict[str, list[dict[str, Any]]] = {}
    for name, frame, rows in (("sobol", sobol, sobol_rows), ("adaptive", adaptive,
                                                             adaptive_rows_)):
        done = set(rows[sur.group_column].astype(str))
        ids = [c for c in frame["case_id"] if c in done]
        curve = []
        for n in sizes:
            train = rows[rows[sur.group_column].astype(str).isin(ids[:n])]
            predict, info = fit_served(train, sur)
            pred = heldout_predictions(test, predict(test), sur)
            score = {"n_cases": len(ids[:n]), "n_train_rows": int(len(train)), "n_iter": info["n_iter"],
                     **deciding_scores(pred, sur.horizon_h),
                     "subsets": [deciding_scores(pred[pred["case_id"].isin(s)], sur.horizon_h)
                                 for s in subsets]}
            curve.append(score)
            print(f"{name} {n}: factor 2 {score['factor2_fraction']:.3f} rmse "
                  f"{score['rmse']:.3f}", flush=True)
        curves[name] = curve

    summary = summarise(curves, sizes, args.n_max, len(subsets))
    result = {
        "benchmark": "learning_curve_prospective", "python": platform.python_version(),
        "machine": platform.machine(),
        "settings": {k: v for k, v in vars(args).items() if k not in ("out", "resummarise")},
        "served_model": "gbm (fit_gbm on every row of the first n cases)",
        "metric": "held-out rows predicted within surrogate.horizon_h (deciding_metrics rows)",
        "n_test_cases": int(test_ids.size), "n_test_rows": int(len(test)),
        "checked_bit_identical": args.check,
        "adaptive_rounds": rounds,
        "adaptive_profiles": {str(k): int(v) for k, v in
                              adaptive["well.profile"].value_counts().sort_index().items()},
        "sobol_profiles": {str(k): int(v) for k, v in
                           sobol["well.profile"].value_counts().sort_index().items()},
        "adaptive_new_rpm_quartiles": [float(q) for q in np.quantile(
            adaptive.loc[adaptive["round"] > 0, "operation.rpm"], [0.25, 0.5, 0.75])],
        "sobol_new_rpm_quartiles": [float(q) for q in np.quantile(
            sobol["operation.rpm"].iloc[args.n_initial:], [0.25, 0.5, 0.75])],
        "sizes": sizes, "curves": curves, "summary": summary,
        "wall_s_adaptive_design": round(t_adaptive, 1),
        "wall_s": round(time.perf_counter() - t0, 1)}
    write_json(result, args.out)
    for metric in ("factor2_fraction", "rmse"):
        s = summary[metric]
        print(f"{metric}: sobol {s['sobol'][-1]:.3f} adaptive {s['adaptive'][-1]:.3f} "
              f"ratio {s['ratio_adaptive_to_sobol']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
