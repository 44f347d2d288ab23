"""Research-scale accuracy of the served model, and how much of its error is the simulation's.

Reads the outputs of a research-scale run of the pipeline (``dvc exp run -S
sweep.n_cases=256 -S heldout.n_cases=64``, or the same two values set in
``params.yaml`` of a clone before ``make repro``) and reports:

* the ``evaluate`` stage's figures for the served gradient boosting on the rows
  that decide life (rows predicted within the horizon): factor 2, coverage,
  per component type x location, and the governing damage per component;
* the held-out cases split by how much their own damage moves under a 1 %
  change of rpm (``heldout_draws``: three runs per case, the spread of the
  log10 rate per case, ``data/heldout/draws/spread.json``): a case whose rate
  moves by more than a factor 2 (sigma > 0.3 decades) under a change no rig can
  hold has no answer a model can be scored on within a factor 2. The served
  model is scored again on the other cases; and the cases above the threshold
  are described by their design inputs (profile, BHA, mean rpm and lobes);
* the replicate spread of the ``replicates`` stage (8 training cases x 3 runs).

Usage: ``python benchmarks/research_accuracy.py --run PATH
[--out benchmarks/results/surrogate_research_driller_inputs.json]`` where
``PATH`` is the clone that ran the research scale (its ``data/`` folder).
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.surrogate.evaluation import deciding_metrics
from drillfatigue.surrogate.io import write_json

RESULT = Path(__file__).parent / "results" / "surrogate_research_driller_inputs.json"
#: a case whose log10 rate moves by more than this (1 sigma, decades) under a
#: 1 % rpm change: a factor 2 is 0.301 decades
CHAOTIC_SIGMA_LOG10 = 0.3
HORIZON_H = 1e5


def _rows(metrics: dict[str, Any]) -> dict[str, Any]:
    r = metrics["hgb"]["rows"]
    return {"factor2": round(r["factor2_fraction"], 4), "coverage": round(r["coverage"], 4),
            "rmse": round(r["rmse"], 4), "n_rows": int(r["n"])}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", type=Path, required=True, help="clone that ran the research scale")
    ap.add_argument("--out", type=Path, default=RESULT)
    args = ap.parse_args()
    run = args.run
    metrics = json.loads((run / "data/surrogate/metrics.json").read_text(encoding="utf-8"))
    pred = pd.read_csv(run / "data/surrogate/plots/predictions.csv")
    sigma = json.loads((run / "data/heldout/draws/spread.json").read_text(
        encoding="utf-8"))["case_sigma_log10"]
    cases = pd.read_parquet(run / "data/heldout/design/cases.parquet")
    replicates = json.loads((run / "data/replicates/spread.json").read_text(encoding="utf-8"))

    pred["sigma"] = pred["case_id"].astype(str).map(sigma)
    cases["sigma"] = cases["case_id"].astype(str).map(sigma)
    chaotic = cases["sigma"] > CHAOTIC_SIGMA_LOG10
    steady_ids = set(cases.loc[~chaotic, "case_id"].astype(str))
    steady = pred[pred["case_id"].astype(str).isin(steady_ids)]

    d = metrics["deciding"]["hgb"]
    gov = metrics["governing"]["hgb"]
    out: dict[str, Any] = {
        "run": str(run),
        "commit": subprocess.run(["git", "-C", str(run), "rev-parse", "HEAD"],
                                 capture_output=True, text=True, check=False).stdout.strip(),
        "machine": {"python": platform.python_version()},
        "n_train_cases": metrics["hgb"].get("n_train_cases"),
        "n_test_cases": metrics["n_test_cases"],
        "n_test_rows": metrics["n_test_rows"],
        "ood_fraction_test": round(metrics["ood_fraction_test"], 4),
        "served_deciding_rows": {
            "factor2": round(d["rows"]["factor2_fraction"], 4),
            "coverage": round(d["rows"]["coverage"], 4),
            "rmse": round(d["rows"]["rmse"], 4), "n_rows": d["rows"]["n"],
            "mean_width_decades": round(d["rows"]["mean_width"], 4)},
        "served_by_component_type_location": {
            k: {"n_rows": v["n"], "factor2": round(v["factor2_fraction"], 4),
                "coverage": round(v["coverage"], 4)}
            for k, v in d["by_component_type_location"].items()},
        "served_governing_per_case": round(gov["case_max"]["factor2_fraction"], 4),
        "against_mean_of_draws": _rows(metrics["deciding_draws"]["log_mean_of_draws"]),
        "replicate_spread": {"sigma_log10": round(replicates["sigma_log10"], 4),
                             "ceiling_factor2": round(replicates["ceiling_factor2_fraction"], 4),
                             "n_cases": replicates["n_cases"]},
        "heldout_case_sigma_quantiles": {
            str(q): round(float(np.quantile(list(sigma.values()), q)), 4)
            for q in (0.5, 0.75, 0.9)},
        "chaotic_threshold_sigma_log10": CHAOTIC_SIGMA_LOG10,
        "n_chaotic_cases": int(chaotic.sum()),
        "served_deciding_rows_without_chaotic_cases": {
            **_rows(deciding_metrics(steady, ("hgb",), HORIZON_H)),
            "n_cases": int(steady["case_id"].nunique())},
        "chaotic_cases_by_profile": {
            str(k): int(v) for k, v in cases.loc[chaotic, "well.profile"].value_counts().items()},
        "cases_by_profile": {
            str(k): int(v) for k, v in cases["well.profile"].value_counts().items()},
        "chaotic_cases_by_bha": {
            str(k): int(v) for k, v in cases.loc[chaotic, "string.bha"].value_counts().items()},
        "mean_inputs": {
            name: {"chaotic": round(float(cases.loc[chaotic, col].mean()), 6),
                   "other": round(float(cases.loc[~chaotic, col].mean()), 6)}
            for name, col in (("rpm", "operation.rpm"), ("wob_N", "operation.wob_N"),
                              ("lobe_amplitude_m", "operation.lobe_amplitude_m"),
                              ("mu_dynamic", "friction.mu_dynamic"))},
    }
    write_json(out, args.out)
    print(json.dumps({k: out[k] for k in ("served_deciding_rows",
                                          "served_deciding_rows_without_chaotic_cases",
                                          "n_chaotic_cases", "replicate_spread")}, indent=1))


if __name__ == "__main__":
    main()
