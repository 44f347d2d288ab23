"""The friction force at one contact point, of whichever registered law the case chose.

All laws give the tangential friction force on the string at a contact point from
the tangential slip velocity ``v`` (3D, the caller removes the normal component)
and the normal force ``N``. Except a stiction law inside its band, the force is
anti-parallel to the slip, ``F = -N mu(|v|) v / |v|``, with ``mu`` the law's
coefficient (:mod:`drillfatigue.dynamics.contact.friction.laws`,
docs/model.md#friction).

Invariants (tested): ``F.v <= 0``; ``|F| <= mu_s N`` to round-off (every shape is
bounded by mu_s); odd in ``v`` (jointly with ``f_other`` for stiction);
``|F| -> mu_d N`` at high slip.

Axial (drag) coefficient: :func:`friction_force_split` computes the force of the
law from the full 3D slip (so rotation reduces axial drag, as it does in the
field), then scales its component along the string axis by ``mu_axial / mu_d``
(an anisotropic friction ellipse). Scaling a component of a force anti-parallel
to ``v`` keeps ``F.v <= 0``; ``|F|`` is then bounded by
``max(1, mu_axial / mu_d) mu_s N``.
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.contact.friction.base import I_AX_RATIO, I_MU_S
from drillfatigue.dynamics.contact.friction.dispatch import (
    N_LAWS, slip_coefficient, stiction_band,
)
from drillfatigue.dynamics.core.status import OK, UNKNOWN_FRICTION


@njit(cache=True, inline="always")
def friction_force(model, p, v_slip, N, f_other, dt, out):
    """Tangential wall-friction force on the string at one contact point.

    Parameters
    ----------
    model : int
        A law id (:data:`drillfatigue.dynamics.contact.friction.registry.MODEL_IDS`).
    p : ndarray, shape (N_PARAMS,)
        Parameters from :func:`~drillfatigue.dynamics.contact.friction.registry.pack_friction_params`.
    v_slip : ndarray, shape (3,)
        Tangential slip velocity of the string relative to the wall, m/s
        (contact-point velocity with its normal component removed).
    N : float
        Normal force magnitude, N (<= 0 gives zero friction).
    f_other : ndarray, shape (3,)
        Net other tangential force on the body at this point, N (read by a
        stiction law only; pass zeros otherwise).
    dt : float
        Integrator step, s. Reserved: no law uses it at present (the Karnopp
        band is a velocity band), kept so step-aware laws need no signature change.
    out : ndarray, shape (3,)
        Written: friction force on the string, N.

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``, or
        ``UNKNOWN_FRICTION`` for an unknown law id (``out`` is zeroed).
    """
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    if model < 0 or model >= N_LAWS:
        return UNKNOWN_FRICTION
    if N <= 0.0:
        return OK
    vx = v_slip[0]
    vy = v_slip[1]
    vz = v_slip[2]
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    band = stiction_band(model, p)
    if speed < band:
        cap = p[I_MU_S] * N
        k = cap / band
        fx = -f_other[0] - k * vx
        fy = -f_other[1] - k * vy
        fz = -f_other[2] - k * vz
        mag = math.sqrt(fx * fx + fy * fy + fz * fz)
        if mag > cap:
            sc = cap / mag
            fx *= sc
            fy *= sc
            fz *= sc
        fv = fx * vx + fy * vy + fz * vz
        if fv > 0.0:  # would push along the slip: drop that component
            # direction from the scaled slip (its squares may underflow)
            s = max(abs(vx), abs(vy), abs(vz))
            ux = vx / s
            uy = vy / s
            uz = vz / s
            inv = (fx * ux + fy * uy + fz * uz) / (ux * ux + uy * uy + uz * uz)
            fx -= inv * ux
            fy -= inv * uy
            fz -= inv * uz
        out[0] = fx
        out[1] = fy
        out[2] = fz
        return OK
    if speed == 0.0:
        return OK
    f = -N * slip_coefficient(model, p, speed) / speed
    out[0] = f * vx
    out[1] = f * vy
    out[2] = f * vz
    return OK


@njit(cache=True, inline="always")
def friction_force_split(model, p, v_slip, axial_dir, N, f_other, dt, out):
    """Friction force with a separate axial (drag) coefficient.

    As :func:`friction_force`, then the component along ``axial_dir`` (unit
    string axis, shape (3,)) is scaled by ``p[I_AX_RATIO] = mu_axial / mu_d``.
    Returns the status of :func:`friction_force`.
    """
    status = friction_force(model, p, v_slip, N, f_other, dt, out)
    r = p[I_AX_RATIO]
    if r != 1.0:
        fa = (out[0] * axial_dir[0] + out[1] * axial_dir[1] + out[2] * axial_dir[2]) * (r - 1.0)
        out[0] += fa * axial_dir[0]
        out[1] += fa * axial_dir[1]
        out[2] += fa * axial_dir[2]
    return status
