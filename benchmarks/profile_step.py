"""Where the time of one simulator step goes, per submodel (room).

Usage: ``python benchmarks/profile_step.py [--quick]`` -> ``benchmarks/results/profile_step.json``
and a markdown table on stdout (docs/performance.md).

The deviated drilling case of ``bench_simulator.py`` (``data/cases/case2_profile.yaml``:
120 segments on profile_1, wall contact, tanh-exponential friction, ROP 0.5 m/s) is
built and run for a short while so the string lies on the wall, then the state is
frozen and the kernels of each room run alone on it in a loop (each wrapper below is a
plain numba loop around the room's kernel, as :func:`integrator.step` calls it, and like
it compiled without numba's reference counting; the recorder's loops keep it, as
:func:`integrator.advance` does):

* ``rotations + body``: quaternion -> rotation matrices, world angular velocities,
  gravity and mud damping (:mod:`forces`);
* ``joints``: the joint spring-dampers (:mod:`joints`);
* ``boundaries``: top drive / hoisting and the bit guide (:mod:`boundaries`);
* ``contact + friction``: the wall loop (:mod:`contact`, :mod:`friction`, whirl and
  contact statistics);
* ``integrator``: two half kicks, the drift with the exact free rotor and the speed
  check (:mod:`rigid`);
* ``growth``: the top segment's length change (:func:`growth.grow_top`);
* ``recorder``: the rows of the record buffers at the run's rates (per step, amortised);
* ``span record``: the span-bending correction of the recorded joints (per step,
  amortised over the loads interval; only with ``contact.span_bending``).

Each part is timed in CPU time of this thread (``time.thread_time``: a shared machine
takes the core away, but the time the thread runs is what the kernel costs) as the best
of ``--repeat`` loops, and compared with the whole step (:func:`integrator.advance` on a
copy of the state). Two option sets: the case as written (contact points at the segment
ends) and ``contact.points: string`` with ``contact.span_bending: true``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from drillfatigue.files import atomic_write_json  # noqa: E402
from drillfatigue.numba_cache import scope_numba_cache  # noqa: E402

scope_numba_cache()

from drillfatigue.dynamics.core import layout as L  # noqa: E402
from drillfatigue.dynamics.run.simulation import Runner  # noqa: E402
from drillfatigue.dynamics.top.boundaries import bit_guide, top_boundary  # noqa: E402
from drillfatigue.dynamics.core.bundles import new_records  # noqa: E402
from drillfatigue.dynamics.contact.wall import wall_contact  # noqa: E402
from drillfatigue.dynamics.step.forces import body_forces, rotations  # noqa: E402
from drillfatigue.dynamics.top.growth import grow_top, growth_rate  # noqa: E402
from drillfatigue.dynamics.step.integrator import (  # noqa: E402
    advance, drift, half_kicks, half_kicks_checked, record,
)
from drillfatigue.dynamics.core.joints import joint_forces  # noqa: E402
from drillfatigue.dynamics.step.pack import stable_step  # noqa: E402
from drillfatigue.dynamics.span.record import span_sample  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_simulator import OPTION_SETS, deviated_case, reference_us_per_segment_step  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results" / "profile_step.json"


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_body(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    for _ in range(k):
        rotations(n, s.q, s.w, wk.R, wk.wW)
        body_forces(n, s, p, wk)


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_joints(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    for _ in range(k):
        joint_forces(n, growth_rate(p.bp, s.sc), s, p, wk)


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_boundaries(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    t = s.sc[L.C_STEP] * p.dt
    for _ in range(k):
        top_boundary(t, n, s, p, wk)
        bit_guide(s, p, wk)


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_contact(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    t = s.sc[L.C_STEP] * p.dt
    for _ in range(k):
        wall_contact(t, n, s, p, wk)


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_integrator(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    dt = p.dt
    hdt = 0.5 * dt
    latm = p.cpar.shape[0] > L.P_LATMASS and p.cpar[L.P_LATMASS] != 0.0
    worst = 0.0
    for _ in range(k):
        half_kicks(n, s, p, wk, hdt, latm)
        drift(n, s, p, wk, dt, latm)
        worst = max(worst, half_kicks_checked(n, s, p, wk, -hdt, latm)[0])
    return worst


@njit(cache=True, _nrt=False)  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def loop_growth(k, s, p, wk):
    n = int(s.sc[L.C_NACT])
    for j in range(k):
        n = grow_top(n, (s.sc[L.C_STEP] + j) * p.dt, s, p, wk)


@njit(cache=True)
def loop_record(k, s, p, wk, rec):
    n = int(s.sc[L.C_NACT])
    for j in range(k):
        record(j + 1, (j + 1) * p.dt, n, s, p, wk, rec)


@njit(cache=True)
def loop_span(k, s, p, wk, sel, out):
    n = int(s.sc[L.C_NACT])
    for _ in range(k):
        span_sample(n, s, p, wk, sel, out)


def _best(fn, reps: int) -> float:
    best = np.inf
    for _ in range(reps):
        t0 = time.thread_time()
        fn()
        best = min(best, time.thread_time() - t0)
    return best


def settled_runner(options: str, settle_s: float) -> Runner:
    """The deviated case with ``options`` built and advanced ``settle_s`` s (on the wall)."""
    r = Runner(deviated_case(options, settle_s), None, None)
    m = r.model
    rec = new_records(r.sel, (10 ** 15,) * 3, (2, 2, 2), m.n, m.n_ch,
                      span=m.cpar[L.P_SPAN] != 0.0)
    steps = int(round(settle_s / m.dt))
    if steps:
        advance(steps, r.state, m.params, m.work, rec)
    return r


def profile(options: str, steps: int, reps: int, settle_s: float) -> dict:
    r = settled_runner(options, settle_s)
    m = r.model
    p = m.params
    base_state = r.state
    n = base_state.n_active

    def fresh():
        return base_state.copy(), m.work._replace(R=m.work.R.copy(), wW=m.work.wW.copy(),
                                                  loads=m.work.loads.copy(), ch=m.work.ch.copy(),
                                                  vec=m.work.vec.copy(), mat=m.work.mat.copy())

    # the topmost rows of seg / jp / topp change with growth: work on copies
    def pcopy():
        return p._replace(seg=p.seg.copy(), jp=p.jp.copy(), topp=p.topp.copy(), bp=p.bp.copy())

    parts: dict[str, float] = {}
    s, wk = fresh()
    rot_body = lambda: loop_body(steps, s, p, wk)  # noqa: E731
    parts["rotations + body"] = _best(rot_body, reps)
    s, wk = fresh()
    loop_body(1, s, p, wk)
    parts["joints"] = _best(lambda: loop_joints(steps, s, p, wk), reps)
    s, wk = fresh()
    loop_body(1, s, p, wk)
    parts["boundaries"] = _best(lambda: loop_boundaries(steps, s, p, wk), reps)
    s, wk = fresh()
    loop_body(1, s, p, wk)
    parts["contact + friction"] = _best(lambda: loop_contact(steps, s, p, wk), reps)
    s, wk = fresh()
    parts["integrator"] = _best(lambda: loop_integrator(steps, s, p, wk), reps)

    def growth():
        s2, wk2 = fresh()
        p2 = pcopy()
        loop_body(1, s2, p2, wk2)
        t0 = time.thread_time()
        loop_growth(steps, s2, p2, wk2)
        return time.thread_time() - t0

    parts["growth"] = min(growth() for _ in range(reps))
    ev = tuple(r.every)
    rows = tuple(steps // e + 2 for e in ev)
    span = m.cpar[L.P_SPAN] != 0.0
    # the recorder without and with the span correction (which it calls at the loads rate)
    rec = new_records(r.sel, ev, rows, m.n, m.n_ch, span=False)
    s, wk = fresh()
    p_nospan = p._replace(cpar=p.cpar.copy())
    if p_nospan.cpar.shape[0] > L.P_SPAN:
        p_nospan.cpar[L.P_SPAN] = 0.0

    def recorder():
        rec.counts[:] = 0
        loop_record(steps, s, p_nospan, wk, rec)

    parts["recorder"] = _best(recorder, reps)
    if span:
        out = np.zeros((r.sel.size, 2))
        k_span = max(1, steps // ev[0])
        parts["span record"] = _best(lambda: loop_span(k_span, s, p, wk, r.sel, out), reps)
    # the whole step
    rec_w = new_records(r.sel, ev, rows, m.n, m.n_ch, span=span)

    def whole():
        s2, wk2 = fresh()
        p2 = pcopy()
        rec_w.counts[:] = 0
        t0 = time.thread_time()
        st = advance(steps, s2, p2, wk2, rec_w)
        dt_wall = time.thread_time() - t0
        assert st == 0, st
        return dt_wall

    whole_s = min(whole() for _ in range(reps))
    us = {k: 1e6 * v / (steps * n) for k, v in parts.items()}
    return {"options": options, "n_segments": n, "dt_s": m.dt, "steps": steps,
            "points_per_segment_mean": _points(m, n), "step": step_limits(m, n),
            "us_per_segment_step": us, "sum_of_parts_us": sum(us.values()),
            "whole_step_us": 1e6 * whole_s / (steps * n)}


def step_limits(m, n: int) -> dict:
    """The stable step of the model's ``n`` active segments (before the safety factor) with
    and without the wall contact's penalty springs: how much smaller the contact makes
    the step."""
    dt_all = stable_step(m.seg[:n], m.jp[:n], m.bp, m.cpar, m.cp_n[:n])
    dt_joints = stable_step(m.seg[:n], m.jp[:n], m.bp)
    return {"dt_s": m.dt, "stable_dt_s": dt_all, "stable_dt_without_contact_s": dt_joints,
            "contact_step_ratio": dt_joints / dt_all}


def _points(m, n: int) -> float:
    if m.cpar[L.P_CPTAB] != 0.0:
        return float(np.mean(m.cp_n[: n - 1]))
    return float(m.cpar[L.P_NPTS])


def table(results: list[dict], ref_us: float) -> str:
    names = list(dict.fromkeys(k for r in results for k in r["us_per_segment_step"]))
    head = "| part | " + " | ".join(f"{r['options']} (µs / ×ref)" for r in results) + " |"
    lines = [head, "|---|" + "---|" * len(results)]
    for k in names:
        cells = []
        for r in results:
            u = r["us_per_segment_step"].get(k)
            cells.append("—" if u is None else f"{u:.3f} / {u / ref_us:.1f}")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    for label, key in (("sum of parts", "sum_of_parts_us"), ("whole step", "whole_step_us")):
        lines.append(f"| **{label}** | " + " | ".join(
            f"{r[key]:.3f} / {r[key] / ref_us:.1f}" for r in results) + " |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer steps and repetitions")
    ap.add_argument("--repeat", type=int, default=0)
    ap.add_argument("--settle", type=float, default=1.0, help="simulated s before freezing")
    ap.add_argument("--out", type=Path, default=RESULTS)
    args = ap.parse_args()
    steps = 300 if args.quick else 2000
    reps = args.repeat or (3 if args.quick else 7)
    ref = reference_us_per_segment_step(reps, time.thread_time)
    results = []
    for opt in OPTION_SETS:
        results.append(profile(opt, steps, reps, args.settle))
    ref2 = reference_us_per_segment_step(reps, time.thread_time)
    ref_us = min(ref, ref2)
    out = {"benchmark": "profile_step", "reference_us_per_segment_step": ref_us,
           "reference_runs_us": [ref, ref2], "steps": steps, "repeat": reps,
           "settle_s": args.settle, "results": results,
           "note": "best of the repetitions; one thread; the machine may be shared"}
    print(table(results, ref_us))
    for r in results:
        st = r["step"]
        print(f"{r['options']}: dt {st['dt_s']:.3g} s; stable step {st['stable_dt_s']:.3g} s, "
              f"{st['stable_dt_without_contact_s']:.3g} s without the contact springs "
              f"({st['contact_step_ratio']:.2f}x)")
    print(f"reference kernel: {ref_us:.4f} µs per segment-step")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
