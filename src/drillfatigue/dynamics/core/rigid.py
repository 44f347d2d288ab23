"""Rigid-body kinematics: unit quaternions and the Newton-Euler update (docs/model.md#bodies).

Quaternions are stored scalar first, q = (w, x, y, z), and rotate body-frame
vectors to the world frame (v_world = R(q) v_body). Orientation has no
singularity in horizontal holes and is renormalised after every drift.
Angular velocity is kept in the body frame; the Euler equations are
I dw/dt + w x (I w) = M_body with the axisymmetric inertia diag(It, It, Ia),
split into a kick by the moments and the exact free rotation of a symmetric top.

All functions are numba kernels on float64 arrays in SI units.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def quat_to_rot(q, out):
    """Rotation matrix of a unit quaternion.

    Parameters
    ----------
    q : ndarray, shape (4,)
        Unit quaternion (w, x, y, z).
    out : ndarray, shape (3, 3)
        Written: R with v_world = R @ v_body.
    """
    w, x, y, z = q[0], q[1], q[2], q[3]
    out[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    out[0, 1] = 2.0 * (x * y - w * z)
    out[0, 2] = 2.0 * (x * z + w * y)
    out[1, 0] = 2.0 * (x * y + w * z)
    out[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    out[1, 2] = 2.0 * (y * z - w * x)
    out[2, 0] = 2.0 * (x * z - w * y)
    out[2, 1] = 2.0 * (y * z + w * x)
    out[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@njit(cache=True, inline="always")
def quat_mul(a, b, out):
    """Hamilton product out = a * b (shapes (4,)); ``out`` must not alias a or b."""
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3]
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2]
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1]
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]


@njit(cache=True, inline="always")
def quat_conj_mul(a, b, out):
    """out = conj(a) * b: the rotation of b relative to a, in a's body frame."""
    out[0] = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
    out[1] = a[0] * b[1] - a[1] * b[0] - a[2] * b[3] + a[3] * b[2]
    out[2] = a[0] * b[2] + a[1] * b[3] - a[2] * b[0] - a[3] * b[1]
    out[3] = a[0] * b[3] - a[1] * b[2] + a[2] * b[1] - a[3] * b[0]


@njit(cache=True, inline="always")
def quat_log(q, out):
    """Rotation vector (axis x angle, rad) of a unit quaternion, shortest arc.

    Parameters
    ----------
    q : ndarray, shape (4,)
    out : ndarray, shape (3,)
        Written: theta with |theta| <= pi.
    """
    w = q[0]
    x, y, z = q[1], q[2], q[3]
    if w < 0.0:
        w, x, y, z = -w, -x, -y, -z
    s = math.sqrt(x * x + y * y + z * z)
    if s < 1e-12:
        f = 2.0 / w if w > 0.0 else 2.0
    else:
        f = 2.0 * math.atan2(s, w) / s
    out[0] = f * x
    out[1] = f * y
    out[2] = f * z


@njit(cache=True, inline="always")
def quat_exp_mul_terms(q0, q1, q2, q3, th0, th1, th2):
    """q * exp(theta / 2), theta a body-frame rotation vector, renormalised: its four
    components as a tuple (every intermediate a local, no scratch array)."""
    a = math.sqrt(th0 * th0 + th1 * th1 + th2 * th2)
    e0 = math.cos(0.5 * a)
    if a < 1e-12:
        s = 0.5
    else:
        s = math.sin(0.5 * a) / a
    e1 = s * th0
    e2 = s * th1
    e3 = s * th2
    # the Hamilton product q * e (quat_mul)
    o0 = q0 * e0 - q1 * e1 - q2 * e2 - q3 * e3
    o1 = q0 * e1 + q1 * e0 + q2 * e3 - q3 * e2
    o2 = q0 * e2 - q1 * e3 + q2 * e0 + q3 * e1
    o3 = q0 * e3 + q1 * e2 - q2 * e1 + q3 * e0
    n = math.sqrt(o0 ** 2 + o1 ** 2 + o2 ** 2 + o3 ** 2)
    return o0 / n, o1 / n, o2 / n, o3 / n


@njit(cache=True, inline="always")
def quat_exp_mul(q, th0, th1, th2, out):
    """out = q * exp(theta / 2), theta a body-frame rotation vector; renormalised
    (:func:`quat_exp_mul_terms`); ``out`` may be ``q``."""
    o0, o1, o2, o3 = quat_exp_mul_terms(q[0], q[1], q[2], q[3], th0, th1, th2)
    out[0] = o0
    out[1] = o1
    out[2] = o2
    out[3] = o3


@njit(cache=True, inline="always")
def kick(v, w, F, Mb, m, It, Ia, h):
    """Kick of one body: v += h F / m; w += h I^-1 M_b (body frame).

    The gyroscopic term is not here: it is integrated exactly by
    :func:`free_rotation` in the drift (symplectic splitting).

    Parameters
    ----------
    v : ndarray, shape (3,)   world velocity (m/s), updated in place
    w : ndarray, shape (3,)   body angular velocity (rad/s), updated in place
    F : ndarray, shape (3,)   world force (N)
    Mb : ndarray, shape (3,)  body-frame moment (N m)
    m, It, Ia : float         mass (kg), transverse and axial inertia (kg m^2)
    h : float                 time increment (s)
    """
    for k in range(3):
        v[k] += h * F[k] / m
    w[0] += h * Mb[0] / It
    w[1] += h * Mb[1] / It
    w[2] += h * Mb[2] / Ia


@njit(cache=True, inline="always")
def kick_lateral(v, w, F, Mb, m, ratio, It, Ia, axis, h):
    """:func:`kick` with the body-frame mass diag(m r, m r, m) and transverse inertia
    It r (r = ``ratio`` >= 1: the mud moving with the pipe across its axis); ``axis``
    (3,) the body's unit axis in the world frame."""
    fa = F[0] * axis[0] + F[1] * axis[1] + F[2] * axis[2]
    ml = m * ratio
    for k in range(3):
        fk = fa * axis[k]
        v[k] += h * (fk / m + (F[k] - fk) / ml)
    itl = It * ratio
    w[0] += h * Mb[0] / itl
    w[1] += h * Mb[1] / itl
    w[2] += h * Mb[2] / Ia


@njit(cache=True, inline="always")
def free_rotation(q, w, It, Ia, dt):
    """Exact torque-free motion of an axisymmetric body over dt (in place).

    With I = diag(It, It, Ia) the body angular velocity splits into
    w = L_b / It + c e3, c = w_z (1 - Ia / It): a rotation about the fixed
    angular momentum plus a rotation about the body axis, so
    q <- q exp(dt L_b / It) exp(dt c e3) and (w_x, w_y) turn by -c dt about e3
    (the symmetric Euler top; Dullweber, Leimkuhler & McLachlan, J. Chem. Phys.
    107 (1997) 5840, used as the free-rotor flow of a symplectic splitting).
    The intermediate quaternion stays in locals (:func:`quat_exp_mul_terms`).

    Parameters
    ----------
    q : ndarray, shape (4,)  orientation, updated and renormalised
    w : ndarray, shape (3,)  body angular velocity (rad/s), updated
    It, Ia : float           transverse and axial inertia (kg m^2)
    dt : float               step (s)
    """
    c = w[2] * (1.0 - Ia / It)
    p0, p1, p2, p3 = quat_exp_mul_terms(q[0], q[1], q[2], q[3],
                                        dt * w[0], dt * w[1], dt * w[2] * Ia / It)
    q[0], q[1], q[2], q[3] = quat_exp_mul_terms(p0, p1, p2, p3, 0.0, 0.0, dt * c)
    a = -c * dt
    ca = math.cos(a)
    sa = math.sin(a)
    w0 = ca * w[0] - sa * w[1]
    w[1] = sa * w[0] + ca * w[1]
    w[0] = w0


def quat_from_rot(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Python helper, shape (3, 3))."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr > 0.0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif R[1, 1] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    qa = np.asarray(q, dtype=np.float64)
    return qa / np.linalg.norm(qa)
