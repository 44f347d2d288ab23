"""Invariants of the span-bending kernels (hypothesis).

The continuous beam on rigid supports is linear in the load; mirroring the
chain mirrors the moments; turning the load in the cross-section turns the
moment vectors by the same angle (the section is round); resolving into a
pipe frame and back is the identity.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.span.beam import (chain_span_moments, continuous_beam_moments,
                                        pipe_frame_moments)

spans = st.lists(st.floats(1.0, 15.0), min_size=1, max_size=8)
loads = st.floats(-2e3, 2e3)
ENDS = st.sampled_from(["pinned", "clamped"])
EI = 1.2e6


def _q(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-500.0, 500.0, (n, 2))


@settings(max_examples=40, deadline=None)
@given(spans, st.integers(0, 2**31), st.integers(0, 2**31), loads, loads, ENDS, ENDS,
       st.floats(-2e4, 5e5))
def test_linear_in_the_load(L: list[float], s1: int, s2: int, a: float, b: float, e0: str,
                            e1: str, P: float) -> None:
    n = len(L)
    q1, q2 = _q(n, s1), _q(n, s2)
    P = max(P, -0.5 * np.pi**2 * EI / max(L) ** 2)  # keep every span below its Euler load
    r1 = continuous_beam_moments(L, EI, q1, P, (e0, e1), np.arange(n), np.array(L) / 3)
    r2 = continuous_beam_moments(L, EI, q2, P, (e0, e1), np.arange(n), np.array(L) / 3)
    r = continuous_beam_moments(L, EI, a * q1 + b * q2, P, (e0, e1), np.arange(n),
                                np.array(L) / 3)
    scale = 1.0 + np.abs(a * r1.support_Nm).max() + np.abs(b * r2.support_Nm).max()
    # a linear solve: equal to rounding, relative to the moment scale
    np.testing.assert_allclose(r.support_Nm, a * r1.support_Nm + b * r2.support_Nm,
                               atol=1e-9 * scale)
    np.testing.assert_allclose(r.read_Nm, a * r1.read_Nm + b * r2.read_Nm, atol=1e-9 * scale)


@settings(max_examples=40, deadline=None)
@given(spans, st.integers(0, 2**31), ENDS, ENDS)
def test_mirror_symmetry(L: list[float], seed: int, e0: str, e1: str) -> None:
    n = len(L)
    q = _q(n, seed)
    ei = np.linspace(0.8e6, 1.6e6, n)
    r = continuous_beam_moments(L, ei, q, 1e4, (e0, e1))
    m = continuous_beam_moments(L[::-1], ei[::-1], q[::-1], 1e4, (e1, e0))
    np.testing.assert_allclose(m.support_Nm, r.support_Nm[::-1],
                               atol=1e-9 * (1.0 + np.abs(r.support_Nm).max()))


@settings(max_examples=40, deadline=None)
@given(spans, st.integers(0, 2**31), st.floats(-np.pi, np.pi))
def test_turning_the_load_turns_the_moments(L: list[float], seed: int, a: float) -> None:
    n = len(L)
    q = _q(n, seed)
    c, s = np.cos(a), np.sin(a)
    R = np.array([[c, -s], [s, c]])
    r = continuous_beam_moments(L, EI, q, 0.0, ("clamped", "pinned"))
    t = continuous_beam_moments(L, EI, q @ R.T, 0.0, ("clamped", "pinned"))
    np.testing.assert_allclose(t.support_Nm, r.support_Nm @ R.T,
                               atol=1e-9 * (1.0 + np.abs(r.support_Nm).max()))
    # the pipe-fixed frame: turning the pipe by a undoes a load turned by a
    back = pipe_frame_moments(t.support_Nm, np.full(n + 1, a))
    np.testing.assert_allclose(back, r.support_Nm, atol=1e-9 * (1.0 + np.abs(r.support_Nm).max()))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(1.0, 15.0), min_size=2, max_size=8), st.integers(0, 2**31),
       st.integers(0, 7), st.floats(1.0, 3.0), ENDS, ENDS)
def test_a_buckled_span_leaves_the_chain_without_it(L: list[float], seed: int, k: int,
                                                    over: float, e0: str, e1: str) -> None:
    """A span beyond its Euler load (``over`` times pi^2 EI/L^2 in compression) cuts
    the chain: every other span's moments are those of the continuous beam without
    it, pinned at the cut (the chain's own end condition at a chain end), to
    rounding of the same solve (1e-9 of the largest moment)."""
    n = len(L)
    k = k % n
    rng = np.random.default_rng(seed)
    q = _q(n, seed)
    T = rng.uniform(-0.5, 2.0, n) * np.pi ** 2 * EI / np.asarray(L) ** 2
    T[k] = -over * np.pi ** 2 * EI / L[k] ** 2
    bounds = np.concatenate([[0.0], np.cumsum(L)])
    mid = 0.5 * (bounds[:-1] + bounds[1:])
    sup_M, rd, cut = chain_span_moments(bounds, bounds, np.full(n, EI), T, q, mid, (e0, e1))
    assert cut[k] != 0 and np.count_nonzero(cut) == 1
    want_sup = np.zeros((n + 1, 2))
    want_rd = np.zeros((n, 2))
    for a, b in ((0, k), (k + 1, n)):
        if b <= a:
            continue
        ends = (e0 if a == 0 else "pinned", e1 if b == n else "pinned")
        r = continuous_beam_moments(L[a:b], EI, q[a:b], T[a:b], ends,
                                    read_span=np.arange(b - a), read_x_m=0.5 * np.asarray(L[a:b]))
        want_sup[a:b + 1] = r.support_Nm
        want_rd[a:b] = r.read_Nm
    scale = max(np.abs(want_sup).max(), np.abs(want_rd).max(), 1.0)
    np.testing.assert_allclose(sup_M, want_sup, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(rd, want_rd, rtol=0, atol=1e-9 * scale)
