"""Sweep engine throughput: cases per hour, local process pool vs Dask LocalCluster.

A CPU-bound synthetic case (:func:`testkit.synthetic_sweep.synthetic_case`,
a numba loop calibrated to ``--case-s`` seconds) is run ``--n-cases`` times
with ``n_workers`` workers on the ``processes`` and ``local-cluster``
schedulers, and once in series as the baseline. Reported per scheduler:
wall time (including pool / cluster start), cases per hour, and overhead =
wall / ideal - 1 with ideal = n_cases x case time / n_workers, with and
without the start-up + tear-down time (measured by a sweep of trivial
cases). The Dask vs pool ratio is the goal figure (<= +10 %); on a shared
2-core machine the absolute overheads also contain other users' load
(``load_avg_1min`` is recorded).
Unless ``--no-real``, a tiny real case (16 segments, 0.5 s simulated) is timed on
the process pool too.

Usage: ``PYTHONPATH=tests python benchmarks/bench_sweep.py [--quick] [--no-real] [--n-workers 2]``
→ ``benchmarks/results/sweep.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import sys
import tempfile
import time
from pathlib import Path

from drillfatigue.sweep.runner import Case, run_sweep
from testkit.synthetic_sweep import _burn, synthetic_case, warmup

RESULT = Path(__file__).parent / "results" / "sweep.json"


def calibrate(case_s: float) -> tuple[int, float]:
    """Iterations of the synthetic kernel that take about ``case_s`` seconds in series."""
    warmup()
    n = 1_000_000
    while True:
        t0 = time.perf_counter()
        _burn(n, 0.3)
        dt = time.perf_counter() - t0
        if dt > 0.05:
            break
        n *= 4
    work = max(1, int(n * case_s / dt))
    root = Path(tempfile.mkdtemp(prefix="bench_cal_"))
    try:
        t0 = time.perf_counter()
        reps = 3
        for i in range(reps):
            synthetic_case({"i": i, "synthetic": {"work": work}}, root)
        return work, (time.perf_counter() - t0) / reps
    finally:
        shutil.rmtree(root, ignore_errors=True)


def timed_sweep(cases: list[Case], case_fn, scheduler: str, n_workers: int) -> dict[str, float]:
    root = Path(tempfile.mkdtemp(prefix=f"bench_{scheduler}_"))
    try:
        t0 = time.perf_counter()
        report = run_sweep(cases, case_fn, root, scheduler=scheduler, n_workers=n_workers,
                           max_retries=0, failure_threshold=0.0)
        wall = time.perf_counter() - t0
    finally:
        shutil.rmtree(root, ignore_errors=True)
    assert report.n_done == len(cases)
    return {"wall_s": wall, "cases_per_hour": len(cases) / wall * 3600.0}


def real_cases(n: int) -> list[Case]:
    from drillfatigue.config import CaseConfig
    from drillfatigue.sweep.design import case_id_of

    base = CaseConfig().model_dump(mode="json")
    base["operation"].update(duration_s=0.5, bit_md_m=500.0, rop_m_per_s=0.005)
    base["string"]["components"] = [
        {"type": "collar", "name": "DC", "od_m": 0.17145, "id_m": 0.0714, "length_m": 60.0,
         "n_segments": 6},
        {"type": "drill_pipe", "name": "DP", "od_m": 0.127, "id_m": 0.1086, "length_m": 440.0,
         "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
         "tool_joint_length_fraction": 0.05, "n_segments": 10}]
    base["recording"].update(joints=[2, 8], loads_rate_hz=100.0)
    out = []
    for i in range(n):
        case = json.loads(json.dumps(base))
        case["operation"]["rpm"] = 60.0 + 10.0 * i
        out.append(Case(case_id_of(case), case))
    return out


def bench_real(quick: bool, n_workers: int) -> dict:
    """Cases per hour of the real case function (tiny case) on the process pool."""
    from drillfatigue.sweep.cases import run_case, warmup_simulation

    rc = real_cases(2 if quick else 8)
    warmup_simulation(rc[0].inputs)
    with tempfile.TemporaryDirectory(prefix="bench_real_one_") as tmp:
        t0 = time.perf_counter()
        run_case(rc[0].inputs, Path(tmp))
        one = time.perf_counter() - t0
    r = timed_sweep(rc, run_case, "processes", n_workers)
    r.update(case_s=one, n_cases=len(rc),
             overhead_vs_ideal=r["wall_s"] / (len(rc) * one / n_workers) - 1.0)
    print(f"real case     {r['wall_s']:7.2f} s  {r['cases_per_hour']:9.0f} cases/h "
          f"(one case {one:.2f} s in series)")
    return {"processes": r, "case": "16 segments, 0.5 s simulated, 2 joints"}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 cases of 0.5 s (default 32 of 2 s)")
    parser.add_argument("--no-real", dest="real", action="store_false",
                        help="skip timing the real simulator case function")
    parser.add_argument("--n-workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=RESULT)
    args = parser.parse_args(argv)
    n_cases, case_s = (8, 0.5) if args.quick else (32, 2.0)
    work, t_case = calibrate(case_s)
    cases = [Case(f"c{i:04d}", {"i": i, "synthetic": {"work": work}}) for i in range(n_cases)]
    ideal = n_cases * t_case / args.n_workers
    result: dict = {
        "quick": args.quick, "n_workers": args.n_workers, "n_cases": n_cases,
        "case_s": t_case, "ideal_wall_s": ideal,
        "machine": {"cpu_count": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(),
                    "load_avg_1min": os.getloadavg()[0]},
        "synthetic": {},
    }
    trivial = [Case(f"t{i}", {"i": i, "synthetic": {"work": 1}}) for i in range(args.n_workers)]
    for scheduler in ("processes", "local-cluster"):
        # start-up + tear-down: a sweep of n_workers trivial cases
        startup = timed_sweep(trivial, synthetic_case, scheduler, args.n_workers)["wall_s"]
        r = timed_sweep(cases, synthetic_case, scheduler, args.n_workers)
        r["startup_s"] = startup
        r["overhead_vs_ideal"] = r["wall_s"] / ideal - 1.0
        r["steady_overhead_vs_ideal"] = (r["wall_s"] - startup) / ideal - 1.0
        result["synthetic"][scheduler] = r
        print(f"{scheduler:14s} {r['wall_s']:7.2f} s  {r['cases_per_hour']:9.0f} cases/h  "
              f"overhead {r['overhead_vs_ideal']:+.1%} (start-up {startup:.1f} s, "
              f"steady {r['steady_overhead_vs_ideal']:+.1%})", flush=True)
    pool, dask = result["synthetic"]["processes"], result["synthetic"]["local-cluster"]
    result["dask_over_pool"] = dask["wall_s"] / pool["wall_s"] - 1.0
    result["dask_over_pool_steady"] = ((dask["wall_s"] - dask["startup_s"])
                                       / (pool["wall_s"] - pool["startup_s"]) - 1.0)
    result["goal_dask_over_pool_le"] = 0.10
    print(f"Dask vs pool: {result['dask_over_pool']:+.1%} incl. start-up, "
          f"{result['dask_over_pool_steady']:+.1%} steady state (goal <= +10 %)")
    if args.real:
        try:
            result["real"] = bench_real(args.quick, args.n_workers)
        except Exception as exc:  # noqa: BLE001 - report, keep the synthetic figures
            result["real"] = {"error": f"{type(exc).__name__}: {exc}"}
            print(f"real case: {result['real']['error']}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_name(f".{args.out.name}.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    os.replace(tmp, args.out)
    print(f"-> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
