"""The step size: what sets the stable step, and what a larger safety factor costs and gains.

Usage: ``python benchmarks/bench_step.py [--quick] [--duration S] [--factors 0.5,0.85]
[--paper-string]`` -> ``benchmarks/results/step.json`` (docs/performance.md#the-step-size).

1. The stable step of the case-2 drilling string (the ``case2`` study's case, profile 1,
   rig boundaries: autodriller on WOB, bit law, lobed rock face; :func:`stable_step`, the
   Gershgorin bound) as the string grows: the top segment lengthens from ``LSPLIT - LNOM``
   to ``LSPLIT`` and a ``LNOM`` segment is split off it, so the bound is scanned over
   that range of top lengths (``update_top`` on copies of the parameter rows), with and
   without the wall's penalty springs.
2. The same case drilled for ``--duration`` s (default 60) at each safety factor of
   ``--factors``, plus the reference 0.5 with its step halved (0.25): CPU time of the
   run, real-time factor, whether it completed, and the difference of its histories
   from the 0.5 run measured as the step-halving convergence test does
   (``tests/unit/test_integrator_convergence.py``: the largest difference of a history
   interpolated to common times, relative to the largest value of that history; 1 %
   is its tolerance). The bit-rock interaction, friction and whirl make the string's
   motion chaotic over tens of seconds, so point-by-point histories of two steps part
   after a while whatever the step; the comparison is therefore made over the first
   ``--window`` s (default 1.5 s, the convergence test's length) and, for the whole
   run, on the statistics a fatigue or drilling study reads (mean and standard
   deviation of each channel and of each joint load).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from drillfatigue.files import atomic_write_json  # noqa: E402
from drillfatigue.numba_cache import scope_numba_cache  # noqa: E402

scope_numba_cache()

from drillfatigue.config import case_from_dict  # noqa: E402
from drillfatigue.config.studies import Case2Config  # noqa: E402
from drillfatigue.dynamics import layout as L  # noqa: E402
from drillfatigue.dynamics.api import Runner, simulate  # noqa: E402
from drillfatigue.dynamics.growth import update_top  # noqa: E402
from drillfatigue.dynamics.model import stable_step  # noqa: E402
from drillfatigue.studies.case2 import case_dict  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results" / "step.json"
CHANNELS = ("surface_torque_Nm", "wob_N", "bit_rpm", "hook_load_N")
#: the step-halving convergence test's tolerance (relative to the history's largest value)
TOLERANCE = 0.01


#: the case-2 study's boundaries (``--boundaries``): ``rig`` (its default) or
#: ``prescribed_rop`` (the paper's: the string grows at the ROP, 0.5 m/s, a split every 6 s)
BOUNDARIES = "rig"


def case(duration_s: float, safety: float, paper_string: bool, dt_s: float | None = None):
    """The case-2 study's drilling case (profile 1, 480 m) for ``duration_s`` s."""
    spec = {"dc_segments": 20, "dp_segments": 100} if paper_string else {}
    cfg = Case2Config(sample_s=duration_s, settle_s=0.0, safety_factor=safety,
                      string=spec, boundaries=BOUNDARIES)
    data = case_dict(cfg, "profile_1", cfg.bit_md_start_m, None)
    data["solver"]["checkpoint_every_s"] = 0.0
    if dt_s is not None:
        data["solver"]["dt_s"] = dt_s
    return case_from_dict(data)


def growth_scan(duration_s: float, paper_string: bool) -> dict:
    """Stable step at the build and over the top segment's length range during growth."""
    r = Runner(case(duration_s, 0.5, paper_string), None, None)
    m = r.model
    n = r.state.n_active
    bp = m.bp
    base = stable_step(m.seg[:n], m.jp[:n], bp, m.cpar, m.cp_n[:n])
    rows = []
    lo = float(bp[L.B_LSPLIT] - bp[L.B_LNOM])
    for top_m in np.linspace(lo, float(bp[L.B_LSPLIT]), 7):
        seg, jp, topp = m.seg.copy(), m.jp.copy(), m.topp.copy()
        update_top(0.5 * top_m, n, seg, jp, topp, bp)
        rows.append({"top_segment_m": float(top_m),
                     "stable_dt_s": stable_step(seg[:n], jp[:n], bp, m.cpar, m.cp_n[:n]),
                     "stable_dt_without_contact_s": stable_step(seg[:n], jp[:n], bp)})
    # the deepest point (contact.deepest_point) is one more penalty spring on a segment
    # with >= 3 points, which stable_step does not count
    deep = m.cpar.shape[0] > L.P_DEEP and m.cpar[L.P_DEEP] != 0.0 and m.cpar[L.P_CPTAB] != 0.0
    cp_deep = np.where(m.cp_n[:n] >= 3, m.cp_n[:n] + 1, m.cp_n[:n]) if deep else m.cp_n[:n]
    with_deep = stable_step(m.seg[:n], m.jp[:n], bp, m.cpar, cp_deep)
    return {"n_segments": n, "top_segment_at_build_m": 2.0 * float(m.seg[n - 1, L.S_H]),
            "points_per_segment_max": int(m.cp_n[:n].max()),
            "stable_dt_counting_the_deepest_point_s": with_deep,
            "stable_dt_at_build_s": base,
            "stable_dt_without_contact_at_build_s": stable_step(m.seg[:n], m.jp[:n], bp),
            "min_over_growth_s": min(r_["stable_dt_s"] for r_ in rows), "scan": rows}


def run(cfg) -> tuple[object, float, str]:
    t0 = time.process_time()
    try:
        res = simulate(cfg, None, progress=False)
        status = res.status
    except Exception as exc:  # a diverged run is a result here, not a failure of the script
        return None, time.process_time() - t0, f"{type(exc).__name__}: {exc}"
    return res, time.process_time() - t0, status


def _rel(a_t, a, b_t, b, t_end) -> float:
    keep = a_t <= t_end
    bi = np.interp(a_t[keep], b_t, b)
    return float(np.abs(a[keep] - bi).max() / (np.abs(b).max() + 1.0))


def compare(res, ref, window_s: float) -> dict:
    """Differences of ``res`` from ``ref`` as the convergence test measures them."""
    ta, tb = res.channels["time_s"], ref.channels["time_s"]
    t0 = max(ta[0], tb[0])
    out: dict[str, dict] = {"window": {}, "whole_run_stats": {}}
    for key in CHANNELS:
        if key not in res.channels:
            continue
        a, b = res.channels[key], ref.channels[key]
        out["window"][key] = _rel(ta, a, tb, b, t0 + window_s)
        scale = np.abs(b).max() + 1.0
        out["whole_run_stats"][key] = {
            "mean_rel": float(abs(a.mean() - b.mean()) / scale),
            "std_rel": float(abs(a.std() - b.std()) / scale)}
    la, lb = res.loads, ref.loads
    worst_w = 0.0
    worst_mean = 0.0
    worst_std = 0.0
    for j in range(la.shape[1]):
        for k in range(6):
            sc = np.abs(lb[:, :, k]).max() + 1.0
            keep = res.times_s <= res.times_s[0] + window_s
            bi = np.interp(res.times_s[keep], ref.times_s, lb[:, j, k])
            worst_w = max(worst_w, float(np.abs(la[keep, j, k] - bi).max() / sc))
            worst_mean = max(worst_mean, float(abs(la[:, j, k].mean() - lb[:, j, k].mean()) / sc))
            worst_std = max(worst_std, float(abs(la[:, j, k].std() - lb[:, j, k].std()) / sc))
    out["window"]["joint_loads_worst"] = worst_w
    out["whole_run_stats"]["joint_loads_worst"] = {"mean_rel": worst_mean, "std_rel": worst_std}
    out["window_within_tolerance"] = all(
        v < TOLERANCE for v in out["window"].values())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 5 s run")
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--window", type=float, default=1.5)
    ap.add_argument("--factors", default="0.5,0.7,0.85")
    ap.add_argument("--paper-string", action="store_true",
                    help="20 collar + 100 drill-pipe segments (the paper's) instead of 9 + 20")
    ap.add_argument("--boundaries", choices=("rig", "prescribed_rop"), default="rig")
    ap.add_argument("--out", type=Path, default=RESULTS)
    args = ap.parse_args()
    global BOUNDARIES
    BOUNDARIES = args.boundaries
    dur = 5.0 if args.quick else args.duration
    factors = [float(f) for f in args.factors.split(",")]
    scan = growth_scan(dur, args.paper_string)
    print(json.dumps({k: v for k, v in scan.items() if k != "scan"}, indent=1))
    simulate(case(0.05, 0.5, args.paper_string), None, progress=False)  # compile / load cache
    runs = {}
    results = {}
    for f in factors:
        res, cpu, status = run(case(dur, f, args.paper_string))
        results[f] = res
        row = {"safety_factor": f, "status": status, "cpu_s": cpu}
        if res is not None:
            s = res.summary
            row.update(dt_s=s["dt_s"], n_steps=s["n_steps"],
                       segments=[s["n_segments_initial"], s["n_segments_final"]],
                       cpu_real_time_factor=s["duration_s"] / cpu,
                       energy_balance_error_rel=s["energy_balance_error_rel"])
        runs[f"{f:g}"] = row
        print(row, flush=True)
    ref = results.get(0.5)
    if ref is not None:
        half, cpu, status = run(case(dur, 0.5, args.paper_string, dt_s=0.5 * ref.summary["dt_s"]))
        row = {"safety_factor": "0.5, dt halved", "status": status, "cpu_s": cpu}
        if half is not None:
            row.update(dt_s=half.summary["dt_s"], cpu_real_time_factor=dur / cpu,
                       vs_0_5=compare(half, ref, args.window))
        runs["0.5_halved"] = row
        print(row, flush=True)
        for f, res in results.items():
            if res is not None and f != 0.5:
                runs[f"{f:g}"]["vs_0_5"] = compare(res, ref, args.window)
                runs[f"{f:g}"]["speedup_vs_0_5"] = runs["0.5"]["cpu_s"] / runs[f"{f:g}"]["cpu_s"]
                print(f, runs[f"{f:g}"]["vs_0_5"], flush=True)
    out = {"benchmark": "step", "case": f"case2 study, profile 1, {BOUNDARIES}, "
           + ("20 + 100 segments" if args.paper_string else "9 + 20 segments"),
           "duration_s": dur, "window_s": args.window, "tolerance": TOLERANCE,
           "growth_scan": scan, "runs": runs,
           "note": "CPU time of the process per run (build included); the machine may be shared"}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
