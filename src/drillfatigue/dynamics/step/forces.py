"""Force assembly: every force and moment on every segment at one instant.

:func:`compute_forces` calls one kernel per force kind, in this order
(docs/model.md):

1. :func:`rotations`: rotation matrices and world angular velocities;
2. :func:`body_forces`: gravity and buoyancy (``seg[:, S_W]`` along +z, world z
   = TVD, down) and viscous mud damping, lateral / axial / rotational,
   proportional to length;
3. :func:`drillfatigue.dynamics.core.joints.joint_forces`: the joint spring-dampers;
4. :func:`drillfatigue.dynamics.top.boundaries.top_boundary`: top drive and
   hoisting system;
5. :func:`drillfatigue.dynamics.top.boundaries.bit_guide`: the bit on the rock;
6. :func:`drillfatigue.dynamics.contact.wall.wall_contact`: wall contact and
   friction, with contact and whirl statistics (it runs last among the
   forces: Karnopp's pre-pass needs all the others);
7. :func:`moments_to_body`: world moments added to the body-frame moments;
8. with ``solver.implicit_bit_torque``,
   :func:`drillfatigue.dynamics.top.boundaries.implicit_bit_damping`: the bit torque's own
   damping taken linearly implicit on segment 0's spin (it needs the whole moment).

The order is part of the results (floating-point sums): a new force kind is
added as its own kernel and called here. Each kernel adds to ``s.Fw`` (world
force, N), ``s.Mw`` (world moment about the centre, N m) and ``s.Mb``
(body-frame moment) and to the energy channels of ``wk.ch`` (``H_PE`` spring
and contact energy, ``H_PG`` gravity energy, ``H_PDISS`` dissipated power,
``H_PIN`` power put in by the boundaries), which start from zero here.
The integrator never changes when a force kind is added.

The per-kind kernels that take the bundles are compiled with
``inline="always"``: numba passes a bundle's arrays one by one at every call
of a separately compiled function, so a call that crossed the bundles would
cost more than a small kernel's work (the wall loop, heavy and called once,
stays a call).
"""

from __future__ import annotations

from numba import njit

from drillfatigue.dynamics.top.boundaries import bit_guide, implicit_bit_damping, top_boundary
from drillfatigue.dynamics.contact.wall import wall_contact
from drillfatigue.dynamics.top.growth import growth_rate
from drillfatigue.dynamics.core.joints import joint_forces
from drillfatigue.dynamics.core.layout import (
    B_IMPBIT, C_NACT, C_STEP, H_PDISS, H_PE, H_PG, H_PIN, S_CA, S_CL, S_CRA, S_CRL, S_W,
)
from drillfatigue.dynamics.core.rigid import quat_to_rot
from drillfatigue.dynamics.core.status import OK


@njit(cache=True, inline="always")
def rotations(n, q, w, R, wW):
    """Rotation matrices ``R`` (n, 3, 3) and world angular velocities ``wW`` (n, 3) of the
    first ``n`` segments from their quaternions ``q`` and body angular velocities ``w``."""
    for i in range(n):
        quat_to_rot(q[i], R[i])
        for k in range(3):
            wW[i, k] = R[i, k, 0] * w[i, 0] + R[i, k, 1] * w[i, 1] + R[i, k, 2] * w[i, 2]


@njit(cache=True, inline="always")
def body_forces(n, s, p, wk):
    """Gravity with buoyancy and viscous mud damping; sets ``s.Fw``, ``s.Mw`` (zero) and
    ``s.Mb`` of the first ``n`` segments, adds to ``wk.ch[H_PG]`` and ``wk.ch[H_PDISS]``."""
    x = s.x
    v = s.v
    w = s.w
    Fw = s.Fw
    Mw = s.Mw
    Mb = s.Mb
    R = wk.R
    ch = wk.ch
    seg = p.seg
    for i in range(n):
        e0 = R[i, 0, 2]
        e1 = R[i, 1, 2]
        e2 = R[i, 2, 2]
        vax = v[i, 0] * e0 + v[i, 1] * e1 + v[i, 2] * e2
        cl = seg[i, S_CL]
        ca = seg[i, S_CA]
        Fw[i, 0] = -cl * (v[i, 0] - vax * e0) - ca * vax * e0
        Fw[i, 1] = -cl * (v[i, 1] - vax * e1) - ca * vax * e1
        Fw[i, 2] = -cl * (v[i, 2] - vax * e2) - ca * vax * e2 + seg[i, S_W]
        ch[H_PG] -= seg[i, S_W] * x[i, 2]
        vv = v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2
        ch[H_PDISS] += cl * (vv - vax * vax) + ca * vax * vax
        Mw[i, 0] = 0.0
        Mw[i, 1] = 0.0
        Mw[i, 2] = 0.0
        Mb[i, 0] = -seg[i, S_CRL] * w[i, 0]
        Mb[i, 1] = -seg[i, S_CRL] * w[i, 1]
        Mb[i, 2] = -seg[i, S_CRA] * w[i, 2]
        ch[H_PDISS] += seg[i, S_CRL] * (w[i, 0] ** 2 + w[i, 1] ** 2) + seg[i, S_CRA] * w[i, 2] ** 2


@njit(cache=True, inline="always")
def moments_to_body(n, R, Mw, Mb):
    """Add the world moments ``Mw`` to the body-frame moments ``Mb`` (Mb += R^T Mw)."""
    for i in range(n):
        m0 = Mw[i, 0]
        m1 = Mw[i, 1]
        m2 = Mw[i, 2]
        Mb[i, 0] += R[i, 0, 0] * m0 + R[i, 1, 0] * m1 + R[i, 2, 0] * m2
        Mb[i, 1] += R[i, 0, 1] * m0 + R[i, 1, 1] * m1 + R[i, 2, 1] * m2
        Mb[i, 2] += R[i, 0, 2] * m0 + R[i, 1, 2] * m1 + R[i, 2, 2] * m2


@njit(cache=True, inline="always")
def compute_forces(s, p, wk):
    """All forces at the current state ``s`` (:class:`bundles.State`) of the model ``p``
    (:class:`bundles.Params`) into ``s.Fw, s.Mw, s.Mb``, the joint loads ``wk.loads`` and
    the channels ``wk.ch``; updates the contact hints, statistics and bit state in ``s``.

    Returns a status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``, or
    ``UNKNOWN_FRICTION`` / ``UNKNOWN_BIT`` for a model id no kernel knows.
    """
    n = int(s.sc[C_NACT])
    t = s.sc[C_STEP] * p.dt
    ch = wk.ch
    ch[H_PE] = 0.0
    ch[H_PG] = 0.0
    ch[H_PDISS] = 0.0
    ch[H_PIN] = 0.0
    rotations(n, s.q, s.w, wk.R, wk.wW)
    body_forces(n, s, p, wk)
    joint_forces(n, growth_rate(p.bp, s.sc), s, p, wk)
    top_boundary(t, n, s, p, wk)
    st = bit_guide(s, p, wk)
    if st != OK:
        return st
    st = wall_contact(t, n, s, p, wk)
    if st != OK:
        return st
    moments_to_body(n, wk.R, s.Mw, s.Mb)
    if p.bp[B_IMPBIT] == 1.0:
        implicit_bit_damping(s, p, wk)
    return OK
