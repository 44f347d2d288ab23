"""The rigid chain's static moments kept inside the hole (drillfatigue.dynamics.span.chain).

Reference: the chain's own statics and the hole's geometry. A chain of rigid segments
on joint springs k = EI/L, held at given points, is solved exactly by
``chain_static_moments``; where that solution stays inside the hole,
``chain_static_moments_in_hole`` must give the same numbers bit for bit (a chain at rest
on its holds). A free run between two holds in compression near its buckling load
amplifies its load without bound (the recorder's 4e6 N m spikes); no chain inside the
hole can carry more than the kinks its room allows, |M_j| <= k (|dtheta_lo| + |dtheta_up|)
with each slope at most 2 room / L, and the kept-inside solution must respect that.
Beyond the buckling load there is no static solution: it must hold the run at its
middle where the chain is and solve.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.dynamics.span.chain import (
    STATUS_OK, STATUS_SINGULAR, WALL_TOL_M, chain_static_moments, chain_static_moments_in_hole,
)

EI = 2.07e11 * math.pi / 64.0 * (0.127 ** 4 - 0.1086 ** 4)  # 5 in 19.5 ppf body, N m^2
L = 9.144
N = 6
ROOM = 0.5 * (0.2159 - 0.1683)  # tool joint off the hole's axis, m


def _run(T: float, q: float = 240.0):
    """N drill-pipe segments held at both chain ends on the low wall (+z), weight along +z,
    axial force T everywhere."""
    top_s = np.arange(N + 1) * L
    k = np.full(N - 1, EI / L)
    seg_T = np.full(N, T)
    seg_q = np.zeros((N, 3))
    seg_q[:, 2] = q
    hold_s = np.array([0.0, N * L])
    hold_y = np.zeros((2, 3))
    hold_y[:, 2] = ROOM
    room = np.full(N + 1, ROOM)
    now = np.zeros((N + 1, 3))
    now[:, 2] = ROOM
    return top_s, k, seg_T, seg_q, hold_s, hold_y, room, now


def _buckling_T() -> float:
    """Compression at which the free run loses its static solution (bisection on the
    pivots of chain_static_moments)."""
    lo, hi = 0.0, 10.0 * EI / L ** 2
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        top_s, k, T, q, hs, hy, _, _ = _run(-mid)
        st = chain_static_moments(top_s, k, T, q, hs, hy, np.zeros((N - 1, 3)))
        if st == STATUS_OK:
            lo = mid
        else:
            hi = mid
    return lo


def _in_hole(args):
    top_s, k, T, q, hs, hy, room, now = args
    out = np.zeros((N - 1, 3))
    n_held = np.zeros(2, dtype=np.int64)
    st = chain_static_moments_in_hole(top_s, k, T, q, hs, hy, room, now, out, n_held)
    return st, out, n_held


def test_a_chain_inside_the_hole_is_solved_as_on_its_holds() -> None:
    """Held at every node on the low wall: nothing leaves the hole, the same numbers."""
    top_s, k, T, q, _, _, room, now = _run(50e3)
    hs = top_s.copy()
    hy = np.zeros((N + 1, 3))
    hy[:, 2] = ROOM
    ref = np.zeros((N - 1, 3))
    assert chain_static_moments(top_s, k, T, q, hs, hy, ref) == STATUS_OK
    st, out, n_held = _in_hole((top_s, k, T, q, hs, hy, room, now))
    assert st == STATUS_OK and not n_held.any()
    np.testing.assert_array_equal(out, ref)


def test_a_free_run_near_its_buckling_load_is_kept_inside_the_hole() -> None:
    p_cr = _buckling_T()
    # the discrete run buckles well below a continuous pipe's Euler load over its length
    assert p_cr < math.pi ** 2 * EI / (N * L) ** 2
    args = _run(-0.999 * p_cr)
    top_s, k, T, q, hs, hy, _, _ = args
    free = np.zeros((N - 1, 3))
    assert chain_static_moments(top_s, k, T, q, hs, hy, free) == STATUS_OK
    st, out, n_held = _in_hole(args)
    assert st == STATUS_OK and n_held[0] >= 1 and n_held[1] == 0
    bound = (EI / L) * 2 * (2 * ROOM / L)
    # on its end holds alone the run carries many times what fits in the hole
    assert np.abs(free).max() > 10 * bound
    assert np.abs(out).max() <= bound * (1 + 1e-6) + 1e-6


def test_a_free_run_beyond_its_buckling_load_is_held_where_it_is() -> None:
    p_cr = _buckling_T()
    args = _run(-1.5 * p_cr)
    top_s, k, T, q, hs, hy, _, _ = args
    assert chain_static_moments(top_s, k, T, q, hs, hy, np.zeros((N - 1, 3))) \
        == STATUS_SINGULAR
    st, out, n_held = _in_hole(args)
    assert st == STATUS_OK and n_held[1] >= 1
    assert np.all(np.isfinite(out))
    assert np.abs(out).max() <= (EI / L) * 2 * (2 * (ROOM + WALL_TOL_M) / L) * (1 + 1e-6)
