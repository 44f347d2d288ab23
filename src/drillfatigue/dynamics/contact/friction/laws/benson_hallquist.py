"""Benson and Hallquist: ``mu = [mu_d + (mu_s - mu_d) exp(-|v| / v_c)] min(|v| / v_reg, 1)``.

The LS-DYNA exponential decay from the static to the dynamic coefficient, with
the Coulomb ramp below ``v_reg`` (docs/model.md#friction).
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, I_MU_S

NAME = "benson_hallquist"
PARAMS = ("v_reg_m_per_s", "v_c_m_per_s")
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    mu_s = p[I_MU_S]
    mu_d = p[I_MU_D]
    return (mu_d + (mu_s - mu_d) * math.exp(-speed / p[o + 1])) * min(speed / p[o], 1.0)


def slip_scale_m_per_s(q):
    """The ramp's width."""
    return q[0]
