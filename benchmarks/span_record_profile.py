"""Benchmark: what the span-bending record costs a research case's simulation, and where.

Workload: the first ``--cases`` cases of the default sweep design (``params.yaml``,
``sweep`` section, as ``benchmarks/case_throughput.py`` builds them), each simulated in
memory (``simulate(case_from_dict(c), None, progress=False)``) over ``--duration``
simulated seconds (the window rule's first window, 18 s, by default).

Every time is the CPU time of the process (``time.process_time``: the simulation runs on
one thread; on a machine shared with other work its wall time varied by 2x between
repeats, its CPU time by a few %).

``profile`` (this tree, one process, numba cache warm)
    Per case: the simulation with ``contact.span_bending`` and without it (the record's
    cost is the difference), the number of loads samples, and, on states captured
    every ``--stride`` samples of a run driven sample by sample
    (:func:`drillfatigue.dynamics.step.integrator.advance` one loads interval at a time),
    the seconds of one :func:`drillfatigue.dynamics.span.record.span_sample` call and,
    where the tree has them, of its phases (``span_phases``).
``compare`` (this tree against ``--baseline-rev`` or ``--baseline-tree``)
    Each tree in its own process, the trees alternating ``--repeat`` times: seconds of
    the simulations with the span record (and without it), and every output array of
    the runs with it (loads, span bending, channels, kinematics, final state) compared
    with ``np.array_equal`` (NaN positions included: ``equal_nan``) between the trees.

    Each run also times :func:`span_sample` on the states captured every ``--stride``
    samples (as ``profile``; the trees' runs are the same, so are their states):
    ``ratio_span_sample_min`` is the span record alone. Ratios are baseline / this of
    the best of the repeats; ``span_record_s`` = best with less best without.

Run: ``python benchmarks/span_record_profile.py compare --baseline-rev ec28afb [--cases 3]
[--duration 18] [--repeat 3] [--stride 20]`` -> ``benchmarks/results/span_record_profile.json``
(its ``compare`` section; ``profile`` writes its own section). Each tree compiles its
kernels once (about 2 min per tree on a cold numba cache); an untimed short run of each
tree loads them before the timed runs. About 10 min on 2 busy cores.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RESULT = ROOT / "benchmarks" / "results" / "span_record_profile.json"


# --- run inside a tree's process -------------------------------------------------------
def _cases(tree: Path, n: int, duration_s: float) -> list[tuple[str, dict]]:
    """(case_id, case dict) of the first ``n`` designed cases, over ``duration_s``."""
    from drillfatigue.config import load_params
    from drillfatigue.sweep.design import apply_overrides, base_case_from_params, design_cases

    p = load_params(tree / "params.yaml")
    rows = design_cases(p.sweep, base_case_from_params(p)).iloc[:n].to_dict("records")
    return [(r["case_id"], apply_overrides(json.loads(r["case_json"]),
                                           {"operation.duration_s": duration_s}))
            for r in rows]


def _outputs(res: Any) -> dict[str, Any]:
    """Every array a simulation returns, by name."""
    import numpy as np

    out = {"times_s": res.times_s, "loads": res.loads, "span_bending": res.span_bending,
           "joints": res.joints}
    for k, v in res.channels.items():
        out[f"channels.{k}"] = np.asarray(v)
    kin = res.kinematics
    if isinstance(kin, dict):
        for k, v in kin.items():
            out[f"kinematics.{k}"] = np.asarray(v)
    elif kin is not None:
        out["kinematics"] = np.asarray(kin)
    for k, v in res.state.arrays().items():
        out[f"state.{k}"] = v
    return {k: v for k, v in out.items() if v is not None}


def _simulate(case: dict, span: bool) -> tuple[float, Any]:
    from drillfatigue.config import case_from_dict
    from drillfatigue.dynamics.run.simulation import simulate
    from drillfatigue.sweep.design import apply_overrides

    c = apply_overrides(case, {"contact.span_bending": span})
    cfg = case_from_dict(c)
    t = time.process_time()
    res = simulate(cfg, None, progress=False)
    return time.process_time() - t, res


def _capture(case: dict, stride: int) -> tuple[list, Any, int]:
    """States (n, s, p, wk) every ``stride`` loads samples of the case's run with the span
    record, driven one loads interval at a time; the recorded joints; samples taken."""
    import numpy as np

    from drillfatigue.config import case_from_dict
    from drillfatigue.dynamics.core import layout as L
    from drillfatigue.dynamics.run.simulation import Runner
    from drillfatigue.dynamics.core.bundles import new_records
    from drillfatigue.dynamics.step.integrator import advance

    from drillfatigue.sweep.design import apply_overrides
    cfg = case_from_dict(apply_overrides(case, {"contact.span_bending": True}))
    r = Runner(cfg, None, None)
    m, s = r.model, r.state
    every = tuple(r.every)
    rec = new_records(r.sel, every, tuple(e + 2 for e in every), m.n, m.n_ch,
                      span=m.cpar[L.P_SPAN] != 0.0)
    states = []
    k = 0
    while int(s.sc[L.C_STEP]) < r.n_steps_total:
        rec.counts[:] = 0
        steps = min(every[0], r.n_steps_total - int(s.sc[L.C_STEP]))
        advance(steps, s, m.params, m.work, rec)
        if int(s.sc[L.C_STEP]) < r.start_step:
            continue  # not recorded
        if k % stride == 0:
            p = m.params
            pc = type(p)(*(a.copy() if isinstance(a, np.ndarray) else a for a in p))
            wk = m.work
            wc = type(wk)(*(a.copy() if isinstance(a, np.ndarray) else a for a in wk))
            states.append((int(s.sc[L.C_NACT]), s.copy(), pc, wc))
        k += 1
    return states, r.sel, k


def _time_span_sample(states: list, sel: Any, repeat: int) -> dict[str, Any]:
    """Seconds per :func:`span_sample` call on the captured states (best of ``repeat``)."""
    import numpy as np

    from drillfatigue.dynamics.span.record import span_sample

    out = np.zeros((sel.size, 2))
    best = np.inf
    for _ in range(repeat):
        t = time.process_time()
        for n, s, p, wk in states:
            span_sample(n, s, p, wk, sel, out)
        best = min(best, time.process_time() - t)
    res: dict[str, Any] = {"span_sample_s_per_call": best / len(states)}
    from drillfatigue.dynamics.span import record as span_record
    if hasattr(span_record, "_new_scratch"):  # a tree with span_sample split in phases
        res["span_phases_s_per_call"] = _time_phases(states, sel, repeat)
    return res


def _phase_driver() -> Any:
    """:func:`span_sample`'s body (this tree's) with a stop after each phase, compiled here."""
    import numpy as np
    from numba import njit

    from drillfatigue.dynamics.span import record as R

    @njit
    def upto(n, s, p, wk, sel, out, stop):  # pragma: no cover - numba
        g, nd, sw, pt = R._new_scratch(n)
        R._segment_loads(n, s, p, wk, g)
        X = np.zeros(3)
        info = np.zeros(R.OUT_SIZE)
        R._hole_nodes(n, s, p, g, nd, X, info)
        R._find_supports(n, s, p, g, nd, sw, pt, X, info)
        sup = R._merge_supports(sw, g.top_s[n])
        if stop == 1 or sup[0].shape[0] < 2:
            return 0
        nr = sel.size
        read_s = np.zeros(nr)
        for a in range(nr):
            read_s[a] = g.top_s[min(sel[a], n - 1) + 1]
        rd = np.zeros((nr, 3))
        rok = np.zeros(nr, dtype=np.int64)
        st, n_cut = R._beam_sample(n, s, p, g, sw, sup, read_s, rd, rok)
        if stop == 2 or st != 0:
            return 0
        ms_chain = np.zeros((n - 1, 3))
        st = R._chain_moments(n, p, g, nd, sw, ms_chain)
        if stop == 3 or st != 0:
            return 0
        R._correction(n, s, sel, rd, rok, ms_chain, out)
        return n_cut

    return upto


def _time_phases(states: list, sel: Any, repeat: int) -> dict[str, float]:
    """Seconds per call of each phase of :func:`span_sample` (this tree): supports (loads,
    hole nodes, contact search, merge), beam (the releases and splits' solves and the
    reads), chain (the rigid chain's static moments), output (joint frames); each the
    best of ``repeat`` runs up to it less the best up to the phase before."""
    import numpy as np

    upto = _phase_driver()
    out = np.zeros((sel.size, 2))
    best = {}
    for stop in (1, 2, 3, 4):
        n, s, p, wk = states[0]
        upto(n, s, p, wk, sel, out, stop)  # compiled
    for _ in range(repeat):
        for stop in (1, 2, 3, 4):
            t = time.process_time()
            for n, s, p, wk in states:
                upto(n, s, p, wk, sel, out, stop)
            best[stop] = min(best.get(stop, np.inf), (time.process_time() - t) / len(states))
    names = ("supports", "beam", "chain", "output")
    return {names[k - 1]: best[k] - best.get(k - 1, 0.0) for k in (1, 2, 3, 4)}


def child(args: argparse.Namespace) -> dict[str, Any]:
    import numpy as np

    import drillfatigue
    drillfatigue.scope_numba_cache()
    tree = Path(args.tree)
    cases = _cases(tree, args.cases, args.duration)
    out: dict[str, Any] = {"cases": []}
    t = time.perf_counter()
    # kernels loaded from the cache (or compiled): a short run (recording starts at 3 s)
    from drillfatigue.sweep.design import apply_overrides
    _simulate(apply_overrides(cases[0][1], {"operation.duration_s": 4.0}), True)
    out["warmup_s"] = time.perf_counter() - t
    for cid, case in cases:
        ph: dict[str, Any] = {"case_id": cid}
        ph["simulate_span_s"], res = _simulate(case, True)
        ph["n_loads_samples"] = int(res.times_s.shape[0])
        ph["summary_span"] = {k: v for k, v in res.summary.items() if k.startswith("span_")}
        if args.dump:
            np.savez(Path(args.dump) / f"{cid}.npz", **_outputs(res))
        if not args.no_nospan:
            ph["simulate_no_span_s"], _ = _simulate(case, False)
        if args.stride:
            states, sel, k = _capture(case, args.stride)
            ph["captured_states"] = len(states)
            ph.update(_time_span_sample(states, sel, args.sample_repeat))
            ph["span_record_estimate_s"] = ph["span_sample_s_per_call"] * k
        out["cases"].append(ph)
        print(json.dumps(ph), file=sys.stderr, flush=True)
    return out


# --- the parent ---------------------------------------------------------------------------
def _baseline(args: argparse.Namespace, tmp: Path) -> Path:
    if args.baseline_tree:
        return Path(args.baseline_tree)
    base = tmp / "baseline"
    base.mkdir()
    arch = subprocess.run(["git", "-C", str(ROOT), "archive", args.baseline_rev, "src",
                           "params.yaml"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(base)], input=arch, check=True)
    return base


def _run_child(tree: Path, extra: list[str]) -> dict[str, Any]:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"))
    with tempfile.NamedTemporaryFile("r", suffix=".json") as f:
        subprocess.run([sys.executable, __file__, "child", "--tree", str(tree),
                        "--json-out", f.name, *extra], env=env, check=True)
        return json.loads(Path(f.name).read_text(encoding="utf-8"))


def _compare_dumps(a: Path, b: Path) -> dict[str, Any]:
    import numpy as np

    res: dict[str, Any] = {}
    for fa in sorted(a.glob("*.npz")):
        da, db = np.load(fa), np.load(b / fa.name)
        diff = sorted(k for k in set(da.files) | set(db.files)
                      if k not in da.files or k not in db.files
                      or not np.array_equal(da[k], db[k],
                                            equal_nan=da[k].dtype.kind == "f"))
        res[fa.stem] = {"arrays": len(da.files), "differ": diff,
                        "span_bending_finite": int(np.isfinite(da["span_bending"]).sum())
                        if "span_bending" in da.files else 0}
    return res


def _write(section: str, data: dict[str, Any]) -> None:
    old = json.loads(RESULT.read_text(encoding="utf-8")) if RESULT.is_file() else {}
    old[section] = data
    RESULT.write_text(json.dumps(old, indent=1) + "\n", encoding="utf-8")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=("profile", "compare", "child"))
    ap.add_argument("--cases", type=int, default=3)
    ap.add_argument("--duration", type=float, default=18.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--stride", type=int, default=0, help="profile: capture every k samples")
    ap.add_argument("--sample-repeat", type=int, default=3)
    ap.add_argument("--baseline-rev", default="ec28afb")
    ap.add_argument("--baseline-tree")
    ap.add_argument("--no-nospan", action="store_true")
    ap.add_argument("--tree", default=str(ROOT))
    ap.add_argument("--dump")
    ap.add_argument("--json-out")
    args = ap.parse_args()
    if args.mode == "child":
        res = child(args)
        Path(args.json_out).write_text(json.dumps(res), encoding="utf-8")
        return
    common = ["--cases", str(args.cases), "--duration", str(args.duration)]
    meta = {"machine": platform.node(), "cpus": os.cpu_count(), "cases": args.cases,
            "duration_s": args.duration,
            "git": subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                                  capture_output=True, text=True).stdout.strip()}
    if args.mode == "profile":
        res = _run_child(ROOT, [*common, "--stride", str(args.stride or 10),
                                "--sample-repeat", str(args.sample_repeat)])
        _write("profile", {**meta, **res})
        return
    with tempfile.TemporaryDirectory() as tmpd:
        tmp = Path(tmpd)
        trees = {"baseline": _baseline(args, tmp), "this": ROOT}
        dumps = {k: tmp / f"dump_{k}" for k in trees}
        for d in dumps.values():
            d.mkdir()
        runs: dict[str, list] = {k: [] for k in trees}
        for r in range(args.repeat):
            for name in (("baseline", "this") if r % 2 == 0 else ("this", "baseline")):
                extra = [*common, "--stride", str(args.stride or 20)]
                if r == 0:
                    extra += ["--dump", str(dumps[name])]
                runs[name].append(_run_child(trees[name], extra))
        equal = _compare_dumps(dumps["baseline"], dumps["this"])
    per_case: dict[str, Any] = {}
    for name, rr in runs.items():
        for run in rr:
            for c in run["cases"]:
                d = per_case.setdefault(c["case_id"], {}).setdefault(name, {})
                for k in ("simulate_span_s", "simulate_no_span_s", "span_sample_s_per_call"):
                    if k in c:
                        d.setdefault(k, []).append(c[k])
                if "span_phases_s_per_call" in c:
                    d.setdefault("span_phases_s_per_call", []).append(c["span_phases_s_per_call"])
    for d in per_case.values():
        b, t = d["baseline"], d["this"]
        d["ratio_simulate_span_min"] = min(b["simulate_span_s"]) / min(t["simulate_span_s"])
        d["ratio_span_sample_min"] = (min(b["span_sample_s_per_call"])
                                      / min(t["span_sample_s_per_call"]))
        if "simulate_no_span_s" in b and "simulate_no_span_s" in t:
            rec_b = min(b["simulate_span_s"]) - min(b["simulate_no_span_s"])
            rec_t = min(t["simulate_span_s"]) - min(t["simulate_no_span_s"])
            d["span_record_s"] = {"baseline": rec_b, "this": rec_t}
    tot_b = sum(min(d["baseline"]["simulate_span_s"]) for d in per_case.values())
    tot_t = sum(min(d["this"]["simulate_span_s"]) for d in per_case.values())
    _write("compare", {**meta, "baseline": args.baseline_rev if not args.baseline_tree
                       else args.baseline_tree, "repeat": args.repeat,
                       "bit_identical": all(not v["differ"] for v in equal.values()),
                       "outputs": equal, "per_case": per_case,
                       "ratio_total_simulate_span": tot_b / tot_t,
                       "ratio_total_span_record": sum(
                           d["span_record_s"]["baseline"] for d in per_case.values())
                       / sum(d["span_record_s"]["this"] for d in per_case.values()),
                       "load_avg": os.getloadavg()})


if __name__ == "__main__":
    main()
