"""Yigit-Christoforou torque on bit with the Sarker, Rideout and Butt rate of penetration.

Torque on bit after Yigit & Christoforou (J. Sound Vib. 1998/2000; the
standard form, docs/model.md#bit)::

    TOB = WOB r_b mu_b(Omega),   mu_b = mu0 [tanh(b1 Omega) + b2 Omega / (1 + b3 Omega^2)]

with the public parameter set b0 = r_b mu0 = 0.0239 m, b1 = 1.91, b2 = 8.5,
b3 = 5.47 (Omega in rad/s). Which constant is which follows from the shape:
b0 carries the length unit (it multiplies WOB to give N m), b1 is the rate of
the tanh (s/rad; the tanh term, the bit's Coulomb-like friction, saturates at
Omega ~ 1/b1 = 0.5 rad/s), and b2 (s/rad), b3 (s^2/rad^2) shape the rational
term, which peaks at Omega = 1/sqrt(b3) = 0.43 rad/s (4 rpm) at
b2/(2 sqrt(b3)) = 1.82 and then decays as b2/(b3 Omega). The sum rises from 0
at Omega = 0 to a peak mu_b ~ 2.5 mu0 near 0.45 rad/s and then falls towards
mu0: the velocity weakening that drives torsional stick-slip. TOB is odd in
Omega.

ROP after Sarker, Rideout & Butt (J. Petrol. Sci. Eng. 2012)::

    ROP = c1 WOB sqrt(Omega) + c2     (clipped at 0)

with thresholds: no penetration below a threshold WOB or bit speed, where the
torque is the friction term ``WOB b0 tanh(b1 Omega)`` only. Here the cutting
part (the rational term of TOB and the ROP) is multiplied by a factor
f = S(WOB) S(Omega) that rises from 0 at the threshold to 1 at
threshold (1 + band) by a smoothstep S (band = 0: the sharp switch), so the
law is continuous for the integrator. Backward rotation (Omega <= 0) cuts
nothing.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from numba import njit

from drillfatigue.dynamics.bit.laws.base import fade_in, fade_in_slope

if TYPE_CHECKING:
    from drillfatigue.config.bit import BitConfig

NAME = "yigit_christoforou"
ALIASES: tuple[str, ...] = ()
PARAMS = ("b0_m", "b1_s_per_rad", "b2_s_per_rad", "b3_s2_per_rad2", "c1_m_per_N_sqrt_s",
          "c2_m_per_s", "wob_threshold_N", "omega_threshold_rad_s", "threshold_band")
#: The ROP is the operation's, not the law's (the bit is guided kinematically).
ROP_PRESCRIBED = False

I_B0 = 0  # r_b mu0, m
I_B1 = 1  # s/rad
I_B2 = 2  # s/rad
I_B3 = 3  # s^2/rad^2
I_C1 = 4  # m / (N sqrt(s))
I_C2 = 5  # m/s
I_WOB_TH = 6  # N
I_OMEGA_TH = 7  # rad/s
I_BAND = 8  # relative fade-in width


def pack(cfg: BitConfig, rop_m_per_s: float) -> list[float]:
    return [cfg.bit_radius_m * cfg.mu0, cfg.tob_b1_s_per_rad, cfg.tob_b2_s_per_rad,
            cfg.tob_b3_s2_per_rad2, cfg.rop_c1_m_per_N_sqrt_s, cfg.rop_c2_m_per_s,
            cfg.wob_threshold_N, cfg.omega_threshold_rad_s, cfg.threshold_band]


@njit(cache=True, inline="always")
def torque(p, o, wob_N, om):
    """TOB (N m) and the cutting factor f at WOB ``wob_N`` > 0 and bit speed ``om``."""
    f = (fade_in(wob_N, p[o + I_WOB_TH], p[o + I_BAND])
         * fade_in(om, p[o + I_OMEGA_TH], p[o + I_BAND]))
    tob = wob_N * p[o + I_B0] * (math.tanh(p[o + I_B1] * om)
                                 + f * p[o + I_B2] * om / (1.0 + p[o + I_B3] * om * om))
    return tob, f


@njit(cache=True, inline="always")
def response(p, o, wob_N, om, out):
    """``out = [TOB, ROP]`` at WOB ``wob_N`` > 0 (``out`` zeroed by the caller)."""
    tob, f = torque(p, o, wob_N, om)
    out[0] = tob
    if f > 0.0:
        rop = p[o + I_C1] * wob_N * math.sqrt(om) + p[o + I_C2]
        out[1] = f * rop if rop > 0.0 else 0.0


@njit(cache=True, inline="always")
def torque_slope(p, o, wob_N, om):
    """``d TOB / d Omega`` at fixed WOB > 0, N m s/rad."""
    b1 = p[o + I_B1]
    b2 = p[o + I_B2]
    b3 = p[o + I_B3]
    fw = fade_in(wob_N, p[o + I_WOB_TH], p[o + I_BAND])
    fo = fade_in(om, p[o + I_OMEGA_TH], p[o + I_BAND])
    dfo = fade_in_slope(om, p[o + I_OMEGA_TH], p[o + I_BAND])
    th = math.tanh(b1 * om)
    den = 1.0 + b3 * om * om
    rat = b2 * om / den
    drat = b2 * (1.0 - b3 * om * om) / (den * den)
    return wob_N * p[o + I_B0] * (b1 * (1.0 - th * th) + fw * (fo * drat + dfo * rat))


def rop_bound_m_per_s(cfg: BitConfig, wob_N: float, omega_rad_s: float) -> float | None:
    """Largest ROP (m/s) the law gives at WOB ``wob_N`` and bit speed ``omega_rad_s``:
    the Sarker law without its thresholds (the growth allowance of a run)."""
    return (cfg.rop_c1_m_per_N_sqrt_s * wob_N * math.sqrt(omega_rad_s)
            + max(cfg.rop_c2_m_per_s, 0.0))
