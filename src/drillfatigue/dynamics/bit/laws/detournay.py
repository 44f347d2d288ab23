"""Detournay-Defourny depth-of-cut law of a PDC bit.

After Detournay & Defourny (Int. J. Rock Mech. Min. Sci. 29 (1992) 13; the
bit-level form of Richard, Germay & Detournay, J. Sound Vib. 305 (2007) 432),
cutting plus frictional contact on the wear flats::

    W = W_c + W_f,   W_c = zeta eps a d,   W_f = min(W, sigma a l)
    T = T_c + T_f,   T_c = eps a^2 d / 2,  T_f = mu gamma a W_f / 2
    d = (W - sigma a l) / (zeta eps a)  (0 below W_f* = sigma a l),  ROP = d Omega / (2 pi)

with ``a`` the bit radius, ``eps`` the intrinsic specific energy, ``zeta`` the
ratio of normal to tangential cutting force, ``sigma`` the contact strength,
``l`` the total wear-flat length and ``mu gamma`` the bit's friction times
geometry number; ``d`` is the depth of cut per revolution. In the specific
energy ``E = 2 T / (a^2 d)`` and drilling strength ``S = W / (a d)`` every
cutting point lies on the friction line ``E = (1 - mu gamma zeta) eps + mu gamma S``.
The bit cuts only turning forward; backwards only the wear-flat friction acts.
The torque is multiplied by ``tanh(Omega / omega_reg)`` so that it passes
continuously through zero speed (a regularised stick; at drilling speeds the
factor is 1 to round-off: 1 - 1e-27 at 150 rpm with the default 0.5 rad/s).
:func:`detournay_law` is the law without the regularisation.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

if TYPE_CHECKING:
    from drillfatigue.config.bit import BitConfig

NAME = "detournay"
ALIASES: tuple[str, ...] = ()
PARAMS = ("a_m", "eps_Pa", "zeta", "sigma_Pa", "wear_flat_m", "mu_gamma", "omega_reg_rad_s")
ROP_PRESCRIBED = False

I_DA = 0  # bit radius a, m
I_DEPS = 1  # intrinsic specific energy eps, Pa
I_DZETA = 2  # normal / tangential cutting force zeta
I_DSIGMA = 3  # wear-flat contact strength sigma, Pa
I_DL = 4  # total wear-flat length l, m
I_DMUGAMMA = 5  # mu gamma
I_DWREG = 6  # torque regularisation speed, rad/s


def pack(cfg: BitConfig, rop_m_per_s: float) -> list[float]:
    return [cfg.bit_radius_m, cfg.detournay_eps_Pa, cfg.detournay_zeta, cfg.detournay_sigma_Pa,
            cfg.detournay_wear_flat_m, cfg.detournay_mu_gamma, cfg.detournay_omega_reg_rad_s]


@njit(cache=True)
def detournay_law(a, eps, zeta, sigma, wear_flat, mu_gamma, wob_N, omega_rad_s, out):
    """The law (module docstring), unregularised.

    Writes ``out[0:3] = [tob_Nm, rop_m_per_s, depth_of_cut_m_per_rev]``: turning forward,
    cutting plus wear-flat friction; at rest 0; backwards only the friction, negative.
    WOB <= 0 (off bottom): all 0.
    """
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    if wob_N <= 0.0:
        return
    wf_max = sigma * a * wear_flat
    wf = wob_N if wob_N < wf_max else wf_max
    tf = 0.5 * mu_gamma * a * wf
    if omega_rad_s <= 0.0:
        out[0] = -tf if omega_rad_s < 0.0 else 0.0
        return
    d = (wob_N - wf) / (zeta * eps * a)
    out[0] = 0.5 * eps * a * a * d + tf
    out[1] = d * omega_rad_s / (2.0 * math.pi)
    out[2] = d


@njit(cache=True)
def response(p, o, wob_N, om, out):
    """``out = [TOB, ROP]`` at WOB ``wob_N`` > 0: the law at ``|om|``, the torque times
    tanh(om / omega_reg)."""
    o3 = np.zeros(3)
    detournay_law(p[o + I_DA], p[o + I_DEPS], p[o + I_DZETA], p[o + I_DSIGMA], p[o + I_DL],
                  p[o + I_DMUGAMMA], wob_N, abs(om), o3)
    wreg = p[o + I_DWREG]
    reg = math.tanh(om / wreg) if wreg > 0.0 else (1.0 if om > 0.0 else -1.0)
    if om > 0.0:
        out[0] = o3[0] * reg
        out[1] = o3[1]
    elif om < 0.0:
        # backwards: no cutting, the wear flats' friction only
        wf = min(wob_N, p[o + I_DSIGMA] * p[o + I_DA] * p[o + I_DL])
        out[0] = 0.5 * p[o + I_DMUGAMMA] * p[o + I_DA] * wf * reg


@njit(cache=True, inline="always")
def torque_slope(p, o, wob_N, om):
    """``d TOB / d Omega`` at fixed WOB > 0: only the regularisation tanh(om / omega_reg)
    changes with the speed."""
    wreg = p[o + I_DWREG]
    if wreg <= 0.0 or om == 0.0:
        return 0.0
    wf = min(wob_N, p[o + I_DSIGMA] * p[o + I_DA] * p[o + I_DL])
    tf = 0.5 * p[o + I_DMUGAMMA] * p[o + I_DA] * wf
    if om > 0.0:
        tq = (0.5 * p[o + I_DEPS] * p[o + I_DA] * p[o + I_DA] * (wob_N - wf)
              / (p[o + I_DZETA] * p[o + I_DEPS] * p[o + I_DA]) + tf)
    else:
        tq = tf
    th = math.tanh(om / wreg)
    return tq * (1.0 - th * th) / wreg


def rop_bound_m_per_s(cfg: BitConfig, wob_N: float, omega_rad_s: float) -> float | None:
    """Largest ROP (m/s) the law gives at WOB ``wob_N`` and bit speed ``omega_rad_s``:
    the depth of cut with the whole WOB cutting (the growth allowance of a run)."""
    return wob_N / (cfg.detournay_zeta * cfg.detournay_eps_Pa
                    * cfg.bit_radius_m) * omega_rad_s / (2.0 * math.pi)
