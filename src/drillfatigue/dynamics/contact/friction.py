"""Wall friction: seven switchable models behind one kernel signature.

All models return the tangential friction force on the string at a contact
point, given the tangential slip velocity ``v`` (3D, the caller removes the
normal component) and the normal force magnitude ``N``. Except Karnopp inside
its stick band, the force is anti-parallel to the slip,
``F = -N mu(|v|) v/|v|``, with the coefficient shapes (docs/model.md#friction):

``COULOMB`` (regularised)
    ``mu = mu_d min(|v|/v_reg, 1)``: Coulomb with a linear (viscous) ramp
    below ``v_reg`` so the force is continuous through zero slip.
``BENSON_HALLQUIST``
    ``mu = [mu_d + (mu_s - mu_d) exp(-|v|/v_c)] min(|v|/v_reg, 1)``
    (Benson & Hallquist, the LS-DYNA exponential decay; same ramp as Coulomb).
``KARNOPP``
    Karnopp (ASME J. Dyn. Sys. Meas. Control 107 (1985) 100-103). Outside the
    band ``|v| >= Dv``: ``mu = mu_d``. Inside: true stiction, the friction
    cancels the other tangential forces ``f_other`` on the body up to
    ``mu_s N``: ``F = -f_other - mu_s N v/Dv`` (the second term drags the
    residual slip of an explicit integrator back to zero), clipped to
    ``|F| <= mu_s N``; if that force would push along the slip (``F.v > 0``,
    ``f_other`` already braking the body) its component along ``v`` is
    dropped, so friction never adds energy. Needs the net applied tangential
    force, which is what makes it awkward with many contacts.
``TANH`` (Mostaghel & Davis, Earthquake Eng. Struct. Dyn. 26 (1997) 541-548)
    ``mu = mu_d tanh(|v|/v_t)``.
``VELOCITY_TRIG`` (velocity-based trigonometric, after Wang & Rui; their exact
    form is not available, this is a documented plausible one with the fitted
    constants configurable)
    ``mu = mu_s sin(pi/2 |v|/v_p)`` for ``|v| <= v_p`` (quarter-sine rise to
    the static peak), ``mu = mu_d + (mu_s - mu_d)(1 + cos(pi(|v| - v_p)/v_w))/2``
    for ``v_p < |v| < v_p + v_w`` (half-cosine Stribeck decay), ``mu_d`` beyond.
    C1-continuous at the peak and at the end of the decay.
``TANH_EXP`` (the paper's hybrid tanh-exponential, plausible form, docs/model.md#friction)
    ``mu = tanh(|v|/v_t) [mu_d + (mu_s - mu_d) exp(-|v|/v_s)]``, ``v_t << v_s``.
``STICK_BAND`` (Coulomb friction with a stated stick band: the distributed inclusion of
    Aarsnes & Shor, J. Petrol. Sci. Eng. 163 (2018) 712-721, eq. 4, a Karnopp-style law)
    ``mu = mu_s min(|v|/v_reg, 1)`` inside the band ``|v| < Dv``, ``mu_d`` outside. Inside
    the band the wall holds a point with up to ``mu_s N``; what holds it still is the
    contact kernel's slip cap (:func:`drillfatigue.dynamics.contact.wall.wall_contact`: the
    force that stops the slip within a step, never more), so no estimate of the other
    forces is needed and the band may be wide (Aarsnes & Shor fit 0.5-2 rad/s of the
    pipe's speed, tens of mm/s at its surface). The band is where a slowing string
    sticks again; with ``mu_d`` flat outside it, the band's width sets how much of a
    stick-slip cycle the string spends stuck (docs/rig.md#off-bottom-stick-slip-and-the-stick-band).

Invariants (tested): ``F.v <= 0``; ``|F| <= mu_s N`` to round-off (every
shape is bounded by mu_s; ``STICK_BAND`` reaches it); odd in ``v`` (jointly with
``f_other`` for Karnopp); ``|F| -> mu_d N`` at high slip.
``KARNOPP`` and ``STICK_BAND`` read their band from ``p[I_DV]`` (packed from
``karnopp_dv_m_per_s`` or ``stick_band_m_per_s`` by the model chosen).

Axial (drag) coefficient. :func:`friction_force_split` computes the force of
the chosen model from the full 3D slip (so rotation reduces axial drag, as it
does in the field) and then scales its component along the string axis by
``mu_axial / mu_d`` (an anisotropic friction ellipse). Scaling a component of
a force anti-parallel to ``v`` keeps ``F.v <= 0``; ``|F|`` is then bounded by
``max(1, mu_axial/mu_d) mu_s N``.

Parameter vector ``p`` (float64, length ``N_PARAMS``), built by
:func:`pack_friction_params`: indices ``I_MU_S, I_MU_D, I_AX_RATIO, I_V_REG,
I_V_C, I_DV, I_V_T, I_V_S, I_TRIG_PEAK, I_TRIG_DECAY``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from drillfatigue.dynamics.core.status import OK, UNKNOWN_FRICTION

if TYPE_CHECKING:  # pydantic stays out of the kernel module at run time
    from drillfatigue.config.friction import FrictionConfig

COULOMB = 0
BENSON_HALLQUIST = 1
KARNOPP = 2
TANH = 3
VELOCITY_TRIG = 4
TANH_EXP = 5
STICK_BAND = 6

MODEL_IDS: dict[str, int] = {
    "coulomb": COULOMB,
    "benson_hallquist": BENSON_HALLQUIST,
    "karnopp": KARNOPP,
    "tanh": TANH,
    "velocity_trig": VELOCITY_TRIG,
    "tanh_exp": TANH_EXP,
    "stick_band": STICK_BAND,
}

I_MU_S = 0
I_MU_D = 1
I_AX_RATIO = 2
I_V_REG = 3
I_V_C = 4
I_DV = 5
I_V_T = 6
I_V_S = 7
I_TRIG_PEAK = 8
I_TRIG_DECAY = 9
N_PARAMS = 10


@njit(cache=True, inline="always")
def _tanh(x):
    """tanh, skipping the libm call where it is 1.0 in float64 (x >= 19.1)."""
    if x >= 19.1:
        return 1.0
    return math.tanh(x)


@njit(cache=True, inline="always")
def slip_coefficient(model, p, speed):
    """Friction coefficient ``mu(|v|)`` of a sliding model at slip speed ``speed`` (m/s).

    For ``KARNOPP`` this is the sliding value outside the band (``mu_d``) and
    ``mu_s`` inside it (the stiction cap); ``STICK_BAND`` the same with the
    Coulomb ramp below ``v_reg``. Returns a float in [0, mu_s].
    """
    mu_s = p[I_MU_S]
    mu_d = p[I_MU_D]
    if model == COULOMB:
        return mu_d * min(speed / p[I_V_REG], 1.0)
    if model == BENSON_HALLQUIST:
        return (mu_d + (mu_s - mu_d) * math.exp(-speed / p[I_V_C])) * min(speed / p[I_V_REG], 1.0)
    if model == KARNOPP:
        if speed < p[I_DV]:
            return mu_s
        return mu_d
    if model == TANH:
        return mu_d * _tanh(speed / p[I_V_T])
    if model == VELOCITY_TRIG:
        vp = p[I_TRIG_PEAK]
        vw = p[I_TRIG_DECAY]
        if speed <= vp:
            return mu_s * math.sin(0.5 * math.pi * speed / vp)
        if speed < vp + vw:
            return mu_d + (mu_s - mu_d) * 0.5 * (1.0 + math.cos(math.pi * (speed - vp) / vw))
        return mu_d
    if model == TANH_EXP:
        return _tanh(speed / p[I_V_T]) * (mu_d + (mu_s - mu_d) * math.exp(-speed / p[I_V_S]))
    if model == STICK_BAND:
        if speed < p[I_DV]:
            return mu_s * min(speed / p[I_V_REG], 1.0)
        return mu_d
    return -1.0  # unknown model: caller checks


@njit(cache=True, inline="always")
def friction_force(model, p, v_slip, N, f_other, dt, out):
    """Tangential wall-friction force on the string at one contact point.

    Parameters
    ----------
    model : int
        One of ``COULOMB, BENSON_HALLQUIST, KARNOPP, TANH, VELOCITY_TRIG, TANH_EXP,
        STICK_BAND``.
    p : ndarray, shape (N_PARAMS,)
        Parameters from :func:`pack_friction_params`.
    v_slip : ndarray, shape (3,)
        Tangential slip velocity of the string relative to the wall, m/s
        (contact-point velocity with its normal component removed).
    N : float
        Normal force magnitude, N (<= 0 gives zero friction).
    f_other : ndarray, shape (3,)
        Net other tangential force on the body at this point, N (used by
        Karnopp only; pass zeros otherwise).
    dt : float
        Integrator step, s. Reserved: no model uses it at present (the Karnopp
        band is a velocity band), kept so step-aware variants need no
        signature change.
    out : ndarray, shape (3,)
        Written: friction force on the string, N.

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``, or
        ``UNKNOWN_FRICTION`` for an unknown model id (``out`` is zeroed).

    References
    ----------
    docs/model.md#friction and the module docstring.
    """
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    if model < 0 or model > STICK_BAND:
        return UNKNOWN_FRICTION
    if N <= 0.0:
        return OK
    vx = v_slip[0]
    vy = v_slip[1]
    vz = v_slip[2]
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    if model == KARNOPP and speed < p[I_DV]:
        cap = p[I_MU_S] * N
        k = cap / p[I_DV]
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


def pack_friction_params(cfg: FrictionConfig) -> tuple[int, np.ndarray]:
    """Model id and parameter vector for the kernels from a validated ``FrictionConfig``.

    Returns
    -------
    model_id : int
    p : ndarray, shape (N_PARAMS,), float64
    """
    p = np.zeros(N_PARAMS)
    p[I_MU_S] = cfg.mu_static
    p[I_MU_D] = cfg.mu_dynamic
    mu_ax = cfg.mu_dynamic if cfg.mu_axial is None else cfg.mu_axial
    if cfg.mu_dynamic > 0.0:
        p[I_AX_RATIO] = mu_ax / cfg.mu_dynamic
    else:  # no sliding friction at all: nothing to scale
        p[I_AX_RATIO] = 1.0
    p[I_V_REG] = cfg.v_reg_m_per_s
    p[I_V_C] = cfg.v_c_m_per_s
    p[I_DV] = cfg.stick_band_m_per_s if cfg.model == "stick_band" else cfg.karnopp_dv_m_per_s
    p[I_V_T] = cfg.v_t_m_per_s
    p[I_V_S] = cfg.v_s_m_per_s
    p[I_TRIG_PEAK] = cfg.trig_v_peak_m_per_s
    p[I_TRIG_DECAY] = cfg.trig_v_decay_m_per_s
    return MODEL_IDS[cfg.model], p
