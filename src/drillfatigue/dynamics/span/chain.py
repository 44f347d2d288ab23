"""The rigid-segment chain's own quasi-static joint moments on given holds (kernels).

The span correction (:mod:`drillfatigue.dynamics.span.record`, docs/bending.md,
"What the chain carries and what the span adds") replaces the quasi-static
moment the rigid chain carries at a joint by the continuous beam's. This module
gives the first of the two: the joint moments of the chain of rigid segments,
as the simulator builds it, in static equilibrium under a transverse load per
segment while held at given points, each at a given position.

Model
-----
Nodes j = 0..n at the segment ends s_j (from the bit), lateral positions y_j
(one scalar problem per component; each segment is a straight bar between its
two end nodes: the joints' shear springs are taken as rigid). Segment i has
length L_i, slope theta_i = (y_{i+1} - y_i)/L_i, axial force T_i (tension > 0)
and a uniform transverse load q_i. The joint at node j (between segments j-1
and j) has the bending spring k_j of the simulator's joint (``jp[:, J_KB]``,
EI over the distance between the segment centres) and carries

    M_j = -k_j (theta_j - theta_{j-1})

(sagging positive, the sign convention of :mod:`drillfatigue.dynamics.span.bending`:
the chain curving towards +y under a +y load is M > 0). The positions minimise

    sum_j k_j (theta_j - theta_{j-1})^2 / 2 + sum_i T_i L_i phi_i^2 / 2 - sum_i q_i L_i (y_i + y_{i+1})/2

with each hold k (position s_k inside segment i, fraction xi) fixing
(1 - xi) y_i + xi y_{i+1} = Y_k. phi_i is the slope of the segment measured
from the polyline through the holds: the axial force acts on the chain's
deviation from that polyline, not on the polyline's own slope, because the
loads are transverse only (the axial part of the weight, which balances the
gradient of T along the axis, is not in q): with world components as the
lateral directions, T acting on the polyline's slope would put the axial
force's gradient across the chain. The error of this is the axial-force
gradient times the tilt of a polyline piece from the local axis (of order
1 kN/m x 2 mrad against loads of 1 kN/m: 0.2 %).

A hold is a penalty spring of ``HOLD_PENALTY`` times the stiffness around its
segment (k/L^2 of the joints at its ends over the shortest segment they join, and
|T|/L), so redundant holds (three
blade points of one rigid stabilizer) cost nothing; the relative error of a
hold is 1/HOLD_PENALTY and the round-off of the solve about HOLD_PENALTY x 1e-16.
The system is symmetric and pentadiagonal; it is solved by banded LDL^T
(Golub & Van Loan, *Matrix Computations*, 4th ed. 2013, algorithm 4.3.5 for
band width 2).

When the holds are where the simulated chain is at its contact points and
the load is the one the chain carries, the result is the chain's own joint
moment at rest (the contact forces are the holds' reactions). Where it stops
being valid: compression that makes the held chain unstable (a non-positive
pivot, ``STATUS_SINGULAR``), large rotations between segments (linear), the
joints' shear and axial compliance (rigid here).

Kernels take float64 arrays in SI, write into ``out`` arrays and return a
status code of :mod:`drillfatigue.status`.

References
----------
Golub, G. H. & Van Loan, C. F., *Matrix Computations*, 4th ed., Johns Hopkins
2013, section 4.3 (banded symmetric positive definite systems); Bazant, Z. P.
& Cedolin, L., *Stability of Structures*, Oxford 1991, section 1.5 (rigid-bar
models with rotational springs, the axial force's second-order work);
docs/bending.md.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.status import BAD_SPAN as STATUS_BAD_SPAN
from drillfatigue.status import OK as STATUS_OK
from drillfatigue.status import SINGULAR as STATUS_SINGULAR

#: stiffness of a hold over the stiffness around its segment (its relative error)
HOLD_PENALTY = 1e8
#: a node of the chain's static solution further than this beyond the wall is held on
#: it, m (half the contact penetration of a string at rest, about 0.2 mm: a node that
#: passes the wall by more is where the wall would push it)
WALL_TOL_M = 1e-4
#: rounds of holds added where the static chain leaves the hole (each round holds the
#: worst node of every free run: a run of k segments needs about log2(k) rounds)
MAX_WALL_ROUNDS = 16
#: a node this close to a hold along the chain is not held again, m
HOLD_MERGE_M = 0.01


@njit(cache=True)
def segment_of(top_s, s):
    """Index of the segment holding position ``s`` (bisection; the end ones for
    positions outside the chain)."""
    n = top_s.shape[0] - 1
    lo = 0
    hi = n
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if top_s[mid] <= s:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def chain_static_moments(top_s, k_joint, seg_T, seg_q, hold_s, hold_y, out_M):
    """Joint moments of a chain of rigid segments held at given points under its load
    (:func:`chain_static_solve` without the positions)."""
    out_y = np.zeros((top_s.shape[0], seg_q.shape[1]))
    fail = np.zeros(1, dtype=np.int64)
    return chain_static_solve(top_s, k_joint, seg_T, seg_q, hold_s, hold_y, out_M, out_y, fail)


@njit(cache=True)
def chain_static_solve(top_s, k_joint, seg_T, seg_q, hold_s, hold_y, out_M, out_y, fail):
    """Joint moments and node positions of a chain of rigid segments held at given points
    under its load.

    Parameters
    ----------
    top_s : ndarray, shape (n + 1,)
        Segment ends from the bit, m (0 first, increasing; n >= 1).
    k_joint : ndarray, shape (n - 1,)
        Bending stiffness of joint j (between segments j and j + 1), N m/rad (> 0).
    seg_T : ndarray, shape (n,)
        Effective axial force of each segment, N, tension > 0.
    seg_q : ndarray, shape (n, m)
        Transverse load per length of each segment, N/m, in m lateral components.
    hold_s : ndarray, shape (n_hold,)
        Hold positions from the bit, m, non-decreasing, at least two distinct.
    hold_y : ndarray, shape (n_hold, m)
        Position of the chain at each hold, m, per component.
    out_M : ndarray, shape (n - 1, m)
        Output: sagging-positive moment at each joint, N m, per component.
    out_y : ndarray, shape (n + 1, m)
        Output: position of each node (segment end), m, per component.
    fail : ndarray of int64, shape (1,)
        Output with ``STATUS_SINGULAR``: the node whose pivot failed (the held
        chain up to it is not stable).

    Returns
    -------
    int
        ``STATUS_OK``; ``STATUS_BAD_SPAN`` (segment lengths or stiffness not
        positive, holds unsorted or fewer than two distinct); ``STATUS_SINGULAR``
        (the held chain is not stable: a non-positive or non-finite pivot).
    """
    n = top_s.shape[0] - 1
    m = seg_q.shape[1]
    nh = hold_s.shape[0]
    out_M[:, :] = 0.0
    out_y[:, :] = 0.0
    fail[0] = -1
    if n < 2:
        return STATUS_OK
    if nh < 2 or not hold_s[nh - 1] > hold_s[0]:
        return STATUS_BAD_SPAN
    for k in range(1, nh):
        if hold_s[k] < hold_s[k - 1]:
            return STATUS_BAD_SPAN
    N = n + 1
    L = np.empty(n)
    for i in range(n):
        L[i] = top_s[i + 1] - top_s[i]
        if not L[i] > 0.0:
            return STATUS_BAD_SPAN
    for j in range(n - 1):
        if not k_joint[j] > 0.0:
            return STATUS_BAD_SPAN
    r = _hold_polyline(top_s, hold_s, hold_y)
    # banded matrix: A0 diagonal, A1 first and A2 second super-diagonal; rhs per component
    A0 = np.zeros(N)
    A1 = np.zeros(N)
    A2 = np.zeros(N)
    rhs = np.zeros((N, m))
    _assemble_chain(top_s, L, k_joint, seg_T, seg_q, hold_s, hold_y, r, A0, A1, A2, rhs)
    if _banded_ldlt_solve(A0, A1, A2, rhs, fail) != STATUS_OK:
        return STATUS_SINGULAR
    u = rhs
    for j in range(N):
        for c in range(m):
            out_y[j, c] = r[j, c] + u[j, c]
    for j in range(1, n):
        for c in range(m):
            t_lo = (r[j, c] + u[j, c] - r[j - 1, c] - u[j - 1, c]) / L[j - 1]
            t_up = (r[j + 1, c] + u[j + 1, c] - r[j, c] - u[j, c]) / L[j]
            out_M[j - 1, c] = -k_joint[j - 1] * (t_up - t_lo)
    return STATUS_OK


@njit(cache=True)
def _hold_polyline(top_s, hold_s, hold_y):
    """The polyline through the holds (the first of holds at one position) at the nodes
    ``top_s``, prolonged linearly beyond its ends: (n + 1, m)."""
    nh = hold_s.shape[0]
    m = hold_y.shape[1]
    N = top_s.shape[0]
    us = np.empty(nh)
    uy = np.empty((nh, m))
    nu = 0
    for h in range(nh):
        if nu == 0 or hold_s[h] > us[nu - 1]:
            us[nu] = hold_s[h]
            for c in range(m):
                uy[nu, c] = hold_y[h, c]
            nu += 1
    r = np.empty((N, m))
    a = 0
    for j in range(N):
        s = top_s[j]
        while a < nu - 2 and us[a + 1] <= s:
            a += 1
        t = (s - us[a]) / (us[a + 1] - us[a])
        for c in range(m):
            r[j, c] = uy[a, c] + t * (uy[a + 1, c] - uy[a, c])
    return r


@njit(cache=True)
def _assemble_chain(top_s, L, k_joint, seg_T, seg_q, hold_s, hold_y, r, A0, A1, A2, rhs):
    """The banded system of :func:`chain_static_solve` for the deviation from the
    polyline ``r``: joint springs, axial force, load and hold penalties added into the
    diagonal ``A0``, super-diagonals ``A1``, ``A2`` and right-hand sides ``rhs``."""
    n = L.shape[0]
    m = seg_q.shape[1]
    for j in range(1, n):
        kj = k_joint[j - 1]
        ca = 1.0 / L[j - 1]
        cc = 1.0 / L[j]
        cb = -(ca + cc)
        A0[j - 1] += kj * ca * ca
        A0[j] += kj * cb * cb
        A0[j + 1] += kj * cc * cc
        A1[j - 1] += kj * ca * cb
        A1[j] += kj * cb * cc
        A2[j - 1] += kj * ca * cc
        for c in range(m):
            # the polyline's own kink at the joint
            kr = (r[j + 1, c] - r[j, c]) / L[j] - (r[j, c] - r[j - 1, c]) / L[j - 1]
            rhs[j - 1, c] -= kj * kr * ca
            rhs[j, c] -= kj * kr * cb
            rhs[j + 1, c] -= kj * kr * cc
    for i in range(n):
        g = seg_T[i] / L[i]
        A0[i] += g
        A0[i + 1] += g
        A1[i] -= g
        for c in range(m):
            f = 0.5 * seg_q[i, c] * L[i]
            rhs[i, c] += f
            rhs[i + 1, c] += f
    for h in range(hold_s.shape[0]):
        i = segment_of(top_s, hold_s[h])
        xi = (hold_s[h] - top_s[i]) / L[i]
        # the stiffest spring around the hold: the joints at its segment's ends over the
        # shortest of the segments they join, the axial force over its segment
        lmin = L[i]
        kmax = 0.0
        if i > 0:
            lmin = min(lmin, L[i - 1])
            kmax = max(kmax, k_joint[i - 1])
        if i < n - 1:
            lmin = min(lmin, L[i + 1])
            kmax = max(kmax, k_joint[i])
        stiff = max(abs(seg_T[i]) / L[i], kmax / (lmin * lmin))
        K = HOLD_PENALTY * stiff
        wa = 1.0 - xi
        wb = xi
        A0[i] += K * wa * wa
        A0[i + 1] += K * wb * wb
        A1[i] += K * wa * wb
        for c in range(m):
            e = hold_y[h, c] - (wa * r[i, c] + wb * r[i + 1, c])
            rhs[i, c] += K * e * wa
            rhs[i + 1, c] += K * e * wb


@njit(cache=True)
def _banded_ldlt_solve(A0, A1, A2, rhs, fail):
    """Solve the symmetric pentadiagonal system (diagonal ``A0``, super-diagonals ``A1``,
    ``A2``) for every column of ``rhs`` in place by banded LDL^T; ``STATUS_SINGULAR`` (and
    the node in ``fail[0]``) at a non-positive or non-finite pivot."""
    N = A0.shape[0]
    m = rhs.shape[1]
    # banded LDL^T: l1[j] = L_{j+1,j}, l2[j] = L_{j+2,j}
    d = np.zeros(N)
    l1 = np.zeros(N)
    l2 = np.zeros(N)
    for j in range(N):
        dj = A0[j]
        if j >= 1:
            dj -= l1[j - 1] * l1[j - 1] * d[j - 1]
        if j >= 2:
            dj -= l2[j - 2] * l2[j - 2] * d[j - 2]
        if not (dj > 0.0 and np.isfinite(dj)):
            fail[0] = j
            return STATUS_SINGULAR
        d[j] = dj
        a1 = A1[j]
        if j >= 1:
            a1 -= l2[j - 1] * l1[j - 1] * d[j - 1]
        l1[j] = a1 / dj
        l2[j] = A2[j] / dj
    u = rhs
    for c in range(m):
        for j in range(1, N):
            u[j, c] -= l1[j - 1] * u[j - 1, c]
            if j >= 2:
                u[j, c] -= l2[j - 2] * u[j - 2, c]
        for j in range(N):
            u[j, c] /= d[j]
        for j in range(N - 2, -1, -1):
            u[j, c] -= l1[j] * u[j + 1, c]
            if j + 2 < N:
                u[j, c] -= l2[j] * u[j + 2, c]
    return STATUS_OK


@njit(cache=True)
def _insert_hold(hold_s, hold_y, s, y):
    """``hold_s``, ``hold_y`` with a hold at ``s`` (position ``y``) inserted in order."""
    nh = hold_s.shape[0]
    m = hold_y.shape[1]
    hs = np.empty(nh + 1)
    hy = np.empty((nh + 1, m))
    k = 0
    placed = False
    for h in range(nh):
        if not placed and hold_s[h] > s:
            hs[k] = s
            for c in range(m):
                hy[k, c] = y[c]
            k += 1
            placed = True
        hs[k] = hold_s[h]
        for c in range(m):
            hy[k, c] = hold_y[h, c]
        k += 1
    if not placed:
        hs[k] = s
        for c in range(m):
            hy[k, c] = y[c]
    return hs, hy


@njit(cache=True)
def chain_static_moments_in_hole(top_s, k_joint, seg_T, seg_q, hold_s, hold_y, node_room,
                                 node_now, out_M, out_n):
    """Joint moments of the held chain of :func:`chain_static_solve` kept inside the hole.

    The chain's static solution on its holds alone can leave the hole: a free run
    between holds in compression near its buckling load (a rigid-segment run buckles
    at a fraction of a continuous pipe's Euler load: two segments on one joint
    spring k = EI/l at 4 k/L) amplifies its load without bound, and at or beyond it
    has no equilibrium at all. The real chain there lies on the wall, which bounds
    its kinks, and the continuous beam it is subtracted from is bounded by the wall
    the same way (:mod:`drillfatigue.dynamics.span.record`, step 5). So, in rounds:

    * a node the solution puts further from the hole's axis than its room
      (``node_room``, hole radius less its largest contact radius) by more than
      ``WALL_TOL_M`` is held on the wall there, radially (in each free run between
      two holds, the node furthest beyond it);
    * a free run without equilibrium (a non-positive pivot) is held at its node
      nearest its middle, where the chain is now (``node_now``): beyond its buckling
      load it is not at rest, and where it is is where the wall and its inertia put it;

    up to ``MAX_WALL_ROUNDS`` rounds. A chain that still has no equilibrium is solved
    without the compression's softening (its axial forces clipped at zero). A chain
    whose solution stays inside the hole (a chain at rest on its holds) is solved
    exactly as by :func:`chain_static_solve`.

    Parameters
    ----------
    top_s, k_joint, seg_T, seg_q, hold_s, hold_y, out_M
        As :func:`chain_static_solve`; ``seg_q`` and ``hold_y`` with m = 3 world
        components of the positions relative to the hole's axis, m.
    node_room : ndarray, shape (n + 1,)
        Room of each node (segment end) off the hole's axis, m.
    node_now : ndarray, shape (n + 1, 3)
        Where each node is now relative to the hole's axis, m.
    out_n : ndarray of int64, shape (2,)
        Output: holds added on the wall, holds added where the chain is.

    Returns
    -------
    int
        A status of :func:`chain_static_solve` (``STATUS_SINGULAR`` only when the
        chain without compression's softening is singular too).
    """
    n = top_s.shape[0] - 1
    m = seg_q.shape[1]
    out_n[0] = 0
    out_n[1] = 0
    y = np.zeros((n + 1, m))
    fail = np.zeros(1, dtype=np.int64)
    hs = hold_s
    hy = hold_y
    st = STATUS_OK
    rounds = 0
    while True:
        st = chain_static_solve(top_s, k_joint, seg_T, seg_q, hs, hy, out_M, y, fail)
        if st != STATUS_OK and st != STATUS_SINGULAR:
            return st
        if rounds >= MAX_WALL_ROUNDS:
            break
        rounds += 1
        added = False
        if st == STATUS_SINGULAR:
            # the free run holding the failed pivot's node: its node nearest its middle
            s_f = top_s[fail[0]]
            a = 0
            while a < hs.shape[0] - 2 and hs[a + 1] < s_f:
                a += 1
            lo = hs[a]
            hi = hs[a + 1]
            best = -1
            gap = np.inf
            for j in range(n + 1):
                if lo + HOLD_MERGE_M < top_s[j] < hi - HOLD_MERGE_M:
                    g = abs(top_s[j] - 0.5 * (lo + hi))
                    if g < gap:
                        gap = g
                        best = j
            if best >= 0:
                hs, hy = _insert_hold(hs, hy, top_s[best], node_now[best])
                out_n[1] += 1
                added = True
        else:
            # each free run's node furthest beyond the wall, held on the wall
            h = 0
            nh0 = hs.shape[0]
            new_s = np.empty(n + 1)
            new_y = np.empty((n + 1, m))
            nnew = 0
            while h < nh0 - 1:
                lo = hs[h]
                hi = hs[h + 1]
                h += 1
                if not hi > lo + 2.0 * HOLD_MERGE_M:
                    continue
                best = -1
                most = WALL_TOL_M
                for j in range(n + 1):
                    if lo + HOLD_MERGE_M < top_s[j] < hi - HOLD_MERGE_M:
                        rr = 0.0
                        for c in range(m):
                            rr += y[j, c] * y[j, c]
                        e = math.sqrt(rr) - node_room[j]
                        if e > most:
                            most = e
                            best = j
                if best >= 0:
                    rr = 0.0
                    for c in range(m):
                        rr += y[best, c] * y[best, c]
                    f = node_room[best] / math.sqrt(rr)
                    new_s[nnew] = top_s[best]
                    for c in range(m):
                        new_y[nnew, c] = f * y[best, c]
                    nnew += 1
            for k in range(nnew):
                hs, hy = _insert_hold(hs, hy, new_s[k], new_y[k])
            out_n[0] += nnew
            added = nnew > 0
        if not added:
            break
    if st == STATUS_SINGULAR:
        seg_Tt = np.maximum(seg_T, 0.0)
        st = chain_static_solve(top_s, k_joint, seg_Tt, seg_q, hs, hy, out_M, y, fail)
    return st
