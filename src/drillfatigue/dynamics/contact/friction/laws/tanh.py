"""tanh friction (Mostaghel & Davis, Earthquake Eng. Struct. Dyn. 26 (1997) 541-548):
``mu = mu_d tanh(|v| / v_t)``."""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, tanh_sat

NAME = "tanh"
PARAMS = ("v_t_m_per_s",)
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    return p[I_MU_D] * tanh_sat(speed / p[o])


def slip_scale_m_per_s(q):
    """The tanh's regularisation speed."""
    return q[0]
