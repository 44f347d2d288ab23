"""Prescribed rate of penetration: the Yigit-Christoforou torque on bit, ROP the given value.

The bit is guided kinematically at ``operation.rop_m_per_s``; 0 during bit bounce.
``given_tob`` (the simulator's given-torque mode) maps to this law wherever a law is
still needed (e.g. the soft-string TOB estimate).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from numba import njit

from drillfatigue.dynamics.bit.laws import yigit_christoforou as yc

if TYPE_CHECKING:
    from drillfatigue.config.bit import BitConfig

NAME = "prescribed_rop"
ALIASES = ("given_tob",)
PARAMS = (*yc.PARAMS, "rop_m_per_s")
ROP_PRESCRIBED = True
I_ROP = len(yc.PARAMS)  # prescribed ROP, m/s


def pack(cfg: BitConfig, rop_m_per_s: float) -> list[float]:
    return [*yc.pack(cfg, rop_m_per_s), float(rop_m_per_s)]


@njit(cache=True, inline="always")
def response(p, o, wob_N, om, out):
    """``out = [TOB, the prescribed ROP]`` at WOB ``wob_N`` > 0."""
    tob, f = yc.torque(p, o, wob_N, om)
    out[0] = tob
    out[1] = p[o + I_ROP]


@njit(cache=True, inline="always")
def torque_slope(p, o, wob_N, om):
    return yc.torque_slope(p, o, wob_N, om)


def rop_bound_m_per_s(cfg: BitConfig, wob_N: float, omega_rad_s: float) -> float | None:
    """None: the ROP is the operation's."""
    return None
