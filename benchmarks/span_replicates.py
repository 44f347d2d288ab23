"""Benchmark: replicate spread and window convergence of the span correction.

Workload: the sweep cases in ``benchmarks/cases/span_replicates/`` (four of the
default sweep's designed cases that the replicates stage runs, one per BHA
kind: packed, pendulum, slick, MWD + jar + HWDP), each simulated as the
pipeline does (:func:`drillfatigue.sweep.window.run_case_converged`: the window
rule of ``params.yaml``'s ``sweep.window``) and evaluated as the fatigue stage
does (:func:`drillfatigue.sweep.cases.fatigue_case` with ``surrogate.criterion``)
at ``rpm x (1 + k rel_step)``, k = 0 .. ``--replicates`` - 1. Reported per
source tree:

``sigma_governing_log10``
    pooled standard deviation over the cases of log10 of the governing damage
    rate (the largest of the case's joints and locations), each case's variance
    over its replicates (ddof 1);
``sigma_log10``
    the replicates stage's pooled figure over every joint and location
    (:func:`drillfatigue.sweep.replicates.replicate_spread`);
``windows_converged``
    how many runs the window rule closed below ``sweep.window.max_s``;
``simulate_s_per_simulated_s``
    wall time of the simulation over the simulated time (every window tried).

Baselines, in the same run: other revisions of this repository
(``--baseline NAME=REV``: its ``src/`` and ``params.yaml`` by ``git archive``)
or source trees (``--baseline NAME=DIR``, DIR holding ``src/`` and
``params.yaml``), each run in its own process with its own numba cache.

Run: ``python benchmarks/span_replicates.py [--rel-step 1e-4] [--replicates 3]
[--baseline level=REV ...]`` -> benchmarks/results/span_replicates.json. About
half a minute of one core per run and tree (12 runs a tree with the defaults).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "benchmarks" / "cases" / "span_replicates"
RESULT = ROOT / "benchmarks" / "results" / "span_replicates.json"


def _git(root: Path, *args: str) -> str | None:
    """Output of a git command in ``root``, or None when it fails."""
    res = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True)
    return res.stdout.strip() or None if res.returncode == 0 else None


def run_tree(tree: Path, cases: list[Path], rel_step: float, n_rep: int,
             work: Path) -> list[dict[str, Any]]:
    """Simulate and evaluate every case and replicate with the package under ``tree/src``
    (this process must have imported it from there); one record per run."""
    import numpy as np
    import pandas as pd
    import yaml

    from drillfatigue.config import load_params
    from drillfatigue.sweep.cases import fatigue_case
    from drillfatigue.sweep.window import run_case_converged, window_inputs

    params = load_params(tree / "params.yaml")
    criterion = params.surrogate.criterion
    fatigue_cfg = params.fatigue.model_dump(mode="json")
    records = []
    for path in cases:
        base = yaml.safe_load(path.read_text(encoding="utf-8"))
        for k in range(n_rep):
            done = work / f"{path.stem}-{k}.json"
            if done.is_file():
                records.append(json.loads(done.read_text(encoding="utf-8")))
                continue
            case = json.loads(json.dumps(base))
            case["operation"]["rpm"] = base["operation"]["rpm"] * (1.0 + k * rel_step)
            run_dir = work / f"{path.stem}-{k}" / "run"
            fat_dir = work / f"{path.stem}-{k}" / "fatigue"
            run_dir.mkdir(parents=True, exist_ok=True)
            fat_dir.mkdir(parents=True, exist_ok=True)
            t0 = time.perf_counter()
            run_case_converged({"case": case, "window": window_inputs(params)}, run_dir)
            sim_wall = time.perf_counter() - t0
            window = json.loads((run_dir / "window.json").read_text(encoding="utf-8"))
            fatigue_case({"run_dir": str(run_dir), "fatigue": fatigue_cfg,
                          "criteria": [criterion], "api_rp7g": False}, fat_dir)
            rows = pd.read_parquet(fat_dir / "damage.parquet")
            rows = rows[rows["criterion"] == criterion]
            rate = rows["damage_rate_per_h"].to_numpy(dtype=float)
            gov = int(np.nanargmax(rate))
            summary = json.loads((run_dir / "summary.json").read_text(encoding="utf-8"))
            rec = {"case": path.stem, "replicate": k, "rpm": case["operation"]["rpm"],
                   "window_s": window["window_s"], "converged": window["converged"],
                   "rate_change_rel": window["rate_change_rel"],
                   "simulated_s": sum(t["window_s"] for t in window["tries"]),
                   "simulate_wall_s": sim_wall,
                   "governing": {"joint": int(rows["joint"].iloc[gov]),
                                 "location": str(rows["location"].iloc[gov]),
                                 "damage_rate_per_h": float(rate[gov])},
                   "span_bending_buckled_samples": summary.get("span_bending_buckled_samples"),
                   "rows": [{"joint": int(j), "location": str(loc), "damage_rate_per_h": float(r)}
                            for j, loc, r in zip(rows["joint"], rows["location"],
                                                 rows["damage_rate_per_h"], strict=True)]}
            done.write_text(json.dumps(rec), encoding="utf-8")
            records.append(rec)
            print(f"{tree.name}: {path.stem} k={k}: window {rec['window_s']:.0f} s "
                  f"converged {rec['converged']}, governing {rec['governing']}", flush=True)
    return records


def summarise(records: list[dict[str, Any]], floor_per_h: float) -> dict[str, Any]:
    """Spread and window figures of one tree's runs (see the module docstring)."""
    import numpy as np
    import pandas as pd

    from drillfatigue.sweep.replicates import replicate_spread

    cases: dict[str, Any] = {}
    var = []
    for name in sorted({r["case"] for r in records}):
        runs = sorted((r for r in records if r["case"] == name), key=lambda r: r["replicate"])
        y = np.log10([max(r["governing"]["damage_rate_per_h"], floor_per_h) for r in runs])
        s = float(np.std(y, ddof=1)) if len(y) > 1 else math.nan
        var.append(s * s)
        cases[name] = {"sigma_governing_log10": s,
                       "governing_rate_per_h": [r["governing"]["damage_rate_per_h"] for r in runs],
                       "governing": [f"{r['governing']['joint']}/{r['governing']['location']}"
                                     for r in runs],
                       "window_s": [r["window_s"] for r in runs],
                       "converged": [r["converged"] for r in runs],
                       "rate_change_rel": [r["rate_change_rel"] for r in runs]}
    frame = pd.DataFrame([{"base_case_id": r["case"], "replicate": r["replicate"], **row}
                          for r in records for row in r["rows"]])
    spread = replicate_spread(frame, floor_per_h=floor_per_h)
    sim_s = sum(r["simulated_s"] for r in records)
    wall = sum(r["simulate_wall_s"] for r in records)
    return {"sigma_governing_log10": float(math.sqrt(np.mean(var))),
            "sigma_log10": spread["sigma_log10"],
            "ceiling_factor2_fraction": spread["ceiling_factor2_fraction"],
            "windows_converged": sum(bool(r["converged"]) for r in records),
            "runs": len(records),
            "simulated_s": sim_s, "simulate_wall_s": wall,
            "simulate_s_per_simulated_s": wall / sim_s if sim_s else math.nan,
            "cases": cases}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rel-step", type=float, default=1e-4,
                    help="relative rpm step between replicates (default 1e-4)")
    ap.add_argument("--replicates", type=int, default=3, help="runs per case (default 3)")
    ap.add_argument("--case", type=Path, action="append", default=None,
                    help="case YAML (repeatable; default: benchmarks/cases/span_replicates/)")
    ap.add_argument("--baseline", action="append", default=[], metavar="NAME=REV|DIR",
                    help="a git revision of this repository, or a source tree "
                         "(DIR/src, DIR/params.yaml)")
    ap.add_argument("--work", type=Path,
                    default=Path(tempfile.gettempdir()) / "drillfatigue-span-replicates",
                    help="run folders (runs found there are reused)")
    ap.add_argument("--out", type=Path, default=RESULT)
    ap.add_argument("--tree", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--records", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    cases = sorted(args.case or CASES.glob("*.yaml"))
    if args.tree is not None:
        # worker: this process imports drillfatigue from args.tree/src, with numba's cache
        # keyed by that tree's kernels (as the pipeline's stages do: a cached kernel is not
        # recompiled when a kernel it calls in another module changes)
        from drillfatigue.numba_cache import scope_numba_cache
        scope_numba_cache()
        recs = run_tree(args.tree, cases, args.rel_step, args.replicates, args.work)
        args.records.write_text(json.dumps(recs), encoding="utf-8")
        return
    trees = {"this": ROOT}
    revs: dict[str, str | None] = {"this": _git(ROOT, "rev-parse", "--short", "HEAD")}
    for item in args.baseline:
        name, _, where = item.partition("=")
        if not name or not where or name in trees:
            raise SystemExit(f"--baseline {item!r}: NAME=REV or NAME=DIR with a new NAME")
        if Path(where).is_dir():
            trees[name] = Path(where).resolve()
            revs[name] = None
            continue
        rev = _git(ROOT, "rev-parse", "--short", where)
        if rev is None:
            raise SystemExit(f"--baseline {item!r}: neither a folder nor a git revision")
        tree = args.work / f"tree-{name}-{rev}"
        if not (tree / "params.yaml").is_file():
            tree.mkdir(parents=True, exist_ok=True)
            archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src",
                                      "params.yaml"], capture_output=True, check=True).stdout
            subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
        trees[name] = tree
        revs[name] = rev
    out: dict[str, Any] = {"rel_step": args.rel_step, "replicates": args.replicates,
                           "cases": [c.stem for c in cases], "trees": {}}
    from drillfatigue.config import load_params
    floor = load_params(ROOT / "params.yaml").surrogate.rate_floor_per_h
    for name, tree in trees.items():
        work = args.work / f"{name}-{args.rel_step:g}"
        work.mkdir(parents=True, exist_ok=True)
        rec_path = work / "records.json"
        env = dict(os.environ, PYTHONPATH=str(tree / "src"),
                   NUMBA_CACHE_DIR=str(args.work / f"numba-{name}"))
        cmd = [sys.executable, __file__, "--tree", str(tree), "--records", str(rec_path),
               "--rel-step", repr(args.rel_step), "--replicates", str(args.replicates),
               "--work", str(work)] + [a for c in cases for a in ("--case", str(c))]
        subprocess.run(cmd, env=env, check=True)
        summary = summarise(json.loads(rec_path.read_text(encoding="utf-8")), floor)
        out["trees"][name] = {"git": revs[name], **summary}
        print(f"{name}: sigma governing {summary['sigma_governing_log10']:.3f}, pooled "
              f"{summary['sigma_log10']:.3f}, windows converged "
              f"{summary['windows_converged']}/{summary['runs']}", flush=True)
    out["machine"] = {"python": platform.python_version(), "cpus": os.cpu_count(),
                      "load_1min": os.getloadavg()[0]}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
