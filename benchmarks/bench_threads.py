"""Would a single long case profit from two threads? (docs/performance.md#two-threads-for-one-case)

Usage: ``python benchmarks/bench_threads.py [--quick] [--segments 1000]``
-> ``benchmarks/results/threads.json``.

A vertical string of ``--segments`` 9 m segments (5 in drill pipe springs) in an 8.5 in
hole, each segment a little off the axis and tilted, spinning: one step's two per-segment
loops that take most of a simulator step (docs/performance.md, the profile), written the
way a parallel step would have to be written:

* the joints: :func:`drillfatigue.dynamics.core.joints.joint_force` for every joint into
  per-joint rows (a thread may not add into the rows of a segment another thread
  also adds into), then one serial pass adding each joint's force and moments to its
  two segments;
* the wall search: :func:`drillfatigue.dynamics.contact.wall.find_contact` for each segment's
  two end points, into per-point rows.

Three versions of that step are timed in wall time (a parallel region is what the
thread count changes), best of ``--repeat`` loops of ``--steps`` steps: the serial
loops (``range``), the ``prange`` loops on one thread and on two. The load average
of the machine is recorded with them: on a machine shared by several jobs a second
thread only pays when a second core is free.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit, prange

from drillfatigue.files import atomic_write_json
from drillfatigue.numba_cache import scope_numba_cache

scope_numba_cache()

from drillfatigue.dynamics.contact.wall import build_cylinder_chain, find_contact  # noqa: E402
from drillfatigue.dynamics.core.joints import joint_force  # noqa: E402
from drillfatigue.dynamics.core.rigid import quat_to_rot  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results" / "threads.json"
SEG_M = 9.0
R_HOLE = 0.108
R_TJ = 0.0841


@njit(cache=True, inline="always")
def _joint(j, x, v, R, q, w, h, kp, out, loads, ed):
    joint_force((x[j], v[j], R[j], q[j], w[j], h[j]),
                (x[j + 1], v[j + 1], R[j + 1], q[j + 1], w[j + 1], h[j + 1]), kp,
                (out[j, 0], out[j, 1], out[j, 2], loads[j], ed[j]))


@njit(cache=True, inline="always")
def _search(i, x, R, h, p0, ax, ln, rad, hint, info):
    for pt in range(2):
        off = h[i] if pt == 0 else -h[i]
        X = info[i, pt, 6:9]
        for k in range(3):
            X[k] = x[i, k] + off * R[i, k, 2]
        ic = find_contact(X, R_TJ, p0, ax, ln, rad, hint[i, pt], info[i, pt, :6])
        if ic >= 0:
            hint[i, pt] = ic


@njit(cache=True, inline="always")
def _gather(n, out, F, M):
    for i in range(n):
        for k in range(3):
            F[i, k] = 0.0
            M[i, k] = 0.0
    for j in range(n - 1):
        for k in range(3):
            F[j, k] += out[j, 0, k]
            F[j + 1, k] -= out[j, 0, k]
            M[j, k] += out[j, 1, k]
            M[j + 1, k] += out[j, 2, k]


# like the simulator's loops, without numba's reference counting on the row views
@njit(cache=True, _nrt=False)
def steps_serial(k, x, v, R, q, w, h, kp, out, loads, ed, p0, ax, ln, rad, hint, info,
                 F, M):
    n = x.shape[0]
    for _ in range(k):
        for j in range(n - 1):
            _joint(j, x, v, R, q, w, h, kp, out, loads, ed)
        for i in range(n):
            _search(i, x, R, h, p0, ax, ln, rad, hint, info)
        _gather(n, out, F, M)


@njit(cache=True, parallel=True)
def steps_parallel(k, x, v, R, q, w, h, kp, out, loads, ed, p0, ax, ln, rad, hint, info,
                   F, M):
    n = x.shape[0]
    for _ in range(k):
        for j in prange(n - 1):
            _joint(j, x, v, R, q, w, h, kp, out, loads, ed)
        for i in prange(n):
            _search(i, x, R, h, p0, ax, ln, rad, hint, info)
        _gather(n, out, F, M)


def build(n: int, seed: int = 0) -> tuple:
    rng = np.random.default_rng(seed)
    h = np.full(n, 0.5 * SEG_M)
    x = np.zeros((n, 3))
    x[:, 2] = (n - np.arange(n) - 0.5) * SEG_M
    x[:, :2] = rng.normal(0.0, 0.01, (n, 2))
    v = rng.normal(0.0, 0.05, (n, 3))
    w = rng.normal(0.0, 0.5, (n, 3))
    w[:, 2] += 15.7
    q = np.zeros((n, 4))
    q[:, 0] = 1.0
    q[:, 1:] = rng.normal(0.0, 1e-3, (n, 3))
    q /= np.linalg.norm(q, axis=1)[:, None]
    R = np.zeros((n, 3, 3))
    for i in range(n):
        quat_to_rot(q[i], R[i])
    # magnitudes of 5 in drill pipe over 9 m (EA/L, a stiff shear spring, EI/L, GJ/L) and
    # dampers: the cost of the kernel does not depend on the values
    ea, ei, gj = 2.07e11 * 3.4e-3, 2.07e11 * 5.9e-6, 7.9e10 * 1.18e-5
    kp = np.array([ea / SEG_M, 12.0 * ei / SEG_M ** 3 * 100.0, ei / SEG_M, gj / SEG_M,
                   2e4, 2e3, 1e3, 1e2])
    out = np.zeros((n, 3, 3))
    loads = np.zeros((n, 6))
    ed = np.zeros((n, 2))
    pts = np.zeros((n // 3 + 2, 3))
    pts[:, 2] = np.arange(pts.shape[0]) * 3.0 * SEG_M - SEG_M
    p0, ax, ln, rad = build_cylinder_chain(pts, R_HOLE)
    hint = np.zeros((n, 2), dtype=np.int64)
    for i in range(n):
        hint[i, :] = max(0, int((x[i, 2] + SEG_M) // (3.0 * SEG_M)))
    info = np.zeros((n, 2, 9))
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    return (x, v, R, q, w, h, kp, out, loads, ed, p0, ax, ln, rad, hint, info, F, M)


def best_wall(fn, k: int, args: tuple, reps: int) -> float:
    best = math.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        fn(k, *args)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--segments", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=0)
    ap.add_argument("--out", type=Path, default=RESULTS)
    args = ap.parse_args()
    n = args.segments
    steps = args.steps or (100 if args.quick else 500)
    reps = args.repeat or (3 if args.quick else 7)
    a_ser = build(n)
    a_par = build(n)
    steps_serial(1, *a_ser)
    numba.set_num_threads(1)
    steps_parallel(1, *a_par)
    same = bool(np.array_equal(a_ser[-2], a_par[-2]) and np.array_equal(a_ser[-4], a_par[-4]))
    load_before = os.getloadavg()
    res = {}
    rounds = []
    for _ in range(2):  # serial / 1 thread / 2 threads, twice, interleaved
        row = {"serial": best_wall(steps_serial, steps, a_ser, reps)}
        for t in (1, 2):
            numba.set_num_threads(t)
            row[f"prange_{t}_threads"] = best_wall(steps_parallel, steps, a_par, reps)
        rounds.append({k: 1e6 * v / (steps * n) for k, v in row.items()})
    for key in rounds[0]:
        res[key] = min(r[key] for r in rounds)
    out = {"benchmark": "threads", "segments": n, "steps": steps, "repeat": reps,
           "us_per_segment_step": res, "rounds_us_per_segment_step": rounds,
           "speedup_2_threads_vs_serial": res["serial"] / res["prange_2_threads"],
           "parallel_result_equals_serial": same,
           "threading_layer": numba.threading_layer(), "cpus": os.cpu_count(),
           "load_average_before_after": [list(load_before), list(os.getloadavg())],
           "note": "wall time (a parallel region is what the thread count changes); the "
                   "machine may be shared: see the load average"}
    print(json.dumps(out, indent=1))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
