"""Benchmark: where a research case's time goes, and cases per hour on the machine's cores.

Workload: the first ``--cases`` cases of the default sweep design (``params.yaml``,
``sweep`` section, as ``drillfatigue sweep design`` makes it), window rule and
fatigue criteria of ``params.yaml``.

``throughput``
    Per source tree, in a fresh process (start-up, imports, warm-up hook and the
    pool included; numba's cache filled beforehand by an untimed run of the same
    command in another folder), the wall time from nothing to the dataset rows of
    the cases with ``--workers`` worker processes, and ``cases_per_h``:

    * a tree without :mod:`drillfatigue.sweep.research` (the baseline) runs the
      pipeline's stages as ``drillfatigue sweep run`` does: ``simulate_stage``,
      ``fatigue_stage`` (load histories on disk) and ``dataset_stage``;
    * this tree runs :func:`drillfatigue.sweep.research.run_research` on the same
      cases (rows only, one file per case, assembled).

    ``cpu_s_per_case``: CPU seconds (user + system) of the command and every process it
    starts, per case; ``cases_per_h_on_idle_cores`` = workers x 3600 / that: the rate of
    a machine whose cores do nothing else (the wall time of a shared machine depends on
    its other load, and a process with more threads takes a larger share of it).

    ``rows_equal``: the two trees' tables (today's ``damage.parquet`` and the research
    ``train.parquet`` without ``split``), sorted by case, joint and location, compared
    value for value and dtype for dtype but for ``wall_time_s`` (the simulation's wall
    time, a measurement) (``max_rel_diff`` over numeric columns otherwise).
``profile``
    This tree, one case at a time in one process (numba cache warm), seconds per
    phase: process start and imports, warm-up (kernels loaded from the cache), each
    window's simulation with the span-bending record and without it (its cost is the
    difference), the simulation without writing histories (parquet writes are the
    difference), reading the histories back, the window check, each fatigue criterion
    (matake with numba's default threads and with one thread), API RP7G, the hole
    geometry columns, the row building and writing the case file.

Baselines: ``--baseline-tree DIR`` (a folder holding ``src/`` and ``params.yaml``,
e.g. a ``git worktree`` of main) or ``--baseline-rev REV`` (``git archive`` of this
repository's ``src`` and ``params.yaml`` at REV).

Run: ``python benchmarks/case_throughput.py --baseline-rev c93d910 [--cases 6]
[--workers 2] [--repeat 2]`` -> benchmarks/results/case_throughput.json. About 20 min
on 2 cores with a cold numba cache (each tree compiles its kernels once). ``cases_per_h``
counts every timed run of a tree; the trees alternate, so a drifting machine load
(``load_avg``) favours neither.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RESULT = ROOT / "benchmarks" / "results" / "case_throughput.json"


def _git(root: Path, *args: str) -> str | None:
    res = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True)
    return res.stdout.strip() or None if res.returncode == 0 else None


# --- run inside a tree's process -------------------------------------------------------
def _params(tree: Path, work: Path) -> Any:
    """The tree's params.yaml with every sweep folder under ``work``."""
    from drillfatigue.config import load_params

    p = load_params(tree / "params.yaml")
    sweep = p.sweep.model_copy(update={
        "cases_path": str(work / "design" / "cases.parquet"),
        "sweep_dir": str(work / "sweep"), "fatigue_dir": str(work / "fatigue"),
        "dataset_dir": str(work / "dataset")})
    return p.model_copy(update={"sweep": sweep})


def _design(tree: Path, n: int) -> Any:
    from drillfatigue.config import load_params
    from drillfatigue.sweep.design import base_case_from_params, design_cases

    p = load_params(tree / "params.yaml")
    return design_cases(p.sweep, base_case_from_params(p)).iloc[:n].reset_index(drop=True)


def child_throughput(tree: Path, work: Path, n: int, workers: int) -> dict[str, Any]:
    """Rows of the first ``n`` designed cases from nothing, the tree's way (see module doc)."""
    import pandas as pd

    params = _params(tree, work)
    cases = _design(tree, n)
    try:
        from drillfatigue.sweep.research import run_research
    except ImportError:
        run_research = None
    if run_research is None:
        from drillfatigue.sweep.design import write_cases
        from drillfatigue.sweep.stages import dataset_stage, fatigue_stage, simulate_stage

        write_cases(cases, params.sweep.cases_path)
        simulate_stage(params, n_workers=workers)
        fatigue_stage(params, n_workers=workers)
        dataset_stage(params)
        rows = pd.read_parquet(work / "dataset" / "damage.parquet")
        extra = {"histories_MB": sum(f.stat().st_size for f in (work / "sweep").rglob("*")
                                     if f.is_file()) / 1e6}
    else:
        res = run_research(params, work / "research", n_cases=n, heldout_cases=0,
                           n_workers=workers, progress=False,
                           designs={"train": cases, "heldout": cases.iloc[:0]})
        rows = pd.read_parquet(work / "research" / "dataset" / "train.parquet").drop(
            columns="split")
        files = list((work / "research" / "cases" / "train").glob("*.parquet"))
        extra = {"case_file_bytes": [f.stat().st_size for f in sorted(files)],
                 "n_failed": res["n_failed"]}
    rows.to_parquet(work / "rows.parquet", index=False)
    return {"n_rows": len(rows), **extra}


def child_profile(tree: Path, work: Path, n: int) -> dict[str, Any]:
    """Seconds per phase for each case (this tree, one process, warm numba cache)."""
    t0 = time.perf_counter()
    import numba
    import pandas as pd

    from drillfatigue.config import case_from_dict
    from drillfatigue.dynamics.run.simulation import simulate
    from drillfatigue.fatigue.run import evaluate_run
    from drillfatigue.sweep.cases import api_rp7g_rows, position_columns, run_case
    from drillfatigue.sweep.dataset import build_dataset
    from drillfatigue.sweep.design import apply_overrides
    from drillfatigue.sweep.research import _case_inputs
    from drillfatigue.sweep.research_case import _warmup, write_case_file
    from drillfatigue.sweep.window import governing_rate_change, run_case_converged
    imports = time.perf_counter() - t0
    params = _params(tree, work)
    cases = _design(tree, n)
    variables = [v for v in params.sweep.variables if v in cases.columns]
    default_threads = numba.get_num_threads()
    out: dict[str, Any] = {"imports_s": imports, "numba_default_threads": default_threads,
                           "cases": []}
    rows0 = cases.to_dict("records")
    t = time.perf_counter()
    _warmup({"row": rows0[0], "inputs": _case_inputs(params, rows0[0], variables)})
    out["warmup_s"] = time.perf_counter() - t
    for row in rows0:
        cid = row["case_id"]
        inputs = _case_inputs(params, row, variables)
        case = inputs["case"]
        d = work / "profile" / cid
        ph: dict[str, Any] = {"case_id": cid}
        t = time.perf_counter()
        run_case_converged({"case": case, "window": inputs["window"]}, d / "sweep" / cid)
        ph["simulate_with_window_rule_s"] = time.perf_counter() - t
        win = json.loads((d / "sweep" / cid / "window.json").read_text(encoding="utf-8"))
        ph["windows_s"] = [x["window_s"] for x in win["tries"]]
        for w in ph["windows_s"]:
            c = apply_overrides(case, {"operation.duration_s": w})
            t = time.perf_counter()
            run_case(c, d / f"w{w:.0f}")
            ph[f"simulate_{w:.0f}s_s"] = time.perf_counter() - t
            t = time.perf_counter()
            simulate(case_from_dict(c), None, progress=False)
            ph[f"simulate_{w:.0f}s_in_memory_s"] = time.perf_counter() - t
            c = apply_overrides(c, {"contact.span_bending": False})
            t = time.perf_counter()
            simulate(case_from_dict(c), None, progress=False)
            ph[f"simulate_{w:.0f}s_no_span_record_s"] = time.perf_counter() - t
            t = time.perf_counter()
            governing_rate_change(d / f"w{w:.0f}", params.fatigue)
            ph[f"window_check_{w:.0f}s_s"] = time.perf_counter() - t
        run_dir = d / "sweep" / cid
        ph["histories_MB"] = sum(f.stat().st_size for f in run_dir.rglob("*")) / 1e6
        t = time.perf_counter()
        for name in ("loads.parquet", "channels.parquet"):
            if (run_dir / name).is_file():
                pd.read_parquet(run_dir / name)
        ph["read_histories_s"] = time.perf_counter() - t
        for crit in params.sweep.fatigue_criteria:
            for threads in sorted({default_threads, 1}, reverse=True):
                numba.set_num_threads(threads)
                t = time.perf_counter()
                evaluate_run(run_dir, params.fatigue, None, criterion=crit)
                ph[f"fatigue_{crit}_{threads}thread_s"] = time.perf_counter() - t
        numba.set_num_threads(1)
        t = time.perf_counter()
        api_rp7g_rows(run_dir, case, params.fatigue)
        ph["fatigue_api_rp7g_s"] = time.perf_counter() - t
        from drillfatigue.sweep.cases import fatigue_case
        fat = d / "fatigue" / cid
        fatigue_case({"run_dir": str(run_dir), "fatigue": inputs["fatigue"],
                      "criteria": inputs["criteria"], "api_rp7g": inputs["api_rp7g"],
                      "case": case}, fat)
        dmg = pd.read_parquet(fat / "damage.parquet")
        t = time.perf_counter()
        position_columns(case, dmg["md_m"], dmg["s_from_bit_m"])
        ph["position_columns_s"] = time.perf_counter() - t
        t = time.perf_counter()
        rows = build_dataset(pd.DataFrame([row]), d / "sweep", d / "fatigue", variables)
        ph["row_building_s"] = time.perf_counter() - t
        t = time.perf_counter()
        write_case_file(rows, d / "rows.parquet", {"case_id": cid})
        ph["write_case_file_s"] = time.perf_counter() - t
        ph["case_file_bytes"] = (d / "rows.parquet").stat().st_size
        out["cases"].append(ph)
        print(json.dumps(ph), flush=True)
    return out


# --- the parent ---------------------------------------------------------------------------
def _run_child(tree: Path, mode: str, work: Path, n: int, workers: int) -> tuple[dict, float]:
    env = {**os.environ, "PYTHONPATH": str(tree / "src"),
           "NUMBA_CACHE_DIR": str(work.parent / f"numba-{tree.name}")}
    work.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, __file__, "--child", mode, "--tree", str(tree),
                                 "--work", str(work), "--cases", str(n), "--workers",
                                 str(workers)], env=env, cwd=tree, stdout=out, stderr=err,
                                text=True, start_new_session=True)
        cpu = _session_cpu_s(proc)
        wall = time.perf_counter() - t0
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read(), err.read()
    if proc.returncode != 0:
        raise SystemExit(f"{tree} {mode} failed:\n{stderr[-3000:]}")
    return {**json.loads(stdout.strip().splitlines()[-1]), "cpu_s": cpu}, wall


def _session_cpu_s(proc: subprocess.Popen, every_s: float = 0.2) -> float:
    """CPU seconds (user + system) of every process of ``proc``'s session until it ends:
    the command, its pools' workers and their servers. Sampled from /proc every
    ``every_s``; a process's last ``every_s`` before it exits is not counted."""
    tick = os.sysconf("SC_CLK_TCK")
    seen: dict[int, float] = {}
    while True:
        for d in Path("/proc").iterdir():
            if not d.name.isdigit():
                continue
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            fields = stat[stat.rindex(")") + 2:].split()
            if int(fields[3]) != proc.pid:  # session id
                continue
            seen[int(d.name)] = (int(fields[11]) + int(fields[12])) / tick
        if proc.poll() is not None:
            return sum(seen.values())
        time.sleep(every_s)


def compare_rows(a: Path, b: Path) -> dict[str, Any]:
    import numpy as np
    import pandas as pd

    # wall_time_s (the simulation's wall time) is a measurement, different in every run
    x = pd.read_parquet(a).drop(columns="wall_time_s", errors="ignore")
    y = pd.read_parquet(b).drop(columns="wall_time_s", errors="ignore")
    keys = ["case_id", "joint", "location"]
    x = x.sort_values(keys, kind="mergesort").reset_index(drop=True)
    y = y.sort_values(keys, kind="mergesort").reset_index(drop=True)
    out: dict[str, Any] = {"columns_equal": list(x.columns) == list(y.columns),
                           "only_baseline": sorted(set(x.columns) - set(y.columns)),
                           "only_this": sorted(set(y.columns) - set(x.columns))}
    try:
        pd.testing.assert_frame_equal(x, y[x.columns], check_exact=True)
        out["rows_equal"] = True
    except (AssertionError, KeyError) as exc:
        out["rows_equal"] = False
        out["difference"] = str(exc)[:500]
    common = [c for c in x.columns if c in y.columns and pd.api.types.is_float_dtype(x[c])]
    if len(x) == len(y) and common:
        xv, yv = x[common].to_numpy(float), y[common].to_numpy(float)
        with np.errstate(invalid="ignore", divide="ignore"):
            rel = np.abs(xv - yv) / np.maximum(np.abs(xv), np.abs(yv))
        out["max_rel_diff"] = float(np.nanmax(np.where(xv == yv, 0.0, rel)))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-tree", type=Path, default=None)
    ap.add_argument("--baseline-rev", default=None)
    ap.add_argument("--cases", type=int, default=6)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=2, help="timed runs per tree (default 2)")
    ap.add_argument("--profile", action=argparse.BooleanOptionalAction, default=True,
                    help="profile this tree's phases (--no-profile keeps the last profile)")
    ap.add_argument("--work", type=Path, default=None, help="scratch folder (default: a temp one)")
    ap.add_argument("--out", type=Path, default=RESULT)
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--tree", type=Path, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        fn = child_throughput if args.child != "profile" else None
        res = (child_profile(args.tree, args.work, args.cases) if fn is None
               else fn(args.tree, args.work, args.cases, args.workers))
        print(json.dumps(res))
        return
    work = args.work or Path(tempfile.mkdtemp(prefix="case-throughput-"))
    trees: dict[str, Path] = {"this": ROOT}
    revs = {"this": _git(ROOT, "rev-parse", "--short", "HEAD")}
    if args.baseline_tree is not None:
        trees["baseline"] = args.baseline_tree.resolve()
        revs["baseline"] = _git(args.baseline_tree, "rev-parse", "--short", "HEAD")
    elif args.baseline_rev is not None:
        rev = _git(ROOT, "rev-parse", "--short", args.baseline_rev)
        if rev is None:
            raise SystemExit(f"--baseline-rev {args.baseline_rev}: not a git revision")
        tree = work / f"tree-baseline-{rev}"
        if not tree.is_dir():
            tree.mkdir(parents=True)
            arch = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src", "params.yaml"],
                                  capture_output=True, check=True)
            subprocess.run(["tar", "-x", "-C", str(tree)], input=arch.stdout, check=True)
        trees["baseline"], revs["baseline"] = tree, rev
    result: dict[str, Any] = {"cases": args.cases, "workers": args.workers,
                              "repeat": args.repeat, "trees": {}}
    for name, tree in trees.items():
        print(f"{name}: warm-up run (fills numba's cache, not timed)", flush=True)
        _run_child(tree, "throughput", work / f"{name}-warm", args.cases, args.workers)
    walls: dict[str, list[float]] = {name: [] for name in trees}
    cpus: dict[str, list[float]] = {name: [] for name in trees}
    for r in range(args.repeat):
        # the trees take turns, the first one changing every round: a machine whose
        # load drifts favours neither
        names = list(trees) if r % 2 == 0 else list(reversed(trees))
        for name in names:
            res, wall = _run_child(trees[name], "throughput", work / f"{name}-timed-{r}",
                                   args.cases, args.workers)
            walls[name].append(wall)
            cpus[name].append(res.pop("cpu_s"))
            result["trees"][name] = {"git": revs[name], **res}
            print(f"{name} round {r}: {wall:.1f} s wall, {cpus[name][-1]:.1f} CPU s, "
                  f"load {os.getloadavg()[0]:.1f}", flush=True)
    for name in trees:
        n_runs = len(walls[name])
        cpu_case = sum(cpus[name]) / (args.cases * n_runs)
        result["trees"][name].update(
            wall_s=walls[name], cpu_s=cpus[name],
            cases_per_h=args.cases * n_runs / sum(walls[name]) * 3600.0,
            cpu_s_per_case=cpu_case,
            cases_per_h_on_idle_cores=args.workers * 3600.0 / cpu_case)
    if "baseline" in trees:
        b, t = result["trees"]["baseline"], result["trees"]["this"]
        result["ratio_cases_per_h"] = t["cases_per_h"] / b["cases_per_h"]
        result["ratio_per_round"] = [wb / wt for wb, wt in zip(walls["baseline"], walls["this"],
                                                               strict=True)]
        result["ratio_cpu_s_per_case"] = b["cpu_s_per_case"] / t["cpu_s_per_case"]
        result["rows"] = compare_rows(work / "baseline-timed-0" / "rows.parquet",
                                      work / "this-timed-0" / "rows.parquet")
    if args.profile:
        print("this: profile", flush=True)
        prof, _ = _run_child(ROOT, "profile", work / "this-profile", args.cases, 1)
        result["profile"] = {"git": revs["this"], **prof}
    elif args.out.is_file():  # keep the last profile, with the revision it was taken at
        last = json.loads(args.out.read_text(encoding="utf-8"))
        if "profile" in last:
            result["profile"] = {"git": last.get("profile", {}).get("git")
                                 or last["trees"]["this"].get("git"), **last["profile"]}
    result["machine"] = {"python": platform.python_version(), "cpus": os.cpu_count(),
                         "platform": platform.platform(), "load_avg_at_end": os.getloadavg()}
    args.out.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(json.dumps({k: v for k, v in result.items() if k != "profile"}, indent=2))
    if args.work is None:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
