"""Span correction at the recorded joints: bending between the wall supports (docs/bending.md).

A chain of rigid segments lying on the wall is nearly collinear, so its joint
moments miss what the pipe's own weight does between the points where it
touches the wall (about w L^2 / 12 over each support of a long row of equal
spans). :func:`span_sample` adds that quasi-statically at a recorded sample,
without feeding anything back into the integrator:

1. Supports: the bit (s = 0) and every contact point of every active segment
   that penetrates the wall now (:func:`drillfatigue.dynamics.contact.find_contact`
   from the point's hint, which it does not update), by distance from the bit;
   points closer than ``MERGE_M`` count once.
2. Load per length, across the segment's axis, in the world frame: buoyed
   weight + lateral mud drag + the segment's lateral inertia -m_lat a / L.
   As the integrator moves the segment by a = F / m_lat (F all forces on
   it), the inertia is -F / L whatever the lateral mass, so the load is
   (weight + drag - F) / L: the part of the weight and drag that the
   concentrated wall and joint forces hold, smeared uniformly over the
   segment. At rest on its supports this is the weight. (The inertia of the
   segment's tilting, a load varying linearly along it, is not included.)
   A segment with three or more points, all in the wall, is in line contact:
   the wall carries its load along its length and it gets none.
3. Axial force of a segment: the mean effective tension of its two joints
   (the bit end of the first segment takes its one joint's value).
4. :func:`drillfatigue.dynamics.span_bending.chain_span_moments` with both
   chain ends pinned, once for the world (x, y) load components and once for
   z; the moments are put together as world vectors and resolved in each
   recorded joint's frame (the mid-rotation frame of its two segments, the
   frame of ``bending_x/y_Nm``), which turns with the pipe, so the correction
   alternates once per revolution.

5. Where the elastic pipe would reach the wall between two supports (its
   mid-span deflection, :func:`~drillfatigue.dynamics.span_bending.midspan_deflection`,
   exceeds the room of its body to the wall: hole radius - body radius) or a
   span is at its Euler load in compression (v >= ``BUCKLED_V``), the pipe
   lies on the wall there: a support is added at that span's middle and the
   chain solved again, up to ``MAX_SPLIT_ROUNDS`` times (a span into at most
   16 pieces). This bounds the beam-column's amplification in compression by
   the wall, as it is bounded in the hole. The room is the full radial
   clearance, so a span sagging toward supports on the same side (tool joints
   on the low side) touches earlier than this test says: there the moment is
   an upper estimate.

Validity (see :mod:`drillfatigue.dynamics.span_bending`): small deflections,
supports that do not move relative to each other under the load. A span
still buckled after the last round gives a status other than OK: the
sample's corrections are then zero and the status is returned (the caller
counts such samples).
Arrays read: ``s.x, s.v, s.q, s.Fw, s.hint``, ``p.seg, p.wall, p.cpar, p.cp_n, p.cp,
p.ei, p.topp``, ``wk.loads``; scratch allocated per call (a sample is taken
every few hundred steps).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from drillfatigue.dynamics.contact import OUT_DELTA, OUT_SIZE, contact_point, find_contact
from drillfatigue.dynamics.layout import (
    MAX_CONTACT_POINTS, MAX_TABLE_POINTS, P_CPTAB, P_NPTS, S_CL, S_H, S_RB, S_W,
)
from drillfatigue.dynamics.rigid import quat_conj_mul, quat_mul, quat_to_rot
from drillfatigue.dynamics.span_bending import (
    BUCKLED_V, END_PINNED, STATUS_OK, STATUS_SPAN_BUCKLED, chain_span_moments, midspan_deflection,
)

#: supports closer than this along the string are one support, m
MERGE_M = 0.01


@njit(cache=True)
def _joint_frame(q_lo, q_up, qr, qh, qm, Rm):
    """The joint frame of :func:`drillfatigue.dynamics.joints.joint_force`: the lower
    segment's frame turned by half the relative rotation."""
    quat_conj_mul(q_lo, q_up, qr)
    if qr[0] < 0.0:
        for k in range(4):
            qr[k] = -qr[k]
    nrm = np.sqrt((1.0 + qr[0]) ** 2 + qr[1] ** 2 + qr[2] ** 2 + qr[3] ** 2)
    qh[0] = (1.0 + qr[0]) / nrm
    qh[1] = qr[1] / nrm
    qh[2] = qr[2] / nrm
    qh[3] = qr[3] / nrm
    quat_mul(q_lo, qh, qm)
    quat_to_rot(qm, Rm)


#: rounds of mid-span supports added where a span touches the wall or buckles
#: (each round halves the offending spans: up to 2^rounds pieces)
MAX_SPLIT_ROUNDS = 4
#: internal: the supports were split, solve again
STATUS_SPLIT = -1


@njit(cache=True)
def _solve_or_split(sup_c, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap, read_s, rxy, rz,
                    may_split):
    """Solve the chain on ``sup_c``; where a span's mid-span deflection exceeds the
    room its body has to the wall, or it is at its Euler load in compression, the
    elastic pipe lies on the wall there: with ``may_split`` add a support at that
    span's middle and return ``(STATUS_SPLIT, new supports)``; else the solve's status."""
    m = sup_c.shape[0]
    span_L = np.zeros(m - 1)
    span_ei = np.zeros(m - 1)
    span_T = np.zeros(m - 1)
    span_q = np.zeros((m - 1, 2))
    work = np.zeros((m, 6))
    sup_M = np.zeros((m, 2))
    sup_Mz = np.zeros((m, 2))
    span_qz = np.zeros((m - 1, 2))
    st = chain_span_moments(sup_c, top_s, seg_ei, seg_T, seg_q, END_PINNED, END_PINNED, read_s,
                            span_L, span_ei, span_T, span_q, work, sup_M, rxy)
    if st == STATUS_OK:
        st = chain_span_moments(sup_c, top_s, seg_ei, seg_T, seg_qz, END_PINNED, END_PINNED,
                                read_s, span_L, span_ei, span_T, span_qz, work, sup_Mz, rz)
    if st != STATUS_OK and st != STATUS_SPAN_BUCKLED:
        return st, sup_c
    if not may_split:
        return st, sup_c
    split = np.zeros(m - 1, dtype=np.bool_)
    nsplit = 0
    d_xy = np.zeros(m - 1)
    d_z = np.zeros(m - 1)
    ok_xy = STATUS_SPAN_BUCKLED
    ok_z = STATUS_SPAN_BUCKLED
    if st == STATUS_OK:
        ok_xy = midspan_deflection(span_L, span_ei, span_T, span_q, sup_M, d_xy)
        ok_z = midspan_deflection(span_L, span_ei, span_T, span_qz, sup_Mz, d_z)
    for k in range(m - 1):
        L = span_L[k]
        v2 = -span_T[k] * L * L / span_ei[k]
        buckled = v2 >= BUCKLED_V * BUCKLED_V
        room = _span_gap(sup_c[k], sup_c[k + 1], top_s, seg_gap)
        touches = (ok_xy == STATUS_OK and ok_z == STATUS_OK
                   and d_xy[k] * d_xy[k] + d_z[k] * d_z[k] > room * room)
        if (buckled or touches) and L > 2.0 * MERGE_M:
            split[k] = True
            nsplit += 1
    if nsplit == 0:
        return st, sup_c
    out = np.zeros(m + nsplit)
    j = 0
    for k in range(m):
        out[j] = sup_c[k]
        j += 1
        if k < m - 1 and split[k]:
            out[j] = 0.5 * (sup_c[k] + sup_c[k + 1])
            j += 1
    return STATUS_SPLIT, out


@njit(cache=True)
def _span_gap(a, b, top_s, seg_gap):
    """Smallest room to the wall of the segments a span [a, b] crosses, m."""
    g = np.inf
    for i in range(seg_gap.shape[0]):
        if top_s[i + 1] > a and top_s[i] < b:
            g = min(g, seg_gap[i])
    return g if np.isfinite(g) else 0.0


@njit(cache=True)
def span_sample(n, s, p, wk, sel, out):
    """Span-bending moments at the joints ``sel`` now: ``out[a] = (M_x, M_y)`` in joint
    ``sel[a]``'s frame, N m (module docstring). Returns a span-bending status."""
    for a in range(sel.size):
        out[a, 0] = 0.0
        out[a, 1] = 0.0
    if n < 2:
        return STATUS_OK
    seg = p.seg
    cpar = p.cpar
    x = s.x
    hint = s.hint
    wall = p.wall
    p0 = wall[:, 0:3]
    axc = wall[:, 3:6]
    lnc = wall[:, 6]
    rad = wall[:, 7]
    loads = wk.loads
    table = cpar[P_CPTAB] != 0.0
    npts = int(cpar[P_NPTS])
    tbase = MAX_CONTACT_POINTS * x.shape[0]
    # segment boundaries from the bit, axes, loads and properties
    top_s = np.zeros(n + 1)
    for i in range(n):
        top_s[i + 1] = top_s[i] + 2.0 * seg[i, S_H]
    R = np.zeros((n, 3, 3))
    for i in range(n):
        quat_to_rot(s.q[i], R[i])
    seg_q = np.zeros((n, 2))
    seg_qz = np.zeros((n, 2))
    seg_T = np.zeros(n)
    seg_ei = np.zeros(n)
    Fw = s.Fw
    v = s.v
    for i in range(n):
        inv_l = 1.0 / (2.0 * seg[i, S_H])
        # weight + drag - m_lat a = weight + drag - (all forces): the distributed load
        # that the wall and joint forces at the supports hold (see the module docstring)
        cl = seg[i, S_CL]
        ex = R[i, 0, 2]
        ey = R[i, 1, 2]
        ez = R[i, 2, 2]
        vax = v[i, 0] * ex + v[i, 1] * ey + v[i, 2] * ez
        gx = -cl * (v[i, 0] - vax * ex) - Fw[i, 0]
        gy = -cl * (v[i, 1] - vax * ey) - Fw[i, 1]
        gz = -cl * (v[i, 2] - vax * ez) - Fw[i, 2] + seg[i, S_W]
        ga = gx * ex + gy * ey + gz * ez
        seg_q[i, 0] = (gx - ga * ex) * inv_l
        seg_q[i, 1] = (gy - ga * ey) * inv_l
        seg_qz[i, 0] = (gz - ga * ez) * inv_l
        lo = loads[i - 1, 0] if i > 0 else loads[0, 0]
        up = loads[i, 0] if i < n - 1 else loads[n - 2, 0]
        seg_T[i] = 0.5 * (lo + up)
        seg_ei[i] = p.ei[i]
    # supports: the bit and the contact points in the wall now
    cap = 1 + n * MAX_TABLE_POINTS
    sup = np.zeros(cap)
    nsup = 1
    X = np.zeros(3)
    info = np.zeros(OUT_SIZE)
    for i in range(n):
        own = table and i < n - 1
        npi = int(p.cp_n[i]) if own else npts
        h = seg[i, S_H]
        ncon = 0
        for pt in range(npi):
            if own:
                off = p.cp[i, pt, 0]
                rc = p.cp[i, pt, 1]
                hi = hint[tbase + MAX_TABLE_POINTS * i + pt]
                if hi < 0:
                    hi = hint[MAX_CONTACT_POINTS * i]
            else:
                off, rc = contact_point(seg, i, pt)
                hi = hint[MAX_CONTACT_POINTS * i + pt]
            for k in range(3):
                X[k] = x[i, k] + off * R[i, k, 2]
            find_contact(X, rc, p0, axc, lnc, rad, hi, info)
            if info[OUT_DELTA] > 0.0:
                sup[nsup] = top_s[i] + h - off
                nsup += 1
                ncon += 1
        if npi >= 3 and ncon == npi:
            # line contact: the wall carries the segment's weight along its length
            seg_q[i, 0] = 0.0
            seg_q[i, 1] = 0.0
            seg_qz[i, 0] = 0.0
    sup_s = np.sort(sup[:nsup])
    keep = np.zeros(nsup, dtype=np.bool_)
    last = -1.0
    m = 0
    for k in range(nsup):
        if k == 0 or sup_s[k] - last > MERGE_M:
            keep[k] = True
            last = sup_s[k]
            m += 1
    if m < 2:
        return STATUS_OK
    sup_c = np.zeros(m)
    j = 0
    for k in range(nsup):
        if keep[k]:
            sup_c[j] = min(max(sup_s[k], 0.0), top_s[n])
            j += 1
    nr = sel.size
    read_s = np.zeros(nr)
    for a in range(nr):
        read_s[a] = top_s[min(sel[a], n - 1) + 1]
    # per-segment room for the body to sag: hole radius at its cylinder - body radius
    seg_gap = np.zeros(n)
    rmin = rad.min()
    for i in range(n):
        h0 = hint[MAX_CONTACT_POINTS * i]
        r_hole = rad[h0] if 0 <= h0 < rad.shape[0] else rmin
        seg_gap[i] = max(r_hole - seg[i, S_RB], 0.0)
    rxy = np.zeros((nr, 2))
    rz = np.zeros((nr, 2))
    st = STATUS_OK
    for _round in range(MAX_SPLIT_ROUNDS + 1):
        st, sup_c = _solve_or_split(sup_c, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap,
                                    read_s, rxy, rz, _round < MAX_SPLIT_ROUNDS)
        if st != STATUS_SPLIT:
            break
    if st != STATUS_OK:
        return st
    qr = np.zeros(4)
    qh = np.zeros(4)
    qm = np.zeros(4)
    Rm = np.zeros((3, 3))
    for a in range(nr):
        jj = sel[a]
        if jj >= n - 1:
            continue
        # sagging moments of the world load components (span_bending's vector convention)
        msx = -rxy[a, 1]
        msy = rxy[a, 0]
        msz = -rz[a, 1]
        _joint_frame(s.q[jj], s.q[jj + 1], qr, qh, qm, Rm)
        t0 = Rm[0, 2]
        t1 = Rm[1, 2]
        t2 = Rm[2, 2]
        # moment vector sum_c M_c (e_c x t)
        mw0 = msy * t2 - msz * t1
        mw1 = msz * t0 - msx * t2
        mw2 = msx * t1 - msy * t0
        out[a, 0] = Rm[0, 0] * mw0 + Rm[1, 0] * mw1 + Rm[2, 0] * mw2
        out[a, 1] = Rm[0, 1] * mw0 + Rm[1, 1] * mw1 + Rm[2, 1] * mw2
    return STATUS_OK
