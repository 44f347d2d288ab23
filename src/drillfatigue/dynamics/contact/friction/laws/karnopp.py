"""Karnopp stiction (ASME J. Dyn. Sys. Meas. Control 107 (1985) 100-103).

Outside the band ``|v| >= Dv``: ``mu = mu_d``. Inside: true stiction, the
friction cancels the other tangential forces ``f_other`` on the body up to
``mu_s N`` (:func:`drillfatigue.dynamics.contact.friction.kernel.friction_force`):
``F = -f_other - mu_s N v / Dv`` (the second term drags the residual slip of
an explicit integrator back to zero), clipped to ``|F| <= mu_s N``; a force
that would push along the slip loses that component, so friction never adds
energy. Needs the net applied tangential force (the contact kernel's pre-pass),
and limits the step: a slip overshoot in one step must land inside the band
(:func:`drillfatigue.dynamics.step.pack.stable_step`).
"""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, I_MU_S

NAME = "karnopp"
PARAMS = ("karnopp_dv_m_per_s",)
STICTION = True


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    """The sliding value outside the band (``mu_d``), ``mu_s`` (the stiction cap) inside."""
    if speed < p[o]:
        return p[I_MU_S]
    return p[I_MU_D]


@njit(cache=True, inline="always")
def band(p, o):
    """The stick band's half-width Dv, m/s."""
    return p[o]


def slip_scale_m_per_s(q):
    """The band's half-width."""
    return q[0]
