"""Simulator speed: µs per segment-step against a machine-speed reference, real-time
factor, peak memory, and a numpy + scipy BDF baseline.

Usage: ``python benchmarks/bench_simulator.py [--quick]`` -> ``benchmarks/results/simulator.json``.

* Machine-speed reference: :func:`reference_chain_step`, a plain rigid chain frozen in
  this file (about 300 flops and 7 transcendental functions per segment and step),
  timed (best of 5, CPU time of the thread) at the start and at the end of the run.
  Every case below is reported as µs per segment-step in wall time (the real-time
  factor) and in CPU time of the thread (``cpu_us_per_segment_step``: a long minus a
  short run of the same set-up, so the stepping loop alone; on a shared machine the
  wall time of the same run varies by 2x, its CPU time by a few %), and as
  ``ratio_to_reference`` (CPU µs per segment-step over the reference's): absolute
  times do not carry across machines, the ratios do (to within the differences of
  their instruction mixes).
* For 5, 30 and 120 segments (collars + 5 in drill pipe, ~9 m segments, vertical
  hole, 150 rpm, TOB, ROP with the growing top segment, lobed bit motion, loads
  of every joint recorded at 200 Hz): simulated seconds per wall second on one
  core (``drillfatigue.simulate`` in memory, numba kernels compiled and cached
  beforehand) and the peak resident memory of a fresh process per case.
* Baseline: the same model's right-hand side written the usual way (numpy,
  vectorised over joints and segments) integrated by ``scipy.integrate.solve_ivp``
  (BDF, rtol 1e-5, max step 1 ms, as the paper) on the 30-segment case over a
  short window; the numba run of the very same case (no ROP, no lobes) gives the
  ratio. The numpy RHS is checked against the numba force kernel first.
* Deviated drilling, the paper-scale case 2 in a short window:
  ``data/cases/case2_profile.yaml`` -- 120 segments on profile_1 from 480 m, wall
  contact, tanh-exponential friction, 150 rpm, drilling at 0.5 m/s (segments split
  off the top as it grows), 0.5 s relaxation; real-time factor and µs per
  segment-step over the run after a warm-up, with the contact points at the segment
  ends (the case as written) and with ``contact.points: string`` and
  ``contact.span_bending: true`` (:data:`OPTION_SETS`).
* Friction-law cost: ``data/cases/case1_whirl.yaml`` (5 segments,
  sustained backward whirl) with Karnopp and with tanh-exponential: wall-time
  ratio of the stepping loop (paper: 47 vs 18 min, 2.6x).
Goals: 120 segments >= 1x real time (vertical and deviated drilling);
>= 50x the scipy baseline; deviated drilling <= 0.5 µs per segment-step and case 2
>= 5x real time on one core. ``benchmarks/profile_step.py`` splits one step by room.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from drillfatigue.files import atomic_write_json  # noqa: E402
from drillfatigue.numba_cache import scope_numba_cache  # noqa: E402

# numba's cache under the kernels' digest: its own index only sees a kernel's own file,
# so a cached step would keep an edited callee's old code
scope_numba_cache()

from drillfatigue.config import case_from_dict  # noqa: E402
from drillfatigue.dynamics.core import layout as L  # noqa: E402
from drillfatigue.dynamics.run.model import build_model, evaluate_forces, straight_path  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results" / "simulator.json"
SPLIT = {5: (1, 4), 30: (5, 25), 120: (20, 100)}


def case(n: int, duration: float, full: bool = True, baseline: bool = False):
    n_dc, n_dp = SPLIT[n]
    extra = {"bit": {"model": "given_tob"}, "contact": {"enabled": False}} if baseline else {}
    return case_from_dict({**extra,
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 9.0 * n_dc,
             "n_segments": n_dc},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 9.0 * n_dp,
             "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
             "tool_joint_length_fraction": 0.05, "n_segments": n_dp}]},
        "operation": {"bit_md_m": 9.0 * n + 5.0, "duration_s": duration, "rpm": 150.0,
                      "rpm_ramp_s": 1.0 if full else 0.0, "tob_Nm": 3000.0,
                      "rop_m_per_s": 0.01 if full else 0.0, "lobe_count": 3,
                      "lobe_amplitude_m": 0.001 if full else 0.0, "top_axial": "neutral_point"},
        "recording": {"loads_rate_hz": 200.0, "channels_rate_hz": 200.0,
                      "kinematics_rate_hz": 10.0},
    })


def path_for(n: int):
    return straight_path(9.0 * n + 200.0)


def _cpu_per_step(run, short_s: float, long_s: float):
    """CPU time of this thread per step of the stepping loop: ``run(duration)`` for a long
    and a short window (the same set-up and relaxation), the difference over the
    difference of their steps. Returns (the long run's result, µs per step)."""
    t0 = time.thread_time()
    short = run(short_s)
    t1 = time.thread_time()
    res = run(long_s)
    t2 = time.thread_time()
    steps = res.summary["n_steps"] - short.summary["n_steps"]
    return res, 1e6 * ((t2 - t1) - (t1 - t0)) / steps


def run_one(n: int, duration: float, full: bool = True) -> dict:
    """Run one case in this process; return timings and peak RSS."""
    from drillfatigue.dynamics.run.simulation import simulate

    simulate(case(n, 0.05, full), None, progress=False, path=path_for(n))  # compile / load cache
    t0 = time.perf_counter()
    res, cpu_step = _cpu_per_step(
        lambda d: simulate(case(n, d, full), None, progress=False, path=path_for(n)),
        0.05, duration)
    wall_total = time.perf_counter() - t0
    s = res.summary
    return {"n_segments": n, "simulated_s": s["duration_s"], "wall_s": s["wall_time_s"],
            "wall_with_setup_s": wall_total, "real_time_factor": s["real_time_factor"],
            "dt_s": s["dt_s"], "steps_per_s": s["n_steps"] / s["wall_time_s"],
            "us_per_segment_step": 1e6 * s["wall_time_s"] / (s["n_steps"] * n),
            "cpu_us_per_segment_step": cpu_step / n,
            "cpu_real_time_factor": s["dt_s"] / (1e-6 * cpu_step),
            "peak_rss_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "energy_balance_error_rel": s["energy_balance_error_rel"]}


CASES_DIR = Path(__file__).resolve().parents[1] / "data" / "cases"


def _case_file(name: str, **sections: dict):
    from drillfatigue.config.base import read_yaml

    data = read_yaml(CASES_DIR / name)
    for sec, vals in sections.items():
        data.setdefault(sec, {}).update(vals)
    return case_from_dict(data)


#: the deviated case's contact options: as case2_profile.yaml is written (contact points at
#: the segment ends) and with the string's own contact points and the span-bending
#: correction (``contact.points: string``, ``contact.span_bending: true``)
OPTION_SETS = {"ends": {}, "string_span": {"points": "string", "span_bending": True}}


def deviated_case(options: str, duration: float):
    """case2_profile.yaml for ``duration`` s with the contact options ``OPTION_SETS[options]``
    (no checkpoints; the rpm ramped over 1 s)."""
    return _case_file("case2_profile.yaml", operation={"duration_s": duration, "rpm_ramp_s": 1.0},
                      solver={"checkpoint_every_s": 0.0}, contact=dict(OPTION_SETS[options]))


def run_deviated(duration: float, options: str = "ends") -> dict:
    """case2_profile.yaml (120 segments, contact, tanh-exp, 0.5 m/s) for ``duration`` s."""
    from drillfatigue.dynamics.run.simulation import simulate

    simulate(deviated_case(options, 0.05), None, progress=False)  # compile / load cache
    res, cpu_step = _cpu_per_step(
        lambda d: simulate(deviated_case(options, d), None, progress=False), 0.05, duration)
    s = res.summary
    n_mean = 0.5 * (s["n_segments_initial"] + s["n_segments_final"])
    return {"case": "case2_profile (120 segments, deviated, contact, tanh_exp, ROP 0.5 m/s)",
            "contact_options": OPTION_SETS[options],
            "simulated_s": s["duration_s"], "wall_s": s["wall_time_s"],
            "real_time_factor": s["real_time_factor"], "dt_s": s["dt_s"],
            "n_steps": s["n_steps"],
            "segments_initial": s["n_segments_initial"], "segments_final": s["n_segments_final"],
            "us_per_segment_step": 1e6 * s["wall_time_s"] / (s["n_steps"] * s["n_segments_final"]),
            "cpu_us_per_segment_step": cpu_step / n_mean,
            "cpu_real_time_factor": s["dt_s"] / (1e-6 * cpu_step),
            "peak_rss_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "energy_balance_error_rel": s["energy_balance_error_rel"]}


def run_whirl(duration: float) -> dict:
    """case1_whirl.yaml with Karnopp and tanh-exp: stepping-loop wall times and their ratio."""
    from drillfatigue.dynamics.run.simulation import simulate

    simulate(_case_file("case1_whirl.yaml", operation={"duration_s": 0.05}), None, progress=False)
    out: dict = {}
    for model in ("tanh_exp", "karnopp"):
        res = simulate(_case_file("case1_whirl.yaml", operation={"duration_s": duration},
                                  friction={"model": model}), None, progress=False)
        s = res.summary
        out[model] = {"wall_s": s["wall_time_s"], "dt_s": s["dt_s"], "n_steps": s["n_steps"],
                      "whirl_class": s["whirl_class"]}
    out["wall_ratio_karnopp_over_tanh_exp"] = out["karnopp"]["wall_s"] / out["tanh_exp"]["wall_s"]
    out["paper_ratio"] = 47.0 / 18.0
    out["simulated_s"] = duration
    return out


# --- the machine-speed reference ---------------------------------------------------------
#: The reference kernel below is frozen: every case is reported as a ratio to its time in
#: the same run, so results compare across machines. Never edit it (a change would break
#: the comparison with earlier results); a new reference needs a new name.
REF_SEGMENTS = 120
REF_STEPS = 2000


@njit(cache=True)
def reference_chain_step(n_steps, x, v, q, w, out):
    """A plain rigid chain, written once for speed (frozen; see above): per segment and
    step a quaternion -> rotation matrix, an axial/lateral spring-damper to the next
    segment's end, a bending spring from the relative quaternion (sqrt, atan2), a
    penalty wall at 2 cm lateral distance from the axis with tanh friction (sqrt,
    tanh, exp), then a symplectic-Euler kick and drift with an exact quaternion
    increment (sqrt, cos, sin) and renormalisation: about 300 flops and 7
    transcendental functions. Angular velocities and moments in the world frame.
    ``out`` (n, 6): scratch for the forces and moments."""
    n = x.shape[0]
    dt = 1e-4
    m = 100.0
    inertia = 10.0
    h = 4.5
    k = 1.0e6
    c = 2.0e3
    kb = 1.0e6
    kc = 1.0e6
    mu = 0.3
    vt = 0.01
    for _ in range(n_steps):
        for i in range(n):
            for j in range(6):
                out[i, j] = 0.0
        for i in range(n - 1):
            a0, a1, a2, a3 = q[i, 0], q[i, 1], q[i, 2], q[i, 3]
            b0, b1, b2, b3 = q[i + 1, 0], q[i + 1, 1], q[i + 1, 2], q[i + 1, 3]
            # body axes (third columns of the rotation matrices)
            ez0 = 2.0 * (a1 * a3 + a0 * a2)
            ez1 = 2.0 * (a2 * a3 - a0 * a1)
            ez2 = 1.0 - 2.0 * (a1 * a1 + a2 * a2)
            fz0 = 2.0 * (b1 * b3 + b0 * b2)
            fz1 = 2.0 * (b2 * b3 - b0 * b1)
            fz2 = 1.0 - 2.0 * (b1 * b1 + b2 * b2)
            d0 = (x[i + 1, 0] + h * fz0) - (x[i, 0] - h * ez0)
            d1 = (x[i + 1, 1] + h * fz1) - (x[i, 1] - h * ez1)
            d2 = (x[i + 1, 2] + h * fz2) - (x[i, 2] - h * ez2)
            u0 = v[i + 1, 0] - v[i, 0]
            u1 = v[i + 1, 1] - v[i, 1]
            u2 = v[i + 1, 2] - v[i, 2]
            f0 = k * d0 + c * u0
            f1 = k * d1 + c * u1
            f2 = k * d2 + c * u2
            # relative rotation b * conj(a) (world frame) and its rotation vector
            r0 = a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3
            r1 = a0 * b1 - b0 * a1 - b2 * a3 + b3 * a2
            r2 = a0 * b2 - b0 * a2 - b3 * a1 + b1 * a3
            r3 = a0 * b3 - b0 * a3 - b1 * a2 + b2 * a1
            sn = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
            fac = 2.0 * math.atan2(sn, r0) / sn if sn > 1e-12 else 2.0
            m0 = kb * fac * r1 + c * (w[i + 1, 0] - w[i, 0])
            m1 = kb * fac * r2 + c * (w[i + 1, 1] - w[i, 1])
            m2 = kb * fac * r3 + c * (w[i + 1, 2] - w[i, 2])
            out[i, 0] += f0
            out[i, 1] += f1
            out[i, 2] += f2
            out[i + 1, 0] -= f0
            out[i + 1, 1] -= f1
            out[i + 1, 2] -= f2
            out[i, 3] += m0 - h * (ez1 * f2 - ez2 * f1)
            out[i, 4] += m1 - h * (ez2 * f0 - ez0 * f2)
            out[i, 5] += m2 - h * (ez0 * f1 - ez1 * f0)
            out[i + 1, 3] -= m0 + h * (fz1 * f2 - fz2 * f1)
            out[i + 1, 4] -= m1 + h * (fz2 * f0 - fz0 * f2)
            out[i + 1, 5] -= m2 + h * (fz0 * f1 - fz1 * f0)
        for i in range(n):
            # penalty wall and tanh friction against the axial slip
            rr = math.sqrt(x[i, 0] * x[i, 0] + x[i, 1] * x[i, 1])
            pen = rr - 0.02
            if pen > 0.0:
                fn = kc * pen
                vs = v[i, 2] + 0.1 * w[i, 2]
                ff = mu * fn * math.tanh(vs / vt) * (1.0 + 0.5 * math.exp(-abs(vs) / 0.5))
                out[i, 0] -= fn * x[i, 0] / rr
                out[i, 1] -= fn * x[i, 1] / rr
                out[i, 2] -= ff
                out[i, 5] -= 0.1 * ff
            for j in range(3):
                v[i, j] += dt * (out[i, j] / m - 0.5 * v[i, j])
                x[i, j] += dt * v[i, j]
                w[i, j] += dt * (out[i, 3 + j] / inertia - 0.5 * w[i, j])
            # q <- exp(dt w / 2) q (w in the world frame), renormalised
            an = dt * math.sqrt(w[i, 0] * w[i, 0] + w[i, 1] * w[i, 1] + w[i, 2] * w[i, 2])
            ch = math.cos(0.5 * an)
            sh = 0.5 * dt * (math.sin(0.5 * an) / (0.5 * an) if an > 1e-12 else 1.0)
            e0 = ch
            e1 = sh * w[i, 0]
            e2 = sh * w[i, 1]
            e3 = sh * w[i, 2]
            q0, q1, q2, q3 = q[i, 0], q[i, 1], q[i, 2], q[i, 3]
            p0 = e0 * q0 - e1 * q1 - e2 * q2 - e3 * q3
            p1 = e0 * q1 + e1 * q0 + e2 * q3 - e3 * q2
            p2 = e0 * q2 - e1 * q3 + e2 * q0 + e3 * q1
            p3 = e0 * q3 + e1 * q2 - e2 * q1 + e3 * q0
            nq = 1.0 / math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
            q[i, 0] = p0 * nq
            q[i, 1] = p1 * nq
            q[i, 2] = p2 * nq
            q[i, 3] = p3 * nq


def reference_state(n: int = REF_SEGMENTS):
    """The reference chain's start: a straight vertical chain, disturbed laterally
    (some segments on the wall), spinning at 15 rad/s."""
    rng = np.random.default_rng(26)
    x = np.zeros((n, 3))
    x[:, 2] = -9.0 * np.arange(n)
    x[:, :2] = rng.normal(0.0, 0.015, (n, 2))
    v = rng.normal(0.0, 0.01, (n, 3))
    q = np.zeros((n, 4))
    q[:, 0] = 1.0
    w = np.zeros((n, 3))
    w[:, 2] = 15.0
    return x, v, q, w, np.zeros((n, 6))


def reference_us_per_segment_step(repeat: int = 5, clock=time.perf_counter) -> float:
    """Best-of-``repeat`` time of the frozen reference kernel, µs per segment-step
    (``clock``: wall time by default, as the cases' real-time factors)."""
    arrays = reference_state()
    reference_chain_step(10, *reference_state())  # compile / load cache
    best = math.inf
    for _ in range(repeat):
        a = [b.copy() for b in arrays]
        t0 = clock()
        reference_chain_step(REF_STEPS, *a)
        best = min(best, clock() - t0)
        if not np.isfinite(a[0]).all():
            raise RuntimeError("the reference chain diverged")
    return 1e6 * best / (REF_STEPS * REF_SEGMENTS)


# --- the numpy baseline ------------------------------------------------------------------
def _qmul(a, b):
    return np.stack([
        a[..., 0] * b[..., 0] - a[..., 1] * b[..., 1] - a[..., 2] * b[..., 2] - a[..., 3] * b[..., 3],
        a[..., 0] * b[..., 1] + a[..., 1] * b[..., 0] + a[..., 2] * b[..., 3] - a[..., 3] * b[..., 2],
        a[..., 0] * b[..., 2] - a[..., 1] * b[..., 3] + a[..., 2] * b[..., 0] + a[..., 3] * b[..., 1],
        a[..., 0] * b[..., 3] + a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1] + a[..., 3] * b[..., 0],
    ], axis=-1)


def _qconj(a):
    return a * np.array([1.0, -1.0, -1.0, -1.0])


def _q2R(q):
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=-2)


def _joints_np(x_lo, v_lo, R_lo, q_lo, wl, h_lo, x_up, v_up, R_up, q_up, wu, h_up, k, c):
    """Vectorised :func:`drillfatigue.dynamics.core.joints.joint_force` (same physics)."""
    rl = -h_lo[:, None] * R_lo[:, :, 2]
    ru = h_up[:, None] * R_up[:, :, 2]
    d = (x_up + ru) - (x_lo + rl)
    vd = (v_up + np.cross(wu, ru)) - (v_lo + np.cross(wl, rl))
    qr = _qmul(_qconj(q_lo), q_up)
    qr = np.where(qr[:, :1] < 0, -qr, qr)
    s = np.linalg.norm(qr[:, 1:], axis=1)
    f = np.where(s < 1e-12, 2.0 / qr[:, 0], 2.0 * np.arctan2(s, qr[:, 0]) / np.maximum(s, 1e-300))
    th = f[:, None] * qr[:, 1:]
    qh = np.concatenate([(1 + qr[:, :1]), qr[:, 1:]], axis=1)
    qh /= np.linalg.norm(qh, axis=1)[:, None]
    Rm = _q2R(_qmul(q_lo, qh))
    dl = np.einsum("nki,nk->ni", Rm, d)
    ul = np.einsum("nki,nk->ni", Rm, vd)
    kt = np.stack([k[1], k[1], k[0]], 1)
    ct = np.stack([c[1], c[1], c[0]], 1)
    F = np.einsum("nik,nk->ni", Rm, kt * dl + ct * ul)
    kr = np.stack([k[2], k[2], k[3]], 1) * th
    a2 = (th * th).sum(1)
    a = np.sqrt(a2)
    with np.errstate(all="ignore"):
        c2 = np.where(a2 < 1e-8, 1 / 12 + a2 / 720, 1 / a2 - (1 + np.cos(a)) / (2 * a * np.sin(a)))
    xk = np.cross(th, kr)
    m = kr + 0.5 * xk + c2[:, None] * np.cross(th, xk)
    Mr = np.einsum("nik,nk->ni", R_lo, m)
    ol = np.einsum("nki,nk->ni", Rm, wu - wl)
    cr = np.stack([c[2], c[2], c[3]], 1)
    Mr = Mr + np.einsum("nik,nk->ni", Rm, cr * ol)
    hc = 0.5 * np.cross(d, F)
    return F, np.cross(rl, F) + Mr + hc, -np.cross(ru, F) - Mr + hc


class NumpyModel:
    """The model's right-hand side in vectorised numpy (straight path, no growth, no lobes)."""

    def __init__(self, model, omega_d: float, phi0: float) -> None:
        self.m = model
        self.omega_d = omega_d
        self.phi0 = phi0
        self.n = model.n
        p = model.path
        self.p0 = p.node_pos_m[0]
        self.t_path = p.node_tan[0]
        self.md0 = p.node_md_m[0]

    def forces(self, t, x, q, v, w):
        m = self.m
        seg, jp, bp = m.seg, m.jp, m.bp
        n = self.n
        R = _q2R(q)
        wW = np.einsum("nik,nk->ni", R, w)
        e3 = R[:, :, 2]
        vax = (v * e3).sum(1)
        F = -seg[:, L.S_CL, None] * (v - vax[:, None] * e3) - (seg[:, L.S_CA] * vax)[:, None] * e3
        F[:, 2] += seg[:, L.S_W]
        Mw = np.zeros((n, 3))
        Mb = -np.stack([seg[:, L.S_CRL] * w[:, 0], seg[:, L.S_CRL] * w[:, 1],
                        seg[:, L.S_CRA] * w[:, 2]], 1)
        a, b = slice(0, n - 1), slice(1, n)
        k = [jp[a, c] for c in (L.J_KA, L.J_KS, L.J_KB, L.J_KT)]
        c = [jp[a, cc] for cc in (L.J_CA, L.J_CS, L.J_CB, L.J_CT)]
        Fj, Ml, Mu = _joints_np(x[a], v[a], R[a], q[a], wW[a], seg[a, L.S_H], x[b], v[b], R[b],
                                q[b], wW[b], seg[b, L.S_H], k, c)
        F[a] += Fj
        F[b] -= Fj
        Mw[a] += Ml
        Mw[b] += Mu
        # top drive
        phi = self.phi0 + self.omega_d * t
        qa = _qmul(m.anchor[3:7], np.array([math.cos(phi / 2), 0, 0, math.sin(phi / 2)]))[None]
        wa = (self.omega_d * m.anchor[7:10])[None]
        tp = slice(n - 1, n)
        k = [jp[tp, cc] for cc in (L.J_KA, L.J_KS, L.J_KB, L.J_KT)]
        c = [jp[tp, cc] for cc in (L.J_CA, L.J_CS, L.J_CB, L.J_CT)]
        pa = m.anchor[None, 0:3].copy()
        va = np.zeros((1, 3))
        if jp[n - 1, L.J_KA] == 0.0:  # hook-load top: the drive follows the top end axially
            ax = m.anchor[7:10]
            r_up = -seg[n - 1, L.S_H] * e3[n - 1]
            pa[0] += ((x[n - 1] + r_up - m.anchor[0:3]) @ ax) * ax
            va[0] = ((v[n - 1] + np.cross(wW[n - 1], r_up)) @ ax) * ax
        Ft, Mt, _ = _joints_np(x[tp], v[tp], R[tp], q[tp], wW[tp], seg[tp, L.S_H],
                               pa, va, _q2R(qa), qa, wa, np.zeros(1), k, c)
        F[tp] += Ft
        Mw[tp] += Mt
        if bp[L.B_AXMODE] == 0.0:
            h = seg[n - 1, L.S_H]
            fh = -bp[L.B_HL] * m.anchor[7:10]
            F[n - 1] += fh
            Mw[n - 1] += np.cross(-h * e3[n - 1], fh)
        if bp[L.B_BITON] == 1.0:
            h0 = seg[0, L.S_H]
            r = h0 * e3[0]
            tgt = self.p0 + (bp[L.B_MD0] - self.md0) * self.t_path
            fb = -bp[L.B_KBIT] * (x[0] + r - tgt) - bp[L.B_CBIT] * (v[0] + np.cross(wW[0], r))
            F[0] += fb
            Mw[0] += np.cross(r, fb)
            Mb[0, 2] -= bp[L.B_TOB] * math.tanh(w[0, 2] / bp[L.B_WREF])
        Mb += np.einsum("nki,nk->ni", R, Mw)
        return F, Mb

    def rhs(self, t, y):
        n = self.n
        x = y[: 3 * n].reshape(n, 3)
        q = y[3 * n: 7 * n].reshape(n, 4)
        v = y[7 * n: 10 * n].reshape(n, 3)
        w = y[10 * n:].reshape(n, 3)
        qn = q / np.linalg.norm(q, axis=1)[:, None]
        F, Mb = self.forces(t, x, qn, v, w)
        seg = self.m.seg
        it, ia = seg[:, L.S_IT], seg[:, L.S_IA]
        dq = 0.5 * _qmul(qn, np.concatenate([np.zeros((n, 1)), w], 1))
        Iw = np.stack([it * w[:, 0], it * w[:, 1], ia * w[:, 2]], 1)
        dw = (Mb - np.cross(w, Iw)) / np.stack([it, it, ia], 1)
        return np.concatenate([v.ravel(), dq.ravel(), (F / seg[:, L.S_M, None]).ravel(), dw.ravel()])


def scipy_baseline(window: float) -> dict:
    from scipy.integrate import solve_ivp

    from drillfatigue.dynamics.run.model import advance_model

    # the issue-3 model the numpy RHS implements: given TOB, no wall contact
    cfg = case(30, window, full=False, baseline=True)
    model, state = build_model(cfg, path_for(30))
    omega = float(model.tab_w[0])
    nm = NumpyModel(model, omega, float(state.sc[L.C_PHID]))
    # the numpy RHS is the same model: compare with the numba kernel at a disturbed state
    rng = np.random.default_rng(0)
    st = state.copy()
    st.v[...] += rng.normal(0, 0.01, st.v.shape)
    st.w[...] += rng.normal(0, 0.05, st.w.shape)
    st.x[...] += rng.normal(0, 1e-5, st.x.shape)
    evaluate_forces(model, st)
    F_np, Mb_np = nm.forces(0.0, st.x, st.q, st.v, st.w)
    scale_f = np.abs(st.Fw).max()
    rhs_err = max(np.abs(F_np - st.Fw).max() / scale_f,
                  np.abs(Mb_np - st.Mb).max() / np.abs(st.Mb).max())
    assert rhs_err < 1e-9, rhs_err
    y0 = np.concatenate([state.x.ravel(), state.q.ravel(), state.v.ravel(), state.w.ravel()])
    t0 = time.perf_counter()
    sol = solve_ivp(nm.rhs, (0.0, window), y0, method="BDF", rtol=1e-5, atol=1e-8, max_step=1e-3)
    wall_scipy = time.perf_counter() - t0
    # numba on the same case and window
    advance_model(model, state.copy(), 10)
    s2 = state.copy()
    n_steps = int(round(window / model.dt))
    t0 = time.perf_counter()
    advance_model(model, s2, n_steps, every=int(round(0.005 / model.dt)))
    wall_numba = time.perf_counter() - t0
    x_np = sol.y[: 90, -1].reshape(30, 3)
    return {"case": "30 segments, 150 rpm, no ROP/lobes", "window_s": window,
            "scipy_status": int(sol.status), "scipy_nfev": int(sol.nfev), "scipy_njev": int(sol.njev),
            "scipy_wall_s": wall_scipy, "scipy_real_time_factor": window / wall_scipy,
            "numba_wall_s": wall_numba, "numba_real_time_factor": n_steps * model.dt / wall_numba,
            "speedup": (n_steps * model.dt / wall_numba) / (window / wall_scipy),
            "rhs_max_rel_difference": rhs_err,
            "final_position_difference_m": float(np.abs(x_np - s2.x).max())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="short runs (CI smoke)")
    ap.add_argument("--one", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--duration", type=float, default=0.0, help=argparse.SUPPRESS)
    ap.add_argument("--part", default="", help=argparse.SUPPRESS)
    ap.add_argument("--options", default="ends", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_one(args.one, args.duration)))
        return
    if args.part:
        if args.part == "deviated":
            print(json.dumps(run_deviated(args.duration, args.options)))
        else:
            print(json.dumps(run_whirl(args.duration)))
        return
    ref_runs = [reference_us_per_segment_step(clock=time.thread_time)]
    print(f"reference kernel: {ref_runs[0]:.4f} µs per segment-step (CPU)", flush=True)
    durations = {5: 2.0, 30: 2.0, 120: 2.0} if args.quick else {5: 20.0, 30: 20.0, 120: 20.0}
    cases = []
    for n, dur in durations.items():
        out = subprocess.run([sys.executable, __file__, "--one", str(n), "--duration", str(dur)],
                             check=True, capture_output=True, text=True)
        cases.append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"{n:4d} segments: {cases[-1]['real_time_factor']:.2f}x real time, "
              f"{cases[-1]['cpu_us_per_segment_step']:.3f} µs (CPU) per segment-step, "
              f"{cases[-1]['peak_rss_MiB']:.0f} MiB peak", flush=True)
    parts = {}
    dev = 2.0 if args.quick else 20.0
    for part, dur, opt in (("deviated", dev, "ends"), ("deviated_string_span", dev, "string_span"),
                           ("whirl", 1.0 if args.quick else 5.0, "")):
        cmd = [sys.executable, __file__, "--part", part.split("_")[0], "--duration", str(dur)]
        if opt:
            cmd += ["--options", opt]
        out = subprocess.run(cmd, check=True, capture_output=True, text=True)
        parts[part] = json.loads(out.stdout.strip().splitlines()[-1])
        if part.startswith("deviated"):
            d = parts[part]
            print(f"deviated 120 segments drilling ({opt}): {d['real_time_factor']:.2f}x real "
                  f"time ({d['cpu_real_time_factor']:.2f}x in CPU time), "
                  f"{d['cpu_us_per_segment_step']:.3f} µs (CPU) per segment-step, "
                  f"dt {d['dt_s']:.3g} s", flush=True)
    print(f"whirl wall-time ratio karnopp / tanh_exp: "
          f"{parts['whirl']['wall_ratio_karnopp_over_tanh_exp']:.2f} (paper 2.6)", flush=True)
    base = scipy_baseline(0.02 if args.quick else 0.1)
    print(f"scipy BDF baseline (30 segments): {base['scipy_real_time_factor']:.2e}x real time; "
          f"numba {base['speedup']:.0f}x faster", flush=True)
    ref_runs.append(reference_us_per_segment_step(clock=time.thread_time))
    ref_us = min(ref_runs)
    print(f"reference kernel: {ref_runs[1]:.4f} µs per segment-step (best {ref_us:.4f})",
          flush=True)
    for c in [*cases, parts["deviated"], parts["deviated_string_span"]]:
        c["ratio_to_reference"] = c["cpu_us_per_segment_step"] / ref_us
    import platform

    result = {
        "benchmark": "simulator", "quick": args.quick,
        "reference": {"kernel": "bench_simulator.reference_chain_step (frozen)",
                      "segments": REF_SEGMENTS, "steps": REF_STEPS,
                      "us_per_segment_step": ref_us, "runs_us": ref_runs,
                      "note": "CPU time of the thread, best of 5 at the start and at the end "
                              "of the run; every case's ratio_to_reference is its "
                              "cpu_us_per_segment_step over this"},
        "cases": cases, "scipy_baseline": base,
        "deviated_drilling": parts["deviated"],
        "deviated_drilling_string_span": parts["deviated_string_span"],
        "whirl_friction_cost": parts["whirl"],
        # the real-time goals are for one core: its CPU time (the wall-time factors are
        # recorded too, and fall on a shared machine)
        "goals": {"rtf_120_segments_ge_1": cases[-1]["cpu_real_time_factor"] >= 1.0,
                  "rtf_120_deviated_drilling_ge_1":
                      parts["deviated"]["cpu_real_time_factor"] >= 1.0,
                  "us_per_segment_step_deviated_le_0p5":
                      parts["deviated"]["cpu_us_per_segment_step"] <= 0.5,
                  "rtf_case2_window_ge_5": parts["deviated"]["cpu_real_time_factor"] >= 5.0,
                  "speedup_vs_scipy_ge_50": base["speedup"] >= 50.0},
        "machine": {"python": platform.python_version(), "processor": platform.processor(),
                    "cpu_count": os.cpu_count(), "threads": 1,
                    "load_average": list(os.getloadavg())},
        "note": "single thread; the machine may be shared with other jobs",
    }
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_json(RESULTS, result)
    print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
