"""Bit-rock interaction: torque on bit and rate of penetration.

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
nothing. WOB <= 0 is bit bounce: the bit is off bottom, TOB = ROP = 0.

``PRESCRIBED_ROP``: the same TOB, ROP = the given value (the bit is guided
kinematically), 0 during bit bounce.

``DETOURNAY``: the depth-of-cut law of a PDC bit after Detournay & Defourny
(Int. J. Rock Mech. Min. Sci. 29 (1992) 13; the bit-level form of Richard,
Germay & Detournay, J. Sound Vib. 305 (2007) 432), cutting plus frictional
contact on the wear flats::

    W = W_c + W_f,   W_c = zeta eps a d,   W_f = min(W, sigma a l)
    T = T_c + T_f,   T_c = eps a^2 d / 2,  T_f = mu gamma a W_f / 2
    d = (W - sigma a l) / (zeta eps a)  (0 below W_f* = sigma a l),  ROP = d Omega / (2 pi)

with ``a`` the bit radius, ``eps`` the intrinsic specific energy, ``zeta`` the
ratio of normal to tangential cutting force, ``sigma`` the contact strength,
``l`` the total wear-flat length and ``mu gamma`` the bit's friction times
geometry number; ``d`` is the depth of cut per revolution. The bit cuts only
turning forward; backwards only the wear-flat friction acts. The torque is
multiplied by ``tanh(Omega / omega_reg)`` so that it passes continuously
through zero speed (a regularised stick; at drilling speeds the factor is 1
to round-off: 1 - 1e-27 at 150 rpm with the default 0.5 rad/s).
:func:`detournay_law` is the law without the regularisation.

Parameter vector ``p`` (float64, length ``N_PARAMS``) from
:func:`pack_bit_params`: indices ``I_B0 .. I_ROP``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from drillfatigue.dynamics.core.status import OK, UNKNOWN_BIT

if TYPE_CHECKING:  # pydantic stays out of the kernel module at run time
    from drillfatigue.config.bit import BitConfig

YIGIT_CHRISTOFOROU = 0
PRESCRIBED_ROP = 1
DETOURNAY = 2

#: ``given_tob`` (the simulator's given-torque mode) maps to the prescribed-ROP law
#: wherever a law is still needed (e.g. the soft-string TOB estimate).
MODEL_IDS: dict[str, int] = {"yigit_christoforou": YIGIT_CHRISTOFOROU, "prescribed_rop": PRESCRIBED_ROP,
                             "given_tob": PRESCRIBED_ROP, "detournay": DETOURNAY}

I_B0 = 0  # r_b mu0, m
I_B1 = 1  # s/rad
I_B2 = 2  # s/rad
I_B3 = 3  # s^2/rad^2
I_C1 = 4  # m / (N sqrt(s))
I_C2 = 5  # m/s
I_WOB_TH = 6  # N
I_OMEGA_TH = 7  # rad/s
I_BAND = 8  # relative fade-in width
I_ROP = 9  # prescribed ROP, m/s
N_PARAMS = 10

# DETOURNAY uses the first seven entries of the same vector with its own meaning
I_DA = 0  # bit radius a, m
I_DEPS = 1  # intrinsic specific energy eps, Pa
I_DZETA = 2  # normal / tangential cutting force zeta
I_DSIGMA = 3  # wear-flat contact strength sigma, Pa
I_DL = 4  # total wear-flat length l, m
I_DMUGAMMA = 5  # mu gamma
I_DWREG = 6  # torque regularisation speed, rad/s


@njit(cache=True)
def _fade_in(x, th, band):
    """0 below th, smoothstep to 1 at th (1 + band); a sharp step if band or th is 0."""
    if x < th or x <= 0.0:
        return 0.0
    w = band * th
    if w <= 0.0 or x >= th + w:
        return 1.0
    t = (x - th) / w
    return t * t * (3.0 - 2.0 * t)


@njit(cache=True)
def detournay_law(a, eps, zeta, sigma, wear_flat, mu_gamma, wob_N, omega_rad_s, out):
    """Detournay-Defourny PDC bit law (module docstring), unregularised.

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
def _detournay_response(p, wob_N, om, out):
    """DETOURNAY in :func:`bit_response`: the law at ``|om|``, torque times tanh(om / w_reg)."""
    o3 = np.zeros(3)
    detournay_law(p[I_DA], p[I_DEPS], p[I_DZETA], p[I_DSIGMA], p[I_DL], p[I_DMUGAMMA],
                  wob_N, abs(om), o3)
    reg = math.tanh(om / p[I_DWREG]) if p[I_DWREG] > 0.0 else (1.0 if om > 0.0 else -1.0)
    if om > 0.0:
        out[0] = o3[0] * reg
        out[1] = o3[1]
    elif om < 0.0:
        # backwards: no cutting, the wear flats' friction only
        wf = min(wob_N, p[I_DSIGMA] * p[I_DA] * p[I_DL])
        out[0] = 0.5 * p[I_DMUGAMMA] * p[I_DA] * wf * reg


@njit(cache=True)
def bit_response(model, p, wob_N, omega_bit_rad_s, out):
    """Torque on bit and rate of penetration.

    Parameters
    ----------
    model : int
        ``YIGIT_CHRISTOFOROU``, ``PRESCRIBED_ROP`` or ``DETOURNAY``.
    p : ndarray, shape (N_PARAMS,)
        From :func:`pack_bit_params`.
    wob_N : float
        Weight on bit (axial contact force of the rock on the bit), N; <= 0 is
        bit bounce (off bottom).
    omega_bit_rad_s : float
        Bit rotary speed about its axis, rad/s (positive: drilling direction).
    out : ndarray, shape (2,)
        Written: ``[tob_Nm, rop_m_per_s]``; TOB resists rotation (its sign is
        that of Omega; apply it as ``-tob`` about the bit axis).

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``, or
        ``UNKNOWN_BIT`` for an unknown model id (``out`` zeroed).

    References
    ----------
    Yigit & Christoforou (1998, 2000); Sarker, Rideout & Butt (2012); docs/model.md#bit.
    """
    out[0] = 0.0
    out[1] = 0.0
    if model != YIGIT_CHRISTOFOROU and model != PRESCRIBED_ROP and model != DETOURNAY:
        return UNKNOWN_BIT
    if wob_N <= 0.0:
        return OK
    if model == DETOURNAY:
        _detournay_response(p, wob_N, omega_bit_rad_s, out)
        return OK
    om = omega_bit_rad_s
    f = _fade_in(wob_N, p[I_WOB_TH], p[I_BAND]) * _fade_in(om, p[I_OMEGA_TH], p[I_BAND])
    out[0] = wob_N * p[I_B0] * (math.tanh(p[I_B1] * om) + f * p[I_B2] * om / (1.0 + p[I_B3] * om * om))
    if model == PRESCRIBED_ROP:
        out[1] = p[I_ROP]
    elif f > 0.0:
        rop = p[I_C1] * wob_N * math.sqrt(om) + p[I_C2]
        out[1] = f * rop if rop > 0.0 else 0.0
    return OK


@njit(cache=True)
def _fade_in_slope(x, th, band):
    """Derivative of :func:`_fade_in` with respect to ``x`` (0 outside the band)."""
    if x < th or x <= 0.0:
        return 0.0
    w = band * th
    if w <= 0.0 or x >= th + w:
        return 0.0
    t = (x - th) / w
    return 6.0 * t * (1.0 - t) / w


@njit(cache=True)
def bit_torque_slope(model, p, wob_N, omega_bit_rad_s):
    """Derivative of the torque on bit with respect to the bit speed at fixed WOB,
    ``d TOB / d Omega`` (N m s/rad), of :func:`bit_response`'s law.

    Positive where the law acts as a damper on the bit's spin (near zero speed: the
    regularised stick, the fade-in of the cutting term above the speed threshold),
    negative where it weakens with speed. 0 off bottom and for an unknown model.
    Used by the linearly implicit bit torque
    (:func:`drillfatigue.dynamics.top.boundaries.implicit_bit_damping`).
    """
    if wob_N <= 0.0:
        return 0.0
    om = omega_bit_rad_s
    if model == DETOURNAY:
        wreg = p[I_DWREG]
        if wreg <= 0.0 or om == 0.0:
            return 0.0
        # the law's torque does not change with the speed at fixed WOB; the regularisation
        # tanh(om / wreg) does
        wf = min(wob_N, p[I_DSIGMA] * p[I_DA] * p[I_DL])
        tf = 0.5 * p[I_DMUGAMMA] * p[I_DA] * wf
        if om > 0.0:
            tq = 0.5 * p[I_DEPS] * p[I_DA] * p[I_DA] * (wob_N - wf) / (p[I_DZETA] * p[I_DEPS] * p[I_DA]) + tf
        else:
            tq = tf
        th = math.tanh(om / wreg)
        return tq * (1.0 - th * th) / wreg
    if model != YIGIT_CHRISTOFOROU and model != PRESCRIBED_ROP:
        return 0.0
    b1 = p[I_B1]
    b2 = p[I_B2]
    b3 = p[I_B3]
    fw = _fade_in(wob_N, p[I_WOB_TH], p[I_BAND])
    fo = _fade_in(om, p[I_OMEGA_TH], p[I_BAND])
    dfo = _fade_in_slope(om, p[I_OMEGA_TH], p[I_BAND])
    th = math.tanh(b1 * om)
    den = 1.0 + b3 * om * om
    rat = b2 * om / den
    drat = b2 * (1.0 - b3 * om * om) / (den * den)
    return wob_N * p[I_B0] * (b1 * (1.0 - th * th) + fw * (fo * drat + dfo * rat))


def pack_bit_params(cfg: BitConfig, rop_m_per_s: float = 0.0) -> tuple[int, np.ndarray]:
    """Model id and parameter vector from a validated ``BitConfig``.

    Parameters
    ----------
    cfg : BitConfig
    rop_m_per_s : float
        Prescribed ROP (``operation.rop_m_per_s``), used by ``prescribed_rop``.

    Returns
    -------
    model_id : int
    p : ndarray, shape (N_PARAMS,), float64
    """
    p = np.zeros(N_PARAMS)
    if cfg.model == "detournay":
        p[I_DA] = cfg.bit_radius_m
        p[I_DEPS] = cfg.detournay_eps_Pa
        p[I_DZETA] = cfg.detournay_zeta
        p[I_DSIGMA] = cfg.detournay_sigma_Pa
        p[I_DL] = cfg.detournay_wear_flat_m
        p[I_DMUGAMMA] = cfg.detournay_mu_gamma
        p[I_DWREG] = cfg.detournay_omega_reg_rad_s
        return DETOURNAY, p
    p[I_B0] = cfg.bit_radius_m * cfg.mu0
    p[I_B1] = cfg.tob_b1_s_per_rad
    p[I_B2] = cfg.tob_b2_s_per_rad
    p[I_B3] = cfg.tob_b3_s2_per_rad2
    p[I_C1] = cfg.rop_c1_m_per_N_sqrt_s
    p[I_C2] = cfg.rop_c2_m_per_s
    p[I_WOB_TH] = cfg.wob_threshold_N
    p[I_OMEGA_TH] = cfg.omega_threshold_rad_s
    p[I_BAND] = cfg.threshold_band
    p[I_ROP] = float(rop_m_per_s)
    return MODEL_IDS[cfg.model], p
