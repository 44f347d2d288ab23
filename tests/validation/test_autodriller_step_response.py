"""Autodriller: step response against the closed-loop second-order model, and the stability rule.

Reference (drillfatigue.dynamics.top.rig docstring): with the string quasi-static,
``WOB(s)/WOB_set(s) = k (Kp s + Ki) / (s^2 + k (Kp + c) s + k Ki)`` for a string
of axial stiffness k (string in series with the rock) and the linearised bit
law ROP = c WOB. The kernel is integrated in time on a single-mass model of
the string: a 40 t lumped mass hanging from the block on the string spring,
standing on the rock spring-dashpot, with mud drag, its weight, and a rock
face that advances at c WOB. Its axial mode (4.2 rad/s) is 20 times faster
than the loop (0.2 rad/s), so the closed form should hold to a few per cent
(the mass's inertia and the drag, which biases the hook-load estimate of WOB
by c_m v ~ 0.3 kN, are what it leaves out); the issue's bound is 10 % of the
step, the test asks 3 %, and the measured worst deviation is 1.5 % for both
the WOB-measured loop and the hook-load-measured loop with a 0.1 s control
period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.dynamics.top import rig as R

from testkit.rig_references import (C_ROP, K_EFF, KI, KP, KS, W0, W1,
                            single_mass_autodriller)


@pytest.mark.parametrize(("mode", "ts", "tol"), [(R.BLOCK_AUTODRILLER_WOB, 0.0, 0.03),
                                                  (R.BLOCK_AUTODRILLER_HOOK, 0.1, 0.03)])
def test_step_response_matches_the_single_mass_closed_loop(mode: int, ts: float, tol: float) -> None:
    t, wob = single_mass_autodriller(mode, ts)
    ref = W0 + R.second_order_step(t, K_EFF, KP, KI, C_ROP, W1 - W0)
    err = np.abs(wob - ref).max() / (W1 - W0)
    assert err < tol  # within 3 % of the step (the bound is 10 %)
    # and it settles on the set-point
    assert wob[-1000:].mean() == pytest.approx(W1, rel=0.01)


def _kp_at_zero_margin(k: float, ki: float, c: float, tau: float) -> float:
    lo, hi = 1e-7, 1e-3  # margin > 0 at lo, < 0 at hi (the delay dominates)
    assert R.autodriller_loop(lo, ki, k, c, tau)[1] > 0 > R.autodriller_loop(hi, ki, k, c, tau)[1]
    for _ in range(100):
        mid = math.sqrt(lo * hi)
        if R.autodriller_loop(mid, ki, k, c, tau)[1] > 0.0:
            lo = mid
        else:
            hi = mid
    return lo


def _delayed_loop_amplitudes(kp: float, tau: float, dt: float = 2e-3, t_end: float = 150.0):
    """Quasi-static plant dW/dt = k (v(t - tau) - c W), kernel as controller; late/early amplitude."""
    p = np.zeros(R.N_BLOCK_P)
    p[R.BP_VMAX], p[R.BP_AMAX], p[R.BP_TRAVEL] = 100.0, 1e6, 1e6
    p[R.BP_WOBSET], p[R.BP_KP], p[R.BP_KI], p[R.BP_ROPLIM] = 1e5 + 1e4, kp, KI, 100.0
    s = R.new_block_state(1e5)
    s[R.BS_I] = C_ROP * 1e5 / KI
    nd = int(round(tau / dt))
    vbuf = np.full(nd, C_ROP * 1e5)
    w = 1e5
    n = int(round(t_end / dt))
    hist = np.empty(n)
    for k in range(n):
        R.block_step(R.BLOCK_AUTODRILLER_WOB, p, s, w, 0.0, dt)
        v_del = vbuf[k % nd]
        vbuf[k % nd] = s[R.BS_V]
        w += dt * KS * (v_del - C_ROP * w)
        hist[k] = w
    dev = np.abs(hist - 1.1e5)
    q = n // 5
    return dev[q: 2 * q].max(), dev[-q:].max()


def test_stability_rule_separates_decaying_from_growing_loops() -> None:
    # the derived rule (phase margin > 0) against the time-domain loop with a 1 s delay:
    # 15 % inside the boundary the oscillation decays, 15 % outside it grows
    tau = 1.0
    kp_c = _kp_at_zero_margin(KS, KI, C_ROP, tau)
    early, late = _delayed_loop_amplitudes(0.85 * kp_c, tau)
    assert late < 0.5 * early
    early, late = _delayed_loop_amplitudes(1.15 * kp_c, tau)
    assert late > 2.0 * early
