"""The continuous beam against the wall: mid-span supports where the elastic pipe reaches
it or buckles between its supports, and wall supports it would pull from let go of.

Reference: the beam-column's own validity limits (drillfatigue.dynamics.span.bending)
and the wall's one-sidedness: a span whose middle (chord plus mid-span deflection) lies
beyond the wall, or whose compression reaches the Euler load of the pinned span
(pi^2 EI / L^2), lies on the wall in between, so the touching point is a support; a wall
point can only push the pipe towards the hole's axis. Checked on drill pipe lying on its
tool joints on the low side of a horizontal hole (world z down, hole along x): (1) a
chain that sags less than its tool joints' stand-off is solved as on level supports;
(2) drill pipe in compression past the Euler load of its 9.144 m spans (which the chain
alone can only cut) gets a support at each span's middle and then the same moments as
the chain solved directly on the halved spans; (3) after the splits no span's middle
passes the wall; (4) a support on the wall beside a raised one, which the beam would
pull, is let go of, and the beam then pushes at every wall support; (5) supports decided
without lateral weight, the wall still bounds the beam under the inertial load it carries.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.dynamics.span.bending import (
    END_PINNED, STATUS_OK, STATUS_SPAN_BUCKLED, SegmentChain, Spans, chain_span_moments,
    chain_span_moments_settled, read_moments,
)
from drillfatigue.dynamics.span.record import (
    ACT_NONE, ACT_RELEASE, ACT_SPLIT, MAX_RELEASES, MAX_SPLIT_ROUNDS, MIN_SPLIT_SPAN_M, SPLIT_TOL_M,
    STATUS_SPLIT, SegLoad, _chain_work, _set_supports, _solve_chain, _solve_round,
)

EI = 2.07e11 * math.pi / 64.0 * (0.127 ** 4 - 0.1086 ** 4)  # 5 in 19.5 ppf body, N m^2
L_JOINT = 9.144
N = 12
Q = 240.0  # buoyed weight per length, N/m
HOLE_R = 0.5 * 0.2159
R_BODY = 0.5 * 0.127
R_TJ = 0.5 * 0.1683


def _chain(T: float, standoff: float = R_TJ - R_BODY):
    """Tool joints at the segment ends on the low wall of a horizontal hole (z down),
    standing the body ``standoff`` off it: positions relative to the hole's axis; the
    weight acts along +z (the (x, y) solve carries no load)."""
    top_s = np.arange(N + 1) * L_JOINT
    seg_ei = np.full(N, EI)
    seg_T = np.full(N, T)
    seg_q = np.zeros((N, 2))
    seg_qz = np.zeros((N, 2))
    seg_qz[:, 0] = Q
    seg_qw = np.zeros((N, 3))
    seg_rb = np.full(N, R_BODY)
    seg_Rh = np.full(N, HOLE_R)
    read_s = top_s[1:-1].copy()
    sup = top_s.copy()
    sup_P = np.zeros((sup.size, 3))
    sup_P[:, 2] = HOLE_R - R_BODY - standoff
    sup_n = np.zeros((sup.size, 3))
    sup_n[:, 2] = 1.0
    return (sup, sup_P, sup_n, top_s, seg_ei, seg_T, seg_q, seg_qz, seg_qw, seg_rb, seg_Rh,
            read_s)


def _direct(sup, top_s, seg_ei, seg_T, seg_qz, read_s):
    """The z solve of the chain on ``sup`` as given, level: (status, moments, cut codes)."""
    m = sup.size
    out = np.zeros((read_s.size, 2))
    cut = np.zeros(m - 1, dtype=np.int64)
    st = chain_span_moments(sup, SegmentChain(top_s, seg_ei, seg_T, seg_qz), END_PINNED,
                            END_PINNED, read_s, _spans(m - 1), np.zeros((m, 6)),
                            np.zeros((m, 2)), out, cut)
    return st, out, cut


def _spans(n):
    return Spans(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros((n, 2)))


def _settled(sup, d, top_s, ei, T, qz, read):
    """The z solve of the chain on ``sup`` at offsets ``d``: (spans, support moments)."""
    m = sup.size
    sp = _spans(m - 1)
    M = np.zeros((m, 2))
    chain_span_moments_settled(sup, d, SegmentChain(top_s, ei, T, qz), END_PINNED, END_PINNED,
                               read, sp, np.zeros((m, 6)), M, np.zeros((read.size, 2)),
                               np.zeros(m - 1, np.int64), np.zeros(read.size, np.int64))
    return sp, M


def _load(top_s, ei, T, q, qz, qw, rb, Rh):
    """The recorder's segments under the (x, y) load ``q`` and the z load ``qz[:, 0]``."""
    q3 = np.ascontiguousarray(np.column_stack([q[:, 0], q[:, 1], qz[:, 0]]))
    return SegLoad(top_s, ei, T, q3, qw, Rh - rb)


def _work(sup, sup_P, sup_n):
    return _set_supports(_chain_work(2 * sup.size + 8), sup, sup_P, sup_n)


def _round(args, may_split=True, may_release=True, banned=None):
    """One round of the recorder's solve: ((status, supports, heights, normals, cut codes,
    action), z moments as the z solve's (M_x, M_y), read points solved)."""
    sup, sup_P, sup_n, top_s, ei, T, q, qz, qw, rb, Rh, read = args
    b = np.zeros(MAX_RELEASES)
    nb = np.zeros(1, dtype=np.int64)
    if banned:
        b[:len(banned)] = banned
        nb[0] = len(banned)
    st, act, cw = _solve_round(_work(sup, sup_P, sup_n), _load(top_s, ei, T, q, qz, qw, rb, Rh),
                               int(may_split), bool(may_release), b, nb)
    m = cw.m[0]
    rd = np.zeros((read.size, 3))
    rok = np.zeros(read.size, dtype=np.int64)
    if st == STATUS_OK and act == ACT_NONE:
        read_moments(cw.c[:m], cw.sp, cw.M[:m], cw.cut[:m - 1], read, rd, rok)
    rz = np.zeros((read.size, 2))
    rz[:, 1] = rd[:, 2]
    got = (st, cw.c[:m].copy(), cw.v[:m].copy(), cw.n[:m].copy(), cw.cut[:m - 1].copy(), act)
    return got, rz, rok


def _chain_solve(args, dec=None):
    """The recorder's chain solve of ``args`` (as :func:`_chain`'s), decided under ``dec``
    ((x, y) load, z load, wall load; default: the loads of ``args``): (status, cut codes,
    read moments (x, y), z moments as the z solve's (M_x, M_y), read points solved)."""
    sup, sup_P, sup_n, top_s, ei, T, q, qz, qw, rb, Rh, read = args
    dq, dqz, dqw = (q, qz, qw) if dec is None else dec
    rd = np.zeros((read.size, 3))
    rok = np.zeros(read.size, dtype=np.int64)
    st, _, cw = _solve_chain(_work(sup, sup_P, sup_n), _load(top_s, ei, T, dq, dqz, dqw, rb, Rh),
                             _load(top_s, ei, T, q, qz, qw, rb, Rh), read, rd, rok)
    rz = np.zeros((read.size, 2))
    rz[:, 1] = rd[:, 2]
    return st, cw.cut[:cw.m[0] - 1].copy(), rd[:, :2].copy(), rz, rok


def test_a_span_within_its_room_is_solved_as_on_level_supports() -> None:
    args = _chain(50e3)
    (st, sup2, _, _, _, act), rz, rok = _round(args)
    assert st == STATUS_OK and act == ACT_NONE and sup2.size == args[0].size
    sup, _, _, top_s, ei, T, _, qz, _, _, _, read = args
    st_d, ref, _ = _direct(sup, top_s, ei, T, qz, read)
    assert st_d == STATUS_OK and np.all(rok == 1)
    # level supports: the same moments as the level solution, to round-off
    np.testing.assert_allclose(rz, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    # interior supports of equal spans: about the clamped span's qL^2/12 (tension lowers it)
    assert 0.5 * Q * L_JOINT ** 2 / 12 < abs(rz[N // 2, 1]) < Q * L_JOINT ** 2 / 12


def test_a_buckled_span_gets_a_mid_span_support() -> None:
    p_euler = math.pi ** 2 * EI / L_JOINT ** 2
    args = _chain(-1.2 * p_euler)
    sup, sup_P, sup_n, top_s, ei, T, q, qz, qw, rb, Rh, read = args
    _, _, cut0 = _direct(sup, top_s, ei, T, qz, read)
    assert np.all(cut0 == STATUS_SPAN_BUCKLED)  # on the tool joints alone every span buckles
    (st, sup2, P2, n2, _, act), _, _ = _round(args)
    assert st == STATUS_SPLIT and act == ACT_SPLIT and sup2.size == 2 * sup.size - 1
    assert np.allclose(sup2[1::2], 0.5 * (sup[:-1] + sup[1:]))
    # a buckled span's new support: at its chord's middle, two-sided
    np.testing.assert_allclose(P2[1::2], 0.5 * (sup_P[:-1] + sup_P[1:]))
    assert not n2[1::2].any()
    (st, sup3, _, _, cut, act), rz, _ = _round((sup2, P2, n2) + args[3:])
    assert st == STATUS_OK and act == ACT_NONE and sup3.size == sup2.size
    assert np.all(cut == STATUS_OK)
    st_d, ref, _ = _direct(sup2, top_s, ei, T, qz, read)
    assert st_d == STATUS_OK
    np.testing.assert_allclose(rz, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    # halved spans at 1.2/4 of their Euler load: amplified, finite, below the tool-joint spans'
    # tension-free value
    assert np.all(np.isfinite(rz)) and np.max(np.abs(rz)) < Q * L_JOINT ** 2 / 12


def test_after_the_splits_no_span_passes_the_wall() -> None:
    """Tool joints 2 mm proud of the body, compression 0.9 of the spans' Euler load: the
    sag of a 9 m span (about 3 mm, amplified) reaches the wall; after the splits every
    span's middle is inside it."""
    p_euler = math.pi ** 2 * EI / L_JOINT ** 2
    args = _chain(-0.9 * p_euler, standoff=0.002)
    sup, sup_P, sup_n = args[:3]
    rest = args[3:]
    n_split = 0
    for _ in range(64):
        (st, sup, sup_P, sup_n, _, act), _, _ = _round((sup, sup_P, sup_n) + rest,
                                                       may_split=n_split < 16)
        if act == ACT_NONE:
            break
        n_split += act == ACT_SPLIT
    # splits and releases alternate (a tool joint beside a span lying on the wall is let
    # go of) down to spans of MIN_SPLIT_SPAN_M
    assert st == STATUS_OK and act == ACT_NONE and n_split >= 1
    top_s, ei, T, q, qz = rest[:5]
    read = rest[-1]
    m = sup.size
    d = np.zeros((m, 2))
    d[:, 0] = sup_P[:, 2] - sup_P[0, 2]
    (L, e, t, qq), M = _settled(sup, d, top_s, ei, T, qz, read)
    # the middle of each span: chord's middle plus the amplified sag (z down, load +z);
    # spans too short to split may pass by the split tolerance
    sag = (5 * qq[:, 0] * L ** 4 / (384 * e) - (M[:-1, 1] + M[1:, 1]) * L ** 2 / (16 * e)) \
        / (1 + t * L ** 2 / (math.pi ** 2 * e))
    mid_z = 0.5 * (sup_P[:-1, 2] + sup_P[1:, 2]) + sag
    assert np.all(mid_z[L >= MIN_SPLIT_SPAN_M] <= HOLE_R - R_BODY + SPLIT_TOL_M)


def test_a_wall_support_the_beam_pulls_is_let_go_of() -> None:
    """A support raised 21 mm off the wall at the chain's start (a stabilizer blade),
    then wall points every joint, no load: without the first wall point the beam from
    the raised support over the others passes above it, so the beam would pull it down
    to the wall; it is let go of first. With the weight on, after all releases every
    remaining wall support pushes (reaction towards the hole's axis, from the spans'
    statics)."""
    args = list(_chain(0.0))
    sup, sup_P, sup_n = args[:3]
    sup_P = sup_P.copy()
    sup_P[0, 2] -= 0.021
    sup_n = sup_n.copy()
    sup_n[0] = 0.0
    qz0 = np.zeros_like(args[7])
    (st, sup2, _, _, _, act), _, _ = _round((sup, sup_P, sup_n) + tuple(args[3:7]) + (qz0,)
                                            + tuple(args[8:]), may_split=False)
    assert st == STATUS_SPLIT and act == ACT_RELEASE
    assert sup2.size == sup.size - 1 and L_JOINT not in sup2
    # with the weight: loop to the end, then check every reaction by hand
    top_s, ei, T, q, qz, qw, rb, Rh, read = args[3:]
    st = _chain_solve((sup, sup_P, sup_n) + tuple(args[3:]))[0]
    assert st == STATUS_OK
    s, P, n = sup, sup_P, sup_n
    for _ in range(64):
        (st, s2, P2, n2, _, act), _, _ = _round((s, P, n) + tuple(args[3:]))
        if act == ACT_NONE:
            break
        s, P, n = s2, P2, n2
    m = s.size
    d = np.zeros((m, 2))
    d[:, 0] = P[:, 2] - P[0, 2]
    (L, e, t, qq), M = _settled(s, d, top_s, ei, T, qz, read)
    ms = -M[:, 1]  # sagging moment of the z component
    psi = np.diff(d[:, 0]) / L
    s_start = np.diff(ms) / L + qq[:, 0] * L / 2 + t * psi
    s_end = s_start - qq[:, 0] * L
    reaction_z = s_end[:-1] - s_start[1:]  # force of the support on the beam, +z (outwards)
    wall = n[1:-1, 2] > 0
    assert np.all(reaction_z[wall] <= 1e-9 * Q * L_JOINT)


def test_spans_merged_by_releases_are_split_until_inside_the_wall() -> None:
    """A load lifting the pipe off its tool joints (3 kN/m towards the high side, -z: a
    lateral inertia) pulls every interior wall support: all are let go of, one free span
    of 110 m is left, and its splits must go on until no span's middle passes the high
    wall. Four rounds leave 6.9 m spans sagging 70 mm where the room is 44 mm (q L^2/8 of
    a span far longer than the wall allows); the recorder's budget (MAX_SPLIT_ROUNDS) must
    reach spans that fit, and _solve_chain must end where that loop ends."""
    args = list(_chain(0.0))
    args[7] = -12.5 * args[7]
    sup, sup_P, sup_n = args[:3]
    rest = tuple(args[3:])
    n_split = n_release = 0
    banned: list[float] = []
    added: set[float] = set()
    for _ in range(256):
        (st, s2, P2, n2, _, act), rz_loop, _ = _round((sup, sup_P, sup_n) + rest,
                                                       may_split=n_split < MAX_SPLIT_ROUNDS,
                                                       may_release=n_release < MAX_RELEASES,
                                                       banned=banned)
        if act == ACT_NONE:
            break
        n_split += act == ACT_SPLIT
        if act == ACT_SPLIT:
            added |= set(s2) - set(sup)
        if act == ACT_RELEASE:
            n_release += 1
            # where a mid-span support was let go of, none is added again (as _solve_chain)
            banned.extend(s for s in sorted(set(sup) - set(s2))[:1] if s in added)
        sup, sup_P, sup_n = s2, P2, n2
    assert st == STATUS_OK and n_release >= N - 1 and n_split > 4, (n_release, n_split)
    top_s, ei, T, q, qz = rest[:5]
    read = rest[-1]
    m = sup.size
    d = np.zeros((m, 2))
    d[:, 0] = sup_P[:, 2] - sup_P[0, 2]
    (Ls, e, t, qq), M = _settled(sup, d, top_s, ei, T, qz, read)
    sag = 5 * qq[:, 0] * Ls ** 4 / (384 * e) - (M[:-1, 1] + M[1:, 1]) * Ls ** 2 / (16 * e)
    mid_z = 0.5 * (sup_P[:-1, 2] + sup_P[1:, 2]) + sag
    assert np.all(np.abs(mid_z[Ls >= MIN_SPLIT_SPAN_M]) <= HOLE_R - R_BODY + SPLIT_TOL_M)
    st, _, _, rz, _ = _chain_solve(tuple(args))
    assert st == STATUS_OK
    np.testing.assert_allclose(rz, rz_loop, rtol=1e-12, atol=1e-9)


def test_the_wall_bounds_the_beam_under_the_whole_load_too() -> None:
    """Drill pipe in a vertical stretch (no lateral weight to decide supports with)
    between two tool joints on the wall 12 joints apart, carrying a whirl's inertial
    load of 1.5 kN/m across the hole: on the supports the weight decides (its two ends)
    the span would carry q L^2 / 8 = 2.3 MN m, metres beyond the wall. The wall holds
    the pipe where that load takes a span's middle beyond it, so the spans end where
    the pipe's middle stays within the wall (5 q s^4 / (384 EI) below the room, s below
    6 m here) and no moment reaches the 9.144 m span's q L^2 / 8."""
    top_s, ei, T, q, qz, qw, rb, Rh, read = _chain(0.0)[3:]
    sup = np.array([0.0, top_s[-1]])
    sup_P = np.zeros((2, 3))
    sup_P[:, 2] = HOLE_R - R_TJ
    sup_n = np.zeros((2, 3))
    sup_n[:, 2] = 1.0
    q_dyn = np.zeros_like(q)
    q_dyn[:, 1] = 1500.0
    qz0 = np.zeros_like(qz)
    st, cut, rxy, _, rok = _chain_solve((sup, sup_P, sup_n, top_s, ei, T, q_dyn, qz0, qw, rb, Rh,
                                         read), dec=(np.zeros_like(q), qz0, np.zeros_like(qw)))
    assert st == STATUS_OK and not cut.any() and np.all(rok == 1)
    assert np.abs(rxy).max() < 1500.0 * L_JOINT ** 2 / 8.0
