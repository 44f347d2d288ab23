"""Regularised Coulomb friction: ``mu = mu_d min(|v| / v_reg, 1)``.

Coulomb with a linear (viscous) ramp below ``v_reg`` so that the force is
continuous through zero slip (docs/model.md#friction).
"""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D

NAME = "coulomb"
PARAMS = ("v_reg_m_per_s",)
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    return p[I_MU_D] * min(speed / p[o], 1.0)


def slip_scale_m_per_s(q):
    """The ramp's width."""
    return q[0]
