"""Coulomb friction with a stated stick band: the distributed inclusion of Aarsnes &
Shor (J. Petrol. Sci. Eng. 163 (2018) 712-721, eq. 4), a Karnopp-style law.

``mu = mu_s min(|v| / v_reg, 1)`` inside the band ``|v| < Dv``, ``mu_d``
outside. Inside the band the wall holds a point with up to ``mu_s N``; what
holds it still is the contact kernel's slip cap
(:func:`drillfatigue.dynamics.contact.wall.wall_contact`: the force that stops
the slip within a step, never more), so no estimate of the other forces is
needed and the band may be wide (Aarsnes & Shor fit 0.5-2 rad/s of the pipe's
speed, tens of mm/s at its surface). With ``mu_d`` flat outside it, the band's
width sets how much of a stick-slip cycle the string spends stuck
(docs/rig.md#off-bottom-stick-slip-and-the-stick-band).
"""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_MU_D, I_MU_S

NAME = "stick_band"
PARAMS = ("stick_band_m_per_s", "v_reg_m_per_s")
STICTION = False


@njit(cache=True, inline="always")
def coefficient(p, o, speed):
    if speed < p[o]:
        return p[I_MU_S] * min(speed / p[o + 1], 1.0)
    return p[I_MU_D]


def slip_scale_m_per_s(q):
    """The ramp's width."""
    return q[1]
