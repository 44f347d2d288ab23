"""The step size: what sets the stable step, and what a larger safety factor costs and gains.

Usage: ``python benchmarks/bench_step.py [--quick] [--duration S] [--factors 0.5,0.85]
[--implicit-factors 0.85,0.95] [--ensemble K] [--paper-string]`` ->
``benchmarks/results/step.json`` (docs/performance.md#the-step-size).

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
   (``tests/unit/dynamics/step/test_integrator.py``: the largest difference of a history
   interpolated to common times, relative to the largest value of that history; 1 %
   is its tolerance). The bit-rock interaction, friction and whirl make the string's
   motion chaotic over tens of seconds, so point-by-point histories of two steps part
   after a while whatever the step; the comparison is therefore made over the first
   ``--window`` s (default 1.5 s, the convergence test's length) and, for the whole
   run, on the statistics a fatigue or drilling study reads (mean and standard
   deviation of each channel and of each joint load).
3. ``--implicit-factors``: the same runs with ``solver.implicit_bit_torque`` (the bit
   law's own damping of the bit's spin taken linearly implicit), compared with the
   explicit 0.5 run in the same way; the growth scan reports the explicit limit of that
   damping (``bit_damping``).
4. ``--ensemble K``: the torsional motion of the paper string with the rig is bistable
   (a stick-slip limit cycle, or a decaying oscillation about steady rotation), and
   which one a run ends in changes with a 1 N change of the 100 kN WOB set-point; one
   run per step therefore compares regimes, not steps. Each variant (explicit 0.5, the
   same with the step halved, the largest explicit factor and every implicit factor) is
   run K more times with the WOB set-point moved by +1, -1, +2, -2, ... N
   (``--perturb-N``); each run's regime is read from its bit speed over the last 10 s
   (stick-slip: it falls below 10 % of its mean), and the statistics of each regime
   after ``--settled`` s (default 20) are averaged over the runs in it and compared
   between variants (relative to the largest value of the history + 1, as above).
"""

from __future__ import annotations

import argparse
import json
import math
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
from drillfatigue.dynamics.bit import laws as bitrock  # noqa: E402
from drillfatigue.dynamics.core import layout as L  # noqa: E402
from drillfatigue.dynamics.run.simulation import Runner, simulate  # noqa: E402
from drillfatigue.dynamics.top.growth import update_top  # noqa: E402
from drillfatigue.dynamics.step.pack import stable_step  # noqa: E402
from drillfatigue.studies.case2 import case_dict  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results" / "step.json"
CHANNELS = ("surface_torque_Nm", "wob_N", "bit_rpm", "hook_load_N")
#: the step-halving convergence test's tolerance (relative to the history's largest value)
TOLERANCE = 0.01


#: the case-2 study's boundaries (``--boundaries``): ``rig`` (its default) or
#: ``prescribed_rop`` (the paper's: the string grows at the ROP, 0.5 m/s, a split every 6 s)
BOUNDARIES = "rig"
#: the rpm ramp of the drilling case (``--rpm-ramp-s``): the study's default (1 s), or the
#: paper-scale command's 5 s
RPM_RAMP_S: float | None = None


def case(duration_s: float, safety: float, paper_string: bool, dt_s: float | None = None,
         implicit: bool = False, wob_offset_N: float = 0.0):
    """The case-2 study's drilling case (profile 1, 480 m) for ``duration_s`` s."""
    spec = {"dc_segments": 20, "dp_segments": 100} if paper_string else {}
    cfg = Case2Config(sample_s=duration_s, settle_s=0.0, safety_factor=safety,
                      string=spec, boundaries=BOUNDARIES)
    cfg = cfg.model_copy(update={"wob_set_N": cfg.wob_set_N + wob_offset_N,
                                 "rpm_ramp_s": cfg.rpm_ramp_s if RPM_RAMP_S is None else RPM_RAMP_S})
    data = case_dict(cfg, "profile_1", cfg.bit_md_start_m, None)
    data["solver"]["checkpoint_every_s"] = 0.0
    data["solver"]["implicit_bit_torque"] = implicit
    if dt_s is not None:
        data["solver"]["dt_s"] = dt_s
    return case_from_dict(data)


def bit_damping(m, wob_N: float) -> dict:
    """The bit law's damping of the bit segment's spin and the explicit step it allows.

    ``c = dTOB/dOmega`` at fixed WOB, largest just above the law's speed threshold
    (Yigit-Christoforou: WOB b0 (b1 + b2) there; in the fade-in band itself up to
    ``WOB b0 b2 Omega_th 1.5 / (band Omega_th)`` more); on the bit segment's torsion row
    of the Gershgorin bound (``omega^2 = k_t / I_a + k_t / sqrt(I_a I_a1)``) the damped
    limit ``2 / omega (sqrt(1 + zeta^2) - zeta)`` with ``zeta = c / (2 I_a omega)``,
    which for large ``zeta`` is ``2 I_a / c``."""
    cp = m.cpar
    p = cp[L.P_BP:L.P_BP + bitrock.N_PARAMS]
    mid = int(cp[L.P_BITMODEL])
    oms = np.linspace(0.0, 2.0, 20001)
    slopes = np.array([bitrock.bit_torque_slope(mid, p, wob_N, o) for o in oms])
    th = p[bitrock.I_OMEGA_TH] * (1.0 + p[bitrock.I_BAND])
    above = oms > th
    c_law = float(slopes[above].max())
    c_band = float(slopes.max())
    ia, ia1 = float(m.seg[0, L.S_IA]), float(m.seg[1, L.S_IA])
    kt = float(m.jp[0, L.J_KT])
    om = math.sqrt(kt / ia + kt / math.sqrt(ia * ia1))

    def lim(c: float) -> float:
        z = c / (2.0 * ia * om)
        return 2.0 / om * (math.sqrt(1.0 + z * z) - z)

    return {"wob_N": wob_N, "bit_segment_Ia_kg_m2": ia,
            "slope_above_threshold_Nms_per_rad": c_law, "slope_in_fade_in_band_Nms_per_rad": c_band,
            "explicit_limit_above_threshold_s": lim(c_law), "explicit_limit_in_band_s": lim(c_band),
            "two_Ia_over_c_s": 2.0 * ia / c_law}


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
            "bit_damping": bit_damping(m, Case2Config().wob_set_N),
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


#: bit speed below which a run counts as sticking, as a fraction of its mean (case 2's)
STUCK_FRACTION = 0.1


def regime_stats(res, settled_s: float) -> dict:
    """Regime of one run (from its bit speed over the last 10 s) and its statistics
    after ``settled_s``: mean and standard deviation of each channel and of each joint
    load (arrays), and the largest absolute value of each (the scale of a difference)."""
    ch = res.channels
    t = ch["time_s"]
    rpm = ch["bit_rpm"]
    last = t >= t[-1] - 10.0
    stick = bool(rpm[last].min() < STUCK_FRACTION * rpm[last].mean())
    keep = t >= settled_s
    out = {"regime": "stick_slip" if stick else "steady", "channels": {}}
    for key in CHANNELS:
        x = ch[key][keep]
        out["channels"][key] = (float(x.mean()), float(x.std()), float(np.abs(ch[key]).max()))
    lk = res.times_s >= settled_s
    la = res.loads[lk]
    out["loads"] = (la.mean(axis=0), la.std(axis=0), np.abs(res.loads).max(axis=0))
    return out


def ensemble_means(members: list[dict]) -> dict:
    """Per regime: the number of runs and the averages of their statistics."""
    out: dict[str, dict] = {}
    for reg in ("stick_slip", "steady"):
        sel = [m for m in members if m["regime"] == reg]
        if not sel:
            out[reg] = {"runs": 0}
            continue
        chs = {k: tuple(float(np.mean([m["channels"][k][i] for m in sel])) for i in range(2))
               + (float(max(m["channels"][k][2] for m in sel)),) for k in CHANNELS}
        loads = tuple(np.mean([m["loads"][i] for m in sel], axis=0) for i in range(2)) \
            + (np.max([m["loads"][2] for m in sel], axis=0),)
        out[reg] = {"runs": len(sel), "channels": chs, "loads": loads}
    return out


def compare_ensembles(a: dict, ref: dict) -> dict:
    """Differences of ensemble ``a``'s regime statistics from ``ref``'s, relative to the
    reference's largest value + 1 (per channel; for the joint loads the worst of all)."""
    out: dict[str, dict] = {}
    for reg in ("stick_slip", "steady"):
        if a[reg]["runs"] == 0 or ref[reg]["runs"] == 0:
            continue
        row: dict[str, dict] = {}
        for k in CHANNELS:
            (ma, sa, _), (mr, sr, sc) = a[reg]["channels"][k], ref[reg]["channels"][k]
            row[k] = {"mean_rel": abs(ma - mr) / (sc + 1.0), "std_rel": abs(sa - sr) / (sc + 1.0)}
        (ma, sa, _), (mr, sr, sc) = a[reg]["loads"], ref[reg]["loads"]
        row["joint_loads_worst"] = {"mean_rel": float((np.abs(ma - mr) / (sc + 1.0)).max()),
                                    "std_rel": float((np.abs(sa - sr) / (sc + 1.0)).max())}
        out[reg] = row
    return out


def summarise_ensemble(ens: dict) -> dict:
    """JSON form of :func:`ensemble_means` (joint loads as the worst joint)."""
    out = {}
    for reg, v in ens.items():
        if v["runs"] == 0:
            out[reg] = {"runs": 0}
            continue
        out[reg] = {"runs": v["runs"],
                    "channels": {k: {"mean": m, "std": s} for k, (m, s, _) in v["channels"].items()},
                    "joint_loads_std_max_N_or_Nm": float(v["loads"][1].max())}
    return out


def run_ensemble(args, variants: dict[str, tuple[float, float | None, bool]], base: dict,
                 dur: float) -> dict:
    """Each variant ``name: (safety, dt_s, implicit)`` run ``args.ensemble`` more times with
    the WOB set-point perturbed; ``base[name]``: the :func:`regime_stats` of its run at
    offset 0, reused."""
    offs = [args.perturb_N * (1 + k // 2) * (1 if k % 2 == 0 else -1) for k in range(args.ensemble)]
    members: dict[str, list[dict]] = {}
    out: dict = {"wob_offsets_N": [0.0, *offs], "settled_s": args.settled, "variants": {}}
    for name, (sf, dt_s, imp) in variants.items():
        members[name] = [base[name]] if name in base else []
        for o in offs:
            res, cpu, status = run(case(dur, sf, args.paper_string, dt_s=dt_s, implicit=imp,
                                        wob_offset_N=o))
            if res is None:
                members[name].append({"regime": "failed: " + status})
                continue
            members[name].append(regime_stats(res, args.settled))
            print(name, o, members[name][-1]["regime"], f"{cpu:.1f} s", flush=True)
        ok = [m for m in members[name] if m["regime"] in ("stick_slip", "steady")]
        out["variants"][name] = {"regimes": [m["regime"] for m in members[name]],
                                 "ensemble": summarise_ensemble(ensemble_means(ok))}
    ref = ensemble_means([m for m in members["explicit 0.5"]
                          if m["regime"] in ("stick_slip", "steady")])
    for name in members:
        if name == "explicit 0.5":
            continue
        ok = [m for m in members[name] if m["regime"] in ("stick_slip", "steady")]
        out["variants"][name]["vs_explicit_0_5"] = compare_ensembles(ensemble_means(ok), ref)
    return out


def _row(name: str, sf: float, res, cpu: float, status: str, dur: float) -> dict:
    row = {"variant": name, "safety_factor": sf, "status": status, "cpu_s": cpu}
    if res is not None:
        s = res.summary
        row.update(dt_s=s["dt_s"], n_steps=s["n_steps"],
                   segments=[s["n_segments_initial"], s["n_segments_final"]],
                   cpu_real_time_factor=dur / cpu,
                   energy_balance_error_rel=s["energy_balance_error_rel"])
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 5 s run")
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--window", type=float, default=1.5)
    ap.add_argument("--factors", default="0.5,0.7,0.85")
    ap.add_argument("--implicit-factors", default="",
                    help="safety factors run with solver.implicit_bit_torque, e.g. 0.85,0.95")
    ap.add_argument("--ensemble", type=int, default=0,
                    help="runs per variant more with the WOB set-point perturbed (0: none)")
    ap.add_argument("--perturb-N", type=float, default=1.0)
    ap.add_argument("--settled", type=float, default=20.0,
                    help="start of the regime statistics of the ensemble, s")
    ap.add_argument("--paper-string", action="store_true",
                    help="20 collar + 100 drill-pipe segments (the paper's) instead of 9 + 20")
    ap.add_argument("--boundaries", choices=("rig", "prescribed_rop"), default="rig")
    ap.add_argument("--rpm-ramp-s", type=float, default=None,
                    help="rpm ramp of the case (default: the case-2 study's; paper scale: 5)")
    ap.add_argument("--out", type=Path, default=RESULTS)
    args = ap.parse_args()
    global BOUNDARIES, RPM_RAMP_S
    BOUNDARIES = args.boundaries
    RPM_RAMP_S = args.rpm_ramp_s
    dur = 5.0 if args.quick else args.duration
    factors = [float(f) for f in args.factors.split(",")]
    implicit = [float(f) for f in args.implicit_factors.split(",") if f]
    scan = growth_scan(dur, args.paper_string)
    print(json.dumps({k: v for k, v in scan.items() if k != "scan"}, indent=1))
    simulate(case(0.05, 0.5, args.paper_string), None, progress=False)  # compile / load cache
    runs = {}
    results = {}
    variants: dict[str, tuple[float, float | None, bool]] = {}
    for f in factors:
        res, cpu, status = run(case(dur, f, args.paper_string))
        results[f"explicit {f:g}"] = res
        variants[f"explicit {f:g}"] = (f, None, False)
        runs[f"{f:g}"] = row = _row(f"explicit {f:g}", f, res, cpu, status, dur)
        print(row, flush=True)
    for f in implicit:
        res, cpu, status = run(case(dur, f, args.paper_string, implicit=True))
        results[f"implicit {f:g}"] = res
        variants[f"implicit {f:g}"] = (f, None, True)
        runs[f"implicit_{f:g}"] = row = _row(f"implicit {f:g}", f, res, cpu, status, dur)
        print(row, flush=True)
    ref = results.get("explicit 0.5")
    if ref is not None:
        dt_half = 0.5 * ref.summary["dt_s"]
        half, cpu, status = run(case(dur, 0.5, args.paper_string, dt_s=dt_half))
        results["explicit 0.5, dt halved"] = half
        variants["explicit 0.5, dt halved"] = (0.5, dt_half, False)
        row = {"variant": "explicit 0.5, dt halved", "safety_factor": "0.5, dt halved",
               "status": status, "cpu_s": cpu}
        if half is not None:
            row.update(dt_s=half.summary["dt_s"], cpu_real_time_factor=dur / cpu,
                       vs_0_5=compare(half, ref, args.window))
        runs["0.5_halved"] = row
        print(row, flush=True)
        for key, r in runs.items():
            res = results[r["variant"]]
            if res is not None and key not in ("0.5", "0.5_halved"):
                r["vs_0_5"] = compare(res, ref, args.window)
                r["speedup_vs_0_5"] = runs["0.5"]["cpu_s"] / r["cpu_s"]
                print(key, r["vs_0_5"], flush=True)
    out = {"benchmark": "step", "case": f"case2 study, profile 1, {BOUNDARIES}, "
           + ("20 + 100 segments" if args.paper_string else "9 + 20 segments"),
           "duration_s": dur, "window_s": args.window, "tolerance": TOLERANCE,
           "rpm_ramp_s": args.rpm_ramp_s,
           "growth_scan": scan, "runs": runs,
           "note": "CPU time of the process per run (build included); the machine may be shared"}
    if args.ensemble > 0 and ref is not None:
        # the variants of the ensemble: the reference, its halved step, the largest explicit
        # factor and every implicit one
        keep = ["explicit 0.5", "explicit 0.5, dt halved", f"explicit {max(factors):g}",
                *[f"implicit {f:g}" for f in implicit]]
        chosen = {k: variants[k] for k in dict.fromkeys(keep) if k in variants}
        base = {k: regime_stats(results[k], args.settled) for k in chosen
                if results.get(k) is not None and dur > args.settled}
        out["ensemble"] = run_ensemble(args, chosen, base, dur)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
