"""Span correction at the recorded joints: bending between the wall supports (docs/bending.md).

A chain of rigid segments lying on the wall is nearly collinear, so its joint
moments miss what the pipe's own weight does between the points where it
touches the wall (about w L^2 / 12 over each support of a long row of equal
spans), and turn the stand-off of a stabilizer or a tool joint into a kink at a
few joints only. :func:`span_sample` records, quasi-statically at a sample and
without feeding anything back into the integrator, the continuous beam's moment
at each recorded joint less what the rigid chain already carries there, so
that joint moment + correction is the continuous pipe's moment, counted once
(docs/bending.md, "What the chain carries and what the span adds"):

1. Supports: the bit (s = 0) and every contact point of every active segment
   that penetrates the wall now (:func:`drillfatigue.dynamics.contact.wall.find_contact`
   from the point's hint, which it does not update), by distance from the bit;
   points closer than ``MERGE_M`` count once. With ``contact.deepest_point``
   a segment's deepest point between its tested points
   (:func:`drillfatigue.dynamics.contact.wall.deepest_point`) is a support where the
   contact kernel pushes on it (body penetration there above the tested
   points' largest). Each stands at its height: where the rigid wall puts the
   pipe's axis (hole radius - contact radius from the hole's axis, along the
   point's normal; the penalty penetration taken out), as a vector from the
   hole's axis beside it; the bit where it is.
2. Load per length, across the segment's axis, in the world frame: buoyed
   weight + lateral mud drag + the segment's lateral inertia -m_lat a / L.
   As the integrator moves the segment by a = F / m_lat (F all forces on
   it), the inertia is -F / L whatever the lateral mass, so the load is
   (weight + drag - F) / L: the part of the weight and drag that the
   concentrated wall and joint forces hold, smeared uniformly over the
   segment. At rest on its supports this is the weight. (The inertia of the
   segment's tilting, a load varying linearly along it, is not included.)
   A segment in line contact gets none in the beam (the wall carries its load
   along its length) and its two ends are supports (on the wall):

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
     segment's ends.
3. Axial force of a segment: the mean effective tension of its two joints
   (the bit end of the first segment takes its one joint's value).
4. The beam: :func:`drillfatigue.dynamics.span.bending.chain_span_moments_settled`
   with both chain ends pinned and the supports' offsets (their chord
   rotations: settlement terms), once for the world (x, y) components and once
   for z. Offsets relative to the hole's axis leave the hole's own curvature
   out of the beam: it stays with the chain.
5. The wall is one-sided. An interior wall support the beam would pull from
   the wall (:func:`_most_pulled`) is let go of and the beam solved again, up to
   ``MAX_RELEASES`` times. Where the elastic pipe's middle between two supports
   (chord's middle plus its mid-span sag,
   :func:`~drillfatigue.dynamics.span.bending.midspan_offset`) passes the wall
   by more than ``SPLIT_TOL_M`` (spans of ``MIN_SPLIT_SPAN_M`` or more), or a
   span is at its Euler load in compression (v >= ``BUCKLED_V``), the pipe lies
   on the wall there: a support is added at that span's middle (on the wall)
   and the chain solved again, up to ``MAX_SPLIT_ROUNDS`` times; a mid-span
   support let go of is not added again in that sample (it would cycle). This
   bounds the beam-column's amplification in compression by the wall, as it is
   bounded in the hole. Which supports hold the pipe is decided under the
   segments' buoyed weight alone (step 2's load without the inertia and drag);
   the beam then carries step 2's whole load on those supports. The weight and
   the stand-offs set where a pipe rests on the wall; decided under the
   inertial load sample by sample, the support set followed the load's noise
   (the split/release iteration cycled in a quarter to a half of a drilling
   BHA's samples and stopped wherever its budget ran out). Under the whole
   load the wall still bounds the beam: where it takes a span's middle beyond
   the wall, a mid-span support is added there (up to ``MAX_SPLIT_ROUNDS``
   rounds, none let go of, so nothing can cycle), on the chord of its two
   neighbours: the chain does not touch the wall there (it would be a contact
   support), so it is a bound on the quasi-static beam, not a contact at a
   height, and adds no settlement. Where the weight has almost no lateral part
   (drill pipe near a kick-off) the weight leaves spans of tens of metres that
   the inertial load, ten to thirty times the weight there, would otherwise
   bend metres beyond the wall (q L^2 / 8 of a 20 m span: about 75 kN m in
   5 in drill pipe); put on the wall where the beam's middle passes it, such
   supports stood on opposite walls 1.7 m apart (87 kN m).
6. The span from the bit: from the bit end (guided on the hole's axis on
   bottom, free off bottom) the string reaches the wall at a tangency point,
   where it meets the wall with the wall's slope and the wall's curvature (the
   moment of that curvature, E I kappa, is in the rigid chain's joint moments):
   beyond it the pipe lies on the wall and holds no span moment. When the first
   support above the bit opens a segment in line contact (step 2), the span
   from the bit ends at the tangency length L_t (:func:`tangency_length_m`, the
   pendulum of Lubinski and Woods (1953) generalised to a curved hole, with r
   the bit end's distance from the wall: infinite when the bit lies on it)
   clipped to that first support, and is solved alone, pinned at both ends
   (zero span moment at the tangency); the rest of the chain is solved from
   that support on, pinned there.
7. What the chain carries:
   :func:`drillfatigue.dynamics.span.chain.chain_static_moments_in_hole`, the
   rigid chain's joint moments held at rest where it is at the bit, its top end
   and the points the wall pushes (step 1's, at the chain's positions), under
   its own transverse load per segment (step 2's before the line-contact rule),
   positions relative to the hole's axis at its nodes, kept inside the hole (a
   node its solution puts beyond the wall is held on it). At rest this is its
   recorded joint moment; on its contact holds alone a free run of drill pipe
   in compression near its buckling load took moments of 1e6 N m, metres
   outside the hole.
8. The correction is the beam's moment less the chain's, put together as world
   vectors and resolved in each recorded joint's frame (the mid-rotation frame
   of its two segments, the frame of ``bending_x/y_Nm``, which turns with the
   pipe, so the correction alternates once per revolution), in that joint
   moment's sign convention (the moment of the upper part on the lower, z
   downhole: :mod:`drillfatigue.dynamics.core.joints`). A joint outside the beam's
   supports or in a span the beam cuts gets none.

Validity (see :mod:`drillfatigue.dynamics.span.bending`): small deflections,
supports that do not move relative to each other under the load. A span
still at or beyond its Euler load after the last round (or one the solution
cannot handle) is handled locally by
:func:`drillfatigue.dynamics.span.bending.chain_span_moments_settled`: the chain
is cut there, pinned over that span's supports, the span gets no correction
and every other span is solved as in the chain without it; the number of
such spans is returned (the caller counts them and the samples that had
any), so a buckled span far away never zeroes a joint's correction.
Arrays read: ``s.x, s.v, s.q, s.Fw, s.hint, s.cst``, ``p.seg, p.jp, p.wall, p.cpar,
p.cp_n, p.cp, p.ei``, ``wk.loads``; scratch allocated per call (a sample is taken
every few hundred steps).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.dynamics.contact.wall import (
    OUT_DELTA, OUT_DIST, OUT_NX, OUT_SIZE, contact_point, deepest_point, find_contact,
)
from drillfatigue.dynamics.core.layout import (
    CS_SQF, CS_SQON, J_KB, MAX_CONTACT_POINTS, MAX_TABLE_POINTS, P_CPTAB, P_DEEP, P_NPTS,
    P_SPANDYN, S_CL, S_H, S_RB, S_W,
)
from drillfatigue.dynamics.core.rigid import quat_conj_mul, quat_mul, quat_to_rot
from drillfatigue.dynamics.span.bending import (
    END_PINNED, STATUS_OK, STATUS_SPAN_BUCKLED, chain_span_moments_settled,
    midspan_offset,
)
from drillfatigue.dynamics.span.chain import chain_static_moments_in_hole, segment_of
from drillfatigue.dynamics.span.modal import segment_axial_N

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
    """The joint frame of :func:`drillfatigue.dynamics.core.joints.joint_force`: the lower
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


#: rounds of mid-span supports added where a span touches the wall or buckles (each
#: round halves the offending spans). Releases merge spans, up to a free run of the
#: whole chain (hundreds of metres of drill pipe off the wall): halving 1 km down to
#: ``MIN_SPLIT_SPAN_M`` takes 10 rounds, and splits alternate with releases. With
#: fewer (4) a span merged by late releases kept its middle metres beyond the wall and
#: carried q L^2 / 8 of a 40 m span (1e5 N m) for one sample
MAX_SPLIT_ROUNDS = 16
#: wall supports the continuous beam would pull from the wall that are let go of, at
#: most, in one sample (one per solve, the most pulled first; a drilling BHA with its
#: drill pipe needs up to about 100 when no mid-span support is split again where one
#: was let go of)
MAX_RELEASES = 128
#: a wall support is let go of when the beam pulls it from the wall by more than this
#: share of the largest span load q L (round-off of a support that carries nothing)
RELEASE_TOL = 1e-9
#: a span's middle reaches the wall when it passes it by more than this, m (round-off
#: of a beam lying along the wall between supports on it is not a contact). A pipe
#: lying on a straight wall is then held every (384 EI tol / q)^(1/4) at most (2.2 m
#: for 6 3/4 in collars: its span moment there below q s^2 / 12 = 0.15 kN m once split)
SPLIT_TOL_M = 1e-5
#: spans shorter than this are not split, m (Euler-Bernoulli spans much longer than
#: the pipe; a span of 9 m is split three times at most)
MIN_SPLIT_SPAN_M = 1.0
#: internal: the supports were changed, solve again
STATUS_SPLIT = -1
#: ``may_split`` of :func:`_solve_or_split`: a mid-span support stands on the wall where
#: the span's middle passes it (the weight's supports; True), or on the chord of its two
#: neighbours (the bound the wall puts on the beam under the whole load)
SPLIT_ON_WALL = 1
SPLIT_ON_CHORD = 2
#: what a round of :func:`_solve_or_split` did
ACT_NONE = 0
ACT_SPLIT = 1
ACT_RELEASE = 2


@njit(cache=True)
def _offsets(sup_v, d_xy, d_z):
    """Support offsets of the (x, y) and z solves from the supports' positions relative
    to the hole's axis (world components, m), taken from the first support's (only
    their chord rotations matter)."""
    for k in range(sup_v.shape[0]):
        d_xy[k, 0] = sup_v[k, 0] - sup_v[0, 0]
        d_xy[k, 1] = sup_v[k, 1] - sup_v[0, 1]
        d_z[k, 0] = sup_v[k, 2] - sup_v[0, 2]
        d_z[k, 1] = 0.0


@njit(cache=True)
def _span_means(sup_c, top_s, seg_v, out):
    """Length-weighted mean of a per-segment quantity ``seg_v`` (n, k) over each span
    between the supports ``sup_c``, into ``out`` (m - 1, k)."""
    n = seg_v.shape[0]
    for k in range(sup_c.shape[0] - 1):
        a = sup_c[k]
        b = sup_c[k + 1]
        for c in range(seg_v.shape[1]):
            out[k, c] = 0.0
        i = segment_of(top_s, a)
        while i < n and top_s[i] < b:
            w = min(b, top_s[i + 1]) - max(a, top_s[i])
            if w > 0.0:
                for c in range(seg_v.shape[1]):
                    out[k, c] += w * seg_v[i, c]
            i += 1
        for c in range(seg_v.shape[1]):
            out[k, c] /= (b - a)


@njit(cache=True)
def _most_pulled(sup_n, span_L, span_T, span_q, span_qz, span_qw, sup_M, sup_Mz, d_xy, d_z):
    """The interior wall support the continuous beam pulls from the wall the most, or -1.

    The reaction of support k on the beam, per world component, is the jump of the
    lateral force S = M' + T w' (M sagging positive, w the offset: (M' + T w')' = -q for
    EI w'''' - T w'' = q), which integrated over a span gives S(0) = (M_b - M_a)/L
    + T psi + q L/2 at its first support and S(L) = S(0) - q L at its second (psi the
    chord rotation). ``span_qw`` is the load the wall carries along segments in line
    contact (their span load is zero): half of it on each span pushes its two
    supports, so a collar lying on the wall is let go of only where the beam pulls it
    harder than its weight presses it there. The wall can only push towards the hole's
    axis: a reaction along the outward normal ``sup_n`` (zero: a two-sided support,
    the bit) pulls."""
    m = sup_n.shape[0]
    scale = 1.0
    for i in range(m - 1):
        qq = math.sqrt(span_q[i, 0] ** 2 + span_q[i, 1] ** 2 + span_qz[i, 0] ** 2
                       + span_qw[i, 0] ** 2 + span_qw[i, 1] ** 2 + span_qw[i, 2] ** 2)
        scale = max(scale, qq * span_L[i])
    worst = -1
    most = RELEASE_TOL * scale
    for k in range(1, m - 1):
        if sup_n[k, 0] == 0.0 and sup_n[k, 1] == 0.0 and sup_n[k, 2] == 0.0:
            continue
        pull = 0.0
        for c in range(3):
            if c == 0:
                ma, mb, mc = -sup_M[k - 1, 1], -sup_M[k, 1], -sup_M[k + 1, 1]
                qa, qb = span_q[k - 1, 0], span_q[k, 0]
                da, db, dc = d_xy[k - 1, 0], d_xy[k, 0], d_xy[k + 1, 0]
            elif c == 1:
                ma, mb, mc = sup_M[k - 1, 0], sup_M[k, 0], sup_M[k + 1, 0]
                qa, qb = span_q[k - 1, 1], span_q[k, 1]
                da, db, dc = d_xy[k - 1, 1], d_xy[k, 1], d_xy[k + 1, 1]
            else:
                ma, mb, mc = -sup_Mz[k - 1, 1], -sup_Mz[k, 1], -sup_Mz[k + 1, 1]
                qa, qb = span_qz[k - 1, 0], span_qz[k, 0]
                da, db, dc = d_z[k - 1, 0], d_z[k, 0], d_z[k + 1, 0]
            La = span_L[k - 1]
            Lb = span_L[k]
            s_end = (mb - ma) / La + span_T[k - 1] * (db - da) / La - 0.5 * qa * La
            s_start = (mc - mb) / Lb + span_T[k] * (dc - db) / Lb + 0.5 * qb * Lb
            R = s_end - s_start - 0.5 * (span_qw[k - 1, c] * La + span_qw[k, c] * Lb)
            pull += R * sup_n[k, c]
        if pull > most:
            most = pull
            worst = k
    return worst


@njit(cache=True)
def _solve_or_split(sup_c, sup_v, sup_n, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_qw, seg_rb,
                    seg_Rh, read_s, rxy, rz, rok, may_split, may_release, banned):
    """Solve the chain on supports ``sup_c`` standing at ``sup_v`` (their positions
    relative to the hole's axis; spans the solution cannot hold are cut,
    :func:`~drillfatigue.dynamics.span.bending.chain_span_moments_settled`), then check
    the solution against the wall (module docstring, step 5).

    With ``may_release``, an interior wall support (outward normal ``sup_n`` not zero)
    that the beam pulls from the wall is let go of (the most pulled one). Else, with
    ``may_split``, where a span is at its Euler load in compression, or its middle
    (the chord's middle plus the mid-span deflection, relative to the hole's axis) lies
    beyond the wall by more than ``SPLIT_TOL_M`` (hole radius ``seg_Rh`` less body radius
    ``seg_rb`` of the segment there), the elastic pipe lies on the wall there: a support
    is added at that span's middle (on the wall, radially, with the wall's normal; at
    the chord's middle and two-sided for a buckled span). Returns ``(status, supports,
    positions, normals, cut, action)``: ``STATUS_SPLIT`` and ``ACT_RELEASE`` or
    ``ACT_SPLIT`` when the supports changed, else the solve's status and ``ACT_NONE``
    with the per-span cut codes and ``rok`` the read points solved."""
    m = sup_c.shape[0]
    span_L = np.zeros(m - 1)
    span_ei = np.zeros(m - 1)
    span_T = np.zeros(m - 1)
    span_q = np.zeros((m - 1, 2))
    span_qz = np.zeros((m - 1, 2))
    work = np.zeros((m, 6))
    sup_M = np.zeros((m, 2))
    sup_Mz = np.zeros((m, 2))
    d_xy = np.zeros((m, 2))
    d_z = np.zeros((m, 2))
    _offsets(sup_v, d_xy, d_z)
    cut = np.zeros(m - 1, dtype=np.int64)
    rok_z = np.zeros(rok.shape[0], dtype=np.int64)
    st = chain_span_moments_settled(sup_c, d_xy, top_s, seg_ei, seg_T, seg_q, END_PINNED,
                                    END_PINNED, read_s, span_L, span_ei, span_T, span_q, work,
                                    sup_M, rxy, cut, rok)
    if st != STATUS_OK:
        return st, sup_c, sup_v, sup_n, cut, ACT_NONE
    # same spans, axial forces and stiffness: the same spans are cut
    st = chain_span_moments_settled(sup_c, d_z, top_s, seg_ei, seg_T, seg_qz, END_PINNED,
                                    END_PINNED, read_s, span_L, span_ei, span_T, span_qz, work,
                                    sup_Mz, rz, cut, rok_z)
    if st != STATUS_OK:
        return st, sup_c, sup_v, sup_n, cut, ACT_NONE
    any_cut = False
    for k in range(m - 1):
        if cut[k] != STATUS_OK:
            any_cut = True
    if may_release and not any_cut and m > 2:
        span_qw = np.zeros((m - 1, 3))
        _span_means(sup_c, top_s, seg_qw, span_qw)
        k = _most_pulled(sup_n, span_L, span_T, span_q, span_qz, span_qw, sup_M, sup_Mz, d_xy,
                         d_z)
        if k >= 0:
            out = np.zeros(m - 1)
            out_v = np.zeros((m - 1, 3))
            out_n = np.zeros((m - 1, 3))
            j = 0
            for kk in range(m):
                if kk == k:
                    continue
                out[j] = sup_c[kk]
                for c in range(3):
                    out_v[j, c] = sup_v[kk, c]
                    out_n[j, c] = sup_n[kk, c]
                j += 1
            return STATUS_SPLIT, out, out_v, out_n, cut, ACT_RELEASE
    if not may_split:
        return st, sup_c, sup_v, sup_n, cut, ACT_NONE
    split = np.zeros(m - 1, dtype=np.bool_)
    new_v = np.zeros((m - 1, 3))
    new_n = np.zeros((m - 1, 3))
    nsplit = 0
    for k in range(m - 1):
        if cut[k] == STATUS_SPAN_BUCKLED and span_L[k] > 2.0 * MERGE_M:
            split[k] = True
            nsplit += 1
            for c in range(3):
                new_v[k, c] = 0.5 * (sup_v[k, c] + sup_v[k + 1, c])
    if not any_cut:
        w_xy = np.zeros((m - 1, 2))
        w_z = np.zeros((m - 1, 2))
        if (midspan_offset(span_L, span_ei, span_T, span_q, sup_M, w_xy) == STATUS_OK
                and midspan_offset(span_L, span_ei, span_T, span_qz, sup_Mz, w_z) == STATUS_OK):
            V = np.zeros(3)
            for k in range(m - 1):
                if not span_L[k] >= MIN_SPLIT_SPAN_M:
                    continue
                s_mid = 0.5 * (sup_c[k] + sup_c[k + 1])
                again = False
                for b in range(banned.shape[0]):
                    if abs(banned[b] - s_mid) < MERGE_M:
                        again = True
                if again:
                    continue
                V[0] = 0.5 * (sup_v[k, 0] + sup_v[k + 1, 0]) + w_xy[k, 0]
                V[1] = 0.5 * (sup_v[k, 1] + sup_v[k + 1, 1]) + w_xy[k, 1]
                V[2] = 0.5 * (sup_v[k, 2] + sup_v[k + 1, 2]) + w_z[k, 0]
                i = segment_of(top_s, 0.5 * (sup_c[k] + sup_c[k + 1]))
                room = seg_Rh[i] - seg_rb[i]
                dist = math.sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2])
                if dist - room > SPLIT_TOL_M:
                    split[k] = True
                    nsplit += 1
                    if may_split == SPLIT_ON_CHORD:
                        # a bound, not a contact: on its neighbours' chord, no settlement
                        for c in range(3):
                            new_v[k, c] = 0.5 * (sup_v[k, c] + sup_v[k + 1, c])
                    else:
                        for c in range(3):
                            new_n[k, c] = V[c] / dist
                            new_v[k, c] = room * new_n[k, c]
    if nsplit == 0:
        return st, sup_c, sup_v, sup_n, cut, ACT_NONE
    out = np.zeros(m + nsplit)
    out_v = np.zeros((m + nsplit, 3))
    out_n = np.zeros((m + nsplit, 3))
    j = 0
    for k in range(m):
        out[j] = sup_c[k]
        for c in range(3):
            out_v[j, c] = sup_v[k, c]
            out_n[j, c] = sup_n[k, c]
        j += 1
        if k < m - 1 and split[k]:
            out[j] = 0.5 * (sup_c[k] + sup_c[k + 1])
            for c in range(3):
                out_v[j, c] = new_v[k, c]
                out_n[j, c] = new_n[k, c]
            j += 1
    return STATUS_SPLIT, out, out_v, out_n, cut, ACT_SPLIT


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
def _solve_chain(sup_c, sup_v, sup_n, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_qw, seg_rb,
                 seg_Rh, read_s, rxy, rz, rok, dec_q, dec_qz, dec_qw):
    """The chain on supports ``sup_c`` at ``sup_v`` (outward wall normals ``sup_n``)
    pinned at both ends, with the wall supports the beam pulls let go of and mid-span
    supports added where a span reaches the wall or buckles (module docstring, step 5),
    decided under the loads ``dec_q``, ``dec_qz``, ``dec_qw``, then solved under
    ``seg_q``, ``seg_qz`` on the supports so found, with mid-span supports added on
    their neighbours' chord where that load takes a span's middle beyond the wall
    (none let go of):
    ``(status, cut)`` with the read moments in ``rxy``, ``rz`` and the read points
    solved flagged in ``rok``."""
    st = STATUS_OK
    cut = np.zeros(sup_c.shape[0] - 1, dtype=np.int64)
    rounds = 0
    releases = 0
    # mid-span supports added, and those let go of: no mid-span support is added there
    # again in this sample (one at a span's middle that the beam pulls means the pipe
    # touches the wall elsewhere in that span; let go of and split again it would cycle)
    added = np.zeros(0)
    banned = np.zeros(MAX_RELEASES)
    nban = 0
    while True:
        old_c = sup_c
        st, sup_c, sup_v, sup_n, cut, act = _solve_or_split(
            sup_c, sup_v, sup_n, top_s, seg_ei, seg_T, dec_q, dec_qz, dec_qw, seg_rb, seg_Rh,
            read_s, rxy, rz, rok, SPLIT_ON_WALL if rounds < MAX_SPLIT_ROUNDS else 0,
            releases < MAX_RELEASES,
            banned[:nban])
        if act == ACT_RELEASE:
            # the one support let go of: the first of the old ones missing from the new
            k = 0
            while k < sup_c.shape[0] and old_c[k] == sup_c[k]:
                k += 1
            for a in range(added.shape[0]):
                if added[a] == old_c[k]:
                    banned[nban] = old_c[k]
                    nban += 1
                    break
            releases += 1
        elif act == ACT_SPLIT:
            # the new ones: those of the new supports not among the old
            more = np.zeros(sup_c.shape[0] - old_c.shape[0])
            j = 0
            k = 0
            for a in range(sup_c.shape[0]):
                if k < old_c.shape[0] and sup_c[a] == old_c[k]:
                    k += 1
                else:
                    more[j] = sup_c[a]
                    j += 1
            added = np.concatenate((added, more))
            rounds += 1
        else:
            break
    if st != STATUS_OK:
        return st, cut
    # the whole load on those supports, bounded by the wall: where it takes a span's middle
    # beyond the wall a mid-span support on the chord of its neighbours (none let go of)
    for _r in range(MAX_SPLIT_ROUNDS + 1):
        st, sup_c, sup_v, sup_n, cut, act = _solve_or_split(
            sup_c, sup_v, sup_n, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_qw, seg_rb, seg_Rh,
            read_s, rxy, rz, rok, SPLIT_ON_CHORD if _r < MAX_SPLIT_ROUNDS else 0, False,
            banned[:0])
        if act == ACT_NONE:
            break
    return st, cut


@njit(cache=True)
def span_sample(n, s, p, wk, sel, out):
    """Span correction at the joints ``sel`` now: ``out[a] = (M_x, M_y)`` in joint
    ``sel[a]``'s frame and in the convention of its recorded joint moment
    (``bending_x/y_Nm``), N m: the continuous beam's moment there less the rigid
    chain's own quasi-static moment (module docstring).

    Returns the number of spans handled locally (no correction in them, the chain
    cut there), or minus a status code when no span could be solved or the chain's
    static moments could not be found (every ``out`` zero)."""
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
    seg_qs = np.zeros((n, 2))
    seg_qzs = np.zeros((n, 2))
    seg_T = np.zeros(n)
    seg_ei = np.zeros(n)
    seg_rb = np.zeros(n)
    seg_Rh = np.zeros(n)
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
        # the buoyed weight alone across the axis: the load that decides the supports
        gw = seg[i, S_W] * ez
        seg_qs[i, 0] = -gw * ex * inv_l
        seg_qs[i, 1] = -gw * ey * inv_l
        seg_qzs[i, 0] = (seg[i, S_W] - gw * ez) * inv_l
        seg_T[i] = segment_axial_N(i, n, loads)
        seg_ei[i] = p.ei[i]
        seg_rb[i] = seg[i, S_RB]
        h0 = hint[MAX_CONTACT_POINTS * i]
        seg_Rh[i] = rad[h0] if 0 <= h0 < rad.shape[0] else rad.min()
    # the load the rigid chain carries (before the line-contact rule hands a segment's
    # load to the wall)
    q3 = np.zeros((n, 3))
    for i in range(n):
        q3[i, 0] = seg_q[i, 0]
        q3[i, 1] = seg_q[i, 1]
        q3[i, 2] = seg_qz[i, 0]
    # the hole's axis beside each node (segment end) of the chain: the foot of the
    # perpendicular from the node; positions are taken relative to it (module docstring)
    X = np.zeros(3)
    info = np.zeros(OUT_SIZE)
    C_node = np.zeros((n + 1, 3))
    # each node's hole radius, where it is relative to the hole's axis now, and its
    # largest contact radius (the body's, or a tool joint's or blade's at the segment end)
    node_R = np.zeros(n + 1)
    node_now = np.zeros((n + 1, 3))
    node_r = np.zeros(n + 1)
    for i in range(n):
        node_r[i] = max(node_r[i], seg[i, S_RB])
        node_r[i + 1] = max(node_r[i + 1], seg[i, S_RB])
    for j in range(n + 1):
        if j == 0:
            for k in range(3):
                X[k] = x[0, k] + seg[0, S_H] * R[0, k, 2]
        elif j == n:
            for k in range(3):
                X[k] = x[n - 1, k] - seg[n - 1, S_H] * R[n - 1, k, 2]
        else:
            for k in range(3):
                X[k] = 0.5 * (x[j - 1, k] - seg[j - 1, S_H] * R[j - 1, k, 2]
                              + x[j, k] + seg[j, S_H] * R[j, k, 2])
        ic = find_contact(X, seg[min(j, n - 1), S_RB], p0, axc, lnc, rad,
                          hint[MAX_CONTACT_POINTS * min(j, n - 1)], info)
        node_R[j] = rad[ic] if ic >= 0 else rad.min()
        for k in range(3):
            C_node[j, k] = X[k] - info[OUT_DIST] * info[OUT_NX + k]
            node_now[j, k] = info[OUT_DIST] * info[OUT_NX + k]
    # supports of the continuous beam (sup, at their true positions supP: a point in or
    # along the wall where the rigid wall puts the pipe's axis, the bit where it is) and
    # holds of the rigid chain (hold, where the chain is: the bit, the points the wall
    # pushes, the top end)
    cap = 2 + n * (MAX_TABLE_POINTS + 1)
    sup = np.zeros(cap)
    supP = np.zeros((cap, 3))
    supN = np.zeros((cap, 3))
    hold = np.zeros(cap)
    holdY = np.zeros((cap, 3))
    hold[1] = top_s[n]
    for k in range(3):
        holdY[0, k] = x[0, k] + seg[0, S_H] * R[0, k, 2]
        supP[0, k] = holdY[0, k] - C_node[0, k]
        holdY[1, k] = x[n - 1, k] - seg[n - 1, S_H] * R[n - 1, k, 2]
    nsup = 1
    nhold = 2
    npmax = MAX_TABLE_POINTS + MAX_CONTACT_POINTS
    pt_u = np.zeros(npmax)
    pt_gap = np.zeros(npmax)
    pt_g = np.zeros(npmax)
    pt_hint = np.zeros(npmax, dtype=np.int64)
    pt_n = np.zeros((npmax, 3))
    pt_W = np.zeros((npmax, 3))
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
            if off >= h - MERGE_M:
                node_r[i] = max(node_r[i], rc)
            elif off <= -h + MERGE_M:
                node_r[i + 1] = max(node_r[i + 1], rc)
            pt_gap[pt] = -info[OUT_DELTA]
            # where the rigid wall puts the pipe's axis there, from the hole's axis
            rw = info[OUT_DIST] - info[OUT_DELTA]
            for k in range(3):
                pt_n[pt, k] = info[OUT_NX + k]
                pt_W[pt, k] = rw * info[OUT_NX + k]
            if i == 0 and off >= h - MERGE_M:
                bit_gap = -info[OUT_DELTA]
            if info[OUT_DELTA] > 0.0:
                sup[nsup] = top_s[i] + h - off
                hold[nhold] = sup[nsup]
                for k in range(3):
                    supP[nsup, k] = pt_W[pt, k]
                    supN[nsup, k] = info[OUT_NX + k]
                    holdY[nhold, k] = X[k]
                nsup += 1
                nhold += 1
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
                    hold[nhold] = sup[nsup]
                    rw = info[OUT_DIST] - info[OUT_DELTA]
                    for k in range(3):
                        supP[nsup, k] = rw * info[OUT_NX + k]
                        supN[nsup, k] = info[OUT_NX + k]
                        holdY[nhold, k] = X[k]
                    nsup += 1
                    nhold += 1
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
                    # the touching points are supports already; of the others the
                    # segment's ends (at a joint: the neighbour's chord meets it there).
                    # Points inside a rigid segment lie on its chord, and the beam on
                    # supports a metre apart would turn the chain's kinks at the joints
                    # between them into moments several times the chain's own
                    if pt_gap[pt] >= 0.0 and abs(pt_u[pt]) >= h - MERGE_M:
                        # the pipe lies on the wall there: its axis where the wall puts it
                        sup[nsup] = top_s[i] + h - pt_u[pt]
                        for k in range(3):
                            supP[nsup, k] = pt_W[pt, k]
                            supN[nsup, k] = pt_n[pt, k]
                        nsup += 1
        seg_line[i] = line
        if line:
            # line contact: the wall carries the segment's weight along its length
            seg_q[i, 0] = 0.0
            seg_q[i, 1] = 0.0
            seg_qz[i, 0] = 0.0
            seg_qs[i, 0] = 0.0
            seg_qs[i, 1] = 0.0
            seg_qzs[i, 0] = 0.0
    # the load the wall carries along segments in line contact (for the supports' check)
    seg_qw = np.zeros((n, 3))
    seg_qws = np.zeros((n, 3))
    for i in range(n):
        seg_qw[i, 0] = q3[i, 0] - seg_q[i, 0]
        seg_qw[i, 1] = q3[i, 1] - seg_q[i, 1]
        seg_qw[i, 2] = q3[i, 2] - seg_qz[i, 0]
        if seg_line[i]:
            inv_l = 1.0 / (2.0 * seg[i, S_H])
            gw = seg[i, S_W] * R[i, 2, 2]
            seg_qws[i, 0] = -gw * R[i, 0, 2] * inv_l
            seg_qws[i, 1] = -gw * R[i, 1, 2] * inv_l
            seg_qws[i, 2] = (seg[i, S_W] - gw * R[i, 2, 2]) * inv_l
    # clipped to the chain before merging, so that the kept supports stay strictly increasing
    sup_s = np.minimum(np.maximum(sup[:nsup], 0.0), top_s[n])
    order = np.argsort(sup_s, kind="mergesort")
    keep = np.zeros(nsup, dtype=np.bool_)
    last = -1.0
    m = 0
    kept = 0
    for kk in range(nsup):
        k = order[kk]
        if kk == 0 or sup_s[k] - last > MERGE_M:
            keep[kk] = True
            last = sup_s[k]
            kept = k
            m += 1
        elif supN[kept, 0] == 0.0 and supN[kept, 1] == 0.0 and supN[kept, 2] == 0.0:
            # the bit where a point of it is in the wall: the wall holds the pipe there
            for c in range(3):
                supP[kept, c] = supP[k, c]
                supN[kept, c] = supN[k, c]
    if m < 2:
        return 0
    sup_c = np.zeros(m)
    sup_Pc = np.zeros((m, 3))
    sup_Nc = np.zeros((m, 3))
    j = 0
    for kk in range(nsup):
        if keep[kk]:
            sup_c[j] = sup_s[order[kk]]
            for c in range(3):
                sup_Pc[j, c] = supP[order[kk], c]
                sup_Nc[j, c] = supN[order[kk], c]
            j += 1
    nr = sel.size
    read_s = np.zeros(nr)
    for a in range(nr):
        read_s[a] = top_s[min(sel[a], n - 1) + 1]
    rxy = np.zeros((nr, 2))
    rz = np.zeros((nr, 2))
    rok = np.zeros(nr, dtype=np.int64)
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
        # a tangency within MERGE_M of the bit leaves no span there (zero moments); a
        # single span pinned at both ends takes no moment from its ends' offsets
        if bit_span[1] > MERGE_M:
            st, cut = _solve_chain(bit_span, np.zeros((2, 3)), np.zeros((2, 3)), top_s, seg_ei,
                                   seg_T, seg_q, seg_qz, seg_qw, seg_rb, seg_Rh, read_s, rxy,
                                   rz, rok, seg_qs, seg_qzs, seg_qws)
            if st != STATUS_OK:
                return -st
            for k in range(cut.shape[0]):
                if cut[k] != STATUS_OK:
                    n_cut += 1
        if m > 2:
            rxy2 = np.zeros((nr, 2))
            rz2 = np.zeros((nr, 2))
            rok2 = np.zeros(nr, dtype=np.int64)
            st, cut = _solve_chain(sup_c[1:].copy(), sup_Pc[1:].copy(), sup_Nc[1:].copy(), top_s,
                                   seg_ei, seg_T, seg_q, seg_qz, seg_qw, seg_rb, seg_Rh,
                                   read_s, rxy2, rz2, rok2, seg_qs, seg_qzs, seg_qws)
            if st != STATUS_OK:
                return -st
            # read points outside a chain's supports get zero from it
            for a in range(nr):
                for k in range(2):
                    rxy[a, k] += rxy2[a, k]
                    rz[a, k] += rz2[a, k]
                if rok2[a] != 0:
                    rok[a] = 1
            for k in range(cut.shape[0]):
                if cut[k] != STATUS_OK:
                    n_cut += 1
    else:
        st, cut = _solve_chain(sup_c, sup_Pc, sup_Nc, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_qw,
                               seg_rb, seg_Rh, read_s, rxy, rz, rok, seg_qs, seg_qzs, seg_qws)
        if st != STATUS_OK:
            return -st
        for k in range(cut.shape[0]):
            if cut[k] != STATUS_OK:
                n_cut += 1
    # what the rigid chain carries there now, quasi-statically: its joints' moments held
    # where it is at the bit, its top and the points the wall pushes, under the same load
    hs = hold[:nhold]
    ho = np.argsort(hs, kind="mergesort")
    hold_s = np.zeros(nhold)
    hold_y = np.zeros((nhold, 3))
    for kk in range(nhold):
        hold_s[kk] = min(max(hs[ho[kk]], 0.0), top_s[n])
        i = segment_of(top_s, hold_s[kk])
        xi = (hold_s[kk] - top_s[i]) / (top_s[i + 1] - top_s[i])
        for c in range(3):
            hold_y[kk, c] = holdY[ho[kk], c] - ((1.0 - xi) * C_node[i, c]
                                                 + xi * C_node[i + 1, c])
    k_joint = np.zeros(n - 1)
    for j in range(n - 1):
        k_joint[j] = p.jp[j, J_KB]
    ms_chain = np.zeros((n - 1, 3))
    # kept inside the hole, as the continuous beam is (span_chain): a free run between
    # holds near or beyond its buckling load would otherwise amplify its load without
    # bound, a moment no chain inside the hole can carry
    node_room = np.zeros(n + 1)
    for j in range(n + 1):
        node_room[j] = node_R[j] - node_r[j]
    n_held = np.zeros(2, dtype=np.int64)
    st = chain_static_moments_in_hole(top_s, k_joint, seg_T, q3, hold_s, hold_y, node_room,
                                      node_now, ms_chain, n_held)
    if st != STATUS_OK:
        return -st
    qr = np.zeros(4)
    qh = np.zeros(4)
    qm = np.zeros(4)
    Rm = np.zeros((3, 3))
    for a in range(nr):
        jj = sel[a]
        if jj >= n - 1 or rok[a] == 0:
            continue
        # sagging moments of the world components (span_bending's convention): the
        # continuous beam's less the chain's
        msx = -rxy[a, 1] - ms_chain[jj, 0]
        msy = rxy[a, 0] - ms_chain[jj, 1]
        msz = -rz[a, 1] - ms_chain[jj, 2]
        _joint_frame(s.q[jj], s.q[jj + 1], qr, qh, qm, Rm)
        t0 = Rm[0, 2]
        t1 = Rm[1, 2]
        t2 = Rm[2, 2]
        # the moment of the upper part on the lower, sum_c M_c (t x e_c) with t the
        # joint's axis downhole: the recorded joint moment's convention (joints.py)
        mw0 = msz * t1 - msy * t2
        mw1 = msx * t2 - msz * t0
        mw2 = msy * t0 - msx * t1
        out[a, 0] = Rm[0, 0] * mw0 + Rm[1, 0] * mw1 + Rm[2, 0] * mw2
        out[a, 1] = Rm[0, 1] * mw0 + Rm[1, 1] * mw1 + Rm[2, 1] * mw2
    return n_cut
