"""Is ROP worth a model input? The served model with and without it, on the held-out design.

The sweep designs the driller's controls (rpm, the WOB set-point) and the rock's
drillability; the ROP is what the bit cut (the dataset's post-run column
``achieved_mean_rop_m_per_s``). A rig logs ROP, so the twin could pass it to the
model: at a given rpm and WOB it tells how drillable the rock is. This fits the
model of ``params.yaml``'s ``surrogate`` section twice on the pipeline's dataset,
as the ``train`` stage does (:func:`drillfatigue.surrogate.fit_surrogate` with the
design's domain), once as configured and once with the achieved ROP as one more
input (named ``rop_m_per_s``, so a log's ROP channel would fill it), and scores
both on the held-out design as the ``evaluate`` stage does
(:func:`drillfatigue.surrogate.evaluation.evaluate`): the served model's rows
predicted within the horizon (factor 2, interval coverage) and the governing
damage per component.

Usage: ``python benchmarks/rop_input.py [--params params.yaml]
[--out benchmarks/results/rop_input.json]`` after ``make repro`` (reads
``data/dataset`` and ``data/heldout/dataset``).
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path
from typing import Any

import pandas as pd

from drillfatigue.config import load_params
from drillfatigue.surrogate import fit_surrogate
from drillfatigue.surrogate.bounds import domain_bounds
from drillfatigue.surrogate.evaluation import evaluate
from drillfatigue.surrogate.io import write_json

RESULT = Path(__file__).parent / "results" / "rop_input.json"
ROP = "rop_m_per_s"
ACHIEVED = "achieved_mean_rop_m_per_s"


def _with_rop(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.assign(**{ROP: frame[ACHIEVED].to_numpy()})


def _summary(metrics: dict[str, Any], served: str) -> dict[str, Any]:
    d = metrics["deciding"][served]
    return {"deciding_rows": d["rows"], "governing": {k: d["governing"][k] for k in
                                                      ("n", "factor2_fraction", "rmse")
                                                      if k in d["governing"]},
            "by_component_type_location": d.get("by_component_type_location", {}),
            "ood_fraction_test": metrics["ood_fraction_test"]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", default="params.yaml")
    ap.add_argument("--out", default=str(RESULT))
    args = ap.parse_args(argv)
    params = load_params(args.params)
    base = params.surrogate
    frame = _with_rop(pd.read_parquet(Path(params.sweep.dataset_dir) / "damage.parquet"))
    held = _with_rop(pd.read_parquet(params.heldout.dataset_dir + "/damage.parquet"))
    served = "hgb" if base.served_model == "gbm" else "ensemble"
    out: dict[str, Any] = {"served_model": served, "n_train_cases": int(frame["case_id"].nunique()),
                           "n_heldout_cases": int(held["case_id"].nunique()),
                           "machine": platform.processor() or platform.machine(), "variants": {}}
    for name, features in (("without_rop", tuple(base.features)),
                           ("with_rop", (*base.features, ROP))):
        cfg = base.model_copy(update={"features": features})
        t = time.perf_counter()
        bounds = domain_bounds(params, cfg.features, frame["s_from_bit_m"].to_numpy())
        model = fit_surrogate(frame, cfg, bounds=bounds)
        metrics, _ = evaluate(frame, model, cfg, heldout=held)
        out["variants"][name] = {**_summary(metrics, served),
                                 "fit_and_score_s": time.perf_counter() - t}
        r = out["variants"][name]["deciding_rows"]
        print(f"{name}: factor 2 on {r['factor2_fraction']:.3f} of {r['n']} deciding rows, "
              f"coverage {r['coverage']:.3f}")
    write_json(out, Path(args.out))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
