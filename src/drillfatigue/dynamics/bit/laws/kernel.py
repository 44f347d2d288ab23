"""Torque on bit and rate of penetration of whichever registered bit law the case chose."""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.bit.laws.dispatch import N_LAWS, law_response, law_torque_slope
from drillfatigue.dynamics.core.status import OK, UNKNOWN_BIT


@njit(cache=True)
def bit_response(model, p, wob_N, omega_bit_rad_s, out):
    """Torque on bit and rate of penetration.

    Parameters
    ----------
    model : int
        A law id (:data:`drillfatigue.dynamics.bit.laws.registry.MODEL_IDS`).
    p : ndarray, shape (N_PARAMS,)
        From :func:`~drillfatigue.dynamics.bit.laws.registry.pack_bit_params`.
    wob_N : float
        Weight on bit (axial contact force of the rock on the bit), N; <= 0 is
        bit bounce (off bottom): TOB = ROP = 0.
    omega_bit_rad_s : float
        Bit rotary speed about its axis, rad/s (positive: drilling direction).
    out : ndarray, shape (2,)
        Written: ``[tob_Nm, rop_m_per_s]``; TOB resists rotation (its sign is
        that of Omega; apply it as ``-tob`` about the bit axis).

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``, or
        ``UNKNOWN_BIT`` for an unknown law id (``out`` zeroed).
    """
    out[0] = 0.0
    out[1] = 0.0
    if model < 0 or model >= N_LAWS:
        return UNKNOWN_BIT
    if wob_N <= 0.0:
        return OK
    law_response(model, p, wob_N, omega_bit_rad_s, out)
    return OK


@njit(cache=True)
def bit_torque_slope(model, p, wob_N, omega_bit_rad_s):
    """Derivative of the torque on bit with respect to the bit speed at fixed WOB,
    ``d TOB / d Omega`` (N m s/rad), of :func:`bit_response`'s law.

    Positive where the law acts as a damper on the bit's spin (near zero speed: the
    regularised stick, the fade-in of the cutting term above the speed threshold),
    negative where it weakens with speed. 0 off bottom and for an unknown law.
    Used by the linearly implicit bit torque
    (:func:`drillfatigue.dynamics.top.boundaries.implicit_bit_damping`).
    """
    if wob_N <= 0.0:
        return 0.0
    return law_torque_slope(model, p, wob_N, omega_bit_rad_s)
