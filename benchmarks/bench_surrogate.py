"""Surrogate query speed: batched predictions per second and single-query latency.

A surrogate with the default architecture of ``params.yaml`` (5 members x
[64, 64] SiLU MLPs, Gaussian heads) is fitted on the documented synthetic
table (:func:`drillfatigue.surrogate.make_synthetic_dataset`) for a few epochs
only: speed does not depend on how well it is trained. Measured on this CPU,
``torch.set_num_threads(--threads)``:

- batched throughput on 10^5-row batches (median of the repeats) through
  ``Surrogate.predict_array`` without the OOD test (the network: mean, sigma,
  interval), with the per-feature range test, with range + k-NN test, and
  through the TorchScript export; goal >= 1e6 predictions/s;
- single-query latency (p50, p90) through ``Surrogate.predict`` (one-row
  DataFrame in and out: the public API, goal p50 < 2 ms) and through the
  ``predict_array`` fast path;
- the served gradient boosting (``surrogate.served_model: gbm``) in the same
  run: a surrogate with ``served_model: gbm`` fitted on the same synthetic
  table (its trees grown with the default early stopping on whole cases),
  batched 10^5 rows through ``predict_array`` (the compiled tree walker
  :class:`drillfatigue.surrogate.gbm.FlatForest`) without the domain check,
  with the range check and with range + k-NN check (also on one thread, and
  with the k-NN distance of every row), the domain check alone, the
  evaluators served before (leaf masks one row at a time in 64-bit words,
  the exact k-NN distance of every row) for a before/after ratio under the
  same load, the trees of the regressor and of the scale model in one pass
  (``forest_one_pass``, served) against two (``forest_two_passes``), and the
  flags of both domain checks on every row of the batch,
  scikit-learn's own ``predict`` on the design matrix for reference, and the
  single-query latency; ``--served-model DIR --served-data PARQUET`` also measures a saved
  model (e.g. the train stage's ``data/surrogate/model``) on 10^5 rows drawn
  from its dataset, and ``--served-baseline DIR`` a second one on the same rows
  in the same run (``vs_baseline``: the ratios, e.g. the scaled interval's
  second forest against one width per decade). Goals are stated per served
  model (``goals``);
- the ratio against one simulator run of the same condition: ``--sim-seconds``
  (a measured simulator wall time) if given, and the founding paper's figure
  (three profiles x 800 s simulated in about 38 h, i.e. ~12.7 h per case) as
  a reference.

Accuracy (``--accuracy-cases N``, N >= 500 for the issue's targets): a surrogate
with the default hyper-parameters (full training, early stopping) is fitted on
N cases of the synthetic table and scored with the ``evaluate`` stage's
:func:`drillfatigue.surrogate.evaluation.evaluate` (ensemble, GP and
gradient-boosting baselines on the same case-wise split); the targets are R^2
>= 0.95 on log10 damage rate, >= 90 % of points within a factor of 2, 90 %
interval coverage within +-3 %, and a lower RMSE than both baselines. The
synthetic table is a documented analytic stand-in with heteroscedastic noise,
not simulated data: the same run on the simulated dataset is the ``evaluate``
stage. ``--no-speed`` skips the speed part and updates only the accuracy
section of an existing result file.

``--knn-scaling`` measures only the k-NN distance's CPU time per row against
the reference size (synthetic fits of 60, 300 and 1 024 cases, 2 000 reference
rows at most), the exact compiled search against the float32 GEMM distance
and the served flag search in the same run, and keeps the rest of an
existing result file.

Usage: ``python benchmarks/bench_surrogate.py [--quick] [--threads 2] [--sim-seconds S]
[--accuracy-cases N] [--no-speed] [--knn-scaling] [--served-model DIR --served-data PARQUET
[--served-baseline DIR]]]``
-> ``benchmarks/results/surrogate.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import torch
from numba import njit

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.export import export_torchscript, load_torchscript
from drillfatigue.surrogate.gbm import FlatForest, design_matrix
from drillfatigue.surrogate.io import write_json
from drillfatigue.surrogate.kernels import _design_value, _rank
from drillfatigue.surrogate.ood import DomainChecker
from drillfatigue.surrogate.parallel import map_chunks
from drillfatigue.surrogate.served_gbm import scale_model

RESULT = Path(__file__).parent / "results" / "surrogate.json"
PARAMS = Path(__file__).resolve().parents[1] / "params.yaml"
PAPER_SECONDS_PER_CASE = 38 * 3600.0 / 3.0  # Liyanarachchi & Rideout: 3 profiles in ~38 h


def _median_rate(fn, n_rows: int, repeats: int) -> dict[str, float]:
    for _ in range(3):  # warm-up: TorchScript's profiling executor optimises after 2 calls
        fn()
    times, cpu = [], []
    for _ in range(repeats):
        c0 = time.process_time()
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    med = float(np.median(times))
    # CPU seconds (all threads) per batch: what the batch costs whatever the machine's load
    med_cpu = float(np.median(cpu))
    return {"median_s_per_batch": med, "predictions_per_s": n_rows / med,
            "best_predictions_per_s": n_rows / float(np.min(times)),
            "median_cpu_s_per_batch": med_cpu,
            "predictions_per_cpu_s": n_rows / med_cpu if med_cpu > 0 else float("nan")}


def _latency(fn, repeats: int) -> dict[str, float]:
    for _ in range(5):
        fn()
    t = np.empty(repeats)
    for i in range(repeats):
        t0 = time.perf_counter()
        fn()
        t[i] = time.perf_counter() - t0
    return {"p50_ms": float(np.percentile(t, 50) * 1e3), "p90_ms": float(np.percentile(t, 90) * 1e3),
            "min_ms": float(t.min() * 1e3)}


def _previous_knn(z: np.ndarray, reference: np.ndarray, k: int) -> np.ndarray:
    """The domain distance as served before the compiled search, for the ratio in one run:
    float32 |z|^2 - 2 z.r + |r|^2 as one torch GEMM per 1024-row chunk, top-k per row,
    chunks on the thread pool."""
    ref = torch.from_numpy(np.asarray(reference, dtype=np.float32))
    r2 = (ref * ref).sum(dim=1)
    zt = torch.from_numpy(np.asarray(z, dtype=np.float32))
    out = np.empty(z.shape[0])
    kk = min(int(k), ref.shape[0])

    def run(a: int) -> None:
        with torch.inference_mode():
            zc = zt[a:a + 1024]
            d2 = torch.addmm(r2.unsqueeze(0), zc, ref.t(), alpha=-2.0)
            d2 += (zc * zc).sum(dim=1, keepdim=True)
            small = torch.topk(d2, kk, dim=1, largest=False).values
            out[a:a + 1024] = small.clamp_min(0.0).sqrt().mean(dim=1).numpy()

    map_chunks(run, range(0, z.shape[0], 1024))
    return out


#: lowest set bit -> its index, by de Bruijn multiplication (the previous evaluator's way)
_DEBRUIJN = np.uint64(0x03F79D71B4CB0A89)
_LOWEST_BIT = np.zeros(64, dtype=np.int64)
for _b in range(64):
    _LOWEST_BIT[(((1 << _b) * 0x03F79D71B4CB0A89) & 0xFFFFFFFFFFFFFFFF) >> 58] = _b


@njit(cache=True, nogil=True)
def _previous_leafmask_kernel(x_num: np.ndarray, x_cat: np.ndarray, mean: np.ndarray,
                              scale: np.ndarray, col_cat: np.ndarray, col_index: np.ndarray,
                              col_level: np.ndarray, cuts: np.ndarray, cut_start: np.ndarray,
                              mask_start: np.ndarray, masks: np.ndarray, leaf_value: np.ndarray,
                              baseline: float, out: np.ndarray) -> None:
    """The leaf-mask evaluator as served before: one row at a time, 64-bit masks, a binary
    search per input, the lowest set bit by de Bruijn multiplication, one chain of sums."""
    n_cols = col_cat.shape[0]
    n_trees = masks.shape[1]
    alive = np.empty(n_trees, dtype=np.uint64)
    for i in range(x_num.shape[0]):
        for t in range(n_trees):
            alive[t] = ~np.uint64(0)
        for j in range(n_cols):
            lo = cut_start[j]
            hi = cut_start[j + 1]
            if lo == hi:
                continue
            v = _design_value(x_num, x_cat, mean, scale, col_cat, col_index, col_level, i, j)
            row = mask_start[j] + _rank(cuts, lo, hi, v) - lo
            for t in range(n_trees):
                alive[t] &= masks[row, t]
        acc = baseline
        for t in range(n_trees):
            w = alive[t]
            low = w & (~w + np.uint64(1))
            acc += leaf_value[t, _LOWEST_BIT[(low * _DEBRUIJN) >> np.uint64(58)]]
        out[i] = acc


def _previous_trees(forest: FlatForest, x_num: np.ndarray, x_cat: np.ndarray) -> np.ndarray:
    """The trees as served before (:func:`_previous_leafmask_kernel` on the same tables in
    64-bit words), in the same 8192-row chunks on the pool."""
    masks = forest.masks
    if masks is None:  # trees of more than 64 leaves: walked on ranks, as before
        return forest.predict(x_num, x_cat)
    leaf_value = np.zeros((forest.n_trees, 64))
    leaf_value[:, :forest.leaf_mask_value.shape[1]] = forest.leaf_mask_value
    if masks.dtype == np.uint32:  # the unused upper bits as they were: set
        masks = masks.astype(np.uint64) | np.uint64(0xFFFFFFFF00000000)
    out = np.empty(x_num.shape[0])

    def run(a: int) -> None:
        b = a + 8192
        _previous_leafmask_kernel(x_num[a:b], x_cat[a:b], forest.mean, forest.scale,
                                  forest.col_cat, forest.col_index, forest.col_level, forest.cuts,
                                  forest.cut_start, forest.mask_start, masks, leaf_value,
                                  forest.baseline, out[a:b])

    map_chunks(run, range(0, x_num.shape[0], 8192))
    return out


def gbm_speed(model: Surrogate, big, repeats: int, n_single: int) -> dict[str, object]:
    """Batched and single-query speed of a surrogate whose served model is gradient boosting.

    Also, in the same run: the evaluators served before (leaf masks one row at a time in
    64-bit words; the exact k-NN distance of every row, ``distances=True``) with the same
    range check, so ``ratio_vs_previous`` is a ratio of two figures measured under the same
    load; and the served path with the full domain check on one thread, against the
    ``--threads`` of the run.
    """
    n = len(big)
    x_num, x_cat = model.encode(big)
    model.predict_array(x_num[:10], x_cat[:10])  # build the flat forest and the k-NN index
    forest = model._forest
    dom = model.domain
    assert forest is not None
    # the regressor's trees alone and the scale model's alone: the two-pass form
    regressor = FlatForest(model.gbm, model.preprocessor)
    sm = scale_model(model.gbm)
    scale_alone = None if sm is None else FlatForest(sm, model.preprocessor)
    served = model.predict_array(x_num, x_cat)
    assert np.array_equal(_previous_trees(regressor, x_num, x_cat), served["log10"])
    if scale_alone is not None:
        both = forest.predict(x_num, x_cat)
        assert np.array_equal(both[:, 0], served["log10"])
        assert np.array_equal(both[:, 1], scale_alone.predict(x_num, x_cat))
    assert np.array_equal(model.gbm.predict(design_matrix(model.preprocessor, x_num, x_cat)),
                          served["log10"])

    # the served answer against the previous one on this batch: the same flags on every
    # row, and the same distance (bit for bit) on every row beyond the threshold
    flag_now, dist_now = dom.check(x_num)
    flag_before, dist_before = dom.check(x_num, distances=True)
    beyond = dist_before > dom.threshold_
    agreement = {"rows": n, "flagged": int(flag_now.sum()),
                 "flagged_by_distance": int(beyond.sum()),
                 "flags_differing_from_previous": int((flag_now != flag_before).sum()),
                 "distances_beyond_threshold_differing": int(
                     (dist_now[beyond] != dist_before[beyond]).sum()),
                 "max_abs_distance_difference": float(
                     np.max(np.abs(dist_now[beyond] - dist_before[beyond]), initial=0.0)),
                 "rows_without_distance": int(np.isnan(dist_now).sum())}

    def previous_full() -> None:
        _previous_trees(regressor, x_num, x_cat)
        if scale_alone is not None:
            scale_alone.predict(x_num, x_cat)
        dom.check(x_num, distances=True)

    def two_passes() -> None:
        regressor.predict(x_num, x_cat)
        if scale_alone is not None:
            scale_alone.predict(x_num, x_cat)

    batched = {
        "trees_only": _median_rate(lambda: model.predict_array(x_num, x_cat, ood=False), n,
                                   repeats),
        "with_range_ood": _median_rate(lambda: model.predict_array(x_num, x_cat, knn=False), n,
                                       repeats),
        "with_range_and_knn_ood": _median_rate(lambda: model.predict_array(x_num, x_cat), n,
                                               repeats),
        "with_range_and_knn_ood_all_distances": _median_rate(
            lambda: model.predict_array(x_num, x_cat, distances=True), n, max(1, repeats // 2)),
        "domain_check_only": _median_rate(lambda: dom.check(x_num), n, repeats),
        "forest_one_pass": _median_rate(lambda: forest.predict(x_num, x_cat), n, repeats),
        "forest_two_passes": _median_rate(two_passes, n, repeats),
        "previous_trees_only": _median_rate(lambda: _previous_trees(regressor, x_num, x_cat), n,
                                            repeats),
        "previous_knn_only": _median_rate(lambda: dom.check(x_num, distances=True), n,
                                          max(1, repeats // 2)),
        "previous_with_range_and_knn_ood": _median_rate(previous_full, n, max(1, repeats // 2)),
        "predict_dataframe": _median_rate(lambda: model.predict(big), n, max(1, repeats // 2)),
        "sklearn_predict_reference": _median_rate(
            lambda: model.gbm.predict(design_matrix(model.preprocessor, x_num, x_cat)), n,
            max(1, repeats // 2)),
    }
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        batched["with_range_and_knn_ood_1_thread"] = _median_rate(
            lambda: model.predict_array(x_num, x_cat), n, repeats)
    finally:
        torch.set_num_threads(threads)
    r = {k: v["predictions_per_s"] for k, v in batched.items()}
    ratios = {"trees_only": r["trees_only"] / r["previous_trees_only"],
              "forest_one_pass_vs_two": r["forest_one_pass"] / r["forest_two_passes"],
              "knn_only": r["domain_check_only"] / r["previous_knn_only"],
              "with_range_and_knn_ood": (r["with_range_and_knn_ood"]
                                         / r["previous_with_range_and_knn_ood"]),
              f"{threads}_threads_vs_1": (r["with_range_and_knn_ood"]
                                          / r["with_range_and_knn_ood_1_thread"])}
    one = big.iloc[[123]]
    xn1, xc1 = model.encode(one)
    single = {
        "predict_dataframe": _latency(lambda: model.predict(one), n_single),
        "predict_array_with_ood": _latency(lambda: model.predict_array(xn1, xc1), n_single),
        "predict_array_no_ood": _latency(lambda: model.predict_array(xn1, xc1, ood=False),
                                         n_single),
    }
    idx = dom.index
    return {"n_trees": int(model.gbm.n_iter_),
            "leaf_mask_bits": int(forest.masks.dtype.itemsize * 8) if forest.masks is not None
            else None,
            "ood_reference_rows": int(dom.reference_.shape[0]),
            "ood_index": {"distinct_rows": int(idx.rest.shape[0]),
                          "groups": int(idx.keys_t.shape[1]),
                          "super_groups": int(idx.super_start.size - 1),
                          "key_columns": [dom.names[c] for c in idx.perm[:idx.n_key]]},
            "previous": "leaf masks one row at a time in 64-bit words; exact k-NN distance "
                        "of every row (the evaluators served before, same run)",
            "batched": batched, "ratio_vs_previous": ratios,
            "domain_check_vs_previous": agreement, "single_query": single,
            "goals": _goals(batched, single, ("trees_only", "with_range_ood",
                                              "with_range_and_knn_ood"))}


def knn_scaling(case_counts: tuple[int, ...] = (60, 300, 1024), n_rows: int = 20_000
                ) -> list[dict[str, object]]:
    """CPU time per row of the k-NN distance against the reference size, one thread.

    A domain check fitted as the train stage fits it (2 000 reference rows at most)
    on ``make_synthetic_dataset(n, seed=0)`` per ``n`` of ``case_counts``; queries:
    ``n_rows`` rows of unseen cases (seed 1) and ``n_rows`` training rows; the
    exact compiled search (every row's distance) against the float32 GEMM distance,
    and the served flag search (stops once a row is certainly within the threshold;
    :meth:`~drillfatigue.surrogate.ood.KnnIndex.distance_beyond`) in the same run.
    """
    cfg = SurrogateConfig()
    feats = list(cfg.features)
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    out = []
    try:
        for n_cases in case_counts:
            tr = make_synthetic_dataset(n_cases, seed=0)[feats].to_numpy()
            cal = make_synthetic_dataset(max(20, n_cases // 5), seed=5)[feats].to_numpy()
            unseen = make_synthetic_dataset(n_rows // 16 + 1, seed=1)[feats].to_numpy()[:n_rows]
            seen = tr[np.random.default_rng(0).integers(0, len(tr), n_rows)]
            dom = DomainChecker(feats, reference_rows=2000).fit(tr, cal, tr.mean(axis=0),
                                                                tr.std(axis=0))
            row: dict[str, object] = {"cases": n_cases,
                                      "distinct_reference_rows": int(dom.index.rest.shape[0]),
                                      "groups": int(dom.index.keys_t.shape[1]),
                                      "super_groups": int(dom.index.super_start.size - 1)}
            for name, x in (("unseen_cases", unseen), ("training_rows", seen)):
                dist = np.empty(len(x))
                dom.index.mean_distance(x, dom.mean_, dom.scale_, dom.k, dist)
                c0 = time.process_time()
                dom.index.mean_distance(x, dom.mean_, dom.scale_, dom.k, dist)
                c1 = time.process_time()
                _previous_knn((x - dom.mean_) / dom.scale_, dom.reference_, dom.k)
                c2 = time.process_time()
                far = np.empty(len(x))
                dom.index.distance_beyond(x, dom.mean_, dom.scale_, dom.k, dom.threshold_, far)
                c3 = time.process_time()
                dom.index.distance_beyond(x, dom.mean_, dom.scale_, dom.k, dom.threshold_, far)
                c4 = time.process_time()
                assert np.array_equal(far > dom.threshold_, dist > dom.threshold_)
                row[name] = {"us_per_row": (c1 - c0) / len(x) * 1e6,
                             "previous_us_per_row": (c2 - c1) / len(x) * 1e6,
                             "ratio": (c2 - c1) / (c1 - c0),
                             "served_flag_us_per_row": (c4 - c3) / len(x) * 1e6,
                             "served_flag_vs_exact": (c1 - c0) / (c4 - c3)}
            out.append(row)
    finally:
        torch.set_num_threads(threads)
    return out


def _goals(batched: dict, single: dict, served: tuple[str, ...]) -> dict[str, bool]:
    """The issue's speed goals: >= 1e6 predictions/s batched (best served path and with the
    full domain check), single query p50 < 2 ms through the public API."""
    return {"batched_predictions_per_s_ge_1e6": max(batched[k]["predictions_per_s"]
                                                    for k in served) >= 1e6,
            "batched_with_range_and_knn_ood_ge_1e6":
                batched["with_range_and_knn_ood"]["predictions_per_s"] >= 1e6,
            "single_query_p50_lt_2ms": single["predict_dataframe"]["p50_ms"] < 2.0}


def accuracy(n_cases: int, threads: int) -> dict[str, object]:
    """Fit with the default hyper-parameters on ``n_cases`` synthetic cases; score
    ensemble, GP and HGB on the held-out test cases (see module docstring)."""
    from drillfatigue.surrogate.evaluation import evaluate

    cfg = SurrogateConfig(n_threads=threads)
    data = make_synthetic_dataset(n_cases, seed=cfg.split_seed)
    t0 = time.perf_counter()
    model = fit_surrogate(data, cfg)
    fit_s = time.perf_counter() - t0
    metrics, _ = evaluate(data, model, cfg)
    ens = metrics["ensemble"]
    return {
        "dataset": f"make_synthetic_dataset({n_cases}, seed={cfg.split_seed}), "
                   f"{len(data)} rows, case-wise split",
        "fit_s": fit_s, "epochs": model.metadata["training"]["epochs"],
        "load_avg_1min_end": os.getloadavg()[0],
        "metrics": metrics,
        "targets": {
            "r2_ge_0.95": ens["r2"] >= 0.95,
            "factor2_ge_0.90": ens["factor2_fraction"] >= 0.90,
            "coverage_within_3pct": abs(ens["coverage"] - model.coverage) <= 0.03,
            "rmse_below_gp": ens["rmse"] < metrics["gp"]["rmse"],
            "rmse_below_hgb": ens["rmse"] < metrics["hgb"]["rmse"],
        },
    }


def simulator_case_seconds(params_path: Path) -> dict[str, float | str]:
    """Wall time of the simulator + fatigue answer the surrogate replaces.

    One case of the project's default sweep (``params.yaml``: its first design
    point, its window and string), simulated and evaluated on one process in
    this run, after a warm-up that fills numba's cache (compilation excluded).
    """
    import tempfile

    from drillfatigue.config import load_params
    from drillfatigue.sweep.cases import fatigue_case, run_case, warmup_fatigue, warmup_simulation
    from drillfatigue.sweep.design import base_case_from_params, design_cases

    params = load_params(params_path)
    table = design_cases(params.sweep, base_case_from_params(params))
    case = json.loads(table["case_json"].iloc[0])
    warmup_simulation(case)
    with tempfile.TemporaryDirectory() as tmp:
        run_dir = Path(tmp) / "run"
        run_dir.mkdir()
        t0 = time.perf_counter()
        summary = run_case(case, run_dir)
        sim_s = time.perf_counter() - t0
        (run_dir / "DONE").write_text("bench", encoding="utf-8")
        task = {"run_dir": str(run_dir), "run_marker": "bench",
                "fatigue": params.fatigue.model_dump(mode="json"),
                "criteria": list(params.sweep.fatigue_criteria), "api_rp7g": True, "case": case}
        warmup_fatigue(task)
        fat_dir = Path(tmp) / "fatigue"
        fat_dir.mkdir()
        t0 = time.perf_counter()
        fatigue_case(task, fat_dir)
        fat_s = time.perf_counter() - t0
    return {"case": f"params.yaml sweep case {table['case_id'].iloc[0]}",
            "simulated_s": float(summary["duration_s"]), "n_segments": int(summary["n_segments"]),
            "simulate_wall_s": sim_s, "fatigue_wall_s": fat_s, "total_wall_s": sim_s + fat_s}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats (CI smoke run)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sim-seconds", type=float, default=None,
                    help="wall time of one simulator run of a comparable case (default: "
                         "measured in this run on the first case of params.yaml's sweep)")
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--accuracy-cases", type=int, default=0,
                    help="also fit on this many synthetic cases and score vs the baselines")
    ap.add_argument("--no-speed", action="store_true", help="accuracy only (keeps the "
                    "speed section of an existing result file)")
    ap.add_argument("--knn-scaling", action="store_true", help="only the k-NN distance's "
                    "cost against the reference size (kept with the rest of an existing "
                    "result file)")
    ap.add_argument("--served-model", default=None,
                    help="also measure this saved gbm model folder (with --served-data)")
    ap.add_argument("--served-data", default=None,
                    help="dataset parquet the --served-model was trained on (query rows)")
    ap.add_argument("--served-baseline", default=None,
                    help="a second saved gbm model folder measured in the same run on the same "
                         "rows (e.g. one with gbm_interval: per_decade against scaled)")
    args = ap.parse_args(argv)
    repeats, n_single = (3, 200) if args.quick else (10, 2000)
    if args.knn_scaling:
        res = json.loads(Path(args.out).read_text()) if Path(args.out).is_file() else {}
        res["knn_scaling"] = knn_scaling()
        write_json(res, args.out)
        print(json.dumps(res["knn_scaling"], indent=2))
        return 0
    if args.no_speed:
        if args.accuracy_cases <= 0:
            ap.error("--no-speed needs --accuracy-cases N")
        res = json.loads(Path(args.out).read_text()) if Path(args.out).is_file() else {}
        res["accuracy_synthetic"] = accuracy(args.accuracy_cases, args.threads)
        write_json(res, args.out)
        print(json.dumps(res["accuracy_synthetic"], indent=2))
        return 0

    cfg = SurrogateConfig(max_epochs=3, patience=3, n_threads=args.threads)
    data = make_synthetic_dataset(60, seed=0)
    t0 = time.perf_counter()
    model = fit_surrogate(data, cfg)
    fit_s = time.perf_counter() - t0
    torch.set_num_threads(args.threads)

    n = 100_000
    big = make_synthetic_dataset(n // 16 + 1, seed=1).iloc[:n]
    x_num, x_cat = model.encode(big)
    res: dict[str, object] = {
        "machine": {"cpu_count": os.cpu_count(), "torch_threads": args.threads,
                    "load_avg_1min_start": os.getloadavg()[0], "python": platform.python_version(),
                    "torch": torch.__version__, "processor": platform.processor()},
        "model": {"members": len(cfg.seeds), "hidden_layers": list(cfg.hidden_layers),
                  "n_numeric": len(model.features), "n_categorical": len(model.categorical),
                  "ood_reference_rows": int(model.domain.reference_.shape[0]),
                  "fit_s_3_epochs": fit_s},
        "batch_rows": n,
    }
    batched = {
        "network_only": _median_rate(lambda: model.predict_array(x_num, x_cat, ood=False), n, repeats),
        "with_range_ood": _median_rate(lambda: model.predict_array(x_num, x_cat, knn=False), n, repeats),
        "with_range_and_knn_ood": _median_rate(lambda: model.predict_array(x_num, x_cat), n,
                                               max(1, repeats // 2)),
        "predict_dataframe": _median_rate(lambda: model.predict(big), n, max(1, repeats // 2)),
    }
    ts_path = Path(os.environ.get("TMPDIR", "/tmp")) / f"bench_surrogate_{os.getpid()}.ts"
    export_torchscript(model, ts_path)
    ts = load_torchscript(ts_path)
    xt, ct = torch.from_numpy(x_num.astype(np.float32)), torch.from_numpy(x_cat)

    def run_ts() -> None:
        with torch.inference_mode():
            ts(xt, ct)

    batched["torchscript"] = _median_rate(run_ts, n, repeats)
    ts_path.unlink(missing_ok=True)
    try:
        import onnxruntime as ort

        from drillfatigue.surrogate.export import export_onnx

        onnx_path = ts_path.with_suffix(".onnx")
        export_onnx(model, onnx_path)
        so = ort.SessionOptions()
        so.intra_op_num_threads = args.threads
        sess = ort.InferenceSession(str(onnx_path), so, providers=["CPUExecutionProvider"])
        feed = {"x_num": x_num.astype(np.float32), "x_cat": x_cat.astype(np.int64)}
        batched["onnxruntime"] = _median_rate(lambda: sess.run(None, feed), n, repeats)
        onnx_path.unlink(missing_ok=True)
    except ImportError:
        pass
    res["batched"] = batched

    one = big.iloc[[123]]
    xn1, xc1 = model.encode(one)
    res["single_query"] = {
        "predict_dataframe": _latency(lambda: model.predict(one), n_single),
        "predict_array_with_ood": _latency(lambda: model.predict_array(xn1, xc1), n_single),
        "predict_array_no_ood": _latency(lambda: model.predict_array(xn1, xc1, ood=False), n_single),
    }
    p50_s = res["single_query"]["predict_dataframe"]["p50_ms"] / 1e3
    measured = None
    if args.sim_seconds is None:
        measured = simulator_case_seconds(PARAMS)
        sim_seconds = float(measured["total_wall_s"])
    else:
        sim_seconds = args.sim_seconds
    res["speedup_vs_simulator"] = {
        "paper_seconds_per_case": PAPER_SECONDS_PER_CASE,
        "paper_ratio_single_query": PAPER_SECONDS_PER_CASE / p50_s,
        "sim_seconds": sim_seconds,
        "simulator_case": measured,
        "ratio_single_query": sim_seconds / p50_s,
    }
    ens_goals = _goals(batched, res["single_query"], tuple(batched))
    # served gradient boosting, same synthetic table and query rows
    gcfg = SurrogateConfig(max_epochs=3, patience=3, n_threads=args.threads, served_model="gbm")
    t0 = time.perf_counter()
    gmodel = fit_surrogate(data, gcfg)
    res["gbm"] = {"model": "served_model gbm fitted on make_synthetic_dataset(60, seed=0)",
                  "fit_s": time.perf_counter() - t0,
                  **gbm_speed(gmodel, big, repeats, n_single)}
    res["goals"] = {"ensemble": ens_goals, "gbm": res["gbm"]["goals"]}
    if args.served_model:
        saved = Surrogate.load(args.served_model)
        rows = pd.read_parquet(args.served_data).sample(n, replace=True, random_state=0)
        res["gbm_saved_model"] = {"model": str(args.served_model),
                                  "query_rows": f"{n} rows drawn from {args.served_data}",
                                  **gbm_speed(saved, rows, repeats, n_single)}
        res["goals"]["gbm_saved_model"] = res["gbm_saved_model"]["goals"]
        if args.served_baseline:
            base = Surrogate.load(args.served_baseline)
            res["gbm_saved_baseline"] = {"model": str(args.served_baseline),
                                         **gbm_speed(base, rows, repeats, n_single)}
            a, b = res["gbm_saved_model"], res["gbm_saved_baseline"]
            res["gbm_saved_model"]["vs_baseline"] = {
                "interval": [saved.metadata["gbm"].get("interval"),
                             base.metadata["gbm"].get("interval")],
                "batched_ratio": {k: a["batched"][k]["predictions_per_s"]
                                  / b["batched"][k]["predictions_per_s"]
                                  for k in a["batched"] if k in b["batched"]},
                "single_p50_ratio": {k: a["single_query"][k]["p50_ms"]
                                     / b["single_query"][k]["p50_ms"]
                                     for k in a["single_query"]}}
    res["machine"]["load_avg_1min_end"] = os.getloadavg()[0]
    if args.accuracy_cases > 0:
        res["accuracy_synthetic"] = accuracy(args.accuracy_cases, args.threads)
    elif Path(args.out).is_file():  # keep an earlier accuracy section
        old = json.loads(Path(args.out).read_text())
        if "accuracy_synthetic" in old:
            res["accuracy_synthetic"] = old["accuracy_synthetic"]
    if Path(args.out).is_file():  # and an earlier k-NN scaling section
        old = json.loads(Path(args.out).read_text())
        if "knn_scaling" in old:
            res["knn_scaling"] = old["knn_scaling"]
    write_json(res, args.out)
    summary = {"batched_predictions_per_s": {k: round(v["predictions_per_s"])
                                             for k, v in batched.items()},
               "single_query_p50_ms": {k: round(v["p50_ms"], 3)
                                       for k, v in res["single_query"].items()}}
    for key in ("gbm", "gbm_saved_model"):
        if key in res:
            summary[key] = {"n_trees": res[key]["n_trees"],
                            "ratio_vs_previous": res[key]["ratio_vs_previous"],
                            "domain_check_vs_previous": res[key]["domain_check_vs_previous"],
                            "batched_predictions_per_s": {
                                k: round(v["predictions_per_s"])
                                for k, v in res[key]["batched"].items()},
                            "single_query_p50_ms": {k: round(v["p50_ms"], 3) for k, v in
                                                    res[key]["single_query"].items()}}
    summary["goals"] = res["goals"]
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
