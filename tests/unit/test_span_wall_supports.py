"""Mid-span supports where the elastic pipe reaches the wall or buckles between its supports.

Reference: the beam-column's own validity limits (drillfatigue.dynamics.span_bending):
a span whose mid-span deflection exceeds the room to the wall, or whose compression
reaches the Euler load of the pinned span (pi^2 EI / L^2), lies on the wall in between,
so the touching point is a support. Checked: (1) a chain that sags less than its room is
solved exactly as before (same bits); (2) drill pipe in compression past the Euler load of
its 9.144 m spans (which the chain alone can only cut) gets a support at each span's
middle and then the same moments as the chain solved directly on the halved spans;
(3) after the splits no span's deflection exceeds its room.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.dynamics.span_bending import (
    END_PINNED, STATUS_OK, STATUS_SPAN_BUCKLED, chain_span_moments, midspan_deflection,
)
from drillfatigue.dynamics.span_record import STATUS_SPLIT, _solve_or_split

EI = 2.07e11 * math.pi / 64.0 * (0.127 ** 4 - 0.1086 ** 4)  # 5 in 19.5 ppf body, N m^2
L_JOINT = 9.144
N = 12
Q = 240.0  # buoyed weight per length, N/m


def _chain(T: float, gap: float):
    top_s = np.arange(N + 1) * L_JOINT
    seg_ei = np.full(N, EI)
    seg_T = np.full(N, T)
    seg_q = np.zeros((N, 2))
    seg_q[:, 1] = -Q
    seg_qz = np.zeros((N, 2))
    seg_gap = np.full(N, gap)
    read_s = top_s[1:-1].copy()
    return top_s, seg_ei, seg_T, seg_q, seg_qz, seg_gap, read_s


def _direct(sup, top_s, seg_ei, seg_T, seg_q, read_s):
    """The chain solved on ``sup`` as given: (status, moments, per-span cut codes)."""
    m = sup.size
    out = np.zeros((read_s.size, 2))
    cut = np.zeros(m - 1, dtype=np.int64)
    st = chain_span_moments(sup, top_s, seg_ei, seg_T, seg_q, END_PINNED, END_PINNED, read_s,
                            np.zeros(m - 1), np.zeros(m - 1), np.zeros(m - 1),
                            np.zeros((m - 1, 2)), np.zeros((m, 6)), np.zeros((m, 2)), out, cut)
    return st, out, cut


def test_a_span_within_its_room_is_solved_as_before() -> None:
    top_s, ei, T, q, qz, gap, read = _chain(50e3, 0.044)
    sup = top_s.copy()
    rxy = np.zeros((read.size, 2))
    rz = np.zeros((read.size, 2))
    st, sup2, _ = _solve_or_split(sup, top_s, ei, T, q, qz, gap, read, rxy, rz, True)
    assert st == STATUS_OK and sup2.size == sup.size
    st_d, ref, _ = _direct(sup, top_s, ei, T, q, read)
    assert st_d == STATUS_OK
    assert np.array_equal(rxy, ref)
    # interior supports of equal spans: about the clamped span's -qL^2/12 (tension lowers it)
    assert 0.5 * Q * L_JOINT ** 2 / 12 < abs(rxy[N // 2, 0]) < Q * L_JOINT ** 2 / 12


def test_a_buckled_span_gets_a_mid_span_support() -> None:
    p_euler = math.pi ** 2 * EI / L_JOINT ** 2
    top_s, ei, T, q, qz, gap, read = _chain(-1.2 * p_euler, 0.044)
    sup = top_s.copy()
    _, _, cut0 = _direct(sup, top_s, ei, T, q, read)
    assert np.all(cut0 == STATUS_SPAN_BUCKLED)  # on the tool joints alone every span buckles
    rxy = np.zeros((read.size, 2))
    rz = np.zeros((read.size, 2))
    st, sup2, _ = _solve_or_split(sup, top_s, ei, T, q, qz, gap, read, rxy, rz, True)
    assert st == STATUS_SPLIT and sup2.size == 2 * sup.size - 1
    assert np.allclose(sup2[1::2], 0.5 * (sup[:-1] + sup[1:]))
    st, sup3, cut = _solve_or_split(sup2, top_s, ei, T, q, qz, gap, read, rxy, rz, True)
    assert st == STATUS_OK and sup3.size == sup2.size and np.all(cut == STATUS_OK)
    st_d, ref, _ = _direct(sup2, top_s, ei, T, q, read)
    assert st_d == STATUS_OK and np.array_equal(rxy, ref)
    # halved spans at 1.2/4 of their Euler load: amplified, finite, below the tool-joint spans'
    # tension-free value
    assert np.all(np.isfinite(rxy)) and np.max(np.abs(rxy)) < Q * L_JOINT ** 2 / 12


def test_after_the_splits_no_span_passes_the_wall() -> None:
    p_euler = math.pi ** 2 * EI / L_JOINT ** 2
    gap = 0.002  # a tight hole: the sag of a 9 m span (~3 mm) reaches the wall
    top_s, ei, T, q, qz, gaps, read = _chain(-0.9 * p_euler, gap)
    sup = top_s.copy()
    rxy = np.zeros((read.size, 2))
    rz = np.zeros((read.size, 2))
    for _ in range(5):
        st, sup, _ = _solve_or_split(sup, top_s, ei, T, q, qz, gaps, read, rxy, rz, True)
        if st != STATUS_SPLIT:
            break
    assert st == STATUS_OK
    m = sup.size
    L, e, t, qq = np.zeros(m - 1), np.zeros(m - 1), np.zeros(m - 1), np.zeros((m - 1, 2))
    M = np.zeros((m, 2))
    chain_span_moments(sup, top_s, ei, T, q, END_PINNED, END_PINNED, read, L, e, t, qq,
                       np.zeros((m, 6)), M, np.zeros((read.size, 2)), np.zeros(m - 1, np.int64))
    d = np.zeros(m - 1)
    assert midspan_deflection(L, e, t, qq, M, d) == STATUS_OK
    assert np.all(d <= gap)
