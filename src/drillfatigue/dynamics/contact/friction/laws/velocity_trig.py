"""Velocity-based trigonometric friction (after Wang & Rui; their exact form is not
available, this is a documented plausible one with the fitted constants configurable).

``mu = mu_s sin(pi/2 |v| / v_p)`` for ``|v| <= v_p`` (quarter-sine rise to the
static peak), ``mu = mu_d + (mu_s - mu_d)(1 + cos(pi (|v| - v_p) / v_w)) / 2``
for ``v_p < |v| < v_p + v_w`` (half-cosine Stribeck decay), ``mu_d`` beyond.
C1-continuous at the peak and at the end of the decay.
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, I_MU_S

NAME = "velocity_trig"
PARAMS = ("trig_v_peak_m_per_s", "trig_v_decay_m_per_s")
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    mu_s = p[I_MU_S]
    mu_d = p[I_MU_D]
    vp = p[o]
    vw = p[o + 1]
    if speed <= vp:
        return mu_s * math.sin(0.5 * math.pi * speed / vp)
    if speed < vp + vw:
        return mu_d + (mu_s - mu_d) * 0.5 * (1.0 + math.cos(math.pi * (speed - vp) / vw))
    return mu_d


def slip_scale_m_per_s(q):
    """The quarter sine's initial slope: mu_s per (2 v_p / pi)."""
    return q[0] * 2.0 / math.pi
