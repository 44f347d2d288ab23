"""The paper's hybrid tanh-exponential friction (plausible form, docs/model.md#friction):
``mu = tanh(|v| / v_t) [mu_d + (mu_s - mu_d) exp(-|v| / v_s)]``, ``v_t << v_s``."""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, I_MU_S, tanh_sat

NAME = "tanh_exp"
PARAMS = ("v_t_m_per_s", "v_s_m_per_s")
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    mu_s = p[I_MU_S]
    mu_d = p[I_MU_D]
    return tanh_sat(speed / p[o]) * (mu_d + (mu_s - mu_d) * math.exp(-speed / p[o + 1]))


def slip_scale_m_per_s(q):
    """The tanh's regularisation speed."""
    return q[0]
