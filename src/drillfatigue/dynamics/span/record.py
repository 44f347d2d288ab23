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
p.cp_n, p.cp, p.ei``, ``wk.loads``; scratch allocated once per call (a sample is
taken every few hundred steps) and shared by the beam's rounds of releases and splits,
which solve the (x, y) and z components together and read the moments at the joints
after the last round only.
"""

from __future__ import annotations

import math
from collections import namedtuple

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
    END_PINNED, STATUS_BAD_SPAN, STATUS_OK, STATUS_SPAN_BUCKLED, Spans, midspan_offset,
    read_moments, runs_support_moments, span_properties,
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
#: ``may_split`` of :func:`_solve_round`: a mid-span support stands on the wall where
#: the span's middle passes it (the weight's supports; True), or on the chord of its two
#: neighbours (the bound the wall puts on the beam under the whole load)
SPLIT_ON_WALL = 1
SPLIT_ON_CHORD = 2
#: what a round of :func:`_solve_round` did
ACT_NONE = 0
ACT_SPLIT = 1
ACT_RELEASE = 2


# The helpers of a round and of a segment's support search are inlined into their
# callers (``inline="always"``): a call hands every array of its bundles over one by one,
# which cost a segment's search more than its arithmetic.
#: the segments under one load (:func:`_solve_chain`): ends from the bit ``top_s``
#: (n + 1,), m; bending stiffness ``ei`` (n,), N m^2; axial force ``T`` (n,), N; the load
#: per length across each segment ``q`` (n, 3), N/m, world x, y, z; the part of it the
#: wall carries along segments in line contact ``qw`` (n, 3), N/m; and the room of the
#: body off the hole's axis ``room`` (n,), m (hole radius less body radius). Its first
#: four fields are a :class:`~drillfatigue.dynamics.span.bending.SegmentChain`'s.
SegLoad = namedtuple("SegLoad", ("top_s", "ei", "T", "q", "qw", "room"))
#: the beam solves' scratch of one chain (:func:`_solve_chain`), rows for up to as many
#: supports as ``c`` holds: supports ``c`` (from the bit, m, ``m[0]`` of them in use),
#: ``v`` (positions relative to the hole's axis, world, m), ``n`` (outward wall normals;
#: zero: a two-sided support), ``a`` (a mid-span support added where the weight's beam
#: reached the wall or buckled); their offsets ``d`` and moments ``M`` (columns: M_x and
#: M_y of the world (x, y) load, M_y of the z load, as the two solves of
#: :func:`~drillfatigue.dynamics.span.bending.chain_span_moments_settled`); the spans
#: ``sp`` (``q`` with the three world components), the wall's load per span ``qw``, the
#: spans' cut codes ``cut``, the tridiagonal scratch ``work``, the mid-span offsets
#: ``w``; the spans to split ``split`` with their new supports ``new_c, new_v, new_n``
ChainWork = namedtuple("ChainWork", ("c", "v", "n", "a", "d", "M", "sp", "qw", "cut", "work",
                                     "w", "split", "new_c", "new_v", "new_n", "m"))


@njit(cache=True)
def _chain_work(cap):
    """A :data:`ChainWork` for up to ``cap`` supports, none in use."""
    return ChainWork(np.zeros(cap), np.zeros((cap, 3)), np.zeros((cap, 3)),
                     np.zeros(cap, dtype=np.bool_), np.zeros((cap, 3)), np.zeros((cap, 3)),
                     Spans(np.zeros(cap), np.zeros(cap), np.zeros(cap), np.zeros((cap, 3))),
                     np.zeros((cap, 3)), np.zeros(cap, dtype=np.int64), np.zeros((cap, 7)),
                     np.zeros((cap, 3)), np.zeros(cap, dtype=np.bool_), np.zeros(cap),
                     np.zeros((cap, 3)), np.zeros((cap, 3)), np.zeros(1, dtype=np.int64))


@njit(cache=True)
def _set_supports(cw, sup_c, sup_v, sup_n):
    """``cw`` (or a larger :data:`ChainWork`) holding the supports ``sup_c`` at ``sup_v``
    with normals ``sup_n``, none added."""
    m = sup_c.shape[0]
    if m > cw.c.shape[0]:
        cw = _chain_work(2 * m)
    for k in range(m):
        cw.c[k] = sup_c[k]
        cw.a[k] = False
        for c in range(3):
            cw.v[k, c] = sup_v[k, c]
            cw.n[k, c] = sup_n[k, c]
    cw.m[0] = m
    return cw


@njit(cache=True, inline="always")
def _offsets(cw, m):
    """Support offsets of the (x, y) and z solves (``cw.d``) from the supports' positions
    relative to the hole's axis (world components, m), taken from the first support's
    (only their chord rotations matter)."""
    v = cw.v
    d = cw.d
    for k in range(m):
        d[k, 0] = v[k, 0] - v[0, 0]
        d[k, 1] = v[k, 1] - v[0, 1]
        d[k, 2] = v[k, 2] - v[0, 2]


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


@njit(cache=True, inline="always")
def _most_pulled(cw, m):
    """The interior wall support the continuous beam pulls from the wall the most, or -1.

    The reaction of support k on the beam, per world component, is the jump of the
    lateral force S = M' + T w' (M sagging positive, w the offset: (M' + T w')' = -q for
    EI w'''' - T w'' = q), which integrated over a span gives S(0) = (M_b - M_a)/L
    + T psi + q L/2 at its first support and S(L) = S(0) - q L at its second (psi the
    chord rotation). ``cw.qw`` is the load the wall carries along segments in line
    contact (their span load is zero): half of it on each span pushes its two
    supports, so a collar lying on the wall is let go of only where the beam pulls it
    harder than its weight presses it there. The wall can only push towards the hole's
    axis: a reaction along the outward normal ``cw.n`` (zero: a two-sided support,
    the bit) pulls."""
    sup_n = cw.n
    span_L = cw.sp.L
    span_T = cw.sp.T
    span_q = cw.sp.q
    span_qw = cw.qw
    sup_M = cw.M
    d = cw.d
    scale = 1.0
    for i in range(m - 1):
        qq = math.sqrt(span_q[i, 0] ** 2 + span_q[i, 1] ** 2 + span_q[i, 2] ** 2
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
            elif c == 1:
                ma, mb, mc = sup_M[k - 1, 0], sup_M[k, 0], sup_M[k + 1, 0]
                qa, qb = span_q[k - 1, 1], span_q[k, 1]
            else:
                ma, mb, mc = -sup_M[k - 1, 2], -sup_M[k, 2], -sup_M[k + 1, 2]
                qa, qb = span_q[k - 1, 2], span_q[k, 2]
            da, db, dc = d[k - 1, c], d[k, c], d[k + 1, c]
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


@njit(cache=True, inline="always")
def _beam_moments(cw, sl):
    """The chain on the supports of ``cw`` under the load of ``sl`` (:data:`SegLoad`),
    pinned at both ends: the spans, their cut codes and the support moments of the
    (x, y) and z solves in ``cw`` (spans the solution cannot hold are cut,
    :func:`~drillfatigue.dynamics.span.bending.chain_span_moments_settled`; the two
    solves share their spans, axial forces and stiffness, so the same spans are cut).
    Returns the status of the solve."""
    m = cw.m[0]
    cut = cw.cut[:m - 1]
    cw.M[:m, :] = 0.0
    cut[:] = STATUS_OK
    if m < 2:
        return STATUS_OK
    if span_properties(cw.c[:m], sl, cw.sp, cut) != STATUS_OK:
        cut[:] = STATUS_BAD_SPAN
        return STATUS_BAD_SPAN
    _offsets(cw, m)
    runs_support_moments(cw.d[:m], True, cw.sp, END_PINNED, END_PINNED, cw.work[:m], cw.M[:m],
                         cut)
    return STATUS_OK


@njit(cache=True, inline="always")
def _release(cw, m, k, banned, nban):
    """Let go of support ``k`` of ``cw``; a mid-span support let go of is banned (no
    mid-span support is added there again in this sample: one at a span's middle that
    the beam pulls means the pipe touches the wall elsewhere in that span; let go of and
    split again it would cycle)."""
    cw_a = cw.a
    cw_c = cw.c
    cw_m = cw.m
    cw_n = cw.n
    cw_v = cw.v
    if cw_a[k]:
        banned[nban[0]] = cw_c[k]
        nban[0] += 1
    for kk in range(k, m - 1):
        cw_c[kk] = cw_c[kk + 1]
        cw_a[kk] = cw_a[kk + 1]
        for c in range(3):
            cw_v[kk, c] = cw_v[kk + 1, c]
            cw_n[kk, c] = cw_n[kk + 1, c]
    cw_m[0] = m - 1


@njit(cache=True, inline="always")
def _mark_splits(cw, m, sl, any_cut, may_split, banned, nban):
    """The spans of ``cw`` to split (``cw.split``, their new supports in ``cw.new_c,
    new_v, new_n``; :func:`_solve_round`): a span at its Euler load in compression, at its
    chord's middle, two-sided; else, where no span is cut, a span whose middle (the
    chord's middle plus the mid-span deflection, relative to the hole's axis) lies
    beyond the wall by more than ``SPLIT_TOL_M``, on the wall (``SPLIT_ON_WALL``: radially,
    with the wall's normal) or on its neighbours' chord (``SPLIT_ON_CHORD``). Returns how
    many."""
    cw_M = cw.M
    c = cw.c
    cw_cut = cw.cut
    cw_new_c = cw.new_c
    new_n = cw.new_n
    new_v = cw.new_v
    sp = cw.sp
    split = cw.split
    v = cw.v
    w = cw.w
    sl_room = sl.room
    sl_top_s = sl.top_s
    nsplit = 0
    for k in range(m - 1):
        split[k] = False
        cw_new_c[k] = 0.5 * (c[k] + c[k + 1])
        for cc in range(3):
            new_v[k, cc] = 0.0
            new_n[k, cc] = 0.0
        if cw_cut[k] == STATUS_SPAN_BUCKLED and sp.L[k] > 2.0 * MERGE_M:
            split[k] = True
            nsplit += 1
            for cc in range(3):
                new_v[k, cc] = 0.5 * (v[k, cc] + v[k + 1, cc])
    if any_cut:
        return nsplit
    if midspan_offset(sp.L[:m - 1], sp.ei[:m - 1], sp.T[:m - 1], sp.q[:m - 1], cw_M[:m],
                      w[:m - 1]) != STATUS_OK:
        return nsplit
    for k in range(m - 1):
        if not sp.L[k] >= MIN_SPLIT_SPAN_M:
            continue
        s_mid = 0.5 * (c[k] + c[k + 1])
        again = False
        for b in range(nban):
            if abs(banned[b] - s_mid) < MERGE_M:
                again = True
        if again:
            continue
        V0 = 0.5 * (v[k, 0] + v[k + 1, 0]) + w[k, 0]
        V1 = 0.5 * (v[k, 1] + v[k + 1, 1]) + w[k, 1]
        V2 = 0.5 * (v[k, 2] + v[k + 1, 2]) + w[k, 2]
        i = segment_of(sl_top_s, 0.5 * (c[k] + c[k + 1]))
        room = sl_room[i]
        dist = math.sqrt(V0 * V0 + V1 * V1 + V2 * V2)
        if dist - room > SPLIT_TOL_M:
            split[k] = True
            nsplit += 1
            if may_split == SPLIT_ON_CHORD:
                # a bound, not a contact: on its neighbours' chord, no settlement
                for cc in range(3):
                    new_v[k, cc] = 0.5 * (v[k, cc] + v[k + 1, cc])
            else:
                new_n[k, 0] = V0 / dist
                new_n[k, 1] = V1 / dist
                new_n[k, 2] = V2 / dist
                for cc in range(3):
                    new_v[k, cc] = room * new_n[k, cc]
    return nsplit


@njit(cache=True, inline="always")
def _insert_splits(src, dst, m, nsplit):
    """The supports of ``src`` with its marked spans' new supports (added) in order, into
    ``dst`` (``src`` itself, filled from the top down, or a larger one)."""
    dst_a = dst.a
    dst_c = dst.c
    dst_m = dst.m
    dst_n = dst.n
    dst_v = dst.v
    src_a = src.a
    src_c = src.c
    src_n = src.n
    src_new_c = src.new_c
    src_new_n = src.new_n
    src_new_v = src.new_v
    src_split = src.split
    src_v = src.v
    j = m + nsplit - 1
    for k in range(m - 1, -1, -1):
        if k < m - 1 and src_split[k]:
            dst_c[j] = src_new_c[k]
            dst_a[j] = True
            for c in range(3):
                dst_v[j, c] = src_new_v[k, c]
                dst_n[j, c] = src_new_n[k, c]
            j -= 1
        dst_c[j] = src_c[k]
        dst_a[j] = src_a[k]
        for c in range(3):
            dst_v[j, c] = src_v[k, c]
            dst_n[j, c] = src_n[k, c]
        j -= 1
    dst_m[0] = m + nsplit


@njit(cache=True)
def _solve_round(cw, sl, may_split, may_release, banned, nban):
    """Solve the chain on the supports of ``cw`` under ``sl`` (:func:`_beam_moments`),
    then check the solution against the wall (module docstring, step 5).

    With ``may_release``, an interior wall support (outward normal not zero) that the
    beam pulls from the wall is let go of (the most pulled one, :func:`_release`;
    ``banned[:nban[0]]`` the mid-span supports let go of so far). Else, with
    ``may_split`` (``SPLIT_ON_WALL`` or ``SPLIT_ON_CHORD``), mid-span supports are added
    where a span buckles or reaches the wall (:func:`_mark_splits`), none within
    ``MERGE_M`` of a banned one. Returns ``(status, action, cw)``: ``STATUS_SPLIT`` and
    ``ACT_RELEASE`` or ``ACT_SPLIT`` when the supports changed (``cw`` may be a larger
    one then), else the solve's status and ``ACT_NONE``."""
    m = cw.m[0]
    st = _beam_moments(cw, sl)
    if st != STATUS_OK:
        return st, ACT_NONE, cw
    any_cut = False
    for k in range(m - 1):
        if cw.cut[k] != STATUS_OK:
            any_cut = True
    if may_release and not any_cut and m > 2:
        _span_means(cw.c[:m], sl.top_s, sl.qw, cw.qw)
        k = _most_pulled(cw, m)
        if k >= 0:
            _release(cw, m, k, banned, nban)
            return STATUS_SPLIT, ACT_RELEASE, cw
    if not may_split:
        return st, ACT_NONE, cw
    nsplit = _mark_splits(cw, m, sl, any_cut, may_split, banned, nban[0])
    if nsplit == 0:
        return st, ACT_NONE, cw
    dst = cw if m + nsplit <= cw.c.shape[0] else _chain_work(2 * (m + nsplit))
    _insert_splits(cw, dst, m, nsplit)
    return STATUS_SPLIT, ACT_SPLIT, dst


@njit(cache=True)
def _solve_chain(cw, dec, sl, read_s, rd, rok):
    """The chain on the supports of ``cw`` pinned at both ends, with the wall supports
    the beam pulls let go of and mid-span supports added where a span reaches the wall
    or buckles (module docstring, step 5), decided under the load of ``dec``
    (:data:`SegLoad`), then solved under that of ``sl`` on the supports so found, with
    mid-span supports added on their neighbours' chord where that load takes a span's
    middle beyond the wall (none let go of).

    Returns ``(status, spans cut, cw)`` with the read moments at ``read_s`` in ``rd``
    (n_read, 3: M_x, M_y of the (x, y) load, M_y of the z load) and the read points
    solved flagged in ``rok`` (both written only with ``STATUS_OK``)."""
    rounds = 0
    releases = 0
    banned = np.zeros(MAX_RELEASES)
    nban = np.zeros(1, dtype=np.int64)
    while True:
        st, act, cw = _solve_round(cw, dec, SPLIT_ON_WALL if rounds < MAX_SPLIT_ROUNDS else 0,
                                   releases < MAX_RELEASES, banned, nban)
        if act == ACT_RELEASE:
            releases += 1
        elif act == ACT_SPLIT:
            rounds += 1
        else:
            break
    if st != STATUS_OK:
        return st, 0, cw
    # the whole load on those supports, bounded by the wall: where it takes a span's middle
    # beyond the wall a mid-span support on the chord of its neighbours (none let go of)
    none = np.zeros(1, dtype=np.int64)
    for _r in range(MAX_SPLIT_ROUNDS + 1):
        st, act, cw = _solve_round(cw, sl, SPLIT_ON_CHORD if _r < MAX_SPLIT_ROUNDS else 0, False,
                                   banned, none)
        if act == ACT_NONE:
            break
    if st != STATUS_OK:
        return st, 0, cw
    # the moments at the read points, of the last solve only (each round's supports
    # replace the last's)
    m = cw.m[0]
    rd[:, :] = 0.0
    rok[:] = 0
    read_moments(cw.c[:m], cw.sp, cw.M[:m], cw.cut[:m - 1], read_s, rd, rok)
    n_cut = 0
    for k in range(m - 1):
        if cw.cut[k] != STATUS_OK:
            n_cut += 1
    return st, n_cut, cw


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


#: one sample's per-segment arrays (:func:`_segment_loads`): segment ends from the bit
#: ``top_s`` (n + 1,), m; rotation matrices ``R`` (n, 3, 3); the load per length across
#: each segment ``q`` and the buoyed weight's alone ``qs`` (n, 3), N/m, world x, y, z
#: (zero for a segment in line contact); the load the rigid chain carries ``q3`` (``q``
#: before the line-contact rule); the parts of them the wall carries along segments in
#: line contact ``qw``, ``qws``; axial force ``T``, N; ``ei``, N m^2; the body's room off
#: the hole's axis ``room``, m; line contact ``line``
Segs = namedtuple("Segs", ("top_s", "R", "q", "qs", "q3", "qw", "qws", "T", "ei", "room",
                           "line"))
#: the hole beside each node (segment end) of the chain (:func:`_hole_nodes`): the foot
#: of the perpendicular from the node on the hole's axis ``C`` (n + 1, 3), m; the hole's
#: radius there ``R`` (n + 1,), m; where the node is relative to the hole's axis ``now``
#: (n + 1, 3), m; the node's largest contact radius ``r`` (n + 1,), m
Nodes = namedtuple("Nodes", ("C", "R", "now", "r"))
#: supports of the continuous beam and holds of the rigid chain (:func:`_find_supports`):
#: supports ``sup`` (from the bit, m) at ``P`` (where the rigid wall puts the pipe's
#: axis, relative to the hole's axis; the bit where it is) with outward wall normals
#: ``N``; holds ``hold`` (from the bit, m) where the chain is, ``Y`` (world, m: the bit,
#: the points the wall pushes, the top end); ``cnt`` (supports, holds) in use;
#: ``bit_gap`` (1,): the bit end's distance from the wall (the pendulum's offset r), m
Supports = namedtuple("Supports", ("sup", "P", "N", "hold", "Y", "cnt", "bit_gap"))
#: the tested points of one segment (:func:`_segment_supports`): offsets along its axis
#: ``u``, m; gap to the wall ``gap``, m; axis offset from the wall ``g``, m; cylinder
#: hints ``hint`` and found cylinders ``ic``; outward normals ``n``; where the rigid wall
#: puts the pipe's axis ``W`` (relative to the hole's axis), m
Points = namedtuple("Points", ("u", "gap", "g", "hint", "ic", "n", "W"))


@njit(cache=True)
def _new_scratch(n):
    """The per-sample scratch of ``n`` segments: (:data:`Segs`, :data:`Nodes`,
    :data:`Supports`, :data:`Points`)."""
    g = Segs(np.zeros(n + 1), np.zeros((n, 3, 3)), np.zeros((n, 3)), np.zeros((n, 3)),
             np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n), np.zeros(n),
             np.zeros(n), np.zeros(n, dtype=np.bool_))
    nd = Nodes(np.zeros((n + 1, 3)), np.zeros(n + 1), np.zeros((n + 1, 3)), np.zeros(n + 1))
    cap = 2 + n * (MAX_TABLE_POINTS + 1)
    sw = Supports(np.zeros(cap), np.zeros((cap, 3)), np.zeros((cap, 3)), np.zeros(cap),
                  np.zeros((cap, 3)), np.zeros(2, dtype=np.int64), np.zeros(1))
    npmax = MAX_TABLE_POINTS + MAX_CONTACT_POINTS
    pt = Points(np.zeros(npmax), np.zeros(npmax), np.zeros(npmax),
                np.zeros(npmax, dtype=np.int64), np.zeros(npmax, dtype=np.int64),
                np.zeros((npmax, 3)), np.zeros((npmax, 3)))
    return g, nd, sw, pt


@njit(cache=True)
def _segment_loads(n, s, p, wk, g):
    """Segment boundaries, axes, loads and properties (module docstring, steps 2-3)."""
    cpar = p.cpar
    p_ei = p.ei
    seg = p.seg
    p_wall = p.wall
    Fw = s.Fw
    cst = s.cst
    hint = s.hint
    s_q = s.q
    v = s.v
    R = g.R
    g_T = g.T
    g_ei = g.ei
    g_q = g.q
    g_q3 = g.q3
    g_qs = g.qs
    g_room = g.room
    top_s = g.top_s
    rad = p_wall[:, 7]
    loads = wk.loads
    for i in range(n):
        top_s[i + 1] = top_s[i] + 2.0 * seg[i, S_H]
    for i in range(n):
        quat_to_rot(s_q[i], R[i])
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
        g_q[i, 0] = (gx - ga * ex) * inv_l
        g_q[i, 1] = (gy - ga * ey) * inv_l
        g_q[i, 2] = (gz - ga * ez) * inv_l
        # the buoyed weight alone across the axis: the load that decides the supports
        gw = seg[i, S_W] * ez
        g_qs[i, 0] = -gw * ex * inv_l
        g_qs[i, 1] = -gw * ey * inv_l
        g_qs[i, 2] = (seg[i, S_W] - gw * ez) * inv_l
        g_T[i] = segment_axial_N(i, n, loads)
        g_ei[i] = p_ei[i]
        h0 = hint[MAX_CONTACT_POINTS * i]
        Rh = rad[h0] if 0 <= h0 < rad.shape[0] else rad.min()
        g_room[i] = Rh - seg[i, S_RB]
    # the load the rigid chain carries (before the line-contact rule hands a segment's
    # load to the wall)
    for i in range(n):
        for c in range(3):
            g_q3[i, c] = g_q[i, c]


@njit(cache=True)
def _hole_nodes(n, s, p, g, nd, X, info):
    """The hole's axis beside each node (segment end) of the chain: the foot of the
    perpendicular from the node; positions are taken relative to it (module docstring).
    Also each node's hole radius, where it is relative to the hole's axis now, and its
    contact radius so far (the body's)."""
    seg = p.seg
    wall = p.wall
    s_hint = s.hint
    x = s.x
    nd_C = nd.C
    nd_R = nd.R
    nd_now = nd.now
    node_r = nd.r
    R = g.R
    p0 = wall[:, 0:3]
    axc = wall[:, 3:6]
    lnc = wall[:, 6]
    rad = wall[:, 7]
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
                          s_hint[MAX_CONTACT_POINTS * min(j, n - 1)], info)
        nd_R[j] = rad[ic] if ic >= 0 else rad.min()
        for k in range(3):
            nd_C[j, k] = X[k] - info[OUT_DIST] * info[OUT_NX + k]
            nd_now[j, k] = info[OUT_DIST] * info[OUT_NX + k]


@njit(cache=True, inline="always")
def _add_support(sw, s_m, P, N, hold_Y):
    """A support at ``s_m`` (from the bit) standing at ``P`` with normal ``N`` (3-vectors);
    with ``hold_Y`` (not empty) a hold of the rigid chain there too, where it is."""
    sw_N = sw.N
    sw_P = sw.P
    sw_Y = sw.Y
    sw_cnt = sw.cnt
    sw_hold = sw.hold
    sw_sup = sw.sup
    k = sw_cnt[0]
    sw_sup[k] = s_m
    for c in range(3):
        sw_P[k, c] = P[c]
        sw_N[k, c] = N[c]
    sw_cnt[0] = k + 1
    if hold_Y.shape[0] > 0:
        h = sw_cnt[1]
        sw_hold[h] = s_m
        for c in range(3):
            sw_Y[h, c] = hold_Y[c]
        sw_cnt[1] = h + 1


@njit(cache=True, inline="always")
def _points_curvature(pt, npi, axc, lnc):
    """The largest hole curvature at the cylinders of a segment's points found in the
    chain (:func:`_hole_curvature`), in the points' order, 1/m."""
    kap = 0.0
    for k in range(npi):
        ic = pt.ic[k]
        if ic >= 0:
            kap = max(kap, _hole_curvature(axc, lnc, ic))
    return kap


@njit(cache=True, inline="always")
def _along_wall(i, npi, h, kap, top_s, sw, pt):
    """Whether segment ``i`` (half-length ``h``, hole curvature ``kap``, its ``npi`` points
    in ``pt``) lies along the wall of a curved hole (module docstring, step 2); if so its
    ends on the wall become supports."""
    pt_W = pt.W
    pt_gap = pt.gap
    pt_n = pt.n
    pt_u = pt.u
    # every point no further from the wall than the chord's offset from the arc there,
    # (h^2 - u^2) kappa / 2 resting on the outer wall (ends in it) or u^2 kappa / 2 on
    # the inner wall (middle in it). A segment whose bulge exceeds the clearance cannot
    # lie along one wall (it touches both; the hole-fit rule cuts segments so that it
    # does not)
    tol = CHORD_TOL * 0.5 * h * h * kap
    outer = True
    inner = True
    for k in range(npi):
        u2 = pt_u[k] * pt_u[k]
        if pt_gap[k] > 0.5 * (h * h - u2) * kap + tol:
            outer = False
        if pt_gap[k] > 0.5 * u2 * kap + tol:
            inner = False
    if not (outer or inner):
        return False
    for k in range(npi):
        # the touching points are supports already; of the others the segment's ends (at
        # a joint: the neighbour's chord meets it there). Points inside a rigid segment
        # lie on its chord, and the beam on supports a metre apart would turn the chain's
        # kinks at the joints between them into moments several times the chain's own
        if pt_gap[k] >= 0.0 and abs(pt_u[k]) >= h - MERGE_M:
            # the pipe lies on the wall there: its axis where the wall puts it
            _add_support(sw, top_s[i] + h - pt_u[k], pt_W[k], pt_n[k], pt_W[k, :0])
    return True


@njit(cache=True)
def _segment_supports(n, s, p, g, nd, sw, pt, X, info):
    """The supports and holds of each segment (module docstring, steps 1-2): its points
    that penetrate the wall (and its deepest point with ``contact.deepest_point``), its
    ends where it lies along the wall; its line contact in ``g.line[i]`` (its loads
    zeroed then), its points' contact radii at its nodes in ``nd.r``. The bundles' arrays
    are bound once, outside the segment loop (bound per segment, their reference counts
    cost as much as the search in a hole without contact)."""
    p_cp = p.cp
    p_cp_n = p.cp_n
    cpar = p.cpar
    seg = p.seg
    wall = p.wall
    hint = s.hint
    x = s.x
    R = g.R
    g_line = g.line
    g_q = g.q
    g_qs = g.qs
    top_s = g.top_s
    nd_r = nd.r
    pt_W = pt.W
    pt_g = pt.g
    pt_gap = pt.gap
    pt_hint = pt.hint
    pt_ic = pt.ic
    pt_n = pt.n
    pt_u = pt.u
    sw_bit_gap = sw.bit_gap
    p0 = wall[:, 0:3]
    axc = wall[:, 3:6]
    lnc = wall[:, 6]
    rad = wall[:, 7]
    tbase = MAX_CONTACT_POINTS * x.shape[0]
    for i in range(n):
        own = cpar[P_CPTAB] != 0.0 and i < n - 1
        npi = int(p_cp_n[i]) if own else int(cpar[P_NPTS])
        h = seg[i, S_H]
        ncon = 0
        clr = np.inf
        raised = False
        dpen = 0.0
        for k in range(npi):
            if own:
                off = p_cp[i, k, 0]
                rc = p_cp[i, k, 1]
                hi = hint[tbase + MAX_TABLE_POINTS * i + k]
                if hi < 0:
                    hi = hint[MAX_CONTACT_POINTS * i]
            else:
                off, rc = contact_point(seg, i, k)
                hi = hint[MAX_CONTACT_POINTS * i + k]
            for c in range(3):
                X[c] = x[i, c] + off * R[i, c, 2]
            ic = find_contact(X, rc, p0, axc, lnc, rad, hi, info)
            pt_ic[k] = ic
            if ic >= 0:
                clr = min(clr, rad[ic] - rc)
            pt_u[k] = off
            if off >= h - MERGE_M:
                nd_r[i] = max(nd_r[i], rc)
            elif off <= -h + MERGE_M:
                nd_r[i + 1] = max(nd_r[i + 1], rc)
            pt_gap[k] = -info[OUT_DELTA]
            # where the rigid wall puts the pipe's axis there, from the hole's axis
            rw = info[OUT_DIST] - info[OUT_DELTA]
            for c in range(3):
                pt_n[k, c] = info[OUT_NX + c]
                pt_W[k, c] = rw * info[OUT_NX + c]
            if i == 0 and off >= h - MERGE_M:
                sw_bit_gap[0] = -info[OUT_DELTA]
            if info[OUT_DELTA] > 0.0:
                _add_support(sw, top_s[i] + h - off, pt_W[k], pt_n[k], X)
                ncon += 1
            pt_g[k] = info[OUT_DELTA] - rc
            pt_hint[k] = hi
            if info[OUT_DELTA] > dpen:
                dpen = info[OUT_DELTA]
            if rc != seg[i, S_RB]:
                raised = True
        if cpar.shape[0] > P_DEEP and cpar[P_DEEP] != 0.0 and npi >= 3:
            # the deepest point between the tested points, a support where the contact
            # kernel pushes on it (contact.wall_contact: beyond the tested points' largest
            # penetration)
            kd, ud, gd = deepest_point(pt_u, pt_g, npi)
            if kd >= 0 and gd + seg[i, S_RB] > dpen:
                for c in range(3):
                    X[c] = x[i, c] + ud * R[i, c, 2]
                find_contact(X, seg[i, S_RB], p0, axc, lnc, rad, pt_hint[kd], info)
                if info[OUT_DELTA] > dpen:
                    rw = info[OUT_DIST] - info[OUT_DELTA]
                    for c in range(3):
                        pt_W[npi, c] = rw * info[OUT_NX + c]
                    _add_support(sw, top_s[i] + h - ud, pt_W[npi], info[OUT_NX:OUT_NX + 3], X)
        line = npi >= 3 and ncon == npi
        if not raised and not line:
            # in a curved hole, a segment without raised points (module docstring, step 2)
            kap = _points_curvature(pt, npi, axc, lnc)
            if kap > STRAIGHT_KAPPA and 0.5 * h * h * kap < clr:
                line = _along_wall(i, npi, h, kap, top_s, sw, pt)
        g_line[i] = line
        if line:
            # line contact: the wall carries the segment's weight along its length
            for c in range(3):
                g_q[i, c] = 0.0
                g_qs[i, c] = 0.0


@njit(cache=True)
def _find_supports(n, s, p, g, nd, sw, pt, X, info):
    """Supports of the continuous beam and holds of the rigid chain of the sample
    (:data:`Supports`; module docstring, step 1), segments in line contact, and the
    loads the wall carries along them (``g.qw``, ``g.qws``)."""
    R = g.R
    g_line = g.line
    g_q = g.q
    g_q3 = g.q3
    g_qw = g.qw
    g_qws = g.qws
    g_top_s = g.top_s
    nd_C = nd.C
    sw_P = sw.P
    sw_Y = sw.Y
    sw_cnt = sw.cnt
    sw_hold = sw.hold
    seg = p.seg
    x = s.x
    sw_hold[1] = g_top_s[n]
    for k in range(3):
        sw_Y[0, k] = x[0, k] + seg[0, S_H] * R[0, k, 2]
        sw_P[0, k] = sw_Y[0, k] - nd_C[0, k]
        sw_Y[1, k] = x[n - 1, k] - seg[n - 1, S_H] * R[n - 1, k, 2]
    sw_cnt[0] = 1
    sw_cnt[1] = 2
    _segment_supports(n, s, p, g, nd, sw, pt, X, info)
    # the load the wall carries along segments in line contact (for the supports' check)
    for i in range(n):
        for c in range(3):
            g_qw[i, c] = g_q3[i, c] - g_q[i, c]
        if g_line[i]:
            inv_l = 1.0 / (2.0 * seg[i, S_H])
            gw = seg[i, S_W] * R[i, 2, 2]
            g_qws[i, 0] = -gw * R[i, 0, 2] * inv_l
            g_qws[i, 1] = -gw * R[i, 1, 2] * inv_l
            g_qws[i, 2] = (seg[i, S_W] - gw * R[i, 2, 2]) * inv_l


@njit(cache=True)
def _merge_supports(sw, top):
    """The supports of ``sw`` clipped to the chain [0, ``top``], sorted, those closer than
    ``MERGE_M`` counted once: (positions, heights, normals); the bit where a point of it
    is in the wall stands there, held by the wall."""
    nsup = sw.cnt[0]
    supP = sw.P
    supN = sw.N
    # clipped to the chain before merging, so that the kept supports stay strictly increasing
    sup_s = np.minimum(np.maximum(sw.sup[:nsup], 0.0), top)
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
    return sup_c, sup_Pc, sup_Nc


@njit(cache=True)
def _beam_sample(n, s, p, g, sw, sup, read_s, rd, rok):
    """The continuous beam's moments at ``read_s`` on the merged supports ``sup``
    (positions, heights, normals; module docstring, steps 4-6) into ``rd`` (n_read, 3:
    M_x, M_y of the (x, y) load, M_y of the z load) and ``rok``: (status, spans cut)."""
    sup_c, sup_P, sup_N = sup
    m = sup_c.shape[0]
    top_s = g.top_s
    wall = p.wall
    rad = wall[:, 7]
    dec = SegLoad(top_s, g.ei, g.T, g.qs, g.qws, g.room)
    sl = SegLoad(top_s, g.ei, g.T, g.q, g.qw, g.room)
    cw = _chain_work(2 * m + 8)
    # the span from the bit ends at the tangency where the string reaches a wall it
    # then lies along (module docstring, step 6)
    s_hi = sup_c[1]
    i_hi = 0
    while i_hi < n - 1 and top_s[i_hi + 1] <= s_hi + MERGE_M:
        i_hi += 1
    if not (sup_c[0] == 0.0 and g.line[i_hi] and not g.line[0]):
        cw = _set_supports(cw, sup_c, sup_P, sup_N)
        st, n_cut, cw = _solve_chain(cw, dec, sl, read_s, rd, rok)
        return st, n_cut
    seg_q = g.q
    q0 = math.sqrt(seg_q[0, 0] ** 2 + seg_q[0, 1] ** 2 + seg_q[0, 2] ** 2)
    h0 = s.hint[MAX_CONTACT_POINTS * 0]
    kap_out = 0.0
    if 0 <= h0 < rad.shape[0] and q0 > 0.0:
        kv = np.zeros(3)
        _hole_curvature_vector(wall[:, 3:6], wall[:, 6], h0, kv)
        # the load's share pointing away from the centre of curvature
        kap_out = -(kv[0] * seg_q[0, 0] + kv[1] * seg_q[0, 1] + kv[2] * seg_q[0, 2]) / q0
    l_t = tangency_length_m(g.ei[0], sw.bit_gap[0], q0, kap_out)
    bit_span = np.zeros(2)
    bit_span[1] = min(l_t, s_hi)
    n_cut = 0
    # a tangency within MERGE_M of the bit leaves no span there (zero moments); a
    # single span pinned at both ends takes no moment from its ends' offsets
    if bit_span[1] > MERGE_M:
        cw = _set_supports(cw, bit_span, np.zeros((2, 3)), np.zeros((2, 3)))
        st, n_cut, cw = _solve_chain(cw, dec, sl, read_s, rd, rok)
        if st != STATUS_OK:
            return st, 0
    if m > 2:
        rd2 = np.zeros(rd.shape)
        rok2 = np.zeros(rok.shape[0], dtype=np.int64)
        cw = _set_supports(cw, sup_c[1:], sup_P[1:], sup_N[1:])
        st, cut2, cw = _solve_chain(cw, dec, sl, read_s, rd2, rok2)
        if st != STATUS_OK:
            return st, 0
        # read points outside a chain's supports get zero from it
        for a in range(rd.shape[0]):
            for k in range(3):
                rd[a, k] += rd2[a, k]
            if rok2[a] != 0:
                rok[a] = 1
        n_cut += cut2
    return STATUS_OK, n_cut


@njit(cache=True)
def _chain_moments(n, p, g, nd, sw, ms_chain):
    """What the rigid chain carries now, quasi-statically (module docstring, step 7): its
    joints' moments held where it is at the bit, its top and the points the wall pushes,
    under the same load, into ``ms_chain`` (n - 1, 3); returns the solve's status."""
    nd_C = nd.C
    nd_R = nd.R
    nd_now = nd.now
    nd_r = nd.r
    sw_Y = sw.Y
    sw_cnt = sw.cnt
    sw_hold = sw.hold
    nhold = sw_cnt[1]
    top_s = g.top_s
    hs = sw_hold[:nhold]
    ho = np.argsort(hs, kind="mergesort")
    hold_s = np.zeros(nhold)
    hold_y = np.zeros((nhold, 3))
    for kk in range(nhold):
        hold_s[kk] = min(max(hs[ho[kk]], 0.0), top_s[n])
        i = segment_of(top_s, hold_s[kk])
        xi = (hold_s[kk] - top_s[i]) / (top_s[i + 1] - top_s[i])
        for c in range(3):
            hold_y[kk, c] = sw_Y[ho[kk], c] - ((1.0 - xi) * nd_C[i, c] + xi * nd_C[i + 1, c])
    k_joint = np.zeros(n - 1)
    for j in range(n - 1):
        k_joint[j] = p.jp[j, J_KB]
    # kept inside the hole, as the continuous beam is (span_chain): a free run between
    # holds near or beyond its buckling load would otherwise amplify its load without
    # bound, a moment no chain inside the hole can carry
    node_room = np.zeros(n + 1)
    for j in range(n + 1):
        node_room[j] = nd_R[j] - nd_r[j]
    n_held = np.zeros(2, dtype=np.int64)
    return chain_static_moments_in_hole(top_s, k_joint, g.T, g.q3, hold_s, hold_y, node_room,
                                        nd_now, ms_chain, n_held)


@njit(cache=True)
def _correction(n, s, sel, rd, rok, ms_chain, out):
    """The correction at the joints ``sel`` (module docstring, step 8): the beam's moment
    ``rd`` less the chain's ``ms_chain``, resolved in each joint's frame, into ``out``."""
    s_q = s.q
    qr = np.zeros(4)
    qh = np.zeros(4)
    qm = np.zeros(4)
    Rm = np.zeros((3, 3))
    for a in range(sel.size):
        jj = sel[a]
        if jj >= n - 1 or rok[a] == 0:
            continue
        # sagging moments of the world components (span_bending's convention): the
        # continuous beam's less the chain's
        msx = -rd[a, 1] - ms_chain[jj, 0]
        msy = rd[a, 0] - ms_chain[jj, 1]
        msz = -rd[a, 2] - ms_chain[jj, 2]
        _joint_frame(s_q[jj], s_q[jj + 1], qr, qh, qm, Rm)
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
    g, nd, sw, pt = _new_scratch(n)
    _segment_loads(n, s, p, wk, g)
    X = np.zeros(3)
    info = np.zeros(OUT_SIZE)
    _hole_nodes(n, s, p, g, nd, X, info)
    _find_supports(n, s, p, g, nd, sw, pt, X, info)
    sup = _merge_supports(sw, g.top_s[n])
    if sup[0].shape[0] < 2:
        return 0
    nr = sel.size
    read_s = np.zeros(nr)
    for a in range(nr):
        read_s[a] = g.top_s[min(sel[a], n - 1) + 1]
    rd = np.zeros((nr, 3))
    rok = np.zeros(nr, dtype=np.int64)
    st, n_cut = _beam_sample(n, s, p, g, sw, sup, read_s, rd, rok)
    if st != STATUS_OK:
        return -st
    ms_chain = np.zeros((n - 1, 3))
    st = _chain_moments(n, p, g, nd, sw, ms_chain)
    if st != STATUS_OK:
        return -st
    _correction(n, s, sel, rd, rok, ms_chain, out)
    return n_cut
