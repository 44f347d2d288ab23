"""Numba kernels on the well path, for use inside simulator kernels.

Plain ``@njit(cache=True)`` functions on float64 arrays in SI units; this
module imports only numpy, numba and math.

Between two path nodes the well follows the minimum-curvature arc: a circle
of radius ``R = dMD / beta`` in the plane of the node tangents ``t1, t2``
(``beta`` the angle between them). At arc length ``s`` from node 1, with
``theta = s / R``::

    t(s) = [sin(beta - theta) t1 + sin(theta) t2] / sin(beta)        (slerp)
    p(s) = p1 + R [2 sin(beta - theta/2) sin(theta/2) t1
                   + 2 sin^2(theta/2) t2] / sin(beta)

(the integral of t over s, written with half-angle products so it stays
accurate for tiny beta). At ``s = dMD`` this is the minimum-curvature step
``dMD/2 (t1 + t2) (2/beta) tan(beta/2)`` (Sawaryn & Thorogood 2005, eq. 3).
Within 1e-3 rad of a half turn, where ``1/sin(beta)`` is ill-conditioned,
the same arc is written in the basis of ``t1`` and its in-plane normal.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["path_point"]

# Below this dogleg (rad) per interval the arc is replaced by its second-order
# expansion p = p1 + s t1 + s^2/(2 dMD) (t2 - t1); the neglected terms are
# O(beta^2 s) < 1e-24 m per metre.
_BETA_STRAIGHT = 1e-12
# Above this dogleg (rad) per interval 1/sin(beta) is ill-conditioned (a
# relative error eps / (pi - beta)); the arc is written in the basis of t1 and
# the in-plane normal found from the bisector instead (drillfatigue.well.survey
# switches its step at the same angle).
_BETA_NEAR_PI = math.pi - 1e-3


@njit(cache=True)
def _half_turn_point(node_pos, node_tan, i, beta, R, th, out_pos, out_tan):
    """The arc point for a dogleg near pi: ``t = cos(th) t1 + sin(th) u``.

    ``u`` is the unit normal to ``t1`` in the plane of the turn, towards
    ``t2``: the part of ``b``, the unit bisector of the end tangents, normal
    to ``t1`` (of length ``sin(beta/2)``, near 1), normalised. When
    ``t1 + t2`` is zero (or its square underflows) the plane is undefined
    and ``b`` is the unit normal to ``t1`` in its vertical plane, towards
    increasing tvd (north when ``t1`` is vertical). Position:
    ``p1 + R [sin(th) t1 + 2 sin^2(th/2) u]``. The survey's step near pi is
    this point at ``th = beta``
    (:func:`drillfatigue.well.survey.half_turn_normal`).
    """
    b0 = node_tan[i, 0] + node_tan[i + 1, 0]
    b1 = node_tan[i, 1] + node_tan[i + 1, 1]
    b2 = node_tan[i, 2] + node_tan[i + 1, 2]
    nb = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    if nb > 0.0:
        b0 /= nb
        b1 /= nb
        b2 /= nb
    else:
        h = math.sqrt(node_tan[i, 0] ** 2 + node_tan[i, 1] ** 2)
        if h > 0.0:
            b0 = -node_tan[i, 2] * node_tan[i, 0] / h
            b1 = -node_tan[i, 2] * node_tan[i, 1] / h
            b2 = h
        else:
            b0 = 1.0
            b1 = 0.0
            b2 = 0.0
    # u: b with its t1 part removed, normalised (drillfatigue.well.survey.half_turn_normal)
    d = b0 * node_tan[i, 0] + b1 * node_tan[i, 1] + b2 * node_tan[i, 2]
    w0 = b0 - d * node_tan[i, 0]
    w1 = b1 - d * node_tan[i, 1]
    w2 = b2 - d * node_tan[i, 2]
    nw = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    st = math.sin(th)
    ct = math.cos(th)
    vt = 2.0 * math.sin(0.5 * th) ** 2
    for k in range(3):
        t1 = node_tan[i, k]
        wk = w0 if k == 0 else (w1 if k == 1 else w2)
        u = wk / nw
        out_pos[k] = node_pos[i, k] + R * (st * t1 + vt * u)
        out_tan[k] = ct * t1 + st * u


@njit(cache=True)
def path_point(md, node_md, node_pos, node_tan, hint, out_pos, out_tan):
    """Position and unit tangent of the well path at measured depth ``md``.

    Parameters
    ----------
    md : float
        Measured depth, m.
    node_md : ndarray, shape (m,), float64
        MD of the path nodes, strictly increasing, m >= 2, m.
    node_pos : ndarray, shape (m, 3), float64
        Node positions [north, east, tvd], m.
    node_tan : ndarray, shape (m, 3), float64
        Unit tangents of the path at the nodes.
    hint : int
        Interval index found by the previous call (any value is safe; the
        lookup is O(1) when ``md`` stays in the same or a neighbouring
        interval, O(log m) otherwise).
    out_pos : ndarray, shape (3,), float64
        Receives the position, m.
    out_tan : ndarray, shape (3,), float64
        Receives the unit tangent.

    Returns
    -------
    int
        Index ``i`` of the interval [node i, node i+1] used, in [0, m-2]. Above
        the first node / below the last the path is extended straight along
        the end tangent and 0 / m-2 is returned.
    """
    m = node_md.shape[0]
    last = m - 2
    if md <= node_md[0]:
        d = md - node_md[0]
        for k in range(3):
            out_pos[k] = node_pos[0, k] + d * node_tan[0, k]
            out_tan[k] = node_tan[0, k]
        return 0
    if md >= node_md[m - 1]:
        d = md - node_md[m - 1]
        for k in range(3):
            out_pos[k] = node_pos[m - 1, k] + d * node_tan[m - 1, k]
            out_tan[k] = node_tan[m - 1, k]
        return last
    i = hint
    if i < 0:
        i = 0
    if i > last:
        i = last
    if md < node_md[i] or md > node_md[i + 1]:
        # Try the neighbours (a slowly moving md), else bisect: O(log m).
        if i > 0 and node_md[i - 1] <= md <= node_md[i]:
            i -= 1
        elif i < last and node_md[i + 1] <= md <= node_md[i + 2]:
            i += 1
        else:
            lo = 0
            hi = last
            while lo < hi:
                mid = (lo + hi + 1) // 2
                if node_md[mid] <= md:
                    lo = mid
                else:
                    hi = mid - 1
            i = lo
    ds = node_md[i + 1] - node_md[i]
    s = md - node_md[i]
    dn = 0.0
    sn = 0.0
    for k in range(3):
        a = node_tan[i + 1, k] - node_tan[i, k]
        b = node_tan[i + 1, k] + node_tan[i, k]
        dn += a * a
        sn += b * b
    beta = 2.0 * math.atan2(math.sqrt(dn), math.sqrt(sn))
    if beta < _BETA_STRAIGHT:
        f = s / ds
        nrm = 0.0
        for k in range(3):
            t1 = node_tan[i, k]
            dt = node_tan[i + 1, k] - t1
            out_pos[k] = node_pos[i, k] + s * t1 + 0.5 * s * f * dt
            out_tan[k] = t1 + f * dt
            nrm += out_tan[k] * out_tan[k]
        nrm = math.sqrt(nrm)
        for k in range(3):
            out_tan[k] /= nrm
        return i
    R = ds / beta
    th = s / R
    if beta > _BETA_NEAR_PI:
        _half_turn_point(node_pos, node_tan, i, beta, R, th, out_pos, out_tan)
        return i
    sb = math.sin(beta)
    ca = 2.0 * R * math.sin(beta - 0.5 * th) * math.sin(0.5 * th) / sb
    cb = 2.0 * R * math.sin(0.5 * th) ** 2 / sb
    wa = math.sin(beta - th) / sb
    wb = math.sin(th) / sb
    for k in range(3):
        t1 = node_tan[i, k]
        t2 = node_tan[i + 1, k]
        out_pos[k] = node_pos[i, k] + ca * t1 + cb * t2
        out_tan[k] = wa * t1 + wb * t2
    return i


def _warm() -> None:  # pragma: no cover - convenience for benchmarks
    """Compile :func:`path_point` once for float64 inputs."""
    md = np.array([0.0, 1.0])
    pos = np.zeros((2, 3))
    tan = np.zeros((2, 3))
    tan[:, 2] = 1.0
    path_point(0.5, md, pos, tan, 0, np.empty(3), np.empty(3))
