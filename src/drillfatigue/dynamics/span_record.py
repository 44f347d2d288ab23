"""Span correction at the recorded joints: bending between the wall supports (docs/bending.md).

A chain of rigid segments lying on the wall is nearly collinear, so its joint
moments miss what the pipe's own weight does between the points where it
touches the wall (about w L^2 / 12 over each support of a long row of equal
spans). :func:`span_sample` adds that quasi-statically at a recorded sample,
without feeding anything back into the integrator:

1. Supports: the bit (s = 0) and every contact point of every active segment
   that penetrates the wall now (:func:`drillfatigue.dynamics.contact.find_contact`
   from the point's hint, which it does not update), by distance from the bit;
   points closer than ``MERGE_M`` count once. With ``contact.deepest_point``
   a segment's deepest point between its tested points
   (:func:`drillfatigue.dynamics.contact.deepest_point`) is a support where the
   contact kernel pushes on it (body penetration there above the tested
   points' largest).
2. Load per length, across the segment's axis, in the world frame: buoyed
   weight + lateral mud drag + the segment's lateral inertia -m_lat a / L.
   As the integrator moves the segment by a = F / m_lat (F all forces on
   it), the inertia is -F / L whatever the lateral mass, so the load is
   (weight + drag - F) / L: the part of the weight and drag that the
   concentrated wall and joint forces hold, smeared uniformly over the
   segment. At rest on its supports this is the weight. (The inertia of the
   segment's tilting, a load varying linearly along it, is not included.)
   A segment in line contact gets none (the wall carries its load along its
   length) and all its points are supports:

   * three or more points, all in the wall (any hole);
   * in a curved hole (curvature kappa above ``STRAIGHT_KAPPA`` at any of its
     points), a segment without raised points (tool joints, blades, upsets:
     every point at the body radius) whose chord bulge h^2 kappa / 2 (L^2
     kappa / 8, L = 2h) is below its clearance, with every point no further
     from the wall than the chord's offset from the arc there: (h^2 - u^2)
     kappa / 2 resting on the outer wall (ends in it), or u^2 kappa / 2 on
     the inner wall (middle in it), u the point's offset from the segment's
     centre, plus ``CHORD_TOL`` x the bulge. The real pipe there is bent to
     the hole's curvature and lies along the wall: the moment E I kappa of
     that bending is what the rigid chain's joint moments hold, and its
     weight goes to the wall where it lies, not to a span between the rigid
     segment's ends. Without this the span moment of collars lying in a
     build scaled with L^2 (halving the segments took 75 % off it).
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

6. The span from the bit: from the bit end (guided on the hole's axis on
   bottom, free off bottom) the string reaches the wall at a tangency point, where it meets the wall with
   the wall's slope and the wall's curvature (the moment of that curvature,
   E I kappa, is in the rigid chain's joint moments): beyond it the pipe lies
   on the wall and holds no span moment. When the first support above the
   bit opens a segment in line contact (step 2), the span from the bit ends
   at the tangency length L_t (:func:`tangency_length_m`, the pendulum of
   Lubinski and Woods (1953) generalised to a curved hole, with r the bit end's
   distance from the wall: infinite when the bit lies on it) clipped to that first
   support, and is solved alone, pinned at both ends (zero span moment at
   the tangency); the rest of the chain is solved from that support on,
   pinned there. Solved as one continuous beam with the unloaded line-contact
   spans beyond it, the span would take a moment over that support set by
   those spans' lengths, i.e. by the contact-point spacing (docs/bending.md).

Validity (see :mod:`drillfatigue.dynamics.span_bending`): small deflections,
supports that do not move relative to each other under the load. A span
still at or beyond its Euler load after the last round (or one the solution
cannot handle) is handled locally by
:func:`drillfatigue.dynamics.span_bending.chain_span_moments`: the chain is
cut there, pinned over that span's supports, the span gets no correction
and every other span is solved as in the chain without it; the number of
such spans is returned (the caller counts them and the samples that had
any), so a buckled span far away never zeroes a joint's correction.
Arrays read: ``s.x, s.v, s.q, s.Fw, s.hint``, ``p.seg, p.wall, p.cpar, p.cp_n, p.cp,
p.ei, p.topp``, ``wk.loads``; scratch allocated per call (a sample is taken
every few hundred steps).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.dynamics.contact import (
    OUT_DELTA, OUT_SIZE, contact_point, deepest_point, find_contact,
)
from drillfatigue.dynamics.layout import (
    CS_SQF, CS_SQON, MAX_CONTACT_POINTS, MAX_TABLE_POINTS, P_CPTAB, P_DEEP, P_NPTS, P_SPANDYN, S_CL,
    S_H, S_RB, S_W,
)
from drillfatigue.dynamics.rigid import quat_conj_mul, quat_mul, quat_to_rot
from drillfatigue.dynamics.span_bending import (
    BUCKLED_V, END_PINNED, STATUS_OK, STATUS_SPAN_BUCKLED, chain_span_moments, midspan_deflection,
)
from drillfatigue.dynamics.span_dynamics import segment_axial_N

#: supports closer than this along the string are one support, m
MERGE_M = 0.01
#: tolerance of the line-contact test in a curved hole, as a share of the segment's
#: chord bulge L^2 kappa / 8: the middle of a segment resting on the outer wall of the
#: polygonal hole measured up to 1.01 bulge off it; a segment leaving the wall is off
#: by more at its ends (near the bit, below the held top: several bulges)
CHORD_TOL = 0.1
#: hole curvature below which the hole counts as straight, 1/m (0.017 deg/30 m: the
#: bulge of a 10 m segment is 0.13 mm, below the contact penetration at rest; it keeps
#: the round-off of a straight cylinder chain's axes from changing anything)
STRAIGHT_KAPPA = 1e-5


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
    """Solve the chain on ``sup_c`` (spans the solution cannot hold are cut,
    :func:`~drillfatigue.dynamics.span_bending.chain_span_moments`). With ``may_split``,
    where a span is at its Euler load in compression or its mid-span deflection exceeds
    the room its body has to the wall, the elastic pipe lies on the wall there: add a
    support at that span's middle and return ``(STATUS_SPLIT, new supports, cut)``;
    else ``(status, supports, cut)`` with the per-span cut codes."""
    m = sup_c.shape[0]
    span_L = np.zeros(m - 1)
    span_ei = np.zeros(m - 1)
    span_T = np.zeros(m - 1)
    span_q = np.zeros((m - 1, 2))
    span_qz = np.zeros((m - 1, 2))
    work = np.zeros((m, 6))
    sup_M = np.zeros((m, 2))
    sup_Mz = np.zeros((m, 2))
    cut = np.zeros(m - 1, dtype=np.int64)
    st = chain_span_moments(sup_c, top_s, seg_ei, seg_T, seg_q, END_PINNED, END_PINNED, read_s,
                            span_L, span_ei, span_T, span_q, work, sup_M, rxy, cut)
    if st != STATUS_OK:
        return st, sup_c, cut
    # same spans, axial forces and stiffness: the same spans are cut
    st = chain_span_moments(sup_c, top_s, seg_ei, seg_T, seg_qz, END_PINNED, END_PINNED,
                            read_s, span_L, span_ei, span_T, span_qz, work, sup_Mz, rz, cut)
    if st != STATUS_OK or not may_split:
        return st, sup_c, cut
    split = np.zeros(m - 1, dtype=np.bool_)
    nsplit = 0
    any_cut = False
    for k in range(m - 1):
        if cut[k] == STATUS_SPAN_BUCKLED and span_L[k] > 2.0 * MERGE_M:
            split[k] = True
            nsplit += 1
        if cut[k] != STATUS_OK:
            any_cut = True
    if not any_cut:
        d_xy = np.zeros(m - 1)
        d_z = np.zeros(m - 1)
        if (midspan_deflection(span_L, span_ei, span_T, span_q, sup_M, d_xy) == STATUS_OK
                and midspan_deflection(span_L, span_ei, span_T, span_qz, sup_Mz, d_z)
                == STATUS_OK):
            for k in range(m - 1):
                room = _span_gap(sup_c[k], sup_c[k + 1], top_s, seg_gap)
                if (d_xy[k] * d_xy[k] + d_z[k] * d_z[k] > room * room
                        and span_L[k] > 2.0 * MERGE_M):
                    split[k] = True
                    nsplit += 1
    if nsplit == 0:
        return st, sup_c, cut
    out = np.zeros(m + nsplit)
    j = 0
    for k in range(m):
        out[j] = sup_c[k]
        j += 1
        if k < m - 1 and split[k]:
            out[j] = 0.5 * (sup_c[k] + sup_c[k + 1])
            j += 1
    return STATUS_SPLIT, out, cut


@njit(cache=True)
def _span_gap(a, b, top_s, seg_gap):
    """Smallest room to the wall of the segments a span [a, b] crosses, m."""
    g = np.inf
    for i in range(seg_gap.shape[0]):
        if top_s[i + 1] > a and top_s[i] < b:
            g = min(g, seg_gap[i])
    return g if np.isfinite(g) else 0.0


@njit(cache=True)
def _hole_curvature(axc, lnc, ic):
    """Curvature of the hole at cylinder ``ic`` of the chain, 1/m: the larger turning
    rate of its axis towards its two neighbours (angle between the axes over the
    distance between the cylinders' middles); zero in a straight hole."""
    kap = 0.0
    for j in (ic - 1, ic + 1):
        if j < 0 or j >= lnc.shape[0]:
            continue
        c = axc[ic, 0] * axc[j, 0] + axc[ic, 1] * axc[j, 1] + axc[ic, 2] * axc[j, 2]
        s0 = axc[ic, 1] * axc[j, 2] - axc[ic, 2] * axc[j, 1]
        s1 = axc[ic, 2] * axc[j, 0] - axc[ic, 0] * axc[j, 2]
        s2 = axc[ic, 0] * axc[j, 1] - axc[ic, 1] * axc[j, 0]
        # atan2 keeps small angles exact (acos of a cosine near 1 does not)
        ang = math.atan2(math.sqrt(s0 * s0 + s1 * s1 + s2 * s2), c)
        kap = max(kap, ang / (0.5 * (lnc[ic] + lnc[j])))
    return kap


@njit(cache=True)
def tangency_length_m(ei_Nm2, clearance_m, q_N_per_m, kappa_out_rad_per_m):
    """Length from a pinned end on the hole's axis to where a pipe under a uniform
    lateral load q meets the wall tangentially, m (infinite without load).

    Beam EI y^(4) = q (y towards the wall the load presses the pipe on), pinned
    at the bit on the axis: y(0) = 0, M(0) = 0. At the tangency x = L the pipe
    joins the wall: its offset, slope and curvature are the wall's. The wall
    is at y_w(x) = r - kappa_out x^2 / 2 (r the radial clearance, kappa_out
    the hole's curvature, > 0 where the load points away from the centre of
    curvature, i.e. onto the outer wall, < 0 onto the inner wall), so
    y(L) = y_w(L), y'(L) = -kappa_out L, y''(L) = -kappa_out. Integrating,
    y = c1 x + c3 x^3 + q x^4 / (24 EI) with c3 = -(kappa_out + q L^2/(2 EI))/(6 L),
    c1 = -kappa_out L / 2 + q L^3 / (12 EI), and the offset condition reads

        q L^4 / (24 EI) - kappa_out L^2 / 6 = r,

    a quadratic in L^2. In a straight hole L = (24 EI r / q)^(1/4), the
    pendulum BHA's tangency length with no weight on bit (Lubinski & Woods,
    "Factors affecting the angle of inclination and dog-legging in rotary bore
    holes", API Drilling and Production Practice 1953): the span's moment is
    then the simply supported q x (L - x) / 2, zero at both ends, largest
    q L^2 / 8 at mid span. Axial force is neglected (valid for |T| L^2 / EI
    << 1: 0.015 for the collars near the bit of the build test)."""
    if not (q_N_per_m > 0.0 and ei_Nm2 > 0.0 and clearance_m > 0.0):
        return np.inf
    a = kappa_out_rad_per_m / 6.0
    b = q_N_per_m * clearance_m / (6.0 * ei_Nm2)
    root = math.sqrt(a * a + b)
    # a + root without cancellation when a < 0
    u = a + root if a >= 0.0 else b / (root - a)
    return math.sqrt(12.0 * ei_Nm2 / q_N_per_m * u)


@njit(cache=True)
def _hole_curvature_vector(axc, lnc, ic, out):
    """Curvature vector of the hole at cylinder ``ic`` (towards the centre of
    curvature, 1/m): the change of the cylinders' axes between its neighbours
    over the distance between their middles (one-sided at the chain's ends)."""
    lo = max(ic - 1, 0)
    hi = min(ic + 1, lnc.shape[0] - 1)
    for k in range(3):
        out[k] = 0.0
    if hi == lo:
        return
    ds = 0.5 * lnc[lo] + 0.5 * lnc[hi]
    for j in range(lo + 1, hi):
        ds += lnc[j]
    for k in range(3):
        out[k] = (axc[hi, k] - axc[lo, k]) / ds


@njit(cache=True)
def _solve_chain(sup_c, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap, read_s, rxy, rz):
    """The chain on supports ``sup_c`` pinned at both ends, with mid-span supports added
    where a span reaches the wall or buckles (module docstring, step 5): ``(status, cut)``
    with the read moments in ``rxy``, ``rz``."""
    st = STATUS_OK
    cut = np.zeros(sup_c.shape[0] - 1, dtype=np.int64)
    for _round in range(MAX_SPLIT_ROUNDS + 1):
        st, sup_c, cut = _solve_or_split(sup_c, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap,
                                         read_s, rxy, rz, _round < MAX_SPLIT_ROUNDS)
        if st != STATUS_SPLIT:
            break
    return st, cut


@njit(cache=True)
def span_sample(n, s, p, wk, sel, out):
    """Span-bending moments at the joints ``sel`` now: ``out[a] = (M_x, M_y)`` in joint
    ``sel[a]``'s frame, N m (module docstring).

    Returns the number of spans handled locally (no correction in them, the chain
    cut there), or minus a status code when no span could be solved (every
    ``out`` zero)."""
    for a in range(sel.size):
        out[a, 0] = 0.0
        out[a, 1] = 0.0
    if n < 2:
        return 0
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
    cst = s.cst
    dyn = cpar.shape[0] > P_SPANDYN and cpar[P_SPANDYN] > 0.0
    for i in range(n):
        inv_l = 1.0 / (2.0 * seg[i, S_H])
        # weight + drag - m_lat a = weight + drag - (all forces): the distributed load
        # that the wall and joint forces at the supports hold (see the module docstring)
        cl = seg[i, S_CL]
        ex = R[i, 0, 2]
        ey = R[i, 1, 2]
        ez = R[i, 2, 2]
        if dyn and cst[i, CS_SQON] != 0.0:
            # through the span's first mode (span_dynamics): the filtered -c v - F,
            # whose axial part the projection below removes as it does the drag's
            gx = cst[i, CS_SQF]
            gy = cst[i, CS_SQF + 1]
            gz = cst[i, CS_SQF + 2] + seg[i, S_W]
        else:
            vax = v[i, 0] * ex + v[i, 1] * ey + v[i, 2] * ez
            gx = -cl * (v[i, 0] - vax * ex) - Fw[i, 0]
            gy = -cl * (v[i, 1] - vax * ey) - Fw[i, 1]
            gz = -cl * (v[i, 2] - vax * ez) - Fw[i, 2] + seg[i, S_W]
        ga = gx * ex + gy * ey + gz * ez
        seg_q[i, 0] = (gx - ga * ex) * inv_l
        seg_q[i, 1] = (gy - ga * ey) * inv_l
        seg_qz[i, 0] = (gz - ga * ez) * inv_l
        seg_T[i] = segment_axial_N(i, n, loads)
        seg_ei[i] = p.ei[i]
    # supports: the bit and the contact points in the wall now
    cap = 1 + n * (MAX_TABLE_POINTS + 1)
    sup = np.zeros(cap)
    nsup = 1
    X = np.zeros(3)
    info = np.zeros(OUT_SIZE)
    pt_u = np.zeros(MAX_TABLE_POINTS + MAX_CONTACT_POINTS)
    pt_gap = np.zeros(MAX_TABLE_POINTS + MAX_CONTACT_POINTS)
    pt_g = np.zeros(MAX_TABLE_POINTS + MAX_CONTACT_POINTS)
    pt_hint = np.zeros(MAX_TABLE_POINTS + MAX_CONTACT_POINTS, dtype=np.int64)
    deep = cpar.shape[0] > P_DEEP and cpar[P_DEEP] != 0.0
    seg_line = np.zeros(n, dtype=np.bool_)
    # the bit end's distance from the wall (the pendulum's offset r), m
    bit_gap = 0.0
    for i in range(n):
        own = table and i < n - 1
        npi = int(p.cp_n[i]) if own else npts
        h = seg[i, S_H]
        ncon = 0
        kap = 0.0
        clr = np.inf
        raised = False
        dpen = 0.0
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
            ic = find_contact(X, rc, p0, axc, lnc, rad, hi, info)
            if ic >= 0:
                kap = max(kap, _hole_curvature(axc, lnc, ic))
                clr = min(clr, rad[ic] - rc)
            pt_u[pt] = off
            pt_gap[pt] = -info[OUT_DELTA]
            if i == 0 and off >= h - MERGE_M:
                bit_gap = -info[OUT_DELTA]
            if info[OUT_DELTA] > 0.0:
                sup[nsup] = top_s[i] + h - off
                nsup += 1
                ncon += 1
            pt_g[pt] = info[OUT_DELTA] - rc
            pt_hint[pt] = hi
            if info[OUT_DELTA] > dpen:
                dpen = info[OUT_DELTA]
            if rc != seg[i, S_RB]:
                raised = True
        if deep and npi >= 3:
            # the deepest point between the tested points, a support where the contact
            # kernel pushes on it (contact.wall_contact: beyond the tested points'
            # largest penetration)
            kd, ud, gd = deepest_point(pt_u, pt_g, npi)
            if kd >= 0 and gd + seg[i, S_RB] > dpen:
                for k in range(3):
                    X[k] = x[i, k] + ud * R[i, k, 2]
                find_contact(X, seg[i, S_RB], p0, axc, lnc, rad, pt_hint[kd], info)
                if info[OUT_DELTA] > dpen:
                    sup[nsup] = top_s[i] + h - ud
                    nsup += 1
        line = npi >= 3 and ncon == npi
        if kap > STRAIGHT_KAPPA and not raised and not line and 0.5 * h * h * kap < clr:
            # along the wall of a curved hole: every point no further from the wall than
            # the chord's offset from the arc there, (h^2 - u^2) kappa / 2 resting on the
            # outer wall (ends in it) or u^2 kappa / 2 on the inner wall (middle in it).
            # A segment whose bulge exceeds the clearance cannot lie along one wall (it
            # touches both; the hole-fit rule cuts segments so that it does not)
            tol = CHORD_TOL * 0.5 * h * h * kap
            outer = True
            inner = True
            for pt in range(npi):
                u2 = pt_u[pt] * pt_u[pt]
                if pt_gap[pt] > 0.5 * (h * h - u2) * kap + tol:
                    outer = False
                if pt_gap[pt] > 0.5 * u2 * kap + tol:
                    inner = False
            if outer or inner:
                line = True
                for pt in range(npi):
                    if pt_gap[pt] >= 0.0:
                        sup[nsup] = top_s[i] + h - pt_u[pt]
                        nsup += 1
        seg_line[i] = line
        if line:
            # line contact: the wall carries the segment's weight along its length
            seg_q[i, 0] = 0.0
            seg_q[i, 1] = 0.0
            seg_qz[i, 0] = 0.0
    # clipped to the chain before merging, so that the kept supports stay strictly increasing
    sup_s = np.sort(np.minimum(np.maximum(sup[:nsup], 0.0), top_s[n]))
    keep = np.zeros(nsup, dtype=np.bool_)
    last = -1.0
    m = 0
    for k in range(nsup):
        if k == 0 or sup_s[k] - last > MERGE_M:
            keep[k] = True
            last = sup_s[k]
            m += 1
    if m < 2:
        return 0
    sup_c = np.zeros(m)
    j = 0
    for k in range(nsup):
        if keep[k]:
            sup_c[j] = sup_s[k]
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
    # the span from the bit ends at the tangency where the string reaches a wall it
    # then lies along (module docstring, step 6)
    s_hi = sup_c[1]
    i_hi = 0
    while i_hi < n - 1 and top_s[i_hi + 1] <= s_hi + MERGE_M:
        i_hi += 1
    n_cut = 0
    if sup_c[0] == 0.0 and seg_line[i_hi] and not seg_line[0]:
        q0 = math.sqrt(seg_q[0, 0] ** 2 + seg_q[0, 1] ** 2 + seg_qz[0, 0] ** 2)
        h0 = hint[MAX_CONTACT_POINTS * 0]
        kap_out = 0.0
        if 0 <= h0 < rad.shape[0] and q0 > 0.0:
            kv = np.zeros(3)
            _hole_curvature_vector(axc, lnc, h0, kv)
            # the load's share pointing away from the centre of curvature
            kap_out = -(kv[0] * seg_q[0, 0] + kv[1] * seg_q[0, 1] + kv[2] * seg_qz[0, 0]) / q0
        l_t = tangency_length_m(seg_ei[0], bit_gap, q0, kap_out)
        bit_span = np.zeros(2)
        bit_span[1] = min(l_t, s_hi)
        # a tangency within MERGE_M of the bit leaves no span there (zero moments)
        if bit_span[1] > MERGE_M:
            st, cut = _solve_chain(bit_span, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap,
                                   read_s, rxy, rz)
            if st != STATUS_OK:
                return -st
            for k in range(cut.shape[0]):
                if cut[k] != STATUS_OK:
                    n_cut += 1
        if m > 2:
            rxy2 = np.zeros((nr, 2))
            rz2 = np.zeros((nr, 2))
            st, cut = _solve_chain(sup_c[1:].copy(), top_s, seg_ei, seg_T, seg_q, seg_qz,
                                   seg_gap, read_s, rxy2, rz2)
            if st != STATUS_OK:
                return -st
            # read points outside a chain's supports get zero from it
            for a in range(nr):
                for k in range(2):
                    rxy[a, k] += rxy2[a, k]
                    rz[a, k] += rz2[a, k]
            for k in range(cut.shape[0]):
                if cut[k] != STATUS_OK:
                    n_cut += 1
    else:
        st, cut = _solve_chain(sup_c, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap, read_s,
                               rxy, rz)
        if st != STATUS_OK:
            return -st
        for k in range(cut.shape[0]):
            if cut[k] != STATUS_OK:
                n_cut += 1
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
    return n_cut
