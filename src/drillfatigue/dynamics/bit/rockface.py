"""The rock face under the bit: a lobed bottom-hole profile, rock contact, depth of cut.

Lobed face
    The bottom of the hole carries the pattern the bit cut into it: a face
    height ``h(phi) = A sin(n phi)`` under the bit at its angle ``phi`` relative
    to the rock (``n`` lobes per revolution, 3 for the tricone pattern, peak
    to peak ``2 A``; docs/model.md#bit). The bit presses on it through a
    penalty spring and dash-pot that never pulls, so the bit can leave bottom
    and come back (bit bounce) instead of being guided kinematically. A bit
    pressed by a constant force ``F`` with an effective mass ``m`` follows the
    face while ``m A (n Omega)^2 <= F`` (the face's largest downward
    acceleration stays below ``F / m``) and leaves it above.

Rock advance
    The rock face advances only by what the bit cuts: ``d(md_rock)/dt = ROP``,
    with ROP from the bit law, 0 off bottom. Two laws: the Yigit-Christoforou
    torque with the Sarker et al. ROP and thresholds of
    :mod:`drillfatigue.dynamics.bit.laws` (:func:`rop_tob_from_wob`), and the
    depth-of-cut law of Detournay & Defourny (Int. J. Rock Mech. Min. Sci. 29
    (1992) 13) for a PDC bit
    (:func:`drillfatigue.dynamics.bit.laws.detournay_law`):

        W = W_c + W_f,  T = T_c + T_f,
        W_c = zeta eps a d,  T_c = eps a^2 d / 2      (cutting, proportional to the depth of cut d per rev)
        W_f = min(W, sigma a l),  T_f = mu gamma a W_f / 2   (friction on the wear flats)

    with ``a`` the bit radius, ``eps`` the intrinsic specific energy, ``zeta``
    the ratio of normal to tangential cutting force, ``sigma`` the contact
    strength and ``l`` the total wear-flat length, ``mu gamma`` the bit's
    friction and geometry numbers. Below ``W_f* = sigma a l`` the wear flats
    carry the weight and nothing is cut; above it
    ``d = (W - W_f*) / (zeta eps a)`` and ``ROP = d Omega / (2 pi)``. In the
    specific energy ``E = 2 T / (a^2 d)`` and drilling strength ``S = W / (a d)``
    every cutting point lies on the friction line
    ``E = (1 - mu gamma zeta) eps + mu gamma S`` (their eq. for phase II).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from drillfatigue.dynamics.bit.laws.kernel import bit_response
from drillfatigue.dynamics.bit.laws.registry import LAWS, pack_bit_params
from drillfatigue.units import rad_per_s_from_rpm

if TYPE_CHECKING:
    from drillfatigue.config.bit import BitConfig

#: bit laws whose ROP follows from the WOB (the rig's bit cuts what the weight lets it)
ROP_FROM_WOB_MODELS = tuple(law.NAME for law in LAWS if not law.ROP_PRESCRIBED)


@njit(cache=True)
def rock_face_height(phi_rad, amplitude_m, lobes):
    """Height of the lobed face at bit angle ``phi``: ``A sin(n phi)`` (m, towards the bit)."""
    return amplitude_m * math.sin(lobes * phi_rad)


@njit(cache=True)
def rock_face_contact(u_m, u_dot_m_per_s, phi_rad, omega_rad_s, amplitude_m, lobes, k_N_per_m,
                      c_N_s_per_m, out):
    """Rock contact force on the bit from the lobed face (penalty spring and dash-pot).

    Parameters
    ----------
    u_m, u_dot_m_per_s : float
        Bit face position beyond the mean rock face along the hole axis (m,
        > 0 into the rock) and its rate (m/s).
    phi_rad, omega_rad_s : float
        Bit angle relative to the rock (rad) and its rate (rad/s).
    amplitude_m, lobes : float
        Face profile ``A sin(n phi)``.
    k_N_per_m, c_N_s_per_m : float
        Contact stiffness and damping.
    out : ndarray, shape (2,)
        Written: ``[wob_N, penetration_m]``; WOB >= 0 (the face never pulls),
        0 off bottom (penetration <= 0).

    Returns
    -------
    int
        1 on bottom, 0 off bottom.
    """
    h = amplitude_m * math.sin(lobes * phi_rad)
    hdot = amplitude_m * lobes * math.cos(lobes * phi_rad) * omega_rad_s
    d = u_m - h
    out[1] = d
    if d <= 0.0:
        out[0] = 0.0
        return 0
    f = k_N_per_m * d + c_N_s_per_m * (u_dot_m_per_s - hdot)
    out[0] = f if f > 0.0 else 0.0
    return 1


def rop_tob_from_wob(bit: BitConfig, wob_N: float | np.ndarray, rpm: float | np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
    """ROP (m/s) and TOB (N m) of the configured bit law at given WOB (N) and bit speed (rpm).

    The bit cuts what the weight lets it: with ``model = yigit_christoforou``
    this is ``ROP = c1 WOB sqrt(Omega) + c2`` above the Sarker thresholds
    (:mod:`drillfatigue.dynamics.bit.laws`), 0 below them and off bottom; with
    ``detournay`` the depth of cut of the Detournay-Defourny law times the
    revolutions per second; with ``prescribed_rop``/``given_tob`` the rate is
    not a function of WOB and the call is refused.
    """
    if bit.model not in ROP_FROM_WOB_MODELS:
        raise ValueError(f"bit.model {bit.model} prescribes the ROP; the ROP from WOB needs "
                         f"bit.model {' or '.join(ROP_FROM_WOB_MODELS)}")
    mid, p = pack_bit_params(bit, 0.0)
    w, r = np.broadcast_arrays(np.asarray(wob_N, float), np.asarray(rpm, float))
    rop = np.empty(w.shape)
    tob = np.empty(w.shape)
    out = np.empty(2)
    for i in np.ndindex(w.shape):
        bit_response(mid, p, float(w[i]), rad_per_s_from_rpm(float(r[i])), out)
        tob[i] = out[0]
        rop[i] = out[1]
    return rop, tob


def rop_slope_m_per_N_s(bit: BitConfig, wob_N: float, rpm: float, rel_step: float = 1e-3) -> float:
    """``dROP/dWOB`` of the bit law at an operating point (central difference), m/(N s).

    The linearised bit law the autodriller stability check and the step-response
    reference use.
    """
    h = max(abs(wob_N) * rel_step, 1.0)
    hi, _ = rop_tob_from_wob(bit, wob_N + h, rpm)
    lo, _ = rop_tob_from_wob(bit, wob_N - h, rpm)
    return float((hi - lo) / (2.0 * h))


def steady_wob_for_rop_N(bit: BitConfig, rop_m_per_s: float, rpm: float, wob_max_N: float
                         ) -> tuple[float, float, float]:
    """The WOB at which the configured bit law cuts ``rop_m_per_s`` at ``rpm`` (steady drilling).

    The inverse of :func:`rop_tob_from_wob` in WOB, in closed form where the law has
    one (Yigit-Christoforou above the Sarker thresholds and their fade-in band:
    ``WOB = (ROP - c2) / (c1 sqrt(Omega))``; Detournay above the wear-flat load:
    ``WOB = sigma a l + 2 pi zeta eps a ROP / Omega``), otherwise by bisection of the
    law's ROP, which does not decrease with WOB, on ``[0, wob_max_N]``.

    Returns
    -------
    (wob_N, rop_min_m_per_s, rop_max_m_per_s)
        ``wob_N`` is NaN where no WOB up to ``wob_max_N`` gives the set-point; the
        reachable range is the law's smallest positive ROP above its threshold and
        its ROP at ``wob_max_N``.
    """
    if bit.model not in ROP_FROM_WOB_MODELS:
        raise ValueError(f"bit.model {bit.model} prescribes the ROP; the steady WOB needs "
                         f"bit.model {' or '.join(ROP_FROM_WOB_MODELS)}")
    omega = rad_per_s_from_rpm(abs(rpm))

    def rop_at(w: float) -> float:
        return float(rop_tob_from_wob(bit, w, abs(rpm))[0])

    rop_max = rop_at(wob_max_N)
    # the smallest positive ROP: at the WOB threshold (sharp switch) or just above
    # the point where the law starts cutting
    lo, hi = 0.0, wob_max_N
    if rop_max > 0.0:
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if rop_at(mid) > 0.0:
                hi = mid
            else:
                lo = mid
        rop_min = rop_at(hi)
    else:
        rop_min = 0.0
    if not (rop_max > 0.0 and rop_min <= rop_m_per_s <= rop_max):
        return math.nan, rop_min, rop_max
    if bit.model == "detournay":
        a = bit.bit_radius_m
        wob = (bit.detournay_sigma_Pa * a * bit.detournay_wear_flat_m
               + 2.0 * math.pi * bit.detournay_zeta * bit.detournay_eps_Pa * a * rop_m_per_s / omega)
        return wob, rop_min, rop_max
    band = 1.0 + bit.threshold_band
    wob = (rop_m_per_s - bit.rop_c2_m_per_s) / (bit.rop_c1_m_per_N_sqrt_s * math.sqrt(omega))
    if wob >= bit.wob_threshold_N * band and omega >= bit.omega_threshold_rad_s * band:
        return wob, rop_min, rop_max
    # in the thresholds' fade-in band: the law's ROP is monotone in WOB there
    lo, hi = 0.0, wob_max_N
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if rop_at(mid) < rop_m_per_s:
            lo = mid
        else:
            hi = mid
    return hi, rop_min, rop_max
